//! Writes the drawings of the studio's benchmark (`tests/browser/bench.mjs`)
//! into the folder given as the only argument: generated Inkscape maps of
//! touching regions, by the generator the compiler's benchmarks and the CLI
//! tests share (`compiler/benches/drawings`), so the studio is measured on
//! the drawings the build is measured on.
//!
//! - `map1000.svg`: the real-size map of `benches/real_build.rs` (1,000
//!   regions, over 1 MB), rebuilt after a style change;
//! - `map2000.svg`: 2,000 regions, explored.
//!
//! `cargo run --example studio_scenes -- DIR` (bench.mjs runs it).

use std::path::PathBuf;

#[path = "../compiler/benches/drawings/mod.rs"]
mod drawings;

fn main() -> std::io::Result<()> {
    let Some(dir) = std::env::args_os().nth(1).map(PathBuf::from) else {
        eprintln!("usage: studio_scenes DIR");
        std::process::exit(2);
    };
    std::fs::create_dir_all(&dir)?;
    // The same arguments as benches/real_build.rs's map.
    std::fs::write(dir.join("map1000.svg"), drawings::inkscape_map(1_000, 16, 11))?;
    std::fs::write(dir.join("map2000.svg"), drawings::inkscape_map(2_000, 8, 12))?;
    Ok(())
}
