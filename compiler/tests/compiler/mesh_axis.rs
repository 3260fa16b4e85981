//! The height axis of a mesh: chosen from the model's shape when `--up` is
//! not given (note T0619), and any axis, even one that shows the triangles
//! edge on, builds to the exact top surface.

use taxel_compiler::UpAxis;
use taxel_compiler::mesh::write::HeightMesh;
use taxel_compiler::mesh::{self, MeshOptions};
use taxel_format::{FIELD_CONTACT, HeightField, profiles};

fn no_files(_: &str) -> Result<Vec<u8>, String> {
    Err("no external files in this test".into())
}

/// A wavy terrain of `n` x `n` quads, 4 km a side and 200 m high, with its
/// height along model +Y (`y_up`) or +Z.
fn terrain(n: u32, y_up: bool) -> HeightMesh {
    HeightMesh::grid(n, n, |u, v| {
        let h = 100.0 + 60.0 * (7.0 * u).sin() * (5.0 * v).cos() + 25.0 * (23.0 * u + 3.0).sin() * (19.0 * v).sin();
        if y_up { [4000.0 * u, h, 4000.0 * v] } else { [4000.0 * u, 4000.0 * v, h] }
    })
}

fn build(m: &HeightMesh, opts: &MeshOptions) -> HeightField {
    match mesh::height_field(&m.to_glb(), &mut no_files, opts) {
        Ok((f, _)) => f,
        Err(e) => panic!("{e}"),
    }
}

#[test]
fn a_model_flat_across_z_is_read_z_up_by_default_with_a_note() {
    let profile = profiles::builtin("finger3").unwrap();
    let fit = |up| MeshOptions { up, fit: Some([160.0, 100.0]), ..MeshOptions::default() };
    let z_terrain = terrain(20, false);
    let out = mesh::compile_gltf(&z_terrain.to_glb(), &mut no_files, &profile, &fit(None));
    assert!(out.bundle.is_some(), "{:?}", out.diagnostics);
    let note = out.diagnostics.iter().find(|d| d.code == "T0619").expect("the note on the chosen axis");
    assert!(note.message.contains("+Z is taken as up"), "{note:?}");
    assert!(note.help.as_deref().unwrap_or("").contains("--up y"), "{note:?}");
    assert!(out.diagnostics.iter().all(|d| d.code != "T0616"), "{:?}", out.diagnostics);
    // The default is exactly what `--up z` builds.
    assert_eq!(build(&z_terrain, &fit(None)), build(&z_terrain, &fit(Some(UpAxis::Z))));

    // A terrain flat across Y keeps glTF's +Y, without a note, as does a
    // model flat across neither axis; `--up y` is obeyed.
    let y_terrain = terrain(20, true);
    for (m, up) in [(&y_terrain, None), (&y_terrain, Some(UpAxis::Y))] {
        let out = mesh::compile_gltf(&m.to_glb(), &mut no_files, &profile, &fit(up));
        assert!(out.bundle.is_some() && out.diagnostics.iter().all(|d| d.code != "T0619"), "{:?}", out.diagnostics);
    }
    assert_eq!(build(&y_terrain, &fit(None)), build(&y_terrain, &fit(Some(UpAxis::Y))));
    assert_eq!(mesh::chosen_up([1.0, 1.0, 1.0]), UpAxis::Y);
    assert_eq!(mesh::chosen_up([1.0, 1.0, 0.3]), UpAxis::Y, "not far smaller than both");
    assert_eq!(mesh::chosen_up([1.0, 1.0, 0.2]), UpAxis::Z);
    // Asked to read the Z-flat terrain with +Y up, the build says which axis reads it better.
    let out = mesh::compile_gltf(&z_terrain.to_glb(), &mut no_files, &profile, &fit(Some(UpAxis::Y)));
    assert!(out.diagnostics.iter().all(|d| d.code != "T0619"), "{:?}", out.diagnostics);
    assert!(out.diagnostics.iter().any(|d| d.code == "T0616"), "{:?}", out.diagnostics);
}

/// The top surface of `m` read with +Z up (page x = 1000 X, page y = −1000 Y,
/// height 1000 Z) at `(x, y)`: the highest triangle there, linear on it.
fn z_up_reference(m: &HeightMesh, x: f64, y: f64) -> Option<f64> {
    let p: Vec<[f64; 3]> =
        m.positions.iter().map(|v| [v[0] as f64 * 1000.0, -(v[1] as f64) * 1000.0, v[2] as f64 * 1000.0]).collect();
    let mut best: Option<f64> = None;
    for t in m.indices.chunks(3) {
        let [a, b, c] = [p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]];
        let d = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        if d.abs() < 1e-9 * ((b[0] - a[0]).abs() + (c[1] - a[1]).abs()).powi(2) {
            continue;
        }
        let l1 = ((b[0] - x) * (c[1] - y) - (c[0] - x) * (b[1] - y)) / d;
        let l2 = ((c[0] - x) * (a[1] - y) - (a[0] - x) * (c[1] - y)) / d;
        let l3 = 1.0 - l1 - l2;
        if l1 >= -1e-9 && l2 >= -1e-9 && l3 >= -1e-9 {
            let z = l1 * a[2] + l2 * b[2] + l3 * c[2];
            best = Some(best.map_or(z, |w: f64| w.max(z)));
        }
    }
    best
}

#[test]
fn a_terrain_seen_edge_on_builds_to_the_exact_top_surface() {
    // A terrain with +Y up read with +Z up: seen from the side, every column
    // of quads projects onto one thin strip, and the triangles overlap many
    // deep. The field must still hold the top surface at every node.
    let m = HeightMesh::grid(12, 12, |u, v| {
        let h = 0.02 + 0.008 * (7.0 * u).sin() * (5.0 * v).cos() + 0.003 * (11.0 * v + 1.0).sin();
        [0.06 * u, h, 0.06 * v]
    });
    let f = build(&m, &MeshOptions { up: Some(UpAxis::Z), nodes_per_mm: Some(2.0), ..MeshOptions::default() });
    let eps = f.cell.0 as f64 * 2e-3;
    let (mut checked, mut touching) = (0, 0);
    for j in 0..f.rows {
        for i in 0..f.cols {
            let k = (j * f.cols + i) as usize;
            let (x, y) =
                (f.origin_x.0 as f64 + i as f64 * f.cell.0 as f64, f.origin_y.0 as f64 + j as f64 * f.cell.0 as f64);
            // Nodes within the field's outline slack of a face's edge may take
            // the neighbouring face's height: compare where the reference is
            // the same a little way round the node.
            let around: Vec<Option<f64>> = [(0.0, 0.0), (eps, 0.0), (-eps, 0.0), (0.0, eps), (0.0, -eps)]
                .iter()
                .map(|(dx, dy)| z_up_reference(&m, x + dx, y + dy))
                .collect();
            let Some(z) = around[0] else { continue };
            if around.iter().any(|a| a.is_none_or(|a| (a - z).abs() > 1e-3)) {
                continue;
            }
            checked += 1;
            touching += usize::from(f.flags[k] & FIELD_CONTACT != 0);
            assert!(f.flags[k] & FIELD_CONTACT != 0, "contact at ({x}, {y})");
            assert!((f.heights[k] as f64 - z).abs() < 1e-3, "h({x}, {y}) = {} vs {z}", f.heights[k]);
        }
    }
    assert!(checked > 100 && touching == checked, "{checked} nodes compared");
}
