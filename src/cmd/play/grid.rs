//! `taxel play` for grid bundles (Tactile Brush strokes). Strokes play in
//! time from tick 0, so no trace is needed: `--out DRIVE.wav` writes the
//! multichannel drive signal (one channel per actuator, the profile's audio
//! rate), any other `--out` (or standard output) the frames CSV
//! `tick,a0,a1,...` with each actuator's amplitude (0..1) from tick 0 to the
//! end of the last stroke. Files are written atomically.

use std::io::{self, BufWriter, Write};
use std::path::Path;
use std::process::ExitCode;

use anyhow::{Context, Result};
use taxel_format::{BundleView, Tick};
use taxel_runtime::grid::{ActuatorDrive, GridPlayer};
use taxel_runtime::sinks::wav::{SampleBits, write_wav_file};

pub fn run(bundle: &Path, view: &BundleView<'_>, trace: Option<&Path>, out: Option<&Path>) -> Result<ExitCode> {
    let shown = bundle.display();
    let player = match GridPlayer::new(view) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {shown}: {e}");
            return Ok(ExitCode::from(1));
        }
    };
    if let Some(t) = trace {
        eprintln!("note: {shown} is a grid bundle: its strokes play in time, so the trace {} is not used", t.display());
    }
    let is_wav = out.and_then(|p| p.extension()).is_some_and(|e| e.eq_ignore_ascii_case("wav"));
    match out {
        Some(path) if is_wav => {
            let bits = SampleBits::for_output_bits(view.manifest().profile.output_bits);
            let s = match write_wav_file(path, &player, bits) {
                Ok(s) => s,
                Err(e) => {
                    eprintln!("error: {e}");
                    return Ok(ExitCode::from(2));
                }
            };
            println!(
                "wrote {}: {} channels, {} Hz, {}-bit, {:.3} s",
                path.display(),
                s.channels,
                s.sample_rate,
                s.bits,
                s.frames as f64 / s.sample_rate as f64
            );
            if s.clamped_frames > 0 {
                eprintln!(
                    "note: in {} of {} sample frames an actuator shared by overlapping points was clamped to full drive",
                    s.clamped_frames, s.frames
                );
            }
        }
        Some(path) => {
            let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
            let tmp = tempfile::Builder::new()
                .prefix(".taxel-frames-")
                .tempfile_in(dir)
                .with_context(|| format!("cannot write in {}", dir.display()))?;
            let written = write_frames(&player, BufWriter::new(tmp.as_file()))
                .and_then(|_| tmp.as_file().sync_all())
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
                .and_then(|_| tmp.persist(path).map_err(|e| anyhow::anyhow!("{}: {}", path.display(), e.error)));
            if let Err(e) = written {
                eprintln!("error: {e}");
                return Ok(ExitCode::from(2));
            }
            println!(
                "wrote {}: {} frames of {} actuators",
                path.display(),
                player.end().0 + 1,
                player.actuator_count()
            );
        }
        None => {
            let stdout = io::stdout();
            if let Err(e) = write_frames(&player, BufWriter::new(stdout.lock()))
                && e.kind() != io::ErrorKind::BrokenPipe
            {
                eprintln!("error: standard output: {e}");
                return Ok(ExitCode::from(2));
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// Frames CSV: `tick,a0,...` from tick 0 to the end of the last stroke
/// (inclusive, so the stream ends at rest).
fn write_frames(player: &GridPlayer<'_>, mut w: impl Write) -> io::Result<()> {
    let n = player.actuator_count();
    let mut header = String::from("tick");
    for a in 0..n {
        header += &format!(",a{a}");
    }
    writeln!(w, "{header}")?;
    let mut out = vec![ActuatorDrive::default(); n];
    for tick in 0..=player.end().0 {
        player.frame(Tick(tick), &mut out);
        write!(w, "{tick}")?;
        for a in &out {
            write!(w, ",{:.6}", a.amplitude)?;
        }
        writeln!(w)?;
    }
    w.flush()
}
