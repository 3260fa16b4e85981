//! Grid player cost: one frame (every actuator's amplitude and carrier) per
//! tick, and per audio sample (the WAV sink's envelope plus 12 carriers).
//!
//! `cargo bench -p taxel-runtime --features bench --bench grid -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;
use std::io::Cursor;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use taxel_format::{
    ActuatorIndex, Bundle, BundleView, Chunk, Drive, Manifest, MilliHertz, Mm, Stroke, StrokePoint, StrokeTable, Tick,
    profiles,
};
use taxel_runtime::grid::{ActuatorDrive, GridPlayer};
use taxel_runtime::sinks::wav::{SampleBits, write_wav};

/// The paper's diagonal over 1 s on the chair (5 points, 2 drives in the middle),
/// repeated `n` times one after another.
fn bundle(n: u64) -> Vec<u8> {
    let pts = [
        (0u32, 72u32, vec![(0u16, 1.0f32)]),
        (70, 330, vec![(1, 0.577), (5, 0.816)]),
        (245, 594, vec![(5, 0.707), (6, 0.707)]),
        (483, 517, vec![(6, 0.816), (10, 0.577)]),
        (709, 291, vec![(11, 1.0)]),
    ];
    let strokes = (0..n)
        .map(|i| Stroke {
            start: Tick(i * 1000),
            duration: 1000,
            carrier: MilliHertz(200_000),
            intensity: 1.0,
            source: None,
            points: pts
                .iter()
                .map(|(on, d, drives)| StrokePoint {
                    onset: *on,
                    duration: *d,
                    peak: *on,
                    x: Mm(0.0),
                    y: Mm(0.0),
                    drives: drives.iter().map(|&(a, v)| Drive { actuator: ActuatorIndex(a), intensity: v }).collect(),
                })
                .collect(),
        })
        .collect();
    let mut b = Bundle::new(Manifest::new(profiles::builtin("brush-4x3").unwrap()));
    b.chunks.push(Chunk::Strokes(StrokeTable { strokes }));
    b.to_bytes().unwrap()
}

fn bench(c: &mut Criterion) {
    for n in [1u64, 20] {
        let bytes = bundle(n);
        let view = BundleView::parse(&bytes).unwrap();
        let player = GridPlayer::new(&view).unwrap();
        let mut out = [ActuatorDrive::default(); 12];
        let mut t = 0u64;
        c.bench_function(&format!("frame/{n}_strokes"), |b| {
            b.iter(|| {
                t = (t + 7) % (n * 1000);
                black_box(player.frame(Tick(black_box(t)), &mut out))
            })
        });
    }
    let bytes = bundle(1);
    let view = BundleView::parse(&bytes).unwrap();
    let player = GridPlayer::new(&view).unwrap();
    let mut g = c.benchmark_group("wav");
    g.throughput(Throughput::Elements(48_000));
    g.sample_size(10);
    g.bench_function("one_second_12_channels", |b| {
        b.iter(|| {
            let mut cur = Cursor::new(Vec::with_capacity(48_000 * 24 + 128));
            black_box(write_wav(&mut cur, &player, SampleBits::Sixteen).unwrap())
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
