//! Distance layers: one style's shapes as a signed distance field in sparse
//! tiles (SPEC.md section 6.2), built from exact f64 polylines in page mm.
//!
//! This is a pure function of geometry: polylines and fill rules in, a
//! [`Field`] out, independent of usvg, so that any front end (the SVG scene
//! or the resolved [`Drawing`](crate::drawing::Drawing)) plugs into it.
//!
//! The signed distance `s` of a layer at a point (positive where the style
//! is felt) combines its parts:
//! - fills: `+D` inside the union of the fills, `−D` outside, `D` the
//!   distance to the nearest outline of any fill of the style (so a grating's
//!   regions of one style are one layer);
//! - a band (vibrating outlines): `w/2 − d`, `d` the distance to the nearest
//!   centre line of any shape of the style (so touching borders of one style
//!   merge into one border instead of adding up);
//! - cut bands (vibrating borders crossing a grating): `min(s, d_c − w_c/2)`;
//! - clip regions: `min(s, ±d_clip)`, signed like a fill;
//! - occluders (opaque fills painted above the layer's shapes): `min(s, ∓d_occ)`,
//!   signed like a fill of their union but negated, so a region is not felt
//!   where the drawing paints over it; `d_occ` is the distance to their
//!   union's outline (they are united as the fills are, up to
//!   2,048 of them), so that a side two of them share is no edge;
//! - the page: `min(s, distance inside the page)`, so nothing beyond the
//!   surface is felt or stored.
//!
//! Samples are clamped to `±cap` with `cap = soft/2 + 2h` (+ one step): the
//! distance is 1-Lipschitz, so in a cell with a clamped corner every point
//! lies at least `soft/2` from the edge, on the corner's side, and the
//! profile there is saturated whatever the interpolation gives.
//!
//! `build.rs` builds a layer tile by tile (the lattice, the segments'
//! buckets, each tile written as the kind that plays it, fine tiles, the
//! numbering); `inside.rs` sweeps the rows of lattice points for what they
//! are inside of.

use taxel_format::{DISTANCE_ZERO, TilePlane};

use crate::geometry::overlay;
use crate::geometry::{FillRule, Polyline};

/// The geometry of one layer (one style).
#[derive(Debug, Clone, Default)]
pub struct LayerGeometry<'a> {
    /// Filled shapes (a grating's regions), each with its fill rule; each
    /// shape's subpaths are closed implicitly, as SVG fills are.
    pub fills: Vec<(&'a [Polyline], FillRule)>,
    /// Centre lines of a vibrating band, and the band's width in mm.
    pub band: Option<(Vec<&'a [Polyline]>, f64)>,
    /// Vibrating bands `(centre lines, width mm)` cut out of the fills.
    pub cuts: Vec<(&'a [Polyline], f64)>,
    /// Clip regions: the layer is felt only inside every one of them.
    pub clips: Vec<(&'a [Polyline], FillRule)>,
    /// Occluders: opaque fills painted above the layer's shapes; the layer is
    /// not felt inside their union.
    pub occluders: Vec<(&'a [Polyline], FillRule)>,
}

/// How to sample a layer.
#[derive(Debug, Clone, Copy)]
pub struct FieldParams {
    /// Lattice pitch `h`, mm.
    pub pitch_mm: f64,
    /// Edge profile ramp, mm (0: hard).
    pub soft_mm: f64,
    /// The page (surface) rectangle `(x0, y0, x1, y1)` in mm.
    pub page: (f64, f64, f64, f64),
}

/// A built field: the tile lattice and its stored tiles (SPEC.md section 6.2).
#[derive(Debug, Clone, PartialEq)]
pub struct Field {
    /// Page position of lattice sample (0, 0).
    pub origin: (f64, f64),
    /// Tiles per row and rows of tiles.
    pub tile_cols: u32,
    /// Rows of tiles.
    pub tile_rows: u32,
    /// Distance of one sample code, mm.
    pub step_mm: f64,
    /// Tile index, row-major.
    pub tiles: Vec<u32>,
    /// Plane and ridge tiles' records, in index order.
    pub planes: Vec<TilePlane>,
    /// Stored tiles' samples.
    pub samples: Vec<u8>,
}

impl Field {
    /// Number of stored tiles.
    #[cfg(test)]
    pub fn stored(&self) -> usize {
        self.samples.len() / taxel_format::TILE_SAMPLES
    }
}

type Seg = ((f64, f64), (f64, f64));

fn closed_segments(pl: &Polyline) -> impl Iterator<Item = Seg> + '_ {
    let n = pl.points.len();
    (0..if n > 1 { n } else { 0 }).map(move |i| (pl.points[i], pl.points[(i + 1) % n]))
}

fn seg_bounds(s: &Seg) -> (f64, f64, f64, f64) {
    (s.0.0.min(s.1.0), s.0.1.min(s.1.1), s.0.0.max(s.1.0), s.0.1.max(s.1.1))
}

/// The span of tiles of a segment that acts on none (empty: `c0 > c1`).
const NO_TILES: [u16; 4] = [1, 0, 1, 0];

/// The tiles of a layer's lattice as its buckets count them: `cols` by
/// `rows` tiles of side `side` from `origin`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Tiles {
    pub origin: (f64, f64),
    pub side: f64,
    pub cols: usize,
    pub rows: usize,
}

impl Tiles {
    /// The tile index of coordinate `v` along an axis from `o` with `n`
    /// tiles, up to `n` (past the last): `floor` then not below 0, a
    /// truncation of what is above 0 (NaN and below give 0, +inf
    /// saturates), without the floor's work.
    fn index(&self, v: f64, o: f64, n: usize) -> usize {
        let x = (v - o) / self.side;
        (if x > 0.0 { x as usize } else { 0 }).min(n)
    }

    /// The span of tiles `[c0, c1, r0, r1]` (inclusive) that segment `s`'s
    /// bounds grown by `m` meet; `None` when they meet no tile.
    pub(super) fn span(&self, s: &Seg, m: f64) -> Option<[usize; 4]> {
        let (ox, oy) = self.origin;
        let b = seg_bounds(s);
        let (c0, c1) = (self.index(b.0 - m, ox, self.cols), self.index(b.2 + m, ox, self.cols));
        let (r0, r1) = (self.index(b.1 - m, oy, self.rows), self.index(b.3 + m, oy, self.rows));
        if b.2 + m < ox || b.3 + m < oy || c0 >= self.cols || r0 >= self.rows {
            return None;
        }
        Some([c0, c1.min(self.cols - 1), r0, r1.min(self.rows - 1)])
    }

    /// The columns `(c0, c1)` of tile row `r` (within `span`, the
    /// segment's [`span`](Self::span)) on which segment `s`, acting `m`
    /// around it, may act: those that the part of the segment within `m`
    /// of the row (in y) meets, grown by `m` (in x). Every point within `m`
    /// of the segment lies there (its nearest point of the segment is in
    /// that part), so a bucket holds every segment that acts on its tile;
    /// and a long slanted segment is held by the tiles along it, not by
    /// every tile of its bounds (a scribble's segments cross the whole
    /// drawing, and by their bounds every tile held every segment); nor
    /// by a tile at the lattice's side that its bounds meet only because
    /// whatever lies beyond the side counts as the side's tiles.
    pub(super) fn row_cols(&self, s: &Seg, m: f64, r: usize, [c0, c1, _, _]: [usize; 4]) -> (usize, usize) {
        let ((a, b), dy) = (*s, s.1.1 - s.0.1);
        // A level segment's part is the whole of it, its bounds.
        if dy == 0.0 || !dy.is_finite() {
            return (c0, c1);
        }
        let (ox, oy) = self.origin;
        // A thousandth of a tile for the rounding of the bounds, the
        // division and the products.
        let slack = 1e-3 * self.side;
        let (y0, y1) = (oy + r as f64 * self.side, oy + (r + 1) as f64 * self.side);
        let (ta, tb) = ((y0 - m - slack - a.1) / dy, (y1 + m + slack - a.1) / dy);
        let (lo, hi) = (ta.min(tb).max(0.0), ta.max(tb).min(1.0));
        // (NaN, or a part that rounding left empty, is taken whole.)
        if lo.partial_cmp(&hi).is_none_or(|o| o == std::cmp::Ordering::Greater) {
            return (c0, c1);
        }
        let (xa, xb) = (a.0 + lo * (b.0 - a.0), a.0 + hi * (b.0 - a.0));
        let lo_x = xa.min(xb) - m - slack;
        let hi_x = xa.max(xb) + m + slack;
        // Wholly before the lattice's first column (which `index` would
        // give it): on no tile, as wholly past its last.
        if hi_x < ox {
            return (1, 0);
        }
        (self.index(lo_x, ox, self.cols).max(c0), self.index(hi_x, ox, self.cols).min(c1))
    }
}

/// The segments acting on each tile of `tiles` (row-major): those whose
/// part within their reach of the tile's row meets the tile grown by the
/// reach ([`Tiles::row_cols`]), in segment order; and each segment's span
/// of tiles `[c0, c1, r0, r1]` by its bounds (inclusive; [`NO_TILES`] when
/// it acts on none), within which [`Tiles::row_cols`] gives its tiles.
///
/// The spans are kept in 16 bits (8 bytes a segment instead of 16, some
/// 20 MB for each layer being built on the map at the input limit, 2.7 M
/// segments a layer), so they are left out (empty) for a lattice of more
/// than 65,535 tiles along one side: their only reader, the layer's grid,
/// is never built for one (its cells are capped far below that).
fn buckets_of(segs: &[(Seg, Part, f64)], tiles: &Tiles) -> (Vec<Vec<u32>>, Vec<[u16; 4]>) {
    let (cols, rows) = (tiles.cols, tiles.rows);
    let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); cols * rows];
    let narrow = cols <= usize::from(u16::MAX) && rows <= usize::from(u16::MAX);
    let mut spans = Vec::with_capacity(if narrow { segs.len() } else { 0 });
    for (n, (s, _, m)) in segs.iter().enumerate() {
        let Some(span) = tiles.span(s, *m) else {
            if narrow {
                spans.push(NO_TILES);
            }
            continue;
        };
        for r in span[2]..=span[3] {
            let (c0, c1) = tiles.row_cols(s, *m, r, span);
            for c in c0..=c1 {
                buckets[r * cols + c].push(n as u32);
            }
        }
        // Below `cols` and `rows`, so they fit when the lattice is narrow.
        if narrow {
            spans.push(span.map(|v| v as u16));
        }
    }
    (buckets, spans)
}

/// Squared distance from `p` to the segment `a`-`b` (as
/// `crate::geometry::distance_to_segment`, without its square root).
fn distance2_to_segment(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    // The division only where the projection falls inside the segment: a
    // numerator at or below 0 (at or above `len2`) divides to a value the
    // clamp takes to 0 (1) anyway, since correctly rounded division is
    // monotone, so the result is the same to the bit and most samples of a
    // short segment skip the division's latency (an infinite numerator
    // still divides, as `inf / inf` is NaN).
    let num = (p.0 - a.0) * dx + (p.1 - a.1) * dy;
    let t = if len2 <= 0.0 || len2.is_nan() || num <= 0.0 {
        0.0
    } else if num >= len2 && num.is_finite() {
        1.0
    } else {
        (num / len2).clamp(0.0, 1.0)
    };
    let (ex, ey) = (a.0 + t * dx - p.0, a.1 + t * dy - p.1);
    ex * ex + ey * ey
}

/// Above this every `f64` is a whole number (2^52).
const WHOLE_FROM: f64 = 4_503_599_627_370_496.0;

/// `v.floor()`, equal to it (`==`) for every `v`, without the call into
/// libm that `f64::floor` is on a target without SSE4.1's rounding
/// instruction (the release build's): a layer's setup floors four bounds
/// of each of its segments, and each tile's search each of its bucket's,
/// some 1.5 million calls on the 1,000-region map. Only the sign of a zero
/// may differ (`-0.5` floors to `-1`, `-0.0` to `0.0`), which every caller
/// clamps or casts away.
fn floor_f64(v: f64) -> f64 {
    // Beyond 2^52 (and for infinities) `v` is whole; NaN fails the test and stays NaN.
    if v.abs() < WHOLE_FROM {
        let t = v as i64 as f64;
        if t > v { t - 1.0 } else { t }
    } else {
        v
    }
}

/// `v.ceil()`, as [`floor_f64`] is `v.floor()`.
fn ceil_f64(v: f64) -> f64 {
    if v.abs() < WHOLE_FROM {
        let t = v as i64 as f64;
        if t < v { t + 1.0 } else { t }
    } else {
        v
    }
}

/// Signed distance inside a rectangle (positive inside).
fn inside_rect(r: (f64, f64, f64, f64), p: (f64, f64)) -> f64 {
    let dx = (p.0 - r.0).min(r.2 - p.0);
    let dy = (p.1 - r.1).min(r.3 - p.1);
    if dx >= 0.0 && dy >= 0.0 {
        dx.min(dy)
    } else {
        let ox = (r.0 - p.0).max(p.0 - r.2).max(0.0);
        let oy = (r.1 - p.1).max(p.1 - r.3).max(0.0);
        -(ox.hypot(oy))
    }
}

/// One kind of segment, for the per-tile buckets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Part {
    /// A fill outline.
    Fill,
    /// The layer's band centre line.
    Band,
    /// A cut band of width group `k` (cuts of one width share a running minimum).
    Cut(usize),
    /// Clip region `k`.
    Clip(usize),
    /// An occluder's outline.
    Occluder,
}

/// Most crossings of a layer's fills for which their union is taken.
const UNION_MAX_CROSSINGS: usize = 100_000;

/// The union of a layer's fills as one outline, when two of them meet: the
/// distance is then measured to the union's boundary, not to a side that
/// two regions of the style share (which lies inside the union and would
/// play at half amplitude). `None` when no two fills' boxes meet (nothing to
/// unite) or the fills lie too far out for the union's integer units.
///
/// Fills whose boxes do not meet, directly or through others, share no
/// side and cross nowhere, so each such group is united on its own (in
/// parallel: a world map's continents and islands), and the union is the
/// groups' unions one after another, in the order of their first fills.
fn united_fills(fills: &[(&[Polyline], FillRule)]) -> Option<Vec<Polyline>> {
    use rayon::prelude::*;
    if fills.len() < 2 {
        return None;
    }
    let boxed: Vec<(&[Polyline], FillRule, crate::spatial::Bbox)> =
        fills.iter().filter_map(|&(pls, rule)| Some((pls, rule, crate::geometry::bounds(pls)?))).collect();
    let boxes: Vec<_> = boxed.iter().map(|f| f.2).collect();
    let groups = crate::spatial::meeting_groups(&boxes);
    if groups.iter().all(|g| g.len() < 2) {
        return None;
    }
    let all = boxes.iter().copied().reduce(|a, b| (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3)))?;
    let f = overlay::Frame::over(all)?;
    // An overlay's work follows the outlines' crossings: a map's regions
    // share sides and cross a few times, a scribble's fill crosses itself
    // by the million (16 GB). Past the budget (in any one group: no two
    // groups cross) the fills are kept as they are (a side two of them
    // share then plays as an edge).
    let tangled = groups.par_iter().filter(|g| g.len() > 1).any(|g| {
        let segments: Vec<Seg> = g.iter().flat_map(|&k| boxed[k].0.iter().flat_map(closed_segments)).collect();
        crate::geometry::crossings::crossings_exceed(&segments, UNION_MAX_CROSSINGS)
    });
    if tangled {
        return None;
    }
    let back = |p: &i_overlay::i_float::int::point::IntPoint| (f.ox + p.x as f64 * f.q, f.oy + p.y as f64 * f.q);
    let united: Vec<Vec<Polyline>> = groups
        .par_iter()
        .map(|g| {
            let each: Vec<_> = g.iter().flat_map(|&k| overlay::simple(boxed[k].0, boxed[k].1, f)).collect();
            let union = overlay::shapes_of(&each, i_overlay::core::fill_rule::FillRule::NonZero);
            union.iter().flatten().map(|c| Polyline { points: c.iter().map(back).collect(), closed: true }).collect()
        })
        .collect();
    Some(united.into_iter().flatten().collect())
}

/// The `max` entries of `items` with the least keys, nearest first, in the
/// order a stable sort by key would leave them (equal keys in the order
/// `items` gives them), so the fits see the same segments as after sorting
/// every entry; a tile's bucket holds hundreds of segments and the fits want
/// a few, so each entry is only compared with the last one kept.
fn nearest_first<T>(items: impl Iterator<Item = (f64, T)>, max: usize) -> Vec<(f64, T)> {
    let mut kept: Vec<(f64, T)> = Vec::with_capacity(max + 1);
    for entry in items {
        keep_nearest(&mut kept, entry, max);
    }
    kept
}

/// One step of [`nearest_first`]: `entry` into `kept` (at most `max`
/// entries, least keys first) if its key is below the last kept one's or
/// fewer than `max` are kept.
#[inline]
fn keep_nearest<T>(kept: &mut Vec<(f64, T)>, (key, item): (f64, T), max: usize) {
    if kept.len() == max && kept.last().is_none_or(|l| key.total_cmp(&l.0).is_ge()) {
        return;
    }
    // After every kept entry whose key is not greater: a stable sort's place.
    let at = kept.partition_point(|k| k.0.total_cmp(&key).is_le());
    kept.insert(at, (key, item));
    kept.truncate(max);
}

/// The index and squared distance of the first of `near`'s segments nearest
/// `p`: what scanning all of them and keeping each strictly nearer one
/// (by `total_cmp`) finds. `near` holds segments with their squared
/// distances to `middle`, nearest first, as [`nearest_first`] leaves them.
///
/// The scan stops at the first segment whose distance to `middle`, less
/// `|p − middle|`, exceeds the best distance so far (by more than a margin
/// far above the rounding of either): by the triangle inequality it and
/// every later one (not nearer `middle`) lies farther from `p` than the
/// best, so none of them would be kept. The writers ask this at each of a
/// tile's points over the 24 to 48 segments nearest its middle, most of
/// which lie beyond the tile.
///
/// `least`, when given, is the least squared distance from `p` to a set of
/// segments that holds all of `near`, as [`distance2_to_segment`] gives it
/// (what the samples' search measured there): no segment of `near` is then
/// nearer, so the scan also stops at the first segment that distance away.
fn nearest_of(near: &[(f64, Seg)], middle: (f64, f64), p: (f64, f64), least: Option<f64>) -> Option<(usize, f64)> {
    let r = (p.0 - middle.0).hypot(p.1 - middle.1);
    // Distances are some millimetres, their rounding some 1e-16 of the
    // coordinates: a nanometre is far above it, and far below any gap that
    // decides which segment is nearest.
    let slack = 1e-9 * (1.0 + p.0.abs() + p.1.abs() + middle.0.abs() + middle.1.abs());
    let mut best: Option<(usize, f64)> = None;
    for (k, &(key, (a, b))) in near.iter().enumerate() {
        if let Some((_, d)) = best
            && key.sqrt() - r > d.sqrt() + slack * (1.0 + key.sqrt())
        {
            break;
        }
        let d = distance2_to_segment(p, a, b);
        if best.is_none_or(|(_, m)| d.total_cmp(&m).is_lt()) {
            best = Some((k, d));
            // None later is strictly nearer, so none would replace it.
            if least.is_some_and(|l| d.total_cmp(&l).is_le()) {
                break;
            }
        }
    }
    best
}

/// The lowest code played at full amplitude and the highest played at zero
/// under the edge profile `clamp(½ + (code − 128) step / ramp, 0, 1)`, each
/// with a margin of a hundredth of a code for the player's rounding.
fn saturated_codes(soft: f64, step: f64) -> (u8, u8) {
    let half = 0.5 * taxel_format::edge_ramp(soft as f32, step as f32) as f64 / step;
    let zero = DISTANCE_ZERO as f64;
    let full = (zero + half + 0.01).ceil().clamp(zero + 1.0, 255.0);
    let none = (zero - half - 0.01).floor().clamp(0.0, zero - 1.0);
    (full as u8, none as u8)
}

mod arcs;
mod bends;
mod build;
mod cut_arcs;
mod exact;
mod fine;
mod hiding;
mod inside;
mod junctions;
mod layer_grid;
mod near;
mod planes;
mod sanity;
pub use build::{build_field, build_field_within};
pub use exact::{ExactRegion, ON_EDGE_MM, Segment};
use inside::{FineRows, fill_bits};
pub use sanity::sanity_check;
#[cfg(test)]
pub(crate) mod tests;
