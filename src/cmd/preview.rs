//! `taxel preview INPUT|BUNDLE -o PNG`: a picture of what a reader will feel.
//! A drawing is compiled and drawn over a faint copy of itself; a bundle is
//! drawn from the bundle alone.

use std::path::Path;
use std::process::ExitCode;

use anyhow::{Context, Result};
use taxel_compiler::Severity;
use taxel_compiler::preview::{self, Picture};
use taxel_format::Bundle;

use crate::batch::output::write_atomic;
use crate::cli::CompileOpts;
use crate::compile::{compile_file, compile_options};

pub fn run(input: &Path, out: &Path, opts: &CompileOpts) -> Result<ExitCode> {
    let ext = input.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).unwrap_or_default();
    let shown = input.display().to_string();
    let picture = match ext.as_str() {
        "svg" => {
            let options = match compile_options(opts)? {
                Ok(o) => o,
                Err(d) => {
                    eprintln!("{}", d.render(&shown));
                    return Ok(ExitCode::from(1));
                }
            };
            let bytes = std::fs::read(input).with_context(|| format!("reading {shown}"))?;
            let text = String::from_utf8_lossy(&bytes);
            let (picture, compiled) = preview::preview_svg(&text, &options);
            print_diagnostics(&shown, &compiled.diagnostics);
            picture
        }
        "gltf" | "glb" => {
            let compiled = compile_file(input, opts)?;
            print_diagnostics(&shown, &compiled.diagnostics);
            compiled.bundle.as_ref().map(|b| preview::render_bundle(b, None))
        }
        _ => {
            let bytes = std::fs::read(input).with_context(|| format!("reading {shown}"))?;
            match Bundle::from_bytes(&bytes) {
                Ok(b) => Some(preview::render_bundle(&b, None)),
                Err(e) => {
                    eprintln!("error: {shown}: not a valid bundle: {e}");
                    return Ok(ExitCode::from(1));
                }
            }
        }
    };
    let Some(picture) = picture else { return Ok(ExitCode::from(1)) };
    write_atomic(out, &encode_png(&picture)?).with_context(|| format!("writing {}", out.display()))?;
    eprintln!("wrote {} ({} x {} px)", out.display(), picture.width, picture.height);
    Ok(ExitCode::SUCCESS)
}

fn print_diagnostics(file: &str, diags: &[taxel_compiler::Diagnostic]) {
    for line in crate::account::lines(diags, file, Severity::Warning, false) {
        eprintln!("{line}");
    }
}

pub(crate) fn encode_png(p: &Picture) -> Result<Vec<u8>> {
    let img = image::RgbaImage::from_raw(p.width, p.height, p.rgba.clone()).context("preview has the wrong size")?;
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png)?;
    Ok(out.into_inner())
}
