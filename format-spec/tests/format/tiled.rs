//! Tiled height fields (format 4.5, SPEC.md section 9.1): the tables read
//! from the bytes by the specification's rules alone, the round trip
//! through the owned model, and every check of the reader.

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

/// Node `(i, j)`'s height and contact read from the chunk's bytes as
/// section 9.1 says, without the crate.
fn spec_node(d: &[u8], i: u32, j: u32) -> Option<f32> {
    let w = |o: usize| u32::from_le_bytes(d[o..o + 4].try_into().unwrap());
    let f = |o: usize| f32::from_bits(w(o));
    let (cols, cell, step, base, s) = (w(4), f(24), f(48), f(52), w(56) as usize);
    let pool = |k: u32| w(64 + 4 * s + 4 * k as usize);
    let sc = cols.div_ceil(8).div_ceil(4);
    let (tx, ty) = (i / 8, j / 8);
    let e = w(64 + 4 * ((ty / 4) * sc + tx / 4) as usize);
    let r = if e >> 31 == 1 { e & 0x7fff_ffff } else { pool(e + (ty % 4) * 4 + tx % 4) };
    let head = pool(r);
    let l = (j % 8) * 8 + i % 8;
    let bits = (head >> 8) & 0xff;
    let body = match head & 0xff {
        0 => return None,
        1 => 3,
        _ => 4 + 2 * bits,
    };
    let bit = |at: u32, k: u32| (pool(at + k / 32) >> (k % 32)) & 1;
    if head & 1 << 16 != 0 && bit(r + 1 + body, l) == 0 {
        return None;
    }
    Some(if head & 0xff == 1 {
        let (h0, gx, gy) = (f32::from_bits(pool(r + 1)), f32::from_bits(pool(r + 2)), f32::from_bits(pool(r + 3)));
        h0 + gx * (i as f32 * cell) + gy * (j as f32 * cell)
    } else {
        let residual = (0..bits).map(|b| bit(r + 5, l * bits + b) << b).sum::<u32>() as i64;
        let (c0, m) = (pool(r + 1) as i32 as i64, pool(r + 2) as i64);
        let (sx, sy) = (pool(r + 3) as i32 as i64, pool(r + 4) as i32 as i64);
        let code = c0 + ((sx * (i % 8) as i64 + sy * (j % 8) as i64) >> 8) + m * residual;
        base + code as f32 * step
    })
}

#[test]
fn a_tiled_field_stores_every_height_within_half_a_step_and_reads_back_byte_for_byte() {
    let f = field();
    let bytes = bytes_of(&f);
    assert_eq!(BundleView::parse(&bytes).unwrap().version(), (4, 5));
    let view = view_of(&bytes);
    assert!(view.is_tiled());
    let chunks = decompose(&bytes);
    let d = &chunks[find(&chunks, b"HFLD")].data;
    assert_eq!(u32::from_le_bytes(d[12..16].try_into().unwrap()), 1, "encoding 1");
    // A 4.0 field of these nodes is 13 bytes a node; the tiled one a fraction of it.
    assert!(d.len() * 4 < 13 * 70 * 45, "{} bytes", d.len());
    for j in 0..f.rows {
        for i in 0..f.cols {
            let k = (j * f.cols + i) as usize;
            let spec = spec_node(d, i, j);
            assert_eq!(spec.is_some(), f.flags[k] & FIELD_CONTACT != 0, "contact of ({i}, {j})");
            assert_eq!(view.flags_at(k as u32), f.flags[k], "flags of ({i}, {j})");
            if let Some(h) = spec {
                assert!((h - f.heights[k]).abs() <= 0.001 + 1e-5, "({i}, {j}): {h} vs {}", f.heights[k]);
                assert_eq!(view.height_at(k as u32).to_bits(), h.to_bits(), "({i}, {j}) as the crate reads it");
            }
        }
    }
    // Unpacked into the owned model and written again: the same bytes.
    let back = Bundle::from_view(&BundleView::parse(&bytes).unwrap());
    assert_eq!(back.to_bytes().unwrap(), bytes);
}

/// The field's chunk edited by `edit`, in a 4.5 bundle with re-sealed checksums.
fn edited(edit: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
    let mut chunks = decompose(&bytes_of(&field()));
    let i = find(&chunks, b"HFLD");
    edit(&mut chunks[i].data);
    craft_version(&chunks, 4, 5)
}

fn refused(bytes: Vec<u8>, field: &str) {
    match BundleView::parse(&bytes) {
        Err(FormatError::InvalidValue { tag, field: f, .. }) if tag == Tag::HEIGHT && f == field => {}
        other => panic!("expected `{field}` to be refused, got {other:?}"),
    }
}

#[test]
fn every_check_of_the_tiled_reader_is_reached() {
    let d = {
        let chunks = decompose(&bytes_of(&field()));
        chunks[find(&chunks, b"HFLD")].data.clone()
    };
    let s = u32::from_le_bytes(d[56..60].try_into().unwrap()) as usize;
    let first = u32::from_le_bytes(d[64..68].try_into().unwrap());
    let pool = 64 + 4 * s;
    refused(edited(|d| put_f32(d, 48, 0.0)), "height step");
    refused(edited(|d| put_f32(d, 52, f32::NAN)), "height base");
    refused(edited(|d| put_u32(d, 56, 7)), "superblocks");
    refused(edited(|d| put_f32(d, 28, -7.0)), "extremes");
    refused(edited(|d| put_f32(d, 36, 5.0)), "max gradient");
    // The first superblock names records through a list or directly.
    refused(edited(|d| put_u32(d, 64, 1 << 31 | 0x7fff_0000)), "tile record");
    if first >> 31 == 0 {
        refused(edited(|d| put_u32(d, 64, 0x7fff_0000)), "tile list");
    }
    // The first record (word 0 of the pool) with an unknown kind, too many
    // bits, or reserved bits set.
    for head in [3u32, 25 << 8 | 2, 1 << 20 | 1, 4 << 8 | 1] {
        refused(edited(|d| put_u32(d, pool, head)), "tile record");
    }
    // A length that disagrees with S and W.
    match BundleView::parse(&edited(|d| d.extend_from_slice(&[0; 4]))) {
        Err(FormatError::ChunkLength { tag, .. }) if tag == Tag::HEIGHT => {}
        other => panic!("expected a length error, got {other:?}"),
    }
    // A 4.0 field whose encoding word says tiled is refused, never misread.
    let float = HeightField { encoding: HeightEncoding::Float, ..field() };
    let mut chunks = decompose(&bytes_of(&float));
    let i = find(&chunks, b"HFLD");
    put_u32(&mut chunks[i].data, 12, 1);
    assert!(BundleView::parse(&craft_version(&chunks, 4, 4)).is_err());
}
