//! Oscillator arithmetic for the per-tick path: exact phase from an integer
//! tick, and a cosine cheap enough to run for every actuator of every layer.
//!
//! The cosine is a polynomial, not `libm::cosf`, because a frame evaluates up
//! to a few hundred of them and must stay well under a microsecond on a
//! desktop-class core (and stay cheap on a Cortex-M4F). Its error is below
//! 1e-6, a thousandth of one 10-bit output step (1/1023); the unit test
//! `cos_turns_error_is_far_below_one_output_step` measures it against `f64::cos`.

use taxel_format::{MilliHertz, Tick};
use wide::f32x4;

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
    // Estrin's scheme: the same polynomial in three independent pairs, so
    // a lone evaluation (a dot) waits on a chain half as long as Horner's.
    let z4 = z2 * z2;
    let (a, b, c) = (S1 + z2 * S3, S5 + z2 * S7, S9 + z2 * S11);
    z * (a + z4 * (b + z4 * c))
}

/// [`cos_turns`] on four lanes at once, with the same polynomial and the
/// same rounding, so every lane equals the scalar result.
#[inline(always)]
pub(crate) fn cos_turns4(u: f32x4) -> f32x4 {
    let magic = f32x4::splat(ROUND_MAGIC);
    let x = u - ((u + magic) - magic);
    let z = f32x4::splat(0.25) - x.abs();
    let z2 = z * z;
    let z4 = z2 * z2;
    let s = |c: f32| f32x4::splat(c);
    let (a, b, c) = (s(S1) + z2 * s(S3), s(S5) + z2 * s(S7), s(S9) + z2 * s(S11));
    z * (a + z4 * (b + z4 * c))
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

/// The integer nearest to `v` (ties to even), for `|v| ≤ 2²²`: adding
/// 1.5 · 2²³ leaves it in the low mantissa bits. Two instructions.
#[inline(always)]
pub(crate) fn round_small(v: f32) -> i32 {
    (v + ROUND_MAGIC).to_bits().wrapping_sub(ROUND_MAGIC.to_bits()) as i32
}

/// `v` clamped to `[lo, hi]`, NaN to `lo`. Comparisons rather than
/// `f32::max`/`min`, whose NaN rules cost a blend per call, so this is one
/// `maxss` and one `minss`.
#[inline(always)]
fn clamp_f(v: f32, lo: f32, hi: f32) -> f32 {
    let c = if v > lo { v } else { lo };
    if c < hi { c } else { hi }
}

/// `floor(v)` clamped to `lo..=hi` (NaN gives `lo`), for bounds within
/// ±2²²: the clamp comes first, in `f32`, so that the rounding trick of
/// [`round_small`] applies. Cheaper than a saturating `as` conversion.
#[inline(always)]
pub(crate) fn floor_in(v: f32, lo: i32, hi: i32) -> i32 {
    let c = clamp_f(v, lo as f32, hi as f32);
    let r = round_small(c);
    r - ((r as f32) > c) as i32
}

/// `ceil(v)` clamped to `lo..=hi` (NaN gives `lo`), like [`floor_in`].
#[inline(always)]
pub(crate) fn ceil_in(v: f32, lo: i32, hi: i32) -> i32 {
    let c = clamp_f(v, lo as f32, hi as f32);
    let r = round_small(c);
    r + ((r as f32) < c) as i32
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
    fn four_lane_cosine_equals_the_scalar_one() {
        for k in 0..100_000 {
            let u = -300.0 + k as f32 * 0.006_1;
            let lanes = [u, u + 0.1, -u * 0.37, u * 1e-3];
            let got = cos_turns4(f32x4::new(lanes)).to_array();
            for (g, &l) in got.iter().zip(&lanes) {
                assert_eq!(g.to_bits(), cos_turns(l).to_bits(), "u = {l}");
            }
        }
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
    fn clamped_floor_and_ceil_match_std() {
        let vals = [-3.5f32, -2.0, -1.5, -0.5, -0.1, 0.0, 0.1, 0.5, 0.9, 1.0, 1.5, 2.5, 6.99, 7.0, 7.01, 1e9, -1e9];
        for v in vals.into_iter().chain((0..4000).map(|k| -20.0 + k as f32 * 0.01)) {
            for (lo, hi) in [(0, 7), (-1, 7), (2, 5), (-4_000_000, 4_000_000)] {
                assert_eq!(floor_in(v, lo, hi), (v.floor() as i32).clamp(lo, hi), "floor {v} in {lo}..={hi}");
                assert_eq!(ceil_in(v, lo, hi), (v.ceil() as i32).clamp(lo, hi), "ceil {v} in {lo}..={hi}");
            }
        }
        for v in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let want = if v > 0.0 { 7 } else { 0 };
            assert_eq!(floor_in(v, 0, 7), want, "{v}");
            assert_eq!(ceil_in(v, 0, 7), want, "{v}");
        }
        assert_eq!(round_small(2.5), 2);
        assert_eq!(round_small(-2.5), -2);
        assert_eq!(round_small(3.5), 4);
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
