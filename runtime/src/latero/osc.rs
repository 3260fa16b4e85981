//! Oscillator arithmetic for the per-tick path: exact phase from an integer
//! tick, and a cosine cheap enough to run for every actuator of every layer.
//!
//! The cosine is a polynomial, not `libm::cosf`, because a frame evaluates up
//! to a few hundred of them and must stay well under a microsecond on a
//! desktop-class core (and stay cheap on a Cortex-M4F). Its error is below
//! 1e-6, a thousandth of one 10-bit output step (1/1023); the unit test
//! `cos_turns_error_is_far_below_one_output_step` measures it against `f64::cos`.

use taxel_format::{MilliHertz, Tick};

/// Adding and subtracting 1.5 · 2²³ rounds an `f32` of magnitude below 2²²
/// to the nearest integer with plain arithmetic (no `floorf`, which is a
/// library call on targets without a rounding instruction).
const ROUND_MAGIC: f32 = 12_582_912.0;

const TAU: f64 = core::f64::consts::TAU;
// Taylor coefficients of sin(2π z) in powers of z; with |z| ≤ ¼ the first
// omitted term, (π/2)¹³/13!, is 3.6e-8.
const S1: f32 = TAU as f32;
const S3: f32 = (-(TAU * TAU * TAU) / 6.0) as f32;
const S5: f32 = (TAU * TAU * TAU * TAU * TAU / 120.0) as f32;
const S7: f32 = (-(TAU * TAU * TAU * TAU * TAU * TAU * TAU) / 5_040.0) as f32;
const S9: f32 = (TAU * TAU * TAU * TAU * TAU * TAU * TAU * TAU * TAU / 362_880.0) as f32;
const S11: f32 = (-(TAU * TAU * TAU * TAU * TAU * TAU * TAU * TAU * TAU * TAU * TAU) / 39_916_800.0) as f32;

/// `cos(2π u)`, for `|u| < 2²²` turns (larger or non-finite `u` give an
/// unspecified value; callers reduce their phases first).
#[inline(always)]
pub(crate) fn cos_turns(u: f32) -> f32 {
    // x in [-½, ½] turns, then cos(2πx) = sin(2π(¼ − |x|)) with the sine's
    // argument in [-¼, ¼] turns, where its odd Taylor series converges fast.
    let x = u - ((u + ROUND_MAGIC) - ROUND_MAGIC);
    let z = 0.25 - f32::from_bits(x.to_bits() & 0x7fff_ffff);
    let z2 = z * z;
    z * (S1 + z2 * (S3 + z2 * (S5 + z2 * (S7 + z2 * (S9 + z2 * S11)))))
}

/// The oscillator phase at `tick`, in turns in `[0, 1)`: exactly
/// `(tick · mhz) mod (rate_hz · 1000)` divided by `rate_hz · 1000`.
///
/// `tick` is reduced modulo `rate_hz · 1000` before the product, which keeps
/// the arithmetic in `u64` without changing the residue, so the phase is
/// exact for every tick a `u64` can count: hour 24 sounds like hour 0.
#[inline]
pub(crate) fn phase_turns(tick: Tick, freq: MilliHertz, rate_hz: u32) -> f32 {
    let m = (rate_hz as u64 * 1000).max(1);
    // (tick mod m) < 2^30 and mhz < 2^32, so the product fits in u64.
    let p = (tick.0 % m) * freq.0 as u64 % m;
    (p as f64 / m as f64) as f32
}

/// The largest integer not above `v`, saturating at the `i32` range (NaN gives 0).
#[inline]
pub(crate) fn floor_i32(v: f32) -> i32 {
    let t = v as i32;
    if (t as f32) > v { t.saturating_sub(1) } else { t }
}

/// The smallest integer not below `v`, saturating at the `i32` range (NaN gives 0).
#[inline]
pub(crate) fn ceil_i32(v: f32) -> i32 {
    let t = v as i32;
    if (t as f32) < v { t.saturating_add(1) } else { t }
}

/// `v − floor(v)` in `f64`, in `[0, 1)` for finite `v`.
#[inline]
pub(crate) fn frac64(v: f64) -> f64 {
    let f = v - libm::floor(v);
    if f >= 1.0 { 0.0 } else { f }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cos_turns_error_is_far_below_one_output_step() {
        // Dense sweep over the phases the player produces (|u| up to a few
        // hundred turns) plus exact quarter turns.
        let mut worst = 0.0f64;
        let n = 2_000_000;
        for k in 0..=n {
            let u = -300.0 + 600.0 * k as f64 / n as f64;
            let got = cos_turns(u as f32) as f64;
            // Compare against the cosine of the f32 actually passed in.
            let want = (core::f64::consts::TAU * (u as f32) as f64).cos();
            worst = worst.max((got - want).abs());
        }
        for q in -8..=8 {
            let u = q as f64 * 0.25;
            let want = (core::f64::consts::TAU * u).cos();
            worst = worst.max((cos_turns(u as f32) as f64 - want).abs());
        }
        // One 10-bit step of δ = ½ + ½ cos is 1/1023 ≈ 9.8e-4; demand 1000x less.
        assert!(worst < 1.0e-6, "worst cos_turns error {worst:e}");
    }

    #[test]
    fn phase_is_exact_and_periodic() {
        let f = MilliHertz(50_000);
        assert_eq!(phase_turns(Tick(0), f, 1000), 0.0);
        assert_eq!(phase_turns(Tick(5), f, 1000), 0.25);
        assert_eq!(phase_turns(Tick(10), f, 1000), 0.5);
        assert_eq!(phase_turns(Tick(86_400_000), f, 1000), 0.0);
        assert_eq!(phase_turns(Tick(86_400_005), f, 1000), 0.25);
        // Beyond where tick · mhz would overflow u64.
        let big = u64::MAX - 7;
        let m = 1_000_000u128;
        let want = (big as u128 * 50_000 % m) as f64 / m as f64;
        assert_eq!(phase_turns(Tick(big), f, 1000) as f64, want as f32 as f64);
    }

    #[test]
    fn floor_and_ceil_match_std() {
        for v in [-2.5f32, -2.0, -0.1, 0.0, 0.1, 1.0, 1.9, 1e9, -1e9] {
            assert_eq!(floor_i32(v), v.floor() as i32, "{v}");
            assert_eq!(ceil_i32(v), v.ceil() as i32, "{v}");
        }
        assert_eq!(floor_i32(f32::NAN), 0);
        assert_eq!(floor_i32(-1e30), i32::MIN);
        assert_eq!(ceil_i32(1e30), i32::MAX);
    }
}
