//! Playing a finger-device bundle: one motors row per trace sample.
//!
//! Output CSV `t_ms,left,down,right,period_ms`: `t_ms` as in the trace, the
//! three actuators' intensities (0..1; the active one carries D, the others
//! 0), and the active actuator's modulating period in ms, empty when all
//! are off. The player runs on touch events, as the paper's tablet did, so
//! there is exactly one row per trace row; the tick given to the player is
//! the trace time rounded to the profile's rate.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;
use std::process::ExitCode;

use anyhow::{Context, Result};
use taxel_format::{BundleView, Mm, Tick};
use taxel_runtime::finger::{FingerPlayer, Touch};
use taxel_runtime::trace::Trace;

/// The motors CSV of `player` along `trace` (one row per trace sample), for
/// a profile running at `rate_hz`; `taxel play` and the demo both write it.
pub(crate) fn motors_csv(player: &mut FingerPlayer<'_>, trace: &Trace, rate_hz: u32) -> String {
    let rate = rate_hz as f64;
    let mut csv = String::from("t_ms,left,down,right,period_ms\n");
    for s in trace.samples() {
        // The parser bounds times, so the tick is finite and non-negative.
        let tick = Tick((s.t_ms * rate / 1000.0).round() as u64);
        let f = player.sample(Touch { tick, x: Mm(s.x_mm as f32), y: Mm(s.y_mm as f32), contact: s.contact });
        let [l, d, r] = f.levels();
        let _ = write!(csv, "{},{l:.4},{d:.4},{r:.4},", s.t_ms);
        if f.active.is_some() {
            let _ = write!(csv, "{:.2}", f.period_ms);
        }
        csv.push('\n');
    }
    csv
}

/// Plays `view` on the trace at `trace_path`.
pub fn run(bundle: &Path, view: &BundleView<'_>, trace_path: Option<&Path>, out: Option<&Path>) -> Result<ExitCode> {
    let Some(trace_path) = trace_path else {
        eprintln!("error: {}: a finger bundle plays on a trace: add --trace TRACE.csv", bundle.display());
        return Ok(ExitCode::from(2));
    };
    let file = std::fs::File::open(trace_path).with_context(|| format!("cannot read {}", trace_path.display()))?;
    let trace = match Trace::parse(std::io::BufReader::new(file)) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {}: {e}", trace_path.display());
            return Ok(ExitCode::from(1));
        }
    };
    let mut player = match FingerPlayer::new(view) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {}: {e}", bundle.display());
            return Ok(ExitCode::from(1));
        }
    };
    let csv = motors_csv(&mut player, &trace, view.manifest().profile.rate_hz);
    match out {
        Some(path) => {
            // Through a temporary file in the same folder: never a partial output.
            let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
            let mut tmp = tempfile::Builder::new()
                .prefix(".taxel-motors-")
                .tempfile_in(dir)
                .with_context(|| format!("cannot write in {}", dir.display()))?;
            tmp.write_all(csv.as_bytes()).with_context(|| format!("cannot write {}", path.display()))?;
            tmp.persist(path).map_err(|e| anyhow::anyhow!("cannot write {}: {}", path.display(), e.error))?;
            println!("wrote {}: {} samples", path.display(), trace.samples().len());
        }
        None => print!("{csv}"),
    }
    Ok(ExitCode::SUCCESS)
}
