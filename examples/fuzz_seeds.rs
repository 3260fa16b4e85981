//! Writes the seeds of the `svg` fuzz target (`fuzz/`) into the folder given
//! as the only argument (`fuzz/corpus/svg` when none is): the drawing
//! generators' classes (`compiler/benches/drawings`: the scribbles, scatter
//! plots and jittered rings of issue 47, a map, a city plan, a chart) at
//! small sizes, as SVG documents, which the target compiles as they are.
//!
//! `cargo run --example fuzz_seeds`, then, in `fuzz/`,
//! `cargo +nightly fuzz run svg corpus/svg -- -max_len=65536`.

use std::path::PathBuf;

#[path = "../compiler/benches/drawings/mod.rs"]
mod drawings;

fn main() -> std::io::Result<()> {
    let dir = std::env::args_os().nth(1).map_or_else(|| PathBuf::from("fuzz/corpus/svg"), PathBuf::from);
    std::fs::create_dir_all(&dir)?;
    for (name, svg) in drawings::fuzz_seeds() {
        std::fs::write(dir.join(name), svg)?;
    }
    println!("wrote {} seeds to {}", drawings::fuzz_seeds().len(), dir.display());
    Ok(())
}
