//! Marks cut to a region: an element's clip paths (a chart's data in its
//! axes, a map's inset, the crop to the page), a page's window of a
//! drawing printed on several pages, and the opaque fills painted over a
//! texture, which hide it there.
//!
//! A line is kept where its centre line is inside the region (its round
//! ends may then stand half its width beyond the region's edge, as a pen
//! stroke cut there would); a dot or a braille dot where its centre is; a
//! polygon (a symbol, an arrowhead) where its area is. Lines and polygons
//! are cut by `i_overlay`, the region first made simple under its own fill
//! rule so that one rule, non-zero, serves both.

use i_overlay::core::fill_rule::FillRule as OvFill;
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::float::clip::FloatClip;
use i_overlay::float::simplify::SimplifyShape;
use i_overlay::float::single::SingleFloatOverlay;
use i_overlay::string::clip::ClipRule;

use super::{Mark, MarkShape};
use crate::geometry::{FillRule, Polyline};
use crate::spatial::{Bbox, meet};

type Contour = Vec<[f64; 2]>;

/// A region marks are cut to, in paper mm.
pub(super) struct Region {
    /// Its contours made simple (outer rings and holes, non-zero).
    contours: Vec<Contour>,
    /// Its outline as given, for the inside test of points.
    outline: Vec<Polyline>,
    rule: FillRule,
    /// Its box; `None` when it has no area.
    bounds: Option<Bbox>,
    /// Whether it is its box (a crop, a page): marks inside its box need no cutting.
    is_box: bool,
    /// Whether marks are kept outside it rather than inside (an opaque fill
    /// painted over a texture hides the texture under it).
    outside: bool,
}

impl Region {
    /// The region `outline` (page mm, filled by `rule`) moved by `shift` onto the paper.
    pub fn new(outline: &[Polyline], rule: FillRule, shift: (f64, f64)) -> Self {
        let outline: Vec<Polyline> = outline
            .iter()
            .map(|pl| Polyline {
                points: pl.points.iter().map(|p| (p.0 + shift.0, p.1 + shift.1)).collect(),
                closed: true,
            })
            .collect();
        let raw: Vec<Contour> = outline
            .iter()
            .filter(|pl| pl.points.len() >= 3 && pl.points.iter().all(|p| p.0.is_finite() && p.1.is_finite()))
            .map(|pl| pl.points.iter().map(|p| [p.0, p.1]).collect())
            .collect();
        let ov = match rule {
            FillRule::NonZero => OvFill::NonZero,
            FillRule::EvenOdd => OvFill::EvenOdd,
        };
        let contours: Vec<Contour> = raw.simplify_shape(ov).into_iter().flatten().collect();
        let bounds = crate::geometry::bounds(&outline).filter(|_| !contours.is_empty());
        let is_box = bounds.is_some_and(|b| {
            outline.len() == 1
                && outline[0].points.len() == 4
                && outline[0].points.iter().all(|p| (p.0 == b.0 || p.0 == b.2) && (p.1 == b.1 || p.1 == b.3))
        });
        Region { contours, outline, rule, bounds, is_box, outside: false }
    }

    /// The region, marks kept outside it.
    pub fn hiding(self) -> Self {
        Region { outside: true, ..self }
    }

    /// The box `b` as a region.
    pub fn rect(b: Bbox) -> Self {
        let ring = Polyline { points: vec![(b.0, b.1), (b.2, b.1), (b.2, b.3), (b.0, b.3)], closed: true };
        Region::new(&[ring], FillRule::NonZero, (0.0, 0.0))
    }

    fn holds(&self, p: (f64, f64)) -> bool {
        let Some(b) = self.bounds else { return false };
        p.0 >= b.0
            && p.0 <= b.2
            && p.1 >= b.1
            && p.1 <= b.3
            && (self.is_box || crate::geometry::contains(&self.outline, p, self.rule))
    }

    /// Whether the box `b` lies inside the region's box.
    fn within_box(&self, b: Bbox) -> bool {
        self.bounds.is_some_and(|r| b.0 >= r.0 && b.1 >= r.1 && b.2 <= r.2 && b.3 <= r.3)
    }
}

/// The box of a mark's geometry (a dot's centre alone: it is kept by its centre).
fn mark_box(m: &MarkShape) -> Option<Bbox> {
    let pts: Box<dyn Iterator<Item = (f64, f64)>> = match m {
        MarkShape::Line { points, .. } => Box::new(points.iter().copied()),
        MarkShape::Polygon { rings } => Box::new(rings.iter().flatten().copied()),
        MarkShape::Dot { centre, .. } => Box::new(std::iter::once(*centre)),
    };
    pts.fold(None, |b: Option<Bbox>, p| {
        Some(b.map_or((p.0, p.1, p.0, p.1), |b| (b.0.min(p.0), b.1.min(p.1), b.2.max(p.0), b.3.max(p.1))))
    })
}

fn length(path: &[[f64; 2]]) -> f64 {
    path.windows(2).map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1])).sum()
}

/// `marks` cut to `region`: what lies outside is left out (inside, for a
/// [`Region::hiding`] one), what crosses its edge is cut there, and a mark
/// wholly kept is kept as it is.
pub(super) fn cut(marks: Vec<Mark>, region: &Region) -> Vec<Mark> {
    let keep_inside = !region.outside;
    let Some(rb) = region.bounds else { return if keep_inside { Vec::new() } else { marks } };
    let mut out = Vec::with_capacity(marks.len());
    for m in marks {
        let Some(b) = mark_box(&m.shape) else { continue };
        if !meet(b, rb) {
            if !keep_inside {
                out.push(m);
            }
            continue;
        }
        match &m.shape {
            MarkShape::Dot { centre, .. } => {
                if region.holds(*centre) == keep_inside {
                    out.push(m);
                }
            }
            _ if keep_inside && region.is_box && region.within_box(b) => out.push(m),
            MarkShape::Line { points, closed, width_mm } => {
                let mut path: Contour = points.iter().map(|p| [p.0, p.1]).collect();
                if *closed && let Some(&first) = path.first() {
                    path.push(first);
                }
                if path.len() == 1 {
                    // A line of one point is a round dot of its width.
                    if region.holds(points[0]) == keep_inside {
                        out.push(m);
                    }
                    continue;
                }
                let rule = ClipRule { invert: !keep_inside, boundary_included: keep_inside };
                let pieces = path.clip_by(&region.contours, OvFill::NonZero, rule);
                let kept: f64 = pieces.iter().map(|p| length(p)).sum();
                let whole = length(&path);
                if (kept - whole).abs() <= 1e-9 * whole.max(1.0) {
                    out.push(m);
                    continue;
                }
                let (width_mm, level, element) = (*width_mm, m.level, m.element);
                for piece in pieces.into_iter().filter(|p| p.len() >= 2) {
                    let points = piece.into_iter().map(|p| (p[0], p[1])).collect();
                    out.push(Mark { shape: MarkShape::Line { points, closed: false, width_mm }, level, element });
                }
            }
            MarkShape::Polygon { rings } => {
                let subject: Vec<Contour> = rings.iter().map(|r| r.iter().map(|p| [p.0, p.1]).collect()).collect();
                let op = if keep_inside { OverlayRule::Intersect } else { OverlayRule::Difference };
                let shapes = subject.overlay(&region.contours, op, OvFill::NonZero);
                let rings: Vec<Vec<(f64, f64)>> = shapes
                    .into_iter()
                    .flatten()
                    .filter(|c| c.len() >= 3)
                    .map(|c| c.into_iter().map(|p| (p[0], p[1])).collect())
                    .collect();
                if !rings.is_empty() {
                    out.push(Mark { shape: MarkShape::Polygon { rings }, ..m });
                }
            }
        }
    }
    out
}

/// `marks` moved by `d`.
pub(super) fn shift(marks: &mut [Mark], d: (f64, f64)) {
    let mv = |p: &mut (f64, f64)| *p = (p.0 + d.0, p.1 + d.1);
    for m in marks {
        match &mut m.shape {
            MarkShape::Line { points, .. } => points.iter_mut().for_each(mv),
            MarkShape::Polygon { rings } => rings.iter_mut().flatten().for_each(mv),
            MarkShape::Dot { centre, .. } => mv(centre),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::print::Level;

    fn line(points: &[(f64, f64)], closed: bool) -> Mark {
        Mark {
            shape: MarkShape::Line { points: points.to_vec(), closed, width_mm: 1.0 },
            level: Level::Line,
            element: Some(0),
        }
    }

    fn dot(c: (f64, f64)) -> Mark {
        Mark { shape: MarkShape::Dot { centre: c, diameter_mm: 1.5 }, level: Level::Braille, element: None }
    }

    fn lines(marks: &[Mark]) -> Vec<Vec<(f64, f64)>> {
        marks
            .iter()
            .filter_map(|m| match &m.shape {
                MarkShape::Line { points, .. } => Some(points.clone()),
                _ => None,
            })
            .collect()
    }

    fn near(a: (f64, f64), b: (f64, f64)) -> bool {
        (a.0 - b.0).abs() < 1e-6 && (a.1 - b.1).abs() < 1e-6
    }

    /// A line across a square is cut at the square's sides; one inside is
    /// kept as it is, closed; one outside is left out.
    #[test]
    fn lines_are_cut_at_the_region_edge() {
        let r = Region::rect((10.0, 10.0, 20.0, 20.0));
        let inside = line(&[(12.0, 12.0), (18.0, 12.0), (18.0, 18.0)], true);
        let out = cut(
            vec![line(&[(0.0, 15.0), (30.0, 15.0)], false), inside.clone(), line(&[(0.0, 0.0), (5.0, 5.0)], false)],
            &r,
        );
        assert_eq!(out.len(), 2);
        let across = &lines(&out)[0];
        assert_eq!(across.len(), 2);
        let (a, b) = (across[0].min_by_x(across[1]), across[0].max_by_x(across[1]));
        assert!(near(a, (10.0, 15.0)) && near(b, (20.0, 15.0)), "{across:?}");
        assert_eq!(out[1], inside);
    }

    trait ByX {
        fn min_by_x(self, o: Self) -> Self;
        fn max_by_x(self, o: Self) -> Self;
    }

    impl ByX for (f64, f64) {
        fn min_by_x(self, o: Self) -> Self {
            if self.0 <= o.0 { self } else { o }
        }
        fn max_by_x(self, o: Self) -> Self {
            if self.0 > o.0 { self } else { o }
        }
    }

    /// A region with a hole (even-odd): a line through it keeps only the
    /// two pieces in the ring, each of the ring's width; dots in the hole go.
    #[test]
    fn a_ring_region_cuts_out_its_hole() {
        let sq = |a: f64, b: f64| Polyline { points: vec![(a, a), (b, a), (b, b), (a, b)], closed: true };
        let r = Region::new(&[sq(0.0, 30.0), sq(10.0, 20.0)], FillRule::EvenOdd, (0.0, 0.0));
        let out = cut(vec![line(&[(-5.0, 15.0), (35.0, 15.0)], false), dot((15.0, 15.0)), dot((5.0, 15.0))], &r);
        let mut widths: Vec<f64> = lines(&out).iter().map(|p| (p[0].0 - p[p.len() - 1].0).abs()).collect();
        widths.sort_by(f64::total_cmp);
        assert_eq!(widths.len(), 2, "{out:?}");
        assert!(widths.iter().all(|w| (w - 10.0).abs() < 1e-6), "{widths:?}");
        let dots: Vec<_> = out.iter().filter(|m| matches!(m.shape, MarkShape::Dot { .. })).collect();
        assert_eq!(dots.len(), 1);
        assert_eq!(dots[0].shape, dot((5.0, 15.0)).shape);
    }

    /// A polygon half over the edge keeps the half inside: its area halves.
    #[test]
    fn polygons_keep_their_area_inside() {
        let r = Region::new(
            &[Polyline { points: vec![(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)], closed: true }],
            FillRule::NonZero,
            (5.0, 0.0),
        );
        let tri = Mark {
            shape: MarkShape::Polygon { rings: vec![vec![(0.0, 0.0), (10.0, 0.0), (10.0, 4.0), (0.0, 4.0)]] },
            level: Level::Line,
            element: Some(1),
        };
        let out = cut(vec![tri], &r);
        let MarkShape::Polygon { rings } = &out[0].shape else { panic!("{out:?}") };
        let area: f64 = rings
            .iter()
            .map(|r| {
                (0..r.len()).map(|i| r[i].0 * r[(i + 1) % r.len()].1 - r[(i + 1) % r.len()].0 * r[i].1).sum::<f64>()
                    / 2.0
            })
            .sum();
        assert!((area.abs() - 20.0).abs() < 1e-6, "{area}");
        assert!(rings.iter().flatten().all(|p| p.0 >= 5.0 - 1e-9));
    }
}
