//! `taxel report INPUT [--profile P] [--plot PNG] [--default-only] [--format human|json]`:
//! error against run time over a ladder of settings (docs/report.md).

use std::path::Path;

use crate::cli::{CompileOpts, Format};
use crate::error::CmdResult;
use crate::io::stdout::{self, outln};
use crate::report::{self, Report, plot};

/// Runs the report and prints it; writes the plot when asked.
pub fn run(
    input: &Path,
    opts: &CompileOpts,
    plot_path: Option<&Path>,
    default_only: bool,
    format: Format,
) -> CmdResult {
    let rep = report::run(input, opts, None, default_only)?;
    if let Some(p) = plot_path {
        let title = format!(
            "{} on {}",
            input.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default(),
            rep.profile
        );
        let png = plot::draw(&rep.rows, &title)?;
        crate::io::write_file(p, &png)?;
    }
    match format {
        Format::Human => stdout::print(&human(&rep)),
        Format::Json => outln!("{}", serde_json::to_string_pretty(&rep).map_err(anyhow::Error::new)?),
    }
}

/// The report as a table for people.
pub fn human(rep: &Report) -> String {
    let mut s = format!(
        "{} on {}: {} frames of {}\n\n{:<10} {:>9} {:>11} {:>10} {:>9} {:>9} {:>10} {:>10} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}  {}\n",
        rep.input,
        rep.profile,
        rep.trace_frames,
        rep.trace,
        "kernel",
        "setting",
        "compile ms",
        "bytes",
        "µs/frame",
        "run ms",
        "max err",
        "rms err",
        "step rms",
        "far err",
        "far rms",
        "crnr err",
        "edge mm",
        "crnr mm",
        "note"
    );
    for r in &rep.rows {
        let mut note = Vec::new();
        if r.default {
            note.push("default");
        }
        if r.on_front {
            note.push("front");
        }
        s += &format!(
            "{:<10} {:>9} {:>11.2} {:>10} {:>9.3} {:>9.1} {:>10.2} {:>10.3} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}  {}\n",
            r.kernel,
            setting(r.setting),
            r.compile_ms,
            r.bundle_bytes,
            r.frame_us,
            r.run_ms,
            r.max_error,
            r.rms_error,
            r.step_rms_error.map_or("-".to_string(), |e| format!("{e:.3}")),
            r.far_error.map_or("-".to_string(), |e| format!("{e:.2}")),
            r.far_rms_error.map_or("-".to_string(), |e| format!("{e:.2}")),
            r.corner_error.map_or("-".to_string(), |e| format!("{e:.2}")),
            r.edge_error_mm.map_or("-".to_string(), |e| format!("{e:.4}")),
            r.corner_edge_error_mm.map_or("-".to_string(), |e| format!("{e:.4}")),
            note.join(", ")
        );
    }
    if let Some(r) = rep.rows.first() {
        s += &format!(
            "\nsetting: {}; errors in {} against the exact reference (docs/report.md)\n",
            r.unit, r.error_unit
        );
    }
    for n in &rep.notes {
        s += &format!("note: {n}\n");
    }
    s
}

/// A setting as the table shows it: at most four decimals, trailing zeros
/// dropped (a mesh's default resolution is 5.98 nodes per mm, not
/// 5.979998966336429).
fn setting(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s };
    if s == "0" && v != 0.0 { format!("{v:.2e}") } else { s }
}

#[cfg(test)]
mod tests {
    use super::setting;

    #[test]
    fn settings_are_shown_short() {
        assert_eq!(setting(5.979998966336429), "5.98");
        assert_eq!(setting(0.25), "0.25");
        assert_eq!(setting(0.0625), "0.0625");
        assert_eq!(setting(2.0), "2");
        assert_eq!(setting(1000.0), "1000");
        assert_eq!(setting(1.5e-5), "1.50e-5");
    }
}
