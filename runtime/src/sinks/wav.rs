//! Multichannel WAV drive signals for vibrotactile grids: one channel per
//! actuator (row-major, channel `cols · r + c`), each the actuator's carrier at
//! its amplitude, at the profile's audio rate — the way the Tactile Brush chair
//! drove its tactors through a multichannel audio interface (seed 001).
//!
//! Sample `n` is the instant `n / audio_rate` s, which is tick
//! `n · rate / audio_rate` of the stroke tables: the integer part and the
//! remainder are computed in integers, and the envelope is evaluated there
//! ([`GridPlayer::frame_at`]). The carrier phase is exact, from the integer
//! sample index: `phase = (n · mHz) mod (audio_rate · 1000)`, so hour 24 sounds
//! like hour 0. Files are written to a temporary name beside the target and
//! renamed into place, so a failed write never leaves a partial file.

use std::fmt;
use std::io::{self, Seek, Write};
use std::path::{Path, PathBuf};
use std::vec;

use taxel_format::Tick;

use crate::grid::{ActuatorDrive, GridPlayer};

/// Sample formats the sink writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SampleBits {
    /// 16-bit signed integers.
    Sixteen,
    /// 24-bit signed integers.
    TwentyFour,
}

impl SampleBits {
    /// 16 bits for devices of up to 16 output bits, 24 above.
    pub fn for_output_bits(bits: u8) -> Self {
        if bits > 16 { SampleBits::TwentyFour } else { SampleBits::Sixteen }
    }

    /// Bits per sample.
    pub fn bits(self) -> u16 {
        match self {
            SampleBits::Sixteen => 16,
            SampleBits::TwentyFour => 24,
        }
    }

    fn full_scale(self) -> f64 {
        match self {
            SampleBits::Sixteen => i16::MAX as f64,
            SampleBits::TwentyFour => ((1 << 23) - 1) as f64,
        }
    }
}

/// What was written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WavSummary {
    /// Channels (one per actuator).
    pub channels: u16,
    /// Sample frames (samples per channel).
    pub frames: u64,
    /// Samples per second.
    pub sample_rate: u32,
    /// Bits per sample.
    pub bits: u16,
    /// Frames in which some actuator's combined energy was clamped to full drive.
    pub clamped_frames: u64,
}

/// Why a WAV file could not be written.
#[derive(Debug)]
pub enum WavError {
    /// Reading or writing a file failed.
    Io {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        source: io::Error,
    },
    /// The WAV encoder refused the data.
    Encode(hound::Error),
    /// The drive signal would not fit in a WAV file (4 GiB of samples).
    TooLong {
        /// Sample frames needed.
        frames: u64,
        /// Channels.
        channels: u16,
    },
    /// The profile has more actuators than a WAV file has channels.
    TooManyChannels {
        /// Actuators.
        actuators: usize,
    },
}

impl fmt::Display for WavError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WavError::Io { path, source } => write!(f, "{}: {source}", path.display()),
            WavError::Encode(e) => write!(f, "cannot encode the WAV file: {e}"),
            WavError::TooLong { frames, channels } => write!(
                f,
                "{frames} sample frames of {channels} channels do not fit in a WAV file (at most 4 GiB of samples)"
            ),
            WavError::TooManyChannels { actuators } => {
                write!(f, "{actuators} actuators do not fit in a WAV file's 65535 channels")
            }
        }
    }
}

impl std::error::Error for WavError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            WavError::Io { source, .. } => Some(source),
            WavError::Encode(e) => Some(e),
            _ => None,
        }
    }
}

impl From<hound::Error> for WavError {
    fn from(e: hound::Error) -> Self {
        WavError::Encode(e)
    }
}

/// Number of audio sample frames from tick 0 to the player's end.
pub fn frame_count(player: &GridPlayer<'_>) -> u64 {
    let (rate, audio) = (player.rate_hz().max(1) as u128, player.audio_rate_hz() as u128);
    (player.end().0 as u128 * audio).div_ceil(rate).min(u64::MAX as u128) as u64
}

/// The instant of audio sample `n` as a tick and a fraction of a tick.
#[inline]
pub fn sample_instant(n: u64, rate_hz: u32, audio_rate_hz: u32) -> (Tick, f32) {
    let audio = audio_rate_hz.max(1) as u128;
    let num = n as u128 * rate_hz as u128;
    let tick = (num / audio).min(u64::MAX as u128) as u64;
    (Tick(tick), (num % audio) as f32 / audio as f32)
}

/// The carrier's phase at audio sample `n`, in turns (0..1), computed exactly
/// in integers from the sample index.
#[inline]
pub fn carrier_phase(n: u64, millihertz: u32, audio_rate_hz: u32) -> f64 {
    let period = audio_rate_hz as u64 * 1000;
    if period == 0 {
        return 0.0;
    }
    // (n mod P) · mHz < 3.84e8 · 4.3e9 fits in a u64.
    let num = ((n % period) * millihertz as u64) % period;
    num as f64 / period as f64
}

/// Writes the player's drive signal, from tick 0 to its end, as a WAV stream.
pub fn write_wav<W: Write + Seek>(
    writer: W,
    player: &GridPlayer<'_>,
    bits: SampleBits,
) -> Result<WavSummary, WavError> {
    let actuators = player.actuator_count();
    let channels = u16::try_from(actuators).map_err(|_| WavError::TooManyChannels { actuators })?;
    let frames = frame_count(player);
    let bytes = frames as u128 * channels as u128 * (bits.bits() / 8) as u128;
    if bytes > u32::MAX as u128 - 1024 {
        return Err(WavError::TooLong { frames, channels });
    }
    let audio = player.audio_rate_hz();
    let spec = hound::WavSpec {
        channels,
        sample_rate: audio,
        bits_per_sample: bits.bits(),
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::new(writer, spec)?;
    let mut out = vec![ActuatorDrive::default(); actuators];
    let scale = bits.full_scale();
    let mut clamped_frames = 0;
    for n in 0..frames {
        let (tick, frac) = sample_instant(n, player.rate_hz(), audio);
        let stats = player.frame_at(tick, frac, &mut out);
        if stats.clamped > 0 {
            clamped_frames += 1;
        }
        for a in &out {
            let v = if a.amplitude > 0.0 {
                let phase = carrier_phase(n, a.carrier.0, audio);
                a.amplitude as f64 * (std::f64::consts::TAU * phase).sin()
            } else {
                0.0
            };
            let sample = (v * scale).round().clamp(-scale, scale) as i32;
            w.write_sample(sample)?;
        }
    }
    w.finalize()?;
    Ok(WavSummary { channels, frames, sample_rate: audio, bits: bits.bits(), clamped_frames })
}

/// Writes the drive signal to `path` atomically: a temporary file in the same
/// folder, renamed over `path` only once it is complete.
pub fn write_wav_file(path: &Path, player: &GridPlayer<'_>, bits: SampleBits) -> Result<WavSummary, WavError> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let io_err = |source| WavError::Io { path: path.to_path_buf(), source };
    let tmp = tempfile::Builder::new().prefix(".taxel-wav-").suffix(".tmp").tempfile_in(dir).map_err(io_err)?;
    let summary = {
        let file = tmp.as_file().try_clone().map_err(io_err)?;
        write_wav(io::BufWriter::new(file), player, bits)?
    };
    tmp.as_file().sync_all().map_err(io_err)?;
    tmp.persist(path).map_err(|e| io_err(e.error))?;
    Ok(summary)
}
