//! Where a label's braille goes: its boxes, the places tried around its own,
//! and what it keeps clear of (the page's edge, other braille, the lines the
//! sheet makes vibrate, the figures it was not drawn on).

use super::keys::Keys;
use super::{BRAILLE_CLEARANCE_MM, BRAILLE_RADIUS_MM, Decision, Filled, LeftOut, Measure};
use crate::braille::paper::{CELL_PITCH_MM, DOT_PITCH_MM};
use crate::drawing::{Drawing, Element, Shape, TextRun, TextShape};
use crate::geometry::{FillRule, Polyline};
use crate::spatial::{self, Bbox, Occupancy};

/// Boxes of the braille an element's text would make: one per run, placed as
/// the layer builder places it (from the run's start, after its anchor).
pub(super) fn braille_boxes(runs: &[TextRun], shape: Option<&TextShape>, m: Measure<'_>) -> Vec<Bbox> {
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

/// The regions that stand alone, for braille to keep off unless it was
/// drawn on them: a chart's bars, a diagram's boxes, a legend's swatches.
/// Braille clears a grating around itself (the layers' clearing), so a
/// label moved onto a bar it was not drawn on would cut the bar short. The
/// regions of a tessellation (a map's, whose labels lie across its borders)
/// are not figures.
#[derive(Default)]
pub(super) struct Figures<'d> {
    outlines: Vec<(&'d [Polyline], FillRule)>,
    index: Option<spatial::BoxIndex>,
}

impl<'d> Figures<'d> {
    pub(super) fn of(d: &'d Drawing, shapes: &[Filled<'d>], abuts: &[bool], decisions: &[Decision]) -> Figures<'d> {
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
    pub(super) fn under(&self, e: &Element) -> Vec<usize> {
        e.bounds().map(|b| self.meeting(b).collect()).unwrap_or_default()
    }
}

/// The outlines the sheet makes vibrate, for braille to keep off: their
/// boxes in an R*-tree, each outline's segments looked at only when its box
/// meets a label's (a scatter plot's 5,651 stroked circles made an R*-tree
/// of half a million segments, slower to build than the labels need).
#[derive(Default)]
pub(super) struct Lines<'d> {
    outlines: Vec<&'d [Polyline]>,
    index: Option<spatial::BoxIndex>,
}

impl<'d> Lines<'d> {
    pub(super) fn of(d: &'d Drawing, decisions: &[Decision]) -> Lines<'d> {
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

/// What a label's braille keeps clear of: the page's edge, the lines the
/// sheet makes vibrate (by `off_lines` mm), and the figures it was not
/// drawn on.
pub(super) struct Room<'d> {
    pub(super) page: Bbox,
    pub(super) lines: Lines<'d>,
    pub(super) off_lines: f64,
    pub(super) figures: Figures<'d>,
}

/// Where a label's braille `boxes` go: the shift from its place that the
/// first of its places clear of the page's edge, other braille, the
/// vibrating lines and the figures other than `own` takes, or `None`.
pub(super) fn place_label(boxes: &[Bbox], room: &Room<'_>, braille: &Occupancy, own: &[usize]) -> Option<(f64, f64)> {
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

/// Places the braille of `texts` in `room`, clear of the braille already
/// placed. Labels whose braille finds no place are written as a key code
/// (two letters) where that fits, after every whole label has had its place.
/// The larger a label is drawn, the more it matters (a map's region names
/// before its towns, a chart's title before its ticks): where labels compete
/// for room, the larger take it first; labels of one size in document order.
pub(super) fn place_labels<'d>(
    d: &'d Drawing,
    mut texts: Vec<(usize, &'d TextShape)>,
    room: &Room<'d>,
    decisions: &mut [Decision],
    braille: &mut Occupancy,
    m: Measure<'_>,
) {
    texts.sort_by(|a, b| b.1.font_size_mm.total_cmp(&a.1.font_size_mm));
    let mut unplaced = Vec::new();
    for (i, t) in texts {
        let own = room.figures.under(&d.elements[i]);
        let dec = &mut decisions[i];
        let boxes = braille_boxes(&t.runs, Some(t), m);
        match place_label(&boxes, room, braille, &own) {
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
    let mut keys = Keys::new(d, decisions);
    for (i, t, own) in unplaced {
        let Some((code, run)) = keys.code_for(t, m) else { continue };
        let boxes = braille_boxes(std::slice::from_ref(&run), Some(t), m.key());
        if let Some((dx, dy)) = place_label(&boxes, room, braille, &own) {
            for q in &boxes {
                braille.place((q.0 + dx, q.1 + dy, q.2 + dx, q.3 + dy));
            }
            keys.take(t, code);
            let dec = &mut decisions[i];
            (dec.braille, dec.braille_shift, dec.key, dec.left_out) = (true, (dx, dy), Some(code), None);
        }
    }
}
