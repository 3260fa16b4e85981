//! Reproducible exploration traces for the report: the scene's own trace
//! when it has one, otherwise a seeded sweep over every layer.

use std::path::{Path, PathBuf};

use taxel_runtime::trace::{Trace, TraceError, TraceSample};

/// The trace a report plays (the runtime's own type, so `taxel play` and the
/// report read and interpolate traces the same way) and where it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Explored {
    /// The trace.
    pub trace: Trace,
    /// Where it came from, for the report's header.
    pub origin: String,
}

/// Speed of the generated sweep in mm/s (inside the 20–80 mm/s of exploring fingers).
pub const SWEEP_MM_PER_S: f64 = 40.0;
/// Longest generated sweep in ms, so that a report stays quick on a full page.
pub const SWEEP_MAX_MS: f64 = 60_000.0;

impl Explored {
    /// Parses a trace CSV with the runtime's parser; `name` prefixes its messages.
    pub fn parse(text: &str, name: &str) -> Result<Explored, String> {
        let trace = Trace::parse(text.as_bytes()).map_err(|e| format!("{name}: {e}"))?;
        Ok(Explored { trace, origin: name.to_string() })
    }

    /// A seeded boustrophedon sweep over each box `(x0, y0, x1, y1)` in turn,
    /// rows `row_mm` apart (offset by the seed), at [`SWEEP_MM_PER_S`], at most [`SWEEP_MAX_MS`] long.
    pub fn sweep(boxes: &[(f64, f64, f64, f64)], row_mm: f64, seed: u64) -> Result<Explored, TraceError> {
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
            if !t.is_finite() || t > SWEEP_MAX_MS {
                break;
            }
            samples.push(TraceSample { t_ms: t, x_mm: x, y_mm: y, contact: true });
        }
        if samples.is_empty() {
            // No box to sweep: the carrier rests at the origin.
            samples.push(TraceSample { t_ms: 0.0, x_mm: 0.0, y_mm: 0.0, contact: true });
        }
        let origin = format!("seeded sweep (seed {seed}) over {} layer boxes", boxes.len());
        Ok(Explored { trace: Trace::from_samples(samples)?, origin })
    }

    /// Carrier position `(tick, x_mm, y_mm)` at every tick of `rate_hz` the
    /// trace covers, interpolated by the runtime.
    pub fn positions(&self, rate_hz: u32) -> Vec<(u64, f64, f64)> {
        self.trace.ticks(rate_hz).map(|(tick, p)| (tick.0, p.x_mm, p.y_mm)).collect()
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
            let scenes = crate::examples::read_index(&index).ok()?;
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
        let t = Explored::parse("t_ms,x_mm,y_mm\n0,0,0\n10,10,20\n", "t").expect("valid");
        let p = t.positions(1000);
        assert_eq!(p.len(), 11);
        assert_eq!(p[5], (5, 5.0, 10.0));
        assert_eq!(p[10], (10, 10.0, 20.0));
    }

    #[test]
    fn bad_traces_name_the_file_and_line() {
        let e = Explored::parse("t_ms,x_mm,y_mm\n0,0,0\n5,NaN,0\n", "a.csv").expect_err("NaN");
        assert!(e.starts_with("a.csv: line 3") && e.contains("x_mm"), "{e}");
    }

    #[test]
    fn sweep_is_reproducible_and_covers_the_box() {
        let a = Explored::sweep(&[(10.0, 10.0, 30.0, 20.0)], 2.0, 7).unwrap();
        assert_eq!(a, Explored::sweep(&[(10.0, 10.0, 30.0, 20.0)], 2.0, 7).unwrap());
        let s = a.trace.samples();
        assert!(s.iter().all(|s| (10.0..=20.0).contains(&s.y_mm)));
        assert!(s.iter().map(|s| s.y_mm).fold(0.0, f64::max) > 18.0);
        // Consecutive samples are SWEEP_MM_PER_S apart in time per mm.
        let (s0, s1) = (s[0], s[1]);
        assert!(((s1.t_ms - s0.t_ms) - (s1.x_mm - s0.x_mm).abs() / SWEEP_MM_PER_S * 1000.0).abs() < 1e-9);
    }

    #[test]
    fn a_sweep_over_nothing_or_huge_boxes_is_still_a_trace() {
        assert_eq!(Explored::sweep(&[], 2.0, 1).unwrap().trace.samples().len(), 1);
        let huge = Explored::sweep(&[(-1e308, 0.0, 1e308, 1.0)], 2.0, 1).unwrap();
        assert!(!huge.trace.samples().is_empty());
        assert!(huge.trace.samples().iter().all(|s| s.t_ms.is_finite()));
    }
}
