//! One test per diagnostic code: the drawing that triggers it, and where it points.

use taxel_compiler::{CompileOptions, Severity, compile_svg};
use taxel_format::profiles;

use crate::common::*;

fn codes(svg: &str) -> Vec<&'static str> {
    compile(svg).diagnostics.iter().map(|d| d.code).collect()
}

fn assert_code(svg: &str, code: &str, severity: Severity) {
    let c = compile(svg);
    let d = with_code(&c, code);
    assert!(!d.is_empty(), "expected {code}, got {:#?}", c.diagnostics);
    assert!(d.iter().all(|d| d.severity == severity), "{code}: {d:#?}");
}

#[test]
fn malformed_annotation_points_at_line_and_column() {
    let svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"50mm\" height=\"50mm\">\n  <rect width=\"30\" height=\"30\"\n        data-tactile=\"vibrate(width 2mm)\"/>\n</svg>";
    let c = compile(svg);
    let d = with_code(&c, "T0101");
    assert_eq!(d.len(), 1, "{:#?}", c.diagnostics);
    // Line 3: eight spaces and `data-tactile="` take 22 columns, so the value starts at column 23;
    // the offending `2` is its 15th character.
    assert_eq!((d[0].line, d[0].column), (Some(3), Some(23 + 14)));
    assert!(d[0].message.contains("expected `:`"), "{}", d[0].message);
    assert_eq!(d[0].element.as_deref(), Some("svg/rect[1]"));
    assert!(d[0].render("map.svg").starts_with("map.svg:3:37: error[T0101]"), "{}", d[0].render("map.svg"));
}

#[test]
fn column_counts_through_entities_in_the_attribute() {
    let svg = page(r#"<rect width="30" height="30" data-tactile="vibrate(width:&#32;2)"/>"#);
    let c = compile(&svg);
    let d = with_code(&c, "T0104");
    let line = svg.lines().nth(1).unwrap();
    let col = line.find("2)").unwrap() as u32 + 1;
    assert_eq!(d[0].column, Some(col), "{:#?}", c.diagnostics);
}

#[test]
fn each_annotation_error_has_its_code() {
    for (a, code) in [
        ("vibrate(", "T0101"),
        ("wobble()", "T0102"),
        ("grating(colour: 2mm)", "T0103"),
        ("grating(wavelength: 2)", "T0104"),
        ("vibrate(amplitude: 3)", "T0105"),
        ("dot(radius: 1mm, radius: 1mm)", "T0106"),
        // (T0107 is retired: `braille(grade: 2)` is contracted braille through liblouis.)
        ("braille(grade: 3)", "T0105"),
    ] {
        let svg = page(&format!(r#"<rect width="30" height="30" data-tactile="{a}"/>"#));
        assert_code(&svg, code, Severity::Error);
    }
}

#[test]
fn layer_label_errors_point_inside_the_label() {
    let svg = page(
        r#"<g inkscape:groupmode="layer" inkscape:label="tactile: grating(angle: 0)"><rect width="30" height="30"/></g>"#,
    );
    let c = compile(&svg);
    let d = with_code(&c, "T0104");
    let line = svg.lines().nth(1).unwrap();
    assert_eq!(d[0].column, Some(line.find("0)").unwrap() as u32 + 1), "{:#?}", c.diagnostics);
}

#[test]
fn device_and_element_mismatches_are_warnings() {
    assert_code(&page(r#"<path d="M10 10 L 80 10" data-tactile="brush()"/>"#), "T0120", Severity::Warning);
    assert_code(
        &page(r#"<rect x="5" y="5" width="30" height="30" data-tactile="braille(); vibrate()"/>"#),
        "T0121",
        Severity::Warning,
    );
}

#[test]
fn document_problems() {
    assert_code("<svg><rect></svg>", "T0200", Severity::Error);
    assert_code("<html/>", "T0200", Severity::Error);
    let no_size = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 100"><rect x="20" y="20" width="80" height="60" data-tactile="vibrate()"/></svg>"#;
    assert_code(no_size, "T0201", Severity::Note);
    let big = r#"<svg xmlns="http://www.w3.org/2000/svg" width="300mm" height="100mm" viewBox="0 0 300 100"><rect x="20" y="20" width="80" height="60" data-tactile="vibrate()"/></svg>"#;
    assert_code(big, "T0202", Severity::Warning);
    let opts = CompileOptions { width_mm: Some(80.0), ..CompileOptions::new(stress2()) };
    let c = no_internal_error(compile_svg(
        &page(r#"<rect x="20" y="10" width="30" height="30" data-tactile="vibrate()"/>"#),
        &opts,
    ));
    assert_eq!(with_code(&c, "T0203")[0].severity, Severity::Note);
    let opts = CompileOptions { resolution_px_per_mm: Some(-1.0), ..CompileOptions::new(stress2()) };
    let c = no_internal_error(compile_svg(&page(r#"<rect width="30" height="30" data-tactile="vibrate()"/>"#), &opts));
    assert_eq!(with_code(&c, "T0204")[0].severity, Severity::Error);
}

/// Characters without braille are named once each, in the order they come
/// in the text (an Arabic or CJK label reads as written); a text with none
/// at all gets that one warning, not a second one saying it is empty.
#[test]
fn characters_without_braille_are_named_in_their_order() {
    // (القاهرة, Cairo: its second alef is a repeat.)
    let c = compile(&page(r#"<text x="10" y="30" data-tactile="braille()">北京 · القاهرة 北京</text>"#));
    let w = with_code(&c, "T0304");
    assert_eq!(w.len(), 1, "{:#?}", c.diagnostics);
    assert!(
        w[0].message.contains("\"北京·القهرة\"") && w[0].message.contains("the text is left out"),
        "{}",
        w[0].message
    );
    assert!(with_code(&c, "T0301").is_empty(), "{:#?}", c.diagnostics);
    let c = compile(&page(r#"<text x="10" y="30" data-tactile="braille()">Søndre Zürich ø</text>"#));
    let w = with_code(&c, "T0304");
    assert!(w[0].message.contains("\"ø\"; these characters are left out"), "{}", w[0].message);
    // Punctuation alone says nothing: a label whose letters all lack braille
    // is left out whole, its parentheses with it (and the drawing, with
    // nothing else, has nothing tactile).
    let c = compile(&page(
        r#"<text x="10" y="30" data-tactile="braille()">Осадки (мм)</text>
        <rect x="10" y="40" width="30" height="20" data-tactile="grating()"/>"#,
    ));
    let w = with_code(&c, "T0304");
    assert!(w.len() == 1 && w[0].message.contains("the text is left out"), "{:#?}", c.diagnostics);
    let bundle = c.bundle.as_ref().expect("the grating builds");
    assert!(!bundle.chunks.iter().any(|ch| matches!(ch, taxel_format::Chunk::Dots(_))), "no braille dots");
    // With letters of its own it keeps its punctuation.
    let c = compile(&page(r#"<text x="10" y="30" data-tactile="braille()">Осадки (mm)</text>"#));
    assert!(with_code(&c, "T0304")[0].message.contains("these characters are left out"), "{:#?}", c.diagnostics);
    assert!(c.bundle.as_ref().is_some_and(|b| b.chunks.iter().any(|ch| matches!(ch, taxel_format::Chunk::Dots(_)))));
}

/// Inkscape 0.92's flowed text is not SVG and no renderer draws it: taxel
/// reads it as Inkscape shows it (`drawing.rs` checks where). One whose
/// frame it cannot read says what is lost and how to keep it; SVG 2 text in
/// a shape (Inkscape 1) is read as text.
#[test]
fn inkscape_flowed_text_is_read_or_says_it_is_left_out() {
    let c = compile(&page(
        r#"<rect x="10" y="10" width="30" height="30" data-tactile="grating()"/>
<flowRoot id="flow1" data-tactile="braille()"><flowRegion><g/></flowRegion><flowPara>Lake</flowPara><flowPara>Tana</flowPara></flowRoot>
<flowRoot id="flow2" style="font-size:4px" data-tactile="braille()"><flowRegion><rect x="50" y="40" width="40" height="15"/></flowRegion><flowPara>a</flowPara></flowRoot>
<text id="river" x="50" y="20" style="font-size:5px;shape-inside:url(#box)" data-tactile="braille()"><tspan>b</tspan></text>
<rect id="box" x="50" y="10" width="40" height="15" fill="none"/>
<g inkscape:groupmode="layer" style="display:none"><flowRoot id="off"><flowRegion><g/></flowRegion><flowPara>Hidden</flowPara></flowRoot></g>"#,
    ));
    // (The hidden layer's flowed text is not drawn: no word of it.)
    let w = with_code(&c, "T0306");
    assert_eq!(w.len(), 1, "{:#?}", c.diagnostics);
    assert!(w[0].message.contains("\"Lake Tana\" is left out"), "{}", w[0].message);
    assert_eq!((w[0].element.as_deref(), w[0].line), (Some("flow1"), Some(3)));
    assert!(w[0].help.as_deref().unwrap_or("").contains("Convert to Text"));
    // "a" (dot 1) from the flowed text's frame, one font size down; "b"
    // (dots 1 2) from the text in a shape: each dot 1 is at its cell's left.
    let d = dots(bundle(&c), taxel_format::DotKind::Braille).expect("braille for both texts");
    let r = d.dots[0].radius.0;
    let lefts: Vec<(f32, f32)> = d.dots.iter().filter(|p| p.x.0 - r < 50.01).map(|p| (p.x.0 - r, p.y.0 + r)).collect();
    let dot = 2.34f32;
    assert!(lefts.iter().any(|&(x, y)| (x - 50.0).abs() < 0.01 && (y - (44.0 - 2.0 * dot)).abs() < 0.01), "{lefts:?}");
    assert!(lefts.iter().any(|&(x, y)| (x - 50.0).abs() < 0.01 && (y - (20.0 - 2.0 * dot)).abs() < 0.01), "{lefts:?}");
}

/// A multilingual drawing (Wikimedia's maps) holds each label once per
/// language in a `<switch>`: only the child for the reader's language is
/// drawn, texts (which taxel places itself) as shapes (which usvg draws),
/// and the others make no braille and no warning.
#[test]
fn a_switch_draws_the_child_for_the_readers_language() {
    let svg = page(
        r#"<switch data-tactile="braille()">
  <text id="fr" x="10" y="20" systemLanguage="fr">Lac</text>
  <text id="de" x="10" y="35" systemLanguage="de,de-CH">See</text>
  <text id="en" x="10" y="50">Lake</text>
</switch>
<switch>
  <rect id="fr-box" x="60" y="10" width="20" height="20" systemLanguage="fr-CA" data-tactile="grating()"/>
  <rect id="other-box" x="60" y="40" width="20" height="20" data-tactile="grating()"/>
</switch>"#,
    );
    let drawn = |languages: &[&str]| {
        let opts = CompileOptions {
            languages: languages.iter().map(|l| l.to_string()).collect(),
            ..CompileOptions::new(stress2())
        };
        let c = no_internal_error(compile_svg(&svg, &opts));
        assert!(c.diagnostics.iter().all(|d| d.code != "T0301"), "{languages:?}: {:#?}", c.diagnostics);
        let b = bundle(&c);
        let prov = b
            .chunks
            .iter()
            .find_map(|ch| match ch {
                taxel_format::Chunk::Provenance(p) => Some(p.entries.iter().map(|e| e.id.clone()).collect::<Vec<_>>()),
                _ => None,
            })
            .unwrap_or_default();
        // The braille's height on the page says which text it is.
        let ys: Vec<f32> =
            dots(b, taxel_format::DotKind::Braille).map_or(vec![], |t| t.dots.iter().map(|d| d.y.0).collect());
        let text_line = ys.iter().all(|y| *y < 21.0) as u8
            + 2 * ys.iter().all(|y| *y > 21.0 && *y < 36.0) as u8
            + 4 * ys.iter().all(|y| *y > 36.0) as u8;
        (prov, text_line)
    };
    let (prov, line) = drawn(&["en"]);
    assert_eq!(
        (line, prov.contains(&"en".to_string()), prov.contains(&"other-box".to_string())),
        (4, true, true),
        "{prov:?}"
    );
    assert!(!prov.iter().any(|p| p == "fr" || p == "de" || p == "fr-box"), "{prov:?}");
    // `fr` takes a child for `fr-CA` too (a longer tag of it).
    let (prov, line) = drawn(&["fr"]);
    assert_eq!(
        (line, prov.contains(&"fr".to_string()), prov.contains(&"fr-box".to_string())),
        (1, true, true),
        "{prov:?}"
    );
    assert!(!prov.iter().any(|p| p == "en" || p == "de" || p == "other-box"), "{prov:?}");
    // A longer tag of the reader's does not take a shorter one: `de-AT` alone
    // matches neither `de` nor `de-CH` (the system's locale gives `de` too).
    assert_eq!(drawn(&["de-AT"]).1, 4);
    assert_eq!(drawn(&["de-AT", "de"]).1, 2);
    // Outside a `<switch>` an element whose language is not the reader's
    // is not drawn either (usvg's rule for shapes).
    let svg = page(
        r#"<text x="10" y="20" systemLanguage="de" data-tactile="braille()">Weg</text>
<g systemLanguage="de"><text x="10" y="40" data-tactile="braille()">Pfad</text></g>
<rect x="60" y="10" width="20" height="20" data-tactile="grating()"/>"#,
    );
    for (lang, braille) in [("en", 0), ("de", 2)] {
        let opts = CompileOptions { languages: vec![lang.to_string()], ..CompileOptions::new(stress2()) };
        let c = no_internal_error(compile_svg(&svg, &opts));
        let lines = dots(bundle(&c), taxel_format::DotKind::Braille).map_or(0, |t| {
            (t.dots.iter().any(|d| d.y.0 < 21.0) as usize) + (t.dots.iter().any(|d| d.y.0 > 21.0) as usize)
        });
        assert_eq!(lines, braille, "{lang}: {:#?}", c.diagnostics);
        // Another language's label is left out by design, not "not drawn".
        assert!(c.diagnostics.iter().all(|d| d.code != "T0301"), "{lang}: {:#?}", c.diagnostics);
    }
}

/// Text along a path (a street's name on a map) becomes braille starting
/// where the path starts (braille does not bend), the path's own transform
/// applied, for `xlink:href`, `href` and SVG 2's `path`; it was left out.
#[test]
fn text_on_a_path_starts_its_braille_where_the_path_starts() {
    for text_path in [
        r##"<textPath xlink:href="#road">main</textPath>"##,
        r##"<textPath href="#road">main</textPath>"##,
        r#"<textPath path="M 25 30 H 85">main</textPath>"#,
    ] {
        let c = compile(&page(&format!(
            r#"<path id="road" d="M 20 30 H 80" transform="translate(5 0)" fill="none" stroke="black"/>
<text xmlns:xlink="http://www.w3.org/1999/xlink" data-tactile="braille()">{text_path}</text>"#
        )));
        let b = bundle(&c);
        let d = dots(b, taxel_format::DotKind::Braille).expect("braille for the text on the path");
        let x0 = d.dots.iter().map(|d| d.x.0).fold(f32::INFINITY, f32::min);
        let y1 = d.dots.iter().map(|d| d.y.0).fold(f32::NEG_INFINITY, f32::max);
        // The first dot's left edge at the path's start, x = 25; the
        // cells' lowest dots rest on its baseline, y = 30.
        let r = d.dots[0].radius.0;
        assert!((x0 - r - 25.0).abs() < 0.01 && (y1 + r - 30.0).abs() < 0.01, "{text_path}: {x0}, {y1}");
    }
}

/// Lines written as `<tspan x="…" dy="1.2em">` (d3's and many editors'
/// multi-line labels) are braille lines that far apart, and a `dx` or `dy`
/// on the text (d3's axis labels, `dy="0.71em"`) moves its braille: they
/// were all placed on the first line's baseline, ran into each other and
/// were left out.
#[test]
fn dx_and_dy_move_the_braille_of_a_text_and_its_lines() {
    let c = compile(&page(
        r#"<g data-tactile="braille()" font-size="10">
<text x="10" y="15"><tspan x="10" dy="0">ab</tspan><tspan x="10" dy="1.2em">c</tspan><tspan x="10" dy="1em" font-size="20">a</tspan></text>
<text x="60" y="20" dx="5" dy="0.5em">d</text>
<text x="60" y="30" style="font: italic 20px/1.5 sans-serif"><tspan x="60" dy="1em">a</tspan></text>
</g>"#,
    ));
    let b = bundle(&c);
    let d = dots(b, taxel_format::DotKind::Braille).expect("braille for the texts");
    let r = d.dots[0].radius.0;
    // Each run's first dot's centre less r, and its lowest dots' centres plus
    // r, among the dots in the box x0..x1, y0..y1.
    let run = |x0: f32, x1: f32, y0: f32, y1: f32| {
        let inside: Vec<_> = d.dots.iter().filter(|p| p.x.0 > x0 && p.x.0 < x1 && p.y.0 > y0 && p.y.0 < y1).collect();
        let left = inside.iter().map(|p| p.x.0).fold(f32::INFINITY, f32::min) - r;
        let base = inside.iter().map(|p| p.y.0).fold(f32::NEG_INFINITY, f32::max) + r;
        (inside.len(), left, base)
    };
    // "ab" on y = 15 (a = dot 1, b = dots 1 2); "c" (dots 1 4) 1.2 em = 12
    // lower; "a" one em lower still, in its own font size (20): y = 47;
    // "d" (dots 1 4 5) at x = 60 + 5, y = 20 + 5; "a" at x = 60, one em
    // below y = 30 in the size its style's `font` gives. The lowest dot of a cell
    // whose lowest row is empty is a pitch (2.34 mm) or two above the baseline.
    let dot = 2.34f32;
    let near = |got: (usize, f32, f32), want: (usize, f32, f32)| {
        got.0 == want.0 && (got.1 - want.1).abs() < 0.01 && (got.2 - want.2).abs() < 0.01
    };
    let ab = run(0.0, 40.0, 0.0, 16.0);
    assert!(near(ab, (3, 10.0, 15.0 - dot)), "ab: {ab:?} in {d:?}");
    let c2 = run(0.0, 40.0, 16.0, 28.0);
    assert!(near(c2, (2, 10.0, 27.0 - 2.0 * dot)), "c: {c2:?} in {d:?}");
    let a3 = run(0.0, 40.0, 28.0, 60.0);
    assert!(near(a3, (1, 10.0, 47.0 - 2.0 * dot)), "a: {a3:?} in {d:?}");
    let d4 = run(50.0, 100.0, 0.0, 28.0);
    assert!(near(d4, (3, 65.0, 25.0 - dot)), "d: {d4:?} in {d:?}");
    let a5 = run(50.0, 100.0, 28.0, 60.0);
    assert!(near(a5, (1, 60.0, 50.0 - 2.0 * dot)), "a: {a5:?} in {d:?}");
    assert_eq!(d.dots.len(), 3 + 2 + 1 + 3 + 1, "{d:?}");
}

/// A text inside a nested `<svg>` (a chart or pictogram pasted into a page)
/// is braille where the nested viewport puts it: its `x`, `y`, and its
/// `viewBox` scaled onto its size, also under a group inside it. It was
/// placed at its own coordinates, as if the viewport were not there.
#[test]
fn a_text_in_a_nested_svg_is_placed_through_its_viewport() {
    let c = compile(&page(
        r#"<svg x="10" y="10" width="40" height="20" viewBox="0 0 20 10" data-tactile="braille()">
<text x="2" y="5">a</text>
<g transform="translate(10 0)"><text x="2" y="5">b</text></g>
</svg>
<svg x="60" y="30" width="20" height="20" viewBox="0 0 40 20" data-tactile="braille()"><text x="0" y="20">c</text></svg>"#,
    ));
    let d = dots(bundle(&c), taxel_format::DotKind::Braille).expect("braille for the texts");
    let r = d.dots[0].radius.0;
    let dot = 2.34f32;
    // Each dot as (its cell's left edge + its column's offset, the baseline
    // less its row's height): "a" (dot 1) at (10 + 2·2, 10 + 5·2) = (14, 20);
    // "b" (dots 1 2) at (10 + 12·2, 20) = (34, 20); "c" (dots 1 4): the 40 x
    // 20 box meets the 20 x 20 viewport at scale 0.5, centred (xMidYMid), so
    // 5 down: (60, 30 + 5 + 20·0.5) = (60, 45).
    let mut want = vec![
        (14.0, 20.0 - 2.0 * dot),
        (34.0, 20.0 - 2.0 * dot),
        (34.0, 20.0 - dot),
        (60.0, 45.0 - 2.0 * dot),
        (60.0 + dot, 45.0 - 2.0 * dot),
    ];
    let mut got: Vec<(f32, f32)> = d.dots.iter().map(|p| (p.x.0 - r, p.y.0 + r)).collect();
    let order = |a: &(f32, f32), b: &(f32, f32)| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1));
    got.sort_by(order);
    want.sort_by(order);
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(&want) {
        assert!((g.0 - w.0).abs() < 0.01 && (g.1 - w.1).abs() < 0.01, "{got:?} against {want:?}");
    }
}

/// A text inside a `<symbol>` is braille where each `<use>` shows it, through
/// the symbol's viewBox mapped onto the `<use>`'s size; it was left out
/// (and, outside `<defs>`, would have been placed at its own coordinates).
#[test]
fn a_text_in_a_symbol_is_braille_where_each_use_shows_it() {
    let c = compile(&page(
        r##"<symbol id="exit" viewBox="0 0 20 10"><text x="2" y="8">a</text></symbol>
<use href="#exit" x="10" y="10" width="40" height="20" data-tactile="braille()"/>
<use href="#exit" x="60" y="30" data-tactile="braille()"/>"##,
    ));
    let d = dots(bundle(&c), taxel_format::DotKind::Braille).expect("braille for both uses");
    let r = d.dots[0].radius.0;
    // "a" (dot 1, two pitches above the baseline): at (10 + 2·2, 10 + 8·2) =
    // (14, 26) in the first; in the second, no size given, the viewBox's
    // own (scale 1): (62, 38).
    let mut got: Vec<(f32, f32)> = d.dots.iter().map(|p| (p.x.0 - r, p.y.0 + r + 2.0 * 2.34)).collect();
    got.sort_by(|a, b| a.0.total_cmp(&b.0));
    let want = [(14.0, 26.0), (62.0, 38.0)];
    assert_eq!(got.len(), 2, "{got:?}");
    for (g, w) in got.iter().zip(want) {
        assert!((g.0 - w.0).abs() < 0.01 && (g.1 - w.1).abs() < 0.01, "{got:?}");
    }
}

/// A label matplotlib drew as glyph outlines (its SVG backend's default)
/// carries its text in a comment: it is braille at the glyphs' baseline
/// origin, and its glyphs are no longer shapes of the drawing (they were
/// textured blobs, and every label of a chart was lost). A comment holding
/// mathtext is not taken for the text.
#[test]
fn a_label_drawn_as_glyphs_with_its_text_in_a_comment_is_braille() {
    let label = |said: &str| {
        format!(
            r##"<g id="text_1" data-tactile="braille()" xmlns:xlink="http://www.w3.org/1999/xlink"><!-- {said} -->
<g transform="translate(20 30) scale(0.1 -0.1)"><defs><path id="glyph" d="M 0 0 L 500 0 L 500 700 L 0 700 z"/></defs>
<use xlink:href="#glyph"/><use xlink:href="#glyph" x="600"/></g></g>"##
        )
    };
    let c = compile(&page(&label("ab")));
    let d = dots(bundle(&c), taxel_format::DotKind::Braille).expect("braille for the label");
    let r = d.dots[0].radius.0;
    // "ab": a = dot 1, b = dots 1 2; the first dot's left edge at x = 20, dot 1
    // two pitches above the baseline at y = 30.
    assert_eq!(d.dots.len(), 3, "{d:?}");
    let x0 = d.dots.iter().map(|p| p.x.0).fold(f32::INFINITY, f32::min) - r;
    let y0 = d.dots.iter().map(|p| p.y.0).fold(f32::INFINITY, f32::min) + r + 2.0 * 2.34;
    assert!((x0 - 20.0).abs() < 0.01 && (y0 - 30.0).abs() < 0.01, "{x0}, {y0}");
    // The glyphs are not shapes of the drawing: no "braille() applies to text" for them.
    assert!(c.diagnostics.iter().all(|d| d.code != "T0121"), "{:#?}", c.diagnostics);
    // Mathtext: the glyphs stay shapes (and are said not to be text).
    let c = compile(&page(&label("$x^2$")));
    assert!(c.diagnostics.iter().any(|d| d.code == "T0121"), "{:#?}", c.diagnostics);
    // An axis title turned on its side (`rotate(-90)` before the flip) is a
    // label too, its braille horizontal from the same origin.
    let turned =
        label("ab").replace("translate(20 30) scale(0.1 -0.1)", "translate(20 30) rotate(-90) scale(0.1 -0.1)");
    let c = compile(&page(&turned));
    let d = dots(bundle(&c), taxel_format::DotKind::Braille).expect("braille for the turned label");
    assert_eq!(d.dots.len(), 3, "{d:?}");
    // A drawing someone commented is not a label: a group of shapes (not
    // glyph uses), or glyph uses not mirrored as a font's are.
    for drawing in [
        label("ab").replace(
            r##"<use xlink:href="#glyph"/><use xlink:href="#glyph" x="600"/>"##,
            r#"<rect width="500" height="700"/>"#,
        ),
        label("ab").replace("scale(0.1 -0.1)", "scale(0.1 0.1)"),
    ] {
        let c = compile(&page(&drawing));
        assert!(c.diagnostics.iter().any(|d| d.code == "T0121"), "{drawing}: {:#?}", c.diagnostics);
    }
}

/// A label kept once in `<defs>` and shown by `<use>` is braille where each
/// `<use>` puts it (its transform, then its `x` and `y`), named by the
/// `<use>`; it was left out, and the `<use>`'s annotation with it.
#[test]
fn a_text_shown_by_use_is_braille_where_the_use_puts_it() {
    let c = compile(&page(
        r##"<defs><text id="oak" x="1" y="2">oak</text></defs>
<use id="first" href="#oak" x="20" y="30px" data-tactile="braille()"/>
<g transform="translate(40 0)"><use id="second" xlink:href="#oak" transform="translate(0 10)" x="10" y="30" data-tactile="braille()" xmlns:xlink="http://www.w3.org/1999/xlink"/></g>"##,
    ));
    let b = bundle(&c);
    let d = dots(b, taxel_format::DotKind::Braille).expect("braille for both uses");
    let r = d.dots[0].radius.0;
    // "oak": o = dots 1 3 5, a = 1, k = 1 3; each copy's first dot at its
    // left edge + r, its lowest dots on its baseline.
    let left = |lo: f32, hi: f32| {
        d.dots.iter().filter(|p| p.x.0 > lo && p.x.0 < hi).map(|p| p.x.0).fold(f32::INFINITY, f32::min)
    };
    let base = |lo: f32, hi: f32| {
        d.dots.iter().filter(|p| p.x.0 > lo && p.x.0 < hi).map(|p| p.y.0).fold(f32::NEG_INFINITY, f32::max)
    };
    assert!((left(0.0, 45.0) - r - 21.0).abs() < 0.01 && (base(0.0, 45.0) + r - 32.0).abs() < 0.01, "{d:?}");
    assert!((left(45.0, 100.0) - r - 51.0).abs() < 0.01 && (base(45.0, 100.0) + r - 42.0).abs() < 0.01, "{d:?}");
    assert_eq!(d.dots.len(), 2 * 6);
    // A group of labels kept in `<defs>` (a symbol with its name): each text
    // where the `<use>`, then the group, puts it; the group's annotation
    // styles them.
    let c = compile(&page(
        r##"<defs><g id="town" transform="translate(0 5)" data-tactile="braille()"><circle r="1"/><text x="2" y="0">ab</text><g transform="translate(0 12)"><text x="2" y="0">c</text></g></g></defs>
<use href="#town" x="20" y="20"/>"##,
    ));
    let d = dots(bundle(&c), taxel_format::DotKind::Braille).expect("braille for the group's texts");
    let r = d.dots[0].radius.0;
    // "ab" starting at (22, 25) and "c" at (22, 37): a = dot 1, b = dots 1 2,
    // c = dots 1 4; cells 6.2 mm apart, dots 2.34 mm apart, the lowest row
    // (dot 3) on the baseline, so dot 1 is two dot pitches above it. Each
    // dot as its centre less r in x and plus r in y.
    let (cell, dot) = (6.2f32, 2.34f32);
    let want = [
        (22.0, 25.0 - 2.0 * dot),
        (22.0 + cell, 25.0 - 2.0 * dot),
        (22.0 + cell, 25.0 - dot),
        (22.0, 37.0 - 2.0 * dot),
        (22.0 + dot, 37.0 - 2.0 * dot),
    ];
    let got: Vec<(f32, f32)> = d.dots.iter().map(|p| (p.x.0 - r, p.y.0 + r)).collect();
    assert_eq!(got.len(), want.len(), "{got:?}");
    assert!(want.iter().all(|w| got.iter().any(|g| (g.0 - w.0).abs() < 0.01 && (g.1 - w.1).abs() < 0.01)), "{got:?}");
}

/// A drawing whose annotated shapes all lie beyond the surface is still an
/// annotated drawing: the automatic sheet does not style what is left in
/// their place, and the errors say to fit the drawing, not to annotate it.
#[test]
fn annotations_beyond_the_surface_say_fit_not_annotate() {
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="300mm" height="100mm" viewBox="0 0 300 100">
        <rect x="10" y="10" width="40" height="40" fill="red"/>
        <rect x="200" y="20" width="40" height="40" data-tactile="grating()"/></svg>"#;
    let c = compile(svg);
    assert!(c.bundle.is_none());
    assert!(with_code(&c, "T0320").is_empty(), "{:#?}", c.diagnostics);
    assert_eq!(with_code(&c, "T0205")[0].severity, Severity::Warning);
    let e = with_code(&c, "T0300");
    assert!(e[0].message.contains("beyond"), "{:?}", e[0]);
    assert!(e[0].help.as_deref().is_some_and(|h| h.contains("--fit") && !h.contains("data-tactile")), "{:?}", e[0]);
    // Fitted, the annotated square is the one layer; the red one stays out.
    let opts = CompileOptions { fit: true, ..CompileOptions::new(stress2()) };
    let c = no_internal_error(compile_svg(svg, &opts));
    assert!(with_code(&c, "T0205").is_empty());
    assert_eq!(masks(bundle(&c)).len(), 1, "{:#?}", c.diagnostics);
}

#[test]
fn nothing_tactile_is_an_error_that_says_how_to_annotate() {
    // Unannotated, the automatic style sheet makes the red square a grating (note T0320) ...
    let c = compile(&page(r#"<rect width="30" height="30" fill="red"/>"#));
    assert_eq!(with_code(&c, "T0320").len(), 1);
    assert!(c.bundle.is_some(), "{:?}", c.diagnostics);
    // ... but finds nothing to feel in white paper.
    let c = compile(&page(r#"<rect width="30" height="30" fill="white"/>"#));
    let d = with_code(&c, "T0300");
    assert_eq!(d.len(), 1);
    assert!(d[0].message.contains("nothing tactile"));
    assert!(d[0].help.as_deref().unwrap_or("").contains("data-tactile"));
    assert!(c.bundle.is_none());
}

#[test]
fn a_drawing_of_pictures_alone_says_to_trace_them() {
    // A scan placed in Inkscape, linked (the default for large images: the
    // file is not read) or embedded, with nothing drawn over it. usvg drops an
    // image whose file it does not read, which read as "no elements drawn".
    let png = "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAAAAAA6fptVAAAACklEQVR4nGNgAAAAAgABSK+kcQAAAABJRU5ErkJggg==";
    for href in ["scan.png", "../maps/scan.jpg", png] {
        let svg = page(&format!(r#"<image id="scan" x="0" y="0" width="80" height="60" href="{href}"/>"#));
        for profile in [stress2(), profiles::builtin("dotpad").unwrap()] {
            let name = profile.name;
            let c = no_internal_error(compile_svg(&svg, &CompileOptions { fit: true, ..CompileOptions::new(profile) }));
            assert!(c.bundle.is_none());
            let e = with_code(&c, "T0300");
            assert_eq!(e.len(), 1, "{href} on {name}: {:#?}", c.diagnostics);
            let help = e[0].help.as_deref().unwrap_or("");
            assert!(help.contains("Trace Bitmap") && !help.contains("data-tactile"), "{href} on {name}: {:?}", e[0]);
            assert!(!e[0].message.contains("no elements"), "{href} on {name}: {:?}", e[0]);
        }
    }
    // A picture under drawn shapes is a background: the shapes build.
    let c = compile(&page(
        r#"<image x="0" y="0" width="80" height="60" href="scan.png"/>
        <rect x="10" y="10" width="30" height="30" data-tactile="grating()"/>"#,
    ));
    assert!(c.bundle.is_some(), "{:#?}", c.diagnostics);
    // Shapes that make nothing keep the advice to annotate.
    let c = compile(&page(
        r#"<image x="0" y="0" width="80" height="60" href="scan.png"/>
        <rect x="10" y="10" width="30" height="30" fill="white"/>"#,
    ));
    assert!(with_code(&c, "T0300")[0].help.as_deref().unwrap_or("").contains("data-tactile"), "{:#?}", c.diagnostics);
}

#[test]
fn empty_and_invisible_shapes_warn_instead_of_making_empty_layers() {
    let c = compile(&page(
        r#"<rect x="5" y="5" width="30" height="30" data-tactile="vibrate()"/>
<rect id="hidden" x="40" y="5" width="30" height="30" visibility="hidden" data-tactile="grating()"/>
<rect id="flat" x="40" y="40" width="0" height="30" data-tactile="grating()"/>
<circle id="gone" cx="50" cy="50" r="5" display="none" data-tactile="grating()"/>"#,
    ));
    let names: Vec<_> = with_code(&c, "T0301").iter().filter_map(|d| d.element.clone()).collect();
    for n in ["hidden", "flat", "gone"] {
        assert!(names.iter().any(|x| x == n), "{n}: {:#?}", c.diagnostics);
    }
    assert_eq!(masks(bundle(&c)).len(), 1);
}

#[test]
fn layer_problems() {
    assert_code(
        &page(r#"<path d="M10 30 L 90 30" data-tactile="dots(radius: 1mm, spacing: 1mm)"/>"#),
        "T0302",
        Severity::Warning,
    );
    let huge = r#"<svg xmlns="http://www.w3.org/2000/svg" width="2000mm" height="2000mm" viewBox="0 0 2000 2000"><rect width="2000" height="2000" data-tactile="grating()"/></svg>"#;
    // Layers are distance fields stored only on the surface: a 2 m square
    // needs no lowered resolution (format 1.x lowered it, T0303, now
    // retired): its lattice is the default 0.5 mm one (5 / 10 px/mm), and
    // nothing beyond the 110 x 60 mm surface is stored.
    let c = compile(huge);
    let m = masks(bundle(&c));
    assert_eq!(m.len(), 1);
    assert_eq!(m[0].pitch_mm, 0.5, "the default lattice, not a lowered one");
    let span = 8.0 * m[0].pitch_mm;
    assert!(m[0].tile_cols as f32 * span <= 110.0 + 3.0 + span && m[0].tile_rows as f32 * span <= 60.0 + 3.0 + span);
    assert_code(&page(r#"<text x="10" y="30" data-tactile="braille()">fjørd</text>"#), "T0304", Severity::Warning);
    assert_code(
        &page(
            r#"<rect x="5" y="5" width="30" height="30" data-tactile="vibrate()"/><image id="photo" x="40" y="5" width="20" height="20" href="data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR4nGNgYGD4DwABBAEAwS2OUAAAAABJRU5ErkJggg==" data-tactile="grating()"/>"#,
        ),
        "T0305",
        Severity::Warning,
    );
}

#[test]
fn adjacent_gratings_with_close_wavelengths() {
    let two = |a: f64, b: f64| {
        page(&format!(
            r#"<rect x="5" y="5" width="30" height="30" data-tactile="grating(wavelength: {a}mm, angle: 0deg)"/>
<rect x="40" y="5" width="30" height="30" data-tactile="grating(wavelength: {b}mm, angle: 0deg)"/>"#
        ))
    };
    assert_code(&two(4.0, 4.3), "T0401", Severity::Error);
    assert_code(&two(4.0, 6.0), "T0402", Severity::Warning);
    let far = codes(&two(3.0, 6.0));
    assert!(!far.contains(&"T0401") && !far.contains(&"T0402"), "{far:?}");
}

#[test]
fn design_rules_for_single_features() {
    assert_code(
        &page(r#"<rect x="5" y="5" width="30" height="30" data-tactile="grating(wavelength: 6mm, angle: 30deg)"/>"#),
        "T0403",
        Severity::Warning,
    );
    let ok = codes(&page(
        r#"<rect x="5" y="5" width="30" height="30" data-tactile="grating(wavelength: 6mm, angle: 135deg)"/>"#,
    ));
    assert!(!ok.contains(&"T0403"), "{ok:?}");
    assert_code(
        &page(r#"<rect x="5" y="5" width="30" height="30" data-tactile="vibrate(width: 0.8mm)"/>"#),
        "T0404",
        Severity::Warning,
    );
    // 2 mm across vertical ridges (variation along x, pitch 1.2 mm): Nyquist needs 2.4 mm.
    assert_code(
        &page(r#"<rect x="5" y="5" width="30" height="30" data-tactile="grating(wavelength: 2mm, angle: 90deg)"/>"#),
        "T0405",
        Severity::Warning,
    );
    let ok = codes(&page(
        r#"<rect x="5" y="5" width="30" height="30" data-tactile="grating(wavelength: 2.5mm, angle: 90deg)"/>"#,
    ));
    assert!(!ok.contains(&"T0405"), "{ok:?}");
    assert_code(
        &page(r#"<rect x="5" y="5" width="12" height="12" data-tactile="vibrate()"/>"#),
        "T0407",
        Severity::Warning,
    );
}

/// Issue 14 (France's departments, x192 T0407 and x187 T0408 once their
/// borders were left out): regions of one grating style that touch are felt
/// as one texture, so neither the size rule nor the gap rule judges them one
/// by one. Here `a` and `c` are 1 mm apart across the thin `b` of the same
/// style, and each is under 2 cm while the three together are 21 mm wide;
/// `d`, of the same style but touching none of them, is still a shape of its
/// own 1.5 mm from `c`: both are told so, as any two elements that close
/// are, though `c`'s nearest neighbour is `a` of its own texture (1 mm).
#[test]
fn regions_of_one_texture_are_not_judged_apart() {
    let g = r#"data-tactile="grating(wavelength: 4mm, angle: 0deg)""#;
    let svg = page(&format!(
        r#"<rect id="a" x="10" y="10" width="10" height="10" {g}/>
<rect id="b" x="20" y="10" width="1" height="10" {g}/>
<rect id="c" x="21" y="10" width="10" height="10" {g}/>
<rect id="d" x="32.5" y="10" width="10" height="10" {g}/>"#
    ));
    let c = compile(&svg);
    let on = |code: &str| -> Vec<String> {
        with_code(&c, code).iter().map(|d| d.element.clone().unwrap_or_default()).collect()
    };
    assert_eq!(on("T0407"), ["d"], "{:#?}", c.diagnostics);
    let gaps = with_code(&c, "T0408");
    assert!(gaps.iter().all(|d| d.message.contains("1.5 mm")), "{gaps:#?}");
    assert_eq!(on("T0408"), ["c", "d"], "{gaps:#?}");
}

/// Issue 14: an element with a border and a fill is one shape with one
/// nearest neighbour, said once, not once per style.
#[test]
fn size_and_gap_are_said_once_per_element() {
    let both = r#"data-tactile="vibrate(); grating(wavelength: 4mm, angle: 0deg)""#;
    let c = compile(&page(&format!(
        r#"<rect id="a" x="10" y="10" width="12" height="12" {both}/><rect id="b" x="24" y="10" width="12" height="12" {both}/>"#
    )));
    let on = |code: &str| -> Vec<String> {
        with_code(&c, code).iter().map(|d| d.element.clone().unwrap_or_default()).collect()
    };
    assert_eq!(on("T0407"), ["a", "b"], "{:#?}", c.diagnostics);
    assert_eq!(on("T0408"), ["a", "b"], "{:#?}", c.diagnostics);
}

#[test]
fn design_rules_between_elements() {
    assert_code(
        &page(
            r#"<circle cx="20" cy="20" r="1" data-tactile="dot()"/><circle cx="21.5" cy="20" r="1" data-tactile="dot()"/>"#,
        ),
        "T0406",
        Severity::Warning,
    );
    assert_code(
        &page(
            r#"<rect x="5" y="5" width="30" height="30" data-tactile="vibrate()"/><rect x="38" y="5" width="30" height="30" data-tactile="vibrate()"/>"#,
        ),
        "T0408",
        Severity::Warning,
    );
    let apart = codes(&page(
        r#"<rect x="5" y="5" width="30" height="30" data-tactile="vibrate()"/><rect x="45" y="5" width="30" height="30" data-tactile="vibrate()"/>"#,
    ));
    assert!(!apart.contains(&"T0408"), "{apart:?}");
    let six: String = (0..6)
        .map(|k| {
            format!(
                r#"<circle cx="{}" cy="30" r="1" data-tactile="dot(radius: {}mm)"/>"#,
                8 + 15 * k,
                1.0 + 0.2 * k as f64
            )
        })
        .collect();
    assert_code(&page(&six), "T0409", Severity::Warning);
    assert_code(
        &page(
            r#"<rect x="5" y="5" width="40" height="40" data-tactile="grating(wavelength: 6mm, angle: 0deg)"/><circle cx="25" cy="25" r="1" data-tactile="dot(radius: 2mm)"/>"#,
        ),
        "T0410",
        Severity::Warning,
    );
    // The circle painted over the grating hides it there: a dot no larger
    // than the circle overlaps nothing.
    let hidden = codes(&page(
        r#"<rect x="5" y="5" width="40" height="40" data-tactile="grating(wavelength: 6mm, angle: 0deg)"/><circle cx="25" cy="25" r="1" data-tactile="dot()"/>"#,
    ));
    assert!(!hidden.contains(&"T0410"), "{hidden:?}");
}

#[test]
fn brush_on_a_grid_profile_goes_to_the_brush_scheduler() {
    let opts = CompileOptions::new(profiles::builtin("brush-4x3").unwrap());
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="189mm" height="126mm" viewBox="0 0 189 126"><path d="M 0 0 L 189 0" data-tactile="brush(duration: 1s); vibrate()"/></svg>"#;
    let c = no_internal_error(compile_svg(svg, &opts));
    // vibrate is not rendered on a grid; the brush request reached compile_strokes (its diagnostics, if any, follow).
    assert!(c.diagnostics.iter().any(|d| d.code == "T0120"), "{:#?}", c.diagnostics);
    assert!(
        !c.diagnostics.iter().any(|d| d.code == "T0300" && d.message.contains("nothing tactile")),
        "{:#?}",
        c.diagnostics
    );
}

#[test]
fn a_map_built_for_a_grid_or_finger_device_says_what_that_device_plays() {
    // A teacher's unannotated map, built for the chair or the finger device:
    // the automatic sheet makes laterotactile styles, which those do not play.
    let svg = page(
        r##"<path d="M5,5 L90,8 L85,55 L8,50 Z" fill="#cfe8a9"/>
        <path d="M10,30 C30,10 60,50 90,30" stroke="#36f" stroke-width="1" fill="none"/>"##,
    );
    for (name, says) in [("brush-4x3", "brush()"), ("finger3", ".gltf")] {
        let opts = CompileOptions { fit: true, ..CompileOptions::new(profiles::builtin(name).unwrap()) };
        let c = no_internal_error(compile_svg(&svg, &opts));
        assert!(c.bundle.is_none());
        assert!(!with_code(&c, "T0120").is_empty(), "{name}: {:#?}", c.diagnostics);
        let e = with_code(&c, "T0300");
        let help = e[0].help.as_deref().unwrap_or("");
        assert!(help.contains(says) && help.contains("stress2") && help.contains("dotpad"), "{name}: {:?}", e[0]);
        assert!(!help.contains("style auto"), "{name}: {:?}", e[0]);
    }
    // On stress2 a style it does not play keeps the general help.
    let c = compile(&page(r#"<path d="M10 10 L 80 10" data-tactile="brush()"/>"#));
    let help = with_code(&c, "T0300")[0].help.as_deref().unwrap_or("").to_string();
    assert!(help.contains("may not be rendered on this device"), "{help}");
}

/// Issue 14 (a vector field's arrowheads drawn past the page's edge, which
/// the automatic sheet makes dots): "no dots are left on the page" gave no
/// help saying why or what to do.
#[test]
fn dots_off_the_page_say_where_they_went() {
    let c = compile(&page(
        r#"<defs><marker id="m" markerWidth="4" markerHeight="4" refX="2" refY="2"><path d="M0 0L4 2L0 4Z"/></marker></defs>
<line id="arrow" x1="50" y1="40" x2="50" y2="70" stroke="blue" stroke-width="0.5" marker-end="url(#m)"/>"#,
    ));
    let off = with_code(&c, "T0301");
    assert_eq!(off.len(), 1, "{:#?}", c.diagnostics);
    assert_eq!(off[0].element.as_deref(), Some("arrow"));
    assert!(off[0].help.as_deref().is_some_and(|h| h.contains("beyond the page")), "{off:#?}");
}

/// A label of a paragraph's length (a scanned page's text layer, a long
/// caption) is quoted by its start in the messages that name it (T0326,
/// T0332): they printed all of its 200,000 characters on one line.
#[test]
fn a_long_label_is_quoted_by_its_start_in_every_message() {
    let text = "lorem ipsum dolor sit amet ".repeat(800);
    let svg = page(&format!(
        r#"<rect x="5" y="5" width="40" height="40" fill="green"/><text x="50" y="30" font-size="4">{text}</text>"#
    ));
    let c = compile(&svg);
    assert!(c.diagnostics.iter().any(|d| d.code == "T0326"), "{:#?}", c.diagnostics);
    for d in &c.diagnostics {
        assert!(d.message.chars().count() < 400, "{}: {} characters", d.code, d.message.chars().count());
    }
}
