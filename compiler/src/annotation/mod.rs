//! The annotation language, below the stages: `data-tactile`, layer labels and style sheets.
//!
//! Tactile annotations: the style model every way of marking a drawing
//! resolves to (`data-tactile` attributes, `tactile:` layer labels, style
//! sheets), and its parser.
//!
//! ```
//! use taxel_compiler::annotation::{parse, Declaration, Style};
//!
//! let d = parse("vibrate(); grating(wavelength: 6mm, angle: 0deg)").unwrap();
//! let Declaration::Styles(styles) = d else { panic!() };
//! assert!(matches!(styles[0], Style::Vibrate(v) if v.width_mm == 1.5));
//! assert!(matches!(styles[1], Style::Grating(g) if g.wavelength_mm == 6.0 && g.angle_deg == 0.0));
//! assert_eq!(parse("none").unwrap(), Declaration::None);
//! ```

mod parse;
pub mod sheet;
mod units;

pub use parse::{AnnotationError, AnnotationErrorKind, parse};
pub use units::{Quantity, Unit};

/// A vibrating outline (seed 000 eq. 2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Vibrate {
    /// Width of the vibrating band centred on the shape's outline, in mm (default 1.5, seed 000 §4.1).
    pub width_mm: f64,
    /// Vibration frequency in hertz (default 50, seed 000 §3.2).
    pub freq_hz: f64,
    /// Amplitude, 0..=1 (default 1).
    pub amplitude: f64,
    /// Width of the edge's ramp in mm (`soft: 0.3mm`); 0, the default, is a hard edge.
    pub soft_mm: f64,
}

/// A grated fill (seed 000 eq. 3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grating {
    /// Spatial wavelength in mm (default 2, seed 000 §4.1).
    pub wavelength_mm: f64,
    /// Ridge direction on the page, degrees counter-clockwise from +x (default 90, a vertical grating).
    pub angle_deg: f64,
    /// Amplitude, 0..=1 (default 1).
    pub amplitude: f64,
    /// Width of the edge's ramp in mm (`soft: 0.3mm`); 0, the default, is a hard edge.
    pub soft_mm: f64,
}

/// A dotted outline (seed 000 eq. 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dots {
    /// Dot radius in mm (default 1, seed 000 §4.1).
    pub radius_mm: f64,
    /// Centre-to-centre distance along the path in mm; `None` means three radii.
    pub spacing_mm: Option<f64>,
    /// Amplitude, 0..=1 (default 1).
    pub amplitude: f64,
}

/// One dot per point symbol.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dot {
    /// Dot radius in mm (default 1).
    pub radius_mm: f64,
    /// Amplitude, 0..=1 (default 1).
    pub amplitude: f64,
}

/// A moving stroke for vibrotactile grids (seed 001).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Brush {
    /// Total stroke time T in milliseconds (default 1000).
    pub duration_ms: f64,
    /// Intensity, 0..=1 (default 1).
    pub intensity: f64,
    /// Carrier frequency in hertz (default 200, seed 001 §"Phantom").
    pub freq_hz: f64,
    /// Start time in milliseconds; `None` follows the previous stroke.
    pub start_ms: Option<f64>,
}

/// Braille cells for a `<text>` element (NLS Specification 800 geometry).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Braille {
    /// Dot radius in mm (default 0.72: half the 1.44 mm dot base diameter).
    pub radius_mm: f64,
    /// Amplitude, 0..=1 (default 1).
    pub amplitude: f64,
    /// `grade: 1` uncontracted, `grade: 2` contracted; `None` (the
    /// default): contracted where the language has it.
    pub grade: Option<u8>,
}

/// One tactile style.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Style {
    /// `vibrate(width, freq, amplitude)`.
    Vibrate(Vibrate),
    /// `grating(wavelength, angle, amplitude)`.
    Grating(Grating),
    /// `dots(radius, spacing, amplitude)`.
    Dots(Dots),
    /// `dot(radius, amplitude)`.
    Dot(Dot),
    /// `brush(duration, intensity, freq, start)`.
    Brush(Brush),
    /// `braille(radius, amplitude)`.
    Braille(Braille),
}

impl Style {
    /// The style's name as written.
    pub fn name(&self) -> &'static str {
        match self {
            Style::Vibrate(_) => "vibrate",
            Style::Grating(_) => "grating",
            Style::Dots(_) => "dots",
            Style::Dot(_) => "dot",
            Style::Brush(_) => "brush",
            Style::Braille(_) => "braille",
        }
    }
}

/// What one annotation says: leave the element out, or render it with these styles.
#[derive(Debug, Clone, PartialEq)]
pub enum Declaration {
    /// `none`: the element (and what inherits from it) is not tactile.
    None,
    /// One or more styles, in the order written.
    Styles(Vec<Style>),
}

impl Declaration {
    /// The styles (empty for `none`).
    pub fn styles(&self) -> &[Style] {
        match self {
            Declaration::None => &[],
            Declaration::Styles(s) => s,
        }
    }
}
