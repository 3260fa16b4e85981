//! Helpers shared by the compiler tests.

use taxel_compiler::{CompileOptions, Compiled, Diagnostic, Severity, svg::compile_svg};
use taxel_format::{Bundle, Chunk, DeviceProfile, DotKind, DotTable, MaskLayer, profiles};

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

/// The mask chunks.
pub fn masks(b: &Bundle) -> Vec<&MaskLayer> {
    b.chunks
        .iter()
        .filter_map(|c| match c {
            Chunk::Mask(m) => Some(m),
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

/// Bilinear mask value (0..=1) at page position `(x, y)`, as a player reads it:
/// sample centres at `origin + (i + ½) / px`, zero outside.
pub fn sample(m: &MaskLayer, x: f64, y: f64) -> f64 {
    let px = m.px_per_mm as f64;
    let fx = (x - m.origin_x.0 as f64) * px - 0.5;
    let fy = (y - m.origin_y.0 as f64) * px - 0.5;
    let (i0, j0) = (fx.floor(), fy.floor());
    let (tx, ty) = (fx - i0, fy - j0);
    let get = |i: f64, j: f64| -> f64 {
        if i < 0.0 || j < 0.0 || i >= m.width as f64 || j >= m.height as f64 {
            return 0.0;
        }
        let k = j as usize * m.width as usize + i as usize;
        match &m.samples {
            taxel_format::MaskSamples::U8(v) => v[k] as f64 / 255.0,
            taxel_format::MaskSamples::U16(v) => v[k] as f64 / 65535.0,
        }
    };
    let a = get(i0, j0) * (1.0 - tx) + get(i0 + 1.0, j0) * tx;
    let b = get(i0, j0 + 1.0) * (1.0 - tx) + get(i0 + 1.0, j0 + 1.0) * tx;
    a * (1.0 - ty) + b * ty
}
