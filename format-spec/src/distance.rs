//! Distance layers (`VDST`, `GDST`): one layer per style, stored as a signed
//! distance field in sparse tiles, so that its edge is the drawing's edge and
//! not a pixel grid's (SPEC.md section 6.2).
//!
//! The field holds, at the corners of a square lattice of pitch `h`, the
//! signed distance to the style's exact outline (positive where the style is
//! felt) as a biased byte: `d = (v − 128) · step`, with the layer's `step` in
//! mm. The lattice is cut into tiles of
//! [`TILE_CELLS`] x [`TILE_CELLS`] cells; a tile wholly inside or wholly
//! outside is one index entry, the others store their
//! `(TILE_CELLS + 1)²` corner samples (the shared edge samples repeated, so
//! that a player interpolates inside one tile). A player interpolates the
//! distance bilinearly and maps it to amplitude through the edge profile
//! `clamp(½ + d / soft, 0, 1)`.

use alloc::vec::Vec;

use crate::bytes::{Out, f32_at, u32_at};
use crate::error::FormatError;
use crate::mask::MaskKind;
use crate::units::{MilliHertz, Mm};
use crate::{NO_SOURCE, Tag, in_range};

/// Length of a distance chunk's fixed header.
pub(crate) const DISTANCE_HEADER_LEN: usize = 48;
/// Cells along one side of a tile.
pub const TILE_CELLS: usize = 8;
/// Samples along one side of a stored tile (its cells' corners).
pub const TILE_SIDE: usize = TILE_CELLS + 1;
/// Samples in one stored tile.
pub const TILE_SAMPLES: usize = TILE_SIDE * TILE_SIDE;
/// The sample code of distance 0 (samples are biased bytes).
pub const DISTANCE_ZERO: u8 = 128;
/// Largest number of tiles (index entries) in one distance layer.
pub const MAX_DISTANCE_TILES: u32 = 1 << 22;
/// Largest soft edge width, in mm.
pub const MAX_SOFT_MM: f32 = 16.0;
/// Tile index entry of a tile wholly outside (amplitude 0).
pub const TILE_OUTSIDE: u32 = 0;
/// Tile index entry of a tile wholly inside (full amplitude).
pub const TILE_INSIDE: u32 = 1;
/// Tile index entries from this value up to [`TILE_PLANE`] (exclusive) name
/// stored tile `entry - TILE_FIRST_STORED`.
pub const TILE_FIRST_STORED: u32 = 2;
/// Tile index entry `TILE_PLANE | p`: a **plane** tile, whose code is the
/// affine function of plane record `p` (format 3.0).
pub const TILE_PLANE: u32 = 0x8000_0000;
/// Tile index entry `TILE_RIDGE | p`: a **ridge** tile, whose code is
/// `top − |affine|` of plane record `p` (format 3.0).
pub const TILE_RIDGE: u32 = 0xC000_0000;
/// The bits of a plane or ridge entry that hold its record's number.
pub const TILE_RECORD_MASK: u32 = 0x3FFF_FFFF;
/// Tile index entry `TILE_CORNER | p`: a **corner** tile, whose code is
/// the lesser of the affine functions of plane records `p` and `p + 1`, the
/// exact distance inside a convex corner of the felt region (format 4.0).
/// A 3.0 reader decodes it as a plane entry naming record `2^29 + p`, which
/// its index check refuses.
pub const TILE_CORNER: u32 = 0xA000_0000;
/// Tile index entry `TILE_NOTCH | p`: a **notch** tile, whose code is the
/// greater of the affine functions of plane records `p` and `p + 1` (a
/// concave corner of the felt region, format 4.0).
pub const TILE_NOTCH: u32 = 0xB000_0000;
/// Tile index entry `TILE_BEND | p`: a **bend** tile (format 4.0), a
/// band's centre line bent at a vertex `V` into two rays of unit directions
/// `d1`, `d2` (`d2 = d1` for a band's end): plane record `p` holds
/// `(Vx, Vy, d1x, d1y)`, record `p + 1` holds `(d2x, d2y, k, top)`, in the
/// tile's lattice coordinates, and the code at `q` is
/// `top − k · min(dist(q, ray 1), dist(q, ray 2))`, with `dist(q, ray) =
/// |cross(q − V, d)|` where `dot(q − V, d) ≥ 0`, else `|q − V|`. A 3.0
/// reader decodes it as a plane entry naming record `2^28 + p`, which its
/// index check refuses.
pub const TILE_BEND: u32 = 0x9000_0000;
/// Tile index entry `TILE_ARC | p`: an **arc** tile (format 4.1), a
/// circle of centre `V` and radius `R`: plane record `p` holds
/// `(Vx, Vy, R, k)` in the tile's lattice coordinates (`R` in cells),
/// record `p + 1` holds `(top, 0, 0, 0)`, and the code at `q` is
/// `top − k · ||q − V| − R|`: a band round the circle (a ring), a filled
/// disc (`R` = 0, a cone), or a hole (`R` beyond the tile, where the code
/// grows with `|q − V|`). A 4.0 reader decodes it as a ridge entry naming
/// record `2^28 + p`, which its index check refuses. Where record `p + 1`
/// is `(top, c, gx, gy)` with its plane `(c, gx, gy)` not all 0, a **cut
/// arc** (format 4.3), the code is the lesser of that and
/// `c + gx u + gy w` ([`arc_code`]); a 4.1 or 4.2 reader refuses the
/// record, so it never misplays one.
pub const TILE_ARC: u32 = 0xD000_0000;
/// Tile index entry `TILE_SEGMENTS | p`: a **segments** tile (format 4.2),
/// the union of a band's centre line's pieces near a junction:
/// [`SEGMENT_TILE_RECORDS`] records from `p`, records `p` to `p + 2` each a
/// segment `(ax, ay, bx, by)` and record `p + 3` `(k, top, 0, 0)`, in the
/// tile's lattice coordinates; the code at `q` is
/// `top − k · min_i dist(q, segment i)` ([`segments_code`]). `k` may be
/// negative: a vibrating band cut out of a grating plays
/// `top + |k| · min_i dist(q, segment i)`. A 4.1 reader decodes it as a
/// ridge entry naming record `2^29 + p`, which its index check refuses.
pub const TILE_SEGMENTS: u32 = 0xE000_0000;
/// Tile index entry `TILE_FINE | s << TILE_FINE_SHIFT | c << 25 | k`: a
/// **fine** tile (format 4.4), the distance sampled `f = 2^s` times finer
/// than the layer's lattice (`f` 1, 2, 4 or 8), in one channel (`c` = 0,
/// `f` at least 2) or two (`c` = 1, [`TILE_FINE_PAIR`]): `f²` stored tiles
/// a channel from stored tile `k`, row-major, the channel's sub-tile `(a,
/// b)` (`a, b` below `f`) covering lattice cells `8 a / f ..= 8 (a + 1) /
/// f` by the same along y with 9 x 9 samples `h / f` apart. The code is
/// the channel's bilinear interpolation ([`fine_cell`]), or with two
/// channels the lesser of theirs. Where no single feature decides a tile (a
/// thin wedge between two curved edges, a narrow band cut across a curve),
/// the lattice's own pitch rounds it away; finer samples keep it, and two
/// channels, each the distance to one feature, keep the crease between them
/// exactly. A 4.3 reader decodes it as stored tile `0x6000_0000 − 2 + …`,
/// past every stored tile, which its index check refuses.
pub const TILE_FINE: u32 = 0x6000_0000;
/// Shift of a fine entry's refinement field (two bits: `log2 f`).
pub const TILE_FINE_SHIFT: u32 = 26;
/// The bit of a fine entry that gives it two channels.
pub const TILE_FINE_PAIR: u32 = 1 << 25;
/// The bits of a fine entry that hold its first stored tile's number.
pub const TILE_FINE_FIRST_MASK: u32 = TILE_FINE_PAIR - 1;
/// Finest refinement of a fine tile.
pub const MAX_FINE: u32 = 8;
/// Segments of one segments tile (unused ones repeat a used one).
pub const SEGMENTS_PER_TILE: usize = 3;
/// Plane records of one segments tile: its segments, then `(k, top, 0, 0)`.
pub const SEGMENT_TILE_RECORDS: usize = SEGMENTS_PER_TILE + 1;
/// Largest radius of an arc record, lattice cells.
pub const MAX_ARC_RADIUS: f32 = 2048.0;
/// The bits of a corner, notch or bend entry that hold its first record's number.
pub const TILE_CORNER_RECORD_MASK: u32 = 0x0FFF_FFFF;
/// Bytes of one plane record: `c`, `gx`, `gy`, `top` (f32 each).
pub const PLANE_RECORD_LEN: usize = 16;
/// Largest magnitude of a plane record's gradient, codes per lattice cell.
pub const MAX_PLANE_GRADIENT: f32 = 1024.0;
/// Largest magnitude of a plane record's `c` and `top`, codes.
pub const MAX_PLANE_CODE: f32 = 65_536.0;

/// One plane or ridge tile's record (SPEC.md section 6.2), in sample codes:
/// at lattice coordinates `(u, w)` inside the tile (0 to 8 from its
/// top-left lattice point) the affine code is `c + gx u + gy w`; a plane
/// tile plays it, a ridge tile plays `top − |c + gx u + gy w|`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TilePlane {
    /// The affine function's value at the tile's top-left lattice point.
    pub c: f32,
    /// Codes per lattice cell along x.
    pub gx: f32,
    /// Codes per lattice cell along y.
    pub gy: f32,
    /// A ridge's top code; 0 for a plane.
    pub top: f32,
}

impl TilePlane {
    /// The affine part `c + gx u + gy w`, in f64.
    pub fn affine(&self, u: f64, w: f64) -> f64 {
        self.c as f64 + self.gx as f64 * u + self.gy as f64 * w
    }

    /// The code of a tile with index entry `entry` (a plane or a ridge) at
    /// lattice coordinates `(u, w)` inside it, in f64: SPEC.md's reference.
    pub fn code(&self, entry: u32, u: f64, w: f64) -> f64 {
        let a = self.affine(u, w);
        if entry & TILE_RIDGE == TILE_RIDGE { self.top as f64 - a.abs() } else { a }
    }
}

/// What a tile index entry names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TileEntry {
    /// Amplitude 0.
    Outside,
    /// Full amplitude.
    Inside,
    /// Stored tile `k` (81 samples).
    Stored(u32),
    /// Plane record `p`, played as a plane.
    Plane(u32),
    /// Plane record `p`, played as a ridge.
    Ridge(u32),
    /// Plane records `p` and `p + 1`, played as the lesser of the two (format 4.0).
    Corner(u32),
    /// Plane records `p` and `p + 1`, played as the greater of the two (format 4.0).
    Notch(u32),
    /// Plane records `p` and `p + 1`, played as a band's bent centre line
    /// ([`TILE_BEND`], format 4.0).
    Bend(u32),
    /// Plane records `p` and `p + 1`, played as a circle ([`TILE_ARC`], format 4.1).
    Arc(u32),
    /// Plane records `p` to `p + 3`, played as the nearest of three
    /// segments ([`TILE_SEGMENTS`], format 4.2).
    Segments(u32),
    /// Stored tiles from `first`, the tile sampled `fine` times finer than
    /// the lattice (1, 2, 4 or 8), `fine²` a channel, in two channels where
    /// `pair` ([`TILE_FINE`], format 4.4; one channel at `fine` 1 is
    /// refused).
    Fine {
        /// The first stored tile's number.
        first: u32,
        /// How many times finer than the lattice.
        fine: u32,
        /// Two channels, whose lesser code the tile plays.
        pair: bool,
    },
}

impl TileEntry {
    /// Decodes an index entry by its kind nibble (its top four bits), one
    /// arm per kind: a player decodes an entry on every tile change, and
    /// the kinds are told apart with one jump rather than a chain of tests.
    #[inline]
    pub fn of(e: u32) -> Self {
        match e >> 28 {
            0x8 => TileEntry::Plane(e & TILE_RECORD_MASK),
            0xA => TileEntry::Corner(e & TILE_CORNER_RECORD_MASK),
            0xB => TileEntry::Notch(e & TILE_CORNER_RECORD_MASK),
            0x9 => TileEntry::Bend(e & TILE_CORNER_RECORD_MASK),
            0xD => TileEntry::Arc(e & TILE_CORNER_RECORD_MASK),
            0xE => TileEntry::Segments(e & TILE_CORNER_RECORD_MASK),
            0x6 => TileEntry::fine(e),
            // The other nibbles with both ridge bits (an arc's D and a
            // segments tile's E have them too; format 3.0's ridges were C to F).
            0xC | 0xF => TileEntry::Ridge(e & TILE_RECORD_MASK),
            // Below TILE_PLANE.
            _ => match e {
                TILE_OUTSIDE => TileEntry::Outside,
                TILE_INSIDE => TileEntry::Inside,
                e => TileEntry::Stored(e - TILE_FIRST_STORED),
            },
        }
    }

    /// A fine entry's fields (its kind nibble [`TILE_FINE`]).
    #[inline]
    fn fine(e: u32) -> Self {
        TileEntry::Fine {
            first: e & TILE_FINE_FIRST_MASK,
            fine: 1 << ((e >> TILE_FINE_SHIFT) & 3),
            pair: e & TILE_FINE_PAIR != 0,
        }
    }

    /// The number of plane records a tile of this kind plays: one for a
    /// plane or a ridge, two for a corner, a notch, a bend or an arc, four
    /// for a segments tile, none for the others.
    #[inline]
    pub fn records(self) -> u32 {
        match self {
            TileEntry::Plane(_) | TileEntry::Ridge(_) => 1,
            TileEntry::Corner(_) | TileEntry::Notch(_) | TileEntry::Bend(_) | TileEntry::Arc(_) => 2,
            TileEntry::Segments(_) => SEGMENT_TILE_RECORDS as u32,
            TileEntry::Outside | TileEntry::Inside | TileEntry::Stored(_) | TileEntry::Fine { .. } => 0,
        }
    }

    /// The number of stored tiles a tile of this kind plays: one for a
    /// stored tile, `fine²` a channel for a fine tile, none for the others.
    #[inline]
    pub fn stored(self) -> u32 {
        match self {
            TileEntry::Stored(_) => 1,
            TileEntry::Fine { fine, pair, .. } => fine * fine * (1 + pair as u32),
            _ => 0,
        }
    }

    /// The code of a plane, ridge, corner or notch tile at lattice
    /// coordinates `(u, w)` inside it, in f64, from the layer's plane
    /// records: SPEC.md section 6.2's reference. `None` for the other
    /// kinds, or when a record it names is missing.
    pub fn code(self, records: &[TilePlane], u: f64, w: f64) -> Option<f64> {
        let rec = |p: u32| records.get(p as usize);
        match self {
            TileEntry::Plane(p) => Some(rec(p)?.affine(u, w)),
            TileEntry::Ridge(p) => {
                let r = rec(p)?;
                Some(r.top as f64 - r.affine(u, w).abs())
            }
            TileEntry::Corner(p) => Some(rec(p)?.affine(u, w).min(rec(p.checked_add(1)?)?.affine(u, w))),
            TileEntry::Notch(p) => Some(rec(p)?.affine(u, w).max(rec(p.checked_add(1)?)?.affine(u, w))),
            TileEntry::Bend(p) => {
                let (a, b) = (rec(p)?, rec(p.checked_add(1)?)?);
                Some(bend_code([a, b], u, w))
            }
            TileEntry::Arc(p) => {
                let (a, b) = (rec(p)?, rec(p.checked_add(1)?)?);
                Some(arc_code([a, b], u, w))
            }
            TileEntry::Segments(p) => {
                let r = records.get(p as usize..p as usize + SEGMENT_TILE_RECORDS)?;
                Some(segments_code([&r[0], &r[1], &r[2], &r[3]], u, w))
            }
            TileEntry::Outside | TileEntry::Inside | TileEntry::Stored(_) | TileEntry::Fine { .. } => None,
        }
    }
}

/// The index entry of a fine tile ([`TILE_FINE`]) `fine` times finer than
/// the lattice (1, 2, 4 or 8), of two channels where `pair`, whose stored
/// tiles start at `first`; `None` for another refinement, one channel at
/// `fine` 1 (a stored tile), or a `first` beyond the entry's bits.
pub fn fine_entry(first: u32, fine: u32, pair: bool) -> Option<u32> {
    let s = match fine {
        1 if pair => 0,
        2 => 1,
        4 => 2,
        8 => 3,
        _ => return None,
    };
    let c = if pair { TILE_FINE_PAIR } else { 0 };
    (first <= TILE_FINE_FIRST_MASK).then_some(TILE_FINE | s << TILE_FINE_SHIFT | c | first)
}

/// Where lattice coordinate `u` (in `[0, 8]` within the tile) falls in a
/// fine tile `fine` times finer ([`TILE_FINE`]): its sub-tile along that
/// axis, the fine cell within the sub-tile (0 to 7) and the weight of the
/// cell's far sample, `f u` less the fine cell's start. `u` = 8 falls in
/// the last cell with weight 1. Exact in `f32`: `fine` is a power of two.
#[inline]
pub fn fine_cell(u: f32, fine: u32) -> (usize, usize, f32) {
    let fu = u * fine as f32;
    let last = (TILE_CELLS as u32 * fine).saturating_sub(1);
    // (`as` saturates: a NaN or negative `u` lands in cell 0.)
    let c = (fu as u32).min(last);
    ((c as usize) / TILE_CELLS, (c as usize) % TILE_CELLS, fu - c as f32)
}

/// One distance layer: every shape of one style.
///
/// Tile `(tx, ty)` covers the page rectangle from
/// `(origin_x + 8 tx h, origin_y + 8 ty h)` to `8 h` further on each axis;
/// its stored sample `(i, j)` (`i, j` in `0..=8`) is the distance at
/// `(origin_x + (8 tx + i) h, origin_y + (8 ty + j) h)`.
#[derive(Debug, Clone, PartialEq)]
pub struct DistanceLayer {
    /// The primitive and its parameters.
    pub kind: MaskKind,
    /// Amplitude (0..=1) that scales the whole layer.
    pub amplitude: f32,
    /// Width of the edge profile's ramp in mm; 0 is a hard edge (a ramp one `step` wide).
    pub soft_mm: f32,
    /// Distance of one sample code, mm: sample `v` is the distance `(v − 128) · step`.
    pub step_mm: f32,
    /// Page x of the lattice's first column.
    pub origin_x: Mm,
    /// Page y of the lattice's first row.
    pub origin_y: Mm,
    /// Lattice pitch `h`, mm.
    pub pitch_mm: f32,
    /// Tiles per row.
    pub tile_cols: u32,
    /// Rows of tiles.
    pub tile_rows: u32,
    /// Provenance entries of the elements this layer holds, ascending.
    pub sources: Vec<u32>,
    /// `tile_cols * tile_rows` entries, row-major: [`TILE_OUTSIDE`],
    /// [`TILE_INSIDE`], [`TILE_FIRST_STORED`] + the stored tile's number, or
    /// [`TILE_PLANE`] or [`TILE_RIDGE`] `|` the plane record's number; stored
    /// tiles and plane records are each numbered in the order the index
    /// names them.
    pub tiles: Vec<u32>,
    /// The plane and ridge tiles' records, numbered in index order (format 3.0).
    pub planes: Vec<TilePlane>,
    /// The stored tiles' samples, [`TILE_SAMPLES`] per tile, row-major within a tile.
    pub samples: Vec<u8>,
}

impl DistanceLayer {
    /// The chunk tag for this layer's kind.
    pub fn tag(&self) -> Tag {
        match self.kind {
            MaskKind::Vibration { .. } => Tag::VIBRATION_DISTANCE,
            MaskKind::Grating { .. } => Tag::GRATING_DISTANCE,
        }
    }

    /// Number of stored tiles.
    pub fn stored_tiles(&self) -> usize {
        self.samples.len() / TILE_SAMPLES
    }

    /// The interpolated signed distance at page `(x, y)` in mm, or `None`
    /// outside the lattice (where the layer is 0). Reference implementation
    /// of SPEC.md section 6.2 for tools; players use their own kernels.
    pub fn distance_at(&self, x: f32, y: f32) -> Option<f32> {
        let h = self.pitch_mm;
        let fx = (x - self.origin_x.0) / h;
        let fy = (y - self.origin_y.0) / h;
        let (cols, rows) =
            ((self.tile_cols as usize * TILE_CELLS) as f32, (self.tile_rows as usize * TILE_CELLS) as f32);
        if !(fx >= 0.0 && fy >= 0.0 && fx < cols && fy < rows) {
            return None;
        }
        let (ci, cj) = (fx as usize, fy as usize);
        let (tx, ty) = (ci / TILE_CELLS, cj / TILE_CELLS);
        let entry = *self.tiles.get(ty * self.tile_cols as usize + tx)?;
        let big = 127.0 * self.step_mm;
        match TileEntry::of(entry) {
            TileEntry::Outside => Some(-big - self.step_mm),
            TileEntry::Inside => Some(big),
            analytic @ (TileEntry::Plane(_)
            | TileEntry::Ridge(_)
            | TileEntry::Corner(_)
            | TileEntry::Notch(_)
            | TileEntry::Bend(_)
            | TileEntry::Arc(_)
            | TileEntry::Segments(_)) => {
                let (u, w) = (fx as f64 - (tx * TILE_CELLS) as f64, fy as f64 - (ty * TILE_CELLS) as f64);
                let code = analytic.code(&self.planes, u, w)?;
                Some(((code - DISTANCE_ZERO as f64) * self.step_mm as f64) as f32)
            }
            TileEntry::Fine { first, fine, pair } => {
                let (u, w) = (fx - (tx * TILE_CELLS) as f32, fy - (ty * TILE_CELLS) as f32);
                let ((a, i, wx), (b, j, wy)) = (fine_cell(u, fine), fine_cell(w, fine));
                let channel = |c: usize| {
                    let base = (first as usize + (c * fine as usize + b) * fine as usize + a) * TILE_SAMPLES;
                    let s = |i: usize, j: usize| {
                        self.samples.get(base + j * TILE_SIDE + i).map_or(0.0, |&v| v as f32 - 128.0)
                    };
                    let top = s(i, j) + (s(i + 1, j) - s(i, j)) * wx;
                    let bot = s(i, j + 1) + (s(i + 1, j + 1) - s(i, j + 1)) * wx;
                    top + (bot - top) * wy
                };
                let code = if pair { channel(0).min(channel(1)) } else { channel(0) };
                Some(code * self.step_mm)
            }
            TileEntry::Stored(k) => {
                let base = k as usize * TILE_SAMPLES;
                let (i, j) = (ci - tx * TILE_CELLS, cj - ty * TILE_CELLS);
                let s =
                    |i: usize, j: usize| self.samples.get(base + j * TILE_SIDE + i).map_or(0.0, |&v| v as f32 - 128.0);
                let (wx, wy) = (fx - ci as f32, fy - cj as f32);
                let top = s(i, j) + (s(i + 1, j) - s(i, j)) * wx;
                let bot = s(i, j + 1) + (s(i + 1, j + 1) - s(i, j + 1)) * wx;
                Some((top + (bot - top) * wy) * self.step_mm)
            }
        }
    }

    /// The edge profile's amplitude (0..=1, before the layer's amplitude) at
    /// page `(x, y)`: `clamp(½ + d / soft, 0, 1)`, with a hard edge's ramp one
    /// `step` wide.
    pub fn coverage_at(&self, x: f32, y: f32) -> f32 {
        match self.distance_at(x, y) {
            None => 0.0,
            Some(d) => profile(d, ramp(self.soft_mm, self.step_mm)),
        }
    }

    /// Checks the owned model's shape before it is encoded.
    pub(crate) fn check_shape(&self, index: u32) -> Result<(), FormatError> {
        let tag = self.tag();
        let bad = |field, expected| FormatError::InvalidValue { tag, index, field, expected };
        if self.tiles.len() as u64 != self.tile_cols as u64 * self.tile_rows as u64 {
            return Err(bad("tiles", "tile_cols * tile_rows index entries"));
        }
        if !self.samples.len().is_multiple_of(TILE_SAMPLES) {
            return Err(bad("samples", "81 samples per stored tile"));
        }
        if self.planes.len() > SEGMENT_TILE_RECORDS * MAX_DISTANCE_TILES as usize {
            return Err(bad("planes", "at most four plane records per tile"));
        }
        Ok(())
    }

    pub(crate) fn encode(&self) -> Vec<u8> {
        let len = DISTANCE_HEADER_LEN
            + 4 * (self.sources.len() + self.tiles.len())
            + PLANE_RECORD_LEN * self.planes.len()
            + self.samples.len();
        let mut out = Vec::with_capacity(len);
        let mut w = Out(&mut out);
        w.u32(self.sources.len() as u32)
            .u32(self.tile_cols)
            .u32(self.tile_rows)
            .u32(self.stored_tiles() as u32)
            .f32(self.origin_x.0)
            .f32(self.origin_y.0)
            .f32(self.pitch_mm)
            .f32(self.amplitude);
        match self.kind {
            MaskKind::Vibration { freq } => w.u32(freq.0).u32(0),
            MaskKind::Grating { wavelength, angle_deg } => w.f32(wavelength.0).f32(angle_deg),
        };
        w.f32(self.soft_mm).f32(self.step_mm);
        for &s in &self.sources {
            w.u32(s);
        }
        for &t in &self.tiles {
            w.u32(t);
        }
        for p in &self.planes {
            w.f32(p.c).f32(p.gx).f32(p.gy).f32(p.top);
        }
        w.bytes(&self.samples);
        out
    }

    pub(crate) fn from_view(v: &DistanceView<'_>) -> Self {
        DistanceLayer {
            kind: v.kind,
            amplitude: v.amplitude,
            soft_mm: v.soft_mm,
            step_mm: v.step_mm,
            origin_x: v.origin_x,
            origin_y: v.origin_y,
            pitch_mm: v.pitch_mm,
            tile_cols: v.tile_cols,
            tile_rows: v.tile_rows,
            sources: (0..v.source_count()).filter_map(|i| v.source(i)).collect(),
            tiles: (0..v.tile_cols * v.tile_rows).map(|i| v.tile_entry(i)).collect(),
            planes: (0..v.plane_count()).filter_map(|p| v.plane(p)).collect(),
            samples: v.samples.to_vec(),
        }
    }
}

/// The edge profile: amplitude 0..=1 for a signed distance `d` (mm) and a
/// ramp `width` mm wide: `clamp(½ + d / width, 0, 1)`.
pub fn profile(d: f32, width: f32) -> f32 {
    (0.5 + d / width).clamp(0.0, 1.0)
}

/// The ramp width of a layer's edge profile: `soft`, or for a hard edge
/// (`soft` = 0) one sample step.
pub fn ramp(soft_mm: f32, step_mm: f32) -> f32 {
    if soft_mm > 0.0 { soft_mm } else { step_mm }
}

/// A validated distance chunk, read in place.
#[derive(Debug, Clone, Copy)]
pub struct DistanceView<'a> {
    /// The primitive and its parameters.
    pub kind: MaskKind,
    /// Layer amplitude (0..=1).
    pub amplitude: f32,
    /// Edge profile ramp width, mm (0 hard).
    pub soft_mm: f32,
    /// Distance of one sample code, mm.
    pub step_mm: f32,
    /// Page x of the lattice's first column.
    pub origin_x: Mm,
    /// Page y of the lattice's first row.
    pub origin_y: Mm,
    /// Lattice pitch, mm.
    pub pitch_mm: f32,
    /// Tiles per row.
    pub tile_cols: u32,
    /// Rows of tiles.
    pub tile_rows: u32,
    /// Stored tiles.
    pub stored: u32,
    sources: &'a [u8],
    tiles: &'a [u8],
    planes: &'a [u8],
    samples: &'a [u8],
}

impl<'a> DistanceView<'a> {
    /// Number of provenance entries the layer names.
    pub fn source_count(&self) -> u32 {
        (self.sources.len() / 4) as u32
    }

    /// The `i`-th provenance entry the layer holds.
    pub fn source(&self, i: u32) -> Option<u32> {
        u32_at(self.sources, 4 * i as usize)
    }

    /// The tile index entry `i` (row-major), or [`TILE_OUTSIDE`] past the end.
    #[inline]
    pub fn tile_entry(&self, i: u32) -> u32 {
        u32_at(self.tiles, 4 * i as usize).unwrap_or(TILE_OUTSIDE)
    }

    /// Stored sample code `k` (tile `k / 81`, then row-major in the tile),
    /// or [`DISTANCE_ZERO`] past the end.
    #[inline]
    pub fn sample(&self, k: usize) -> u8 {
        self.samples.get(k).copied().unwrap_or(DISTANCE_ZERO)
    }

    /// The tile index bytes (u32 little-endian entries).
    pub fn tile_bytes(&self) -> &'a [u8] {
        self.tiles
    }

    /// Number of plane records (plane and ridge tiles).
    pub fn plane_count(&self) -> u32 {
        (self.planes.len() / PLANE_RECORD_LEN) as u32
    }

    /// Plane record `p`, or `None` past the end.
    pub fn plane(&self, p: u32) -> Option<TilePlane> {
        let o = PLANE_RECORD_LEN * p as usize;
        Some(TilePlane {
            c: f32_at(self.planes, o)?,
            gx: f32_at(self.planes, o + 4)?,
            gy: f32_at(self.planes, o + 8)?,
            top: f32_at(self.planes, o + 12)?,
        })
    }

    /// The plane records' bytes (four little-endian f32 each).
    pub fn plane_bytes(&self) -> &'a [u8] {
        self.planes
    }

    /// The stored samples' bytes (biased codes).
    pub fn sample_bytes(&self) -> &'a [u8] {
        self.samples
    }

    /// The chunk's tag.
    pub fn tag(&self) -> Tag {
        match self.kind {
            MaskKind::Vibration { .. } => Tag::VIBRATION_DISTANCE,
            MaskKind::Grating { .. } => Tag::GRATING_DISTANCE,
        }
    }

    pub(crate) fn parse(d: &'a [u8], tag: Tag, index: u32, full: bool) -> Result<Self, FormatError> {
        FormatError::check_header(d, DISTANCE_HEADER_LEN, tag, index)?;
        let bad = |field, expected| FormatError::InvalidValue { tag, index, field, expected };
        let u = |o| u32_at(d, o).unwrap_or(0);
        let f = |o| f32_at(d, o).unwrap_or(f32::NAN);
        let (nsrc, cols, rows, stored) = (u(0), u(4), u(8), u(12));
        if nsrc > crate::MAX_PROVENANCE_ENTRIES {
            return Err(FormatError::Limit {
                tag,
                field: "sources",
                value: nsrc as u64,
                limit: crate::MAX_PROVENANCE_ENTRIES as u64,
            });
        }
        if cols == 0 || rows == 0 {
            return Err(bad("tiles", "at least one tile column and row"));
        }
        let ntiles = cols as u64 * rows as u64;
        if ntiles > MAX_DISTANCE_TILES as u64 {
            return Err(FormatError::Limit { tag, field: "tiles", value: ntiles, limit: MAX_DISTANCE_TILES as u64 });
        }
        // (A fine tile, format 4.4, stores up to 128.)
        if stored as u64 > 2 * (MAX_FINE * MAX_FINE) as u64 * ntiles {
            return Err(bad("stored tiles", "at most 128 * tile_cols * tile_rows"));
        }
        // The plane records' count is what the length leaves after the
        // other parts; the index check below makes it canonical.
        let fixed = DISTANCE_HEADER_LEN as u64 + 4 * (nsrc as u64 + ntiles) + TILE_SAMPLES as u64 * stored as u64;
        let rec = PLANE_RECORD_LEN as u64;
        let Some(rest) = (d.len() as u64).checked_sub(fixed).filter(|r| r.is_multiple_of(rec)) else {
            // The nearest length below that a whole number of records fits.
            let expected = fixed + (d.len() as u64).saturating_sub(fixed) / rec * rec;
            return Err(FormatError::ChunkLength { tag, index, expected, found: d.len() as u64 });
        };
        let nplanes = rest / rec;
        if nplanes > SEGMENT_TILE_RECORDS as u64 * ntiles {
            return Err(bad("planes", "at most four plane records per tile"));
        }
        let origin_x = in_range(f(16), -1e6, 1e6, tag, index, "origin_x_mm", "from -1e6 to 1e6 mm")?;
        let origin_y = in_range(f(20), -1e6, 1e6, tag, index, "origin_y_mm", "from -1e6 to 1e6 mm")?;
        let pitch_mm = in_range(f(24), 1e-3, 100.0, tag, index, "pitch_mm", "from 0.001 to 100 mm")?;
        let amplitude = in_range(f(28), 0.0, 1.0, tag, index, "amplitude", "from 0 to 1")?;
        let soft_mm = in_range(f(40), 0.0, MAX_SOFT_MM, tag, index, "soft_mm", "from 0 to 16 mm")?;
        let step_mm = in_range(f(44), 1e-6, 1.0, tag, index, "step_mm", "from 1e-6 to 1 mm")?;
        let kind = if tag == Tag::VIBRATION_DISTANCE {
            if u(36) != 0 {
                return Err(bad("reserved", "zero"));
            }
            let freq = u(32);
            if freq == 0 {
                return Err(bad("frequency", "above 0 Hz"));
            }
            MaskKind::Vibration { freq: MilliHertz(freq) }
        } else {
            let wavelength = in_range(f(32), 1e-3, 1e6, tag, index, "wavelength_mm", "from 0.001 to 1e6 mm")?;
            let angle_deg = in_range(f(36), -360.0, 360.0, tag, index, "angle_deg", "from -360 to 360")?;
            MaskKind::Grating { wavelength: Mm(wavelength), angle_deg }
        };
        let src_end = DISTANCE_HEADER_LEN + 4 * nsrc as usize;
        let tiles_end = src_end + 4 * ntiles as usize;
        let planes_end = tiles_end + PLANE_RECORD_LEN * nplanes as usize;
        let view = DistanceView {
            kind,
            amplitude,
            soft_mm,
            step_mm,
            origin_x: Mm(origin_x),
            origin_y: Mm(origin_y),
            pitch_mm,
            tile_cols: cols,
            tile_rows: rows,
            stored,
            sources: &d[DISTANCE_HEADER_LEN..src_end],
            tiles: &d[src_end..tiles_end],
            planes: &d[tiles_end..planes_end],
            samples: &d[planes_end..],
        };
        // The lattice's far corner must be finite in f32, so that a player's
        // box arithmetic never overflows.
        let far = |o: f32, n: u32| o as f64 + n as f64 * TILE_CELLS as f64 * pitch_mm as f64;
        if far(origin_x, cols).abs() > 2e6 || far(origin_y, rows).abs() > 2e6 {
            return Err(bad("tiles", "a lattice that ends within 2e6 mm of the page origin"));
        }
        if full {
            let mut prev: Option<u32> = None;
            for i in 0..nsrc {
                let s = view.source(i).unwrap_or(NO_SOURCE);
                if s == NO_SOURCE || prev.is_some_and(|p| s <= p) {
                    return Err(bad("sources", "provenance indices in strictly increasing order"));
                }
                prev = Some(s);
            }
            let (mut next, mut next_plane) = (0u32, 0u32);
            for i in 0..ntiles as u32 {
                let e = view.tile_entry(i);
                match TileEntry::of(e) {
                    TileEntry::Outside | TileEntry::Inside => {}
                    TileEntry::Stored(k) if k == next => next += 1,
                    f @ TileEntry::Fine { first, fine, pair } if first == next && (pair || fine > 1) => {
                        next += f.stored()
                    }
                    TileEntry::Plane(p) | TileEntry::Ridge(p) if p == next_plane => {
                        let rec = view.plane(p).ok_or(bad("tile index", "a plane record for every plane tile"))?;
                        check_plane(&rec, e).map_err(|expected| bad("plane record", expected))?;
                        next_plane += 1;
                    }
                    TileEntry::Corner(p) | TileEntry::Notch(p) if p == next_plane => {
                        for q in [p, p + 1] {
                            let rec = view
                                .plane(q)
                                .ok_or(bad("tile index", "two plane records for every corner and notch tile"))?;
                            check_plane(&rec, e).map_err(|expected| bad("plane record", expected))?;
                        }
                        next_plane += 2;
                    }
                    TileEntry::Bend(p) if p == next_plane => {
                        let (a, b) = (view.plane(p), view.plane(p + 1));
                        let (Some(a), Some(b)) = (a, b) else {
                            return Err(bad("tile index", "two plane records for every bend tile"));
                        };
                        check_bend([a, b]).map_err(|expected| bad("plane record", expected))?;
                        next_plane += 2;
                    }
                    TileEntry::Arc(p) if p == next_plane => {
                        let (a, b) = (view.plane(p), view.plane(p + 1));
                        let (Some(a), Some(b)) = (a, b) else {
                            return Err(bad("tile index", "two plane records for every arc tile"));
                        };
                        check_arc([a, b]).map_err(|expected| bad("plane record", expected))?;
                        next_plane += 2;
                    }
                    TileEntry::Segments(p) if p == next_plane => {
                        let r: [Option<TilePlane>; SEGMENT_TILE_RECORDS] =
                            core::array::from_fn(|i| view.plane(p + i as u32));
                        let [Some(a), Some(b), Some(c), Some(d)] = r else {
                            return Err(bad("tile index", "four plane records for every segments tile"));
                        };
                        check_segments([a, b, c, d]).map_err(|expected| bad("plane record", expected))?;
                        next_plane += SEGMENT_TILE_RECORDS as u32;
                    }
                    _ => {
                        return Err(bad(
                            "tile index",
                            "0, 1, or the next stored tile's or plane record's number (in index order)",
                        ));
                    }
                }
            }
            if next != stored {
                return Err(bad("stored tiles", "the number of stored tiles the index names"));
            }
            if next_plane as u64 != nplanes {
                return Err(bad("planes", "the number of plane records the index names"));
            }
        }
        Ok(view)
    }
}

/// Checks one plane record of a tile with index entry `e`: finite values
/// within the bounds that keep a player's `f32` arithmetic exact to far
/// below a code, and a plane's `top` zero (SPEC.md section 6.2).
fn check_plane(p: &TilePlane, e: u32) -> Result<(), &'static str> {
    let within = |v: f32, m: f32| v.is_finite() && v.abs() <= m;
    if !(within(p.gx, MAX_PLANE_GRADIENT) && within(p.gy, MAX_PLANE_GRADIENT)) {
        return Err("finite gradients of at most 1024 codes per cell");
    }
    if !(within(p.c, MAX_PLANE_CODE) && within(p.top, MAX_PLANE_CODE)) {
        return Err("finite c and top of at most 65536 codes");
    }
    if e & TILE_RIDGE != TILE_RIDGE && p.top != 0.0 {
        return Err("top 0 in a plane, corner or notch tile's record");
    }
    Ok(())
}

/// The code of a bend tile with records `r` at lattice coordinates
/// `(u, w)`, in f64 ([`TILE_BEND`]; SPEC.md section 6.2's reference).
pub fn bend_code(r: [&TilePlane; 2], u: f64, w: f64) -> f64 {
    let [a, b] = r;
    let (vx, vy) = (a.c as f64, a.gx as f64);
    let (dx, dy) = (u - vx, w - vy);
    let to_vertex = libm::hypot(dx, dy);
    let ray = |ex: f64, ey: f64| {
        if dx * ex + dy * ey >= 0.0 { (dx * ey - dy * ex).abs() } else { to_vertex }
    };
    let d = ray(a.gy as f64, a.top as f64).min(ray(b.c as f64, b.gx as f64));
    b.top as f64 - b.gy as f64 * d
}

/// The code of an arc tile with records `r` at lattice coordinates
/// `(u, w)`, in f64 ([`TILE_ARC`]; SPEC.md section 6.2's reference):
/// `top − k · ||q − V| − R|`.
///
/// Where the second record's last three values `(c, gx, gy)` are not all 0
/// (a **cut arc**, format 4.3), the code is the lesser of that and the
/// affine `c + gx u + gy w`: a fill's straight side and a circular hole in
/// it (or a circle) within one tile.
pub fn arc_code(r: [&TilePlane; 2], u: f64, w: f64) -> f64 {
    let [a, b] = r;
    let rho = libm::hypot(u - a.c as f64, w - a.gx as f64);
    let arc = b.c as f64 - a.top as f64 * (rho - a.gy as f64).abs();
    if is_cut_arc(b) { arc.min(b.gx as f64 + b.gy as f64 * u + b.top as f64 * w) } else { arc }
}

/// Whether an arc tile's second record (`top`, `c`, `gx`, `gy`) holds a
/// plane, whose affine code the tile's code is the lesser of (a **cut
/// arc**, format 4.3): any of its last three values not 0. (A plane of
/// all-zero values plays code 0 everywhere, which saturates the profile at
/// 0; a writer writes such a tile as outside, so the encoding loses
/// nothing.)
#[inline]
pub fn is_cut_arc(second: &TilePlane) -> bool {
    second.gx != 0.0 || second.gy != 0.0 || second.top != 0.0
}

/// Checks an arc tile's two records: finite values, the centre within
/// [`MAX_PLANE_GRADIENT`] cells of the tile, the radius from 0 to
/// [`MAX_ARC_RADIUS`] cells, `k` from 0 to [`MAX_PLANE_GRADIENT`] codes per
/// cell, `top` at most [`MAX_PLANE_CODE`], and the second record's other
/// three values a plane's `c`, `gx` and `gy` within a plane record's bounds
/// (all 0 for an arc alone; SPEC.md section 6.2).
fn check_arc(r: [TilePlane; 2]) -> Result<(), &'static str> {
    let [a, b] = r;
    let within = |v: f32, m: f32| v.is_finite() && v.abs() <= m;
    if !(within(a.c, MAX_PLANE_GRADIENT) && within(a.gx, MAX_PLANE_GRADIENT)) {
        return Err("an arc's centre finite and within 1024 cells");
    }
    if !(within(a.gy, MAX_ARC_RADIUS) && a.gy >= 0.0) {
        return Err("an arc's radius from 0 to 2048 cells");
    }
    if !(within(a.top, MAX_PLANE_GRADIENT) && a.top >= 0.0 && within(b.c, MAX_PLANE_CODE)) {
        return Err("an arc's k from 0 to 1024 and top of at most 65536 codes");
    }
    // A cut arc's plane (format 4.3), bounded as a plane record's.
    if !(within(b.gx, MAX_PLANE_CODE) && within(b.gy, MAX_PLANE_GRADIENT) && within(b.top, MAX_PLANE_GRADIENT)) {
        return Err("a cut arc's plane finite, with |c| at most 65536 and gradients of at most 1024 codes per cell");
    }
    Ok(())
}

/// The code of a segments tile with records `r` at lattice coordinates
/// `(u, w)`, in f64 ([`TILE_SEGMENTS`]; SPEC.md section 6.2's reference):
/// `top − k · min_i dist(q, segment i)`, with `dist(q, segment (a, b)) =
/// |q − (a + t (b − a))|`, `t = clamp(dot(q − a, b − a) / |b − a|², 0, 1)`
/// (`t = 0` where `a = b`).
pub fn segments_code(r: [&TilePlane; SEGMENT_TILE_RECORDS], u: f64, w: f64) -> f64 {
    let [s0, s1, s2, last] = r;
    let dist = |s: &TilePlane| {
        let (ax, ay, bx, by) = (s.c as f64, s.gx as f64, s.gy as f64, s.top as f64);
        let (ex, ey) = (bx - ax, by - ay);
        let (dx, dy) = (u - ax, w - ay);
        let len2 = ex * ex + ey * ey;
        let t = if len2 > 0.0 { ((dx * ex + dy * ey) / len2).clamp(0.0, 1.0) } else { 0.0 };
        libm::hypot(dx - t * ex, dy - t * ey)
    };
    let d = dist(s0).min(dist(s1)).min(dist(s2));
    last.gx as f64 - last.c as f64 * d
}

/// Checks a segments tile's four records: finite ends within
/// [`MAX_PLANE_GRADIENT`] cells of the tile, `|k|` at most
/// [`MAX_PLANE_GRADIENT`] codes per cell, `|top|` at most
/// [`MAX_PLANE_CODE`] and the last record's other two values 0 (SPEC.md
/// section 6.2).
fn check_segments(r: [TilePlane; SEGMENT_TILE_RECORDS]) -> Result<(), &'static str> {
    let within = |v: f32, m: f32| v.is_finite() && v.abs() <= m;
    let [s0, s1, s2, last] = r;
    if ![s0, s1, s2].iter().all(|s| [s.c, s.gx, s.gy, s.top].iter().all(|&v| within(v, MAX_PLANE_GRADIENT))) {
        return Err("a segments tile's ends finite and within 1024 cells");
    }
    if !(within(last.c, MAX_PLANE_GRADIENT) && within(last.gx, MAX_PLANE_CODE)) {
        return Err("a segments tile's |k| at most 1024 and |top| at most 65536 codes");
    }
    if !(last.gy == 0.0 && last.top == 0.0) {
        return Err("a segments tile's last record 0 after its top");
    }
    Ok(())
}

/// Largest distance of a direction's length from 1 in a bend record.
pub const BEND_UNIT_TOLERANCE: f32 = 1e-3;

/// Checks a bend tile's two records: finite values, the vertex within
/// [`MAX_PLANE_GRADIENT`] cells of the tile, unit directions (within
/// [`BEND_UNIT_TOLERANCE`]), `k` from 0 to [`MAX_PLANE_GRADIENT`] codes per
/// cell and `top` at most [`MAX_PLANE_CODE`] (SPEC.md section 6.2).
fn check_bend(r: [TilePlane; 2]) -> Result<(), &'static str> {
    let [a, b] = r;
    let within = |v: f32, m: f32| v.is_finite() && v.abs() <= m;
    if !(within(a.c, MAX_PLANE_GRADIENT) && within(a.gx, MAX_PLANE_GRADIENT)) {
        return Err("a bend's vertex finite and within 1024 cells");
    }
    let unit = |x: f32, y: f32| {
        x.is_finite() && y.is_finite() && (libm::sqrtf(x * x + y * y) - 1.0).abs() <= BEND_UNIT_TOLERANCE
    };
    if !(unit(a.gy, a.top) && unit(b.c, b.gx)) {
        return Err("a bend's directions of unit length");
    }
    if !(within(b.gy, MAX_PLANE_GRADIENT) && b.gy >= 0.0 && within(b.top, MAX_PLANE_CODE)) {
        return Err("a bend's k from 0 to 1024 and top of at most 65536 codes");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profile_is_a_ramp_centred_on_the_edge() {
        assert_eq!(profile(0.0, 0.3), 0.5);
        assert_eq!(profile(0.15, 0.3), 1.0);
        assert_eq!(profile(-0.15, 0.3), 0.0);
        assert!((profile(0.075, 0.3) - 0.75).abs() < 1e-6);
        // Hard: one step wide.
        assert_eq!(ramp(0.0, 0.01), 0.01);
        assert_eq!(ramp(0.3, 0.01), 0.3);
        assert_eq!(profile(0.005, ramp(0.0, 0.01)), 1.0);
    }

    /// The format 4.2 decoding as a chain of tests (stored tiles first,
    /// then the kinds by their nibble, ridges by their two bits): what
    /// [`TileEntry::of`]'s one jump must agree with.
    fn of_by_chain(e: u32) -> TileEntry {
        const NIBBLE: u32 = 0xF000_0000;
        match e {
            TILE_OUTSIDE => TileEntry::Outside,
            TILE_INSIDE => TileEntry::Inside,
            e if e & NIBBLE == TILE_FINE => {
                TileEntry::Fine { first: e & 0x01FF_FFFF, fine: 1 << ((e >> 26) & 3), pair: e & 0x0200_0000 != 0 }
            }
            e if e < TILE_PLANE => TileEntry::Stored(e - TILE_FIRST_STORED),
            e if e & NIBBLE == TILE_CORNER => TileEntry::Corner(e & TILE_CORNER_RECORD_MASK),
            e if e & NIBBLE == TILE_NOTCH => TileEntry::Notch(e & TILE_CORNER_RECORD_MASK),
            e if e & NIBBLE == TILE_BEND => TileEntry::Bend(e & TILE_CORNER_RECORD_MASK),
            e if e & NIBBLE == TILE_ARC => TileEntry::Arc(e & TILE_CORNER_RECORD_MASK),
            e if e & NIBBLE == TILE_SEGMENTS => TileEntry::Segments(e & TILE_CORNER_RECORD_MASK),
            e if e & TILE_RIDGE == TILE_RIDGE => TileEntry::Ridge(e & TILE_RECORD_MASK),
            e => TileEntry::Plane(e & TILE_RECORD_MASK),
        }
    }

    #[test]
    fn entries_decode_by_their_kind_nibble_as_by_the_chain() {
        // Every nibble with low bits at both ends of their range and between.
        for nibble in 0..16u32 {
            for low in [0u32, 1, 2, 3, 0x7F, 0x0FFF_FFFE, 0x0FFF_FFFF, 0x0123_4567] {
                let e = nibble << 28 | low;
                assert_eq!(TileEntry::of(e), of_by_chain(e), "entry {e:#010x}");
            }
        }
        assert_eq!(TileEntry::of(TILE_PLANE | 5), TileEntry::Plane(5));
        assert_eq!(TileEntry::of(TILE_ARC | 5), TileEntry::Arc(5));
        assert_eq!(TileEntry::of(TILE_SEGMENTS | 3), TileEntry::Segments(3));
        assert_eq!(TileEntry::of(0xF000_0003), TileEntry::Ridge(0x3000_0003));
        assert_eq!(TileEntry::of(0x6C00_0007), TileEntry::Fine { first: 7, fine: 8, pair: false });
        assert_eq!(TileEntry::of(0x6600_0007), TileEntry::Fine { first: 7, fine: 2, pair: true });
        assert_eq!(fine_entry(7, 8, false), Some(0x6C00_0007));
        assert_eq!(fine_entry(7, 2, true), Some(0x6600_0007));
        assert_eq!(fine_entry(7, 16, false), None);
        assert_eq!(fine_entry(7, 1, false), None);
        for (fine, pair) in [(1, true), (2, false), (2, true), (4, false), (4, true), (8, false), (8, true)] {
            let e = fine_entry(12345, fine, pair).expect("an entry");
            assert_eq!(TileEntry::of(e), TileEntry::Fine { first: 12345, fine, pair });
            assert_eq!(TileEntry::of(e).stored(), fine * fine * if pair { 2 } else { 1 });
        }
    }

    #[test]
    fn a_fine_cell_is_found_exactly_at_every_refinement() {
        // Written from the definition: fine coordinate f u, its cell, the sub-tile of eight cells.
        assert_eq!(fine_cell(0.0, 2), (0, 0, 0.0));
        assert_eq!(fine_cell(3.75, 2), (0, 7, 0.5));
        assert_eq!(fine_cell(4.0, 2), (1, 0, 0.0));
        assert_eq!(fine_cell(5.3125, 4), (2, 5, 0.25));
        assert_eq!(fine_cell(8.0, 8), (7, 7, 1.0));
        assert_eq!(fine_cell(7.9921875, 8), (7, 7, 0.9375));
        assert_eq!(fine_cell(-1.0, 4), (0, 0, -4.0));
    }
}
