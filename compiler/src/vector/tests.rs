//! The vector layer against exact f64 geometry: random polygons and
//! polylines with slivers, holes, self-intersections and collinear points.
//! What a vector layer guarantees with the default parameters (0.004 mm
//! simplification, 1/256 mm quantum, hard edge):
//! - the half-amplitude contour is within [`EDGE_MM`] of the exact outline;
//! - at every point farther than [`EDGE_MM`] from the exact outline the
//!   amplitude is exact (0 or 1).

use proptest::prelude::*;

use super::*;
use crate::distance::exact_signed_distance;
use crate::distance::tests::{outline, square};

type P = (f64, f64);

const PAGE: (f64, f64, f64, f64) = (0.0, 0.0, 40.0, 30.0);

/// Simplification (0.004) + quantisation (q / √2 = 0.0028) + half a hard ramp (q / 2 = 0.002), rounded up.
const EDGE_MM: f64 = 0.01;

fn params(soft: f64, cell: f64) -> VectorParams {
    VectorParams { cell_mm: cell, ..VectorParams::new(soft, PAGE) }
}

/// Points near every segment of the layer (on both sides, at distances
/// around the guarantee) and on a grid.
fn probe_points(g: &LayerGeometry<'_>, step: f64) -> Vec<(f64, f64)> {
    let mut v = Vec::new();
    let mut y = -1.0 + step / 3.0;
    while y < PAGE.3 + 1.0 {
        let mut x = -1.0 + step / 7.0;
        while x < PAGE.2 + 1.0 {
            v.push((x, y));
            x += step;
        }
        y += step;
    }
    let mut segs: Vec<(P, P, f64)> = Vec::new();
    for (pls, _) in g.fills.iter().chain(&g.clips) {
        for pl in pls.iter() {
            let n = pl.points.len();
            segs.extend((0..n).map(|i| (pl.points[i], pl.points[(i + 1) % n], 0.0)));
        }
    }
    for (lines, w) in g.band.iter().flat_map(|(l, w)| l.iter().map(move |p| (*p, *w))).chain(g.cuts.iter().copied()) {
        for pl in lines {
            segs.extend(pl.segments().map(|(a, b)| (a, b, w / 2.0)));
        }
    }
    for (a, b, off) in segs {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = dx.hypot(dy);
        if len < 1e-9 {
            continue;
        }
        let (nx, ny) = (-dy / len, dx / len);
        for t in [0.0, 0.13, 0.5, 0.91] {
            for o in [0.0, 0.002, 0.008, 0.011, 0.03, 0.3] {
                for side in [-1.0, 1.0] {
                    let k = off + side * o;
                    for sgn in [-1.0, 1.0] {
                        v.push((a.0 + dx * t + sgn * nx * k, a.1 + dy * t + sgn * ny * k));
                    }
                }
            }
        }
    }
    v
}

/// The layer's coverage against the exact signed distance at `points`.
fn check(g: &LayerGeometry<'_>, p: VectorParams, points: &[(f64, f64)]) -> Result<(), TestCaseError> {
    let exact = |q: (f64, f64)| exact_signed_distance(g, p.page, q);
    let layer = build_vector(g, p).map_err(|e| TestCaseError::fail(format!("{e:?}")))?;
    for &q in points {
        let e = exact(q);
        let a = layer.as_ref().map_or(0.0, |l| l.coverage_at(q.0 as f32, q.1 as f32));
        if e.abs() > EDGE_MM + p.soft_mm / 2.0 {
            let want = if e > 0.0 { 1.0 } else { 0.0 };
            prop_assert!(a == want, "{q:?}: amplitude {a}, exact distance {e}");
        }
        if (a >= 0.5) != (e > 0.0) {
            prop_assert!(e.abs() <= EDGE_MM, "{q:?}: amplitude {a} on the wrong side, {e} mm from the edge");
        }
        if p.soft_mm > 0.0 {
            let want = (0.5 + e / p.soft_mm).clamp(0.0, 1.0);
            prop_assert!((a as f64 - want).abs() <= EDGE_MM / p.soft_mm + 1e-4, "{q:?}: soft {a}, exact {want}");
        }
    }
    Ok(())
}

#[test]
fn a_square_is_exact_at_its_sides_and_corners() {
    let sq = [square(5.0, 5.0, 20.0)];
    let g = LayerGeometry { fills: vec![(&sq, FillRule::NonZero)], ..Default::default() };
    let l = build_vector(&g, params(0.0, 2.0)).expect("built").expect("felt");
    // The square's corners and sides land on whole quanta: exact.
    assert_eq!(l.coverage_at(5.01, 5.01), 1.0);
    assert_eq!(l.coverage_at(4.99, 4.99), 0.0);
    assert_eq!(l.coverage_at(24.995, 24.995), 1.0);
    assert_eq!(l.coverage_at(25.005, 15.0), 0.0);
    assert_eq!(l.coverage_at(5.0, 15.0), 0.5);
    check(&g, params(0.0, 2.0), &probe_points(&g, 0.173)).expect("within the guarantee");
}

#[test]
fn touching_and_overlapping_fills_of_one_style_are_one_region() {
    // Two squares sharing a side, a third overlapping them, a fourth touching at a corner.
    let a = [square(5.0, 5.0, 5.0)];
    let b = [square(10.0, 5.0, 5.0)];
    let c = [square(8.0, 8.0, 5.0)];
    let d = [square(15.0, 10.0, 5.0)];
    let g = LayerGeometry {
        fills: vec![(&a, FillRule::NonZero), (&b, FillRule::EvenOdd), (&c, FillRule::NonZero), (&d, FillRule::NonZero)],
        ..Default::default()
    };
    let l = build_vector(&g, params(0.0, 1.0)).expect("built").expect("felt");
    // No edge along the shared side.
    assert_eq!(l.coverage_at(10.0, 6.0), 1.0);
    check(&g, params(0.0, 1.0), &probe_points(&g, 0.11)).expect("within the guarantee");
}

#[test]
fn bands_cut_out_of_a_grating_and_clips() {
    let sq = [square(5.0, 5.0, 20.0)];
    let line = [Polyline { points: vec![(2.0, 15.0), (28.0, 15.0), (28.0, 3.0)], closed: false }];
    let clip = [square(0.0, 0.0, 18.0)];
    let g = LayerGeometry {
        fills: vec![(&sq, FillRule::NonZero)],
        cuts: vec![(&line, 1.5), (&sq, 0.8)],
        clips: vec![(&clip, FillRule::NonZero)],
        ..Default::default()
    };
    let l = build_vector(&g, params(0.0, 2.0)).expect("built").expect("felt");
    assert_eq!(l.coverage_at(10.0, 15.0), 0.0, "under the band");
    assert_eq!(l.coverage_at(10.0, 12.0), 1.0);
    assert_eq!(l.coverage_at(20.0, 12.0), 0.0, "outside the clip");
    check(&g, params(0.0, 2.0), &probe_points(&g, 0.13)).expect("within the guarantee");
    // The vibrating band itself, touching borders of one style merged.
    let other = [square(25.0, 5.0, 10.0)];
    let g = LayerGeometry { band: Some((vec![&sq[..], &other[..], &line[..]], 1.5)), ..Default::default() };
    let l = build_vector(&g, params(0.0, 2.0)).expect("built").expect("felt");
    assert_eq!(l.coverage_at(25.0, 10.0), 1.0, "one border, not two");
    check(&g, params(0.0, 2.0), &probe_points(&g, 0.13)).expect("within the guarantee");
    check(&g, params(0.3, 2.0), &probe_points(&g, 0.13)).expect("soft edges");
}

#[test]
fn a_page_too_large_or_too_many_widths_is_an_error_not_a_panic() {
    let sq = [square(5.0, 5.0, 20.0)];
    let g = LayerGeometry { fills: vec![(&sq, FillRule::NonZero)], ..Default::default() };
    let huge = VectorParams::new(0.0, (0.0, 0.0, 1e9, 1e9));
    assert_eq!(build_vector(&g, huge).err(), Some(VectorError::TooLarge));
    let bad = VectorParams { cell_mm: f64::NAN, ..params(0.0, 1.0) };
    assert_eq!(build_vector(&g, bad).err(), Some(VectorError::BadParams));
    let lines: Vec<[Polyline; 1]> = (0..9).map(|k| [square(1.0 + k as f64, 1.0, 1.0)]).collect();
    let cuts = lines.iter().enumerate().map(|(k, l)| (&l[..], 0.1 + k as f64 * 0.1)).collect();
    let g = LayerGeometry { fills: vec![(&sq, FillRule::NonZero)], cuts, ..Default::default() };
    assert_eq!(build_vector(&g, params(0.0, 1.0)).err(), Some(VectorError::TooManyGroups));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// Fills: one or two outlines as one shape (a second one inside the
    /// first is a hole under even-odd), and a second shape of the style.
    #[test]
    fn fills_match_exact_geometry(a in outline(), b in outline(), c in outline(), two in any::<bool>(), evenodd in any::<bool>(), cell in prop::sample::select(vec![0.5, 1.0, 2.0, 4.0])) {
        let shape = if two { vec![a, b] } else { vec![a] };
        let rule = if evenodd { FillRule::EvenOdd } else { FillRule::NonZero };
        let other = [c];
        let g = LayerGeometry { fills: vec![(&shape, rule), (&other, FillRule::NonZero)], ..Default::default() };
        check(&g, params(0.0, cell), &probe_points(&g, 0.37))?;
    }

    /// Bands along open or closed polylines of any shape, hard or soft.
    #[test]
    fn bands_match_exact_geometry(a in outline(), width in 0.2f64..3.0, soft in prop::sample::select(vec![0.0, 0.3]), cell in prop::sample::select(vec![1.0, 2.0])) {
        let lines = [a];
        let g = LayerGeometry { band: Some((vec![&lines[..]], width)), ..Default::default() };
        check(&g, params(soft, cell), &probe_points(&g, 0.29))?;
    }

    /// A grating minus a band, within a clip.
    #[test]
    fn cut_and_clipped_fills_match_exact_geometry(a in outline(), b in outline(), c in outline(), width in 0.2f64..2.0) {
        let (fill, band, clip) = ([a], [b], [c]);
        let g = LayerGeometry {
            fills: vec![(&fill, FillRule::EvenOdd)],
            cuts: vec![(&band, width)],
            clips: vec![(&clip, FillRule::NonZero)],
            ..Default::default()
        };
        check(&g, params(0.0, 2.0), &probe_points(&g, 0.37))?;
    }
}
