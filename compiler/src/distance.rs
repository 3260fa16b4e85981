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
//!   where the drawing paints over it;
//! - the page: `min(s, distance inside the page)`, so nothing beyond the
//!   surface is felt or stored.
//!
//! Samples are clamped to `±cap` with `cap = soft/2 + 2h` (+ one step): the
//! distance is 1-Lipschitz, so in a cell with a clamped corner every point
//! lies at least `soft/2` from the edge, on the corner's side, and the
//! profile there is saturated whatever the interpolation gives.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use taxel_format::{
    DISTANCE_ZERO, TILE_CELLS, TILE_FIRST_STORED, TILE_INSIDE, TILE_OUTSIDE, TILE_SAMPLES, TILE_SIDE, TilePlane,
};

use crate::budget::{MemoryBudget, OverBudget};
#[cfg(test)]
use crate::geometry::distance_to_segment;
use crate::geometry::overlay;
use crate::geometry::{FillRule, Polyline};
use near::Near;

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
        self.samples.len() / TILE_SAMPLES
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

/// The exact signed distance of a layer at `p`, in f64, before clamping:
/// the reference the tests measure fields against.
#[cfg(test)]
pub fn exact_signed_distance(g: &LayerGeometry<'_>, page: (f64, f64, f64, f64), p: (f64, f64)) -> f64 {
    let mut s = f64::NEG_INFINITY;
    if !g.fills.is_empty() {
        let d = g
            .fills
            .iter()
            .flat_map(|(pls, _)| pls.iter().flat_map(closed_segments))
            .map(|(a, b)| distance_to_segment(p, a, b))
            .fold(f64::INFINITY, f64::min);
        let inside = g.fills.iter().any(|(pls, rule)| crate::geometry::contains(pls, p, *rule));
        s = if inside { d } else { -d };
    }
    if let Some((lines, w)) = &g.band {
        let d = lines
            .iter()
            .flat_map(|pls| pls.iter().flat_map(|pl| pl.segments()))
            .map(|(a, b)| distance_to_segment(p, a, b))
            .fold(f64::INFINITY, f64::min);
        s = s.max(w / 2.0 - d);
    }
    for (lines, w) in &g.cuts {
        let d = lines
            .iter()
            .flat_map(|pl| pl.segments())
            .map(|(a, b)| distance_to_segment(p, a, b))
            .fold(f64::INFINITY, f64::min);
        s = s.min(d - w / 2.0);
    }
    for (pls, rule) in &g.clips {
        let d = pls
            .iter()
            .flat_map(closed_segments)
            .map(|(a, b)| distance_to_segment(p, a, b))
            .fold(f64::INFINITY, f64::min);
        s = s.min(if crate::geometry::contains(pls, p, *rule) { d } else { -d });
    }
    if !g.occluders.is_empty() {
        let d = g
            .occluders
            .iter()
            .flat_map(|(pls, _)| pls.iter().flat_map(closed_segments))
            .map(|(a, b)| distance_to_segment(p, a, b))
            .fold(f64::INFINITY, f64::min);
        let inside = g.occluders.iter().any(|(pls, rule)| crate::geometry::contains(pls, p, *rule));
        s = s.min(if inside { -d } else { d });
    }
    s.min(inside_rect(page, p))
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

/// Integer units of the fills' union: 1/65536 mm, so that it moves an edge
/// by at most 8 nm, far below a sample step.
const UNION_QUANTUM_MM: f64 = 1.0 / 65_536.0;

/// Most crossings of a layer's fills for which their union is taken.
const UNION_MAX_CROSSINGS: usize = 100_000;

/// The union of a layer's fills as one outline, when two of them meet: the
/// distance is then measured to the union's boundary, not to a side that
/// two regions of the style share (which lies inside the union and would
/// play at half amplitude). `None` when no two fills' boxes meet (nothing to
/// unite) or the fills lie too far out for the union's integer units.
fn united_fills(fills: &[(&[Polyline], FillRule)]) -> Option<Vec<Polyline>> {
    if fills.len() < 2 {
        return None;
    }
    let boxes: Vec<_> = fills.iter().filter_map(|(pls, _)| crate::geometry::bounds(pls)).collect();
    let index = crate::spatial::BoxIndex::new(&boxes);
    let meet = boxes.iter().enumerate().any(|(i, b)| index.meeting(*b).any(|j| j != i));
    if !meet {
        return None;
    }
    let all = boxes.iter().copied().reduce(|a, b| (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3)))?;
    // The integer frame keeps coordinates within ±2^28 units.
    let span = (all.2 - all.0).max(all.3 - all.1);
    if !(span.is_finite() && span / UNION_QUANTUM_MM < (1u64 << 28) as f64) {
        return None;
    }
    // An overlay's work follows the outlines' crossings: a map's regions
    // share sides and cross a few times, a scribble's fill crosses itself
    // by the million (16 GB). Past the budget the fills are kept as they are
    // (a side two of them share then plays as an edge).
    let segments: Vec<Seg> = fills.iter().flat_map(|(pls, _)| pls.iter().flat_map(closed_segments)).collect();
    if crate::geometry::crossings::crossings_exceed(&segments, UNION_MAX_CROSSINGS) {
        return None;
    }
    let f = overlay::Frame { ox: all.0, oy: all.1, q: UNION_QUANTUM_MM };
    let mut each: Vec<Vec<i_overlay::i_float::int::point::IntPoint>> = Vec::new();
    for (pls, rule) in fills {
        let shapes = overlay::shapes_of(&overlay::contours(pls, f), overlay::ov_rule(*rule));
        each.extend(shapes.into_iter().flatten());
    }
    let union = overlay::shapes_of(&each, i_overlay::core::fill_rule::FillRule::NonZero);
    let back = |p: &i_overlay::i_float::int::point::IntPoint| (f.ox + p.x as f64 * f.q, f.oy + p.y as f64 * f.q);
    Some(union.iter().flatten().map(|c| Polyline { points: c.iter().map(back).collect(), closed: true }).collect())
}

/// Builds the field of one layer; `None` when nothing of it is felt on the page.
pub fn build_field(g: &LayerGeometry<'_>, params: FieldParams) -> Option<Field> {
    build_field_within(g, params, None).unwrap_or(None)
}

/// [`build_field`] within a memory budget: [`OverBudget`] when the process
/// holds more than `budget` allows before the field is done (looked at
/// before the fills are united and at every tile).
pub fn build_field_within(
    g: &LayerGeometry<'_>,
    params: FieldParams,
    budget: Option<&MemoryBudget>,
) -> Result<Option<Field>, OverBudget> {
    let over = || budget.is_some_and(MemoryBudget::exceeded);
    if over() {
        return Err(OverBudget);
    }
    if let Some(union) = united_fills(&g.fills) {
        let g = LayerGeometry { fills: vec![(&union[..], FillRule::NonZero)], ..g.clone() };
        return build_united(&g, params, budget);
    }
    build_united(g, params, budget)
}

/// [`build_field_within`] once the fills share no side.
fn build_united(
    g: &LayerGeometry<'_>,
    params: FieldParams,
    budget: Option<&MemoryBudget>,
) -> Result<Option<Field>, OverBudget> {
    let Some(built) = build_united_inner(g, params, budget) else { return Ok(None) };
    built.map(Some)
}

/// [`build_united`]: `None` when nothing is felt, `Some(Err)` when the
/// budget stopped it.
fn build_united_inner(
    g: &LayerGeometry<'_>,
    params: FieldParams,
    budget: Option<&MemoryBudget>,
) -> Option<Result<Field, OverBudget>> {
    let h = params.pitch_mm;
    if !(h.is_finite() && h > 0.0) {
        return None;
    }
    let soft = params.soft_mm.max(0.0);
    // Codes run from −128 to +127 steps; the cap is 127 steps.
    let reach = soft / 2.0 + 2.0 * h;
    let step = reach / 126.0;
    let cap = 127.0 * step;
    // The felt region's bounds, grown by the reach, within the page grown by it.
    let mut felt: Option<(f64, f64, f64, f64)> = None;
    let mut grow = |b: (f64, f64, f64, f64), m: f64| {
        let b = (b.0 - m, b.1 - m, b.2 + m, b.3 + m);
        felt = Some(felt.map_or(b, |f| (f.0.min(b.0), f.1.min(b.1), f.2.max(b.2), f.3.max(b.3))));
    };
    for (pls, _) in &g.fills {
        if let Some(b) = crate::geometry::bounds(pls) {
            grow(b, reach);
        }
    }
    if let Some((lines, w)) = &g.band {
        for pls in lines {
            if let Some(b) = crate::geometry::bounds(pls) {
                grow(b, w / 2.0 + reach);
            }
        }
    }
    let f = felt?;
    let pg = params.page;
    let (x0, y0) = (f.0.max(pg.0 - reach), f.1.max(pg.1 - reach));
    let (x1, y1) = (f.2.min(pg.2 + reach), f.3.min(pg.3 + reach));
    if !(x1 > x0 && y1 > y0 && x0.is_finite() && y1.is_finite()) {
        return None;
    }
    // The lattice sits on multiples of h from the page origin, so that
    // layers of one drawing sample the same points.
    let tile = TILE_CELLS as f64 * h;
    let (ox, oy) = ((x0 / h).floor() * h, (y0 / h).floor() * h);
    let cols = ((x1 - ox) / tile).ceil().max(1.0);
    let rows = ((y1 - oy) / tile).ceil().max(1.0);
    if cols * rows > taxel_format::MAX_DISTANCE_TILES as f64 {
        return None;
    }
    let (cols, rows) = (cols as usize, rows as usize);
    let at = |i: usize, j: usize| (ox + i as f64 * h, oy + j as f64 * h);

    // Segments into per-tile buckets, each grown by how far it acts.
    // (Reserved at once: a map's layer holds a few hundred thousand, which
    // grown by doubling were copied a dozen times.)
    let points = |pls: &[Polyline]| pls.iter().map(|pl| pl.points.len() + 1).sum::<usize>();
    let outlines = [&g.fills, &g.clips, &g.occluders].into_iter().flatten().map(|(pls, _)| points(pls));
    let lines = g.band.iter().flat_map(|(lines, _)| lines.iter().map(|pls| points(pls)));
    let cut = g.cuts.iter().map(|(pls, _)| points(pls));
    let mut segs: Vec<(Seg, Part, f64)> = Vec::with_capacity(outlines.chain(lines).chain(cut).sum());
    for (pls, _) in &g.fills {
        for pl in pls.iter() {
            segs.extend(closed_segments(pl).map(|s| (s, Part::Fill, reach)));
        }
    }
    if let Some((lines, w)) = &g.band {
        for pls in lines {
            for pl in pls.iter() {
                segs.extend(pl.segments().map(|s| (s, Part::Band, w / 2.0 + reach)));
            }
        }
    }
    // Cuts grouped by width: within a group, the minimum of `d - w/2` over
    // segments is `sqrt(min d²) - w/2` exactly (square root and subtraction
    // of a constant are monotone under IEEE rounding), so each sample keeps a
    // squared minimum per width instead of taking a square root per segment.
    let mut cut_widths: Vec<f64> = Vec::new();
    for (lines, w) in &g.cuts {
        let group = match cut_widths.iter().position(|v| v.to_bits() == w.to_bits()) {
            Some(k) => k,
            None => {
                cut_widths.push(*w);
                cut_widths.len() - 1
            }
        };
        for pl in lines.iter() {
            segs.extend(pl.segments().map(|s| (s, Part::Cut(group), w / 2.0 + reach)));
        }
    }
    for (k, (pls, _)) in g.clips.iter().enumerate() {
        for pl in pls.iter() {
            segs.extend(closed_segments(pl).map(|s| (s, Part::Clip(k), reach)));
        }
    }
    for (pls, _) in &g.occluders {
        for pl in pls.iter() {
            segs.extend(closed_segments(pl).map(|s| (s, Part::Occluder, reach)));
        }
    }
    let tiles = Tiles { origin: (ox, oy), side: tile, cols, rows };
    let (buckets, spans) = buckets_of(&segs, &tiles);
    let stopped = AtomicBool::new(budget.is_some_and(MemoryBudget::exceeded));
    // Each segment's length, for the length of edge within a tile's reach.
    let seg_len: Vec<f64> =
        segs.iter().map(|&((a, b), _, _)| ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt()).collect();
    // Whether a tile is crowded ([`CROWDED_SEGMENTS`], [`CROWDED_EDGE`]).
    let crowded = |bucket: &[u32]| {
        bucket.len() > CROWDED_SEGMENTS
            && bucket.iter().map(|&n| seg_len.get(n as usize).copied().unwrap_or(0.0)).sum::<f64>()
                > CROWDED_EDGE * tile
    };
    // Inside-the-fills bits at every lattice point, one row sweep each.
    let (nx, ny) = (cols * TILE_CELLS + 1, rows * TILE_CELLS + 1);
    let inside = fill_bits(&g.fills, ox, oy, h, nx, ny);
    let clip_bits: Vec<Vec<bool>> = g.clips.iter().map(|c| fill_bits(&[*c], ox, oy, h, nx, ny)).collect();
    let in_clips = |k: usize| clip_bits.iter().all(|b| b[k]);
    let occluded = fill_bits(&g.occluders, ox, oy, h, nx, ny);
    let page_edge_near = |c: usize, r: usize| {
        let (a, b) = (at(c * TILE_CELLS, r * TILE_CELLS), at((c + 1) * TILE_CELLS, (r + 1) * TILE_CELLS));
        let near = |e: f64, lo: f64, hi: f64| e >= lo - reach && e <= hi + reach;
        (near(pg.0, a.0, b.0) || near(pg.2, a.0, b.0)) && b.1 >= pg.1 - reach && a.1 <= pg.3 + reach
            || (near(pg.1, a.1, b.1) || near(pg.3, a.1, b.1)) && b.0 >= pg.0 - reach && a.0 <= pg.2 + reach
    };
    let ridge_top = g.band.as_ref().map(|(_, w)| w / 2.0 / step);
    // Inside bits at the cell centres, swept when a tile first fits a plane.
    let centre_bits: OnceLock<planes::CentreBits> = OnceLock::new();
    // The shapes each row of tiles crosses, when a fine tile is first measured.
    let fine_rows: OnceLock<FineRows> = OnceLock::new();
    // A segment is measured only at the tile's samples within its reach plus
    // the clamp's margin: farther ones would clamp to the same code anyway
    // (every part is then beyond ±cap, and min, max and the clamp commute).
    let margin = cap - reach + step;
    // Every segment binned once for all the tiles' searches.
    let lattice = layer_grid::Lattice { tiles, h, margin, slots: near::slots(cut_widths.len(), g.clips.len()) };
    let layer_grid = layer_grid::LayerGrid::new(
        &segs,
        spans,
        &lattice,
        |part| near::slot_of(part, cut_widths.len(), g.clips.len()),
        near::GRID_FROM,
        near::MAX_RINGS,
    );
    let in_layer =
        |tile: (usize, usize), shift: isize| layer_grid.as_ref().map(|grid| near::InLayer { grid, tile, shift });
    // The codes whose amplitude is saturated (SPEC.md section 6.2): a
    // stored tile whose codes all lie at or beyond one of them plays exactly
    // as an inside (outside) tile, since bilinear interpolation never leaves
    // the range of its corners. So only tiles the edge profile's ramp
    // crosses are stored.
    let (full, none) = saturated_codes(soft, step);
    let zero = DISTANCE_ZERO as f64;
    let ramp = taxel_format::edge_ramp(soft as f32, step as f32) as f64;
    let sat = planes::Saturation {
        hi: full as f64 - zero,
        lo: none as f64 - zero,
        near: (ramp / 2.0 + h) / step,
        pin: (ramp / 2.0 + h / 2.0) / step + 1.0,
    };
    // Each tile on its own (in parallel: a tile reads only the layer's
    // shared geometry, buckets and bits), then numbered in order, so that
    // the field is the same however the tiles were shared out.
    let scratch = || Scratch {
        near: Near::new(g.clips.len(), cut_widths.clone()),
        centres: Near::new(g.clips.len(), cut_widths.clone()),
    };
    // A tile no other kind plays: its samples, finer where the lattice's
    // misplace the edge (format 4.4), on a second pass (`refine`) within the
    // layer's budget.
    let stored = |tile: &planes::TileCtx<'_, '_>, centres: &mut Near, buf: [u8; TILE_SAMPLES], refine: bool| {
        if refine {
            match fine::refine(tile, centres, &buf) {
                Some(f) => TileOut::Fine(f, buf),
                None => TileOut::Samples(buf),
            }
        } else if !crowded(tile.bucket) && tile.bucket.len().saturating_mul(FINE_POINTS) <= FINE_WORK {
            match fine::priority(tile, centres, &buf) {
                Some(p) => TileOut::Refinable(buf, p),
                None => TileOut::Samples(buf),
            }
        } else {
            TileOut::Samples(buf)
        }
    };
    let tile_of = |Scratch { near, centres }: &mut Scratch, r: usize, c: usize, refine: bool| -> TileOut {
        // Past the budget: the remaining tiles are not worked on.
        if stopped.load(Ordering::Relaxed) || budget.is_some_and(MemoryBudget::exceeded) {
            stopped.store(true, Ordering::Relaxed);
            return TileOut::Constant(TILE_OUTSIDE);
        }
        let bucket = &buckets[r * cols + c];
        let corner = at(c * TILE_CELLS, r * TILE_CELLS);
        if bucket.is_empty() && !page_edge_near(c, r) {
            // No edge within the reach: the tile is what its corner is.
            let k = r * TILE_CELLS * nx + c * TILE_CELLS;
            let felt_here = !g.fills.is_empty() && inside[k] && in_clips(k) && !occluded[k];
            return TileOut::Constant(if felt_here && inside_rect(pg, corner) > 0.0 {
                TILE_INSIDE
            } else {
                TILE_OUTSIDE
            });
        }
        // What each sample is inside of.
        let (mut inside_t, mut occluded_t) = ([false; TILE_SAMPLES], [false; TILE_SAMPLES]);
        let mut in_clip = vec![false; clip_bits.len() * TILE_SAMPLES];
        for t in 0..TILE_SAMPLES {
            let k = (r * TILE_CELLS + t / TILE_SIDE) * nx + c * TILE_CELLS + t % TILE_SIDE;
            (inside_t[t], occluded_t[t]) = (inside[k], occluded[k]);
            for (q, b) in clip_bits.iter().enumerate() {
                in_clip[q * TILE_SAMPLES + t] = b[k];
            }
        }
        let bits = near::TileBits { inside: &inside_t, occluded: &occluded_t, in_clip: &in_clip, cap };
        near.measure_live(g, &segs, bucket, (corner, h, margin), &bits, in_layer((c, r), 0), false);
        let mut tile_buf = [0u8; TILE_SAMPLES];
        // The unquantised distances of the tile's samples, in codes (clamped).
        let mut exact = [0f64; TILE_SAMPLES];
        let mut clipped = vec![false; clip_bits.len()];
        for j in 0..TILE_SIDE {
            for i in 0..TILE_SIDE {
                let (gi, gj) = (c * TILE_CELLS + i, r * TILE_CELLS + j);
                let p = at(gi, gj);
                let t = j * TILE_SIDE + i;
                for (q, v) in clipped.iter_mut().enumerate() {
                    *v = in_clip[q * TILE_SAMPLES + t];
                }
                let s = near.signed(g, t, (inside_t[t], occluded_t[t]), &clipped, p, pg).clamp(-cap, cap);
                let code = (s / step).round().clamp(-128.0, 127.0) as i32 + DISTANCE_ZERO as i32;
                tile_buf[t] = code as u8;
                exact[t] = s / step;
            }
        }
        if tile_buf.iter().all(|&v| v >= full) {
            return TileOut::Constant(TILE_INSIDE);
        }
        if tile_buf.iter().all(|&v| v <= none) {
            return TileOut::Constant(TILE_OUTSIDE);
        }
        // A plane or ridge where one plays the tile, else a corner or notch, else its samples.
        let tile = planes::TileCtx {
            g,
            segs: &segs,
            bucket,
            corner,
            h,
            margin,
            page: pg,
            cap: cap / step,
            cap_mm: cap,
            step,
            sat,
            first: r * TILE_CELLS * nx + c * TILE_CELLS,
            nx,
            layer: in_layer((c, r), 1),
            nearest: planes::NearestSegments::default(),
            order: std::cell::OnceCell::new(),
            centre_codes: std::cell::OnceCell::new(),
            measured: near,
            row: r,
            fine_rows: &fine_rows,
            rows_of: &|| FineRows::new(g, oy, tile, rows),
            centre_bits: centre_bits.get_or_init(|| {
                // The same sweeps as the lattice points', half a cell on.
                let (cx, cy) = (ox + h / 2.0, oy + h / 2.0);
                planes::CentreBits {
                    inside: fill_bits(&g.fills, cx, cy, h, nx, ny),
                    occluded: fill_bits(&g.occluders, cx, cy, h, nx, ny),
                    clips: g.clips.iter().map(|c| fill_bits(&[*c], cx, cy, h, nx, ny)).collect(),
                }
            }),
        };
        let lines = planes::nearest_lines(&tile, &exact);
        let fitted =
            planes::fit(&exact, ridge_top, sat, &lines).into_iter().find(|(e, rec)| tile.centres_fit(centres, *e, rec));
        if let Some((entry, rec)) = fitted {
            return TileOut::Record(entry, rec);
        }
        // The kinds below play two lines, a circle or up to three segments:
        // where hundreds of segments lie within the tile's reach (a map
        // drawn far finer than the lattice) they are not tried.
        if crowded(bucket) {
            return stored(&tile, centres, tile_buf, refine);
        }
        // Two straight edges meeting at a vertex: a corner or a notch.
        let bent = bends::bends(&tile, &exact, ramp)
            .into_iter()
            .find(|b| tile.centres_all(centres, |u, w, e| b.close(u, w, e, sat)));
        if let Some(b) = bent {
            return TileOut::Bend(b.kind, b.recs);
        }
        // A band's centre line bent at a vertex, or its end.
        let band_bent = bends::band_bends(&tile, &exact).into_iter().find(|r| {
            tile.centres_all(centres, |u, w, e| {
                sat.close(taxel_format::bend_code([&r[0], &r[1]], u, w) - DISTANCE_ZERO as f64, e)
            })
        });
        if let Some(r) = band_bent {
            return TileOut::Bend(taxel_format::TILE_BEND, r);
        }
        // A circular arc: the cone round its centre as a bend tile, else an arc tile.
        let circle = arcs::circles(&tile, &exact).into_iter().find(|(kind, r)| {
            let entry = taxel_format::TileEntry::of(*kind);
            tile.centres_all(centres, |u, w, e| {
                entry.code(r, u, w).is_some_and(|code| sat.close(code - DISTANCE_ZERO as f64, e))
            })
        });
        if let Some((kind, r)) = circle {
            return TileOut::Bend(kind, r);
        }
        // Where band centre lines meet: the nearest of up to three segments.
        let joined = junctions::segment_tiles(&tile, &exact).into_iter().find(|r| {
            let [s0, s1, s2, last] = r;
            tile.centres_all(centres, |u, w, e| {
                sat.close(taxel_format::segments_code([s0, s1, s2, last], u, w) - DISTANCE_ZERO as f64, e)
            })
        });
        if let Some(r) = joined {
            return TileOut::Segments(r);
        }
        // A fill's straight side and a circular hole in it: a cut arc (format 4.3).
        let cut = cut_arcs::cut_arcs(&tile, &exact)
            .into_iter()
            .find(|cut| tile.centres_all(centres, |u, w, e| cut.close(u, w, e, sat)));
        if let Some(cut) = cut {
            return TileOut::Bend(taxel_format::TILE_ARC, cut.recs);
        }
        stored(&tile, centres, tile_buf, refine)
    };
    // A small layer on one thread: handing its tiles out costs more than it
    // saves, and on a loaded machine a tile stolen by a worker that is not
    // running holds up the layer until it is.
    let work: usize = buckets.iter().map(Vec::len).sum();
    let mut outs: Vec<TileOut> = if work >= PARALLEL_FROM {
        (0..rows * cols).into_par_iter().map_init(scratch, |s, k| tile_of(s, k / cols, k % cols, false)).collect()
    } else {
        let mut s = scratch();
        (0..rows * cols).map(|k| tile_of(&mut s, k / cols, k % cols, false)).collect()
    };
    if stopped.load(Ordering::Relaxed) {
        return Some(Err(OverBudget));
    }
    // Fine tiles (format 4.4) where stored tiles misplace the edge, the
    // worst first, while they add no more bytes than the layer has without
    // them (or [`FINE_BUDGET_FLOOR`]): refining every tile of a map drawn
    // finer than the lattice (a thousand regions on the device) would take
    // megabytes. A round of refinements that adds none ends the search.
    let mut wanted: Vec<(f64, usize)> = outs
        .iter()
        .enumerate()
        .filter_map(|(k, o)| match o {
            TileOut::Refinable(_, p) => Some((*p, k)),
            _ => None,
        })
        .collect();
    wanted.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    let budget = outs.iter().map(TileOut::bytes).sum::<usize>().max(FINE_BUDGET_FLOOR);
    let mut extra = 0usize;
    // And within a budget of work: a fine tile measures each segment near
    // it at a thousand points, and in a map drawn much finer than the lattice
    // (a thousand regions fitted to the device) every tile has hundreds.
    let work_per = |k: usize| buckets.get(k).map_or(0, Vec::len).saturating_mul(FINE_POINTS);
    let mut work = 0usize;
    let wanted: Vec<(f64, usize)> = wanted
        .into_iter()
        .take_while(|&(_, k)| {
            work = work.saturating_add(work_per(k));
            work <= FINE_WORK
        })
        .collect();
    for chunk in wanted.chunks(REFINE_CHUNK) {
        if budget.saturating_sub(extra) < TILE_SAMPLES {
            break;
        }
        let refined: Vec<(usize, TileOut)> = if work >= PARALLEL_FROM {
            chunk.par_iter().map_init(scratch, |s, &(_, k)| (k, tile_of(s, k / cols, k % cols, true))).collect()
        } else {
            let mut s = scratch();
            chunk.iter().map(|&(_, k)| (k, tile_of(&mut s, k / cols, k % cols, true))).collect()
        };
        // In priority order, whatever the threads' order.
        let mut added = false;
        for (k, out) in refined {
            let out = match out {
                TileOut::Fine(f, buf) if extra + f.samples.len().saturating_sub(TILE_SAMPLES) <= budget => {
                    extra += f.samples.len().saturating_sub(TILE_SAMPLES);
                    added = true;
                    TileOut::Fine(f, buf)
                }
                TileOut::Fine(_, buf) | TileOut::Refinable(buf, _) => TileOut::Samples(buf),
                o => o,
            };
            if let Some(slot) = outs.get_mut(k) {
                *slot = out;
            }
        }
        if !added {
            break;
        }
    }
    if stopped.load(Ordering::Relaxed) {
        return Some(Err(OverBudget));
    }
    let mut tiles = vec![TILE_OUTSIDE; cols * rows];
    let mut samples = Vec::new();
    let mut planes = Vec::new();
    for (entry, out) in tiles.iter_mut().zip(outs) {
        *entry = match out {
            TileOut::Constant(e) => e,
            TileOut::Record(kind, rec) => {
                let n = planes.len() as u32;
                planes.push(rec);
                kind | n
            }
            TileOut::Bend(kind, recs) => {
                let n = planes.len() as u32;
                planes.extend(recs);
                kind | n
            }
            TileOut::Segments(recs) => {
                let n = planes.len() as u32;
                planes.extend(recs);
                taxel_format::TILE_SEGMENTS | n
            }
            TileOut::Samples(buf) | TileOut::Refinable(buf, _) => {
                let n = (samples.len() / TILE_SAMPLES) as u32;
                samples.extend_from_slice(&buf);
                TILE_FIRST_STORED + n
            }
            TileOut::Fine(f, buf) => {
                let n = (samples.len() / TILE_SAMPLES) as u32;
                match taxel_format::fine_entry(n, f.fine, f.pair) {
                    Some(e) => {
                        samples.extend_from_slice(&f.samples);
                        e
                    }
                    // (Past the entry's 2^26 stored tiles: the tile's own samples.)
                    None => {
                        samples.extend_from_slice(&buf);
                        TILE_FIRST_STORED + n
                    }
                }
            }
        };
    }
    if tiles.iter().all(|&t| t == TILE_OUTSIDE) {
        return None;
    }
    Some(Ok(Field {
        origin: (ox, oy),
        tile_cols: cols as u32,
        tile_rows: rows as u32,
        step_mm: step,
        tiles,
        planes,
        samples,
    }))
}

/// The segment entries in a layer's tile buckets from which its tiles are
/// built in parallel (the 1,000-region map's layers hold 100,000 to 300,000;
/// a diagram's, a few hundred).
const PARALLEL_FROM: usize = 16_384;

/// One tile of a layer as built, before the stored ones are numbered.
enum TileOut {
    /// An inside or outside tile (its index entry).
    Constant(u32),
    /// A plane or ridge tile: its index kind and record.
    Record(u32, TilePlane),
    /// A corner, notch or bend tile: its index kind and two records.
    Bend(u32, [TilePlane; 2]),
    /// A segments tile's records (format 4.2).
    Segments([TilePlane; taxel_format::SEGMENT_TILE_RECORDS]),
    /// A stored tile's samples.
    Samples([u8; TILE_SAMPLES]),
    /// A fine tile (format 4.4), and the tile's samples at the lattice's pitch.
    Fine(fine::Fine, [u8; TILE_SAMPLES]),
    /// A stored tile's samples that a fine tile may play better, and how
    /// much ([`fine::priority`]).
    Refinable([u8; TILE_SAMPLES], f64),
}

impl TileOut {
    /// The bytes the tile takes in its layer: its index entry, records and
    /// samples.
    fn bytes(&self) -> usize {
        4 + match self {
            TileOut::Constant(_) => 0,
            TileOut::Record(..) => taxel_format::PLANE_RECORD_LEN,
            TileOut::Bend(..) => 2 * taxel_format::PLANE_RECORD_LEN,
            TileOut::Segments(_) => taxel_format::SEGMENT_TILE_RECORDS * taxel_format::PLANE_RECORD_LEN,
            TileOut::Samples(_) | TileOut::Refinable(..) => TILE_SAMPLES,
            TileOut::Fine(f, _) => f.samples.len(),
        }
    }
}

/// Fine tiles refined at a time, in priority order, between checks of the budget.
const REFINE_CHUNK: usize = 32;
/// The points at which a fine tile measures each segment of its bucket
/// (`fine.rs`: 16 sets of 9 x 9).
const FINE_POINTS: usize = 16 * TILE_SAMPLES;
/// The most segment measurements a layer's fine tiles may take together
/// (a few milliseconds of one core; with the tiles' other work, a
/// thousand-region map's build takes about 10 % longer).
const FINE_WORK: usize = 2_000_000;
/// A tile is crowded where more than [`CROWDED_SEGMENTS`] segments and
/// more than [`CROWDED_EDGE`] tile sides of edge lie within its reach: many
/// shapes' edges, as where a map is drawn far finer than the lattice. The
/// kinds that play two lines, a circle or a few segments (corner, notch,
/// bend, arc, segments and cut arc tiles) are not tried there, nor is it
/// ranked for refining into a fine tile. Measured: on the 1,000-region map
/// fitted to the device most tiles have 400 to 700 segments and 12 to 25
/// sides of edge; those writers found nothing there, and ranking every
/// stored tile for the two or three that the work budget could refine took
/// a tenth of the build. Every tile those kinds play in the demo and the
/// generated drawings has at most 213 segments; a lake flattened into 600
/// segments and crossed by a river has some 200 but 3 sides of edge, and a
/// generated chart's tiles 17 sides but 17 segments (medians).
const CROWDED_SEGMENTS: usize = 4 * TILE_CELLS * TILE_CELLS;
const CROWDED_EDGE: f64 = 12.0;
/// The fine tiles of a layer may add this many bytes even where the layer
/// has fewer (a diagram's layer of a few kB, whose corners they sharpen).
const FINE_BUDGET_FLOOR: usize = 16 * 1024;

/// One worker's scratch for measuring tiles: at the samples and at the cell
/// centres (the plane fits' check).
struct Scratch {
    near: Near,
    centres: Near,
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

/// Whether each lattice point `(i, j)` (row-major, `nx` wide) is inside the
/// union of the fills, by sweeping each row's crossings with every fill
/// outline (the same half-open rule as [`contains`](crate::geometry::contains)).
fn fill_bits(fills: &[(&[Polyline], FillRule)], ox: f64, oy: f64, h: f64, nx: usize, ny: usize) -> Vec<bool> {
    let all = fills.iter().enumerate().flat_map(|(shape, (pls, _))| pls.iter().map(move |pl| (shape, pl)));
    fill_bits_of(fills, all, (ox, oy, h), (nx, ny))
}

/// [`fill_bits`] from the polylines `some` of `fills` (shape number and
/// polyline): the same bits wherever the others cross none of the rows
/// (a fine tile's rows, [`RowShapes`]).
fn fill_bits_of<'p>(
    fills: &[(&[Polyline], FillRule)],
    some: impl Iterator<Item = (usize, &'p Polyline)>,
    (ox, oy, h): (f64, f64, f64),
    (nx, ny): (usize, usize),
) -> Vec<bool> {
    let mut bits = vec![false; nx * ny];
    if fills.is_empty() {
        return bits;
    }
    // Edges bucketed by the lattice rows they span.
    let mut by_row: Vec<Vec<(Seg, usize)>> = vec![Vec::new(); ny];
    for (shape, pl) in some {
        {
            for s in closed_segments(pl) {
                let (lo, hi) = (s.0.1.min(s.1.1), s.0.1.max(s.1.1));
                let j0 = ceil_f64((lo - oy) / h).max(0.0);
                let j1 = floor_f64((hi - oy) / h).min(ny as f64 - 1.0);
                // NaN bounds (never from finite geometry) give no rows.
                if j0.is_nan() || j1.is_nan() || j0 > j1 {
                    continue;
                }
                for row in by_row.iter_mut().take(j1 as usize + 1).skip(j0 as usize) {
                    row.push((s, shape));
                }
            }
        }
    }
    // Each shape's winding number and crossing count so far along the row
    // (indexed by shape, reset after each row for the shapes it crossed).
    let mut state: Vec<(i32, u32)> = vec![(0, 0); fills.len()];
    let mut xs: Vec<(f64, usize, i32)> = Vec::new();
    for (j, edges) in by_row.iter().enumerate() {
        let y = oy + j as f64 * h;
        // Crossings to the right of a point decide it; sweep from the right.
        xs.clear();
        xs.extend(edges.iter().filter(|((a, b), _)| (a.1 <= y) != (b.1 <= y)).map(|&((a, b), shape)| {
            let x = a.0 + (y - a.1) / (b.1 - a.1) * (b.0 - a.0);
            (x, shape, if b.1 > a.1 { 1 } else { -1 })
        }));
        if xs.is_empty() {
            continue;
        }
        xs.sort_by(|a, b| b.0.total_cmp(&a.0));
        for &(_, shape, _) in &xs {
            state[shape] = (0, 0);
        }
        let mut inside_count = 0i32;
        let mut k = 0;
        for i in (0..nx).rev() {
            let x = ox + i as f64 * h;
            while k < xs.len() && xs[k].0 > x {
                let (_, shape, dir) = xs[k];
                let rule = fills[shape].1;
                let e = &mut state[shape];
                let was = is_in(*e, rule);
                e.0 += dir;
                e.1 += 1;
                let now = is_in(*e, rule);
                inside_count += now as i32 - was as i32;
                k += 1;
            }
            bits[j * nx + i] = inside_count > 0;
        }
    }
    bits
}

/// The polylines of a layer's shapes (fills, occluders or one clip) whose
/// vertical extent meets each row of tiles, as (shape, polyline) numbers:
/// a row sweep of points in that row crosses no other.
struct RowShapes(Vec<Vec<(u32, u32)>>);

impl RowShapes {
    /// Over `rows` rows of tiles `tile` mm high from page y `oy`.
    fn new(shapes: &[(&[Polyline], FillRule)], oy: f64, tile: f64, rows: usize) -> RowShapes {
        let mut out = vec![Vec::new(); rows];
        for (k, (pls, _)) in shapes.iter().enumerate() {
            for (i, pl) in pls.iter().enumerate() {
                let (lo, hi) =
                    pl.points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.1), b.max(p.1)));
                // Rows from the one holding `lo` to the one holding `hi`, one more each way for rounding.
                let first = floor_f64((lo - oy) / tile - 1.0).max(0.0);
                let last = floor_f64((hi - oy) / tile + 1.0).min(rows as f64 - 1.0);
                // (NaN bounds, from no points, give no rows.)
                if first.is_nan() || last.is_nan() || first > last {
                    continue;
                }
                for row in out.iter_mut().take(last as usize + 1).skip(first as usize) {
                    row.push((k as u32, i as u32));
                }
            }
        }
        RowShapes(out)
    }

    /// Inside bits of `shapes` (those this index was built from) at the
    /// `n` x `n` points `hf` apart from `corner`, which lie in tile row `row`.
    fn bits(&self, shapes: &[(&[Polyline], FillRule)], row: usize, corner: (f64, f64), hf: f64, n: usize) -> Vec<bool> {
        let some = self.0.get(row).into_iter().flatten().filter_map(|&(k, i)| {
            let (pls, _) = shapes.get(k as usize)?;
            Some((k as usize, pls.get(i as usize)?))
        });
        fill_bits_of(shapes, some, (corner.0, corner.1, hf), (n, n))
    }
}

/// The [`RowShapes`] of a layer's fills, occluders and clips, built when a
/// fine tile is first measured.
pub(super) struct FineRows {
    fills: RowShapes,
    occluders: RowShapes,
    clips: Vec<RowShapes>,
}

impl FineRows {
    fn new(g: &LayerGeometry<'_>, oy: f64, tile: f64, rows: usize) -> FineRows {
        FineRows {
            fills: RowShapes::new(&g.fills, oy, tile, rows),
            occluders: RowShapes::new(&g.occluders, oy, tile, rows),
            clips: g.clips.iter().map(|c| RowShapes::new(std::slice::from_ref(c), oy, tile, rows)).collect(),
        }
    }

    /// Inside-the-fills, inside-the-occluders and inside-each-clip bits at
    /// the `n` x `n` points `hf` apart from `corner`, in tile row `row`.
    pub(super) fn bits(
        &self,
        g: &LayerGeometry<'_>,
        row: usize,
        corner: (f64, f64),
        hf: f64,
        n: usize,
    ) -> (Vec<bool>, Vec<bool>, Vec<Vec<bool>>) {
        (
            self.fills.bits(&g.fills, row, corner, hf, n),
            self.occluders.bits(&g.occluders, row, corner, hf, n),
            self.clips.iter().zip(&g.clips).map(|(r, c)| r.bits(std::slice::from_ref(c), row, corner, hf, n)).collect(),
        )
    }
}

fn is_in(s: (i32, u32), rule: FillRule) -> bool {
    match rule {
        FillRule::NonZero => s.0 != 0,
        FillRule::EvenOdd => s.1 % 2 == 1,
    }
}

/// The interpolated signed distance of a built field at `p` in mm (SPEC.md
/// section 6.2), `None` outside its lattice: what a player computes, in f64.
#[cfg(test)]
pub fn field_distance(f: &Field, h: f64, p: (f64, f64)) -> Option<f64> {
    let fx = (p.0 - f.origin.0) / h;
    let fy = (p.1 - f.origin.1) / h;
    let (w, ht) = ((f.tile_cols as usize * TILE_CELLS) as f64, (f.tile_rows as usize * TILE_CELLS) as f64);
    if !(fx >= 0.0 && fy >= 0.0 && fx < w && fy < ht) {
        return None;
    }
    let (ci, cj) = (fx as usize, fy as usize);
    let (tx, ty) = (ci / TILE_CELLS, cj / TILE_CELLS);
    let e = *f.tiles.get(ty * f.tile_cols as usize + tx)?;
    let step = f.step_mm;
    match e {
        TILE_OUTSIDE => Some(-128.0 * step),
        TILE_INSIDE => Some(127.0 * step),
        e if e >> 28 == taxel_format::TILE_FINE >> 28 => {
            let taxel_format::TileEntry::Fine { first, fine, pair } = taxel_format::TileEntry::of(e) else {
                return None;
            };
            let fine = fine as usize;
            let cell = |v: f64| {
                let last = TILE_CELLS * fine - 1;
                let c = ((v * fine as f64).max(0.0) as usize).min(last);
                (c / TILE_CELLS, c % TILE_CELLS, v * fine as f64 - c as f64)
            };
            let ((a, i, wx), (b, j, wy)) = (cell(fx - (tx * TILE_CELLS) as f64), cell(fy - (ty * TILE_CELLS) as f64));
            let channel = |c: usize| {
                let base = (first as usize + (c * fine + b) * fine + a) * TILE_SAMPLES;
                let s = |i: usize, j: usize| {
                    f.samples.get(base + j * TILE_SIDE + i).map_or(0.0, |&v| v as f64 - DISTANCE_ZERO as f64)
                };
                let top = s(i, j) + (s(i + 1, j) - s(i, j)) * wx;
                let bot = s(i, j + 1) + (s(i + 1, j + 1) - s(i, j + 1)) * wx;
                top + (bot - top) * wy
            };
            Some(if pair { channel(0).min(channel(1)) } else { channel(0) } * step)
        }
        e if e >= taxel_format::TILE_PLANE => {
            // A plane, ridge, corner or notch tile: its function at the point itself.
            let (u, w) = (fx - (tx * TILE_CELLS) as f64, fy - (ty * TILE_CELLS) as f64);
            let code = taxel_format::TileEntry::of(e).code(&f.planes, u, w)?;
            Some((code - DISTANCE_ZERO as f64) * step)
        }
        e => {
            let base = (e - TILE_FIRST_STORED) as usize * TILE_SAMPLES;
            let (i, j) = (ci - tx * TILE_CELLS, cj - ty * TILE_CELLS);
            let s = |i: usize, j: usize| {
                f.samples.get(base + j * TILE_SIDE + i).map_or(0.0, |&v| v as f64 - DISTANCE_ZERO as f64)
            };
            let (wx, wy) = (fx - ci as f64, fy - cj as f64);
            let top = s(i, j) + (s(i + 1, j) - s(i, j)) * wx;
            let bot = s(i, j + 1) + (s(i + 1, j + 1) - s(i, j + 1)) * wx;
            Some((top + (bot - top) * wy) * step)
        }
    }
}

/// Whether `p` lies in a constant tile of a built field: `Some(true)` inside,
/// `Some(false)` outside, `None` in a stored tile or off the lattice.
#[cfg(test)]
pub fn constant_tile_at(f: &Field, h: f64, p: (f64, f64)) -> Option<bool> {
    let fx = (p.0 - f.origin.0) / h;
    let fy = (p.1 - f.origin.1) / h;
    if !(fx >= 0.0 && fy >= 0.0) {
        return None;
    }
    let (tx, ty) = (fx as usize / TILE_CELLS, fy as usize / TILE_CELLS);
    if tx >= f.tile_cols as usize {
        return None;
    }
    match *f.tiles.get(ty * f.tile_cols as usize + tx)? {
        TILE_OUTSIDE => Some(false),
        TILE_INSIDE => Some(true),
        _ => None,
    }
}

mod arcs;
mod bends;
mod cut_arcs;
mod fine;
mod junctions;
mod layer_grid;
mod near;
mod planes;
mod sanity;
pub use sanity::sanity_check;
#[cfg(test)]
pub(crate) mod tests;
