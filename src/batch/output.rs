//! Whether a bundle already built is up to date, and where its key goes.
//! Bundles are written through [`crate::io::write_file`], so a reader (or an
//! interrupted batch) only ever sees the old bundle or the whole new one.
//!
//! A laterotactile or grid bundle whose drawing needs a key has the key's
//! bundles beside it, a page each: `NAME.key.taxel`, then `NAME.key2.taxel`
//! and on when the key is longer than the surface (SPEC.md section 10.2).
//! They are written first and record the same content hash; the graphic's
//! bundle says it has a key (its `key` and `key.*` provenance entries), and
//! each page of a longer key says which page of how many it is, so that a
//! build is up to date only when the graphic and every page are.

use std::path::{Path, PathBuf};

use taxel_compiler::latero::key::page_of;
use taxel_format::{BundleView, Family, ProvenanceEntry};

/// Where the key's first page of the bundle at `output` goes: `a.taxel` →
/// `a.key.taxel`.
pub fn key_path(output: &Path) -> PathBuf {
    key_page_path(output, 1)
}

/// Where page `page` (from 1) of the key of the bundle at `output` goes:
/// `a.key.taxel`, `a.key2.taxel`, `a.key3.taxel` ...
pub fn key_page_path(output: &Path, page: usize) -> PathBuf {
    match page {
        0 | 1 => output.with_extension("key.taxel"),
        k => output.with_extension(format!("key{k}.taxel")),
    }
}

/// Whether the bundle at `output` and, when it has a key, every page of the
/// key's ([`key_page_path`]) are valid and record `hash`.
pub fn complete(output: &Path, hash: &[u8; 32]) -> bool {
    let Some(graphic) = read(output, hash) else { return false };
    if !graphic.has_key {
        return true;
    }
    let Some(first) = read(&key_path(output), hash) else { return false };
    let pages = first.page.1;
    first.page.0 == 1
        && (2..=pages).all(|k| read(&key_page_path(output, k), hash).is_some_and(|p| p.page == (k, pages)))
}

/// Whether a bundle has a key of its own beside it: a laterotactile or grid
/// bundle with the key's provenance entries.
pub fn has_key(v: &BundleView<'_>) -> bool {
    let one_surface = matches!(v.manifest().profile.family(), Family::Laterotactile | Family::Grid);
    one_surface
        && v.provenance().is_some_and(|p| {
            (0..p.len()).filter_map(|i| p.get(i)).any(|e| {
                e.0 == "key"
                    || e.0 == taxel_compiler::style::legend::UNPLACED_ID
                    || taxel_compiler::style::legend::kind_of_id(e.0).is_some()
            })
        })
}

/// Removes the pages of the key of the bundle at `output` from page `from`
/// on, left by an earlier build whose key was longer or that had a key the
/// drawing no longer needs. Pages run without a gap, so it stops at the
/// first that is not there, and removes only files that are bundles, so
/// that nothing else of those names is ever deleted.
pub fn remove_stale_key(output: &Path, from: usize) -> std::io::Result<()> {
    for page in from.max(1).. {
        let key = key_page_path(output, page);
        let is_bundle = std::fs::metadata(&key).is_ok_and(|m| m.is_file() && m.len() <= taxel_format::MAX_FILE_LEN)
            && std::fs::read(&key)
                .is_ok_and(|b| taxel_format::stored::plain(&b).is_ok_and(|p| BundleView::parse(&p).is_ok()));
        if !is_bundle {
            return Ok(());
        }
        std::fs::remove_file(&key)
            .map_err(|e| std::io::Error::new(e.kind(), format!("cannot remove {}: {e}", key.display())))?;
    }
    Ok(())
}

/// What a bundle read back says of its key.
struct Found {
    /// Whether it has a key of its own ([`has_key`]).
    has_key: bool,
    /// Which page of the key it is, of how many ([`page_of`]; `(1, 1)` for
    /// any bundle that does not say).
    page: (usize, usize),
}

/// What the bundle at `path` says of its key, when it is valid and records
/// `hash` (an all-zero hash, meaning "unknown", never matches).
fn read(path: &Path, hash: &[u8; 32]) -> Option<Found> {
    if *hash == [0; 32] {
        return None;
    }
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() && m.len() <= taxel_format::MAX_FILE_LEN => {}
        _ => return None,
    }
    let bytes = std::fs::read(path).ok()?;
    let plain = taxel_format::stored::plain(&bytes).ok()?;
    let v = BundleView::parse(&plain).ok()?;
    if v.manifest().content_hash != *hash {
        return None;
    }
    let entries: Vec<ProvenanceEntry> = v.provenance().map_or_else(Vec::new, |p| {
        (0..p.len())
            .filter_map(|i| p.get(i))
            .map(|(id, label, line)| ProvenanceEntry { id: id.into(), label: label.into(), line })
            .collect()
    });
    Some(Found { has_key: has_key(&v), page: page_of(&entries) })
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
