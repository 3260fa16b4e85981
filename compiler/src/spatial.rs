//! Shared service: spatial indexes.
//!
//! Spatial indexes (R*-trees from `rstar`) for every pass that relates
//! elements to their neighbours: the design rules' gaps and overlaps, and the
//! automatic style sheet's region adjacency. Each finds the pairs of boxes
//! that come within a distance in O(n log n + pairs), never by looking at all
//! n² pairs, which is what made a 10,000-element map take minutes.
//! The distances between outlines those passes measure are in
//! `outline_set.rs` ([`min_outline_distance`], [`OutlineSet`]).

use rstar::{AABB, RStarInsertionStrategy, RTree, RTreeObject, RTreeParams};

use crate::geometry::Polyline;

mod outline_set;

pub use outline_set::{OutlineSet, min_outline_distance};

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

/// Items joined into groups, each group named by its lowest position (a
/// union–find with path halving).
#[derive(Debug)]
pub struct Groups {
    parent: Vec<usize>,
}

impl Groups {
    /// `n` items, each in a group of its own.
    pub fn new(n: usize) -> Self {
        Groups { parent: (0..n).collect() }
    }

    /// The lowest position in `k`'s group.
    pub fn root(&mut self, mut k: usize) -> usize {
        while self.parent[k] != k {
            self.parent[k] = self.parent[self.parent[k]];
            k = self.parent[k];
        }
        k
    }

    /// Joins the groups of `a` and `b`; whether they were apart.
    pub fn join(&mut self, a: usize, b: usize) -> bool {
        let (ra, rb) = (self.root(a), self.root(b));
        // The lower position stays the root: the group's first item.
        self.parent[ra.max(rb)] = ra.min(rb);
        ra != rb
    }

    /// The groups, each as its positions in order, in the order of their
    /// first positions.
    pub fn lists(mut self) -> Vec<Vec<usize>> {
        let mut at = vec![usize::MAX; self.parent.len()];
        let mut lists: Vec<Vec<usize>> = Vec::new();
        for k in 0..self.parent.len() {
            let r = self.root(k);
            if at[r] == usize::MAX {
                at[r] = lists.len();
                lists.push(Vec::new());
            }
            lists[at[r]].push(k);
        }
        lists
    }
}

/// `boxes` in groups that meet, directly or through others (touching edges
/// count): each group as its positions in order, in the order of their first
/// positions. A box with non-finite or inverted corners is a group of its own.
pub fn meeting_groups(boxes: &[Bbox]) -> Vec<Vec<usize>> {
    let index = BoxIndex::new(boxes);
    let mut groups = Groups::new(boxes.len());
    for (a, &b) in boxes.iter().enumerate() {
        for c in index.meeting(b).filter(|&c| c > a) {
            groups.join(a, c);
        }
    }
    groups.lists()
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

#[cfg(test)]
mod tests;
