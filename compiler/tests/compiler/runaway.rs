//! Drawings that ran away (issue 47): hand-drawn scribbles, noisy filled
//! areas and dense scatter plots, at sizes a debug test build compiles in a
//! few seconds. The same generators (`benches/drawings`) at the issue's
//! sizes are the `runaway` group of `benches/real_build.rs`; here each case
//! asserts what a reader gets, and `tests/cli/runaway.rs` runs the binary
//! on them within a memory limit.

use taxel_format::DotKind;

use super::realistic::drawings::{jittered_ring, scatter, scribble};

use super::common::{bundle, compile, dots, masks, page, with_code};

#[test]
fn a_scatter_plot_s_overlapping_marks_are_dots_thinned_to_be_felt_apart() {
    // 1,500 circles of 1.2 mm over 100 x 60 mm: most overlap a neighbour.
    // Before, those that touched became 1,000-odd separately grated regions.
    let c = compile(&scatter(1_500, 0.6, (100.0, 60.0), 7));
    let b = bundle(&c);
    assert!(masks(b).is_empty(), "no grated regions: {:?}", masks(b).len());
    let symbols = dots(b, DotKind::Symbol).expect("the marks are dot symbols");
    let n = symbols.dots.len();
    assert!(n >= 50, "an even sample is kept: {n}");
    // Kept dots lie at least the spacing apart on one axis (the thinning's boxes).
    let spacing = taxel_compiler::style::MARK_SPACING_MM as f32;
    for (i, a) in symbols.dots.iter().enumerate() {
        for q in &symbols.dots[i + 1..] {
            let (dx, dy) = ((a.x.0 - q.x.0).abs(), (a.y.0 - q.y.0).abs());
            assert!(dx.max(dy) >= spacing - 1e-3, "dots {dx} x {dy} mm apart");
        }
    }
    let notes = with_code(&c, "T0327");
    assert_eq!(notes.len(), 1, "{:#?}", c.diagnostics);
    assert!(notes[0].message.starts_with(&format!("{} mark(s) left out", 1_500 - n)), "{}", notes[0].message);
}

#[test]
fn a_few_marks_far_apart_are_all_kept() {
    // Towns on a map: ten dots 8 mm apart, none thinned, no note.
    let body: String =
        (0..10).map(|k| format!(r##"<circle cx="{}" cy="30" r="1" fill="#000"/>"##, 10 + 8 * k)).collect();
    let c = compile(&page(&body));
    assert_eq!(dots(bundle(&c), DotKind::Symbol).map(|d| d.dots.len()), Some(10));
    assert!(with_code(&c, "T0327").is_empty());
}

#[test]
fn a_grid_of_small_cells_sharing_sides_stays_a_tessellation() {
    // A heat map's 4 mm cells of two colours share sides and lie across none:
    // regions (gratings), not dots.
    let mut body = String::new();
    for j in 0..8 {
        for i in 0..16 {
            let fill = if (i + j) % 2 == 0 { "#c00" } else { "#00c" };
            body += &format!(r#"<rect x="{}" y="{}" width="4" height="4" fill="{fill}"/>"#, 10 + 4 * i, 10 + 4 * j);
        }
    }
    let c = compile(&page(&body));
    let b = bundle(&c);
    assert!(!masks(b).is_empty(), "{:#?}", c.diagnostics);
    assert!(dots(b, DotKind::Symbol).is_none());
}

#[test]
fn a_self_crossing_scribble_builds_its_layers() {
    // 2,000 random segments crossing themselves some 400,000 times, filled
    // and stroked: the area, the fills' union and the distance layers all
    // stay bounded (before, the overlay behind the area took 14 s at 3,000).
    let c = compile(&scribble(
        2_000,
        (100.0, 60.0),
        r##"stroke="#000" stroke-width="0.5" data-tactile="grating(); vibrate()""##,
        3,
    ));
    assert_eq!(masks(bundle(&c)).len(), 2, "{:#?}", c.diagnostics);
}

#[test]
fn a_jittered_ring_is_one_grated_region() {
    let c = compile(&jittered_ring(20_000, 20.0, 2.0, (100.0, 60.0), 5));
    assert_eq!(masks(bundle(&c)).len(), 1, "{:#?}", c.diagnostics);
}

#[test]
fn a_detailed_sea_painted_over_many_islands_is_weighed_in_bounded_time() {
    // 1,500 islands of one texture, then an opaque sea of 20,000 points
    // painted over them all, and a lake of a second texture over the sea.
    // Whether the sea hides every island wholly would take an overlay of
    // the sea's outline per island: past a budget of points the islands'
    // texture counts as felt, and stays in the key.
    let mut body = String::new();
    for k in 0..1_500 {
        let (x, y) = (8.0 + (k % 50) as f64 * 1.7, 8.0 + (k / 50) as f64 * 1.4);
        body += &format!(
            r#"<rect x="{x:.2}" y="{y:.2}" width="0.6" height="0.6" data-tactile="grating(wavelength: 3mm)"/>"#
        );
    }
    let n = 5_000;
    let side = |k: usize| -> (f64, f64) {
        let (t, w) = ((k % n) as f64 / n as f64, 0.3 * (k as f64 * 0.7).sin());
        match k / n {
            0 => (4.0 + 92.0 * t, 4.0 + w),
            1 => (96.0 + w, 4.0 + 52.0 * t),
            2 => (96.0 - 92.0 * t, 56.0 + w),
            _ => (4.0 + w, 56.0 - 52.0 * t),
        }
    };
    let sea: Vec<String> = (0..4 * n).map(|k| format!("{:.3},{:.3}", side(k).0, side(k).1)).collect();
    body += &format!(r##"<path fill="#9cf" d="M{} Z"/>"##, sea.join(" L"));
    body += r#"<rect x="40" y="25" width="20" height="10" fill="white" data-tactile="grating(wavelength: 6mm)"/>"#;
    let c = compile(&page(&body));
    let b = bundle(&c);
    // So is whether each island's corners lie under the sea: past a budget
    // of point pairs they count, and the islands' layer is kept as before.
    assert_eq!(masks(b).len(), 2);
    let key = with_code(&c, "T0331");
    assert_eq!(key.len(), 1, "{:#?}", c.diagnostics.iter().filter(|d| d.code != "T0407").collect::<Vec<_>>());
    assert!(key[0].message.contains("(2 entries)"), "{}", key[0].message);
}
