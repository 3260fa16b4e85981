//! Text laid out in a box rather than from a point, which usvg does not
//! draw: Inkscape 0.92's flowed text (`<flowRoot>`) and the HTML in a
//! `<foreignObject>` (Mermaid's labels), read as their editors lay them out.

use resvg::tiny_skia::Transform;
use roxmltree::{Document, Node};

use super::{DEFAULT_EM, anchor, first, hidden, length, own_font_size, parent_transform, use_target, xml_decl};
use crate::drawing::source::Source;
use crate::drawing::walk::{Walked, element_of, length_scale};
use crate::drawing::{Element, Paint, Shape, TextRun, TextShape};

/// Inkscape 0.92's flowed text (`<flowRoot>`, text in a frame), which is not
/// SVG and which no renderer draws, read as the text Inkscape shows: one run
/// per paragraph (`<flowPara>`, also inside a `<flowDiv>`), from the frame's
/// top corner on the side its `text-anchor` names, the first baseline one
/// font size below the frame's top and each paragraph below the lines the
/// last took (Inkscape's wrapping estimated at half a font size a
/// character, `line-height` 1.25 unless the text sets it). Braille is laid
/// out from these runs, as from any text. The frame is the bounding box of
/// the `<flowRegion>`'s first shape (a `<rect>`, a `<path>` or another
/// basic shape, or a `<use>` of one). Returns the texts read, and the
/// flowed texts that could not be: their frame is missing or unreadable, or
/// usvg dropped their group.
pub(crate) fn flowed(
    src: &Source,
    doc: &Document<'_>,
    walked: &Walked,
    mm_per_px: f64,
    root_ts: Transform,
) -> (Vec<(usize, Element)>, Vec<usize>) {
    let (mut read, mut unread) = (Vec::new(), Vec::new());
    for (i, e) in src.elements.iter().enumerate() {
        if e.tag != "flowRoot" || e.in_defs || e.switched_off {
            continue;
        }
        let Some(node) = doc.get_node(e.node) else { continue };
        // (Not drawn, in a hidden layer say: no text, as for a `<text>`.)
        let Some(ts) = parent_transform(src, doc, walked, e, root_ts, false) else { continue };
        match flowed_text(node, ts, mm_per_px) {
            // (An empty one, which a stray click of Inkscape's text tool
            // leaves, is no text.)
            Some(shape) if shape.runs.is_empty() => {}
            Some(shape) => read.push((i, element_of(e, xml_decl(src, i), true, Paint::default(), Shape::Text(shape)))),
            None => unread.push(i),
        }
    }
    (read, unread)
}

/// The text of one `<flowRoot>` ([`flowed`]) drawn in user space `parent`
/// (drawing pixels); `None` when its frame cannot be read. A paragraph that
/// is not displayed, or has no words, makes no run (and a flowed text
/// without runs no braille).
fn flowed_text(node: Node<'_, '_>, parent: Transform, mm_per_px: f64) -> Option<TextShape> {
    let region = node.children().find(|c| c.tag_name().name() == "flowRegion")?;
    let [x0, y0, x1, _] = region.children().filter(|c| c.is_element()).find_map(frame_box)?;
    let s = mm_per_px as f32;
    let ts = Transform::from_scale(s, s).pre_concat(parent).pre_concat(crate::drawing::page::own_transform(node));
    let chain: Vec<Node<'_, '_>> = node.ancestors().filter(|n| n.is_element()).collect();
    let em = chain.iter().rev().fold(DEFAULT_EM, |em, &n| own_font_size(n, em).unwrap_or(em));
    let anchor = anchor(node);
    let x = x0 + (x1 - x0) * anchor;
    let paragraphs = node.children().filter(|c| c.is_element()).flat_map(|c| match c.tag_name().name() {
        "flowPara" => vec![c],
        "flowDiv" => c.children().filter(|p| p.tag_name().name() == "flowPara").collect(),
        _ => Vec::new(),
    });
    // The top of the next paragraph's first line.
    let mut top = y0;
    let mut runs = Vec::new();
    // (`display: none` as an attribute or in the style, on the paragraph or
    // the text: the groups above are usvg's to judge.)
    let hidden = |n: Node<'_, '_>| n.ancestors().take_while(|a| *a != node.parent().unwrap_or(node)).any(hidden);
    for p in paragraphs {
        // Inkscape 0.92 often sets the size and line height on each
        // paragraph (and `line-height: 0.01%` on the text): a paragraph's
        // own, else the text's, and never less than one font size.
        let size = own_font_size(p, em).unwrap_or(em);
        let line = line_height(p, size).or_else(|| line_height(node, size)).unwrap_or(1.25 * size).max(size);
        let text: String =
            p.descendants().filter(|t| t.is_text()).filter_map(|t| t.text()).collect::<Vec<_>>().join("");
        let text = text.split_whitespace().collect::<Vec<_>>().join(" ");
        let lines = lines_taken(&text, size, x1 - x0);
        if !text.is_empty() && !hidden(p) {
            runs.extend(run_at(ts, (x, top + size), text, anchor));
        }
        top += lines * line;
    }
    Some(text_of(runs, em, ts))
}

/// The lines a text of `size` takes in a box `width` wide, its wrapping
/// estimated at half a font size a character (at least one line).
fn lines_taken(text: &str, size: f64, width: f64) -> f64 {
    let per_line = (width / (0.5 * size)).floor().max(1.0);
    (text.chars().count() as f64 / per_line).ceil().max(1.0)
}

/// A run of `text` from `at` (user units under `ts`, which maps them to page
/// mm); `None` where that is not a finite point.
fn run_at(ts: Transform, at: (f64, f64), text: String, anchor: f64) -> Option<TextRun> {
    let (fx, fy) = (at.0 as f32, at.1 as f32);
    let (x_mm, y_mm) = ((ts.sx * fx + ts.kx * fy + ts.tx) as f64, (ts.ky * fx + ts.sy * fy + ts.ty) as f64);
    (x_mm.is_finite() && y_mm.is_finite()).then_some(TextRun { x_mm, y_mm, text, anchor, continues: false })
}

/// The text of `runs`, of font size `em` in user units under `ts`.
fn text_of(runs: Vec<TextRun>, em: f64, ts: Transform) -> TextShape {
    TextShape {
        content: runs.iter().map(|r| r.text.as_str()).collect::<Vec<_>>().join(" "),
        runs,
        font_size_mm: em * length_scale(ts),
        ..Default::default()
    }
}

/// The text of HTML in a `<foreignObject>` (Mermaid's node and edge
/// labels, which no SVG renderer without a browser draws; usvg neither), as
/// a browser lays it out, for braille: a run per line (block elements,
/// `<br>`), from the box's top corner on the side of the first
/// `text-align` its HTML sets (its middle for `center`), the first
/// baseline a font size and half the leading below its top (`line-height`
/// 1.2 unless the HTML sets it), each line below the last, wrapped at the
/// box's width at half a font size a character. The transform comes from
/// the nearest group usvg kept, and the XML's own transforms below it (usvg
/// drops a group left empty, as a label's group is without its HTML); a
/// `<foreignObject>` under a group hidden with `display: none` is not drawn.
/// A `<foreignObject>` that a `<switch>` passes over (draw.io's, beside its
/// `<text>` fallback) is not read.
pub(crate) fn foreign(
    src: &Source,
    doc: &Document<'_>,
    walked: &Walked,
    mm_per_px: f64,
    root_ts: Transform,
) -> Vec<(usize, Element)> {
    let mut out = Vec::new();
    for (i, e) in src.elements.iter().enumerate() {
        if e.tag != "foreignObject" || e.in_defs || e.switched_off {
            continue;
        }
        let Some(node) = doc.get_node(e.node) else { continue };
        let Some(parent) = parent_transform(src, doc, walked, e, root_ts, true) else { continue };
        if let Some(shape) = foreign_text(node, parent, mm_per_px)
            && !shape.runs.is_empty()
        {
            out.push((i, element_of(e, xml_decl(src, i), true, Paint::default(), Shape::Text(shape))));
        }
    }
    out
}

/// `parent` (drawing pixels); `None` when its box is unreadable or empty.
fn foreign_text(node: Node<'_, '_>, parent: Transform, mm_per_px: f64) -> Option<TextShape> {
    let num = |a: &str| first(node, a, DEFAULT_EM);
    let (x0, y0) = (num("x").unwrap_or(0.0), num("y").unwrap_or(0.0));
    let w = num("width").filter(|w| *w > 0.0)?;
    let s = mm_per_px as f32;
    let ts = Transform::from_scale(s, s).pre_concat(parent).pre_concat(crate::drawing::page::own_transform(node));
    let chain: Vec<Node<'_, '_>> = node.ancestors().filter(|n| n.is_element()).collect();
    let em = chain.iter().rev().fold(DEFAULT_EM, |em, &n| own_font_size(n, em).unwrap_or(em));
    // The lines: text broken at block elements and `<br>`, each line's text
    // gathered with its font size (the first that its HTML sets, else the
    // box's).
    let mut lines: Vec<(String, f64)> = vec![(String::new(), em)];
    fn walk(n: Node<'_, '_>, em: f64, lines: &mut Vec<(String, f64)>) {
        for c in n.children() {
            if c.is_text() {
                if let Some(last) = lines.last_mut() {
                    if last.0.trim().is_empty() {
                        last.1 = em;
                    }
                    last.0.push_str(c.text().unwrap_or(""));
                }
            } else if c.is_element() && !hidden(c) {
                let name = c.tag_name().name();
                if matches!(name, "style" | "script" | "title") {
                    continue;
                }
                let em = own_font_size(c, em).unwrap_or(em);
                let block = matches!(
                    name,
                    "p" | "div" | "li" | "br" | "h1" | "h2" | "h3" | "h4" | "h5" | "h6" | "tr" | "ul" | "ol" | "table"
                );
                if block {
                    lines.push((String::new(), em));
                }
                walk(c, em, lines);
                if block {
                    lines.push((String::new(), em));
                }
            }
        }
    }
    walk(node, em, &mut lines);
    let setting = |name: &str| {
        node.descendants().filter(|n| n.is_element()).find_map(|n| {
            n.attribute("style").and_then(|st| {
                st.split(';').find_map(|d| {
                    let (k, v) = d.split_once(':')?;
                    (k.trim() == name).then(|| v.trim().to_string())
                })
            })
        })
    };
    let anchor = match setting("text-align").as_deref() {
        Some("center") => 0.5,
        Some("right" | "end") => 1.0,
        _ => 0.0,
    };
    // `line-height` as a number, a percentage or a length, of the first
    // line's font size.
    let line_height = setting("line-height");
    let leading = |size: f64| line_height_value(line_height.as_deref(), size).unwrap_or(1.2 * size);
    let x = x0 + w * anchor;
    let mut top = y0;
    let mut runs = Vec::new();
    for (text, size) in lines {
        let text = text.split_whitespace().collect::<Vec<_>>().join(" ");
        if text.is_empty() {
            continue;
        }
        let line = leading(size);
        let wraps = lines_taken(&text, size, w);
        runs.extend(run_at(ts, (x, top + (line - size) / 2.0 + size), text, anchor));
        top += wraps * line;
    }
    Some(text_of(runs, em, ts))
}

/// The box `[x0, y0, x1, y1]` of a flowed text's frame shape, in its
/// text's user units (moved by the shape's own `transform`): a `<rect>`, a
/// `<path>`, `<polygon>`, `<circle>` or `<ellipse>`, or a `<use>` of one
/// (moved by its `x`, `y` and `transform`); `None` for anything else or an
/// empty box.
fn frame_box(shape: Node<'_, '_>) -> Option<[f64; 4]> {
    let num = |n: Node<'_, '_>, a: &str| first(n, a, DEFAULT_EM).unwrap_or(0.0);
    let (n, outer) = match shape.tag_name().name() {
        "use" => {
            let id = use_target(shape)?;
            let target = shape.document().descendants().find(|d| d.is_element() && d.attribute("id") == Some(id))?;
            let at = crate::drawing::page::own_transform(shape)
                .pre_translate(num(shape, "x") as f32, num(shape, "y") as f32);
            (target, at)
        }
        _ => (shape, Transform::identity()),
    };
    let points: Vec<(f64, f64)> = match n.tag_name().name() {
        "rect" => {
            let (x, y) = (num(n, "x"), num(n, "y"));
            vec![(x, y), (x + num(n, "width"), y + num(n, "height"))]
        }
        "circle" | "ellipse" => {
            let (cx, cy) = (num(n, "cx"), num(n, "cy"));
            let (rx, ry) = match n.tag_name().name() {
                "circle" => (num(n, "r"), num(n, "r")),
                _ => (num(n, "rx"), num(n, "ry")),
            };
            vec![(cx - rx, cy - ry), (cx + rx, cy + ry)]
        }
        "polygon" | "polyline" => {
            let v: Vec<f64> = svgtypes::NumberListParser::from(n.attribute("points")?).filter_map(Result::ok).collect();
            v.chunks_exact(2).map(|p| (p[0], p[1])).collect()
        }
        "path" => {
            let mut pts = Vec::new();
            for seg in svgtypes::SimplifyingPathParser::from(n.attribute("d")?).filter_map(Result::ok) {
                use svgtypes::SimplePathSegment as S;
                match seg {
                    S::MoveTo { x, y } | S::LineTo { x, y } => pts.push((x, y)),
                    // (The control points bound the curve.)
                    S::CurveTo { x1, y1, x2, y2, x, y } => pts.extend([(x1, y1), (x2, y2), (x, y)]),
                    S::Quadratic { x1, y1, x, y } => pts.extend([(x1, y1), (x, y)]),
                    S::ClosePath => {}
                }
            }
            pts
        }
        _ => return None,
    };
    let ts = outer.pre_concat(crate::drawing::page::own_transform(n));
    let mut b = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
    for (x, y) in points {
        let (x, y) = (x as f32, y as f32);
        let (x, y) = ((ts.sx * x + ts.kx * y + ts.tx) as f64, (ts.ky * x + ts.sy * y + ts.ty) as f64);
        b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
    }
    (b.iter().all(|v| v.is_finite()) && b[2] > b[0]).then_some(b)
}

/// The `line-height` that element `n` sets (its style's or attribute), in
/// user units, `em` being its font size there; `None` when it sets none, or
/// one this reading does not resolve (`normal`).
fn line_height(n: Node<'_, '_>, em: f64) -> Option<f64> {
    let set = n.attribute("style").and_then(|s| {
        s.split(';').find_map(|d| {
            let (k, v) = d.split_once(':')?;
            (k.trim() == "line-height").then(|| v.trim())
        })
    });
    line_height_value(set.or(n.attribute("line-height")), em)
}

/// A `line-height` value in user units, `em` being the font size there: a
/// number or a percentage of the font size, or a length; `None` for none,
/// or one this reading does not resolve (`normal`).
fn line_height_value(v: Option<&str>, em: f64) -> Option<f64> {
    let v = v?.trim();
    let h = match v.parse::<f64>() {
        Ok(k) => Some(k * em),
        Err(_) => match v.strip_suffix('%') {
            Some(p) => p.trim().parse::<f64>().ok().map(|p| p / 100.0 * em),
            None => length(v, em),
        },
    };
    h.filter(|v| v.is_finite() && *v > 0.0)
}
