//! The XML side of an SVG: what usvg does not keep (annotations, layer
//! labels, titles, classes, source lines), read with the same XML parser usvg
//! uses, and the id rewrite that lets us match usvg's nodes to elements.
//!
//! Why ids: usvg keeps the `id` of every path, text, `g` and `use`, so an id
//! is a reliable key from a usvg node back to its element. Elements without an
//! id get a deterministic one (`taxel-auto-N`, in document order) inserted in
//! their start tag before usvg sees the text; matching by document order
//! instead would break wherever usvg drops, splits or clones elements (`use`,
//! markers, `switch`). The insertion adds no line breaks, so line numbers stay
//! true; annotations are always read from the original text.
//!
//! Elements that come from an `<!ENTITY>` expansion have their source in the
//! DTD, before the root element: their id goes into the entity's text (so
//! every expansion of it shares one key, and usvg's inheritance still tells
//! the copies apart), and their line is that of the entity reference in the
//! document body, where the reader sees them.
//!
//! Drawings whose patterns or elements nest too deep for usvg are refused
//! first (`source/limits.rs`).

use std::collections::{BTreeMap, HashMap, HashSet};

use roxmltree::{Document, Node, ParsingOptions};

use crate::annotation::sheet::{ElementFacts, StyleSheet};
use crate::annotation::{self, Declaration};
use crate::diagnostic::Diagnostic;
use crate::text_pos::{LineIndex, line_col, raw_offset};

mod limits;

pub(crate) use limits::{nested_too_deep, patterns_too_nested};

const INKSCAPE_NS: &str = "http://www.inkscape.org/namespaces/inkscape";
/// The prefix of an Inkscape layer label that is an annotation, matched in any case.
const PREFIX: &str = "tactile:";
/// Largest number of XML nodes taxel reads (bounds memory on hostile input).
pub(crate) const NODES_LIMIT: u32 = 2_000_000;

/// How usvg treats an element, as far as inheritance is concerned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// `svg` (root), `g`, `use`: usvg always keeps a group with the id.
    Group,
    /// `defs`: its content only appears through references.
    Defs,
    /// Other containers (`a`, `switch`, `symbol`, nested `svg`) that usvg may flatten away.
    Container,
    /// `text`.
    Text,
    /// Anything else (shapes, images, titles, ...).
    Other,
}

/// One element of the original document.
#[derive(Debug, Clone)]
pub(crate) struct Element {
    /// The id usvg sees (the original one or an inserted one).
    pub key: String,
    /// The id as written, empty when it had none.
    pub id: String,
    /// A name for messages: the id, or a path such as `svg/g[2]/path[1]`.
    pub name: String,
    /// Local tag name.
    pub tag: String,
    pub kind: Kind,
    /// 1-based line of the start tag (of the entity reference, for an element from an entity).
    pub line: u32,
    /// `<title>`, `inkscape:label` (but an annotation) or `aria-label`,
    /// whichever comes first; else the label its group passes down.
    pub label: String,
    /// The label its children take when they have none: its own label, or
    /// what its parent passes; the root's and an Inkscape layer's pass only
    /// what their parent passes (nothing for the root).
    pub passes: String,
    pub classes: String,
    /// Labels of the Inkscape layers that contain the element (itself included).
    pub layers: Vec<String>,
    /// The element's own annotation: `data-tactile`, else a `tactile:` label.
    pub own: Option<Declaration>,
    /// The style sheet rule that selects it by id, class or layer alone.
    pub sheet: Option<Declaration>,
    pub parent: Option<usize>,
    pub in_defs: bool,
    /// Whether it is not drawn for the reader's languages: its conditions,
    /// or an ancestor's, fail ([`conditions_pass`]), or it is under a `<switch>` child
    /// that is not drawn ([`switch_child`]).
    pub switched_off: bool,
    /// Whether it draws markers (so the group after its usvg path holds them).
    pub has_markers: bool,
    /// The node in the original document.
    pub node: roxmltree::NodeId,
}

/// The original document's elements and the text to give usvg.
pub(crate) struct Source {
    pub elements: Vec<Element>,
    /// The elements each key names: one, except for the copies of an
    /// entity's elements (and for ids written twice).
    pub by_key: HashMap<String, Vec<usize>>,
}

impl Source {
    /// The element usvg calls `key`.
    ///
    /// When several elements share the key, the one inside `near` (the element
    /// of the nearest group usvg kept around the node) is meant; failing that,
    /// the last one, as a browser's `getElementById` would not say either.
    pub fn get(&self, key: &str, near: Option<usize>) -> Option<(usize, &Element)> {
        let all = self.by_key.get(key)?;
        let inside = |i: usize| {
            let mut p = self.elements[i].parent;
            while let Some(k) = p {
                if Some(k) == near {
                    return true;
                }
                p = self.elements[k].parent;
            }
            false
        };
        let &i = match all.as_slice() {
            [one] => one,
            _ => all.iter().find(|&&i| inside(i)).or(all.last())?,
        };
        Some((i, &self.elements[i]))
    }
}

/// XML parsing options shared with the usvg pass.
pub(crate) fn xml_options<'a>() -> ParsingOptions<'a> {
    ParsingOptions { allow_dtd: true, nodes_limit: NODES_LIMIT, ..ParsingOptions::default() }
}

/// Parses the XML; `None` (with an error diagnostic) when it is not well-formed.
pub(crate) fn parse_xml<'a>(text: &'a str, diags: &mut Vec<Diagnostic>) -> Option<Document<'a>> {
    // An empty file (an export that failed) is not a malformed one: "no root node" would not say so.
    if text.trim().is_empty() {
        diags.push(
            Diagnostic::error("T0200", "the file is empty, expected an SVG document")
                .with_help("export or save the drawing again: the file that was written holds nothing"),
        );
        return None;
    }
    match Document::parse_with_options(text, xml_options()) {
        Ok(d) => Some(d),
        Err(e) => {
            let p = e.pos();
            diags.push(
                Diagnostic::error("T0200", format!("the file is not well-formed SVG (XML): {e}"))
                    .at(p.row, p.col)
                    .with_help("open it in an SVG editor and save it again, or fix the XML by hand"),
            );
            None
        }
    }
}

/// The ids usvg sees, from a light first pass over the parsed document: the
/// key of every element (in the order of [`read`]) and the text with an id
/// inserted where an element had none. It is all that usvg's pass needs, so
/// usvg can convert the drawing while [`read`] does the rest of the XML side.
pub(crate) struct Keys {
    /// One per element of the document, in document order: the id as
    /// written, or the one inserted (`{prefix}{index}`).
    pub keys: Vec<String>,
    /// The text to give usvg.
    pub rewritten: String,
}

/// The first pass: [`Keys`] of a parsed document; `None` (with an error
/// diagnostic) when it is not SVG.
pub(crate) fn keys(text: &str, doc: &Document<'_>, diags: &mut Vec<Diagnostic>) -> Option<Keys> {
    let root = doc.root_element();
    if root.tag_name().name() != "svg" {
        diags.push(
            Diagnostic::error("T0200", format!("the root element is <{}>, expected <svg>", root.tag_name().name()))
                .at(line_col(text, root.range().start).0, 1),
        );
        return None;
    }
    let existing: HashSet<&str> = doc.descendants().filter_map(|n| n.attribute("id")).collect();
    let mut prefix = String::from("taxel-auto-");
    while existing.iter().any(|id| id.starts_with(&prefix)) {
        prefix.push('x');
    }
    // Where ids are inserted, by byte offset; an entity's elements are inserted
    // once for all of its expansions, so the offset decides the key.
    let mut inserts: BTreeMap<usize, (String, String)> = BTreeMap::new();
    let body_start = root.range().start;
    let mut keys = Vec::new();
    for node in root.descendants().filter(|n| n.is_element()) {
        let id = node.attribute("id").unwrap_or("");
        let key = if id.is_empty() {
            match tag_name_end(text, node) {
                Some(at) => {
                    let k = format!("{prefix}{}", keys.len());
                    let quote = if at < body_start { entity_quote(text, at) } else { '"' };
                    inserts.entry(at).or_insert_with(|| (k.clone(), format!(" id={quote}{k}{quote}"))).0.clone()
                }
                None => format!("{prefix}{}", keys.len()),
            }
        } else {
            id.to_string()
        };
        keys.push(key);
    }
    // XML comments inside a `<style>` are cut out of usvg's text: usvg reads
    // a style sheet's first text only, so a comment in it (Wikimedia's world
    // maps write `/* <!-- Done up to row 1708 --> */` at the top of theirs)
    // lost every rule after it, and the whole map was drawn black. (The
    // comment then leaves `/*  */`, an empty CSS comment.)
    let cuts: BTreeMap<usize, usize> = root
        .descendants()
        .filter(|n| n.is_element() && n.tag_name().name() == "style")
        .flat_map(|n| n.children().filter(|c| c.is_comment()).map(|c| c.range()))
        .filter(|r| r.start >= body_start && r.start < r.end && r.end <= text.len())
        .map(|r| (r.start, r.end))
        .collect();
    let mut rewritten = String::with_capacity(text.len() + inserts.len() * 24);
    let mut last = 0;
    // In offset order (BTreeMaps), so every slice below runs forwards; no
    // id goes inside a comment.
    let mut cuts = cuts.into_iter().peekable();
    for (&at, (_, s)) in &inserts {
        while let Some((start, end)) = cuts.next_if(|&(start, _)| start < at) {
            rewritten.push_str(text.get(last..start).unwrap_or(""));
            last = end.max(last);
        }
        rewritten.push_str(text.get(last..at).unwrap_or(""));
        rewritten.push_str(s);
        last = at;
    }
    for (start, end) in cuts {
        rewritten.push_str(text.get(last..start).unwrap_or(""));
        last = end.max(last);
    }
    rewritten.push_str(text.get(last..).unwrap_or(""));
    Some(Keys { keys, rewritten })
}

/// The second pass: the elements of a parsed document whose [`Keys::keys`]
/// are `keys`, with their annotations (malformed ones as diagnostics),
/// labels, layers, style sheet rules and lines.
pub(crate) fn read(
    text: &str,
    doc: &Document<'_>,
    keys: Vec<String>,
    sheet: Option<&StyleSheet>,
    languages: &[String],
    diags: &mut Vec<Diagnostic>,
) -> Source {
    let root = doc.root_element();
    // Markers set from a `<style>` sheet through a class.
    let css_markers =
        doc.descendants().any(|n| n.tag_name().name() == "style" && n.text().is_some_and(|t| t.contains("marker")));
    let mut elements = Vec::with_capacity(keys.len());
    let mut by_key: HashMap<String, Vec<usize>> = HashMap::new();
    let mut index_of: HashMap<roxmltree::NodeId, usize> = HashMap::new();
    let body_start = root.range().start;
    let mut pos_of: HashMap<roxmltree::NodeId, usize> = HashMap::new();
    let mut seen_tags: HashMap<(Option<roxmltree::NodeId>, String), usize> = HashMap::new();
    let lines = LineIndex::new(text);
    let mut keys = keys.into_iter();
    for node in root.descendants().filter(|n| n.is_element()) {
        // Both passes walk the same elements of the same document, so there is a key for each.
        let key = keys.next().unwrap_or_default();
        let parent = node.parent_element().and_then(|p| index_of.get(&p.id()).copied());
        let parent_el: Option<&Element> = parent.map(|p| &elements[p]);
        let tag = node.tag_name().name().to_string();
        let id = node.attribute("id").unwrap_or("").to_string();
        // Elements of this tag before it among its siblings, counted as the
        // walk (in document order) meets them: counting them again at each
        // element was quadratic in a parent's children (100,000 circles of a
        // scatter plot: 90 % of a 35 s build).
        // (Counted from 1: the element itself is one of them.)
        let nth = {
            let seen = seen_tags.entry((node.parent().map(|n| n.id()), tag.clone())).or_insert(0);
            *seen += 1;
            *seen
        };
        let name = match parent_el {
            _ if !id.is_empty() => id.clone(),
            None => tag.clone(),
            Some(p) => {
                format!("{}/{tag}[{nth}]", p.name)
            }
        };
        let kind = match tag.as_str() {
            "svg" if parent.is_none() => Kind::Group,
            "g" | "use" => Kind::Group,
            "defs" => Kind::Defs,
            "a" | "switch" | "symbol" | "svg" => Kind::Container,
            "text" => Kind::Text,
            _ => Kind::Other,
        };
        let pos = source_pos(text, node, body_start, &pos_of);
        pos_of.insert(node.id(), pos);
        let line = lines.line(pos);
        let ink_label = node.attribute((INKSCAPE_NS, "label"));
        // An Inkscape label that is an annotation (`tactile: ...`) names nothing.
        let names =
            ink_label.filter(|l| !l.trim_start().get(..PREFIX.len()).is_some_and(|p| p.eq_ignore_ascii_case(PREFIX)));
        let own_label = node
            .children()
            .find(|c| c.is_element() && c.tag_name().name() == "title")
            .and_then(|t| t.text())
            .or(names)
            .or(node.attribute("aria-label"))
            .unwrap_or("")
            .trim();
        let is_layer = tag == "g" && node.attribute((INKSCAPE_NS, "groupmode")) == Some("layer");
        // An element without a label of its own takes its group's (a
        // `<g><title>Lake Geneva</title><path/><path/></g>` names both
        // paths); the root's title (the drawing's) and Inkscape layers'
        // labels ("Layer 1") are not passed down.
        let inherited = parent_el.map_or("", |p| p.passes.as_str());
        let label = if own_label.is_empty() { inherited } else { own_label }.to_string();
        let passes = if is_layer || parent.is_none() { inherited.to_string() } else { label.clone() };
        let mut layers = parent_el.map_or(Vec::new(), |p| p.layers.clone());
        if let (true, Some(l)) = (is_layer, ink_label) {
            layers.push(l.trim().to_string());
        }
        // (A `<symbol>`'s content is drawn only where a `<use>` shows it, as `<defs>`' is.)
        let in_defs = parent_el.is_some_and(|p| p.in_defs || p.kind == Kind::Defs || p.tag == "symbol");
        // An element whose conditions fail is not drawn (another language's
        // label), and under a `<switch>` only its chosen child is.
        let switched_off = parent_el.is_some_and(|p| p.switched_off)
            || !conditions_pass(node, languages)
            || node
                .parent_element()
                .is_some_and(|p| p.tag_name().name() == "switch" && switch_child(p, languages) != Some(node.id()));
        let display = if id.is_empty() { name.clone() } else { id.clone() };
        let mut own = None;
        if let Some(attr) = node.attributes().find(|a| a.name() == "data-tactile" && a.namespace().is_none()) {
            own = annotation_at(text, attr.value(), attr.range_value(), 0, &display, diags);
        } else if let Some(attr) = node.attributes().find(|a| a.name() == "label" && a.namespace() == Some(INKSCAPE_NS))
        {
            let v = attr.value();
            let trimmed = v.trim_start();
            // `get`, not indexing: byte 8 may fall inside a character (`Calque élévation`, `レイヤー 1`).
            if trimmed.get(..PREFIX.len()).is_some_and(|p| p.eq_ignore_ascii_case(PREFIX)) {
                let skip = v.len() - trimmed.len() + PREFIX.len();
                own = annotation_at(text, v.get(skip..).unwrap_or(""), attr.range_value(), skip, &display, diags);
            }
        }
        let classes = node.attribute("class").unwrap_or("").to_string();
        let sheet_decl = sheet.and_then(|s| {
            let facts = ElementFacts { id: &id, classes: &classes, layers: &layers, fill: None, stroke: None };
            s.lookup(&facts).map(|r| r.declaration.clone())
        });
        let has_markers = ["marker-start", "marker-mid", "marker-end", "marker"].iter().any(|a| node.has_attribute(*a))
            || node.attribute("style").is_some_and(|s| s.contains("marker"))
            || (css_markers && node.has_attribute("class"));
        by_key.entry(key.clone()).or_default().push(elements.len());
        index_of.insert(node.id(), elements.len());
        elements.push(Element {
            key,
            id,
            name,
            tag,
            kind,
            line,
            label,
            passes,
            classes,
            layers,
            own,
            sheet: sheet_decl,
            parent,
            in_defs,
            switched_off,
            has_markers,
            node: node.id(),
        });
    }
    Source { elements, by_key }
}

/// Whether element `n`'s conditions pass for a reader of `languages`,
/// exactly as usvg decides (so that texts, which taxel places itself, agree
/// with the shapes usvg draws): it fails if it has `requiredExtensions`,
/// names a `requiredFeatures` feature usvg lacks, or has a `systemLanguage`
/// list with no tag equal to a reader's language or starting with it and a
/// `-`. usvg draws no element whose conditions fail, in a `<switch>` or not.
fn conditions_pass(n: Node<'_, '_>, languages: &[String]) -> bool {
    if n.has_attribute("requiredExtensions") {
        return false;
    }
    if let Some(features) = n.attribute("requiredFeatures")
        && !features.split(' ').all(|f| FEATURES.contains(&f))
    {
        return false;
    }
    n.attribute("systemLanguage").is_none_or(|langs| {
        langs.split(',').map(str::trim).any(|lang| {
            languages.iter().any(|v| v == lang || lang.split_once('-').is_some_and(|(prefix, _)| v == prefix))
        })
    })
}

/// The child a `<switch>` draws for a reader of `languages`: its first child
/// element whose conditions pass ([`conditions_pass`]).
pub(crate) fn switch_child(switch: Node<'_, '_>, languages: &[String]) -> Option<roxmltree::NodeId> {
    switch.children().filter(|n| n.is_element()).find(|n| conditions_pass(*n, languages)).map(|n| n.id())
}

/// The SVG 1.1 features usvg supports, for `requiredFeatures` (usvg 0.49's
/// list, `parser/switch.rs`, Apache-2.0 OR MIT).
const FEATURES: &[&str] = &[
    "http://www.w3.org/TR/SVG11/feature#SVGDOM-static",
    "http://www.w3.org/TR/SVG11/feature#SVG-static",
    "http://www.w3.org/TR/SVG11/feature#CoreAttribute",
    "http://www.w3.org/TR/SVG11/feature#Structure",
    "http://www.w3.org/TR/SVG11/feature#BasicStructure",
    "http://www.w3.org/TR/SVG11/feature#ContainerAttribute",
    "http://www.w3.org/TR/SVG11/feature#ConditionalProcessing",
    "http://www.w3.org/TR/SVG11/feature#Image",
    "http://www.w3.org/TR/SVG11/feature#Style",
    "http://www.w3.org/TR/SVG11/feature#Shape",
    "http://www.w3.org/TR/SVG11/feature#Text",
    "http://www.w3.org/TR/SVG11/feature#BasicText",
    "http://www.w3.org/TR/SVG11/feature#PaintAttribute",
    "http://www.w3.org/TR/SVG11/feature#BasicPaintAttribute",
    "http://www.w3.org/TR/SVG11/feature#OpacityAttribute",
    "http://www.w3.org/TR/SVG11/feature#GraphicsAttribute",
    "http://www.w3.org/TR/SVG11/feature#BasicGraphicsAttribute",
    "http://www.w3.org/TR/SVG11/feature#Marker",
    "http://www.w3.org/TR/SVG11/feature#Gradient",
    "http://www.w3.org/TR/SVG11/feature#Pattern",
    "http://www.w3.org/TR/SVG11/feature#Clip",
    "http://www.w3.org/TR/SVG11/feature#BasicClip",
    "http://www.w3.org/TR/SVG11/feature#Mask",
    "http://www.w3.org/TR/SVG11/feature#Filter",
    "http://www.w3.org/TR/SVG11/feature#BasicFilter",
    "http://www.w3.org/TR/SVG11/feature#XlinkAttribute",
];

/// The byte offset just after an element's tag name in its start tag, when
/// the source there really is that start tag (not an entity expansion).
fn tag_name_end(text: &str, node: Node<'_, '_>) -> Option<usize> {
    let start = node.range().start;
    let rest = text.get(start..)?;
    if !rest.starts_with('<') {
        return None;
    }
    let len = rest[1..].find(|c: char| c.is_whitespace() || c == '/' || c == '>')?;
    Some(start + 1 + len)
}

/// The quote that an id inserted at `at`, inside an entity's replacement
/// text, must use: the one that does not delimit the entity's value.
fn entity_quote(text: &str, at: usize) -> char {
    let decl = text.get(..at).and_then(|t| t.rfind("<!ENTITY")).unwrap_or(0);
    match text.get(decl..at).and_then(|t| t.find(['"', '\''])).map(|i| text.as_bytes()[decl + i]) {
        Some(b'"') => '\'',
        _ => '"',
    }
}

/// The byte offset a reader would point at for `node`: its start tag, or,
/// for an element from an entity expansion (whose text is in the DTD, before
/// `body_start`), the entity reference in the document body.
fn source_pos(text: &str, node: Node<'_, '_>, body_start: usize, pos_of: &HashMap<roxmltree::NodeId, usize>) -> usize {
    let start = node.range().start;
    if start >= body_start {
        return start;
    }
    let Some(parent) = node.parent_element() else { return start };
    let pr = parent.range();
    if pr.start < body_start {
        // Nested in another expansion: the outer reference is the place.
        return pos_of.get(&parent.id()).copied().unwrap_or(start);
    }
    // The entity's name, from its declaration before the node's text.
    let name = text.get(..start).and_then(|t| t.rfind("<!ENTITY")).and_then(|d| {
        let rest = text.get(d + "<!ENTITY".len()..start)?.trim_start();
        let end = rest.find(|c: char| c.is_whitespace())?;
        Some(rest.get(..end)?.to_string())
    });
    // Search after the last element before it whose text is in the body (from
    // the start of a text node: roxmltree gives the text before a reference
    // the range of the whole text, reference included).
    let from = node
        .prev_siblings()
        .find(|s| s.range().start >= body_start)
        .map_or(pr.start, |s| if s.is_element() { s.range().end } else { s.range().start });
    let found = name.and_then(|n| {
        let hay = text.get(from..pr.end)?;
        hay.find(&format!("&{n};")).map(|i| from + i)
    });
    found.unwrap_or(pr.start)
}

/// Parses an annotation found at `value_range` of the source (after skipping
/// `skip` decoded bytes), turning an error into a diagnostic at its line and column.
fn annotation_at(
    text: &str,
    value: &str,
    value_range: core::ops::Range<usize>,
    skip: usize,
    element: &str,
    diags: &mut Vec<Diagnostic>,
) -> Option<Declaration> {
    match annotation::parse(value) {
        Ok(d) => Some(d),
        Err(e) => {
            let raw = text.get(value_range.clone()).unwrap_or("");
            let (line, col) = line_col(text, value_range.start + raw_offset(raw, skip + e.offset));
            let mut d = Diagnostic::error(e.kind.code(), format!("malformed annotation: {}", e.message))
                .with_element(element)
                .at(line, col);
            d.help = Some(e.help.unwrap_or_else(|| {
                "annotations look like `vibrate(width: 1.5mm); grating(wavelength: 6mm, angle: 0deg)` \
                 (see docs/annotations.md)"
                    .into()
            }));
            diags.push(d);
            None
        }
    }
}

#[cfg(test)]
mod tests;
