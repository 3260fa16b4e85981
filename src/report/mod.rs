//! Error against run time (`taxel report`): compile a scene at a ladder of
//! settings, play each bundle on one reproducible trace, and measure every
//! output against an exact reference (docs/report.md).
//!
//! Laterotactile scenes climb the ladder of distance-field lattice pitches
//! (`--resolution` R gives a pitch of 5 / R mm, docs/layers.md). Each setting gives
//! one row per kernel present (vibration, grating, dots) and one for the whole
//! composite: a kernel's row plays only that kernel's chunks and compares them
//! with only that kernel's exact layers, so the plot shows one line per kernel.

pub mod detail;
pub mod edge;
pub mod exact;
pub mod mesh;
pub mod plot;
pub mod reference;
pub mod strokes;
pub mod trace;

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use rayon::prelude::*;
use serde::Serialize;
use taxel_format::{Bundle, BundleView, Chunk, Family, Mm, Tick};
use taxel_runtime::latero::LateroPlayer;

use crate::cli::CompileOpts;
use exact::ExactLayer;
use trace::Explored;

/// Lattice pitches (mm) of the distance layers on the ladder, coarse to
/// fine; the compiler's default (0.5 mm) is among them. A vibrating band's
/// lattice is at most half its width whatever the setting.
pub const PITCH_LADDER: [f32; 4] = [2.0, 1.0, 0.5, 0.25];
/// Half-width of the band around every exact edge left out of
/// [`Row::far_error`], mm.
pub const EDGE_BAND_MM: f64 = 0.05;
/// Most frames compared against the reference per row (evenly spaced over the trace).
pub const MAX_EVAL_FRAMES: usize = 20_000;
/// Seed of the generated sweep when the scene has no trace.
pub const SWEEP_SEED: u64 = 2024;

/// One measured setting of one kernel.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    /// `vibration`, `grating`, `dots` or `all`.
    pub kernel: String,
    /// The setting's value (px/mm for masks).
    pub setting: f64,
    /// Its unit.
    pub unit: String,
    /// Whether this is the compiler's default.
    pub default: bool,
    /// Compile time of the whole scene at this setting, ms.
    pub compile_ms: f64,
    /// Bytes of this kernel's chunks (the whole bundle for `all`).
    pub bundle_bytes: usize,
    /// Runtime cost of one frame of this kernel, µs.
    pub frame_us: f64,
    /// Largest error, in `error_unit`.
    pub max_error: f64,
    /// Root-mean-square error, in `error_unit`. For vibration and grating
    /// layers the reference maps the exact signed distance to amplitude
    /// through the layer's own edge profile (SPEC.md section 6.2: a ramp
    /// `soft` wide, or one distance `step`, 0.008 mm at the default, for a
    /// hard edge), so this counts what the representation gets wrong, not
    /// the profile's width.
    pub rms_error: f64,
    /// Root-mean-square error against ideal step edges (coverage 0 or 1),
    /// in `error_unit`: [`Row::rms_error`] plus what the edge profile's own
    /// ramp adds at actuators within half its width of an exact edge
    /// (laterotactile scenes).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step_rms_error: Option<f64>,
    /// Largest error at actuators farther than [`EDGE_BAND_MM`] from every
    /// exact edge and farther than [`edge::CORNER_RADIUS_MM`] from every
    /// corner of the kernel's vibration and grating layers, in `error_unit`
    /// (laterotactile scenes; over every compared frame).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub far_error: Option<f64>,
    /// Root-mean-square error over the same actuators as [`Row::far_error`]
    /// and [`Row::corner_error`] together (every actuator farther than
    /// [`EDGE_BAND_MM`] from every exact edge), in `error_unit`. Over all
    /// actuators, [`Row::rms_error`] also counts actuators on and near an
    /// edge (docs/report.md).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub far_rms_error: Option<f64>,
    /// As [`Row::far_error`], at the actuators within
    /// [`edge::CORNER_RADIUS_MM`] of a corner (and farther than
    /// [`EDGE_BAND_MM`] from every edge).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub corner_error: Option<f64>,
    /// Edge position error away from corners, mm: the Hausdorff distance
    /// between the half-amplitude contour of the kernel's distance layers and
    /// the exact outline, at points farther than [`edge::CORNER_RADIUS_MM`]
    /// from every corner (`edge.rs`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub edge_error_mm: Option<f64>,
    /// The edge position error within [`edge::CORNER_RADIUS_MM`] of a corner, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub corner_edge_error_mm: Option<f64>,
    /// The coarsest lattice pitch among the kernel's distance layers, mm
    /// (the setting, or less for a narrow vibrating band).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lattice_mm: Option<f64>,
    /// Where the default rung's error comes from: the share of its squared
    /// error at the lattice cells where the drawing has detail finer than
    /// the lattice, and how many such cells (`detail.rs`; the default rows
    /// of laterotactile kernels with distance layers).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fine_detail: Option<detail::Share>,
    /// Where the edge error is a feature of the drawing smaller than the
    /// lattice that is not felt at all (an island or a hole): the outline's
    /// place farthest from the played contour, when that is more than the
    /// edge target and the outline there is less than
    /// [`Row::lattice_mm`] across (`edge.rs`, [`edge::Farthest`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unfelt: Option<Unfelt>,
    /// Unit of the errors.
    pub error_unit: String,
    /// Frames compared.
    pub frames: usize,
    /// Run time of the setting: compile plus playing the whole trace, ms.
    pub run_ms: f64,
    /// No other setting of the same kernel is both faster (compile + play) and more accurate (RMS).
    pub on_front: bool,
}

/// A feature of the drawing smaller than the lattice that is not felt ([`Row::unfelt`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Unfelt {
    /// Its place on the page, mm.
    pub x_mm: f64,
    /// Its place on the page, mm.
    pub y_mm: f64,
    /// The larger side of its outline's box, mm.
    pub across_mm: f64,
    /// Its distance to the nearest felt edge, mm: the edge error it makes.
    pub edge_error_mm: f64,
}

impl Unfelt {
    /// The farthest place of an outline from the played contour, if it makes
    /// the edge error exceed its target and is smaller than the lattice
    /// `lattice_mm`. (A layer with no contour at all is infinitely far:
    /// its error is not one feature's.)
    fn of(farthest: Option<edge::Farthest>, lattice_mm: Option<f64>) -> Option<Unfelt> {
        let f = farthest?;
        let beyond = f.distance_mm > detail::EDGE_TARGET_MM && f.distance_mm.is_finite();
        (beyond && lattice_mm.is_some_and(|l| f.across_mm < l)).then_some(Unfelt {
            x_mm: f.at.0,
            y_mm: f.at.1,
            across_mm: f.across_mm,
            edge_error_mm: f.distance_mm,
        })
    }
}

/// A whole report.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    /// The input file.
    pub input: String,
    /// Profile name.
    pub profile: String,
    /// Where the trace came from.
    pub trace: String,
    /// Frames in the trace.
    pub trace_frames: usize,
    /// The rows, kernel by kernel, setting by setting.
    pub rows: Vec<Row>,
    /// Things the reader should know (layers without a reference, ...).
    pub notes: Vec<String>,
}

/// Everything a measurement needs that does not depend on the setting: the
/// trace's positions, the frames to compare, and the exact layers.
pub struct Prepared {
    /// The profile the scene was compiled for.
    pub profile: taxel_format::DeviceProfile,
    /// The exact layers.
    pub reference: Vec<ExactLayer>,
    /// The exact outline of each vibration and grating layer of `reference` (None for dots).
    pub outlines: Vec<Option<edge::Outline>>,
    /// The trace.
    pub trace: Explored,
    /// Carrier position at every tick of the trace.
    pub positions: Vec<(u64, f64, f64)>,
    /// The ticks compared against the reference (evenly spaced, at most `max_eval`).
    pub eval: Vec<(u64, f64, f64)>,
    /// Things the reader should know.
    pub notes: Vec<String>,
    /// [`Prepared::places`] of each kernel asked so far.
    places: std::sync::Mutex<std::collections::HashMap<String, std::sync::Arc<Vec<Place>>>>,
    /// [`Prepared::edge_samples`] of each reference layer (by its index in
    /// `reference`) taken so far.
    edges: std::sync::Mutex<std::collections::HashMap<usize, std::sync::Arc<Sampled>>>,
}

/// A reference layer's [`exact::EdgeSample`] at every compared actuator
/// (frame-major, as the frames), taken with `reach`.
#[derive(Debug)]
struct Sampled {
    reach: f64,
    samples: Vec<exact::EdgeSample>,
}

/// At most this many edge samples are kept between rungs (16 bytes each:
/// 128 MiB), so that a report on a map of many layers does not hold all of
/// them; the layers past it are measured afresh at each rung, as they were.
const MAX_KEPT_SAMPLES: usize = 1 << 23;

/// What one bundle measured against the reference.
#[derive(Debug, Clone)]
pub struct Measured {
    /// Bundle bytes.
    pub bytes: usize,
    /// Mean runtime cost of a frame, µs.
    pub frame_us: f64,
    /// Largest error in output steps.
    pub max_error: f64,
    /// RMS error in output steps.
    pub rms_error: f64,
    /// RMS error in output steps against ideal step edges.
    pub step_rms_error: f64,
    /// Largest error in output steps at actuators away from every exact edge and corner.
    pub far_error: f64,
    /// RMS error in output steps at actuators away from every exact edge.
    pub far_rms_error: f64,
    /// Largest error in output steps at actuators near a corner and away from every exact edge.
    pub corner_error: Option<f64>,
    /// Edge position error, mm.
    pub edge: edge::EdgeError,
    /// The coarsest lattice pitch among the distance layers, mm.
    pub lattice_mm: Option<f64>,
    /// The sum of the squared errors (output steps²) of every compared actuator.
    pub square_error_sum: f64,
    /// The compared actuators off by more than
    /// [`detail::CLASSIFIED_ABOVE_STEPS`]: page position and squared error,
    /// for [`detail::share`].
    pub off: Vec<((f64, f64), f64)>,
}

impl Prepared {
    /// Prepares the reference for a laterotactile scene compiled as `base`.
    pub fn new(
        input: &Path,
        opts: &CompileOpts,
        base: &Bundle,
        trace: Option<&Path>,
        max_eval: usize,
    ) -> Result<Prepared> {
        let profile = base.manifest.profile;
        if profile.family() != Family::Laterotactile {
            bail!(
                "{}: the exact reference covers laterotactile scenes; {} is a {:?} profile and its reference is not available yet",
                input.display(),
                profile.name.as_str(),
                profile.family()
            );
        }
        let svg = crate::io::read_input_text(input)?;
        let options = crate::compile::compile_options(opts)?.map_err(|d| anyhow::anyhow!("{}", d.message))?;
        let (reference, missing) =
            reference::exact_layers(&svg, base, &options).map_err(|e| anyhow::anyhow!("{}: {e}", input.display()))?;
        let mut notes: Vec<String> = missing
            .iter()
            .map(|m| format!("no exact geometry for the layer of {m}; left out of the reference"))
            .collect();
        let trace = load_trace(input, trace, base)?;
        let positions = trace.positions(profile.rate_hz);
        let stride = positions.len().div_ceil(max_eval.max(1)).max(1);
        let eval: Vec<(u64, f64, f64)> = positions.iter().step_by(stride).copied().collect();
        if stride > 1 {
            notes.push(format!("errors are measured on every {} of {} frames", ordinal(stride), positions.len()));
        }
        let surface = (profile.surface_w_mm as f64, profile.surface_h_mm as f64);
        let outlines = reference.iter().map(|l| region_of(l).map(|r| edge::Outline::new(r, surface))).collect();
        Ok(Prepared {
            profile,
            reference,
            outlines,
            trace,
            positions,
            eval,
            notes,
            places: Default::default(),
            edges: Default::default(),
        })
    }

    /// Reference frames (δ in 0..=1, actuator-major per frame) of `kernel`'s
    /// layers at the compared ticks, with ideal step edges.
    pub fn reference_frames(&self, kernel: &str) -> Vec<f64> {
        self.frames_of(kernel, None)
    }

    /// Reference frames of `kernel`'s layers with the edge profile of
    /// `bundle`'s layers: each exact layer's edge ramps over the `soft`
    /// width, or the distance code's `step`, of the distance layer with the
    /// same sources (SPEC.md section 6.2), as the SPEC says a player maps
    /// the exact distance to amplitude. Layers without one keep a step.
    pub fn reference_frames_of(&self, kernel: &str, bundle: &Bundle) -> Vec<f64> {
        self.frames_of(kernel, Some(bundle))
    }

    /// [`reference_frames_of`](Self::reference_frames_of) for every kernel
    /// of `kernels` at once: each kind of layer is measured once (the
    /// exact distances are most of a report's time), and `all` is the sum
    /// of the kinds (so its last bits may differ from a sum in layer order).
    pub fn reference_frames_for(&self, kernels: &[String], bundle: &Bundle) -> Vec<Vec<f64>> {
        let kinds = ["vibration", "grating", "dots"];
        let sums: Vec<Option<Vec<f64>>> = kinds
            .iter()
            .map(|kind| {
                let wanted = kernels.iter().any(|k| k == kind || k == "all");
                let present = self.reference.iter().any(|l| exact_kind(l) == *kind);
                (wanted && present).then(|| self.sums_of(kind, Some(bundle)))
            })
            .collect();
        kernels
            .iter()
            .map(|k| {
                let mut out = vec![0.0; self.eval.len() * self.profile.actuator_count()];
                for (kind, sum) in kinds.iter().zip(&sums) {
                    if let Some(sum) = sum.as_ref().filter(|_| k == kind || k == "all") {
                        out.iter_mut().zip(sum).for_each(|(o, s)| *o += s);
                    }
                }
                out.iter_mut().for_each(|o| *o = exact::clamp_sum(*o));
                out
            })
            .collect()
    }

    fn frames_of(&self, kernel: &str, bundle: Option<&Bundle>) -> Vec<f64> {
        let mut frames = self.sums_of(kernel, bundle);
        frames.iter_mut().for_each(|o| *o = exact::clamp_sum(*o));
        frames
    }

    /// The unclamped sums of `kernel`'s layers ([`exact::frame_sum`]).
    fn sums_of(&self, kernel: &str, bundle: Option<&Bundle>) -> Vec<f64> {
        let ramp = |l: &ExactLayer| {
            let (kind, sources) = (exact_kind(l), sources_of(l)?);
            bundle?.chunks.iter().find_map(|c| match c {
                Chunk::Distance(d) if chunk_kind(c) == Some(kind) && d.sources[..] == *sources => {
                    Some(if d.soft_mm > 0.0 { d.soft_mm as f64 } else { d.step_mm as f64 })
                }
                _ => None,
            })
        };
        let (indices, layers): (Vec<usize>, Vec<ExactLayer>) = self
            .reference
            .iter()
            .enumerate()
            .filter(|(_, l)| kernel == "all" || exact_kind(l) == kernel)
            .map(|(i, l)| {
                let mut l = l.clone();
                let r = ramp(&l).unwrap_or(0.0);
                if let ExactLayer::Vibration { ramp_mm, .. } | ExactLayer::Grating { ramp_mm, .. } = &mut l {
                    *ramp_mm = r;
                }
                (i, l)
            })
            .unzip();
        let sampled: Vec<Option<std::sync::Arc<Sampled>>> =
            indices.iter().zip(&layers).map(|(&i, l)| self.edge_samples(i, l)).collect();
        let n = self.profile.actuator_count();
        let mut frames = vec![0.0; self.eval.len() * n];
        // Each frame on its own: the frames are the same on any number of threads.
        frames.par_chunks_mut(n.max(1)).zip(&self.eval).enumerate().for_each(|(f, (out, &(tick, x, y)))| {
            let mine: Vec<Option<&[exact::EdgeSample]>> =
                sampled.iter().map(|s| s.as_ref().and_then(|s| s.samples.get(f * n..(f + 1) * n))).collect();
            exact::frame_sum(&layers, &mine, &self.profile, tick, x, y, out);
        });
        frames
    }

    /// The [`exact::EdgeSample`] of `layer` (reference layer `index`, with
    /// its ramp for this bundle) at every compared actuator: taken once, with
    /// a reach of half the ramp, and kept for every later rung whose ramp is
    /// no wider (the ladder runs coarse to fine); `None` for dots, or where
    /// keeping them would pass [`MAX_KEPT_SAMPLES`].
    fn edge_samples(&self, index: usize, layer: &ExactLayer) -> Option<std::sync::Arc<Sampled>> {
        let (region, ramp) = match layer {
            ExactLayer::Vibration { region, ramp_mm, .. } | ExactLayer::Grating { region, ramp_mm, .. } => {
                (region, *ramp_mm)
            }
            ExactLayer::Dots(_) => return None,
        };
        // (A ramp of 0 or NaN is the ideal step: the coverage alone.)
        let reach = if ramp > 0.0 { ramp / 2.0 } else { 0.0 };
        let mut known = self.edges.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(s) = known.get(&index).filter(|s| s.reach >= reach) {
            return Some(s.clone());
        }
        let n = self.profile.actuator_count();
        let held: usize = known.iter().filter(|(i, _)| **i != index).map(|(_, s)| s.samples.len()).sum();
        if held.saturating_add(self.eval.len().saturating_mul(n)) > MAX_KEPT_SAMPLES {
            return None;
        }
        let samples: Vec<exact::EdgeSample> = self
            .eval
            .par_iter()
            .flat_map_iter(|&(_, x, y)| {
                (0..n).map(move |k| region.edge_sample(actuator(&self.profile, x, y, k), reach))
            })
            .collect();
        let sampled = std::sync::Arc::new(Sampled { reach, samples });
        known.insert(index, sampled.clone());
        Some(sampled)
    }

    /// Where each compared actuator of `kernel` stands against the exact
    /// edges and corners of the kernel's layers, frame by frame: the same
    /// at every rung, so found once per kernel and kept.
    fn places(&self, kernel: &str) -> std::sync::Arc<Vec<Place>> {
        let mut known = self.places.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(p) = known.get(kernel) {
            return p.clone();
        }
        let n = self.profile.actuator_count();
        if kernel == "all" {
            // Near an edge of any layer, else near a corner of any, else far:
            // each kind's places, already found or found now, combined.
            drop(known);
            let kinds: Vec<std::sync::Arc<Vec<Place>>> = ["vibration", "grating", "dots"]
                .into_iter()
                .filter(|k| !self.kernel_layers(k).is_empty())
                .map(|k| self.places(k))
                .collect();
            let places: Vec<Place> = (0..self.eval.len() * n)
                .map(|i| {
                    let mut at = kinds.iter().filter_map(|p| p.get(i).copied());
                    let (mut edge, mut corner) = (false, false);
                    for p in &mut at {
                        edge |= p == Place::NearEdge;
                        corner |= p == Place::NearCorner;
                    }
                    if edge {
                        Place::NearEdge
                    } else if corner {
                        Place::NearCorner
                    } else {
                        Place::Far
                    }
                })
                .collect();
            let places = std::sync::Arc::new(places);
            let mut known = self.places.lock().unwrap_or_else(|e| e.into_inner());
            known.insert(kernel.to_string(), places.clone());
            return places;
        }
        let layers: Vec<(&ExactLayer, &edge::Outline)> = self.kernel_layers(kernel);
        let regions: Vec<&exact::Region> = layers.iter().filter_map(|(l, _)| region_of(l)).collect();
        let places: Vec<Place> = self
            .eval
            .par_iter()
            .flat_map_iter(|&(_, x, y)| {
                let (layers, regions) = (&layers, &regions);
                (0..n).map(move |k| {
                    let p = actuator(&self.profile, x, y, k);
                    if near_edge(regions, p) {
                        Place::NearEdge
                    } else if layers.iter().any(|(_, o)| o.corners.near([p.0, p.1])) {
                        Place::NearCorner
                    } else {
                        Place::Far
                    }
                })
            })
            .collect();
        let places = std::sync::Arc::new(places);
        known.insert(kernel.to_string(), places.clone());
        places
    }

    /// The exact layers of `kernel` with their outlines.
    fn kernel_layers(&self, kernel: &str) -> Vec<(&ExactLayer, &edge::Outline)> {
        self.reference
            .iter()
            .zip(&self.outlines)
            .filter(|(l, _)| kernel == "all" || exact_kind(l) == kernel)
            .filter_map(|(l, o)| Some((l, o.as_ref()?)))
            .collect()
    }

    /// Plays `bundle` on the whole trace (timed) and compares it at the
    /// compared ticks with `reference` (from [`Prepared::reference_frames_of`]
    /// the same bundle) and, for [`Measured::step_rms_error`], with
    /// `step_reference` (from [`Prepared::reference_frames`]).
    pub fn measure(
        &self,
        bundle: &Bundle,
        reference: &[f64],
        step_reference: &[f64],
        kernel: &str,
    ) -> Result<Measured> {
        let n = self.profile.actuator_count();
        let max_code = ((1u32 << self.profile.output_bits.min(16)) - 1) as f64;
        let bytes = bundle.to_bytes().map_err(|e| anyhow::anyhow!("{e}"))?;
        let view = BundleView::parse(&bytes).map_err(|e| anyhow::anyhow!("{e}"))?;
        let player = LateroPlayer::new(&view).map_err(|e| anyhow::anyhow!("{e}"))?;
        let frame_us = time_frames(&player, &self.positions, n);
        let mut out = vec![0u16; n];
        let (mut max, mut sum2, mut count, mut far) = (0.0f64, 0.0f64, 0usize, 0.0f64);
        let (mut far_sum2, mut far_count) = (0.0f64, 0usize);
        let mut step_sum2 = 0.0f64;
        let mut corner_error: Option<f64> = None;
        let mut off = Vec::new();
        let layers = self.kernel_layers(kernel);
        let places = self.places(kernel);
        for (i, &(tick, x, y)) in self.eval.iter().enumerate() {
            player.frame(Tick(tick), Mm(x as f32), Mm(y as f32), &mut out);
            for (o, r) in out.iter().zip(step_reference.get(i * n..(i + 1) * n).unwrap_or(&[])) {
                step_sum2 += (*o as f64 - r * max_code).powi(2);
            }
            for (k, (o, r)) in out.iter().zip(reference.get(i * n..(i + 1) * n).unwrap_or(&[])).enumerate() {
                let e = (*o as f64 - r * max_code).abs();
                max = max.max(e);
                sum2 += e * e;
                count += 1;
                let p = actuator(&self.profile, x, y, k);
                if e > detail::CLASSIFIED_ABOVE_STEPS {
                    off.push((p, e * e));
                }
                let place = places.get(i * n + k).copied().unwrap_or(Place::NearEdge);
                if place == Place::NearEdge {
                    continue;
                }
                far_sum2 += e * e;
                far_count += 1;
                if place == Place::NearCorner {
                    corner_error = edge::max_opt(corner_error, Some(e));
                } else {
                    far = far.max(e);
                }
            }
        }
        // Each distance layer against the exact layer of the same sources.
        let (mut edge_error, mut lattice_mm) = (edge::EdgeError::default(), None);
        for c in &bundle.chunks {
            let Chunk::Distance(d) = c else { continue };
            let kind = chunk_kind(c).unwrap_or("");
            if let Some((_, outline)) =
                layers.iter().find(|(l, _)| exact_kind(l) == kind && sources_of(l) == Some(&d.sources[..]))
            {
                edge_error = edge_error.max(edge::edge_error(d, outline));
                lattice_mm = edge::max_opt(lattice_mm, Some(d.pitch_mm as f64));
            }
        }
        Ok(Measured {
            bytes: stored_len(&bytes)?,
            frame_us,
            max_error: max,
            rms_error: (sum2 / count.max(1) as f64).sqrt(),
            step_rms_error: (step_sum2 / count.max(1) as f64).sqrt(),
            far_error: far,
            far_rms_error: (far_sum2 / far_count.max(1) as f64).sqrt(),
            corner_error,
            edge: edge_error,
            lattice_mm,
            square_error_sum: sum2,
            off,
        })
    }
}

/// Where a compared actuator stands against a kernel's exact layers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Place {
    /// Within [`EDGE_BAND_MM`] of an exact edge: left out of the far errors.
    NearEdge,
    /// Away from every edge, within [`edge::CORNER_RADIUS_MM`] of a corner.
    NearCorner,
    /// Away from every edge and corner.
    Far,
}

/// The region of a vibration or grating layer.
fn region_of(l: &ExactLayer) -> Option<&exact::Region> {
    match l {
        ExactLayer::Vibration { region, .. } | ExactLayer::Grating { region, .. } => Some(region.as_ref()),
        ExactLayer::Dots(_) => None,
    }
}

/// The provenance entries a vibration or grating layer holds.
fn sources_of(l: &ExactLayer) -> Option<&[u32]> {
    match l {
        ExactLayer::Vibration { sources, .. } | ExactLayer::Grating { sources, .. } => Some(sources),
        ExactLayer::Dots(_) => None,
    }
}

/// Page position of actuator `k` with the carrier at `(x, y)`.
fn actuator(p: &taxel_format::DeviceProfile, x: f64, y: f64, k: usize) -> (f64, f64) {
    let (rows, cols) = (p.rows as f64, p.cols as f64);
    let (row, col) = ((k / p.cols.max(1) as usize) as f64, (k % p.cols.max(1) as usize) as f64);
    (x + (col - (cols - 1.0) / 2.0) * p.pitch_x_mm as f64, y + (row - (rows - 1.0) / 2.0) * p.pitch_y_mm as f64)
}

/// Whether an exact edge of any region passes within [`EDGE_BAND_MM`] of
/// `p`: coverage at `p` differs from coverage at one of 16 points on the
/// circle of that radius around it. Tested only where an edge may pass
/// that close (`ExactRegion::edge_may_pass_within`; elsewhere the
/// coverage is the same on the whole disc), so that every compared frame's
/// actuators are classified at the cost of an index query for most.
fn near_edge(regions: &[&exact::Region], p: (f64, f64)) -> bool {
    regions.iter().any(|r| {
        if !r.exact.edge_may_pass_within(p, EDGE_BAND_MM) {
            return false;
        }
        let here = r.exact.covers(p);
        (0..16).any(|k| {
            let a = k as f64 * std::f64::consts::TAU / 16.0;
            r.exact.covers((p.0 + EDGE_BAND_MM * a.cos(), p.1 + EDGE_BAND_MM * a.sin())) != here
        })
    })
}

/// Runs the report for `input`. `trace` overrides the scene's own trace;
/// `default_only` keeps the compiler's default setting alone.
pub fn run(input: &Path, opts: &CompileOpts, trace: Option<&Path>, default_only: bool) -> Result<Report> {
    let default_px = taxel_compiler::DEFAULT_PX_PER_MM;
    // Each pitch as the resolution that gives it (5 / pitch px/mm).
    let ladder: Vec<f32> =
        PITCH_LADDER.iter().map(|h| 5.0 / h).filter(|&px| !default_only || px == default_px).collect();
    // Compile once at the default for the reference (this also warms fonts and caches).
    let base = compile(input, opts, None)?.0;
    if base.manifest.profile.family() == Family::Grid {
        let mut rows = strokes::ladder(input, opts, &base, default_only)?;
        // Strokes play in time: a row's run time is its compile plus all its ticks.
        mark_front(&mut rows);
        return Ok(Report {
            input: input.display().to_string(),
            profile: base.manifest.profile.name.as_str().to_string(),
            trace: "none: strokes play in time from tick 0".into(),
            trace_frames: rows.iter().find(|r| r.default).map_or(0, |r| r.frames),
            rows,
            notes: vec!["the setting is the tick rate; errors are the largest onset or duration error (max) and the RMS over both, against the unquantised schedule".into()],
        });
    }
    if base.manifest.profile.family() == Family::Finger {
        let tr = load_trace(input, trace, &base)?;
        let (mut rows, notes) = mesh::ladder(input, opts, &base, &tr.trace, default_only)?;
        mark_front(&mut rows);
        return Ok(Report {
            input: input.display().to_string(),
            profile: base.manifest.profile.name.as_str().to_string(),
            trace_frames: tr.trace.samples().len(),
            trace: tr.origin,
            rows,
            notes,
        });
    }
    let prep = Prepared::new(input, opts, &base, trace, MAX_EVAL_FRAMES)?;
    let kernels = kernels_of(&base);
    let steps: Vec<Vec<f64>> = kernels.iter().map(|k| prep.reference_frames(k)).collect();
    let mut rows = Vec::new();
    for &px in &ladder {
        let (bundle, compile_ms) = compile(input, opts, Some(px))?;
        let references = prep.reference_frames_for(&kernels, &bundle);
        for ((k, step_reference), reference) in kernels.iter().zip(&steps).zip(references) {
            let mine = only_kernel(&bundle, k);
            let m = prep.measure(&mine, &reference, step_reference, k)?;
            // Where the error comes from, at the default only: the note is about what `build` writes.
            let fine_detail = if px == default_px { detail::share(&prep, &mine, &m, k) } else { None };
            rows.push(Row {
                kernel: k.clone(),
                setting: 5.0 / px as f64,
                unit: "mm lattice pitch of the distance layers (at most half a vibrating band's width)".into(),
                default: px == default_px,
                compile_ms,
                bundle_bytes: m.bytes,
                frame_us: m.frame_us,
                max_error: m.max_error,
                rms_error: m.rms_error,
                step_rms_error: Some(m.step_rms_error),
                far_error: Some(m.far_error),
                far_rms_error: Some(m.far_rms_error),
                corner_error: m.corner_error,
                edge_error_mm: m.edge.edge_mm,
                corner_edge_error_mm: m.edge.corner_mm,
                lattice_mm: m.lattice_mm,
                fine_detail,
                unfelt: Unfelt::of(m.edge.farthest, m.lattice_mm),
                error_unit: format!("{}-bit steps", prep.profile.output_bits),
                frames: prep.eval.len(),
                run_ms: compile_ms + m.frame_us * prep.positions.len() as f64 / 1000.0,
                on_front: false,
            });
        }
    }
    let frames = prep.positions.len();
    mark_front(&mut rows);
    let mut notes = prep.notes;
    notes.extend(detail::note(&rows));
    notes.extend(detail::unfelt_note(&rows));
    Ok(Report {
        input: input.display().to_string(),
        profile: prep.profile.name.as_str().to_string(),
        trace: prep.trace.origin,
        trace_frames: frames,
        rows,
        notes,
    })
}

/// `n` as an English ordinal: 2nd, 3rd, 11th, 21st.
fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}

/// Marks, per kernel, the rows that no other row beats on both run time and RMS error.
pub fn mark_front(rows: &mut [Row]) {
    let snapshot: Vec<(String, f64, f64)> = rows.iter().map(|r| (r.kernel.clone(), r.run_ms, r.rms_error)).collect();
    for r in rows.iter_mut() {
        let (c, e) = (r.run_ms, r.rms_error);
        r.on_front = !snapshot.iter().any(|(k, c2, e2)| *k == r.kernel && *c2 < c && *e2 < e);
    }
}

fn exact_kind(l: &ExactLayer) -> &'static str {
    match l {
        ExactLayer::Vibration { .. } => "vibration",
        ExactLayer::Grating { .. } => "grating",
        ExactLayer::Dots(_) => "dots",
    }
}

/// The kernels a bundle uses, in a fixed order, then `all`.
pub fn kernels_of(b: &Bundle) -> Vec<String> {
    let mut ks = Vec::new();
    for k in ["vibration", "grating", "dots"] {
        if b.chunks.iter().any(|c| chunk_kind(c) == Some(k)) {
            ks.push(k.to_string());
        }
    }
    if ks.len() > 1 {
        ks.push("all".into());
    }
    ks
}

fn chunk_kind(c: &Chunk) -> Option<&'static str> {
    match c {
        Chunk::Mask(taxel_format::MaskLayer { kind, .. })
        | Chunk::Distance(taxel_format::DistanceLayer { kind, .. }) => Some(match kind {
            taxel_format::MaskKind::Vibration { .. } => "vibration",
            taxel_format::MaskKind::Grating { .. } => "grating",
        }),
        Chunk::Dots(_) => Some("dots"),
        _ => None,
    }
}

/// The bundle with only the chunks of `kernel` (all of them for `all`).
pub fn only_kernel(b: &Bundle, kernel: &str) -> Bundle {
    let mut out = Bundle::new(b.manifest);
    out.chunks =
        b.chunks.iter().filter(|c| kernel == "all" || chunk_kind(c).is_none_or(|k| k == kernel)).cloned().collect();
    out
}

/// Compiles at `px` (None: the default) and returns the bundle and the wall time in ms.
pub fn compile(input: &Path, opts: &CompileOpts, px: Option<f32>) -> Result<(Bundle, f64)> {
    let mut o = opts.clone();
    if px.is_some() {
        o.resolution = px;
    }
    let t0 = Instant::now();
    let compiled = crate::compile::compile_file(input, &o)?;
    let ms = t0.elapsed().as_secs_f64() * 1000.0;
    match compiled.bundle {
        Some(b) => Ok((b, ms)),
        None => {
            let errs: Vec<String> = compiled
                .diagnostics
                .iter()
                .filter(|d| d.severity == taxel_compiler::Severity::Error)
                .map(|d| format!("{}: {}", d.code, d.message))
                .collect();
            bail!(
                "{} does not compile{}: {}",
                input.display(),
                px.map_or(String::new(), |p| format!(" at {p} px/mm")),
                errs.join("; ")
            )
        }
    }
}

/// The trace to play: `explicit`, else the scene's own, else a seeded sweep over every layer.
pub fn load_trace(input: &Path, explicit: Option<&Path>, bundle: &Bundle) -> Result<Explored> {
    let path: Option<PathBuf> = explicit.map(Path::to_path_buf).or_else(|| trace::own_trace_path(input));
    if let Some(p) = path {
        let text = crate::io::read_input_text(&p)?;
        return Explored::parse(&text, &p.display().to_string()).map_err(|e| anyhow::anyhow!(e));
    }
    let p = &bundle.manifest.profile;
    let mut boxes = Vec::new();
    for c in &bundle.chunks {
        match c {
            Chunk::Mask(m) => {
                let (x0, y0) = (m.origin_x.0 as f64, m.origin_y.0 as f64);
                let px = m.px_per_mm.max(1e-6) as f64;
                boxes.push((x0, y0, x0 + m.width as f64 / px, y0 + m.height as f64 / px));
            }
            Chunk::Distance(d) => {
                let (x0, y0) = (d.origin_x.0 as f64, d.origin_y.0 as f64);
                let span = 8.0 * d.pitch_mm as f64;
                boxes.push((x0, y0, x0 + d.tile_cols as f64 * span, y0 + d.tile_rows as f64 * span));
            }
            Chunk::Height(h) => {
                let (x0, y0, c) = (h.origin_x.0 as f64, h.origin_y.0 as f64, h.cell.0 as f64);
                boxes.push((
                    x0,
                    y0,
                    x0 + c * h.cols.saturating_sub(1) as f64,
                    y0 + c * h.rows.saturating_sub(1) as f64,
                ));
            }
            Chunk::Dots(d) if !d.dots.is_empty() => {
                let xs = d.dots.iter().map(|d| d.x.0 as f64);
                let ys = d.dots.iter().map(|d| d.y.0 as f64);
                let (x0, x1) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |a, v| (a.0.min(v), a.1.max(v)));
                let (y0, y1) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |a, v| (a.0.min(v), a.1.max(v)));
                boxes.push((x0, y0, x1, y1));
            }
            _ => {}
        }
    }
    // Rows half the array's height apart: every point of a box passes under the array twice.
    let row_mm = p.rows as f64 * p.pitch_y_mm as f64 / 2.0;
    Explored::sweep(&boxes, row_mm, SWEEP_SEED).context("the generated sweep")
}

/// Wall time of one frame over the trace, in µs: the best of three passes,
/// so that a pass disturbed by another process does not count, each over
/// at most [`TIMED_FRAMES`] of its frames, evenly spaced (the same mix of
/// frames over edges and away from them; every frame of a minute's trace,
/// three times over for each rung and kernel, was a tenth of a report's
/// time in the tests' build).
fn time_frames(player: &LateroPlayer<'_>, positions: &[(u64, f64, f64)], n: usize) -> f64 {
    let stride = positions.len().div_ceil(TIMED_FRAMES).max(1);
    let timed: Vec<(u64, f64, f64)> = positions.iter().step_by(stride).copied().collect();
    let mut out = vec![0u16; n];
    let mut sink = 0u64;
    let mut best = f64::INFINITY;
    for _ in 0..3 {
        let t0 = Instant::now();
        for &(tick, x, y) in &timed {
            player.frame(Tick(tick), Mm(x as f32), Mm(y as f32), std::hint::black_box(&mut out));
            sink = sink.wrapping_add(out.first().copied().unwrap_or(0) as u64);
        }
        best = best.min(t0.elapsed().as_secs_f64());
    }
    std::hint::black_box(sink);
    best * 1e6 / timed.len().max(1) as f64
}

/// The most frames [`time_frames`] plays in a pass.
const TIMED_FRAMES: usize = 4096;

/// The length of a bundle's file as `taxel build` writes it, from its
/// plain encoding `plain`: its stored (compressed) form, SPEC.md section 15.
pub(crate) fn stored_len(plain: &[u8]) -> Result<usize> {
    Ok(taxel_format::stored::store(plain).map_err(|e| anyhow::anyhow!("{e}"))?.len())
}
