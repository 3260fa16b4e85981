//! Fuzzes the bundle reader: `BundleView::parse` must never panic, and any
//! bundle it accepts must read into the owned model and write back to the
//! same bytes (a valid bundle has exactly one encoding, SPEC.md section 1).
//! A stored (compressed) file is inflated first (SPEC.md section 15), which
//! must not panic either, and what it gives is read the same way.
#![no_main]

use libfuzzer_sys::fuzz_target;
use taxel_format::{Bundle, BundleView, stored};

fuzz_target!(|data: &[u8]| {
    let Ok(plain) = stored::plain(data) else { return };
    if let Ok(view) = BundleView::parse(&plain) {
        for chunk in view.chunks() {
            let _ = chunk;
        }
        let (_, minor) = view.version();
        let again = Bundle::from_view(&view).to_bytes_with_minor(minor).expect("an accepted bundle re-encodes");
        assert_eq!(again, &plain[..], "an accepted bundle is canonical");
    }
});
