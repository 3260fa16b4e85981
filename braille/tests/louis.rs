//! taxel's braille against liblouis's own: the same table and string
//! through `lou_translate` (liblouis-bin), computed here, never pasted in.
//!
//! These tests need liblouis and its tools. Without them they say so and
//! pass, unless `TAXEL_REQUIRE_LIBLOUIS` is set (as `.ci/run` sets it), when
//! their absence fails.

use std::io::Write;
use std::process::{Command, Stdio};

use taxel_braille::{Braille, Fallback, Request};

/// liblouis opened, or `None` (after saying why) when it may be absent.
fn louis() -> Option<Braille> {
    let b = Braille::load(None);
    let tool = Command::new("lou_translate").arg("--version").output().is_ok_and(|o| o.status.success());
    if b.liblouis_version().is_some() && tool {
        return Some(b);
    }
    let why = format!("liblouis or lou_translate is not installed ({:?})", b.unavailable());
    assert!(std::env::var_os("TAXEL_REQUIRE_LIBLOUIS").is_none(), "{why}");
    eprintln!("skipped: {why}");
    None
}

/// `lou_translate --forward unicode.dis,TABLE` of `text`, as 8-dot masks.
fn lou_translate(table: &str, text: &str) -> Vec<u8> {
    let mut child = Command::new("lou_translate")
        .args(["--forward", &format!("unicode.dis,{table}")])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(format!("{text}\n").as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "lou_translate {table}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout)
        .unwrap()
        .trim_end_matches('\n')
        .chars()
        .map(|c| match c as u32 {
            0x2800..=0x28ff => (c as u32 - 0x2800) as u8,
            _ => {
                assert_eq!(c, ' ', "lou_translate wrote {c:?}");
                0
            }
        })
        .collect()
}

/// The table file `lang` at `grade` is written in, and the cells checked against `lou_translate`.
fn check(b: &Braille, lang: &str, grade: Option<u8>, text: &str) -> String {
    let t = b.translate(text, &Request { grade, ..Request::new(lang) });
    let table = t.table.clone().unwrap_or_else(|| panic!("{lang}: no liblouis table ({:?})", t.fallback));
    assert!(t.missing.is_empty(), "{lang} {text}: {:?}", t.missing);
    assert_eq!(t.cells, lou_translate(&table, text), "{lang} {text} through {table}");
    assert!(t.cells.iter().any(|&c| c != 0), "{lang} {text}");
    table.rsplit('/').next().unwrap().to_string()
}

#[test]
fn english_ueb_grade_2_and_grade_1_are_liblouis_s() {
    let Some(b) = louis() else { return };
    for text in ["The Knowledge of 42 Capitals, and punctuation!", "GREAT Britain: 3.5 km (about 2 miles)"] {
        assert_eq!(check(&b, "en", None, text), "en-ueb-g2.ctb");
        assert_eq!(check(&b, "en-GB", Some(2), text), "en-ueb-g2.ctb");
        assert_eq!(check(&b, "en-US", Some(1), text), "en-ueb-g1.ctb");
    }
    // Contracted braille is shorter than uncontracted.
    let text = "The Knowledge of the World";
    let g2 = b.translate(text, &Request::new("en")).cells.len();
    let g1 = b.translate(text, &Request { grade: Some(1), ..Request::new("en") }).cells.len();
    assert!(g2 < g1, "{g2} {g1}");
}

#[test]
fn french_german_and_spanish_labels_are_liblouis_s() {
    let Some(b) = louis() else { return };
    assert_eq!(check(&b, "fr", None, "Marseille et la Méditerranée, 12 °C !"), "fr-bfu-g2.ctb");
    assert_eq!(check(&b, "fr-FR", Some(1), "Marseille et la Méditerranée, 12 °C !"), "fr-bfu-comp6.utb");
    assert_eq!(check(&b, "de", None, "Köln und München: 1.086 Einwohner"), "de-g2.ctb");
    assert_eq!(check(&b, "de-DE", Some(1), "Köln und München: 1.086 Einwohner"), "de-g1.ctb");
    assert_eq!(check(&b, "es", None, "Año Nuevo en España, ¿QUÉ? 25"), "es-g2.ctb");
    check(&b, "es", Some(1), "Año Nuevo en España, ¿QUÉ? 25");
}

#[test]
fn arabic_japanese_and_greek_labels_are_liblouis_s() {
    let Some(b) = louis() else { return };
    assert_eq!(check(&b, "ar", None, "القاهرة 2024"), "ar-ar-g2.ctb");
    check(&b, "ar", Some(1), "القاهرة 2024");
    // Japanese has no contracted table: uncontracted, with no note by default.
    let t = b.translate("東京 とうきょう 12", &Request::new("ja"));
    assert_eq!(t.fallback, None);
    assert!(check(&b, "ja", None, "東京 とうきょう 12").starts_with("ja-"));
    // Greek with and without the tonos: both are written (the tonos is a cell of its own).
    let accented = check(&b, "el", None, "Θεσσαλονίκη");
    assert_eq!(accented, check(&b, "el", None, "Θεσσαλονικη"));
    let (a, plain) = (b.translate("Θεσσαλονίκη", &Request::new("el")), b.translate("Θεσσαλονικη", &Request::new("el")));
    assert_eq!(a.cells.len(), plain.cells.len() + 1);
}

#[test]
fn eight_dot_computer_braille_is_the_language_s_where_liblouis_has_it() {
    let Some(b) = louis() else { return };
    let t = b.translate("Hi 42", &Request { computer: true, ..Request::new("en") });
    let table = t.table.unwrap();
    assert!(table.contains("nabcc") || table.contains("comp8"), "{table}");
    assert_eq!(t.cells, lou_translate(&table, "Hi 42"));
    // A capital is one eight-dot cell (dot 7), not an indicator and a letter.
    assert_eq!(t.cells.len(), 5);
    assert_ne!(t.cells[0] & 0x40, 0);
}

#[test]
fn characters_a_table_lacks_are_named_and_leave_no_cells() {
    let Some(b) = louis() else { return };
    let t = b.translate("Осадки x", &Request::new("fr"));
    assert!(t.missing.contains(&'О') && !t.missing.contains(&'x'), "{:?}", t.missing);
    assert_eq!(t.cells, lou_translate(t.table.as_deref().unwrap(), "x"));
    // A language liblouis has no table for is the built-in UEB, with a warning's note.
    let t = b.translate("Hello", &Request::new("x-klingon"));
    assert_eq!((t.table, t.fallback), (None, Some(Fallback::NoTable("x-klingon".into()))));
    // A table named that liblouis cannot use: the language's own, with a note naming the bad one.
    let t = b.translate("Bonjour", &Request { table: Some("no-such-table.ctb"), ..Request::new("fr") });
    assert_eq!(t.fallback, Some(Fallback::BadTable("no-such-table.ctb".into())));
    assert!(t.table.is_some_and(|t| t.ends_with("fr-bfu-g2.ctb")));
    // A table named is used whatever the language.
    let t = b.translate("Bonjour", &Request { table: Some("fr-bfu-comp6.utb"), ..Request::new("en") });
    assert_eq!(t.cells, lou_translate("fr-bfu-comp6.utb", "Bonjour"));
}
