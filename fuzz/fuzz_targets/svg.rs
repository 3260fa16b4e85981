//! Fuzzes the whole SVG front end: a drawing generated from the bytes
//! (`compiler/tests/compiler/svggen.rs`: non-ASCII layer labels, entities,
//! deep nesting, huge and non-finite numbers, every kind of `<use>`), or
//! the bytes themselves where they are an SVG document (the seeds that
//! `cargo run --example fuzz_seeds` writes from the drawing generators of
//! issue 47: scribbles, scatter plots, jittered rings, maps, charts), is
//! compiled for STRESS². It must never panic, and the internal-error
//! diagnostic T0900 counts as a crash.
#![no_main]

use libfuzzer_sys::fuzz_target;
use taxel_compiler::CompileOptions;
use taxel_compiler::compile_svg;

#[path = "../../compiler/tests/compiler/svggen.rs"]
mod svggen;

fuzz_target!(|data: &[u8]| {
    let Some(profile) = taxel_format::profiles::builtin("stress2") else { return };
    let svg = svggen::drawing(data);
    let c = compile_svg(&svg, &CompileOptions::new(profile));
    assert!(!c.diagnostics.iter().any(|d| d.code == "T0900"), "internal error on\n{svg}");
});
