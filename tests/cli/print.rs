//! Print media end to end: one map built for every print profile, the PDF
//! read back by poppler (`pdfinfo` for the page size, `pdftoppm` to measure
//! braille dots), the STL read back by a reader written here from the format
//! (50-byte records) and checked for a closed, outward mesh, the embosser's
//! PNG, and hostile requests refused cleanly.
//!
//! poppler-utils is a test tool (`.ci/run` installs it); where it is missing
//! the PDF read-backs say so and pass, unless `TAXEL_REQUIRE_POPPLER` is set
//! (as CI sets it).

use std::collections::HashMap;
use std::path::Path;
use std::process::{Command, Output};

fn taxel(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taxel")).args(args).output().unwrap()
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

const MAP: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/map/tala-map.svg");

fn build(input: &str, profile: &str, out: &Path, extra: &[&str]) -> Vec<u8> {
    let mut args = vec!["build", input, "--profile", profile, "-o", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    let o = taxel(&args);
    assert!(o.status.success(), "{profile}: {}", text(&o));
    std::fs::read(out).unwrap()
}

/// Whether poppler's `tool` can be run; panics when it is required and missing.
fn poppler(tool: &str) -> bool {
    let here = Command::new(tool).arg("-v").output().is_ok();
    if !here {
        assert!(std::env::var_os("TAXEL_REQUIRE_POPPLER").is_none(), "{tool} is missing: install poppler-utils");
        eprintln!("{tool} not found (poppler-utils): the PDF read-back is skipped here");
    }
    here
}

#[test]
fn one_map_prints_on_every_medium() {
    let dir = tempfile::tempdir().unwrap();
    for (profile, ext, magic) in [
        ("swell-a4", "pdf", &b"%PDF-"[..]),
        ("swell-letter", "pdf", b"%PDF-"),
        ("tiger-20dpi", "pdf", b"%PDF-"),
        ("tiger-20dpi", "png", b"\x89PNG"),
        ("emboss-braille-grid", "pdf", b"%PDF-"),
    ] {
        let bytes = build(MAP, profile, &dir.path().join(format!("{profile}.{ext}")), &["--fit"]);
        assert!(bytes.starts_with(magic), "{profile}.{ext}");
    }
    let stl = build(MAP, "print3d", &dir.path().join("map.stl"), &["--fit"]);
    assert!(stl.len() > 84);
    // The same relief as 3MF: a zip package (its mesh is read back in the compiler's print tests).
    let three_mf = build(MAP, "print3d", &dir.path().join("map.3mf"), &["--fit"]);
    assert!(three_mf.starts_with(b"PK\x03\x04"), "a zip package");
    // Without -o the file goes beside the input with the medium's extension.
    let here = dir.path().join("tala.svg");
    std::fs::copy(MAP, &here).unwrap();
    let o = taxel(&["build", here.to_str().unwrap(), "--profile", "swell-a4"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(dir.path().join("tala.pdf").is_file());
}

#[test]
fn the_pdf_page_is_the_paper() {
    if !poppler("pdfinfo") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for (profile, w_in, h_in) in
        [("swell-a4", 210.0 / 25.4, 297.0 / 25.4), ("swell-letter", 8.5, 11.0), ("tiger-20dpi", 11.0, 11.5)]
    {
        let pdf = dir.path().join(format!("{profile}.pdf"));
        build(MAP, profile, &pdf, &[]);
        let o = Command::new("pdfinfo").arg(&pdf).output().unwrap();
        let info = String::from_utf8_lossy(&o.stdout);
        let line = info.lines().find(|l| l.starts_with("Page size:")).unwrap_or_else(|| panic!("{info}"));
        let nums: Vec<f64> = line.split_whitespace().filter_map(|w| w.parse().ok()).collect();
        assert!((nums[0] - w_in * 72.0).abs() < 0.01 && (nums[1] - h_in * 72.0).abs() < 0.01, "{profile}: {line}");
    }
}

/// Dark blobs of a grey image: `(centre x, centre y, area)` in pixels.
fn blobs(img: &taxel_textform::png::Image) -> Vec<(f64, f64, f64)> {
    let (w, h) = (img.width, img.height);
    let gray = img.to_gray8();
    let mut seen = vec![false; (w * h) as usize];
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            if seen[(y * w + x) as usize] || gray[(y * w + x) as usize] >= 128 {
                continue;
            }
            let (mut n, mut sx, mut sy) = (0.0, 0.0, 0.0);
            let mut stack = vec![(x, y)];
            seen[(y * w + x) as usize] = true;
            while let Some((px, py)) = stack.pop() {
                n += 1.0;
                sx += px as f64;
                sy += py as f64;
                for (dx, dy) in [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)] {
                    let (qx, qy) = (px as i64 + dx, py as i64 + dy);
                    if qx < 0 || qy < 0 || qx >= w as i64 || qy >= h as i64 {
                        continue;
                    }
                    let k = (qy as u32 * w + qx as u32) as usize;
                    if !seen[k] && gray[k] < 128 {
                        seen[k] = true;
                        stack.push((qx as u32, qy as u32));
                    }
                }
            }
            out.push((sx / n, sy / n, n));
        }
    }
    out
}

#[test]
fn braille_dots_read_back_from_the_pdf_have_the_nls_pitch_and_diameter() {
    if !poppler("pdftoppm") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("label.svg");
    // "ll" uncontracted: dots 1, 2, 3 in two cells, the text starting at (20, 30) mm.
    std::fs::write(
        &svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="50mm" viewBox="0 0 100 50">
  <text x="20" y="30" data-tactile="braille(grade: 1)">ll</text></svg>"#,
    )
    .unwrap();
    let pdf = dir.path().join("label.pdf");
    build(svg.to_str().unwrap(), "swell-a4", &pdf, &[]);
    // 508 dpi: 20 px a millimetre; the crop (25..50 mm, 30..45 mm on the
    // paper, the 10 mm margin included) holds the label alone.
    let px_mm = 20.0;
    let prefix = dir.path().join("r");
    let o = Command::new("pdftoppm")
        .args(["-r", "508", "-gray", "-png", "-singlefile", "-x", "500", "-y", "600", "-W", "500", "-H", "300"])
        .arg(&pdf)
        .arg(&prefix)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = crate::read_png(dir.path().join("r.png"));
    let mut dots = blobs(&img);
    assert_eq!(dots.len(), 6, "{dots:?}");
    for d in &dots {
        let diameter = 2.0 * (d.2 / std::f64::consts::PI).sqrt() / px_mm;
        assert!((diameter - 1.5).abs() < 0.1, "dot diameter {diameter} mm, NLS 800 1.5-1.6 mm");
    }
    dots.sort_by(|a, b| (a.0, a.1).partial_cmp(&(b.0, b.1)).unwrap());
    // Dots 1-2-3 of a cell down one column, the next cell's column a cell spacing on.
    for col in dots.chunks(3) {
        for pair in col.windows(2) {
            let pitch = (pair[1].1 - pair[0].1) / px_mm;
            assert!((pitch - 2.34).abs() < 0.06, "dot spacing {pitch} mm");
            assert!((pair[1].0 - pair[0].0).abs() / px_mm < 0.06);
        }
    }
    let cell = (dots[3].0 - dots[0].0) / px_mm;
    assert!((cell - 6.2).abs() < 0.06, "cell spacing {cell} mm");
    // The lowest dots rest on the baseline: 30 mm on the drawing, 40 mm on the paper, 10 mm into the crop.
    let lowest = dots.iter().map(|d| d.1).fold(0.0, f64::max) / px_mm + 0.75;
    assert!((lowest - 10.0).abs() < 0.1, "{lowest}");
}

/// The triangles of a binary STL, read from the format alone.
fn read_stl(bytes: &[u8]) -> Vec<[[f32; 3]; 3]> {
    let n = u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize;
    assert_eq!(bytes.len(), 84 + 50 * n, "a binary STL is 84 bytes then 50 a triangle");
    let f = |o: usize| f32::from_le_bytes(bytes[o..o + 4].try_into().unwrap());
    (0..n)
        .map(|t| {
            let o = 84 + 50 * t + 12;
            [0, 1, 2].map(|v| [f(o + 12 * v), f(o + 12 * v + 4), f(o + 12 * v + 8)])
        })
        .collect()
}

#[test]
fn the_stl_is_watertight_manifold_outward_and_at_the_profile_s_heights() {
    let dir = tempfile::tempdir().unwrap();
    // The built-in print3d with a 1 mm mesh step (a profile file may change
    // it), so that the debug build's check of every edge stays quick.
    let p3d = taxel_format::profiles::BUILTIN.iter().find(|(n, _)| *n == "print3d").unwrap().1;
    let profile = dir.path().join("coarse.toml");
    std::fs::write(&profile, p3d.replace("grid_mm = 0.5", "grid_mm = 1")).unwrap();
    let tris = read_stl(&build(MAP, profile.to_str().unwrap(), &dir.path().join("map.stl"), &["--fit"]));
    let key = |v: [f32; 3]| v.map(f32::to_bits);
    let mut edges: HashMap<([u32; 3], [u32; 3]), u32> = HashMap::new();
    let mut volume = 0.0f64;
    for t in &tris {
        for k in 0..3 {
            *edges.entry((key(t[k]), key(t[(k + 1) % 3]))).or_default() += 1;
        }
        let [p, q, r] = t.map(|v| v.map(f64::from));
        volume += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0])
            + p[2] * (q[0] * r[1] - q[1] * r[0]))
            / 6.0;
    }
    // Every edge is used once each way: shared by exactly two triangles, opposite in orientation.
    for (&(a, b), &n) in &edges {
        assert_eq!(n, 1, "edge used {n} times in one direction");
        assert_eq!(edges.get(&(b, a)), Some(&1), "an edge without its opposite: a hole");
    }
    // The built-in print3d: a 200 x 200 mm plate 2 mm thick, features 1 mm,
    // textures 0.5 mm; a plate a page, 10 mm apart in a row: the map's, then
    // its key's (tala-map has three textures, so it has a key).
    let xs = tris.iter().flatten().map(|v| v[0]);
    let (lo, hi) = xs.fold((f32::MAX, f32::MIN), |a, x| (a.0.min(x), a.1.max(x)));
    assert_eq!((lo, hi), (0.0, 410.0), "two plates");
    let plate = 200.0 * 200.0;
    assert!(volume > 2.0 * plate * 2.0 && volume < 2.0 * plate * 3.0, "volume {volume} mm³");
    let mut zs: Vec<f32> = tris.iter().flatten().map(|v| v[2]).collect();
    zs.sort_by(f32::total_cmp);
    zs.dedup();
    assert_eq!(zs, vec![0.0, 2.0, 2.5, 3.0]);
}

#[test]
fn the_tiger_png_is_20_pixels_an_inch() {
    let dir = tempfile::tempdir().unwrap();
    let png = build(MAP, "tiger-20dpi", &dir.path().join("map.png"), &["--fit"]);
    let img = taxel_textform::png::read(&png).unwrap();
    let gray = img.to_gray8();
    // 11 x 11.5 in at 20 px an inch, a page under the other: the map's,
    // then its key's (tala-map has three textures, so it has a key).
    assert_eq!((img.width, img.height), (220, 2 * 230), "11 x 11.5 in at 20 px an inch, two pages");
    // Dots only inside each page's half-inch margin (10 pixels).
    for (k, p) in gray.iter().enumerate() {
        let (x, y) = (k as u32 % img.width, k as u32 / img.width);
        if *p < 255 {
            let y = y % 230;
            assert!((10..210).contains(&x) && (10..220).contains(&y), "a dot at ({x}, {y}) in the margin");
        }
    }
    assert!(gray.iter().filter(|p| **p < 255).count() > 500);
}

#[test]
fn hostile_print_requests_are_refused_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let out = |n: &str| dir.path().join(n).to_str().unwrap().to_string();
    // A file the medium is not written as, and a print file from a device profile.
    for (profile, file, says) in [
        ("swell-a4", "m.stl", "writes .pdf"),
        ("swell-a4", "m.3mf", "writes .pdf"),
        ("print3d", "m.pdf", "writes .stl"),
        ("swell-a4", "m.taxel", "writes .pdf"),
        ("stress2", "m.pdf", "print profiles"),
    ] {
        let o = taxel(&["build", MAP, "--profile", profile, "-o", &out(file)]);
        assert_eq!(o.status.code(), Some(2), "{profile} -o {file}: {}", text(&o));
        assert!(text(&o).contains(says), "{}", text(&o));
        assert!(!dir.path().join(file).exists());
    }
    // Profile files out of range, named by key.
    let a4 = taxel_format::profiles::BUILTIN.iter().find(|(n, _)| *n == "swell-a4").unwrap().1;
    for (from, to, key) in [
        ("paper_width_mm = 210", "paper_width_mm = 1e9", "print.paper_width_mm"),
        ("grid_mm = 0.25", "grid_mm = 0.001", "print.grid_mm"),
        ("margin_mm = 10", "margin_mm = 150", "print.margin_mm"),
    ] {
        let p = dir.path().join("bad.toml");
        std::fs::write(&p, a4.replace(from, to)).unwrap();
        let o = taxel(&["build", MAP, "--profile", p.to_str().unwrap(), "-o", &out("x.pdf")]);
        assert_eq!(o.status.code(), Some(2), "{}", text(&o));
        assert!(text(&o).contains(key), "{}", text(&o));
    }
    // A drawing with nothing tactile: exit 1 and no file.
    let plain = dir.path().join("plain.svg");
    std::fs::write(&plain, r#"<svg xmlns="http://www.w3.org/2000/svg" width="50mm" height="50mm"><rect width="10" height="10" fill="none"/></svg>"#).unwrap();
    let o = taxel(&["build", plain.to_str().unwrap(), "--profile", "print3d", "-o", &out("p.stl")]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(!dir.path().join("p.stl").exists());
    // A drawing 4 m wide would take more than a hundred pages: exit 1, no file, the way out.
    let wall = dir.path().join("wall.svg");
    std::fs::write(&wall, r#"<svg xmlns="http://www.w3.org/2000/svg" width="4000mm" height="3000mm" viewBox="0 0 4000 3000"><rect x="10" y="10" width="100" height="100" fill="none" stroke="black" data-tactile="vibrate()"/></svg>"#).unwrap();
    let o = taxel(&["build", wall.to_str().unwrap(), "--profile", "swell-a4", "-o", &out("w.pdf")]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("T0213") && text(&o).contains("--fit"), "{}", text(&o));
    assert!(!dir.path().join("w.pdf").exists());
}

/// A wall map larger than the paper, built without `--fit`, prints at its
/// size on the pages that cover it: poppler reads six A4 pages, each the
/// paper's size, and the note says so.
#[test]
fn a_large_drawing_prints_on_several_pages() {
    if !poppler("pdfinfo") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("wall.svg");
    std::fs::write(
        &svg,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="500mm" height="300mm" viewBox="0 0 500 300">
  <rect x="10" y="10" width="480" height="280" fill="none" stroke="black" data-tactile="vibrate()"/>
  <circle cx="250" cy="150" r="100" fill="#c33" data-tactile="grating(wavelength: 6mm)"/>
</svg>"##,
    )
    .unwrap();
    let pdf = dir.path().join("wall.pdf");
    let o = taxel(&["build", svg.to_str().unwrap(), "--profile", "swell-a4", "-o", pdf.to_str().unwrap(), "-v"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("T0212") && text(&o).contains("6 pages, 3 across and 2 down"), "{}", text(&o));
    let info = Command::new("pdfinfo").arg(&pdf).output().unwrap();
    let info = String::from_utf8_lossy(&info.stdout);
    let pages = info.lines().find_map(|l| l.strip_prefix("Pages:")).map(str::trim);
    assert_eq!(pages, Some("6"), "{info}");
    // Every page is A4.
    let o = Command::new("pdfinfo").args(["-f", "1", "-l", "6"]).arg(&pdf).output().unwrap();
    let sizes: Vec<String> = String::from_utf8_lossy(&o.stdout)
        .lines()
        .filter(|l| l.starts_with("Page") && l.contains("size:"))
        .map(String::from)
        .collect();
    assert_eq!(sizes.len(), 6, "{sizes:?}");
    assert!(sizes.iter().all(|l| l.contains("595.276 x 841.89")), "{sizes:?}");
}

#[test]
fn the_felt_preview_of_a_print_profile_is_drawn() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("felt.png");
    let o = taxel(&["preview", MAP, "--profile", "swell-a4", "-o", png.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    let img = crate::read_png(&png);
    // The A4 graphic and its key page side by side at 6 px/mm, with 8 mm
    // around and between them (the map's several textures need a key).
    assert_eq!((img.width, img.height), (((2.0 * 210.0 + 3.0 * 8.0) * 6.0) as u32, ((297.0 + 16.0) * 6.0) as u32));
    // Raised marks are shaded darker than the paper.
    assert!(img.to_rgb8().iter().filter(|p| p[0] < 200).count() > 1000);
}

/// A sheet as text a person can review: its pages and their marks by kind
/// and level, the texture each grated element got, and each page as ASCII
/// art at 2.5 mm a character (`#` lines and symbols, `o` braille, `.` texture).
fn sheet_text(sheet: &taxel_compiler::print::Sheet) -> String {
    use taxel_compiler::print::{Level, MarkShape};
    let mut s = format!(
        "profile {}, paper {} x {} mm, {} page(s)\n",
        sheet.profile.name,
        sheet.paper_mm.0,
        sheet.paper_mm.1,
        sheet.pages.len()
    );
    s += &format!("textures (element, texture): {:?}\n", sheet.textures);
    let cell = 2.5;
    let (cols, rows) = ((sheet.paper_mm.0 / cell).ceil() as usize, (sheet.paper_mm.1 / cell).ceil() as usize);
    for (n, page) in sheet.pages.iter().enumerate() {
        let mut counts = std::collections::BTreeMap::new();
        let mut art = vec![vec![' '; cols]; rows];
        let mut put = |p: (f64, f64), l: Level| {
            let (i, j) = ((p.0 / cell).floor(), (p.1 / cell).floor());
            if i >= 0.0 && j >= 0.0 && (i as usize) < cols && (j as usize) < rows {
                let c = &mut art[j as usize][i as usize];
                let rank = |c: char| " .o#".find(c).unwrap_or(0);
                let new = match l {
                    Level::Texture => '.',
                    Level::Braille => 'o',
                    Level::Line => '#',
                };
                if rank(new) > rank(*c) {
                    *c = new;
                }
            }
        };
        for m in page {
            let kind = match &m.shape {
                MarkShape::Line { points, .. } => {
                    for w in points.windows(2) {
                        let steps = ((w[1].0 - w[0].0).hypot(w[1].1 - w[0].1) / 1.0).ceil().max(1.0) as usize;
                        for k in 0..=steps {
                            let t = k as f64 / steps as f64;
                            put((w[0].0 + t * (w[1].0 - w[0].0), w[0].1 + t * (w[1].1 - w[0].1)), m.level);
                        }
                    }
                    "line"
                }
                MarkShape::Polygon { rings } => {
                    rings.iter().flatten().for_each(|&p| put(p, m.level));
                    "polygon"
                }
                MarkShape::Dot { centre, .. } => {
                    put(*centre, m.level);
                    "dot"
                }
            };
            *counts.entry(format!("{kind} {:?}", m.level)).or_insert(0usize) += 1;
        }
        s += &format!("page {}: {counts:?}\n", n + 1);
        for row in art {
            s += row.iter().collect::<String>().trim_end();
            s += "\n";
        }
    }
    s
}

#[test]
fn the_map_s_sheet_for_each_print_profile_matches_its_golden() {
    // `TAXEL_BLESS=1 cargo test --test cli print::` rewrites the goldens; review them as pictures
    // (`taxel preview examples/map/tala-map.svg --profile P -o P.png`) before committing.
    let text = std::fs::read_to_string(MAP).unwrap();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/cli/print_goldens");
    let mut stale = Vec::new();
    for profile in ["swell-a4", "swell-letter", "tiger-20dpi", "emboss-braille-grid", "print3d"] {
        let opts = taxel_compiler::CompileOptions::new(taxel_format::profiles::builtin(profile).unwrap());
        let compiled = taxel_compiler::compile_svg(&text, &opts);
        let sheet = compiled.print.unwrap_or_else(|| panic!("{profile}: {:?}", compiled.diagnostics));
        let got = sheet_text(&sheet);
        let path = dir.join(format!("tala-map.{profile}.txt"));
        if std::env::var_os("TAXEL_BLESS").is_some() {
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(&path, &got).unwrap();
        } else if std::fs::read_to_string(&path).ok().as_deref() != Some(got.as_str()) {
            stale.push(path.display().to_string());
        }
    }
    assert!(stale.is_empty(), "goldens differ (re-bless with TAXEL_BLESS=1 after looking at the previews): {stale:?}");
}
