//! Braille end to end: a French map's labels come out in French contracted
//! braille (liblouis's, computed here with `lou_translate`), and without
//! liblouis the built-in UEB grade 1 is written with a note saying how to
//! install it.
//!
//! The liblouis tests need liblouis and its tools; without them they say so
//! and pass, unless `TAXEL_REQUIRE_LIBLOUIS` is set (as `.ci/run` sets it).

use std::io::Write;
use std::path::Path;
use std::process::{Command, Output, Stdio};

use taxel_format::{Bundle, Chunk, DotKind};

fn taxel(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_taxel"));
    c.args(args);
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().unwrap()
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

/// Whether `lou_translate` runs (liblouis-bin); when it must, its absence fails.
fn have_liblouis() -> bool {
    if Command::new("lou_translate").arg("--version").output().is_ok_and(|o| o.status.success()) {
        return true;
    }
    assert!(std::env::var_os("TAXEL_REQUIRE_LIBLOUIS").is_none(), "lou_translate (liblouis-bin) is not installed");
    eprintln!("skipped: lou_translate (liblouis-bin) is not installed");
    false
}

/// `lou_translate --forward unicode.dis,TABLE` of `text`, as cells.
fn lou_translate(table: &str, text: &str) -> Vec<u8> {
    let mut child = Command::new("lou_translate")
        .args(["--forward", &format!("unicode.dis,{table}")])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(format!("{text}\n").as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    String::from_utf8(out.stdout)
        .unwrap()
        .trim_end_matches('\n')
        .chars()
        .map(|c| if ('\u{2800}'..='\u{28ff}').contains(&c) { (c as u32 - 0x2800) as u8 } else { 0 })
        .collect()
}

/// Dot centres of cells written from `(x0, baseline)` by NLS Specification
/// 800 (docs/annotations.md): 2.34 mm between dots, 6.2 mm between cells,
/// the lowest dots of radius 0.72 mm resting on the baseline.
fn dots_of(cells: &[u8], x0: f64, baseline: f64) -> Vec<(f64, f64)> {
    let r = 0.72;
    let mut out = Vec::new();
    for (k, &c) in cells.iter().enumerate() {
        for (bit, (col, row)) in [(0, 0), (0, 1), (0, 2), (1, 0), (1, 1), (1, 2)].into_iter().enumerate() {
            if c & (1 << bit) != 0 {
                out.push((x0 + k as f64 * 6.2 + r + col as f64 * 2.34, baseline - r - (2 - row) as f64 * 2.34));
            }
        }
    }
    out
}

/// The braille dots of a bundle, sorted.
fn braille_dots(path: &Path) -> Vec<(f64, f64)> {
    let b = Bundle::from_bytes(&std::fs::read(path).unwrap()).unwrap();
    let mut out: Vec<(f64, f64)> = b
        .chunks
        .iter()
        .filter_map(|c| match c {
            Chunk::Dots(t) if t.kind == DotKind::Braille => Some(t.dots.iter().map(|d| (d.x.0 as f64, d.y.0 as f64))),
            _ => None,
        })
        .flatten()
        .collect();
    out.sort_by(|a, b| a.partial_cmp(b).unwrap());
    out
}

fn sorted(mut v: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v
}

fn same_dots(a: &[(f64, f64)], b: &[(f64, f64)]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(p, q)| (p.0 - q.0).abs() < 0.01 && (p.1 - q.1).abs() < 0.01)
}

/// A map in French (the root's `xml:lang`), one label in German.
const MAP: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" width="110mm" height="60mm" viewBox="0 0 110 60" xml:lang="fr">
  <rect x="60" y="5" width="45" height="25" data-tactile="grating(wavelength: 4mm)"/>
  <text x="5" y="20" data-tactile="braille()">Marseille et la mer</text>
  <g xml:lang="de"><text x="5" y="40" data-tactile="braille()">Köln und München</text></g>
  <text x="5" y="55" data-tactile="braille(grade: 1)">Méditerranée</text>
</svg>"#;

#[test]
fn a_french_map_s_labels_are_french_contracted_braille_in_the_bundle() {
    if !have_liblouis() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (svg, out) = (dir.path().join("map.svg"), dir.path().join("map.taxel"));
    std::fs::write(&svg, MAP).unwrap();
    let o = taxel(&["build", svg.to_str().unwrap(), "-o", out.to_str().unwrap()], &[]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(!text(&o).contains("T0307"), "liblouis is installed: no fallback note\n{}", text(&o));
    let want = sorted(
        [
            dots_of(&lou_translate("fr-bfu-g2.ctb", "Marseille et la mer"), 5.0, 20.0),
            dots_of(&lou_translate("de-g2.ctb", "Köln und München"), 5.0, 40.0),
            dots_of(&lou_translate("fr-bfu-comp6.utb", "Méditerranée"), 5.0, 55.0),
        ]
        .concat(),
    );
    let got = braille_dots(&out);
    assert!(same_dots(&got, &want), "{} dots, liblouis's {}", got.len(), want.len());
    // Not the English grade 1 it was before.
    let o = taxel(&["build", svg.to_str().unwrap(), "-o", out.to_str().unwrap()], &[("TAXEL_LIBLOUIS", "none")]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(!same_dots(&braille_dots(&out), &want));
}

#[test]
fn without_liblouis_the_built_in_ueb_grade_1_is_written_with_a_note() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("map.svg");
    std::fs::write(&svg, MAP).unwrap();
    let (missing, builtin) = (dir.path().join("missing.taxel"), dir.path().join("builtin.taxel"));
    let env = [("TAXEL_LIBLOUIS", "liblouis-taxel-missing.so.99")];
    let o = taxel(&["build", svg.to_str().unwrap(), "-o", missing.to_str().unwrap()], &env);
    assert!(o.status.success(), "{}", text(&o));
    let said = text(&o);
    assert!(said.contains("T0307") && said.contains("install liblouis"), "{said}");
    assert!(said.contains("liblouis-taxel-missing.so.99"), "{said}");
    let o = taxel(&["check", svg.to_str().unwrap(), "--format", "json"], &env);
    assert!(String::from_utf8_lossy(&o.stdout).matches("T0307").count() == 1, "said once: {}", text(&o));
    // The cells are those of the built-in table chosen on purpose (which says nothing).
    let o = taxel(&["build", svg.to_str().unwrap(), "-o", builtin.to_str().unwrap()], &[("TAXEL_LIBLOUIS", "none")]);
    assert!(o.status.success() && !text(&o).contains("T0307"), "{}", text(&o));
    let (a, b) = (braille_dots(&missing), braille_dots(&builtin));
    assert!(!a.is_empty() && same_dots(&a, &b));
}
