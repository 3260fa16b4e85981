//! Bilinear sampling of a height field (no allocation, no panic).

use taxel_format::{FIELD_CONTACT, FIELD_EDGE, HeightFieldView};

/// The surface under one point of the page.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// Height in mm.
    pub height: f32,
    /// ∂h/∂x.
    pub grad_x: f32,
    /// ∂h/∂y (y down the page).
    pub grad_y: f32,
    /// Whether a step (an edge node) is among the four nodes around the point.
    pub edge: bool,
}

/// Samples `field` at page point `(x, y)` mm by bilinear interpolation of
/// the four surrounding nodes.
///
/// Nodes without contact take no part: the others' weights are renormalised,
/// and the point has contact only when the contact nodes carry at least half
/// of the weight, so the mesh's outline is resolved to half a cell. Outside
/// the field, or at a non-finite position, there is no contact (`None`).
#[inline]
pub fn sample(field: &HeightFieldView<'_>, x: f32, y: f32) -> Option<SurfacePoint> {
    let cell = field.cell.0;
    let u = (x - field.origin_x.0) / cell;
    let v = (y - field.origin_y.0) / cell;
    let (cols, rows) = (field.cols, field.rows);
    // Also rejects NaN: every comparison with NaN is false.
    if !(u >= 0.0 && v >= 0.0 && u <= (cols - 1) as f32 && v <= (rows - 1) as f32) {
        return None;
    }
    let i = (libm::floorf(u) as u32).min(cols - 2);
    let j = (libm::floorf(v) as u32).min(rows - 2);
    let (fx, fy) = (u - i as f32, v - j as f32);
    let k00 = j * cols + i;
    let nodes = [
        (k00, (1.0 - fx) * (1.0 - fy)),
        (k00 + 1, fx * (1.0 - fy)),
        (k00 + cols, (1.0 - fx) * fy),
        (k00 + cols + 1, fx * fy),
    ];
    let (mut w, mut h, mut gx, mut gy) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
    let mut edge = false;
    for (k, wk) in nodes {
        let fl = field.flags_at(k);
        if fl & FIELD_CONTACT == 0 {
            continue;
        }
        edge |= fl & FIELD_EDGE != 0 && wk > 0.0;
        let (a, b) = field.gradient_at(k);
        w += wk;
        h += wk * field.height_at(k);
        gx += wk * a;
        gy += wk * b;
    }
    if w < 0.5 {
        return None;
    }
    Some(SurfacePoint { height: h / w, grad_x: gx / w, grad_y: gy / w, edge })
}
