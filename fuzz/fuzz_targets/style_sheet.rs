//! Fuzzes the style-sheet reader on raw text and on generated TOML
//! (`compiler/tests/compiler/svggen.rs`): it must never panic, and an error
//! must name the file.
#![no_main]

use libfuzzer_sys::fuzz_target;
use taxel_compiler::StyleSheet;

#[path = "../../compiler/tests/compiler/svggen.rs"]
mod svggen;

fn check(text: &str) {
    if let Err(e) = StyleSheet::parse(text, "sheet.toml") {
        assert!(e.to_string().starts_with("sheet.toml"), "{e}");
    }
}

fuzz_target!(|data: &[u8]| {
    check(&String::from_utf8_lossy(data));
    check(&svggen::style_sheet(&mut svggen::Choices::new(data)));
});
