//! Footprints (`FOOT`): where each provenance entry lies on the surface, as
//! simplified quantised geometry, so that a host can name the element under
//! a point (SPEC.md section 10.1). Optional; a device may skip it.

use alloc::vec::Vec;

use crate::bytes::{Out, f32_at, u8_at, u16_at, u32_at};
use crate::error::FormatError;
use crate::{NO_SOURCE, Tag, in_range};

/// Length of the chunk's header.
const HEADER_LEN: usize = 24;
/// Length of one shape entry.
const SHAPE_LEN: usize = 12;
/// Largest number of shapes in one footprint chunk.
pub const MAX_FOOTPRINT_SHAPES: u32 = 1 << 20;
/// Largest number of rings in one footprint chunk.
pub const MAX_FOOTPRINT_RINGS: u32 = 1 << 22;
/// Largest number of points in one footprint chunk.
pub const MAX_FOOTPRINT_POINTS: u32 = 1 << 24;

/// How a shape covers the surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FootprintKind {
    /// A filled region: inside its rings by the non-zero rule (code 0).
    AreaNonZero,
    /// A filled region: inside its rings by the even-odd rule (code 1).
    AreaEvenOdd,
    /// Open polylines with a half width; a one-point ring is a disc (code 2).
    Line,
    /// Closed polylines with a half width (code 3).
    ClosedLine,
}

impl FootprintKind {
    /// The kind's code in the chunk.
    pub fn code(self) -> u8 {
        match self {
            FootprintKind::AreaNonZero => 0,
            FootprintKind::AreaEvenOdd => 1,
            FootprintKind::Line => 2,
            FootprintKind::ClosedLine => 3,
        }
    }

    /// The kind of a code, if it is one.
    pub fn from_code(code: u8) -> Option<Self> {
        Some(match code {
            0 => FootprintKind::AreaNonZero,
            1 => FootprintKind::AreaEvenOdd,
            2 => FootprintKind::Line,
            3 => FootprintKind::ClosedLine,
            _ => return None,
        })
    }

    /// Whether the shape is a filled region.
    pub fn is_area(self) -> bool {
        matches!(self, FootprintKind::AreaNonZero | FootprintKind::AreaEvenOdd)
    }

    /// The fewest points a ring of this kind has.
    pub fn min_ring_points(self) -> u32 {
        if self.is_area() { 3 } else { 1 }
    }
}

/// One shape: the footprint of one rendered style of one source element.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Footprint {
    /// The provenance entry it belongs to.
    pub source: u32,
    /// How it covers the surface.
    pub kind: FootprintKind,
    /// Half the width of the band around its rings that it also covers, in quanta.
    pub half_width: u16,
    /// Its rings, each a list of quantised points `(x, y)`.
    pub rings: Vec<Vec<(u16, u16)>>,
}

/// The footprints of a bundle's provenance entries, in drawing order
/// (later shapes lie on top). Point `(x, y)` stands for page position
/// `(origin_x + x * quantum, origin_y + y * quantum)` mm.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Footprints {
    /// Page x of quantised point 0, mm.
    pub origin_x: f32,
    /// Page y of quantised point 0, mm.
    pub origin_y: f32,
    /// Millimetres per quantum.
    pub quantum_mm: f32,
    /// The shapes, bottom first.
    pub shapes: Vec<Footprint>,
}

impl Footprints {
    pub(crate) fn encode(&self) -> Vec<u8> {
        let rings: usize = self.shapes.iter().map(|s| s.rings.len()).sum();
        let points: usize = self.shapes.iter().flat_map(|s| &s.rings).map(|r| r.len()).sum();
        let mut out = Vec::with_capacity(HEADER_LEN + SHAPE_LEN * self.shapes.len() + 4 * rings + 4 * points);
        let mut w = Out(&mut out);
        w.u32(self.shapes.len() as u32)
            .u32(rings as u32)
            .u32(points as u32)
            .f32(self.quantum_mm)
            .f32(self.origin_x)
            .f32(self.origin_y);
        for s in &self.shapes {
            w.u32(s.source).u8(s.kind.code()).u8(0).u16(s.half_width).u32(s.rings.len() as u32);
        }
        for r in self.shapes.iter().flat_map(|s| &s.rings) {
            w.u32(r.len() as u32);
        }
        for &(x, y) in self.shapes.iter().flat_map(|s| &s.rings).flatten() {
            w.u16(x).u16(y);
        }
        out
    }

    pub(crate) fn from_view(v: &FootprintView<'_>) -> Self {
        Footprints {
            origin_x: v.origin_x,
            origin_y: v.origin_y,
            quantum_mm: v.quantum_mm,
            shapes: v
                .shapes()
                .map(|s| Footprint {
                    source: s.source,
                    kind: s.kind,
                    half_width: s.half_width,
                    rings: s.rings().map(|r| r.quanta().collect()).collect(),
                })
                .collect(),
        }
    }

    /// Page position in mm of quantised point `(x, y)`.
    pub fn position(&self, (x, y): (u16, u16)) -> (f32, f32) {
        (self.origin_x + x as f32 * self.quantum_mm, self.origin_y + y as f32 * self.quantum_mm)
    }
}

/// A validated footprint chunk, read in place.
#[derive(Debug, Clone, Copy)]
pub struct FootprintView<'a> {
    shapes: &'a [u8],
    rings: &'a [u8],
    points: &'a [u8],
    shape_count: u32,
    origin_x: f32,
    origin_y: f32,
    quantum_mm: f32,
}

/// One shape of a [`FootprintView`].
#[derive(Debug, Clone, Copy)]
pub struct FootprintShape<'a> {
    /// The provenance entry it belongs to.
    pub source: u32,
    /// How it covers the surface.
    pub kind: FootprintKind,
    /// Half width of its band, in quanta.
    pub half_width: u16,
    rings: &'a [u8],
    points: &'a [u8],
    origin: (f32, f32),
    quantum_mm: f32,
}

/// One ring of a [`FootprintShape`].
#[derive(Debug, Clone, Copy)]
pub struct FootprintRing<'a> {
    points: &'a [u8],
    origin: (f32, f32),
    quantum_mm: f32,
}

impl<'a> FootprintRing<'a> {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len() / 4
    }

    /// Whether the ring has no points (never, in a validated chunk).
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The quantised points.
    pub fn quanta(&self) -> impl Iterator<Item = (u16, u16)> + 'a {
        let p = self.points;
        (0..p.len() / 4).map(move |i| (u16_at(p, 4 * i).unwrap_or(0), u16_at(p, 4 * i + 2).unwrap_or(0)))
    }

    /// The points in page mm.
    pub fn points_mm(&self) -> impl Iterator<Item = (f32, f32)> + 'a {
        let (o, q) = (self.origin, self.quantum_mm);
        self.quanta().map(move |(x, y)| (o.0 + x as f32 * q, o.1 + y as f32 * q))
    }
}

impl<'a> FootprintShape<'a> {
    /// Half width of its band, in mm.
    pub fn half_width_mm(&self) -> f32 {
        self.half_width as f32 * self.quantum_mm
    }

    /// Its rings.
    pub fn rings(&self) -> impl Iterator<Item = FootprintRing<'a>> + 'a {
        let (rings, points, origin, quantum_mm) = (self.rings, self.points, self.origin, self.quantum_mm);
        let mut at = 0usize;
        (0..rings.len() / 4).map(move |i| {
            let n = u32_at(rings, 4 * i).unwrap_or(0) as usize;
            let slice = points.get(4 * at..4 * (at + n)).unwrap_or(&[]);
            at += n;
            FootprintRing { points: slice, origin, quantum_mm }
        })
    }
}

impl<'a> FootprintView<'a> {
    /// Number of shapes.
    pub fn len(&self) -> u32 {
        self.shape_count
    }

    /// Whether there are no shapes.
    pub fn is_empty(&self) -> bool {
        self.shape_count == 0
    }

    /// Page x of quantised point 0, mm.
    pub fn origin_x(&self) -> f32 {
        self.origin_x
    }

    /// Page y of quantised point 0, mm.
    pub fn origin_y(&self) -> f32 {
        self.origin_y
    }

    /// Millimetres per quantum.
    pub fn quantum_mm(&self) -> f32 {
        self.quantum_mm
    }

    /// The shapes in drawing order, bottom first.
    pub fn shapes(&self) -> impl Iterator<Item = FootprintShape<'a>> + 'a {
        let v = *self;
        let (mut ring_at, mut point_at) = (0usize, 0usize);
        (0..v.shape_count as usize).map(move |i| {
            let o = SHAPE_LEN * i;
            let nrings = u32_at(v.shapes, o + 8).unwrap_or(0) as usize;
            let rings = v.rings.get(4 * ring_at..4 * (ring_at + nrings)).unwrap_or(&[]);
            let npoints: usize = (0..nrings).map(|k| u32_at(rings, 4 * k).unwrap_or(0) as usize).sum();
            let points = v.points.get(4 * point_at..4 * (point_at + npoints)).unwrap_or(&[]);
            ring_at += nrings;
            point_at += npoints;
            FootprintShape {
                source: u32_at(v.shapes, o).unwrap_or(NO_SOURCE),
                kind: u8_at(v.shapes, o + 4).and_then(FootprintKind::from_code).unwrap_or(FootprintKind::Line),
                half_width: u16_at(v.shapes, o + 6).unwrap_or(0),
                rings,
                points,
                origin: (v.origin_x, v.origin_y),
                quantum_mm: v.quantum_mm,
            }
        })
    }

    /// Reads the chunk; with `full`, also checks every shape and ring.
    pub(crate) fn parse(d: &'a [u8], index: u32, full: bool) -> Result<Self, FormatError> {
        let tag = Tag::FOOTPRINTS;
        if d.len() < HEADER_LEN {
            return Err(FormatError::ChunkLength { tag, index, expected: HEADER_LEN as u64, found: d.len() as u64 });
        }
        let bad = |field, expected| FormatError::InvalidValue { tag, index, field, expected };
        let u = |o| u32_at(d, o).unwrap_or(0);
        let f = |o| f32_at(d, o).unwrap_or(f32::NAN);
        let (n, r, p) = (u(0), u(4), u(8));
        for (field, value, limit) in [
            ("shapes", n, MAX_FOOTPRINT_SHAPES),
            ("rings", r, MAX_FOOTPRINT_RINGS),
            ("points", p, MAX_FOOTPRINT_POINTS),
        ] {
            if value > limit {
                return Err(FormatError::Limit { tag, field, value: value as u64, limit: limit as u64 });
            }
        }
        let expected = HEADER_LEN as u64 + SHAPE_LEN as u64 * n as u64 + 4 * r as u64 + 4 * p as u64;
        if d.len() as u64 != expected {
            return Err(FormatError::ChunkLength { tag, index, expected, found: d.len() as u64 });
        }
        let quantum_mm = in_range(f(12), 1e-4, 1.0, tag, index, "quantum_mm", "from 0.0001 to 1 mm")?;
        let origin_x = in_range(f(16), -1e6, 1e6, tag, index, "origin_x_mm", "from -1e6 to 1e6 mm")?;
        let origin_y = in_range(f(20), -1e6, 1e6, tag, index, "origin_y_mm", "from -1e6 to 1e6 mm")?;
        let shapes_end = HEADER_LEN + SHAPE_LEN * n as usize;
        let rings_end = shapes_end + 4 * r as usize;
        let view = FootprintView {
            shapes: &d[HEADER_LEN..shapes_end],
            rings: &d[shapes_end..rings_end],
            points: &d[rings_end..],
            shape_count: n,
            origin_x,
            origin_y,
            quantum_mm,
        };
        if !full {
            return Ok(view);
        }
        // Every shape names a source and a kind and has at least one ring;
        // the shapes' rings are exactly the ring table, and the rings'
        // points exactly the point table.
        let (mut rings_seen, mut points_seen) = (0u64, 0u64);
        for i in 0..n as usize {
            let o = SHAPE_LEN * i;
            let source = u32_at(view.shapes, o).unwrap_or(NO_SOURCE);
            if source >= crate::MAX_PROVENANCE_ENTRIES {
                return Err(bad("source", "a provenance index below MAX_PROVENANCE_ENTRIES"));
            }
            let kind = u8_at(view.shapes, o + 4)
                .and_then(FootprintKind::from_code)
                .ok_or(bad("kind", "0 (area, non-zero), 1 (area, even-odd), 2 (line) or 3 (closed line)"))?;
            if u8_at(view.shapes, o + 5) != Some(0) {
                return Err(bad("reserved", "zero"));
            }
            let nrings = u32_at(view.shapes, o + 8).unwrap_or(0) as u64;
            if nrings == 0 {
                return Err(bad("rings", "at least one ring per shape"));
            }
            if rings_seen + nrings > r as u64 {
                return Err(bad("rings", "the shapes' rings add up to the ring count"));
            }
            for k in rings_seen..rings_seen + nrings {
                let len = u32_at(view.rings, 4 * k as usize).unwrap_or(0);
                if len < kind.min_ring_points() {
                    return Err(bad("ring points", "at least 3 points per area ring, 1 per line ring"));
                }
                points_seen += len as u64;
            }
            rings_seen += nrings;
        }
        if rings_seen != r as u64 {
            return Err(bad("rings", "the shapes' rings add up to the ring count"));
        }
        if points_seen != p as u64 {
            return Err(bad("points", "the rings' points add up to the point count"));
        }
        Ok(view)
    }
}
