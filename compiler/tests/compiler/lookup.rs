//! The footprints chunk the compiler writes (SPEC.md section 10.1) and the
//! point lookup over it: what lies under a surface point of a compiled drawing.
//! Expected points are read off the drawings' own coordinates.

use taxel_compiler::{CompileOptions, compile_svg};
use taxel_format::BundleView;
use taxel_format::lookup::PointLookup;

use crate::common::*;

/// The name under each point of `svg` compiled with `opts`.
fn names(svg: &str, opts: &CompileOptions, points: &[(f64, f64)]) -> Vec<Option<String>> {
    let c = no_internal_error(compile_svg(svg, opts));
    let bytes = bundle(&c).to_bytes().unwrap();
    let view = BundleView::parse(&bytes).unwrap();
    // Footprints came with 2.1; every 3.x reader knows them.
    assert_eq!(view.version().0, taxel_format::FORMAT_MAJOR, "a bundle with footprints is of this major version");
    let lookup = PointLookup::new(&view, PointLookup::DEFAULT_TOLERANCE_MM).expect("footprints");
    points.iter().map(|&(x, y)| lookup.under(x, y).map(|h| h.name())).collect()
}

#[test]
fn tala_map_names_a_province_its_border_a_town_and_nothing_outside() {
    let svg = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/map/tala-map.svg")).unwrap();
    let points = [
        // Inside "ash province" (M 7.55,25.27 9.58,10.34 26.89,6.73 31.02,26.69 Z), 8.5 mm from its town's hole.
        (25.0, 15.0),
        // On the border from (30, 2) to (36, 31), halfway.
        (33.0, 16.5),
        // Ashby's dot at (17, 18), in ash province's hole.
        (17.5, 18.0),
        // The hole of elm province around Elmford (52, 22), 2.8 mm from the town: nothing.
        (50.0, 20.0),
        // The sea in the bottom-right corner (not tactile): nothing.
        (100.0, 58.0),
    ];
    let got = names(&svg, &CompileOptions::new(stress2()), &points);
    let want = [Some("ash province"), Some("coast and province borders"), Some("Ashby"), None, None];
    assert_eq!(got, want.map(|n| n.map(String::from)));
}

#[test]
fn the_topmost_element_wins_and_the_id_names_an_unlabelled_one() {
    let svg = page(
        r#"<rect id="low" x="10" y="10" width="30" height="30" data-tactile="grating(wavelength: 3mm)"><title>lower square</title></rect>
<rect id="high" x="25" y="25" width="30" height="30" data-tactile="grating(wavelength: 6mm)" aria-label="upper square"/>
<path id="line" d="M 5 32 H 80" data-tactile="vibrate(width: 1mm)"/>"#,
    );
    let points = [(15.0, 15.0), (30.0, 30.0), (50.0, 50.0), (70.0, 32.4), (70.0, 33.5), (90.0, 50.0)];
    let got = names(&svg, &CompileOptions::new(stress2()), &points);
    let want = [Some("lower square"), Some("upper square"), Some("upper square"), Some("line"), None, None];
    assert_eq!(got, want.map(|n| n.map(String::from)));
}

/// A shape without a label of its own is named by its group's `<title>`,
/// `aria-label` or Inkscape label (charts and maps label groups of paths);
/// the drawing's own title, an Inkscape layer's label and a `tactile:`
/// annotation name nothing, so such a shape keeps its id.
#[test]
fn a_shape_without_a_label_is_named_by_its_group() {
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
     width="100mm" height="60mm" viewBox="0 0 100 60">
<title>Lakes of the region</title>
<g inkscape:groupmode="layer" inkscape:label="Layer 1">
  <g><title>Lake Geneva</title>
    <rect id="west" x="5" y="5" width="10" height="10" data-tactile="grating()"/>
    <g><rect id="east" x="20" y="5" width="10" height="10" data-tactile="grating()"/></g>
  </g>
  <g aria-label="Lake Constance"><rect id="c" x="35" y="5" width="10" height="10" data-tactile="grating()" aria-label="Obersee"/></g>
  <g inkscape:label="tactile: grating()"><rect id="annotated" x="50" y="5" width="10" height="10"/></g>
  <rect id="alone" x="65" y="5" width="10" height="10" data-tactile="grating()"/>
  <rect id="self" x="80" y="5" width="10" height="10" inkscape:label="tactile: grating()"/>
</g>
</svg>"#;
    let got = names(
        svg,
        &CompileOptions::new(stress2()),
        &[(10.0, 10.0), (25.0, 10.0), (40.0, 10.0), (55.0, 10.0), (70.0, 10.0)],
    );
    let want = [Some("Lake Geneva"), Some("Lake Geneva"), Some("Obersee"), Some("annotated"), Some("alone")];
    assert_eq!(got, want.map(|n| n.map(String::from)));
}

#[test]
fn under_fit_footprints_are_in_surface_millimetres() {
    // A 220 x 120 mm page on the 110 x 60 mm stress2 surface: --fit halves it
    // (marks at two corners: the drawing shows its whole page).
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="220mm" height="120mm" viewBox="0 0 220 120">
<rect x="20" y="20" width="40" height="40" data-tactile="grating()" aria-label="square"/>
<rect x="0" y="0" width="2" height="2"/><rect x="218" y="118" width="2" height="2"/>
</svg>"#;
    let mut opts = CompileOptions::new(stress2());
    assert_eq!((opts.profile.surface_w_mm, opts.profile.surface_h_mm), (110.0, 60.0));
    opts.fit = true;
    let got = names(svg, &opts, &[(20.0, 20.0), (50.0, 50.0)]);
    assert_eq!(got, [Some("square".to_string()), None]);
}

#[test]
fn a_finger_between_braille_dots_finds_the_text() {
    let svg = page(r#"<text id="key" x="20" y="30" data-tactile="braille()">key</text>"#);
    let c = no_internal_error(compile_svg(&svg, &CompileOptions::new(stress2())));
    let b = bundle(&c);
    let dots = dots(b, taxel_format::DotKind::Braille).expect("braille dots");
    let pts: Vec<(f64, f64, f64)> = dots.dots.iter().map(|d| (d.x.0 as f64, d.y.0 as f64, d.radius.0 as f64)).collect();
    let (x0, x1) = pts.iter().fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.0), a.1.max(p.0)));
    let (y0, y1) = pts.iter().fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.1), a.1.max(p.1)));
    // A point inside the dots' box but farther from every dot than its radius plus the tolerance.
    let far = |x: f64, y: f64| pts.iter().all(|p| (p.0 - x).hypot(p.1 - y) > p.2 + PointLookup::DEFAULT_TOLERANCE_MM);
    let probe = (0..=40)
        .flat_map(|i| (0..=40).map(move |j| (x0 + (x1 - x0) * i as f64 / 40.0, y0 + (y1 - y0) * j as f64 / 40.0)))
        .find(|&(x, y)| far(x, y))
        .expect("a gap between the dots");
    let bytes = b.to_bytes().unwrap();
    let lookup = PointLookup::new(&BundleView::parse(&bytes).unwrap(), PointLookup::DEFAULT_TOLERANCE_MM).unwrap();
    assert_eq!(lookup.under(probe.0, probe.1).map(|h| h.name()), Some("key".to_string()), "{probe:?}");
    assert_eq!(lookup.under(x1 + 5.0, y0).map(|h| h.name()), None);
}
