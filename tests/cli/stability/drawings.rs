//! Drawings at the edges: degenerate paths, extreme scales, aliasing
//! wavelengths, overlapping layers, empty and unsupported scenes, and NaN or
//! infinity in the SVG, its annotations and style sheets.

use taxel_compiler::{CompileOptions, StyleSheet, svg::compile_svg};
use taxel_format::{Chunk, profiles};

use super::{assert_sane, codes, compile, has, page};

/// A zero-length path and a lone `M` draw nothing: a warning (T0301) for
/// the shape, the error T0300 for the scene, and no NaN anywhere.
#[test]
fn zero_length_and_single_point_paths() {
    for d in ["M 10 10 L 10 10", "M 10 10", "M 10 10 Z"] {
        let out =
            compile(&page(&format!(r#"<path id="p" d="{d}" stroke="black" data-tactile="vibrate()"/>"#)), "stress2");
        if let Some(b) = &out.bundle {
            assert_sane(b);
        } else {
            assert!(has(&out.diagnostics, "T0300"), "{d}: {:?}", codes(&out.diagnostics));
        }
    }
    // Dots along a path of no length: no dots, no division by zero.
    let out = compile(&page(r#"<path id="p" d="M 10 10 L 10 10" data-tactile="dots()"/>"#), "stress2");
    assert!(
        out.bundle.as_ref().is_none_or(|b| {
            assert_sane(b);
            true
        }),
        "{:?}",
        codes(&out.diagnostics)
    );
}

/// A shape of a few nanometres: smaller than 2 cm (T0407) and too small for
/// any mask sample; the compiler says so instead of writing an empty layer.
#[test]
fn coordinates_at_1e_minus_6_mm() {
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="110mm" height="60mm" viewBox="0 0 110 60">
        <rect id="tiny" x="50" y="30" width="0.000001" height="0.000001" data-tactile="grating()"/>
        <circle id="dot" cx="20" cy="20" r="0.000001" data-tactile="dot(radius: 0.000001mm)"/></svg>"#;
    let out = compile(svg, "stress2");
    if let Some(b) = &out.bundle {
        assert_sane(b);
    }
    assert!(!out.diagnostics.is_empty(), "a nanometre shape must not pass silently");
}

/// A kilometre-wide drawing: larger than the surface (T0202), its layers
/// storing nothing beyond the surface; finite values.
#[test]
fn coordinates_at_1e6_mm() {
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="1000000mm" height="600000mm" viewBox="0 0 1000000 600000">
        <rect id="huge" x="0" y="0" width="1000000" height="600000" stroke="black" data-tactile="vibrate(); grating()"/></svg>"#;
    let out = compile(svg, "stress2");
    assert!(has(&out.diagnostics, "T0202"), "{:?}", codes(&out.diagnostics));
    if let Some(b) = &out.bundle {
        assert_sane(b);
        for c in &b.chunks {
            // Nothing beyond the 110 x 60 mm surface is stored.
            if let Chunk::Distance(d) = c {
                let span = 8.0 * d.pitch_mm;
                assert!(
                    d.tile_cols as f32 * span <= 110.0 + 2.0 * span && d.tile_rows as f32 * span <= 60.0 + 2.0 * span
                );
            }
        }
    }
}

/// A 0.5 mm grating is far below twice the 1.2 mm pitch: the aliasing rule
/// (T0405) fires; the layer is still built with its true wavelength.
#[test]
fn wavelength_below_the_actuator_pitch() {
    let out = compile(
        &page(r#"<rect id="r" x="10" y="10" width="40" height="30" data-tactile="grating(wavelength: 0.5mm)"/>"#),
        "stress2",
    );
    assert!(has(&out.diagnostics, "T0405"), "{:?}", codes(&out.diagnostics));
    let b = out.bundle.expect("a warning, not an error");
    assert_sane(&b);
    assert!(b.chunks.iter().any(|c| matches!(c, Chunk::Distance(m) if matches!(m.kind, taxel_format::MaskKind::Grating { wavelength, .. } if (wavelength.0 - 0.5).abs() < 1e-6))));
}

/// Two gratings on the same region add past full deflection: T0410 says so;
/// the runtime clamps (tested in `playback`). The upper shape is unfilled:
/// an opaque fill would hide the grating under it (no overlap).
#[test]
fn overlapping_layers() {
    let out = compile(
        &page(
            r#"<rect id="a" x="10" y="10" width="40" height="30" data-tactile="grating(wavelength: 2mm)"/>
               <rect id="b" x="20" y="15" width="40" height="30" fill="none" stroke="black" data-tactile="grating(wavelength: 6mm, angle: 0deg)"/>"#,
        ),
        "stress2",
    );
    assert!(has(&out.diagnostics, "T0410"), "{:?}", codes(&out.diagnostics));
    if let Some(b) = &out.bundle {
        assert_sane(b);
    }
}

/// Nothing at all: the error that says nothing tactile was found.
#[test]
fn empty_scene() {
    for svg in [page(""), r#"<svg xmlns="http://www.w3.org/2000/svg"/>"#.to_string()] {
        let out = compile(&svg, "stress2");
        assert!(out.bundle.is_none());
        let d = out.diagnostics.iter().find(|d| d.code == "T0300").expect("T0300");
        assert!(d.message.contains("nothing tactile"), "{}", d.message);
    }
}

/// Only things stress2 cannot render (an image, a brushed stroke): a
/// warning for each and the error that nothing can be rendered.
#[test]
fn scene_of_unsupported_elements_only() {
    let out = compile(
        &page(
            r#"<image id="i" x="0" y="0" width="10" height="10" href="data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAAAAAA6fptVAAAACklEQVR4nGNgAAAAAgABSK+kcQAAAABJRU5ErkJggg==" data-tactile="grating()"/>
               <path id="s" d="M 0 0 L 50 50" stroke="black" data-tactile="brush()"/>"#,
        ),
        "stress2",
    );
    assert!(out.bundle.is_none());
    assert!(has(&out.diagnostics, "T0305") && has(&out.diagnostics, "T0120"), "{:?}", codes(&out.diagnostics));
    assert!(out.diagnostics.iter().any(|d| d.code == "T0300" && d.message.contains("nothing in this drawing")));
}

/// NaN and infinity in geometry and in annotations: an error diagnostic or
/// the element dropped, never a panic (T0900) and never a non-finite value.
#[test]
fn nan_and_infinity_in_svg() {
    let bodies = [
        r#"<rect id="r" x="NaN" y="10" width="20" height="20" data-tactile="grating()"/>"#,
        r#"<rect id="r" x="10" y="10" width="inf" height="20" data-tactile="grating()"/>"#,
        r#"<polygon id="p" points="0,0 NaN,5 10,10" stroke="black" data-tactile="vibrate()"/>"#,
        r#"<path id="p" d="M 0 0 L 1e400 5 L 10 10 Z" data-tactile="grating()"/>"#,
        r#"<g transform="scale(NaN)"><rect id="r" x="10" y="10" width="20" height="20" data-tactile="grating()"/></g>"#,
        r#"<rect id="r" x="10" y="10" width="20" height="20" data-tactile="grating(wavelength: NaNmm)"/>"#,
        r#"<rect id="r" x="10" y="10" width="20" height="20" data-tactile="vibrate(width: infmm)"/>"#,
        r#"<rect id="r" x="10" y="10" width="20" height="20" data-tactile="vibrate(freq: 1e999Hz)"/>"#,
    ];
    for body in bodies {
        let out = compile(&page(body), "stress2");
        assert!(!has(&out.diagnostics, "T0900"), "{body}: the compiler panicked");
        match &out.bundle {
            Some(b) => assert_sane(b),
            None => assert!(!out.diagnostics.is_empty(), "{body}: refused without a word"),
        }
    }
    // An annotation with NaN names what was expected.
    let out = compile(&page(bodies[5]), "stress2");
    assert!(out.bundle.is_none() || !out.diagnostics.is_empty(), "{:?}", codes(&out.diagnostics));
}

/// A style sheet with NaN or infinity is refused with its line.
#[test]
fn nan_and_infinity_in_style_sheets() {
    for value in ["NaNmm", "infmm", "-infmm"] {
        let text = format!("[[rule]]\nid = \"r\"\ntactile = \"grating(wavelength: {value})\"\n");
        match StyleSheet::parse(&text, "s.toml") {
            Err(e) => {
                let msg = e.to_string();
                assert!(msg.contains("s.toml") && msg.contains(":3"), "{msg}");
            }
            Ok(sheet) => {
                // Accepted by the parser: the compiler must still refuse it or keep it finite.
                let mut opts = CompileOptions::new(profiles::builtin("stress2").expect("profile"));
                opts.style = Some(sheet);
                let out = compile_svg(&page(r#"<rect id="r" x="10" y="10" width="20" height="20"/>"#), &opts);
                assert!(out.bundle.as_ref().is_none_or(|b| {
                    assert_sane(b);
                    true
                }));
                assert!(!out.diagnostics.is_empty(), "{value}: accepted silently");
            }
        }
    }
}
