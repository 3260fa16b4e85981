//! The exact reference for height meshes: the top surface of the original
//! triangles, interpolated barycentrically (each triangle's own plane), in f64.
//! The height field the runtime samples (bilinear between nodes) is compared
//! with it along the scene's touch trace: height error in mm, slope error in
//! degrees (the angle of the surface along x and along y).

use std::path::{Component, Path};
use std::time::Instant;

use anyhow::{Result, anyhow, bail};
use taxel_format::{Bundle, BundleView, Chunk, Mm, Tick};
use taxel_runtime::finger::{FingerPlayer, Touch, field};

use super::Row;
use crate::cli::CompileOpts;
use taxel_runtime::trace::Trace;

/// Height-field resolutions (nodes per mm) on the ladder; the compiler's own choice is added.
pub const NODE_LADDER: [f64; 5] = [0.25, 0.5, 1.0, 2.0, 4.0];

/// One original triangle with its plane `h = a·x + b·y + c` and its box.
struct Tri {
    p: [[f64; 3]; 3],
    plane: (f64, f64, f64),
    bbox: [f64; 4],
}

/// The original triangles of a glTF file in page mm.
pub struct MeshRef {
    tris: Vec<Tri>,
}

impl MeshRef {
    /// Reads the mesh's triangles with the compiler's loader (the same
    /// frame: page mm, height up); external buffers only from beside the file.
    pub fn read(path: &Path) -> Result<MeshRef> {
        Self::read_with(path, &taxel_compiler::mesh::MeshOptions::default())
    }

    /// Reads the mesh as the compiler places it with `mesh` (`--up`,
    /// `--region`, `--fit`, `--exaggerate`), so the reference is in the field's frame.
    pub fn read_with(path: &Path, mesh: &taxel_compiler::mesh::MeshOptions) -> Result<MeshRef> {
        let bytes = crate::io::read_input(path)?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let mut resolve = |uri: &str| -> Result<Vec<u8>, String> {
            let rel = Path::new(uri);
            if uri.contains(':') || rel.components().any(|c| !matches!(c, Component::Normal(_) | Component::CurDir)) {
                return Err(format!("buffer URI '{uri}' is not a path beside the file"));
            }
            crate::io::read_input(&dir.join(rel)).map_err(|e| format!("buffer '{uri}': {e:#}"))
        };
        let (soup, _) =
            taxel_compiler::mesh::placed(&bytes, &mut resolve, mesh).map_err(|e| anyhow!("{}: {e}", path.display()))?;
        let mut tris = Vec::with_capacity(soup.triangles.len());
        for t in &soup.triangles {
            let Some(p) = t.iter().map(|&i| soup.vertices.get(i as usize).copied()).collect::<Option<Vec<_>>>() else {
                continue;
            };
            let p = [p[0], p[1], p[2]];
            // Plane through the three corners; triangles with no area seen from above
            // (walls, slivers) have no plane: the neighbouring faces decide there.
            let (ux, uy, uh) = (p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]);
            let (vx, vy, vh) = (p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]);
            let det = ux * vy - uy * vx;
            let scale = (ux.abs() + uy.abs()) * (vx.abs() + vy.abs());
            if det.is_nan() || det.abs() <= 1e-12 * scale {
                continue;
            }
            let a = (uh * vy - uy * vh) / det;
            let b = (ux * vh - uh * vx) / det;
            let c = p[0][2] - a * p[0][0] - b * p[0][1];
            let bbox = [
                p.iter().map(|q| q[0]).fold(f64::INFINITY, f64::min),
                p.iter().map(|q| q[1]).fold(f64::INFINITY, f64::min),
                p.iter().map(|q| q[0]).fold(f64::NEG_INFINITY, f64::max),
                p.iter().map(|q| q[1]).fold(f64::NEG_INFINITY, f64::max),
            ];
            tris.push(Tri { p, plane: (a, b, c), bbox });
        }
        if tris.is_empty() {
            bail!("{}: the mesh has no triangle with area seen from above", path.display());
        }
        Ok(MeshRef { tris })
    }

    /// The top surface at `(x, y)`: its height and the gradients of every
    /// highest triangle containing the point, or `None` off the mesh. Inside
    /// a facet that is one gradient; on an edge or vertex that facets share
    /// (a crease of the surface, where the height is the same from each) it
    /// is each of theirs, since the exact slope there is any of them. "On"
    /// is within [`CREASE_MM`]: glTF's `f32` metres put a shared edge drawn
    /// at y = 50 mm a few nm off it, and a touch at 50 mm is on it.
    pub fn slopes_at(&self, x: f64, y: f64) -> Option<(f64, Vec<(f64, f64)>)> {
        // The highest facet's height and steepness so far, and the slopes at that height.
        let (mut top, mut top_steep, mut slopes) = (f64::NEG_INFINITY, 0.0f64, Vec::new());
        for t in &self.tris {
            let m = CREASE_MM;
            if x < t.bbox[0] - m || x > t.bbox[2] + m || y < t.bbox[1] - m || y > t.bbox[3] + m {
                continue;
            }
            let [a, b, c] = t.p;
            let d = (b[1] - c[1]) * (a[0] - c[0]) + (c[0] - b[0]) * (a[1] - c[1]);
            let l1 = ((b[1] - c[1]) * (x - c[0]) + (c[0] - b[0]) * (y - c[1])) / d;
            let l2 = ((c[1] - a[1]) * (x - c[0]) + (a[0] - c[0]) * (y - c[1])) / d;
            let l3 = 1.0 - l1 - l2;
            // Each barycentric coordinate is the distance to the opposite
            // side over the altitude there, `|d|` over the side's length.
            let side = |p: [f64; 3], q: [f64; 3]| (q[0] - p[0]).hypot(q[1] - p[1]);
            let within = |l: f64, p, q| l * d.abs() >= -CREASE_MM * side(p, q);
            if !(within(l1, b, c) && within(l2, c, a) && within(l3, a, b)) {
                continue;
            }
            let h = l1 * a[2] + l2 * b[2] + l3 * c[2];
            let (gx, gy) = (t.plane.0, t.plane.1);
            let steep = gx.hypot(gy);
            // The same height, within the planes' rise over `CREASE_MM`.
            if !slopes.is_empty() && (h - top).abs() <= CREASE_MM * (1.0 + steep + top_steep) {
                slopes.push((gx, gy));
            } else if h > top {
                (top, top_steep) = (h, steep);
                slopes.clear();
                slopes.push((gx, gy));
            }
        }
        (!slopes.is_empty()).then_some((top, slopes))
    }
}

/// How near a facet's side a point is on it ([`MeshRef::slopes_at`]), mm:
/// well above the `f32` rounding of glTF's metres at page scale (15 nm at
/// 140 mm), well below a touch screen's resolution.
const CREASE_MM: f64 = 1e-4;

/// Height and slope errors of one bundle along `trace`.
struct MeshMeasured {
    bytes: usize,
    sample_us: f64,
    height: (f64, f64),
    slope: (f64, f64),
    compared: usize,
}

fn measure(bundle: &Bundle, exact: &MeshRef, trace: &Trace) -> Result<MeshMeasured> {
    let bytes = bundle.to_bytes().map_err(|e| anyhow!("{e}"))?;
    let view = BundleView::parse(&bytes).map_err(|e| anyhow!("{e}"))?;
    let Some(hf) = view.chunks().find_map(|c| if let taxel_format::ChunkView::Height(h) = c { Some(h) } else { None })
    else {
        bail!("the bundle has no height field");
    };
    let rate = view.manifest().profile.rate_hz as f64;
    let mut player = FingerPlayer::new(&view).map_err(|e| anyhow!("{e}"))?;
    let points: Vec<(f64, f64, f64)> = trace.samples().iter().map(|s| (s.t_ms, s.x_mm, s.y_mm)).collect();
    let mut best = f64::INFINITY;
    for _ in 0..3 {
        player.reset();
        let t0 = Instant::now();
        for &(t, x, y) in &points {
            let tick = Tick((t * rate / 1000.0).round() as u64);
            std::hint::black_box(player.sample(Touch { tick, x: Mm(x as f32), y: Mm(y as f32), contact: true }));
        }
        best = best.min(t0.elapsed().as_secs_f64());
    }
    let (mut hm, mut h2, mut sm, mut s2, mut n) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0usize);
    for &(_, x, y) in &points {
        let (Some(s), Some((h, slopes))) = (field::sample(&hf, x as f32, y as f32), exact.slopes_at(x, y)) else {
            continue;
        };
        // At a step the exact slope is vertical and the field's is capped by design: not an error.
        if s.edge {
            continue;
        }
        let eh = (s.height as f64 - h).abs();
        // On a crease the exact slope is any of its facets': the nearest.
        let slope_error = |&(gx, gy): &(f64, f64)| {
            let ex = ((s.grad_x as f64).atan() - gx.atan()).abs().to_degrees();
            let ey = ((s.grad_y as f64).atan() - gy.atan()).abs().to_degrees();
            (ex, ey)
        };
        let Some((ex, ey)) =
            slopes.iter().map(slope_error).min_by(|a, b| (a.0 * a.0 + a.1 * a.1).total_cmp(&(b.0 * b.0 + b.1 * b.1)))
        else {
            continue;
        };
        hm = hm.max(eh);
        h2 += eh * eh;
        sm = sm.max(ex).max(ey);
        s2 += (ex * ex + ey * ey) / 2.0;
        n += 1;
    }
    let rms = |v: f64| (v / n.max(1) as f64).sqrt();
    Ok(MeshMeasured {
        bytes: super::stored_len(&bytes)?,
        sample_us: best * 1e6 / trace.samples().len().max(1) as f64,
        height: (hm, rms(h2)),
        slope: (sm, rms(s2)),
        compared: n,
    })
}

/// The cell of the bundle's height field in mm.
fn cell_of(b: &Bundle) -> Option<f64> {
    b.chunks.iter().find_map(|c| if let Chunk::Height(h) = c { Some(h.cell.0 as f64) } else { None })
}

/// The height-field ladder of a mesh scene: per setting a `height` row (mm)
/// and a `gradient` row (degrees of slope).
pub fn ladder(
    input: &Path,
    opts: &CompileOpts,
    base: &Bundle,
    trace: &Trace,
    default_only: bool,
) -> Result<(Vec<Row>, Vec<String>)> {
    let profile = base.manifest.profile;
    let exact = MeshRef::read_with(input, &crate::compile::mesh_options(opts, &profile))?;
    let default = cell_of(base).map(|c| 1.0 / c);
    let mut settings: Vec<(Option<f64>, f64)> = NODE_LADDER.iter().map(|&r| (Some(r), r)).collect();
    if let Some(d) = default {
        // The compiler's own choice replaces an equal rung of the ladder.
        settings.retain(|s| (s.1 - d).abs() > 1e-9 * d);
        settings.push((None, d));
        settings.sort_by(|a, b| a.1.total_cmp(&b.1));
    }
    if default_only {
        // The compiler's own choice alone (no rung when it has none).
        settings.retain(|s| s.0.is_none());
    }
    let mut rows = Vec::new();
    let mut notes = Vec::new();
    for (setting, value) in settings {
        let (bundle, compile_ms) = match super::compile(input, opts, setting.map(|r| r as f32)) {
            Ok(v) => v,
            Err(e) => {
                notes.push(format!("{value} nodes/mm: {e:#}"));
                continue;
            }
        };
        let m = measure(&bundle, &exact, trace)?;
        if let Some(png) = bundle.chunks.iter().find_map(|c| if let Chunk::Height(h) = c { png16(h) } else { None }) {
            notes.push(format!(
                "{value} nodes/mm: the bundle is {} bytes; a 16-bit PNG of its field's heights is {png} bytes",
                m.bytes
            ));
        }
        let run_ms = compile_ms + m.sample_us * trace.samples().len() as f64 / 1000.0;
        for (kernel, (max, rms), unit) in [("height", m.height, "mm"), ("gradient", m.slope, "degrees of slope")] {
            rows.push(Row {
                kernel: kernel.into(),
                setting: value,
                unit: "nodes/mm".into(),
                default: setting.is_none(),
                compile_ms,
                bundle_bytes: m.bytes,
                frame_us: m.sample_us,
                max_error: max,
                rms_error: rms,
                step_rms_error: None,
                far_error: None,
                far_rms_error: None,
                corner_error: None,
                edge_error_mm: None,
                corner_edge_error_mm: None,
                lattice_mm: None,
                fine_detail: None,
                unfelt: None,
                error_unit: unit.into(),
                frames: m.compared,
                run_ms,
                on_front: false,
            });
        }
    }
    notes.push("touch samples at a step (an edge node around the point) are left out: there the exact slope is vertical and the field's is capped by design".into());
    Ok((rows, notes))
}

/// The size of a 16-bit grayscale PNG of `h`'s heights (contact nodes from
/// 1 at the lowest to 65535 at the highest, 0 elsewhere), as the `png`
/// crate encodes it with adaptive filters at its balanced or its high
/// compression, whichever is smaller (high is not always: on a fitted
/// terrain it was larger), so a field is measured against the strongest
/// PNG the crate writes (the `image` crate's default and best compression,
/// byte for byte). Fast compression is more than twice as large on the
/// paper's convex shape.
pub fn png16(h: &taxel_format::HeightField) -> Option<usize> {
    use taxel_textform::png::{BitDepth, ColorType, Compression, be_bytes, write};
    let contact = || h.heights.iter().zip(&h.flags).filter(|(_, f)| **f & taxel_format::FIELD_CONTACT != 0);
    let lo = contact().map(|(v, _)| *v as f64).fold(f64::INFINITY, f64::min);
    let hi = contact().map(|(v, _)| *v as f64).fold(f64::NEG_INFINITY, f64::max);
    let scale = if hi > lo { 65534.0 / (hi - lo) } else { 0.0 };
    let px: Vec<u16> = h
        .heights
        .iter()
        .zip(&h.flags)
        .map(
            |(v, f)| {
                if f & taxel_format::FIELD_CONTACT != 0 { 1 + ((*v as f64 - lo) * scale).round() as u16 } else { 0 }
            },
        )
        .collect();
    if px.len() != h.cols as usize * h.rows as usize {
        return None;
    }
    let bytes = be_bytes(&px);
    [Compression::Balanced, Compression::High]
        .into_iter()
        .filter_map(|c| Some(write(h.cols, h.rows, ColorType::Grayscale, BitDepth::Sixteen, &bytes, c).ok()?.len()))
        .min()
}

/// The largest height error in mm of `bundle` along `trace` (for the demo).
pub fn max_height_error(input: &Path, bundle: &Bundle, trace: &Trace) -> Result<(f64, f64)> {
    let exact = MeshRef::read(input)?;
    let m = measure(bundle, &exact, trace)?;
    Ok((m.height.0, m.sample_us))
}

#[cfg(test)]
mod tests {
    use super::*;
    use taxel_compiler::mesh::write::HeightMesh;

    #[test]
    fn top_surface_is_the_plane_of_the_highest_triangle() {
        let dir = tempfile::tempdir().expect("temp dir");
        // A 40 x 20 mm ramp rising 10 mm to the right (h = x / 4), and a
        // floating square 5 mm up over part of it.
        let mut m = HeightMesh::grid(2, 2, |u, v| [0.04 * u, 0.01 * u, 0.02 * v]);
        m.append(&HeightMesh::grid(1, 1, |u, v| [0.002 * u, 0.005, 0.002 * v]));
        let p = dir.path().join("m.glb");
        std::fs::write(&p, m.to_glb()).expect("write");
        let r = MeshRef::read(&p).expect("reads");
        let (h, s) = r.slopes_at(30.0, 7.0).expect("on the mesh");
        assert!((h - 7.5).abs() < 1e-6 && s.iter().all(|g| (g.0 - 0.25).abs() < 1e-6 && g.1.abs() < 1e-6), "{h} {s:?}");
        let (h, _) = r.slopes_at(1.0, 1.0).expect("on the square");
        assert!((h - 5.0).abs() < 1e-6, "{h}");
        assert!(r.slopes_at(50.0, 5.0).is_none());
    }

    /// A valley of two facets meeting along x = 20 mm (glTF's `f32` metres
    /// put that crease a few nm off): on it the slope is either facet's,
    /// and a touch 1 µm to either side is on one facet only.
    #[test]
    fn on_a_crease_the_slope_is_each_facets() {
        let dir = tempfile::tempdir().expect("temp dir");
        let m = HeightMesh::grid(2, 3, |u, v| [0.04 * u, 0.01 * (u - 0.5).abs(), 0.03 * v]);
        let p = dir.path().join("valley.glb");
        std::fs::write(&p, m.to_glb()).expect("write");
        let r = MeshRef::read(&p).expect("reads");
        let sorted = |x: f64, y: f64| {
            let (h, mut s) = r.slopes_at(x, y).expect("on the mesh");
            s.sort_by(|a, b| a.0.total_cmp(&b.0));
            s.dedup_by(|a, b| (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9);
            (h, s)
        };
        for y in [5.0, 10.0, 17.5] {
            let (h, s) = sorted(20.0, y);
            assert!(h.abs() < 1e-6, "{h}");
            assert_eq!(s.len(), 2, "{s:?}");
            assert!((s[0].0 + 0.25).abs() < 1e-6 && (s[1].0 - 0.25).abs() < 1e-6 && s.iter().all(|g| g.1.abs() < 1e-6));
            for (x, gx) in [(19.999, -0.25), (20.001, 0.25)] {
                let (_, s) = sorted(x, y);
                assert!(s.len() == 1 && (s[0].0 - gx).abs() < 1e-6, "{x}: {s:?}");
            }
        }
    }
}
