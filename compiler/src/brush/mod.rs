//! Back end for vibrotactile grids (stage 4, family 2), used by `latero` for `brush()` styles.
//!
//! Tactile Brush strokes (seed 001): stroke tables for vibrotactile grids.
//!
//! A `brush(duration, intensity, freq)` path becomes a stroke: virtual
//! actuation points where the path crosses the grid lines (and its ends),
//! peak times by arc length, onsets and durations from the apparent-motion
//! model, and physical intensities from the energy (phantom) model; then the
//! whole schedule in integer ticks. `docs/brush.md` describes the algorithm,
//! what taxel does beyond the paper, and the stiff-case policy.
//!
//! - [`compile_strokes`]: requests in, a [`StrokeTable`] and diagnostics out.
//! - [`plan_strokes`]: the same strokes as the unquantised `f64` schedule (the
//!   exact reference the quantised table is measured against).
//! - [`Planner`], [`apparent_motion`], [`GridGeometry::phantom`]: the kernels.
//!
//! Diagnostics: T0501 bad path, T0502 bad duration or start, T0503 intensity
//! clamped, T0504 carrier clamped, T0505 path moved onto the grid, T0506
//! stationary stroke, T0510 stiff stroke resolved by merging points, T0511 no
//! feasible schedule (states the shortest duration), T0512 shared actuator
//! clamped where strokes overlap, T0513 stroke does not fit the table, T0514
//! profile is not a grid, T0515 (note) clamped where one stroke's own points overlap.

mod grid;
mod motion;
mod path;
mod planner;
mod shared;
mod ticks;

pub use grid::{Drives, GridGeometry, PhysicalDrive};
pub use motion::{Infeasible, SOA_INTERCEPT_MS, SOA_SLOPE, Timing, apparent_motion, feasible, shortest_duration};
pub use planner::{BrushError, PlanReport, PlannedPoint, Planner};
pub use ticks::{TickError, quantise, tick_of};

use taxel_format::{DeviceProfile, FamilyParams, StrokeTable};

use crate::diagnostic::Diagnostic;

/// One `brush(...)` path handed over by the SVG front end.
#[derive(Debug, Clone, PartialEq)]
pub struct BrushRequest {
    /// The path flattened to a polyline in page millimetres, in drawing order.
    pub polyline: Vec<(f64, f64)>,
    /// Total stroke time T in milliseconds.
    pub duration_ms: f64,
    /// Intensity Av (0..=1).
    pub intensity: f64,
    /// Carrier frequency in hertz.
    pub freq_hz: f64,
    /// Explicit start time in milliseconds, or `None` to follow the previous stroke.
    pub start_ms: Option<f64>,
    /// Provenance entry index of the element.
    pub source: Option<u32>,
    /// The element's id, for diagnostics.
    pub element: String,
    /// The element's source line, for diagnostics.
    pub line: Option<u32>,
}

/// One stroke's unquantised schedule.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannedStroke {
    /// Index of the request it came from.
    pub request: usize,
    /// When it starts, in milliseconds from the start of playback.
    pub start_ms: f64,
    /// Its duration T in milliseconds.
    pub duration_ms: f64,
    /// Intensity Av after clamping to 0..=1.
    pub intensity: f64,
    /// Carrier frequency after clamping to the profile's range.
    pub freq_hz: f64,
    /// The virtual points, in order along the path.
    pub points: Vec<PlannedPoint>,
    /// What planning found and changed.
    pub report: PlanReport,
}

fn located(mut d: Diagnostic, req: &BrushRequest) -> Diagnostic {
    if !req.element.is_empty() {
        d = d.with_element(&req.element);
    }
    d.line = req.line;
    d
}

/// Plans every request for `profile` without quantising: one entry per
/// request, `None` where the request had an error (reported in `diags`).
///
/// Strokes without an explicit start follow the previous request in document
/// order (its start plus its duration; the first starts at 0).
pub fn plan_strokes(
    requests: &[BrushRequest],
    profile: &DeviceProfile,
    diags: &mut Vec<Diagnostic>,
) -> Vec<Option<PlannedStroke>> {
    let FamilyParams::Grid(g) = profile.params else {
        if !requests.is_empty() {
            diags.push(
                Diagnostic::warning(
                    "T0514",
                    format!(
                        "{} brushed stroke{} left out: profile `{}` is a {} device, not a vibrotactile grid",
                        requests.len(),
                        if requests.len() == 1 { "" } else { "s" },
                        profile.name,
                        profile.family()
                    ),
                )
                .with_help("build for a grid profile such as `brush-4x3` to play brushed strokes"),
            );
        }
        return requests.iter().map(|_| None).collect();
    };
    let grid = GridGeometry::from_profile(profile);
    let tick_ms = 1000.0 / profile.rate_hz.max(1) as f64;
    let (fmin, fmax) = (g.carrier_min_hz as f64, g.carrier_max_hz as f64);
    let mut planner = Planner::new();
    let mut next_start = 0.0f64;
    let mut out = Vec::with_capacity(requests.len());
    for (i, req) in requests.iter().enumerate() {
        let start_ms = req.start_ms.unwrap_or(next_start);
        if req.duration_ms.is_finite() && req.duration_ms > 0.0 {
            next_start = start_ms + req.duration_ms;
        }
        if !(start_ms.is_finite() && start_ms >= 0.0) {
            diags.push(located(
                Diagnostic::error("T0502", format!("stroke start {start_ms} ms is not a time from 0 on")),
                req,
            ));
            out.push(None);
            continue;
        }
        let mut intensity = req.intensity;
        if !intensity.is_finite() {
            diags.push(located(Diagnostic::error("T0503", "brush intensity is not a number"), req));
            out.push(None);
            continue;
        }
        if !(0.0..=1.0).contains(&intensity) {
            let clamped = intensity.clamp(0.0, 1.0);
            diags.push(located(
                Diagnostic::warning("T0503", format!("brush intensity {intensity} is outside 0..=1; using {clamped}")),
                req,
            ));
            intensity = clamped;
        }
        let mut freq_hz = req.freq_hz;
        if !freq_hz.is_finite() {
            diags.push(located(Diagnostic::error("T0504", "brush frequency is not a number"), req));
            out.push(None);
            continue;
        }
        if !(fmin..=fmax).contains(&freq_hz) {
            let clamped = freq_hz.clamp(fmin, fmax);
            diags.push(located(
                Diagnostic::warning(
                    "T0504",
                    format!(
                        "brush frequency {freq_hz} Hz is outside the {fmin}-{fmax} Hz the tactors of `{}` accept; using {clamped} Hz",
                        profile.name
                    ),
                ),
                req,
            ));
            freq_hz = clamped;
        }
        match planner.plan(&req.polyline, req.duration_ms, intensity, &grid, tick_ms) {
            Ok(report) => {
                note_report(&report, req, &grid, diags);
                out.push(Some(PlannedStroke {
                    request: i,
                    start_ms,
                    duration_ms: req.duration_ms,
                    intensity,
                    freq_hz,
                    points: planner.points().to_vec(),
                    report,
                }));
            }
            Err(e) => {
                let d = match e {
                    BrushError::EmptyPath | BrushError::NonFinite { .. } => Diagnostic::error("T0501", e.to_string()),
                    BrushError::BadDuration { .. } => Diagnostic::error("T0502", e.to_string()),
                    BrushError::BadIntensity { .. } => Diagnostic::error("T0503", e.to_string()),
                    BrushError::TooFast { shortest_ms, .. } => Diagnostic::error("T0511", e.to_string())
                        .with_help(format!("give the stroke a duration of at least {shortest_ms:.2} ms")),
                };
                diags.push(located(d, req));
                out.push(None);
            }
        }
    }
    out
}

fn note_report(r: &PlanReport, req: &BrushRequest, grid: &GridGeometry, diags: &mut Vec<Diagnostic>) {
    if r.clamped {
        diags.push(located(
            Diagnostic::warning(
                "T0505",
                format!(
                    "part of the path lies outside the actuator grid (0..{} x 0..{} mm); it was moved onto the grid's edge",
                    grid.width(),
                    grid.height()
                ),
            ),
            req,
        ));
    }
    if r.stationary {
        diags.push(located(
            Diagnostic::note("T0506", "the path has no length; the stroke is a stationary vibration at its point"),
            req,
        ));
    }
    if let Some(keep_all) = r.merged_keep_all_ms {
        let planned = r.crossings; // count before merging
        let mut d = Diagnostic::warning(
            "T0510",
            format!(
                "a {} ms stroke is too fast for its {planned} virtual points (onsets would come after their peaks); \
                 crowded points were merged so the schedule is feasible",
                req.duration_ms
            ),
        );
        d = d.with_help(format!("give the stroke at least {keep_all:.2} ms to keep every grid crossing"));
        diags.push(located(d, req));
    }
}

/// Schedules every stroke for `profile`; `None` when nothing could be scheduled.
///
/// Each request becomes one stroke of the table, in request order; requests
/// with errors are left out (with an error diagnostic, so no bundle is
/// written). Shared actuators are checked across all strokes (T0512).
pub fn compile_strokes(
    requests: &[BrushRequest],
    profile: &DeviceProfile,
    diags: &mut Vec<Diagnostic>,
) -> Option<StrokeTable> {
    let plans = plan_strokes(requests, profile, diags);
    let mut table = StrokeTable::default();
    let mut origin = Vec::new();
    for plan in plans.iter().flatten() {
        let Some(req) = requests.get(plan.request) else { continue };
        match quantise(plan, profile.rate_hz, req.source) {
            Ok(s) => {
                table.strokes.push(s);
                origin.push(plan.request);
            }
            Err(e) => diags.push(located(Diagnostic::error("T0513", e.to_string()), req)),
        }
    }
    if table.strokes.is_empty() {
        return None;
    }
    let pairs: Vec<(usize, &taxel_format::Stroke)> = origin.iter().copied().zip(table.strokes.iter()).collect();
    shared::check_shared(&pairs, requests, profile.cols, profile.rate_hz, diags);
    // Stay inside the format's limits rather than produce a table the writer refuses.
    let points: usize = table.strokes.iter().map(|s| s.points.len()).sum();
    let drives: usize = table.strokes.iter().flat_map(|s| &s.points).map(|p| p.drives.len()).sum();
    if table.strokes.len() > taxel_format::MAX_STROKES as usize
        || points > taxel_format::MAX_STROKE_POINTS as usize
        || drives > taxel_format::MAX_STROKE_DRIVES as usize
    {
        diags.push(Diagnostic::error(
            "T0513",
            format!(
                "{} strokes with {points} points and {drives} drives exceed a stroke table's limits ({} strokes, {} points, {} drives)",
                table.strokes.len(),
                taxel_format::MAX_STROKES,
                taxel_format::MAX_STROKE_POINTS,
                taxel_format::MAX_STROKE_DRIVES
            ),
        ));
        return None;
    }
    Some(table)
}
