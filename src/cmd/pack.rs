//! `taxel pack DIR -o BUNDLE`: an unpacked folder back into a bundle.

use std::path::Path;

use crate::error::CmdResult;
use crate::textform;

pub fn run(dir: &Path, out: &Path) -> CmdResult {
    let n = textform::pack_to(dir, out).map_err(super::text_error)?;
    eprintln!("packed {} into {} ({n} bytes)", dir.display(), out.display());
    Ok(())
}
