//! Reading hand-editable TOML exactly: numbers are parsed from their text
//! (so an `f32` written with Rust's shortest round-trip formatting reads back
//! bit for bit, never through an `f64` and a second rounding), every key is
//! checked against the keys allowed, and errors name the file, the line and
//! the key path.

use toml::de::{DeTable, DeValue};

use super::error::TextError;

/// A parsed TOML file.
pub struct Doc<'i> {
    file: String,
    text: &'i str,
    root: DeTable<'i>,
}

impl<'i> Doc<'i> {
    /// Parses `text`, the contents of `file`.
    pub fn parse(file: &str, text: &'i str) -> Result<Self, TextError> {
        let root = DeTable::parse(text).map_err(|e| {
            let line = e.span().map(|s| line_of(text, s.start));
            TextError { file: file.into(), line, message: first_line(&e.to_string()), io: false }
        })?;
        Ok(Doc { file: file.into(), text, root: root.into_inner() })
    }

    /// The top-level table, with `allowed` keys.
    pub fn root(&self, allowed: &[&str]) -> Result<Table<'_, 'i>, TextError> {
        Table::new(self, &self.root, String::new(), 1, allowed)
    }
}

fn line_of(text: &str, at: usize) -> usize {
    text.get(..at).map_or(0, |t| t.matches('\n').count()) + 1
}

/// The message of a toml error without its source excerpt.
fn first_line(msg: &str) -> String {
    let lines: Vec<&str> = msg.lines().filter(|l| !l.trim().is_empty()).collect();
    // toml's messages are "TOML parse error at line N, column M", an excerpt, then the reason.
    lines.last().map_or_else(|| msg.to_string(), |l| l.trim().to_string())
}

/// One table of a document, with its key path (`chunk[3]`).
pub struct Table<'d, 'i> {
    doc: &'d Doc<'i>,
    table: &'d DeTable<'i>,
    path: String,
    line: usize,
}

impl<'d, 'i> Table<'d, 'i> {
    fn new(
        doc: &'d Doc<'i>,
        table: &'d DeTable<'i>,
        path: String,
        line: usize,
        allowed: &[&str],
    ) -> Result<Self, TextError> {
        let t = Table { doc, table, path, line };
        let mut keys: Vec<_> = table.iter().map(|(k, _)| k).collect();
        keys.sort_by_key(|k| k.span().start);
        if let Some(k) = keys.into_iter().find(|k| !allowed.contains(&k.get_ref().as_ref())) {
            return Err(t.err_at(
                line_of(doc.text, k.span().start),
                k.get_ref(),
                format!("unknown key, expected one of: {}", allowed.join(", ")),
            ));
        }
        Ok(t)
    }

    fn key(&self, k: &str) -> String {
        if self.path.is_empty() { k.to_string() } else { format!("{}.{k}", self.path) }
    }

    fn err_at(&self, line: usize, k: &str, message: String) -> TextError {
        TextError::at(&self.doc.file, line, format!("key `{}`: {message}", self.key(k)))
    }

    /// An error about key `k` of this table, at its line (or the table's when absent).
    pub fn err(&self, k: &str, message: impl Into<String>) -> TextError {
        let line = self.find(k).map_or(self.line, |(_, l)| l);
        self.err_at(line, k, message.into())
    }

    fn find(&self, k: &str) -> Option<(&'d DeValue<'i>, usize)> {
        self.table
            .iter()
            .find(|(key, _)| key.get_ref().as_ref() == k)
            .map(|(_, v)| (v.get_ref(), line_of(self.doc.text, v.span().start)))
    }

    fn get(&self, k: &str) -> Result<(&'d DeValue<'i>, usize), TextError> {
        self.find(k).ok_or_else(|| self.err_at(self.line, k, "missing key".into()))
    }

    /// Whether the table has key `k`.
    pub fn has(&self, k: &str) -> bool {
        self.find(k).is_some()
    }

    /// A string.
    pub fn str(&self, k: &str) -> Result<&'d str, TextError> {
        match self.get(k)? {
            (DeValue::String(s), _) => Ok(s.as_ref()),
            (_, line) => Err(self.err_at(line, k, "expected a string".into())),
        }
    }

    /// A boolean.
    pub fn bool(&self, k: &str) -> Result<bool, TextError> {
        match self.get(k)? {
            (DeValue::Boolean(b), _) => Ok(*b),
            (_, line) => Err(self.err_at(line, k, "expected true or false".into())),
        }
    }

    /// A non-negative integer up to `max`.
    pub fn uint(&self, k: &str, max: u64) -> Result<u64, TextError> {
        let (v, line) = self.get(k)?;
        uint_of(v, max).ok_or_else(|| self.err_at(line, k, format!("expected an integer from 0 to {max}")))
    }

    /// An optional non-negative integer up to `max`.
    pub fn opt_uint(&self, k: &str, max: u64) -> Result<Option<u64>, TextError> {
        if self.has(k) { self.uint(k, max).map(Some) } else { Ok(None) }
    }

    /// A number, read as the `f32` nearest to its text.
    pub fn f32(&self, k: &str) -> Result<f32, TextError> {
        let (v, line) = self.get(k)?;
        f32_of(v).ok_or_else(|| self.err_at(line, k, "expected a number".into()))
    }

    /// An array of numbers.
    pub fn f32_array(&self, k: &str) -> Result<Vec<f32>, TextError> {
        let (v, line) = self.get(k)?;
        let bad = || self.err_at(line, k, "expected an array of numbers".into());
        let DeValue::Array(a) = v else { return Err(bad()) };
        a.iter().map(|e| f32_of(e.get_ref()).ok_or_else(bad)).collect()
    }

    /// An array of non-negative integers up to `max`.
    pub fn uint_array(&self, k: &str, max: u64) -> Result<Vec<u64>, TextError> {
        let (v, line) = self.get(k)?;
        let bad = || self.err_at(line, k, format!("expected an array of integers from 0 to {max}"));
        let DeValue::Array(a) = v else { return Err(bad()) };
        a.iter().map(|e| uint_of(e.get_ref(), max).ok_or_else(bad)).collect()
    }

    /// An array of tables (`[[k]]`), each with `allowed` keys; empty when absent.
    pub fn tables(&self, k: &str, allowed: &[&str]) -> Result<Vec<Table<'d, 'i>>, TextError> {
        let Some((v, line)) = self.find(k) else { return Ok(Vec::new()) };
        let DeValue::Array(a) = v else {
            return Err(self.err_at(line, k, format!("expected tables [[{}]]", self.key(k))));
        };
        a.iter()
            .enumerate()
            .map(|(i, e)| match e.get_ref() {
                DeValue::Table(t) => Table::new(
                    self.doc,
                    t,
                    format!("{}[{}]", self.key(k), i + 1),
                    line_of(self.doc.text, e.span().start),
                    allowed,
                ),
                _ => Err(self.err_at(line, k, format!("expected tables [[{}]]", self.key(k)))),
            })
            .collect()
    }
}

fn uint_of(v: &DeValue<'_>, max: u64) -> Option<u64> {
    match v {
        DeValue::Integer(i) => u64::from_str_radix(i.as_str(), i.radix()).ok().filter(|&n| n <= max),
        _ => None,
    }
}

fn f32_of(v: &DeValue<'_>) -> Option<f32> {
    match v {
        DeValue::Float(f) => f.as_str().parse().ok(),
        DeValue::Integer(i) if i.radix() == 10 => i.as_str().parse().ok(),
        _ => None,
    }
}

/// Formats an `f32` for TOML or CSV: Rust's shortest round-trip formatting,
/// in the form that switches to an exponent for very large and very small
/// values (so TOML never sees a 39-digit integer) and keeps a `.0` on whole
/// numbers (so TOML reads a float).
pub fn f32_text(v: f32) -> String {
    format!("{v:?}")
}

/// A TOML string literal with every character that needs it escaped.
pub fn toml_string(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_round_trip_through_their_text() {
        for v in [0.1f32, -0.0, 1e38, f32::MAX, 1e-45, f32::MIN_POSITIVE, 0.70710677, 16_777_216.0, 123_456.79] {
            let text = format!("x = {}\n", f32_text(v));
            let doc = Doc::parse("t.toml", &text).unwrap();
            assert_eq!(doc.root(&["x"]).unwrap().f32("x").unwrap().to_bits(), v.to_bits(), "{text}");
        }
    }

    #[test]
    fn errors_name_file_line_and_key() {
        let doc = Doc::parse("m.toml", "a = 1\n\n[[chunk]]\nkind = 3\nwat = 1\n").unwrap();
        let root = doc.root(&["a", "chunk"]).unwrap();
        let e = root.tables("chunk", &["kind"]).err().unwrap();
        assert_eq!(e.to_string(), "m.toml:5: key `chunk[1].wat`: unknown key, expected one of: kind");
        let chunks = root.tables("chunk", &["kind", "wat"]).unwrap();
        assert_eq!(chunks[0].str("kind").unwrap_err().to_string(), "m.toml:4: key `chunk[1].kind`: expected a string");
        assert_eq!(root.uint("b", 9).unwrap_err().to_string(), "m.toml:1: key `b`: missing key");
        let e = Doc::parse("m.toml", "a = = 1\n").err().unwrap();
        assert_eq!((e.file.as_str(), e.line), ("m.toml", Some(1)));
    }

    #[test]
    fn strings_are_escaped() {
        let s = "quote \" backslash \\ newline \n tab \t é";
        let text = format!("s = {}\n", toml_string(s));
        assert_eq!(Doc::parse("t", &text).unwrap().root(&["s"]).unwrap().str("s").unwrap(), s);
    }
}
