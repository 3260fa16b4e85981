//! Cost of one finger-player sample: field lookup (bilinear over four
//! nodes), direction window update, actuator choice, intensity and rhythm,
//! on the same field stored as 4.0 (`f32` heights and gradients, 13 bytes a
//! node) and tiled (format 4.6: quantised heights in tiles, each code
//! predicted from its neighbours, a tile decoded when the finger reaches
//! it, the gradient derived from the cell's four heights), side by side in
//! one run.
//!
//! Run briefly with
//! `cargo bench -p taxel-runtime --features bench --bench finger -- --warm-up-time 1 --measurement-time 3`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use taxel_format::{
    Bundle, BundleView, Chunk, FIELD_CONTACT, HeightEncoding, HeightField, Manifest, Mm, Tick, profiles,
};
use taxel_runtime::finger::{FingerPlayer, Touch};

/// A 120 x 60 mm convex cap sampled every 0.5 mm (the size of the paper's
/// shapes), stored as 4.0 or (`tiled`) in format 4.6's tiles with a
/// 0.0005 mm step.
fn bytes(tiled: bool) -> Vec<u8> {
    let (cols, rows, cell) = (241u32, 121u32, 0.5f32);
    let n = (cols * rows) as usize;
    let mut f = HeightField {
        source: None,
        cols,
        rows,
        origin_x: Mm(20.0),
        origin_y: Mm(20.0),
        cell: Mm(cell),
        gradient_cap: 1.0,
        heights: vec![0.0; n],
        grad_x: vec![0.0; n],
        grad_y: vec![0.0; n],
        flags: vec![FIELD_CONTACT; n],
        encoding: taxel_format::HeightEncoding::Float,
    };
    for j in 0..rows {
        for i in 0..cols {
            let k = (j * cols + i) as usize;
            let (u, v) = ((i as f32 * cell - 60.0) / 60.0, (j as f32 * cell - 30.0) / 30.0);
            f.heights[k] = 35.0 - 20.0 * u * u - 10.0 * v * v;
            f.grad_x[k] = -40.0 * u / 60.0;
            f.grad_y[k] = -20.0 * v / 30.0;
        }
    }
    if tiled {
        f.encoding = HeightEncoding::Tiled { step: 0.0005, base: 5.0, max_gradient: 0.9 };
    }
    let mut b = Bundle::new(Manifest::new(profiles::builtin("finger3").expect("built-in profile")));
    b.chunks.push(Chunk::Height(f));
    b.to_bytes().expect("valid bundle")
}

fn bench(c: &mut Criterion) {
    // A wavy sweep across the shape, as touch events.
    let touches: Vec<Touch> = (0..1024u64)
        .map(|k| Touch {
            tick: Tick(k),
            x: Mm(15.0 + 0.13 * k as f32),
            y: Mm(50.0 + 8.0 * (k as f32 * 0.05).sin()),
            contact: k % 300 != 299,
        })
        .collect();
    for (name, tiled) in [("finger sample", false), ("finger sample, tiled field", true)] {
        let bytes = bytes(tiled);
        let view = BundleView::parse(&bytes).expect("valid bundle");
        let mut player = FingerPlayer::new(&view).expect("finger bundle");
        let mut k = 0usize;
        c.bench_function(name, |b| {
            b.iter(|| {
                let t = touches[k & 1023];
                k += 1;
                black_box(player.sample(black_box(t)))
            })
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
