//! The one error type of the format crate: every variant carries what a person
//! needs to find the problem (offset, chunk tag and index, expected and found).

use core::fmt;

use crate::Tag;

/// Why a bundle (or a value about to be written into one) was refused.
#[derive(Debug, Clone, PartialEq)]
pub enum FormatError {
    /// The file ends before a structure that must be there.
    Truncated {
        /// What was being read.
        what: &'static str,
        /// Byte offset where the structure starts.
        offset: u64,
        /// Bytes needed from that offset.
        needed: u64,
        /// Bytes available from that offset.
        available: u64,
    },
    /// The first eight bytes are not the taxel magic.
    BadMagic {
        /// The bytes found.
        found: [u8; 8],
    },
    /// A major version this reader does not understand.
    UnsupportedVersion {
        /// Major version in the file.
        major: u16,
        /// Minor version in the file.
        minor: u16,
    },
    /// The header's file length disagrees with the bytes given.
    FileLength {
        /// Length the header records.
        header: u64,
        /// Length of the bytes given.
        actual: u64,
    },
    /// The file does not end where the canonical layout ends (right after the
    /// last chunk and its zero padding to a multiple of 8 bytes).
    CanonicalLength {
        /// Length the canonical layout gives.
        expected: u64,
        /// Length of the file.
        found: u64,
    },
    /// The header or chunk table checksum does not match.
    TableChecksum {
        /// Checksum recorded in the header.
        expected: u32,
        /// Checksum computed over header and table.
        found: u32,
    },
    /// A chunk's data does not match its checksum.
    ChunkChecksum {
        /// Position of the chunk in the table.
        index: u32,
        /// The chunk's tag.
        tag: Tag,
        /// Checksum recorded in the table.
        expected: u32,
        /// Checksum of the data.
        found: u32,
    },
    /// A chunk is not where the canonical layout puts it (8-byte aligned,
    /// in table order, with nothing between chunks but zero padding).
    ChunkPlacement {
        /// Position of the chunk in the table.
        index: u32,
        /// The chunk's tag.
        tag: Tag,
        /// Offset the canonical layout requires.
        expected: u64,
        /// Offset recorded in the table.
        found: u64,
    },
    /// Padding or a reserved field is not zero.
    NonZeroReserved {
        /// Byte offset of the offending byte.
        offset: u64,
    },
    /// A chunk this reader does not know and that is marked required.
    UnknownRequiredChunk {
        /// Position of the chunk in the table.
        index: u32,
        /// The chunk's tag.
        tag: Tag,
    },
    /// A known chunk appears where it may not (wrong position or repeated).
    ChunkOrder {
        /// Position of the chunk in the table.
        index: u32,
        /// The chunk's tag.
        tag: Tag,
        /// What the rule is.
        rule: &'static str,
    },
    /// A known chunk's required flag is not what the specification says.
    RequiredFlag {
        /// Position of the chunk in the table.
        index: u32,
        /// The chunk's tag.
        tag: Tag,
        /// The flag the specification requires.
        expected: bool,
    },
    /// The bundle has no manifest chunk.
    MissingManifest,
    /// A chunk's length does not match what its contents need.
    ChunkLength {
        /// The chunk's tag.
        tag: Tag,
        /// Position of the chunk in the table.
        index: u32,
        /// Length its header fields imply.
        expected: u64,
        /// Length recorded in the table.
        found: u64,
    },
    /// A count or size above the format's limit.
    Limit {
        /// The chunk's tag (the header's for file-level limits).
        tag: Tag,
        /// The field.
        field: &'static str,
        /// The value found.
        value: u64,
        /// The largest value allowed.
        limit: u64,
    },
    /// A field holds a value outside its domain (not finite, out of range, bad text).
    InvalidValue {
        /// The chunk's tag.
        tag: Tag,
        /// Position of the chunk in the table (or of the layer being written).
        index: u32,
        /// The field.
        field: &'static str,
        /// What the value must be.
        expected: &'static str,
    },
    /// A stored (compressed) bundle (SPEC.md section 15) that cannot be
    /// read, or one given where a plain bundle is needed.
    Stored {
        /// What is wrong.
        reason: &'static str,
    },
}

impl FormatError {
    /// Refuses chunk `index` (`tag`) when its data `d` is shorter than its
    /// fixed header of `len` bytes.
    pub(crate) fn check_header(d: &[u8], len: usize, tag: Tag, index: u32) -> Result<(), FormatError> {
        if d.len() < len {
            return Err(FormatError::ChunkLength { tag, index, expected: len as u64, found: d.len() as u64 });
        }
        Ok(())
    }
}

impl fmt::Display for FormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FormatError::Truncated { what, offset, needed, available } => write!(
                f,
                "truncated bundle: {what} at offset {offset} needs {needed} bytes but only {available} remain"
            ),
            FormatError::BadMagic { found } => {
                write!(f, "not a taxel bundle: the file starts with {found:02x?} instead of the taxel magic")
            }
            FormatError::UnsupportedVersion { major, minor } if *major < crate::FORMAT_MAJOR => write!(
                f,
                "bundle format version {major}.{minor} is older than this reader's {}.x (layers by style with exact edges); rebuild the bundle from its drawing with `taxel build`",
                crate::FORMAT_MAJOR
            ),
            FormatError::UnsupportedVersion { major, minor } => write!(
                f,
                "bundle format version {major}.{minor} is not supported: this reader reads major version {}; use a newer taxel",
                crate::FORMAT_MAJOR
            ),
            FormatError::FileLength { header, actual } => {
                write!(f, "bundle length mismatch: the header records {header} bytes but the file has {actual}")
            }
            FormatError::CanonicalLength { expected, found } => {
                write!(f, "bundle is {found} bytes long, but its last chunk and padding end at {expected}")
            }
            FormatError::TableChecksum { expected, found } => write!(
                f,
                "header or chunk table is corrupt: checksum {found:08x} does not match the recorded {expected:08x}"
            ),
            FormatError::ChunkChecksum { index, tag, expected, found } => write!(
                f,
                "chunk {index} ({tag}) is corrupt: checksum {found:08x} does not match the recorded {expected:08x}"
            ),
            FormatError::ChunkPlacement { index, tag, expected, found } => write!(
                f,
                "chunk {index} ({tag}) starts at offset {found}, but the canonical layout puts it at {expected}"
            ),
            FormatError::NonZeroReserved { offset } => {
                write!(f, "reserved or padding byte at offset {offset} is not zero")
            }
            FormatError::UnknownRequiredChunk { index, tag } => write!(
                f,
                "chunk {index} ({tag}) is required but unknown to this reader: the bundle needs a newer taxel"
            ),
            FormatError::ChunkOrder { index, tag, rule } => {
                write!(f, "chunk {index} ({tag}) is out of place: {rule}")
            }
            FormatError::RequiredFlag { index, tag, expected } => {
                write!(f, "chunk {index} ({tag}) must be marked {}", if *expected { "required" } else { "optional" })
            }
            FormatError::MissingManifest => write!(f, "bundle has no manifest chunk (MANI)"),
            FormatError::ChunkLength { tag, index, expected, found } => {
                write!(f, "chunk {index} ({tag}) is {found} bytes long but its contents need {expected}")
            }
            FormatError::Limit { tag, field, value, limit } if *tag == Tag::HEADER => {
                write!(f, "{field} in the header is {value}, above the limit of {limit}")
            }
            FormatError::Limit { tag, field, value, limit } => {
                write!(f, "{field} in the {tag} chunk is {value}, above the limit of {limit}")
            }
            FormatError::InvalidValue { tag, index, field, expected } => {
                write!(f, "chunk {index} ({tag}): {field} must be {expected}")
            }
            FormatError::Stored { reason } => write!(f, "compressed bundle: {reason}"),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for FormatError {}
