//! `taxel inkscape install|uninstall [--dir DIR]`: puts the Inkscape
//! extension (Extensions ▸ Tactile, `inkscape/` in the repository) into the
//! user's Inkscape extensions folder, or takes it out again.
//!
//! The extension's files are compiled into the binary, so an installed
//! `taxel` installs the extension that matches it. They go into a folder of
//! their own, `DIR/taxel/`, which Inkscape 1.x searches like the folder
//! above it; uninstall removes only the files this command writes (and the
//! bytecode Python may have cached for them), then the folder when nothing
//! else is left in it. Beside them, `taxel-program.txt` records where this
//! binary is, so the extension finds it even when Inkscape is started from
//! a desktop menu whose PATH lacks `~/.cargo/bin`.

use std::path::{Path, PathBuf};

use crate::error::{CliError, CmdResult};
use crate::io;

/// The folder inside the extensions folder that holds the extension.
const FOLDER: &str = "taxel";

/// The file that records the path of the `taxel` program that installed the extension.
const PROGRAM_FILE: &str = "taxel-program.txt";

/// The extension's files, as kept in `inkscape/`: one `.inx` menu entry and
/// one Python script per effect, and the module they share.
const FILES: &[(&str, &str)] = &[
    ("tactile_style.inx", include_str!("../../inkscape/tactile_style.inx")),
    ("tactile_style.py", include_str!("../../inkscape/tactile_style.py")),
    ("tactile_check.inx", include_str!("../../inkscape/tactile_check.inx")),
    ("tactile_check.py", include_str!("../../inkscape/tactile_check.py")),
    ("tactile_preview.inx", include_str!("../../inkscape/tactile_preview.inx")),
    ("tactile_preview.py", include_str!("../../inkscape/tactile_preview.py")),
    ("tactile_export.inx", include_str!("../../inkscape/tactile_export.inx")),
    ("tactile_export.py", include_str!("../../inkscape/tactile_export.py")),
    ("taxel_ink.py", include_str!("../../inkscape/taxel_ink.py")),
];

/// The user's Inkscape extensions folder (Inkscape ▸ Edit ▸ Preferences ▸
/// System ▸ User extensions): `%APPDATA%\inkscape\extensions` on Windows,
/// `~/Library/Application Support/org.inkscape.Inkscape/config/inkscape/extensions`
/// on macOS, else `$XDG_CONFIG_HOME/inkscape/extensions` or
/// `~/.config/inkscape/extensions`.
fn default_dir() -> Result<PathBuf, CliError> {
    let var = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty()).map(PathBuf::from);
    let missing = |why: &str| {
        CliError::trouble(anyhow::anyhow!(
            "cannot find the Inkscape extensions folder: {why}; give it with --dir \
             (Inkscape shows it under Edit > Preferences > System > User extensions)"
        ))
    };
    if cfg!(windows) {
        return var("APPDATA")
            .map(|a| a.join("inkscape").join("extensions"))
            .ok_or_else(|| missing("APPDATA is not set"));
    }
    let home = var("HOME");
    if cfg!(target_os = "macos") {
        let home = home.ok_or_else(|| missing("HOME is not set"))?;
        return Ok(home.join("Library/Application Support/org.inkscape.Inkscape/config/inkscape/extensions"));
    }
    match (var("XDG_CONFIG_HOME"), home) {
        (Some(config), _) => Ok(config.join("inkscape").join("extensions")),
        (None, Some(home)) => Ok(home.join(".config").join("inkscape").join("extensions")),
        (None, None) => Err(missing("neither XDG_CONFIG_HOME nor HOME is set")),
    }
}

pub fn install(dir: Option<&Path>) -> CmdResult {
    let base = match dir {
        Some(d) => d.to_path_buf(),
        None => default_dir()?,
    };
    let folder = base.join(FOLDER);
    for (name, text) in FILES {
        io::write_file(&folder.join(name), text.as_bytes())?;
    }
    // Where this program is, for the extension's search (see the module's comment).
    let program = std::env::current_exe().and_then(|p| p.canonicalize()).map_err(|e| {
        CliError::trouble(anyhow::anyhow!("cannot tell where this taxel program is, to record it for Inkscape: {e}"))
    })?;
    let line = format!("{}\n", program.display());
    io::write_file(&folder.join(PROGRAM_FILE), line.as_bytes())?;
    eprintln!(
        "installed the Inkscape extension in {} ({} files; it runs {})\n\
         restart Inkscape, then use Extensions > Tactile (docs/inkscape.md)",
        folder.display(),
        FILES.len() + 1,
        program.display()
    );
    Ok(())
}

pub fn uninstall(dir: Option<&Path>) -> CmdResult {
    let base = match dir {
        Some(d) => d.to_path_buf(),
        None => default_dir()?,
    };
    let folder = base.join(FOLDER);
    let ours = FILES.iter().map(|(n, _)| *n).chain([PROGRAM_FILE]);
    let mut removed = 0;
    for name in ours {
        removed += usize::from(remove_file(&folder.join(name))?);
    }
    // Bytecode that Python cached for our modules (`taxel_ink.cpython-311.pyc`).
    let cache = folder.join("__pycache__");
    let stems: Vec<&str> = FILES.iter().filter_map(|(n, _)| n.strip_suffix(".py")).collect();
    if let Ok(entries) = std::fs::read_dir(&cache) {
        for entry in entries.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            let is_ours = name.ends_with(".pyc") && stems.iter().any(|s| name.split('.').next() == Some(s));
            if is_ours {
                remove_file(&entry.path())?;
            }
        }
        // Only when empty: a folder with someone else's files stays.
        let _ = std::fs::remove_dir(&cache);
    }
    let folder_gone = std::fs::remove_dir(&folder).is_ok() || !folder.exists();
    match (removed, folder_gone) {
        (0, _) => eprintln!("nothing to remove: no taxel extension in {}", folder.display()),
        (n, true) => eprintln!("removed the Inkscape extension ({n} files) and its folder {}", folder.display()),
        (n, false) => eprintln!(
            "removed the Inkscape extension ({n} files); {} keeps files that are not taxel's",
            folder.display()
        ),
    }
    Ok(())
}

/// Removes one file; `false` when it was not there.
fn remove_file(path: &Path) -> Result<bool, CliError> {
    match std::fs::remove_file(path) {
        Ok(()) => Ok(true),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(false),
        Err(e) => Err(CliError::trouble(anyhow::anyhow!("cannot remove {}: {e}", path.display()))),
    }
}
