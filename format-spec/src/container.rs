//! The container: header, chunk table, canonical placement and checksums.
//! Nothing here knows what a chunk means.

use alloc::vec::Vec;

use crate::Tag;
use crate::bytes::{Out, array_at, u16_at, u32_at, u64_at};
use crate::error::FormatError;

/// The eight bytes every bundle starts with. Like PNG's signature, the high
/// byte catches 7-bit transfers and the CR-LF / Ctrl-Z / LF tail catches
/// line-ending conversion.
pub const MAGIC: [u8; 8] = *b"\x89TXL\r\n\x1a\n";
/// The major version this crate reads and writes.
pub const FORMAT_MAJOR: u16 = 4;
/// The newest minor version of the plain form this crate knows; a bundle
/// records the lowest minor that has all its chunks
/// ([`Bundle::to_bytes`](crate::Bundle::to_bytes)). The stored form is 4.7
/// ([`STORED_MINOR`](crate::stored::STORED_MINOR)) and holds a plain bundle.
pub const FORMAT_MINOR: u16 = 6;
/// Length of the fixed header.
pub const HEADER_LEN: usize = 32;
/// Length of one chunk table entry.
pub const TABLE_ENTRY_LEN: usize = 32;
/// Every chunk's data starts at a multiple of this.
pub const CHUNK_ALIGN: u64 = 8;
/// Largest number of chunks in one bundle.
pub const MAX_CHUNKS: u32 = 65_536;
/// Largest bundle, in bytes (1 GiB).
pub const MAX_FILE_LEN: u64 = 1 << 30;

/// Flag bit: a reader that does not know the tag must refuse the bundle.
pub(crate) const FLAG_REQUIRED: u16 = 1;

/// One validated table entry.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Entry {
    pub tag: Tag,
    pub required: bool,
    pub offset: usize,
    pub length: usize,
}

pub(crate) fn align_up(v: u64) -> u64 {
    v.div_ceil(CHUNK_ALIGN) * CHUNK_ALIGN
}

fn truncated(what: &'static str, offset: usize, needed: usize, total: usize) -> FormatError {
    FormatError::Truncated {
        what,
        offset: offset as u64,
        needed: needed as u64,
        available: total.saturating_sub(offset) as u64,
    }
}

/// Validates the header, the table and the placement and checksum of every
/// chunk. Returns the version and the entries' count; entries are read again
/// on demand with [`entry`], which cannot fail after this succeeded.
pub(crate) fn validate(bytes: &[u8]) -> Result<(u16, u16, u32), FormatError> {
    let total = bytes.len();
    // Magic first, so that a wrong file type is named as such even when short.
    let magic_len = total.min(8);
    if crate::stored::is_stored(bytes) {
        return Err(FormatError::Stored {
            reason: "inflate it first (taxel_format::stored::plain or inflate_into), then read the plain bundle",
        });
    }
    if bytes[..magic_len] != MAGIC[..magic_len] {
        let mut found = [0u8; 8];
        found[..magic_len].copy_from_slice(&bytes[..magic_len]);
        return Err(FormatError::BadMagic { found });
    }
    if total < HEADER_LEN {
        return Err(truncated("header", 0, HEADER_LEN, total));
    }
    let major = u16_at(bytes, 8).unwrap_or(0);
    let minor = u16_at(bytes, 10).unwrap_or(0);
    if major != FORMAT_MAJOR {
        return Err(FormatError::UnsupportedVersion { major, minor });
    }
    let count = u32_at(bytes, 12).unwrap_or(0);
    let file_len = u64_at(bytes, 16).unwrap_or(0);
    let table_crc = u32_at(bytes, 24).unwrap_or(0);
    if u32_at(bytes, 28) != Some(0) {
        return Err(FormatError::NonZeroReserved { offset: 28 });
    }
    if file_len > MAX_FILE_LEN {
        return Err(FormatError::Limit {
            tag: Tag::HEADER,
            field: "file length",
            value: file_len,
            limit: MAX_FILE_LEN,
        });
    }
    if file_len != total as u64 {
        return Err(FormatError::FileLength { header: file_len, actual: total as u64 });
    }
    if count == 0 {
        // The manifest is itself a chunk, so an empty table has no manifest.
        return Err(FormatError::MissingManifest);
    }
    if count > MAX_CHUNKS {
        return Err(FormatError::Limit {
            tag: Tag::HEADER,
            field: "chunk count",
            value: count as u64,
            limit: MAX_CHUNKS as u64,
        });
    }
    let table_len = count as usize * TABLE_ENTRY_LEN;
    if total < HEADER_LEN + table_len {
        return Err(truncated("chunk table", HEADER_LEN, table_len, total));
    }
    let mut hasher = crc32fast::Hasher::new();
    hasher.update(&bytes[..24]);
    hasher.update(&bytes[HEADER_LEN..HEADER_LEN + table_len]);
    let found = hasher.finalize();
    if found != table_crc {
        return Err(FormatError::TableChecksum { expected: table_crc, found });
    }

    let mut expected_offset = align_up((HEADER_LEN + table_len) as u64);
    let mut prev_end = (HEADER_LEN + table_len) as u64;
    for index in 0..count {
        let e = HEADER_LEN + index as usize * TABLE_ENTRY_LEN;
        let tag = Tag(array_at::<4>(bytes, e).unwrap_or([0; 4]));
        let flags = u16_at(bytes, e + 4).unwrap_or(0);
        let offset = u64_at(bytes, e + 8).unwrap_or(0);
        let length = u64_at(bytes, e + 16).unwrap_or(0);
        let crc = u32_at(bytes, e + 24).unwrap_or(0);
        if flags & !FLAG_REQUIRED != 0 || u16_at(bytes, e + 6) != Some(0) {
            return Err(FormatError::NonZeroReserved { offset: (e + 4) as u64 });
        }
        if u32_at(bytes, e + 28) != Some(0) {
            return Err(FormatError::NonZeroReserved { offset: (e + 28) as u64 });
        }
        if offset != expected_offset {
            return Err(FormatError::ChunkPlacement { index, tag, expected: expected_offset, found: offset });
        }
        check_zero(bytes, prev_end, offset)?;
        let end = offset.checked_add(length).filter(|&end| end <= total as u64).ok_or(FormatError::Truncated {
            what: "chunk data",
            offset,
            needed: length,
            available: (total as u64).saturating_sub(offset),
        })?;
        let data = &bytes[offset as usize..end as usize];
        let found = crc32fast::hash(data);
        if found != crc {
            return Err(FormatError::ChunkChecksum { index, tag, expected: crc, found });
        }
        prev_end = end;
        expected_offset = align_up(end);
    }
    if expected_offset != total as u64 {
        // Bytes after the last chunk's padding, or padding missing at the end.
        return Err(FormatError::CanonicalLength { expected: expected_offset, found: total as u64 });
    }
    check_zero(bytes, prev_end, total as u64)?;
    Ok((major, minor, count))
}

fn check_zero(bytes: &[u8], from: u64, to: u64) -> Result<(), FormatError> {
    for o in from..to {
        if bytes.get(o as usize).copied().unwrap_or(0) != 0 {
            return Err(FormatError::NonZeroReserved { offset: o });
        }
    }
    Ok(())
}

/// Reads table entry `index` of a bundle that [`validate`] accepted.
pub(crate) fn entry(bytes: &[u8], index: u32) -> Option<Entry> {
    let e = HEADER_LEN + index as usize * TABLE_ENTRY_LEN;
    let tag = Tag(array_at::<4>(bytes, e)?);
    let flags = u16_at(bytes, e + 4)?;
    let offset = usize::try_from(u64_at(bytes, e + 8)?).ok()?;
    let length = usize::try_from(u64_at(bytes, e + 16)?).ok()?;
    bytes.get(offset..offset.checked_add(length)?)?;
    Some(Entry { tag, required: flags & FLAG_REQUIRED != 0, offset, length })
}

/// A chunk ready to be placed: tag, flag and encoded data.
pub(crate) struct Encoded {
    pub tag: Tag,
    pub required: bool,
    pub data: Vec<u8>,
}

/// Lays chunks out canonically and computes every checksum.
pub(crate) fn assemble(chunks: &[Encoded], minor: u16) -> Result<Vec<u8>, FormatError> {
    let count = chunks.len();
    if count == 0 || count > MAX_CHUNKS as usize {
        return Err(FormatError::Limit {
            tag: Tag::HEADER,
            field: "chunk count",
            value: count as u64,
            limit: MAX_CHUNKS as u64,
        });
    }
    let table_end = (HEADER_LEN + count * TABLE_ENTRY_LEN) as u64;
    let mut offsets = Vec::with_capacity(count);
    let mut cursor = align_up(table_end);
    for c in chunks {
        offsets.push(cursor);
        cursor = align_up(cursor + c.data.len() as u64);
    }
    let file_len = cursor;
    if file_len > MAX_FILE_LEN {
        return Err(FormatError::Limit {
            tag: Tag::HEADER,
            field: "file length",
            value: file_len,
            limit: MAX_FILE_LEN,
        });
    }
    let mut out = Vec::with_capacity(file_len as usize);
    let mut w = Out(&mut out);
    w.bytes(&MAGIC).u16(FORMAT_MAJOR).u16(minor).u32(count as u32).u64(file_len).u32(0).u32(0);
    for (c, &offset) in chunks.iter().zip(&offsets) {
        w.bytes(&c.tag.0)
            .u16(if c.required { FLAG_REQUIRED } else { 0 })
            .u16(0)
            .u64(offset)
            .u64(c.data.len() as u64)
            .u32(crc32fast::hash(&c.data))
            .u32(0);
    }
    for (c, &offset) in chunks.iter().zip(&offsets) {
        out.resize(offset as usize, 0);
        out.extend_from_slice(&c.data);
    }
    out.resize(file_len as usize, 0);
    let mut hasher = crc32fast::Hasher::new();
    hasher.update(&out[..24]);
    hasher.update(&out[HEADER_LEN..table_end as usize]);
    let crc = hasher.finalize();
    out[24..28].copy_from_slice(&crc.to_le_bytes());
    Ok(out)
}
