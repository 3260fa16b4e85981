//! The resolved drawing (`drawing::resolve`): every drawn element with its
//! styles, paint and geometry in page mm, and the front end's regressions
//! (root annotations, labels in any script, entity expansion).

use taxel_compiler::drawing::{self, Drawing, Element, Shape, StyledBy};
use taxel_compiler::{CompileOptions, StyleSheet};
use taxel_format::{Chunk, DotKind, MaskKind};

use crate::common::*;

fn resolve(svg: &str) -> Drawing {
    let r = taxel_compiler::pipeline::resolve(svg, &CompileOptions::new(stress2()));
    r.drawing.unwrap_or_else(|| panic!("no drawing: {:#?}", r.diagnostics))
}

/// The drawing as read, with no automatic sheet (an empty style sheet):
/// what the reader found, before labels that find no place become key codes.
fn resolve_as_read(svg: &str) -> Drawing {
    let mut opts = CompileOptions::new(stress2());
    opts.style = Some(taxel_compiler::annotation::sheet::StyleSheet::parse("", "empty.toml").expect("an empty sheet"));
    let r = taxel_compiler::pipeline::resolve(svg, &opts);
    r.drawing.unwrap_or_else(|| panic!("no drawing: {:#?}", r.diagnostics))
}

fn by_id<'a>(d: &'a Drawing, id: &str) -> &'a Element {
    d.elements.iter().find(|e| e.id == id).unwrap_or_else(|| panic!("no element {id}: {:#?}", d.elements))
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-3
}

fn bounds_close(e: &Element, want: (f64, f64, f64, f64)) {
    let b = e.bounds().unwrap_or_else(|| panic!("{} has no bounds", e.name));
    assert!(close(b.0, want.0) && close(b.1, want.1) && close(b.2, want.2) && close(b.3, want.3), "{}: {b:?}", e.name);
}

/// The 1-based line of the first line of `svg` that contains `needle`.
fn line_of(svg: &str, needle: &str) -> u32 {
    svg.lines().position(|l| l.contains(needle)).unwrap_or_else(|| panic!("{needle} not in the drawing")) as u32 + 1
}

#[test]
fn every_drawn_element_is_in_the_drawing_with_its_paint_and_geometry() {
    // 200 x 120 user units on 100 x 60 mm: one unit is half a millimetre.
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm" viewBox="0 0 200 120">
  <title> Pond map </title>
  <rect id="bg" width="200" height="120" fill="#ffffff"/>
  <g transform="translate(20 10)">
    <circle id="pond" cx="40" cy="40" r="20" fill="#0000ff" fill-opacity="0.5" stroke="#ff0000" stroke-width="4" data-tactile="grating()"/>
  </g>
  <path id="road" d="M 10 100 L 190 100" stroke="black" stroke-width="2" fill="none"/>
  <rect id="gone" width="10" height="10" display="none"/>
</svg>"##;
    let d = resolve(svg);
    assert_eq!(d.title, "Pond map");
    assert!(close(d.page.width_mm, 100.0) && close(d.page.height_mm, 60.0), "{:?}", d.page);
    assert!(close(d.page.scale, 0.5), "{:?}", d.page);
    let ids: Vec<&str> = d.elements.iter().map(|e| e.id.as_str()).collect();
    assert_eq!(ids, ["bg", "pond", "road"], "display: none is not drawn");

    let bg = by_id(&d, "bg");
    assert_eq!((bg.styled_by, bg.styles.len()), (StyledBy::Nothing, 0));
    assert_eq!(bg.paint.fill, Some([255, 255, 255, 255]));
    assert!(!bg.paint.stroked);
    bounds_close(bg, (0.0, 0.0, 100.0, 60.0));

    let pond = by_id(&d, "pond");
    assert_eq!((pond.styled_by, pond.styles.len(), pond.line), (StyledBy::Annotation, 1, 5));
    assert_eq!(pond.paint.fill, Some([0, 0, 255, 128]), "fill-opacity 0.5 folds into alpha");
    assert_eq!(pond.paint.stroke, Some([255, 0, 0, 255]));
    assert!(close(pond.paint.stroke_width_mm, 2.0), "4 units of 0.5 mm: {}", pond.paint.stroke_width_mm);
    // Centre (20 + 40, 10 + 40) units = (30, 25) mm, radius 10 mm.
    bounds_close(pond, (20.0, 15.0, 40.0, 35.0));
    let Shape::Path(p) = &pond.shape else { panic!("the circle is a path") };
    let worst = p.outline[0].points.iter().map(|&(x, y)| ((x - 30.0).hypot(y - 25.0) - 10.0).abs()).fold(0.0, f64::max);
    // usvg draws a circle as four cubic arcs, 0.027 % of the radius off the true circle at worst.
    assert!(worst < 10.0 * 0.00028 + 0.0005, "the outline lies on the circle: {worst}");

    let road = by_id(&d, "road");
    assert!(close(road.paint.stroke_width_mm, 1.0));
    bounds_close(road, (5.0, 50.0, 95.0, 50.0));
}

/// An element's `opacity`, and its groups', fold into its paint's alpha as
/// `fill-opacity` does: what is drawn at opacity 0 is not seen.
#[test]
fn the_opacity_of_an_element_and_its_groups_folds_into_its_paint() {
    let svg = page(
        r##"<rect id="clear" width="10" height="10" fill="#ff0000" opacity="0"/>
<g opacity="0.5"><rect id="half" width="10" height="10" fill="#000000" stroke="#0000ff" stroke-opacity="0.5"/>
<g opacity="0.5"><rect id="quarter" width="10" height="10" fill="#000000" fill-opacity="0.5"/></g></g>
<rect id="whole" width="10" height="10" fill="#000000"/>"##,
    );
    let d = resolve(&svg);
    assert_eq!(by_id(&d, "clear").paint.fill, Some([255, 0, 0, 0]));
    assert_eq!(by_id(&d, "half").paint.fill, Some([0, 0, 0, 128]));
    assert_eq!(by_id(&d, "half").paint.stroke, Some([0, 0, 255, 64]));
    assert_eq!(by_id(&d, "quarter").paint.fill, Some([0, 0, 0, 32]));
    assert_eq!(by_id(&d, "whole").paint.fill, Some([0, 0, 0, 255]));
}

/// What is drawn at opacity 0 is not seen, so it is not felt and hides
/// nothing: the automatic sheet leaves it out (resvg's test
/// `painting/opacity/bBox-impact` drew it as a grating), and a grating
/// under an opaque rectangle at opacity 0 is still felt there.
#[test]
fn an_element_drawn_at_opacity_0_is_not_felt_and_hides_nothing() {
    let c = compile(&page(
        r##"<rect id="land" x="5" y="5" width="40" height="40" fill="#00aa00"/>
<g opacity="0"><rect id="ghost" x="50" y="5" width="40" height="40" fill="#ff0000"/></g>"##,
    ));
    let b = bundle(&c);
    let layers = masks(b);
    assert!(!layers.is_empty());
    let felt_at = |x: f64, y: f64| layers.iter().map(|m| sample(m, x, y)).fold(0.0, f64::max);
    assert!(felt_at(25.0, 25.0) > 0.99, "the land is felt");
    assert_eq!(felt_at(70.0, 25.0), 0.0, "the ghost is not");
    let under = compile(&page(
        r##"<rect id="land" x="5" y="5" width="40" height="40" data-tactile="grating()"/>
<rect id="ghost" x="15" y="15" width="20" height="20" fill="#ffffff" opacity="0"/>"##,
    ));
    let layers = masks(bundle(&under));
    assert_eq!(layers.len(), 1);
    assert!(sample(layers[0], 25.0, 25.0) > 0.99, "the grating is felt under the ghost");
}

/// A gradient drawn at opacity 0 is not seen either: no colour of it is
/// known, but none of it shows.
#[test]
fn a_gradient_drawn_at_opacity_0_is_not_felt() {
    let c = compile(&page(
        r##"<defs><linearGradient id="k"><stop offset="0" stop-color="#f00"/><stop offset="1" stop-color="#00f"/></linearGradient></defs>
<rect id="land" x="5" y="5" width="40" height="40" fill="#00aa00"/>
<g opacity="0"><rect id="ghost" x="50" y="5" width="40" height="40" fill="url(#k)"/></g>
<rect id="seen" x="50" y="48" width="40" height="10" fill="url(#k)" opacity="0.5"/>"##,
    ));
    let layers = masks(bundle(&c));
    let felt_at = |x: f64, y: f64| layers.iter().map(|m| sample(m, x, y)).fold(0.0, f64::max);
    assert!(felt_at(25.0, 25.0) > 0.99, "the land is felt");
    assert_eq!(felt_at(70.0, 25.0), 0.0, "the ghost is not");
    assert!(felt_at(70.0, 53.0) > 0.99, "a gradient at opacity 0.5 is");
}

/// A mask hides what it masks where it shows nothing, as resvg draws it:
/// an element under a mask of black content (a luminance mask), of clear
/// content (an alpha mask), of a black gradient or of no content is not
/// seen, so not felt, and hides nothing under it; under a mask that shows
/// one part of it, only that part is felt.
#[test]
fn an_element_is_felt_only_where_its_mask_shows_it() {
    let c = compile(&page(
        r##"<defs>
  <mask id="black" maskUnits="userSpaceOnUse" x="0" y="0" width="100" height="60"><rect width="100" height="60" fill="#000"/></mask>
  <mask id="clear" mask-type="alpha"><rect x="0" y="0" width="1" height="1" fill="#fff" fill-opacity="0" maskContentUnits="objectBoundingBox"/></mask>
  <linearGradient id="dark"><stop offset="0" stop-color="#000"/><stop offset="1" stop-color="#000"/></linearGradient>
  <mask id="fade" maskUnits="userSpaceOnUse" x="0" y="0" width="100" height="60"><rect width="100" height="60" fill="url(#dark)"/></mask>
  <mask id="left" maskUnits="userSpaceOnUse" x="0" y="0" width="100" height="60"><rect x="0" y="0" width="20" height="60" fill="#fff"/></mask>
</defs>
<rect id="land" x="5" y="5" width="40" height="40" fill="#00aa00"/>
<rect id="a" x="50" y="5" width="20" height="15" fill="#ff0000" mask="url(#black)"/>
<rect id="b" x="75" y="5" width="20" height="15" fill="#ff0000" mask="url(#clear)"/>
<rect id="c" x="50" y="25" width="20" height="15" fill="#ff0000" mask="url(#fade)"/>
<rect id="over" x="15" y="15" width="20" height="20" fill="#ffffff" mask="url(#black)"/>
<g transform="translate(5 0)" mask="url(#left)"><rect id="half" x="5" y="48" width="40" height="10" fill="#0000ff"/></g>"##,
    ));
    let layers = masks(bundle(&c));
    let felt_at = |x: f64, y: f64| layers.iter().map(|m| sample(m, x, y)).fold(0.0, f64::max);
    assert!(felt_at(25.0, 25.0) > 0.99, "the land is felt, under a white square masked out");
    assert_eq!(felt_at(60.0, 12.0), 0.0, "under a black luminance mask");
    assert_eq!(felt_at(85.0, 12.0), 0.0, "under a clear alpha mask");
    assert_eq!(felt_at(60.0, 32.0), 0.0, "under a black gradient");
    // The mask's user space is the group's, translated 5 mm: it shows 5..25 mm.
    assert!(felt_at(15.0, 53.0) > 0.99, "where the mask shows the band");
    assert_eq!(felt_at(40.0, 53.0), 0.0, "where it does not");
    let d = resolve(&page(
        r##"<defs><mask id="dim"><rect x="0" y="0" width="100" height="60" fill="#808080"/></mask>
<linearGradient id="fading"><stop offset="0" stop-color="#fff" stop-opacity="0"/><stop offset="1" stop-color="#000"/></linearGradient>
<mask id="middle"><rect x="0" y="0" width="100" height="60" fill="url(#fading)"/></mask></defs>
<rect id="dimmed" x="5" y="5" width="40" height="40" fill="#000000" mask="url(#dim)"/>
<rect id="midway" x="50" y="5" width="40" height="40" fill="#000000" mask="url(#middle)"/>"##,
    ));
    let alpha = |id: &str| by_id(&d, id).paint.fill.map(|c| c[3]);
    // #808080's luminance is 128 / 255 of white.
    assert_eq!(alpha("dimmed"), Some(128), "a grey mask fades the paint as opacity would");
    // Neither stop shows (clear white, black); half way, grey at half alpha
    // shows a quarter: resvg's `masking/mask/simple-case`.
    assert_eq!(alpha("midway"), Some(64), "a mask shows most between its gradient's stops");
}

#[test]
fn styles_come_from_the_style_sheet_and_are_overridden_by_annotations() {
    let sheet = StyleSheet::parse("[[rule]]\nclass = \"water\"\ntactile = \"grating()\"\n", "s.toml").unwrap();
    let svg = page(
        r#"<g data-tactile="vibrate()"><rect id="a" class="water" width="10" height="10"/><rect id="b" width="10" height="10"/>
<rect id="c" class="water" width="10" height="10" data-tactile="dots()"/></g>"#,
    );
    let mut opts = CompileOptions::new(stress2());
    opts.style = Some(sheet);
    let d = taxel_compiler::pipeline::resolve(&svg, &opts).drawing.unwrap();
    let names = |e: &Element| e.styles.iter().map(|s| s.name()).collect::<Vec<_>>();
    assert_eq!((by_id(&d, "a").styled_by, names(by_id(&d, "a"))), (StyledBy::StyleSheet, vec!["grating"]));
    assert_eq!((by_id(&d, "b").styled_by, names(by_id(&d, "b"))), (StyledBy::Annotation, vec!["vibrate"]));
    assert_eq!((by_id(&d, "c").styled_by, names(by_id(&d, "c"))), (StyledBy::Annotation, vec!["dots"]));
}

#[test]
fn text_runs_are_placed_for_braille_in_page_mm() {
    let svg = page(
        r#"<text id="t" x="20" y="30" font-size="5" text-anchor="middle" data-tactile="braille()">Ab<tspan x="20" y="45">c</tspan><tspan>d</tspan></text>"#,
    );
    let d = resolve(&svg);
    let Shape::Text(t) = &by_id(&d, "t").shape else { panic!("a text") };
    let runs: Vec<(&str, bool)> = t.runs.iter().map(|r| (r.text.as_str(), r.continues)).collect();
    assert_eq!(runs, [("Ab", false), ("cd", false)]);
    let at: Vec<(f64, f64)> = t.runs.iter().map(|r| (r.x_mm, r.y_mm)).collect();
    assert!(close(at[0].0, 20.0) && close(at[0].1, 30.0) && close(at[1].0, 20.0) && close(at[1].1, 45.0), "{at:?}");
    assert!(t.runs.iter().all(|r| r.anchor == 0.5));
    assert_eq!(t.content, "Ab cd");
}

#[test]
fn root_annotation_applies_to_the_whole_drawing() {
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm" viewBox="0 0 100 60" data-tactile="vibrate()">
  <rect id="r" x="10" y="10" width="30" height="30"/>
  <g><circle id="c" cx="70" cy="30" r="10"/></g>
  <text id="t" x="10" y="55" data-tactile="braille()">hi</text>
</svg>"#;
    let d = resolve(svg);
    for id in ["r", "c"] {
        let e = by_id(&d, id);
        assert_eq!(
            (e.styled_by, e.styles.iter().map(|s| s.name()).collect::<Vec<_>>()),
            (StyledBy::Annotation, vec!["vibrate"])
        );
    }
    let c = compile(svg);
    let b = bundle(&c);
    // Both vibrating shapes share one style, so one layer holds both.
    let vibrating: Vec<_> = masks(b).into_iter().filter(|m| matches!(m.kind, MaskKind::Vibration { .. })).collect();
    assert_eq!(vibrating.len(), 1, "{:#?}", c.diagnostics);
    assert_eq!(vibrating[0].sources.len(), 2, "{:?}", vibrating[0].sources);
    assert_eq!(dots(b, DotKind::Braille).map(|t| t.dots.len()), Some(3 + 2), "h is dots 125, i is dots 24");
}

#[test]
fn root_annotation_none_leaves_the_drawing_out_but_children_may_opt_in() {
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm" viewBox="0 0 100 60" data-tactile="none">
  <rect x="10" y="10" width="30" height="30"/>
  <rect x="50" y="10" width="30" height="30" data-tactile="grating()"/>
</svg>"#;
    let b = compile(svg).bundle.expect("one grating");
    assert_eq!(masks(&b).len(), 1);
}

/// Regression: byte slicing `trimmed[..8]` inside a character panicked on an
/// Inkscape layer labelled in French or Japanese (caught as T0900 before).
#[test]
fn inkscape_layer_labelled_calque_elevation_or_japanese_does_not_panic() {
    for label in ["Calque élévation", "レイヤー 1", "tactileé", "tactil", "é"] {
        let svg = page(&format!(
            r#"<g id="layer1" inkscape:groupmode="layer" inkscape:label="{label}"><rect id="r" width="30" height="30" data-tactile="vibrate()"/></g>"#
        ));
        let c = compile(&svg);
        assert!(c.bundle.is_some(), "{label}: {:#?}", c.diagnostics);
        let d = resolve(&svg);
        assert_eq!(by_id(&d, "r").layers, [label]);
    }
    // A `tactile:` label still works in any case, after a non-ASCII layer.
    let svg = page(
        r#"<g inkscape:groupmode="layer" inkscape:label="レイヤー 1"><g inkscape:groupmode="layer" inkscape:label="  TACTILE: grating()"><rect id="r" width="30" height="30"/></g></g>"#,
    );
    let d = resolve(&svg);
    assert_eq!(by_id(&d, "r").styles.iter().map(|s| s.name()).collect::<Vec<_>>(), ["grating"]);
}

#[test]
fn ids_classes_titles_and_annotations_in_any_script_keep_their_positions() {
    let svg = page(
        "<rect id=\"湖\" class=\"eau 水\" width=\"30\" height=\"30\" data-tactile=\"grating()\"><title>Lac élevé 湖</title></rect>\n<rect id=\"é\" x=\"50\" width=\"30\" height=\"30\" data-tactile=\"vibrate(width: 2)\"/>",
    );
    let d = resolve(&svg);
    let lake = by_id(&d, "湖");
    assert_eq!((lake.label.as_str(), lake.classes.as_str(), lake.line), ("Lac élevé 湖", "eau 水", 2));
    let c = compile(&svg);
    let err = with_code(&c, "T0104");
    assert_eq!(err.len(), 1, "{:#?}", c.diagnostics);
    let line = svg.lines().nth(2).unwrap();
    // Columns count characters: `é` in the id is one column.
    let col = line[..line.find("2)").unwrap()].chars().count() as u32 + 1;
    assert_eq!((err[0].line, err[0].column, err[0].element.as_deref()), (Some(3), Some(col), Some("é")));
}

/// Regression: an element from an `<!ENTITY>` expansion has its text in the
/// DTD; inserting its id there was out of order and panicked (T0900).
#[test]
fn element_from_entity_expansion_is_drawn_at_its_reference() {
    let svg = r#"<?xml version="1.0"?>
<!DOCTYPE svg [
  <!ENTITY square "<rect x='10' y='10' width='20' height='20'/>">
  <!ENTITY dot '<circle cx="5" cy="5" r="2"/>'>
]>
<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm" viewBox="0 0 100 60">
  <g id="v" data-tactile="vibrate()">&square;</g>
  <g id="g" data-tactile="grating()" transform="translate(50 0)">
    &square;
  </g>
  <g id="d" data-tactile="dot()">&dot;</g>
</svg>"#;
    let c = compile(svg);
    let b = bundle(&c);
    let kinds: Vec<&str> = masks(b)
        .iter()
        .map(|m| match m.kind {
            MaskKind::Vibration { .. } => "vibration",
            MaskKind::Grating { .. } => "grating",
        })
        .collect();
    assert_eq!(kinds, ["vibration", "grating"], "{:#?}", c.diagnostics);
    assert_eq!(dots(b, DotKind::Symbol).map(|t| t.dots.len()), Some(1));
    let d = resolve(svg);
    let squares: Vec<(u32, (f64, f64, f64, f64))> =
        d.elements.iter().filter(|e| e.tag == "rect").map(|e| (e.line, e.bounds().unwrap())).collect();
    assert_eq!(squares.len(), 2, "{:#?}", d.elements);
    // Each copy is where its reference is: line 7, and line 9 moved 50 mm right.
    assert_eq!(squares[0].0, line_of(svg, "id=\"v\""));
    assert_eq!(squares[1].0, line_of(svg, "    &square;"));
    assert!(close(squares[0].1.0, 10.0) && close(squares[1].1.0, 60.0), "{squares:?}");
    let prov: Vec<u32> = b
        .chunks
        .iter()
        .find_map(|c| match c {
            Chunk::Provenance(p) => Some(p.entries.iter().map(|e| e.line).collect()),
            _ => None,
        })
        .unwrap();
    assert!(prov.contains(&line_of(svg, "id=\"d\"")), "{prov:?}");
}

#[test]
fn annotation_inside_an_entity_is_read_and_its_error_points_into_the_entity() {
    let svg = r#"<!DOCTYPE svg [
  <!ENTITY bad "<rect width='9' height='9' data-tactile='vibrate(width 2mm)'/>">
]>
<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm">
  &bad;
</svg>"#;
    let c = compile(svg);
    let e = with_code(&c, "T0101");
    assert_eq!(e.len(), 1, "{:#?}", c.diagnostics);
    // The characters at fault are in the entity's text on line 2.
    let col = svg.lines().nth(1).unwrap().find("2mm").unwrap() as u32 + 1;
    assert_eq!((e[0].line, e[0].column), (Some(2), Some(col)));
}

/// Tuffy (public domain), loaded from bytes as a caller would hand it over.
fn tuffy() -> std::sync::Arc<taxel_compiler::fontdb::Database> {
    let bytes =
        std::fs::read(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/fonts/Tuffy.ttf")).unwrap();
    let mut db = taxel_compiler::fontdb::Database::new();
    db.load_font_data(bytes);
    std::sync::Arc::new(db)
}

#[test]
fn fonts_are_an_input_and_the_faces_used_are_reported() {
    let svg = page(
        r#"<text id="t" x="10" y="30" font-family="Tuffy" font-size="10" data-tactile="vibrate(); braille()">Hi</text>"#,
    );
    let outline = |r: &drawing::Resolved| match &by_id(r.drawing.as_ref().unwrap(), "t").shape {
        Shape::Text(t) => t.outline.len(),
        _ => panic!("a text"),
    };
    // Without fonts: no glyph outlines, no faces; braille still comes from the characters.
    let none = taxel_compiler::pipeline::resolve(&svg, &CompileOptions::new(stress2()));
    assert_eq!((outline(&none), none.fonts_used.len()), (0, 0));
    let b = compile(&svg).bundle.expect("braille without fonts");
    assert!(masks(&b).is_empty() && dots(&b, DotKind::Braille).is_some());

    let opts = CompileOptions { fonts: Some(tuffy()), ..CompileOptions::new(stress2()) };
    let with = taxel_compiler::pipeline::resolve(&svg, &opts);
    assert!(outline(&with) >= 2, "H and i have outlines");
    let faces: Vec<(&str, Option<&std::path::Path>)> =
        with.fonts_used.iter().map(|f| (f.family.as_str(), f.path.as_deref())).collect();
    assert_eq!(faces, [("Tuffy", None)]);
    assert_eq!(drawing::fonts_used(&svg, opts.fonts.as_ref().unwrap(), &opts.languages), with.fonts_used);
    let c = no_internal_error(taxel_compiler::compile_svg(&svg, &opts));
    assert_eq!(masks(bundle(&c)).len(), 1, "the glyphs vibrate: {:#?}", c.diagnostics);
    // A drawing without text uses no face.
    assert!(
        drawing::fonts_used(&page(r#"<rect width="5" height="5"/>"#), opts.fonts.as_ref().unwrap(), &opts.languages)
            .is_empty()
    );
}

/// Inkscape 0.92's flowed text (`<flowRoot>`) is read as Inkscape shows it:
/// a run per paragraph from its frame's top corner on its anchor's side, the
/// first baseline a font size down, each paragraph below the lines the last
/// took (wrapped at half a font size a character), under the text's and its
/// groups' transforms; a frame may be a rectangle, a path or a `<use>` of one.
#[test]
fn inkscape_flowed_text_is_a_text_of_its_paragraphs_in_its_frame() {
    let svg = page(
        r##"<flowRoot id="lake" transform="translate(5 2)" style="font-size:4px;line-height:1.5"><flowRegion><rect x="20" y="10" width="30" height="20"/></flowRegion><flowPara>Lake   Tana</flowPara><flowDiv><flowPara>fresh water lake of <flowSpan>Ethiopia</flowSpan></flowPara></flowDiv><flowPara/><flowPara>End</flowPara></flowRoot>
<g transform="translate(0 5)"><flowRoot id="forest" style="font-size:3px;line-height:125%;text-anchor:middle"><flowRegion><path d="M 60,40 h 30 v 10 h -30 z"/></flowRegion><flowPara>Forest</flowPara></flowRoot></g>
<defs><rect id="frame" x="0" y="0" width="20" height="8"/><flowRoot id="hidden"><flowRegion><rect x="0" y="0" width="9" height="9"/></flowRegion><flowPara>no</flowPara></flowRoot></defs>
<flowRoot id="used"><flowRegion><use href="#frame" x="70" y="2"/></flowRegion><flowPara>hill</flowPara><flowPara style="display:none">dale</flowPara></flowRoot>
<flowRoot id="sized" style="font-size:2px;line-height:0.01%"><flowRegion><rect x="60" y="50" width="30" height="9"/></flowRegion><flowPara style="font-size:5px;line-height:1.2">ab</flowPara><flowPara style="font-size:5px">cd</flowPara></flowRoot>
<flowRoot id="empty"><flowRegion><rect x="0" y="0" width="9" height="9"/></flowRegion><flowPara/></flowRoot>"##,
    );
    let d = resolve_as_read(&svg);
    let runs = |id: &str| match &by_id(&d, id).shape {
        Shape::Text(t) => t.runs.iter().map(|r| (r.text.clone(), r.x_mm, r.y_mm, r.anchor)).collect::<Vec<_>>(),
        s => panic!("{id} is not a text: {s:?}"),
    };
    // 15 characters a line (30 / (4 / 2)): "Lake Tana" takes one line of
    // 6, the 28 characters of the next paragraph two, the empty one one.
    let want = [("Lake Tana", 16.0), ("fresh water lake of Ethiopia", 22.0), ("End", 40.0)];
    let got = runs("lake");
    assert_eq!(got.len(), want.len(), "{got:?}");
    for ((text, x, y, anchor), (t, wy)) in got.iter().zip(want) {
        assert!(text == t && close(*x, 25.0) && close(*y, wy) && *anchor == 0.0, "{got:?}");
    }
    // Anchored in the middle of its path's box, moved by its group.
    let got = runs("forest");
    assert!(got.len() == 1 && got[0].0 == "Forest" && close(got[0].1, 75.0) && close(got[0].2, 48.0), "{got:?}");
    assert_eq!(got[0].3, 0.5);
    // A `<use>`'s frame is where the `<use>` puts it; the default font size is 16 px.
    let got = runs("used");
    assert!(got.len() == 1 && close(got[0].1, 70.0) && close(got[0].2, 18.0), "{got:?}");
    assert!(d.elements.iter().all(|e| e.id != "hidden"), "a flowed text in <defs> is not drawn");
    // Sizes and line heights set on the paragraphs (as Inkscape 0.92 does,
    // with a `line-height` of 0.01% on the text): the first's 1.2, the
    // second's the text's, which is never less than one font size.
    let got = runs("sized");
    assert!(got.len() == 2 && close(got[0].2, 55.0) && close(got[1].2, 61.0), "{got:?}");
    assert!(d.elements.iter().all(|e| e.id != "empty"), "an empty flowed text is no text");
}

/// HTML in a `<foreignObject>` (Mermaid's labels; usvg draws none of it) is
/// a text of its lines, laid out as a browser would: from the box's top
/// corner on its `text-align` side, the first baseline a font size and half
/// the leading below the top, a line per block element or `<br>`, under the
/// transforms of groups usvg dropped as empty. One a `<switch>` passes over
/// (draw.io's, beside its `<text>`) or in a hidden group is not read.
#[test]
fn html_in_a_foreign_object_is_a_text_of_its_lines() {
    let xhtml = r#"xmlns="http://www.w3.org/1999/xhtml""#;
    let svg = page(&format!(
        r#"<g transform="translate(50 20)"><g class="label" transform="translate(-15 -6)"><rect/><foreignObject id="start" width="30" height="9"><div {xhtml} style="font-size: 6px; line-height: 1.5; text-align: center;"><span><p>Start</p></span></div></foreignObject></g></g>
<foreignObject id="gate" x="5" y="40" width="40" height="20"><div {xhtml} style="font-size:4px">North<br/>  Gate </div></foreignObject>
<switch><foreignObject id="skipped" requiredFeatures="http://www.w3.org/TR/SVG11/feature#Extensibility" width="20" height="9"><div {xhtml}>Dup</div></foreignObject><text id="fallback" x="70" y="50">Dup</text></switch>
<g style="display:none"><foreignObject id="hidden" width="20" height="9"><div {xhtml}>Hidden</div></foreignObject></g>"#
    ));
    let d = resolve(&svg);
    let runs = |id: &str| match &by_id(&d, id).shape {
        Shape::Text(t) => t.runs.iter().map(|r| (r.text.clone(), r.x_mm, r.y_mm, r.anchor)).collect::<Vec<_>>(),
        s => panic!("{id} is not a text: {s:?}"),
    };
    // Centred in its 30-unit box at x 35: 50; its top at 14, a 9-unit line
    // of a 6-unit font: baseline 14 + 1.5 + 6.
    let got = runs("start");
    assert!(got.len() == 1 && got[0].0 == "Start" && close(got[0].1, 50.0) && close(got[0].2, 21.5), "{got:?}");
    assert_eq!(got[0].3, 0.5);
    // Lines of 1.2 font sizes: baselines at 40 + 0.4 + 4 and 4.8 below.
    let got = runs("gate");
    let want = [("North", 44.4), ("Gate", 49.2)];
    assert_eq!(got.len(), 2, "{got:?}");
    for ((text, x, y, anchor), (t, wy)) in got.iter().zip(want) {
        assert!(text == t && close(*x, 5.0) && close(*y, wy) && *anchor == 0.0, "{got:?}");
    }
    let texts: Vec<&str> =
        d.elements.iter().filter(|e| matches!(e.shape, Shape::Text(_))).map(|e| e.id.as_str()).collect();
    assert_eq!(texts, ["start", "gate", "fallback"], "{:#?}", d.elements);
}

/// Text turned on its side (Vega-Lite's and matplotlib's tick labels under
/// a bar chart, `rotate(270)` with `text-anchor: end`) is placed at its
/// middle, centred: braille is written level, and from the anchor (the
/// text's end, on the axis) it stood on the axis and ran into the bars. A
/// level text keeps its anchor.
#[test]
fn text_turned_on_its_side_is_placed_at_its_middle() {
    let svg = page(
        r#"<text id="turned" transform="translate(50 40) rotate(270)" text-anchor="end" font-size="4">ABCD</text>
<text id="tilted" transform="translate(20 20) rotate(-30)" text-anchor="end" font-size="4">ABCD</text>"#,
    );
    let d = resolve_as_read(&svg);
    let run = |id: &str| match &by_id(&d, id).shape {
        Shape::Text(t) => (t.runs[0].x_mm, t.runs[0].y_mm, t.runs[0].anchor),
        s => panic!("{id} is not a text: {s:?}"),
    };
    // Four characters at half a font size each: 8 mm, running up the page
    // and ending at (50, 40), so its middle is 4 mm below that.
    let (x, y, anchor) = run("turned");
    assert!(close(x, 50.0) && close(y, 44.0) && anchor == 0.5, "{:?}", run("turned"));
    // Closer to level than upright: its anchor as written.
    let (x, y, anchor) = run("tilted");
    assert!(close(x, 20.0) && close(y, 20.0) && anchor == 1.0, "{:?}", run("tilted"));
}

/// A label drawn in no colour that is seen (at opacity 0, as an exported
/// chart's tooltip that waits for the pointer, or with no fill and no
/// stroke, as a scanned PDF's hidden text layer) becomes no braille under
/// the automatic sheet; the label beside it does.
#[test]
fn text_drawn_at_opacity_0_is_no_label() {
    let opts = CompileOptions { fonts: Some(tuffy()), ..CompileOptions::new(stress2()) };
    let braille_cells = |body: &str| {
        let c = no_internal_error(taxel_compiler::compile_svg(&page(body), &opts));
        dots(bundle(&c), DotKind::Braille).map_or(0, |t| t.dots.len())
    };
    let shown = r##"<rect x="5" y="5" width="40" height="40" fill="#00aa00"/><text x="55" y="40" font-family="Tuffy" font-size="6">Shown</text>"##;
    let alone = braille_cells(shown);
    assert!(alone > 0);
    for hidden in [
        r#"<text x="55" y="20" font-family="Tuffy" font-size="6" opacity="0">Hidden</text>"#,
        r#"<g opacity="0"><text x="55" y="20" font-family="Tuffy" font-size="6">Hidden</text></g>"#,
        r##"<text x="55" y="20" font-family="Tuffy" font-size="6" fill="#000000" fill-opacity="0">Hidden</text>"##,
        r#"<text x="55" y="20" font-family="Tuffy" font-size="6" fill="none">Hidden</text>"#,
    ] {
        assert_eq!(braille_cells(&format!("{shown}{hidden}")), alone, "{hidden}");
    }
    let seen = r#"<text x="55" y="20" font-family="Tuffy" font-size="6" opacity="0.5">Seen</text>"#;
    assert!(braille_cells(&format!("{shown}{seen}")) > alone);
    // Annotated, hidden text is braille all the same: a label written for the reader's hand alone.
    for asked in [
        r#"<text x="55" y="20" font-family="Tuffy" font-size="6" fill="none" data-tactile="braille()">Asked</text>"#,
        r#"<text x="55" y="20" font-family="Tuffy" font-size="6" opacity="0" data-tactile="braille()">Asked</text>"#,
    ] {
        let c = no_internal_error(taxel_compiler::compile_svg(&page(asked), &opts));
        assert!(dots(bundle(&c), DotKind::Braille).is_some_and(|t| !t.dots.is_empty()), "{asked}");
    }
}

#[test]
fn a_symbol_placed_by_a_transformed_use_is_clipped_to_its_own_viewport() {
    // Inkscape places a symbol from its libraries with a `<use>` moved by
    // `transform`; the symbol's viewport clips it there, not at the origin
    // (usvg's transform to the root of the group that clips it leaves the
    // move out). 200 user units are 100 mm.
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="100mm" height="50mm" viewBox="0 0 200 100">
  <defs>
    <symbol id="church" viewBox="0 0 20 20"><path d="M2 18 L10 2 L18 18 Z" fill="black"/></symbol>
    <symbol id="wide"><rect x="-20" y="-10" width="60" height="60" fill="green"/></symbol>
  </defs>
  <use id="far" xlink:href="#church" width="20" height="20" transform="translate(150,40)"/>
  <use id="over" xlink:href="#wide" transform="translate(50,20)"/>
</svg>"##;
    let d = resolve(svg);
    let clip_bounds = |e: &Element| match &e.shape {
        Shape::Path(p) => p.clips.iter().map(|c| taxel_compiler::geometry::bounds(&c.outline)).collect::<Vec<_>>(),
        _ => panic!("{} is not a path", e.name),
    };
    // The church, felt where it is drawn: its viewport is the use's 20 x 20
    // units at (150, 40), and the triangle lies inside it.
    let far = by_id(&d, "far");
    assert!(!far.styles.is_empty(), "the symbol is felt: {far:#?}");
    bounds_close(far, (76.0, 21.0, 84.0, 29.0));
    let [Some(c)] = clip_bounds(far)[..] else { panic!("one clip: {:?}", clip_bounds(far)) };
    assert!(close(c.0, 75.0) && close(c.1, 20.0) && close(c.2, 85.0) && close(c.3, 30.0), "{c:?}");
    // A symbol without a viewBox takes the page's viewport, moved with the
    // use: what it draws left of and above the use's origin is cut away.
    let over = by_id(&d, "over");
    bounds_close(over, (15.0, 5.0, 45.0, 35.0));
    let [Some(c)] = clip_bounds(over)[..] else { panic!("one clip: {:?}", clip_bounds(over)) };
    assert!(close(c.0, 25.0) && close(c.1, 10.0), "the viewport starts at the use's origin: {c:?}");
}

#[test]
fn a_clip_path_of_hidden_shapes_clips_everything_away() {
    let svg = page(
        r#"<clipPath id="hidden"><rect x="0" y="0" width="100" height="60" visibility="hidden"/></clipPath>
<clipPath id="shown"><rect x="0" y="0" width="100" height="60"/></clipPath>
<rect id="away" x="10" y="10" width="30" height="30" fill="red" clip-path="url(#hidden)" data-tactile="grating()"/>
<rect id="kept" x="50" y="10" width="30" height="30" fill="green" clip-path="url(#shown)" data-tactile="grating()"/>"#,
    );
    let c = compile(&svg);
    let away = with_code(&c, "T0301");
    assert_eq!(away.len(), 1, "{:#?}", c.diagnostics);
    assert!(away[0].message.contains("clipped or masked away") && away[0].element.as_deref() == Some("away"));
    assert_eq!(masks(bundle(&c)).len(), 1);
}
