//! The public layer plan (`latero::plan`): the layers a bundle holds, each
//! built from the plan's geometry and nothing else; a grating's makeup
//! (the bands cut out of it, the opaque fills and braille clearings over
//! it, its clips); the dot tables and brush requests.

use taxel_compiler::latero::distance::{FieldParams, build_field};
use taxel_compiler::{CompileOptions, compile_svg, latero, pipeline};
use taxel_format::{Chunk, MaskKind, profiles};

use crate::common::{bundle, masks, no_internal_error, page, stress2};

/// A grating crossed by a vibrating ring, half hidden by an opaque fill
/// painted after it, another grating clipped by a nested viewport, a dot,
/// and braille beside the first grating.
fn scene() -> String {
    page(
        r##"<rect id="land" x="5" y="5" width="40" height="40" data-tactile="grating(wavelength: 2mm)"/>
<circle id="ring" cx="25" cy="25" r="12" fill="none" stroke="black" data-tactile="vibrate(width: 2mm)"/>
<rect id="lake" x="30" y="30" width="12" height="12" fill="#0000ff"/>
<svg x="55" y="5" width="20" height="20" viewBox="0 0 20 20">
  <circle id="sea" cx="10" cy="10" r="14" data-tactile="grating(wavelength: 3mm)"/>
</svg>
<circle id="spot" cx="85" cy="50" r="2" data-tactile="dot()"/>
<text id="label" x="8" y="52" font-size="4" data-tactile="braille()">land</text>"##,
    )
}

#[test]
fn every_distance_layer_is_built_from_its_plan() {
    let svg = scene();
    let opts = CompileOptions::new(stress2());
    let compiled = no_internal_error(compile_svg(&svg, &opts));
    let b = bundle(&compiled);
    let drawing = pipeline::resolve(&svg, &opts).drawing.expect("a drawing");
    let plan = latero::plan(&drawing, &opts);
    plan.sanity_check(&drawing).expect("a sane plan");
    let chunks = masks(b);
    assert_eq!(plan.layers.len(), chunks.len(), "{:?}", plan.layers.iter().map(|l| l.kind).collect::<Vec<_>>());
    for (k, (l, d)) in plan.layers.iter().zip(&chunks).enumerate() {
        assert_eq!((l.kind, l.amplitude as f32, l.soft_mm as f32), (d.kind, d.amplitude, d.soft_mm));
        assert_eq!(l.sources, d.sources);
        assert_eq!(plan.pitch_mm as f32, d.pitch_mm);
        // The plan's geometry alone gives the bundle's field, tile for tile.
        let g = plan.geometry(&drawing, k).expect("its geometry");
        let params = FieldParams { pitch_mm: plan.pitch_mm, soft_mm: l.soft_mm, page: plan.page };
        let field = build_field(&g, params).expect("a field");
        assert_eq!((field.tile_cols, field.tile_rows), (d.tile_cols, d.tile_rows));
        assert!(field.tiles == d.tiles && field.planes == d.planes && field.samples == d.samples, "layer {k}");
    }
    // The dot tables are the bundle's.
    let tables: Vec<_> = b.chunks.iter().filter_map(|c| if let Chunk::Dots(t) = c { Some(t) } else { None }).collect();
    assert_eq!(plan.dots.iter().collect::<Vec<_>>(), tables);
}

#[test]
fn a_gratings_plan_names_what_cuts_hides_and_clips_it() {
    let svg = scene();
    let opts = CompileOptions::new(stress2());
    let drawing = pipeline::resolve(&svg, &opts).drawing.expect("a drawing");
    let plan = latero::plan(&drawing, &opts);
    let index = |id: &str| drawing.elements.iter().position(|e| e.id == id).expect(id);
    let layer_of = |id: &str| plan.layers.iter().find(|l| l.elements.contains(&index(id))).expect(id);
    let land = layer_of("land");
    assert!(matches!(land.kind, MaskKind::Grating { .. }) && land.fills.len() == 1);
    // The ring crossing it is cut out of it, 2 mm wide; the lake painted over it hides it.
    assert_eq!(land.cuts.len(), 1);
    assert_eq!(land.cuts[0].1, 2.0);
    assert_eq!(land.covered_by, vec![index("lake")]);
    // Braille is written beside it, and its clearing meets it.
    assert!(!plan.braille_clearing.is_empty() && !land.clearing.is_empty());
    let g = plan.geometry(&drawing, 0).expect("its geometry");
    assert_eq!(g.occluders.len(), land.covered_by.len() + land.clearing.len());
    // The nested viewport clips the sea; the ring is a band of its own, uncut.
    let sea = layer_of("sea");
    assert_eq!(sea.clips.len(), 1);
    assert!(sea.cuts.is_empty(), "the ring is far from the sea");
    let ring = layer_of("ring");
    assert_eq!(ring.band.as_ref().map(|b| (b.0.len(), b.1)), Some((1, 2.0)));
    assert!(ring.fills.is_empty() && ring.covered_by.is_empty());
}

#[test]
fn brushed_paths_are_planned_for_a_grid() {
    let svg = page(
        r#"<path id="stroke" d="M 10 10 L 50 40" fill="none" stroke="black" data-tactile="brush(duration: 400ms)"/>"#,
    );
    let opts = CompileOptions::new(profiles::builtin("brush-4x3").expect("built-in profile"));
    let compiled = no_internal_error(compile_svg(&svg, &opts));
    let drawing = pipeline::resolve(&svg, &opts).drawing.expect("a drawing");
    let plan = latero::plan(&drawing, &opts);
    assert!(plan.layers.is_empty());
    assert_eq!(plan.brush.len(), 1);
    assert_eq!(plan.brush[0].duration_ms, 400.0);
    let strokes = bundle(&compiled).chunks.iter().find_map(|c| if let Chunk::Strokes(s) = c { Some(s) } else { None });
    assert_eq!(strokes.map(|s| s.strokes.len()), Some(1));
}
