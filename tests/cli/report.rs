//! `taxel report`: the ladder's rows, the defaults on the efficient front,
//! convergence towards the exact reference, the plot, and clear refusals.

use std::process::Command;

use serde_json::Value;

fn report(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_taxel")).arg("report").args(args).output().expect("runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn rows(json: &str) -> Vec<Value> {
    let v: Value = serde_json::from_str(json).expect("JSON report");
    v["rows"].as_array().expect("rows").clone()
}

fn f(r: &Value, k: &str) -> f64 {
    r[k].as_f64().unwrap_or_else(|| panic!("{k} in {r}"))
}

/// The default mask resolution is on the efficient front of every kernel:
/// no setting that costs less (fewer bundle bytes, the deterministic
/// stand-in for compile and memory cost, which grow with the resolution) is
/// more accurate. Run times are measured but never asserted.
#[test]
fn default_resolution_is_on_the_efficient_front() {
    let dir = tempfile::tempdir().expect("temp dir");
    let plot = dir.path().join("plot.png");
    let root = env!("CARGO_MANIFEST_DIR");
    let input = format!("{root}/examples/stress2/exp5-icon-circle-vertical-2mm.svg");
    let (ok, out, err) = report(&[&input, "--format", "json", "--plot", plot.to_str().expect("utf-8")]);
    assert!(ok, "{err}");
    let rows = rows(&out);
    let kernels: Vec<&str> = rows.iter().filter_map(|r| r["kernel"].as_str()).collect();
    assert!(kernels.contains(&"vibration") && kernels.contains(&"grating"), "{kernels:?}");
    for k in ["vibration", "grating", "all"] {
        let mine: Vec<&Value> = rows.iter().filter(|r| r["kernel"] == k).collect();
        let default = mine.iter().find(|r| r["default"] == true).expect("a default row");
        for r in &mine {
            let cheaper = f(r, "bundle_bytes") < f(default, "bundle_bytes");
            assert!(
                !(cheaper && f(r, "rms_error") < f(default, "rms_error")),
                "{k}: a {} mm lattice is cheaper and more accurate than the default",
                f(r, "setting")
            );
        }
        // Convergence: the finest lattice (0.25 mm) is more accurate (RMS) than the coarsest (2 mm).
        // (Hard edges: the RMS is made at the few actuators near corners and
        // curves, and falls more slowly than the pitch; docs/layers.md.)
        let by = |s: f64| mine.iter().find(|r| f(r, "setting") == s).map(|r| f(r, "rms_error")).expect("setting");
        assert!(by(0.25) < by(2.0), "{k}: {} vs {}", by(0.25), by(2.0));
        // Away from exact edges (more than 0.05 mm) the default is within one
        // output step, for the vibration and grating kernels.
        if k != "all" {
            assert!(f(default, "far_error") <= 1.0, "{k}: far error {}", f(default, "far_error"));
        }
        assert!(mine.iter().all(|r| f(r, "max_error") <= 1023.0 && f(r, "frame_us") > 0.0));
    }
    let png = std::fs::read(&plot).expect("plot written");
    assert!(png.starts_with(b"\x89PNG"));
}

/// Brushed strokes climb the tick-rate ladder; at every rate the stored
/// schedule is within one tick of the unquantised one (onsets round to the
/// nearest tick, durations to whole ticks).
#[test]
fn stroke_schedule_error_is_within_one_tick() {
    let root = env!("CARGO_MANIFEST_DIR");
    let input = format!("{root}/examples/brush/brush-1-diagonal.svg");
    let (ok, out, err) = report(&[&input, "--profile", "brush-4x3", "--format", "json"]);
    assert!(ok, "{err}");
    let rows = rows(&out);
    assert!(rows.len() >= 5);
    for r in &rows {
        let tick_ms = 1000.0 / f(r, "setting");
        assert!(f(r, "max_error") <= tick_ms + 1e-6, "{r}");
        assert_eq!(r["error_unit"], "ms");
    }
    assert!(rows.iter().any(|r| r["default"] == true && f(r, "setting") == 1000.0));
}

/// A file that is not there, and a drawing with nothing tactile: exit 2 with a message, no table.
#[test]
fn bad_inputs_are_refused_clearly() {
    let (ok, out, err) = report(&["/nonexistent/drawing.svg"]);
    assert!(!ok && out.is_empty() && err.contains("drawing.svg"), "{err}");
    let dir = tempfile::tempdir().expect("temp dir");
    let empty = dir.path().join("empty.svg");
    std::fs::write(&empty, r#"<svg xmlns="http://www.w3.org/2000/svg" width="10mm" height="10mm"/>"#).expect("write");
    let (ok, _, err) = report(&[empty.to_str().expect("utf-8")]);
    assert!(!ok && err.contains("T0300"), "{err}");
}
