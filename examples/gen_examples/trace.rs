//! Exploration traces: where a reader's finger (the display's carrier) is
//! over time. A reader first sweeps the sheet row by row to find what is on
//! it, then goes back to each thing and feels it: follows outlines, crosses
//! textures, circles symbols. Speeds stay in the 20–80 mm/s of ordinary
//! exploration. Samples every 10 ms; deterministic.

use crate::scene::Visit;
use crate::shapes::Pt;

/// Sweep speed, mm/s.
const SWEEP: f64 = 40.0;
/// Following an outline or reading a line, mm/s.
const FOLLOW: f64 = 30.0;
/// Crossing a texture, mm/s.
const CROSS: f64 = 35.0;
/// Moving from one thing to the next, mm/s.
const TRANSFER: f64 = 60.0;
/// Rows of the sweep are at most this far apart. The 8 x 8 array is about
/// 11 mm tall, so neighbouring rows overlap and nothing is missed.
const ROW_STEP: f64 = 8.0;
/// Sample period, ms.
const DT_MS: u64 = 10;

/// A path with a speed for each leg.
struct Route {
    pts: Vec<Pt>,
    /// `speeds[i]` is the speed from `pts[i]` to `pts[i + 1]`.
    speeds: Vec<f64>,
}

impl Route {
    fn go(&mut self, p: Pt, speed: f64) {
        match self.pts.last() {
            Some(&q) if dist(q, p) < 1e-9 => {}
            Some(_) => {
                self.pts.push(p);
                self.speeds.push(speed);
            }
            None => self.pts.push(p),
        }
    }
}

fn dist(a: Pt, b: Pt) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

/// The trace CSV for a page of `size` with these visits.
pub fn csv(size: (f64, f64), visits: &[Visit]) -> String {
    let route = route(size, visits);
    let mut out = String::from("t_ms,x_mm,y_mm\n");
    // Arrival time of each point, in ms.
    let mut at = vec![0.0];
    for (i, s) in route.speeds.iter().enumerate() {
        at.push(at[i] + dist(route.pts[i], route.pts[i + 1]) / s * 1000.0);
    }
    let end = at.last().copied().unwrap_or(0.0);
    let mut leg = 0;
    let mut t = 0;
    while t as f64 <= end {
        while leg + 1 < at.len() - 1 && at[leg + 1] <= t as f64 {
            leg += 1;
        }
        let (p, q) = (route.pts[leg], route.pts[(leg + 1).min(route.pts.len() - 1)]);
        let span = at[(leg + 1).min(at.len() - 1)] - at[leg];
        let f = if span > 0.0 { ((t as f64 - at[leg]) / span).clamp(0.0, 1.0) } else { 0.0 };
        out += &format!("{t},{:.2},{:.2}\n", p.0 + (q.0 - p.0) * f, p.1 + (q.1 - p.1) * f);
        t += DT_MS;
    }
    out
}

/// The sweep over everything the visits touch, then the visits in order.
fn route(size: (f64, f64), visits: &[Visit]) -> Route {
    let pts: Vec<Pt> = visits.iter().flat_map(extent).collect();
    let clamp = |v: f64, hi: f64| v.clamp(1.0, hi - 1.0);
    let x0 = clamp(pts.iter().map(|p| p.0).fold(f64::MAX, f64::min) - 1.0, size.0);
    let x1 = clamp(pts.iter().map(|p| p.0).fold(f64::MIN, f64::max) + 1.0, size.0);
    let y0 = clamp(pts.iter().map(|p| p.1).fold(f64::MAX, f64::min) + 2.0, size.1);
    let y1 = clamp(pts.iter().map(|p| p.1).fold(f64::MIN, f64::max) - 2.0, size.1);
    let rows = ((y1 - y0) / ROW_STEP).ceil().max(1.0) as usize;
    let mut r = Route { pts: vec![], speeds: vec![] };
    for k in 0..=rows {
        let y = y0 + (y1 - y0) * k as f64 / rows as f64;
        let (a, b) = if k % 2 == 0 { (x0, x1) } else { (x1, x0) };
        r.go((a, y), SWEEP);
        r.go((b, y), SWEEP);
    }
    for v in visits {
        match v {
            Visit::Outline(o) => {
                r.go(o[0], TRANSFER);
                for &p in o.iter().skip(1).chain(std::iter::once(&o[0])) {
                    r.go(p, FOLLOW);
                }
            }
            Visit::Path(o) => {
                r.go(o[0], TRANSFER);
                for &p in &o[1..] {
                    r.go(p, FOLLOW);
                }
            }
            Visit::Area { centre: (cx, cy), reach: d } => {
                let e = d * std::f64::consts::FRAC_1_SQRT_2;
                let passes = [
                    ((cx - d, *cy), (cx + d, *cy)),
                    ((*cx, cy - d), (*cx, cy + d)),
                    ((cx - e, cy + e), (cx + e, cy - e)),
                    ((cx + e, cy + e), (cx - e, cy - e)),
                ];
                r.go(passes[0].0, TRANSFER);
                for (a, b) in passes {
                    r.go(a, CROSS);
                    r.go(b, CROSS);
                }
            }
            Visit::Point((px, py)) => {
                // Circle the symbol at 2 mm, so the whole array passes over it.
                let ring = |k: usize| {
                    let a = std::f64::consts::TAU * k as f64 / 12.0;
                    (px + 2.0 * a.cos(), py + 2.0 * a.sin())
                };
                r.go(ring(0), TRANSFER);
                for k in 1..=12 {
                    r.go(ring(k), FOLLOW);
                }
            }
        }
    }
    r
}

/// The points that bound a visit.
fn extent(v: &Visit) -> Vec<Pt> {
    match v {
        Visit::Outline(o) | Visit::Path(o) => o.clone(),
        Visit::Area { centre: (x, y), reach: d } => vec![(x - d, y - d), (x + d, y + d)],
        Visit::Point(p) => vec![*p],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(csv: &str) -> Vec<(u64, f64, f64)> {
        csv.lines()
            .skip(1)
            .map(|l| {
                let v: Vec<&str> = l.split(',').collect();
                (v[0].parse().unwrap(), v[1].parse().unwrap(), v[2].parse().unwrap())
            })
            .collect()
    }

    #[test]
    fn samples_every_10_ms_from_zero_and_never_faster_than_a_transfer() {
        let r = rows(&csv((110.0, 60.0), &[Visit::Point((20.0, 20.0)), Visit::Point((90.0, 40.0))]));
        for (k, w) in r.windows(2).enumerate() {
            assert_eq!((w[0].0, w[1].0), (k as u64 * 10, k as u64 * 10 + 10));
            let v = (w[1].1 - w[0].1).hypot(w[1].2 - w[0].2) / 0.010;
            // Positions are written to 0.01 mm, so a chord may gain up to 1.42 mm/s.
            assert!(v <= TRANSFER + 1.5, "{v} mm/s");
        }
    }

    #[test]
    fn the_sweep_leaves_no_gap_taller_than_the_array() {
        // The 8 x 8 array reaches 4.9 mm above and below the carrier.
        let visits = [Visit::Area { centre: (55.0, 30.0), reach: 28.0 }];
        let r = rows(&csv((110.0, 60.0), &visits));
        for y in (2..=58).map(f64::from) {
            assert!(r.iter().any(|&(_, _, ty)| (ty - y).abs() <= 4.9), "y = {y} mm is never under the array");
        }
    }
}
