//! Occlusion, part of the drawing as written: opaque fills hide what is
//! painted under them, on paper as under the finger.

use super::{Drawing, Shape};
use crate::geometry::crossings::{Segment, crossings_exceed};
use crate::geometry::overlay;
use crate::spatial::{Bbox, BoxIndex};

/// Most crossings of a shape's outline with those of the fills over it for
/// which what they leave of it is measured (an overlay's work follows them).
const MAX_CROSSINGS: usize = 10_000;

/// Most outline points (sides), the shapes' and the fills' over them together,
/// that [`OpaqueFills::hide_all`] runs overlays on for one key entry: past
/// it the texture counts as felt (a sea painted over ten thousand islands
/// of one texture costs a bounded time).
const MAX_POINTS: usize = 250_000;

/// Less area than this left of a shape under the fills over it, in mm²,
/// is none: a sliver a tenth of a millimetre square, far finer than a
/// texture's lattice or a finger.
const LEFT_MM2: f64 = 0.01;

/// The opaque fills of `drawing` that hide a grated layer made of
/// `elements` (drawing indices, in drawing order), as the layers are built:
/// solid, opaque, visible, unclipped fills painted over some of the
/// elements and under none of them. For `taxel report`'s exact reference,
/// which must leave out what the layer leaves out.
pub fn occluders(drawing: &Drawing, elements: &[usize]) -> Vec<usize> {
    OpaqueFills::of(drawing).above(drawing, elements)
}

/// The drawing's opaque filled shapes, which hide what is painted under them.
pub(crate) struct OpaqueFills {
    /// Element index and bounds of each.
    shapes: Vec<(usize, Bbox)>,
    index: BoxIndex,
}

impl OpaqueFills {
    pub(crate) fn of(drawing: &Drawing) -> Self {
        let shapes: Vec<(usize, Bbox)> = drawing
            .elements
            .iter()
            .enumerate()
            .filter(|(_, e)| {
                // A solid, opaque, visible, unclipped fill (a gradient's or a
                // clip's coverage is not known exactly, so it hides nothing).
                e.visible
                    && e.paint.fill.is_some_and(|c| c[3] == u8::MAX)
                    && matches!(&e.shape, Shape::Path(p) if p.clips.is_empty())
            })
            .filter_map(|(i, e)| crate::geometry::bounds(e.outline()).map(|b| (i, b)))
            .collect();
        let index = BoxIndex::new(&shapes.iter().map(|s| s.1).collect::<Vec<_>>());
        OpaqueFills { shapes, index }
    }

    /// The opaque fills painted over some of `elements` (drawing indices, in
    /// drawing order) and under none of them: a grated layer is not felt
    /// where they cover it, as it is not seen there. A fill that lies between
    /// two of the layer's shapes hides nothing (the layer is one union), so
    /// the overlap stays and the design rules report it.
    pub(crate) fn above(&self, drawing: &Drawing, elements: &[usize]) -> Vec<usize> {
        let boxes: Vec<(usize, Bbox)> = elements
            .iter()
            .filter_map(|&i| crate::geometry::bounds(drawing.elements[i].outline()).map(|b| (i, b)))
            .collect();
        let mine = BoxIndex::new(&boxes.iter().map(|b| b.1).collect::<Vec<_>>());
        let mut seen = std::collections::HashSet::new();
        let mut out = Vec::new();
        for &(i, b) in &boxes {
            for k in self.index.meeting(b) {
                let Some(&(j, bj)) = self.shapes.get(k) else { continue };
                if j <= i || !seen.insert(j) {
                    continue;
                }
                if mine.meeting(bj).all(|m| boxes.get(m).is_some_and(|&(e, _)| e < j)) {
                    out.push(j);
                }
            }
        }
        out
    }

    /// Whether the opaque fills painted over the filled `elements` ([`Self::above`]:
    /// over some of them and under none) hide every one of them wholly, so
    /// that nothing of their texture is felt, as nothing of it is seen: each
    /// element's fill less the fills over it leaves no area. `false` when
    /// that cannot be told within a budget (outlines that cross too often,
    /// more points than [`MAX_POINTS`], coordinates beyond the overlay's
    /// range): a texture is then counted as felt.
    pub(crate) fn hide_all(&self, drawing: &Drawing, elements: &[usize]) -> bool {
        let over = self.above(drawing, elements);
        let mut budget = MAX_POINTS;
        !over.is_empty() && elements.iter().all(|&i| self.hides(drawing, i, &over, &mut budget))
    }

    /// Whether the fills `over` (drawing indices) that are painted after
    /// element `i` leave nothing of its fill.
    fn hides(&self, drawing: &Drawing, i: usize, over: &[usize], budget: &mut usize) -> bool {
        let Some(Shape::Path(p)) = drawing.elements.get(i).map(|e| &e.shape) else { return false };
        let Some(b) = crate::geometry::bounds(&p.outline) else { return true };
        let meets = |o: Bbox| o.0 <= b.2 && b.0 <= o.2 && o.1 <= b.3 && b.1 <= o.3;
        let fills: Vec<(&super::PathShape, Bbox)> = over
            .iter()
            .filter(|&&j| j > i)
            .filter_map(|&j| {
                let k = self.shapes.binary_search_by_key(&j, |s| s.0).ok()?;
                let bj = self.shapes[k].1;
                match &drawing.elements.get(j)?.shape {
                    Shape::Path(q) if meets(bj) => Some((q, bj)),
                    _ => None,
                }
            })
            .collect();
        if fills.is_empty() {
            return false;
        }
        let segments: Vec<Segment> = std::iter::once(&p.outline)
            .chain(fills.iter().map(|(q, _)| &q.outline))
            .flat_map(|pls| pls.iter())
            .flat_map(|pl| {
                let n = pl.points.len();
                (0..if n > 1 { n } else { 0 }).map(move |k| (pl.points[k], pl.points[(k + 1) % n]))
            })
            .collect();
        match budget.checked_sub(segments.len()) {
            Some(left) => *budget = left,
            None => return false,
        }
        if crossings_exceed(&segments, MAX_CROSSINGS) {
            return false;
        }
        let all = fills.iter().fold(b, |a, (_, o)| (a.0.min(o.0), a.1.min(o.1), a.2.max(o.2), a.3.max(o.3)));
        let Some(f) = overlay::Frame::over(all) else { return false };
        let cover: Vec<_> = fills.iter().flat_map(|(q, _)| overlay::simple(&q.outline, q.fill_rule, f)).collect();
        let left = overlay::difference(&overlay::simple(&p.outline, p.fill_rule, f), &cover);
        overlay::area(&left) * f.q * f.q < LEFT_MM2
    }
}
