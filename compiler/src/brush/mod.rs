//! Tactile Brush strokes (seed 001): stroke tables for vibrotactile grids.
//! (Placeholder signature; issue 5 fills it in.)

use taxel_format::{DeviceProfile, StrokeTable};

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

/// Schedules every stroke for `profile`; `None` when nothing could be scheduled.
pub fn compile_strokes(
    requests: &[BrushRequest],
    profile: &DeviceProfile,
    diags: &mut Vec<Diagnostic>,
) -> Option<StrokeTable> {
    let _ = (requests, profile);
    diags.push(Diagnostic::error("T0500", "brushed strokes are not available yet (issue 5)"));
    None
}
