//! Cut arcs (SPEC.md section 6.2, format 4.3): a tile where a fill's
//! straight side and a circular hole in it (a province's side and its lake)
//! both lie within the clamp plays the lesser of the side's affine distance
//! and the circle's arc code, instead of 81 samples.
//!
//! No single analytic kind plays two features, so before 4.3 such a tile
//! was stored, and a stored tile is exact only at its lattice points: the
//! bilinear interpolation of the lake's curved distance between them, and
//! the rounding of its codes to whole steps, are up to the whole of a hard
//! edge's one-step ramp. Seven such tiles held 69% of `tala-map`'s grating
//! RMS error (`taxel report`, docs/report.md). The felt region there is the
//! intersection of the side's half plane and the outside of the circle, so
//! inside it the exact distance is the lesser of the two distances, and
//! outside it the lesser is the exact distance wherever the outline's
//! nearest point is on the side or on the circle; the writer keeps one
//! only where, as for every analytic tile, it plays the exact distance
//! within half a code at the 81 lattice points (and, by the caller, at the
//! 64 cell centres), or saturated on the same side. It is tried last, only
//! where no other kind plays the tile.

use taxel_format::{DISTANCE_ZERO, MAX_PLANE_CODE, MAX_PLANE_GRADIENT, TILE_ARC, TILE_CELLS, TILE_SAMPLES, TILE_SIDE};
use taxel_format::{TileEntry, TilePlane};

use super::planes::TileCtx;
use super::{Part, Seg};

/// Fill segments near the tile among which its side and its circle's
/// vertices are looked for.
const NEAR_SEGMENTS: usize = 48;
/// The numbers of nearest segments off the side whose vertices are fitted
/// (besides those over the tile).
const FIT_SEGMENTS: [usize; 3] = [24, 8, 3];
/// Most sides tried: the segments nearest the most lattice points where the
/// code matters.
const MAX_SIDES: usize = 3;

/// The cut arcs' records (an arc tile's two, the second holding the side's
/// plane) that may play a fill's tile whose exact codes are `exact`, each
/// kept only if it plays the 81 samples (the caller checks the cell
/// centres). None for a band layer.
pub(super) fn cut_arcs(t: &TileCtx<'_, '_>, exact: &[f64; TILE_SAMPLES]) -> Vec<[TilePlane; 2]> {
    if t.g.band.is_some() {
        return Vec::new();
    }
    let span = TILE_CELLS as f64 * t.h;
    let middle = t.middle();
    let nearest = t.nearest(Part::Fill, NEAR_SEGMENTS);
    let near: Vec<Seg> = nearest.iter().map(|&(_, s)| s).collect();
    let mut out: Vec<[TilePlane; 2]> = Vec::new();
    let order = t.order(exact);
    for side in sides(t, exact, &nearest) {
        let Some(line) = Line::of(t, side) else { continue };
        // The circle's vertices: the other segments' ends off the side's line.
        let off = |p: &(f64, f64)| line.distance_mm(*p).abs() > super::arcs::ON_CIRCLE_MM;
        let others: Vec<Seg> = near.iter().copied().filter(|s| *s != side && (off(&s.0) || off(&s.1))).collect();
        let m = t.h;
        let over = |p: &(f64, f64)| {
            p.0 >= t.corner.0 - m
                && p.0 <= t.corner.0 + span + m
                && p.1 >= t.corner.1 - m
                && p.1 <= t.corner.1 + span + m
        };
        let ends = |segs: &[Seg]| -> Vec<(f64, f64)> { segs.iter().flat_map(|(a, b)| [*a, *b]).filter(off).collect() };
        let mut here: Vec<(f64, f64)> = ends(&others).into_iter().filter(over).collect();
        here.dedup();
        let sets = std::iter::once(here)
            .chain(FIT_SEGMENTS.iter().filter(|&&n| others.len() >= n).map(|&n| ends(&others[..n])));
        for points in sets {
            let Some((c, r)) = super::arcs::circle_through(points.iter().copied(), middle) else { continue };
            for arc in super::arcs::arcs(t, c, r, None) {
                for sign in [1.0, -1.0] {
                    let Some(rec) = line.cut(arc, sign) else { continue };
                    if plays(t, &rec, exact, order) && !out.contains(&rec) {
                        out.push(rec);
                    }
                }
            }
        }
    }
    out
}

/// The candidate sides: among `near`, the segments nearest the most lattice
/// points whose exact code is within the clamp (where the code matters),
/// at most [`MAX_SIDES`], most points first.
fn sides(t: &TileCtx<'_, '_>, exact: &[f64; TILE_SAMPLES], near: &[(f64, Seg)]) -> Vec<Seg> {
    let middle = t.middle();
    let mut count: Vec<(usize, usize)> = Vec::new();
    for (i, &e) in exact.iter().enumerate() {
        if e.abs() >= t.cap {
            continue;
        }
        let p = (t.corner.0 + (i % TILE_SIDE) as f64 * t.h, t.corner.1 + (i / TILE_SIDE) as f64 * t.h);
        // The first of the nearest, as `min_by` keeps.
        let Some((n, _)) = super::nearest_of(near, middle, p, t.measured.least(Part::Fill, i)) else { continue };
        match count.iter_mut().find(|(k, _)| *k == n) {
            Some((_, c)) => *c += 1,
            None => count.push((n, 1)),
        }
    }
    count.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    count.into_iter().take(MAX_SIDES).map(|(n, _)| near[n].1).collect()
}

/// A side's line over the tile: the signed distance to it, in codes, is
/// `c + gx u + gy w` at lattice coordinates `(u, w)` in the tile.
struct Line {
    /// A point of the line and its unit normal, page mm.
    a: (f64, f64),
    n: (f64, f64),
    c: f64,
    gx: f64,
    gy: f64,
}

impl Line {
    /// The line through segment `s`, `None` for a point.
    fn of(t: &TileCtx<'_, '_>, (a, b): Seg) -> Option<Line> {
        let len = (b.0 - a.0).hypot(b.1 - a.1);
        if !(len.is_finite() && len > 0.0) {
            return None;
        }
        let n = ((a.1 - b.1) / len, (b.0 - a.0) / len);
        let k = t.h / t.step;
        let c = (n.0 * (t.corner.0 - a.0) + n.1 * (t.corner.1 - a.1)) / t.step;
        Some(Line { a, n, c, gx: n.0 * k, gy: n.1 * k })
    }

    /// The signed distance from the line to page point `p`, mm.
    fn distance_mm(&self, p: (f64, f64)) -> f64 {
        self.n.0 * (p.0 - self.a.0) + self.n.1 * (p.1 - self.a.1)
    }

    /// Arc records `arc` with this line's plane, positive on the side
    /// `sign` gives, in their second record (a cut arc), if within a plane
    /// record's bounds.
    fn cut(&self, arc: [TilePlane; 2], sign: f64) -> Option<[TilePlane; 2]> {
        let c = DISTANCE_ZERO as f64 + sign * self.c;
        let (gx, gy) = (sign * self.gx, sign * self.gy);
        let ok = |x: f64, m: f32| x.is_finite() && x.abs() <= m as f64;
        if !(ok(c, MAX_PLANE_CODE) && ok(gx, MAX_PLANE_GRADIENT) && ok(gy, MAX_PLANE_GRADIENT)) {
            return None;
        }
        let [first, second] = arc;
        let rec = [first, TilePlane { c: second.c, gx: c as f32, gy: gx as f32, top: gy as f32 }];
        // (A plane of three zeros would read as an arc alone.)
        taxel_format::is_cut_arc(&rec[1]).then_some(rec)
    }
}

/// Whether a cut arc's records play the tile's 81 exact codes as a plane must.
/// `order` is [`edge_first`](super::planes::edge_first)'s.
fn plays(t: &TileCtx<'_, '_>, r: &[TilePlane; 2], exact: &[f64; TILE_SAMPLES], order: &[u8; TILE_SAMPLES]) -> bool {
    let entry = TileEntry::of(TILE_ARC);
    order.iter().map(|&i| i as usize).all(|i| {
        let code = entry.code(r, (i % TILE_SIDE) as f64, (i / TILE_SIDE) as f64);
        code.is_some_and(|code| t.sat.close(code - DISTANCE_ZERO as f64, exact[i]))
    })
}
