//! Vibration and grating layers by style (`VDST`, `GDST`): a signed distance
//! field in sparse tiles, interpolated bilinearly at each actuator, mapped to
//! amplitude by the layer's edge profile, times the primitive's deflection
//! (seed 000 eqs. 2 and 3).
//!
//! The memory pattern is the raster mask's (`mask.rs`): per actuator one
//! read of its tile's index entry and two reads of a byte pair (the samples
//! left and right of it, in the lattice rows above and below), then the
//! horizontal interpolation in fixed point (`pmaddwd` on x86-64, weights of
//! 14 bits) and the vertical one, the profile and the primitive in `f32`
//! lanes, four actuators at a time. A tile wholly inside or outside reads no
//! samples: its entry stands for a pair of constant codes. A plane or ridge
//! tile (format 3.0) reads no samples either: on a tile change each lane
//! evaluates its record's affine function at its column, so that per row it
//! costs one multiply-add (and for a ridge an absolute value), and a
//! constant tile is the plane of gradient 0. The cost per actuator per
//! layer is constant: it depends neither on the number of shapes in the
//! layer nor on where their edges are.

use taxel_format::{DistanceView, PLANE_RECORD_LEN, TILE_CELLS, TILE_SAMPLES, TILE_SIDE, TileEntry};
use wide::bytemuck::cast;
use wide::{f32x4, i16x8, i32x4, u8x16, u16x8};

use super::mask::Primitive;
use super::osc::{cos_turns, cos_turns4, frac64};
use super::{Acc, Frame, LANES, add_lanes};

/// The fixed-point unit of the horizontal weights (as in `mask.rs`).
const W: i32 = 1 << 14;
/// Index entries: tile columns are found with a shift.
const SHIFT: u32 = TILE_CELLS.trailing_zeros();

/// Four lanes' tiles, as [`FieldLayer::tile_lanes`] reads them.
#[derive(Debug, Clone, Copy, Default)]
struct TileLanes {
    base: [usize; LANES],
    /// Whether any lane is in a plane or ridge tile: else the others'
    /// code is the constant `a0` and the row loop skips the plane's algebra.
    analytic: bool,
    stored: i32x4,
    a0: f32x4,
    gy: f32x4,
    top: f32x4,
    ridge: i32x4,
}

/// A distance layer prepared for playback.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FieldLayer<'a> {
    primitive: Primitive,
    tiles: &'a [u8],
    planes: &'a [u8],
    samples: &'a [u8],
    tile_cols: u32,
    /// Largest lattice cell index along x and y.
    cmax: i32,
    rmax: i32,
    x0: f32,
    y0: f32,
    inv_pitch: f32,
    /// `[x0, x1, y0, y1]`, the lattice's box, for [`Frame::runs`].
    bounds: f32x4,
    /// Profile: amplitude = clamp(v · slope + offset, 0, 1) for the
    /// interpolated code `v` in units of `W`.
    slope: f32,
    offset: f32,
    /// The layer's amplitude.
    amplitude: f32,
}

impl<'a> FieldLayer<'a> {
    pub(crate) fn new(m: &DistanceView<'a>, pitch_x: f32, pitch_y: f32) -> Self {
        let primitive = Primitive::of(m.kind, pitch_x, pitch_y);
        let h = m.pitch_mm as f64;
        let span = |n: u32| n as f64 * TILE_CELLS as f64 * h;
        // Profile: ½ + (code − 128) · step / ramp (SPEC.md section 6.2).
        let k = m.step_mm / taxel_format::edge_ramp(m.soft_mm, m.step_mm);
        FieldLayer {
            primitive,
            tiles: m.tile_bytes(),
            planes: m.plane_bytes(),
            samples: m.sample_bytes(),
            tile_cols: m.tile_cols,
            cmax: (m.tile_cols as usize * TILE_CELLS - 1) as i32,
            rmax: (m.tile_rows as usize * TILE_CELLS - 1) as i32,
            x0: m.origin_x.0,
            y0: m.origin_y.0,
            inv_pitch: (1.0 / h) as f32,
            bounds: f32x4::new([
                m.origin_x.0,
                (m.origin_x.0 as f64 + span(m.tile_cols)) as f32,
                m.origin_y.0,
                (m.origin_y.0 as f64 + span(m.tile_rows)) as f32,
            ]),
            slope: k / W as f32,
            offset: 0.5 - 128.0 * k,
            amplitude: m.amplitude,
        }
    }

    /// Adds this layer's deflection for rows `f.r0..f.r1` to `acc`.
    #[inline(never)]
    pub(crate) fn accumulate(&self, f: &Frame, acc: &mut Acc) {
        match self.primitive {
            Primitive::Vibration { .. } => self.rows::<false>(f, acc),
            Primitive::Grating { .. } => self.rows::<true>(f, acc),
        }
    }

    /// For the tile row starting at index entry `tile_row`, four lanes' cell
    /// columns `ci` and lattice x coordinates within their tiles `u`: each
    /// lane's byte offset of its cell's column in its stored tile (0 for
    /// the others), a mask of the lanes in stored tiles, and for the others
    /// the analytic code `c + gx u + gy w = a0 + gy w` (codes) as `a0` and
    /// `gy`, the ridge's `top` and a mask of the ridge lanes. A constant tile
    /// is the plane of code 0 (outside) or 255 (inside).
    #[inline(always)]
    fn tile_lanes(&self, tile_row: usize, ci: [u32; LANES], u: [f32; LANES]) -> TileLanes {
        let mut t = TileLanes { base: [0usize; LANES], ..TileLanes::default() };
        let mut stored = [0i32; LANES];
        let mut ridge = [0i32; LANES];
        let (mut a0, mut gy, mut top) = ([0f32; LANES], [0f32; LANES], [0f32; LANES]);
        let f = |b: &[u8], o: usize| f32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]);
        for k in 0..LANES {
            let at = 4 * (tile_row + (ci[k] >> SHIFT) as usize);
            let e = self.tiles.get(at..at + 4).map_or(0, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
            match TileEntry::of(e) {
                TileEntry::Outside => {}
                TileEntry::Inside => a0[k] = 255.0,
                TileEntry::Stored(n) => {
                    t.base[k] = n as usize * TILE_SAMPLES + (ci[k] & (TILE_CELLS as u32 - 1)) as usize;
                    stored[k] = -1;
                }
                TileEntry::Plane(p) | TileEntry::Ridge(p) => {
                    let at = p as usize * PLANE_RECORD_LEN;
                    // The chunk was validated, so the record is there; a
                    // missing one plays as outside rather than panicking.
                    if let Some(r) = self.planes.get(at..at + PLANE_RECORD_LEN) {
                        t.analytic = true;
                        a0[k] = f(r, 0) + f(r, 4) * u[k];
                        gy[k] = f(r, 8);
                        if matches!(TileEntry::of(e), TileEntry::Ridge(_)) {
                            top[k] = f(r, 12);
                            ridge[k] = -1;
                        }
                    }
                }
            }
        }
        t.stored = i32x4::new(stored);
        t.ridge = i32x4::new(ridge);
        (t.a0, t.gy, t.top) = (f32x4::new(a0), f32x4::new(gy), f32x4::new(top));
        t
    }

    /// The byte pairs at `base + j` (the lattice row above) and `base + j +
    /// 9` (below) of four lanes, as (left, right) i16 lanes. Every offset is
    /// clamped to the last pair that fits, so each read is in bounds by
    /// construction; a stored tile's offsets always fit.
    #[inline(always)]
    fn pairs(&self, base: &[usize; LANES], j: usize) -> (i16x8, i16x8) {
        let s = self.samples;
        let lim = s.len().saturating_sub(TILE_SIDE + 2);
        let pair = |a: usize| s.get(a..a + 2).map_or(0, |p| u16::from_le_bytes([p[0], p[1]]));
        let a = base.map(|b| (b + j).min(lim));
        let bytes: u8x16 = cast(u16x8::new([
            pair(a[0]),
            pair(a[1]),
            pair(a[2]),
            pair(a[3]),
            pair(a[0] + TILE_SIDE),
            pair(a[1] + TILE_SIDE),
            pair(a[2] + TILE_SIDE),
            pair(a[3] + TILE_SIDE),
        ]));
        (i16x8::from_u8x16_low(bytes), i16x8::from_u8x16_high(bytes))
    }

    #[inline(always)]
    fn rows<const GRATING: bool>(&self, f: &Frame, acc: &mut Acc) {
        let [c_lo, c_hi, r_lo, r_hi] = f.runs(self.bounds);
        if c_lo >= c_hi || r_lo >= r_hi {
            return;
        }
        let unit = self.amplitude;
        let (differ, same) = match self.primitive {
            Primitive::Vibration { freq } => {
                let c = cos_turns(f.clock.phase(f.tick_in_second, freq));
                ((0.5 + 0.5 * c) * unit, (0.5 - 0.5 * c) * unit)
            }
            Primitive::Grating { .. } => (0.0, 0.0),
        };
        let parity = [f32x4::new([same, differ, same, differ]), f32x4::new([differ, same, differ, same])];
        let (base, step_col, step_row) = match self.primitive {
            Primitive::Grating { kx, ky, step_col, step_row } => {
                (frac64(kx * f.col_x(c_lo) as f64 + ky * f.row_y(f.r0) as f64) as f32, step_col, step_row)
            }
            Primitive::Vibration { .. } => (0.0, 0.0, 0.0),
        };
        let lanes = f32x4::new([0.0, 1.0, 2.0, 3.0]);
        let lane_index = i32x4::new([0, 1, 2, 3]);
        let half_unit = f32x4::splat(0.5 * unit);
        let lane_phase = lanes * step_col;
        let last_x = f.col_x(c_hi - 1);
        let (slope, offset) = (f32x4::splat(self.slope), f32x4::splat(self.offset));
        let mut cols = c_lo;
        while cols < c_hi {
            let first = f32x4::from_i32x4(i32x4::splat(cols as i32) + lane_index);
            let x = (f32x4::splat(f.x_first) + first * f.pitch_x).fast_min(f32x4::splat(last_x));
            let fx = ((x - self.x0) * self.inv_pitch).fast_max(f32x4::ZERO);
            let ci = fx.fast_trunc_int().min(i32x4::splat(self.cmax)).max(i32x4::ZERO);
            let wi = ((fx - f32x4::from_i32x4(ci)).fast_min(f32x4::ONE) * W as f32).fast_round_int();
            let real = lane_index.simd_lt(i32x4::splat((c_hi - cols) as i32));
            let w: i16x8 = cast(((i32x4::splat(W) - wi) | (wi << 16)) & real);
            // Each lane's lattice x within its tile, for plane and ridge tiles.
            let tile_x = f32x4::from_i32x4((ci >> SHIFT as i32) << SHIFT as i32);
            let u = cast::<f32x4, [f32; LANES]>((fx - tile_x).fast_min(f32x4::splat(TILE_CELLS as f32)));
            let ci = cast::<i32x4, [u32; LANES]>(ci);
            let group_phase = f32x4::splat(base + (cols - c_lo) as u32 as f32 * step_col) + lane_phase;
            // The lanes' tiles change only every eight lattice rows.
            let mut ty_now = u32::MAX;
            let mut lanes_now = TileLanes::default();
            for r in r_lo..r_hi {
                let fy = ((f.row_y(r) - self.y0) * self.inv_pitch).max(0.0);
                let cj = (fy as i32).clamp(0, self.rmax) as u32;
                let wy = (fy - cj as f32).min(1.0);
                let ty = cj >> SHIFT;
                if ty != ty_now {
                    ty_now = ty;
                    lanes_now = self.tile_lanes(ty as usize * self.tile_cols as usize, ci, u);
                }
                let tl = &lanes_now;
                let j = (cj & (TILE_CELLS as u32 - 1)) as usize * TILE_SIDE;
                let (top, bot) = self.pairs(&tl.base, j);
                let t = f32x4::from_i32x4(top.dot(w));
                let b = f32x4::from_i32x4(bot.dot(w));
                // The other lanes' code at this row's lattice y within the
                // tile, converted to units of `W`, whatever was read.
                let code = if tl.analytic {
                    let wt = (fy - (ty << SHIFT) as f32).min(TILE_CELLS as f32);
                    let plane = tl.a0 + tl.gy * wt;
                    cast::<i32x4, f32x4>(tl.ridge).select(tl.top - plane.abs(), plane)
                } else {
                    tl.a0
                };
                let v = cast::<i32x4, f32x4>(tl.stored).select(t + (b - t) * wy, code * W as f32);
                // Lanes past the run have weights 0: code 0, amplitude 0.
                let a = (v * slope + offset).fast_max(f32x4::ZERO).fast_min(f32x4::ONE);
                let a = a & cast::<i32x4, f32x4>(real);
                let v = if GRATING {
                    let phase = f32x4::splat((r - f.r0) as u32 as f32 * step_row) + group_phase;
                    a * (f32x4::ONE + cos_turns4(phase)) * half_unit
                } else {
                    a * parity[(r + cols) & 1]
                };
                add_lanes(acc, (r - f.r0) * f.cols + cols, v);
            }
            cols += LANES;
        }
    }
}
