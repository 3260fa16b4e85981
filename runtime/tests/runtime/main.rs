//! Integration tests of the runtime, one module per area.
//!
//! The allocation counter (`allocation-counter`) is this binary's global
//! allocator; it counts per thread, so tests running in parallel do not
//! disturb each other's counts.
//!
//! Built without the runtime's `std` feature (`cargo test -p taxel-runtime
//! --no-default-features`, as CI does), the players run their baseline
//! kernels, which the `std` build replaces by those for the CPU it runs on
//! where it has them (AVX on x86-64): the modules on `std`'s sinks, device
//! and trace are left out then.

#[cfg(feature = "std")]
mod device;
mod finger;
mod finger_tiled;
#[cfg(feature = "std")]
mod grid;
mod latero_alloc;
mod latero_art;
mod latero_extreme;
mod latero_field;
mod latero_formula;
mod latero_load;
mod pins;
mod support;
#[cfg(feature = "std")]
mod trace;
