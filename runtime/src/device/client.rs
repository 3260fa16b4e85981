//! The loader client: talks to a device (or the simulator) over TCP.
//!
//! ```no_run
//! use std::time::Duration;
//! use taxel_runtime::device::Client;
//!
//! let bytes = std::fs::read("map.taxel").unwrap();
//! let mut device = Client::connect("127.0.0.1:7878", Duration::from_secs(10)).unwrap();
//! let entry = device.load("map.taxel", &bytes).unwrap();
//! assert_eq!(entry.size, bytes.len() as u64);
//! ```

use std::fmt;
use std::io;
use std::net::{TcpStream, ToSocketAddrs};
use std::string::{String, ToString};
use std::time::Duration;
use std::vec::Vec;

use taxel_format::BundleView;

use super::protocol::{
    DATA_CHUNK, DeviceInfo, Entry, ErrorCode, Offer, PROTOCOL_VERSION, ProtocolError, Reply, Request, checksum,
    read_frame, valid_name, write_frame,
};
use super::store::Refusal;

/// Why a client operation failed.
#[derive(Debug)]
pub enum ClientError {
    /// No connection could be made.
    Connect {
        /// The address tried.
        addr: String,
        /// Why.
        source: io::Error,
    },
    /// The connection failed or the device sent something unreadable.
    Protocol(ProtocolError),
    /// The device (or the client's own check before sending) refused.
    Refused(Refusal),
    /// The device answered with a message that makes no sense here.
    Unexpected(&'static str),
}

impl ClientError {
    /// The refusal code, when the device refused.
    pub fn code(&self) -> Option<ErrorCode> {
        match self {
            ClientError::Refused(r) => Some(r.code),
            _ => None,
        }
    }
}

impl fmt::Display for ClientError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ClientError::Connect { addr, source } => write!(f, "cannot connect to {addr}: {source}"),
            ClientError::Protocol(e) => write!(f, "{e}"),
            ClientError::Refused(r) => write!(f, "{r}"),
            ClientError::Unexpected(what) => write!(f, "unexpected reply from the device: {what}"),
        }
    }
}

impl std::error::Error for ClientError {}

impl From<ProtocolError> for ClientError {
    fn from(e: ProtocolError) -> Self {
        ClientError::Protocol(e)
    }
}

/// A session with one device.
#[derive(Debug)]
pub struct Client {
    stream: TcpStream,
    info: DeviceInfo,
}

impl Client {
    /// Connects to `addr` (`HOST:PORT`) and says hello. `timeout` bounds the
    /// connection and every wait for a reply.
    pub fn connect(addr: &str, timeout: Duration) -> Result<Client, ClientError> {
        let err = |source| ClientError::Connect { addr: addr.to_string(), source };
        let mut last = io::Error::new(io::ErrorKind::NotFound, "the address resolves to nothing");
        let mut stream = None;
        for a in addr.to_socket_addrs().map_err(err)? {
            match TcpStream::connect_timeout(&a, timeout) {
                Ok(s) => {
                    stream = Some(s);
                    break;
                }
                Err(e) => last = e,
            }
        }
        let stream = stream.ok_or_else(|| err(last))?;
        stream.set_read_timeout(Some(timeout)).map_err(ProtocolError::from)?;
        stream.set_write_timeout(Some(timeout)).map_err(ProtocolError::from)?;
        let _ = stream.set_nodelay(true);
        let mut client =
            Client { stream, info: DeviceInfo { version: 0, profile: String::new(), capacity: 0, free: 0 } };
        client.send(&Request::Hello { version: PROTOCOL_VERSION })?;
        match client.receive()? {
            Reply::Welcome(info) => client.info = info,
            _ => return Err(ClientError::Unexpected("expected WELCOME")),
        }
        Ok(client)
    }

    /// What the device said about itself when the session opened.
    pub fn info(&self) -> &DeviceInfo {
        &self.info
    }

    fn send(&mut self, req: &Request) -> Result<(), ProtocolError> {
        write_frame(&mut self.stream, &req.encode())
    }

    /// The next reply; a device refusal becomes [`ClientError::Refused`].
    fn receive(&mut self) -> Result<Reply, ClientError> {
        let (kind, payload) = read_frame(&mut self.stream)?;
        match Reply::decode(kind, &payload)? {
            Reply::Error { code, message } => Err(ClientError::Refused(Refusal { code, message })),
            r => Ok(r),
        }
    }

    /// Loads a bundle as `name`, and returns once the device has verified
    /// and stored it. The bundle is validated and its profile checked
    /// against the device's before anything is sent.
    pub fn load(&mut self, name: &str, bytes: &[u8]) -> Result<Entry, ClientError> {
        if !valid_name(name) {
            return Err(ClientError::Refused(Refusal::new(
                ErrorCode::InvalidName,
                std::format!("{name:?} is not a plain bundle name"),
            )));
        }
        // A stored (compressed) bundle is checked inflated and sent as it is.
        let invalid = |e| ClientError::Refused(Refusal::new(ErrorCode::InvalidBundle, std::format!("{name}: {e}")));
        let plain = taxel_format::stored::plain(bytes).map_err(invalid)?;
        let view = BundleView::parse(&plain).map_err(invalid)?;
        let profile = view.manifest().profile.name.as_str().to_string();
        if !self.info.profile.is_empty() && self.info.profile != profile {
            return Err(ClientError::Refused(Refusal::new(
                ErrorCode::WrongProfile,
                std::format!("{name} is for profile {profile:?} but the device is {:?}", self.info.profile),
            )));
        }
        let sum = checksum(bytes);
        self.send(&Request::Offer(Offer { name: name.into(), profile, size: bytes.len() as u64, checksum: sum }))?;
        match self.receive()? {
            Reply::Ready => {}
            _ => return Err(ClientError::Unexpected("expected READY")),
        }
        for chunk in bytes.chunks(DATA_CHUNK) {
            if let Err(e) = self.send(&Request::Data(chunk.to_vec())) {
                // The device may have refused and closed; its reason is worth more than ours.
                return Err(match self.receive() {
                    Err(refused @ ClientError::Refused(_)) => refused,
                    _ => ClientError::Protocol(e),
                });
            }
        }
        self.send(&Request::Commit)?;
        match self.receive()? {
            Reply::Verified(entry) if entry.checksum == sum && entry.size == bytes.len() as u64 => Ok(entry),
            Reply::Verified(_) => Err(ClientError::Unexpected("the device verified different bytes")),
            _ => Err(ClientError::Unexpected("expected VERIFIED")),
        }
    }

    /// The bundles on the device.
    pub fn list(&mut self) -> Result<Vec<Entry>, ClientError> {
        self.send(&Request::List)?;
        match self.receive()? {
            Reply::Listing(entries) => Ok(entries),
            _ => Err(ClientError::Unexpected("expected LISTING")),
        }
    }

    /// Deletes a bundle from the device.
    pub fn delete(&mut self, name: &str) -> Result<(), ClientError> {
        self.send(&Request::Delete { name: name.into() })?;
        match self.receive()? {
            Reply::Deleted => Ok(()),
            _ => Err(ClientError::Unexpected("expected DELETED")),
        }
    }

    /// Ends the session politely.
    pub fn bye(mut self) {
        let _ = self.send(&Request::Bye);
    }
}
