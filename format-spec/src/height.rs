//! Height fields (`HFLD`): a regular grid of surface heights, gradients and
//! flags sampled from a mesh, for the finger-mounted device.

use alloc::vec::Vec;

use crate::bytes::{Out, array_at, f32_at, u8_at, u32_at};
use crate::error::FormatError;
use crate::height_tiles::{self, ENCODING_TILED, ENCODING_TILED_4_5, TILE, TILED_HEADER_LEN, TileNodes, Tiled};
use crate::units::Mm;
use crate::{NO_SOURCE, Tag, in_range, source_from_raw};

const HEADER_LEN: usize = 48;
/// Largest number of nodes along one side of a height field.
pub const MAX_FIELD_SIDE: u32 = 16_384;
/// Largest number of nodes in one height field.
pub const MAX_FIELD_NODES: u64 = 16 << 20;
/// Flag bit: the surface is present above this node (the finger can touch it).
pub const FIELD_CONTACT: u8 = 1;
/// Flag bit: a step (vertical wall) passes next to this node; its gradient is capped.
pub const FIELD_EDGE: u8 = 2;

/// How a height field is stored (SPEC.md section 9).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum HeightEncoding {
    /// Format 4.0: every node's height, gradient and flags as they are
    /// (`f32`, 13 bytes a node).
    Float,
    /// Format 4.6 (section 9.1): heights quantised to `step` above `base`
    /// in tiles that are empty, one plane, or coded (each code predicted
    /// from its neighbours), each stored once;
    /// gradients are not stored (a player derives them from the heights),
    /// so [`HeightField::grad_x`] and [`HeightField::grad_y`] are only a
    /// writer's hint and come back as the planes' slopes (0 elsewhere).
    Tiled {
        /// Height of one code, mm (above 0).
        step: f32,
        /// Height of code 0, mm (at most the lowest contact height).
        base: f32,
        /// The largest gradient magnitude a player scales rhythm by (0 to the cap).
        max_gradient: f32,
    },
}

/// A height field: node `(i, j)` (column `i`, row `j`, row 0 at the top) is at
/// page position `(origin_x + i * cell, origin_y + j * cell)`.
///
/// Heights are in millimetres; gradients are dimensionless slopes
/// (millimetres of height per millimetre on the page, x right and y down).
/// Nodes without [`FIELD_CONTACT`] have height and gradient 0.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightField {
    /// Provenance entry of the mesh.
    pub source: Option<u32>,
    /// Nodes per row (at least 2).
    pub cols: u32,
    /// Rows of nodes (at least 2).
    pub rows: u32,
    /// Page x of node (0, 0).
    pub origin_x: Mm,
    /// Page y of node (0, 0).
    pub origin_y: Mm,
    /// Distance between nodes.
    pub cell: Mm,
    /// The cap applied to gradient magnitudes (at steps).
    pub gradient_cap: f32,
    /// Heights, row-major.
    pub heights: Vec<f32>,
    /// ∂h/∂x, row-major.
    pub grad_x: Vec<f32>,
    /// ∂h/∂y (y down the page), row-major.
    pub grad_y: Vec<f32>,
    /// [`FIELD_CONTACT`] and [`FIELD_EDGE`] bits, row-major.
    pub flags: Vec<u8>,
    /// How the field is stored.
    pub encoding: HeightEncoding,
}

/// The little-endian `f32` of node `k` of a plane, 0 past its end.
#[inline]
fn plane_f32(plane: &[u8], k: u32) -> f32 {
    (k as usize).checked_mul(4).and_then(|o| f32_at(plane, o)).unwrap_or(0.0)
}

/// Extremes a player needs to scale intensity and rhythm: computed by the
/// writer, checked by the reader.
fn extremes(heights: impl Iterator<Item = (f32, f32, f32, u8)>) -> (f32, f32, f32) {
    let (mut lo, mut hi, mut g) = (0.0f32, 0.0f32, 0.0f32);
    let mut any = false;
    for (h, gx, gy, fl) in heights {
        if fl & FIELD_CONTACT == 0 {
            continue;
        }
        if !any {
            (lo, hi) = (h, h);
            any = true;
        }
        lo = lo.min(h);
        hi = hi.max(h);
        g = g.max(libm::sqrtf(gx * gx + gy * gy));
    }
    (lo, hi, g)
}

impl HeightField {
    /// Checks that the four node arrays hold `cols * rows` values each, so the
    /// writer never pads or drops data silently.
    pub(crate) fn check_shape(&self, index: u32) -> Result<(), FormatError> {
        let n = self.cols as usize * self.rows as usize;
        let lens = [self.heights.len(), self.grad_x.len(), self.grad_y.len(), self.flags.len()];
        if lens.iter().any(|&l| l != n) {
            return Err(FormatError::InvalidValue {
                tag: Tag::HEIGHT,
                index,
                field: "heights, grad_x, grad_y and flags",
                expected: "cols * rows values each",
            });
        }
        Ok(())
    }

    pub(crate) fn encode(&self, index: u32) -> Result<Vec<u8>, FormatError> {
        let n = self.cols as usize * self.rows as usize;
        let (lo, hi, g) = extremes((0..n).map(|k| {
            (
                self.heights.get(k).copied().unwrap_or(0.0),
                self.grad_x.get(k).copied().unwrap_or(0.0),
                self.grad_y.get(k).copied().unwrap_or(0.0),
                self.flags.get(k).copied().unwrap_or(0),
            )
        }));
        let (encoding, g) = match self.encoding {
            HeightEncoding::Float => (0, g),
            HeightEncoding::Tiled { max_gradient, .. } => (ENCODING_TILED, max_gradient),
        };
        let mut out = Vec::with_capacity(HEADER_LEN + 13 * n + 4);
        let mut w = Out(&mut out);
        w.u32(self.source.unwrap_or(NO_SOURCE))
            .u32(self.cols)
            .u32(self.rows)
            .u32(encoding)
            .f32(self.origin_x.0)
            .f32(self.origin_y.0)
            .f32(self.cell.0)
            .f32(lo)
            .f32(hi)
            .f32(g)
            .f32(self.gradient_cap)
            .u32(0);
        if let HeightEncoding::Tiled { step, base, .. } = self.encoding {
            let bad = |expected| FormatError::InvalidValue { tag: Tag::HEIGHT, index, field: "height step", expected };
            if !(step.is_finite() && step > 0.0 && base.is_finite()) {
                return Err(bad("a finite step above 0 and a finite base"));
            }
            let tables = height_tiles::encode_tiles(self, step, base).map_err(bad)?;
            height_tiles::write_tables(&mut w, step, base, &tables);
            // The extremes are those of the heights as stored: read them back.
            let view = HeightFieldView::parse(&out, index, false)?;
            let (lo, hi) = view.tiled_extremes();
            out[28..32].copy_from_slice(&lo.to_le_bytes());
            out[32..36].copy_from_slice(&hi.to_le_bytes());
            return Ok(out);
        }
        for v in [&self.heights, &self.grad_x, &self.grad_y] {
            for k in 0..n {
                w.f32(v.get(k).copied().unwrap_or(0.0));
            }
        }
        for k in 0..n {
            w.u8(self.flags.get(k).copied().unwrap_or(0));
        }
        w.zeros(n.next_multiple_of(4) - n);
        Ok(out)
    }

    pub(crate) fn from_view(v: &HeightFieldView<'_>) -> Self {
        if let Some(t) = &v.tiled {
            return Self::from_tiled(v, t);
        }
        let n = v.cols * v.rows;
        HeightField {
            source: v.source,
            cols: v.cols,
            rows: v.rows,
            origin_x: v.origin_x,
            origin_y: v.origin_y,
            cell: v.cell,
            gradient_cap: v.gradient_cap,
            heights: (0..n).map(|k| v.height_at(k)).collect(),
            grad_x: (0..n).map(|k| v.gradient_at(k).0).collect(),
            grad_y: (0..n).map(|k| v.gradient_at(k).1).collect(),
            flags: (0..n).map(|k| v.flags_at(k)).collect(),
            encoding: HeightEncoding::Float,
        }
    }

    /// A tiled field's nodes, decoded tile by tile: heights and flags as
    /// stored, and the gradients of its plane tiles (0 elsewhere).
    fn from_tiled(v: &HeightFieldView<'_>, t: &Tiled<'_>) -> Self {
        let n = v.cols as usize * v.rows as usize;
        let mut f = HeightField {
            source: v.source,
            cols: v.cols,
            rows: v.rows,
            origin_x: v.origin_x,
            origin_y: v.origin_y,
            cell: v.cell,
            gradient_cap: v.gradient_cap,
            heights: alloc::vec![0.0; n],
            grad_x: alloc::vec![0.0; n],
            grad_y: alloc::vec![0.0; n],
            flags: alloc::vec![0; n],
            encoding: HeightEncoding::Tiled { step: t.step, base: t.base, max_gradient: v.max_gradient },
        };
        v.for_each_tile(t, |tx, ty, nodes| {
            let plane = t.plane_at(tx * TILE, ty * TILE);
            for l in 0..TILE * TILE {
                let (i, j) = (tx * TILE + l % TILE, ty * TILE + l / TILE);
                if i < v.cols && j < v.rows {
                    let k = (j * v.cols + i) as usize;
                    (f.heights[k], f.flags[k]) = nodes.node(l);
                    if let (Some((_, gx, gy)), true) = (plane, f.flags[k] & FIELD_CONTACT != 0) {
                        (f.grad_x[k], f.grad_y[k]) = (gx, gy);
                    }
                }
            }
        });
        f
    }
}

/// A validated height field, read in place.
#[derive(Debug, Clone, Copy)]
pub struct HeightFieldView<'a> {
    /// Provenance entry of the mesh.
    pub source: Option<u32>,
    /// Nodes per row.
    pub cols: u32,
    /// Rows of nodes.
    pub rows: u32,
    /// Page x of node (0, 0).
    pub origin_x: Mm,
    /// Page y of node (0, 0).
    pub origin_y: Mm,
    /// Distance between nodes.
    pub cell: Mm,
    /// Lowest height over contact nodes.
    pub height_min: f32,
    /// Highest height over contact nodes.
    pub height_max: f32,
    /// Largest gradient magnitude over contact nodes.
    pub max_gradient: f32,
    /// The cap applied to gradient magnitudes.
    pub gradient_cap: f32,
    // The four node planes, sliced once by `parse` so that each read checks
    // only its own plane's bounds: heights, ∂h/∂x and ∂h/∂y hold `4 * n`
    // little-endian bytes each, flags `n` bytes.
    heights: &'a [u8],
    grad_x: &'a [u8],
    grad_y: &'a [u8],
    flags: &'a [u8],
    // The tiled encoding's tables (format 4.6); the four planes are empty then.
    tiled: Option<Tiled<'a>>,
}

/// The four nodes around one cell of a height field, as read by
/// [`HeightFieldView::cell_nodes`].
///
/// Each array lists, in this order, the top-left node `k`, its right
/// neighbour `k + 1`, the node below it `k + cols`, and the node diagonally
/// below `k + cols + 1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellNodes {
    /// Heights in mm.
    pub heights: [f32; 4],
    /// ∂h/∂x.
    pub grad_x: [f32; 4],
    /// ∂h/∂y (y down the page).
    pub grad_y: [f32; 4],
    /// [`FIELD_CONTACT`] and [`FIELD_EDGE`] bits.
    pub flags: [u8; 4],
}

/// The little-endian `f32` values of nodes `k` and `k + 1` of a plane, or
/// `None` when node `k + 1` is past its end.
#[inline]
fn f32_pair(plane: &[u8], k: usize) -> Option<[f32; 2]> {
    let b: [u8; 8] = array_at(plane, k.checked_mul(4)?)?;
    Some([f32::from_le_bytes([b[0], b[1], b[2], b[3]]), f32::from_le_bytes([b[4], b[5], b[6], b[7]])])
}

impl<'a> HeightFieldView<'a> {
    /// The tiled node `k`, when the field is tiled and `k` inside it.
    fn tiled_node(&self, t: &Tiled<'_>, k: u32) -> (f32, u8) {
        if k as u64 >= self.cols as u64 * self.rows as u64 {
            return (0.0, 0);
        }
        t.node(k % self.cols, k / self.cols)
    }

    /// Height of node `k` (row-major index), 0 outside.
    #[inline]
    pub fn height_at(&self, k: u32) -> f32 {
        match &self.tiled {
            None => plane_f32(self.heights, k),
            Some(t) => self.tiled_node(t, k).0,
        }
    }

    /// Gradient `(∂h/∂x, ∂h/∂y)` of node `k`, zero outside. A tiled field
    /// stores no gradients: its nodes give their plane tile's slope, and 0
    /// in sampled tiles (a player derives the gradient from the heights).
    #[inline]
    pub fn gradient_at(&self, k: u32) -> (f32, f32) {
        match &self.tiled {
            None => (plane_f32(self.grad_x, k), plane_f32(self.grad_y, k)),
            Some(t) if (k as u64) < self.cols as u64 * self.rows as u64 && self.tiled_node(t, k).1 != 0 => {
                t.plane_at(k % self.cols, k / self.cols).map_or((0.0, 0.0), |p| (p.1, p.2))
            }
            Some(_) => (0.0, 0.0),
        }
    }

    /// Flags of node `k`, 0 (no contact) outside.
    #[inline]
    pub fn flags_at(&self, k: u32) -> u8 {
        match &self.tiled {
            None => u8_at(self.flags, k as usize).unwrap_or(0),
            Some(t) => self.tiled_node(t, k).1,
        }
    }

    /// `1 / cell` in `f32`, for a tiled field computed once when it was
    /// read: a player of a tiled field multiplies height differences by it
    /// (SPEC.md section 9.1) on every sample.
    #[inline]
    pub fn inverse_cell(&self) -> f32 {
        match &self.tiled {
            Some(t) => t.inv_cell,
            None => 1.0 / self.cell.0,
        }
    }

    /// Whether the field is tiled (format 4.6): then a player reads cells
    /// with [`FieldReader::cell_heights`](crate::FieldReader::cell_heights)
    /// and derives the gradient.
    #[inline]
    pub fn is_tiled(&self) -> bool {
        self.tiled.is_some()
    }

    /// The tiled encoding's tables, when the field is tiled.
    #[inline]
    pub(crate) fn tiled(&self) -> Option<&Tiled<'a>> {
        self.tiled.as_ref()
    }

    /// Calls `visit` with every tile of a tiled field, decoded, row by row.
    fn for_each_tile(&self, t: &Tiled<'_>, mut visit: impl FnMut(u32, u32, &TileNodes)) {
        let mut nodes = TileNodes::EMPTY;
        for ty in 0..self.rows.div_ceil(TILE) {
            for tx in 0..self.cols.div_ceil(TILE) {
                t.decode(tx, ty, &mut nodes);
                visit(tx, ty, &nodes);
            }
        }
    }

    /// The least and greatest height over the contact nodes of a tiled
    /// field (section 9.1's derived extremes, in IEEE 754 total order, so
    /// the order the tiles are read in does not matter), 0 and 0 without
    /// contact.
    fn tiled_extremes(&self) -> (f32, f32) {
        let Some(t) = &self.tiled else { return (0.0, 0.0) };
        let mut ext: Option<(f32, f32)> = None;
        self.for_each_tile(t, |tx, ty, nodes| {
            for l in 0..TILE * TILE {
                let (i, j) = (tx * TILE + l % TILE, ty * TILE + l / TILE);
                let (h, fl) = nodes.node(l);
                if i < self.cols && j < self.rows && fl & FIELD_CONTACT != 0 {
                    ext = Some(ext.map_or((h, h), |(lo, hi)| {
                        (if h.total_cmp(&lo).is_lt() { h } else { lo }, if h.total_cmp(&hi).is_gt() { h } else { hi })
                    }));
                }
            }
        });
        ext.unwrap_or((0.0, 0.0))
    }

    /// The four nodes around the cell whose top-left node is `k` (row-major
    /// index): `k`, `k + 1`, `k + cols` and `k + cols + 1`, or `None` when
    /// one of them is past the last node.
    ///
    /// This is the bilinear lookup's read: one call instead of sixteen
    /// single-node reads. For a cell of the grid `k` is `j * cols + i` with
    /// `i <= cols - 2` and `j <= rows - 2`; with `i = cols - 1` the nodes
    /// `k + 1` and `k + cols + 1` are the first ones of the next rows.
    #[inline]
    pub fn cell_nodes(&self, k: u32) -> Option<CellNodes> {
        if self.tiled.is_some() {
            return None;
        }
        let top = k as usize;
        let below = top.checked_add(self.cols as usize)?;
        let flags = |at: usize| -> Option<[u8; 2]> { array_at(self.flags, at) };
        let [f0, f1] = flags(top)?;
        let [f2, f3] = flags(below)?;
        let [h0, h1] = f32_pair(self.heights, top)?;
        let [h2, h3] = f32_pair(self.heights, below)?;
        let [x0, x1] = f32_pair(self.grad_x, top)?;
        let [x2, x3] = f32_pair(self.grad_x, below)?;
        let [y0, y1] = f32_pair(self.grad_y, top)?;
        let [y2, y3] = f32_pair(self.grad_y, below)?;
        Some(CellNodes {
            heights: [h0, h1, h2, h3],
            grad_x: [x0, x1, x2, x3],
            grad_y: [y0, y1, y2, y3],
            flags: [f0, f1, f2, f3],
        })
    }

    /// Reads the field; with `full`, also checks every node and the extremes.
    pub(crate) fn parse(d: &'a [u8], index: u32, full: bool) -> Result<Self, FormatError> {
        let tag = Tag::HEIGHT;
        FormatError::check_header(d, HEADER_LEN, tag, index)?;
        let bad = |field, expected| FormatError::InvalidValue { tag, index, field, expected };
        let cols = u32_at(d, 4).unwrap_or(0);
        let rows = u32_at(d, 8).unwrap_or(0);
        let encoding = u32_at(d, 12).unwrap_or(u32::MAX);
        if encoding == ENCODING_TILED_4_5 {
            return Err(bad("encoding", "0 or 2 (encoding 1 was 4.5's tiled field, a development version: rebuild)"));
        }
        if encoding > ENCODING_TILED || u32_at(d, 44) != Some(0) {
            return Err(bad("reserved", "zero (encoding: 0 or 2)"));
        }
        for (field, v) in [("cols", cols), ("rows", rows)] {
            if !(2..=MAX_FIELD_SIDE).contains(&v) {
                return Err(FormatError::Limit {
                    tag,
                    field: if field == "cols" { "cols (2 or more)" } else { "rows (2 or more)" },
                    value: v as u64,
                    limit: MAX_FIELD_SIDE as u64,
                });
            }
        }
        let n = cols as u64 * rows as u64;
        if n > MAX_FIELD_NODES {
            return Err(FormatError::Limit { tag, field: "nodes", value: n, limit: MAX_FIELD_NODES });
        }
        if encoding == ENCODING_TILED {
            return Self::parse_tiled(d, index, cols, rows, full);
        }
        let expected = HEADER_LEN as u64 + 13 * n + (n.next_multiple_of(4) - n);
        if d.len() as u64 != expected {
            return Err(FormatError::ChunkLength { tag, index, expected, found: d.len() as u64 });
        }
        let f = |o| f32_at(d, o).unwrap_or(f32::NAN);
        // The length check above makes every split succeed; a failure would
        // still be reported, never a panic.
        let planes = |body: &'a [u8]| {
            let n = n as usize;
            let (heights, rest) = body.split_at_checked(4 * n)?;
            let (grad_x, rest) = rest.split_at_checked(4 * n)?;
            let (grad_y, rest) = rest.split_at_checked(4 * n)?;
            let (flags, _padding) = rest.split_at_checked(n)?;
            Some((heights, grad_x, grad_y, flags))
        };
        let (heights, grad_x, grad_y, flags) = d
            .get(HEADER_LEN..)
            .and_then(planes)
            .ok_or(FormatError::ChunkLength { tag, index, expected, found: d.len() as u64 })?;
        const BIG: f32 = 1e9;
        let view = HeightFieldView {
            source: source_from_raw(u32_at(d, 0).unwrap_or(NO_SOURCE)),
            cols,
            rows,
            origin_x: Mm(in_range(f(16), -BIG, BIG, tag, index, "origin_x_mm", "finite, within 1e9 mm")?),
            origin_y: Mm(in_range(f(20), -BIG, BIG, tag, index, "origin_y_mm", "finite, within 1e9 mm")?),
            cell: Mm(in_range(f(24), 1e-9, BIG, tag, index, "cell_mm", "above 0, within 1e9 mm")?),
            height_min: f(28),
            height_max: f(32),
            max_gradient: f(36),
            gradient_cap: in_range(f(40), 0.0, BIG, tag, index, "gradient_cap", "from 0 to 1e9")?,
            heights,
            grad_x,
            grad_y,
            flags,
            tiled: None,
        };
        if !full {
            return Ok(view);
        }
        let n = n as u32;
        for k in 0..n {
            let h = view.height_at(k);
            let (gx, gy) = view.gradient_at(k);
            let fl = view.flags_at(k);
            in_range(h, -BIG, BIG, tag, index, "height", "finite, within 1e9 mm")?;
            let cap = view.gradient_cap * (1.0 + 1e-6);
            in_range(gx, -cap, cap, tag, index, "gradient x", "finite and within the gradient cap")?;
            in_range(gy, -cap, cap, tag, index, "gradient y", "finite and within the gradient cap")?;
            if fl & !(FIELD_CONTACT | FIELD_EDGE) != 0 {
                return Err(bad("flags", "only the contact and edge bits"));
            }
            if fl & FIELD_CONTACT == 0 && (h != 0.0 || gx != 0.0 || gy != 0.0 || fl != 0) {
                return Err(bad("no-contact node", "height, gradient and flags 0"));
            }
        }
        let pad = 12 * n as usize + n as usize;
        if d[HEADER_LEN + pad..].iter().any(|&b| b != 0) {
            return Err(bad("padding", "zero"));
        }
        let (lo, hi, g) = extremes((0..n).map(|k| {
            let (gx, gy) = view.gradient_at(k);
            (view.height_at(k), gx, gy, view.flags_at(k))
        }));
        if lo.to_bits() != view.height_min.to_bits()
            || hi.to_bits() != view.height_max.to_bits()
            || g.to_bits() != view.max_gradient.to_bits()
        {
            return Err(bad("extremes", "the lowest and highest height and largest gradient of the contact nodes"));
        }
        Ok(view)
    }

    /// Reads a tiled field (format 4.6, section 9.1); with `full`, checks
    /// every record and the derived extremes.
    fn parse_tiled(d: &'a [u8], index: u32, cols: u32, rows: u32, full: bool) -> Result<Self, FormatError> {
        let tag = Tag::HEIGHT;
        let bad = |field, expected| FormatError::InvalidValue { tag, index, field, expected };
        if d.len() < TILED_HEADER_LEN {
            return Err(FormatError::ChunkLength {
                tag,
                index,
                expected: TILED_HEADER_LEN as u64,
                found: d.len() as u64,
            });
        }
        let f = |o| f32_at(d, o).unwrap_or(f32::NAN);
        const BIG: f32 = 1e9;
        let cell = in_range(f(24), 1e-9, BIG, tag, index, "cell_mm", "above 0, within 1e9 mm")?;
        let cap = in_range(f(40), 0.0, BIG, tag, index, "gradient_cap", "from 0 to 1e9")?;
        let tiled = height_tiles::parse_tiled(d, index, cols, rows, cell, cap, full)?;
        let view = HeightFieldView {
            source: source_from_raw(u32_at(d, 0).unwrap_or(NO_SOURCE)),
            cols,
            rows,
            origin_x: Mm(in_range(f(16), -BIG, BIG, tag, index, "origin_x_mm", "finite, within 1e9 mm")?),
            origin_y: Mm(in_range(f(20), -BIG, BIG, tag, index, "origin_y_mm", "finite, within 1e9 mm")?),
            cell: Mm(cell),
            height_min: f(28),
            height_max: f(32),
            max_gradient: in_range(f(36), 0.0, cap, tag, index, "max gradient", "from 0 to the gradient cap")?,
            gradient_cap: cap,
            heights: &[],
            grad_x: &[],
            grad_y: &[],
            flags: &[],
            tiled: Some(tiled),
        };
        if !full {
            return Ok(view);
        }
        let (lo, hi) = view.tiled_extremes();
        if !(lo.is_finite() && hi.is_finite() && lo >= -BIG && hi <= BIG) {
            return Err(bad("height", "finite, within 1e9 mm"));
        }
        if lo.to_bits() != view.height_min.to_bits() || hi.to_bits() != view.height_max.to_bits() {
            return Err(bad("extremes", "the lowest and highest height of the contact nodes"));
        }
        Ok(view)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 5 x 3 field whose every node holds distinct values, with a hole and an edge.
    fn field() -> HeightField {
        let (cols, rows) = (5u32, 3u32);
        let n = (cols * rows) as usize;
        let mut f = HeightField {
            source: None,
            cols,
            rows,
            origin_x: Mm(1.0),
            origin_y: Mm(2.0),
            cell: Mm(0.5),
            gradient_cap: 100.0,
            heights: (0..n).map(|k| 1.0 + k as f32).collect(),
            grad_x: (0..n).map(|k| 0.5 - k as f32).collect(),
            grad_y: (0..n).map(|k| 0.25 * k as f32).collect(),
            flags: alloc::vec![FIELD_CONTACT; n],
            encoding: HeightEncoding::Float,
        };
        // Node 7 has no contact, so its values must be zero; node 8 is at a step.
        (f.heights[7], f.grad_x[7], f.grad_y[7], f.flags[7]) = (0.0, 0.0, 0.0, 0);
        f.flags[8] |= FIELD_EDGE;
        f
    }

    #[test]
    fn cell_nodes_agree_with_the_single_node_reads() {
        let f = field();
        let bytes = f.encode(0).unwrap();
        let view = HeightFieldView::parse(&bytes, 0, true).unwrap();
        let n = f.cols * f.rows;
        for k in 0..n + 8 {
            let got = view.cell_nodes(k);
            if k + f.cols + 1 >= n {
                assert_eq!(got, None, "cell at node {k}");
                continue;
            }
            let nodes = [k, k + 1, k + f.cols, k + f.cols + 1];
            let want = CellNodes {
                heights: nodes.map(|k| view.height_at(k)),
                grad_x: nodes.map(|k| view.gradient_at(k).0),
                grad_y: nodes.map(|k| view.gradient_at(k).1),
                flags: nodes.map(|k| view.flags_at(k)),
            };
            assert_eq!(got, Some(want), "cell at node {k}");
            // And both agree with the owned field the bytes were written from.
            assert_eq!(want.heights, nodes.map(|k| f.heights[k as usize]));
            assert_eq!(want.flags, nodes.map(|k| f.flags[k as usize]));
        }
        assert_eq!(view.cell_nodes(u32::MAX), None);
    }

    #[test]
    fn single_node_reads_are_zero_past_the_last_node() {
        let bytes = field().encode(0).unwrap();
        let view = HeightFieldView::parse(&bytes, 0, true).unwrap();
        for k in [15, 16, u32::MAX / 4, u32::MAX] {
            assert_eq!(view.height_at(k), 0.0);
            assert_eq!(view.gradient_at(k), (0.0, 0.0));
            assert_eq!(view.flags_at(k), 0);
        }
        assert_eq!(view.height_at(14), 15.0);
        assert_eq!(view.flags_at(8), FIELD_CONTACT | FIELD_EDGE);
    }
}
