use alloc::vec::Vec;

use proptest::prelude::*;

use super::*;
use crate::{Bundle, sample};

fn every_kind_plain() -> Vec<u8> {
    sample::every_kind().to_bytes().unwrap()
}

#[test]
fn a_stored_bundle_reads_back_as_its_plain_bundle_byte_for_byte() {
    for b in [sample::tiny(), sample::every_kind()] {
        let plain_bytes = b.to_bytes().unwrap();
        let file = b.to_stored_bytes().unwrap();
        assert!(is_stored(&file) && !is_stored(&plain_bytes));
        assert_eq!(plain_len(&file).unwrap(), plain_bytes.len());
        assert_eq!(&*plain(&file).unwrap(), &plain_bytes[..]);
        let mut buf = alloc::vec![0u8; plain_bytes.len()];
        assert_eq!(inflate_into(&file, &mut buf).unwrap(), &plain_bytes[..]);
        assert_eq!(Bundle::from_bytes(&file).unwrap(), b);
        // The same bundle always gives the same file.
        assert_eq!(b.to_stored_bytes().unwrap(), file);
    }
}

/// A bundle whose plain form is above [`SMALL_LEN`], so the writer takes
/// its faster level: a 16-bit grating mask of 256 x 256 samples.
fn large() -> Bundle {
    let mut b = sample::every_kind();
    // Squares of 16 samples, as a map's regions: it compresses.
    let samples = (0..256u32 * 256).map(|k| if (k % 256 / 16 + k / 4096) % 2 == 0 { 0 } else { 65_535 }).collect();
    b.chunks.push(sample::grating_mask(256, 256, samples));
    b
}

#[test]
fn a_large_bundle_stored_at_the_faster_level_reads_back_and_is_deterministic() {
    let b = large();
    let plain_bytes = b.to_bytes().unwrap();
    assert!(plain_bytes.len() > SMALL_LEN, "{} bytes", plain_bytes.len());
    let file = b.to_stored_bytes().unwrap();
    assert!(file.len() < plain_bytes.len() / 2, "{} of {} bytes", file.len(), plain_bytes.len());
    assert_eq!(&*plain(&file).unwrap(), &plain_bytes[..]);
    assert_eq!(Bundle::from_bytes(&file).unwrap(), b);
    assert_eq!(b.to_stored_bytes().unwrap(), file);
    // The stream is the one the larger level writes, not level 6's.
    let mut filtered = plain_bytes.clone();
    filter(&mut filtered);
    let at_6 = miniz_oxide::deflate::compress_to_vec(&filtered, LEVEL);
    assert_eq!(&file[STORED_HEADER_LEN..], &miniz_oxide::deflate::compress_to_vec(&filtered, LEVEL_LARGE)[..]);
    assert_ne!(&file[STORED_HEADER_LEN..], &at_6[..]);
}

#[test]
fn a_plain_bundle_passes_through_plain_unchanged() {
    let bytes = every_kind_plain();
    assert!(matches!(plain(&bytes).unwrap(), Cow::Borrowed(b) if b == &bytes[..]));
}

#[test]
fn the_filters_clear_the_numbers_and_the_points_and_restore_them() {
    let bytes = every_kind_plain();
    let mut filtered = bytes.clone();
    filter(&mut filtered);
    assert_ne!(filtered, bytes, "every_kind has numbered tiles and footprints");
    // Every numbered index entry is its kind alone.
    for (tag, start, end) in chunks(&filtered) {
        if tag == Tag::GRATING_DISTANCE || tag == Tag::VIBRATION_DISTANCE {
            let d = &filtered[start..end];
            let (s, c, r) = (u32_at(d, 0).unwrap() as usize, u32_at(d, 4).unwrap(), u32_at(d, 8).unwrap());
            for t in 0..(c * r) as usize {
                let e = u32_at(d, 48 + 4 * s + 4 * t).unwrap();
                let number = match e >> 28 {
                    0x8..=0xF => e & 0x0FFF_FFFF,
                    0x6 => e & crate::TILE_FINE_FIRST_MASK,
                    _ => e.saturating_sub(crate::TILE_FIRST_STORED),
                };
                assert_eq!(number, 0, "entry {e:#x} keeps a number");
            }
        }
    }
    unfilter(&mut filtered);
    assert_eq!(filtered, bytes);
}

#[test]
fn a_plain_reader_given_a_stored_bundle_says_to_inflate_it() {
    let file = sample::tiny().to_stored_bytes().unwrap();
    let e = BundleView::parse(&file).unwrap_err();
    assert!(matches!(e, FormatError::Stored { .. }), "{e}");
    assert!(alloc::format!("{e}").contains("inflate"), "{e}");
}

/// A stored file with its header's field at `offset` set to `value`.
fn with_field(file: &[u8], offset: usize, value: &[u8]) -> Vec<u8> {
    let mut f = file.to_vec();
    f[offset..offset + value.len()].copy_from_slice(value);
    f
}

#[test]
fn a_damaged_stored_bundle_is_refused_with_what_is_wrong() {
    let file = sample::every_kind().to_stored_bytes().unwrap();
    let len = plain_len(&file).unwrap() as u64;
    let cases: [(Vec<u8>, &str); 8] = [
        (file[..20].to_vec(), "truncated"),
        (with_field(&file, 8, &5u16.to_le_bytes()), "version"),
        (with_field(&file, 10, &6u16.to_le_bytes()), "version"),
        (with_field(&file, 12, &1u32.to_le_bytes()), "reserved"),
        (with_field(&file, 16, &(MAX_FILE_LEN + 1).to_le_bytes()), "limit"),
        (with_field(&file, 16, &(len + 8).to_le_bytes()), "less than the plain length"),
        (with_field(&file, 16, &(len - 8).to_le_bytes()), "more than the plain length"),
        (with_field(&file, 24, &0u32.to_le_bytes()), "checksum"),
    ];
    for (bytes, said) in cases {
        let e = plain(&bytes).unwrap_err();
        assert!(alloc::format!("{e}").contains(said), "expected {said:?}, got: {e}");
    }
    let cut = &file[..file.len() - 10];
    assert!(alloc::format!("{}", plain(cut).unwrap_err()).contains("cut short"));
    let mut buf = alloc::vec![0u8; len as usize - 1];
    assert!(inflate_into(&file, &mut buf).is_err(), "a buffer of the wrong length");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Any byte of a stored file changed, or any tail: an error or the
    /// bundle itself, never a panic and never another bundle.
    #[test]
    fn a_changed_stored_file_is_refused_or_the_same(at in 0usize..4096, byte in any::<u8>(), cut in 0usize..4096) {
        let b = sample::every_kind();
        let file = b.to_stored_bytes().unwrap();
        let mut changed = file.clone();
        let at = at % changed.len();
        changed[at] = byte;
        if let Ok(read) = Bundle::from_bytes(&changed) {
            prop_assert_eq!(read, b);
        }
        let cut = cut % file.len();
        prop_assert!(Bundle::from_bytes(&file[..cut]).is_err());
    }

    /// The reader's filter on arbitrary bytes (a table that points anywhere)
    /// never panics.
    #[test]
    fn the_filters_never_panic(mut bytes in proptest::collection::vec(any::<u8>(), 0..600), tag in 0usize..3) {
        let tags = [*b"VDST", *b"GDST", *b"FOOT"];
        if bytes.len() >= 68 {
            bytes[12..16].copy_from_slice(&2u32.to_le_bytes());
            bytes[32..36].copy_from_slice(&tags[tag]);
            bytes[64..68].copy_from_slice(&tags[(tag + 1) % 3]);
        }
        unfilter(&mut bytes);
        filter(&mut bytes);
    }

    /// A real bundle whose distance and footprint headers (counts, tile
    /// grid) or table entries hold any value: the filters never panic.
    #[test]
    fn the_filters_never_panic_on_a_bundle_with_changed_headers(field in 0usize..64, value in any::<u32>()) {
        let mut bytes = every_kind_plain();
        let found: Vec<(Tag, usize, usize)> = chunks(&bytes).collect();
        let headers: Vec<usize> = found
            .iter()
            .filter(|(t, _, _)| [Tag::GRATING_DISTANCE, Tag::VIBRATION_DISTANCE, Tag::FOOTPRINTS].contains(t))
            .flat_map(|&(_, start, _)| (0..12).step_by(4).map(move |o| start + o))
            .chain((0..found.len()).flat_map(|i| [32 + 32 * i + 8, 32 + 32 * i + 16]))
            .collect();
        let at = headers[field % headers.len()];
        bytes[at..at + 4].copy_from_slice(&value.to_le_bytes());
        unfilter(&mut bytes);
        filter(&mut bytes);
    }
}
