//! Compiling one input file, whatever its kind: the CLI's single entry into
//! the compiler, used by `build`, `check`, `preview`, `report` and the demo.

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use anyhow::{Result, bail};
use percent_encoding::percent_decode_str;
use taxel_compiler::{CompileOptions, Compiled, Diagnostic, fontdb};
use taxel_format::DeviceProfile;

use crate::cli::CompileOpts;
use crate::io::{self, load};

/// The fonts text is laid out with: those under `--fonts DIR`, or the
/// system's. Each database is loaded once per process and shared.
pub fn font_database(dir: Option<&Path>) -> Result<Arc<fontdb::Database>> {
    static LOADED: Mutex<Option<HashMap<Option<PathBuf>, Arc<fontdb::Database>>>> = Mutex::new(None);
    fonts_dir(dir)?;
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

/// Starts loading the fonts a drawing at `path` will be laid out with into
/// [`font_database`]'s cache, on a thread of its own, once per process, so
/// that they are loaded while the input is read and parsed (the compiler
/// asks for them when usvg lays the text out; until then it does not wait).
/// Nothing for other inputs; a failure is left for the build to report.
pub fn warm_up_fonts(path: &Path, opts: &CompileOpts) {
    static STARTED: AtomicBool = AtomicBool::new(false);
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).unwrap_or_default();
    if matches!(ext.as_str(), "svg" | "svgz") && !STARTED.swap(true, Ordering::Relaxed) {
        let dir = opts.fonts.clone();
        std::thread::spawn(move || font_database(dir.as_deref()).is_ok());
    }
}

/// Checks that `--fonts DIR` names a folder.
fn fonts_dir(dir: Option<&Path>) -> Result<()> {
    if let Some(d) = dir
        && !d.is_dir()
    {
        bail!("--fonts {}: not a folder", d.display());
    }
    Ok(())
}

/// The reader's languages: `--lang`, else the system's (the first of
/// `LC_ALL`, `LC_MESSAGES` and `LANG` that is set), else English.
pub fn languages(opts: &CompileOpts) -> Vec<String> {
    if let Some(tags) = &opts.lang {
        return tags.split(',').map(String::from).collect();
    }
    let locale = ["LC_ALL", "LC_MESSAGES", "LANG"].iter().find_map(|v| std::env::var(v).ok().filter(|l| !l.is_empty()));
    locale.as_deref().map_or_else(|| vec!["en".to_string()], locale_languages)
}

/// The language tags of a POSIX locale name: `fr_CA.UTF-8@euro` gives
/// `fr-CA` and `fr`; `C`, `POSIX` and names that are no language give `en`.
fn locale_languages(locale: &str) -> Vec<String> {
    let name = locale.split(['.', '@']).next().unwrap_or("");
    let (lang, region) = name.split_once('_').unwrap_or((name, ""));
    let letters = |s: &str, n: std::ops::RangeInclusive<usize>| {
        n.contains(&s.len()) && s.chars().all(|c| c.is_ascii_alphabetic())
    };
    if !letters(lang, 2..=3) || lang.eq_ignore_ascii_case("c") {
        return vec!["en".to_string()];
    }
    let lang = lang.to_ascii_lowercase();
    match region {
        r if letters(r, 2..=3) => vec![format!("{lang}-{}", r.to_ascii_uppercase()), lang],
        _ => vec![lang],
    }
}

/// The compiler options for `opts`, or the diagnostic that says why the style
/// sheet cannot be used (an input problem, reported like the drawing's own).
pub fn compile_options(opts: &CompileOpts) -> Result<Result<CompileOptions, Diagnostic>> {
    options_with_fonts(opts, true)
}

/// [`compile_options`]; without `fonts` the options hold none, and
/// `--fonts DIR` is only checked (the caller gives them to the compiler late).
fn options_with_fonts(opts: &CompileOpts, fonts: bool) -> Result<Result<CompileOptions, Diagnostic>> {
    let profile = load::profile(opts.profile.as_deref().unwrap_or(load::DEFAULT_DRAWING_PROFILE))?;
    let style = match &opts.style {
        None => None,
        Some(_) if opts.style_is_auto() => None,
        Some(path) => match load::style_sheet(path)? {
            Ok(s) => Some(s),
            Err(d) => return Ok(Err(d)),
        },
    };
    Ok(Ok(CompileOptions {
        profile,
        style,
        resolution_px_per_mm: opts.resolution,
        width_mm: opts.width_mm,
        content_hash: [0; 32],
        fit: opts.fit,
        region: opts.region.clone(),
        up: up_axis(opts.up),
        exaggerate: opts.exaggerate.unwrap_or(1.0),
        fonts: match fonts {
            true => Some(font_database(opts.fonts.as_deref())?),
            false => {
                fonts_dir(opts.fonts.as_deref())?;
                None
            }
        },
        auto: opts.style_is_auto(),
        languages: languages(opts),
        braille: braille(),
        memory: match opts.max_memory.unwrap_or(crate::cli::DEFAULT_MAX_MEMORY) {
            usize::MAX => None,
            limit => Some(taxel_compiler::budget::MemoryBudget { in_use: crate::held, limit }),
        },
        flattening: taxel_compiler::geometry::Flattening::DEFAULT,
    }))
}

/// The braille service, made once per process: liblouis when the system
/// has it, under its usual names or the library `TAXEL_LIBLOUIS` names
/// (a file name or path); `TAXEL_LIBLOUIS=none` keeps the built-in
/// uncontracted UEB alone. Without liblouis the built-in table is used and
/// each compilation notes it (T0307), saying how to install liblouis.
pub fn braille() -> std::sync::Arc<taxel_braille::Braille> {
    static BRAILLE: std::sync::OnceLock<std::sync::Arc<taxel_braille::Braille>> = std::sync::OnceLock::new();
    BRAILLE
        .get_or_init(|| {
            std::sync::Arc::new(match std::env::var("TAXEL_LIBLOUIS").ok().filter(|v| !v.is_empty()).as_deref() {
                Some("none") => taxel_braille::Braille::builtin(),
                name => taxel_braille::Braille::load(name),
            })
        })
        .clone()
}

/// Reads and compiles one input (.svg, .gltf, .glb). IO failures are `Err`;
/// problems in the input are diagnostics in the result.
pub fn compile_file(path: &Path, opts: &CompileOpts) -> Result<Compiled> {
    warm_up_fonts(path, opts);
    compile_bytes(path, io::read_input(path)?, opts)
}

/// [`compile_file`] of an input already read (`bytes`, through
/// [`io::read_input`]): the batch builder reads each input once, for its
/// content hash and its compilation.
pub fn compile_bytes(path: &Path, bytes: Vec<u8>, opts: &CompileOpts) -> Result<Compiled> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).unwrap_or_default();
    match ext.as_str() {
        "svg" | "svgz" => compile_drawing(path, bytes, opts),
        "gltf" | "glb" => compile_mesh(path, &bytes, opts),
        _ => match crate::batch::discover::convert_hint(&ext) {
            Some(hint) => {
                bail!("{}: taxel does not read .{ext} files, only .svg, .svgz, .gltf and .glb: {hint}", path.display())
            }
            None => bail!("{}: unknown input kind, expected .svg, .svgz, .gltf or .glb", path.display()),
        },
    }
}

/// An annotated SVG drawing (docs/annotations.md).
fn compile_drawing(path: &Path, bytes: Vec<u8>, opts: &CompileOpts) -> Result<Compiled> {
    // The fonts are given to the compiler late: it asks for them once the
    // XML is parsed, and they may be loading on another thread meanwhile
    // ([`warm_up_fonts`]).
    let options = match options_with_fonts(opts, false)? {
        Ok(o) => o,
        Err(d) => {
            return Ok(stopped(d));
        }
    };
    // A compressed drawing is unpacked (within the input limit); what is
    // neither SVG text nor gzip is a problem of the input, said like the others.
    let text = match io::drawing_text(path, bytes) {
        Ok(t) => t,
        Err(e) => {
            let shown = path.display().to_string();
            let why = format!("{e:#}");
            let why = why.strip_prefix(&format!("{shown}: ")).unwrap_or(&why).to_string();
            let d = Diagnostic::error("T0200", why);
            return Ok(stopped(d));
        }
    };
    let fonts = || font_database(opts.fonts.as_deref()).ok();
    Ok(taxel_compiler::compile_svg_with_fonts(&text, &options, &fonts))
}

/// A glTF height mesh for the finger device (docs/finger.md). Without
/// `--profile` the built-in `finger3` is used: a mesh only plays on a finger device.
fn compile_mesh(path: &Path, bytes: &[u8], opts: &CompileOpts) -> Result<Compiled> {
    let profile = load::profile(opts.profile.as_deref().unwrap_or(load::DEFAULT_MESH_PROFILE))?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut resolve = |uri: &str| read_beside(&dir, uri);
    let mesh_opts = mesh_options(opts, &profile);
    Ok(taxel_compiler::mesh::compile_gltf(bytes, &mut resolve, &profile, &mesh_opts))
}

/// The compiler's up axis for `--up` (`None`: chosen from the model).
fn up_axis(up: Option<crate::cli::Up>) -> Option<taxel_compiler::UpAxis> {
    up.map(|u| match u {
        crate::cli::Up::Y => taxel_compiler::UpAxis::Y,
        crate::cli::Up::Z => taxel_compiler::UpAxis::Z,
    })
}

/// The mesh compiler's options for `opts` on `profile` (`--fit` fits onto its surface).
pub fn mesh_options(opts: &CompileOpts, profile: &DeviceProfile) -> taxel_compiler::mesh::MeshOptions {
    taxel_compiler::mesh::MeshOptions {
        nodes_per_mm: opts.resolution.map(f64::from),
        up: up_axis(opts.up),
        fit: opts.fit.then_some([profile.surface_w_mm as f64, profile.surface_h_mm as f64]),
        region: opts.region.clone(),
        exaggerate: opts.exaggerate.unwrap_or(1.0),
    }
}

/// Reads an external buffer named by a relative URI, only from the glTF's
/// own folder or below it: absolute paths, `..`, and URI schemes are refused.
fn read_beside(dir: &Path, uri: &str) -> Result<Vec<u8>, String> {
    let rel = percent_decode_str(uri)
        .decode_utf8()
        .map_err(|_| format!("buffer URI '{uri}' is not valid percent-encoded UTF-8"))?;
    if rel.contains(':') || rel.contains('\\') {
        return Err(format!("buffer URI '{uri}' is not a relative path (schemes and drive letters are refused)"));
    }
    let rel_path = PathBuf::from(&*rel);
    if rel_path.components().any(|c| !matches!(c, Component::Normal(_) | Component::CurDir)) {
        return Err(format!("buffer URI '{uri}' leaves the glTF file's folder"));
    }
    let full = dir.join(&rel_path);
    // Symbolic links may still point elsewhere: compare the real paths.
    let real_dir = dir.canonicalize().unwrap_or_else(|_| dir.to_path_buf());
    let real = full.canonicalize().map_err(|e| format!("cannot read buffer '{}': {e}", full.display()))?;
    if !real.starts_with(&real_dir) {
        return Err(format!("buffer '{}' lies outside the glTF file's folder", full.display()));
    }
    io::read_input(&real).map_err(|e| format!("buffer '{}': {e:#}", full.display()))
}

/// A compilation stopped by one diagnostic before the compiler ran (the
/// options or the input's text were refused): nothing made but what it says.
fn stopped(d: Diagnostic) -> Compiled {
    Compiled { bundle: None, diagnostics: vec![d], fonts_used: Vec::new(), print: None, key: Vec::new() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_locale_gives_its_language_and_region_as_tags() {
        let tags = |l: &str| locale_languages(l);
        assert_eq!(tags("fr_CA.UTF-8"), ["fr-CA", "fr"]);
        assert_eq!(tags("de_DE.UTF-8@euro"), ["de-DE", "de"]);
        assert_eq!(tags("pt_BR"), ["pt-BR", "pt"]);
        assert_eq!(tags("es"), ["es"]);
        assert_eq!(tags("ast_ES.UTF-8"), ["ast-ES", "ast"]);
        for none in ["C", "C.UTF-8", "POSIX", "", "en_US.UTF-8"] {
            assert_eq!(
                tags(none)[..],
                *if none.starts_with("en") { &["en-US", "en"][..] } else { &["en"][..] },
                "{none}"
            );
        }
        // `--lang` wins over the system's.
        let opts = CompileOpts { lang: Some("nl-BE,nl".into()), ..CompileOpts::default() };
        assert_eq!(languages(&opts), ["nl-BE", "nl"]);
    }
}
