//! Oscillator arithmetic for the per-tick path: exact phase from an integer
//! tick, and a cosine cheap enough to run for every actuator of every layer.
//!
//! The cosine is a polynomial, not `libm::cosf`, because a frame evaluates up
//! to a few hundred of them and must stay well under a microsecond on a
//! desktop-class core (and stay cheap on a Cortex-M4F). Its error is below
//! 1e-6, a thousandth of one 10-bit output step (1/1023); the unit test
//! `cos_turns_error_is_far_below_one_output_step` measures it against `f64::cos`.

use taxel_format::{MilliHertz, Tick};
use wide::bytemuck::cast;
use wide::{f32x4, i32x4};

/// Adding and subtracting 1.5 · 2²³ rounds an `f32` of magnitude below 2²²
/// to the nearest integer with plain arithmetic (no `floorf`, which is a
/// library call on targets without a rounding instruction).
const ROUND_MAGIC: f32 = 12_582_912.0;

// Coefficients of sin(2π z) ≈ z (S1 + S3 z² + S5 z⁴ + S7 z⁶ + S9 z⁸) for
// |z| ≤ ¼: a least-squares fit whose weights were raised where the error
// peaked until it levelled (near-minimax). Its error in exact arithmetic is
// 3.3e-9; in f32 the rounding dominates, and the unit test below measures
// the whole below 1e-6. One term fewer than the Taylor series, whose first
// omitted term after z⁹ would be 3.6e-6.
// A fitted value a hair below 2π (f32's 2π would add 1.2e-7 of error).
#[allow(clippy::approx_constant)]
const S1: f32 = 6.283_185;
const S3: f32 = -41.341_655;
const S5: f32 = 81.601_004;
const S7: f32 = -76.549_79;
const S9: f32 = 39.536_734;

/// `cos(2π u)`, for `|u| < 2²²` turns (larger or non-finite `u` give an
/// unspecified value; callers reduce their phases first).
#[inline(always)]
pub(crate) fn cos_turns(u: f32) -> f32 {
    // x in [-½, ½] turns, then cos(2πx) = sin(2π(¼ − |x|)) with the sine's
    // argument in [-¼, ¼] turns, where its odd Taylor series converges fast.
    let x = u - ((u + ROUND_MAGIC) - ROUND_MAGIC);
    let z = 0.25 - f32::from_bits(x.to_bits() & 0x7fff_ffff);
    let z2 = z * z;
    // Estrin's scheme: the polynomial in independent pairs, so a lone
    // evaluation (a dot) waits on a chain shorter than Horner's.
    let z4 = z2 * z2;
    let (a, b) = (S1 + z2 * S3, S5 + z2 * S7);
    z * (a + z4 * (b + z4 * S9))
}

/// [`cos_turns`] on four lanes at once, with the same polynomial and the
/// same rounding, so every lane equals the scalar result.
#[inline(always)]
pub(crate) fn cos_turns4(u: f32x4) -> f32x4 {
    let magic = f32x4::splat(ROUND_MAGIC);
    // The nearest whole turn off, x is within ½ turn.
    cos_turns4_half(u - ((u + magic) - magic))
}

/// Turns a tick into oscillator phases: the tick modulo one second's worth
/// of millihertz cycles, `m = rate_hz · 1000`, reduced once per frame, then
/// `(tick · mhz) mod m` per oscillator, all in integers. The reductions
/// multiply by a reciprocal taken at load (Barrett reduction) instead of
/// dividing, which is several times slower on x86-64 and a library call on
/// 32-bit cores.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PhaseClock {
    /// `rate_hz · 1000`, at most 10⁹ (profiles run at up to 1 MHz).
    m: u64,
    /// `⌊(2⁶⁴ − 1) / m⌋`.
    inv: u64,
    /// `1 / m`, to turn a residue into turns without a division.
    turn: f64,
}

impl PhaseClock {
    pub(crate) fn new(rate_hz: u32) -> Self {
        let m = (rate_hz as u64 * 1000).max(1);
        PhaseClock { m, inv: u64::MAX / m, turn: 1.0 / m as f64 }
    }

    /// `x mod m`. The quotient estimate `⌊x · inv / 2⁶⁴⌋` is at most
    /// `⌊x / m⌋` and short of it by at most 1, so one subtraction settles
    /// it: `inv = 2⁶⁴ / m − e` with `0 ≤ e ≤ 1`, so `x · inv / 2⁶⁴` is
    /// `x / m` less `x · e / 2⁶⁴`, which is below 1 for every `x < 2⁶⁴`.
    #[inline(always)]
    pub(crate) fn rem(&self, x: u64) -> u64 {
        let q = ((x as u128 * self.inv as u128) >> 64) as u64;
        let r = x.wrapping_sub(q.wrapping_mul(self.m));
        if r >= self.m { r - self.m } else { r }
    }

    /// The tick reduced modulo `m`: the same phase for every oscillator
    /// (every frequency is a whole number of millihertz), below 2³⁰.
    #[inline(always)]
    pub(crate) fn tick_in_second(&self, tick: Tick) -> u64 {
        self.rem(tick.0)
    }

    /// The phase of `freq` at a tick whose [`tick_in_second`](Self::tick_in_second)
    /// is `t`, in turns in `[0, 1)`: exactly `(t · mhz) mod m` over `m`,
    /// the residue in integers (`t < 2³⁰` and `mhz < 2³²`, so the product
    /// fits in u64), so the phase is the same for every tick a `u64` can
    /// count: hour 24 sounds like hour 0.
    #[inline(always)]
    pub(crate) fn phase(&self, t: u64, freq: MilliHertz) -> f32 {
        // The residue is below m ≤ 10⁹, so it converts through u32 (one
        // instruction, where a u64 takes several on x86-64).
        (self.rem(t * freq.0 as u64) as u32 as f64 * self.turn) as f32
    }
}

/// The oscillator phase at `tick`, in turns in `[0, 1)`, through a
/// [`PhaseClock`] (for callers with one tick and one oscillator).
#[cfg(test)]
pub(crate) fn phase_turns(tick: Tick, freq: MilliHertz, rate_hz: u32) -> f32 {
    let clock = PhaseClock::new(rate_hz);
    clock.phase(clock.tick_in_second(tick), freq)
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
#[cfg(test)]
#[inline(always)]
pub(crate) fn round_small(v: f32) -> i32 {
    (v + ROUND_MAGIC).to_bits().wrapping_sub(ROUND_MAGIC.to_bits()) as i32
}

/// `v` clamped to `[lo, hi]`, NaN to `lo`. Comparisons rather than
/// `f32::max`/`min`, whose NaN rules cost a blend per call, so this is one
/// `maxss` and one `minss`.
#[cfg(test)]
#[inline(always)]
fn clamp_f(v: f32, lo: f32, hi: f32) -> f32 {
    let c = if v > lo { v } else { lo };
    if c < hi { c } else { hi }
}

/// [`ceil_in`] on four lanes, each with its own bounds.
#[inline(always)]
pub(crate) fn ceil_in4(v: f32x4, lo: i32x4, hi: i32x4) -> i32x4 {
    // `fast_max` and `fast_min` return their second operand for a NaN lane:
    // max(NaN, lo) is lo, as in `ceil_in`.
    let c = v.fast_max(f32x4::from_i32x4(lo)).fast_min(f32x4::from_i32x4(hi));
    let m = f32x4::splat(ROUND_MAGIC);
    let r = cast::<f32x4, i32x4>(c + m) - i32x4::splat(ROUND_MAGIC.to_bits() as i32);
    // A true lane compares as −1.
    r - cast::<f32x4, i32x4>(f32x4::from_i32x4(r).simd_lt(c))
}

/// [`cos_turns4`] for `|u| ≤ ½` turn, where the reduction to the nearest
/// whole turn changes nothing: the same lanes, bit for bit, four operations
/// sooner. (It is [`cos_turns4`]'s polynomial.)
#[inline(always)]
pub(crate) fn cos_turns4_half(u: f32x4) -> f32x4 {
    sin_turns4_quarter(f32x4::splat(0.25) - u.abs())
}

/// The polynomial of [`cos_turns`], `sin(2π z)` for `|z| ≤ ¼` turn, on
/// four lanes. (Measured over every `f32` in `[¼, 0.45]`, beyond its
/// range, it stays within `[0.3, 1]`.)
#[inline(always)]
pub(crate) fn sin_turns4_quarter(z: f32x4) -> f32x4 {
    let z2 = z * z;
    let z4 = z2 * z2;
    let s = |c: f32| f32x4::splat(c);
    let (a, b) = (s(S1) + z2 * s(S3), s(S5) + z2 * s(S7));
    z * (a + z4 * (b + z4 * s(S9)))
}

/// `floor(v)` clamped to `lo..=hi` (NaN gives `lo`), for bounds within
/// ±2²²: the clamp comes first, in `f32`, so that the rounding trick of
/// [`round_small`] applies. Cheaper than a saturating `as` conversion.
#[cfg(test)]
#[inline(always)]
pub(crate) fn floor_in(v: f32, lo: i32, hi: i32) -> i32 {
    let c = clamp_f(v, lo as f32, hi as f32);
    let r = round_small(c);
    r - ((r as f32) > c) as i32
}

/// `floor(v)` on four lanes, for lanes within ±2²² (clamp them first):
/// the rounding and correction of `floor_in` (the scalar reference), lane by lane.
#[inline(always)]
pub(crate) fn floor4(v: f32x4) -> i32x4 {
    let r = cast::<f32x4, i32x4>(v + f32x4::splat(ROUND_MAGIC)) - i32x4::splat(ROUND_MAGIC.to_bits() as i32);
    // A true lane compares as −1.
    r + cast::<f32x4, i32x4>(f32x4::from_i32x4(r).simd_gt(v))
}

/// `ceil(v)` clamped to `lo..=hi` (NaN gives `lo`), like [`floor_in`].
#[cfg(test)]
#[inline(always)]
pub(crate) fn ceil_in(v: f32, lo: i32, hi: i32) -> i32 {
    let c = clamp_f(v, lo as f32, hi as f32);
    let r = round_small(c);
    r + ((r as f32) < c) as i32
}

/// 1.5 · 2⁵²: [`ROUND_MAGIC`]'s trick for `f64` below 2⁵¹ in magnitude.
const ROUND_MAGIC64: f64 = 6_755_399_441_055_744.0;

/// `v − floor(v)` in `f64`, in `[0, 1)` for finite `v`.
#[inline]
pub(crate) fn frac64(v: f64) -> f64 {
    // Below 2⁵¹ (every phase a page produces) by the rounding trick, which
    // is plain arithmetic; beyond it through `floor`.
    let fl = if v.abs() < 2_251_799_813_685_248.0 {
        let r = (v + ROUND_MAGIC64) - ROUND_MAGIC64;
        if r > v { r - 1.0 } else { r }
    } else {
        libm::floor(v)
    };
    let f = v - fl;
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

    /// The dot profile relies on this past the polynomial's range: on the
    /// plateau it takes the larger of the rim and the amplitude.
    #[test]
    fn quarter_turn_sine_stays_at_most_one_up_to_045() {
        let (lo, hi) = (0.25f32.to_bits(), 0.45f32.to_bits());
        let mut worst = 0.0f32;
        for b in (lo..=hi).step_by(4) {
            let z = [b, b + 1, b + 2, b + 3].map(|b| f32::from_bits(b.min(hi)));
            for v in sin_turns4_quarter(f32x4::new(z)).to_array() {
                worst = worst.max(v);
            }
        }
        assert!(worst <= 1.0, "largest value {worst}");
    }

    #[test]
    fn half_turn_cosine_equals_the_full_one() {
        for k in 0..=200_000 {
            let u = -0.5 + k as f32 * 5e-6;
            let lanes = [u, -u, u * 0.5, 0.5];
            assert_eq!(
                cos_turns4_half(f32x4::new(lanes)).to_array().map(f32::to_bits),
                cos_turns4(f32x4::new(lanes)).to_array().map(f32::to_bits),
                "u = {u}"
            );
        }
    }

    #[test]
    fn four_lane_ceil_equals_the_scalar_one() {
        let specials = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e9, -1e9, -0.0];
        for v in (0..8000).map(|k| -40.0 + k as f32 * 0.01).chain(specials) {
            for (lo, hi) in [(0, 7), (-1, 7), (2, 5), (-4_000_000, 4_000_000)] {
                let got = ceil_in4(f32x4::splat(v), i32x4::splat(lo), i32x4::splat(hi)).to_array();
                assert_eq!(got, [ceil_in(v, lo, hi); 4], "ceil {v} in {lo}..={hi}");
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
    fn barrett_reduction_equals_the_remainder() {
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        for rate in [1u32, 7, 999, 1000, 44_100, 65_536, 999_983, 1_000_000] {
            let clock = PhaseClock::new(rate);
            let m = rate as u64 * 1000;
            let edges =
                [0, 1, m - 1, m, m + 1, 2 * m - 1, u64::MAX, u64::MAX - 1, u64::MAX / m * m, u64::MAX / m * m - 1];
            for v in edges {
                assert_eq!(clock.rem(v), v % m, "{v} mod {m}");
            }
            for _ in 0..100_000 {
                // xorshift64: values over the whole u64 range.
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                assert_eq!(clock.rem(x), x % m, "{x} mod {m}");
                let small = x >> (x % 64);
                assert_eq!(clock.rem(small), small % m, "{small} mod {m}");
            }
        }
    }

    #[test]
    fn phase_equals_the_exact_fraction() {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        for rate in [1u32, 1000, 1_000_000] {
            let clock = PhaseClock::new(rate);
            let m = rate as u128 * 1000;
            for _ in 0..20_000 {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                let freq = MilliHertz((x >> 32) as u32);
                let want = (x as u128 * freq.0 as u128 % m) as f64 / m as f64;
                let got = clock.phase(clock.tick_in_second(Tick(x)), freq);
                // Within one f32 step of the exact fraction (`turn` is 1/m
                // rounded, so the last f64 bit may differ before the cast).
                assert!((got as f64 - want).abs() <= 0.5f64.powi(24), "tick {x} at {} mHz, {rate} Hz", freq.0);
                assert!((0.0..1.0).contains(&got));
            }
        }
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
    fn frac64_is_v_minus_its_floor() {
        let edges = [0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 2.5, -2.5, 1e-300, -1e-300, 1e15, -1e15 - 0.25];
        let big = [2f64.powi(51) - 0.5, -(2f64.powi(51) - 0.5), 2f64.powi(51), 2f64.powi(52) + 2.0, -1e300, 1e300];
        let sweep = (0..20_000).map(|k| (k as f64 - 10_000.0) * 0.123_456_789);
        for v in edges.into_iter().chain(big).chain(sweep) {
            let want = v - v.floor();
            let want = if want >= 1.0 { 0.0 } else { want };
            assert_eq!(frac64(v), want, "{v}");
            assert!((0.0..1.0).contains(&frac64(v)), "{v}");
        }
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
