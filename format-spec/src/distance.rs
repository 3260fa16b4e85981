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
//!
//! The kinds of tile besides stored ones (plane, ridge, corner, notch,
//! bend, arc, segments, fine), their records and codes are in
//! `distance/tiles.rs`; `distance/tile.rs` reads one tile at a time
//! ([`Tile`]), for the tools that look inside a layer.

use alloc::vec::Vec;

mod tile;
mod tiles;

pub use tile::{Tile, TileGroup, TileIter, TileKind};
pub use tiles::{
    MAX_ARC_RADIUS, MAX_FINE, MAX_PLANE_CODE, MAX_PLANE_GRADIENT, PLANE_RECORD_LEN, SEGMENT_TILE_RECORDS,
    SEGMENTS_PER_TILE, TILE_ARC, TILE_BEND, TILE_CORNER, TILE_CORNER_RECORD_MASK, TILE_FINE, TILE_FINE_FIRST_MASK,
    TILE_FINE_PAIR, TILE_FINE_SHIFT, TILE_FIRST_STORED, TILE_INSIDE, TILE_NOTCH, TILE_OUTSIDE, TILE_PLANE,
    TILE_RECORD_MASK, TILE_RIDGE, TILE_SEGMENTS, TileEntry, TilePlane, arc_code, bend_code, fine_cell, fine_entry,
    is_cut_arc, segments_code,
};
use tiles::{check_arc, check_bend, check_plane, check_segments};

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
