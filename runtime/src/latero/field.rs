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
//! of line on a tile change and played only in rows that have an arc lane. A tile change first looks up each lane's window as if
//! every lane's tile stored samples or were constant, the common case
//! (region interiors and exteriors are constant tiles), and only when a
//! lane's tile is of another kind reads the lanes' records. Which of these
//! the kernel carries is chosen per layer at load ([`Tiles`]): a layer whose
//! tiles all store samples or are constant runs an instance with no analytic
//! lanes at all; only a layer with bend tiles carries the bend lanes. The
//! cost per actuator per layer is bounded: it
//! depends neither on the number of shapes in the layer nor on where their
//! edges are.

use taxel_format::{
    DistanceView, PLANE_RECORD_LEN, SEGMENTS_PER_TILE, TILE_CELLS, TILE_FIRST_STORED, TILE_INSIDE, TILE_OUTSIDE,
    TILE_PLANE, TILE_SAMPLES, TILE_SIDE, TileEntry,
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
    /// The lanes in such tiles.
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
    /// centre's x, the centre's y, the radius, `k` and the top code.
    arc: [i32; LANES],
    c: [[f32; LANES]; 5],
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
        }
    }
}

/// What a tile index entry makes a lane read.
#[derive(Debug, Clone, Copy)]
enum Read<'a> {
    Samples(&'a Tile),
    /// A plane, ridge, corner or notch tile's record bytes (two records
    /// for a corner or notch), and its kind.
    Plane(&'a [u8], TileEntry),
}

/// A distance layer prepared for playback.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FieldLayer<'a> {
    primitive: Primitive,
    /// The tile index, one little-endian `u32` entry per tile.
    entries: &'a [[u8; 4]],
    /// The stored tiles' samples, row by row.
    stored: &'a [Tile],
    /// The plane and ridge records (format 3.0), four little-endian `f32` each.
    planes: &'a [u8],
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
            planes: m.plane_bytes(),
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
                    TileEntry::Bend(_) | TileEntry::Arc(_) | TileEntry::Segments(_) => Tiles::Bent,
                    _ if t == Tiles::Bent => t,
                    _ => Tiles::Analytic,
                }
            }),
        }
    }

    /// Adds this layer's deflection for rows `f.r0..f.r1` to `acc`.
    #[inline(never)]
    pub(crate) fn accumulate(&self, f: &Frame, acc: &mut Acc) {
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
    /// `W`), so they need no per-lane select; a plane or ridge tile's lanes
    /// take its affine code at their column, `c + gx u`, and its gradient
    /// along y. (An index entry past the stored tiles or records, which
    /// validation rules out, reads as outside.)
    #[inline(always)]
    fn tile_lanes<const BENDS: bool>(
        &self,
        tile_row: usize,
        ci: [u32; LANES],
        u: [f32; LANES],
        bl: &mut BendLanes,
    ) -> TileLanes<'a> {
        let mut t = TileLanes::default();
        if BENDS {
            bl.arced = false;
            bl.segged = false;
        }
        let mut planar = [0i32; LANES];
        let (mut t0, mut tgy, mut a0, mut gy, mut sign) =
            ([0f32; LANES], [0f32; LANES], [0f32; LANES], [0f32; LANES], [0f32; LANES]);
        // The lanes' columns grow from lane to lane, so neighbours often
        // share a tile: each tile is looked up once.
        let mut read = self.tile(tile_row + (ci[0] >> SHIFT) as usize);
        let mut prev = ci[0] >> SHIFT;
        for k in 0..LANES {
            let c = ci[k];
            if c >> SHIFT != prev {
                prev = c >> SHIFT;
                read = self.tile(tile_row + prev as usize);
            }
            match read {
                Read::Samples(tile) => {
                    let col = (c & (TILE_CELLS as u32 - 1)) as usize;
                    // A column below TILE_CELLS leaves a whole window: never `None`.
                    t.windows[k] =
                        tile.get(col..col + WINDOW).and_then(|w| w.try_into().ok()).unwrap_or(&OUTSIDE_WINDOW);
                }
                Read::Plane(r, kind) => {
                    let f = |o: usize| r.get(o..o + 4).map_or(0.0, |b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]));
                    // A record's affine code at the lane's column, and its gradient along y.
                    let affine = |o: usize| (f(o) + f(o + 4) * u[k], f(o + 8));
                    let (a, g) = affine(0);
                    match kind {
                        TileEntry::Ridge(_) => {
                            (t0[k], a0[k], gy[k], sign[k]) = (f(12), a, g, 1.0);
                        }
                        TileEntry::Corner(_) | TileEntry::Notch(_) => {
                            let (a2, g2) = affine(PLANE_RECORD_LEN);
                            (t0[k], tgy[k]) = ((a + a2) * 0.5, (g + g2) * 0.5);
                            (a0[k], gy[k]) = ((a - a2) * 0.5, (g - g2) * 0.5);
                            sign[k] = if matches!(kind, TileEntry::Notch(_)) { -1.0 } else { 1.0 };
                        }
                        // (A layer without bend tiles never reads one: `bends`.)
                        TileEntry::Bend(_) if BENDS => {
                            // The first bend lane of these tiles clears the others'.
                            Self::bend_lane(r, u[k], k, !t.bent, bl);
                            t.bent = true;
                        }
                        TileEntry::Arc(_) if BENDS => {
                            Self::arc_lane(r, u[k], k, !bl.arced, bl);
                            bl.arced = true;
                        }
                        TileEntry::Segments(_) if BENDS => {
                            Self::segments_lane(r, u[k], k, !bl.segged, bl);
                            bl.segged = true;
                        }
                        _ => (t0[k], tgy[k]) = (a, g),
                    }
                    planar[k] = -1;
                    t.analytic = true;
                }
            }
        }
        t.planar = i32x4::new(planar);
        (t.t0, t.tgy, t.a0, t.gy, t.sign) =
            (f32x4::new(t0), f32x4::new(tgy), f32x4::new(a0), f32x4::new(gy), f32x4::new(sign));
        t
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
    fn bend_lane(r: &[u8], u: f32, k: usize, first: bool, bl: &mut BendLanes) {
        if first {
            bl.bend = [0; LANES];
        }
        let f = |o: usize| r.get(o..o + 4).map_or(0.0, |b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        for (i, v) in bl.v.iter_mut().enumerate() {
            v[k] = f(4 * i);
        }
        bl.v[0][k] = u - bl.v[0][k];
        bl.bend[k] = -1;
    }

    /// The arc lanes' codes at lattice y `wt` within the tile (format 4.1):
    /// `top − k · ||q − C| − R|`, one square root per row for four lanes,
    /// out of line as [`Self::bend`].
    #[inline(never)]
    fn arc(b: &BendLanes, wt: f32) -> f32x4 {
        let [dx, cy, radius, k, top] = b.c.map(f32x4::new);
        let dy = f32x4::splat(wt) - cy;
        top - k * ((dx * dx + dy * dy).sqrt() - radius).abs()
    }

    /// Lane `k`'s arc values from its tile's two records `r` ((Cx, Cy, R,
    /// k), (top, 0, 0, 0)), at lattice x `u` in the tile; the `first` arc
    /// lane of a tile change clears the other lanes' flags.
    #[cold]
    #[inline(never)]
    fn arc_lane(r: &[u8], u: f32, k: usize, first: bool, bl: &mut BendLanes) {
        if first {
            bl.arc = [0; LANES];
        }
        let f = |o: usize| r.get(o..o + 4).map_or(0.0, |b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        for (i, v) in bl.c.iter_mut().enumerate() {
            v[k] = f(4 * i);
        }
        bl.c[0][k] = u - bl.c[0][k];
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

    /// What the tile at index entry `i` makes its lanes read.
    #[inline(always)]
    fn tile(&self, i: usize) -> Read<'a> {
        let e = self.entries.get(i).map_or(TILE_OUTSIDE, |b| u32::from_le_bytes(*b));
        // Stored tiles first, the common kind near edges: one bounds check
        // decodes them. Any other entry (below `TILE_FIRST_STORED`, or with
        // a kind's high bits) is no stored tile's number once shifted down.
        if let Some(tile) = self.stored.get(e.wrapping_sub(TILE_FIRST_STORED) as usize) {
            return Read::Samples(tile);
        }
        match TileEntry::of(e) {
            TileEntry::Outside => Read::Samples(&OUTSIDE),
            TileEntry::Inside => Read::Samples(&INSIDE),
            TileEntry::Stored(k) => Read::Samples(self.stored.get(k as usize).unwrap_or(&OUTSIDE)),
            kind @ (TileEntry::Plane(p)
            | TileEntry::Ridge(p)
            | TileEntry::Corner(p)
            | TileEntry::Notch(p)
            | TileEntry::Bend(p)
            | TileEntry::Arc(p)
            | TileEntry::Segments(p)) => {
                let at = p as usize * PLANE_RECORD_LEN;
                match self.planes.get(at..at + kind.records() as usize * PLANE_RECORD_LEN) {
                    Some(r) => Read::Plane(r, kind),
                    None => Read::Samples(&OUTSIDE),
                }
            }
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

    /// The samples of the tile at index entry `i` as [`Self::tile`] reads
    /// an outside, inside or stored tile; `None` for any other kind.
    #[inline(always)]
    fn sampled(&self, i: usize) -> Option<&'a Tile> {
        let e = self.entries.get(i).map_or(TILE_OUTSIDE, |b| u32::from_le_bytes(*b));
        match self.stored.get(e.wrapping_sub(TILE_FIRST_STORED) as usize) {
            Some(tile) => Some(tile),
            None if e == TILE_INSIDE => Some(&INSIDE),
            // Outside, or a stored tile past the stored ones (which
            // validation rules out): outside.
            None if e < TILE_PLANE => Some(&OUTSIDE),
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
            let u = cast::<f32x4, [f32; LANES]>((fx - tile_x).fast_min(f32x4::splat(TILE_CELLS as f32)));
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
                let fy = fy.to_array();
                for k in 0..LANES.min(r_hi - r4) {
                    let (r, cj, wy) = (r4 + k, cj[k], f32x4::splat(wy[k]));
                    let ty = cj >> SHIFT;
                    if ty != ty_now {
                        ty_now = ty;
                        let row = ty as usize * self.tile_cols as usize;
                        // Outside, inside and stored tiles first: their
                        // lanes need nothing but their windows. But lanes
                        // that met an analytic tile most likely meet one
                        // again in the next tile row (a straight edge or a
                        // band crosses rows of tiles): they skip the lookup
                        // that would fail. (`tile_lanes` reads every kind,
                        // so a wrong guess costs time, never a frame.)
                        if ANALYTIC && lanes.analytic {
                            lanes = self.tile_lanes::<BENDS>(row, ci, u, &mut bends);
                        } else {
                            match self.sample_windows(row, ci) {
                                Some(windows) => (lanes.windows, lanes.analytic, lanes.bent) = (windows, false, false),
                                // (Never in a layer of such tiles only.)
                                None if !ANALYTIC => lanes.windows = [&OUTSIDE_WINDOW; LANES],
                                None => lanes = self.tile_lanes::<BENDS>(row, ci, u, &mut bends),
                            }
                        }
                    }
                    let (top, bot) = Self::pairs(&lanes.windows, (cj & (TILE_CELLS as u32 - 1)) as usize * TILE_SIDE);
                    let t = f32x4::from_i32x4(top.dot(w));
                    let b = f32x4::from_i32x4(bot.dot(w));
                    let mut v = t + (b - t) * wy;
                    if ANALYTIC && lanes.analytic {
                        // The analytic lanes' code at this row's
                        // lattice y within the tile, in units of `W`.
                        let wt = (fy[k] - (ty << SHIFT) as f32).min(TILE_CELLS as f32);
                        let mut code = (lanes.t0 + lanes.tgy * wt) - lanes.sign * (lanes.a0 + lanes.gy * wt).abs();
                        if BENDS && lanes.bent {
                            code = cast::<i32x4, f32x4>(i32x4::new(bends.bend)).select(Self::bend(&bends, wt), code);
                        }
                        if BENDS && bends.arced {
                            code = cast::<i32x4, f32x4>(i32x4::new(bends.arc)).select(Self::arc(&bends, wt), code);
                        }
                        if BENDS && bends.segged {
                            code = cast::<i32x4, f32x4>(i32x4::new(bends.seg)).select(Self::segments(&bends, wt), code);
                        }
                        v = cast::<i32x4, f32x4>(lanes.planar).select(code * W as f32, v);
                    }
                    let a = (v * slope + offset).fast_max(f32x4::ZERO).fast_min(f32x4::ONE);
                    let v = if GRATING {
                        let phase = f32x4::splat((r - f.r0) as i32 as f32 * step_row) + group_phase;
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
