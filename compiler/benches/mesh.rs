//! Build time of a height field from a glTF mesh of about 100,000 triangles
//! (a 224 x 224 quad grid of a wavy 120 mm terrain): parse, triangulate with
//! spade, find covers and steps, sample at the default resolution.
//!
//! Run briefly with
//! `cargo bench -p taxel-compiler --bench mesh -- --warm-up-time 1 --measurement-time 3`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use taxel_compiler::mesh::write::HeightMesh;
use taxel_compiler::mesh::{self, MeshOptions};

fn bench(c: &mut Criterion) {
    let n = 224;
    let m = HeightMesh::grid(n, n, |u, v| {
        let h = 0.01 + 0.004 * (6.0 * u).sin() * (4.0 * v).cos();
        [0.12 * u, h, 0.12 * v]
    });
    let glb = m.to_glb();
    let triangles = m.indices.len() / 3;
    let mut g = c.benchmark_group("mesh");
    g.sample_size(10);
    g.bench_function(format!("height field from {triangles} triangles"), |b| {
        b.iter(|| {
            let r = mesh::height_field(black_box(&glb), &mut |_| Err("none".into()), &MeshOptions::default());
            black_box(r.map(|(f, _)| f.cols))
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
