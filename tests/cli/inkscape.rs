//! `taxel inkscape install|uninstall`: the extension's files from
//! `inkscape/` land in `DIR/taxel/` as they are in the repository, and
//! uninstall takes away only them.

use std::path::Path;
use std::process::{Command, Output};

fn taxel(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taxel")).args(args).output().unwrap()
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

/// The extension's files in the repository: the top of `inkscape/`, less
/// the test requirements (its tests live below it).
fn repo_files() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("inkscape");
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.file_type().unwrap().is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".inx") || n.ends_with(".py"))
        .collect();
    names.sort();
    names
}

#[test]
fn install_writes_the_repository_s_files_and_where_taxel_is() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    let o = taxel(&["inkscape", "install", "--dir", d]);
    assert!(o.status.success(), "{}", text(&o));
    let folder = dir.path().join("taxel");
    let mut installed: Vec<String> =
        std::fs::read_dir(&folder).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    installed.sort();
    let mut expected = repo_files();
    expected.push("taxel-program.txt".into());
    expected.sort();
    assert_eq!(installed, expected, "every .inx and .py of inkscape/ is installed, and nothing else");
    for name in repo_files() {
        let repo = std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("inkscape").join(&name)).unwrap();
        assert_eq!(std::fs::read(folder.join(&name)).unwrap(), repo, "{name} as in the repository");
    }
    let recorded = std::fs::read_to_string(folder.join("taxel-program.txt")).unwrap();
    let this = Path::new(env!("CARGO_BIN_EXE_taxel")).canonicalize().unwrap();
    assert_eq!(Path::new(recorded.trim()), this);
    // Installing again over an installed extension is fine (an upgrade).
    let o = taxel(&["inkscape", "install", "--dir", d]);
    assert!(o.status.success(), "{}", text(&o));
}

#[test]
fn uninstall_removes_only_the_extension_s_files() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    assert!(taxel(&["inkscape", "install", "--dir", d]).status.success());
    let folder = dir.path().join("taxel");
    // Python's cache of our module, and a teacher's own file beside ours.
    std::fs::create_dir(folder.join("__pycache__")).unwrap();
    std::fs::write(folder.join("__pycache__").join("taxel_ink.cpython-311.pyc"), b"cache").unwrap();
    std::fs::write(folder.join("my_notes.txt"), b"mine").unwrap();
    std::fs::write(dir.path().join("other_extension.inx"), b"<inkscape-extension/>").unwrap();
    let o = taxel(&["inkscape", "uninstall", "--dir", d]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("keeps files that are not taxel's"), "{}", text(&o));
    let left: Vec<String> =
        std::fs::read_dir(&folder).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert_eq!(left, ["my_notes.txt"]);
    assert!(dir.path().join("other_extension.inx").is_file(), "another extension stays");
    // Without the foreign file the folder itself goes; a second uninstall has nothing to do.
    std::fs::remove_file(folder.join("my_notes.txt")).unwrap();
    assert!(taxel(&["inkscape", "install", "--dir", d]).status.success());
    let o = taxel(&["inkscape", "uninstall", "--dir", d]);
    assert!(o.status.success() && !folder.exists(), "{}", text(&o));
    let o = taxel(&["inkscape", "uninstall", "--dir", d]);
    assert!(o.status.success() && text(&o).contains("nothing to remove"), "{}", text(&o));
}

#[test]
fn install_follows_xdg_config_home_without_dir() {
    // Linux's default place (other systems have their own, see src/cmd/inkscape.rs).
    if !cfg!(target_os = "linux") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_taxel"))
        .args(["inkscape", "install"])
        .env("XDG_CONFIG_HOME", dir.path())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    assert!(dir.path().join("inkscape/extensions/taxel/tactile_style.inx").is_file(), "{}", text(&o));
}
