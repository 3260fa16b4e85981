//! What four lanes read on a tile change: each lane's window of samples
//! (outside, inside and stored tiles), or its tile decoded by kind into its
//! records and flags ([`FieldLayer::lane`]) and the lanes' `T` and `A`
//! computed four at a time ([`FieldLayer::tile_lanes`]).

use taxel_format::{
    PLANE_RECORD_LEN, TILE_CELLS, TILE_FINE, TILE_FIRST_STORED, TILE_INSIDE, TILE_OUTSIDE, TILE_PLANE,
    TILE_RECORD_MASK, TileEntry,
};
use wide::bytemuck::cast;
use wide::{f32x4, i32x4};

use super::{BendLanes, FieldLayer, INSIDE, OUTSIDE, OUTSIDE_WINDOW, SHIFT, Tile, TileLanes, WINDOW, Window};
use crate::latero::LANES;

/// One plane record's bytes: `c`, `gx`, `gy`, `top` (little-endian `f32`).
pub(super) type Record = [u8; PLANE_RECORD_LEN];
/// The record a lane with no record of its own reads: zero everywhere.
static ZERO_RECORD: Record = [0; PLANE_RECORD_LEN];

/// What a tile index entry makes its lanes read, decoded once for the
/// lanes that share the tile ([`FieldLayer::lane`]): the same three fields
/// for every kind, which a lane copies with no branch.
#[derive(Debug, Clone, Copy)]
pub(super) struct Lane<'a> {
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
    pub(super) const PLANAR: u32 = 1;
    /// ... as a constant, plane, ridge, corner or notch tile.
    pub(super) const CODE: u32 = 2;
    /// A plane, ridge, corner, notch, bend or arc tile.
    pub(super) const ANALYTIC: u32 = 4;
    /// A ridge tile: `T` is its top, `A` its affine code, sign 1.
    pub(super) const RIDGE: u32 = 8;
    /// A corner tile, sign 1, or a notch tile, sign −1.
    pub(super) const CORNER: u32 = 16;
    pub(super) const NOTCH: u32 = 32;
    /// A bend or an arc tile (formats 4.0 and 4.1), played out of line.
    pub(super) const BEND: u32 = 64;
    pub(super) const ARC: u32 = 128;
    /// A segments tile (format 4.2), played out of line.
    pub(super) const SEGMENTS: u32 = 256;
    /// A fine tile (format 4.4), played out of line.
    pub(super) const FINE: u32 = 512;
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
pub(super) fn record_of(r: &Record) -> f32x4 {
    f32x4::new(core::array::from_fn(|i| f32::from_le_bytes([r[4 * i], r[4 * i + 1], r[4 * i + 2], r[4 * i + 3]])))
}

impl<'a> FieldLayer<'a> {
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
    pub(super) fn tile_lanes<const BENDS: bool>(
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

    /// [`Self::tile_lanes`] when every lane's tile stores samples or is
    /// constant: each lane's window of samples in the tile row starting at
    /// index entry `tile_row`, for lanes with cell columns `ci`; `None` if
    /// a lane's tile is of any other kind.
    #[inline(always)]
    pub(super) fn sample_windows(&self, tile_row: usize, ci: [u32; LANES]) -> Option<[&'a Window; LANES]> {
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
    pub(super) fn affine_lanes(&self, tile_row: usize, ci: [u32; LANES], u: f32x4, t: &mut TileLanes<'a>) -> bool {
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
}
