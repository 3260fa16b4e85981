//! What every command shares: one permission policy for the files and
//! folders it writes, one exit-code policy printed once, and a closed
//! standard output that ends a command quietly with success.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn taxel(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taxel")).args(args).output().unwrap()
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Builds an example drawing into `out` for `profile`.
fn build(input: &str, profile: &str, out: &Path) {
    let o = taxel(&["build", s(&examples().join(input)), "--profile", profile, "-o", s(out)]);
    assert!(o.status.success(), "{}", text(&o));
}

/// Runs taxel with its standard output already closed by the reader, as
/// `taxel inspect B | head -0` does.
fn with_closed_stdout(args: &[&str]) -> Output {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    Command::new(env!("CARGO_BIN_EXE_taxel")).args(args).stdout(writer).stderr(Stdio::piped()).output().unwrap()
}

/// Regression: `taxel inspect B | head -1` panicked on the closed pipe.
#[test]
fn a_closed_standard_output_ends_quietly_with_success() {
    let dir = tempfile::tempdir().unwrap();
    let bundle = dir.path().join("g.taxel");
    build("stress2/exp1-grating-2cm.svg", "stress2", &bundle);
    let trace = examples().join("traces/exp1-grating-2cm.csv");
    for args in [
        vec!["inspect", s(&bundle)],
        vec!["inspect", s(&bundle), "--format", "json"],
        vec!["profiles"],
        vec!["play", s(&bundle), "--trace", s(&trace)],
    ] {
        let o = with_closed_stdout(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {err}");
        assert!(!err.contains("panicked") && !err.contains("error"), "{args:?}: {err}");
    }
}

/// Exit codes as README.md says, and the error printed once with its file.
#[test]
fn errors_are_printed_once_with_their_exit_code() {
    let dir = tempfile::tempdir().unwrap();
    let junk = dir.path().join("junk.taxel");
    std::fs::write(&junk, b"not a bundle").unwrap();
    let o = taxel(&["inspect", s(&junk)]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.matches("error:").count(), 1, "{err}");
    assert!(err.contains("junk.taxel"), "{err}");
    let o = taxel(&["inspect", s(&dir.path().join("missing.taxel"))]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(String::from_utf8_lossy(&o.stderr).contains("missing.taxel"));
    // A bad trace names its file and line; nothing is written.
    let bundle = dir.path().join("g.taxel");
    build("stress2/exp1-grating-2cm.svg", "stress2", &bundle);
    let trace = dir.path().join("bad.csv");
    std::fs::write(&trace, "t_ms,x_mm,y_mm\n0,0,0\n1,NaN,0\n").unwrap();
    let out = dir.path().join("frames.csv");
    let o = taxel(&["play", s(&bundle), "--trace", s(&trace), "--out", s(&out)]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("bad.csv: line 3") && err.contains("x_mm"), "{err}");
    assert!(!out.exists());
}

/// `preview` reads its input like `build`: with the size limit.
#[test]
fn preview_refuses_an_input_over_the_size_limit() {
    let dir = tempfile::tempdir().unwrap();
    let big = dir.path().join("big.svg");
    std::fs::File::create(&big).unwrap().set_len((64 << 20) + 1).unwrap();
    let out = dir.path().join("p.png");
    let o = taxel(&["preview", s(&big), "-o", s(&out)]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("64 MB input limit"), "{}", text(&o));
    assert!(!out.exists());
}

#[cfg(unix)]
#[test]
fn every_command_writes_files_0644_and_folders_0755() {
    use std::os::unix::fs::PermissionsExt;
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let grating = d.join("g.taxel");
    build("stress2/exp1-grating-2cm.svg", "stress2", &grating);
    let brush = d.join("b.taxel");
    build("brush/brush-2-horizontal.svg", "brush-4x3", &brush);
    let trace = examples().join("traces/exp1-grating-2cm.csv");
    let unpacked = d.join("unpacked");
    let runs: Vec<Vec<String>> = vec![
        vec!["unpack".into(), s(&grating).into(), "-o".into(), s(&unpacked).into()],
        vec!["pack".into(), s(&unpacked).into(), "-o".into(), s(&d.join("packed.taxel")).into()],
        vec!["preview".into(), s(&grating).into(), "-o".into(), s(&d.join("preview.png")).into()],
        vec![
            "play".into(),
            s(&grating).into(),
            "--trace".into(),
            s(&trace).into(),
            "--out".into(),
            s(&d.join("frames.csv")).into(),
        ],
        vec!["play".into(), s(&brush).into(), "--out".into(), s(&d.join("drive.wav")).into()],
        vec!["play".into(), s(&brush).into(), "--out".into(), s(&d.join("grid.csv")).into()],
    ];
    for args in &runs {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = taxel(&args);
        assert!(o.status.success(), "{args:?}: {}", text(&o));
    }
    for file in ["g.taxel", "b.taxel", "packed.taxel", "preview.png", "frames.csv", "drive.wav", "grid.csv"] {
        assert_eq!(mode(&d.join(file)), 0o644, "{file}");
    }
    assert_eq!(mode(&unpacked), 0o755);
    for e in std::fs::read_dir(&unpacked).unwrap() {
        assert_eq!(mode(&e.unwrap().path()), 0o644);
    }
    // Nothing temporary is left beside the outputs.
    let left: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}
