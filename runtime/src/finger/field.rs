//! Bilinear sampling of a height field (no allocation, no panic).

use taxel_format::{CellHeights, FIELD_CONTACT, FIELD_EDGE, FieldReader, HeightFieldView};

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
///
/// A tiled field (format 4.6) is decoded a tile at a time: this function
/// decodes the tiles under the point each call. A player that samples one
/// field many times reads it through a [`FieldReader`], which keeps the
/// tiles it decoded, and calls [`sample_with`]: the same values, bit for bit.
pub fn sample(field: &HeightFieldView<'_>, x: f32, y: f32) -> Option<SurfacePoint> {
    sample_with(&mut FieldReader::new(*field), x, y)
}

/// [`sample`] through `reader`, which keeps the tiles of a tiled field
/// between calls (a 4.0 field is read in place).
#[inline]
pub fn sample_with(reader: &mut FieldReader<'_>, x: f32, y: f32) -> Option<SurfacePoint> {
    let (i, j, fx, fy) = locate(reader.view(), x, y)?;
    if !reader.view().is_tiled() {
        return float_point(reader.view(), i, j, fx, fy);
    }
    let c = reader.cell_heights(i, j)?;
    tiled_point(reader.view(), c, fx, fy)
}

/// The surface point at `(fx, fy)` in the cell of a 4.0 field whose
/// top-left node is `(i, j)` (as [`locate`] gives them).
#[inline(always)]
pub(crate) fn float_point(field: &HeightFieldView<'_>, i: u32, j: u32, fx: f32, fy: f32) -> Option<SurfacePoint> {
    // One read of the cell's four nodes, listed in the order of the weights.
    let nodes = field.cell_nodes(j * field.cols + i)?;
    let weights = [(1.0 - fx) * (1.0 - fy), fx * (1.0 - fy), (1.0 - fx) * fy, fx * fy];
    // A node without contact gets weight +0.0 instead of being skipped. The
    // format guarantees that such a node's height and gradient are 0 (a
    // validated view holds nothing else), so its terms are ±0.0, and adding
    // ±0.0 to a sum that starts at +0.0 changes no bit of it: the sums below
    // equal, bit for bit, those of a loop that skips the node, and they need
    // no branch per node. Likewise only a contact node can have a positive
    // masked weight, so the edge test needs no separate contact test.
    let mut wm = [0.0f32; 4];
    let mut edge = false;
    for n in 0..4 {
        let fl = nodes.flags[n];
        wm[n] = if fl & FIELD_CONTACT != 0 { weights[n] } else { 0.0 };
        edge |= fl & FIELD_EDGE != 0 && wm[n] > 0.0;
    }
    // Each sum is added in node order from +0.0, as before, because
    // floating-point addition is not associative and the results must not
    // move by a bit.
    let (hs, xs, ys) = (nodes.heights, nodes.grad_x, nodes.grad_y);
    let w = 0.0 + wm[0] + wm[1] + wm[2] + wm[3];
    let h = 0.0 + wm[0] * hs[0] + wm[1] * hs[1] + wm[2] * hs[2] + wm[3] * hs[3];
    let gx = 0.0 + wm[0] * xs[0] + wm[1] * xs[1] + wm[2] * xs[2] + wm[3] * xs[3];
    let gy = 0.0 + wm[0] * ys[0] + wm[1] * ys[1] + wm[2] * ys[2] + wm[3] * ys[3];
    if w < 0.5 {
        return None;
    }
    Some(SurfacePoint { height: h / w, grad_x: gx / w, grad_y: gy / w, edge })
}

/// The cell under page point `(x, y)`: its top-left node `(i, j)` and the
/// point's place in it, `(fx, fy)` in 0..=1; `None` outside the field or at
/// a non-finite position.
#[inline(always)]
pub(crate) fn locate(field: &HeightFieldView<'_>, x: f32, y: f32) -> Option<(u32, u32, f32, f32)> {
    let cell = field.cell.0;
    let u = (x - field.origin_x.0) / cell;
    let v = (y - field.origin_y.0) / cell;
    let (cols, rows) = (field.cols, field.rows);
    // Also rejects NaN: every comparison with NaN is false.
    if !(u >= 0.0 && v >= 0.0 && u <= (cols - 1) as f32 && v <= (rows - 1) as f32) {
        return None;
    }
    // Here u and v are finite, at least 0 and below 16,384 (the largest
    // side), so truncating them gives their floor.
    let i = (u as u32).min(cols - 2);
    let j = (v as u32).min(rows - 2);
    Some((i, j, u - i as f32, v - j as f32))
}

/// [`sample`] in a tiled field (format 4.6), which stores heights only: the
/// height is the bilinear interpolation of the cell's contact nodes (with
/// all four touching their weights sum to one and are not divided by their
/// sum), and the gradient the slope of that bilinear surface at the point,
/// capped at the field's gradient cap.
///
/// Along x that is the height difference of the top pair of nodes and of the
/// bottom pair, blended by the point's row weights (a pair counts only when
/// both of its nodes have contact; one pair alone is taken as it is); along
/// y likewise with the left and right pairs. Over a plane tile this is the
/// plane's slope; across a step it is the finite difference the 4.0 field
/// stored there (SPEC.md section 9.1).
///
/// `c` is the cell's four nodes (from [`FieldReader::cell_heights`] or,
/// on a player's common path, [`FieldReader::kept_cell`]), `(fx, fy)` the
/// point's place in it.
#[inline(always)]
pub(crate) fn tiled_point(field: &HeightFieldView<'_>, c: CellHeights, fx: f32, fy: f32) -> Option<SurfacePoint> {
    let (inv, cap) = (field.inverse_cell(), field.gradient_cap);
    let weights = [(1.0 - fx) * (1.0 - fy), fx * (1.0 - fy), (1.0 - fx) * fy, fx * fy];
    let hs = c.heights;
    let height = |w: [f32; 4]| 0.0 + w[0] * hs[0] + w[1] * hs[1] + w[2] * hs[2] + w[3] * hs[3];
    if c.flags == [FIELD_CONTACT; 4] {
        // The common cell, every node touching and none at a step: what the
        // general path below gives for it, without its masks and branches.
        let gx = ((hs[1] - hs[0]) * (1.0 - fy) + (hs[3] - hs[2]) * fy) * inv;
        let gy = ((hs[2] - hs[0]) * (1.0 - fx) + (hs[3] - hs[1]) * fx) * inv;
        return Some(capped(cap, height(weights), gx, gy, false));
    }
    let con = c.flags.map(|f| f & FIELD_CONTACT != 0);
    let mut wm = [0.0f32; 4];
    let mut edge = false;
    for n in 0..4 {
        wm[n] = if con[n] { weights[n] } else { 0.0 };
        edge |= c.flags[n] & FIELD_EDGE != 0 && wm[n] > 0.0;
    }
    let w = 0.0 + wm[0] + wm[1] + wm[2] + wm[3];
    if w < 0.5 {
        return None;
    }
    // With every node touching the weights sum to one: the bilinear height
    // as it is (no division on the common path); else renormalised.
    let h = if con == [true; 4] { height(weights) } else { height(wm) / w };
    let slope = |a: bool, da: f32, wa: f32, b: bool, db: f32, wb: f32| match (a, b) {
        (true, true) => da * wa + db * wb,
        (true, false) => da,
        (false, true) => db,
        (false, false) => 0.0,
    };
    let gx = slope(con[0] && con[1], hs[1] - hs[0], 1.0 - fy, con[2] && con[3], hs[3] - hs[2], fy) * inv;
    let gy = slope(con[0] && con[2], hs[2] - hs[0], 1.0 - fx, con[1] && con[3], hs[3] - hs[1], fx) * inv;
    Some(capped(cap, h, gx, gy, edge))
}

/// The surface point with gradient `(gx, gy)` scaled down to the field's
/// cap when it is longer.
#[inline(always)]
fn capped(cap: f32, height: f32, mut gx: f32, mut gy: f32, edge: bool) -> SurfacePoint {
    let m2 = gx * gx + gy * gy;
    if m2 > cap * cap {
        let s = cap / libm::sqrtf(m2);
        gx *= s;
        gy *= s;
    }
    SurfacePoint { height, grad_x: gx, grad_y: gy, edge }
}
