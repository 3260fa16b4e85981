//! The finger device end to end: the paper's five shapes (examples/finger)
//! compiled from their glTF files, played on their sweep traces with
//! `taxel play`, give the actuator sequences of seed 002, Fig. 5.

use std::path::{Path, PathBuf};
use std::process::Command;

use taxel_compiler::mesh::shapes::{STEP_X, Shape};
use taxel_compiler::mesh::{self, MeshOptions};
use taxel_format::profiles;

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/finger")
}

fn taxel() -> Command {
    Command::new(env!("CARGO_BIN_EXE_taxel"))
}

/// Compiles an example mesh with the library (the path `taxel build` takes) and writes the bundle.
fn build(file: &str, dir: &Path) -> PathBuf {
    let bytes = std::fs::read(examples().join(file)).unwrap();
    let profile = profiles::builtin("finger3").unwrap();
    let out = mesh::compile_gltf(&bytes, &mut |_| Err("no external buffers".into()), &profile, &MeshOptions::default());
    let bundle = out.bundle.unwrap_or_else(|| panic!("{file}: {:?}", out.diagnostics));
    let path = dir.join(format!("{file}.taxel"));
    std::fs::write(&path, bundle.to_bytes().unwrap()).unwrap();
    path
}

/// One parsed motors row: time, the three levels, the period.
#[derive(Debug)]
struct Row {
    t_ms: f64,
    levels: [f64; 3],
    period: Option<f64>,
}

fn play(bundle: &Path, trace: &Path, out: &Path) -> Vec<Row> {
    let o = taxel().arg("play").arg(bundle).arg("--trace").arg(trace).arg("--out").arg(out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t_ms,left,down,right,period_ms"));
    lines
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            assert_eq!(c.len(), 5, "{l}");
            let f = |s: &str| s.parse::<f64>().unwrap();
            Row { t_ms: f(c[0]), levels: [f(c[1]), f(c[2]), f(c[3])], period: (!c[4].is_empty()).then(|| f(c[4])) }
        })
        .collect()
}

/// The trace's x per row.
fn trace_x(trace: &Path) -> Vec<f64> {
    std::fs::read_to_string(trace)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect()
}

/// The active actuator of each row ('L', 'D', 'R', or '-' when off). A row
/// is on when it has a period; the active actuator is the one with a level
/// (all shapes are at least 5 mm high, so D > 0 whenever on).
fn actuators(rows: &[Row]) -> Vec<char> {
    rows.iter()
        .map(|r| match r.period {
            None => {
                assert_eq!(r.levels, [0.0; 3], "off rows drive nothing");
                '-'
            }
            Some(_) => {
                let on: Vec<usize> = (0..3).filter(|&k| r.levels[k] > 0.0).collect();
                assert_eq!(on.len(), 1, "exactly one actuator at t = {} ms: {:?}", r.t_ms, r.levels);
                ['L', 'D', 'R'][on[0]]
            }
        })
        .collect()
}

/// Consecutive runs of the same actuator, ignoring off rows.
fn runs(acts: &[char]) -> String {
    let mut s = String::new();
    for &a in acts.iter().filter(|&&a| a != '-') {
        if !s.ends_with(a) {
            s.push(a);
        }
    }
    s
}

#[test]
fn every_shape_gives_the_papers_actuator_sequence() {
    let dir = tempfile::tempdir().unwrap();
    let expected = [
        (Shape::Edge, "DRD"),
        (Shape::Flat, "D"),
        (Shape::Inclined, "L"),
        (Shape::Convex, "RDL"),
        (Shape::Concave, "LDR"),
    ];
    for (shape, want) in expected {
        for ext in ["glb", "gltf"] {
            let bundle = build(&format!("{}.{ext}", shape.name()), dir.path());
            let trace = examples().join(format!("{}.trace.csv", shape.name()));
            let rows = play(&bundle, &trace, &dir.path().join(format!("{}.{ext}.csv", shape.name())));
            let xs = trace_x(&trace);
            assert_eq!(rows.len(), xs.len(), "one motors row per trace row");
            let acts = actuators(&rows);
            assert_eq!(runs(&acts), want, "{} ({ext}): {}", shape.name(), acts.iter().collect::<String>());
            // Off exactly outside the shape (x 20..140) and after the lift.
            for (k, (&a, &x)) in acts.iter().zip(&xs).enumerate() {
                if k + 1 == acts.len() {
                    assert_eq!(a, '-', "the finger lifts at the end");
                } else if !(19.0..=141.0).contains(&x) {
                    assert_eq!(a, '-', "{}: x = {x} is outside the shape", shape.name());
                } else if (21.0..=139.0).contains(&x) {
                    assert_ne!(a, '-', "{}: x = {x} is on the shape", shape.name());
                }
            }
            if shape == Shape::Edge {
                // The single side event sits at the step.
                for (a, x) in acts.iter().zip(&xs) {
                    if *a == 'R' {
                        assert!((x - STEP_X).abs() <= 2.0, "right actuator at x = {x}, step at {STEP_X}");
                    }
                }
            }
        }
    }
}

#[test]
fn intensity_follows_height_and_period_follows_slope() {
    // Convex: h = 35 - 20 u^2 on the sweep row; intensity_max 1 and the
    // highest point 35 mm give D = h / 35. Rhythm R = 100 |slope| / max
    // slope, T = 210 - 2 R: at the peak the slope is 0, so T = 210 ms.
    let dir = tempfile::tempdir().unwrap();
    let bundle = build("convex.glb", dir.path());
    let trace = examples().join("convex.trace.csv");
    let rows = play(&bundle, &trace, &dir.path().join("m.csv"));
    let xs = trace_x(&trace);
    let mut checked = 0;
    for (r, &x) in rows.iter().zip(&xs) {
        if (30.0..=130.0).contains(&x) {
            let u = (x - 80.0) / 60.0;
            let h = 35.0 - 20.0 * u * u;
            let d: f64 = r.levels.iter().sum();
            assert!((d - h / 35.0).abs() < 0.01, "x = {x}: D = {d}, expected {}", h / 35.0);
            if (x - 80.0).abs() < 0.3 {
                let t = r.period.unwrap();
                assert!(t > 200.0, "at the peak the rhythm is slowest, T = {t}");
            }
            checked += 1;
        }
    }
    assert!(checked > 100);
}

#[test]
fn play_reports_a_bad_trace_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let bundle = build("flat.glb", dir.path());
    let trace = dir.path().join("bad.csv");
    std::fs::write(&trace, "t_ms,x_mm,y_mm,contact\n0,30,50,1\n10,abc,50,1\n").unwrap();
    let out = dir.path().join("m.csv");
    let o = taxel().arg("play").arg(&bundle).arg("--trace").arg(&trace).arg("--out").arg(&out).output().unwrap();
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("bad.csv") && err.contains("line 3") && err.contains("x_mm"), "{err}");
    assert!(!out.exists(), "no partial output");
}

#[test]
fn play_refuses_a_corrupt_bundle_and_a_missing_trace() {
    let dir = tempfile::tempdir().unwrap();
    let bundle = build("flat.glb", dir.path());
    let o = taxel().arg("play").arg(&bundle).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--trace"));
    let mut bytes = std::fs::read(&bundle).unwrap();
    let n = bytes.len();
    bytes[n - 5] ^= 0xff;
    let bad = dir.path().join("bad.taxel");
    std::fs::write(&bad, bytes).unwrap();
    let trace = examples().join("flat.trace.csv");
    let o = taxel().arg("play").arg(&bad).arg("--trace").arg(&trace).output().unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("bad.taxel"));
}

#[test]
fn taxel_build_compiles_glb_and_gltf_with_an_external_buffer() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("edge.taxel");
    let o = taxel()
        .arg("build")
        .arg(examples().join("edge.glb"))
        .args(["--profile", "finger3", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let from_cli = std::fs::read(&out).unwrap();
    let from_lib = std::fs::read(build("edge.glb", dir.path())).unwrap();
    let (a, l) =
        (taxel_format::Bundle::from_bytes(&from_cli).unwrap(), taxel_format::Bundle::from_bytes(&from_lib).unwrap());
    // The CLI adds a content hash to the manifest; the layers are the library's.
    assert!(a.chunks == l.chunks, "the CLI builds the layers the library builds");

    // The same mesh with its buffer in a file beside the .gltf.
    let (json, bin) = Shape::Edge.mesh().to_gltf_external("edge%20data.bin");
    std::fs::write(dir.path().join("ext.gltf"), json).unwrap();
    std::fs::write(dir.path().join("edge data.bin"), bin).unwrap();
    let out2 = dir.path().join("ext.taxel");
    let o = taxel().arg("build").arg(dir.path().join("ext.gltf")).arg("-o").arg(&out2).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let b = taxel_format::Bundle::from_bytes(&std::fs::read(&out2).unwrap()).unwrap();
    assert!(a.chunks[0] == b.chunks[0], "same height field from an external buffer");
}

#[test]
fn taxel_build_refuses_a_buffer_outside_the_meshs_folder() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("sub");
    std::fs::create_dir(&sub).unwrap();
    let (json, bin) = Shape::Flat.mesh().to_gltf_external("../secret.bin");
    std::fs::write(sub.join("m.gltf"), json).unwrap();
    std::fs::write(dir.path().join("secret.bin"), bin).unwrap();
    let out = dir.path().join("m.taxel");
    let o = taxel().arg("build").arg(sub.join("m.gltf")).arg("-o").arg(&out).output().unwrap();
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("m.gltf") && err.contains("leaves the glTF file's folder"), "{err}");
    assert!(!out.exists());
}

/// A Z-up DEM as a GIS tool exports it: 161 x 161 samples (25,921 vertices)
/// over 9 km east (X) by 11 km north (Y), heights Z in metres, 760 to 1440 m:
/// a ridge running north-south through the middle, rising and falling gently
/// along its crest.
fn dem() -> taxel_compiler::mesh::write::HeightMesh {
    let mut m = taxel_compiler::mesh::write::HeightMesh::grid(160, 160, |u, v| {
        let (x, y) = (9000.0 * u, 11000.0 * v);
        let across = (x - 4500.0) / 4500.0;
        [x, y, 1400.0 - 600.0 * across * across + 40.0 * (y / 1800.0).sin()]
    });
    m.name = "dem".into();
    m
}

#[test]
fn a_z_up_terrain_fitted_and_swept_across_its_ridge_plays_right_down_left() {
    let dir = tempfile::tempdir().unwrap();
    let glb = dir.path().join("dem.glb");
    std::fs::write(&glb, dem().to_glb()).unwrap();
    let bundle = dir.path().join("dem.taxel");
    let o = taxel()
        .arg("build")
        .arg(&glb)
        .args(["--profile", "finger3", "--fit", "--up", "z", "-o"])
        .arg(&bundle)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("T0612") && !err.contains("T0616"), "fitted and read Z-up: {err}");

    // 11 km fill the 100 mm height of finger3's surface; 9 km are 81.8 mm,
    // centred: x 39.1..120.9 mm. The finger slides left to right along the
    // middle row from beside the terrain (so it has a direction when it
    // arrives, as in the paper's sweeps) over the crest (x = 80) to the east.
    let trace = dir.path().join("sweep.csv");
    let mut text = String::from("t_ms,x_mm,y_mm,contact\n");
    let xs: Vec<f64> = (0..=180).map(|k| 35.0 + 0.5 * k as f64).collect();
    for (k, x) in xs.iter().enumerate() {
        // A hand is not a ruler: the row wobbles by a quarter millimetre.
        let y = 50.0 + 0.25 * ((k as f64) * 0.7).sin();
        text += &format!("{},{x},{y:.4},1\n", 10 * k);
    }
    text += &format!("{},125,50,0\n", 10 * xs.len());
    std::fs::write(&trace, text).unwrap();
    let rows = play(&bundle, &trace, &dir.path().join("motors.csv"));
    let acts = actuators(&rows);
    assert_eq!(runs(&acts), "RDL", "{}", acts.iter().collect::<String>());
    // Down exactly around the crest: the slope across the ridge is
    // 2 * 600 * (x - 80) / 4500 / (40.9 mm per 4500 m) per mm, within the
    // profile's flat band of 0.05 for |x - 80| < 7.7 mm.
    for (a, x) in acts.iter().zip(&xs) {
        if (x - 80.0).abs() < 6.0 {
            assert_eq!(*a, 'D', "x = {x}");
        }
        if (x - 80.0).abs() > 10.0 && (42.0..118.0).contains(x) {
            assert_ne!(*a, 'D', "x = {x}");
        }
        if !(38.0..122.0).contains(x) {
            assert_eq!(*a, '-', "x = {x} is beside the terrain");
        }
    }
}

#[test]
fn taxel_build_refuses_a_draco_file_in_one_sentence_that_says_what_to_do() {
    use taxel_compiler::mesh::write::Builder;
    let dir = tempfile::tempdir().unwrap();
    // As Blender writes it with "Compression" ticked: accessors without buffer
    // views, the primitive's extension pointing at the compressed bytes.
    let mut b = Builder::default();
    let v = b.view(&[0u8; 16], None);
    let pos =
        b.accessor("{\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,1]}".into());
    let mesh = b.mesh(
        "Box",
        &[format!(
            "{{\"attributes\":{{\"POSITION\":{pos}}},\"extensions\":{{\"KHR_draco_mesh_compression\":\
             {{\"bufferView\":{v},\"attributes\":{{\"POSITION\":0}}}}}}}}"
        )],
    );
    let node = b.node(format!("{{\"mesh\":{mesh}}}"));
    b.extensions_used.push("KHR_draco_mesh_compression".into());
    b.extensions_required.push("KHR_draco_mesh_compression".into());
    let glb = dir.path().join("box.glb");
    std::fs::write(&glb, b.to_glb(&[node])).unwrap();
    let out = dir.path().join("box.taxel");
    let o = taxel().arg("build").arg(&glb).arg("-o").arg(&out).output().unwrap();
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("box.glb") && err.contains("T0614"), "{err}");
    assert!(err.contains("KHR_draco_mesh_compression") && err.contains("untick \"Compression\""), "{err}");
    assert!(!err.contains("Missing data") && !out.exists(), "{err}");
}
