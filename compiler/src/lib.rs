//! taxel's compiler: annotated SVG drawings and glTF height meshes in,
//! bundles and diagnostics out. The library does no file IO of its own: it
//! takes bytes and strings, and returns the bundle together with every
//! diagnostic it collected.
//!
//! Entry points: [`compile_svg`] for drawings (the [`pipeline`]);
//! [`mesh::compile_gltf`] for meshes; [`drawing::resolve`] for the drawing
//! as written and [`pipeline::resolve`] for the drawing its layers are built
//! from; [`preview`]
//! draws a bundle the way a reader will feel it; [`geometry`] holds the exact
//! (f64) geometry that error reports compare rasters against.
//!
//! The modules are declared below in the pipeline's order, top down: each
//! imports only from those declared after it (a test checks this, and that
//! no circle of imports remains). ARCHITECTURE.md has the map.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

// The stages, in the order a drawing goes through them (ARCHITECTURE.md
// has the map): each imports only from those below it.
pub mod pipeline;
pub mod sanity;
pub mod rules;
pub mod latero;
pub mod brush;
pub mod pins;
pub mod mesh;
pub mod print;
pub mod preview;
pub mod style;
pub mod place;
pub mod braille;
pub mod drawing;
mod options;
pub mod annotation;
pub mod spatial;
pub mod geometry;
pub mod budget;
mod diagnostic;
mod text_pos;

pub use annotation::sheet::{StyleError, StyleSheet};
pub use diagnostic::{Diagnostic, Severity, has_errors};
pub use options::{CompileOptions, DEFAULT_PX_PER_MM, Region, UpAxis};
pub use pipeline::{compile_svg, compile_svg_with_fonts};
/// The font database type of [`CompileOptions::fonts`] (usvg's `fontdb`).
pub use usvg::fontdb;

use taxel_format::Bundle;

/// What a compilation produced: the bundle (absent when there were errors)
/// and every diagnostic.
#[derive(Debug, Clone)]
pub struct Compiled {
    /// The bundle, unless an error prevented it.
    pub bundle: Option<Bundle>,
    /// Everything the compiler had to say, in source order where possible.
    pub diagnostics: Vec<Diagnostic>,
    /// The font faces a drawing's text was laid out with, sorted (the same
    /// as [`drawing::fonts_used`] of its text; empty for a mesh), so that a
    /// content hash that covers them needs no second parse.
    pub fonts_used: Vec<drawing::FontFace>,
    /// For a print profile, the legalised sheet (absent when there were
    /// errors), written as the medium's file by [`print::write`]; print
    /// media make no bundle.
    pub print: Option<print::Sheet>,
    /// For a laterotactile array or a vibrotactile grid whose drawing needs a
    /// key, the key's own bundles for the same profile, a page each, first
    /// page first (SPEC.md section 10.2: each texture, line style, symbol or
    /// brushed stroke felt as itself beside its meaning; a page's
    /// [`latero::key::PAGE_ID`] entry says which page it is when there are
    /// several); empty otherwise, and when there were errors.
    pub key: Vec<Bundle>,
}
