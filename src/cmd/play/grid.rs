//! `taxel play` for grid bundles (Tactile Brush strokes). Strokes play in
//! time from tick 0, so no trace is needed: `--out DRIVE.wav` writes the
//! multichannel drive signal (one channel per actuator, the profile's audio
//! rate), any other `--out` (or standard output) the frames CSV
//! `tick,a0,a1,...` with each actuator's amplitude (0..1) from tick 0 to the
//! end of the last stroke.

use std::path::Path;

use taxel_format::BundleView;
use taxel_runtime::grid::GridPlayer;
use taxel_runtime::sinks::wav::SampleBits;

use crate::error::{CliError, CmdResult};
use crate::io::{self, stdout, stdout::outln};
use crate::playback::{grid_frames, write_drive};

pub fn run(bundle: &Path, view: &BundleView<'_>, trace: Option<&Path>, out: Option<&Path>) -> CmdResult {
    let shown = bundle.display();
    let player = GridPlayer::new(view).map_err(|e| CliError::input(anyhow::anyhow!("{shown}: {e}")))?;
    if let Some(t) = trace {
        eprintln!("note: {shown} is a grid bundle: its strokes play in time, so the trace {} is not used", t.display());
    }
    let is_wav = out.and_then(|p| p.extension()).is_some_and(|e| e.eq_ignore_ascii_case("wav"));
    match out {
        Some(path) if is_wav => {
            let bits = SampleBits::for_output_bits(view.manifest().profile.output_bits);
            let s = write_drive(path, &player, bits)?;
            outln!(
                "wrote {}: {} channels, {} Hz, {}-bit, {:.3} s",
                path.display(),
                s.channels,
                s.sample_rate,
                s.bits,
                s.frames as f64 / s.sample_rate as f64
            )?;
            if s.clamped_frames > 0 {
                eprintln!(
                    "note: in {} of {} sample frames an actuator shared by overlapping points was clamped to full drive",
                    s.clamped_frames, s.frames
                );
            }
            Ok(())
        }
        Some(path) => {
            let frames = io::write_with(path, |w| grid_frames(&player, w))?;
            outln!("wrote {}: {frames} frames of {} actuators", path.display(), player.actuator_count())
        }
        None => stdout::stream(|w| grid_frames(&player, w)).map(drop),
    }
}
