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

use std::collections::{BTreeMap, HashMap, HashSet};

use roxmltree::{Document, Node, ParsingOptions};

use crate::annotation::{self, Declaration};
use crate::diagnostic::Diagnostic;
use crate::stylesheet::{ElementFacts, StyleSheet};
use crate::text_pos::{LineIndex, line_col, raw_offset};

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

/// The most drawing elements a pattern may stand for once the patterns it
/// fills and strokes with are expanded inside one another: far above any
/// hatching or texture a drawing carries (a few shapes, nested once or
/// twice), far below the expansion of a hostile file (librsvg's "billion
/// laughs": ten patterns of ten shapes, each filled with the next, which
/// usvg took 24 s to read).
const PATTERN_EXPANSION_LIMIT: f64 = 1e6;
/// Patterns painting with patterns more levels deep than this are refused:
/// real drawings nest two or three, and usvg recurses once per level (a
/// chain of 100,000 overflowed its stack).
const PATTERN_DEPTH_LIMIT: usize = 64;

/// An error when `<pattern>`s nest inside one another so deeply that
/// expanding them would not end in reasonable time (a "billion laughs" of
/// paint servers, which usvg expands before anything can be checked).
pub(crate) fn patterns_too_nested<'a>(doc: &'a Document<'a>) -> Option<Diagnostic> {
    let patterns: HashMap<&str, roxmltree::Node<'a, 'a>> = doc
        .descendants()
        .filter(|n| n.is_element() && n.tag_name().name() == "pattern")
        .filter_map(|n| Some((n.attribute("id")?, n)))
        .collect();
    if patterns.len() < 2 {
        return None;
    }
    // The patterns an element paints with: `url(#id)` in its fill or stroke,
    // as attributes or in its style.
    fn urls<'a>(v: &'a str, out: &mut Vec<&'a str>) {
        let mut rest = v;
        while let Some(k) = rest.find("url(") {
            rest = &rest[k + 4..];
            let id = rest.split(')').next().unwrap_or("").trim().trim_matches(|c| c == '\'' || c == '"');
            if let Some(id) = id.strip_prefix('#') {
                out.push(id);
            }
        }
    }
    fn refs<'a>(n: roxmltree::Node<'a, 'a>) -> Vec<&'a str> {
        let mut out = Vec::new();
        for v in [n.attribute("fill"), n.attribute("stroke"), n.attribute("style")].into_iter().flatten() {
            urls(v, &mut out);
        }
        out
    }
    // Each pattern's expansion, memoised; a pattern met again on the path
    // being expanded (a cycle, which usvg breaks) counts for nothing more.
    // A chain deeper than PATTERN_DEPTH_LIMIT counts as too large (usvg
    // recurses once per level, and so would this).
    fn expand<'a>(
        id: &'a str,
        patterns: &HashMap<&'a str, roxmltree::Node<'a, 'a>>,
        memo: &mut HashMap<&'a str, f64>,
        open: &mut HashSet<&'a str>,
    ) -> f64 {
        if let Some(&v) = memo.get(id) {
            return v;
        }
        let Some(&node) = patterns.get(id) else { return 0.0 };
        if open.len() >= PATTERN_DEPTH_LIMIT {
            return f64::INFINITY;
        }
        if !open.insert(id) {
            return 0.0;
        }
        let mut total = 0.0;
        let children: Vec<_> = node.descendants().skip(1).filter(|n| n.is_element()).collect();
        if children.is_empty() {
            // A pattern without content takes its `href`'s.
            let href = node.attribute(("http://www.w3.org/1999/xlink", "href")).or(node.attribute("href"));
            if let Some(other) = href.and_then(|h| h.trim().strip_prefix('#')) {
                total += expand(other, patterns, memo, open);
            }
        }
        for c in children {
            total += 1.0;
            for r in refs(c) {
                total += expand(r, patterns, memo, open);
            }
            if total > PATTERN_EXPANSION_LIMIT {
                break;
            }
        }
        open.remove(id);
        memo.insert(id, total);
        total
    }
    let mut memo = HashMap::new();
    let mut open = HashSet::new();
    // In document order, so that the message names the same pattern each time.
    let ids = doc.descendants().filter(|n| n.is_element() && n.tag_name().name() == "pattern");
    for id in ids.filter_map(|n| n.attribute("id")) {
        let n = expand(id, &patterns, &mut memo, &mut open);
        if n > PATTERN_EXPANSION_LIMIT {
            let line = patterns.get(id).map_or(1, |p| doc.text_pos_at(p.range().start).row);
            return Some(
                Diagnostic::error(
                    "T0200",
                    format!(
                        "pattern #{id} nests other patterns more than {PATTERN_DEPTH_LIMIT} deep, or so that it \
                         stands for more than {} shapes: the drawing cannot be read in reasonable time",
                        PATTERN_EXPANSION_LIMIT as u64
                    ),
                )
                .at_line(line)
                .with_help("fill the shapes inside the patterns with plain colours, or remove the patterns"),
            );
        }
    }
    None
}

/// How deep elements may nest: usvg's own limit for groups. Deeper nesting
/// is refused before usvg (and taxel's own walks of the XML) could recurse
/// through it: usvg's text parser recurses once per nested `<tspan>`, and
/// 700 of them overflowed a worker thread's stack.
pub(crate) const NESTING_LIMIT: usize = 1024;

/// An error when elements nest more than [`NESTING_LIMIT`] deep, at the line
/// of the first element that does. One pass over the document, keeping each
/// element's depth by its node's index.
pub(crate) fn nested_too_deep(doc: &Document<'_>) -> Option<Diagnostic> {
    let mut depth = vec![0u32; doc.descendants().map(|n| n.id().get_usize() + 1).max().unwrap_or(0)];
    for n in doc.descendants().filter(|n| n.is_element()) {
        let d = n.parent().and_then(|p| depth.get(p.id().get_usize()).copied()).unwrap_or(0) + 1;
        if let Some(slot) = depth.get_mut(n.id().get_usize()) {
            *slot = d;
        }
        if d as usize > NESTING_LIMIT {
            return Some(
                Diagnostic::error(
                    "T0200",
                    format!(
                        "elements nest more than 1,024 deep here (<{}>): the drawing cannot be read",
                        n.tag_name().name()
                    ),
                )
                .at_line(doc.text_pos_at(n.range().start).row)
                .with_help(
                    "the drawing nests groups (or a text's <tspan>s) more than 1,024 deep: ungroup or simplify \
                     it (Inkscape: Edit > Select All, Object > Ungroup)",
                ),
            );
        }
    }
    None
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
mod tests {
    use super::*;

    /// Drawings whose ids the first pass must get right: elements without
    /// ids, ids that already use the inserted prefix, entity expansions
    /// (used twice, quoted either way, nested in a group), Inkscape layers
    /// with labels in other scripts, self-closing and empty elements.
    const DRAWINGS: [&str; 4] = [
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="10mm" height="10mm"><rect width="2" height="2"/><g id="a"><circle r="1"/><path d="M0 0L1 1"/></g><g/></svg>"#,
        r#"<svg xmlns="http://www.w3.org/2000/svg" id="taxel-auto-3">
  <rect width="2" height="2"/><rect id="taxel-auto-x1" width="1" height="1"/>
  <rect width="3" height="3"></rect>
</svg>"#,
        r#"<?xml version="1.0"?>
<!DOCTYPE svg [
  <!ENTITY square "<rect x='10' y='10' width='20' height='20'/>">
  <!ENTITY dot '<g><circle cx="5" cy="5" r="2"/></g>'>
]>
<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm" viewBox="0 0 100 60">
  <g id="v">&square;</g>
  <g>&square;&dot;</g>
  <text x="1" y="2">é &amp; ü</text>
</svg>"#,
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" width="10mm" height="10mm">
  <g inkscape:groupmode="layer" inkscape:label="Calque élévation"><path d="M0 0H5V5Z"/>
    <g inkscape:groupmode="layer" inkscape:label="レイヤー 1"><rect width="1" height="1"/></g>
  </g>
  <g inkscape:groupmode="layer" inkscape:label="tactile: vibrate()" id="l"><rect width="4" height="4"/></g>
</svg>"#,
    ];

    fn parse(text: &str) -> Document<'_> {
        Document::parse_with_options(text, xml_options()).unwrap()
    }

    #[test]
    fn the_first_pass_inserts_exactly_the_keys_usvg_then_reads() {
        for text in DRAWINGS {
            let doc = parse(text);
            let Keys { keys, rewritten } = keys(text, &doc, &mut Vec::new()).unwrap();
            let elements: Vec<Node<'_, '_>> = doc.root_element().descendants().filter(|n| n.is_element()).collect();
            assert_eq!(keys.len(), elements.len(), "{text}");
            // What usvg parses: the same elements, in the same order, each carrying its key as its id.
            let doc2 = parse(&rewritten);
            let seen: Vec<&str> = doc2
                .root_element()
                .descendants()
                .filter(|n| n.is_element())
                .map(|n| n.attribute("id").unwrap_or("(none)"))
                .collect();
            assert_eq!(seen, keys, "{rewritten}");
            // Outside entities, the key is the id as written, or the prefix and
            // the element's position in document order; the prefix is one no
            // id of the drawing starts with.
            let ids: Vec<&str> = elements.iter().filter_map(|n| n.attribute("id")).collect();
            let prefix = (0..)
                .map(|x| format!("taxel-auto-{}", "x".repeat(x)))
                .find(|p| !ids.iter().any(|i| i.starts_with(p.as_str())))
                .unwrap();
            let body = doc.root_element().range().start;
            for (n, (e, k)) in elements.iter().zip(&keys).enumerate() {
                match e.attribute("id") {
                    Some(id) => assert_eq!(k, id),
                    None if e.range().start >= body => assert_eq!(*k, format!("{prefix}{n}")),
                    None => assert!(k.starts_with(&prefix), "{k}"),
                }
            }
            // Taking the inserted ids out again gives the text back, line for line.
            let mut back = rewritten.clone();
            // (Each once: the copies of an entity's element share the one inserted in the entity.)
            let inserted: HashSet<&String> = keys.iter().filter(|k| !ids.contains(&k.as_str())).collect();
            for k in inserted {
                let at = back.find(&format!(" id=\"{k}\"")).or_else(|| back.find(&format!(" id='{k}'"))).unwrap();
                back.replace_range(at..at + k.len() + 6, "");
            }
            assert_eq!(back, text);
        }
    }

    #[test]
    fn the_second_pass_reads_each_element_under_its_key() {
        for text in DRAWINGS {
            let doc = parse(text);
            let first = keys(text, &doc, &mut Vec::new()).unwrap();
            let src = read(text, &doc, first.keys.clone(), None, &["en".to_string()], &mut Vec::new());
            let elements: Vec<Node<'_, '_>> = doc.root_element().descendants().filter(|n| n.is_element()).collect();
            assert_eq!(src.elements.len(), elements.len());
            for (i, (e, node)) in src.elements.iter().zip(&elements).enumerate() {
                assert_eq!(e.key, first.keys[i]);
                assert_eq!(e.node, node.id());
                assert_eq!(e.tag, node.tag_name().name());
                assert!(src.by_key[&e.key].contains(&i));
                assert_eq!(src.get(&e.key, e.parent).map(|(_, f)| f.key.as_str()), Some(e.key.as_str()));
            }
        }
        // Layers, labels and annotations still come from the original text.
        let text = DRAWINGS[3];
        let doc = parse(text);
        let src = read(
            text,
            &doc,
            keys(text, &doc, &mut Vec::new()).unwrap().keys,
            None,
            &["en".to_string()],
            &mut Vec::new(),
        );
        let rect = src.elements.iter().find(|e| e.layers.len() == 2).unwrap();
        assert_eq!(rect.layers, ["Calque élévation", "レイヤー 1"]);
        assert_eq!(rect.line, 3);
        assert!(src.elements.iter().any(|e| e.id == "l" && e.own.is_some()));
    }

    #[test]
    fn a_root_that_is_not_svg_is_refused_by_the_first_pass() {
        let text = "<html><svg/></html>";
        let mut diags = Vec::new();
        assert!(keys(text, &parse(text), &mut diags).is_none());
        assert_eq!(diags.len(), 1);
        assert_eq!(diags[0].code, "T0200");
    }

    /// Patterns filled with patterns, `levels` deep, each of ten rectangles
    /// (the last stroked only), in `style` or as attributes.
    fn nested_patterns(levels: usize, in_style: bool) -> String {
        let mut defs = String::new();
        for k in 0..levels {
            let paint = if k + 1 < levels { format!("url(#p{})", k + 1) } else { "none".into() };
            let fill = if in_style { format!(r#"style="fill: {paint}""#) } else { format!(r#"fill="{paint}""#) };
            defs += &format!(r#"<pattern id="p{k}" width="20" height="20" patternUnits="userSpaceOnUse">"#);
            for j in 0..10 {
                defs += &format!(r#"<rect x="{j}" width="20" height="20" {fill} stroke="green"/>"#);
            }
            defs += "</pattern>";
        }
        format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg"><defs>{defs}</defs><rect width="9" height="9" fill="url(#p0)"/></svg>"#
        )
    }

    /// Patterns nested so deeply that expanding them would not end (usvg
    /// took 24 s on ten levels of ten, librsvg's "billion laughs" test) are
    /// refused before usvg reads them, naming the outermost; hatchings
    /// nested a few levels, and patterns that name each other in a cycle,
    /// are not.
    #[test]
    fn patterns_nested_past_reason_are_refused() {
        for in_style in [false, true] {
            // 11^6 shapes: refused, at the first pattern's line.
            let text = nested_patterns(6, in_style);
            let d = patterns_too_nested(&parse(&text)).expect("refused");
            assert_eq!(d.code, "T0200");
            assert!(d.message.contains("pattern #p0 "), "{}", d.message);
            // 11^5: read.
            assert!(patterns_too_nested(&parse(&nested_patterns(5, in_style))).is_none());
        }
        let cycle = r#"<svg xmlns="http://www.w3.org/2000/svg"><pattern id="a"><rect fill="url(#b)"/></pattern><pattern id="b"><rect fill="url('#a')"/></pattern></svg>"#;
        assert!(patterns_too_nested(&parse(cycle)).is_none());
        // A pattern that takes another's content by `href` counts it.
        let text = nested_patterns(6, false).replace(
            "<defs>",
            r##"<defs><pattern id="q" xmlns:xlink="http://www.w3.org/1999/xlink" xlink:href="#p0"/>"##,
        );
        let d = patterns_too_nested(&parse(&text)).expect("refused");
        assert!(d.message.contains("pattern #q "), "{}", d.message);
    }

    /// Elements nested past 1,024 deep (usvg's limit for groups; 700 nested
    /// `<tspan>`s overflowed a worker's stack inside usvg) are refused
    /// before usvg reads them, at the line of the first too deep; 1,024 are
    /// read. A chain of patterns each painting with the next (100,000 of
    /// them overflowed the stack) is refused past 64 levels.
    #[test]
    fn nesting_past_the_limits_is_refused_before_usvg() {
        let tspans = |n: usize| {
            format!(
                "<svg xmlns=\"http://www.w3.org/2000/svg\">\n<text>{}deep{}</text></svg>",
                "<tspan>".repeat(n),
                "</tspan>".repeat(n)
            )
        };
        // The root is 1 deep, the text 2: 1,022 tspans reach 1,024.
        assert!(nested_too_deep(&parse(&tspans(1022))).is_none());
        let d = nested_too_deep(&parse(&tspans(1023))).expect("refused");
        assert_eq!((d.code, d.line), ("T0200", Some(2)));
        assert!(d.message.contains("(<tspan>)"), "{}", d.message);
        let chain = |n: usize| {
            let defs: String = (0..n)
                .map(|i| {
                    format!(r#"<pattern id="p{i}"><rect width="2" height="2" fill="url(#p{})"/></pattern>"#, i + 1)
                })
                .collect();
            format!(r#"<svg xmlns="http://www.w3.org/2000/svg"><defs>{defs}</defs><rect fill="url(#p0)"/></svg>"#)
        };
        assert!(patterns_too_nested(&parse(&chain(64))).is_none());
        let d = patterns_too_nested(&parse(&chain(65))).expect("refused");
        assert!(d.message.contains("pattern #p0 ") && d.message.contains("64 deep"), "{}", d.message);
    }

    /// An XML comment in a `<style>` (Wikimedia's world maps open theirs with
    /// `/* <!-- Done up to row 1708 --> */`) is cut out of usvg's text, so
    /// that usvg, which reads a style sheet's first text only, applies the
    /// rules after it: the whole map was drawn black. Ids still go in.
    #[test]
    fn comments_in_a_style_sheet_do_not_hide_its_rules_from_usvg() {
        let text = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10\" height=\"10\"><style type=\"text/css\">\n/* <!-- Done up to row 1708 --> */\n.land { fill: #c0c0c0 }\n<!-- and another -->.sea { fill: #0000ff }</style><rect class=\"land\" width=\"4\" height=\"4\"/><rect id=\"s\" class=\"sea\" x=\"5\" width=\"4\" height=\"4\"/></svg>";
        let doc = parse(text);
        let Keys { keys, rewritten } = keys(text, &doc, &mut Vec::new()).unwrap();
        assert!(!rewritten.contains("<!--") && rewritten.contains("/*  */"), "{rewritten}");
        let tree = usvg::Tree::from_str(&rewritten, &usvg::Options::default()).unwrap();
        let fill = |id: &str| match tree.node_by_id(id) {
            Some(usvg::Node::Path(p)) => match p.fill().map(|f| f.paint()) {
                Some(usvg::Paint::Color(c)) => Some((c.red, c.green, c.blue)),
                _ => None,
            },
            _ => None,
        };
        assert_eq!(fill(&keys[2]), Some((0xc0, 0xc0, 0xc0)), "{rewritten}");
        assert_eq!(fill("s"), Some((0, 0, 0xff)), "{rewritten}");
    }
}
