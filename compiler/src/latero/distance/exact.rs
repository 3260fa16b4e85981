//! The exact region of a layer and the exact distance to its edge, in f64,
//! indexed for point queries: what a built field is measured against.
//!
//! A field plays a signed distance sampled on a lattice; this is the region
//! it stands for, evaluated at any point from the layer's own geometry (the
//! [`LayerGeometry`] the field is built from), with no lattice, no
//! quantisation and no clamping. Each part's segments are kept in an R*-tree
//! of their boxes ([`BoxIndex`]), so a query looks only at the segments
//! near the point.

use crate::geometry::{Crossings, FillRule, Polyline, SideRows, offset_to_segment};
use crate::spatial::{Bbox, BoxIndex};

use super::LayerGeometry;

/// A segment `(a, b)` in page mm.
pub type Segment = ((f64, f64), (f64, f64));

/// How close to an exact edge a point counts as on it, and the step across
/// an edge that tells its two sides apart, mm: far below any position a
/// player is given (an `f32` at 100 mm resolves 7.6e-6 mm).
pub const ON_EDGE_MM: f64 = 1e-7;

/// The exact region of one layer (one style), from its [`LayerGeometry`]
/// by [`LayerGeometry::exact`]: where the layer is felt, and how far a
/// point is from the edge of that region. Coordinates and distances are
/// page millimetres, y down.
///
/// The region is the union of the fills (each with its fill rule) and of
/// the band (every point within half the band's width of a centre line),
/// inside every clip, less every cut band and every occluder. Nothing clips
/// it to the page: the caller bounds it (the field builder by the page of
/// its parameters, `taxel report` by the device's surface).
///
/// The **edge** is where coverage changes: a side two fills of the style
/// share, or the end of a centre line inside another band, lies inside the
/// region and is no edge. The signed distance is positive where the layer is
/// felt. It is measured to the nearest point of each part's outline (a
/// fill's, clip's or occluder's side, or a band's offset at half its width)
/// that is on the edge: where the coverage differs a step of [`ON_EDGE_MM`]
/// to either side of it, along the line to the point. That misses an edge
/// point, so that the distance may be larger than the true one but never
/// smaller, in two places: where the nearest point of an outline is not on
/// the edge (it lies inside another part: near where two parts' outlines
/// cross), and from the points whose nearest point is the vertex of a corner
/// sharper than a right angle (the step back from the vertex may stay on the
/// same side). The signed distance the field builder samples (the parts
/// composed by `min` and `max`, SPEC.md section 6.2, before the page and
/// the clamping) has the same sign and is never larger in size.
///
/// ```
/// use taxel_compiler::geometry::{FillRule, Polyline};
/// use taxel_compiler::latero::LayerGeometry;
///
/// let square = [Polyline { points: vec![(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)], closed: true }];
/// let g = LayerGeometry { fills: vec![(&square[..], FillRule::NonZero)], ..Default::default() };
/// let exact = g.exact();
/// assert!(exact.covers((2.0, 5.0)) && !exact.covers((-1.0, 5.0)));
/// // 2 mm inside the left side, 1 mm outside it.
/// assert_eq!(exact.signed_distance((2.0, 5.0)), 2.0);
/// assert_eq!(exact.signed_distance((-1.0, 5.0)), -1.0);
/// // Within a reach only: the nearest edge is 2 mm away.
/// assert_eq!(exact.distance_to_edge_within((2.0, 5.0), 1.0), None);
/// ```
#[derive(Debug)]
pub struct ExactRegion {
    /// The fills' outlines (each subpath closed) and their fill rules.
    fills: Vec<(Outlines, FillRule)>,
    /// The band's centre lines (all of them, of one width) and its width, mm.
    band: Option<(Outlines, f64)>,
    /// The cut bands' centre lines and widths, mm.
    cuts: Vec<(Outlines, f64)>,
    /// The clips' outlines and fill rules.
    clips: Vec<(Outlines, FillRule)>,
    /// The occluders' outlines and fill rules.
    occluders: Vec<(Outlines, FillRule)>,
    /// Where a layer has many parts (a map's regions of one style, the
    /// regions painted over it): the boxes of the fills, the occluders,
    /// and every fill, occluder and clip in [`ExactRegion::parts`]'s order,
    /// so that a point asks only the parts whose box it is in or near.
    index: Option<PartIndex>,
}

/// [`ExactRegion::index`]: the parts' boxes, by position in their lists.
#[derive(Debug)]
struct PartIndex {
    fills: BoxIndex,
    occluders: BoxIndex,
    sides: BoxIndex,
}

/// Most parts a region asks one by one; past it, through [`PartIndex`]
/// (300 grated slivers of a map in two layers: `taxel report` spent half
/// its time asking every one of them at every point).
const UNINDEXED_PARTS: usize = 16;

impl LayerGeometry<'_> {
    /// The exact region of this geometry, indexed for point queries
    /// ([`ExactRegion`]); it owns copies of the segments, so it outlives the
    /// drawing it was planned from.
    pub fn exact(&self) -> ExactRegion {
        let filled = |parts: &[(&[Polyline], FillRule)]| {
            parts.iter().map(|&(pls, rule)| (Outlines::new([pls], true), rule)).collect::<Vec<_>>()
        };
        let mut region = ExactRegion {
            fills: filled(&self.fills),
            band: self.band.as_ref().map(|(lines, w)| (Outlines::new(lines.iter().copied(), false), *w)),
            cuts: self.cuts.iter().map(|&(lines, w)| (Outlines::new([lines], false), w)).collect(),
            clips: filled(&self.clips),
            occluders: filled(&self.occluders),
            index: None,
        };
        if region.fills.len() + region.occluders.len() + region.clips.len() > UNINDEXED_PARTS {
            // (A part with no segment has no box: it contains nothing and
            // is near nothing, and an inverted box is left out of the index.)
            let boxes = |parts: &[(Outlines, FillRule)]| -> Vec<Bbox> {
                parts.iter().map(|(o, _)| o.bounds.unwrap_or((1.0, 1.0, 0.0, 0.0))).collect()
            };
            let sides: Vec<Bbox> =
                [&region.fills, &region.occluders, &region.clips].into_iter().flat_map(|p| boxes(p)).collect();
            region.index = Some(PartIndex {
                fills: BoxIndex::new(&boxes(&region.fills)),
                occluders: BoxIndex::new(&boxes(&region.occluders)),
                sides: BoxIndex::new(&sides),
            });
        }
        region
    }
}

/// The parts of `parts` whose boxes may hold `p` (all of them where `index` is `None`).
fn holding<'a>(
    parts: &'a [(Outlines, FillRule)],
    index: Option<&'a BoxIndex>,
    p: (f64, f64),
) -> impl Iterator<Item = &'a (Outlines, FillRule)> + 'a {
    let (all, some) = match index {
        Some(ix) => (&parts[..0], Some(ix.meeting((p.0, p.1, p.0, p.1)).filter_map(|k| parts.get(k)))),
        None => (parts, None),
    };
    all.iter().chain(some.into_iter().flatten())
}

impl ExactRegion {
    /// Whether the layer is felt at page point `p` (exact coverage, 0 or
    /// 1): inside a fill (by the crossing rule of
    /// [`geometry::contains`](crate::geometry::contains)) or within half
    /// the band's width of a centre line, inside every clip, and neither
    /// within half a cut band's width of its centre line nor inside an
    /// occluder.
    pub fn covers(&self, p: (f64, f64)) -> bool {
        // (A point outside a part's box is outside the part: only those
        // whose box holds it are asked.)
        let ix = self.index.as_ref();
        let felt = holding(&self.fills, ix.map(|i| &i.fills), p).any(|(f, rule)| f.contains(p, *rule))
            || self.band.as_ref().is_some_and(|(b, w)| b.within(p, w / 2.0));
        felt && self.clips.iter().all(|(c, rule)| c.contains(p, *rule))
            && !self.cuts.iter().any(|(b, w)| b.within(p, w / 2.0))
            && !holding(&self.occluders, ix.map(|i| &i.occluders), p).any(|(f, rule)| f.contains(p, *rule))
    }

    /// Every outline bounding a part, as a fill's (its segments) or a band's
    /// (its centre lines and width); of the fills, occluders and clips, only
    /// those whose boxes come within `r` of `p` where the region is indexed
    /// (a part farther has no segment within `r` of it), all of them where
    /// `r` is not finite.
    fn parts(
        &self,
        p: (f64, f64),
        r: f64,
    ) -> (impl Iterator<Item = &Outlines>, impl Iterator<Item = (&Outlines, f64)>) {
        let lists = [&self.fills, &self.occluders, &self.clips];
        let near = self.index.as_ref().filter(|_| r.is_finite()).map(|i| {
            i.sides.meeting((p.0 - r, p.1 - r, p.0 + r, p.1 + r)).filter_map(move |mut k| {
                // Position `k` in the three lists, one after another.
                for list in lists {
                    match list.get(k) {
                        Some((f, _)) => return Some(f),
                        None => k -= list.len(),
                    }
                }
                None
            })
        });
        let all = near.is_none().then(|| lists.into_iter().flat_map(|l| l.iter().map(|(f, _)| f)));
        let sides = all.into_iter().flatten().chain(near.into_iter().flatten());
        let bands = self.band.iter().chain(&self.cuts).map(|(b, w)| (b, *w));
        (sides, bands)
    }

    /// Whether an edge of the region may pass within `r` mm of `p`: a
    /// fill's, clip's or occluder's outline within `r`, or a band's centre
    /// line within `r` plus its half width. Where not, the coverage is the
    /// same over the whole disc of radius `r` round `p` (it changes only
    /// across those lines): a cheap index query, so that callers test the
    /// coverage round `p` only where it may change.
    pub fn edge_may_pass_within(&self, p: (f64, f64), r: f64) -> bool {
        let (mut sides, mut bands) = self.parts(p, r);
        sides.any(|f| f.within(p, r)) || bands.any(|(b, w)| b.within(p, r + w / 2.0))
    }

    /// The distance from `p` to the region's edge, mm, when it is less than
    /// `reach` mm, else `None` (also for a `reach` that is NaN or not above
    /// 0). Candidates are the nearest points of every outline segment (a
    /// fill's, clip's or occluder's side, or the offset of a band's centre
    /// line at half its width) within reach; a candidate is on the edge when
    /// the coverage differs [`ON_EDGE_MM`] to either side of it.
    pub fn distance_to_edge_within(&self, p: (f64, f64), reach: f64) -> Option<f64> {
        if reach.is_nan() || reach <= 0.0 {
            return None;
        }
        let mut best = f64::INFINITY;
        let mut consider = |q: (f64, f64), across: (f64, f64)| {
            let d = length(p.0 - q.0, p.1 - q.1);
            if d >= reach || d >= best {
                return;
            }
            // Across the edge: away from `p` where `p` is off it, else the side's normal.
            let u = if d > ON_EDGE_MM { ((p.0 - q.0) / d, (p.1 - q.1) / d) } else { across };
            let s = ON_EDGE_MM;
            if self.covers((q.0 + s * u.0, q.1 + s * u.1)) != self.covers((q.0 - s * u.0, q.1 - s * u.1)) {
                best = d;
            }
        };
        let (sides, bands) = self.parts(p, reach);
        for f in sides {
            for (a, c) in f.near(p, reach) {
                consider(nearest_on_segment(p, a, c), unit(a.1 - c.1, c.0 - a.0));
            }
        }
        // A band's edge nearest `p` along each centre-line segment: half
        // the width from the segment's point nearest `p`, on the side of `p`.
        for (b, w) in bands {
            let r = w / 2.0;
            for (a, c) in b.near(p, reach + r) {
                let m = nearest_on_segment(p, a, c);
                let l = length(p.0 - m.0, p.1 - m.1);
                if l > ON_EDGE_MM {
                    let u = ((p.0 - m.0) / l, (p.1 - m.1) / l);
                    consider((m.0 + u.0 * r, m.1 + u.1 * r), u);
                } else {
                    // `p` on the centre line: the edge is `r` away on either side.
                    let n = unit(a.1 - c.1, c.0 - a.0);
                    consider((m.0 + n.0 * r, m.1 + n.1 * r), n);
                    consider((m.0 - n.0 * r, m.1 - n.1 * r), (-n.0, -n.1));
                }
            }
        }
        best.is_finite().then_some(best)
    }

    /// The signed distance from `p` to the region's edge, mm, positive where
    /// the layer is felt ([`ExactRegion::covers`]): ± the
    /// [`distance_to_edge_within`](Self::distance_to_edge_within) any reach,
    /// found by widening the reach. A region with no edge (nothing, or a
    /// region whose every outline lies inside another part) gives
    /// `-∞` or `+∞`.
    pub fn signed_distance(&self, p: (f64, f64)) -> f64 {
        let sign = if self.covers(p) { 1.0 } else { -1.0 };
        // Every candidate lies within the outlines' bounds grown by the widest half band.
        let (sides, bands) = self.parts(p, f64::INFINITY);
        let mut far = 0.0f64;
        let mut grow = |b: Option<Bbox>, m: f64| {
            if let Some(b) = b {
                let dx = (p.0 - b.0).abs().max((p.0 - b.2).abs()) + m;
                let dy = (p.1 - b.1).abs().max((p.1 - b.3).abs()) + m;
                far = far.max(dx.hypot(dy));
            }
        };
        sides.for_each(|f| grow(f.bounds, 0.0));
        bands.for_each(|(b, w)| grow(b.bounds, w / 2.0));
        if !far.is_finite() {
            return f64::NAN;
        }
        let mut reach = 1.0f64;
        loop {
            // Strictly beyond the farthest candidate, so that it is within reach.
            let r = reach.min(far * 2.0 + 1.0);
            if let Some(d) = self.distance_to_edge_within(p, r) {
                return sign * d;
            }
            if r > far {
                return sign * f64::INFINITY;
            }
            reach *= 8.0;
        }
    }

    /// Segments on which every point of the region's edge lies (a superset
    /// of it), in page mm: the band's and cut bands' two offset lines and
    /// the arcs round their centre lines' vertices that may be on the edge
    /// (polygons of chords within `sagitta` mm of the circle, at most 4,096
    /// to a whole circle), and the fills', occluders' and clips' outlines.
    pub fn edge_candidates(&self, sagitta: f64) -> Vec<Segment> {
        let mut out = Vec::new();
        let band = |b: &Outlines, w: f64, out: &mut Vec<Segment>| {
            let r = w / 2.0;
            // The directions of the segments from each vertex.
            let mut at: std::collections::HashMap<(u64, u64), Vec<(f64, f64)>> = std::collections::HashMap::new();
            for &(a, b) in &b.segs {
                let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                let len = dx.hypot(dy);
                if len > 0.0 {
                    let (nx, ny) = (-dy / len * r, dx / len * r);
                    out.push(((a.0 + nx, a.1 + ny), (b.0 + nx, b.1 + ny)));
                    out.push(((a.0 - nx, a.1 - ny), (b.0 - nx, b.1 - ny)));
                    at.entry((a.0.to_bits(), a.1.to_bits())).or_default().push((dx / len, dy / len));
                    at.entry((b.0.to_bits(), b.1.to_bits())).or_default().push((-dx / len, -dy / len));
                } else {
                    at.entry((a.0.to_bits(), a.1.to_bits())).or_default();
                }
            }
            let mut vertices: Vec<_> = at.into_iter().collect();
            vertices.sort_by_key(|x| x.0);
            for ((x, y), dirs) in vertices {
                join(((f64::from_bits(x)), f64::from_bits(y)), &dirs, r, sagitta, out);
            }
        };
        if let Some((b, w)) = &self.band {
            band(b, *w, &mut out);
        }
        for (f, _) in self.fills.iter().chain(&self.occluders).chain(&self.clips) {
            out.extend_from_slice(&f.segs);
        }
        for (b, w) in &self.cuts {
            band(b, *w, &mut out);
        }
        out
    }
}

/// The arc of the circle of radius `r` round a centre-line vertex `c` that
/// may be on a band's edge, as chords that stay within `sagitta` of it: a
/// point `c + r u` with `u · d > 0` for a segment leaving `c` along `d` is
/// nearer than `r` to that segment, so inside the band; what is left is the
/// arc where `u · d ≤ 0` for every such `d` (an open end's round cap, a
/// bend's round join on its outer side, nothing much where the line goes
/// straight on). A lone point (no direction) keeps the whole circle. Only
/// that arc: a circle flattened finely has thousands of vertices, and whole
/// circles round each made the report's outline millions of chords.
fn join(c: (f64, f64), dirs: &[(f64, f64)], r: f64, sagitta: f64, out: &mut Vec<Segment>) {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};
    if !(r.is_finite() && r > 0.0) {
        return;
    }
    // Each direction allows the half circle [θ + π/2, θ + 3π/2] of angles;
    // their intersection is one arc (each is half the circle) or nothing.
    let (mut s, mut e) = (0.0, TAU);
    for (k, &(dx, dy)) in dirs.iter().enumerate() {
        let from = dy.atan2(dx) + FRAC_PI_2;
        if k == 0 {
            (s, e) = (from, from + PI);
            continue;
        }
        // The copy of the allowed half circle that may overlap [s, e].
        let from = from + ((s - from) / TAU + 0.5).floor() * TAU;
        let from = if from > s + PI - 1e-12 { from - TAU } else { from };
        (s, e) = (s.max(from), e.min(from + PI));
        if s > e {
            return;
        }
    }
    // Sagitta of a chord over the angle a: r (1 − cos(a/2)) ≈ r a² / 8.
    let step = (8.0 * sagitta.max(1e-9) / r).sqrt().max(TAU / 4096.0);
    let n = ((e - s) / step).ceil().max(1.0) as usize;
    let at = |k: usize| {
        let a = s + (e - s) * k as f64 / n as f64;
        (c.0 + r * a.cos(), c.1 + r * a.sin())
    };
    for k in 0..n {
        out.push((at(k), at(k + 1)));
    }
}

/// The point of segment `a`–`b` nearest `p`.
/// The length of `(x, y)`: the square root of the sum of squares, within an
/// ulp of `hypot` for mm-scale coordinates at a fraction of its cost (the
/// report measures millions of distances).
pub(crate) fn length(x: f64, y: f64) -> f64 {
    (x * x + y * y).sqrt()
}

fn nearest_on_segment(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    if len2.is_nan() || len2 <= 0.0 {
        return a;
    }
    let t = (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0);
    (a.0 + t * dx, a.1 + t * dy)
}

/// `(x, y)` scaled to length 1 (0 stays 0).
fn unit(x: f64, y: f64) -> (f64, f64) {
    let l = x.hypot(y);
    if l > 0.0 { (x / l, y / l) } else { (0.0, 0.0) }
}

/// One part's segments with an index of their boxes.
#[derive(Debug)]
struct Outlines {
    /// The segments, in the order of the polylines and their points.
    segs: Vec<Segment>,
    /// Their boxes, by position in `segs`.
    index: BoxIndex,
    /// The box of every segment, `None` when there is none.
    bounds: Option<Bbox>,
    /// A fill's sides filed by strips, for the crossing test (`None` for a
    /// band, or where a coordinate is not finite: the index then).
    rows: Option<SideRows>,
}

impl Outlines {
    /// The segments of `sets`' polylines: a fill's close every subpath (as
    /// [`geometry::contains`](crate::geometry::contains) does), a band's
    /// only the closed (`Z`) ones of more than two points; a single point is
    /// a segment of no length. Segments with a coordinate that is not
    /// finite are left out.
    fn new<'a>(sets: impl IntoIterator<Item = &'a [Polyline]>, fill: bool) -> Outlines {
        let sets: Vec<&[Polyline]> = sets.into_iter().collect();
        let rows = if fill { SideRows::new(sets.iter().copied().flatten()) } else { None };
        let mut segs = Vec::new();
        for pl in sets.into_iter().flatten() {
            let n = pl.points.len();
            if n == 1 {
                segs.push((pl.points[0], pl.points[0]));
            }
            let closing = if fill { n >= 2 } else { pl.closed && n > 2 };
            for i in 0..n.saturating_sub(1) + usize::from(closing) {
                segs.push((pl.points[i], pl.points[(i + 1) % n]));
            }
        }
        segs.retain(|(a, b)| a.0.is_finite() && a.1.is_finite() && b.0.is_finite() && b.1.is_finite());
        let boxes: Vec<Bbox> =
            segs.iter().map(|&(a, b)| (a.0.min(b.0), a.1.min(b.1), a.0.max(b.0), a.1.max(b.1))).collect();
        let bounds = boxes.iter().copied().reduce(|a, b| (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3)));
        Outlines { index: BoxIndex::new(&boxes), segs, bounds, rows }
    }

    /// Whether `p` is inside, by the crossing rule of `geometry::contains`:
    /// the segments that cross the ray from `p` towards +x are those whose
    /// boxes meet it.
    fn contains(&self, p: (f64, f64), rule: FillRule) -> bool {
        let Some(b) = self.bounds else { return false };
        // Nothing crosses the ray from a point right of every segment, above
        // or below them all, or from NaN (a cheap test first: a layer's
        // every fill and occluder is asked at every point).
        if p.0.is_nan() || p.1.is_nan() || p.0 > b.2 || p.1 < b.1 || p.1 > b.3 {
            return false;
        }
        if let Some(rows) = &self.rows {
            return rows.contains(p, rule);
        }
        let mut ray = Crossings::default();
        for k in self.index.meeting((p.0, p.1, b.2, p.1)) {
            let (a, b) = self.segs[k];
            ray.side(p, a, b);
        }
        ray.inside(rule)
    }

    /// The segments whose boxes come within `r` mm of `p` in both axes (a
    /// superset of those within `r` of it), each once, in no particular
    /// order; none for an `r` that is NaN or below 0.
    fn near(&self, p: (f64, f64), r: f64) -> impl Iterator<Item = Segment> + '_ {
        // (A query that misses every segment's box is answered without the index.)
        let query = match self.bounds {
            Some(b) if r >= 0.0 && p.0 + r >= b.0 && p.0 - r <= b.2 && p.1 + r >= b.1 && p.1 - r <= b.3 => {
                Some((p.0 - r, p.1 - r, p.0 + r, p.1 + r))
            }
            _ => None,
        };
        // (An infinite reach makes a box the index refuses: every segment is near.)
        let all = query.is_some() && !r.is_finite();
        let found = query.filter(|_| !all).into_iter().flat_map(|q| self.index.meeting(q)).map(|k| self.segs[k]);
        found.chain(if all { &self.segs[..] } else { &[] }.iter().copied())
    }

    /// Whether `p` is within `r` mm of a segment (its distance as
    /// [`length`] measures it, as the distances to the edge are).
    fn within(&self, p: (f64, f64), r: f64) -> bool {
        self.near(p, r).any(|(a, b)| {
            let e = offset_to_segment(p, a, b);
            length(e.0, e.1) <= r
        })
    }
}

#[cfg(test)]
mod tests;
