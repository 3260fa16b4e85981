//! The fast path for height-field meshes: when the projected triangles
//! already tile their footprint without overlapping (a terrain, a relief, a
//! single-valued surface), they are the faces of the top surface as they
//! are, each covered by itself, and the constrained triangulation is not
//! needed.
//!
//! The test is exact, on the arrangement's integer grid (`planar`):
//!
//! 1. every triangle has area and the same orientation;
//! 2. every projected edge is used by one triangle (a boundary edge) or by
//!    two lying on opposite sides of it;
//! 3. no boundary edge touches another triangle except at the corners they
//!    share.
//!
//! Why that suffices: the number of triangles covering a point is the
//! winding number of the boundary edges around it (an edge used on both
//! sides cancels out). Where two triangles overlap, that number is 2, and
//! the region where it is 2 is bounded by boundary edges, each of which lies
//! on or inside a second triangle; 3 finds that edge. A T-junction (a corner
//! in the middle of another triangle's edge) also fails 3, so every step
//! lies on an edge two triangles share.

use super::planar::{along, orient};

/// Two triangles that share a projected edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shared {
    /// The edge's ends (point indices).
    pub ends: [u32; 2],
    /// The triangles on its two sides (indices into the triangle list).
    pub tris: [u32; 2],
}

/// The edges that triangles share, when the triangles `tris` (corner
/// indices into `at`) tile their footprint without overlapping; `None` when
/// they do not, or when the test would cost more than the triangulation.
pub fn tiling(at: &[[i64; 2]], tris: &[[u32; 3]]) -> Option<Vec<Shared>> {
    let p = |i: u32| at.get(i as usize).copied();
    if tris.len() >= 1 << 31 {
        return None;
    }
    // 1. One orientation.
    let mut sign = 0;
    for t in tris {
        let s = orient(p(t[0])?, p(t[1])?, p(t[2])?).signum();
        if s == 0 || (sign != 0 && s != sign) {
            return None;
        }
        sign = s;
    }
    // 2. Each edge used once, or twice in opposite directions: (low end, high end, triangle << 1 | forward).
    let mut uses: Vec<(u32, u32, u32)> = Vec::with_capacity(3 * tris.len());
    for (k, t) in tris.iter().enumerate() {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            uses.push((a.min(b), a.max(b), (k as u32) << 1 | u32::from(a < b)));
        }
    }
    uses.sort_unstable();
    let mut shared = Vec::new();
    let mut boundary: Vec<([u32; 2], u32)> = Vec::new();
    let mut i = 0;
    while i < uses.len() {
        let (a, b, x) = uses[i];
        let mut j = i + 1;
        while j < uses.len() && uses[j].0 == a && uses[j].1 == b {
            j += 1;
        }
        match j - i {
            1 => boundary.push(([a, b], x >> 1)),
            2 if (x ^ uses[i + 1].2) & 1 == 1 => {
                shared.push(Shared { ends: [a, b], tris: [x >> 1, uses[i + 1].2 >> 1] })
            }
            _ => return None,
        }
        i = j;
    }
    // 3. Boundary edges against the triangles near them, on a uniform grid
    // of about two cells per boundary edge a side.
    if boundary.is_empty() {
        return Some(shared);
    }
    let (mut lo, mut hi) = ([i64::MAX; 2], [i64::MIN; 2]);
    for (e, _) in &boundary {
        for &v in e {
            let q = p(v)?;
            lo = [lo[0].min(q[0]), lo[1].min(q[1])];
            hi = [hi[0].max(q[0]), hi[1].max(q[1])];
        }
    }
    let grid = super::planar::BoxGrid::new(lo, hi, boundary.len());
    let side = grid.side;
    let cells_of = |q: &[[i64; 2]]| -> Option<[i64; 4]> {
        let b = q.iter().fold([i64::MAX, i64::MAX, i64::MIN, i64::MIN], |b, v| {
            [b[0].min(v[0]), b[1].min(v[1]), b[2].max(v[0]), b[3].max(v[1])]
        });
        grid.cells(b)
    };
    // Past this many cell visits and pair tests the triangulation is cheaper.
    let mut budget = 20 * tris.len() + 100_000;
    let mut cells: Vec<Vec<u32>> = vec![Vec::new(); (side * side) as usize];
    for (k, (e, _)) in boundary.iter().enumerate() {
        let Some(r) = cells_of(&[p(e[0])?, p(e[1])?]) else { continue };
        budget = budget.checked_sub(((r[2] - r[0] + 1) * (r[3] - r[1] + 1)) as usize)?;
        for cy in r[1]..=r[3] {
            for cx in r[0]..=r[2] {
                cells[(cy * side + cx) as usize].push(k as u32);
            }
        }
    }
    for (k, t) in tris.iter().enumerate() {
        let c = [p(t[0])?, p(t[1])?, p(t[2])?];
        let Some(r) = cells_of(&c) else { continue };
        budget = budget.checked_sub(((r[2] - r[0] + 1) * (r[3] - r[1] + 1)) as usize)?;
        for cy in r[1]..=r[3] {
            for cx in r[0]..=r[2] {
                for &b in &cells[(cy * side + cx) as usize] {
                    let (e, owner) = boundary[b as usize];
                    if owner == k as u32 {
                        continue;
                    }
                    budget = budget.checked_sub(1)?;
                    if touches(p(e[0])?, p(e[1])?, c) {
                        return None;
                    }
                }
            }
        }
    }
    Some(shared)
}

/// Whether the segment `a -> b` meets the closed triangle `t` (with area)
/// anywhere but at corners of `t` that are also ends of the segment.
fn touches(a: [i64; 2], b: [i64; 2], t: [[i64; 2]; 3]) -> bool {
    let on_segment = |v: [i64; 2]| orient(a, b, v) == 0 && (0..=along(a, b, b)).contains(&along(a, b, v));
    if t.iter().any(|&v| v != a && v != b && on_segment(v)) {
        return true;
    }
    let inside = |v: [i64; 2]| {
        let o = [orient(t[0], t[1], v), orient(t[1], t[2], v), orient(t[2], t[0], v)];
        o.iter().all(|&x| x >= 0) || o.iter().all(|&x| x <= 0)
    };
    if [a, b].iter().any(|&v| !t.contains(&v) && inside(v)) {
        return true;
    }
    [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])].iter().any(|&(c, d)| {
        orient(a, b, c).signum() * orient(a, b, d).signum() < 0
            && orient(c, d, a).signum() * orient(c, d, b).signum() < 0
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 x 2 grid of unit squares (points 0..9, row by row), each cut along its diagonal.
    fn grid() -> (Vec<[i64; 2]>, Vec<[u32; 3]>) {
        let at: Vec<[i64; 2]> = (0..9).map(|k| [k % 3, k / 3]).collect();
        let mut tris = Vec::new();
        for j in 0..2u32 {
            for i in 0..2u32 {
                let v = j * 3 + i;
                tris.push([v, v + 1, v + 4]);
                tris.push([v, v + 4, v + 3]);
            }
        }
        (at, tris)
    }

    #[test]
    fn a_grid_tiles_and_shares_its_inner_edges() {
        let (at, tris) = grid();
        let s = tiling(&at, &tris).expect("a tiling");
        // 4 diagonals and 4 edges between the squares.
        assert_eq!(s.len(), 8);
    }

    #[test]
    fn overlaps_folds_and_t_junctions_are_not_tilings() {
        let (mut at, tris) = grid();
        // A triangle laid over the middle, the same way up.
        let mut over = tris.clone();
        at.push([3, 3]);
        over.push([4, 9, 7]);
        assert_eq!(orient(at[4], at[9], at[7]).signum(), orient(at[0], at[1], at[4]).signum());
        assert!(tiling(&at, &over).is_none());
        // One square turned over (a fold): two orientations.
        let mut fold = tris.clone();
        fold[0] = [0, 4, 1];
        assert!(tiling(&at, &fold).is_none());
        // A separate triangle whose long edge crosses a corner square: only boundary edges meet.
        let mut apart = tris.clone();
        at.extend([[1, -1], [5, -1], [5, 5]]);
        let n = at.len() as u32;
        apart.push([n - 3, n - 2, n - 1]);
        assert!(tiling(&at, &apart).is_none());
        // A T-junction: the point (1, 0) splits the bottom edge of the other side.
        let at2: Vec<[i64; 2]> = vec![[0, 0], [2, 0], [1, 2], [1, 0], [0, -2], [2, -2]];
        let t = vec![[0, 1, 2], [0, 4, 3], [3, 4, 5], [3, 5, 1]];
        assert!(orient(at2[0], at2[1], at2[2]) > 0 && orient(at2[0], at2[4], at2[3]) > 0);
        assert!(tiling(&at2, &t).is_none());
    }
}
