//! Compile-time benchmark (filled in with the SVG pipeline).
fn main() {}
