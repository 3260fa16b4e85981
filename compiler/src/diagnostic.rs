//! Diagnostics: what the compiler says about a drawing. The compiler collects
//! them and goes on; `Result` is only for "cannot go on".

use serde::Serialize;

/// How bad a diagnostic is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// Something worth knowing; the output is as intended.
    Note,
    /// The output is made but will not read well by touch, or something was changed to make it.
    Warning,
    /// The input is wrong; the bundle is not written.
    Error,
}

impl core::fmt::Display for Severity {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Severity::Note => "note",
            Severity::Warning => "warning",
            Severity::Error => "error",
        })
    }
}

/// One diagnostic, printed like a compiler's and serialisable as JSON.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Diagnostic {
    /// Stable code, such as `T0101`; documented in `docs/diagnostics.md`.
    pub code: &'static str,
    /// How bad it is.
    pub severity: Severity,
    /// What is wrong, lower-case, no trailing period.
    pub message: String,
    /// How to fix it, when there is something to say.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub help: Option<String>,
    /// The element's id (or a path to it when it has none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub element: Option<String>,
    /// 1-based line in the source.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub line: Option<u32>,
    /// 1-based column in the source.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub column: Option<u32>,
}

impl Diagnostic {
    /// A diagnostic with only a code, a severity and a message.
    pub fn new(code: &'static str, severity: Severity, message: impl Into<String>) -> Self {
        Diagnostic { code, severity, message: message.into(), help: None, element: None, line: None, column: None }
    }

    /// An error.
    pub fn error(code: &'static str, message: impl Into<String>) -> Self {
        Self::new(code, Severity::Error, message)
    }

    /// A warning.
    pub fn warning(code: &'static str, message: impl Into<String>) -> Self {
        Self::new(code, Severity::Warning, message)
    }

    /// A note.
    pub fn note(code: &'static str, message: impl Into<String>) -> Self {
        Self::new(code, Severity::Note, message)
    }

    /// Adds advice on how to fix it.
    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    /// Names the element.
    pub fn with_element(mut self, element: impl Into<String>) -> Self {
        self.element = Some(element.into());
        self
    }

    /// Places it at a 1-based line and column.
    pub fn at(mut self, line: u32, column: u32) -> Self {
        self.line = Some(line);
        self.column = Some(column);
        self
    }

    /// Places it at a 1-based source line, without a column (it is about a whole element).
    pub fn at_line(mut self, line: u32) -> Self {
        self.line = Some(line);
        self.column = None;
        self
    }

    /// Sets the source line when it is known (1-based; 0 means unknown and leaves it unset).
    pub fn on_line(mut self, line: u32) -> Self {
        if line > 0 {
            self.line = Some(line);
        }
        self
    }

    /// Formats it like a compiler: `file:line:col: warning[T0101]: message (element #id)`
    /// followed by `  help: ...` when there is help.
    pub fn render(&self, file: &str) -> String {
        let mut s = String::from(file);
        if let Some(l) = self.line {
            s += &format!(":{l}");
            if let Some(c) = self.column {
                s += &format!(":{c}");
            }
        }
        s += &format!(": {}[{}]: {}", self.severity, self.code, self.message);
        if let Some(e) = &self.element {
            s += &format!(" (element #{e})");
        }
        if let Some(h) = &self.help {
            s += &format!("\n  help: {h}");
        }
        s
    }
}

/// Whether any diagnostic is an error.
pub fn has_errors(diags: &[Diagnostic]) -> bool {
    diags.iter().any(|d| d.severity == Severity::Error)
}

/// A length or factor for a message: `decimals` places in the usual range,
/// scientific notation far outside it, where fixed notation would print
/// dozens of digits (a drawing 10³⁰ mm wide) or only zeros (a scale of
/// 10⁻²⁷).
pub(crate) fn number(v: f64, decimals: usize) -> String {
    let a = v.abs();
    if a != 0.0 && a.is_finite() && !(10f64.powi(-(decimals as i32))..1e7).contains(&a) {
        format!("{v:.2e}")
    } else {
        format!("{v:.decimals$}")
    }
}

/// Characters of a drawing's text that a message quotes: a label or a
/// legend text, which may be a paragraph (or a scanned page's text layer).
const QUOTED_CHARS: usize = 60;

/// `text` for a message: as it is up to [`QUOTED_CHARS`] characters, else
/// its start and an ellipsis, so that a message fits on a screen.
pub(crate) fn quoted(text: &str) -> String {
    match text.char_indices().nth(QUOTED_CHARS) {
        Some((at, _)) => format!("{}…", text[..at].trim_end()),
        None => text.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::{number, quoted};

    #[test]
    fn a_long_text_is_quoted_by_its_start() {
        assert_eq!(quoted("Zürich"), "Zürich");
        let long = "é".repeat(200);
        assert_eq!(quoted(&long), format!("{}…", "é".repeat(60)));
        assert_eq!(quoted(&"ab ".repeat(40)).chars().count(), 60);
    }

    #[test]
    fn numbers_stay_short_at_every_magnitude() {
        assert_eq!(number(100.0, 1), "100.0");
        assert_eq!(number(0.25, 3), "0.250");
        assert_eq!(number(0.0, 1), "0.0");
        assert_eq!(number(1e30, 1), "1.00e30");
        assert_eq!(number(6e-29, 3), "6.00e-29");
        assert_eq!(number(-2.5e9, 1), "-2.50e9");
        assert_eq!(number(f64::INFINITY, 1), "inf");
        for e in -40..40 {
            assert!(number(1.2345 * 10f64.powi(e), 1).len() <= 10, "10^{e}");
        }
    }
}
