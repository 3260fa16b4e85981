//! Whether a bundle already built is up to date, and where its key goes.
//! Bundles are written through [`crate::io::write_file`], so a reader (or an
//! interrupted batch) only ever sees the old bundle or the whole new one.
//!
//! A laterotactile or grid bundle whose drawing needs a key has a second
//! bundle beside it, `NAME.key.taxel` (SPEC.md section 10.2), written first
//! and recording the same content hash; the graphic's bundle says it has
//! one (its `key` and `key.*` provenance entries), so that a build is up to
//! date only when both are.

use std::path::{Path, PathBuf};

use taxel_format::{BundleView, Family};

/// Where the key's bundle of the bundle at `output` goes: `a.taxel` →
/// `a.key.taxel`.
pub fn key_path(output: &Path) -> PathBuf {
    output.with_extension("key.taxel")
}

/// Whether the bundle at `output` and, when it has one, its key's bundle
/// ([`key_path`]) are both valid and record `hash`.
pub fn complete(output: &Path, hash: &[u8; 32]) -> bool {
    match read(output, hash) {
        Some(has_key) => !has_key || read(&key_path(output), hash).is_some(),
        None => false,
    }
}

/// Whether a bundle has a key of its own beside it: a laterotactile or grid
/// bundle with the key's provenance entries.
pub fn has_key(v: &BundleView<'_>) -> bool {
    let one_surface = matches!(v.manifest().profile.family(), Family::Laterotactile | Family::Grid);
    one_surface
        && v.provenance().is_some_and(|p| {
            (0..p.len())
                .filter_map(|i| p.get(i))
                .any(|e| e.0 == "key" || taxel_compiler::style::legend::kind_of_id(e.0).is_some())
        })
}

/// Removes the key's bundle of the bundle at `output` left by an earlier
/// build, when the drawing no longer needs a key: only a file that is a
/// bundle, so that nothing else of that name is ever deleted.
pub fn remove_stale_key(output: &Path) -> std::io::Result<()> {
    let key = key_path(output);
    let is_bundle = std::fs::metadata(&key).is_ok_and(|m| m.is_file() && m.len() <= taxel_format::MAX_FILE_LEN)
        && std::fs::read(&key).is_ok_and(|b| BundleView::parse(&b).is_ok());
    if is_bundle { std::fs::remove_file(&key) } else { Ok(()) }
}

/// Whether `path` holds a valid bundle recording `hash` (an all-zero hash,
/// meaning "unknown", never matches): `Some(whether it has a key)`.
fn read(path: &Path, hash: &[u8; 32]) -> Option<bool> {
    if *hash == [0; 32] {
        return None;
    }
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() && m.len() <= taxel_format::MAX_FILE_LEN => {}
        _ => return None,
    }
    let bytes = std::fs::read(path).ok()?;
    let v = BundleView::parse(&bytes).ok()?;
    (v.manifest().content_hash == *hash).then(|| has_key(&v))
}

#[cfg(test)]
mod tests {
    use super::*;
    use taxel_format::{Bundle, Manifest, profiles};

    #[test]
    fn up_to_date_only_for_a_valid_bundle_with_the_same_hash() {
        let up_to_date = complete;
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
