//! Stage 3, style: the automatic style sheet for what no annotation styles. It never places or fits.
//!
//! The built-in automatic style sheet `auto`: tactile styles decided from what
//! a drawing shows, for the drawings nobody annotated (a Wikimedia map, an
//! OpenStreetMap plan, a chart from a plotting library).
//!
//! It runs on the resolved [`Drawing`] and gives styles only to elements that
//! have none from an annotation or a style sheet:
//! - stroked lines and outlines vibrate, and so do the outlines of regions
//!   that share a border with a region of their own fill (a map's districts
//!   drawn in one colour: one texture on both sides, only the border tells them apart);
//! - filled regions become gratings, one texture per distinct fill colour,
//!   chosen from [`textures`] (wavelengths 3 mm apart, orientations among 0°,
//!   45°, 90° and 135°: seed 000 §4.2–4.4) so that fills whose regions touch
//!   or nearly touch never share one (a colouring of the region-adjacency
//!   graph, largest area first, at most five textures, BANA 2010); a fill
//!   that cannot get a texture falls back to its outline, with a note;
//! - small filled circles, small compact marks, marker instances and
//!   arrowheads (a small shape of a line's colour where the line ends) become
//!   dot symbols;
//! - text becomes braille where the braille fits on the page without running
//!   into other braille (moved a little, or pulled back onto the page when it
//!   runs off its side); a label that finds no place is written as a
//!   two-letter key code where that fits (BANA's keys, note T0326 gives the
//!   key; the label's words are its name, said when the finger is on it), and
//!   is left out otherwise, with one note;
//! - page backgrounds (and a chart's very light plot panel under its bars),
//!   white or transparent fills, hidden, clipped- or masked-away and
//!   off-page elements, and images are left out (white fills count as regions
//!   when they are all a coloured background carries: a flag's white cross on red).
//!
//! [`sheet_toml`] writes the same decisions as a style sheet a teacher can
//! start from (`taxel style auto [INPUT]`).

//!
//! [`plan`] (`decide.rs`) decides in steps, from the ground the elements lie
//! on (`ground.rs`), the arrowheads (`arrows.rs`), the adjacency of regions
//! (`adjacency.rs`), the places of labels' braille (`labels.rs`) and the key
//! codes (`keys.rs`); `notes.rs` writes what a reader of the build is told.

pub(crate) mod adjacency;
mod arrows;
mod decide;
mod ground;
mod keys;
pub(crate) mod key_page;
mod labels;
pub mod legend;
mod notes;
mod sheet;
mod ticks;

pub use adjacency::{Neighbours, Region, abutting, abutting_alike, class_edges, colour, touching};
pub use decide::{plan, plan_measured};
/// Text broken into lines at spaces, as the key pages break theirs (also
/// the report plot's legend).
pub use key_page::wrap;
pub use keys::{KeyCode, key_line, label_text};
pub use legend::{Legend, legend};
pub use notes::{fill_name, nothing_made, summary};
pub use sheet::sheet_toml;

use taxel_format::DeviceProfile;

use crate::annotation::{Braille, Dot, Grating, Style, Vibrate};
use crate::diagnostic::Diagnostic;
use crate::drawing::{Drawing, Rgba, Shape, StyledBy, TextRun, TextShape};
use crate::spatial::Bbox;

/// Most textures the automatic sheet uses (BANA 2010: about five of each kind).
pub const MAX_TEXTURES: usize = 5;
/// Regions closer than this count as touching: they are not felt apart (Hasty's 1/8 in).
pub const NEAR_MM: f64 = 3.2;
/// Filled shapes no larger than this both ways are marks (dot symbols), not regions.
pub const MARK_MM: f64 = 5.0;
/// Filled circles up to this diameter are point symbols (a town on a map).
pub const CIRCLE_MM: f64 = 8.0;
/// Closest that the centres of two marks' dots may lie (both ways, the
/// marks' boxes' centres): the dots' diameter (2 mm) and the gap below which
/// neighbours are not felt apart ([`NEAR_MM`]). Marks crowded closer (a
/// scatter plot of thousands of points) are thinned to an even sample, in
/// document order, with note T0327.
pub const MARK_SPACING_MM: f64 = 2.0 + NEAR_MM;
/// Fewest marks of one kind (one fill, one size) that make a scatter: when
/// one of them lies across another, all of them are marks.
pub const MARK_KIND_MIN: usize = 8;
/// A filled element covering this share of the page is its background.
pub const BACKGROUND_SHARE: f64 = 0.9;
/// Fills and strokes with less alpha than this (of 255) are not seen, so not felt.
pub const MIN_ALPHA: u8 = 26;
/// Fills whose every channel is at least this light are paper, not regions
/// (unless they are all that a coloured background carries).
pub const WHITE: u8 = 240;
/// A grey line is faint (a chart's grid, a light frame) when it is less than
/// this share as dark as the drawing's darkest line: Vega-Lite's `#ddd` grid
/// beside its `#888` axes (0.28 against 0.75), matplotlib's `#b0b0b0` grid
/// beside black axes (0.57 against 1).
pub const FAINT_SHARE: f64 = 0.6;
/// A grey line at least this light (each channel, as seen over white) is
/// faint too whenever a darker line is drawn, however light that one is:
/// Highcharts' `#e6e6e6` grid beside its `#ccd6eb` axis (0.21 against 0.33,
/// 63 %). Lines this light are barely seen on paper; they guide the eye.
pub const LIGHT_GUIDE: u8 = 224;
const LIGHT_GUIDE_GREY: Rgba = [LIGHT_GUIDE, LIGHT_GUIDE, LIGHT_GUIDE, 255];
/// Colours whose channels differ by no more than this are grey (no hue): a
/// light coloured line is data (a yellow series), a light grey one is a guide.
const GREY_SPREAD: u8 = 24;
/// Fills enclosing no more than this many mm² enclose nothing that can be seen.
const MIN_FILL_MM2: f64 = 1e-6;
/// Radius of the dots of braille the automatic sheet writes (NLS 800: 1.44 mm base).
const BRAILLE_RADIUS_MM: f64 = 0.72;
/// Clearance kept between two pieces of braille, so labels are felt apart.
const BRAILLE_CLEARANCE_MM: f64 = 1.0;

/// The textures, in the order fills receive them (largest area first), for a
/// device of this pitch. The shortest wavelength is the smallest of 2 mm
/// (seed 000's default) raised to twice the actuator pitch and rounded up to
/// half a millimetre, so no texture aliases on the still array; the others
/// are 3 and 6 mm longer, and two textures of one orientation always differ
/// by at least 3 mm (seed 000 §4.2: told apart almost always).
///
/// ```
/// use taxel_compiler::style::textures;
/// use taxel_format::profiles;
///
/// let t = textures(&profiles::builtin("stress2").unwrap());
/// assert_eq!(t.map(|g| (g.wavelength_mm, g.angle_deg)), [(3.0, 90.0), (6.0, 0.0), (3.0, 45.0), (6.0, 135.0), (9.0, 90.0)]);
/// ```
pub fn textures(profile: &DeviceProfile) -> [Grating; MAX_TEXTURES] {
    let pitch = (profile.pitch_x_mm as f64).max(profile.pitch_y_mm as f64);
    let base = if pitch.is_finite() && pitch > 0.0 { ((2.0 * pitch).max(2.0) * 2.0).ceil() / 2.0 } else { 2.0 };
    let g = |wavelength_mm: f64, angle_deg: f64| Grating { wavelength_mm, angle_deg, amplitude: 1.0, soft_mm: 0.0 };
    [g(base, 90.0), g(base + 3.0, 0.0), g(base, 45.0), g(base + 3.0, 135.0), g(base + 6.0, 90.0)]
}

/// The vibrating outline: the STRESS² study's 1.5 mm, widened to the actuator
/// pitch where the pitch is larger (T0404: thinner outlines alias).
pub(crate) fn outline_style(profile: &DeviceProfile) -> Vibrate {
    let pitch = (profile.pitch_x_mm as f64).max(profile.pitch_y_mm as f64);
    Vibrate {
        width_mm: if pitch.is_finite() { pitch.max(1.5) } else { 1.5 },
        freq_hz: 50.0,
        amplitude: 1.0,
        soft_mm: 0.0,
    }
}

/// Why the automatic sheet left an element out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum LeftOut {
    /// `visibility: hidden`.
    Hidden,
    /// No geometry.
    Empty,
    /// Entirely off the page.
    OffPage,
    /// Entirely outside its clip path.
    ClippedAway,
    /// A filled shape covering the page.
    Background,
    /// Neither a visible fill (white and transparent fills do not count) nor a visible stroke.
    Unpainted,
    /// A small filled shape that is not a mark (a glyph outline, a sliver).
    SmallShape,
    /// Text whose braille does not fit.
    TextDoesNotFit,
    /// A raster image.
    Image,
    /// A faint grey line (a chart's grid): see [`darkness`] and [`FAINT_SHARE`].
    Faint,
    /// A mark among marks too dense to feel apart (a scatter plot's), thinned: see [`MARK_SPACING_MM`].
    Crowded,
    /// A tick label of an axis whose labels' braille would run together,
    /// thinned to every `every`-th label (T0328).
    Thinned {
        /// The step the axis kept: 2, 5, 10 or 20.
        every: u8,
    },
}

/// What the automatic sheet made of one element.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Decision {
    /// Its stroke vibrates (also a region that fell back to its outline).
    pub outline: bool,
    /// Its fill is a region of this fill class (an index into [`Plan::fills`]).
    pub region: Option<usize>,
    /// It is a mark: a dot at its centre or at each marker.
    pub mark: bool,
    /// Its text becomes braille.
    pub braille: bool,
    /// How far its braille is moved from the text's place, mm `(x, y)`, so
    /// that it clears the lines the sheet makes vibrate.
    pub braille_shift: (f64, f64),
    /// Its braille is this key code rather than its text, which found no
    /// place ([`KeyCode`]).
    pub key: Option<KeyCode>,
    /// Its stroke is faint (a grid line) and does not vibrate.
    pub faint: bool,
    /// Why nothing was made of it; `None` when something was, or when an
    /// annotation or style sheet had already styled it.
    pub left_out: Option<LeftOut>,
}

/// The elements of one fill colour that became regions.
#[derive(Debug, Clone, PartialEq)]
pub struct FillClass {
    /// The colour; `None` for gradient and pattern fills.
    pub fill: Option<[u8; 3]>,
    /// Their summed area in mm².
    pub area_mm2: f64,
    /// How many regions.
    pub regions: usize,
    /// The first region's name.
    pub first: String,
    /// The texture (index into [`Plan::textures`]); `None` when it fell back to its outline.
    pub texture: Option<usize>,
}

/// Everything the automatic sheet decided about a drawing.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The textures it chose from.
    pub textures: [Grating; MAX_TEXTURES],
    /// The vibrating outline it gives.
    pub outline: Vibrate,
    /// The fill classes, largest area first.
    pub fills: Vec<FillClass>,
    /// Distinct stroke colours that vibrate, in first-seen order.
    pub strokes: Vec<Option<[u8; 3]>>,
    /// Distinct faint stroke colours left out (a chart's grid), in first-seen order.
    pub faint: Vec<[u8; 3]>,
    /// The darkest line's colour, beside which the faint ones are faint.
    pub darkest: Option<[u8; 3]>,
    /// One decision per element of the drawing.
    pub decisions: Vec<Decision>,
    /// Regions (element indices) that share a border with a region of their
    /// own fill, of a fill most of whose such regions are too small for a
    /// border ([`min_region_mm`]): they get their texture and no outline, so
    /// they are felt as one texture.
    pub too_small: Vec<usize>,
}

/// Whether no element of the drawing was styled by an annotation or a style sheet.
pub fn unannotated(d: &Drawing) -> bool {
    d.elements.iter().all(|e| e.styled_by == StyledBy::Nothing)
}

fn visible(c: Rgba) -> bool {
    c[3] >= MIN_ALPHA
}

fn rgb(c: Rgba) -> [u8; 3] {
    [c[0], c[1], c[2]]
}

/// How dark a colour looks on white paper, from 0 (white, or transparent) to
/// 1 (black): one less the relative luminance (WCAG 2, sRGB linearised) of
/// the colour laid over white at its alpha.
///
/// ```
/// use taxel_compiler::style::darkness;
/// assert_eq!(darkness([0, 0, 0, 255]), 1.0);
/// assert_eq!(darkness([0, 0, 0, 0]), 0.0);
/// assert!((darkness([0xdd, 0xdd, 0xdd, 255]) - 0.277).abs() < 0.001);
/// ```
pub fn darkness(c: Rgba) -> f64 {
    let a = c[3] as f64 / 255.0;
    let lin = |v: u8| {
        let v = a * (v as f64 / 255.0) + (1.0 - a);
        if v <= 0.04045 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }
    };
    1.0 - (0.2126 * lin(c[0]) + 0.7152 * lin(c[1]) + 0.0722 * lin(c[2]))
}

fn grey(c: Rgba) -> bool {
    let (lo, hi) = (c[0].min(c[1]).min(c[2]), c[0].max(c[1]).max(c[2]));
    hi - lo <= GREY_SPREAD
}

/// A small compact mark (circle, square, triangle, diamond) rather than a
/// glyph or a sliver: about as wide as high, and filling about half its box or more.
fn compact(b: Bbox, a: f64) -> bool {
    let (w, h) = (b.2 - b.0, b.3 - b.1);
    w > 0.0 && h > 0.0 && (0.5..=2.0).contains(&(w / h)) && a >= 0.45 * w * h
}

/// A filled circle (or ellipse near one): its area is that of the inscribed ellipse.
fn round(b: Bbox, a: f64) -> bool {
    let (w, h) = (b.2 - b.0, b.3 - b.1);
    w > 0.0
        && h > 0.0
        && (0.8..=1.25).contains(&(w / h))
        && (a / (std::f64::consts::PI * w * h / 4.0) - 1.0).abs() < 0.1
}

/// A filled shape waiting for the adjacency to decide what it is.
struct Filled<'a> {
    i: usize,
    region: Region<'a>,
    area: f64,
}

/// How many cells a text's braille takes, as the layers will write it: the
/// compilation's braille service and table ([`crate::braille`]), or the
/// built-in UEB grade 1 ([`Measure::BUILTIN`], what [`plan`] and [`apply`] use).
#[derive(Clone, Copy)]
pub struct Measure<'a>(Option<&'a crate::CompileOptions>, Option<u8>);

impl<'a> Measure<'a> {
    /// The built-in uncontracted UEB's cells.
    pub const BUILTIN: Measure<'static> = Measure(None, None);

    /// The cells of the braille `opts` chooses.
    pub fn of(opts: &'a crate::CompileOptions) -> Self {
        Measure(Some(opts), None)
    }

    /// The cells of a key code, written uncontracted (letters, not a word).
    fn key(self) -> Self {
        Measure(self.0, Some(1))
    }

    /// How many cells `text` (of `shape`, whose language chooses the table) takes.
    fn cells(self, shape: Option<&TextShape>, text: &str) -> usize {
        match self.0 {
            Some(opts) => crate::braille::translate(text, shape, opts, self.1, false).cells.len(),
            None => taxel_braille::ueb::translate(text).0.len(),
        }
    }
}

/// The size (the side of a square of the same area) below which a region's
/// own vibrating border, `width` wide and centred on its outline, would cover
/// more than half of it: the band's inner half takes `width / 2` from each
/// side, so a square of side `s` keeps `(s - width)²` of its `s²` as texture,
/// and that is half when `s = width / (1 - 1/√2)`, about 3.4 widths (5.1 mm
/// for the 1.5 mm outline).
///
/// ```
/// let s = taxel_compiler::style::min_region_mm(1.5);
/// assert!(((s - 1.5) * (s - 1.5) / (s * s) - 0.5).abs() < 1e-12);
/// ```
pub fn min_region_mm(width: f64) -> f64 {
    width / (1.0 - std::f64::consts::FRAC_1_SQRT_2)
}

impl Plan {
    /// The styles the plan gives element `i` (empty when it leaves it out or
    /// did not decide it).
    pub fn styles(&self, i: usize) -> Vec<Style> {
        let Some(d) = self.decisions.get(i) else { return Vec::new() };
        let mut out = Vec::new();
        if d.outline {
            out.push(Style::Vibrate(self.outline));
        }
        if let Some(t) = d.region.and_then(|k| self.fills.get(k)).and_then(|f| f.texture) {
            out.push(Style::Grating(self.textures[t]));
        }
        if d.mark {
            out.push(Style::Dot(Dot { radius_mm: 1.0, amplitude: 1.0 }));
        }
        if d.braille {
            out.push(Style::Braille(Braille { radius_mm: BRAILLE_RADIUS_MM, amplitude: 1.0, grade: None }));
        }
        out
    }
}

/// Styles every element no annotation or style sheet styled, as [`plan`]
/// decides, and adds the notes a reader of the build needs: textures shared
/// or given up, text left out. Returns the plan.
pub fn apply(d: &mut Drawing, profile: &DeviceProfile, diags: &mut Vec<Diagnostic>) -> Plan {
    apply_measured(d, profile, Measure::BUILTIN, diags)
}

/// [`apply`] with labels measured by `m`.
pub fn apply_measured(d: &mut Drawing, profile: &DeviceProfile, m: Measure<'_>, diags: &mut Vec<Diagnostic>) -> Plan {
    let plan = plan_measured(d, profile, m);
    for (i, e) in d.elements.iter_mut().enumerate() {
        let styles = plan.styles(i);
        if !styles.is_empty() {
            e.styles = styles;
            e.styled_by = StyledBy::Auto;
        }
        if let (Some(LeftOut::TextDoesNotFit), Shape::Text(t)) = (plan.decisions[i].left_out, &mut e.shape) {
            t.unplaced = true;
        }
        let (dx, dy) = plan.decisions[i].braille_shift;
        if let (true, Shape::Text(t)) = (plan.decisions[i].braille, &mut e.shape) {
            if let Some(code) = plan.decisions[i].key {
                // The code where the label's first line starts; the label's
                // words are what the host says when the finger is on it.
                e.label = label_text(t);
                let code = String::from_utf8_lossy(&code).into_owned();
                if let Some(first) = t.runs.iter().find(|r| !r.text.trim().is_empty()).cloned() {
                    t.runs = vec![TextRun { text: code.clone(), continues: false, ..first }];
                }
                t.content = code;
                t.keyed = Some(e.label.clone());
            }
            for r in &mut t.runs {
                r.x_mm += dx;
                r.y_mm += dy;
            }
            t.moved_mm = (t.moved_mm.0 + dx, t.moved_mm.1 + dy);
        }
    }
    notes::notes(&plan, d, diags);
    plan
}

#[cfg(test)]
pub(crate) mod tests;
