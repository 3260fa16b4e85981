//! glTF height meshes to height fields: the paper's shapes against their
//! analytic surfaces, an independent reference for arbitrary meshes, walls,
//! holes, degenerate input, extreme scales, limits and malformed files;
//! real models in `models`.

mod models;

use proptest::prelude::*;
use taxel_compiler::UpAxis;
use taxel_compiler::mesh::shapes::{FOOTPRINT, STEP_X, Shape};
use taxel_compiler::mesh::write::HeightMesh;
use taxel_compiler::mesh::{self, MeshError, MeshOptions};
use taxel_format::{FIELD_CONTACT, FIELD_EDGE, HeightField, profiles};

fn no_files(_: &str) -> Result<Vec<u8>, String> {
    Err("no external files in this test".into())
}

fn field(bytes: &[u8]) -> HeightField {
    field_with(bytes, MeshOptions::default())
}

fn field_with(bytes: &[u8], opts: MeshOptions) -> HeightField {
    match mesh::height_field(bytes, &mut no_files, &opts) {
        Ok((f, _)) => f,
        Err(e) => panic!("{e}"),
    }
}

fn error(bytes: &[u8]) -> MeshError {
    mesh::height_field(bytes, &mut no_files, &MeshOptions::default()).expect_err("an error")
}

fn node_xy(f: &HeightField, i: u32, j: u32) -> (f64, f64) {
    (f.origin_x.0 as f64 + i as f64 * f.cell.0 as f64, f.origin_y.0 as f64 + j as f64 * f.cell.0 as f64)
}

/// An independent bilinear sampler over contact nodes: (h, gx, gy).
fn bilinear(f: &HeightField, x: f64, y: f64) -> Option<(f64, f64, f64)> {
    let c = f.cell.0 as f64;
    let u = (x - f.origin_x.0 as f64) / c;
    let v = (y - f.origin_y.0 as f64) / c;
    let i = (u.floor() as u32).min(f.cols - 2);
    let j = (v.floor() as u32).min(f.rows - 2);
    let (fx, fy) = (u - i as f64, v - j as f64);
    let mut acc = (0.0, 0.0, 0.0, 0.0);
    for (di, dj, w) in
        [(0, 0, (1.0 - fx) * (1.0 - fy)), (1, 0, fx * (1.0 - fy)), (0, 1, (1.0 - fx) * fy), (1, 1, fx * fy)]
    {
        let k = ((j + dj) * f.cols + i + di) as usize;
        if f.flags[k] & FIELD_CONTACT == 0 {
            return None;
        }
        acc.0 += w * f.heights[k] as f64;
        acc.1 += w * f.grad_x[k] as f64;
        acc.2 += w * f.grad_y[k] as f64;
        acc.3 += w;
    }
    Some((acc.0, acc.1, acc.2))
}

#[test]
fn the_five_shapes_match_their_analytic_surfaces_within_the_derived_bounds() {
    for shape in Shape::ALL {
        for bytes in [shape.mesh().to_glb(), shape.mesh().to_gltf_embedded().into_bytes()] {
            let f = field(&bytes);
            let h = f.cell.0 as f64;
            let m = shape.curvature_bound();
            // docs/finger.md: the mesh's 2 mm right triangles (legs e, circumradius
            // R = e/√2) and bilinear sampling at spacing h give
            //   |h − h_exact| <= M (R²/2 + h²/4),  |∇h − ∇h_exact| <= M (2 e + √2 h),
            // plus f32 rounding.
            let (nu, _) = shape.grid();
            let e = (FOOTPRINT[2] - FOOTPRINT[0]) / nu as f64;
            let tol_h = m * (e * e / 4.0 + h * h / 4.0) + 1e-4;
            let tol_g = m * (2.0 * e + 2f64.sqrt() * h) + 1e-4;
            let mut checked = 0;
            for a in 0..=200 {
                for b in 0..=40 {
                    let x = FOOTPRINT[0] + 1.0 + (FOOTPRINT[2] - FOOTPRINT[0] - 2.0) * a as f64 / 200.0;
                    let y = FOOTPRINT[1] + 1.0 + (FOOTPRINT[3] - FOOTPRINT[1] - 2.0) * b as f64 / 40.0;
                    if shape == Shape::Edge && (x - STEP_X).abs() < 2.0 * h {
                        continue;
                    }
                    let (zh, gx, gy) =
                        bilinear(&f, x, y).unwrap_or_else(|| panic!("{shape:?}: no contact at {x}, {y}"));
                    let z = shape.height(x, y).unwrap();
                    let (ex, ey) = shape.gradient(x, y).unwrap();
                    assert!((zh - z).abs() <= tol_h, "{shape:?} h({x}, {y}) = {zh}, exact {z}, tolerance {tol_h}");
                    let ge = ((gx - ex).powi(2) + (gy - ey).powi(2)).sqrt();
                    assert!(
                        ge <= tol_g,
                        "{shape:?} ∇h({x}, {y}) = ({gx}, {gy}), exact ({ex}, {ey}), tolerance {tol_g}"
                    );
                    checked += 1;
                }
            }
            assert!(checked > 7000);
        }
    }
}

#[test]
fn outside_the_footprint_has_no_contact_and_the_field_is_cropped_to_it() {
    let f = field(&Shape::Flat.mesh().to_glb());
    assert_eq!((f.origin_x.0, f.origin_y.0), (20.0, 20.0));
    let (x1, y1) = node_xy(&f, f.cols - 1, f.rows - 1);
    assert!(x1 >= 140.0 && x1 < 140.0 + f.cell.0 as f64);
    assert!(y1 >= 80.0 && y1 < 80.0 + f.cell.0 as f64);
    assert!(f.flags.iter().all(|&fl| fl & FIELD_CONTACT != 0) || x1 > 140.0 || y1 > 80.0);
}

#[test]
fn a_vertical_wall_is_a_flagged_step_with_a_capped_gradient_and_the_top_wins() {
    let f = field(&Shape::Edge.mesh().to_glb());
    let c = f.cell.0 as f64;
    let mut edge_nodes = 0;
    for j in 0..f.rows {
        for i in 0..f.cols {
            let k = (j * f.cols + i) as usize;
            let (x, _) = node_xy(&f, i, j);
            let (gx, gy) = (f.grad_x[k], f.grad_y[k]);
            assert!(gx.is_finite() && gy.is_finite());
            assert!(gx.hypot(gy) <= f.gradient_cap * 1.000_001);
            if f.flags[k] & FIELD_EDGE != 0 {
                edge_nodes += 1;
                assert!((x - STEP_X).abs() <= c + 1e-6, "edge flag at x = {x}, away from the step");
                assert!(gx > 0.0, "the step rises to the right");
            }
            if x == STEP_X && f.flags[k] & FIELD_CONTACT != 0 {
                assert_eq!(f.heights[k], 15.0, "a node on the wall touches its top");
            }
            if (x - STEP_X).abs() > 1.5 * c && f.flags[k] & FIELD_CONTACT != 0 {
                assert_eq!(f.flags[k] & FIELD_EDGE, 0);
            }
        }
    }
    assert!(edge_nodes >= 2 * (f.rows as usize - 2), "every row crosses the step: {edge_nodes}");
    // The cap is at least a 45° slope (the terraces themselves are flat).
    assert_eq!(f.gradient_cap, 1.0);
}

/// A square terrain of `n` x `n` quads over 0..10 mm with heights `h[j][i]` (mm),
/// optionally without some quads.
fn terrain(n: usize, h: &[f64], skip: impl Fn(usize, usize) -> bool) -> HeightMesh {
    let mut m = HeightMesh::default();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (10.0 * i as f64 / n as f64, 10.0 * j as f64 / n as f64);
            m.positions.push([(x / 1000.0) as f32, (h[j * (n + 1) + i] / 1000.0) as f32, (y / 1000.0) as f32]);
        }
    }
    let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..n {
        for i in 0..n {
            if !skip(i, j) {
                m.indices.extend([at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
    }
    m
}

/// The exact reference: the highest original triangle over (x, y), linear on it.
fn reference(m: &HeightMesh, x: f64, y: f64) -> Option<f64> {
    let p: Vec<[f64; 3]> =
        m.positions.iter().map(|v| [v[0] as f64 * 1000.0, v[2] as f64 * 1000.0, v[1] as f64 * 1000.0]).collect();
    let mut best: Option<f64> = None;
    for t in m.indices.chunks(3) {
        let [a, b, c] = [p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]];
        let d = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        if d.abs() < 1e-12 {
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

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// At every node the field holds the exact top-surface height of the
    /// original triangles (and contact exactly where a triangle is).
    #[test]
    fn node_heights_are_the_exact_top_surface(
        heights in proptest::collection::vec(0.0f64..8.0, 36),
        holes in proptest::collection::vec(any::<bool>(), 25),
        per_mm in 1.0f64..4.0,
    ) {
        let n = 5;
        let m = terrain(n, &heights, |i, j| holes[j * n + i] && (i + j) % 3 == 0);
        prop_assume!(!m.indices.is_empty());
        let f = match mesh::height_field(&m.to_glb(), &mut no_files, &MeshOptions { nodes_per_mm: Some(per_mm), ..MeshOptions::default() }) {
            Ok((f, _)) => f,
            Err(e) => return Err(TestCaseError::fail(e.to_string())),
        };
        for j in 0..f.rows {
            for i in 0..f.cols {
                let k = (j * f.cols + i) as usize;
                let (x, y) = node_xy(&f, i, j);
                match reference(&m, x, y) {
                    Some(z) => {
                        prop_assert!(f.flags[k] & FIELD_CONTACT != 0, "contact at ({x}, {y})");
                        // A node within the field's outline slack (a thousandth of a
                        // cell) of a neighbouring face may take that face's height:
                        // allow the slope difference (at most 2 * 4 * sqrt 2 here) times the slack.
                        let tol = 1e-3 + 12.0 * 1e-3 * f.cell.0 as f64;
                        prop_assert!((f.heights[k] as f64 - z).abs() < tol, "h({x}, {y}) = {} vs {z}", f.heights[k]);
                    }
                    // The field counts nodes within a thousandth of a cell of the
                    // outline as touching (its vertices are f32), so a node that
                    // the f64 reference puts just outside may touch only if a
                    // triangle lies within that slack.
                    None if f.flags[k] != 0 => {
                        let eps = f.cell.0 as f64 * 2e-3;
                        let near = [(eps, 0.0), (-eps, 0.0), (0.0, eps), (0.0, -eps), (eps, eps), (-eps, -eps), (eps, -eps), (-eps, eps)]
                            .iter()
                            .any(|(dx, dy)| reference(&m, x + dx, y + dy).is_some());
                        prop_assert!(near, "contact at ({}, {}) away from every triangle", x, y);
                    }
                    None => {}
                }
            }
        }
    }
}

#[test]
fn holes_in_the_mesh_have_no_contact() {
    let flat = vec![3.0; 36];
    let m = terrain(5, &flat, |i, j| (i, j) == (2, 2));
    let f = field_with(&m.to_glb(), MeshOptions { nodes_per_mm: Some(2.0), ..MeshOptions::default() });
    for j in 0..f.rows {
        for i in 0..f.cols {
            let (x, y) = node_xy(&f, i, j);
            let inside_hole = x > 4.0 && x < 6.0 && y > 4.0 && y < 6.0;
            let k = (j * f.cols + i) as usize;
            assert_eq!(f.flags[k] & FIELD_CONTACT == 0, inside_hole, "({x}, {y})");
        }
    }
}

#[test]
fn degenerate_and_sliver_triangles_and_duplicate_vertices_change_nothing_they_should_not() {
    let hs: Vec<f64> = (0..36).map(|k| (k % 7) as f64).collect();
    let clean = terrain(5, &hs, |_, _| false);
    let mut dirty = clean.clone();
    // Zero-area triangles (a repeated corner, three collinear corners), a
    // repeated triangle, and a duplicate of every vertex referenced by a copy of the mesh.
    dirty.indices.extend([0, 0, 1, 0, 1, 2, 3, 4, 5]);
    dirty.positions.push([0.0, 0.0, 0.0]);
    dirty.positions.push([0.002, 0.0, 0.0]);
    dirty.positions.push([0.004, 0.0, 0.0]);
    let base = dirty.positions.len() as u32;
    dirty.positions.push([0.001, 0.0, 0.0]);
    dirty.positions.push([0.001, 0.0, 0.0]);
    dirty.positions.push([0.003, 0.0, 0.0]);
    dirty.indices.extend([base, base + 1, base + 2]);
    let mut copy = clean.clone();
    copy.indices.truncate(6);
    dirty.append(&copy);
    let opts = MeshOptions { nodes_per_mm: Some(2.0), ..MeshOptions::default() };
    let a = field_with(&clean.to_glb(), opts.clone());
    let b = field_with(&dirty.to_glb(), opts.clone());
    assert_eq!(a.heights, b.heights);
    assert_eq!(a.flags, b.flags);

    // A sliver: 10 mm long, 1e-6 mm wide, rising 5 mm, inside a flat square.
    let mut s = terrain(1, &[1.0; 4], |_, _| false);
    s.positions.extend([[0.0, 0.006, 0.005], [0.01, 0.006, 0.005], [0.005, 0.006, 0.005 + 1e-9]]);
    s.indices.extend([4, 5, 6]);
    let f = field_with(&s.to_glb(), opts);
    assert!(f.grad_x.iter().chain(&f.grad_y).all(|g| g.is_finite() && g.abs() <= f.gradient_cap * 1.000_001));
    assert!(f.flags.iter().all(|fl| fl & FIELD_CONTACT != 0));
}

#[test]
fn tiny_and_huge_meshes_get_a_bounded_field() {
    for scale in [1e-6, 1e-3, 1.0, 10.0] {
        // A convex cap `scale` metres across and a tenth of that high.
        let m = HeightMesh::grid(40, 40, |u, v| {
            let (x, z) = (scale * u, scale * v);
            let h = 0.1 * scale * (1.0 - (2.0 * u - 1.0).powi(2)) * (1.0 - (2.0 * v - 1.0).powi(2));
            [x, h, z]
        });
        let f = field(&m.to_glb());
        assert!(f.cols <= 1024 && f.rows <= 1024, "{scale} m: {} x {}", f.cols, f.rows);
        assert!(f.cols >= 17 && f.rows >= 17, "{scale} m: {} x {}", f.cols, f.rows);
        // The top of the cap (0.1 scale m = 100 scale mm), at the centre node.
        let top = f.heights.iter().cloned().fold(f32::MIN, f32::max) as f64;
        let want = 100.0 * scale;
        assert!((top - want).abs() <= 0.02 * want, "{scale} m: top {top} mm, expected {want}");
    }
}

#[test]
fn an_absurd_resolution_is_refused_with_the_limit() {
    let m = HeightMesh::grid(2, 2, |u, v| [10.0 * u, 0.0, 10.0 * v]);
    let e = mesh::height_field(
        &m.to_glb(),
        &mut no_files,
        &MeshOptions { nodes_per_mm: Some(100.0), ..MeshOptions::default() },
    )
    .unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, MeshError::FieldTooLarge { .. }), "{msg}");
    assert!(msg.contains("16384") && msg.contains("at most"), "{msg}");
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let r = mesh::height_field(
            &m.to_glb(),
            &mut no_files,
            &MeshOptions { nodes_per_mm: Some(bad), ..MeshOptions::default() },
        );
        assert!(r.is_err(), "resolution {bad}");
    }
}

#[test]
fn node_transforms_are_applied() {
    // One 10 mm square at height 2 mm, moved by its node 30 mm right, 4 mm up and 5 mm down the page.
    let mut m = HeightMesh::grid(1, 1, |u, v| [0.01 * u, 0.002, 0.01 * v]);
    m.translation = Some([0.03, 0.004, 0.005]);
    let f = field(&m.to_glb());
    assert_eq!((f.origin_x.0, f.origin_y.0), (30.0, 5.0));
    assert!(f.heights.iter().all(|&h| (h - 6.0).abs() < 1e-5));
    // Nested: a parent that scales by 2 around a child that translates.
    let json = m.to_gltf_embedded().replace(
        "\"nodes\":[{\"name\":\"grid\",\"mesh\":0,\"translation\":[0.03,0.004,0.005]}]",
        "\"nodes\":[{\"children\":[1],\"scale\":[2,2,2]},{\"mesh\":0,\"translation\":[0.03,0.004,0.005]}]",
    );
    assert!(json.contains("children"), "the test's replacement applies");
    let f = field(json.as_bytes());
    assert_eq!((f.origin_x.0, f.origin_y.0), (60.0, 10.0));
    assert!(f.heights.iter().all(|&h| (h - 12.0).abs() < 1e-4));
}

#[test]
fn strips_and_fans_give_the_same_surface_as_triangles() {
    let m = HeightMesh::grid(1, 1, |u, v| [0.01 * u, 0.001 + 0.002 * u * v, 0.01 * v]);
    let tri = field(&m.to_glb());
    // Grid corners: 0 (0,0), 1 (1,0), 2 (0,1), 3 (1,1). Triangles (0,2,3) and (0,3,1).
    for (mode, idx) in [(5, [2u32, 0, 3, 1]), (6, [0, 2, 3, 1])] {
        let mut s = m.clone();
        s.indices = idx.to_vec();
        let json = s.to_gltf_embedded().replace("\"mode\":4", &format!("\"mode\":{mode}"));
        let f = field(json.as_bytes());
        assert_eq!(f.heights, tri.heights, "mode {mode}");
    }
}

#[test]
fn malformed_files_are_errors_that_name_the_mesh_and_primitive() {
    let m = HeightMesh { name: "Terrain".into(), ..HeightMesh::grid(2, 2, |u, v| [0.01 * u, 0.0, 0.01 * v]) };
    let json = m.to_gltf_embedded();
    let cases: Vec<(String, &str)> = vec![
        (json.replace("\"mode\":4", "\"mode\":0"), "mesh 'Terrain' (#0), primitive 0: mode Points"),
        (json.replace("\"mode\":4", "\"mode\":1"), "mode Lines is not supported"),
        (json.replace("\"POSITION\":0", "\"NORMAL\":0"), "meshes[0].primitives[0].attributes[\"POSITION\"]"),
        (json.replace("\"count\":24", "\"count\":25"), "indices accessor"),
        (json.replace("\"POSITION\":0", "\"POSITION\":9"), "not a valid glTF"),
        (json.replace("\"indices\":1", "\"indices\":9"), "not a valid glTF"),
        (json.replace("\"mesh\":0", "\"mesh\":3"), "not a valid glTF"),
        (json.replace("\"nodes\":[0]", "\"nodes\":[]"), "the scene has no triangles"),
        (json.replace("\"mesh\":0", "\"mesh\":0,\"scale\":[1e30,1e30,1e30]"), "more than 10 million km"),
        (json.replace("\"mesh\":0", "\"mesh\":0,\"scale\":[1e39,1,1]"), "node 'Terrain' (#0)"),
        (json.replace("base64,", "base64,@@"), "buffer 0: has a data: URI that is not valid base64"),
        (json.replace(";base64,", ","), "buffer 0: is a data: URI that is not base64"),
        // A buffer without a URI is the GLB's binary chunk, which a .gltf has not.
        (json.replace("\"uri\":", "\"extras\":"), "buffer 0: refers to the binary chunk of a GLB file"),
        ("{\"asset\":{\"version\":\"2.0\"}".to_string(), "not a valid glTF"),
        ("not json at all".to_string(), "not a valid glTF"),
    ];
    for (text, want) in cases {
        let e = error(text.as_bytes());
        assert!(e.to_string().contains(want), "expected '{want}' in '{e}'");
    }
    // An index past the end of the vertices.
    let mut bad = m.clone();
    bad.indices[4] = 99;
    let e = error(&bad.to_glb()).to_string();
    assert!(e.contains("index 99 is out of range") && e.contains("'Terrain'"), "{e}");
    // A NaN vertex.
    let mut nan = m.clone();
    nan.positions[3][1] = f32::NAN;
    let e = error(&nan.to_glb()).to_string();
    assert!(e.contains("POSITION") && e.contains("finite"), "{e}");
    // A truncated GLB at many lengths: always an error, never a panic.
    let glb = m.to_glb();
    for len in (0..glb.len()).step_by(7) {
        assert!(mesh::height_field(&glb[..len], &mut no_files, &MeshOptions::default()).is_err(), "length {len}");
    }
    // All walls: nothing covers the page.
    // (Read +Y up: without `--up` this plate, flat across Z, is read +Z up.)
    let wall = HeightMesh::grid(2, 2, |u, v| [0.01 * u, 0.01 * v, 0.0]);
    let y_up = MeshOptions { up: Some(UpAxis::Y), ..MeshOptions::default() };
    assert!(matches!(mesh::height_field(&wall.to_glb(), &mut no_files, &y_up), Err(MeshError::NoArea)));
}

#[test]
fn external_buffers_come_through_the_resolver() {
    let m = Shape::Flat.mesh();
    let (json, bin) = m.to_gltf_external("flat.bin");
    let mut asked = Vec::new();
    let mut resolve = |uri: &str| {
        asked.push(uri.to_string());
        Ok(bin.clone())
    };
    let (f, _) = mesh::height_field(json.as_bytes(), &mut resolve, &MeshOptions::default()).unwrap();
    assert_eq!(asked, ["flat.bin"]);
    assert_eq!(f, field(&m.to_glb()));
    let e = mesh::height_field(json.as_bytes(), &mut |_| Err("no such file".into()), &MeshOptions::default());
    assert!(e.unwrap_err().to_string().contains("buffer 0: no such file"));
    // A buffer shorter than it declares.
    let e = mesh::height_field(json.as_bytes(), &mut |_| Ok(vec![0; 10]), &MeshOptions::default());
    assert!(e.unwrap_err().to_string().contains("holds 10 bytes"));
}

#[test]
fn a_mesh_needs_a_finger_profile() {
    let glb = Shape::Flat.mesh().to_glb();
    let out = mesh::compile_gltf(&glb, &mut no_files, &profiles::builtin("stress2").unwrap(), &MeshOptions::default());
    assert!(out.bundle.is_none());
    assert_eq!(out.diagnostics[0].code, "T0609");
    let out = mesh::compile_gltf(&glb, &mut no_files, &profiles::builtin("finger3").unwrap(), &MeshOptions::default());
    assert!(out.bundle.is_some());
    assert!(out.diagnostics.iter().all(|d| d.severity != taxel_compiler::Severity::Error));
}
