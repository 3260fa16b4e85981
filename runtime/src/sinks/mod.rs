//! Sinks: where frames go on a host (files, standard output).

pub mod frames;
pub mod wav;
