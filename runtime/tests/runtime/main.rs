//! Integration tests of the runtime, one module per area.
//!
//! The allocation counter (`allocation-counter`) is this binary's global
//! allocator; it counts per thread, so tests running in parallel do not
//! disturb each other's counts.

mod device;
mod finger;
mod grid;
mod latero_alloc;
mod latero_art;
mod latero_extreme;
mod latero_field;
mod latero_formula;
mod latero_load;
mod pins;
mod support;
mod trace;
