//! Compile time of a typical map (an Inkscape drawing of an island with three
//! grated provinces, vibrating coast and borders, towns, a key and braille
//! labels) beside resvg's own render of the same SVG at the same resolution
//! (10 px/mm, the default mask resolution), in the same run.
//!
//! `cargo bench -p taxel-compiler --features bench --bench compile -- --warm-up-time 1 --measurement-time 3`

use criterion::{Criterion, criterion_group, criterion_main};
use taxel_compiler::{CompileOptions, DEFAULT_PX_PER_MM, compile_svg};
use taxel_format::profiles;

const MAP: &str = include_str!("map.svg");

fn bench(c: &mut Criterion) {
    let opts = CompileOptions::new(profiles::builtin("stress2").expect("built-in profile"));
    let compiled = compile_svg(MAP, &opts);
    assert!(compiled.bundle.is_some(), "{:?}", compiled.diagnostics);

    let mut g = c.benchmark_group("typical map");
    g.bench_function("taxel compile_svg (stress2, 10 px/mm)", |b| b.iter(|| compile_svg(MAP, &opts)));

    // resvg: parse with usvg and render the whole page at the same resolution.
    let uopt = usvg::Options::default();
    let tree = usvg::Tree::from_str(MAP, &uopt).expect("map parses");
    // The map is 110 mm wide; usvg's size is in CSS px (96 per inch).
    let k = (DEFAULT_PX_PER_MM as f64 * 25.4 / 96.0) as f32;
    let (w, h) = ((tree.size().width() * k).ceil() as u32, (tree.size().height() * k).ceil() as u32);
    g.bench_function("resvg parse + render (10 px/mm)", |b| {
        b.iter(|| {
            let tree = usvg::Tree::from_str(MAP, &uopt).expect("map parses");
            let mut pixmap = resvg::tiny_skia::Pixmap::new(w, h).expect("pixmap");
            resvg::render(&tree, resvg::tiny_skia::Transform::from_scale(k, k), &mut pixmap.as_mut());
            pixmap
        })
    });
    g.finish();

    // Size, measured once: the bundle beside the 8-bit grayscale PNG of the
    // same page at the same resolution (what an embosser workflow would store).
    let bundle_bytes = compiled.bundle.as_ref().and_then(|b| b.to_bytes().ok()).map_or(0, |b| b.len());
    // The file `taxel build` writes: the stored form (SPEC.md 15).
    let file_bytes = compiled.bundle.as_ref().and_then(|b| b.to_stored_bytes().ok()).map_or(0, |b| b.len());
    let mut pixmap = resvg::tiny_skia::Pixmap::new(w, h).expect("pixmap");
    pixmap.fill(resvg::tiny_skia::Color::WHITE);
    resvg::render(&tree, resvg::tiny_skia::Transform::from_scale(k, k), &mut pixmap.as_mut());
    let gray: Vec<u8> = pixmap
        .data()
        .chunks_exact(4)
        .map(|p| ((p[0] as u32 * 299 + p[1] as u32 * 587 + p[2] as u32 * 114) / 1000) as u8)
        .collect();
    // As the `image` crate writes an 8-bit gray PNG by default: fast compression, adaptive filters.
    use taxel_textform::png::{BitDepth, ColorType, Compression, write};
    let png = write(w, h, ColorType::Grayscale, BitDepth::Eight, &gray, Compression::Fast).expect("png");
    let png_bytes = png.len();
    eprintln!(
        "typical map: bundle {bundle_bytes} bytes, its file {file_bytes} bytes, 8-bit PNG {w}x{h} {png_bytes} bytes, ratios {:.2} and {:.3}",
        bundle_bytes as f64 / png_bytes as f64,
        file_bytes as f64 / png_bytes as f64
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
