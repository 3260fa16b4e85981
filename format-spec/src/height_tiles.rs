//! The tiled encoding of a height field (format 4.5, SPEC.md section 9.1):
//! heights quantised to a step, in tiles of 8 x 8 nodes that are empty,
//! one plane, or sampled (a base code, a plane of codes and packed
//! residuals), grouped in superblocks of 4 x 4 tiles that may all name one record. Identical
//! records and tile lists are stored once. Gradients are not stored: a
//! player derives them from the heights of the cell it is in.

use alloc::collections::BTreeMap;
use alloc::vec::Vec;

use crate::bytes::{Out, f32_at, u32_at};
use crate::error::FormatError;
use crate::height::{FIELD_CONTACT, FIELD_EDGE, HeightField};
use crate::{Tag, in_range};

/// Nodes along one side of a tile.
pub const TILE: u32 = 8;
/// Tiles along one side of a superblock.
pub const SUPER: u32 = 4;
/// Bytes before the superblock index.
pub(crate) const TILED_HEADER_LEN: usize = 64;
/// The encoding number of the tiled encoding (the word at offset 12).
pub(crate) const ENCODING_TILED: u32 = 1;
/// Largest number of bits of one residual.
pub const MAX_RESIDUAL_BITS: u32 = 24;
/// Largest code (base code, multiplier): codes stay exact in `f32`.
const MAX_CODE: u32 = (1 << MAX_RESIDUAL_BITS) - 1;
/// A superblock entry whose every tile names one record.
const UNIFORM: u32 = 1 << 31;
/// Record kinds.
const KIND_EMPTY: u32 = 0;
const KIND_PLANE: u32 = 1;
const KIND_SAMPLED: u32 = 2;
/// Record header bits: a contact mask follows; an edge mask follows.
const HAS_CONTACT: u32 = 1 << 16;
const HAS_EDGE: u32 = 1 << 17;

/// The words of the pool, read in place.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Tiled<'a> {
    /// Superblock entries, `4 * S` bytes.
    pub supers: &'a [u8],
    /// The pool of tile lists and records, `4 * W` bytes.
    pub pool: &'a [u8],
    /// Superblocks per row.
    pub super_cols: u32,
    /// Height of code 0.
    pub base: f32,
    /// Height of one code.
    pub step: f32,
    /// Node spacing (for planes).
    pub cell: f32,
}

#[inline]
fn word(b: &[u8], w: u32) -> u32 {
    (w as usize).checked_mul(4).and_then(|o| u32_at(b, o)).unwrap_or(0)
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

impl<'a> Tiled<'a> {
    /// The record offset of tile `(tx, ty)`.
    #[inline]
    fn record_of(&self, tx: u32, ty: u32) -> u32 {
        let e = word(self.supers, (ty / SUPER) * self.super_cols + tx / SUPER);
        if e & UNIFORM != 0 { e & !UNIFORM } else { word(self.pool, e.wrapping_add((ty % SUPER) * SUPER + tx % SUPER)) }
    }

    /// Height and flags of node `(i, j)` of the tile whose record is at `r`
    /// (`l` is the node's index in the tile, row-major).
    #[inline]
    fn node_in(&self, r: u32, i: u32, j: u32, l: u32) -> (f32, u8) {
        let head = word(self.pool, r);
        let kind = head & 0xff;
        let bits = (head >> 8) & 0xff;
        let body = match kind {
            KIND_PLANE => 3,
            KIND_SAMPLED => 4 + 2 * bits,
            _ => return (0.0, 0),
        };
        let mut at = r + 1 + body;
        let mut flags = FIELD_CONTACT;
        if head & HAS_CONTACT != 0 {
            if !mask_bit(self.pool, at, l) {
                return (0.0, 0);
            }
            at += 2;
        }
        if head & HAS_EDGE != 0 && mask_bit(self.pool, at, l) {
            flags |= FIELD_EDGE;
        }
        let h = if kind == KIND_PLANE {
            let h0 = f32::from_bits(word(self.pool, r + 1));
            let gx = f32::from_bits(word(self.pool, r + 2));
            let gy = f32::from_bits(word(self.pool, r + 3));
            h0 + gx * (i as f32 * self.cell) + gy * (j as f32 * self.cell)
        } else {
            let code = sampled_code(self.pool, r, l, bits);
            self.base + code as f32 * self.step
        };
        (h, flags)
    }

    /// Height and flags of node `(i, j)` (inside the field).
    #[inline]
    pub fn node(&self, i: u32, j: u32) -> (f32, u8) {
        let r = self.record_of(i / TILE, j / TILE);
        self.node_in(r, i, j, (j % TILE) * TILE + i % TILE)
    }

    /// The four nodes of the cell whose top-left node is `(i, j)`; the
    /// caller keeps `i + 1` and `j + 1` inside the field.
    #[inline]
    pub fn cell(&self, i: u32, j: u32) -> CellHeights {
        let (li, lj) = (i % TILE, j % TILE);
        let n = if li + 1 < TILE && lj + 1 < TILE {
            // All four in one tile: one record lookup.
            let r = self.record_of(i / TILE, j / TILE);
            let l = lj * TILE + li;
            [
                self.node_in(r, i, j, l),
                self.node_in(r, i + 1, j, l + 1),
                self.node_in(r, i, j + 1, l + TILE),
                self.node_in(r, i + 1, j + 1, l + TILE + 1),
            ]
        } else {
            [self.node(i, j), self.node(i + 1, j), self.node(i, j + 1), self.node(i + 1, j + 1)]
        };
        CellHeights { heights: n.map(|v| v.0), flags: n.map(|v| v.1) }
    }

    /// The plane `(h0, gx, gy)` of the tile holding node `(i, j)`, if it is a plane tile.
    pub fn plane_at(&self, i: u32, j: u32) -> Option<(f32, f32, f32)> {
        let r = self.record_of(i / TILE, j / TILE);
        (word(self.pool, r) & 0xff == KIND_PLANE).then(|| {
            let f = |k| f32::from_bits(word(self.pool, r + k));
            (f(1), f(2), f(3))
        })
    }
}

/// The code of node `l` of the sampled record at `r` with `bits`-bit
/// residuals: `c0 + ((sx a + sy b) >> 8) + m r_l` for the node's place
/// `(a, b)` in the tile (a checked record keeps it within `0..2^24`).
#[inline]
fn sampled_code(pool: &[u8], r: u32, l: u32, bits: u32) -> i64 {
    let c0 = word(pool, r + 1) as i32 as i64;
    let m = word(pool, r + 2) as i64;
    let (sx, sy) = (word(pool, r + 3) as i32 as i64, word(pool, r + 4) as i32 as i64);
    let pred = (sx * (l % TILE) as i64 + sy * (l / TILE) as i64) >> 8;
    c0 + pred + m * residual(pool, r + 5, l, bits) as i64
}

#[inline]
fn mask_bit(pool: &[u8], at: u32, l: u32) -> bool {
    word(pool, at + l / 32) >> (l % 32) & 1 != 0
}

/// Residual `l` of `bits` bits from the bit stream starting at word `at`.
#[inline]
fn residual(pool: &[u8], at: u32, l: u32, bits: u32) -> u32 {
    if bits == 0 || bits > MAX_RESIDUAL_BITS {
        return 0;
    }
    let p = l * bits;
    let w = at + p / 32;
    let pair = word(pool, w) as u64 | (word(pool, w + 1) as u64) << 32;
    ((pair >> (p % 32)) as u32) & ((1u32 << bits) - 1)
}

/// Records of a field being written: words, with identical records and
/// lists stored once.
struct Pool {
    words: Vec<u32>,
    seen: BTreeMap<Vec<u32>, u32>,
}

impl Pool {
    fn add(&mut self, rec: Vec<u32>) -> u32 {
        if let Some(&at) = self.seen.get(&rec) {
            return at;
        }
        let at = self.words.len() as u32;
        self.words.extend_from_slice(&rec);
        self.seen.insert(rec, at);
        at
    }
}

/// The nodes of tile `(tx, ty)`: `(local index, i, j, height, flags)` of
/// each node inside the field.
fn tile_nodes(f: &HeightField, tx: u32, ty: u32) -> Vec<(u32, u32, u32, f32, u8)> {
    let mut v = Vec::with_capacity(64);
    for l in 0..TILE * TILE {
        let (i, j) = (tx * TILE + l % TILE, ty * TILE + l / TILE);
        if i < f.cols && j < f.rows {
            let k = (j * f.cols + i) as usize;
            let fl = f.flags.get(k).copied().unwrap_or(0);
            v.push((l, i, j, f.heights.get(k).copied().unwrap_or(0.0), fl));
        }
    }
    v
}

/// The plane through a tile's contact nodes, quantised so that the tiles of
/// one plane of the model write the same record, when every node lies within
/// half a step of it.
fn plane_of(f: &HeightField, step: f32, nodes: &[(u32, u32, u32, f32, u8)]) -> Option<[f32; 3]> {
    let c: Vec<_> = nodes.iter().filter(|n| n.4 & FIELD_CONTACT != 0).collect();
    if c.len() < 3 {
        return None;
    }
    let cell = f.cell.0 as f64;
    // Least squares h = a + b x + c y about the nodes' mean (x, y in mm).
    let k = c.len() as f64;
    let (mx, my, mh) = c
        .iter()
        .fold((0.0, 0.0, 0.0), |s, n| (s.0 + n.1 as f64 * cell / k, s.1 + n.2 as f64 * cell / k, s.2 + n.3 as f64 / k));
    let (mut sxx, mut sxy, mut syy, mut sxh, mut syh) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for n in &c {
        let (x, y, h) = (n.1 as f64 * cell - mx, n.2 as f64 * cell - my, n.3 as f64 - mh);
        sxx += x * x;
        sxy += x * y;
        syy += y * y;
        sxh += x * h;
        syh += y * h;
    }
    let det = sxx * syy - sxy * sxy;
    if det.is_nan() || det.abs() <= 1e-12 * (sxx * syy).max(f64::MIN_POSITIVE) {
        return None;
    }
    let gx = (sxh * syy - syh * sxy) / det;
    let gy = (syh * sxx - sxh * sxy) / det;
    // The gradient on the coarsest lattice of 2^-4, 2^-6, ... 2^-24 that
    // still holds every node within half a step, and the height at the
    // field's origin on multiples of the step: so every tile of one plane of
    // the model (an incline of 1 in 8, a level terrace) finds the same
    // numbers from its own nodes, and its record is stored once.
    let cap = f.gradient_cap * (1.0 + 1e-6);
    for k in (4..=24).step_by(2) {
        let unit = (1u32 << k) as f64;
        let (gx, gy) = (((gx * unit).round() / unit) as f32, ((gy * unit).round() / unit) as f32);
        let h0 = mh - gx as f64 * mx - gy as f64 * my;
        let h0 = ((h0 / step as f64).round() * step as f64) as f32;
        if ![h0, gx, gy].iter().all(|v| v.is_finite()) || gx.abs() > cap || gy.abs() > cap || h0.abs() > 1e9 {
            return None;
        }
        if fits(f, step, nodes, [h0, gx, gy]) {
            return Some([h0, gx, gy]);
        }
    }
    None
}

/// Whether every contact node lies within half a step of plane `p`.
fn fits(f: &HeightField, step: f32, nodes: &[(u32, u32, u32, f32, u8)], p: [f32; 3]) -> bool {
    let half = step as f64 / 2.0;
    nodes.iter().filter(|n| n.4 & FIELD_CONTACT != 0).all(|n| {
        let h = p[0] + p[1] * (n.1 as f32 * f.cell.0) + p[2] * (n.2 as f32 * f.cell.0);
        (h as f64 - n.3 as f64).abs() <= half
    })
}

/// Greatest common divisor.
fn gcd(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// The record of one tile, and its plane when it is a plane tile. A tile
/// first tries the planes of its neighbours to the left and above (`near`),
/// so one plane of the model is one record however far it reaches.
fn record(
    f: &HeightField,
    step: f32,
    base: f32,
    (tx, ty): (u32, u32),
    near: [Option<[f32; 3]>; 2],
) -> Result<(Vec<u32>, Option<[f32; 3]>), &'static str> {
    let nodes = tile_nodes(f, tx, ty);
    // Nodes past the field's edge are never read: they count as touching,
    // so an edge tile needs no mask for them and matches the tiles inside.
    let mut contact = [u32::MAX; 2];
    let mut edge = [0u32; 2];
    for n in &nodes {
        if n.4 & FIELD_CONTACT == 0 {
            contact[(n.0 / 32) as usize] &= !(1 << (n.0 % 32));
        } else if n.4 & FIELD_EDGE != 0 {
            edge[(n.0 / 32) as usize] |= 1 << (n.0 % 32);
        }
    }
    if nodes.iter().all(|n| n.4 & FIELD_CONTACT == 0) {
        return Ok((alloc::vec![KIND_EMPTY], None));
    }
    let mut masks = Vec::new();
    let mut flags = 0;
    if contact != [u32::MAX, u32::MAX] {
        flags |= HAS_CONTACT;
        masks.extend_from_slice(&contact);
    }
    if edge != [0, 0] {
        flags |= HAS_EDGE;
        masks.extend_from_slice(&edge);
    }
    let plane = near.into_iter().flatten().find(|&p| fits(f, step, &nodes, p)).or_else(|| plane_of(f, step, &nodes));
    if let Some([h0, gx, gy]) = plane {
        let mut r = alloc::vec![KIND_PLANE | flags, h0.to_bits(), gx.to_bits(), gy.to_bits()];
        r.extend_from_slice(&masks);
        return Ok((r, plane));
    }
    let mut codes = [0i64; 64];
    for n in nodes.iter().filter(|n| n.4 & FIELD_CONTACT != 0) {
        let c = ((n.3 as f64 - base as f64) / step as f64).round();
        if !(0.0..=MAX_CODE as f64).contains(&c) {
            return Err("heights within 2^24 - 1 steps of the lowest");
        }
        codes[n.0 as usize] = c as i64;
    }
    let touching: Vec<u32> = nodes.iter().filter(|n| n.4 & FIELD_CONTACT != 0).map(|n| n.0).collect();
    // The codes less a plane of codes (slopes in 1/256 code a node, from
    // their least-squares plane) when that needs fewer bits than the codes
    // themselves: a smooth surface's residuals are its bending within the
    // tile, a terrace's or a step's are its levels.
    let slopes = code_slopes(&touching, &codes);
    let best = [(0, 0), slopes].into_iter().map(|sl| sampled(&touching, &codes, sl)).min_by_key(|r| r.0);
    let Some((bits, c0, m, (sx, sy), res)) = best else { return Err("a tile with contact") };
    let mut packed = alloc::vec![0u32; 2 * bits as usize];
    for (l, &r) in res.iter().enumerate() {
        let p = l as u32 * bits;
        for b in 0..bits {
            if r >> b & 1 != 0 {
                let q = p + b;
                packed[(q / 32) as usize] |= 1 << (q % 32);
            }
        }
    }
    let mut r = alloc::vec![KIND_SAMPLED | bits << 8 | flags, c0 as i32 as u32, m, sx as u32, sy as u32];
    r.extend_from_slice(&packed);
    r.extend_from_slice(&masks);
    Ok((r, None))
}

/// The least-squares slopes of the codes of nodes `l` along the tile's
/// columns and rows, in 1/256 code a node.
fn code_slopes(l: &[u32], codes: &[i64; 64]) -> (i32, i32) {
    let k = l.len() as f64;
    let at = |l: u32| ((l % TILE) as f64, (l / TILE) as f64, codes[l as usize] as f64);
    let (ma, mb, mc) = l.iter().fold((0.0, 0.0, 0.0), |s, &l| {
        let (a, b, c) = at(l);
        (s.0 + a / k, s.1 + b / k, s.2 + c / k)
    });
    let (mut saa, mut sab, mut sbb, mut sac, mut sbc) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for &l in l {
        let (a, b, c) = at(l);
        let (a, b, c) = (a - ma, b - mb, c - mc);
        (saa, sab, sbb, sac, sbc) = (saa + a * a, sab + a * b, sbb + b * b, sac + a * c, sbc + b * c);
    }
    let det = saa * sbb - sab * sab;
    if det.is_nan() || det <= 1e-9 {
        return (0, 0);
    }
    let q = |v: f64| (v * 256.0).round().clamp(-(1 << 30) as f64, (1 << 30) as f64) as i32;
    (q((sac * sbb - sbc * sab) / det), q((sbc * saa - sac * sab) / det))
}

/// A sampled tile's numbers with code slopes `sl`: residual bits, base
/// code, multiplier, slopes and the 64 residuals.
type Sampled = (u32, i64, u32, (i32, i32), [u32; 64]);

fn sampled(l: &[u32], codes: &[i64; 64], sl: (i32, i32)) -> Sampled {
    let pred = |l: u32| (sl.0 as i64 * (l % TILE) as i64 + sl.1 as i64 * (l / TILE) as i64) >> 8;
    let d = |l: u32| codes[l as usize] - pred(l);
    let c0 = l.iter().map(|&l| d(l)).min().unwrap_or(0);
    let m = l.iter().fold(0u64, |g, &l| gcd(g, (d(l) - c0) as u64)).max(1);
    let mut res = [0u32; 64];
    let mut top = 0u64;
    for &l in l {
        let r = (d(l) - c0) as u64 / m;
        top = top.max(r);
        res[l as usize] = r.min(u32::MAX as u64) as u32;
    }
    let bits = 64 - top.leading_zeros();
    // Residuals that do not fit in 24 bits cannot be stored: such a choice
    // of slopes is never the smaller one (the plain codes fit).
    let bits = if bits > MAX_RESIDUAL_BITS || m > MAX_CODE as u64 { u32::MAX } else { bits };
    (bits, c0, m as u32, sl, res)
}

/// The superblock index and the pool of field `f` in the tiled encoding
/// with height step `step` and base `base`.
pub(crate) fn encode_tiles(f: &HeightField, step: f32, base: f32) -> Result<(Vec<u32>, Vec<u32>), &'static str> {
    let (tcols, trows) = (f.cols.div_ceil(TILE), f.rows.div_ceil(TILE));
    let (scols, srows) = (tcols.div_ceil(SUPER), trows.div_ceil(SUPER));
    let mut pool = Pool { words: Vec::new(), seen: BTreeMap::new() };
    let mut of_tile = Vec::with_capacity((tcols * trows) as usize);
    let mut planes: Vec<Option<[f32; 3]>> = Vec::with_capacity((tcols * trows) as usize);
    for ty in 0..trows {
        for tx in 0..tcols {
            let left = if tx > 0 { planes.last().copied().flatten() } else { None };
            let above = if ty > 0 { planes.get(((ty - 1) * tcols + tx) as usize).copied().flatten() } else { None };
            let (rec, plane) = record(f, step, base, (tx, ty), [left, above])?;
            of_tile.push(pool.add(rec));
            planes.push(plane);
        }
    }
    // Lists after every record, so records are numbered in tile order.
    let mut lists = Pool { words: Vec::new(), seen: BTreeMap::new() };
    let records_len = pool.words.len() as u32;
    let mut supers = Vec::with_capacity((scols * srows) as usize);
    for sy in 0..srows {
        for sx in 0..scols {
            let mut list = Vec::with_capacity((SUPER * SUPER) as usize);
            for k in 0..SUPER * SUPER {
                let (tx, ty) = (sx * SUPER + k % SUPER, sy * SUPER + k / SUPER);
                // A tile past the field's last one names the superblock's first tile's record.
                list.push(if tx < tcols && ty < trows { of_tile[(ty * tcols + tx) as usize] } else { u32::MAX });
            }
            let first = list[0];
            for e in list.iter_mut().filter(|e| **e == u32::MAX) {
                *e = first;
            }
            if list.iter().all(|&e| e == first) {
                supers.push(UNIFORM | first);
            } else {
                supers.push(records_len + lists.add(list));
            }
        }
    }
    pool.words.extend_from_slice(&lists.words);
    if pool.words.len() >= UNIFORM as usize {
        return Err("fewer than 2^31 words of tiles");
    }
    Ok((supers, pool.words))
}

/// Writes the header's tiled part and the tables after the common header.
pub(crate) fn write_tables(w: &mut Out<'_>, step: f32, base: f32, supers: &[u32], pool: &[u32]) {
    w.f32(step).f32(base).u32(supers.len() as u32).u32(pool.len() as u32);
    for &s in supers {
        w.u32(s);
    }
    for &p in pool {
        w.u32(p);
    }
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
    let s = u32_at(d, 56).unwrap_or(0);
    let w = u32_at(d, 60).unwrap_or(0);
    if s as u64 != scols as u64 * srows as u64 {
        return Err(bad("superblocks", "one entry per 64 x 64 nodes"));
    }
    let expected = TILED_HEADER_LEN as u64 + 4 * s as u64 + 4 * w as u64;
    if d.len() as u64 != expected {
        return Err(FormatError::ChunkLength { tag, index, expected, found: d.len() as u64 });
    }
    let (supers, pool) = d
        .get(TILED_HEADER_LEN..)
        .and_then(|b| b.split_at_checked(4 * s as usize))
        .ok_or(FormatError::ChunkLength { tag, index, expected, found: d.len() as u64 })?;
    let t = Tiled { supers, pool, super_cols: scols, base, step, cell };
    if !full {
        return Ok(t);
    }
    for k in 0..s {
        let e = word(supers, k);
        if e & UNIFORM != 0 {
            check_record(&t, e & !UNIFORM, w, cap, index)?;
        } else {
            if e as u64 + (SUPER * SUPER) as u64 > w as u64 {
                return Err(bad("tile list", "16 entries inside the pool"));
            }
            for l in 0..SUPER * SUPER {
                check_record(&t, word(pool, e + l), w, cap, index)?;
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
    let kind = head & 0xff;
    let bits = (head >> 8) & 0xff;
    if head & !(0xffff | HAS_CONTACT | HAS_EDGE) != 0 || kind > KIND_SAMPLED || bits > MAX_RESIDUAL_BITS {
        return Err(bad("tile record", "kind 0 to 2, at most 24 bits, reserved bits 0"));
    }
    if bits != 0 && kind != KIND_SAMPLED || kind == KIND_EMPTY && head != 0 {
        return Err(bad("tile record", "bits only in a sampled tile, nothing else in an empty one"));
    }
    let body = match kind {
        KIND_PLANE => 3,
        KIND_SAMPLED => 4 + 2 * bits,
        _ => 0,
    };
    let masks = 2 * ((head & HAS_CONTACT != 0) as u32 + (head & HAS_EDGE != 0) as u32);
    if r as u64 + 1 + body as u64 + masks as u64 > w as u64 {
        return Err(bad("tile record", "inside the pool"));
    }
    let contact = |l: u32| head & HAS_CONTACT == 0 || mask_bit(t.pool, r + 1 + body, l);
    if head & HAS_CONTACT != 0 && (0..64).all(|l| !contact(l)) {
        return Err(bad("contact mask", "at least one node (an empty tile otherwise)"));
    }
    if head & HAS_EDGE != 0 {
        let at = r + 1 + body + if head & HAS_CONTACT != 0 { 2 } else { 0 };
        if (0..64).any(|l| mask_bit(t.pool, at, l) && !contact(l)) || (0..64).all(|l| !mask_bit(t.pool, at, l)) {
            return Err(bad("edge mask", "contact nodes only, at least one"));
        }
    }
    match kind {
        KIND_PLANE => {
            let f = |k| f32::from_bits(word(t.pool, r + k));
            in_range(f(1), -1e9, 1e9, tag, index, "plane height", "finite, within 1e9 mm")?;
            let cap = cap * (1.0 + 1e-6);
            in_range(f(2), -cap, cap, tag, index, "plane gradient x", "within the gradient cap")?;
            in_range(f(3), -cap, cap, tag, index, "plane gradient y", "within the gradient cap")?;
        }
        KIND_SAMPLED => {
            let m = word(t.pool, r + 2);
            if !(1..=MAX_CODE).contains(&m) {
                return Err(bad("sampled tile", "a multiplier from 1 to 2^24 - 1"));
            }
            for l in 0..64 {
                if !contact(l) && residual(t.pool, r + 5, l, bits) != 0 {
                    return Err(bad("sampled tile", "residual 0 at nodes without contact"));
                }
            }
        }
        _ => {}
    }
    Ok(())
}
