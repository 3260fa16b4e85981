//! The file-system side of the text form (`taxel-textform` is the codec): where files go, what may be
//! overwritten, and atomic writes.
//!
//! - `unpack` writes into a folder that does not exist, is empty, or holds a
//!   previous unpack and nothing else (only `manifest.toml`, `profile.toml`
//!   and `NN-kind.ext` files, with a manifest that `taxel unpack` wrote); any
//!   other folder is refused, so no one's files are lost. The new folder is
//!   written beside the target and swapped in, so a failure leaves the old
//!   one as it was.
//! - `pack` writes the bundle to a temporary file beside the output and
//!   renames it over the output, so there is never a partial bundle.

use std::fs;
use std::path::Path;

use taxel_textform::{MANIFEST, MANIFEST_HEADER, PROFILE, TextError, pack, unpack};

fn io_err(path: &Path, what: &str, e: std::io::Error) -> TextError {
    TextError::io(path.display().to_string(), format!("{what}: {e}"))
}

/// Unpacks the bundle file `bundle` into the folder `dir`. Returns the number of files written.
pub fn unpack_to(bundle: &Path, dir: &Path) -> Result<usize, TextError> {
    let bytes =
        crate::io::read_bundle(bundle).map_err(|e| TextError::io(bundle.display().to_string(), format!("{e:#}")))?;
    let files = unpack(&bundle.display().to_string(), &bytes)?;
    check_replaceable(dir)?;
    crate::io::write_folder(dir, &files).map_err(io_failure)?;
    Ok(files.len())
}

/// Refuses a folder that holds anything but a previous unpack.
fn check_replaceable(dir: &Path) -> Result<(), TextError> {
    if !dir.exists() {
        return Ok(());
    }
    let refuse = |why: &str| {
        TextError::io(
            dir.display().to_string(),
            format!("{why}; refusing to overwrite it (remove it or choose another folder)"),
        )
    };
    if !dir.is_dir() {
        return Err(refuse("exists and is not a folder"));
    }
    let entries: Vec<_> = fs::read_dir(dir)
        .map_err(|e| io_err(dir, "cannot list the folder", e))?
        .filter_map(Result::ok)
        .map(|e| (e.file_name().to_string_lossy().into_owned(), e.path().is_file()))
        .collect();
    if entries.is_empty() {
        return Ok(());
    }
    let manifest = fs::read_to_string(dir.join(MANIFEST)).unwrap_or_default();
    if !manifest.starts_with(MANIFEST_HEADER) {
        return Err(refuse("is not empty and is not a folder written by `taxel unpack`"));
    }
    if let Some((name, _)) = entries.iter().find(|(name, is_file)| !is_file || !is_unpack_file(name)) {
        return Err(refuse(&format!("holds `{name}`, which `taxel unpack` did not write")));
    }
    Ok(())
}

/// Whether `name` is a file that `unpack` writes.
fn is_unpack_file(name: &str) -> bool {
    if name == MANIFEST || name == PROFILE {
        return true;
    }
    let Some((num, rest)) = name.split_once('-') else { return false };
    let kinds = [
        "vibration.png",
        "grating.png",
        "vibration-field.png",
        "grating-field.png",
        "vibration-field-tiles.csv",
        "grating-field-tiles.csv",
        "vibration-field-samples.png",
        "grating-field-samples.png",
        "vibration-field-planes.csv",
        "grating-field-planes.csv",
        "dots.csv",
        "strokes.toml",
        "height.csv",
        "provenance.csv",
        "raw.bin",
    ];
    !num.is_empty() && num.bytes().all(|b| b.is_ascii_digit()) && kinds.contains(&rest)
}

/// Packs the folder `dir` into the bundle file `out`, atomically. Returns the bundle's size.
pub fn pack_to(dir: &Path, out: &Path) -> Result<usize, TextError> {
    if !dir.is_dir() {
        return Err(TextError::io(
            dir.display().to_string(),
            "is not a folder (expected one written by `taxel unpack`)",
        ));
    }
    let read = |name: &str| -> Result<Vec<u8>, TextError> {
        let path = dir.join(name);
        // A folder holds one bundle's worth: its files have the bundle's size limit.
        crate::io::read_bundle_file(&path)
            .map_err(|e| TextError::io(path.display().to_string(), format!("cannot read: {}", e.root_cause())))
    };
    let bytes = pack(&read).map_err(|mut e| {
        // Name files by their path, so the message can be acted on from anywhere.
        if !Path::new(&e.file).is_absolute() && !e.file.starts_with(&*dir.display().to_string()) {
            e.file = dir.join(&e.file).display().to_string();
        }
        e
    })?;
    // Written as `taxel build` writes a bundle: its stored form (SPEC.md 15).
    let bytes =
        taxel_format::stored::store(&bytes).map_err(|e| TextError::new(out.display().to_string(), e.to_string()))?;
    crate::io::write_file(out, &bytes).map_err(io_failure)?;
    Ok(bytes.len())
}

/// A failed write, as the text form reports it.
fn io_failure(e: crate::io::IoError) -> TextError {
    TextError::io(e.path.display().to_string(), format!("{}: {}", e.what, e.source))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_unpack_files_are_recognised() {
        for n in [
            "manifest.toml",
            "profile.toml",
            "01-vibration.png",
            "123-raw.bin",
            "07-strokes.toml",
            "02-grating-field-tiles.csv",
            "03-vibration-field.png",
        ] {
            assert!(is_unpack_file(n), "{n}");
        }
        for n in ["notes.txt", "01-vibration.jpg", "-dots.csv", "a1-dots.csv", "01-dots.csv.bak"] {
            assert!(!is_unpack_file(n), "{n}");
        }
    }
}
