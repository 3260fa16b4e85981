//! An encoder and decoder of the container written from `SPEC.md` alone, to
//! craft files byte by byte: the tests edit a chunk or a header field and
//! then re-seal the checksums so that the reader's deeper checks are reached.

/// One chunk as the table sees it: tag, flags word and data.
#[derive(Debug, Clone, PartialEq)]
pub struct Raw {
    pub tag: [u8; 4],
    pub flags: u16,
    pub data: Vec<u8>,
}

pub fn raw(tag: &[u8; 4], required: bool, data: Vec<u8>) -> Raw {
    Raw { tag: *tag, flags: required as u16, data }
}

const MAGIC: &[u8; 8] = b"\x89TXL\r\n\x1a\n";

fn align8(v: usize) -> usize {
    v.div_ceil(8) * 8
}

/// Lays chunks out as SPEC.md says: 32-byte header, 32-byte entries, each
/// chunk at the next multiple of 8, zero padding, file ending on a multiple of 8.
pub fn craft(chunks: &[Raw]) -> Vec<u8> {
    craft_version(chunks, taxel_format::FORMAT_MAJOR, 0)
}

pub fn craft_version(chunks: &[Raw], major: u16, minor: u16) -> Vec<u8> {
    let table_end = 32 + 32 * chunks.len();
    let mut offsets = Vec::new();
    let mut cursor = align8(table_end);
    for c in chunks {
        offsets.push(cursor);
        cursor = align8(cursor + c.data.len());
    }
    let mut out = vec![0u8; cursor];
    out[..8].copy_from_slice(MAGIC);
    out[8..10].copy_from_slice(&major.to_le_bytes());
    out[10..12].copy_from_slice(&minor.to_le_bytes());
    out[12..16].copy_from_slice(&(chunks.len() as u32).to_le_bytes());
    out[16..24].copy_from_slice(&(cursor as u64).to_le_bytes());
    for (i, (c, &o)) in chunks.iter().zip(&offsets).enumerate() {
        let e = 32 + 32 * i;
        out[e..e + 4].copy_from_slice(&c.tag);
        out[e + 4..e + 6].copy_from_slice(&c.flags.to_le_bytes());
        out[e + 8..e + 16].copy_from_slice(&(o as u64).to_le_bytes());
        out[e + 16..e + 24].copy_from_slice(&(c.data.len() as u64).to_le_bytes());
        out[o..o + c.data.len()].copy_from_slice(&c.data);
    }
    reseal(&mut out);
    out
}

/// Recomputes every chunk checksum whose range is inside the file, then the
/// header and table checksum (CRC-32/IEEE of bytes 0..24 and the table).
pub fn reseal(b: &mut [u8]) {
    if b.len() < 32 {
        return;
    }
    let count = u32::from_le_bytes(b[12..16].try_into().unwrap()) as usize;
    let table_end = (32 + 32 * count).min(b.len() / 32 * 32);
    for e in (32..table_end).step_by(32) {
        let off = u64::from_le_bytes(b[e + 8..e + 16].try_into().unwrap()) as usize;
        let len = u64::from_le_bytes(b[e + 16..e + 24].try_into().unwrap()) as usize;
        if let Some(data) = off.checked_add(len).and_then(|end| b.get(off..end)) {
            let crc = crc32fast::hash(data);
            b[e + 24..e + 28].copy_from_slice(&crc.to_le_bytes());
        }
    }
    let mut h = crc32fast::Hasher::new();
    h.update(&b[..24]);
    h.update(&b[32..table_end]);
    let crc = h.finalize();
    b[24..28].copy_from_slice(&crc.to_le_bytes());
}

/// The chunks of a well-formed file, read from its table.
pub fn decompose(b: &[u8]) -> Vec<Raw> {
    let count = u32::from_le_bytes(b[12..16].try_into().unwrap()) as usize;
    (0..count)
        .map(|i| {
            let e = 32 + 32 * i;
            let off = u64::from_le_bytes(b[e + 8..e + 16].try_into().unwrap()) as usize;
            let len = u64::from_le_bytes(b[e + 16..e + 24].try_into().unwrap()) as usize;
            Raw {
                tag: b[e..e + 4].try_into().unwrap(),
                flags: u16::from_le_bytes(b[e + 4..e + 6].try_into().unwrap()),
                data: b[off..off + len].to_vec(),
            }
        })
        .collect()
}

/// `(offset, length)` of chunk `i` from the table.
pub fn span(b: &[u8], i: usize) -> (usize, usize) {
    let e = 32 + 32 * i;
    let off = u64::from_le_bytes(b[e + 8..e + 16].try_into().unwrap()) as usize;
    let len = u64::from_le_bytes(b[e + 16..e + 24].try_into().unwrap()) as usize;
    (off, len)
}

/// Index of the first chunk with `tag` in a decomposed file.
pub fn find(chunks: &[Raw], tag: &[u8; 4]) -> usize {
    chunks.iter().position(|c| &c.tag == tag).unwrap()
}

/// The sample with every chunk kind, encoded by the crate.
pub fn every_kind_bytes() -> Vec<u8> {
    taxel_format::sample::every_kind().to_bytes().unwrap()
}

/// Re-crafts the every-kind sample after `edit` changed the data of the first chunk with `tag`.
pub fn edit_chunk(tag: &[u8; 4], edit: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
    let mut chunks = decompose(&every_kind_bytes());
    let i = find(&chunks, tag);
    edit(&mut chunks[i].data);
    craft(&chunks)
}

pub fn put_u32(d: &mut [u8], o: usize, v: u32) {
    d[o..o + 4].copy_from_slice(&v.to_le_bytes());
}

pub fn put_f32(d: &mut [u8], o: usize, v: f32) {
    put_u32(d, o, v.to_bits());
}

pub fn put_u16(d: &mut [u8], o: usize, v: u16) {
    d[o..o + 2].copy_from_slice(&v.to_le_bytes());
}
