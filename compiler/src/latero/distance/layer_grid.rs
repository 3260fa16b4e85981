//! One grid of a layer's segments for all its tiles' nearest-segment
//! searches.
//!
//! A crowded tile's samples search a grid of segments ring by ring
//! ([`Near`](super::near::Near)). Built per tile from the tile's bucket,
//! that grid cost as much as the searches on a dense map: every segment
//! acting on a tile was sorted into cells, so a segment was binned once for
//! every tile (and every centre check) its reach meets, and each bucket was
//! walked several times per tile. Here each segment is binned once, into
//! cells of half the lattice pitch over the whole layer, and a tile's search
//! keeps from a cell only the segments of its own bucket (a segment keeps
//! the span of tiles whose buckets hold it), so it finds the same minima as
//! the tile's own grid.
//!
//! (Tried and dropped: a Chebyshev distance transform of the occupied cells,
//! so that a search starts at the first ring that holds a segment. On the
//! 1,000-region map its two raster passes over every layer's cells cost
//! more than the empty cells they skip, and on the map at the input limit
//! every cell near a sample holds segments.)

use taxel_format::TILE_CELLS;

use super::{Part, Seg, Tiles, seg_bounds};

/// Grid cells per lattice cell along each axis (the per-tile grid's `SUB`).
pub(super) const SUB: usize = 2;

/// Slots of the squared-distance array, `TILE_SAMPLES` each: the fills, the
/// band and the occluders, then one per cut width group, then one per clip.
pub(super) const FILL: usize = 0;
pub(super) const BAND: usize = 1;
pub(super) const OCC: usize = 2;
pub(super) const FIRST_CUT: usize = 3;

/// `floor(v)` as an integer, for `|v|` within ±1e6 (clamped; NaN gives 0)
/// and without a call into libm.
pub(super) fn floor_cell(v: f64) -> isize {
    let v = v.clamp(-1e6, 1e6);
    let t = v as isize;
    if (t as f64) > v { t - 1 } else { t }
}

/// The cells of row `y` (the band `y <= v <= y + 1`, in cell units) that the
/// segment `a`-`b` (in cell units) passes through, within its box's columns
/// `[x0, x1]`: a long slanted segment is binned in the cells along it, not in
/// every cell of its box (a scribble's segments cross the whole drawing, and
/// binned by their boxes every cell held every segment). A few cells more
/// than it meets, never fewer, so a search finds the same minima.
pub(super) fn row_cells(a: (f64, f64), b: (f64, f64), y: isize, (x0, x1): (isize, isize)) -> (isize, isize) {
    let dy = b.1 - a.1;
    if dy == 0.0 || !dy.is_finite() {
        return (x0, x1);
    }
    let (ta, tb) = ((y as f64 - a.1) / dy, (y as f64 + 1.0 - a.1) / dy);
    let (lo, hi) = (ta.min(tb).max(0.0), ta.max(tb).min(1.0));
    // (NaN, from a segment whose ends lie a world apart, is taken whole.)
    if lo.partial_cmp(&hi).is_none_or(|o| o == std::cmp::Ordering::Greater) {
        return (x0, x1);
    }
    let (xa, xb) = (a.0 + lo * (b.0 - a.0), a.0 + hi * (b.0 - a.0));
    // A thousandth of a cell for the rounding of `lo`, `hi` and the products.
    const SLACK: f64 = 1e-3;
    let (c0, c1) = (floor_cell(xa.min(xb) - SLACK), floor_cell(xa.max(xb) + SLACK));
    (c0.max(x0), c1.min(x1))
}

/// The most cells a layer's grid may have per segment it holds (and at
/// most [`MAX_CELLS`] in all): a sparse layer on a large lattice keeps the
/// per-tile grids, whose size follows the tile's segments.
const CELLS_PER_SEGMENT: usize = 16;
/// A grid of up to this many cells is small whatever its segments.
const MIN_CELLS: usize = 1 << 16;
/// The most cells of a layer's grid (two `u32` and a `u16` each, per group).
const MAX_CELLS: usize = 1 << 22;

/// The most entries of one group's cells (256 MB of `u32`): past it
/// the per-tile grids, whose size follows each tile's segments, are used.
/// (Also keeps the counts within `u32`.)
const MAX_ITEMS: u64 = 1 << 26;

/// The part of a layer's slots a group holds: the layer's own fills and
/// band, or the parts that only lower its distance.
pub(super) fn is_own(slot: usize) -> bool {
    slot == FILL || slot == BAND
}

/// What the searches of one tile need to know of its bucket, counted once
/// per layer instead of per tile.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct TileStats {
    /// Entries of the layer's own slots, and of the others.
    pub own: u32,
    pub rest: u32,
    /// The slots with at least one entry (slot `s` at bit `s`).
    pub slots: u64,
}

/// A segment being binned, while the rows it spans are filled: its
/// number, its ends in stored cell units, its box's columns and last row.
struct Member {
    n: u32,
    a: (f64, f64),
    b: (f64, f64),
    cols: (isize, isize),
    last_row: usize,
}

/// One group's segments by cell (compressed rows).
#[derive(Debug, Default)]
pub(super) struct Cells {
    start: Vec<u32>,
    items: Vec<u32>,
}

/// Every segment of a layer by cells of half the lattice pitch, the two
/// groups (own, other) apart.
#[derive(Debug)]
pub(super) struct LayerGrid {
    /// The lattice's origin, and the cell side `h / SUB`, mm.
    pub origin: (f64, f64),
    pub cell: f64,
    /// Layer cell `x` (counted from the origin) is stored at column `x + pad`.
    pad: isize,
    width: usize,
    height: usize,
    cols: usize,
    /// The tiles, as the buckets count them.
    tiles: Tiles,
    /// Each segment's slot, and its span of tiles `[c0, c1, r0, r1]`
    /// (its tiles within: [`Tiles::row_cols`]).
    slot: Vec<u8>,
    span: Vec<[u16; 4]>,
    /// Per tile, row-major.
    pub stats: Vec<TileStats>,
    /// Each slot's reach plus the margin, the same for all its segments.
    pub reach: Vec<f64>,
    /// `[own, other]`.
    groups: [Cells; 2],
}

/// What [`LayerGrid::new`] needs of a layer besides its segments.
pub(super) struct Lattice {
    /// The tiles, as the buckets count them.
    pub tiles: Tiles,
    pub h: f64,
    /// The clamp's margin added to every reach, mm.
    pub margin: f64,
    /// The layer's slots: the slot of a part, `None` for one it does not have.
    pub slots: usize,
}

/// `members` (segment number, stored cells `[x0, y0, x1, y1]`) ordered by
/// their first row `y0`, those of one row in the order given: what a stable
/// sort by `y0` gives, by counting the rows (all below `height`) instead of
/// comparing (the sort was a fifth of the grid's build on a map of states,
/// issue 46).
fn by_first_row(members: &[(u32, [u32; 4])], height: usize) -> Vec<(u32, [u32; 4])> {
    let rows = height.max(1);
    let row = |c: &[u32; 4]| (c[1] as usize).min(rows - 1);
    let mut start = vec![0usize; rows + 1];
    for (_, c) in members {
        start[row(c) + 1] += 1;
    }
    for y in 1..start.len() {
        start[y] += start[y - 1];
    }
    let mut out = vec![(0, [0; 4]); members.len()];
    for &m in members {
        let y = row(&m.1);
        out[start[y]] = m;
        start[y] += 1;
    }
    out
}

impl LayerGrid {
    /// The grid of a layer's segments, with the tiles' buckets and each
    /// segment's span of tiles (both from [`buckets_of`](super::buckets_of)); `None` where the per-tile
    /// grids do as well or better: no tile crowded enough to search, a
    /// segment that is not finite, a slot whose segments reach differently,
    /// no spans (a lattice too wide for them), or more cells than the caps
    /// allow.
    pub(super) fn new(
        segs: &[(Seg, Part, f64)],
        (buckets, mut span): (&[Vec<u32>], Vec<[u16; 4]>),
        lat: &Lattice,
        slot_of: impl Fn(Part) -> Option<usize>,
        grid_from: usize,
        max_rings: f64,
    ) -> Option<LayerGrid> {
        let (cols, rows, h) = (lat.tiles.cols, lat.tiles.rows, lat.h);
        if !(h.is_finite() && h > 0.0) || lat.slots >= 64 || span.len() != segs.len() {
            return None;
        }
        let cell = h / SUB as f64;
        let mut stats = vec![TileStats::default(); cols.checked_mul(rows)?];
        let mut reach: Vec<Option<f64>> = vec![None; lat.slots];
        let mut slot = Vec::with_capacity(segs.len());
        for (&((a, b), part, m), sp) in segs.iter().zip(span.iter_mut()) {
            let Some(s) = slot_of(part).filter(|_| sp[0] <= sp[1] && sp[2] <= sp[3]) else {
                slot.push(u8::MAX);
                *sp = super::NO_TILES;
                continue;
            };
            if ![a.0, a.1, b.0, b.1, m].iter().all(|v| v.is_finite()) {
                return None;
            }
            // One reach per slot: a tile's is then its slots' reaches.
            let r = m + lat.margin;
            if !(r > 0.0 && r.is_finite()) {
                return None;
            }
            match reach[s] {
                Some(v) if v.to_bits() != r.to_bits() => return None,
                _ => reach[s] = Some(r),
            }
            slot.push(s as u8);
        }
        // Counted from the buckets, which hold each segment in the tiles
        // its span's rows give it ([`Tiles::row_cols`]): working those out
        // again here was a tenth of the grid's build on a map of states
        // (issue 46).
        if buckets.len() != stats.len() {
            return None;
        }
        for (t, bucket) in stats.iter_mut().zip(buckets) {
            for &n in bucket {
                let Some(&s) = slot.get(n as usize).filter(|&&s| s != u8::MAX) else { continue };
                if is_own(usize::from(s)) {
                    t.own += 1;
                } else {
                    t.rest += 1;
                }
                t.slots |= 1 << s;
            }
        }
        let reach: Vec<f64> = reach.into_iter().map(|r| r.unwrap_or(0.0)).collect();
        let searched = |own: bool| stats.iter().any(|t| (if own { t.own } else { t.rest }) as usize >= grid_from);
        let wanted = [searched(true), searched(false)];
        if !(wanted[0] || wanted[1]) {
            return None;
        }
        let reach_max = reach.iter().copied().fold(0.0, f64::max);
        if reach_max / cell > max_rings {
            return None;
        }
        // Samples sit at cell corners 0..=SUB * TILE_CELLS * cols (cell
        // centres one further), and a search reaches `rings + 1` cells past.
        let rings = (reach_max / cell).ceil() as isize + 1;
        let pad = rings + 2;
        let width = (SUB * TILE_CELLS).checked_mul(cols)? + 2 + 2 * pad as usize;
        let height = (SUB * TILE_CELLS).checked_mul(rows)? + 2 + 2 * pad as usize;
        let cells = width.checked_mul(height)?;
        if cells > MAX_CELLS || cells > CELLS_PER_SEGMENT.saturating_mul(segs.len()).max(MIN_CELLS) {
            return None;
        }
        let mut grid = LayerGrid {
            origin: lat.tiles.origin,
            tiles: lat.tiles,
            cell,
            pad,
            width,
            height,
            cols,
            slot,
            span,
            stats,
            reach,
            groups: [Cells::default(), Cells::default()],
        };
        for (g, &want) in wanted.iter().enumerate() {
            if want {
                grid.groups[g] = grid.bin(segs, g == 0)?;
            }
        }
        Some(grid)
    }

    /// The stored cell range `[x0, y0, x1, y1]` a segment's bounds meet.
    fn cells_of(&self, seg: &Seg) -> [usize; 4] {
        let b = seg_bounds(seg);
        let c =
            |v: f64, o: f64, n: usize| (floor_cell((v - o) / self.cell) + self.pad).clamp(0, n as isize - 1) as usize;
        let (ox, oy) = self.origin;
        [c(b.0, ox, self.width), c(b.1, oy, self.height), c(b.2, ox, self.width), c(b.3, oy, self.height)]
    }

    /// The segments of one group (`own` or the others) that act on some
    /// tile, in every cell their bounds meet, in segment order; `None`
    /// past [`MAX_ITEMS`] entries.
    fn bin(&self, segs: &[(Seg, Part, f64)], own: bool) -> Option<Cells> {
        let n_cells = self.width * self.height;
        let in_group = |s: u8| s != u8::MAX && is_own(s as usize) == own;
        // Each member's cells are reckoned once and kept for both passes,
        // in 32 bits (the grid has at most `MAX_CELLS` cells, so each side
        // fits): reckoning them again cost as much as the rest of the
        // binning. The same records, ordered by first row, feed the second
        // pass (20 bytes a member twice, where cells kept in 16 bits and
        // then widened to `usize` for the ordering took 92, grown by
        // doubling: a fifth of the grid's build on the map at the input
        // limit was page faults and copies, issue 47).
        if u32::try_from(self.width).is_err() || u32::try_from(self.height).is_err() {
            return None;
        }
        let mut kept: Vec<(u32, [u32; 4])> = Vec::with_capacity(self.slot.iter().filter(|&&s| in_group(s)).count());
        for (n, ((seg, _, _), &s)) in segs.iter().zip(&self.slot).enumerate() {
            if in_group(s) {
                kept.push((n as u32, self.cells_of(seg).map(|v| v as u32)));
            }
        }
        let each = |f: &mut dyn FnMut(u32, [usize; 4])| {
            for &(n, c) in &kept {
                f(n, c.map(|v| v as usize));
            }
        };
        // The cells of each row that the segment passes through ([`row_cells`]).
        let (ox, oy) = self.origin;
        let in_cells =
            |p: (f64, f64)| ((p.0 - ox) / self.cell + self.pad as f64, (p.1 - oy) / self.cell + self.pad as f64);
        let rows = move |n: u32, [x0, y0, x1, y1]: [usize; 4]| {
            let ((a, b), _, _) = segs[n as usize];
            let (a, b) = (in_cells(a), in_cells(b));
            (y0..=y1).filter_map(move |y| {
                let (c0, c1) = row_cells(a, b, y as isize, (x0 as isize, x1 as isize));
                (c0 <= c1).then_some((y, c0 as usize, c1 as usize))
            })
        };
        // Each member's run of cells counted at its ends (a difference
        // array, `+1` at the run's first cell and `-1` past its last, in
        // wrapping arithmetic), then summed once over the cells into the
        // counts and once more into the starts: the count pass follows the
        // rows a member spans, not the cells (a scribble's segments cross
        // hundreds of cells each).
        let mut start = vec![0u32; n_cells + 2];
        let mut total = 0u64;
        each(&mut |n, c| {
            for (y, x0, x1) in rows(n, c) {
                total += (x1 - x0 + 1) as u64;
                start[y * self.width + x0 + 1] = start[y * self.width + x0 + 1].wrapping_add(1);
                start[y * self.width + x1 + 2] = start[y * self.width + x1 + 2].wrapping_sub(1);
            }
        });
        if total > MAX_ITEMS {
            return None;
        }
        start.truncate(n_cells + 1);
        for c in 1..start.len() {
            start[c] = start[c].wrapping_add(start[c - 1]);
        }
        for c in 1..start.len() {
            start[c] = start[c].wrapping_add(start[c - 1]);
        }
        let mut items = vec![0u32; start[n_cells] as usize];
        let mut next = start[..n_cells].to_vec();
        // Filled row by row, so that the writes of a row go to its own
        // stretch of `items` (one row of a scribble's cells holds some
        // 100,000 entries, and written segment by segment, each entry went
        // to a cache line of its own). The members spanning the row are in
        // hand in segment order (those starting on it merged in), so each
        // cell lists its segments in segment order, as counted.
        // The members in segment order within a first row.
        let by_first = by_first_row(&kept, self.height);
        drop(kept);
        let (mut active, mut merged): (Vec<Member>, Vec<Member>) = (Vec::new(), Vec::new());
        let mut k = 0;
        for y in 0..self.height {
            active.retain(|m| m.last_row >= y);
            let first = k;
            while by_first.get(k).is_some_and(|&(_, c)| c[1] as usize <= y) {
                k += 1;
            }
            let starting =
                by_first[first..k].iter().filter(|&&(_, c)| c[3] as usize >= y).map(|&(n, [x0, _, x1, y1])| {
                    let ((a, b), _, _) = segs[n as usize];
                    Member {
                        n,
                        a: in_cells(a),
                        b: in_cells(b),
                        cols: (x0 as isize, x1 as isize),
                        last_row: y1 as usize,
                    }
                });
            if first < k {
                merged.clear();
                let mut old = active.drain(..).peekable();
                for m in starting {
                    while let Some(o) = old.next_if(|o| o.n < m.n) {
                        merged.push(o);
                    }
                    merged.push(m);
                }
                merged.extend(old);
                std::mem::swap(&mut active, &mut merged);
            }
            for m in &active {
                let (c0, c1) = row_cells(m.a, m.b, y as isize, m.cols);
                if c0 > c1 {
                    continue;
                }
                for e in &mut next[y * self.width + c0 as usize..=y * self.width + c1 as usize] {
                    items[*e as usize] = m.n;
                    *e += 1;
                }
            }
        }
        Some(Cells { start, items })
    }

    /// The stored position of the cell corner `(x, y)` (layer cells from
    /// the origin) of tile `(c, r)`: its tile-local corner plus the tile's
    /// offset.
    pub(super) fn corner(&self, (c, r): (usize, usize), (x, y): (isize, isize)) -> (isize, isize) {
        let side = (SUB * TILE_CELLS) as isize;
        (c as isize * side + x + self.pad, r as isize * side + y + self.pad)
    }

    fn index(&self, (x, y): (isize, isize)) -> Option<usize> {
        (x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height)
            .then(|| y as usize * self.width + x as usize)
    }

    /// The segments of the group in stored cell `(x, y)`.
    pub(super) fn cell(&self, own: bool, xy: (isize, isize)) -> &[u32] {
        let cells = &self.groups[usize::from(!own)];
        let Some(k) = self.index(xy) else { return &[] };
        match (cells.start.get(k), cells.start.get(k + 1)) {
            (Some(&a), Some(&b)) => cells.items.get(a as usize..b as usize).unwrap_or(&[]),
            _ => &[],
        }
    }

    /// The segments of the group in stored cells `x0..=x1` of row `y`, cell
    /// after cell: one slice, as the cells of a row lie together (the cells
    /// of the range off the grid hold nothing).
    pub(super) fn row(&self, own: bool, y: isize, x0: isize, x1: isize) -> &[u32] {
        let cells = &self.groups[usize::from(!own)];
        let (x0, x1) = (x0.max(0), x1.min(self.width as isize - 1));
        if y < 0 || y as usize >= self.height || x0 > x1 {
            return &[];
        }
        let k = y as usize * self.width;
        match (cells.start.get(k + x0 as usize), cells.start.get(k + x1 as usize + 1)) {
            (Some(&a), Some(&b)) => cells.items.get(a as usize..b as usize).unwrap_or(&[]),
            _ => &[],
        }
    }

    /// Segment `n` of `segs`'s slot if tile `(c, r)`'s bucket holds it.
    pub(super) fn slot_in(&self, segs: &[(Seg, Part, f64)], n: usize, (c, r): (u32, u32)) -> Option<usize> {
        let span = self.span.get(n)?.map(u32::from);
        let s = *self.slot.get(n)?;
        if !(span[0] <= c && c <= span[1] && span[2] <= r && r <= span[3] && s != u8::MAX) {
            return None;
        }
        let (seg, _, m) = segs.get(n)?;
        let (c0, c1) = self.tiles.row_cols(seg, *m, r as usize, span.map(|v| v as usize));
        (c0 as u32 <= c && c <= c1 as u32).then_some(s as usize)
    }

    /// The slot of segment `n`, `None` for one the grid does not hold.
    pub(super) fn slot_of_segment(&self, n: usize) -> Option<usize> {
        self.slot.get(n).filter(|&&s| s != u8::MAX).map(|&s| usize::from(s))
    }

    /// Whether the group's segments were binned (only a group some tile's
    /// search wants is).
    pub(super) fn holds(&self, own: bool) -> bool {
        !self.groups[usize::from(!own)].start.is_empty()
    }

    /// The first `max` of tile `tile`'s bucket entries whose slot `want`
    /// takes, in the groups `groups` (`[own, other]`), by squared distance
    /// to page point `p` (at stored cell corner `xy`, a lattice point of
    /// the tile) and then by segment number: what
    /// [`nearest_first`](super::nearest_first) keeps of them in bucket
    /// order, since a bucket lists its segments by number. `None` when a
    /// group asked for was not binned.
    ///
    /// Found by searching rings of cells round `xy` rather than measuring
    /// every entry of the bucket: the search stops once it holds `max`
    /// segments all nearer than any cell of the next ring (the segments not
    /// yet seen lie beyond the rings searched, so strictly farther), or
    /// once the rings cover the tile grown by every reach (every entry of
    /// the bucket is binned in a cell there).
    pub(super) fn nearest_to(
        &self,
        segs: &[(Seg, Part, f64)],
        (tile, xy, p): ((usize, usize), (isize, isize), (f64, f64)),
        groups: [bool; 2],
        want: impl Fn(usize) -> bool,
        max: usize,
    ) -> Option<Vec<(f64, u32)>> {
        if (groups[0] && !self.holds(true)) || (groups[1] && !self.holds(false)) {
            return None;
        }
        let mut found: Vec<(f64, u32)> = Vec::new();
        if max == 0 {
            return Some(found);
        }
        let tile_u32 = (tile.0 as u32, tile.1 as u32);
        let reach = self.reach.iter().copied().fold(0.0, f64::max);
        // From a point of the tile, ring `last` lies beyond the tile grown by every reach.
        let last = (SUB * TILE_CELLS) as isize + (reach / self.cell).ceil() as isize + 2;
        let (x, y) = xy;
        let visit = |items: &[u32], found: &mut Vec<(f64, u32)>| {
            for &n in items {
                let Some(slot) = self.slot_in(segs, n as usize, tile_u32) else { continue };
                if !want(slot) {
                    continue;
                }
                if let Some(&((a, b), _, _)) = segs.get(n as usize) {
                    found.push((super::distance2_to_segment(p, a, b), n));
                }
            }
        };
        let order = |v: &mut Vec<(f64, u32)>| {
            v.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            // A segment binned in several cells is seen once per cell.
            v.dedup_by_key(|e| e.1);
        };
        for r in 0..=last {
            for own in [true, false] {
                if !groups[usize::from(!own)] {
                    continue;
                }
                visit(self.row(own, y - 1 - r, x - 1 - r, x + r), &mut found);
                visit(self.row(own, y + r, x - 1 - r, x + r), &mut found);
                for cy in y - r..y + r {
                    visit(self.cell(own, (x - 1 - r, cy)), &mut found);
                    visit(self.cell(own, (x + r, cy)), &mut found);
                }
            }
            // Not seen yet: at least `next` away (a hundredth of a cell for
            // the rounding of the cell bounds). Sorted only once `max` seen
            // (counted with repeats) lie nearer.
            let next = (r as f64 + 0.99) * self.cell;
            if r < last && found.iter().filter(|e| e.0 < next * next).count() >= max {
                order(&mut found);
                if found.len() >= max && found[max - 1].0 < next * next {
                    break;
                }
            }
        }
        order(&mut found);
        found.truncate(max);
        Some(found)
    }

    /// Tile `(c, r)`'s counts.
    pub(super) fn tile(&self, (c, r): (usize, usize)) -> TileStats {
        self.stats.get(r * self.cols + c).copied().unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::by_first_row;

    /// The counting order is the stable sort by first row it replaces, on
    /// members with many equal rows and out of order.
    #[test]
    fn members_by_first_row_as_a_stable_sort_orders_them() {
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut next = |n: u64| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s % n) as usize
        };
        for (count, height) in [(0, 1), (1, 1), (7, 3), (500, 40), (3_000, 700)] {
            let members: Vec<(u32, [u32; 4])> = (0..count)
                .map(|n| (n as u32, [next(50), next(height as u64), next(50), height - 1].map(|v| v as u32)))
                .collect();
            let mut sorted = members.clone();
            sorted.sort_by_key(|&(_, c)| c[1]);
            assert_eq!(by_first_row(&members, height), sorted, "{count} members over {height} rows");
        }
    }
}
