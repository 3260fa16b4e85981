//! From SVG text to a [`Drawing`]: the XML side (annotations, labels, ids,
//! lines), usvg's resolved tree, the page size, then every drawn element
//! with its styles and exact geometry.

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::sync::{Arc, OnceLock};

use super::source::{self, Source};
use super::{Drawing, Page, page, text, walk};
use crate::annotation::Declaration;
use crate::diagnostic::Diagnostic;
use crate::options::CompileOptions;

/// What [`resolve`] returns: the drawing (absent when the SVG could not be
/// read at all; present, though possibly with error diagnostics such as a
/// malformed annotation, otherwise), every diagnostic found on the way
/// (malformed annotations, the page size, shapes that were asked for but are
/// not drawn), and the font faces its text used.
#[derive(Debug, Clone)]
pub struct Resolved {
    /// The drawing, unless an error prevented it.
    pub drawing: Option<Drawing>,
    /// Everything resolution had to say.
    pub diagnostics: Vec<Diagnostic>,
    /// The font faces of `CompileOptions::fonts` that the text was laid out with, sorted.
    pub fonts_used: Vec<FontFace>,
}

/// Where the fonts come from: called once, on usvg's side, when usvg is
/// about to need them (so a caller can load them while the XML is parsed and
/// read); `None` for no fonts.
pub type Fonts<'a> = &'a (dyn Fn() -> Option<Arc<usvg::fontdb::Database>> + Sync);

/// usvg's options: the caller's fonts (none when it gave none), and no file
/// IO: an image that names a file is not read but stands as a blank
/// [`LINKED_IMAGE`], so that it stays in the drawing as an image (left out,
/// and named in messages) instead of vanishing. usvg drops an image it cannot
/// resolve, and a drawing of a linked scan then read as "no elements that
/// are drawn".
pub(crate) fn usvg_options(
    fonts: Option<&Arc<usvg::fontdb::Database>>,
    languages: &[String],
) -> usvg::Options<'static> {
    static NO_FONTS: OnceLock<Arc<usvg::fontdb::Database>> = OnceLock::new();
    static LINKED: OnceLock<Arc<Vec<u8>>> = OnceLock::new();
    let fontdb =
        fonts.cloned().unwrap_or_else(|| NO_FONTS.get_or_init(|| Arc::new(usvg::fontdb::Database::new())).clone());
    let mut uopt = usvg::Options { fontdb, languages: languages.to_vec(), ..usvg::Options::default() };
    uopt.image_href_resolver.resolve_string =
        Box::new(|_, _| Some(usvg::ImageKind::GIF(LINKED.get_or_init(|| Arc::new(LINKED_IMAGE.to_vec())).clone())));
    uopt
}

/// What a linked image stands as: a blank 1 x 1 GIF (usvg reads its size
/// from the header; nothing decodes it). Its box is the `<image>`'s, fitted
/// as a square by the default `preserveAspectRatio`.
const LINKED_IMAGE: [u8; 43] = [
    0x47, 0x49, 0x46, 0x38, 0x39, 0x61, 0x01, 0x00, 0x01, 0x00, 0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0xff, 0xff, 0xff,
    0x21, 0xf9, 0x04, 0x01, 0x00, 0x00, 0x00, 0x00, 0x2c, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x01, 0x00, 0x00, 0x02,
    0x02, 0x44, 0x01, 0x00, 0x3b,
];

/// A font face that a drawing's text was laid out with.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct FontFace {
    /// The file it was loaded from; `None` for a face loaded from memory.
    pub path: Option<PathBuf>,
    /// Its index in a font collection file (0 for a single font).
    pub index: u32,
    /// Its first family name.
    pub family: String,
    /// Its PostScript name.
    pub post_script_name: String,
}

/// The faces of `db` that the text of `tree` uses, sorted, each once.
fn faces_used(tree: &usvg::Tree) -> Vec<FontFace> {
    fn visit(g: &usvg::Group, ids: &mut BTreeSet<usvg::fontdb::ID>) {
        for c in g.children() {
            match c {
                usvg::Node::Group(g) => visit(g, ids),
                usvg::Node::Text(t) => {
                    ids.extend(t.layouted().iter().flat_map(|s| s.positioned_glyphs.iter().map(|g| g.font)));
                }
                _ => {}
            }
            // Text in clip paths and masks is laid out too.
            c.subroots(|g| visit(g, ids));
        }
    }
    let mut ids = BTreeSet::new();
    visit(tree.root(), &mut ids);
    let db = tree.fontdb();
    let mut faces: Vec<FontFace> = ids
        .into_iter()
        .filter_map(|id| db.face(id))
        .map(|f| FontFace {
            path: match &f.source {
                usvg::fontdb::Source::File(p) | usvg::fontdb::Source::SharedFile(p, _) => Some(p.clone()),
                usvg::fontdb::Source::Binary(_) => None,
            },
            index: f.index,
            family: f.families.first().map(|(name, _)| name.clone()).unwrap_or_default(),
            post_script_name: f.post_script_name.clone(),
        })
        .collect();
    faces.sort();
    faces.dedup();
    faces
}

/// The font faces of `fonts` that the text of `svg_text` is laid out with,
/// without building the drawing (for a content hash that must cover them;
/// the same as [`Resolved::fonts_used`]). Empty when the SVG cannot be read
/// or has no text.
pub fn fonts_used(svg_text: &str, fonts: &Arc<usvg::fontdb::Database>, languages: &[String]) -> Vec<FontFace> {
    if !svg_text.contains("<text") {
        return Vec::new();
    }
    let Ok(doc) = roxmltree::Document::parse_with_options(svg_text, source::xml_options()) else {
        return Vec::new();
    };
    usvg::Tree::from_xmltree(&doc, &usvg_options(Some(fonts), languages)).map_or(Vec::new(), |t| faces_used(&t))
}

/// Resolves an annotated SVG into a [`Drawing`] for `opts` (its profile
/// decides the page when the drawing has no physical size; its style sheet
/// takes part in style resolution): the drawing as written, before the
/// pipeline adapts it to the device (`crate::pipeline::resolve` does that:
/// automatic styles, `--region`, `--fit`). No panic is reachable from the
/// input.
///
/// ```
/// use taxel_compiler::{CompileOptions, drawing::{self, Shape}};
/// use taxel_format::profiles;
///
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="60mm" height="40mm" viewBox="0 0 60 40">
///   <rect id="box" x="10" y="10" width="30" height="20" data-tactile="vibrate()"/>
/// </svg>"#;
/// let r = drawing::resolve(svg, &CompileOptions::new(profiles::builtin("stress2").unwrap()));
/// let d = r.drawing.unwrap();
/// assert_eq!(d.elements[0].id, "box");
/// let (x0, y0, x1, y1) = d.elements[0].bounds().unwrap();
/// assert!((x0 - 10.0).abs() < 1e-4 && (y0 - 10.0).abs() < 1e-4 && (x1 - 40.0).abs() < 1e-4 && (y1 - 30.0).abs() < 1e-4);
/// ```
pub fn resolve(svg_text: &str, opts: &CompileOptions) -> Resolved {
    let mut diagnostics = Vec::new();
    let mut fonts_used = Vec::new();
    let drawing = run(svg_text, opts, &|| opts.fonts.clone(), &mut diagnostics, &mut fonts_used);
    Resolved { drawing, diagnostics, fonts_used }
}

/// [`resolve`], adding to `diags` and `fonts_used`, with the fonts of
/// `fonts` (not `opts.fonts`).
pub(crate) fn run(
    text: &str,
    opts: &CompileOptions,
    fonts: Fonts<'_>,
    diags: &mut Vec<Diagnostic>,
    fonts_used: &mut Vec<FontFace>,
) -> Option<Drawing> {
    let doc = source::parse_xml(text, diags)?;
    if let Some(d) = source::nested_too_deep(&doc).or_else(|| source::patterns_too_nested(&doc)) {
        diags.push(d);
        return None;
    }
    let source::Keys { keys, rewritten } = source::keys(text, &doc, diags)?;
    // usvg needs only the rewritten text: it parses and converts the drawing
    // on this thread while the rest of the XML side (annotations, labels,
    // layers, style sheet rules, lines) is read on the other (on the
    // 1,000-region map, a third of the time before the layers used one core).
    // usvg's side, which allocates the most, stays on the calling thread.
    let (converted, src) = rayon::join(
        || {
            let doc2 = roxmltree::Document::parse_with_options(&rewritten, source::xml_options()).ok()?;
            let tree = usvg::Tree::from_xmltree(&doc2, &usvg_options(fonts().as_ref(), &opts.languages));
            Some((doc2, tree))
        },
        || source::read(text, &doc, keys, opts.style.as_ref(), &opts.languages, diags),
    );
    let (doc2, tree) = converted?;
    let tree = match tree {
        Ok(t) => t,
        Err(e) => {
            diags.push(Diagnostic::error("T0200", format!("the SVG could not be read: {e}")).with_help(read_help(&e)));
            return None;
        }
    };
    let (w, h) = (tree.size().width(), tree.size().height());
    let root = doc.root_element();
    let sizing = page::page(root, w as f64, h as f64, opts.width_mm, &opts.profile, diags);
    let root_ts = page::root_transform(root, w, h);
    let mut walked = walk::walk(&tree, &src, opts.style.as_ref(), sizing.scale, opts.flattening);
    let outlines = std::mem::take(&mut walked.text_outlines);
    *fonts_used = faces_used(&tree);
    // usvg's tree and the second parse are freed on another thread while
    // the text is placed: on the map at the input limit, freeing them
    // one after the other was a tenth of a second of the one thread working.
    let (texts, ()) = rayon::join(
        || text::texts(&src, &doc, &walked, outlines, sizing.scale, root_ts, diags),
        move || drop((tree, doc2)),
    );
    not_drawn(&src, &walked, diags);
    // Inkscape 0.92's flowed text, which usvg does not draw: read as text.
    let (flows, unread) = text::flowed(&src, &doc, &walked, sizing.scale, root_ts);
    unread_flowed_text(&src, &doc, &unread, diags);
    // HTML in a `<foreignObject>` (Mermaid's labels), which usvg does not draw: read as text.
    let html = text::foreign(&src, &doc, &walked, sizing.scale, root_ts);
    // Labels matplotlib drew as glyphs, with their text in a comment: braille, not shapes.
    let (labels, glyphs) = text::glyph_labels(&src, &doc, &walked, sizing.scale);
    let mut elements: Vec<(usize, super::Element)> = walked.elements;
    if !glyphs.is_empty() {
        elements.retain(|(i, _)| !glyphs.contains(i));
    }
    elements.extend(texts);
    elements.extend(flows);
    elements.extend(html);
    elements.extend(labels);
    // Document order: a `<use>`'s copies sit at the `<use>`, in usvg's order (the sort is stable).
    elements.sort_by_key(|(i, _)| *i);
    // Each text's language, for its braille table.
    for (i, e) in &mut elements {
        if let super::Shape::Text(t) = &mut e.shape {
            t.lang = src.elements.get(*i).and_then(|s| doc.get_node(s.node)).and_then(text::lang);
        }
    }
    let title = root
        .children()
        .find(|c| c.is_element() && c.tag_name().name() == "title")
        .and_then(|t| t.text())
        .unwrap_or("")
        .trim()
        .to_string();
    let page = Page {
        width_mm: sizing.width_mm,
        height_mm: sizing.height_mm,
        scale: sizing.scale * root_ts.sx as f64,
        offset_mm: (sizing.scale * root_ts.tx as f64, sizing.scale * root_ts.ty as f64),
        sheet_mm: None,
    };
    Some(Drawing { page, title, elements: elements.into_iter().map(|(_, e)| e).collect() })
}

/// Warns about shapes that carry their own annotation but that usvg does not draw.
fn not_drawn(src: &Source, walked: &walk::Walked, diags: &mut Vec<Diagnostic>) {
    const SHAPES: &[&str] = &["path", "rect", "circle", "ellipse", "line", "polyline", "polygon"];
    for (i, e) in src.elements.iter().enumerate() {
        let annotated = matches!(&e.own, Some(Declaration::Styles(s)) if !s.is_empty());
        // (Another language's child of a `<switch>` is not drawn, by design.)
        if annotated && !e.in_defs && !e.switched_off && SHAPES.contains(&e.tag.as_str()) && !walked.seen.contains(&i) {
            diags.push(
                Diagnostic::warning(
                    NOT_DRAWN,
                    "this shape is not drawn (display: none, zero size or no geometry); nothing is rendered for it",
                )
                .with_element(&e.name)
                .at_line(e.line),
            );
        }
    }
}

/// T0306 for each Inkscape flowed text (`<flowRoot>`, Inkscape 0.92's text
/// in a frame) that [`text::flowed`] could not read (source indices
/// `unread`): its frame is not a shape it reads, or its group is not drawn.
/// Its words would otherwise vanish without a word.
fn unread_flowed_text(src: &Source, doc: &roxmltree::Document<'_>, unread: &[usize], diags: &mut Vec<Diagnostic>) {
    for e in unread.iter().filter_map(|&i| src.elements.get(i)) {
        let Some(node) = doc.get_node(e.node) else { continue };
        // The words of its paragraphs (not of its frame's `flowRegion`).
        let words: String = node
            .descendants()
            .filter(|n| n.is_text() && !n.ancestors().any(|a| a.tag_name().name() == "flowRegion"))
            .filter_map(|n| n.text())
            .collect::<Vec<_>>()
            .join(" ");
        let words = words.split_whitespace().collect::<Vec<_>>().join(" ");
        let shown = match words.char_indices().nth(40) {
            Some((cut, _)) => format!("\"{}…\"", words.get(..cut).unwrap_or("")),
            None if words.is_empty() => "its (empty) text".to_string(),
            None => format!("\"{words}\""),
        };
        diags.push(
            Diagnostic::warning(
                "T0306",
                format!(
                    "Inkscape flowed text (<flowRoot>) whose frame is not a rectangle, path or basic shape is not \
                     read: {shown} is left out"
                ),
            )
            .with_element(&e.name)
            .with_help("in Inkscape, select it and use Text > Convert to Text, then save")
            .at_line(e.line),
        );
    }
}

/// The code of "a tactile style was asked of something that is not drawn".
pub(crate) const NOT_DRAWN: &str = "T0301";

/// What to do about an SVG usvg refuses: its size, or its limits (more
/// than 1,000,000 elements, or elements nested more than 1,024 deep).
fn read_help(e: &usvg::Error) -> &'static str {
    match e {
        usvg::Error::InvalidSize => "check the root <svg> has a valid width, height or viewBox",
        usvg::Error::ElementsLimitReached | usvg::Error::ParsingFailed(roxmltree::Error::NodesLimitReached) => {
            "the drawing has more than 1,000,000 elements or nests groups more than 1,024 deep: \
             ungroup or simplify it (Inkscape: Edit > Select All, Object > Ungroup), or split it into several drawings"
        }
        _ => "open the drawing in Inkscape or a browser and save it again as plain SVG",
    }
}
