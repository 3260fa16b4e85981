//! Loading bundles onto devices (`std` only): the loader protocol, a device's
//! bundle store, the device simulator's server and the loader client.
//!
//! The protocol is documented in `docs/protocol.md`. In short: a client says
//! `HELLO`, the device answers `WELCOME` with its profile and free space; the
//! client `OFFER`s a bundle (name, profile, size, BLAKE3 checksum), the device
//! answers `READY` once it has reserved the space, the client sends `DATA`
//! frames and a `COMMIT`, and the device answers `VERIFIED` only after it has
//! checked the size, the checksum, the bundle's validity and its profile, and
//! put the bundle in place of any older one of the same name. A refusal is an
//! `ERROR` frame with a code ([`ErrorCode`]).
//!
//! The [`Store`] holds the rules that keep a device's storage consistent;
//! the simulator ([`Server`]) and a mounted device folder share it.

mod client;
pub mod protocol;
mod server;
mod store;

pub use client::{Client, ClientError};
pub use protocol::{Checksum, DeviceInfo, Entry, ErrorCode, Offer, Reply, Request, checksum, valid_name};
pub use server::{Server, ServerConfig, ServerHandle};
pub use store::{Refusal, STAGING_PREFIX, Store, StoreConfig, Upload};
