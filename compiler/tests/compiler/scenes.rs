//! Whole scenes through the SVG pipeline: one feature each, every kind, none.

use taxel_format::{DotKind, MaskKind};

use crate::common::*;

#[test]
fn vibrating_rectangle_outline() {
    let c = compile(&page(
        r#"<rect id="box" x="20" y="10" width="30" height="30" fill="none" stroke="black" data-tactile="vibrate(width: 2mm)"/>"#,
    ));
    let b = bundle(&c);
    let m = masks(b);
    assert_eq!(m.len(), 1, "{:?}", c.diagnostics);
    assert!(matches!(m[0].kind, MaskKind::Vibration { freq } if freq.0 == 50_000));
    // On the outline: full; 0.8 mm from it (inside the 1 mm half band): full; 2 mm off: zero; centre: zero.
    assert!(sample(m[0], 20.0, 25.0) > 0.99);
    assert!(sample(m[0], 20.8, 25.0) > 0.99);
    assert!(sample(m[0], 22.0, 25.0) < 0.01);
    assert!(sample(m[0], 35.0, 25.0) == 0.0);
    // Stored from the band's bounding box (19..51 x 9..41 mm), give or take two pitches.
    assert!(covers_tightly(m[0], 19.0, 51.0), "{:?}", lattice_x(m[0]));
}

#[test]
fn grating_fills_the_shape_with_its_parameters() {
    let c = compile(&page(
        r#"<circle id="lake" cx="50" cy="30" r="12" fill="blue" data-tactile="grating(wavelength: 6mm, angle: 0deg, amplitude: 80%)"/>"#,
    ));
    let m = masks(bundle(&c));
    assert_eq!(m.len(), 1);
    let MaskKind::Grating { wavelength, angle_deg } = m[0].kind else { panic!("{:?}", m[0].kind) };
    assert_eq!((wavelength.0, angle_deg, m[0].amplitude), (6.0, 0.0, 0.8));
    assert!(sample(m[0], 50.0, 30.0) > 0.99);
    assert!(sample(m[0], 50.0 + 11.5, 30.0) > 0.99);
    assert_eq!(sample(m[0], 50.0 + 12.5, 30.0), 0.0);
    // A circle's layer starts at its 24 mm box.
    assert!(covers_tightly(m[0], 38.0, 62.0), "{:?}", lattice_x(m[0]));
}

#[test]
fn tactile_icon_keeps_grating_out_of_the_vibrating_band() {
    let c = compile(&page(
        r#"<rect id="icon" x="10" y="10" width="30" height="30" data-tactile="vibrate(); grating(wavelength: 6mm, angle: 0deg)"/>"#,
    ));
    let m = masks(bundle(&c));
    assert_eq!(m.len(), 2);
    let (vib, grat) = (m[0], m[1]);
    // 0.5 mm inside the edge the band vibrates and the grating is off; deep inside, the reverse.
    assert!(sample(vib, 10.5, 25.0) > 0.99 && sample(grat, 10.5, 25.0) < 0.01);
    assert!(sample(vib, 25.0, 25.0) == 0.0 && sample(grat, 25.0, 25.0) > 0.99);
    assert!(with_code(&c, "T0410").is_empty(), "{:?}", c.diagnostics);
}

#[test]
fn a_grated_sea_is_not_felt_under_the_opaque_land_painted_over_it() {
    // A map as drawn: the sea is one rectangle under everything, the land is painted over it.
    let c = compile(&page(
        r##"<rect id="sea" x="5" y="5" width="90" height="50" fill="#a6cee3" data-tactile="grating(wavelength: 3mm, angle: 90deg)"/>
<rect id="land" x="20" y="15" width="30" height="30" fill="#ccebc5" data-tactile="grating(wavelength: 9mm, angle: 0deg)"/>
<circle id="isle" cx="75" cy="30" r="8" fill="white"/>"##,
    ));
    let m = masks(bundle(&c));
    let (sea, land) = (m[0], m[1]);
    let MaskKind::Grating { wavelength, .. } = sea.kind else { panic!("{:?}", sea.kind) };
    assert_eq!(wavelength.0, 3.0);
    // The sea is felt on open water, and not under the land nor under the unstyled white isle.
    assert!(sample(sea, 10.0, 30.0) > 0.99);
    assert!(sample(sea, 35.0, 30.0) == 0.0 && sample(land, 35.0, 30.0) > 0.99);
    assert!(sample(sea, 75.0, 30.0) == 0.0);
    // The cut follows the land's edge: 0.3 mm either side of it.
    assert!(sample(sea, 19.7, 30.0) > 0.99 && sample(sea, 20.3, 30.0) == 0.0);
    assert!(sample(sea, 75.0 + 8.3, 30.0) > 0.99 && sample(sea, 75.0 + 7.7, 30.0) == 0.0);
    assert!(with_code(&c, "T0410").is_empty(), "{:?}", c.diagnostics);
}

#[test]
fn a_fill_between_two_shapes_of_one_style_hides_nothing_and_the_overlap_is_reported() {
    // `mid` is painted over `low` and under `top`, which share a style: the
    // style is one layer, which cannot be both above and below `mid`.
    let c = compile(&page(
        r##"<rect id="low" x="10" y="10" width="30" height="30" fill="#a6cee3" data-tactile="grating(wavelength: 3mm, angle: 90deg)"/>
<rect id="mid" x="20" y="20" width="30" height="30" fill="#ccebc5" data-tactile="grating(wavelength: 9mm, angle: 0deg)"/>
<rect id="top" x="45" y="25" width="20" height="20" fill="#a6cee3" data-tactile="grating(wavelength: 3mm, angle: 90deg)"/>"##,
    ));
    let m = masks(bundle(&c));
    assert!(sample(m[0], 30.0, 30.0) > 0.99 && sample(m[1], 30.0, 30.0) > 0.99);
    assert!(!with_code(&c, "T0410").is_empty(), "{:?}", c.diagnostics);
}

#[test]
fn dots_along_a_path_never_overlap() {
    let c = compile(&page(
        r#"<path id="route" d="M 10 30 L 90 30" stroke="black" data-tactile="dots(radius: 1mm, spacing: 4mm)"/>"#,
    ));
    let t = dots(bundle(&c), DotKind::Outline).expect("outline dots");
    // 80 mm at 4 mm: 21 dots including both ends.
    assert_eq!(t.dots.len(), 21);
    let mut xs: Vec<f32> = t.dots.iter().map(|d| d.x.0).collect();
    xs.sort_by(f32::total_cmp);
    assert!((xs[0] - 10.0).abs() < 1e-4 && (xs[20] - 90.0).abs() < 1e-4);
    for w in xs.windows(2) {
        assert!((w[1] - w[0] - 4.0).abs() < 1e-3);
    }
    assert!(t.dots.iter().all(|d| d.radius.0 == 1.0 && d.source == Some(0)));
}

#[test]
fn point_symbols_give_one_dot_each_at_their_centres() {
    let c = compile(&page(
        r#"<g id="towns" data-tactile="dot(radius: 1.5mm)">
  <circle cx="20" cy="20" r="1"/><ellipse cx="70" cy="40" rx="2" ry="1"/>
</g>"#,
    ));
    let t = dots(bundle(&c), DotKind::Symbol).expect("symbol dots");
    let mut got: Vec<(f32, f32)> = t.dots.iter().map(|d| (d.x.0, d.y.0)).collect();
    got.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert_eq!(got.len(), 2);
    assert!((got[0].0 - 20.0).abs() < 1e-3 && (got[0].1 - 20.0).abs() < 1e-3);
    assert!((got[1].0 - 70.0).abs() < 1e-3 && (got[1].1 - 40.0).abs() < 1e-3);
}

#[test]
fn markers_are_point_symbols() {
    let c = compile(&page(
        r#"<defs><marker id="m" markerWidth="4" markerHeight="4" refX="2" refY="2" markerUnits="userSpaceOnUse"><circle cx="2" cy="2" r="2"/></marker></defs>
<polyline id="stops" points="10,10 40,10 40,40" fill="none" stroke="black" marker-start="url(#m)" marker-mid="url(#m)" marker-end="url(#m)" data-tactile="dot()"/>"#,
    ));
    let t = dots(bundle(&c), DotKind::Symbol).expect("symbol dots");
    let mut got: Vec<(f32, f32)> = t.dots.iter().map(|d| (d.x.0, d.y.0)).collect();
    got.sort_by(|a, b| (a.0, a.1).partial_cmp(&(b.0, b.1)).unwrap());
    let want = [(10.0, 10.0), (40.0, 10.0), (40.0, 40.0)];
    assert_eq!(got.len(), 3, "{got:?}");
    for (g, w) in got.iter().zip(want) {
        assert!((g.0 - w.0).abs() < 0.01 && (g.1 - w.1).abs() < 0.01, "{got:?}");
    }
}

#[test]
fn braille_follows_the_text_not_the_font() {
    // "ab": a = dot 1, b = dots 1 2 — three dots; the first cell's left edge at x = 10, baseline y = 40.
    let c = compile(&page(r#"<text id="label" x="10" y="40" font-size="4" data-tactile="braille()">ab</text>"#));
    let t = dots(bundle(&c), DotKind::Braille).expect("braille dots");
    let mut got: Vec<(f32, f32)> = t.dots.iter().map(|d| (d.x.0, d.y.0)).collect();
    got.sort_by(|a, b| (a.0, a.1).partial_cmp(&(b.0, b.1)).unwrap());
    let r = 0.72f32;
    let top = 40.0 - r - 2.0 * 2.34;
    let want = [(10.0 + r, top), (10.0 + r + 6.2, top), (10.0 + r + 6.2, top + 2.34)];
    assert_eq!(got.len(), 3, "{got:?}");
    for (g, w) in got.iter().zip(want) {
        assert!((g.0 - w.0).abs() < 1e-3 && (g.1 - w.1).abs() < 1e-3, "{got:?} vs {want:?}");
    }
    assert!(t.dots.iter().all(|d| (d.radius.0 - 0.72).abs() < 1e-6));
}

#[test]
fn building_twice_gives_identical_bytes() {
    let svg =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/compiler/golden/every-kind.svg")).unwrap();
    let a = bundle(&compile(&svg)).to_bytes().unwrap();
    let b = bundle(&compile(&svg)).to_bytes().unwrap();
    assert_eq!(a, b);
}

#[test]
fn every_layer_kind_in_one_scene_gives_one_chunk_per_kind_and_shape() {
    let svg =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/compiler/golden/every-kind.svg")).unwrap();
    let b = bundle(&compile(&svg)).clone();
    let tags: Vec<String> = b.chunks.iter().map(|c| c.tag().to_string()).collect();
    assert_eq!(tags, ["VDST", "GDST", "DOTS", "DOTS", "DOTS", "PROV", "FOOT"]);
    for kind in [DotKind::Outline, DotKind::Symbol, DotKind::Braille] {
        assert!(dots(&b, kind).is_some(), "{kind:?}");
    }
}

#[test]
fn only_what_the_scene_needs() {
    let b = bundle(&compile(&page(r#"<circle cx="30" cy="30" r="12" data-tactile="grating()"/>"#))).clone();
    let tags: Vec<String> = b.chunks.iter().map(|c| c.tag().to_string()).collect();
    assert_eq!(tags, ["GDST", "PROV", "FOOT"]);
}

#[test]
fn precedence_inherited_then_style_sheet_then_attribute() {
    use taxel_compiler::{CompileOptions, StyleSheet, svg::compile_svg};
    let svg = page(
        r#"<g data-tactile="vibrate()">
  <rect id="a" x="5" y="5" width="25" height="25"/>
  <rect id="b" x="40" y="5" width="25" height="25" data-tactile="dot()"/>
  <rect id="c" x="5" y="35" width="20" height="20"/>
  <rect id="d" x="40" y="35" width="20" height="20" data-tactile="none"/>
</g>"#,
    );
    let sheet = "[[rule]]\nid = \"a\"\ntactile = \"grating(wavelength: 6mm, angle: 0deg)\"\n\n[[rule]]\nid = \"b\"\ntactile = \"grating()\"\n";
    let opts =
        CompileOptions { style: Some(StyleSheet::parse(sheet, "s.toml").unwrap()), ..CompileOptions::new(stress2()) };
    let c = no_internal_error(compile_svg(&svg, &opts));
    let b = bundle(&c);
    let prov = b.provenance().unwrap();
    let id_of = |s: Option<u32>| prov.entries[s.unwrap() as usize].id.clone();
    let kinds: Vec<(String, &str)> = masks(b)
        .iter()
        .map(|m| {
            (
                id_of(m.sources.first().copied()),
                if matches!(m.kind, MaskKind::Grating { .. }) { "grating" } else { "vibrate" },
            )
        })
        .collect();
    // a: the sheet beats the inherited vibrate; c: inherits it; b: its attribute beats the sheet; d: none.
    assert_eq!(kinds, [("a".to_string(), "grating"), ("c".to_string(), "vibrate")]);
    let sym = dots(b, DotKind::Symbol).unwrap();
    assert_eq!(sym.dots.iter().map(|d| id_of(d.source)).collect::<Vec<_>>(), ["b"]);
}

#[test]
fn width_mm_scales_a_drawing_without_size() {
    use taxel_compiler::{CompileOptions, svg::compile_svg};
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 100"><rect x="50" y="25" width="100" height="50" data-tactile="grating()"/></svg>"#;
    let opts = CompileOptions { width_mm: Some(80.0), ..CompileOptions::new(stress2()) };
    let c = no_internal_error(compile_svg(svg, &opts));
    let m = masks(bundle(&c))[0];
    // 200 user units = 80 mm: the rectangle spans 20..60 mm.
    assert!(covers_tightly(m, 20.0, 60.0), "{:?}", lattice_x(m));
    assert!(sample(m, 20.05, 20.0) == 1.0 && sample(m, 19.95, 20.0) == 0.0);
    assert!(with_code(&c, "T0201").is_empty());
}

/// The default resolution's promise (docs/annotations.md, "Mask resolution"):
/// the bilinear 50 % contour of a straight edge lies within the carrier's
/// 13 µm position resolution of the true edge, and a sample more than a
/// pixel and a half from the edge reads exactly.
#[test]
fn default_resolution_places_edges_within_13_micrometres() {
    for edge in [20.0, 20.013, 20.025, 20.037, 20.05, 20.071, 20.094] {
        let c =
            compile(&page(&format!(r#"<rect x="{edge}" y="10" width="30" height="30" data-tactile="grating()"/>"#)));
        let m = masks(bundle(&c))[0];
        // Scan along y = 25 mm for the 0.5 crossing, finely.
        let mut x = edge - 0.5;
        while sample(m, x, 25.0) < 0.5 {
            x += 0.0005;
        }
        assert!((x - edge).abs() < 0.013, "edge at {edge}: crossing at {x}");
        assert_eq!(sample(m, edge + 0.15, 25.0), 1.0);
        assert_eq!(sample(m, edge - 0.15, 25.0), 0.0);
    }
}

#[test]
fn clip_paths_and_transforms_are_honoured() {
    let c = compile(&page(
        r#"<defs><clipPath id="half"><rect x="0" y="0" width="30" height="60"/></clipPath></defs>
<g clip-path="url(#half)"><g transform="translate(10 10) scale(2)"><rect id="r" width="20" height="10" data-tactile="grating()"/></g></g>"#,
    ));
    let m = masks(bundle(&c))[0];
    // The rectangle spans 10..50 x 10..30 mm after the transform; the clip keeps x < 30.
    assert!(sample(m, 20.0, 20.0) > 0.99);
    assert_eq!(sample(m, 40.0, 20.0), 0.0);
    assert!(sample(m, 29.95, 20.0) == 1.0 && sample(m, 30.05, 20.0) == 0.0);
}

/// A braille label inside a grated region clears the texture over the box
/// of its dots and the design rules' gap (3.2 mm) around it, where braille
/// amid the texture would read as more texture and their sum would clamp
/// (T0410); beyond it the texture goes on.
#[test]
fn braille_clears_the_texture_around_itself() {
    let c = compile(&page(
        r#"<rect x="5" y="5" width="90" height="50" data-tactile="grating()"/>
<text x="30" y="30" data-tactile="braille()">ab</text>"#,
    ));
    assert!(with_code(&c, "T0410").is_empty(), "{:#?}", c.diagnostics);
    let b = bundle(&c);
    let grating = masks(b);
    assert_eq!(grating.len(), 1);
    let g = grating[0];
    let d = dots(b, DotKind::Braille).expect("braille");
    let r = d.dots[0].radius.0 as f64;
    assert!(d.dots.iter().all(|p| sample(g, p.x.0 as f64, p.y.0 as f64) == 0.0), "texture under a dot");
    // The dots' box: "ab" (dot 1; dots 1 and 2) is two cells from x 30, the
    // lowest of its three dot rows on y 30: dots 1 and 2 in its top two rows.
    let (x0, y0) = (30.0, 30.0 - 2.0 * 2.34 - 2.0 * r);
    let (x1, y1) = (30.0 + 6.2 + 2.0 * r, 30.0 - 2.34);
    let (mx, my) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    for (inside, outside) in [
        ((x0 - 2.9, my), (x0 - 3.5, my)),
        ((x1 + 2.9, my), (x1 + 3.5, my)),
        ((mx, y0 - 2.9), (mx, y0 - 3.5)),
        ((mx, y1 + 2.9), (mx, y1 + 3.5)),
    ] {
        assert_eq!(sample(g, inside.0, inside.1), 0.0, "texture at {inside:?}, in the gap");
        assert_eq!(sample(g, outside.0, outside.1), 1.0, "no texture at {outside:?}, past the gap");
    }
}
