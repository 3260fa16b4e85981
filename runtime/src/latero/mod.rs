//! Player for the latero device family (placeholder until its issue lands).
