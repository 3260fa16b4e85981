//! The print media's design rules (`docs/diagnostics.md`, T0720 to T0727),
//! judged on the legalised marks in paper millimetres, after `--fit`:
//! - T0722: braille over a raised line, symbol or dot of another element;
//! - T0723: raised lines of two elements closer than the medium's minimum
//!   gap without touching (felt as one);
//! - T0724: a textured region smaller than the medium's minimum texture area;
//! - T0725: a line narrower than a relief's grid step (it would vanish; an
//!   embosser's lost marks are found when its grid is made, `grid.rs`).
//!
//! T0721 (lines widened), T0726 (more styles than the medium tells apart)
//! and T0728 (point symbols left out where they would touch) are said where
//! the marks are made; T0727 where the key is laid out.

use std::collections::BTreeMap;

use taxel_format::{Medium, PrintParams};

use super::braille::Labels;
use super::{Level, Mark, MarkShape};
use crate::annotation::Style;
use crate::diagnostic::Diagnostic;
use crate::drawing::{Drawing, Element, PathShape, Shape};
use crate::spatial::{self, Bbox, BoxIndex};

/// T0724 for a grated region whose box is smaller than the minimum texture area's side.
pub(super) fn texture_area(p: &PrintParams, e: &Element, path: &PathShape, diags: &mut Vec<Diagnostic>) {
    let Some(b) = crate::geometry::bounds(&path.outline) else { return };
    let side = p.min_texture_mm as f64;
    let (w, h) = (b.2 - b.0, b.3 - b.1);
    if w < side || h < side {
        diags.push(
            Diagnostic::warning(
                "T0724",
                format!(
                    "the textured region is {:.1} x {:.1} mm, smaller than the {side} x {side} mm a texture needs \
                     to be felt as one on this medium",
                    w, h
                ),
            )
            .with_element(e.name.clone())
            .on_line(e.line)
            .with_help("make the region larger (or --fit to a larger paper), or give it an outline instead"),
        );
    }
}

fn mark_box(m: &Mark) -> Option<Bbox> {
    let (pts, grow): (Box<dyn Iterator<Item = &(f64, f64)>>, f64) = match &m.shape {
        MarkShape::Line { points, width_mm, .. } => (Box::new(points.iter()), width_mm / 2.0),
        MarkShape::Polygon { rings } => (Box::new(rings.iter().flatten()), 0.0),
        MarkShape::Dot { centre, diameter_mm } => (Box::new(std::iter::once(centre)), diameter_mm / 2.0),
    };
    let b = pts.fold(None, |b: Option<Bbox>, p| {
        Some(b.map_or((p.0, p.1, p.0, p.1), |b| (b.0.min(p.0), b.1.min(p.1), b.2.max(p.0), b.3.max(p.1))))
    })?;
    (b.0.is_finite() && b.1.is_finite() && b.2.is_finite() && b.3.is_finite()).then(|| spatial::grow(b, grow))
}

/// Whether a raised mark reaches into box `b`: a line within half its width
/// of it, a dot or polygon whose box meets it.
fn reaches(m: &Mark, b: Bbox) -> bool {
    match &m.shape {
        MarkShape::Line { points, width_mm, .. } => {
            let g = spatial::grow(b, width_mm / 2.0);
            let inside = |p: &(f64, f64)| p.0 >= g.0 && p.0 <= g.2 && p.1 >= g.1 && p.1 <= g.3;
            points.iter().any(inside) || points.windows(2).any(|w| segment_meets_box(w[0], w[1], g))
        }
        _ => mark_box(m).is_some_and(|mb| spatial::meet(mb, b)),
    }
}

fn segment_meets_box(a: (f64, f64), b: (f64, f64), bx: Bbox) -> bool {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [(-dx, a.0 - bx.0), (dx, bx.2 - a.0), (-dy, a.1 - bx.1), (dy, bx.3 - a.1)] {
        if p == 0.0 {
            if q < 0.0 {
                return false;
            }
        } else if p < 0.0 {
            t0 = t0.max(q / p);
        } else {
            t1 = t1.min(q / p);
        }
    }
    t0 <= t1
}

/// The rules on the graphic's page.
pub(super) fn check(p: &PrintParams, drawing: &Drawing, page: &[Mark], labels: &Labels, diags: &mut Vec<Diagnostic>) {
    braille_over_lines(p, drawing, page, labels, diags);
    gaps(p, drawing, diags);
    if p.medium == Medium::Relief {
        let g = p.grid_mm as f64;
        let thin = page.iter().filter(|m| matches!(m.shape, MarkShape::Line { width_mm, .. } if width_mm < g)).count();
        if thin > 0 {
            diags.push(
                Diagnostic::warning(
                    "T0725",
                    format!("{thin} line(s) are narrower than the relief's {g} mm grid and may vanish from the print"),
                )
                .with_help("set min_line_mm of the profile to at least grid_mm"),
            );
        }
    }
}

/// T0722: a label whose braille (and half the minimum gap around it) meets a
/// raised line, symbol or dot of another element.
fn braille_over_lines(p: &PrintParams, drawing: &Drawing, page: &[Mark], labels: &Labels, diags: &mut Vec<Diagnostic>) {
    let raised: Vec<&Mark> = page.iter().filter(|m| m.level == Level::Line).collect();
    let boxes: Vec<Bbox> = raised.iter().map(|m| mark_box(m).unwrap_or((0.0, 0.0, -1.0, -1.0))).collect();
    let index = BoxIndex::new(&boxes);
    // The label boxes were grown by the minimum gap; half of it is the rule's margin.
    let shrink = p.min_gap_mm as f64 / 2.0;
    let mut hits: BTreeMap<usize, usize> = BTreeMap::new();
    for (b, &owner) in labels.boxes.iter().zip(&labels.owners) {
        let b = (b.0 + shrink, b.1 + shrink, b.2 - shrink, b.3 - shrink);
        let hit = index.meeting(b).find(|&k| raised[k].element != Some(owner) && reaches(raised[k], b));
        if let Some(k) = hit {
            hits.entry(owner).or_insert(raised[k].element.unwrap_or(usize::MAX));
        }
    }
    for (label, other) in hits {
        let e = &drawing.elements[label];
        let what = drawing.elements.get(other).map_or("another mark".to_string(), |o| format!("#{}", o.name));
        diags.push(
            Diagnostic::warning(
                "T0722",
                format!("the braille of this label runs over {what}: the dots cannot be read on a raised line"),
            )
            .with_element(e.name.clone())
            .on_line(e.line)
            .with_help("move the label off the line, or let the automatic sheet place it (--style auto)"),
        );
    }
}

/// T0723: outlines of two elements closer than the minimum gap without touching.
fn gaps(p: &PrintParams, drawing: &Drawing, diags: &mut Vec<Diagnostic>) {
    let mut lined: Vec<(usize, &PathShape, f64)> = Vec::new();
    for (i, e) in drawing.elements.iter().enumerate().filter(|(_, e)| e.visible) {
        let Shape::Path(path) = &e.shape else { continue };
        let w = e.styles.iter().find_map(|s| match s {
            Style::Vibrate(v) => Some(v.width_mm.max(p.min_line_mm as f64)),
            Style::Brush(_) => Some(p.min_line_mm as f64),
            _ => None,
        });
        if let Some(w) = w.filter(|w| w.is_finite()) {
            lined.push((i, path, w));
        }
    }
    let gap = p.min_gap_mm as f64;
    let boxes: Vec<Bbox> = lined
        .iter()
        .map(|(_, path, _)| crate::geometry::bounds(&path.outline).unwrap_or((0.0, 0.0, -1.0, -1.0)))
        .collect();
    let widest = lined.iter().map(|l| l.2).fold(0.0, f64::max);
    let mut found: Option<(usize, usize, f64)> = None;
    let mut count = 0usize;
    for (a, b) in spatial::near_pairs(&boxes, gap + widest) {
        let (ia, pa, wa) = lined[a];
        let (ib, pb, wb) = lined[b];
        let touch = (wa + wb) / 2.0;
        let d = spatial::min_outline_distance(&pa.outline, &pb.outline, touch + gap, touch);
        let g = d - touch;
        if d > touch + 1e-6 && g < gap {
            count += 1;
            if found.is_none_or(|f| g < f.2) {
                found = Some((ia, ib, g));
            }
        }
    }
    if let Some((ia, ib, g)) = found {
        let (ea, eb) = (&drawing.elements[ia], &drawing.elements[ib]);
        diags.push(
            Diagnostic::warning(
                "T0723",
                format!(
                    "{count} pair(s) of raised lines are closer than the medium's {gap} mm gap without touching \
                     (felt as one); the closest: #{} and #{}, {g:.2} mm apart",
                    ea.name, eb.name
                ),
            )
            .with_element(ea.name.clone())
            .on_line(ea.line)
            .with_help("move them apart, join them, or --fit the drawing to a larger paper"),
        );
    }
}
