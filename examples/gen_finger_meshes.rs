//! Writes the five test shapes of seed 002 to `examples/finger/`: each as a
//! binary glTF (`<shape>.glb`), a glTF with an embedded buffer
//! (`<shape>.gltf`), and a left-to-right sweep trace (`<shape>.trace.csv`).
//! Output is deterministic; run `cargo run --example gen_finger_meshes` and
//! commit the result.

use std::fmt::Write as _;
use std::path::Path;

use taxel_compiler::mesh::shapes::{FOOTPRINT, SWEEP_Y, Shape};

/// Sweep speed per shape, mm/s (the paper's subjects slid at a few cm/s).
fn speed(shape: Shape) -> f64 {
    match shape {
        Shape::Edge => 30.0,
        Shape::Flat => 40.0,
        Shape::Inclined => 50.0,
        Shape::Convex => 60.0,
        Shape::Concave => 70.0,
    }
}

/// A left-to-right sweep along `SWEEP_Y`, starting 10 mm left of the shape
/// and ending 10 mm right of it, sampled at 100 Hz like a tablet, with the
/// coarse, jittery positions of a touch screen (0.25 mm steps, ±0.5 mm
/// across the stroke), then the finger lifts.
fn trace(shape: Shape) -> String {
    let [x0, _, x1, _] = FOOTPRINT;
    let (start, end) = (x0 - 10.0, x1 + 10.0);
    let v = speed(shape);
    let mut s = String::from("t_ms,x_mm,y_mm,contact\n");
    // A fixed linear congruential generator: the same jitter on every run.
    let mut seed: u32 = 0x2545_f491 ^ shape.name().len() as u32;
    let mut k = 0u32;
    loop {
        let t_ms = 10.0 * k as f64;
        let x = start + v * t_ms / 1000.0;
        if x > end {
            break;
        }
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        let jitter = (seed >> 8) as f64 / (1u32 << 24) as f64 - 0.5;
        let q = |p: f64| (p * 4.0).round() / 4.0;
        let _ = writeln!(s, "{t_ms},{},{},1", q(x), q(SWEEP_Y + jitter));
        k += 1;
    }
    let _ = writeln!(s, "{},{},{},0", 10.0 * k as f64, (end * 4.0).round() / 4.0, SWEEP_Y);
    s
}

fn main() -> std::io::Result<()> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/finger");
    std::fs::create_dir_all(&dir)?;
    for shape in Shape::ALL {
        let mesh = shape.mesh();
        std::fs::write(dir.join(format!("{}.glb", shape.name())), mesh.to_glb())?;
        std::fs::write(dir.join(format!("{}.gltf", shape.name())), mesh.to_gltf_embedded())?;
        std::fs::write(dir.join(format!("{}.trace.csv", shape.name())), trace(shape))?;
        println!("{}: {} triangles", shape.name(), mesh.indices.len() / 3);
    }
    Ok(())
}
