//! Segments tiles (SPEC.md section 6.2, format 4.2): a tile where three
//! band centre lines meet, or a vibrating band is cut out of a grating
//! there, plays `top − k · min_i dist(q, segment i)` over up to three
//! segments of the centre lines, instead of 81 samples.
//!
//! Where three borders of a map meet, the union of their bands has sharp
//! concave corners between the bands (and the grating cut out of the
//! regions has sharp convex ones): a bilinear sampled tile rounds them by up
//! to a few hundredths of a mm, which at a hard edge (a ramp of one step,
//! 0.008 mm at the default pitch) is the full amplitude. That was all of
//! `tala-map`'s vibration RMS error (`taxel report`, docs/report.md). No
//! bend plays it (a bend has two rays from one
//! vertex); the distance to the union of the centre lines does, exactly:
//! a band of width `w` is `w / 2 − d` and a band cut out of a grating is
//! `d − w / 2`, `d` the distance to the nearest centre line, so a segments
//! tile with `k = h / step` (a band) or `k = −h / step` (a cut) and the
//! segments nearest the tile's points is the exact distance wherever those
//! segments hold the nearest point of the centre lines. The writer keeps
//! one only where, as for every analytic tile, it plays the exact distance
//! within half a code at the 81 lattice points (and, by the caller, the 64
//! cell centres), or saturated on the same side.

use taxel_format::{
    DISTANCE_ZERO, MAX_PLANE_CODE, MAX_PLANE_GRADIENT, SEGMENT_TILE_RECORDS, SEGMENTS_PER_TILE, TILE_CELLS,
    TILE_SAMPLES, TILE_SIDE, TilePlane, segments_code,
};

use super::Part;
use super::planes::TileCtx;

/// Most centre-line segments near a tile among which the nearest to its
/// points are looked for.
const MAX_CANDIDATES: usize = 24;

/// The segments tiles' records that may play a tile whose exact codes are
/// `exact`: for a band layer, its centre lines; for a grating, each width
/// of the bands cut out of it. Each is kept only if it plays the 81
/// samples (the caller checks the cell centres).
pub(super) fn segment_tiles(
    t: &TileCtx<'_, '_>,
    exact: &[f64; TILE_SAMPLES],
) -> Vec<[TilePlane; SEGMENT_TILE_RECORDS]> {
    let k = t.h / t.step;
    let zero = DISTANCE_ZERO as f64;
    // (which segments, codes per cell, top code)
    let mut kinds: Vec<(Part, f64, f64)> = Vec::new();
    if let Some((_, w)) = t.g.band.as_ref() {
        kinds.push((Part::Band, k, zero + w / 2.0 / t.step));
    }
    for (group, w) in t.cut_widths().into_iter().enumerate() {
        kinds.push((Part::Cut(group), -k, zero - w / 2.0 / t.step));
    }
    kinds.into_iter().filter_map(|(part, k, top)| segments_of(t, exact, part, k, top)).collect()
}

/// The segments tile of the `part` segments nearest the tile's points, if
/// at most [`SEGMENTS_PER_TILE`] of them are nearest to a point where the
/// code matters and it plays the samples.
fn segments_of(
    t: &TileCtx<'_, '_>,
    exact: &[f64; TILE_SAMPLES],
    part: Part,
    k: f64,
    top: f64,
) -> Option<[TilePlane; SEGMENT_TILE_RECORDS]> {
    let near = t.nearest(part, MAX_CANDIDATES);
    let middle = t.middle();
    if near.is_empty() {
        return None;
    }
    // A point decides nothing where its exact code is saturated on the side
    // to which a farther segment moves the code (a band's outside, a cut's
    // inside): leaving a segment out only lengthens the distance there.
    let matters = |e: f64| e.abs() <= t.sat.near || if k > 0.0 { e > t.sat.lo } else { e < t.sat.hi };
    // (point, its exact code and the least distance the samples' measure
    // found there; neither is at hand at a cell centre)
    let lattice = (0..TILE_SAMPLES)
        .map(|i| ((i % TILE_SIDE) as f64, (i / TILE_SIDE) as f64, Some(exact[i]), t.measured.least(part, i)));
    let centres = (0..TILE_CELLS * TILE_CELLS)
        .map(|i| ((i % TILE_CELLS) as f64 + 0.5, (i / TILE_CELLS) as f64 + 0.5, None::<f64>, None));
    let mut chosen: Vec<usize> = Vec::new();
    for (u, w, e, least) in lattice.chain(centres) {
        // A cell centre's exact code is not at hand: every centre counts.
        if e.is_some_and(|e| !matters(e)) {
            continue;
        }
        let p = (t.corner.0 + u * t.h, t.corner.1 + w * t.h);
        let (nearest, _) = super::nearest_of(&near, middle, p, least)?;
        if !chosen.contains(&nearest) {
            chosen.push(nearest);
            // More than a tile holds: none plays it (most crowded tiles stop here).
            if chosen.len() > SEGMENTS_PER_TILE {
                return None;
            }
        }
    }
    if chosen.is_empty() || chosen.len() > SEGMENTS_PER_TILE {
        return None;
    }
    let ok = |v: f64, m: f32| v.is_finite() && v.abs() <= m as f64;
    let cell = |p: (f64, f64)| ((p.0 - t.corner.0) / t.h, (p.1 - t.corner.1) / t.h);
    let mut recs = [TilePlane { c: 0.0, gx: 0.0, gy: 0.0, top: 0.0 }; SEGMENT_TILE_RECORDS];
    for (slot, rec) in recs.iter_mut().take(SEGMENTS_PER_TILE).enumerate() {
        // Unused slots repeat the first segment, which leaves the minimum as it is.
        let (_, (a, b)) = near[*chosen.get(slot).unwrap_or(&chosen[0])];
        let ((ax, ay), (bx, by)) = (cell(a), cell(b));
        if ![ax, ay, bx, by].iter().all(|&v| ok(v, MAX_PLANE_GRADIENT)) {
            return None;
        }
        *rec = TilePlane { c: ax as f32, gx: ay as f32, gy: bx as f32, top: by as f32 };
    }
    if !(ok(k, MAX_PLANE_GRADIENT) && ok(top, MAX_PLANE_CODE)) {
        return None;
    }
    recs[SEGMENTS_PER_TILE] = TilePlane { c: k as f32, gx: top as f32, gy: 0.0, top: 0.0 };
    let plays = exact.iter().enumerate().all(|(i, &e)| {
        let [s0, s1, s2, last] = &recs;
        let code = segments_code([s0, s1, s2, last], (i % TILE_SIDE) as f64, (i / TILE_SIDE) as f64);
        t.sat.close(code - DISTANCE_ZERO as f64, e)
    });
    plays.then_some(recs)
}
