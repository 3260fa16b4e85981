//! The planar arrangement of projected mesh edges, so that the constrained
//! triangulation never has to split a constraint itself.
//!
//! Why: spade's `add_constraint_and_split` computes each crossing in floating
//! point and then repairs the triangulation around a point that lies only
//! near both edges. With exactly collinear, overlapping or T-shaped
//! constraints — what touching blocks that share walls give — that repair
//! fails spade's own assertions (`cdt.rs`: "!previous_region.is_empty()",
//! `is_ordered_ccw`); random constraint sets on a small lattice hit it about
//! once in six. Its bulk loader never fails: it only reports the edges it
//! could not insert. So the arrangement is made here, in exact integer
//! arithmetic, and the bulk loader only ever sees edges that neither cross
//! nor touch except at shared end points.
//!
//! Vertices are first snapped to a power-of-two grid of about 2⁻³⁰ of the
//! footprint (far below the f32 precision of glTF positions, 2⁻²⁴), which
//! merges near-duplicate vertices and makes every position an exact integer.
//! Orientation tests on these integers are exact (i128). A crossing point is
//! rounded to the grid; that rounding can, rarely, create a new crossing a
//! grid step long, which the next round of the same procedure splits.

use std::collections::HashMap;

use super::error::MeshError;

/// Grid steps across the footprint: 2³⁰, so coordinates fit in 31 bits and
/// every product of the orientation test in 64.
const SNAP_STEPS: f64 = (1u64 << 30) as f64;

/// The snapping grid: an origin on the grid and a power-of-two step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Snap {
    ox: f64,
    oy: f64,
    q: f64,
}

impl Snap {
    /// The grid for a footprint `[xmin, ymin, xmax, ymax]` (finite).
    pub fn new(bbox: [f64; 4]) -> Snap {
        let extent = (bbox[2] - bbox[0]).max(bbox[3] - bbox[1]).max(f64::MIN_POSITIVE);
        // The smallest power of two with extent / q <= 2^30.
        let q = 2f64.powi((extent / SNAP_STEPS).log2().ceil().clamp(-1000.0, 1000.0) as i32).max(f64::MIN_POSITIVE);
        Snap { ox: (bbox[0] / q).floor() * q, oy: (bbox[1] / q).floor() * q, q }
    }

    /// The grid step in mm.
    #[cfg(test)]
    pub fn step(&self) -> f64 {
        self.q
    }

    /// The nearest grid point, as integers.
    pub fn to_grid(self, x: f64, y: f64) -> [i64; 2] {
        [((x - self.ox) / self.q).round() as i64, ((y - self.oy) / self.q).round() as i64]
    }

    /// A grid point in mm; exact, since the origin is a multiple of the power-of-two step.
    pub fn to_mm(self, p: [i64; 2]) -> [f64; 2] {
        [self.ox + p[0] as f64 * self.q, self.oy + p[1] as f64 * self.q]
    }
}

/// Sign of the turn `a -> b -> c`: positive counter-clockwise, exact.
pub(super) fn orient(a: [i64; 2], b: [i64; 2], c: [i64; 2]) -> i128 {
    let (abx, aby) = ((b[0] - a[0]) as i128, (b[1] - a[1]) as i128);
    let (acx, acy) = ((c[0] - a[0]) as i128, (c[1] - a[1]) as i128);
    abx * acy - aby * acx
}

/// Position of `p` along `a -> b` as the dot product with the direction
/// (0 at `a`, |ab|² at `b`).
pub(super) fn along(a: [i64; 2], b: [i64; 2], p: [i64; 2]) -> i128 {
    (b[0] - a[0]) as i128 * (p[0] - a[0]) as i128 + (b[1] - a[1]) as i128 * (p[1] - a[1]) as i128
}

/// Whether `p`, collinear with `a -> b`, lies strictly between them.
fn strictly_inside(a: [i64; 2], b: [i64; 2], p: [i64; 2]) -> bool {
    let t = along(a, b, p);
    t > 0 && t < along(a, b, b)
}

/// `num / den` rounded to the nearest integer (den != 0).
fn div_round(num: i128, den: i128) -> i128 {
    let (num, den) = if den < 0 { (-num, -den) } else { (num, den) };
    (2 * num + den).div_euclid(2 * den)
}

/// The crossing of `a -> b` and `c -> d` (known to cross properly), rounded to the grid.
fn crossing(a: [i64; 2], b: [i64; 2], c: [i64; 2], d: [i64; 2]) -> [i64; 2] {
    let (rx, ry) = ((b[0] - a[0]) as i128, (b[1] - a[1]) as i128);
    let (sx, sy) = ((d[0] - c[0]) as i128, (d[1] - c[1]) as i128);
    let den = rx * sy - ry * sx;
    let num = (c[0] - a[0]) as i128 * sy - (c[1] - a[1]) as i128 * sx;
    // |num|, |den| < 2^64 and |r| < 2^32, so the products fit in i128.
    [(a[0] as i128 + div_round(num * rx, den)) as i64, (a[1] as i128 + div_round(num * ry, den)) as i64]
}

/// The points of an arrangement: integer positions without duplicates.
#[derive(Debug, Default, Clone)]
pub struct Points {
    /// Positions, in insertion order.
    pub at: Vec<[i64; 2]>,
    index: HashMap<[i64; 2], u32>,
}

impl Points {
    /// The index of `p`, adding it when new.
    pub fn add(&mut self, p: [i64; 2]) -> u32 {
        *self.index.entry(p).or_insert_with(|| {
            self.at.push(p);
            (self.at.len() - 1) as u32
        })
    }
}

/// A uniform grid of about two cells per item a side over the integer box
/// `lo..=hi`, for finding which items' boxes may meet.
pub(super) struct BoxGrid {
    lo: [i64; 2],
    hi: [i64; 2],
    /// Cells along each side.
    pub(super) side: i64,
    cw: i64,
    ch: i64,
}

impl BoxGrid {
    pub(super) fn new(lo: [i64; 2], hi: [i64; 2], items: usize) -> Self {
        let side = ((items as f64).sqrt() * 2.0).clamp(1.0, 512.0) as i64;
        let cw = ((hi[0] - lo[0]) / side + 1).max(1);
        let ch = ((hi[1] - lo[1]) / side + 1).max(1);
        BoxGrid { lo, hi, side, cw, ch }
    }

    /// The cells `[x0, y0, x1, y1]` (inclusive) that box `[x0, y0, x1, y1]`
    /// covers, or `None` when it misses the grid.
    pub(super) fn cells(&self, b: [i64; 4]) -> Option<[i64; 4]> {
        let (lo, hi) = (self.lo, self.hi);
        if b[2] < lo[0] || b[3] < lo[1] || b[0] > hi[0] || b[1] > hi[1] {
            return None;
        }
        Some([
            (b[0].max(lo[0]) - lo[0]) / self.cw,
            (b[1].max(lo[1]) - lo[1]) / self.ch,
            ((b[2].min(hi[0]) - lo[0]) / self.cw).min(self.side - 1),
            ((b[3].min(hi[1]) - lo[1]) / self.ch).min(self.side - 1),
        ])
    }
}

/// Splits every edge of `edges` that crosses or touches one of `suspects`
/// (in its interior), and each suspect likewise, at the crossing points
/// (rounded to the grid, added to `points`) and at the end points that lie
/// on the other edge. Returns the new edge list, sorted and without
/// duplicates or zero-length edges. `work` bounds the pair tests.
pub fn split(
    points: &mut Points,
    edges: &[[u32; 2]],
    suspects: &[[u32; 2]],
    work: usize,
) -> Result<Vec<[u32; 2]>, MeshError> {
    let pos = |points: &Points, i: u32| points.at.get(i as usize).copied().unwrap_or([0, 0]);
    let bbox = |e: [u32; 2]| {
        let (a, b) = (pos(points, e[0]), pos(points, e[1]));
        [a[0].min(b[0]), a[1].min(b[1]), a[0].max(b[0]), a[1].max(b[1])]
    };
    // A uniform grid over the suspects' boxes, about two cells per suspect a side.
    let mut lo = [i64::MAX; 2];
    let mut hi = [i64::MIN; 2];
    for &s in suspects {
        let b = bbox(s);
        lo = [lo[0].min(b[0]), lo[1].min(b[1])];
        hi = [hi[0].max(b[2]), hi[1].max(b[3])];
    }
    if suspects.is_empty() {
        return Ok(edges.to_vec());
    }
    let grid = BoxGrid::new(lo, hi, suspects.len());
    let (side, cell_range) = (grid.side, |b| grid.cells(b));
    let mut cells: Vec<Vec<u32>> = vec![Vec::new(); (side * side) as usize];
    let mut budget = work;
    let mut spend = |n: usize| -> Result<(), MeshError> {
        budget = budget
            .checked_sub(n)
            .ok_or(MeshError::TooBig { what: "crossings between projected edges", limit: work })?;
        Ok(())
    };
    for (k, &s) in suspects.iter().enumerate() {
        let Some(r) = cell_range(bbox(s)) else { continue };
        spend(((r[2] - r[0] + 1) * (r[3] - r[1] + 1)) as usize)?;
        for cy in r[1]..=r[3] {
            for cx in r[0]..=r[2] {
                cells[(cy * side + cx) as usize].push(k as u32);
            }
        }
    }

    // Split points per edge (all edges first, then the suspects).
    let mut cuts: HashMap<[u32; 2], Vec<[i64; 2]>> = HashMap::new();
    let mut seen = vec![usize::MAX; suspects.len()];
    for (ei, &e) in edges.iter().enumerate() {
        let Some(r) = cell_range(bbox(e)) else { continue };
        spend(((r[2] - r[0] + 1) * (r[3] - r[1] + 1)) as usize)?;
        for cy in r[1]..=r[3] {
            for cx in r[0]..=r[2] {
                for &k in &cells[(cy * side + cx) as usize] {
                    let s = suspects[k as usize];
                    if seen[k as usize] == ei || s == e {
                        continue;
                    }
                    seen[k as usize] = ei;
                    spend(1)?;
                    let (a, b, c, d) = (pos(points, s[0]), pos(points, s[1]), pos(points, e[0]), pos(points, e[1]));
                    let (o1, o2) = (orient(a, b, c).signum(), orient(a, b, d).signum());
                    let (o3, o4) = (orient(c, d, a).signum(), orient(c, d, b).signum());
                    if o1 * o2 < 0 && o3 * o4 < 0 {
                        let p = crossing(a, b, c, d);
                        cuts.entry(s).or_default().push(p);
                        cuts.entry(e).or_default().push(p);
                        continue;
                    }
                    // Touching: an end point of one in the interior of the other
                    // (T-junctions and collinear overlaps).
                    for (on, p) in [(o1, c), (o2, d)] {
                        if on == 0 && strictly_inside(a, b, p) {
                            cuts.entry(s).or_default().push(p);
                        }
                    }
                    for (on, p) in [(o3, a), (o4, b)] {
                        if on == 0 && strictly_inside(c, d, p) {
                            cuts.entry(e).or_default().push(p);
                        }
                    }
                }
            }
        }
    }

    let mut out: Vec<[u32; 2]> = Vec::with_capacity(edges.len() + 2 * cuts.len());
    for &e in edges {
        let Some(ps) = cuts.get_mut(&e) else {
            out.push(e);
            continue;
        };
        let (a, b) = (pos(points, e[0]), pos(points, e[1]));
        ps.sort_unstable_by_key(|&p| along(a, b, p));
        ps.dedup();
        let mut prev = e[0];
        for &p in ps.iter() {
            let i = points.add(p);
            if i != prev {
                out.push([prev.min(i), prev.max(i)]);
            }
            prev = i;
        }
        if prev != e[1] {
            out.push([prev.min(e[1]), prev.max(e[1])]);
        }
    }
    out.sort_unstable();
    out.dedup();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arrangement(segs: &[[[i64; 2]; 2]]) -> (Points, Vec<[u32; 2]>) {
        let mut pts = Points::default();
        let edges: Vec<[u32; 2]> = segs.iter().map(|s| [pts.add(s[0]), pts.add(s[1])]).collect();
        let out = split(&mut pts, &edges, &edges, 1_000_000).unwrap();
        (pts, out)
    }

    fn named(pts: &Points, edges: &[[u32; 2]]) -> Vec<[[i64; 2]; 2]> {
        let mut v: Vec<[[i64; 2]; 2]> = edges
            .iter()
            .map(|e| {
                let (a, b) = (pts.at[e[0] as usize], pts.at[e[1] as usize]);
                if a <= b { [a, b] } else { [b, a] }
            })
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_cross_is_split_at_its_centre() {
        let (p, e) = arrangement(&[[[0, 0], [10, 10]], [[0, 10], [10, 0]]]);
        assert_eq!(named(&p, &e), vec![[[0, 0], [5, 5]], [[0, 10], [5, 5]], [[5, 5], [10, 0]], [[5, 5], [10, 10]]]);
    }

    #[test]
    fn collinear_overlaps_and_t_junctions_become_shared_pieces() {
        // Two walls along y = 0 overlapping on 4..10, and a third edge ending on the first.
        let (p, e) = arrangement(&[[[0, 0], [10, 0]], [[4, 0], [14, 0]], [[7, 0], [7, 5]]]);
        assert_eq!(
            named(&p, &e),
            vec![[[0, 0], [4, 0]], [[4, 0], [7, 0]], [[7, 0], [7, 5]], [[7, 0], [10, 0]], [[10, 0], [14, 0]]]
        );
    }

    #[test]
    fn a_rounded_crossing_lies_within_half_a_step_of_the_exact_one() {
        // Crossing of (0,0)-(7,3) and (0,3)-(7,0) is at (3.5, 1.5).
        let p = crossing([0, 0], [7, 3], [0, 3], [7, 0]);
        assert!((p[0] as f64 - 3.5).abs() <= 0.5 && (p[1] as f64 - 1.5).abs() <= 0.5, "{p:?}");
        assert_eq!(div_round(7, 2), 4);
        assert_eq!(div_round(-7, 2), -3);
        assert_eq!(div_round(7, -2), -3);
    }

    #[test]
    fn snapping_is_exact_and_merges_near_duplicates() {
        let s = Snap::new([1000.0, -5.0, 1100.0, 20.0]);
        // The smallest power of two that divides the 100 mm extent into at most 2^30 steps.
        assert!(s.step() >= 100.0 / SNAP_STEPS && s.step() < 200.0 / SNAP_STEPS, "{}", s.step());
        assert_eq!(s.step(), 2f64.powi(-23));
        let g = s.to_grid(1012.345, 3.25);
        let back = s.to_mm(g);
        assert!((back[0] - 1012.345).abs() <= s.step() / 2.0 && (back[1] - 3.25).abs() <= s.step() / 2.0);
        assert_eq!(s.to_grid(back[0], back[1]), g, "a grid point maps to itself");
        assert_eq!(s.to_grid(1012.345 + s.step() * 0.1, 3.25), g);
    }
}
