//! `taxel pack DIR -o BUNDLE`: an unpacked folder back into a bundle.

use std::path::Path;

use crate::error::CmdResult;
use crate::textform::folder;

pub fn run(dir: &Path, out: &Path) -> CmdResult {
    let n = folder::pack_to(dir, out).map_err(super::text_error)?;
    eprintln!("packed {} into {} ({n} bytes)", dir.display(), out.display());
    Ok(())
}
