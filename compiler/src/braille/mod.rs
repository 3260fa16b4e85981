//! Shared service: braille for every medium.
//!
//! The braille service the back ends share (paper cells, pin arrays, the
//! automatic sheet's measures): which table writes a text, and the notes
//! that say when it is not the braille asked for.
//!
//! The cells come from [`taxel_braille`]: liblouis when the caller gave a
//! service that found it ([`CompileOptions::braille`]), taxel's built-in
//! uncontracted UEB otherwise. A text is written in its own language (the
//! nearest `xml:lang` or `lang` around it), else the reader's (`--lang`,
//! [`CompileOptions::languages`]); a style sheet's `braille-table` names a
//! liblouis table for every text; `braille(grade: 1|2)` chooses the grade,
//! contracted being the default where the language has it.

pub mod paper;

pub use taxel_braille::{Braille, Cell, Fallback, Request, Translation};

use crate::diagnostic::Diagnostic;
use crate::drawing::TextShape;
use crate::options::CompileOptions;

/// Dot `k` (0-based bit of a Unicode braille mask) at `(column, row)` within its cell.
pub const DOT_POSITIONS: [(u32, u32); 8] = [(0, 0), (0, 1), (0, 2), (1, 0), (1, 1), (1, 2), (0, 3), (1, 3)];

/// The language `text` is written in: its own, else the reader's first, else English.
pub(crate) fn lang_of<'a>(text: Option<&'a TextShape>, opts: &'a CompileOptions) -> &'a str {
    text.and_then(|t| t.lang.as_deref()).or(opts.languages.first().map(String::as_str)).unwrap_or("en")
}

/// The request for a text of `shape` (its language) at `grade`, in eight-dot computer braille when `computer`.
pub(crate) fn request<'a>(
    shape: Option<&'a TextShape>,
    opts: &'a CompileOptions,
    grade: Option<u8>,
    computer: bool,
) -> Request<'a> {
    Request {
        lang: lang_of(shape, opts),
        grade,
        table: opts.style.as_ref().and_then(|s| s.braille_table.as_deref()),
        computer,
    }
}

/// Makes liblouis ready for the drawing's labels: the table of the
/// reader's first language at the default grade chosen (liblouis reads
/// every table's metadata the first time) and compiled, as the first
/// translation would. Nothing is kept but liblouis's and [`Braille`]'s
/// caches, so a build that calls it gives the same bundle as one that
/// does not.
///
/// [`Braille`]: taxel_braille::Braille
pub(crate) fn warm(opts: &CompileOptions) {
    translate("a", None, opts, None, false);
}

/// `text` of `shape` in braille as the options and its style ask.
pub(crate) fn translate(
    text: &str,
    shape: Option<&TextShape>,
    opts: &CompileOptions,
    grade: Option<u8>,
    computer: bool,
) -> Translation {
    opts.braille.translate(text, &request(shape, opts, grade, computer))
}

/// The cells of translation `t` of `text` (drawn by element `e`), after a
/// warning (T0304) naming the characters its table has no braille for:
/// none at all when what is left says nothing (its punctuation alone).
/// Shared by every medium that writes braille cells (pins, paper).
pub(crate) fn cells_warning_missing(
    text: &str,
    t: Translation,
    e: Option<&crate::drawing::Element>,
    diags: &mut Vec<Diagnostic>,
) -> Vec<u8> {
    let table = table_name(&t);
    let (mut cells, missing) = (t.cells, t.missing);
    if !missing.is_empty() {
        let list = taxel_braille::left_out(&missing);
        // Punctuation alone says nothing: then the text is left out whole.
        if taxel_braille::says_nothing(text, &missing) {
            cells.clear();
        }
        let left = if cells.iter().all(|&c| c == 0) { "the text is left out" } else { "these characters are left out" };
        let mut d = Diagnostic::warning("T0304", format!("no braille in {table} for {list}; {left}"))
            .with_help(missing_help(&table));
        if let Some(e) = e {
            d = d.with_element(e.name.clone()).on_line(e.line);
        }
        diags.push(d);
    }
    cells
}

/// What T0304 says helps, for the table that left characters out.
pub(crate) fn missing_help(table: &str) -> String {
    if table == "uncontracted UEB" {
        format!(
            "{}; with liblouis installed, a text's `xml:lang` chooses its language's table",
            taxel_braille::TABLE_HELP
        )
    } else {
        "mark the text's language with `xml:lang` (its table is chosen from it), or name a table with a style sheet's `braille-table`".into()
    }
}

/// The table a translation used, for messages: its file name, or the built-in one.
pub(crate) fn table_name(t: &Translation) -> String {
    match &t.table {
        Some(name) => format!("the liblouis table {}", name.rsplit(['/', '\\']).next().unwrap_or(name)),
        None => "uncontracted UEB".to_string(),
    }
}

/// The notes of a compilation's translations, each said once (T0307).
#[derive(Debug, Default)]
pub(crate) struct Notes(Vec<Fallback>);

impl Notes {
    /// Keeps `t`'s note, if it has one not kept yet.
    pub(crate) fn add(&mut self, t: &Translation) {
        if let Some(f) = &t.fallback
            && !self.0.contains(f)
        {
            self.0.push(f.clone());
        }
    }

    /// One diagnostic per note: a note when liblouis is absent or a
    /// language has no table of the grade asked for, a warning when a
    /// language has no table at all or the table named cannot be used.
    pub(crate) fn emit(self, diags: &mut Vec<Diagnostic>) {
        for f in self.0 {
            let d = match &f {
                Fallback::NoLibrary(_) | Fallback::OtherGrade { .. } => Diagnostic::note("T0307", f.message()),
                Fallback::NoTable(_) | Fallback::BadTable(_) => Diagnostic::warning("T0307", f.message())
                    .with_help("liblouis's tables are listed by `lou_translate --help` and in /usr/share/liblouis/tables; a style sheet's `braille-table` names one"),
            };
            diags.push(d);
        }
    }
}
