//! Cost of one 64-actuator STRESS² frame: all three primitives active at
//! once, each alone, and dots in a scene of 1 dot against 10,000 dots; the
//! same with distance layers (one per style), and a distance layer of one
//! region against one of 5,000 regions (every tile of a 300 mm square stored);
//! fine tiles (format 4.4) under the array.
//!
//! Run briefly with
//! `cargo bench -p taxel-runtime --features bench --bench latero -- --warm-up-time 1 --measurement-time 3`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use taxel_format::{
    Bundle, BundleView, Chunk, DeviceProfile, DistanceLayer, Dot, DotKind, DotTable, Manifest, MaskKind, MaskLayer,
    MaskSamples, MilliHertz, Mm, Tick, profiles,
};
use taxel_runtime::latero::LateroPlayer;

/// Carrier position of every benchmark: the middle of the surface.
const X: f32 = 500.0;
const Y: f32 = 500.0;

fn bytes(chunks: Vec<Chunk>) -> Vec<u8> {
    // STRESS² on a 1 x 1 m surface, so that a large dot table fits without overlaps.
    let profile = DeviceProfile {
        surface_w_mm: 1000.0,
        surface_h_mm: 1000.0,
        ..profiles::builtin("stress2").expect("built-in profile")
    };
    let mut b = Bundle::new(Manifest::new(profile));
    b.chunks = chunks;
    b.to_bytes().expect("valid bundle")
}

/// A mask at 10 px/mm over `[x0, x0 + w) x [y0, y0 + h)` mm with a soft gradient.
fn mask(kind: MaskKind, x0: f32, y0: f32, w_mm: u32, h_mm: u32) -> Chunk {
    let (w, h) = (w_mm * 10, h_mm * 10);
    let samples = (0..w * h).map(|k| (128 + (k % w) * 127 / w) as u8).collect();
    Chunk::Mask(MaskLayer {
        source: None,
        kind,
        amplitude: 0.8,
        origin_x: Mm(x0),
        origin_y: Mm(y0),
        px_per_mm: 10.0,
        width: w,
        height: h,
        samples: MaskSamples::U8(samples),
    })
}

fn vibration(x0: f32, y0: f32, w: u32, h: u32) -> Chunk {
    mask(MaskKind::Vibration { freq: MilliHertz(50_000) }, x0, y0, w, h)
}

fn grating(x0: f32, y0: f32, w: u32, h: u32) -> Chunk {
    mask(MaskKind::Grating { wavelength: Mm(3.0), angle_deg: 30.0 }, x0, y0, w, h)
}

/// A distance layer (pitch 0.5 mm, hard edge) over `[x0, x0 + 4 cols) x
/// [y0, y0 + 4 rows)` mm whose tiles are all stored when `stored`, else only
/// the tiles under the carrier: the codes climb across each tile, so that
/// every actuator reads samples and lands between 0 and full amplitude.
fn field(kind: MaskKind, x0: f32, y0: f32, cols: u32, rows: u32, stored: bool) -> Chunk {
    field_of(kind, x0, y0, cols, rows, stored, false)
}

/// As [`field`], with plane tiles (format 3.0) instead of stored ones under
/// the carrier when `planes`: the same climbing codes as one record each.
fn field_of(kind: MaskKind, x0: f32, y0: f32, cols: u32, rows: u32, stored: bool, planes: bool) -> Chunk {
    field_with(kind, x0, y0, cols, rows, stored, planes, false, false)
}

/// As [`field_of`] with plane tiles, as corner tiles (format 4.0) when
/// `corners`: the lesser of the same climbing plane and a falling one, which
/// cross inside each tile; as bend tiles (format 4.0) when `bends`.
#[allow(clippy::too_many_arguments)]
fn field_with(
    kind: MaskKind,
    x0: f32,
    y0: f32,
    cols: u32,
    rows: u32,
    stored: bool,
    planes: bool,
    corners: bool,
    bends: bool,
) -> Chunk {
    let mut tiles = Vec::new();
    let mut samples = Vec::new();
    let mut records = Vec::new();
    for r in 0..rows {
        for c in 0..cols {
            let (tx, ty) = (x0 + 4.0 * c as f32, y0 + 4.0 * r as f32);
            let near = (tx - X).abs() < 16.0 && (ty - Y).abs() < 16.0;
            if bends && (stored || near) {
                // A band's centre line bent at the tile's middle.
                tiles.push(taxel_format::TILE_BEND | records.len() as u32);
                let (s, c) = 0.6f32.sin_cos();
                records.push(taxel_format::TilePlane { c: 4.0, gx: 4.0, gy: -1.0, top: 0.0 });
                records.push(taxel_format::TilePlane { c, gx: s, gy: 50.0, top: 300.0 });
            } else if corners && (stored || near) {
                tiles.push(taxel_format::TILE_CORNER | records.len() as u32);
                records.push(taxel_format::TilePlane { c: 100.0, gx: 7.0, gy: 3.0, top: 0.0 });
                records.push(taxel_format::TilePlane { c: 160.0, gx: -5.0, gy: 4.0, top: 0.0 });
            } else if planes && (stored || near) {
                tiles.push(taxel_format::TILE_PLANE | records.len() as u32);
                records.push(taxel_format::TilePlane { c: 100.0, gx: 7.0, gy: 3.0, top: 0.0 });
            } else if stored || near {
                tiles.push(2 + (samples.len() / 81) as u32);
                samples.extend((0..81u32).map(|k| (100 + (k % 9) * 7 + (k / 9) * 3) as u8));
            } else {
                tiles.push((c + r) % 2);
            }
        }
    }
    distance_layer(kind, (x0, y0), (cols, rows), tiles, records, samples)
}

/// As [`field`] with the tiles under the carrier as fine tiles (format
/// 4.4), `fine` times finer, in two channels where `pair`: the same climbing
/// codes in every sub-tile (the second channel falling), so that every
/// lane interpolates its fine cell, and the lesser of two where `pair`.
fn field_fine(kind: MaskKind, x0: f32, y0: f32, cols: u32, rows: u32, fine: u32, pair: bool) -> Chunk {
    let mut tiles = Vec::new();
    let mut samples = Vec::new();
    for r in 0..rows {
        for c in 0..cols {
            let (tx, ty) = (x0 + 4.0 * c as f32, y0 + 4.0 * r as f32);
            if (tx - X).abs() < 16.0 && (ty - Y).abs() < 16.0 {
                let first = (samples.len() / 81) as u32;
                tiles.push(taxel_format::fine_entry(first, fine, pair).expect("a fine entry"));
                for channel in 0..1 + pair as u32 {
                    for _ in 0..fine * fine {
                        samples.extend((0..81u32).map(|k| match channel {
                            0 => (100 + (k % 9) * 7 + (k / 9) * 3) as u8,
                            _ => (200 - (k % 9) * 5 - (k / 9) * 4) as u8,
                        }));
                    }
                }
            } else {
                tiles.push((c + r) % 2);
            }
        }
    }
    distance_layer(kind, (x0, y0), (cols, rows), tiles, vec![], samples)
}

/// A distance layer as the compiler writes one for a region with a straight
/// vertical edge (pitch 0.5 mm, hard edge) over `[x0, x0 + 4 cols) x [y0, y0
/// + 4 rows)` mm: the tiles wholly inside or outside are constant, and the
/// column of tiles `edge` holds the edge at its middle as one plane tile
/// each, inside to the left (`inside_left`) or to the right.
fn field_compiled(kind: MaskKind, x0: f32, y0: f32, cols: u32, rows: u32, edge: u32, inside_left: bool) -> Chunk {
    let mut tiles = Vec::new();
    let mut records = Vec::new();
    // 50 codes a lattice cell (0.5 mm over steps of 0.01 mm), code 128 at
    // the tile's middle (u = 4).
    let gx = if inside_left { -50.0 } else { 50.0 };
    for _ in 0..rows {
        for c in 0..cols {
            if c == edge {
                tiles.push(taxel_format::TILE_PLANE | records.len() as u32);
                records.push(taxel_format::TilePlane { c: 128.0 - 4.0 * gx, gx, gy: 0.0, top: 0.0 });
            } else {
                tiles.push(if (c < edge) == inside_left {
                    taxel_format::TILE_INSIDE
                } else {
                    taxel_format::TILE_OUTSIDE
                });
            }
        }
    }
    distance_layer(kind, (x0, y0), (cols, rows), tiles, records, vec![])
}

/// The benches' distance layers: pitch 0.5 mm, steps of 0.01 mm, a hard
/// edge, amplitude 0.8, with these tiles, records and samples.
fn distance_layer(
    kind: MaskKind,
    (x0, y0): (f32, f32),
    (cols, rows): (u32, u32),
    tiles: Vec<u32>,
    planes: Vec<taxel_format::TilePlane>,
    samples: Vec<u8>,
) -> Chunk {
    Chunk::Distance(DistanceLayer {
        kind,
        amplitude: 0.8,
        soft_mm: 0.0,
        step_mm: 0.01,
        origin_x: Mm(x0),
        origin_y: Mm(y0),
        pitch_mm: 0.5,
        tile_cols: cols,
        tile_rows: rows,
        sources: vec![],
        tiles,
        planes,
        samples,
    })
}

const VIBRATE: MaskKind = MaskKind::Vibration { freq: MilliHertz(50_000) };
const GRATE: MaskKind = MaskKind::Grating { wavelength: Mm(3.0), angle_deg: 30.0 };

fn dots(list: impl IntoIterator<Item = (f32, f32)>) -> Chunk {
    let dots = list.into_iter().map(|(x, y)| Dot { x: Mm(x), y: Mm(y), radius: Mm(1.0), amplitude: 1.0, source: None });
    Chunk::Dots(DotTable { kind: DotKind::Outline, dots: dots.collect() })
}

/// 10,000 dots of radius 1 mm on a 100 x 100 lattice `pitch` mm apart, one of
/// them at the carrier position.
fn lattice(pitch: f32) -> Chunk {
    let (x0, y0) = (X - 50.0 * pitch, Y - 50.0 * pitch);
    dots((0..100).flat_map(|i| (0..100).map(move |j| (x0 + pitch * i as f32, y0 + pitch * j as f32))))
}

fn bench_scene(c: &mut Criterion, name: &str, chunks: Vec<Chunk>) {
    let bytes = bytes(chunks);
    let view = BundleView::parse(&bytes).expect("valid bundle");
    let player = LateroPlayer::new(&view).expect("laterotactile bundle");
    let mut out = [0u16; 64];
    let mut tick = 0u64;
    c.bench_function(name, |b| {
        b.iter(|| {
            tick += 1;
            // Small movements so that positions vary like a real exploration.
            let dx = (tick % 16) as f32 * 0.01;
            black_box(player.frame(Tick(tick), Mm(black_box(X + dx)), Mm(black_box(Y)), &mut out));
        })
    });
}

fn latero(c: &mut Criterion) {
    // All three at once: a vibrating region on the left half of the array,
    // a grated region on the right half, and two dots on the boundary.
    bench_scene(
        c,
        "latero frame: vibration + grating + dots",
        vec![vibration(X - 10.0, Y - 10.0, 10, 20), grating(X, Y - 10.0, 10, 20), dots([(X, Y - 2.0), (X, Y + 2.0)])],
    );
    // The same with distance layers.
    bench_scene(
        c,
        "latero frame (distance): vibration + grating + dots",
        vec![
            field(VIBRATE, X - 12.0, Y - 12.0, 3, 6, true),
            field(GRATE, X, Y - 12.0, 3, 6, true),
            dots([(X, Y - 2.0), (X, Y + 2.0)]),
        ],
    );
    // The same regions as the compiler writes them: constant tiles inside
    // and outside, and plane tiles along the two straight edges under the
    // array (their layers play the kernel instance with analytic lanes).
    bench_scene(
        c,
        "latero frame (distance, as compiled): vibration + grating + dots",
        vec![
            field_compiled(VIBRATE, X - 12.0, Y - 12.0, 3, 6, 2, true),
            field_compiled(GRATE, X, Y - 12.0, 3, 6, 0, false),
            dots([(X, Y - 2.0), (X, Y + 2.0)]),
        ],
    );
    bench_scene(c, "latero frame (distance): vibration alone", vec![field(VIBRATE, X - 12.0, Y - 12.0, 6, 6, true)]);
    bench_scene(c, "latero frame (distance): grating alone", vec![field(GRATE, X - 12.0, Y - 12.0, 6, 6, true)]);
    bench_scene(
        c,
        "latero frame (distance): plane tiles, vibration and grating",
        vec![field_of(VIBRATE, X - 12.0, Y - 12.0, 3, 6, true, true), field_of(GRATE, X, Y - 12.0, 3, 6, true, true)],
    );
    bench_scene(
        c,
        "latero frame (distance): corner tiles, vibration and grating",
        vec![
            field_with(VIBRATE, X - 12.0, Y - 12.0, 3, 6, true, true, true, false),
            field_with(GRATE, X, Y - 12.0, 3, 6, true, true, true, false),
        ],
    );
    bench_scene(
        c,
        "latero frame (distance): bend tiles, vibration and grating",
        vec![
            field_with(VIBRATE, X - 12.0, Y - 12.0, 3, 6, true, true, false, true),
            field_with(GRATE, X, Y - 12.0, 3, 6, true, true, false, true),
        ],
    );
    // Fine tiles (format 4.4) under the array: one channel 4 times finer,
    // and two channels twice as fine.
    for (name, fine, pair) in [("one channel x4", 4, false), ("two channels x2", 2, true)] {
        bench_scene(
            c,
            &format!("latero frame (distance): fine tiles, {name}, vibration and grating"),
            vec![
                field_fine(VIBRATE, X - 12.0, Y - 12.0, 3, 6, fine, pair),
                field_fine(GRATE, X, Y - 12.0, 3, 6, fine, pair),
            ],
        );
    }
    // Frame-cost independence: the same two styles over one region (the
    // tiles near the carrier stored, the rest flags) and over 5,000 regions
    // (all 5,625 tiles of a 300 mm square stored, 456 kB per layer).
    for (name, stored) in [("1 region", false), ("5,000 regions", true)] {
        bench_scene(
            c,
            &format!("latero frame (distance): vibration + grating, {name}"),
            vec![
                field(VIBRATE, X - 150.0, Y - 150.0, 75, 75, stored),
                field(GRATE, X - 150.0, Y - 150.0, 75, 75, stored),
            ],
        );
    }
    bench_scene(c, "latero frame: vibration alone", vec![vibration(X - 10.0, Y - 10.0, 20, 20)]);
    bench_scene(c, "latero frame: grating alone", vec![grating(X - 10.0, Y - 10.0, 20, 20)]);
    bench_scene(c, "latero frame: 1 dot", vec![dots([(X, Y)])]);
    // The same dot under the array among 9,999 others 10 mm apart, out of
    // its reach: the cost must match the single dot's.
    bench_scene(c, "latero frame: 10,000 dots (1 under the array)", vec![lattice(10.0)]);
    // A page dense with dots 2.5 mm apart (about 16 under the array): the
    // cost follows the dots near the array, not the table's size.
    bench_scene(c, "latero frame: 10,000 dots (2.5 mm apart)", vec![lattice(2.5)]);
}

criterion_group!(benches, latero);
criterion_main!(benches);
