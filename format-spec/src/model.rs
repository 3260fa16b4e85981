//! The owned bundle model and its canonical writer.

use alloc::vec::Vec;

use crate::Tag;
use crate::container::{self, Encoded};
use crate::distance::DistanceLayer;
use crate::dots::DotTable;
use crate::error::FormatError;
use crate::footprint::Footprints;
use crate::height::HeightField;
use crate::manifest::Manifest;
use crate::mask::MaskLayer;
use crate::pins::PinImage;
use crate::provenance::Provenance;
use crate::strokes::StrokeTable;
use crate::view::{BundleView, ChunkView};

/// A chunk this crate does not interpret, kept byte for byte (an optional
/// chunk from a newer minor version, say).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RawChunk {
    /// Its tag.
    pub tag: Tag,
    /// Whether readers that do not know it must refuse the bundle.
    pub required: bool,
    /// Its data.
    pub data: Vec<u8>,
}

/// One chunk after the manifest.
#[derive(Debug, Clone, PartialEq)]
pub enum Chunk {
    /// A vibration or grating mask (`VIBR` / `GRAT`).
    Mask(MaskLayer),
    /// A vibration or grating layer by style, as a distance field (`VDST` / `GDST`).
    Distance(DistanceLayer),
    /// A dot table (`DOTS`).
    Dots(DotTable),
    /// A stroke table (`STRK`).
    Strokes(StrokeTable),
    /// A height field (`HFLD`).
    Height(HeightField),
    /// A pin image (`PINS`).
    Pins(PinImage),
    /// Provenance (`PROV`).
    Provenance(Provenance),
    /// Footprints of the provenance entries (`FOOT`, format 2.1).
    Footprints(Footprints),
    /// Anything else, kept as it was.
    Raw(RawChunk),
}

impl Chunk {
    /// The chunk's tag.
    pub fn tag(&self) -> Tag {
        match self {
            Chunk::Mask(m) => m.kind.tag(),
            Chunk::Distance(d) => d.tag(),
            Chunk::Dots(_) => Tag::DOTS,
            Chunk::Strokes(_) => Tag::STROKES,
            Chunk::Height(_) => Tag::HEIGHT,
            Chunk::Pins(_) => Tag::PINS,
            Chunk::Provenance(_) => Tag::PROVENANCE,
            Chunk::Footprints(_) => Tag::FOOTPRINTS,
            Chunk::Raw(r) => r.tag,
        }
    }
}

/// A whole bundle: the manifest and the chunks after it, in file order.
#[derive(Debug, Clone, PartialEq)]
pub struct Bundle {
    /// The manifest.
    pub manifest: Manifest,
    /// Layers, provenance and any other chunks, in the order they are written.
    pub chunks: Vec<Chunk>,
}

impl Bundle {
    /// A bundle with only a manifest.
    pub fn new(manifest: Manifest) -> Self {
        Bundle { manifest, chunks: Vec::new() }
    }

    /// The canonical encoding, as format version
    /// [`FORMAT_MAJOR`](crate::FORMAT_MAJOR).*m*, where *m* is the lowest
    /// minor version that has every chunk of the bundle (SPEC.md section 12):
    /// 6 when a height field is tiled (format 4.6), else 4 when a distance layer holds a fine tile (format 4.4), else 3 when
    /// one holds a cut arc (format 4.3), else 2 when one
    /// holds a segments tile (format 4.2), else 1
    /// when one holds an arc tile (format 4.1), else 0.
    /// The result is checked with the reader before it is returned, so a
    /// bundle that the writer accepts always reads back.
    pub fn to_bytes(&self) -> Result<Vec<u8>, FormatError> {
        self.to_bytes_with_minor(self.lowest_minor())
    }

    /// The stored form (SPEC.md section 15): the canonical encoding
    /// ([`Bundle::to_bytes`]) compressed for a file or a wire, as `taxel
    /// build` writes it. [`stored::plain`](crate::stored::plain) gives the
    /// canonical encoding back.
    pub fn to_stored_bytes(&self) -> Result<Vec<u8>, FormatError> {
        crate::stored::store(&self.to_bytes()?)
    }

    /// The lowest minor version that defines every chunk of the bundle.
    pub fn lowest_minor(&self) -> u16 {
        let holds = |kind: fn(crate::TileEntry) -> bool| {
            self.chunks.iter().any(|c| match c {
                Chunk::Distance(d) => d.tiles.iter().any(|&e| kind(crate::TileEntry::of(e))),
                _ => false,
            })
        };
        // A cut arc (format 4.3): an arc tile whose second record holds a plane.
        let cut_arc = self.chunks.iter().any(|c| match c {
            Chunk::Distance(d) => d.tiles.iter().any(|&e| match crate::TileEntry::of(e) {
                crate::TileEntry::Arc(p) => d.planes.get(p as usize + 1).is_some_and(crate::is_cut_arc),
                _ => false,
            }),
            _ => false,
        });
        let tiled_field = self
            .chunks
            .iter()
            .any(|c| matches!(c, Chunk::Height(h) if matches!(h.encoding, crate::HeightEncoding::Tiled { .. })));
        if tiled_field {
            6
        } else if holds(|e| matches!(e, crate::TileEntry::Fine { .. })) {
            4
        } else if cut_arc {
            3
        } else if holds(|e| matches!(e, crate::TileEntry::Segments(_))) {
            2
        } else {
            u16::from(holds(|e| matches!(e, crate::TileEntry::Arc(_))))
        }
    }

    /// The canonical encoding with minor version `minor` in the header: for
    /// tools that rewrite a bundle from a newer minor version (whose unknown
    /// optional chunks they keep as [`RawChunk`]s) without changing a byte.
    pub fn to_bytes_with_minor(&self, minor: u16) -> Result<Vec<u8>, FormatError> {
        // Print media make device files, not bundles: no manifest holds the family.
        if self.manifest.profile.family() == crate::Family::Print {
            return Err(FormatError::InvalidValue {
                tag: Tag::MANIFEST,
                index: 0,
                field: "family",
                expected: "a family that plays bundles (a print profile makes PDF, PNG or STL files)",
            });
        }
        let mut encoded = Vec::with_capacity(self.chunks.len() + 1);
        encoded.push(Encoded { tag: Tag::MANIFEST, required: true, data: self.manifest.encode() });
        for (i, c) in self.chunks.iter().enumerate() {
            // Chunk index in the table: the manifest is chunk 0.
            let index = u32::try_from(i + 1).unwrap_or(u32::MAX);
            match c {
                Chunk::Mask(m) => m.check_shape(index)?,
                Chunk::Distance(d) => d.check_shape(index)?,
                Chunk::Strokes(s) => s.check_shape()?,
                Chunk::Height(h) => h.check_shape(index)?,
                Chunk::Pins(p) => p.check_shape(index)?,
                _ => {}
            }
            encoded.push(match c {
                Chunk::Mask(m) => Encoded { tag: m.kind.tag(), required: true, data: m.encode() },
                Chunk::Distance(d) => Encoded { tag: d.tag(), required: true, data: d.encode() },
                Chunk::Dots(d) => Encoded { tag: Tag::DOTS, required: true, data: d.encode() },
                Chunk::Strokes(s) => Encoded { tag: Tag::STROKES, required: true, data: s.encode() },
                Chunk::Height(h) => Encoded { tag: Tag::HEIGHT, required: true, data: h.encode(index)? },
                Chunk::Pins(p) => Encoded { tag: Tag::PINS, required: true, data: p.encode() },
                Chunk::Provenance(p) => Encoded { tag: Tag::PROVENANCE, required: false, data: p.encode() },
                Chunk::Footprints(f) => Encoded { tag: Tag::FOOTPRINTS, required: false, data: f.encode() },
                Chunk::Raw(r) => Encoded { tag: r.tag, required: r.required, data: r.data.clone() },
            });
        }
        let bytes = container::assemble(&encoded, minor)?;
        BundleView::parse(&bytes)?;
        Ok(bytes)
    }

    /// Copies a validated bundle into the owned model.
    pub fn from_view(view: &BundleView<'_>) -> Self {
        let chunks = view
            .chunks()
            .map(|c| match c {
                ChunkView::Mask(m) => Chunk::Mask(MaskLayer::from_view(&m)),
                ChunkView::Distance(d) => Chunk::Distance(DistanceLayer::from_view(&d)),
                ChunkView::Dots(d) => Chunk::Dots(DotTable::from_view(&d)),
                ChunkView::Strokes(s) => Chunk::Strokes(StrokeTable::from_view(&s)),
                ChunkView::Height(h) => Chunk::Height(HeightField::from_view(&h)),
                ChunkView::Pins(p) => Chunk::Pins(PinImage::from_view(&p)),
                ChunkView::Provenance(p) => Chunk::Provenance(Provenance::from_view(&p)),
                ChunkView::Footprints(f) => Chunk::Footprints(Footprints::from_view(&f)),
                ChunkView::Unknown { tag, required, data } => {
                    Chunk::Raw(RawChunk { tag, required, data: data.to_vec() })
                }
            })
            .collect();
        Bundle { manifest: *view.manifest(), chunks }
    }

    /// Reads and validates `bytes`, plain or stored (inflated first), into
    /// the owned model.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, FormatError> {
        Ok(Bundle::from_view(&BundleView::parse(&crate::stored::plain(bytes)?)?))
    }

    /// The pin image, if the bundle has one.
    pub fn pin_image(&self) -> Option<&PinImage> {
        self.chunks.iter().find_map(|c| match c {
            Chunk::Pins(p) => Some(p),
            _ => None,
        })
    }

    /// The footprints, if the bundle has them.
    pub fn footprints(&self) -> Option<&Footprints> {
        self.chunks.iter().find_map(|c| match c {
            Chunk::Footprints(f) => Some(f),
            _ => None,
        })
    }

    /// The provenance table, if the bundle has one.
    pub fn provenance(&self) -> Option<&Provenance> {
        self.chunks.iter().find_map(|c| match c {
            Chunk::Provenance(p) => Some(p),
            _ => None,
        })
    }
}
