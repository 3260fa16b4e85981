//! Vibration and grating layers: a mask sampled bilinearly at each actuator,
//! times the primitive's deflection (seed 000 eqs. 2 and 3).

use taxel_format::{MaskKind, MaskView, MilliHertz};

use super::osc::{cos_turns, frac64, phase_turns};
use super::{BLOCK, Frame, MAX_COLS};

/// Lanes of the interpolation loop.
const LANES: usize = 8;

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
    width: u32,
    height: u32,
    x0: f32,
    y0: f32,
    x1: f32,
    y1: f32,
    px_per_mm: f32,
    /// Layer amplitude divided by the mask's full-scale code.
    scale: f32,
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
        MaskLayer {
            primitive,
            samples: m.sample_bytes(),
            wide: m.bits == 16,
            width: m.width,
            height: m.height,
            x0: m.origin_x.0,
            y0: m.origin_y.0,
            x1: (m.origin_x.0 as f64 + m.width as f64 / ppm as f64) as f32,
            y1: (m.origin_y.0 as f64 + m.height as f64 / ppm as f64) as f32,
            px_per_mm: ppm,
            scale: m.amplitude / m.full_scale() as f32,
        }
    }

    /// Adds this layer's deflection for rows `f.r0..f.r1` to `acc`.
    #[inline]
    pub(crate) fn accumulate(&self, f: &Frame, acc: &mut [f32; BLOCK]) {
        // `pair(row, i)` reads samples i and i + 1 of a row with one bounds
        // check; at a row's last sample (a mask one sample wide) it repeats it.
        if self.wide {
            self.accumulate_in(f, acc, |row: &[u8], i: usize| match row.get(2 * i..2 * i + 4) {
                Some(&[a, b, c, d]) => (u16::from_le_bytes([a, b]) as i32, u16::from_le_bytes([c, d]) as i32),
                _ => {
                    let v = match row.get(2 * i..2 * i + 2) {
                        Some(&[a, b]) => u16::from_le_bytes([a, b]) as i32,
                        _ => 0,
                    };
                    (v, v)
                }
            })
        } else {
            self.accumulate_in(f, acc, |row: &[u8], i: usize| match row.get(i..i + 2) {
                Some(&[a, b]) => (a as i32, b as i32),
                _ => {
                    let v = row.get(i).copied().unwrap_or(0) as i32;
                    (v, v)
                }
            })
        }
    }

    /// Per row, a scalar gather of the four samples around each actuator,
    /// then straight-line arithmetic over the row (interpolation and the
    /// primitive) that the compiler vectorises.
    #[inline(always)]
    fn accumulate_in(&self, f: &Frame, acc: &mut [f32; BLOCK], pair: impl Fn(&[u8], usize) -> (i32, i32)) {
        // Columns inside both the surface and the mask's box, with their
        // bilinear taps (index k = column − c_lo). Pixel centres sit at
        // (i + ½) / px_per_mm; between the box edge and the first centre the
        // edge sample holds. Tap `a` is at most width − 2, so that samples a
        // and a + 1 are both in the row; at the right edge the weight on
        // a + 1 is then 1.
        let mut tap_a = [0u32; MAX_COLS];
        let mut tap_w = [0.0f32; MAX_COLS];
        let (mut c_lo, mut n) = (0usize, 0usize);
        let wmax = (self.width - 1) as f32;
        let amax = self.width.saturating_sub(2);
        for c in f.col_lo..f.col_hi {
            let x = f.col_x(c);
            if x >= self.x0 && x < self.x1 {
                if n == 0 {
                    c_lo = c;
                }
                let fx = ((x - self.x0) * self.px_per_mm - 0.5).max(0.0).min(wmax);
                let a = (fx as u32).min(amax);
                if let (Some(ta), Some(tw)) = (tap_a.get_mut(c - c_lo), tap_w.get_mut(c - c_lo)) {
                    (*ta, *tw) = (a, fx - a as f32);
                }
                n = c - c_lo + 1;
            }
        }
        if n == 0 {
            return;
        }
        let bpr = if self.wide { 2 } else { 1 } * self.width as usize;
        let hmax = (self.height - 1) as f32;
        let mut base = 0.0;
        if let Primitive::Grating { kx, ky, .. } = self.primitive {
            // Phase at actuator (f.r0, c_lo), reduced in f64 once per frame;
            // the other actuators add whole multiples of the reduced steps.
            let u = kx * f.col_x(c_lo) as f64 + ky * f.row_y(f.r0) as f64;
            base = frac64(u) as f32;
        }
        // Eq. 2's two values: ½ + ½ cos where row and column parities differ, ½ − ½ cos elsewhere.
        let (differ, same) = match self.primitive {
            Primitive::Vibration { freq } => {
                let c = cos_turns(phase_turns(f.tick, freq, f.rate_hz));
                (0.5 + 0.5 * c, 0.5 - 0.5 * c)
            }
            Primitive::Grating { .. } => (0.0, 0.0),
        };
        // The four samples around each actuator of a row, in separate arrays
        // so that the interpolation below runs on whole vectors.
        let (mut g00, mut g10, mut g01, mut g11) =
            ([0i32; MAX_COLS], [0i32; MAX_COLS], [0i32; MAX_COLS], [0i32; MAX_COLS]);
        let mut m = [0.0f32; MAX_COLS];
        for r in f.r0.max(f.row_lo)..f.r1.min(f.row_hi) {
            let y = f.row_y(r);
            if !(y >= self.y0 && y < self.y1) {
                continue;
            }
            let fy = ((y - self.y0) * self.px_per_mm - 0.5).max(0.0).min(hmax);
            let j0 = (fy as u32).min(self.height.saturating_sub(2));
            let wy = fy - j0 as f32;
            let j1 = (j0 + 1).min(self.height - 1);
            let row0 = self.samples.get(j0 as usize * bpr..).unwrap_or(&[]);
            let row1 = self.samples.get(j1 as usize * bpr..).unwrap_or(&[]);
            let k0 = (r - f.r0) * f.cols + c_lo;
            let Some(out) = acc.get_mut(k0..k0 + n) else { continue };
            // Eq. 2: column c_lo + k differs in parity from row r when r + c_lo + k is odd.
            let parity = if (r + c_lo) & 1 == 1 { [differ, same] } else { [same, differ] };
            let row_phase = match self.primitive {
                Primitive::Grating { step_row, .. } => base + (r - f.r0) as f32 * step_row,
                Primitive::Vibration { .. } => 0.0,
            };
            // A scalar gather of the row's samples (n ≤ MAX_COLS, so the
            // indexing below cannot fail).
            for k in 0..n.min(MAX_COLS) {
                let a = tap_a[k] as usize;
                ((g00[k], g10[k]), (g01[k], g11[k])) = (pair(row0, a), pair(row1, a));
            }
            // Then LANES actuators at a time, with a fixed trip count the
            // compiler turns into vector code, over the groups the row needs.
            let groups = n.div_ceil(LANES);
            let chunks = m.chunks_exact_mut(LANES).zip(tap_w.chunks_exact(LANES));
            let chunks = chunks.zip(g00.chunks_exact(LANES).zip(g10.chunks_exact(LANES)));
            let chunks = chunks.zip(g01.chunks_exact(LANES).zip(g11.chunks_exact(LANES)));
            let bilinear = |w: f32, s00: i32, s10: i32, s01: i32, s11: i32| {
                let (s00, s10, s01, s11) = (s00 as f32, s10 as f32, s01 as f32, s11 as f32);
                let top = s00 + w * (s10 - s00);
                let bot = s01 + w * (s11 - s01);
                (top + wy * (bot - top)) * self.scale
            };
            match self.primitive {
                Primitive::Vibration { .. } => {
                    for (((m, w), (g00, g10)), (g01, g11)) in chunks.take(groups) {
                        for i in 0..LANES {
                            m[i] = bilinear(w[i], g00[i], g10[i], g01[i], g11[i]) * parity[i & 1];
                        }
                    }
                }
                // Eq. 3.
                Primitive::Grating { step_col, .. } => {
                    for (group, (((m, w), (g00, g10)), (g01, g11))) in chunks.take(groups).enumerate() {
                        let phase0 = row_phase + (group * LANES) as f32 * step_col;
                        for i in 0..LANES {
                            let delta = 0.5 + 0.5 * cos_turns(phase0 + i as f32 * step_col);
                            m[i] = bilinear(w[i], g00[i], g10[i], g01[i], g11[i]) * delta;
                        }
                    }
                }
            }
            for (a, &v) in out.iter_mut().zip(m.iter()) {
                *a += v;
            }
        }
    }
}
