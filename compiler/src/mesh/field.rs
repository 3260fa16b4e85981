//! Sampling the top surface into a height field: resolution, heights,
//! gradients, contact and edge flags.

use taxel_format::{FIELD_CONTACT, FIELD_EDGE, HeightField, MAX_FIELD_NODES, MAX_FIELD_SIDE, Mm};

use super::error::MeshError;
use super::surface::{Face, Surface};

/// Default node spacing ceiling: half a millimetre, finer than a touch
/// screen reports a fingertip's position and than the ring can render.
pub const FINGER_CELL_MM: f64 = 0.5;
/// Most nodes along the longer side that the default resolution uses, so a
/// 10 m mesh stays at a megabyte-sized field; an explicit resolution may go
/// up to the format's limits.
pub const DEFAULT_MAX_SIDE: u32 = 1024;
/// Fewest nodes along the longer side that the default resolution uses, so a
/// micrometre-sized mesh still has a shape.
pub const DEFAULT_MIN_SIDE: u32 = 17;
/// Smallest gradient cap: a step is felt at least as strongly as a 45° slope.
pub const MIN_GRADIENT_CAP: f64 = 1.0;

/// The grid of a field: origin, spacing, size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    /// Page x of node (0, 0), as stored (f32).
    pub ox: f32,
    /// Page y of node (0, 0), as stored (f32).
    pub oy: f32,
    /// Node spacing, as stored (f32).
    pub cell: f32,
    /// Nodes per row.
    pub cols: u32,
    /// Rows.
    pub rows: u32,
}

impl Grid {
    /// Page position of node `(i, j)`, computed from the stored values as the player will.
    pub fn node(&self, i: u32, j: u32) -> (f64, f64) {
        (self.ox as f64 + i as f64 * self.cell as f64, self.oy as f64 + j as f64 * self.cell as f64)
    }
}

/// The default node spacing for a surface (see docs/finger.md).
pub fn default_cell(s: &Surface) -> f64 {
    let extent = (s.bbox[2] - s.bbox[0]).max(s.bbox[3] - s.bbox[1]);
    let target = if s.median_edge > 0.0 { (s.median_edge / 2.0).min(FINGER_CELL_MM) } else { FINGER_CELL_MM };
    target.max(extent / (DEFAULT_MAX_SIDE - 1) as f64).min(extent / (DEFAULT_MIN_SIDE - 1) as f64)
}

/// The grid covering the surface's footprint at `cell` mm, or an error when
/// it would exceed the format's limits.
pub fn grid(s: &Surface, cell: f64) -> Result<Grid, MeshError> {
    if !(cell.is_finite() && cell > 0.0) {
        return Err(MeshError::BadResolution(1.0 / cell));
    }
    let ox = s.bbox[0] as f32;
    let oy = s.bbox[1] as f32;
    let c = cell as f32;
    // Enough nodes that the last one reaches the far side of the footprint,
    // give or take a thousandth of a cell: glTF's f32 metres rarely convert
    // to round millimetres, and a whole extra row of nodes beyond the mesh
    // for 1e-7 mm would only hold no-contact nodes.
    let side = |far: f64, o: f32| ((far - o as f64) / c as f64 - 1e-3).ceil().max(1.0) + 1.0;
    let cols = side(s.bbox[2], ox);
    let rows = side(s.bbox[3], oy);
    let (w, h) = (s.bbox[2] - s.bbox[0], s.bbox[3] - s.bbox[1]);
    let fits = c >= 1e-9
        && cols <= MAX_FIELD_SIDE as f64
        && rows <= MAX_FIELD_SIDE as f64
        && cols * rows <= MAX_FIELD_NODES as f64;
    if !fits {
        let per_side = (MAX_FIELD_SIDE - 1) as f64 / w.max(h).max(f64::MIN_POSITIVE);
        let per_area = ((MAX_FIELD_NODES as f64).sqrt() - 1.0) / (w * h).sqrt().max(f64::MIN_POSITIVE);
        return Err(MeshError::FieldTooLarge {
            cols: cols.min(u64::MAX as f64) as u64,
            rows: rows.min(u64::MAX as f64) as u64,
            per_mm: 1.0 / cell,
            max_per_mm: per_side.min(per_area) * 0.999,
        });
    }
    Ok(Grid { ox, oy, cell: c, cols: cols as u32, rows: rows as u32 })
}

/// Samples `s` on `g`: exact top-surface heights at the nodes, facet
/// gradients, finite differences across steps, and the gradient cap.
pub fn sample(s: &Surface, g: &Grid, source: Option<u32>) -> HeightField {
    let n = g.cols as usize * g.rows as usize;
    let mut tops = Tops::new(n);
    for (fi, f) in s.faces.iter().enumerate() {
        tops.add_face(s, g, fi, f);
    }
    let Tops { best, mut grad, ties, top } = tops;
    for (g2, &t) in grad.iter_mut().zip(&ties) {
        if t > 1 {
            g2[0] /= t as f64;
            g2[1] /= t as f64;
        }
    }
    let flags: Vec<u8> = best.iter().map(|h| if h.is_finite() { FIELD_CONTACT } else { 0 }).collect();

    // Across a step the finite difference between the two nodes is the
    // slope the bilinear field actually has there; it replaces the facet slope.
    let mut marks = StepMarks { best: &best, cell: g.cell as f64, over: vec![[f64::NAN; 2]; n], flags };
    marks.cross_steps(s, g);
    if s.raster {
        raster_steps(s, g, &best, &top, &mut |k1, k2, axis| marks.mark(k1, k2, axis));
    }
    let StepMarks { over, flags, .. } = marks;
    for (g2, o) in grad.iter_mut().zip(&over) {
        for axis in 0..2 {
            if !o[axis].is_nan() {
                g2[axis] = o[axis];
            }
        }
    }
    capped(s, g, source, &best, &grad, flags)
}

/// The highest top over each node of a grid, as the faces are added.
struct Tops {
    /// The height, `-inf` where no face covers the node.
    best: Vec<f64>,
    /// The sum of the facet gradients of the faces tied for the top.
    grad: Vec<[f64; 2]>,
    /// How many faces are tied for the top.
    ties: Vec<u16>,
    /// The face on top at each node (for the steps of a raster surface).
    top: Vec<u32>,
}

impl Tops {
    /// No face over any of `n` nodes.
    fn new(n: usize) -> Tops {
        Tops {
            best: vec![f64::NEG_INFINITY; n],
            grad: vec![[0.0f64; 2]; n],
            ties: vec![0u16; n],
            top: vec![u32::MAX; n],
        }
    }

    /// Offers the top of face `fi` (`f` of `s`) to every node of `g` it covers.
    fn add_face(&mut self, s: &Surface, g: &Grid, fi: usize, f: &Face) {
        let cell = g.cell as f64;
        let Some(sides) = Sides::new(f.corners, 1e-3 * cell) else { return };
        let [a, b, c] = f.corners;
        let (x0, x1) = (a[0].min(b[0]).min(c[0]), a[0].max(b[0]).max(c[0]));
        let (y0, y1) = (a[1].min(b[1]).min(c[1]), a[1].max(b[1]).max(c[1]));
        let Some((i0, i1)) = span(x0, x1, g.ox as f64, cell, g.cols) else { return };
        let Some((j0, j1)) = span(y0, y1, g.oy as f64, cell, g.rows) else { return };
        for j in j0..=j1 {
            let y = g.node(0, j).1;
            let (lo, hi) = sides.row(y, x0 - cell, x1 + cell);
            let Some((ia, ib)) = span(lo, hi, g.ox as f64, cell, g.cols) else { continue };
            for i in ia.max(i0)..=ib.min(i1) {
                let (x, y) = g.node(i, j);
                if !sides.covers(x, y) {
                    continue;
                }
                let Some(top) = s.top(f, x, y) else { continue };
                self.offer(j as usize * g.cols as usize + i as usize, top, fi, s.step_tol);
            }
        }
    }

    /// Offers node `k` the top `(h, gx, gy)` of face `fi`: it wins when it
    /// is higher by more than the rounding tolerance `tol`, and ties when
    /// it is as high within it.
    fn offer(&mut self, k: usize, (h, gx, gy): (f64, f64, f64), fi: usize, tol: f64) {
        let (best, grad, ties, top) = (&mut self.best, &mut self.grad, &mut self.ties, &mut self.top);
        if h > best[k] + tol {
            best[k] = h;
            grad[k] = [gx, gy];
            ties[k] = 1;
            top[k] = fi as u32;
        } else if h >= best[k] - tol && ties[k] < u16::MAX {
            // Same height from another face (the node is on an edge or
            // corner): average the slopes so a ridge on a node is level,
            // and keep the higher of the roundings, so the height does
            // not depend on the order of the faces.
            best[k] = best[k].max(h);
            grad[k][0] += gx;
            grad[k][1] += gy;
            ties[k] += 1;
        }
    }
}

/// The sides of a face, for the tests of which nodes it covers.
struct Sides {
    /// Each side from one corner to the next, with its length.
    sides: [([f64; 2], [f64; 2], f64); 3],
    /// Twice the face's signed area.
    area2: f64,
    /// How far outside a side (mm) a node still counts as inside.
    slack: f64,
}

impl Sides {
    /// The sides of the triangle `corners`, or `None` when it has no area.
    fn new(corners: [[f64; 2]; 3], slack: f64) -> Option<Sides> {
        let [a, b, c] = corners;
        let area2 = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        if area2 == 0.0 {
            return None;
        }
        Some(Sides { sides: [(a, b, dist(a, b)), (b, c, dist(b, c)), (c, a, dist(c, a))], area2, slack })
    }

    /// The x interval, within `lo..hi`, of the nodes of the row at `y`
    /// inside the triangle (widened by the slack): each side's test is
    /// linear in x, so the row meets the triangle in one interval, and a
    /// long thin triangle costs the nodes it covers, not its bounding box.
    fn row(&self, y: f64, mut lo: f64, mut hi: f64) -> (f64, f64) {
        let sign = self.area2.signum();
        for (p, q, len) in self.sides {
            // Inside: sign * ((q - p) x (node - p)) >= -slack * len, that is k x >= r.
            let k = -sign * (q[1] - p[1]);
            let r = -self.slack * len - sign * ((q[0] - p[0]) * (y - p[1]) + p[0] * (q[1] - p[1]));
            if k > 0.0 {
                lo = lo.max(r / k);
            } else if k < 0.0 {
                hi = hi.min(r / k);
            } else if r > 0.0 {
                hi = f64::NEG_INFINITY;
            }
        }
        (lo, hi)
    }

    /// Whether node `(x, y)` is inside, or within the slack of the face: so
    /// a node on a shared edge is never lost to rounding between two faces,
    /// and a node on the outline is not lost to the f32 metres of glTF.
    fn covers(&self, x: f64, y: f64) -> bool {
        let out = |p: [f64; 2], q: [f64; 2], len: f64| {
            ((q[0] - p[0]) * (y - p[1]) - (x - p[0]) * (q[1] - p[1])) * self.area2.signum() < -self.slack * len
        };
        let [(a, b, lab), (_, c, lbc), (_, _, lca)] = self.sides;
        !(out(a, b, lab) || out(b, c, lbc) || out(c, a, lca))
    }
}

/// The node pairs that straddle a step, with the finite difference across
/// each, as they are marked.
struct StepMarks<'a> {
    /// The heights at the nodes.
    best: &'a [f64],
    /// The node spacing, mm.
    cell: f64,
    /// Per node and axis, the steepest finite difference across a step
    /// (`NaN` where none crosses).
    over: Vec<[f64; 2]>,
    /// Per node, its contact flag, and the edge flag once marked.
    flags: Vec<u8>,
}

impl StepMarks<'_> {
    /// Marks the neighbouring nodes `k1` and `k2` along `axis` as on either
    /// side of a step, when both are in contact.
    fn mark(&mut self, k1: usize, k2: usize, axis: usize) {
        let (over, flags) = (&mut self.over, &mut self.flags);
        if flags[k1] & FIELD_CONTACT == 0 || flags[k2] & FIELD_CONTACT == 0 {
            return;
        }
        let d = (self.best[k2] - self.best[k1]) / self.cell;
        for k in [k1, k2] {
            flags[k] |= FIELD_EDGE;
            if over[k][axis].is_nan() || d.abs() > over[k][axis].abs() {
                over[k][axis] = d;
            }
        }
    }

    /// Marks the node pairs of `g` that each of the surface's steps passes
    /// between, along each axis.
    fn cross_steps(&mut self, s: &Surface, g: &Grid) {
        let cell = self.cell;
        let idx = |i: u32, j: u32| j as usize * g.cols as usize + i as usize;
        for st in &s.steps {
            // Rows the step crosses: the horizontal node pair it passes between.
            for (along, across, axis) in [(0usize, 1usize, 0usize), (1, 0, 1)] {
                let (o_across, o_along) =
                    if axis == 0 { (g.oy as f64, g.ox as f64) } else { (g.ox as f64, g.oy as f64) };
                let (n_across, n_along) = if axis == 0 { (g.rows, g.cols) } else { (g.cols, g.rows) };
                let (c0, c1) = (st.a[across].min(st.b[across]), st.a[across].max(st.b[across]));
                let Some((r0, r1)) = span(c0, c1, o_across, cell, n_across) else { continue };
                for r in r0..=r1 {
                    let line = o_across + r as f64 * cell;
                    let dc = st.b[across] - st.a[across];
                    if dc == 0.0 {
                        // Parallel to these node lines: the other axis sees it.
                        continue;
                    }
                    let t = ((line - st.a[across]) / dc).clamp(0.0, 1.0);
                    let pos = st.a[along] + t * (st.b[along] - st.a[along]);
                    let u = (pos - o_along) / cell;
                    if !(u > -1.0 && u < n_along as f64) {
                        continue;
                    }
                    let lo = u.floor();
                    // On a node: both neighbouring pairs straddle the step.
                    let pairs: &[(f64, f64)] =
                        if (u - lo) < 1e-9 { &[(lo - 1.0, lo), (lo, lo + 1.0)] } else { &[(lo, lo + 1.0)] };
                    for &(p, q) in pairs {
                        if p < 0.0 || q > (n_along - 1) as f64 {
                            continue;
                        }
                        let (p, q) = (p as u32, q as u32);
                        let (k1, k2) = if axis == 0 { (idx(p, r), idx(q, r)) } else { (idx(r, p), idx(r, q)) };
                        self.mark(k1, k2, axis);
                    }
                }
            }
        }
    }
}

/// The field of `g` from the nodes' heights `best`, gradients `grad` and
/// `flags`: gradients capped at the steepest slope of the surface proper
/// and at least 45° (a capped node is flagged an edge), nodes out of
/// contact zero.
fn capped(
    s: &Surface,
    g: &Grid,
    source: Option<u32>,
    best: &[f64],
    grad: &[[f64; 2]],
    mut flags: Vec<u8>,
) -> HeightField {
    let n = best.len();
    let cap = s.max_surface_slope.max(MIN_GRADIENT_CAP);
    let cap32 = cap as f32;
    let mut heights = Vec::with_capacity(n);
    let (mut gxs, mut gys) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for k in 0..n {
        if flags[k] & FIELD_CONTACT == 0 {
            heights.push(0.0);
            gxs.push(0.0);
            gys.push(0.0);
            continue;
        }
        let [mut gx, mut gy] = grad[k];
        let m = gx.hypot(gy);
        if m > cap {
            gx *= cap / m;
            gy *= cap / m;
            flags[k] |= FIELD_EDGE;
        }
        heights.push(best[k] as f32);
        gxs.push((gx as f32).clamp(-cap32, cap32));
        gys.push((gy as f32).clamp(-cap32, cap32));
    }
    HeightField {
        source,
        cols: g.cols,
        rows: g.rows,
        origin_x: Mm(g.ox),
        origin_y: Mm(g.oy),
        cell: Mm(g.cell),
        gradient_cap: cap32,
        heights,
        grad_x: gxs,
        grad_y: gys,
        flags,
        encoding: taxel_format::HeightEncoding::Float,
    }
}

/// The steps of a raster surface (`Surface::raster`), whose faces are the
/// mesh triangles themselves with no arrangement to find steps on: a pair of
/// neighbouring contact nodes on different top faces whose heights differ by
/// more than the steepest slope of the surface proper allows over one cell.
/// A continuous surface cannot rise that fast, so nothing is flagged that is
/// not a step; a step lower than that slope over a cell is felt as a slope.
fn raster_steps(s: &Surface, g: &Grid, best: &[f64], top: &[u32], mark: &mut dyn FnMut(usize, usize, usize)) {
    let rise = s.max_surface_slope.max(MIN_GRADIENT_CAP) * g.cell as f64 + s.step_tol;
    let (cols, rows) = (g.cols as usize, g.rows as usize);
    for j in 0..rows {
        for i in 0..cols {
            let k = j * cols + i;
            for (next, axis) in
                [(i + 1 < cols).then_some(k + 1), (j + 1 < rows).then_some(k + cols)].into_iter().zip(0..)
            {
                let Some(k2) = next else { continue };
                let both = best[k].is_finite() && best[k2].is_finite();
                if both && top[k] != top[k2] && (best[k2] - best[k]).abs() > rise {
                    mark(k, k2, axis);
                }
            }
        }
    }
}

fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
    (q[0] - p[0]).hypot(q[1] - p[1])
}

/// Node indices `i` with `lo <= origin + i * cell <= hi` (a thousandth of a
/// cell inclusive), clamped to `0..count`.
fn span(lo: f64, hi: f64, origin: f64, cell: f64, count: u32) -> Option<(u32, u32)> {
    let a = ((lo - origin) / cell - 1e-3).ceil().max(0.0);
    let b = ((hi - origin) / cell + 1e-3).floor().min(count as f64 - 1.0);
    (a <= b && b >= 0.0).then_some((a as u32, b as u32))
}
