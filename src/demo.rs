//! The demo, `taxel` with no arguments: build every scene of
//! `examples/examples.toml` for its profile, play each on its example trace,
//! measure it against the exact reference, and print a summary. Bundles,
//! previews and frames go under `target/taxel-demo/`.
//!
//! A scene that fails is reported in its row and the demo goes on; the exit
//! code is 1 when any scene failed.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use rayon::prelude::*;
use taxel_format::{BundleView, Chunk, Family, Tick};
use taxel_runtime::finger::FingerPlayer;
use taxel_runtime::grid::{ActuatorDrive, GridPlayer};
use taxel_runtime::latero::LateroPlayer;
use taxel_runtime::pins::PinsPlayer;
use taxel_runtime::sinks::wav::SampleBits;

use crate::cli::CompileOpts;
use crate::error::{CliError, CmdResult};
use crate::examples::{Scene, read_index};
use crate::io::{self, stdout};
use crate::playback;
use crate::report::{self, Prepared};

/// Frames compared with the reference per scene (evenly spaced over its trace).
const DEMO_EVAL_FRAMES: usize = 4_000;

/// One line of the summary.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// Scene name.
    pub scene: String,
    /// Profile name.
    pub profile: String,
    /// What happened.
    pub result: Result<Figures, String>,
}

/// The figures of a scene that built and played.
#[derive(Debug, Clone)]
pub struct Figures {
    /// Layer chunks in the bundle.
    pub layers: usize,
    /// Bundle size.
    pub bundle_bytes: usize,
    /// Build wall time, ms.
    pub build_ms: f64,
    /// Runtime cost per frame, µs.
    pub frame_us: f64,
    /// Frames played.
    pub frames: usize,
    /// Largest error against the exact reference, with its unit; `None` when there is no reference yet.
    pub max_error: Option<(f64, String)>,
    /// The report's measures of a laterotactile scene (`taxel report`'s default rung).
    pub measures: Option<Measures>,
}

/// How close a laterotactile scene plays to its exact drawing, in the
/// measures `taxel report` defines (docs/report.md).
#[derive(Debug, Clone, Copy)]
pub struct Measures {
    /// Where a felt edge lies from the drawn edge, away from corners, mm
    /// (`None` when the scene has no distance layer).
    pub edge_mm: Option<f64>,
    /// Largest value error farther than [`report::EDGE_BAND_MM`] from every
    /// exact edge and away from corners, output steps.
    pub far_steps: f64,
    /// Root-mean-square error over every actuator and frame, output steps.
    pub rms_steps: f64,
}

impl Measures {
    fn cell(&self) -> String {
        let edge = self.edge_mm.map_or("n/a".to_string(), |e| format!("{e:.3} mm"));
        format!("edge {edge}, far {:.1}, RMS {:.2}", self.far_steps, self.rms_steps)
    }
}

/// The demo entry point: examples next to the current folder, else the source tree's.
pub fn main() -> CmdResult {
    let root = [PathBuf::from("."), PathBuf::from(env!("CARGO_MANIFEST_DIR"))]
        .into_iter()
        .find(|r| r.join("examples/examples.toml").is_file())
        .context("no examples/examples.toml here or in the source tree: run the demo from the taxel repository")?;
    let t0 = Instant::now();
    let outcomes = run(&root.join("examples"), &root.join("target/taxel-demo"), None)?;
    stdout::print(&summary(&outcomes))?;
    stdout::outln!(
        "wall time {:.1} s; output in {}",
        t0.elapsed().as_secs_f64(),
        root.join("target/taxel-demo").display()
    )?;
    match outcomes.iter().filter(|o| o.result.is_err()).count() {
        0 => Ok(()),
        n => Err(CliError::input(anyhow::anyhow!("{n} scenes failed (see the summary)"))),
    }
}

/// Builds and plays the scenes of `examples/examples.toml` (only those named
/// in `only`, when given) into `out`; writes `out/summary.txt`.
pub fn run(examples: &Path, out: &Path, only: Option<&[&str]>) -> Result<Vec<Outcome>> {
    let scenes = read_index(&examples.join("examples.toml"))?;
    let scenes: Vec<Scene> = scenes.into_iter().filter(|s| only.is_none_or(|o| o.contains(&s.name.as_str()))).collect();
    for sub in ["bundles", "frames", "previews"] {
        std::fs::create_dir_all(out.join(sub)).with_context(|| format!("cannot create {}", out.join(sub).display()))?;
    }
    let outcomes: Vec<Outcome> = scenes
        .par_iter()
        .map(|s| Outcome {
            scene: s.name.clone(),
            profile: s.profile.clone(),
            result: scene(examples, out, s).map_err(|e| format!("{e:#}")),
        })
        .collect();
    io::write_file(&out.join("summary.txt"), summary(&outcomes).as_bytes())?;
    Ok(outcomes)
}

fn scene(examples: &Path, out: &Path, s: &Scene) -> Result<Figures> {
    let input = examples.join(&s.input);
    let opts = CompileOpts {
        profile: Some(s.profile.clone()),
        style: s.style.as_ref().map(|p| examples.join(p)),
        ..CompileOpts::default()
    };
    // A print profile makes the medium's file and its felt preview, no bundle.
    let profile = io::load::profile(&s.profile)?;
    if profile.family() == Family::Print {
        return print_scene(&input, out, s, &opts);
    }
    let (bundle, build_ms) = report::compile(&input, &opts, None)?;
    // The file is the stored form, as `taxel build` writes it; the players read the plain bundle.
    let bytes = bundle.to_bytes().map_err(|e| anyhow::anyhow!("{e}"))?;
    let file = taxel_format::stored::store(&bytes).map_err(|e| anyhow::anyhow!("{e}"))?;
    io::write_file(&out.join("bundles").join(format!("{}.taxel", s.name)), &file)?;
    // The preview is drawn from the bundle alone, as `taxel preview B.taxel` does.
    let picture = taxel_compiler::preview::render_bundle(&bundle, None);
    io::write_file(&out.join("previews").join(format!("{}.png", s.name)), &io::png::encode_picture(&picture)?)?;
    let layers = bundle
        .chunks
        .iter()
        .filter(|c| !matches!(c, Chunk::Provenance(_) | Chunk::Footprints(_) | Chunk::Raw(_)))
        .count();
    let trace = s.trace.as_ref().map(|t| examples.join(t));
    match bundle.manifest.profile.family() {
        Family::Laterotactile => {
            let prep = Prepared::new(&input, &opts, &bundle, trace.as_deref(), DEMO_EVAL_FRAMES)?;
            let reference = prep.reference_frames_of("all", &bundle);
            let m = prep.measure(&bundle, &reference, &prep.reference_frames("all"), "all")?;
            write_frames(&out.join("frames").join(format!("{}.csv", s.name)), &bytes, &prep.positions)?;
            Ok(Figures {
                layers,
                bundle_bytes: file.len(),
                build_ms,
                frame_us: m.frame_us,
                frames: prep.positions.len(),
                max_error: Some((m.max_error, format!("{}-bit steps", prep.profile.output_bits))),
                measures: Some(Measures { edge_mm: m.edge.edge_mm, far_steps: m.far_error, rms_steps: m.rms_error }),
            })
        }
        Family::Grid => {
            let view = BundleView::parse(&bytes).map_err(|e| anyhow::anyhow!("{e}"))?;
            let player = GridPlayer::new(&view).map_err(|e| anyhow::anyhow!("{e}"))?;
            let wav = out.join("frames").join(format!("{}.wav", s.name));
            let bits = SampleBits::for_output_bits(bundle.manifest.profile.output_bits);
            playback::write_drive(&wav, &player, bits)?;
            let ticks = player.end().0 + 1;
            let mut drive = vec![ActuatorDrive::default(); player.actuator_count()];
            let t0 = Instant::now();
            for t in 0..ticks {
                player.frame(Tick(t), std::hint::black_box(&mut drive));
            }
            let frame_us = t0.elapsed().as_secs_f64() * 1e6 / ticks as f64;
            let max_error = report::strokes::max_schedule_error(&input, &opts, &bundle).ok();
            Ok(Figures {
                layers,
                bundle_bytes: file.len(),
                build_ms,
                frame_us,
                frames: ticks as usize,
                max_error: max_error.map(|e| (e, "ms".to_string())),
                measures: None,
            })
        }
        Family::Finger => {
            let Some(t) = trace.as_deref() else { anyhow::bail!("a finger scene needs a touch trace") };
            let tr = report::load_trace(&input, Some(t), &bundle)?;
            let (max, sample_us) = report::mesh::max_height_error(&input, &bundle, &tr.trace)?;
            write_motors(&out.join("frames").join(format!("{}.csv", s.name)), &bytes, &tr.trace)?;
            Ok(Figures {
                layers,
                bundle_bytes: file.len(),
                build_ms,
                frame_us: sample_us,
                frames: tr.trace.samples().len(),
                max_error: Some((max, "mm of height".to_string())),
                measures: None,
            })
        }
        // Print scenes are made above, by `print_scene`; no bundle holds a print profile.
        Family::Print => anyhow::bail!("a print profile makes no bundle"),
        Family::Pins => {
            // A pin display shows still pages: the figures are the frame cost
            // over every page for a second of 1 ms ticks (blinking included),
            // and the device's own files beside the bundle.
            let view = BundleView::parse(&bytes).map_err(|e| anyhow::anyhow!("{e}"))?;
            let player = PinsPlayer::new(&view).map_err(|e| anyhow::anyhow!("{e}"))?;
            let mut frame = vec![0u8; player.frame_len()];
            let (across, down) = player.pages();
            let t0 = Instant::now();
            let mut frames = 0usize;
            for page in 0..across * down {
                let vp = player.page(page).unwrap_or_default();
                for t in 0..1000 {
                    player.frame(Tick(t), std::hint::black_box(vp), &mut frame);
                    frames += 1;
                }
            }
            let frame_us = t0.elapsed().as_secs_f64() * 1e6 / frames.max(1) as f64;
            if let Some(image) = bundle.pin_image() {
                let art = taxel_compiler::pins::export::unicode(image);
                io::write_file(&out.join("frames").join(format!("{}.txt", s.name)), art.as_bytes())?;
            }
            Ok(Figures {
                layers,
                bundle_bytes: file.len(),
                build_ms,
                frame_us,
                frames,
                max_error: None,
                measures: None,
            })
        }
    }
}

/// A print scene: the medium's file under `prints/` (its PDF or STL) and the
/// felt preview; the figures are the marks on the graphic's page, the file's
/// size and the build time (nothing is played).
fn print_scene(input: &Path, out: &Path, s: &Scene, opts: &CompileOpts) -> Result<Figures> {
    let t0 = Instant::now();
    let compiled = crate::compile::compile_file(input, opts)?;
    let Some(sheet) = compiled.print else {
        let errors: Vec<String> = compiled.diagnostics.iter().map(|d| d.render(&input.display().to_string())).collect();
        anyhow::bail!("no print sheet: {}", errors.join("; "));
    };
    let kind = taxel_compiler::print::FileKind::for_medium(sheet.medium())[0];
    let bytes = taxel_compiler::print::write(&sheet, kind).map_err(|e| anyhow::anyhow!("{e}"))?;
    let build_ms = t0.elapsed().as_secs_f64() * 1e3;
    std::fs::create_dir_all(out.join("prints"))
        .with_context(|| format!("cannot create {}", out.join("prints").display()))?;
    io::write_file(&out.join("prints").join(format!("{}.{}", s.name, kind.extension())), &bytes)?;
    let picture = taxel_compiler::print::preview::render(&sheet);
    io::write_file(&out.join("previews").join(format!("{}.png", s.name)), &io::png::encode_picture(&picture)?)?;
    Ok(Figures {
        layers: sheet.pages.first().map_or(0, Vec::len),
        bundle_bytes: bytes.len(),
        build_ms,
        frame_us: 0.0,
        frames: 0,
        max_error: None,
        measures: None,
    })
}

/// Frames CSV (`tick,a0,…`) of a laterotactile bundle along `positions`.
fn write_frames(path: &Path, bytes: &[u8], positions: &[(u64, f64, f64)]) -> Result<()> {
    let view = BundleView::parse(bytes).map_err(|e| anyhow::anyhow!("{e}"))?;
    let player = LateroPlayer::new(&view).map_err(|e| anyhow::anyhow!("{e}"))?;
    let ticks = positions.iter().map(|&(t, x, y)| (Tick(t), x, y));
    io::write_with(path, |w| playback::latero_frames(&player, ticks, w))?;
    Ok(())
}

/// Motor output CSV (`t_ms,left,down,right,period_ms`, as `taxel play` writes it) along a touch trace.
fn write_motors(path: &Path, bytes: &[u8], trace: &taxel_runtime::trace::Trace) -> Result<()> {
    let view = BundleView::parse(bytes).map_err(|e| anyhow::anyhow!("{e}"))?;
    let mut player = FingerPlayer::new(&view).map_err(|e| anyhow::anyhow!("{e}"))?;
    let rate = view.manifest().profile.rate_hz;
    io::write_with(path, |w| playback::finger_motors(&mut player, trace, rate, w))?;
    Ok(())
}

/// The summary table, and a line saying what its accuracy column measures.
pub fn summary(outcomes: &[Outcome]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<36} {:<10} {:>6} {:>9} {:>9} {:>9} {:>9}  accuracy",
        "scene", "profile", "layers", "bytes", "build ms", "µs/frame", "frames"
    );
    let mut failed = 0;
    for o in outcomes {
        match &o.result {
            Ok(f) => {
                let err = match (&f.measures, &f.max_error) {
                    (Some(m), _) => m.cell(),
                    (None, Some((e, u))) => format!("{e:.1} {u}"),
                    (None, None) => "n/a".to_string(),
                };
                let _ = writeln!(
                    s,
                    "{:<36} {:<10} {:>6} {:>9} {:>9.1} {:>9.3} {:>9}  {}",
                    o.scene, o.profile, f.layers, f.bundle_bytes, f.build_ms, f.frame_us, f.frames, err
                );
            }
            Err(e) => {
                failed += 1;
                let _ = writeln!(s, "{:<36} {:<10} FAILED: {e}", o.scene, o.profile);
            }
        }
    }
    let _ = writeln!(s, "{} scenes, {} built and played, {failed} failed", outcomes.len(), outcomes.len() - failed);
    let _ = writeln!(
        s,
        "accuracy against the exact drawing: edge = felt edge to drawn edge, away from corners; far = largest \
         error over {} mm from any edge; RMS = over every actuator (output steps); strokes: timing; finger: height",
        report::EDGE_BAND_MM
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The demo on the map's pin scenes writes their bundles, previews (drawn
    /// pin by pin) and Unicode braille art, and times the pin player.
    #[test]
    fn demo_shows_the_pin_scenes_and_their_previews() {
        let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
        let out = tempfile::tempdir().expect("temp dir");
        let names = ["tala-map-dotpad", "tala-map-graphiti"];
        let outcomes = run(&examples, out.path(), Some(&names)).expect("runs");
        assert_eq!(outcomes.len(), 2);
        for o in &outcomes {
            let f = o.result.as_ref().unwrap_or_else(|e| panic!("{}: {e}", o.scene));
            // One pin image: the map's page, then the key's pages (tala-map
            // has three textures), each played for 1000 ticks.
            assert_eq!(f.layers, 1, "{}: one pin image", o.scene);
            assert!(f.frames >= 2000 && f.frames % 1000 == 0, "{}: {} frames", o.scene, f.frames);
            assert!(f.frame_us.is_finite() && f.frame_us > 0.0);
        }
        for n in names {
            let png = std::fs::read(out.path().join("previews").join(format!("{n}.png"))).expect("preview");
            let png = taxel_textform::png::read(&png).expect("a PNG");
            assert_eq!(png.width, 620, "{n}: 60 pins and a margin, 10 px a pin");
            let art = std::fs::read_to_string(out.path().join("frames").join(format!("{n}.txt"))).expect("art");
            assert!(art.chars().any(|c| ('\u{2801}'..='\u{28FF}').contains(&c)), "{n}: raised pins in the art");
        }
    }

    #[test]
    fn demo_writes_the_print_scenes_files_and_felt_previews() {
        let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
        let out = tempfile::tempdir().expect("temp dir");
        let names = ["tala-map-swell", "tala-map-tiger", "tala-map-print3d"];
        let outcomes = run(&examples, out.path(), Some(&names)).expect("runs");
        assert_eq!(outcomes.len(), 3);
        for o in &outcomes {
            let f = o.result.as_ref().unwrap_or_else(|e| panic!("{}: {e}", o.scene));
            assert!(f.layers > 0 && f.bundle_bytes > 0, "{}: marks and a file", o.scene);
        }
        for (n, ext, magic) in [
            ("tala-map-swell", "pdf", &b"%PDF-"[..]),
            ("tala-map-tiger", "pdf", b"%PDF-"),
            ("tala-map-print3d", "stl", &[0u8; 80][..]),
        ] {
            let bytes = std::fs::read(out.path().join("prints").join(format!("{n}.{ext}"))).expect("the file");
            assert!(bytes.starts_with(magic), "{n}.{ext}");
            let png = std::fs::read(out.path().join("previews").join(format!("{n}.png"))).expect("preview");
            let png = taxel_textform::png::read(&png).expect("a PNG");
            assert!(png.width > 1000, "{n}: the paper at 6 px/mm");
        }
    }

    /// The demo on two scenes (one per device family played) writes the
    /// summary, the bundles, the frames CSV and the WAV, and fails no scene.
    #[test]
    fn demo_on_a_subset_writes_summary_and_files() {
        let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
        let out = tempfile::tempdir().expect("temp dir");
        let outcomes = run(&examples, out.path(), Some(&["exp1-dots-2cm", "brush-2-horizontal"])).expect("runs");
        assert_eq!(outcomes.len(), 2);
        for o in &outcomes {
            let f = o.result.as_ref().unwrap_or_else(|e| panic!("{}: {e}", o.scene));
            assert!(f.layers >= 1 && f.bundle_bytes > 0 && f.frames > 0);
            assert!(f.frame_us.is_finite() && f.frame_us > 0.0);
        }
        let summary = std::fs::read_to_string(out.path().join("summary.txt")).expect("summary");
        assert!(summary.contains("exp1-dots-2cm") && summary.contains("brush-2-horizontal"), "{summary}");
        assert!(summary.contains("2 built and played, 0 failed"), "{summary}");
        // Dots are exact geometry already: the error is the last rounding to 10
        // bits (½ step) plus the runtime's f32 arithmetic, within one step.
        let dots = outcomes.iter().find(|o| o.scene == "exp1-dots-2cm").and_then(|o| o.result.as_ref().ok());
        let (err, unit) = dots.and_then(|f| f.max_error.clone()).expect("dots have a reference");
        assert!(err < 1.0 && unit == "10-bit steps", "{err} {unit}");
        // The summary prints the report's measures, not a bare "max error",
        // and says in one line what they are.
        let m = dots.and_then(|f| f.measures).expect("a latero scene has the report's measures");
        assert!(m.rms_steps <= m.far_steps.max(err) + 1e-9 && m.rms_steps < 1.0, "{m:?}");
        assert_eq!(m.edge_mm, None, "dots have no distance layer, so no edge to place: {m:?}");
        let line = summary.lines().find(|l| l.starts_with("exp1-dots-2cm")).expect("the scene's line");
        assert!(line.contains("edge n/a, far ") && line.contains(", RMS "), "{line}");
        let explained: Vec<&str> = summary.lines().filter(|l| l.starts_with("accuracy against")).collect();
        assert_eq!(explained.len(), 1, "{summary}");
        assert!(explained[0].contains("edge =") && explained[0].contains("RMS ="), "{summary}");
        // A 1 kHz stroke schedule is within one tick of the unquantised one.
        let brush = outcomes.iter().find(|o| o.scene == "brush-2-horizontal").and_then(|o| o.result.as_ref().ok());
        let (err, unit) = brush.and_then(|f| f.max_error.clone()).expect("strokes have a reference");
        assert!(err <= 1.0 + 1e-9 && unit == "ms", "{err} {unit}");
        for file in [
            "bundles/exp1-dots-2cm.taxel",
            "bundles/brush-2-horizontal.taxel",
            "frames/brush-2-horizontal.wav",
            "previews/exp1-dots-2cm.png",
            "previews/brush-2-horizontal.png",
        ] {
            assert!(out.path().join(file).is_file(), "{file} missing");
        }
        let frames = std::fs::read_to_string(out.path().join("frames/exp1-dots-2cm.csv")).expect("frames");
        assert!(frames.starts_with("tick,a0,a1,"));
        assert_eq!(frames.lines().count(), dots.map_or(0, |f| f.frames) + 1);
        // The bundle written is a valid stress2 bundle.
        let b = std::fs::read(out.path().join("bundles/exp1-dots-2cm.taxel")).expect("bundle");
        let b = taxel_format::stored::plain(&b).expect("a stored bundle");
        assert_eq!(BundleView::parse(&b).expect("valid").manifest().profile.name.as_str(), "stress2");
    }
}
