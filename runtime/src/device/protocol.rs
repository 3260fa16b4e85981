//! The loader protocol's frames and messages (see `docs/protocol.md`).
//!
//! Every message is one frame: a kind byte, a little-endian `u32` payload
//! length, then the payload. Integers are little-endian; strings are a `u16`
//! byte length followed by UTF-8. A reader never allocates more than
//! [`MAX_FRAME`] bytes for one frame, whatever the length field claims.

use std::io::{self, Read, Write};
use std::string::{String, ToString};
use std::vec::Vec;
use std::{fmt, format};

/// Version of the protocol this crate speaks.
pub const PROTOCOL_VERSION: u16 = 1;
/// Magic bytes at the start of a `HELLO` payload.
pub const HELLO_MAGIC: [u8; 4] = *b"TXLD";
/// Largest payload of one frame; larger length fields are refused before any allocation.
pub const MAX_FRAME: u32 = 1 << 20;
/// Bytes of bundle data a client puts in one `DATA` frame.
pub const DATA_CHUNK: usize = 64 * 1024;
/// Longest bundle name a device accepts, in bytes.
pub const MAX_NAME_LEN: usize = 64;
/// Length of a checksum: BLAKE3 of the whole bundle file.
pub const CHECKSUM_LEN: usize = 32;

/// A BLAKE3 checksum of a whole bundle file.
pub type Checksum = [u8; CHECKSUM_LEN];

/// The BLAKE3 checksum the protocol uses for `bytes`.
pub fn checksum(bytes: &[u8]) -> Checksum {
    *blake3::hash(bytes).as_bytes()
}

/// Frame kinds. Requests have the high bit clear, replies have it set.
mod kind {
    pub const HELLO: u8 = 0x01;
    pub const OFFER: u8 = 0x02;
    pub const DATA: u8 = 0x03;
    pub const COMMIT: u8 = 0x04;
    pub const LIST: u8 = 0x05;
    pub const DELETE: u8 = 0x06;
    pub const BYE: u8 = 0x07;
    pub const WELCOME: u8 = 0x81;
    pub const READY: u8 = 0x82;
    pub const VERIFIED: u8 = 0x83;
    pub const LISTING: u8 = 0x84;
    pub const DELETED: u8 = 0x85;
    pub const ERROR: u8 = 0xEE;
}

/// Why a device refused a request. The numbers are part of the protocol.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ErrorCode {
    /// A frame that is malformed or not allowed at this point of the session.
    Protocol = 1,
    /// The client speaks a protocol version the device does not.
    Version = 2,
    /// The bundle was compiled for another device profile.
    WrongProfile = 3,
    /// The bundle does not fit in the device's free space.
    NoSpace = 4,
    /// The received bytes do not match the offered checksum.
    ChecksumMismatch = 5,
    /// The received file is not a valid bundle.
    InvalidBundle = 6,
    /// The device is busy (the same name is being loaded, or too many clients); retry later.
    Busy = 7,
    /// The name is not a plain file name.
    InvalidName = 8,
    /// No bundle of that name is stored.
    NotFound = 9,
    /// More or fewer bytes arrived than were offered.
    SizeMismatch = 10,
    /// The device's storage failed.
    Storage = 11,
    /// The client was silent for longer than the device waits.
    Timeout = 12,
}

impl ErrorCode {
    /// The code for a number, `None` for a number this version does not know.
    pub fn from_u16(n: u16) -> Option<Self> {
        use ErrorCode::*;
        Some(match n {
            1 => Protocol,
            2 => Version,
            3 => WrongProfile,
            4 => NoSpace,
            5 => ChecksumMismatch,
            6 => InvalidBundle,
            7 => Busy,
            8 => InvalidName,
            9 => NotFound,
            10 => SizeMismatch,
            11 => Storage,
            12 => Timeout,
            _ => return None,
        })
    }

    /// A short lower-case name, as `docs/protocol.md` lists it.
    pub fn name(self) -> &'static str {
        use ErrorCode::*;
        match self {
            Protocol => "protocol error",
            Version => "unsupported protocol version",
            WrongProfile => "wrong profile",
            NoSpace => "no space",
            ChecksumMismatch => "checksum mismatch",
            InvalidBundle => "invalid bundle",
            Busy => "busy, retry later",
            InvalidName => "invalid name",
            NotFound => "not found",
            SizeMismatch => "size mismatch",
            Storage => "storage failure",
            Timeout => "timeout",
        }
    }
}

impl fmt::Display for ErrorCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What a device says about itself in `WELCOME`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DeviceInfo {
    /// Protocol version the device speaks.
    pub version: u16,
    /// The profile the device accepts; empty when it accepts any.
    pub profile: String,
    /// Storage capacity in bytes (`u64::MAX` when unlimited).
    pub capacity: u64,
    /// Free bytes now.
    pub free: u64,
}

/// An offer to store one bundle.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Offer {
    /// Name on the device (a plain file name).
    pub name: String,
    /// Profile the bundle says it was compiled for (checked again on commit).
    pub profile: String,
    /// Size of the whole file in bytes.
    pub size: u64,
    /// BLAKE3 of the whole file.
    pub checksum: Checksum,
}

/// One stored bundle.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Entry {
    /// Its name.
    pub name: String,
    /// Its size in bytes.
    pub size: u64,
    /// BLAKE3 of the file as stored.
    pub checksum: Checksum,
}

/// A message from a client to a device.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Request {
    /// Opens a session.
    Hello {
        /// The client's protocol version.
        version: u16,
    },
    /// Offers a bundle; the device answers `READY` or `ERROR`.
    Offer(Offer),
    /// The next bytes of the offered bundle (no reply).
    Data(Vec<u8>),
    /// All bytes are sent; the device verifies and answers `VERIFIED` or `ERROR`.
    Commit,
    /// Asks for the stored bundles.
    List,
    /// Deletes a stored bundle.
    Delete {
        /// Its name.
        name: String,
    },
    /// Ends the session.
    Bye,
}

/// A message from a device to a client.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Reply {
    /// The answer to `HELLO`.
    Welcome(DeviceInfo),
    /// The offer is accepted and space is reserved; send the data.
    Ready,
    /// The bundle is stored, verified and in place.
    Verified(Entry),
    /// The stored bundles, sorted by name.
    Listing(Vec<Entry>),
    /// The bundle is deleted.
    Deleted,
    /// A refusal.
    Error {
        /// Why.
        code: ErrorCode,
        /// Details for people.
        message: String,
    },
}

/// Why a frame could not be read or decoded.
#[derive(Debug)]
pub enum ProtocolError {
    /// The peer closed the connection cleanly between frames.
    Closed,
    /// The connection ended inside a frame.
    Truncated,
    /// The peer was silent for longer than allowed.
    Timeout,
    /// Another IO failure.
    Io(io::Error),
    /// A frame kind this version does not know, or one sent the wrong way.
    UnknownKind(u8),
    /// A frame longer than [`MAX_FRAME`].
    TooLarge(u32),
    /// A payload that does not decode.
    Malformed(&'static str),
}

impl fmt::Display for ProtocolError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ProtocolError::Closed => write!(f, "connection closed"),
            ProtocolError::Truncated => write!(f, "connection closed in the middle of a frame"),
            ProtocolError::Timeout => write!(f, "timed out waiting for the peer"),
            ProtocolError::Io(e) => write!(f, "{e}"),
            ProtocolError::UnknownKind(k) => write!(f, "unknown frame kind 0x{k:02x}"),
            ProtocolError::TooLarge(n) => write!(f, "frame of {n} bytes is larger than the limit of {MAX_FRAME}"),
            ProtocolError::Malformed(what) => write!(f, "malformed frame: {what}"),
        }
    }
}

impl std::error::Error for ProtocolError {}

impl From<io::Error> for ProtocolError {
    fn from(e: io::Error) -> Self {
        match e.kind() {
            io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut => ProtocolError::Timeout,
            io::ErrorKind::UnexpectedEof => ProtocolError::Truncated,
            _ => ProtocolError::Io(e),
        }
    }
}

/// Whether `name` may name a bundle on a device: 1 to [`MAX_NAME_LEN`] bytes
/// of ASCII letters, digits, `-`, `_` and `.`, not starting with `.` and
/// without `..`, so it can never leave the device's folder or hide as a dot file.
pub fn valid_name(name: &str) -> bool {
    !name.is_empty()
        && name.len() <= MAX_NAME_LEN
        && !name.starts_with('.')
        && !name.contains("..")
        && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_' || b == b'.')
}

/// Builds a payload.
struct Payload(Vec<u8>);

impl Payload {
    fn u16(&mut self, v: u16) -> &mut Self {
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    fn u64(&mut self, v: u64) -> &mut Self {
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    fn bytes(&mut self, v: &[u8]) -> &mut Self {
        self.0.extend_from_slice(v);
        self
    }
    fn str(&mut self, s: &str) -> &mut Self {
        // Longer strings are cut at a character boundary: they are names
        // (validated to be short) or messages for people.
        let mut end = s.len().min(u16::MAX as usize);
        while !s.is_char_boundary(end) {
            end -= 1;
        }
        self.u16(end as u16).bytes(&s.as_bytes()[..end])
    }
    fn entry(&mut self, e: &Entry) -> &mut Self {
        self.str(&e.name).u64(e.size).bytes(&e.checksum)
    }
}

/// Reads a payload.
struct Cursor<'a>(&'a [u8]);

impl<'a> Cursor<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], ProtocolError> {
        if self.0.len() < n {
            return Err(ProtocolError::Malformed("payload too short"));
        }
        let (head, tail) = self.0.split_at(n);
        self.0 = tail;
        Ok(head)
    }
    fn u16(&mut self) -> Result<u16, ProtocolError> {
        let b = self.take(2)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }
    fn u32(&mut self) -> Result<u32, ProtocolError> {
        let mut a = [0; 4];
        a.copy_from_slice(self.take(4)?);
        Ok(u32::from_le_bytes(a))
    }
    fn u64(&mut self) -> Result<u64, ProtocolError> {
        let mut a = [0; 8];
        a.copy_from_slice(self.take(8)?);
        Ok(u64::from_le_bytes(a))
    }
    fn checksum(&mut self) -> Result<Checksum, ProtocolError> {
        let mut a = [0; CHECKSUM_LEN];
        a.copy_from_slice(self.take(CHECKSUM_LEN)?);
        Ok(a)
    }
    fn str(&mut self) -> Result<String, ProtocolError> {
        let n = self.u16()? as usize;
        let b = self.take(n)?;
        core::str::from_utf8(b).map(ToString::to_string).map_err(|_| ProtocolError::Malformed("string is not UTF-8"))
    }
    fn entry(&mut self) -> Result<Entry, ProtocolError> {
        Ok(Entry { name: self.str()?, size: self.u64()?, checksum: self.checksum()? })
    }
    fn end(&self) -> Result<(), ProtocolError> {
        if self.0.is_empty() { Ok(()) } else { Err(ProtocolError::Malformed("trailing bytes in payload")) }
    }
}

fn frame(kind: u8, payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(5 + payload.len());
    out.push(kind);
    out.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    out.extend_from_slice(payload);
    out
}

impl Request {
    /// The request as one frame.
    pub fn encode(&self) -> Vec<u8> {
        let mut p = Payload(Vec::new());
        let k = match self {
            Request::Hello { version } => {
                p.bytes(&HELLO_MAGIC).u16(*version);
                kind::HELLO
            }
            Request::Offer(o) => {
                p.str(&o.name).str(&o.profile).u64(o.size).bytes(&o.checksum);
                kind::OFFER
            }
            Request::Data(d) => {
                p.bytes(d);
                kind::DATA
            }
            Request::Commit => kind::COMMIT,
            Request::List => kind::LIST,
            Request::Delete { name } => {
                p.str(name);
                kind::DELETE
            }
            Request::Bye => kind::BYE,
        };
        frame(k, &p.0)
    }

    /// Decodes a request frame's kind and payload.
    pub fn decode(k: u8, payload: Vec<u8>) -> Result<Request, ProtocolError> {
        if k == kind::DATA {
            return Ok(Request::Data(payload));
        }
        let mut c = Cursor(&payload);
        let r = match k {
            kind::HELLO => {
                if c.take(4)? != HELLO_MAGIC {
                    return Err(ProtocolError::Malformed("hello without the TXLD magic"));
                }
                Request::Hello { version: c.u16()? }
            }
            kind::OFFER => {
                Request::Offer(Offer { name: c.str()?, profile: c.str()?, size: c.u64()?, checksum: c.checksum()? })
            }
            kind::COMMIT => Request::Commit,
            kind::LIST => Request::List,
            kind::DELETE => Request::Delete { name: c.str()? },
            kind::BYE => Request::Bye,
            other => return Err(ProtocolError::UnknownKind(other)),
        };
        c.end()?;
        Ok(r)
    }
}

impl Reply {
    /// The reply as one frame.
    pub fn encode(&self) -> Vec<u8> {
        let mut p = Payload(Vec::new());
        let k = match self {
            Reply::Welcome(i) => {
                p.u16(i.version).str(&i.profile).u64(i.capacity).u64(i.free);
                kind::WELCOME
            }
            Reply::Ready => kind::READY,
            Reply::Verified(e) => {
                p.entry(e);
                kind::VERIFIED
            }
            Reply::Listing(entries) => {
                p.0.extend_from_slice(&(entries.len() as u32).to_le_bytes());
                for e in entries {
                    p.entry(e);
                }
                kind::LISTING
            }
            Reply::Deleted => kind::DELETED,
            Reply::Error { code, message } => {
                p.u16(*code as u16).str(message);
                kind::ERROR
            }
        };
        frame(k, &p.0)
    }

    /// Decodes a reply frame's kind and payload.
    pub fn decode(k: u8, payload: &[u8]) -> Result<Reply, ProtocolError> {
        let mut c = Cursor(payload);
        let r = match k {
            kind::WELCOME => {
                Reply::Welcome(DeviceInfo { version: c.u16()?, profile: c.str()?, capacity: c.u64()?, free: c.u64()? })
            }
            kind::READY => Reply::Ready,
            kind::VERIFIED => Reply::Verified(c.entry()?),
            kind::LISTING => {
                let n = c.u32()?;
                // Each entry takes at least 42 bytes, so `n` is bounded by the frame length.
                let mut entries = Vec::with_capacity((n as usize).min(payload.len() / 42));
                for _ in 0..n {
                    entries.push(c.entry()?);
                }
                Reply::Listing(entries)
            }
            kind::DELETED => Reply::Deleted,
            kind::ERROR => {
                let n = c.u16()?;
                let message = c.str()?;
                match ErrorCode::from_u16(n) {
                    Some(code) => Reply::Error { code, message },
                    // An unknown code from a newer device still reads as a refusal.
                    None => Reply::Error {
                        code: ErrorCode::Protocol,
                        message: format!("unknown error code {n}: {message}"),
                    },
                }
            }
            other => return Err(ProtocolError::UnknownKind(other)),
        };
        c.end()?;
        Ok(r)
    }
}

/// Reads one frame: `(kind, payload)`. A clean end of stream before the first
/// byte is [`ProtocolError::Closed`]; inside a frame, [`ProtocolError::Truncated`].
pub fn read_frame(r: &mut impl Read) -> Result<(u8, Vec<u8>), ProtocolError> {
    let mut head = [0u8; 5];
    let mut got = 0;
    while got < head.len() {
        match r.read(&mut head[got..]) {
            Ok(0) if got == 0 => return Err(ProtocolError::Closed),
            Ok(0) => return Err(ProtocolError::Truncated),
            Ok(n) => got += n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e.into()),
        }
    }
    let len = u32::from_le_bytes([head[1], head[2], head[3], head[4]]);
    if len > MAX_FRAME {
        return Err(ProtocolError::TooLarge(len));
    }
    let mut payload = std::vec![0u8; len as usize];
    r.read_exact(&mut payload)?;
    Ok((head[0], payload))
}

/// Writes one already encoded frame and flushes it.
pub fn write_frame(w: &mut impl Write, frame: &[u8]) -> Result<(), ProtocolError> {
    w.write_all(frame)?;
    w.flush()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec;

    #[test]
    fn requests_round_trip() {
        let reqs = [
            Request::Hello { version: 1 },
            Request::Offer(Offer { name: "map.taxel".into(), profile: "stress2".into(), size: 77, checksum: [9; 32] }),
            Request::Data(vec![1, 2, 3]),
            Request::Commit,
            Request::List,
            Request::Delete { name: "a".into() },
            Request::Bye,
        ];
        for r in reqs {
            let f = r.encode();
            let (k, p) = read_frame(&mut &f[..]).unwrap();
            assert_eq!(Request::decode(k, p).unwrap(), r);
        }
    }

    #[test]
    fn replies_round_trip() {
        let e = Entry { name: "x".into(), size: 5, checksum: [3; 32] };
        let reps = [
            Reply::Welcome(DeviceInfo { version: 1, profile: "stress2".into(), capacity: 10, free: 4 }),
            Reply::Ready,
            Reply::Verified(e.clone()),
            Reply::Listing(vec![e.clone(), e]),
            Reply::Deleted,
            Reply::Error { code: ErrorCode::NoSpace, message: "full".into() },
        ];
        for r in reps {
            let f = r.encode();
            let (k, p) = read_frame(&mut &f[..]).unwrap();
            assert_eq!(Reply::decode(k, &p).unwrap(), r);
        }
    }

    #[test]
    fn a_huge_length_is_refused_before_allocating() {
        let f = [kind::DATA, 0xff, 0xff, 0xff, 0xff];
        assert!(matches!(read_frame(&mut &f[..]), Err(ProtocolError::TooLarge(u32::MAX))));
    }

    #[test]
    fn every_prefix_of_a_frame_is_closed_or_truncated() {
        let f = Request::Offer(Offer { name: "n".into(), profile: "p".into(), size: 1, checksum: [0; 32] }).encode();
        assert!(matches!(read_frame(&mut &f[..0]), Err(ProtocolError::Closed)));
        for k in 1..f.len() {
            assert!(matches!(read_frame(&mut &f[..k]), Err(ProtocolError::Truncated)), "prefix {k}");
        }
    }

    #[test]
    fn a_listing_claiming_many_entries_fails_without_allocating_them() {
        let mut p = u32::MAX.to_le_bytes().to_vec();
        p.extend_from_slice(&[0; 10]);
        assert!(Reply::decode(kind::LISTING, &p).is_err());
    }

    #[test]
    fn names_are_plain_file_names() {
        for good in ["map.taxel", "a", "Europe_1-2.taxel"] {
            assert!(valid_name(good), "{good}");
        }
        let long = "a".repeat(MAX_NAME_LEN + 1);
        for bad in ["", ".", "..", "../x", "a/b", "a\\b", ".hidden", "a..b", "caf\u{e9}", "a b", long.as_str()] {
            assert!(!valid_name(bad), "{bad}");
        }
    }
}
