//! Device profiles as TOML files, and the built-in ones (`std` only).
//!
//! ```
//! let p = taxel_format::profiles::builtin("stress2").unwrap();
//! assert_eq!((p.rows, p.cols, p.rate_hz, p.output_bits), (8, 8, 1000, 10));
//! let err = taxel_format::profiles::parse("name = \"x\"\n", "x.toml").unwrap_err();
//! assert!(err.to_string().contains("x.toml"));
//! ```

use std::string::{String, ToString};
use std::vec::Vec;
use std::{fmt, format};

use serde::Deserialize;

use crate::profile::{DeviceProfile, FamilyParams, FingerParams, GridParams, ProfileName};

/// The built-in profiles: `(name, TOML source)`.
pub const BUILTIN: &[(&str, &str)] = &[
    ("stress2", include_str!("../profiles/stress2.toml")),
    ("brush-4x3", include_str!("../profiles/brush-4x3.toml")),
    ("finger3", include_str!("../profiles/finger3.toml")),
];

/// Why a profile file was refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ProfileError {
    /// The file (or built-in name) the profile came from.
    pub source_name: String,
    /// The key that was wrong, when one is known (`array.rows`).
    pub key: Option<String>,
    /// What was wrong and what was expected.
    pub message: String,
}

impl fmt::Display for ProfileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.key {
            Some(k) => write!(f, "{}: key `{}`: {}", self.source_name, k, self.message),
            None => write!(f, "{}: {}", self.source_name, self.message),
        }
    }
}

impl std::error::Error for ProfileError {}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    name: String,
    family: String,
    rate_hz: u32,
    output_bits: u8,
    array: Array,
    surface: Surface,
    grid: Option<Grid>,
    finger: Option<Finger>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Array {
    rows: u16,
    cols: u16,
    pitch_x_mm: f32,
    pitch_y_mm: f32,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Surface {
    width_mm: f32,
    height_mm: f32,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Grid {
    carrier_min_hz: f32,
    carrier_max_hz: f32,
    audio_rate_hz: u32,
    ramp_ms: f32,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Finger {
    rhythm_max: f32,
    intensity_max: f32,
    flat_slope: f32,
    direction_window: u32,
    min_move_mm: f32,
}

/// Parses a profile from TOML. `source_name` (a file path or a built-in name)
/// is carried into every error.
pub fn parse(text: &str, source_name: &str) -> Result<DeviceProfile, ProfileError> {
    let err = |key: Option<&str>, message: String| ProfileError {
        source_name: source_name.into(),
        key: key.map(Into::into),
        message,
    };
    let file: File = toml::from_str(text).map_err(|e| err(None, e.to_string().trim_end().replace('\n', " ")))?;
    let name = ProfileName::new(&file.name)
        .ok_or_else(|| err(Some("name"), "expected a name of 1 to 31 bytes without NUL".into()))?;
    let params = match file.family.as_str() {
        "laterotactile" => {
            if file.grid.is_some() || file.finger.is_some() {
                return Err(err(None, "a laterotactile profile has no [grid] or [finger] table".into()));
            }
            FamilyParams::Laterotactile
        }
        "grid" => {
            let g = file.grid.ok_or_else(|| err(Some("grid"), "missing table [grid] for family \"grid\"".into()))?;
            if file.finger.is_some() {
                return Err(err(Some("finger"), "a grid profile has no [finger] table".into()));
            }
            FamilyParams::Grid(GridParams {
                carrier_min_hz: g.carrier_min_hz,
                carrier_max_hz: g.carrier_max_hz,
                audio_rate_hz: g.audio_rate_hz,
                ramp_ms: g.ramp_ms,
            })
        }
        "finger" => {
            let f = file
                .finger
                .ok_or_else(|| err(Some("finger"), "missing table [finger] for family \"finger\"".into()))?;
            if file.grid.is_some() {
                return Err(err(Some("grid"), "a finger profile has no [grid] table".into()));
            }
            FamilyParams::Finger(FingerParams {
                rhythm_max: f.rhythm_max,
                intensity_max: f.intensity_max,
                flat_slope: f.flat_slope,
                direction_window: f.direction_window,
                min_move_mm: f.min_move_mm,
            })
        }
        other => {
            return Err(err(
                Some("family"),
                format!("unknown family \"{other}\", expected \"laterotactile\", \"grid\" or \"finger\""),
            ));
        }
    };
    let profile = DeviceProfile {
        name,
        rows: file.array.rows,
        cols: file.array.cols,
        pitch_x_mm: file.array.pitch_x_mm,
        pitch_y_mm: file.array.pitch_y_mm,
        rate_hz: file.rate_hz,
        output_bits: file.output_bits,
        surface_w_mm: file.surface.width_mm,
        surface_h_mm: file.surface.height_mm,
        params,
    };
    profile.check().map_err(|(key, expected)| err(Some(key), format!("out of range, expected {expected}")))?;
    Ok(profile)
}

/// A built-in profile by name.
pub fn builtin(name: &str) -> Option<DeviceProfile> {
    BUILTIN.iter().find(|(n, _)| *n == name).and_then(|(n, text)| parse(text, n).ok())
}

/// The names of the built-in profiles.
pub fn builtin_names() -> Vec<&'static str> {
    BUILTIN.iter().map(|(n, _)| *n).collect()
}

/// Writes a profile back as TOML in the same layout as the built-in files.
pub fn to_toml(p: &DeviceProfile) -> String {
    let mut s = format!(
        "name = {:?}\nfamily = {:?}\nrate_hz = {}\noutput_bits = {}\n\n[array]\nrows = {}\ncols = {}\npitch_x_mm = {}\npitch_y_mm = {}\n\n[surface]\nwidth_mm = {}\nheight_mm = {}\n",
        p.name.as_str(),
        p.family().name(),
        p.rate_hz,
        p.output_bits,
        p.rows,
        p.cols,
        p.pitch_x_mm,
        p.pitch_y_mm,
        p.surface_w_mm,
        p.surface_h_mm
    );
    match p.params {
        FamilyParams::Laterotactile => {}
        FamilyParams::Grid(g) => {
            s += &format!(
                "\n[grid]\ncarrier_min_hz = {}\ncarrier_max_hz = {}\naudio_rate_hz = {}\nramp_ms = {}\n",
                g.carrier_min_hz, g.carrier_max_hz, g.audio_rate_hz, g.ramp_ms
            )
        }
        FamilyParams::Finger(f) => {
            s += &format!(
                "\n[finger]\nrhythm_max = {}\nintensity_max = {}\nflat_slope = {}\ndirection_window = {}\nmin_move_mm = {}\n",
                f.rhythm_max, f.intensity_max, f.flat_slope, f.direction_window, f.min_move_mm
            )
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtins_parse_with_the_papers_values() {
        let s = builtin("stress2").unwrap();
        assert_eq!((s.rows, s.cols, s.pitch_x_mm, s.pitch_y_mm), (8, 8, 1.2, 1.4));
        assert_eq!((s.rate_hz, s.output_bits, s.surface_w_mm, s.surface_h_mm), (1000, 10, 110.0, 60.0));
        let b = builtin("brush-4x3").unwrap();
        assert_eq!((b.rows, b.cols, b.pitch_x_mm), (3, 4, 63.0));
        let FamilyParams::Grid(g) = b.params else { panic!("brush-4x3 is a grid") };
        assert_eq!((g.carrier_min_hz, g.carrier_max_hz), (150.0, 270.0));
        assert_eq!(builtin("finger3").unwrap().actuator_count(), 3);
        assert!(builtin("nope").is_none());
    }

    #[test]
    fn to_toml_round_trips() {
        for name in builtin_names() {
            let p = builtin(name).unwrap();
            assert_eq!(parse(&to_toml(&p), "x").unwrap(), p);
        }
    }

    #[test]
    fn unknown_field_is_named_with_the_file() {
        let text = BUILTIN[0].1.replace("rate_hz = 1000", "rate_hz = 1000\nspeed = 3");
        let e = parse(&text, "my.toml").unwrap_err();
        assert!(e.to_string().starts_with("my.toml"), "{e}");
        assert!(e.message.contains("speed"), "{e}");
    }

    #[test]
    fn missing_field_is_named() {
        let text = BUILTIN[0].1.replace("rate_hz = 1000", "");
        let e = parse(&text, "my.toml").unwrap_err();
        assert!(e.message.contains("rate_hz"), "{e}");
    }

    #[test]
    fn out_of_range_value_names_the_key() {
        let text = BUILTIN[0].1.replace("pitch_x_mm = 1.2", "pitch_x_mm = -1.2");
        let e = parse(&text, "my.toml").unwrap_err();
        assert_eq!(e.key.as_deref(), Some("pitch_x_mm"), "{e}");
        let text = BUILTIN[0].1.replace("output_bits = 10", "output_bits = 40");
        assert_eq!(parse(&text, "p").unwrap_err().key.as_deref(), Some("output_bits"));
        let text = BUILTIN[0].1.replace("family = \"laterotactile\"", "family = \"piano\"");
        assert_eq!(parse(&text, "p").unwrap_err().key.as_deref(), Some("family"));
    }

    #[test]
    fn grid_profile_needs_its_table() {
        let text = BUILTIN[1].1.split("[grid]").next().unwrap();
        assert_eq!(parse(text, "p").unwrap_err().key.as_deref(), Some("grid"));
    }
}
