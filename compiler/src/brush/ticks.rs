//! Step 5: the unquantised schedule in integer ticks of the profile's rate.
//!
//! Rounding rule: every *absolute* instant (stroke start + time within the
//! stroke, in milliseconds) becomes the nearest tick, halves rounding up
//! (`floor(ms · rate / 1000 + 0.5)`); stored times are differences of rounded
//! instants. Rounding is monotone and commutes with whole-tick shifts, so
//! onsets never decrease, every peak stays inside its point's activity, a
//! point lasting at least one tick keeps at least one tick, and the stroke's
//! last point ends exactly on the stroke's last tick, within half a tick of T.
//! Consecutive strokes in document order share their boundary tick, so they
//! neither overlap nor leave a gap.

use taxel_format::{ActuatorIndex, Drive, MilliHertz, Mm, Stroke, StrokePoint, Tick};

use super::PlannedStroke;

/// Why a planned stroke does not fit in a stroke table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TickError {
    /// The stroke is shorter than one tick of the profile.
    TooShort,
    /// The stroke starts or lasts longer than the table can count.
    TooLong,
    /// The carrier frequency cannot be stored.
    BadCarrier,
}

impl core::fmt::Display for TickError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            TickError::TooShort => "the stroke is shorter than one tick of the profile",
            TickError::TooLong => "the stroke starts or lasts longer than a stroke table can count at this rate",
            TickError::BadCarrier => "the carrier frequency cannot be stored",
        })
    }
}

impl std::error::Error for TickError {}

/// The tick nearest to the instant `ms` (halves round up), as a float so that
/// range checks come before the conversion.
pub fn tick_of(ms: f64, rate_hz: u32) -> f64 {
    (ms * rate_hz as f64 / 1000.0 + 0.5).floor()
}

/// Quantises one planned stroke to a table entry.
pub fn quantise(plan: &PlannedStroke, rate_hz: u32, source: Option<u32>) -> Result<Stroke, TickError> {
    let start = tick_of(plan.start_ms, rate_hz);
    let end = tick_of(plan.start_ms + plan.duration_ms, rate_hz);
    // Keep every tick value exactly representable and every duration in a u32.
    if !(start >= 0.0 && end < 2f64.powi(52)) || end - start > u32::MAX as f64 {
        return Err(TickError::TooLong);
    }
    if end <= start {
        return Err(TickError::TooShort);
    }
    let rel = |ms: f64| (tick_of(plan.start_ms + ms, rate_hz) - start).clamp(0.0, end - start) as u32;
    let carrier = MilliHertz::from_hz(plan.freq_hz).filter(|m| m.0 > 0).ok_or(TickError::BadCarrier)?;
    let mut points = Vec::with_capacity(plan.points.len());
    for p in &plan.points {
        let onset = rel(p.onset_ms);
        let stop = rel(p.end_ms);
        if stop <= onset {
            // Cannot happen for a feasible plan (every activity lasts a tick); never emit it.
            return Err(TickError::TooShort);
        }
        points.push(StrokePoint {
            onset,
            duration: stop - onset,
            peak: rel(p.peak_ms).clamp(onset, stop),
            x: Mm(p.x_mm as f32),
            y: Mm(p.y_mm as f32),
            drives: p
                .drives
                .as_slice()
                .iter()
                .map(|d| Drive {
                    actuator: ActuatorIndex(d.actuator.0),
                    intensity: (d.intensity as f32).clamp(0.0, 1.0),
                })
                .collect(),
        });
    }
    Ok(Stroke {
        start: Tick(start as u64),
        duration: (end - start) as u32,
        carrier,
        intensity: (plan.intensity as f32).clamp(0.0, 1.0),
        source,
        points,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halves_round_up() {
        assert_eq!(tick_of(0.5, 1000), 1.0);
        assert_eq!(tick_of(0.49, 1000), 0.0);
        assert_eq!(tick_of(1000.0 / 7.0, 1000), 143.0);
        assert_eq!(tick_of(10.0, 48_000), 480.0);
    }
}
