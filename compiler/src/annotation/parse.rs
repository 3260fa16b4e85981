//! The annotation parser: hand-written recursive descent over
//!
//! ```text
//! annotation = ws ( "none" | style { ws ";" ws [ style ] } ) ws EOF
//! style      = name ws [ "(" ws [ arg { ws "," ws [ arg ] } ] ws ")" ]
//! arg        = [ name ws ":" ws ] value
//! value      = number [ ws unit ]
//! ```
//!
//! Every error carries the byte offset (within the annotation text) of the
//! character that was unexpected and says what was expected there, so the
//! caller can point at the line and column in the SVG or style sheet.

use super::units::{Dimension, Quantity, Unit};
use super::{Braille, Brush, Declaration, Dot, Dots, Grating, Style, Vibrate};

/// What went wrong in an annotation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AnnotationErrorKind {
    /// The text does not follow the grammar.
    Syntax,
    /// A style name that taxel does not know.
    UnknownStyle,
    /// A parameter the style does not take.
    UnknownParameter,
    /// A value with a missing or wrong unit.
    Unit,
    /// A value outside the parameter's range.
    Range,
    /// The same parameter twice.
    Duplicate,
    /// Something taxel deliberately does not do (contracted braille).
    Unsupported,
}

impl AnnotationErrorKind {
    /// The stable diagnostic code (see `docs/diagnostics.md`).
    pub fn code(self) -> &'static str {
        match self {
            AnnotationErrorKind::Syntax => "T0101",
            AnnotationErrorKind::UnknownStyle => "T0102",
            AnnotationErrorKind::UnknownParameter => "T0103",
            AnnotationErrorKind::Unit => "T0104",
            AnnotationErrorKind::Range => "T0105",
            AnnotationErrorKind::Duplicate => "T0106",
            AnnotationErrorKind::Unsupported => "T0107",
        }
    }
}

/// A malformed annotation.
#[derive(Debug, Clone, PartialEq)]
pub struct AnnotationError {
    /// Byte offset, within the annotation text, of the offending character.
    pub offset: usize,
    /// What kind of problem.
    pub kind: AnnotationErrorKind,
    /// What was wrong and what was expected (lower-case, no trailing period).
    pub message: String,
    /// Advice, when there is some.
    pub help: Option<String>,
}

impl core::fmt::Display for AnnotationError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "at byte {}: {}", self.offset, self.message)
    }
}

impl std::error::Error for AnnotationError {}

/// The styles taxel knows, for messages.
const STYLE_NAMES: &str = "vibrate, grating, dots, dot, brush, braille or none";

/// Parses one annotation (`vibrate(width: 2mm); grating()`, `none`, ...).
pub fn parse(text: &str) -> Result<Declaration, AnnotationError> {
    let mut p = Parser { src: text, pos: 0 };
    p.ws();
    if p.at_end() {
        return Err(p.err(AnnotationErrorKind::Syntax, format!("expected a style ({STYLE_NAMES}), found nothing")));
    }
    let mut styles = Vec::new();
    loop {
        let start = p.pos;
        let name = p.ident("a style name")?;
        if name == "none" {
            p.ws();
            if !p.at_end() || !styles.is_empty() {
                return Err(AnnotationError {
                    offset: if styles.is_empty() { p.pos } else { start },
                    kind: AnnotationErrorKind::Syntax,
                    message: "`none` must stand alone".into(),
                    help: Some("write either `none` or a list of styles".into()),
                });
            }
            return Ok(Declaration::None);
        }
        p.ws();
        let args = if p.peek() == Some('(') { p.args()? } else { Vec::new() };
        styles.push(build(name, start, &args)?);
        p.ws();
        if p.at_end() {
            break;
        }
        if p.peek() != Some(';') {
            return Err(p.unexpected("`;` between styles, `(` or the end of the annotation"));
        }
        p.pos += 1;
        p.ws();
        if p.at_end() {
            break;
        }
    }
    Ok(Declaration::Styles(styles))
}

/// One argument: its name (absent for positional ones), value and offsets.
struct Arg<'a> {
    name: Option<(&'a str, usize)>,
    value: Quantity,
    at: usize,
}

struct Parser<'a> {
    src: &'a str,
    pos: usize,
}

impl<'a> Parser<'a> {
    fn peek(&self) -> Option<char> {
        self.src[self.pos..].chars().next()
    }

    fn at_end(&self) -> bool {
        self.pos >= self.src.len()
    }

    fn ws(&mut self) {
        while let Some(c) = self.peek().filter(|c| c.is_whitespace()) {
            self.pos += c.len_utf8();
        }
    }

    fn err(&self, kind: AnnotationErrorKind, message: String) -> AnnotationError {
        AnnotationError { offset: self.pos, kind, message, help: None }
    }

    fn unexpected(&self, expected: &str) -> AnnotationError {
        let found = match self.peek() {
            None => "the end of the annotation".to_string(),
            Some(c) => format!("`{c}`"),
        };
        self.err(AnnotationErrorKind::Syntax, format!("expected {expected}, found {found}"))
    }

    fn ident(&mut self, what: &str) -> Result<&'a str, AnnotationError> {
        let start = self.pos;
        match self.peek() {
            Some(c) if c.is_ascii_alphabetic() || c == '_' => {}
            _ => return Err(self.unexpected(what)),
        }
        while let Some(c) = self.peek().filter(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == '-') {
            self.pos += c.len_utf8();
        }
        Ok(&self.src[start..self.pos])
    }

    /// `( [arg {, [arg]}] )`, the opening parenthesis next.
    fn args(&mut self) -> Result<Vec<Arg<'a>>, AnnotationError> {
        self.pos += 1;
        let mut args = Vec::new();
        loop {
            self.ws();
            match self.peek() {
                Some(')') => {
                    self.pos += 1;
                    return Ok(args);
                }
                None => return Err(self.unexpected("a parameter or `)`")),
                _ => {}
            }
            let at = self.pos;
            let name = if self.peek().is_some_and(|c| c.is_ascii_alphabetic() || c == '_') {
                let n = self.ident("a parameter name")?;
                self.ws();
                if self.peek() != Some(':') {
                    return Err(self.unexpected(&format!("`:` after the parameter name `{n}`")));
                }
                self.pos += 1;
                self.ws();
                Some((n, at))
            } else {
                None
            };
            let value_at = self.pos;
            let value = self.quantity()?;
            args.push(Arg { name, value, at: value_at });
            self.ws();
            match self.peek() {
                Some(',') => self.pos += 1,
                Some(')') => {}
                _ => return Err(self.unexpected("`,` or `)`")),
            }
        }
    }

    fn quantity(&mut self) -> Result<Quantity, AnnotationError> {
        let start = self.pos;
        let b = self.src.as_bytes();
        let mut i = self.pos;
        if i < b.len() && (b[i] == b'+' || b[i] == b'-') {
            i += 1;
        }
        let digits = |mut i: usize| {
            while i < b.len() && b[i].is_ascii_digit() {
                i += 1;
            }
            i
        };
        let int_end = digits(i);
        let mut end = int_end;
        if end < b.len() && b[end] == b'.' {
            end = digits(end + 1);
        }
        if end == i || (end == i + 1 && b[i] == b'.') {
            return Err(self.unexpected("a number, such as 1.5mm"));
        }
        // An exponent only when digits follow, so `1e` reads as an unknown unit.
        if end < b.len() && (b[end] == b'e' || b[end] == b'E') {
            let mut j = end + 1;
            if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
                j += 1;
            }
            if j < b.len() && b[j].is_ascii_digit() {
                end = digits(j);
            }
        }
        let value: f64 = self.src[start..end]
            .parse()
            .map_err(|_| self.err(AnnotationErrorKind::Syntax, "expected a number".into()))?;
        if !value.is_finite() {
            return Err(self.err(AnnotationErrorKind::Range, "expected a finite number".into()));
        }
        self.pos = end;
        self.ws();
        let unit_at = self.pos;
        while let Some(c) = self.peek().filter(|c| c.is_ascii_alphabetic() || *c == '%') {
            self.pos += c.len_utf8();
        }
        let suffix = &self.src[unit_at..self.pos];
        if suffix.is_empty() {
            return Ok(Quantity { value, unit: None });
        }
        match Unit::from_suffix(suffix) {
            Some(u) => Ok(Quantity { value, unit: Some(u) }),
            None => Err(AnnotationError {
                offset: unit_at,
                kind: AnnotationErrorKind::Unit,
                message: format!("unknown unit `{suffix}`"),
                help: Some("units are mm, cm, in, pt, px, deg, rad, turn, Hz, kHz, ms, s and %".into()),
            }),
        }
    }
}

/// A parameter a style takes: name, dimension and the open/closed range it must lie in.
struct Param {
    name: &'static str,
    dim: Dimension,
    min: f64,
    min_inclusive: bool,
    max: f64,
}

const fn p(name: &'static str, dim: Dimension, min: f64, min_inclusive: bool, max: f64) -> Param {
    Param { name, dim, min, min_inclusive, max }
}

const AMP: Param = p("amplitude", Dimension::Ratio, 0.0, true, 1.0);
/// `soft`: the width of the edge profile's ramp (0, the default, is a hard
/// edge); at most the format's limit of 16 mm.
const SOFT: Param = p("soft", Dimension::Length, 0.0, true, 16.0);
const VIBRATE: &[Param] = &[
    p("width", Dimension::Length, 0.0, false, 1000.0),
    p("freq", Dimension::Frequency, 0.0, false, 100_000.0),
    AMP,
    SOFT,
];
const GRATING: &[Param] = &[
    p("wavelength", Dimension::Length, 0.0, false, 1000.0),
    p("angle", Dimension::Angle, -360.0, true, 360.0),
    AMP,
    SOFT,
];
const DOTS: &[Param] =
    &[p("radius", Dimension::Length, 0.0, false, 100.0), p("spacing", Dimension::Length, 0.0, false, 1000.0), AMP];
const DOT: &[Param] = &[p("radius", Dimension::Length, 0.0, false, 100.0), AMP];
const BRUSH: &[Param] = &[
    p("duration", Dimension::Time, 0.0, false, 3_600_000.0),
    p("intensity", Dimension::Ratio, 0.0, true, 1.0),
    p("freq", Dimension::Frequency, 0.0, false, 100_000.0),
    p("start", Dimension::Time, 0.0, true, 86_400_000.0),
];
const BRAILLE: &[Param] =
    &[p("radius", Dimension::Length, 0.0, false, 5.0), AMP, p("grade", Dimension::Count, 1.0, true, 2.0)];

/// Checks the arguments against the style's parameters and fills in defaults.
fn build(name: &str, at: usize, args: &[Arg<'_>]) -> Result<Style, AnnotationError> {
    let params = match name {
        "vibrate" => VIBRATE,
        "grating" => GRATING,
        "dots" => DOTS,
        "dot" => DOT,
        "brush" => BRUSH,
        "braille" => BRAILLE,
        _ => {
            return Err(AnnotationError {
                offset: at,
                kind: AnnotationErrorKind::UnknownStyle,
                message: format!("unknown style `{name}`, expected {STYLE_NAMES}"),
                help: Some("see docs/annotations.md for every style and its parameters".into()),
            });
        }
    };
    let names = params.iter().map(|p| p.name).collect::<Vec<_>>().join(", ");
    let mut values: Vec<Option<f64>> = vec![None; params.len()];
    let mut positional = 0usize;
    let mut seen_named = false;
    for a in args {
        let index = match a.name {
            Some((n, n_at)) => {
                seen_named = true;
                params.iter().position(|p| p.name == n).ok_or_else(|| AnnotationError {
                    offset: n_at,
                    kind: AnnotationErrorKind::UnknownParameter,
                    message: format!("`{name}` has no parameter `{n}`, expected one of {names}"),
                    help: None,
                })?
            }
            None => {
                if seen_named || positional >= params.len() {
                    return Err(AnnotationError {
                        offset: a.at,
                        kind: AnnotationErrorKind::Syntax,
                        message: format!("expected a named parameter ({names}) here, found a bare value"),
                        help: Some(format!("unnamed values are taken in the order {names}, before any named one")),
                    });
                }
                positional += 1;
                positional - 1
            }
        };
        let spec = &params[index];
        if values[index].is_some() {
            return Err(AnnotationError {
                offset: a.name.map_or(a.at, |(_, o)| o),
                kind: AnnotationErrorKind::Duplicate,
                message: format!("parameter `{}` is given twice", spec.name),
                help: None,
            });
        }
        let v = a.value.to(spec.dim).ok_or_else(|| AnnotationError {
            offset: a.at,
            kind: AnnotationErrorKind::Unit,
            message: format!("`{}` of `{name}` expects {}", spec.name, spec.dim.expected()),
            help: None,
        })?;
        let low_ok = if spec.min_inclusive { v >= spec.min } else { v > spec.min };
        if !low_ok || v > spec.max || (spec.dim == Dimension::Count && v.fract() != 0.0) {
            let low = if spec.min_inclusive { "from" } else { "above" };
            return Err(AnnotationError {
                offset: a.at,
                kind: AnnotationErrorKind::Range,
                message: format!(
                    "`{}` of `{name}` is {v}, expected a value {low} {} up to {}",
                    spec.name, spec.min, spec.max
                ),
                help: None,
            });
        }
        values[index] = Some(v);
    }
    let get = |i: usize, default: f64| values[i].unwrap_or(default);
    Ok(match name {
        "vibrate" => Style::Vibrate(Vibrate {
            width_mm: get(0, 1.5),
            freq_hz: get(1, 50.0),
            amplitude: get(2, 1.0),
            soft_mm: get(3, 0.0),
        }),
        "grating" => Style::Grating(Grating {
            wavelength_mm: get(0, 2.0),
            angle_deg: get(1, 90.0),
            amplitude: get(2, 1.0),
            soft_mm: get(3, 0.0),
        }),
        "dots" => Style::Dots(Dots { radius_mm: get(0, 1.0), spacing_mm: values[1], amplitude: get(2, 1.0) }),
        "dot" => Style::Dot(Dot { radius_mm: get(0, 1.0), amplitude: get(1, 1.0) }),
        "brush" => Style::Brush(Brush {
            duration_ms: get(0, 1000.0),
            intensity: get(1, 1.0),
            freq_hz: get(2, 200.0),
            start_ms: values[3],
        }),
        // (A grade is a whole 1 or 2: checked with the parameter's range.)
        _ => Style::Braille(Braille {
            radius_mm: get(0, 0.72),
            amplitude: get(1, 1.0),
            grade: values[2].map(|g| g as u8),
        }),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn styles(s: &str) -> Vec<Style> {
        match parse(s) {
            Ok(Declaration::Styles(v)) => v,
            other => panic!("{s:?}: {other:?}"),
        }
    }

    #[test]
    fn defaults_come_from_the_papers() {
        assert_eq!(
            styles("vibrate()"),
            vec![Style::Vibrate(Vibrate { width_mm: 1.5, freq_hz: 50.0, amplitude: 1.0, soft_mm: 0.0 })]
        );
        assert_eq!(
            styles("grating"),
            vec![Style::Grating(Grating { wavelength_mm: 2.0, angle_deg: 90.0, amplitude: 1.0, soft_mm: 0.0 })]
        );
        assert_eq!(styles("dots()"), vec![Style::Dots(Dots { radius_mm: 1.0, spacing_mm: None, amplitude: 1.0 })]);
        assert_eq!(styles("braille()"), vec![Style::Braille(Braille { radius_mm: 0.72, amplitude: 1.0, grade: None })]);
    }

    #[test]
    fn units_convert_and_several_styles_split_on_semicolons() {
        let s = styles(" vibrate( width : 0.2cm , freq: 0.1kHz, amplitude: 50% ) ;grating(6mm, 0.5turn);");
        assert_eq!(s[0], Style::Vibrate(Vibrate { width_mm: 2.0, freq_hz: 100.0, amplitude: 0.5, soft_mm: 0.0 }));
        assert_eq!(
            s[1],
            Style::Grating(Grating { wavelength_mm: 6.0, angle_deg: 180.0, amplitude: 1.0, soft_mm: 0.0 })
        );
        let soft = styles("vibrate(soft: 0.3mm); grating(6mm, 0deg, 1, 0.5mm)");
        assert!(matches!(soft[0], Style::Vibrate(v) if v.soft_mm == 0.3 && v.width_mm == 1.5));
        assert!(matches!(soft[1], Style::Grating(g) if g.soft_mm == 0.5 && g.wavelength_mm == 6.0));
        assert!(parse("vibrate(soft: 20mm)").is_err(), "soft is at most 16 mm");
        let b = styles("brush(duration: 1.5s, start: 200ms)");
        assert_eq!(
            b[0],
            Style::Brush(Brush { duration_ms: 1500.0, intensity: 1.0, freq_hz: 200.0, start_ms: Some(200.0) })
        );
    }

    #[test]
    fn errors_point_at_the_offending_character() {
        let e = parse("vibrate(width 2mm)").unwrap_err();
        assert_eq!((e.offset, e.kind), (14, AnnotationErrorKind::Syntax));
        assert!(e.message.contains("expected `:`"), "{}", e.message);
        let e = parse("vibrate(width: 2)").unwrap_err();
        assert_eq!((e.offset, e.kind), (15, AnnotationErrorKind::Unit));
        let e = parse("wobble()").unwrap_err();
        assert_eq!((e.offset, e.kind), (0, AnnotationErrorKind::UnknownStyle));
        let e = parse("grating(colour: 2mm)").unwrap_err();
        assert_eq!((e.offset, e.kind), (8, AnnotationErrorKind::UnknownParameter));
        let e = parse("grating(wavelength: 2furlong)").unwrap_err();
        assert_eq!((e.offset, e.kind), (21, AnnotationErrorKind::Unit));
        let e = parse("vibrate(amplitude: 2)").unwrap_err();
        assert_eq!(e.kind, AnnotationErrorKind::Range);
        let e = parse("dot(radius: 1mm, radius: 2mm)").unwrap_err();
        assert_eq!((e.offset, e.kind), (17, AnnotationErrorKind::Duplicate));
        assert_eq!(
            styles("braille(grade: 2)"),
            vec![Style::Braille(Braille { radius_mm: 0.72, amplitude: 1.0, grade: Some(2) })]
        );
        assert_eq!(parse("braille(grade: 3)").unwrap_err().kind, AnnotationErrorKind::Range);
        assert_eq!(parse("braille(grade: 1.5)").unwrap_err().kind, AnnotationErrorKind::Range);
        let e = parse("vibrate() grating()").unwrap_err();
        assert_eq!(e.offset, 10);
        let e = parse("none; vibrate()").unwrap_err();
        assert_eq!(e.kind, AnnotationErrorKind::Syntax);
        assert!(parse("").is_err());
        assert!(parse("vibrate(").is_err());
        assert!(parse("vibrate(1e999mm)").is_err());
        assert!(parse("vibrate(;;)").is_err());
    }
}
