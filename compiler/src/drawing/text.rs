//! `<text>` elements read from the XML, so that braille never depends on
//! fonts: their runs, positioned in page millimetres the way braille lays
//! them out, and the style in force from the element and its XML ancestors.
//! Glyph outlines, when usvg could lay the text out, come from the walk.
//! Text laid out in a box (`<flowRoot>`, `<foreignObject>`) is read in
//! `text/boxed.rs`.

use std::collections::HashMap;

use rayon::prelude::*;
use resvg::tiny_skia::Transform;
use roxmltree::{Document, Node};

use super::source::{Kind, Source};
use super::walk::{Decl, Walked, element_of, length_scale};
use super::{Element, Paint, Shape, StyledBy, TextRun, TextShape};
use crate::annotation::Style;
use crate::diagnostic::Diagnostic;
use crate::geometry::Polyline;

mod boxed;

pub(crate) use boxed::{flowed, foreign};

/// The declaration in force at a `<text>` from the XML alone (own, style
/// sheet by id/class/layer, then its ancestors', the root `<svg>` included).
fn xml_decl(src: &Source, elem: usize) -> Option<Decl> {
    let mut i = Some(elem);
    while let Some(k) = i {
        let e = &src.elements[k];
        if let Some(d) = &e.own {
            return Some((d.clone(), StyledBy::Annotation));
        }
        if let Some(d) = &e.sheet {
            return Some((d.clone(), StyledBy::StyleSheet));
        }
        i = e.parent;
    }
    None
}

/// The drawing elements of every `<text>` outside `<defs>` that is drawn,
/// with the index of its source element, each given its glyph outline from
/// `outlines` (the walk's, taken from it). A text with a braille style that
/// is not drawn gets a warning.
pub(crate) fn texts(
    src: &Source,
    doc: &Document<'_>,
    walked: &Walked,
    mut outlines: HashMap<usize, Vec<Polyline>>,
    mm_per_px: f64,
    root_ts: Transform,
    diags: &mut Vec<Diagnostic>,
) -> Vec<(usize, Element)> {
    // Each text alone, in parallel, in document order.
    // (A text under a `<switch>` child that is not drawn, another language's
    // label, is no text of this drawing.)
    let drawn = |e: &super::source::Element| !e.in_defs && !e.switched_off;
    let mut texts: Vec<(usize, Option<usize>)> = (0..src.elements.len())
        .filter(|&i| src.elements[i].kind == Kind::Text && drawn(&src.elements[i]))
        .map(|i| (i, None))
        .collect();
    // A `<use>` of a `<text>` (a label kept once in `<defs>`) is that text
    // where the `<use>` puts it.
    texts.extend(used_texts(src, doc).into_iter().filter(|&(_, u)| drawn(&src.elements[u])).map(|(t, u)| (t, Some(u))));
    let made: Vec<Result<Option<(usize, Element)>, Diagnostic>> =
        texts.into_par_iter().map(|(i, by)| text(src, doc, walked, i, by, mm_per_px, root_ts)).collect();
    let mut out = Vec::with_capacity(made.len());
    for m in made {
        match m {
            Ok(Some((i, mut el))) => {
                if let Shape::Text(t) = &mut el.shape {
                    t.outline = outlines.remove(&i).unwrap_or_default();
                }
                out.push((i, el));
            }
            Ok(None) => {}
            Err(d) => diags.push(d),
        }
    }
    out
}

/// The language of a node's text: the nearest `xml:lang` (or HTML's `lang`)
/// on it or an ancestor; `None` when none says, or the nearest is empty
/// (`xml:lang=""`: unknown).
pub(crate) fn lang(node: Node<'_, '_>) -> Option<String> {
    const XML: &str = "http://www.w3.org/XML/1998/namespace";
    let tag = node.ancestors().find_map(|n| n.attribute((XML, "lang")).or_else(|| n.attribute("lang")))?;
    let tag = tag.trim();
    (!tag.is_empty()).then(|| tag.to_string())
}

/// Labels drawn as glyph outlines with their text in a comment, as
/// matplotlib's SVG backend writes every label by default (`svg.fonttype:
/// path`): a group whose first child is the comment (`<!-- Apples -->`) and
/// whose one element is a group of glyphs (`<use>`s of outlines in `<defs>`),
/// its transform putting the text's baseline origin and turning the font's y
/// axis up (`translate(x y) scale(s -s)`, the font size `100 s`). A group
/// of other shapes with a comment is a commented drawing, not a label.
/// Each becomes a text element of the outer group, at that origin, so the
/// label is braille rather than glyph shapes; returned with the source
/// indices of the glyphs' elements, which the label replaces. A comment
/// holding mathtext (`$...$`) is not taken for the text.
pub(crate) fn glyph_labels(
    src: &Source,
    doc: &Document<'_>,
    walked: &Walked,
    mm_per_px: f64,
) -> (Vec<(usize, Element)>, std::collections::HashSet<usize>) {
    let mut labels = Vec::new();
    let mut glyphs = std::collections::HashSet::new();
    if !doc.descendants().any(|n| n.is_comment()) {
        return (labels, glyphs);
    }
    let by_node: HashMap<roxmltree::NodeId, usize> =
        src.elements.iter().enumerate().map(|(i, e)| (e.node, i)).collect();
    for (i, e) in src.elements.iter().enumerate() {
        if e.tag != "g" || e.in_defs || e.switched_off {
            continue;
        }
        let Some(node) = doc.get_node(e.node) else { continue };
        let mut kids = node.children().filter(|c| c.is_element() || c.is_comment());
        let (Some(comment), Some(inner), None) = (kids.next(), kids.next(), kids.next()) else { continue };
        let said = comment.text().map(str::trim).unwrap_or("");
        if !comment.is_comment() || said.is_empty() || said.contains('$') || inner.tag_name().name() != "g" {
            continue;
        }
        // Glyphs, not a drawing someone commented: uses of outlines kept in
        // `<defs>`, under a uniform scale that turns the font's y axis up
        // (`scale(s -s)`), as a font's outlines are.
        let mut parts = inner.children().filter(|c| c.is_element() && c.tag_name().name() != "defs").peekable();
        let glyphs_only = parts.peek().is_some() && parts.all(|c| c.tag_name().name() == "use");
        let Some(inner_ts) = inner.attribute("transform").and_then(|t| t.parse::<svgtypes::Transform>().ok()) else {
            continue;
        };
        // A uniform scale, maybe rotated (an axis title turned on its side),
        // that mirrors: the font's y axis turned up.
        let (a, b, c, d) = (inner_ts.a, inner_ts.b, inner_ts.c, inner_ts.d);
        let det = a * d - b * c;
        let tol = 1e-9 * (a * a + b * b);
        let font_axes = det < 0.0 && (a * c + b * d).abs() <= tol && (a * a + b * b - c * c - d * d).abs() <= tol;
        if !(glyphs_only && font_axes) {
            continue;
        }
        // The group usvg kept gives the transform (it has an id); if usvg
        // dropped it, the label is not drawn.
        let Some(&group_ts) = walked.group_ts.get(&e.key) else { continue };
        let s = mm_per_px as f32;
        let ts = Transform::from_scale(s, s).pre_concat(group_ts);
        let (ox, oy) = (inner_ts.e as f32, inner_ts.f as f32);
        let (x_mm, y_mm) = ((ts.sx * ox + ts.kx * oy + ts.tx) as f64, (ts.ky * ox + ts.sy * oy + ts.ty) as f64);
        let font_size_mm = 100.0 * det.abs().sqrt() * length_scale(ts);
        if !(x_mm.is_finite() && y_mm.is_finite()) {
            continue;
        }
        let text = said.split_whitespace().collect::<Vec<_>>().join(" ");
        let run = TextRun { x_mm, y_mm, text: text.clone(), anchor: 0.0, continues: false };
        let shape = TextShape { content: text, runs: vec![run], font_size_mm, ..Default::default() };
        labels.push((i, element_of(e, xml_decl(src, i), true, Paint::default(), Shape::Text(shape))));
        glyphs.extend(inner.descendants().filter_map(|d| by_node.get(&d.id())).copied());
    }
    (labels, glyphs)
}

/// The `<text>` elements that `<use>` elements show, a text itself or the
/// texts of a group (`<g>`): (the text's source index, the `<use>`'s), in
/// document order of the `<use>`s.
fn used_texts(src: &Source, doc: &Document<'_>) -> Vec<(usize, usize)> {
    if !src.elements.iter().any(|e| e.tag == "use") {
        return Vec::new();
    }
    let by_id: HashMap<&str, usize> = src
        .elements
        .iter()
        .enumerate()
        .filter(|(_, e)| matches!(e.tag.as_str(), "text" | "g" | "symbol") && !e.id.is_empty())
        .map(|(i, e)| (e.id.as_str(), i))
        .collect();
    let by_node: HashMap<roxmltree::NodeId, usize> =
        src.elements.iter().enumerate().filter(|(_, e)| e.kind == Kind::Text).map(|(i, e)| (e.node, i)).collect();
    let mut out = Vec::new();
    for (u, e) in src.elements.iter().enumerate().filter(|(_, e)| e.tag == "use") {
        let Some(node) = doc.get_node(e.node) else { continue };
        let Some(&target) = use_target(node).and_then(|id| by_id.get(id)) else { continue };
        let Some(target) = doc.get_node(src.elements[target].node) else { continue };
        // (A group's texts in document order; the target itself when it is one.)
        out.extend(target.descendants().filter_map(|n| by_node.get(&n.id())).map(|&t| (t, u)));
    }
    out
}

/// The id a `<use>` names (`href` or `xlink:href`, `#id`).
fn use_target<'a>(u: Node<'a, '_>) -> Option<&'a str> {
    u.attribute((XLINK_NS, "href")).or(u.attribute("href"))?.trim().strip_prefix('#')
}

/// The drawing element of the `<text>` that is source element `i`, shown
/// by itself or, with `by`, by that `<use>` (whose place, transform, name
/// and styles it then takes), without its glyph outline; `None` when it is
/// not drawn, a warning when it is not drawn and asks for braille.
fn text(
    src: &Source,
    doc: &Document<'_>,
    walked: &Walked,
    i: usize,
    by: Option<usize>,
    mm_per_px: f64,
    root_ts: Transform,
) -> Result<Option<(usize, Element)>, Diagnostic> {
    // The element on the page: the text, or the `<use>` that shows it.
    let t = i;
    let i = by.unwrap_or(t);
    let e = &src.elements[i];
    let decl = match by {
        Some(u) => {
            // The text's own annotation, or its groups' up to the one the
            // `<use>` names; then the `<use>`'s and its groups'.
            let target = doc.get_node(src.elements[u].node).and_then(use_target);
            let mut k = Some(t);
            let mut found = None;
            while let Some(e) = k.and_then(|j| src.elements.get(j)) {
                if let Some(d) = &e.own {
                    found = Some((d.clone(), StyledBy::Annotation));
                    break;
                }
                if Some(e.id.as_str()) == target {
                    break;
                }
                k = e.parent;
            }
            found.or_else(|| xml_decl(src, i))
        }
        None => xml_decl(src, i),
    };
    let braille = decl.as_ref().is_some_and(|(d, _)| d.styles().iter().any(|s| matches!(s, Style::Braille(_))));
    let parent_ts = parent_transform(src, doc, walked, e, root_ts, false);
    let Some(node) = doc.get_node(src.elements[t].node) else { return Ok(None) };
    let transform = |n: Node<'_, '_>| {
        n.attribute("transform")
            .and_then(|t| t.parse::<svgtypes::Transform>().ok())
            .map_or(Transform::identity(), |t| {
                Transform::from_row(t.a as f32, t.b as f32, t.c as f32, t.d as f32, t.e as f32, t.f as f32)
            })
    };
    // A `<use>` adds its transform, then its `x` and `y`, then those of the
    // groups from the one it names down to the text, before the text's own.
    let by_ts = match by.and_then(|u| doc.get_node(src.elements[u].node)) {
        Some(u) => {
            let at = |a: &str| first(u, a, DEFAULT_EM).unwrap_or(0.0) as f32;
            let mut ts = Transform::identity();
            if node.attribute("id") != use_target(u) {
                for a in node.ancestors().skip(1) {
                    ts = transform(a).pre_concat(ts);
                    let target = a.attribute("id") == use_target(u);
                    if target && a.tag_name().name() == "symbol" {
                        // A symbol's viewBox maps onto the `<use>`'s size (else its own).
                        ts = viewport(a, &[u, a]).pre_concat(ts);
                    }
                    if target || a.parent_element().is_none() {
                        break;
                    }
                }
            }
            transform(u).pre_translate(at("x"), at("y")).pre_concat(ts)
        }
        None => Transform::identity(),
    };
    let own_ts = by_ts.pre_concat(transform(node));
    let s = mm_per_px as f32;
    let ts = parent_ts.map(|pts| Transform::from_scale(s, s).pre_concat(pts).pre_concat(own_ts));
    let Some(ts) = ts.filter(|ts| ts.sx.is_finite() && ts.ty.is_finite() && node.attribute("display") != Some("none"))
    else {
        if braille {
            return Err(Diagnostic::warning("T0301", "this text is not drawn; no braille is made for it")
                .with_element(&e.name)
                .at_line(e.line));
        }
        return Ok(None);
    };
    let anchor = anchor(node);
    let laid = walked.text_paint.get(&i).copied();
    // The font size in the text's user units, for lengths in `em` (usvg's
    // size, when it laid the text out, is in millimetres on the page).
    let scale = length_scale(ts);
    let em = match laid {
        Some((_, size_mm)) if scale > 0.0 => size_mm / scale,
        // (No layout, for want of fonts: the sizes the XML sets, from the root down.)
        _ => {
            let chain: Vec<Node<'_, '_>> = node.ancestors().filter(|n| n.is_element()).collect();
            chain.iter().rev().fold(DEFAULT_EM, |em, &n| own_font_size(n, em).unwrap_or(em))
        }
    };
    // Without a layout, the font size on the page is the XML's too.
    let (paint, font_size_mm) = laid.unwrap_or_else(|| {
        let size = em * scale;
        (Paint::default(), if size.is_finite() && size > 0.0 { size } else { 16.0 * s as f64 })
    });
    let (mut ux, mut uy) = (0.0f64, 0.0f64);
    let mut runs = Vec::new();
    // Text turned on its side (an axis's tick labels and title, turned 90°):
    // braille is written level, so each run is placed at its middle along
    // its own direction (its length estimated at half a font size a
    // character), centred there, rather than from an anchor that lies at
    // one of its ends on the page's vertical.
    let upright = ts.ky.abs() <= ts.sx.abs();
    for run in runs_of(node, em) {
        let continues = run.x.is_none() && run.y.is_none() && !runs.is_empty();
        ux = run.x.unwrap_or(ux);
        uy = run.y.unwrap_or(uy);
        let (at_x, anchor) = if upright || continues {
            (ux, anchor)
        } else {
            (ux + (0.5 - anchor) * 0.5 * em * run.text.trim().chars().count() as f64, 0.5)
        };
        let (fx, fy) = (at_x as f32, uy as f32);
        runs.push(TextRun {
            x_mm: (ts.sx * fx + ts.kx * fy + ts.tx) as f64,
            y_mm: (ts.ky * fx + ts.sy * fy + ts.ty) as f64,
            text: run.text,
            anchor,
            continues,
        });
    }
    let shape = TextShape {
        content: runs.iter().map(|r| r.text.as_str()).collect::<Vec<_>>().join(" "),
        runs,
        font_size_mm,
        ..Default::default()
    };
    Ok(Some((i, element_of(e, decl, true, paint, Shape::Text(shape)))))
}

/// The transform of the user space an element `e` is drawn in (its
/// parent's), in drawing pixels: the nearest group usvg kept gives it; if
/// usvg dropped that group, the element is not drawn (`None`), unless
/// `through_dropped`: then the dropped groups' own `transform`s from the XML
/// are taken on the way up (usvg drops a group left empty, as a
/// `<foreignObject>`'s is), and only one hidden with `display: none`, or
/// with a transform that is not invertible, hides it. A nested `<svg>` on
/// the way adds its viewport's transform (usvg's group for it carries no id
/// to find it by).
fn parent_transform(
    src: &Source,
    doc: &Document<'_>,
    walked: &Walked,
    e: &super::source::Element,
    root_ts: Transform,
    through_dropped: bool,
) -> Option<Transform> {
    let mut inner = Transform::identity();
    let mut p = e.parent;
    while let Some(k) = p {
        let a = &src.elements[k];
        if a.parent.is_none() {
            break;
        }
        if a.kind == Kind::Group {
            match walked.group_ts.get(&a.key) {
                Some(g) => return Some(g.pre_concat(inner)),
                None if !through_dropped => return None,
                None => {}
            }
        }
        if a.tag == "svg" {
            inner = doc.get_node(a.node).map_or(inner, |n| nested_svg_transform(n).pre_concat(inner));
        } else if through_dropped {
            let n = doc.get_node(a.node)?;
            let own = super::page::own_transform(n);
            if hidden(n) || !own.is_finite() || own.invert().is_none() {
                return None;
            }
            inner = own.pre_concat(inner);
        }
        p = a.parent;
    }
    Some(root_ts.pre_concat(inner))
}

/// Whether element `n` is hidden by `display: none` (attribute or style).
fn hidden(n: Node<'_, '_>) -> bool {
    n.attribute("display") == Some("none")
        || n.attribute("style").is_some_and(|st| {
            st.split(';').any(|d| d.split_once(':').is_some_and(|(k, v)| k.trim() == "display" && v.trim() == "none"))
        })
}

/// The transform a nested `<svg>` gives its content, as usvg reads it: its
/// own `transform`, its `x` and `y`, then its `viewBox` mapped onto its
/// `width` and `height` (where one is not given, or is a percentage of a
/// viewport this reading does not follow, the `viewBox`'s own: a scale of 1).
fn nested_svg_transform(n: Node<'_, '_>) -> Transform {
    let (x, y) = (first(n, "x", DEFAULT_EM).unwrap_or(0.0) as f32, first(n, "y", DEFAULT_EM).unwrap_or(0.0) as f32);
    super::page::own_transform(n).pre_translate(x, y).pre_concat(viewport(n, &[n]))
}

/// The `viewBox` of `n` (a nested `<svg>` or a `<symbol>`) mapped onto the
/// `width` and `height` the first of `sized_by` gives (a `<use>`'s before
/// the element's own), else onto the `viewBox`'s own size: a scale of 1.
fn viewport(n: Node<'_, '_>, sized_by: &[Node<'_, '_>]) -> Transform {
    let vb = n.attribute("viewBox").and_then(|v| v.parse::<svgtypes::ViewBox>().ok());
    let size = |a: &str, of_box: Option<f64>| {
        sized_by.iter().find_map(|m| first(*m, a, DEFAULT_EM)).or(of_box).unwrap_or(0.0) as f32
    };
    let (w, h) = (size("width", vb.map(|v| v.w)), size("height", vb.map(|v| v.h)));
    super::page::view_box_transform(n, w, h)
}

/// CSS's initial font size, in user units (pixels).
const DEFAULT_EM: f64 = 16.0;

/// One positioned run of a `<text>`: a start position (user units, when given) and its text.
#[derive(Debug, Clone, PartialEq)]
struct Run {
    x: Option<f64>,
    y: Option<f64>,
    text: String,
}

/// The first length of attribute `a` of `n` (a list such as `x="10 12 14"`
/// starts at its first), in user units, `em` being the font size there in
/// user units; `None` when absent, unreadable or a percentage (of the
/// viewport, which a text's position seldom uses).
fn first(n: Node<'_, '_>, a: &str, em: f64) -> Option<f64> {
    let v = n.attribute(a)?;
    let tok = v.split(|c: char| c.is_whitespace() || c == ',').find(|t| !t.is_empty())?;
    length(tok, em)
}

/// One length in user units, `em` being the font size in user units (an
/// `ex` is taken as half of it, as usvg does); `None` when unreadable or a
/// percentage.
fn length(tok: &str, em: f64) -> Option<f64> {
    let l: svgtypes::Length = tok.trim().parse().ok()?;
    let per = match l.unit {
        svgtypes::LengthUnit::Mm => 96.0 / 25.4,
        svgtypes::LengthUnit::Cm => 96.0 / 2.54,
        svgtypes::LengthUnit::In => 96.0,
        svgtypes::LengthUnit::Pt => 96.0 / 72.0,
        svgtypes::LengthUnit::Pc => 16.0,
        svgtypes::LengthUnit::Em => em,
        svgtypes::LengthUnit::Ex => em / 2.0,
        svgtypes::LengthUnit::Percent => return None,
        _ => 1.0,
    };
    Some(l.number * per).filter(|v| v.is_finite())
}

/// The font size an element of a text sets itself (its `font-size`
/// attribute, or its style's `font-size` or `font` shorthand, as
/// matplotlib writes `font: 10px 'DejaVu Sans'`), in user units, `em` being
/// its parent's; `None` when it sets none, or one this reading does not
/// resolve (a keyword such as `larger`, or a percentage: the parent's size
/// stays).
fn own_font_size(n: Node<'_, '_>, em: f64) -> Option<f64> {
    let declared = |name: &str| {
        n.attribute("style").and_then(|s| {
            s.split(';').find_map(|d| {
                let (k, v) = d.split_once(':')?;
                (k.trim() == name).then(|| v.trim())
            })
        })
    };
    // The shorthand's size is its first token that reads as a length
    // (before any `/line-height`).
    let shorthand = || {
        declared("font")?.split_whitespace().find_map(|t| {
            t.split('/').next().and_then(|t| t.starts_with(|c: char| c.is_ascii_digit() || c == '.').then_some(t))
        })
    };
    let size = declared("font-size").or_else(shorthand).or(n.attribute("font-size"))?;
    length(size, em).filter(|&v| v > 0.0)
}

/// The runs of a `<text>` element, `em` being its font size in user units:
/// a new run wherever `x` or `y` is given (on the text or a `<tspan>`), at
/// the current text position moved by the element's `dx` and `dy` (which
/// move the position even where no run starts, as SVG's do: a line written
/// as `<tspan x="0" dy="1.2em">` is a run one line below the last);
/// whitespace collapsed as SVG does by default.
fn runs_of(text: Node<'_, '_>, em: f64) -> Vec<Run> {
    /// The current text position in user units, as far as it is known.
    struct At {
        x: Option<f64>,
        y: Option<f64>,
    }
    impl At {
        /// Moves to element `n`'s `x`, `y` (where given), then by its `dx`,
        /// `dy`; whether it gave `x` or `y` (a run starts there).
        fn step(&mut self, n: Node<'_, '_>, em: f64) -> bool {
            let (x, y) = (first(n, "x", em), first(n, "y", em));
            self.x = x.or(self.x);
            self.y = y.or(self.y);
            if let Some(dx) = first(n, "dx", em) {
                self.x = Some(self.x.unwrap_or(0.0) + dx);
            }
            if let Some(dy) = first(n, "dy", em) {
                self.y = Some(self.y.unwrap_or(0.0) + dy);
            }
            x.is_some() || y.is_some()
        }
    }
    fn walk(n: Node<'_, '_>, em: f64, at: &mut At, runs: &mut Vec<Run>) {
        for c in n.children() {
            if c.is_text() {
                if let Some(t) = runs.last_mut() {
                    t.text.push_str(c.text().unwrap_or(""));
                }
            } else if c.is_element() && matches!(c.tag_name().name(), "tspan" | "a") {
                let em = own_font_size(c, em).unwrap_or(em);
                let (before_x, before_y) = (at.x, at.y);
                if at.step(c, em) {
                    runs.push(Run { x: at.x, y: at.y, text: String::new() });
                } else if (at.x, at.y) != (before_x, before_y) && runs.last().is_some_and(|r| r.text.trim().is_empty())
                {
                    // A shift before any text of the run (`<text x="0"
                    // y="9"><tspan dy="0.71em">`) moves the run itself.
                    if let Some(r) = runs.last_mut() {
                        (r.x, r.y) = (at.x, at.y);
                    }
                }
                walk(c, em, at, runs);
            } else if c.is_element() && c.tag_name().name() == "textPath" {
                // Text along a path (a street's name on a map): braille does
                // not bend, so it starts where the path starts.
                let (x, y) = path_start(c).unzip();
                (at.x, at.y) = (x.or(at.x), y.or(at.y));
                runs.push(Run { x, y, text: String::new() });
                walk(c, em, at, runs);
            }
        }
    }
    let mut at = At { x: None, y: None };
    at.step(text, em);
    let mut out = vec![Run { x: at.x, y: at.y, text: String::new() }];
    walk(text, em, &mut at, &mut out);
    for r in &mut out {
        r.text = r.text.split_whitespace().collect::<Vec<_>>().join(" ");
    }
    out.retain(|r| !r.text.is_empty());
    out
}

/// Where the path of a `<textPath>` starts, in its text's user units: its
/// `path` attribute (SVG 2), else the first point of the `<path>` its `href`
/// names, moved by that path's own `transform` (SVG: a supplemental
/// transform in the text's coordinates). `None` when neither is readable.
fn path_start(text_path: Node<'_, '_>) -> Option<(f64, f64)> {
    let d = match text_path.attribute("path") {
        Some(d) => (d, None),
        None => {
            let href = text_path.attribute((XLINK_NS, "href")).or(text_path.attribute("href"))?;
            let id = href.trim().strip_prefix('#')?;
            let path = text_path.document().descendants().find(|n| n.is_element() && n.attribute("id") == Some(id))?;
            (path.attribute("d")?, path.attribute("transform"))
        }
    };
    let (x, y) = match svgtypes::PathParser::from(d.0).next()?.ok()? {
        svgtypes::PathSegment::MoveTo { x, y, .. } => (x, y),
        _ => return None,
    };
    let t = d.1.and_then(|t| t.parse::<svgtypes::Transform>().ok()).unwrap_or_default();
    Some((t.a * x + t.c * y + t.e, t.b * x + t.d * y + t.f)).filter(|p| p.0.is_finite() && p.1.is_finite())
}

/// The XLink namespace, of `xlink:href`.
const XLINK_NS: &str = "http://www.w3.org/1999/xlink";

/// The text's `text-anchor` as a fraction of the run's width to shift left (0, ½ or 1).
fn anchor(text: Node<'_, '_>) -> f64 {
    let from_style = text.attribute("style").and_then(|s| {
        s.split(';').find_map(|d| {
            let (k, v) = d.split_once(':')?;
            (k.trim() == "text-anchor").then(|| v.trim())
        })
    });
    match from_style.or(text.attribute("text-anchor")) {
        Some("middle") => 0.5,
        Some("end") => 1.0,
        _ => 0.0,
    }
}
