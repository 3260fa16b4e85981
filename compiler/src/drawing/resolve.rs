//! From SVG text to a [`Drawing`]: the XML side (annotations, labels, ids,
//! lines), usvg's resolved tree, the page size, then every drawn element
//! with its styles and exact geometry.

use std::sync::{Arc, OnceLock};

use super::source::{self, Source};
use super::{Drawing, Page, page, text, walk};
use crate::annotation::Declaration;
use crate::diagnostic::Diagnostic;
use crate::options::CompileOptions;

/// What [`resolve`] returns: the drawing (absent when the SVG could not be
/// read at all; present, though possibly with error diagnostics such as a
/// malformed annotation, otherwise) and every diagnostic found on the way (malformed annotations,
/// the page size, shapes that were asked for but are not drawn).
#[derive(Debug, Clone)]
pub struct Resolved {
    /// The drawing, unless an error prevented it.
    pub drawing: Option<Drawing>,
    /// Everything resolution had to say.
    pub diagnostics: Vec<Diagnostic>,
}

/// System fonts, loaded once per process (text converted to paths needs them;
/// braille does not).
pub(crate) fn fonts() -> Arc<usvg::fontdb::Database> {
    static DB: OnceLock<Arc<usvg::fontdb::Database>> = OnceLock::new();
    DB.get_or_init(|| {
        let mut db = usvg::fontdb::Database::new();
        db.load_system_fonts();
        Arc::new(db)
    })
    .clone()
}

/// usvg's options: the font database, and no file IO (images that name files are not loaded).
pub(crate) fn usvg_options() -> usvg::Options<'static> {
    let mut uopt = usvg::Options { fontdb: fonts(), ..usvg::Options::default() };
    uopt.image_href_resolver.resolve_string = Box::new(|_, _| None);
    uopt
}

/// Resolves an annotated SVG into a [`Drawing`] for `opts` (its profile
/// decides the page when the drawing has no physical size; its style sheet
/// takes part in style resolution). Never panics.
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
    let drawing = run(svg_text, opts, &mut diagnostics);
    Resolved { drawing, diagnostics }
}

/// [`resolve`], adding to `diags`.
pub(crate) fn run(text: &str, opts: &CompileOptions, diags: &mut Vec<Diagnostic>) -> Option<Drawing> {
    let doc = source::parse_xml(text, diags)?;
    let src = source::read(text, &doc, opts.style.as_ref(), diags)?;
    let doc2 = roxmltree::Document::parse_with_options(&src.rewritten, source::xml_options()).ok()?;
    let tree = match usvg::Tree::from_xmltree(&doc2, &usvg_options()) {
        Ok(t) => t,
        Err(e) => {
            diags.push(
                Diagnostic::error("T0200", format!("the SVG could not be read: {e}"))
                    .with_help("check the root <svg> has a valid width, height or viewBox"),
            );
            return None;
        }
    };
    let (w, h) = (tree.size().width(), tree.size().height());
    let root = doc.root_element();
    let sizing = page::page(root, w as f64, h as f64, opts.width_mm, &opts.profile, diags);
    let root_ts = page::root_transform(root, w, h);
    let walked = walk::walk(&tree, &src, opts.style.as_ref(), sizing.scale);
    let texts = text::texts(&src, &doc, &walked, sizing.scale, root_ts, diags);
    not_drawn(&src, &walked, diags);
    let mut elements: Vec<(usize, super::Element)> = walked.elements;
    elements.extend(texts);
    // Document order: a `<use>`'s copies sit at the `<use>`, in usvg's order (the sort is stable).
    elements.sort_by_key(|(i, _)| *i);
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
    };
    Some(Drawing { page, title, elements: elements.into_iter().map(|(_, e)| e).collect() })
}

/// Warns about shapes that carry their own annotation but that usvg does not draw.
fn not_drawn(src: &Source, walked: &walk::Walked, diags: &mut Vec<Diagnostic>) {
    const SHAPES: &[&str] = &["path", "rect", "circle", "ellipse", "line", "polyline", "polygon"];
    for (i, e) in src.elements.iter().enumerate() {
        let annotated = matches!(&e.own, Some(Declaration::Styles(s)) if !s.is_empty());
        if annotated && !e.in_defs && SHAPES.contains(&e.tag.as_str()) && !walked.seen.contains(&i) {
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

/// The code of "a tactile style was asked of something that is not drawn".
pub(crate) const NOT_DRAWN: &str = "T0301";
