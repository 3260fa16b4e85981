//! Units written with a number in an annotation, and their conversion to the
//! compiler's internal units (millimetres, degrees, hertz, milliseconds, ratios).

/// A unit suffix.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unit {
    /// Millimetre.
    Mm,
    /// Centimetre.
    Cm,
    /// Inch (25.4 mm).
    In,
    /// Point (1/72 in).
    Pt,
    /// CSS pixel (1/96 in), as in SVG.
    Px,
    /// Degree.
    Deg,
    /// Radian.
    Rad,
    /// Turn (360°).
    Turn,
    /// Hertz.
    Hz,
    /// Kilohertz.
    KHz,
    /// Millisecond.
    Ms,
    /// Second.
    S,
    /// Percent (of full amplitude).
    Percent,
}

/// What a parameter measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Dimension {
    Length,
    Angle,
    Frequency,
    Time,
    Ratio,
    Count,
}

impl Dimension {
    /// What a value of this dimension looks like, for "expected ..." messages.
    pub(crate) fn expected(self) -> &'static str {
        match self {
            Dimension::Length => "a length with a unit (mm, cm, in, pt or px), such as 1.5mm",
            Dimension::Angle => "an angle with a unit (deg, rad or turn), such as 45deg",
            Dimension::Frequency => "a frequency with a unit (Hz or kHz), such as 50Hz",
            Dimension::Time => "a time with a unit (ms or s), such as 800ms",
            Dimension::Ratio => "a number from 0 to 1 or a percentage, such as 0.8 or 80%",
            Dimension::Count => "a whole number without a unit",
        }
    }
}

impl Unit {
    /// The unit for a suffix as written (case-sensitive except `hz`/`khz`, which people write either way).
    pub fn from_suffix(s: &str) -> Option<Unit> {
        Some(match s {
            "mm" => Unit::Mm,
            "cm" => Unit::Cm,
            "in" => Unit::In,
            "pt" => Unit::Pt,
            "px" => Unit::Px,
            "deg" => Unit::Deg,
            "rad" => Unit::Rad,
            "turn" => Unit::Turn,
            "ms" => Unit::Ms,
            "s" => Unit::S,
            "%" => Unit::Percent,
            _ if s.eq_ignore_ascii_case("hz") => Unit::Hz,
            _ if s.eq_ignore_ascii_case("khz") => Unit::KHz,
            _ => return None,
        })
    }

    fn dimension(self) -> Dimension {
        match self {
            Unit::Mm | Unit::Cm | Unit::In | Unit::Pt | Unit::Px => Dimension::Length,
            Unit::Deg | Unit::Rad | Unit::Turn => Dimension::Angle,
            Unit::Hz | Unit::KHz => Dimension::Frequency,
            Unit::Ms | Unit::S => Dimension::Time,
            Unit::Percent => Dimension::Ratio,
        }
    }

    /// Factor to the dimension's internal unit (mm, deg, Hz, ms, ratio).
    fn factor(self) -> f64 {
        match self {
            Unit::Mm => 1.0,
            Unit::Cm => 10.0,
            Unit::In => 25.4,
            Unit::Pt => 25.4 / 72.0,
            Unit::Px => 25.4 / 96.0,
            Unit::Deg => 1.0,
            Unit::Rad => 180.0 / core::f64::consts::PI,
            Unit::Turn => 360.0,
            Unit::Hz => 1.0,
            Unit::KHz => 1000.0,
            Unit::Ms => 1.0,
            Unit::S => 1000.0,
            Unit::Percent => 0.01,
        }
    }
}

/// A number with its optional unit, as written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantity {
    /// The number.
    pub value: f64,
    /// The unit, when one was written.
    pub unit: Option<Unit>,
}

impl Quantity {
    /// The value in the dimension's internal unit, or `None` when the unit does
    /// not measure that dimension. Only ratios may be written without a unit.
    pub(crate) fn to(self, dim: Dimension) -> Option<f64> {
        match self.unit {
            None => matches!(dim, Dimension::Ratio | Dimension::Count).then_some(self.value),
            Some(u) => (u.dimension() == dim).then(|| self.value * u.factor()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conversions_match_their_definitions() {
        let q = |value, unit| Quantity { value, unit: Some(unit) };
        assert_eq!(q(2.0, Unit::Cm).to(Dimension::Length), Some(20.0));
        assert_eq!(q(1.0, Unit::In).to(Dimension::Length), Some(25.4));
        assert!((q(72.0, Unit::Pt).to(Dimension::Length).unwrap() - 25.4).abs() < 1e-12);
        assert!((q(96.0, Unit::Px).to(Dimension::Length).unwrap() - 25.4).abs() < 1e-12);
        assert!((q(core::f64::consts::FRAC_PI_2, Unit::Rad).to(Dimension::Angle).unwrap() - 90.0).abs() < 1e-12);
        assert_eq!(q(0.5, Unit::S).to(Dimension::Time), Some(500.0));
        assert_eq!(q(80.0, Unit::Percent).to(Dimension::Ratio), Some(0.8));
        assert_eq!(q(1.0, Unit::Mm).to(Dimension::Angle), None);
        assert_eq!(Quantity { value: 3.0, unit: None }.to(Dimension::Length), None);
        assert_eq!(Unit::from_suffix("HZ"), Some(Unit::Hz));
        assert_eq!(Unit::from_suffix("MM"), None);
    }
}
