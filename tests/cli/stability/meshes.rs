//! Height meshes at the edges: vertical cliffs, sliver and degenerate
//! triangles, micrometre and kilometre scales, and NaN or infinity in glTF.
//! Every field value is finite, every gradient within the field's cap, and
//! the finger player's output finite and in range along a sweep.

use taxel_compiler::Compiled;
use taxel_compiler::mesh::{MeshOptions, compile_gltf, write::HeightMesh};
use taxel_format::{BundleView, Chunk, FIELD_EDGE, Mm, Tick, profiles};
use taxel_runtime::finger::{FingerPlayer, Touch};

use super::{codes, has};

fn build(m: &HeightMesh) -> Compiled {
    let profile = profiles::builtin("finger3").expect("profile");
    compile_gltf(&m.to_glb(), &mut |_| Err("no files".into()), &profile, &MeshOptions::default())
}

/// Checks the field and sweeps the finger across its middle row.
fn check_and_sweep(out: &Compiled) {
    let b = out.bundle.as_ref().unwrap_or_else(|| panic!("{:?}", codes(&out.diagnostics)));
    let hf =
        b.chunks.iter().find_map(|c| if let Chunk::Height(h) = c { Some(h) } else { None }).expect("a height field");
    assert!(hf.gradient_cap.is_finite() && hf.gradient_cap > 0.0);
    for i in 0..hf.heights.len() {
        assert!(hf.heights[i].is_finite() && hf.grad_x[i].is_finite() && hf.grad_y[i].is_finite());
        assert!(hf.grad_x[i].abs() <= hf.gradient_cap * 1.0001 && hf.grad_y[i].abs() <= hf.gradient_cap * 1.0001);
    }
    let bytes = b.to_bytes().expect("writes");
    let view = BundleView::parse(&bytes).expect("reads");
    let mut player = FingerPlayer::new(&view).expect("finger bundle");
    let (x0, y0) = (hf.origin_x.0 as f64, hf.origin_y.0 as f64);
    let (w, h) = (hf.cell.0 as f64 * (hf.cols.max(2) - 1) as f64, hf.cell.0 as f64 * (hf.rows.max(2) - 1) as f64);
    for k in 0..=400u64 {
        let x = x0 - 0.1 * w + 1.2 * w * k as f64 / 400.0;
        let f =
            player.sample(Touch { tick: Tick(k * 10), x: Mm(x as f32), y: Mm((y0 + h / 2.0) as f32), contact: true });
        assert!(f.intensity.is_finite() && f.rhythm.is_finite() && f.period_ms.is_finite() && f.height.is_finite());
        assert!(f.intensity >= 0.0 && f.rhythm >= 0.0 && f.period_ms >= 0.0, "{f:?}");
    }
}

/// A 10 mm step (a vertical wall between two flat terraces): the wall
/// triangles have no area from above (note T0611); the step is flagged as
/// an edge with a finite, capped gradient.
#[test]
fn vertical_cliff() {
    // Terraces from x = 0..20 mm at height 0 and x = 20..40 mm at height 10 mm, 20 mm deep.
    let mut m = HeightMesh::grid(4, 2, |u, v| [0.02 * u, 0.0, 0.02 * v]);
    m.append(&HeightMesh::grid(4, 2, |u, v| [0.02 + 0.02 * u, 0.01, 0.02 * v]));
    m.append(&HeightMesh::grid(1, 2, |u, v| [0.02, 0.01 * u, 0.02 * v]));
    let out = build(&m);
    assert!(has(&out.diagnostics, "T0611"), "{:?}", codes(&out.diagnostics));
    check_and_sweep(&out);
    let b = out.bundle.as_ref().expect("bundle");
    let hf = b.chunks.iter().find_map(|c| if let Chunk::Height(h) = c { Some(h) } else { None }).expect("field");
    assert!(hf.flags.iter().any(|f| f & FIELD_EDGE != 0), "the step is not flagged");
}

/// Sliver triangles (a millionth of a millimetre wide) and duplicate
/// vertices inside an ordinary ramp: skipped or absorbed, never NaN.
#[test]
fn sliver_and_degenerate_triangles() {
    let mut m = HeightMesh::grid(3, 3, |u, v| [0.03 * u, 0.005 * u, 0.03 * v]);
    let n = m.positions.len() as u32;
    m.positions.extend([[0.0, 0.0, 0.015], [0.03, 0.005, 0.015], [0.015, 0.0025, 0.015 + 1e-9]]);
    m.positions.extend([[0.01, 0.001, 0.01], [0.01, 0.001, 0.01], [0.01, 0.001, 0.01]]);
    m.indices.extend([n, n + 1, n + 2, n + 3, n + 4, n + 5]);
    let out = build(&m);
    check_and_sweep(&out);
}

/// A 1 µm mesh and a 10 m mesh (the range docs/finger.md supports) build
/// with finite values; a kilometre mesh is beyond the surface (T0612) or
/// refused by the field-size limit (T0607), never out of memory.
#[test]
fn micrometre_and_kilometre_scales() {
    for size_m in [1e-6f64, 10.0] {
        let m = HeightMesh::grid(4, 4, |u, v| [size_m * u, size_m * 0.2 * u * v, size_m * v]);
        check_and_sweep(&build(&m));
    }
    let m = HeightMesh::grid(4, 4, |u, v| [1000.0 * u, 10.0 * u * v, 1000.0 * v]);
    let out = build(&m);
    assert!(has(&out.diagnostics, "T0612") || has(&out.diagnostics, "T0607"), "{:?}", codes(&out.diagnostics));
    if out.bundle.is_some() {
        check_and_sweep(&out);
    }
}

/// NaN or infinity in positions (patched into the binary buffer, so that
/// the JSON stays valid) or in a node's translation: an error that
/// names the mesh (T0604, the POSITION accessor), and no bundle.
#[test]
fn nan_and_infinity_in_gltf() {
    let profile = profiles::builtin("finger3").expect("profile");
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let mut m = HeightMesh::grid(2, 2, |u, v| [0.02 * u, 0.0, 0.02 * v]);
        m.name = "terrain".into();
        let mut glb = m.to_glb();
        // GLB: 12-byte header, JSON chunk (8-byte header + body), BIN chunk header (8 bytes).
        let json_len = u32::from_le_bytes(glb[12..16].try_into().expect("4 bytes")) as usize;
        let bin = 12 + 8 + json_len + 8;
        let at = bin + (3 + 1) * 4; // vertex 1, component Y
        glb[at..at + 4].copy_from_slice(&bad.to_le_bytes());
        let out = compile_gltf(&glb, &mut |_| Err("no files".into()), &profile, &MeshOptions::default());
        assert!(out.bundle.is_none(), "{bad} accepted");
        // The accessor check catches it (T0604) before any geometry does (T0605 would be next).
        let d = out
            .diagnostics
            .iter()
            .find(|d| d.code == "T0604" || d.code == "T0605")
            .unwrap_or_else(|| panic!("{:?}", out.diagnostics));
        assert!(d.message.contains("terrain") && d.message.contains("finite"), "{}", d.message);
    }
    // In JSON text a NaN is not even a number: the file is refused as malformed (T0601).
    let mut m = HeightMesh::grid(2, 2, |u, v| [0.02 * u, 0.0, 0.02 * v]);
    m.translation = Some([0.0, f32::NAN, 0.0]);
    let out = build(&m);
    assert!(
        out.bundle.is_none() && (has(&out.diagnostics, "T0601") || has(&out.diagnostics, "T0605")),
        "{:?}",
        out.diagnostics
    );
}
