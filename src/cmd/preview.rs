//! `taxel preview INPUT|BUNDLE -o PNG`: a picture of what a reader will feel.
//! A drawing is compiled and drawn over a faint copy of itself; a bundle is
//! drawn from the bundle alone.

use std::path::Path;

use taxel_compiler::Severity;
use taxel_compiler::{pipeline, preview};
use taxel_format::Bundle;

use crate::cli::CompileOpts;
use crate::compile::{compile_file, compile_options};
use crate::error::{CliError, CmdResult};
use crate::io;

pub fn run(input: &Path, out: &Path, opts: &CompileOpts) -> CmdResult {
    let ext = input.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).unwrap_or_default();
    let shown = input.display().to_string();
    let no_picture = || CliError::input(anyhow::anyhow!("{shown}: nothing to preview: the input has errors (above)"));
    let picture = match ext.as_str() {
        "svg" | "svgz" => {
            let options = match compile_options(opts)? {
                Ok(o) => o,
                Err(d) => {
                    eprintln!("{}", d.render(&shown));
                    return Err(no_picture());
                }
            };
            // Read like `build` reads it: with the size limit, and UTF-8 or nothing.
            let text = io::read_drawing(input).map_err(CliError::input)?;
            let (picture, compiled) = pipeline::preview_svg(&text, &options);
            print_diagnostics(&shown, &compiled.diagnostics);
            picture
        }
        "gltf" | "glb" => {
            let compiled = compile_file(input, opts)?;
            print_diagnostics(&shown, &compiled.diagnostics);
            compiled.bundle.as_ref().map(|b| preview::render_bundle(b, None))
        }
        _ if let Some(hint) = crate::batch::discover::convert_hint(&ext) => {
            return Err(CliError::input(anyhow::anyhow!(
                "{shown}: taxel does not read .{ext} files, only drawings (.svg, .svgz), meshes (.gltf, .glb) and bundles: {hint}"
            )));
        }
        _ => {
            let bytes = io::read_bundle(input)?;
            let bundle = Bundle::from_bytes(&bytes)
                .map_err(|e| CliError::input(anyhow::anyhow!("{shown}: not a valid bundle: {e}")))?;
            Some(preview::render_bundle(&bundle, None))
        }
    };
    let picture = picture.ok_or_else(no_picture)?;
    io::write_file(out, &io::png::encode_picture(&picture)?).map_err(anyhow::Error::new)?;
    eprintln!("wrote {} ({} x {} px)", out.display(), picture.width, picture.height);
    Ok(())
}

fn print_diagnostics(file: &str, diags: &[taxel_compiler::Diagnostic]) {
    for line in crate::account::lines(diags, file, Severity::Warning, false) {
        eprintln!("{line}");
    }
}
