//! `taxel build` over many files: see the batch stage.
