//! Hostile sizes: counts and dimensions far beyond the file are refused from
//! the headers alone, before anything is read or allocated (the reader has no
//! allocation at all: it is `no_std` without `alloc` in its paths).

use taxel_format::{BundleView, FormatError, MAX_CHUNKS, MAX_FILE_LEN, Tag};

use crate::craft::{edit_chunk, put_u32, reseal};

fn limit_of(bytes: &[u8]) -> (Tag, &'static str, u64, u64) {
    match BundleView::parse(bytes) {
        Err(FormatError::Limit { tag, field, value, limit }) => (tag, field, value, limit),
        other => panic!("expected a limit error, got {other:?}"),
    }
}

#[test]
fn huge_header_fields() {
    let mut b = crate::craft::every_kind_bytes();
    b[16..24].copy_from_slice(&u64::MAX.to_le_bytes());
    reseal(&mut b);
    assert_eq!(limit_of(&b), (Tag::HEADER, "file length", u64::MAX, MAX_FILE_LEN));
    let mut b = crate::craft::every_kind_bytes();
    put_u32(&mut b, 12, u32::MAX);
    assert_eq!(limit_of(&b), (Tag::HEADER, "chunk count", u32::MAX as u64, MAX_CHUNKS as u64));
    // The most chunks allowed, in a small file: the table is missing, not allocated.
    let mut b = crate::craft::every_kind_bytes();
    put_u32(&mut b, 12, MAX_CHUNKS);
    let len = b.len() as u64;
    assert_eq!(
        BundleView::parse(&b).unwrap_err(),
        FormatError::Truncated { what: "chunk table", offset: 32, needed: 32 * MAX_CHUNKS as u64, available: len - 32 }
    );
}

#[test]
fn huge_chunk_counts() {
    let (tag, field, ..) = limit_of(&edit_chunk(b"DOTS", |d| put_u32(d, 4, u32::MAX)));
    assert_eq!((tag, field), (Tag::DOTS, "dot count"));
    let (_, field, value, _) = limit_of(&edit_chunk(b"DOTS", |d| {
        put_u32(d, 8, 65_536);
        put_u32(d, 12, 65_536);
    }));
    assert_eq!((field, value), ("grid cells (1 or more)", 1 << 32));
    for (o, field) in [(0, "strokes"), (4, "points"), (8, "drives")] {
        assert_eq!(limit_of(&edit_chunk(b"STRK", |d| put_u32(d, o, u32::MAX))).1, field);
    }
    assert_eq!(limit_of(&edit_chunk(b"PROV", |d| put_u32(d, 0, u32::MAX))).1, "entries");
    // 16 384 x 16 384 masks are allowed a side each but not together.
    let (_, field, value, _) = limit_of(&edit_chunk(b"VIBR", |d| {
        put_u32(d, 4, 16_384);
        put_u32(d, 8, 16_384);
    }));
    assert_eq!((field, value), ("samples", 1 << 28));
    let (_, field, value, _) = limit_of(&edit_chunk(b"HFLD", |d| {
        put_u32(d, 4, 16_384);
        put_u32(d, 8, 16_384);
    }));
    assert_eq!((field, value), ("nodes", 1 << 28));
}

#[test]
fn drives_per_point_are_bounded() {
    use taxel_format::{ActuatorIndex, Bundle, Drive, MAX_DRIVES_PER_POINT, sample};
    let mut b = sample::every_kind();
    for c in &mut b.chunks {
        if let taxel_format::Chunk::Strokes(s) = c {
            s.strokes[0].points[0].drives =
                vec![Drive { actuator: ActuatorIndex(0), intensity: 0.1 }; MAX_DRIVES_PER_POINT as usize + 1];
        }
    }
    let err = Bundle::to_bytes(&b).unwrap_err();
    assert!(matches!(err, FormatError::Limit { field: "drives per point", .. }), "{err:?}");
}
