//! The validating, zero-copy reader.

use crate::Tag;
use crate::container;
use crate::distance::DistanceView;
use crate::dots::DotTableView;
use crate::error::FormatError;
use crate::footprint::FootprintView;
use crate::height::HeightFieldView;
use crate::manifest::Manifest;
use crate::mask::MaskView;
use crate::pins::PinImageView;
use crate::profile::{DeviceProfile, Family};
use crate::provenance::ProvenanceView;
use crate::strokes::StrokeTableView;

/// A bundle that has passed every check of the specification, read in place.
///
/// [`BundleView::parse`] checks the magic, the version, the header and table
/// checksum, the canonical placement of every chunk, every chunk's checksum,
/// and every field of every known chunk (ranges, finiteness, internal
/// indices) before it returns. After that, nothing read through the view can
/// be out of bounds or out of range.
#[derive(Debug, Clone, Copy)]
pub struct BundleView<'a> {
    bytes: &'a [u8],
    manifest: Manifest,
    count: u32,
    version: (u16, u16),
}

/// One chunk of a validated bundle (the manifest excepted).
#[derive(Debug, Clone, Copy)]
pub enum ChunkView<'a> {
    /// A vibration or grating raster mask (hand-painted masks).
    Mask(MaskView<'a>),
    /// A vibration or grating layer by style, as a distance field.
    Distance(DistanceView<'a>),
    /// A dot table.
    Dots(DotTableView<'a>),
    /// A stroke table.
    Strokes(StrokeTableView<'a>),
    /// A height field.
    Height(HeightFieldView<'a>),
    /// A pin image.
    Pins(PinImageView<'a>),
    /// The provenance table.
    Provenance(ProvenanceView<'a>),
    /// The provenance entries' footprints (format 2.1).
    Footprints(FootprintView<'a>),
    /// An optional chunk this reader does not know.
    Unknown {
        /// Its tag.
        tag: Tag,
        /// Always false: unknown required chunks are refused.
        required: bool,
        /// Its data.
        data: &'a [u8],
    },
}

fn known_required(tag: Tag) -> Option<bool> {
    match tag {
        Tag::MANIFEST
        | Tag::VIBRATION
        | Tag::GRATING
        | Tag::VIBRATION_DISTANCE
        | Tag::GRATING_DISTANCE
        | Tag::DOTS
        | Tag::STROKES
        | Tag::HEIGHT
        | Tag::PINS => Some(true),
        Tag::PROVENANCE | Tag::FOOTPRINTS => Some(false),
        _ => None,
    }
}

impl<'a> BundleView<'a> {
    /// Validates `bytes` as a whole. Allocates nothing.
    pub fn parse(bytes: &'a [u8]) -> Result<Self, FormatError> {
        let (major, minor, count) = container::validate(bytes)?;
        let mut manifest = None;
        let mut seen_provenance = false;
        let mut seen_pins = false;
        let mut seen_footprints = false;
        for index in 0..count {
            let e = container::entry(bytes, index).ok_or(FormatError::MissingManifest)?;
            let data = &bytes[e.offset..e.offset + e.length];
            if index == 0 && e.tag != Tag::MANIFEST {
                return Err(FormatError::ChunkOrder {
                    index,
                    tag: e.tag,
                    rule: "the first chunk must be the manifest",
                });
            }
            match known_required(e.tag) {
                None if e.required => return Err(FormatError::UnknownRequiredChunk { index, tag: e.tag }),
                None => continue,
                Some(req) if req != e.required => {
                    return Err(FormatError::RequiredFlag { index, tag: e.tag, expected: req });
                }
                Some(_) => {}
            }
            if e.tag == Tag::MANIFEST {
                if index != 0 {
                    return Err(FormatError::ChunkOrder { index, tag: e.tag, rule: "the manifest comes first, once" });
                }
                manifest = Some(Manifest::decode(data, index)?);
                continue;
            }
            // Chunk 0 was the manifest (checked above), so it is known here.
            let Some(m) = manifest else {
                return Err(FormatError::MissingManifest);
            };
            if e.tag == Tag::PROVENANCE {
                if seen_provenance {
                    return Err(FormatError::ChunkOrder { index, tag: e.tag, rule: "at most one provenance chunk" });
                }
                seen_provenance = true;
            }
            if e.tag == Tag::FOOTPRINTS {
                if seen_footprints {
                    return Err(FormatError::ChunkOrder { index, tag: e.tag, rule: "at most one footprint chunk" });
                }
                seen_footprints = true;
            }
            // A pin-matrix bundle holds one pin image and no other layer.
            let pins_family = m.profile.family() == Family::Pins;
            if e.tag == Tag::PINS {
                if seen_pins {
                    return Err(FormatError::ChunkOrder { index, tag: e.tag, rule: "at most one pin image" });
                }
                seen_pins = true;
            } else if pins_family && e.tag != Tag::PROVENANCE && e.tag != Tag::FOOTPRINTS {
                return Err(FormatError::ChunkOrder {
                    index,
                    tag: e.tag,
                    rule: "a pin-matrix bundle holds only a pin image, provenance and footprints",
                });
            }
            parse_chunk(e.tag, data, index, &m.profile, true)?;
        }
        let manifest = manifest.ok_or(FormatError::MissingManifest)?;
        Ok(BundleView { bytes, manifest, count, version: (major, minor) })
    }

    /// The manifest.
    pub fn manifest(&self) -> &Manifest {
        &self.manifest
    }

    /// The format version `(major, minor)` recorded in the file.
    pub fn version(&self) -> (u16, u16) {
        self.version
    }

    /// The bundle's bytes.
    pub fn bytes(&self) -> &'a [u8] {
        self.bytes
    }

    /// Number of chunks, the manifest included.
    pub fn chunk_count(&self) -> u32 {
        self.count
    }

    /// `(tag, required, offset, length)` of chunk `index` as the table records it.
    pub fn chunk_entry(&self, index: u32) -> Option<(Tag, bool, u64, u64)> {
        if index >= self.count {
            return None;
        }
        container::entry(self.bytes, index).map(|e| (e.tag, e.required, e.offset as u64, e.length as u64))
    }

    /// The chunks after the manifest, in file order.
    pub fn chunks(&self) -> impl Iterator<Item = ChunkView<'a>> + 'a {
        let bytes = self.bytes;
        let profile = self.manifest.profile;
        (1..self.count).filter_map(move |index| {
            let e = container::entry(bytes, index)?;
            let data = bytes.get(e.offset..e.offset + e.length)?;
            match known_required(e.tag) {
                None => Some(ChunkView::Unknown { tag: e.tag, required: e.required, data }),
                // Every chunk was validated in full by `parse`, so this cannot
                // fail; only the O(1) header reads are repeated, not the scans.
                Some(_) => parse_chunk(e.tag, data, index, &profile, false).ok().flatten(),
            }
        })
    }

    /// The pin image, if any.
    pub fn pin_image(&self) -> Option<PinImageView<'a>> {
        self.chunks().find_map(|c| match c {
            ChunkView::Pins(p) => Some(p),
            _ => None,
        })
    }

    /// The footprints of the provenance entries, if any (format 2.1).
    pub fn footprints(&self) -> Option<FootprintView<'a>> {
        self.chunks().find_map(|c| match c {
            ChunkView::Footprints(f) => Some(f),
            _ => None,
        })
    }

    /// The provenance table, if any.
    pub fn provenance(&self) -> Option<ProvenanceView<'a>> {
        self.chunks().find_map(|c| match c {
            ChunkView::Provenance(p) => Some(p),
            _ => None,
        })
    }
}

fn parse_chunk<'a>(
    tag: Tag,
    data: &'a [u8],
    index: u32,
    profile: &DeviceProfile,
    full: bool,
) -> Result<Option<ChunkView<'a>>, FormatError> {
    let actuators = profile.actuator_count();
    Ok(Some(match tag {
        Tag::VIBRATION | Tag::GRATING => ChunkView::Mask(MaskView::parse(data, tag, index)?),
        Tag::VIBRATION_DISTANCE | Tag::GRATING_DISTANCE => {
            ChunkView::Distance(DistanceView::parse(data, tag, index, full)?)
        }
        Tag::DOTS => ChunkView::Dots(DotTableView::parse(data, index, full)?),
        Tag::STROKES => ChunkView::Strokes(StrokeTableView::parse(data, index, actuators, full)?),
        Tag::HEIGHT => ChunkView::Height(HeightFieldView::parse(data, index, full)?),
        Tag::PROVENANCE => ChunkView::Provenance(ProvenanceView::parse(data, index, full)?),
        Tag::FOOTPRINTS => ChunkView::Footprints(FootprintView::parse(data, index, full)?),
        Tag::PINS => ChunkView::Pins(PinImageView::parse(data, index, profile, full)?),
        _ => return Ok(None),
    }))
}
