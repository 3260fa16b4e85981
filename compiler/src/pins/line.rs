//! Pixel-art lines on the pin grid.
//!
//! Readers of refreshable pin arrays found lines clearest when they follow
//! the pixel-art rules (Bhatnagar et al., DIS 2023): one pin wide, every pin
//! touching the next one by a side or a corner (8-connected), and no
//! "L-corners" or doubled pins where a diagonal steps, which a finger feels
//! as a thickening or a bump. A polyline is walked through Bresenham
//! segments between its vertices (rounded to pin centres), and the walk is
//! cleaned as it is built: repeated pins and back-steps are dropped, and a pin
//! that makes an L between its neighbours is removed, so that its neighbours
//! touch by a corner instead. A real corner of the drawing (a turn of more
//! than 45° between segments at least 1.5 pins long) keeps its pin, so a
//! rectangle keeps square corners while a curve's stair steps are smoothed.

/// A pin position (column, row) in image pins; may lie outside the image.
pub(crate) type PinPos = (i64, i64);

/// The pins of a walked path (vertices in pin units, pin centres at
/// integers), one pin wide and 8-connected, with no L-corners. A closed path
/// repeats its first vertex last.
pub(crate) fn walk(points: &[(f64, f64)], closed: bool) -> Vec<PinPos> {
    let pts: Vec<(f64, f64)> = points.iter().copied().filter(|p| p.0.is_finite() && p.1.is_finite()).collect();
    let corners = corners(&pts, closed);
    let mut w = Walk::default();
    let mut prev: Option<PinPos> = None;
    for (i, &(x, y)) in pts.iter().enumerate() {
        // Keep far-away vertices finite in i64 (they are off the image anyway).
        let p = (x.round().clamp(-1e12, 1e12) as i64, y.round().clamp(-1e12, 1e12) as i64);
        match prev {
            None => w.push(p),
            Some(a) => bresenham(a, p, |q| w.push(q)),
        }
        if corners[i] {
            w.keep(p);
        }
        prev = Some(p);
    }
    let Walk { mut out, kept } = w;
    if closed && out.len() > 3 {
        // The walk ends where it started; clean the corner at the seam too.
        if out.first() == out.last() {
            out.pop();
        }
        let n = out.len();
        if n > 3 && is_l(out[n - 1], out[0], out[1]) && !kept.contains(&out[0]) {
            out.remove(0);
        }
        let n = out.len();
        if n > 3 && is_l(out[n - 2], out[n - 1], out[0]) && !kept.contains(&out[n - 1]) {
            out.pop();
        }
    }
    out
}

/// Which vertices are real corners: a turn of more than 45° between
/// segments that are both at least 1.5 pins long.
fn corners(pts: &[(f64, f64)], closed: bool) -> Vec<bool> {
    let n = pts.len();
    let mut out = vec![false; n];
    for (i, c) in out.iter_mut().enumerate() {
        let (prev, next) = match (i, closed) {
            (0, false) => continue,
            (i, false) if i + 1 == n => continue,
            (0, true) => (pts[n.saturating_sub(2).min(n - 1)], pts[1.min(n - 1)]),
            (i, _) => (pts[i - 1], pts[(i + 1) % n]),
        };
        let p = pts[i];
        let (u, v) = ((p.0 - prev.0, p.1 - prev.1), (next.0 - p.0, next.1 - p.1));
        let (lu, lv) = (u.0.hypot(u.1), v.0.hypot(v.1));
        *c = lu >= 1.5 && lv >= 1.5 && (u.0 * v.0 + u.1 * v.1) < lu * lv * std::f64::consts::FRAC_1_SQRT_2;
    }
    out
}

#[derive(Default)]
struct Walk {
    out: Vec<PinPos>,
    /// Pins of real corners, which the L-corner rule leaves in place.
    kept: Vec<PinPos>,
}

impl Walk {
    fn keep(&mut self, p: PinPos) {
        self.kept.push(p);
    }

    fn push(&mut self, p: PinPos) {
        let out = &mut self.out;
        let n = out.len();
        if n >= 1 && out[n - 1] == p {
            return;
        }
        if n >= 2 && out[n - 2] == p {
            // A back-step (the walk returned to the pin before): drop the detour.
            out.pop();
            return;
        }
        if n >= 2 && is_l(out[n - 2], out[n - 1], p) && self.kept.last().is_none_or(|k| *k != out[n - 1]) {
            out.pop();
        }
        out.push(p);
    }
}

/// Whether `b` makes an L-corner between `a` and `c`: each neighbour touches
/// `b` by a side, and `a` and `c` touch each other by a corner.
fn is_l(a: PinPos, b: PinPos, c: PinPos) -> bool {
    let side = |p: PinPos, q: PinPos| (p.0 - q.0).abs() + (p.1 - q.1).abs() == 1;
    side(a, b) && side(b, c) && (a.0 - c.0).abs() == 1 && (a.1 - c.1).abs() == 1
}

/// Bresenham's line from `a` to `b` (both ends included), 8-connected and one pin wide.
fn bresenham(a: PinPos, b: PinPos, mut f: impl FnMut(PinPos)) {
    let (dx, dy) = ((b.0 - a.0).abs(), -(b.1 - a.1).abs());
    // A segment longer than any pin image is off the image in practice; walk
    // only its ends so that a hostile coordinate cannot make a long loop.
    if dx > 1 << 20 || -dy > 1 << 20 {
        f(a);
        f(b);
        return;
    }
    let (sx, sy) = (if a.0 < b.0 { 1 } else { -1 }, if a.1 < b.1 { 1 } else { -1 });
    let (mut x, mut y, mut err) = (a.0, a.1, dx + dy);
    loop {
        f((x, y));
        if (x, y) == b {
            break;
        }
        let e2 = 2 * err;
        if e2 >= dy {
            err += dy;
            x += sx;
        }
        if e2 <= dx {
            err += dx;
            y += sy;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_staircase_of_vertices_loses_its_l_corners() {
        // Vertices that step right then down: the corners go, the diagonal stays.
        let pts = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (2.0, 1.0), (2.0, 2.0)];
        assert_eq!(walk(&pts, false), vec![(0, 0), (1, 1), (2, 2)]);
    }

    #[test]
    fn jitter_back_and_forth_does_not_double_a_pin() {
        let pts = [(0.0, 0.0), (3.0, 0.0), (2.0, 0.0), (5.0, 0.0)];
        assert_eq!(walk(&pts, false), (0..=5).map(|x| (x, 0)).collect::<Vec<_>>());
    }

    #[test]
    fn a_closed_square_has_no_doubled_seam() {
        let pts = [(0.0, 0.0), (3.0, 0.0), (3.0, 3.0), (0.0, 3.0), (0.0, 0.0)];
        let w = walk(&pts, true);
        assert_eq!(w.len(), 12, "{w:?}");
        let mut sorted = w.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), 12, "each pin once");
    }
}
