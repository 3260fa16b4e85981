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
        let img = crate::read_png(&png);
        // 100 x 60 mm page on the 110 x 60 surface, 8 mm margins, 8 px/mm.
        assert_eq!((img.width, img.height), ((110 + 16) * 8, (60 + 16) * 8));
        // Grating stripes inside the box: along y (angle 0) the colour changes, along x it does not.
        let px =
            |x: f64, y: f64| img.pixel(((x + 8.0) * 8.0) as u32, ((y + 8.0) * 8.0) as u32).expect("on the preview");
        assert_eq!(px(20.0, 24.0), px(30.0, 24.0));
        assert_ne!(px(20.0, 24.0), px(20.0, 27.0));
        // Far from every layer the surface stays light.
        assert!(px(90.0, 5.0)[0] > 150);
    }
    let o = taxel(&["preview", &write(dir.path(), "x.taxel", "not a bundle"), "-o", "/dev/null"]);
    assert_eq!(o.status.code(), Some(1));
}

/// `--lang` chooses a `<switch>`'s child for the reader (the same drawing
/// gives another bundle, and a bundle rebuilt for another language is not
/// up to date); the system's language (`LANG`) is the default; a locale
/// name given as a tag is refused with what is expected.
#[test]
fn lang_chooses_the_labels_of_a_multilingual_drawing() {
    let dir = tempfile::tempdir().unwrap();
    let svg = write(
        dir.path(),
        "m.svg",
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm" viewBox="0 0 100 60">
  <rect x="10" y="10" width="30" height="30" data-tactile="grating()"/>
  <switch data-tactile="braille()">
    <text id="fr" x="50" y="20" systemLanguage="fr">Lac</text>
    <text id="en" x="50" y="40">Lake</text>
  </switch>
</svg>"#,
    );
    let out = dir.path().join("m.taxel");
    let build = |args: &[&str], lang_env: &str| {
        let o = Command::new(env!("CARGO_BIN_EXE_taxel"))
            .args(["build", &svg, "-o", out.to_str().unwrap()])
            .args(args)
            .env_remove("LC_ALL")
            .env_remove("LC_MESSAGES")
            .env("LANG", lang_env)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        (String::from_utf8_lossy(&o.stdout).to_string(), std::fs::read(&out).unwrap())
    };
    let (_, english) = build(&[], "C.UTF-8");
    let (said, again) = build(&[], "C.UTF-8");
    assert!(said.starts_with("skipped "), "{said}");
    assert_eq!(english, again);
    let (said, french) = build(&["--lang", "fr"], "C.UTF-8");
    assert!(said.starts_with("built "), "another language is not up to date: {said}");
    assert_ne!(english, french);
    let (said, _) = build(&["--lang", "fr"], "C.UTF-8");
    assert!(said.starts_with("skipped "), "{said}");
    // LANG=fr_FR gives fr-FR and fr: the same label as --lang fr.
    let (said, system) = build(&[], "fr_FR.UTF-8");
    assert!(said.starts_with("built "), "{said}");
    // The braille dots, unpacked: the same (the bundles differ in their
    // manifest's content hash).
    let dots = |bundle: &[u8], name: &str| {
        let (b, folder) = (dir.path().join(format!("{name}.taxel")), dir.path().join(name));
        std::fs::write(&b, bundle).unwrap();
        let o = taxel(&["unpack", b.to_str().unwrap(), "-o", folder.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        let csv = std::fs::read_dir(&folder)
            .unwrap()
            .map(|e| e.unwrap().path())
            .find(|p| p.to_string_lossy().ends_with("dots.csv"));
        std::fs::read_to_string(csv.expect("a dots table")).unwrap()
    };
    assert_eq!(dots(&system, "system"), dots(&french, "french"));
    assert_ne!(dots(&english, "english"), dots(&french, "french2"));
    let o = taxel(&["build", &svg, "--lang", "fr_FR.UTF-8", "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("is not a language tag"));
}
