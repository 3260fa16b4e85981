//! The manifest chunk (`MANI`): which device the bundle was compiled for and
//! which build produced it.

use alloc::vec::Vec;

use crate::bytes::{Out, array_at, f32_at, u8_at, u16_at, u32_at};
use crate::error::FormatError;
use crate::profile::{DeviceProfile, Family, FamilyParams, FingerParams, GridParams, PinParams};
use crate::units::FixedStr;
use crate::{Tag, finite};

/// Length of the manifest chunk.
pub const MANIFEST_LEN: usize = 144;

/// The manifest: the target device and the identity of the build.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Manifest {
    /// The device profile the bundle was compiled for.
    pub profile: DeviceProfile,
    /// Hash of everything the build depended on (input, style sheet, options,
    /// tool version), so that an incremental build can skip unchanged inputs.
    /// All zero when unknown.
    pub content_hash: [u8; 32],
    /// The program that wrote the bundle, such as `taxel 0.1.0`.
    pub generator: FixedStr<16>,
}

impl Manifest {
    /// A manifest for `profile` with no content hash and this crate's generator name.
    pub fn new(profile: DeviceProfile) -> Self {
        Manifest {
            profile,
            content_hash: [0; 32],
            generator: FixedStr::new(concat!("taxel ", env!("CARGO_PKG_VERSION"))).unwrap_or(FixedStr::EMPTY),
        }
    }

    pub(crate) fn encode(&self) -> Vec<u8> {
        let p = &self.profile;
        let mut out = Vec::with_capacity(MANIFEST_LEN);
        let mut w = Out(&mut out);
        w.bytes(p.name.padded())
            .u8(p.family().code())
            .u8(p.output_bits)
            .u16(p.rows)
            .u16(p.cols)
            .u16(0)
            .f32(p.pitch_x_mm)
            .f32(p.pitch_y_mm)
            .u32(p.rate_hz)
            .f32(p.surface_w_mm)
            .f32(p.surface_h_mm)
            .u32(0)
            .bytes(&self.content_hash)
            .bytes(self.generator.padded());
        match p.params {
            // A print profile is never written ([`crate::Bundle::to_bytes`] refuses it).
            FamilyParams::Laterotactile | FamilyParams::Print(_) => {
                w.zeros(32);
            }
            FamilyParams::Grid(g) => {
                w.f32(g.carrier_min_hz).f32(g.carrier_max_hz).u32(g.audio_rate_hz).f32(g.ramp_ms).zeros(16);
            }
            FamilyParams::Finger(f) => {
                w.f32(f.rhythm_max)
                    .f32(f.intensity_max)
                    .f32(f.flat_slope)
                    .u32(f.direction_window)
                    .f32(f.min_move_mm)
                    .zeros(12);
            }
            FamilyParams::Pins(p) => {
                w.u8(p.height_levels)
                    .u8(p.cell_rows)
                    .u8(p.cell_gap_cols)
                    .u8(p.line_gap_rows)
                    .u16(p.blink_step_ms)
                    .u16(p.text_cells)
                    .u32(p.refresh_ms)
                    .zeros(20);
            }
        }
        out
    }

    pub(crate) fn decode(d: &[u8], index: u32) -> Result<Self, FormatError> {
        let tag = Tag::MANIFEST;
        if d.len() != MANIFEST_LEN {
            return Err(FormatError::ChunkLength { tag, index, expected: MANIFEST_LEN as u64, found: d.len() as u64 });
        }
        let bad = |field, expected| FormatError::InvalidValue { tag, index, field, expected };
        let name_raw = array_at::<32>(d, 0).unwrap_or([0; 32]);
        let name = FixedStr::from_padded(&name_raw).ok_or(bad("profile name", "UTF-8, NUL-padded"))?;
        let family = Family::from_code(u8_at(d, 32).unwrap_or(0)).ok_or(bad("family", "1, 2, 3 or 4"))?;
        let gen_raw = array_at::<16>(d, 96).unwrap_or([0; 16]);
        let generator = FixedStr::from_padded(&gen_raw).ok_or(bad("generator", "UTF-8, NUL-padded"))?;
        let f = |o| f32_at(d, o).unwrap_or(f32::NAN);
        let u = |o| u32_at(d, o).unwrap_or(0);
        if u16_at(d, 38) != Some(0) || u32_at(d, 60) != Some(0) {
            return Err(bad("reserved", "zero"));
        }
        let params = match family {
            Family::Laterotactile => {
                if d[112..].iter().any(|&b| b != 0) {
                    return Err(bad("family parameters", "zero for a laterotactile profile"));
                }
                FamilyParams::Laterotactile
            }
            Family::Grid => {
                if d[128..].iter().any(|&b| b != 0) {
                    return Err(bad("reserved", "zero"));
                }
                FamilyParams::Grid(GridParams {
                    carrier_min_hz: finite(f(112), tag, index, "carrier_min_hz")?,
                    carrier_max_hz: finite(f(116), tag, index, "carrier_max_hz")?,
                    audio_rate_hz: u(120),
                    ramp_ms: finite(f(124), tag, index, "ramp_ms")?,
                })
            }
            Family::Finger => {
                if d[132..].iter().any(|&b| b != 0) {
                    return Err(bad("reserved", "zero"));
                }
                FamilyParams::Finger(FingerParams {
                    rhythm_max: finite(f(112), tag, index, "rhythm_max")?,
                    intensity_max: finite(f(116), tag, index, "intensity_max")?,
                    flat_slope: finite(f(120), tag, index, "flat_slope")?,
                    direction_window: u(124),
                    min_move_mm: finite(f(128), tag, index, "min_move_mm")?,
                })
            }
            Family::Pins => {
                if d[124..].iter().any(|&b| b != 0) {
                    return Err(bad("reserved", "zero"));
                }
                FamilyParams::Pins(PinParams {
                    height_levels: u8_at(d, 112).unwrap_or(0),
                    cell_rows: u8_at(d, 113).unwrap_or(0),
                    cell_gap_cols: u8_at(d, 114).unwrap_or(0),
                    line_gap_rows: u8_at(d, 115).unwrap_or(0),
                    blink_step_ms: u16_at(d, 116).unwrap_or(0),
                    text_cells: u16_at(d, 118).unwrap_or(0),
                    refresh_ms: u(120),
                })
            }
            // `Family::from_code` never gives it: no bundle holds a print profile.
            Family::Print => return Err(bad("family", "1, 2, 3 or 4")),
        };
        let profile = DeviceProfile {
            name,
            rows: u16_at(d, 34).unwrap_or(0),
            cols: u16_at(d, 36).unwrap_or(0),
            pitch_x_mm: f(40),
            pitch_y_mm: f(44),
            rate_hz: u(48),
            output_bits: u8_at(d, 33).unwrap_or(0),
            surface_w_mm: f(52),
            surface_h_mm: f(56),
            params,
        };
        profile.check().map_err(|(field, expected)| bad(field, expected))?;
        let content_hash = array_at::<32>(d, 64).unwrap_or([0; 32]);
        Ok(Manifest { profile, content_hash, generator })
    }
}
