//! The build of one layer's field: the lattice over what is felt, the
//! segments in per-tile buckets, each tile measured at its samples and
//! written as the kind that plays it, fine tiles within the layer's budget,
//! then the tiles numbered into a [`Field`].

use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use taxel_format::{
    DISTANCE_ZERO, TILE_CELLS, TILE_FIRST_STORED, TILE_INSIDE, TILE_OUTSIDE, TILE_PLANE, TILE_RIDGE, TILE_SAMPLES,
    TILE_SIDE, TilePlane,
};

use super::hiding::occluders_that_hide;
use super::near::{self, Near};
use super::{
    Field, FieldParams, FineRows, LayerGeometry, Part, Seg, Tiles, arcs, bends, buckets_of, closed_segments, cut_arcs,
    fill_bits, fine, inside_rect, junctions, layer_grid, planes, saturated_codes, united_fills,
};
use crate::budget::{MemoryBudget, OverBudget};
use crate::geometry::{FillRule, Polyline};
use crate::spatial::Bbox;

/// Builds the field of one layer; `None` when nothing of it is felt on the page.
pub fn build_field(g: &LayerGeometry<'_>, params: FieldParams) -> Option<Field> {
    build_field_within(g, params, None).unwrap_or(None)
}

/// Most occluders that are united (a layer under a map's other regions has
/// them by the thousand, side by side, and their union cost the 64 MB map
/// at the input limit 2 s of its 7 without changing a byte: their shared
/// sides lie where no fill is). Past it they are measured one by one.
const MAX_UNITED_OCCLUDERS: usize = 2_048;

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
    // The fills' union, and the occluders': a side two occluders share lies
    // inside their union, where the layer is not felt, and measured as an
    // occluder's edge it made a crease of half amplitude there (a region
    // under a braille label's clearing and the region beside it).
    // Only the occluders that can hide some of the layer (a map's regions
    // of other styles border it and hide nothing).
    let hiding = occluders_that_hide(&g.fills, &g.occluders, Clamp::of(params).cap);
    let occluders = (hiding.len() <= MAX_UNITED_OCCLUDERS).then(|| united_fills(&hiding)).flatten();
    let fills = united_fills(&g.fills);
    let g = LayerGeometry {
        fills: one(fills.as_deref(), &g.fills),
        occluders: one(occluders.as_deref(), &hiding),
        ..g.clone()
    };
    build_united(&g, params, budget)
}

/// [`build_field`] with every occluder measured, as before the occluders
/// that hide nothing were left out (their union as it would be).
#[cfg(test)]
pub(super) fn build_field_with_every_occluder(g: &LayerGeometry<'_>, params: FieldParams) -> Option<Field> {
    let occluders = united_fills(&g.occluders);
    let g = LayerGeometry { occluders: one(occluders.as_deref(), &g.occluders), ..g.clone() };
    build_united(&g, params, None).unwrap_or(None)
}

/// How far a layer's edges act and how its samples are coded: the reach
/// `soft/2 + 2h`, the step of one code (codes run from −128 to +127 steps)
/// and the clamp, 127 steps.
struct Clamp {
    reach: f64,
    step: f64,
    cap: f64,
}

impl Clamp {
    fn of(params: FieldParams) -> Clamp {
        let reach = params.soft_mm.max(0.0) / 2.0 + 2.0 * params.pitch_mm;
        let step = reach / 126.0;
        Clamp { reach, step, cap: 127.0 * step }
    }
}

/// A union as the one shape that stands for `parts`, or `parts` themselves.
fn one<'a>(union: Option<&'a [Polyline]>, parts: &[(&'a [Polyline], FillRule)]) -> Vec<(&'a [Polyline], FillRule)> {
    match union {
        Some(u) => vec![(u, FillRule::NonZero)],
        None => parts.to_vec(),
    }
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
    let sampling = Sampling::of(g, params)?;
    let (segs, cut_widths) = segments(g, sampling.reach);
    let build = Build::new(g, sampling, &segs, &cut_widths, budget);
    let Tiles { origin, cols, rows, .. } = build.s.tiles;
    // Each tile on its own (in parallel: a tile reads only the layer's
    // shared geometry, buckets and bits), then numbered in order, so that
    // the field is the same however the tiles were shared out.
    // A small layer on one thread: handing its tiles out costs more than it
    // saves, and on a loaded machine a tile stolen by a worker that is not
    // running holds up the layer until it is.
    let work: usize = build.buckets.iter().map(Vec::len).sum();
    let mut outs: Vec<TileOut> = if work >= PARALLEL_FROM {
        (0..rows * cols)
            .into_par_iter()
            .map_init(|| build.scratch(), |s, k| build.tile(s, k / cols, k % cols, false))
            .collect()
    } else {
        let mut s = build.scratch();
        (0..rows * cols).map(|k| build.tile(&mut s, k / cols, k % cols, false)).collect()
    };
    if build.stopped.load(Ordering::Relaxed) {
        return Some(Err(OverBudget));
    }
    build.refine(&mut outs);
    if build.stopped.load(Ordering::Relaxed) {
        return Some(Err(OverBudget));
    }
    // Stored samples that saturate on one side play as the constant (tiles
    // kept for a fill's vertex that no other kind played, refined or not).
    for out in &mut outs {
        if let TileOut::Samples(buf) | TileOut::Refinable(buf, _) = out
            && let Some(constant) = build.saturated(buf)
        {
            *out = TileOut::Constant(constant);
        }
    }
    let (tiles, planes, samples) = number(outs, cols * rows)?;
    Some(Ok(Field {
        origin,
        tile_cols: cols as u32,
        tile_rows: rows as u32,
        step_mm: build.s.step,
        tiles,
        planes,
        samples,
    }))
}

/// How a layer is sampled: its lattice pitch and edge ramp, how far its
/// edges act, its codes' step and clamp, the page, and the tiles of its
/// lattice over what is felt.
struct Sampling {
    h: f64,
    soft: f64,
    reach: f64,
    step: f64,
    cap: f64,
    page: (f64, f64, f64, f64),
    tiles: Tiles,
}

impl Sampling {
    /// `None` when the pitch is not usable, when nothing is felt on the
    /// page, or when the lattice would hold more tiles than a layer may.
    fn of(g: &LayerGeometry<'_>, params: FieldParams) -> Option<Sampling> {
        let h = params.pitch_mm;
        if !(h.is_finite() && h > 0.0) {
            return None;
        }
        let soft = params.soft_mm.max(0.0);
        let Clamp { reach, step, cap } = Clamp::of(params);
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
        let tiles = Tiles { origin: (ox, oy), side: tile, cols, rows };
        Some(Sampling { h, soft, reach, step, cap, page: pg, tiles })
    }

    /// The page position of lattice point `(i, j)`.
    #[inline]
    fn at(&self, i: usize, j: usize) -> (f64, f64) {
        let (ox, oy) = self.tiles.origin;
        (ox + i as f64 * self.h, oy + j as f64 * self.h)
    }
}

/// The layer's segments, each with its part and how far it acts (for the
/// per-tile buckets), and the widths of its cut bands, one group each.
fn segments(g: &LayerGeometry<'_>, reach: f64) -> (Vec<(Seg, Part, f64)>, Vec<f64>) {
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
    (segs, cut_widths)
}

/// The bounds of a layer's occluders, and of its clips, in order.
type ShadeBoxes = (Vec<Option<Bbox>>, Vec<Option<Bbox>>);

/// Most pairs of a fill's point and an occluder's or clip's point for which
/// a layer asks whether each fill vertex lies under an occluder or outside a
/// clip ([`Build::fill_vertex_in`]; the fills' points times the others', a
/// bound decided before any tile, so the layer is the same however its
/// tiles are shared out). Past it every vertex counts, as before the
/// question was asked: a coastline painted over ten thousand islands costs
/// a bounded time.
const SHADE_PAIRS: usize = 50_000_000;

/// One layer being built: what each of its tiles reads (the layer's
/// geometry, its segments and their buckets, what the lattice points are
/// inside of), shared by the threads that build the tiles.
struct Build<'a, 'g> {
    g: &'a LayerGeometry<'g>,
    s: Sampling,
    segs: &'a [(Seg, Part, f64)],
    cut_widths: &'a [f64],
    buckets: Vec<Vec<u32>>,
    /// Each segment's length, for the length of edge within a tile's reach.
    seg_len: Vec<f64>,
    /// Lattice points per row, and rows of them.
    nx: usize,
    ny: usize,
    /// Inside-the-fills bits at every lattice point (row-major, `nx` wide),
    /// and inside each clip and the occluders.
    inside: Vec<bool>,
    clip_bits: Vec<Vec<bool>>,
    occluded: Vec<bool>,
    /// A band's half width in codes.
    ridge_top: Option<f64>,
    /// Inside bits at the cell centres, swept when a tile first fits a plane.
    centre_bits: OnceLock<planes::CentreBits>,
    /// The shapes each row of tiles crosses, when a fine tile is first measured.
    fine_rows: OnceLock<FineRows>,
    /// The bounds of each occluder and each clip, when a fill's vertex in
    /// a tile they shade is first asked about ([`Build::fill_vertex_in`]).
    shade_boxes: OnceLock<ShadeBoxes>,
    /// Whether the fills' points times the occluders' and clips' are
    /// within [`SHADE_PAIRS`].
    shade_affordable: bool,
    /// A segment is measured only at the tile's samples within its reach plus
    /// this margin: farther ones would clamp to the same code anyway
    /// (every part is then beyond ±cap, and min, max and the clamp commute).
    margin: f64,
    /// Every segment binned once for all the tiles' searches.
    layer_grid: Option<layer_grid::LayerGrid>,
    /// The lowest code played at full amplitude and the highest at zero.
    full: u8,
    none: u8,
    /// The edge profile's ramp, in codes.
    ramp: f64,
    sat: planes::Saturation,
    budget: Option<&'a MemoryBudget>,
    /// Past the budget: the remaining tiles are not worked on.
    stopped: AtomicBool,
}

impl<'a, 'g> Build<'a, 'g> {
    fn new(
        g: &'a LayerGeometry<'g>,
        s: Sampling,
        segs: &'a [(Seg, Part, f64)],
        cut_widths: &'a [f64],
        budget: Option<&'a MemoryBudget>,
    ) -> Self {
        let (h, step) = (s.h, s.step);
        let Tiles { origin: (ox, oy), cols, rows, .. } = s.tiles;
        let (buckets, spans) = buckets_of(segs, &s.tiles);
        let stopped = AtomicBool::new(budget.is_some_and(MemoryBudget::exceeded));
        let seg_len: Vec<f64> =
            segs.iter().map(|&((a, b), _, _)| ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt()).collect();
        let (nx, ny) = (cols * TILE_CELLS + 1, rows * TILE_CELLS + 1);
        let inside = fill_bits(&g.fills, ox, oy, h, nx, ny);
        let clip_bits: Vec<Vec<bool>> = g.clips.iter().map(|c| fill_bits(&[*c], ox, oy, h, nx, ny)).collect();
        let occluded = fill_bits(&g.occluders, ox, oy, h, nx, ny);
        let ridge_top = g.band.as_ref().map(|(_, w)| w / 2.0 / step);
        let margin = s.cap - s.reach + step;
        let lattice =
            layer_grid::Lattice { tiles: s.tiles, h, margin, slots: near::slots(cut_widths.len(), g.clips.len()) };
        let layer_grid = layer_grid::LayerGrid::new(
            segs,
            (&buckets, spans),
            &lattice,
            |part| near::slot_of(part, cut_widths.len(), g.clips.len()),
            near::GRID_FROM,
            near::MAX_RINGS,
        );
        // The codes whose amplitude is saturated (SPEC.md section 6.2): a
        // stored tile whose codes all lie at or beyond one of them plays exactly
        // as an inside (outside) tile, since bilinear interpolation never leaves
        // the range of its corners. So only tiles the edge profile's ramp
        // crosses are stored.
        let (full, none) = saturated_codes(s.soft, step);
        let zero = DISTANCE_ZERO as f64;
        let ramp = taxel_format::edge_ramp(s.soft as f32, step as f32) as f64;
        let sat = planes::Saturation {
            hi: full as f64 - zero,
            lo: none as f64 - zero,
            near: (ramp / 2.0 + h) / step,
            pin: (ramp / 2.0 + h / 2.0) / step + 1.0,
        };
        Build {
            g,
            s,
            segs,
            cut_widths,
            buckets,
            seg_len,
            nx,
            ny,
            inside,
            clip_bits,
            occluded,
            ridge_top,
            centre_bits: OnceLock::new(),
            fine_rows: OnceLock::new(),
            shade_boxes: OnceLock::new(),
            shade_affordable: {
                let points = |parts: &[(&[Polyline], FillRule)]| -> usize {
                    parts.iter().flat_map(|(pls, _)| pls.iter()).map(|pl| pl.points.len()).sum()
                };
                let others = points(&g.occluders) + points(&g.clips);
                points(&g.fills).checked_mul(others).is_some_and(|n| n <= SHADE_PAIRS)
            },
            margin,
            layer_grid,
            full,
            none,
            ramp,
            sat,
            budget,
            stopped,
        }
    }

    /// One worker's scratch.
    fn scratch(&self) -> Scratch {
        Scratch {
            near: Near::new(self.g.clips.len(), self.cut_widths.to_vec()),
            centres: Near::new(self.g.clips.len(), self.cut_widths.to_vec()),
        }
    }

    /// Whether a tile is crowded ([`CROWDED_SEGMENTS`], [`CROWDED_EDGE`]).
    fn crowded(&self, bucket: &[u32]) -> bool {
        bucket.len() > CROWDED_SEGMENTS
            && bucket.iter().map(|&n| self.seg_len.get(n as usize).copied().unwrap_or(0.0)).sum::<f64>()
                > CROWDED_EDGE * self.s.tiles.side
    }

    /// Whether lattice point `k` is inside every clip.
    #[inline]
    fn in_clips(&self, k: usize) -> bool {
        self.clip_bits.iter().all(|b| b[k])
    }

    /// Whether a vertex of a fill's outline (an end of a segment of
    /// `bucket`) lies inside the tile from `corner`: there the layer's edge
    /// turns, and may enter the tile between its samples while every sample
    /// is beyond the ramp on one side (a province's corner tip). A straight
    /// edge that crosses the tile leaves samples on both sides, and a band's
    /// joins and caps, at least a pitch in radius (a band's lattice is at
    /// most half its width), always hold a sample. A vertex that an
    /// occluder covers, or that lies outside a clip, by more than a code
    /// turns no felt edge: a region wholly under opaque fills is then not
    /// kept as a layer that plays nothing.
    fn fill_vertex_in(&self, bucket: &[u32], (c, r): (usize, usize), corner: (f64, f64)) -> bool {
        let side = self.s.h * TILE_CELLS as f64;
        let inside = |p: (f64, f64)| p.0 > corner.0 && p.0 < corner.0 + side && p.1 > corner.1 && p.1 < corner.1 + side;
        let mut vertices = bucket
            .iter()
            .filter_map(|&k| self.segs.get(k as usize))
            .filter(|(_, part, _)| matches!(part, Part::Fill))
            .flat_map(|&((a, b), _, _)| [a, b])
            .filter(|&p| inside(p))
            .peekable();
        if vertices.peek().is_none() {
            return false;
        }
        // Where every sample of the tile is felt but for the fills (none
        // under an occluder or outside a clip), any vertex counts.
        let first = r * TILE_CELLS * self.nx + c * TILE_CELLS;
        let shaded = (0..=TILE_CELLS)
            .flat_map(|j| (0..=TILE_CELLS).map(move |i| first + j * self.nx + i))
            .filter(|&k| k < self.inside.len())
            .any(|k| self.occluded.get(k) == Some(&true) || !self.in_clips(k));
        if !shaded || !self.shade_affordable {
            return true;
        }
        let (occluder_boxes, clip_boxes) = self.shade_boxes.get_or_init(|| {
            let boxes = |parts: &[(&[Polyline], FillRule)]| -> Vec<Option<Bbox>> {
                parts.iter().map(|(pls, _)| crate::geometry::bounds(pls)).collect()
            };
            (boxes(&self.g.occluders), boxes(&self.g.clips))
        });
        let m = self.s.step;
        let within = |b: &Option<Bbox>, p: (f64, f64)| {
            b.is_some_and(|b| p.0 >= b.0 - m && p.0 <= b.2 + m && p.1 >= b.1 - m && p.1 <= b.3 + m)
        };
        let felt = |p: (f64, f64)| {
            self.g
                .occluders
                .iter()
                .zip(occluder_boxes)
                .all(|(&(pls, rule), b)| !within(b, p) || !crate::geometry::deep_inside(pls, p, rule, m))
                && self.g.clips.iter().zip(clip_boxes).all(|(&(pls, rule), b)| {
                    within(b, p)
                        && (crate::geometry::contains(pls, p, rule)
                            || crate::geometry::distance_to_outline_within(pls, p, m, m) <= m)
                })
        };
        vertices.any(felt)
    }

    /// The constant tile that samples `buf` play, where every one saturates
    /// the edge profile on the same side.
    fn saturated(&self, buf: &[u8; TILE_SAMPLES]) -> Option<u32> {
        if buf.iter().all(|&v| v >= self.full) {
            Some(TILE_INSIDE)
        } else if buf.iter().all(|&v| v <= self.none) {
            Some(TILE_OUTSIDE)
        } else {
            None
        }
    }

    /// Whether plane `rec` plays `constant` (inside or outside) over its
    /// whole tile: saturated on that side at the four corners.
    fn plane_saturated(&self, rec: &TilePlane, constant: u32) -> bool {
        let side = TILE_CELLS as f64;
        [(0.0, 0.0), (side, 0.0), (0.0, side), (side, side)].iter().all(|&(u, w)| {
            let v = rec.affine(u, w);
            if constant == TILE_INSIDE { v >= self.sat.hi } else { v <= self.sat.lo }
        })
    }

    /// Whether the page's edge lies within the reach of tile `(c, r)`.
    fn page_edge_near(&self, c: usize, r: usize) -> bool {
        let (pg, reach) = (self.s.page, self.s.reach);
        let (a, b) = (self.s.at(c * TILE_CELLS, r * TILE_CELLS), self.s.at((c + 1) * TILE_CELLS, (r + 1) * TILE_CELLS));
        let near = |e: f64, lo: f64, hi: f64| e >= lo - reach && e <= hi + reach;
        (near(pg.0, a.0, b.0) || near(pg.2, a.0, b.0)) && b.1 >= pg.1 - reach && a.1 <= pg.3 + reach
            || (near(pg.1, a.1, b.1) || near(pg.3, a.1, b.1)) && b.0 >= pg.0 - reach && a.0 <= pg.2 + reach
    }

    /// Tile `tile` in the layer's grid, `shift` grid cells on.
    #[inline]
    fn in_layer(&self, tile: (usize, usize), shift: isize) -> Option<near::InLayer<'_>> {
        self.layer_grid.as_ref().map(|grid| near::InLayer { grid, tile, shift })
    }

    /// Tile `(c, r)`: constant where no edge acts on it, else measured at
    /// its samples and written as the first kind that plays it within half
    /// a code ([`Build::write`]); `refine`: the second pass, for the tiles
    /// that a fine tile may play better.
    fn tile(&self, Scratch { near, centres }: &mut Scratch, r: usize, c: usize, refine: bool) -> TileOut {
        // Past the budget: the remaining tiles are not worked on.
        if self.stopped.load(Ordering::Relaxed) || self.budget.is_some_and(MemoryBudget::exceeded) {
            self.stopped.store(true, Ordering::Relaxed);
            return TileOut::Constant(TILE_OUTSIDE);
        }
        let (g, h, nx) = (self.g, self.s.h, self.nx);
        let bucket = &self.buckets[r * self.s.tiles.cols + c];
        let corner = self.s.at(c * TILE_CELLS, r * TILE_CELLS);
        if bucket.is_empty() && !self.page_edge_near(c, r) {
            // No edge within the reach: the tile is what its corner is.
            let k = r * TILE_CELLS * nx + c * TILE_CELLS;
            let felt_here = !g.fills.is_empty() && self.inside[k] && self.in_clips(k) && !self.occluded[k];
            return TileOut::Constant(if felt_here && inside_rect(self.s.page, corner) > 0.0 {
                TILE_INSIDE
            } else {
                TILE_OUTSIDE
            });
        }
        let (tile_buf, exact) = self.measure(near, bucket, corner, (c, r));
        // Saturated samples play as a constant tile, unless a fill's vertex
        // lies in the tile, whose corner may poke in between them (a
        // province's corner tip): there the tile is written as any other,
        // and stays constant where no kind but stored samples or a plane
        // saturated over it, which play as the constant, plays it.
        let saturated = self.saturated(&tile_buf);
        if let Some(constant) = saturated
            && !self.fill_vertex_in(bucket, (c, r), corner)
        {
            return TileOut::Constant(constant);
        }
        let Tiles { origin: (ox, oy), side, rows, .. } = self.s.tiles;
        let ny = self.ny;
        let rows_of = move || FineRows::new(g, oy, side, rows);
        let tile = planes::TileCtx {
            g,
            segs: self.segs,
            bucket,
            corner,
            h,
            margin: self.margin,
            page: self.s.page,
            cap: self.s.cap / self.s.step,
            cap_mm: self.s.cap,
            step: self.s.step,
            sat: self.sat,
            first: r * TILE_CELLS * nx + c * TILE_CELLS,
            nx,
            layer: self.in_layer((c, r), 1),
            nearest: planes::NearestSegments::default(),
            order: std::cell::OnceCell::new(),
            centre_codes: std::cell::OnceCell::new(),
            measured: near,
            row: r,
            fine_rows: &self.fine_rows,
            rows_of: &rows_of,
            centre_bits: self.centre_bits.get_or_init(|| {
                // The same sweeps as the lattice points', half a cell on.
                let (cx, cy) = (ox + h / 2.0, oy + h / 2.0);
                planes::CentreBits {
                    inside: fill_bits(&g.fills, cx, cy, h, nx, ny),
                    occluded: fill_bits(&g.occluders, cx, cy, h, nx, ny),
                    clips: g.clips.iter().map(|c| fill_bits(&[*c], cx, cy, h, nx, ny)).collect(),
                }
            }),
        };
        match (self.write(&tile, centres, &exact, tile_buf, refine), saturated) {
            // A plane saturated at the tile's four corners is saturated
            // over it (an affine function's extremes are at the corners).
            (TileOut::Record(entry, rec), Some(constant))
                if entry & TILE_RIDGE == TILE_PLANE && self.plane_saturated(&rec, constant) =>
            {
                TileOut::Constant(constant)
            }
            (out, _) => out,
        }
    }

    /// The codes of tile `(c, r)`'s samples (of its `bucket`, from its
    /// `corner`), and their unquantised distances in codes (clamped).
    #[inline]
    fn measure(
        &self,
        near: &mut Near,
        bucket: &[u32],
        corner: (f64, f64),
        (c, r): (usize, usize),
    ) -> ([u8; TILE_SAMPLES], [f64; TILE_SAMPLES]) {
        let (g, nx, pg) = (self.g, self.nx, self.s.page);
        let (h, step, cap, margin) = (self.s.h, self.s.step, self.s.cap, self.margin);
        // What each sample is inside of.
        let (mut inside_t, mut occluded_t) = ([false; TILE_SAMPLES], [false; TILE_SAMPLES]);
        let mut in_clip = vec![false; self.clip_bits.len() * TILE_SAMPLES];
        for t in 0..TILE_SAMPLES {
            let k = (r * TILE_CELLS + t / TILE_SIDE) * nx + c * TILE_CELLS + t % TILE_SIDE;
            (inside_t[t], occluded_t[t]) = (self.inside[k], self.occluded[k]);
            for (q, b) in self.clip_bits.iter().enumerate() {
                in_clip[q * TILE_SAMPLES + t] = b[k];
            }
        }
        let bits = near::TileBits { inside: &inside_t, occluded: &occluded_t, in_clip: &in_clip, cap };
        near.measure_live(g, self.segs, bucket, (corner, h, margin), &bits, self.in_layer((c, r), 0), false);
        let mut tile_buf = [0u8; TILE_SAMPLES];
        // The unquantised distances of the tile's samples, in codes (clamped).
        let mut exact = [0f64; TILE_SAMPLES];
        let mut clipped = vec![false; self.clip_bits.len()];
        for j in 0..TILE_SIDE {
            for i in 0..TILE_SIDE {
                let (gi, gj) = (c * TILE_CELLS + i, r * TILE_CELLS + j);
                let p = self.s.at(gi, gj);
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
        (tile_buf, exact)
    }

    /// The first kind that plays `tile` (its samples' distances `exact`,
    /// their codes `tile_buf`) within half a code, checked at the cell
    /// centres with `centres`: a plane or ridge, else a corner or notch, a
    /// bend, an arc, a segments tile or a cut arc, else its samples
    /// ([`Build::stored`]). Where a plane, ridge, corner or band's bend
    /// plays a circle's chords, the circle plays instead if it can.
    fn write(
        &self,
        tile: &planes::TileCtx<'_, '_>,
        centres: &mut Near,
        exact: &[f64; TILE_SAMPLES],
        tile_buf: [u8; TILE_SAMPLES],
        refine: bool,
    ) -> TileOut {
        let sat = self.sat;
        let lines = planes::nearest_lines(tile, exact);
        let fitted = planes::fit(exact, self.ridge_top, sat, &lines)
            .into_iter()
            .find(|(e, rec)| tile.centres_fit(centres, *e, rec));
        // The kinds below play two lines, a circle or up to three segments:
        // where hundreds of segments lie within the tile's reach (a map
        // drawn far finer than the lattice) they are not tried.
        let crowded = self.crowded(tile.bucket);
        if let Some((entry, rec)) = fitted {
            // A plane or ridge is exact on a straight edge. Where the edge is
            // a circle's arc (a tile the arc only grazes), it is within half
            // a code at the checked points, but between them off by the
            // arc's sagitta, up to half a code more (20 steps at an actuator
            // on the experiment-5 circle's band at the default pitch): the
            // circle, where one plays the tile, is exact everywhere.
            if !crowded && let Some((kind, r)) = self.circle(tile, centres, exact) {
                return TileOut::Bend(kind, r);
            }
            return TileOut::Record(entry, rec);
        }
        if crowded {
            return self.stored(tile, centres, tile_buf, refine);
        }
        // Two straight edges meeting at a vertex: a corner or a notch.
        let bent = bends::bends(tile, exact, self.ramp)
            .into_iter()
            .find(|b| tile.centres_all(centres, |u, w, e| b.close(u, w, e, sat)));
        if let Some(b) = bent {
            // Two chords of a flattened circle: the circle, where it plays the tile.
            if let Some((kind, r)) = self.flattened_arc(tile, centres, exact) {
                return TileOut::Bend(kind, r);
            }
            return TileOut::Bend(b.kind, b.recs);
        }
        // A band's centre line bent at a vertex, or its end.
        let band_bent = bends::band_bends(tile, exact).into_iter().find(|r| {
            tile.centres_all(centres, |u, w, e| {
                sat.close(taxel_format::bend_code([&r[0], &r[1]], u, w) - DISTANCE_ZERO as f64, e)
            })
        });
        if let Some(r) = band_bent {
            // A band round a flattened circle: the circle, where it plays the tile.
            if let Some((kind, r)) = self.flattened_arc(tile, centres, exact) {
                return TileOut::Bend(kind, r);
            }
            return TileOut::Bend(taxel_format::TILE_BEND, r);
        }
        // A circular arc: the cone round its centre as a bend tile, else an arc tile.
        if let Some((kind, r)) = self.circle(tile, centres, exact) {
            return TileOut::Bend(kind, r);
        }
        // Where band centre lines meet: the nearest of up to three segments.
        let joined = junctions::segment_tiles(tile, exact).into_iter().find(|r| {
            let [s0, s1, s2, last] = r;
            tile.centres_all(centres, |u, w, e| {
                sat.close(taxel_format::segments_code([s0, s1, s2, last], u, w) - DISTANCE_ZERO as f64, e)
            })
        });
        if let Some(r) = joined {
            return TileOut::Segments(r);
        }
        // A fill's straight side and a circular hole in it: a cut arc (format 4.3).
        let cut = cut_arcs::cut_arcs(tile, exact)
            .into_iter()
            .find(|cut| tile.centres_all(centres, |u, w, e| cut.close(u, w, e, sat)));
        if let Some(cut) = cut {
            return TileOut::Bend(taxel_format::TILE_ARC, cut.recs);
        }
        self.stored(tile, centres, tile_buf, refine)
    }

    /// The first circle ([`arcs::circles`]) that plays the tile within half
    /// a code at its samples and cell centres: its index kind and records.
    fn circle(
        &self,
        tile: &planes::TileCtx<'_, '_>,
        centres: &mut Near,
        exact: &[f64; TILE_SAMPLES],
    ) -> Option<(u32, [TilePlane; 2])> {
        self.first_at_centres(tile, centres, arcs::circles(tile, exact))
    }

    /// [`Build::circle`] for a tile whose nearest segments are a flattened
    /// circular arc ([`arcs::flattened_arc_circles`]).
    fn flattened_arc(
        &self,
        tile: &planes::TileCtx<'_, '_>,
        centres: &mut Near,
        exact: &[f64; TILE_SAMPLES],
    ) -> Option<(u32, [TilePlane; 2])> {
        self.first_at_centres(tile, centres, arcs::flattened_arc_circles(tile, exact))
    }

    /// The first of `circles` that plays the tile within half a code at its cell centres.
    fn first_at_centres(
        &self,
        tile: &planes::TileCtx<'_, '_>,
        centres: &mut Near,
        circles: Vec<(u32, [TilePlane; 2])>,
    ) -> Option<(u32, [TilePlane; 2])> {
        let sat = self.sat;
        circles.into_iter().find(|(kind, r)| {
            let entry = taxel_format::TileEntry::of(*kind);
            tile.centres_all(centres, |u, w, e| {
                entry.code(r, u, w).is_some_and(|code| sat.close(code - DISTANCE_ZERO as f64, e))
            })
        })
    }

    /// A tile no other kind plays: its samples, finer where the lattice's
    /// misplace the edge (format 4.4), on a second pass (`refine`) within the
    /// layer's budget.
    fn stored(
        &self,
        tile: &planes::TileCtx<'_, '_>,
        centres: &mut Near,
        buf: [u8; TILE_SAMPLES],
        refine: bool,
    ) -> TileOut {
        if refine {
            match fine::refine(tile, centres, &buf) {
                Some(f) => TileOut::Fine(f, buf),
                None => TileOut::Samples(buf),
            }
        } else if !self.crowded(tile.bucket) && tile.bucket.len().saturating_mul(FINE_POINTS) <= FINE_WORK {
            match fine::priority(tile, centres, &buf) {
                Some(p) => TileOut::Refinable(buf, p),
                None => TileOut::Samples(buf),
            }
        } else {
            TileOut::Samples(buf)
        }
    }

    /// Fine tiles (format 4.4) where stored tiles misplace the edge, the
    /// worst first, while they add no more bytes than the layer has without
    /// them (or [`FINE_BUDGET_FLOOR`]): refining every tile of a map drawn
    /// finer than the lattice (a thousand regions on the device) would take
    /// megabytes. A round of refinements that adds none ends the search.
    fn refine(&self, outs: &mut [TileOut]) {
        let cols = self.s.tiles.cols;
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
        let work_per = |k: usize| self.buckets.get(k).map_or(0, Vec::len).saturating_mul(FINE_POINTS);
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
                chunk
                    .par_iter()
                    .map_init(|| self.scratch(), |s, &(_, k)| (k, self.tile(s, k / cols, k % cols, true)))
                    .collect()
            } else {
                let mut s = self.scratch();
                chunk.iter().map(|&(_, k)| (k, self.tile(&mut s, k / cols, k % cols, true))).collect()
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
    }
}

/// A record's four values to 20 significant bits (the nearest; the low four
/// bits of each `f32` zero), so that the stored form's DEFLATE spends less
/// on noise (SPEC.md 15; issue 46 point 4). Each value moves by at most
/// 2^-20 of itself: on `tala-map`'s records (`c` to 800 codes, gradients
/// to 63 codes a cell, vertices and centres within a few hundred cells) a
/// code moves by at most 0.002 of a code, some 0.00002 mm at its step of
/// 0.008 mm. (At 16 bits the file was 270 bytes smaller, but the default
/// rung's edge error on `tala-map` went from 0.0033 to 0.0137 mm.)
fn twenty_bits(r: TilePlane) -> TilePlane {
    let round = |v: f32| if v.is_finite() { f32::from_bits(v.to_bits().wrapping_add(0x8) & !0xF) } else { v };
    TilePlane { c: round(r.c), gx: round(r.gx), gy: round(r.gy), top: round(r.top) }
}

/// The `n` tiles `outs` numbered in order: the tile index, the records and
/// the stored samples; `None` when every tile is outside.
fn number(outs: Vec<TileOut>, n: usize) -> Option<(Vec<u32>, Vec<TilePlane>, Vec<u8>)> {
    let mut tiles = vec![TILE_OUTSIDE; n];
    let mut samples = Vec::new();
    let mut planes = Vec::new();
    for (entry, out) in tiles.iter_mut().zip(outs) {
        *entry = match out {
            TileOut::Constant(e) => e,
            TileOut::Record(kind, rec) => {
                let n = planes.len() as u32;
                planes.push(twenty_bits(rec));
                kind | n
            }
            TileOut::Bend(kind, recs) => {
                let n = planes.len() as u32;
                planes.extend(recs.map(twenty_bits));
                kind | n
            }
            TileOut::Segments(recs) => {
                let n = planes.len() as u32;
                planes.extend(recs.map(twenty_bits));
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
    Some((tiles, planes, samples))
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
