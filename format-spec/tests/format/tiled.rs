//! Tiled height fields (format 4.6, SPEC.md section 9.1): every node read
//! from the bytes by the specification's rules alone, bit for bit as the
//! crate reads it, the round trip through the owned model, random fields,
//! and every check of the reader.

use proptest::prelude::*;
use taxel_format::{
    Bundle, BundleView, Chunk, ChunkView, FIELD_CONTACT, FIELD_EDGE, FormatError, HeightEncoding, HeightField,
    Manifest, Mm, Tag, profiles,
};

use crate::craft::{craft_version, decompose, find, put_f32, put_u32};

/// A 70 x 45 field (two superblock columns, edge tiles reaching past the
/// field): a level terrace, an incline, a bowl, a hole and a step.
fn field() -> HeightField {
    let (cols, rows) = (70u32, 45u32);
    let n = (cols * rows) as usize;
    let mut f = HeightField {
        source: Some(0),
        cols,
        rows,
        origin_x: Mm(3.0),
        origin_y: Mm(-2.0),
        cell: Mm(0.5),
        gradient_cap: 4.0,
        heights: vec![0.0; n],
        grad_x: vec![0.0; n],
        grad_y: vec![0.0; n],
        flags: vec![0; n],
        encoding: HeightEncoding::Tiled { step: 0.002, base: 1.0, max_gradient: 1.5 },
    };
    for j in 0..rows {
        for i in 0..cols {
            let k = (j * cols + i) as usize;
            let (x, y) = (i as f64 * 0.5, j as f64 * 0.5);
            if (x - 20.0).hypot(y - 12.0) < 3.0 {
                continue;
            }
            let h = if x < 10.0 {
                1.0
            } else if x < 25.0 {
                1.0 + 0.125 * (x - 10.0)
            } else {
                3.0 + 0.01 * ((x - 28.0).powi(2) + (y - 11.0).powi(2))
            };
            f.heights[k] = h as f32 + if i >= 60 { 1.5 } else { 0.0 };
            f.flags[k] = FIELD_CONTACT | if i == 59 || i == 60 { FIELD_EDGE } else { 0 };
        }
    }
    f
}

fn bytes_of(f: &HeightField) -> Vec<u8> {
    let mut b = Bundle::new(Manifest::new(profiles::builtin("finger3").unwrap()));
    b.chunks.push(Chunk::Height(f.clone()));
    b.to_bytes().unwrap()
}

fn view_of(bytes: &[u8]) -> taxel_format::HeightFieldView<'_> {
    let v = BundleView::parse(bytes).unwrap();
    v.chunks().find_map(|c| if let ChunkView::Height(h) = c { Some(h) } else { None }).unwrap()
}

/// A field chunk read as section 9.1 says, without the crate.
struct Spec<'a> {
    d: &'a [u8],
}

impl Spec<'_> {
    fn word(&self, o: usize) -> u32 {
        u32::from_le_bytes(self.d[o..o + 4].try_into().unwrap())
    }

    /// Entry `n` of `w` bits of the packed table at byte `at`, bit by bit.
    fn entry(&self, at: usize, n: usize, w: usize) -> u32 {
        (0..w).map(|k| (self.word(at + 4 * ((n * w + k) / 32)) >> ((n * w + k) % 32) & 1) << k).sum()
    }

    fn bits(n: u64) -> usize {
        (64 - n.leading_zeros()) as usize
    }

    /// Node `(i, j)`'s height, or `None` without contact.
    fn node(&self, i: u32, j: u32) -> Option<f32> {
        let f = |o: usize| f32::from_bits(self.word(o));
        let (cols, rows, cell, step, base) = (self.word(4), self.word(8), f(24), f(48), f(52));
        let (l_count, w_count) = (self.word(56) as u64, self.word(60) as u64);
        let sc = cols.div_ceil(8).div_ceil(4) as usize;
        let s = sc * rows.div_ceil(8).div_ceil(4) as usize;
        let wr = Self::bits(w_count - 1).max(1);
        let ws = 1 + wr.max(Self::bits(l_count.saturating_sub(1)));
        let lists = 64 + 4 * (s * ws).div_ceil(32);
        let pool = lists + 4 * (16 * l_count as usize * wr).div_ceil(32);
        let (tx, ty) = ((i / 8) as usize, (j / 8) as usize);
        let e = self.entry(64, (ty / 4) * sc + tx / 4, ws);
        let r = if e & 1 == 1 { e >> 1 } else { self.entry(lists, (e >> 1) as usize * 16 + (ty % 4) * 4 + tx % 4, wr) };
        let at = |k: u32| pool + 4 * (r + k) as usize;
        let head = self.word(at(0));
        let (a, b) = ((i % 8) as usize, (j % 8) as usize);
        let l = 8 * b + a;
        let body = match head & 3 {
            0 => return None,
            1 if head & 16 != 0 => 3,
            1 => 1,
            _ => 0,
        };
        let mut next = 1 + body;
        let mut mask = || {
            let m = self.word(at(next)) as u64 | (self.word(at(next + 1)) as u64) << 32;
            next += 2;
            m
        };
        if head & 4 != 0 && mask() >> l & 1 == 0 {
            return None;
        }
        if head & 8 != 0 {
            mask();
        }
        if head & 3 == 1 {
            let h0 = f(at(1));
            if head & 16 == 0 {
                return Some(h0);
            }
            return Some(h0 + f(at(2)) * (i as f32 * cell) + f(at(3)) * (j as f32 * cell));
        }
        // The residual stream: three widths, then the slopes (nodes 1 and 8),
        // the first row and column, and the inside.
        let stream = at(next);
        let width = |g: usize| self.entry(stream, g, 6) as usize;
        let (w0, w1, w2) = (width(0), width(1), width(2));
        let read = |start: usize, n: usize, w: usize| -> i32 {
            let v = (0..w)
                .map(|k| (self.word(stream + 4 * ((start + n * w + k) / 32)) >> ((start + n * w + k) % 32) & 1) << k);
            (v.sum::<u32>() as i64 - if w == 0 { 0 } else { 1i64 << (w - 1) }) as i32
        };
        let (p1, p2) = (18 + 2 * w0, 18 + 2 * w0 + 12 * w1);
        let residual = |a: usize, b: usize| match (a, b) {
            (1, 0) => read(18, 0, w0),
            (0, 1) => read(18, 1, w0),
            (a, 0) => read(p1, a - 2, w1),
            (0, b) => read(p1, 6 + b - 2, w1),
            (a, b) => read(p2, (b - 1) * 7 + a - 1, w2),
        };
        let mut c = [[0i32; 8]; 8];
        for bb in 0..8 {
            for aa in 0..8 {
                c[bb][aa] = match (aa, bb) {
                    (0, 0) => (head >> 8) as i32,
                    (1, 0) | (0, 1) => c[0][0].wrapping_add(residual(aa, bb)),
                    (aa, 0) => c[0][aa - 1].wrapping_mul(2).wrapping_sub(c[0][aa - 2]).wrapping_add(residual(aa, 0)),
                    (0, bb) => c[bb - 1][0].wrapping_mul(2).wrapping_sub(c[bb - 2][0]).wrapping_add(residual(0, bb)),
                    (aa, bb) => c[bb][aa - 1]
                        .wrapping_add(c[bb - 1][aa])
                        .wrapping_sub(c[bb - 1][aa - 1])
                        .wrapping_add(residual(aa, bb)),
                };
            }
        }
        Some(base + c[b][a] as f32 * step)
    }
}

/// Every node of `f` stored in `bytes`: within half a step of its height
/// (plus `f32` rounding), read bit for bit alike by the specification and
/// the crate, and back through the owned model byte for byte.
fn check_every_node(f: &HeightField, bytes: &[u8]) -> Result<(), TestCaseError> {
    let HeightEncoding::Tiled { step, .. } = f.encoding else { unreachable!() };
    let chunks = decompose(bytes);
    let d = &chunks[find(&chunks, b"HFLD")].data;
    prop_assert_eq!(u32::from_le_bytes(d[12..16].try_into().unwrap()), 2, "encoding 2");
    let spec = Spec { d };
    let view = view_of(bytes);
    prop_assert!(view.is_tiled());
    let tol = step / 2.0 + 4.0 * f32::EPSILON * f.heights.iter().fold(1.0f32, |m, h| m.max(h.abs()));
    for j in 0..f.rows {
        for i in 0..f.cols {
            let k = (j * f.cols + i) as usize;
            let h = spec.node(i, j);
            prop_assert_eq!(h.is_some(), f.flags[k] & FIELD_CONTACT != 0, "contact of ({}, {})", i, j);
            prop_assert_eq!(view.flags_at(k as u32), f.flags[k], "flags of ({}, {})", i, j);
            if let Some(h) = h {
                prop_assert!((h - f.heights[k]).abs() <= tol, "({}, {}): {} vs {}", i, j, h, f.heights[k]);
                prop_assert_eq!(
                    view.height_at(k as u32).to_bits(),
                    h.to_bits(),
                    "({}, {}) as the crate reads it",
                    i,
                    j
                );
            }
        }
    }
    let back = Bundle::from_view(&BundleView::parse(bytes).unwrap());
    prop_assert_eq!(back.to_bytes().unwrap(), bytes.to_vec());
    Ok(())
}

#[test]
fn a_tiled_field_stores_every_height_within_half_a_step_and_reads_back_byte_for_byte() {
    let f = field();
    let bytes = bytes_of(&f);
    assert_eq!(BundleView::parse(&bytes).unwrap().version(), (4, 6));
    check_every_node(&f, &bytes).unwrap();
    // A 4.0 field of these nodes is 13 bytes a node; the tiled one a small fraction of it.
    let chunks = decompose(&bytes);
    let d = &chunks[find(&chunks, b"HFLD")].data;
    assert!(d.len() * 10 < 13 * 70 * 45, "{} bytes", d.len());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Random fields: a tilted bumpy surface (its bending and noise from
    /// nothing to far more than a step), a level terrace (at any height, or exactly
    /// at a code), holes, steps, any size, the codes from 0 or from the
    /// lowest height; the specification and the crate read every node
    /// alike, within half a step, and the field read back writes the same
    /// bytes.
    #[test]
    fn random_tiled_fields_read_alike_by_the_spec_and_the_crate(
        cols in 2u32..90, rows in 2u32..75, bump in 0.0f64..40.0, noise in 0.0f64..0.05,
        hole in proptest::option::of((0.0f64..45.0, 0.0f64..37.0, 0.5f64..8.0)),
        step_at in proptest::option::of(1u32..89), seed in any::<u64>(),
        terrace in proptest::option::of((1u32..90, 0.0f64..5.0, any::<bool>())), zero_base in any::<bool>(),
        tilt in (-0.3f64..0.3, -0.3f64..0.3), cell in 0.05f32..2.0,
    ) {
        let mut rng = seed;
        let mut next = || { rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407); (rng >> 33) as f64 / (1u64 << 31) as f64 };
        let n = (cols * rows) as usize;
        let mut f = HeightField {
            source: None, cols, rows, origin_x: Mm(0.0), origin_y: Mm(0.0), cell: Mm(cell), gradient_cap: 50.0,
            heights: vec![0.0; n], grad_x: vec![0.0; n], grad_y: vec![0.0; n], flags: vec![0; n],
            encoding: HeightEncoding::Tiled { step: 0.001, base: 0.0, max_gradient: 1.0 },
        };
        for j in 0..rows {
            for i in 0..cols {
                let (x, y) = (i as f64 * 0.5, j as f64 * 0.5);
                if hole.is_some_and(|(hx, hy, r)| (x - hx).hypot(y - hy) < r) {
                    continue;
                }
                let k = (j * cols + i) as usize;
                let up = step_at.is_some_and(|s| i >= s);
                let surface = (x * 0.3).sin() * (y * 0.2).cos() * bump / 10.0 + tilt.0 * x + tilt.1 * y;
                f.heights[k] = (40.0 + surface + noise * next() + if up { 3.0 } else { 0.0 }) as f32;
                if let Some((width, level, on_code)) = terrace.filter(|t| i < t.0) {
                    // A code of step 0.001 from 0, as the reader computes it.
                    f.heights[k] = if on_code { 0.0 + (level * 1000.0).round() as f32 * 0.001 } else { level as f32 };
                    let _ = width;
                }
                f.flags[k] = FIELD_CONTACT | if step_at.is_some_and(|s| i + 1 == s || i == s) { FIELD_EDGE } else { 0 };
            }
        }
        let lowest = f.heights.iter().zip(&f.flags).filter(|(_, fl)| **fl != 0).map(|(h, _)| *h).fold(f32::INFINITY, f32::min);
        let base = if zero_base || !lowest.is_finite() { 0.0 } else { lowest };
        f.encoding = HeightEncoding::Tiled { step: 0.001, base, max_gradient: 1.0 };
        let mut b = Bundle::new(Manifest::new(profiles::builtin("finger3").unwrap()));
        b.chunks.push(Chunk::Height(f.clone()));
        let bytes = b.to_bytes().unwrap();
        check_every_node(&f, &bytes)?;
    }
}

/// The field's chunk edited by `edit`, in a 4.6 bundle with re-sealed checksums.
fn edited(edit: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
    edited_with(&field(), edit)
}

fn refused(bytes: Vec<u8>, field: &str) {
    match BundleView::parse(&bytes) {
        Err(FormatError::InvalidValue { tag, field: f, .. }) if tag == Tag::HEIGHT && f == field => {}
        other => panic!("expected `{field}` to be refused, got {other:?}"),
    }
}

/// The layout of a field chunk's tables: `(ws, wr, L, W)` and the byte
/// offsets of the list table and the pool.
fn layout(d: &[u8]) -> (usize, usize, u64, u64, usize, usize) {
    let w = |o: usize| u32::from_le_bytes(d[o..o + 4].try_into().unwrap());
    let (l_count, w_count) = (w(56) as u64, w(60) as u64);
    let bits = |n: u64| (64 - n.leading_zeros()) as usize;
    let s = (w(4).div_ceil(8).div_ceil(4) * w(8).div_ceil(8).div_ceil(4)) as usize;
    let wr = bits(w_count - 1).max(1);
    let ws = 1 + wr.max(bits(l_count.saturating_sub(1)));
    let lists = 64 + 4 * (s * ws).div_ceil(32);
    (ws, wr, l_count, w_count, lists, lists + 4 * (16 * l_count as usize * wr).div_ceil(32))
}

/// The records of a field chunk, as byte offsets with their header word,
/// walked back to back from the pool's start (the writer stores them so,
/// then the lists).
fn records(d: &[u8]) -> Vec<(usize, u32)> {
    let w = |o: usize| u32::from_le_bytes(d[o..o + 4].try_into().unwrap());
    let (.., pool) = layout(d);
    let mut out = Vec::new();
    let mut at = pool;
    while at < d.len() {
        let head = w(at);
        let kind = head & 3;
        if kind == 3 || head & 0xe0 != 0 || kind != 2 && head >> 8 != 0 {
            break;
        }
        out.push((at, head));
        let masks = 2 * ((head >> 2 & 1) + (head >> 3 & 1)) as usize;
        at += 4 * match kind {
            0 => 1,
            1 => 2 + 2 * (head >> 4 & 1) as usize + masks,
            _ => {
                let ws = w(at + 4 * (1 + masks));
                let g = |k: u32| (ws >> (6 * k) & 63) as usize;
                1 + masks + (18 + 2 * g(0) + 12 * g(1) + 49 * g(2)).div_ceil(32)
            }
        };
    }
    out
}

/// Sets entry `n` of `w` bits of the packed table at byte `at` to `v`.
fn put_entry(d: &mut [u8], at: usize, n: usize, w: usize, v: u32) {
    for k in 0..w {
        let bit = n * w + k;
        let byte = at + bit / 8;
        d[byte] = d[byte] & !(1 << (bit % 8)) | ((v >> k & 1) as u8) << (bit % 8);
    }
}

#[test]
fn every_check_of_the_tiled_reader_is_reached() {
    let d = {
        let chunks = decompose(&bytes_of(&field()));
        chunks[find(&chunks, b"HFLD")].data.clone()
    };
    let recs = records(&d);
    let first = |kind: u32, flags: u32| recs.iter().find(|(_, h)| h & 3 == kind && h & flags == flags).copied();
    let (plane, _) = first(1, 0).expect("a plane tile");
    let (coded, head) = first(2, 0).expect("a coded tile");
    refused(edited(|d| put_f32(d, 48, 0.0)), "height step");
    refused(edited(|d| put_f32(d, 52, f32::NAN)), "height base");
    refused(edited(|d| put_u32(d, 56, 7)), "tile lists");
    refused(edited(|d| put_u32(d, 60, 0)), "pool");
    refused(edited(|d| put_f32(d, 28, -7.0)), "extremes");
    refused(edited(|d| put_f32(d, 36, 5.0)), "max gradient");
    // The index: bits past the superblock table's six entries; a list past
    // the last one, or a record past the pool's end.
    let (ws, wr, l_count, w_count, lists, _) = layout(&d);
    let used = 6 * ws;
    assert!(used % 32 != 0, "the superblock table ends inside a word");
    refused(edited(|d| d[64 + 4 * (used / 32) + 3] |= 0x80), "index");
    if (1u64 << (ws - 1)) > l_count {
        refused(edited(|d| put_entry(d, 64, 0, ws, (l_count as u32) << 1)), "superblock");
    }
    if (1u64 << wr) > w_count {
        let past = ((1u64 << wr) - 1) as u32;
        refused(edited(|d| put_entry(d, 64, 0, ws, past << 1 | 1)), "tile record");
        if l_count > 0 {
            refused(edited(|d| put_entry(d, lists, 0, wr, past)), "tile record");
        }
    }
    // A record's header: kind 3, reserved bits, a code in a plane's header.
    for h in [3u32, 1 << 5 | 1, 1 << 8 | 1] {
        refused(edited(|d| put_u32(d, plane, h)), "tile record");
    }
    // A plane written with slopes that are both 0.
    if let Some((sloped, _)) = first(1, 16) {
        refused(
            edited(|d| {
                put_f32(d, sloped + 8, 0.0);
                put_f32(d, sloped + 12, 0.0);
            }),
            "plane tile",
        );
    }
    // Masks: a contact mask of every node or of none; an edge mask of none.
    let (masked, _) = first(0, 4).into_iter().chain(first(1, 4)).chain(first(2, 4)).next().expect("a contact mask");
    let contact_at = masked + 4 * mask_at(&d, masked);
    for m in [u32::MAX, 0] {
        refused(
            edited(|d| {
                put_u32(d, contact_at, m);
                put_u32(d, contact_at + 4, m);
            }),
            "contact mask",
        );
    }
    let (edged, edge_head) = recs.iter().find(|(_, h)| h & 8 != 0).copied().expect("an edge mask");
    let edge_at = edged + 4 * (mask_at(&d, edged) + 2 * (edge_head >> 2 & 1) as usize);
    refused(
        edited(|d| {
            put_u32(d, edge_at, 0);
            put_u32(d, edge_at + 4, 0);
        }),
        "edge mask",
    );
    // A coded tile: a width above 32, and bits after the last residual.
    let stream = coded + 4 * (mask_at(&d, coded) + 2 * ((head >> 2 & 1) + (head >> 3 & 1)) as usize);
    let widths = u32::from_le_bytes(d[stream..stream + 4].try_into().unwrap());
    refused(edited(|d| put_u32(d, stream, widths & !63 | 33)), "coded tile");
    let g = |k: u32| (widths >> (6 * k) & 63) as usize;
    let used = 18 + 2 * g(0) + 12 * g(1) + 49 * g(2);
    assert!(used % 32 != 0 || g(2) > 0, "a stream with spare bits or residuals to set");
    if used % 32 != 0 {
        let last = stream + 4 * (used / 32);
        refused(edited(|d| d[last + 3] |= 0x80), "coded tile");
    }
    // A length that disagrees with L and W.
    match BundleView::parse(&edited(|d| d.extend_from_slice(&[0; 4]))) {
        Err(FormatError::ChunkLength { tag, .. }) if tag == Tag::HEIGHT => {}
        other => panic!("expected a length error, got {other:?}"),
    }
    // 4.5's encoding 1 is refused with its own message, never misread.
    refused(edited(|d| put_u32(d, 12, 1)), "encoding");
    // A 4.0 field whose encoding word says tiled is refused, never misread.
    let float = HeightField { encoding: HeightEncoding::Float, ..field() };
    let mut chunks = decompose(&bytes_of(&float));
    let i = find(&chunks, b"HFLD");
    put_u32(&mut chunks[i].data, 12, 2);
    assert!(BundleView::parse(&craft_version(&chunks, 4, 6)).is_err());
}

/// The word of record `at` where its masks start.
fn mask_at(d: &[u8], at: usize) -> usize {
    let head = u32::from_le_bytes(d[at..at + 4].try_into().unwrap());
    match head & 3 {
        1 => 2 + 2 * (head >> 4 & 1) as usize,
        _ => 1,
    }
}

#[test]
fn nodes_without_contact_have_residual_0_and_node_0_takes_the_first_touching_code() {
    // Coded tiles with a hole in them: bowls with a hole and a step.
    let mut f = field();
    for j in 0..f.rows {
        for i in 0..f.cols {
            let k = (j * f.cols + i) as usize;
            let (x, y) = (i as f64 * 0.5, j as f64 * 0.5);
            if (x - 30.5).hypot(y - 4.3) < 2.2 || (x - 28.0).hypot(y - 16.0) < 1.2 {
                (f.heights[k], f.flags[k]) = (0.0, 0);
            }
        }
    }
    let bytes = bytes_of(&f);
    check_every_node(&f, &bytes).unwrap();
    let chunks = decompose(&bytes);
    let d = chunks[find(&chunks, b"HFLD")].data.clone();
    let w = |o: usize| u32::from_le_bytes(d[o..o + 4].try_into().unwrap());
    let holed: Vec<(usize, u32)> = records(&d).into_iter().filter(|(_, h)| h & 3 == 2 && h & 4 != 0).collect();
    assert!(!holed.is_empty(), "coded tiles with a contact mask");
    let mut flipped = 0;
    for &(at, head) in &holed {
        let contact = w(at + 4) as u64 | (w(at + 8) as u64) << 32;
        let stream = at + 4 * (1 + 2 * ((head >> 2 & 1) + (head >> 3 & 1)) as usize);
        let ws = w(stream);
        let g = |k: u32| (ws >> (6 * k) & 63) as usize;
        // The bit of node `l`'s residual that holds the lowest bit of its
        // offset binary (`None` when its width is 0).
        let bit_of = |l: usize| {
            let (start, n, width) = match (l % 8, l / 8) {
                (1, 0) => (18, 0, g(0)),
                (0, 1) => (18, 1, g(0)),
                (a, 0) => (18 + 2 * g(0), a - 2, g(1)),
                (0, b) => (18 + 2 * g(0), 6 + b - 2, g(1)),
                (a, b) => (18 + 2 * g(0) + 12 * g(1), (b - 1) * 7 + a - 1, g(2)),
            };
            (width > 0).then_some(start + n * width)
        };
        // A residual of a node without contact, set to something other than 0.
        if let Some(bit) = (1..64usize).filter(|&l| contact >> l & 1 == 0).find_map(bit_of) {
            refused(edited_with(&f, |d| d[stream + bit / 8] ^= 1 << (bit % 8)), "coded tile");
            flipped += 1;
        }
        // Node 0 without contact: the first touching node's code is node
        // 0's (changing its residual breaks that; changing node 0's code
        // moves every code of the tile alike, a field of other heights).
        if contact & 1 == 0 {
            let first = (1..64usize).find(|&l| contact >> l & 1 != 0).unwrap();
            if let Some(bit) = bit_of(first) {
                refused(edited_with(&f, |d| d[stream + bit / 8] ^= 1 << (bit % 8)), "coded tile");
                flipped += 1;
            }
        }
    }
    assert!(flipped > 0, "a residual or a node 0 without contact to change");
}

/// `f`'s chunk edited by `edit`, in a 4.6 bundle with re-sealed checksums.
fn edited_with(f: &HeightField, edit: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
    let mut chunks = decompose(&bytes_of(f));
    let i = find(&chunks, b"HFLD");
    edit(&mut chunks[i].data);
    craft_version(&chunks, 4, 6)
}
