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
//!
//! Where the side meets the circle the felt region has a corner (a Bézier
//! side meeting a straight one, as a country's outline often has). Outside
//! it, near the corner, the lesser of the two codes is the miter, not the
//! exact distance (the distance to the corner point), so a check of the
//! codes alone refused every such tile. As for corner tiles (`bends.rs`),
//! the writer checks instead that the exact distance is, within half a code,
//! that of the region the records stand for (the half plane cut by the disc
//! or the hole, [`Cut::model`]), and that the played code gives the same
//! amplitude as that region's distance everywhere but in a spot round each
//! corner of radius `(ramp / 2) / sin(θ / 2)`, at most
//! [`SPOT_MM`](super::bends::SPOT_MM).

use taxel_format::{DISTANCE_ZERO, MAX_PLANE_CODE, MAX_PLANE_GRADIENT, TILE_ARC, TILE_CELLS, TILE_SAMPLES, TILE_SIDE};
use taxel_format::{TileEntry, TilePlane};

use super::planes::{Saturation, TOLERANCE, TileCtx};
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
pub(super) fn cut_arcs(t: &TileCtx<'_, '_>, exact: &[f64; TILE_SAMPLES]) -> Vec<Cut> {
    if t.g.band.is_some() {
        return Vec::new();
    }
    let span = TILE_CELLS as f64 * t.h;
    let middle = t.middle();
    let nearest = t.nearest(Part::Fill, NEAR_SEGMENTS);
    let near: Vec<Seg> = nearest.iter().map(|&(_, s)| s).collect();
    let mut out: Vec<Cut> = Vec::new();
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
                    let cut = Cut::new(t, &line, sign, (c, r), rec);
                    if plays(t, &cut, exact, order) && !out.iter().any(|o| o.recs == rec) {
                        out.push(cut);
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
    let mut out: Vec<Seg> = count.into_iter().take(MAX_SIDES).map(|(n, _)| near[n].1).collect();
    // A straight side beside a tight curve: the curve's many short
    // segments crowd the nearest, and the side may not be among them. The
    // longest fill segment acting on the tile, if at least a cell long, is
    // tried too.
    let longest = t
        .bucket
        .iter()
        .filter_map(|&n| t.segs.get(n as usize))
        .filter(|(_, part, _)| *part == Part::Fill)
        .map(|&((a, b), _, _)| ((b.0 - a.0).hypot(b.1 - a.1), (a, b)))
        .max_by(|x, y| x.0.total_cmp(&y.0));
    if let Some((len, s)) = longest
        && len >= t.h
        && !out.contains(&s)
    {
        out.push(s);
    }
    out
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

/// Whether a cut arc plays the tile's 81 exact codes ([`Cut::close`]).
/// `order` is [`edge_first`](super::planes::edge_first)'s.
fn plays(t: &TileCtx<'_, '_>, cut: &Cut, exact: &[f64; TILE_SAMPLES], order: &[u8; TILE_SAMPLES]) -> bool {
    order
        .iter()
        .map(|&i| i as usize)
        .all(|i| cut.close((i % TILE_SIDE) as f64, (i / TILE_SIDE) as f64, exact[i], t.sat))
}

/// A cut arc's records and the region they stand for, in the tile's lattice
/// coordinates: where the side's signed distance `n · q + d` (cells, `n` a
/// unit normal towards the felt side) and the circle's, `inside · (ρ − |q −
/// C|)`, are both positive.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Cut {
    /// The tile's two records (an arc tile's, the second holding the side's plane).
    pub recs: [TilePlane; 2],
    n: (f64, f64),
    d: f64,
    centre: (f64, f64),
    rho: f64,
    /// 1 for a disc (felt inside the circle), −1 for a hole.
    inside: f64,
    /// Codes per cell.
    k: f64,
    /// Where the side's line crosses the circle (`count` of them).
    corners: [(f64, f64); 2],
    count: usize,
    /// The radius round each corner where the amplitude may differ, cells.
    spot: f64,
}

impl Cut {
    /// The cut arc of `recs`: the side's `line` on the side `sign` gives, the
    /// circle of centre `c` and radius `r` (page mm), a disc where the arc
    /// record's radius is 0, else a hole. Its `spot` is NaN where a corner's
    /// spot over the tile is wider than [`SPOT_MM`](super::bends::SPOT_MM):
    /// then only the codes' own check holds.
    fn new(t: &TileCtx<'_, '_>, line: &Line, sign: f64, (c, r): ((f64, f64), f64), recs: [TilePlane; 2]) -> Cut {
        let k = t.h / t.step;
        let n = (sign * line.gx / k, sign * line.gy / k);
        let d = sign * line.c / k;
        let centre = ((c.0 - t.corner.0) / t.h, (c.1 - t.corner.1) / t.h);
        let rho = r / t.h;
        let inside = if recs[0].gy == 0.0 { 1.0 } else { -1.0 };
        // The line's points nearest the centre, then along it either way.
        let s = n.0 * centre.0 + n.1 * centre.1 + d;
        let foot = (centre.0 - s * n.0, centre.1 - s * n.1);
        let mut cut = Cut { recs, n, d, centre, rho, inside, k, corners: [foot; 2], count: 0, spot: 0.0 };
        if s.abs() <= rho {
            let along = (rho * rho - s * s).sqrt();
            let dir = (-n.1, n.0);
            cut.corners =
                [(foot.0 + along * dir.0, foot.1 + along * dir.1), (foot.0 - along * dir.0, foot.1 - along * dir.1)];
            cut.count = 2;
            // The spot as a corner tile's (`bends.rs`): the half ramp over
            // sin(θ / 2), from the felt sides' normals at the corner. Only
            // corners over the tile (grown by two cells) matter; a sharp one
            // there leaves the cut arc to the codes' own check.
            let grown = -2.0..=TILE_CELLS as f64 + 2.0;
            for x in cut.corners.into_iter().filter(|x| grown.contains(&x.0) && grown.contains(&x.1)) {
                let nc = (inside * (centre.0 - x.0) / rho, inside * (centre.1 - x.1) / rho);
                let sin_half = ((1.0 + n.0 * nc.0 + n.1 * nc.1) / 2.0).max(0.0).sqrt();
                let spot_mm = t.sat.hi * t.step / sin_half;
                // (A NaN, from a zero sine, is refused too.)
                if spot_mm.is_nan() || spot_mm > super::bends::SPOT_MM {
                    cut.spot = f64::NAN;
                    break;
                }
                cut.spot = cut.spot.max(spot_mm / t.h);
            }
        }
        cut
    }

    /// The signed distance (codes) from `(u, w)` to the region's outline:
    /// the nearest of the side's line where it is inside the circle's felt
    /// side, the circle where it is on the side's felt side, and the corners.
    fn model(&self, u: f64, w: f64) -> f64 {
        let p = self.n.0 * u + self.n.1 * w + self.d;
        let (dx, dy) = (u - self.centre.0, w - self.centre.1);
        let from_centre = dx.hypot(dy);
        let a = self.inside * (self.rho - from_centre);
        let mut best = f64::INFINITY;
        // The foot on the line, on the circle's felt side.
        let foot = (u - p * self.n.0, w - p * self.n.1);
        if self.inside * (self.rho - (foot.0 - self.centre.0).hypot(foot.1 - self.centre.1)) >= 0.0 {
            best = best.min(p.abs());
        }
        // The foot on the circle, on the side's felt side.
        if from_centre > 0.0 {
            let f = (self.centre.0 + self.rho * dx / from_centre, self.centre.1 + self.rho * dy / from_centre);
            if self.n.0 * f.0 + self.n.1 * f.1 + self.d >= 0.0 {
                best = best.min(a.abs());
            }
        }
        for x in &self.corners[..self.count] {
            best = best.min((u - x.0).hypot(w - x.1));
        }
        let felt = p >= 0.0 && a >= 0.0;
        self.k * if felt { best } else { -best }
    }

    /// Whether the cut arc plays the exact distance `e` (codes, clamped) at
    /// `(u, w)`: the region's distance is close to it as a plane's must be,
    /// and outside the corners' spots the played code gives the amplitude
    /// of the region's distance.
    pub(super) fn close(&self, u: f64, w: f64, e: f64, sat: Saturation) -> bool {
        let entry = TileEntry::of(TILE_ARC);
        let Some(v) = entry.code(&self.recs, u, w) else { return false };
        // The codes' own check first (all a cut arc had before corners).
        if sat.close(v - DISTANCE_ZERO as f64, e) {
            return true;
        }
        let m = self.model(u, w);
        if self.spot.is_nan() || !(m.is_finite() && sat.close(m, e)) {
            return false;
        }
        if self.corners[..self.count].iter().any(|x| (u - x.0).hypot(w - x.1) <= self.spot) {
            return true;
        }
        let clamp = |x: f64| x.clamp(sat.lo, sat.hi);
        (clamp(v - DISTANCE_ZERO as f64) - clamp(m)).abs() <= TOLERANCE
    }
}
