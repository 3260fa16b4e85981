//! Whether a bundle already built is up to date. Bundles are written through
//! [`crate::io::write_file`], so a reader (or an interrupted batch) only ever
//! sees the old bundle or the whole new one.

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

#[cfg(test)]
mod tests {
    use super::*;
    use taxel_format::{Bundle, Manifest, profiles};

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
