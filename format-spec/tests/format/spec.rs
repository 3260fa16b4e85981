//! `SPEC.md` cannot rot: its worked hex dump must be what the writer produces
//! for `sample::tiny()`, and its constants must be the crate's.
//!
//! `TAXEL_BLESS=1 cargo test -p taxel-format --test format spec` rewrites the
//! dump in SPEC.md after a deliberate change.

use taxel_format::{Bundle, BundleView, sample};

const BEGIN: &str = "<!-- hexdump:begin -->\n```text\n";
const END: &str = "```\n<!-- hexdump:end -->";

/// `xxd`-style lines: offset, 16 bytes in two groups of 8, printable ASCII.
fn hexdump(bytes: &[u8]) -> String {
    let mut out = String::new();
    for (row, line) in bytes.chunks(16).enumerate() {
        out += &format!("{:08x} ", row * 16);
        for (i, b) in line.iter().enumerate() {
            if i == 8 {
                out.push(' ');
            }
            out += &format!(" {b:02x}");
        }
        let ascii: String =
            line.iter().map(|&b| if b.is_ascii_graphic() || b == b' ' { b as char } else { '.' }).collect();
        out += &format!("  |{ascii}|\n");
    }
    out
}

#[test]
fn the_worked_example_is_what_the_writer_writes() {
    let bytes = sample::tiny().to_bytes().unwrap();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/SPEC.md");
    let spec = std::fs::read_to_string(path).unwrap();
    let start = spec.find(BEGIN).expect("SPEC.md has a hexdump:begin marker") + BEGIN.len();
    let end = start + spec[start..].find(END).expect("SPEC.md has a hexdump:end marker");
    let dump = hexdump(&bytes);
    if std::env::var_os("TAXEL_BLESS").is_some() {
        std::fs::write(path, format!("{}{}{}", &spec[..start], dump, &spec[end..])).unwrap();
        return;
    }
    assert_eq!(spec[start..end], dump, "SPEC.md's dump is stale; re-bless with TAXEL_BLESS=1");
    // The dump reads back to the example, so a reader can follow it field by field.
    assert_eq!(Bundle::from_view(&BundleView::parse(&bytes).unwrap()), sample::tiny());
}

#[test]
fn the_spec_quotes_the_crates_constants() {
    let spec = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/SPEC.md")).unwrap();
    for (name, value) in [
        ("MAX_CHUNKS", taxel_format::MAX_CHUNKS as u64),
        ("MAX_FILE_LEN", taxel_format::MAX_FILE_LEN),
        ("MAX_MASK_SIDE", taxel_format::MAX_MASK_SIDE as u64),
        ("MAX_MASK_SAMPLES", taxel_format::MAX_MASK_SAMPLES),
        ("MAX_DISTANCE_TILES", taxel_format::MAX_DISTANCE_TILES as u64),
        ("MAX_DOTS", taxel_format::MAX_DOTS as u64),
        ("MAX_DOT_GRID_CELLS", taxel_format::MAX_DOT_GRID_CELLS as u64),
        ("MAX_STROKES", taxel_format::MAX_STROKES as u64),
        ("MAX_STROKE_POINTS", taxel_format::MAX_STROKE_POINTS as u64),
        ("MAX_STROKE_DRIVES", taxel_format::MAX_STROKE_DRIVES as u64),
        ("MAX_DRIVES_PER_POINT", taxel_format::MAX_DRIVES_PER_POINT as u64),
        ("MAX_FIELD_SIDE", taxel_format::MAX_FIELD_SIDE as u64),
        ("MAX_FIELD_NODES", taxel_format::MAX_FIELD_NODES),
        ("MAX_FIELD_CODE", taxel_format::MAX_FIELD_CODE as u64),
        ("MAX_PROVENANCE_ENTRIES", taxel_format::MAX_PROVENANCE_ENTRIES as u64),
        ("MAX_FOOTPRINT_SHAPES", taxel_format::MAX_FOOTPRINT_SHAPES as u64),
        ("MAX_FOOTPRINT_RINGS", taxel_format::MAX_FOOTPRINT_RINGS as u64),
        ("MAX_FOOTPRINT_POINTS", taxel_format::MAX_FOOTPRINT_POINTS as u64),
        ("MAX_ACTUATORS", taxel_format::MAX_ACTUATORS as u64),
        ("MAX_RATE_HZ", taxel_format::MAX_RATE_HZ as u64),
    ] {
        let row = format!("| `{name}` | {value} |");
        assert!(spec.contains(&row), "SPEC.md should have the row {row}");
    }
}
