//! taxel's runtime: plays bundles on tactile devices. The core is `no_std`
//! and allocation-free per tick; the `std` feature adds sinks, the loader and
//! the device simulator. The players read a plain bundle in place; a bundle
//! file is usually its stored (compressed) form, which
//! `taxel_format::stored::inflate_into` turns into the plain bundle once,
//! when the file is loaded, without an allocator.
//!
//! - [`latero::LateroPlayer`]: laterotactile arrays (dots, vibration, gratings).
//! - [`pins::PinsPlayer`]: refreshable pin-matrix displays (bit-packed pin frames).
//! - [`RuntimeError`]: why a bundle cannot be played.
//! - With `std`: [`trace`] (exploration traces) and [`sinks`] (frames CSV).
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

#[cfg(feature = "std")]
extern crate std;

#[cfg(feature = "std")]
pub mod device;
mod error;
pub mod finger;
pub mod grid;
pub mod latero;
pub mod pins;
#[cfg(feature = "std")]
pub mod sinks;
#[cfg(feature = "std")]
pub mod trace;

pub use error::RuntimeError;
