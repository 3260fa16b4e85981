//! `taxel play` for laterotactile bundles: the carrier follows an
//! exploration trace, and every tick of the profile's rate from the trace's
//! first time to its last gives one frame of output codes
//! (`tick,a0,…,a{n−1}`), to `--out` (written atomically) or standard output.

use std::io::{self, BufWriter, Write};
use std::path::Path;
use std::process::ExitCode;

use anyhow::{Context, Result};
use taxel_format::{BundleView, Mm};
use taxel_runtime::latero::{LateroPlayer, Layer};
use taxel_runtime::sinks::frames::FramesCsv;
use taxel_runtime::trace::Trace;

/// Most frames one run may write (a little over 24 hours at 1 kHz); a trace
/// asking for more is refused instead of filling the disk.
const MAX_FRAMES: u64 = 100_000_000;

pub fn run(bundle: &Path, view: &BundleView<'_>, trace: Option<&Path>, out: Option<&Path>) -> Result<ExitCode> {
    let shown = bundle.display();
    // Storage for every chunk is always enough for the player's layers.
    let storage = vec![Layer::EMPTY; view.chunk_count() as usize];
    let player = match LateroPlayer::with_storage(view, storage) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {shown}: {e}");
            return Ok(ExitCode::from(1));
        }
    };
    let Some(trace_path) = trace else {
        eprintln!(
            "error: {shown} is a laterotactile bundle: playing it needs an exploration trace (--trace CSV with t_ms,x_mm,y_mm)"
        );
        return Ok(ExitCode::from(2));
    };
    let text = match std::fs::read(trace_path) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: cannot read {}: {e}", trace_path.display());
            return Ok(ExitCode::from(2));
        }
    };
    let trace = match Trace::parse(&text[..]) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {}: {e}", trace_path.display());
            return Ok(ExitCode::from(1));
        }
    };
    let rate = view.manifest().profile.rate_hz;
    if let Some((first, last)) = trace.tick_range(rate) {
        let frames = last.0 - first.0 + 1;
        if frames > MAX_FRAMES {
            eprintln!(
                "error: {}: the trace spans {frames} ticks at {rate} Hz, above the limit of {MAX_FRAMES} frames",
                trace_path.display()
            );
            return Ok(ExitCode::from(1));
        }
    }
    let result = match out {
        Some(path) => {
            let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
            let tmp = tempfile::Builder::new()
                .prefix(".taxel-frames-")
                .tempfile_in(dir)
                .with_context(|| format!("cannot write in {}", dir.display()))?;
            let played = play(&player, &trace, rate, BufWriter::new(tmp.as_file()))
                .and_then(|p| tmp.as_file().sync_all().map(|_| p))
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
                .and_then(|p| {
                    tmp.persist(path).map(|_| p).map_err(|e| anyhow::anyhow!("{}: {}", path.display(), e.error))
                });
            match played {
                Ok(p) => {
                    println!("wrote {}: {} frames of {} actuators", path.display(), p.frames, player.actuator_count());
                    Ok(p)
                }
                Err(e) => Err(e),
            }
        }
        None => {
            let stdout = io::stdout();
            match play(&player, &trace, rate, BufWriter::new(stdout.lock())) {
                Err(e) if e.kind() == io::ErrorKind::BrokenPipe => return Ok(ExitCode::SUCCESS),
                r => r.map_err(|e| anyhow::anyhow!("standard output: {e}")),
            }
        }
    };
    match result {
        Ok(p) => {
            if p.frames == 0 {
                eprintln!(
                    "note: {}: no tick of the {rate} Hz clock falls between the trace's first and last times",
                    trace_path.display()
                );
            }
            if p.clamped_frames > 0 {
                eprintln!(
                    "note: in {} of {} frames overlapping layers summed past full deflection and were clamped \
                     ({} actuator samples)",
                    p.clamped_frames, p.frames, p.clamped_samples
                );
            }
            Ok(ExitCode::SUCCESS)
        }
        Err(e) => {
            eprintln!("error: {e:#}");
            Ok(ExitCode::from(2))
        }
    }
}

/// What a run produced.
struct Played {
    frames: u64,
    clamped_frames: u64,
    clamped_samples: u64,
}

fn play<'a>(
    player: &LateroPlayer<'a, Vec<Layer<'a>>>,
    trace: &Trace,
    rate: u32,
    out: impl Write,
) -> io::Result<Played> {
    let mut csv = FramesCsv::new(out, player.actuator_count())?;
    let mut codes = vec![0u16; player.actuator_count()];
    let mut played = Played { frames: 0, clamped_frames: 0, clamped_samples: 0 };
    for (tick, p) in trace.ticks(rate) {
        let stats = player.frame(tick, Mm(p.x_mm as f32), Mm(p.y_mm as f32), &mut codes);
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
