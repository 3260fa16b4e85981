//! The field against exact f64 geometry: random polygons and polylines with
//! slivers, holes, self-intersections and collinear points.

use proptest::prelude::*;

use super::*;

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
/// - in a plane or ridge tile (which plays its function at the point, not a
///   bilinear interpolation): at the corners and the centre of the point's
///   cell (what the writer checks, here against exact geometry), within
///   half a step, or farther than half the ramp plus `h` from the edge
///   saturated on the exact side; at the point itself on the exact side
///   farther than `h √2` plus a step from any edge.
fn check(g: &LayerGeometry<'_>, p: FieldParams, points: &[(f64, f64)]) -> Result<(), TestCaseError> {
    let h = p.pitch_mm;
    let exact = |q: (f64, f64)| exact_signed_distance(g, p.page, q);
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

/// The index entry of the plane, ridge, bend or arc tile `p` lies in, if it
/// does (each plays its function at the point, checked at the samples and
/// the cell centres).
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
                || matches!(kind, taxel_format::TileEntry::Bend(_) | taxel_format::TileEntry::Arc(_)))
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
/// the prototype's tests (`vector/tests.rs`).
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
    fn occluded_fills_match_exact_geometry(a in outline(), b in outline(), c in outline(), pitch in prop::sample::select(vec![0.25, 0.5])) {
        let (shape, over) = ([a], [b, c]);
        let g = LayerGeometry {
            fills: vec![(&shape, FillRule::NonZero)],
            occluders: vec![(&over[..1], FillRule::NonZero), (&over[1..], FillRule::EvenOdd)],
            ..Default::default()
        };
        check(&g, params(pitch, 0.0), &grid_points(0.37))?;
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

proptest! {
    /// `nearest_first` keeps what a stable sort then a truncation keep, ties
    /// (few distinct keys, so many) and NaN included.
    #[test]
    fn nearest_first_is_a_stable_sort_cut_short(
        keys in proptest::collection::vec(prop_oneof![0u8..6, Just(255u8)], 0..40),
        max in 0usize..12,
    ) {
        let v: Vec<(f64, usize)> =
            keys.iter().enumerate().map(|(i, &k)| (if k == 255 { f64::NAN } else { k as f64 }, i)).collect();
        let mut want = v.clone();
        want.sort_by(|a, b| a.0.total_cmp(&b.0));
        want.truncate(max);
        let got = nearest_first(v.into_iter(), max);
        let ids = |x: &[(f64, usize)]| x.iter().map(|e| e.1).collect::<Vec<_>>();
        prop_assert_eq!(ids(&got), ids(&want));
    }
}

/// A circle of radius `r` round `c` as a closed polygon of `n` vertices on it.
fn ring(c: (f64, f64), r: f64, n: usize) -> Polyline {
    let at = |k: usize| {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        (c.0 + r * a.cos(), c.1 + r * a.sin())
    };
    Polyline { points: (0..n).map(at).collect(), closed: true }
}

/// Points along a circle of radius `r` round `c`, `off` mm out from it.
fn along_circle(c: (f64, f64), r: f64, offsets: &[f64]) -> Vec<(f64, f64)> {
    (0..997)
        .flat_map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 997.0;
            offsets.iter().map(move |o| (c.0 + (r + o) * a.cos(), c.1 + (r + o) * a.sin()))
        })
        .collect()
}

#[test]
fn a_filled_circle_plays_its_exact_distance_at_the_edge() {
    // 720 vertices: the chords stay within 0.08 µm of the circle, a
    // hundredth of a code.
    let (c, r) = ((20.0, 15.0), 8.0);
    let disc = [ring(c, r, 720)];
    let g = LayerGeometry { fills: vec![(&disc, FillRule::NonZero)], ..Default::default() };
    let p = params(0.5, 0.0);
    let f = build_field(&g, p).expect("a field");
    // Every tile the circle crosses is a cone (a bend tile round its centre).
    assert_eq!(f.stored(), 0);
    let ramp = taxel_format::edge_ramp(0.0, f.step_mm as f32) as f64;
    let amp = |d: f64| (0.5 + d / ramp).clamp(0.0, 1.0);
    // Within the hard edge's ramp, where a sampled tile was off by up to
    // the whole amplitude, the amplitude is the exact distance's within 2%.
    for q in along_circle(c, r, &[-0.006, -0.003, -0.001, 0.0, 0.0015, 0.004, 0.05, -0.3]) {
        let (d, e) = (field_distance(&f, 0.5, q).expect("in the lattice"), exact_signed_distance(&g, p.page, q));
        assert!((amp(d) - amp(e)).abs() <= 0.02, "{q:?}: field {d}, exact {e}");
    }
}

#[test]
fn a_band_round_a_circle_and_a_hole_play_their_exact_distance_at_the_edges() {
    let (c, r, w) = ((20.0, 15.0), 8.0, 1.5);
    let lines = [ring(c, r, 720)];
    // A band round the circle: both its sides in one tile are an arc tile's ring.
    let band = LayerGeometry { band: Some((vec![&lines[..]], w)), ..Default::default() };
    // A square with a circular hole (even-odd): the hole's side is an arc tile.
    let holed = [square(8.0, 3.0, 24.0), ring(c, r, 720)];
    let hole = LayerGeometry { fills: vec![(&holed, FillRule::EvenOdd)], ..Default::default() };
    let p = params(0.5, 0.0);
    for (g, sides) in [(&band, [r - w / 2.0, r + w / 2.0]), (&hole, [r, r])] {
        let f = build_field(g, p).expect("a field");
        assert_eq!(f.stored(), 0, "every tile a circle crosses is a cone or an arc");
        let arcs =
            f.tiles.iter().filter(|&&e| matches!(taxel_format::TileEntry::of(e), taxel_format::TileEntry::Arc(_)));
        assert!(arcs.count() > 0);
        let ramp = taxel_format::edge_ramp(0.0, f.step_mm as f32) as f64;
        let amp = |d: f64| (0.5 + d / ramp).clamp(0.0, 1.0);
        for side in sides {
            for q in along_circle(c, side, &[-0.004, -0.001, 0.0, 0.002, 0.006, 0.2]) {
                let d = field_distance(&f, 0.5, q).expect("in the lattice");
                let e = exact_signed_distance(g, p.page, q);
                assert!((amp(d) - amp(e)).abs() <= 0.02, "{q:?}: field {d}, exact {e}");
            }
        }
    }
}

/// Whether the tile of a built field at `p` is a segments tile (format 4.2).
fn segments_at(f: &Field, h: f64, p: (f64, f64)) -> bool {
    let (tx, ty) = (((p.0 - f.origin.0) / h) as usize / TILE_CELLS, ((p.1 - f.origin.1) / h) as usize / TILE_CELLS);
    f.tiles
        .get(ty * f.tile_cols as usize + tx)
        .is_some_and(|&e| matches!(taxel_format::TileEntry::of(e), taxel_format::TileEntry::Segments(_)))
}

#[test]
fn three_bands_meeting_at_a_point_play_their_exact_distance_round_the_junction() {
    // Three centre lines from (20.3, 14.7) at 0, 110 and 230 degrees (a
    // map's coast and two borders), bands 1.5 mm wide: the union has three
    // sharp concave corners between the bands. Cut out of a square
    // grating, the same lines leave three sharp convex corners.
    let v = (20.3, 14.7);
    let arm = |deg: f64| {
        let a = deg.to_radians();
        Polyline { points: vec![v, (v.0 + 9.0 * a.cos(), v.1 + 9.0 * a.sin())], closed: false }
    };
    let lines = [arm(0.0), arm(110.0), arm(230.0)];
    let band = LayerGeometry { band: Some((vec![&lines[..]], 1.5)), ..Default::default() };
    let sq = [square(8.0, 3.0, 24.0)];
    let cut = LayerGeometry { fills: vec![(&sq, FillRule::NonZero)], cuts: vec![(&lines, 1.5)], ..Default::default() };
    let p = params(0.5, 0.0);
    for g in [&band, &cut] {
        let f = build_field(g, p).expect("a field");
        let ramp = taxel_format::edge_ramp(0.0, f.step_mm as f32) as f64;
        let amp = |d: f64| (0.5 + d / ramp).clamp(0.0, 1.0);
        // Within 1.5 mm of the junction no tile is stored (where a bend
        // plays the junction's tile, the third arm only grazes it), and in
        // the segments tiles there, on a grid finer than the lattice and
        // off its points, the amplitude is the exact distance's within 2%
        // (a sampled tile rounded the corners by up to the whole amplitude).
        let mut checked = 0;
        for i in 0..=60 {
            for j in 0..=60 {
                let q = (v.0 - 1.5 + i as f64 * 0.0501, v.1 - 1.5 + j as f64 * 0.0497);
                let (tx, ty) = (
                    ((q.0 - f.origin.0) / 0.5) as usize / TILE_CELLS,
                    ((q.1 - f.origin.1) / 0.5) as usize / TILE_CELLS,
                );
                let e = f.tiles.get(ty * f.tile_cols as usize + tx).copied().unwrap_or(TILE_OUTSIDE);
                assert!(!matches!(taxel_format::TileEntry::of(e), taxel_format::TileEntry::Stored(_)), "{q:?} stored");
                if !segments_at(&f, 0.5, q) {
                    continue;
                }
                checked += 1;
                let (d, e) = (field_distance(&f, 0.5, q).expect("in the lattice"), exact_signed_distance(g, p.page, q));
                assert!((amp(d) - amp(e)).abs() <= 0.02, "{q:?}: field {d}, exact {e}");
            }
        }
        assert!(checked > 500, "{checked} points in segments tiles");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Each tile's bucket holds, in segment order, every segment within
    /// its reach of the tile (measured: the least distance between the
    /// segment and the tile's square), and only segments whose bounds grown
    /// by their reach meet the tile (with the same rounding of bounds to
    /// tiles); each segment's span is the range of tiles its bounds meet,
    /// and the tiles holding it lie within its span. A negative reach (a
    /// span that comes out empty) acts on no tile and never panics; an
    /// infinite one acts on every tile.
    #[test]
    fn buckets_hold_the_segments_that_reach_each_tile(
        segs in prop::collection::vec(
            ((-3.0f64..12.0, -3.0f64..12.0), (-8.0f64..8.0, -8.0f64..8.0), prop_oneof![
                8 => 0.0f64..2.0,
                1 => -3.0f64..0.0,
                1 => Just(f64::INFINITY),
            ]),
            0..60,
        ),
        (cols, rows) in (1usize..6, 1usize..6),
        tile in 0.5f64..3.0,
        origin in (-1.0f64..1.0, -1.0f64..1.0),
    ) {
        let segs: Vec<(Seg, Part, f64)> =
            segs.iter().map(|&((x, y), (dx, dy), m)| (((x, y), (x + dx, y + dy)), Part::Fill, m)).collect();
        let tiles = Tiles { origin, side: tile, cols, rows };
        let (buckets, spans) = buckets_of(&segs, &tiles);
        prop_assert_eq!(buckets.len(), cols * rows);
        prop_assert_eq!(spans.len(), segs.len());
        // The tile index of a coordinate (unbounded: the lattice's first and
        // last tiles take what lies beyond them).
        let index = |v: f64, o: f64| ((v - o) / tile).floor();
        let by_bounds = |(s, _, m): &(Seg, Part, f64), c: usize, r: usize| {
            let b = seg_bounds(s);
            let (lo_c, hi_c) = (index(b.0 - m, origin.0), index(b.2 + m, origin.0));
            let (lo_r, hi_r) = (index(b.1 - m, origin.1), index(b.3 + m, origin.1));
            let covers = |lo: f64, hi: f64, k: usize| lo <= k as f64 && k as f64 <= hi;
            b.2 + m >= origin.0
                && b.3 + m >= origin.1
                && lo_c < cols as f64
                && lo_r < rows as f64
                && covers(lo_c, hi_c, c)
                && covers(lo_r, hi_r, r)
        };
        for r in 0..rows {
            for c in 0..cols {
                let bucket = &buckets[r * cols + c];
                prop_assert!(bucket.windows(2).all(|w| w[0] < w[1]), "tile ({}, {}) in segment order", c, r);
                let square = (
                    (origin.0 + c as f64 * tile, origin.1 + r as f64 * tile),
                    (origin.0 + (c + 1) as f64 * tile, origin.1 + (r + 1) as f64 * tile),
                );
                for (n, seg) in segs.iter().enumerate() {
                    let held = bucket.contains(&(n as u32));
                    prop_assert!(!held || by_bounds(seg, c, r), "tile ({}, {}) holds segment {} beyond its bounds", c, r, n);
                    let d = distance_to_square(seg.0, square);
                    prop_assert!(held || d >= seg.2 * (1.0 - 1e-9), "tile ({}, {}) lacks segment {} at {}", c, r, n, d);
                }
            }
        }
        for (n, sp) in spans.iter().enumerate() {
            let [c0, c1, r0, r1] = sp.map(usize::from);
            let in_span = |c: usize, r: usize| c0 <= c && c <= c1 && r0 <= r && r <= r1;
            for (c, r) in (0..rows).flat_map(|r| (0..cols).map(move |c| (c, r))) {
                prop_assert_eq!(in_span(c, r), by_bounds(&segs[n], c, r), "segment {} tile ({}, {})", n, c, r);
                prop_assert!(!buckets[r * cols + c].contains(&(n as u32)) || in_span(c, r));
            }
        }
    }
}

/// The least distance between segment `s` and the closed square
/// `(low, high)` corners: 0 where they meet.
fn distance_to_square(s: Seg, (lo, hi): ((f64, f64), (f64, f64))) -> f64 {
    let inside = |p: (f64, f64)| lo.0 <= p.0 && p.0 <= hi.0 && lo.1 <= p.1 && p.1 <= hi.1;
    if inside(s.0) || inside(s.1) {
        return 0.0;
    }
    let sides = [(lo, (hi.0, lo.1)), ((hi.0, lo.1), hi), (hi, (lo.0, hi.1)), ((lo.0, hi.1), lo)];
    sides.iter().map(|&(a, b)| crate::geometry::segment_distance(s.0, s.1, a, b)).fold(f64::INFINITY, f64::min)
}

/// A long slanted segment is held by the tiles along it, not by every tile
/// of its bounds: a diagonal across 20 by 20 tiles is held by a band of
/// them a few tiles wide.
#[test]
fn a_diagonal_is_held_by_the_tiles_along_it() {
    let tiles = Tiles { origin: (0.0, 0.0), side: 2.0, cols: 20, rows: 20 };
    let segs = [(((0.5, 0.5), (39.5, 39.0)), Part::Band, 0.6)];
    let (buckets, spans) = buckets_of(&segs, &tiles);
    assert_eq!(spans[0], [0, 19, 0, 19]);
    let held: Vec<(usize, usize)> = (0..400).filter(|&k| !buckets[k].is_empty()).map(|k| (k % 20, k / 20)).collect();
    assert!(held.iter().all(|&(c, r)| c.abs_diff(r) <= 1), "{held:?}");
    assert!((0..20).all(|k| held.contains(&(k, k))), "{held:?}");
    assert!(held.len() < 60, "{} tiles", held.len());
}
/// Whether the tile of a built field at `p` is a cut arc (format 4.3).
fn cut_arc_at(f: &Field, h: f64, p: (f64, f64)) -> bool {
    let (tx, ty) = (((p.0 - f.origin.0) / h) as usize / TILE_CELLS, ((p.1 - f.origin.1) / h) as usize / TILE_CELLS);
    f.tiles.get(ty * f.tile_cols as usize + tx).is_some_and(|&e| match taxel_format::TileEntry::of(e) {
        taxel_format::TileEntry::Arc(r) => f.planes.get(r as usize + 1).is_some_and(taxel_format::is_cut_arc),
        _ => false,
    })
}

#[test]
fn a_side_and_a_hole_within_a_millimetre_play_their_exact_distance_as_cut_arcs() {
    // A square with a circular hole (a province and its lake) whose edge
    // comes within 0.8 mm of the square's top side: where both lie within
    // the clamp of one tile, no plane or arc plays it alone.
    let (c, r) = ((20.0, 8.8), 5.0);
    let holed = [square(8.0, 3.0, 24.0), ring(c, r, 720)];
    let g = LayerGeometry { fills: vec![(&holed, FillRule::EvenOdd)], ..Default::default() };
    let p = params(0.5, 0.0);
    let f = build_field(&g, p).expect("a field");
    assert_eq!(f.stored(), 0, "every tile is analytic");
    let ramp = taxel_format::edge_ramp(0.0, f.step_mm as f32) as f64;
    let amp = |d: f64| (0.5 + d / ramp).clamp(0.0, 1.0);
    // Along the circle and along the side, inside the hard edge's ramp and
    // off the lattice, in the cut arcs the amplitude is the exact
    // distance's within 2% (a sampled tile was off by up to the whole).
    let side = (0..997)
        .flat_map(|k| [-0.004, -0.001, 0.0, 0.002, 0.006, 0.3].map(|o| (8.0 + 24.0 * k as f64 / 997.0, 3.0 + o)));
    let mut checked = 0;
    for q in along_circle(c, r, &[-0.004, -0.001, 0.0, 0.002, 0.006, 0.3]).into_iter().chain(side) {
        if !cut_arc_at(&f, 0.5, q) {
            continue;
        }
        checked += 1;
        let (d, e) = (field_distance(&f, 0.5, q).expect("in the lattice"), exact_signed_distance(&g, p.page, q));
        assert!((amp(d) - amp(e)).abs() <= 0.02, "{q:?}: field {d}, exact {e}");
    }
    assert!(checked > 100, "{checked} points in cut arcs");
}

#[test]
fn a_curved_side_meeting_a_straight_one_plays_its_corner_as_a_cut_arc() {
    // A disc cut by a chord (a country's Bézier coast meeting a straight
    // border): at the two corners the lesser of the chord's plane and the
    // circle's cone is the miter outside, not the exact distance, which a
    // check of codes alone refused, so those tiles were stored and their
    // corners rounded (0.17 mm on a teacher's map).
    let (c, r, chord) = ((20.0, 14.0), 6.0, 11.0);
    let (t0, t1) = (-std::f64::consts::FRAC_PI_6, 7.0 * std::f64::consts::FRAC_PI_6);
    let arc = Polyline {
        points: (0..=720)
            .map(|k| t0 + (t1 - t0) * k as f64 / 720.0)
            .map(|t| (c.0 + r * t.cos(), c.1 + r * t.sin()))
            .collect(),
        closed: true,
    };
    let shapes = [arc];
    let g = LayerGeometry { fills: vec![(&shapes, FillRule::NonZero)], ..Default::default() };
    let p = params(0.5, 0.0);
    let f = build_field(&g, p).expect("a field");
    let half = (r * r - (c.1 - chord) * (c.1 - chord)).sqrt();
    let corners = [(c.0 - half, chord), (c.0 + half, chord)];
    for x in corners {
        let at = |p: (f64, f64)| {
            let (tx, ty) =
                (((p.0 - f.origin.0) / 0.5) as usize / TILE_CELLS, ((p.1 - f.origin.1) / 0.5) as usize / TILE_CELLS);
            taxel_format::TileEntry::of(f.tiles[ty * f.tile_cols as usize + tx])
        };
        assert!(
            cut_arc_at(&f, 0.5, x),
            "the tile of the corner at {x:?} is a cut arc: {:?}, stored {}",
            at(x),
            f.stored()
        );
    }
    assert_eq!(f.stored(), 0, "every tile is analytic");
    // Round each corner, off the lattice, inside and outside the hard edge's
    // ramp: the amplitude is the exact distance's within 2%, but within
    // the spot (SPOT_MM) round the corner point.
    let ramp = taxel_format::edge_ramp(0.0, f.step_mm as f32) as f64;
    let amp = |d: f64| (0.5 + d / ramp).clamp(0.0, 1.0);
    let mut checked = 0;
    for x in corners {
        for i in -60..=60 {
            for j in -60..=60 {
                let q = (x.0 + i as f64 * 0.0101, x.1 + j as f64 * 0.0097);
                if (q.0 - x.0).hypot(q.1 - x.1) <= bends::SPOT_MM {
                    continue;
                }
                let (d, e) =
                    (field_distance(&f, 0.5, q).expect("in the lattice"), exact_signed_distance(&g, p.page, q));
                assert!((amp(d) - amp(e)).abs() <= 0.02, "{q:?}: field {d}, exact {e}");
                checked += 1;
            }
        }
    }
    assert!(checked > 20_000, "{checked}");
}

/// Points to search from near [`clustered_segments`]' tile: anywhere, or on
/// its lattice of 0.5 mm (where distances tie).
fn probe_points() -> impl Strategy<Value = (f64, f64)> {
    prop_oneof![
        (8.0f64..14.0, 8.0f64..14.0),
        (0u8..9, 0u8..9).prop_map(|(i, j)| (9.0 + i as f64 * 0.5, 9.0 + j as f64 * 0.5))
    ]
}

/// Segments for the nearest-segment searches: short ones clustered round a
/// tile, many sharing ends or lying on one another (equal keys), some far.
fn clustered_segments() -> impl Strategy<Value = Vec<(Seg, Part, f64)>> {
    let coord = prop_oneof![4 => 8.0f64..14.0, 1 => -20.0f64..40.0, 1 => (0u8..8).prop_map(|k| 9.0 + k as f64 * 0.5)];
    let part = prop_oneof![Just(Part::Fill), Just(Part::Band), Just(Part::Cut(0)), Just(Part::Cut(1))];
    proptest::collection::vec((coord.clone(), coord.clone(), coord.clone(), coord, part), 0..160)
        .prop_map(|v| v.into_iter().map(|(ax, ay, bx, by, p)| (((ax, ay), (bx, by)), p, 1.0)).collect())
}

proptest! {
    /// The writers' shared nearest segments: the first `max` of the
    /// [`planes::NEAREST_KEPT`] nearest (what [`TileCtx::nearest`](planes::TileCtx::nearest)
    /// hands a writer asking for `max`) are what `nearest_first` with `max`
    /// keeps, bit for bit, ties (shared ends, overlapping segments) included.
    #[test]
    fn the_shared_nearest_segments_are_nearest_firsts(
        segs in clustered_segments(),
        middle in (9.0f64..13.0, 9.0f64..13.0),
        max in 0usize..=planes::NEAREST_KEPT,
        part in prop_oneof![Just(Part::Fill), Just(Part::Band), Just(Part::Cut(0))],
    ) {
        let all = |max: usize| {
            nearest_first(
                segs.iter().filter(|s| s.1 == part).map(|&((a, b), _, _)| (distance2_to_segment(middle, a, b), (a, b))),
                max,
            )
        };
        let bits = |v: &[(f64, Seg)]| {
            v.iter().map(|(k, (a, b))| [k.to_bits(), a.0.to_bits(), a.1.to_bits(), b.0.to_bits(), b.1.to_bits()]).collect::<Vec<_>>()
        };
        let shared = all(planes::NEAREST_KEPT);
        prop_assert_eq!(bits(&shared[..max.min(shared.len())]), bits(&all(max)));
    }

    /// `nearest_of` (which stops at the first segment too far from the
    /// tile's middle to be nearer the point) finds the same segment and
    /// distance as a scan of them all keeping the first least; fails if it
    /// stopped one segment too early.
    #[test]
    fn nearest_of_is_the_first_least_of_a_full_scan(
        segs in clustered_segments(),
        middle in (9.0f64..13.0, 9.0f64..13.0),
        p in probe_points(),
        max in 1usize..48,
    ) {
        let near = nearest_first(segs.iter().map(|&((a, b), _, _)| (distance2_to_segment(middle, a, b), (a, b))), max);
        let want = near
            .iter()
            .enumerate()
            .map(|(k, (_, (a, b)))| (distance2_to_segment(p, *a, *b), k))
            .min_by(|x, y| x.0.total_cmp(&y.0))
            .map(|(d, k)| (k, d.to_bits()));
        prop_assert_eq!(nearest_of(&near, middle, p, None).map(|(k, d)| (k, d.to_bits())), want);
    }

    /// `nearest_of` told the least distance over a set of segments that
    /// holds its list (all the segments, of which the list keeps the
    /// nearest to the middle) finds what it finds untold; fails if it
    /// stopped at a segment merely close to that least distance.
    #[test]
    fn nearest_of_told_the_least_finds_what_it_finds_untold(
        segs in clustered_segments(),
        middle in (9.0f64..13.0, 9.0f64..13.0),
        p in probe_points(),
        max in 1usize..48,
    ) {
        let near = nearest_first(segs.iter().map(|&((a, b), _, _)| (distance2_to_segment(middle, a, b), (a, b))), max);
        let least = segs.iter().map(|&((a, b), _, _)| distance2_to_segment(p, a, b)).min_by(f64::total_cmp);
        let bits = |v: Option<(usize, f64)>| v.map(|(k, d)| (k, d.to_bits()));
        prop_assert_eq!(bits(nearest_of(&near, middle, p, least)), bits(nearest_of(&near, middle, p, None)));
    }

    /// The gradient length the corner writer reckons once per segment is
    /// that of the record it makes, for either sign, bit for bit; fails if
    /// it were taken from the unrounded gradient.
    #[test]
    fn a_segments_gradient_length_is_its_records(
        gx in prop_oneof![-300.0f64..300.0, -1e-3f64..1e-3, (-1000i32..1000).prop_map(|k| k as f64 / 7.0)],
        gy in prop_oneof![-300.0f64..300.0, -1e-3f64..1e-3, (-1000i32..1000).prop_map(|k| k as f64 / 3.0)],
        c in -200.0f64..200.0,
    ) {
        for s in [1.0, -1.0] {
            if let Some(r) = planes::record(128.0 + s * c, s * gx, s * gy, 0.0) {
                prop_assert_eq!(bends::gradient_norm(gx, gy).to_bits(), (r.gx as f64).hypot(r.gy as f64).to_bits());
            }
        }
    }

    /// `floor_f64` and `ceil_f64` equal `f64::floor` and `f64::ceil`
    /// (whole values, halves, tiny and huge magnitudes, both signs).
    #[test]
    fn the_inline_floor_and_ceil_are_libms(
        v in prop_oneof![
            -1e7f64..1e7,
            (-1000i64..1000).prop_map(|k| k as f64 * 0.5),
            any::<f64>(),
            prop_oneof![Just(-0.0), Just(0.0), Just(f64::INFINITY), Just(f64::NEG_INFINITY), Just(4_503_599_627_370_495.5), Just(-4_503_599_627_370_495.5)],
        ],
    ) {
        let same = |a: f64, b: f64| a == b || (a.is_nan() && b.is_nan());
        prop_assert!(same(floor_f64(v), v.floor()), "floor {v}: {} vs {}", floor_f64(v), v.floor());
        prop_assert!(same(ceil_f64(v), v.ceil()), "ceil {v}: {} vs {}", ceil_f64(v), v.ceil());
    }
}

proptest! {
    /// The order in which the writers check candidates at a tile's samples
    /// holds every sample once (so a check over it is a check over all 81),
    /// those nearest the edge first; fails if a sample were left out or
    /// taken twice.
    #[test]
    fn the_writers_check_every_sample_edge_first(
        exact in proptest::collection::vec(prop_oneof![-127.0f64..127.0, -3.0f64..3.0, Just(f64::NAN), Just(0.0)], TILE_SAMPLES),
        near in prop_oneof![0.0f64..40.0, Just(f64::NAN)],
    ) {
        let exact: [f64; TILE_SAMPLES] = exact.try_into().expect("81 samples");
        let order = planes::edge_first(&exact, near);
        let mut seen = [false; TILE_SAMPLES];
        for &i in &order {
            prop_assert!(!seen[i as usize], "sample {} twice", i);
            seen[i as usize] = true;
        }
        let close = |i: u8| exact[i as usize].abs() <= 2.0;
        let first_far = order.iter().position(|&i| !close(i)).unwrap_or(TILE_SAMPLES);
        prop_assert!(order[first_far..].iter().all(|&i| !close(i)));
    }
}

/// A thin wedge of land between a lake and a river band crossing its shore
/// at about 8 degrees (the river over the lake of a teacher's map): no
/// analytic kind plays two curved edges, and stored samples round the
/// crease between them away, so before fine tiles (format 4.4) the wedge
/// was lost for up to 0.76 mm from where they cross. Fine tiles keep it:
/// wherever the exact distance is farther than 0.1 mm from the edge, the
/// field is on its side, even round the crossings (`taxel report` counts
/// those within 1 mm of them as corners; the writer checks its tolerance,
/// 0.03 mm, at points `h / 4` apart).
#[test]
fn a_thin_wedge_between_a_lake_and_a_river_is_kept_by_fine_tiles() {
    let land = [square(2.0, 2.0, 26.0)];
    let (c, a, b) = ((20.0, 18.0), 9.0, 4.5);
    let lake = [Polyline {
        points: (0..600)
            .map(|k| k as f64 * std::f64::consts::TAU / 600.0)
            .map(|t| (c.0 + a * t.cos(), c.1 + b * t.sin()))
            .collect(),
        closed: true,
    }];
    // A river gently curving across the lake's top: y = 13.6 + 0.1 d + 0.004 d², d = x − 20.
    let river = [Polyline {
        points: (0..=400)
            .map(|k| 8.0 + 20.0 * k as f64 / 400.0)
            .map(|x| (x, 13.6 + 0.1 * (x - 20.0) + 0.004 * (x - 20.0) * (x - 20.0)))
            .collect(),
        closed: false,
    }];
    let g = LayerGeometry {
        fills: vec![(&land, FillRule::NonZero)],
        cuts: vec![(&river, 0.35)],
        occluders: vec![(&lake, FillRule::NonZero)],
        ..Default::default()
    };
    let p = params(0.5, 0.0);
    let f = build_field(&g, p).expect("a field");
    let fine =
        f.tiles.iter().filter(|&&e| matches!(taxel_format::TileEntry::of(e), taxel_format::TileEntry::Fine { .. }));
    assert!(fine.count() > 0, "fine tiles where the river crosses the shore");
    // Round both crossings (x near 19.2 and 25.0), 0.02 mm apart.
    let tol = 0.1;
    let (mut wedge, mut checked) = (0, 0);
    for x0 in [17.5, 23.0] {
        for i in 0..200 {
            for j in 0..100 {
                let q = (x0 + i as f64 * 0.0201, 12.8 + j as f64 * 0.0199);
                let e = exact_signed_distance(&g, p.page, q);
                if e.abs() <= tol {
                    continue;
                }
                let d = field_distance(&f, 0.5, q).expect("in the lattice");
                assert!(d.signum() == e.signum(), "{q:?}: field {d}, exact {e}");
                checked += 1;
                wedge += usize::from(e > 0.0 && e < 0.2);
            }
        }
    }
    assert!(checked > 30_000 && wedge > 200, "{checked} points, {wedge} in the wedges");
}

/// An icon as experiment 5 draws it: a grated right triangle less its
/// vibrating outline cut out of it. The grating's edge is the outline's
/// inner offset; near an acute corner both offsets cross one tile, a wedge
/// that a corner tile of two cut lines plays (each segment's line less the
/// cut's half width), exactly, and the field matches the exact geometry
/// everywhere.
#[test]
fn a_grating_s_wedge_inside_a_cut_outline_is_a_corner_tile() {
    let tri = [Polyline { points: vec![(5.0, 3.0), (27.0, 25.0), (5.0, 25.0)], closed: true }];
    let g = LayerGeometry { fills: vec![(&tri, FillRule::NonZero)], cuts: vec![(&tri, 1.5)], ..Default::default() };
    let p = params(0.5, 0.0);
    check(&g, p, &grid_points(0.173)).expect("field within bounds");
    let f = build_field(&g, p).expect("a field");
    // Below the top acute corner, the wedge between the offsets of the leg
    // x = 5 and the hypotenuse y = x - 2 (both 0.75 mm in) crosses the tile
    // from (4, 6) to (8, 10).
    let q = (5.75, 8.0);
    let (tx, ty) = (((q.0 - f.origin.0) / 0.5) as usize / TILE_CELLS, ((q.1 - f.origin.1) / 0.5) as usize / TILE_CELLS);
    let e = f.tiles.get(ty * f.tile_cols as usize + tx).copied().unwrap_or(TILE_OUTSIDE);
    assert!(
        matches!(taxel_format::TileEntry::of(e), taxel_format::TileEntry::Corner(_)),
        "{:?}",
        taxel_format::TileEntry::of(e)
    );
    assert_amplitude_exact_round(&g, p, &f, q);
}
