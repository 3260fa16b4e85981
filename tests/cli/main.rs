//! End-to-end tests of the `taxel` command line, one module per area.

mod batch;
mod braille;
mod brush;
mod compile;
mod device;
mod examples;
mod finger;
mod finger_size;
mod format;
mod inkscape;
mod key;
mod lookup;
mod outputs;
mod pins;
mod play;
mod played;
mod print;
mod real;
mod report;
mod runaway;
mod stability;
mod studio;
mod studio_wasm;
