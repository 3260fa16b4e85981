//! `taxel style auto [INPUT]`: the built-in automatic style sheet as TOML, a
//! starting point for a teacher's own sheet; with a drawing, the sheet as
//! the automatic conversion decides it for that drawing (after `--fit` and
//! `--region`, as a build would).

use std::path::Path;

use taxel_compiler::{CompileOptions, Diagnostic, Severity, drawing, place, style};

use crate::cli::{BuiltinSheet, CompileOpts};
use crate::compile::compile_options;
use crate::error::{CliError, CmdResult};
use crate::io;

pub fn run(sheet: BuiltinSheet, input: Option<&Path>, opts: &CompileOpts) -> CmdResult {
    let BuiltinSheet::Auto = sheet;
    let Some(path) = input else {
        let profile = io::load::profile(opts.profile.as_deref().unwrap_or(io::load::DEFAULT_DRAWING_PROFILE))?;
        return io::stdout::print(&style::sheet_toml(&profile, None));
    };
    let shown = path.display().to_string();
    let options = match compile_options(opts)? {
        Ok(o) => o,
        Err(d) => {
            eprintln!("{}", d.render(&shown));
            return Err(CliError::input(anyhow::anyhow!("{shown}: the style sheet is malformed")));
        }
    };
    let text = io::read_drawing(path).map_err(CliError::input)?;
    match decided(&text, &options) {
        Ok(sheet) => io::stdout::print(&sheet),
        Err(diags) => {
            for line in crate::account::lines(&diags, &shown, Severity::Warning, false) {
                eprintln!("{line}");
            }
            Err(CliError::input(anyhow::anyhow!("{shown}: no style sheet can be made for this drawing")))
        }
    }
}

/// The automatic style sheet as decided for the drawing `text` (after
/// `--fit` and `--region`, as a build would), as TOML; the diagnostics that
/// say why none can be made. `taxel studio` starts a teacher's sheet from it.
pub fn decided(text: &str, options: &CompileOptions) -> Result<String, Vec<Diagnostic>> {
    let resolved = drawing::resolve(text, options);
    let mut diags = resolved.diagnostics;
    let mut drawing = resolved.drawing.filter(|_| !taxel_compiler::has_errors(&diags));
    let placed = match &mut drawing {
        Some(d) => {
            place::apply(d, &options.profile, options.fit, options.region.as_ref(), options.flattening, &mut diags)
        }
        None => false,
    };
    let Some(d) = drawing.filter(|_| placed) else { return Err(diags) };
    let plan = style::plan(&d, &options.profile);
    Ok(style::sheet_toml(&options.profile, Some((&d, &plan))))
}
