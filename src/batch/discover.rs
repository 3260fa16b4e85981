//! Finding the inputs of a batch: files named on the command line, and the
//! drawings and meshes (`.svg`, `.gltf`, `.glb`) in folders, recursively.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use walkdir::WalkDir;

/// The extensions found in folders (compared without regard to case).
pub const EXTENSIONS: [&str; 3] = ["svg", "gltf", "glb"];

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

/// The inputs named by `args`, in argument order and, within a folder, in
/// file-name order; each file once however often it is named. A path that
/// does not exist is an error (a usage mistake, before anything is built);
/// a folder entry that cannot be read is returned as a problem to report.
pub fn discover(args: &[PathBuf]) -> Result<(Vec<Input>, Vec<String>)> {
    let mut inputs = Vec::new();
    let mut problems = Vec::new();
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
    Ok((inputs, problems))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walks_folders_for_drawings_and_meshes_only() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        for f in ["a.svg", "sub/b.SVG", "sub/deeper/c.gltf", "d.glb", "notes.txt", "e.taxel", ".hidden/f.svg"] {
            let p = d.join(f);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, "x").unwrap();
        }
        let (inputs, problems) = discover(&[d.to_path_buf(), d.join("a.svg")]).unwrap();
        assert!(problems.is_empty());
        let keys: Vec<String> = inputs.iter().map(Input::key).collect();
        assert_eq!(keys, ["a.svg", "d.glb", "sub/b.SVG", "sub/deeper/c.gltf"]);
    }

    #[test]
    fn a_missing_path_is_an_error_naming_it() {
        let err = discover(&[PathBuf::from("/no/such/place.svg")]).unwrap_err();
        assert!(err.to_string().contains("/no/such/place.svg"));
    }
}
