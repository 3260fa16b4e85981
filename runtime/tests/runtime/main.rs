//! Integration tests of the runtime, one module per area.

mod device;
