//! Writing bundles safely: a temporary file in the same folder, flushed to
//! disk, then renamed over the target, so that a reader (or an interrupted
//! batch) only ever sees the old bundle or the whole new one.

use std::io::Write;
use std::path::Path;

use taxel_format::BundleView;

/// Whether `path` holds a valid bundle recording `hash` (an all-zero hash,
/// meaning "unknown", never matches).
pub fn up_to_date(path: &Path, hash: &[u8; 32]) -> bool {
    if *hash == [0; 32] {
        return false;
    }
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() && m.len() <= taxel_format::MAX_FILE_LEN => {}
        _ => return false,
    }
    let Ok(bytes) = std::fs::read(path) else { return false };
    BundleView::parse(&bytes).is_ok_and(|v| v.manifest().content_hash == *hash)
}

/// Writes `bytes` to `path` atomically, creating its folder if needed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir)?;
    let mut tmp = tempfile::Builder::new().prefix(".taxel-tmp-").suffix(".part").tempfile_in(dir)?;
    tmp.write_all(bytes)?;
    // Without the flush a crash soon after the rename could leave an empty
    // file under the final name on some file systems.
    tmp.as_file().sync_all()?;
    #[cfg(unix)]
    {
        // Temporary files are private (0600); a bundle is an ordinary file.
        use std::os::unix::fs::PermissionsExt;
        tmp.as_file().set_permissions(std::fs::Permissions::from_mode(0o644))?;
    }
    tmp.persist(path).map_err(|e| e.error)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use taxel_format::{Bundle, Manifest, profiles};

    #[test]
    fn writes_replaces_and_leaves_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out/sub/a.taxel");
        write_atomic(&p, b"one").unwrap();
        write_atomic(&p, b"two").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        assert_eq!(std::fs::read_dir(p.parent().unwrap()).unwrap().count(), 1);
    }

    #[test]
    fn up_to_date_only_for_a_valid_bundle_with_the_same_hash() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.taxel");
        assert!(!up_to_date(&p, &[1; 32]));
        let mut m = Manifest::new(profiles::builtin("stress2").unwrap());
        m.content_hash = [1; 32];
        let bytes = Bundle::new(m).to_bytes().unwrap();
        std::fs::write(&p, &bytes).unwrap();
        assert!(up_to_date(&p, &[1; 32]));
        assert!(!up_to_date(&p, &[2; 32]));
        std::fs::write(&p, &bytes[..bytes.len() - 1]).unwrap();
        assert!(!up_to_date(&p, &[1; 32]), "a truncated bundle is rebuilt");
    }
}
