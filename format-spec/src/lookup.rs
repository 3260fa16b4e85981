//! The point lookup: which source element lies under a surface point, from a
//! bundle's footprints (`FOOT`, SPEC.md section 10.1) and provenance.
//!
//! [`PointLookup::new`] builds an R-tree (`rstar`) over the bounding boxes of
//! the footprint rings once; [`PointLookup::under`] asks it for the shapes
//! whose boxes hold the point, tests each exactly, and returns the topmost
//! in drawing order. A host uses it to name what the finger is on.

use std::string::String;
use std::vec::Vec;

use rstar::RTree;
use rstar::primitives::{GeomWithData, Rectangle};

use crate::footprint::{FootprintKind, FootprintView};
use crate::provenance::{ProvenanceEntry, ProvenanceView};
use crate::view::BundleView;

/// One shape, decoded to f64 page millimetres.
#[derive(Debug, Clone)]
struct Shape {
    source: u32,
    kind: FootprintKind,
    /// The band's half width, widened to the tolerance for lines.
    reach: f64,
    rings: Vec<Vec<(f64, f64)>>,
}

/// What lies under a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit<'a> {
    /// The footprint shape that was hit (its index in the chunk, bottom first).
    pub shape: usize,
    /// The provenance entry it belongs to.
    pub source: u32,
    /// That entry, when the bundle has it.
    pub entry: Option<&'a ProvenanceEntry>,
}

impl Hit<'_> {
    /// The element's name: its label (`<title>`, `inkscape:label`,
    /// `aria-label`), else its id, else `entry N`.
    pub fn name(&self) -> String {
        match self.entry {
            Some(e) if !e.label.is_empty() => e.label.clone(),
            Some(e) if !e.id.is_empty() => e.id.clone(),
            _ => std::format!("entry {}", self.source),
        }
    }
}

/// A spatial index over a bundle's footprints.
#[derive(Debug)]
pub struct PointLookup {
    shapes: Vec<Shape>,
    tree: RTree<GeomWithData<Rectangle<[f64; 2]>, u32>>,
    entries: Vec<ProvenanceEntry>,
}

impl PointLookup {
    /// The tolerance a host uses unless it has a reason not to: lines and
    /// dots thinner than 1 mm are found within 0.5 mm of their centre line.
    pub const DEFAULT_TOLERANCE_MM: f64 = 0.5;

    /// The lookup of a bundle, or `None` when it has no footprints.
    /// Lines (strokes, outlines, dots) are found within their own half width
    /// or `tolerance_mm` of their centre line, whichever is larger; regions
    /// exactly (and within their own half width of the outline).
    pub fn new(view: &BundleView<'_>, tolerance_mm: f64) -> Option<Self> {
        Some(Self::from_views(&view.footprints()?, view.provenance(), tolerance_mm))
    }

    /// The lookup of a footprint chunk and the provenance it refers to.
    pub fn from_views(
        footprints: &FootprintView<'_>,
        provenance: Option<ProvenanceView<'_>>,
        tolerance_mm: f64,
    ) -> Self {
        let tolerance = if tolerance_mm.is_finite() { tolerance_mm.max(0.0) } else { 0.0 };
        let mut shapes = Vec::with_capacity(footprints.len() as usize);
        let mut boxes = Vec::new();
        for (i, s) in footprints.shapes().enumerate() {
            let own = s.half_width_mm() as f64;
            let reach = if s.kind.is_area() { own } else { own.max(tolerance) };
            let rings: Vec<Vec<(f64, f64)>> =
                s.rings().map(|r| r.points_mm().map(|(x, y)| (x as f64, y as f64)).collect()).collect();
            for r in &rings {
                let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
                for &(x, y) in r {
                    (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
                }
                if x0 <= x1 && y0 <= y1 {
                    let rect = Rectangle::from_corners([x0 - reach, y0 - reach], [x1 + reach, y1 + reach]);
                    boxes.push(GeomWithData::new(rect, i as u32));
                }
            }
            shapes.push(Shape { source: s.source, kind: s.kind, reach, rings });
        }
        let entries = provenance
            .map(|p| {
                (0..p.len())
                    .filter_map(|i| {
                        let (id, label, line) = p.get(i)?;
                        Some(ProvenanceEntry { id: id.into(), label: label.into(), line })
                    })
                    .collect()
            })
            .unwrap_or_default();
        PointLookup { shapes, tree: RTree::bulk_load(boxes), entries }
    }

    /// Number of footprint shapes.
    pub fn len(&self) -> usize {
        self.shapes.len()
    }

    /// Whether there are no shapes.
    pub fn is_empty(&self) -> bool {
        self.shapes.is_empty()
    }

    /// The topmost element (in drawing order) whose footprint covers page
    /// point `(x, y)` mm, or `None`.
    pub fn under(&self, x: f64, y: f64) -> Option<Hit<'_>> {
        if !(x.is_finite() && y.is_finite()) {
            return None;
        }
        let probe = rstar::AABB::from_point([x, y]);
        let top = self
            .tree
            .locate_in_envelope_intersecting(&probe)
            .map(|g| g.data as usize)
            .filter(|&i| self.covers(i, x, y))
            .max()?;
        Some(self.hit(top))
    }

    /// Every element whose footprint covers `(x, y)`, topmost first (each shape once).
    pub fn all_under(&self, x: f64, y: f64) -> Vec<Hit<'_>> {
        if !(x.is_finite() && y.is_finite()) {
            return Vec::new();
        }
        let probe = rstar::AABB::from_point([x, y]);
        let mut found: Vec<usize> =
            self.tree.locate_in_envelope_intersecting(&probe).map(|g| g.data as usize).collect();
        found.sort_unstable_by(|a, b| b.cmp(a));
        found.dedup();
        found.into_iter().filter(|&i| self.covers(i, x, y)).map(|i| self.hit(i)).collect()
    }

    fn hit(&self, shape: usize) -> Hit<'_> {
        let source = self.shapes.get(shape).map_or(u32::MAX, |s| s.source);
        Hit { shape, source, entry: self.entries.get(source as usize) }
    }

    /// The exact test: whether shape `shape` covers `(x, y)`. An area covers
    /// its inside (by its fill rule) and the band of its half width around
    /// its rings; a line the band of its reach around each ring (a closed
    /// line's ring also from its last point back to its first).
    pub fn covers(&self, shape: usize, x: f64, y: f64) -> bool {
        let Some(s) = self.shapes.get(shape) else { return false };
        let p = (x, y);
        let closed = s.kind != FootprintKind::Line;
        let near = s.rings.iter().any(|r| ring_distance(r, p, closed) <= s.reach);
        near || match s.kind {
            FootprintKind::AreaNonZero => s.rings.iter().map(|r| winding(r, p)).sum::<i64>() != 0,
            FootprintKind::AreaEvenOdd => s.rings.iter().map(|r| winding(r, p)).sum::<i64>() % 2 != 0,
            _ => false,
        }
    }
}

/// The distance from `p` to a ring's polyline (closed: with its closing segment).
fn ring_distance(r: &[(f64, f64)], p: (f64, f64), closed: bool) -> f64 {
    let Some(&first) = r.first() else { return f64::INFINITY };
    let mut best = dist(first, p);
    for w in r.windows(2) {
        best = best.min(segment_distance(p, w[0], w[1]));
    }
    if closed && let Some(&last) = r.last() {
        best = best.min(segment_distance(p, last, first));
    }
    best
}

fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

fn segment_distance(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    if len2 == 0.0 {
        return dist(a, p);
    }
    let t = (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0);
    dist((a.0 + t * dx, a.1 + t * dy), p)
}

/// The winding number of a closed ring around `p` (crossings of the ray to +x).
fn winding(r: &[(f64, f64)], p: (f64, f64)) -> i64 {
    let mut w = 0i64;
    for i in 0..r.len() {
        let a = r[i];
        let b = r[(i + 1) % r.len()];
        let side = (b.0 - a.0) * (p.1 - a.1) - (p.0 - a.0) * (b.1 - a.1);
        if a.1 <= p.1 {
            if b.1 > p.1 && side > 0.0 {
                w += 1;
            }
        } else if b.1 <= p.1 && side < 0.0 {
            w -= 1;
        }
    }
    w
}
