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
        // `pair(row, i)` reads samples i and i + 1 of a row with one bounds
        // check; at a row's last sample (a mask one sample wide) it repeats it.
        if self.wide {
            self.accumulate_in(f, acc, |row: &[u8], i: usize| match row.get(2 * i..2 * i + 4) {
                Some(&[a, b, c, d]) => (u16::from_le_bytes([a, b]) as f32, u16::from_le_bytes([c, d]) as f32),
                _ => {
                    let v = match row.get(2 * i..2 * i + 2) {
                        Some(&[a, b]) => u16::from_le_bytes([a, b]) as f32,
                        _ => 0.0,
                    };
                    (v, v)
                }
            })
        } else {
            self.accumulate_in(f, acc, |row: &[u8], i: usize| match row.get(i..i + 2) {
                Some(&[a, b]) => (a as f32, b as f32),
                _ => {
                    let v = row.get(i).copied().unwrap_or(0) as f32;
                    (v, v)
                }
            })
        }
    }

    /// The work is split per row into a gather of mask values (scalar: four
    /// samples per actuator) and the primitive, which is straight-line
    /// arithmetic over the row that the compiler vectorises.
    #[inline(always)]
    fn accumulate_in(&self, f: &Frame, acc: &mut [f32; BLOCK], pair: impl Fn(&[u8], usize) -> (f32, f32)) {
        // Columns inside both the surface and the mask's box, with their
        // bilinear taps. Pixel centres sit at (i + ½) / px_per_mm; between
        // the box edge and the first centre the edge sample holds.
        let mut taps = [Tap::ZERO; MAX_COLS];
        let (mut c_lo, mut c_hi) = (usize::MAX, 0usize);
        // Tap `a` is at most width − 2, so that samples a and a + 1 are both
        // in the row; at the right edge the weight on a + 1 is then 1.
        let wmax = (self.width - 1) as f32;
        let amax = self.width.saturating_sub(2);
        for c in f.col_lo..f.col_hi {
            let x = f.col_x(c);
            if x >= self.x0 && x < self.x1 {
                let fx = ((x - self.x0) * self.px_per_mm - 0.5).max(0.0).min(wmax);
                let a = (fx as u32).min(amax);
                if let Some(slot) = taps.get_mut(c) {
                    *slot = Tap { a, w: fx - a as f32 };
                }
                c_lo = c_lo.min(c);
                c_hi = c + 1;
            }
        }
        let (Some(taps), Some(n)) = (taps.get(c_lo..c_hi), c_hi.checked_sub(c_lo)) else { return };
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
        let mut m = [0.0f32; MAX_COLS];
        for r in f.r0..f.r1 {
            let y = f.row_y(r);
            if r < f.row_lo || r >= f.row_hi || !(y >= self.y0 && y < self.y1) {
                continue;
            }
            let fy = ((y - self.y0) * self.px_per_mm - 0.5).max(0.0).min(hmax);
            let j0 = (fy as u32).min(self.height.saturating_sub(2));
            let wy = fy - j0 as f32;
            let j1 = (j0 + 1).min(self.height - 1);
            let row0 = self.samples.get(j0 as usize * bpr..).unwrap_or(&[]);
            let row1 = self.samples.get(j1 as usize * bpr..).unwrap_or(&[]);
            let k0 = (r - f.r0) * f.cols + c_lo;
            let (Some(out), Some(m)) = (acc.get_mut(k0..k0 + n), m.get_mut(..n)) else { continue };
            for (mv, t) in m.iter_mut().zip(taps) {
                let (a0, b0) = pair(row0, t.a as usize);
                let (a1, b1) = pair(row1, t.a as usize);
                let top = a0 + t.w * (b0 - a0);
                let bot = a1 + t.w * (b1 - a1);
                *mv = (top + wy * (bot - top)) * self.scale;
            }
            match self.primitive {
                Primitive::Vibration { .. } => {
                    // Column c_lo + k differs in parity from row r when (r + c_lo + k) is odd.
                    let pair = if (r + c_lo) & 1 == 1 { [differ, same] } else { [same, differ] };
                    for (k, (a, mv)) in out.iter_mut().zip(m.iter()).enumerate() {
                        *a += mv * pair[k & 1];
                    }
                }
                // Eq. 3.
                Primitive::Grating { step_col, step_row, .. } => {
                    let row_base = base + (r - f.r0) as f32 * step_row;
                    for (k, (a, mv)) in out.iter_mut().zip(m.iter()).enumerate() {
                        *a += mv * (0.5 + 0.5 * cos_turns(row_base + k as f32 * step_col));
                    }
                }
            }
        }
    }
}

/// Bilinear taps of one column: samples `a` and `a + 1`, weight `w` on `a + 1`.
#[derive(Clone, Copy)]
struct Tap {
    a: u32,
    w: f32,
}

impl Tap {
    const ZERO: Tap = Tap { a: 0, w: 0.0 };
}
