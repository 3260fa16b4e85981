//! Back end for the finger device (its own pipeline, family 3): meshes, not drawings.
//!
//! glTF height meshes to height and gradient fields for the finger device
//! (seed 002, `docs/finger.md`).
//!
//! The pipeline has four stages, each in its own file:
//! `load` reads every triangle of the scene into page millimetres,
//! `place` keeps the `--region`, fits the model onto the surface and
//! scales its heights, `surface` builds the top surface (from the triangles
//! themselves when they tile the page, `sheet`; otherwise on a spade
//! constrained Delaunay triangulation of the edges' exact arrangement,
//! `planar`), and `field` samples it into a
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

pub(crate) mod error;
pub(crate) mod field;
pub(crate) mod load;
pub(crate) mod place;
pub(crate) mod planar;
pub mod shapes;
pub(crate) mod sheet;
pub mod store;
pub(crate) mod surface;
pub mod write;

use taxel_format::{Bundle, Chunk, DeviceProfile, Family, HeightField, Manifest, Provenance, ProvenanceEntry};

pub use error::MeshError;
pub use load::Resolver;

use crate::diagnostic::number;
use crate::options::{CompileOptions, Region, UpAxis};
use crate::{Compiled, Diagnostic};

/// Options for compiling a mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshOptions {
    /// Height-field nodes per millimetre; `None` chooses from the mesh (see docs/finger.md).
    pub nodes_per_mm: Option<f64>,
    /// The model's height axis (`--up`); `None` chooses it ([`chosen_up`]).
    pub up: Option<UpAxis>,
    /// Scale and centre the footprint (or the region) into a surface of this
    /// width and height in mm, keeping its aspect ratio, with the lowest
    /// point at height 0 (`--fit`; [`MeshOptions::from_compile`] takes the profile's surface).
    pub fit: Option<[f64; 2]>,
    /// Keep only this part of the footprint (`--region`): a rectangle in
    /// model units along the page axes, or a node or mesh name.
    pub region: Option<Region>,
    /// Factor on heights (`--exaggerate`), above 0.
    pub exaggerate: f64,
}

impl Default for MeshOptions {
    fn default() -> Self {
        MeshOptions { nodes_per_mm: None, up: None, fit: None, region: None, exaggerate: 1.0 }
    }
}

impl MeshOptions {
    /// The mesh options of a compilation: `--resolution` as nodes per mm,
    /// `--fit` onto `options.profile`'s surface, `--region`, `--up`, `--exaggerate`.
    pub fn from_compile(options: &CompileOptions) -> MeshOptions {
        let p = &options.profile;
        MeshOptions {
            nodes_per_mm: options.resolution_px_per_mm.map(f64::from),
            up: options.up,
            fit: options.fit.then_some([p.surface_w_mm as f64, p.surface_h_mm as f64]),
            region: options.region.clone(),
            exaggerate: options.exaggerate,
        }
    }
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
    /// Extent of the model along its X, Y and Z axes, metres.
    pub extent: [f64; 3],
    /// Page mm per model metre after `--fit` (1000 without it).
    pub mm_per_metre: f64,
    /// Projected edges left crossing after the arrangement (see `planar`).
    pub unresolved: usize,
    /// Primitives of points or lines left out.
    pub skipped: usize,
    /// The first of them: where, and its mode.
    pub first_skipped: Option<String>,
}

impl MeshReport {
    /// The other height axis, when the model's shape suggests it
    /// ([`suggested_up`]).
    pub fn suggested_up(&self, up: UpAxis) -> Option<UpAxis> {
        suggested_up(self.extent, up)
    }
}

/// The other height axis, when a model's extent along its X, Y and Z axes
/// suggests it: a model read with +Y up whose Z extent is under a quarter of
/// both its X and Y extents lies flat in X/Y, as a terrain exported Z-up
/// does (and the other way round).
pub fn suggested_up(extent: [f64; 3], up: UpAxis) -> Option<UpAxis> {
    let [x, y, z] = extent;
    match up {
        UpAxis::Y if z < 0.25 * x.min(y) => Some(UpAxis::Z),
        UpAxis::Z if y < 0.25 * x.min(z) => Some(UpAxis::Y),
        _ => None,
    }
}

/// The height axis of a model read without `--up`: +Z when the model is
/// clearly flat across Z (its Z extent under a quarter of both its X and Y
/// extents, as a terrain exported Z-up is), else glTF's +Y. A model flat
/// across Y stays +Y, and one flat across neither has no clear height axis,
/// so it keeps glTF's convention too. `extent` is along X, Y and Z.
pub fn chosen_up(extent: [f64; 3]) -> UpAxis {
    suggested_up(extent, UpAxis::Y).unwrap_or(UpAxis::Y)
}

/// What to say of a model whose extent suggests the other height axis
/// ([`suggested_up`]): the finding, and the flag that reads it so.
fn other_up(extent: [f64; 3], up: UpAxis) -> Option<(String, &'static str)> {
    let [x, y, z] = extent.map(|v| number(v, 3));
    let (flag, now, other) = match suggested_up(extent, up)? {
        UpAxis::Z => ("--up z", "+Y", "Z"),
        UpAxis::Y => ("--up y", "+Z", "Y"),
    };
    Some((
        format!(
            "the model spans {x} x {y} x {z} m along X, Y, Z: it lies flat across the {now} axis taken as up, as a \
             terrain exported {other}-up does"
        ),
        flag,
    ))
}

/// The note that the height axis was chosen from the model's shape (T0619).
fn up_note(extent: [f64; 3]) -> Diagnostic {
    let [x, y, z] = extent.map(|v| number(v, 3));
    Diagnostic::note(
        "T0619",
        format!(
            "the model spans {x} x {y} x {z} m along X, Y, Z: it is flat across Z, so +Z is taken as up (as a \
             terrain exported Z-up is), not glTF's +Y"
        ),
    )
    .with_help("build with --up y to read it with +Y up")
}

/// The triangles a height field is built from: the scene read with
/// `opts.up`, cut to `opts.region`, fitted and exaggerated, in page mm (the
/// exact reference `taxel report` measures fields against). Also returns the
/// page mm per model metre.
pub fn placed(bytes: &[u8], resolve: &mut Resolver<'_>, opts: &MeshOptions) -> Result<(load::Soup, f64), MeshError> {
    let mut soup = load::load_with(bytes, resolve, opts.up.unwrap_or(UpAxis::Y))?;
    if opts.up.is_none() && chosen_up(soup.extent) != soup.up {
        // Read again with the other axis: reading is a small part of a
        // build, and the placement below (`--region`, `--fit`) must see the
        // page as the chosen axis makes it.
        soup = load::load_with(bytes, resolve, chosen_up(soup.extent))?;
        soup.up_chosen = true;
    }
    let mm_per_metre = place::place(&mut soup, opts)?;
    // Placing works in f64 on coordinates up to `MAX_MODEL_MM`, so `--fit`
    // recentres a model at UTM coordinates; without it the model must lie
    // near the origin, as the surface stage and the stored f32 grid need.
    let far = |v: &[f64; 3]| v.iter().any(|c| c.abs() > load::MAX_COORD_MM);
    if soup.triangles.iter().flatten().any(|&i| soup.vertices.get(i as usize).is_some_and(far)) {
        let mut footprint = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
        let mut part = None;
        for p in &soup.parts {
            let b = p.bbox;
            footprint =
                [footprint[0].min(b[0]), footprint[1].min(b[1]), footprint[2].max(b[2]), footprint[3].max(b[3])];
            if part.is_none() && b.iter().any(|c| c.abs() > load::MAX_COORD_MM) {
                part =
                    Some(if p.node.is_empty() { format!("mesh '{}'", p.mesh) } else { format!("node '{}'", p.node) });
            }
        }
        return Err(MeshError::Far {
            part: part.unwrap_or_else(|| "the model".into()),
            footprint: footprint.map(|v| v / 1000.0),
            extent: soup.extent,
        });
    }
    Ok((soup, mm_per_metre))
}

/// Builds the height field of a glTF file (`.gltf` or `.glb` bytes).
pub fn height_field(
    bytes: &[u8],
    resolve: &mut Resolver<'_>,
    opts: &MeshOptions,
) -> Result<(HeightField, MeshReport), MeshError> {
    let (soup, mm_per_metre) = placed(bytes, resolve, opts)?;
    field_of(soup, mm_per_metre, opts)
}

/// The height field of placed triangles ([`placed`]).
fn field_of(soup: load::Soup, mm_per_metre: f64, opts: &MeshOptions) -> Result<(HeightField, MeshReport), MeshError> {
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
        extent: soup.extent,
        mm_per_metre,
        unresolved: surf.unresolved,
        skipped: soup.skipped,
        first_skipped: soup.first_skipped.map(|(at, mode)| format!("{at}, mode {mode}")),
    };
    Ok((hf, report))
}

/// Compiles a glTF height mesh into a bundle for a finger-family `profile`.
///
/// Problems in the file are error diagnostics, never panics.
pub fn compile_gltf(bytes: &[u8], resolve: &mut Resolver<'_>, profile: &DeviceProfile, opts: &MeshOptions) -> Compiled {
    let mut diagnostics = Vec::new();
    let refused = |diagnostics: Vec<Diagnostic>| Compiled {
        bundle: None,
        diagnostics,
        fonts_used: Vec::new(),
        print: None,
        key: Vec::new(),
    };
    if profile.family() != Family::Finger {
        diagnostics.push(not_finger(profile));
        return refused(diagnostics);
    }
    let (hf, report, read) = match placed(bytes, resolve, opts) {
        Err(e) => {
            let extent = if let MeshError::Far { extent, .. } = e { Some(extent) } else { None };
            // A model too far away is refused before its axis is chosen.
            let read = opts.up.unwrap_or_else(|| extent.map_or(UpAxis::Y, chosen_up));
            diagnostics.push(failure(e, extent, read));
            return refused(diagnostics);
        }
        Ok((soup, mm_per_metre)) => {
            let (extent, read, chosen) = (soup.extent, soup.up, soup.up_chosen);
            if chosen {
                diagnostics.push(up_note(extent));
            }
            match field_of(soup, mm_per_metre, opts) {
                Ok((hf, report)) => (hf, report, read),
                Err(e) => {
                    diagnostics.push(failure(e, Some(extent), read));
                    return refused(diagnostics);
                }
            }
        }
    };
    field_notes(&hf, &report, read, opts, profile, &mut diagnostics);
    let bundle = bundle_of(hf, &report, profile);
    // The writer validates its own output; a refusal here is reported, not hidden.
    if let Err(e) = bundle.to_bytes() {
        diagnostics.push(Diagnostic::error("T0613", format!("the height field cannot be stored: {e}")));
        return refused(diagnostics);
    }
    Compiled { bundle: Some(bundle), diagnostics, fonts_used: Vec::new(), print: None, key: Vec::new() }
}

/// The error that `profile` is not for a finger device (T0609).
fn not_finger(profile: &DeviceProfile) -> Diagnostic {
    Diagnostic::error(
        "T0609",
        format!(
            "profile '{}' is for a {} device; a height mesh needs a finger profile",
            profile.name,
            profile.family()
        ),
    )
    .with_help("build with --profile finger3 (or a profile file of family \"finger\")")
}

/// The error diagnostic of a mesh that failed with `e`, read with `read`
/// up. A model read with the wrong axis up (a terrain exported Z-up) is
/// seen edge on: when its `extent` suggests so, the help says which flag
/// reads it the other way.
fn failure(e: MeshError, extent: Option<[f64; 3]>, read: UpAxis) -> Diagnostic {
    let up = extent.and_then(|x| other_up(x, read));
    // The help, then the up-axis finding when there is one.
    let up_help = |help: &str| {
        let finding = up.as_ref().map(|(finding, flag)| format!("{finding}: build with {flag}"));
        [Some(help.to_string()).filter(|h| !h.is_empty()), finding].into_iter().flatten().collect::<Vec<_>>().join("; ")
    };
    let d = Diagnostic::error(e.code(), e.to_string());
    match &e {
        MeshError::Region(_) => d.with_help("a region is X,Y,W,H in model units along the page (x = X, y = Z, or -Y with --up z), or #name of a node or mesh"),
        MeshError::Far { .. } => d.with_help(up_help("build with --fit (and --region for a part) to recentre the model and scale it onto the surface")),
        MeshError::NoArea | MeshError::TooBig { .. } | MeshError::Triangulation(_) if up.is_some() => d.with_help(up_help("")),
        _ => d,
    }
}

/// The notes and warnings on a built height field `hf`, read with `read`
/// up, after what `report` measured: its size (T0610), the other height
/// axis (T0616), points and lines left out (T0618), crossings left
/// (T0617), walls (T0611), and a mesh beyond the surface of `profile`
/// (T0612).
fn field_notes(
    hf: &HeightField,
    report: &MeshReport,
    read: UpAxis,
    opts: &MeshOptions,
    profile: &DeviceProfile,
    diagnostics: &mut Vec<Diagnostic>,
) {
    let scale = if opts.fit.is_some() {
        format!("; fitted at {} mm per model metre", number(report.mm_per_metre, 3))
    } else {
        String::new()
    };
    diagnostics.push(Diagnostic::note(
        "T0610",
        format!(
            "height field of {} x {} nodes every {} mm over {} x {} mm from {} triangles ({} steps{scale})",
            hf.cols,
            hf.rows,
            number(report.cell, 3),
            number(report.bbox[2] - report.bbox[0], 3),
            number(report.bbox[3] - report.bbox[1], 3),
            report.triangles,
            report.steps
        ),
    ));
    if let Some((finding, flag)) = other_up(report.extent, read) {
        diagnostics.push(
            Diagnostic::note("T0616", finding)
                .with_help(format!("if the heights run along the other axis, build with {flag}")),
        );
    }
    if let Some(first) = report.first_skipped.as_ref().filter(|_| report.skipped > 0) {
        let n = report.skipped;
        diagnostics.push(
            Diagnostic::note(
                "T0618",
                format!(
                    "{n} {} of points or lines left out (the first: {first}): a relief is built from triangles",
                    if n == 1 { "primitive" } else { "primitives" }
                ),
            )
            .with_help("loose edges and points have no area to feel; draw them as thin faces if they matter"),
        );
    }
    if report.unresolved > 0 {
        diagnostics.push(Diagnostic::warning(
            "T0617",
            format!(
                "{} projected edges still cross others after the arrangement's rounding; the surface may be \
                 off near them by one triangulation face",
                report.unresolved
            ),
        ));
    }
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
    // A fitted model lies on the surface by construction (up to rounding).
    if opts.fit.is_none() && x0 < 0.0
        || y0 < 0.0
        || x1 > profile.surface_w_mm as f64
        || y1 > profile.surface_h_mm as f64
    {
        diagnostics.push(
            Diagnostic::warning(
                "T0612",
                format!(
                    "the mesh covers x {x0:.3}..{x1:.3} mm, y {y0:.3}..{y1:.3} mm, beyond the {} x {} mm surface of '{}'",
                    profile.surface_w_mm, profile.surface_h_mm, profile.name
                ),
            )
            .with_help("build with --fit to scale and centre the model onto the surface (glTF metres are page millimetres without it)"),
        );
    }
}

/// The bundle of height field `hf` for `profile`: the field stored as the
/// device needs it, and one provenance entry naming the scene and its meshes.
fn bundle_of(hf: HeightField, report: &MeshReport, profile: &DeviceProfile) -> Bundle {
    let mut bundle = Bundle::new(Manifest::new(*profile));
    // Stored as the device needs it: quantised heights in tiles (store.rs).
    bundle.chunks.push(Chunk::Height(store::tiled(hf, profile)));
    // Each mesh named once, in the file's order (many nodes may place one mesh).
    let mut seen = std::collections::HashSet::new();
    let names: Vec<&str> =
        report.mesh_names.iter().map(String::as_str).filter(|s| !s.is_empty() && seen.insert(*s)).collect();
    bundle.chunks.push(Chunk::Provenance(Provenance {
        entries: vec![ProvenanceEntry {
            id: report.scene_name.clone().unwrap_or_else(|| "scene".into()),
            label: names.join(", "),
            line: 0,
        }],
    }));
    bundle
}
