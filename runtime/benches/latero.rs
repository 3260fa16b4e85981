//! Benchmarks of the laterotactile player.
fn main() {}
