//! Integration tests of the compiler, one module per area.

mod brush;
mod common;
mod diagnostics;
mod drawing;
mod golden;
mod malformed;
mod mesh;
mod realistic;
mod scenes;
