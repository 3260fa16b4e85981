//! Stage 1, drawing: the SVG as written, resolved (styles, paint, geometry, occlusion).
//!
//! The resolved drawing: the compiler's public stage between an SVG and its
//! layers, as usvg's `Tree` is between SVG text and pixels.
//!
//! Everything after this stage (the layer builders for every device family,
//! the automatic style sheet, the design rules, `taxel report`'s exact
//! reference, the demo) reads a [`Drawing`], never the SVG text or usvg's
//! tree: one style resolution, one page transform, one geometry.
//!
//! A drawing holds every element that usvg draws (shapes, text, images), in
//! document order, whether or not a tactile style was asked of it, so that the
//! automatic conversion can decide from what the drawing shows. Geometry is
//! exact f64 in page millimetres (origin top-left, y down) after the page
//! transform, including `--fit` and `--region`.
//!
//! [`resolve`] makes a drawing from SVG text; it returns the drawing, the
//! diagnostics found on the way and the font faces its text used
//! ([`Resolved`]). `pipeline::compile_svg` builds its layers from the same stage.

mod occlusion;
mod page;
mod resolve;
pub(crate) mod source;
mod text;
mod walk;

pub(crate) use occlusion::OpaqueFills;
pub use occlusion::occluders;
pub(crate) use page::page as page_size;
pub use resolve::{FontFace, Fonts, Resolved, fonts_used, resolve};
pub(crate) use resolve::{NOT_DRAWN, run as resolve_into, usvg_options};

use crate::annotation::Style;
use crate::geometry::{FillRule, Polyline};

/// A drawing with its styles resolved and its geometry in page millimetres.
#[derive(Debug, Clone, Default)]
pub struct Drawing {
    /// The page the geometry lives on.
    pub page: Page,
    /// The root's `<title>`, trimmed; empty when there is none.
    pub title: String,
    /// The drawn elements in document order.
    pub elements: Vec<Element>,
}

impl Drawing {
    /// Whether every drawn element is a picture (a scan or pasted image, linked
    /// or embedded) and there is at least one: then nothing tactile can come
    /// of it, and [`PICTURES_HELP`] says what to do instead.
    pub fn only_pictures(&self) -> bool {
        !self.elements.is_empty() && self.elements.iter().all(|e| matches!(e.shape, Shape::Image { .. }))
    }
}

/// The help of the error for a drawing that is only pictures
/// ([`Drawing::only_pictures`]): annotating cannot help.
pub const PICTURES_HELP: &str = "taxel does not turn pictures (PNG, JPEG, linked or embedded images) into tactile \
     shapes: trace the image to paths (Inkscape: Path > Trace Bitmap) or draw the shapes over it, then build again";

/// The page: its size in millimetres and how drawing units map onto it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Page {
    /// Page width in mm.
    pub width_mm: f64,
    /// Page height in mm.
    pub height_mm: f64,
    /// Millimetres per unit of the root's user space (after `--fit`).
    pub scale: f64,
    /// Page position, in mm, of the root user space's origin (non-zero after `--fit` or `--region`).
    pub offset_mm: (f64, f64),
    /// Where the drawing's own page lies, `(x0, y0, x1, y1)` in mm, once
    /// `--fit` or `--region` has placed it on the surface (which
    /// [`Page::width_mm`] and [`Page::height_mm`] then are); `None` when it
    /// was not moved. The automatic sheet tells a page's background by it.
    pub sheet_mm: Option<(f64, f64, f64, f64)>,
}

impl Page {
    /// The drawing's own page on this page: [`Page::sheet_mm`] where the
    /// drawing was placed, else the whole page.
    pub fn sheet(&self) -> (f64, f64, f64, f64) {
        self.sheet_mm.unwrap_or((0.0, 0.0, self.width_mm, self.height_mm))
    }
}

/// Where an element's styles came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StyledBy {
    /// No style was asked of it.
    #[default]
    Nothing,
    /// Its own annotation or an ancestor's (`data-tactile`, a `tactile:` label).
    Annotation,
    /// A rule of the style sheet given with `--style`.
    StyleSheet,
    /// The built-in automatic style sheet (`auto`).
    Auto,
}

/// A colour with its alpha (opacity already folded in), 0..=255 each.
pub type Rgba = [u8; 4];

/// How an element is painted, as far as tactile conversion cares.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Paint {
    /// The fill colour; `None` for no fill or a gradient/pattern fill.
    pub fill: Option<Rgba>,
    /// Whether it has a fill at all (a gradient or pattern counts).
    pub filled: bool,
    /// The stroke colour; `None` for no stroke or a gradient/pattern stroke.
    pub stroke: Option<Rgba>,
    /// Whether it has a stroke at all.
    pub stroked: bool,
    /// Stroke width in page mm (0 without a stroke).
    pub stroke_width_mm: f64,
}

/// One drawn element.
#[derive(Debug, Clone, Default)]
pub struct Element {
    /// The id as written; empty when it had none.
    pub id: String,
    /// A name for messages: the id, or a path such as `svg/g[2]/path[1]`.
    pub name: String,
    /// 1-based line of its start tag in the source (0 when unknown).
    pub line: u32,
    /// `<title>`, `inkscape:label` (but a `tactile:` annotation) or
    /// `aria-label`, whichever comes first, else its nearest group's (not the
    /// root's, nor an Inkscape layer's); what a host says when the finger is
    /// on it.
    pub label: String,
    /// Local tag name (`path`, `rect`, `text`, ...).
    pub tag: String,
    /// The `class` attribute as written.
    pub classes: String,
    /// Labels of the Inkscape layers that contain it, outermost first.
    pub layers: Vec<String>,
    /// The tactile styles in force (empty when none was asked).
    pub styles: Vec<Style>,
    /// Where [`Element::styles`] came from.
    pub styled_by: StyledBy,
    /// False for `visibility: hidden` (it still takes part in layout).
    pub visible: bool,
    /// Its paint.
    pub paint: Paint,
    /// Its geometry.
    pub shape: Shape,
}

/// An element's geometry in page millimetres.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// A path (every basic shape is one).
    Path(PathShape),
    /// Text: what it says and where, plus its glyph outlines when fonts were available.
    Text(TextShape),
    /// A raster image (not rendered tactilely), by its bounds `(x0, y0, x1, y1)`.
    Image {
        /// Bounds in page mm.
        bounds: (f64, f64, f64, f64),
    },
}

impl Default for Shape {
    fn default() -> Self {
        Shape::Path(PathShape::default())
    }
}

/// A path's exact geometry.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PathShape {
    /// The outline flattened to polylines (within `geometry::FLATTEN_TOLERANCE_MM`).
    pub outline: Vec<Polyline>,
    /// How its inside is decided.
    pub fill_rule: FillRule,
    /// Centres of the marker instances drawn on it.
    pub markers: Vec<(f64, f64)>,
    /// Clip regions of it and its ancestors; the element is kept only inside all of them.
    pub clips: Vec<Clip>,
}

/// A clip region.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Clip {
    /// The region's outline.
    pub outline: Vec<Polyline>,
    /// How its inside is decided.
    pub fill_rule: FillRule,
}

/// A text element.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TextShape {
    /// Every character it says, runs joined in order.
    pub content: String,
    /// The runs as laid out: each with its text and the page position where
    /// its braille starts (after `text-anchor`), in mm.
    pub runs: Vec<TextRun>,
    /// Font size in page mm (the first run's).
    pub font_size_mm: f64,
    /// Glyph outlines, when the font database had the fonts (else empty).
    pub outline: Vec<Polyline>,
    /// The label this text stands for when it is a key code the automatic
    /// sheet wrote for a label that found no place (note T0326); `None` for
    /// a text that says itself.
    pub keyed: Option<String>,
    /// Its language: the nearest `xml:lang` (or `lang`) on it or around it;
    /// `None` when none says (the reader's language, `--lang`, is used).
    pub lang: Option<String>,
    /// How far the automatic sheet moved its runs so that its braille finds
    /// room `(dx, dy)`, mm; the runs less this are where the drawing has
    /// it (a legend's text beside its swatch, `style::legend`).
    pub moved_mm: (f64, f64),
    /// Whether the automatic sheet found no place on the graphic for its
    /// braille, not even as a key code (note T0323): the key lists it
    /// instead (`style::legend`).
    pub unplaced: bool,
}

/// One positioned run of text.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TextRun {
    /// The characters.
    pub text: String,
    /// Baseline start of the run, page mm.
    pub x_mm: f64,
    /// Baseline, page mm.
    pub y_mm: f64,
    /// Where the anchor is along the run: 0 start, 0.5 middle, 1 end.
    pub anchor: f64,
    /// Whether it continues the previous run on the same line (no own `x`/`y`).
    pub continues: bool,
}

impl Element {
    /// The box of what can be seen of the element: its bounds within the
    /// boxes of its clip regions; `None` when it has no outline or they
    /// leave nothing.
    pub fn seen_bounds(&self) -> Option<(f64, f64, f64, f64)> {
        let mut b = self.bounds()?;
        if let Shape::Path(p) = &self.shape {
            for c in &p.clips {
                let cb = crate::geometry::bounds(&c.outline)?;
                b = (b.0.max(cb.0), b.1.max(cb.1), b.2.min(cb.2), b.3.min(cb.3));
            }
        }
        (b.0 <= b.2 && b.1 <= b.3).then_some(b)
    }

    /// The element's outline in page mm: a path's, or a text's glyph
    /// outlines; none for an image.
    pub fn outline(&self) -> &[Polyline] {
        match &self.shape {
            Shape::Path(p) => &p.outline,
            Shape::Text(t) => &t.outline,
            Shape::Image { .. } => &[],
        }
    }

    /// The element's bounds `(x0, y0, x1, y1)` in page mm, `None` when it has no geometry.
    pub fn bounds(&self) -> Option<(f64, f64, f64, f64)> {
        match &self.shape {
            Shape::Path(p) => crate::geometry::bounds(&p.outline),
            Shape::Text(t) => crate::geometry::bounds(&t.outline).or_else(|| {
                let xs = t.runs.iter().map(|r| r.x_mm);
                let ys = t.runs.iter().map(|r| r.y_mm);
                let (x0, x1) = xs.fold((f64::MAX, f64::MIN), |a, v| (a.0.min(v), a.1.max(v)));
                let (y0, y1) = ys.fold((f64::MAX, f64::MIN), |a, v| (a.0.min(v), a.1.max(v)));
                (x0 <= x1).then_some((x0, y0 - t.font_size_mm, x1, y1))
            }),
            Shape::Image { bounds } => Some(*bounds),
        }
    }
}
