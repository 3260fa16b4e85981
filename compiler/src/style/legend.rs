//! The key of a drawing: each texture, line style and point symbol a reader
//! must tell apart, with its meaning, the key codes (T0326), and the texts
//! the graphic has no room for (T0323), which the key lists instead.
//!
//! A public stage derived from the resolved styles, so that every back end
//! (paper's key page, the pin displays' key page, the provenance a host
//! speaks, `taxel inspect`, the preview) writes the same key. It is in the
//! manner of BANA's *Guidelines and Standards for Tactile Graphics* (2010),
//! which ask for a key whenever symbols, lines or textures are used that
//! are not explained on the graphic itself, each shown "as it appears on the
//! graphic" beside its meaning, and which limit a graphic to about five of
//! each kind.
//!
//! **Entries.** One per distinct texture (a grating's wavelength and angle),
//! vibrating line style (its width and frequency), dotted line (radius and
//! spacing), point symbol (a dot's radius) and brushed stroke (its duration
//! and frequency): the same identities the back ends give one texture, line
//! style or symbol each, in order of first use.
//!
//! **Meaning**, the first that names it ([`Source`]): the text of the
//! drawing's own legend (a small swatch of the style with a text just to its
//! right on its line, as matplotlib, Vega-Lite and map legends draw them,
//! accepted when two or more such pairs line up in a column or a row); else
//! the label (`<title>`, `aria-label`, `inkscape:label`) all its elements
//! share; else the innermost Inkscape layer they share; else a class they
//! share; else the nearest basic colour name of their fill (of their stroke
//! for lines: "red areas", "blue lines"); else an ordinal ("texture 2"). A
//! meaning that two entries of the key would share (a legend text, label,
//! layer, class or colour; of one kind or two, as a region's texture and its
//! outline both titled "Lake") tells neither apart, so those entries take
//! their next meaning, and every meaning in the key is its own.
//!
//! **When** ([`Legend::needed`]): when the drawing has key codes or texts
//! with no room on the graphic, or a kind
//! (textures, line styles, point symbols with dotted lines, brushed strokes)
//! has two or more entries a reader must tell apart. A single texture or a
//! single line style is not explained: BANA's guidelines keep the key for
//! what the graphic does not say by itself, and one kind alone is read as
//! "the region" or "the line" its braille label names.

use std::collections::BTreeMap;

use crate::annotation::{Brush, Dot, Dots, Grating, Style, Vibrate};
use crate::drawing::{Drawing, Element, Rgba, Shape, TextShape};

/// How an entry is felt: the style it explains.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Swatch {
    /// A grated area (a texture).
    Texture(Grating),
    /// A vibrating line (a line style).
    Line(Vibrate),
    /// A dotted line.
    Dotted(Dots),
    /// A point symbol.
    Symbol(Dot),
    /// A brushed stroke (grid devices).
    Stroke(Brush),
}

impl Swatch {
    /// The kind's word, as the key and a host say it: `texture`, `line`,
    /// `dotted line`, `symbol`, `stroke`.
    pub fn kind(&self) -> &'static str {
        match self {
            Swatch::Texture(_) => "texture",
            Swatch::Line(_) => "line",
            Swatch::Dotted(_) => "dotted line",
            Swatch::Symbol(_) => "symbol",
            Swatch::Stroke(_) => "stroke",
        }
    }

    /// The provenance id of an entry of this kind: `key.texture`,
    /// `key.line`, `key.dotted`, `key.symbol`, `key.stroke`.
    pub fn id(&self) -> &'static str {
        match self {
            Swatch::Texture(_) => "key.texture",
            Swatch::Line(_) => "key.line",
            Swatch::Dotted(_) => "key.dotted",
            Swatch::Symbol(_) => "key.symbol",
            Swatch::Stroke(_) => "key.stroke",
        }
    }

    /// What the style is, as written (`grating 6 mm at 45°`), for a host to
    /// say what is felt on a device that plays the style itself.
    pub fn felt(&self) -> String {
        match self {
            Swatch::Texture(g) => format!("grating {} mm at {}°", num(g.wavelength_mm), num(g.angle_deg)),
            Swatch::Line(v) => format!("vibrating line {} mm, {} Hz", num(v.width_mm), num(v.freq_hz)),
            Swatch::Dotted(d) => format!("dots of {} mm", num(2.0 * d.radius_mm)),
            Swatch::Symbol(d) => format!("dot of {} mm", num(2.0 * d.radius_mm)),
            Swatch::Stroke(b) => format!("brushed stroke {} ms", num(b.duration_ms)),
        }
    }

    /// Its identity: the parameters the back ends tell one texture, line
    /// style or symbol from another by (as bits, so that it can be compared).
    fn identity(&self) -> (u8, u64, u64) {
        match self {
            Swatch::Texture(g) => (0, g.wavelength_mm.to_bits(), g.angle_deg.to_bits()),
            Swatch::Line(v) => (1, v.width_mm.to_bits(), v.freq_hz.to_bits()),
            Swatch::Dotted(d) => (2, d.radius_mm.to_bits(), d.spacing_mm.unwrap_or(-1.0).to_bits()),
            Swatch::Symbol(d) => (3, d.radius_mm.to_bits(), 0),
            Swatch::Stroke(b) => (4, b.duration_ms.to_bits(), b.freq_hz.to_bits()),
        }
    }

    /// The group a reader tells entries apart within (dotted lines and
    /// symbols are both dots on most devices).
    fn group(&self) -> u8 {
        match self {
            Swatch::Texture(_) => 0,
            Swatch::Line(_) => 1,
            Swatch::Dotted(_) | Swatch::Symbol(_) => 2,
            Swatch::Stroke(_) => 3,
        }
    }

    /// The noun a colour word goes with ("red areas").
    fn things(&self) -> &'static str {
        match self {
            Swatch::Texture(_) => "areas",
            Swatch::Line(_) => "lines",
            Swatch::Dotted(_) => "dotted lines",
            Swatch::Symbol(_) => "points",
            Swatch::Stroke(_) => "strokes",
        }
    }
}

/// The kind's word of a provenance id [`Swatch::id`] (`key.texture` →
/// `texture`), `None` for an id that is not a key entry's.
pub fn kind_of_id(id: &str) -> Option<&'static str> {
    Some(match id {
        "key.texture" => "texture",
        "key.line" => "line",
        "key.dotted" => "dotted line",
        "key.symbol" => "symbol",
        "key.stroke" => "stroke",
        _ => return None,
    })
}

/// Where an entry's meaning came from, first rule first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Source {
    /// The text beside its swatch in the drawing's own legend.
    Legend,
    /// The label its elements share (`<title>`, `aria-label`, `inkscape:label`).
    Label,
    /// The innermost Inkscape layer its elements share.
    Layer,
    /// A class its elements share.
    Class,
    /// The basic colour name of its elements' fill (stroke, for lines).
    Colour,
    /// Its place among the entries of its kind.
    Ordinal,
}

/// One entry of the key.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// How it is felt.
    pub swatch: Swatch,
    /// What it means.
    pub meaning: String,
    /// Where the meaning came from.
    pub source: Source,
    /// The language of the meaning's text, when a legend text or label says.
    pub lang: Option<String>,
    /// The elements it stands for (indices into the drawing), in drawing order.
    pub elements: Vec<usize>,
}

impl Entry {
    /// The entry as one line of print: `texture: Forest`.
    pub fn line(&self) -> String {
        format!("{}: {}", self.swatch.kind(), self.meaning)
    }
}

/// The key of a drawing: its entries (textures, then lines, dotted lines,
/// symbols and strokes, each kind in order of first use), its key codes,
/// and the texts the graphic has no room for.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Legend {
    /// Each distinct texture, line style and point symbol.
    pub entries: Vec<Entry>,
    /// Each key code and the label it stands for, codes in order.
    pub codes: Vec<(String, String)>,
    /// The texts the automatic sheet found no place for on the graphic,
    /// not even as a key code (note T0323: an axis's labels under a chart
    /// fitted to the surface's height, single letters no code shortens),
    /// in the drawing's order, each once: the key lists them rather than
    /// leave them out.
    pub unplaced: Vec<String>,
}

/// The provenance entry of [`Legend::unplaced`]: its label is the texts,
/// `A, B, C`, for a host to say (SPEC.md section 10.2).
pub const UNPLACED_ID: &str = "key.text";

/// Texts of [`Legend::unplaced`] on one line of the key.
const UNPLACED_PER_LINE: usize = 8;
/// Most texts of [`Legend::unplaced`] the key lists (eight lines); past
/// them it says how many more (a map's thousands of labels are no key a
/// reader reads; the provenance entry [`UNPLACED_ID`] has them all).
const UNPLACED_LISTED: usize = 64;

impl Legend {
    /// Whether a key is written: there are key codes or texts the graphic
    /// has no room for, or a kind of entry has two or more a reader must
    /// tell apart (module docs).
    pub fn needed(&self) -> bool {
        if !self.codes.is_empty() || !self.unplaced.is_empty() {
            return true;
        }
        (0..4).any(|g| self.entries.iter().filter(|e| e.swatch.group() == g).count() >= 2)
    }

    /// The entries a key lists: all of them when a key is [`needed`](Self::needed), else none.
    pub fn shown(&self) -> &[Entry] {
        if self.needed() { &self.entries } else { &[] }
    }

    /// The key codes as lines of print: `bs Bundle Store`.
    pub fn code_lines(&self) -> Vec<String> {
        self.codes.iter().map(|(c, l)| format!("{c} {l}")).collect()
    }

    /// The provenance entry [`UNPLACED_ID`] of the texts the graphic has no
    /// room for, when there are any.
    pub fn unplaced_entry(&self) -> Option<taxel_format::ProvenanceEntry> {
        (!self.unplaced.is_empty()).then(|| taxel_format::ProvenanceEntry {
            id: UNPLACED_ID.into(),
            label: self.unplaced.join(", "),
            line: 0,
        })
    }

    /// The key's lines of print after its entries: the key codes, then the
    /// texts the graphic has no room for, a few to a line, the first line
    /// saying what they are: `not on the graphic: A, B, C`; past 64 of
    /// them, a last line says how many more.
    pub fn text_lines(&self) -> Vec<String> {
        let mut lines = self.code_lines();
        lines.extend(unplaced_lines(&self.unplaced));
        lines
    }
}

/// The lines that list `texts` the graphic has no room for, as the key
/// prints them ([`Legend::text_lines`]): eight to a line, the first saying
/// what they are, at most 64, then how many more. The preview lists a
/// bundle's entry [`UNPLACED_ID`] with them too.
pub fn unplaced_lines<S: AsRef<str>>(texts: &[S]) -> Vec<String> {
    let listed = &texts[..texts.len().min(UNPLACED_LISTED)];
    let mut lines: Vec<String> = listed
        .chunks(UNPLACED_PER_LINE)
        .enumerate()
        .map(|(k, chunk)| {
            let texts = chunk.iter().map(AsRef::as_ref).collect::<Vec<&str>>().join(", ");
            if k == 0 { format!("not on the graphic: {texts}") } else { texts }
        })
        .collect();
    if texts.len() > listed.len() {
        lines.push(format!("and {} more not on the graphic", texts.len() - listed.len()));
    }
    lines
}

/// The key of `d` ([`Legend`]): its entries and their meanings, and its key
/// codes.
///
/// ```
/// use taxel_compiler::annotation::{Grating, Style};
/// use taxel_compiler::drawing::{Drawing, Element, PathShape, Shape};
/// use taxel_compiler::geometry::Polyline;
/// use taxel_compiler::style::legend::{legend, Source};
///
/// let square = |x: f64, label: &str, wavelength_mm: f64| Element {
///     label: label.into(),
///     visible: true,
///     styles: vec![Style::Grating(Grating { wavelength_mm, angle_deg: 0.0, amplitude: 1.0, soft_mm: 0.0 })],
///     shape: Shape::Path(PathShape {
///         outline: vec![Polyline { points: vec![(x, 0.0), (x + 30.0, 0.0), (x + 30.0, 30.0), (x, 30.0)], closed: true }],
///         ..Default::default()
///     }),
///     ..Default::default()
/// };
/// let d = Drawing { elements: vec![square(0.0, "Forest", 3.0), square(40.0, "Lake", 6.0)], ..Default::default() };
/// let key = legend(&d);
/// assert!(key.needed());
/// assert_eq!(key.entries[1].meaning, "Lake");
/// assert_eq!(key.entries[1].source, Source::Label);
/// ```
pub fn legend(d: &Drawing) -> Legend {
    legend_with(d, &crate::drawing::OpaqueFills::of(d))
}

/// [`legend()`], with the drawing's opaque fills already gathered.
pub(crate) fn legend_with(d: &Drawing, opaque: &crate::drawing::OpaqueFills) -> Legend {
    let mut entries: Vec<Entry> = Vec::new();
    let mut of_identity: std::collections::HashMap<(u8, u64, u64), usize> = Default::default();
    for (i, e) in d.elements.iter().enumerate().filter(|(_, e)| e.visible) {
        // Only what is felt somewhere: not a shape that is empty, or
        // clipped or masked away (T0301).
        let Shape::Path(p) = &e.shape else { continue };
        if p.outline.is_empty() || p.clips.iter().any(|c| c.outline.is_empty()) {
            continue;
        }
        for s in &e.styles {
            let swatch = match *s {
                Style::Grating(g) => Swatch::Texture(g),
                Style::Vibrate(v) => Swatch::Line(v),
                Style::Dots(d) => Swatch::Dotted(d),
                Style::Dot(d) => Swatch::Symbol(d),
                Style::Brush(b) => Swatch::Stroke(b),
                Style::Braille(_) => continue,
            };
            match of_identity.get(&swatch.identity()).and_then(|&k| entries.get_mut(k)) {
                Some(x) => {
                    if x.elements.last() != Some(&i) {
                        x.elements.push(i);
                    }
                }
                None => {
                    of_identity.insert(swatch.identity(), entries.len());
                    entries.push(Entry {
                        swatch,
                        meaning: String::new(),
                        source: Source::Ordinal,
                        lang: None,
                        elements: vec![i],
                    })
                }
            }
        }
    }
    // Nor a texture that opaque fills painted over it hide wholly, as
    // they do on every device and on paper (its layer is not felt).
    entries.retain(|x| !matches!(x.swatch, Swatch::Texture(_)) || !opaque.hide_all(d, &x.elements));
    // Textures, then lines, dotted lines, symbols and strokes (stable: each
    // kind keeps its order of first use).
    entries.sort_by_key(|x| x.swatch.identity().0);
    name(d, &mut entries);
    Legend { entries, codes: codes(d), unplaced: unplaced(d) }
}

/// The provenance entries of the key's entries a device plays (those
/// `plays` keeps), for a host to say: id [`Swatch::id`] (`key.texture`),
/// label the meaning and, in brackets, the style as written
/// (`Forest (grating 3 mm at 0°)`); none when no key is needed.
pub fn provenance(legend: &Legend, plays: impl Fn(&Swatch) -> bool) -> Vec<taxel_format::ProvenanceEntry> {
    legend
        .shown()
        .iter()
        .filter(|e| plays(&e.swatch))
        .map(|e| taxel_format::ProvenanceEntry {
            id: e.swatch.id().into(),
            label: format!("{} ({})", e.meaning, e.swatch.felt()),
            line: 0,
        })
        .collect()
}

/// The texts of `d` that found no place on the graphic
/// ([`Legend::unplaced`]), in order, each once.
fn unplaced(d: &Drawing) -> Vec<String> {
    let mut seen = std::collections::HashSet::new();
    d.elements
        .iter()
        .filter_map(|e| match &e.shape {
            Shape::Text(t) if t.unplaced => Some(crate::style::keys::label_text(t)),
            _ => None,
        })
        .filter(|t| !t.is_empty() && seen.insert(t.clone()))
        .collect()
}

/// The key codes of `d` and the labels they stand for, codes in order.
fn codes(d: &Drawing) -> Vec<(String, String)> {
    let mut key: BTreeMap<&str, &str> = BTreeMap::new();
    for e in &d.elements {
        if let Shape::Text(TextShape { content, keyed: Some(label), .. }) = &e.shape {
            key.insert(content, label);
        }
    }
    key.into_iter().map(|(c, l)| (c.to_string(), l.to_string())).collect()
}

/// Gives every entry its meaning (module docs: the rules in order).
fn name(d: &Drawing, entries: &mut [Entry]) {
    let legends = legend_texts(d, entries);
    let mut candidates: Vec<Vec<(Source, String, Option<String>)>> = entries
        .iter()
        .enumerate()
        .map(|(k, x)| {
            let mut c = Vec::new();
            if let Some((text, lang)) = legends.get(&k) {
                c.push((Source::Legend, text.clone(), lang.clone()));
            }
            let of = |f: &dyn Fn(&Element) -> Option<String>| shared(d, &x.elements, f);
            if let Some(l) = of(&|e| Some(e.label.trim().to_string()).filter(|l| !l.is_empty())) {
                c.push((Source::Label, l, None));
            }
            if let Some(l) = innermost_layer(d, &x.elements) {
                c.push((Source::Layer, l, None));
            }
            if let Some(l) = shared_class(d, &x.elements) {
                c.push((Source::Class, l, None));
            }
            if let Some(w) = of(&|e| colour_word(paint_of(e, &x.swatch)?)) {
                c.push((Source::Colour, format!("{w} {}", x.swatch.things()), None));
            }
            c.reverse(); // popped from the end: the first rule last
            c
        })
        .collect();
    // An entry takes its first candidate; where two entries would say the
    // same (a legend text, label, layer, class or colour they share: a
    // region's texture and its outline, both titled "Lake"), both take
    // their next, so that every meaning in the key is its own.
    loop {
        let mut said: std::collections::HashMap<String, usize> = Default::default();
        for c in &candidates {
            if let Some((_, text, _)) = c.last() {
                *said.entry(text.clone()).or_insert(0) += 1;
            }
        }
        let mut changed = false;
        for c in &mut candidates {
            if c.last().is_some_and(|(_, text, _)| said.get(text).is_some_and(|&n| n > 1)) {
                c.pop();
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    let mut ordinal: BTreeMap<&str, usize> = BTreeMap::new();
    for (x, c) in entries.iter_mut().zip(&mut candidates) {
        let n = ordinal.entry(x.swatch.kind()).or_insert(0);
        *n += 1;
        match c.pop() {
            Some((source, meaning, lang)) => {
                x.source = source;
                x.meaning = meaning;
                x.lang = lang;
            }
            None => {
                x.source = Source::Ordinal;
                x.meaning = format!("{} {n}", x.swatch.kind());
            }
        }
    }
}

/// The value `f` gives every element of `elements`, when they all give the same one.
fn shared(d: &Drawing, elements: &[usize], f: &dyn Fn(&Element) -> Option<String>) -> Option<String> {
    let mut it = elements.iter().filter_map(|&i| d.elements.get(i));
    let first = f(it.next()?)?;
    it.all(|e| f(e).as_ref() == Some(&first)).then_some(first)
}

/// The innermost Inkscape layer every element of `elements` lies in (not a
/// `tactile:` annotation, nor Inkscape's default "Layer 1").
fn innermost_layer(d: &Drawing, elements: &[usize]) -> Option<String> {
    let mut it = elements.iter().filter_map(|&i| d.elements.get(i));
    let mut common: Vec<&str> = it.next()?.layers.iter().map(String::as_str).collect();
    for e in it {
        let n = common.iter().zip(&e.layers).take_while(|(a, b)| **a == b.as_str()).count();
        common.truncate(n);
    }
    common.into_iter().rev().map(str::trim).find(|l| meaningful_layer(l)).map(str::to_string)
}

fn meaningful_layer(l: &str) -> bool {
    let default = l.strip_prefix("Layer ").is_some_and(|n| n.trim().chars().all(|c| c.is_ascii_digit()));
    !l.is_empty() && !default && !l.trim_start().starts_with("tactile:")
}

/// A class every element of `elements` has, as words (`land-use` → "land use").
fn shared_class(d: &Drawing, elements: &[usize]) -> Option<String> {
    let mut it = elements.iter().filter_map(|&i| d.elements.get(i));
    let first = it.next()?;
    let mut common: Vec<&str> = first.classes.split_whitespace().collect();
    for e in it {
        let theirs: Vec<&str> = e.classes.split_whitespace().collect();
        common.retain(|c| theirs.contains(c));
    }
    let words = |c: &str| c.replace(['-', '_'], " ").trim().to_string();
    common.into_iter().map(words).find(|w| w.chars().any(char::is_alphabetic))
}

/// The colour that names an element of an entry: its fill, or its stroke
/// for a line (and a fill-less mark).
fn paint_of(e: &Element, s: &Swatch) -> Option<Rgba> {
    match s {
        Swatch::Line(_) | Swatch::Dotted(_) | Swatch::Stroke(_) => e.paint.stroke.or(e.paint.fill),
        Swatch::Texture(_) | Swatch::Symbol(_) => e.paint.fill.or(e.paint.stroke),
    }
}

/// The basic colour name of `c` (one of Berlin and Kay's eleven: black,
/// white, grey, red, orange, yellow, green, blue, purple, pink, brown), by
/// its hue, saturation and lightness; `None` when it is hardly seen.
pub fn colour_word(c: Rgba) -> Option<String> {
    if c[3] < super::MIN_ALPHA {
        return None;
    }
    let [r, g, b] = [c[0], c[1], c[2]].map(|v| v as f64 / 255.0);
    let (max, min) = (r.max(g).max(b), r.min(g).min(b));
    let l = (max + min) / 2.0;
    let chroma = max - min;
    let word = if chroma < 0.12 {
        // No hue: by lightness.
        if l < 0.2 {
            "black"
        } else if l > 0.85 {
            "white"
        } else {
            "grey"
        }
    } else {
        let h = if max == r {
            60.0 * ((g - b) / chroma).rem_euclid(6.0)
        } else if max == g {
            60.0 * ((b - r) / chroma + 2.0)
        } else {
            60.0 * ((r - g) / chroma + 4.0)
        };
        match h {
            h if !(15.0..330.0).contains(&h) => {
                if l > 0.7 {
                    "pink"
                } else if max < 0.45 {
                    "brown"
                } else {
                    "red"
                }
            }
            h if h < 45.0 => {
                if max < 0.65 {
                    "brown"
                } else {
                    "orange"
                }
            }
            h if h < 70.0 => {
                if max < 0.55 {
                    "brown"
                } else {
                    "yellow"
                }
            }
            h if h < 165.0 => "green",
            h if h < 255.0 => "blue",
            h if h < 290.0 => "purple",
            _ => {
                if l > 0.6 {
                    "pink"
                } else {
                    "purple"
                }
            }
        }
    };
    Some(word.to_string())
}

/// Largest side of a legend's swatch, mm (matplotlib's patch is 2 em by
/// 0.7 em, Vega-Lite's symbol 5 mm; a map legend's box rarely passes 15 mm).
pub const SWATCH_MAX_MM: f64 = 20.0;
/// Farthest a legend's text starts right of its swatch, mm (matplotlib:
/// 0.8 em; Vega-Lite: 4 px), with room for larger legends.
pub const LEGEND_GAP_MM: f64 = 12.0;
/// Farthest the swatches of one legend's rows may stray from their column
/// (or a horizontal legend's from its row), mm.
const ALIGN_MM: f64 = 2.5;

/// The legend texts of the entries: for each entry (by index) the text to
/// the right of one of its small elements, when two or more such pairs line
/// up as a legend's rows (or its columns).
fn legend_texts(d: &Drawing, entries: &[Entry]) -> BTreeMap<usize, (String, Option<String>)> {
    let texts = Texts::of(d);
    // A text over a region of a texture is that region's label (a map's),
    // not a legend's: a legend's text lies on the page or on its own box.
    let mut textured: Vec<usize> = entries
        .iter()
        .filter(|x| matches!(x.swatch, Swatch::Texture(_)))
        .flat_map(|x| x.elements.iter().copied())
        .collect();
    textured.sort_unstable();
    let grounds = Grounds::of(d);
    let is_label = |t: &TextShape| {
        let at = Texts::place(t);
        at.and_then(|(x, y, _)| grounds.topmost_at((x, y))).is_some_and(|i| textured.binary_search(&i).is_ok())
    };
    // (entry, swatch's box, text, lang)
    let mut pairs: Vec<(usize, Bounds, String, Option<String>)> = Vec::new();
    for (k, x) in entries.iter().enumerate() {
        let mut best: Option<(f64, Bounds, &TextShape)> = None;
        for &i in &x.elements {
            let Some(b) = d.elements.get(i).and_then(Element::seen_bounds) else { continue };
            if let Some((gap, t)) = texts.beside(b)
                && best.as_ref().is_none_or(|bb| gap < bb.0)
                && !is_label(t)
            {
                best = Some((gap, b, t));
            }
        }
        if let Some((_, b, t)) = best {
            // A legend text written as a key code means the label it stands for.
            let text = t.keyed.clone().unwrap_or_else(|| super::keys::label_text(t));
            pairs.push((k, b, text, t.lang.clone()));
        }
    }
    let boxes: Vec<(usize, Bounds)> = pairs.iter().map(|p| (p.0, p.1)).collect();
    let lined = lined_up(&boxes);
    pairs.into_iter().zip(lined).filter(|(_, l)| *l).map(|(p, _)| (p.0, (p.2, p.3))).collect()
}

/// The texts of a drawing where a legend's are looked for: where each
/// starts, its middle height (a capital's half above the baseline) and its
/// size, where the drawing has them (before the automatic sheet moved their
/// braille). They are filed by band of height and, within a band, by where
/// they start, so that a swatch looks only at the texts in its reach: a map
/// of tens of thousands of labelled regions asks this of every small region.
pub(crate) struct Texts<'d> {
    /// `(text, (x, y, size), rank)` by band, then by `x`; `rank` is the
    /// text's place in the order of `x` alone (drawing order among equals).
    texts: Vec<(&'d TextShape, (f64, f64, f64), usize)>,
    /// Each band's texts in `texts`, by band number (`y` / [`BAND_MM`]).
    bands: BTreeMap<i64, core::ops::Range<usize>>,
    /// The largest text size, mm (how far above or below a text may be level with a swatch).
    max_size: f64,
}

/// Height of a band of [`Texts`], mm.
const BAND_MM: f64 = 4.0;

impl<'d> Texts<'d> {
    /// The texts of `d` that say something.
    pub(crate) fn of(d: &'d Drawing) -> Self {
        let mut texts: Vec<(&TextShape, (f64, f64, f64))> = d
            .elements
            .iter()
            .filter_map(|e| match &e.shape {
                Shape::Text(t) if !t.content.trim().is_empty() => Some((t, Self::place(t)?)),
                _ => None,
            })
            .collect();
        texts.sort_by(|a, b| a.1.0.total_cmp(&b.1.0));
        let band = |y: f64| (y / BAND_MM).floor().clamp(-1e15, 1e15) as i64;
        let mut texts: Vec<_> = texts.into_iter().enumerate().map(|(rank, (t, at))| (t, at, rank)).collect();
        texts.sort_by_key(|&(_, at, rank)| (band(at.1), rank));
        let mut bands: BTreeMap<i64, core::ops::Range<usize>> = BTreeMap::new();
        for (n, &(_, at, _)) in texts.iter().enumerate() {
            bands.entry(band(at.1)).or_insert(n..n).end = n + 1;
        }
        let max_size = texts.iter().map(|t| t.1.2).fold(0.0, f64::max);
        Texts { texts, bands, max_size }
    }

    /// Where a text starts, its middle height and its size, where the
    /// drawing has it (before its braille was moved); `None` for a text
    /// with nothing to say or no finite place.
    fn place(t: &TextShape) -> Option<(f64, f64, f64)> {
        let run = t.runs.iter().find(|r| !r.text.trim().is_empty())?;
        let (x, y) = (run.x_mm - t.moved_mm.0, run.y_mm - t.moved_mm.1);
        let x = x - run.anchor * t.content.chars().count() as f64 * t.font_size_mm * 0.5;
        let at = (x, y - 0.35 * t.font_size_mm, t.font_size_mm);
        (at.0.is_finite() && at.1.is_finite() && at.2.is_finite()).then_some(at)
    }

    /// The text a legend would write beside a swatch of box `b`, and how far
    /// right of it it starts: the nearest that starts within
    /// [`LEGEND_GAP_MM`] to its right, its middle level with the swatch's
    /// (within half the swatch's height, or three quarters of the text's
    /// size for a thin swatch); the first in the order of `x` among equals.
    /// `None` when `b` is too large for a swatch.
    pub(crate) fn beside(&self, b: Bounds) -> Option<(f64, &'d TextShape)> {
        let (w, h) = (b.2 - b.0, b.3 - b.1);
        if w > SWATCH_MAX_MM || h > SWATCH_MAX_MM || !(b.1 + b.3).is_finite() {
            return None;
        }
        let mid = (b.1 + b.3) / 2.0;
        // No text farther above or below than this is level with the swatch.
        let most = (h / 2.0).max(self.max_size * 0.75).max(1.0);
        let band = |y: f64| (y / BAND_MM).floor().clamp(-1e15, 1e15) as i64;
        let mut best: Option<(f64, usize, &TextShape)> = None;
        for range in self.bands.range(band(mid - most)..=band(mid + most)).map(|(_, r)| r.clone()) {
            let texts = self.texts.get(range).unwrap_or(&[]);
            let from = texts.partition_point(|t| t.1.0 < b.2 - 0.5);
            let to = texts.partition_point(|t| t.1.0 <= b.2 + LEGEND_GAP_MM);
            for &(t, (tx, ty, size), rank) in texts.get(from..to).unwrap_or(&[]) {
                let gap = tx - b.2;
                // Level with the swatch: a bar's tick label, under the bar's
                // foot, is not beside it, however tall the bar.
                let reach = (h / 2.0).max(size * 0.75).max(1.0);
                if (-0.5..=LEGEND_GAP_MM).contains(&gap)
                    && (ty - mid).abs() <= reach
                    && best.is_none_or(|bb| (gap, rank) < (bb.0, bb.1))
                {
                    best = Some((gap, rank, t));
                }
            }
        }
        best.map(|(gap, _, t)| (gap, t))
    }
}

/// The visible filled shapes of a drawing, by box: what lies under a point.
struct Grounds<'d> {
    d: &'d Drawing,
    tree: rstar::RTree<rstar::primitives::GeomWithData<rstar::primitives::Rectangle<[f64; 2]>, usize>>,
}

impl<'d> Grounds<'d> {
    fn of(d: &'d Drawing) -> Self {
        let boxes = d
            .elements
            .iter()
            .enumerate()
            .filter(|(_, e)| e.visible && e.paint.fill.is_some() && matches!(e.shape, Shape::Path(_)))
            .filter_map(|(i, e)| {
                let b = e.seen_bounds()?;
                let r = rstar::primitives::Rectangle::from_corners([b.0, b.1], [b.2, b.3]);
                [b.0, b.1, b.2, b.3].iter().all(|v| v.is_finite()).then(|| rstar::primitives::GeomWithData::new(r, i))
            })
            .collect();
        Grounds { d, tree: rstar::RTree::bulk_load(boxes) }
    }

    /// The last element in drawing order whose fill holds `p`.
    fn topmost_at(&self, p: (f64, f64)) -> Option<usize> {
        self.tree
            .locate_all_at_point(&[p.0, p.1])
            .map(|g| g.data)
            .filter(|&i| match self.d.elements.get(i).map(|e| &e.shape) {
                Some(Shape::Path(ps)) => crate::geometry::contains(&ps.outline, p, ps.fill_rule),
                _ => false,
            })
            .max()
    }
}

/// Which of the swatches `pairs` (each with something to tell it from the
/// others by, and its box) line up with another's as a legend's rows or
/// columns do: two or more swatches in a column (their left sides within
/// [`ALIGN_MM`]) or a row (their middles).
pub(crate) fn lined_up(pairs: &[(usize, Bounds)]) -> Vec<bool> {
    // Along each axis in turn, sorted: a swatch lines up when the nearest
    // other one (of another id) on either side is within ALIGN_MM, so a
    // map's thousands of small regions are not compared pair by pair.
    let mut lined = vec![false; pairs.len()];
    let left = |p: &(usize, Bounds)| p.1.0;
    let middle = |p: &(usize, Bounds)| (p.1.1 + p.1.3) / 2.0;
    for key in [&left as &dyn Fn(&(usize, Bounds)) -> f64, &middle] {
        let mut order: Vec<usize> = (0..pairs.len()).filter(|&n| key(&pairs[n]).is_finite()).collect();
        order.sort_by(|&a, &b| key(&pairs[a]).total_cmp(&key(&pairs[b])));
        for (at, &n) in order.iter().enumerate() {
            let v = key(&pairs[n]);
            let near = |m: &usize| (key(&pairs[*m]) - v).abs() <= ALIGN_MM;
            let other = |m: &&usize| pairs[**m].0 != pairs[n].0;
            let below = order[..at].iter().rev().take_while(|m| near(m)).find(other).is_some();
            lined[n] |= below || order[at + 1..].iter().take_while(|m| near(m)).find(other).is_some();
        }
    }
    lined
}

/// A box `(x0, y0, x1, y1)` in page mm.
pub(crate) type Bounds = (f64, f64, f64, f64);

/// A number as the key writes it: at most two decimals, no trailing zeros.
fn num(v: f64) -> String {
    let s = format!("{:.2}", v);
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

#[cfg(test)]
mod tests;
