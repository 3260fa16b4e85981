//! taxel's runtime: plays bundles on tactile devices. The core is `no_std`
//! and allocation-free per tick; the `std` feature adds sinks, the loader and
//! the device simulator.
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

#[cfg(feature = "std")]
extern crate std;

#[cfg(feature = "std")]
pub mod device;
pub mod finger;
pub mod grid;
pub mod latero;
