//! The exact reference for brushed strokes: the unquantised (f64 ms)
//! schedule of every stroke, planned from the brush requests of the
//! compiler's layer plan (`taxel_compiler::latero::plan`), against the
//! integer ticks stored in the bundle.

use std::path::Path;

use anyhow::{Result, anyhow, bail};
use taxel_compiler::brush::plan_strokes;
use taxel_format::{Bundle, Chunk};

use crate::cli::CompileOpts;

/// Errors of one bundle's schedule against the unquantised one, in ms.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScheduleError {
    /// Largest onset error.
    pub max_onset_ms: f64,
    /// Largest duration error.
    pub max_duration_ms: f64,
    /// RMS over onsets and durations together.
    pub rms_ms: f64,
    /// Points compared.
    pub points: usize,
}

/// Plans the strokes of `input` in f64, from the compiler's requests, and compares them with `bundle`'s ticks.
pub fn schedule_error(input: &Path, opts: &CompileOpts, bundle: &Bundle) -> Result<ScheduleError> {
    let svg = crate::io::read_input_text(input)?;
    let profile = bundle.manifest.profile;
    let options = crate::compile::compile_options(opts)?.map_err(|d| anyhow!("{}", d.message))?;
    let options = taxel_compiler::CompileOptions { profile, ..options };
    let resolved = taxel_compiler::pipeline::resolve(&svg, &options);
    let Some(drawing) = resolved.drawing else {
        let why = resolved.diagnostics.first().map_or("the SVG could not be read".into(), |d| d.message.clone());
        bail!("{}: {why}", input.display());
    };
    let Some(table) = bundle.chunks.iter().find_map(|c| if let Chunk::Strokes(t) = c { Some(t) } else { None }) else {
        bail!("{}: the bundle has no strokes", input.display());
    };
    // The brush requests the compiler planned its strokes from.
    let requests = taxel_compiler::latero::plan(&drawing, &options).brush;
    let plans: Vec<_> = plan_strokes(&requests, &profile, &mut Vec::new()).into_iter().flatten().collect();
    if plans.len() != table.strokes.len() {
        bail!("{} strokes planned, {} in the bundle", plans.len(), table.strokes.len());
    }
    let ms = 1000.0 / profile.rate_hz.max(1) as f64;
    let (mut mo, mut md, mut sum2, mut n) = (0.0f64, 0.0f64, 0.0f64, 0usize);
    for (plan, stroke) in plans.iter().zip(&table.strokes) {
        if plan.points.len() != stroke.points.len() {
            bail!("a stroke has {} points planned again and {} in the bundle", plan.points.len(), stroke.points.len());
        }
        for (p, q) in plan.points.iter().zip(&stroke.points) {
            let onset = (stroke.start.0 as f64 + q.onset as f64) * ms;
            let eo = (onset - (plan.start_ms + p.onset_ms)).abs();
            let ed = (q.duration as f64 * ms - (p.end_ms - p.onset_ms)).abs();
            mo = mo.max(eo);
            md = md.max(ed);
            sum2 += eo * eo + ed * ed;
            n += 2;
        }
    }
    Ok(ScheduleError { max_onset_ms: mo, max_duration_ms: md, rms_ms: (sum2 / n.max(1) as f64).sqrt(), points: n / 2 })
}

/// The largest onset or duration error in ms (for the demo's summary).
pub fn max_schedule_error(input: &Path, opts: &CompileOpts, bundle: &Bundle) -> Result<f64> {
    schedule_error(input, opts, bundle).map(|e| e.max_onset_ms.max(e.max_duration_ms))
}

/// Tick rates (Hz) on the stroke ladder; the profile's own rate is added when missing.
pub const RATE_LADDER: [u32; 5] = [250, 500, 1000, 2000, 4000];

/// The tick-rate ladder of a grid scene: one `strokes` row per rate, the
/// error being the schedule's largest onset or duration error in ms.
pub fn ladder(input: &Path, opts: &CompileOpts, base: &Bundle, default_only: bool) -> Result<Vec<super::Row>> {
    use std::time::Instant;
    use taxel_format::{BundleView, Tick};
    use taxel_runtime::grid::{ActuatorDrive, GridPlayer};

    let svg = crate::io::read_input_text(input)?;
    let default_rate = base.manifest.profile.rate_hz;
    let mut rates: Vec<u32> = RATE_LADDER.to_vec();
    if !rates.contains(&default_rate) {
        rates.push(default_rate);
        rates.sort_unstable();
    }
    if default_only {
        rates.retain(|&r| r == default_rate);
    }
    let options = crate::compile::compile_options(opts)?.map_err(|d| anyhow!("{}", d.message))?;
    let mut rows = Vec::new();
    for rate in rates {
        let mut profile = base.manifest.profile;
        profile.rate_hz = rate;
        let o = taxel_compiler::CompileOptions { profile, ..options.clone() };
        let t0 = Instant::now();
        let compiled = taxel_compiler::compile_svg(&svg, &o);
        let compile_ms = t0.elapsed().as_secs_f64() * 1000.0;
        let Some(bundle) = compiled.bundle else {
            bail!("{} does not compile at {rate} Hz", input.display());
        };
        let err = schedule_error(input, opts, &bundle)?;
        let bytes = bundle.to_bytes().map_err(|e| anyhow!("{e}"))?;
        let view = BundleView::parse(&bytes).map_err(|e| anyhow!("{e}"))?;
        let player = GridPlayer::new(&view).map_err(|e| anyhow!("{e}"))?;
        let ticks = player.end().0 + 1;
        let mut drive = vec![ActuatorDrive::default(); player.actuator_count()];
        let mut best = f64::INFINITY;
        for _ in 0..3 {
            let t0 = Instant::now();
            for t in 0..ticks {
                player.frame(Tick(t), std::hint::black_box(&mut drive));
            }
            best = best.min(t0.elapsed().as_secs_f64());
        }
        rows.push(super::Row {
            kernel: "strokes".into(),
            setting: rate as f64,
            unit: "Hz".into(),
            default: rate == default_rate,
            compile_ms,
            bundle_bytes: super::stored_len(&bytes)?,
            frame_us: best * 1e6 / ticks as f64,
            max_error: err.max_onset_ms.max(err.max_duration_ms),
            rms_error: err.rms_ms,
            step_rms_error: None,
            far_error: None,
            far_rms_error: None,
            corner_error: None,
            edge_error_mm: None,
            corner_edge_error_mm: None,
            lattice_mm: None,
            fine_detail: None,
            unfelt: None,
            error_unit: "ms".into(),
            frames: ticks as usize,
            run_ms: compile_ms + best * 1000.0,
            on_front: false,
        });
    }
    Ok(rows)
}
