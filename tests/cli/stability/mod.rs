//! The named stiff and extreme cases (docs/stability.md lists each one, what
//! taxel does and why). Every case asserts its outcome: values finite and in
//! range, the diagnostic that must appear, or the limit's message.

mod drawings;
mod limits;
mod meshes;
mod playback;
mod strokes;

use taxel_compiler::{CompileOptions, Compiled, Diagnostic, svg::compile_svg};
use taxel_format::{Bundle, BundleView, Chunk, Family, profiles};

/// Compiles `svg` for the built-in profile `profile`.
pub fn compile(svg: &str, profile: &str) -> Compiled {
    compile_svg(svg, &CompileOptions::new(profiles::builtin(profile).expect("built-in profile")))
}

/// Whether a diagnostic with `code` is among `diags`.
pub fn has(diags: &[Diagnostic], code: &str) -> bool {
    diags.iter().any(|d| d.code == code)
}

/// Codes of `diags`, for assertion messages.
pub fn codes(diags: &[Diagnostic]) -> Vec<&'static str> {
    diags.iter().map(|d| d.code).collect()
}

/// A 110 x 60 mm drawing (the stress2 surface) around `body`.
pub fn page(body: &str) -> String {
    format!(r#"<svg xmlns="http://www.w3.org/2000/svg" width="110mm" height="60mm" viewBox="0 0 110 60">{body}</svg>"#)
}

/// Asserts every number a bundle carries is finite and in its range, that
/// it survives its own writer and reader, and that its distance layers and
/// layer plan keep the compiler's invariants (`distance::sanity_check`,
/// `sanity::latero_plan`).
pub fn assert_sane(b: &Bundle) {
    let bytes = b.to_bytes().expect("the bundle writes");
    BundleView::parse(&bytes).expect("the bundle reads back");
    for c in &b.chunks {
        match c {
            Chunk::Mask(m) => {
                assert!(m.origin_x.0.is_finite() && m.origin_y.0.is_finite() && m.px_per_mm.is_finite());
                assert!((0.0..=1.0).contains(&m.amplitude));
            }
            Chunk::Dots(t) => {
                for d in &t.dots {
                    assert!(d.x.0.is_finite() && d.y.0.is_finite() && d.radius.0.is_finite() && d.radius.0 > 0.0);
                    assert!((0.0..=1.0).contains(&d.amplitude));
                }
            }
            Chunk::Strokes(t) => {
                for s in &t.strokes {
                    assert!((0.0..=1.0).contains(&s.intensity));
                    for p in &s.points {
                        assert!(p.duration >= 1 && p.x.0.is_finite() && p.y.0.is_finite());
                        assert!(p.drives.iter().all(|d| (0.0..=1.0).contains(&d.intensity)));
                    }
                }
            }
            Chunk::Distance(d) => {
                assert!(d.origin_x.0.is_finite() && d.origin_y.0.is_finite());
                assert!(d.pitch_mm > 0.0 && d.step_mm > 0.0 && d.soft_mm >= 0.0);
                assert!((0.0..=1.0).contains(&d.amplitude));
                // What the writer promises of its tiles beyond the format's checks.
                if let Err(e) = taxel_compiler::distance::sanity_check(d) {
                    panic!("{} layer: {e}", d.tag());
                }
            }
            // Checked by the reader above; meshes and pin images have their own cases.
            Chunk::Height(_) | Chunk::Pins(_) | Chunk::Provenance(_) | Chunk::Footprints(_) | Chunk::Raw(_) => {}
        }
    }
    if b.manifest.profile.family() == Family::Laterotactile
        && let Err(e) = taxel_compiler::sanity::latero_plan(b)
    {
        panic!("the layer plan breaks an invariant: {e}");
    }
}
