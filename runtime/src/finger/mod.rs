//! Player for the finger device family (placeholder until its issue lands).
