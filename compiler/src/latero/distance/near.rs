//! The nearest segment of each part of a layer at every sample of one tile:
//! the innermost loop of the field build.
//!
//! Two ways to the same minima, chosen per tile by how many segments act on
//! it. A few segments are measured segment by segment at the samples within
//! their reach. Many short ones (a map of thousands of small regions puts a
//! thousand segments on a tile) go into a grid of the tile's cells, and each
//! sample searches that grid ring by ring outward, stopping once no farther
//! segment can be nearer than the nearest found or within reach: a sample
//! then measures the few segments around it instead of every segment whose
//! reach covers it.
//!
//! Both store, for each part, the same minimum wherever it is within the part's
//! reach plus the clamp's margin (the minimum of one set of values, each
//! computed by the same function of the same sample point and segment), and a
//! value beyond it elsewhere, which clamps to the same code. So the field, its
//! tiles and the bundle do not depend on which way a tile took.
//!
//! The parts that only lower a layer's distance (cut bands, clips,
//! occluders) are measured only at the samples where they can still change
//! its code, once the layer's own fills and band are known there: outside a
//! grating's regions (or far from a band) nothing lowers a distance that is
//! already clamped, and a cut band or an edge that is not crossed cannot lower
//! a distance below what the regions give.

use taxel_format::{TILE_CELLS, TILE_SAMPLES, TILE_SIDE};

use super::layer_grid::{BAND, FILL, FIRST_CUT, LayerGrid, OCC, floor_cell, row_cells};
use super::{LayerGeometry, Part, Seg, distance2_to_segment};

/// From this many segments of a group (the layer's own parts, or the
/// others) on a tile, the samples search a grid of them: below it, building
/// the grid costs more than it saves (measured on the generated maps of 1,000
/// and 10,000 regions: 48, 128 and 400 were within the noise of each other on
/// the denser map, and 128 the fastest on the sparser).
pub(super) const GRID_FROM: usize = 128;

/// The most rings of cells a sample's search may need, else the tile is
/// measured segment by segment.
pub(super) const MAX_RINGS: f64 = 64.0;

/// What the samples of one tile are inside of, for deciding where the parts
/// that only lower the distance can change it.
pub(super) struct TileBits<'a> {
    /// Inside the fills, per sample.
    pub inside: &'a [bool; TILE_SAMPLES],
    /// Inside an occluder, per sample.
    pub occluded: &'a [bool; TILE_SAMPLES],
    /// Inside clip `k`, at `k * TILE_SAMPLES + t`.
    pub in_clip: &'a [bool],
    /// The clamp, mm.
    pub cap: f64,
}

/// The nearest segments of each part at every sample of one tile, as squared
/// distances (the cuts per width group), and the scratch to find them.
pub(super) struct Near {
    /// Squared distances, `TILE_SAMPLES` per slot.
    d: Vec<f64>,
    /// The width of each cut group, mm.
    cut_widths: Vec<f64>,
    /// Number of clip regions.
    clips: usize,
    /// Whether a slot is still measured at a sample (`TILE_SAMPLES` per slot).
    live: Vec<bool>,
    /// The grid of the sample-major search.
    grid: Grid,
    /// The slot of each bucket entry, and each slot's reach plus margin.
    slot_of: Vec<usize>,
    reach: Vec<f64>,
    /// The layer grid's search: `in_tile[n] == tile_mark` for the
    /// segments `n` of the tile being searched (its bucket), set once per
    /// tile so that each segment a sample meets is kept or passed over with
    /// one load (reckoning its tiles again per visit was half the build of
    /// a scribble whose cells hold hundreds of segments).
    in_tile: Vec<u32>,
    tile_mark: u32,
}

/// Grid cells per lattice cell along each axis: half cells, so that a sample
/// whose nearest segment is close searches a small square.
const SUB: isize = super::layer_grid::SUB as isize;

/// Segments by cells of the tile (cell `(x, y)` spans `[x, x + 1) h / SUB`
/// from the tile's first sample, for `x` in `-pad..TILE_CELLS * SUB + pad`),
/// each in every cell its bounding box meets, as compressed rows.
#[derive(Default)]
struct Grid {
    pad: isize,
    side: usize,
    start: Vec<u32>,
    items: Vec<u32>,
    /// Scratch: each entry's cell range, `None` when not in this grid.
    ranges: Vec<Option<Binned>>,
}

/// Whether sample `t` is in a tile's last lattice row or column: on a
/// lattice shifted half a cell, past the tile's cell centres.
fn past_centres(t: usize) -> bool {
    t % TILE_SIDE == TILE_CELLS || t / TILE_SIDE == TILE_CELLS
}

/// A segment in a tile's grid: its ends in cell units (the grid's padding
/// added) and its box's cells `[x0, y0, x1, y1]`.
type Binned = ((f64, f64), (f64, f64), [isize; 4]);

impl Grid {
    /// Fills the grid with the `n` entries whose segments in cell units
    /// (from the tile's corner) `cells(k)` gives (`None`: not in this grid),
    /// each in the cells it passes through ([`row_cells`]).
    fn fill(&mut self, pad: isize, n: usize, cells: impl Fn(usize) -> Option<((f64, f64), (f64, f64))>) {
        self.pad = pad;
        let side = TILE_CELLS as isize * SUB + 2 * pad;
        self.side = side as usize;
        self.ranges.clear();
        self.ranges.extend((0..n).map(|k| {
            let (a, b) = cells(k)?;
            let (x0, y0) = (floor_cell(a.0.min(b.0)), floor_cell(a.1.min(b.1)));
            let (x1, y1) = (floor_cell(a.0.max(b.0)), floor_cell(a.1.max(b.1)));
            let (x0, y0, x1, y1) =
                ((x0 + pad).max(0), (y0 + pad).max(0), (x1 + pad).min(side - 1), (y1 + pad).min(side - 1));
            let shift = pad as f64;
            (x0 <= x1 && y0 <= y1).then_some(((a.0 + shift, a.1 + shift), (b.0 + shift, b.1 + shift), [x0, y0, x1, y1]))
        }));
        let spans =
            |&(a, b, [x0, y0, x1, y1]): &Binned| (y0..=y1).map(move |y| (y as usize, row_cells(a, b, y, (x0, x1))));
        self.start.clear();
        self.start.resize(self.side * self.side + 1, 0);
        for r in self.ranges.iter().flatten() {
            for (y, (x0, x1)) in spans(r).filter(|(_, (x0, x1))| x0 <= x1) {
                let (x0, x1) = (x0 as usize, x1 as usize);
                for c in &mut self.start[y * self.side + x0 + 1..=y * self.side + x1 + 1] {
                    *c += 1;
                }
            }
        }
        for c in 1..self.start.len() {
            self.start[c] += self.start[c - 1];
        }
        self.items.clear();
        self.items.resize(self.start.last().map_or(0, |&v| v as usize), 0);
        // Filled back to front, each cell's end counting down to its start.
        let mut end: Vec<u32> = self.start[1..].to_vec();
        for (k, r) in self.ranges.iter().enumerate().rev() {
            let Some(r) = r.as_ref() else { continue };
            for (y, (x0, x1)) in spans(r).filter(|(_, (x0, x1))| x0 <= x1) {
                for x in x0 as usize..=x1 as usize {
                    let e = &mut end[y * self.side + x];
                    *e -= 1;
                    self.items[*e as usize] = k as u32;
                }
            }
        }
    }

    /// The entries in cell `(x, y)` (tile cell coordinates).
    fn cell(&self, x: isize, y: isize) -> &[u32] {
        let (x, y) = (x + self.pad, y + self.pad);
        if x < 0 || y < 0 || x as usize >= self.side || y as usize >= self.side {
            return &[];
        }
        let c = y as usize * self.side + x as usize;
        match (self.start.get(c), self.start.get(c + 1)) {
            (Some(&a), Some(&b)) => self.items.get(a as usize..b as usize).unwrap_or(&[]),
            _ => &[],
        }
    }
}

/// Where a tile lies in its layer's grid: the grid, the tile `(c, r)`, and
/// the offset of its samples in grid cells (1 for the cell centres, half a
/// lattice cell on).
#[derive(Clone, Copy)]
pub(super) struct InLayer<'a> {
    pub grid: &'a LayerGrid,
    pub tile: (usize, usize),
    pub shift: isize,
}

/// What the sample-major search of one tile reads.
struct Search<'a> {
    segs: &'a [(Seg, Part, f64)],
    bucket: &'a [u32],
    slot_of: &'a [usize],
    /// Grid cell side, mm, and the last ring to search.
    cell: f64,
    rings: isize,
}

/// The slot of a part in a layer of `cuts` cut width groups and `clips`
/// clip regions, `None` for a group or clip it does not have.
pub(super) fn slot_of(part: Part, cuts: usize, clips: usize) -> Option<usize> {
    match part {
        Part::Fill => Some(FILL),
        Part::Band => Some(BAND),
        Part::Occluder => Some(OCC),
        Part::Cut(k) => (k < cuts).then_some(FIRST_CUT + k),
        Part::Clip(k) => (k < clips).then_some(FIRST_CUT + cuts + k),
    }
}

/// The slot of a part in a layer of `slots` slots and `clips` clip regions.
pub(super) fn slot_in_layer(part: Part, slots: usize, clips: usize) -> Option<usize> {
    slot_of(part, slots.checked_sub(FIRST_CUT + clips)?, clips)
}

/// The number of slots of a layer of `cuts` cut width groups and `clips` clip regions.
pub(super) fn slots(cuts: usize, clips: usize) -> usize {
    FIRST_CUT + cuts + clips
}

impl Near {
    pub(super) fn new(clips: usize, cut_widths: Vec<f64>) -> Self {
        let slots = FIRST_CUT + cut_widths.len() + clips;
        Near {
            d: vec![f64::INFINITY; slots * TILE_SAMPLES],
            cut_widths,
            clips,
            live: vec![true; slots * TILE_SAMPLES],
            grid: Grid::default(),
            slot_of: Vec::new(),
            in_tile: Vec::new(),
            tile_mark: 0,
            reach: vec![0.0; slots],
        }
    }

    fn slots(&self) -> usize {
        FIRST_CUT + self.cut_widths.len() + self.clips
    }

    /// The slot of a part, `None` for a cut group or clip this layer does not have.
    fn slot(&self, part: Part) -> Option<usize> {
        slot_of(part, self.cut_widths.len(), self.clips)
    }

    fn at(&self, slot: usize, t: usize) -> f64 {
        self.d.get(slot * TILE_SAMPLES + t).copied().unwrap_or(f64::INFINITY)
    }

    /// The least squared distance from sample `t` to the `part` segments
    /// of the tile's bucket, where the last measure is sure of it: where
    /// the value stored is within the part's reach plus the margin (less a
    /// millionth, far above the rounding of the search's bounds), it is that
    /// minimum; elsewhere (beyond the reach, or where the part was not
    /// measured) `None`.
    pub(super) fn least(&self, part: Part, t: usize) -> Option<f64> {
        let slot = self.slot(part)?;
        let (d, r) = (self.at(slot, t), *self.reach.get(slot)?);
        (d <= r * r * (1.0 - 1e-6)).then_some(d)
    }

    /// How many of the parts (the fills, the band, the occluders, each cut
    /// width group and each clip) have an edge within `within` mm of one of
    /// the tile's samples, where the last measure is sure of it: a cut's
    /// edge is its centre line's distance less its half width. Two or more
    /// may meet inside a cell, where a stored tile rounds their crease.
    pub(super) fn edges_within(&self, within: f64) -> usize {
        (0..self.slots())
            .filter(|&slot| {
                let r = self.reach.get(slot).copied().unwrap_or(0.0);
                let half = slot.checked_sub(FIRST_CUT).and_then(|k| self.cut_widths.get(k)).map_or(0.0, |w| w / 2.0);
                (0..TILE_SAMPLES).any(|t| {
                    let d2 = self.at(slot, t);
                    d2 <= r * r * (1.0 - 1e-6) && (d2.sqrt() - half).abs() <= within
                })
            })
            .count()
    }

    /// Measures every part at the tile's samples (corner `corner`, pitch
    /// `h`), each segment within its reach plus `margin`, with the segment
    /// sweep whatever the
    /// number of segments (a fine tile's cells: few segments each, and a
    /// reach of many of their pitches, which the grid search walks ring by
    /// ring).
    pub(super) fn measure_swept(
        &mut self,
        segs: &[(Seg, Part, f64)],
        bucket: &[u32],
        (corner, h, margin): ((f64, f64), f64, f64),
    ) {
        self.run(segs, bucket, (corner, h, margin), None, None, (usize::MAX, false));
    }

    /// Measures every part at the tile's samples (corner `corner`, pitch
    /// `h`), each segment within its reach plus `margin`, the grid search
    /// for crowded groups (the layer's grid where it has one, `layer`); the
    /// parts that only lower the distance (cuts, clips, occluders) only
    /// where, given the layer's own parts and what each sample is inside of
    /// (`bits`), they can change the clamped distance; elsewhere their slots
    /// are left infinite. With `centres`, the lattice is one shifted half a
    /// cell and only a tile's 64 cell centres are measured: the samples of
    /// its last row and column, past the centres, read infinite.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn measure_live(
        &mut self,
        g: &LayerGeometry<'_>,
        segs: &[(Seg, Part, f64)],
        bucket: &[u32],
        (corner, h, margin): ((f64, f64), f64, f64),
        bits: &TileBits<'_>,
        layer: Option<InLayer<'_>>,
        centres: bool,
    ) {
        self.run(segs, bucket, (corner, h, margin), Some((g, bits)), layer, (GRID_FROM, centres));
    }

    /// Measures, with the grid search for groups of at least `grid_from`
    /// segments: the layer's grid where it has one (`layer`), else the
    /// tile's own; at the cell centres only where `centres` (the samples
    /// of the last row and column are not live in any slot).
    fn run(
        &mut self,
        segs: &[(Seg, Part, f64)],
        bucket: &[u32],
        (corner, h, margin): ((f64, f64), f64, f64),
        live: Option<(&LayerGeometry<'_>, &TileBits<'_>)>,
        layer: Option<InLayer<'_>>,
        (grid_from, centres): (usize, bool),
    ) {
        self.d.fill(f64::INFINITY);
        self.live.fill(true);
        if centres {
            for (k, l) in self.live.iter_mut().enumerate() {
                *l = !past_centres(k % TILE_SAMPLES);
            }
        }
        // Each entry's slot (`usize::MAX`: none) and each slot's reach.
        self.slot_of.clear();
        self.reach.clear();
        self.reach.resize(self.slots(), 0.0);
        let own = |s: usize| s == FILL || s == BAND;
        let mut finite = true;
        let (n_own, n_rest) = match layer {
            // The layer's grid counted the tile's entries and has one reach
            // per slot (and only finite segments).
            Some(at) if at.grid.reach.len() == self.slots() => {
                let t = at.grid.tile(at.tile);
                for (s, r) in self.reach.iter_mut().enumerate() {
                    if t.slots & (1 << s) != 0 {
                        *r = at.grid.reach[s];
                    }
                }
                (t.own as usize, t.rest as usize)
            }
            _ => {
                for &n in bucket {
                    let found =
                        segs.get(n as usize).and_then(|&(seg, part, reach)| Some((seg, self.slot(part)?, reach)));
                    match found {
                        Some((((ax, ay), (bx, by)), slot, reach)) => {
                            finite &= [ax, ay, bx, by, reach].iter().all(|v| v.is_finite());
                            self.reach[slot] = self.reach[slot].max(reach + margin);
                            self.slot_of.push(slot);
                        }
                        None => self.slot_of.push(usize::MAX),
                    }
                }
                let n_own = self.slot_of.iter().filter(|&&s| s != usize::MAX && own(s)).count();
                let n_rest = self.slot_of.iter().filter(|&&s| s != usize::MAX && !own(s)).count();
                (n_own, n_rest)
            }
        };
        let layer = layer.filter(|at| at.grid.reach.len() == self.slots());
        // The layer's own parts first (the others are live only where these
        // leave the distance within reach of a change), each group the way
        // its number of segments makes cheaper.
        // A grid only for finite segments, slots that fit the search's
        // bit mask, and a reach of a bounded number of cells (a band much
        // wider than the lattice pitch would make the grid large).
        let fits = |own_group: bool| {
            let reach = (0..self.slots()).filter(|&s| own(s) == own_group).map(|s| self.reach[s]).fold(0.0, f64::max);
            finite && h > 0.0 && self.slots() < 64 && reach / (h / SUB as f64) <= MAX_RINGS
        };
        let grid = (fits(true), fits(false));
        if n_own >= grid_from && grid.0 {
            match layer {
                Some(at) => self.search_layer(segs, bucket, at, (corner, h), true),
                None => self.search(segs, bucket, corner, h, true),
            }
        } else {
            self.sweep(segs, bucket, corner, h, margin, &|s| own(s));
        }
        if let Some((g, bits)) = live {
            self.mark_live(g, bits, (0..TILE_SAMPLES).filter(|&t| !(centres && past_centres(t))));
        }
        if n_rest >= grid_from && grid.1 {
            match layer {
                Some(at) => self.search_layer(segs, bucket, at, (corner, h), false),
                None => self.search(segs, bucket, corner, h, false),
            }
        } else {
            self.sweep(segs, bucket, corner, h, margin, &|s| !own(s));
        }
    }

    /// Segment-major: each entry of a wanted slot at the tile's samples
    /// within its reach plus `margin` where its slot is live.
    fn sweep(
        &mut self,
        segs: &[(Seg, Part, f64)],
        bucket: &[u32],
        corner: (f64, f64),
        h: f64,
        margin: f64,
        want: &dyn Fn(usize) -> bool,
    ) {
        let last = TILE_CELLS as f64;
        // The sample range `lo..=hi` (within the tile) of a span grown by `m`.
        let range = |lo: f64, hi: f64, o: f64, m: f64| {
            let a = super::floor_f64((lo - m - o) / h).max(0.0);
            let b = super::ceil_f64((hi + m - o) / h).min(last);
            (a as usize, b as usize, a <= b)
        };
        for &n in bucket {
            let Some(&(seg, part, reach)) = segs.get(n as usize) else { continue };
            let Some(slot) = self.slot(part).filter(|&s| want(s)) else { continue };
            let (a, b) = seg;
            let bb = super::seg_bounds(&seg);
            let m = reach + margin;
            let (i0, i1, some_i) = range(bb.0, bb.2, corner.0, m);
            let (j0, j1, some_j) = range(bb.1, bb.3, corner.1, m);
            if !(some_i && some_j) {
                continue;
            }
            let (Some(out), Some(live)) = (
                self.d.get_mut(slot * TILE_SAMPLES..(slot + 1) * TILE_SAMPLES),
                self.live.get(slot * TILE_SAMPLES..(slot + 1) * TILE_SAMPLES),
            ) else {
                continue;
            };
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let t = j * TILE_SIDE + i;
                    if live[t] {
                        let p = (corner.0 + i as f64 * h, corner.1 + j as f64 * h);
                        out[t] = out[t].min(distance2_to_segment(p, a, b));
                    }
                }
            }
        }
    }

    /// Sample-major, for the layer's own parts (`own`) or the others: each
    /// sample searches a grid of them ring by ring.
    fn search(&mut self, segs: &[(Seg, Part, f64)], bucket: &[u32], corner: (f64, f64), h: f64, own: bool) {
        let cell = h / SUB as f64;
        let mask = if own { (1u64 << FILL) | (1 << BAND) } else { ((1u64 << self.slots()) - 1) & !0b11 };
        let in_group = |s: usize| s < 64 && mask & (1 << s) != 0;
        let reach_max = (0..self.slots()).filter(|&s| in_group(s)).map(|s| self.reach[s]).fold(0.0, f64::max);
        // Rings up to `rings` see every segment within `reach_max`.
        let rings = (reach_max / cell).ceil() as isize + 1;
        let pad = rings + 1;
        let slot_of = std::mem::take(&mut self.slot_of);
        let mut grid = std::mem::take(&mut self.grid);
        grid.fill(pad, bucket.len(), |k| {
            let slot = *slot_of.get(k)?;
            let &(seg, _, _) = bucket.get(k).and_then(|&n| segs.get(n as usize))?;
            if !in_group(slot) {
                return None;
            }
            let c = |p: (f64, f64)| ((p.0 - corner.0) / cell, (p.1 - corner.1) / cell);
            Some((c(seg.0), c(seg.1)))
        });
        let search = Search { segs, bucket, slot_of: &slot_of, cell, rings };
        for j in 0..TILE_SIDE {
            for i in 0..TILE_SIDE {
                let t = j * TILE_SIDE + i;
                let p = (corner.0 + i as f64 * h, corner.1 + j as f64 * h);
                self.nearest(&search, &grid, (i as isize * SUB, j as isize * SUB, t, p), mask);
            }
        }
        self.slot_of = slot_of;
        self.grid = grid;
    }

    /// As [`search`](Self::search), in the layer's grid: the same rings
    /// round the same samples, keeping from each cell the segments of this
    /// tile's bucket.
    fn search_layer(
        &mut self,
        segs: &[(Seg, Part, f64)],
        bucket: &[u32],
        at: InLayer<'_>,
        (corner, h): ((f64, f64), f64),
        own: bool,
    ) {
        let cell = h / SUB as f64;
        let mask = if own { (1u64 << FILL) | (1 << BAND) } else { ((1u64 << self.slots()) - 1) & !0b11 };
        let in_group = |s: usize| s < 64 && mask & (1 << s) != 0;
        let reach_max = (0..self.slots()).filter(|&s| in_group(s)).map(|s| self.reach[s]).fold(0.0, f64::max);
        let rings = (reach_max / cell).ceil() as isize + 1;
        self.mark_bucket(segs.len(), bucket);
        for j in 0..TILE_SIDE {
            for i in 0..TILE_SIDE {
                let t = j * TILE_SIDE + i;
                let p = (corner.0 + i as f64 * h, corner.1 + j as f64 * h);
                let xy = at.grid.corner(at.tile, (i as isize * SUB + at.shift, j as isize * SUB + at.shift));
                self.nearest_layer(segs, at.grid, (own, cell, rings), (xy, t, p), mask);
            }
        }
    }

    /// Marks the segments of `bucket` (of a layer of `n` segments) as the
    /// tile's: `in_tile[k] == tile_mark` for them alone.
    fn mark_bucket(&mut self, n: usize, bucket: &[u32]) {
        self.tile_mark = self.tile_mark.wrapping_add(1);
        if self.tile_mark == 0 || self.in_tile.len() != n {
            // A new layer, or the marks wrapped: none is left that could match.
            self.in_tile.clear();
            self.in_tile.resize(n, 0);
            self.tile_mark = 1;
        }
        for &k in bucket {
            if let Some(m) = self.in_tile.get_mut(k as usize) {
                *m = self.tile_mark;
            }
        }
    }

    /// [`nearest`](Self::nearest) in the layer's grid for sample `t` (stored
    /// cell corner `xy`, page point `p`), keeping only the entries of the
    /// tile's bucket ([`mark_bucket`](Self::mark_bucket)).
    fn nearest_layer(
        &mut self,
        segs: &[(Seg, Part, f64)],
        grid: &LayerGrid,
        (own, cell, rings): (bool, f64, isize),
        ((x, y), t, p): ((isize, isize), usize, (f64, f64)),
        mask: u64,
    ) {
        let mut active = self.live_slots(mask, t);
        if active == 0 {
            return;
        }
        let (d, in_tile, mark) = (&mut self.d, &self.in_tile, self.tile_mark);
        let visit = |items: &[u32], d: &mut [f64], active: u64| {
            for &n in items {
                if in_tile.get(n as usize) != Some(&mark) {
                    continue;
                }
                let Some(slot) = grid.slot_of_segment(n as usize) else { continue };
                if slot >= 64 || active & (1 << slot) == 0 {
                    continue;
                }
                let Some(&((a, b), _, _)) = segs.get(n as usize) else { continue };
                if let Some(v) = d.get_mut(slot * TILE_SAMPLES + t) {
                    *v = v.min(distance2_to_segment(p, a, b));
                }
            }
        };
        // The same cells as `nearest`'s rings, a ring's top and bottom rows
        // each as one slice of the grid (the order of the segments does
        // not change a minimum).
        for r in 0..=rings {
            visit(grid.row(own, y - 1 - r, x - 1 - r, x + r), d, active);
            visit(grid.row(own, y + r, x - 1 - r, x + r), d, active);
            for cy in y - r..y + r {
                visit(grid.cell(own, (x - 1 - r, cy)), d, active);
                visit(grid.cell(own, (x + r, cy)), d, active);
            }
            let next = (r as f64 + 0.99) * cell;
            let mut bits = active;
            while bits != 0 {
                let slot = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let best = d.get(slot * TILE_SAMPLES + t).copied().unwrap_or(0.0);
                if best <= next * next || next > self.reach.get(slot).copied().unwrap_or(0.0) {
                    active &= !(1 << slot);
                }
            }
            if active == 0 {
                return;
            }
        }
    }

    /// The slots of `mask` still live at sample `t`.
    fn live_slots(&self, mask: u64, t: usize) -> u64 {
        let mut active = 0u64;
        let mut bits = mask;
        while bits != 0 {
            let slot = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            if self.live.get(slot * TILE_SAMPLES + t).copied().unwrap_or(false) {
                active |= 1 << slot;
            }
        }
        active
    }

    /// The nearest entries of `grid` to sample `t` (grid point `(x, y)`,
    /// page point `p`) in the slots of `mask` live there, searching rings
    /// of cells outward until every such slot has found a segment nearer
    /// than the next ring can hold, or the next ring lies beyond the slot's
    /// reach.
    fn nearest(&mut self, s: &Search<'_>, grid: &Grid, (x, y, t, p): (isize, isize, usize, (f64, f64)), mask: u64) {
        let mut active = self.live_slots(mask, t);
        if active == 0 {
            return;
        }
        let d = &mut self.d;
        let visit = |cx: isize, cy: isize, d: &mut [f64], active: u64| {
            for &k in grid.cell(cx, cy) {
                let Some(&slot) = s.slot_of.get(k as usize) else { continue };
                if slot >= 64 || active & (1 << slot) == 0 {
                    continue;
                }
                let Some(&((a, b), _, _)) = s.bucket.get(k as usize).and_then(|&n| s.segs.get(n as usize)) else {
                    continue;
                };
                if let Some(v) = d.get_mut(slot * TILE_SAMPLES + t) {
                    *v = v.min(distance2_to_segment(p, a, b));
                }
            }
        };
        for r in 0..=s.rings {
            if r == 0 {
                for (cx, cy) in [(x - 1, y - 1), (x, y - 1), (x - 1, y), (x, y)] {
                    visit(cx, cy, d, active);
                }
            } else {
                for cx in x - 1 - r..=x + r {
                    visit(cx, y - 1 - r, d, active);
                    visit(cx, y + r, d, active);
                }
                for cy in y - r..y + r {
                    visit(x - 1 - r, cy, d, active);
                    visit(x + r, cy, d, active);
                }
            }
            // Every segment not yet seen lies at least `next` from the
            // sample (its nearest point is in a cell of a later ring; the
            // hundredth of a cell covers the rounding of the cell bounds).
            let next = (r as f64 + 0.99) * s.cell;
            let mut bits = active;
            while bits != 0 {
                let slot = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let best = d.get(slot * TILE_SAMPLES + t).copied().unwrap_or(0.0);
                if best <= next * next || next > self.reach.get(slot).copied().unwrap_or(0.0) {
                    active &= !(1 << slot);
                }
            }
            if active == 0 {
                return;
            }
        }
    }

    /// Marks, at samples `ts`, the slots of the parts that only lower the
    /// distance as not live where they cannot change the clamped distance
    /// (the layer's own slots must be measured there already).
    fn mark_live(&mut self, g: &LayerGeometry<'_>, bits: &TileBits<'_>, ts: impl Iterator<Item = usize>) {
        for t in ts {
            let inside = bits.inside.get(t).copied().unwrap_or(false);
            let u = self.own(g, t, inside).min(bits.cap);
            // At or below −cap the distance clamps there whatever is lower.
            let dead = u <= -bits.cap;
            // A term `v` at or above `u` changes nothing: `min(s, v) = s`
            // when `s ≤ cap`, and both clamp to `cap` otherwise.
            let occluded = bits.occluded.get(t).copied().unwrap_or(false);
            self.set_live(OCC, t, !(dead || !occluded && u <= 0.0));
            for k in 0..self.cut_widths.len() {
                let w = self.cut_widths[k];
                self.set_live(FIRST_CUT + k, t, !(dead || u + w / 2.0 <= 0.0));
            }
            for k in 0..self.clips {
                let in_k = bits.in_clip.get(k * TILE_SAMPLES + t).copied().unwrap_or(false);
                self.set_live(FIRST_CUT + self.cut_widths.len() + k, t, !(dead || in_k && u <= 0.0));
            }
        }
    }

    fn set_live(&mut self, slot: usize, t: usize, v: bool) {
        if let Some(l) = self.live.get_mut(slot * TILE_SAMPLES + t) {
            *l = v;
        }
    }

    /// The layer's own signed distance at sample `t` (its fills and band),
    /// before the parts that only lower it.
    fn own(&self, g: &LayerGeometry<'_>, t: usize, inside: bool) -> f64 {
        let mut s = f64::NEG_INFINITY;
        if !g.fills.is_empty() {
            let d_fill = self.at(FILL, t).sqrt();
            s = if inside { d_fill } else { -d_fill };
        }
        if let Some((_, w)) = &g.band {
            s = s.max(w / 2.0 - self.at(BAND, t).sqrt());
        }
        s
    }

    /// The terms whose least is [`signed`](Self::signed) at sample `t`
    /// (page point `p`), in its order: the layer's own distance, each cut
    /// width group's, each clip's, the occluders' (if any) and the page's;
    /// `inside` says whether it is inside the fills and inside the
    /// occluders.
    pub(super) fn terms<'s>(
        &'s self,
        g: &LayerGeometry<'_>,
        t: usize,
        (inside, occluded): (bool, bool),
        in_clip: &'s [bool],
        p: (f64, f64),
        page: (f64, f64, f64, f64),
    ) -> impl Iterator<Item = f64> + 's {
        let cuts = self.cut_widths.iter().enumerate().map(move |(k, w)| self.at(FIRST_CUT + k, t).sqrt() - w / 2.0);
        let clips = in_clip.iter().enumerate().map(move |(k, &in_k)| {
            let d = self.at(FIRST_CUT + self.cut_widths.len() + k, t).sqrt();
            if in_k { d } else { -d }
        });
        let occluders = (!g.occluders.is_empty()).then(|| {
            let d_occ = self.at(OCC, t).sqrt();
            if occluded { -d_occ } else { d_occ }
        });
        std::iter::once(self.own(g, t, inside))
            .chain(cuts)
            .chain(clips)
            .chain(occluders)
            .chain(std::iter::once(super::inside_rect(page, p)))
    }

    /// The unclamped signed distance at sample `t` (page point `p`): the
    /// least of its [`terms`](Self::terms), taken in their order.
    pub(super) fn signed(
        &self,
        g: &LayerGeometry<'_>,
        t: usize,
        bits: (bool, bool),
        in_clip: &[bool],
        p: (f64, f64),
        page: (f64, f64, f64, f64),
    ) -> f64 {
        // (Never empty: the own distance and the page's are always there.)
        self.terms(g, t, bits, in_clip, p, page).reduce(f64::min).unwrap_or(f64::NEG_INFINITY)
    }
}

#[cfg(test)]
mod tests;
