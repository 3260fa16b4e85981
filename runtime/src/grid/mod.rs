//! Player for the grid device family (placeholder until its issue lands).
