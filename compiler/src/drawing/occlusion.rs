//! Occlusion, part of the drawing as written: opaque fills hide what is
//! painted under them, on paper as under the finger.

use super::{Drawing, Shape};
use crate::spatial::{Bbox, BoxIndex};

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
}
