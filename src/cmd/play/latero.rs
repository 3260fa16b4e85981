//! `taxel play` for laterotactile bundles: the carrier follows an
//! exploration trace, and every tick of the profile's rate from the trace's
//! first time to its last gives one frame of output codes
//! (`tick,a0,…,a{n−1}`), to `--out` or standard output. With `--elements`,
//! what the carrier touched, named through the footprints' point lookup.

use std::path::Path;

use std::fmt::Write as _;

use taxel_format::BundleView;
use taxel_format::lookup::PointLookup;
use taxel_runtime::latero::{LateroPlayer, Layer};

use crate::error::{CliError, CmdResult};
use crate::io::{self, stdout, stdout::outln};
use crate::playback::latero_frames;

/// Most frames one run may write (a little over 24 hours at 1 kHz); a trace
/// asking for more is refused instead of filling the disk.
const MAX_FRAMES: u64 = 100_000_000;

pub fn run(
    bundle: &Path,
    view: &BundleView<'_>,
    trace: Option<&Path>,
    out: Option<&Path>,
    elements: Option<&Path>,
) -> CmdResult {
    let shown = bundle.display();
    // Storage for every chunk is always enough for the player's layers.
    let storage = vec![Layer::EMPTY; view.chunk_count() as usize];
    let player =
        LateroPlayer::with_storage(view, storage).map_err(|e| CliError::input(anyhow::anyhow!("{shown}: {e}")))?;
    let Some(trace_path) = trace else {
        return Err(CliError::trouble(anyhow::anyhow!(
            "{shown} is a laterotactile bundle: playing it needs an exploration trace (--trace CSV with t_ms,x_mm,y_mm)"
        )));
    };
    let trace = super::read_trace(trace_path)?;
    let rate = view.manifest().profile.rate_hz;
    if let Some((first, last)) = trace.tick_range(rate) {
        let frames = last.0 - first.0 + 1;
        if frames > MAX_FRAMES {
            return Err(CliError::input(anyhow::anyhow!(
                "{}: the trace spans {frames} ticks at {rate} Hz, above the limit of {MAX_FRAMES} frames",
                trace_path.display()
            )));
        }
    }
    let positions = || trace.ticks(rate).map(|(tick, p)| (tick, p.x_mm, p.y_mm));
    if let Some(path) = elements {
        let lookup = PointLookup::new(view, PointLookup::DEFAULT_TOLERANCE_MM).ok_or_else(|| {
            CliError::input(anyhow::anyhow!(
                "{shown} has no footprints (chunk FOOT, format 2.1) to name what the finger touches; \
                 rebuild it from its drawing with `taxel build`"
            ))
        })?;
        let csv = touched(&lookup, positions());
        io::write_file(path, csv.as_bytes())?;
    }
    let played = match out {
        Some(path) => {
            let p = io::write_with(path, |w| latero_frames(&player, positions(), w))?;
            outln!("wrote {}: {} frames of {} actuators", path.display(), p.frames, player.actuator_count())?;
            p
        }
        None => stdout::stream(|w| latero_frames(&player, positions(), w))?,
    };
    if played.frames == 0 {
        eprintln!(
            "note: {}: no tick of the {rate} Hz clock falls between the trace's first and last times",
            trace_path.display()
        );
    }
    if played.clamped_frames > 0 {
        eprintln!(
            "note: in {} of {} frames overlapping layers summed past full deflection and were clamped \
             ({} actuator samples)",
            played.clamped_frames, played.frames, played.clamped_samples
        );
    }
    Ok(())
}

/// One row each time the element under the carrier changes (and at the
/// first tick): `tick,x_mm,y_mm,element,id,line`, empty fields for nothing.
fn touched(lookup: &PointLookup, positions: impl Iterator<Item = (taxel_format::Tick, f64, f64)>) -> String {
    let mut out = String::from("tick,x_mm,y_mm,element,id,line\n");
    let mut last: Option<Option<u32>> = None;
    for (tick, x, y) in positions {
        let hit = lookup.under(x, y);
        let key = hit.map(|h| h.source);
        if last == Some(key) {
            continue;
        }
        last = Some(key);
        let (name, id, line) = match hit {
            Some(h) => {
                let e = h.entry;
                (h.name(), e.map_or("", |e| e.id.as_str()), e.map_or(String::new(), |e| e.line.to_string()))
            }
            None => (String::new(), "", String::new()),
        };
        let _ = writeln!(out, "{},{x:.3},{y:.3},{},{},{line}", tick.0, csv_field(&name), csv_field(id));
    }
    out
}

/// A CSV field, quoted when it holds a comma, a quote or a line break.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) { format!("\"{}\"", s.replace('"', "\"\"")) } else { s.to_string() }
}
