//! The trace reader against hostile input, as a bounded stand-in for the
//! `trace` fuzz target (`fuzz/`): any bytes parse or give an error, never a
//! panic, and an accepted trace keeps its documented invariants.

use proptest::prelude::*;
use taxel_runtime::trace::Trace;

/// The invariants `Trace::parse` promises for what it accepts.
fn check(t: &Trace) {
    let s = t.samples();
    assert!(!s.is_empty());
    for x in s {
        assert!(x.t_ms.is_finite() && x.t_ms >= 0.0 && x.x_mm.is_finite() && x.y_mm.is_finite(), "{x:?}");
    }
    assert!(s.windows(2).all(|w| w[0].t_ms <= w[1].t_ms));
    // Interpolated positions stay inside the samples' box.
    let (x0, x1) = s.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, s| (a.0.min(s.x_mm), a.1.max(s.x_mm)));
    let slack = |v: f64| 1e-9 * v.abs().max(1.0);
    for (_, p) in t.ticks(1000).take(2_000) {
        assert!(p.x_mm >= x0 - slack(x0) && p.x_mm <= x1 + slack(x1), "{p:?} outside {x0}..{x1}");
    }
}

/// One CSV field: numbers ordinary and hostile, and junk.
fn field() -> impl Strategy<Value = String> {
    prop_oneof![
        (0u32..100_000).prop_map(|v| (v as f64 / 10.0).to_string()),
        prop::sample::select(vec![
            "0",
            "-1",
            "1e308",
            "-1e308",
            "1e-320",
            "NaN",
            "inf",
            "-inf",
            "",
            " 5 ",
            "1,5",
            "\"3\"",
            "0x10",
            "1e400",
            "é",
            "\u{feff}0",
        ])
        .prop_map(str::to_string),
    ]
}

/// A trace-like CSV: a header of known and unknown columns, then rows.
fn csv_text() -> impl Strategy<Value = String> {
    let header =
        prop::collection::vec(prop::sample::select(vec!["t_ms", "x_mm", "y_mm", "contact", "note", "T_MS", ""]), 0..6);
    let rows = prop::collection::vec(prop::collection::vec(field(), 0..6), 0..12);
    (header, rows).prop_map(|(h, rows)| {
        let mut s = h.join(",");
        s.push('\n');
        for r in rows {
            s.push_str(&r.join(","));
            s.push('\n');
        }
        s
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn any_bytes_parse_or_give_an_error(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
        if let Ok(t) = Trace::parse(&bytes[..]) {
            check(&t);
        }
    }

    #[test]
    fn trace_like_text_parses_or_names_a_line(text in csv_text()) {
        match Trace::parse(text.as_bytes()) {
            Ok(t) => check(&t),
            Err(e) => {
                let m = e.to_string();
                prop_assert!(!m.is_empty());
                // Every row problem names its line, and the line is in the text.
                if let Some(rest) = m.strip_prefix("line ") {
                    let line: usize = rest.split(':').next().and_then(|n| n.parse().ok()).unwrap_or(0);
                    prop_assert!(line >= 1 && line <= text.lines().count().max(1), "{m} in {text:?}");
                }
            }
        }
    }
}

/// Regression-style examples the generator reaches: a time so large that
/// its tick saturates, and a row of only a byte-order mark.
#[test]
fn extreme_times_saturate_instead_of_overflowing() {
    let t = Trace::parse(&b"t_ms,x_mm,y_mm\n0,0,0\n1e308,5,0\n"[..]).unwrap();
    check(&t);
    let (first, last) = t.tick_range(48_000).unwrap();
    assert_eq!((first.0, last.0), (0, 1 << 62));
    assert!(Trace::parse("\u{feff}\n".as_bytes()).is_err());
}
