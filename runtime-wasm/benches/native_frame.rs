//! The studio's latero frame played natively: [`taxel_wasm::Session::latero_frame`],
//! the very function the WASM module's `taxel_latero_frame` export calls,
//! over the bundle and the positions that `tests/browser/bench.mjs` plays
//! in headless Chromium, so the two figures are of the same scene at the
//! same ticks and places (issue 42: the WASM frame at most 2x the native one).
//!
//! The scene comes from outside: `TAXEL_BENCH_BUNDLE` names a laterotactile
//! bundle and `TAXEL_BENCH_TRACE` a trace with one sample a tick (as
//! `bench.mjs` writes them, in `target/studio-bench/`); without them the
//! bench says so and measures nothing. `npm run bench` (in `tests/browser`)
//! writes both and runs this bench itself:
//!
//! `TAXEL_BENCH_BUNDLE=B TAXEL_BENCH_TRACE=T cargo bench --features bench --bench native_frame`
//!
//! One criterion iteration plays every tick of the trace, as one timed round
//! of the browser's does; the figure per frame is a sample's time over its
//! frames.

use std::hint::black_box;

use criterion::{Criterion, SamplingMode, Throughput, criterion_group, criterion_main};
use taxel_format::{BundleView, Tick};
use taxel_runtime::trace::Trace;
use taxel_wasm::Session;

fn scene() -> Option<(Vec<u8>, Vec<u8>)> {
    let bundle = std::env::var_os("TAXEL_BENCH_BUNDLE")?;
    let trace = std::env::var_os("TAXEL_BENCH_TRACE")?;
    let read = |p: &std::ffi::OsStr| std::fs::read(p).unwrap_or_else(|e| panic!("cannot read {}: {e}", p.display()));
    Some((read(&bundle), read(&trace)))
}

fn native_frame(c: &mut Criterion) {
    let Some((bundle, trace)) = scene() else {
        eprintln!("native_frame: set TAXEL_BENCH_BUNDLE and TAXEL_BENCH_TRACE (tests/browser/bench.mjs does)");
        return;
    };
    let rate = BundleView::parse(&bundle).expect("a valid bundle").manifest().profile.rate_hz;
    let mut session = Session::load(&bundle).expect("a bundle the studio plays");
    let trace = Trace::parse(&trace[..]).expect("a valid trace");
    // The positions as the page hands them to the module: f64 millimetres
    // rounded to f32 at the call, the tick a whole number.
    let points: Vec<(Tick, f32, f32)> = trace.ticks(rate).map(|(t, p)| (t, p.x_mm as f32, p.y_mm as f32)).collect();
    assert!(!points.is_empty(), "the trace has positions");
    assert!(!session.latero_frame(points[0].0, points[0].1, points[0].2).is_empty(), "a laterotactile bundle");
    // One iteration plays the whole sweep, as one of the browser's timed
    // rounds does, so every sample covers every position and its time over
    // the frames is comparable with a round's.
    let mut g = c.benchmark_group("studio_latero_frame_native");
    g.sampling_mode(SamplingMode::Flat).sample_size(20).throughput(Throughput::Elements(points.len() as u64));
    // The name is the folder bench.mjs reads the samples from
    // (`target/criterion/studio_latero_frame_native/sweep`).
    g.bench_function("sweep", |b| {
        b.iter(|| {
            let mut sum = 0u32;
            for &(t, x, y) in &points {
                sum = sum.wrapping_add(u32::from(session.latero_frame(black_box(t), black_box(x), black_box(y))[0]));
            }
            black_box(sum)
        })
    });
    g.finish();
}

criterion_group!(benches, native_frame);
criterion_main!(benches);
