//! `taxel unpack BUNDLE -o DIR`: a bundle as a folder people can edit.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Result;

use crate::textform::folder;

pub fn run(bundle: &Path, out: &Path) -> Result<ExitCode> {
    match folder::unpack_to(bundle, out) {
        Ok(n) => {
            eprintln!("unpacked {} into {} ({n} files)", bundle.display(), out.display());
            Ok(ExitCode::SUCCESS)
        }
        Err(e) => super::bad_input(e),
    }
}
