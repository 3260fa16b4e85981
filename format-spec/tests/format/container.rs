//! Container-level errors: truncation, corruption, magic, versions, unknown
//! chunks, order, placement and padding.

use taxel_format::{Bundle, BundleView, ChunkView, FormatError, Tag, sample};

use crate::craft::{craft, craft_version, decompose, every_kind_bytes, raw, reseal, span};

#[test]
fn the_spec_encoder_and_the_writer_agree() {
    for b in [sample::tiny(), sample::every_kind()] {
        let bytes = b.to_bytes().unwrap();
        assert_eq!(craft(&decompose(&bytes)), bytes);
    }
}

#[test]
fn truncated_at_every_offset_is_an_error() {
    let b = every_kind_bytes();
    for n in 0..b.len() {
        let err = BundleView::parse(&b[..n]).unwrap_err();
        if n < 32 {
            assert!(
                matches!(err, FormatError::Truncated { what: "header", offset: 0, needed: 32, available } if available == n as u64),
                "{n}: {err:?}"
            );
        } else {
            assert_eq!(err, FormatError::FileLength { header: b.len() as u64, actual: n as u64 }, "{n}");
        }
        assert!(Bundle::from_bytes(&b[..n]).is_err());
    }
}

#[test]
fn every_single_bit_flip_is_caught_and_named() {
    let b = every_kind_bytes();
    let chunks = decompose(&b);
    let count = chunks.len();
    let table_end = 32 + 32 * count;
    // Which chunk owns each byte (None: header, table or padding).
    let mut owner = vec![None; b.len()];
    for i in 0..count {
        let (o, l) = span(&b, i);
        owner[o..o + l].iter_mut().for_each(|x| *x = Some(i));
    }
    for byte in 0..b.len() {
        for bit in 0..8 {
            let mut m = b.clone();
            m[byte] ^= 1 << bit;
            let err = BundleView::parse(&m).unwrap_err();
            let ok = match byte {
                0..8 => matches!(err, FormatError::BadMagic { .. }),
                8..10 => matches!(err, FormatError::UnsupportedVersion { .. }),
                // Minor version and table checksum: covered by the table checksum.
                10..12 | 24..28 => matches!(err, FormatError::TableChecksum { .. }),
                12..16 => matches!(
                    err,
                    FormatError::TableChecksum { .. }
                        | FormatError::Limit { .. }
                        | FormatError::Truncated { what: "chunk table", .. }
                ),
                16..24 => matches!(err, FormatError::FileLength { .. } | FormatError::Limit { .. }),
                28..32 => err == FormatError::NonZeroReserved { offset: 28 },
                _ if byte < table_end => matches!(err, FormatError::TableChecksum { .. }),
                _ => match owner[byte] {
                    Some(i) => {
                        err == FormatError::ChunkChecksum {
                            index: i as u32,
                            tag: Tag(chunks[i].tag),
                            expected: crc32fast::hash(&chunks[i].data),
                            found: crc32fast::hash(&m[span(&b, i).0..][..span(&b, i).1]),
                        }
                    }
                    None => err == FormatError::NonZeroReserved { offset: byte as u64 },
                },
            };
            assert!(ok, "byte {byte} bit {bit}: {err:?}");
        }
    }
}

#[test]
fn checksum_errors_name_the_chunk() {
    let mut b = every_kind_bytes();
    let (o, _) = span(&b, 2);
    b[o + 50] ^= 4;
    let msg = BundleView::parse(&b).unwrap_err().to_string();
    assert!(msg.starts_with("chunk 2 (GRAT) is corrupt"), "{msg}");
}

#[test]
fn wrong_magic_is_refused_first() {
    let err = BundleView::parse(b"PK\x03\x04 not a bundle at all, just some zip file......").unwrap_err();
    assert_eq!(err, FormatError::BadMagic { found: *b"PK\x03\x04 not" });
    assert!(err.to_string().starts_with("not a taxel bundle"));
    // Short files that are not bundles are named as such, not as truncated.
    assert!(matches!(BundleView::parse(b"hi").unwrap_err(), FormatError::BadMagic { .. }));
    // A text-mode transfer that turned CR-LF into LF breaks the magic.
    let mut b = every_kind_bytes();
    b.remove(4);
    assert!(matches!(BundleView::parse(&b).unwrap_err(), FormatError::BadMagic { .. }));
}

#[test]
fn a_future_major_version_is_refused_and_a_future_minor_is_read() {
    let chunks = decompose(&every_kind_bytes());
    let err = BundleView::parse(&craft_version(&chunks, 5, 0)).unwrap_err();
    assert_eq!(err, FormatError::UnsupportedVersion { major: 5, minor: 0 });
    assert!(err.to_string().contains("5.0") && err.to_string().contains("newer taxel"), "{err}");
    assert!(matches!(
        BundleView::parse(&craft_version(&chunks, 0, 9)).unwrap_err(),
        FormatError::UnsupportedVersion { .. }
    ));
    // A 1.x bundle (one raster mask per shape) is refused with the version
    // and what to do about it.
    let old = BundleView::parse(&craft_version(&chunks, 1, 0)).unwrap_err();
    assert_eq!(old, FormatError::UnsupportedVersion { major: 1, minor: 0 });
    let text = old.to_string();
    assert!(text.contains("version 1.0") && text.contains("rebuild") && text.contains("taxel build"), "{text}");
    // So is a 2.x bundle (distance layers without plane tiles): format 3.0
    // changed what a distance layer's tile index may hold.
    let old = BundleView::parse(&craft_version(&chunks, 2, 1)).unwrap_err();
    let text = old.to_string();
    assert!(text.contains("version 2.1") && text.contains("rebuild") && text.contains("taxel build"), "{text}");
    // And a 3.x bundle (no corner or notch tiles): format 4.0 changed the
    // tile index again.
    let old = BundleView::parse(&craft_version(&chunks, 3, 0)).unwrap_err();
    let text = old.to_string();
    assert!(text.contains("version 3.0") && text.contains("rebuild") && text.contains("taxel build"), "{text}");
    let newer = craft_version(&chunks, 4, 7);
    let view = BundleView::parse(&newer).unwrap();
    assert_eq!(view.version(), (4, 7));
    // A rewriting tool keeps the minor version and so every byte.
    assert_eq!(Bundle::from_view(&view).to_bytes_with_minor(7).unwrap(), newer);
}

#[test]
fn an_unknown_required_chunk_is_refused() {
    let mut chunks = decompose(&every_kind_bytes());
    chunks.insert(3, raw(b"NEW!", true, vec![9; 12]));
    let err = BundleView::parse(&craft(&chunks)).unwrap_err();
    assert_eq!(err, FormatError::UnknownRequiredChunk { index: 3, tag: Tag(*b"NEW!") });
    assert!(err.to_string().contains("newer taxel"));
}

#[test]
fn an_unknown_optional_chunk_is_skipped_and_preserved() {
    let mut chunks = decompose(&every_kind_bytes());
    chunks.insert(1, raw(b"NEW?", false, vec![7; 3]));
    let bytes = craft(&chunks);
    let view = BundleView::parse(&bytes).unwrap();
    let unknown: Vec<_> = view
        .chunks()
        .filter_map(|c| match c {
            ChunkView::Unknown { tag, required, data } => Some((tag, required, data.to_vec())),
            _ => None,
        })
        .collect();
    assert_eq!(unknown, vec![(Tag(*b"NEW?"), false, vec![7; 3]), (sample::EXTRA_TAG, false, vec![1, 2, 3, 4, 5])]);
    // Every known chunk is still there, in order.
    assert_eq!(view.chunks().count(), chunks.len() - 1);
    assert_eq!(Bundle::from_view(&view).to_bytes().unwrap(), bytes);
}

#[test]
fn known_chunks_must_carry_their_required_flag() {
    let mut chunks = decompose(&every_kind_bytes());
    let p = crate::craft::find(&chunks, b"PROV");
    chunks[p].flags = 1;
    let err = BundleView::parse(&craft(&chunks)).unwrap_err();
    assert_eq!(err, FormatError::RequiredFlag { index: p as u32, tag: Tag::PROVENANCE, expected: false });
    let mut chunks = decompose(&every_kind_bytes());
    chunks[1].flags = 0;
    assert_eq!(
        BundleView::parse(&craft(&chunks)).unwrap_err(),
        FormatError::RequiredFlag { index: 1, tag: Tag::VIBRATION, expected: true }
    );
}

#[test]
fn chunk_order_rules() {
    let chunks = decompose(&every_kind_bytes());
    // The manifest must come first.
    let mut c = chunks.clone();
    c.swap(0, 1);
    assert!(matches!(BundleView::parse(&craft(&c)).unwrap_err(), FormatError::ChunkOrder { index: 0, .. }));
    // Even an optional chunk may not come before it.
    let mut c = chunks.clone();
    c.insert(0, raw(b"NEW?", false, vec![]));
    assert!(matches!(BundleView::parse(&craft(&c)).unwrap_err(), FormatError::ChunkOrder { index: 0, .. }));
    // Exactly once.
    let mut c = chunks.clone();
    c.push(chunks[0].clone());
    assert!(matches!(BundleView::parse(&craft(&c)).unwrap_err(), FormatError::ChunkOrder { tag: Tag::MANIFEST, .. }));
    // At most one provenance chunk.
    let mut c = chunks.clone();
    let p = crate::craft::find(&chunks, b"PROV");
    c.push(chunks[p].clone());
    assert_eq!(
        BundleView::parse(&craft(&c)).unwrap_err(),
        FormatError::ChunkOrder {
            index: c.len() as u32 - 1,
            tag: Tag::PROVENANCE,
            rule: "at most one provenance chunk"
        }
    );
    // An empty table has no manifest.
    assert_eq!(BundleView::parse(&craft(&[])).unwrap_err(), FormatError::MissingManifest);
}

#[test]
fn placement_and_padding_are_canonical() {
    let b = every_kind_bytes();
    let (o1, l1) = span(&b, 1);
    // A chunk moved by 8 bytes (table edited, checksums re-sealed).
    let mut m = b.clone();
    let e = 32 + 32;
    m[e + 8..e + 16].copy_from_slice(&(o1 as u64 + 8).to_le_bytes());
    reseal(&mut m);
    assert_eq!(
        BundleView::parse(&m).unwrap_err(),
        FormatError::ChunkPlacement { index: 1, tag: Tag::VIBRATION, expected: o1 as u64, found: o1 as u64 + 8 }
    );
    // A non-zero padding byte after chunk 1 (its length is not a multiple of 8).
    assert_ne!(l1 % 8, 0);
    let mut m = b.clone();
    m[o1 + l1] = 0xAA;
    assert_eq!(BundleView::parse(&m).unwrap_err(), FormatError::NonZeroReserved { offset: (o1 + l1) as u64 });
    // Unknown flag bits and reserved fields in the table and header.
    for (at, offset) in [(e + 4, e + 4), (e + 5, e + 4), (e + 6, e + 4), (e + 28, e + 28)] {
        let mut m = b.clone();
        m[at] |= 0x40;
        reseal(&mut m);
        assert_eq!(BundleView::parse(&m).unwrap_err(), FormatError::NonZeroReserved { offset: offset as u64 }, "{at}");
    }
    // Data after the last chunk's padding, with the header's length updated.
    let mut m = b.clone();
    m.extend_from_slice(&[0; 8]);
    m[16..24].copy_from_slice(&(b.len() as u64 + 8).to_le_bytes());
    reseal(&mut m);
    assert_eq!(
        BundleView::parse(&m).unwrap_err(),
        FormatError::CanonicalLength { expected: b.len() as u64, found: b.len() as u64 + 8 }
    );
    // Appended bytes without a header update.
    let mut m = b.clone();
    m.push(0);
    assert_eq!(
        BundleView::parse(&m).unwrap_err(),
        FormatError::FileLength { header: b.len() as u64, actual: b.len() as u64 + 1 }
    );
    // A last chunk that claims more bytes than the file has.
    let chunks = decompose(&b);
    let last = chunks.len() - 1;
    let (ol, ll) = span(&b, last);
    let mut m = b.clone();
    let e = 32 + 32 * last;
    m[e + 16..e + 24].copy_from_slice(&(ll as u64 + 100).to_le_bytes());
    reseal(&mut m);
    assert_eq!(
        BundleView::parse(&m).unwrap_err(),
        FormatError::Truncated {
            what: "chunk data",
            offset: ol as u64,
            needed: ll as u64 + 100,
            available: (b.len() - ol) as u64
        }
    );
}

#[test]
fn errors_read_as_sentences_naming_what_was_wrong() {
    let msgs = [
        FormatError::Truncated { what: "header", offset: 0, needed: 32, available: 3 }.to_string(),
        FormatError::ChunkPlacement { index: 1, tag: Tag::DOTS, expected: 8, found: 16 }.to_string(),
        FormatError::Limit { tag: Tag::DOTS, field: "dot count", value: 9, limit: 8 }.to_string(),
    ];
    assert_eq!(msgs[0], "truncated bundle: header at offset 0 needs 32 bytes but only 3 remain");
    assert_eq!(msgs[1], "chunk 1 (DOTS) starts at offset 16, but the canonical layout puts it at 8");
    assert_eq!(msgs[2], "dot count in the DOTS chunk is 9, above the limit of 8");
    for m in msgs {
        assert!(!m.ends_with('.') && m.chars().next().unwrap().is_lowercase(), "{m}");
    }
}
