//! Compile time per shape of generated real-size drawings (issue 14): a map of
//! 10, 100, 1,000 and 10,000 touching polygon regions with labels and towns
//! (an Inkscape map with many layers), and a city plan of as many ways (an
//! OpenStreetMap export), both unannotated (the automatic style sheet) and
//! fitted to the stress2 surface. Criterion's throughput is per shape, so the
//! rows compare directly: the time per shape must stay within 2x from 100 to
//! 10,000. The 10,000-region map is the drawing that once took minutes (the
//! design rules compared all pairs).
//!
//! `cargo bench -p taxel-compiler --features bench --bench real_drawings -- --warm-up-time 1 --measurement-time 5`

use criterion::{BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group, criterion_main};
use taxel_compiler::{CompileOptions, compile_svg};
use taxel_format::profiles;

#[path = "drawings/mod.rs"]
mod drawings;

fn bench(c: &mut Criterion) {
    let opts =
        CompileOptions { fit: true, ..CompileOptions::new(profiles::builtin("stress2").expect("built-in profile")) };
    for (name, make) in [
        ("map regions", (|n| drawings::inkscape_map(n, 8, 7)) as fn(usize) -> String),
        ("city plan ways", |n| drawings::city_plan(n, 7)),
    ] {
        let mut g = c.benchmark_group(name);
        g.sampling_mode(SamplingMode::Flat).sample_size(10);
        for n in [10usize, 100, 1_000, 10_000] {
            let svg = make(n);
            // Checked once beside the measurement (the largest only by being measured).
            if n <= 1_000 {
                let out = compile_svg(&svg, &opts);
                let errors: Vec<_> =
                    out.diagnostics.iter().filter(|d| d.severity == taxel_compiler::Severity::Error).collect();
                assert!(out.bundle.is_some(), "{name} {n}: {errors:?}");
            }
            g.throughput(Throughput::Elements(n as u64));
            g.bench_with_input(BenchmarkId::from_parameter(n), &svg, |b, svg| b.iter(|| compile_svg(svg, &opts)));
        }
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
