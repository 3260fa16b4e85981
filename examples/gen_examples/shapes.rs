//! The shapes of the STRESS² experiments (seed 000, Fig. 4 and Fig. 12), each
//! filling a square of side `s` whose top-left corner is `(x, y)`, in
//! millimetres with y down (the page convention).

use std::f64::consts::PI;

/// A point on the page, in millimetres.
pub type Pt = (f64, f64);

/// The shapes the experiments used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Experiment 1: apex at the top.
    TriangleUp,
    /// Experiment 1, and the "inverted triangle" of experiment 5.
    TriangleDown,
    /// Experiments 1 and 5.
    Circle,
    /// Experiments 1 and 5.
    Square,
    /// Experiment 1: a square on its corner.
    Diamond,
    /// Experiment 1: a plus sign with arms a third of the side wide.
    Plus,
    /// Experiment 5: right angle at the bottom left.
    RightTriangle,
}

impl Kind {
    /// The six shapes of experiment 1, in the order of Fig. 4a.
    pub const EXP1: [Kind; 6] =
        [Kind::TriangleUp, Kind::TriangleDown, Kind::Circle, Kind::Square, Kind::Diamond, Kind::Plus];
    /// The four shapes of experiment 5 (Fig. 12a).
    pub const EXP5: [Kind; 4] = [Kind::Circle, Kind::Square, Kind::TriangleDown, Kind::RightTriangle];

    /// A short name used in ids and file names.
    pub fn name(self) -> &'static str {
        match self {
            Kind::TriangleUp => "triangle-up",
            Kind::TriangleDown => "triangle-down",
            Kind::Circle => "circle",
            Kind::Square => "square",
            Kind::Diamond => "diamond",
            Kind::Plus => "plus",
            Kind::RightTriangle => "right-triangle",
        }
    }
}

/// One shape placed on the page.
#[derive(Debug, Clone, Copy)]
pub struct Shape {
    /// Which shape.
    pub kind: Kind,
    /// Left edge of its square.
    pub x: f64,
    /// Top edge of its square.
    pub y: f64,
    /// Side of its square.
    pub s: f64,
}

impl Shape {
    /// The shape's corners (for the circle, a fine polygon used only for traces).
    pub fn outline(&self) -> Vec<Pt> {
        let Shape { x, y, s, .. } = *self;
        let t = s / 3.0;
        match self.kind {
            Kind::TriangleUp => vec![(x + s / 2.0, y), (x + s, y + s), (x, y + s)],
            Kind::TriangleDown => vec![(x, y), (x + s, y), (x + s / 2.0, y + s)],
            Kind::Square => vec![(x, y), (x + s, y), (x + s, y + s), (x, y + s)],
            Kind::Diamond => vec![(x + s / 2.0, y), (x + s, y + s / 2.0), (x + s / 2.0, y + s), (x, y + s / 2.0)],
            Kind::RightTriangle => vec![(x, y), (x + s, y + s), (x, y + s)],
            Kind::Plus => vec![
                (x + t, y),
                (x + 2.0 * t, y),
                (x + 2.0 * t, y + t),
                (x + s, y + t),
                (x + s, y + 2.0 * t),
                (x + 2.0 * t, y + 2.0 * t),
                (x + 2.0 * t, y + s),
                (x + t, y + s),
                (x + t, y + 2.0 * t),
                (x, y + 2.0 * t),
                (x, y + t),
                (x + t, y + t),
            ],
            Kind::Circle => (0..72)
                .map(|k| {
                    let a = 2.0 * PI * k as f64 / 72.0;
                    (x + s / 2.0 + s / 2.0 * a.cos(), y + s / 2.0 + s / 2.0 * a.sin())
                })
                .collect(),
        }
    }

    /// The centre of its square.
    pub fn centre(&self) -> Pt {
        (self.x + self.s / 2.0, self.y + self.s / 2.0)
    }

    /// The SVG element for the shape, with the given id, presentation
    /// attributes (fill, stroke, annotation) and a title that names it.
    pub fn svg(&self, id: &str, attrs: &str, title: &str) -> String {
        if self.kind == Kind::Circle {
            let (cx, cy) = self.centre();
            let (cx, cy, r) = (n(cx), n(cy), n(self.s / 2.0));
            return format!(r#"<circle id="{id}" cx="{cx}" cy="{cy}" r="{r}" {attrs}><title>{title}</title></circle>"#);
        }
        let pts: Vec<String> = self.outline().iter().map(|&(px, py)| format!("{},{}", n(px), n(py))).collect();
        let pts = pts.join(" ");
        format!(r#"<polygon id="{id}" points="{pts}" {attrs}><title>{title}</title></polygon>"#)
    }
}

/// A number as SVG and CSV files show it: at most three decimals, no trailing zeros.
pub fn n(v: f64) -> String {
    let s = format!("{:.3}", v);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shape_fills_its_square() {
        for kind in Kind::EXP1.iter().chain(Kind::EXP5.iter()) {
            let sh = Shape { kind: *kind, x: 10.0, y: 20.0, s: 30.0 };
            let pts = sh.outline();
            let (min_x, max_x) = pts.iter().fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.0), a.1.max(p.0)));
            let (min_y, max_y) = pts.iter().fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.1), a.1.max(p.1)));
            assert!((min_x - 10.0).abs() < 1e-9 && (max_x - 40.0).abs() < 1e-9, "{kind:?}");
            assert!((min_y - 20.0).abs() < 1e-9 && (max_y - 50.0).abs() < 1e-9, "{kind:?}");
        }
    }

    #[test]
    fn numbers_are_short() {
        assert_eq!(n(2.0), "2");
        assert_eq!(n(2.5), "2.5");
        assert_eq!(n(1.0 / 3.0), "0.333");
        assert_eq!(n(-0.0001), "0");
    }
}
