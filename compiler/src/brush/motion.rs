//! Step 3 of Tactile Brush: onsets and durations for apparent motion.
//!
//! Every virtual point k peaks at τ_k. Its activity splits at the peak into a
//! rise `d_k⁻` (onset to peak) and a fall `d_k⁺` (peak to end), with `d_0⁻ = 0`,
//! `d_n⁺ = 0` and `d_k⁺ = d_(k+1)⁻`: point k stops when point k+1 peaks, measured
//! from their onsets. With the optimal SOA law of seed 001,
//! `SOA_k = 0.32 · d_k + 47.3` ms, the explicit forward recurrence of
//! `primitives.md` reduces to one for the rises, `x_k = d_k⁻`:
//!
//! ```text
//! x_0 = 0,    x_(k+1) = (Δ_k + 0.68 · x_k − 47.3) / 1.32,    Δ_k = τ_(k+1) − τ_k
//! onset_k = τ_k − x_k,    d_k = x_k + x_(k+1)  (x_(n+1) = 0)
//! ```
//!
//! (substitute `onset_(k+1) = onset_k + SOA_k` into `x_(k+1) = τ_(k+1) − onset_(k+1)`).
//! A schedule is *feasible* when every rise after the first is at least the
//! shortest activity `min_ms` (one tick): then every onset precedes its peak,
//! every duration is at least one tick and onsets increase. Each rise grows
//! with every gap, so for fixed fractions of the stroke feasibility is
//! monotone in the stroke's duration, which makes bisection exact.

/// Slope of the optimal SOA law (seed 001, Figure 4).
pub const SOA_SLOPE: f64 = 0.32;
/// Intercept of the optimal SOA law, in milliseconds.
pub const SOA_INTERCEPT_MS: f64 = 47.3;

/// When one virtual point starts, peaks and stops, in milliseconds from the
/// stroke's start (unquantised).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Timing {
    /// Peak time τ_k.
    pub peak_ms: f64,
    /// Onset (the sum of the SOAs before it).
    pub onset_ms: f64,
    /// Duration d_k from the model (it may run past the stroke's end; see
    /// [`crate::brush::PlannedPoint::end_ms`]).
    pub duration_ms: f64,
}

/// The recurrence could not give every point a rise of at least `min_ms`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Infeasible {
    /// The first point whose rise was too short (its onset came too late).
    pub point: usize,
}

/// The rise of point k+1 from the gap before it and the rise of point k.
#[inline]
pub(crate) fn next_rise(gap_ms: f64, rise_ms: f64) -> f64 {
    (gap_ms + (1.0 - SOA_SLOPE) * rise_ms - SOA_INTERCEPT_MS) / (1.0 + SOA_SLOPE)
}

/// The rises `x_k` for points peaking at `peaks_ms`, written to `rises`
/// (resized to `peaks_ms.len()`); fails at the first rise below `min_ms`.
pub(crate) fn rises_into(peaks_ms: &[f64], min_ms: f64, rises: &mut Vec<f64>) -> Result<(), Infeasible> {
    rises.clear();
    rises.push(0.0);
    for (k, w) in peaks_ms.windows(2).enumerate() {
        let x = next_rise(w[1] - w[0], rises[k]);
        // A NaN rise (from a NaN gap) is refused too.
        if x.is_nan() || x < min_ms {
            return Err(Infeasible { point: k + 1 });
        }
        rises.push(x);
    }
    Ok(())
}

/// Schedules points that peak at `peaks_ms` (non-decreasing; the first is the
/// stroke's start, 0, and the last its end, T) with the apparent-motion model.
/// Every rise must be at least `min_ms` (use `0.0` for the bare model).
///
/// ```
/// use taxel_compiler::brush::apparent_motion;
/// let t = apparent_motion(&[0.0, 142.857, 571.429, 750.0, 1000.0], 0.0).unwrap();
/// assert!((t[1].onset_ms - 70.465).abs() < 1e-3);
/// assert!((t[4].duration_ms - 291.341).abs() < 1e-3);
/// ```
pub fn apparent_motion(peaks_ms: &[f64], min_ms: f64) -> Result<Vec<Timing>, Infeasible> {
    if peaks_ms.len() < 2 {
        return Err(Infeasible { point: peaks_ms.len() });
    }
    let mut rises = Vec::with_capacity(peaks_ms.len());
    rises_into(peaks_ms, min_ms, &mut rises)?;
    Ok(peaks_ms
        .iter()
        .enumerate()
        .map(|(k, &tau)| {
            let x = rises[k];
            let fall = rises.get(k + 1).copied().unwrap_or(0.0);
            Timing { peak_ms: tau, onset_ms: tau - x, duration_ms: x + fall }
        })
        .collect())
}

/// Whether points at `fractions` of a stroke (0 first, 1 last) can be
/// scheduled over `duration_ms` with every rise at least `min_ms`.
pub fn feasible(fractions: &[f64], duration_ms: f64, min_ms: f64) -> bool {
    let mut rise = 0.0;
    for w in fractions.windows(2) {
        rise = next_rise((w[1] - w[0]) * duration_ms, rise);
        if rise.is_nan() || rise < min_ms {
            return false;
        }
    }
    true
}

/// The shortest stroke duration (ms) over which points at `fractions` of the
/// stroke can all be scheduled with rises of at least `min_ms`, found by
/// bisection (feasibility is monotone in the duration) and rounded up to the
/// next 0.01 ms so that the value itself is feasible. `None` when even 10⁹ ms
/// is not enough (two points at the same place along the path).
pub fn shortest_duration(fractions: &[f64], min_ms: f64) -> Option<f64> {
    if fractions.len() < 2 {
        return Some(0.0);
    }
    let mut hi = 100.0;
    while !feasible(fractions, hi, min_ms) {
        hi *= 2.0;
        if hi > 1e9 {
            return None;
        }
    }
    let mut lo = 0.0;
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if feasible(fractions, mid, min_ms) {
            hi = mid;
        } else {
            lo = mid;
        }
        if hi - lo < 1e-6 {
            break;
        }
    }
    let mut rounded = (hi * 100.0).ceil() / 100.0;
    while !feasible(fractions, rounded, min_ms) {
        rounded += 0.01;
    }
    Some(rounded)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_points_need_more_than_the_intercept() {
        // x_1 = (T − 47.3) / 1.32 ≥ h  ⇔  T ≥ 47.3 + 1.32 h.
        let t = shortest_duration(&[0.0, 1.0], 1.0).unwrap();
        assert!((t - 48.62).abs() < 0.011, "{t}");
        assert!(feasible(&[0.0, 1.0], t, 1.0));
        assert!(!feasible(&[0.0, 1.0], 48.6, 1.0));
    }

    #[test]
    fn soa_law_holds_between_consecutive_points() {
        let t = apparent_motion(&[0.0, 300.0, 450.0, 900.0, 1200.0], 0.0).unwrap();
        for k in 0..4 {
            let soa = t[k + 1].onset_ms - t[k].onset_ms;
            assert!((soa - (0.32 * t[k].duration_ms + 47.3)).abs() < 1e-9);
        }
        assert!((t[4].onset_ms + t[4].duration_ms - 1200.0).abs() < 1e-9);
    }

    #[test]
    fn crowded_points_are_infeasible() {
        assert_eq!(apparent_motion(&[0.0, 10.0, 20.0, 100.0], 1.0).unwrap_err(), Infeasible { point: 1 });
        assert!(apparent_motion(&[0.0], 0.0).is_err());
    }
}
