//! The field against exact f64 geometry: random polygons and polylines with
//! slivers, holes, self-intersections and collinear points. Curved and
//! meeting edges are in `tests/curves.rs`, the searches tiles are built from
//! in `tests/searches.rs`, the references in `tests/reference.rs`.

use proptest::prelude::*;
use taxel_format::{TILE_CELLS, TILE_INSIDE, TILE_OUTSIDE, TILE_SAMPLES};

use super::*;

mod curves;
pub(crate) mod reference;
mod searches;

use reference::{constant_tile_at, exact_signed_distance, field_distance};

const PAGE: (f64, f64, f64, f64) = (0.0, 0.0, 40.0, 30.0);

pub(crate) fn square(x: f64, y: f64, s: f64) -> Polyline {
    Polyline { points: vec![(x, y), (x + s, y), (x + s, y + s), (x, y + s)], closed: true }
}

fn params(pitch: f64, soft: f64) -> FieldParams {
    FieldParams { pitch_mm: pitch, soft_mm: soft, page: PAGE }
}

/// Checks the field at `points` against the exact signed distance:
/// - wherever the exact distance is affine over the point's cell (the
///   bilinear interpolation of the exact corner values gives the exact
///   value), the field is within half a step of it: only quantisation;
/// - everywhere in reach, within the Lipschitz bound of bilinear
///   interpolation (h √2) plus half a step;
/// - farther than that from any edge, on the right side (the hard profile's
///   value is exact);
/// - in a plane, ridge, bend, arc or segments tile (which plays its function
///   at the point, not a bilinear interpolation): at the corners and the centre of the point's
///   cell (what the writer checks, here against exact geometry), within
///   half a step, or farther than half the ramp plus `h` from the edge
///   saturated on the exact side; at the point itself on the exact side
///   farther than `h √2` plus a step from any edge.
fn check(g: &LayerGeometry<'_>, p: FieldParams, points: &[(f64, f64)]) -> Result<(), TestCaseError> {
    check_against(g, g, p, points)
}

/// [`check`] of the field built from `g` against the exact distance of
/// `reference`: the same geometry with parts united as the builder unites
/// them (see `occluded_fills_match_exact_geometry`).
fn check_against(
    g: &LayerGeometry<'_>,
    reference: &LayerGeometry<'_>,
    p: FieldParams,
    points: &[(f64, f64)],
) -> Result<(), TestCaseError> {
    let h = p.pitch_mm;
    let exact = |q: (f64, f64)| exact_signed_distance(reference, p.page, q);
    let reach = p.soft_mm / 2.0 + 2.0 * h;
    let Some(f) = build_field(g, p) else {
        // Nothing felt: the field is what outside constant tiles on the
        // layer's lattice (multiples of h) would play, and is held to their
        // rule below: the exact distances at the corners of each point's
        // cell saturate the profile outside, and a point farther than the
        // interpolation bound h √2 from any edge is outside. (A sliver
        // narrower than a cell between samples that all saturate outside is
        // not felt, as in a stored field.)
        let step = reach / 126.0;
        let ramp = taxel_format::edge_ramp(p.soft_mm as f32, step as f32) as f64;
        for &q in points {
            let e = exact(q);
            let (ci, cj) = ((q.0 / h).floor(), (q.1 / h).floor());
            for (i, j) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
                let v = exact(((ci + i) * h, (cj + j) * h));
                prop_assert!(-v >= ramp / 2.0 - step, "no field, but {q:?}'s cell corner is at {v}");
            }
            if e.abs() > h * std::f64::consts::SQRT_2 {
                prop_assert!(e < 0.0, "no field, but {q:?} is inside by {e}");
            }
        }
        return Ok(());
    };
    if let Err(e) = f.sanity_check(p) {
        return Err(TestCaseError::fail(format!("the field breaks an invariant: {e}")));
    }
    for &q in points {
        let e = exact(q);
        let got = field_distance(&f, h, q);
        let Some(got) = got else {
            prop_assert!(e <= 1e-9, "{q:?} is outside the lattice but inside by {e}");
            continue;
        };
        // Corners of q's cell, on the lattice.
        let (ci, cj) = (((q.0 - f.origin.0) / h).floor(), ((q.1 - f.origin.1) / h).floor());
        let c = |i: f64, j: f64| exact((f.origin.0 + (ci + i) * h, f.origin.1 + (cj + j) * h));
        let (wx, wy) = ((q.0 - f.origin.0) / h - ci, (q.1 - f.origin.1) / h - cj);
        let corners = [c(0.0, 0.0), c(1.0, 0.0), c(0.0, 1.0), c(1.0, 1.0)];
        if let Some(inside) = constant_tile_at(&f, h, q) {
            // A constant tile stands for samples that all saturate the edge
            // profile on its side: so do the exact distances at the cell's
            // corners, within half a step of quantisation.
            let ramp = taxel_format::edge_ramp(p.soft_mm as f32, f.step_mm as f32) as f64;
            let sign = if inside { 1.0 } else { -1.0 };
            for v in corners {
                prop_assert!(sign * v >= ramp / 2.0 - f.step_mm, "{q:?}: constant tile (inside {inside}), corner {v}");
            }
            if e.abs() > h * std::f64::consts::SQRT_2 {
                prop_assert!(e.signum() == sign, "{q:?}: constant tile (inside {inside}), exact {e}");
            }
            continue;
        }
        if let Some((e_tile, vertex)) = bend_at(&f, h, q) {
            // A corner or notch tile: at the corners and the centre of the
            // point's cell, the code plays the exact distance's amplitude
            // (both clamped to the profile's saturated range, within half a
            // step) except within the spot round its vertex; at the point
            // itself on the exact side farther than `h √2` plus a step from
            // any edge.
            let (full, none) = saturated_codes(p.soft_mm, f.step_mm);
            let (hi, lo) = ((full as f64 - 128.0) * f.step_mm, (none as f64 - 128.0) * f.step_mm);
            let tol = f.step_mm * 0.5 + 1e-9;
            for (i, j) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (0.5, 0.5)] {
                let pt = (f.origin.0 + (ci + i) * h, f.origin.1 + (cj + j) * h);
                let Some(v) = field_distance(&f, h, pt) else { continue };
                if bend_at(&f, h, pt).map(|b| b.0) != Some(e_tile)
                    || (pt.0 - vertex.0).hypot(pt.1 - vertex.1) <= bends::SPOT_MM + 1e-9
                {
                    continue;
                }
                let ex = exact(pt);
                prop_assert!(
                    (v.clamp(lo, hi) - ex.clamp(lo, hi)).abs() <= tol,
                    "{pt:?}: corner tile, field {v}, exact {ex} (vertex {vertex:?})"
                );
            }
            if e.abs() > h * std::f64::consts::SQRT_2 + f.step_mm {
                prop_assert!(got.signum() == e.signum(), "{q:?}: corner tile, field {got}, exact {e}");
            }
            continue;
        }
        if let Some(&e_tile) = plane_tile_at(&f, h, q) {
            let ramp = taxel_format::edge_ramp(p.soft_mm as f32, f.step_mm as f32) as f64;
            let (full, none) = saturated_codes(p.soft_mm, f.step_mm);
            let (hi, lo) = ((full as f64 - 128.0) * f.step_mm, (none as f64 - 128.0) * f.step_mm);
            let tol = f.step_mm * 0.5 + 1e-9;
            let cap = 127.0 * f.step_mm;
            for (i, j) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (0.5, 0.5)] {
                let pt = (f.origin.0 + (ci + i) * h, f.origin.1 + (cj + j) * h);
                let (Some(v), ex) = (field_distance(&f, h, pt), exact(pt).clamp(-cap, cap)) else { continue };
                // A corner on the tile's far side belongs to the next tile.
                if plane_tile_at(&f, h, pt) != Some(&e_tile) {
                    continue;
                }
                // The writer's rule (`Saturation::close`): within half a
                // ramp, half a pitch and a step of the edge, by either
                // distance, within half a step; beyond, saturated alike.
                let pin = ramp / 2.0 + h / 2.0 + f.step_mm;
                prop_assert!(
                    (v - ex).abs() <= tol
                        || ex.abs().min(v.abs()) > pin - 1e-9 && ((ex >= hi && v >= hi) || (ex <= lo && v <= lo)),
                    "{pt:?}: plane tile, field {v}, exact {ex} (ramp {ramp})"
                );
            }
            if e.abs() > h * std::f64::consts::SQRT_2 + f.step_mm {
                prop_assert!(got.signum() == e.signum(), "{q:?}: plane tile, field {got}, exact {e}");
            }
            continue;
        }
        if corners.iter().any(|v| v.abs() >= reach) {
            // A clamped cell: saturated on the exact side.
            if e.abs() > h * 1.5 {
                prop_assert!(got.signum() == e.signum(), "{q:?}: field {got}, exact {e}");
            }
            continue;
        }
        let top = corners[0] + (corners[1] - corners[0]) * wx;
        let bot = corners[2] + (corners[3] - corners[2]) * wx;
        let bilinear = top + (bot - top) * wy;
        let tol = f.step_mm * 0.5 + 1e-9;
        // Where the exact distance at `q` is the bilinear interpolation of
        // the cell's corners, a stored tile's field (the interpolation of
        // their codes) is exact within half a step. A fine tile interpolates
        // finer samples instead: where a crease passes between the cell's
        // corners and its fine samples (two parts' edges meeting, which is
        // where the writer refines), the coarse interpolation may meet the
        // exact distance at `q` by chance while the fine one does not; it is
        // held to the bounds below.
        if (bilinear - e).abs() < 1e-9 && !fine_tile_at(&f, h, q) {
            prop_assert!((got - e).abs() <= tol, "{q:?}: affine cell, field {got}, exact {e}");
        }
        prop_assert!((got - e).abs() <= h * std::f64::consts::SQRT_2 + tol, "{q:?}: field {got}, exact {e}");
        if e.abs() > h * std::f64::consts::SQRT_2 + tol {
            prop_assert!(got.signum() == e.signum(), "{q:?}: field {got}, exact {e}");
        }
    }
    Ok(())
}

/// The index entry of the plane, ridge, bend, arc or segments tile `p` lies
/// in, if it does (each plays its function at the point, checked at the
/// samples and the cell centres).
fn plane_tile_at(f: &Field, h: f64, p: (f64, f64)) -> Option<&u32> {
    let (fx, fy) = ((p.0 - f.origin.0) / h, (p.1 - f.origin.1) / h);
    if !(fx >= 0.0 && fy >= 0.0) {
        return None;
    }
    let (tx, ty) = (fx as usize / TILE_CELLS, fy as usize / TILE_CELLS);
    if tx >= f.tile_cols as usize {
        return None;
    }
    f.tiles.get(ty * f.tile_cols as usize + tx).filter(|&&e| {
        let kind = taxel_format::TileEntry::of(e);
        e >= taxel_format::TILE_PLANE
            && (kind.records() == 1
                || matches!(
                    kind,
                    taxel_format::TileEntry::Bend(_)
                        | taxel_format::TileEntry::Arc(_)
                        | taxel_format::TileEntry::Segments(_)
                ))
    })
}

/// Whether `p` lies in a fine tile (format 4.4).
fn fine_tile_at(f: &Field, h: f64, p: (f64, f64)) -> bool {
    let (fx, fy) = ((p.0 - f.origin.0) / h, (p.1 - f.origin.1) / h);
    if !(fx >= 0.0 && fy >= 0.0) || fx as usize / TILE_CELLS >= f.tile_cols as usize {
        return false;
    }
    let k = (fy as usize / TILE_CELLS) * f.tile_cols as usize + fx as usize / TILE_CELLS;
    f.tiles.get(k).is_some_and(|&e| matches!(taxel_format::TileEntry::of(e), taxel_format::TileEntry::Fine { .. }))
}

/// The index entry of the corner or notch tile `p` lies in, if it does,
/// and the page point where its two records' lines meet.
fn bend_at(f: &Field, h: f64, p: (f64, f64)) -> Option<(u32, (f64, f64))> {
    let (fx, fy) = ((p.0 - f.origin.0) / h, (p.1 - f.origin.1) / h);
    if !(fx >= 0.0 && fy >= 0.0) {
        return None;
    }
    let (tx, ty) = (fx as usize / TILE_CELLS, fy as usize / TILE_CELLS);
    if tx >= f.tile_cols as usize {
        return None;
    }
    let e = *f.tiles.get(ty * f.tile_cols as usize + tx)?;
    let (taxel_format::TileEntry::Corner(r) | taxel_format::TileEntry::Notch(r)) = taxel_format::TileEntry::of(e)
    else {
        return None;
    };
    let (a, b) = (f.planes.get(r as usize)?, f.planes.get(r as usize + 1)?);
    let (a1, b1, c1) = (a.gx as f64, a.gy as f64, 128.0 - a.c as f64);
    let (a2, b2, c2) = (b.gx as f64, b.gy as f64, 128.0 - b.c as f64);
    let det = a1 * b2 - b1 * a2;
    let (u, w) = ((c1 * b2 - b1 * c2) / det, (a1 * c2 - c1 * a2) / det);
    let corner = (f.origin.0 + (tx * TILE_CELLS) as f64 * h, f.origin.1 + (ty * TILE_CELLS) as f64 * h);
    Some((e, (corner.0 + u * h, corner.1 + w * h)))
}

fn grid_points(step: f64) -> Vec<(f64, f64)> {
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
    v
}

#[test]
fn a_square_is_exact_along_its_sides() {
    let sq = [square(5.0, 5.0, 20.0)];
    let g = LayerGeometry { fills: vec![(&sq, FillRule::NonZero)], ..Default::default() };
    let p = params(0.5, 0.0);
    let f = build_field(&g, p).expect("a field");
    // Along the sides, away from the corners, the distance is affine in every
    // cell: the field is exact to half a step, at any offset from the edge.
    for k in 0..200 {
        let t = 6.0 + 18.0 * k as f64 / 200.0;
        for off in [-0.3, -0.05, -0.01, 0.01, 0.05, 0.3] {
            let d = field_distance(&f, 0.5, (5.0 + off, t)).expect("in the lattice");
            assert!((d - off).abs() <= f.step_mm * 0.5 + 1e-9, "x offset {off} at y {t}: {d}");
        }
    }
    // Deep inside and far outside are single index entries, the sides
    // plane tiles and the four corners corner tiles: nothing is sampled.
    assert!(f.tiles.contains(&TILE_INSIDE));
    let corners =
        f.tiles.iter().filter(|&&e| matches!(taxel_format::TileEntry::of(e), taxel_format::TileEntry::Corner(_)));
    assert_eq!(corners.count(), 4);
    assert_eq!(f.stored(), 0);
    // Round each corner the amplitude is exact but within the spot at its
    // vertex: the half-amplitude contour is the square's two sides.
    for v in [(5.0, 5.0), (25.0, 5.0), (25.0, 25.0), (5.0, 25.0)] {
        assert_amplitude_exact_round(&g, p, &f, v);
    }
}

#[test]
fn an_inner_corner_is_a_notch_tile() {
    // An L: five convex corners and one concave one, at (15, 15).
    let l = [Polyline {
        points: vec![(5.0, 5.0), (15.0, 5.0), (15.0, 15.0), (25.0, 15.0), (25.0, 25.0), (5.0, 25.0)],
        closed: true,
    }];
    let g = LayerGeometry { fills: vec![(&l, FillRule::NonZero)], ..Default::default() };
    let p = params(0.5, 0.0);
    let f = build_field(&g, p).expect("a field");
    let count = |kind: fn(taxel_format::TileEntry) -> bool| {
        f.tiles.iter().filter(|&&e| kind(taxel_format::TileEntry::of(e))).count()
    };
    assert_eq!(count(|e| matches!(e, taxel_format::TileEntry::Corner(_))), 5);
    assert_eq!(count(|e| matches!(e, taxel_format::TileEntry::Notch(_))), 1);
    assert_eq!(f.stored(), 0);
    for v in [(5.0, 5.0), (15.0, 5.0), (15.0, 15.0), (25.0, 15.0), (25.0, 25.0), (5.0, 25.0)] {
        assert_amplitude_exact_round(&g, p, &f, v);
    }
}

#[test]
fn a_bent_band_and_its_ends_are_bend_tiles_exact_round_the_vertex() {
    // A band bent by 60 degrees at (15, 10), ending at (5, 10) and (20, 10 + 5√3).
    let end = (20.0, 10.0 + 5.0 * 3f64.sqrt());
    let lines = [Polyline { points: vec![(5.0, 10.0), (15.0, 10.0), end], closed: false }];
    let g = LayerGeometry { band: Some((vec![&lines[..]], 1.5)), ..Default::default() };
    let p = params(0.5, 0.0);
    let f = build_field(&g, p).expect("a field");
    let bend_tiles =
        f.tiles.iter().filter(|&&e| matches!(taxel_format::TileEntry::of(e), taxel_format::TileEntry::Bend(_)));
    assert!(bend_tiles.count() >= 3, "the bend and both ends");
    let (full, none) = saturated_codes(0.0, f.step_mm);
    let (hi, lo) = ((full as f64 - 128.0) * f.step_mm, (none as f64 - 128.0) * f.step_mm);
    // At any point (not only the lattice's) of a bend tile within 1.2 mm of
    // the vertex or an end, the field plays the exact distance's amplitude:
    // within half a step where not saturated.
    for v in [(15.0, 10.0), (5.0, 10.0), end] {
        let mut seen = 0;
        for k in 0..2500 {
            let q = (v.0 + (k % 50) as f64 * 0.049 - 1.2, v.1 + (k / 50) as f64 * 0.049 - 1.2);
            let (fx, fy) = ((q.0 - f.origin.0) / 0.5, (q.1 - f.origin.1) / 0.5);
            let e = f.tiles[(fy as usize / TILE_CELLS) * f.tile_cols as usize + fx as usize / TILE_CELLS];
            if !matches!(taxel_format::TileEntry::of(e), taxel_format::TileEntry::Bend(_)) {
                continue;
            }
            seen += 1;
            let got = field_distance(&f, 0.5, q).expect("in the lattice");
            let ex = exact_signed_distance(&g, p.page, q);
            assert!(
                (got.clamp(lo, hi) - ex.clamp(lo, hi)).abs() <= f.step_mm * 0.5 + 1e-6,
                "{q:?} near {v:?}: field {got}, exact {ex}"
            );
        }
        assert!(seen > 0, "no bend tile near {v:?}");
    }
}

/// The hard edge profile's amplitude of the field is the exact distance's
/// at points within 0.45 mm of `v` (a grid, and lines a few micrometres
/// from the axis-parallel sides through `v`, inside the ramp), except
/// within the spot round it.
fn assert_amplitude_exact_round(g: &LayerGeometry<'_>, p: FieldParams, f: &Field, v: (f64, f64)) {
    let ramp = taxel_format::edge_ramp(0.0, f.step_mm as f32) as f64;
    let grid = (0..400).map(|k| ((k % 20) as f64 * 0.047 - 0.45, (k / 20) as f64 * 0.047 - 0.45));
    let off = [-0.003, -0.001, 0.0005, 0.002];
    let along = (0..40).flat_map(|k| off.map(|s| (s, k as f64 * 0.0225 - 0.45))).flat_map(|(s, t)| [(s, t), (t, s)]);
    for (dx, dy) in grid.chain(along) {
        let q = (v.0 + dx, v.1 + dy);
        if dx.hypot(dy) <= bends::SPOT_MM {
            continue;
        }
        let exact = exact_signed_distance(g, p.page, q);
        let d = field_distance(f, p.pitch_mm, q).expect("in the lattice");
        let amp = |d: f64| (0.5 + d / ramp).clamp(0.0, 1.0);
        // The records are f32: a thousandth of the amplitude is a
        // thousandth of a step of distance at the edge.
        assert!((amp(d) - amp(exact)).abs() <= 1e-3, "{q:?}: {d} against {exact}");
    }
}

#[test]
fn touching_borders_of_one_style_are_one_border() {
    // Two squares sharing the side x = 15: the band of the union is the
    // band of the nearest centre line, never more than w/2 inside.
    let (a, b) = ([square(5.0, 5.0, 10.0)], [square(15.0, 5.0, 10.0)]);
    let g = LayerGeometry { band: Some((vec![&a[..], &b[..]], 1.5)), ..Default::default() };
    let f = build_field(&g, params(0.5, 0.0)).expect("a field");
    for k in 0..50 {
        let y = 7.0 + 6.0 * k as f64 / 50.0;
        let d = field_distance(&f, 0.5, (15.0, y)).expect("in the lattice");
        assert!((d - 0.75).abs() <= 1e-2 + f.step_mm, "on the shared side: {d}");
    }
}

#[test]
fn regions_of_one_style_that_share_a_side_are_one_region() {
    // Two grated rectangles sharing the side x = 15 (and a third overlapping
    // the second): inside, the distance is to the union's boundary, never to
    // the shared side, so no half-amplitude line runs along it.
    let (a, b) = ([square(5.0, 5.0, 10.0)], [square(15.0, 5.0, 10.0)]);
    let c = [square(20.0, 10.0, 8.0)];
    let g = LayerGeometry {
        fills: vec![(&a[..], FillRule::NonZero), (&b[..], FillRule::EvenOdd), (&c[..], FillRule::NonZero)],
        ..Default::default()
    };
    let f = build_field(&g, params(0.5, 0.0)).expect("a field");
    for k in 0..=40 {
        let y = 5.0 + 10.0 * k as f64 / 40.0;
        let d = field_distance(&f, 0.5, (15.0, y)).expect("in the lattice");
        // The exact distance from (15, y) to the union's boundary.
        let exact = (y - 5.0).min(15.0 - y).min(10.0);
        assert!((d.min(1.0) - exact.min(1.0)).abs() <= 0.5 * f.step_mm + 1e-9, "at y = {y}: {d} against {exact}");
    }
    // Where the third square overlaps the second, inside both: deep inside the union.
    assert!(field_distance(&f, 0.5, (22.0, 12.0)).expect("in the lattice") >= 1.0);
    // Outside, the union's outline is where the shapes' outlines are.
    assert!(field_distance(&f, 0.5, (29.0, 14.0)).expect("in the lattice") < 0.0);
    assert!(field_distance(&f, 0.5, (27.5, 14.0)).expect("in the lattice") > 0.0);
}

#[test]
fn occluders_that_share_a_side_hide_the_fill_as_one() {
    // A grated square under two occluders that share the side x = 15 and
    // together cover it (a region under a label's clearing, and the region
    // beside it): nothing is felt, and along the shared side the distance
    // is to the occluders' union's boundary, not a crease up to 0.
    // The fill reaches out below them (y 15 to 18), so the layer is felt there.
    let fill = [square(8.0, 3.0, 15.0)];
    let (left, right) = ([square(0.0, 0.0, 15.0)], [square(15.0, 0.0, 15.0)]);
    let g = LayerGeometry {
        fills: vec![(&fill[..], FillRule::NonZero)],
        occluders: vec![(&left[..], FillRule::NonZero), (&right[..], FillRule::NonZero)],
        ..Default::default()
    };
    let f = build_field(&g, params(0.5, 0.0)).expect("felt below the occluders");
    assert!(field_distance(&f, 0.5, (15.0, 17.0)).expect("in the lattice") > 0.5, "felt below them");
    for k in 0..=40 {
        let y = 3.0 + 11.0 * k as f64 / 40.0;
        for x in [14.9, 15.0, 15.1] {
            let d = field_distance(&f, 0.5, (x, y)).expect("in the lattice");
            assert!(d < -f.step_mm, "felt at ({x}, {y}): {d} under the occluders");
        }
    }
}

/// A map's region under the regions around it, painted after it, which
/// only border it, and under a label's clearing that covers its right side
/// and reaches into the neighbour there: the field is the one built with
/// every occluder measured (within a step, the unions' rounding), matches
/// the exact geometry, and is hidden under the clearing right up to the
/// neighbour (no crease where the clearing's side crosses it).
#[test]
fn fills_united_group_by_group_are_the_fills_united_at_once() {
    // Clusters of squares that overlap or share sides, the clusters apart,
    // and in one of them a square with a hole under the even-odd rule.
    let mut s = 4242u64;
    let mut next = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 33) as f64 / (1u64 << 31) as f64
    };
    let mut shapes: Vec<(Vec<Polyline>, FillRule)> = Vec::new();
    for c in 0..12 {
        let (cx, cy) = ((c % 4) as f64 * 40.0, (c / 4) as f64 * 40.0);
        for k in 0..c % 5 + 1 {
            let side = 4.0 + (next() * 8.0).floor();
            shapes.push((vec![square(cx + k as f64 * 3.0, cy + (next() * 6.0).floor(), side)], FillRule::NonZero));
        }
    }
    shapes.push((vec![square(0.0, 100.0, 10.0), square(3.0, 103.0, 4.0)], FillRule::EvenOdd));
    shapes.push((vec![square(10.0, 100.0, 6.0)], FillRule::NonZero));
    let fills: Vec<(&[Polyline], FillRule)> = shapes.iter().map(|(p, r)| (&p[..], *r)).collect();
    let grouped = united_fills(&fills).expect("the squares meet");
    // All the fills in one overlay, in the frame of their bounds.
    let all = crate::geometry::bounds(&shapes.iter().flat_map(|s| s.0.clone()).collect::<Vec<_>>()).expect("bounded");
    let f = overlay::Frame::over(all).expect("in range");
    let each: Vec<_> = fills.iter().flat_map(|&(pls, rule)| overlay::simple(pls, rule, f)).collect();
    let at_once = overlay::shapes_of(&each, i_overlay::core::fill_rule::FillRule::NonZero);
    let back = |p: &i_overlay::i_float::int::point::IntPoint| (f.ox + p.x as f64 * f.q, f.oy + p.y as f64 * f.q);
    let at_once: Vec<Polyline> =
        at_once.iter().flatten().map(|c| Polyline { points: c.iter().map(back).collect(), closed: true }).collect();
    let sorted = |pls: &[Polyline]| {
        let mut v: Vec<Vec<(u64, u64)>> =
            pls.iter().map(|p| p.points.iter().map(|q| (q.0.to_bits(), q.1.to_bits())).collect()).collect();
        v.sort();
        v
    };
    assert_eq!(sorted(&grouped), sorted(&at_once));
    // The shared sides are gone: fewer contours than squares, and the hole kept.
    assert!(grouped.len() < shapes.len() && grouped.len() > 12, "{} contours", grouped.len());
}

#[test]
fn regions_that_border_a_layer_leave_its_field_as_it_was() {
    let wiggle = |a: (f64, f64), b: (f64, f64)| -> Vec<(f64, f64)> {
        (0..20)
            .map(|k| {
                let t = k as f64 / 20.0;
                let off = if k == 0 { 0.0 } else { 0.3 * (t * 17.0).sin() };
                (a.0 + (b.0 - a.0) * t + off * (b.1 - a.1) / 10.0, a.1 + (b.1 - a.1) * t - off * (b.0 - a.0) / 10.0)
            })
            .collect()
    };
    // The region's four borders, shared point for point with its neighbours.
    let corners = [(10.0, 8.0), (20.0, 8.0), (20.0, 18.0), (10.0, 18.0)];
    let sides: Vec<Vec<(f64, f64)>> = (0..4).map(|k| wiggle(corners[k], corners[(k + 1) % 4])).collect();
    let region = [Polyline { points: sides.concat(), closed: true }];
    let outer = [(0.0, 0.0), (30.0, 0.0), (30.0, 26.0), (0.0, 26.0)];
    let neighbour = |k: usize| {
        let mut points: Vec<(f64, f64)> = sides[k].iter().rev().copied().collect();
        points.insert(0, corners[(k + 1) % 4]);
        points.extend([outer[k], outer[(k + 1) % 4]]);
        if k % 2 == 1 {
            points.rotate_left(3);
        }
        [Polyline { points, closed: true }]
    };
    let around: Vec<[Polyline; 1]> = (0..4).map(neighbour).collect();
    let clearing = [square(17.0, 11.0, 3.4)];
    let p = params(0.5, 0.0);
    for with_label in [false, true] {
        let mut occluders: Vec<(&[Polyline], FillRule)> = around.iter().map(|n| (&n[..], FillRule::NonZero)).collect();
        if with_label {
            occluders.push((&clearing[..], FillRule::NonZero));
        }
        let g = LayerGeometry { fills: vec![(&region[..], FillRule::NonZero)], occluders, ..Default::default() };
        let f = as_with_every_occluder(&g, p);
        let union = united_fills(&g.occluders).expect("the occluders meet");
        let reference = LayerGeometry { occluders: vec![(&union[..], FillRule::NonZero)], ..g.clone() };
        check_against(&g, &reference, p, &grid_points(0.173)).expect("field within bounds");
        if with_label {
            // Under the clearing, up to the region's right border and past it.
            for y in [11.5, 12.5, 13.5, 14.0] {
                for x in [19.0, 19.5, 19.8, 20.2] {
                    let d = field_distance(&f, 0.5, (x, y)).expect("in the lattice");
                    assert!(d < -f.step_mm, "felt at ({x}, {y}): {d} under the clearing");
                }
            }
        }
    }
}

/// A label's clearing over a region's side and a thin neighbour beyond it,
/// then a neighbour that only touches the thin one, within the clamp's
/// reach of the clearing: that one is kept too (the thin neighbour's far
/// side, shared with it, is no edge of the union), and the field is the one
/// built with every occluder.
#[test]
fn a_region_beyond_a_thin_neighbour_of_a_clearing_still_counts() {
    let region = [square(10.0, 8.0, 10.0)];
    let thin = [Polyline { points: vec![(20.0, 8.0), (20.5, 8.0), (20.5, 18.0), (20.0, 18.0)], closed: true }];
    let beyond = [Polyline { points: vec![(20.5, 8.0), (30.0, 8.0), (30.0, 18.0), (20.5, 18.0)], closed: true }];
    let clearing = [Polyline { points: vec![(17.0, 11.0), (20.3, 11.0), (20.3, 14.0), (17.0, 14.0)], closed: true }];
    let p = params(0.5, 0.0);
    let g = LayerGeometry {
        fills: vec![(&region[..], FillRule::NonZero)],
        occluders: vec![
            (&thin[..], FillRule::NonZero),
            (&beyond[..], FillRule::NonZero),
            (&clearing[..], FillRule::NonZero),
        ],
        ..Default::default()
    };
    as_with_every_occluder(&g, p);
}

/// The field of `g` (pitch 0.5 mm), checked to play, within a code step
/// (the unions' rounding), the field built with every occluder measured.
fn as_with_every_occluder(g: &LayerGeometry<'_>, p: FieldParams) -> Field {
    let f = build_field(g, p).expect("felt");
    let every = build::build_field_with_every_occluder(g, p).expect("felt");
    for &q in &grid_points(0.173) {
        let (a, b) = (field_distance(&f, 0.5, q), field_distance(&every, 0.5, q));
        assert!(
            a.zip(b).is_none_or(|(a, b)| (a - b).abs() <= f.step_mm + 1e-9),
            "{q:?}: {a:?} against {b:?} with every occluder"
        );
    }
    f
}

#[test]
fn a_grating_minus_a_band_is_the_fill_outside_the_band() {
    let sq = [square(5.0, 5.0, 20.0)];
    let line = [Polyline { points: vec![(15.0, 0.0), (15.0, 30.0)], closed: false }];
    let g = LayerGeometry { fills: vec![(&sq, FillRule::NonZero)], cuts: vec![(&line, 2.0)], ..Default::default() };
    let p = params(0.5, 0.0);
    check(&g, p, &grid_points(0.173)).expect("field within bounds");
    let f = build_field(&g, p).expect("a field");
    // 0.5 mm off the band's edge on either side.
    assert!(field_distance(&f, 0.5, (15.5, 10.0)).expect("lattice") < 0.0);
    assert!(field_distance(&f, 0.5, (13.5, 10.0)).expect("lattice") > 0.4);
}

/// Cut bands of two widths, the wide one listed after two narrow ones (its
/// width group, 1, is not its place among the cuts, 2): the field is exact
/// and the tiles along the wide band's straight edges are plane tiles.
#[test]
fn a_wide_cut_after_narrow_ones_has_plane_tiles_at_its_own_edges() {
    let sq = [square(2.0, 2.0, 26.0)];
    let vertical = |x: f64| [Polyline { points: vec![(x, 0.0), (x, 30.0)], closed: false }];
    let (a, b, c) = (vertical(6.0), vertical(9.0), vertical(18.0));
    let g = LayerGeometry {
        fills: vec![(&sq, FillRule::NonZero)],
        cuts: vec![(&a, 1.0), (&b, 1.0), (&c, 8.0)],
        ..Default::default()
    };
    let p = params(0.5, 0.0);
    check(&g, p, &grid_points(0.173)).expect("field within bounds");
    let f = build_field(&g, p).expect("a field");
    // The wide band's edges are at 14 and 22 mm, 4 mm from anything else.
    for y in [8.0, 12.0, 16.0, 20.0] {
        for x in [14.0, 22.0] {
            let e = plane_tile_at(&f, 0.5, (x, y)).expect("a plane tile along the wide cut's edge");
            assert_eq!(taxel_format::TileEntry::of(*e).records(), 1, "({x}, {y}): {e:#x}");
        }
    }
}

#[test]
fn soft_edges_reach_half_their_width() {
    let sq = [square(5.0, 5.0, 20.0)];
    let g = LayerGeometry { fills: vec![(&sq, FillRule::NonZero)], ..Default::default() };
    check(&g, params(0.5, 0.3), &grid_points(0.211)).expect("soft field within bounds");
    check(&g, params(0.25, 2.0), &grid_points(0.311)).expect("wide soft field within bounds");
}

/// A random outline: a polygon around a centre with random radii (spiky
/// slivers when the radii jump), optionally self-intersecting (vertices in
/// random angular order), with collinear midpoints inserted. Shared with
/// the exact region's tests (`exact/tests.rs`).
pub(crate) fn outline() -> impl Strategy<Value = Polyline> {
    (
        2.0f64..38.0,
        2.0f64..28.0,
        prop::collection::vec((0.0f64..std::f64::consts::TAU, 0.05f64..12.0), 3..12),
        any::<bool>(),
        any::<bool>(),
        any::<bool>(),
    )
        .prop_map(|(cx, cy, mut polar, sorted, collinear, closed)| {
            if sorted {
                polar.sort_by(|a, b| a.0.total_cmp(&b.0));
            }
            let mut pts: Vec<(f64, f64)> = polar.iter().map(|&(a, r)| (cx + r * a.cos(), cy + r * a.sin())).collect();
            if collinear {
                let mut with = Vec::new();
                for i in 0..pts.len() {
                    let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
                    with.push(a);
                    with.push(((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0));
                }
                pts = with;
            }
            Polyline { points: pts, closed }
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Fills: one or two outlines as one shape (a second one inside the
    /// first is a hole under even-odd), under either fill rule.
    #[test]
    fn fills_match_exact_geometry(a in outline(), b in outline(), two in any::<bool>(), evenodd in any::<bool>(), pitch in prop::sample::select(vec![0.25, 0.5, 1.0])) {
        let shape = if two { vec![a, b] } else { vec![a] };
        let rule = if evenodd { FillRule::EvenOdd } else { FillRule::NonZero };
        let g = LayerGeometry { fills: vec![(&shape, rule)], ..Default::default() };
        check(&g, params(pitch, 0.0), &grid_points(0.37))?;
    }

    /// Fills minus the union of occluders of any shape painted over them.
    #[test]
    ///
    /// The builder measures the distance to the occluders' union (a side two
    /// of them share, or a degenerate outline of no area, hides nothing and
    /// is no edge), so the reference is the distance to that union; the
    /// union covers exactly the points the occluders cover.
    fn occluded_fills_match_exact_geometry(a in outline(), b in outline(), c in outline(), pitch in prop::sample::select(vec![0.25, 0.5])) {
        let (shape, over) = ([a], [b, c]);
        let g = LayerGeometry {
            fills: vec![(&shape, FillRule::NonZero)],
            occluders: vec![(&over[..1], FillRule::NonZero), (&over[1..], FillRule::EvenOdd)],
            ..Default::default()
        };
        let points = grid_points(0.37);
        let Some(union) = united_fills(&g.occluders) else {
            return check(&g, params(pitch, 0.0), &points);
        };
        let covered = |q: (f64, f64), parts: &[(&[Polyline], FillRule)]| {
            parts.iter().any(|(pls, rule)| crate::geometry::contains(pls, q, *rule))
        };
        let united = [(&union[..], FillRule::NonZero)];
        for &q in &points {
            // (Not on an outline, where either answer is right.)
            let near = over.iter().flat_map(closed_segments).any(|(a, b)| crate::geometry::distance_to_segment(q, a, b) < 1e-3);
            prop_assert!(near || covered(q, &g.occluders) == covered(q, &united), "{q:?}: the union covers it differently");
        }
        let reference = LayerGeometry { occluders: united.to_vec(), ..g.clone() };
        check_against(&g, &reference, params(pitch, 0.0), &points)?;
    }

    /// Bands along open or closed polylines of any shape.
    #[test]
    fn bands_match_exact_geometry(a in outline(), width in 0.2f64..3.0, pitch in prop::sample::select(vec![0.25, 0.5])) {
        let lines = [a];
        let g = LayerGeometry { band: Some((vec![&lines[..]], width)), ..Default::default() };
        check(&g, params(pitch, 0.0), &grid_points(0.29))?;
    }
}

/// A crowded map: 12 x 12 small 16-gons 1 mm apart, each a region of the
/// layer, an occluder painted over it or a cut band, so that a tile holds
/// hundreds of segments of each kind (the samples then search a grid of
/// them instead of measuring each segment).
fn crowded(radii: &[f64], kinds: &[u8]) -> [Vec<Polyline>; 3] {
    let mut out: [Vec<Polyline>; 3] = Default::default();
    for (k, (&r, &kind)) in radii.iter().zip(kinds).enumerate() {
        let (cx, cy) = (3.0 + (k % 12) as f64, 3.0 + (k / 12) as f64 + 0.1 * (k % 5) as f64);
        let points = (0..16)
            .map(|i| {
                let a = i as f64 * std::f64::consts::TAU / 16.0;
                let r = r * if i % 2 == 0 { 1.0 } else { 0.8 };
                (cx + r * a.cos(), cy + r * a.sin())
            })
            .collect();
        out[kind as usize % 3].push(Polyline { points, closed: true });
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 6, ..ProptestConfig::default() })]

    /// Crowded fills, occluders and cut bands: the field is as exact as a
    /// sparse one's.
    #[test]
    fn crowded_layers_match_exact_geometry(
        radii in prop::collection::vec(0.2f64..0.48, 144),
        kinds in prop::collection::vec(any::<u8>(), 144),
        width in 0.2f64..0.6,
    ) {
        let [fills, over, cuts] = crowded(&radii, &kinds);
        let g = LayerGeometry {
            fills: fills.iter().map(|p| (std::slice::from_ref(p), FillRule::NonZero)).collect(),
            occluders: over.iter().map(|p| (std::slice::from_ref(p), FillRule::NonZero)).collect(),
            cuts: cuts.iter().map(|p| (std::slice::from_ref(p), width)).collect(),
            ..Default::default()
        };
        check(&g, params(0.5, 0.0), &grid_points(0.41))?;
    }
}

#[test]
fn a_clipped_fill_is_felt_only_inside_its_clip() {
    let sq = [square(5.0, 5.0, 20.0)];
    let clip = [square(0.0, 0.0, 15.0)];
    let g = LayerGeometry {
        fills: vec![(&sq, FillRule::NonZero)],
        clips: vec![(&clip, FillRule::NonZero)],
        ..Default::default()
    };
    check(&g, params(0.5, 0.0), &grid_points(0.173)).expect("field within bounds");
    let f = build_field(&g, params(0.5, 0.0)).expect("a field");
    assert!(field_distance(&f, 0.5, (10.0, 10.0)).expect("lattice") > 0.0);
    assert!(field_distance(&f, 0.5, (20.0, 10.0)).is_none_or(|d| d < 0.0));
}

/// A band whose tile near a joint is a segments tile (format 4.2): at a
/// corner outside the band, saturated at zero amplitude, the tile's nearest
/// segment is not the centre line's nearest (the writer leaves out a
/// segment that only matters where the code saturates), so the field reads
/// 0.025 mm farther out than the exact distance there, which plays the
/// same. `bands_match_exact_geometry` drew it (2026-11-29) when
/// `plane_tile_at` did not know segments tiles and held the cell to
/// bilinear exactness; now the tile is held to the writer's rule.
#[test]
fn a_band_with_collinear_joints_matches_exact_geometry() {
    let points = vec![
        (16.069090933281487, 10.36828312308425),
        (17.161184365421384, 8.863752761584966),
        (18.25327779756128, 7.359222400085681),
        (22.492147265509573, 10.630011101970446),
        (26.731016733457867, 13.900799803855213),
        (21.400053833369675, 12.13454146346973),
    ];
    let lines = [Polyline { points, closed: false }];
    let g = LayerGeometry { band: Some((vec![&lines[..]], 1.5308110584987458)), ..Default::default() };
    check(&g, params(0.5, 0.0), &grid_points(0.29)).expect("field within bounds");
}
