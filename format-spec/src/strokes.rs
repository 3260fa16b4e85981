//! Stroke tables (`STRK`): Tactile Brush strokes for a vibrotactile grid, in
//! integer ticks of the manifest's rate.

use alloc::vec::Vec;

use crate::bytes::{Out, f32_at, u16_at, u32_at, u64_at};
use crate::error::FormatError;
use crate::units::{ActuatorIndex, MilliHertz, Mm, Tick};
use crate::{NO_SOURCE, Tag, finite, in_range, source_from_raw};

const HEADER_LEN: usize = 16;
const STROKE_LEN: usize = 32;
const POINT_LEN: usize = 28;
const DRIVE_LEN: usize = 8;
/// Largest number of strokes in one table.
pub const MAX_STROKES: u32 = 65_536;
/// Largest number of virtual actuation points in one table.
pub const MAX_STROKE_POINTS: u32 = 1 << 20;
/// Largest number of physical drives in one table.
pub const MAX_STROKE_DRIVES: u32 = 4 << 20;
/// Largest number of physical actuators one virtual point may drive.
pub const MAX_DRIVES_PER_POINT: u16 = 16;

/// One physical actuator driven by a virtual point, at an intensity in 0..=1
/// (the energy model's share of the stroke's intensity).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drive {
    /// The actuator (row-major index).
    pub actuator: ActuatorIndex,
    /// Its intensity, 0..=1 of full drive.
    pub intensity: f32,
}

/// A virtual actuation point λ_k: when it starts, how long it lasts, when it
/// peaks, where it is, and which physical actuators produce it.
#[derive(Debug, Clone, PartialEq)]
pub struct StrokePoint {
    /// Onset, in ticks after the stroke's start.
    pub onset: u32,
    /// Duration in ticks (at least 1).
    pub duration: u32,
    /// Peak time τ_k, in ticks after the stroke's start, within the point's activity.
    pub peak: u32,
    /// Page x of the point.
    pub x: Mm,
    /// Page y of the point.
    pub y: Mm,
    /// The physical actuators that produce the point.
    pub drives: Vec<Drive>,
}

/// One stroke H = {P0, P1, I, F, T} after scheduling.
#[derive(Debug, Clone, PartialEq)]
pub struct Stroke {
    /// When the stroke starts, in ticks from the start of playback.
    pub start: Tick,
    /// Total time T in ticks; every point ends by then.
    pub duration: u32,
    /// Carrier frequency F.
    pub carrier: MilliHertz,
    /// Intensity I (0..=1).
    pub intensity: f32,
    /// Provenance entry of the path.
    pub source: Option<u32>,
    /// The virtual points in order along the path.
    pub points: Vec<StrokePoint>,
}

/// A table of strokes.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StrokeTable {
    /// The strokes.
    pub strokes: Vec<Stroke>,
}

impl StrokeTable {
    /// Checks the counts that the encoding stores in fixed-width fields, so
    /// that none of them can wrap.
    pub(crate) fn check_shape(&self) -> Result<(), FormatError> {
        let tag = Tag::STROKES;
        let points: usize = self.strokes.iter().map(|s| s.points.len()).sum();
        let drives: usize = self.strokes.iter().flat_map(|s| &s.points).map(|p| p.drives.len()).sum();
        let per_point = self.strokes.iter().flat_map(|s| &s.points).map(|p| p.drives.len()).max().unwrap_or(0);
        for (field, v, limit) in [
            ("strokes", self.strokes.len(), MAX_STROKES as usize),
            ("points", points, MAX_STROKE_POINTS as usize),
            ("drives", drives, MAX_STROKE_DRIVES as usize),
            ("drives per point", per_point, MAX_DRIVES_PER_POINT as usize),
        ] {
            if v > limit {
                return Err(FormatError::Limit { tag, field, value: v as u64, limit: limit as u64 });
            }
        }
        Ok(())
    }

    pub(crate) fn encode(&self) -> Vec<u8> {
        let points: usize = self.strokes.iter().map(|s| s.points.len()).sum();
        let drives: usize = self.strokes.iter().flat_map(|s| &s.points).map(|p| p.drives.len()).sum();
        let mut out =
            Vec::with_capacity(HEADER_LEN + STROKE_LEN * self.strokes.len() + POINT_LEN * points + DRIVE_LEN * drives);
        let mut w = Out(&mut out);
        w.u32(self.strokes.len() as u32).u32(points as u32).u32(drives as u32).u32(0);
        let mut first_point = 0u32;
        for s in &self.strokes {
            w.u64(s.start.0)
                .u32(s.duration)
                .u32(s.carrier.0)
                .f32(s.intensity)
                .u32(first_point)
                .u32(s.points.len() as u32)
                .u32(s.source.unwrap_or(NO_SOURCE));
            first_point += s.points.len() as u32;
        }
        let mut first_drive = 0u32;
        for p in self.strokes.iter().flat_map(|s| &s.points) {
            w.u32(p.onset)
                .u32(p.duration)
                .u32(p.peak)
                .f32(p.x.0)
                .f32(p.y.0)
                .u32(first_drive)
                .u16(p.drives.len() as u16)
                .u16(0);
            first_drive += p.drives.len() as u32;
        }
        for d in self.strokes.iter().flat_map(|s| &s.points).flat_map(|p| &p.drives) {
            w.u16(d.actuator.0).u16(0).f32(d.intensity);
        }
        out
    }

    pub(crate) fn from_view(v: &StrokeTableView<'_>) -> Self {
        let strokes = (0..v.stroke_count())
            .filter_map(|i| {
                let (mut s, points) = v.stroke(i)?;
                s.points = points
                    .filter_map(|k| {
                        let (mut p, drives) = v.point(k)?;
                        p.drives = drives.filter_map(|j| v.drive(j)).collect();
                        Some(p)
                    })
                    .collect();
                Some(s)
            })
            .collect();
        StrokeTable { strokes }
    }
}

/// A validated stroke table, read in place.
#[derive(Debug, Clone, Copy)]
pub struct StrokeTableView<'a> {
    strokes: &'a [u8],
    points: &'a [u8],
    drives: &'a [u8],
    stroke_count: u32,
}

impl<'a> StrokeTableView<'a> {
    /// Number of strokes.
    pub fn stroke_count(&self) -> u32 {
        self.stroke_count
    }

    /// Number of virtual points over all strokes.
    pub fn point_count(&self) -> u32 {
        (self.points.len() / POINT_LEN) as u32
    }

    /// Stroke `i` (with an empty `points`) and the range of its point indices.
    pub fn stroke(&self, i: u32) -> Option<(Stroke, core::ops::Range<u32>)> {
        let o = i as usize * STROKE_LEN;
        let first = u32_at(self.strokes, o + 20)?;
        let n = u32_at(self.strokes, o + 24)?;
        Some((
            Stroke {
                start: Tick(u64_at(self.strokes, o)?),
                duration: u32_at(self.strokes, o + 8)?,
                carrier: MilliHertz(u32_at(self.strokes, o + 12)?),
                intensity: f32_at(self.strokes, o + 16)?,
                source: source_from_raw(u32_at(self.strokes, o + 28)?),
                points: Vec::new(),
            },
            first..first.checked_add(n)?,
        ))
    }

    /// Point `k` (with an empty `drives`) and the range of its drive indices.
    pub fn point(&self, k: u32) -> Option<(StrokePoint, core::ops::Range<u32>)> {
        let o = k as usize * POINT_LEN;
        let first = u32_at(self.points, o + 20)?;
        let n = u16_at(self.points, o + 24)? as u32;
        Some((
            StrokePoint {
                onset: u32_at(self.points, o)?,
                duration: u32_at(self.points, o + 4)?,
                peak: u32_at(self.points, o + 8)?,
                x: Mm(f32_at(self.points, o + 12)?),
                y: Mm(f32_at(self.points, o + 16)?),
                drives: Vec::new(),
            },
            first..first.checked_add(n)?,
        ))
    }

    /// The timing of point `k` without building a [`StrokePoint`]:
    /// `(onset, duration, drive range)`. Allocation-free, for players.
    #[inline]
    pub fn point_timing(&self, k: u32) -> Option<(u32, u32, core::ops::Range<u32>)> {
        let o = k as usize * POINT_LEN;
        let first = u32_at(self.points, o + 20)?;
        let n = u16_at(self.points, o + 24)? as u32;
        Some((u32_at(self.points, o)?, u32_at(self.points, o + 4)?, first..first.checked_add(n)?))
    }

    /// Stroke `i`'s timing and carrier without building a [`Stroke`]:
    /// `(start, duration, carrier, intensity, point range)`. Allocation-free, for players.
    #[inline]
    pub fn stroke_timing(&self, i: u32) -> Option<(Tick, u32, MilliHertz, f32, core::ops::Range<u32>)> {
        let o = i as usize * STROKE_LEN;
        let first = u32_at(self.strokes, o + 20)?;
        let n = u32_at(self.strokes, o + 24)?;
        Some((
            Tick(u64_at(self.strokes, o)?),
            u32_at(self.strokes, o + 8)?,
            MilliHertz(u32_at(self.strokes, o + 12)?),
            f32_at(self.strokes, o + 16)?,
            first..first.checked_add(n)?,
        ))
    }

    /// Drive `j`.
    #[inline]
    pub fn drive(&self, j: u32) -> Option<Drive> {
        let o = j as usize * DRIVE_LEN;
        Some(Drive { actuator: ActuatorIndex(u16_at(self.drives, o)?), intensity: f32_at(self.drives, o + 4)? })
    }

    /// Reads the table; with `full`, also checks every stroke, point and drive
    /// (the reader does that once, in [`crate::BundleView::parse`]).
    pub(crate) fn parse(d: &'a [u8], index: u32, actuators: usize, full: bool) -> Result<Self, FormatError> {
        let tag = Tag::STROKES;
        FormatError::check_header(d, HEADER_LEN, tag, index)?;
        let bad = |field, expected| FormatError::InvalidValue { tag, index, field, expected };
        let ns = u32_at(d, 0).unwrap_or(0);
        let np = u32_at(d, 4).unwrap_or(0);
        let nd = u32_at(d, 8).unwrap_or(0);
        if u32_at(d, 12) != Some(0) {
            return Err(bad("reserved", "zero"));
        }
        for (field, v, limit) in
            [("strokes", ns, MAX_STROKES), ("points", np, MAX_STROKE_POINTS), ("drives", nd, MAX_STROKE_DRIVES)]
        {
            if v > limit {
                return Err(FormatError::Limit { tag, field, value: v as u64, limit: limit as u64 });
            }
        }
        let (ls, lp, ld) = (ns as usize * STROKE_LEN, np as usize * POINT_LEN, nd as usize * DRIVE_LEN);
        let expected = (HEADER_LEN + ls + lp + ld) as u64;
        if d.len() as u64 != expected {
            return Err(FormatError::ChunkLength { tag, index, expected, found: d.len() as u64 });
        }
        let view = StrokeTableView {
            strokes: &d[HEADER_LEN..HEADER_LEN + ls],
            points: &d[HEADER_LEN + ls..HEADER_LEN + ls + lp],
            drives: &d[HEADER_LEN + ls + lp..],
            stroke_count: ns,
        };
        if !full {
            return Ok(view);
        }
        let (mut next_point, mut next_drive) = (0u32, 0u32);
        for i in 0..ns {
            let (s, range) = view.stroke(i).ok_or(bad("point range", "within the table"))?;
            if range.start != next_point || range.end > np {
                return Err(bad("point range", "contiguous, in stroke order, within the table"));
            }
            next_point = range.end;
            if s.duration == 0 {
                return Err(bad("stroke duration", "at least one tick"));
            }
            s.start.0.checked_add(s.duration as u64).ok_or(bad("stroke start", "such that start + duration fits"))?;
            if s.carrier.0 == 0 {
                return Err(bad("carrier", "above 0 Hz"));
            }
            in_range(s.intensity, 0.0, 1.0, tag, index, "stroke intensity", "from 0 to 1")?;
            for k in range {
                let (p, drives) = view.point(k).ok_or(bad("drive range", "within the table"))?;
                if drives.start != next_drive || drives.end > nd {
                    return Err(bad("drive range", "contiguous, in point order, within the table"));
                }
                if drives.len() > MAX_DRIVES_PER_POINT as usize {
                    return Err(FormatError::Limit {
                        tag,
                        field: "drives per point",
                        value: drives.len() as u64,
                        limit: MAX_DRIVES_PER_POINT as u64,
                    });
                }
                next_drive = drives.end;
                if u16_at(view.points, k as usize * POINT_LEN + 26) != Some(0) {
                    return Err(bad("reserved", "zero"));
                }
                let end = p.onset as u64 + p.duration as u64;
                if p.duration == 0 || end > s.duration as u64 {
                    return Err(bad("point timing", "a duration of at least one tick, ending by the stroke's end"));
                }
                if (p.peak as u64) < p.onset as u64 || p.peak as u64 > end {
                    return Err(bad("point peak", "within the point's activity"));
                }
                finite(p.x.0, tag, index, "point x")?;
                finite(p.y.0, tag, index, "point y")?;
                for j in drives {
                    let dr = view.drive(j).ok_or(bad("drive", "within the table"))?;
                    if dr.actuator.0 as usize >= actuators {
                        return Err(bad("drive actuator", "an actuator of the manifest's profile"));
                    }
                    if u16_at(view.drives, j as usize * DRIVE_LEN + 2) != Some(0) {
                        return Err(bad("reserved", "zero"));
                    }
                    in_range(dr.intensity, 0.0, 1.0, tag, index, "drive intensity", "from 0 to 1")?;
                }
            }
        }
        if next_point != np || next_drive != nd {
            return Err(bad("counts", "every point and drive used by exactly one stroke"));
        }
        Ok(view)
    }
}
