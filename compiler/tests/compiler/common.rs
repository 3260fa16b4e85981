//! Helpers shared by the compiler tests.

use taxel_compiler::{CompileOptions, Compiled, Diagnostic, Severity, compile_svg};
use taxel_format::{Bundle, Chunk, DeviceProfile, DistanceLayer, DotKind, DotTable, profiles};

/// The STRESS² profile.
pub fn stress2() -> DeviceProfile {
    profiles::builtin("stress2").expect("built-in profile")
}

/// Compiles `svg` for STRESS² with default options. An internal error
/// (T0900, a panic caught) fails the test: no test may pass through one.
pub fn compile(svg: &str) -> Compiled {
    no_internal_error(compile_svg(svg, &CompileOptions::new(stress2())))
}

/// `c`, failing the test if it holds an internal error (T0900).
pub fn no_internal_error(c: Compiled) -> Compiled {
    assert!(c.diagnostics.iter().all(|d| d.code != "T0900"), "internal error: {:#?}", c.diagnostics);
    c
}

/// Wraps shapes in a 100 x 60 mm page whose user unit is one millimetre.
pub fn page(body: &str) -> String {
    format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" width="100mm" height="60mm" viewBox="0 0 100 60">
{body}
</svg>"#
    )
}

/// The bundle, failing the test with the diagnostics when there is none.
pub fn bundle(c: &Compiled) -> &Bundle {
    c.bundle.as_ref().unwrap_or_else(|| panic!("no bundle: {:#?}", c.diagnostics))
}

/// The diagnostics with `code`.
pub fn with_code<'a>(c: &'a Compiled, code: &str) -> Vec<&'a Diagnostic> {
    c.diagnostics.iter().filter(|d| d.code == code).collect()
}

/// Whether there is an error.
pub fn has_error(c: &Compiled) -> bool {
    c.diagnostics.iter().any(|d| d.severity == Severity::Error)
}

/// The distance layers (one per vibration or grating style).
pub fn masks(b: &Bundle) -> Vec<&DistanceLayer> {
    b.chunks
        .iter()
        .filter_map(|c| match c {
            Chunk::Distance(m) => Some(m),
            _ => None,
        })
        .collect()
}

/// The dot table of `kind`, if any.
pub fn dots(b: &Bundle, kind: DotKind) -> Option<&DotTable> {
    b.chunks.iter().find_map(|c| match c {
        Chunk::Dots(d) if d.kind == kind => Some(d),
        _ => None,
    })
}

/// A layer's edge profile (0..=1) at page position `(x, y)`, as a player
/// reads it (SPEC.md section 6.2), zero outside its lattice.
pub fn sample(m: &DistanceLayer, x: f64, y: f64) -> f64 {
    m.coverage_at(x as f32, y as f32) as f64
}

/// The page x range `[x0, x1)` of a distance layer's lattice.
pub fn lattice_x(m: &DistanceLayer) -> (f32, f32) {
    (m.origin_x.0, m.origin_x.0 + m.tile_cols as f32 * 8.0 * m.pitch_mm)
}

/// Whether a lattice starting at `x0` and ending at `x1` covers `[lo, hi]`
/// and starts at most a tile's reach (two pitches) and one pitch before `lo`.
pub fn covers_tightly(m: &DistanceLayer, lo: f32, hi: f32) -> bool {
    let (x0, x1) = lattice_x(m);
    x0 <= lo && x0 >= lo - 3.0 * m.pitch_mm - 1e-3 && x1 >= hi
}
