//! Finding the inputs of a batch: files named on the command line, and the
//! drawings and meshes (`.svg`, `.svgz`, `.gltf`, `.glb`, in any case) in
//! folders, recursively.

use std::collections::{BTreeMap, HashSet};
use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use walkdir::WalkDir;

/// The extensions found in folders (compared without regard to case).
pub const EXTENSIONS: [&str; 4] = ["svg", "svgz", "gltf", "glb"];

/// One input of a batch.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Input {
    /// The file.
    pub path: PathBuf,
    /// Its path relative to the folder it was found in, or its file name
    /// when it was named directly: where its bundle goes under `-o DIR`, and
    /// its shard key.
    pub rel: PathBuf,
}

impl Input {
    /// The relative path with `/` separators, the same on every platform.
    pub fn key(&self) -> String {
        self.rel.components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/")
    }
}

/// Whether a file found in a folder is an input.
pub fn is_input(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| EXTENSIONS.iter().any(|x| x.eq_ignore_ascii_case(e)))
}

/// What a walk over the arguments found.
#[derive(Debug, Default)]
pub struct Discovered {
    /// The inputs, as [`discover`] returns them.
    pub inputs: Vec<Input>,
    /// Folder entries that cannot be read.
    pub problems: Vec<String>,
    /// Files in the folders that are not inputs, counted by extension
    /// (lower case, `""` for none), so a build can say what it did not build
    /// (a teacher's folder holds PDFs and PNGs beside the drawings).
    pub others: BTreeMap<String, usize>,
}

impl Discovered {
    /// One line naming the files in folders that were not built, or `None`.
    pub fn others_line(&self) -> Option<String> {
        let total: usize = self.others.values().sum();
        if total == 0 {
            return None;
        }
        let mut by: Vec<(&String, &usize)> = self.others.iter().collect();
        by.sort_by(|a, b| b.1.cmp(a.1).then(a.0.cmp(b.0)));
        let mut kinds: Vec<String> = by
            .iter()
            .take(4)
            .map(|(e, n)| if e.is_empty() { format!("{n} without extension") } else { format!("{n} .{e}") })
            .collect();
        if by.len() > 4 {
            kinds.push(format!("{} of other kinds", by[4..].iter().map(|(_, n)| **n).sum::<usize>()));
        }
        // What to do with each kind found, once per kind of advice.
        let mut advice: Vec<&str> = Vec::new();
        for (e, _) in &by {
            let a = convert_hint(e).unwrap_or(OTHER_DRAWINGS);
            if !advice.contains(&a) {
                advice.push(a);
            }
        }
        Some(format!(
            "note: {total} other file(s) in the folders are not drawings and were not built ({}); taxel builds .svg, .svgz, .gltf and .glb: {}",
            kinds.join(", "),
            advice.join("; ")
        ))
    }
}

/// Advice for files of kinds taxel does not read.
const OTHER_DRAWINGS: &str = "save other drawings as SVG";
const MESHES: &str = "export 3D models from Blender as glTF 2.0 (File > Import, then File > Export > glTF 2.0 .glb) and build them with --fit";
const PICTURES: &str = "trace pictures to paths and save them as SVG (Inkscape: Path > Trace Bitmap)";
const DOCUMENTS: &str = "open PDF, EPS, AI and other vector files in Inkscape and save them as SVG";

/// What to do with a file of extension `ext` (lower case) that taxel does
/// not read, when it is a known kind: a 3D model, a picture or a vector
/// document.
pub fn convert_hint(ext: &str) -> Option<&'static str> {
    match ext {
        "stl" | "obj" | "fbx" | "ply" | "dae" | "3ds" | "3mf" | "blend" | "usd" | "usda" | "usdc" | "usdz" | "x3d"
        | "wrl" | "off" | "step" | "stp" => Some(MESHES),
        "png" | "jpg" | "jpeg" | "gif" | "bmp" | "tif" | "tiff" | "webp" | "heic" => Some(PICTURES),
        "pdf" | "eps" | "ps" | "ai" | "emf" | "wmf" | "cdr" | "odg" | "vsd" | "vsdx" | "dxf" => Some(DOCUMENTS),
        _ => None,
    }
}

/// The inputs named by `args`, in argument order and, within a folder, in
/// file-name order; each file once however often it is named. A path that
/// does not exist is an error (a usage mistake, before anything is built);
/// a folder entry that cannot be read is returned as a problem to report.
pub fn discover(args: &[PathBuf]) -> Result<(Vec<Input>, Vec<String>)> {
    let d = discover_all(args)?;
    Ok((d.inputs, d.problems))
}

/// [`discover`], with the other files found in the folders counted.
pub fn discover_all(args: &[PathBuf]) -> Result<Discovered> {
    let mut inputs = Vec::new();
    let mut problems = Vec::new();
    let mut others: BTreeMap<String, usize> = BTreeMap::new();
    let mut seen = HashSet::new();
    let mut push = |path: PathBuf, rel: PathBuf, inputs: &mut Vec<Input>| {
        let id = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
        if seen.insert(id) {
            inputs.push(Input { path, rel });
        }
    };
    for arg in args {
        let meta = match std::fs::metadata(arg) {
            Ok(m) => m,
            Err(e) => bail!("{}: {e}", arg.display()),
        };
        if meta.is_file() {
            let Some(name) = arg.file_name() else { bail!("{}: not a file name", arg.display()) };
            push(arg.clone(), PathBuf::from(name), &mut inputs);
            continue;
        }
        // Hidden folders (.git, .cache) are not walked; symbolic links are
        // not followed, so a link cycle cannot make the walk endless.
        let walk = WalkDir::new(arg)
            .sort_by_file_name()
            .into_iter()
            .filter_entry(|e| e.depth() == 0 || !e.file_name().to_string_lossy().starts_with('.'));
        for entry in walk {
            match entry {
                Ok(e) if e.file_type().is_file() && is_input(e.path()) => {
                    let rel = e.path().strip_prefix(arg).unwrap_or(e.path()).to_path_buf();
                    push(e.path().to_path_buf(), rel, &mut inputs);
                }
                Ok(e) if e.file_type().is_file() => {
                    let ext =
                        e.path().extension().map(|x| x.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
                    *others.entry(ext).or_default() += 1;
                }
                Ok(_) => {}
                Err(e) => {
                    let at = e.path().map_or_else(|| arg.display().to_string(), |p| p.display().to_string());
                    problems.push(format!(
                        "{at}: cannot read: {}",
                        e.io_error().map_or_else(|| e.to_string(), |io| io.to_string())
                    ));
                }
            }
        }
    }
    Ok(Discovered { inputs, problems, others })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walks_folders_for_drawings_and_meshes_only() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        for f in ["a.svg", "sub/b.SVG", "sub/deeper/c.gltf", "d.glb", "notes.txt", "e.taxel", ".hidden/f.svg", "g.SVGZ"]
        {
            let p = d.join(f);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, "x").unwrap();
        }
        let (inputs, problems) = discover(&[d.to_path_buf(), d.join("a.svg")]).unwrap();
        assert!(problems.is_empty());
        let keys: Vec<String> = inputs.iter().map(Input::key).collect();
        assert_eq!(keys, ["a.svg", "d.glb", "g.SVGZ", "sub/b.SVG", "sub/deeper/c.gltf"]);
        // The files that are not inputs are counted, not silently passed over (hidden folders are not walked).
        let found = discover_all(&[d.to_path_buf()]).unwrap();
        let others: Vec<(&str, usize)> = found.others.iter().map(|(e, n)| (e.as_str(), *n)).collect();
        assert_eq!(others, [("taxel", 1), ("txt", 1)]);
        let line = found.others_line().unwrap();
        assert!(line.contains("2 other file(s)") && line.contains("1 .taxel, 1 .txt"), "{line}");
    }

    #[test]
    fn a_missing_path_is_an_error_naming_it() {
        let err = discover(&[PathBuf::from("/no/such/place.svg")]).unwrap_err();
        assert!(err.to_string().contains("/no/such/place.svg"));
    }
}
