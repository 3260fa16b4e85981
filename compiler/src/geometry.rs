//! Shared service: exact geometry.
//!
//! Exact geometry in f64: outlines flattened to polylines in page
//! millimetres, point-in-shape tests and distances to an outline.
//!
//! The compiler uses these for dots along paths, spacing rules and overlap
//! checks; error reports use them as the exact reference that raster masks
//! are measured against ("coverage computed from the path itself").
//!
//! ```
//! use taxel_compiler::geometry::{FillRule, Polyline, contains, distance_to_outline};
//!
//! let square = vec![Polyline { points: vec![(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)], closed: true }];
//! assert!(contains(&square, (5.0, 5.0), FillRule::NonZero));
//! assert!(!contains(&square, (15.0, 5.0), FillRule::NonZero));
//! assert!((distance_to_outline(&square, (5.0, 3.0)) - 3.0).abs() < 1e-12);
//! ```

use resvg::tiny_skia::{Path, PathSegment, Transform};

mod area;
mod sides;
pub(crate) mod apart;
pub(crate) mod crossings;
pub(crate) mod overlay;
pub use area::{filled_area, filled_area_within};
pub use sides::SideRows;

/// Largest distance, in millimetres, between a curve and the polyline that replaces it.
///
/// Masks are rasterised from these polylines, so this bounds how far a mask's
/// edge moves against the true curve: 0.5 µm is 0.5 % of a sample at the
/// default 10 px/mm (about 1 LSB of coverage), below tiny-skia's own
/// anti-aliasing noise. At 5 µm a chord's bias alone was worth 13 LSB on a
/// circle's edge samples. A 30 mm circle takes about 300 points.
pub const FLATTEN_TOLERANCE_MM: f64 = 0.0005;

/// How finely [`flatten_with`] flattens: the largest distance, mm, between a
/// curve and its polyline, for curves in general and for the cubics that
/// stand for circular arcs (see [`flatten_with`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Flattening {
    /// Curves in general.
    pub curves: f64,
    /// Circular arcs, flattened on the arc itself.
    pub arcs: f64,
}

impl Flattening {
    /// The drawing stage's: [`FLATTEN_TOLERANCE_MM`] for both.
    pub const DEFAULT: Flattening = Flattening { curves: FLATTEN_TOLERANCE_MM, arcs: FLATTEN_TOLERANCE_MM };
}

/// The flattening of `taxel report`'s exact reference: curves as a build
/// flattens them (its polylines are what the compiler is given), circular
/// arcs within 1 nm, the rounding of the arc tiles' `f32` records, so that
/// the reference is the circle and not a polygon 0.5 µm inside it (a
/// fifteenth of a hard edge's ramp at the finest rung of the report's
/// ladder, 0.25 mm).
pub const REFERENCE_FLATTENING: Flattening = Flattening { curves: FLATTEN_TOLERANCE_MM, arcs: 0.000_001 };

impl Default for Flattening {
    fn default() -> Self {
        Flattening::DEFAULT
    }
}

/// How the inside of a shape is decided (SVG `fill-rule`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FillRule {
    /// Inside where the winding number is not zero.
    #[default]
    NonZero,
    /// Inside where a ray crosses the outline an odd number of times.
    EvenOdd,
}

/// One subpath as a polyline in page millimetres.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Polyline {
    /// The vertices, in drawing order. A closed polyline does not repeat its first point.
    pub points: Vec<(f64, f64)>,
    /// Whether the subpath was closed (`Z`).
    pub closed: bool,
}

impl Polyline {
    /// The vertices as a path that is walked: a closed polyline ends where it
    /// started (its first point repeated), an open one is returned as it is.
    pub fn walked(&self) -> Vec<(f64, f64)> {
        let mut points = self.points.clone();
        if let (true, Some(&first)) = (self.closed, self.points.first()) {
            points.push(first);
        }
        points
    }

    /// The segments, including the closing one of a closed polyline.
    pub fn segments(&self) -> impl Iterator<Item = ((f64, f64), (f64, f64))> + '_ {
        let n = self.points.len();
        (0..self.segment_count()).map(move |i| (self.points[i], self.points[(i + 1) % n]))
    }

    /// How many segments [`Polyline::segments`] gives.
    pub fn segment_count(&self) -> usize {
        let n = self.points.len();
        n.saturating_sub(1) + usize::from(self.closed && n > 2)
    }

    /// The length along the polyline (closing segment included when closed).
    pub fn length(&self) -> f64 {
        self.segments().map(|(a, b)| dist(a, b)).sum()
    }
}

/// Euclidean distance between two points.
pub fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

/// Flattens `path` after applying `ts` (which should map to page millimetres),
/// so that no point of a curve is farther than `tolerance` from the result.
/// Subpaths with fewer than two distinct points are dropped.
pub fn flatten(path: &Path, ts: Transform, tolerance: f64) -> Vec<Polyline> {
    flatten_with(path, ts, Flattening { curves: tolerance, arcs: tolerance })
}

/// [`flatten`], with circular arcs apart: a cubic that is the usual
/// approximation of a circular arc ([`circular_arc`]; how usvg writes a
/// `<circle>`, an `<ellipse>` of equal radii, a rounded corner and an
/// `A` command under a similarity) is flattened on the arc itself, its
/// vertices on the circle, within `tolerance.arcs`. The cubic strays from
/// the circle by up to 0.027 % of its radius (4 µm on a 15 mm circle), a
/// code or half a code of a distance layer's hard edge: the writer plays a
/// circle as the circle (an arc tile), and the report's reference is the
/// circle too, so that neither measures the other's approximation.
pub fn flatten_with(path: &Path, ts: Transform, tolerance: Flattening) -> Vec<Polyline> {
    let fine = |t: f64| if t.is_finite() && t > 0.0 { t } else { FLATTEN_TOLERANCE_MM };
    let (tol, arc_tol) = (fine(tolerance.curves), fine(tolerance.arcs));
    let map = |p: resvg::tiny_skia::Point| {
        let (x, y) = (p.x as f64, p.y as f64);
        (ts.sx as f64 * x + ts.kx as f64 * y + ts.tx as f64, ts.ky as f64 * x + ts.sy as f64 * y + ts.ty as f64)
    };
    let mut out: Vec<Polyline> = Vec::new();
    let mut cur = Polyline::default();
    let finish = |cur: &mut Polyline, out: &mut Vec<Polyline>| {
        let mut pl = core::mem::take(cur);
        pl.points.dedup();
        if pl.closed && pl.points.len() > 1 && pl.points.first() == pl.points.last() {
            pl.points.pop();
        }
        if pl.points.len() >= 2 && pl.points.iter().all(|p| p.0.is_finite() && p.1.is_finite()) {
            out.push(pl);
        }
    };
    for seg in path.segments() {
        match seg {
            PathSegment::MoveTo(p) => {
                finish(&mut cur, &mut out);
                cur.points.push(map(p));
            }
            PathSegment::LineTo(p) => cur.points.push(map(p)),
            PathSegment::QuadTo(c, p) => {
                let p0 = cur.points.last().copied().unwrap_or(map(c));
                let (c, p) = (map(c), map(p));
                let d = second_diff(p0, c, p);
                let n = steps(0.25 * d, tol);
                for i in 1..=n {
                    let t = i as f64 / n as f64;
                    let u = 1.0 - t;
                    cur.points.push((
                        u * u * p0.0 + 2.0 * u * t * c.0 + t * t * p.0,
                        u * u * p0.1 + 2.0 * u * t * c.1 + t * t * p.1,
                    ));
                }
            }
            PathSegment::CubicTo(c1, c2, p) => {
                let p0 = cur.points.last().copied().unwrap_or(map(c1));
                let (c1, c2, p) = (map(c1), map(c2), map(p));
                if let Some(arc) = circular_arc(p0, c1, c2, p) {
                    arc.flatten(p, arc_tol, &mut cur.points);
                    continue;
                }
                let d = second_diff(p0, c1, c2).max(second_diff(c1, c2, p));
                let n = steps(0.75 * d, tol);
                for i in 1..=n {
                    let t = i as f64 / n as f64;
                    let u = 1.0 - t;
                    let (a, b, c, e) = (u * u * u, 3.0 * u * u * t, 3.0 * u * t * t, t * t * t);
                    cur.points
                        .push((a * p0.0 + b * c1.0 + c * c2.0 + e * p.0, a * p0.1 + b * c1.1 + c * c2.1 + e * p.1));
                }
            }
            PathSegment::Close => {
                cur.closed = true;
                let start = cur.points.first().copied();
                finish(&mut cur, &mut out);
                // A drawing command after `Z` starts from the subpath's first point.
                if let Some(s) = start {
                    cur.points.push(s);
                }
            }
        }
    }
    finish(&mut cur, &mut out);
    out
}

/// A circular arc: its centre, radius, the angle of its start and its
/// sweep (radians, signed).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CircularArc {
    /// The centre, mm.
    pub centre: (f64, f64),
    /// The radius, mm.
    pub radius: f64,
    /// The angle of the start point round the centre.
    pub start: f64,
    /// The angle swept to the end point, at most a half turn either way.
    pub sweep: f64,
}

impl CircularArc {
    /// Appends the arc's vertices after its start, the last `end` itself,
    /// so that no chord's sagitta exceeds `tol`.
    fn flatten(&self, end: (f64, f64), tol: f64, out: &mut Vec<(f64, f64)>) {
        // A chord of angle a has the sagitta r (1 − cos(a / 2)).
        let half = (1.0 - (tol / self.radius).min(1.0)).acos();
        let n = (self.sweep.abs() / (2.0 * half)).ceil();
        let n = if n.is_finite() { (n as usize).clamp(1, MAX_ARC_STEPS) } else { 1 };
        for i in 1..n {
            let a = self.start + self.sweep * i as f64 / n as f64;
            out.push((self.centre.0 + self.radius * a.cos(), self.centre.1 + self.radius * a.sin()));
        }
        out.push(end);
    }
}

/// The most chords an arc is flattened into (a 15 mm circle's quarter
/// takes about 2,000 at 1 nm).
const MAX_ARC_STEPS: usize = 4096;

/// The circular arc that the cubic `p0 c1 c2 p3` stands for, if it is the
/// usual approximation of one: its handles tangent to the circle at its
/// ends, of equal length `4/3 tan(θ / 4) r` for a sweep `θ` (at most a half
/// turn) and a radius `r` (the construction of usvg, tiny-skia, kurbo and
/// most editors; a quarter circle's handle is 0.5523 `r`). The points are
/// the path's `f32` coordinates, so each test allows their rounding.
pub fn circular_arc(p0: (f64, f64), c1: (f64, f64), c2: (f64, f64), p3: (f64, f64)) -> Option<CircularArc> {
    let (t0, t1) = ((c1.0 - p0.0, c1.1 - p0.1), (p3.0 - c2.0, p3.1 - c2.1));
    let (l0, l1) = (t0.0.hypot(t0.1), t1.0.hypot(t1.1));
    let chord = (p3.0 - p0.0).hypot(p3.1 - p0.1);
    // The rounding of f32 coordinates of this size, with room to spare.
    let size = [p0, c1, c2, p3].iter().fold(0.0f64, |m, p| m.max(p.0.abs()).max(p.1.abs()));
    let slack = 16.0 * f32::EPSILON as f64 * size.max(1.0);
    if !(l0 > slack && l1 > slack && chord > slack) || (l0 - l1).abs() > 4.0 * slack {
        return None;
    }
    // The centre, where the normals at the two ends meet: p0 + a n0 = p3 + b n1.
    let (n0, n1) = ((-t0.1 / l0, t0.0 / l0), (-t1.1 / l1, t1.0 / l1));
    let det = n0.0 * (-n1.1) - n0.1 * (-n1.0);
    if det.abs() < 1e-9 {
        return None;
    }
    let (dx, dy) = (p3.0 - p0.0, p3.1 - p0.1);
    let a = (dx * (-n1.1) - dy * (-n1.0)) / det;
    let centre = (p0.0 + a * n0.0, p0.1 + a * n0.1);
    let (r0, r1) = ((p0.0 - centre.0).hypot(p0.1 - centre.1), (p3.0 - centre.0).hypot(p3.1 - centre.1));
    let radius = (r0 + r1) / 2.0;
    if !(radius.is_finite() && radius > slack) || (r0 - r1).abs() > 4.0 * slack {
        return None;
    }
    let start = (p0.1 - centre.1).atan2(p0.0 - centre.0);
    let end = (p3.1 - centre.1).atan2(p3.0 - centre.0);
    // Turning the way the start's handle points.
    let turn = (p0.0 - centre.0) * t0.1 - (p0.1 - centre.1) * t0.0;
    let mut sweep = end - start;
    let tau = std::f64::consts::TAU;
    if turn > 0.0 {
        while sweep <= 0.0 {
            sweep += tau;
        }
    } else {
        while sweep >= 0.0 {
            sweep -= tau;
        }
    }
    if sweep.abs() > std::f64::consts::PI + 1e-9 {
        return None;
    }
    // The handles' length for this sweep and radius.
    let handle = 4.0 / 3.0 * (sweep.abs() / 4.0).tan() * radius;
    if (l0 - handle).abs() > 4.0 * slack + 1e-6 * radius || (l1 - handle).abs() > 4.0 * slack + 1e-6 * radius {
        return None;
    }
    Some(CircularArc { centre, radius, start, sweep })
}

fn second_diff(a: (f64, f64), b: (f64, f64), c: (f64, f64)) -> f64 {
    (a.0 - 2.0 * b.0 + c.0).hypot(a.1 - 2.0 * b.1 + c.1)
}

/// Segments needed so that a curve whose chord error bound is `m / n²` stays within `tol`.
fn steps(m: f64, tol: f64) -> usize {
    let n = (m / tol).sqrt().ceil();
    if n.is_finite() { (n as usize).clamp(1, 1000) } else { 1 }
}

/// Whether `p` is inside the shape whose subpaths are `polys` (each closed
/// implicitly, as SVG fills do).
pub fn contains(polys: &[Polyline], p: (f64, f64), rule: FillRule) -> bool {
    let mut ray = Crossings::default();
    for pl in polys {
        let n = pl.points.len();
        for i in 0..n {
            ray.side(p, pl.points[i], pl.points[(i + 1) % n]);
        }
    }
    ray.inside(rule)
}

/// The sides crossing the ray from a point towards +x, counted side by side
/// (the crossing rule of [`contains`]): whether the point is inside by
/// either fill rule once every side of the outline has been offered.
#[derive(Debug, Default)]
pub(crate) struct Crossings {
    winding: i32,
    crossings: u32,
}

impl Crossings {
    /// Counts side `a`-`b` if it crosses the ray from `p`.
    pub(crate) fn side(&mut self, p: (f64, f64), a: (f64, f64), b: (f64, f64)) {
        if (a.1 <= p.1) != (b.1 <= p.1) {
            let x = a.0 + (p.1 - a.1) / (b.1 - a.1) * (b.0 - a.0);
            if x > p.0 {
                self.crossings += 1;
                self.winding += if b.1 > a.1 { 1 } else { -1 };
            }
        }
    }

    /// Whether the point is inside by `rule`.
    pub(crate) fn inside(&self, rule: FillRule) -> bool {
        match rule {
            FillRule::NonZero => self.winding != 0,
            FillRule::EvenOdd => self.crossings % 2 == 1,
        }
    }
}

/// Whether side `a`-`b` comes within `margin` of `p`, to the bit (its box
/// first, with the slack of [`distance_to_outline_within`]).
pub(crate) fn side_within(p: (f64, f64), a: (f64, f64), b: (f64, f64), margin: f64) -> bool {
    let t = margin + margin * 1e-9 + 1e-9;
    let dx = (a.0.min(b.0) - p.0).max(p.0 - a.0.max(b.0)).max(0.0);
    let dy = (a.1.min(b.1) - p.1).max(p.1 - a.1.max(b.1)).max(0.0);
    dx * dx + dy * dy <= t * t && distance_to_segment(p, a, b) <= margin
}

/// Whether `p` lies inside the shape (by `rule`) farther than `margin` from
/// its outline: `contains(polys, p, rule)` and
/// `distance_to_outline_within(polys, p, margin, margin) > margin`, in one
/// pass over the sides that stops at the first side within `margin`.
pub fn deep_inside(polys: &[Polyline], p: (f64, f64), rule: FillRule, margin: f64) -> bool {
    let mut ray = Crossings::default();
    for pl in polys {
        let n = pl.points.len();
        // The sides [`Polyline::segments`] measures; every side closes the ring for the winding.
        let measured = pl.segment_count();
        for i in 0..n {
            let (a, b) = (pl.points[i], pl.points[(i + 1) % n]);
            if i < measured && side_within(p, a, b, margin) {
                return false;
            }
            ray.side(p, a, b);
        }
    }
    ray.inside(rule)
}

/// Douglas–Peucker simplification: the points of `points` that keep every
/// dropped point within `tol` of the result (a closed ring is split at its
/// first point and the point farthest from it).
pub fn simplify(points: &[(f64, f64)], closed: bool, tol: f64) -> Vec<(f64, f64)> {
    if points.len() <= 3 {
        return points.to_vec();
    }
    let mut keep = vec![false; points.len()];
    // Scratch for [`farthest`]: each point's squared offset.
    let mut squares = vec![0.0; points.len()];
    let last = points.len() - 1;
    keep[0] = true;
    keep[last] = true;
    let mut stack = vec![(0usize, last)];
    if closed {
        // The farthest point from the first splits the ring into two chains
        // (the last of equal ones, as `max_by` takes it).
        let p0 = points[0];
        let far = farthest(1..points.len(), |i| (p0.0 - points[i].0, p0.1 - points[i].1), &mut squares, Ties::Last)
            .map_or(last, |f| f.at);
        keep[far] = true;
        stack = vec![(0, far), (far, last)];
    }
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        // The first of equal farthest points, if any is off the chord.
        let (pa, pb) = (points[a], points[b]);
        let far = farthest(a + 1..b, |i| offset_to_segment(points[i], pa, pb), &mut squares, Ties::First);
        if let Some(f) = far
            && f.beyond(tol)
        {
            keep[f.at] = true;
            stack.push((a, f.at));
            stack.push((f.at, b));
        }
    }
    points.iter().zip(keep).filter(|(_, k)| *k).map(|(p, _)| *p).collect()
}

/// The points of `points` that keep every dropped point within `tol` of the
/// result, as [`simplify`] keeps them but in windows of at most
/// [`THIN_WINDOW`] points whose ends are kept, so that the work is linear in
/// the points whatever their shape (Douglas–Peucker's worst case is
/// quadratic, a spiral's). A closed ring keeps its first point; one that
/// would keep fewer than three points, or a `tol` that is not positive,
/// leaves `points` as they are.
pub fn thin(points: &[(f64, f64)], closed: bool, tol: f64) -> Vec<(f64, f64)> {
    if points.len() <= 3 || !(tol > 0.0 && tol.is_finite()) {
        return points.to_vec();
    }
    // A ring is walked back to its first point, which ends the last window.
    let ring: Vec<(f64, f64)>;
    let chain = if closed {
        ring = points.iter().chain(points.first()).copied().collect();
        &ring[..]
    } else {
        points
    };
    let last = chain.len() - 1;
    let mut out = Vec::with_capacity(points.len() / 2 + 2);
    let mut start = 0;
    while start < last {
        let end = (start + THIN_WINDOW - 1).min(last);
        let kept = simplify(&chain[start..=end], false, tol);
        out.extend_from_slice(&kept[..kept.len() - 1]);
        start = end;
    }
    if !closed {
        out.push(chain[last]);
    } else if out.len() < 3 {
        return points.to_vec();
    }
    out
}

/// The most points [`thin`] simplifies at once.
pub const THIN_WINDOW: usize = 256;

/// Which of equally far points [`farthest`] names.
#[derive(Clone, Copy, PartialEq)]
enum Ties {
    /// The first of them, and none when all lie at distance 0.
    First,
    /// The last of them.
    Last,
}

/// The point of `range` whose offset (`offset(i)`) is the farthest by its
/// `hypot`, as [`dist`] measures it, to the bit: the first or last of equal
/// ones (`ties`). `squares` is scratch space, at least as long as the
/// range's end.
///
/// `hypot` (a fifth of a 3.2 M-segment outline's simplification, and on
/// real-size drawings a third of it) is computed only for the points whose
/// squared offset comes within a relative 1e-12 of the largest square, and
/// not at all when one point alone does. The square's rounding (three
/// roundings of 2^-53) and `hypot`'s (under one ulp) are far inside that
/// margin, so a point left out could not have been as far. When the largest
/// square is too small or too large to hold its value (below 1e-280, or
/// infinite), or some square is NaN, every point is measured ([`Farthest`]).
fn farthest(
    range: std::ops::Range<usize>,
    offset: impl Fn(usize) -> (f64, f64),
    squares: &mut [f64],
    ties: Ties,
) -> Option<Far> {
    let mut top = 0.0f64;
    let mut nan = false;
    for i in range.clone() {
        let e = offset(i);
        let s = e.0 * e.0 + e.1 * e.1;
        squares[i] = s;
        nan |= s.is_nan();
        if s > top {
            top = s;
        }
    }
    if nan || !(top > 1e-280 && top.is_finite()) {
        return measure_every_point(range, offset, ties);
    }
    let near = top * (1.0 - 1e-12);
    let mut found: Option<Far> = None;
    let mut alone = true;
    for i in range.clone() {
        if squares[i] < near {
            continue;
        }
        if found.is_some() {
            alone = false;
            break;
        }
        found = Some(Far { at: i, offset: offset(i), square: squares[i], distance: None });
    }
    if alone {
        return found;
    }
    // Several points come within the margin: their `hypot` decides.
    let mut best: Option<Far> = None;
    for i in range {
        if squares[i] < near {
            continue;
        }
        let e = offset(i);
        let d = e.0.hypot(e.1);
        let take = match (&best, ties) {
            (None, _) => true,
            (Some(b), Ties::First) => d > b.distance.unwrap_or(f64::INFINITY),
            (Some(b), Ties::Last) => d.total_cmp(&b.distance.unwrap_or(f64::NEG_INFINITY)).is_ge(),
        };
        if take {
            best = Some(Far { at: i, offset: e, square: squares[i], distance: Some(d) });
        }
    }
    best
}

/// [`farthest`] by measuring every point's `hypot` (with [`Farthest`]'s
/// shortcut), for ranges whose squares cannot be trusted.
fn measure_every_point(range: std::ops::Range<usize>, offset: impl Fn(usize) -> (f64, f64), ties: Ties) -> Option<Far> {
    let mut far = Farthest::new();
    for i in range {
        match ties {
            Ties::First => far.offer(i, offset(i), |d| d > 0.0, |d, worst| d > worst),
            Ties::Last => far.offer(i, offset(i), |_| true, |d, worst| d.total_cmp(&worst).is_ge()),
        }
    }
    far.at.map(|at| Far { at, offset: (far.worst, 0.0), square: far.worst * far.worst, distance: Some(far.worst) })
}

/// The farthest point [`farthest`] found: its position, its offset and
/// squared offset, and its distance when it was measured.
struct Far {
    at: usize,
    offset: (f64, f64),
    square: f64,
    distance: Option<f64>,
}

impl Far {
    /// Whether the point lies farther than `tol` (its `hypot` above `tol`):
    /// from the squares when they differ by more than a relative 1e-12
    /// (as in [`farthest`]), else measured.
    fn beyond(&self, tol: f64) -> bool {
        let tt = tol * tol;
        if self.distance.is_none() && tt > 1e-280 && tt.is_finite() {
            if self.square > tt * (1.0 + 1e-12) {
                return true;
            }
            if self.square < tt * (1.0 - 1e-12) {
                return false;
            }
        }
        self.distance.unwrap_or_else(|| self.offset.0.hypot(self.offset.1)) > tol
    }
}

/// The farthest of offsets offered one by one, by their `hypot` as
/// [`dist`] measures it, to the bit; `hypot` (a fifth of a 3.2 M-segment
/// outline's simplification) is computed only for an offset whose square
/// comes within a relative 1e-12 of the farthest so far's. The square's
/// rounding (three roundings of 2^-53) and `hypot`'s (under one ulp) are
/// far inside that margin, so an offset skipped could not have been
/// farther; squares too small or too large to hold their value (below
/// 1e-280, or infinite) and NaNs are always measured.
struct Farthest {
    worst: f64,
    /// `worst`'s square less the margin, below which nothing can beat it.
    floor: f64,
    at: Option<usize>,
}

impl Farthest {
    fn new() -> Self {
        Farthest { worst: 0.0, floor: 0.0, at: None }
    }

    /// Takes offset `e` of point `i` when `first(its distance)` while none
    /// is taken, then when `better(its distance, the farthest so far)`;
    /// `better` must be false for a distance below the farthest.
    fn offer(&mut self, i: usize, e: (f64, f64), first: impl Fn(f64) -> bool, better: impl Fn(f64, f64) -> bool) {
        let s = e.0 * e.0 + e.1 * e.1;
        if s < self.floor && s > 1e-280 {
            return;
        }
        let d = e.0.hypot(e.1);
        let take = match self.at {
            None => first(d),
            Some(_) => better(d, self.worst),
        };
        if take {
            self.worst = d;
            self.at = Some(i);
            let f = d * d * (1.0 - 1e-12);
            self.floor = if f.is_finite() { f } else { 0.0 };
        }
    }
}

/// The offset from the nearest point of a segment to `p` (its length is [`distance_to_segment`]).
pub(crate) fn offset_to_segment(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 { (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (p.0 - (a.0 + t * dx), p.1 - (a.1 + t * dy))
}

/// Distance from `p` to the nearest point of a segment.
pub fn distance_to_segment(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let e = offset_to_segment(p, a, b);
    e.0.hypot(e.1)
}

/// Distance from `p` to the nearest point of the outline (every segment of every subpath);
/// infinite when there is no segment.
pub fn distance_to_outline(polys: &[Polyline], p: (f64, f64)) -> f64 {
    polys.iter().flat_map(|pl| pl.segments()).map(|(a, b)| distance_to_segment(p, a, b)).fold(f64::INFINITY, f64::min)
}

/// [`distance_to_outline`] when it is at most `reach`, to the bit; some
/// value above `reach` otherwise. Segments whose boxes lie farther from `p`
/// than the nearest so far (or `reach`) are not measured: a town's dot
/// beside a region's long border needs the few segments near it, and the
/// design rules ask this of every dot and outline that come near.
///
/// Stops as soon as it finds a distance at or below `stop_at` and returns
/// it (a dot that reaches into an outline's band needs no exact distance:
/// the rules treat every overlap alike); pass `f64::NEG_INFINITY` never to stop.
pub fn distance_to_outline_within(polys: &[Polyline], p: (f64, f64), reach: f64, stop_at: f64) -> f64 {
    let mut best = f64::INFINITY;
    for (a, b) in polys.iter().flat_map(|pl| pl.segments()) {
        // The box's distance bounds the segment's from below; the margin
        // keeps rounding from ever skipping a segment that could be nearest.
        let t = best.min(reach);
        let t = t + t * 1e-9 + 1e-9;
        let dx = (a.0.min(b.0) - p.0).max(p.0 - a.0.max(b.0)).max(0.0);
        let dy = (a.1.min(b.1) - p.1).max(p.1 - a.1.max(b.1)).max(0.0);
        if dx * dx + dy * dy > t * t {
            continue;
        }
        best = best.min(distance_to_segment(p, a, b));
        if best <= stop_at {
            return best;
        }
    }
    best
}

/// Exact coverage of a vibrating outline: whether `p` lies within `width / 2`
/// of the outline (the band the compiler strokes with round joins and caps).
pub fn in_outline_band(polys: &[Polyline], p: (f64, f64), width: f64) -> bool {
    distance_to_outline(polys, p) <= width / 2.0
}

/// Smallest distance between two segments (0 when they cross).
pub fn segment_distance(a0: (f64, f64), a1: (f64, f64), b0: (f64, f64), b1: (f64, f64)) -> f64 {
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0);
    let (d1, d2) = (cross(a0, a1, b0), cross(a0, a1, b1));
    let (d3, d4) = (cross(b0, b1, a0), cross(b0, b1, a1));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0)) {
        return 0.0;
    }
    distance_to_segment(a0, b0, b1)
        .min(distance_to_segment(a1, b0, b1))
        .min(distance_to_segment(b0, a0, a1))
        .min(distance_to_segment(b1, a0, a1))
}

/// The box two boxes `(x0, y0, x1, y1)` have in common (inverted when they
/// do not meet).
pub(crate) fn common_bounds(a: (f64, f64, f64, f64), b: (f64, f64, f64, f64)) -> (f64, f64, f64, f64) {
    (a.0.max(b.0), a.1.max(b.1), a.2.min(b.2), a.3.min(b.3))
}

/// Axis-aligned bounds `(x0, y0, x1, y1)` of polylines, or `None` when empty.
pub fn bounds(polys: &[Polyline]) -> Option<(f64, f64, f64, f64)> {
    let mut it = polys.iter().flat_map(|p| p.points.iter());
    let first = *it.next()?;
    Some(it.fold((first.0, first.1, first.0, first.1), |b, &(x, y)| (b.0.min(x), b.1.min(y), b.2.max(x), b.3.max(y))))
}

/// Points at arc-length positions `s` (ascending) along a polyline.
pub fn points_at(pl: &Polyline, positions: &[f64]) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(positions.len());
    let mut acc = 0.0;
    let mut segs = pl.segments().peekable();
    let mut k = 0;
    while let Some((a, b)) = segs.next() {
        let l = dist(a, b);
        while k < positions.len() && (positions[k] <= acc + l || segs.peek().is_none()) {
            let t = if l > 0.0 { ((positions[k] - acc) / l).clamp(0.0, 1.0) } else { 0.0 };
            out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
            k += 1;
        }
        acc += l;
    }
    out
}

#[cfg(test)]
pub(crate) mod tests;
