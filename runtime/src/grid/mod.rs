//! The player for sparse vibrotactile grids (device family 2, Tactile Brush,
//! seed 001): stroke tables in, each actuator's amplitude and carrier out.
//!
//! A [`GridPlayer`] is built once from a validated [`BundleView`]; it keeps
//! zero-copy views of the bundle's stroke tables (at most [`MAX_TABLES`]).
//! [`GridPlayer::frame`] then gives, for a tick, each physical actuator's
//! amplitude (0..=1) and carrier; [`GridPlayer::frame_at`] does the same at
//! any instant between two ticks, which is what an audio-rate sink needs.
//! The per-tick path does not allocate, cannot panic, and computes every time
//! from integers (the instant within a point is `tick − start − onset` plus a
//! fraction of a tick), so nothing drifts however long it plays.
//!
//! # Envelope
//! A virtual point drives its actuators at its table intensity from its onset
//! to its end, with a ramp of the profile's `ramp_ms` (at most half the
//! point's duration) at each side so that tactors do not click. The ramp is
//! the smoothstep `3u² − 2u³`, which starts and ends with zero slope, like a
//! raised cosine, without trigonometry.
//!
//! # Shared actuators
//! Points active at once that need the same actuator combine by energy:
//! `A = min(1, √(Σ (Aᵢ · envᵢ)²))`. The carrier is that of the strongest
//! contribution. The compiler warns (T0512) where the sum can exceed 1;
//! [`GridStats::clamped`] counts where it did.
//!
//! ```
//! use taxel_format::{Bundle, BundleView, Chunk, Drive, Manifest, MilliHertz, Mm, Stroke, StrokePoint, StrokeTable, Tick, ActuatorIndex, profiles};
//! use taxel_runtime::grid::{ActuatorDrive, GridPlayer};
//!
//! let point = |onset, x, actuator| StrokePoint {
//!     onset, duration: 100, peak: onset + 50, x: Mm(x), y: Mm(0.0),
//!     drives: vec![Drive { actuator: ActuatorIndex(actuator), intensity: 0.5 }],
//! };
//! let stroke = Stroke {
//!     start: Tick(0), duration: 160, carrier: MilliHertz(200_000), intensity: 0.5, source: None,
//!     points: vec![point(0, 0.0, 0), point(60, 63.0, 1)],
//! };
//! let mut bundle = Bundle::new(Manifest::new(profiles::builtin("brush-4x3").unwrap()));
//! bundle.chunks.push(Chunk::Strokes(StrokeTable { strokes: vec![stroke] }));
//! let bytes = bundle.to_bytes().unwrap();
//! let view = BundleView::parse(&bytes).unwrap();
//! let player = GridPlayer::new(&view).unwrap();
//! let mut out = [ActuatorDrive::default(); 12];
//! player.frame(Tick(30), &mut out);
//! assert_eq!(out[0].amplitude, 0.5); // past its 5 ms ramp
//! assert_eq!(out[0].carrier, MilliHertz(200_000));
//! assert_eq!(out[1].amplitude, 0.0); // not started yet
//! assert_eq!(player.end(), Tick(160));
//! ```

use taxel_format::{BundleView, ChunkView, Family, FamilyParams, MilliHertz, StrokeTableView, Tag, Tick};

use crate::error::RuntimeError;

/// Largest number of stroke tables (`STRK` chunks) one bundle may hold for this player.
pub const MAX_TABLES: usize = 8;

/// Energy above full drive by more than this counts as clamped (f32 shares
/// that sum to exactly full drive may round a hair above it).
const CLAMP_TOLERANCE: f32 = 1e-5;

/// One actuator's output for an instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ActuatorDrive {
    /// Amplitude of the carrier, 0..=1 of full drive.
    pub amplitude: f32,
    /// Carrier frequency (0 when the actuator is at rest).
    pub carrier: MilliHertz,
    /// Energy of the strongest contribution so far (working state of a frame).
    strongest: f32,
}

/// What happened while computing one frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct GridStats {
    /// Virtual points active at the instant.
    pub active_points: u32,
    /// Actuators whose combined energy exceeded full drive and were clamped.
    pub clamped: u32,
    /// Actuators written (the profile's count, or fewer when the output is shorter).
    pub written: u32,
}

/// Plays the stroke tables of a grid bundle.
#[derive(Debug, Clone, Copy)]
pub struct GridPlayer<'a> {
    tables: [Option<StrokeTableView<'a>>; MAX_TABLES],
    actuators: usize,
    rate_hz: u32,
    audio_rate_hz: u32,
    ramp_ticks: f32,
    end: u64,
}

impl<'a> GridPlayer<'a> {
    /// A player for a validated grid bundle. Refuses bundles of another
    /// family, chunks a grid cannot play, and more than [`MAX_TABLES`] stroke
    /// tables. Allocates nothing.
    pub fn new(view: &BundleView<'a>) -> Result<Self, RuntimeError> {
        let profile = view.manifest().profile;
        let FamilyParams::Grid(g) = profile.params else {
            return Err(RuntimeError::WrongFamily {
                expected: Family::Grid,
                found: profile.family(),
                profile: profile.name,
            });
        };
        let mut tables = [None; MAX_TABLES];
        let mut len = 0;
        let mut needed = 0;
        let mut end = 0u64;
        for chunk in view.chunks() {
            match chunk {
                ChunkView::Strokes(t) => {
                    needed += 1;
                    if let Some(slot) = tables.get_mut(len) {
                        *slot = Some(t);
                        len += 1;
                    }
                    for i in 0..t.stroke_count() {
                        if let Some((start, duration, ..)) = t.stroke_timing(i) {
                            end = end.max(start.0.saturating_add(duration as u64));
                        }
                    }
                }
                ChunkView::Provenance(_) | ChunkView::Footprints(_) | ChunkView::Unknown { .. } => {}
                ChunkView::Mask(m) => {
                    return Err(RuntimeError::UnexpectedChunk { family: Family::Grid, tag: m.kind.tag() });
                }
                ChunkView::Distance(m) => {
                    return Err(RuntimeError::UnexpectedChunk { family: Family::Grid, tag: m.tag() });
                }
                ChunkView::Dots(_) => {
                    return Err(RuntimeError::UnexpectedChunk { family: Family::Grid, tag: Tag::DOTS });
                }
                ChunkView::Height(_) => {
                    return Err(RuntimeError::UnexpectedChunk { family: Family::Grid, tag: Tag::HEIGHT });
                }
                ChunkView::Pins(_) => {
                    return Err(RuntimeError::UnexpectedChunk { family: Family::Grid, tag: Tag::PINS });
                }
            }
        }
        if needed > MAX_TABLES {
            return Err(RuntimeError::TooManyLayers { needed, capacity: MAX_TABLES });
        }
        Ok(GridPlayer {
            tables,
            actuators: profile.actuator_count(),
            rate_hz: profile.rate_hz,
            audio_rate_hz: g.audio_rate_hz,
            ramp_ticks: g.ramp_ms * profile.rate_hz as f32 / 1000.0,
            end,
        })
    }

    /// Number of physical actuators (`rows · cols`).
    pub fn actuator_count(&self) -> usize {
        self.actuators
    }

    /// Ticks per second of the stroke tables.
    pub fn rate_hz(&self) -> u32 {
        self.rate_hz
    }

    /// Sample rate of the audio interface that drives the tactors.
    pub fn audio_rate_hz(&self) -> u32 {
        self.audio_rate_hz
    }

    /// The first tick after every stroke has ended (0 for a bundle without strokes).
    pub fn end(&self) -> Tick {
        Tick(self.end)
    }

    /// Each actuator's amplitude and carrier at the instant of `tick`.
    pub fn frame(&self, tick: Tick, out: &mut [ActuatorDrive]) -> GridStats {
        self.frame_at(tick, 0.0, out)
    }

    /// Each actuator's amplitude and carrier at the instant `tick + frac`
    /// ticks (`frac` in `0..1`; other values are clamped into it).
    pub fn frame_at(&self, tick: Tick, frac: f32, out: &mut [ActuatorDrive]) -> GridStats {
        let frac = if frac.is_finite() { frac.clamp(0.0, 0.999_999) } else { 0.0 };
        let n = self.actuators.min(out.len());
        let out = &mut out[..n];
        out.fill(ActuatorDrive::default());
        let mut stats = GridStats { written: n as u32, ..GridStats::default() };
        for table in self.tables.iter().flatten() {
            for i in 0..table.stroke_count() {
                let Some((start, duration, carrier, _, points)) = table.stroke_timing(i) else { continue };
                let Some(local) = tick.0.checked_sub(start.0) else { continue };
                if local >= duration as u64 {
                    continue;
                }
                for k in points {
                    let Some((onset, length, drives)) = table.point_timing(k) else { continue };
                    if onset as u64 > local {
                        // Onsets never decrease along a stroke.
                        break;
                    }
                    let into = local - onset as u64;
                    if into >= length as u64 {
                        continue;
                    }
                    // Both distances from integers, so the ramps stay exact on long points.
                    let since = into as f32 + frac;
                    let until = (length as u64 - into) as f32 - frac;
                    let env = envelope(since, until, self.ramp_ticks);
                    stats.active_points += 1;
                    for j in drives {
                        let Some(d) = table.drive(j) else { continue };
                        let Some(slot) = out.get_mut(d.actuator.0 as usize) else { continue };
                        let a = d.intensity * env;
                        let e = a * a;
                        slot.amplitude += e;
                        if e > slot.strongest {
                            slot.strongest = e;
                            slot.carrier = carrier;
                        }
                    }
                }
            }
        }
        for slot in out.iter_mut() {
            let e = slot.amplitude;
            if e > 1.0 + CLAMP_TOLERANCE {
                stats.clamped += 1;
            }
            slot.amplitude = libm::sqrtf(e).min(1.0);
            if slot.amplitude <= 0.0 {
                slot.carrier = MilliHertz(0);
            }
        }
        stats
    }
}

/// The envelope of a point `since` ticks after its onset and `until` ticks
/// before its end: smoothstep ramps of `ramp` ticks (at most half the
/// point's length) at both ends, 0 outside the point.
#[inline]
pub fn envelope(since: f32, until: f32, ramp: f32) -> f32 {
    if since < 0.0 || until <= 0.0 {
        return 0.0;
    }
    let r = ramp.min(0.5 * (since + until));
    if r <= 0.0 {
        return 1.0;
    }
    let v = (since.min(until) / r).clamp(0.0, 1.0);
    v * v * (3.0 - 2.0 * v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn envelope_ramps_and_holds() {
        assert_eq!(envelope(0.0, 100.0, 5.0), 0.0);
        assert_eq!(envelope(2.5, 97.5, 5.0), 0.5);
        assert_eq!(envelope(5.0, 95.0, 5.0), 1.0);
        assert_eq!(envelope(50.0, 50.0, 5.0), 1.0);
        assert_eq!(envelope(97.5, 2.5, 5.0), 0.5);
        assert_eq!(envelope(100.0, 0.0, 5.0), 0.0);
        // A short point ramps over half its length each way.
        assert_eq!(envelope(2.0, 2.0, 5.0), 1.0);
        assert_eq!(envelope(1.0, 3.0, 5.0), 0.5);
        assert_eq!(envelope(0.0, 4.0, 0.0), 1.0);
        // A point of four billion ticks still ramps exactly at its end.
        assert_eq!(envelope(4.0e9, 2.5, 5.0), 0.5);
    }
}
