//! `taxel style auto [INPUT]`: the built-in automatic style sheet as TOML, a
//! starting point for a teacher's own sheet; with a drawing, the sheet as
//! the automatic conversion decides it for that drawing (after `--fit` and
//! `--region`, as a build would).

use std::path::Path;
use std::process::ExitCode;

use anyhow::{Context, Result};
use taxel_compiler::{Severity, auto, drawing, fit};

use crate::cli::{BuiltinSheet, CompileOpts};
use crate::compile::{compile_options, resolve_profile};

pub fn run(sheet: BuiltinSheet, input: Option<&Path>, opts: &CompileOpts) -> Result<ExitCode> {
    let BuiltinSheet::Auto = sheet;
    let Some(path) = input else {
        let profile = resolve_profile(opts.profile.as_deref())?;
        print!("{}", auto::sheet_toml(&profile, None));
        return Ok(ExitCode::SUCCESS);
    };
    let shown = path.display().to_string();
    crate::compile::check_input_size(path)?;
    let options = match compile_options(opts)? {
        Ok(o) => o,
        Err(d) => {
            eprintln!("{}", d.render(&shown));
            return Ok(ExitCode::from(1));
        }
    };
    let bytes = std::fs::read(path).with_context(|| format!("reading {shown}"))?;
    let Ok(text) = String::from_utf8(bytes) else {
        eprintln!("{shown}: error[T0200]: the file is not UTF-8 text, expected an SVG document");
        return Ok(ExitCode::from(1));
    };
    let resolved = drawing::resolve_as_drawn(&text, &options);
    let mut diags = resolved.diagnostics;
    let mut drawing = resolved.drawing.filter(|_| !taxel_compiler::has_errors(&diags));
    let placed = match &mut drawing {
        Some(d) => fit::apply(d, &options.profile, options.fit, options.region.as_ref(), &mut diags),
        None => false,
    };
    let Some(d) = drawing.filter(|_| placed) else {
        for line in crate::account::lines(&diags, &shown, Severity::Warning, false) {
            eprintln!("{line}");
        }
        return Ok(ExitCode::from(1));
    };
    let plan = auto::plan(&d, &options.profile);
    print!("{}", auto::sheet_toml(&options.profile, Some((&d, &plan))));
    Ok(ExitCode::SUCCESS)
}
