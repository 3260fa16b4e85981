//! The area a fill covers under its fill rule, in bounded work.
//!
//! A boolean overlay gives the exact area of any outline, but its work and
//! memory follow the number of self-crossings, which a hand-drawn scribble or
//! a noisy plotted area can have by the million (a 30,000-segment random
//! path: some 10^8 crossings, 16 GB). This measures the area by sweeping
//! horizontal rows instead: along a row the covered length is exact (the
//! crossings sorted, the winding counted under the rule), and the rows are
//! integrated.
//!
//! Between two consecutive vertex heights an outline that does not cross
//! itself covers a length linear in `y`, so one row at the middle of each such
//! slab integrates it exactly: for the outlines of real drawings (regions,
//! circles, marks) the result is exact up to rounding. Where the slabs would
//! cost more than [`AREA_WORK`] crossings, the rows are spaced evenly, as many
//! as the budget allows (at least [`MIN_EVEN_ROWS`]): the midpoint rule's
//! approximation, within a row's height times the outline's width, and the
//! work stays within [`AREA_WORK`] whatever the outline, but for an outline
//! that crosses every row more than `AREA_WORK / MIN_EVEN_ROWS` times.

use super::{FillRule, Polyline};

/// Most row crossings one area may take before its rows are spaced evenly.
/// (At 4 million, the area of a 3,000-segment scribble, 4,000 rows of 1,000
/// crossings each, was 0.17 s of its 0.25 s build, on one core; at 1 million
/// it is 1,000 rows, within 0.02 % of that, and the build takes 0.10 s. The
/// automatic sheet compares areas with shares of the page.)
pub const AREA_WORK: usize = 1_000_000;
/// Fewest rows over the outline's height (slabs are split into rows no
/// taller than its share).
const MIN_ROWS: usize = 256;
/// Fewest evenly spaced rows, whatever the work. (At 256, a 300,000-segment
/// scribble, 100,000 crossings a row, took 26 million sorted crossings, over
/// a second, for each area the automatic sheet asked of it.)
const MIN_EVEN_ROWS: usize = 32;
/// Most evenly spaced rows.
const MAX_ROWS: usize = 4096;

/// One non-horizontal edge: its lower and upper `y`, the `x` at the lower
/// end, `dx/dy`, and its direction (+1 upward in `y`).
#[derive(Clone, Copy)]
struct Edge {
    y0: f64,
    y1: f64,
    x0: f64,
    slope: f64,
    dir: i32,
    /// The `x` at the upper end, exactly as the outline has it.
    x1: f64,
}

impl Edge {
    /// The `x` at height `y` within the edge, its ends' own at its ends (so
    /// that two edges meeting at a vertex meet there to the bit).
    fn x_at(&self, y: f64) -> f64 {
        if y <= self.y0 {
            self.x0
        } else if y >= self.y1 {
            self.x1
        } else {
            self.x0 + (y - self.y0) * self.slope
        }
    }
}

/// The area, in mm², that the shape whose subpaths are `pls` (each closed
/// implicitly, as SVG fills are) covers under `rule`.
///
/// ```
/// use taxel_compiler::geometry::{FillRule, Polyline, filled_area};
///
/// let square = |o: f64| Polyline { points: vec![(o, 0.0), (o + 10.0, 0.0), (o + 10.0, 10.0), (o, 10.0)], closed: true };
/// // Two squares overlapping by half: 150 mm² under either rule's union...
/// assert!((filled_area(&[square(0.0), square(5.0)], FillRule::NonZero) - 150.0).abs() < 1e-9);
/// // ...and the overlap is a hole under even-odd.
/// assert!((filled_area(&[square(0.0), square(5.0)], FillRule::EvenOdd) - 100.0).abs() < 1e-9);
/// ```
pub fn filled_area(pls: &[Polyline], rule: FillRule) -> f64 {
    area_in(pls, rule, None)
}

/// The area, in mm², that the shape covers under `rule` inside the box
/// `(x0, y0, x1, y1)`: the same sweep with each row's covered spans cut to
/// the box and the rows to its height. Exact in the same sense as
/// [`filled_area`]: the slabs also break where an edge crosses the box's
/// sides, so that the covered length stays linear within each. (No ring is
/// clipped: a clipped scribble would still cross itself as often, and an
/// overlay's work follows its crossings.)
///
/// ```
/// use taxel_compiler::geometry::{FillRule, Polyline, filled_area_within};
///
/// // A diamond of area 200 mm², half of it right of x = 10.
/// let diamond = Polyline { points: vec![(10.0, 0.0), (20.0, 10.0), (10.0, 20.0), (0.0, 10.0)], closed: true };
/// let right = filled_area_within(&[diamond], FillRule::NonZero, (10.0, -5.0, 30.0, 25.0));
/// assert!((right - 100.0).abs() < 1e-9);
/// ```
pub fn filled_area_within(pls: &[Polyline], rule: FillRule, window: (f64, f64, f64, f64)) -> f64 {
    area_in(pls, rule, Some(window))
}

/// [`filled_area`], within `window` where there is one.
fn area_in(pls: &[Polyline], rule: FillRule, window: Option<(f64, f64, f64, f64)>) -> f64 {
    let mut edges: Vec<Edge> = Vec::with_capacity(pls.iter().map(|p| p.points.len()).sum());
    for pl in pls {
        let n = pl.points.len();
        if n < 3 {
            continue;
        }
        for i in 0..n {
            let (a, b) = (pl.points[i], pl.points[(i + 1) % n]);
            if !(a.0.is_finite() && a.1.is_finite() && b.0.is_finite() && b.1.is_finite()) || a.1 == b.1 {
                continue;
            }
            let (lo, hi, dir) = if a.1 < b.1 { (a, b, 1) } else { (b, a, -1) };
            edges.push(Edge { y0: lo.1, y1: hi.1, x0: lo.0, slope: (hi.0 - lo.0) / (hi.1 - lo.1), dir, x1: hi.0 });
        }
    }
    if edges.is_empty() {
        return 0.0;
    }
    edges.sort_by(|a, b| a.y0.total_cmp(&b.y0));
    let rows = rows_of(&edges, window);
    let xs = window.map_or((f64::NEG_INFINITY, f64::INFINITY), |w| (w.0, w.2));
    sweep(&edges, &rows, rule, xs)
}

/// The rows `(y, weight)` to integrate over: the slabs' midpoints where they
/// fit the budget, else evenly spaced rows.
fn rows_of(edges: &[Edge], window: Option<(f64, f64, f64, f64)>) -> Vec<(f64, f64)> {
    let mut ys: Vec<f64> = edges.iter().flat_map(|e| [e.y0, e.y1]).collect();
    if let Some((x0, y0, x1, y1)) = window {
        // Where an edge crosses the window's sides, the covered length within
        // it bends: those heights are slab ends too. The window's own top and
        // bottom bound the rows.
        for e in edges {
            for x in [x0, x1] {
                let y = e.y0 + (x - e.x0) / e.slope;
                if e.slope != 0.0 && y > e.y0 && y < e.y1 {
                    ys.push(y);
                }
            }
        }
        ys.extend([y0, y1]);
        ys.retain(|&y| y >= y0 && y <= y1);
        if ys.len() < 2 {
            return Vec::new();
        }
    }
    ys.sort_by(f64::total_cmp);
    ys.dedup();
    let (lo, hi) = (ys[0], ys[ys.len() - 1]);
    let height = hi - lo;
    // Each slab split into rows of at most 1/MIN_ROWS of the height: exact
    // still where the length is linear, and where the outline crosses itself
    // (the length bends inside a slab) the midpoint rule's error shrinks with
    // the square of the rows' height.
    let split = |w: f64| ((w / height * MIN_ROWS as f64).ceil() as usize).max(1);
    let mut first_row = Vec::with_capacity(ys.len());
    let mut total = 0usize;
    for w in ys.windows(2) {
        first_row.push(total);
        total += split(w[1] - w[0]);
    }
    first_row.push(total);
    // Rows each edge spans: those of the slabs between its ends (within
    // the window's rows: an edge past them spans its last).
    let row_at = |y: f64| first_row[ys.partition_point(|&v| v < y).min(ys.len() - 1)];
    let slab_work: usize = edges.iter().map(|e| row_at(e.y1) - row_at(e.y0)).sum();
    if slab_work <= AREA_WORK {
        // A slab no two edges cross inside needs only its middle row: the
        // length is linear there. Splitting every slab took 256 rows or
        // more for each small island of a world map, most of the time
        // the automatic sheet spent on it (issue 46).
        let crossed = crossed_slabs(edges, &ys);
        return ys
            .windows(2)
            .zip(crossed)
            .flat_map(|(w, crossed)| {
                let k = if crossed { split(w[1] - w[0]) } else { 1 };
                let dy = (w[1] - w[0]) / k as f64;
                (0..k).map(move |i| (w[0] + (i as f64 + 0.5) * dy, dy))
            })
            .collect();
    }
    // Rows an edge spans out of `n` evenly spaced ones: about `n` times its share of the height.
    let share: f64 = edges.iter().map(|e| (e.y1 - e.y0) / height).sum();
    let n = ((AREA_WORK as f64 / share.max(1e-9)) as usize).clamp(MIN_EVEN_ROWS, MAX_ROWS);
    let dy = height / n as f64;
    (0..n).map(|k| (lo + (k as f64 + 0.5) * dy, dy)).collect()
}

/// For each slab `ys[k]..ys[k + 1]` (heights that hold every edge's ends,
/// ascending, `edges` sorted by their lower end), whether two edges spanning
/// it cross inside it: their order along the slab's bottom (ties broken by
/// the top) is not their order along its top. Work within the rows' own,
/// as every slab has a row for each edge spanning it.
fn crossed_slabs(edges: &[Edge], ys: &[f64]) -> Vec<bool> {
    let mut active: Vec<Edge> = Vec::new();
    let mut next = 0;
    let mut ends: Vec<(f64, f64)> = Vec::new();
    ys.windows(2)
        .map(|w| {
            let (lo, hi) = (w[0], w[1]);
            let mid = lo + (hi - lo) / 2.0;
            while next < edges.len() && edges[next].y0 <= mid {
                active.push(edges[next]);
                next += 1;
            }
            active.retain(|e| e.y1 > mid);
            ends.clear();
            ends.extend(active.iter().map(|e| (e.x_at(lo), e.x_at(hi))));
            ends.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
            ends.windows(2).any(|p| p[1].1 < p[0].1)
        })
        .collect()
}

/// The covered length of each row under `rule`, times its weight, summed.
/// `edges` are sorted by their lower end and `rows` ascend.
fn sweep(edges: &[Edge], rows: &[(f64, f64)], rule: FillRule, (x0, x1): (f64, f64)) -> f64 {
    let mut active: Vec<Edge> = Vec::new();
    let mut next = 0;
    let mut xs: Vec<(f64, i32)> = Vec::new();
    let mut total = 0.0;
    for &(y, weight) in rows {
        while next < edges.len() && edges[next].y0 <= y {
            active.push(edges[next]);
            next += 1;
        }
        // Half-open spans `[y0, y1)`: a vertex on the row counts once.
        active.retain(|e| e.y1 > y);
        xs.clear();
        xs.extend(active.iter().map(|e| (e.x0 + (y - e.y0) * e.slope, e.dir)));
        xs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (mut winding, mut crossings) = (0i32, 0u32);
        for pair in xs.windows(2) {
            winding += pair[0].1;
            crossings += 1;
            let inside = match rule {
                FillRule::NonZero => winding != 0,
                FillRule::EvenOdd => crossings % 2 == 1,
            };
            if inside {
                // Cut to the window (a whole row's span where there is none).
                let (a, b) = (pair[0].0.max(x0), pair[1].0.min(x1));
                if b > a {
                    total += (b - a) * weight;
                }
            }
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniform numbers in `[0, scale)` from a xorshift generator seeded with `seed`.
    fn uniform(mut s: u64, scale: f64) -> impl FnMut() -> f64 {
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 * scale
        }
    }

    fn ring(points: &[(f64, f64)]) -> Polyline {
        Polyline { points: points.to_vec(), closed: true }
    }

    /// The shoelace formula: the exact area of a ring that does not cross itself.
    fn shoelace(points: &[(f64, f64)]) -> f64 {
        let n = points.len();
        (0..n).map(|i| points[i].0 * points[(i + 1) % n].1 - points[(i + 1) % n].0 * points[i].1).sum::<f64>().abs()
            / 2.0
    }

    #[test]
    fn a_ring_that_does_not_cross_itself_is_measured_exactly() {
        // A 257-gon of radius 3 and a concave star: the slabs integrate both exactly.
        let circle: Vec<_> = (0..257)
            .map(|k| {
                let a = k as f64 / 257.0 * std::f64::consts::TAU;
                (10.0 + 3.0 * a.cos(), 20.0 + 3.0 * a.sin())
            })
            .collect();
        let star: Vec<_> = (0..10)
            .map(|k| {
                let a = k as f64 / 10.0 * std::f64::consts::TAU;
                let r = if k % 2 == 0 { 5.0 } else { 2.0 };
                (r * a.cos(), r * a.sin())
            })
            .collect();
        for pts in [circle, star] {
            for rule in [FillRule::NonZero, FillRule::EvenOdd] {
                let got = filled_area(&[ring(&pts)], rule);
                assert!((got - shoelace(&pts)).abs() < 1e-9 * shoelace(&pts), "{got} against {}", shoelace(&pts));
            }
        }
    }

    #[test]
    fn the_rules_differ_where_the_outline_winds_twice() {
        // A pentagram: its centre pentagon is wound twice, a hole under even-odd.
        let pts: Vec<_> = (0..5)
            .map(|k| {
                let a = (k * 2) as f64 / 5.0 * std::f64::consts::TAU;
                (10.0 * a.sin(), -10.0 * a.cos())
            })
            .collect();
        let (nonzero, evenodd) =
            (filled_area(&[ring(&pts)], FillRule::NonZero), filled_area(&[ring(&pts)], FillRule::EvenOdd));
        // The inner pentagon's vertices: where the star's edges cross, at radius r cos(72°)/cos(36°).
        let inner_r = 10.0 * (72f64.to_radians().cos() / 36f64.to_radians().cos());
        let inner: Vec<_> = (0..5)
            .map(|k| {
                let a = (k as f64 + 0.5) / 5.0 * std::f64::consts::TAU;
                (inner_r * a.sin(), -inner_r * a.cos())
            })
            .collect();
        let hole = shoelace(&inner);
        assert!((nonzero - evenodd - hole).abs() < 1e-3 * hole, "{nonzero} - {evenodd} against {hole}");
    }

    #[test]
    fn degenerate_outlines_cover_nothing() {
        assert_eq!(filled_area(&[], FillRule::NonZero), 0.0);
        assert_eq!(filled_area(&[ring(&[(0.0, 0.0), (5.0, 5.0)])], FillRule::NonZero), 0.0);
        assert_eq!(filled_area(&[ring(&[(0.0, 0.0), (5.0, 5.0), (10.0, 10.0)])], FillRule::NonZero), 0.0);
        assert_eq!(filled_area(&[ring(&[(0.0, 0.0), (f64::NAN, 5.0), (10.0, 0.0)])], FillRule::NonZero), 0.0);
    }

    #[test]
    fn a_scribble_is_measured_in_bounded_work_close_to_its_area() {
        // 3,000 random segments over a 100 mm square: far over the budget
        // for slabs, so evenly spaced rows; the reference is the winding
        // rule sampled on a fine grid.
        let mut next = uniform(0x2545_f491_4f6c_dd1d_u64, 100.0);
        let pts: Vec<_> = (0..3_000).map(|_| (next(), next())).collect();
        let shape = [ring(&pts)];
        for rule in [FillRule::NonZero, FillRule::EvenOdd] {
            let got = filled_area(&shape, rule);
            let n = 150;
            let cell = 100.0 / n as f64;
            let mut inside = 0usize;
            for j in 0..n {
                for i in 0..n {
                    let p = ((i as f64 + 0.37) * cell, (j as f64 + 0.61) * cell);
                    inside += usize::from(crate::geometry::contains(&shape, p, rule));
                }
            }
            let sampled = inside as f64 * cell * cell;
            assert!((got - sampled).abs() < 0.02 * 10_000.0, "{rule:?}: {got} against {sampled} sampled");
        }
    }

    fn edges_of(points: &[(f64, f64)]) -> Vec<Edge> {
        let n = points.len();
        let mut edges: Vec<Edge> = (0..n)
            .filter_map(|i| {
                let (a, b) = (points[i], points[(i + 1) % n]);
                let (lo, hi, dir) = if a.1 < b.1 { (a, b, 1) } else { (b, a, -1) };
                (a.1 != b.1).then(|| Edge {
                    y0: lo.1,
                    y1: hi.1,
                    x0: lo.0,
                    slope: (hi.0 - lo.0) / (hi.1 - lo.1),
                    dir,
                    x1: hi.0,
                })
            })
            .collect();
        edges.sort_by(|a, b| a.y0.total_cmp(&b.y0));
        edges
    }

    /// The slabs found crossed are those where some pair of edges spanning
    /// the slab swaps sides between its bottom and its top.
    #[test]
    fn crossed_slabs_are_those_a_pairwise_check_finds() {
        let mut next = uniform(0x9e37_79b9_7f4a_7c15, 100.0);
        for n in [3, 5, 12, 40, 150] {
            let pts: Vec<_> = (0..n).map(|_| (next(), next())).collect();
            let edges = edges_of(&pts);
            let mut ys: Vec<f64> = edges.iter().flat_map(|e| [e.y0, e.y1]).collect();
            ys.sort_by(f64::total_cmp);
            ys.dedup();
            let got = crossed_slabs(&edges, &ys);
            let x_at = |e: &Edge, y: f64| e.x_at(y);
            for (k, w) in ys.windows(2).enumerate() {
                let spanning: Vec<&Edge> = edges.iter().filter(|e| e.y0 <= w[0] && e.y1 >= w[1]).collect();
                let pairwise = spanning.iter().enumerate().any(|(i, a)| {
                    spanning[i + 1..]
                        .iter()
                        .any(|b| (x_at(a, w[0]) - x_at(b, w[0])) * (x_at(a, w[1]) - x_at(b, w[1])) < 0.0)
                });
                assert_eq!(got[k], pairwise, "{n} points, slab {k}");
            }
        }
        // A ring that does not cross itself has no crossed slab.
        let star: Vec<_> = (0..9)
            .map(|k| {
                let (a, r) = (k as f64 / 9.0 * std::f64::consts::TAU, if k % 2 == 0 { 10.0 } else { 4.0 });
                (r * a.cos(), r * a.sin())
            })
            .collect();
        let edges = edges_of(&star);
        let mut ys: Vec<f64> = edges.iter().flat_map(|e| [e.y0, e.y1]).collect();
        ys.sort_by(f64::total_cmp);
        ys.dedup();
        assert!(crossed_slabs(&edges, &ys).iter().all(|&c| !c));
    }

    /// Splitting only the crossed slabs gives the area that splitting every
    /// slab into rows of at most 1/`MIN_ROWS` of the height gave, up to
    /// rounding, for outlines that cross themselves and outlines that do not.
    #[test]
    fn only_crossed_slabs_are_split_and_the_area_is_the_same() {
        let mut next = uniform(0x1234_5678_9abc_def1, 50.0);
        for n in [4, 9, 30, 120] {
            let pts: Vec<_> = (0..n).map(|_| (next(), next())).collect();
            let edges = edges_of(&pts);
            let mut ys: Vec<f64> = edges.iter().flat_map(|e| [e.y0, e.y1]).collect();
            ys.sort_by(f64::total_cmp);
            ys.dedup();
            let height = ys[ys.len() - 1] - ys[0];
            let every: Vec<(f64, f64)> = ys
                .windows(2)
                .flat_map(|w| {
                    let k = ((w[1] - w[0]) / height * MIN_ROWS as f64).ceil().max(1.0) as usize;
                    let dy = (w[1] - w[0]) / k as f64;
                    (0..k).map(move |i| (w[0] + (i as f64 + 0.5) * dy, dy))
                })
                .collect();
            let rows = rows_of(&edges, None);
            assert!(rows.len() <= every.len());
            for rule in [FillRule::NonZero, FillRule::EvenOdd] {
                let (new, old) = (
                    sweep(&edges, &rows, rule, (f64::NEG_INFINITY, f64::INFINITY)),
                    sweep(&edges, &every, rule, (f64::NEG_INFINITY, f64::INFINITY)),
                );
                assert!((new - old).abs() <= 1e-9 * old.max(1.0), "{n} points {rule:?}: {new} against {old}");
            }
        }
        let square = [(0.0, 0.0), (3.0, 0.5), (2.5, 3.5), (-0.5, 3.0)];
        assert_eq!(rows_of(&edges_of(&square), None).len(), 3, "one row per slab");
    }

    /// The crossings the rows of [`rows_of`] take (the edges each row
    /// meets, half-open as the sweep counts them).
    fn work(edges: &[Edge], rows: &[(f64, f64)]) -> usize {
        rows.iter().map(|&(y, _)| edges.iter().filter(|e| e.y0 <= y && y < e.y1).count()).sum()
    }

    #[test]
    fn a_dense_scribble_takes_at_most_the_work_budget() {
        // 60,000 random segments over a 100 mm square cross each row some
        // 20,000 times: 256 rows would be five times the budget.
        let mut next = uniform(0x9e37_79b9_7f4a_7c15_u64, 100.0);
        let pts: Vec<_> = (0..60_000).map(|_| (next(), next())).collect();
        let edges = edges_of(&pts);
        let rows = rows_of(&edges, None);
        assert!(rows.len() >= MIN_EVEN_ROWS, "{} rows", rows.len());
        let w = work(&edges, &rows);
        assert!(w <= AREA_WORK, "{w} crossings in {} rows", rows.len());
        // And the area is still close to the sampled winding rule's.
        let shape = [ring(&pts)];
        let got = filled_area(&shape, FillRule::EvenOdd);
        let n = 100;
        let cell = 100.0 / n as f64;
        let inside: usize = (0..n * n)
            .map(|k| ((k % n) as f64 + 0.37, (k / n) as f64 + 0.61))
            .filter(|&(i, j)| crate::geometry::contains(&shape, (i * cell, j * cell), FillRule::EvenOdd))
            .count();
        let sampled = inside as f64 * cell * cell;
        assert!((got - sampled).abs() < 0.03 * 10_000.0, "{got} against {sampled} sampled");
    }

    /// The area of a simple ring inside a box, independently: the ring
    /// clipped to the box side by side (Sutherland and Hodgman, exact for a
    /// convex window), then the shoelace formula.
    fn clipped_shoelace(points: &[(f64, f64)], (x0, y0, x1, y1): (f64, f64, f64, f64)) -> f64 {
        let mut ring = points.to_vec();
        let sides: [&dyn Fn((f64, f64)) -> f64; 4] = [&|p| p.0 - x0, &|p| p.1 - y0, &|p| x1 - p.0, &|p| y1 - p.1];
        for f in sides {
            let n = ring.len();
            let mut next = Vec::new();
            for k in 0..n {
                let (a, c) = (ring[k], ring[(k + 1) % n]);
                if f(a) >= 0.0 {
                    next.push(a);
                }
                if (f(a) >= 0.0) != (f(c) >= 0.0) {
                    let t = f(a) / (f(a) - f(c));
                    next.push((a.0 + t * (c.0 - a.0), a.1 + t * (c.1 - a.1)));
                }
            }
            ring = next;
        }
        if ring.len() < 3 { 0.0 } else { shoelace(&ring) }
    }

    #[test]
    fn the_area_within_a_box_is_exact_for_rings_that_do_not_cross_themselves() {
        let mut next = uniform(0x0123_4567_89ab_cdef_u64, 1.0);
        for _ in 0..200 {
            // A star-shaped ring (so simple) of 3 to 40 points round (50, 50).
            let n = 3 + (next() * 38.0) as usize;
            let pts: Vec<(f64, f64)> = (0..n)
                .map(|k| {
                    let a = (k as f64 + 0.8 * next()) / n as f64 * std::f64::consts::TAU;
                    let r = 5.0 + 40.0 * next();
                    (50.0 + r * a.cos(), 50.0 + r * a.sin())
                })
                .collect();
            let (xa, xb, ya, yb) = (next() * 100.0, next() * 100.0, next() * 100.0, next() * 100.0);
            let window = (xa.min(xb), ya.min(yb), xa.max(xb), ya.max(yb));
            let want = clipped_shoelace(&pts, window);
            for rule in [FillRule::NonZero, FillRule::EvenOdd] {
                let got = filled_area_within(&[ring(&pts)], rule, window);
                assert!(
                    (got - want).abs() <= 1e-9 * shoelace(&pts),
                    "{got} against {want}, window {window:?}, {pts:?}"
                );
            }
        }
        // A box that holds it all is the whole area, to the bit; one beside it, nothing.
        let pts = [(0.0, 0.0), (10.0, 0.0), (3.0, 8.0)];
        assert_eq!(
            filled_area_within(&[ring(&pts)], FillRule::NonZero, (-1.0, -1.0, 11.0, 9.0)),
            filled_area(&[ring(&pts)], FillRule::NonZero)
        );
        assert_eq!(filled_area_within(&[ring(&pts)], FillRule::NonZero, (20.0, 0.0, 30.0, 9.0)), 0.0);
    }
}
