//! `taxel unpack BUNDLE -o DIR`: a bundle as a folder people can edit.

use std::path::Path;

use crate::error::CmdResult;
use crate::textform;

pub fn run(bundle: &Path, out: &Path) -> CmdResult {
    let n = textform::unpack_to(bundle, out).map_err(super::text_error)?;
    eprintln!("unpacked {} into {} ({n} files)", bundle.display(), out.display());
    Ok(())
}
