//! One tile of a distance layer at a time: its kind, its own plane records
//! and stored samples, and the code it plays (SPEC.md section 6.2).
//!
//! Tools that look inside a layer (`taxel report`'s edge error, `taxel
//! inspect`'s counts, the text form) read tiles through [`Tile`] rather than
//! indexing the layer's records and samples themselves, so that a new kind
//! of tile is taught to them here, in one place. Nothing here allocates: a
//! tile copies its (at most four) records and borrows its samples.

use super::tiles::{
    SEGMENT_TILE_RECORDS, TILE_ARC, TILE_BEND, TILE_CORNER, TILE_FINE, TILE_FINE_PAIR, TILE_FINE_SHIFT,
    TILE_FIRST_STORED, TILE_INSIDE, TILE_NOTCH, TILE_OUTSIDE, TILE_PLANE, TILE_RIDGE, TILE_SEGMENTS, TileEntry,
    TilePlane,
};
use super::{DistanceLayer, DistanceView, TILE_CELLS, TILE_SAMPLES, TILE_SIDE};

/// The kinds of tile, one per index entry kind (SPEC.md section 6.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TileKind {
    /// Wholly outside: amplitude 0.
    Outside,
    /// Wholly inside: full amplitude.
    Inside,
    /// 9 x 9 stored samples.
    Stored,
    /// One plane record, played as a plane.
    Plane,
    /// One plane record, played as a ridge.
    Ridge,
    /// Two records, their lesser.
    Corner,
    /// Two records, their greater.
    Notch,
    /// Two records, a band's bent centre line.
    Bend,
    /// Two records, a circle (or a cut arc).
    Arc,
    /// Four records, the nearest of three segments.
    Segments,
    /// Stored samples finer than the lattice, in one or two channels.
    Fine,
}

/// How tools count tiles ([`TileKind::group`]): by what plays them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TileGroup {
    /// Outside and inside tiles: one constant.
    Constant,
    /// Stored tiles: samples at the lattice's pitch.
    Stored,
    /// Fine tiles: samples finer than the lattice.
    Fine,
    /// Plane and ridge tiles: one record.
    Plane,
    /// Corner and notch tiles: two planes.
    Corner,
    /// Bend, arc and segments tiles: curves round a vertex, a centre or segments.
    Bend,
}

impl TileKind {
    /// Every kind, in the order the format added them (fine tiles last).
    pub const ALL: [TileKind; 11] = [
        TileKind::Outside,
        TileKind::Inside,
        TileKind::Stored,
        TileKind::Plane,
        TileKind::Ridge,
        TileKind::Corner,
        TileKind::Notch,
        TileKind::Bend,
        TileKind::Arc,
        TileKind::Segments,
        TileKind::Fine,
    ];

    /// The kind's name, lower-case, as SPEC.md names it.
    pub fn name(self) -> &'static str {
        match self {
            TileKind::Outside => "outside",
            TileKind::Inside => "inside",
            TileKind::Stored => "stored",
            TileKind::Plane => "plane",
            TileKind::Ridge => "ridge",
            TileKind::Corner => "corner",
            TileKind::Notch => "notch",
            TileKind::Bend => "bend",
            TileKind::Arc => "arc",
            TileKind::Segments => "segments",
            TileKind::Fine => "fine",
        }
    }

    /// The group tools count the kind in.
    pub fn group(self) -> TileGroup {
        match self {
            TileKind::Outside | TileKind::Inside => TileGroup::Constant,
            TileKind::Stored => TileGroup::Stored,
            TileKind::Fine => TileGroup::Fine,
            TileKind::Plane | TileKind::Ridge => TileGroup::Plane,
            TileKind::Corner | TileKind::Notch => TileGroup::Corner,
            TileKind::Bend | TileKind::Arc | TileKind::Segments => TileGroup::Bend,
        }
    }

    /// The kind's index entries as a person reads them, in decimal (the
    /// text form's note on its tile index, `docs/text-form.md`).
    pub fn entry_text(self) -> &'static str {
        // Written out so that the text is a constant; a test checks the numbers.
        match self {
            TileKind::Outside => "0 outside",
            TileKind::Inside => "1 inside",
            TileKind::Stored => "2 + k stored tile k",
            TileKind::Plane => "2147483648 + p plane record p",
            TileKind::Ridge => "3221225472 + p ridge record p",
            TileKind::Corner => "2684354560 + p corner of records p and p + 1",
            TileKind::Notch => "2952790016 + p notch of records p and p + 1",
            TileKind::Bend => "2415919104 + p bend of records p and p + 1",
            TileKind::Arc => "3489660928 + p arc of records p and p + 1",
            TileKind::Segments => "3758096384 + p segments of records p to p + 3",
            TileKind::Fine => {
                "1610612736 + 67108864 s + 33554432 c + k fine tile from stored tile k (2^s times finer, two channels where c is 1)"
            }
        }
    }

    /// The first index entry of the kind (its record or stored tile 0, one
    /// channel at the least refinement for a fine tile).
    pub fn first_entry(self) -> u32 {
        match self {
            TileKind::Outside => TILE_OUTSIDE,
            TileKind::Inside => TILE_INSIDE,
            TileKind::Stored => TILE_FIRST_STORED,
            TileKind::Plane => TILE_PLANE,
            TileKind::Ridge => TILE_RIDGE,
            TileKind::Corner => TILE_CORNER,
            TileKind::Notch => TILE_NOTCH,
            TileKind::Bend => TILE_BEND,
            TileKind::Arc => TILE_ARC,
            TileKind::Segments => TILE_SEGMENTS,
            TileKind::Fine => TILE_FINE,
        }
    }
}

impl TileEntry {
    /// The entry's kind.
    pub fn kind(self) -> TileKind {
        match self {
            TileEntry::Outside => TileKind::Outside,
            TileEntry::Inside => TileKind::Inside,
            TileEntry::Stored(_) => TileKind::Stored,
            TileEntry::Plane(_) => TileKind::Plane,
            TileEntry::Ridge(_) => TileKind::Ridge,
            TileEntry::Corner(_) => TileKind::Corner,
            TileEntry::Notch(_) => TileKind::Notch,
            TileEntry::Bend(_) => TileKind::Bend,
            TileEntry::Arc(_) => TileKind::Arc,
            TileEntry::Segments(_) => TileKind::Segments,
            TileEntry::Fine { .. } => TileKind::Fine,
        }
    }

    /// The same entry naming record (or stored tile) 0: the tile's own
    /// numbering, as [`Tile`] holds its records.
    fn local(self) -> TileEntry {
        match self {
            TileEntry::Stored(_) => TileEntry::Stored(0),
            TileEntry::Plane(_) => TileEntry::Plane(0),
            TileEntry::Ridge(_) => TileEntry::Ridge(0),
            TileEntry::Corner(_) => TileEntry::Corner(0),
            TileEntry::Notch(_) => TileEntry::Notch(0),
            TileEntry::Bend(_) => TileEntry::Bend(0),
            TileEntry::Arc(_) => TileEntry::Arc(0),
            TileEntry::Segments(_) => TileEntry::Segments(0),
            TileEntry::Fine { fine, pair, .. } => TileEntry::Fine { first: 0, fine, pair },
            e @ (TileEntry::Outside | TileEntry::Inside) => e,
        }
    }

    /// The first plane record or stored tile the entry names.
    fn first(self) -> u32 {
        match self {
            TileEntry::Stored(k)
            | TileEntry::Plane(k)
            | TileEntry::Ridge(k)
            | TileEntry::Corner(k)
            | TileEntry::Notch(k)
            | TileEntry::Bend(k)
            | TileEntry::Arc(k)
            | TileEntry::Segments(k)
            | TileEntry::Fine { first: k, .. } => k,
            TileEntry::Outside | TileEntry::Inside => 0,
        }
    }
}

// The fine entry's bits, as `TileKind::entry_text` spells them.
const _: () = assert!(1 << TILE_FINE_SHIFT == 67_108_864 && TILE_FINE_PAIR == 33_554_432);

/// One tile of a distance layer, with the records and samples it plays.
#[derive(Debug, Clone, Copy)]
pub struct Tile<'a> {
    /// Its column in the layer's tile lattice.
    pub col: u32,
    /// Its row.
    pub row: u32,
    /// Its index entry, as the layer numbers records and stored tiles.
    pub entry: TileEntry,
    /// Page position of its first lattice point (the top-left one), mm:
    /// `origin + 8 · col · pitch` (and the same along y), in f64.
    pub corner_mm: (f64, f64),
    records: [TilePlane; SEGMENT_TILE_RECORDS],
    samples: &'a [u8],
}

const NO_RECORD: TilePlane = TilePlane { c: 0.0, gx: 0.0, gy: 0.0, top: 0.0 };

impl<'a> Tile<'a> {
    /// The tile's kind.
    pub fn kind(&self) -> TileKind {
        self.entry.kind()
    }

    /// The plane records the tile plays ([`TileEntry::records`] of them; a
    /// record missing from the layer reads as all zero).
    pub fn records(&self) -> &[TilePlane] {
        &self.records[..self.entry.records() as usize]
    }

    /// The code of a plane, ridge, corner, notch, bend, arc or segments
    /// tile at lattice coordinates `(u, w)` inside it (0 to 8 from its
    /// first lattice point), in f64: [`TileEntry::code`] on the tile's own
    /// records. `None` for the other kinds.
    pub fn code(&self, u: f64, w: f64) -> Option<f64> {
        self.entry.local().code(self.records(), u, w)
    }

    /// How many times finer than the lattice its samples are: 1 for a
    /// stored tile, 1 to 8 for a fine tile, 0 for a tile without samples.
    pub fn refinement(&self) -> usize {
        match self.entry {
            TileEntry::Stored(_) => 1,
            TileEntry::Fine { fine, .. } => fine as usize,
            _ => 0,
        }
    }

    /// Sample channels: 2 for a fine tile of two channels, 1 for another
    /// tile with samples, 0 for a tile without.
    pub fn channels(&self) -> usize {
        match self.entry {
            TileEntry::Stored(_) => 1,
            TileEntry::Fine { pair, .. } => 1 + pair as usize,
            _ => 0,
        }
    }

    /// Samples along a side of one channel: `8 f + 1` for a refinement `f`
    /// (the sub-tiles' shared sides counted once), 0 without samples.
    pub fn side(&self) -> usize {
        match self.refinement() {
            0 => 0,
            f => TILE_CELLS * f + 1,
        }
    }

    /// The sample code of `channel` at its lattice point `(x, y)` (each
    /// `0..side()`, `h / f` apart from the tile's first point; a point on a
    /// side two sub-tiles share is read from the earlier one, where the
    /// later one stores the same code). `None` past the tile's samples.
    #[inline]
    pub fn sample(&self, channel: usize, x: usize, y: usize) -> Option<u8> {
        let fine = self.refinement();
        if channel >= self.channels() || x >= self.side() || y >= self.side() {
            return None;
        }
        let (a, b) = ((x / TILE_CELLS).min(fine - 1), (y / TILE_CELLS).min(fine - 1));
        let (i, j) = (x - a * TILE_CELLS, y - b * TILE_CELLS);
        let k = ((channel * fine + b) * fine + a) * TILE_SAMPLES + j * TILE_SIDE + i;
        self.samples.get(k).copied()
    }
}

/// What a layer's tiles are read from: the owned layer or a view.
#[derive(Debug, Clone, Copy)]
enum Layer<'a> {
    Owned(&'a DistanceLayer),
    View(DistanceView<'a>),
}

impl<'a> Layer<'a> {
    fn cols(&self) -> u32 {
        match self {
            Layer::Owned(l) => l.tile_cols,
            Layer::View(v) => v.tile_cols,
        }
    }

    fn rows(&self) -> u32 {
        match self {
            Layer::Owned(l) => l.tile_rows,
            Layer::View(v) => v.tile_rows,
        }
    }

    fn tile(&self, col: u32, row: u32) -> Option<Tile<'a>> {
        if col >= self.cols() || row >= self.rows() {
            return None;
        }
        let i = row as usize * self.cols() as usize + col as usize;
        let (entry, origin, pitch, samples) = match *self {
            Layer::Owned(l) => (*l.tiles.get(i)?, (l.origin_x.0, l.origin_y.0), l.pitch_mm, &l.samples[..]),
            Layer::View(v) => (v.tile_entry(i as u32), (v.origin_x.0, v.origin_y.0), v.pitch_mm, v.sample_bytes()),
        };
        let entry = TileEntry::of(entry);
        let mut records = [NO_RECORD; SEGMENT_TILE_RECORDS];
        let first = entry.first();
        for (k, r) in records.iter_mut().enumerate().take(entry.records() as usize) {
            let p = first.saturating_add(k as u32);
            *r = match *self {
                Layer::Owned(l) => l.planes.get(p as usize).copied(),
                Layer::View(v) => v.plane(p),
            }
            .unwrap_or(NO_RECORD);
        }
        let stored = entry.stored() as usize;
        let start = first as usize * TILE_SAMPLES;
        let samples = if stored == 0 { &[][..] } else { samples.get(start..).unwrap_or(&[]) };
        let samples = &samples[..samples.len().min(stored * TILE_SAMPLES)];
        let (h, span) = (pitch as f64, (TILE_CELLS * col as usize) as f64);
        let corner_mm = (origin.0 as f64 + span * h, origin.1 as f64 + (TILE_CELLS * row as usize) as f64 * h);
        Some(Tile { col, row, entry, corner_mm, records, samples })
    }
}

/// The tiles of a layer, row by row ([`DistanceLayer::each_tile`], [`DistanceView::each_tile`]).
#[derive(Debug, Clone)]
pub struct TileIter<'a> {
    layer: Layer<'a>,
    next: u64,
}

impl<'a> Iterator for TileIter<'a> {
    type Item = Tile<'a>;

    fn next(&mut self) -> Option<Tile<'a>> {
        let cols = self.layer.cols() as u64;
        if cols == 0 || self.next >= cols * self.layer.rows() as u64 {
            return None;
        }
        let i = self.next;
        self.next += 1;
        self.layer.tile((i % cols) as u32, (i / cols) as u32)
    }
}

impl DistanceLayer {
    /// Tile `(col, row)`, or `None` past the lattice.
    pub fn tile(&self, col: u32, row: u32) -> Option<Tile<'_>> {
        Layer::Owned(self).tile(col, row)
    }

    /// Every tile, row by row.
    pub fn each_tile(&self) -> TileIter<'_> {
        TileIter { layer: Layer::Owned(self), next: 0 }
    }
}

impl<'a> DistanceView<'a> {
    /// Tile `(col, row)`, or `None` past the lattice.
    pub fn tile(&self, col: u32, row: u32) -> Option<Tile<'a>> {
        Layer::View(*self).tile(col, row)
    }

    /// Every tile, row by row.
    pub fn each_tile(&self) -> TileIter<'a> {
        TileIter { layer: Layer::View(*self), next: 0 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::distance::tiles::fine_entry;

    #[test]
    fn entry_texts_name_each_kinds_first_entry() {
        for kind in TileKind::ALL {
            let text = kind.entry_text();
            let first: u32 = text.split(' ').next().and_then(|n| n.parse().ok()).expect("a number first");
            assert_eq!(first, kind.first_entry(), "{text}");
            assert_eq!(TileEntry::of(kind.first_entry()).kind(), kind, "{text}");
            assert!(text.contains(kind.name()), "{text}");
        }
    }

    #[test]
    fn a_local_entry_plays_the_tiles_own_records() {
        for e in [
            TileEntry::Plane(7),
            TileEntry::Corner(7),
            TileEntry::Segments(7),
            TileEntry::Fine { first: 7, fine: 2, pair: true },
        ] {
            assert_eq!(e.local().first(), 0);
            assert_eq!(e.local().kind(), e.kind());
            assert_eq!(e.local().records(), e.records());
            assert_eq!(e.local().stored(), e.stored());
        }
        assert_eq!(fine_entry(0, 2, true).map(|e| TileEntry::of(e).first()), Some(0));
    }
}
