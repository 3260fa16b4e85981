//! Integration tests of the compiler, one module per area.

mod brush;
