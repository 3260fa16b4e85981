//! Sample bundles built in code: the worked example of `SPEC.md` and a bundle
//! that holds every kind of chunk. Tests, benchmarks and documentation use
//! them, so that they all talk about the same bytes.

use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

use crate::{
    ActuatorIndex, Bundle, Chunk, DeviceProfile, DistanceLayer, Dot, DotKind, DotTable, Drive, FIELD_CONTACT,
    FIELD_EDGE, FamilyParams, FixedStr, GridParams, HeightField, Manifest, MaskKind, MaskLayer, MaskSamples,
    MilliHertz, Mm, Provenance, ProvenanceEntry, RawChunk, Stroke, StrokePoint, StrokeTable, Tag, Tick,
};

/// The tag of the unknown optional chunk in [`every_kind`].
pub const EXTRA_TAG: Tag = Tag(*b"XTRA");

/// A 4 x 3 vibrotactile grid like the Tactile Brush chair (`brush-4x3`),
/// written out here so that this module does not need the `std` feature.
pub fn grid_profile() -> DeviceProfile {
    DeviceProfile {
        name: FixedStr::new("brush-4x3").unwrap_or(FixedStr::EMPTY),
        rows: 3,
        cols: 4,
        pitch_x_mm: 63.0,
        pitch_y_mm: 63.0,
        rate_hz: 1000,
        output_bits: 16,
        surface_w_mm: 189.0,
        surface_h_mm: 126.0,
        params: FamilyParams::Grid(GridParams {
            carrier_min_hz: 150.0,
            carrier_max_hz: 270.0,
            audio_rate_hz: 48_000,
            ramp_ms: 5.0,
        }),
    }
}

/// A laterotactile 8 x 8 array like STRESS² (`stress2`).
pub fn laterotactile_profile() -> DeviceProfile {
    DeviceProfile {
        name: FixedStr::new("stress2").unwrap_or(FixedStr::EMPTY),
        rows: 8,
        cols: 8,
        pitch_x_mm: 1.2,
        pitch_y_mm: 1.4,
        rate_hz: 1000,
        output_bits: 10,
        surface_w_mm: 110.0,
        surface_h_mm: 60.0,
        params: FamilyParams::Laterotactile,
    }
}

/// The worked example of `SPEC.md`: a `stress2` manifest and one 2 x 2
/// vibration mask at 50 Hz. Its encoding is the hex dump in the specification.
pub fn tiny() -> Bundle {
    let mut manifest = Manifest::new(laterotactile_profile());
    manifest.generator = FixedStr::new("spec example").unwrap_or(FixedStr::EMPTY);
    let mut bundle = Bundle::new(manifest);
    bundle.chunks.push(Chunk::Mask(MaskLayer {
        source: None,
        kind: MaskKind::Vibration { freq: MilliHertz(50_000) },
        amplitude: 1.0,
        origin_x: Mm(10.0),
        origin_y: Mm(20.0),
        px_per_mm: 2.0,
        width: 2,
        height: 2,
        samples: MaskSamples::U8(vec![0, 128, 255, 64]),
    }));
    bundle
}

/// A bundle with every kind of chunk: an 8-bit vibration mask, a 16-bit
/// grating mask, dot tables of every kind (one empty), a stroke table, a
/// height field, provenance and an unknown optional chunk (`XTRA`) of odd
/// length. Every value is exactly representable so that text round trips
/// can be compared bit for bit.
pub fn every_kind() -> Bundle {
    let mut manifest = Manifest::new(grid_profile());
    manifest.content_hash = core::array::from_fn(|i| (i as u8).wrapping_mul(37).wrapping_add(11));
    let mut b = Bundle::new(manifest);
    b.chunks.push(Chunk::Mask(MaskLayer {
        source: Some(0),
        kind: MaskKind::Vibration { freq: MilliHertz(50_000) },
        amplitude: 0.75,
        origin_x: Mm(10.5),
        origin_y: Mm(20.25),
        px_per_mm: 4.0,
        width: 3,
        height: 2,
        samples: MaskSamples::U8(vec![0, 1, 127, 128, 254, 255]),
    }));
    b.chunks.push(Chunk::Mask(MaskLayer {
        source: None,
        kind: MaskKind::Grating { wavelength: Mm(6.0), angle_deg: 45.0 },
        amplitude: 0.1,
        origin_x: Mm(-3.0),
        origin_y: Mm(0.1),
        px_per_mm: 10.0,
        width: 2,
        height: 3,
        samples: MaskSamples::U16(vec![0, 1, 255, 256, 65_534, 65_535]),
    }));
    b.chunks.push(Chunk::Distance(distance_layer()));
    let dot = |x: f32, y: f32, radius: f32, amplitude: f32, source| Dot {
        x: Mm(x),
        y: Mm(y),
        radius: Mm(radius),
        amplitude,
        source,
    };
    b.chunks.push(Chunk::Dots(DotTable {
        kind: DotKind::Outline,
        dots: vec![
            dot(5.0, 5.0, 1.0, 1.0, Some(1)),
            dot(7.5, 5.0, 1.0, 0.5, Some(1)),
            dot(10.0, 5.0, 1.0, 1.0, Some(1)),
            dot(10.0, 7.5, 1.0, 1.0, None),
            dot(40.0, 30.0, 0.75, 0.3, None),
        ],
    }));
    b.chunks.push(Chunk::Dots(DotTable { kind: DotKind::Symbol, dots: vec![dot(60.0, 45.0, 2.5, 1.0, Some(0))] }));
    b.chunks.push(Chunk::Dots(DotTable {
        kind: DotKind::Braille,
        dots: vec![
            // In the order the writer stores them (by grid cell), so that the
            // bundle reads back equal to this value.
            dot(20.0, 40.0, 0.72, 1.0, Some(1)),
            dot(22.34, 40.0, 0.72, 1.0, Some(1)),
            dot(20.0, 42.34, 0.72, 1.0, Some(1)),
            dot(26.2, 40.0, 0.72, 1.0, Some(1)),
            dot(26.2, 42.34, 0.72, 1.0, Some(1)),
            dot(22.34, 44.68, 0.72, 1.0, Some(1)),
        ],
    }));
    b.chunks.push(Chunk::Dots(DotTable { kind: DotKind::Outline, dots: Vec::new() }));
    let drive = |a: u16, intensity: f32| Drive { actuator: ActuatorIndex(a), intensity };
    b.chunks.push(Chunk::Strokes(StrokeTable {
        strokes: vec![
            Stroke {
                start: Tick(0),
                duration: 1000,
                carrier: MilliHertz(200_000),
                intensity: 1.0,
                source: Some(1),
                points: vec![
                    StrokePoint {
                        onset: 0,
                        duration: 72,
                        peak: 0,
                        x: Mm(0.0),
                        y: Mm(0.0),
                        drives: vec![drive(0, 1.0)],
                    },
                    StrokePoint {
                        onset: 70,
                        duration: 399,
                        peak: 143,
                        x: Mm(31.5),
                        y: Mm(0.0),
                        drives: vec![drive(0, 0.70710677), drive(1, 0.70710677)],
                    },
                    StrokePoint {
                        onset: 709,
                        duration: 291,
                        peak: 1000,
                        x: Mm(189.0),
                        y: Mm(0.0),
                        drives: vec![drive(3, 1.0)],
                    },
                ],
            },
            Stroke {
                start: Tick(86_400_000),
                duration: 1,
                carrier: MilliHertz(150_000),
                intensity: 0.5,
                source: None,
                points: vec![StrokePoint {
                    onset: 0,
                    duration: 1,
                    peak: 1,
                    x: Mm(63.0),
                    y: Mm(126.0),
                    drives: vec![drive(11, 0.25)],
                }],
            },
        ],
    }));
    let c = FIELD_CONTACT;
    b.chunks.push(Chunk::Height(HeightField {
        source: Some(0),
        cols: 3,
        rows: 2,
        origin_x: Mm(1.0),
        origin_y: Mm(2.0),
        cell: Mm(0.5),
        gradient_cap: 4.0,
        heights: vec![0.0, 1.5, -2.25, 3.0, 0.125, 0.0],
        grad_x: vec![0.0, 0.5, -4.0, 1.0, 0.0, 0.0],
        grad_y: vec![0.0, -0.25, 0.0, 4.0, 0.1, 0.0],
        flags: vec![0, c, c | FIELD_EDGE, c | FIELD_EDGE, c, 0],
        encoding: crate::HeightEncoding::Float,
    }));
    b.chunks.push(Chunk::Provenance(Provenance {
        entries: vec![
            ProvenanceEntry { id: "lake".into(), label: "Lac Léman".into(), line: 12 },
            ProvenanceEntry { id: "route-1".into(), label: String::new(), line: 0 },
        ],
    }));
    b.chunks.push(Chunk::Raw(RawChunk { tag: EXTRA_TAG, required: false, data: vec![1, 2, 3, 4, 5] }));
    b
}

/// A small distance layer (a grating style of two elements): 3 x 2 tiles of
/// 4 mm, one inside, one outside, two stored, one plane and one ridge, with
/// a soft edge.
pub fn distance_layer() -> DistanceLayer {
    DistanceLayer {
        kind: MaskKind::Grating { wavelength: Mm(3.0), angle_deg: 30.0 },
        amplitude: 0.9,
        soft_mm: 0.3,
        step_mm: 0.01,
        origin_x: Mm(2.0),
        origin_y: Mm(-1.5),
        pitch_mm: 0.5,
        tile_cols: 4,
        tile_rows: 2,
        sources: vec![0, 2],
        // Every kind of tile: outside, stored, plane, notch (format 4.0),
        // inside, stored, ridge, corner (format 4.0).
        tiles: vec![
            0,
            2,
            crate::TILE_PLANE,
            crate::TILE_NOTCH | 1,
            1,
            3,
            crate::TILE_RIDGE | 3,
            crate::TILE_CORNER | 4,
        ],
        planes: vec![
            crate::TilePlane { c: 100.0, gx: 4.5, gy: -2.25, top: 0.0 },
            crate::TilePlane { c: 130.0, gx: -16.0, gy: 0.0, top: 0.0 },
            crate::TilePlane { c: 60.0, gx: 0.0, gy: 16.0, top: 0.0 },
            crate::TilePlane { c: -10.0, gx: 3.0, gy: 1.5, top: 160.0 },
            crate::TilePlane { c: 200.0, gx: -12.0, gy: -9.0, top: 0.0 },
            crate::TilePlane { c: 150.0, gx: 9.0, gy: -12.0, top: 0.0 },
        ],
        samples: (0..2 * crate::TILE_SAMPLES).map(|k| (k * 7 % 256) as u8).collect(),
    }
}

/// A 16-bit grating mask (wavelength 2 mm, vertical) of `width` x `height`
/// samples at 8 px/mm from the page origin, for bundles of a given size.
pub fn grating_mask(width: u32, height: u32, samples: Vec<u16>) -> Chunk {
    Chunk::Mask(MaskLayer {
        source: None,
        kind: MaskKind::Grating { wavelength: Mm(2.0), angle_deg: 90.0 },
        amplitude: 1.0,
        origin_x: Mm(0.0),
        origin_y: Mm(0.0),
        px_per_mm: 8.0,
        width,
        height,
        samples: MaskSamples::U16(samples),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::BundleView;

    #[test]
    fn samples_are_valid_and_read_back() {
        for b in [tiny(), every_kind()] {
            let bytes = b.to_bytes().unwrap();
            assert_eq!(Bundle::from_bytes(&bytes).unwrap(), b);
            assert_eq!(Bundle::from_view(&BundleView::parse(&bytes).unwrap()).to_bytes().unwrap(), bytes);
        }
    }
}
