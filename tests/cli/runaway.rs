//! Drawings that ran away (issue 47), built by the binary within a memory
//! limit: each is built or refused with a diagnostic, never killed, and the
//! most the process held (its allocator's count, which the build's summary
//! line gives) stays under 1 GB. At sizes a debug build runs in seconds;
//! the issue's sizes are the `runaway` group of `benches/real_build.rs`.

use std::path::Path;
use std::process::Command;

use super::real::drawings;

/// A `taxel` run: its exit code (`None`: killed by a signal), its output
/// (stderr then stdout), and the peak memory its summary line gives, bytes.
struct Run {
    code: Option<i32>,
    text: String,
    peak: Option<u64>,
}

fn run(args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_taxel")).args(args).output().expect("taxel runs");
    let text = format!("{}{}", String::from_utf8_lossy(&out.stderr), String::from_utf8_lossy(&out.stdout));
    Run { code: out.status.code(), peak: peak_of(&text), text }
}

/// The bytes of the summary's `peak memory 12 MB` (or KB, GB).
fn peak_of(text: &str) -> Option<u64> {
    let said = text.rsplit_once("peak memory ")?.1.lines().next()?;
    let (number, unit) = said.split_once(' ')?;
    let shift = match unit.trim() {
        "KB" => 10,
        "MB" => 20,
        "GB" => 30,
        _ => return None,
    };
    Some((number.parse::<f64>().ok()? * (1u64 << shift) as f64) as u64)
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("drawing written");
    p.display().to_string()
}

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
        let peak = run.peak.unwrap_or_else(|| panic!("{name}: no peak said\n{}", run.text));
        assert!((1 << 20..1 << 30).contains(&peak), "{name}: peak {} MB", peak >> 20);
    }
}

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
