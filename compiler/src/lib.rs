//! taxel's compiler: annotated SVG drawings and glTF height meshes in,
//! bundles and diagnostics out. The library does no file IO of its own: it
//! takes bytes and strings, and returns the bundle together with every
//! diagnostic it collected.
//!
//! Entry points: [`svg::compile_svg`] for drawings; [`drawing::resolve`] for
//! the resolved drawing that its layers are built from; [`preview`] draws a
//! bundle the way a reader will feel it; [`geometry`] holds the exact (f64)
//! geometry that error reports compare rasters against.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod annotation;
pub mod auto;
pub mod braille;
pub mod brush;
pub mod budget;
mod diagnostic;
#[doc(hidden)]
pub mod distance;
pub mod drawing;
pub mod fit;
pub mod geometry;
pub mod mesh;
mod options;
pub mod pins;
mod prepare;
pub mod preview;
pub mod print;
pub mod sanity;
pub mod spatial;
pub mod stylesheet;
pub mod svg;
mod text_pos;

pub use diagnostic::{Diagnostic, Severity, has_errors};
pub use options::{CompileOptions, DEFAULT_PX_PER_MM, Region, UpAxis};
pub use stylesheet::{StyleError, StyleSheet};
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
}
