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
//!   white or transparent fills, hidden, clipped-away and
//!   off-page elements, and images are left out (white fills count as regions
//!   when they are all a coloured background carries: a flag's white cross on red).
//!
//! [`sheet_toml`] writes the same decisions as a style sheet a teacher can
//! start from (`taxel style auto [INPUT]`).

pub(crate) mod adjacency;
mod sheet;

pub use adjacency::{Neighbours, Region, abutting, abutting_alike, class_edges, colour, touching};
pub use sheet::sheet_toml;

use std::collections::BTreeMap;

use taxel_format::DeviceProfile;

use crate::annotation::{Braille, Dot, Grating, Style, Vibrate};
use crate::diagnostic::Diagnostic;
use crate::drawing::{Drawing, Element, Rgba, Shape, StyledBy, TextRun, TextShape};
use crate::geometry::{FillRule, Polyline, filled_area};
use crate::spatial::{self, Bbox, Occupancy};
use crate::svg::{CELL_PITCH_MM, DOT_PITCH_MM};

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
/// use taxel_compiler::auto::textures;
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
/// use taxel_compiler::auto::darkness;
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

/// Boxes of the braille an element's text would make: one per run, placed as
/// the layer builder places it (from the run's start, after its anchor).
fn braille_boxes(runs: &[TextRun], shape: Option<&TextShape>, m: Measure<'_>) -> Vec<Bbox> {
    let height = 2.0 * DOT_PITCH_MM + 2.0 * BRAILLE_RADIUS_MM;
    runs.iter()
        .filter(|r| !r.text.trim().is_empty())
        .map(|r| {
            // The run's width from its first dot's left edge to its last's right edge.
            let cells = m.cells(shape, &r.text).max(1);
            let w = (cells - 1) as f64 * CELL_PITCH_MM + DOT_PITCH_MM + 2.0 * BRAILLE_RADIUS_MM;
            let x0 = r.x_mm - r.anchor.clamp(0.0, 1.0) * w;
            (x0, r.y_mm - height, x0 + w, r.y_mm)
        })
        .collect()
}

/// Where a label's braille may go, tried in this order, mm: its own place,
/// then a little below, above, left and right of it (as far as one cell's
/// clearance, then a cell's height), so it stays beside what it names.
const BRAILLE_SHIFTS: [(f64, f64); 9] =
    [(0.0, 0.0), (0.0, 1.5), (0.0, -1.5), (-1.5, 0.0), (1.5, 0.0), (0.0, 3.0), (0.0, -3.0), (-3.0, 0.0), (3.0, 0.0)];

/// Where a label kept off its place by a vibrating line alone may go last:
/// a cell's height below. A chart's tick label, set in a font smaller than
/// braille, sits under its axis, and braille stands on the baseline and grows
/// upwards, into the axis. (Not above: that took an axis's labels up into the
/// bars they name; and not for a label that meets other braille, which is
/// left out as before rather than stacked under it.)
const BELOW_A_LINE: (f64, f64) = (0.0, 6.0);

/// The shift that brings a label's braille `boxes` that run off the page
/// back onto it: left (or right) by no more than the label's width, so that
/// it still covers where it began, and up (or down) by no more than its
/// height; `None` when it lies on the page, or cannot be brought onto it so.
fn pull_inside(boxes: &[Bbox], page: Bbox) -> Option<(f64, f64)> {
    let u = boxes.iter().copied().reduce(|a, b| (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3)))?;
    let (w, h) = (u.2 - u.0, u.3 - u.1);
    let pull = |lo: f64, hi: f64, page_lo: f64, page_hi: f64| {
        if hi > page_hi {
            page_hi - hi
        } else if lo < page_lo {
            page_lo - lo
        } else {
            0.0
        }
    };
    let (dx, dy) = (pull(u.0, u.2, page.0, page.2), pull(u.1, u.3, page.1, page.3));
    let ok = (dx != 0.0 || dy != 0.0)
        && w <= page.2 - page.0
        && h <= page.3 - page.1
        && dx.abs() < w
        && dy.abs() <= h
        && dx.is_finite()
        && dy.is_finite();
    ok.then_some((dx, dy))
}

/// How far from a small filled shape a line of its colour may end for the
/// shape to be its arrowhead, mm, beyond half the line's width: Graphviz
/// ends an edge 0.19 pt short of its arrowhead's base.
const ARROW_GAP_MM: f64 = 0.3;

/// Most corners an arrowhead has: a triangle, a barbed or notched head
/// (Graphviz's `vee`, draw.io's `classic`), closed or with its first corner
/// repeated. An emblem's detail (a flag's sun rays, its leaves) is drawn
/// with curves, many points once flattened.
const ARROW_CORNERS: usize = 6;

/// How much longer than its head an arrow's line is, at least: a diagram's
/// edge, not an emblem's short detail stroke ending on a small shape.
const SHAFT_PER_HEAD: f64 = 2.0;

/// The ends of the drawing's open stroked lines, by colour, for telling
/// arrowheads from regions: a filled shape of a few straight sides
/// ([`ARROW_CORNERS`]) no larger than a mark ([`MARK_MM`]) whose fill is the
/// colour of a line that ends on it (within half the line's width and
/// [`ARROW_GAP_MM`]) and is [`SHAFT_PER_HEAD`] times as long as the shape is
/// wide is that line's arrowhead, as Graphviz, draw.io, LibreOffice and
/// matplotlib draw them (a separate filled triangle beside the stroked line).
struct LineEnds {
    /// Each end's line's colour and length, mm.
    lines: Vec<([u8; 3], f64)>,
    index: spatial::BoxIndex,
}

impl LineEnds {
    fn of(d: &Drawing) -> LineEnds {
        let mut lines = Vec::new();
        let mut boxes = Vec::new();
        for e in d.elements.iter().filter(|e| e.styled_by == StyledBy::Nothing && e.visible) {
            let (Shape::Path(p), Some(c), true) = (&e.shape, e.paint.stroke, e.paint.stroked) else { continue };
            let reach = e.paint.stroke_width_mm / 2.0 + ARROW_GAP_MM;
            for l in p.outline.iter().filter(|l| !l.closed) {
                let length: f64 = l.points.windows(2).map(|w| (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1)).sum();
                for &(x, y) in l.points.first().into_iter().chain(l.points.last()) {
                    lines.push((rgb(c), length));
                    boxes.push((x - reach, y - reach, x + reach, y + reach));
                }
            }
        }
        LineEnds { index: spatial::BoxIndex::new(&boxes), lines }
    }

    /// Whether a filled shape of outline `outline`, box `b` and fill `fill`
    /// is an arrowhead.
    fn arrowhead(&self, outline: &[Polyline], b: Bbox, fill: Option<Rgba>) -> bool {
        let Some(fill) = fill.map(rgb) else { return false };
        let size = (b.2 - b.0).max(b.3 - b.1);
        let few_corners = matches!(outline, [l] if l.points.len() <= ARROW_CORNERS);
        few_corners
            && size <= MARK_MM
            && self.index.meeting(b).any(|k| self.lines[k].0 == fill && self.lines[k].1 >= SHAFT_PER_HEAD * size)
    }
}

/// The regions that stand alone, for braille to keep off unless it was
/// drawn on them: a chart's bars, a diagram's boxes, a legend's swatches.
/// Braille clears a grating around itself (the layers' clearing), so a
/// label moved onto a bar it was not drawn on would cut the bar short. The
/// regions of a tessellation (a map's, whose labels lie across its borders)
/// are not figures.
#[derive(Default)]
struct Figures<'d> {
    outlines: Vec<(&'d [Polyline], FillRule)>,
    index: Option<spatial::BoxIndex>,
}

impl<'d> Figures<'d> {
    fn of(d: &'d Drawing, shapes: &[Filled<'d>], abuts: &[bool], decisions: &[Decision]) -> Figures<'d> {
        let mut outlines = Vec::new();
        let mut boxes = Vec::new();
        for (f, _) in shapes.iter().zip(abuts).filter(|(f, abuts)| !**abuts && decisions[f.i].region.is_some()) {
            let Shape::Path(p) = &d.elements[f.i].shape else { continue };
            outlines.push((f.region.outline, p.fill_rule));
            boxes.push(f.region.bbox);
        }
        Figures { index: Some(spatial::BoxIndex::new(&boxes)), outlines }
    }

    /// The figures whose area meets box `q`.
    fn meeting(&self, q: Bbox) -> impl Iterator<Item = usize> + '_ {
        self.index.iter().flat_map(move |index| index.meeting(q)).filter(move |&k| {
            let (outline, rule) = self.outlines[k];
            let centre = ((q.0 + q.2) / 2.0, (q.1 + q.3) / 2.0);
            crate::geometry::contains(outline, centre, rule) || outline.iter().any(|l| line_meets_box(l, true, q))
        })
    }

    /// The figures a text was drawn on (its own box meets them).
    fn under(&self, e: &Element) -> Vec<usize> {
        e.bounds().map(|b| self.meeting(b).collect()).unwrap_or_default()
    }
}

/// The outlines the sheet makes vibrate, for braille to keep off: their
/// boxes in an R*-tree, each outline's segments looked at only when its box
/// meets a label's (a scatter plot's 5,651 stroked circles made an R*-tree
/// of half a million segments, slower to build than the labels need).
#[derive(Default)]
struct Lines<'d> {
    outlines: Vec<&'d [Polyline]>,
    index: Option<spatial::BoxIndex>,
}

impl<'d> Lines<'d> {
    fn of(d: &'d Drawing, decisions: &[Decision]) -> Lines<'d> {
        let mut outlines = Vec::new();
        let mut boxes = Vec::new();
        for (e, dec) in d.elements.iter().zip(decisions) {
            let (true, Shape::Path(p)) = (dec.outline, &e.shape) else { continue };
            if let Some(b) = crate::geometry::bounds(&p.outline) {
                outlines.push(p.outline.as_slice());
                boxes.push(b);
            }
        }
        Lines { index: Some(spatial::BoxIndex::new(&boxes)), outlines }
    }

    /// Whether a segment of an outline passes through box `q`.
    fn meet(&self, q: Bbox) -> bool {
        let Some(index) = &self.index else { return false };
        index.meeting(q).any(|k| self.outlines[k].iter().any(|l| line_meets_box(l, l.closed, q)))
    }
}

/// Whether a segment of polyline `l` passes through box `q`, with its
/// closing segment when `closed` (a filled outline is closed whether or not
/// its path says so).
fn line_meets_box(l: &Polyline, closed: bool, q: Bbox) -> bool {
    let closing = closed.then(|| l.points.last().copied().zip(l.points.first().copied())).flatten();
    l.points.windows(2).map(|w| (w[0], w[1])).chain(closing).any(|s| segment_meets_box(s, q))
}

/// Whether segment `a`-`b` passes through box `q` (Liang-Barsky clipping).
fn segment_meets_box((a, b): ((f64, f64), (f64, f64)), q: Bbox) -> bool {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, r) in [(-dx, a.0 - q.0), (dx, q.2 - a.0), (-dy, a.1 - q.1), (dy, q.3 - a.1)] {
        if p == 0.0 {
            if r < 0.0 {
                return false;
            }
        } else {
            let t = r / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
            if t0 > t1 {
                return false;
            }
        }
    }
    true
}

/// Shapes closer than this share a border (a tessellation's neighbours).
const ABUT_MM: f64 = 0.05;

/// A filled shape waiting for the adjacency to decide what it is.
struct Filled<'a> {
    i: usize,
    region: Region<'a>,
    area: f64,
}

/// Decides, without changing the drawing, what the automatic sheet makes of
/// each element that no annotation or style sheet styled.
pub fn plan(d: &Drawing, profile: &DeviceProfile) -> Plan {
    plan_measured(d, profile, Measure::BUILTIN)
}

/// [`plan`] with labels measured by `m`.
pub fn plan_measured(d: &Drawing, profile: &DeviceProfile, m: Measure<'_>) -> Plan {
    // What can be felt: the page, as far as it lies on the device's surface.
    let (sw, sh) = (profile.surface_w_mm as f64, profile.surface_h_mm as f64);
    let page: Bbox = (0.0, 0.0, d.page.width_mm.min(sw), d.page.height_mm.min(sh));
    // The drawing's own page on it: all of it, unless `--fit` or `--region`
    // placed a page of another shape there (a 3:2 map on a 2:1 surface).
    let s = d.page.sheet();
    let sheet: Bbox = (s.0.max(page.0), s.1.max(page.1), s.2.min(page.2), s.3.min(page.3));
    let backgrounds = backgrounds(d, page, sheet);
    // White is the paper, except where a coloured ground carries nothing but
    // white shapes (a flag's white cross on its red field, an app icon's white
    // glyph on its tile): there the white shapes are the figure. Where other
    // colours are drawn too (a map's white label boxes), white stays the paper.
    let paper = |c: Rgba| c[..3].iter().all(|&v| v >= WHITE);
    let coloured = |e: &Element| e.paint.filled && e.paint.fill.is_none_or(|c| visible(c) && !paper(c));
    let coloured_ground = backgrounds.iter().any(|&i| coloured(&d.elements[i]));
    let white_is_figure =
        coloured_ground
            && !d.elements.iter().enumerate().any(|(i, e)| {
                e.visible && matches!(e.shape, Shape::Path(_)) && coloured(e) && !backgrounds.contains(&i)
            });
    let mut decisions = vec![Decision::default(); d.elements.len()];
    let mut strokes: Vec<Option<[u8; 3]>> = Vec::new();
    let mut classes: BTreeMap<Option<[u8; 3]>, usize> = BTreeMap::new();
    let mut fills: Vec<FillClass> = Vec::new();
    let mut shapes: Vec<Filled<'_>> = Vec::new();
    let mut braille = Occupancy::default();
    let mut texts = Vec::new();
    // The darkest line the sheet would make vibrate: grey lines much lighter
    // than it are guides (grid lines, light frames) and are left out, so the
    // axes and the data are felt rather than a lattice of grid lines.
    let darkest = d
        .elements
        .iter()
        .filter(|e| e.styled_by == StyledBy::Nothing && e.visible && matches!(e.shape, Shape::Path(_)))
        .filter(|e| e.paint.stroked && e.paint.stroke_width_mm > 0.0)
        .filter_map(|e| e.paint.stroke.filter(|&c| visible(c)))
        .max_by(|a, b| darkness(*a).total_cmp(&darkness(*b)));
    let faint = |c: Option<Rgba>| {
        c.zip(darkest).is_some_and(|(c, top)| {
            let (d, top) = (darkness(c), darkness(top));
            grey(c) && (d < FAINT_SHARE * top || (d <= darkness(LIGHT_GUIDE_GREY) && d < top))
        })
    };
    let mut faint_colours: Vec<[u8; 3]> = Vec::new();
    let line_ends = LineEnds::of(d);
    for (i, e) in d.elements.iter().enumerate() {
        if e.styled_by != StyledBy::Nothing {
            continue;
        }
        let dec = &mut decisions[i];
        let Some(b) = e.bounds() else {
            dec.left_out = Some(LeftOut::Empty);
            continue;
        };
        dec.left_out = if !e.visible {
            Some(LeftOut::Hidden)
        } else if !spatial::meet(b, page) {
            Some(LeftOut::OffPage)
        } else if clipped_away(e, b) {
            Some(LeftOut::ClippedAway)
        } else {
            None
        };
        if dec.left_out.is_some() {
            continue;
        }
        match &e.shape {
            Shape::Image { .. } => dec.left_out = Some(LeftOut::Image),
            // Text is placed once every mark is known, so braille avoids the dots.
            Shape::Text(t) => texts.push((i, t)),
            Shape::Path(p) => {
                let paint = e.paint;
                // A fill that encloses nothing (a `<line>`, which SVG fills by default, or
                // collinear points) is not seen, so not a region: taken for one, it would
                // abut the lines it crosses and lose its vibrating stroke (a chart's axes).
                let filled = paint.filled
                    && paint.fill.is_none_or(|c| visible(c) && (white_is_figure || !paper(c)))
                    && filled_area(&p.outline, p.fill_rule) > MIN_FILL_MM2;
                let stroked = paint.stroked && paint.stroke_width_mm > 0.0 && paint.stroke.is_none_or(visible);
                if filled && backgrounds.contains(&i) {
                    dec.left_out = Some(LeftOut::Background);
                    continue;
                }
                if stroked && faint(paint.stroke) {
                    dec.faint = true;
                    let c = paint.stroke.map(rgb).unwrap_or_default();
                    if !faint_colours.contains(&c) {
                        faint_colours.push(c);
                    }
                } else if stroked {
                    dec.outline = true;
                    let key = paint.stroke.map(rgb);
                    if !strokes.contains(&key) {
                        strokes.push(key);
                    }
                }
                for &(x, y) in &p.markers {
                    dec.mark = true;
                    let r = 1.0 + BRAILLE_CLEARANCE_MM;
                    braille.place((x - r, y - r, x + r, y + r));
                }
                if filled && line_ends.arrowhead(&p.outline, b, paint.fill) {
                    // An arrowhead (a diagram's, a chart's annotation): a
                    // mark at its line's end, not a piece of a tessellation
                    // with the box its tip touches, which would lose its
                    // outline there.
                    if compact(b, filled_area(&p.outline, p.fill_rule)) {
                        dec.mark = true;
                        braille.place(spatial::grow(b, BRAILLE_CLEARANCE_MM));
                    } else if !dec.outline && !dec.mark {
                        dec.left_out = Some(LeftOut::SmallShape);
                    }
                } else if filled {
                    let area = filled_area(&p.outline, p.fill_rule);
                    shapes.push(Filled { i, region: Region { outline: &p.outline, bbox: b }, area });
                } else if !dec.outline && !dec.mark {
                    dec.left_out = Some(if dec.faint { LeftOut::Faint } else { LeftOut::Unpainted });
                }
            }
        }
    }
    // Shapes that share a border with another filled shape are regions of a
    // tessellation (a map's small districts), however small they have become.
    let regions: Vec<Region<'_>> = shapes.iter().map(|f| f.region).collect();
    let neighbours = Neighbours::of(&regions);
    let abuts = neighbours.abutting(ABUT_MM);
    // Small shapes that touch are a tessellation's pieces (a map's small
    // districts), but marks that lie across each other (a dense scatter
    // plot's) stay marks, and so do all the marks of their kind (one fill,
    // one size), the ones that only graze a neighbour too.
    let small_size = |f: &Filled<'_>| {
        let b = f.region.bbox;
        let (w, h) = (b.2 - b.0, b.3 - b.1);
        w.max(h) <= MARK_MM || (w.max(h) <= CIRCLE_MM && round(b, f.area))
    };
    let across = neighbours.lying_across(ABUT_MM, |k| abuts[k] && small_size(&shapes[k]));
    let kind_of = |f: &Filled<'_>| {
        let b = f.region.bbox;
        let size = |v: f64| (v * 100.0).round() as i64;
        (d.elements[f.i].paint.fill.map(rgb), size(b.2 - b.0), size(b.3 - b.1))
    };
    let mut kinds: BTreeMap<_, (usize, bool)> = BTreeMap::new();
    for (k, f) in shapes.iter().enumerate().filter(|(_, f)| small_size(f)) {
        let e = kinds.entry(kind_of(f)).or_default();
        *e = (e.0 + 1, e.1 || across[k]);
    }
    let scattered = |f: &Filled<'_>| kinds.get(&kind_of(f)).is_some_and(|&(n, any)| any && n >= MARK_KIND_MIN);
    let mut class_of = vec![None; shapes.len()];
    let mut kept_marks = Occupancy::default();
    for (k, f) in shapes.iter().enumerate() {
        let e = &d.elements[f.i];
        let b = f.region.bbox;
        let small = small_size(f) && (!abuts[k] || across[k] || scattered(f));
        let dec = &mut decisions[f.i];
        if small {
            if compact(b, f.area) {
                // A dot closer to one already kept than it can be felt apart
                // from is left out: a dense scatter keeps an even sample of its marks.
                let (cx, cy) = ((b.0 + b.2) / 2.0, (b.1 + b.3) / 2.0);
                let half = MARK_SPACING_MM / 2.0;
                if !kept_marks.place((cx - half, cy - half, cx + half, cy + half)) {
                    dec.left_out = Some(LeftOut::Crowded);
                    continue;
                }
                dec.mark = true;
                braille.place(spatial::grow(b, BRAILLE_CLEARANCE_MM));
            } else if !dec.outline && !dec.mark {
                dec.left_out = Some(LeftOut::SmallShape);
            }
            continue;
        }
        let key = e.paint.fill.map(rgb);
        let c = *classes.entry(key).or_insert_with(|| {
            fills.push(FillClass { fill: key, area_mm2: 0.0, regions: 0, first: e.name.clone(), texture: None });
            fills.len() - 1
        });
        fills[c].area_mm2 += f.area;
        fills[c].regions += 1;
        dec.region = Some(c);
        class_of[k] = Some(c);
    }
    // Colour the fill classes: touching regions of different fills get different textures.
    // Touching (or lying in) each other, through the R*-tree.
    let edges = neighbours.class_edges(&class_of, NEAR_MM);
    let mut order: Vec<usize> = (0..fills.len()).collect();
    order.sort_by(|&a, &b| fills[b].area_mm2.total_cmp(&fills[a].area_mm2).then(fills[a].fill.cmp(&fills[b].fill)));
    let colours = colour(fills.len(), &edges, &order, MAX_TEXTURES);
    for (k, c) in colours.into_iter().enumerate() {
        fills[k].texture = c;
    }
    // Report classes largest first; keep decisions pointing at the right class.
    let mut rank = vec![0; fills.len()];
    for (r, &k) in order.iter().enumerate() {
        rank[k] = r;
    }
    let fills: Vec<FillClass> = order.iter().map(|&k| fills[k].clone()).collect();
    // Regions of one fill that share a border (a map's districts drawn in one
    // colour) have one texture on both sides: only an outline tells them apart.
    let alike = neighbours.abutting_alike(&class_of, ABUT_MM);
    let outline = outline_style(profile);
    let min_region = min_region_mm(outline.width_mm);
    // A region its own border band would mostly cover is felt as border, not
    // as a region. The borders of one fill are kept or left out together, so
    // the reader meets one rule across the map rather than a few outlined
    // regions adrift in a texture: left out when most of the fill's regions
    // that share borders with each other are that small (France's 96
    // departments on a 60 mm map), kept when most are large enough (a map of
    // states keeps its few small ones' borders).
    let mut felt = vec![(0usize, 0usize); fills.len()];
    for (k, f) in shapes.iter().enumerate() {
        if let (true, Some(c)) = (alike[k], class_of[k]) {
            felt[rank[c]].0 += usize::from(f.area.sqrt() >= min_region);
            felt[rank[c]].1 += 1;
        }
    }
    let bordered = |c: usize| 2 * felt[c].0 >= felt[c].1;
    let mut too_small = Vec::new();
    for (k, f) in shapes.iter().enumerate() {
        let dec = &mut decisions[f.i];
        if let Some(c) = dec.region {
            let c = rank[c];
            dec.region = Some(c);
            if alike[k] && !bordered(c) {
                too_small.push(f.i);
            }
            if fills[c].texture.is_none() || (alike[k] && bordered(c)) {
                // Given up, or beside its own texture: its outline says where it is.
                dec.outline = true;
            } else if abuts[k] {
                // Between textured regions the border is felt as the change of
                // texture; a stroke on both sides of it would vibrate twice.
                dec.outline = false;
            }
        }
    }
    // Text last, once every mark and vibrating line is known: braille on a
    // vibrating line is felt as neither (the two add up, T0410; a chart's
    // tick labels sat on its axis), so a label is moved off the lines, a
    // little, or left out.
    let room = Room {
        page,
        lines: if texts.is_empty() { Lines::default() } else { Lines::of(d, &decisions) },
        off_lines: BRAILLE_CLEARANCE_MM + outline.width_mm / 2.0,
        figures: if texts.is_empty() { Figures::default() } else { Figures::of(d, &shapes, &abuts, &decisions) },
    };
    // Labels whose braille finds no place are written as a key code (two
    // letters) where that fits, after every whole label has had its place.
    // The larger a label is drawn, the more it matters (a map's region
    // names before its towns, a chart's title before its ticks): where
    // labels compete for room, the larger take it first; labels of one size
    // in document order.
    texts.sort_by(|a, b| b.1.font_size_mm.total_cmp(&a.1.font_size_mm));
    let mut unplaced = Vec::new();
    for (i, t) in texts {
        let own = room.figures.under(&d.elements[i]);
        let dec = &mut decisions[i];
        let boxes = braille_boxes(&t.runs, Some(t), m);
        match place_label(&boxes, &room, &braille, &own) {
            Some((dx, dy)) => {
                for q in &boxes {
                    braille.place((q.0 + dx, q.1 + dy, q.2 + dx, q.3 + dy));
                }
                dec.braille = true;
                dec.braille_shift = (dx, dy);
            }
            None if boxes.is_empty() => dec.left_out = Some(LeftOut::Empty),
            None => {
                dec.left_out = Some(LeftOut::TextDoesNotFit);
                unplaced.push((i, t, own));
            }
        }
    }
    let mut keys = Keys::new(d, &decisions);
    for (i, t, own) in unplaced {
        let Some((code, run)) = keys.code_for(t, m) else { continue };
        let boxes = braille_boxes(std::slice::from_ref(&run), Some(t), m.key());
        if let Some((dx, dy)) = place_label(&boxes, &room, &braille, &own) {
            for q in &boxes {
                braille.place((q.0 + dx, q.1 + dy, q.2 + dx, q.3 + dy));
            }
            keys.take(t, code);
            let dec = &mut decisions[i];
            (dec.braille, dec.braille_shift, dec.key, dec.left_out) = (true, (dx, dy), Some(code), None);
        }
    }
    Plan {
        textures: textures(profile),
        outline,
        fills,
        strokes,
        faint: faint_colours,
        darkest: darkest.map(rgb),
        decisions,
        too_small,
    }
}

/// What a label's braille keeps clear of: the page's edge, the lines the
/// sheet makes vibrate (by `off_lines` mm), and the figures it was not
/// drawn on.
struct Room<'d> {
    page: Bbox,
    lines: Lines<'d>,
    off_lines: f64,
    figures: Figures<'d>,
}

/// Where a label's braille `boxes` go: the shift from its place that the
/// first of its places clear of the page's edge, other braille, the
/// vibrating lines and the figures other than `own` takes, or `None`.
fn place_label(boxes: &[Bbox], room: &Room<'_>, braille: &Occupancy, own: &[usize]) -> Option<(f64, f64)> {
    let page = room.page;
    let inside = |q: &Bbox| q.0 >= page.0 && q.1 >= page.1 && q.2 <= page.2 && q.3 <= page.3;
    // Every run is checked before any is placed, so a label is whole or absent.
    let fits = |(dx, dy): (f64, f64)| {
        boxes.iter().all(|q| {
            let q = (q.0 + dx, q.1 + dy, q.2 + dx, q.3 + dy);
            let near = spatial::grow(q, BRAILLE_CLEARANCE_MM);
            inside(&q)
                && braille.is_free(near)
                && !room.lines.meet(spatial::grow(q, room.off_lines))
                && room.figures.meeting(near).all(|k| own.contains(&k))
        })
    };
    // Then, for a label that runs off the page (a town on the map's
    // east coast, once fitted), the same places pulled back inside.
    let pulled = pull_inside(boxes, page)
        .into_iter()
        .flat_map(|(px, py)| BRAILLE_SHIFTS.iter().map(move |&(sx, sy)| (px + sx, py + sy)));
    let clear_of_braille = boxes.iter().all(|q| braille.is_free(spatial::grow(*q, BRAILLE_CLEARANCE_MM)));
    let below = clear_of_braille.then_some(BELOW_A_LINE);
    let mut shifts = BRAILLE_SHIFTS.iter().copied().chain(below).chain(pulled);
    shifts.find(|&s| !boxes.is_empty() && fits(s))
}

/// A key code: two lowercase Latin letters that stand for a label whose
/// braille finds no place (BANA's Guidelines and Standards for Tactile
/// Graphics, 2010: a label that does not fit is replaced by a short
/// abbreviation explained in a key).
pub type KeyCode = [u8; 2];

/// The key codes of a drawing: each label text that needs one has one
/// (the same text, the same code), no two texts share one, and no code is
/// the text of a label written whole.
struct Keys {
    /// Codes taken, and by which label (empty for a label written whole).
    taken: BTreeMap<KeyCode, String>,
    /// Each keyed label's code.
    of_label: BTreeMap<String, KeyCode>,
}

impl Keys {
    fn new(d: &Drawing, decisions: &[Decision]) -> Keys {
        let mut taken = BTreeMap::new();
        for (e, dec) in d.elements.iter().zip(decisions) {
            let Shape::Text(t) = &e.shape else { continue };
            if let (true, [a, b]) = (dec.braille, t.content.trim().to_lowercase().as_bytes()) {
                taken.insert([*a, *b], String::new());
            }
        }
        Keys { taken, of_label: BTreeMap::new() }
    }

    /// The code for a label, and the run that writes it where the label's
    /// first line starts; `None` for a label shorter than [`MIN_KEYED_CELLS`], or one
    /// with fewer than two Latin letters (a code must say something of what
    /// it stands for: "R108" gets none).
    fn code_for(&self, t: &TextShape, m: Measure<'_>) -> Option<(KeyCode, TextRun)> {
        let text = label_text(t);
        let first = t.runs.iter().find(|r| !r.text.trim().is_empty())?;
        let words: Vec<Vec<u8>> = text
            .split(|c: char| !c.is_alphanumeric())
            .map(|w| w.chars().filter_map(latin_letter).collect::<Vec<u8>>())
            .filter(|w| !w.is_empty())
            .collect();
        let letters: Vec<u8> = words.concat();
        let &initial = letters.first()?;
        let long = text.chars().filter(|c| !c.is_whitespace()).count() >= MIN_KEYED_CELLS
            && m.cells(Some(t), &text) >= MIN_KEYED_CELLS;
        if !long || letters.len() < 2 {
            return None;
        }
        let code = match self.of_label.get(&text) {
            Some(code) => *code,
            None => {
                // The first letters of its first two words, then its first
                // letter with each later one, then with any letter, then
                // any free pair.
                let initials = words.get(1).and_then(|w| w.first()).map(|&b| [initial, b]);
                let with_first = letters.iter().skip(1).map(|&b| [initial, b]);
                let first_any = (b'a'..=b'z').map(|b| [initial, b]);
                let any = (b'a'..=b'z').flat_map(|a| (b'a'..=b'z').map(move |b| [a, b]));
                initials
                    .into_iter()
                    .chain(with_first)
                    .chain(first_any)
                    .chain(any)
                    .find(|c| !self.taken.contains_key(c))?
            }
        };
        let run = TextRun { text: String::from_utf8_lossy(&code).into_owned(), continues: false, ..first.clone() };
        Some((code, run))
    }

    fn take(&mut self, t: &TextShape, code: KeyCode) {
        let text = label_text(t);
        self.of_label.insert(text.clone(), code);
        self.taken.insert(code, text);
    }
}

/// The key of a drawing's key codes (T0326) as one line of print, codes in
/// order: `"key: bs Bundle Store, kf 1 kHz frames"`; empty when it has none.
pub fn key_line(d: &Drawing) -> String {
    let mut key: BTreeMap<&str, &str> = BTreeMap::new();
    for e in &d.elements {
        if let Shape::Text(TextShape { content, keyed: Some(label), .. }) = &e.shape {
            key.insert(content, label);
        }
    }
    if key.is_empty() {
        return String::new();
    }
    let entries: Vec<String> = key.iter().map(|(code, label)| format!("{code} {label}")).collect();
    format!("key: {}", entries.join(", "))
}

/// A label's words, its runs joined by spaces (the lines of a label).
pub fn label_text(t: &TextShape) -> String {
    let words: Vec<&str> = t.runs.iter().flat_map(|r| r.text.split_whitespace()).collect();
    words.join(" ")
}

/// A letter as a key code's letter: Latin, lowercase, without its accents.
fn latin_letter(c: char) -> Option<u8> {
    use unicode_normalization::UnicodeNormalization;
    let base = c.nfd().next()?.to_ascii_lowercase();
    base.is_ascii_lowercase().then_some(base as u8)
}

/// The fewest characters and braille cells a label takes to be worth a key
/// code (two cells): one of two characters ("No", "Nr") is written whole or not at all.
const MIN_KEYED_CELLS: usize = 3;

/// How many of a drawing's key codes note T0326 shows.
const KEY_SHOWN: usize = 8;

/// The size (the side of a square of the same area) below which a region's
/// own vibrating border, `width` wide and centred on its outline, would cover
/// more than half of it: the band's inner half takes `width / 2` from each
/// side, so a square of side `s` keeps `(s - width)²` of its `s²` as texture,
/// and that is half when `s = width / (1 - 1/√2)`, about 3.4 widths (5.1 mm
/// for the 1.5 mm outline).
///
/// ```
/// let s = taxel_compiler::auto::min_region_mm(1.5);
/// assert!(((s - 1.5) * (s - 1.5) / (s * s) - 0.5).abs() < 1e-12);
/// ```
pub fn min_region_mm(width: f64) -> f64 {
    width / (1.0 - std::f64::consts::FRAC_1_SQRT_2)
}

/// The page backgrounds among the filled paths: those covering nine tenths of
/// the drawing's own page (`sheet`, where it lies on the felt `page`), and
/// those covering nine tenths of what the drawing occupies when other
/// filled shapes lie on them (a sea under the countries; a lone country with
/// only labels on it stays a region).
fn backgrounds(d: &Drawing, page: Bbox, sheet: Bbox) -> Vec<usize> {
    let area = |b: Bbox| (b.2 - b.0).max(0.0) * (b.3 - b.1).max(0.0);
    let clip = |b: Bbox| (b.0.max(page.0), b.1.max(page.1), b.2.min(page.2), b.3.min(page.3));
    let filled = |e: &Element| matches!(e.shape, Shape::Path(_)) && e.visible && e.paint.filled;
    // Every element's box as far as its clip regions let it be seen (a
    // page-sized shape clipped to a small square is that square), worked out
    // once and in parallel (each is a pass over its outline).
    let bounds: Vec<Option<Bbox>> = {
        use rayon::prelude::*;
        d.elements.par_iter().map(seen_bounds).collect()
    };
    let boxes: Vec<Option<Bbox>> =
        d.elements.iter().zip(&bounds).map(|(e, b)| b.filter(|_| filled(e)).map(clip)).collect();
    let extent = d
        .elements
        .iter()
        .zip(&bounds)
        .filter(|(e, _)| e.visible)
        .filter_map(|(_, b)| *b)
        .map(clip)
        .reduce(|a, b| (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3)));
    let Some(extent) = extent else { return Vec::new() };
    let mut out = Vec::new();
    // Each candidate looks at every other shape once; a drawing has a few
    // backgrounds, so a flood of page-sized shapes is cut short (never all pairs).
    let mut candidates = 0;
    let mut panels = 0;
    // What a shape covers is its own area on the page, not its box's: a flag's
    // cross or a logo's disc spans the page without covering it.
    let covered = |i: usize| match (&d.elements[i].shape, boxes[i]) {
        (Shape::Path(p), Some(seen)) => area_within(&p.outline, p.fill_rule, seen),
        _ => 0.0,
    };
    for (i, b) in boxes.iter().enumerate() {
        let Some(b) = *b else { continue };
        if area(sheet) > 0.0
            && area(b) >= BACKGROUND_SHARE * area(sheet)
            && covered(i) >= BACKGROUND_SHARE * area(sheet)
        {
            out.push(i);
        } else if area(b) >= BACKGROUND_SHARE * area(extent)
            && candidates < 8
            && covered(i) >= BACKGROUND_SHARE * area(extent)
        {
            candidates += 1;
            let under = |j: usize, o: Bbox| {
                j != i && o.0 >= b.0 && o.1 >= b.1 && o.2 <= b.2 && o.3 <= b.3 && (o.2 - o.0).max(o.3 - o.1) > MARK_MM
            };
            if boxes.iter().enumerate().any(|(j, o)| o.is_some_and(|o| under(j, o))) {
                out.push(i);
            }
        } else if panels < 8 && very_light(&d.elements[i]) && covered(i) >= BACKGROUND_SHARE * area(b) {
            // A chart's plot panel: a very light rectangle (Plotly's
            // #e5ecf6, ggplot2's #ebebeb, seaborn's #eaeaf2) with coloured
            // shapes painted on it (the bars), which the panel only sets off.
            panels += 1;
            let on_it = |j: usize, o: Bbox| {
                j > i
                    && o.0 >= b.0
                    && o.1 >= b.1
                    && o.2 <= b.2
                    && o.3 <= b.3
                    && (o.2 - o.0).max(o.3 - o.1) > MARK_MM
                    && !very_light(&d.elements[j])
            };
            if boxes.iter().enumerate().any(|(j, o)| o.is_some_and(|o| on_it(j, o))) {
                out.push(i);
            }
        }
    }
    out
}

/// Whether an element's fill is very light: every channel, over white
/// paper after its opacity, at least [`LIGHT_GUIDE`] (a gradient's or a
/// pattern's is not known, so not).
fn very_light(e: &Element) -> bool {
    e.paint.fill.is_some_and(|c| {
        let a = c[3] as f64 / 255.0;
        c[..3].iter().all(|&v| a * v as f64 + (1.0 - a) * 255.0 >= LIGHT_GUIDE as f64)
    })
}

/// The box of what can be seen of an element: its bounds within the boxes
/// of its clip regions; `None` when it has no outline or they leave nothing.
pub(crate) fn seen_bounds(e: &Element) -> Option<Bbox> {
    let mut b = e.bounds()?;
    if let Shape::Path(p) = &e.shape {
        for c in &p.clips {
            let cb = crate::geometry::bounds(&c.outline)?;
            b = (b.0.max(cb.0), b.1.max(cb.1), b.2.min(cb.2), b.3.min(cb.3));
        }
    }
    (b.0 <= b.2 && b.1 <= b.3).then_some(b)
}

/// Area a fill of `polys` under `rule` covers inside the box `b`: each ring
/// clipped to the box (Sutherland and Hodgman: exact for a convex window),
/// then [`filled_area`].
fn area_within(polys: &[Polyline], rule: FillRule, b: Bbox) -> f64 {
    // The window's four sides as "keep where f(p) >= 0" and the crossing with the side.
    type Side = (fn((f64, f64), f64) -> f64, f64);
    let sides: [Side; 4] =
        [(|p, x0| p.0 - x0, b.0), (|p, y0| p.1 - y0, b.1), (|p, x1| x1 - p.0, b.2), (|p, y1| y1 - p.1, b.3)];
    let clipped: Vec<Polyline> = polys
        .iter()
        .map(|pl| {
            let mut ring = pl.points.clone();
            for (f, v) in sides {
                let n = ring.len();
                let mut next = Vec::with_capacity(n + 4);
                for k in 0..n {
                    let (a, c) = (ring[k], ring[(k + 1) % n]);
                    let (fa, fc) = (f(a, v), f(c, v));
                    if fa >= 0.0 {
                        next.push(a);
                    }
                    if (fa >= 0.0) != (fc >= 0.0) {
                        let t = fa / (fa - fc);
                        next.push((a.0 + t * (c.0 - a.0), a.1 + t * (c.1 - a.1)));
                    }
                }
                ring = next;
            }
            Polyline { points: ring, closed: true }
        })
        .collect();
    filled_area(&clipped, rule)
}

/// Whether one of the element's clip regions lies wholly away from it.
fn clipped_away(e: &Element, b: Bbox) -> bool {
    let Shape::Path(p) = &e.shape else { return false };
    p.clips.iter().any(|c| crate::geometry::bounds(&c.outline).is_none_or(|cb| !spatial::meet(cb, b)))
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
        }
    }
    notes(&plan, d, diags);
    plan
}

/// The passes between the resolved drawing and its layers that make a
/// drawing as teachers have it usable: `--region` and `--fit` (and cropping to
/// the surface, [`crate::fit::apply`]); then the automatic sheet, where
/// `--style auto` asks for it or where nothing else styles the drawing (no
/// annotation, no style sheet; with note T0320); then the note saying how many
/// elements became which style. Returns `false` when an error stops the
/// compilation (a region that cannot be taken).
pub fn prepare(d: &mut Drawing, opts: &crate::CompileOptions, diags: &mut Vec<Diagnostic>) -> bool {
    // Whether the author annotated the drawing is decided on the whole
    // drawing: annotated shapes that cropping leaves out (beyond the surface,
    // outside `--region`) still make it an annotated drawing, not one for the
    // automatic sheet.
    let annotated = !unannotated(d);
    if !crate::fit::apply(d, &opts.profile, opts.fit, opts.region.as_ref(), diags) {
        return false;
    }
    if annotated && unannotated(d) {
        diags.push(
            Diagnostic::warning(
                "T0205",
                format!(
                    "every annotated shape lies {} the {} surface: nothing annotated is left to build",
                    if opts.region.is_some() { "outside the region or beyond" } else { "beyond" },
                    opts.profile.name
                ),
            )
            .with_help(
                "build with --fit to scale the drawing to the surface, or --region to take the part you annotated",
            ),
        );
    }
    let implicit = !opts.auto && opts.style.is_none() && !annotated;
    if implicit {
        diags.push(
            Diagnostic::note(
                "T0320",
                "nothing in the drawing is annotated: the automatic style sheet decided its tactile styles",
            )
            .with_help("`taxel style auto INPUT` prints what it decided as a style sheet to start your own from"),
        );
    }
    if opts.auto || implicit {
        apply_measured(d, &opts.profile, Measure::of(opts), diags);
    }
    diags.push(summary(d));
    true
}

impl LeftOut {
    /// What it says in a message.
    pub fn describe(self) -> &'static str {
        match self {
            LeftOut::Hidden => "hidden",
            LeftOut::Empty => "empty",
            LeftOut::OffPage => "off the page",
            LeftOut::ClippedAway => "clipped away",
            LeftOut::Background => "page background(s)",
            LeftOut::Unpainted => "with no visible fill or stroke (white, transparent or none)",
            LeftOut::SmallShape => "small shape(s) (glyph outlines, slivers)",
            LeftOut::TextDoesNotFit => "text whose braille does not fit",
            LeftOut::Image => "image(s)",
            LeftOut::Faint => "faint grey line(s)",
            LeftOut::Crowded => "mark(s) too crowded to feel apart",
        }
    }
}

/// Why the automatic sheet made nothing of `d`, when it made nothing: how
/// many elements it left out for which reason, most first (`3 hidden, 2
/// images`), for the error that says nothing tactile was found. `None` when
/// it styled something (then the layers say why nothing was made).
pub fn nothing_made(d: &Drawing, profile: &DeviceProfile) -> Option<String> {
    let plan = plan(d, profile);
    if (0..d.elements.len()).any(|i| !plan.styles(i).is_empty()) {
        return None;
    }
    // An element the sheet did not decide was styled by an annotation or a sheet: as nothing.
    let mut why: BTreeMap<&str, usize> = BTreeMap::new();
    for dec in &plan.decisions {
        *why.entry(dec.left_out.map_or("annotated `none`", LeftOut::describe)).or_default() += 1;
    }
    let mut why: Vec<(&str, usize)> = why.into_iter().collect();
    why.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
    Some(match d.elements.len() {
        0 => "the drawing has no elements that are drawn".into(),
        n => format!(
            "the automatic style sheet left out all {n} element(s): {}",
            why.iter().map(|(w, k)| format!("{k} {w}")).collect::<Vec<_>>().join(", ")
        ),
    })
}

/// A fill for messages: `#rrggbb`, or `a gradient`.
pub fn fill_name(f: Option<[u8; 3]>) -> String {
    f.map_or("a gradient or pattern".into(), |c| format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2]))
}

/// Up to three names, then how many more.
fn first_three(names: &[String]) -> String {
    let mut s = names.iter().take(3).cloned().collect::<Vec<_>>().join(", ");
    if names.len() > 3 {
        s += &format!(" and {} more", names.len() - 3);
    }
    s
}

fn notes(plan: &Plan, d: &Drawing, diags: &mut Vec<Diagnostic>) {
    let dropped: Vec<String> = plan.fills.iter().filter(|f| f.texture.is_none()).map(|f| fill_name(f.fill)).collect();
    if !dropped.is_empty() {
        diags.push(
            Diagnostic::note(
                "T0321",
                format!(
                    "{} fill colour(s) became outlines only, because more than {MAX_TEXTURES} textures would be needed where they touch: {}",
                    dropped.len(),
                    first_three(&dropped)
                ),
            )
            .with_help("give them textures in a style sheet (start from `taxel style auto INPUT`), or split the drawing"),
        );
    }
    // One note for every texture that is shared: a note per texture would be
    // grouped into one line naming a single texture for all of them.
    let shared: Vec<String> = plan
        .textures
        .iter()
        .enumerate()
        .filter_map(|(t, g)| {
            let sharing: Vec<String> =
                plan.fills.iter().filter(|f| f.texture == Some(t)).map(|f| fill_name(f.fill)).collect();
            (sharing.len() > 1)
                .then(|| format!("{} share grating({} mm, {}°)", first_three(&sharing), g.wavelength_mm, g.angle_deg))
        })
        .collect();
    if !shared.is_empty() {
        diags.push(Diagnostic::note(
            "T0322",
            format!("fills whose regions do not touch share textures: {}", shared.join("; ")),
        ));
    }
    if !plan.too_small.is_empty() {
        let names: Vec<String> = plan.too_small.iter().map(|&i| format!("#{}", d.elements[i].name)).collect();
        diags.push(
            Diagnostic::note(
                "T0324",
                format!(
                    "the borders between {} region(s) of one fill are left out, so they are felt as one texture: most are under {:.1} mm across, where a {} mm border would cover most of each ({})",
                    names.len(),
                    min_region_mm(plan.outline.width_mm),
                    plan.outline.width_mm,
                    first_three(&names)
                ),
            )
            .with_help("to feel them apart, take part of the drawing with --region so they are larger, or give them colours of their own"),
        );
    }
    let faint = plan.decisions.iter().filter(|dec| dec.faint).count();
    if faint > 0 {
        let colours: Vec<String> = plan.faint.iter().map(|&c| fill_name(Some(c))).collect();
        let first = plan.faint.first().map_or_else(|| "#dddddd".to_string(), |&c| fill_name(Some(c)));
        diags.push(
            Diagnostic::note(
                "T0325",
                format!(
                    "{faint} faint grey stroke(s) left out ({}): less than {:.0} % as dark as the darkest lines ({}), or as light as {}, as a chart's grid lines are, so the axes and the data are felt rather than the grid",
                    first_three(&colours),
                    FAINT_SHARE * 100.0,
                    fill_name(plan.darkest),
                    fill_name(Some([LIGHT_GUIDE; 3])),
                ),
            )
            .with_help(format!(
                "to feel them, weaker than the other lines, use a style sheet with a rule `stroke = \"{first}\"`, `tactile = \"vibrate(amplitude: 0.5)\"` (start from `taxel style auto INPUT`)"
            )),
        );
    }
    let mut key: BTreeMap<KeyCode, &str> = BTreeMap::new();
    for (dec, e) in plan.decisions.iter().zip(&d.elements) {
        if let Some(code) = dec.key {
            key.insert(code, &e.label);
        }
    }
    if !key.is_empty() {
        let shown: Vec<String> =
            key.iter().take(KEY_SHOWN).map(|(c, label)| format!("{} {label}", String::from_utf8_lossy(c))).collect();
        let more = if key.len() > KEY_SHOWN { format!(" and {} more", key.len() - KEY_SHOWN) } else { String::new() };
        diags.push(
            Diagnostic::note(
                "T0326",
                format!(
                    "{} label(s) too long for their place are written as two-letter key codes: {}{more}",
                    key.len(),
                    shown.join("; ")
                ),
            )
            .with_help("a keyed label's words are its name in the bundle, said when the finger is on it; the whole key is the bundle's provenance entry `key` (`taxel unpack` lists it) and a Dot Pad's text line"),
        );
    }
    let crowded: Vec<String> = plan
        .decisions
        .iter()
        .zip(&d.elements)
        .filter(|(dec, _)| dec.left_out == Some(LeftOut::Crowded))
        .map(|(_, e)| format!("#{}", e.name))
        .collect();
    if !crowded.is_empty() {
        let kept = plan.decisions.iter().filter(|dec| dec.mark).count();
        diags.push(
            Diagnostic::note(
                "T0327",
                format!(
                    "{} mark(s) left out, too crowded to feel apart: {kept} dot(s) are kept, an even sample with centres at least {MARK_SPACING_MM:.1} mm apart ({})",
                    crowded.len(),
                    first_three(&crowded)
                ),
            )
            .with_help("to feel more of them, take part of the drawing with --region so they spread out, or draw a density texture (a grating) in a style sheet"),
        );
    }
    let text: Vec<String> = plan
        .decisions
        .iter()
        .zip(&d.elements)
        .filter(|(dec, _)| dec.left_out == Some(LeftOut::TextDoesNotFit))
        .map(|(_, e)| format!("#{}", e.name))
        .collect();
    if !text.is_empty() {
        diags.push(
            Diagnostic::note(
                "T0323",
                format!(
                    "{} text element(s) left out: their braille would leave the page, or run into other braille or a vibrating line ({})",
                    text.len(),
                    first_three(&text)
                ),
            )
            .with_help("braille cells are 6.2 mm wide: shorten the labels, or take part of the drawing with --region"),
        );
    }
}

/// One note saying how many elements became which tactile style, for any
/// drawing (annotated, styled by a sheet, or automatic).
pub fn summary(d: &Drawing) -> Diagnostic {
    let mut counts: BTreeMap<&'static str, usize> = BTreeMap::new();
    let mut none = 0;
    for e in &d.elements {
        if e.styles.is_empty() {
            none += 1;
        }
        let mut seen: Vec<&'static str> = e.styles.iter().map(Style::name).collect();
        seen.sort_unstable();
        seen.dedup();
        for n in seen {
            *counts.entry(n).or_default() += 1;
        }
    }
    let order = ["vibrate", "grating", "dots", "dot", "brush", "braille"];
    let mut parts: Vec<String> =
        order.iter().filter_map(|n| counts.get(n).map(|c| format!("{c} {n}"))).collect::<Vec<_>>();
    if none > 0 {
        parts.push(format!("{none} left out"));
    }
    let by = if d.elements.iter().any(|e| e.styled_by == StyledBy::Auto) { " (automatic style sheet)" } else { "" };
    Diagnostic::note(
        "T0330",
        format!(
            "{} element(s){by}: {}",
            d.elements.len(),
            if parts.is_empty() { "none".into() } else { parts.join(", ") }
        ),
    )
}

#[cfg(test)]
mod tests;
