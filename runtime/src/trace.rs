//! Exploration traces: where the reader's finger (or the array's carrier)
//! was at each moment, as CSV with the header `t_ms,x_mm,y_mm` and an
//! optional `contact` column (0 or 1, for the finger device).
//!
//! Columns are found by name, in any order; other columns are ignored.
//! Lines starting with `#` are comments (a recorder's preamble), except a
//! first comment whose fields name the columns (`# t_ms,x_mm,y_mm`, as
//! numpy's `savetxt` writes a header), which is the header. Fields are
//! separated by commas, or by semicolons or tabs when the header has no comma
//! (spreadsheets in locales with a decimal comma); with those, a number may
//! be written with a decimal comma (`12,5`).
//! Times are milliseconds on the trace's own clock, not negative, and never
//! decreasing; every number is finite. Between samples the position is
//! interpolated linearly and contact holds the latest sample's value. Tick
//! `k` of a rate `R` is the instant `k · 1000 / R` ms on the same clock
//! (t_ms = 0 is tick 0), and a trace covers the ticks from its first
//! sample's time to its last's, both included.
//!
//! ```
//! use taxel_runtime::trace::Trace;
//!
//! let trace = Trace::parse("t_ms,x_mm,y_mm\n0,10,20\n4,14,20\n".as_bytes()).unwrap();
//! let points: Vec<_> = trace.ticks(1000).collect();
//! assert_eq!(points.len(), 5);
//! assert_eq!((points[1].0.0, points[1].1.x_mm, points[1].1.y_mm), (1, 11.0, 20.0));
//! ```

use std::fmt;
use std::io::Read;
use std::string::{String, ToString};
use std::vec::Vec;

use taxel_format::Tick;

/// One row of a trace.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TraceSample {
    /// Time in milliseconds.
    pub t_ms: f64,
    /// Page x in millimetres.
    pub x_mm: f64,
    /// Page y in millimetres (down).
    pub y_mm: f64,
    /// Whether the finger touches the surface (true when the trace has no `contact` column).
    pub contact: bool,
}

/// The state of the exploration at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TracePoint {
    /// Page x in millimetres.
    pub x_mm: f64,
    /// Page y in millimetres.
    pub y_mm: f64,
    /// Whether the finger touches the surface.
    pub contact: bool,
}

/// A parsed, checked exploration trace (at least one sample).
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    samples: Vec<TraceSample>,
    has_contact: bool,
}

/// Why a trace was refused. `line` is the 1-based line in the file.
#[derive(Debug, Clone, PartialEq)]
pub enum TraceError {
    /// The CSV itself is malformed (or not UTF-8), or could not be read.
    Csv {
        /// Line of the problem, when known.
        line: Option<u64>,
        /// What the CSV reader said.
        message: String,
    },
    /// A required column is not in the header.
    MissingColumn {
        /// Line of the header.
        line: u64,
        /// The column.
        column: &'static str,
        /// The header found.
        header: String,
    },
    /// A column appears twice in the header.
    DuplicateColumn {
        /// Line of the header.
        line: u64,
        /// The column.
        column: &'static str,
    },
    /// A row has fewer fields than the header.
    MissingField {
        /// Line of the row.
        line: u64,
        /// The column with no value.
        column: &'static str,
    },
    /// A field is not a number.
    NotANumber {
        /// Line of the row.
        line: u64,
        /// The column.
        column: &'static str,
        /// The text found.
        value: String,
    },
    /// A number is NaN or infinite.
    NotFinite {
        /// Line of the row.
        line: u64,
        /// The column.
        column: &'static str,
        /// The text found.
        value: String,
    },
    /// A `contact` field is not 0 or 1.
    BadContact {
        /// Line of the row.
        line: u64,
        /// The text found.
        value: String,
    },
    /// A time before 0 ms.
    NegativeTime {
        /// Line of the row.
        line: u64,
        /// The time.
        t_ms: f64,
    },
    /// A time earlier than the previous row's.
    TimeBackwards {
        /// Line of the row.
        line: u64,
        /// The time.
        t_ms: f64,
        /// The previous row's time.
        previous: f64,
    },
    /// The trace has a header but no samples (or nothing at all).
    Empty,
}

impl fmt::Display for TraceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TraceError::Csv { line: Some(l), message } => write!(f, "line {l}: malformed CSV: {message}"),
            TraceError::Csv { line: None, message } => write!(f, "malformed CSV: {message}"),
            TraceError::MissingColumn { line, column, header } => write!(
                f,
                "line {line}: the header has no `{column}` column (expected t_ms,x_mm,y_mm and optionally contact; found `{header}`)"
            ),
            TraceError::DuplicateColumn { line, column } => write!(f, "line {line}: the header names `{column}` twice"),
            TraceError::MissingField { line, column } => write!(f, "line {line}: no value for `{column}`"),
            TraceError::NotANumber { line, column, value } => {
                write!(f, "line {line}: `{column}` must be a number, found `{value}`")
            }
            TraceError::NotFinite { line, column, value } => {
                write!(f, "line {line}: `{column}` must be a finite number, found `{value}`")
            }
            TraceError::BadContact { line, value } => {
                write!(f, "line {line}: `contact` must be 0 or 1, found `{value}`")
            }
            TraceError::NegativeTime { line, t_ms } => {
                write!(f, "line {line}: time {t_ms} ms is negative (t_ms = 0 is tick 0)")
            }
            TraceError::TimeBackwards { line, t_ms, previous } => {
                write!(f, "line {line}: time goes backwards, from {previous} ms to {t_ms} ms")
            }
            TraceError::Empty => write!(f, "the trace has no samples (expected a header t_ms,x_mm,y_mm and rows)"),
        }
    }
}

impl std::error::Error for TraceError {}

const COLUMNS: [&str; 4] = ["t_ms", "x_mm", "y_mm", "contact"];

impl Trace {
    /// Reads and checks a trace.
    pub fn parse(mut reader: impl Read) -> Result<Trace, TraceError> {
        let mut bytes = Vec::new();
        reader.read_to_end(&mut bytes).map_err(|e| TraceError::Csv { line: None, message: e.to_string() })?;
        // One pass over the lines. The header is the first line that is
        // neither blank nor a comment, or a comment that names the columns
        // (numpy's `savetxt` writes its header as `# t_ms,x_mm,y_mm`), which
        // loses its `#`. Comment lines (and lines of spaces, which the CSV
        // reader would take for a header of one empty column) are emptied,
        // rather than left to the CSV reader's comments, which it does not
        // count as lines: errors name the line in the file.
        let names_columns = |l: &[u8]| {
            let fields = || l.split(|b| matches!(b, b',' | b';' | b'\t')).map(|f| f.trim_ascii());
            COLUMNS[..3].iter().all(|c| fields().any(|f| f == c.as_bytes()))
        };
        let mut text = Vec::with_capacity(bytes.len());
        let mut header: Option<(u64, &[u8])> = None;
        for (i, l) in bytes.split(|&b| b == b'\n').enumerate() {
            if i > 0 {
                text.push(b'\n');
            }
            let bare = l.strip_prefix("\u{feff}".as_bytes()).unwrap_or(l);
            let comment = bare.strip_prefix(b"#");
            if header.is_none()
                && let Some(names) = comment.filter(|c| names_columns(c))
            {
                header = Some((i as u64 + 1, names));
                text.extend_from_slice(names);
            } else if comment.is_none() && !bare.iter().all(u8::is_ascii_whitespace) {
                header = header.or(Some((i as u64 + 1, bare)));
                text.extend_from_slice(l);
            }
        }
        let (header_line, header_text) = header.unwrap_or((1, &[]));
        // Line numbers from byte offsets: the CSV reader's own skip blank
        // lines without counting them (a record's position is where the
        // reader started, before the blank lines it skipped).
        let starts: Vec<usize> = core::iter::once(0)
            .chain(text.iter().enumerate().filter(|(_, b)| **b == b'\n').map(|(i, _)| i + 1))
            .collect();
        let line_of = |p: &csv::Position| {
            let mut at = p.byte() as usize;
            while matches!(text.get(at), Some(b'\n' | b'\r')) {
                at += 1;
            }
            starts.partition_point(|&s| s <= at) as u64
        };
        let delimiter = match header_text {
            h if h.contains(&b',') => b',',
            h if h.contains(&b';') => b';',
            h if h.contains(&b'\t') => b'\t',
            _ => b',',
        };
        let mut csv = csv::ReaderBuilder::new()
            .has_headers(true)
            .flexible(true)
            .trim(csv::Trim::All)
            .comment(None)
            .delimiter(delimiter)
            .from_reader(text.as_slice());
        let csv_error = |e: csv::Error| TraceError::Csv {
            line: e.position().map(line_of),
            message: match e.kind() {
                csv::ErrorKind::Utf8 { .. } => "not UTF-8 text".to_string(),
                _ => e.to_string(),
            },
        };
        let header = csv.headers().map_err(csv_error)?.clone();
        if header.is_empty() || header.iter().all(str::is_empty) {
            return Err(TraceError::Empty);
        }
        let mut index = [None; 4];
        for (i, name) in header.iter().enumerate() {
            // A byte-order mark may precede the first column's name.
            let name = name.trim_start_matches('\u{feff}');
            if let Some(c) = COLUMNS.iter().position(|&c| c == name) {
                if index[c].is_some() {
                    return Err(TraceError::DuplicateColumn { line: header_line, column: COLUMNS[c] });
                }
                index[c] = Some(i);
            }
        }
        let header_text = header.iter().collect::<Vec<_>>().join(&(delimiter as char).to_string());
        let mut required = [0usize; 3];
        for c in 0..3 {
            required[c] = index[c].ok_or(TraceError::MissingColumn {
                line: header_line,
                column: COLUMNS[c],
                header: header_text.clone(),
            })?;
        }
        let has_contact = index[3].is_some();
        let mut samples: Vec<TraceSample> = Vec::new();
        let mut record = csv::StringRecord::new();
        loop {
            match csv.read_record(&mut record) {
                Ok(true) => {}
                Ok(false) => break,
                Err(e) => return Err(csv_error(e)),
            }
            let line = record.position().map(line_of).unwrap_or(0);
            // A blank line reads as one empty field; skip it.
            if record.len() == 1 && record.get(0) == Some("") {
                continue;
            }
            let field = |c: usize, i: usize| record.get(i).ok_or(TraceError::MissingField { line, column: COLUMNS[c] });
            let number = |c: usize| -> Result<f64, TraceError> {
                let text = field(c, required[c])?;
                // A decimal comma, where commas do not separate fields.
                let parsed = match delimiter {
                    b',' => text.parse(),
                    _ => text.replacen(',', ".", 1).parse(),
                };
                let v: f64 =
                    parsed.map_err(|_| TraceError::NotANumber { line, column: COLUMNS[c], value: text.to_string() })?;
                if v.is_finite() {
                    Ok(v)
                } else {
                    Err(TraceError::NotFinite { line, column: COLUMNS[c], value: text.to_string() })
                }
            };
            let (t_ms, x_mm, y_mm) = (number(0)?, number(1)?, number(2)?);
            let contact = match index[3] {
                None => true,
                Some(i) => match field(3, i)? {
                    "1" => true,
                    "0" => false,
                    other => return Err(TraceError::BadContact { line, value: other.to_string() }),
                },
            };
            if t_ms < 0.0 {
                return Err(TraceError::NegativeTime { line, t_ms });
            }
            if let Some(prev) = samples.last()
                && t_ms < prev.t_ms
            {
                return Err(TraceError::TimeBackwards { line, t_ms, previous: prev.t_ms });
            }
            samples.push(TraceSample { t_ms, x_mm, y_mm, contact });
        }
        if samples.is_empty() {
            return Err(TraceError::Empty);
        }
        Ok(Trace { samples, has_contact })
    }

    /// A trace made in code (a generated sweep) rather than read from a
    /// file, checked like a parsed one: at least one sample, every number
    /// finite, times not negative and never decreasing. The `line` of an
    /// error is the sample's line had the trace been written as CSV (the
    /// first sample is line 2). Contact is taken from the samples; the trace
    /// counts as having a `contact` column when any sample is lifted.
    pub fn from_samples(samples: Vec<TraceSample>) -> Result<Trace, TraceError> {
        if samples.is_empty() {
            return Err(TraceError::Empty);
        }
        let mut previous: Option<f64> = None;
        for (i, s) in samples.iter().enumerate() {
            let line = i as u64 + 2;
            for (column, v) in [("t_ms", s.t_ms), ("x_mm", s.x_mm), ("y_mm", s.y_mm)] {
                if !v.is_finite() {
                    return Err(TraceError::NotFinite { line, column, value: v.to_string() });
                }
            }
            if s.t_ms < 0.0 {
                return Err(TraceError::NegativeTime { line, t_ms: s.t_ms });
            }
            if let Some(p) = previous
                && s.t_ms < p
            {
                return Err(TraceError::TimeBackwards { line, t_ms: s.t_ms, previous: p });
            }
            previous = Some(s.t_ms);
        }
        let has_contact = samples.iter().any(|s| !s.contact);
        Ok(Trace { samples, has_contact })
    }

    /// The samples, in time order.
    pub fn samples(&self) -> &[TraceSample] {
        &self.samples
    }

    /// Whether the trace had a `contact` column.
    pub fn has_contact(&self) -> bool {
        self.has_contact
    }

    /// The first and last tick of `rate_hz` inside the trace's time span, or
    /// `None` when no tick falls inside it (a span shorter than one tick).
    pub fn tick_range(&self, rate_hz: u32) -> Option<(Tick, Tick)> {
        let (first, last) = (self.samples.first()?, self.samples.last()?);
        let rate = rate_hz.max(1) as f64;
        // A tolerance of a millionth of a tick absorbs decimal rounding
        // (0.3 ms at 10 kHz is tick 3, not 2.9999999999999996).
        let a = first.t_ms * rate / 1000.0;
        let b = last.t_ms * rate / 1000.0;
        // Times beyond 2^62 ticks (some 146 million years at 1 kHz)
        // saturate there; a player refuses such spans by their length.
        const LAST: f64 = (1u64 << 62) as f64;
        let k0 = (a - 1e-6).ceil().clamp(0.0, LAST);
        let k1 = (b + 1e-6).floor().min(LAST);
        if k1 < k0 {
            return None;
        }
        Some((Tick(k0 as u64), Tick(k1 as u64)))
    }

    /// The interpolated state at `t_ms` (clamped to the trace's span).
    pub fn at_ms(&self, t_ms: f64) -> TracePoint {
        let i = self.samples.partition_point(|s| s.t_ms <= t_ms);
        self.between(i.saturating_sub(1), t_ms)
    }

    /// Every tick of `rate_hz` inside the trace with its interpolated state,
    /// in order (linear time over the whole trace).
    pub fn ticks(&self, rate_hz: u32) -> impl Iterator<Item = (Tick, TracePoint)> + '_ {
        let range = self.tick_range(rate_hz);
        let (k0, k1) = range.map(|(a, b)| (a.0, b.0)).unwrap_or((1, 0));
        let rate = rate_hz.max(1) as f64;
        let mut seg = 0usize;
        (k0..=k1).map(move |k| {
            let t = k as f64 * 1000.0 / rate;
            while seg + 1 < self.samples.len() && self.samples[seg + 1].t_ms <= t {
                seg += 1;
            }
            (Tick(k), self.between(seg, t))
        })
    }

    /// Interpolates between sample `i` and the next at `t` (clamped).
    fn between(&self, i: usize, t: f64) -> TracePoint {
        let Some(a) = self.samples.get(i) else {
            return TracePoint { x_mm: 0.0, y_mm: 0.0, contact: false };
        };
        let point = |s: &TraceSample| TracePoint { x_mm: s.x_mm, y_mm: s.y_mm, contact: s.contact };
        match self.samples.get(i + 1) {
            Some(b) if b.t_ms > a.t_ms && t > a.t_ms => {
                let u = ((t - a.t_ms) / (b.t_ms - a.t_ms)).min(1.0);
                TracePoint {
                    x_mm: a.x_mm + u * (b.x_mm - a.x_mm),
                    y_mm: a.y_mm + u * (b.y_mm - a.y_mm),
                    contact: a.contact,
                }
            }
            _ => point(a),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec;

    fn parse(s: &str) -> Result<Trace, TraceError> {
        Trace::parse(s.as_bytes())
    }

    #[test]
    fn interpolates_linearly_between_samples() {
        let t = parse("t_ms,x_mm,y_mm\n0,0,10\n10,20,0\n20,20,0\n").unwrap();
        assert_eq!(t.tick_range(1000), Some((Tick(0), Tick(20))));
        let p: Vec<_> = t.ticks(1000).collect();
        assert_eq!(p.len(), 21);
        assert_eq!((p[5].1.x_mm, p[5].1.y_mm), (10.0, 5.0));
        assert_eq!((p[15].1.x_mm, p[15].1.y_mm), (20.0, 0.0));
        assert_eq!(t.at_ms(2.5).x_mm, 5.0);
        // At 48 kHz the first millisecond holds 48 ticks.
        assert_eq!(t.tick_range(48_000), Some((Tick(0), Tick(960))));
    }

    #[test]
    fn ticks_cover_only_the_trace_span() {
        let t = parse("t_ms,x_mm,y_mm\n2.5,0,0\n7.5,5,0\n").unwrap();
        assert_eq!(t.tick_range(1000), Some((Tick(3), Tick(7))));
        let first = t.ticks(1000).next().unwrap();
        assert_eq!(first.0, Tick(3));
        assert!((first.1.x_mm - 0.5).abs() < 1e-12);
        let t = parse("t_ms,x_mm,y_mm\n0.3,0,0\n0.6,1,1\n").unwrap();
        assert_eq!(t.tick_range(1000), None);
        assert_eq!(t.ticks(1000).count(), 0);
        assert_eq!(t.tick_range(10_000), Some((Tick(3), Tick(6))));
        let t = parse("t_ms,x_mm,y_mm\n0,0,0\n1e300,0,0\n").unwrap();
        assert_eq!(t.tick_range(1000), Some((Tick(0), Tick(1 << 62))));
    }

    #[test]
    fn columns_by_name_with_contact_and_extras() {
        let t = parse("y_mm, note ,x_mm,contact,t_ms\n1,a,2,1,0\n3,b,4,0,5\n").unwrap();
        assert!(t.has_contact());
        assert_eq!(t.samples()[1], TraceSample { t_ms: 5.0, x_mm: 4.0, y_mm: 3.0, contact: false });
        assert!(!t.at_ms(5.0).contact);
        assert!(t.at_ms(4.9).contact);
        assert!(parse("t_ms,x_mm,y_mm\n0,1,2\n").unwrap().samples()[0].contact);
    }

    #[test]
    fn comments_semicolons_tabs_and_decimal_commas_are_read() {
        // A recorder's preamble, blank lines and a comment between rows.
        let t = parse("# recorded 2026-11-27, carrier 3\n\nt_ms,x_mm,y_mm\n0,1,2\n# paused\n4,5,6\n").unwrap();
        assert_eq!(t.samples().len(), 2);
        assert_eq!(t.samples()[1], TraceSample { t_ms: 4.0, x_mm: 5.0, y_mm: 6.0, contact: true });
        // A spreadsheet in a locale with decimal commas, and one with tabs.
        for text in ["t_ms;x_mm;y_mm\n0;10,5;20\n2,5;11;20,25\n", "t_ms\tx_mm\ty_mm\n0\t10.5\t20\n2.5\t11\t20.25\n"] {
            let t = parse(text).unwrap();
            assert_eq!(
                t.samples(),
                [
                    TraceSample { t_ms: 0.0, x_mm: 10.5, y_mm: 20.0, contact: true },
                    TraceSample { t_ms: 2.5, x_mm: 11.0, y_mm: 20.25, contact: true }
                ],
                "{text:?}"
            );
        }
        // Errors count the comment lines: they name the line in the file.
        let e = parse("# a\n# b\nt_ms;x_mm\n0;1\n").unwrap_err().to_string();
        assert!(e.starts_with("line 3: the header has no `y_mm` column") && e.contains("`t_ms;x_mm`"), "{e}");
        let e = parse("# a\nt_ms,x_mm,y_mm\n0,1,2\n# b\n1,abc,2\n").unwrap_err().to_string();
        assert!(e.starts_with("line 5: `x_mm` must be a number"), "{e}");
        // Blank lines count too (the CSV reader skips them uncounted), with
        // Unix or Windows line ends.
        let e = parse("t_ms,x_mm,y_mm\n\n0,1,2\n\n1,abc,2\n").unwrap_err().to_string();
        assert!(e.starts_with("line 5: "), "{e}");
        let e = parse("t_ms,x_mm,y_mm\r\n\r\n0,1,2\r\n1,abc,2\r\n").unwrap_err().to_string();
        assert!(e.starts_with("line 4: "), "{e}");
        let t = parse("  \n\t\nt_ms,x_mm,y_mm\n0,1,2\n").unwrap();
        assert_eq!(t.samples().len(), 1);
        // numpy's savetxt: the header as a comment, after another comment.
        let t = parse("# sweep 3\n# t_ms,x_mm,y_mm\n0,1,2\n5,3,4\n").unwrap();
        assert_eq!(t.samples()[1], TraceSample { t_ms: 5.0, x_mm: 3.0, y_mm: 4.0, contact: true });
        let e = parse("# t_ms,x_mm,y_mm\n0,1,2\n1,abc,2\n").unwrap_err().to_string();
        assert!(e.starts_with("line 3: "), "{e}");
        // A comment that only mentions the columns stays a comment.
        let t = parse("# columns: t_ms, x_mm, y_mm in ms and mm\nt_ms,x_mm,y_mm\n0,1,2\n").unwrap();
        assert_eq!(t.samples().len(), 1);
        // With commas between fields, a decimal comma is two fields.
        assert!(parse("t_ms,x_mm,y_mm\n0,1,5,2\n").is_ok_and(|t| t.samples()[0].y_mm == 5.0));
    }

    #[test]
    fn bad_traces_name_the_line_and_the_problem() {
        let cases = [
            ("t_ms,x_mm\n0,1\n", "line 1: the header has no `y_mm` column"),
            ("t_ms,x_mm,y_mm,x_mm\n", "line 1: the header names `x_mm` twice"),
            ("t_ms,x_mm,y_mm\n0,1,2\n1,abc,2\n", "line 3: `x_mm` must be a number, found `abc`"),
            ("t_ms,x_mm,y_mm\n0,1,2\n1,NaN,2\n", "line 3: `x_mm` must be a finite number, found `NaN`"),
            ("t_ms,x_mm,y_mm\n0,1,inf\n", "line 2: `y_mm` must be a finite number, found `inf`"),
            ("t_ms,x_mm,y_mm\n0,1,2\n5,1,2\n4,1,2\n", "line 4: time goes backwards, from 5 ms to 4 ms"),
            ("t_ms,x_mm,y_mm\n-1,1,2\n", "line 2: time -1 ms is negative"),
            ("t_ms,x_mm,y_mm\n0,1\n", "line 2: no value for `y_mm`"),
            ("t_ms,x_mm,y_mm,contact\n0,1,2,yes\n", "line 2: `contact` must be 0 or 1, found `yes`"),
            ("t_ms,x_mm,y_mm\n", "the trace has no samples"),
            ("", "the trace has no samples"),
        ];
        for (text, want) in cases {
            let got = parse(text).unwrap_err().to_string();
            assert!(got.starts_with(want), "{text:?}: {got}");
        }
        let bad_utf8 = b"t_ms,x_mm,y_mm\n0,1,\xff\n";
        let got = Trace::parse(&bad_utf8[..]).unwrap_err().to_string();
        assert!(got.contains("line 2") && got.contains("UTF-8"), "{got}");
    }

    #[test]
    fn made_traces_are_checked_like_parsed_ones() {
        let at = |t_ms: f64, x_mm: f64| TraceSample { t_ms, x_mm, y_mm: 0.0, contact: true };
        let t = Trace::from_samples(vec![at(0.0, 0.0), at(10.0, 10.0)]).unwrap();
        assert_eq!(t, parse("t_ms,x_mm,y_mm\n0,0,0\n10,10,0\n").unwrap());
        let e = Trace::from_samples(vec![at(0.0, 0.0), at(5.0, f64::NAN)]).unwrap_err();
        assert_eq!(e.to_string(), "line 3: `x_mm` must be a finite number, found `NaN`");
        let e = Trace::from_samples(vec![at(5.0, 0.0), at(4.0, 0.0)]).unwrap_err();
        assert_eq!(e.to_string(), "line 3: time goes backwards, from 5 ms to 4 ms");
        assert_eq!(
            Trace::from_samples(vec![at(-1.0, 0.0)]).unwrap_err(),
            TraceError::NegativeTime { line: 2, t_ms: -1.0 }
        );
        assert_eq!(Trace::from_samples(Vec::new()).unwrap_err(), TraceError::Empty);
    }

    #[test]
    fn equal_times_are_allowed_and_blank_lines_skipped() {
        let t = parse("t_ms,x_mm,y_mm\n0,0,0\n\n5,1,0\n5,2,0\n10,2,0\n").unwrap();
        assert_eq!(t.samples().len(), 4);
        assert_eq!(t.at_ms(5.0).x_mm, 2.0);
    }
}
