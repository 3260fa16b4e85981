//! Plane and ridge tiles (SPEC.md section 6.2, format 3.0): a tile that one
//! straight edge crosses holds an affine signed distance, and a tile that
//! one straight band centre line crosses a ridge `top − |affine|`; either is
//! one 16-byte record instead of 81 samples, and plays the function at the
//! point itself, with no bilinear interpolation.
//!
//! The writer fits the function to the tile's unquantised samples (least
//! squares, so that exact affine data gives the exact plane) and keeps it
//! only if, rounded to the record's `f32`s, it is within half a code of the
//! exact distance at all 81 samples and at the 64 cell centres, wherever that
//! distance is within the clamp (and saturated on the same side where it is
//! not). A sampled tile is within half a code at its samples only, so a
//! plane tile is never worse than the stored tile it replaces there.

use taxel_format::{
    DISTANCE_ZERO, MAX_PLANE_CODE, MAX_PLANE_GRADIENT, TILE_CELLS, TILE_PLANE, TILE_RIDGE, TILE_SAMPLES, TILE_SIDE,
    TilePlane,
};

use super::near::{InLayer, Near, TileBits};
use super::{LayerGeometry, Part, Seg};

/// Largest error of a plane or ridge tile against the exact distance, codes.
pub(super) const TOLERANCE: f64 = 0.5;
/// The clamp, in codes (the writer clamps distances to ±127 steps).
const CAP: f64 = 127.0;

/// The unbiased codes from which on the edge profile is saturated: at or
/// above `hi` a code plays full amplitude, at or below `lo` none (the
/// `full` and `none` of `saturated_codes`, less the bias).
#[derive(Debug, Clone, Copy)]
pub(super) struct Saturation {
    pub hi: f64,
    pub lo: f64,
    /// Within this many codes of the edge a code must be within the
    /// tolerance even where saturated: the profile's half ramp plus one
    /// lattice pitch (the writer's orderings and junction tests use it too).
    pub near: f64,
    /// Within this many codes of the edge, by the exact code or by the
    /// played one, [`Saturation::close`] asks for the tolerance: the
    /// profile's half ramp plus half a lattice pitch and one code, so that
    /// every point where either profile is not saturated lies within half a
    /// pitch of a checked point (a lattice point or a cell centre) that
    /// pins both. Not [`Saturation::near`] by the exact code alone: the
    /// layer's distance where parts combine (a grating less the band cut out
    /// of it) is a bound, short of the true distance a plane plays, a pitch
    /// from the edge (the experiment-5 icons' gratings were stored for it).
    pub pin: f64,
}

impl Saturation {
    /// Whether the code `v` (unbiased) plays as the exact distance `e`
    /// (codes, clamped to ±[`CAP`]): within [`TOLERANCE`], or, both farther
    /// than `pin` from the edge, both saturated on the same side, where the
    /// amplitude is the same whatever the code.
    pub(super) fn close(&self, v: f64, e: f64) -> bool {
        (v - e).abs() <= TOLERANCE
            || e.abs().min(v.abs()) > self.pin && ((e >= self.hi && v >= self.hi) || (e <= self.lo && v <= self.lo))
    }
}

/// The windows (largest |code| of the samples fitted) tried in turn: all
/// unclamped samples, then those within about one and a half cells of the
/// edge, so that a tile where a second feature bends the distance only in
/// the saturated part still fits its edge's plane.
const WINDOWS: [f64; 3] = [CAP, 96.0, 48.0];

/// The plane or ridge that plays a tile's samples (`exact`, unquantised
/// codes clamped to ±127, row-major 9 x 9) within half a code, or saturated
/// on the same side where they are, as its tile index kind and record;
/// `ridge_top` is a vibration layer's half band width in codes (the ridge's
/// top), `None` for a grating.
pub(super) fn fit(
    exact: &[f64; TILE_SAMPLES],
    ridge_top: Option<f64>,
    sat: Saturation,
    lines: &[Line],
) -> Vec<(u32, TilePlane)> {
    let at = |t: usize| ((t % TILE_SIDE) as f64, (t / TILE_SIDE) as f64);
    let plays = |kind: u32, rec: &TilePlane| {
        exact.iter().enumerate().all(|(t, &e)| {
            let (u, w) = at(t);
            sat.close(rec.code(kind, u, w) - DISTANCE_ZERO as f64, e)
        })
    };
    let mut found = Vec::new();
    // From the geometry: the lines of the segments nearest the edge.
    for l in lines {
        for s in [1.0, -1.0] {
            let rec = match l.top {
                None => {
                    record(DISTANCE_ZERO as f64 + s * l.c - l.off, s * l.gx, s * l.gy, 0.0).map(|r| (TILE_PLANE, r))
                }
                Some(top) if s > 0.0 => record(l.c, l.gx, l.gy, top + DISTANCE_ZERO as f64).map(|r| (TILE_RIDGE, r)),
                Some(_) => None,
            };
            if let Some((kind, rec)) = rec.filter(|(k, r)| plays(*k, r)) {
                found.push((kind, rec));
            }
        }
    }
    for window in WINDOWS {
        let open = |e: f64| e.abs() < window;
        // A plane: least squares in (1, u, w) over the samples in the window.
        let mut ls = LeastSquares::<3>::default();
        for (t, &e) in exact.iter().enumerate().filter(|(_, e)| open(**e)) {
            let (u, w) = at(t);
            ls.add([1.0, u, w], e);
        }
        if let Some([c, gx, gy]) = ls.solve() {
            let rec = record(c + DISTANCE_ZERO as f64, gx, gy, 0.0);
            if let Some(rec) = rec.filter(|r| plays(TILE_PLANE, r)) {
                found.push((TILE_PLANE, rec));
                return found;
            }
        }
        // A ridge: the squared distance to the centre line,
        // `(c + gx u + gy w)²` = `(top − e)²`, is a quadratic in (u, w) whose
        // coefficients give the line.
        let Some(top) = ridge_top else { continue };
        let mut ls = LeastSquares::<6>::default();
        for (t, &e) in exact.iter().enumerate().filter(|(_, e)| open(**e)) {
            let (u, w) = at(t);
            let m = top - e;
            ls.add([u * u, u * w, w * w, u, w, 1.0], m * m);
        }
        let Some([a, b, cc, d, e, _]) = ls.solve() else { continue };
        let gx = a.max(0.0).sqrt();
        let gy = cc.max(0.0).sqrt() * if b < 0.0 { -1.0 } else { 1.0 };
        let g2 = gx * gx + gy * gy;
        if g2 <= 0.0 {
            continue;
        }
        let c = (d * gx + e * gy) / (2.0 * g2);
        if let Some(rec) = record(c, gx, gy, top + DISTANCE_ZERO as f64).filter(|r| plays(TILE_RIDGE, r)) {
            found.push((TILE_RIDGE, rec));
            return found;
        }
    }
    found
}

/// A segment's line over a tile, in codes: the signed distance to it is
/// `c + gx u + gy w` at lattice coordinates `(u, w)` in the tile; a fill's
/// edge plays it less `off` (a cut band's half width), a band's centre line
/// as the ridge `top − |…|`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Line {
    c: f64,
    gx: f64,
    gy: f64,
    off: f64,
    top: Option<f64>,
}

/// The lines of the segments nearest the tile's sample nearest its edge
/// (and, for a band, nearest its sample on the ridge), at most a few.
pub(super) fn nearest_lines(t: &TileCtx<'_, '_>, exact: &[f64; TILE_SAMPLES]) -> Vec<Line> {
    let mut out = Vec::new();
    let pick = |key: &dyn Fn(f64) -> f64| (0..TILE_SAMPLES).min_by(|&a, &b| key(exact[a]).total_cmp(&key(exact[b])));
    let mut probes = vec![pick(&|e: f64| e.abs())];
    if t.g.band.is_some() {
        let top = w_half(t);
        probes.push(pick(&|e: f64| (e - top).abs()));
    }
    for probe in probes.into_iter().flatten() {
        let (i, j) = (probe % TILE_SIDE, probe / TILE_SIDE);
        let p = (t.corner.0 + i as f64 * t.h, t.corner.1 + j as f64 * t.h);
        let sub = super::layer_grid::SUB as isize;
        let near = t.in_grid(None, p, (i as isize * sub, j as isize * sub), 2).unwrap_or_else(|| {
            super::nearest_first(
                t.bucket.iter().filter_map(|&n| {
                    t.segs.get(n as usize).map(|((a, b), _, _)| (super::distance2_to_segment(p, *a, *b), n))
                }),
                2,
            )
        });
        for &(_, n) in &near {
            let Some(&((a, b), part, _)) = t.segs.get(n as usize) else { continue };
            let len = (b.0 - a.0).hypot(b.1 - a.1);
            if len.is_nan() || len <= 0.0 {
                continue;
            }
            // The unit normal, and the signed distance at the tile's corner.
            let (nx, ny) = ((a.1 - b.1) / len, (b.0 - a.0) / len);
            let k = t.h / t.step;
            let c = (nx * (t.corner.0 - a.0) + ny * (t.corner.1 - a.1)) / t.step;
            let (off, top) = match part {
                // `kc` is the cut's width group, not its place among the cuts.
                Part::Cut(kc) => (t.cut_widths().get(kc).map_or(0.0, |w| w / 2.0 / t.step), None),
                Part::Band => (0.0, Some(w_half(t))),
                _ => (0.0, None),
            };
            out.push(Line { c, gx: nx * k, gy: ny * k, off, top });
            if let Part::Band = part {
                // A band's edge alone (the other side clamped): a plane.
                out.push(Line { c, gx: nx * k, gy: ny * k, off: -w_half(t), top: None });
            }
        }
    }
    out
}

/// A band layer's half width in codes (0 without a band).
fn w_half(t: &TileCtx<'_, '_>) -> f64 {
    t.g.band.as_ref().map_or(0.0, |(_, w)| w / 2.0 / t.step)
}

/// A record in `f32`, if its values are within the format's bounds.
pub(super) fn record(c: f64, gx: f64, gy: f64, top: f64) -> Option<TilePlane> {
    let ok = |v: f64, m: f32| v.is_finite() && v.abs() <= m as f64;
    (ok(c, MAX_PLANE_CODE) && ok(top, MAX_PLANE_CODE) && ok(gx, MAX_PLANE_GRADIENT) && ok(gy, MAX_PLANE_GRADIENT))
        .then_some(TilePlane { c: c as f32, gx: gx as f32, gy: gy as f32, top: top as f32 })
}

/// Normal equations of a linear least-squares fit in `N` unknowns.
pub(super) struct LeastSquares<const N: usize> {
    a: [[f64; N]; N],
    b: [f64; N],
    n: usize,
}

impl<const N: usize> Default for LeastSquares<N> {
    fn default() -> Self {
        LeastSquares { a: [[0.0; N]; N], b: [0.0; N], n: 0 }
    }
}

impl<const N: usize> LeastSquares<N> {
    pub(super) fn add(&mut self, x: [f64; N], y: f64) {
        for i in 0..N {
            for j in 0..N {
                self.a[i][j] += x[i] * x[j];
            }
            self.b[i] += x[i] * y;
        }
        self.n += 1;
    }

    /// The solution, by Gaussian elimination with partial pivoting; `None`
    /// when the samples do not determine it.
    pub(super) fn solve(&self) -> Option<[f64; N]> {
        if self.n < N {
            return None;
        }
        let (mut a, mut b) = (self.a, self.b);
        let scale = a.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        for col in 0..N {
            let piv = (col..N).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
            // A pivot that is no pivot (also a NaN one): undetermined.
            if a[piv][col].abs().partial_cmp(&(1e-12 * scale)) != Some(std::cmp::Ordering::Greater) {
                return None;
            }
            a.swap(col, piv);
            b.swap(col, piv);
            let (pivot_row, pivot_b) = (a[col], b[col]);
            for (row, rb) in a.iter_mut().zip(b.iter_mut()).skip(col + 1) {
                let f = row[col] / pivot_row[col];
                for (v, p) in row.iter_mut().zip(&pivot_row).skip(col) {
                    *v -= f * p;
                }
                *rb -= f * pivot_b;
            }
        }
        let mut x = [0.0; N];
        for row in (0..N).rev() {
            let s: f64 = (row + 1..N).map(|k| a[row][k] * x[k]).sum();
            x[row] = (b[row] - s) / a[row][row];
        }
        x.iter().all(|v| v.is_finite()).then_some(x)
    }
}

/// One tile of a layer being built: what measuring its cell centres needs.
pub(super) struct TileCtx<'a, 'g> {
    pub g: &'a LayerGeometry<'g>,
    pub segs: &'a [(Seg, Part, f64)],
    pub bucket: &'a [u32],
    /// Page position of the tile's first lattice point.
    pub corner: (f64, f64),
    pub h: f64,
    pub margin: f64,
    pub page: (f64, f64, f64, f64),
    /// The clamp in codes, and in mm (exactly the samples'), and mm per code.
    pub cap: f64,
    pub cap_mm: f64,
    pub step: f64,
    pub sat: Saturation,
    /// Index of the tile's first cell centre in `centre_bits`, and centres per row.
    pub first: usize,
    pub nx: usize,
    pub centre_bits: &'a CentreBits,
    /// The tile's row of tiles, and the layer's shapes by row of tiles for
    /// fine tiles' inside bits, built by `rows_of` when first asked.
    pub row: usize,
    pub fine_rows: &'a std::sync::OnceLock<super::FineRows>,
    pub rows_of: &'a (dyn Fn() -> super::FineRows + Sync),
    /// The tile in its layer's grid, for the cell centres' search (one
    /// grid cell on from the samples').
    pub layer: Option<InLayer<'a>>,
    /// The segments nearest the tile's middle, by part, found once for all
    /// the writers that ask ([`TileCtx::nearest`]).
    pub nearest: NearestSegments,
    /// The nearest-segment measure of the tile's samples
    /// ([`Near::least`] there).
    pub measured: &'a Near,
    /// [`edge_first`] of the tile's samples, once a writer asks.
    pub order: std::cell::OnceCell<[u8; TILE_SAMPLES]>,
    /// The exact distance at the 64 cell centres (codes, clamped), measured
    /// when a writer first checks a candidate there and shared by the rest.
    pub centre_codes: std::cell::OnceCell<[f64; TILE_CELLS * TILE_CELLS]>,
}

/// Most segments of one part kept nearest a tile's middle: as many as the
/// writer that wants the most (the circles' and cut arcs' 48) asks for.
pub(super) const NEAREST_KEPT: usize = 48;

/// The segments of each part that a tile's writers asked for, nearest its
/// middle first, as [`nearest_first`](super::nearest_first) keeps them (at
/// most [`NEAREST_KEPT`]), each part's found once.
///
/// Before, each writer tried on a tile that would otherwise be stored
/// (corners, circles, segments tiles, cut arcs) measured every segment of
/// the tile's bucket (hundreds) again to find its few nearest; and
/// `nearest_first`'s `max` entries are the first `max` of a stable sort by
/// the key, so the first `max` of one list of [`NEAREST_KEPT`] are what a
/// writer asking for `max <= NEAREST_KEPT` would have found itself.
#[derive(Default)]
pub(super) struct NearestSegments {
    lists: std::cell::RefCell<Vec<(Part, SharedList)>>,
}

/// One part's segments nearest a tile's middle, with their squared distances.
type SharedList = std::rc::Rc<[(f64, Seg)]>;

/// The first entries of a shared list of nearest segments.
pub(super) struct Nearest {
    list: SharedList,
    len: usize,
}

impl std::ops::Deref for Nearest {
    type Target = [(f64, Seg)];

    fn deref(&self) -> &Self::Target {
        &self.list[..self.len]
    }
}

/// The tile's sample indices in the order the writers check a candidate
/// at them: those whose exact code is within two codes of the edge first,
/// then those within `near` (where a code must be within the tolerance even
/// if saturated), then the rest, each in index order. A wrong candidate
/// misses most often near the edge, and a check over all 81 samples (an
/// `all`, whose outcome does not depend on the order) stops at the first
/// miss; three passes, not a sort, which would cost more than it saves.
pub(super) fn edge_first(exact: &[f64; TILE_SAMPLES], near: f64) -> [u8; TILE_SAMPLES] {
    let mut order = [0u8; TILE_SAMPLES];
    let mut n = 0;
    let class = |e: f64| {
        if e.abs() <= 2.0 {
            0
        } else if e.abs() <= near {
            1
        } else {
            2
        }
    };
    for pass in 0..3 {
        for (i, &e) in exact.iter().enumerate() {
            if class(e) == pass {
                order[n] = i as u8;
                n += 1;
            }
        }
    }
    // Every sample is in exactly one class (a NaN code in the last).
    debug_assert_eq!(n, TILE_SAMPLES);
    order
}

impl TileCtx<'_, '_> {
    /// The distinct widths of a grating's cut bands, in the order of their
    /// groups ([`Part::Cut`]: the first band of each width names its group).
    pub(super) fn cut_widths(&self) -> Vec<f64> {
        let mut widths: Vec<f64> = Vec::new();
        for (_, w) in &self.g.cuts {
            if !widths.iter().any(|v| v.to_bits() == w.to_bits()) {
                widths.push(*w);
            }
        }
        widths
    }

    /// The order in which the writers check a candidate at the tile's
    /// samples ([`edge_first`]); `exact` must be the tile's exact codes.
    pub(super) fn order(&self, exact: &[f64; TILE_SAMPLES]) -> &[u8; TILE_SAMPLES] {
        self.order.get_or_init(|| edge_first(exact, self.sat.near))
    }

    /// The tile's middle, page mm (the fourth lattice point along each side).
    pub(super) fn middle(&self) -> (f64, f64) {
        let half = TILE_CELLS as f64 * self.h / 2.0;
        (self.corner.0 + half, self.corner.1 + half)
    }

    /// The `part` segments of the tile's bucket nearest its middle, with
    /// their squared distances to it, nearest first (ties in bucket order),
    /// at most `max`: `nearest_first` over the bucket, shared by the writers.
    pub(super) fn nearest(&self, part: Part, max: usize) -> Nearest {
        if max > NEAREST_KEPT {
            let list: SharedList = self.nearest_uncached(part, max).into();
            return Nearest { len: list.len(), list };
        }
        let found = self.nearest.lists.borrow().iter().find(|(p, _)| *p == part).map(|(_, l)| l.clone());
        let list = found.unwrap_or_else(|| {
            let list: SharedList = self.nearest_uncached(part, NEAREST_KEPT).into();
            self.nearest.lists.borrow_mut().push((part, list.clone()));
            list
        });
        Nearest { len: list.len().min(max), list }
    }

    /// [`TileCtx::nearest`] without the shared lists.
    pub(super) fn nearest_uncached(&self, part: Part, max: usize) -> Vec<(f64, Seg)> {
        let middle = self.middle();
        let half = (super::layer_grid::SUB * TILE_CELLS / 2) as isize;
        if let Some(found) = self.in_grid(Some(part), middle, (half, half), max) {
            return found
                .into_iter()
                .filter_map(|(d, n)| self.segs.get(n as usize).map(|&(seg, _, _)| (d, seg)))
                .collect();
        }
        self.nearest_scanned(part, max)
    }

    /// [`TileCtx::nearest_uncached`] by measuring every entry of the bucket.
    pub(super) fn nearest_scanned(&self, part: Part, max: usize) -> Vec<(f64, Seg)> {
        let middle = self.middle();
        super::nearest_first(
            self.bucket.iter().filter_map(|&n| match self.segs.get(n as usize) {
                Some(&((a, b), p, _)) if p == part => Some((super::distance2_to_segment(middle, a, b), (a, b))),
                _ => None,
            }),
            max,
        )
    }
}

impl TileCtx<'_, '_> {
    /// What `nearest_first` keeps of the bucket's `part` segments (all
    /// parts for `None`) by squared distance to `p`, at most `max`, as
    /// (squared distance, segment number), found
    /// in the layer's grid ([`LayerGrid::nearest_to`](super::layer_grid::LayerGrid::nearest_to)):
    /// `p` lies at grid cell corner `xy` of the tile (half a lattice pitch
    /// a cell). `None` where the tile's bucket holds too few of the groups
    /// searched for a search to pay, or the layer has no grid of them.
    pub(super) fn in_grid(
        &self,
        part: Option<Part>,
        p: (f64, f64),
        xy: (isize, isize),
        max: usize,
    ) -> Option<Vec<(f64, u32)>> {
        let at = self.layer?;
        let grid = at.grid;
        let slot = match part {
            Some(part) => Some(super::near::slot_in_layer(part, grid.reach.len(), self.g.clips.len())?),
            None => None,
        };
        let stats = grid.tile(at.tile);
        let groups = match slot {
            Some(s) => {
                let own = super::layer_grid::is_own(s);
                [own, !own]
            }
            None => [stats.own > 0, stats.rest > 0],
        };
        let count = if groups[0] { stats.own } else { 0 } + if groups[1] { stats.rest } else { 0 };
        if (count as usize) < super::near::GRID_FROM {
            return None;
        }
        let xy = grid.corner(at.tile, xy);
        grid.nearest_to(self.segs, (at.tile, xy, p), groups, |s| slot.is_none_or(|w| w == s), max)
    }
}

/// Inside-the-fills, inside-the-occluders and inside-each-clip bits at
/// every cell centre of a layer's lattice (row-major, as the lattice points).
pub(super) struct CentreBits {
    pub inside: Vec<bool>,
    pub occluded: Vec<bool>,
    pub clips: Vec<Vec<bool>>,
}

impl TileCtx<'_, '_> {
    /// Whether plane record `rec` (tile index kind `kind`) plays the exact
    /// distance within half a code (or saturated on the exact side) at the
    /// tile's 64 cell centres; `centres` is scratch.
    pub(super) fn centres_fit(&self, centres: &mut Near, kind: u32, rec: &TilePlane) -> bool {
        self.centres_all(centres, |u, w, e| self.sat.close(rec.code(kind, u, w) - DISTANCE_ZERO as f64, e))
    }

    /// Whether `ok(u, w, e)` holds at each of the tile's 64 cell centres,
    /// `(u, w)` its lattice coordinates in the tile and `e` the exact
    /// distance there in codes (clamped); `centres` is scratch.
    pub(super) fn centres_all(&self, centres: &mut Near, ok: impl Fn(f64, f64, f64) -> bool) -> bool {
        let codes = self.centre_codes.get_or_init(|| self.measure_centres(centres));
        codes.iter().enumerate().all(|(k, &e)| ok((k % TILE_CELLS) as f64 + 0.5, (k / TILE_CELLS) as f64 + 0.5, e))
    }

    /// The exact distance at the tile's 64 cell centres, row-major, in codes
    /// (clamped); `centres` is scratch.
    fn measure_centres(&self, centres: &mut Near) -> [f64; TILE_CELLS * TILE_CELLS] {
        let h = self.h;
        let corner = (self.corner.0 + h / 2.0, self.corner.1 + h / 2.0);
        // What each centre is inside of, at the sample of the shifted
        // lattice it sits on: the parts that only lower the distance are
        // measured only where they can change its clamp, as at the samples.
        let clips = &self.centre_bits.clips;
        let (mut inside, mut occluded) = ([false; TILE_SAMPLES], [false; TILE_SAMPLES]);
        let mut in_clip = vec![false; clips.len() * TILE_SAMPLES];
        for j in 0..TILE_CELLS {
            for i in 0..TILE_CELLS {
                let (t, k) = (j * TILE_SIDE + i, self.first + j * self.nx + i);
                let bit = |bits: &[bool]| bits.get(k).copied().unwrap_or(false);
                (inside[t], occluded[t]) = (bit(&self.centre_bits.inside), bit(&self.centre_bits.occluded));
                for (q, b) in clips.iter().enumerate() {
                    if let Some(v) = in_clip.get_mut(q * TILE_SAMPLES + t) {
                        *v = bit(b);
                    }
                }
            }
        }
        let bits = TileBits { inside: &inside, occluded: &occluded, in_clip: &in_clip, cap: self.cap_mm };
        centres.measure_live(self.g, self.segs, self.bucket, (corner, h, self.margin), &bits, self.layer, true);
        let mut clipped = vec![false; clips.len()];
        let mut out = [0.0; TILE_CELLS * TILE_CELLS];
        for j in 0..TILE_CELLS {
            for i in 0..TILE_CELLS {
                let t = j * TILE_SIDE + i;
                for (q, slot) in clipped.iter_mut().enumerate() {
                    *slot = in_clip.get(q * TILE_SAMPLES + t).copied().unwrap_or(false);
                }
                let p = (self.corner.0 + (i as f64 + 0.5) * h, self.corner.1 + (j as f64 + 0.5) * h);
                let s = centres.signed(self.g, t, (inside[t], occluded[t]), &clipped, p, self.page);
                if let Some(slot) = out.get_mut(j * TILE_CELLS + i) {
                    *slot = (s / self.step).clamp(-self.cap, self.cap);
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAT: Saturation = Saturation { hi: 1.0, lo: -1.0, near: 64.0, pin: 64.0 };

    fn samples(f: impl Fn(f64, f64) -> f64) -> [f64; TILE_SAMPLES] {
        std::array::from_fn(|t| f((t % TILE_SIDE) as f64, (t / TILE_SIDE) as f64).clamp(-CAP, CAP))
    }

    #[test]
    fn an_affine_tile_fits_a_plane_exactly() {
        let f = |u: f64, w: f64| 3.0 + 12.5 * u - 7.25 * w;
        let (kind, rec) = fit(&samples(f), None, SAT, &[]).into_iter().next().expect("a plane");
        assert_eq!(kind, TILE_PLANE);
        for (u, w) in [(0.0, 0.0), (3.5, 2.25), (8.0, 8.0)] {
            assert!((rec.code(kind, u, w) - 128.0 - f(u, w)).abs() < 1e-3);
        }
    }

    #[test]
    fn a_band_across_a_tile_fits_a_ridge() {
        // Distance 30 codes per cell; the line through (4, 0) and (6, 8).
        let (nx, ny) = (8.0 / 68f64.sqrt(), -2.0 / 68f64.sqrt());
        let f = |u: f64, w: f64| 90.0 - 30.0 * (nx * (u - 4.0) + ny * w).abs();
        let (kind, rec) = fit(&samples(f), Some(90.0), SAT, &[]).into_iter().next().expect("a ridge");
        assert_eq!(kind, TILE_RIDGE);
        for (u, w) in [(0.0, 0.0), (4.5, 1.5), (5.0, 4.0), (8.0, 8.0)] {
            assert!((rec.code(kind, u, w) - 128.0 - f(u, w).clamp(-CAP, CAP)).abs() < 1e-2 || f(u, w) < -CAP);
        }
        // Without a band the same samples are no plane.
        assert_eq!(fit(&samples(f), None, SAT, &[]), vec![]);
    }

    #[test]
    fn a_corner_is_no_plane() {
        // Inside a square corner the distance is the min of two planes.
        let f = |u: f64, w: f64| 10.0 * (u - 4.0).min(w - 4.0);
        assert_eq!(fit(&samples(f), None, SAT, &[]), vec![]);
    }
}
