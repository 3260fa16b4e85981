//! Whether outlines cross each other more often than a budget, found in work
//! bounded by that budget.
//!
//! A boolean overlay's work and memory follow its input's crossings: a few for
//! a map's regions (neighbours share sides, they do not cross), up to some
//! 10^8 for a scribble of 30,000 random segments. Before an overlay is asked
//! for, [`crossings_exceed`] says whether it would meet more than a given
//! number of crossings, looking at each pair of segments that share a cell of
//! a uniform grid, and giving up (yes, too many) as soon as the segments
//! cover more cells, or the pairs it looks at number more, than a budget
//! proportional to the input allows.

/// One segment `(a, b)` in page mm.
pub type Segment = ((f64, f64), (f64, f64));

/// Most grid cells along a side.
const MAX_SIDE: usize = 4096;
/// Cells a segment may cover on average before the outlines count as
/// crossing too often (a scribble's long segments across the drawing).
const CELLS_PER_SEGMENT: usize = 16;
/// Pairs of segments in one cell looked at, per segment, before the outlines
/// count as crossing too often.
const PAIRS_PER_SEGMENT: usize = 64;

/// Whether the segments cross each other (properly, away from shared ends)
/// more than `limit` times, or are too tangled to tell within the budget.
/// `false` means at most `limit` crossings.
pub fn crossings_exceed(segments: &[Segment], limit: usize) -> bool {
    let finite = |p: (f64, f64)| p.0.is_finite() && p.1.is_finite();
    let segs: Vec<Segment> = segments.iter().copied().filter(|&(a, b)| finite(a) && finite(b)).collect();
    let n = segs.len();
    if n < 2 {
        return false;
    }
    let (mut x0, mut y0, mut x1, mut y1) = (f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
    for &(a, b) in &segs {
        x0 = x0.min(a.0).min(b.0);
        y0 = y0.min(a.1).min(b.1);
        x1 = x1.max(a.0).max(b.0);
        y1 = y1.max(a.1).max(b.1);
    }
    let side = ((n as f64).sqrt().ceil() as usize).clamp(1, MAX_SIDE);
    let (cw, ch) = (((x1 - x0) / side as f64).max(f64::MIN_POSITIVE), ((y1 - y0) / side as f64).max(f64::MIN_POSITIVE));
    let cell_of = |v: f64, o: f64, c: f64| (((v - o) / c) as usize).min(side - 1);
    // Each segment into the cells its box covers, while the budget lasts.
    let mut cells: Vec<Vec<u32>> = vec![Vec::new(); side * side];
    let mut covered = 0usize;
    let cell_budget = CELLS_PER_SEGMENT.saturating_mul(n);
    for (k, &(a, b)) in segs.iter().enumerate() {
        let (c0, c1) = (cell_of(a.0.min(b.0), x0, cw), cell_of(a.0.max(b.0), x0, cw));
        let (r0, r1) = (cell_of(a.1.min(b.1), y0, ch), cell_of(a.1.max(b.1), y0, ch));
        covered = covered.saturating_add((c1 - c0 + 1) * (r1 - r0 + 1));
        if covered > cell_budget {
            return true;
        }
        for r in r0..=r1 {
            for c in c0..=c1 {
                cells[r * side + c].push(k as u32);
            }
        }
    }
    // Pairs within each cell; a crossing is counted in the cell that holds it.
    let (mut crossings, mut pairs) = (0usize, 0usize);
    let pair_budget = PAIRS_PER_SEGMENT.saturating_mul(n);
    for (idx, cell) in cells.iter().enumerate() {
        let (cx, cy) = (idx % side, idx / side);
        for (i, &p) in cell.iter().enumerate() {
            for &q in &cell[i + 1..] {
                pairs += 1;
                if pairs > pair_budget {
                    return true;
                }
                let Some(x) = proper_crossing(segs[p as usize], segs[q as usize]) else { continue };
                if cell_of(x.0, x0, cw) == cx && cell_of(x.1, y0, ch) == cy {
                    crossings += 1;
                    if crossings > limit {
                        return true;
                    }
                }
            }
        }
    }
    false
}

/// Where two segments cross, each strictly between its ends.
fn proper_crossing((a, b): Segment, (c, d): Segment) -> Option<(f64, f64)> {
    let cross = |o: (f64, f64), p: (f64, f64), q: (f64, f64)| (p.0 - o.0) * (q.1 - o.1) - (p.1 - o.1) * (q.0 - o.0);
    let (d1, d2, d3, d4) = (cross(a, b, c), cross(a, b, d), cross(c, d, a), cross(c, d, b));
    let apart = |u: f64, v: f64| (u > 0.0 && v < 0.0) || (u < 0.0 && v > 0.0);
    if !(apart(d1, d2) && apart(d3, d4)) {
        return None;
    }
    let t = d3 / (d3 - d4);
    Some((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ring(points: &[(f64, f64)]) -> Vec<Segment> {
        (0..points.len()).map(|i| (points[i], points[(i + 1) % points.len()])).collect()
    }

    #[test]
    fn a_tessellation_does_not_cross_itself() {
        // A 30 x 30 grid of squares sharing sides: no proper crossing.
        let mut segs = Vec::new();
        for j in 0..30 {
            for i in 0..30 {
                let (x, y) = (i as f64, j as f64);
                segs.extend(ring(&[(x, y), (x + 1.0, y), (x + 1.0, y + 1.0), (x, y + 1.0)]));
            }
        }
        assert!(!crossings_exceed(&segs, 0));
    }

    #[test]
    fn crossings_are_counted_once_against_the_limit() {
        // 10 horizontal and 10 vertical lines: exactly 100 crossings.
        let mut segs = Vec::new();
        for k in 0..10 {
            let v = k as f64 + 0.5;
            segs.push(((0.0, v), (10.0, v)));
            segs.push(((v, 0.0), (v, 10.0)));
        }
        assert!(!crossings_exceed(&segs, 100));
        assert!(crossings_exceed(&segs, 99));
    }

    #[test]
    fn a_scribble_is_too_tangled() {
        let mut s = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 * 100.0
        };
        let pts: Vec<_> = (0..5_000).map(|_| (next(), next())).collect();
        assert!(crossings_exceed(&ring(&pts), 100_000));
    }
}
