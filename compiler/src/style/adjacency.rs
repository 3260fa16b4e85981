//! Which filled regions touch or nearly touch, and a colouring of the
//! fill classes that keeps touching classes on different textures.

use std::sync::OnceLock;

use crate::geometry::{FillRule, Polyline, SideRows, contains, deep_inside};
use crate::spatial::{self, Bbox};

/// One filled region: its outline and box.
#[derive(Debug, Clone, Copy)]
pub struct Region<'a> {
    /// Outline in page mm.
    pub outline: &'a [Polyline],
    /// Its box.
    pub bbox: Bbox,
}

/// Pairs `(i, j)`, `i < j`, of regions whose outlines come within `near` mm of
/// each other, or one of which lies inside the other (a lake in a country).
/// Candidates come from an R*-tree over the boxes; exact distances are taken
/// only for them, so the cost grows as n log n for a map, not n².
pub fn touching(regions: &[Region<'_>], near: f64) -> Vec<(usize, usize)> {
    let boxes: Vec<Bbox> = regions.iter().map(|r| r.bbox).collect();
    let outlines = outlines(regions);
    spatial::near_pairs(&boxes, near)
        .into_iter()
        .filter(|&(i, j)| near_or_inside(regions, &outlines, i, j, near))
        .collect()
}

/// Whether each region shares a border with another: their outlines come
/// within `abut` mm. Only regions whose boxes come that close are looked at
/// (a tessellation's few neighbours), however dense the drawing.
pub fn abutting(regions: &[Region<'_>], abut: f64) -> Vec<bool> {
    Neighbours::of(regions).abutting(abut)
}

/// Whether each region shares a border with another region of its own class
/// (two districts of one colour) and lies across none that it meets: their
/// outlines come within `abut` mm, `class_of` gives both the same class
/// (`None`: no class, never alike), and neither lies across the other. A
/// region that lies across one of its class (a piece of a larger figure, a
/// duplicate) is not looked at further, so a pile of identical shapes costs
/// one test each. Only boxes that come that close are looked at, as in
/// [`abutting`].
pub fn abutting_alike(regions: &[Region<'_>], class_of: &[Option<usize>], abut: f64) -> Vec<bool> {
    Neighbours::of(regions).abutting_alike(class_of, abut)
}

/// The pairs `(a, b)`, `a < b`, of classes that touch: some region of class
/// `a` and some region of class `b` are [`touching`] at `near` mm. The same
/// edges as classing the pairs [`touching`] returns, but a pair of regions is
/// measured only while its two classes are not yet known to touch, so a dense
/// map of a few fills costs a few exact distances per region, not one per
/// pair of neighbours. `class_of[k]` is the class of region `k` (`None`:
/// none, never an edge).
pub fn class_edges(regions: &[Region<'_>], class_of: &[Option<usize>], near: f64) -> Vec<(usize, usize)> {
    Neighbours::of(regions).class_edges(class_of, near)
}

/// Regions with their boxes in an R*-tree and their outlines prepared for
/// exact distances: made once for both [`abutting`] and [`class_edges`]
/// (on a 1,000-region map, preparing the outlines costs more than either).
pub struct Neighbours<'r, 'a> {
    regions: &'r [Region<'a>],
    index: spatial::BoxIndex,
    outlines: spatial::OutlineSet,
    /// The sides of each region of more than [`FILED_FROM`] sides, filed
    /// when first asked about: a coastline beside hundreds of islands is
    /// asked about each island's sides.
    filed: Vec<OnceLock<Option<SideRows>>>,
}

/// Regions of more sides than this have theirs filed by strips ([`SideRows`]).
const FILED_FROM: usize = 64;

/// Regions per piece of work when [`Neighbours::class_edges`] runs in parallel.
const REGIONS_PER_JOB: usize = 512;

impl<'r, 'a> Neighbours<'r, 'a> {
    /// Prepares `regions`.
    pub fn of(regions: &'r [Region<'a>]) -> Self {
        // The index and the outlines are made at once, each on a thread;
        // the outlines, much the larger, on this one.
        let (outlines, index) = rayon::join(
            || outlines(regions),
            || spatial::BoxIndex::new(&regions.iter().map(|r| r.bbox).collect::<Vec<Bbox>>()),
        );
        let filed = regions.iter().map(|_| OnceLock::new()).collect();
        Neighbours { regions, index, outlines, filed }
    }

    /// [`overlap`] of regions `a` and `b`, through the filed sides of large ones.
    fn overlap(&self, a: usize, b: usize, abut: f64) -> bool {
        let inside = |k: usize, m: (f64, f64)| {
            let r = &self.regions[k];
            let filed = self.filed.get(k).and_then(|f| {
                f.get_or_init(|| {
                    (r.outline.iter().map(Polyline::segment_count).sum::<usize>() > FILED_FROM)
                        .then(|| SideRows::new(r.outline))
                        .flatten()
                })
                .as_ref()
            });
            match filed {
                Some(rows) => rows.deep_inside(m, FillRule::NonZero, abut),
                None => deep_inside(r.outline, m, FillRule::NonZero, abut),
            }
        };
        overlap_with(&self.regions[a], &self.regions[b], abut, [&|m| inside(a, m), &|m| inside(b, m)])
    }

    /// [`abutting`]. Regions are looked at in parallel; a region found to
    /// abut marks its neighbour too, so the neighbour is not searched again.
    /// The marks do not depend on the order the threads take: a region is
    /// marked exactly when some region within `abut` of it exists (the
    /// distance between two outlines is the same both ways round).
    pub fn abutting(&self, abut: f64) -> Vec<bool> {
        use rayon::prelude::*;
        use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
        let out: Vec<AtomicBool> = (0..self.regions.len()).map(|_| AtomicBool::new(false)).collect();
        self.regions.par_iter().enumerate().with_min_len(REGIONS_PER_JOB).for_each(|(k, r)| {
            if out[k].load(Relaxed) {
                return;
            }
            for j in self.index.meeting(spatial::grow(r.bbox, abut)) {
                if j != k && self.outlines.distance(k, j, abut, abut) <= abut {
                    out[k].store(true, Relaxed);
                    if let Some(o) = out.get(j) {
                        o.store(true, Relaxed);
                    }
                    break;
                }
            }
        });
        out.into_iter().map(AtomicBool::into_inner).collect()
    }

    /// Whether each region lies across another that it meets: their
    /// outlines come within `abut` mm and one reaches into the other
    /// (as `overlap` tells). A tessellation's pieces only share sides; the marks of a
    /// scatter plot pile up across each other. Only the regions `asked` says
    /// yes to are looked at (the others are `false`).
    ///
    /// The test is the same both ways round, so a pair of asked regions is
    /// tested once, from the first of the two, and marks both (on a map at
    /// the input limit every region is asked, and each pair was tested
    /// twice). A pair is skipped only when both of its ends that need an
    /// answer already have it, so the marks do not depend on the order the
    /// threads take.
    pub fn lying_across(&self, abut: f64, asked: impl Fn(usize) -> bool + Sync) -> Vec<bool> {
        use rayon::prelude::*;
        use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
        let out: Vec<AtomicBool> = (0..self.regions.len()).map(|_| AtomicBool::new(false)).collect();
        self.regions.par_iter().enumerate().with_min_len(REGIONS_PER_JOB).for_each(|(k, r)| {
            if !asked(k) {
                return;
            }
            for j in self.index.meeting(spatial::grow(r.bbox, abut)) {
                let j_asked = asked(j);
                if j == k || (j < k && j_asked) {
                    continue;
                }
                let known = |i: usize| out.get(i).is_some_and(|o| o.load(Relaxed));
                if known(k) && (!j_asked || known(j)) {
                    continue;
                }
                if self.outlines.distance(k, j, abut, abut) <= abut
                    && (self.overlap(k, j, abut) || self.overlap(j, k, abut))
                {
                    out[k].store(true, Relaxed);
                    if let Some(o) = out.get(j).filter(|_| j_asked) {
                        o.store(true, Relaxed);
                    }
                }
            }
        });
        out.into_iter().map(AtomicBool::into_inner).collect()
    }

    /// [`abutting_alike`]: each region is decided on its own, so in parallel.
    pub fn abutting_alike(&self, class_of: &[Option<usize>], abut: f64) -> Vec<bool> {
        use rayon::prelude::*;
        let regions = self.regions;
        let alike = |(k, r): (usize, &Region<'_>)| {
            let Some(c) = class_of.get(k).copied().flatten() else { return false };
            let mut out = false;
            for j in self.index.meeting(spatial::grow(r.bbox, abut)) {
                if j == k || class_of.get(j).copied().flatten() != Some(c) {
                    continue;
                }
                if self.outlines.distance(k, j, abut, abut) > abut {
                    continue;
                }
                if self.overlap(k, j, abut) || self.overlap(j, k, abut) {
                    return false;
                }
                out = true;
            }
            out
        };
        regions.par_iter().enumerate().with_min_len(REGIONS_PER_JOB).map(alike).collect()
    }

    /// [`class_edges`]. Runs of regions are searched in parallel, each run
    /// keeping, for each class, the sorted classes it has found it touches
    /// and pruning with them; the edges are their union, sorted, so the
    /// result does not depend on how the work was shared.
    ///
    /// A region is searched only for the classes its own is not yet known
    /// to touch. When there are a few classes (a map's fills) and only a
    /// few are still unknown, only their regions are looked up, each class
    /// in an R*-tree of its own: a map whose fills all touch but one rare
    /// class (a few large dots) had every region look at its hundreds of
    /// neighbours for the one edge that never comes, and those queries
    /// were most of the automatic sheet's time on the map at the input limit.
    /// When the unknown classes are common, one query over all the
    /// neighbours is cheaper, and is made instead.
    pub fn class_edges(&self, class_of: &[Option<usize>], near: f64) -> Vec<(usize, usize)> {
        use rayon::prelude::*;
        let n = class_of.iter().flatten().max().map_or(0, |&c| c + 1);
        let mut members: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (k, c) in class_of.iter().enumerate().take(self.regions.len()) {
            if let Some(c) = *c {
                members[c].push(k);
            }
        }
        let present: Vec<usize> = (0..n).filter(|&c| !members[c].is_empty()).collect();
        let others = present.len().saturating_sub(1);
        // Each class's own index, for the few-classes search.
        let by_class: Vec<spatial::BoxIndex> = if present.len() <= FEW_CLASSES {
            members
                .par_iter()
                .map(|m| spatial::BoxIndex::new(&m.iter().map(|&k| self.regions[k].bbox).collect::<Vec<_>>()))
                .collect()
        } else {
            Vec::new()
        };
        let search = |mut known: Known, k: usize| {
            let Some(ca) = class_of.get(k).copied().flatten() else { return known };
            if known.of(ca).len() >= others {
                return known;
            }
            let query = spatial::grow(self.regions[k].bbox, near);
            let near_to = |j: usize| j > k && near_or_inside(self.regions, &self.outlines, k, j, near);
            // The few classes still unknown, looked up one by one when they are
            // rare: a query per class costs more than one over all the
            // neighbours unless it skips most of them (on the generated map of
            // 10,000 regions, per-class lookups whatever the classes cost
            // 370 M instructions more, 3 % of the build, than the one query).
            let unknown = || present.iter().copied().filter(|&cb| cb != ca && !known.has(ca, cb));
            let rare = || unknown().map(|cb| members[cb].len()).sum::<usize>() * RARE_SHARE <= self.regions.len();
            if !by_class.is_empty() && others - known.of(ca).len() <= UNKNOWN_CLASSES && rare() {
                for &cb in &present {
                    if cb == ca || known.has(ca, cb) {
                        continue;
                    }
                    let found = by_class[cb].meeting(query).filter_map(|p| members[cb].get(p).copied()).any(near_to);
                    if found {
                        known.add(ca, cb);
                    }
                }
                return known;
            }
            for j in self.index.meeting(query) {
                let Some(cb) = class_of.get(j).copied().flatten() else { continue };
                if j <= k || ca == cb || known.has(ca, cb) {
                    continue;
                }
                if near_to(j) {
                    known.add(ca, cb);
                    if known.of(ca).len() >= others {
                        break;
                    }
                }
            }
            known
        };
        let known = (0..self.regions.len())
            .into_par_iter()
            .with_min_len(REGIONS_PER_JOB)
            .fold(|| Known::new(n), search)
            .reduce(|| Known::new(n), Known::union);
        known.edges()
    }
}

/// Most classes present for [`Neighbours::class_edges`] to give each its
/// own R*-tree.
const FEW_CLASSES: usize = 64;

/// Most classes a region's class may still not be known to touch for
/// [`Neighbours::class_edges`] to look them up one by one rather than
/// look at all the region's neighbours.
const UNKNOWN_CLASSES: usize = 4;

/// The regions of the classes still unknown must be at most one in this
/// many for [`Neighbours::class_edges`] to look them up class by class.
const RARE_SHARE: usize = 4;

/// For each class, the classes it is known to touch, sorted.
struct Known {
    touches: Vec<Vec<usize>>,
}

impl Known {
    fn new(n: usize) -> Self {
        Known { touches: vec![Vec::new(); n] }
    }

    fn of(&self, a: usize) -> &[usize] {
        self.touches.get(a).map_or(&[], Vec::as_slice)
    }

    fn has(&self, a: usize, b: usize) -> bool {
        self.of(a).binary_search(&b).is_ok()
    }

    /// Records that `a` and `b` touch.
    fn add(&mut self, a: usize, b: usize) {
        for (x, y) in [(a, b), (b, a)] {
            if let Some(t) = self.touches.get_mut(x)
                && let Err(at) = t.binary_search(&y)
            {
                t.insert(at, y);
            }
        }
    }

    /// What either knows.
    fn union(mut self, other: Known) -> Known {
        if self.touches.len() < other.touches.len() {
            return other.union(self);
        }
        for (mine, theirs) in self.touches.iter_mut().zip(other.touches) {
            if theirs.is_empty() {
                continue;
            }
            mine.extend(theirs);
            mine.sort_unstable();
            mine.dedup();
        }
        self
    }

    /// The pairs `(a, b)`, `a < b`, sorted.
    fn edges(&self) -> Vec<(usize, usize)> {
        self.touches
            .iter()
            .enumerate()
            .flat_map(|(a, t)| t.iter().filter(move |&&b| b > a).map(move |&b| (a, b)))
            .collect()
    }
}

/// The regions' outlines, prepared once for every pair's distance.
fn outlines(regions: &[Region<'_>]) -> spatial::OutlineSet {
    spatial::OutlineSet::new(regions.iter().map(|r| r.outline))
}

/// Whether `a` reaches into `b`: the centre of `a`'s box, or the midpoint of
/// one of `a`'s sides (at most [`OVERLAP_SAMPLES`] of them, evenly spread),
/// lies inside `b` (and the centre inside `a`) farther than `abut` from the
/// outline. Neighbours of a tessellation only share sides; two pieces of one
/// figure (the bars of a cross) lie across each other.
#[cfg(test)]
fn overlap(a: &Region<'_>, b: &Region<'_>, abut: f64) -> bool {
    let (oa, ob) = (a.outline, b.outline);
    let inside_a = |m| deep_inside(oa, m, FillRule::NonZero, abut);
    let inside_b = |m| deep_inside(ob, m, FillRule::NonZero, abut);
    overlap_with(a, b, abut, [&inside_a, &inside_b])
}

/// [`overlap`], asking `inside[0](m)` (`inside[1](m)`) whether `m` lies
/// inside `a` (`b`) farther than `abut` from its outline.
fn overlap_with(a: &Region<'_>, b: &Region<'_>, abut: f64, inside: [&dyn Fn((f64, f64)) -> bool; 2]) -> bool {
    // The centre of `a`'s box, where it lies inside `a`, finds a duplicate (whose sides lie on `b`'s).
    let c = ((a.bbox.0 + a.bbox.2) / 2.0, (a.bbox.1 + a.bbox.3) / 2.0);
    // (Only whether the outline lies farther than `abut` is asked: the
    // segments whose boxes lie farther are not measured. Every side
    // measured made this a tenth of the build of a 64 MB map.)
    // A point inside farther than `abut` from a closed outline lies in its
    // box shrunk by `abut` (a ray from it crosses the outline within the box).
    let shrunk = |r: &Region<'_>, m: (f64, f64)| {
        let b = r.bbox;
        m.0 - b.0 > abut && b.2 - m.0 > abut && m.1 - b.1 > abut && b.3 - m.1 > abut
    };
    let deep = |k: usize, m: (f64, f64)| {
        let r = [a, b][k];
        let closed = r.outline.iter().all(|p| p.closed);
        (if closed { shrunk(r, m) } else { spatial::meet((m.0, m.1, m.0, m.1), r.bbox) }) && inside[k](m)
    };
    if deep(0, c) && deep(1, c) {
        return true;
    }
    let sides: usize = a.outline.iter().map(Polyline::segment_count).sum();
    let step = sides.div_ceil(OVERLAP_SAMPLES).max(1);
    sampled_mids(a.outline, step).any(|m| deep(1, m))
}

/// The midpoints of every `step`-th side of `outline` (its sides counted on
/// across its polylines, from the first): what `step_by(step)` over the
/// midpoints of all its sides gives, without walking the sides between (a
/// coastline of thousands of sides is sampled for each of its neighbours).
fn sampled_mids(outline: &[Polyline], step: usize) -> impl Iterator<Item = (f64, f64)> + '_ {
    let step = step.max(1);
    let mut before = 0usize;
    outline.iter().flat_map(move |p| {
        let n = p.segment_count();
        // The first of this polyline's sides whose overall number is a multiple of `step`.
        let first = (step - before % step) % step;
        before += n;
        let len = p.points.len();
        (first..n).step_by(step).map(move |i| {
            let (a, b) = (p.points[i], p.points[(i + 1) % len]);
            ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0)
        })
    })
}

/// Most sides of a region [`overlap`] looks at.
const OVERLAP_SAMPLES: usize = 64;

/// Whether the outlines of regions `i` and `j` come within `near` mm, or one lies inside the other.
fn near_or_inside(regions: &[Region<'_>], outlines: &spatial::OutlineSet, i: usize, j: usize, near: f64) -> bool {
    let inside = |r: &Region<'_>, o: &Region<'_>| {
        o.outline.iter().find_map(|p| p.points.first()).is_some_and(|&p| contains(r.outline, p, FillRule::NonZero))
    };
    let (a, b) = (&regions[i], &regions[j]);
    // Whether they come within `near` is all that is asked: the search stops
    // at the first pair of segments that close. Stopping only at a touch (0)
    // made near but apart outlines (a logo's letters, 577 of them) scan every
    // segment pair within `near`, most of memgraph.svg's build.
    outlines.distance(i, j, near, near) <= near || inside(a, b) || inside(b, a)
}

/// Colours the graph of `n` classes with at most `colours` colours, taking the
/// classes in `order` (most important first) and giving each, among the
/// colours none of its already coloured neighbours has, the one used least so
/// far (the lowest of those): so up to `colours` classes all differ, and
/// beyond that colours are shared only between classes that do not touch. A
/// class whose neighbours already use every colour gets `None`.
pub fn colour(n: usize, edges: &[(usize, usize)], order: &[usize], colours: usize) -> Vec<Option<usize>> {
    let mut next: Vec<Vec<usize>> = vec![Vec::new(); n];
    for &(a, b) in edges {
        if a != b && a < n && b < n {
            next[a].push(b);
            next[b].push(a);
        }
    }
    let mut out: Vec<Option<usize>> = vec![None; n];
    let mut uses = vec![0usize; colours];
    for &c in order.iter().filter(|&&c| c < n) {
        let mut taken = vec![false; colours];
        for &m in &next[c] {
            if let Some(k) = out[m] {
                taken[k] = true;
            }
        }
        out[c] = (0..colours).filter(|&k| !taken[k]).min_by_key(|&k| (uses[k], k));
        if let Some(k) = out[c] {
            uses[k] += 1;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each outline as a region with its box.
    fn regions_of(shapes: &[Vec<Polyline>]) -> Vec<Region<'_>> {
        shapes.iter().map(|s| Region { outline: s, bbox: crate::geometry::bounds(s).expect("a shape") }).collect()
    }

    /// A deterministic stream of numbers in [0, 1) from `seed` (an LCG).
    fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 33) as f64 / (1u64 << 31) as f64
        }
    }

    fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Polyline> {
        vec![Polyline { points: vec![(x0, y0), (x1, y0), (x1, y1), (x0, y1)], closed: true }]
    }

    /// `sampled_mids` gives what `step_by` over every side's midpoint gives:
    /// outlines of several polylines, open and closed, of 0 to 40 points.
    #[test]
    fn sampled_midpoints_are_every_step_th_sides() {
        let mut next = uniform(11);
        for case in 0..300 {
            let outline: Vec<Polyline> = (0..1 + case % 5)
                .map(|_| Polyline {
                    points: (0..(next() * 40.0) as usize).map(|_| (next() * 50.0, next() * 30.0)).collect(),
                    closed: next() < 0.7,
                })
                .collect();
            for step in [1, 2, 3, 7, 16, 64] {
                let every =
                    outline.iter().flat_map(|p| p.segments()).map(|(p, q)| ((p.0 + q.0) / 2.0, (p.1 + q.1) / 2.0));
                let want: Vec<(f64, f64)> = every.step_by(step).collect();
                assert_eq!(sampled_mids(&outline, step).collect::<Vec<_>>(), want, "case {case}, step {step}");
            }
        }
    }

    #[test]
    fn touching_finds_shared_borders_near_misses_and_islands() {
        let shapes = [
            rect(0.0, 0.0, 10.0, 10.0),  // 0
            rect(10.0, 0.0, 20.0, 10.0), // 1 shares a border with 0
            rect(22.0, 0.0, 30.0, 10.0), // 2 is 2 mm from 1
            rect(40.0, 0.0, 50.0, 10.0), // 3 is alone
            rect(42.0, 2.0, 44.0, 4.0),  // 4 lies inside 3
            rect(0.0, 10.5, 10.0, 20.0), // 5 is 0.5 mm below 0 and 0.5 mm from 1's corner
        ];
        let regions = regions_of(&shapes);
        assert_eq!(touching(&regions, 1.0), vec![(0, 1), (0, 5), (1, 5), (3, 4)]);
        assert_eq!(touching(&regions, 3.2), vec![(0, 1), (0, 5), (1, 2), (1, 5), (3, 4)]);
        // Only shared borders abut: 0 and 1 (2 is 2 mm off, 5 is 0.5 mm off).
        assert_eq!(abutting(&regions, 0.05), [true, true, false, false, false, false]);
    }

    #[test]
    fn class_edges_are_the_classes_of_the_touching_pairs() {
        // A deterministic scatter of rectangles in four classes, some unclassed.
        let mut next = uniform(7u64);
        let shapes: Vec<Vec<Polyline>> = (0..150)
            .map(|_| {
                let (x, y) = (next() * 120.0, next() * 80.0);
                rect(x, y, x + 1.0 + next() * 9.0, y + 1.0 + next() * 9.0)
            })
            .collect();
        let regions = regions_of(&shapes);
        let class_of: Vec<Option<usize>> = (0..regions.len()).map(|k| (k % 5 < 4).then_some(k % 7 % 4)).collect();
        for near in [0.5, 3.2] {
            let mut want: Vec<(usize, usize)> = touching(&regions, near)
                .into_iter()
                .filter_map(|(a, b)| Some((class_of[a]?, class_of[b]?)))
                .filter(|(a, b)| a != b)
                .map(|(a, b)| (a.min(b), a.max(b)))
                .collect();
            want.sort_unstable();
            want.dedup();
            assert_eq!(class_edges(&regions, &class_of, near), want, "near {near}");
        }
    }

    /// All pairs, each measured over every pair of segments with the
    /// geometry module's own distance (not the R*-tree or `OutlineSet`).
    fn all_pairs(regions: &[Region<'_>], near: f64) -> Vec<(usize, usize)> {
        let inside = |a: &[Polyline], b: &[Polyline]| contains(a, b[0].points[0], FillRule::NonZero);
        let mut out = Vec::new();
        for i in 0..regions.len() {
            for j in i + 1..regions.len() {
                let (a, b) = (regions[i].outline, regions[j].outline);
                if min_outline_distance(&regions[i], &regions[j]) <= near || inside(a, b) || inside(b, a) {
                    out.push((i, j));
                }
            }
        }
        out
    }

    proptest::proptest! {
        /// The parallel searches against an all-pairs answer: class edges
        /// with few classes (each looked up in its own tree), with more than
        /// [`FEW_CLASSES`] (all neighbours looked at), and in between; which
        /// regions abut, and which abut one of their own class.
        #[test]
        fn class_edges_and_abutting_agree_with_all_pairs(
            cells in proptest::collection::vec((0u8..24, 0u8..16, 1u8..5, 1u8..5, 0usize..200), 1..140),
            classes in proptest::sample::select(vec![1usize, 2, 3, 5, 7, 12, 80, 150]),
            near in proptest::sample::select(vec![0.05, 0.5, 3.2]),
        ) {
            // Rectangles on a half-millimetre grid, so that many share sides exactly.
            let shapes: Vec<Vec<Polyline>> = cells
                .iter()
                .map(|&(x, y, w, h, _)| {
                    let (x, y) = (f64::from(x) * 0.5, f64::from(y) * 0.5);
                    rect(x, y, x + f64::from(w) * 0.5, y + f64::from(h) * 0.5)
                })
                .collect();
            let regions = regions_of(&shapes);
            // Every fifth region has no class.
            let class_of: Vec<Option<usize>> =
                cells.iter().enumerate().map(|(k, c)| (k % 5 != 4).then_some(c.4 % classes)).collect();
            let pairs = all_pairs(&regions, near);
            let mut want: Vec<(usize, usize)> = pairs
                .iter()
                .filter_map(|&(a, b)| Some((class_of[a]?, class_of[b]?)))
                .filter(|(a, b)| a != b)
                .map(|(a, b)| (a.min(b), a.max(b)))
                .collect();
            want.sort_unstable();
            want.dedup();
            let neighbours = Neighbours::of(&regions);
            proptest::prop_assert_eq!(neighbours.class_edges(&class_of, near), want);
            let abut = all_pairs(&regions, ABUT);
            let mut abuts = vec![false; regions.len()];
            for &(a, b) in &abut {
                // `all_pairs` also counts a region inside another; abutting is the outlines alone.
                if min_outline_distance(&regions[a], &regions[b]) <= ABUT {
                    abuts[a] = true;
                    abuts[b] = true;
                }
            }
            proptest::prop_assert_eq!(neighbours.abutting(ABUT), abuts);
            let alike: Vec<bool> = (0..regions.len())
                .map(|k| {
                    let mates: Vec<usize> = (0..regions.len())
                        .filter(|&j| j != k && class_of[k].is_some() && class_of[j] == class_of[k])
                        .filter(|&j| min_outline_distance(&regions[k], &regions[j]) <= ABUT)
                        .collect();
                    let across = mates.iter().any(|&j| {
                        overlap(&regions[k], &regions[j], ABUT) || overlap(&regions[j], &regions[k], ABUT)
                    });
                    !mates.is_empty() && !across
                })
                .collect();
            proptest::prop_assert_eq!(neighbours.abutting_alike(&class_of, ABUT), alike);
        }
    }

    /// The outlines' distance over every pair of segments.
    fn min_outline_distance(a: &Region<'_>, b: &Region<'_>) -> f64 {
        let mut best = f64::INFINITY;
        for (p, q) in a.outline.iter().flat_map(|l| l.segments()) {
            for (r, s) in b.outline.iter().flat_map(|l| l.segments()) {
                best = best.min(crate::geometry::segment_distance(p, q, r, s));
            }
        }
        best
    }

    const ABUT: f64 = 0.05;

    #[test]
    fn colouring_gives_neighbours_different_colours_and_drops_the_last_when_out_of_colours() {
        // A wheel: hub 0 touching a ring of five (an odd cycle needs three colours, the hub a fourth).
        let mut edges = vec![];
        for k in 1..=5 {
            edges.push((0, k));
            edges.push((k, if k == 5 { 1 } else { k + 1 }));
        }
        let order: Vec<usize> = (0..6).collect();
        let c = colour(6, &edges, &order, 5);
        for &(a, b) in &edges {
            assert_ne!(c[a], c[b], "{a} and {b}");
        }
        assert!(c.iter().all(Option::is_some));
        // Six classes, five colours: all five are used, the sixth shares with a class it does not touch.
        assert_eq!(c, [Some(0), Some(1), Some(2), Some(3), Some(4), Some(2)]);
        // With three colours the last ring class cannot be coloured.
        let c = colour(6, &edges, &order, 3);
        assert_eq!(c[5], None);
        assert!(c[..5].iter().all(Option::is_some));
    }

    /// Each asked region is marked exactly when some other region lies
    /// across it, as testing every pair both ways round finds, on a scatter
    /// of squares that pile up, graze and share sides, with some regions
    /// not asked (a pair is tested once, from the first of two asked ones).
    #[test]
    fn lying_across_marks_what_every_pair_tested_finds() {
        let mut next = uniform(11u64);
        // A tessellation's row of squares sharing sides, then a scatter.
        let mut shapes: Vec<Vec<Polyline>> =
            (0..8).map(|k| rect(k as f64 * 2.0, 0.0, k as f64 * 2.0 + 2.0, 2.0)).collect();
        shapes.extend((0..120).map(|_| {
            let (x, y, w) = (next() * 40.0, 5.0 + next() * 30.0, 0.5 + next() * 3.0);
            rect(x, y, x + w, y + w)
        }));
        let regions = regions_of(&shapes);
        let neighbours = Neighbours::of(&regions);
        for skip in [0, 3] {
            let asked = |k: usize| skip == 0 || k % skip != 1;
            let want: Vec<bool> = (0..regions.len())
                .map(|k| {
                    asked(k)
                        && (0..regions.len()).any(|j| {
                            j != k
                                && min_outline_distance(&regions[k], &regions[j]) <= ABUT
                                && (overlap(&regions[k], &regions[j], ABUT) || overlap(&regions[j], &regions[k], ABUT))
                        })
                })
                .collect();
            assert!(want.iter().any(|&w| w) && !want.iter().all(|&w| w), "the scatter has both kinds");
            assert_eq!(neighbours.lying_across(ABUT, asked), want, "every {skip}th not asked");
        }
    }
}
