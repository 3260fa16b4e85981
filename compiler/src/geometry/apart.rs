//! Whether two filled shapes' insides certainly do not meet: a map's
//! neighbouring regions, which share sides vertex for vertex, do not; a
//! label's clearing over a region does.
//!
//! The answer is one-sided: `true` is proved, `false` means "they may meet"
//! (and is also the answer when the outlines come within [`NEAR_MM`] of each
//! other anywhere but at shared vertices and shared sides, when a shared side
//! belongs to a shape that is not one simple ring, or when the work would pass
//! its bounds: [`SWEEP_WORK`] open sides a side, [`MAX_RUNS`] tests). No overlay is computed: the work is one sweep over the
//! two outlines' sides near their common box, and one point-in-shape test per
//! run of sides between points where the outlines touch.
//!
//! Why that suffices. The two outlines cut the plane into faces. A face
//! inside both shapes is bounded by some side of one of them, say a side `e`
//! of A, with the face along it. If `e` is not a side of B, it meets B's
//! outline at most at its ends (the sweep checked that), and so does the
//! run of A's sides it belongs to, which then lies wholly inside B or wholly
//! outside it, as the point tested on it does: outside, so the face is not
//! inside B. If `e` is a side of B as well, both shapes are simple rings
//! (checked), each inside on one side of `e` only, and the sides differ
//! (checked), so no face along `e` is inside both.

use super::{FillRule, Polyline, contains, segment_distance};

/// How near two outlines may come, mm, away from the points and sides they
/// share, before they are taken to meet.
const NEAR_MM: f64 = 1e-6;

/// Two sides from a shared point are taken as running along each other when
/// the sine of the angle between them is below this (a point halfway along
/// one then lies within a billionth of its length of the other).
const COLLINEAR: f64 = 1e-9;

/// Most runs of sides tested against the other shape, for each shape.
const MAX_RUNS: usize = 64;

/// Most open sides a sweep looks at for each side it meets, on average.
const SWEEP_WORK: usize = 64;

type Point = (f64, f64);

/// A filled shape made ready for [`apart`]: its rings with repeated points
/// dropped, their bounds, and (once asked) whether it is one simple ring.
#[derive(Debug)]
pub(crate) struct Filled<'a> {
    outline: &'a [Polyline],
    rule: FillRule,
    rings: Vec<Vec<Point>>,
    bounds: Option<(f64, f64, f64, f64)>,
    /// Whether every coordinate is finite.
    finite: bool,
    /// The sign of the area of its one ring when that ring is simple.
    simple: std::sync::OnceLock<Option<f64>>,
}

impl<'a> Filled<'a> {
    /// The shape of `outline`, every subpath closed, filled by `rule`.
    pub(crate) fn new(outline: &'a [Polyline], rule: FillRule) -> Self {
        let rings: Vec<Vec<Point>> = outline
            .iter()
            .map(|pl| {
                let mut r = pl.points.clone();
                r.dedup();
                while r.len() > 1 && r.first() == r.last() {
                    r.pop();
                }
                r
            })
            .filter(|r| r.len() >= 3)
            .collect();
        let bounds = super::bounds(outline);
        let finite = outline.iter().flat_map(|pl| &pl.points).all(|p| p.0.is_finite() && p.1.is_finite());
        Filled { outline, rule, rings, bounds, finite, simple: std::sync::OnceLock::new() }
    }

    /// The sign of its area when it is one ring that neither crosses nor
    /// touches itself (only neighbouring sides meet, at their shared point);
    /// `None` otherwise.
    fn simple_sign(&self) -> Option<f64> {
        *self.simple.get_or_init(|| {
            let [ring] = self.rings.as_slice() else { return None };
            let sides = sides_of(ring, 0);
            let n = ring.len();
            let mut simple = true;
            let swept = sweep_one(&sides, |s, t| {
                let (s, t) = if s.side < t.side { (s, t) } else { (t, s) };
                let neighbours = t.side == s.side + 1 || (s.side == 0 && t.side == n - 1);
                simple = if neighbours { !folds_back(s, t) } else { segment_distance(s.a, s.b, t.a, t.b) > NEAR_MM };
                simple
            });
            simple &= swept;
            let area: f64 = (0..n).map(|i| cross(ring[i], ring[(i + 1) % n])).sum();
            (simple && area != 0.0 && area.is_finite()).then_some(area.signum())
        })
    }
}

/// One side of a shape: its ends, its bounds, and which side of which ring it is.
#[derive(Debug, Clone, Copy)]
struct Side {
    a: Point,
    b: Point,
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
    ring: usize,
    side: usize,
}

fn sides_of(ring: &[Point], k: usize) -> Vec<Side> {
    sides_in(ring, k, None).collect()
}

/// The sides of ring `k` whose bounds meet `window` (all of them without one).
fn sides_in(ring: &[Point], k: usize, window: Option<(f64, f64, f64, f64)>) -> impl Iterator<Item = Side> + '_ {
    let n = ring.len();
    (0..n).filter_map(move |i| {
        let (a, b) = (ring[i], ring[(i + 1) % n]);
        let (x0, x1, y0, y1) = (a.0.min(b.0), a.0.max(b.0), a.1.min(b.1), a.1.max(b.1));
        let meets = window.is_none_or(|w| x1 >= w.0 && x0 <= w.2 && y1 >= w.1 && y0 <= w.3);
        meets.then_some(Side { a, b, x0, x1, y0, y1, ring: k, side: i })
    })
}

fn cross(p: Point, q: Point) -> f64 {
    p.0 * q.1 - p.1 * q.0
}

/// Whether two sides from one shared point run along each other from it.
fn folds_back(s: &Side, t: &Side) -> bool {
    let Some((c, s2, t2)) = shared_end(s, t) else { return false };
    let (u, v) = ((s2.0 - c.0, s2.1 - c.1), (t2.0 - c.0, t2.1 - c.1));
    let dot = u.0 * v.0 + u.1 * v.1;
    dot > 0.0 && cross(u, v).abs() <= COLLINEAR * u.0.hypot(u.1) * v.0.hypot(v.1)
}

/// The point two sides share (not both ends) and each side's other end.
fn shared_end(s: &Side, t: &Side) -> Option<(Point, Point, Point)> {
    if s.a == t.a {
        Some((s.a, s.b, t.b))
    } else if s.a == t.b {
        Some((s.a, s.b, t.a))
    } else if s.b == t.a {
        Some((s.b, s.a, t.b))
    } else if s.b == t.b {
        Some((s.b, s.a, t.a))
    } else {
        None
    }
}

/// Calls `pair(s, t)` for every side `s` of `xs` and `t` of `ys` whose
/// bounds come within [`NEAR_MM`] of each other (a sweep along x); stops when
/// it returns `false`. `false` when the sweep would look at more than
/// [`SWEEP_WORK`] open sides for each side (long sides across each other,
/// as a scribble's: the answer is then "may meet", and the caller's other
/// bounds apply).
fn sweep(xs: &[Side], ys: &[Side], pair: impl FnMut(&Side, &Side) -> bool) -> bool {
    sweep_lists([xs, ys], false, pair)
}

/// [`sweep`] of the sides of one shape against each other: each pair once,
/// in either order.
fn sweep_one(sides: &[Side], pair: impl FnMut(&Side, &Side) -> bool) -> bool {
    sweep_lists([sides, &[]], true, pair)
}

/// The sweep of [`sweep`] and [`sweep_one`] (`within`: the first list's
/// sides against each other, the second list empty).
fn sweep_lists(lists: [&[Side]; 2], within: bool, mut pair: impl FnMut(&Side, &Side) -> bool) -> bool {
    let mut order: Vec<(f64, usize, usize)> =
        (0..2).flat_map(|l| lists[l].iter().enumerate().map(move |(i, s)| (s.x0, l, i))).collect();
    order.sort_unstable_by(|p, q| p.0.total_cmp(&q.0));
    let mut budget = SWEEP_WORK.saturating_mul(order.len());
    let mut open: [Vec<usize>; 2] = [Vec::new(), Vec::new()];
    for (x0, l, i) in order {
        let s = &lists[l][i];
        let other = if within { l } else { 1 - l };
        budget = match budget.checked_sub(open[other].len()) {
            Some(b) => b,
            None => return false,
        };
        open[other].retain(|&j| lists[other][j].x1 >= x0 - NEAR_MM);
        for &j in &open[other] {
            let t = &lists[other][j];
            if t.y0 > s.y1 + NEAR_MM || s.y0 > t.y1 + NEAR_MM {
                continue;
            }
            let go = if l == 0 { pair(s, t) } else { pair(t, s) };
            if !go {
                return true;
            }
        }
        open[l].push(i);
    }
    true
}

/// What the sweep learned of one shape's sides against the other's.
struct Contacts {
    /// Per ring, per side: whether the other shape has the same side.
    shared: Vec<Vec<bool>>,
    /// Per ring, per point: whether the other shape's outline passes through it.
    touched: Vec<Vec<bool>>,
}

impl Contacts {
    fn of(f: &Filled<'_>) -> Self {
        Contacts {
            shared: f.rings.iter().map(|r| vec![false; r.len()]).collect(),
            touched: f.rings.iter().map(|r| vec![false; r.len()]).collect(),
        }
    }

    /// Marks the end `c` of side `s` as touched.
    fn touch(&mut self, s: &Side, c: Point) {
        let n = self.touched[s.ring].len();
        let at = if s.a == c { s.side } else { (s.side + 1) % n };
        self.touched[s.ring][at] = true;
    }

    fn share(&mut self, s: &Side) {
        self.shared[s.ring][s.side] = true;
        let n = self.touched[s.ring].len();
        self.touched[s.ring][s.side] = true;
        self.touched[s.ring][(s.side + 1) % n] = true;
    }

    /// Whether every run of unshared sides of `f` between touched points lies
    /// outside `other` (one point of each tested), within [`MAX_RUNS`] runs.
    fn runs_outside(&self, f: &Filled<'_>, other: &Filled<'_>) -> bool {
        let mut runs = 0;
        for (k, ring) in f.rings.iter().enumerate() {
            let n = ring.len();
            let (shared, touched) = (&self.shared[k], &self.touched[k]);
            let any_touch = touched.iter().any(|&t| t);
            for i in 0..n {
                // A run starts at an unshared side from a touched point (or,
                // on a ring the other outline never touches, at its first side).
                let starts = !shared[i] && if any_touch { touched[i] } else { i == 0 };
                if !starts {
                    continue;
                }
                runs += 1;
                if runs > MAX_RUNS {
                    return false;
                }
                let (a, b) = (ring[i], ring[(i + 1) % n]);
                let mid = (a.0 + (b.0 - a.0) / 2.0, a.1 + (b.1 - a.1) / 2.0);
                if contains(other.outline, mid, other.rule) {
                    return false;
                }
            }
        }
        true
    }
}

/// Whether the insides of `a` and `b` (each filled by its rule) certainly do
/// not meet; `false` when they may (see the module's note).
pub(crate) fn apart(a: &Filled<'_>, b: &Filled<'_>) -> bool {
    if !(a.finite && b.finite) {
        return false;
    }
    let (Some(ba), Some(bb)) = (a.bounds, b.bounds) else { return true };
    let c = super::common_bounds(ba, bb);
    let common = (c.0 - NEAR_MM, c.1 - NEAR_MM, c.2 + NEAR_MM, c.3 + NEAR_MM);
    if common.0 > common.2 || common.1 > common.3 {
        return true;
    }
    let near = |f: &Filled<'_>| -> Vec<Side> {
        f.rings.iter().enumerate().flat_map(|(k, r)| sides_in(r, k, Some(common))).collect()
    };
    let (sa, sb) = (near(a), near(b));
    let (mut ca, mut cb) = (Contacts::of(a), Contacts::of(b));
    // Each shared side: whether it runs the same way in both.
    let mut shared_ways: Vec<bool> = Vec::new();
    let mut meet = false;
    let swept = sweep(&sa, &sb, |s, t| {
        if (s.a == t.a && s.b == t.b) || (s.a == t.b && s.b == t.a) {
            ca.share(s);
            cb.share(t);
            shared_ways.push(s.a == t.a);
        } else if let Some((c, _, _)) = shared_end(s, t) {
            // Two sides from a shared point at an angle too small for the
            // runs' test points to lie clearly on one side may meet.
            if folds_back(s, t) {
                meet = true;
            } else {
                ca.touch(s, c);
                cb.touch(t, c);
            }
        } else if segment_distance(s.a, s.b, t.a, t.b) <= NEAR_MM {
            meet = true;
        }
        !meet
    });
    if meet || !swept {
        return false;
    }
    if !shared_ways.is_empty() {
        // Inside on the left of its sides when the area is positive.
        let (Some(ka), Some(kb)) = (a.simple_sign(), b.simple_sign()) else { return false };
        if shared_ways.iter().any(|&same| if same { ka == kb } else { ka != kb }) {
            return false;
        }
    }
    ca.runs_outside(a, b) && cb.runs_outside(b, a)
}

#[cfg(test)]
mod tests;
