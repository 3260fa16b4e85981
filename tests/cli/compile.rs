//! `taxel check`, `taxel build` on a drawing, and `taxel preview` (drawing and bundle).

use std::path::Path;
use std::process::{Command, Output};

fn taxel(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taxel")).args(args).output().unwrap()
}

const GOOD: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm" viewBox="0 0 100 60">
  <rect id="box" x="10" y="10" width="30" height="30" fill="#e41a1c" data-tactile="vibrate(); grating(wavelength: 6mm, angle: 0deg)"/>
  <circle id="town" cx="70" cy="25" r="1.5" fill="black" data-tactile="dot()"/>
  <text id="label" x="55" y="50" data-tactile="braille()">Map</text>
</svg>"##;

const BAD: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm" viewBox="0 0 100 60">
  <rect id="box" x="10" y="10" width="30" height="30" data-tactile="grating(wavelength 6mm)"/>
</svg>"#;

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

#[test]
fn check_reports_like_a_compiler_and_exits_1_on_errors() {
    let dir = tempfile::tempdir().unwrap();
    let good = write(dir.path(), "good.svg", GOOD);
    let bad = write(dir.path(), "bad.svg", BAD);
    let out = taxel(&["check", &good]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let out = taxel(&["check", &good, &bad]);
    assert_eq!(out.status.code(), Some(1));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains(&format!("{bad}:2:")), "{text}");
    assert!(text.contains("error[T0101]"), "{text}");
    assert!(text.contains("(element #box)"), "{text}");
}

#[test]
fn check_json_lists_codes_lines_and_columns() {
    let dir = tempfile::tempdir().unwrap();
    let bad = write(dir.path(), "bad.svg", BAD);
    let out = taxel(&["check", "--format", "json", &bad]);
    assert_eq!(out.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let d = &v[0]["diagnostics"][0];
    assert_eq!(d["code"], "T0101");
    assert_eq!(d["severity"], "error");
    assert_eq!(d["line"], 2);
    assert_eq!(d["element"], "box");
    assert_eq!(v[0]["errors"], 1);
    // `data-tactile="grating(wavelength 6mm)"`: the `6` is where `:` was expected.
    let col = BAD.lines().nth(1).unwrap().find("6mm").unwrap() + 1;
    assert_eq!(d["column"], col as u64);
}

#[test]
fn a_bad_style_sheet_is_an_input_error_naming_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let good = write(dir.path(), "good.svg", GOOD);
    let sheet = write(dir.path(), "s.toml", "[[rule]]\nfill = \"red\"\ntactile = \"grating(angle: 7)\"\n");
    let out = taxel(&["check", "--style", &sheet, &good]);
    assert_eq!(out.status.code(), Some(1));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("T0110") && text.contains(&format!("{sheet}:3:")), "{text}");
}

#[test]
fn build_is_deterministic_and_preview_draws_drawings_and_bundles() {
    let dir = tempfile::tempdir().unwrap();
    let good = write(dir.path(), "good.svg", GOOD);
    let a = dir.path().join("a.taxel");
    let b = dir.path().join("b.taxel");
    for out in [&a, &b] {
        let o = taxel(&["build", &good, "-o", out.to_str().unwrap(), "--force"]);
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    }
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    for input in [good.as_str(), a.to_str().unwrap()] {
        let png = dir.path().join("p.png");
        let o = taxel(&["preview", input, "-o", png.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        let img = image::open(&png).unwrap().to_rgba8();
        // 100 x 60 mm page on the 110 x 60 surface, 8 mm margins, 8 px/mm.
        assert_eq!((img.width(), img.height()), ((110 + 16) * 8, (60 + 16) * 8));
        // Grating stripes inside the box: along y (angle 0) the colour changes, along x it does not.
        let px = |x: f64, y: f64| img.get_pixel(((x + 8.0) * 8.0) as u32, ((y + 8.0) * 8.0) as u32).0;
        assert_eq!(px(20.0, 24.0), px(30.0, 24.0));
        assert_ne!(px(20.0, 24.0), px(20.0, 27.0));
        // Far from every layer the surface stays light.
        assert!(px(90.0, 5.0)[0] > 150);
    }
    let o = taxel(&["preview", &write(dir.path(), "x.taxel", "not a bundle"), "-o", "/dev/null"]);
    assert_eq!(o.status.code(), Some(1));
}
