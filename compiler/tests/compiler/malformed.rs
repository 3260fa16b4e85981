//! Hostile and malformed input: errors, never panics.

use proptest::prelude::*;
use taxel_compiler::{StyleSheet, annotation};

use crate::common::*;

/// A panic inside the compiler is caught and reported as T0900; none may happen.
fn no_internal_error(svg: &str) {
    let c = compile(svg);
    assert!(!c.diagnostics.iter().any(|d| d.code == "T0900"), "internal error on {svg:?}");
}

#[test]
fn malformed_svgs_give_errors() {
    for svg in [
        "",
        "not xml",
        "<svg",
        "<svg xmlns=\"http://www.w3.org/2000/svg\"><g></svg>",
        "<?xml version=\"1.0\"?><!DOCTYPE svg [<!ENTITY a \"&b;\"><!ENTITY b \"&a;\">]><svg>&a;</svg>",
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"0\" height=\"0\"/>",
    ] {
        let c = compile(svg);
        assert!(has_error(&c), "{svg:?}: {:#?}", c.diagnostics);
        assert!(c.bundle.is_none());
        no_internal_error(svg);
    }
}

/// usvg's limits (elements nested more than 1,024 deep) and its size check
/// each get their own hint, not one generic line.
#[test]
fn unreadable_svgs_say_what_to_change() {
    let deep = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"50mm\" height=\"50mm\" viewBox=\"0 0 50 50\">{}<rect width=\"9\" height=\"9\" data-tactile=\"vibrate()\"/>{}</svg>",
        "<g>".repeat(1500),
        "</g>".repeat(1500)
    );
    let sizeless = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"0\" height=\"0\"/>";
    for (svg, hint) in [(deep.as_str(), "nests groups"), (sizeless, "width, height or viewBox")] {
        let c = compile(svg);
        let e = c.diagnostics.iter().find(|d| d.code == "T0200").unwrap_or_else(|| panic!("{:#?}", c.diagnostics));
        assert!(e.help.as_deref().is_some_and(|h| h.contains(hint)), "{e:?}");
    }
}

#[test]
fn extreme_geometry_does_not_panic() {
    for body in [
        r#"<rect x="1e30" y="-1e30" width="1e30" height="1e30" data-tactile="vibrate(); grating(); dots()"/>"#,
        r#"<path d="M 0 0 L NaN 5 L 3 3" data-tactile="dots()"/>"#,
        r#"<path d="M 10 10 L 10 10 Z" data-tactile="vibrate(); dots(); dot()"/>"#,
        r##"<use id="u" href="#u" data-tactile="vibrate()"/>"##,
        r##"<g id="a"><use href="#a" data-tactile="vibrate()"/></g>"##,
        r#"<rect width="30" height="30" transform="scale(0)" data-tactile="grating()"/>"#,
        r#"<text x="5" y="20" data-tactile="braille()"></text>"#,
        r#"<text x="1e38" y="20" data-tactile="braille()">far</text>"#,
        r#"<path d="M 0 0 C 1e20 1e20 -1e20 -1e20 5 5" data-tactile="dots(radius: 0.001mm)"/>"#,
    ] {
        no_internal_error(&page(body));
    }
    no_internal_error(
        r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 0 0"><rect width="1" height="1" data-tactile="vibrate()"/></svg>"#,
    );
    let deep = format!(
        "{}<rect width=\"30\" height=\"30\" data-tactile=\"vibrate()\"/>{}",
        "<g>".repeat(300),
        "</g>".repeat(300)
    );
    no_internal_error(&page(&deep));
}

#[test]
fn malformed_style_sheets_name_file_and_line() {
    for (text, line) in [
        ("[[rule]]\nid = 3\ntactile = \"none\"\n", 2),
        ("[[rule]]\nid = \"x\"\ntactile = \"grating(wavelength: -1mm)\"\n", 3),
        ("version = 2\n", 1),
        ("[[rule]]\nid = \"x\"\n", 1),
    ] {
        let e = StyleSheet::parse(text, "sheet.toml").unwrap_err();
        assert!(e.to_string().starts_with("sheet.toml"), "{e}");
        assert_eq!(e.line, line, "{text:?}: {e}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn annotation_parser_never_panics(s in "\\PC{0,40}") {
        if let Err(e) = annotation::parse(&s) {
            prop_assert!(e.offset <= s.len());
            prop_assert!(!e.message.is_empty());
        }
    }

    #[test]
    fn annotation_like_strings_never_panic(s in "(vibrate|grating|dots|dot|braille|brush|none|x)[(]?([a-z]{0,9}[:]? ?-?[0-9.e]{0,6}(mm|deg|Hz|%|s|)[,;]? ?){0,4}[)]?;?") {
        let _ = annotation::parse(&s);
        let escaped = s.replace('&', "&amp;").replace('"', "&quot;").replace('<', "&lt;");
        no_internal_error(&page(&format!(r#"<rect x="5" y="5" width="30" height="30" data-tactile="{escaped}"/>"#)));
    }

    #[test]
    fn random_bytes_as_svg_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        no_internal_error(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn mangled_svg_never_panics(cut in 0usize..400, junk in "[<>\"/=a-z ]{0,8}") {
        let svg = page(r#"<g data-tactile="vibrate()"><rect x="5" y="5" width="30" height="30"/><circle cx="60" cy="30" r="10" data-tactile="grating(wavelength: 6mm)"/></g><text x="5" y="50" data-tactile="braille()">Hi 5</text>"#);
        let cut = cut.min(svg.len());
        let cut = (0..=cut).rev().find(|&i| svg.is_char_boundary(i)).unwrap_or(0);
        no_internal_error(&format!("{}{}{}", &svg[..cut], junk, &svg[cut..]));
    }
}
