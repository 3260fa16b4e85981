//! Vibration and grating layers by style (`VDST`, `GDST`): a signed distance
//! field in sparse tiles, interpolated bilinearly at each actuator, mapped to
//! amplitude by the layer's edge profile, times the primitive's deflection
//! (seed 000 eqs. 2 and 3).
//!
//! The memory pattern is the raster mask's (`mask.rs`): per actuator two
//! reads of a byte pair (the samples left and right of it, in the lattice
//! rows above and below; on x86-64 each pair goes straight from memory
//! into its 16-bit lane, `pinsrw`), then the horizontal interpolation in fixed point
//! (`pmaddwd` on x86-64, weights of 14 bits) and the vertical one, the
//! profile and the primitive in `f32` lanes, four actuators at a time. Four
//! actuators are a column group walked down the block's rows; a lane reads
//! the tile index only when the group enters a new row of tiles (every
//! eight lattice rows), and then keeps a window of its tile's samples
//! (`tile_lanes`), typed so that the per-row reads need no bounds checks.
//! The rows' lattice cells and vertical weights do not depend on the
//! column group: a layer computes them once, eight rows at a time, for all
//! its groups.
//! A tile wholly inside or outside stores no samples: its lanes read a
//! static tile of its constant code, which interpolates to that code
//! exactly, so the per-row kernel has no per-lane select. A plane or ridge
//! tile (format 3.0) stores no samples either: on a tile change each lane
//! evaluates its record's affine function at its column, so that per row it
//! costs two multiply-adds, an absolute value, a multiply and a select;
//! rows whose lanes read no such tile skip that work (one predictable
//! branch). A corner or notch tile (format 4.0) plays the
//! lesser or the greater of two affine codes, `min(A1, A2) = T − |A|`
//! with `T` and `A` their half sum and half difference, so that every
//! such lane plays `T − sign · |A|` from two affine functions: plane,
//! ridge, corner and notch lanes share one formula and need no select
//! among them. A bend tile (format 4.0) plays a band's bent centre line,
//! `top − k · min(dist(q, ray 1), dist(q, ray 2))`, one square root per
//! row for four lanes, written out of line on a tile change and played only
//! in rows that have a bend lane (one more predictable branch inside the
//! analytic one). An arc tile (format 4.1) plays a circle, `top − k · ||q −
//! C| − R|`, the same way: its lanes ride with the bend lanes, written out
//! of line on a tile change and played only in rows that have an arc lane;
//! a cut arc (format 4.3, an arc tile whose second record holds a plane)
//! plays the lesser of that and the plane's affine code in the same lanes
//! (a plain arc's plane is `f32::MAX`), so it needs no flag of its own and
//! the other kinds' code is unchanged. A fine tile (format 4.4, samples
//! 2 to 8 times finer, in one channel or two whose lesser it plays) rides
//! with them too: its lanes are written out of line on a tile change and
//! interpolated lane by lane ([`FieldLayer::fine`]) in rows that have a
//! fine lane. In a layer of outside, inside and
//! stored tiles only, a tile change looks up each lane's window. In a layer
//! with other kinds, it first tries the tiles the compiler writes most:
//! when every lane's tile is constant or a plane tile (region interiors
//! and exteriors, straight edges), it reads each tile's entry once and its
//! record directly, with no decode by kind ([`FieldLayer::affine_lanes`]),
//! and the rows play that code `T = c + gx u + gy w` behind one test, with
//! no samples (a constant tile's code is its record's `c`, exactly the
//! interpolation of its samples). Then it tries every lane's window as if
//! every lane's tile stored samples or were constant, and only when a
//! lane's tile is of another kind reads the lanes' records: each tile is
//! decoded once for the lanes that share it, by its kind nibble with one
//! arm per kind ([`FieldLayer::lane`]), into its samples, its two records
//! and a word of kind flags, which each lane copies with no branch; the
//! records are read one vector a lane and the lanes' `T`, `A`, gradients,
//! signs and masks are computed four at a time. Among such lanes a
//! constant tile's lanes play their constant as a plane (the same code as
//! its samples' interpolation, exactly), so that rows whose lanes read no
//! stored tile read no samples at all. When no lane of a tile change is a
//! ridge, corner or notch lane, `A` and the sign are 0 and the rows play
//! `T` alone. (A new kind of tile adds its arm to
//! `TileEntry::of` and to [`FieldLayer::lane`], with a flag; a kind played
//! out of line, as bends and arcs are, adds its lane writer to
//! `curved_lanes` and its row function beside [`FieldLayer::bend`], in
//! `field/curved.rs`; the decoding by kind is in `field/lanes.rs`.) Which of these
//! the kernel carries is chosen per layer at load ([`Tiles`]): a layer whose
//! tiles all store samples or are constant runs an instance with no analytic
//! lanes at all; only a layer with bend tiles carries the bend lanes. The
//! cost per actuator per layer is bounded: it
//! depends neither on the number of shapes in the layer nor on where their
//! edges are.

use taxel_format::{DistanceView, PLANE_RECORD_LEN, TILE_CELLS, TILE_SAMPLES, TILE_SIDE, TileEntry};
use wide::bytemuck::cast;
#[cfg(not(target_arch = "x86_64"))]
use wide::u16x8;
use wide::{f32x4, i16x8, i32x4, u8x16};

use super::mask::Primitive;
use super::osc::{cos_turns, cos_turns4, frac64};
use super::{Acc, Frame, LANES, add_lanes};

use curved::BendLanes;
use lanes::Record;

/// The fixed-point unit of the horizontal weights (as in `mask.rs`).
const W: i32 = 1 << 14;
/// Rows whose lattice cells are computed at once ([`FieldLayer::rows`]).
const ROWS: usize = 2 * LANES;
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

/// What four lanes read until their tiles change ([`FieldLayer::tile_lanes`]).
#[derive(Debug, Clone, Copy)]
struct TileLanes<'a> {
    /// Each lane's window of samples (a plane or ridge lane's is the
    /// outside window, whose code its select replaces).
    windows: [&'a Window; LANES],
    /// Whether any lane is in a plane, ridge, corner or notch tile.
    analytic: bool,
    /// The lanes that play their code below rather than their samples:
    /// when `analytic`, every lane but a stored tile's.
    planar: i32x4,
    /// Every such lane plays `T − sign · |A|`, with `T` and `A` affine
    /// along y: `T = t0 + tgy w`, `A = a0 + gy w`. A plane lane has its
    /// affine code as `T` and sign 0; a ridge lane its top as `T` and its
    /// affine code as `A`, sign 1; a corner or notch lane, with `A1` and
    /// `A2` its records' affine codes, `T = (A1 + A2) / 2` and
    /// `A = (A1 − A2) / 2`, sign 1 (`min(A1, A2)`) or −1 (`max(A1, A2)`).
    /// `t0` and `a0` are the values at the lane's column, `tgy` and `gy`
    /// the gradients along y in codes per lattice cell.
    t0: f32x4,
    tgy: f32x4,
    a0: f32x4,
    gy: f32x4,
    sign: f32x4,
    /// Whether any lane is in a bend tile (format 4.0): its other values
    /// are in a [`BendLanes`], written only then.
    bent: bool,
    /// Whether any lane reads a stored tile's samples. When lanes are
    /// analytic, all the others play their code ([`Self::planar`]), and
    /// rows with no stored tile read no samples.
    sampled: bool,
    /// Whether no lane is a ridge, corner or notch lane: then `sign`, `a0`
    /// and `gy` are 0 and every lane's code is `T` alone (the rows skip
    /// `− sign · |A|`, which is exactly 0 there).
    flat: bool,
    /// Whether every lane is a constant or plane lane written by
    /// [`FieldLayer::affine_lanes`]: then `analytic` and `flat` hold, no
    /// lane reads samples or is curved, and the rows play `T` alone.
    affine: bool,
    /// Whether these lanes were decoded by kind ([`FieldLayer::tile_lanes`]):
    /// then the next tile change most likely needs that too.
    decoded: bool,
}

impl Default for TileLanes<'_> {
    fn default() -> Self {
        TileLanes {
            windows: [&OUTSIDE_WINDOW; LANES],
            analytic: false,
            planar: i32x4::ZERO,
            t0: f32x4::ZERO,
            tgy: f32x4::ZERO,
            a0: f32x4::ZERO,
            gy: f32x4::ZERO,
            sign: f32x4::ZERO,
            bent: false,
            sampled: false,
            flat: false,
            affine: false,
            decoded: false,
        }
    }
}

/// A distance layer prepared for playback.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FieldLayer<'a> {
    primitive: Primitive,
    /// The tile index, one little-endian `u32` entry per tile.
    entries: &'a [[u8; 4]],
    /// The stored tiles' samples, row by row.
    stored: &'a [Tile],
    /// The plane records (format 3.0 on), four little-endian `f32` each.
    planes: &'a [Record],
    tile_cols: u32,
    /// Largest lattice cell index along x and y, converted to `f32` here
    /// rather than per frame: the kernel clamps with them in `f32`.
    cmax: f32,
    rmax: f32,
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
    /// The kinds of tile the layer holds, which choose the instance of the
    /// kernel that plays it.
    tiles: Tiles,
}

/// The kinds of tile in a layer. Each kind of layer has its own instance
/// of the kernel, chosen at load: a layer whose tiles all store samples or
/// are constant carries no analytic lanes at all and finds its lanes'
/// windows with one lookup per tile; only a layer with bend tiles carries
/// the bend lanes (and the arc lanes, format 4.1, which ride with them), so
/// that other layers play the code they played before bends existed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Tiles {
    /// Outside, inside and stored tiles only.
    Sampled,
    /// Also plane, ridge, corner or notch tiles.
    Analytic,
    /// Also bend tiles.
    Bent,
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
            planes: m.plane_bytes().as_chunks::<PLANE_RECORD_LEN>().0,
            tile_cols: m.tile_cols,
            cmax: (m.tile_cols as usize * TILE_CELLS - 1) as i32 as f32,
            rmax: (m.tile_rows as usize * TILE_CELLS - 1) as i32 as f32,
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
            tiles: m.tile_bytes().as_chunks::<4>().0.iter().fold(Tiles::Sampled, |t, e| {
                match TileEntry::of(u32::from_le_bytes(*e)) {
                    TileEntry::Outside | TileEntry::Inside | TileEntry::Stored(_) => t,
                    TileEntry::Bend(_) | TileEntry::Arc(_) | TileEntry::Segments(_) | TileEntry::Fine { .. } => {
                        Tiles::Bent
                    }
                    _ if t == Tiles::Bent => t,
                    _ => Tiles::Analytic,
                }
            }),
        }
    }

    /// Adds this layer's deflection for rows `f.r0..f.r1` to `acc`.
    #[inline(always)]
    pub(crate) fn accumulate(&self, f: &Frame, acc: &mut Acc) {
        accumulate_field(self, f, acc)
    }

    /// The body of [`accumulate_field`]: the kernel's instance for the
    /// layer's primitive and kinds of tile.
    #[inline(always)]
    fn accumulate_in(&self, f: &Frame, acc: &mut Acc) {
        match (self.primitive, self.tiles) {
            (Primitive::Vibration { .. }, Tiles::Sampled) => self.rows::<false, false, false>(f, acc),
            (Primitive::Vibration { .. }, Tiles::Analytic) => self.rows::<false, true, false>(f, acc),
            (Primitive::Vibration { .. }, Tiles::Bent) => self.rows::<false, true, true>(f, acc),
            (Primitive::Grating { .. }, Tiles::Sampled) => self.rows::<true, false, false>(f, acc),
            (Primitive::Grating { .. }, Tiles::Analytic) => self.rows::<true, true, false>(f, acc),
            (Primitive::Grating { .. }, Tiles::Bent) => self.rows::<true, true, true>(f, acc),
        }
    }
}

// The lanes' decoding by kind and the out-of-line lanes are declared here,
// between `accumulate_in` and `pairs`, rather than at the top: the
// kernel's items then come in the order they had when this was one file,
// and LLVM compiles the kernel to the same instructions (declared at the
// top, its registers and spills came out differently).
mod curved;
mod lanes;

impl<'a> FieldLayer<'a> {
    /// The byte pairs at offset `j` (the lattice row above, `j` a multiple
    /// of [`TILE_SIDE`] below `TILE_CELLS · TILE_SIDE`) and `j + TILE_SIDE`
    /// (below) of each lane's window, as (top, bottom) rows of (left,
    /// right) i16 lanes. Every index is in bounds by the window's type, so
    /// no read is checked.
    #[inline(always)]
    fn pairs(lanes: &[&Window; LANES], j: usize) -> (i16x8, i16x8) {
        let j = j.min(WINDOW - TILE_SIDE - 2);
        let pair = |w: &Window, j: usize| u16::from_le_bytes([w[j], w[j + 1]]);
        // On x86-64 the pairs go into place one 16-bit insert each
        // (`pinsrw` from memory), where building the vector from eight
        // scalars takes a move into a vector register for each and a tree
        // of unpacks.
        #[cfg(target_arch = "x86_64")]
        let bytes: u8x16 = {
            use safe_arch::{insert_i16_from_i32_m128i as insert, set_i32_m128i_s};
            let p = |w: &Window, j: usize| i32::from(pair(w, j));
            // The first pair as the low half of a u32 (`movd` from memory;
            // its high half lands in lane 1, which the next insert
            // replaces): `j + 3` is inside the window too.
            let w = lanes[0];
            let v = set_i32_m128i_s(i32::from_le_bytes([w[j], w[j + 1], w[j + 2], w[j + 3]]));
            let v = insert::<1>(v, p(lanes[1], j));
            let v = insert::<2>(v, p(lanes[2], j));
            let v = insert::<3>(v, p(lanes[3], j));
            let v = insert::<4>(v, p(lanes[0], j + TILE_SIDE));
            let v = insert::<5>(v, p(lanes[1], j + TILE_SIDE));
            let v = insert::<6>(v, p(lanes[2], j + TILE_SIDE));
            cast(insert::<7>(v, p(lanes[3], j + TILE_SIDE)))
        };
        #[cfg(not(target_arch = "x86_64"))]
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

    /// Reads the lanes' tiles anew for the tile row that starts at index
    /// `row`, the lanes at lattice columns `ci` and lattice x `u` within
    /// their tiles: a sampled layer's windows, else constant and plane
    /// lanes, else stored tiles' windows, else every kind of tile
    /// ([`Self::tile_lanes`]).
    #[inline(always)]
    fn next_tiles<const ANALYTIC: bool, const BENDS: bool>(
        &self,
        row: usize,
        ci: [u32; LANES],
        u: f32x4,
        lanes: &mut TileLanes<'a>,
        bends: &mut BendLanes,
    ) {
        if !ANALYTIC {
            // (`None` never happens in a layer of such tiles only.)
            lanes.windows = self.sample_windows(row, ci).unwrap_or([&OUTSIDE_WINDOW; LANES]);
        } else if self.affine_lanes(row, ci, u, lanes) {
            // Constant and plane tiles only, the tiles the compiler writes
            // along straight edges and inside and outside regions, first: no
            // decode by kind, no second record, no samples.
            if BENDS {
                (bends.arced, bends.segged, bends.fined) = (false, false, false);
            }
        } else {
            // Then outside, inside and stored tiles: their lanes need nothing
            // but their windows. But lanes that met another kind of tile most
            // likely meet one again in the next tile row (a band or a corner
            // crosses rows of tiles): they skip the lookup that would fail.
            // (`tile_lanes` reads every kind, so a wrong guess costs time,
            // never a frame.)
            let windows = if lanes.decoded { None } else { self.sample_windows(row, ci) };
            match windows {
                Some(windows) => {
                    (lanes.windows, lanes.analytic, lanes.bent, lanes.affine, lanes.decoded) =
                        (windows, false, false, false, false)
                }
                None => *lanes = self.tile_lanes::<BENDS>(row, ci, u, bends),
            }
        }
    }

    /// The analytic lanes' code at lattice y `wt` within their tile, in
    /// units of `W`: `T − sign · |A|`, replaced in bend, arc, segments and
    /// fine lanes by their own code.
    #[inline(always)]
    fn analytic_code<const BENDS: bool>(&self, lanes: &TileLanes<'a>, bends: &BendLanes, wt: f32) -> f32x4 {
        let mut code = lanes.t0 + lanes.tgy * wt;
        if !lanes.flat {
            code -= lanes.sign * (lanes.a0 + lanes.gy * wt).abs();
        }
        if BENDS && lanes.bent {
            code = cast::<i32x4, f32x4>(i32x4::new(bends.bend)).select(Self::bend(bends, wt), code);
        }
        if BENDS && bends.arced {
            code = cast::<i32x4, f32x4>(i32x4::new(bends.arc)).select(Self::arc(bends, wt), code);
        }
        if BENDS && bends.segged {
            code = cast::<i32x4, f32x4>(i32x4::new(bends.seg)).select(Self::segments(bends, wt), code);
        }
        if BENDS && bends.fined {
            code = cast::<i32x4, f32x4>(i32x4::new(bends.fine)).select(self.fine(bends, wt), code);
        }
        code
    }

    /// The kernel: adds this layer's deflection for the frame's rows to
    /// `acc`, up to eight rows and four columns at a time, for a grating or
    /// a vibration (`GRATING`) over sampled tiles only or analytic ones
    /// (`ANALYTIC`), with bend, arc, segments and fine tiles (`BENDS`).
    #[inline(always)]
    fn rows<const GRATING: bool, const ANALYTIC: bool, const BENDS: bool>(&self, f: &Frame, acc: &mut Acc) {
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
        let (y0, inv_pitch, rmax) = (f32x4::splat(self.y0), f32x4::splat(self.inv_pitch), f32x4::splat(self.rmax));
        // Up to eight rows at a time: their lattice cells and vertical
        // weights, computed once for all column groups (every row of a
        // 64-actuator array at once), four rows in the lanes (row_y's
        // arithmetic; fy ≥ 0, where truncation is the floor). Rows past
        // `r_hi` are computed and not played.
        let lattice = |r: usize| {
            let y = f32x4::splat(f.y_first) + f32x4::from_i32x4(i32x4::splat(r as i32) + lane_index) * f.pitch_y;
            let fy = ((y - y0) * inv_pitch).fast_max(f32x4::ZERO);
            let cj = fy.fast_min(rmax).fast_trunc_int();
            let wy = (fy - f32x4::from_i32x4(cj)).fast_min(f32x4::ONE).to_array();
            // The lattice y within the row's tile, for analytic lanes.
            let tile_y = f32x4::from_i32x4((cj >> SHIFT as i32) << SHIFT as i32);
            let wt = (fy - tile_y).fast_min(f32x4::splat(TILE_CELLS as f32));
            (cast::<i32x4, [u32; LANES]>(cj), wy, wt.to_array())
        };
        let mut r8 = r_lo;
        while r8 < r_hi {
            let ((cj0, wy0, wt0), (cj1, wy1, wt1)) = (lattice(r8), lattice(r8 + LANES));
            let pick = |a: [u32; LANES], b: [u32; LANES]| -> [u32; ROWS] {
                core::array::from_fn(|i| if i < LANES { a[i % LANES] } else { b[i % LANES] })
            };
            let pickf = |a: [f32; LANES], b: [f32; LANES]| -> [f32; ROWS] {
                core::array::from_fn(|i| if i < LANES { a[i % LANES] } else { b[i % LANES] })
            };
            let (cjs, wys, wts) = (pick(cj0, cj1), pickf(wy0, wy1), pickf(wt0, wt1));
            // A grating's phase from row `f.r0` to each of these rows (the
            // product each row took, in lanes).
            let row_phase =
                |r: usize| (f32x4::from_i32x4(i32x4::splat((r - f.r0) as i32) + lane_index) * step_row).to_array();
            let phases = if GRATING { pickf(row_phase(r8), row_phase(r8 + LANES)) } else { [0.0; ROWS] };
            let rows = ROWS.min(r_hi - r8);
            let mut cols = c_lo;
            while cols < c_hi {
                let first = f32x4::from_i32x4(i32x4::splat(cols as i32) + lane_index);
                let x = (f32x4::splat(f.x_first) + first * f.pitch_x).fast_min(f32x4::splat(last_x));
                let fx = ((x - self.x0) * self.inv_pitch).fast_max(f32x4::ZERO);
                // Clamped before the truncation, as the rows are (`fx ≥ 0`, and
                // `cmax` is exact in f32): SSE2 has no 32-bit integer min or max.
                let ci = fx.fast_min(f32x4::splat(self.cmax)).fast_trunc_int();
                let wi = ((fx - f32x4::from_i32x4(ci)).fast_min(f32x4::ONE) * W as f32).fast_round_int();
                let real = lane_index.simd_lt(i32x4::splat((c_hi - cols) as i32));
                let w: i16x8 = cast(((i32x4::splat(W) - wi) | (wi << 16)) & real);
                // Each lane's lattice x within its tile, for plane and ridge tiles.
                let tile_x = f32x4::from_i32x4((ci >> SHIFT as i32) << SHIFT as i32);
                let u = (fx - tile_x).fast_min(f32x4::splat(TILE_CELLS as f32));
                let ci = cast::<i32x4, [u32; LANES]>(ci);
                // Lanes past the run have weights 0, code 0, but a profile's
                // amplitude at code 0 need not be 0: their factor is.
                let real = cast::<i32x4, f32x4>(real);
                let parity = parity.map(|p| p & real);
                let half_unit = half_unit & real;
                let group_phase = f32x4::splat(base + (cols - c_lo) as i32 as f32 * step_col) + lane_phase;
                // The lanes' tiles change only every eight lattice rows.
                let mut ty_now = u32::MAX;
                let mut lanes = TileLanes::default();
                let mut bends = BendLanes::default();
                for k in 0..rows {
                    let (r, cj) = (r8 + k, cjs[k]);
                    let ty = cj >> SHIFT;
                    if ty != ty_now {
                        ty_now = ty;
                        let row = ty as usize * self.tile_cols as usize;
                        self.next_tiles::<ANALYTIC, BENDS>(row, ci, u, &mut lanes, &mut bends);
                    }
                    // The lanes' interpolated samples.
                    let samples = |lanes: &TileLanes| {
                        let (top, bot) =
                            Self::pairs(&lanes.windows, (cj & (TILE_CELLS as u32 - 1)) as usize * TILE_SIDE);
                        let t = f32x4::from_i32x4(top.dot(w));
                        let b = f32x4::from_i32x4(bot.dot(w));
                        t + (b - t) * f32x4::splat(wys[k])
                    };
                    let v = if ANALYTIC && lanes.affine {
                        // Constant and plane lanes only: `T` alone, no
                        // samples (one test for the rows of such tiles).
                        (lanes.t0 + lanes.tgy * wts[k]) * W as f32
                    } else if ANALYTIC && lanes.analytic {
                        let code = self.analytic_code::<BENDS>(&lanes, &bends, wts[k]);
                        // Only lanes in stored tiles read samples.
                        if lanes.sampled {
                            cast::<i32x4, f32x4>(lanes.planar).select(code * W as f32, samples(&lanes))
                        } else {
                            code * W as f32
                        }
                    } else {
                        samples(&lanes)
                    };
                    let a = (v * slope + offset).fast_max(f32x4::ZERO).fast_min(f32x4::ONE);
                    let v = if GRATING {
                        let phase = f32x4::splat(phases[k]) + group_phase;
                        a * (f32x4::ONE + cos_turns4(phase)) * half_unit
                    } else {
                        a * parity[(r + cols) & 1]
                    };
                    add_lanes(acc, (r - f.r0) * f.cols + cols, v);
                }
                cols += LANES;
            }
            r8 += ROWS;
        }
    }
}

kernel! {
/// [`FieldLayer::accumulate`] (a `kernel!`).
fn accumulate_field<'a>(layer: &FieldLayer<'a>, f: &Frame, acc: &mut Acc) {
    layer.accumulate_in(f, acc)
}
}
