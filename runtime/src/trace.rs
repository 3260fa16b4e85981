//! Exploration traces.
