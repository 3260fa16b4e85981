//! An embosser's sheet: every mark becomes the dots of the embosser's grid
//! it covers. The marks are drawn with tiny-skia into a raster whose pixel
//! centres are the grid points, without anti-aliasing, so a point is raised
//! exactly when its centre is inside a mark (lines at least a grid step
//! wide, so that no line breaks up); a dot smaller than two grid steps is
//! the grid point nearest its centre, which keeps braille, already laid out
//! on the grid, dot for dot. A point takes the highest level over it.

use taxel_format::PrintParams;

use super::raster::{Frame, coverage};
use super::{Level, Mark, MarkShape};
use crate::diagnostic::Diagnostic;
use crate::drawing::Drawing;

/// Diameter the dots of an embosser's sheet are drawn with in its PDF: four
/// fifths of a grid step, at most a braille dot, so that a driver that
/// rasterises the page at the grid's resolution finds each dot in one cell.
pub fn dot_diameter(p: &PrintParams) -> f64 {
    (0.8 * p.grid_mm as f64).min(p.braille_dot_mm as f64)
}

/// `marks` as grid dots; warns (T0725) about marks that cover no grid point.
pub(super) fn snap(
    p: &PrintParams,
    origin: (f64, f64),
    marks: Vec<Mark>,
    drawing: &Drawing,
    diags: &mut Vec<Diagnostic>,
) -> Vec<Mark> {
    let g = p.grid_mm as f64;
    let (cols, rows) = p.grid_size();
    let (cols, rows) = (cols as u32, rows as u32);
    // Pixel (i, j)'s centre is grid point (i, j) at origin + (i + 0.5, j + 0.5) * g.
    let frame = Frame { x0: origin.0, y0: origin.1, px: 1.0 / g, w: cols, h: rows };
    let mut level: Vec<Option<Level>> = vec![None; cols as usize * rows as usize];
    let mut raise = |i: i64, j: i64, l: Level| {
        if i >= 0 && j >= 0 && (i as u32) < cols && (j as u32) < rows {
            let k = j as usize * cols as usize + i as usize;
            level[k] = level[k].max(Some(l));
        }
    };
    let mut drawn = Vec::new();
    let mut lost: Vec<usize> = Vec::new();
    for m in marks {
        match &m.shape {
            MarkShape::Dot { centre, diameter_mm } if *diameter_mm < 2.0 * g => {
                let (i, j) = (((centre.0 - origin.0) / g).floor(), ((centre.1 - origin.1) / g).floor());
                if i.is_finite() && j.is_finite() {
                    raise(i.clamp(-1.0, 1e9) as i64, j.clamp(-1.0, 1e9) as i64, m.level);
                }
            }
            MarkShape::Line { points, closed, width_mm } => {
                if let Some(e) = m.element.filter(|_| covers_nothing(&m.shape, origin, g)) {
                    lost.push(e);
                }
                drawn.push(Mark {
                    shape: MarkShape::Line { points: points.clone(), closed: *closed, width_mm: width_mm.max(g) },
                    ..m
                });
            }
            _ => {
                if let Some(e) = m.element.filter(|_| covers_nothing(&m.shape, origin, g)) {
                    lost.push(e);
                }
                drawn.push(m);
            }
        }
    }
    if let Some(cov) = coverage(&drawn, frame, false) {
        for (li, l) in [Level::Texture, Level::Braille, Level::Line].into_iter().enumerate() {
            for (k, &a) in cov.levels[li].iter().enumerate() {
                if a >= 128 {
                    level[k] = level[k].max(Some(l));
                }
            }
        }
    }
    lost.sort_unstable();
    lost.dedup();
    if let Some(&first) = lost.first() {
        let e = &drawing.elements[first];
        diags.push(
            Diagnostic::warning(
                "T0725",
                format!(
                    "{} element(s) have marks smaller than the {} mm grid that fall between its dots and are lost",
                    lost.len(),
                    p.grid_mm
                ),
            )
            .with_element(e.name.clone())
            .on_line(e.line)
            .with_help("make them larger, or build for swell paper"),
        );
    }
    let d = dot_diameter(p);
    let mut out = Vec::new();
    for j in 0..rows as usize {
        for i in 0..cols as usize {
            if let Some(l) = level[j * cols as usize + i] {
                let centre = (origin.0 + (i as f64 + 0.5) * g, origin.1 + (j as f64 + 0.5) * g);
                out.push(Mark { shape: MarkShape::Dot { centre, diameter_mm: d }, level: l, element: None });
            }
        }
    }
    out
}

/// Whether a mark's box (grown by half its line width) holds no grid point.
fn covers_nothing(shape: &MarkShape, origin: (f64, f64), g: f64) -> bool {
    let (pts, grow): (Vec<(f64, f64)>, f64) = match shape {
        MarkShape::Line { points, width_mm, .. } => (points.clone(), width_mm.max(g) / 2.0),
        MarkShape::Polygon { rings } => (rings.iter().flatten().copied().collect(), 0.0),
        MarkShape::Dot { centre, diameter_mm } => (vec![*centre], diameter_mm / 2.0),
    };
    let Some(b) = pts.iter().fold(None, |b: Option<(f64, f64, f64, f64)>, p| {
        Some(b.map_or((p.0, p.1, p.0, p.1), |b| (b.0.min(p.0), b.1.min(p.1), b.2.max(p.0), b.3.max(p.1))))
    }) else {
        return true;
    };
    let holds = |lo: f64, hi: f64, o: f64| {
        let k = ((lo - grow - o) / g - 0.5).ceil();
        o + (k + 0.5) * g <= hi + grow
    };
    !(holds(b.0, b.2, origin.0) && holds(b.1, b.3, origin.1))
}
