//! Outlines through `i_overlay`: a fill's contours made simple under its
//! fill rule, in integer coordinates of a [`Frame`]. The distance writer
//! unites the fills of a layer with these (`distance::united_fills`), once
//! `crossings::crossings_exceed` has said the overlay's work is bounded (a
//! fill's area is measured without an overlay, `area.rs`).

use i_overlay::core::fill_rule::FillRule as OvFill;
use i_overlay::core::overlay::{IntOverlayOptions, Overlay, ShapeType};
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::i_float::int::point::IntPoint;

use super::{FillRule, Polyline};

/// Integer coordinates are kept within ±2^28.
const LIMIT: f64 = (1u32 << 28) as f64;

/// Integer units of the overlays taken in page mm (a layer's fills united,
/// a shape less the fills over it): 1/65536 mm, so that an edge moves by at
/// most 8 nm, far below a sample step.
pub(crate) const QUANTUM_MM: f64 = 1.0 / 65_536.0;

/// Integer frame: page mm to integer units.
#[derive(Clone, Copy)]
pub(crate) struct Frame {
    pub(crate) ox: f64,
    pub(crate) oy: f64,
    pub(crate) q: f64,
}

impl Frame {
    /// The frame of [`QUANTUM_MM`] units from the corner of `bounds`
    /// `(x0, y0, x1, y1)`; `None` when they span too far for the integer
    /// coordinates to stay within ±2^28.
    pub(crate) fn over(bounds: (f64, f64, f64, f64)) -> Option<Frame> {
        let span = (bounds.2 - bounds.0).max(bounds.3 - bounds.1);
        (span.is_finite() && span / QUANTUM_MM < LIMIT).then_some(Frame { ox: bounds.0, oy: bounds.1, q: QUANTUM_MM })
    }

    fn to_int(self, p: (f64, f64)) -> IntPoint {
        // Far-off coordinates are clamped (the overlay's arithmetic stays in range).
        let c = |v: f64| v.round().clamp(-LIMIT, LIMIT) as i32;
        IntPoint::new(c((p.0 - self.ox) / self.q), c((p.1 - self.oy) / self.q))
    }
}

/// The overlay's fill rule for ours.
pub(crate) fn ov_rule(r: FillRule) -> OvFill {
    match r {
        FillRule::NonZero => OvFill::NonZero,
        FillRule::EvenOdd => OvFill::EvenOdd,
    }
}

/// One shape's closed contours, quantised: the points that lie exactly on
/// the chord of their neighbours are dropped first ([`simplify`](super::simplify)
/// at tolerance 0, on the walked ring), then repeats after rounding.
pub(crate) fn contours(pls: &[Polyline], f: Frame) -> Vec<Vec<IntPoint>> {
    pls.iter()
        .filter(|pl| pl.points.len() >= 3)
        .map(|pl| {
            let mut w = pl.points.clone();
            w.push(pl.points[0]);
            let mut s = super::simplify(&w, false, 0.0);
            s.pop();
            let mut c: Vec<IntPoint> = s.into_iter().map(|p| f.to_int(p)).collect();
            c.dedup();
            c
        })
        .filter(|c| c.len() >= 3)
        .collect()
}

/// The shapes of one set of contours under a fill rule, as simple contours.
pub(crate) fn shapes_of(cs: &[Vec<IntPoint>], rule: OvFill) -> Vec<Vec<Vec<IntPoint>>> {
    if cs.is_empty() {
        return Vec::new();
    }
    let mut o = Overlay::new_custom(cs.len(), IntOverlayOptions::<u64>::default(), Default::default());
    o.add_source(cs, ShapeType::Subject);
    o.overlay(OverlayRule::Subject, rule)
}

/// One filled shape's outlines (`pls` under `rule`) as simple contours.
pub(crate) fn simple(pls: &[Polyline], rule: FillRule, f: Frame) -> Vec<Vec<IntPoint>> {
    shapes_of(&contours(pls, f), ov_rule(rule)).into_iter().flatten().collect()
}

/// The part of `subject` that `clip` does not cover, both as simple
/// contours ([`shapes_of`]'s), under the non-zero rule.
pub(crate) fn difference(subject: &[Vec<IntPoint>], clip: &[Vec<IntPoint>]) -> Vec<Vec<Vec<IntPoint>>> {
    if subject.is_empty() {
        return Vec::new();
    }
    let mut o =
        Overlay::new_custom(subject.len() + clip.len(), IntOverlayOptions::<u64>::default(), Default::default());
    o.add_source(subject, ShapeType::Subject);
    o.add_source(clip, ShapeType::Clip);
    o.overlay(OverlayRule::Difference, OvFill::NonZero)
}

/// The area that shapes of simple contours enclose ([`shapes_of`]'s: each
/// an outer contour, then its holes), in square units of the frame.
pub(crate) fn area(shapes: &[Vec<Vec<IntPoint>>]) -> f64 {
    let ring = |c: &Vec<IntPoint>| -> f64 {
        let n = c.len();
        let twice: f64 = (0..n)
            .map(|k| {
                let (a, b) = (c[k], c[(k + 1) % n]);
                a.x as f64 * b.y as f64 - b.x as f64 * a.y as f64
            })
            .sum();
        twice.abs() / 2.0
    };
    shapes
        .iter()
        .map(|s| s.split_first().map_or(0.0, |(outer, holes)| ring(outer) - holes.iter().map(ring).sum::<f64>()))
        .sum()
}
