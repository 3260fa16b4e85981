//! The kinds of tile a distance layer's index names (SPEC.md section 6.2):
//! their index entries, their plane records and the codes they play, and
//! the checks a reader makes of each kind's records.

use super::TILE_CELLS;

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

/// Checks one plane record of a tile with index entry `e`: finite values
/// within the bounds that keep a player's `f32` arithmetic exact to far
/// below a code, and a plane's `top` zero (SPEC.md section 6.2).
pub(super) fn check_plane(p: &TilePlane, e: u32) -> Result<(), &'static str> {
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

/// The length of `(x, y)`: a square root of the sum of squares, which for
/// a tile's coordinates (at most thousands of cells) is within an ulp of
/// `hypot` at a fraction of its cost (the report's contour evaluates these
/// references millions of times).
#[inline]
fn length(x: f64, y: f64) -> f64 {
    libm::sqrt(x * x + y * y)
}

/// The code of a bend tile with records `r` at lattice coordinates
/// `(u, w)`, in f64 ([`TILE_BEND`]; SPEC.md section 6.2's reference).
pub fn bend_code(r: [&TilePlane; 2], u: f64, w: f64) -> f64 {
    let [a, b] = r;
    let (vx, vy) = (a.c as f64, a.gx as f64);
    let (dx, dy) = (u - vx, w - vy);
    let to_vertex = length(dx, dy);
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
    let rho = length(u - a.c as f64, w - a.gx as f64);
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
pub(super) fn check_arc(r: [TilePlane; 2]) -> Result<(), &'static str> {
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
        length(dx - t * ex, dy - t * ey)
    };
    let d = dist(s0).min(dist(s1)).min(dist(s2));
    last.gx as f64 - last.c as f64 * d
}

/// Checks a segments tile's four records: finite ends within
/// [`MAX_PLANE_GRADIENT`] cells of the tile, `|k|` at most
/// [`MAX_PLANE_GRADIENT`] codes per cell, `|top|` at most
/// [`MAX_PLANE_CODE`] and the last record's other two values 0 (SPEC.md
/// section 6.2).
pub(super) fn check_segments(r: [TilePlane; SEGMENT_TILE_RECORDS]) -> Result<(), &'static str> {
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
pub(super) fn check_bend(r: [TilePlane; 2]) -> Result<(), &'static str> {
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
