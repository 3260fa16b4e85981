//! `taxel check INPUT... [--format human|json]`: compile without writing and
//! print every diagnostic; exit 1 when any input has errors.

use std::path::PathBuf;

use serde::Serialize;
use taxel_compiler::{Diagnostic, Severity};

use crate::batch;
use crate::cli::{CompileOpts, Format};
use crate::compile::compile_file;
use crate::error::{CliError, CmdResult};
use crate::io::stdout::outln;

#[derive(Serialize)]
struct FileReport<'a> {
    file: String,
    errors: usize,
    warnings: usize,
    diagnostics: &'a [Diagnostic],
}

pub fn run(inputs: &[PathBuf], opts: &CompileOpts, format: Format, verbose: bool) -> CmdResult {
    let (found, problems) = batch::discover(inputs)?;
    let mut failed = !problems.is_empty();
    for p in &problems {
        eprintln!("error: {p}");
    }
    let mut reports: Vec<(String, Vec<Diagnostic>)> = Vec::new();
    for input in &found {
        let shown = input.path.display().to_string();
        match compile_file(&input.path, opts) {
            Ok(c) => reports.push((shown, c.diagnostics)),
            Err(e) => {
                failed = true;
                let d = Diagnostic::error("T0001", format!("{e:#}"));
                reports.push((shown, vec![d]));
            }
        }
    }
    let count = |d: &[Diagnostic], s: Severity| d.iter().filter(|x| x.severity == s).count();
    for (_, d) in &reports {
        failed |= count(d, Severity::Error) > 0;
    }
    match format {
        Format::Json => {
            let out: Vec<FileReport> = reports
                .iter()
                .map(|(f, d)| FileReport {
                    file: f.clone(),
                    errors: count(d, Severity::Error),
                    warnings: count(d, Severity::Warning),
                    diagnostics: d,
                })
                .collect();
            outln!("{}", serde_json::to_string_pretty(&out).map_err(anyhow::Error::new)?)?;
        }
        Format::Human => {
            for (file, diags) in &reports {
                for line in crate::account::lines(diags, file, Severity::Note, verbose) {
                    outln!("{line}")?;
                }
                let (e, w) = (count(diags, Severity::Error), count(diags, Severity::Warning));
                let styles = crate::account::style_summary(diags).map(|s| format!("; {s}")).unwrap_or_default();
                outln!("{file}: {}, {e} error(s), {w} warning(s){styles}", if e > 0 { "failed" } else { "ok" })?;
            }
        }
    }
    if failed {
        return Err(CliError::input(anyhow::anyhow!("the check failed: see the diagnostics above")));
    }
    Ok(())
}
