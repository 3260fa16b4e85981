//! Provenance (`PROV`): what each layer was made from — SVG ids, titles or
//! labels, source lines — so diagnostics and speech can name what the finger is on.

use alloc::string::String;
use alloc::vec::Vec;

use crate::Tag;
use crate::bytes::{Out, u16_at, u32_at};
use crate::error::FormatError;

const HEADER_LEN: usize = 8;
const ENTRY_LEN: usize = 16;
/// Largest number of provenance entries.
pub const MAX_PROVENANCE_ENTRIES: u32 = 1 << 20;

/// One source element.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ProvenanceEntry {
    /// The element's id (SVG `id`, glTF node or mesh name), possibly empty.
    pub id: String,
    /// A human label (`<title>`, `inkscape:label`, `aria-label`), possibly empty.
    pub label: String,
    /// 1-based source line, 0 when unknown.
    pub line: u32,
}

/// The provenance table; layers refer to entries by index.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Provenance {
    /// The entries.
    pub entries: Vec<ProvenanceEntry>,
}

impl Provenance {
    pub(crate) fn encode(&self) -> Vec<u8> {
        let mut blob = Vec::new();
        let mut table = Vec::new();
        let mut w = Out(&mut table);
        for e in &self.entries {
            // Strings longer than the 16-bit length field are cut at a character boundary.
            let id = clip(&e.id);
            let label = clip(&e.label);
            w.u32(blob.len() as u32).u16(id.len() as u16).u16(label.len() as u16).u32(e.line).u32(0);
            blob.extend_from_slice(id.as_bytes());
            blob.extend_from_slice(label.as_bytes());
        }
        let mut out = Vec::with_capacity(HEADER_LEN + table.len() + blob.len());
        Out(&mut out).u32(self.entries.len() as u32).u32(blob.len() as u32).bytes(&table).bytes(&blob);
        out
    }

    pub(crate) fn from_view(v: &ProvenanceView<'_>) -> Self {
        Provenance {
            entries: (0..v.len())
                .filter_map(|i| {
                    let (id, label, line) = v.get(i)?;
                    Some(ProvenanceEntry { id: id.into(), label: label.into(), line })
                })
                .collect(),
        }
    }
}

fn clip(s: &str) -> &str {
    let mut end = s.len().min(u16::MAX as usize);
    while !s.is_char_boundary(end) {
        end -= 1;
    }
    &s[..end]
}

/// A validated provenance table, read in place.
#[derive(Debug, Clone, Copy)]
pub struct ProvenanceView<'a> {
    table: &'a [u8],
    blob: &'a [u8],
    count: u32,
}

impl<'a> ProvenanceView<'a> {
    /// Number of entries.
    pub fn len(&self) -> u32 {
        self.count
    }

    /// Whether there are no entries.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Entry `i` as `(id, label, line)`.
    pub fn get(&self, i: u32) -> Option<(&'a str, &'a str, u32)> {
        if i >= self.count {
            return None;
        }
        let o = i as usize * ENTRY_LEN;
        let start = u32_at(self.table, o)? as usize;
        let id_len = u16_at(self.table, o + 4)? as usize;
        let label_len = u16_at(self.table, o + 6)? as usize;
        let line = u32_at(self.table, o + 8)?;
        let id = core::str::from_utf8(self.blob.get(start..start + id_len)?).ok()?;
        let label = core::str::from_utf8(self.blob.get(start + id_len..start + id_len + label_len)?).ok()?;
        Some((id, label, line))
    }

    /// Reads the table; with `full`, also checks every entry's strings.
    pub(crate) fn parse(d: &'a [u8], index: u32, full: bool) -> Result<Self, FormatError> {
        let tag = Tag::PROVENANCE;
        let bad = |field, expected| FormatError::InvalidValue { tag, index, field, expected };
        let count = u32_at(d, 0).ok_or(FormatError::ChunkLength {
            tag,
            index,
            expected: HEADER_LEN as u64,
            found: d.len() as u64,
        })?;
        let blob_len = u32_at(d, 4).unwrap_or(0) as u64;
        if count > MAX_PROVENANCE_ENTRIES {
            return Err(FormatError::Limit {
                tag,
                field: "entries",
                value: count as u64,
                limit: MAX_PROVENANCE_ENTRIES as u64,
            });
        }
        let expected = HEADER_LEN as u64 + ENTRY_LEN as u64 * count as u64 + blob_len;
        if d.len() as u64 != expected {
            return Err(FormatError::ChunkLength { tag, index, expected, found: d.len() as u64 });
        }
        let split = HEADER_LEN + ENTRY_LEN * count as usize;
        let view = ProvenanceView { table: &d[HEADER_LEN..split], blob: &d[split..], count };
        if !full {
            return Ok(view);
        }
        // Entries are laid out back to back in the blob, in order.
        let mut next = 0usize;
        for i in 0..count {
            let o = i as usize * ENTRY_LEN;
            if u32_at(view.table, o) != Some(next as u32) || u32_at(view.table, o + 12) != Some(0) {
                return Err(bad("string offsets", "strings back to back in entry order, reserved zero"));
            }
            view.get(i).ok_or(bad("strings", "UTF-8 within the blob"))?;
            next += u16_at(view.table, o + 4).unwrap_or(0) as usize + u16_at(view.table, o + 6).unwrap_or(0) as usize;
        }
        if next != view.blob.len() {
            return Err(bad("blob", "exactly the entries' strings"));
        }
        Ok(view)
    }
}
