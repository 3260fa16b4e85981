//! The tiled encoding of a height field (format 4.6, SPEC.md section 9.1):
//! heights quantised to a step, in tiles of 8 x 8 nodes that are empty, one
//! plane, or coded (each code predicted from its neighbours in the tile,
//! the residuals in two fixed widths), grouped in superblocks of 4 x 4 tiles
//! that may all name one record. Identical records and tile lists are
//! stored once, and the index is packed in as few bits as the pool needs.
//! Gradients are not stored: a player derives them from the heights of the
//! cell it is in.
//!
//! A coded tile is decoded whole (its codes depend on the ones before), so
//! a player reads the field through a [`FieldReader`], which keeps the
//! tiles it decoded, and decodes again only when the finger reaches
//! another tile.

mod coded;
mod write;

use crate::bytes::{f32_at, u32_at};
use crate::error::FormatError;
use crate::height::{FIELD_CONTACT, FIELD_EDGE, HeightFieldView};
use crate::{Tag, in_range};

pub(crate) use write::{encode_tiles, write_tables};

/// Nodes along one side of a tile.
pub const TILE: u32 = 8;
/// Tiles along one side of a superblock.
pub const SUPER: u32 = 4;
/// Bytes before the superblock index.
pub(crate) const TILED_HEADER_LEN: usize = 64;
/// The encoding number of the tiled encoding (the word at offset 12).
pub(crate) const ENCODING_TILED: u32 = 2;
/// The encoding number 4.5's tiled fields had (a development version,
/// never released): refused with a message that says so.
pub(crate) const ENCODING_TILED_4_5: u32 = 1;
/// Largest code a writer stores: codes stay exact in `f32`, and node 0's
/// fits the 24 bits of its record's header.
pub const MAX_CODE: u32 = (1 << 24) - 1;
/// Record kinds (header bits 0–1).
const KIND_EMPTY: u32 = 0;
const KIND_PLANE: u32 = 1;
const KIND_CODED: u32 = 2;
/// Record header bits: a contact mask follows; an edge mask follows; the
/// plane has slopes.
const HAS_CONTACT: u32 = 1 << 2;
const HAS_EDGE: u32 = 1 << 3;
const SLOPED: u32 = 1 << 4;

#[inline]
fn word(b: &[u8], w: u32) -> u32 {
    (w as usize).checked_mul(4).and_then(|o| u32_at(b, o)).unwrap_or(0)
}

/// Entry `n` of `w` bits (1 to 32) of a packed table.
#[inline]
fn entry(b: &[u8], n: u32, w: u32) -> u32 {
    let p = n as u64 * w as u64;
    let at = (p / 32) as u32;
    let pair = word(b, at) as u64 | (word(b, at.wrapping_add(1)) as u64) << 32;
    ((pair >> (p % 32)) & ((1u64 << w) - 1)) as u32
}

/// Bits needed to write every number below `n` (at least 1).
#[inline]
pub(crate) fn bits_below(n: u32) -> u32 {
    (32 - n.saturating_sub(1).leading_zeros()).max(1)
}

/// The widths of a superblock entry and of a list entry, for `lists` lists
/// and a pool of `pool` words.
#[inline]
pub(crate) fn index_widths(lists: u32, pool: u32) -> (u32, u32) {
    let record = bits_below(pool);
    (1 + record.max(bits_below(lists)), record)
}

/// Words of a packed table of `n` entries of `w` bits.
#[inline]
pub(crate) fn packed_words(n: u64, w: u32) -> u64 {
    (n * w as u64).div_ceil(32)
}

/// The four nodes of one cell, as the tiled encoding gives them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellHeights {
    /// Heights of the top-left node, its right neighbour, the node below and
    /// the node diagonally below, in mm (0 without contact).
    pub heights: [f32; 4],
    /// Their [`FIELD_CONTACT`] and [`FIELD_EDGE`] bits.
    pub flags: [u8; 4],
}

/// One tile's nodes, decoded: heights (0 without contact) and flags
/// ([`FIELD_CONTACT`], [`FIELD_EDGE`]), node `l` row-major in the tile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TileNodes {
    pub heights: [f32; 64],
    pub flags: [u8; 64],
}

impl TileNodes {
    pub(crate) const EMPTY: TileNodes = TileNodes { heights: [0.0; 64], flags: [0; 64] };

    /// Height and flags of node `l`.
    #[inline]
    pub fn node(&self, l: u32) -> (f32, u8) {
        let l = (l & 63) as usize;
        (self.heights[l], self.flags[l])
    }
}

/// The tables of a tiled field, read in place.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Tiled<'a> {
    /// Superblock entries, packed.
    supers: &'a [u8],
    /// Tile lists, packed.
    lists: &'a [u8],
    /// The records.
    pool: &'a [u8],
    /// Superblocks per row.
    super_cols: u32,
    /// Widths of a superblock entry and of a list entry.
    widths: (u32, u32),
    /// Height of code 0.
    pub base: f32,
    /// Height of one code.
    pub step: f32,
    /// Node spacing (for planes).
    cell: f32,
    /// `1 / cell`, for a player's slopes.
    pub inv_cell: f32,
}

impl<'a> Tiled<'a> {
    /// The record offset of tile `(tx, ty)`.
    #[inline]
    fn record_of(&self, tx: u32, ty: u32) -> u32 {
        let e = entry(self.supers, (ty / SUPER) * self.super_cols + tx / SUPER, self.widths.0);
        if e & 1 != 0 {
            e >> 1
        } else {
            entry(
                self.lists,
                (e >> 1).wrapping_mul(SUPER * SUPER).wrapping_add((ty % SUPER) * SUPER + tx % SUPER),
                self.widths.1,
            )
        }
    }

    /// The masks of the record at `r` with header `head` as stored (all
    /// nodes touching without a contact mask, none at a step without an
    /// edge mask), and the word after them.
    #[inline]
    fn masks(&self, r: u32, head: u32) -> (u64, u64, u32) {
        let body = match head & 3 {
            KIND_PLANE if head & SLOPED != 0 => 3,
            KIND_PLANE => 1,
            _ => 0,
        };
        let mut at = r.wrapping_add(1 + body);
        let mut pair = || {
            let m = word(self.pool, at) as u64 | (word(self.pool, at.wrapping_add(1)) as u64) << 32;
            at = at.wrapping_add(2);
            m
        };
        let contact = if head & HAS_CONTACT != 0 { pair() } else { u64::MAX };
        let edge = if head & HAS_EDGE != 0 { pair() } else { 0 };
        (contact, edge, at)
    }

    /// Decodes tile `(tx, ty)` into `out`.
    #[inline(never)]
    pub(crate) fn decode(&self, tx: u32, ty: u32, out: &mut TileNodes) {
        let r = self.record_of(tx, ty);
        let head = word(self.pool, r);
        let (contact, edge, at) = self.masks(r, head);
        let kind = head & 3;
        if kind != KIND_PLANE && kind != KIND_CODED {
            *out = TileNodes::EMPTY;
            return;
        }
        if contact == u64::MAX && edge == 0 {
            // Most tiles: every node touching, none at a step.
            out.flags = [FIELD_CONTACT; 64];
        } else {
            let edge = edge & contact;
            for (l, f) in out.flags.iter_mut().enumerate() {
                *f = ((contact >> l & 1) as u8 * FIELD_CONTACT) | ((edge >> l & 1) as u8 * FIELD_EDGE);
            }
        }
        if kind == KIND_PLANE {
            let h0 = f32::from_bits(word(self.pool, r.wrapping_add(1)));
            if head & SLOPED == 0 {
                out.heights = [h0; 64];
            } else {
                let gx = f32::from_bits(word(self.pool, r.wrapping_add(2)));
                let gy = f32::from_bits(word(self.pool, r.wrapping_add(3)));
                for (l, h) in out.heights.iter_mut().enumerate() {
                    let (i, j) = (tx.wrapping_mul(TILE) + l as u32 % TILE, ty.wrapping_mul(TILE) + l as u32 / TILE);
                    *h = h0 + gx * (i as f32 * self.cell) + gy * (j as f32 * self.cell);
                }
            }
        } else {
            let mut codes = [0i32; 64];
            coded::decode(self.pool, at, head >> 8, &mut codes);
            for (h, c) in out.heights.iter_mut().zip(codes) {
                *h = self.base + c as f32 * self.step;
            }
        }
        if contact != u64::MAX {
            for (h, f) in out.heights.iter_mut().zip(out.flags) {
                if f == 0 {
                    *h = 0.0;
                }
            }
        }
    }

    /// Height and flags of node `(i, j)` (inside the field), decoding its tile.
    pub fn node(&self, i: u32, j: u32) -> (f32, u8) {
        let mut t = TileNodes::EMPTY;
        self.decode(i / TILE, j / TILE, &mut t);
        t.node((j % TILE) * TILE + i % TILE)
    }

    /// The four nodes of the cell whose top-left node is `(i, j)` from the
    /// tiles `cache` (this field's) holds, or `None` when one of them is
    /// not decoded yet; the caller keeps `i + 1` and `j + 1` inside the
    /// field. It decodes nothing, so a player's common path makes no call.
    #[inline]
    pub fn kept_cell(&self, cache: &TileCache, i: u32, j: u32) -> Option<CellHeights> {
        let (li, lj) = (i % TILE, j % TILE);
        if li + 1 < TILE && lj + 1 < TILE {
            // All four in one tile (49 cells of 64).
            let t = cache.get(i / TILE, j / TILE)?;
            let l = (lj * TILE + li) as usize;
            let (h, f) = (&t.heights, &t.flags);
            return Some(CellHeights {
                heights: [h[l], h[l + 1], h[l + 8], h[l + 9]],
                flags: [f[l], f[l + 1], f[l + 8], f[l + 9]],
            });
        }
        // A cell on a tile's last row or column: its nodes lie in two or
        // four tiles.
        let (tx, ty) = (i / TILE, j / TILE);
        let (tx1, a1) = if li + 1 < TILE { (tx, li + 1) } else { (tx + 1, 0) };
        let (ty1, b1) = if lj + 1 < TILE { (ty, lj + 1) } else { (ty + 1, 0) };
        let (h0, f0) = cache.get(tx, ty)?.node(lj * TILE + li);
        let (h1, f1) = cache.get(tx1, ty)?.node(lj * TILE + a1);
        let (h2, f2) = cache.get(tx, ty1)?.node(b1 * TILE + li);
        let (h3, f3) = cache.get(tx1, ty1)?.node(b1 * TILE + a1);
        Some(CellHeights { heights: [h0, h1, h2, h3], flags: [f0, f1, f2, f3] })
    }

    /// Decodes into `cache` the tiles of the cell whose top-left node is
    /// `(i, j)` that it does not hold.
    pub fn keep_cell(&self, cache: &mut TileCache, i: u32, j: u32) {
        for (tx, ty) in [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)].map(|(i, j)| (i / TILE, j / TILE)) {
            cache.load(self, tx, ty);
        }
    }

    /// The plane `(h0, gx, gy)` of the tile holding node `(i, j)`, if it is a plane tile.
    pub fn plane_at(&self, i: u32, j: u32) -> Option<(f32, f32, f32)> {
        let r = self.record_of(i / TILE, j / TILE);
        let head = word(self.pool, r);
        (head & 3 == KIND_PLANE).then(|| {
            let f = |k: u32| f32::from_bits(word(self.pool, r.wrapping_add(k)));
            if head & SLOPED != 0 { (f(1), f(2), f(3)) } else { (f(1), 0.0, 0.0) }
        })
    }
}

/// A height field read by a player: its view and, for a tiled field, the
/// tiles decoded so far, kept between samples (a coded tile's codes depend
/// on the ones before them, so a tile is decoded whole, once, when the
/// finger first needs it).
///
/// The reader owns its tiles, so they always belong to its field. Four
/// slots, one for each parity of the tile's column and row: the up to four
/// tiles a cell touches never evict one another, and a finger that stays
/// in a tile decodes it once. About 1.3 KB; it allocates nothing.
///
/// ```
/// use taxel_format::{BundleView, ChunkView, FieldReader, sample};
///
/// let bytes = sample::every_kind().to_bytes().unwrap();
/// let bundle = BundleView::parse(&bytes).unwrap();
/// let view = bundle.chunks().find_map(|c| if let ChunkView::Height(h) = c { Some(h) } else { None }).unwrap();
/// let mut reader = FieldReader::new(view);
/// // A 4.0 field is read in place (`HeightFieldView::cell_nodes`): no tiles.
/// assert!(reader.cell_heights(0, 0).is_none());
/// ```
#[derive(Debug, Clone)]
pub struct FieldReader<'a> {
    view: HeightFieldView<'a>,
    tiles: TileCache,
}

impl<'a> FieldReader<'a> {
    /// A reader of `view`, no tile decoded yet.
    pub fn new(view: HeightFieldView<'a>) -> Self {
        FieldReader { view, tiles: TileCache::new() }
    }

    /// The field.
    #[inline]
    pub fn view(&self) -> &HeightFieldView<'a> {
        &self.view
    }

    /// The four nodes of the cell whose top-left node is `(i, j)` of a
    /// tiled field, from the tiles kept or decoded now; `None` when the
    /// field is not tiled or the cell is not inside it (`i + 1 < cols`,
    /// `j + 1 < rows`).
    #[inline]
    pub fn cell_heights(&mut self, i: u32, j: u32) -> Option<CellHeights> {
        self.keep_cell(i, j);
        self.kept_cell(i, j)
    }

    /// [`FieldReader::cell_heights`] from the tiles already kept only:
    /// `None` also when one of the cell's tiles is not decoded yet. It
    /// decodes nothing, so a player's common path calls nothing and keeps
    /// its values in registers; on `None` it calls
    /// [`FieldReader::keep_cell`] and asks again.
    #[inline]
    pub fn kept_cell(&self, i: u32, j: u32) -> Option<CellHeights> {
        let t = self.view.tiled()?;
        let inside = i.checked_add(1)? < self.view.cols && j.checked_add(1)? < self.view.rows;
        if !inside {
            return None;
        }
        t.kept_cell(&self.tiles, i, j)
    }

    /// Decodes the tiles of the cell whose top-left node is `(i, j)` that
    /// are not kept yet (nothing for a 4.0 field or a cell outside it).
    #[inline(never)]
    pub fn keep_cell(&mut self, i: u32, j: u32) {
        let Some(t) = self.view.tiled() else { return };
        let inside = i.checked_add(1).is_some_and(|i1| i1 < self.view.cols)
            && j.checked_add(1).is_some_and(|j1| j1 < self.view.rows);
        if inside {
            t.keep_cell(&mut self.tiles, i, j);
        }
    }
}

/// The tiles of one tiled field decoded so far (see [`FieldReader`]).
#[derive(Debug, Clone)]
pub(crate) struct TileCache {
    // The key of the tile each slot holds (`TileCache::slot`).
    keys: [u32; 4],
    tiles: [TileNodes; 4],
}

impl TileCache {
    const NONE: u32 = u32::MAX;

    /// An empty cache.
    pub(crate) const fn new() -> Self {
        TileCache { keys: [Self::NONE; 4], tiles: [TileNodes::EMPTY; 4] }
    }

    /// The slot and key of tile `(tx, ty)`: one slot for each parity of
    /// its column and row, the key `ty << 16 | tx` (both below 2^11).
    #[inline]
    fn slot(tx: u32, ty: u32) -> (usize, u32) {
        (((tx & 1) | (ty & 1) << 1) as usize, ty << 16 | tx)
    }

    /// Tile `(tx, ty)` when its slot holds it.
    #[inline]
    fn get(&self, tx: u32, ty: u32) -> Option<&TileNodes> {
        let (slot, key) = Self::slot(tx, ty);
        (self.keys[slot] == key).then(|| &self.tiles[slot])
    }

    /// Decodes tile `(tx, ty)` into its slot unless the slot holds it.
    fn load(&mut self, t: &Tiled<'_>, tx: u32, ty: u32) {
        let (slot, key) = Self::slot(tx, ty);
        if self.keys[slot] != key {
            t.decode(tx, ty, &mut self.tiles[slot]);
            self.keys[slot] = key;
        }
    }
}

/// Whether the bits of the packed table at word `at` after its first `used`
/// bits, to the end of the word, are 0.
fn zero_past(b: &[u8], at: u32, used: u64) -> bool {
    used.is_multiple_of(32) || word(b, at.wrapping_add((used / 32) as u32)) >> (used % 32) == 0
}

/// Reads the tiled part of a field chunk: the tables, checked for length;
/// with `full`, every record they name.
pub(crate) fn parse_tiled<'a>(
    d: &'a [u8],
    index: u32,
    cols: u32,
    rows: u32,
    cell: f32,
    cap: f32,
    full: bool,
) -> Result<Tiled<'a>, FormatError> {
    let tag = Tag::HEIGHT;
    let bad = |field, expected| FormatError::InvalidValue { tag, index, field, expected };
    let f = |o| f32_at(d, o).unwrap_or(f32::NAN);
    let step = in_range(f(48), 1e-12, 1e9, tag, index, "height step", "above 0, within 1e9 mm")?;
    let base = in_range(f(52), -1e9, 1e9, tag, index, "height base", "finite, within 1e9 mm")?;
    let (scols, srows) = (cols.div_ceil(TILE).div_ceil(SUPER), rows.div_ceil(TILE).div_ceil(SUPER));
    let s = scols as u64 * srows as u64;
    let lists = u32_at(d, 56).unwrap_or(0);
    let w = u32_at(d, 60).unwrap_or(0);
    if lists as u64 > s {
        return Err(bad("tile lists", "at most one per superblock"));
    }
    if w == 0 || w > 1 << 30 {
        return Err(bad("pool", "1 to 2^30 words"));
    }
    let widths = index_widths(lists, w);
    let (sw, lw) = (packed_words(s, widths.0), packed_words(16 * lists as u64, widths.1));
    let expected = TILED_HEADER_LEN as u64 + 4 * (sw + lw + w as u64);
    if d.len() as u64 != expected {
        return Err(FormatError::ChunkLength { tag, index, expected, found: d.len() as u64 });
    }
    let length = || FormatError::ChunkLength { tag, index, expected, found: d.len() as u64 };
    let (supers, rest) =
        d.get(TILED_HEADER_LEN..).and_then(|b| b.split_at_checked(4 * sw as usize)).ok_or_else(length)?;
    let (lists_bytes, pool) = rest.split_at_checked(4 * lw as usize).ok_or_else(length)?;
    let t =
        Tiled { supers, lists: lists_bytes, pool, super_cols: scols, widths, base, step, cell, inv_cell: 1.0 / cell };
    if !full {
        return Ok(t);
    }
    if !zero_past(supers, 0, s * widths.0 as u64) || !zero_past(lists_bytes, 0, 16 * lists as u64 * widths.1 as u64) {
        return Err(bad("index", "0 in the bits after the last entry"));
    }
    for k in 0..s as u32 {
        let e = entry(supers, k, widths.0);
        if e & 1 != 0 {
            check_record(&t, e >> 1, w, cap, index)?;
        } else {
            if e >> 1 >= lists {
                return Err(bad("superblock", "a record or a list inside the tables"));
            }
            for l in 0..SUPER * SUPER {
                check_record(&t, entry(lists_bytes, (e >> 1) * SUPER * SUPER + l, widths.1), w, cap, index)?;
            }
        }
    }
    Ok(t)
}

/// Checks the record at word `r` of a pool of `w` words.
fn check_record(t: &Tiled<'_>, r: u32, w: u32, cap: f32, index: u32) -> Result<(), FormatError> {
    let tag = Tag::HEIGHT;
    let bad = |field, expected| FormatError::InvalidValue { tag, index, field, expected };
    if r >= w {
        return Err(bad("tile record", "an offset inside the pool"));
    }
    let head = word(t.pool, r);
    let kind = head & 3;
    let reserved = match kind {
        KIND_PLANE => !(3 | HAS_CONTACT | HAS_EDGE | SLOPED),
        KIND_CODED => 0xf0,
        _ => !0,
    };
    if kind == 3 || head & reserved != 0 {
        return Err(bad("tile record", "kind 0 to 2, reserved bits 0"));
    }
    if kind == KIND_EMPTY {
        return Ok(());
    }
    let (contact, edge, at) = t.masks(r, head);
    let stream = if kind == KIND_CODED {
        let widths = coded::widths(t.pool, at);
        if widths.iter().any(|&w| w > coded::MAX_WIDTH) {
            return Err(bad("coded tile", "residual widths of at most 32 bits"));
        }
        coded::stream_bits(widths)
    } else {
        0
    };
    if at as u64 + stream.div_ceil(32) as u64 > w as u64 {
        return Err(bad("tile record", "inside the pool"));
    }
    if !zero_past(t.pool, at, stream as u64) {
        return Err(bad("coded tile", "0 in the bits after the last residual"));
    }
    if head & HAS_CONTACT != 0 && (contact == 0 || contact == u64::MAX) {
        return Err(bad("contact mask", "some nodes, not all (an empty tile or no mask otherwise)"));
    }
    if head & HAS_EDGE != 0 && (edge == 0 || edge & !contact != 0) {
        return Err(bad("edge mask", "contact nodes only, at least one"));
    }
    if kind == KIND_PLANE {
        let f = |k: u32| f32::from_bits(word(t.pool, r + k));
        in_range(f(1), -1e9, 1e9, tag, index, "plane height", "finite, within 1e9 mm")?;
        if head & SLOPED != 0 {
            let cap = cap * (1.0 + 1e-6);
            let gx = in_range(f(2), -cap, cap, tag, index, "plane gradient x", "within the gradient cap")?;
            let gy = in_range(f(3), -cap, cap, tag, index, "plane gradient y", "within the gradient cap")?;
            if gx == 0.0 && gy == 0.0 {
                return Err(bad("plane tile", "slopes only when one is not 0"));
            }
        }
        return Ok(());
    }
    // A coded tile: residual 0 at the nodes without contact, and node 0,
    // when it has none, coded as the first node that has.
    let first = head >> 8;
    let residuals = coded::residuals(t.pool, at);
    if (1..64).any(|l| contact >> l & 1 == 0 && residuals[l] != 0) {
        return Err(bad("coded tile", "residual 0 at nodes without contact"));
    }
    if contact & 1 == 0 {
        let mut codes = [0i32; 64];
        coded::decode(t.pool, at, first, &mut codes);
        let want = (0..64).find(|&l| contact >> l & 1 != 0).map_or(0, |l| codes[l] as u32);
        if first != want {
            return Err(bad("coded tile", "node 0 without contact coded as the first node with contact"));
        }
    }
    Ok(())
}
