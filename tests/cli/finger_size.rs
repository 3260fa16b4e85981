//! Finger bundles stored as the device needs them (format 4.6's tiled height
//! fields): each of the paper's five shapes (the demo's finger scenes) and a
//! fitted terrain is at most a 16-bit PNG of its heights, and plays the same
//! actuators as the 4.0 field it replaces, within the stated error.

use std::path::Path;

use taxel_compiler::mesh::write::HeightMesh;
use taxel_compiler::mesh::{self, MeshOptions, store};
use taxel_format::{
    Bundle, BundleView, Chunk, ChunkView, FIELD_CONTACT, FamilyParams, HeightEncoding, HeightField, Manifest, Mm, Tick,
    profiles,
};
use taxel_runtime::finger::{FingerPlayer, Touch};
use taxel_runtime::trace::Trace;
use taxel_textform::png::{BitDepth, ColorType, Compression, write};

fn no_files(_: &str) -> Result<Vec<u8>, String> {
    Err("no external buffers".into())
}

/// A 16-bit grayscale PNG of the field's heights: contact nodes from 1 (the
/// lowest) to 65535 (the highest), 0 where there is no contact, encoded by
/// the `png` crate with adaptive filters and `compression` (as the `image`
/// crate encodes it at its default and its best compression).
fn png_of(f: &HeightField, compression: Compression) -> usize {
    let contact = || f.heights.iter().zip(&f.flags).filter(|(_, fl)| **fl & FIELD_CONTACT != 0).map(|(h, _)| *h);
    let lo = contact().fold(f32::INFINITY, f32::min) as f64;
    let hi = contact().fold(f32::NEG_INFINITY, f32::max) as f64;
    let scale = if hi > lo { 65534.0 / (hi - lo) } else { 0.0 };
    let px: Vec<u16> = f
        .heights
        .iter()
        .zip(&f.flags)
        .map(|(h, fl)| if fl & FIELD_CONTACT != 0 { 1 + ((*h as f64 - lo) * scale).round() as u16 } else { 0 })
        .collect();
    assert_eq!(px.len(), (f.cols * f.rows) as usize, "cols * rows pixels");
    let bytes: Vec<u8> = px.iter().flat_map(|v| v.to_be_bytes()).collect();
    write(f.cols, f.rows, ColorType::Grayscale, BitDepth::Sixteen, &bytes, compression).expect("png").len()
}

/// The bytes a height field chunk takes in a bundle (its data, its table entry, its padding).
fn field_bytes(f: &HeightField) -> usize {
    let manifest = Manifest::new(profiles::builtin("finger3").unwrap());
    let mut b = Bundle::new(manifest);
    let empty = b.to_bytes().unwrap().len();
    b.chunks.push(Chunk::Height(f.clone()));
    b.to_bytes().unwrap().len() - empty
}

/// A fitted terrain: a 179 x 219 quad grid of a 9 x 11 km landscape of
/// several octaves of ridges and valleys, +Y up.
fn terrain() -> HeightMesh {
    HeightMesh::grid(179, 219, |u, v| {
        let mut h = 0.0;
        let mut amp = 400.0;
        for k in 0..6 {
            let f = (2.0f64).powi(k) * 3.0;
            let (p, q) = (1.7 * k as f64 + 0.3, 2.3 * k as f64 + 1.1);
            h += amp * ((f * u + p).sin() * (f * 1.3 * v + q).cos() + 0.5 * (f * 0.7 * (u + v) + q).sin());
            amp *= 0.5;
        }
        [9000.0 * u, 1200.0 + h, 11000.0 * v]
    })
}

/// The compiler's 4.0 field and its tiled field for `glb` with `opts`.
fn fields(glb: &[u8], opts: &MeshOptions) -> (HeightField, HeightField) {
    let profile = profiles::builtin("finger3").unwrap();
    let (float, _) = mesh::height_field(glb, &mut no_files, opts).expect("builds");
    let out = mesh::compile_gltf(glb, &mut no_files, &profile, opts);
    let b = out.bundle.unwrap_or_else(|| panic!("{:?}", out.diagnostics));
    let tiled = b.chunks.iter().find_map(|c| if let Chunk::Height(h) = c { Some(h.clone()) } else { None });
    let tiled = tiled.expect("a height field");
    assert!(matches!(tiled.encoding, HeightEncoding::Tiled { .. }));
    assert_eq!(store::tiled(float.clone(), &profile).encoding, tiled.encoding);
    (float, tiled)
}

#[test]
fn finger_fields_are_at_most_a_16_bit_png_of_their_heights() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/finger");
    let mut cases: Vec<(String, Vec<u8>, MeshOptions)> = ["edge", "flat", "inclined", "convex", "concave"]
        .iter()
        .map(|s| (s.to_string(), std::fs::read(dir.join(format!("{s}.glb"))).unwrap(), MeshOptions::default()))
        .collect();
    let fit = MeshOptions { fit: Some([160.0, 100.0]), nodes_per_mm: Some(4.0), ..MeshOptions::default() };
    cases.push(("fitted terrain".into(), terrain().to_glb(), fit));
    let mut over = Vec::new();
    for (name, glb, opts) in &cases {
        let (float, tiled) = fields(glb, opts);
        let (old, new) = (field_bytes(&float), field_bytes(&tiled));
        // High compression is not always the smallest
        // (the terrain's is larger than balanced): the bar is the smaller.
        let (png, best) = (png_of(&float, Compression::Balanced), png_of(&float, Compression::High));
        eprintln!(
            "{name}: {} x {} nodes: 4.0 field {old} B, tiled {new} B, 16-bit PNG {png} B (best compression {best} B)",
            float.cols, float.rows
        );
        if new > png.min(best) {
            over.push(format!("{name}: the tiled field is {new} bytes, its PNG {}", png.min(best)));
        }
    }
    assert!(over.is_empty(), "{over:?}");
}

/// The frames of the bundle holding `f`, played along `trace`.
fn frames(f: &HeightField, trace: &Trace) -> Vec<taxel_runtime::finger::FingerFrame> {
    let mut b = Bundle::new(Manifest::new(profiles::builtin("finger3").unwrap()));
    b.chunks.push(Chunk::Height(f.clone()));
    let bytes = b.to_bytes().unwrap();
    let view = BundleView::parse(&bytes).unwrap();
    assert!(view.chunks().any(|c| matches!(c, ChunkView::Height(_))));
    let mut p = FingerPlayer::new(&view).unwrap();
    trace
        .samples()
        .iter()
        .map(|s| {
            let tick = Tick((s.t_ms / 10.0).round() as u64);
            p.sample(Touch { tick, x: Mm(s.x_mm as f32), y: Mm(s.y_mm as f32), contact: s.contact })
        })
        .collect()
}

#[test]
fn the_tiled_shapes_play_the_4_0_fields_actuators_within_the_stated_error() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/finger");
    let FamilyParams::Finger(fp) = profiles::builtin("finger3").unwrap().params else { panic!() };
    for shape in ["edge", "flat", "inclined", "convex", "concave"] {
        let glb = std::fs::read(dir.join(format!("{shape}.glb"))).unwrap();
        let (float, tiled) = fields(&glb, &MeshOptions::default());
        let HeightEncoding::Tiled { step, max_gradient, .. } = tiled.encoding else { unreachable!() };
        let trace = Trace::parse(std::fs::File::open(dir.join(format!("{shape}.trace.csv"))).unwrap()).unwrap();
        let (a, b) = (frames(&float, &trace), frames(&tiled, &trace));
        let hmax = float.heights.iter().fold(0.0f32, |m, h| m.max(h.abs()));
        // Intensity: half a step of height. Rhythm: the derived slope within
        // step / cell of the secant, and the secant within M * cell of the
        // stored facet slope (M = 20 / 900 per mm for the quadrics, 0 for the others).
        let m = if shape == "convex" || shape == "concave" { 2.0 * 20.0 / 900.0 } else { 0.0 };
        let slope = (step / float.cell.0) as f64 + m * float.cell.0 as f64 + 1e-5;
        let (mut worst_d, mut worst_r, mut same) = (0.0f64, 0.0f64, 0);
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.active.is_some(), y.active.is_some(), "{shape}: contact at tick {:?}", x.tick);
            if x.on_edge || y.on_edge {
                continue;
            }
            worst_d = worst_d.max((x.intensity - y.intensity).abs() as f64);
            worst_r = worst_r.max((x.rhythm - y.rhythm).abs() as f64);
            same += usize::from(x.active == y.active);
        }
        eprintln!(
            "{shape}: step {step} mm, intensity off by {worst_d:.5} at most, rhythm by {worst_r:.4}, same actuator {same} of {}",
            a.len()
        );
        assert!(worst_d <= (step / hmax * fp.intensity_max) as f64 + 1e-4, "{shape}: intensity {worst_d}");
        assert!(worst_r <= fp.rhythm_max as f64 / max_gradient as f64 * slope, "{shape}: rhythm {worst_r}");
    }
}
