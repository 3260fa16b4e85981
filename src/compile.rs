//! Compiling one input file, whatever its kind: the CLI's single entry into
//! the compiler, used by `build`, `check`, `preview`, `report` and the demo.

use std::path::Path;

use anyhow::Result;
use taxel_compiler::Compiled;

use crate::cli::CompileOpts;

/// Reads and compiles one input (.svg, .gltf, .glb). IO failures are `Err`;
/// problems in the input are diagnostics in the result.
pub fn compile_file(path: &Path, opts: &CompileOpts) -> Result<Compiled> {
    check_input_size(path)?;
    let _ = opts;
    anyhow::bail!("{}: compiling is not available yet (issues 3 and 6)", path.display())
}

/// Largest input file taxel reads, in bytes (docs/stability.md): far above
/// any drawing a person makes, far below what would exhaust memory once
/// usvg's tree and the masks are built from it.
pub const MAX_INPUT_BYTES: u64 = 64 << 20;

/// Refuses an input larger than [`MAX_INPUT_BYTES`] before reading it.
pub fn check_input_size(path: &Path) -> Result<()> {
    let len = std::fs::metadata(path).map_err(|e| anyhow::anyhow!("cannot read {}: {e}", path.display()))?.len();
    if len > MAX_INPUT_BYTES {
        anyhow::bail!(
            "{}: the file is {:.1} MB, larger than the {} MB input limit; split the drawing or remove embedded images",
            path.display(),
            len as f64 / (1 << 20) as f64,
            MAX_INPUT_BYTES >> 20
        );
    }
    Ok(())
}
