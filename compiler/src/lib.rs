//! taxel's compiler: annotated SVG drawings and glTF height meshes in,
//! bundles and diagnostics out. The library does no file IO of its own.
#![forbid(unsafe_code)]
#![warn(missing_docs)]
