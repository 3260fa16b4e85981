//! Drawings compiled by the library and played by the runtime's
//! laterotactile player: what a reader feels at an edge (soft and hard) and
//! where shapes of one style overlap. Here rather than in the compiler's
//! tests, since the compiler does not depend on the runtime.

use taxel_compiler::{CompileOptions, Compiled, svg::compile_svg};
use taxel_format::{Bundle, Chunk, DeviceProfile, DistanceLayer, profiles};

/// The STRESS² profile.
fn stress2() -> DeviceProfile {
    profiles::builtin("stress2").expect("built-in profile")
}

/// Compiles `svg` for STRESS² with default options; an internal error
/// (T0900, a panic caught) fails the test.
fn compile(svg: &str) -> Compiled {
    let c = compile_svg(svg, &CompileOptions::new(stress2()));
    assert!(c.diagnostics.iter().all(|d| d.code != "T0900"), "internal error: {:#?}", c.diagnostics);
    c
}

/// Wraps shapes in a 100 x 60 mm page whose user unit is one millimetre.
fn page(body: &str) -> String {
    format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm" viewBox="0 0 100 60">
{body}
</svg>"#
    )
}

/// The bundle, failing the test with the diagnostics when there is none.
fn bundle(c: &Compiled) -> &Bundle {
    c.bundle.as_ref().unwrap_or_else(|| panic!("no bundle: {:#?}", c.diagnostics))
}

/// The distance layers (one per vibration or grating style).
fn masks(b: &Bundle) -> Vec<&DistanceLayer> {
    b.chunks
        .iter()
        .filter_map(|c| match c {
            Chunk::Distance(m) => Some(m),
            _ => None,
        })
        .collect()
}

/// A layer's edge profile (0..=1) at page position `(x, y)`, as a player reads it.
fn sample(m: &DistanceLayer, x: f64, y: f64) -> f64 {
    m.coverage_at(x as f32, y as f32) as f64
}

/// The code an actuator plays at tick 0 of a STRESS² frame whose actuator
/// (row 3, column 0) sits at `(x, y)`: there, with row and column parities
/// differing, a vibration is fully deflected, so the code is the layer's
/// amplitude there times 1023 (seed 000 eq. 2, primitives.md).
fn played_at(b: &taxel_format::Bundle, x: f32, y: f32) -> u16 {
    let p = stress2();
    let bytes = b.to_bytes().expect("the bundle encodes");
    let view = taxel_format::BundleView::parse(&bytes).expect("the bundle validates");
    let player = taxel_runtime::latero::LateroPlayer::new(&view).expect("a laterotactile bundle");
    let (cx, cy) = (x + 3.5 * p.pitch_x_mm, y + 0.5 * p.pitch_y_mm);
    let mut frame = [0u16; 64];
    player.frame(taxel_format::Tick(0), taxel_format::Mm(cx), taxel_format::Mm(cy), &mut frame);
    frame[3 * p.cols as usize]
}

/// `soft:` in `vibrate(...)` goes from the drawing to the bundle and is what
/// the player plays: a ramp of that width centred on the band's edge,
/// `clamp(½ + d / soft, 0, 1)` with `d` the distance inside the band
/// (SPEC.md section 6.2), where a hard edge jumps from 0 to full within
/// one sample step (0.01 mm). The same for `grating(..., soft: ...)`.
#[test]
fn a_soft_edge_is_written_and_played_as_a_ramp_of_its_width() {
    let svg = |style: &str| {
        page(&format!(
            r#"<rect x="30" y="20" width="40" height="20" fill="none" stroke="black" data-tactile="{style}"/>"#
        ))
    };
    let soft = compile(&svg("vibrate(width: 2mm, soft: 0.4mm)"));
    let hard = compile(&svg("vibrate(width: 2mm)"));
    let (soft_b, hard_b) = (bundle(&soft), bundle(&hard));
    assert_eq!(masks(soft_b)[0].soft_mm, 0.4);
    assert_eq!(masks(hard_b)[0].soft_mm, 0.0);
    // The left side's band spans x = 29 to 31 mm; its outer edge is x = 29.
    for (d, want) in [(-0.3f32, 0.0f32), (-0.1, 0.25), (0.0, 0.5), (0.1, 0.75), (0.15, 0.875), (0.3, 1.0)] {
        let code = played_at(soft_b, 29.0 + d, 30.0);
        let exact = (want * 1023.0).round() as i32;
        assert!((code as i32 - exact).abs() <= 2, "soft edge at {d} mm inside: code {code}, want {exact}");
        let hard_code = played_at(hard_b, 29.0 + d, 30.0);
        let hard_want = if d > 0.0 {
            1023
        } else if d < 0.0 {
            0
        } else {
            hard_code
        };
        assert_eq!(hard_code, hard_want, "hard edge at {d} mm inside");
    }
    // A grating's soft edge is written the same way.
    let grated = compile(&page(
        r#"<rect x="30" y="20" width="40" height="20" data-tactile="grating(wavelength: 3mm, soft: 0.5mm)"/>"#,
    ));
    let m = masks(bundle(&grated));
    assert_eq!((m.len(), m[0].soft_mm), (1, 0.5));
    // Its ramp: half amplitude on the edge, a quarter 0.125 mm outside.
    assert!((sample(m[0], 30.0, 30.0) - 0.5).abs() < 0.01);
    assert!((sample(m[0], 29.875, 30.0) - 0.25).abs() < 0.01);
    assert!((sample(m[0], 30.125, 30.0) - 0.75).abs() < 0.01);
}

/// Shapes of one style that overlap or touch are one region of one layer:
/// no overlap warning (T0410, for different layers only) and nothing
/// clamped where they meet, played across the overlap.
#[test]
fn overlapping_shapes_of_one_style_are_one_region_and_never_clamp() {
    let c = compile(&page(
        r#"<g data-tactile="vibrate(width: 2mm)" fill="none" stroke="black">
  <rect x="20" y="20" width="30" height="20"/>
  <rect x="40" y="25" width="30" height="20"/>
  <rect x="70" y="25" width="10" height="20"/>
</g>"#,
    ));
    assert!(c.diagnostics.iter().all(|d| d.code != "T0410"), "{:#?}", c.diagnostics);
    let b = bundle(&c);
    assert_eq!(masks(b).len(), 1);
    let bytes = b.to_bytes().expect("the bundle encodes");
    let view = taxel_format::BundleView::parse(&bytes).expect("the bundle validates");
    let player = taxel_runtime::latero::LateroPlayer::new(&view).expect("a laterotactile bundle");
    let mut frame = [0u16; 64];
    // Over the crossings of the first two outlines and along the shared side.
    for (x, y) in [(40.0, 20.0), (50.0, 25.0), (40.0, 40.0), (50.0, 45.0), (70.0, 35.0), (45.0, 32.0)] {
        for tick in [0u64, 7, 10, 13] {
            let stats = player.frame(taxel_format::Tick(tick), taxel_format::Mm(x), taxel_format::Mm(y), &mut frame);
            assert_eq!(stats.clamped, 0, "clamped at ({x}, {y}), tick {tick}");
        }
    }
}
