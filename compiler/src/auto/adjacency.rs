//! Which filled regions touch or nearly touch, and a colouring of the
//! fill classes that keeps touching classes on different textures.

use std::collections::BTreeSet;

use crate::geometry::{FillRule, Polyline, contains, distance_to_outline};
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
}

/// Regions per piece of work when [`Neighbours::class_edges`] runs in parallel.
const REGIONS_PER_JOB: usize = 512;

impl<'r, 'a> Neighbours<'r, 'a> {
    /// Prepares `regions`.
    pub fn of(regions: &'r [Region<'a>]) -> Self {
        let boxes: Vec<Bbox> = regions.iter().map(|r| r.bbox).collect();
        Neighbours { regions, index: spatial::BoxIndex::new(&boxes), outlines: outlines(regions) }
    }

    /// [`abutting`].
    pub fn abutting(&self, abut: f64) -> Vec<bool> {
        let mut out = vec![false; self.regions.len()];
        for (k, r) in self.regions.iter().enumerate() {
            if out[k] {
                continue;
            }
            for j in self.index.meeting(spatial::grow(r.bbox, abut)) {
                if j != k && self.outlines.distance(k, j, abut, abut) <= abut {
                    out[k] = true;
                    out[j] = true;
                    break;
                }
            }
        }
        out
    }

    /// [`abutting_alike`].
    pub fn abutting_alike(&self, class_of: &[Option<usize>], abut: f64) -> Vec<bool> {
        let regions = self.regions;
        let mut out = vec![false; regions.len()];
        for (k, r) in regions.iter().enumerate() {
            let Some(c) = class_of.get(k).copied().flatten() else { continue };
            for j in self.index.meeting(spatial::grow(r.bbox, abut)) {
                if j == k || class_of.get(j).copied().flatten() != Some(c) {
                    continue;
                }
                if self.outlines.distance(k, j, abut, abut) > abut {
                    continue;
                }
                if overlap(r, &regions[j], abut) || overlap(&regions[j], r, abut) {
                    out[k] = false;
                    break;
                }
                out[k] = true;
            }
        }
        out
    }

    /// [`class_edges`]. Runs of regions are searched in parallel, each
    /// pruning with the edges it has found itself; the edges are their
    /// union, sorted, so the result does not depend on how the work was shared.
    pub fn class_edges(&self, class_of: &[Option<usize>], near: f64) -> Vec<(usize, usize)> {
        use rayon::prelude::*;
        // Once a class is known to touch every other class, its regions
        // can add no edge, and their neighbours need not even be looked up:
        // on a dense map of a few fills every class soon touches every
        // other, and the queries (hundreds of boxes within `near` of each
        // region of a map fitted to the surface) were most of the cost.
        let n = class_of.iter().flatten().max().map_or(0, |&c| c + 1);
        let mut present = vec![false; n];
        for &c in class_of.iter().flatten() {
            present[c] = true;
        }
        let others = present.iter().filter(|&&p| p).count().saturating_sub(1);
        let search = |(mut edges, mut touched): (BTreeSet<(usize, usize)>, Vec<usize>), k: usize| {
            let Some(ca) = class_of.get(k).copied().flatten() else { return (edges, touched) };
            if touched[ca] == others {
                return (edges, touched);
            }
            for j in self.index.meeting(spatial::grow(self.regions[k].bbox, near)) {
                let Some(cb) = class_of.get(j).copied().flatten() else { continue };
                let e = (ca.min(cb), ca.max(cb));
                if j <= k || ca == cb || edges.contains(&e) {
                    continue;
                }
                if near_or_inside(self.regions, &self.outlines, k, j, near) {
                    edges.insert(e);
                    touched[ca] += 1;
                    touched[cb] += 1;
                    if touched[ca] == others {
                        break;
                    }
                }
            }
            (edges, touched)
        };
        let edges: BTreeSet<(usize, usize)> = (0..self.regions.len())
            .into_par_iter()
            .with_min_len(REGIONS_PER_JOB)
            .fold(|| (BTreeSet::new(), vec![0; n]), search)
            .map(|(edges, _)| edges)
            .reduce(BTreeSet::new, |mut a, mut b| {
                a.append(&mut b);
                a
            });
        edges.into_iter().collect()
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
fn overlap(a: &Region<'_>, b: &Region<'_>, abut: f64) -> bool {
    // The centre of `a`'s box, where it lies inside `a`, finds a duplicate (whose sides lie on `b`'s).
    let c = ((a.bbox.0 + a.bbox.2) / 2.0, (a.bbox.1 + a.bbox.3) / 2.0);
    let deep = |r: &Region<'_>, m: (f64, f64)| {
        spatial::meet((m.0, m.1, m.0, m.1), r.bbox)
            && contains(r.outline, m, FillRule::NonZero)
            && distance_to_outline(r.outline, m) > abut
    };
    if deep(a, c) && deep(b, c) {
        return true;
    }
    let mids: Vec<(f64, f64)> =
        a.outline.iter().flat_map(|p| p.segments()).map(|(p, q)| ((p.0 + q.0) / 2.0, (p.1 + q.1) / 2.0)).collect();
    let step = mids.len().div_ceil(OVERLAP_SAMPLES).max(1);
    mids.iter().step_by(step).any(|&m| deep(b, m))
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

    fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Polyline> {
        vec![Polyline { points: vec![(x0, y0), (x1, y0), (x1, y1), (x0, y1)], closed: true }]
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
        let regions: Vec<Region<'_>> =
            shapes.iter().map(|s| Region { outline: s, bbox: crate::geometry::bounds(s).unwrap() }).collect();
        assert_eq!(touching(&regions, 1.0), vec![(0, 1), (0, 5), (1, 5), (3, 4)]);
        assert_eq!(touching(&regions, 3.2), vec![(0, 1), (0, 5), (1, 2), (1, 5), (3, 4)]);
        // Only shared borders abut: 0 and 1 (2 is 2 mm off, 5 is 0.5 mm off).
        assert_eq!(abutting(&regions, 0.05), [true, true, false, false, false, false]);
    }

    #[test]
    fn class_edges_are_the_classes_of_the_touching_pairs() {
        // A deterministic scatter of rectangles in four classes, some unclassed.
        let mut s = 7u64;
        let mut next = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 33) as f64 / (1u64 << 31) as f64
        };
        let shapes: Vec<Vec<Polyline>> = (0..150)
            .map(|_| {
                let (x, y) = (next() * 120.0, next() * 80.0);
                rect(x, y, x + 1.0 + next() * 9.0, y + 1.0 + next() * 9.0)
            })
            .collect();
        let regions: Vec<Region<'_>> =
            shapes.iter().map(|s| Region { outline: s, bbox: crate::geometry::bounds(s).unwrap() }).collect();
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
}
