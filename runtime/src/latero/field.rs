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
//! samples: its entry stands for a pair of constant codes. The cost per
//! actuator per layer is constant: it depends neither on the number of
//! shapes in the layer nor on where their edges are.

use taxel_format::{DistanceView, TILE_CELLS, TILE_FIRST_STORED, TILE_INSIDE, TILE_OUTSIDE, TILE_SIDE};
use wide::bytemuck::cast;
use wide::{f32x4, i16x8, i32x4, u8x16, u16x8};

use super::mask::Primitive;
use super::osc::{cos_turns, cos_turns4, frac64};
use super::{Acc, Frame, LANES, add_lanes};

/// The fixed-point unit of the horizontal weights (as in `mask.rs`).
const W: i32 = 1 << 14;
/// Index entries: tile columns are found with a shift.
const SHIFT: u32 = TILE_CELLS.trailing_zeros();

/// A tile's samples, row by row.
type Tile = [[u8; TILE_SIDE]; TILE_SIDE];
/// What a lane in a constant tile reads: the code of every sample of an
/// outside tile, and of an inside one.
static OUTSIDE: Tile = [[0; TILE_SIDE]; TILE_SIDE];
static INSIDE: Tile = [[255; TILE_SIDE]; TILE_SIDE];

/// A distance layer prepared for playback.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FieldLayer<'a> {
    primitive: Primitive,
    tiles: &'a [u8],
    /// The stored tiles' samples, row by row.
    stored: &'a [Tile],
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
            stored: m.sample_bytes().as_chunks::<TILE_SIDE>().0.as_chunks::<TILE_SIDE>().0,
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

    /// For the tile row starting at index entry `tile_row` and four lanes'
    /// cell columns `ci`: the samples each lane reads until its tile
    /// changes. A stored tile's lanes read its samples; a constant tile's
    /// lanes read a tile of that constant code (0 outside, 255 inside),
    /// whose interpolation is the constant exactly (the weights sum to
    /// `W`), so the per-row kernel needs no per-lane select. (An index
    /// entry past the stored tiles, which validation rules out, reads as
    /// outside.)
    #[inline(always)]
    fn tile_lanes(&self, tile_row: usize, ci: [u32; LANES]) -> [&'a Tile; LANES] {
        ci.map(|c| {
            let at = 4 * (tile_row + (c >> SHIFT) as usize);
            let e = self.tiles.get(at..at + 4).map_or(TILE_OUTSIDE, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
            match e {
                TILE_INSIDE => &INSIDE,
                e if e >= TILE_FIRST_STORED => self.stored.get((e - TILE_FIRST_STORED) as usize).unwrap_or(&OUTSIDE),
                _ => &OUTSIDE,
            }
        })
    }

    /// The byte pairs at row `j` and `j + 1`, columns `c` and `c + 1` of
    /// each lane's tile (`j` and `c` below [`TILE_CELLS`], so every index
    /// is in bounds by its type and no read is checked), as (top, bottom)
    /// rows of (left, right) i16 lanes.
    #[inline(always)]
    fn pairs(tiles: &[&Tile; LANES], col: &[usize; LANES], j: usize) -> (i16x8, i16x8) {
        let j = j & (TILE_CELLS - 1);
        let pair = |k: usize, j: usize| {
            let (t, c) = (tiles[k], col[k] & (TILE_CELLS - 1));
            u16::from_le_bytes([t[j][c], t[j][c + 1]])
        };
        let bytes: u8x16 = cast(u16x8::new([
            pair(0, j),
            pair(1, j),
            pair(2, j),
            pair(3, j),
            pair(0, j + 1),
            pair(1, j + 1),
            pair(2, j + 1),
            pair(3, j + 1),
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
            let ci = cast::<i32x4, [u32; LANES]>(ci);
            let col = ci.map(|c| (c & (TILE_CELLS as u32 - 1)) as usize);
            let group_phase = f32x4::splat(base + (cols - c_lo) as u32 as f32 * step_col) + lane_phase;
            // The lanes' tiles change only every eight lattice rows.
            let mut ty_now = u32::MAX;
            let mut tiles = [&OUTSIDE; LANES];
            for r in r_lo..r_hi {
                let fy = ((f.row_y(r) - self.y0) * self.inv_pitch).max(0.0);
                let cj = (fy as i32).clamp(0, self.rmax) as u32;
                let wy = (fy - cj as f32).min(1.0);
                let ty = cj >> SHIFT;
                if ty != ty_now {
                    ty_now = ty;
                    tiles = self.tile_lanes(ty as usize * self.tile_cols as usize, ci);
                }
                let (top, bot) = Self::pairs(&tiles, &col, cj as usize);
                let t = f32x4::from_i32x4(top.dot(w));
                let b = f32x4::from_i32x4(bot.dot(w));
                let v = t + (b - t) * wy;
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
