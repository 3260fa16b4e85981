//! Atomic writes with one permission policy.

use std::fmt;
use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// Mode of every file taxel writes (Unix): read-write for the owner,
/// readable by others, like a file saved by any program. Temporary files are
/// created private (0600), so the mode is set before the rename.
pub const FILE_MODE: u32 = 0o644;
/// Mode of every folder taxel writes (Unix).
pub const DIR_MODE: u32 = 0o755;

/// A file-system failure, naming the path and what was being done.
#[derive(Debug)]
pub struct IoError {
    /// The file or folder.
    pub path: PathBuf,
    /// What failed, e.g. "cannot write".
    pub what: &'static str,
    /// The system's reason.
    pub source: io::Error,
}

impl IoError {
    fn new<'a>(path: &'a Path, what: &'static str) -> impl FnOnce(io::Error) -> IoError + 'a {
        move |source| IoError { path: path.to_path_buf(), what, source }
    }
}

impl fmt::Display for IoError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {}: {}", self.what, self.path.display(), self.source)
    }
}

impl std::error::Error for IoError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.source)
    }
}

/// The folder a file at `path` goes into ("." for a bare name).
fn parent_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

fn set_mode(file: &File, mode: u32) -> io::Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        file.set_permissions(fs::Permissions::from_mode(mode))?;
    }
    #[cfg(not(unix))]
    let _ = (file, mode);
    Ok(())
}

fn set_dir_mode(dir: &Path) -> io::Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        fs::set_permissions(dir, fs::Permissions::from_mode(DIR_MODE))?;
    }
    #[cfg(not(unix))]
    let _ = dir;
    Ok(())
}

/// Writes `bytes` to `path` atomically, creating its folder if needed.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    write_with(path, |w| w.write_all(bytes))
}

/// Writes `path` atomically from what `fill` writes into a buffered writer
/// (which can also seek, for formats such as WAV that patch their header).
/// When `fill` fails nothing is left behind: the temporary file is removed
/// and an existing `path` is untouched.
pub fn write_with<T>(path: &Path, fill: impl FnOnce(&mut BufWriter<&mut File>) -> io::Result<T>) -> Result<T, IoError> {
    let dir = parent_of(path);
    fs::create_dir_all(dir).map_err(IoError::new(dir, "cannot create the folder"))?;
    let mut tmp = tempfile::Builder::new()
        .prefix(".taxel-")
        .suffix(".part")
        .tempfile_in(dir)
        .map_err(IoError::new(dir, "cannot create a temporary file in"))?;
    let value = {
        let mut w = BufWriter::new(tmp.as_file_mut());
        let value = fill(&mut w).map_err(IoError::new(path, "cannot write"))?;
        w.flush().map_err(IoError::new(path, "cannot write"))?;
        value
    };
    // Without the flush to disk a crash soon after the rename could leave an
    // empty file under the final name on some file systems.
    tmp.as_file().sync_all().map_err(IoError::new(path, "cannot write"))?;
    set_mode(tmp.as_file(), FILE_MODE).map_err(IoError::new(path, "cannot set the permissions of"))?;
    tmp.persist(path).map_err(|e| IoError { path: path.to_path_buf(), what: "cannot rename into", source: e.error })?;
    Ok(value)
}

/// Replaces the folder `dir` with one holding exactly `files` (names
/// relative to `dir`, no sub-folders): the new folder is written beside it
/// and swapped in, so a failure leaves the old folder as it was. Whether
/// `dir` may be replaced is the caller's decision.
pub fn write_folder(dir: &Path, files: &[(String, Vec<u8>)]) -> Result<(), IoError> {
    let parent = parent_of(dir);
    fs::create_dir_all(parent).map_err(IoError::new(parent, "cannot create the folder"))?;
    let fresh = tempfile::Builder::new()
        .prefix(".taxel-")
        .tempdir_in(parent)
        .map_err(IoError::new(parent, "cannot create a temporary folder in"))?;
    for (name, data) in files {
        let target = dir.join(name);
        let mut file = File::create(fresh.path().join(name)).map_err(IoError::new(&target, "cannot write"))?;
        file.write_all(data).and_then(|()| file.sync_all()).map_err(IoError::new(&target, "cannot write"))?;
        set_mode(&file, FILE_MODE).map_err(IoError::new(&target, "cannot set the permissions of"))?;
    }
    set_dir_mode(fresh.path()).map_err(IoError::new(dir, "cannot set the permissions of"))?;
    if dir.exists() {
        // Move the old folder aside first, so that it is only deleted once the new one is in place.
        let old = parent.join(format!(".taxel-old-{}", std::process::id()));
        fs::rename(dir, &old).map_err(IoError::new(dir, "cannot replace the folder"))?;
        if let Err(e) = fs::rename(fresh.path(), dir) {
            let _ = fs::rename(&old, dir);
            return Err(IoError { path: dir.to_path_buf(), what: "cannot replace the folder", source: e });
        }
        let _ = fs::remove_dir_all(&old);
    } else {
        fs::rename(fresh.path(), dir).map_err(IoError::new(dir, "cannot create the folder"))?;
    }
    // The temporary folder was renamed away; keep TempDir from deleting the result.
    let _ = fresh.keep();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> =
            fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        v.sort();
        v
    }

    #[test]
    fn writes_replaces_and_leaves_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out/sub/a.taxel");
        write_file(&p, b"one").unwrap();
        write_file(&p, b"two").unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"two");
        assert_eq!(names(p.parent().unwrap()), ["a.taxel"]);
    }

    #[cfg(unix)]
    #[test]
    fn files_and_folders_share_one_permission_policy() {
        use std::os::unix::fs::PermissionsExt;
        let mode = |p: &Path| fs::metadata(p).unwrap().permissions().mode() & 0o777;
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a.png");
        write_file(&file, b"x").unwrap();
        assert_eq!(mode(&file), 0o644);
        let streamed = dir.path().join("frames.csv");
        write_with(&streamed, |w| w.write_all(b"tick\n")).unwrap();
        assert_eq!(mode(&streamed), 0o644);
        let folder = dir.path().join("unpacked");
        write_folder(&folder, &[("manifest.toml".into(), b"m".to_vec())]).unwrap();
        assert_eq!(mode(&folder), 0o755);
        assert_eq!(mode(&folder.join("manifest.toml")), 0o644);
    }

    #[test]
    fn a_failed_write_leaves_no_partial_file_and_keeps_the_old_one() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("frames.csv");
        let e = write_with(&p, |w| {
            w.write_all(b"tick,a0\n0,1\n")?;
            Err::<(), _>(io::Error::other("the player stopped"))
        })
        .unwrap_err();
        assert_eq!(e.to_string(), format!("cannot write {}: the player stopped", p.display()));
        assert!(names(dir.path()).is_empty(), "{:?}", names(dir.path()));
        write_file(&p, b"old").unwrap();
        assert!(write_with(&p, |_| Err::<(), _>(io::Error::other("no"))).is_err());
        assert_eq!(fs::read(&p).unwrap(), b"old");
        assert_eq!(names(dir.path()), ["frames.csv"]);
    }

    #[test]
    fn a_folder_is_swapped_whole() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("b");
        write_folder(&out, &[("one.csv".into(), b"1".to_vec()), ("two.csv".into(), b"2".to_vec())]).unwrap();
        write_folder(&out, &[("three.csv".into(), b"3".to_vec())]).unwrap();
        assert_eq!(names(&out), ["three.csv"]);
        assert_eq!(names(dir.path()), ["b"]);
        // A name that cannot be created fails before the old folder is touched.
        assert!(write_folder(&out, &[("no/such/sub.csv".into(), b"x".to_vec())]).is_err());
        assert_eq!(names(&out), ["three.csv"]);
        assert_eq!(names(dir.path()), ["b"]);
    }
}
