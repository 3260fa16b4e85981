//! Real models: quantised, sparse and stripped accessors, many touching and
//! overlapping meshes, compressed files, fitting, regions and the up axis.

use super::*;
use taxel_compiler::Region;
use taxel_compiler::mesh::write::Builder;

fn opts() -> MeshOptions {
    MeshOptions { nodes_per_mm: Some(2.0), ..MeshOptions::default() }
}

/// A ramp over the unit square, in glTF order [X, Y (height), Z].
fn unit_ramp(n: u32) -> HeightMesh {
    HeightMesh::grid(n, n, |u, v| [u, 0.25 * u + 0.5 * u * v, v])
}

#[test]
fn quantised_positions_are_read_as_their_normalised_or_integer_values() {
    let m = unit_ramp(8);
    // u16 normalised: value q / 65535; i8 plain: integers 0..=16 scaled by the node.
    for (ctype, normalized, levels, stride, size) in
        [(5123u32, true, 65535.0f64, 8usize, 2usize), (5120, false, 16.0, 4, 1)]
    {
        let q: Vec<[i64; 3]> = m.positions.iter().map(|p| p.map(|c| (c as f64 * levels).round() as i64)).collect();
        let mut bytes = Vec::new();
        for p in &q {
            for &c in p {
                if size == 2 {
                    bytes.extend_from_slice(&(c as u16).to_le_bytes());
                } else {
                    bytes.push(c as i8 as u8);
                }
            }
            bytes.resize(bytes.len() + stride - 3 * size, 0);
        }
        let mut b = Builder::default();
        let v = b.view(&bytes, Some(stride));
        let lo = |k: usize| q.iter().map(|p| p[k]).min().unwrap();
        let hi = |k: usize| q.iter().map(|p| p[k]).max().unwrap();
        let pos = b.accessor(format!(
            "{{\"bufferView\":{v},\"componentType\":{ctype},\"normalized\":{normalized},\"count\":{},\"type\":\"VEC3\",\
             \"min\":[{},{},{}],\"max\":[{},{},{}]}}",
            q.len(),
            lo(0),
            lo(1),
            lo(2),
            hi(0),
            hi(1),
            hi(2)
        ));
        let idx = b.indices(&m.indices);
        let mesh = b.mesh("quantised", &[format!("{{\"attributes\":{{\"POSITION\":{pos}}},\"indices\":{idx}}}")]);
        // The node scales the unit cube (or the integer grid) to 20 x 8 x 10 mm.
        let k = if normalized { 1.0 } else { 1.0 / levels };
        let scale = format!("[{},{},{}]", 0.02 * k, 0.008 * k, 0.01 * k);
        let node = b.node(format!("{{\"mesh\":{mesh},\"scale\":{scale}}}"));
        b.extensions_used.push("KHR_mesh_quantization".into());
        b.extensions_required.push("KHR_mesh_quantization".into());
        let f = field_with(&b.to_glb(&[node]), opts());
        // The same positions as floats, dequantised independently.
        let mut float = m.clone();
        float.positions = q.iter().map(|p| p.map(|c| (c as f64 / levels) as f32)).collect();
        float.translation = None;
        let mut fb = Builder::default();
        let n2 = fb.height_mesh(&float, ",\"scale\":[0.02,0.008,0.01]");
        let g = field_with(&fb.to_glb(&[n2]), opts());
        assert_eq!((f.cols, f.rows, f.flags.clone()), (g.cols, g.rows, g.flags.clone()), "type {ctype}");
        for (a, b) in f.heights.iter().zip(&g.heights) {
            assert!((a - b).abs() < 1e-4, "type {ctype}: {a} vs {b}");
        }
        // The far corner (u = v = 1) is 0.75 of 8 mm high.
        let last = *f.heights.last().unwrap();
        assert!((last - 6.0).abs() < 1e-3, "type {ctype}: corner height {last}");
    }
}

#[test]
fn sparse_positions_replace_their_base_values() {
    // A flat 4 x 4 grid at 1 mm; the sparse part lifts three inner vertices.
    let base = HeightMesh::grid(4, 4, |u, v| [0.02 * u, 0.001, 0.02 * v]);
    let lifted: [(u32, f32); 3] = [(6, 0.004), (12, 0.006), (18, 0.003)];
    let mut want = base.clone();
    for &(i, h) in &lifted {
        want.positions[i as usize][1] = h;
    }
    let mut b = Builder::default();
    let pbytes: Vec<u8> = base.positions.iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
    let pv = b.view(&pbytes, None);
    let iv = b.view(&lifted.iter().flat_map(|(i, _)| (*i as u16).to_le_bytes()).collect::<Vec<u8>>(), None);
    let vv = b.view(
        &lifted
            .iter()
            .flat_map(|&(i, h)| {
                let p = base.positions[i as usize];
                [p[0], h, p[2]].into_iter().flat_map(f32::to_le_bytes)
            })
            .collect::<Vec<u8>>(),
        None,
    );
    let pos = b.accessor(format!(
        "{{\"bufferView\":{pv},\"componentType\":5126,\"count\":25,\"type\":\"VEC3\",\"min\":[0,0.001,0],\"max\":[0.02,0.006,0.02],\
         \"sparse\":{{\"count\":3,\"indices\":{{\"bufferView\":{iv},\"componentType\":5123}},\"values\":{{\"bufferView\":{vv}}}}}}}"
    ));
    let idx = b.indices(&base.indices);
    let mesh = b.mesh("sparse", &[format!("{{\"attributes\":{{\"POSITION\":{pos}}},\"indices\":{idx}}}")]);
    let node = b.node(format!("{{\"mesh\":{mesh}}}"));
    let f = field_with(&b.to_glb(&[node]), opts());
    assert_eq!(f, field_with(&want.to_glb(), opts()));
    let top = f.heights.iter().cloned().fold(f32::MIN, f32::max);
    assert_eq!(top, 6.0, "the lifted vertex 12 is the top");

    // Sparse indices out of order are an error that says so.
    let mut b2 = b.clone();
    let iv2 = b2.view(&[6u8, 0, 4, 0, 18, 0], None);
    let pos2 = b2.accessor(format!(
        "{{\"bufferView\":{pv},\"componentType\":5126,\"count\":25,\"type\":\"VEC3\",\"min\":[0,0.001,0],\"max\":[0.02,0.006,0.02],\
         \"sparse\":{{\"count\":3,\"indices\":{{\"bufferView\":{iv2},\"componentType\":5123}},\"values\":{{\"bufferView\":{vv}}}}}}}"
    ));
    let mesh2 = b2.mesh("bad", &[format!("{{\"attributes\":{{\"POSITION\":{pos2}}},\"indices\":{idx}}}")]);
    let node2 = b2.node(format!("{{\"mesh\":{mesh2}}}"));
    let e = error(&b2.to_glb(&[node2])).to_string();
    assert!(e.contains("sparse index 4") && e.contains("not increasing") && e.contains("POSITION"), "{e}");
}

#[test]
fn a_grid_as_one_stitched_strip_gives_the_triangle_lists_surface() {
    let (nu, nv) = (10u32, 6u32);
    let m = HeightMesh::grid(nu, nv, |u, v| [0.03 * u, 0.002 + 0.004 * u * (1.0 - v), 0.02 * v]);
    // Row j of quads as a strip down (j, j+1) columns; rows joined by two
    // repeated indices (degenerate triangles), as exporters stitch strips.
    let at = |i: u32, j: u32| j * (nu + 1) + i;
    let mut strip = Vec::new();
    for j in 0..nv {
        if j > 0 {
            strip.push(*strip.last().unwrap());
            strip.push(at(0, j + 1));
        }
        // Lower row first: the quads split along the grid's own diagonal (i, j)-(i+1, j+1).
        for i in 0..=nu {
            strip.push(at(i, j + 1));
            strip.push(at(i, j));
        }
    }
    let mut b = Builder::default();
    let pos = b.positions(&m.positions);
    let idx = b.indices(&strip);
    let mesh = b.mesh("strip", &[format!("{{\"attributes\":{{\"POSITION\":{pos}}},\"indices\":{idx},\"mode\":5}}")]);
    let node = b.node(format!("{{\"mesh\":{mesh}}}"));
    let (f, report) = mesh::height_field(&b.to_glb(&[node]), &mut no_files, &opts()).unwrap();
    let g = field_with(&m.to_glb(), opts());
    assert_eq!(f.flags, g.flags);
    for (a, b) in f.heights.iter().zip(&g.heights) {
        assert!((a - b).abs() < 1e-5, "{a} vs {b}");
    }
    // 2 (nu + 1) - 2 triangles per row and 4 degenerate joins between rows.
    assert_eq!(report.triangles, (nv * (2 * (nu + 1) - 2) + 4 * (nv - 1)) as usize);
}

/// A closed box (top, four walls, bottom), `w` x `d` m, `h` m high, in its own frame.
fn cuboid(w: f64, d: f64, h: f64) -> HeightMesh {
    let mut m = HeightMesh { name: "block".into(), ..HeightMesh::default() };
    for y in [0.0, h] {
        for (u, v) in [(0.0, 0.0), (w, 0.0), (w, d), (0.0, d)] {
            m.positions.push([u as f32, y as f32, v as f32]);
        }
    }
    m.indices.extend([0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7]);
    for k in 0..4u32 {
        let n = (k + 1) % 4;
        m.indices.extend([k, n, 4 + n, k, 4 + n, 4 + k]);
    }
    m
}

#[test]
fn fifty_touching_and_overlapping_meshes_build_to_their_highest_tops() {
    // A city: 40 blocks of 10 x 10 m on a grid turned by 0.3 rad, neighbours
    // sharing walls exactly (in the same frame) and every other row shifted by
    // 3.7 m, so walls overlap in part and meet in T-junctions; plus 10 taller
    // blocks across them at other angles. Each block is its own mesh and node.
    let mut b = Builder::default();
    let mut roots = Vec::new();
    // (centre-free description) origin x, z (m), size w, d, height, angle.
    let mut blocks: Vec<(f64, f64, f64, f64, f64, f64)> = Vec::new();
    let turn = 0.3f64;
    for k in 0..40 {
        let (gx, gz) = ((k % 8) as f64, (k / 8) as f64);
        let (u, v) = (gx * 10.0 + if k / 8 % 2 == 1 { 3.7 } else { 0.0 }, gz * 10.0);
        let (x, z) = (200.0 + u * turn.cos() - v * turn.sin(), 100.0 + u * turn.sin() + v * turn.cos());
        blocks.push((x, z, 10.0, 10.0, 5.0 + ((k * 7) % 11) as f64, turn));
    }
    for k in 0..10 {
        let a = 0.05 + 0.31 * k as f64;
        blocks.push((215.0 + 6.0 * k as f64, 120.0 + 3.0 * (k % 4) as f64, 14.0, 6.0, 8.0 + k as f64, a));
    }
    for (k, &(x, z, w, d, h, a)) in blocks.iter().enumerate() {
        let mut m = cuboid(w, d, h);
        m.name = format!("block{k}");
        // A rotation of `a` about +Y that turns +X towards +Z: q = (0, sin(-a/2), 0, cos(-a/2)).
        let extra =
            format!(",\"translation\":[{x},0,{z}],\"rotation\":[0,{},0,{}]", (-a / 2.0).sin(), (-a / 2.0).cos());
        roots.push(b.height_mesh(&m, &extra));
    }
    let glb = b.to_glb(&roots);
    let profile = profiles::builtin("finger3").unwrap();
    let out = mesh::compile_gltf(&glb, &mut no_files, &profile, &MeshOptions::default());
    assert!(out.bundle.is_some(), "{:?}", out.diagnostics);
    assert!(out.diagnostics.iter().all(|d| d.code != "T0617"), "{:?}", out.diagnostics);
    // A node every 0.25 m (the default would take 1024 nodes across the 92 m).
    let coarse = MeshOptions { nodes_per_mm: Some(1.0 / 250.0), ..MeshOptions::default() };
    let (f, report) = mesh::height_field(&glb, &mut no_files, &coarse).unwrap();
    assert_eq!(report.mesh_names.len(), 50);
    // Reference: the highest block whose footprint holds the point, in mm.
    let top = |px: f64, py: f64, margin: f64| -> Option<Option<f64>> {
        let mut best = None;
        for &(x, z, w, d, h, a) in &blocks {
            let (dx, dz) = (px / 1000.0 - x, py / 1000.0 - z);
            let (u, v) = (dx * a.cos() + dz * a.sin(), -dx * a.sin() + dz * a.cos());
            let m = margin / 1000.0;
            let near = |s: f64, len: f64| (s.abs() < m) || ((s - len).abs() < m);
            if (near(u, w) && v > -m && v < d + m) || (near(v, d) && u > -m && u < w + m) {
                return None;
            }
            if u > 0.0 && u < w && v > 0.0 && v < d {
                best = Some(best.map_or(h, |b: f64| b.max(h)));
            }
        }
        Some(best.map(|b| b * 1000.0))
    };
    let mut checked = 0;
    for j in 0..f.rows {
        for i in 0..f.cols {
            let (x, y) = node_xy(&f, i, j);
            let k = (j * f.cols + i) as usize;
            // Nodes within two cells of any wall are left out (the step is there).
            let Some(want) = top(x, y, 2.0 * f.cell.0 as f64) else { continue };
            match want {
                Some(h) => assert!((f.heights[k] as f64 - h).abs() < 1e-3, "({x}, {y}): {} vs {h}", f.heights[k]),
                None => assert_eq!(f.flags[k] & FIELD_CONTACT, 0, "({x}, {y}) is between blocks"),
            }
            checked += 1;
        }
    }
    assert!(checked > f.cols as usize * f.rows as usize / 2, "{checked} nodes checked");
}

/// A point within `d` mm of an edge of a triangle of `m`.
fn near_an_edge(m: &HeightMesh, x: f64, y: f64, d: f64) -> bool {
    let p: Vec<[f64; 2]> = m.positions.iter().map(|v| [v[0] as f64 * 1000.0, v[2] as f64 * 1000.0]).collect();
    m.indices.chunks(3).any(|t| {
        (0..3).any(|k| {
            let (a, b) = (p[t[k] as usize], p[t[(k + 1) % 3] as usize]);
            let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
            let len2 = ex * ex + ey * ey;
            let s = if len2 > 0.0 { (((x - a[0]) * ex + (y - a[1]) * ey) / len2).clamp(0.0, 1.0) } else { 0.0 };
            (a[0] + s * ex - x).hypot(a[1] + s * ey - y) < d
        })
    })
}

#[test]
fn triangles_on_a_lattice_collinear_crossing_and_touching_build_to_the_exact_top_surface() {
    // The inputs that made spade's constraint splitting panic (58 in 1000
    // seeds before the arrangement was made exactly): 20 triangles with corners
    // on an 8 x 8 lattice of 10 mm, so edges overlap, cross at lattice
    // fractions and end on one another.
    for seed0 in 1..=120u64 {
        let mut seed = seed0.wrapping_mul(2654435761);
        let mut rnd = |m: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % m
        };
        let mut m = HeightMesh::default();
        for t in 0..20u32 {
            for _ in 0..3 {
                let (x, z, h) = (rnd(8), rnd(8), rnd(5));
                m.positions.push([x as f32 * 0.01, h as f32 * 0.001, z as f32 * 0.01]);
            }
            m.indices.extend([3 * t, 3 * t + 1, 3 * t + 2]);
        }
        let f = match mesh::height_field(&m.to_glb(), &mut no_files, &opts()) {
            Ok((f, _)) => f,
            Err(MeshError::NoArea) => continue,
            Err(e) => panic!("seed {seed0}: {e}"),
        };
        for j in 0..f.rows {
            for i in 0..f.cols {
                let (x, y) = node_xy(&f, i, j);
                if near_an_edge(&m, x, y, 0.01) {
                    continue;
                }
                let k = (j * f.cols + i) as usize;
                match reference(&m, x, y) {
                    Some(z) => assert!(
                        f.flags[k] & FIELD_CONTACT != 0 && (f.heights[k] as f64 - z).abs() < 1e-3,
                        "seed {seed0} ({x}, {y}): {} vs {z}",
                        f.heights[k]
                    ),
                    None => assert_eq!(f.flags[k] & FIELD_CONTACT, 0, "seed {seed0} ({x}, {y})"),
                }
            }
        }
    }
}

#[test]
fn compressed_meshes_are_refused_with_the_compression_and_the_way_out() {
    let m = unit_ramp(2);
    for (ext, want) in
        [("KHR_draco_mesh_compression", "untick \"Compression\""), ("EXT_meshopt_compression", "gltfpack")]
    {
        // As the exporters write them: the accessors have no buffer view; the
        // primitive (Draco) or the buffer view (meshopt) carries the extension.
        let mut b = Builder::default();
        let v = b.view(&[0u8; 16], None);
        let pos =
            b.accessor("{\"componentType\":5126,\"count\":9,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,1]}".into());
        let idx = b.accessor(format!("{{\"componentType\":5125,\"count\":{},\"type\":\"SCALAR\"}}", m.indices.len()));
        let mesh = b.mesh(
            "compressed",
            &[format!(
                "{{\"attributes\":{{\"POSITION\":{pos}}},\"indices\":{idx},\
                 \"extensions\":{{\"{ext}\":{{\"bufferView\":{v},\"attributes\":{{\"POSITION\":0}}}}}}}}"
            )],
        );
        let node = b.node(format!("{{\"mesh\":{mesh}}}"));
        b.extensions_used.push(ext.into());
        b.extensions_required.push(ext.into());
        let glb = b.to_glb(&[node]);
        let e = error(&glb);
        let msg = e.to_string();
        assert_eq!(e.code(), "T0614", "{msg}");
        assert!(msg.contains(ext) && msg.contains(want) && msg.contains("cannot decode"), "{msg}");
        // Listed as used only, it is refused the same way before any accessor is read.
        b.extensions_required.clear();
        assert_eq!(error(&b.to_glb(&[node])).code(), "T0614");
    }
    // Material and texture extensions do not stop a relief.
    let mut b = Builder::default();
    let node = b.height_mesh(&unit_ramp(2), "");
    b.extensions_used.push("KHR_texture_basisu".into());
    b.extensions_required.push("KHR_texture_basisu".into());
    assert!(mesh::height_field(&b.to_glb(&[node]), &mut no_files, &MeshOptions::default()).is_ok());
    // An unknown required extension may change geometry: refused by name.
    // (KHR_implicit_shapes describes shapes without triangles.)
    b.extensions_required = vec!["KHR_implicit_shapes".into()];
    let e = error(&b.to_glb(&[node])).to_string();
    assert!(e.contains("KHR_implicit_shapes") && e.contains("requires"), "{e}");
}

/// A Z-up terrain as a GIS tool exports it: X east and Y north over 9 x 11
/// km, heights Z in metres (760 to 1440 m), a ridge running north-south
/// through the middle, a gentle rise and fall along it.
fn dem(n: u32) -> HeightMesh {
    let mut m = HeightMesh::grid(n, n, |u, v| {
        let (x, y) = (9000.0 * u, 11000.0 * v);
        let across = (x - 4500.0) / 4500.0;
        let z = 1400.0 - 600.0 * across * across + 40.0 * (y / 1800.0).sin();
        [x, y, z]
    });
    m.name = "dem".into();
    m
}

#[test]
fn a_z_up_terrain_gets_the_up_note_and_fits_the_surface_with_up_z() {
    let profile = profiles::builtin("finger3").unwrap();
    let glb = dem(60).to_glb();
    let y_up = MeshOptions { up: Some(UpAxis::Y), ..MeshOptions::default() };
    let plain = mesh::compile_gltf(&glb, &mut no_files, &profile, &y_up);
    let note = plain.diagnostics.iter().find(|d| d.code == "T0616").expect("the up note");
    assert!(note.help.as_deref().unwrap_or("").contains("--up z"), "{note:?}");

    let fit = MeshOptions { up: Some(UpAxis::Z), fit: Some([160.0, 100.0]), ..MeshOptions::default() };
    let out = mesh::compile_gltf(&glb, &mut no_files, &profile, &fit);
    assert!(out.diagnostics.iter().all(|d| d.code != "T0616" && d.code != "T0612"), "{:?}", out.diagnostics);
    let (f, report) = mesh::height_field(&glb, &mut no_files, &fit).unwrap();
    // 11 km north-south onto 100 mm: 1/110 mm per metre; 9 km is 81.8 mm, centred.
    let s = 100.0 / 11000.0;
    assert!((report.mm_per_metre - s).abs() < 1e-9, "{}", report.mm_per_metre);
    let [x0, y0, x1, y1] = report.bbox;
    assert!((x0 - (80.0 - 4500.0 * s)).abs() < 1e-3 && (x1 - (80.0 + 4500.0 * s)).abs() < 1e-3, "{x0}..{x1}");
    assert!(y0.abs() < 1e-3 && (y1 - 100.0).abs() < 1e-3, "{y0}..{y1}");
    // Heights keep the slopes (scaled like the footprint) and start at 0: the
    // crest (1440 m at most) is 680 m above the lowest point (760 m, on the
    // eastern and western edges where the sine along the ridge is -1).
    let lo = f
        .heights
        .iter()
        .zip(&f.flags)
        .filter(|(_, fl)| **fl & FIELD_CONTACT != 0)
        .map(|(h, _)| *h)
        .fold(f32::MAX, f32::min);
    let hi = f.heights.iter().cloned().fold(f32::MIN, f32::max) as f64;
    assert!(lo.abs() < 1e-3, "lowest {lo}");
    assert!((hi - 680.0 * s).abs() < 0.01, "highest {hi}, expected about {}", 680.0 * s);
    // North is up the page: the northern (high Y) edge is at the top (small y).
    let exaggerated = MeshOptions { exaggerate: 3.0, ..fit.clone() };
    let (g, _) = mesh::height_field(&glb, &mut no_files, &exaggerated).unwrap();
    for (a, b) in f.heights.iter().zip(&g.heights) {
        assert!((3.0 * a - b).abs() < 1e-3, "{a} x 3 vs {b}");
    }
}

#[test]
fn a_terrain_at_utm_coordinates_builds_with_fit_and_is_refused_without_it() {
    // The DEM moved to UTM-like coordinates (500 km east, 5,000 km north) by
    // its node, as GIS exports place tiles. The translation is exact in f32,
    // so the model is the same terrain; --fit recentres it in f64 before any
    // f32, so the field equals the one of the terrain at the origin.
    let near = dem(30);
    let far = HeightMesh { translation: Some([500_000.0, 5_000_000.0, 0.0]), ..dem(30) };
    let fit = MeshOptions { up: Some(UpAxis::Z), fit: Some([160.0, 100.0]), ..MeshOptions::default() };
    let same = |a: &HeightField, b: &HeightField| {
        assert_eq!((a.cols, a.rows, a.origin_x, a.origin_y, a.cell), (b.cols, b.rows, b.origin_x, b.origin_y, b.cell));
        assert_eq!(a.flags, b.flags);
        for (x, y) in a.heights.iter().zip(&b.heights) {
            assert!((x - y).abs() < 1e-4, "{x} vs {y}");
        }
    };
    same(&field_with(&near.to_glb(), fit.clone()), &field_with(&far.to_glb(), fit.clone()));
    // A region in model units (page y is -Y with --up z): the same 4 km square of both.
    let region = |dx: f64, dy: f64| MeshOptions {
        region: Some(Region::Rect { x: 2000.0 + dx, y: -9000.0 - dy, w: 4000.0, h: 4000.0 }),
        ..fit.clone()
    };
    same(&field_with(&near.to_glb(), region(0.0, 0.0)), &field_with(&far.to_glb(), region(500_000.0, 5_000_000.0)));

    // Without --fit it cannot go on the page: a clear refusal that suggests --fit.
    let plain = MeshOptions { up: Some(UpAxis::Z), ..MeshOptions::default() };
    let e = error_with(&far.to_glb(), plain.clone());
    assert!(
        e.contains("more than 100 km") && e.contains("node 'dem'") && e.contains("x 500000.000..509000.000"),
        "{e}"
    );
    let profile = profiles::builtin("finger3").unwrap();
    let out = mesh::compile_gltf(&far.to_glb(), &mut no_files, &profile, &plain);
    let d = out.diagnostics.iter().find(|d| d.code == "T0605").expect("the refusal");
    let help = d.help.as_deref().unwrap_or("");
    assert!(out.bundle.is_none() && help.contains("--fit") && !help.contains("--up"), "{d:?}");
    // Read with +Y up (as `--up y` asks), the Z-up terrain lies flat across
    // the axis taken as up: the refusal also says which flag reads it right.
    let y_up = MeshOptions { up: Some(UpAxis::Y), ..MeshOptions::default() };
    let out = mesh::compile_gltf(&far.to_glb(), &mut no_files, &profile, &y_up);
    let d = out.diagnostics.iter().find(|d| d.code == "T0605").expect("the refusal");
    let help = d.help.as_deref().unwrap_or("");
    assert!(help.contains("--fit") && help.contains("flat across the +Y axis") && help.contains("--up z"), "{d:?}");
}

#[test]
fn a_flat_model_seen_edge_on_fails_with_the_up_axis_that_reads_it() {
    // A square in the X/Y plane (a Z-up export of a flat plate) read with +Y
    // up covers no area of the page: the error names --up z; read Z-up, the
    // same file builds.
    let plate = HeightMesh::grid(4, 4, |u, v| [10.0 * u, 10.0 * v, 0.0]);
    let glb = plate.to_glb();
    let profile = profiles::builtin("finger3").unwrap();
    let y_up = MeshOptions { up: Some(UpAxis::Y), ..MeshOptions::default() };
    let out = mesh::compile_gltf(&glb, &mut no_files, &profile, &y_up);
    let d = out.diagnostics.iter().find(|d| d.code == "T0606").expect("no area");
    assert!(out.bundle.is_none() && d.help.as_deref().unwrap_or("").contains("build with --up z"), "{d:?}");
    let z_up = MeshOptions { up: Some(UpAxis::Z), fit: Some([160.0, 100.0]), ..MeshOptions::default() };
    let out = mesh::compile_gltf(&glb, &mut no_files, &profile, &z_up);
    assert!(out.bundle.is_some(), "{:?}", out.diagnostics);
}

#[test]
fn regions_keep_part_of_the_model_and_fit_it() {
    // Two blocks side by side: "low" (0..10 m x 0..10 m, 2 m) and "tall" (10..20 m, 6 m).
    let mut b = Builder::default();
    let mut low = cuboid(10.0, 10.0, 2.0);
    low.name = "low".into();
    let mut tall = cuboid(10.0, 10.0, 6.0);
    tall.name = "tall".into();
    let roots = [b.height_mesh(&low, ""), b.height_mesh(&tall, ",\"translation\":[10,0,0]")];
    let glb = b.to_glb(&roots);
    let fit =
        |region: Region| MeshOptions { fit: Some([160.0, 100.0]), region: Some(region), ..MeshOptions::default() };
    // #tall: its 10 x 10 m footprint fills 100 x 100 mm, centred at x 30..130; heights 0..60 mm.
    let (f, r) = mesh::height_field(&glb, &mut no_files, &fit(Region::Element("tall".into()))).unwrap();
    assert!((r.bbox[0] - 30.0).abs() < 1e-6 && (r.bbox[2] - 130.0).abs() < 1e-6, "{:?}", r.bbox);
    let hi = f.heights.iter().cloned().fold(f32::MIN, f32::max);
    assert!((hi - 60.0).abs() < 1e-3, "{hi}");
    // A rectangle across both, 5..15 m x 0..10 m: half of each block, the step in the middle.
    let (f, r) =
        mesh::height_field(&glb, &mut no_files, &fit(Region::Rect { x: 5.0, y: 0.0, w: 10.0, h: 10.0 })).unwrap();
    assert!((r.bbox[0] - 30.0).abs() < 1e-6 && (r.bbox[2] - 130.0).abs() < 1e-6, "{:?}", r.bbox);
    let row = f.rows / 2;
    let at = |x: f64| {
        let i = ((x - f.origin_x.0 as f64) / f.cell.0 as f64).round() as u32;
        f.heights[(row * f.cols + i) as usize]
    };
    // Fitted: 10 m onto 100 mm; lowest point (the ground, 0 m) stays 0.
    assert!((at(50.0) - 20.0).abs() < 1e-3 && (at(110.0) - 60.0).abs() < 1e-3, "{} {}", at(50.0), at(110.0));
    // Nothing there, and a name that is not in the file.
    let e = error_with(&glb, fit(Region::Rect { x: 50.0, y: 50.0, w: 1.0, h: 1.0 }));
    assert!(e.contains("keeps nothing") && e.contains("footprint is x 0.000..20.000"), "{e}");
    let e = error_with(&glb, fit(Region::Element("church".into())));
    assert!(e.contains("'church'") && e.contains("#low") && e.contains("#tall"), "{e}");
}

fn error_with(bytes: &[u8], opts: MeshOptions) -> String {
    mesh::height_field(bytes, &mut no_files, &opts).expect_err("an error").to_string()
}

#[test]
fn fit_scales_and_centres_a_large_model_and_exaggerate_multiplies_heights() {
    // A 1.6 x 0.8 m model (a duck's size), 0.2 m high with its base at 0.05 m.
    let m = HeightMesh::grid(4, 4, |u, v| [1.6 * u, 0.05 + 0.2 * u * v, 0.8 * v]);
    let profile = profiles::builtin("finger3").unwrap();
    let plain = mesh::compile_gltf(&m.to_glb(), &mut no_files, &profile, &MeshOptions::default());
    let warn = plain.diagnostics.iter().find(|d| d.code == "T0612").expect("beyond the surface");
    assert!(warn.help.as_deref().unwrap_or("").contains("--fit"), "{warn:?}");
    let fit = MeshOptions { fit: Some([160.0, 100.0]), exaggerate: 2.0, ..MeshOptions::default() };
    let out = mesh::compile_gltf(&m.to_glb(), &mut no_files, &profile, &fit);
    assert!(out.bundle.is_some() && out.diagnostics.iter().all(|d| d.code != "T0612"), "{:?}", out.diagnostics);
    // 1.6 m onto 160 mm: 100 mm per metre; 0.8 m is 80 mm, centred at y 10..90.
    let (f, r) = mesh::height_field(&m.to_glb(), &mut no_files, &fit).unwrap();
    assert!((r.mm_per_metre - 100.0).abs() < 1e-5, "{}", r.mm_per_metre);
    assert!((r.bbox[0]).abs() < 1e-6 && (r.bbox[2] - 160.0).abs() < 1e-6);
    assert!((r.bbox[1] - 10.0).abs() < 1e-6 && (r.bbox[3] - 90.0).abs() < 1e-6);
    // Heights from 0 (the base) to 0.2 m x 100 x 2 = 40 mm.
    let hi = f.heights.iter().cloned().fold(f32::MIN, f32::max);
    assert!((hi - 40.0).abs() < 1e-3, "{hi}");
    assert!(mesh::height_field(&m.to_glb(), &mut no_files, &MeshOptions { exaggerate: 0.0, ..fit }).is_err());
}

#[test]
fn skinned_and_morphed_meshes_are_read_in_their_rest_pose_from_the_default_or_first_scene() {
    let ramp = unit_ramp(4);
    let rest = {
        let mut b = Builder::default();
        let n = b.height_mesh(&ramp, ",\"scale\":[0.02,0.01,0.01]");
        field_with(&b.to_glb(&[n]), opts())
    };
    // The same mesh with a morph target that would lift it 5 mm at weight 1
    // and a skin whose joint is a node moved 1 m away: neither is applied.
    let mut b = Builder::default();
    let pos = b.positions(&ramp.positions);
    let lift: Vec<[f32; 3]> = ramp.positions.iter().map(|_| [0.0, 0.5, 0.0]).collect();
    let delta = b.positions(&lift);
    let idx = b.indices(&ramp.indices);
    let mesh = b.mesh(
        "morphed",
        &[format!(
            "{{\"attributes\":{{\"POSITION\":{pos}}},\"indices\":{idx},\"targets\":[{{\"POSITION\":{delta}}}]}}"
        )],
    );
    let joint = b.node("{\"name\":\"joint\",\"translation\":[1,1,1]}".into());
    let skinned = b.node(format!("{{\"mesh\":{mesh},\"skin\":0,\"scale\":[0.02,0.01,0.01]}}"));
    let json = b.to_gltf_embedded(&[joint, skinned]).replace(
        "\"meshes\":[{\"name\":\"morphed\"",
        "\"skins\":[{\"joints\":[0]}],\"meshes\":[{\"name\":\"morphed\",\"weights\":[1]",
    );
    assert!(json.contains("\"skins\"") && json.contains("\"weights\":[1]"), "the test's replacements apply");
    assert_eq!(field_with(json.as_bytes(), opts()), rest);

    // Two scenes: the default one (1) is read; without "scene", the first (0).
    let mut b = Builder::default();
    let far = b.height_mesh(&ramp, ",\"scale\":[0.02,0.01,0.01],\"translation\":[0.5,0,0]");
    let near = b.height_mesh(&ramp, ",\"scale\":[0.02,0.01,0.01]");
    let two = |default: &str| {
        b.to_gltf_embedded(&[far]).replace(
            "\"scene\":0,\"scenes\":[{\"nodes\":[0]}]",
            &format!("{default}\"scenes\":[{{\"nodes\":[{far}]}},{{\"nodes\":[{near}]}}]"),
        )
    };
    let (f, _) = mesh::height_field(two("\"scene\":1,").as_bytes(), &mut no_files, &opts()).unwrap();
    assert_eq!(f, rest, "the default scene, 1");
    let (f, _) = mesh::height_field(two("").as_bytes(), &mut no_files, &opts()).unwrap();
    assert_eq!(f.origin_x.0, 500.0, "the first scene, 0, holds the far copy");
}

#[test]
fn instanced_meshes_are_placed_as_nodes_with_the_same_transforms_are() {
    // Three instances of one block (EXT_mesh_gpu_instancing): moved, moved
    // and stretched up, moved and turned 30 degrees about +Y. The reference
    // is the same block placed by three plain nodes with those transforms
    // (the gltf crate's own matrices): the two fields must agree.
    let block = HeightMesh { name: "block".into(), ..cuboid(2.0, 1.0, 1.0) };
    let (s, c) = (15f32.to_radians().sin(), 15f32.to_radians().cos());
    let t = [[0.0f32, 0.0, 0.0], [4.0, 0.0, 0.0], [1.0, 0.0, 4.0]];
    let r = [[0.0f32, 0.0, 0.0, 1.0], [0.0, 0.0, 0.0, 1.0], [0.0, s, 0.0, c]];
    let sc = [[1.0f32, 1.0, 1.0], [1.0, 2.5, 1.0], [1.0, 1.0, 1.0]];
    let floats = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();

    let mut b = Builder::default();
    // The block's mesh (0) and a node of it left out of the scene.
    let _ = b.height_mesh(&block, "");
    let mut attrs = Vec::new();
    for (name, data, kind) in
        [("TRANSLATION", t.concat(), "VEC3"), ("ROTATION", r.concat(), "VEC4"), ("SCALE", sc.concat(), "VEC3")]
    {
        let v = b.view(&floats(&data), None);
        let a = b.accessor(format!("{{\"bufferView\":{v},\"componentType\":5126,\"count\":3,\"type\":\"{kind}\"}}"));
        attrs.push(format!("\"{name}\":{a}"));
    }
    let mut inst = b.clone();
    inst.extensions_used = vec!["EXT_mesh_gpu_instancing".into()];
    inst.extensions_required = inst.extensions_used.clone();
    // The instanced node: the block's mesh (0) with the extension.
    let root = inst.node(format!(
        "{{\"name\":\"forest\",\"mesh\":0,\"extensions\":{{\"EXT_mesh_gpu_instancing\":{{\"attributes\":{{{}}}}}}}}}",
        attrs.join(",")
    ));
    let instanced = inst.to_glb(&[root]);

    let mut plain = Builder::default();
    let _ = plain.height_mesh(&block, "");
    let nodes: Vec<usize> = (0..3)
        .map(|k| {
            plain.node(format!(
                "{{\"mesh\":0,\"translation\":{:?},\"rotation\":{:?},\"scale\":{:?}}}",
                t[k], r[k], sc[k]
            ))
        })
        .collect();
    let reference = plain.to_glb(&nodes);

    let coarse = MeshOptions { nodes_per_mm: Some(0.05), ..MeshOptions::default() };
    let (a, ra) = mesh::height_field(&instanced, &mut no_files, &coarse).unwrap();
    let (e, re) = mesh::height_field(&reference, &mut no_files, &coarse).unwrap();
    assert_eq!(ra.triangles, 3 * 12, "three instances of twelve triangles");
    assert_eq!((ra.triangles, ra.bbox.map(|v| (v * 1e3).round())), (re.triangles, re.bbox.map(|v| (v * 1e3).round())));
    assert_eq!((a.cols, a.rows, a.origin_x, a.origin_y, a.cell), (e.cols, e.rows, e.origin_x, e.origin_y, e.cell));
    for (k, (x, y)) in a.heights.iter().zip(&e.heights).enumerate() {
        assert!((x - y).abs() < 1e-3, "node {k}: instanced {x} vs nodes {y}");
    }
    // The stretched instance stands 2.5 m high, the others 1 m.
    let top = a.heights.iter().cloned().fold(f32::MIN, f32::max);
    assert!((top - 2500.0).abs() < 1e-2, "{top}");
    // Provenance names the mesh once, not once per node or instance.
    let profile = profiles::builtin("finger3").unwrap();
    for glb in [&instanced, &reference] {
        let out = mesh::compile_gltf(glb, &mut no_files, &profile, &coarse);
        let labels: Vec<String> = out
            .bundle
            .iter()
            .flat_map(|b| &b.chunks)
            .filter_map(|c| match c {
                taxel_format::Chunk::Provenance(p) => {
                    Some(p.entries.iter().map(|e| e.label.clone()).collect::<Vec<_>>())
                }
                _ => None,
            })
            .flatten()
            .collect();
        assert_eq!(labels, ["block"]);
    }

    // Instances whose attributes disagree on their number are refused.
    let mut bad = inst.clone();
    let v = bad.view(&floats(&[1.0, 1.0, 1.0]), None);
    let a1 = bad.accessor(format!("{{\"bufferView\":{v},\"componentType\":5126,\"count\":1,\"type\":\"VEC3\"}}"));
    let root = bad.node(format!(
        "{{\"mesh\":0,\"extensions\":{{\"EXT_mesh_gpu_instancing\":{{\"attributes\":{{{},\"SCALE\":{a1}}}}}}}}}",
        attrs[0]
    ));
    let e = error(&bad.to_glb(&[root]));
    assert!(e.to_string().contains("different numbers of instances (TRANSLATION 3, ROTATION none, SCALE 1)"), "{e}");
    // So is an extension that is not an object of attributes.
    let root = bad.node("{\"mesh\":0,\"extensions\":{\"EXT_mesh_gpu_instancing\":\"all\"}}".into());
    let e = error(&bad.to_glb(&[root]));
    assert!(e.to_string().contains("EXT_mesh_gpu_instancing: expected an object with \"attributes\""), "{e}");
}

#[test]
fn loose_edges_and_points_beside_triangles_are_left_out_with_a_note() {
    // A ramp with a second primitive of lines (Blender's loose edges) and a
    // mesh of points: the relief is the ramp's, as without them, and a note
    // names the first primitive left out. Lines alone stay an error.
    let ramp = unit_ramp(4);
    let mut b = Builder::default();
    let p = b.positions(&ramp.positions);
    let i = b.indices(&ramp.indices);
    let edges = b.indices(&[0, 1, 1, 2]);
    let tri = format!("{{\"attributes\":{{\"POSITION\":{p}}},\"indices\":{i}}}");
    let lines = format!("{{\"attributes\":{{\"POSITION\":{p}}},\"indices\":{edges},\"mode\":1}}");
    let points = format!("{{\"attributes\":{{\"POSITION\":{p}}},\"mode\":0}}");
    let both = b.mesh("ramp", &[tri.clone(), lines.clone()]);
    let dots = b.mesh("dots", &[points]);
    let n1 = b.node(format!("{{\"name\":\"ramp\",\"mesh\":{both}}}"));
    let n2 = b.node(format!("{{\"name\":\"survey\",\"mesh\":{dots}}}"));
    let mixed = b.to_glb(&[n1, n2]);
    let mut plain = Builder::default();
    let root = plain.height_mesh(&ramp, "");
    let (f, r) = mesh::height_field(&mixed, &mut no_files, &opts()).unwrap();
    let (g, _) = mesh::height_field(&plain.to_glb(&[root]), &mut no_files, &opts()).unwrap();
    assert_eq!((f.cols, f.rows, &f.heights), (g.cols, g.rows, &g.heights));
    assert_eq!(r.skipped, 2);
    let profile = profiles::builtin("finger3").unwrap();
    let out = mesh::compile_gltf(&mixed, &mut no_files, &profile, &opts());
    let note = out.diagnostics.iter().find(|d| d.code == "T0618").expect("the note");
    assert!(out.bundle.is_some(), "{:?}", out.diagnostics);
    assert!(
        note.message.starts_with("2 primitives of points or lines left out (the first: node 'ramp' (#0), mesh 'ramp' (#0), primitive 1, mode Lines)"),
        "{}",
        note.message
    );
    // Lines alone: nothing to build, the error names them.
    let mut only = Builder::default();
    let p = only.positions(&ramp.positions);
    let edges = only.indices(&[0, 1, 1, 2]);
    let m = only.mesh("wire", &[format!("{{\"attributes\":{{\"POSITION\":{p}}},\"indices\":{edges},\"mode\":1}}")]);
    let n = only.node(format!("{{\"mesh\":{m}}}"));
    let e = error(&only.to_glb(&[n])).to_string();
    assert!(e.contains("mode Lines is not supported") && e.contains("no triangles"), "{e}");
}

#[test]
fn corrupted_files_are_errors_or_fields_never_panics() {
    // A small file with most of what the reader takes (an instanced node
    // with translations and normalised-short rotations, a plain node, u16
    // indices, a primitive of lines), corrupted a few bytes at a time:
    // random bytes anywhere, or a digit of the JSON changed (which keeps it
    // JSON and reaches the accessors, counts and offsets). Every result is a
    // field or an error; a panic fails the test.
    let ramp = HeightMesh::grid(3, 3, |u, v| [0.01 * u, 0.004 * u * v, 0.01 * v]);
    let mut b = Builder::default();
    let p = b.positions(&ramp.positions);
    let idx: Vec<u8> = ramp.indices.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect();
    let v = b.view(&idx, None);
    let i = b.accessor(format!(
        "{{\"bufferView\":{v},\"componentType\":5123,\"count\":{},\"type\":\"SCALAR\"}}",
        ramp.indices.len()
    ));
    let edges = b.indices(&[0, 1, 1, 2]);
    let m = b.mesh(
        "ramp",
        &[
            format!("{{\"attributes\":{{\"POSITION\":{p}}},\"indices\":{i}}}"),
            format!("{{\"attributes\":{{\"POSITION\":{p}}},\"indices\":{edges},\"mode\":1}}"),
        ],
    );
    let t: Vec<u8> = [0.0f32, 0.0, 0.0, 0.02, 0.0, 0.0].iter().flat_map(|x| x.to_le_bytes()).collect();
    let tv = b.view(&t, None);
    let ta = b.accessor(format!("{{\"bufferView\":{tv},\"componentType\":5126,\"count\":2,\"type\":\"VEC3\"}}"));
    let r: Vec<u8> = [0i16, 0, 0, 32767, 0, 23170, 0, 23170].iter().flat_map(|x| x.to_le_bytes()).collect();
    let rv = b.view(&r, None);
    let ra = b.accessor(format!(
        "{{\"bufferView\":{rv},\"componentType\":5122,\"normalized\":true,\"count\":2,\"type\":\"VEC4\"}}"
    ));
    b.extensions_used = vec!["EXT_mesh_gpu_instancing".into()];
    let n1 = b.node(format!(
        "{{\"mesh\":{m},\"extensions\":{{\"EXT_mesh_gpu_instancing\":{{\"attributes\":{{\"TRANSLATION\":{ta},\"ROTATION\":{ra}}}}}}}}}"
    ));
    let n2 = b.node(format!("{{\"mesh\":{m},\"translation\":[0,0,0.03]}}"));
    let glb = b.to_glb(&[n1, n2]);
    let opts = MeshOptions { nodes_per_mm: Some(0.5), ..MeshOptions::default() };
    let (_, report) = mesh::height_field(&glb, &mut no_files, &opts).expect("the file itself builds");
    assert_eq!(report.triangles, 3 * ramp.indices.len() / 3, "two instances and a node of the ramp");

    let json_end = 20 + u32::from_le_bytes([glb[12], glb[13], glb[14], glb[15]]) as usize;
    let digits: Vec<usize> = (20..json_end).filter(|&k| glb[k].is_ascii_digit()).collect();
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let (mut built, mut refused) = (0, 0);
    for round in 0..3000 {
        let mut bytes = glb.clone();
        for _ in 0..1 + next() % 3 {
            if round % 2 == 0 {
                let k = digits[next() as usize % digits.len()];
                bytes[k] = b"0123456789"[next() as usize % 10];
            } else {
                let k = next() as usize % bytes.len();
                bytes[k] = next() as u8;
            }
        }
        match mesh::height_field(&bytes, &mut no_files, &opts) {
            Ok(_) => built += 1,
            Err(e) => {
                assert!(!e.to_string().is_empty());
                refused += 1;
            }
        }
    }
    // Both outcomes are exercised: the corruption reaches past the parser.
    assert!(built > 100 && refused > 100, "built {built}, refused {refused}");
}
