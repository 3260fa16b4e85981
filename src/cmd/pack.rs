//! `taxel pack DIR -o BUNDLE`: an unpacked folder back into a bundle.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Result;

use crate::textform::folder;

pub fn run(dir: &Path, out: &Path) -> Result<ExitCode> {
    match folder::pack_to(dir, out) {
        Ok(n) => {
            eprintln!("packed {} into {} ({n} bytes)", dir.display(), out.display());
            Ok(ExitCode::SUCCESS)
        }
        Err(e) => super::bad_input(e),
    }
}
