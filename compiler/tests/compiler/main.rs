//! Integration tests of the compiler, one module per area.

mod brush;
mod common;
mod diagnostics;
mod malformed;
mod scenes;
