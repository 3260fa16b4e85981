//! The examples index, `examples/examples.toml`: the scenes the demo builds
//! and the traces the report plays for them.

use std::path::Path;

use anyhow::{Context, Result};
use serde::Deserialize;

/// One `[[scene]]` of the examples index.
#[derive(Debug, Clone, Deserialize)]
pub struct Scene {
    /// Unique name.
    pub name: String,
    /// The drawing or mesh, relative to the index's folder.
    pub input: String,
    /// Device profile.
    pub profile: String,
    /// Exploration trace, relative to the index's folder.
    pub trace: Option<String>,
    /// Style sheet, relative to the index's folder.
    pub style: Option<String>,
}

#[derive(Deserialize)]
struct Index {
    #[serde(default)]
    scene: Vec<Scene>,
}

/// Reads an examples index.
pub fn read_index(path: &Path) -> Result<Vec<Scene>> {
    let text = crate::io::read_input_text(path)?;
    let index: Index =
        toml::from_str(&text).with_context(|| format!("{} is not a valid examples index", path.display()))?;
    Ok(index.scene)
}
