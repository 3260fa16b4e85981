//! Playing a bundle into an output file or stream: the pieces `taxel play`
//! and the demo share. Frames go through the runtime's CSV sink
//! ([`taxel_runtime::sinks::frames`]).

use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::Path;

use taxel_format::{Mm, Tick};
use taxel_runtime::finger::{FingerPlayer, Touch};
use taxel_runtime::grid::{ActuatorDrive, GridPlayer};
use taxel_runtime::latero::{LateroPlayer, Layer};
use taxel_runtime::sinks::frames::FramesCsv;
use taxel_runtime::sinks::wav::{SampleBits, WavSummary, write_wav};
use taxel_runtime::trace::Trace;

/// What a laterotactile run produced.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Played {
    /// Frames written.
    pub frames: u64,
    /// Frames in which overlapping layers summed past full deflection.
    pub clamped_frames: u64,
    /// Actuator samples clamped over all frames.
    pub clamped_samples: u64,
}

/// Frames CSV (`tick,a0,…`, output codes) of a laterotactile player at each
/// `(tick, x_mm, y_mm)` of `positions`.
pub fn latero_frames<'a, S: AsRef<[Layer<'a>]> + AsMut<[Layer<'a>]>>(
    player: &LateroPlayer<'a, S>,
    positions: impl IntoIterator<Item = (Tick, f64, f64)>,
    out: impl Write,
) -> io::Result<Played> {
    let mut csv = FramesCsv::new(out, player.actuator_count())?;
    let mut codes = vec![0u16; player.actuator_count()];
    let mut played = Played::default();
    for (tick, x, y) in positions {
        let stats = player.frame(tick, Mm(x as f32), Mm(y as f32), &mut codes);
        csv.frame(tick, &codes)?;
        played.frames += 1;
        if stats.clamped > 0 {
            played.clamped_frames += 1;
            played.clamped_samples += stats.clamped as u64;
        }
    }
    csv.finish()?;
    Ok(played)
}

/// Frames CSV (`tick,a0,…`, amplitudes 0..1) of a grid player from tick 0
/// to the end of the last stroke (inclusive, so the stream ends at rest).
/// Returns the frames written.
pub fn grid_frames(player: &GridPlayer<'_>, out: impl Write) -> io::Result<u64> {
    let n = player.actuator_count();
    let mut csv = FramesCsv::new(out, n)?;
    let mut drive = vec![ActuatorDrive::default(); n];
    let mut levels = vec![0f32; n];
    for tick in 0..=player.end().0 {
        player.frame(Tick(tick), &mut drive);
        for (l, d) in levels.iter_mut().zip(&drive) {
            *l = d.amplitude;
        }
        csv.levels(Tick(tick), &levels)?;
    }
    csv.finish()?;
    Ok(player.end().0 + 1)
}

/// The motors CSV `t_ms,left,down,right,period_ms` of a finger player along
/// `trace`, one row per trace sample, for a profile running at `rate_hz`:
/// the three actuators' intensities (0..1; the active one carries D, the
/// others 0) and the active actuator's modulating period in ms, empty when
/// all are off. The player runs on touch events, as the paper's tablet did;
/// the tick given to it is the trace time rounded to the profile's rate.
pub fn finger_motors(
    player: &mut FingerPlayer<'_>,
    trace: &Trace,
    rate_hz: u32,
    mut out: impl Write,
) -> io::Result<()> {
    let rate = rate_hz as f64;
    let mut line = String::from("t_ms,left,down,right,period_ms\n");
    out.write_all(line.as_bytes())?;
    for s in trace.samples() {
        // The parser bounds times, so the tick is finite and non-negative.
        let tick = Tick((s.t_ms * rate / 1000.0).round() as u64);
        let f = player.sample(Touch { tick, x: Mm(s.x_mm as f32), y: Mm(s.y_mm as f32), contact: s.contact });
        let [l, d, r] = f.levels();
        line.clear();
        let _ = write!(line, "{},{l:.4},{d:.4},{r:.4},", s.t_ms);
        if f.active.is_some() {
            let _ = write!(line, "{:.2}", f.period_ms);
        }
        line.push('\n');
        out.write_all(line.as_bytes())?;
    }
    out.flush()
}

/// The multichannel drive signal of a grid player as a WAV file, written
/// through [`crate::io`] like every other output.
pub fn write_drive(path: &Path, player: &GridPlayer<'_>, bits: SampleBits) -> Result<WavSummary, crate::io::IoError> {
    crate::io::write_with(path, |w| write_wav(w, player, bits).map_err(io::Error::other))
}
