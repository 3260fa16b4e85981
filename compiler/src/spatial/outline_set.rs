//! Distances between outlines: [`min_outline_distance`] for one pair, and
//! [`OutlineSet`], many outlines prepared once for the distance between any
//! two (the inner loop of the gap rule).

use std::sync::OnceLock;

use rstar::{AABB, RTree, RTreeObject};

use super::{Bbox, envelope, grow, meet};
use crate::geometry::Polyline;

/// Squared distance from `p` to the segment `a`-`b`.
fn point_segment2(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 { (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0) } else { 0.0 };
    let (ex, ey) = (a.0 + t * dx - p.0, a.1 + t * dy - p.1);
    ex * ex + ey * ey
}

/// The distance between two segments (0 when they cross), as
/// [`crate::geometry::segment_distance`] gives it, but through squared
/// distances and one square root: this is the inner loop of every gap.
pub(super) fn segment_distance(a0: (f64, f64), a1: (f64, f64), b0: (f64, f64), b1: (f64, f64)) -> f64 {
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0);
    let (d1, d2) = (cross(a0, a1, b0), cross(a0, a1, b1));
    let (d3, d4) = (cross(b0, b1, a0), cross(b0, b1, a1));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0)) {
        return 0.0;
    }
    point_segment2(a0, b0, b1)
        .min(point_segment2(a1, b0, b1))
        .min(point_segment2(b0, a0, a1))
        .min(point_segment2(b1, a0, a1))
        .sqrt()
}

fn seg_box(s: ((f64, f64), (f64, f64))) -> Bbox {
    let ((x0, y0), (x1, y1)) = s;
    (x0.min(x1), y0.min(y1), x0.max(x1), y0.max(y1))
}

/// The smallest distance between the outlines `a` and `b` (every segment of
/// every subpath, closing segments included) when it is at most `reach`;
/// otherwise some value above `reach` (infinite when nothing is that close).
///
/// Stops as soon as it finds a distance at or below `stop_at` (outlines that
/// touch or cross need no more work). Only segments within `reach` of the
/// other outline's box are looked at, and when many are, the larger side is
/// put in an R*-tree, so two long borders cost O(n log n), not O(n²).
pub fn min_outline_distance(a: &[Polyline], b: &[Polyline], reach: f64, stop_at: f64) -> f64 {
    let (Some(ba), Some(bb)) = (crate::geometry::bounds(a), crate::geometry::bounds(b)) else {
        return f64::INFINITY;
    };
    let near = |polys: &[Polyline], other: Bbox| -> Vec<((f64, f64), (f64, f64))> {
        let g = grow(other, reach);
        polys.iter().flat_map(|p| p.segments()).filter(|&s| meet(seg_box(s), g)).collect()
    };
    let (sa, sb) = (near(a, bb), near(b, ba));
    let (small, large) = if sa.len() <= sb.len() { (sa, sb) } else { (sb, sa) };
    let mut best = f64::INFINITY;
    if small.len().saturating_mul(large.len()) <= 4096 {
        for &(p0, p1) in &small {
            for &(q0, q1) in &large {
                best = best.min(segment_distance(p0, p1, q0, q1));
                if best <= stop_at {
                    return best;
                }
            }
        }
        return best;
    }
    let large: Vec<Seg> = large.into_iter().map(|(a, b)| Seg { a, b }).collect();
    let tree = RTree::bulk_load(runs(&large));
    for &(p0, p1) in &small {
        let r = best.min(reach);
        let q = grow(seg_box((p0, p1)), r);
        for run in tree.locate_in_envelope_intersecting(&envelope(q)) {
            let (a, n) = (run.first as usize, run.len as usize);
            for t in large.get(a..a + n).into_iter().flatten().filter(|t| meet(t.bbox(), q)) {
                best = best.min(segment_distance(p0, p1, t.a, t.b));
                if best <= stop_at {
                    return best;
                }
            }
        }
    }
    best
}

/// Squared distance between two boxes (0 when they meet).
fn box_distance2(a: Bbox, b: Bbox) -> f64 {
    let dx = (b.0 - a.2).max(a.0 - b.2).max(0.0);
    let dy = (b.1 - a.3).max(a.1 - b.3).max(0.0);
    dx * dx + dy * dy
}

/// One segment of a prepared outline. Its box is worked out when needed
/// rather than stored: a dense drawing's gap rule reads the segments of
/// hundreds of neighbours per feature, and at half the size (32 bytes, not
/// 64) twice as many stay in the cache.
#[derive(Debug, Clone, Copy)]
pub(super) struct Seg {
    a: (f64, f64),
    b: (f64, f64),
}

impl Seg {
    fn bbox(&self) -> Bbox {
        seg_box((self.a, self.b))
    }
}

/// A run of up to [`TREE_RUN`] consecutive segments of one outline in an
/// R*-tree, with the box of the run worked out once: bulk loading asks for
/// an item's envelope at every comparison of its partitioning, and an
/// outline of millions of segments (a curve-heavy path far larger than the
/// page) spent most of its build recomputing them.
///
/// The tree holds runs, not segments: consecutive segments of an outline lie
/// side by side, so a run's box is hardly larger than its segments' and the
/// tree is a run's length times smaller. Building the trees of a map of
/// 1,200 states with detailed borders was a quarter of the gap rule's time
/// when each segment was an item.
#[derive(Debug, Clone, Copy)]
struct TreeRun {
    /// The run is `segments(k)[first..first + len]`.
    first: u32,
    len: u32,
    env: AABB<[f64; 2]>,
}

impl RTreeObject for TreeRun {
    type Envelope = AABB<[f64; 2]>;
    fn envelope(&self) -> Self::Envelope {
        self.env
    }
}

/// Consecutive segments per item of an outline's R*-tree ([`TreeRun`]).
const TREE_RUN: usize = 8;

/// The runs of [`TREE_RUN`] consecutive segments of `segs`, each with its box.
fn runs(segs: &[Seg]) -> Vec<TreeRun> {
    segs.chunks(TREE_RUN)
        .enumerate()
        .filter_map(|(k, run)| {
            let b =
                run.iter().map(Seg::bbox).reduce(|p, b| (p.0.min(b.0), p.1.min(b.1), p.2.max(b.2), p.3.max(b.3)))?;
            Some(TreeRun { first: u32::try_from(k * TREE_RUN).ok()?, len: run.len() as u32, env: envelope(b) })
        })
        .collect()
}

/// Outlines with more segments than this get their own R*-tree, so that two
/// long borders cost O(n log n) instead of O(n²) segment pairs.
pub(super) const TREE_ABOVE: usize = 64;

/// Many outlines prepared once for [`OutlineSet::distance`] between any two:
/// each one's segments, its box, and for long outlines an R*-tree of their
/// segments. [`min_outline_distance`] prepares both outlines on every call
/// (collecting their segments, measuring their boxes, building a tree),
/// which dominated the gap rule when a dense drawing gives each element
/// hundreds of candidate neighbours.
///
/// The segments may be laid out in memory in another order than the
/// outlines' positions ([`OutlineSet::in_order`]): measuring a feature
/// against its neighbours reads theirs, and when neighbours on the page are
/// neighbours in memory those reads hit the cache.
#[derive(Debug)]
pub struct OutlineSet {
    segs: Vec<Seg>,
    /// Outline `k`'s segments are `segs[span[k].0..span[k].1]`.
    span: Vec<(usize, usize)>,
    bounds: Vec<Option<Bbox>>,
    /// The R*-tree of each outline of more than [`TREE_ABOVE`] segments,
    /// built the first time a distance searches it: most outlines never
    /// are (two neighbours' near parts are mostly short enough to scan), and
    /// building every tree up front was a twentieth of the build of a map
    /// of 1,200 states with detailed borders (issue 46).
    trees: Vec<OnceLock<RTree<TreeRun>>>,
}

impl OutlineSet {
    /// Prepares `outlines` (every segment of every subpath, closing segments
    /// included, as [`min_outline_distance`] measures them).
    pub fn new<'a>(outlines: impl IntoIterator<Item = &'a [Polyline]>) -> Self {
        let outlines: Vec<&[Polyline]> = outlines.into_iter().collect();
        Self::in_order(&outlines, 0..outlines.len())
    }

    /// Prepares `outlines` as [`OutlineSet::new`] does, their segments laid
    /// out in memory in `order` (positions into `outlines`; a position left
    /// out, repeated or out of range is laid out once, after the others, or
    /// skipped). Distances do not depend on the order, only how fast they
    /// are measured.
    pub fn in_order(outlines: &[&[Polyline]], order: impl IntoIterator<Item = usize>) -> Self {
        let n = outlines.len();
        let mut set = OutlineSet {
            segs: Vec::with_capacity(
                outlines.iter().map(|o| o.iter().map(|p| p.points.len() + 1).sum::<usize>()).sum(),
            ),
            span: vec![(0, 0); n],
            bounds: outlines.iter().map(|o| crate::geometry::bounds(o)).collect(),
            trees: (0..n).map(|_| OnceLock::new()).collect(),
        };
        let mut placed = vec![false; n];
        let order: Vec<usize> = order.into_iter().filter(|&k| k < n).collect();
        for k in order.into_iter().chain(0..n) {
            if std::mem::replace(&mut placed[k], true) {
                continue;
            }
            let first = set.segs.len();
            set.segs.extend(outlines[k].iter().flat_map(|p| p.segments()).map(|(a, b)| Seg { a, b }));
            set.span[k] = (first, set.segs.len());
        }
        set
    }

    /// Whether outline `k` has a tree (more than [`TREE_ABOVE`] segments).
    fn has_tree(&self, k: usize) -> bool {
        let (a, b) = self.span[k];
        b - a > TREE_ABOVE
    }

    /// Which outlines' trees have been built (the tests look).
    #[cfg(test)]
    pub(super) fn trees_built(&self) -> Vec<bool> {
        self.trees.iter().map(|t| t.get().is_some()).collect()
    }

    /// Outline `k`'s tree of runs, built on first use.
    fn tree(&self, k: usize) -> &RTree<TreeRun> {
        self.trees[k].get_or_init(|| RTree::bulk_load(runs(self.segments(k))))
    }

    /// How many outlines were prepared.
    pub fn len(&self) -> usize {
        self.bounds.len()
    }

    /// Whether no outline was prepared.
    pub fn is_empty(&self) -> bool {
        self.bounds.is_empty()
    }

    pub(super) fn segments(&self, k: usize) -> &[Seg] {
        let (a, b) = self.span[k];
        &self.segs[a..b]
    }

    /// [`min_outline_distance`] between outlines `i` and `j`: the smallest
    /// distance between them when it is at most `reach`, otherwise some value
    /// above `reach`; some value at or below `stop_at` as soon as one is found.
    /// Out-of-range positions are as far as can be (infinite).
    pub fn distance(&self, i: usize, j: usize, reach: f64, stop_at: f64) -> f64 {
        let (Some(&Some(bi)), Some(&Some(bj))) = (self.bounds.get(i), self.bounds.get(j)) else {
            return f64::INFINITY;
        };
        // Outlines within `stop_at` at their first points need no search:
        // a vibrating band 1.5 mm wide meets its neighbours' bands from
        // the first points on, and finding the nearest segments first cost
        // a pass over both outlines for each of its hundreds of neighbours.
        if let (Some(s), Some(t)) = (self.segments(i).first(), self.segments(j).first()) {
            let (dx, dy) = (s.a.0 - t.a.0, s.a.1 - t.a.1);
            let d = (dx * dx + dy * dy).sqrt();
            if d <= stop_at {
                return d;
            }
        }
        let (gi, gj) = (grow(bj, reach), grow(bi, reach));
        let near = |k: usize, g: Bbox| self.segments(k).iter().filter(move |s| meet(s.bbox(), g));
        let mut best = f64::INFINITY;
        if !self.has_tree(i) && !self.has_tree(j) {
            return self.short_distance(i, gi, j, reach, stop_at);
        }
        // A short outline beside a long one (an island beside a coast, a
        // map's frame beside every region) is walked, and the long one
        // searched through its tree: counting the long one's segments near
        // the short one's box read all of them for each of its neighbours.
        // Otherwise the side with fewer segments near the other's box is
        // walked, and the other searched, through its tree when it has one.
        let (walk, wg, other, og, tree) = match (self.has_tree(i), self.has_tree(j)) {
            (true, false) => (j, gj, i, gi, true),
            (false, true) => (i, gi, j, gj, true),
            _ => {
                let (ni, nj) = (near(i, gi).count(), near(j, gj).count());
                let (walk, wg, other, og) = if ni <= nj { (i, gi, j, gj) } else { (j, gj, i, gi) };
                (walk, wg, other, og, ni.min(nj).saturating_mul(ni.max(nj)) > 4096)
            }
        };
        if tree {
            let (tree, segs) = (self.tree(other), self.segments(other));
            for s in near(walk, wg) {
                let r = best.min(reach);
                let q = grow(s.bbox(), r);
                for run in tree.locate_in_envelope_intersecting(&envelope(q)) {
                    let (a, n) = (run.first as usize, run.len as usize);
                    // The segments of the run whose own boxes meet the
                    // query: the pairs a tree of segments would give.
                    for t in segs.get(a..a + n).into_iter().flatten().filter(|t| meet(t.bbox(), q)) {
                        best = best.min(segment_distance(s.a, s.b, t.a, t.b));
                        if best <= stop_at {
                            return best;
                        }
                    }
                }
            }
        } else {
            best = scan_pairs(near(walk, wg), || near(other, og), best, reach, stop_at);
        }
        best
    }
}

impl OutlineSet {
    /// [`OutlineSet::distance`] between two short outlines (a street, a
    /// small region; neither has a tree, so each has at most [`TREE_ABOVE`]
    /// segments): every pair of a segment of `i` near `j`'s box (`gi`, grown
    /// by the reach) and a segment of `j` near the box of those, skipping
    /// pairs whose boxes are farther apart than the best so far (or the
    /// reach). Narrowing `j`'s side to what is near `i`'s near part, not to
    /// all of `i`'s box, matters for long ways that cross or pass each other
    /// at one place: a dense plan's way has hundreds of such neighbours, and
    /// scanning all of `j` for each near segment of `i` was most of the gap
    /// rule's time.
    fn short_distance(&self, i: usize, gi: Bbox, j: usize, reach: f64, stop_at: f64) -> f64 {
        let (si, sj) = (self.segments(i), self.segments(j));
        // Positions within the outline and the boxes of the segments near
        // the other side; a short outline has at most `TREE_ABOVE`
        // segments, so they fit in a byte and on the stack. The boxes are
        // worked out once here: the pair scans below check every box of
        // `j`'s side once per segment of `i`'s, and working them out there
        // again was most of the gap rule's time on the map at the input
        // limit.
        let mut ki = [0u8; TREE_ABOVE];
        let mut bi = [(0.0, 0.0, 0.0, 0.0); TREE_ABOVE];
        let mut ni = 0;
        let mut part: Option<Bbox> = None;
        for (k, s) in si.iter().enumerate().take(TREE_ABOVE) {
            let b = s.bbox();
            if meet(b, gi) {
                ki[ni] = k as u8;
                bi[ni] = b;
                ni += 1;
                part = Some(part.map_or(b, |p| (p.0.min(b.0), p.1.min(b.1), p.2.max(b.2), p.3.max(b.3))));
            }
        }
        let Some(part) = part else { return f64::INFINITY };
        let gj = grow(part, reach);
        let mut kj = [0u8; TREE_ABOVE];
        let mut bj = [(0.0, 0.0, 0.0, 0.0); TREE_ABOVE];
        let mut nj = 0;
        for (k, t) in sj.iter().enumerate().take(TREE_ABOVE) {
            let b = t.bbox();
            if meet(b, gj) {
                kj[nj] = k as u8;
                bj[nj] = b;
                nj += 1;
            }
        }
        let side_i = Side { segs: si, at: &ki[..ni], boxes: &bi[..ni] };
        let side_j = Side { segs: sj, at: &kj[..nj], boxes: &bj[..nj] };
        if ni * nj < RUNS_FROM {
            return scan_sides(side_i, side_j, f64::INFINITY, reach, stop_at);
        }
        // Two regions of a map, each of some 64 sides: the box checks of
        // every segment pair (4,096) were most of the time of a pair that
        // does not come within the reach. Runs of `RUN` near segments,
        // each with its box, turn most of them away in one check; a run's
        // box holds its segments' boxes, so a pair skipped with its run
        // would have been skipped alone (the same grown-box check).
        let run_box =
            |bs: &[Bbox]| bs.iter().copied().reduce(|p, b| (p.0.min(b.0), p.1.min(b.1), p.2.max(b.2), p.3.max(b.3)));
        // `j`'s run boxes once, not once per run of `i` (at most
        // `TREE_ABOVE / RUN` of them, on the stack).
        let mut runs_j = [(0.0, 0.0, 0.0, 0.0); TREE_ABOVE.div_ceil(RUN)];
        for (rj, boxes_j) in runs_j.iter_mut().zip(side_j.boxes.chunks(RUN)) {
            *rj = run_box(boxes_j).unwrap_or(*rj);
        }
        let mut best = f64::INFINITY;
        for (run_i, boxes_i) in side_i.at.chunks(RUN).zip(side_i.boxes.chunks(RUN)) {
            let Some(ri) = run_box(boxes_i) else { continue };
            for ((run_j, boxes_j), &rj) in side_j.at.chunks(RUN).zip(side_j.boxes.chunks(RUN)).zip(&runs_j) {
                let r = best.min(reach);
                if !meet(rj, grow(ri, r + r * 1e-9)) {
                    continue;
                }
                best = scan_sides(
                    Side { segs: si, at: run_i, boxes: boxes_i },
                    Side { segs: sj, at: run_j, boxes: boxes_j },
                    best,
                    reach,
                    stop_at,
                );
                if best <= stop_at {
                    return best;
                }
            }
        }
        best
    }
}

/// Some segments of a short outline (`segs[at[k]]`, each with its box
/// `boxes[k]`) for [`scan_sides`].
#[derive(Clone, Copy)]
struct Side<'a> {
    segs: &'a [Seg],
    at: &'a [u8],
    boxes: &'a [Bbox],
}

/// [`scan_pairs`] between two sides whose boxes are worked out: the same
/// pairs in the same order, so the same distance to the bit.
fn scan_sides(ss: Side<'_>, ts: Side<'_>, mut best: f64, reach: f64, stop_at: f64) -> f64 {
    for (&k, &sb) in ss.at.iter().zip(ss.boxes) {
        let Some(s) = ss.segs.get(usize::from(k)) else { continue };
        let r = best.min(reach);
        let grown = grow(sb, r + r * 1e-9);
        for (&l, &tb) in ts.at.iter().zip(ts.boxes) {
            if !meet(tb, grown) {
                continue;
            }
            let r = best.min(reach);
            if box_distance2(sb, tb) > r * r {
                continue;
            }
            let Some(t) = ts.segs.get(usize::from(l)) else { continue };
            best = best.min(segment_distance(s.a, s.b, t.a, t.b));
            if best <= stop_at {
                return best;
            }
        }
    }
    best
}

/// Segment pairs of two short outlines from which [`OutlineSet::short_distance`]
/// checks runs of segments before the segments (below it, runs cost more
/// than they save: a city plan's short ways).
pub(super) const RUNS_FROM: usize = 256;

/// Segments per run in [`OutlineSet::short_distance`].
const RUN: usize = 8;

/// The smallest distance between a segment of `ss` and one of `ts()`, down
/// from `best`, skipping pairs whose boxes lie farther apart than the best so
/// far (or `reach`); some value at or below `stop_at` as soon as one is found.
fn scan_pairs<'s, T: Iterator<Item = &'s Seg>>(
    ss: impl Iterator<Item = &'s Seg>,
    ts: impl Fn() -> T,
    mut best: f64,
    reach: f64,
    stop_at: f64,
) -> f64 {
    for s in ss {
        let sb = s.bbox();
        // Most pairs are far apart on one axis: a box grown once per segment
        // (by the reach now, which only shrinks, and a hair more so that
        // rounding never drops a pair the exact test would keep) turns them
        // away with four comparisons.
        let r = best.min(reach);
        let grown = grow(sb, r + r * 1e-9);
        for t in ts() {
            let tb = t.bbox();
            if !meet(tb, grown) {
                continue;
            }
            let r = best.min(reach);
            if box_distance2(sb, tb) > r * r {
                continue;
            }
            best = best.min(segment_distance(s.a, s.b, t.a, t.b));
            if best <= stop_at {
                return best;
            }
        }
    }
    best
}
