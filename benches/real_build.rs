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
//! A second group builds the largest drawings under the 64 MB input limit
//! (`src/io/read.rs`), a map and a city plan just under it, whole process,
//! for the rule that no drawing under the limit takes more than 10 s. Each
//! build takes long; run it alone with `-- 'input limit'`, or leave it out
//! with `-- real-size`. With `TAXEL_KEEP_DRAWINGS=DIR` the two drawings are
//! also written to DIR, to time `taxel build --fit` on them by hand.
//!
//! A third group, `runaway`, builds the drawings of issue 47 at its sizes
//! (a self-crossing scribble of 3,000 to 300,000 segments, unannotated and
//! annotated, 20,000 and 100,000 scatter marks, a jittered ring of 300,000
//! points), whole process, beside resvg's render of each at 1,100 px
//! wide: `-- runaway` (`TAXEL_KEEP_DRAWINGS=DIR` keeps them too, for their
//! peak memory by hand). resvg takes minutes on the 300,000-segment
//! scribbles: leave those out with
//! `-- 'runaway/(.*scribble [0-9,]+: taxel|.*scribble (3,000|30,000): resvg|scatter|ring)'`.
//!
//! A fourth group, `issue 46`, builds the shapes issue 46 found slow on
//! public drawings (`drawings/world.rs`): a world map of 2,200 tiny islands
//! and a few landmasses, a world map of 300 states with long shared wiggly
//! borders, subway plans of 700 and 900 ways crossing each other, and the
//! 380-region city map, each `taxel build --fit -p stress2` (whole process)
//! beside resvg's render of the same file at the width it has once fitted to
//! the surface, at 10 px/mm: `-- 'issue 46'`. `TAXEL_KEEP_DRAWINGS=DIR`
//! writes them to DIR too.
//!
//! `cargo bench --features bench --bench real_build -- --warm-up-time 1 --measurement-time 10`

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
    issue46(c, dir.path(), taxel);
    near_the_limit(c, dir.path(), taxel);
    runaway(c, dir.path(), taxel);
}

/// The stress2 surface, mm.
const STRESS2_MM: (f64, f64) = (110.0, 60.0);

/// The width in pixels at 10 px/mm of drawing `svg` fitted to a `surface`
/// (its aspect kept, as `--fit` does).
fn fitted_px(svg: &str, surface: (f64, f64)) -> u32 {
    let tree = resvg::usvg::Tree::from_str(svg, &resvg::usvg::Options::default()).expect("the drawing parses");
    let (w, h) = (tree.size().width() as f64, tree.size().height() as f64);
    let mm = if h / w > surface.1 / surface.0 { surface.1 * w / h } else { surface.0 };
    (mm * PX_PER_MM as f64).ceil() as u32
}

/// Issue 46's shapes: `taxel build --fit -p stress2` (whole process) beside
/// resvg's render at the fitted width.
fn issue46(c: &mut Criterion, dir: &Path, taxel: &str) {
    let cases: Vec<(&str, &str, String)> = vec![
        ("archipelago (2,200 islands)", "archipelago.svg", drawings::archipelago(12, 2_200, 46)),
        ("world states (300, 40 points a border)", "states.svg", drawings::world_states(300, 40, 46)),
        ("subway plan (700 ways)", "subway.svg", drawings::subway_plan(12, 700, 46)),
        ("subway plan (900 ways)", "subway900.svg", drawings::subway_plan(16, 900, 47)),
        ("city map (380 regions)", "city380.svg", drawings::inkscape_map(380, 16, 46)),
    ];
    let mut g = c.benchmark_group("issue 46");
    g.sampling_mode(SamplingMode::Flat).sample_size(10);
    for (name, file, svg) in &cases {
        let input = dir.join(file);
        std::fs::write(&input, svg).expect("drawing written");
        if let Some(keep) = std::env::var_os("TAXEL_KEEP_DRAWINGS") {
            std::fs::write(Path::new(&keep).join(file), svg).expect("kept drawing written");
        }
        let bundle = dir.join("issue46.taxel");
        g.bench_function(format!("{name}: taxel build --fit -p stress2"), |b| {
            b.iter(|| {
                let out = Command::new(taxel)
                    .args(["build", "--fit", "-p", "stress2", "--force", "-o"])
                    .arg(&bundle)
                    .arg(&input)
                    .output()
                    .expect("taxel runs");
                assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
            })
        });
        let px = fitted_px(svg, STRESS2_MM);
        let png = dir.join("issue46.png");
        g.bench_function(format!("{name}: resvg at 10 px/mm, fitted ({px} px)"), |b| {
            b.iter(|| resvg_png(svg, px, &png))
        });
    }
    g.finish();
}

/// Issue 47's drawings: `taxel build` (whole process, the default memory
/// limit) beside resvg's render at 1,100 px wide. A build the limit stops
/// counts as done (it is refused in bounded time, which is the point).
fn runaway(c: &mut Criterion, dir: &Path, taxel: &str) {
    let page = (200.0, 150.0);
    let annotated = r##"stroke="#000" stroke-width="0.5" data-tactile="grating(); vibrate()""##;
    let cases: Vec<(String, String)> = vec![
        ("scribble 3,000".into(), drawings::scribble(3_000, page, "", 1)),
        ("scribble 30,000".into(), drawings::scribble(30_000, page, "", 1)),
        ("scribble 300,000".into(), drawings::scribble(300_000, page, "", 1)),
        ("annotated scribble 3,000".into(), drawings::scribble(3_000, page, annotated, 1)),
        ("annotated scribble 30,000".into(), drawings::scribble(30_000, page, annotated, 1)),
        ("annotated scribble 300,000".into(), drawings::scribble(300_000, page, annotated, 1)),
        ("scatter 20,000".into(), drawings::scatter(20_000, 0.6, page, 1)),
        ("scatter 100,000".into(), drawings::scatter(100_000, 0.6, page, 1)),
        ("ring 300,000".into(), drawings::jittered_ring(300_000, 50.0, 3.0, page, 1)),
    ];
    let mut g = c.benchmark_group("runaway");
    g.sampling_mode(SamplingMode::Flat).sample_size(10);
    for (name, svg) in &cases {
        let file = format!("{}.svg", name.replace([' ', ','], ""));
        let input = dir.join(&file);
        std::fs::write(&input, svg).expect("drawing written");
        if let Some(keep) = std::env::var_os("TAXEL_KEEP_DRAWINGS") {
            std::fs::write(Path::new(&keep).join(&file), svg).expect("kept drawing written");
        }
        let bundle = dir.join("runaway.taxel");
        g.bench_function(format!("{name}: taxel build"), |b| {
            b.iter(|| {
                let out = Command::new(taxel)
                    .args(["build", "--force", "-o"])
                    .arg(&bundle)
                    .arg(&input)
                    .output()
                    .expect("taxel runs");
                // Built, or refused with a diagnostic: never killed.
                assert!(out.status.code().is_some(), "{name}: killed");
            })
        });
        let png = dir.join("runaway.png");
        g.bench_function(format!("{name}: resvg at 1,100 px"), |b| b.iter(|| resvg_png(svg, 1_100, &png)));
    }
    g.finish();
}

/// The input limit of `src/io/read.rs` (a bench cannot import the binary's modules).
const MAX_INPUT_BYTES: usize = 64 << 20;

/// The largest `n` whose drawing `make(n)` stays under the input limit, by
/// doubling then bisecting on the generated size (sizes grow with `n`).
fn largest_under_limit(make: impl Fn(usize) -> String) -> (usize, String) {
    let mut lo = 1_000usize;
    let mut hi = lo;
    while make(hi).len() < MAX_INPUT_BYTES {
        lo = hi;
        hi *= 2;
    }
    // Size is close to linear in n: 1 % steps are enough.
    while hi - lo > lo / 100 {
        let mid = (lo + hi) / 2;
        if make(mid).len() < MAX_INPUT_BYTES { lo = mid } else { hi = mid }
    }
    (lo, make(lo))
}

fn near_the_limit(c: &mut Criterion, dir: &Path, taxel: &str) {
    let mut g = c.benchmark_group("input limit (64 MB), taxel build --fit (whole process)");
    g.sampling_mode(SamplingMode::Flat).sample_size(10);
    for (name, make) in [
        ("map regions", (|n| drawings::inkscape_map(n, 16, 11)) as fn(usize) -> String),
        ("city plan ways", |n| drawings::city_plan(n, 11)),
    ] {
        let (n, svg) = largest_under_limit(make);
        let file = format!("{}.svg", name.replace(' ', "-"));
        let input = dir.join(&file);
        std::fs::write(&input, &svg).expect("drawing written");
        if let Some(keep) = std::env::var_os("TAXEL_KEEP_DRAWINGS") {
            std::fs::write(Path::new(&keep).join(&file), &svg).expect("kept drawing written");
        }
        eprintln!("{name}: {n}, {:.1} MB", svg.len() as f64 / (1 << 20) as f64);
        let bundle = dir.join("limit.taxel");
        g.bench_function(format!("{name} ({n})"), |b| {
            b.iter(|| {
                let out = Command::new(taxel)
                    .args(["build", "--fit", "--force", "-o"])
                    .arg(&bundle)
                    .arg(&input)
                    .output()
                    .expect("taxel runs");
                assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
            })
        });
    }
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
