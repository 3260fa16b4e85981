//! Vibration and grating layers: a mask sampled bilinearly at each actuator,
//! times the primitive's deflection (seed 000 eqs. 2 and 3).
//!
//! The kernel works on groups of [`LANES`] actuators of one row. Per actuator
//! it reads two packed sample pairs, the pair above it and the pair below
//! it; the eight reads of a group share one window whose bounds are checked
//! once, and the compiler proves each read in it in bounds, so the reads
//! themselves carry no check. It interpolates horizontally
//! in fixed point: the pair's 16-bit lanes are multiplied by the weights
//! `(W − w, w)` and added in one instruction (`pmaddwd` on x86-64). It then
//! interpolates vertically, and applies the primitive, in `f32` lanes.
//! The weights carry 14 bits, so the interpolated value is within 3·10⁻⁵ of
//! full scale of the exact bilinear one: a thirtieth of one 10-bit step.
//! (16-bit masks also drop their lowest sample bit, 1.5·10⁻⁵ of full scale.)

use taxel_format::{MaskKind, MaskView, MilliHertz};
use wide::bytemuck::{cast, cast_ref};
use wide::{f32x4, i16x8, i32x4, u8x16, u16x8, u32x4};

use super::osc::{cos_turns, cos_turns4, frac64, phase_turns};
use super::{Acc, Frame, LANES};

/// Columns whose taps are prepared together: a multiple of [`LANES`], small
/// so that the per-frame tap arrays cost a few stores to set up.
const CHUNK: usize = 16;
/// Groups of [`LANES`] columns in a chunk.
const GROUPS: usize = CHUNK / LANES;
/// The fixed-point unit of the horizontal weights: `(W − w, w)` fit in
/// `i16`, and a sample below 2¹⁵ times `W` fits in `i32`.
const W: i32 = 1 << 14;

/// What a mask modulates, with the per-layer constants computed at load.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Primitive {
    /// Eq. 2: adjacent actuators in antiphase at `freq`.
    Vibration { freq: MilliHertz },
    /// Eq. 3 with the page-angle decision: `u = (x sin θ + y cos θ) / λ`
    /// turns on the page (y down), which is the paper's `d / λ` after y is
    /// flipped (up to the sign of d, which the cosine ignores).
    Grating {
        /// `sin θ / λ` and `cos θ / λ`, per millimetre (f64 so that the
        /// phase at the array's corner is exact anywhere on the page).
        kx: f64,
        ky: f64,
        /// Phase change from one column, or one row, to the next, reduced
        /// to `[0, 1)` turns (an integer number of turns changes nothing).
        step_col: f32,
        step_row: f32,
    },
}

/// A vibration or grating layer prepared for playback.
#[derive(Debug, Clone, Copy)]
pub(crate) struct MaskLayer<'a> {
    primitive: Primitive,
    samples: &'a [u8],
    wide: bool,
    /// Bytes per mask row, and per sample (1 or 2).
    bpr: u32,
    bps: u32,
    /// Largest index of a left (top) tap: width − 2 (height − 2), or 0 for a
    /// mask one sample wide (tall), so that the tap and its right (lower)
    /// neighbour are both in the mask.
    amax: u32,
    jmax: u32,
    /// Largest sample index along x and y, as `f32`.
    wmax: f32,
    hmax: f32,
    /// Last row index.
    last_row: u32,
    x0: f32,
    y0: f32,
    x1: f32,
    y1: f32,
    px_per_mm: f32,
    /// What one unit of the fixed-point interpolation is worth in δ: the
    /// layer's amplitude over the mask's full-scale code, over `W`, times 2
    /// for 16-bit masks (whose samples lose their lowest bit to fit `i16`).
    unit: f32,
}

impl<'a> MaskLayer<'a> {
    pub(crate) fn new(m: &MaskView<'a>, pitch_x: f32, pitch_y: f32) -> Self {
        let primitive = match m.kind {
            MaskKind::Vibration { freq } => Primitive::Vibration { freq },
            MaskKind::Grating { wavelength, angle_deg } => {
                let theta = (angle_deg as f64).to_radians();
                let lambda = wavelength.0 as f64;
                let kx = libm::sin(theta) / lambda;
                let ky = libm::cos(theta) / lambda;
                Primitive::Grating {
                    kx,
                    ky,
                    step_col: frac64(kx * pitch_x as f64) as f32,
                    step_row: frac64(ky * pitch_y as f64) as f32,
                }
            }
        };
        let ppm = m.px_per_mm;
        let wide = m.bits == 16;
        let bps = if wide { 2 } else { 1 };
        let scale = m.amplitude / m.full_scale() as f32;
        MaskLayer {
            primitive,
            samples: m.sample_bytes(),
            wide,
            // A mask holds at most 2²⁶ samples (`MAX_MASK_SAMPLES`), 2²⁷
            // bytes, so every byte offset fits in u32 and in i32 lanes.
            bpr: bps * m.width,
            bps,
            amax: m.width.saturating_sub(2),
            jmax: m.height.saturating_sub(2),
            wmax: m.width.saturating_sub(1) as f32,
            hmax: m.height.saturating_sub(1) as f32,
            last_row: m.height.saturating_sub(1),
            x0: m.origin_x.0,
            y0: m.origin_y.0,
            x1: (m.origin_x.0 as f64 + m.width as f64 / ppm as f64) as f32,
            y1: (m.origin_y.0 as f64 + m.height as f64 / ppm as f64) as f32,
            px_per_mm: ppm,
            unit: scale * if wide { 2.0 } else { 1.0 } / W as f32,
        }
    }

    /// Adds this layer's deflection for rows `f.r0..f.r1` to `acc`.
    #[inline]
    pub(crate) fn accumulate(&self, f: &Frame, acc: &mut Acc) {
        // `pairs(b0, b1, taps)` reads, for each of a group's four taps, the
        // sample at byte offset b + tap and its right neighbour, for the
        // mask rows starting at b0 (above the actuators) and b1 (below),
        // and returns them as (left, right) i16 lanes. The caller passes
        // b0 ≤ b1 and taps that grow, clamped to the last one, so all eight
        // pairs lie in the window that ends with the last tap's pair in row
        // b1: one check of that window, and the compiler proves every read
        // in it in bounds (a tap is at most width − 2, so for a valid layer
        // the check always passes; if it ever failed the group would add 0).
        let s = self.samples;
        if self.wmax == 0.0 {
            // A mask one sample wide: the sample twice (its right weight is 0).
            let Some(lim) = s.len().checked_sub(self.bps as usize) else { return };
            let one = |a: u32| -> u32 {
                let a = (a as usize).min(lim);
                let v = if self.wide {
                    s.get(a..a + 2).map_or(0, |s| u16::from_le_bytes([s[0], s[1]]) >> 1)
                } else {
                    s.get(a).map_or(0, |&p| p as u16)
                };
                v as u32 * 0x0001_0001
            };
            self.accumulate_in(f, acc, |b0, b1, t: [u32; LANES]| {
                (cast(u32x4::new(t.map(|t| one(b0 + t)))), cast(u32x4::new(t.map(|t| one(b1 + t)))))
            })
        } else if self.wide {
            // 16-bit samples lose their lowest bit to fit the i16 lanes; the
            // reads share one window, as for 8-bit samples below.
            let half = |v: u32x4| -> i16x8 { cast((v >> 1) & u32x4::splat(0x7fff_7fff)) };
            self.accumulate_in(f, acc, |b0, b1, t: [u32; LANES]| {
                let (b0, b1, last) = (b0 as usize, b1 as usize, t[LANES - 1] as usize);
                let Some(win) = s.get(..b1 + last + 4) else {
                    return (i16x8::ZERO, i16x8::ZERO);
                };
                let pair = |a: usize| win.get(a..a + 4).map_or(0, |p| u32::from_le_bytes([p[0], p[1], p[2], p[3]]));
                let t = t.map(|t| (t as usize).min(last));
                (half(u32x4::new(t.map(|t| pair(b0 + t)))), half(u32x4::new(t.map(|t| pair(b1 + t)))))
            })
        } else {
            // Eight u16 pairs fill one u16x8, whose bytes widen to two i16x8.
            // The pairs lie between the first tap of the upper row and the
            // end of the last tap's pair in the lower row: one check of that
            // window covers all eight reads (the caller passes b0 ≤ b1 and
            // taps bounded by the last one).
            self.accumulate_in(f, acc, |b0, b1, t: [u32; LANES]| {
                let (b0, b1, last) = (b0 as usize, b1 as usize, t[LANES - 1] as usize);
                let Some(win) = s.get(..b1 + last + 2) else {
                    return (i16x8::ZERO, i16x8::ZERO);
                };
                let pair = |a: usize| win.get(a..a + 2).map_or(0, |p| u16::from_le_bytes([p[0], p[1]]));
                let t = t.map(|t| (t as usize).min(last));
                let bytes: u8x16 = cast(u16x8::new([
                    pair(b0 + t[0]),
                    pair(b0 + t[1]),
                    pair(b0 + t[2]),
                    pair(b0 + t[3]),
                    pair(b1 + t[0]),
                    pair(b1 + t[1]),
                    pair(b1 + t[2]),
                    pair(b1 + t[3]),
                ]));
                (i16x8::from_u8x16_low(bytes), i16x8::from_u8x16_high(bytes))
            })
        }
    }

    /// The columns inside both the surface and the mask's box are one run
    /// (positions grow with the column), and so are the rows; both are
    /// taken [`CHUNK`] at a time. For a chunk of columns the horizontal taps
    /// and weights are prepared once, for a chunk of rows the vertical ones,
    /// both [`LANES`] at a time. Then each group of columns runs down the
    /// rows with its four taps in registers: eight `pair` reads, two
    /// `pmaddwd`, the vertical step and the primitive per row.
    #[inline(always)]
    fn accumulate_in(&self, f: &Frame, acc: &mut Acc, pairs: impl Fn(u32, u32, [u32; LANES]) -> (i16x8, i16x8)) {
        let mut c = f.col_lo;
        while c < f.col_hi && f.col_x(c) < self.x0 {
            c += 1;
        }
        let c_lo = c;
        while c < f.col_hi && f.col_x(c) < self.x1 {
            c += 1;
        }
        let c_hi = c;
        let mut r = f.r0.max(f.row_lo);
        let r_end = f.r1.min(f.row_hi);
        while r < r_end && f.row_y(r) < self.y0 {
            r += 1;
        }
        let r_lo = r;
        while r < r_end && f.row_y(r) < self.y1 {
            r += 1;
        }
        let r_hi = r;
        if c_lo >= c_hi || r_lo >= r_hi {
            return;
        }
        // Eq. 2's two values in units of the interpolation: ½ + ½ cos where
        // row and column parities differ, ½ − ½ cos where they agree.
        let (differ, same) = match self.primitive {
            Primitive::Vibration { freq } => {
                let c = cos_turns(phase_turns(f.tick, freq, f.rate_hz));
                ((0.5 + 0.5 * c) * self.unit, (0.5 - 0.5 * c) * self.unit)
            }
            Primitive::Grating { .. } => (0.0, 0.0),
        };
        let parity = [f32x4::new([same, differ, same, differ]), f32x4::new([differ, same, differ, same])];
        // Eq. 3's phase at actuator (f.r0, c_lo), reduced in f64 once per
        // frame; the other actuators add whole multiples of the reduced steps.
        let (base, step_col, step_row) = match self.primitive {
            Primitive::Grating { kx, ky, step_col, step_row } => {
                (frac64(kx * f.col_x(c_lo) as f64 + ky * f.row_y(f.r0) as f64) as f32, step_col, step_row)
            }
            Primitive::Vibration { .. } => (0.0, 0.0, 0.0),
        };
        let lanes = f32x4::new([0.0, 1.0, 2.0, 3.0]);
        let lane_index = i32x4::new([0, 1, 2, 3]);
        let unit = f32x4::splat(self.unit);
        let mut start = c_lo;
        while start < c_hi {
            let n = (c_hi - start).min(CHUNK);
            let groups = n.div_ceil(LANES).min(GROUPS);
            // Per column: byte offset of the left tap, and the weights of
            // the left and right samples as (W − w, w) i16 pairs. Pixel
            // centres sit at (i + ½) / px_per_mm; between the box edge and
            // the first centre the edge sample holds. Lanes past the run
            // take its last tap with weights 0, so they read in bounds and
            // add nothing.
            let mut taps = [[0u32; LANES]; GROUPS];
            let mut weights = [i16x8::ZERO; GROUPS];
            let last_x = f.col_x(c_hi - 1);
            for g in 0..groups {
                let first = start + g * LANES;
                // The same formula as `Frame::col_x`, lane by lane.
                let cols = f32x4::from_i32x4(i32x4::splat(first as i32) + lane_index);
                let x = (f32x4::splat(f.x_first) + cols * f.pitch_x).fast_min(f32x4::splat(last_x));
                let fx = ((x - self.x0) * self.px_per_mm - 0.5).fast_max(f32x4::ZERO).fast_min(f32x4::splat(self.wmax));
                let a = (fx - 0.5).fast_round_int().min(i32x4::splat(self.amax as i32));
                let wi = ((fx - f32x4::from_i32x4(a)) * W as f32).fast_round_int();
                let real = lane_index.simd_lt(i32x4::splat((n - g * LANES) as i32));
                let pairs = (i32x4::splat(W) - wi) | (wi << 16);
                weights[g] = cast(pairs & real);
                taps[g] = cast::<i32x4, [u32; LANES]>(a * self.bps as i32);
            }
            let col_phase = (start - c_lo) as u32 as f32 * step_col;
            let mut rs = r_lo;
            while rs < r_hi {
                let m = (r_hi - rs).min(CHUNK);
                // Per row: byte offsets of the mask rows above and below it,
                // and the weight of the lower one.
                let (mut off0, mut off1, mut wy) =
                    ([[0u32; LANES]; GROUPS], [[0u32; LANES]; GROUPS], [f32x4::ZERO; GROUPS]);
                for q in 0..m.div_ceil(LANES).min(GROUPS) {
                    let rows = f32x4::from_i32x4(i32x4::splat((rs + q * LANES) as i32) + lane_index);
                    let y = f32x4::splat(f.y_first) + rows * f.pitch_y;
                    let fy =
                        ((y - self.y0) * self.px_per_mm - 0.5).fast_max(f32x4::ZERO).fast_min(f32x4::splat(self.hmax));
                    let j0 = (fy - 0.5).fast_round_int().min(i32x4::splat(self.jmax as i32));
                    let j1 = (j0 + 1).min(i32x4::splat(self.last_row as i32));
                    wy[q] = fy - f32x4::from_i32x4(j0);
                    off0[q] = cast(j0 * self.bpr as i32);
                    off1[q] = cast(j1 * self.bpr as i32);
                }
                let (off0, off1): (&[u32; CHUNK], &[u32; CHUNK]) = (cast_ref(&off0), cast_ref(&off1));
                let wy: &[f32; CHUNK] = cast_ref(&wy);
                for g in 0..groups {
                    // The taps of a group only grow (columns move right):
                    // saying so with a min lets each row check one window.
                    let (taps, w) = (taps[g], weights[g]);
                    let taps = taps.map(|t| t.min(taps[LANES - 1]));
                    let group_phase = base + col_phase + (g * LANES) as u32 as f32 * step_col;
                    let cols = start + g * LANES;
                    for i in 0..m.min(CHUNK) {
                        let (b0, b1, r) = (off0[i].min(off1[i]), off1[i], rs + i);
                        let (top, bot) = pairs(b0, b1, taps);
                        let t = f32x4::from_i32x4(top.dot(w));
                        let b = f32x4::from_i32x4(bot.dot(w));
                        let v = t + (b - t) * wy[i];
                        let v = match self.primitive {
                            // Eq. 2: column `cols + lane` differs in parity
                            // from row r when r + cols + lane is odd.
                            Primitive::Vibration { .. } => v * parity[(r + cols) & 1],
                            Primitive::Grating { .. } => {
                                let phase =
                                    f32x4::splat(group_phase + (r - f.r0) as u32 as f32 * step_row) + lanes * step_col;
                                v * (f32x4::splat(0.5) + f32x4::splat(0.5) * cos_turns4(phase)) * unit
                            }
                        };
                        // Lanes past the row's last column carry 0 and land
                        // in the accumulator's padding or the next row.
                        let k = (r - f.r0) * f.cols + cols;
                        if let Some(out) = acc.get_mut(k..k + LANES).and_then(|s| <&mut [f32; LANES]>::try_from(s).ok())
                        {
                            *out = (f32x4::new(*out) + v).to_array();
                        }
                    }
                }
                rs += m;
            }
            start += n;
        }
    }
}
