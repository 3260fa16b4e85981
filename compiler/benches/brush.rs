//! Brushed-stroke compile cost on the 4 x 3 chair.
//!
//! - `plan/*`: the scheduling core ([`Planner::plan`]: virtual points,
//!   apparent-motion recurrence, stiff-case check, energy model) with its
//!   buffers reused, so it allocates nothing: this is the figure to hold under
//!   0.5 µs per straight stroke.
//! - `compile_strokes/*`: the whole public entry, which also builds the
//!   `StrokeTable` (the format's table owns a `Vec` of points and one of drives
//!   per point, so it allocates) and runs the shared-actuator check.
//!
//! `cargo bench -p taxel-compiler --features bench --bench brush -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use taxel_compiler::brush::{BrushRequest, GridGeometry, Planner, compile_strokes};
use taxel_format::profiles;

/// A straight stroke's two ends (page mm).
type Line = [(f64, f64); 2];

fn bench(c: &mut Criterion) {
    let grid = GridGeometry { rows: 3, cols: 4, pitch_x: 63.0, pitch_y: 63.0 };
    let strokes: [(&str, Line, f64); 4] = [
        ("diagonal_1s", [(0.0, 0.0), (189.0, 126.0)], 1000.0),
        ("row_1s", [(0.0, 63.0), (189.0, 63.0)], 1000.0),
        ("virtual_only_1s", [(31.5, 0.0), (157.5, 126.0)], 1000.0),
        ("stiff_diagonal_100ms", [(0.0, 0.0), (189.0, 126.0)], 100.0),
    ];
    let mut planner = Planner::new();
    for (name, line, t) in strokes {
        c.bench_function(&format!("plan/{name}"), |b| {
            b.iter(|| {
                let r = planner.plan(black_box(&line), black_box(t), 1.0, &grid, 1.0);
                black_box((r.is_ok(), planner.points().len()))
            })
        });
    }
    let profile = profiles::builtin("brush-4x3").unwrap();
    let req = BrushRequest {
        polyline: vec![(0.0, 0.0), (189.0, 126.0)],
        duration_ms: 1000.0,
        intensity: 0.8,
        freq_hz: 200.0,
        start_ms: None,
        source: None,
        element: "s".into(),
        line: None,
    };
    c.bench_function("compile_strokes/diagonal_1s", |b| {
        b.iter(|| {
            let mut diags = Vec::new();
            black_box(compile_strokes(black_box(std::slice::from_ref(&req)), &profile, &mut diags))
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
