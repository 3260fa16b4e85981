//! The lanes played out of line: bend (format 4.0), arc and cut arc (4.1,
//! 4.3), segments (4.2) and fine (4.4) tiles. Their values are written by
//! one cold call on a tile change ([`FieldLayer::curved_lanes`]) and played
//! by row functions of their own ([`FieldLayer::bend`] and its siblings),
//! so that layers and rows without such tiles cost nothing more.

use taxel_format::{PLANE_RECORD_LEN, SEGMENTS_PER_TILE, TILE_OUTSIDE, TILE_SIDE, TileEntry, fine_cell};
use wide::f32x4;

use super::lanes::{Lane, Record, record_of};
use super::{FieldLayer, SHIFT};
use crate::latero::LANES;

/// The bend lanes (format 4.0) of a [`TileLanes`](super::TileLanes): a bend lane plays `top −
/// k · min(dist(q, ray 1), dist(q, ray 2))` ([`FieldLayer::bend`]); `v`
/// holds per lane its column less its vertex's x, the vertex's y, its
/// rays' unit directions (x, y, x, y), its codes per cell and its top
/// code. Kept apart and written out of line, so that tiles without bends
/// cost nothing more.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct BendLanes {
    pub(super) bend: [i32; LANES],
    pub(super) v: [[f32; LANES]; 8],
    /// The arc lanes (format 4.1): an arc lane plays `top − k · ||q − C| −
    /// R|` ([`FieldLayer::arc`]); `c` holds per lane its column less its
    /// centre's x, the centre's y, the radius, `k` and the top code, then a
    /// cut arc's plane (format 4.3) at its column and its gradient along y
    /// (`f32::MAX` and 0 for an arc alone, so that the lesser is the arc's).
    pub(super) arc: [i32; LANES],
    pub(super) c: [[f32; LANES]; 7],
    /// Whether any lane of the current tiles is in an arc tile. Kept here,
    /// not in [`TileLanes`], so that kernels without bend lanes are the
    /// code they were before arcs; reset on every tile change that reads
    /// records.
    pub(super) arced: bool,
    /// The segments lanes (format 4.2): a segments lane plays `top − k ·
    /// min_i dist(q, segment i)` over three segments
    /// ([`FieldLayer::segments`]); `s` holds per lane, for each segment, its
    /// column less the segment's first end's x, that end's y, the segment's
    /// vector (x, y) and the inverse of its squared length (0 for a point),
    /// then `k` and the top code.
    pub(super) seg: [i32; LANES],
    pub(super) s: [[f32; LANES]; SEGMENT_LANE_VALUES],
    /// Whether any lane of the current tiles is in a segments tile, reset
    /// as `arced` is.
    pub(super) segged: bool,
    /// The fine lanes (format 4.4): a fine lane plays the bilinear
    /// interpolation of its fine tile's samples, or the lesser of its two
    /// channels' ([`FieldLayer::fine`]); per lane its first stored tile,
    /// its refinement, whether it has two channels, and its lattice x
    /// within the tile.
    pub(super) fine: [i32; LANES],
    pub(super) fine_first: [u32; LANES],
    pub(super) fine_by: [u32; LANES],
    pub(super) fine_pair: [bool; LANES],
    pub(super) fine_u: [f32; LANES],
    /// Whether any lane of the current tiles is in a fine tile, reset as
    /// `arced` is.
    pub(super) fined: bool,
}

/// Values per lane of a segments tile: five per segment, `k` and `top`.
pub(super) const SEGMENT_LANE_VALUES: usize = 5 * SEGMENTS_PER_TILE + 2;

impl<'a> FieldLayer<'a> {
    /// The bend, arc and segments lanes' values (lanes of `kind`
    /// [`Lane::BEND`], [`Lane::ARC`] or [`Lane::SEGMENTS`]) from their
    /// records `first` and `second` (a segments lane's four records are
    /// read again from its entry, at `tile_row` and column `ci`), at
    /// lattice x `u` in their tiles; sets `bent` if any lane is a bend lane.
    #[cold]
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    pub(super) fn curved_lanes(
        &self,
        tile_row: usize,
        ci: [u32; LANES],
        kind: &[u32; LANES],
        first: &[&Record; LANES],
        second: &[&Record; LANES],
        u: f32x4,
        bent: &mut bool,
        bl: &mut BendLanes,
    ) {
        let u = u.to_array();
        for k in 0..LANES {
            let r = [first[k], second[k]];
            // The first bend (arc) lane of these tiles clears the others' flags.
            if kind[k] & Lane::ARC != 0 {
                Self::arc_lane(r, u[k], k, !bl.arced, bl);
                bl.arced = true;
            } else if kind[k] & Lane::SEGMENTS != 0 {
                let e = self
                    .entries
                    .get(tile_row + (ci[k] >> SHIFT) as usize)
                    .map_or(TILE_OUTSIDE, |b| u32::from_le_bytes(*b));
                // (`lane` checked the four records are there.)
                if let TileEntry::Segments(p) = TileEntry::of(e)
                    && let Some(r) = self.planes.get(p as usize..p as usize + 4)
                {
                    Self::segments_lane(r.as_flattened(), u[k], k, !bl.segged, bl);
                    bl.segged = true;
                }
            } else if kind[k] & Lane::FINE != 0 {
                let e = self
                    .entries
                    .get(tile_row + (ci[k] >> SHIFT) as usize)
                    .map_or(TILE_OUTSIDE, |b| u32::from_le_bytes(*b));
                // (`lane` checked its stored tiles are there.)
                if let TileEntry::Fine { first, fine, pair } = TileEntry::of(e) {
                    if !bl.fined {
                        bl.fine = [0; LANES];
                    }
                    (bl.fine[k], bl.fine_first[k], bl.fine_by[k], bl.fine_pair[k], bl.fine_u[k]) =
                        (-1, first, fine, pair, u[k]);
                    bl.fined = true;
                }
            } else if kind[k] & Lane::BEND != 0 {
                Self::bend_lane(r, u[k], k, !*bent, bl);
                *bent = true;
            }
        }
    }

    /// The bend lanes' codes at lattice y `wt` within the tile: one square
    /// root per row for four lanes. Out of line, so that rows without bend
    /// lanes keep their registers.
    #[inline(never)]
    pub(super) fn bend(b: &BendLanes, wt: f32) -> f32x4 {
        let [dx, vy, d1x, d1y, d2x, d2y, k, top] = b.v.map(f32x4::new);
        let dy = f32x4::splat(wt) - vy;
        let r = (dx * dx + dy * dy).sqrt();
        let ray = |ex: f32x4, ey: f32x4| {
            let ahead = (dx * ex + dy * ey).simd_ge(f32x4::ZERO);
            ahead.select((dx * ey - dy * ex).abs(), r)
        };
        top - k * ray(d1x, d1y).fast_min(ray(d2x, d2y))
    }

    /// Lane `k`'s bend values from its tile's two records `r` ((Vx, Vy,
    /// d1x, d1y), (d2x, d2y, k, top)), at lattice x `u` in the tile; the
    /// `first` bend lane of a tile change clears the other lanes' flags.
    #[cold]
    #[inline(never)]
    fn bend_lane(r: [&Record; 2], u: f32, k: usize, first: bool, bl: &mut BendLanes) {
        if first {
            bl.bend = [0; LANES];
        }
        let f = |i: usize| record_of(r[i / 4]).to_array()[i % 4];
        for (i, v) in bl.v.iter_mut().enumerate() {
            v[k] = f(i);
        }
        bl.v[0][k] = u - bl.v[0][k];
        bl.bend[k] = -1;
    }

    /// The arc lanes' codes at lattice y `wt` within the tile (format 4.1):
    /// `top − k · ||q − C| − R|`, one square root per row for four lanes,
    /// out of line as [`Self::bend`].
    #[inline(never)]
    pub(super) fn arc(b: &BendLanes, wt: f32) -> f32x4 {
        let [dx, cy, radius, k, top, p0, pgy] = b.c.map(f32x4::new);
        let wt = f32x4::splat(wt);
        let dy = wt - cy;
        let arc = top - k * ((dx * dx + dy * dy).sqrt() - radius).abs();
        // A cut arc's plane `(c + gx u') + gy w'` (format 4.3).
        arc.fast_min(p0 + pgy * wt)
    }

    /// Lane `k`'s arc values from its tile's two records `r` ((Cx, Cy, R,
    /// k), (top, c, gx, gy)), at lattice x `u` in the tile; the `first` arc
    /// lane of a tile change clears the other lanes' flags. A second record
    /// whose plane `(c, gx, gy)` is not all 0 is a cut arc (format 4.3):
    /// its plane's value at the column and its `gy` are kept; for an arc
    /// alone, `f32::MAX` and 0, which the lesser never picks.
    #[cold]
    #[inline(never)]
    fn arc_lane(r: [&Record; 2], u: f32, k: usize, first: bool, bl: &mut BendLanes) {
        if first {
            bl.arc = [0; LANES];
        }
        let [cx, cy, radius, kk] = record_of(r[0]).to_array();
        let [top, c, gx, gy] = record_of(r[1]).to_array();
        let cut = c != 0.0 || gx != 0.0 || gy != 0.0;
        let (p0, pgy) = if cut { (c + gx * u, gy) } else { (f32::MAX, 0.0) };
        for (v, x) in bl.c.iter_mut().zip([u - cx, cy, radius, kk, top, p0, pgy]) {
            v[k] = x;
        }
        bl.arc[k] = -1;
    }

    /// The segments lanes' codes at lattice y `wt` within the tile (format
    /// 4.2): `top − k · min_i dist(q, segment i)`, one square root per row
    /// for four lanes, out of line as [`Self::bend`].
    #[inline(never)]
    pub(super) fn segments(b: &BendLanes, wt: f32) -> f32x4 {
        let v = b.s.map(f32x4::new);
        let mut d2 = f32x4::splat(f32::MAX);
        for i in 0..SEGMENTS_PER_TILE {
            let [dx, ay, ex, ey, inv] = [v[5 * i], v[5 * i + 1], v[5 * i + 2], v[5 * i + 3], v[5 * i + 4]];
            let dy = f32x4::splat(wt) - ay;
            // The nearest point's place along the segment, clamped to it.
            let t = ((dx * ex + dy * ey) * inv).fast_max(f32x4::ZERO).fast_min(f32x4::ONE);
            let (px, py) = (dx - t * ex, dy - t * ey);
            d2 = d2.fast_min(px * px + py * py);
        }
        let [k, top] = [v[5 * SEGMENTS_PER_TILE], v[5 * SEGMENTS_PER_TILE + 1]];
        top - k * d2.sqrt()
    }

    /// The fine lanes' codes at lattice y `wt` within the tile (format
    /// 4.4): each lane's bilinear interpolation of the fine cell it lies
    /// in (the lesser of its two channels'), lane by lane (fine tiles are
    /// few), out of line as [`Self::bend`]. A stored tile past the layer's
    /// (which validation rules out) plays code 0.
    #[inline(never)]
    pub(super) fn fine(&self, b: &BendLanes, wt: f32) -> f32x4 {
        let mut out = [0.0f32; LANES];
        for (k, code) in out.iter_mut().enumerate() {
            if b.fine[k] == 0 {
                continue;
            }
            let fine = b.fine_by[k] as usize;
            let ((a, i, wx), (sb, j, wy)) = (fine_cell(b.fine_u[k], fine as u32), fine_cell(wt, fine as u32));
            let channel = |c: usize| {
                let slot = (b.fine_first[k] as usize).saturating_add((c * fine + sb) * fine + a);
                let tile = self.stored.get(slot)?;
                let s = |i: usize, j: usize| tile.get(j * TILE_SIDE + i).map_or(0.0, |&v| f32::from(v));
                let top = s(i, j) + (s(i + 1, j) - s(i, j)) * wx;
                let bot = s(i, j + 1) + (s(i + 1, j + 1) - s(i, j + 1)) * wx;
                Some(top + (bot - top) * wy)
            };
            let first = channel(0);
            *code = match (first, b.fine_pair[k]) {
                (Some(c), false) => c,
                (Some(c), true) => channel(1).map_or(0.0, |d| c.min(d)),
                (None, _) => 0.0,
            };
        }
        f32x4::new(out)
    }

    /// Lane `k`'s segments values from its tile's four records `r` (three
    /// segments (ax, ay, bx, by), then (k, top, 0, 0)), at lattice x `u` in
    /// the tile; the `first` segments lane of a tile change clears the other
    /// lanes' flags.
    #[cold]
    #[inline(never)]
    fn segments_lane(r: &[u8], u: f32, k: usize, first: bool, bl: &mut BendLanes) {
        if first {
            bl.seg = [0; LANES];
        }
        let f = |o: usize| r.get(o..o + 4).map_or(0.0, |b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        for i in 0..SEGMENTS_PER_TILE {
            let o = i * PLANE_RECORD_LEN;
            let (ax, ay, ex, ey) = (f(o), f(o + 4), f(o + 8) - f(o), f(o + 12) - f(o + 4));
            let len2 = ex * ex + ey * ey;
            // A segment shorter than a millionth of a cell plays as its first end.
            let inv = if len2 > 1e-12 { 1.0 / len2 } else { 0.0 };
            for (j, x) in [u - ax, ay, ex, ey, inv].into_iter().enumerate() {
                bl.s[5 * i + j][k] = x;
            }
        }
        let o = SEGMENTS_PER_TILE * PLANE_RECORD_LEN;
        bl.s[5 * SEGMENTS_PER_TILE][k] = f(o);
        bl.s[5 * SEGMENTS_PER_TILE + 1][k] = f(o + 4);
        bl.seg[k] = -1;
    }
}
