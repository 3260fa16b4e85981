//! Fuzzes the annotation parser, on raw text and on generated, mostly
//! well-formed annotations (`compiler/tests/compiler/svggen.rs`): it must
//! never panic, and an error must point inside the text.
#![no_main]

use libfuzzer_sys::fuzz_target;
use taxel_compiler::annotation;

#[path = "../../compiler/tests/compiler/svggen.rs"]
mod svggen;

fn check(text: &str) {
    if let Err(e) = annotation::parse(text) {
        assert!(e.offset <= text.len(), "offset {} past {text:?}", e.offset);
    }
}

fuzz_target!(|data: &[u8]| {
    check(&String::from_utf8_lossy(data));
    check(&svggen::annotation(&mut svggen::Choices::new(data)));
});
