//! The footprints chunk (`FOOT`, SPEC.md section 10.1): where each source
//! element lies on the surface, for the host's point lookup. Each rendered
//! style of an element gives one shape: a grated region its fill, a
//! vibrating outline its centre lines with half the band's width, dots
//! their discs, a braille text the box around its cells (a brushed stroke,
//! which plays in time with no reader's position, has none). Outlines are
//! simplified
//! (Douglas–Peucker, [`SIMPLIFY_MM`]) and quantised to 16-bit coordinates.

use taxel_format::{Footprint, FootprintKind, Footprints};

use crate::geometry::{FillRule, Polyline};

/// How far a simplified outline may stray from the drawing's: far below a
/// finger's resolution, and it keeps a typical map's chunk a few kilobytes.
pub(crate) const SIMPLIFY_MM: f64 = 0.05;
/// The finest quantum (mm per coordinate step); coarser only when the
/// drawing is wider than 65535 quanta.
const FINEST_QUANTUM_MM: f64 = 0.01;

/// One shape before quantisation, in page (surface) mm.
#[derive(Debug, Clone)]
pub(crate) struct Pending {
    /// Document order of the element: later ones lie on top.
    pub order: usize,
    pub source: u32,
    pub kind: FootprintKind,
    pub half_width_mm: f64,
    pub rings: Vec<Vec<(f64, f64)>>,
}

impl Pending {
    /// A filled region's shape.
    pub fn area(order: usize, source: u32, outline: &[Polyline], rule: FillRule) -> Option<Self> {
        let kind = match rule {
            FillRule::EvenOdd => FootprintKind::AreaEvenOdd,
            FillRule::NonZero => FootprintKind::AreaNonZero,
        };
        let rings: Vec<_> =
            outline.iter().map(|p| simplify(&p.points, true)).filter(|r: &Vec<_>| r.len() >= 3).collect();
        (!rings.is_empty()).then_some(Pending { order, source, kind, half_width_mm: 0.0, rings })
    }

    /// A band around polylines (closed ones walked back to their start).
    pub fn band(order: usize, source: u32, outline: &[Polyline], half_width_mm: f64) -> Option<Self> {
        let rings: Vec<_> = outline.iter().map(|p| simplify(&p.walked(), false)).filter(|r| !r.is_empty()).collect();
        (!rings.is_empty()).then_some(Pending { order, source, kind: FootprintKind::Line, half_width_mm, rings })
    }

    /// A rectangle `(x0, y0, x1, y1)` as a region (a braille text's box, so
    /// that a finger between its dots still finds it).
    pub fn rect(order: usize, source: u32, (x0, y0, x1, y1): (f64, f64, f64, f64)) -> Option<Self> {
        (x0 < x1 && y0 < y1).then(|| Pending {
            order,
            source,
            kind: FootprintKind::AreaNonZero,
            half_width_mm: 0.0,
            rings: vec![vec![(x0, y0), (x1, y0), (x1, y1), (x0, y1)]],
        })
    }

    /// Discs of one radius.
    pub fn discs(order: usize, source: u32, centres: &[(f64, f64)], radius_mm: f64) -> Option<Self> {
        let rings: Vec<_> = centres.iter().filter(|p| p.0.is_finite() && p.1.is_finite()).map(|&p| vec![p]).collect();
        (!rings.is_empty()).then_some(Pending {
            order,
            source,
            kind: FootprintKind::Line,
            half_width_mm: radius_mm,
            rings,
        })
    }
}

/// The chunk: shapes in document order (stable, so an element's styles keep
/// the order they were rendered in), quantised from the smallest corner.
pub(crate) fn chunk(mut pending: Vec<Pending>) -> Option<Footprints> {
    pending.retain(|p| p.rings.iter().flatten().all(|q| q.0.is_finite() && q.1.is_finite()));
    // Within one element, its fill lies below its outline and dots (SVG paints fill, then stroke).
    pending.sort_by_key(|p| (p.order, !p.kind.is_area()));
    let pts = || pending.iter().flat_map(|p| p.rings.iter().flatten());
    let (x0, y0) = pts().fold((f64::MAX, f64::MAX), |a, p| (a.0.min(p.0), a.1.min(p.1)));
    let (x1, y1) = pts().fold((f64::MIN, f64::MIN), |a, p| (a.0.max(p.0), a.1.max(p.1)));
    if x0 > x1 || y0 > y1 {
        return None;
    }
    let origin = (x0.floor().clamp(-1e6, 1e6), y0.floor().clamp(-1e6, 1e6));
    let extent = (x1 - origin.0).max(y1 - origin.1);
    let quantum = (FINEST_QUANTUM_MM.max(extent / 65_000.0) as f32).min(1.0);
    let q = quantum as f64;
    let quant = |v: f64, o: f64| ((v - o) / q).round().clamp(0.0, 65_535.0) as u16;
    let shapes = pending
        .into_iter()
        .map(|p| {
            let mut rings: Vec<Vec<(u16, u16)>> = p
                .rings
                .iter()
                .map(|r| {
                    let mut out: Vec<(u16, u16)> =
                        r.iter().map(|&(x, y)| (quant(x, origin.0), quant(y, origin.1))).collect();
                    out.dedup();
                    out
                })
                .collect();
            if p.kind.is_area() {
                rings.retain(|r| r.len() >= 3);
            }
            Footprint {
                source: p.source,
                kind: p.kind,
                half_width: (p.half_width_mm / q).round().clamp(0.0, 65_535.0) as u16,
                rings,
            }
        })
        .filter(|s| !s.rings.is_empty())
        .collect::<Vec<_>>();
    (!shapes.is_empty()).then_some(Footprints {
        origin_x: origin.0 as f32,
        origin_y: origin.1 as f32,
        quantum_mm: quantum,
        shapes,
    })
}

/// Douglas–Peucker simplification to [`SIMPLIFY_MM`].
fn simplify(points: &[(f64, f64)], closed: bool) -> Vec<(f64, f64)> {
    crate::geometry::simplify(points, closed, SIMPLIFY_MM)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simplify_keeps_corners_and_drops_collinear_points() {
        let square: Vec<(f64, f64)> = vec![(0.0, 0.0), (5.0, 0.0), (10.0, 0.0), (10.0, 10.0), (5.0, 10.0), (0.0, 10.0)];
        assert_eq!(simplify(&square, true), vec![(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)]);
        let line: Vec<(f64, f64)> = (0..=10).map(|i| (i as f64, 0.01 * (i % 2) as f64)).collect();
        assert_eq!(simplify(&line, false), vec![(0.0, 0.0), (10.0, 0.0)]);
    }
}
