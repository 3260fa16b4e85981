//! Back end for paper and 3D print (stage 4, family 5).
//!
//! Print media (device family 5): a resolved [`Drawing`] legalised to a
//! [`Sheet`] of raised marks on paper, from the same annotations as every
//! other device, and the sheet written as the medium's own file.
//!
//! Each style becomes what paper or a print can say (`docs/print.md`):
//! - `vibrate` → a solid raised line of at least the medium's width; a
//!   drawing with several vibrating styles gets solid, dashed, double and
//!   dotted lines, one per style in order of first use (`marks.rs`);
//! - `grating` → a texture of lines or dots at spacings a finger tells apart,
//!   the grating's own orientation where it is free, and never the texture of
//!   a grated region that touches it (`texture.rs`, over the automatic sheet's
//!   region adjacency);
//! - `dots` → round dots along the path; `dot` → a point symbol, one shape
//!   per dot style (disc, square, triangle, diamond, ring, cross);
//! - `brush` → a line with an arrowhead where the stroke ends;
//! - `braille` → braille cells at the medium's dimensions drawn as dots
//!   (`braille.rs`), the texture cleared around them.
//!
//! When the drawing needs a key ([`crate::style::legend()`]), it follows on
//! pages of its own (`key.rs`): each texture, line style and point symbol
//! felt as itself beside its meaning in braille, then the key codes.
//!
//! An embosser's sheet is then snapped to its grid: every mark becomes the
//! grid's dots it covers (`grid.rs`). The files: [`pdf()`] (swell paper and
//! embossers, through pdf-writer), [`png()`] (an embosser's grid, a pixel a dot),
//! [`stl()`] (a relief: a watertight height-field mesh). [`preview`] draws a
//! sheet as it is felt; `rules.rs` checks the medium's design rules (T0720 to
//! T0727).
//!
//! ```
//! use taxel_compiler::drawing::{Drawing, Element, Page, PathShape, Shape};
//! use taxel_compiler::annotation::{Style, Vibrate};
//! use taxel_compiler::geometry::Polyline;
//! use taxel_format::profiles;
//!
//! let square = Polyline { points: vec![(10.0, 10.0), (40.0, 10.0), (40.0, 40.0), (10.0, 40.0)], closed: true };
//! let drawing = Drawing {
//!     page: Page { width_mm: 190.0, height_mm: 277.0, scale: 1.0, offset_mm: (0.0, 0.0), sheet_mm: None },
//!     elements: vec![Element {
//!         name: "square".into(),
//!         visible: true,
//!         styles: vec![Style::Vibrate(Vibrate { width_mm: 1.5, freq_hz: 50.0, amplitude: 1.0, soft_mm: 0.0 })],
//!         shape: Shape::Path(PathShape { outline: vec![square], ..Default::default() }),
//!         ..Default::default()
//!     }],
//!     ..Default::default()
//! };
//! let mut diags = Vec::new();
//! let sheet = taxel_compiler::print::legalise(&drawing, &profiles::builtin("swell-a4").unwrap(), &mut diags).unwrap();
//! assert_eq!(sheet.paper_mm, (210.0, 297.0));
//! let pdf = taxel_compiler::print::pdf(&sheet).unwrap();
//! assert!(pdf.starts_with(b"%PDF"));
//! ```

mod braille;
mod clip;
mod grid;
mod key;
mod marks;
mod pdf;
pub mod preview;
mod raster;
mod rules;
pub(crate) mod stl;
mod texture;

pub use pdf::pdf;
pub use raster::png;
pub use stl::stl;

use taxel_format::{DeviceProfile, FamilyParams, Medium, PrintParams};

use crate::annotation::Style;
use crate::diagnostic::Diagnostic;
use crate::drawing::{Drawing, Shape};

/// How high a mark stands, lowest first: on a relief each has its height,
/// on an embosser with several dot heights its level, on swell paper all
/// rise alike.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Level {
    /// Area textures.
    Texture,
    /// Braille.
    Braille,
    /// Lines, point symbols, arrowheads.
    Line,
}

/// What a mark draws, in paper millimetres (origin at the paper's top-left, y down).
#[derive(Debug, Clone, PartialEq)]
pub enum MarkShape {
    /// A raised line along a polyline, with round ends and joins.
    Line {
        /// Its centre line.
        points: Vec<(f64, f64)>,
        /// Whether the last point joins the first.
        closed: bool,
        /// Its width.
        width_mm: f64,
    },
    /// A filled polygon (point symbols, arrowheads), its rings by the non-zero rule.
    Polygon {
        /// Its rings.
        rings: Vec<Vec<(f64, f64)>>,
    },
    /// A round dot (braille, dotted lines and textures, an embosser's dots).
    Dot {
        /// Its centre.
        centre: (f64, f64),
        /// Its base diameter.
        diameter_mm: f64,
    },
}

/// One raised mark.
#[derive(Debug, Clone, PartialEq)]
pub struct Mark {
    /// What it draws.
    pub shape: MarkShape,
    /// How high it stands.
    pub level: Level,
    /// The drawing's element it comes from (its index), `None` for the key page's text.
    pub element: Option<usize>,
}

/// A texture of the medium, as the sheet records it for each grated element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TextureId(pub u8);

/// The drawing legalised for one print medium: the compiler's public stage
/// between a [`Drawing`] and the medium's file, as the pin image is for pin
/// displays.
#[derive(Debug, Clone)]
pub struct Sheet {
    /// The profile it was made for.
    pub profile: DeviceProfile,
    /// Its print parameters.
    pub params: PrintParams,
    /// Paper size, `(width, height)` in mm.
    pub paper_mm: (f64, f64),
    /// The pages: the graphic's first (`tiles.0 * tiles.1` of them, row by
    /// row), then the key's pages when there is a key.
    pub pages: Vec<Vec<Mark>>,
    /// The pages the graphic is printed on, `(across, down)`: `(1, 1)` when
    /// it fits the printable area, more for a larger drawing printed at its
    /// size (note T0212).
    pub tiles: (usize, usize),
    /// The texture each grated element got, by element index.
    pub textures: Vec<(usize, TextureId)>,
    /// The drawing's title (empty when none).
    pub title: String,
}

impl Sheet {
    /// The medium.
    pub fn medium(&self) -> Medium {
        self.params.medium
    }

    /// Where each page lies when the pages are shown together (the preview,
    /// a relief's plates): `(column, row)`, the graphic's pages as they
    /// join, the key's in a column to their right.
    pub fn layout(&self) -> Vec<(usize, usize)> {
        let (across, down) = (self.tiles.0.max(1), self.tiles.1.max(1));
        (0..self.pages.len())
            .map(|n| match n.checked_sub(across * down) {
                None => (n % across, n / across),
                Some(k) => (across + k / down, k % down),
            })
            .collect()
    }

    /// Where the printable area starts on the paper, in mm (the margin).
    pub fn origin(&self) -> (f64, f64) {
        (self.params.margin_mm as f64, self.params.margin_mm as f64)
    }
}

/// The file kinds a sheet is written as.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileKind {
    /// A PDF at true size (swell paper, embossers).
    Pdf,
    /// A grey PNG a pixel per grid dot (embossers).
    Png,
    /// A binary STL relief (3D prints).
    Stl,
    /// The same relief as a 3MF package (3D prints): indexed vertices, in
    /// millimetres, which slicers read without repairing.
    ThreeMf,
}

impl FileKind {
    /// The kind an output file's extension names, `None` for another.
    pub fn from_extension(ext: &str) -> Option<Self> {
        match ext.to_ascii_lowercase().as_str() {
            "pdf" => Some(FileKind::Pdf),
            "png" => Some(FileKind::Png),
            "stl" => Some(FileKind::Stl),
            "3mf" => Some(FileKind::ThreeMf),
            _ => None,
        }
    }

    /// Its extension.
    pub fn extension(self) -> &'static str {
        match self {
            FileKind::Pdf => "pdf",
            FileKind::Png => "png",
            FileKind::Stl => "stl",
            FileKind::ThreeMf => "3mf",
        }
    }

    /// The kinds a medium is written as, its usual one first.
    pub fn for_medium(m: Medium) -> &'static [FileKind] {
        match m {
            Medium::Swell => &[FileKind::Pdf],
            Medium::Emboss => &[FileKind::Pdf, FileKind::Png],
            Medium::Relief => &[FileKind::Stl, FileKind::ThreeMf],
        }
    }
}

/// Why a sheet could not be written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PrintError(pub String);

impl std::fmt::Display for PrintError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for PrintError {}

/// Writes `sheet` as a file of `kind`.
pub fn write(sheet: &Sheet, kind: FileKind) -> Result<Vec<u8>, PrintError> {
    if !FileKind::for_medium(sheet.medium()).contains(&kind) {
        let kinds: Vec<&str> = FileKind::for_medium(sheet.medium()).iter().map(|k| k.extension()).collect();
        return Err(PrintError(format!(
            "a {} sheet ({}) is not written as .{}; it is written as .{}",
            sheet.medium().name(),
            sheet.profile.name,
            kind.extension(),
            kinds.join(" or .")
        )));
    }
    match kind {
        FileKind::Pdf => pdf(sheet),
        FileKind::Png => png(sheet),
        FileKind::Stl => stl(sheet),
        FileKind::ThreeMf => stl::three_mf(sheet),
    }
}

/// Legalises `drawing` for the print `profile`: the sheet, or `None` (with
/// an error diagnostic) when the profile is not a print profile or nothing
/// tactile was made.
pub fn legalise(drawing: &Drawing, profile: &DeviceProfile, diags: &mut Vec<Diagnostic>) -> Option<Sheet> {
    legalise_with(drawing, &crate::CompileOptions::new(*profile), diags)
}

/// [`legalise`] for `opts.profile`, its braille written as `opts` chooses
/// (the braille service, the reader's language, a style sheet's table).
pub fn legalise_with(drawing: &Drawing, opts: &crate::CompileOptions, diags: &mut Vec<Diagnostic>) -> Option<Sheet> {
    let profile = &opts.profile;
    let FamilyParams::Print(params) = profile.params else {
        diags.push(Diagnostic::error("T0900", format!("internal error: {} is not a print profile", profile.name)));
        return None;
    };
    let origin = (params.margin_mm as f64, params.margin_mm as f64);
    let mut b = marks::Builder::new(drawing, &params, origin);
    let textures = texture::assign(drawing, &params, diags);
    // Labels first, so that textures are cleared around them.
    let mut notes = crate::braille::Notes::default();
    let opaque = crate::drawing::OpaqueFills::of(drawing);
    let labels = braille::labels(drawing, &params, origin, &mut braille::Cx { opts, notes: &mut notes, diags });
    for (i, e) in drawing.elements.iter().enumerate().filter(|(_, e)| e.visible) {
        let first = b.marks.len();
        for style in &e.styles {
            match (style, &e.shape) {
                (Style::Vibrate(v), Shape::Path(p)) => b.outline(i, &p.outline, v),
                (Style::Grating(_), Shape::Path(p)) => {
                    if let Some(&(_, t)) = textures.iter().find(|(k, _)| *k == i) {
                        let outlined = e.styles.iter().any(|s| matches!(s, Style::Vibrate(_) | Style::Dots(_)));
                        let fill = texture::Fill { texture: t, outlined, clear: &labels.boxes };
                        let mut marks = texture::fill(&params, origin, i, p, fill);
                        // Not where opaque fills painted over it hide it (a
                        // legend's box, an inset), as on the pin arrays.
                        for j in opaque.above(drawing, &[i]) {
                            let over = &drawing.elements[j];
                            let Shape::Path(o) = &over.shape else { continue };
                            marks = clip::cut(marks, &clip::Region::new(&o.outline, o.fill_rule, origin).hiding());
                        }
                        b.marks.extend(marks);
                        rules::texture_area(&params, e, p, diags);
                    }
                }
                (Style::Dots(d), Shape::Path(p)) => b.dotted(i, &p.outline, d.radius_mm, d.spacing_mm),
                (Style::Dot(d), Shape::Path(p)) => {
                    let centres = if p.markers.is_empty() {
                        e.bounds().map(|b| vec![((b.0 + b.2) / 2.0, (b.1 + b.3) / 2.0)]).unwrap_or_default()
                    } else {
                        p.markers.clone()
                    };
                    b.symbols(i, &centres, d.radius_mm);
                }
                (Style::Brush(_), Shape::Path(p)) => b.arrow(i, &p.outline),
                (Style::Braille(_), Shape::Text(_)) => {}
                (Style::Braille(_), _) => diags.push(
                    Diagnostic::warning("T0121", "braille() applies to <text> elements; this one is not text")
                        .with_element(e.name.clone())
                        .on_line(e.line),
                ),
                _ => {}
            }
        }
        // Kept only inside its clip regions (and the crop to its page).
        if let Shape::Path(p) = &e.shape {
            for c in &p.clips {
                let region = clip::Region::new(&c.outline, c.fill_rule, origin);
                let cut = clip::cut(b.marks.split_off(first), &region);
                b.marks.extend(cut);
            }
        }
    }
    b.finish_notes(diags);
    let mut page = b.marks;
    page.extend(labels.marks.iter().cloned());
    rules::check(&params, drawing, &page, &labels, diags);
    let tiles = crate::place::print_pages((drawing.page.width_mm, drawing.page.height_mm), profile)
        .filter(|&(a, d)| a * d <= crate::place::MAX_PRINT_PAGES)
        .unwrap_or((1, 1));
    let mut pages = if tiles == (1, 1) { vec![page] } else { tile(page, tiles, &params, origin) };
    let legend = crate::style::legend(drawing);
    let cx = &mut braille::Cx { opts, notes: &mut notes, diags };
    pages.extend(key::pages(drawing, &legend, &textures, &params, origin, cx));
    notes.emit(diags);
    if params.medium == Medium::Emboss {
        pages = pages.into_iter().map(|p| grid::snap(&params, origin, p, drawing, diags)).collect();
    }
    if pages[..tiles.0 * tiles.1].iter().all(Vec::is_empty) {
        if !crate::diagnostic::has_errors(diags) {
            let help = if drawing.only_pictures() {
                crate::drawing::PICTURES_HELP
            } else {
                "mark shapes with data-tactile=\"vibrate()\" (or grating(), dots(), dot(), braille()), \
                 or convert it with --style auto (see docs/annotations.md)"
            };
            diags.push(
                Diagnostic::error("T0300", format!("nothing in this drawing can be printed on {}", profile.name))
                    .with_help(help),
            );
        }
        return None;
    }
    Some(Sheet {
        profile: *profile,
        params,
        paper_mm: (params.paper_w_mm as f64, params.paper_h_mm as f64),
        pages,
        tiles,
        textures,
        title: drawing.title.clone(),
    })
}

/// The graphic's marks `page` (paper mm, the drawing at its size from
/// `origin`) on `tiles` pages `(across, down)`, each the printable area's
/// window of the drawing moved onto its own sheet, row by row. Marks are cut
/// at the windows' edges, but a braille label is kept whole on the page
/// where its first dot falls: a word cut in two cannot be read.
fn tile(page: Vec<Mark>, (across, down): (usize, usize), p: &PrintParams, origin: (f64, f64)) -> Vec<Vec<Mark>> {
    let (sw, sh) = (p.surface_mm().0 as f64, p.surface_mm().1 as f64);
    let (mut braille, graphic): (Vec<Mark>, Vec<Mark>) =
        page.into_iter().partition(|m| m.level == Level::Braille && matches!(m.shape, MarkShape::Dot { .. }));
    let index = |c: (f64, f64)| {
        let i = ((c.0 - origin.0) / sw).floor().clamp(0.0, (across - 1) as f64) as usize;
        let j = ((c.1 - origin.1) / sh).floor().clamp(0.0, (down - 1) as f64) as usize;
        j * across + i
    };
    // Each label's page: that of its first dot (braille marks come label by label).
    let mut label_page: std::collections::HashMap<Option<usize>, usize> = Default::default();
    let mut pages: Vec<Vec<Mark>> = vec![Vec::new(); across * down];
    for m in braille.drain(..) {
        let MarkShape::Dot { centre, .. } = m.shape else { continue };
        let n = *label_page.entry(m.element).or_insert_with(|| index(centre));
        pages[n].push(m);
    }
    for (n, marks) in pages.iter_mut().enumerate() {
        let (i, j) = ((n % across) as f64, (n / across) as f64);
        let window = (origin.0 + i * sw, origin.1 + j * sh, origin.0 + (i + 1.0) * sw, origin.1 + (j + 1.0) * sh);
        let mut cut = clip::cut(graphic.clone(), &clip::Region::rect(window));
        cut.append(marks);
        clip::shift(&mut cut, (-i * sw, -j * sh));
        *marks = cut;
    }
    pages
}

#[cfg(test)]
mod tests;
