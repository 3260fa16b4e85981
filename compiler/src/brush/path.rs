//! Step 1 of Tactile Brush on any polyline: arc length and the virtual
//! actuation points where the path crosses the grid lines, plus its ends.
//!
//! The paper draws straight strokes between grid lines; here the path is any
//! polyline (Béziers arrive flattened). A crossing is a point where a segment
//! reaches a row or column line of the grid from elsewhere: a segment that runs
//! *along* a line meets the perpendicular lines at the actuators, a segment
//! through an actuator gives one point there, and zero-length segments give
//! nothing. Points closer than [`DUPLICATE_MM`] in arc length (more on huge
//! grids, see `GridGeometry::tolerance`) are one point.

use super::grid::GridGeometry;

/// Two virtual points closer than this along the path (mm) are the same point
/// (a path through an actuator crosses a row and a column line at once).
pub(crate) const DUPLICATE_MM: f64 = 1e-7;

/// A virtual actuation point: where it is, and how far along the path.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct VirtualPoint {
    /// Arc length from the start of the path (mm).
    pub s: f64,
    /// Page x (mm).
    pub x: f64,
    /// Page y (mm).
    pub y: f64,
}

/// Fills `cum` with the cumulative arc length at each vertex and returns the
/// total length.
pub(crate) fn arc_lengths(poly: &[(f64, f64)], cum: &mut Vec<f64>) -> f64 {
    cum.clear();
    let mut s = 0.0;
    let mut prev = match poly.first() {
        Some(&p) => p,
        None => return 0.0,
    };
    for &p in poly {
        s += (p.0 - prev.0).hypot(p.1 - prev.1);
        cum.push(s);
        prev = p;
    }
    s
}

/// The point at arc length `s` along the path (clamped to its ends).
pub(crate) fn point_at(poly: &[(f64, f64)], cum: &[f64], s: f64) -> (f64, f64) {
    let i = cum.partition_point(|&c| c < s);
    match (i.checked_sub(1).and_then(|j| poly.get(j)), poly.get(i), cum.get(i)) {
        (Some(&a), Some(&b), Some(&cb)) => {
            let ca = cum[i - 1];
            let t = if cb > ca { ((s - ca) / (cb - ca)).clamp(0.0, 1.0) } else { 1.0 };
            (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
        }
        (_, Some(&b), _) => b,
        _ => poly.last().copied().unwrap_or((0.0, 0.0)),
    }
}

/// Appends to `out`, in travel order, the grid lines (of pitch `pitch`,
/// `n` of them starting at 0) that the coordinate reaches when it moves from
/// `a` (excluded) to `b` (included), as the parameter `t` along the segment.
fn line_hits(a: f64, b: f64, pitch: f64, n: u16, mut f: impl FnMut(f64, f64)) {
    if a == b || n == 0 {
        return;
    }
    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
    let first = ((lo / pitch).floor() as i64 - 1).max(0);
    let last = ((hi / pitch).ceil() as i64 + 1).min(n as i64 - 1);
    if first > last {
        return;
    }
    let mut visit = |k: i64| {
        let line = k as f64 * pitch;
        let reached = if a < b { line > a && line <= b } else { line < a && line >= b };
        if reached {
            f((line - a) / (b - a), line);
        }
    };
    if a < b {
        (first..=last).for_each(&mut visit);
    } else {
        (first..=last).rev().for_each(&mut visit);
    }
}

/// Pushes `p` unless it duplicates the last point (then the last point takes
/// whichever coordinates were snapped to a grid line).
fn push_point(out: &mut Vec<VirtualPoint>, grid: &GridGeometry, p: VirtualPoint) {
    let (x, y) = grid.snap(p.x, p.y);
    let p = VirtualPoint { x, y, ..p };
    if let Some(last) = out.last_mut()
        && (p.s - last.s).abs() <= DUPLICATE_MM.max(grid.tolerance())
    {
        let (lx, ly) = grid.snap(last.x, last.y);
        // A crossing found on a vertical line has an exact x, one on a
        // horizontal line an exact y; keep the exact one of each.
        last.x = if on_line(x, grid.pitch_x, grid.cols) { x } else { lx };
        last.y = if on_line(y, grid.pitch_y, grid.rows) { y } else { ly };
        return;
    }
    out.push(p);
}

/// Whether `v` is exactly a grid line's coordinate (as [`GridGeometry::snap`]
/// and the crossing search compute it).
fn on_line(v: f64, pitch: f64, n: u16) -> bool {
    (v / pitch).round().clamp(0.0, (n.max(1) - 1) as f64) * pitch == v
}

/// The virtual points of a polyline that lies inside the grid: its start, every
/// grid-line crossing in travel order, and its end. `cum` must hold the
/// cumulative arc lengths from [`arc_lengths`]; `scratch` is a reusable buffer.
pub(crate) fn virtual_points(
    poly: &[(f64, f64)],
    cum: &[f64],
    grid: &GridGeometry,
    scratch: &mut Vec<VirtualPoint>,
    out: &mut Vec<VirtualPoint>,
) {
    out.clear();
    let Some(&(x0, y0)) = poly.first() else { return };
    push_point(out, grid, VirtualPoint { s: 0.0, x: x0, y: y0 });
    for (i, w) in poly.windows(2).enumerate() {
        let (a, b) = (w[0], w[1]);
        let (Some(&s0), Some(&s1)) = (cum.get(i), cum.get(i + 1)) else { break };
        let len = s1 - s0;
        if len <= 0.0 {
            continue;
        }
        // Column and row crossings each come in travel order; sorting the
        // (short) union by arc length merges them.
        scratch.clear();
        line_hits(a.0, b.0, grid.pitch_x, grid.cols, |t, line| {
            scratch.push(VirtualPoint { s: s0 + t * len, x: line, y: a.1 + t * (b.1 - a.1) });
        });
        let from_cols = scratch.len();
        line_hits(a.1, b.1, grid.pitch_y, grid.rows, |t, line| {
            scratch.push(VirtualPoint { s: s0 + t * len, x: a.0 + t * (b.0 - a.0), y: line });
        });
        if from_cols > 0 && from_cols < scratch.len() {
            scratch.sort_by(|p, q| p.s.total_cmp(&q.s));
        }
        for &p in scratch.iter() {
            push_point(out, grid, p);
        }
    }
    let total = cum.last().copied().unwrap_or(0.0);
    if let Some(&(xe, ye)) = poly.last() {
        push_point(out, grid, VirtualPoint { s: total, x: xe, y: ye });
        // The end is the end, even when it merged into a crossing just before it.
        if let Some(last) = out.last_mut() {
            last.s = total;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> GridGeometry {
        GridGeometry { rows: 3, cols: 4, pitch_x: 63.0, pitch_y: 63.0 }
    }

    fn points(poly: &[(f64, f64)]) -> Vec<VirtualPoint> {
        let (mut cum, mut scratch, mut out) = (Vec::new(), Vec::new(), Vec::new());
        arc_lengths(poly, &mut cum);
        virtual_points(poly, &cum, &grid(), &mut scratch, &mut out);
        out
    }

    fn xy(v: &[VirtualPoint]) -> Vec<(f64, f64)> {
        v.iter().map(|p| (p.x, p.y)).collect()
    }

    #[test]
    fn stroke_along_a_row_stops_at_each_actuator() {
        let v = points(&[(0.0, 63.0), (189.0, 63.0)]);
        assert_eq!(xy(&v), vec![(0.0, 63.0), (63.0, 63.0), (126.0, 63.0), (189.0, 63.0)]);
        assert_eq!(v.iter().map(|p| p.s).collect::<Vec<_>>(), vec![0.0, 63.0, 126.0, 189.0]);
    }

    #[test]
    fn diagonal_through_a_node_gives_one_point_there() {
        // (0,0) -> (126,126) passes the actuators (1,1) and (2,2) exactly.
        let v = points(&[(0.0, 0.0), (126.0, 126.0)]);
        assert_eq!(xy(&v), vec![(0.0, 0.0), (63.0, 63.0), (126.0, 126.0)]);
    }

    #[test]
    fn zero_length_segments_and_reversals() {
        let v = points(&[(10.0, 10.0), (10.0, 10.0), (70.0, 10.0), (70.0, 10.0), (10.0, 10.0)]);
        // Out across x = 63 and back across it.
        assert_eq!(xy(&v), vec![(10.0, 10.0), (63.0, 10.0), (63.0, 10.0), (10.0, 10.0)]);
        assert_eq!(v.iter().map(|p| p.s).collect::<Vec<_>>(), vec![0.0, 53.0, 67.0, 120.0]);
    }

    #[test]
    fn point_at_interpolates_by_arc_length() {
        let poly = [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0)];
        let mut cum = Vec::new();
        assert_eq!(arc_lengths(&poly, &mut cum), 20.0);
        assert_eq!(point_at(&poly, &cum, 15.0), (10.0, 5.0));
        assert_eq!(point_at(&poly, &cum, 0.0), (0.0, 0.0));
        assert_eq!(point_at(&poly, &cum, 25.0), (10.0, 10.0));
    }
}
