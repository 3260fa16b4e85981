//! Field-level errors in every known chunk, crafted at the offsets SPEC.md
//! gives and re-sealed, so that each check of the reader is reached.

use taxel_format::{BundleView, FormatError, Tag};

use crate::craft::{edit_chunk, put_f32, put_u16, put_u32};

/// Asserts that `bytes` are refused with `InvalidValue` for `field` of a chunk with `tag`.
fn invalid(bytes: Vec<u8>, tag: &[u8; 4], field: &str) {
    match BundleView::parse(&bytes) {
        Err(FormatError::InvalidValue { tag: t, field: f, .. }) if t == Tag(*tag) && f == field => {}
        other => panic!("expected {} `{field}` to be refused, got {other:?}", Tag(*tag)),
    }
}

fn limit(bytes: Vec<u8>, tag: &[u8; 4], field: &str) {
    match BundleView::parse(&bytes) {
        Err(FormatError::Limit { tag: t, field: f, .. }) if t == Tag(*tag) && f == field => {}
        other => panic!("expected {} `{field}` over its limit, got {other:?}", Tag(*tag)),
    }
}

fn length(bytes: Vec<u8>, tag: &[u8; 4]) {
    match BundleView::parse(&bytes) {
        Err(FormatError::ChunkLength { tag: t, .. }) if t == Tag(*tag) => {}
        other => panic!("expected a {} length error, got {other:?}", Tag(*tag)),
    }
}

#[test]
fn manifest_fields() {
    invalid(edit_chunk(b"MANI", |d| d[32] = 9), b"MANI", "family");
    invalid(edit_chunk(b"MANI", |d| d[..32].fill(b'a')), b"MANI", "profile name");
    invalid(edit_chunk(b"MANI", |d| d[96..112].fill(0xff)), b"MANI", "generator");
    invalid(edit_chunk(b"MANI", |d| put_u32(d, 48, 0)), b"MANI", "rate_hz");
    invalid(edit_chunk(b"MANI", |d| put_f32(d, 40, f32::NAN)), b"MANI", "array.pitch_x_mm");
    invalid(edit_chunk(b"MANI", |d| put_u16(d, 36, 0)), b"MANI", "array.cols");
    invalid(edit_chunk(b"MANI", |d| d[38] = 1), b"MANI", "reserved");
    invalid(edit_chunk(b"MANI", |d| d[143] = 1), b"MANI", "reserved");
    // The sample targets a grid: its carrier range must be valid.
    invalid(edit_chunk(b"MANI", |d| put_f32(d, 112, 0.0)), b"MANI", "grid.carrier_min_hz");
    // A laterotactile manifest has no family parameters.
    invalid(edit_chunk(b"MANI", |d| d[32] = 1), b"MANI", "family parameters");
    length(edit_chunk(b"MANI", |d| d.truncate(143)), b"MANI");
}

#[test]
fn mask_fields() {
    invalid(edit_chunk(b"VIBR", |d| d[12] = 12), b"VIBR", "bits");
    invalid(edit_chunk(b"VIBR", |d| d[14] = 1), b"VIBR", "reserved");
    invalid(edit_chunk(b"VIBR", |d| d[47] = 1), b"VIBR", "reserved");
    invalid(edit_chunk(b"VIBR", |d| put_f32(d, 16, f32::INFINITY)), b"VIBR", "origin_x_mm");
    invalid(edit_chunk(b"VIBR", |d| put_f32(d, 20, f32::NAN)), b"VIBR", "origin_y_mm");
    invalid(edit_chunk(b"VIBR", |d| put_f32(d, 24, 0.0)), b"VIBR", "px_per_mm");
    invalid(edit_chunk(b"VIBR", |d| put_f32(d, 28, 1.5)), b"VIBR", "amplitude");
    invalid(edit_chunk(b"VIBR", |d| put_u32(d, 32, 0)), b"VIBR", "frequency");
    invalid(edit_chunk(b"VIBR", |d| put_u32(d, 36, 1)), b"VIBR", "reserved");
    invalid(edit_chunk(b"GRAT", |d| put_f32(d, 32, 0.0)), b"GRAT", "wavelength_mm");
    invalid(edit_chunk(b"GRAT", |d| put_f32(d, 36, 400.0)), b"GRAT", "angle_deg");
    limit(edit_chunk(b"VIBR", |d| put_u32(d, 4, 0)), b"VIBR", "width");
    limit(edit_chunk(b"VIBR", |d| put_u32(d, 8, 16_385)), b"VIBR", "height");
    length(edit_chunk(b"VIBR", |d| d.truncate(d.len() - 1)), b"VIBR");
    // 16-bit samples take two bytes each: one byte short is refused.
    length(edit_chunk(b"GRAT", |d| d.truncate(d.len() - 1)), b"GRAT");
    length(edit_chunk(b"GRAT", |d| d.truncate(40)), b"GRAT");
}

/// Offset of dot `i` in the first (outline) dot table of the sample: 2 x 1
/// cells of 32 mm (at most one cell per dot: 5 dots, SPEC.md section 7).
fn dot(i: usize) -> usize {
    32 + 4 * (2 + 1) + 20 * i
}

#[test]
fn dot_table_fields() {
    let grid = edit_chunk(b"DOTS", |_| {});
    let view = BundleView::parse(&grid).unwrap();
    let Some(taxel_format::ChunkView::Dots(d)) = view.chunks().nth(3) else { panic!() };
    assert_eq!((d.grid.cols, d.grid.rows, d.grid.cell_mm), (2, 1, 32.0), "the offsets below assume this grid");
    invalid(edit_chunk(b"DOTS", |d| d[0] = 4), b"DOTS", "kind");
    invalid(edit_chunk(b"DOTS", |d| d[2] = 4), b"DOTS", "reserved");
    invalid(edit_chunk(b"DOTS", |d| put_f32(d, 16, f32::NAN)), b"DOTS", "grid origin_x");
    invalid(edit_chunk(b"DOTS", |d| put_f32(d, 24, 0.0)), b"DOTS", "cell_mm");
    invalid(edit_chunk(b"DOTS", |d| put_f32(d, 28, -1.0)), b"DOTS", "max_radius");
    // A larger max_radius keeps every dot in its cell but is not the canonical grid.
    invalid(edit_chunk(b"DOTS", |d| put_f32(d, 28, 5.0)), b"DOTS", "grid");
    invalid(edit_chunk(b"DOTS", |d| put_u32(d, 32, 1)), b"DOTS", "grid index");
    // Dot 0 moved a cell to the right but still listed in cell 0.
    invalid(edit_chunk(b"DOTS", |d| put_f32(d, dot(0), 39.0)), b"DOTS", "grid index");
    invalid(edit_chunk(b"DOTS", |d| put_f32(d, dot(0) + 8, 0.0)), b"DOTS", "dot radius");
    invalid(edit_chunk(b"DOTS", |d| put_f32(d, dot(1) + 12, 1.01)), b"DOTS", "dot amplitude");
    invalid(edit_chunk(b"DOTS", |d| put_f32(d, dot(4) + 4, f32::NAN)), b"DOTS", "dot y");
    // Cell starts that decrease: cell 1 (4 dots in cell 0) claims to start
    // after the end (5).
    invalid(edit_chunk(b"DOTS", |d| put_u32(d, 36, 6)), b"DOTS", "grid index");
    length(edit_chunk(b"DOTS", |d| put_u32(d, 4, 6)), b"DOTS");
    limit(edit_chunk(b"DOTS", |d| put_u32(d, 8, 0)), b"DOTS", "grid cells (1 or more)");
}

// Stroke table layout of the sample: 2 strokes, 4 points, 5 drives.
const S0: usize = 16;
const P0: usize = 16 + 2 * 32;
const D0: usize = P0 + 4 * 28;

#[test]
fn stroke_table_fields() {
    invalid(edit_chunk(b"STRK", |d| put_u32(d, 12, 1)), b"STRK", "reserved");
    invalid(edit_chunk(b"STRK", |d| put_u32(d, S0 + 8, 0)), b"STRK", "stroke duration");
    invalid(edit_chunk(b"STRK", |d| put_u32(d, S0 + 12, 0)), b"STRK", "carrier");
    invalid(edit_chunk(b"STRK", |d| put_f32(d, S0 + 16, 1.5)), b"STRK", "stroke intensity");
    invalid(edit_chunk(b"STRK", |d| put_u32(d, S0 + 20, 1)), b"STRK", "point range");
    // The second stroke starts at tick 86 400 000: u64::MAX would overflow its end.
    invalid(
        edit_chunk(b"STRK", |d| d[S0 + 32..S0 + 40].copy_from_slice(&u64::MAX.to_le_bytes())),
        b"STRK",
        "stroke start",
    );
    invalid(edit_chunk(b"STRK", |d| put_u32(d, P0 + 4, 0)), b"STRK", "point timing");
    invalid(edit_chunk(b"STRK", |d| put_u32(d, P0 + 4, 2000)), b"STRK", "point timing");
    invalid(edit_chunk(b"STRK", |d| put_u32(d, P0 + 28 + 8, 10)), b"STRK", "point peak");
    invalid(edit_chunk(b"STRK", |d| put_f32(d, P0 + 12, f32::NAN)), b"STRK", "point x");
    invalid(edit_chunk(b"STRK", |d| put_u32(d, P0 + 20, 1)), b"STRK", "drive range");
    invalid(edit_chunk(b"STRK", |d| put_u16(d, P0 + 26, 1)), b"STRK", "reserved");
    // brush-4x3 has 12 actuators: index 12 does not exist.
    invalid(edit_chunk(b"STRK", |d| put_u16(d, D0, 12)), b"STRK", "drive actuator");
    invalid(edit_chunk(b"STRK", |d| put_u16(d, D0 + 2, 1)), b"STRK", "reserved");
    invalid(edit_chunk(b"STRK", |d| put_f32(d, D0 + 4, -0.5)), b"STRK", "drive intensity");
    // A table whose strokes do not use every point.
    invalid(edit_chunk(b"STRK", |d| put_u32(d, S0 + 32 + 24, 0)), b"STRK", "counts");
    length(edit_chunk(b"STRK", |d| put_u32(d, 8, 6)), b"STRK");
    length(edit_chunk(b"STRK", |d| d.truncate(8)), b"STRK");
}

// Height field of the sample: 3 x 2 nodes.
const N: usize = 6;

#[test]
fn height_field_fields() {
    invalid(edit_chunk(b"HFLD", |d| put_u32(d, 12, 3)), b"HFLD", "reserved");
    invalid(edit_chunk(b"HFLD", |d| put_f32(d, 24, 0.0)), b"HFLD", "cell_mm");
    invalid(edit_chunk(b"HFLD", |d| put_f32(d, 40, -1.0)), b"HFLD", "gradient_cap");
    invalid(edit_chunk(b"HFLD", |d| put_f32(d, 28, -5.0)), b"HFLD", "extremes");
    invalid(edit_chunk(b"HFLD", |d| put_f32(d, 48 + 4, f32::NAN)), b"HFLD", "height");
    // Node 0 has no contact: it must be all zero.
    invalid(edit_chunk(b"HFLD", |d| put_f32(d, 48, 1.0)), b"HFLD", "no-contact node");
    invalid(edit_chunk(b"HFLD", |d| d[48 + 12 * N] = taxel_format::FIELD_EDGE), b"HFLD", "no-contact node");
    invalid(edit_chunk(b"HFLD", |d| d[48 + 12 * N + 1] = 1 | 4), b"HFLD", "flags");
    invalid(edit_chunk(b"HFLD", |d| put_f32(d, 48 + 4 * N + 4, 4.5)), b"HFLD", "gradient x");
    invalid(edit_chunk(b"HFLD", |d| put_f32(d, 48 + 8 * N + 4, -4.5)), b"HFLD", "gradient y");
    invalid(edit_chunk(b"HFLD", |d| d[48 + 13 * N] = 1), b"HFLD", "padding");
    limit(edit_chunk(b"HFLD", |d| put_u32(d, 4, 1)), b"HFLD", "cols (2 or more)");
    limit(edit_chunk(b"HFLD", |d| put_u32(d, 8, 16_385)), b"HFLD", "rows (2 or more)");
    length(edit_chunk(b"HFLD", |d| d.truncate(d.len() - 4)), b"HFLD");
}

#[test]
fn provenance_fields() {
    // Entry 0 is "lake" + "Lac Léman": the blob starts after 2 entries.
    let blob = 8 + 2 * 16;
    invalid(edit_chunk(b"PROV", |d| d[blob + 5] = 0xff), b"PROV", "strings");
    invalid(edit_chunk(b"PROV", |d| put_u32(d, 8, 1)), b"PROV", "string offsets");
    invalid(edit_chunk(b"PROV", |d| put_u32(d, 8 + 12, 1)), b"PROV", "string offsets");
    invalid(
        edit_chunk(b"PROV", |d| {
            d.push(b'x');
            let n = u32::from_le_bytes(d[4..8].try_into().unwrap());
            put_u32(d, 4, n + 1);
        }),
        b"PROV",
        "blob",
    );
    length(edit_chunk(b"PROV", |d| d.truncate(4)), b"PROV");
    length(edit_chunk(b"PROV", |d| put_u32(d, 4, 1000)), b"PROV");
}

/// Every field of a distance layer (SPEC.md section 6.2) that the reader checks.
#[test]
fn distance_layer_fields() {
    let tag = b"GDST";
    // Header: sources 2, 4 x 2 tiles, 2 stored (and 6 plane records).
    length(edit_chunk(tag, |d| d[12] = 3), tag);
    invalid(edit_chunk(tag, |d| d[4..8].copy_from_slice(&0u32.to_le_bytes())), tag, "tiles");
    invalid(edit_chunk(tag, |d| d[24..28].copy_from_slice(&0.0f32.to_le_bytes())), tag, "pitch_mm");
    invalid(edit_chunk(tag, |d| d[28..32].copy_from_slice(&1.5f32.to_le_bytes())), tag, "amplitude");
    invalid(edit_chunk(tag, |d| d[40..44].copy_from_slice(&17.0f32.to_le_bytes())), tag, "soft_mm");
    invalid(edit_chunk(tag, |d| d[44..48].copy_from_slice(&0.0f32.to_le_bytes())), tag, "step_mm");
    invalid(edit_chunk(tag, |d| d[16..20].copy_from_slice(&f32::NAN.to_le_bytes())), tag, "origin_x_mm");
    // Sources ascending: 0, 2 -> 2, 0.
    invalid(edit_chunk(tag, |d| d[48..52].copy_from_slice(&2u32.to_le_bytes())), tag, "sources");
    // Tile index 0, 2, plane 0, notch 1, 1, 3, ridge 3, corner 4 at
    // 56..88: stored tiles named out of order, or twice.
    invalid(edit_chunk(tag, |d| put_u32(d, 60, 3)), tag, "tile index");
    invalid(edit_chunk(tag, |d| put_u32(d, 64, 2)), tag, "tile index");
    // One stored tile fewer than the index names.
    invalid(edit_chunk(tag, |d| put_u32(d, 76, 0)), tag, "stored tiles");
    // Plane records named out of order, or twice.
    invalid(edit_chunk(tag, |d| put_u32(d, 80, 0xC000_0000)), tag, "tile index");
    invalid(edit_chunk(tag, |d| put_u32(d, 64, 0x8000_0001)), tag, "tile index");
    // A corner or notch names the next record and uses two: naming the one
    // after, or the notch's own second record, is out of order.
    invalid(edit_chunk(tag, |d| put_u32(d, 84, 0xA000_0005)), tag, "tile index");
    invalid(edit_chunk(tag, |d| put_u32(d, 68, 0xB000_0000)), tag, "tile index");
    invalid(edit_chunk(tag, |d| put_u32(d, 80, 0xC000_0002)), tag, "tile index");
    // An entry with only bit 30 set is no kind at all, nor is the top
    // nibble F (D is an arc since format 4.1, E a segments tile since 4.2,
    // below: here its four records would run past the table).
    for bad in [0x4000_0003u32, 0xE000_0004, 0xF000_0004] {
        invalid(edit_chunk(tag, |d| put_u32(d, 84, bad)), tag, "tile index");
    }
    // One plane record fewer than the index names (the record's bytes
    // left as samples would be a length error; a corner entry made outside
    // leaves two records unnamed).
    invalid(edit_chunk(tag, |d| put_u32(d, 84, 0)), tag, "planes");
    // A corner whose second record is missing.
    invalid(edit_chunk(tag, |d| drop(d.drain(168..184))), tag, "tile index");
    // Plane records at 88..184, (c, gx, gy, top): not finite, too steep,
    // too far, a plane, a notch's second record or a corner's first with a
    // top; a corner's second record not finite.
    invalid(edit_chunk(tag, |d| put_f32(d, 88, f32::NAN)), tag, "plane record");
    invalid(edit_chunk(tag, |d| put_f32(d, 92, f32::INFINITY)), tag, "plane record");
    invalid(edit_chunk(tag, |d| put_f32(d, 96, 1025.0)), tag, "plane record");
    invalid(edit_chunk(tag, |d| put_f32(d, 148, 70_000.0)), tag, "plane record");
    invalid(edit_chunk(tag, |d| put_f32(d, 100, 1.0)), tag, "plane record");
    invalid(edit_chunk(tag, |d| put_f32(d, 132, 1.0)), tag, "plane record");
    invalid(edit_chunk(tag, |d| put_f32(d, 164, 1.0)), tag, "plane record");
    invalid(edit_chunk(tag, |d| put_f32(d, 172, f32::NAN)), tag, "plane record");
    // The corner at 84 made a bend (records 4 and 5 at 152..184, (Vx, Vy,
    // d1x, d1y), (d2x, d2y, k, top)): its records as a corner's are no
    // bend's (directions not unit), a valid bend's are read, and each field
    // out of bounds is refused.
    let bend = |d: &mut Vec<u8>, vals: [f32; 8]| {
        put_u32(d, 84, 0x9000_0004);
        for (i, v) in vals.into_iter().enumerate() {
            put_f32(d, 152 + 4 * i, v);
        }
    };
    invalid(edit_chunk(tag, |d| put_u32(d, 84, 0x9000_0004)), tag, "plane record");
    let good = [4.0, 3.0, 0.6, 0.8, -1.0, 0.0, 16.0, 150.0];
    let bytes = edit_chunk(tag, |d| bend(d, good));
    let b = taxel_format::Bundle::from_bytes(&bytes).expect("a valid bend tile reads");
    assert!(format!("{b:?}").contains("planes"));
    for (i, bad) in
        [(0, f32::NAN), (1, 1025.0), (2, 0.5), (3, f32::INFINITY), (4, 1.01), (6, -1.0), (6, 1025.0), (7, 70_000.0)]
    {
        let mut vals = good;
        vals[i] = bad;
        invalid(edit_chunk(tag, |d| bend(d, vals)), tag, "plane record");
    }
    // The corner at 84 made an arc (format 4.1; records 4 and 5, (Cx, Cy,
    // R, k), (top, 0, 0, 0)): the corner's records are no arc's (a second
    // record that is not 0 after its top), a valid arc's are read and
    // raise the bundle's minor version to 1, and each field out of bounds
    // is refused.
    let arc = |d: &mut Vec<u8>, vals: [f32; 8]| {
        put_u32(d, 84, 0xD000_0004);
        for (i, v) in vals.into_iter().enumerate() {
            put_f32(d, 152 + 4 * i, v);
        }
    };
    invalid(edit_chunk(tag, |d| put_u32(d, 84, 0xD000_0004)), tag, "plane record");
    let good = [4.0, -3.0, 10.5, 16.0, 150.0, 0.0, 0.0, 0.0];
    let bytes = edit_chunk(tag, |d| arc(d, good));
    let b = taxel_format::Bundle::from_bytes(&bytes).expect("a valid arc tile reads");
    assert_eq!(b.lowest_minor(), 1);
    let Some(taxel_format::Chunk::Distance(layer)) =
        b.chunks.iter().find(|c| matches!(c, taxel_format::Chunk::Distance(_)))
    else {
        panic!("no distance layer");
    };
    // The arc tile (the fourth of the second row) plays `top` on its
    // circle, and `top − k` one cell inside it.
    let (h, tx, ty) = (layer.pitch_mm as f64, 3.0, 1.0);
    let corner = (layer.origin_x.0 as f64 + 8.0 * tx * h, layer.origin_y.0 as f64 + 8.0 * ty * h);
    let on = |u: f64, w: f64| layer.distance_at((corner.0 + u * h) as f32, (corner.1 + w * h) as f32);
    let step = layer.step_mm as f64;
    let code = |d: Option<f32>| d.map(|d| d as f64 / step + 128.0);
    assert!(code(on(4.0, -3.0 + 10.5)).is_some_and(|c| (c - 150.0).abs() < 1e-2));
    assert!(code(on(4.0, -3.0 + 9.5)).is_some_and(|c| (c - 134.0).abs() < 1e-2));
    for (i, bad) in [
        (0, f32::NAN),
        (1, 1025.0),
        (2, -1.0),
        (2, 2049.0),
        (3, -1.0),
        (3, 1025.0),
        (4, 70_000.0),
        (5, 70_000.0),
        (5, f32::NAN),
        (6, 1025.0),
        (7, f32::INFINITY),
    ] {
        let mut vals = good;
        vals[i] = bad;
        invalid(edit_chunk(tag, |d| arc(d, vals)), tag, "plane record");
    }
    // A cut arc (format 4.3): the arc with a plane `c + gx u + gy w` in its
    // second record's last three values reads, raises the minor version to
    // 3, writes as 4.3, and plays the lesser of the two codes: the plane
    // `200 − 8 u` is below the arc right of u = 6.25 on the circle (where
    // the arc plays 150) and above it left of there.
    let cut = [4.0, -3.0, 10.5, 16.0, 150.0, 200.0, -8.0, 0.0];
    let bytes = edit_chunk(tag, |d| arc(d, cut));
    let b = taxel_format::Bundle::from_bytes(&bytes).expect("a valid cut arc reads");
    assert_eq!(b.lowest_minor(), 3);
    let again = b.to_bytes().expect("a cut arc's bundle writes");
    assert_eq!(u16::from_le_bytes([again[10], again[11]]), 3, "written as 4.3");
    let Some(taxel_format::Chunk::Distance(layer)) =
        b.chunks.iter().find(|c| matches!(c, taxel_format::Chunk::Distance(_)))
    else {
        panic!("no distance layer");
    };
    let on = |u: f64, w: f64| layer.distance_at((corner.0 + u * h) as f32, (corner.1 + w * h) as f32);
    for (u, w) in [(4.0, 7.5), (4.0, 6.5), (7.0, 2.0), (1.0, 5.0), (7.5, 7.0)] {
        let arc = 150.0 - 16.0 * (((u - 4.0f64).hypot(w + 3.0) - 10.5).abs());
        let want = arc.min(200.0 - 8.0 * u);
        assert!(code(on(u, w)).is_some_and(|c| (c - want).abs() < 1e-2), "({u}, {w}): {:?} vs {want}", code(on(u, w)));
    }
    // The corner at 84 made a segments tile (format 4.2; records 4 to 7,
    // three segments (ax, ay, bx, by), then (k, top, 0, 0): two records
    // more, inserted before the samples): the corner's records alone are
    // too few, a valid segments tile is read, plays `top − k · d` and
    // raises the bundle's minor version to 2, and each field out of bounds
    // is refused.
    let segments = |d: &mut Vec<u8>, vals: [f32; 16]| {
        put_u32(d, 84, 0xE000_0004);
        d.splice(184..184, [0u8; 32]);
        for (i, v) in vals.into_iter().enumerate() {
            put_f32(d, 152 + 4 * i, v);
        }
    };
    invalid(edit_chunk(tag, |d| put_u32(d, 84, 0xE000_0004)), tag, "tile index");
    // Segments from (0, 2) to (8, 2), a point at (4, 6), the first again;
    // k = 16 codes per cell, top 150; k may be negative (a cut band).
    let good = [0.0, 2.0, 8.0, 2.0, 4.0, 6.0, 4.0, 6.0, 0.0, 2.0, 8.0, 2.0, 16.0, 150.0, 0.0, 0.0];
    for k in [16.0, -16.0] {
        let mut vals = good;
        vals[12] = k;
        let bytes = edit_chunk(tag, |d| segments(d, vals));
        let b = taxel_format::Bundle::from_bytes(&bytes).expect("a valid segments tile reads");
        assert_eq!(b.lowest_minor(), 2);
        let again = b.to_bytes().expect("a segments tile's bundle writes");
        assert_eq!(u16::from_le_bytes([again[10], again[11]]), 2, "written as 4.2");
        let Some(taxel_format::Chunk::Distance(layer)) =
            b.chunks.iter().find(|c| matches!(c, taxel_format::Chunk::Distance(_)))
        else {
            panic!("no distance layer");
        };
        let (h, step) = (layer.pitch_mm as f64, layer.step_mm as f64);
        let corner = (layer.origin_x.0 as f64 + 24.0 * h, layer.origin_y.0 as f64 + 8.0 * h);
        let code = |u: f64, w: f64| {
            layer.distance_at((corner.0 + u * h) as f32, (corner.1 + w * h) as f32).map(|d| d as f64 / step + 128.0)
        };
        // On the first segment, 1.5 cells below it (nearer it than the
        // point), and 1 cell right of the point (nearer the point).
        for ((u, w), d) in [((3.0, 2.0), 0.0), ((6.0, 3.5), 1.5), ((5.0, 6.0), 1.0)] {
            let want = 150.0 - k as f64 * d;
            assert!(code(u, w).is_some_and(|c| (c - want).abs() < 0.05), "({u}, {w}): {:?} vs {want}", code(u, w));
        }
    }
    for (i, bad) in
        [(0, f32::NAN), (5, 1025.0), (11, f32::INFINITY), (12, -1025.0), (13, 70_000.0), (14, 1.0), (15, 1.0)]
    {
        let mut vals = good;
        vals[i] = bad;
        invalid(edit_chunk(tag, |d| segments(d, vals)), tag, "plane record");
    }
    // The record table's length follows the index.
    invalid(edit_chunk(tag, |d| d.extend_from_slice(&[0; 16])), tag, "planes");
    length(edit_chunk(tag, |d| d.truncate(47)), tag);
    length(edit_chunk(tag, |d| d.push(0)), tag);
}

/// A fine tile (format 4.4): a layer of two tiles, the first stored, the
/// second `fine` times finer, in two channels where `pair` (`fine²` stored
/// tiles a channel from stored tile 1), whose samples are `code(c, x, y)`
/// in channel `c` at fine lattice point `(x, y)` of the second tile (`x, y`
/// from 0 to `8 fine`).
fn fine_layer(fine: u32, pair: bool, code: impl Fn(usize, usize, usize) -> u8) -> taxel_format::DistanceLayer {
    let f = fine as usize;
    let mut samples: Vec<u8> = (0..81).map(|k| 100 + (k % 9) as u8).collect();
    for c in 0..1 + pair as usize {
        for b in 0..f {
            for a in 0..f {
                for j in 0..9 {
                    for i in 0..9 {
                        samples.push(code(c, 8 * a + i, 8 * b + j));
                    }
                }
            }
        }
    }
    taxel_format::DistanceLayer {
        kind: taxel_format::MaskKind::Grating { wavelength: taxel_format::Mm(3.0), angle_deg: 0.0 },
        amplitude: 1.0,
        soft_mm: 0.0,
        step_mm: 0.01,
        origin_x: taxel_format::Mm(10.0),
        origin_y: taxel_format::Mm(20.0),
        pitch_mm: 0.5,
        tile_cols: 2,
        tile_rows: 1,
        sources: vec![],
        tiles: vec![taxel_format::TILE_FIRST_STORED, taxel_format::fine_entry(1, fine, pair).expect("an entry")],
        planes: vec![],
        samples,
    }
}

fn bundle_of(layer: taxel_format::DistanceLayer) -> taxel_format::Bundle {
    let profile = taxel_format::profiles::builtin("stress2").expect("built-in profile");
    let mut b = taxel_format::Bundle::new(taxel_format::Manifest::new(profile));
    b.chunks.push(taxel_format::Chunk::Distance(layer));
    b
}

#[test]
fn a_fine_tile_plays_its_fine_samples_and_is_written_as_4_4() {
    for (fine, pair) in [(1u32, true), (2, false), (2, true), (4, false), (4, true), (8, false), (8, true)] {
        let f = fine as f32;
        // At every fine lattice point the code is its sample (the lesser of
        // the two channels'); between them the bilinear interpolation of
        // its fine cell's corners (the lesser of each channel's).
        let code = |c: usize, x: usize, y: usize| ((x * 37 + y * 11 + x * y + c * 101) % 200) as u8 + 20;
        let b = bundle_of(fine_layer(fine, pair, code));
        assert_eq!(b.lowest_minor(), 4);
        let bytes = b.to_bytes().expect("a fine tile's bundle writes");
        assert_eq!(u16::from_le_bytes([bytes[10], bytes[11]]), 4, "written as 4.4");
        let back = taxel_format::Bundle::from_bytes(&bytes).expect("it reads back");
        assert_eq!(back, b);
        let Some(taxel_format::Chunk::Distance(layer)) = back.chunks.first() else { panic!("no layer") };
        // The second tile starts 4 mm right of the origin; a fine cell is 0.5 / f mm.
        let at = |x: f32, y: f32| layer.distance_at(14.0 + x * 0.5 / f, 20.0 + y * 0.5 / f);
        let channels = if pair { 2 } else { 1 };
        let n = 8 * fine as usize;
        for y in 0..n {
            for x in 0..n {
                let least = |v: &dyn Fn(usize) -> f32| (0..channels).map(v).fold(f32::MAX, f32::min);
                let want = (least(&|c| code(c, x, y) as f32) - 128.0) * 0.01;
                assert!(at(x as f32, y as f32).is_some_and(|d| (d - want).abs() < 1e-5), "fine {fine} at ({x}, {y})");
                // A quarter into the cell, a quarter down.
                let inner = |c: usize| {
                    let s = |dx: usize, dy: usize| code(c, x + dx, y + dy) as f32;
                    let top = s(0, 0) * 0.75 + s(1, 0) * 0.25;
                    let bot = s(0, 1) * 0.75 + s(1, 1) * 0.25;
                    top * 0.75 + bot * 0.25
                };
                let want = (least(&inner) - 128.0) * 0.01;
                let got = at(x as f32 + 0.25, y as f32 + 0.25);
                assert!(got.is_some_and(|d| (d - want).abs() < 1e-4), "fine {fine} in ({x}, {y}): {got:?} vs {want}");
            }
        }
        // The first tile is unchanged: its own samples.
        assert!(layer.distance_at(10.0, 20.0).is_some_and(|d| (d - (100.0 - 128.0) * 0.01).abs() < 1e-6));
    }
}

#[test]
fn a_fine_tile_with_the_wrong_stored_tiles_is_refused() {
    let code = |_: usize, _: usize, _: usize| 128u8;
    // Naming stored tile 0 again, or 2 (skipping 1).
    for first in [0, 2] {
        let mut layer = fine_layer(2, false, code);
        layer.tiles[1] = taxel_format::fine_entry(first, 2, false).expect("an entry");
        assert!(bundle_of(layer).to_bytes().is_err(), "first {first}");
    }
    // One channel at the lattice's own pitch (a stored tile's second encoding).
    let mut layer = fine_layer(1, true, code);
    layer.tiles[1] = taxel_format::TILE_FINE | 1;
    layer.samples.truncate(81 * 2);
    assert!(bundle_of(layer).to_bytes().is_err());
    // Fewer stored tiles than it names: one channel of a pair.
    let mut layer = fine_layer(4, true, code);
    layer.samples.truncate(81 * 17);
    assert!(bundle_of(layer).to_bytes().is_err());
}
