//! Arrowheads: small filled shapes of a line's colour where the line ends,
//! which become dot symbols rather than pieces of a tessellation.

use super::{MARK_MM, rgb};
use crate::drawing::{Drawing, Rgba, Shape, StyledBy};
use crate::geometry::Polyline;
use crate::spatial::{self, Bbox};

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
pub(super) struct LineEnds {
    /// Each end's line's colour and length, mm.
    lines: Vec<([u8; 3], f64)>,
    index: spatial::BoxIndex,
}

impl LineEnds {
    pub(super) fn of(d: &Drawing) -> LineEnds {
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
    pub(super) fn arrowhead(&self, outline: &[Polyline], b: Bbox, fill: Option<Rgba>) -> bool {
        let Some(fill) = fill.map(rgb) else { return false };
        let size = (b.2 - b.0).max(b.3 - b.1);
        let few_corners = matches!(outline, [l] if l.points.len() <= ARROW_CORNERS);
        few_corners
            && size <= MARK_MM
            && self.index.meeting(b).any(|k| self.lines[k].0 == fill && self.lines[k].1 >= SHAFT_PER_HEAD * size)
    }
}
