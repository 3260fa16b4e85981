//! Vibration and grating layers by style (`VDST`, `GDST`): a signed distance
//! field in sparse tiles, interpolated bilinearly at each actuator, mapped to
//! amplitude by the layer's edge profile, times the primitive's deflection
//! (seed 000 eqs. 2 and 3).
//!
//! The memory pattern is the raster mask's (`mask.rs`): per actuator two
//! reads of a byte pair (the samples left and right of it, in the lattice
//! rows above and below), then the horizontal interpolation in fixed point
//! (`pmaddwd` on x86-64, weights of 14 bits) and the vertical one, the
//! profile and the primitive in `f32` lanes, four actuators at a time. Four
//! actuators are a column group walked down the block's rows; a lane reads
//! the tile index only when the group enters a new row of tiles (every
//! eight lattice rows), and then keeps a window of its tile's samples
//! (`tile_lanes`), typed so that the per-row reads need no bounds checks.
//! A tile wholly inside or outside stores no samples: its lanes read a
//! static tile of its constant code, which interpolates to that code
//! exactly, so the per-row kernel has no per-lane select. The cost per
//! actuator per layer is constant: it depends neither on the number of
//! shapes in the layer nor on where their edges are.

use taxel_format::{DistanceView, TILE_CELLS, TILE_FIRST_STORED, TILE_INSIDE, TILE_OUTSIDE, TILE_SAMPLES, TILE_SIDE};
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
type Tile = [u8; TILE_SAMPLES];
/// What a lane in a constant tile reads: the code of every sample of an
/// outside tile, and of an inside one.
static OUTSIDE: Tile = [0; TILE_SAMPLES];
static INSIDE: Tile = [255; TILE_SAMPLES];
/// The samples a lane reads from its tile: those from its column on, up to
/// the pair right of it in the tile's last lattice row.
const WINDOW: usize = TILE_CELLS * TILE_SIDE + 2;
type Window = [u8; WINDOW];
static OUTSIDE_WINDOW: Window = [0; WINDOW];

/// A distance layer prepared for playback.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FieldLayer<'a> {
    primitive: Primitive,
    /// The tile index, one little-endian `u32` entry per tile.
    entries: &'a [[u8; 4]],
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
            entries: m.tile_bytes().as_chunks::<4>().0,
            stored: m.sample_bytes().as_chunks::<TILE_SAMPLES>().0,
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
    /// changes, as the window of its tile that starts at the lane's column.
    /// A stored tile's lanes read its samples; a constant tile's lanes read
    /// a tile of that constant code (0 outside, 255 inside), whose
    /// interpolation is the constant exactly (the weights sum to `W`), so
    /// the per-row kernel needs no per-lane select. (An index entry past
    /// the stored tiles, which validation rules out, reads as outside.)
    #[inline(always)]
    fn tile_lanes(&self, tile_row: usize, ci: [u32; LANES]) -> [&'a Window; LANES] {
        // The lanes' columns grow from lane to lane, so neighbours often
        // share a tile: each tile is looked up once.
        let mut tile = self.tile(tile_row + (ci[0] >> SHIFT) as usize);
        let mut prev = ci[0] >> SHIFT;
        ci.map(|c| {
            if c >> SHIFT != prev {
                prev = c >> SHIFT;
                tile = self.tile(tile_row + prev as usize);
            }
            let col = (c & (TILE_CELLS as u32 - 1)) as usize;
            // A column below TILE_CELLS leaves a whole window: never `None`.
            tile.get(col..col + WINDOW).and_then(|w| w.try_into().ok()).unwrap_or(&OUTSIDE_WINDOW)
        })
    }

    /// The samples of the tile at index entry `i`.
    #[inline(always)]
    fn tile(&self, i: usize) -> &'a Tile {
        let e = self.entries.get(i).map_or(TILE_OUTSIDE, |b| u32::from_le_bytes(*b));
        if e >= TILE_FIRST_STORED {
            self.stored.get((e - TILE_FIRST_STORED) as usize).unwrap_or(&OUTSIDE)
        } else if e == TILE_INSIDE {
            &INSIDE
        } else {
            &OUTSIDE
        }
    }

    /// The byte pairs at offset `j` (the lattice row above, `j` a multiple
    /// of [`TILE_SIDE`] below `TILE_CELLS · TILE_SIDE`) and `j + TILE_SIDE`
    /// (below) of each lane's window, as (top, bottom) rows of (left,
    /// right) i16 lanes. Every index is in bounds by the window's type, so
    /// no read is checked.
    #[inline(always)]
    fn pairs(lanes: &[&Window; LANES], j: usize) -> (i16x8, i16x8) {
        let j = j.min(WINDOW - TILE_SIDE - 2);
        let pair = |w: &Window, j: usize| u16::from_le_bytes([w[j], w[j + 1]]);
        let bytes: u8x16 = cast(u16x8::new([
            pair(lanes[0], j),
            pair(lanes[1], j),
            pair(lanes[2], j),
            pair(lanes[3], j),
            pair(lanes[0], j + TILE_SIDE),
            pair(lanes[1], j + TILE_SIDE),
            pair(lanes[2], j + TILE_SIDE),
            pair(lanes[3], j + TILE_SIDE),
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
        let (y0, inv_pitch, rmax) =
            (f32x4::splat(self.y0), f32x4::splat(self.inv_pitch), f32x4::splat(self.rmax as f32));
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
            // Lanes past the run have weights 0, code 0, but a profile's
            // amplitude at code 0 need not be 0: their factor is.
            let real = cast::<i32x4, f32x4>(real);
            let parity = parity.map(|p| p & real);
            let half_unit = half_unit & real;
            let group_phase = f32x4::splat(base + (cols - c_lo) as u32 as f32 * step_col) + lane_phase;
            // The lanes' tiles change only every eight lattice rows.
            let mut ty_now = u32::MAX;
            let mut lanes = [&OUTSIDE_WINDOW; LANES];
            let mut r4 = r_lo;
            while r4 < r_hi {
                // Four rows' lattice cells and vertical weights at once, in
                // the lanes (row_y's arithmetic; fy ≥ 0, where truncation
                // is the floor).
                let y = f32x4::splat(f.y_first) + f32x4::from_i32x4(i32x4::splat(r4 as i32) + lane_index) * f.pitch_y;
                let fy = ((y - y0) * inv_pitch).fast_max(f32x4::ZERO);
                let cj = fy.fast_min(rmax).fast_trunc_int();
                let wy = (fy - f32x4::from_i32x4(cj)).fast_min(f32x4::ONE).to_array();
                let cj = cast::<i32x4, [u32; LANES]>(cj);
                for k in 0..LANES.min(r_hi - r4) {
                    let (r, cj, wy) = (r4 + k, cj[k], f32x4::splat(wy[k]));
                    let ty = cj >> SHIFT;
                    if ty != ty_now {
                        ty_now = ty;
                        lanes = self.tile_lanes(ty as usize * self.tile_cols as usize, ci);
                    }
                    let (top, bot) = Self::pairs(&lanes, (cj & (TILE_CELLS as u32 - 1)) as usize * TILE_SIDE);
                    let t = f32x4::from_i32x4(top.dot(w));
                    let b = f32x4::from_i32x4(bot.dot(w));
                    let v = t + (b - t) * wy;
                    let a = (v * slope + offset).fast_max(f32x4::ZERO).fast_min(f32x4::ONE);
                    let v = if GRATING {
                        let phase = f32x4::splat((r - f.r0) as u32 as f32 * step_row) + group_phase;
                        a * (f32x4::ONE + cos_turns4(phase)) * half_unit
                    } else {
                        a * parity[(r + cols) & 1]
                    };
                    add_lanes(acc, (r - f.r0) * f.cols + cols, v);
                }
                r4 += LANES;
            }
            cols += LANES;
        }
    }
}
