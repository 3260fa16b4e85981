//! `taxel play` for laterotactile bundles: the carrier follows an
//! exploration trace, and every tick of the profile's rate from the trace's
//! first time to its last gives one frame of output codes
//! (`tick,a0,…,a{n−1}`), to `--out` or standard output.

use std::path::Path;

use taxel_format::BundleView;
use taxel_runtime::latero::{LateroPlayer, Layer};

use crate::error::{CliError, CmdResult};
use crate::io::{self, stdout, stdout::outln};
use crate::playback::latero_frames;

/// Most frames one run may write (a little over 24 hours at 1 kHz); a trace
/// asking for more is refused instead of filling the disk.
const MAX_FRAMES: u64 = 100_000_000;

pub fn run(bundle: &Path, view: &BundleView<'_>, trace: Option<&Path>, out: Option<&Path>) -> CmdResult {
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
