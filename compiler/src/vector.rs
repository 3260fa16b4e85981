//! Vector layers, a measured prototype of technique (b) of issue 16: one
//! style's exact geometry, simplified to the device's precision, with a
//! per-cell index of the segments that can decide the amplitude in each
//! cell (`docs/layers.md` has the figures against the distance fields of
//! [`crate::distance`], the decision and a draft of the byte layout).
//!
//! Nothing here is in the bundle format: the builder takes the same
//! [`LayerGeometry`] as [`build_field`](crate::distance::build_field), and
//! [`VectorLayer::coverage4`] is the evaluation a player would run, written
//! as a runtime kernel (no allocation, no panic, bounded loops, `f32`
//! distances and an exact i64 side test).
//!
//! **The layer.** A layer is
//! - a *region*: closed contours in integer coordinates (a quantum `q` of
//!   1/256 mm, or coarser for pages over 255 mm), the union of the style's
//!   fills under their fill rules, intersected with its clip regions and the
//!   page (for a vibration: the clips and the page only). The union is made by
//!   `i_overlay`, so the contours are simple and do not cross one another:
//!   a point is inside where it is inside an odd number of them, and the
//!   distance to the region's outline is the distance to the nearest
//!   contour segment (no inner edges of overlapping or touching fills);
//! - *band groups*: centre lines with a half width `w / 2`. A vibration's
//!   band is felt where `w/2 − d > 0`; a grating's bands (the vibrating
//!   outlines that cross it) are cut out where `d − w/2 < 0`.
//!
//! The signed distance is `s = min(±D, max_g(w_g/2 − d_g))` for a vibration
//! and `s = min(±D, min_g(d_g − w_g/2))` for a grating, `D` the distance to
//! the nearest region segment, `d_g` to the nearest centre line of group
//! `g`. The amplitude is the edge profile `clamp(½ + s / ramp, 0, 1)` with
//! `ramp` the layer's `soft` width, or one quantum for a hard edge.
//!
//! **The cells.** A square grid of cells of side `c` (whole quanta) over
//! the felt part of the page; each cell lists, in increasing order, the ids
//! of the segments that lie within `m` of the cell (region segments:
//! `m = ramp/2 + 2q`; band segments of group `g`: `m = w_g/2 + ramp/2 + 2q`),
//! and one bit: the region's state at the cell's centre `c'`, displaced by
//! the infinitesimal `(ε, ε²)` so that it lies on no segment. Why this is
//! exact (up to the simplification):
//! - *Distance*: a point `p` of the cell whose nearest segment is within `m`
//!   of `p` finds it listed; otherwise every listed segment is farther than
//!   `m`, the profile is saturated, and so is the computed one.
//! - *Side*: every region segment that crosses the segment `c' → p` meets
//!   the cell, so it is listed; `p` is inside iff the centre's bit differs
//!   from the parity of those crossings. The crossing test ([`crosses`]) is
//!   exact (integer coordinates in fixed point, i64 products) and decides
//!   the degenerate cases by the displacement of `c'` (simulation of
//!   simplicity): a vertex on the line `c' p` counts on one side, whichever
//!   edge it belongs to, so a closed contour is counted once. The builder
//!   finds the centre's bit with the same test, from `c'` to a point left of
//!   every contour.
//!
//! Degenerate input is the overlay's concern (collinear points, touching
//! contours, zero-area slivers and self-intersections come out as simple
//! contours); a cell may list many segments (a dense coastline): the loop is
//! bounded by the stored count, and the figures report the distribution.

use i_overlay::core::fill_rule::FillRule as OvFill;
use i_overlay::core::overlay::{IntOverlayOptions, Overlay, ShapeType};
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::i_float::int::point::IntPoint;

use crate::distance::LayerGeometry;
use crate::geometry::{FillRule, Polyline};

/// Fixed-point sub-units per integer unit for the exact side test.
pub const FIXED: i64 = 256;

/// `(b − a) × (c − a)`, exact in i64 for coordinates below 2^24.
#[inline(always)]
fn orient(a: (i64, i64), b: (i64, i64), c: (i64, i64)) -> i64 {
    (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
}

/// Whether the segment from `c'` (the cell centre `c` moved by the
/// infinitesimal `(ε, ε²)`) to `p` crosses the segment `ab`, decided
/// exactly: a vertex on the line `c'p` counts on the side the displacement
/// gives it, so each vertex has one side and crossings of a closed contour
/// count its boundary once. `p` on `ab` counts as on its left.
#[inline(always)]
pub fn crosses(a: (i64, i64), b: (i64, i64), c: (i64, i64), p: (i64, i64)) -> bool {
    // Side of x relative to the directed line c' → p: orient(c, p, x) + (x − p) × (ε, ε²).
    let side = |x: (i64, i64)| {
        let o = orient(c, p, x);
        if o != 0 {
            o > 0
        } else if x.1 != p.1 {
            x.1 < p.1
        } else {
            x.0 > p.0
        }
    };
    if side(a) == side(b) {
        return false;
    }
    // Side of c' relative to a → b: orient(a, b, c) + (b − a) × (ε, ε²).
    let o = orient(a, b, c);
    let c_left = if o != 0 {
        o > 0
    } else if b.1 != a.1 {
        b.1 < a.1
    } else {
        b.0 > a.0
    };
    c_left != (orient(a, b, p) >= 0)
}

/// A stored point in fixed point.
#[inline(always)]
fn fixed(p: &[u16; 2]) -> (i64, i64) {
    (p[0] as i64 * FIXED, p[1] as i64 * FIXED)
}

/// At most this many band groups (distinct band widths) in one layer.
pub const MAX_GROUPS: usize = 8;

/// How to build a vector layer.
#[derive(Debug, Clone, Copy)]
pub struct VectorParams {
    /// Largest distance a simplified outline moves from the given one, mm
    /// (before quantisation, which adds at most `q / √2`).
    pub tolerance_mm: f64,
    /// Cell side, mm.
    pub cell_mm: f64,
    /// Edge profile ramp, mm (0: hard, one quantum).
    pub soft_mm: f64,
    /// The page (surface) rectangle `(x0, y0, x1, y1)` in mm.
    pub page: (f64, f64, f64, f64),
}

impl VectorParams {
    /// The prototype's defaults: 0.004 mm simplification, 2 mm cells.
    pub fn new(soft_mm: f64, page: (f64, f64, f64, f64)) -> Self {
        VectorParams { tolerance_mm: 0.004, cell_mm: 2.0, soft_mm, page }
    }
}

/// What kind of layer: how bands combine with the region.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Bands are felt (within the region: clips and page).
    Vibration,
    /// The region is felt, minus the bands.
    Grating,
}

/// A built vector layer, in the shape of its proposed encoding.
#[derive(Debug, Clone)]
pub struct VectorLayer {
    /// Band combination.
    pub mode: Mode,
    /// Page position of integer point (0, 0), mm.
    pub origin: (f32, f32),
    /// mm per integer unit (a power of two).
    pub quantum: f32,
    /// Cell side in integer units.
    pub cell: f32,
    /// The grid's corner in integer units.
    pub grid: (f32, f32),
    /// Cells across and down.
    pub cols: u32,
    /// Rows of cells.
    pub rows: u32,
    /// Edge profile ramp in integer units.
    pub ramp: f32,
    /// Points, polylines laid end to end: segment `i` joins points `i` and `i + 1`.
    pub points: Vec<[u16; 2]>,
    /// Segments `0..region_end` are region segments.
    pub region_end: u32,
    /// Band groups: segments `previous end..end` with this half width (integer units).
    pub groups: Vec<(u32, f32)>,
    /// Per cell, the first of its references (`cols * rows + 1` entries).
    pub starts: Vec<u32>,
    /// Segment ids, increasing within a cell.
    pub refs: Vec<u32>,
    /// Region state per cell (bit `k % 8` of byte `k / 8`), for cells without region segments.
    pub inside: Vec<u8>,
}

/// Why a layer could not be built.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum VectorError {
    /// More distinct band widths than [`MAX_GROUPS`].
    TooManyGroups,
    /// More than 65,536 points, or a page too large for 16-bit coordinates.
    TooLarge,
    /// Non-finite parameters.
    BadParams,
}

type P = (f64, f64);

/// Integer coordinates are kept within ±2^28.
const LIMIT: f64 = (1u32 << 28) as f64;

/// Ramer–Douglas–Peucker on a walked path (closed paths repeat their first point).
fn simplify(pts: &[P], tol: f64) -> Vec<P> {
    if pts.len() < 3 {
        return pts.to_vec();
    }
    let mut keep = vec![false; pts.len()];
    keep[0] = true;
    keep[pts.len() - 1] = true;
    let mut stack = vec![(0usize, pts.len() - 1)];
    while let Some((i, j)) = stack.pop() {
        if j <= i + 1 {
            continue;
        }
        let (a, b) = (pts[i], pts[j]);
        let (mut far, mut at) = (-1.0, i);
        for (k, &p) in pts.iter().enumerate().take(j).skip(i + 1) {
            let d = crate::geometry::distance_to_segment(p, a, b);
            if d > far {
                far = d;
                at = k;
            }
        }
        if far > tol {
            keep[at] = true;
            stack.push((i, at));
            stack.push((at, j));
        }
    }
    pts.iter().zip(keep).filter(|(_, k)| *k).map(|(p, _)| *p).collect()
}

/// Integer frame: page mm to integer units.
#[derive(Clone, Copy)]
pub(crate) struct Frame {
    pub(crate) ox: f64,
    pub(crate) oy: f64,
    pub(crate) q: f64,
}

impl Frame {
    fn to_int(self, p: P) -> IntPoint {
        // Far-off coordinates are clamped (the overlay's arithmetic stays in range).
        let c = |v: f64| v.round().clamp(-LIMIT, LIMIT) as i32;
        IntPoint::new(c((p.0 - self.ox) / self.q), c((p.1 - self.oy) / self.q))
    }
}

pub(crate) fn ov_rule(r: FillRule) -> OvFill {
    match r {
        FillRule::NonZero => OvFill::NonZero,
        FillRule::EvenOdd => OvFill::EvenOdd,
    }
}

/// One shape's closed contours, simplified and quantised.
pub(crate) fn contours(pls: &[Polyline], f: Frame, tol: f64) -> Vec<Vec<IntPoint>> {
    pls.iter()
        .filter(|pl| pl.points.len() >= 3)
        .map(|pl| {
            let mut w = pl.points.clone();
            w.push(pl.points[0]);
            let mut s = simplify(&w, tol);
            s.pop();
            let mut c: Vec<IntPoint> = s.into_iter().map(|p| f.to_int(p)).collect();
            c.dedup();
            c
        })
        .filter(|c| c.len() >= 3)
        .collect()
}

fn opts() -> IntOverlayOptions<u64> {
    IntOverlayOptions::default()
}

/// The shapes of one set of contours under a fill rule, as simple contours.
pub(crate) fn shapes_of(cs: &[Vec<IntPoint>], rule: OvFill) -> Vec<Vec<Vec<IntPoint>>> {
    if cs.is_empty() {
        return Vec::new();
    }
    let mut o = Overlay::new_custom(cs.len(), opts(), Default::default());
    o.add_source(cs, ShapeType::Subject);
    o.overlay(OverlayRule::Subject, rule)
}

fn intersect(a: &[Vec<Vec<IntPoint>>], b: &[Vec<Vec<IntPoint>>]) -> Vec<Vec<Vec<IntPoint>>> {
    if a.is_empty() || b.is_empty() {
        return Vec::new();
    }
    let mut o = Overlay::new_custom(16, opts(), Default::default());
    o.add_source(a, ShapeType::Subject);
    o.add_source(b, ShapeType::Clip);
    o.overlay(OverlayRule::Intersect, OvFill::NonZero)
}

/// `a` minus `b`.
fn subtract(a: &[Vec<Vec<IntPoint>>], b: &[Vec<Vec<IntPoint>>]) -> Vec<Vec<Vec<IntPoint>>> {
    if a.is_empty() || b.is_empty() {
        return a.to_vec();
    }
    let mut o = Overlay::new_custom(16, opts(), Default::default());
    o.add_source(a, ShapeType::Subject);
    o.add_source(b, ShapeType::Clip);
    o.overlay(OverlayRule::Difference, OvFill::NonZero)
}

/// The pieces of a path inside a rectangle (Liang–Barsky on each segment).
fn clip_path(path: &[P], r: (f64, f64, f64, f64)) -> Vec<Vec<P>> {
    let inside = |p: P| p.0 >= r.0 && p.0 <= r.2 && p.1 >= r.1 && p.1 <= r.3;
    if path.len() == 1 {
        return if inside(path[0]) { vec![path.to_vec()] } else { Vec::new() };
    }
    let mut out: Vec<Vec<P>> = Vec::new();
    let mut cur: Vec<P> = Vec::new();
    for w in path.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        let mut keep = true;
        for (pp, qq) in [(-dx, a.0 - r.0), (dx, r.2 - a.0), (-dy, a.1 - r.1), (dy, r.3 - a.1)] {
            if pp == 0.0 {
                if qq < 0.0 {
                    keep = false;
                }
            } else {
                let t = qq / pp;
                if pp < 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
            }
        }
        if !keep || t0 > t1 {
            if !cur.is_empty() {
                out.push(std::mem::take(&mut cur));
            }
            continue;
        }
        let (s, e) = ((a.0 + t0 * dx, a.1 + t0 * dy), (a.0 + t1 * dx, a.1 + t1 * dy));
        if cur.last() != Some(&s) {
            if !cur.is_empty() {
                out.push(std::mem::take(&mut cur));
            }
            cur.push(s);
        }
        cur.push(e);
        if t1 < 1.0 {
            out.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// Distance between a segment and an axis-aligned rectangle (0 if they meet).
fn seg_rect_distance(a: P, b: P, r: (f64, f64, f64, f64)) -> f64 {
    let inside = |p: P| p.0 >= r.0 && p.0 <= r.2 && p.1 >= r.1 && p.1 <= r.3;
    if inside(a) || inside(b) {
        return 0.0;
    }
    let corners = [(r.0, r.1), (r.2, r.1), (r.2, r.3), (r.0, r.3)];
    // Crossing a side: the segment meets the rectangle.
    let cross = |p: P, q: P, s: P, t: P| {
        let o = |a: P, b: P, c: P| (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
        let (d1, d2) = (o(s, t, p), o(s, t, q));
        let (d3, d4) = (o(p, q, s), o(p, q, t));
        (d1 > 0.0) != (d2 > 0.0) && (d3 > 0.0) != (d4 > 0.0)
    };
    let mut d = f64::INFINITY;
    for k in 0..4 {
        let (s, t) = (corners[k], corners[(k + 1) % 4]);
        if cross(a, b, s, t) {
            return 0.0;
        }
        d = d.min(crate::geometry::distance_to_segment(s, a, b));
    }
    let out = |p: P| {
        let dx = (r.0 - p.0).max(p.0 - r.2).max(0.0);
        let dy = (r.1 - p.1).max(p.1 - r.3).max(0.0);
        dx.hypot(dy)
    };
    d.min(out(a)).min(out(b))
}

/// Builds the vector layer of one style; `Ok(None)` when nothing is felt.
pub fn build_vector(g: &LayerGeometry<'_>, p: VectorParams) -> Result<Option<VectorLayer>, VectorError> {
    let soft = p.soft_mm.max(0.0);
    let finite = p.tolerance_mm.is_finite() && p.cell_mm.is_finite() && soft.is_finite();
    if !(finite && p.tolerance_mm >= 0.0 && p.cell_mm > 0.0) {
        return Err(VectorError::BadParams);
    }
    let pg = p.page;
    let mode = if g.fills.is_empty() { Mode::Vibration } else { Mode::Grating };
    // The quantum: 1/256 mm, doubled until the page (plus a margin) fits 16 bits.
    let extent = (pg.2 - pg.0).max(pg.3 - pg.1) + 8.0 + soft;
    let mut q = 1.0 / 256.0;
    while extent / q > 65_000.0 {
        q *= 2.0;
        if q > 1.0 {
            return Err(VectorError::TooLarge);
        }
    }
    let ramp = if soft > 0.0 { soft } else { q };
    let reach = ramp / 2.0 + 2.0 * q;
    // The integer origin sits a margin outside the page, on a multiple of q.
    let margin = 4.0 + soft;
    let f = Frame { ox: ((pg.0 - margin) / q).floor() * q, oy: ((pg.1 - margin) / q).floor() * q, q };
    let tol = p.tolerance_mm;

    // The region.
    let page_corners =
        vec![f.to_int((pg.0, pg.1)), f.to_int((pg.2, pg.1)), f.to_int((pg.2, pg.3)), f.to_int((pg.0, pg.3))];
    let page_shape = shapes_of(&[page_corners], OvFill::NonZero);
    let mut region = if mode == Mode::Grating {
        let mut all: Vec<Vec<Vec<IntPoint>>> = Vec::new();
        for (pls, rule) in &g.fills {
            all.extend(shapes_of(&contours(pls, f, tol), ov_rule(*rule)));
        }
        let flat: Vec<Vec<IntPoint>> = all.into_iter().flatten().collect();
        shapes_of(&flat, OvFill::NonZero)
    } else {
        page_shape.clone()
    };
    for (pls, rule) in &g.clips {
        region = intersect(&region, &shapes_of(&contours(pls, f, tol), ov_rule(*rule)));
    }
    for (pls, rule) in &g.occluders {
        region = subtract(&region, &shapes_of(&contours(pls, f, tol), ov_rule(*rule)));
    }
    if mode == Mode::Grating {
        region = intersect(&region, &page_shape);
    }
    // Band groups: (half width, walked polylines).
    let mut groups: Vec<(f64, Vec<Vec<P>>)> = Vec::new();
    let mut add_band = |lines: &[Polyline], w: f64| -> Result<(), VectorError> {
        let k = match groups.iter().position(|(hw, _)| *hw == w / 2.0) {
            Some(k) => k,
            None => {
                if groups.len() == MAX_GROUPS {
                    return Err(VectorError::TooManyGroups);
                }
                groups.push((w / 2.0, Vec::new()));
                groups.len() - 1
            }
        };
        // Only the parts of a centre line that can reach the page matter.
        // Grid points lie up to `reach` beyond the page and see bands up to `w/2 + reach` away.
        let m = w / 2.0 + 2.0 * reach + 2.0 * q;
        let grown = (pg.0 - m, pg.1 - m, pg.2 + m, pg.3 + m);
        for pl in lines {
            for piece in clip_path(&pl.walked(), grown) {
                groups[k].1.push(simplify(&piece, tol));
            }
        }
        Ok(())
    };
    if let Some((lines, w)) = &g.band {
        for pls in lines {
            add_band(pls, *w)?;
        }
    }
    for (lines, w) in &g.cuts {
        add_band(lines, *w)?;
    }
    groups.sort_by(|a, b| a.0.total_cmp(&b.0));
    if mode == Mode::Vibration && groups.is_empty() {
        return Ok(None);
    }
    if region.is_empty() {
        return Ok(None);
    }

    // Points: region contours closed (first point repeated), then band lines by group.
    let mut pts: Vec<IntPoint> = Vec::new();
    let mut segs: Vec<u32> = Vec::new(); // first point of each segment
    let mut seg_reach: Vec<f64> = Vec::new();
    for c in region.iter().flatten() {
        let base = pts.len() as u32;
        pts.extend_from_slice(c);
        pts.push(c[0]);
        segs.extend((0..c.len() as u32).map(|i| base + i));
        seg_reach.extend(std::iter::repeat_n(reach, c.len()));
    }
    let region_end = segs.len() as u32;
    let mut group_table = Vec::new();
    for (hw, lines) in &groups {
        for l in lines {
            let mut c: Vec<IntPoint> = l.iter().map(|&p| f.to_int(p)).collect();
            c.dedup();
            let base = pts.len() as u32;
            if c.len() == 1 {
                // A dot: one zero-length segment.
                c.push(c[0]);
            }
            pts.extend_from_slice(&c);
            segs.extend((0..c.len() as u32 - 1).map(|i| base + i));
            seg_reach.extend(std::iter::repeat_n(hw + reach, c.len() - 1));
        }
        group_table.push((segs.len() as u32, (hw / q) as f32));
    }
    if pts.len() > 65_536 {
        return Err(VectorError::TooLarge);
    }
    let to_mm = |ip: IntPoint| (f.ox + ip.x as f64 * q, f.oy + ip.y as f64 * q);
    // Points must fit u16.
    if pts.iter().any(|ip| ip.x < 0 || ip.y < 0 || ip.x > 65_535 || ip.y > 65_535) {
        return Err(VectorError::TooLarge);
    }

    // The grid: the felt part's bounds, grown by the reach, within the page grown by it.
    let mut bb = (f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
    for (k, &s) in segs.iter().enumerate() {
        let m = seg_reach[k];
        for ip in [pts[s as usize], pts[s as usize + 1]] {
            let (x, y) = to_mm(ip);
            bb = (bb.0.min(x - m), bb.1.min(y - m), bb.2.max(x + m), bb.3.max(y + m));
        }
    }
    let bb = (bb.0.max(pg.0 - reach), bb.1.max(pg.1 - reach), bb.2.min(pg.2 + reach), bb.3.min(pg.3 + reach));
    if !(bb.2 > bb.0 && bb.3 > bb.1) {
        return Ok(None);
    }
    // Cells on whole quanta, starting at the grid's corner.
    let cell_q = (p.cell_mm / q).round().max(1.0);
    let cell = cell_q * q;
    let gx = ((bb.0 - f.ox) / q).floor();
    let gy = ((bb.1 - f.oy) / q).floor();
    let (x0, y0) = (f.ox + gx * q, f.oy + gy * q);
    let cols = ((bb.2 - x0) / cell).ceil().max(1.0) as usize;
    let rows = ((bb.3 - y0) / cell).ceil().max(1.0) as usize;
    if cols * rows > 4_000_000 {
        return Err(VectorError::TooLarge);
    }
    let mut lists: Vec<Vec<u32>> = vec![Vec::new(); cols * rows];
    for (id, &s) in segs.iter().enumerate() {
        let (a, b) = (to_mm(pts[s as usize]), to_mm(pts[s as usize + 1]));
        let m = seg_reach[id];
        let cr = |v: f64, o: f64, n: usize| (((v - o) / cell).floor().max(0.0) as usize).min(n - 1);
        let (c0, c1) = (cr(a.0.min(b.0) - m, x0, cols), cr(a.0.max(b.0) + m, x0, cols));
        let (r0, r1) = (cr(a.1.min(b.1) - m, y0, rows), cr(a.1.max(b.1) + m, y0, rows));
        for r in r0..=r1 {
            for c in c0..=c1 {
                let rect = (
                    x0 + c as f64 * cell,
                    y0 + r as f64 * cell,
                    x0 + (c + 1) as f64 * cell,
                    y0 + (r + 1) as f64 * cell,
                );
                if seg_rect_distance(a, b, rect) <= m {
                    lists[r * cols + c].push(id as u32);
                }
            }
        }
    }
    // Region state at each cell's (displaced) centre: crossings of the
    // segment from it to a point left of everything, which is outside.
    let mut inside = vec![0u8; (cols * rows).div_ceil(8)];
    let fx = |ip: IntPoint| (ip.x as i64 * FIXED, ip.y as i64 * FIXED);
    let region_segs: Vec<((i64, i64), (i64, i64))> =
        segs[..region_end as usize].iter().map(|&s| (fx(pts[s as usize]), fx(pts[s as usize + 1]))).collect();
    let far_left = region_segs.iter().map(|(a, b)| a.0.min(b.0)).min().unwrap_or(0) - 1024 * FIXED;
    let half = cell_q as i64 * FIXED / 2;
    for r in 0..rows {
        let cy = (gy as i64 + r as i64 * cell_q as i64) * FIXED + half;
        // Segments that reach the centre's row (within a unit: the displacement is infinitesimal).
        let row: Vec<_> =
            region_segs.iter().filter(|(a, b)| a.1.min(b.1) <= cy + FIXED && a.1.max(b.1) >= cy - FIXED).collect();
        for c in 0..cols {
            let centre = ((gx as i64 + c as i64 * cell_q as i64) * FIXED + half, cy);
            let z = (far_left, cy);
            if row.iter().filter(|(a, b)| crosses(*a, *b, centre, z)).count() % 2 == 1 {
                let k = r * cols + c;
                inside[k / 8] |= 1 << (k % 8);
            }
        }
    }
    let mut starts = Vec::with_capacity(cols * rows + 1);
    let mut refs = Vec::new();
    for l in &lists {
        starts.push(refs.len() as u32);
        // A segment id names its first point.
        refs.extend(l.iter().copied());
    }
    starts.push(refs.len() as u32);
    // Segment ids become point ids (segment i joins points i and i + 1).
    let refs = refs.into_iter().map(|id| segs[id as usize]).collect();
    let region_end = if region_end == 0 { 0 } else { segs[region_end as usize - 1] + 1 };
    let group_table = group_table.into_iter().map(|(end, hw)| (segs[end as usize - 1] + 1, hw)).collect();
    Ok(Some(VectorLayer {
        mode,
        origin: ((f.ox) as f32, (f.oy) as f32),
        quantum: q as f32,
        cell: cell_q as f32,
        cols: cols as u32,
        rows: rows as u32,
        ramp: (ramp / q) as f32,
        points: pts.iter().map(|ip| [ip.x as u16, ip.y as u16]).collect(),
        region_end,
        groups: group_table,
        starts,
        refs,
        inside,
        grid: (gx as f32, gy as f32),
    }))
}

/// Bytes of the proposed chunk header (`docs/layers.md`, "Draft: vector layers").
pub const VECTOR_HEADER_LEN: usize = 64;

impl VectorLayer {
    /// The exact length of the proposed encoding with `sources` provenance
    /// entries: header, sources, band groups, points, cell starts, region
    /// bits, references (16-bit starts and references when they fit).
    pub fn encoded_len(&self, sources: usize) -> usize {
        let cells = self.cols as usize * self.rows as usize;
        let wide_starts = self.refs.len() > 65_535;
        let wide_refs = self.points.len() > 65_536;
        let pad4 = |n: usize| n.div_ceil(4) * 4;
        VECTOR_HEADER_LEN
            + 4 * sources
            + 8 * self.groups.len()
            + 4 * self.points.len()
            + pad4((cells + 1) * if wide_starts { 4 } else { 2 })
            + pad4(cells.div_ceil(8))
            + pad4(self.refs.len() * if wide_refs { 4 } else { 2 })
    }

    /// Segments listed per cell: (cells with any, mean over those, largest).
    pub fn cell_stats(&self) -> (usize, f64, usize) {
        let counts: Vec<usize> = self.starts.windows(2).map(|w| (w[1] - w[0]) as usize).filter(|&n| n > 0).collect();
        let mean = if counts.is_empty() { 0.0 } else { counts.iter().sum::<usize>() as f64 / counts.len() as f64 };
        (counts.len(), mean, counts.iter().copied().max().unwrap_or(0))
    }

    /// The edge profile's amplitude (0..=1, before the layer's amplitude) at
    /// page `(x, y)` mm: what a player computes.
    #[inline]
    pub fn coverage_at(&self, x: f32, y: f32) -> f32 {
        let u = (x - self.origin.0) / self.quantum;
        let v = (y - self.origin.1) / self.quantum;
        let cx = (u - self.grid.0) / self.cell;
        let cy = (v - self.grid.1) / self.cell;
        // NaN fails both comparisons.
        if !(cx >= 0.0 && cy >= 0.0 && cx < self.cols as f32 && cy < self.rows as f32) {
            return 0.0;
        }
        let k = cy as usize * self.cols as usize + cx as usize;
        let (Some(&s0), Some(&s1)) = (self.starts.get(k), self.starts.get(k + 1)) else { return 0.0 };
        let refs = self.refs.get(s0 as usize..s1 as usize).unwrap_or(&[]);
        let inside = self.inside.get(k / 8).is_some_and(|b| b >> (k % 8) & 1 == 1);
        if refs.is_empty() {
            // No edge within reach: the cell is what its centre is.
            return if inside && self.mode == Mode::Grating { 1.0 } else { 0.0 };
        }
        // Region: nearest squared distance, and the signed cross / length of its segment.
        let mut dmin = f32::INFINITY;
        let mut flips = false;
        // The cell's centre and the point in fixed point (units of q / 256).
        let (ci, cj) = ((k % self.cols as usize) as i64, (k / self.cols as usize) as i64);
        let half = self.cell as i64 * FIXED / 2;
        let centre = (
            (self.grid.0 as i64 + ci * self.cell as i64) * FIXED + half,
            (self.grid.1 as i64 + cj * self.cell as i64) * FIXED + half,
        );
        let pp = ((u * FIXED as f32).round() as i64, (v * FIXED as f32).round() as i64);
        let mut band = [f32::INFINITY; MAX_GROUPS];
        let mut g = 0usize;
        for &id in refs {
            let i = id as usize;
            let (Some(a), Some(b)) = (self.points.get(i), self.points.get(i + 1)) else { break };
            let (ax, ay, bx, by) = (a[0] as f32, a[1] as f32, b[0] as f32, b[1] as f32);
            let (ex, ey, wx, wy) = (bx - ax, by - ay, u - ax, v - ay);
            let l2 = ex * ex + ey * ey;
            let t = wx * ex + wy * ey;
            let cross = ex * wy - ey * wx;
            let d2 = if t <= 0.0 {
                wx * wx + wy * wy
            } else if t >= l2 {
                (u - bx) * (u - bx) + (v - by) * (v - by)
            } else {
                cross * cross / l2
            };
            if id < self.region_end {
                dmin = dmin.min(d2);
                let (a, b) = (fixed(a), fixed(b));
                flips ^= crosses(a, b, centre, pp);
            } else {
                // Groups follow the region in id order; a cell's ids increase.
                while g + 1 < self.groups.len() && id >= self.groups[g].0 {
                    g += 1;
                }
                if let Some(m) = band.get_mut(g) {
                    *m = m.min(d2);
                }
            }
        }
        // The side: the centre's state, flipped by each crossing on the way to the point.
        let s = if inside != flips { dmin.sqrt() } else { -dmin.sqrt() };
        let mut s = if s.is_nan() { f32::NEG_INFINITY } else { s };
        match self.mode {
            Mode::Vibration => {
                let mut felt = f32::NEG_INFINITY;
                for (k, &(_, hw)) in self.groups.iter().enumerate().take(MAX_GROUPS) {
                    felt = felt.max(hw - band[k].sqrt());
                }
                s = s.min(felt);
            }
            Mode::Grating => {
                for (k, &(_, hw)) in self.groups.iter().enumerate().take(MAX_GROUPS) {
                    s = s.min(band[k].sqrt() - hw);
                }
            }
        }
        (0.5 + s / self.ramp).clamp(0.0, 1.0)
    }

    /// Four actuators at a time (lanes are independent: each has its own cell).
    #[inline]
    pub fn coverage4(&self, x: [f32; 4], y: [f32; 4]) -> [f32; 4] {
        [
            self.coverage_at(x[0], y[0]),
            self.coverage_at(x[1], y[1]),
            self.coverage_at(x[2], y[2]),
            self.coverage_at(x[3], y[3]),
        ]
    }
}

/// Capturing the layers a compilation builds, for the figures and benches.
pub mod capture {
    use std::cell::RefCell;

    use taxel_format::DistanceLayer;

    use crate::distance::{FieldParams, LayerGeometry};
    use crate::geometry::{FillRule, Polyline};

    /// A style's geometry, owned.
    #[derive(Debug, Clone, Default)]
    pub struct OwnedGeometry {
        /// Fills and their rules.
        pub fills: Vec<(Vec<Polyline>, FillRule)>,
        /// Band centre lines and width.
        pub band: Option<(Vec<Vec<Polyline>>, f64)>,
        /// Cut bands.
        pub cuts: Vec<(Vec<Polyline>, f64)>,
        /// Clip regions.
        pub clips: Vec<(Vec<Polyline>, FillRule)>,
        /// Opaque fills painted over the layer.
        pub occluders: Vec<(Vec<Polyline>, FillRule)>,
    }

    impl OwnedGeometry {
        /// Borrowed, as the builders take it.
        pub fn view(&self) -> LayerGeometry<'_> {
            LayerGeometry {
                fills: self.fills.iter().map(|(p, r)| (&p[..], *r)).collect(),
                band: self.band.as_ref().map(|(l, w)| (l.iter().map(|p| &p[..]).collect(), *w)),
                cuts: self.cuts.iter().map(|(p, w)| (&p[..], *w)).collect(),
                clips: self.clips.iter().map(|(p, r)| (&p[..], *r)).collect(),
                occluders: self.occluders.iter().map(|(p, r)| (&p[..], *r)).collect(),
            }
        }
    }

    /// One layer as the compiler built it.
    #[derive(Debug, Clone)]
    pub struct Captured {
        /// Its geometry.
        pub geometry: OwnedGeometry,
        /// The field's parameters (pitch, soft, page).
        pub params: FieldParams,
        /// The distance layer (technique (a)) written to the bundle.
        pub layer: DistanceLayer,
        /// Source elements it holds.
        pub sources: usize,
    }

    thread_local! {
        static SINK: RefCell<Option<Vec<Captured>>> = const { RefCell::new(None) };
    }

    /// Runs `f` and returns every distance layer the compiler built meanwhile on this thread.
    pub fn layers_of(f: impl FnOnce()) -> Vec<Captured> {
        SINK.with(|s| *s.borrow_mut() = Some(Vec::new()));
        f();
        SINK.with(|s| s.borrow_mut().take()).unwrap_or_default()
    }

    /// Whether a capture is under way (one thread-local read per layer built).
    pub(crate) fn active() -> bool {
        SINK.with(|s| s.borrow().is_some())
    }

    /// Records one layer.
    pub(crate) fn record(g: &LayerGeometry<'_>, params: FieldParams, layer: &DistanceLayer) {
        let own = OwnedGeometry {
            fills: g.fills.iter().map(|(p, r)| (p.to_vec(), *r)).collect(),
            band: g.band.as_ref().map(|(l, w)| (l.iter().map(|p| p.to_vec()).collect(), *w)),
            cuts: g.cuts.iter().map(|(p, w)| (p.to_vec(), *w)).collect(),
            clips: g.clips.iter().map(|(p, r)| (p.to_vec(), *r)).collect(),
            occluders: g.occluders.iter().map(|(p, r)| (p.to_vec(), *r)).collect(),
        };
        let c = Captured { geometry: own, params, layer: layer.clone(), sources: layer.sources.len() };
        SINK.with(|s| {
            if let Some(v) = s.borrow_mut().as_mut() {
                v.push(c);
            }
        });
    }
}

#[cfg(test)]
mod tests;
