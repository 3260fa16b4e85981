//! An outline's sides filed by horizontal strips, for many point queries
//! against one large outline: [`SideRows::deep_inside`] answers
//! [`super::deep_inside`] reading only the sides of the strips near the
//! point. A coastline of thousands of sides asked about every midpoint of
//! the hundreds of islands beside it otherwise reads every side each time
//! (a world map's automatic sheet spent half its build there).

use super::{Crossings, FillRule, Polyline, side_within};

/// Sides per strip, on average, that [`SideRows::new`] aims at.
const SIDES_PER_STRIP: usize = 8;
/// Most strips of one outline.
const MAX_STRIPS: usize = 4096;

/// One side: its ends, and whether it is measured ([`Polyline::segments`]
/// gives it) or only closes its ring for the winding.
#[derive(Debug, Clone, Copy)]
struct Side {
    a: (f64, f64),
    b: (f64, f64),
    measured: bool,
}

/// The sides of an outline (every subpath closed, as fills are) filed by
/// the horizontal strips their heights meet.
#[derive(Debug)]
pub struct SideRows {
    sides: Vec<Side>,
    /// The first strip's top and each strip's height.
    y0: f64,
    h: f64,
    /// Strip `s` holds `index[start[s]..start[s + 1]]`, in side order.
    start: Vec<u32>,
    index: Vec<u32>,
}

impl SideRows {
    /// Files the sides of `polys`; `None` when a coordinate is not finite
    /// or there are too many sides to number (callers then read every side).
    pub fn new<'a>(polys: impl IntoIterator<Item = &'a Polyline>) -> Option<SideRows> {
        let mut sides = Vec::new();
        for pl in polys {
            let n = pl.points.len();
            let measured = pl.segment_count();
            for i in 0..n {
                sides.push(Side { a: pl.points[i], b: pl.points[(i + 1) % n], measured: i < measured });
            }
        }
        if sides.len() >= u32::MAX as usize
            || !sides.iter().all(|s| s.a.0.is_finite() && s.a.1.is_finite() && s.b.0.is_finite() && s.b.1.is_finite())
        {
            return None;
        }
        let (y0, y1) = sides.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
            (lo.min(s.a.1).min(s.b.1), hi.max(s.a.1).max(s.b.1))
        });
        let strips = (sides.len() / SIDES_PER_STRIP).clamp(1, MAX_STRIPS);
        let h = if y1 > y0 { (y1 - y0) / strips as f64 } else { 1.0 };
        let mut rows = SideRows { sides, y0, h, start: vec![0; strips + 1], index: Vec::new() };
        // Counted, then placed (a counting sort: each strip in side order).
        for s in &rows.sides {
            let (lo, hi) = rows.strips(s.a.1.min(s.b.1), s.a.1.max(s.b.1));
            for k in lo..=hi {
                rows.start[k + 1] += 1;
            }
        }
        for k in 1..rows.start.len() {
            rows.start[k] += rows.start[k - 1];
        }
        let mut next = rows.start.clone();
        rows.index = vec![0; rows.start[strips] as usize];
        for (n, s) in rows.sides.iter().enumerate() {
            let (lo, hi) = rows.strips(s.a.1.min(s.b.1), s.a.1.max(s.b.1));
            for at in &mut next[lo..=hi] {
                rows.index[*at as usize] = n as u32;
                *at += 1;
            }
        }
        Some(rows)
    }

    /// The strips `[lo, hi]` that heights `y_lo..=y_hi` meet, clamped to the
    /// outline's (`floor` is monotone, so a side whose heights meet a range
    /// is filed in a strip of it).
    fn strips(&self, y_lo: f64, y_hi: f64) -> (usize, usize) {
        let last = self.start.len() - 2;
        let at = |y: f64| {
            let k = ((y - self.y0) / self.h).floor();
            if k.is_nan() || k < 0.0 { 0 } else { (k as usize).min(last) }
        };
        (at(y_lo), at(y_hi))
    }

    /// [`super::deep_inside`] of the outline this was made of: whether `p`
    /// lies inside it (by `rule`) farther than `margin` from its measured
    /// sides.
    pub fn deep_inside(&self, p: (f64, f64), rule: FillRule, margin: f64) -> bool {
        let (lo, hi) = self.strips(p.1 - margin, p.1 + margin);
        for k in lo..=hi {
            for &n in &self.index[self.start[k] as usize..self.start[k + 1] as usize] {
                let Side { a, b, measured } = self.sides[n as usize];
                if measured && side_within(p, a, b, margin) {
                    return false;
                }
            }
        }
        self.contains(p, rule)
    }

    /// [`super::contains`] of the outline this was made of (every subpath
    /// closed): every side that the ray from `p` towards +x can cross is
    /// filed in `p`'s strip.
    pub fn contains(&self, p: (f64, f64), rule: FillRule) -> bool {
        let (k, _) = self.strips(p.1, p.1);
        let mut ray = Crossings::default();
        for &n in &self.index[self.start[k] as usize..self.start[k + 1] as usize] {
            let Side { a, b, .. } = self.sides[n as usize];
            ray.side(p, a, b);
        }
        ray.inside(rule)
    }
}
