//! The text form of a bundle: a folder that people can read and edit.
//!
//! `taxel unpack B -o DIR` writes:
//!
//! - `manifest.toml`: the format version, the generator, the content hash,
//!   and one `[[chunk]]` per chunk in table order, with its kind, its
//!   parameters and the file that holds its data;
//! - `profile.toml`: the device profile, in the same layout as a profile file
//!   (so it can also be given to `--profile`);
//! - one file per chunk, named `NN-kind.ext` after its position in the table:
//!   masks as grayscale PNG (8- or 16-bit, like the mask), dot tables, height
//!   fields and provenance as CSV, stroke tables as TOML, and chunks this
//!   version does not know as `.bin` (their bytes, unchanged).
//!
//! `taxel pack DIR -o B` reads it back; `pack(unpack(b))` is byte-identical
//! to `b`. Floats are written with Rust's shortest round-trip formatting and
//! read back from their text as `f32`, so they survive exactly. The layout is
//! documented for people in docs/text-form.md.
//!
//! [`unpack`] and [`pack`] work on bytes and file contents only; the
//! `taxel` binary does the file system part (refusing to overwrite, atomic
//! writes). The codec sits beside `taxel-format`, which it reads and writes
//! through; it is a crate of its own so that the format crate stays
//! `no_std` with no dependency on PNG, CSV or TOML.

pub mod error;
mod pins;
pub mod png;
mod read;
mod tables;
pub mod toml_in;
mod write;

pub use error::TextError;
pub use read::pack;
pub use write::unpack;

/// The manifest's file name.
pub const MANIFEST: &str = "manifest.toml";
/// The device profile's file name.
pub const PROFILE: &str = "profile.toml";
/// The first line of every manifest `taxel unpack` writes; `unpack` only
/// replaces a folder whose manifest starts with it.
pub const MANIFEST_HEADER: &str = "# A taxel bundle in text form, written by `taxel unpack`.";

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use proptest::prelude::*;
    use taxel_format::{
        Bundle, Chunk, Dot, DotKind, DotTable, FIELD_CONTACT, HeightField, Manifest, MaskKind, MaskLayer, MaskSamples,
        Mm, sample,
    };

    use super::*;

    fn round_trip(bytes: &[u8]) -> Result<Vec<u8>, TextError> {
        let files: BTreeMap<String, Vec<u8>> = unpack("b.taxel", bytes)?.into_iter().collect();
        pack(&|name: &str| files.get(name).cloned().ok_or_else(|| TextError::io(name, "missing")))
    }

    #[test]
    fn every_chunk_kind_packs_back_byte_for_byte() {
        for b in [sample::every_kind(), sample::tiny(), Bundle::new(sample::tiny().manifest)] {
            let bytes = b.to_bytes().unwrap();
            assert_eq!(round_trip(&bytes).unwrap(), bytes);
        }
        // A newer minor version with a chunk this taxel does not know, whose tag is not text.
        let mut b = sample::every_kind();
        b.chunks.push(Chunk::Raw(taxel_format::RawChunk {
            tag: taxel_format::Tag([0, 0xff, b'"', 7]),
            required: false,
            data: vec![0; 3],
        }));
        let bytes = b.to_bytes_with_minor(3).unwrap();
        assert_eq!(round_trip(&bytes).unwrap(), bytes);
    }

    #[test]
    fn tile_and_plane_rows_read_through_csv_and_say_which_line_is_wrong() {
        let bytes = sample::every_kind().to_bytes().unwrap();
        let mut files: BTreeMap<String, Vec<u8>> = unpack("b.taxel", &bytes).unwrap().into_iter().collect();
        let pack_files = |files: &BTreeMap<String, Vec<u8>>| {
            pack(&|name: &str| files.get(name).cloned().ok_or_else(|| TextError::io(name, "missing")))
        };
        // Fields padded with spaces (as earlier versions wrote plane records) read the same.
        let planes = "03-grating-field-planes.csv";
        let spaced = String::from_utf8(files[planes].clone()).unwrap().replace(',', ", ");
        files.insert(planes.into(), spaced.into_bytes());
        assert_eq!(pack_files(&files).unwrap(), bytes);
        // A row of the wrong width, and a field that is not a number, name the file and line.
        let tiles = "03-grating-field-tiles.csv";
        files.insert(tiles.into(), b"0,2,2147483648,2952790017\n1,3,3221225475\n".to_vec());
        let e = pack_files(&files).unwrap_err().to_string();
        assert!(e.starts_with(&format!("{tiles}:2:")) && e.contains("expected 4"), "{e}");
        files.insert(tiles.into(), b"0,2,2147483648,2952790017\n1,3,x,2684354564\n".to_vec());
        let e = pack_files(&files).unwrap_err().to_string();
        assert!(e.starts_with(&format!("{tiles}:2:")) && e.contains("`x`"), "{e}");
        files.insert(tiles.into(), b"0,2,2147483648,2952790017\n1,3,3221225475,2684354564\n".to_vec());
        files.insert(planes.into(), b"100.0,4.5,-2.25\n".to_vec());
        let e = pack_files(&files).unwrap_err().to_string();
        assert!(e.starts_with(&format!("{planes}:1:")) && e.contains("expected 4"), "{e}");
    }

    #[test]
    fn the_manifest_lists_every_chunk_in_order() {
        let files = unpack("b.taxel", &sample::every_kind().to_bytes().unwrap()).unwrap();
        let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            [
                "profile.toml",
                "01-vibration.png",
                "02-grating.png",
                "03-grating-field-samples.png",
                "03-grating-field-planes.csv",
                "03-grating-field-tiles.csv",
                "03-grating-field.png",
                "04-dots.csv",
                "05-dots.csv",
                "06-dots.csv",
                "07-dots.csv",
                "08-strokes.toml",
                "09-height.csv",
                "10-provenance.csv",
                "11-raw.bin",
                "manifest.toml"
            ]
        );
        // A distance layer: its amplitude as a picture, and the exact data
        // (tile index, stored tiles and plane records) that pack reads.
        let tiles = &files.iter().find(|(n, _)| n == "03-grating-field-tiles.csv").unwrap().1;
        assert_eq!(String::from_utf8(tiles.clone()).unwrap(), "0,2,2147483648,2952790017\n1,3,3221225475,2684354564\n");
        let planes = &files.iter().find(|(n, _)| n == "03-grating-field-planes.csv").unwrap().1;
        assert_eq!(
            String::from_utf8(planes.clone()).unwrap(),
            "100.0,4.5,-2.25,0.0\n130.0,-16.0,0.0,0.0\n60.0,0.0,16.0,0.0\n-10.0,3.0,1.5,160.0\n\
             200.0,-12.0,-9.0,0.0\n150.0,9.0,-12.0,0.0\n"
        );
        let manifest = String::from_utf8(files.last().unwrap().1.clone()).unwrap();
        assert!(manifest.starts_with(MANIFEST_HEADER));
        assert!(manifest.contains("kind = \"grating\"\nfile = \"02-grating.png\"\namplitude = 0.1\n"), "{manifest}");
        assert!(manifest.contains("tag = \"XTRA\"\nrequired = false\n"), "{manifest}");
        // The note on a distance layer's tile index names every kind of
        // entry, as the format spells it (fine tiles too), in comment lines.
        for kind in taxel_format::TileKind::ALL {
            let first = kind.entry_text().split(' ').next().unwrap();
            assert!(manifest.contains(&format!("{first} ")), "{kind:?}: {manifest}");
        }
        assert!(manifest.lines().filter(|l| l.contains("1610612736")).all(|l| l.starts_with("# ") && l.len() <= 100));
    }

    fn finite() -> impl Strategy<Value = f32> {
        prop_oneof![-1.0e30f32..1.0e30, -10.0f32..10.0, Just(-0.0f32), Just(1.0e-40f32)]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Arbitrary finite values survive the text form bit for bit.
        #[test]
        fn random_values_round_trip_exactly(
            origin in (finite(), finite()),
            ppm in 0.001f32..10_000.0,
            amplitude in 0.0f32..=1.0,
            samples in proptest::collection::vec(any::<u16>(), 6),
            base in (finite(), finite()),
            dots in proptest::collection::vec((-50.0f32..50.0, -50.0f32..50.0, 1.0f32..10.0, 0.0f32..=1.0, any::<Option<u32>>()), 0..20),
            heights in proptest::collection::vec((-1.0e9f32..1.0e9, -3.0f32..3.0, -3.0f32..3.0, any::<bool>()), 6),
        ) {
            let mut b = Bundle::new(Manifest::new(sample::grid_profile()));
            b.chunks.push(Chunk::Mask(MaskLayer {
                source: None,
                kind: MaskKind::Grating { wavelength: Mm(ppm.min(1e6)), angle_deg: amplitude * 360.0 - 180.0 },
                amplitude,
                origin_x: Mm(origin.0),
                origin_y: Mm(origin.1),
                px_per_mm: ppm,
                width: 3,
                height: 2,
                samples: MaskSamples::U16(samples),
            }));
            // Near an arbitrary base, so values are arbitrary but the dot grid stays small.
            let dots = dots.into_iter().map(|(x, y, r, a, s)| Dot {
                x: Mm(base.0 + x), y: Mm(base.1 + y), radius: Mm(r), amplitude: a, source: s.filter(|&s| s != u32::MAX),
            }).collect();
            b.chunks.push(Chunk::Dots(DotTable { kind: DotKind::Braille, dots }));
            let contact = |c: bool| if c { FIELD_CONTACT } else { 0 };
            b.chunks.push(Chunk::Height(HeightField {
                source: Some(0),
                cols: 3,
                rows: 2,
                origin_x: Mm(origin.0.clamp(-1e9, 1e9)),
                origin_y: Mm(origin.1.clamp(-1e9, 1e9)),
                cell: Mm(ppm),
                gradient_cap: 3.0,
                heights: heights.iter().map(|h| if h.3 { h.0 } else { 0.0 }).collect(),
                grad_x: heights.iter().map(|h| if h.3 { h.1 } else { 0.0 }).collect(),
                grad_y: heights.iter().map(|h| if h.3 { h.2 } else { 0.0 }).collect(),
                flags: heights.iter().map(|h| contact(h.3)).collect(),
                encoding: taxel_format::HeightEncoding::Float,
            }));
            let bytes = b.to_bytes().unwrap();
            prop_assert_eq!(round_trip(&bytes).unwrap(), bytes);
        }
    }
}
