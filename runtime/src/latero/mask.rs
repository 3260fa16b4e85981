//! Vibration and grating layers: a mask sampled bilinearly at each actuator,
//! times the primitive's deflection (seed 000 eqs. 2 and 3).
//!
//! The kernel works on groups of [`LANES`] actuators of one row. Per actuator
//! it reads two packed sample pairs, the pair above it and the pair below
//! it; the eight reads of a group share one window whose bounds are checked
//! once, and the compiler proves each read in it in bounds, so the reads
//! themselves carry no check. (On x86-64 each 8-bit pair goes from memory
//! straight into its 16-bit lane, `pinsrw`; elsewhere it is read as the
//! first half of a u32, which loads straight into a vector lane, and the
//! lanes' low halves are then gathered into one vector, see
//! `quads_to_pairs`.) It interpolates horizontally
//! in fixed point: the pair's 16-bit lanes are multiplied by the weights
//! `(W − w, w)` and added in one instruction (`pmaddwd` on x86-64). It then
//! interpolates vertically, and applies the primitive, in `f32` lanes.
//! The weights carry 14 bits, so the interpolated value is within 3·10⁻⁵ of
//! full scale of the exact bilinear one: a thirtieth of one 10-bit step.
//! (16-bit masks also drop their lowest sample bit, 1.5·10⁻⁵ of full scale.)

use taxel_format::{MaskKind, MaskView, MilliHertz};
use wide::bytemuck::cast;
use wide::{f32x4, i16x8, i32x4, u8x16, u16x8, u32x4};

use super::osc::{cos_turns, cos_turns4, frac64};
use super::{Acc, Frame, LANES, add_lanes};

/// Rows whose vertical taps are prepared together: a multiple of [`LANES`].
const ROWS: usize = 8;
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

impl Primitive {
    /// The primitive of a layer of this kind on an array of this pitch (mm).
    pub(crate) fn of(kind: MaskKind, pitch_x: f32, pitch_y: f32) -> Self {
        match kind {
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
        }
    }
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
    /// The box's top-left corner, as scalars for the tap arithmetic (the
    /// same values as `bounds`' lanes 0 and 2).
    x0: f32,
    y0: f32,
    /// The box, `[x0, x1, y0, y1]`, for [`Frame::runs`].
    bounds: f32x4,
    px_per_mm: f32,
    /// What one unit of the fixed-point interpolation is worth in δ: the
    /// layer's amplitude over the mask's full-scale code, over `W`, times 2
    /// for 16-bit masks (whose samples lose their lowest bit to fit `i16`).
    unit: f32,
}

impl<'a> MaskLayer<'a> {
    pub(crate) fn new(m: &MaskView<'a>, pitch_x: f32, pitch_y: f32) -> Self {
        let primitive = Primitive::of(m.kind, pitch_x, pitch_y);
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
            bounds: f32x4::new([
                m.origin_x.0,
                (m.origin_x.0 as f64 + m.width as f64 / ppm as f64) as f32,
                m.origin_y.0,
                (m.origin_y.0 as f64 + m.height as f64 / ppm as f64) as f32,
            ]),
            px_per_mm: ppm,
            unit: scale * if wide { 2.0 } else { 1.0 } / W as f32,
        }
    }

    /// Adds this layer's deflection for rows `f.r0..f.r1` to `acc`.
    #[inline(always)]
    pub(crate) fn accumulate(&self, f: &Frame, acc: &mut Acc) {
        accumulate_mask(self, f, acc)
    }

    /// The body of [`accumulate_mask`].
    #[inline(always)]
    fn accumulate_body(&self, f: &Frame, acc: &mut Acc) {
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
            // On x86-64 each pair goes from memory into its 16-bit lane
            // (`pairs_to_lanes`); elsewhere each is read as the first two
            // bytes of a u32, which goes straight into a vector lane, and
            // `quads_to_pairs` gathers the eight into one vector. The
            // vector's bytes then widen to two i16x8. The reads lie
            // between the first tap of the upper row and the end of the last
            // tap's u32 in the lower row: one check of that window covers
            // all eight (the caller passes b0 ≤ b1 and taps bounded by the
            // last one). Only near the end of the samples, where the u32s
            // would run past them, are the pairs read as u16s.
            self.accumulate_in(f, acc, |b0, b1, t: [u32; LANES]| {
                let (b0, b1, last) = (b0 as usize, b1 as usize, t[LANES - 1] as usize);
                let t = t.map(|t| (t as usize).min(last));
                let bytes: u8x16 = if let Some(win) = s.get(..b1 + last + 4) {
                    #[cfg(target_arch = "x86_64")]
                    {
                        // The first pair as a u32, the others as u16s: see `pairs_to_lanes`.
                        let pair =
                            |a: usize| win.get(a..a + 2).map_or(0, |p| i32::from(u16::from_le_bytes([p[0], p[1]])));
                        let quad =
                            |a: usize| win.get(a..a + 4).map_or(0, |p| i32::from_le_bytes([p[0], p[1], p[2], p[3]]));
                        let mut top = t.map(|t| pair(b0 + t));
                        top[0] = quad(b0 + t[0]);
                        pairs_to_lanes(top, t.map(|t| pair(b1 + t)))
                    }
                    #[cfg(not(target_arch = "x86_64"))]
                    {
                        let quad =
                            |a: usize| win.get(a..a + 4).map_or(0, |p| i32::from_le_bytes([p[0], p[1], p[2], p[3]]));
                        quads_to_pairs(t.map(|t| quad(b0 + t)), t.map(|t| quad(b1 + t)))
                    }
                } else {
                    let Some(win) = s.get(..b1 + last + 2) else {
                        return (i16x8::ZERO, i16x8::ZERO);
                    };
                    let pair = |a: usize| win.get(a..a + 2).map_or(0, |p| u16::from_le_bytes([p[0], p[1]]));
                    cast(u16x8::new([
                        pair(b0 + t[0]),
                        pair(b0 + t[1]),
                        pair(b0 + t[2]),
                        pair(b0 + t[3]),
                        pair(b1 + t[0]),
                        pair(b1 + t[1]),
                        pair(b1 + t[2]),
                        pair(b1 + t[3]),
                    ]))
                };
                (i16x8::from_u8x16_low(bytes), i16x8::from_u8x16_high(bytes))
            })
        }
    }

    /// The columns inside both the surface and the mask's box are one run
    /// (positions grow with the column), and so are the rows
    /// ([`Frame::runs`]). The rows are taken [`ROWS`] at a time, their
    /// vertical taps and weights prepared [`LANES`] at a time; then each
    /// group of [`LANES`] columns prepares its horizontal taps and weights
    /// and runs down those rows with them in registers: eight reads, two
    /// `pmaddwd`, the vertical step and the primitive per row.
    #[inline(always)]
    fn accumulate_in(&self, f: &Frame, acc: &mut Acc, pairs: impl Fn(u32, u32, [u32; LANES]) -> (i16x8, i16x8)) {
        // One loop per primitive, so that neither carries the other's
        // registers and tests.
        match self.primitive {
            Primitive::Vibration { .. } => self.tiles::<false>(f, acc, pairs),
            Primitive::Grating { .. } => self.tiles::<true>(f, acc, pairs),
        }
    }

    /// [`accumulate_in`](Self::accumulate_in) for a grating (`GRATING`) or a vibration.
    #[inline(always)]
    fn tiles<const GRATING: bool>(
        &self,
        f: &Frame,
        acc: &mut Acc,
        pairs: impl Fn(u32, u32, [u32; LANES]) -> (i16x8, i16x8),
    ) {
        let [c_lo, c_hi, r_lo, r_hi] = f.runs(self.bounds);
        if c_lo >= c_hi || r_lo >= r_hi {
            return;
        }
        // Eq. 2's two values in units of the interpolation: ½ + ½ cos where
        // row and column parities differ, ½ − ½ cos where they agree.
        let (differ, same) = match self.primitive {
            Primitive::Vibration { freq } => {
                let c = cos_turns(f.clock.phase(f.tick_in_second, freq));
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
        // Eq. 3's ½ + ½ cos, times the unit: (1 + cos) · unit / 2.
        let half_unit = f32x4::splat(0.5 * self.unit);
        let lane_phase = lanes * step_col;
        let last_x = f.col_x(c_hi - 1);
        let mut rs = r_lo;
        while rs < r_hi {
            let m = (r_hi - rs).min(ROWS);
            // Per row of the tile: byte offsets of the mask rows above and
            // below it, and the weight of the lower one, [`LANES`] rows at
            // a time (rows past the run are computed too, and not used).
            let mut off0 = [0u32; ROWS];
            let mut off1 = [0u32; ROWS];
            let mut wy = [0f32; ROWS];
            // And eq. 3's phase step from row f.r0 to each row.
            let mut row_phase = [0f32; ROWS];
            for q in 0..ROWS / LANES {
                let rows = f32x4::from_i32x4(i32x4::splat((rs + q * LANES) as i32) + lane_index);
                let y = f32x4::splat(f.y_first) + rows * f.pitch_y;
                let fy = ((y - self.y0) * self.px_per_mm - 0.5).fast_max(f32x4::ZERO).fast_min(f32x4::splat(self.hmax));
                let j0 = (fy - 0.5).fast_round_int().min(i32x4::splat(self.jmax as i32));
                // The row below, unless j0 is the last row (a mask one row tall).
                let below = j0.simd_lt(i32x4::splat(self.last_row as i32)) & i32x4::splat(self.bpr as i32);
                let o0 = j0 * self.bpr as i32;
                let at = q * LANES..(q + 1) * LANES;
                wy[at.clone()].copy_from_slice(&(fy - f32x4::from_i32x4(j0)).to_array());
                off0[at.clone()].copy_from_slice(&cast::<i32x4, [u32; LANES]>(o0));
                off1[at.clone()].copy_from_slice(&cast::<i32x4, [u32; LANES]>(o0 + below));
                if GRATING {
                    let from_r0 = f32x4::from_i32x4(i32x4::splat((rs + q * LANES - f.r0) as i32) + lane_index);
                    row_phase[at].copy_from_slice(&(from_r0 * step_row).to_array());
                }
            }
            let mut cols = c_lo;
            while cols < c_hi {
                // The group's columns: byte offset of each left tap, and
                // the weights of the left and right samples as (W − w, w)
                // i16 pairs. Pixel centres sit at (i + ½) / px_per_mm;
                // between the box edge and the first centre the edge sample
                // holds. Lanes past the run take its last tap with weights
                // 0, so they read in bounds and add nothing.
                let first = f32x4::from_i32x4(i32x4::splat(cols as i32) + lane_index);
                // The same formula as `Frame::col_x`, lane by lane.
                let x = (f32x4::splat(f.x_first) + first * f.pitch_x).fast_min(f32x4::splat(last_x));
                let fx = ((x - self.x0) * self.px_per_mm - 0.5).fast_max(f32x4::ZERO).fast_min(f32x4::splat(self.wmax));
                let a = (fx - 0.5).fast_round_int().min(i32x4::splat(self.amax as i32));
                let wi = ((fx - f32x4::from_i32x4(a)) * W as f32).fast_round_int();
                let real = lane_index.simd_lt(i32x4::splat((c_hi - cols) as i32));
                let w: i16x8 = cast(((i32x4::splat(W) - wi) | (wi << 16)) & real);
                let taps = cast::<i32x4, [u32; LANES]>(a * self.bps as i32);
                // The taps of a group only grow (columns move right):
                // saying so with a min lets each row check one window.
                let taps = taps.map(|t| t.min(taps[LANES - 1]));
                // Eq. 3's phase of the group's columns in row f.r0.
                let group_phase = f32x4::splat(base + (cols - c_lo) as i32 as f32 * step_col) + lane_phase;
                for i in 0..m {
                    let (b0, b1, r) = (off0[i].min(off1[i]), off1[i], rs + i);
                    let (top, bot) = pairs(b0, b1, taps);
                    let t = f32x4::from_i32x4(top.dot(w));
                    let b = f32x4::from_i32x4(bot.dot(w));
                    let v = t + (b - t) * wy[i];
                    let v = if GRATING {
                        let phase = f32x4::splat(row_phase[i]) + group_phase;
                        v * (f32x4::ONE + cos_turns4(phase)) * half_unit
                    } else {
                        // Eq. 2: column `cols + lane` differs in parity
                        // from row r when r + cols + lane is odd.
                        v * parity[(r + cols) & 1]
                    };
                    // Lanes past the row's last column carry 0.
                    add_lanes(acc, (r - f.r0) * f.cols + cols, v);
                }
                cols += LANES;
            }
            rs += m;
        }
    }
}

/// Four pairs read from the upper row and four from the lower row, each in
/// the low 16 bits of its `i32`, in that order, on x86-64. The first goes
/// into the vector whole (`movd`), so it may be the u32 read at the pair
/// (its high half lands in lane 1, which the next insert replaces); each
/// other goes into its 16-bit lane with one insert, which LLVM folds with
/// the pair's read (`pinsrw $k, (mem)`). That is eight instructions for
/// the eight pairs, where moving each u32 into a vector register and
/// interleaving their halves (`punpcklwd`, `punpckldq`, `punpcklqdq`) took
/// fifteen. (Read as u16s, the
/// first pair too, LLVM rebuilds a tree of moves and unpacks.)
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn pairs_to_lanes(top: [i32; LANES], bot: [i32; LANES]) -> u8x16 {
    use safe_arch::{insert_i16_from_i32_m128i as insert, set_i32_m128i_s};
    let v = set_i32_m128i_s(top[0]);
    let v = insert::<1>(v, top[1]);
    let v = insert::<2>(v, top[2]);
    let v = insert::<3>(v, top[3]);
    let v = insert::<4>(v, bot[0]);
    let v = insert::<5>(v, bot[1]);
    let v = insert::<6>(v, bot[2]);
    cast(insert::<7>(v, bot[3]))
}

/// The first two bytes of each of four u32 read from the upper row and four
/// from the lower row, in that order (off x86-64, where `pairs_to_lanes`
/// reads the pairs into place): each lane is sign-extended from its low 16
/// bits and the lanes narrowed with signed saturation, which keeps those
/// bits exactly.
#[cfg(any(test, not(target_arch = "x86_64")))]
#[inline(always)]
fn quads_to_pairs(top: [i32; LANES], bot: [i32; LANES]) -> u8x16 {
    let pairs = |q: [i32; LANES]| (i32x4::new(q) << 16) >> 16;
    cast(i16x8::from_i32x8_saturate(cast([pairs(top), pairs(bot)])))
}

kernel! {
/// [`MaskLayer::accumulate`] (a `kernel!`).
fn accumulate_mask<'a>(layer: &MaskLayer<'a>, f: &Frame, acc: &mut Acc) {
    layer.accumulate_body(f, acc)
}
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quads_give_their_first_two_bytes_in_order() {
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s as i32
        };
        for _ in 0..100_000 {
            let (top, bot) = ([next(), next(), next(), next()], [next(), next(), next(), i32::MIN]);
            let mut want = [0u8; 16];
            for (k, q) in top.iter().chain(&bot).enumerate() {
                want[2 * k..2 * k + 2].copy_from_slice(&q.to_le_bytes()[..2]);
            }
            assert_eq!(quads_to_pairs(top, bot).to_array(), want);
            // As the x86-64 player reads them: the first whole, the others as pairs.
            #[cfg(target_arch = "x86_64")]
            {
                let pair = |q: i32| q & 0xffff;
                let top = [top[0], pair(top[1]), pair(top[2]), pair(top[3])];
                assert_eq!(pairs_to_lanes(top, bot.map(pair)).to_array(), want);
            }
        }
    }
}
