//! The point lookup's cost: building the index over 2,000 region footprints
//! and 2,000 lines, and one `under` query, side by side with a scan that
//! tests every shape (what the index saves).
//!
//! `cargo bench -p taxel-format --features bench --bench lookup -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use taxel_format::lookup::PointLookup;
use taxel_format::{
    Bundle, BundleView, Chunk, Footprint, FootprintKind, Footprints, Provenance, ProvenanceEntry, sample,
};

/// 2,000 squares of 1 x 1.5 mm (hexagon-like 6-point rings) in a 80 x 25 grid
/// and a 40-point polyline beside each row of them.
fn scene() -> Vec<u8> {
    let mut b: Bundle = Bundle::new(sample::tiny().manifest);
    let mut shapes = Vec::new();
    let mut entries = Vec::new();
    for j in 0..25u16 {
        for i in 0..80u16 {
            let (x, y) = (100 + i * 135, 100 + j * 230);
            let ring = vec![(x, y), (x + 50, y), (x + 100, y), (x + 100, y + 150), (x + 50, y + 150), (x, y + 150)];
            shapes.push(Footprint {
                source: entries.len() as u32,
                kind: FootprintKind::AreaNonZero,
                half_width: 0,
                rings: vec![ring],
            });
            entries.push(ProvenanceEntry { id: format!("r{i}-{j}"), label: String::new(), line: 0 });
        }
        let line = (0..40u16).map(|k| (100 + k * 270, 100 + j * 230 + 190 + (k % 2) * 10)).collect();
        shapes.push(Footprint { source: 0, kind: FootprintKind::Line, half_width: 5, rings: vec![line] });
    }
    b.chunks.push(Chunk::Provenance(Provenance { entries }));
    b.chunks.push(Chunk::Footprints(Footprints { origin_x: 0.0, origin_y: 0.0, quantum_mm: 0.01, shapes }));
    b.to_bytes().expect("a valid bundle")
}

fn bench(c: &mut Criterion) {
    let bytes = scene();
    let view = BundleView::parse(&bytes).expect("valid");
    let lookup = PointLookup::new(&view, PointLookup::DEFAULT_TOLERANCE_MM).expect("footprints");
    let probes: Vec<(f64, f64)> =
        (0..64).map(|k| (1.0 + (k as f64 * 1.7) % 108.0, 1.0 + (k as f64 * 0.9) % 58.0)).collect();
    let mut g = c.benchmark_group("lookup");
    g.bench_function("build index, 2,025 shapes", |b| {
        b.iter(|| PointLookup::new(black_box(&view), PointLookup::DEFAULT_TOLERANCE_MM))
    });
    g.bench_function("under, 64 points, R-tree", |b| {
        b.iter(|| probes.iter().filter(|&&(x, y)| lookup.under(black_box(x), black_box(y)).is_some()).count())
    });
    g.bench_function("under, 64 points, scan of every shape", |b| {
        b.iter(|| {
            probes
                .iter()
                .filter(|&&(x, y)| (0..lookup.len()).rev().any(|i| lookup.covers(i, black_box(x), black_box(y))))
                .count()
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
