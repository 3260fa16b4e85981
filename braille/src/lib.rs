//! Braille for taxel: text to braille cells in the reader's language.
//!
//! [`Braille`] is the service every back end shares. It uses liblouis, the
//! library every braille tool uses, when the system has it: opened at run
//! time as a system library (LGPL-2.1+; never linked, never through a GPL
//! binding crate), its table chosen from the text's language and the grade
//! asked for, contracted where the language has it. Without liblouis it is
//! taxel's built-in uncontracted Unified English Braille ([`ueb`]), and a
//! [`Fallback`] says so and how to install liblouis.
//!
//! ```
//! use taxel_braille::{Braille, Request};
//!
//! let braille = Braille::builtin();
//! let t = braille.translate("Hi 42", &Request::new("en"));
//! assert_eq!(t.cells.len(), 7);
//! assert!(t.missing.is_empty());
//! ```
//!
//! The crate does no file IO of its own; liblouis reads its tables.

#![deny(unsafe_code)]

mod louis;
mod tables;
pub mod ueb;

use std::collections::HashMap;
use std::sync::Mutex;

pub use louis::LIBRARY_NAMES;
pub use ueb::{TABLE_HELP, left_out, says_nothing};

/// A braille cell: bit `k` is dot `k + 1` (dots 1-3 down the left column,
/// 4-6 down the right, 7 and 8 below them), as in Unicode's braille block.
pub type Cell = u8;

/// What a text is to be written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Request<'a> {
    /// The text's language, a BCP 47 tag (`fr`, `en-GB`, `de-CH`).
    pub lang: &'a str,
    /// `Some(1)` uncontracted, `Some(2)` contracted; `None`: contracted
    /// where the language has a contracted table, else uncontracted.
    pub grade: Option<u8>,
    /// A liblouis table list to use whatever the language (a style sheet's
    /// `braille-table`, such as `fr-bfu-g2.ctb`).
    pub table: Option<&'a str>,
    /// Eight-dot computer braille, for displays whose cells have eight dots.
    pub computer: bool,
}

impl<'a> Request<'a> {
    /// Literary braille in `lang` at the language's default grade.
    pub fn new(lang: &'a str) -> Self {
        Request { lang, grade: None, table: None, computer: false }
    }
}

/// Why the braille is not what was asked for.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Fallback {
    /// liblouis was sought and is not installed: the built-in UEB grade 1 was used.
    NoLibrary(String),
    /// liblouis has no table for the language: the built-in UEB grade 1 was used.
    NoTable(String),
    /// The table named could not be compiled by liblouis: the language's table, or the built-in one, was used.
    BadTable(String),
    /// The grade asked for does not exist for the language: the other one was used (the table named).
    OtherGrade {
        /// The language.
        lang: String,
        /// The grade asked for.
        grade: u8,
        /// The table used instead.
        table: String,
    },
}

impl Fallback {
    /// A sentence for the reader's report.
    pub fn message(&self) -> String {
        match self {
            Fallback::NoLibrary(why) => format!(
                "braille is taxel's built-in uncontracted UEB (grade 1): {why}; install liblouis for contracted braille and other languages (Debian/Ubuntu: `apt install liblouis20 liblouis-data`; Fedora: `dnf install liblouis`; macOS: `brew install liblouis`)"
            ),
            Fallback::NoTable(lang) => format!(
                "liblouis has no braille table for the language `{lang}`: this text is taxel's built-in uncontracted UEB (grade 1)"
            ),
            Fallback::BadTable(table) => format!("liblouis cannot use the braille table `{table}`"),
            Fallback::OtherGrade { lang, grade, table } => {
                format!("liblouis has no grade {grade} braille for `{lang}`: this text is in `{table}`")
            }
        }
    }
}

/// A text in braille.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Translation {
    /// The cells; a space is an empty cell.
    pub cells: Vec<Cell>,
    /// The characters the table has no braille for (left out), in text order.
    pub missing: Vec<char>,
    /// The liblouis table used; `None` for the built-in UEB grade 1.
    pub table: Option<String>,
    /// Why this is not the braille asked for, if it is not.
    pub fallback: Option<Fallback>,
}

/// A table chosen (`None`: the built-in one) and the note that goes with it.
type Choice = (Option<String>, Option<Fallback>);
/// What a choice is cached by: language (lowercase), grade, computer braille.
type ChoiceKey = (String, Option<u8>, bool);

/// The braille service: liblouis when it was found, the built-in UEB grade 1 otherwise.
#[derive(Debug)]
pub struct Braille {
    louis: Result<louis::Louis, Option<String>>,
    /// Tables chosen per request (language, grade, computer), and the fallback note.
    chosen: Mutex<HashMap<ChoiceKey, Choice>>,
    /// Per table, the characters it has no braille for, once looked up.
    undefined: Mutex<HashMap<(String, char), bool>>,
}

impl Braille {
    /// Only the built-in UEB grade 1 (deterministic, needs nothing
    /// installed): no note says that liblouis is absent.
    pub fn builtin() -> Braille {
        Braille { louis: Err(None), chosen: Mutex::default(), undefined: Mutex::default() }
    }

    /// liblouis opened under `library` (a name or path), or under the usual
    /// names ([`LIBRARY_NAMES`]) when `None`; the built-in table, with a
    /// [`Fallback::NoLibrary`] on every translation, when it cannot be opened.
    pub fn load(library: Option<&str>) -> Braille {
        Braille {
            louis: louis::Louis::open(library).map_err(Some),
            chosen: Mutex::default(),
            undefined: Mutex::default(),
        }
    }

    /// liblouis's version when it is in use.
    pub fn liblouis_version(&self) -> Option<&str> {
        self.louis.as_ref().ok().map(louis::Louis::version)
    }

    /// Why liblouis is not in use, when it was sought and not found.
    pub fn unavailable(&self) -> Option<&str> {
        self.louis.as_ref().err().and_then(|e| e.as_deref())
    }

    /// The liblouis table for `req` and a note when it is not what was
    /// asked; `None` for the built-in table.
    pub fn table_for(&self, req: &Request<'_>) -> Choice {
        let louis = match &self.louis {
            Ok(l) => l,
            Err(None) => return (None, None),
            Err(Some(why)) => {
                // Only a note when the built-in table is not what a reader of UEB grade 1 would get anyway.
                let asked_for_ueb1 = tables::is_english(req.lang) && req.grade == Some(1) && req.table.is_none();
                return (None, (!asked_for_ueb1).then(|| Fallback::NoLibrary(why.clone())));
            }
        };
        let key = (req.lang.to_ascii_lowercase(), req.grade, req.computer);
        let mut chosen = self.chosen.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(c) = chosen.get(&key) {
            return c.clone();
        }
        let c = tables::choose(req.lang, req.grade, req.computer, |q| louis.find_table(q));
        chosen.insert(key, c.clone());
        c
    }

    /// `text` in braille as `req` asks, or as near as the system allows
    /// (the [`Translation::fallback`] says how near).
    pub fn translate(&self, text: &str, req: &Request<'_>) -> Translation {
        let (table, mut fallback) = match (req.table, &self.louis) {
            (Some(t), Ok(_)) => (Some(t.to_string()), None),
            _ => self.table_for(req),
        };
        if let (Some(t), Ok(louis)) = (&table, &self.louis) {
            match self.with_louis(louis, t, text) {
                Some((cells, missing)) => return Translation { cells, missing, table, fallback },
                None if req.table.is_some() => {
                    // The named table failed: the language's own, with a note naming the bad one.
                    let (t2, _) = self.table_for(&Request { table: None, ..*req });
                    let bad = Some(Fallback::BadTable(t.clone()));
                    if let Some((cells, missing)) = t2.as_deref().and_then(|t2| self.with_louis(louis, t2, text)) {
                        return Translation { cells, missing, table: t2, fallback: bad };
                    }
                    fallback = bad;
                }
                None => fallback = Some(Fallback::BadTable(t.clone())),
            }
        }
        let (cells, missing) = ueb::translate(text);
        Translation { cells, missing, table: None, fallback }
    }

    /// liblouis's cells for `text` through `table`, with the characters
    /// the table does not define left out and named; `None` when the table
    /// cannot be used.
    fn with_louis(&self, louis: &louis::Louis, table: &str, text: &str) -> Option<(Vec<Cell>, Vec<char>)> {
        // Each distinct character is looked up alone once per table: one
        // that gives no dots (nothing, or only blank cells) is not in the
        // table. It is taken out of the text before the text is translated,
        // so that it leaves no stray cells.
        let mut missing = Vec::new();
        {
            let mut undefined = self.undefined.lock().unwrap_or_else(|p| p.into_inner());
            for c in text.chars().filter(|c| !c.is_whitespace()) {
                let key = (table.to_string(), c);
                let is_missing = match undefined.get(&key) {
                    Some(&m) => m,
                    None => {
                        let cells = louis.translate(table, c.encode_utf8(&mut [0; 4]))?;
                        let m = cells.iter().all(|&d| d == 0);
                        undefined.insert(key, m);
                        m
                    }
                };
                if is_missing {
                    missing.push(c);
                }
            }
        }
        let kept: String = if missing.is_empty() {
            text.to_string()
        } else {
            text.chars().map(|c| if missing.contains(&c) { ' ' } else { c }).collect()
        };
        // Whitespace of any kind is a space between words.
        let kept: String = kept.split_whitespace().collect::<Vec<_>>().join(" ");
        let cells = louis.translate(table, &kept)?;
        Some((cells, missing))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_built_in_service_writes_ueb_grade_1_without_a_note() {
        let b = Braille::builtin();
        let t = b.translate("Café", &Request { grade: Some(2), ..Request::new("fr") });
        assert_eq!((t.cells, t.missing), ueb::translate("Café"));
        assert_eq!((t.table, t.fallback), (None, None));
        assert_eq!(b.liblouis_version(), None);
    }

    #[test]
    fn a_missing_liblouis_falls_back_to_ueb_grade_1_with_a_note() {
        let b = Braille::load(Some("liblouis-taxel-test-missing.so.99"));
        assert!(b.unavailable().is_some_and(|w| w.contains("liblouis-taxel-test-missing")));
        let t = b.translate("Marseille", &Request::new("fr"));
        assert_eq!(t.cells, ueb::translate("Marseille").0);
        let Some(Fallback::NoLibrary(why)) = &t.fallback else { panic!("{:?}", t.fallback) };
        assert!(why.contains("not found"));
        assert!(t.fallback.as_ref().is_some_and(|f| f.message().contains("install liblouis")));
        // English grade 1 asked for is what the built-in table writes: no note.
        let t = b.translate("Hi", &Request { grade: Some(1), ..Request::new("en-GB") });
        assert_eq!(t.fallback, None);
    }
}
