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
//! `curved_lanes` and its row function beside [`FieldLayer::bend`].) Which of these
//! the kernel carries is chosen per layer at load ([`Tiles`]): a layer whose
//! tiles all store samples or are constant runs an instance with no analytic
//! lanes at all; only a layer with bend tiles carries the bend lanes. The
//! cost per actuator per layer is bounded: it
//! depends neither on the number of shapes in the layer nor on where their
//! edges are.

use taxel_format::{
    DistanceView, PLANE_RECORD_LEN, SEGMENTS_PER_TILE, TILE_CELLS, TILE_FINE, TILE_FIRST_STORED, TILE_INSIDE,
    TILE_OUTSIDE, TILE_PLANE, TILE_RECORD_MASK, TILE_SAMPLES, TILE_SIDE, TileEntry, fine_cell,
};
use wide::bytemuck::cast;
#[cfg(not(target_arch = "x86_64"))]
use wide::u16x8;
use wide::{f32x4, i16x8, i32x4, u8x16};

use super::mask::Primitive;
use super::osc::{cos_turns, cos_turns4, frac64};
use super::{Acc, Frame, LANES, add_lanes};

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

/// The bend lanes (format 4.0) of a [`TileLanes`]: a bend lane plays `top −
/// k · min(dist(q, ray 1), dist(q, ray 2))` ([`FieldLayer::bend`]); `v`
/// holds per lane its column less its vertex's x, the vertex's y, its
/// rays' unit directions (x, y, x, y), its codes per cell and its top
/// code. Kept apart and written out of line, so that tiles without bends
/// cost nothing more.
#[derive(Debug, Clone, Copy, Default)]
struct BendLanes {
    bend: [i32; LANES],
    v: [[f32; LANES]; 8],
    /// The arc lanes (format 4.1): an arc lane plays `top − k · ||q − C| −
    /// R|` ([`FieldLayer::arc`]); `c` holds per lane its column less its
    /// centre's x, the centre's y, the radius, `k` and the top code, then a
    /// cut arc's plane (format 4.3) at its column and its gradient along y
    /// (`f32::MAX` and 0 for an arc alone, so that the lesser is the arc's).
    arc: [i32; LANES],
    c: [[f32; LANES]; 7],
    /// Whether any lane of the current tiles is in an arc tile. Kept here,
    /// not in [`TileLanes`], so that kernels without bend lanes are the
    /// code they were before arcs; reset on every tile change that reads
    /// records.
    arced: bool,
    /// The segments lanes (format 4.2): a segments lane plays `top − k ·
    /// min_i dist(q, segment i)` over three segments
    /// ([`FieldLayer::segments`]); `s` holds per lane, for each segment, its
    /// column less the segment's first end's x, that end's y, the segment's
    /// vector (x, y) and the inverse of its squared length (0 for a point),
    /// then `k` and the top code.
    seg: [i32; LANES],
    s: [[f32; LANES]; SEGMENT_LANE_VALUES],
    /// Whether any lane of the current tiles is in a segments tile, reset
    /// as `arced` is.
    segged: bool,
    /// The fine lanes (format 4.4): a fine lane plays the bilinear
    /// interpolation of its fine tile's samples, or the lesser of its two
    /// channels' ([`FieldLayer::fine`]); per lane its first stored tile,
    /// its refinement, whether it has two channels, and its lattice x
    /// within the tile.
    fine: [i32; LANES],
    fine_first: [u32; LANES],
    fine_by: [u32; LANES],
    fine_pair: [bool; LANES],
    fine_u: [f32; LANES],
    /// Whether any lane of the current tiles is in a fine tile, reset as
    /// `arced` is.
    fined: bool,
}

/// Values per lane of a segments tile: five per segment, `k` and `top`.
const SEGMENT_LANE_VALUES: usize = 5 * SEGMENTS_PER_TILE + 2;

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

/// One plane record's bytes: `c`, `gx`, `gy`, `top` (little-endian `f32`).
type Record = [u8; PLANE_RECORD_LEN];
/// The record a lane with no record of its own reads: zero everywhere.
static ZERO_RECORD: Record = [0; PLANE_RECORD_LEN];

/// What a tile index entry makes its lanes read, decoded once for the
/// lanes that share the tile ([`FieldLayer::lane`]): the same three fields
/// for every kind, which a lane copies with no branch.
#[derive(Debug, Clone, Copy)]
struct Lane<'a> {
    /// The samples a lane reads: a stored tile's, or a constant tile's
    /// (0 outside, 255 inside); the outside tile's for the other kinds.
    tile: &'a Tile,
    /// The records a lane plays `T − sign · |A|` from ([`TileLanes`]): a
    /// plane's or a ridge's record twice, a corner's or a notch's two, a
    /// constant tile's code as a plane's `c` twice, a bend's or an arc's
    /// two (whose code replaces this one); zeros for a stored tile.
    records: [&'a Record; 2],
    /// What the lane plays: [`Lane::PLANAR`] and the other flags.
    kind: u32,
}

impl Lane<'_> {
    /// The lane plays its records' code rather than its samples (every kind
    /// but a stored tile).
    const PLANAR: u32 = 1;
    /// ... as a constant, plane, ridge, corner or notch tile.
    const CODE: u32 = 2;
    /// A plane, ridge, corner, notch, bend or arc tile.
    const ANALYTIC: u32 = 4;
    /// A ridge tile: `T` is its top, `A` its affine code, sign 1.
    const RIDGE: u32 = 8;
    /// A corner tile, sign 1, or a notch tile, sign −1.
    const CORNER: u32 = 16;
    const NOTCH: u32 = 32;
    /// A bend or an arc tile (formats 4.0 and 4.1), played out of line.
    const BEND: u32 = 64;
    const ARC: u32 = 128;
    /// A segments tile (format 4.2), played out of line.
    const SEGMENTS: u32 = 256;
    /// A fine tile (format 4.4), played out of line.
    const FINE: u32 = 512;
}

/// The constant tiles' codes as plane records (`c` only): a lane in a
/// constant tile among analytic lanes plays its code as a plane, so that
/// rows with no stored tile read no samples.
static OUTSIDE_RECORD: Record = ZERO_RECORD;
static INSIDE_RECORD: Record = {
    let c = 255f32.to_le_bytes();
    [c[0], c[1], c[2], c[3], 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]
};

/// A record's four values as one vector (one load on little-endian targets).
#[inline(always)]
fn record_of(r: &Record) -> f32x4 {
    f32x4::new(core::array::from_fn(|i| f32::from_le_bytes([r[4 * i], r[4 * i + 1], r[4 * i + 2], r[4 * i + 3]])))
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

    /// For the tile row starting at index entry `tile_row`, four lanes' cell
    /// columns `ci` and lattice x within their tiles `u`: what each lane
    /// reads until its tile changes. A stored tile's lanes read the window
    /// of its samples that starts at the lane's column; a constant tile's
    /// lanes read a tile of that constant code (0 outside, 255 inside),
    /// whose interpolation is the constant exactly (the weights sum to
    /// `W`), and play it as a plane of that code too (the same code, so
    /// that rows whose lanes read no stored tile read no samples); a plane,
    /// ridge, corner or notch tile's lanes take their records' affine codes
    /// at their column, `c + gx u`, and gradients along y. Each tile is
    /// decoded once for the lanes that share it ([`Self::lane`]); the
    /// records are read as one vector each and the lanes' values computed
    /// four at a time. (An index entry past the stored tiles or records,
    /// which validation rules out, reads as outside.)
    #[inline(always)]
    fn tile_lanes<const BENDS: bool>(
        &self,
        tile_row: usize,
        ci: [u32; LANES],
        u: f32x4,
        bl: &mut BendLanes,
    ) -> TileLanes<'a> {
        let mut t = TileLanes { decoded: true, ..TileLanes::default() };
        if BENDS {
            bl.arced = false;
            bl.segged = false;
            bl.fined = false;
        }
        let (mut first, mut second) = ([&ZERO_RECORD; LANES], [&ZERO_RECORD; LANES]);
        let mut kind = [0u32; LANES];
        // The lanes' kinds, or'ed and and'ed.
        let (mut any, mut all) = (0u32, u32::MAX);
        // The lanes' columns grow from lane to lane, so neighbours often
        // share a tile: each tile is decoded once.
        let mut prev = ci[0] >> SHIFT;
        let mut lane = self.lane(tile_row + prev as usize);
        for k in 0..LANES {
            let c = ci[k];
            if c >> SHIFT != prev {
                prev = c >> SHIFT;
                lane = self.lane(tile_row + prev as usize);
            }
            let col = (c & (TILE_CELLS as u32 - 1)) as usize;
            // A column below TILE_CELLS leaves a whole window: never `None`.
            t.windows[k] = lane.tile.get(col..col + WINDOW).and_then(|w| w.try_into().ok()).unwrap_or(&OUTSIDE_WINDOW);
            [first[k], second[k]] = lane.records;
            kind[k] = lane.kind;
            (any, all) = (any | lane.kind, all & lane.kind);
        }
        t.analytic = any & Lane::ANALYTIC != 0;
        t.sampled = all & Lane::PLANAR == 0;
        t.flat = any & (Lane::RIDGE | Lane::CORNER | Lane::NOTCH) == 0;
        // (A layer without bend tiles never reads one: `bends`.)
        if BENDS && any & (Lane::BEND | Lane::ARC | Lane::SEGMENTS | Lane::FINE) != 0 {
            self.curved_lanes(tile_row, ci, &kind, &first, &second, u, &mut t.bent, bl);
        }
        let kind = i32x4::new(kind.map(|k| k as i32));
        let has = |flag: u32| (kind & i32x4::splat(flag as i32)).simd_eq(i32x4::splat(flag as i32));
        // Every lane but a stored tile's plays its code: `T − sign · |A|`.
        // With `A1`, `A2` the records' affine codes (a plane's, a ridge's
        // and a constant's twice), `T = (A1 + A2) / 2` and `A = (A1 − A2)
        // / 2` (exactly `A1` and 0 for a plane); a ridge's `T` is its top
        // and its `A` its affine code.
        t.planar = has(Lane::PLANAR);
        // (Bend and arc lanes alone need none of it: their code replaces it.
        // Tested in layers with bend tiles only, where it pays.)
        if any & Lane::CODE != 0 || !BENDS {
            let [c1, gx1, gy1, top1] = f32x4::transpose(first.map(record_of));
            let a1 = c1 + gx1 * u;
            let ridge = cast::<i32x4, f32x4>(has(Lane::RIDGE));
            if any & (Lane::CORNER | Lane::NOTCH) != 0 {
                let [c2, gx2, gy2, _] = f32x4::transpose(second.map(record_of));
                let a2 = c2 + gx2 * u;
                let half = f32x4::splat(0.5);
                t.t0 = ridge.select(top1, (a1 + a2) * half);
                t.tgy = ridge.select(f32x4::ZERO, (gy1 + gy2) * half);
                t.a0 = ridge.select(a1, (a1 - a2) * half);
                t.gy = ridge.select(gy1, (gy1 - gy2) * half);
            } else if t.flat {
                // Plane and constant lanes only (a bend's or an arc's aside,
                // whose code replaces this one): `T = A1`; `A` and the sign
                // keep their 0.
                (t.t0, t.tgy) = (a1, gy1);
                return t;
            } else {
                // Every lane's records are one record twice (a bend's or an
                // arc's lanes aside, whose code replaces this one): `T =
                // A1`, `A = 0` exactly.
                (t.t0, t.tgy) = (ridge.select(top1, a1), ridge.select(f32x4::ZERO, gy1));
                (t.a0, t.gy) = (ridge & a1, ridge & gy1);
            }
            let one = cast::<i32x4, f32x4>(has(Lane::RIDGE) | has(Lane::CORNER)) & f32x4::ONE;
            t.sign = one | (cast::<i32x4, f32x4>(has(Lane::NOTCH)) & f32x4::splat(-1.0));
        }
        t
    }

    /// The bend, arc and segments lanes' values (lanes of `kind`
    /// [`Lane::BEND`], [`Lane::ARC`] or [`Lane::SEGMENTS`]) from their
    /// records `first` and `second` (a segments lane's four records are
    /// read again from its entry, at `tile_row` and column `ci`), at
    /// lattice x `u` in their tiles; sets `bent` if any lane is a bend lane.
    #[cold]
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn curved_lanes(
        &self,
        tile_row: usize,
        ci: [u32; LANES],
        kind: &[u32; LANES],
        first: &[&Record; LANES],
        second: &[&Record; LANES],
        u: f32x4,
        bent: &mut bool,
        bl: &mut BendLanes,
    ) {
        let u = u.to_array();
        for k in 0..LANES {
            let r = [first[k], second[k]];
            // The first bend (arc) lane of these tiles clears the others' flags.
            if kind[k] & Lane::ARC != 0 {
                Self::arc_lane(r, u[k], k, !bl.arced, bl);
                bl.arced = true;
            } else if kind[k] & Lane::SEGMENTS != 0 {
                let e = self
                    .entries
                    .get(tile_row + (ci[k] >> SHIFT) as usize)
                    .map_or(TILE_OUTSIDE, |b| u32::from_le_bytes(*b));
                // (`lane` checked the four records are there.)
                if let TileEntry::Segments(p) = TileEntry::of(e)
                    && let Some(r) = self.planes.get(p as usize..p as usize + 4)
                {
                    Self::segments_lane(r.as_flattened(), u[k], k, !bl.segged, bl);
                    bl.segged = true;
                }
            } else if kind[k] & Lane::FINE != 0 {
                let e = self
                    .entries
                    .get(tile_row + (ci[k] >> SHIFT) as usize)
                    .map_or(TILE_OUTSIDE, |b| u32::from_le_bytes(*b));
                // (`lane` checked its stored tiles are there.)
                if let TileEntry::Fine { first, fine, pair } = TileEntry::of(e) {
                    if !bl.fined {
                        bl.fine = [0; LANES];
                    }
                    (bl.fine[k], bl.fine_first[k], bl.fine_by[k], bl.fine_pair[k], bl.fine_u[k]) =
                        (-1, first, fine, pair, u[k]);
                    bl.fined = true;
                }
            } else if kind[k] & Lane::BEND != 0 {
                Self::bend_lane(r, u[k], k, !*bent, bl);
                *bent = true;
            }
        }
    }

    /// The bend lanes' codes at lattice y `wt` within the tile: one square
    /// root per row for four lanes. Out of line, so that rows without bend
    /// lanes keep their registers.
    #[inline(never)]
    fn bend(b: &BendLanes, wt: f32) -> f32x4 {
        let [dx, vy, d1x, d1y, d2x, d2y, k, top] = b.v.map(f32x4::new);
        let dy = f32x4::splat(wt) - vy;
        let r = (dx * dx + dy * dy).sqrt();
        let ray = |ex: f32x4, ey: f32x4| {
            let ahead = (dx * ex + dy * ey).simd_ge(f32x4::ZERO);
            ahead.select((dx * ey - dy * ex).abs(), r)
        };
        top - k * ray(d1x, d1y).fast_min(ray(d2x, d2y))
    }

    /// Lane `k`'s bend values from its tile's two records `r` ((Vx, Vy,
    /// d1x, d1y), (d2x, d2y, k, top)), at lattice x `u` in the tile; the
    /// `first` bend lane of a tile change clears the other lanes' flags.
    #[cold]
    #[inline(never)]
    fn bend_lane(r: [&Record; 2], u: f32, k: usize, first: bool, bl: &mut BendLanes) {
        if first {
            bl.bend = [0; LANES];
        }
        let f = |i: usize| record_of(r[i / 4]).to_array()[i % 4];
        for (i, v) in bl.v.iter_mut().enumerate() {
            v[k] = f(i);
        }
        bl.v[0][k] = u - bl.v[0][k];
        bl.bend[k] = -1;
    }

    /// The arc lanes' codes at lattice y `wt` within the tile (format 4.1):
    /// `top − k · ||q − C| − R|`, one square root per row for four lanes,
    /// out of line as [`Self::bend`].
    #[inline(never)]
    fn arc(b: &BendLanes, wt: f32) -> f32x4 {
        let [dx, cy, radius, k, top, p0, pgy] = b.c.map(f32x4::new);
        let wt = f32x4::splat(wt);
        let dy = wt - cy;
        let arc = top - k * ((dx * dx + dy * dy).sqrt() - radius).abs();
        // A cut arc's plane `(c + gx u') + gy w'` (format 4.3).
        arc.fast_min(p0 + pgy * wt)
    }

    /// Lane `k`'s arc values from its tile's two records `r` ((Cx, Cy, R,
    /// k), (top, c, gx, gy)), at lattice x `u` in the tile; the `first` arc
    /// lane of a tile change clears the other lanes' flags. A second record
    /// whose plane `(c, gx, gy)` is not all 0 is a cut arc (format 4.3):
    /// its plane's value at the column and its `gy` are kept; for an arc
    /// alone, `f32::MAX` and 0, which the lesser never picks.
    #[cold]
    #[inline(never)]
    fn arc_lane(r: [&Record; 2], u: f32, k: usize, first: bool, bl: &mut BendLanes) {
        if first {
            bl.arc = [0; LANES];
        }
        let [cx, cy, radius, kk] = record_of(r[0]).to_array();
        let [top, c, gx, gy] = record_of(r[1]).to_array();
        let cut = c != 0.0 || gx != 0.0 || gy != 0.0;
        let (p0, pgy) = if cut { (c + gx * u, gy) } else { (f32::MAX, 0.0) };
        for (v, x) in bl.c.iter_mut().zip([u - cx, cy, radius, kk, top, p0, pgy]) {
            v[k] = x;
        }
        bl.arc[k] = -1;
    }

    /// The segments lanes' codes at lattice y `wt` within the tile (format
    /// 4.2): `top − k · min_i dist(q, segment i)`, one square root per row
    /// for four lanes, out of line as [`Self::bend`].
    #[inline(never)]
    fn segments(b: &BendLanes, wt: f32) -> f32x4 {
        let v = b.s.map(f32x4::new);
        let mut d2 = f32x4::splat(f32::MAX);
        for i in 0..SEGMENTS_PER_TILE {
            let [dx, ay, ex, ey, inv] = [v[5 * i], v[5 * i + 1], v[5 * i + 2], v[5 * i + 3], v[5 * i + 4]];
            let dy = f32x4::splat(wt) - ay;
            // The nearest point's place along the segment, clamped to it.
            let t = ((dx * ex + dy * ey) * inv).fast_max(f32x4::ZERO).fast_min(f32x4::ONE);
            let (px, py) = (dx - t * ex, dy - t * ey);
            d2 = d2.fast_min(px * px + py * py);
        }
        let [k, top] = [v[5 * SEGMENTS_PER_TILE], v[5 * SEGMENTS_PER_TILE + 1]];
        top - k * d2.sqrt()
    }

    /// The fine lanes' codes at lattice y `wt` within the tile (format
    /// 4.4): each lane's bilinear interpolation of the fine cell it lies
    /// in (the lesser of its two channels'), lane by lane (fine tiles are
    /// few), out of line as [`Self::bend`]. A stored tile past the layer's
    /// (which validation rules out) plays code 0.
    #[inline(never)]
    fn fine(&self, b: &BendLanes, wt: f32) -> f32x4 {
        let mut out = [0.0f32; LANES];
        for (k, code) in out.iter_mut().enumerate() {
            if b.fine[k] == 0 {
                continue;
            }
            let fine = b.fine_by[k] as usize;
            let ((a, i, wx), (sb, j, wy)) = (fine_cell(b.fine_u[k], fine as u32), fine_cell(wt, fine as u32));
            let channel = |c: usize| {
                let slot = (b.fine_first[k] as usize).saturating_add((c * fine + sb) * fine + a);
                let tile = self.stored.get(slot)?;
                let s = |i: usize, j: usize| tile.get(j * TILE_SIDE + i).map_or(0.0, |&v| f32::from(v));
                let top = s(i, j) + (s(i + 1, j) - s(i, j)) * wx;
                let bot = s(i, j + 1) + (s(i + 1, j + 1) - s(i, j + 1)) * wx;
                Some(top + (bot - top) * wy)
            };
            let first = channel(0);
            *code = match (first, b.fine_pair[k]) {
                (Some(c), false) => c,
                (Some(c), true) => channel(1).map_or(0.0, |d| c.min(d)),
                (None, _) => 0.0,
            };
        }
        f32x4::new(out)
    }

    /// Lane `k`'s segments values from its tile's four records `r` (three
    /// segments (ax, ay, bx, by), then (k, top, 0, 0)), at lattice x `u` in
    /// the tile; the `first` segments lane of a tile change clears the other
    /// lanes' flags.
    #[cold]
    #[inline(never)]
    fn segments_lane(r: &[u8], u: f32, k: usize, first: bool, bl: &mut BendLanes) {
        if first {
            bl.seg = [0; LANES];
        }
        let f = |o: usize| r.get(o..o + 4).map_or(0.0, |b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        for i in 0..SEGMENTS_PER_TILE {
            let o = i * PLANE_RECORD_LEN;
            let (ax, ay, ex, ey) = (f(o), f(o + 4), f(o + 8) - f(o), f(o + 12) - f(o + 4));
            let len2 = ex * ex + ey * ey;
            // A segment shorter than a millionth of a cell plays as its first end.
            let inv = if len2 > 1e-12 { 1.0 / len2 } else { 0.0 };
            for (j, x) in [u - ax, ay, ex, ey, inv].into_iter().enumerate() {
                bl.s[5 * i + j][k] = x;
            }
        }
        let o = SEGMENTS_PER_TILE * PLANE_RECORD_LEN;
        bl.s[5 * SEGMENTS_PER_TILE][k] = f(o);
        bl.s[5 * SEGMENTS_PER_TILE + 1][k] = f(o + 4);
        bl.seg[k] = -1;
    }

    /// What the tile at index entry `i` makes its lanes read: one arm per
    /// kind of [`TileEntry`] (a new kind adds its arm here, and its lanes'
    /// values in [`Self::tile_lanes`]).
    #[inline(always)]
    fn lane(&self, i: usize) -> Lane<'a> {
        let e = self.entries.get(i).map_or(TILE_OUTSIDE, |b| u32::from_le_bytes(*b));
        // Stored tiles first, the common kind near edges: one bounds check
        // decodes them. Any other entry (below `TILE_FIRST_STORED`, or with
        // a kind's high bits) is no stored tile's number once shifted down.
        if let Some(tile) = self.stored.get(e.wrapping_sub(TILE_FIRST_STORED) as usize) {
            return Lane { tile, records: [&ZERO_RECORD; 2], kind: 0 };
        }
        let constant = |tile, record| Lane { tile, records: [record; 2], kind: Lane::PLANAR | Lane::CODE };
        let outside = constant(&OUTSIDE, &OUTSIDE_RECORD);
        // Each kind's first record `p`, its second `p + second` (its first
        // twice for 0) and its flags.
        let (p, second, kind) = match TileEntry::of(e) {
            TileEntry::Plane(p) => (p, 0, Lane::CODE),
            TileEntry::Corner(p) => (p, 1, Lane::CODE | Lane::CORNER),
            TileEntry::Notch(p) => (p, 1, Lane::CODE | Lane::NOTCH),
            TileEntry::Ridge(p) => (p, 0, Lane::CODE | Lane::RIDGE),
            TileEntry::Bend(p) => (p, 1, Lane::BEND),
            TileEntry::Arc(p) => (p, 1, Lane::ARC),
            // Its three segments' records are read again from the entry
            // (`curved_lanes`): here the last is checked.
            TileEntry::Segments(p) => (p, 3, Lane::SEGMENTS),
            TileEntry::Inside => return constant(&INSIDE, &INSIDE_RECORD),
            // Its stored tiles are read again from the entry (`curved_lanes`):
            // here the last is checked.
            fine @ TileEntry::Fine { first, .. } => {
                let last = (first as usize).saturating_add(fine.stored() as usize).saturating_sub(1);
                return match self.stored.get(last) {
                    Some(_) => Lane {
                        tile: &OUTSIDE,
                        records: [&ZERO_RECORD; 2],
                        kind: Lane::FINE | Lane::PLANAR | Lane::ANALYTIC,
                    },
                    _ => outside,
                };
            }
            // Outside, or a stored tile past the stored ones.
            TileEntry::Outside | TileEntry::Stored(_) => return outside,
        };
        match (self.planes.get(p as usize), self.planes.get(p as usize + second)) {
            (Some(a), Some(b)) => Lane { tile: &OUTSIDE, records: [a, b], kind: kind | Lane::PLANAR | Lane::ANALYTIC },
            _ => outside,
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

    /// [`Self::tile_lanes`] when every lane's tile stores samples or is
    /// constant: each lane's window of samples in the tile row starting at
    /// index entry `tile_row`, for lanes with cell columns `ci`; `None` if
    /// a lane's tile is of any other kind.
    #[inline(always)]
    fn sample_windows(&self, tile_row: usize, ci: [u32; LANES]) -> Option<[&'a Window; LANES]> {
        let mut windows = [&OUTSIDE_WINDOW; LANES];
        // Neighbouring lanes often share a tile: each is looked up once.
        let mut tile = self.sampled(tile_row + (ci[0] >> SHIFT) as usize)?;
        for k in 0..LANES {
            if k > 0 && ci[k] >> SHIFT != ci[k - 1] >> SHIFT {
                tile = self.sampled(tile_row + (ci[k] >> SHIFT) as usize)?;
            }
            let col = (ci[k] & (TILE_CELLS as u32 - 1)) as usize;
            // A column below TILE_CELLS leaves a whole window: never `None`.
            windows[k] = tile.get(col..col + WINDOW).and_then(|w| w.try_into().ok()).unwrap_or(&OUTSIDE_WINDOW);
        }
        Some(windows)
    }

    /// [`Self::tile_lanes`] when every lane's tile is constant or a plane
    /// tile: each lane plays `T = c + gx u`, `tgy = gy` from its record (a
    /// constant tile's code as a plane's `c`, so `T` is that code exactly),
    /// with no ridge, corner or notch lane (`flat`) and no samples. Only
    /// the fields the rows read in that case are written (the windows,
    /// `planar`, `a0`, `gy` and `sign` keep whatever they held: no row
    /// reads them until a tile change writes them again). Returns false,
    /// leaving `t` alone, if a lane's tile is of any other kind or names a
    /// missing record (then [`Self::tile_lanes`] decides).
    #[inline(always)]
    fn affine_lanes(&self, tile_row: usize, ci: [u32; LANES], u: f32x4, t: &mut TileLanes<'a>) -> bool {
        let mut records = [&OUTSIDE_RECORD; LANES];
        // Neighbouring lanes often share a tile: each is looked up once.
        let mut prev = ci[0] >> SHIFT;
        let Some(mut record) = self.affine(tile_row + prev as usize) else { return false };
        for k in 0..LANES {
            if ci[k] >> SHIFT != prev {
                prev = ci[k] >> SHIFT;
                match self.affine(tile_row + prev as usize) {
                    Some(r) => record = r,
                    None => return false,
                }
            }
            records[k] = record;
        }
        let [c, gx, gy, _] = f32x4::transpose(records.map(record_of));
        (t.t0, t.tgy) = (c + gx * u, gy);
        (t.analytic, t.flat, t.sampled, t.bent, t.affine, t.decoded) = (true, true, false, false, true, false);
        true
    }

    /// The record the tile at index entry `i` plays if it is constant
    /// (its code as a plane's `c`) or a plane tile; `None` for any other
    /// kind, or a plane record past the stored ones.
    #[inline(always)]
    fn affine(&self, i: usize) -> Option<&'a Record> {
        match self.entries.get(i).map_or(TILE_OUTSIDE, |b| u32::from_le_bytes(*b)) {
            TILE_OUTSIDE => Some(&OUTSIDE_RECORD),
            TILE_INSIDE => Some(&INSIDE_RECORD),
            e if e >> 28 == TILE_PLANE >> 28 => self.planes.get((e & TILE_RECORD_MASK) as usize),
            _ => None,
        }
    }

    /// The samples of the tile at index entry `i` as [`Self::lane`] reads
    /// an outside, inside or stored tile; `None` for any other kind.
    #[inline(always)]
    fn sampled(&self, i: usize) -> Option<&'a Tile> {
        let e = self.entries.get(i).map_or(TILE_OUTSIDE, |b| u32::from_le_bytes(*b));
        match self.stored.get(e.wrapping_sub(TILE_FIRST_STORED) as usize) {
            Some(tile) => Some(tile),
            None if e == TILE_INSIDE => Some(&INSIDE),
            // Outside, or a stored tile past the stored ones (which
            // validation rules out): outside.
            // (A fine tile's entry, format 4.4, is not: its lanes are analytic.)
            None if e < TILE_FINE => Some(&OUTSIDE),
            None => None,
        }
    }

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
                        if !ANALYTIC {
                            // (`None` never happens in a layer of such tiles only.)
                            lanes.windows = self.sample_windows(row, ci).unwrap_or([&OUTSIDE_WINDOW; LANES]);
                        } else if self.affine_lanes(row, ci, u, &mut lanes) {
                            // Constant and plane tiles only, the tiles the
                            // compiler writes along straight edges and
                            // inside and outside regions, first: no decode
                            // by kind, no second record, no samples.
                            if BENDS {
                                (bends.arced, bends.segged, bends.fined) = (false, false, false);
                            }
                        } else {
                            // Then outside, inside and stored tiles: their
                            // lanes need nothing but their windows. But
                            // lanes that met another kind of tile most
                            // likely meet one again in the next tile row (a
                            // band or a corner crosses rows of tiles): they
                            // skip the lookup that would fail.
                            // (`tile_lanes` reads every kind, so a wrong
                            // guess costs time, never a frame.)
                            let windows = if lanes.decoded { None } else { self.sample_windows(row, ci) };
                            match windows {
                                Some(windows) => {
                                    (lanes.windows, lanes.analytic, lanes.bent, lanes.affine, lanes.decoded) =
                                        (windows, false, false, false, false)
                                }
                                None => lanes = self.tile_lanes::<BENDS>(row, ci, u, &mut bends),
                            }
                        }
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
                        // The analytic lanes' code at this row's
                        // lattice y within the tile, in units of `W`.
                        let wt = wts[k];
                        let mut code = lanes.t0 + lanes.tgy * wt;
                        if !lanes.flat {
                            code -= lanes.sign * (lanes.a0 + lanes.gy * wt).abs();
                        }
                        if BENDS && lanes.bent {
                            code = cast::<i32x4, f32x4>(i32x4::new(bends.bend)).select(Self::bend(&bends, wt), code);
                        }
                        if BENDS && bends.arced {
                            code = cast::<i32x4, f32x4>(i32x4::new(bends.arc)).select(Self::arc(&bends, wt), code);
                        }
                        if BENDS && bends.segged {
                            code = cast::<i32x4, f32x4>(i32x4::new(bends.seg)).select(Self::segments(&bends, wt), code);
                        }
                        if BENDS && bends.fined {
                            code = cast::<i32x4, f32x4>(i32x4::new(bends.fine)).select(self.fine(&bends, wt), code);
                        }
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
