//! Distance layers (`VDST`, `GDST`) against an f64 evaluation of SPEC.md
//! section 6.2 and the seed-000 equations: random sparse fields (inside,
//! outside and stored tiles with random codes, plane, ridge, corner,
//! notch, bend, arc (plain and cut) and segments tiles with random records,
//! fine tiles with random codes), hard and soft edges, both primitives,
//! anywhere on and off the lattice.

use proptest::prelude::*;
use taxel_format::{
    Chunk, DeviceProfile, DistanceLayer, MaskKind, Mm, TILE_ARC, TILE_BEND, TILE_CORNER, TILE_NOTCH, TILE_PLANE,
    TILE_RIDGE, TILE_SEGMENTS, TilePlane,
};

use crate::support::*;

#[allow(clippy::too_many_arguments)]
pub(crate) fn field(
    kind: MaskKind,
    x0: f32,
    y0: f32,
    pitch: f32,
    cols: u32,
    rows: u32,
    entries: &[u8],
    codes: &[u8],
    soft: f32,
) -> DistanceLayer {
    let mut tiles = Vec::new();
    let mut samples = Vec::new();
    let mut planes = Vec::new();
    let mut next = 2;
    for k in 0..(cols * rows) as usize {
        // A record from the codes: c within a few hundred codes of the
        // bias, gradients up to ±64 codes per cell, a top near the bias.
        let at = |n: usize| codes[(k * 7 + n) % codes.len()] as f32;
        let record = |top: f32, n: usize| TilePlane {
            c: (at(n) - 128.0) * 2.0 + at(n + 1) / 256.0,
            gx: (at(n + 2) - 128.0) / 2.0,
            gy: (at(n + 3) - 128.0) / 2.0,
            top,
        };
        let entry = entries[k % entries.len()];
        match entry % 10 {
            0 => tiles.push(0),
            1 => tiles.push(1),
            3 => {
                tiles.push(TILE_PLANE | planes.len() as u32);
                planes.push(record(0.0, 0));
            }
            4 => {
                tiles.push(TILE_RIDGE | planes.len() as u32);
                planes.push(record(at(4) + 64.0, 0));
            }
            kind @ (5 | 6) => {
                tiles.push(if kind == 5 { TILE_CORNER } else { TILE_NOTCH } | planes.len() as u32);
                planes.push(record(0.0, 0));
                planes.push(record(0.0, 3));
            }
            7 => {
                // A bend: a vertex within a few cells of the tile, two
                // random rays (one in eight a band's end, d2 = d1), k up to
                // 64 codes per cell.
                tiles.push(TILE_BEND | planes.len() as u32);
                let turn = |n: usize| (at(n) / 256.0 * std::f32::consts::TAU).sin_cos();
                let (s1, c1) = turn(2);
                let (s2, c2) = if at(5) < 32.0 { (s1, c1) } else { turn(3) };
                planes.push(TilePlane { c: at(0) / 16.0 - 4.0, gx: at(1) / 16.0 - 4.0, gy: c1, top: s1 });
                planes.push(TilePlane { c: c2, gx: s2, gy: at(4) / 4.0, top: 128.0 + at(6) });
            }
            8 => {
                // An arc (format 4.1): a centre within a few cells of the
                // tile, a radius up to 16 cells (one in eight a cone, 0), k
                // up to 64 codes per cell.
                tiles.push(TILE_ARC | planes.len() as u32);
                let radius = if at(5) < 32.0 { 0.0 } else { at(1) / 16.0 };
                planes.push(TilePlane { c: at(0) / 16.0 - 4.0, gx: at(2) / 16.0 - 4.0, gy: radius, top: at(4) / 4.0 });
                // One in two a cut arc (format 4.3): the lesser of that and
                // a random plane.
                let cut =
                    if at(3) >= 128.0 { record(0.0, 1) } else { TilePlane { c: 0.0, gx: 0.0, gy: 0.0, top: 0.0 } };
                planes.push(TilePlane { c: 64.0 + at(6), gx: cut.c, gy: cut.gx, top: cut.gy });
            }
            9 => {
                // Segments (format 4.2): three segments with ends within a
                // few cells of the tile (one in eight a point, a = b), k up
                // to ±64 codes per cell (negative for a band cut out of a
                // grating).
                tiles.push(TILE_SEGMENTS | planes.len() as u32);
                for s in 0..3 {
                    let end = |n: usize| at(n + 2 * s) / 16.0 - 4.0;
                    let (ax, ay) = (end(0), end(1));
                    let (bx, by) = if at(7 + s) < 32.0 { (ax, ay) } else { (end(2), end(3)) };
                    planes.push(TilePlane { c: ax, gx: ay, gy: bx, top: by });
                }
                planes.push(TilePlane { c: (at(4) - 128.0) / 2.0, gx: 128.0 + at(6) - at(1), gy: 0.0, top: 0.0 });
            }
            _ => {
                // Entries from 10 on: one in four a plain stored tile, the
                // others fine tiles (format 4.4), 1 (two channels only), 2, 4
                // or 8 times finer, in one or two channels: fine² stored
                // tiles a channel. (Below 10, plain: `sampled_fields`.)
                let fine = if entry < 10 { 0 } else { [0u32, 1, 2, 4, 8][at(5) as usize % 5] };
                let pair = fine == 1 || (fine > 1 && at(6) >= 128.0);
                let stored = if fine == 0 { 1 } else { fine * fine * (1 + pair as u32) };
                tiles.push(if fine == 0 {
                    next
                } else {
                    0x6000_0000 | fine.trailing_zeros() << 26 | (pair as u32) << 25 | (next - 2)
                });
                for n in 0..stored as usize {
                    samples.extend((0..81).map(|i| codes[(k * 81 + n * 13 + i) % codes.len()]));
                }
                next += stored;
            }
        }
    }
    DistanceLayer {
        kind,
        amplitude: 0.9,
        soft_mm: soft,
        step_mm: 0.01,
        origin_x: Mm(x0),
        origin_y: Mm(y0),
        pitch_mm: pitch,
        tile_cols: cols,
        tile_rows: rows,
        sources: vec![],
        tiles,
        planes,
        samples,
    }
}

/// Every actuator within one 10-bit step of the reference, except where
/// the profile is so steep (a hard edge) that the reference itself moves by
/// more than half a step when the interpolated code moves by 0.02: there the
/// 14-bit interpolation weights decide, a few micrometres from the edge.
fn assert_close(layer: DistanceLayer, tick: u64, x: f32, y: f32) {
    assert_close_on(stress2(), layer, tick, x, y);
}

/// Whether the field of `layer` jumps by more than a code within 3e-5 mm of
/// `(x, y)`, ten times the f32 error of an actuator's position (random fine
/// tiles climb up to 8,200 codes a millimetre: 0.7 codes over that distance
/// wherever the field is continuous), or leaves the layer there.
fn jumps(layer: &DistanceLayer, x: f64, y: f64) -> bool {
    const E: f64 = 3e-5;
    let around = [(-E, -E), (E, -E), (-E, E), (E, E)].map(|(dx, dy)| field_code(layer, x + dx, y + dy));
    let codes: Vec<f64> = around.iter().flatten().copied().collect();
    let spread =
        codes.iter().fold(f64::NEG_INFINITY, |a, &c| a.max(c)) - codes.iter().fold(f64::INFINITY, |a, &c| a.min(c));
    spread > 1.0 || !(codes.is_empty() || codes.len() == 4)
}

/// [`assert_close`] on the array of profile `p`.
fn assert_close_on(p: DeviceProfile, layer: DistanceLayer, tick: u64, x: f32, y: f32) {
    let chunks = vec![Chunk::Distance(layer.clone())];
    let bytes = bundle_bytes(p, chunks.clone());
    let got = play(&bytes, tick, x, y);
    let cols = p.cols as usize;
    for row in 0..p.rows as usize {
        for col in 0..cols {
            let (ax, ay) = actuator_pos(&p, x as f64, y as f64, row, col);
            if let Some(c) = field_code(&layer, ax, ay) {
                let steep = (profile_of_code(&layer, c + 0.02) - profile_of_code(&layer, c - 0.02)).abs();
                if steep * 1023.0 > 0.5 {
                    continue;
                }
            }
            // Random tiles need not agree where they meet (a compiled field
            // does: both sides sample the same distance), so on a tile's or
            // fine sub-tile's edge the field jumps, and which side an
            // actuator exactly on it reads depends on the last bit of its
            // f32 position: either is right. Such points are skipped.
            if jumps(&layer, ax, ay) {
                continue;
            }
            let want = expected_code(&p, reference(&p, &chunks, tick, x as f64, y as f64, row, col));
            let code = got[cols * row + col];
            assert!(
                (code as f64 - want).abs() <= 1.0,
                "actuator ({row}, {col}) at ({ax:.4}, {ay:.4}), tick {tick}: got {code}, want {want:.3}"
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn fields_follow_the_spec_and_the_equations(
        (x, y) in (6.0f32..104.0, 6.0f32..54.0),
        (dx, dy) in (-12.0f32..4.0, -12.0f32..4.0),
        pitch in prop::sample::select(vec![0.25f32, 0.5, 0.7, 1.0]),
        (cols, rows) in (1u32..5, 1u32..5),
        entries in prop::collection::vec(any::<u8>(), 1..20),
        codes in prop::collection::vec(any::<u8>(), 81..400),
        soft in prop::sample::select(vec![0.0f32, 0.05, 0.3, 2.0]),
        grating in any::<bool>(),
        (lambda, angle) in (0.5f32..10.0, -360.0f32..=360.0),
        tick in 0u64..10_000_000,
    ) {
        let kind = if grating { grating_kind(lambda, angle) } else { vibration(50_000) };
        assert_close(field(kind, x + dx, y + dy, pitch, cols, rows, &entries, &codes, soft), tick, x, y);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// A layer of outside, inside and stored tiles only plays through its
    /// own instance of the kernel (chosen at load): the same checks.
    #[test]
    fn sampled_fields_follow_the_spec_and_the_equations(
        (x, y) in (6.0f32..104.0, 6.0f32..54.0),
        (dx, dy) in (-12.0f32..4.0, -12.0f32..4.0),
        pitch in prop::sample::select(vec![0.25f32, 0.5, 0.7, 1.0]),
        (cols, rows) in (1u32..5, 1u32..5),
        entries in prop::collection::vec(0u8..3, 1..20),
        codes in prop::collection::vec(any::<u8>(), 81..400),
        soft in prop::sample::select(vec![0.0f32, 0.05, 0.3, 2.0]),
        grating in any::<bool>(),
        (lambda, angle) in (0.5f32..10.0, -360.0f32..=360.0),
        tick in 0u64..10_000_000,
    ) {
        let kind = if grating { grating_kind(lambda, angle) } else { vibration(50_000) };
        // Entries 0, 1 and 2: outside, inside and a stored tile (`field`).
        assert_close(field(kind, x + dx, y + dy, pitch, cols, rows, &entries, &codes, soft), tick, x, y);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    /// Arrays of more than eight rows, in one block (3 x 20, 1 x 40) or
    /// several (5 x 30: blocks of 12 rows): a layer plays its rows eight
    /// at a time, so every actuator of the later eights is checked too.
    #[test]
    fn tall_arrays_follow_the_spec_and_the_equations(
        (cols, rows) in prop::sample::select(vec![(3u16, 20u16), (1, 40), (5, 30)]),
        (x, fy) in (6.0f32..104.0, 0.0f32..1.0),
        (dx, dy) in (-12.0f32..4.0, -12.0f32..4.0),
        pitch in prop::sample::select(vec![0.25f32, 0.5, 0.7, 1.0]),
        (tile_cols, tile_rows) in (1u32..5, 1u32..8),
        entries in prop::collection::vec(any::<u8>(), 1..20),
        codes in prop::collection::vec(any::<u8>(), 81..400),
        soft in prop::sample::select(vec![0.0f32, 0.3]),
        grating in any::<bool>(),
        tick in 0u64..10_000_000,
    ) {
        let p = DeviceProfile { cols, rows, ..stress2() };
        // The carrier anywhere the whole array stays on the 60 mm tall surface.
        let half = (rows as f32 - 1.0) / 2.0 * p.pitch_y_mm + 1.0;
        let y = half + fy * (p.surface_h_mm - 2.0 * half);
        let kind = if grating { grating_kind(3.0, 30.0) } else { vibration(50_000) };
        // The layer reaches from above the array's top to below its bottom.
        let layer = field(kind, x + dx, y - half + dy, pitch, tile_cols, tile_rows, &entries, &codes, soft);
        assert_close_on(p, layer, tick, x, y);
    }
}

fn grating_kind(lambda: f32, angle: f32) -> MaskKind {
    grating(lambda, angle)
}

#[test]
fn an_inside_tile_is_full_amplitude_and_an_outside_one_rests() {
    // Two tiles of 4 mm: inside on the left, outside on the right, under a
    // grating of angle 90 at tick 0 (eq. 3 at x = multiples of λ is 1).
    let p = stress2();
    let layer = field(grating(2.0, 90.0), 40.0, 26.0, 0.5, 2, 1, &[1, 0], &[128], 0.0);
    let bytes = bundle_bytes(p, vec![Chunk::Distance(layer)]);
    let frame = play(&bytes, 0, 44.0, 30.0);
    // Row 0 (y = 25.1) lies above the lattice: at rest.
    assert!(frame[..8].iter().all(|&c| c == 0), "{frame:?}");
    // Actuator columns 0..3 lie at x 39.8, 41, 42.2, 43.4: column 0 is left
    // of the lattice, the others in the inside tile; 4..7 (44.6..48.2) outside.
    let row = &frame[8..16];
    assert_eq!(row[0], 0);
    for (c, &code) in row.iter().enumerate().take(4).skip(1) {
        let x = 39.8 + 1.2 * c as f64;
        let want = (0.9 * eq3(x, 26.5, 2.0, 90.0) * 1023.0).round() as i64;
        assert!((code as i64 - want).abs() <= 1, "column {c}: {code} against {want}");
    }
    assert!(row[4..].iter().all(|&c| c == 0), "{row:?}");
}

#[test]
fn a_corner_tile_plays_the_lesser_of_its_planes_and_a_notch_the_greater() {
    // One 4 mm tile at (40, 26), steps of 0.01 mm (50 codes per cell of
    // 0.5 mm): the planes are the signed distances to x = 42 and y = 28, so
    // a corner is felt right of and below (42, 28) and a notch right of or below it.
    let p = stress2();
    let planes =
        vec![TilePlane { c: -72.0, gx: 50.0, gy: 0.0, top: 0.0 }, TilePlane { c: -72.0, gx: 0.0, gy: 50.0, top: 0.0 }];
    let art = |entry: u32| {
        let layer = DistanceLayer {
            tiles: vec![entry],
            planes: planes.clone(),
            samples: vec![],
            ..field(grating(3.0, 90.0), 40.0, 26.0, 0.5, 1, 1, &[0], &[128], 0.0)
        };
        let frame = play(&bundle_bytes(p, vec![Chunk::Distance(layer)]), 0, 44.0, 30.0);
        // Actuator rows 1..=3 lie at y 26.5, 27.9, 29.3 and columns 1..=3 at
        // x 41, 42.2, 43.4: inside the tile.
        (1..=3)
            .map(|r| (1..=3).map(|c| if frame[8 * r + c] > 0 { '#' } else { '.' }).collect::<String>())
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(art(TILE_CORNER), "...\n...\n.##");
    assert_eq!(art(TILE_NOTCH), ".##\n.##\n###");
}

/// A distance layer's vibration takes its phase from the integer tick, as a
/// raster mask's does: a day of ticks later (and near `u64::MAX`) the frames
/// are those of tick 0, bit for bit, while a quarter period later they move.
#[test]
fn a_distance_layer_s_phase_comes_from_the_integer_tick() {
    let p = stress2();
    // Two inside tiles of 4 mm under the array, a 50 Hz vibration.
    let layer = field(vibration(50_000), 40.0, 26.0, 0.5, 2, 2, &[1, 1, 1, 1], &[128], 0.0);
    let bytes = bundle_bytes(p, vec![Chunk::Distance(layer)]);
    let (x, y) = (44.0, 30.0);
    let frame0 = play(&bytes, 0, x, y);
    assert!(frame0.iter().any(|&c| c > 0), "the layer plays under the array: {frame0:?}");
    for k in 0..40 {
        assert_eq!(play(&bytes, 86_400_000 + k, x, y), play(&bytes, k, x, y), "tick {k}");
    }
    let far = u64::MAX - u64::MAX % 1_000_000;
    assert_eq!(play(&bytes, far, x, y), frame0);
    assert_ne!(play(&bytes, 86_400_005, x, y), frame0);
}
