//! Reproducible exploration traces for the report: the scene's own trace
//! when it has one, otherwise a seeded sweep over every layer.

use std::path::{Path, PathBuf};

/// A trace: samples `(t_ms, x_mm, y_mm)` with non-decreasing times.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    /// The samples.
    pub samples: Vec<(f64, f64, f64)>,
    /// Where it came from, for the report's header.
    pub origin: String,
}

/// Speed of the generated sweep in mm/s (inside the 20–80 mm/s of exploring fingers).
pub const SWEEP_MM_PER_S: f64 = 40.0;
/// Longest generated sweep in ms, so that a report stays quick on a full page.
pub const SWEEP_MAX_MS: f64 = 60_000.0;

impl Trace {
    /// Parses a trace CSV with the runtime's parser (`taxel play` reads the
    /// same files); `name` prefixes its messages.
    pub fn parse(text: &str, name: &str) -> Result<Trace, String> {
        let t = taxel_runtime::trace::Trace::parse(text.as_bytes()).map_err(|e| format!("{name}: {e}"))?;
        let samples: Vec<(f64, f64, f64)> = t.samples().iter().map(|s| (s.t_ms, s.x_mm, s.y_mm)).collect();
        if samples.is_empty() {
            return Err(format!("{name}: the trace has no samples"));
        }
        Ok(Trace { samples, origin: name.to_string() })
    }

    /// A seeded boustrophedon sweep over each box `(x0, y0, x1, y1)` in turn,
    /// rows `row_mm` apart (offset by the seed), at [`SWEEP_MM_PER_S`], at most [`SWEEP_MAX_MS`] long.
    pub fn sweep(boxes: &[(f64, f64, f64, f64)], row_mm: f64, seed: u64) -> Trace {
        let mut rng = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut pts: Vec<(f64, f64)> = Vec::new();
        let row_mm = if row_mm.is_finite() && row_mm > 0.01 { row_mm } else { 1.0 };
        for &(x0, y0, x1, y1) in boxes {
            if ![x0, y0, x1, y1].iter().all(|v| v.is_finite()) || x1 < x0 || y1 < y0 {
                continue;
            }
            let mut y = y0 + next() * row_mm.min(y1 - y0 + 1e-9);
            let mut forward = true;
            while y <= y1 + 1e-9 {
                let (a, b) = if forward { (x0, x1) } else { (x1, x0) };
                pts.push((a, y));
                pts.push((b, y));
                forward = !forward;
                y += row_mm;
            }
        }
        let mut samples = Vec::with_capacity(pts.len());
        let mut t = 0.0;
        for (k, &(x, y)) in pts.iter().enumerate() {
            if k > 0 {
                let (px, py) = pts[k - 1];
                t += (x - px).hypot(y - py) / SWEEP_MM_PER_S * 1000.0;
            }
            if t > SWEEP_MAX_MS {
                break;
            }
            samples.push((t, x, y));
        }
        if samples.is_empty() {
            samples.push((0.0, 0.0, 0.0));
        }
        Trace { samples, origin: format!("seeded sweep (seed {seed}) over {} layer boxes", boxes.len()) }
    }

    /// The first and last tick at `rate_hz` (tick k is the instant k / rate).
    pub fn ticks(&self, rate_hz: u32) -> (u64, u64) {
        let r = rate_hz.max(1) as f64 / 1000.0;
        let first = self.samples.first().map_or(0.0, |s| s.0);
        let last = self.samples.last().map_or(0.0, |s| s.0);
        ((first * r).ceil() as u64, (last * r).floor().max((first * r).ceil()) as u64)
    }

    /// Positions at every tick from the first to the last, linearly interpolated.
    pub fn positions(&self, rate_hz: u32) -> Vec<(u64, f64, f64)> {
        let (t0, t1) = self.ticks(rate_hz);
        let mut out = Vec::with_capacity((t1 - t0 + 1) as usize);
        let mut k = 0;
        let s = &self.samples;
        for tick in t0..=t1 {
            let t = tick as f64 * 1000.0 / rate_hz.max(1) as f64;
            while k + 1 < s.len() && s[k + 1].0 <= t {
                k += 1;
            }
            let (ta, xa, ya) = s[k];
            let (x, y) = match s.get(k + 1) {
                Some(&(tb, xb, yb)) if tb > ta => {
                    let u = ((t - ta) / (tb - ta)).clamp(0.0, 1.0);
                    (xa + u * (xb - xa), ya + u * (yb - ya))
                }
                _ => (xa, ya),
            };
            out.push((tick, x, y));
        }
        out
    }
}

/// The scene's own trace: the one examples/examples.toml names for it, else a
/// sibling `<stem>.trace.csv`, else `None`.
pub fn own_trace_path(input: &Path) -> Option<PathBuf> {
    let sibling = input.with_extension("trace.csv");
    if sibling.is_file() {
        return Some(sibling);
    }
    // Walk up to an examples index that lists this input.
    for dir in input.ancestors().skip(1) {
        let index = dir.join("examples.toml");
        if index.is_file() {
            let scenes = crate::demo::read_index(&index).ok()?;
            let canon = input.canonicalize().ok()?;
            return scenes
                .into_iter()
                .find(|s| dir.join(&s.input).canonicalize().ok().as_ref() == Some(&canon))
                .and_then(|s| s.trace.map(|t| dir.join(t)));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_interpolate_linearly_per_tick() {
        let t = Trace::parse("t_ms,x_mm,y_mm\n0,0,0\n10,10,20\n", "t").expect("valid");
        let p = t.positions(1000);
        assert_eq!(p.len(), 11);
        assert_eq!(p[5], (5, 5.0, 10.0));
        assert_eq!(p[10], (10, 10.0, 20.0));
    }

    #[test]
    fn bad_traces_name_the_line() {
        let e = Trace::parse("t_ms,x_mm,y_mm\n0,0,0\n5,NaN,0\n", "a.csv").expect_err("NaN");
        assert!(e.starts_with("a.csv: line 3") && e.contains("x_mm"), "{e}");
        let e = Trace::parse("t_ms,x_mm,y_mm\n5,0,0\n4,0,0\n", "a.csv").expect_err("backwards");
        assert!(e.contains("line 3"), "{e}");
        assert!(Trace::parse("x,y\n", "a.csv").is_err());
    }

    #[test]
    fn sweep_is_reproducible_and_covers_the_box() {
        let a = Trace::sweep(&[(10.0, 10.0, 30.0, 20.0)], 2.0, 7);
        assert_eq!(a, Trace::sweep(&[(10.0, 10.0, 30.0, 20.0)], 2.0, 7));
        let ys: Vec<f64> = a.samples.iter().map(|s| s.2).collect();
        assert!(ys.iter().all(|&y| (10.0..=20.0).contains(&y)));
        assert!(ys.iter().cloned().fold(0.0, f64::max) > 18.0);
        // Consecutive samples are SWEEP_MM_PER_S apart in time per mm.
        let (s0, s1) = (a.samples[0], a.samples[1]);
        assert!(((s1.0 - s0.0) - (s1.1 - s0.1).abs() / SWEEP_MM_PER_S * 1000.0).abs() < 1e-9);
    }
}
