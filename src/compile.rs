//! Compiling one input file, whatever its kind: the CLI's single entry into
//! the compiler, used by `build`, `check`, `preview`, `report` and the demo.

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};
use std::sync::{Arc, Mutex};

use anyhow::{Context, Result, bail};
use taxel_compiler::{CompileOptions, Compiled, Diagnostic, StyleSheet, fontdb};
use taxel_format::{DeviceProfile, profiles};

use crate::cli::CompileOpts;

/// The profile `--profile` names: a built-in name or a TOML file (default `stress2`).
pub fn resolve_profile(name: Option<&str>) -> Result<DeviceProfile> {
    let name = name.unwrap_or("stress2");
    if let Some(p) = profiles::builtin(name) {
        return Ok(p);
    }
    let path = Path::new(name);
    if path.is_file() {
        let text = std::fs::read_to_string(path).with_context(|| format!("reading profile {name}"))?;
        return Ok(profiles::parse(&text, name)?);
    }
    bail!("--profile {name}: not a built-in profile ({}) nor a profile file", profiles::builtin_names().join(", "))
}

/// The fonts text is laid out with: those under `--fonts DIR`, or the
/// system's. Each database is loaded once per process and shared.
pub fn font_database(dir: Option<&Path>) -> Result<Arc<fontdb::Database>> {
    static LOADED: Mutex<Option<HashMap<Option<PathBuf>, Arc<fontdb::Database>>>> = Mutex::new(None);
    if let Some(d) = dir
        && !d.is_dir()
    {
        bail!("--fonts {}: not a folder", d.display());
    }
    let mut loaded = LOADED.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let map = loaded.get_or_insert_with(HashMap::new);
    let key = dir.map(Path::to_path_buf);
    if let Some(db) = map.get(&key) {
        return Ok(db.clone());
    }
    let mut db = fontdb::Database::new();
    match dir {
        Some(d) => db.load_fonts_dir(d),
        None => db.load_system_fonts(),
    }
    let db = Arc::new(db);
    map.insert(key, db.clone());
    Ok(db)
}

/// The compiler options for `opts`, or the diagnostic that says why the style
/// sheet cannot be used (an input problem, reported like the drawing's own).
pub fn compile_options(opts: &CompileOpts) -> Result<Result<CompileOptions, Diagnostic>> {
    let profile = resolve_profile(opts.profile.as_deref())?;
    let style = match &opts.style {
        None => None,
        Some(_) if opts.style_is_auto() => None,
        Some(path) => {
            let text =
                std::fs::read_to_string(path).with_context(|| format!("reading style sheet {}", path.display()))?;
            match StyleSheet::parse(&text, &path.display().to_string()) {
                Ok(s) => Some(s),
                Err(e) => {
                    return Ok(Err(Diagnostic::error("T0110", format!("the style sheet is malformed: {e}"))
                        .with_help("see docs/annotations.md, \"Style sheets\"")));
                }
            }
        }
    };
    Ok(Ok(CompileOptions {
        profile,
        style,
        resolution_px_per_mm: opts.resolution,
        width_mm: opts.width_mm,
        content_hash: [0; 32],
        fit: opts.fit,
        region: opts.region.clone(),
        up: match opts.up {
            crate::cli::Up::Y => taxel_compiler::UpAxis::Y,
            crate::cli::Up::Z => taxel_compiler::UpAxis::Z,
        },
        exaggerate: opts.exaggerate.unwrap_or(1.0),
        fonts: Some(font_database(opts.fonts.as_deref())?),
        auto: opts.style_is_auto(),
    }))
}

/// Reads and compiles one input (.svg, .gltf, .glb). IO failures are `Err`;
/// problems in the input are diagnostics in the result.
pub fn compile_file(path: &Path, opts: &CompileOpts) -> Result<Compiled> {
    check_input_size(path)?;
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).unwrap_or_default();
    match ext.as_str() {
        "svg" => compile_drawing(path, opts),
        "gltf" | "glb" => compile_mesh(path, opts),
        _ => bail!("{}: unknown input kind, expected .svg, .gltf or .glb", path.display()),
    }
}

/// An annotated SVG drawing (docs/annotations.md).
fn compile_drawing(path: &Path, opts: &CompileOpts) -> Result<Compiled> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    let options = match compile_options(opts)? {
        Ok(o) => o,
        Err(d) => return Ok(Compiled { bundle: None, diagnostics: vec![d] }),
    };
    let Ok(text) = String::from_utf8(bytes) else {
        let d = Diagnostic::error("T0200", "the file is not UTF-8 text, expected an SVG document")
            .with_help("compressed .svgz files must be unpacked first");
        return Ok(Compiled { bundle: None, diagnostics: vec![d] });
    };
    Ok(taxel_compiler::svg::compile_svg(&text, &options))
}

/// A glTF height mesh for the finger device (docs/finger.md). Without
/// `--profile` the built-in `finger3` is used: a mesh only plays on a finger device.
fn compile_mesh(path: &Path, opts: &CompileOpts) -> Result<Compiled> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    let profile = load_profile(opts.profile.as_deref().unwrap_or("finger3"))?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut resolve = |uri: &str| read_beside(&dir, uri);
    let mesh_opts = mesh_options(opts, &profile);
    Ok(taxel_compiler::mesh::compile_gltf(&bytes, &mut resolve, &profile, &mesh_opts))
}

/// The mesh compiler's options for `opts` on `profile` (`--fit` fits onto its surface).
pub fn mesh_options(opts: &CompileOpts, profile: &DeviceProfile) -> taxel_compiler::mesh::MeshOptions {
    taxel_compiler::mesh::MeshOptions {
        nodes_per_mm: opts.resolution.map(f64::from),
        up: match opts.up {
            crate::cli::Up::Y => taxel_compiler::UpAxis::Y,
            crate::cli::Up::Z => taxel_compiler::UpAxis::Z,
        },
        fit: opts.fit.then_some([profile.surface_w_mm as f64, profile.surface_h_mm as f64]),
        region: opts.region.clone(),
        exaggerate: opts.exaggerate.unwrap_or(1.0),
    }
}

fn load_profile(spec: &str) -> Result<taxel_format::DeviceProfile> {
    if let Some(p) = taxel_format::profiles::builtin(spec) {
        return Ok(p);
    }
    let text = std::fs::read_to_string(spec)
        .with_context(|| format!("'{spec}' is neither a built-in profile nor a readable profile file"))?;
    taxel_format::profiles::parse(&text, spec).map_err(|e| anyhow::anyhow!("{e}"))
}

/// Reads an external buffer named by a relative URI, only from the glTF's
/// own folder or below it: absolute paths, `..`, and URI schemes are refused.
fn read_beside(dir: &Path, uri: &str) -> Result<Vec<u8>, String> {
    let rel = percent_decode(uri).ok_or_else(|| format!("buffer URI '{uri}' is not valid percent-encoded UTF-8"))?;
    if rel.contains(':') || rel.contains('\\') {
        return Err(format!("buffer URI '{uri}' is not a relative path (schemes and drive letters are refused)"));
    }
    let rel_path = PathBuf::from(&rel);
    if rel_path.components().any(|c| !matches!(c, Component::Normal(_) | Component::CurDir)) {
        return Err(format!("buffer URI '{uri}' leaves the glTF file's folder"));
    }
    let full = dir.join(&rel_path);
    check_input_size(&full).map_err(|e| e.to_string())?;
    // Symbolic links may still point elsewhere: compare the real paths.
    let real_dir = dir.canonicalize().unwrap_or_else(|_| dir.to_path_buf());
    let real = full.canonicalize().map_err(|e| format!("cannot read buffer '{}': {e}", full.display()))?;
    if !real.starts_with(&real_dir) {
        return Err(format!("buffer '{}' lies outside the glTF file's folder", full.display()));
    }
    std::fs::read(&real).map_err(|e| format!("cannot read buffer '{}': {e}", full.display()))
}

fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = s.get(i + 1..i + 3)?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// Largest input file taxel reads, in bytes (docs/stability.md): far above
/// any drawing a person makes, far below what would exhaust memory once
/// usvg's tree and the masks are built from it.
pub const MAX_INPUT_BYTES: u64 = 64 << 20;

/// Refuses an input larger than [`MAX_INPUT_BYTES`] before reading it.
pub fn check_input_size(path: &Path) -> Result<()> {
    let len = std::fs::metadata(path).map_err(|e| anyhow::anyhow!("cannot read {}: {e}", path.display()))?.len();
    if len > MAX_INPUT_BYTES {
        anyhow::bail!(
            "{}: the file is {:.1} MB, larger than the {} MB input limit; split the drawing or remove embedded images",
            path.display(),
            len as f64 / (1 << 20) as f64,
            MAX_INPUT_BYTES >> 20
        );
    }
    Ok(())
}
