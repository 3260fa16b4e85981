//! Fine tiles (SPEC.md section 6.2, format 4.4): a tile that no analytic
//! kind plays and whose stored samples misplace its edge is sampled 2, 4 or
//! 8 times finer, as `f²` stored tiles (an adaptive distance field, refined
//! only where the lattice is too coarse for the drawing).
//!
//! A stored tile is exact at its 81 lattice points only; between them it
//! interpolates bilinearly. Where one edge crosses a cell that is close to
//! the distance (within a code or two of curvature and rounding). Where two
//! features meet inside a cell, the distance has a crease there (the lesser
//! of two distances) and the interpolation cuts it: a thin wedge of a map
//! between a river and a lake crossing at a shallow angle, or a band cut
//! across a curve, is rounded away or shifted by up to half a pitch (a
//! river over a lake: 0.76 mm at the default pitch). No analytic kind plays
//! two curved features, and the features of real drawings are Béziers and
//! ellipses, not circles; finer samples play any of them.
//!
//! The writer refines only where needed: it first compares the stored
//! tile's interpolation with the exact distance at the 64 cell centres, and
//! only where one is off by more than [`FINE_TOLERANCE_MM`] (beyond the
//! saturation on the same side, where every code plays the same amplitude)
//! measures the exact distance on the tile's finest lattice (65 x 65
//! points, `h / 8` apart, the cell centres among them) and keeps the
//! coarsest refinement whose interpolation is within the tolerance at every
//! one of those points (8 times finer if none is, where that is better than
//! the stored tile).

use taxel_format::{DISTANCE_ZERO, TILE_CELLS, TILE_SAMPLES, TILE_SIDE};

use super::near::Near;
use super::planes::TileCtx;

/// Largest distance between a stored or fine tile's interpolated distance
/// and the exact one, where the amplitude is not saturated on the same side
/// for both, mm: within it the edge (half amplitude) is at most this far
/// from the drawing's (`taxel report`'s edge error; its target is 0.05 mm).
pub(super) const FINE_TOLERANCE_MM: f64 = 0.03;
/// The refinements tried with two channels, and with one.
const PAIR_LEVELS: [usize; 2] = [1, 2];
const ONE_LEVELS: [usize; 3] = [1, 2, 4];
/// The finest refinement the writer measures and writes (the format allows
/// [`MAX_FINE`](taxel_format::MAX_FINE)): the exact distance is measured
/// on this lattice, where every coarser refinement is checked.
const FINEST: usize = 4;
/// Fine lattice points along a side of the tile at the finest refinement.
const SIDE: usize = TILE_CELLS * FINEST + 1;
/// Lattice cells a set of 9 x 9 fine points covers along each side.
const SPAN: usize = TILE_CELLS / FINEST;

/// A tile sampled `fine` times finer than the lattice, in one channel or
/// two (`pair`): `fine²` stored tiles a channel, row-major, each 81 codes
/// (SPEC.md section 6.2).
pub(super) struct Fine {
    pub fine: u32,
    pub pair: bool,
    pub samples: Vec<u8>,
}

/// How much a stored tile with samples `plain` (biased codes) needs
/// refining: `None` where it is within the tolerance at the cell centres
/// and no two parts' edges come within a cell of its samples; else its
/// largest error at the centres in codes, or just above the tolerance
/// where only the parts' meeting asks for a look (a wedge thinner than a
/// cell passes between the lattice points and the centres). `scratch` is
/// a [`Near`] of the layer's slots, overwritten.
pub(super) fn priority(t: &TileCtx<'_, '_>, scratch: &mut Near, plain: &[u8; TILE_SAMPLES]) -> Option<f64> {
    let tol = FINE_TOLERANCE_MM / t.step;
    let worst = std::cell::Cell::new(0.0f64);
    t.centres_all(scratch, |u, w, e| {
        worst.set(worst.get().max(error(t, interpolate(plain, 1, u, w), e)));
        true
    });
    let creased = t.measured.edges_within(t.h) >= 2;
    let w = worst.get();
    if w > tol {
        Some(w)
    } else if creased {
        Some(tol * (1.0 + 1e-9))
    } else {
        None
    }
}

/// The error of code `v` against the exact `e` (codes): 0 where both are
/// saturated on the same side, where every code plays the same amplitude.
fn error(t: &TileCtx<'_, '_>, v: f64, e: f64) -> f64 {
    let sat = t.sat;
    if (e >= sat.hi && v >= sat.hi) || (e <= sat.lo && v <= sat.lo) { 0.0 } else { (v - e).abs() }
}

/// The fine tile that plays a tile better than its stored samples `plain`
/// (biased codes), `None` where those are within the tolerance at every
/// point of the finest lattice or no refinement is better. `scratch` is a
/// [`Near`] of the layer's slots, overwritten.
///
/// Where the edges of two or more parts (the fills, a cut band, an
/// occluder, a clip) come within a cell of the tile's samples, the tile is
/// played in two channels where one passes: one part's distance, and the
/// lesser of the others'. Each is the distance to smooth edges, which
/// interpolates well, and their lesser has the crease exactly where the
/// drawing has it, however thin the wedge. Elsewhere, or where no pair
/// passes, one channel at the coarsest refinement that passes.
pub(super) fn refine(t: &TileCtx<'_, '_>, scratch: &mut Near, plain: &[u8; TILE_SAMPLES]) -> Option<Fine> {
    let tol = FINE_TOLERANCE_MM / t.step;
    let err = |v: f64, e: f64| error(t, v, e);
    let plain_code = |u: f64, w: f64| interpolate(plain, 1, u, w);
    let creased = t.measured.edges_within(t.h) >= 2;
    let m = finest(t, scratch);
    let finest = FINEST;
    // The largest error at the finest lattice's points of `play` (stops
    // early past the tolerance, where only passing matters).
    let worst = |play: &dyn Fn(f64, f64) -> f64, stop: bool| {
        let mut worst = 0.0f64;
        for y in 0..SIDE {
            for x in 0..SIDE {
                let (u, w) = (x as f64 / finest as f64, y as f64 / finest as f64);
                worst = worst.max(err(play(u, w), m.exact[y * SIDE + x]));
                if stop && worst > tol {
                    return worst;
                }
            }
        }
        worst
    };
    // The best candidate yet that misses the tolerance: its error, refinement
    // and samples (`None` samples: the tile's own). The tile's own samples
    // first: within the tolerance at every fine point, they stay.
    let plain_error = worst(&plain_code, false);
    if plain_error <= tol {
        return None;
    }
    let mut best: (f64, Option<Fine>) = (plain_error, None);
    if creased {
        // The parts' terms that decide the distance somewhere near the edge,
        // most points first: each tried as the first channel, at each
        // refinement up to 4 (two channels 8 times finer would take
        // 10 kB for a tile).
        for lone in m.deciding() {
            let (a, b) = m.channels(lone);
            for fine in PAIR_LEVELS {
                let (ca, cb) = (sub_samples(&a, fine), sub_samples(&b, fine));
                let play = |u: f64, w: f64| interpolate(&ca, fine, u, w).min(interpolate(&cb, fine, u, w));
                let e = worst(&play, best.0 <= tol);
                if e < best.0 {
                    let mut samples = ca;
                    samples.extend(cb);
                    best = (e, Some(Fine { fine: fine as u32, pair: true, samples }));
                }
                if e <= tol {
                    return best.1;
                }
            }
        }
    }
    // One channel: the coarsest refinement within the tolerance, else the
    // best of every candidate, if better than the tile's own samples.
    let codes = m.codes();
    for fine in ONE_LEVELS.into_iter().skip(1) {
        let level = sub_samples(&codes, fine);
        let e = worst(&|u: f64, w: f64| interpolate(&level, fine, u, w), false);
        if e < best.0 {
            best = (e, Some(Fine { fine: fine as u32, pair: false, samples: level }));
        }
        if e <= tol {
            break;
        }
    }
    best.1
}

/// A tile measured on its finest lattice (`SIDE` x `SIDE` points, row-major):
/// the exact distance and each term of it, in codes clamped to the cap.
struct Measured {
    exact: Vec<f64>,
    /// `terms` values per point, point-major.
    terms: Vec<f64>,
    n: usize,
    cap: f64,
}

impl Measured {
    /// The biased code of a distance in codes, as a stored tile holds it.
    fn code(v: f64) -> u8 {
        (v.round().clamp(-128.0, 127.0) as i32 + DISTANCE_ZERO as i32) as u8
    }

    /// The exact distance's codes.
    fn codes(&self) -> Vec<u8> {
        self.exact.iter().map(|&v| Self::code(v)).collect()
    }

    /// The terms that are the least (the distance) at some point within
    /// the clamp, where another term is within the clamp too, the one that
    /// is at the most points first.
    fn deciding(&self) -> Vec<usize> {
        let mut count = vec![0usize; self.n];
        for (k, ts) in self.terms.chunks_exact(self.n.max(1)).enumerate() {
            let e = self.exact.get(k).copied().unwrap_or(0.0);
            if e.abs() >= self.cap {
                continue;
            }
            let within = ts.iter().filter(|v| v.abs() < self.cap).count();
            if within < 2 {
                continue;
            }
            if let Some(c) = ts.iter().position(|&v| v == e).and_then(|i| count.get_mut(i)) {
                *c += 1;
            }
        }
        let mut order: Vec<(usize, usize)> = count.into_iter().enumerate().filter(|&(_, c)| c > 0).collect();
        order.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        order.into_iter().map(|(i, _)| i).collect()
    }

    /// The two channels' codes: term `lone`, and the least of the others.
    fn channels(&self, lone: usize) -> (Vec<u8>, Vec<u8>) {
        let n = self.n.max(1);
        let clamp = |v: f64| v.clamp(-self.cap, self.cap);
        let a = self.terms.chunks_exact(n).map(|ts| Self::code(clamp(ts.get(lone).copied().unwrap_or(self.cap))));
        let b = self.terms.chunks_exact(n).map(|ts| {
            let rest = ts.iter().enumerate().filter(|&(i, _)| i != lone).map(|(_, &v)| v);
            Self::code(clamp(rest.fold(f64::INFINITY, f64::min)))
        });
        (a.collect(), b.collect())
    }
}

/// The exact distance and its terms at every point of the tile's finest
/// lattice, measured [`SPAN`] lattice cells square at a time (their fine
/// points as one 9 x 9 sample set, `h / FINEST` apart).
fn finest(t: &TileCtx<'_, '_>, near: &mut Near) -> Measured {
    let finest = TILE_CELLS;
    let hf = t.h / FINEST as f64;
    let (inside, occluded, clips) = t.fine_rows.get_or_init(t.rows_of).bits(t.g, t.row, t.corner, hf, SIDE);
    let mut in_clip = vec![false; clips.len()];
    let step = t.step;
    let mut terms_here: Vec<f64> = Vec::new();
    let mut m = Measured { exact: vec![0.0; SIDE * SIDE], terms: Vec::new(), n: 0, cap: t.cap };
    let mut cell_bucket: Vec<u32> = Vec::new();
    let mut nearest_bound: Vec<(super::Part, f64)> = Vec::new();
    let span = SPAN as f64 * t.h;
    for b in 0..FINEST {
        for a in 0..FINEST {
            let corner = (t.corner.0 + a as f64 * span, t.corner.1 + b as f64 * span);
            // The tile's segments that act on these cells: within their
            // reach plus the margin of their box.
            cell_bucket.clear();
            cell_bucket.extend(t.bucket.iter().copied().filter(|&n| {
                t.segs.get(n as usize).is_some_and(|&((p, q), _, reach)| {
                    let m = reach + t.margin;
                    p.0.max(q.0) >= corner.0 - m
                        && p.0.min(q.0) <= corner.0 + span + m
                        && p.1.max(q.1) >= corner.1 - m
                        && p.1.min(q.1) <= corner.1 + span + m
                })
            }));
            prune(t.segs, &mut cell_bucket, corner, span, &mut nearest_bound);
            near.measure_swept(t.segs, &cell_bucket, (corner, hf, t.margin));
            for j in 0..TILE_SIDE {
                for i in 0..TILE_SIDE {
                    let (x, y) = (finest * a + i, finest * b + j);
                    let k = y * SIDE + x;
                    for (slot, c) in in_clip.iter_mut().zip(&clips) {
                        *slot = c.get(k).copied().unwrap_or(false);
                    }
                    let bits = (inside.get(k).copied().unwrap_or(false), occluded.get(k).copied().unwrap_or(false));
                    let p = (t.corner.0 + x as f64 * hf, t.corner.1 + y as f64 * hf);
                    terms_here.clear();
                    terms_here.extend(near.terms(t.g, j * TILE_SIDE + i, bits, &in_clip, p, t.page));
                    if m.n == 0 {
                        m.n = terms_here.len();
                        m.terms = vec![0.0; m.n * SIDE * SIDE];
                    }
                    let s = terms_here.iter().fold(f64::INFINITY, |a, &b| a.min(b));
                    if let Some(slot) = m.exact.get_mut(k) {
                        *slot = (s / step).clamp(-t.cap, t.cap);
                    }
                    for (slot, v) in m.terms.iter_mut().skip(k * m.n).zip(&terms_here) {
                        *slot = v / step;
                    }
                }
            }
        }
    }
    m
}
/// Keeps of `bucket` the segments that may be the nearest of their part to
/// some point of the square `span` mm from `corner`: for each part, no point
/// of the square is farther from its nearest segment than the least, over
/// the part's segments, of the segment's farthest distance to the square's
/// corners (the distance to a segment is convex, so its greatest over the
/// square is at a corner), and a segment whose bounding box lies farther
/// than that from the square is nearest nowhere in it. In a dense map (a
/// thousand regions' outlines within a millimetre) this leaves a few dozen
/// of hundreds; every point's nearest of each part, which is all the fine
/// lattice's measure keeps, is among them. `bound` is scratch.
fn prune(
    segs: &[(super::Seg, super::Part, f64)],
    bucket: &mut Vec<u32>,
    corner: (f64, f64),
    span: f64,
    bound: &mut Vec<(super::Part, f64)>,
) {
    let corners =
        [corner, (corner.0 + span, corner.1), (corner.0, corner.1 + span), (corner.0 + span, corner.1 + span)];
    bound.clear();
    for &n in bucket.iter() {
        let Some(&((a, b), part, _)) = segs.get(n as usize) else { continue };
        let far = corners.iter().map(|&c| crate::geometry::distance_to_segment(c, a, b)).fold(0.0, f64::max);
        match bound.iter_mut().find(|(p, _)| *p == part) {
            Some((_, u)) => *u = u.min(far),
            None => bound.push((part, far)),
        }
    }
    bucket.retain(|&n| {
        let Some(&((a, b), part, _)) = segs.get(n as usize) else { return false };
        let gap_x = (a.0.min(b.0) - (corner.0 + span)).max(corner.0 - a.0.max(b.0)).max(0.0);
        let gap_y = (a.1.min(b.1) - (corner.1 + span)).max(corner.1 - a.1.max(b.1)).max(0.0);
        let u = bound.iter().find(|(p, _)| *p == part).map_or(f64::INFINITY, |&(_, u)| u);
        // (NaN coordinates keep the segment, as the sweep would measure it.)
        let gap = gap_x.hypot(gap_y);
        gap.is_nan() || gap <= u
    });
}

/// The stored tiles of one channel sampled `fine` times finer (1, 2, 4 or 8)
/// from the codes of its finest lattice: `fine²` tiles of 81 codes,
/// row-major, sub-tile `(a, b)`'s sample `(i, j)` the finest point
/// `(8 / fine) (8 a + i, 8 b + j)`.
fn sub_samples(codes: &[u8], fine: usize) -> Vec<u8> {
    let stride = FINEST / fine;
    let mut out = Vec::with_capacity(fine * fine * TILE_SAMPLES);
    for b in 0..fine {
        for a in 0..fine {
            for j in 0..TILE_SIDE {
                for i in 0..TILE_SIDE {
                    let (x, y) = (stride * (TILE_CELLS * a + i), stride * (TILE_CELLS * b + j));
                    out.push(codes.get(y * SIDE + x).copied().unwrap_or(DISTANCE_ZERO));
                }
            }
        }
    }
    out
}

/// The code (unbiased) that `fine²` stored tiles `samples` (a tile sampled
/// `fine` times finer; 1: a stored tile) play at lattice coordinates
/// `(u, w)` in the tile, in f64, as SPEC.md section 6.2 interpolates.
fn interpolate(samples: &[u8], fine: usize, u: f64, w: f64) -> f64 {
    let f = fine as f64;
    let last = TILE_CELLS * fine - 1;
    let cell = |v: f64| {
        let c = ((v * f).max(0.0) as usize).min(last);
        (c / TILE_CELLS, c % TILE_CELLS, v * f - c as f64)
    };
    let ((a, i, wx), (b, j, wy)) = (cell(u), cell(w));
    let base = (b * fine + a) * TILE_SAMPLES;
    let s =
        |i: usize, j: usize| samples.get(base + j * TILE_SIDE + i).map_or(0.0, |&v| v as f64 - DISTANCE_ZERO as f64);
    let top = s(i, j) + (s(i + 1, j) - s(i, j)) * wx;
    let bot = s(i, j + 1) + (s(i + 1, j + 1) - s(i, j + 1)) * wx;
    top + (bot - top) * wy
}
