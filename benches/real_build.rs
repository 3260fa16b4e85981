//! Whole-process `taxel build --fit` of a real-size drawing beside resvg's own
//! render of the same file to a PNG, measured side by side in one run
//! (issue 14: at most 2x). The drawing is a generated Inkscape map of 1,000
//! touching regions with labels and towns, over 1 MB of SVG, unannotated (so
//! the automatic style sheet decides every style), built for stress2.
//!
//! resvg's side is everything its command line does, in this process: load
//! the system fonts (the map has text), parse, render, encode the PNG and
//! write it. It renders at the bundle's 10 px/mm at the size the drawing has
//! once fitted to the surface (the pixels taxel's masks cover), and, for
//! reference, at the drawing's own 529 mm width.
//!
//! `cargo bench --bench real_build -- --warm-up-time 1 --measurement-time 10`

use std::path::Path;
use std::process::Command;

use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};

#[path = "../compiler/benches/drawings/mod.rs"]
mod drawings;

const PX_PER_MM: f32 = 10.0;

fn resvg_png(svg: &str, width_px: u32, out: &Path) {
    let mut db = resvg::usvg::fontdb::Database::new();
    db.load_system_fonts();
    let opt = resvg::usvg::Options { fontdb: std::sync::Arc::new(db), ..resvg::usvg::Options::default() };
    let tree = resvg::usvg::Tree::from_str(svg, &opt).expect("the map parses");
    let k = width_px as f32 / tree.size().width();
    let h = (tree.size().height() * k).ceil() as u32;
    let mut pixmap = resvg::tiny_skia::Pixmap::new(width_px, h).expect("pixmap");
    resvg::render(&tree, resvg::tiny_skia::Transform::from_scale(k, k), &mut pixmap.as_mut());
    pixmap.save_png(out).expect("png written");
}

fn bench(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temp dir");
    let svg = drawings::inkscape_map(1_000, 16, 11);
    assert!(svg.len() > 1 << 20, "the map is {} bytes, under 1 MB", svg.len());
    let input = dir.path().join("map.svg");
    std::fs::write(&input, &svg).expect("map written");
    let bundle = dir.path().join("map.taxel");
    let taxel = env!("CARGO_BIN_EXE_taxel");
    let build = || {
        let out = Command::new(taxel)
            .args(["build", "--fit", "--force", "-o"])
            .arg(&bundle)
            .arg(&input)
            .output()
            .expect("taxel runs");
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        out
    };
    let first = build();
    eprintln!(
        "taxel build --fit said:\n{}{}",
        String::from_utf8_lossy(&first.stderr),
        String::from_utf8_lossy(&first.stdout)
    );
    // Fitted to 110 x 60 mm, the 529 x ~509 mm map is about 62 mm wide.
    let fitted_mm = 60.0 * 529.0 / (529.0 * drawings_aspect(&svg));
    let png = dir.path().join("map.png");
    let mut g = c.benchmark_group("real-size map (1,000 regions, over 1 MB)");
    g.sampling_mode(SamplingMode::Flat).sample_size(10);
    g.bench_function("taxel build --fit (whole process)", |b| b.iter(build));
    g.bench_function("resvg to PNG at 10 px/mm, fitted size", |b| {
        b.iter(|| resvg_png(&svg, (fitted_mm * PX_PER_MM as f64).ceil() as u32, &png))
    });
    g.bench_function("resvg to PNG at 10 px/mm, own size (529 mm)", |b| {
        b.iter(|| resvg_png(&svg, (529.0 * PX_PER_MM) as u32, &png))
    });
    g.finish();
}

/// Height over width of the generated map's page.
fn drawings_aspect(svg: &str) -> f64 {
    let grab = |key: &str| -> f64 {
        let i = svg.find(key).expect("size attribute") + key.len();
        svg[i..].split('"').next().and_then(|v| v.trim_end_matches("mm").parse().ok()).expect("a number")
    };
    grab("height=\"") / grab("width=\"")
}

criterion_group!(benches, bench);
criterion_main!(benches);
