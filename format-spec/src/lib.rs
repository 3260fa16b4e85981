//! The taxel bundle format, version 2.
//!
//! A bundle is one packed binary file that a tactile device's player reads in
//! place: a 32-byte header, a table of tagged chunks (each with its length,
//! a required flag and a CRC-32), then the chunks' data, 8-byte aligned and
//! little-endian. `SPEC.md` beside this crate is the normative description;
//! this crate is its only implementation of the byte layout.
//!
//! - [`BundleView::parse`] validates a whole bundle (magic, version, bounds,
//!   checksums, every field of every known chunk) and then hands out
//!   zero-copy views of its chunks. It allocates nothing.
//! - [`Bundle`] is the owned model; [`Bundle::to_bytes`] writes the canonical
//!   encoding and [`Bundle::from_view`] copies a validated bundle into it.
//! - [`stored`] is the form a bundle file has on a disk or a wire (format
//!   4.7): the plain bundle compressed. [`stored::plain`] (or
//!   [`stored::inflate_into`], without an allocator) gives the plain bundle
//!   back, once, when a file is loaded; [`Bundle::to_stored_bytes`] writes it.
//! - [`DeviceProfile`] describes a device; with the `std` feature,
//!   [`profiles`] parses profile TOML files and provides the built-in ones.
//!
//! ```
//! use taxel_format::{Bundle, BundleView, Manifest, profiles};
//!
//! let profile = profiles::builtin("stress2").unwrap();
//! let bundle = Bundle::new(Manifest::new(profile));
//! let bytes = bundle.to_bytes().unwrap();
//! let view = BundleView::parse(&bytes).unwrap();
//! assert_eq!(view.manifest().profile.name.as_str(), "stress2");
//! assert_eq!(Bundle::from_view(&view), bundle);
//! ```
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

mod bytes;
mod container;
mod distance;
mod dots;
mod error;
mod footprint;
mod height;
mod height_tiles;
#[cfg(feature = "std")]
pub mod lookup;
mod manifest;
mod mask;
mod model;
mod pins;
mod profile;
#[cfg(feature = "profiles")]
pub mod profiles;
mod provenance;
pub mod sample;
pub mod stored;
mod strokes;
mod units;
mod view;

pub use container::{
    CHUNK_ALIGN, FORMAT_MAJOR, FORMAT_MINOR, HEADER_LEN, MAGIC, MAX_CHUNKS, MAX_FILE_LEN, TABLE_ENTRY_LEN,
};
pub use distance::{
    DISTANCE_ZERO, DistanceLayer, DistanceView, MAX_ARC_RADIUS, MAX_DISTANCE_TILES, MAX_FINE, MAX_PLANE_CODE,
    MAX_PLANE_GRADIENT, MAX_SOFT_MM, PLANE_RECORD_LEN, SEGMENT_TILE_RECORDS, SEGMENTS_PER_TILE, TILE_ARC, TILE_BEND,
    TILE_CELLS, TILE_CORNER, TILE_CORNER_RECORD_MASK, TILE_FINE, TILE_FINE_FIRST_MASK, TILE_FINE_PAIR, TILE_FINE_SHIFT,
    TILE_FIRST_STORED, TILE_INSIDE, TILE_NOTCH, TILE_OUTSIDE, TILE_PLANE, TILE_RECORD_MASK, TILE_RIDGE, TILE_SAMPLES,
    TILE_SEGMENTS, TILE_SIDE, Tile, TileEntry, TileGroup, TileIter, TileKind, TilePlane, arc_code, bend_code,
    fine_cell, fine_entry, is_cut_arc, profile as edge_profile, ramp as edge_ramp, segments_code,
};
pub use dots::{Dot, DotGrid, DotKind, DotRun, DotTable, DotTableView, MAX_DOT_GRID_CELLS, MAX_DOTS};
pub use error::FormatError;
pub use footprint::{
    Footprint, FootprintKind, FootprintRing, FootprintShape, FootprintView, Footprints, MAX_FOOTPRINT_POINTS,
    MAX_FOOTPRINT_RINGS, MAX_FOOTPRINT_SHAPES,
};
pub use height::{
    CellNodes, FIELD_CONTACT, FIELD_EDGE, HeightEncoding, HeightField, HeightFieldView, MAX_FIELD_NODES, MAX_FIELD_SIDE,
};
pub use height_tiles::{
    CellHeights, FieldReader, MAX_CODE as MAX_FIELD_CODE, SUPER as FIELD_SUPERBLOCK_TILES, TILE as FIELD_TILE,
};
pub use manifest::{MANIFEST_LEN, Manifest};
pub use mask::{MAX_MASK_SAMPLES, MAX_MASK_SIDE, MaskKind, MaskLayer, MaskSamples, MaskView};
pub use model::{Bundle, Chunk, RawChunk};
pub use pins::{MAX_BLINK_MS, MAX_PIN_IMAGE, MAX_PIN_SIDE, MAX_TEXT_CELLS, Navigation, Pin, PinImage, PinImageView};
pub use profile::{
    DeviceProfile, Family, FamilyParams, FingerParams, GridParams, MAX_ACTUATORS, MAX_PIN_HEIGHT, MAX_PINS,
    MAX_PRINT_GRID, MAX_RATE_HZ, MAX_TEXT_LINE_CELLS, Medium, PinParams, PrintParams, ProfileName,
};
pub use provenance::{MAX_PROVENANCE_ENTRIES, Provenance, ProvenanceEntry, ProvenanceView};
pub use strokes::{
    Drive, MAX_DRIVES_PER_POINT, MAX_STROKE_DRIVES, MAX_STROKE_POINTS, MAX_STROKES, Stroke, StrokePoint, StrokeTable,
    StrokeTableView,
};
pub use units::{ActuatorIndex, FixedStr, MilliHertz, Mm, Tick};
pub use view::{BundleView, ChunkView};

/// A four-byte chunk tag such as `MANI` or `GRAT`.
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Tag(pub [u8; 4]);

impl Tag {
    /// The manifest: the device profile and build identity. Required, first, exactly once.
    pub const MANIFEST: Tag = Tag(*b"MANI");
    /// A vibration layer: a mask and a frequency. Required.
    pub const VIBRATION: Tag = Tag(*b"VIBR");
    /// A grating layer: a mask, a wavelength and an angle. Required.
    pub const GRATING: Tag = Tag(*b"GRAT");
    /// A vibration layer by style: a signed distance field in sparse tiles and a frequency. Required.
    pub const VIBRATION_DISTANCE: Tag = Tag(*b"VDST");
    /// A grating layer by style: a signed distance field, a wavelength and an angle. Required.
    pub const GRATING_DISTANCE: Tag = Tag(*b"GDST");
    /// A dot table (outline dots, point symbols or braille). Required.
    pub const DOTS: Tag = Tag(*b"DOTS");
    /// A stroke table for a vibrotactile grid. Required.
    pub const STROKES: Tag = Tag(*b"STRK");
    /// A height and gradient field for the finger device. Required.
    pub const HEIGHT: Tag = Tag(*b"HFLD");
    /// A pin image for a pin-matrix display. Required, at most once, only for family 4.
    pub const PINS: Tag = Tag(*b"PINS");
    /// Provenance: SVG ids, titles and labels. Optional, at most once.
    pub const PROVENANCE: Tag = Tag(*b"PROV");
    /// Footprints: where each provenance entry lies, for the point lookup. Optional, at most once (format 2.1).
    pub const FOOTPRINTS: Tag = Tag(*b"FOOT");
    /// Stands for the header itself in file-level errors.
    pub const HEADER: Tag = Tag(*b"HEAD");

    /// The tag as text (non-printable bytes as `?`).
    pub fn as_chars(&self) -> [char; 4] {
        self.0.map(|b| if b.is_ascii_graphic() { b as char } else { '?' })
    }
}

impl core::fmt::Display for Tag {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        for c in self.as_chars() {
            core::fmt::Write::write_char(f, c)?;
        }
        Ok(())
    }
}

impl core::fmt::Debug for Tag {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "Tag({self})")
    }
}

/// Checks that `v` is finite (used by every chunk validator).
pub(crate) fn finite(v: f32, tag: Tag, index: u32, field: &'static str) -> Result<f32, FormatError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(FormatError::InvalidValue { tag, index, field, expected: "a finite number" })
    }
}

/// Checks that `v` is in `lo..=hi` (and so finite).
pub(crate) fn in_range(
    v: f32,
    lo: f32,
    hi: f32,
    tag: Tag,
    index: u32,
    field: &'static str,
    expected: &'static str,
) -> Result<f32, FormatError> {
    if v >= lo && v <= hi { Ok(v) } else { Err(FormatError::InvalidValue { tag, index, field, expected }) }
}

/// The source index stored for "no provenance entry".
pub(crate) const NO_SOURCE: u32 = u32::MAX;

#[inline]
pub(crate) fn source_from_raw(raw: u32) -> Option<u32> {
    (raw != NO_SOURCE).then_some(raw)
}
