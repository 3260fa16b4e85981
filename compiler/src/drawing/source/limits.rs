//! Drawings refused before usvg reads them: `<pattern>`s nested into a
//! "billion laughs", and elements nested deeper than usvg can recurse.

use std::collections::{HashMap, HashSet};

use roxmltree::Document;

use crate::diagnostic::Diagnostic;

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
