//! The reader's cost: validating (`BundleView::parse`, every check of
//! SPEC.md section 3.4) a bundle of about 1 MB with every chunk kind,
//! reading its chunk views again after validation, and inflating its stored
//! form (SPEC.md section 15), which a host does once when it loads a file.
//!
//! `cargo bench -p taxel-format --features bench --bench reader -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use taxel_format::{
    Bundle, BundleView, Chunk, Dot, DotKind, DotTable, FIELD_CONTACT, HeightField, MaskKind, MaskLayer, MaskSamples,
    MilliHertz, Mm, sample,
};

/// About 1 MB: a 512 x 512 16-bit grating mask, a 256 x 256 8-bit vibration
/// mask, 12 000 outline dots, a 100 x 100 height field and the sample's
/// stroke table and provenance.
fn one_megabyte() -> Vec<u8> {
    let mut b: Bundle = sample::every_kind();
    let (w, h) = (512u32, 512u32);
    b.chunks.push(sample::grating_mask(w, h, (0..w * h).map(|k| (k % 65_536) as u16).collect()));
    b.chunks.push(Chunk::Mask(MaskLayer {
        source: None,
        kind: MaskKind::Vibration { freq: MilliHertz(50_000) },
        amplitude: 1.0,
        origin_x: Mm(5.0),
        origin_y: Mm(5.0),
        px_per_mm: 8.0,
        width: 256,
        height: 256,
        samples: MaskSamples::U8((0..256 * 256).map(|k| (k % 256) as u8).collect()),
    }));
    let dots = (0..12_000)
        .map(|k| Dot {
            x: Mm((k % 120) as f32 * 0.9),
            y: Mm((k / 120) as f32 * 0.6),
            radius: Mm(0.25),
            amplitude: 1.0,
            source: None,
        })
        .collect();
    b.chunks.push(Chunk::Dots(DotTable { kind: DotKind::Outline, dots }));
    let n = 100 * 100;
    b.chunks.push(Chunk::Height(HeightField {
        source: None,
        cols: 100,
        rows: 100,
        origin_x: Mm(0.0),
        origin_y: Mm(0.0),
        cell: Mm(1.0),
        gradient_cap: 10.0,
        heights: (0..n).map(|k| (k % 17) as f32 * 0.25).collect(),
        grad_x: (0..n).map(|k| (k % 7) as f32 * 0.5).collect(),
        grad_y: (0..n).map(|k| (k % 5) as f32 * -0.5).collect(),
        flags: vec![FIELD_CONTACT; n],
        encoding: taxel_format::HeightEncoding::Float,
    }));
    b.to_bytes().expect("the benchmark bundle is valid")
}

fn reader(c: &mut Criterion) {
    let big = one_megabyte();
    let smallest = Bundle::new(sample::tiny().manifest).to_bytes().expect("a manifest alone is valid");
    println!("bundle for validation: {} bytes; smallest valid bundle: {} bytes", big.len(), smallest.len());
    let mut g = c.benchmark_group("reader");
    g.throughput(Throughput::Bytes(big.len() as u64));
    g.bench_function("validate 1 MB bundle", |b| b.iter(|| BundleView::parse(black_box(&big)).is_ok()));
    let view = BundleView::parse(&big).expect("valid");
    g.bench_function("iterate chunk views after validation", |b| b.iter(|| black_box(view).chunks().count()));
    // The stored form (SPEC.md 15): inflating the file once when it is
    // loaded, beside validating the plain bundle it gives.
    let file = taxel_format::stored::store(&big).expect("the benchmark bundle stores");
    println!("stored form of the 1 MB bundle: {} bytes", file.len());
    let mut buf = vec![0u8; big.len()];
    g.bench_function("inflate the stored 1 MB bundle into a buffer", |b| {
        b.iter(|| taxel_format::stored::inflate_into(black_box(&file), &mut buf).is_ok())
    });
    g.finish();
    c.bench_function("validate smallest bundle", |b| b.iter(|| BundleView::parse(black_box(&smallest)).is_ok()));
}

criterion_group!(benches, reader);
criterion_main!(benches);
