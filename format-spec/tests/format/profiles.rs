//! Device profile files: every error names the file and the key.

use taxel_format::profiles::{self, BUILTIN};

fn stress2() -> &'static str {
    BUILTIN.iter().find(|(n, _)| *n == "stress2").unwrap().1
}

#[test]
fn every_builtin_matches_the_papers() {
    let s = profiles::builtin("stress2").unwrap();
    assert_eq!((s.rows, s.cols, s.pitch_x_mm, s.pitch_y_mm, s.rate_hz, s.output_bits), (8, 8, 1.2, 1.4, 1000, 10));
    let b = profiles::builtin("brush-4x3").unwrap();
    assert_eq!((b.rows, b.cols, b.pitch_x_mm, b.pitch_y_mm), (3, 4, 63.0, 63.0));
    assert_eq!((b.surface_w_mm, b.surface_h_mm), (189.0, 126.0), "3 x 63 by 2 x 63 mm");
    let f = profiles::builtin("finger3").unwrap();
    assert_eq!(f.actuator_count(), 3);
    assert_eq!(
        profiles::builtin_names(),
        [
            "stress2",
            "brush-4x3",
            "finger3",
            "dotpad",
            "monarch",
            "graphiti",
            "hyperbraille",
            // The print media (their papers' values: `profiles::tests` and docs/print.md).
            "swell-a4",
            "swell-letter",
            "tiger-20dpi",
            "emboss-braille-grid",
            "print3d"
        ]
    );
}

#[test]
fn an_unknown_field_is_named_with_file_and_key() {
    let text = stress2().replace("pitch_y_mm = 1.4", "pitch_y_mm = 1.4\npitch_z_mm = 2");
    let e = profiles::parse(&text, "lab/array.toml").unwrap_err();
    let msg = e.to_string();
    assert!(msg.starts_with("lab/array.toml"), "{msg}");
    assert_eq!(e.key.as_deref(), Some("array.pitch_z_mm"), "{msg}");
    assert!(msg.contains("unknown"), "{msg}");
}

#[test]
fn a_missing_field_is_named_with_file_and_key() {
    let text = stress2().replace("pitch_y_mm = 1.4", "");
    let e = profiles::parse(&text, "lab/array.toml").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("array.pitch_y_mm"), "{e}");
    assert!(e.to_string().starts_with("lab/array.toml"), "{e}");
    let text = stress2().replace("rate_hz = 1000", "");
    assert_eq!(profiles::parse(&text, "p").unwrap_err().key.as_deref(), Some("rate_hz"));
}

#[test]
fn a_value_of_the_wrong_type_or_out_of_range_is_named() {
    for (from, to, key) in [
        ("rows = 8", "rows = -8", "array.rows"),
        ("rows = 8", "rows = \"eight\"", "array.rows"),
        ("rows = 8", "rows = 1000", "array.rows"),
        ("cols = 8", "cols = 0", "array.cols"),
        ("rate_hz = 1000", "rate_hz = 0", "rate_hz"),
        ("rate_hz = 1000", "rate_hz = 2000000", "rate_hz"),
        ("output_bits = 10", "output_bits = 40", "output_bits"),
        ("width_mm = 110", "width_mm = nan", "surface.width_mm"),
        ("height_mm = 60", "height_mm = -60", "surface.height_mm"),
        ("pitch_x_mm = 1.2", "pitch_x_mm = 0", "array.pitch_x_mm"),
    ] {
        assert!(stress2().contains(from), "{from}");
        let e = profiles::parse(&stress2().replace(from, to), "dev.toml").unwrap_err();
        assert_eq!(e.key.as_deref(), Some(key), "{to}: {e}");
        assert!(e.to_string().starts_with("dev.toml: key `"), "{e}");
    }
}

#[test]
fn family_tables_are_checked() {
    let brush = BUILTIN.iter().find(|(n, _)| *n == "brush-4x3").unwrap().1;
    let e = profiles::parse(&brush.replace("audio_rate_hz = 48000", "audio_rate_hz = 400"), "b.toml").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("grid.audio_rate_hz"), "{e}");
    let e = profiles::parse(&brush.replace("carrier_max_hz = 270", "carrier_max_hz = 100"), "b.toml").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("grid.carrier_min_hz"), "{e}");
    let finger = BUILTIN.iter().find(|(n, _)| *n == "finger3").unwrap().1;
    let e = profiles::parse(&finger.replace("rhythm_max = 100", "rhythm_max = 105"), "f.toml").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("finger.rhythm_max"), "{e}");
    let e = profiles::parse(&finger.replace("cols = 3", "cols = 4"), "f.toml").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("array.cols"), "{e}");
    let e = profiles::parse(&format!("{}\n[grid]\nramp_ms = 1\n", stress2()), "s.toml").unwrap_err();
    assert!(e.to_string().starts_with("s.toml"), "{e}");
}

#[test]
fn toml_syntax_errors_name_the_file_and_line() {
    let e = profiles::parse("name = \"x\"\nrate_hz = = 3\n", "bad.toml").unwrap_err();
    let msg = e.to_string();
    assert!(msg.starts_with("bad.toml"), "{msg}");
    assert!(msg.contains("line 2"), "{msg}");
}

#[test]
fn value_errors_give_the_line() {
    let text = stress2().replace("rows = 8", "rows = \"eight\"");
    let line = text.lines().position(|l| l.starts_with("rows")).unwrap() + 1;
    let e = profiles::parse(&text, "dev.toml").unwrap_err();
    assert_eq!(e.to_string(), format!("dev.toml: key `array.rows`: line {line}: expected an integer from 0 to 65535"));
}

proptest::proptest! {
    /// Floats are read from their text as `f32`, so any pitch written with
    /// Rust's shortest round-trip `Display` reads back bit for bit.
    #[test]
    fn profile_floats_round_trip_exactly(bits in 0x3000_0000u32..0x447a_0000u32, w in 1.0e-3f32..1.0e6) {
        let mut p = profiles::builtin("brush-4x3").unwrap();
        p.pitch_x_mm = f32::from_bits(bits);
        p.surface_w_mm = w;
        if let taxel_format::FamilyParams::Grid(g) = &mut p.params {
            g.ramp_ms = f32::from_bits(bits).min(1000.0);
        }
        let back = profiles::parse(&profiles::to_toml(&p), "p.toml").unwrap();
        proptest::prop_assert_eq!(back.pitch_x_mm.to_bits(), p.pitch_x_mm.to_bits());
        proptest::prop_assert_eq!(back, p);
    }
}
