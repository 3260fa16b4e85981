//! Integration tests of the bundle format: round trips of every chunk kind,
//! every reader error from crafted files, limits, property tests, device
//! profiles, and the worked example of `SPEC.md`.
//!
//! `craft` is an encoder written from `SPEC.md` alone (not from the crate's
//! writer), so the tests check the crate against the specification.

mod chunks;
mod container;
mod craft;
mod footprints;
mod limits;
mod profiles;
mod props;
mod roundtrip;
mod spec;
mod tile_access;
mod tiled;
