//! Dot tables (`DOTS`): outline dots, point symbols and braille cells, stored
//! with a uniform grid index so that a player finds the dots near an actuator
//! without scanning the whole table.

use alloc::vec::Vec;

use crate::bytes::{Out, f32_at, u8_at, u32_at};
use crate::error::FormatError;
use crate::units::Mm;
use crate::{NO_SOURCE, Tag, finite, in_range, source_from_raw};

pub(crate) const DOTS_HEADER_LEN: usize = 32;
pub(crate) const DOT_LEN: usize = 20;
/// Largest number of dots in one table.
pub const MAX_DOTS: u32 = 4 << 20;
/// Largest number of cells in a table's grid index.
pub const MAX_DOT_GRID_CELLS: u32 = 1 << 20;

/// What a dot table draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DotKind {
    /// Dots spaced along an outline (`dots(...)`).
    Outline,
    /// A single dot per point symbol (`dot(...)`).
    Symbol,
    /// Braille cells (`braille(...)`).
    Braille,
}

impl DotKind {
    /// Code stored in the chunk.
    pub fn code(self) -> u8 {
        match self {
            DotKind::Outline => 1,
            DotKind::Symbol => 2,
            DotKind::Braille => 3,
        }
    }

    /// Kind for a stored code.
    pub fn from_code(c: u8) -> Option<Self> {
        match c {
            1 => Some(DotKind::Outline),
            2 => Some(DotKind::Symbol),
            3 => Some(DotKind::Braille),
            _ => None,
        }
    }

    /// Name used in the text form and messages.
    pub fn name(self) -> &'static str {
        match self {
            DotKind::Outline => "outline",
            DotKind::Symbol => "symbol",
            DotKind::Braille => "braille",
        }
    }
}

/// One dot (seed 000 eq. 1): centre, radius and amplitude.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dot {
    /// Centre x on the page.
    pub x: Mm,
    /// Centre y on the page.
    pub y: Mm,
    /// Radius ρ.
    pub radius: Mm,
    /// Amplitude (0..=1) that scales δ.
    pub amplitude: f32,
    /// Provenance entry of the element the dot came from.
    pub source: Option<u32>,
}

/// A dot table. When written, dots are stored sorted by grid cell (stable
/// within a cell), so reading a table back gives that order.
#[derive(Debug, Clone, PartialEq)]
pub struct DotTable {
    /// What the dots draw.
    pub kind: DotKind,
    /// The dots.
    pub dots: Vec<Dot>,
}

/// The grid index of a dot table: cells of `cell_mm`, `cols` x `rows`, from
/// `(origin_x, origin_y)`. A dot belongs to the cell that holds its centre
/// (clamped to the grid).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DotGrid {
    /// Page x of the grid's left edge.
    pub origin_x: f32,
    /// Page y of the grid's top edge.
    pub origin_y: f32,
    /// Side of one cell in millimetres.
    pub cell_mm: f32,
    /// Cells per row.
    pub cols: u32,
    /// Rows of cells.
    pub rows: u32,
    /// Largest dot radius in the table.
    pub max_radius: f32,
}

impl DotGrid {
    /// The cell column of page x, clamped to the grid.
    #[inline]
    pub fn col_of(&self, x: f32) -> u32 {
        clamp_cell((x - self.origin_x) / self.cell_mm, self.cols)
    }

    /// The cell row of page y, clamped to the grid.
    #[inline]
    pub fn row_of(&self, y: f32) -> u32 {
        clamp_cell((y - self.origin_y) / self.cell_mm, self.rows)
    }

    /// The canonical grid of a set of dots (SPEC.md, `DOTS`): the writer
    /// always uses it and the reader accepts no other, so that a dot table
    /// has exactly one encoding.
    fn derive(dots: impl Iterator<Item = Dot>) -> DotGrid {
        let (mut x0, mut y0, mut x1, mut y1, mut r) = (f32::MAX, f32::MAX, f32::MIN, f32::MIN, 0.0f32);
        let mut m = 0u64;
        for d in dots {
            m += 1;
            x0 = x0.min(d.x.0);
            y0 = y0.min(d.y.0);
            x1 = x1.max(d.x.0);
            y1 = y1.max(d.y.0);
            r = r.max(d.radius.0);
        }
        if m == 0 {
            return DotGrid { origin_x: 0.0, origin_y: 0.0, cell_mm: 1.0, cols: 1, rows: 1, max_radius: 0.0 };
        }
        // A cell of at least two radii means an actuator is reached by dots
        // of at most 2 x 2 cells; grow the cell until the grid has no more
        // cells than dots (format 3.0: a sparse table's index stays about
        // as small as its dots, 4 bytes a cell against 20 a dot) and fits
        // the limit.
        // The span is measured in f64 so that coordinates near f32::MAX
        // cannot overflow it, and the cell counts saturate instead of wrapping.
        let (span_x, span_y) = (x1 as f64 - x0 as f64, y1 as f64 - y0 as f64);
        let mut cell = (2.0 * r).max(1e-3);
        loop {
            let cols = (span_x / cell as f64).min(u32::MAX as f64) as u64 + 1;
            let rows = (span_y / cell as f64).min(u32::MAX as f64) as u64 + 1;
            // The cell stays finite: at f32::MAX the span (below 2^129) gives 3 cells a side.
            let most = m.min(MAX_DOT_GRID_CELLS as u64);
            if cols.saturating_mul(rows) <= most || cell >= f32::MAX / 2.0 {
                return DotGrid {
                    origin_x: x0,
                    origin_y: y0,
                    cell_mm: cell,
                    cols: cols.min(MAX_DOT_GRID_CELLS as u64) as u32,
                    rows: rows.min(MAX_DOT_GRID_CELLS as u64) as u32,
                    max_radius: r,
                };
            }
            cell *= 2.0;
        }
    }
}

#[inline]
fn clamp_cell(v: f32, n: u32) -> u32 {
    // `as` saturates and maps NaN to 0, so this never panics.
    let c = libm::floorf(v) as i64;
    c.clamp(0, n as i64 - 1) as u32
}

impl DotTable {
    pub(crate) fn encode(&self) -> Vec<u8> {
        let grid = DotGrid::derive(self.dots.iter().copied());
        let cells = grid.cols as usize * grid.rows as usize;
        let cell_of = |d: &Dot| grid.row_of(d.y.0) as usize * grid.cols as usize + grid.col_of(d.x.0) as usize;
        let mut order: Vec<(usize, usize)> = self.dots.iter().enumerate().map(|(i, d)| (cell_of(d), i)).collect();
        order.sort_unstable();
        let mut starts = alloc::vec![0u32; cells + 1];
        for &(c, _) in &order {
            starts[c + 1] += 1;
        }
        for c in 0..cells {
            starts[c + 1] += starts[c];
        }
        let mut out = Vec::with_capacity(DOTS_HEADER_LEN + 4 * (cells + 1) + DOT_LEN * self.dots.len());
        let mut w = Out(&mut out);
        w.u8(self.kind.code())
            .zeros(3)
            .u32(self.dots.len() as u32)
            .u32(grid.cols)
            .u32(grid.rows)
            .f32(grid.origin_x)
            .f32(grid.origin_y)
            .f32(grid.cell_mm)
            .f32(grid.max_radius);
        for s in starts {
            w.u32(s);
        }
        for &(_, i) in &order {
            let d = &self.dots[i];
            w.f32(d.x.0).f32(d.y.0).f32(d.radius.0).f32(d.amplitude).u32(d.source.unwrap_or(NO_SOURCE));
        }
        out
    }

    pub(crate) fn from_view(v: &DotTableView<'_>) -> Self {
        DotTable { kind: v.kind, dots: (0..v.len()).filter_map(|i| v.dot(i)).collect() }
    }
}

/// The dots of a run of cells ([`DotTableView::row_run`]), read in place.
#[derive(Debug, Clone)]
pub struct DotRun<'a>(&'a [[u8; DOT_LEN]]);

/// The dot stored in `d`. Its fields are at constant offsets of a
/// fixed-size array: no bounds checks.
#[inline]
fn dot_at(d: &[u8; DOT_LEN]) -> Dot {
    let w = |o: usize| [d[o], d[o + 1], d[o + 2], d[o + 3]];
    Dot {
        x: Mm(f32::from_le_bytes(w(0))),
        y: Mm(f32::from_le_bytes(w(4))),
        radius: Mm(f32::from_le_bytes(w(8))),
        amplitude: f32::from_le_bytes(w(12)),
        source: source_from_raw(u32::from_le_bytes(w(16))),
    }
}

impl Iterator for DotRun<'_> {
    type Item = Dot;

    #[inline]
    fn next(&mut self) -> Option<Dot> {
        let (d, rest) = self.0.split_first()?;
        self.0 = rest;
        Some(dot_at(d))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        (self.0.len(), Some(self.0.len()))
    }
}

impl ExactSizeIterator for DotRun<'_> {}

/// A validated dot table, read in place.
#[derive(Debug, Clone, Copy)]
pub struct DotTableView<'a> {
    /// What the dots draw.
    pub kind: DotKind,
    /// The grid index.
    pub grid: DotGrid,
    count: u32,
    /// The cell starts, one little-endian `u32` each, and the dots, as
    /// arrays: a run of cells is found by index, with no multiplications
    /// and no offset arithmetic to check.
    starts: &'a [[u8; 4]],
    dots: &'a [[u8; DOT_LEN]],
}

impl<'a> DotTableView<'a> {
    /// Number of dots.
    pub fn len(&self) -> u32 {
        self.count
    }

    /// Whether the table has no dots.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Dot `i` in stored order.
    #[inline]
    pub fn dot(&self, i: u32) -> Option<Dot> {
        self.dots.get(i as usize).map(dot_at)
    }

    /// Cell start `c`, if the index has it.
    #[inline]
    fn start(&self, c: usize) -> Option<u32> {
        self.starts.get(c).map(|b| u32::from_le_bytes(*b))
    }

    /// The range of dot indices stored in cell `(col, row)`.
    #[inline]
    pub fn cell(&self, col: u32, row: u32) -> core::ops::Range<u32> {
        if col >= self.grid.cols || row >= self.grid.rows {
            return 0..0;
        }
        let c = row as usize * self.grid.cols as usize + col as usize;
        let a = self.start(c).unwrap_or(0);
        let b = self.start(c + 1).unwrap_or(a);
        a..b.max(a)
    }

    /// The dots stored in cells `col0..=col1` of grid row `row`, in stored
    /// order. The table keeps its dots sorted by cell, row by row, so these
    /// are one contiguous run: finding it costs two index reads, and each dot
    /// is then read without a further bounds check. Cells outside the grid
    /// hold no dots.
    #[inline]
    pub fn row_run(&self, col0: u32, col1: u32, row: u32) -> DotRun<'a> {
        let col1 = col1.min(self.grid.cols.saturating_sub(1));
        let dots = if col0 <= col1 && row < self.grid.rows {
            // Cell c's dots are starts[c]..starts[c + 1]; the run of cells
            // col0..=col1 of this row is starts[first]..starts[last + 1].
            let cell = row as usize * self.grid.cols as usize;
            let first = self.start(cell + col0 as usize).unwrap_or(0) as usize;
            let end = self.start(cell + col1 as usize + 1).unwrap_or(0) as usize;
            self.dots.get(first..end).unwrap_or(&[])
        } else {
            &[]
        };
        DotRun(dots)
    }

    /// The dots stored in cells `first..end`, cells numbered row by row
    /// (`row · cols + col`): [`DotTableView::row_run`] for a caller that
    /// has clamped its cells to the grid already and steps from one grid
    /// row to the next by adding `grid.cols`. Cells past the index hold
    /// no dots.
    #[inline]
    pub fn cell_run(&self, first: usize, end: usize) -> DotRun<'a> {
        let dots = match (self.start(first), self.start(end)) {
            (Some(a), Some(b)) => self.dots.get(a as usize..b as usize).unwrap_or(&[]),
            _ => &[],
        };
        DotRun(dots)
    }

    /// Calls `f` for every dot whose disc may contain the point `(x, y)`
    /// (every dot within `max_radius` of it, and possibly a few more).
    /// The work is bounded by the dots in at most a few cells, whatever the
    /// size of the table.
    #[inline]
    pub fn for_each_near(&self, x: f32, y: f32, mut f: impl FnMut(Dot)) {
        if self.count == 0 {
            return;
        }
        let r = self.grid.max_radius;
        let (c0, c1) = (self.grid.col_of(x - r), self.grid.col_of(x + r));
        let (r0, r1) = (self.grid.row_of(y - r), self.grid.row_of(y + r));
        for row in r0..=r1 {
            self.row_run(c0, c1, row).for_each(&mut f);
        }
    }

    /// Reads the table; with `full`, also checks the index and every dot.
    pub(crate) fn parse(d: &'a [u8], index: u32, full: bool) -> Result<Self, FormatError> {
        let tag = Tag::DOTS;
        FormatError::check_header(d, DOTS_HEADER_LEN, tag, index)?;
        let bad = |field, expected| FormatError::InvalidValue { tag, index, field, expected };
        let kind = DotKind::from_code(u8_at(d, 0).unwrap_or(0)).ok_or(bad("kind", "1, 2 or 3"))?;
        if d[1..4].iter().any(|&b| b != 0) {
            return Err(bad("reserved", "zero"));
        }
        let count = u32_at(d, 4).unwrap_or(0);
        let cols = u32_at(d, 8).unwrap_or(0);
        let rows = u32_at(d, 12).unwrap_or(0);
        if count > MAX_DOTS {
            return Err(FormatError::Limit { tag, field: "dot count", value: count as u64, limit: MAX_DOTS as u64 });
        }
        let cells = cols as u64 * rows as u64;
        if cols == 0 || rows == 0 || cells > MAX_DOT_GRID_CELLS as u64 {
            return Err(FormatError::Limit {
                tag,
                field: "grid cells (1 or more)",
                value: cells,
                limit: MAX_DOT_GRID_CELLS as u64,
            });
        }
        let f = |o| f32_at(d, o).unwrap_or(f32::NAN);
        let grid = DotGrid {
            origin_x: finite(f(16), tag, index, "grid origin_x")?,
            origin_y: finite(f(20), tag, index, "grid origin_y")?,
            cell_mm: in_range(f(24), 1e-6, f32::MAX, tag, index, "cell_mm", "finite and above 0")?,
            cols,
            rows,
            max_radius: in_range(f(28), 0.0, f32::MAX, tag, index, "max_radius", "finite and not negative")?,
        };
        let starts_len = 4 * (cells as usize + 1);
        let expected = (DOTS_HEADER_LEN + starts_len) as u64 + DOT_LEN as u64 * count as u64;
        if d.len() as u64 != expected {
            return Err(FormatError::ChunkLength { tag, index, expected, found: d.len() as u64 });
        }
        // The length check above makes both whole arrays.
        let starts = d[DOTS_HEADER_LEN..DOTS_HEADER_LEN + starts_len].as_chunks::<4>().0;
        let dots = d[DOTS_HEADER_LEN + starts_len..].as_chunks::<DOT_LEN>().0;
        let view = DotTableView { kind, grid, count, starts, dots };
        if !full {
            return Ok(view);
        }
        // The index must partition the dots: starts run from 0 to count without
        // decreasing, and every dot lies in the cell that lists it.
        if view.start(0) != Some(0) || view.start(cells as usize) != Some(count) {
            return Err(bad("grid index", "cell starts from 0 to the dot count"));
        }
        for row in 0..rows {
            for col in 0..cols {
                let c = row as usize * cols as usize + col as usize;
                let (a, b) = (view.start(c).unwrap_or(0), view.start(c + 1).unwrap_or(0));
                if b < a {
                    return Err(bad("grid index", "non-decreasing cell starts"));
                }
                for i in a..b {
                    let dot = view.dot(i).ok_or(bad("grid index", "starts within the table"))?;
                    finite(dot.x.0, tag, index, "dot x")?;
                    finite(dot.y.0, tag, index, "dot y")?;
                    in_range(dot.radius.0, 1e-6, f32::MAX, tag, index, "dot radius", "finite and above 0")?;
                    in_range(dot.amplitude, 0.0, 1.0, tag, index, "dot amplitude", "from 0 to 1")?;
                    if view.grid.col_of(dot.x.0) != col || view.grid.row_of(dot.y.0) != row {
                        return Err(bad("grid index", "every dot in the cell that holds its centre"));
                    }
                }
            }
        }
        let canonical = DotGrid::derive((0..count).filter_map(|i| view.dot(i)));
        let same = |a: f32, b: f32| a.to_bits() == b.to_bits();
        if !(same(canonical.origin_x, grid.origin_x)
            && same(canonical.origin_y, grid.origin_y)
            && same(canonical.cell_mm, grid.cell_mm)
            && same(canonical.max_radius, grid.max_radius)
            && canonical.cols == grid.cols
            && canonical.rows == grid.rows)
        {
            return Err(bad("grid", "the canonical grid of its dots (SPEC.md, DOTS)"));
        }
        Ok(view)
    }
}
