//! The stored form (SPEC.md section 15, format 4.7): a bundle compressed for
//! storage and transfer.
//!
//! A player reads a bundle in place, so the plain form of sections 2 to 14
//! keeps its fixed-width fields. A file on a disk or a wire has no such
//! need: `taxel build` writes the **stored form**, a 32-byte header and one
//! raw DEFLATE stream (RFC 1951) of the plain bundle, after two
//! length-preserving filters that take out what the plain form repeats (a
//! distance layer's record and tile numbers, which follow from their order;
//! a footprint's points, close to the point before). A reader inflates it
//! once, when it loads the file, into a buffer of [`plain_len`] bytes
//! ([`inflate_into`], which allocates nothing) or a vector ([`plain`]), and
//! then parses the plain bundle with [`BundleView::parse`](crate::BundleView::parse)
//! as before: the per-tick path does not change.
//!
//! ```
//! use taxel_format::{Bundle, BundleView, Manifest, profiles, stored};
//!
//! let bundle = Bundle::new(Manifest::new(profiles::builtin("stress2").unwrap()));
//! let file = bundle.to_stored_bytes().unwrap();
//! assert!(stored::is_stored(&file));
//! // With an allocator:
//! let plain = stored::plain(&file).unwrap();
//! assert_eq!(Bundle::from_view(&BundleView::parse(&plain).unwrap()), bundle);
//! // Without one, into a buffer of the length the header gives:
//! let mut buf = [0u8; 256];
//! let n = stored::plain_len(&file).unwrap();
//! let plain = stored::inflate_into(&file, &mut buf[..n]).unwrap();
//! assert!(BundleView::parse(plain).is_ok());
//! ```

use alloc::borrow::Cow;
use alloc::vec::Vec;

use crate::bytes::{u16_at, u32_at, u64_at};
use crate::container::{FORMAT_MAJOR, MAGIC, MAX_FILE_LEN};
use crate::error::FormatError;
use crate::{BundleView, Tag, TileEntry};

/// The eight bytes a stored bundle starts with: the plain magic with `Z`
/// for `L`, so that a reader of the plain form refuses it as another file.
pub const STORED_MAGIC: [u8; 8] = *b"\x89TXZ\r\n\x1a\n";
/// The stored form's minor version: the stored form is format 4.7.
pub const STORED_MINOR: u16 = 7;
/// Length of the stored form's header; the DEFLATE stream follows it.
pub const STORED_HEADER_LEN: usize = 32;
/// The DEFLATE level the writer uses for a plain bundle of up to
/// [`SMALL_LEN`] bytes: 6, zlib's default. Miniz's best, 10, made
/// `tala-map`'s file 22 bytes smaller (3,775 against 3,797) and the 64 MB
/// map's at the input limit 0.15 % smaller, and cost the latter 0.4 to
/// 1.5 s of its build (three runs each, alternated).
const LEVEL: u8 = 6;
/// The level for a larger plain bundle: 4. On generated maps of 190 to
/// 340 KB, level 6 took 2.8 to 3 times as long (11 to 22 ms, after the
/// layers, with one core working) for a file 0.3 to 0.7 % smaller
/// (docs/performance.md).
const LEVEL_LARGE: u8 = 4;
/// The plain length up to which [`LEVEL`] is used: 64 KiB, where level 6
/// costs well under a millisecond.
const SMALL_LEN: usize = 64 * 1024;

/// Whether `bytes` start with the stored form's magic.
pub fn is_stored(bytes: &[u8]) -> bool {
    bytes.starts_with(&STORED_MAGIC)
}

fn refused(reason: &'static str) -> FormatError {
    FormatError::Stored { reason }
}

/// The stored header's plain length and checksum, checked.
fn header(bytes: &[u8]) -> Result<(usize, u32), FormatError> {
    if !is_stored(bytes) {
        return Err(refused("the file does not start with the stored form's magic"));
    }
    if bytes.len() < STORED_HEADER_LEN {
        return Err(FormatError::Truncated {
            what: "stored header",
            offset: 0,
            needed: STORED_HEADER_LEN as u64,
            available: bytes.len() as u64,
        });
    }
    let (major, minor) = (u16_at(bytes, 8).unwrap_or(0), u16_at(bytes, 10).unwrap_or(0));
    if major != FORMAT_MAJOR || minor < STORED_MINOR {
        return Err(FormatError::UnsupportedVersion { major, minor });
    }
    for offset in [12, 28] {
        if u32_at(bytes, offset) != Some(0) {
            return Err(FormatError::NonZeroReserved { offset: offset as u64 });
        }
    }
    let len = u64_at(bytes, 16).unwrap_or(0);
    if len > MAX_FILE_LEN {
        return Err(FormatError::Limit { tag: Tag::HEADER, field: "plain length", value: len, limit: MAX_FILE_LEN });
    }
    let len = usize::try_from(len).map_err(|_| refused("the plain length does not fit this machine's memory"))?;
    Ok((len, u32_at(bytes, 24).unwrap_or(0)))
}

/// The length of the plain bundle a stored one holds, from its header: the
/// buffer [`inflate_into`] needs.
pub fn plain_len(bytes: &[u8]) -> Result<usize, FormatError> {
    header(bytes).map(|(len, _)| len)
}

/// Inflates the stored bundle `bytes` into `out`, which must be exactly
/// [`plain_len`] bytes, undoes the filters and checks the plain bundle's
/// checksum; returns the plain bundle (all of `out`), ready for
/// [`BundleView::parse`](crate::BundleView::parse). Allocates nothing (the
/// inflater's state, about 11 KB, is on the stack), so a player without an
/// allocator loads a stored bundle with it.
pub fn inflate_into<'o>(bytes: &[u8], out: &'o mut [u8]) -> Result<&'o [u8], FormatError> {
    let (len, crc) = header(bytes)?;
    if out.len() != len {
        return Err(refused("the buffer is not the plain length the header records"));
    }
    let stream = &bytes[STORED_HEADER_LEN..];
    let n = miniz_oxide::inflate::decompress_slice_iter_to_slice(out, core::iter::once(stream), false, true).map_err(
        |e| match e {
            miniz_oxide::inflate::TINFLStatus::HasMoreOutput => too_long(),
            _ => corrupt(),
        },
    )?;
    finish(out, n, len, crc)?;
    Ok(out)
}

fn too_long() -> FormatError {
    refused("the compressed data holds more than the plain length the header records")
}

fn corrupt() -> FormatError {
    refused("the compressed data is corrupt or cut short")
}

/// Checks the inflated length `n` against the header's `len`, undoes the
/// filters and checks the plain bundle against the header's `crc`.
fn finish(out: &mut [u8], n: usize, len: usize, crc: u32) -> Result<(), FormatError> {
    if n != len {
        return Err(refused("the compressed data holds less than the plain length the header records"));
    }
    unfilter(out);
    if crc32fast::hash(out) != crc {
        return Err(refused("the plain bundle does not match its checksum: the file is corrupt"));
    }
    Ok(())
}

/// The plain bundle of `bytes`: `bytes` themselves when they are a plain
/// bundle (or not a bundle at all: [`BundleView::parse`](crate::BundleView::parse)
/// then says what they are), else the stored bundle inflated into a new
/// vector, which grows with what the data holds (not with what the header
/// claims) up to the plain length.
pub fn plain(bytes: &[u8]) -> Result<Cow<'_, [u8]>, FormatError> {
    if !is_stored(bytes) {
        return Ok(Cow::Borrowed(bytes));
    }
    let (len, crc) = header(bytes)?;
    let stream = &bytes[STORED_HEADER_LEN..];
    let mut out = miniz_oxide::inflate::decompress_to_vec_with_limit(stream, len).map_err(|e| match e.status {
        miniz_oxide::inflate::TINFLStatus::HasMoreOutput => too_long(),
        _ => corrupt(),
    })?;
    let n = out.len();
    finish(&mut out, n, len, crc)?;
    Ok(Cow::Owned(out))
}

/// The stored form of the plain bundle `plain`, which must be valid (it is
/// parsed first). Deterministic: the same bundle always gives the same
/// bytes. The result is read back before it is returned.
pub fn store(plain: &[u8]) -> Result<Vec<u8>, FormatError> {
    BundleView::parse(plain)?;
    let mut filtered = plain.to_vec();
    filter(&mut filtered);
    let level = if plain.len() <= SMALL_LEN { LEVEL } else { LEVEL_LARGE };
    let stream = miniz_oxide::deflate::compress_to_vec(&filtered, level);
    let mut out = Vec::with_capacity(STORED_HEADER_LEN + stream.len());
    out.extend_from_slice(&STORED_MAGIC);
    out.extend_from_slice(&FORMAT_MAJOR.to_le_bytes());
    out.extend_from_slice(&STORED_MINOR.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    out.extend_from_slice(&(plain.len() as u64).to_le_bytes());
    out.extend_from_slice(&crc32fast::hash(plain).to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    out.extend_from_slice(&stream);
    if plain_of(&out).as_deref() != Some(plain) {
        return Err(refused("the compressed form does not read back as the bundle (a writer defect)"));
    }
    Ok(out)
}

fn plain_of(stored: &[u8]) -> Option<Vec<u8>> {
    plain(stored).ok().map(Cow::into_owned)
}

/// Where chunk `i` of a plain bundle lies, by tag: `(tag, start, end)`,
/// `None` for an entry that does not fit (the parser refuses it later).
fn chunk_at(b: &[u8], i: usize) -> Option<(Tag, usize, usize)> {
    let at = 32usize.checked_add(i.checked_mul(32)?)?;
    let tag = Tag(b.get(at..at.checked_add(4)?)?.try_into().ok()?);
    let start = usize::try_from(u64_at(b, at.checked_add(8)?)?).ok()?;
    let end = start.checked_add(usize::try_from(u64_at(b, at.checked_add(16)?)?).ok()?)?;
    Some((tag, start, end.min(b.len())))
}

/// Every chunk of a plain bundle, as [`chunk_at`] finds them, up to the
/// first entry that does not fit.
#[cfg(test)]
fn chunks(b: &[u8]) -> impl Iterator<Item = (Tag, usize, usize)> + '_ {
    let count = u32_at(b, 12).unwrap_or(0) as usize;
    (0..count).map_while(move |i| chunk_at(b, i))
}

/// One length-preserving filter over a plain bundle's chunks, forwards
/// (the writer's) or backwards (the reader's), in place and without
/// allocating (the reader's runs in [`inflate_into`]).
fn each_chunk(b: &mut [u8], forwards: bool) {
    let count = u32_at(b, 12).unwrap_or(0) as usize;
    for i in 0..count {
        let Some((tag, start, end)) = chunk_at(b, i) else { return };
        let Some(d) = b.get_mut(start..end) else { continue };
        if tag == Tag::VIBRATION_DISTANCE || tag == Tag::GRATING_DISTANCE {
            index_numbers(d, forwards);
        } else if tag == Tag::FOOTPRINTS {
            point_deltas(d, forwards);
        }
    }
}

fn filter(b: &mut [u8]) {
    each_chunk(b, true)
}

fn unfilter(b: &mut [u8]) {
    each_chunk(b, false)
}

/// A distance layer's tile index (SPEC.md 6.2): every stored, fine and
/// record-playing entry names the tile or record after the previous one's,
/// so the filter keeps each entry's kind and clears its number, and the
/// reader numbers them again by counting.
fn index_numbers(d: &mut [u8], forwards: bool) {
    let field = |o: usize| u32_at(d, o).map(|v| v as usize);
    let (Some(sources), Some(cols), Some(rows)) = (field(0), field(4), field(8)) else { return };
    let Some(index) = sources.checked_mul(4).and_then(|s| s.checked_add(48)) else { return };
    let Some(tiles) = cols.checked_mul(rows) else { return };
    let (mut record, mut stored) = (0u32, 0u32);
    for t in 0..tiles {
        let Some(at) = t.checked_mul(4).and_then(|o| o.checked_add(index)) else { return };
        let Some(e) = u32_at(d, at) else { return };
        let kind = TileEntry::of(e);
        let (records, tiles_stored) = (kind.records(), kind.stored());
        let renumbered = match e >> 28 {
            // Plane, bend, corner, notch, ridge, arc, segments: the nibble is the kind.
            0x8..=0xF => (e & 0xF000_0000) | if forwards { 0 } else { record & 0x0FFF_FFFF },
            0x6 => (e & !crate::TILE_FINE_FIRST_MASK) | if forwards { 0 } else { stored & crate::TILE_FINE_FIRST_MASK },
            0x7 => e,
            _ if e < crate::TILE_FIRST_STORED => e,
            _ => crate::TILE_FIRST_STORED.wrapping_add(if forwards { 0 } else { stored }),
        };
        // An entry's kind, and so what it counts, is the same with its number and without.
        record = record.wrapping_add(records);
        stored = stored.wrapping_add(tiles_stored);
        if let Some(slot) = d.get_mut(at..at + 4) {
            slot.copy_from_slice(&renumbered.to_le_bytes());
        }
    }
}

/// A footprint table's points (SPEC.md 10.1), each as its difference from
/// the point before (the first from (0, 0)), modulo 2^16.
fn point_deltas(d: &mut [u8], forwards: bool) {
    let field = |o: usize| u32_at(d, o).map(|v| v as usize);
    let (Some(shapes), Some(rings), Some(points)) = (field(0), field(4), field(8)) else { return };
    let start = shapes.checked_mul(12).zip(rings.checked_mul(4)).and_then(|(s, r)| s.checked_add(r)?.checked_add(24));
    let Some(start) = start else { return };
    let Some(end) = points.checked_mul(4).and_then(|p| p.checked_add(start)) else { return };
    let Some(pts) = d.get_mut(start..end) else { return };
    let (mut px, mut py) = (0u16, 0u16);
    for p in pts.chunks_exact_mut(4) {
        let (x, y) = (u16::from_le_bytes([p[0], p[1]]), u16::from_le_bytes([p[2], p[3]]));
        let (nx, ny) =
            if forwards { (x.wrapping_sub(px), y.wrapping_sub(py)) } else { (x.wrapping_add(px), y.wrapping_add(py)) };
        (px, py) = if forwards { (x, y) } else { (nx, ny) };
        p[..2].copy_from_slice(&nx.to_le_bytes());
        p[2..].copy_from_slice(&ny.to_le_bytes());
    }
}

// The plain magic and the stored one differ in one byte only.
const _: () = assert!(MAGIC[3] == b'L' && STORED_MAGIC[3] == b'Z');

#[cfg(test)]
mod tests;
