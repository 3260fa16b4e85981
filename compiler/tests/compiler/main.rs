//! Integration tests of the compiler, one module per area.

mod brush;
mod common;
mod diagnostics;
mod drawing;
mod fuzzed;
mod golden;
mod layout;
mod legend;
mod lookup;
mod malformed;
mod mesh;
mod mesh_axis;
mod plan;
mod realistic;
mod runaway;
mod scenes;
mod sizes;
mod svggen;
