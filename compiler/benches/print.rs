//! Print media: a 1,000-region map (40 x 25 jittered quadrilaterals, each
//! with a vibrating border and one of six gratings, and 50 braille labels)
//! from SVG text to the file: a swell-paper PDF (`swell_a4_pdf`) and a
//! binary STL relief (`print3d_stl`), each the whole path a `taxel build`
//! takes after reading the file (resolve, legalise, design rules, write).
//! The issue's target is 2 s for each.
//!
//! `cargo bench -p taxel-compiler --features bench --bench print -- --warm-up-time 1 --measurement-time 3`

use std::fmt::Write as _;
use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use taxel_compiler::{CompileOptions, compile_svg, print};
use taxel_format::profiles;

/// The map: page 190 x 277 mm, 40 x 25 regions whose shared corners are
/// jittered (so neighbours share their sides exactly, as on a real map).
fn map() -> String {
    let (nx, ny) = (25usize, 40usize);
    let (w, h) = (190.0 / nx as f64, 277.0 / ny as f64);
    // A fixed jitter from a small LCG, so every run draws the same map.
    let mut seed = 12345u64;
    let mut rnd = move || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((seed >> 33) as f64 / (1u64 << 31) as f64) - 0.5
    };
    let mut corner = vec![(0.0, 0.0); (nx + 1) * (ny + 1)];
    for j in 0..=ny {
        for i in 0..=nx {
            let edge = i == 0 || j == 0 || i == nx || j == ny;
            let (dx, dy) = if edge { (0.0, 0.0) } else { (rnd() * w * 0.5, rnd() * h * 0.5) };
            corner[j * (nx + 1) + i] = (i as f64 * w + dx, j as f64 * h + dy);
        }
    }
    let mut s =
        String::from(r#"<svg xmlns="http://www.w3.org/2000/svg" width="190mm" height="277mm" viewBox="0 0 190 277">"#);
    for j in 0..ny {
        for i in 0..nx {
            let c = |a: usize, b: usize| corner[b * (nx + 1) + a];
            let (p, q, r, t) = (c(i, j), c(i + 1, j), c(i + 1, j + 1), c(i, j + 1));
            let style = (i + 2 * j) % 6;
            let _ = write!(
                s,
                r#"<path id="r{i}_{j}" d="M{:.2},{:.2} L{:.2},{:.2} L{:.2},{:.2} L{:.2},{:.2} Z" data-tactile="vibrate(width: 1mm); grating(wavelength: {}mm, angle: {}deg)"/>"#,
                p.0,
                p.1,
                q.0,
                q.1,
                r.0,
                r.1,
                t.0,
                t.1,
                2 + style,
                30 * style
            );
        }
    }
    for k in 0..50 {
        let (x, y) = (10.0 + (k % 5) as f64 * 35.0, 12.0 + (k / 5) as f64 * 26.0);
        let _ = write!(s, r#"<text x="{x}" y="{y}" data-tactile="braille()">town {k}</text>"#);
    }
    s + "</svg>"
}

fn bench(c: &mut Criterion) {
    let text = map();
    let mut g = c.benchmark_group("print_1000_regions");
    g.sample_size(10);
    for (name, profile, kind) in
        [("swell_a4_pdf", "swell-a4", print::FileKind::Pdf), ("print3d_stl", "print3d", print::FileKind::Stl)]
    {
        let opts = CompileOptions { fit: true, ..CompileOptions::new(profiles::builtin(profile).unwrap()) };
        g.bench_function(name, |b| {
            b.iter(|| {
                let compiled = compile_svg(black_box(&text), &opts);
                let sheet = compiled.print.expect("the map prints");
                black_box(print::write(&sheet, kind).expect("the file is written").len())
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
