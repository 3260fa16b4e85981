//! The writer of tiled height fields (SPEC.md section 9.1, "The writer"):
//! tiles to records, records and tile lists stored once, the index packed.

use alloc::collections::BTreeMap;
use alloc::vec::Vec;

use super::{
    HAS_CONTACT, HAS_EDGE, KIND_CODED, KIND_EMPTY, KIND_PLANE, MAX_CODE, SLOPED, SUPER, TILE, coded, index_widths,
};
use crate::bytes::Out;
use crate::height::{FIELD_CONTACT, FIELD_EDGE, HeightField};

/// A tiled field's tables: the packed superblock entries and tile lists,
/// the number of lists, and the pool of records.
pub(crate) struct Tables {
    pub supers: Vec<u32>,
    pub lists: Vec<u32>,
    pub list_count: u32,
    pub pool: Vec<u32>,
}

/// Words stored once: a record or a list is written the first time it
/// comes, and named by its number (or offset) after that.
struct Once {
    words: Vec<u32>,
    seen: BTreeMap<Vec<u32>, u32>,
    count: u32,
}

impl Once {
    fn new() -> Self {
        Once { words: Vec::new(), seen: BTreeMap::new(), count: 0 }
    }

    /// The word offset of `rec`, stored now if it is new.
    fn offset(&mut self, rec: Vec<u32>) -> u32 {
        if let Some(&at) = self.seen.get(&rec) {
            return at;
        }
        let at = self.words.len() as u32;
        self.words.extend_from_slice(&rec);
        self.seen.insert(rec, at);
        at
    }

    /// The number of `rec` in the order of first appearance, stored now if it is new.
    fn number(&mut self, rec: Vec<u32>) -> u32 {
        if let Some(&n) = self.seen.get(&rec) {
            return n;
        }
        let n = self.count;
        self.count += 1;
        self.words.extend_from_slice(&rec);
        self.seen.insert(rec, n);
        n
    }
}

/// One node of a tile being written.
#[derive(Clone, Copy)]
struct Node {
    /// Index in the tile, row-major.
    l: u32,
    /// Field column and row.
    i: u32,
    j: u32,
    height: f32,
    flags: u8,
}

impl Node {
    fn touches(&self) -> bool {
        self.flags & FIELD_CONTACT != 0
    }
}

/// The nodes of tile `(tx, ty)` inside the field.
fn tile_nodes(f: &HeightField, tx: u32, ty: u32) -> Vec<Node> {
    let mut v = Vec::with_capacity(64);
    for l in 0..TILE * TILE {
        let (i, j) = (tx * TILE + l % TILE, ty * TILE + l / TILE);
        if i < f.cols && j < f.rows {
            let k = (j * f.cols + i) as usize;
            let flags = f.flags.get(k).copied().unwrap_or(0);
            v.push(Node { l, i, j, height: f.heights.get(k).copied().unwrap_or(0.0), flags });
        }
    }
    v
}

/// The planes a tile's own contact nodes suggest, coarsest first: their
/// least-squares plane with the gradient on the lattices 2^-4, 2^-6, ...
/// 2^-24 and the height at the field's origin on multiples of the step, so
/// every tile of one plane of the model (an incline of 1 in 8, a level
/// terrace) finds the same numbers from its own nodes and its record is
/// stored once. A level plane is also tried at the height the least
/// squares give (a level tile's own height, shared by every tile of its
/// terrace; a sloped plane's would differ from tile to tile). Adding 0
/// turns -0 into +0, so a level plane is always written level.
fn own_planes(f: &HeightField, step: f32, nodes: &[Node]) -> Vec<[f32; 3]> {
    let c: Vec<_> = nodes.iter().filter(|n| n.touches()).collect();
    let mut out = Vec::new();
    let Some(first) = c.first() else { return out };
    let cell = f.cell.0 as f64;
    // Least squares h = a + b x + c y about the nodes' mean, x and y in
    // nodes from the first contact node (small integers, so nodes in one
    // row or column are exactly that: their other spread is exactly 0, and
    // they give a line, not a slope across them made of rounding noise).
    let k = c.len() as f64;
    let at = |n: &Node| ((n.i as f64 - first.i as f64), (n.j as f64 - first.j as f64));
    let (sx, sy, sh) = c.iter().fold((0.0, 0.0, 0.0), |s, n| (s.0 + at(n).0, s.1 + at(n).1, s.2 + n.height as f64));
    let (mx, my, mh) = (sx / k, sy / k, sh / k);
    let (mut sxx, mut sxy, mut syy, mut sxh, mut syh) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for n in &c {
        let (x, y) = at(n);
        let (x, y, h) = (x - mx, y - my, n.height as f64 - mh);
        sxx += x * x;
        sxy += x * y;
        syy += y * y;
        sxh += x * h;
        syh += y * h;
    }
    let det = sxx * syy - sxy * sxy;
    // Slopes in height a node, then a millimetre.
    let (gx, gy) = if sxx > 0.0 && syy > 0.0 && det > 1e-9 * sxx * syy {
        ((sxh * syy - syh * sxy) / det, (syh * sxx - sxh * sxy) / det)
    } else if sxx > 0.0 && syy == 0.0 {
        (sxh / sxx, 0.0)
    } else if syy > 0.0 && sxx == 0.0 {
        (0.0, syh / syy)
    } else if sxx == 0.0 && syy == 0.0 {
        (0.0, 0.0)
    } else {
        // Nodes on a slanted line (a diagonal of a tile): no plane of their own.
        return out;
    };
    let (gx, gy) = (gx / cell, gy / cell);
    // The mean node's place in mm from the field's origin.
    let (mx, my) = ((first.i as f64 + mx) * cell, (first.j as f64 + my) * cell);
    let cap = f.gradient_cap * (1.0 + 1e-6);
    for k in (4..=24).step_by(2) {
        let unit = (1u32 << k) as f64;
        let (gx, gy) = ((libm::round(gx * unit) / unit) as f32 + 0.0, (libm::round(gy * unit) / unit) as f32 + 0.0);
        let h0 = mh - gx as f64 * mx - gy as f64 * my;
        let rounded = (libm::round(h0 / step as f64) * step as f64) as f32 + 0.0;
        let level = gx == 0.0 && gy == 0.0;
        for h0 in [rounded, h0 as f32 + 0.0].into_iter().take(1 + level as usize) {
            if [h0, gx, gy].iter().all(|v| v.is_finite()) && gx.abs() <= cap && gy.abs() <= cap && h0.abs() <= 1e9 {
                out.push([h0, gx, gy]);
            }
        }
    }
    out
}

/// The height of plane `p` at node `n`, as a player computes it.
fn plane_height(f: &HeightField, p: [f32; 3], n: &Node) -> f32 {
    if p[1] == 0.0 && p[2] == 0.0 {
        p[0]
    } else {
        p[0] + p[1] * (n.i as f32 * f.cell.0) + p[2] * (n.j as f32 * f.cell.0)
    }
}

/// Whether plane `p` gives every contact node its height exactly.
fn exact(f: &HeightField, nodes: &[Node], p: [f32; 3]) -> bool {
    nodes.iter().filter(|n| n.touches()).all(|n| plane_height(f, p, n).to_bits() == n.height.to_bits())
}

/// Whether every contact node lies within half a step of plane `p`, as a
/// player computes the plane's heights.
fn fits(f: &HeightField, step: f32, nodes: &[Node], p: [f32; 3]) -> bool {
    let half = step as f64 / 2.0;
    nodes.iter().filter(|n| n.touches()).all(|n| (plane_height(f, p, n) as f64 - n.height as f64).abs() <= half)
}

/// The code of height `h`, rounded (`libm`'s rounding: `no_std` has no
/// `f64::round`).
fn code_of(h: f32, step: f32, base: f32) -> f64 {
    libm::round((h as f64 - base as f64) / step as f64)
}

/// The record of one tile, and its plane when it is a plane tile. A tile
/// first tries the planes of its neighbours to the left and above (`near`),
/// so one plane of the model is one record however far it reaches.
///
/// The choice is made so that writing the field again from the heights a
/// reader gets back gives the same record (the owned model of a read
/// bundle holds those heights, and `taxel pack` of `taxel unpack` must
/// give the same bytes): first a plane, of the neighbours' and then the
/// tile's own, that gives every node its height exactly (a plane tile read
/// back); else a coded tile when every height is exactly a code (a coded
/// tile read back); else a plane within half a step of every height, of
/// the neighbours' first, then the tile's own or one its codes suggest (a
/// plane that gives the rounded heights exactly, which the tile read back
/// would find, is tried on the heights first), an own plane written as the
/// first of the planes its own heights suggest that gives them exactly (the
/// one the tile read back finds; one that none gives exactly is passed
/// over); else a coded tile.
fn record(
    f: &HeightField,
    step: f32,
    base: f32,
    (tx, ty): (u32, u32),
    near: [Option<[f32; 3]>; 2],
) -> Result<(Vec<u32>, Option<[f32; 3]>), &'static str> {
    let nodes = tile_nodes(f, tx, ty);
    if nodes.iter().all(|n| !n.touches()) {
        return Ok((alloc::vec![KIND_EMPTY], None));
    }
    // Nodes past the field's edge are never read: they count as touching,
    // so an edge tile needs no mask for them and matches the tiles inside.
    let mut contact = u64::MAX;
    let mut edge = 0u64;
    let mut keep = 0u64;
    for n in &nodes {
        if !n.touches() {
            contact &= !(1 << n.l);
        } else {
            keep |= 1 << n.l;
            if n.flags & FIELD_EDGE != 0 {
                edge |= 1 << n.l;
            }
        }
    }
    let mut masks = Vec::new();
    let mut flags = 0;
    if contact != u64::MAX {
        flags |= HAS_CONTACT;
        masks.extend_from_slice(&[contact as u32, (contact >> 32) as u32]);
    }
    if edge != 0 {
        flags |= HAS_EDGE;
        masks.extend_from_slice(&[edge as u32, (edge >> 32) as u32]);
    }
    let near = near.into_iter().flatten();
    let is_code = |n: &Node| {
        let c = code_of(n.height, step, base);
        (0.0..=MAX_CODE as f64).contains(&c) && (base + c as f32 * step).to_bits() == n.height.to_bits()
    };
    let own = own_planes(f, step, &nodes);
    let plane = near.clone().chain(own.iter().copied()).find(|&p| exact(f, &nodes, p)).or_else(|| {
        if nodes.iter().filter(|n| n.touches()).all(is_code) {
            return None;
        }
        if let Some(p) = near.clone().find(|&p| fits(f, step, &nodes, p)) {
            return Some(p);
        }
        let quantised: Vec<Node> =
            nodes.iter().map(|n| Node { height: base + code_of(n.height, step, base) as f32 * step, ..*n }).collect();
        own.into_iter().chain(own_planes(f, step, &quantised)).filter(|&p| fits(f, step, &nodes, p)).find_map(|p| {
            // The tile as a reader gets it back, and the plane it finds there.
            let back: Vec<Node> = nodes.iter().map(|n| Node { height: plane_height(f, p, n), ..*n }).collect();
            own_planes(f, step, &back).into_iter().find(|&q| exact(f, &back, q))
        })
    });
    if let Some([h0, gx, gy]) = plane {
        let mut r = if gx == 0.0 && gy == 0.0 {
            alloc::vec![KIND_PLANE | flags, h0.to_bits()]
        } else {
            alloc::vec![KIND_PLANE | flags | SLOPED, h0.to_bits(), gx.to_bits(), gy.to_bits()]
        };
        r.extend_from_slice(&masks);
        return Ok((r, plane));
    }
    let mut codes = [0u32; 64];
    for n in nodes.iter().filter(|n| n.touches()) {
        let c = code_of(n.height, step, base);
        if !(0.0..=MAX_CODE as f64).contains(&c) {
            return Err("heights within 2^24 - 1 steps of the lowest");
        }
        codes[n.l as usize] = c as u32;
    }
    let (first, stream) = coded::encode(&codes, keep);
    let mut r = alloc::vec![KIND_CODED | flags | first << 8];
    r.extend_from_slice(&masks);
    r.extend_from_slice(&stream);
    Ok((r, None))
}

/// Packs `values` in `w` bits each, low bits first, into words.
fn pack(values: &[u32], w: u32) -> Vec<u32> {
    let mut out = alloc::vec![0u32; super::packed_words(values.len() as u64, w) as usize];
    for (n, &v) in values.iter().enumerate() {
        let p = n as u64 * w as u64;
        let (at, shift) = ((p / 32) as usize, p % 32);
        let wide = (v as u64) << shift;
        out[at] |= wide as u32;
        if let Some(next) = out.get_mut(at + 1) {
            *next |= (wide >> 32) as u32;
        }
    }
    out
}

/// The tables of field `f` in the tiled encoding with height step `step`
/// and base `base`.
pub(crate) fn encode_tiles(f: &HeightField, step: f32, base: f32) -> Result<Tables, &'static str> {
    let (tcols, trows) = (f.cols.div_ceil(TILE), f.rows.div_ceil(TILE));
    let (scols, srows) = (tcols.div_ceil(SUPER), trows.div_ceil(SUPER));
    let mut pool = Once::new();
    let mut of_tile = Vec::with_capacity((tcols * trows) as usize);
    let mut planes: Vec<Option<[f32; 3]>> = Vec::with_capacity((tcols * trows) as usize);
    for ty in 0..trows {
        for tx in 0..tcols {
            let left = if tx > 0 { planes.last().copied().flatten() } else { None };
            let above = if ty > 0 { planes.get(((ty - 1) * tcols + tx) as usize).copied().flatten() } else { None };
            let (rec, plane) = record(f, step, base, (tx, ty), [left, above])?;
            of_tile.push(pool.offset(rec));
            planes.push(plane);
        }
    }
    if pool.words.len() > 1 << 30 {
        return Err("at most 2^30 words of tiles");
    }
    let mut lists = Once::new();
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
            supers.push(if list.iter().all(|&e| e == first) { first << 1 | 1 } else { lists.number(list) << 1 });
        }
    }
    let widths = index_widths(lists.count, pool.words.len() as u32);
    Ok(Tables {
        supers: pack(&supers, widths.0),
        lists: pack(&lists.words, widths.1),
        list_count: lists.count,
        pool: pool.words,
    })
}

/// Writes the header's tiled part and the tables after the common header.
pub(crate) fn write_tables(w: &mut Out<'_>, step: f32, base: f32, t: &Tables) {
    w.f32(step).f32(base).u32(t.list_count).u32(t.pool.len() as u32);
    for &v in t.supers.iter().chain(&t.lists).chain(&t.pool) {
        w.u32(v);
    }
}
