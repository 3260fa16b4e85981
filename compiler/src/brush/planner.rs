//! One stroke from path to unquantised schedule: virtual points (step 1),
//! peak times by arc length (step 2), apparent-motion timing (step 3) with the
//! stiff case resolved, and phantom intensities (step 4).
//!
//! The [`Planner`] keeps its buffers between strokes, so planning a stroke
//! allocates nothing once the buffers have grown to the largest stroke seen.

use super::grid::{Drives, GridGeometry};
use super::motion::{SOA_INTERCEPT_MS, next_rise, shortest_duration};
use super::path::{DUPLICATE_MM, VirtualPoint, arc_lengths, point_at, virtual_points};

/// One virtual point of a planned stroke, unquantised (milliseconds from the
/// stroke's start, page millimetres).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlannedPoint {
    /// Arc length from the start of the path (mm).
    pub arc_mm: f64,
    /// Page x (mm).
    pub x_mm: f64,
    /// Page y (mm).
    pub y_mm: f64,
    /// Peak time τ_k = T · s_k / L.
    pub peak_ms: f64,
    /// Onset (sum of the SOAs before this point).
    pub onset_ms: f64,
    /// Duration d_k from the apparent-motion model.
    pub duration_ms: f64,
    /// When the point stops as played: `min(onset + duration, T)`. The
    /// generalised recurrence can let a point outlast the stroke (in the worked
    /// example of `primitives.md` λ₃ would stop at 1041 ms of 1000); taxel ends
    /// every point by T so the stroke lasts what the author wrote.
    pub end_ms: f64,
    /// The physical actuators that produce the point (energy model).
    pub drives: Drives,
}

/// What planning found and changed, for diagnostics.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlanReport {
    /// Length of the path on the grid (mm).
    pub length_mm: f64,
    /// Virtual points found on the path (its ends included), before any merging.
    pub crossings: usize,
    /// When the stroke was too fast for all its virtual points: the shortest
    /// duration (ms) that would keep them all. The planned points are fewer.
    pub merged_keep_all_ms: Option<f64>,
    /// Whether some of the path lay outside the grid and was moved onto its edge.
    pub clamped: bool,
    /// Whether the path has no length: the stroke is one stationary point.
    pub stationary: bool,
}

/// Why a stroke could not be planned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BrushError {
    /// The path has no vertices.
    EmptyPath,
    /// A vertex is not a finite number.
    NonFinite {
        /// Its index in the polyline.
        vertex: usize,
    },
    /// The duration is not a finite positive number of milliseconds.
    BadDuration {
        /// The duration given.
        ms: f64,
    },
    /// The intensity is not in 0..=1.
    BadIntensity {
        /// The intensity given.
        value: f64,
    },
    /// No feasible apparent-motion schedule exists, even with two points.
    TooFast {
        /// The duration given.
        duration_ms: f64,
        /// The shortest duration that works.
        shortest_ms: f64,
    },
}

impl core::fmt::Display for BrushError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            BrushError::EmptyPath => write!(f, "the path has no points"),
            BrushError::NonFinite { vertex } => write!(f, "point {vertex} of the path is not a finite number"),
            BrushError::BadDuration { ms } => write!(f, "stroke duration {ms} ms is not a positive number"),
            BrushError::BadIntensity { value } => write!(f, "intensity {value} is not in 0..=1"),
            BrushError::TooFast { duration_ms, shortest_ms } => write!(
                f,
                "a {duration_ms} ms stroke is too fast for apparent motion: the shortest duration that works is {shortest_ms:.2} ms"
            ),
        }
    }
}

impl std::error::Error for BrushError {}

/// Plans strokes with reusable buffers.
#[derive(Debug, Default, Clone)]
pub struct Planner {
    poly: Vec<(f64, f64)>,
    cum: Vec<f64>,
    scratch: Vec<VirtualPoint>,
    points: Vec<VirtualPoint>,
    fractions: Vec<f64>,
    rises: Vec<f64>,
    out: Vec<PlannedPoint>,
}

impl Planner {
    /// A planner with empty buffers.
    pub fn new() -> Self {
        Self::default()
    }

    /// The points of the last successful [`Planner::plan`].
    pub fn points(&self) -> &[PlannedPoint] {
        &self.out
    }

    /// Plans one stroke along `polyline` (page mm) lasting `duration_ms` at
    /// intensity `intensity` on `grid`. `min_ms` is the shortest activity a
    /// point may have (one tick of the profile). The points are then in
    /// [`Planner::points`].
    pub fn plan(
        &mut self,
        polyline: &[(f64, f64)],
        duration_ms: f64,
        intensity: f64,
        grid: &GridGeometry,
        min_ms: f64,
    ) -> Result<PlanReport, BrushError> {
        self.out.clear();
        if polyline.is_empty() {
            return Err(BrushError::EmptyPath);
        }
        if let Some(vertex) = polyline.iter().position(|p| !(p.0.is_finite() && p.1.is_finite())) {
            return Err(BrushError::NonFinite { vertex });
        }
        if !(duration_ms.is_finite() && duration_ms > 0.0) {
            return Err(BrushError::BadDuration { ms: duration_ms });
        }
        if !(0.0..=1.0).contains(&intensity) {
            return Err(BrushError::BadIntensity { value: intensity });
        }
        let min_ms = if min_ms.is_finite() { min_ms.max(0.0) } else { 0.0 };
        let t = duration_ms;
        let mut report = PlanReport::default();

        self.poly.clear();
        for &(x, y) in polyline {
            let c = grid.clamp(x, y);
            report.clamped |= c != (x, y);
            self.poly.push(c);
        }
        let length = arc_lengths(&self.poly, &mut self.cum);
        report.length_mm = length;

        if length <= DUPLICATE_MM.max(grid.tolerance()) {
            if t < min_ms {
                return Err(BrushError::TooFast { duration_ms: t, shortest_ms: min_ms });
            }
            report.stationary = true;
            report.crossings = 1;
            let (x, y) = self.poly[0];
            self.out.push(PlannedPoint {
                arc_mm: 0.0,
                x_mm: x,
                y_mm: y,
                peak_ms: 0.0,
                onset_ms: 0.0,
                duration_ms: t,
                end_ms: t,
                drives: grid.phantom(x, y, intensity),
            });
            return Ok(report);
        }

        virtual_points(&self.poly, &self.cum, grid, &mut self.scratch, &mut self.points);
        report.crossings = self.points.len();
        self.fractions.clear();
        self.fractions.extend(self.points.iter().map(|p| p.s / length));

        self.thin_hopeless(t, length);
        self.resolve(t, length, min_ms, grid)?;
        if self.points.len() < report.crossings {
            report.merged_keep_all_ms = shortest_duration(&self.fractions, min_ms);
        }

        let n = self.points.len();
        for (k, p) in self.points.iter().enumerate() {
            let x = self.rises[k];
            let fall = if k + 1 < n { self.rises[k + 1] } else { 0.0 };
            let peak = t * (p.s / length);
            let onset = peak - x;
            self.out.push(PlannedPoint {
                arc_mm: p.s,
                x_mm: p.x,
                y_mm: p.y,
                peak_ms: peak,
                onset_ms: onset,
                duration_ms: x + fall,
                end_ms: (onset + x + fall).min(t),
                drives: grid.phantom(p.x, p.y, intensity),
            });
        }
        Ok(report)
    }

    /// Every SOA is at least 47.3 ms, so a stroke of T ms can keep at most
    /// about T / 47.3 + 1 points. When a path has many times more crossings
    /// than that (a scribble along a grid line), merging them one by one would
    /// cost time quadratic in their number; instead keep, in one linear pass,
    /// only points at least one minimum SOA after the last kept one (and the
    /// end), then let [`Planner::resolve`] finish as usual.
    fn thin_hopeless(&mut self, t: f64, length: f64) {
        let cap = (t / SOA_INTERCEPT_MS) as usize + 2;
        if self.points.len() <= 4 * cap {
            return;
        }
        let last = self.points.len() - 1;
        let end = self.points[last];
        let mut kept = 1;
        let mut prev = 0.0;
        for k in 1..last {
            let p = self.points[k];
            let tau = t * (p.s / length);
            if tau - prev >= SOA_INTERCEPT_MS && t - tau >= SOA_INTERCEPT_MS {
                self.points[kept] = p;
                kept += 1;
                prev = tau;
            }
        }
        self.points[kept] = end;
        self.points.truncate(kept + 1);
    }

    /// Runs the rise recurrence along the points and, where a rise comes out
    /// shorter than `min_ms` (the stiff case), merges the two points around it
    /// and steps back one point. The recurrence only looks backwards, so the
    /// rises before the merge stay valid: the whole pass is linear in the
    /// number of points plus merges.
    ///
    /// Merging keeps the stroke's ends: a crowded pair at the start loses its
    /// second point, one at the end loses its second-to-last, and an interior
    /// pair becomes one point halfway between them along the path.
    fn resolve(&mut self, t: f64, length: f64, min_ms: f64, grid: &GridGeometry) -> Result<(), BrushError> {
        let peak = |p: &VirtualPoint| t * (p.s / length);
        self.rises.clear();
        self.rises.push(0.0);
        let mut k = 0;
        while k + 1 < self.points.len() {
            let gap = peak(&self.points[k + 1]) - peak(&self.points[k]);
            let x = next_rise(gap, self.rises[k]);
            if x >= min_ms {
                self.rises.truncate(k + 1);
                self.rises.push(x);
                k += 1;
                continue;
            }
            let last = self.points.len() - 1;
            if last == 1 {
                let shortest_ms = shortest_duration(&[0.0, 1.0], min_ms).unwrap_or(f64::INFINITY);
                return Err(BrushError::TooFast { duration_ms: t, shortest_ms });
            }
            if k == 0 {
                self.points.remove(1);
            } else if k + 1 == last {
                self.points.remove(k);
                k -= 1;
            } else {
                let s = 0.5 * (self.points[k].s + self.points[k + 1].s);
                let (x, y) = point_at(&self.poly, &self.cum, s);
                let (x, y) = grid.snap(x, y);
                self.points[k] = VirtualPoint { s, x, y };
                self.points.remove(k + 1);
                k -= 1;
            }
            self.rises.truncate(k + 1);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> GridGeometry {
        GridGeometry { rows: 3, cols: 4, pitch_x: 63.0, pitch_y: 63.0 }
    }

    #[test]
    fn slow_row_stroke_keeps_every_actuator() {
        let mut p = Planner::new();
        let r = p.plan(&[(0.0, 0.0), (189.0, 0.0)], 2000.0, 1.0, &grid(), 1.0).unwrap();
        assert_eq!((r.crossings, r.merged_keep_all_ms), (4, None));
        let peaks: Vec<f64> = p.points().iter().map(|q| q.peak_ms).collect();
        assert_eq!(peaks.len(), 4);
        for (k, want) in [0.0, 2000.0 / 3.0, 4000.0 / 3.0, 2000.0].into_iter().enumerate() {
            assert!((peaks[k] - want).abs() < 1e-9);
        }
        assert_eq!(p.points()[3].end_ms, 2000.0);
    }

    #[test]
    fn fast_stroke_is_merged_and_stays_feasible() {
        let mut p = Planner::new();
        let r = p.plan(&[(0.0, 0.0), (189.0, 126.0)], 100.0, 1.0, &grid(), 1.0).unwrap();
        assert!(r.merged_keep_all_ms.unwrap() > 100.0);
        let pts = p.points();
        assert!(pts.len() < r.crossings && pts.len() >= 2);
        assert_eq!((pts[0].x_mm, pts[0].y_mm), (0.0, 0.0));
        assert_eq!((pts[pts.len() - 1].x_mm, pts[pts.len() - 1].y_mm), (189.0, 126.0));
        for q in pts {
            assert!(q.onset_ms <= q.peak_ms && q.duration_ms >= 1.0 && q.end_ms <= 100.0);
        }
    }

    #[test]
    fn too_fast_names_the_shortest_duration() {
        let mut p = Planner::new();
        let e = p.plan(&[(0.0, 0.0), (63.0, 0.0)], 40.0, 1.0, &grid(), 1.0).unwrap_err();
        let BrushError::TooFast { shortest_ms, .. } = e else { panic!("{e:?}") };
        assert!(p.plan(&[(0.0, 0.0), (63.0, 0.0)], shortest_ms, 1.0, &grid(), 1.0).is_ok());
        assert!(p.plan(&[(0.0, 0.0), (63.0, 0.0)], shortest_ms - 0.02, 1.0, &grid(), 1.0).is_err());
    }

    #[test]
    fn a_scribble_with_thousands_of_crossings_is_thinned_quickly() {
        // 20 000 zigzags across the column line x = 63 in 1 s.
        let poly: Vec<(f64, f64)> =
            (0..40_000).map(|i| (if i % 2 == 0 { 60.0 } else { 66.0 }, 10.0 + i as f64 * 1e-3)).collect();
        let mut p = Planner::new();
        let r = p.plan(&poly, 1000.0, 1.0, &grid(), 1.0).unwrap();
        assert!(r.crossings > 39_000);
        assert!(p.points().len() <= 1000 / 47 + 1);
        for q in p.points() {
            assert!(q.onset_ms <= q.peak_ms && q.duration_ms >= 1.0 && q.end_ms <= 1000.0);
        }
    }

    #[test]
    fn bad_input_is_refused() {
        let mut p = Planner::new();
        let g = grid();
        assert_eq!(p.plan(&[], 100.0, 1.0, &g, 1.0), Err(BrushError::EmptyPath));
        assert_eq!(p.plan(&[(0.0, f64::NAN)], 100.0, 1.0, &g, 1.0), Err(BrushError::NonFinite { vertex: 0 }));
        assert!(matches!(p.plan(&[(0.0, 0.0)], f64::NAN, 1.0, &g, 1.0), Err(BrushError::BadDuration { .. })));
        assert!(matches!(p.plan(&[(0.0, 0.0)], 10.0, 1.5, &g, 1.0), Err(BrushError::BadIntensity { .. })));
    }
}
