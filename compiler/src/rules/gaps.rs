//! The gap rule's search (T0408): each feature's nearest distinct
//! neighbour closer than [`MIN_GAP_MM`] that does not touch it, in two
//! bounded passes along a Hilbert order, and the gap between two features.

use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

use super::{GAP_TOLERANCE_MM, MIN_GAP_MM, Textures};
use crate::geometry::{FillRule, Polyline, contains, dist, distance_to_outline_within, simplify};
use crate::latero::{Feature, FeatureKind};
use crate::spatial;

/// For each feature, its nearest feature of another element whose footprint
/// comes closer than [`MIN_GAP_MM`] without touching it (a gap above 0), and
/// that gap; `None` when there is none. Among equal gaps the first feature
/// is named.
///
/// Two passes, because a dense drawing's neighbours come in two kinds. The
/// pairs whose boxes meet (a plan's crossing ways, a map's bordering
/// regions) are mostly touching; each is measured once, for both of its
/// features, up to the larger of their nearest gaps so far. The pairs whose
/// boxes do not meet are then searched from each feature in turn, nearest
/// box first, measured only up to that feature's nearest gap, and the search
/// stops at the first box farther than it (the distance between boxes bounds
/// the gap from below). Measuring those once for both as well (up to the
/// larger nearest gap, the whole [`MIN_GAP_MM`] for a feature not yet
/// reached) made the 45,000-region map measure every pair within 3.2 mm in
/// full; searching the meeting pairs from each side measured a dense plan's
/// touching pairs twice. Every pair is measured with its lower position
/// first, so both sides see the same gap to the bit.
///
/// Both passes run in parallel and visit the features along a Hilbert curve
/// ([`spatial::locality_order`]), whose outlines are laid out in memory in
/// the same order: a feature's neighbours were mostly read for the feature
/// before, and in document order each one was a cache miss (most of the
/// time the gap rule took on a 10,000-way plan). In the first pass, pairs
/// are shared out by feature (each pair goes with the one that comes first
/// on the curve), and the nearest gaps found so far are shared between the
/// threads as bounds that only ever go down: a bound only decides how far a
/// pair is measured, and a pair is kept only when it is measured exactly
/// (up to the larger of its features' bounds, which are never below their
/// final nearest gaps). The kept gaps are then taken in for each feature
/// as the smallest (the first feature among equal ones), which does not
/// depend on the order they come in, so neither does the outcome depend on
/// how the threads share the work.
///
/// The first pass calls `on_meet(i, j, out)` for every pair `i < j` whose
/// boxes meet and that are not one layer (whose overlaps need a look); what
/// it adds to `out` is returned in order of `i` then `j`.
pub(super) fn nearest_gaps<D: Send>(
    f: &[Feature],
    index: &spatial::BoxIndex,
    textures: &Textures,
    on_meet: impl Fn(usize, usize, &mut Vec<D>) + Sync,
) -> (Vec<Option<(usize, f64)>>, Vec<D>) {
    let boxes: Vec<_> = f.iter().map(|x| x.bbox).collect();
    let order = spatial::locality_order(&boxes);
    let mut rank = vec![0; f.len()];
    for (r, &k) in order.iter().enumerate() {
        rank[k] = r;
    }
    // Gaps are measured between outlines simplified to `GAP_TOLERANCE_MM`:
    // a small circle flattened for the fields has ~100 sides, and a pair of
    // nearby ones costs the product of their counts.
    let simple: Vec<Vec<Polyline>> = f
        .par_iter()
        .map(|x| {
            x.outline
                .iter()
                .map(|p| Polyline { points: simplify(&p.points, p.closed, GAP_TOLERANCE_MM), closed: p.closed })
                .collect()
        })
        .collect();
    let outlines: Vec<&[Polyline]> = simple.iter().map(Vec::as_slice).collect();
    let search = GapSearch {
        f,
        index,
        outlines: spatial::OutlineSet::in_order(&outlines, order.iter().copied()),
        shared: spatial::SharedVertices::new(&outlines),
        probes: f.iter().enumerate().map(|(k, x)| Probe::of(x, textures.get(&k).map(|t| t.0))).collect(),
    };
    let masks: Vec<Option<usize>> = f.iter().map(|x| x.mask).collect();
    // Gaps are above 0, and the bits of positive floats order as the floats do.
    let bounds: Vec<AtomicU64> = f.iter().map(|_| AtomicU64::new(MIN_GAP_MM.to_bits())).collect();
    let bound = |k: usize| f64::from_bits(bounds[k].load(Ordering::Relaxed));
    let found: Vec<Found<D>> = order
        .par_chunks(MEET_CHUNK)
        .map_init(
            || (Vec::new(), Vec::new()),
            |(met, out), chunk| {
                let mut found = Found { gaps: Vec::new(), meets: Vec::new(), near: Vec::new(), covered: Vec::new() };
                for &i in chunk {
                    let a = f[i].bbox;
                    // The boxes apart from this one but nearer than what the
                    // second pass's first ring would look at come from the
                    // same query: by now a dense drawing's features mostly
                    // have a small bound from the neighbours before them.
                    let covered = GAP_RINGS[0].min(bound(i));
                    let before = found.near.len();
                    met.clear();
                    for (j, bj) in index.meeting_boxes(spatial::grow(a, covered)) {
                        if spatial::meet(a, bj) {
                            if rank[j] > rank[i] {
                                met.push(j);
                            }
                        } else if search.probes[j].distinct(&search.probes[i]) {
                            let d = spatial::box_distance(bj, a);
                            if d < covered {
                                found.near.push((d, j));
                            }
                        }
                    }
                    found.covered.push((covered, found.near.len() - before));
                    for &j in met.iter() {
                        let (p, q) = (i.min(j), i.max(j));
                        if !(masks[p].is_some() && masks[p] == masks[q]) {
                            on_meet(p, q, out);
                            found.meets.extend(out.drain(..).map(|d| (p, q, d)));
                        }
                        if search.probes[p].distinct(&search.probes[q]) {
                            let reach = bound(p).max(bound(q));
                            let g = search.measure(p, q, reach);
                            if g > 0.0 && g <= reach {
                                found.gaps.push((p, q, g));
                                bounds[p].fetch_min(g.to_bits(), Ordering::Relaxed);
                                bounds[q].fetch_min(g.to_bits(), Ordering::Relaxed);
                            }
                        }
                    }
                }
                found
            },
        )
        .collect();
    let mut best: Vec<Option<(usize, f64)>> = vec![None; f.len()];
    let (mut meets, mut near, mut covered) = (Vec::new(), Vec::new(), Vec::with_capacity(f.len()));
    for x in found {
        for (p, q, g) in x.gaps {
            offer(&mut best[p], q, g);
            offer(&mut best[q], p, g);
        }
        meets.extend(x.meets);
        near.extend(x.near);
        covered.extend(x.covered);
    }
    meets.sort_by_key(|&(p, q, _)| (p, q));
    // Where each feature's candidates apart start in `near` (`covered` is in
    // the order of the curve, as `near` is).
    let mut start = Vec::with_capacity(f.len() + 1);
    start.push(0);
    for &(_, k) in &covered {
        start.push(start[start.len() - 1] + k);
    }
    // Each feature's search of the boxes apart from its own writes only its
    // own result.
    let apart: Vec<Option<(usize, f64)>> = order
        .par_iter()
        .enumerate()
        .map_init(Vec::new, |cands, (k, &i)| {
            let mut b = best[i];
            search.apart(i, &mut b, cands, &near[start[k]..start[k + 1]], covered[k].0);
            b
        })
        .collect();
    for (&i, b) in order.iter().zip(apart) {
        best[i] = b;
    }
    (best, meets.into_iter().map(|(_, _, d)| d).collect())
}

/// What [`nearest_gaps`]'s first pass finds in a piece of the curve.
struct Found<D> {
    /// Pairs `(i, j, gap)` measured exactly, `i < j`, with a gap above 0.
    gaps: Vec<(usize, usize, f64)>,
    /// What `on_meet` added for the pair `(i, j)`.
    meets: Vec<(usize, usize, D)>,
    /// Each feature's candidates for the second pass that the first pass's
    /// query found: `(box distance, position)`, below what it covered.
    near: Vec<(f64, usize)>,
    /// For each feature of the piece, the box distance below which `near`
    /// holds all its candidates, and how many they are.
    covered: Vec<(f64, usize)>,
}

/// Features per piece of work in [`nearest_gaps`]'s first pass: enough that
/// handing pieces out costs nothing next to measuring them, few enough
/// that the threads stay busy to the end.
const MEET_CHUNK: usize = 32;

/// How far a feature's nearest gap so far leaves its search open.
fn limit(best: Option<(usize, f64)>) -> f64 {
    best.map_or(MIN_GAP_MM, |(_, g)| g)
}

/// Takes gap `g` to feature `k` as `best` when it is a gap (above 0) and
/// nearer (or as near, and `k` first).
fn offer(best: &mut Option<(usize, f64)>, k: usize, g: f64) {
    let nearer = match *best {
        None => g < MIN_GAP_MM,
        Some((m, b)) => g < b || (g == b && k < m),
    };
    if g > 0.0 && nearer {
        *best = Some((k, g));
    }
}

/// The box distances up to which [`GapSearch::apart`] looks for candidates,
/// one ring after another: a dense map gives each feature hundreds of boxes
/// within [`MIN_GAP_MM`], but its nearest gap is most often within the first
/// ring, and taking all of them from the index and sorting them cost as
/// much as measuring the few that matter.
const GAP_RINGS: [f64; 4] = [0.4, 0.8, 1.6, MIN_GAP_MM];

/// What [`nearest_gaps`] searches: the features, an index of their boxes,
/// their outlines prepared for distances, and what a gap needs of each
/// feature side by side in memory (in a dense drawing each feature has
/// hundreds of neighbours, and reading them from the features themselves
/// was a cache miss each).
struct GapSearch<'a> {
    f: &'a [Feature],
    index: &'a spatial::BoxIndex,
    outlines: spatial::OutlineSet,
    /// Which of `outlines` share a vertex (and so touch).
    shared: spatial::SharedVertices,
    probes: Vec<Probe>,
}

/// What [`GapSearch::measure`] reads of a feature for most pairs.
#[derive(Debug, Clone, Copy)]
struct Probe {
    elem: usize,
    /// The first feature of the texture this grating is part of
    /// ([`one_texture`](super::one_texture)), or `usize::MAX`.
    texture: usize,
    half_band: f64,
    /// No dots: the gap is between outlines (after a grating's inside).
    dotless: bool,
    /// Outlines only: no dots, and not a grating (whose inside counts).
    plain: bool,
}

impl Probe {
    fn of(f: &Feature, texture: Option<usize>) -> Self {
        let dotless = f.dots.is_empty();
        let plain = dotless && !matches!(f.kind, FeatureKind::Grating { .. });
        Probe { elem: f.elem, texture: texture.unwrap_or(usize::MAX), half_band: f.half_band, dotless, plain }
    }

    /// Whether a gap between these two is one to feel: they are distinct
    /// elements, and not two parts of one texture (what lies between those
    /// is the same texture, so a nearer one must not hide a farther real gap).
    fn distinct(&self, other: &Probe) -> bool {
        self.elem != other.elem && (self.texture == usize::MAX || self.texture != other.texture)
    }
}

impl GapSearch<'_> {
    /// [`gap`] between features `i` and `j`, measured with the lower
    /// position first whichever side asks.
    fn measure(&self, i: usize, j: usize, reach: f64) -> f64 {
        let (p, q) = (i.min(j), i.max(j));
        let (a, b) = (self.probes[p], self.probes[q]);
        // Outlines that share a vertex are 0 apart, within any band: the
        // gap is at most 0 (a grating's inside would only make it 0), and
        // every rule treats such gaps alike. On a map most neighbours share
        // a border, and finding the first close segments of each pair
        // (measuring up to the nearest gaps, often the whole 3.2 mm, so
        // scanning most segment pairs before reaching the border) was most
        // of the gap rule's time.
        if a.dotless && b.dotless && a.half_band + b.half_band >= 0.0 && self.shared.share(p, q) {
            return 0.0;
        }
        if a.plain && b.plain {
            // `gap` for two outlines, without reading the features.
            let bands = a.half_band + b.half_band;
            return self.outlines.distance(p, q, reach + bands, bands) - bands;
        }
        gap(&self.f[p], &self.f[q], reach, |r, stop| self.outlines.distance(p, q, r, stop))
    }

    /// Lowers feature `i`'s nearest gap `best` to the nearest among the
    /// features of other elements whose boxes do not meet its own but lie
    /// within [`MIN_GAP_MM`], ring by ring. The candidates whose box
    /// distance is below `covered` are `near` (the first pass found them);
    /// the rings beyond come from the index. `cands` is scratch space, kept
    /// by the caller across features.
    fn apart(
        &self,
        i: usize,
        best: &mut Option<(usize, f64)>,
        cands: &mut Vec<(f64, usize)>,
        near: &[(f64, usize)],
        covered: f64,
    ) {
        let a = self.f[i].bbox;
        cands.clear();
        cands.extend_from_slice(near);
        if !self.nearest_of(i, best, cands) || best.is_some_and(|(_, g)| g < covered) {
            return;
        }
        let mut inner = covered;
        for ring in GAP_RINGS.into_iter().filter(|&r| r > covered) {
            // The candidates whose box distance lies in [inner, ring), and
            // none beyond the nearest gap so far.
            cands.clear();
            cands.extend(
                self.index
                    .meeting_boxes(spatial::grow(a, ring.min(limit(*best))))
                    .filter(|&(j, bj)| self.probes[j].distinct(&self.probes[i]) && !spatial::meet(a, bj))
                    .map(|(j, bj)| (spatial::box_distance(bj, a), j))
                    .filter(|&(d, _)| d >= inner && d < ring),
            );
            // Every candidate of the rings beyond lies at least `ring` away.
            if !self.nearest_of(i, best, cands) || best.is_some_and(|(_, g)| g < ring) {
                return;
            }
            inner = ring;
        }
    }

    /// Measures `cands` (`(box distance, position)`) against feature `i`
    /// nearest box first, lowering `best`, until the next box lies farther
    /// than the nearest gap; whether the search should go on (every
    /// candidate was measured).
    fn nearest_of(&self, i: usize, best: &mut Option<(usize, f64)>, cands: &mut [(f64, usize)]) -> bool {
        cands.sort_unstable_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)));
        for &(lower, j) in cands.iter() {
            if let Some((m, g)) = *best
                && (lower > g || (lower == g && j > m))
            {
                // Every later candidate lies farther (or as far and later).
                return false;
            }
            let g = self.measure(i, j, limit(*best));
            offer(best, j, g);
        }
        true
    }
}

/// The gap between two features' footprints (≤ 0 when they touch or overlap),
/// exact when it is at most `reach`; otherwise some value above `reach`.
/// `outline_distance(reach, stop_at)` is [`spatial::min_outline_distance`]
/// between the two outlines (prepared once for all pairs in [`nearest_gaps`]).
pub(super) fn gap(a: &Feature, b: &Feature, reach: f64, outline_distance: impl FnOnce(f64, f64) -> f64) -> f64 {
    // A feature inside a filled region overlaps it, whatever the distance to its outline.
    for (r, o) in [(a, b), (b, a)] {
        if let FeatureKind::Grating { .. } = r.kind {
            let p = o.dots.first().map(|d| (d.0, d.1)).or(o.outline.first().and_then(|p| p.points.first().copied()));
            if p.is_some_and(|p| contains(&r.outline, p, FillRule::NonZero)) {
                return 0.0;
            }
        }
    }
    match (a.dots.is_empty(), b.dots.is_empty()) {
        (true, true) => {
            // Outlines that touch or cross need no exact distance: every rule treats them alike.
            let bands = a.half_band + b.half_band;
            outline_distance(reach + bands, bands) - bands
        }
        (false, true) | (true, false) => {
            let (d, m) = if a.dots.is_empty() { (b, a) } else { (a, b) };
            // A dot's gap is at most `reach` when its centre is within
            // `reach` plus its radius and the band of the outline.
            // A dot that reaches into the outline's band settles the gap at
            // or below 0, and every rule treats such gaps alike.
            let mut best = f64::INFINITY;
            for &(x, y, r) in &d.dots {
                let within = |stop| distance_to_outline_within(&m.outline, (x, y), reach + r + m.half_band, stop);
                let touch = r + m.half_band;
                let mut dist = within(touch);
                if dist <= touch && dist - r - m.half_band > 0.0 {
                    // Stopped at a distance that rounds to a gap above 0:
                    // the exact one decides.
                    dist = within(f64::NEG_INFINITY);
                }
                best = best.min(dist - r - m.half_band);
                if best <= 0.0 {
                    break;
                }
            }
            best
        }
        (false, false) => {
            let mut best = f64::INFINITY;
            near_dot_pairs(a, b, MIN_GAP_MM, |p, q| best = best.min(dist((p.0, p.1), (q.0, q.1)) - p.2 - q.2));
            best
        }
    }
}

/// Calls `f` for every pair of dots (one of `a`, one of `b`) whose discs come
/// within `reach` of each other, using a grid so the work stays near linear.
pub(super) fn near_dot_pairs(
    a: &Feature,
    b: &Feature,
    reach: f64,
    mut f: impl FnMut((f64, f64, f64), (f64, f64, f64)),
) {
    let rmax = a.dots.iter().chain(&b.dots).map(|d| d.2).fold(0.0, f64::max);
    let cell = (2.0 * rmax + reach).max(1e-3);
    let key = |x: f64, y: f64| ((x / cell).floor() as i64, (y / cell).floor() as i64);
    let mut grid: std::collections::HashMap<(i64, i64), Vec<usize>> = std::collections::HashMap::new();
    for (i, d) in b.dots.iter().enumerate() {
        grid.entry(key(d.0, d.1)).or_default().push(i);
    }
    for &p in &a.dots {
        let (kx, ky) = key(p.0, p.1);
        for x in kx - 1..=kx + 1 {
            for y in ky - 1..=ky + 1 {
                for &j in grid.get(&(x, y)).into_iter().flatten() {
                    f(p, b.dots[j]);
                }
            }
        }
    }
}
