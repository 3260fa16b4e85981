//! Build time of a height field from glTF meshes of about 100,000 triangles:
//! parse, arrange the projected edges, triangulate with spade, find covers
//! and steps, sample at the default resolution.
//!
//! - a 224 x 224 quad grid of a wavy 120 mm terrain (100,352 triangles, one
//!   mesh, no crossing edges: the bulk load takes every edge at once);
//! - a city of 8,192 closed blocks (98,304 triangles) on a turned grid,
//!   touching and overlapping in every row, so the arrangement splits
//!   collinear walls, T-junctions and crossings before the bulk load.
//!
//! - a 179 x 179 quad grid of a 4 km terrain 200 m high (64,082 triangles,
//!   +Y up), built with the right axis (seen from above) and with `--up z`
//!   (seen edge on: every column of quads projects onto one thin strip, and
//!   the triangles overlap many deep), both fitted to the surface: the wrong
//!   axis must cost no more than the right one.
//!
//! Run briefly with
//! `cargo bench -p taxel-compiler --features bench --bench mesh -- --warm-up-time 1 --measurement-time 3`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use taxel_compiler::UpAxis;
use taxel_compiler::mesh::write::HeightMesh;
use taxel_compiler::mesh::{self, MeshOptions};

/// A closed block `w` x `d` x `h` (metres) at `(x, z)`, turned by `a` about +Y.
fn block(x: f64, z: f64, w: f64, d: f64, h: f64, a: f64) -> HeightMesh {
    let (c, s) = (a.cos(), a.sin());
    let mut m = HeightMesh::default();
    for y in [0.0, h] {
        for (u, v) in [(0.0, 0.0), (w, 0.0), (w, d), (0.0, d)] {
            m.positions.push([(x + c * u - s * v) as f32, y as f32, (z + s * u + c * v) as f32]);
        }
    }
    m.indices.extend([0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7]);
    for k in 0..4u32 {
        let n = (k + 1) % 4;
        m.indices.extend([k, n, 4 + n, k, 4 + n, 4 + k]);
    }
    m
}

fn bench(c: &mut Criterion) {
    let n = 224;
    let terrain = HeightMesh::grid(n, n, |u, v| {
        let h = 0.01 + 0.004 * (6.0 * u).sin() * (4.0 * v).cos();
        [0.12 * u, h, 0.12 * v]
    });
    let mut city = HeightMesh::default();
    for k in 0..8192u32 {
        let (gx, gz) = ((k % 128) as f64, (k / 128) as f64);
        // Odd rows shifted by 37 % of a block: walls overlap in part and end on each other.
        let (u, v) = (10.0 * gx + if k / 128 % 2 == 1 { 3.7 } else { 0.0 }, 10.0 * gz);
        let a: f64 = 0.3;
        let (x, z) = (u * a.cos() - v * a.sin(), u * a.sin() + v * a.cos());
        city.append(&block(x, z, 10.0, 10.0, 5.0 + (k * 7 % 11) as f64, a));
    }
    let mut g = c.benchmark_group("mesh");
    g.sample_size(10);
    for (name, m) in [("terrain", terrain), ("city", city)] {
        let glb = m.to_glb();
        let triangles = m.indices.len() / 3;
        g.bench_function(format!("{name}: height field from {triangles} triangles"), |b| {
            b.iter(|| {
                let r = mesh::height_field(black_box(&glb), &mut |_| Err("none".into()), &MeshOptions::default());
                black_box(r.map(|(f, _)| f.cols))
            })
        });
    }
    let n = 179;
    let dem = HeightMesh::grid(n, n, |u, v| {
        let h = 100.0 + 60.0 * (7.0 * u).sin() * (5.0 * v).cos() + 25.0 * (23.0 * u + 3.0).sin() * (19.0 * v).sin();
        [4000.0 * u, h, 4000.0 * v]
    });
    let glb = dem.to_glb();
    let triangles = dem.indices.len() / 3;
    for (axis, up) in [("+Y up, seen from above", UpAxis::Y), ("--up z, seen edge on", UpAxis::Z)] {
        let opts = MeshOptions { up: Some(up), fit: Some([160.0, 100.0]), ..MeshOptions::default() };
        g.bench_function(format!("dem: {triangles} triangles, {axis}"), |b| {
            b.iter(|| {
                let r = mesh::height_field(black_box(&glb), &mut |_| Err("none".into()), &opts);
                black_box(r.map(|(f, _)| f.cols))
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
