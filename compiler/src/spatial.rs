//! Shared service: spatial indexes.
//!
//! Spatial indexes (R*-trees from `rstar`) for every pass that relates
//! elements to their neighbours: the design rules' gaps and overlaps, and the
//! automatic style sheet's region adjacency. Each finds the pairs of boxes
//! that come within a distance in O(n log n + pairs), never by looking at all
//! n² pairs, which is what made a 10,000-element map take minutes.

use rstar::{AABB, RStarInsertionStrategy, RTree, RTreeObject, RTreeParams};

use crate::geometry::Polyline;

/// An axis-aligned box `(x0, y0, x1, y1)` in page mm.
pub type Bbox = (f64, f64, f64, f64);

/// Whether a box is finite and not inverted (usable as an index entry).
fn usable(b: Bbox) -> bool {
    b.0.is_finite() && b.1.is_finite() && b.2.is_finite() && b.3.is_finite() && b.0 <= b.2 && b.1 <= b.3
}

/// `b` grown by `m` on every side.
pub fn grow(b: Bbox, m: f64) -> Bbox {
    (b.0 - m, b.1 - m, b.2 + m, b.3 + m)
}

/// Whether two boxes meet (touching edges count).
pub fn meet(a: Bbox, b: Bbox) -> bool {
    a.0 <= b.2 && b.0 <= a.2 && a.1 <= b.3 && b.1 <= a.3
}

/// The distance between two boxes (0 when they meet): a lower bound on the
/// distance between anything the two contain.
pub fn box_distance(a: Bbox, b: Bbox) -> f64 {
    let dx = (b.0 - a.2).max(a.0 - b.2).max(0.0);
    let dy = (b.1 - a.3).max(a.1 - b.3).max(0.0);
    (dx * dx + dy * dy).sqrt()
}

fn envelope(b: Bbox) -> AABB<[f64; 2]> {
    AABB::from_corners([b.0, b.1], [b.2, b.3])
}

/// One indexed box and the position of what it bounds.
#[derive(Debug, Clone, Copy)]
struct Entry {
    index: usize,
    bbox: Bbox,
}

impl RTreeObject for Entry {
    type Envelope = AABB<[f64; 2]>;
    fn envelope(&self) -> Self::Envelope {
        envelope(self.bbox)
    }
}

/// An index of boxes, each standing for the item at its position in the
/// slice it was built from.
#[derive(Debug)]
pub struct BoxIndex {
    tree: RTree<Entry, Wide>,
}

/// R*-tree nodes of up to 16 children instead of rstar's default 6: a
/// [`BoxIndex`] is built once and then asked for hundreds of boxes at a
/// time (a dense plan's way meets that many), and wider nodes make the tree
/// shallower, so a query visits fewer nodes for what it finds.
#[derive(Debug)]
struct Wide;

impl RTreeParams for Wide {
    const MIN_SIZE: usize = 6;
    const MAX_SIZE: usize = 16;
    const REINSERTION_COUNT: usize = 4;
    type DefaultInsertionStrategy = RStarInsertionStrategy;
}

impl BoxIndex {
    /// Indexes `boxes`; boxes with non-finite or inverted corners are left out
    /// (they can be near nothing).
    pub fn new(boxes: &[Bbox]) -> Self {
        let entries: Vec<Entry> =
            boxes.iter().enumerate().filter(|(_, b)| usable(**b)).map(|(index, &bbox)| Entry { index, bbox }).collect();
        BoxIndex { tree: RTree::bulk_load_with_params(entries) }
    }

    /// Positions of the boxes that meet `query`, in no particular order.
    pub fn meeting(&self, query: Bbox) -> impl Iterator<Item = usize> + '_ {
        let q = usable(query).then(|| envelope(query));
        q.into_iter().flat_map(move |q| self.tree.locate_in_envelope_intersecting(&q).map(|e| e.index))
    }

    /// Positions and boxes of the boxes that meet `query`, in no particular
    /// order (the boxes come from the index, so callers need not look them up).
    pub fn meeting_boxes(&self, query: Bbox) -> impl Iterator<Item = (usize, Bbox)> + '_ {
        let q = usable(query).then(|| envelope(query));
        q.into_iter().flat_map(move |q| self.tree.locate_in_envelope_intersecting(&q).map(|e| (e.index, e.bbox)))
    }
}

/// Boxes placed one at a time, each refused when it would meet one already
/// placed (braille labels that must not run into each other).
#[derive(Debug, Default)]
pub struct Occupancy {
    tree: RTree<Entry>,
}

impl Occupancy {
    /// Places `b` unless it meets a placed box; returns whether it was placed.
    /// A box with non-finite or inverted corners is never placed.
    pub fn place(&mut self, b: Bbox) -> bool {
        if !usable(b) || self.tree.locate_in_envelope_intersecting(&envelope(b)).next().is_some() {
            return false;
        }
        let index = self.tree.size();
        self.tree.insert(Entry { index, bbox: b });
        true
    }

    /// Whether `b` meets no placed box.
    pub fn is_free(&self, b: Bbox) -> bool {
        usable(b) && self.tree.locate_in_envelope_intersecting(&envelope(b)).next().is_none()
    }
}

/// Every pair `(i, j)`, `i < j`, of `boxes` that come within `margin` of each
/// other (their boxes grown by `margin` meet), sorted.
///
/// ```
/// use taxel_compiler::spatial::near_pairs;
///
/// let boxes = [(0.0, 0.0, 1.0, 1.0), (1.5, 0.0, 2.0, 1.0), (9.0, 9.0, 10.0, 10.0)];
/// assert_eq!(near_pairs(&boxes, 0.5), vec![(0, 1)]);
/// assert_eq!(near_pairs(&boxes, 0.1), vec![]);
/// ```
pub fn near_pairs(boxes: &[Bbox], margin: f64) -> Vec<(usize, usize)> {
    let index = BoxIndex::new(boxes);
    let mut out = Vec::new();
    for (i, &b) in boxes.iter().enumerate() {
        out.extend(index.meeting(grow(b, margin)).filter(|&j| j > i).map(|j| (i, j)));
    }
    out.sort_unstable();
    out
}

/// Positions of `boxes` in the order a Hilbert curve visits their centres:
/// boxes near each other on the page come near each other in the order.
/// Passes that visit every item and its neighbours go this way so that the
/// neighbours' data is still in the cache from the item before (in document
/// order a city plan's next way is anywhere on the page). Boxes with
/// non-finite or inverted corners come last; equal keys keep their
/// positions' order, so the order depends on the boxes alone.
///
/// ```
/// use taxel_compiler::spatial::locality_order;
///
/// // Four boxes at the corners of a square and one at its centre.
/// let at = |x: f64, y: f64| (x, y, x + 1.0, y + 1.0);
/// let boxes = [at(0.0, 0.0), at(90.0, 90.0), at(0.0, 90.0), at(45.0, 45.0), at(90.0, 0.0)];
/// let order = locality_order(&boxes);
/// let mut sorted = order.clone();
/// sorted.sort();
/// assert_eq!(sorted, vec![0, 1, 2, 3, 4]);
/// // The curve goes from corner to neighbouring corner, never across a diagonal.
/// let corners: Vec<_> = order.iter().filter(|&&k| k != 3).map(|&k| boxes[k]).collect();
/// for w in corners.windows(2) {
///     assert!(w[0].0 == w[1].0 || w[0].1 == w[1].1, "{w:?}");
/// }
/// ```
pub fn locality_order(boxes: &[Bbox]) -> Vec<usize> {
    let centre = |b: Bbox| ((b.0 + b.2) / 2.0, (b.1 + b.3) / 2.0);
    let mut lo = (f64::INFINITY, f64::INFINITY);
    let mut hi = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    for &b in boxes.iter().filter(|b| usable(**b)) {
        let c = centre(b);
        lo = (lo.0.min(c.0), lo.1.min(c.1));
        hi = (hi.0.max(c.0), hi.1.max(c.1));
    }
    // One scale for both axes keeps the curve's cells square.
    let span = (hi.0 - lo.0).max(hi.1 - lo.1);
    let scale = if span > 0.0 && span.is_finite() { f64::from(HILBERT_SIDE - 1) / span } else { 0.0 };
    let key = |b: Bbox| -> u64 {
        if !usable(b) {
            return u64::MAX;
        }
        let c = centre(b);
        // In range by construction; the casts saturate should rounding stray.
        let cell = |v: f64, lo: f64| ((v - lo) * scale).round().clamp(0.0, f64::from(HILBERT_SIDE - 1)) as u32;
        hilbert(cell(c.0, lo.0), cell(c.1, lo.1))
    };
    let mut order: Vec<(u64, usize)> = boxes.iter().enumerate().map(|(k, &b)| (key(b), k)).collect();
    order.sort_unstable();
    order.into_iter().map(|(_, k)| k).collect()
}

/// Cells per side of the grid [`locality_order`] runs its curve over.
const HILBERT_SIDE: u32 = 1 << 16;

/// The distance along a Hilbert curve over a [`HILBERT_SIDE`]-square grid
/// of the cell `(x, y)` (both below [`HILBERT_SIDE`]).
fn hilbert(mut x: u32, mut y: u32) -> u64 {
    let mut d = 0u64;
    let mut s = HILBERT_SIDE / 2;
    while s > 0 {
        let rx = u32::from(x & s > 0);
        let ry = u32::from(y & s > 0);
        d += u64::from(s) * u64::from(s) * u64::from((3 * rx) ^ ry);
        // Rotate the quadrant so that the curve inside it runs the right way.
        if ry == 0 {
            if rx == 1 {
                x = HILBERT_SIDE - 1 - x;
                y = HILBERT_SIDE - 1 - y;
            }
            std::mem::swap(&mut x, &mut y);
        }
        s /= 2;
    }
    d
}

/// Which outlines share a vertex: the same point, to the bit, on both
/// (a map's neighbouring regions, drawn from one border's coordinates).
/// Outlines that share a vertex touch, their distance is exactly 0, and a
/// rule that only needs to know that need not measure them: on a map of
/// abutting regions almost every neighbouring pair is such a pair, and
/// settling each one by scanning its segments was most of the gap rule.
///
/// Only points on a segment count (a polyline of one point has none).
/// Points shared by more than [`SharedVertices::MAX_AT_ONE_POINT`] outlines
/// are left out (a star of lines through one point would otherwise list
/// every pair of them): for such pairs [`SharedVertices::share`] says
/// `false`, which only means "not known", so they are measured as before.
///
/// ```
/// use taxel_compiler::geometry::Polyline;
/// use taxel_compiler::spatial::SharedVertices;
///
/// let square = |x: f64| vec![Polyline { points: vec![(x, 0.0), (x + 1.0, 0.0), (x + 1.0, 1.0), (x, 1.0)], closed: true }];
/// let (a, b, c) = (square(0.0), square(1.0), square(3.0));
/// let shared = SharedVertices::new(&[a.as_slice(), b.as_slice(), c.as_slice()]);
/// assert!(shared.share(0, 1) && shared.share(1, 0));
/// assert!(!shared.share(0, 2) && !shared.share(1, 2) && !shared.share(0, 7));
/// ```
#[derive(Debug)]
pub struct SharedVertices {
    /// The outlines that share a vertex with outline `k` are
    /// `with[start[k]..start[k + 1]]`, ascending.
    start: Vec<usize>,
    with: Vec<usize>,
}

impl SharedVertices {
    /// Most outlines through one point for which the pairs are listed.
    pub const MAX_AT_ONE_POINT: usize = 16;

    /// Finds the outlines (positions in `outlines`) that share a vertex:
    /// O(v) in the vertices and the pairs found. Each distinct point gets a
    /// list of the distinct outlines through it (one hash look-up per
    /// vertex), then each outline collects the others on its points'
    /// lists. Sorting every vertex (and then every pair found, each
    /// neighbour once per shared vertex) came to 46 M instructions on a
    /// map of 1,000 regions of 64 vertices, a quarter of its design rules.
    pub fn new(outlines: &[&[Polyline]]) -> Self {
        use std::collections::HashMap;
        /// The end of a point's list of outlines.
        const END: u32 = u32::MAX;
        fn vertices(o: &[Polyline]) -> impl Iterator<Item = &(f64, f64)> {
            o.iter()
                .filter(|p| p.points.len() >= 2)
                .flat_map(|p| p.points.iter())
                .filter(|v| v.0.is_finite() && v.1.is_finite())
        }
        // -0.0 and 0.0 are one point; adding 0.0 makes both 0.0.
        let key = |v: &(f64, f64)| ((v.0 + 0.0).to_bits(), (v.1 + 0.0).to_bits());
        let counts: Vec<usize> = outlines.iter().map(|o| vertices(o).count()).collect();
        let total: usize = counts.iter().sum();
        // Positions and counts past u32 cannot be listed; such a drawing is
        // far beyond the input limit, and "not known" is always a right answer.
        if total >= END as usize || outlines.len() >= END as usize {
            return SharedVertices { start: vec![0; outlines.len() + 1], with: Vec::new() };
        }
        let mut point: HashMap<(u64, u64), u32, foldhash::fast::FixedState> =
            HashMap::with_capacity_and_hasher(total, Default::default());
        // Per point: the newest entry of its list and how many outlines it holds.
        let mut head: Vec<u32> = Vec::new();
        let mut count: Vec<u32> = Vec::new();
        // Per entry: its outline and the entry after it.
        let mut entry: Vec<(u32, u32)> = Vec::new();
        // Per vertex, in the order visited: its point.
        let mut point_of: Vec<u32> = Vec::with_capacity(total);
        for (k, o) in outlines.iter().enumerate() {
            let k = k as u32;
            for v in vertices(o) {
                let p = *point.entry(key(v)).or_insert_with(|| {
                    head.push(END);
                    count.push(0);
                    (head.len() - 1) as u32
                });
                point_of.push(p);
                let h = head[p as usize];
                // Outlines are visited in order, so an outline already on
                // this point's list is its newest entry.
                if h == END || entry[h as usize].0 != k {
                    entry.push((k, h));
                    head[p as usize] = (entry.len() - 1) as u32;
                    count[p as usize] += 1;
                }
            }
        }
        drop(point);
        let mut start = Vec::with_capacity(outlines.len() + 1);
        let mut with: Vec<usize> = Vec::new();
        // The outline whose list last took each outline.
        let mut taken_by: Vec<u32> = vec![END; outlines.len()];
        let mut at = point_of.iter();
        for (k, &n) in counts.iter().enumerate() {
            start.push(with.len());
            let first = with.len();
            for p in at.by_ref().take(n) {
                let n = count[*p as usize] as usize;
                if !(2..=Self::MAX_AT_ONE_POINT).contains(&n) {
                    continue;
                }
                let mut e = head[*p as usize];
                while e != END {
                    let (j, next) = entry[e as usize];
                    if j as usize != k && taken_by[j as usize] != k as u32 {
                        taken_by[j as usize] = k as u32;
                        with.push(j as usize);
                    }
                    e = next;
                }
            }
            with[first..].sort_unstable();
        }
        start.push(with.len());
        let shared = SharedVertices { start, with };
        debug_assert!(shared.sanity_check(), "shared vertices: lists not ascending or not symmetric");
        shared
    }

    /// Whether outlines `i` and `j` share a vertex (false for positions out
    /// of range, and for pairs through a point of too many outlines).
    pub fn share(&self, i: usize, j: usize) -> bool {
        match (self.start.get(i), self.start.get(i + 1)) {
            (Some(&a), Some(&b)) => self.with[a..b].binary_search(&j).is_ok(),
            _ => false,
        }
    }

    /// The invariants: each list ascending without repeats and without
    /// its own outline, and every pair listed from both sides.
    fn sanity_check(&self) -> bool {
        (0..self.start.len().saturating_sub(1)).all(|k| {
            let list = &self.with[self.start[k]..self.start[k + 1]];
            list.windows(2).all(|w| w[0] < w[1]) && list.iter().all(|&j| j != k && self.share(j, k))
        })
    }
}

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
fn segment_distance(a0: (f64, f64), a1: (f64, f64), b0: (f64, f64), b1: (f64, f64)) -> f64 {
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
    let tree = RTree::bulk_load(large.into_iter().map(|(a, b)| TreeSeg::new(Seg { a, b })).collect());
    for &(p0, p1) in &small {
        let r = best.min(reach);
        let q = envelope(grow(seg_box((p0, p1)), r));
        for s in tree.locate_in_envelope_intersecting(&q) {
            best = best.min(segment_distance(p0, p1, s.seg.a, s.seg.b));
            if best <= stop_at {
                return best;
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
struct Seg {
    a: (f64, f64),
    b: (f64, f64),
}

impl Seg {
    fn bbox(&self) -> Bbox {
        seg_box((self.a, self.b))
    }
}

/// A segment in an R*-tree, with its box worked out once: bulk loading asks
/// for an item's envelope at every comparison of its partitioning, and an
/// outline of millions of segments (a curve-heavy path far larger than the
/// page) spent most of its build recomputing them.
#[derive(Debug, Clone, Copy)]
struct TreeSeg {
    seg: Seg,
    env: AABB<[f64; 2]>,
}

impl TreeSeg {
    fn new(seg: Seg) -> Self {
        TreeSeg { seg, env: envelope(seg.bbox()) }
    }
}

impl RTreeObject for TreeSeg {
    type Envelope = AABB<[f64; 2]>;
    fn envelope(&self) -> Self::Envelope {
        self.env
    }
}

/// Outlines with more segments than this get their own R*-tree, so that two
/// long borders cost O(n log n) instead of O(n²) segment pairs.
const TREE_ABOVE: usize = 64;

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
    trees: Vec<Option<RTree<TreeSeg>>>,
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
            trees: (0..n).map(|_| None).collect(),
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
            let own = &set.segs[first..];
            set.trees[k] =
                (own.len() > TREE_ABOVE).then(|| RTree::bulk_load(own.iter().copied().map(TreeSeg::new).collect()));
        }
        set
    }

    /// How many outlines were prepared.
    pub fn len(&self) -> usize {
        self.bounds.len()
    }

    /// Whether no outline was prepared.
    pub fn is_empty(&self) -> bool {
        self.bounds.is_empty()
    }

    fn segments(&self, k: usize) -> &[Seg] {
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
        if self.trees[i].is_none() && self.trees[j].is_none() {
            return self.short_distance(i, gi, j, reach, stop_at);
        }
        // The side with fewer segments near the other's box is walked; the
        // other is searched, through its tree when it has one.
        let (ni, nj) = (near(i, gi).count(), near(j, gj).count());
        let (walk, wg, other, og) = if ni <= nj { (i, gi, j, gj) } else { (j, gj, i, gi) };
        match &self.trees[other] {
            Some(tree) if ni.min(nj).saturating_mul(ni.max(nj)) > 4096 => {
                for s in near(walk, wg) {
                    let r = best.min(reach);
                    let q = envelope(grow(s.bbox(), r));
                    for t in tree.locate_in_envelope_intersecting(&q) {
                        best = best.min(segment_distance(s.a, s.b, t.seg.a, t.seg.b));
                        if best <= stop_at {
                            return best;
                        }
                    }
                }
            }
            _ => best = scan_pairs(near(walk, wg), || near(other, og), best, reach, stop_at),
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
const RUNS_FROM: usize = 256;

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

#[cfg(test)]
mod tests {
    use super::*;

    /// The pairs an all-pairs scan finds, the reference the index must match.
    fn brute(boxes: &[Bbox], m: f64) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for i in 0..boxes.len() {
            for j in i + 1..boxes.len() {
                if usable(boxes[i]) && usable(boxes[j]) && meet(grow(boxes[i], m), boxes[j]) {
                    out.push((i, j));
                }
            }
        }
        out
    }

    #[test]
    fn near_pairs_match_an_all_pairs_scan() {
        // A deterministic scatter of boxes of mixed sizes (a linear congruential sequence).
        let mut s = 12345u64;
        let mut next = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 33) as f64 / (1u64 << 31) as f64
        };
        let boxes: Vec<Bbox> = (0..400)
            .map(|_| {
                let (x, y, w, h) = (next() * 200.0, next() * 100.0, next() * 8.0, next() * 8.0);
                (x, y, x + w, y + h)
            })
            .chain([(f64::NAN, 0.0, 1.0, 1.0), (5.0, 5.0, 4.0, 4.0)])
            .collect();
        for m in [0.0, 1.0, 3.2, 10.0] {
            assert_eq!(near_pairs(&boxes, m), brute(&boxes, m), "margin {m}");
        }
    }

    fn square(x: f64, y: f64, s: f64, n: usize) -> Vec<Polyline> {
        // A square with `n` vertices per side, so that the tree path is taken for large n.
        let mut pts = Vec::new();
        for k in 0..n {
            pts.push((x + s * k as f64 / n as f64, y));
        }
        for k in 0..n {
            pts.push((x + s, y + s * k as f64 / n as f64));
        }
        for k in 0..n {
            pts.push((x + s - s * k as f64 / n as f64, y + s));
        }
        for k in 0..n {
            pts.push((x, y + s - s * k as f64 / n as f64));
        }
        vec![Polyline { points: pts, closed: true }]
    }

    #[test]
    fn the_fast_segment_distance_agrees_with_the_geometry_module() {
        let mut s = 99u64;
        let mut next = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 33) as f64 / (1u64 << 31) as f64 * 20.0
        };
        for _ in 0..2000 {
            let (a0, a1, b0, b1) = ((next(), next()), (next(), next()), (next(), next()), (next(), next()));
            let (fast, slow) = (segment_distance(a0, a1, b0, b1), crate::geometry::segment_distance(a0, a1, b0, b1));
            assert!((fast - slow).abs() < 1e-9, "{a0:?} {a1:?} {b0:?} {b1:?}: {fast} vs {slow}");
        }
    }

    /// A random-walk outline of `n` segments from `(x, y)`, closed or open.
    fn walk(next: &mut impl FnMut() -> f64, x: f64, y: f64, n: usize, step: f64) -> Vec<Polyline> {
        let (mut x, mut y) = (x, y);
        let mut points = vec![(x, y)];
        for _ in 0..n {
            x += (next() - 0.5) * step;
            y += (next() - 0.5) * step;
            points.push((x, y));
        }
        vec![Polyline { points, closed: n.is_multiple_of(3) }]
    }

    #[test]
    fn prepared_outline_distances_are_those_of_every_segment_pair() {
        let mut s = 4242u64;
        let mut next = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 33) as f64 / (1u64 << 31) as f64
        };
        // Short ways and long borders (above the tree threshold), packed so that many cross.
        let outlines: Vec<Vec<Polyline>> = (0..60)
            .map(|k| {
                let n = if k % 5 == 0 { 150 + k } else { 1 + k % 17 };
                let (x, y) = (next() * 30.0, next() * 30.0);
                walk(&mut next, x, y, n, if n > 100 { 1.5 } else { 4.0 })
            })
            .chain([vec![], vec![Polyline { points: vec![(3.0, 3.0)], closed: false }]])
            .collect();
        let set = OutlineSet::new(outlines.iter().map(Vec::as_slice));
        assert_eq!(set.len(), outlines.len());
        let mut within = 0;
        for i in 0..outlines.len() {
            for j in 0..outlines.len() {
                let exact = all_pairs_distance(&outlines[i], &outlines[j]);
                for reach in [0.5, 3.2, 10.0] {
                    let d = set.distance(i, j, reach, 0.0);
                    if exact <= reach {
                        within += 1;
                        assert_eq!(d, exact, "{i} {j} reach {reach}");
                    } else {
                        assert!(d > reach, "{i} {j} reach {reach}: {d}, exact {exact}");
                    }
                    let old = min_outline_distance(&outlines[i], &outlines[j], reach, 0.0);
                    assert_eq!(old <= reach, d <= reach, "{i} {j} reach {reach}");
                    if exact <= reach {
                        assert_eq!(old, d);
                    }
                    // Stopping early at 1 mm: some value at or below it when
                    // the outlines come that close, the exact distance otherwise.
                    let stop = set.distance(i, j, reach, 1.0);
                    if exact <= reach.min(1.0) {
                        assert!(stop <= 1.0, "{i} {j} reach {reach}: {stop}, exact {exact}");
                    } else if exact > 1.0 {
                        assert!(stop > 1.0 && (exact > reach || stop == exact), "{i} {j} reach {reach}: {stop}");
                    }
                }
            }
        }
        assert!(within > 1000, "only {within} pairs within reach");
        assert_eq!(set.distance(0, 999, 10.0, 0.0), f64::INFINITY);
    }

    /// The exact distance between two outlines: every pair of segments.
    fn all_pairs_distance(a: &[Polyline], b: &[Polyline]) -> f64 {
        a.iter()
            .flat_map(|p| p.segments())
            .flat_map(|s| b.iter().flat_map(|p| p.segments()).map(move |t| (s, t)))
            .map(|(s, t)| segment_distance(s.0, s.1, t.0, t.1))
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn outlines_of_up_to_64_sides_measured_by_runs_are_exact() {
        // Random walks of 20 to 64 segments (no tree; most pairs past
        // `RUNS_FROM`), some short and packed, some spread out.
        let mut s = 777u64;
        let mut next = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 33) as f64 / (1u64 << 31) as f64
        };
        let outlines: Vec<Vec<Polyline>> = (0..40)
            .map(|k| {
                let n = 20 + (k * 7) % 45;
                let (x, y) = (next() * 12.0, next() * 12.0);
                walk(&mut next, x, y, n, if k % 2 == 0 { 0.6 } else { 2.0 })
            })
            .collect();
        let set = OutlineSet::new(outlines.iter().map(Vec::as_slice));
        let (mut runs, mut within) = (0, 0);
        for i in 0..outlines.len() {
            for j in 0..outlines.len() {
                let (ni, nj) = (set.segments(i).len(), set.segments(j).len());
                assert!(ni <= TREE_ABOVE && nj <= TREE_ABOVE);
                runs += usize::from(ni * nj >= RUNS_FROM);
                let exact = all_pairs_distance(&outlines[i], &outlines[j]);
                for reach in [0.05, 0.5, 3.2] {
                    let d = set.distance(i, j, reach, 0.0);
                    if exact <= reach {
                        within += 1;
                        assert_eq!(d, exact, "{i} {j} reach {reach}");
                    } else {
                        assert!(d > reach, "{i} {j} reach {reach}: {d}, exact {exact}");
                    }
                    let stop = set.distance(i, j, reach, 0.3);
                    if exact <= reach.min(0.3) {
                        assert!(stop <= 0.3, "{i} {j} reach {reach}: {stop}, exact {exact}");
                    } else if exact > 0.3 {
                        assert!(stop > 0.3 && (exact > reach || stop == exact), "{i} {j} reach {reach}: {stop}");
                    }
                }
            }
        }
        assert!(runs > 1000 && within > 1000, "{runs} pairs by runs, {within} within reach");
    }

    #[test]
    fn shared_vertices_are_those_an_all_pairs_scan_finds_and_touch() {
        // Squares on a grid of spacing 1 with sides of 1 (sharing corners
        // and sides with their neighbours) or 0.5 (sharing nothing), plus
        // an open line and a one-point outline through a grid corner.
        let mut outlines: Vec<Vec<Polyline>> = Vec::new();
        for k in 0..36 {
            let (x, y) = ((k % 6) as f64, (k / 6) as f64);
            let side = if k % 5 == 0 { 0.5 } else { 1.0 };
            let points = vec![(x, y), (x + side, y), (x + side, y + side), (x, y + side)];
            outlines.push(vec![Polyline { points, closed: true }]);
        }
        outlines.push(vec![Polyline { points: vec![(-0.0, 0.0), (-3.0, 0.5)], closed: false }]);
        outlines.push(vec![Polyline { points: vec![(2.0, 2.0)], closed: false }]);
        let refs: Vec<&[Polyline]> = outlines.iter().map(Vec::as_slice).collect();
        let shared = SharedVertices::new(&refs);
        assert!(shared.sanity_check());
        let on_segments = |o: &[Polyline]| -> Vec<(f64, f64)> {
            o.iter().filter(|p| p.points.len() >= 2).flat_map(|p| p.points.clone()).collect()
        };
        let mut pairs = 0;
        for i in 0..outlines.len() {
            for j in 0..outlines.len() {
                let brute = i != j
                    && on_segments(&outlines[i]).iter().any(|a| on_segments(&outlines[j]).iter().any(|b| a == b));
                assert_eq!(shared.share(i, j), brute, "{i} {j}");
                if brute {
                    pairs += 1;
                    assert_eq!(min_outline_distance(&outlines[i], &outlines[j], 1.0, -1.0), 0.0, "{i} {j}");
                }
            }
        }
        assert!(pairs > 100, "only {pairs} pairs share a vertex");
        // Through one point of more outlines than are listed: none listed.
        let star: Vec<Vec<Polyline>> = (0..=SharedVertices::MAX_AT_ONE_POINT)
            .map(|k| vec![Polyline { points: vec![(0.0, 0.0), (1.0, k as f64)], closed: false }])
            .collect();
        let refs: Vec<&[Polyline]> = star.iter().map(Vec::as_slice).collect();
        assert!(!SharedVertices::new(&refs).share(0, 1));
        assert!(SharedVertices::new(&refs[..2]).share(0, 1));
        // An outline through the point twice (two subpaths) counts once.
        let mut star = star;
        star.truncate(SharedVertices::MAX_AT_ONE_POINT);
        star[3].push(Polyline { points: vec![(0.0, 0.0), (-1.0, 2.0)], closed: false });
        let refs: Vec<&[Polyline]> = star.iter().map(Vec::as_slice).collect();
        let shared = SharedVertices::new(&refs);
        assert!(shared.share(0, 1) && shared.share(3, 15) && shared.sanity_check());
    }

    #[test]
    fn outline_distance_is_exact_with_and_without_the_tree() {
        for n in [1, 4, 200] {
            // Two 10 mm squares 2.5 mm apart side by side.
            let d = min_outline_distance(&square(0.0, 0.0, 10.0, n), &square(12.5, 3.0, 10.0, n), 10.0, 0.0);
            assert!((d - 2.5).abs() < 1e-9, "n {n}: {d}");
            // Diagonal: corner (10, 10) to corner (13, 14) is 5 mm.
            let d = min_outline_distance(&square(0.0, 0.0, 10.0, n), &square(13.0, 14.0, 10.0, n), 10.0, 0.0);
            assert!((d - 5.0).abs() < 1e-9, "n {n}: {d}");
            // Sharing a border.
            let d = min_outline_distance(&square(0.0, 0.0, 10.0, n), &square(10.0, 0.0, 10.0, n), 10.0, 0.0);
            assert_eq!(d, 0.0);
            // Beyond reach: above it.
            let d = min_outline_distance(&square(0.0, 0.0, 10.0, n), &square(40.0, 0.0, 10.0, n), 10.0, 0.0);
            assert!(d > 10.0);
        }
    }
}
