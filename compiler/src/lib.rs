//! taxel's compiler: annotated SVG drawings and glTF height meshes in,
//! bundles and diagnostics out. The library does no file IO of its own: it
//! takes bytes and strings, and returns the bundle together with every
//! diagnostic it collected.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod brush;
pub mod diagnostic;
pub mod mesh;

pub use diagnostic::{Diagnostic, Severity, has_errors};

use taxel_format::Bundle;

/// What a compilation produced: the bundle (absent when there were errors)
/// and every diagnostic.
#[derive(Debug, Clone)]
pub struct Compiled {
    /// The bundle, unless an error prevented it.
    pub bundle: Option<Bundle>,
    /// Everything the compiler had to say, in source order where possible.
    pub diagnostics: Vec<Diagnostic>,
}
