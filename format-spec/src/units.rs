//! Newtypes for the quantities a bundle stores, so that millimetres, ticks,
//! frequencies and actuator indices cannot be mixed up.

/// A length or coordinate on the page in millimetres (x right, y down).
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd, Default)]
pub struct Mm(pub f32);

/// An instant or a duration counted in ticks of the bundle's declared rate.
///
/// Tick `k` is the instant `k / rate_hz` seconds after the start of playback.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Tick(pub u64);

/// A frequency in millihertz, so that oscillator phase can be computed exactly
/// from an integer tick: `phase = (tick * mhz) mod (rate_hz * 1000)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct MilliHertz(pub u32);

impl MilliHertz {
    /// The nearest representable frequency to `hz`, or `None` when `hz` is not
    /// finite, negative, or too large for the representation.
    pub fn from_hz(hz: f64) -> Option<Self> {
        let m = hz * 1000.0;
        if m.is_finite() && m >= 0.0 && m <= u32::MAX as f64 {
            // Rounding a finite value in range cannot fail.
            Some(MilliHertz(libm_round(m) as u32))
        } else {
            None
        }
    }

    /// The frequency in hertz.
    pub fn hz(self) -> f64 {
        self.0 as f64 / 1000.0
    }
}

/// `f64::round` is not in `core`; this is round-half-away-from-zero for
/// non-negative values, which is all the format needs.
fn libm_round(x: f64) -> f64 {
    let t = x as u64 as f64;
    if x - t >= 0.5 { t + 1.0 } else { t }
}

/// The index of one physical actuator in a frame (row-major: `cols * row + col`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct ActuatorIndex(pub u16);

/// A short UTF-8 string stored in a fixed number of bytes, NUL-padded, so that
/// manifests and profiles need no allocation.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct FixedStr<const N: usize> {
    bytes: [u8; N],
    len: u8,
}

impl<const N: usize> FixedStr<N> {
    /// The empty string.
    pub const EMPTY: Self = FixedStr { bytes: [0; N], len: 0 };

    /// Copies `s`, or returns `None` when it is longer than `N - 1` bytes or
    /// contains a NUL byte.
    pub fn new(s: &str) -> Option<Self> {
        let b = s.as_bytes();
        if b.len() >= N || b.len() > u8::MAX as usize || b.contains(&0) {
            return None;
        }
        let mut bytes = [0u8; N];
        bytes[..b.len()].copy_from_slice(b);
        Some(FixedStr { bytes, len: b.len() as u8 })
    }

    /// Reads a NUL-padded field; `None` when it is not UTF-8 or has bytes after the first NUL.
    pub fn from_padded(raw: &[u8; N]) -> Option<Self> {
        let len = raw.iter().position(|&b| b == 0).unwrap_or(N);
        if len >= N || raw[len..].iter().any(|&b| b != 0) {
            return None;
        }
        core::str::from_utf8(&raw[..len]).ok()?;
        Some(FixedStr { bytes: *raw, len: len as u8 })
    }

    /// The string.
    pub fn as_str(&self) -> &str {
        // The constructors only accept valid UTF-8.
        core::str::from_utf8(&self.bytes[..self.len as usize]).unwrap_or("")
    }

    /// The NUL-padded bytes as stored.
    pub fn padded(&self) -> &[u8; N] {
        &self.bytes
    }
}

impl<const N: usize> core::fmt::Debug for FixedStr<N> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        core::fmt::Debug::fmt(self.as_str(), f)
    }
}

impl<const N: usize> core::fmt::Display for FixedStr<N> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_str_round_trips_and_refuses_overlong() {
        let s = FixedStr::<8>::new("stress2").unwrap();
        assert_eq!(s.as_str(), "stress2");
        assert_eq!(FixedStr::<8>::from_padded(s.padded()), Some(s));
        assert!(FixedStr::<8>::new("12345678").is_none());
        assert!(FixedStr::<8>::from_padded(&[b'a', 0, b'b', 0, 0, 0, 0, 0]).is_none());
    }

    #[test]
    fn millihertz_rounds_to_nearest() {
        assert_eq!(MilliHertz::from_hz(50.0), Some(MilliHertz(50_000)));
        assert_eq!(MilliHertz::from_hz(0.0004), Some(MilliHertz(0)));
        assert_eq!(MilliHertz::from_hz(0.0006), Some(MilliHertz(1)));
        assert_eq!(MilliHertz::from_hz(f64::NAN), None);
        assert_eq!(MilliHertz::from_hz(-1.0), None);
    }
}
