//! `taxel style auto [INPUT]`: the built-in automatic style sheet as TOML, a
//! starting point for a teacher's own sheet; with a drawing, the sheet as
//! the automatic conversion decides it for that drawing.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Result;

use crate::cli::{BuiltinSheet, CompileOpts};
use crate::compile::resolve_profile;

pub fn run(sheet: BuiltinSheet, input: Option<&Path>, opts: &CompileOpts) -> Result<ExitCode> {
    let BuiltinSheet::Auto = sheet;
    let profile = resolve_profile(opts.profile.as_deref())?;
    match input {
        None => {
            print!("{}", taxel_compiler::auto::sheet_toml(&profile, None));
            Ok(ExitCode::SUCCESS)
        }
        Some(path) => {
            eprintln!(
                "error: `taxel style auto {}`: the sheet for one drawing is not built yet; `taxel style auto` prints the general sheet",
                path.display()
            );
            Ok(ExitCode::from(2))
        }
    }
}
