//! Style sheets: TOML files that map ids, classes, layers and colours to
//! tactile styles, for drawings that were never annotated for taxel.
//!
//! ```toml
//! [[rule]]
//! fill = "#ff0000"             # any SVG colour: "#f00", "red", "rgb(255,0,0)"
//! tactile = "grating(wavelength: 2mm, angle: 0deg)"
//!
//! [[rule]]
//! class = "road"
//! layer = "Transport"          # inside the layer labelled "Transport"
//! tactile = "vibrate(width: 2mm)"
//! ```
//!
//! A sheet may also name the liblouis table all braille is written in,
//! before its rules: `braille-table = "fr-bfu-g2.ctb"`.
//!
//! A rule applies to an element when every selector it gives matches. When
//! several rules apply, the most specific wins (`id` 100, `class` 10, `layer`,
//! `fill` and `stroke` 1 each, summed); among equally specific rules the later one wins.
//!
//! ```
//! use taxel_compiler::annotation::sheet::{ElementFacts, StyleSheet};
//!
//! let sheet = StyleSheet::parse("[[rule]]\nfill = \"red\"\ntactile = \"grating()\"\n", "s.toml").unwrap();
//! let facts = ElementFacts { fill: Some([255, 0, 0]), ..Default::default() };
//! assert!(sheet.lookup(&facts).is_some());
//! ```

use serde::Deserialize;
use toml::Spanned;

use crate::annotation::{self, Declaration};
use crate::text_pos::line_col;

/// A parsed style sheet.
#[derive(Debug, Clone, PartialEq)]
pub struct StyleSheet {
    /// The file it came from, for messages.
    pub source_name: String,
    /// The rules, in file order.
    pub rules: Vec<Rule>,
    /// The liblouis table every text's braille is written in (the key
    /// `braille-table = "fr-bfu-g2.ctb"`, before the rules), whatever its
    /// language; `None`: each text's language chooses.
    pub braille_table: Option<String>,
}

/// One rule: what it selects and the styles it gives.
#[derive(Debug, Clone, PartialEq)]
pub struct Rule {
    /// The selectors; all that are present must match.
    pub selector: Selector,
    /// The styles (or `none`).
    pub declaration: Declaration,
    /// 1-based line of the rule's `tactile` key in the style sheet.
    pub line: u32,
}

/// What a rule selects.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Selector {
    /// The element's `id`.
    pub id: Option<String>,
    /// One of the element's classes (its `class` attribute, split on whitespace).
    pub class: Option<String>,
    /// The `inkscape:label` of the layer the element is in (or is).
    pub layer: Option<String>,
    /// The element's resolved fill colour (RGB).
    pub fill: Option<[u8; 3]>,
    /// The element's resolved stroke colour (RGB).
    pub stroke: Option<[u8; 3]>,
}

impl Selector {
    /// CSS-like specificity: id 100, class 10, layer, fill and stroke 1 each.
    pub fn specificity(&self) -> u32 {
        100 * self.id.is_some() as u32
            + 10 * self.class.is_some() as u32
            + self.layer.is_some() as u32
            + self.fill.is_some() as u32
            + self.stroke.is_some() as u32
    }

    /// Whether every selector present matches `e`.
    pub fn matches(&self, e: &ElementFacts<'_>) -> bool {
        self.id.as_deref().is_none_or(|id| e.id == id)
            && self.class.as_deref().is_none_or(|c| e.classes.split_whitespace().any(|x| x == c))
            && self.layer.as_deref().is_none_or(|l| e.layers.iter().any(|x| x.trim() == l.trim()))
            && self.fill.is_none_or(|c| e.fill == Some(c))
            && self.stroke.is_none_or(|c| e.stroke == Some(c))
    }
}

/// What a style sheet can see of an element.
#[derive(Debug, Clone, Default)]
pub struct ElementFacts<'a> {
    /// The element's id (empty when it has none).
    pub id: &'a str,
    /// Its `class` attribute.
    pub classes: &'a str,
    /// Labels of the Inkscape layers that contain it (itself included).
    pub layers: &'a [String],
    /// Its resolved fill colour, when it is filled with a plain colour.
    pub fill: Option<[u8; 3]>,
    /// Its resolved stroke colour, when it is stroked with a plain colour.
    pub stroke: Option<[u8; 3]>,
}

/// Why a style sheet was refused: file, line, column and what was expected.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StyleError {
    /// The style sheet's file name.
    pub source_name: String,
    /// 1-based line (0 when unknown).
    pub line: u32,
    /// 1-based column (0 when unknown).
    pub column: u32,
    /// What was wrong and what was expected.
    pub message: String,
}

impl core::fmt::Display for StyleError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if self.line > 0 {
            write!(f, "{}:{}:{}: {}", self.source_name, self.line, self.column, self.message)
        } else {
            write!(f, "{}: {}", self.source_name, self.message)
        }
    }
}

impl std::error::Error for StyleError {}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    version: Option<Spanned<i64>>,
    #[serde(rename = "braille-table")]
    braille_table: Option<Spanned<String>>,
    #[serde(default)]
    rule: Vec<RawRule>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRule {
    id: Option<String>,
    class: Option<String>,
    layer: Option<String>,
    fill: Option<Spanned<String>>,
    stroke: Option<Spanned<String>>,
    tactile: Spanned<String>,
}

/// Parses an SVG colour (`#f00`, `#ff0000`, `red`, `rgb(255, 0, 0)`) to RGB.
pub fn parse_colour(s: &str) -> Option<[u8; 3]> {
    let c: svgtypes::Color = s.trim().parse().ok()?;
    Some([c.red, c.green, c.blue])
}

impl StyleSheet {
    /// Parses a style sheet. `source_name` (the file name) goes into every error.
    pub fn parse(text: &str, source_name: &str) -> Result<StyleSheet, StyleError> {
        let err_at = |offset: Option<usize>, message: String| {
            let (line, column) = offset.map_or((0, 0), |o| line_col(text, o));
            StyleError { source_name: source_name.into(), line, column, message }
        };
        let file: File = toml::from_str(text).map_err(|e| {
            let msg = e.message().trim_end().replace('\n', " ");
            err_at(e.span().map(|s| s.start), msg)
        })?;
        if let Some(v) = &file.version
            && *v.get_ref() != 1
        {
            return Err(err_at(
                Some(v.span().start),
                format!("unknown style sheet version {}, expected 1", v.get_ref()),
            ));
        }
        if let Some(t) = &file.braille_table {
            let name = t.get_ref();
            if name.trim().is_empty() || name.contains('\0') || name.len() > 1024 {
                return Err(err_at(
                    Some(t.span().start),
                    "`braille-table` names a liblouis table list, such as \"fr-bfu-g2.ctb\"".into(),
                ));
            }
        }
        let braille_table = file.braille_table.map(|t| t.into_inner().trim().to_string());
        let mut rules = Vec::with_capacity(file.rule.len());
        for r in file.rule {
            let colour = |c: &Option<Spanned<String>>, key: &str| -> Result<Option<[u8; 3]>, StyleError> {
                match c {
                    None => Ok(None),
                    Some(s) => parse_colour(s.get_ref()).map(Some).ok_or_else(|| {
                        err_at(
                            Some(s.span().start),
                            format!(
                                "`{key}` is {:?}, expected an SVG colour such as \"#ff0000\" or \"red\"",
                                s.get_ref()
                            ),
                        )
                    }),
                }
            };
            let selector = Selector {
                id: r.id,
                class: r.class,
                layer: r.layer,
                fill: colour(&r.fill, "fill")?,
                stroke: colour(&r.stroke, "stroke")?,
            };
            let span = r.tactile.span();
            if selector.specificity() == 0 {
                return Err(err_at(
                    Some(span.start),
                    "a rule needs at least one selector: id, class, layer, fill or stroke".into(),
                ));
            }
            let declaration = annotation::parse(r.tactile.get_ref()).map_err(|e| {
                err_at(Some(value_offset(text, span.clone(), r.tactile.get_ref(), e.offset)), e.message)
            })?;
            rules.push(Rule { selector, declaration, line: line_col(text, span.start).0 });
        }
        Ok(StyleSheet { source_name: source_name.into(), rules, braille_table })
    }

    /// The rule that applies to `e`, if any: the most specific, the later on ties.
    pub fn lookup(&self, e: &ElementFacts<'_>) -> Option<&Rule> {
        let mut best: Option<&Rule> = None;
        for r in &self.rules {
            if r.selector.matches(e) && best.is_none_or(|b| r.selector.specificity() >= b.selector.specificity()) {
                best = Some(r);
            }
        }
        best
    }

    /// Whether any rule looks at colours (so the compiler must resolve them).
    pub fn uses_colours(&self) -> bool {
        self.rules.iter().any(|r| r.selector.fill.is_some() || r.selector.stroke.is_some())
    }
}

/// The source offset of byte `offset` of a TOML string value whose token spans
/// `span`: exact when the string has no escapes, else the token's start.
fn value_offset(text: &str, span: core::ops::Range<usize>, value: &str, offset: usize) -> usize {
    let raw = text.get(span.clone()).unwrap_or("");
    let quotes = raw.chars().take_while(|&c| c == '"' || c == '\'').count().min(3);
    let quotes = if quotes == 2 { 1 } else { quotes };
    match raw.get(quotes..quotes + value.len()) {
        Some(inner) if inner == value => span.start + quotes + offset,
        _ => span.start,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn most_specific_rule_wins_and_later_breaks_ties() {
        let text = r##"
[[rule]]
fill = "#f00"
tactile = "grating(wavelength: 2mm)"

[[rule]]
class = "lake"
tactile = "grating(wavelength: 6mm)"

[[rule]]
fill = "red"
tactile = "grating(wavelength: 4mm)"
"##;
        let s = StyleSheet::parse(text, "s.toml").unwrap();
        let red = ElementFacts { fill: Some([255, 0, 0]), ..Default::default() };
        assert_eq!(s.lookup(&red).unwrap().line, 12);
        let lake = ElementFacts { fill: Some([255, 0, 0]), classes: "water lake", ..Default::default() };
        assert_eq!(s.lookup(&lake).unwrap().line, 8);
        assert!(s.lookup(&ElementFacts::default()).is_none());
    }

    #[test]
    fn a_sheet_names_the_braille_table() {
        let s = StyleSheet::parse(
            "braille-table = \"fr-bfu-g2.ctb\"\n[[rule]]\nid = \"a\"\ntactile = \"braille()\"\n",
            "s.toml",
        )
        .unwrap();
        assert_eq!(s.braille_table.as_deref(), Some("fr-bfu-g2.ctb"));
        assert_eq!(StyleSheet::parse("", "s.toml").unwrap().braille_table, None);
        let e = StyleSheet::parse("braille-table = \" \"\n", "s.toml").unwrap_err();
        assert_eq!(e.line, 1, "{e}");
        assert!(e.message.contains("liblouis"), "{e}");
    }

    #[test]
    fn errors_name_file_line_and_column() {
        let e = StyleSheet::parse("[[rule]]\nid = \"a\"\ntactile = \"vibrate(width 2mm)\"\n", "s.toml").unwrap_err();
        // `tactile = "` is 11 characters; the offending `2` is byte 14 of the value.
        assert_eq!((e.line, e.column), (3, 12 + 14), "{e}");
        assert!(e.to_string().starts_with("s.toml:3:"), "{e}");
        let e = StyleSheet::parse("[[rule]]\nfill = \"#zz\"\ntactile = \"none\"\n", "s.toml").unwrap_err();
        assert_eq!(e.line, 2);
        let e = StyleSheet::parse("[[rule]]\ntactile = \"none\"\n", "s.toml").unwrap_err();
        assert!(e.message.contains("selector"));
        let e = StyleSheet::parse("[[rule]]\nid = \"a\"\ncolour = 3\ntactile = \"none\"\n", "s.toml").unwrap_err();
        assert_eq!(e.line, 3, "{e}");
        assert!(StyleSheet::parse("[[rule]\n", "s.toml").is_err());
    }
}
