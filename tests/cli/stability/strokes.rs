//! Brushed strokes on the 4 x 3 grid (63 mm pitch, 1 kHz ticks): the stiff
//! case, degenerate paths, and paths that run along grid lines and through nodes.

use taxel_compiler::brush::{BrushRequest, compile_strokes, plan_strokes};
use taxel_format::{Bundle, BundleView, Chunk, Manifest, StrokeTable, Tick, profiles};
use taxel_runtime::grid::{ActuatorDrive, GridPlayer};

use super::{codes, has};

fn request(polyline: Vec<(f64, f64)>, duration_ms: f64) -> BrushRequest {
    BrushRequest {
        polyline,
        duration_ms,
        intensity: 1.0,
        freq_hz: 200.0,
        start_ms: None,
        source: None,
        element: "s".into(),
        line: None,
    }
}

fn brush(reqs: &[BrushRequest]) -> (Option<StrokeTable>, Vec<taxel_compiler::Diagnostic>) {
    let mut diags = Vec::new();
    let t = compile_strokes(reqs, &profiles::builtin("brush-4x3").expect("profile"), &mut diags);
    (t, diags)
}

/// Checks the schedule invariants of every stroke and plays it: positive
/// durations, non-decreasing onsets, the end within one tick of T, every
/// drive and every played amplitude finite and in [0, 1].
fn check_and_play(t: &StrokeTable, duration_ticks: u32) {
    for s in &t.strokes {
        let mut last = 0;
        for p in &s.points {
            assert!(p.duration >= 1, "a point with no duration");
            assert!(p.onset >= last, "onsets go backwards");
            last = p.onset;
            assert!(p.onset + p.duration <= duration_ticks + 1, "a point outlasts the stroke");
            assert!(p.drives.iter().all(|d| (0.0..=1.0).contains(&d.intensity)));
        }
        let end = s.points.iter().map(|p| p.onset + p.duration).max().unwrap_or(0);
        assert!(end.abs_diff(duration_ticks) <= 1, "the stroke ends at {end}, not {duration_ticks}");
    }
    let mut b = Bundle::new(Manifest::new(profiles::builtin("brush-4x3").expect("profile")));
    b.chunks.push(Chunk::Strokes(t.clone()));
    let bytes = b.to_bytes().expect("writes");
    let view = BundleView::parse(&bytes).expect("reads");
    let player = GridPlayer::new(&view).expect("grid bundle");
    let mut out = vec![ActuatorDrive::default(); player.actuator_count()];
    for tick in 0..=player.end().0 + 2 {
        player.frame(Tick(tick), &mut out);
        for d in &out {
            assert!(d.amplitude.is_finite() && (0.0..=1.0).contains(&d.amplitude), "tick {tick}: {d:?}");
        }
    }
}

/// Stiff: a 100 ms diagonal across the whole grid crosses 5 grid lines, so
/// the published recurrence gives negative durations. taxel merges points
/// until the schedule is feasible and says so (T0510).
#[test]
fn fast_stroke_with_crowded_virtual_points() {
    let (t, diags) = brush(&[request(vec![(0.0, 0.0), (189.0, 126.0)], 100.0)]);
    assert!(has(&diags, "T0510"), "{:?}", codes(&diags));
    let t = t.expect("a feasible table");
    assert!(!t.strokes.is_empty());
    check_and_play(&t, 100);
}

/// Stiffer than any merge can fix: 10 ms for the full diagonal (one point
/// already needs about 69 ms by the SOA model). An error that names the
/// shortest duration that works, and no table.
#[test]
fn infeasible_stroke_names_the_shortest_duration() {
    let (t, diags) = brush(&[request(vec![(0.0, 0.0), (189.0, 126.0)], 10.0)]);
    let d = diags.iter().find(|d| d.code == "T0511").unwrap_or_else(|| panic!("{:?}", codes(&diags)));
    assert!(d.help.as_deref().is_some_and(|h| h.contains("at least")), "{d:?}");
    assert!(t.is_none_or(|t| t.strokes.is_empty()));
}

/// A zero-length path is a stationary vibration at its point (note T0506), never a division by zero.
#[test]
fn zero_length_path() {
    let (t, diags) = brush(&[request(vec![(63.0, 63.0), (63.0, 63.0)], 500.0)]);
    assert!(has(&diags, "T0506"), "{:?}", codes(&diags));
    check_and_play(&t.expect("a table"), 500);
}

/// A single point is the same stationary vibration; an empty path is an error (T0501).
#[test]
fn single_point_and_empty_paths() {
    let (t, diags) = brush(&[request(vec![(30.0, 20.0)], 300.0)]);
    assert!(has(&diags, "T0506") || has(&diags, "T0501"), "{:?}", codes(&diags));
    if let Some(t) = t {
        check_and_play(&t, 300);
    }
    let (_, diags) = brush(&[request(vec![], 300.0)]);
    assert!(has(&diags, "T0501"), "{:?}", codes(&diags));
}

/// Along a grid line every crossing is a node: each virtual point is one
/// physical actuator at full intensity (β = 0), and the energy model still
/// holds exactly.
#[test]
fn stroke_along_a_grid_line() {
    let (t, diags) = brush(&[request(vec![(0.0, 63.0), (189.0, 63.0)], 1000.0)]);
    let t = t.unwrap_or_else(|| panic!("{:?}", codes(&diags)));
    check_and_play(&t, 1000);
    for p in &t.strokes[0].points {
        let energy: f64 = p.drives.iter().map(|d| (d.intensity as f64).powi(2)).sum();
        assert!((energy - 1.0).abs() < 1e-5, "energy {energy} at ({}, {})", p.x.0, p.y.0);
        assert!((p.y.0 - 63.0).abs() < 1e-4);
    }
    // Actuators at x = 0, 63, 126, 189: four points, one per column.
    assert_eq!(t.strokes[0].points.len(), 4);
}

/// Through a node the row and column crossings coincide: they must not
/// become two points at the same place with a zero interval between them.
#[test]
fn stroke_through_a_grid_node() {
    let (t, diags) = brush(&[request(vec![(0.0, 0.0), (126.0, 126.0)], 1000.0)]);
    let t = t.unwrap_or_else(|| panic!("{:?}", codes(&diags)));
    check_and_play(&t, 1000);
    let pts = &t.strokes[0].points;
    for w in pts.windows(2) {
        let d = ((w[1].x.0 - w[0].x.0) as f64).hypot((w[1].y.0 - w[0].y.0) as f64);
        assert!(d > 1e-3, "two points at the same place: {:?} {:?}", (w[0].x, w[0].y), (w[1].x, w[1].y));
    }
    // The unquantised plan puts the node's peak at exactly half of T (it is half way along).
    let plans = plan_strokes(
        &[request(vec![(0.0, 0.0), (126.0, 126.0)], 1000.0)],
        &profiles::builtin("brush-4x3").expect("profile"),
        &mut Vec::new(),
    );
    let plan = plans[0].as_ref().expect("planned");
    assert!(plan.points.iter().any(|p| (p.peak_ms - 500.0).abs() < 1e-9 && (p.x_mm - 63.0).abs() < 1e-9));
}
