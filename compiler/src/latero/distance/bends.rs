//! Corner and notch tiles (SPEC.md section 6.2, format 4.0): a tile that two
//! straight edges of a fill cross, meeting at a vertex, plays the lesser (a
//! convex corner of the felt region) or the greater (a concave one) of the
//! two edges' affine distances: two 16-byte plane records instead of 81
//! samples, played at the point itself.
//!
//! Inside a convex corner the lesser is the exact distance. Outside it, it
//! is the exact distance too, except in the wedge where the vertex is the
//! nearest point, where it is the miter `−max(|l1|, |l2|)` instead of the
//! round `−|p − v|`. Both lie below `−ramp / 2` (no amplitude) except in a
//! spot round the vertex of radius `(ramp / 2) / sin(θ / 2)`, θ the corner's
//! angle: so the amplitude the edge profile makes of the record is the
//! exact distance's everywhere but there, and the half-amplitude contour is
//! exactly the two edges. (A notch is the same with inside and outside
//! exchanged.) The writer keeps a bend only where that spot lies within
//! [`SPOT_MM`] of the vertex, which rules out soft edges and, for a hard
//! edge at the default pitch (a half ramp of 0.004 mm), corners sharper
//! than about 18 degrees; and only where the exact distance at the 81
//! samples and the 64 cell centres is, within half a code (or saturated on
//! the same side farther than `ramp / 2 + h` from the edge, as for planes),
//! the signed distance to the two rays from the vertex that the records
//! stand for, so that the tile's geometry is the corner's and the analysis
//! holds.
//!
//! A vibrating band's centre line bent at a vertex is round on the outer
//! side (the distance to the vertex), which no minimum or maximum of planes
//! plays: a **bend** tile ([`TILE_BEND`](taxel_format::TILE_BEND)) plays `top − k · min(dist(q, ray
//! 1), dist(q, ray 2))`, the distance to the two rays from the vertex along
//! the centre line's two segments, which is the exact distance wherever the
//! centre line's nearest point lies on them: the band's whole edge in the
//! tile, inner notch and outer round side. A band's end (a round cap) is a
//! bend with both rays the same. [`band_bends`] tries the band segments
//! nearest the tile, kept only where at the 81 samples (and, by the caller,
//! the 64 cell centres) the played code is within half a code of the exact
//! distance, or saturated on the same side, as for planes.

use taxel_format::{
    DISTANCE_ZERO, MAX_PLANE_CODE, MAX_PLANE_GRADIENT, TILE_CORNER, TILE_NOTCH, TILE_SAMPLES, TILE_SIDE, TileEntry,
    TilePlane,
};

use super::Part;
use super::planes::{Saturation, TOLERANCE, TileCtx, record};

/// Largest radius round a corner's vertex within which a corner or notch
/// tile may play another amplitude than the exact distance, mm: half the
/// band round every edge that `taxel report` leaves out of the value error.
pub(crate) const SPOT_MM: f64 = 0.025;
/// Most fill segments near a tile whose pairs are tried (the nearest).
const MAX_SEGMENTS: usize = 16;

/// A corner or notch tile's records, with what the writer's check needs.
#[derive(Debug, Clone, Copy)]
pub(super) struct Bend {
    /// [`TILE_CORNER`] or [`TILE_NOTCH`].
    pub kind: u32,
    /// The two records, in index order.
    pub recs: [TilePlane; 2],
    /// The vertex in the tile's lattice coordinates.
    vertex: (f64, f64),
    /// Codes per lattice cell of a distance.
    k: f64,
    /// Radius of the spot round the vertex where the amplitude may differ, cells.
    spot: f64,
    /// The rays' gradient lengths and dot product, as [`Bend::wedge`] uses them
    /// (the same for every sample, so reckoned once).
    rays: (f64, f64, f64),
}

impl Bend {
    /// The tile's two records from two affine codes, if they meet at one
    /// vertex at an angle whose spot is small enough; `norms` are the
    /// lengths of the records' gradients ([`gradient_norm`]).
    fn with_norms(
        kind: u32,
        recs: [TilePlane; 2],
        k: f64,
        half_ramp_mm: f64,
        h: f64,
        (n1, n2): (f64, f64),
    ) -> Option<Bend> {
        let [r1, r2] = recs;
        let (g1, g2) = ((r1.gx as f64, r1.gy as f64), (r2.gx as f64, r2.gy as f64));
        let det = g1.0 * g2.1 - g1.1 * g2.0;
        if !(n1 > 0.0 && n2 > 0.0 && det.abs() > 1e-6 * n1 * n2) {
            return None;
        }
        // g1 · v = 128 − c1 and g2 · v = 128 − c2.
        let (b1, b2) = (DISTANCE_ZERO as f64 - r1.c as f64, DISTANCE_ZERO as f64 - r2.c as f64);
        let vertex = ((b1 * g2.1 - g1.1 * b2) / det, (g1.0 * b2 - b1 * g2.0) / det);
        // sin(θ / 2) for the corner's angle θ: the normals' angle is π − θ.
        let sin_half = ((1.0 + (g1.0 * g2.0 + g1.1 * g2.1) / (n1 * n2)) / 2.0).max(0.0).sqrt();
        let spot_mm = half_ramp_mm / sin_half;
        if spot_mm > SPOT_MM {
            return None;
        }
        let rays = Bend::rays(kind, &recs, (n1, n2));
        Some(Bend { kind, recs, vertex, k, spot: spot_mm / h, rays })
    }

    /// The sign of the rays' side (a notch is the corner of the region where it is not felt).
    fn side(kind: u32) -> f64 {
        if kind == TILE_NOTCH { -1.0 } else { 1.0 }
    }

    /// The rays' gradients' lengths (`norms`, the records' gradients'
    /// lengths: a sign does not change them) and their dot product, each
    /// signed as a wedge takes them.
    fn rays(kind: u32, [r1, r2]: &[TilePlane; 2], (n1, n2): (f64, f64)) -> (f64, f64, f64) {
        let s = Bend::side(kind);
        let g = |r: &TilePlane| (s * r.gx as f64, s * r.gy as f64);
        let (g1, g2) = (g(r1), g(r2));
        (n1, n2, g1.0 * g2.0 + g1.1 * g2.1)
    }

    /// The code it plays at `(u, w)`, less the bias.
    fn played(&self, u: f64, w: f64) -> f64 {
        TileEntry::of(self.kind).code(&self.recs, u, w).unwrap_or(f64::NAN) - DISTANCE_ZERO as f64
    }

    /// The signed distance in codes at `(u, w)` to the two rays from the
    /// vertex along which the records' lines bound the felt region (for a
    /// corner where both codes are positive, for a notch where either is):
    /// the exact distance of that geometry, round round the vertex.
    /// `r` is the distance from `(u, w)` to the vertex, in cells.
    fn wedge(&self, u: f64, w: f64, r: f64) -> f64 {
        let s = Bend::side(self.kind);
        let a = |r: &TilePlane| s * (r.affine(u, w) - DISTANCE_ZERO as f64);
        let [r1, r2] = &self.recs;
        let (a1, a2) = (a(r1), a(r2));
        let (n1, n2, dot) = self.rays;
        let to_vertex = self.k * r;
        // The foot of the perpendicular on line 1 is on ray 1 where the other
        // code is not negative there, and the same for line 2.
        let d1 = if a2 - a1 * dot / (n1 * n1) >= 0.0 { a1.abs() * self.k / n1 } else { to_vertex };
        let d2 = if a1 - a2 * dot / (n2 * n2) >= 0.0 { a2.abs() * self.k / n2 } else { to_vertex };
        let d = d1.min(d2);
        s * if a1 >= 0.0 && a2 >= 0.0 { d } else { -d }
    }

    /// Whether the bend plays the exact distance `e` (codes, clamped) at
    /// `(u, w)`: the rays' distance is close to it as a plane's must be, and
    /// outside the spot the played code is the rays' distance within the
    /// profile's saturated range.
    pub(super) fn close(&self, u: f64, w: f64, e: f64, sat: Saturation) -> bool {
        let r = (u - self.vertex.0).hypot(w - self.vertex.1);
        let d = self.wedge(u, w, r);
        let played = self.played(u, w);
        // The layer's distance is the rays' (round round the vertex), or,
        // where it is a bound, the played miter itself: a grating less the
        // vibrating band cut out of it has `d_c − w / 2` at the band's inner
        // corners, the lesser of the two offset lines, exactly what a corner
        // tile plays (the experiment-5 triangles' acute inner corners, whose
        // tiles were refused for it and stored).
        if !sat.close(d, e) && !sat.close(played, e) {
            return false;
        }
        let in_spot = r <= self.spot;
        let clamp = |v: f64| v.clamp(sat.lo, sat.hi);
        in_spot || (clamp(played) - clamp(d)).abs() <= TOLERANCE
    }
}

/// The corners and notches that play a tile's samples (`exact`, codes,
/// row-major 9 x 9): pairs of the fills' segments near the tile that share
/// an end, each side either way round, as a corner or a notch.
pub(super) fn bends(t: &TileCtx<'_, '_>, exact: &[f64; TILE_SAMPLES], ramp_mm: f64) -> Vec<Bend> {
    let mut out = Vec::new();
    if t.g.band.is_some() {
        return out;
    }
    let near = t.nearest(Part::Fill, MAX_SEGMENTS);
    let k = t.h / t.step;
    // A segment's line over the tile: signed distance in codes at its first
    // lattice point, and gradient in codes per cell.
    let line = |a: (f64, f64), b: (f64, f64)| {
        let len = (b.0 - a.0).hypot(b.1 - a.1);
        let (nx, ny) = ((a.1 - b.1) / len, (b.0 - a.0) / len);
        let c = (nx * (t.corner.0 - a.0) + ny * (t.corner.1 - a.1)) / t.step;
        (len.is_finite() && len > 0.0).then_some((c, nx * k, ny * k))
    };
    let order = t.order(exact);
    let plays = |bend: &Bend| {
        order
            .iter()
            .map(|&i| i as usize)
            .all(|i| bend.close((i % TILE_SIDE) as f64, (i / TILE_SIDE) as f64, exact[i], t.sat))
    };
    // Pairs of segments that share an end, as two lines less `off` codes:
    // a fill's own edges (`off` 0), or a cut band's centre lines less its
    // half width, whose offsets are the inner edges of a grating less the
    // vibrating outline cut out of it (an icon's inner corners).
    let mut pairs = |near: &[(f64, super::Seg)], off: f64| {
        // Each segment's line once (a segment is in up to two pairs that
        // share an end), with the length of its record's gradient (either sign).
        let lines: Vec<_> =
            near.iter().map(|&(_, (a, b))| line(a, b).map(|(c, gx, gy)| (c, gx, gy, gradient_norm(gx, gy)))).collect();
        for (i, &(_, (a1, b1))) in near.iter().enumerate() {
            for (j, &(_, (a2, b2))) in near.iter().enumerate().skip(i + 1) {
                // Whether they share an end first: most pairs do not.
                let shares = [a1, b1].iter().any(|p| [a2, b2].iter().any(|q| p.0 == q.0 && p.1 == q.1));
                if !shares {
                    continue;
                }
                let (Some(l1), Some(l2)) = (lines[i], lines[j]) else { continue };
                let norms = (l1.3, l2.3);
                for (s1, s2) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                    let rec = |(c, gx, gy, _): (f64, f64, f64, f64), s: f64| {
                        record(DISTANCE_ZERO as f64 + s * c - off, s * gx, s * gy, 0.0)
                    };
                    let (Some(r1), Some(r2)) = (rec(l1, s1), rec(l2, s2)) else { continue };
                    for kind in [TILE_CORNER, TILE_NOTCH] {
                        let bend = Bend::with_norms(kind, [r1, r2], k, ramp_mm / 2.0, t.h, norms);
                        if let Some(bend) = bend.filter(|b| plays(b)) {
                            out.push(bend);
                        }
                    }
                }
            }
        }
    };
    pairs(&near, 0.0);
    for (kc, w) in t.cut_widths().into_iter().enumerate() {
        pairs(&t.nearest(Part::Cut(kc), MAX_SEGMENTS), w / 2.0 / t.step);
    }
    out
}

/// The length of the gradient of a plane record made from `(±gx, ±gy)`,
/// `(r.gx as f64).hypot(r.gy as f64)`, the same for either sign (`hypot`
/// takes magnitudes, and rounding to `f32` is symmetric): a segment's is
/// reckoned once, not once per sign, kind and pair it is tried in.
pub(super) fn gradient_norm(gx: f64, gy: f64) -> f64 {
    (gx as f32 as f64).hypot(gy as f32 as f64)
}

/// Most band segments near a tile whose pairs and ends are tried as bends.
const MAX_BAND_SEGMENTS: usize = 8;

/// The bend tiles' records (vertex, directions, `k`, top; SPEC.md section
/// 6.2) that may play a band layer's tile whose exact codes are `exact`:
/// two band segments near the tile that share an end, and each band
/// segment's end alone (a cap), each kept if it plays the 81 samples.
pub(super) fn band_bends(t: &TileCtx<'_, '_>, exact: &[f64; TILE_SAMPLES]) -> Vec<[TilePlane; 2]> {
    let mut out = Vec::new();
    let Some((_, width)) = t.g.band.as_ref() else { return out };
    let top = DISTANCE_ZERO as f64 + width / 2.0 / t.step;
    let k = t.h / t.step;
    let near = t.nearest(Part::Band, MAX_BAND_SEGMENTS);
    // The unit direction from `v` towards `p`, if they differ.
    let unit = |v: (f64, f64), p: (f64, f64)| {
        let len = (p.0 - v.0).hypot(p.1 - v.1);
        (len.is_finite() && len > 0.0).then(|| ((p.0 - v.0) / len, (p.1 - v.1) / len))
    };
    let rec = |v: (f64, f64), d1: (f64, f64), d2: (f64, f64)| {
        let (vu, vw) = ((v.0 - t.corner.0) / t.h, (v.1 - t.corner.1) / t.h);
        let ok = |x: f64, m: f32| x.is_finite() && x.abs() <= m as f64;
        (ok(vu, MAX_PLANE_GRADIENT)
            && ok(vw, MAX_PLANE_GRADIENT)
            && ok(k, MAX_PLANE_GRADIENT)
            && ok(top, MAX_PLANE_CODE))
        .then_some([
            TilePlane { c: vu as f32, gx: vw as f32, gy: d1.0 as f32, top: d1.1 as f32 },
            TilePlane { c: d2.0 as f32, gx: d2.1 as f32, gy: k as f32, top: top as f32 },
        ])
    };
    let order = t.order(exact);
    let plays = |r: &[TilePlane; 2]| {
        order.iter().map(|&i| i as usize).all(|i| {
            let code = taxel_format::bend_code([&r[0], &r[1]], (i % TILE_SIDE) as f64, (i / TILE_SIDE) as f64);
            t.sat.close(code - DISTANCE_ZERO as f64, exact[i])
        })
    };
    let mut try_bend = |v: (f64, f64), p1: (f64, f64), p2: (f64, f64)| {
        let (Some(d1), Some(d2)) = (unit(v, p1), unit(v, p2)) else { return };
        if let Some(r) = rec(v, d1, d2).filter(|r| plays(r)) {
            out.push(r);
        }
    };
    for (i, &(_, (a1, b1))) in near.iter().enumerate() {
        for &(_, (a2, b2)) in &near[i + 1..] {
            for (v, p1) in [(a1, b1), (b1, a1)] {
                for (w, p2) in [(a2, b2), (b2, a2)] {
                    if v == w {
                        try_bend(v, p1, p2);
                    }
                }
            }
        }
    }
    // Caps: each segment's end alone.
    for &(_, (a, b)) in near.iter() {
        try_bend(a, b, b);
        try_bend(b, a, a);
    }
    out
}
