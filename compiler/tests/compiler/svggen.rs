//! Hostile inputs made from bytes: annotated SVG drawings, annotations and
//! style sheets. The same bytes always give the same text, so a fuzzer's
//! corpus and a property test's shrunk case are both plain byte strings.
//! Shared by the compiler's property tests (`fuzzed.rs`) and the cargo-fuzz
//! targets in `fuzz/` (which include this file by path), so it uses only std.
//!
//! The drawings have what broke the front end before and what a person's
//! editor can produce: non-ASCII Inkscape layer labels (`Calque élévation`,
//! `レイヤー 1`), `<!ENTITY>` expansions as elements and in attributes, deep
//! nesting, huge and non-finite numbers, and empty, missing, self- and
//! ancestor-referencing `<use>`.

#![allow(dead_code)]

use std::fmt::Write as _;

/// Reads choices from bytes; past the end every choice is the first one.
pub struct Choices<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Choices<'a> {
    /// Choices from `bytes`.
    pub fn new(bytes: &'a [u8]) -> Self {
        Choices { bytes, pos: 0 }
    }

    /// The next byte (0 when exhausted).
    pub fn byte(&mut self) -> u8 {
        let b = self.bytes.get(self.pos).copied().unwrap_or(0);
        self.pos += 1;
        b
    }

    /// Whether any byte is left.
    pub fn more(&self) -> bool {
        self.pos < self.bytes.len()
    }

    /// A number below `n` (`n` > 0).
    pub fn below(&mut self, n: usize) -> usize {
        self.byte() as usize % n.max(1)
    }

    /// One of `items`.
    pub fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[self.below(items.len())]
    }
}

/// Numbers as an SVG or annotation may write them, ordinary and hostile.
pub const NUMBERS: &[&str] = &[
    "10",
    "30",
    "5.5",
    "0",
    "-3",
    "1e308",
    "-1e308",
    "1e-320",
    "NaN",
    "inf",
    "-inf",
    "3e38",
    "1e39",
    "",
    "1e",
    "0x10",
    "99999999999999999999",
    "-0",
    ".5",
    "2.",
    "1e-5",
];

/// Layer labels: plain, non-ASCII, annotated in any case, broken.
pub const LABELS: &[&str] = &[
    "Layer 1",
    "Calque élévation",
    "レイヤー 1",
    "Ebene ü",
    "tactile: vibrate()",
    "TACTILE: Grating(wavelength: 2mm)",
    "Tactile: dots(radius: 1mm)",
    "tactile:",
    "tactile: none",
    "Ünïcödé tactile: vibrate(width: 1e308mm)",
    "💥 tactile: braille()",
    "tactile: dot(radius: NaNmm)",
    "",
    "&lbl;",
    "tactile: brush()",
];

/// Labels that annotate well or not at all, in several scripts.
pub const GOOD_LABELS: &[&str] = &[
    "Layer 1",
    "Calque élévation",
    "レイヤー 1",
    "tactile: vibrate()",
    "Tactile: dots(radius: 1mm)",
    "TACTILE: grating()",
];

const STYLE_WORDS: &[&str] = &["vibrate", "grating", "dots", "dot", "braille", "brush", "none", "Vibrate", "x", "é"];
const ARG_NAMES: &[&str] =
    &["width", "freq", "amplitude", "wavelength", "angle", "radius", "spacing", "grade", "speed", "", "wïdth"];
const UNITS: &[&str] = &["mm", "cm", "in", "pt", "px", "deg", "rad", "Hz", "kHz", "%", "s", "ms", "", "mmm", "é"];

/// Well-formed annotations with ordinary values, so that drawings reach the layer builders.
const GOOD_ANNOTATIONS: &[&str] = &[
    "vibrate()",
    "vibrate(width: 1.5mm)",
    "vibrate(width: 2mm, freq: 50Hz, amplitude: 0.5)",
    "grating()",
    "grating(wavelength: 3mm, angle: 30deg)",
    "dots(radius: 1mm, spacing: 4mm)",
    "dot(radius: 1.5mm)",
    "vibrate(); grating(wavelength: 6mm, angle: 0deg)",
    "none",
];

/// An annotation: seven in eight well formed, the rest with hostile numbers,
/// units and punctuation (one malformed annotation refuses the whole drawing,
/// so most must be good for the drawings to reach the layer builders).
pub fn annotation(c: &mut Choices<'_>) -> String {
    if c.below(8) != 0 {
        return c.pick(GOOD_ANNOTATIONS).to_string();
    }
    let mut s = String::new();
    let styles = 1 + c.below(3);
    for i in 0..styles {
        if i > 0 {
            s.push_str(c.pick(&["; ", ";", " ; ", ",", ""]));
        }
        s.push_str(c.pick(STYLE_WORDS));
        if c.below(5) == 0 {
            continue;
        }
        s.push('(');
        let args = c.below(4);
        for k in 0..args {
            if k > 0 {
                s.push_str(c.pick(&[", ", ",", " ", ";"]));
            }
            s.push_str(c.pick(ARG_NAMES));
            s.push_str(c.pick(&[": ", ":", " ", "::"]));
            s.push_str(c.pick(NUMBERS));
            s.push_str(c.pick(UNITS));
        }
        if c.below(8) != 0 {
            s.push(')');
        }
    }
    if c.below(10) == 0 {
        // A raw byte run: anything at all.
        let n = c.below(12);
        let raw: Vec<u8> = (0..n).map(|_| c.byte()).collect();
        s.push_str(&String::from_utf8_lossy(&raw));
    }
    s
}

/// Escapes text for an XML attribute value.
pub fn attr(s: &str) -> String {
    s.replace('&', "&amp;").replace('"', "&quot;").replace('<', "&lt;")
}

/// A style sheet in TOML: rules with selectors and annotations, some broken.
pub fn style_sheet(c: &mut Choices<'_>) -> String {
    let mut s = String::new();
    if c.below(3) == 0 {
        let _ = writeln!(s, "version = {}", c.pick(&["1", "2", "0", "\"1\"", "1e308"]));
    }
    let rules = c.below(5);
    for _ in 0..rules {
        s.push_str(c.pick(&["[[rule]]\n", "[rule]\n", "[[rules]]\n", "[[rule]]\n"]));
        let keys = c.below(5);
        for _ in 0..keys {
            let key = c.pick(&["id", "class", "layer", "fill", "stroke", "tactile", "colour", "id"]);
            let value = match key {
                "tactile" => format!("\"{}\"", annotation(c).replace('\\', "\\\\").replace('"', "\\\"")),
                "fill" | "stroke" => {
                    format!("\"{}\"", c.pick(&["#f00", "red", "rgb(255,0,0)", "#ff000", "none", "url(#g)", "é"]))
                }
                "layer" => format!("\"{}\"", c.pick(LABELS).replace('"', "\\\"")),
                _ => c.pick(&["\"a\"", "\"\"", "3", "\"レイヤー\"", "[1]", "{ x = 1 }"]).to_string(),
            };
            let _ = writeln!(s, "{key} = {value}");
        }
    }
    if c.below(8) == 0 {
        s.push_str(c.pick(&["= oops", "[[rule]", "tactile = \"unterminated", "\u{0}"]));
    }
    s
}

/// The drawing a fuzz input stands for: the input itself where it is an
/// SVG document (it begins with `<svg` or `<?xml`, as a seed written from
/// a drawing generator does: `cargo run --example fuzz_seeds`), else the
/// drawing [`svg`] generates from its bytes.
pub fn drawing(bytes: &[u8]) -> String {
    let raw = bytes.starts_with(b"<svg") || bytes.starts_with(b"<?xml");
    match std::str::from_utf8(bytes) {
        Ok(text) if raw => text.to_string(),
        _ => svg(&mut Choices::new(bytes)),
    }
}

/// A whole annotated SVG drawing.
pub fn svg(c: &mut Choices<'_>) -> String {
    let mut s = String::new();
    let entities = c.below(3) == 0;
    if entities {
        s.push_str("<?xml version=\"1.0\"?>\n<!DOCTYPE svg [\n");
        s.push_str("  <!ENTITY shape \"<rect x='5' y='5' width='20' height='20' data-tactile='vibrate()'/>\">\n");
        let _ = writeln!(s, "  <!ENTITY lbl \"{}\">", attr(c.pick(LABELS)).replace('&', ""));
        let _ = writeln!(s, "  <!ENTITY ann \"{}\">", attr(&annotation(c)).replace('&', ""));
        s.push_str(
            "  <!ENTITY layer \"<g inkscape:groupmode='layer' inkscape:label='Calque élévation'>&shape;</g>\">\n",
        );
        s.push_str("]>\n");
    }
    let (w, h) = match c.below(6) {
        0 => (c.pick(NUMBERS).to_string(), c.pick(NUMBERS).to_string()),
        1 => ("100%".to_string(), "auto".to_string()),
        _ => ("100mm".to_string(), "60mm".to_string()),
    };
    let view_box = match c.below(5) {
        0 => format!("{} {} {} {}", c.pick(NUMBERS), c.pick(NUMBERS), c.pick(NUMBERS), c.pick(NUMBERS)),
        1 => String::new(),
        _ => "0 0 100 60".to_string(),
    };
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" width="{}" height="{}" viewBox="{}">"#,
        attr(&w),
        attr(&h),
        attr(&view_box)
    );
    let mut ids = 0usize;
    let mut budget = 16usize;
    while c.more() && budget > 0 {
        element(c, &mut s, entities, &mut ids, &mut budget);
    }
    s.push_str("</svg>\n");
    s
}

/// One element and its children, at most `budget` elements in all.
fn element(c: &mut Choices<'_>, s: &mut String, entities: bool, ids: &mut usize, budget: &mut usize) {
    if *budget == 0 {
        return;
    }
    *budget -= 1;
    let id = *ids;
    *ids += 1;
    let tactile = if c.below(3) == 0 {
        let a = if entities && c.below(4) == 0 { "&ann;".to_string() } else { attr(&annotation(c)) };
        format!(r#" data-tactile="{a}""#)
    } else {
        String::new()
    };
    let n = |c: &mut Choices<'_>| attr(c.pick(NUMBERS));
    match c.below(12) {
        0 | 1 => {
            let label = if entities && c.below(3) == 0 {
                "&lbl;".to_string()
            } else if c.below(4) == 0 {
                attr(c.pick(LABELS))
            } else {
                attr(c.pick(GOOD_LABELS))
            };
            let _ = write!(s, r#"<g id="e{id}" inkscape:groupmode="layer" inkscape:label="{label}"{tactile}>"#);
            let children = c.below(4);
            for _ in 0..children {
                element(c, s, entities, ids, budget);
            }
            s.push_str("</g>\n");
        }
        2 => {
            // Deep nesting: a tower of groups around one shape.
            let levels = 1 + c.below(4) * 100;
            let _ = write!(s, "{}", "<g>".repeat(levels));
            let _ = write!(s, r#"<rect width="30" height="20"{tactile}/>"#);
            let _ = write!(s, "{}", "</g>".repeat(levels));
            s.push('\n');
        }
        3 => {
            let _ = writeln!(
                s,
                r#"<rect id="e{id}" x="{}" y="{}" width="{}" height="{}"{tactile}/>"#,
                n(c),
                n(c),
                n(c),
                n(c)
            );
        }
        4 => {
            let _ = writeln!(s, r#"<circle id="e{id}" cx="{}" cy="{}" r="{}"{tactile}/>"#, n(c), n(c), n(c));
        }
        5 => {
            let _ = writeln!(
                s,
                r#"<path id="e{id}" d="M {} {} L {} {} C {} {} {} {} {} {} Z" fill="none" stroke="black"{tactile}/>"#,
                n(c),
                n(c),
                n(c),
                n(c),
                n(c),
                n(c),
                n(c),
                n(c),
                n(c),
                n(c)
            );
        }
        6 => {
            let text = c.pick(&["Ashby", "", "Calque élévation", "レイヤー", "⠁⠃", "&amp;", "a\u{301}"]);
            let _ = writeln!(s, r#"<text id="e{id}" x="{}" y="{}"{tactile}>{text}</text>"#, n(c), n(c));
        }
        7 => {
            // Every kind of <use>: empty, missing, self, an earlier element or an ancestor.
            let target = match c.below(5) {
                0 => String::new(),
                1 => "#missing".to_string(),
                2 => format!("#e{id}"),
                _ => format!("#e{}", c.below(id + 1)),
            };
            let attr_name = c.pick(&["href", "xlink:href"]);
            let _ = writeln!(s, r#"<use id="e{id}" {attr_name}="{target}" x="{}"{tactile}/>"#, n(c));
        }
        8 if entities => s.push_str(c.pick(&["&shape;\n", "&layer;\n"])),
        9 => {
            let _ = writeln!(
                s,
                r#"<rect id="e{id}" width="20" height="20" transform="{}"{tactile}/>"#,
                c.pick(&[
                    "scale(0)",
                    "scale(1e308)",
                    "rotate(NaN)",
                    "matrix(1 0 0 1 1e308 0)",
                    "translate(10 10)",
                    "skewX(90)"
                ])
            );
        }
        10 => {
            let _ = writeln!(
                s,
                r#"<polyline id="e{id}" points="{} {} {} {} {} {}" stroke="red" fill="none"{tactile}/>"#,
                n(c),
                n(c),
                n(c),
                n(c),
                n(c),
                n(c)
            );
        }
        _ => {
            let _ = writeln!(
                s,
                r#"<rect id="e{id}" class="{}" x="10" y="10" width="30" height="20" fill="{}"{tactile}/>"#,
                c.pick(&["town", "", "a b", "é"]),
                c.pick(&["red", "#e41a1c", "none", "url(#nope)"])
            );
        }
    }
}
