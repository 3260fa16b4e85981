//! Drawings that ran away (issue 47), built by the binary within a memory
//! limit: each is built or refused with a diagnostic, never killed, and the
//! process's peak stays under 1 GB (read from the kernel's account of the
//! child, `wait4`). At sizes a debug build runs in seconds; the issue's
//! sizes are the `runaway` group of `benches/real_build.rs`.

use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};

#[path = "../../compiler/benches/drawings/mod.rs"]
mod drawings;

/// A `taxel` run: its exit code (`None`: killed by a signal), its output
/// (stderr then stdout), and its peak resident memory in bytes.
struct Run {
    code: Option<i32>,
    text: String,
    peak: u64,
}

#[cfg(unix)]
fn run(args: &[&str]) -> Run {
    let mut child = Command::new(env!("CARGO_BIN_EXE_taxel"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("taxel starts");
    // Read both pipes to their ends (on threads, so neither fills up), then
    // reap the child with wait4 for its own resource use.
    let mut out = child.stdout.take().expect("stdout");
    let mut err = child.stderr.take().expect("stderr");
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = out.read_to_string(&mut s);
        s
    });
    let mut text = String::new();
    let _ = err.read_to_string(&mut text);
    text += &reader.join().expect("stdout read");
    let mut status = 0;
    // SAFETY: an all-zero rusage is a valid value, filled in by wait4.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: the pid is our child's, not yet reaped (std never waited on it).
    let pid = unsafe { libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut usage) };
    assert_eq!(pid, child.id() as libc::pid_t, "wait4 reaped the child");
    let code = libc::WIFEXITED(status).then(|| libc::WEXITSTATUS(status));
    // ru_maxrss is in kilobytes on Linux.
    Run { code, text, peak: usage.ru_maxrss as u64 * 1024 }
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("drawing written");
    p.display().to_string()
}

#[cfg(unix)]
#[test]
fn drawings_that_ran_away_build_or_are_refused_within_the_memory_limit() {
    let dir = tempfile::tempdir().expect("temp dir");
    let page = (200.0, 150.0);
    let annotated = r##"stroke="#000" stroke-width="0.5" data-tactile="grating(); vibrate()""##;
    let cases = [
        ("scribble.svg", drawings::scribble(10_000, page, "", 1)),
        ("annotated.svg", drawings::scribble(2_000, page, annotated, 2)),
        ("scatter.svg", drawings::scatter(5_000, 0.6, page, 3)),
        ("ring.svg", drawings::jittered_ring(30_000, 50.0, 3.0, page, 4)),
    ];
    for (name, svg) in &cases {
        let input = write(dir.path(), name, svg);
        let output = dir.path().join(name.replace(".svg", ".taxel")).display().to_string();
        let run = run(&["build", "--max-memory", "1G", &input, "-o", &output]);
        let Some(code) = run.code else { panic!("{name}: taxel was killed\n{}", run.text) };
        assert!(code == 0 || run.text.contains("error["), "{name}: exit {code} with no error said\n{}", run.text);
        assert!(!run.text.contains("T0900"), "{name}: an internal error\n{}", run.text);
        assert_eq!(Path::new(&output).exists(), code == 0, "{name}: a bundle only when built\n{}", run.text);
        assert!(run.peak < 1 << 30, "{name}: peak {} MB", run.peak >> 20);
    }
}

#[cfg(unix)]
#[test]
fn a_build_past_the_memory_limit_stops_with_an_error_and_writes_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="60mm" height="40mm" viewBox="0 0 60 40">
<rect id="lake" x="10" y="10" width="30" height="20" data-tactile="grating()"/></svg>"#;
    let input = write(dir.path(), "lake.svg", svg);
    let output = dir.path().join("lake.taxel").display().to_string();
    let run = run(&["build", "--max-memory", "1K", &input, "-o", &output]);
    assert_eq!(run.code, Some(1), "{}", run.text);
    assert!(run.text.contains("error[T0308]"), "{}", run.text);
    assert!(run.text.contains("more memory than the limit of 1 KB"), "{}", run.text);
    assert!(run.text.contains("--max-memory"), "the help says how to raise it:\n{}", run.text);
    assert!(!Path::new(&output).exists(), "nothing written");
    // Within the default limit the same drawing builds.
    let run = self::run(&["build", &input, "-o", &output]);
    assert_eq!(run.code, Some(0), "{}", run.text);
    assert!(Path::new(&output).exists());
    // A size that does not read is refused by the command line.
    let run = self::run(&["build", "--max-memory", "lots", &input, "-o", &output]);
    assert_eq!(run.code, Some(2), "{}", run.text);
    assert!(run.text.contains("not a memory size"), "{}", run.text);
}
