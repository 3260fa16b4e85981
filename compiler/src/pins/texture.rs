//! Grating textures on the pin grid.
//!
//! A grating's ridges become lines of raised pins that keep the grating's
//! orientation, quantised to what a square pin grid draws without jaggies:
//! horizontal, vertical and the two diagonals (0°, 45°, 90°, 135°). Its
//! period is the wavelength rounded to whole pins, at least 2 pins (a raised
//! line and a blank one) and at least 3 on a diagonal (at 2 a diagonal
//! pattern is a checkerboard with no direction). Ridges are anchored to the
//! image's origin, so every region with the same grating is in phase, as
//! SPEC.md asks of gratings.
//!
//! No published, tested texture set exists for 2.5 mm pin arrays
//! (`reference/pins.md`), so distinguishability is this rule, stated and
//! tested: two textures are told apart when their orientations differ, or,
//! at the same orientation, when their periods differ by at least 2 pins. Each
//! distinct grating of a drawing (by wavelength and angle) gets the pattern
//! nearest to what it asks that no earlier grating already holds, and a note
//! says when a grating had to move.

/// A pin texture: ridge orientation (0 = 0°, 1 = 45°, 2 = 90°, 3 = 135°) and period in pins.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) struct Pattern {
    pub orient: u8,
    pub period: u32,
}

/// Longest texture period considered, in pins.
pub(crate) const MAX_PERIOD: u32 = 8;

impl Pattern {
    /// The pattern a grating asks for at `pitch_mm`, before distinctness.
    pub fn wanted(wavelength_mm: f64, angle_deg: f64, pitch_mm: f64) -> Self {
        let orient = ((angle_deg / 45.0).round().rem_euclid(4.0)) as u8 % 4;
        let p = (wavelength_mm / pitch_mm).round();
        let period = if p.is_finite() { p.clamp(Self::min_period(orient) as f64, MAX_PERIOD as f64) as u32 } else { 2 };
        Pattern { orient, period }
    }

    fn min_period(orient: u8) -> u32 {
        if orient % 2 == 1 { 3 } else { 2 }
    }

    /// The ridge angle in degrees.
    pub fn angle_deg(self) -> u32 {
        self.orient as u32 * 45
    }

    /// Pin `(c, r)`'s place across the ridges: constant along a ridge,
    /// one more a pin across them.
    fn across(self, c: i64, r: i64) -> i64 {
        match self.orient {
            0 => r,
            // Ridges rising to the right on the page (y down): c + r constant.
            1 => c + r,
            2 => c,
            _ => c - r,
        }
    }

    /// Whether image pin `(c, r)` is on a ridge.
    pub fn raised(self, c: i64, r: i64) -> bool {
        self.across(c, r).rem_euclid(self.period as i64) == 0
    }

    /// Which ridge (or gap after it) pin `(c, r)` belongs to, counted across
    /// the ridges: two raised pins are on one ridge when these are equal.
    pub fn ridge(self, (c, r): (i64, i64)) -> i64 {
        self.across(c, r).div_euclid(self.period as i64)
    }

    /// Whether a reader can tell `self` from `other` (the rule above).
    pub fn distinct(self, other: Pattern) -> bool {
        self.orient != other.orient || self.period.abs_diff(other.period) >= 2
    }

    /// The nearest pattern to `self` that is distinct from every one in
    /// `taken`: orientation first (each 45° step costs more than any period
    /// change), then period. `None` when every pattern is taken.
    pub fn nearest_free(self, taken: &[Pattern]) -> Option<Pattern> {
        let mut best: Option<(u32, Pattern)> = None;
        for orient in 0..4u8 {
            let turn = (orient as i32 - self.orient as i32).rem_euclid(4);
            let turn = turn.min(4 - turn) as u32;
            for period in Self::min_period(orient)..=MAX_PERIOD {
                let cand = Pattern { orient, period };
                if taken.iter().any(|t| !cand.distinct(*t)) {
                    continue;
                }
                let cost = turn * 100 + period.abs_diff(self.period);
                if best.is_none_or(|(c, _)| cost < c) {
                    best = Some((cost, cand));
                }
            }
        }
        best.map(|(_, p)| p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wavelengths_round_to_whole_pins_and_angles_to_45_degrees() {
        assert_eq!(Pattern::wanted(6.0, 90.0, 2.5), Pattern { orient: 2, period: 2 });
        assert_eq!(Pattern::wanted(7.6, 0.0, 2.5), Pattern { orient: 0, period: 3 });
        assert_eq!(Pattern::wanted(10.0, 40.0, 2.5), Pattern { orient: 1, period: 4 });
        assert_eq!(Pattern::wanted(2.0, 135.0, 2.5), Pattern { orient: 3, period: 3 }, "diagonals need 3 pins");
        assert_eq!(Pattern::wanted(1.0, -90.0, 2.5), Pattern { orient: 2, period: 2 });
        assert_eq!(Pattern::wanted(500.0, 180.0, 2.5), Pattern { orient: 0, period: MAX_PERIOD });
    }

    #[test]
    fn taken_patterns_push_a_grating_to_the_nearest_distinct_one() {
        let want = Pattern { orient: 2, period: 3 };
        assert_eq!(want.nearest_free(&[]), Some(want));
        // Period 3 and 2 are too close to 2; 4 is the nearest at the same angle.
        assert_eq!(want.nearest_free(&[Pattern { orient: 2, period: 2 }]), Some(Pattern { orient: 2, period: 4 }));
        let all_vertical: Vec<_> = (2..=MAX_PERIOD).map(|period| Pattern { orient: 2, period }).collect();
        assert_eq!(want.nearest_free(&all_vertical).map(|p| p.orient % 2), Some(1), "a diagonal next");
    }
}
