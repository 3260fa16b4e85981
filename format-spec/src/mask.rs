//! Mask layers (`VIBR`, `GRAT`): a grayscale amplitude mask cropped to one
//! shape's bounding box, plus the primitive's parameters.

use alloc::vec::Vec;

use crate::bytes::{Out, f32_at, u8_at, u16_at, u32_at};
use crate::error::FormatError;
use crate::units::{MilliHertz, Mm};
use crate::{NO_SOURCE, Tag, finite, in_range, source_from_raw};

/// Length of a mask chunk's fixed header.
pub(crate) const MASK_HEADER_LEN: usize = 48;
/// Largest mask width or height, in samples.
pub const MAX_MASK_SIDE: u32 = 16_384;
/// Largest number of samples in one mask.
pub const MAX_MASK_SAMPLES: u64 = 64 << 20;

/// What a mask modulates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MaskKind {
    /// Vibration (seed 000 eq. 2): adjacent actuators in antiphase at `freq`.
    Vibration {
        /// The vibration frequency.
        freq: MilliHertz,
    },
    /// Grating (seed 000 eq. 3): `½ + ½ cos(2π d / λ)` with `d` measured from a
    /// line through the page origin at the ridge angle.
    Grating {
        /// The spatial wavelength λ.
        wavelength: Mm,
        /// The ridge direction on the page, degrees counter-clockwise from +x.
        angle_deg: f32,
    },
}

impl MaskKind {
    /// The chunk tag for this kind.
    pub fn tag(&self) -> Tag {
        match self {
            MaskKind::Vibration { .. } => Tag::VIBRATION,
            MaskKind::Grating { .. } => Tag::GRATING,
        }
    }
}

/// Mask samples, 8 or 16 bits; 0 is no amplitude, the largest code is full amplitude.
#[derive(Debug, Clone, PartialEq)]
pub enum MaskSamples {
    /// 8-bit samples (full = 255).
    U8(Vec<u8>),
    /// 16-bit samples (full = 65535).
    U16(Vec<u16>),
}

impl MaskSamples {
    /// Number of samples.
    pub fn len(&self) -> usize {
        match self {
            MaskSamples::U8(v) => v.len(),
            MaskSamples::U16(v) => v.len(),
        }
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Bits per sample.
    pub fn bits(&self) -> u8 {
        match self {
            MaskSamples::U8(_) => 8,
            MaskSamples::U16(_) => 16,
        }
    }
}

/// One mask layer: a cropped raster of one shape with its primitive.
///
/// Sample `(i, j)` (column `i`, row `j`, row 0 at the top) is the value at the
/// centre of its pixel, page position `(origin_x + (i + ½) / px_per_mm,
/// origin_y + (j + ½) / px_per_mm)`. Between centres a player interpolates
/// bilinearly; outside the box `[origin, origin + size / px_per_mm)` the mask is 0.
#[derive(Debug, Clone, PartialEq)]
pub struct MaskLayer {
    /// Provenance entry of the shape this mask was made from.
    pub source: Option<u32>,
    /// The primitive and its parameters.
    pub kind: MaskKind,
    /// Amplitude (0..=1) that scales the whole layer.
    pub amplitude: f32,
    /// Page x of the box's left edge.
    pub origin_x: Mm,
    /// Page y of the box's top edge.
    pub origin_y: Mm,
    /// Samples per millimetre.
    pub px_per_mm: f32,
    /// Samples per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `width * height` samples, row-major, top row first.
    pub samples: MaskSamples,
}

impl MaskLayer {
    /// Checks that the samples fill exactly `width * height`.
    pub(crate) fn check_shape(&self, index: u32) -> Result<(), FormatError> {
        if self.samples.len() as u64 != self.width as u64 * self.height as u64 {
            return Err(FormatError::InvalidValue {
                tag: self.kind.tag(),
                index,
                field: "samples",
                expected: "width * height samples",
            });
        }
        Ok(())
    }

    pub(crate) fn encode(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(MASK_HEADER_LEN + self.samples.len() * 2);
        let mut w = Out(&mut out);
        w.u32(self.source.unwrap_or(NO_SOURCE))
            .u32(self.width)
            .u32(self.height)
            .u8(self.samples.bits())
            .zeros(3)
            .f32(self.origin_x.0)
            .f32(self.origin_y.0)
            .f32(self.px_per_mm)
            .f32(self.amplitude);
        match self.kind {
            MaskKind::Vibration { freq } => w.u32(freq.0).u32(0),
            MaskKind::Grating { wavelength, angle_deg } => w.f32(wavelength.0).f32(angle_deg),
        };
        w.zeros(8);
        match &self.samples {
            MaskSamples::U8(v) => {
                w.bytes(v);
            }
            MaskSamples::U16(v) => {
                for &s in v {
                    w.u16(s);
                }
            }
        }
        out
    }

    pub(crate) fn from_view(v: &MaskView<'_>) -> Self {
        let n = v.width as usize * v.height as usize;
        let samples = if v.bits == 8 {
            MaskSamples::U8(v.data[..n].to_vec())
        } else {
            MaskSamples::U16((0..n).map(|i| u16_at(v.data, 2 * i).unwrap_or(0)).collect())
        };
        MaskLayer {
            source: v.source,
            kind: v.kind,
            amplitude: v.amplitude,
            origin_x: v.origin_x,
            origin_y: v.origin_y,
            px_per_mm: v.px_per_mm,
            width: v.width,
            height: v.height,
            samples,
        }
    }
}

/// A validated mask chunk, read in place.
#[derive(Debug, Clone, Copy)]
pub struct MaskView<'a> {
    /// Provenance entry of the shape.
    pub source: Option<u32>,
    /// The primitive and its parameters.
    pub kind: MaskKind,
    /// Layer amplitude (0..=1).
    pub amplitude: f32,
    /// Page x of the box's left edge.
    pub origin_x: Mm,
    /// Page y of the box's top edge.
    pub origin_y: Mm,
    /// Samples per millimetre.
    pub px_per_mm: f32,
    /// Samples per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Bits per sample: 8 or 16.
    pub bits: u8,
    data: &'a [u8],
}

impl<'a> MaskView<'a> {
    /// The raw sample at column `i`, row `j`, or 0 outside the mask.
    #[inline]
    pub fn raw(&self, i: u32, j: u32) -> u32 {
        if i >= self.width || j >= self.height {
            return 0;
        }
        let k = j as usize * self.width as usize + i as usize;
        if self.bits == 8 {
            self.data.get(k).copied().unwrap_or(0) as u32
        } else {
            u16_at(self.data, 2 * k).unwrap_or(0) as u32
        }
    }

    /// The code of a full-amplitude sample (255 or 65535).
    pub fn full_scale(&self) -> u32 {
        if self.bits == 8 { 255 } else { 65_535 }
    }

    /// The sample bytes as stored (little-endian for 16-bit masks).
    pub fn sample_bytes(&self) -> &'a [u8] {
        self.data
    }

    pub(crate) fn parse(d: &'a [u8], tag: Tag, index: u32) -> Result<Self, FormatError> {
        FormatError::check_header(d, MASK_HEADER_LEN, tag, index)?;
        let bad = |field, expected| FormatError::InvalidValue { tag, index, field, expected };
        let f = |o| f32_at(d, o).unwrap_or(f32::NAN);
        let width = u32_at(d, 4).unwrap_or(0);
        let height = u32_at(d, 8).unwrap_or(0);
        let bits = u8_at(d, 12).unwrap_or(0);
        if d[13..16].iter().any(|&b| b != 0) || d[40..48].iter().any(|&b| b != 0) {
            return Err(bad("reserved", "zero"));
        }
        for (field, v) in [("width", width), ("height", height)] {
            if v == 0 || v > MAX_MASK_SIDE {
                return Err(FormatError::Limit { tag, field, value: v as u64, limit: MAX_MASK_SIDE as u64 });
            }
        }
        let n = width as u64 * height as u64;
        if n > MAX_MASK_SAMPLES {
            return Err(FormatError::Limit { tag, field: "samples", value: n, limit: MAX_MASK_SAMPLES });
        }
        let bytes_per = match bits {
            8 => 1,
            16 => 2,
            _ => return Err(bad("bits", "8 or 16")),
        };
        let expected = MASK_HEADER_LEN as u64 + n * bytes_per;
        if d.len() as u64 != expected {
            return Err(FormatError::ChunkLength { tag, index, expected, found: d.len() as u64 });
        }
        let origin_x = finite(f(16), tag, index, "origin_x_mm")?;
        let origin_y = finite(f(20), tag, index, "origin_y_mm")?;
        let px_per_mm = in_range(f(24), 1e-3, 1e4, tag, index, "px_per_mm", "from 0.001 to 10000")?;
        let amplitude = in_range(f(28), 0.0, 1.0, tag, index, "amplitude", "from 0 to 1")?;
        let kind = if tag == Tag::VIBRATION {
            if u32_at(d, 36) != Some(0) {
                return Err(bad("reserved", "zero"));
            }
            let freq = u32_at(d, 32).unwrap_or(0);
            if freq == 0 {
                return Err(bad("frequency", "above 0 Hz"));
            }
            MaskKind::Vibration { freq: MilliHertz(freq) }
        } else {
            let wavelength = in_range(f(32), 1e-3, 1e6, tag, index, "wavelength_mm", "from 0.001 to 1e6 mm")?;
            let angle_deg = in_range(f(36), -360.0, 360.0, tag, index, "angle_deg", "from -360 to 360")?;
            MaskKind::Grating { wavelength: Mm(wavelength), angle_deg }
        };
        Ok(MaskView {
            source: source_from_raw(u32_at(d, 0).unwrap_or(NO_SOURCE)),
            kind,
            amplitude,
            origin_x: Mm(origin_x),
            origin_y: Mm(origin_y),
            px_per_mm,
            width,
            height,
            bits,
            data: &d[MASK_HEADER_LEN..],
        })
    }
}
