//! Integration tests of the compiler, one module per area.

mod brush;
mod common;
mod diagnostics;
mod golden;
mod malformed;
mod mesh;
mod scenes;
