//! Property tests: the reader never panics, and whatever it accepts is
//! canonical (re-encoding what was read gives the same bytes).

use proptest::prelude::*;
use taxel_format::{Bundle, BundleView};

use crate::craft::{every_kind_bytes, reseal};

/// Whatever the outcome, reading must not panic; an accepted bundle must
/// read into the model and write back byte for byte.
fn check(bytes: &[u8]) {
    if let Ok(view) = BundleView::parse(bytes) {
        for c in view.chunks() {
            let _ = c;
        }
        let (major, minor) = view.version();
        assert_eq!(major, taxel_format::FORMAT_MAJOR);
        let again = Bundle::from_view(&view).to_bytes_with_minor(minor).expect("an accepted bundle re-encodes");
        assert_eq!(again, bytes, "an accepted bundle is canonical");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..600)) {
        check(&bytes);
    }

    #[test]
    fn arbitrary_bytes_after_the_magic_never_panic(tail in proptest::collection::vec(any::<u8>(), 0..600)) {
        let mut b = b"\x89TXL\r\n\x1a\n\x01\x00".to_vec();
        b.extend(tail);
        check(&b);
    }

    /// Edits to a valid bundle, re-sealed so that the checksums hold and the
    /// chunk validators are reached with hostile values.
    #[test]
    fn mutated_valid_bundles_never_panic(
        edits in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>(), 0u8..4), 1..8),
        seal in any::<bool>(),
    ) {
        let mut b = every_kind_bytes();
        for (at, v, how) in edits {
            let i = at.index(b.len());
            match how {
                0 => b[i] = v,
                1 => b[i] ^= 1 << (v % 8),
                // Interesting values for counts and sizes.
                2 => b[i] = [0, 1, 0x7f, 0x80, 0xff][v as usize % 5],
                _ => b[i] = b[i].wrapping_add(1),
            }
        }
        if seal {
            reseal(&mut b);
        }
        check(&b);
    }
}
