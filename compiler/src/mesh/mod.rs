//! glTF height meshes to height and gradient fields for the finger device
//! (seed 002, `docs/finger.md`).
//!
//! The pipeline has three stages, each in its own file:
//! [`load`] reads every triangle of the scene into page millimetres,
//! [`surface`] builds the top surface on a spade constrained Delaunay
//! triangulation, and [`field`] samples it into a
//! [`taxel_format::HeightField`]. The library does no file IO:
//! external buffers come through a resolver closure.
//!
//! ```
//! use taxel_compiler::mesh::{self, MeshOptions, write::HeightMesh};
//! use taxel_format::profiles;
//!
//! // A 40 x 20 mm ramp rising 10 mm to the right, as a binary glTF.
//! let m = HeightMesh::grid(2, 2, |u, v| [0.04 * u, 0.01 * u, 0.02 * v]);
//! let glb = m.to_glb();
//! let profile = profiles::builtin("finger3").unwrap();
//! let out = mesh::compile_gltf(&glb, &mut |_| Err("no files".into()), &profile, &MeshOptions::default());
//! assert!(out.bundle.is_some());
//! ```

pub mod error;
pub mod field;
pub mod load;
pub mod shapes;
pub mod surface;
pub mod write;

use taxel_format::{Bundle, Chunk, DeviceProfile, Family, HeightField, Manifest, Provenance, ProvenanceEntry};

pub use error::MeshError;
pub use load::Resolver;

use crate::{Compiled, Diagnostic};

/// Options for compiling a mesh.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MeshOptions {
    /// Height-field nodes per millimetre; `None` chooses from the mesh (see docs/finger.md).
    pub nodes_per_mm: Option<f64>,
}

/// What the build measured, for notes and reports.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshReport {
    /// Triangles read from the file.
    pub triangles: usize,
    /// Triangles with no area seen from above.
    pub degenerate: usize,
    /// Faces of the triangulation that the mesh covers.
    pub faces: usize,
    /// Step segments found.
    pub steps: usize,
    /// Footprint `[xmin, ymin, xmax, ymax]` in page mm.
    pub bbox: [f64; 4],
    /// Node spacing in mm.
    pub cell: f64,
    /// Mesh names (for provenance).
    pub mesh_names: Vec<String>,
    /// The scene's name.
    pub scene_name: Option<String>,
}

/// Builds the height field of a glTF file (`.gltf` or `.glb` bytes).
pub fn height_field(
    bytes: &[u8],
    resolve: &mut Resolver<'_>,
    opts: &MeshOptions,
) -> Result<(HeightField, MeshReport), MeshError> {
    let soup = load::load(bytes, resolve)?;
    let surf = surface::build(&soup)?;
    let cell = match opts.nodes_per_mm {
        Some(r) if r.is_finite() && r > 0.0 => 1.0 / r,
        Some(r) => return Err(MeshError::BadResolution(r)),
        None => field::default_cell(&surf),
    };
    let grid = field::grid(&surf, cell)?;
    let hf = field::sample(&surf, &grid, Some(0));
    let report = MeshReport {
        triangles: soup.triangles.len(),
        degenerate: surf.degenerate,
        faces: surf.faces.len(),
        steps: surf.steps.len(),
        bbox: surf.bbox,
        cell: grid.cell as f64,
        mesh_names: soup.mesh_names,
        scene_name: soup.scene_name,
    };
    Ok((hf, report))
}

/// Compiles a glTF height mesh into a bundle for a finger-family `profile`.
///
/// Never panics on any input: a panic inside a dependency is caught and
/// reported as an error diagnostic.
pub fn compile_gltf(bytes: &[u8], resolve: &mut Resolver<'_>, profile: &DeviceProfile, opts: &MeshOptions) -> Compiled {
    let mut diagnostics = Vec::new();
    if profile.family() != Family::Finger {
        diagnostics.push(
            Diagnostic::error(
                "T0609",
                format!(
                    "profile '{}' is for a {} device; a height mesh needs a finger profile",
                    profile.name,
                    profile.family()
                ),
            )
            .with_help("build with --profile finger3 (or a profile file of family \"finger\")"),
        );
        return Compiled { bundle: None, diagnostics };
    }
    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| height_field(bytes, resolve, opts)));
    let (hf, report) = match run {
        Ok(Ok(v)) => v,
        Ok(Err(e)) => {
            diagnostics.push(Diagnostic::error(e.code(), e.to_string()));
            return Compiled { bundle: None, diagnostics };
        }
        Err(_) => {
            diagnostics.push(Diagnostic::error("T0608", "triangulating the mesh failed (internal error)"));
            return Compiled { bundle: None, diagnostics };
        }
    };
    diagnostics.push(Diagnostic::note(
        "T0610",
        format!(
            "height field of {} x {} nodes every {} mm over {:.3} x {:.3} mm from {} triangles ({} steps)",
            hf.cols,
            hf.rows,
            report.cell,
            report.bbox[2] - report.bbox[0],
            report.bbox[3] - report.bbox[1],
            report.triangles,
            report.steps
        ),
    ));
    if report.degenerate > 0 {
        diagnostics.push(Diagnostic::note(
            "T0611",
            format!(
                "{} triangles have no area seen from above (vertical walls or degenerate); \
                 the heights on either side of a wall make a step",
                report.degenerate
            ),
        ));
    }
    let [x0, y0, x1, y1] = report.bbox;
    if x0 < 0.0 || y0 < 0.0 || x1 > profile.surface_w_mm as f64 || y1 > profile.surface_h_mm as f64 {
        diagnostics.push(
            Diagnostic::warning(
                "T0612",
                format!(
                    "the mesh covers x {x0:.3}..{x1:.3} mm, y {y0:.3}..{y1:.3} mm, beyond the {} x {} mm surface of '{}'",
                    profile.surface_w_mm, profile.surface_h_mm, profile.name
                ),
            )
            .with_help("glTF metres become page millimetres (X right, Z down); scale or move the mesh in its file"),
        );
    }
    let mut bundle = Bundle::new(Manifest::new(*profile));
    bundle.chunks.push(Chunk::Height(hf));
    let names: Vec<&str> = report.mesh_names.iter().map(String::as_str).filter(|s| !s.is_empty()).collect();
    bundle.chunks.push(Chunk::Provenance(Provenance {
        entries: vec![ProvenanceEntry {
            id: report.scene_name.clone().unwrap_or_else(|| "scene".into()),
            label: names.join(", "),
            line: 0,
        }],
    }));
    // The writer validates its own output; a refusal here is reported, not hidden.
    if let Err(e) = bundle.to_bytes() {
        diagnostics.push(Diagnostic::error("T0613", format!("the height field cannot be stored: {e}")));
        return Compiled { bundle: None, diagnostics };
    }
    Compiled { bundle: Some(bundle), diagnostics }
}
