//! Edge position error: how far the half-amplitude contour that a distance
//! layer produces lies from the exact outline of its style (docs/report.md).
//!
//! The measure is the Hausdorff distance between two curves:
//!
//! - the **contour**: the zero set of the layer's interpolated signed
//!   distance (where the edge profile gives ½, hard or soft), evaluated with
//!   the SPEC reference [`DistanceLayer::distance_at`], which the runtime's
//!   kernel is property-tested equal to. Inside a lattice cell the distance
//!   is bilinear, so along any line parallel to an axis it is linear and its
//!   zero is found exactly: the contour is sampled where it crosses lines
//!   [`SAMPLE_MM`] apart in both directions (consecutive points at most
//!   `SAMPLE_MM · √2` apart along it);
//! - the **outline**: the boundary of the exact region of the layer's style
//!   (the union of its sources, gratings minus vibrating bands, within the
//!   device's surface), cut into pieces at most [`SAMPLE_MM`] long; a piece
//!   of a candidate edge (a fill's outline, a band's offset lines and the
//!   circles round its vertices) is on the boundary when exact coverage
//!   differs 1 µm on either side of its middle.
//!
//! The error is the larger of the two directed distances: the largest exact
//! distance from a contour point to the outline's pieces, and the largest
//! distance from a piece's middle to the nearest contour point. Both are
//! within about `SAMPLE_MM` of the distance between the continuous curves.
//! Points within [`CORNER_RADIUS_MM`] of a corner of the outline are
//! reported apart from the rest.

use std::sync::OnceLock;

use rayon::prelude::*;
use rstar::RTree;
use rstar::primitives::Line;
use taxel_format::{DISTANCE_ZERO, DistanceLayer, TILE_CELLS, Tile, TileKind};

use super::exact::{Region, Seg};

/// Spacing of the sample lines across the contour and longest piece of the outline, mm.
pub const SAMPLE_MM: f64 = 0.005;

/// How closely a curved tile's contour point is bisected, mm.
const BISECT_MM: f64 = 1e-9;
/// The fraction of the distance within which a curved tile's code keeps
/// its sign (its value over its slope) that [`bend_contour`]'s walk skips.
const SKIP_MARGIN: f64 = 0.999;
/// Radius round each corner of an outline within which errors count as the corner's, mm.
pub const CORNER_RADIUS_MM: f64 = 1.0;
/// Offset either side of an outline piece at which coverage is compared, mm.
const SIDE_MM: f64 = 0.001;
/// How far beyond its tile's sides, in lattice cells, a corner or notch
/// tile's edge still counts as its own. An edge on a tile's side (a
/// rectangle's side on a lattice line) has its zero a few millionths of a
/// cell inside the tile or outside it, as the records' rounding falls; with
/// the tile taken as half-open, an edge just outside both tiles beside it
/// was found by neither (`tala-map`'s key swatches at the default lattice:
/// 1.75 mm of "edge error" where the field was right).
const SIDE_CELLS: f64 = 1e-4;
/// Largest gap between a band's round join and the chords standing for it, mm.
const SAGITTA_MM: f64 = 0.000_25;

/// Edge position errors of one or more layers, mm; `None` where there was nothing to measure.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EdgeError {
    /// Away from corners.
    pub edge_mm: Option<f64>,
    /// Within [`CORNER_RADIUS_MM`] of a corner.
    pub corner_mm: Option<f64>,
    /// The place of the exact outline farthest from the played contour.
    pub farthest: Option<Farthest>,
}

/// The place of an exact outline farthest from the played contour, and how
/// large the outline there is: an island or a hole smaller than the
/// lattice, which the field does not play, is as far from the contour as
/// the nearest edge that is played (a town's 0.4 mm disc cut out of a
/// region, 1 mm from the region's sides).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Farthest {
    /// Page mm.
    pub at: (f64, f64),
    /// Its distance to the played contour, mm.
    pub distance_mm: f64,
    /// The larger side of the box of the connected piece of outline it
    /// lies on, mm, up to [`FEATURE_CAP_MM`] (more stands for "at least").
    pub across_mm: f64,
}

/// How far the outline round [`Farthest`] is followed, mm: features
/// larger than this are not small.
pub const FEATURE_CAP_MM: f64 = 2.0;

impl EdgeError {
    /// The larger of two measurements, part by part.
    pub fn max(self, o: EdgeError) -> EdgeError {
        let farthest = match (self.farthest, o.farthest) {
            (Some(a), Some(b)) => Some(if b.distance_mm > a.distance_mm { b } else { a }),
            (a, b) => a.or(b),
        };
        EdgeError {
            edge_mm: max_opt(self.edge_mm, o.edge_mm),
            corner_mm: max_opt(self.corner_mm, o.corner_mm),
            farthest,
        }
    }
}

/// The larger of two optional values.
pub fn max_opt(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.max(b)),
        (a, b) => a.or(b),
    }
}

/// Corners of outlines, for "is this point near a corner" queries.
pub struct Corners(RTree<[f64; 2]>);

impl Corners {
    /// Indexes `points`.
    pub fn new(points: impl IntoIterator<Item = (f64, f64)>) -> Corners {
        Corners(RTree::bulk_load(points.into_iter().map(|(x, y)| [x, y]).collect()))
    }

    /// Whether `p` is within [`CORNER_RADIUS_MM`] of a corner.
    pub fn near(&self, p: [f64; 2]) -> bool {
        self.0.locate_within_distance(p, CORNER_RADIUS_MM * CORNER_RADIUS_MM).next().is_some()
    }
}

/// Side of a [`Buckets`] cell, mm: four sample spacings, so that a cell's
/// neighbourhood holds a few dozen contour points or outline pieces.
const BUCKET_MM: f64 = 4.0 * SAMPLE_MM;

/// How many rings of cells round a point's own [`Buckets`] looks through
/// for its nearest item before the R*-tree is asked: 0.16 mm, farther
/// than the coarse rungs' edge errors (a few hundredths of a mm) that sent
/// every point to the tree when only the first ring was looked through.
const BUCKET_RINGS: i32 = 8;

/// The rings [`Buckets`] always looks through.
const NEAR_RINGS: i32 = 2;

/// Items (points, or outline pieces at most [`SAMPLE_MM`] long) filed by
/// the [`BUCKET_MM`] cells their boxes meet, row by row: an item within `k`
/// cells' sides of a point is among those of the cells at most `k` rows
/// and columns from the point's, runs of the sorted keys. The errors
/// measured are mostly micrometres; the R*-tree answers the rest. (A
/// report's edge errors asked the tree for every one of its contour points
/// and pieces' middles, half of the whole report's time; issue 46 point 6.)
struct Buckets {
    /// `(key, item)`, sorted: a key is the cell's row, then its column.
    keys: Vec<(u64, u32)>,
    /// The first row with a key, and where each row's keys start in `keys`
    /// from it on (one more entry than rows, the last `keys.len()`), so
    /// that a row's cells are looked up among its own keys, not all of
    /// them (the whole list's binary search was a fifth of a report's time
    /// in the tests' build); empty where the rows would be too many.
    first_row: i64,
    row_start: Vec<u32>,
}

/// The most rows [`Buckets`] keeps a start for (a 4 m page at its cell).
const BUCKET_MAX_ROWS: i64 = 1 << 18;

impl Buckets {
    /// Files items by their boxes `(min, max)`.
    fn new(boxes: impl Iterator<Item = ([f64; 2], [f64; 2])>) -> Buckets {
        let mut keys = Vec::new();
        for (n, (lo, hi)) in boxes.enumerate() {
            let ((c0, r0), (c1, r1)) = (Self::cell(lo), Self::cell(hi));
            for r in r0..=r1 {
                for c in c0..=c1 {
                    keys.push((Self::key(c, r), n as u32));
                }
            }
        }
        keys.sort_unstable();
        let row = |k: u64| i64::from((k >> 32) as u32);
        let (first_row, last_row) = match (keys.first(), keys.last()) {
            (Some(a), Some(b)) => (row(a.0), row(b.0)),
            _ => (0, -1),
        };
        let mut row_start = Vec::new();
        if last_row - first_row < BUCKET_MAX_ROWS && keys.len() < u32::MAX as usize {
            let rows = (last_row - first_row + 1) as usize;
            row_start.reserve(rows + 1);
            for (n, &(k, _)) in keys.iter().enumerate() {
                // Every row up to this key's starts here (empty rows included).
                while row_start.len() as i64 <= row(k) - first_row {
                    row_start.push(n as u32);
                }
            }
            row_start.resize(rows + 1, keys.len() as u32);
        }
        Buckets { keys, first_row, row_start }
    }

    /// The cell of `p`: column and row.
    fn cell(p: [f64; 2]) -> (i32, i32) {
        // (Saturating casts: a point off any sensible page lands in an edge cell.)
        ((p[0] / BUCKET_MM).floor() as i32, (p[1] / BUCKET_MM).floor() as i32)
    }

    fn key(c: i32, r: i32) -> u64 {
        (u64::from(r.wrapping_sub(i32::MIN) as u32) << 32) | u64::from(c.wrapping_sub(i32::MIN) as u32)
    }

    /// Calls `f` on every item filed in row `row`, columns `c0..=c1`.
    fn each_in_row(&self, row: i32, (c0, c1): (i32, i32), f: &mut impl FnMut(usize)) {
        let (from, to) = (Self::key(c0, row), Self::key(c1, row));
        let keys = if self.row_start.is_empty() {
            &self.keys[..]
        } else {
            // The row's own keys (none for a row outside the filed ones).
            let i = i64::from(row.wrapping_sub(i32::MIN) as u32) - self.first_row;
            match usize::try_from(i).ok().and_then(|i| Some((*self.row_start.get(i)?, *self.row_start.get(i + 1)?))) {
                Some((a, b)) => &self.keys[a as usize..b as usize],
                None => return,
            }
        };
        let start = keys.partition_point(|&(k, _)| k < from);
        for &(_, n) in keys[start..].iter().take_while(|&&(k, _)| k <= to) {
            f(n as usize);
        }
    }

    /// Calls `f` on every item of `p`'s cell and the eight round it (each
    /// item within a cell's side of `p` among them, some more than once).
    fn each_near(&self, p: [f64; 2], mut f: impl FnMut(usize)) {
        let (c, r) = Self::cell(p);
        for row in [r.saturating_sub(1), r, r.saturating_add(1)] {
            self.each_in_row(row, (c.saturating_sub(1), c.saturating_add(1)), &mut f);
        }
    }

    /// The least `d2(item)` (a squared distance from `p`) over every item,
    /// or `None` where the rings do not reach it: the items of `p`'s cell
    /// and of the rings of cells round it are looked through one ring after
    /// another, until the least so far is within the rings' reach. Past
    /// [`NEAR_RINGS`], a point with nothing found within [`BUCKET_RINGS`]
    /// is left to the tree at once (an island the field does not play is
    /// millimetres from any contour: looking through every ring first made
    /// a map of slivers' report slower).
    fn nearest_2(&self, p: [f64; 2], d2: impl Fn(usize) -> f64) -> Option<f64> {
        let (c, r) = Self::cell(p);
        let best = std::cell::Cell::new(f64::INFINITY);
        let mut least = |n: usize| best.set(best.get().min(d2(n)));
        self.each_in_row(r, (c, c), &mut least);
        for k in 1..=BUCKET_RINGS {
            // Ring `k`: its top and bottom rows whole, the columns `k`
            // away on the rows between.
            let (c0, c1) = (c.saturating_sub(k), c.saturating_add(k));
            for row in [r.saturating_sub(k), r.saturating_add(k)] {
                self.each_in_row(row, (c0, c1), &mut least);
            }
            for row in r.saturating_sub(k - 1)..=r.saturating_add(k - 1) {
                self.each_in_row(row, (c0, c0), &mut least);
                self.each_in_row(row, (c1, c1), &mut least);
            }
            // An item of no cell within `k` of `p`'s is farther than `k` sides.
            let reach = f64::from(k) * BUCKET_MM;
            if best.get() <= reach * reach {
                return Some(best.get());
            }
            let rings = f64::from(BUCKET_RINGS) * BUCKET_MM;
            if k >= NEAR_RINGS && best.get() > rings * rings {
                return None;
            }
        }
        None
    }
}

/// The exact outline of one layer's region, measured once for every rung.
pub struct Outline {
    /// The boundary's pieces, in the outline's order.
    piece_list: Vec<Line<[f64; 2]>>,
    /// The same pieces filed by cells.
    near_pieces: Buckets,
    /// The same pieces in an R*-tree, built only if a point is farther from
    /// every piece than [`Buckets`] looks.
    pieces: OnceLock<RTree<Line<[f64; 2]>>>,
    /// Their middles.
    mids: Vec<[f64; 2]>,
    /// The region's corners: the outlines' own (see [`super::exact::corners`])
    /// and every point where two pieces of the boundary meet at more than
    /// [`super::exact::CORNER_TURN_DEG`] (the inner corners of crossing or
    /// joining bands, a fill's edge meeting a cut band).
    pub corners: Corners,
}

impl Outline {
    /// The outline of `region` clipped to the surface `(width, height)` mm.
    pub fn new(region: &Region, surface: (f64, f64)) -> Outline {
        let segs = outline(region, surface, SAMPLE_MM);
        let piece_list: Vec<Line<[f64; 2]>> = segs.iter().map(|&(a, b)| Line::new([a.0, a.1], [b.0, b.1])).collect();
        let near_pieces = Buckets::new(piece_list.iter().map(|l| {
            let [(x0, x1), (y0, y1)] = [(l.from[0], l.to[0]), (l.from[1], l.to[1])];
            ([x0.min(x1), y0.min(y1)], [x0.max(x1), y0.max(y1)])
        }));
        let sharp = super::exact::CORNER_TURN_DEG.to_radians().sin();
        let dir = |l: &Line<[f64; 2]>| {
            let (dx, dy) = (l.to[0] - l.from[0], l.to[1] - l.from[1]);
            let n = dx.hypot(dy).max(1e-12);
            (dx / n, dy / n)
        };
        let mut corners: Vec<(f64, f64)> = region.corners.clone();
        let mut mids = Vec::with_capacity(segs.len());
        // A corner where a piece within two sample spacings of a piece's
        // middle turns sharply from it (the pieces within that reach are
        // among those of the middle's cell and the eight round it).
        let reach_2 = 4.0 * SAMPLE_MM * SAMPLE_MM;
        for l in &piece_list {
            let m = [(l.from[0] + l.to[0]) / 2.0, (l.from[1] + l.to[1]) / 2.0];
            mids.push(m);
            let u = dir(l);
            let mut meets = false;
            near_pieces.each_near(m, |n| {
                let o = &piece_list[n];
                if !meets && line_distance_2(o, m) <= reach_2 {
                    let v = dir(o);
                    meets = (u.0 * v.1 - u.1 * v.0).abs() > sharp;
                }
            });
            if meets {
                corners.push((m[0], m[1]));
            }
        }
        Outline { piece_list, near_pieces, pieces: OnceLock::new(), mids, corners: Corners::new(corners) }
    }

    /// The larger side of the box of the outline connected to piece `n`
    /// (pieces whose middles are within two sample spacings of each
    /// other), followed until it is [`FEATURE_CAP_MM`] across.
    fn extent(&self, n: usize) -> f64 {
        let reach_2 = 4.0 * SAMPLE_MM * SAMPLE_MM;
        let mut seen = vec![false; self.mids.len()];
        let (mut todo, [x, y]) = (vec![n], self.mids[n]);
        let (mut lo, mut hi) = ((x, y), (x, y));
        seen[n] = true;
        while let Some(k) = todo.pop() {
            let m = self.mids[k];
            (lo, hi) = ((lo.0.min(m[0]), lo.1.min(m[1])), (hi.0.max(m[0]), hi.1.max(m[1])));
            if (hi.0 - lo.0).max(hi.1 - lo.1) >= FEATURE_CAP_MM {
                break;
            }
            self.near_pieces.each_near(m, |o| {
                let q = self.mids[o];
                if !seen[o] && (q[0] - m[0]).powi(2) + (q[1] - m[1]).powi(2) <= reach_2 {
                    seen[o] = true;
                    todo.push(o);
                }
            });
        }
        (hi.0 - lo.0).max(hi.1 - lo.1)
    }

    /// The squared distance from `p` to the nearest piece.
    fn nearest_2(&self, p: [f64; 2]) -> Option<f64> {
        self.near_pieces.nearest_2(p, |n| line_distance_2(&self.piece_list[n], p)).or_else(|| {
            let tree = self.pieces.get_or_init(|| RTree::bulk_load(self.piece_list.clone()));
            tree.nearest_neighbor(&p).map(|l| line_distance_2(l, p))
        })
    }
}

/// The squared distance from `q` to segment `l`: what `rstar`'s
/// `Line::distance_2` gives, step for step (the same nearest point, the
/// same sums), written out so that it inlines where the tests' build does
/// not inline `rstar`'s generic point arithmetic (a fifth of a report's
/// time there).
#[inline]
fn line_distance_2(l: &Line<[f64; 2]>, q: [f64; 2]) -> f64 {
    let (a, b) = (l.from, l.to);
    let dir = [b[0] - a[0], b[1] - a[1]];
    let s = ((q[0] - a[0]) * dir[0] + (q[1] - a[1]) * dir[1]) / (dir[0] * dir[0] + dir[1] * dir[1]);
    let n = if 0.0 < s && s < 1.0 {
        [a[0] + dir[0] * s, a[1] + dir[1] * s]
    } else if s <= 0.0 {
        a
    } else {
        b
    };
    point_distance_2(n, q)
}

/// The squared distance between `p` and `q`, as `rstar`'s for points.
#[inline]
fn point_distance_2(p: [f64; 2], q: [f64; 2]) -> f64 {
    let d = [p[0] - q[0], p[1] - q[1]];
    d[0] * d[0] + d[1] * d[1]
}

/// The edge position error of `layer` against the exact `outline` of its style.
pub fn edge_error(layer: &DistanceLayer, outline: &Outline) -> EdgeError {
    let contour = contour(layer, SAMPLE_MM);
    // Each point's distance on its own, the largest kept: the same on any
    // number of threads. A curve with nothing to compare against is
    // infinitely far from it.
    let at = |p: [f64; 2], d: f64| {
        if outline.corners.near(p) {
            EdgeError { edge_mm: None, corner_mm: Some(d), farthest: None }
        } else {
            EdgeError { edge_mm: Some(d), corner_mm: None, farthest: None }
        }
    };
    let to_outline = contour
        .par_iter()
        .map(|&p| at(p, outline.nearest_2(p).map_or(f64::INFINITY, f64::sqrt)))
        .reduce(EdgeError::default, EdgeError::max);
    let near_points = Buckets::new(contour.iter().map(|&c| (c, c)));
    // The tree only where a middle is beyond the buckets' rings.
    let points: OnceLock<RTree<[f64; 2]>> = OnceLock::new();
    let from_outline: Vec<f64> = outline
        .mids
        .par_iter()
        .map(|&q| {
            let near = near_points.nearest_2(q, |n| point_distance_2(contour[n], q));
            let tree = || points.get_or_init(|| RTree::bulk_load(contour.clone()));
            let d2 = near.or_else(|| tree().nearest_neighbor(&q).map(|&c| point_distance_2(c, q)));
            d2.map_or(f64::INFINITY, f64::sqrt)
        })
        .collect();
    let to_contour = (outline.mids.par_iter().zip(&from_outline))
        .map(|(&q, &d)| at(q, d))
        .reduce(EdgeError::default, EdgeError::max);
    // The first of the farthest, for the same answer on any number of threads.
    let farthest = from_outline.iter().enumerate().fold(None, |best: Option<(usize, f64)>, (n, &d)| match best {
        Some((_, b)) if b >= d => best,
        _ => Some((n, d)),
    });
    let farthest = farthest.map(|(n, d)| Farthest {
        at: (outline.mids[n][0], outline.mids[n][1]),
        distance_mm: d,
        across_mm: outline.extent(n),
    });
    EdgeError { farthest, ..to_outline.max(to_contour) }
}

/// Points of the half-amplitude contour of `layer` (the zero set of its
/// interpolated distance), where it crosses the lines `sample` mm apart in
/// each lattice cell, in page mm.
pub fn contour(layer: &DistanceLayer, sample: f64) -> Vec<[f64; 2]> {
    let h = layer.pitch_mm as f64;
    if !(h.is_finite() && h > 0.0) {
        return Vec::new();
    }
    let lines = ((h / sample).ceil() as usize).max(1);
    let (ox, oy) = (layer.origin_x.0 as f64, layer.origin_y.0 as f64);
    // The tiles with an edge, each on whichever core is free; their points
    // in the tiles' order, as one pass would give them.
    let tiles: Vec<Tile<'_>> =
        layer.each_tile().filter(|t| !matches!(t.kind(), TileKind::Outside | TileKind::Inside)).collect();
    let each: Vec<Vec<[f64; 2]>> = tiles
        .par_iter()
        .with_max_len(1)
        .map(|tile| {
            let mut out = Vec::new();
            tile_contour(layer, tile, (ox, oy), lines, &mut out);
            out
        })
        .collect();
    each.concat()
}

/// [`contour`]'s points in one tile.
fn tile_contour(layer: &DistanceLayer, tile: &Tile<'_>, (ox, oy): (f64, f64), lines: usize, out: &mut Vec<[f64; 2]>) {
    let h = layer.pitch_mm as f64;
    let (tx, ty) = (tile.col as usize, tile.row as usize);
    match tile.kind() {
        TileKind::Outside | TileKind::Inside => return,
        TileKind::Corner | TileKind::Notch => {
            bent_contour(tile, h, lines * TILE_CELLS, out);
            return;
        }
        TileKind::Bend | TileKind::Arc | TileKind::Segments => {
            bend_contour(tile, h, lines * TILE_CELLS, out);
            return;
        }
        TileKind::Fine => {
            fine_contour(layer, tile, lines.div_ceil(tile.refinement()), out);
            return;
        }
        // Bilinear in each lattice cell: read through the SPEC's reference.
        TileKind::Stored | TileKind::Plane | TileKind::Ridge => {}
    }
    for cj in ty * TILE_CELLS..(ty + 1) * TILE_CELLS {
        for ci in tx * TILE_CELLS..(tx + 1) * TILE_CELLS {
            let (x0, y0) = (ox + ci as f64 * h, oy + cj as f64 * h);
            let Some(c) = cell_corners(layer, (x0, y0), h) else { continue };
            let inside = c.map(|d| d > 0.0);
            if inside.iter().all(|&s| s == inside[0]) {
                continue;
            }
            let [c00, c10, c01, c11] = c;
            for k in 0..=lines {
                let t = k as f64 / lines as f64;
                // Along the vertical line u = t, then the horizontal line v = t.
                let (a, b) = (c00 + (c10 - c00) * t, c01 + (c11 - c01) * t);
                if (a > 0.0) != (b > 0.0) {
                    out.push([x0 + t * h, y0 + a / (a - b) * h]);
                }
                let (a, b) = (c00 + (c01 - c00) * t, c10 + (c11 - c10) * t);
                if (a > 0.0) != (b > 0.0) {
                    out.push([x0 + a / (a - b) * h, y0 + t * h]);
                }
            }
        }
    }
}

/// Points of the half-amplitude contour of a fine tile (format 4.4;
/// samples finer than the lattice, in one or two channels), where it
/// crosses `lines + 1` lines across each fine cell in each direction. Each
/// channel is bilinear in a fine cell, so its zero on a line is found
/// exactly; with two channels it is on the contour where the other channel
/// is not below 0 there (their lesser's zero). A code of exactly 0 counts
/// as inside, so that an edge on the tile's side (a rectangle's side on a
/// lattice line, where the samples are 0) is found from the outside tile.
fn fine_contour(layer: &DistanceLayer, tile: &Tile<'_>, lines: usize, out: &mut Vec<[f64; 2]>) {
    let (fine, corner) = (tile.refinement(), tile.corner_mm);
    let size = layer.pitch_mm as f64 / fine as f64;
    let lines = lines.max(1);
    // Channel `c`'s code (unbiased) at fine lattice point `(x, y)` of the tile.
    let at = |c: usize, x: usize, y: usize| tile.sample(c, x, y).map_or(f64::NAN, |v| v as f64 - DISTANCE_ZERO as f64);
    let channels = tile.channels();
    for y in 0..TILE_CELLS * fine {
        for x in 0..TILE_CELLS * fine {
            let cell: [[f64; 4]; 2] =
                core::array::from_fn(|c| [at(c, x, y), at(c, x + 1, y), at(c, x, y + 1), at(c, x + 1, y + 1)]);
            let cell = &cell[..channels];
            let value = |[c00, c10, c01, c11]: [f64; 4], u: f64, v: f64| {
                let (top, bot) = (c00 + (c10 - c00) * u, c01 + (c11 - c01) * u);
                top + (bot - top) * v
            };
            let (x0, y0) = (corner.0 + x as f64 * size, corner.1 + y as f64 * size);
            for (c, &[c00, c10, c01, c11]) in cell.iter().enumerate() {
                let sides = [c00, c10, c01, c11].map(|d| d >= 0.0);
                if sides.iter().all(|&s| s == sides[0]) {
                    continue;
                }
                // On the contour where every other channel is not below 0.
                let on = |u: f64, v: f64| cell.iter().enumerate().all(|(o, &d)| o == c || value(d, u, v) >= 0.0);
                for k in 0..=lines {
                    let t = k as f64 / lines as f64;
                    let (a, b) = (c00 + (c10 - c00) * t, c01 + (c11 - c01) * t);
                    if (a >= 0.0) != (b >= 0.0) && on(t, a / (a - b)) {
                        out.push([x0 + t * size, y0 + a / (a - b) * size]);
                    }
                    let (a, b) = (c00 + (c01 - c00) * t, c10 + (c11 - c10) * t);
                    if (a >= 0.0) != (b >= 0.0) && on(a / (a - b), t) {
                        out.push([x0 + a / (a - b) * size, y0 + t * size]);
                    }
                }
            }
        }
    }
}

/// Points of the half-amplitude contour of a bend, arc or segments tile (SPEC.md section
/// 6.2) whose first lattice point is at page `corner`, where it crosses
/// `lines + 1` lines across the tile in each direction: the function is
/// round round the vertex, so each line is walked in steps of a tenth of
/// the lines' spacing ([`sign_changes`]) and each change of sign is bisected.
fn bend_contour(tile: &Tile<'_>, h: f64, lines: usize, out: &mut Vec<[f64; 2]>) {
    let zero = DISTANCE_ZERO as f64;
    let span = TILE_CELLS as f64;
    let (corner, r) = (tile.corner_mm, tile.records());
    let f = |u: f64, w: f64| tile.code(u, w).map_or(f64::NAN, |c| c - zero);
    let steps = 10 * lines;
    // The code changes by at most `slope` codes per lattice cell (a bend's
    // and an arc's `k`: `k` times a distance), so a point `|v| / slope`
    // cells from one of value `v` has its sign: the walk skips the steps
    // that close to it, which cannot hold a change of sign (the same points
    // as a step-by-step walk). The codes are worked out in f64 from the
    // records, so the bound holds but for f64 rounding, far below the
    // [`SKIP_MARGIN`] kept. (Half the bound was kept before: approaching an
    // edge then took a step for every halving of the distance, not a few.)
    let slope = match tile.kind() {
        TileKind::Bend => r.get(1).map(|r| r.gy),
        // A cut arc (format 4.3) is the lesser of its arc and a plane: its
        // slope is at most the greater of theirs.
        TileKind::Arc => r.first().map(|a| {
            let plane = r.get(1).map_or(0.0, |s| s.gy.hypot(s.top));
            a.top.abs().max(plane)
        }),
        TileKind::Segments => r.get(taxel_format::SEGMENTS_PER_TILE).map(|r| r.c),
        _ => None,
    }
    .map(|k| f64::from(k).abs())
    .filter(|k| k.is_finite() && *k > 0.0);
    let step = span / steps as f64;
    let reach = |v: f64| match slope {
        Some(k) if v.is_finite() => (SKIP_MARGIN * v.abs() / k / step).floor().min(steps as f64) as usize,
        _ => 0,
    };
    for k in 0..=lines {
        let t = k as f64 / lines as f64 * span;
        // The vertical line u = t, then the horizontal line w = t.
        for vertical in [true, false] {
            let along = |s: f64| if vertical { (t, s) } else { (s, t) };
            let at = |i: usize| i as f64 / steps as f64 * span;
            let g = |s: f64| {
                let (u, w) = along(s);
                f(u, w)
            };
            sign_changes(
                steps,
                |i| g(at(i)),
                reach,
                |i, v, next| {
                    // To a picometre (the report's figures are to a
                    // micrometre, the records' f32 positions to a few nm).
                    let (u, w) = along(zero_between(g, (at(i), v), (at(i + 1), next), BISECT_MM / h));
                    out.push([corner.0 + u * h, corner.1 + w * h]);
                },
            );
        }
    }
}

/// The steps `i` of `0..=steps` along a line where the sign of `g` (above
/// 0 or not, both finite) changes between `i` and `i + 1`, handed to
/// `found` with `g(i)` and `g(i + 1)` in increasing order: what a walk that evaluated
/// every step finds, with `g` evaluated at few of them. `reach(v)` is how
/// many steps either side of a step of value `v` surely have its sign.
///
/// Two ends close in. Each skips the steps its value allows; where the low
/// end can skip none (it is next to a change) it steps by one and looks
/// for a change there. Once the steps the two ends' values answer for
/// cover the whole line between them, and their signs agree, no change is
/// left. Every step skipped has the sign of the end it was skipped from,
/// so a change lies between two steps both evaluated, next to each other.
/// Walking from one end alone, leaving an edge took a step for every
/// doubling of the distance from it; from both ends, a line crossing the
/// contour once costs a few steps each side of it.
fn sign_changes(
    steps: usize,
    g: impl Fn(usize) -> f64,
    reach: impl Fn(f64) -> usize,
    mut found: impl FnMut(usize, f64, f64),
) {
    let changes = |a: f64, b: f64| (a > 0.0) != (b > 0.0) && a.is_finite() && b.is_finite();
    let (mut lo, mut v_lo) = (0, g(0));
    if steps == 0 {
        return;
    }
    let (mut hi, mut v_hi) = (steps, g(steps));
    while hi - lo > 1 {
        let (a, b) = (reach(v_lo), reach(v_hi));
        if !changes(v_lo, v_hi) && v_lo.is_finite() && v_hi.is_finite() && lo + a + b + 1 >= hi {
            return;
        }
        if a >= 1 {
            lo = (lo + a).min(hi - 1);
            v_lo = g(lo);
        } else {
            let v = g(lo + 1);
            if changes(v_lo, v) {
                found(lo, v_lo, v);
            }
            (lo, v_lo) = (lo + 1, v);
        }
        if b >= 1 && hi - lo > 1 {
            hi = hi.saturating_sub(b).max(lo + 1);
            v_hi = g(hi);
        }
    }
    if changes(v_lo, v_hi) {
        found(lo, v_lo, v_hi);
    }
}

/// A point within `tol` of a zero of `g` between `a` and `b`, given with
/// their values `(s, g(s))` of opposite signs (above 0, and not): the
/// middle of a bracket narrowed by the Illinois method (the secant through
/// the bracket's ends, the end kept twice in a row halved in weight). A
/// tile's code is smooth across its contour, so that takes a few
/// evaluations where bisection from a walk's step to a picometre took 19.
/// Past 8 secant steps, or where the secant leaves the bracket, it halves
/// instead, so the bracket always narrows to `tol`; a step is at least
/// half `tol` from either end. A value that is not a
/// number counts as not above 0, as it did in the bisection.
fn zero_between(g: impl Fn(f64) -> f64, (mut a, mut ga): (f64, f64), (mut b, mut gb): (f64, f64), tol: f64) -> f64 {
    let above = ga > 0.0;
    // Which end was kept last: -1 the low end, 1 the high end.
    let mut kept = 0;
    let mut secants = 0;
    // (A bound on the steps, for a tolerance below the floats' spacing: 8
    // secant steps and 64 halvings narrow any bracket of a tile to it.)
    for _ in 0..8 + 64 {
        if b - a <= tol {
            break;
        }
        let mut m = (a * gb - b * ga) / (gb - ga);
        secants += 1;
        if secants > 8 || !(m >= a && m <= b) {
            m = 0.5 * (a + b);
        }
        // At least half the tolerance in from either end: where the secant
        // lands on the zero, the next step lands just past it and closes
        // the bracket, rather than crawl from the far end.
        let m = m.max(a + 0.5 * tol).min(b - 0.5 * tol);
        let gm = g(m);
        if (gm > 0.0) == above {
            (a, ga) = (m, gm);
            if kept == -1 {
                gb *= 0.5;
            }
            kept = -1;
        } else {
            (b, gb) = (m, gm);
            if kept == 1 {
                ga *= 0.5;
            }
            kept = 1;
        }
    }
    0.5 * (a + b)
}

/// Points of the half-amplitude contour of a corner or notch tile (the
/// lesser or greater of plane records `p` and `p + 1`, SPEC.md section 6.2)
/// whose first lattice point is at page `corner`, where it crosses `lines +
/// 1` lines across the tile in each direction. The function is not bilinear
/// in the cell of the vertex, so the contour is found per record: the zero
/// of one record's affine code on a line is on the contour where the other
/// code is not below it (a corner's lesser) or not above it (a notch's
/// greater).
fn bent_contour(tile: &Tile<'_>, h: f64, lines: usize, out: &mut Vec<[f64; 2]>) {
    let (&[r1, r2], corner) = (tile.records(), tile.corner_mm) else { return };
    let zero = DISTANCE_ZERO as f64;
    let span = TILE_CELLS as f64;
    let notch = tile.kind() == TileKind::Notch;
    let on = |u: f64, w: f64, other: &taxel_format::TilePlane| {
        if notch { other.affine(u, w) <= zero } else { other.affine(u, w) >= zero }
    };
    for k in 0..=lines {
        let t = k as f64 / lines as f64 * span;
        for (r, other) in [(&r1, &r2), (&r2, &r1)] {
            let (c, gx, gy) = (r.c as f64 - zero, r.gx as f64, r.gy as f64);
            // The vertical line u = t, then the horizontal line w = t.
            if gy != 0.0 {
                let w = -(c + gx * t) / gy;
                if (-SIDE_CELLS..=span + SIDE_CELLS).contains(&w) && on(t, w, other) {
                    out.push([corner.0 + t * h, corner.1 + w * h]);
                }
            }
            if gx != 0.0 {
                let u = -(c + gy * t) / gx;
                if (-SIDE_CELLS..=span + SIDE_CELLS).contains(&u) && on(u, t, other) {
                    out.push([corner.0 + u * h, corner.1 + t * h]);
                }
            }
        }
    }
}

/// The distance at the four corners of the cell `size` mm square from page
/// `(x0, y0)` (a lattice cell, or a fine tile's cell) as its bilinear
/// interpolation sees them, `[(0,0), (1,0), (0,1), (1,1)]`: read through
/// [`DistanceLayer::distance_at`] at the cell's quarter points (so that
/// every read lands in the cell itself) and extrapolated, which is exact
/// for a bilinear function.
fn cell_corners(layer: &DistanceLayer, (x0, y0): (f64, f64), size: f64) -> Option<[f64; 4]> {
    let at = |u: f64, v: f64| layer.distance_at((x0 + u * size) as f32, (y0 + v * size) as f32).map(f64::from);
    let (q1, q3) = (0.25, 0.75);
    let (a, b, c, d) = (at(q1, q1)?, at(q3, q1)?, at(q1, q3)?, at(q3, q3)?);
    // A linear function known at ¼ and ¾ is 1.5 f(¼) − 0.5 f(¾) at 0 and the reverse at 1.
    let ext = |near: f64, far: f64| 1.5 * near - 0.5 * far;
    let (l0, l1) = (ext(a, c), ext(c, a)); // column u = ¼ at v = 0 and v = 1
    let (r0, r1) = (ext(b, d), ext(d, b)); // column u = ¾
    Some([ext(l0, r0), ext(r0, l0), ext(l1, r1), ext(r1, l1)])
}

/// The boundary of the exact `region`, clipped to the surface `(width,
/// height)`, as pieces at most `sample` mm long.
pub fn outline(region: &Region, surface: (f64, f64), sample: f64) -> Vec<Seg> {
    let (w, h) = surface;
    let covers = |p: (f64, f64)| (0.0..=w).contains(&p.0) && (0.0..=h).contains(&p.1) && region.exact.covers(p);
    let mut candidates = region.exact.edge_candidates(SAGITTA_MM);
    candidates.extend([((0.0, 0.0), (w, 0.0)), ((w, 0.0), (w, h)), ((w, h), (0.0, h)), ((0.0, h), (0.0, 0.0))]);
    // Each candidate on its own, in order (on every core: two coverage
    // tests a piece were most of a report's serial time on a scene of bands).
    candidates
        .par_iter()
        .flat_map_iter(|&(a, b)| {
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let len = dx.hypot(dy);
            let n = if len.is_finite() && len > 0.0 { (len / sample).ceil().max(1.0) as usize } else { 0 };
            let (nx, ny) = (-dy / len * SIDE_MM, dx / len * SIDE_MM);
            let at = move |k: usize| {
                let t = k as f64 / n as f64;
                (a.0 + dx * t, a.1 + dy * t)
            };
            (0..n).map(move |k| (at(k), at(k + 1))).filter(move |&(p, q)| {
                let m = ((p.0 + q.0) / 2.0, (p.1 + q.1) / 2.0);
                covers((m.0 + nx, m.1 + ny)) != covers((m.0 - nx, m.1 - ny))
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::exact::corners;
    use rstar::PointDistance;
    use taxel_compiler::geometry::{FillRule, Polyline};
    use taxel_compiler::latero::LayerGeometry;
    use taxel_format::{MaskKind, Mm, TILE_FIRST_STORED, TILE_SAMPLES, TILE_SIDE, TilePlane};

    proptest::proptest! {
        /// [`sign_changes`] finds exactly the changes of sign a walk that
        /// evaluates every step finds, in order, with the value before each,
        /// on functions of at most the slope its `reach` is told: a sum of
        /// "tent" and "wave" terms whose zeros fall anywhere, several to a
        /// line or none, between steps or on them, with stretches of NaN.
        #[test]
        fn sign_changes_are_those_of_every_step(
            steps in 1usize..400,
            slope in 0.01f64..5.0,
            offset in -3.0f64..3.0,
            waves in proptest::collection::vec((0.0f64..1.0, 0.0f64..40.0, 0.0f64..6.3), 0..4),
            gap in proptest::option::of((0usize..400, 0usize..20)),
        ) {
            // Slope at most `slope` per step in all: the terms' slopes share it out.
            let n = waves.len().max(1) as f64;
            let g = |i: usize| {
                if gap.is_some_and(|(at, len)| (at..at + len).contains(&i)) {
                    return f64::NAN;
                }
                let x = i as f64;
                let mut v = offset;
                for &(a, period, phase) in &waves {
                    // Of slope at most `a · slope / n`: `sin`'s is 1 over its argument.
                    let w = (period + 1.0).recip();
                    v += a * slope / n / w * (w * x + phase).sin();
                }
                v
            };
            let reach = |v: f64| if v.is_finite() { (SKIP_MARGIN * v.abs() / slope).floor().min(steps as f64) as usize } else { 0 };
            let mut every = Vec::new();
            for i in 0..steps {
                let (a, b) = (g(i), g(i + 1));
                if (a > 0.0) != (b > 0.0) && a.is_finite() && b.is_finite() {
                    every.push((i, a));
                }
            }
            let mut found = Vec::new();
            let evaluated = std::cell::Cell::new(0usize);
            sign_changes(steps, |i| { evaluated.set(evaluated.get() + 1); g(i) }, reach, |i, v, _| found.push((i, v)));
            proptest::prop_assert_eq!(found, every);
            proptest::prop_assert!(evaluated.get() <= 2 * steps + 2);
        }
    }

    proptest::proptest! {
        /// [`line_distance_2`] and [`point_distance_2`] are `rstar`'s, bit for bit,
        /// degenerate segments (a point) and far queries included.
        #[test]
        fn distances_are_rstar_s(
            a in proptest::array::uniform2(-1e3f64..1e3),
            b in proptest::array::uniform2(-1e3f64..1e3),
            q in proptest::array::uniform2(-1e3f64..1e3),
            point in proptest::bool::ANY,
        ) {
            let l = Line::new(a, if point { a } else { b });
            proptest::prop_assert_eq!(line_distance_2(&l, q).to_bits(), l.distance_2(&q).to_bits());
            proptest::prop_assert_eq!(point_distance_2(a, q).to_bits(), a.distance_2(&q).to_bits());
        }
    }

    /// [`zero_between`] lands within its tolerance of the zero: in a few
    /// evaluations on a line and on a circle's distance (a tile's code
    /// along a line), within the bisection's count where `g` jumps or bends
    /// at its zero, and on either sign at the low end.
    #[test]
    fn zero_between_finds_the_zero_to_its_tolerance() {
        let tol = 1e-12;
        let count = |g: &dyn Fn(f64) -> f64, a: f64, b: f64| {
            let n = std::cell::Cell::new(0);
            let z = zero_between(
                |s| {
                    n.set(n.get() + 1);
                    g(s)
                },
                (a, g(a)),
                (b, g(b)),
                tol,
            );
            (z, n.get())
        };
        // A line through 0.3 (rising and falling).
        for sign in [1.0, -1.0] {
            let (z, n) = count(&|s| sign * (s - 0.3) * 7.0, 0.0, 1.0);
            assert!((z - 0.3).abs() <= tol, "{z}");
            assert!(n <= 6, "{n} evaluations");
        }
        // A circle's distance along a line 0.01 from its centre: `R - |q - C|`.
        let circle = |s: f64| 0.5 - ((s - 0.1).powi(2) + 1e-4).sqrt();
        let exact = 0.1 + (0.25f64 - 1e-4).sqrt();
        let (z, n) = count(&circle, 0.2, 0.9);
        assert!((z - exact).abs() <= tol, "{z} against {exact}");
        assert!(n <= 10, "{n} evaluations");
        // A jump at 0.123456: no secant helps, halving does.
        let (z, n) = count(&|s| if s < 0.123456 { 1.0 } else { -2.0 }, 0.0, 1.0);
        assert!((z - 0.123456).abs() <= tol, "{z}");
        assert!(n <= 8 + 41, "{n} evaluations");
        // A kink at the zero: the slope 10,000 times steeper past it.
        let (z, n) = count(&|s| (s - 0.7) * if s < 0.7 { 0.01 } else { 100.0 }, 0.0, 0.7 + 1e-3);
        assert!((z - 0.7).abs() <= tol, "{z}");
        assert!(n <= 8 + 41, "{n} evaluations");
        // A tolerance below the floats' spacing ends too, at the zero.
        let n = std::cell::Cell::new(0);
        let g = |s: f64| {
            n.set(n.get() + 1);
            s - 0.3
        };
        let z = zero_between(g, (0.0, -0.3), (1.0, 0.7), 1e-30);
        assert!((z - 0.3).abs() < 1e-15 && n.get() <= 8 + 64, "{z} after {}", n.get());
    }

    /// Where a line crosses the contour once, far from its ends, the walk
    /// evaluates a few steps either side of the change, not the line.
    #[test]
    fn one_change_costs_a_few_steps() {
        let (steps, slope) = (8000, 1.0);
        let g = |i: usize| (i as f64 - 3000.5) * 0.7;
        let reach = |v: f64| (SKIP_MARGIN * v.abs() / slope).floor() as usize;
        let evaluated = std::cell::Cell::new(0usize);
        let mut found = Vec::new();
        sign_changes(
            steps,
            |i| {
                evaluated.set(evaluated.get() + 1);
                g(i)
            },
            reach,
            |i, v, _| found.push((i, v)),
        );
        assert_eq!(found, vec![(3000, g(3000))]);
        assert!(evaluated.get() < 40, "{} evaluations", evaluated.get());
    }

    /// One stored tile of pitch 0.5 mm at the origin whose samples are `f(x, y)` in steps of `step` mm.
    fn layer(f: impl Fn(f64, f64) -> f64, step: f32) -> DistanceLayer {
        let h = 0.5f32;
        let mut samples = vec![0u8; TILE_SAMPLES];
        for j in 0..TILE_SIDE {
            for i in 0..TILE_SIDE {
                let d = f(i as f64 * h as f64, j as f64 * h as f64) / step as f64;
                samples[j * TILE_SIDE + i] = (128.0 + d.round()).clamp(1.0, 255.0) as u8;
            }
        }
        DistanceLayer {
            kind: MaskKind::Grating { wavelength: Mm(2.0), angle_deg: 0.0 },
            amplitude: 1.0,
            soft_mm: 0.0,
            step_mm: step,
            origin_x: Mm(0.0),
            origin_y: Mm(0.0),
            pitch_mm: h,
            tile_cols: 1,
            tile_rows: 1,
            sources: vec![0],
            tiles: vec![TILE_FIRST_STORED],
            planes: vec![],
            samples,
        }
    }

    /// Positive left of x = 2, in steps of 0.05 mm (every node a whole number of steps).
    fn half_plane() -> DistanceLayer {
        layer(|x, _| 2.0 - x, 0.05)
    }

    /// Signed distance to the square [1, 3]², positive inside.
    fn square(x: f64, y: f64) -> f64 {
        let (dx, dy) = ((x - 2.0).abs() - 1.0, (y - 2.0).abs() - 1.0);
        if dx <= 0.0 && dy <= 0.0 { -dx.max(dy) } else { -dx.max(0.0).hypot(dy.max(0.0)) }
    }

    #[test]
    fn a_straight_edge_is_found_where_the_samples_put_it() {
        let pts = contour(&half_plane(), 0.01);
        for p in &pts {
            assert!((p[0] - 2.0).abs() < 1e-5, "{p:?}");
            assert!((0.0..=4.0).contains(&p[1]));
        }
        // 51 lines across each of the 8 cells along the edge.
        assert_eq!(pts.len(), 8 * 51);
    }

    /// A fine tile's contour (format 4.4) with two channels: the zero set of
    /// their lesser, each channel's zero where the other is not below 0.
    #[test]
    fn a_fine_tile_of_two_channels_has_the_contour_of_their_lesser() {
        // Channel A positive left of x = 2, channel B below y = 1 (page y
        // down): their lesser is positive in the quarter x < 2, y > 1, and
        // its contour the two half lines x = 2, y >= 1 and y = 1, x <= 2.
        for fine in [1usize, 2] {
            let mut l = layer(|x, _| 2.0 - x, 0.05);
            // Each channel sampled `fine` times finer: sub-tile (sa, sb)'s
            // sample (i, j) at fine lattice point (8 sa + i, 8 sb + j).
            let h = 0.5 / fine as f64;
            let chan = |f: &dyn Fn(f64, f64) -> f64| -> Vec<u8> {
                let mut out = Vec::new();
                for sb in 0..fine {
                    for sa in 0..fine {
                        for j in 0..TILE_SIDE {
                            for i in 0..TILE_SIDE {
                                let (x, y) = ((8 * sa + i) as f64 * h, (8 * sb + j) as f64 * h);
                                out.push((128.0 + (f(x, y) / 0.05).round()).clamp(1.0, 255.0) as u8);
                            }
                        }
                    }
                }
                out
            };
            l.samples = chan(&|x, _| 2.0 - x);
            l.samples.extend(chan(&|_, y| y - 1.0));
            l.tiles = vec![taxel_format::fine_entry(0, fine as u32, true).expect("an entry")];
            let pts = contour(&l, 0.01);
            let (mut vertical, mut horizontal) = (0, 0);
            for p in &pts {
                if (p[0] - 2.0).abs() < 1e-5 && p[1] >= 1.0 - 1e-5 {
                    vertical += 1;
                } else if (p[1] - 1.0).abs() < 1e-5 && p[0] <= 2.0 + 1e-5 {
                    horizontal += 1;
                } else {
                    panic!("fine {fine}: {p:?} is on neither half line");
                }
            }
            assert!(vertical > 100 && horizontal > 100, "fine {fine}: {vertical} and {horizontal} points");
        }
    }

    /// Two corner tiles side by side (`tala-map`'s key swatches at the
    /// default lattice): the region is x < 4 mm (the tiles' shared side) and
    /// y > 1 mm. The first tile's plane for the side is zero a millionth of a
    /// cell past its right side, the second's a millionth before its left, as
    /// rounded records put them: the side is still on the contour.
    #[test]
    fn an_edge_on_the_side_between_two_corner_tiles_is_found() {
        let side = |c: f32| TilePlane { c, gx: -63.0, gy: 0.0, top: 0.0 };
        let below = TilePlane { c: 128.0 - 126.0, gx: 0.0, gy: 63.0, top: 0.0 };
        let mut l = layer(|x, _| 2.0 - x, 0.05);
        l.tile_cols = 2;
        l.samples.clear();
        l.tiles = vec![taxel_format::TILE_CORNER, taxel_format::TILE_CORNER | 2];
        // Zero at u = 8 + 1e-6 in the first tile, u = -1e-6 in the second.
        l.planes = vec![side(128.0 + 63.0 * 8.000_001), below, side(128.0 - 63.0 * 0.000_001), below];
        let pts = contour(&l, 0.01);
        let on_side = pts.iter().filter(|p| (p[0] - 4.0).abs() < 1e-4 && p[1] > 1.0).count();
        assert!(on_side > 100, "{on_side} points on the shared side");
    }

    /// The buckets give the least distance over every item exactly where
    /// it is within their rings' reach, and nothing farther: pieces that
    /// cross cells (and lie across the origin, where the cells' keys wrap)
    /// and points, against every item measured, from queries on them to
    /// queries well beyond the reach.
    #[test]
    fn buckets_find_the_nearest_item_within_a_cell_as_a_full_search_does() {
        // A deterministic scatter: short pieces along a wavy line, and queries round them.
        let wave = |t: f64| [t * 0.003 - 0.3, (t * 0.05).sin() * 0.04 + (t * 0.31).cos() * 0.002];
        let pieces: Vec<Line<[f64; 2]>> = (0..200).map(|k| Line::new(wave(k as f64), wave(k as f64 + 1.0))).collect();
        let buckets = Buckets::new(pieces.iter().map(|l| {
            ([l.from[0].min(l.to[0]), l.from[1].min(l.to[1])], [l.from[0].max(l.to[0]), l.from[1].max(l.to[1])])
        }));
        let points: Vec<[f64; 2]> = (0..200).map(|k| wave(k as f64 * 1.7)).collect();
        let point_buckets = Buckets::new(points.iter().map(|&p| (p, p)));
        // The rows' starts only narrow the search: without them (as past
        // `BUCKET_MAX_ROWS` rows) every answer is the same.
        assert!(!buckets.row_start.is_empty());
        let flat = Buckets { keys: buckets.keys.clone(), first_row: 0, row_start: Vec::new() };
        let (mut found, mut ringed, mut beyond) = (0, 0, 0);
        for k in 0..4000 {
            let t = k as f64 * 0.151;
            let off = ((k * 37) % 101) as f64 / 100.0 * 0.5 - 0.25;
            let q = [wave(t)[0] + off * 0.3, wave(t)[1] + off];
            let d2 = |n: usize| pieces[n].distance_2(&q);
            assert_eq!(buckets.nearest_2(q, d2), flat.nearest_2(q, d2), "{q:?}");
            for (got, all) in [
                (
                    buckets.nearest_2(q, |n| pieces[n].distance_2(&q)),
                    pieces.iter().map(|l| l.distance_2(&q)).collect::<Vec<_>>(),
                ),
                (
                    point_buckets.nearest_2(q, |n| points[n].distance_2(&q)),
                    points.iter().map(|p| p.distance_2(&q)).collect(),
                ),
            ] {
                let least = all.into_iter().fold(f64::INFINITY, f64::min);
                let (near, reach) = (f64::from(NEAR_RINGS) * BUCKET_MM, f64::from(BUCKET_RINGS) * BUCKET_MM);
                // Whatever is found is the least; within the rings always
                // looked through it is found; beyond every ring, never.
                if let Some(d2) = got {
                    assert_eq!(d2, least, "{q:?}");
                    found += 1;
                    // Farther than the first ring.
                    ringed += usize::from(least > BUCKET_MM * BUCKET_MM);
                } else {
                    assert!(least > near * near, "{q:?}: {least} is within the near rings");
                    beyond += usize::from(least > reach * reach);
                }
            }
        }
        // Every case was met.
        assert!(found > 1000 && ringed > 300 && beyond > 100, "{found} {ringed} {beyond}");
    }

    #[test]
    fn cell_corners_recover_the_samples() {
        let c = cell_corners(&half_plane(), (1.5, 1.0), 0.5).expect("inside the lattice");
        // Cell 3 spans x = 1.5..2.0: distances 0.5 and 0.
        assert!((c[0] - 0.5).abs() < 1e-5 && (c[2] - 0.5).abs() < 1e-5, "{c:?}");
        assert!(c[1].abs() < 1e-5 && c[3].abs() < 1e-5, "{c:?}");
    }

    /// An island of the exact region that the field does not play is
    /// as far from the contour as the nearest played edge: the farthest
    /// place is on it, and its size is the island's, where the square the
    /// field plays is larger than any lattice.
    #[test]
    fn the_farthest_place_of_the_outline_is_an_unplayed_island_with_its_size() {
        let layer = layer(square, 0.004);
        let main = Polyline { points: vec![(1.0, 1.0), (3.0, 1.0), (3.0, 3.0), (1.0, 3.0)], closed: true };
        let islet = Polyline { points: vec![(3.6, 3.6), (3.65, 3.6), (3.65, 3.65), (3.6, 3.65)], closed: true };
        let region = |polys: &[Polyline]| {
            let fills = vec![(polys, FillRule::NonZero)];
            Region { exact: LayerGeometry { fills, ..Default::default() }.exact(), corners: Vec::new() }
        };
        let both = [main.clone(), islet];
        let e = edge_error(&layer, &Outline::new(&region(&both), (4.0, 4.0)));
        let far = e.farthest.expect("a farthest place");
        // The islet's far corner, (3.65, 3.65), is 0.65 √2 mm from the
        // square's corner (3, 3), where the contour is; the place is a
        // piece's middle, within a sample of it.
        assert!((far.at.0 - 3.65).abs() < 2.0 * SAMPLE_MM && (far.at.1 - 3.65).abs() < 2.0 * SAMPLE_MM, "{far:?}");
        assert!((far.distance_mm - 0.65 * 2f64.sqrt()).abs() < 2.0 * SAMPLE_MM, "{far:?}");
        assert!((far.across_mm - 0.05).abs() < 2.0 * SAMPLE_MM, "{far:?}");
        // The square alone: played, its farthest place within micrometres of
        // the contour, on an outline 2 mm across.
        let alone = edge_error(&layer, &Outline::new(&region(std::slice::from_ref(&main)), (4.0, 4.0)));
        let far = alone.farthest.expect("a farthest place");
        assert!(far.distance_mm < 0.01 && far.across_mm > 1.9, "{far:?}");
        // The larger of two layers' places is kept.
        assert_eq!(alone.max(e).farthest, e.farthest);
        assert_eq!(e.max(alone).farthest, e.farthest);
    }

    #[test]
    fn edge_error_is_the_offset_between_contour_and_outline() {
        // The field's square is [1, 3]² (nodes on its sides are exact: 0.5 mm
        // is 125 steps of 0.004 mm); the exact square is 0.1 mm to the right.
        let layer = layer(square, 0.004);
        let shifted = Polyline { points: vec![(1.1, 1.0), (3.1, 1.0), (3.1, 3.0), (1.1, 3.0)], closed: true };
        let corners_at = |c: Vec<(f64, f64)>| {
            let fills = vec![(std::slice::from_ref(&shifted), FillRule::NonZero)];
            Region { exact: LayerGeometry { fills, ..Default::default() }.exact(), corners: c }
        };
        // The outline finds the square's corners where its sides meet, named or not.
        let named = corners_at(corners(std::slice::from_ref(&shifted), true, None));
        assert_eq!(named.corners.len(), 4);
        for region in [corners_at(Vec::new()), named] {
            let out = Outline::new(&region, (4.0, 4.0));
            for c in [[1.1, 1.0], [3.1, 1.0], [3.1, 3.0], [1.1, 3.0]] {
                assert!(out.corners.0.locate_within_distance(c, 4.0 * SAMPLE_MM * SAMPLE_MM).next().is_some(), "{c:?}");
            }
            // Nothing but the corners: the middle of each side is no corner.
            assert!(out.corners.0.locate_within_distance([2.1, 1.0], 0.25).next().is_none());
            let e = edge_error(&layer, &out);
            // The sides are 0.1 mm apart, and so are the corners.
            assert!((e.corner_mm.expect("corners") - 0.1).abs() < SAMPLE_MM, "{e:?}");
            // Points of a 2 mm square are at most 1 mm from a corner, so
            // only the sides' middles (if any) are left for the rest.
            assert!(e.edge_mm.is_none_or(|d| (d - 0.1).abs() < SAMPLE_MM), "{e:?}");
        }
        let with = corners_at(Vec::new());
        // The outline is the shifted square: its pieces lie on its sides.
        for (a, _) in outline(&with, (4.0, 4.0), 0.01) {
            let on = (a.0 - 1.1).abs() < 1e-9 || (a.0 - 3.1).abs() < 1e-9 || a.1 == 1.0 || a.1 == 3.0;
            assert!(on, "{a:?}");
        }
    }
}
