//! Which liblouis table writes a language: asked of liblouis's own table
//! metadata (`lou_findTable`), so every language liblouis has a table for
//! is covered, and the tables a system adds are found too.
//!
//! A language tag is tried whole (`pt-BR`), then as its primary language
//! (`pt`): liblouis's metadata names regions apart. Literary braille is
//! asked for contracted first (`contraction:full`, then `partial`) unless
//! grade 1 is asked, then the language's grade 1 (`grade:1`: German
//! Basisschrift), then uncontracted (`contraction:no`), then
//! any literary table, then any table. Eight-dot computer braille asks for
//! `type:computer dots:8` first.

use crate::Fallback;

/// The queries for a tag, in order of preference.
fn queries(tag: &str, grade: Option<u8>, computer: bool) -> Vec<String> {
    let mut features: Vec<&str> = Vec::new();
    if computer {
        features.push("type:computer dots:8");
    }
    let contracted = ["type:literary contraction:full", "type:literary grade:2", "type:literary contraction:partial"];
    // A language's own grade 1 first (German Basisschrift, `de-g1.ctb`), else its uncontracted table.
    let uncontracted = ["type:literary grade:1", "type:literary contraction:no"];
    if grade == Some(1) {
        features.extend(uncontracted);
        features.extend(contracted);
    } else {
        features.extend(contracted);
        features.extend(uncontracted);
    }
    features.extend(["type:literary", ""]);
    features.iter().map(|f| format!("language:{tag} {f}").trim_end().to_string()).collect()
}

/// Whether a query asks for the grade wanted (for the note when it does not).
fn gives_grade(query: &str, grade: u8) -> bool {
    match grade {
        1 => query.contains("contraction:no") || query.contains("grade:1"),
        _ => query.contains("contraction:full") || query.contains("grade:2") || query.contains("contraction:partial"),
    }
}

/// The tags to try for a language: whole, then its primary language.
fn tags(lang: &str) -> Vec<String> {
    let tag = lang.trim().replace('_', "-").to_ascii_lowercase();
    let primary = tag.split('-').next().unwrap_or("").to_string();
    let mut out = vec![tag.clone()];
    if primary != tag && !primary.is_empty() {
        out.push(primary);
    }
    out.retain(|t| !t.is_empty() && t.chars().all(|c| c.is_ascii_alphanumeric() || c == '-'));
    out
}

/// Whether `lang` is English (so the built-in UEB is its braille).
pub(crate) fn is_english(lang: &str) -> bool {
    tags(lang).last().is_some_and(|t| t == "en")
}

/// The table for a language and grade, found with `find` (a metadata
/// query to a table name), and a note when it is not the grade asked for
/// or when no table writes the language.
pub(crate) fn choose(
    lang: &str,
    grade: Option<u8>,
    computer: bool,
    mut find: impl FnMut(&str) -> Option<String>,
) -> (Option<String>, Option<Fallback>) {
    for tag in tags(lang) {
        for q in queries(&tag, grade, computer) {
            if let Some(t) = find(&q) {
                let note = grade.filter(|&g| !(gives_grade(&q, g) || computer && q.contains("type:computer")));
                let note = note.map(|g| Fallback::OtherGrade { lang: lang.to_string(), grade: g, table: short(&t) });
                return (Some(t), note);
            }
        }
    }
    let note = (!is_english(lang)).then(|| Fallback::NoTable(lang.to_string()));
    (None, note)
}

/// A table's file name, without the folder liblouis found it in.
pub(crate) fn short(table: &str) -> String {
    table.rsplit(['/', '\\']).next().unwrap_or(table).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pretend liblouis that knows a few tables by their metadata.
    fn find(q: &str) -> Option<String> {
        let known = [
            ("language:fr type:literary contraction:full", "fr-bfu-g2.ctb"),
            ("language:fr type:literary contraction:no", "fr-bfu-comp6.utb"),
            ("language:en type:literary contraction:full", "en-ueb-g2.ctb"),
            ("language:en type:literary contraction:no", "en-ueb-g1.ctb"),
            ("language:en type:computer dots:8", "en-nabcc.utb"),
            ("language:el type:literary contraction:full", "el.ctb"),
            ("language:ja type:literary contraction:no", "ja-kantenji.utb"),
        ];
        known.iter().find(|(k, _)| *k == q).map(|(_, t)| format!("/usr/share/liblouis/tables/{t}"))
    }

    #[test]
    fn a_language_gets_its_contracted_table_by_default_and_its_uncontracted_for_grade_1() {
        assert_eq!(short(&choose("fr", None, false, find).0.unwrap()), "fr-bfu-g2.ctb");
        assert_eq!(short(&choose("fr-CA", Some(1), false, find).0.unwrap()), "fr-bfu-comp6.utb");
        assert_eq!(short(&choose("EN_us", Some(2), false, find).0.unwrap()), "en-ueb-g2.ctb");
        assert_eq!(short(&choose("en", None, true, find).0.unwrap()), "en-nabcc.utb");
        // A language without a contracted table is uncontracted, silently by default.
        assert_eq!(choose("ja", None, false, find).1, None);
        // With a note when grade 2 was asked for, and when grade 1 was and only contracted exists.
        let (t, note) = choose("ja", Some(2), false, find);
        assert_eq!(short(&t.unwrap()), "ja-kantenji.utb");
        assert!(matches!(note, Some(Fallback::OtherGrade { grade: 2, .. })));
        assert!(matches!(choose("el", Some(1), false, find).1, Some(Fallback::OtherGrade { grade: 1, .. })));
        // No table: the built-in UEB, noted unless the language is English.
        assert_eq!(choose("xx", None, false, find), (None, Some(Fallback::NoTable("xx".into()))));
        assert_eq!(choose("en-AU", None, false, |_| None), (None, None));
        // A tag is not a query: nothing but letters, digits and hyphens reaches liblouis.
        assert_eq!(choose("fr contraction:no", None, false, find).0, None);
    }
}
