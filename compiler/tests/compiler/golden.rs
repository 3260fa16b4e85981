//! Golden bundles: small one-feature scenes compiled and dumped as text that a
//! person can review (chunk parameters, an ASCII picture of every mask, every
//! dot, provenance). Every drawing in `golden/` runs, with no test of its
//! own. `TAXEL_BLESS=1 cargo test -p taxel-compiler golden` rewrites the
//! `.txt` files; review the diff like code.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use taxel_compiler::{CompileOptions, StyleSheet, svg::compile_svg};
use taxel_format::{Bundle, Chunk, MaskKind, MaskLayer, MaskSamples};

use crate::common::*;

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/compiler/golden")
}

/// One character per 2 x 2 mm cell: ' ' empty, '.' partial, '#' mostly full.
/// A distance layer's edge profile in cells of 2 mm, the largest of 9 x 9
/// points in each: `#` above 0.75, `.` above 0, blank at 0.
fn ascii_field(d: &taxel_format::DistanceLayer) -> String {
    let (w, h) = (d.tile_cols as f32 * 8.0 * d.pitch_mm, d.tile_rows as f32 * 8.0 * d.pitch_mm);
    let mut out = String::new();
    let mut y = 1.0;
    while y < h {
        out.push_str("      |");
        let mut x = 1.0;
        while x < w {
            let mut v = 0.0f32;
            for j in 0..9 {
                for i in 0..9 {
                    let (px, py) = (x - 1.0 + i as f32 * 0.25, y - 1.0 + j as f32 * 0.25);
                    v = v.max(d.coverage_at(d.origin_x.0 + px, d.origin_y.0 + py));
                }
            }
            out.push(if v > 0.75 {
                '#'
            } else if v > 0.0 {
                '.'
            } else {
                ' '
            });
            x += 2.0;
        }
        out.push_str("|\n");
        y += 2.0;
    }
    out
}

fn ascii(m: &MaskLayer) -> String {
    let px = m.px_per_mm as f64;
    let cell = (2.0 * px).round().max(1.0) as usize;
    let (w, h) = (m.width as usize, m.height as usize);
    let value = |i: usize, j: usize| match &m.samples {
        MaskSamples::U8(v) => v[j * w + i] as f64 / 255.0,
        MaskSamples::U16(v) => v[j * w + i] as f64 / 65535.0,
    };
    let mut out = String::new();
    for cj in (0..h).step_by(cell) {
        out.push_str("      |");
        for ci in (0..w).step_by(cell) {
            let (mut sum, mut n) = (0.0, 0.0);
            for j in cj..(cj + cell).min(h) {
                for i in ci..(ci + cell).min(w) {
                    sum += value(i, j);
                    n += 1.0;
                }
            }
            let mean = sum / n;
            out.push(if mean > 0.75 {
                '#'
            } else if mean > 0.0 {
                '.'
            } else {
                ' '
            });
        }
        out.push_str("|\n");
    }
    out
}

/// The text dump of a bundle.
pub fn dump(b: &Bundle) -> String {
    let mut s = String::new();
    let p = &b.manifest.profile;
    writeln!(s, "profile {} surface {} x {} mm", p.name, p.surface_w_mm, p.surface_h_mm).unwrap();
    for c in &b.chunks {
        match c {
            Chunk::Mask(m) => {
                let kind = match m.kind {
                    MaskKind::Vibration { freq } => format!("VIBR {} Hz", freq.hz()),
                    MaskKind::Grating { wavelength, angle_deg } => {
                        format!("GRAT {} mm at {}°", wavelength.0, angle_deg)
                    }
                };
                let full = match &m.samples {
                    MaskSamples::U8(v) => v.iter().filter(|&&x| x == 255).count(),
                    MaskSamples::U16(v) => v.iter().filter(|&&x| x == 65535).count(),
                };
                writeln!(
                    s,
                    "{kind} amplitude {} source {:?}: {} x {} at {} px/mm from ({:.2}, {:.2}) mm, {full} full samples",
                    m.amplitude, m.source, m.width, m.height, m.px_per_mm, m.origin_x.0, m.origin_y.0
                )
                .unwrap();
                s += &ascii(m);
            }
            Chunk::Distance(d) => {
                let kind = match d.kind {
                    MaskKind::Vibration { freq } => format!("VDST {} Hz", freq.hz()),
                    MaskKind::Grating { wavelength, angle_deg } => {
                        format!("GDST {} mm at {}°", wavelength.0, angle_deg)
                    }
                };
                // Fine tiles (format 4.4, several stored tiles each) are
                // named only where there are some, as arcs are.
                let stored = d
                    .tiles
                    .iter()
                    .filter(|&&t| matches!(taxel_format::TileEntry::of(t), taxel_format::TileEntry::Stored(_)))
                    .count();
                let inside = d.tiles.iter().filter(|&&t| t == taxel_format::TILE_INSIDE).count();
                let count = |f: fn(taxel_format::TileEntry) -> bool| {
                    d.tiles.iter().filter(|&&t| f(taxel_format::TileEntry::of(t))).count()
                };
                let planes = count(|e| matches!(e, taxel_format::TileEntry::Plane(_)));
                let ridges = count(|e| matches!(e, taxel_format::TileEntry::Ridge(_)));
                let corners = count(|e| matches!(e, taxel_format::TileEntry::Corner(_)));
                let notches = count(|e| matches!(e, taxel_format::TileEntry::Notch(_)));
                let bends = count(|e| matches!(e, taxel_format::TileEntry::Bend(_)));
                // Arc tiles (format 4.1) are named only where there are some,
                // so that the goldens of layers without circles keep their text.
                let arcs = match count(|e| matches!(e, taxel_format::TileEntry::Arc(_))) {
                    0 => String::new(),
                    n => format!(", {n} arc"),
                };
                let fine = match count(|e| matches!(e, taxel_format::TileEntry::Fine { .. })) {
                    0 => String::new(),
                    n => format!(", {n} fine"),
                };
                writeln!(
                    s,
                    "{kind} amplitude {} soft {} sources {:?}: {} x {} tiles every {} mm from ({:.2}, {:.2}) mm, {stored} stored{fine}, {planes} plane, {ridges} ridge, {corners} corner, {notches} notch, {bends} bend{arcs}, {inside} inside",
                    d.amplitude, d.soft_mm, d.sources, d.tile_cols, d.tile_rows, d.pitch_mm, d.origin_x.0, d.origin_y.0
                )
                .unwrap();
                s += &ascii_field(d);
            }
            Chunk::Dots(t) => {
                writeln!(s, "DOTS {} ({} dots)", t.kind.name(), t.dots.len()).unwrap();
                for d in &t.dots {
                    writeln!(
                        s,
                        "  ({:.2}, {:.2}) r {:.2} amplitude {} source {:?}",
                        d.x.0, d.y.0, d.radius.0, d.amplitude, d.source
                    )
                    .unwrap();
                }
            }
            Chunk::Provenance(pr) => {
                writeln!(s, "PROV").unwrap();
                for (i, e) in pr.entries.iter().enumerate() {
                    writeln!(s, "  #{i} id {:?} label {:?} line {}", e.id, e.label, e.line).unwrap();
                }
            }
            Chunk::Footprints(f) => {
                writeln!(s, "FOOT quantum {} mm from ({}, {}) mm", f.quantum_mm, f.origin_x, f.origin_y).unwrap();
                for sh in &f.shapes {
                    let lens: Vec<usize> = sh.rings.iter().map(|r| r.len()).collect();
                    let hw = sh.half_width as f32 * f.quantum_mm;
                    writeln!(s, "  source {} {:?} half width {hw:.2} mm, ring points {lens:?}", sh.source, sh.kind)
                        .unwrap();
                }
            }
            other => writeln!(s, "{}", other.tag()).unwrap(),
        }
    }
    s
}

/// The dump of golden drawing `name` (its `.svg`, with its `.toml` style
/// sheet when there is one), followed by its diagnostics.
fn dump_of(name: &str) -> String {
    let svg = std::fs::read_to_string(dir().join(format!("{name}.svg"))).unwrap();
    let mut opts = CompileOptions::new(stress2());
    if let Ok(sheet) = std::fs::read_to_string(dir().join(format!("{name}.toml"))) {
        opts.style = Some(StyleSheet::parse(&sheet, &format!("{name}.toml")).unwrap());
    }
    let c = no_internal_error(compile_svg(&svg, &opts));
    let b = bundle(&c);
    let mut got = dump(b);
    for d in &c.diagnostics {
        writeln!(got, "{}", d.render(&format!("{name}.svg"))).unwrap();
    }
    got
}

/// The names of the golden drawings: every `.svg` in the folder, sorted.
fn golden_names() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "svg"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Every drawing in `golden/` compiles to the dump in its `.txt`: a new
/// drawing needs no test of its own. Every failing drawing is named, with
/// its first differing line; `TAXEL_BLESS=1` rewrites the dumps instead.
#[test]
fn every_golden_drawing_matches_its_dump() {
    let names = golden_names();
    // Every dump has its drawing (a drawing renamed or deleted leaves none behind).
    let orphans: Vec<String> = std::fs::read_dir(dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "txt"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .filter(|n| !names.contains(n))
        .collect();
    assert!(orphans.is_empty(), "golden dumps without a drawing: {orphans:?}");
    assert!(names.len() >= 11, "golden drawings missing from {}: {names:?}", dir().display());
    let bless = std::env::var_os("TAXEL_BLESS").is_some();
    let mut failed = Vec::new();
    for name in &names {
        let got = dump_of(name);
        let path = dir().join(format!("{name}.txt"));
        if bless {
            std::fs::write(&path, &got).unwrap();
            continue;
        }
        let Ok(want) = std::fs::read_to_string(&path) else {
            failed.push(format!("{name}.svg: {} missing (run with TAXEL_BLESS=1)", path.display()));
            continue;
        };
        if got != want {
            let line = got
                .lines()
                .zip(want.lines())
                .position(|(g, w)| g != w)
                .unwrap_or(got.lines().count().min(want.lines().count()));
            let (g, w) = (got.lines().nth(line).unwrap_or("(end)"), want.lines().nth(line).unwrap_or("(end)"));
            failed.push(format!("{name}.svg: line {} differs:\n  got:  {g}\n  want: {w}", line + 1));
        }
    }
    assert!(
        failed.is_empty(),
        "golden drawings differ (TAXEL_BLESS=1 to re-bless after review):\n{}",
        failed.join("\n")
    );
}
