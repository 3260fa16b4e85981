//! Device profiles and style sheets: one loader each, used by every command.

use std::path::Path;

use anyhow::{Result, bail};
use taxel_compiler::{Diagnostic, StyleSheet};
use taxel_format::{DeviceProfile, profiles};

/// The profile a drawing is compiled for when `--profile` is not given.
pub const DEFAULT_DRAWING_PROFILE: &str = "stress2";
/// The profile a glTF mesh is compiled for when `--profile` is not given: a
/// mesh only plays on a finger device.
pub const DEFAULT_MESH_PROFILE: &str = "finger3";

/// The profile `spec` names: a built-in name, else a profile TOML file.
pub fn profile(spec: &str) -> Result<DeviceProfile> {
    if let Some(p) = profiles::builtin(spec) {
        return Ok(p);
    }
    let path = Path::new(spec);
    if !path.is_file() {
        bail!("--profile {spec}: not a built-in profile ({}) nor a profile file", profiles::builtin_names().join(", "));
    }
    let text = super::read_input_text(path)?;
    Ok(profiles::parse(&text, spec)?)
}

/// Reads the style sheet at `path`. A file that cannot be read is `Err`; one
/// that is malformed is the diagnostic T0110, an input problem reported like
/// the drawing's own.
pub fn style_sheet(path: &Path) -> Result<Result<StyleSheet, Diagnostic>> {
    let text = super::read_input_text(path)?;
    Ok(StyleSheet::parse(&text, &path.display().to_string()).map_err(|e| {
        Diagnostic::error("T0110", format!("the style sheet is malformed: {e}"))
            .with_help("see docs/annotations.md, \"Style sheets\"")
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profiles_by_name_or_file_and_a_clear_refusal() {
        assert_eq!(profile("stress2").unwrap().name.as_str(), "stress2");
        let e = format!("{:#}", profile("no-such-profile").unwrap_err());
        assert!(e.starts_with("--profile no-such-profile: not a built-in profile (") && e.contains("stress2"), "{e}");
    }

    #[test]
    fn a_malformed_style_sheet_is_t0110() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("s.toml");
        std::fs::write(&p, "this is = = not toml").unwrap();
        let d = style_sheet(&p).unwrap().unwrap_err();
        assert_eq!(d.code, "T0110");
        assert!(style_sheet(&dir.path().join("missing.toml")).is_err());
    }
}
