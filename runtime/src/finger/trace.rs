//! Exploration traces for the finger device: CSV with the header
//! `t_ms,x_mm,y_mm,contact` (columns in any order, `contact` optional and
//! then always 1). Times must be finite, non-negative and non-decreasing.

extern crate std;

use std::string::{String, ToString};
use std::vec::Vec;
use std::{format, vec};

/// One row of a trace.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TraceRow {
    /// Time in milliseconds on the trace's clock.
    pub t_ms: f64,
    /// Page x in mm.
    pub x_mm: f32,
    /// Page y in mm.
    pub y_mm: f32,
    /// Whether the finger touches.
    pub contact: bool,
}

impl TraceRow {
    /// The tick of this row at `rate_hz`: `round(t_ms · rate / 1000)`.
    pub fn tick(&self, rate_hz: u32) -> u64 {
        let t = self.t_ms * rate_hz as f64 / 1000.0;
        // Parsing bounds t_ms, so this is finite and far below 2^63.
        (t + 0.5).floor() as u64
    }
}

/// A malformed trace: the 1-based line and what was wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TraceError {
    /// 1-based line.
    pub line: usize,
    /// What was expected.
    pub message: String,
}

impl core::fmt::Display for TraceError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

impl std::error::Error for TraceError {}

/// Longest trace time accepted: ten days, in ms.
const MAX_T_MS: f64 = 864_000_000.0;

/// Parses a trace.
pub fn parse(text: &str) -> Result<Vec<TraceRow>, TraceError> {
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty());
    let Some((hl, header)) = lines.next() else {
        return Err(TraceError { line: 1, message: "empty trace: expected the header t_ms,x_mm,y_mm,contact".into() });
    };
    let names: Vec<&str> = header.trim_start_matches('\u{feff}').split(',').map(str::trim).collect();
    let col = |n: &str| names.iter().position(|c| c.eq_ignore_ascii_case(n));
    let (Some(ct), Some(cx), Some(cy)) = (col("t_ms"), col("x_mm"), col("y_mm")) else {
        return Err(TraceError {
            line: hl + 1,
            message: format!("header '{}' lacks t_ms, x_mm or y_mm (expected t_ms,x_mm,y_mm,contact)", header.trim()),
        });
    };
    let cc = col("contact");
    let mut rows = vec![];
    let mut last = 0.0f64;
    for (ln, l) in lines {
        let line = ln + 1;
        let cells: Vec<&str> = l.split(',').map(str::trim).collect();
        if cells.len() != names.len() {
            return Err(TraceError {
                line,
                message: format!("{} fields, expected {} as in the header", cells.len(), names.len()),
            });
        }
        let num = |i: usize, what: &str| -> Result<f64, TraceError> {
            let s = cells[i];
            match s.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(TraceError { line, message: format!("{what} '{s}' is not a finite number") }),
            }
        };
        let t_ms = num(ct, "t_ms")?;
        if !(0.0..=MAX_T_MS).contains(&t_ms) || t_ms < last {
            return Err(TraceError {
                line,
                message: format!("t_ms {t_ms} must be from 0 to {MAX_T_MS} and not before the previous row ({last})"),
            });
        }
        last = t_ms;
        let x = num(cx, "x_mm")?;
        let y = num(cy, "y_mm")?;
        if x.abs() > 1e9 || y.abs() > 1e9 {
            return Err(TraceError { line, message: "position beyond 1e9 mm".to_string() });
        }
        let contact = match cc.map(|i| cells[i]) {
            None => true,
            Some("1" | "true" | "TRUE" | "True") => true,
            Some("0" | "false" | "FALSE" | "False") => false,
            Some(other) => {
                return Err(TraceError { line, message: format!("contact '{other}' must be 1, 0, true or false") });
            }
        };
        rows.push(TraceRow { t_ms, x_mm: x as f32, y_mm: y as f32, contact });
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_columns_in_any_order_and_defaults_contact() {
        let rows = parse("x_mm,t_ms,y_mm\n1.5,0,2\n2.5,10,2\n").unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[1], TraceRow { t_ms: 10.0, x_mm: 2.5, y_mm: 2.0, contact: true });
        assert_eq!(rows[1].tick(100), 1);
    }

    #[test]
    fn names_the_line_of_a_bad_value() {
        let e = parse("t_ms,x_mm,y_mm,contact\n0,1,1,1\n10,nan,1,1\n").unwrap_err();
        assert_eq!(e.line, 3);
        assert!(e.message.contains("x_mm"));
        let e = parse("t_ms,x_mm,y_mm,contact\n10,1,1,1\n5,1,1,1\n").unwrap_err();
        assert_eq!(e.line, 3);
        let e = parse("t_ms,x_mm,y_mm,contact\n0,1,1,maybe\n").unwrap_err();
        assert!(e.message.contains("contact"));
        assert!(parse("").is_err());
        assert!(parse("a,b\n").is_err());
    }
}
