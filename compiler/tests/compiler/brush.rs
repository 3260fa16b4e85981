//! Brushed strokes (issue 5): the Tactile Brush schedule against the worked
//! example and an independent linear solve, the paper's evaluation strokes,
//! the energy model, the stiff case, several strokes, and a property test over
//! random strokes on random grids.

use proptest::prelude::*;
use taxel_compiler::Severity;
use taxel_compiler::brush::{
    BrushRequest, GridGeometry, PlannedPoint, Planner, apparent_motion, compile_strokes, plan_strokes,
};
use taxel_format::{Bundle, Chunk, DeviceProfile, Manifest, StrokeTable, profiles};

fn brush_profile() -> DeviceProfile {
    profiles::builtin("brush-4x3").expect("built-in profile")
}

fn grid_profile(rows: u16, cols: u16, pitch: f32, rate_hz: u32) -> DeviceProfile {
    let mut p = brush_profile();
    p.rows = rows;
    p.cols = cols;
    p.pitch_x_mm = pitch;
    p.pitch_y_mm = pitch;
    p.rate_hz = rate_hz;
    p
}

fn request(polyline: &[(f64, f64)], duration_ms: f64) -> BrushRequest {
    BrushRequest {
        polyline: polyline.to_vec(),
        duration_ms,
        intensity: 1.0,
        freq_hz: 200.0,
        start_ms: None,
        source: None,
        element: "stroke".into(),
        line: Some(3),
    }
}

fn plan_one(profile: &DeviceProfile, req: BrushRequest) -> Vec<PlannedPoint> {
    let mut diags = Vec::new();
    let plans = plan_strokes(&[req], profile, &mut diags);
    assert!(!taxel_compiler::has_errors(&diags), "{diags:?}");
    plans.into_iter().next().flatten().expect("planned").points
}

/// The apparent-motion system of seed 001 for n+1 points, solved as a dense
/// linear system (independently of the compiler's forward recurrence):
/// unknowns d_0..d_n, SOA_0..SOA_(n-1); equations
/// SOA_k = 0.32 d_k + 47.3, d_k = (τ_k − on_k) + (τ_(k+1) − on_(k+1)), d_n = T − on_n,
/// with on_k = SOA_0 + … + SOA_(k−1).
fn solve_linear(tau: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = tau.len() - 1;
    let m = 2 * n + 1; // d: 0..=n, SOA: n+1..=2n
    let soa = |k: usize| n + 1 + k;
    let mut a = vec![vec![0.0; m + 1]; m];
    for k in 0..n {
        // SOA_k − 0.32 d_k = 47.3
        a[k][soa(k)] = 1.0;
        a[k][k] = -0.32;
        a[k][m] = 47.3;
        // d_k + on_k + on_(k+1) = τ_k + τ_(k+1)
        let r = n + k;
        a[r][k] = 1.0;
        for j in 0..k {
            a[r][soa(j)] += 1.0;
        }
        for j in 0..=k {
            a[r][soa(j)] += 1.0;
        }
        a[r][m] = tau[k] + tau[k + 1];
    }
    // d_n + on_n = T
    a[2 * n][n] = 1.0;
    for j in 0..n {
        a[2 * n][soa(j)] = 1.0;
    }
    a[2 * n][m] = tau[n];
    for c in 0..m {
        let p = (c..m).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs())).unwrap();
        a.swap(c, p);
        let pivot = a[c].clone();
        for (r, row) in a.iter_mut().enumerate() {
            if r != c {
                let f = row[c] / pivot[c];
                for (v, p) in row.iter_mut().zip(&pivot).skip(c) {
                    *v -= f * p;
                }
            }
        }
    }
    let x: Vec<f64> = (0..m).map(|i| a[i][m] / a[i][i]).collect();
    let d = x[..=n].to_vec();
    let mut on = vec![0.0];
    for k in 0..n {
        on.push(on[k] + x[soa(k)]);
    }
    (on, d)
}

const WORKED_TAU: [f64; 5] = [0.0, 142.857, 571.429, 750.0, 1000.0];
const WORKED_ONSETS: [f64; 5] = [0.0, 70.465, 245.294, 482.543, 708.659];
const WORKED_DURATIONS: [f64; 5] = [72.392, 398.527, 593.592, 558.798, 291.341];

#[test]
fn worked_example_of_primitives_md_to_a_microsecond() {
    let t = apparent_motion(&WORKED_TAU, 0.0).unwrap();
    for k in 0..5 {
        assert!((t[k].onset_ms - WORKED_ONSETS[k]).abs() <= 1e-3, "onset {k}: {}", t[k].onset_ms);
        assert!((t[k].duration_ms - WORKED_DURATIONS[k]).abs() <= 1e-3, "duration {k}: {}", t[k].duration_ms);
    }
}

#[test]
fn worked_example_through_a_drawn_path() {
    // On a 4-row x 3-column grid of pitch p, the segment from (0, 13/17 p) to
    // (7/4 p, 41/17 p) crosses row 1 at 1/7 of its length, column 1 at 4/7 and
    // row 2 at 3/4: the worked example's peaks for T = 1000 ms.
    let p = 50.0;
    let profile = grid_profile(4, 3, p as f32, 1000);
    let pts = plan_one(&profile, request(&[(0.0, 13.0 / 17.0 * p), (1.75 * p, 41.0 / 17.0 * p)], 1000.0));
    assert_eq!(pts.len(), 5);
    for k in 0..5 {
        assert!((pts[k].onset_ms - WORKED_ONSETS[k]).abs() <= 1e-3, "onset {k}: {}", pts[k].onset_ms);
        assert!((pts[k].duration_ms - WORKED_DURATIONS[k]).abs() <= 1e-3, "duration {k}: {}", pts[k].duration_ms);
    }
    // λ3 would stop at 1041.3 ms; as played every point stops by T.
    assert!((pts[3].end_ms - 1000.0).abs() < 1e-9);
    assert!((pts[1].end_ms - (70.465 + 398.527)).abs() <= 2e-3);
}

#[test]
fn recurrence_matches_a_dense_solve_for_many_points() {
    let tau = [0.0, 120.0, 260.0, 300.0 + 90.0, 610.0, 700.0, 980.0, 1100.0, 1500.0];
    let t = apparent_motion(&tau, 0.0).unwrap();
    let (on, d) = solve_linear(&tau);
    for k in 0..tau.len() {
        assert!((t[k].onset_ms - on[k]).abs() < 1e-9, "onset {k}");
        assert!((t[k].duration_ms - d[k]).abs() < 1e-9, "duration {k}");
    }
    let (on, d) = solve_linear(&WORKED_TAU);
    for k in 0..5 {
        assert!((on[k] - WORKED_ONSETS[k]).abs() <= 1e-3 && (d[k] - WORKED_DURATIONS[k]).abs() <= 1e-3);
    }
}

fn drive_map(p: &PlannedPoint) -> Vec<(u16, f64)> {
    p.drives.as_slice().iter().map(|d| (d.actuator.0, d.intensity)).collect()
}

fn assert_drives(p: &PlannedPoint, want: &[(u16, f64)]) {
    let got = drive_map(p);
    assert_eq!(got.len(), want.len(), "{got:?} vs {want:?}");
    for ((a, x), (b, y)) in got.iter().zip(want) {
        assert_eq!(a, b, "{got:?} vs {want:?}");
        assert!((x - y).abs() < 1e-12, "{got:?} vs {want:?}");
    }
}

#[test]
fn paper_stroke_1_diagonal_with_three_virtual_points_in_the_middle() {
    // Corner actuator (0,0) to corner actuator (2,3) of the 4 x 3 chair.
    let av: f64 = 0.8;
    let mut req = request(&[(0.0, 0.0), (189.0, 126.0)], 1500.0);
    req.intensity = av;
    let pts = plan_one(&brush_profile(), req);
    let xy: Vec<(f64, f64)> = pts.iter().map(|p| (p.x_mm, p.y_mm)).collect();
    assert_eq!(xy, vec![(0.0, 0.0), (63.0, 42.0), (94.5, 63.0), (126.0, 84.0), (189.0, 126.0)]);
    // Ends on physical actuators; the middle three are phantoms of Eq. 4.
    assert_drives(&pts[0], &[(0, av)]);
    assert_drives(&pts[1], &[(1, (1.0f64 / 3.0).sqrt() * av), (5, (2.0f64 / 3.0).sqrt() * av)]);
    assert_drives(&pts[2], &[(5, 0.5f64.sqrt() * av), (6, 0.5f64.sqrt() * av)]);
    assert_drives(&pts[3], &[(6, (2.0f64 / 3.0).sqrt() * av), (10, (1.0f64 / 3.0).sqrt() * av)]);
    assert_drives(&pts[4], &[(11, av)]);
    // Peaks by arc length: the diagonal is 227.15 mm long.
    let len = 189.0f64.hypot(126.0);
    for p in &pts {
        assert!((p.peak_ms - 1500.0 * p.x_mm.hypot(p.y_mm) / len).abs() < 1e-9);
    }
}

#[test]
fn paper_stroke_2_horizontal_from_virtual_to_virtual() {
    // Along row 1 from midway between columns 0 and 1 to midway between 2 and 3.
    let pts = plan_one(&brush_profile(), request(&[(31.5, 63.0), (157.5, 63.0)], 800.0));
    let xy: Vec<(f64, f64)> = pts.iter().map(|p| (p.x_mm, p.y_mm)).collect();
    assert_eq!(xy, vec![(31.5, 63.0), (63.0, 63.0), (126.0, 63.0), (157.5, 63.0)]);
    let h = 0.5f64.sqrt();
    assert_drives(&pts[0], &[(4, h), (5, h)]);
    assert_drives(&pts[1], &[(5, 1.0)]);
    assert_drives(&pts[2], &[(6, 1.0)]);
    assert_drives(&pts[3], &[(6, h), (7, h)]);
    let tau: Vec<f64> = pts.iter().map(|p| p.peak_ms).collect();
    assert_eq!(tau, vec![0.0, 200.0, 600.0, 800.0]);
}

#[test]
fn paper_stroke_3_made_of_virtual_points_only() {
    // Between rows 0 and 1, a quarter of the way down, across the whole chair.
    let pts = plan_one(&brush_profile(), request(&[(0.0, 15.75), (189.0, 15.75)], 1200.0));
    assert_eq!(pts.len(), 4);
    for (c, p) in pts.iter().enumerate() {
        assert_eq!((p.x_mm, p.y_mm), (63.0 * c as f64, 15.75));
        // β = 1/4 towards row 1: A1 = √(3/4), A2 = √(1/4).
        assert_drives(p, &[(c as u16, 0.75f64.sqrt()), (4 + c as u16, 0.5)]);
    }
}

#[test]
fn energy_is_conserved_at_every_virtual_point() {
    let profile = brush_profile();
    let curve: Vec<(f64, f64)> = (0..=40)
        .map(|i| {
            let a = i as f64 / 40.0 * std::f64::consts::TAU;
            (94.5 + 80.0 * a.cos(), 63.0 + 55.0 * a.sin())
        })
        .collect();
    for av in [0.3, 0.77, 1.0] {
        let mut req = request(&curve, 4000.0);
        req.intensity = av;
        let pts = plan_one(&profile, req);
        assert!(pts.len() >= 6, "{}", pts.len());
        for p in &pts {
            let e: f64 = p.drives.as_slice().iter().map(|d| d.intensity * d.intensity).sum();
            assert!((e - av * av).abs() < 1e-8, "{e} vs {}", av * av);
            assert!(p.drives.as_slice().len() <= 4);
        }
    }
}

#[test]
fn fast_stroke_is_resolved_with_a_warning() {
    let profile = brush_profile();
    let mut diags = Vec::new();
    let table = compile_strokes(&[request(&[(0.0, 0.0), (189.0, 126.0)], 100.0)], &profile, &mut diags).unwrap();
    let stiff: Vec<_> = diags.iter().filter(|d| d.code == "T0510").collect();
    assert_eq!(stiff.len(), 1, "{diags:?}");
    assert_eq!(stiff[0].severity, Severity::Warning);
    assert!(stiff[0].message.contains("5 virtual points"), "{}", stiff[0].message);
    assert!(stiff[0].help.as_deref().unwrap_or("").contains("ms"));
    assert_eq!(stiff[0].element.as_deref(), Some("stroke"));
    let s = &table.strokes[0];
    assert!(s.points.len() < 5);
    check_table_invariants(&table, &[100.0], 1000);
    let mut bundle = Bundle::new(Manifest::new(profile));
    bundle.chunks.push(Chunk::Strokes(table));
    assert!(bundle.to_bytes().is_ok());
}

#[test]
fn impossible_stroke_is_an_error_with_the_shortest_duration() {
    let profile = brush_profile();
    let path = [(0.0, 0.0), (189.0, 126.0)];
    let mut diags = Vec::new();
    assert!(compile_strokes(&[request(&path, 30.0)], &profile, &mut diags).is_none());
    let err = diags.iter().find(|d| d.code == "T0511").expect("T0511");
    assert_eq!(err.severity, Severity::Error);
    // Two points need x_1 = (T − 47.3) / 1.32 ≥ one tick (1 ms): T ≥ 48.62 ms.
    let shortest: f64 = err.message.rsplit(' ').nth(1).unwrap().parse().unwrap();
    assert!((shortest - (47.3 + 1.32)).abs() <= 0.011, "{}", err.message);
    let mut ok = Vec::new();
    assert!(compile_strokes(&[request(&path, shortest + 0.001)], &profile, &mut ok).is_some(), "{ok:?}");
    assert!(!taxel_compiler::has_errors(&ok));
    let mut bad = Vec::new();
    assert!(compile_strokes(&[request(&path, shortest - 0.05)], &profile, &mut bad).is_none());
}

#[test]
fn strokes_follow_each_other_or_start_when_told() {
    let profile = brush_profile();
    let mut a = request(&[(0.0, 0.0), (189.0, 0.0)], 700.0);
    a.element = "a".into();
    let mut b = request(&[(0.0, 126.0), (189.0, 126.0)], 300.4);
    b.element = "b".into();
    let mut c = request(&[(0.0, 63.0), (189.0, 63.0)], 500.0);
    c.start_ms = Some(2500.0);
    let d = request(&[(0.0, 0.0), (0.0, 126.0)], 400.0);
    let mut diags = Vec::new();
    let t = compile_strokes(&[a, b, c, d], &profile, &mut diags).unwrap();
    let starts: Vec<u64> = t.strokes.iter().map(|s| s.start.0).collect();
    assert_eq!(starts, vec![0, 700, 2500, 3000]);
    // Consecutive strokes abut: b ends where the next one of the document would start.
    assert_eq!(t.strokes[1].start.0 + t.strokes[1].duration as u64, 1000);
    assert!(!diags.iter().any(|d| d.code == "T0512"), "{diags:?}");
}

#[test]
fn overlapping_strokes_on_one_actuator_are_clamped_with_a_warning() {
    let profile = brush_profile();
    let mut a = request(&[(0.0, 0.0), (189.0, 0.0)], 1000.0);
    a.start_ms = Some(0.0);
    a.element = "first".into();
    let mut b = request(&[(0.0, 0.0), (0.0, 126.0)], 1000.0);
    b.start_ms = Some(0.0);
    b.element = "second".into();
    let mut diags = Vec::new();
    let t = compile_strokes(&[a.clone(), b.clone()], &profile, &mut diags).unwrap();
    assert_eq!(t.strokes.len(), 2);
    let w: Vec<_> = diags.iter().filter(|d| d.code == "T0512").collect();
    assert!(!w.is_empty(), "{diags:?}");
    assert!(w.iter().any(|d| d.message.contains("actuator 0 ") && d.message.contains("#second")), "{w:?}");
    // At half intensity both fit under full energy: no clamping, no warning.
    a.intensity = 0.5;
    b.intensity = 0.5;
    let mut quiet = Vec::new();
    compile_strokes(&[a, b], &profile, &mut quiet).unwrap();
    assert!(!quiet.iter().any(|d| d.code == "T0512"), "{quiet:?}");
}

#[test]
fn one_strokes_own_overlap_is_a_note() {
    // Paper stroke 1 at full intensity: λ1 (2/3 on actuator 5) overlaps λ2 (1/2 on
    // 5 and on 6), which overlaps λ3 (2/3 on 6): 1/2 + 2/3 = 7/6 of full energy.
    let mut diags = Vec::new();
    compile_strokes(&[request(&[(0.0, 0.0), (189.0, 126.0)], 1000.0)], &brush_profile(), &mut diags).unwrap();
    let n: Vec<_> = diags.iter().filter(|d| d.code == "T0515").collect();
    assert_eq!(n.len(), 1, "{diags:?}");
    assert_eq!(n[0].severity, Severity::Note);
    assert!(
        n[0].message.contains("1.17 times")
            && n[0].message.contains("actuators 5 (row 1, column 1), 6 (row 1, column 2)"),
        "{}",
        n[0].message
    );
    assert!(!diags.iter().any(|d| d.severity >= Severity::Warning), "{diags:?}");
}

#[test]
fn odd_paths_are_handled() {
    let profile = brush_profile();
    let mut diags = Vec::new();
    let reqs = [
        request(&[(50.0, 50.0)], 300.0),                                     // a single point
        request(&[(-20.0, 10.0), (250.0, 10.0)], 900.0),                     // leaves the grid
        request(&[(0.0, 0.0), (0.0, 0.0), (63.0, 0.0), (63.0, 0.0)], 600.0), // repeated vertices
    ];
    let t = compile_strokes(&reqs, &profile, &mut diags).unwrap();
    assert_eq!(t.strokes.len(), 3);
    assert!(diags.iter().any(|d| d.code == "T0506"));
    assert!(diags.iter().any(|d| d.code == "T0505" && d.severity == Severity::Warning));
    assert_eq!(t.strokes[0].points.len(), 1);
    assert_eq!(t.strokes[0].points[0].duration, 300);
    assert_eq!(t.strokes[2].points.len(), 2);
    let mut bad = Vec::new();
    let nan = request(&[(0.0, 0.0), (f64::NAN, 1.0)], 300.0);
    assert!(compile_strokes(&[nan, request(&[], 100.0)], &profile, &mut bad).is_none());
    assert_eq!(bad.iter().filter(|d| d.code == "T0501").count(), 2, "{bad:?}");
}

#[test]
fn huge_grids_still_see_one_point_per_actuator_crossed() {
    // 64 x 64 actuators 1 m apart: a diagonal through 64 actuators gives 64 points,
    // each on exactly one actuator, with no stiff-case merging over 60 s.
    let profile = grid_profile(64, 64, 1000.0, 1000);
    let mut diags = Vec::new();
    let plans = plan_strokes(&[request(&[(0.0, 0.0), (63_000.0, 63_000.0)], 60_000.0)], &profile, &mut diags);
    assert!(diags.is_empty(), "{diags:?}");
    let pts = &plans[0].as_ref().unwrap().points;
    assert_eq!(pts.len(), 64);
    for (k, p) in pts.iter().enumerate() {
        assert_eq!(p.drives.as_slice().len(), 1, "point {k}");
        assert_eq!(p.drives.as_slice()[0].actuator.0 as usize, 65 * k);
    }
}

#[test]
fn other_families_leave_strokes_out_with_a_warning() {
    let mut diags = Vec::new();
    let stress = profiles::builtin("stress2").unwrap();
    assert!(compile_strokes(&[request(&[(0.0, 0.0), (10.0, 0.0)], 500.0)], &stress, &mut diags).is_none());
    assert_eq!(diags.len(), 1);
    assert_eq!((diags[0].code, diags[0].severity), ("T0514", Severity::Warning));
}

#[test]
fn planner_reuses_its_buffers() {
    let grid = GridGeometry { rows: 3, cols: 4, pitch_x: 63.0, pitch_y: 63.0 };
    let mut p = Planner::new();
    let a = p.plan(&[(0.0, 0.0), (189.0, 126.0)], 1000.0, 1.0, &grid, 1.0).unwrap();
    let first = p.points().to_vec();
    p.plan(&[(0.0, 0.0), (10.0, 0.0)], 1000.0, 1.0, &grid, 1.0).unwrap();
    assert_eq!(p.points().len(), 2);
    let b = p.plan(&[(0.0, 0.0), (189.0, 126.0)], 1000.0, 1.0, &grid, 1.0).unwrap();
    assert_eq!((a, first), (b, p.points().to_vec()));
}

/// Every property a player relies on, checked on a stroke table.
fn check_table_invariants(table: &StrokeTable, durations_ms: &[f64], rate_hz: u32) {
    for (s, &t_ms) in table.strokes.iter().zip(durations_ms) {
        let t_ticks = t_ms * rate_hz as f64 / 1000.0;
        assert!((s.duration as f64 - t_ticks).abs() <= 1.0, "stroke lasts {} ticks for T = {t_ticks}", s.duration);
        let mut prev_onset = 0;
        let mut last_end = 0;
        for p in &s.points {
            assert!(p.duration >= 1, "duration must be positive");
            assert!(p.onset >= prev_onset, "onsets never decrease");
            assert!(p.onset <= p.peak && p.peak <= p.onset + p.duration);
            assert!(p.onset + p.duration <= s.duration);
            prev_onset = p.onset;
            last_end = last_end.max(p.onset + p.duration);
            for d in &p.drives {
                assert!((0.0..=1.0).contains(&d.intensity));
            }
        }
        assert_eq!(last_end, s.duration, "the stroke's last point ends at T");
    }
}

fn polyline_strategy() -> impl Strategy<Value = Vec<(f64, f64)>> {
    prop::collection::vec((-20.0f64..420.0, -20.0f64..420.0), 1..7)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn random_strokes_give_valid_tables(
        poly in polyline_strategy(),
        duration_ms in 50.0f64..10_000.0,
        rows in 1u16..6,
        cols in 1u16..6,
        pitch in 8.0f32..120.0,
        rate_hz in prop::sample::select(vec![250u32, 1000, 2000, 48_000]),
        intensity in 0.0f64..=1.0,
    ) {
        let profile = grid_profile(rows, cols, pitch, rate_hz);
        let mut req = request(&poly, duration_ms);
        req.intensity = intensity;
        let mut diags = Vec::new();
        match compile_strokes(&[req], &profile, &mut diags) {
            Some(table) => {
                prop_assert!(!taxel_compiler::has_errors(&diags), "{:?}", diags);
                check_table_invariants(&table, &[duration_ms], rate_hz);
                let mut bundle = Bundle::new(Manifest::new(profile));
                bundle.chunks.push(Chunk::Strokes(table));
                prop_assert!(bundle.to_bytes().is_ok());
            }
            None => {
                // Only a stroke shorter than the two-point minimum may fail, and
                // the error says what would work.
                let e = diags.iter().find(|d| d.code == "T0511");
                prop_assert!(e.is_some(), "{:?}", diags);
                let tick = 1000.0 / rate_hz as f64;
                prop_assert!(duration_ms < 47.3 + 1.32 * tick + 0.011);
            }
        }
    }
}
