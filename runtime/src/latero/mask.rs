//! Vibration and grating layers: a mask sampled bilinearly at each actuator,
//! times the primitive's deflection (seed 000 eqs. 2 and 3).

use taxel_format::{MaskKind, MaskView, MilliHertz};

use super::osc::{cos_turns, frac64, phase_turns};
use super::{BLOCK, Frame, MAX_COLS};

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
        if self.wide {
            self.accumulate_in(f, acc, |s: &[u8], k: usize| match s.get(2 * k..2 * k + 2) {
                Some(&[a, b]) => u16::from_le_bytes([a, b]) as f32,
                _ => 0.0,
            })
        } else {
            self.accumulate_in(f, acc, |s: &[u8], k: usize| s.get(k).copied().unwrap_or(0) as f32)
        }
    }

    #[inline(always)]
    fn accumulate_in(&self, f: &Frame, acc: &mut [f32; BLOCK], sample: impl Fn(&[u8], usize) -> f32) {
        // Columns inside both the surface and the mask's box, with their
        // bilinear taps. Pixel centres sit at (i + ½) / px_per_mm; between
        // the box edge and the first centre the edge sample holds.
        let mut taps = [Tap::ZERO; MAX_COLS];
        let (mut c_lo, mut c_hi) = (usize::MAX, 0usize);
        let wmax = (self.width - 1) as f32;
        for c in f.col_lo..f.col_hi {
            let x = f.col_x(c);
            if x >= self.x0 && x < self.x1 {
                let fx = ((x - self.x0) * self.px_per_mm - 0.5).max(0.0).min(wmax);
                let i0 = fx as u32;
                let t = Tap { a: i0 as usize, b: (i0 + 1).min(self.width - 1) as usize, w: fx - i0 as f32 };
                if let Some(slot) = taps.get_mut(c) {
                    *slot = t;
                }
                c_lo = c_lo.min(c);
                c_hi = c + 1;
            }
        }
        if c_lo >= c_hi {
            return;
        }
        let (cos_pos, step_col, step_row, base) = match self.primitive {
            Primitive::Vibration { freq } => (cos_turns(phase_turns(f.tick, freq, f.rate_hz)), 0.0, 0.0, 0.0),
            Primitive::Grating { kx, ky, step_col, step_row } => {
                // Phase at actuator (f.r0, c_lo), reduced in f64 once per frame.
                let u = kx * f.col_x(c_lo) as f64 + ky * f.row_y(f.r0) as f64;
                (0.0, step_col, step_row, frac64(u) as f32)
            }
        };
        let hmax = (self.height - 1) as f32;
        let w = self.width as usize;
        for r in f.r0.max(f.row_lo)..f.r1.min(f.row_hi) {
            let y = f.row_y(r);
            if !(y >= self.y0 && y < self.y1) {
                continue;
            }
            let fy = ((y - self.y0) * self.px_per_mm - 0.5).max(0.0).min(hmax);
            let j0 = fy as u32;
            let wy = fy - j0 as f32;
            let row0 = j0 as usize * w;
            let row1 = (j0 + 1).min(self.height - 1) as usize * w;
            let k0 = (r - f.r0) * f.cols + c_lo;
            let Some(out) = acc.get_mut(k0..k0 + (c_hi - c_lo)) else { continue };
            let Some(taps) = taps.get(c_lo..c_hi) else { continue };
            let row_base = base + (r - f.r0) as f32 * step_row;
            for (k, (a, t)) in out.iter_mut().zip(taps).enumerate() {
                let c = c_lo + k;
                let top = sample(self.samples, row0 + t.a) * (1.0 - t.w) + sample(self.samples, row0 + t.b) * t.w;
                let bot = sample(self.samples, row1 + t.a) * (1.0 - t.w) + sample(self.samples, row1 + t.b) * t.w;
                let m = (top * (1.0 - wy) + bot * wy) * self.scale;
                let delta = match self.primitive {
                    // Eq. 2: ½ + ½ cos where row and column parities differ, ½ − ½ cos elsewhere.
                    Primitive::Vibration { .. } => {
                        if (r ^ c) & 1 == 1 {
                            0.5 + 0.5 * cos_pos
                        } else {
                            0.5 - 0.5 * cos_pos
                        }
                    }
                    // Eq. 3.
                    Primitive::Grating { .. } => 0.5 + 0.5 * cos_turns(row_base + k as f32 * step_col),
                };
                *a += m * delta;
            }
        }
    }
}

/// Bilinear taps of one column: samples `a` and `b`, weight `w` on `b`.
#[derive(Clone, Copy)]
struct Tap {
    a: usize,
    b: usize,
    w: f32,
}

impl Tap {
    const ZERO: Tap = Tap { a: 0, b: 0, w: 0.0 };
}
