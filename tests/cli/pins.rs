//! Pin displays end to end: one drawing built for four families, the Dot Pad
//! and Graphiti files `taxel export` writes (read back by decoders written
//! here from `reference/pins.md`), the pin preview, `taxel inspect` and
//! `taxel load`.

use std::path::Path;
use std::process::{Command, Output};

use taxel_format::Bundle;

fn taxel(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taxel")).args(args).output().unwrap()
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

const MAP: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/map/tala-map.svg");

fn build(profile: &str, out: &Path) -> Bundle {
    let o = taxel(&["build", MAP, "--profile", profile, "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{profile}: {}", text(&o));
    Bundle::from_bytes(&std::fs::read(out).unwrap()).unwrap()
}

#[test]
fn one_source_builds_for_four_families() {
    let dir = tempfile::tempdir().unwrap();
    for (profile, family) in
        [("stress2", "laterotactile"), ("brush-4x3", "grid"), ("dotpad", "pins"), ("graphiti", "pins")]
    {
        let b = build(profile, &dir.path().join(format!("{profile}.taxel")));
        assert_eq!(b.manifest.profile.family().name(), family);
        assert!(!b.chunks.is_empty(), "{profile}: something tactile was made");
    }
}

#[test]
fn the_dotpad_map_exports_a_dtms_file_with_the_documented_bit_layout() {
    let dir = tempfile::tempdir().unwrap();
    let bundle = dir.path().join("map.taxel");
    let b = build("dotpad", &bundle);
    let image = b.pin_image().expect("a pin image").clone();
    // The 110 x 60 mm map fits one Dot Pad page; its several gratings need
    // a key, on whole pages after it (docs/pins.md, "The key page").
    assert_eq!(image.cols, 60);
    assert!(image.rows > 40 && image.rows.is_multiple_of(40), "{}", image.rows);
    let dtms = dir.path().join("map.dtms");
    let o = taxel(&["export", bundle.to_str().unwrap(), "--format", "dtms", "-o", dtms.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&dtms).unwrap()).unwrap();
    // The sample's structure: title, lang, lang_option, device, items.
    for key in ["title", "lang", "lang_option", "device"] {
        assert!(v[key].is_string(), "{key}");
    }
    assert_eq!(v["device"], "dotpad320");
    let items = v["items"].as_array().unwrap();
    // The graphic's page, then the key's (rows beyond the first 40).
    assert_eq!(items.len(), image.rows as usize / 40);
    let item = &items[0];
    assert_eq!(item["page"], 1);
    assert_eq!(item["graphic"]["name"], "1.dtm");
    assert_eq!(item["text"]["name"], "1.txt");
    // Graphic: 300 bytes as 600 hex digits, one byte per 2 x 4 cell, 30 per
    // line, bit (y % 4) + (x % 2) * 4; decoded here independently.
    let data = item["graphic"]["data"].as_str().unwrap();
    assert_eq!(data.len(), 600);
    let mut raised = 0;
    for cell in 0..300usize {
        let byte = u8::from_str_radix(&data[2 * cell..2 * cell + 2], 16).unwrap();
        for bit in 0..8u32 {
            let x = (cell % 30) as u32 * 2 + bit / 4;
            let y = (cell / 30) as u32 * 4 + bit % 4;
            assert_eq!(byte & (1 << bit) != 0, image.get(x, y).raised(), "pin ({x}, {y})");
            raised += (byte & (1 << bit) != 0) as usize;
        }
    }
    assert!(raised > 100, "the map's borders, textures, towns and key are there: {raised} pins");
    // The title on the text line: six-dot cells, whole 20-cell lines, and in print.
    let t = item["text"]["data"].as_str().unwrap();
    assert!(!t.is_empty() && t.len().is_multiple_of(40), "{t}");
    assert!(t.starts_with("20"), "a capital sign first: {t}");
    assert_eq!(item["text"]["plain"], "Tala island: three provinces, their towns, and a key");
}

#[test]
fn graphiti_frames_unicode_art_preview_inspect_and_load() {
    let dir = tempfile::tempdir().unwrap();
    let bundle = dir.path().join("map.taxel");
    let b = build("graphiti", &bundle);
    let image = b.pin_image().unwrap().clone();
    assert!(image.pins.iter().any(|p| p.blinks()), "the borders blink on the Graphiti");
    assert!(image.pins.iter().any(|p| p.height() == 2), "textures at height 2");
    let path = |n: &str| dir.path().join(n).to_str().unwrap().to_string();
    let o = taxel(&["export", bundle.to_str().unwrap(), "--format", "graphiti", "-o", &path("map.bin")]);
    assert!(o.status.success(), "{}", text(&o));
    let frame = std::fs::read(path("map.bin")).unwrap();
    // A frame a page: the graphic's, then the key's.
    let pages = taxel_compiler::pins::export::pages(&image, &b.manifest.profile).len();
    assert!(pages > 1);
    assert_eq!(frame.len(), 4800 * pages);
    for r in 0..40u32 {
        for c in 0..60u32 {
            let i = ((r * 60 + c) * 2) as usize;
            let pin = image.get(c, r);
            assert_eq!(frame[i], pin.height(), "height of ({c}, {r})");
            assert_eq!(frame[i + 1], if pin.blinks() { 5 } else { 0 }, "blink of ({c}, {r})");
        }
    }
    let o = taxel(&["export", bundle.to_str().unwrap(), "--format", "unicode", "-o", &path("map.txt")]);
    assert!(o.status.success(), "{}", text(&o));
    let art = std::fs::read_to_string(path("map.txt")).unwrap();
    // Four pins a line: the graphic's page and the key's.
    assert_eq!(art.lines().count(), 10 * pages);
    assert!(
        art.lines().all(|l| l.chars().count() == 30 && l.chars().all(|ch| ('\u{2800}'..='\u{28FF}').contains(&ch)))
    );
    // The preview: 10 px a pin with a pin's margin all round.
    let o = taxel(&["preview", bundle.to_str().unwrap(), "-o", &path("map.png")]);
    assert!(o.status.success(), "{}", text(&o));
    let png = crate::read_png(path("map.png"));
    // (Every page, the key's too, one under the other.)
    assert_eq!((png.width, png.height), (620, (image.rows + 2) * 10));
    let o = taxel(&["inspect", bundle.to_str().unwrap()]);
    assert!(o.status.success() && text(&o).contains("pins"), "{}", text(&o));
    // Loading onto a device folder stores it like any bundle.
    let device = dir.path().join("device");
    std::fs::create_dir(&device).unwrap();
    let o = taxel(&["load", bundle.to_str().unwrap(), "--device", device.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(std::fs::read(device.join("map.taxel")).unwrap(), std::fs::read(&bundle).unwrap());
}

#[test]
fn export_refuses_what_the_format_cannot_hold() {
    let dir = tempfile::tempdir().unwrap();
    let latero = dir.path().join("s.taxel");
    build("stress2", &latero);
    let out = dir.path().join("x.dtms");
    let o = taxel(&["export", latero.to_str().unwrap(), "--format", "dtms", "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("no pin image"), "{}", text(&o));
    let monarch = dir.path().join("m.taxel");
    build("monarch", &monarch);
    let o = taxel(&["export", monarch.to_str().unwrap(), "--format", "dtms", "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("60 x 40"), "{}", text(&o));
    assert!(!out.exists(), "nothing written");
}

/// A diagram nobody annotated whose node names do not fit their boxes: the
/// automatic sheet writes them as key codes (T0326), and the Dot Pad's text
/// line gives the key after the title, in braille and in the DTMS file's
/// print text, as a transcriber gives the key beside the graphic.
#[test]
fn key_codes_have_their_key_on_the_dot_pad_s_text_line() {
    let dir = tempfile::tempdir().unwrap();
    let node = |x: u32, label: &str| {
        format!(
            r##"<rect x="{x}" y="40" width="40" height="20" fill="#dde8ff" stroke="black" stroke-width="0.8"/><text x="{}" y="52" font-size="5" text-anchor="middle">{label}</text>"##,
            x + 20
        )
    };
    let svg = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="150mm" height="100mm" viewBox="0 0 150 100"><title>Process</title>{}{}{}</svg>"#,
        node(2, "Read input"),
        node(55, "Decide path"),
        node(108, "Write output")
    );
    let input = dir.path().join("process.svg");
    std::fs::write(&input, svg).unwrap();
    let bundle = dir.path().join("process.taxel");
    // The built-in UEB grade 1, whose cells are counted below (tests/cli/braille.rs checks liblouis's).
    let o = Command::new(env!("CARGO_BIN_EXE_taxel"))
        .args(["build", input.to_str().unwrap(), "--profile", "dotpad", "-o", bundle.to_str().unwrap()])
        .env("TAXEL_LIBLOUIS", "none")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("T0326"), "{}", text(&o));
    // `taxel inspect` gives the key: its line style and texture (the boxes'
    // outlines and fill, named by their colours), then a code a line.
    let o = taxel(&["inspect", bundle.to_str().unwrap()]);
    let said = text(&o);
    assert!(said.contains("key        texture: blue areas (grating "), "{said}");
    assert!(said.contains("           line: black lines (vibrating line "), "{said}");
    assert!(
        said.contains("\n           dp Decide path\n           ri Read input\n           wo Write output\n"),
        "{said}"
    );
    let dtms = dir.path().join("process.dtms");
    let o = taxel(&["export", bundle.to_str().unwrap(), "--format", "dtms", "-o", dtms.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&dtms).unwrap()).unwrap();
    let line = "Process; key: dp Decide path, ri Read input, wo Write output";
    assert_eq!(v["items"][0]["text"]["plain"], line);
    // The graphic, then the key's page (docs/pins.md, "The key page").
    assert_eq!(v["items"].as_array().unwrap().len(), 2);
    // In braille: a cell for each character but the capitals' signs (one
    // each: P, D, R, W), padded to whole 20-cell lines.
    let cells = v["items"][0]["text"]["data"].as_str().unwrap().len() / 2;
    let capitals = line.chars().filter(char::is_ascii_uppercase).count();
    assert_eq!(cells, (line.chars().count() + capitals).div_ceil(20) * 20);
    let b = Bundle::from_bytes(&std::fs::read(&bundle).unwrap()).unwrap();
    assert_eq!(b.pin_image().unwrap().text.len(), line.chars().count() + capitals);
}

/// Two textures and a line, named by their titles: the key's entries are in
/// the bundle for the laterotactile array (its provenance: the array has no
/// page to show them on) and for the Dot Pad (a page after the graphic, and
/// the provenance), and `taxel inspect` prints them for both.
#[test]
fn the_key_s_entries_are_inspected_on_every_family() {
    let dir = tempfile::tempdir().unwrap();
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="150mm" height="100mm" viewBox="0 0 150 100">
        <rect x="5" y="5" width="60" height="60" data-tactile="grating(wavelength: 3mm, angle: 0deg)"><title>Forest</title></rect>
        <rect x="80" y="5" width="60" height="60" data-tactile="grating(wavelength: 6mm, angle: 90deg)"><title>Lake</title></rect>
        <path d="M5 85 L140 85" stroke="black" data-tactile="vibrate()"><title>Road</title></path></svg>"#;
    let input = dir.path().join("map.svg");
    std::fs::write(&input, svg).unwrap();
    for (profile, pages) in [("stress2", None), ("dotpad", Some(2))] {
        let bundle = dir.path().join(format!("{profile}.taxel"));
        let o =
            taxel(&["build", input.to_str().unwrap(), "--profile", profile, "--fit", "-o", bundle.to_str().unwrap()]);
        assert!(o.status.success(), "{profile}: {}", text(&o));
        let o = taxel(&["inspect", bundle.to_str().unwrap()]);
        let said = text(&o);
        assert!(said.contains("key        texture: Forest (grating 3 mm at 0°)\n"), "{profile}: {said}");
        assert!(said.contains("           texture: Lake (grating 6 mm at 90°)\n"), "{profile}: {said}");
        assert!(said.contains("           line: Road (vibrating line 1.5 mm, 50 Hz)\n"), "{profile}: {said}");
        let o = taxel(&["inspect", bundle.to_str().unwrap(), "--format", "json"]);
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let kinds: Vec<&str> =
            v["key_entries"].as_array().unwrap().iter().map(|e| e["kind"].as_str().unwrap()).collect();
        assert_eq!(kinds, ["texture", "texture", "line"], "{profile}");
        if let Some(pages) = pages {
            let b = Bundle::from_bytes(&std::fs::read(&bundle).unwrap()).unwrap();
            let profile = b.manifest.profile;
            assert_eq!(taxel_compiler::pins::export::pages(b.pin_image().unwrap(), &profile).len(), pages);
        }
    }
}
