use super::*;
use resvg::tiny_skia::PathBuilder;

#[test]
fn walked_closes_only_closed_polylines() {
    let pts = vec![(0.0, 0.0), (1.0, 0.0), (1.0, 1.0)];
    let closed = Polyline { points: pts.clone(), closed: true };
    assert_eq!(closed.walked(), vec![(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 0.0)]);
    let open = Polyline { points: pts.clone(), closed: false };
    assert_eq!(open.walked(), pts);
    assert!(Polyline { points: vec![], closed: true }.walked().is_empty());
}

#[test]
fn circle_flattens_within_tolerance() {
    let path = PathBuilder::from_circle(50.0, 50.0, 20.0).unwrap();
    let polys = flatten(&path, Transform::from_scale(0.5, 0.5), 0.001);
    assert_eq!(polys.len(), 1);
    assert!(polys[0].closed);
    // Vertices lie on the circle (centre 25,25, radius 10; tiny-skia's
    // conic-to-quad circle is itself within ~1e-4 of exact) and chords stay close.
    for (a, b) in polys[0].segments() {
        let mid = ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
        assert!((dist(a, (25.0, 25.0)) - 10.0).abs() < 2e-3);
        assert!((dist(mid, (25.0, 25.0)) - 10.0).abs() < 3e-3);
    }
    let exact = 2.0 * core::f64::consts::PI * 10.0;
    assert!((polys[0].length() - exact).abs() / exact < 1e-3);
}

/// The cubic that usvg (kurbo) writes for an arc of `sweep` radians round
/// `c`, radius `r`, from angle `a0`: handles tangent, `4/3 tan(sweep / 4) r` long.
pub(crate) fn arc_cubic(pb: &mut PathBuilder, c: (f64, f64), r: f64, a0: f64, sweep: f64) {
    let arm = 4.0 / 3.0 * (sweep / 4.0).tan() * r;
    let at = |a: f64| (c.0 + r * a.cos(), c.1 + r * a.sin());
    let (p0, p3) = (at(a0), at(a0 + sweep));
    let (t0, t3) = ((-a0.sin(), a0.cos()), (-(a0 + sweep).sin(), (a0 + sweep).cos()));
    let c1 = (p0.0 + arm * t0.0, p0.1 + arm * t0.1);
    let c2 = (p3.0 - arm * t3.0, p3.1 - arm * t3.1);
    pb.cubic_to(c1.0 as f32, c1.1 as f32, c2.0 as f32, c2.1 as f32, p3.0 as f32, p3.1 as f32);
}

/// A circle as usvg writes it (four cubic arcs, each up to 0.027 % of the
/// radius off the circle) is flattened on the circle: every vertex on it
/// within the `f32` rounding of the path's points (where the Bézier is up
/// to 4 µm off a 15 mm circle), every chord within the tolerance of it.
/// Arcs of other sweeps, either way round and scaled by the transform, too.
#[test]
fn circular_arcs_are_flattened_on_their_circle() {
    let (c, r) = ((55.0, 30.0), 15.0);
    for (sweep, parts) in [(std::f64::consts::FRAC_PI_2, 4), (-std::f64::consts::FRAC_PI_2, 4), (0.3, 5), (2.5, 2)] {
        let mut pb = PathBuilder::new();
        pb.move_to((c.0 + r) as f32, c.1 as f32);
        for k in 0..parts {
            arc_cubic(&mut pb, c, r, k as f64 * sweep, sweep);
        }
        let path = pb.finish().unwrap();
        for (scale, tol) in [(1.0, FLATTEN_TOLERANCE_MM), (0.5, 1e-6)] {
            let ts = Transform::from_scale(scale, scale);
            let (cs, rs) = ((c.0 * scale as f64, c.1 * scale as f64), r * scale as f64);
            let pl = &flatten_with(&path, ts, Flattening { curves: FLATTEN_TOLERANCE_MM, arcs: tol })[0];
            for &p in &pl.points {
                assert!((dist(p, cs) - rs).abs() < 2e-5, "sweep {sweep}: {p:?} is {} off", dist(p, cs) - rs);
            }
            for (a, b) in pl.segments().take(pl.points.len() - 1) {
                let mid = ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
                assert!(rs - dist(mid, cs) <= tol + 2e-5, "sweep {sweep}: a chord {} inside", rs - dist(mid, cs));
            }
            // Not many more chords than the tolerance needs.
            let needed = (sweep.abs() * parts as f64 / (2.0 * (1.0 - tol / rs).acos())).ceil();
            assert!(pl.points.len() as f64 <= needed + 2.0 * parts as f64, "{} points for {needed}", pl.points.len());
        }
    }
}

/// A cubic that is not a circular arc's (an ellipse's quarter, handles of
/// unequal length) is flattened as the cubic it is.
#[test]
fn other_cubics_are_not_taken_for_arcs() {
    assert!(circular_arc((10.0, 0.0), (10.0, 2.761), (5.523, 5.0), (0.0, 5.0)).is_none());
    assert!(circular_arc((10.0, 0.0), (10.0, 5.523), (4.0, 10.0), (0.0, 10.0)).is_none());
    let k = 4.0 / 3.0 * (std::f64::consts::FRAC_PI_8).tan() * 10.0;
    let arc = circular_arc((10.0, 0.0), (10.0, k), (k, 10.0), (0.0, 10.0)).expect("a quarter circle");
    assert!(dist(arc.centre, (0.0, 0.0)) < 1e-9 && (arc.radius - 10.0).abs() < 1e-9, "{arc:?}");
    assert!((arc.sweep - std::f64::consts::FRAC_PI_2).abs() < 1e-9, "{arc:?}");
}

#[test]
fn simplify_keeps_every_point_within_tolerance() {
    // A small circle as the fields flatten it: many more sides than a
    // 2 um tolerance needs.
    let path = PathBuilder::from_circle(0.0, 0.0, 0.7).unwrap();
    let ring = &flatten(&path, Transform::identity(), FLATTEN_TOLERANCE_MM)[0];
    for tol in [0.002, 0.01, 0.05] {
        let kept = simplify(&ring.points, true, tol);
        assert!(kept.len() < ring.points.len(), "tolerance {tol}: nothing dropped");
        assert!(kept.len() >= 3, "tolerance {tol}: the ring collapsed");
        let out = Polyline { points: kept, closed: true };
        for &p in &ring.points {
            let d = out.segments().map(|(a, b)| distance_to_segment(p, a, b)).fold(f64::INFINITY, f64::min);
            assert!(d <= tol + 1e-12, "tolerance {tol}: {p:?} is {d} from the simplified ring");
        }
    }
    // Collinear points go, corners stay.
    let l = [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (2.0, 1.0), (2.0, 2.0)];
    assert_eq!(simplify(&l, false, 0.001), vec![(0.0, 0.0), (2.0, 0.0), (2.0, 2.0)]);
}

/// [`thin`] keeps every dropped point within the tolerance of the chord
/// between the kept points either side of it (so of the result), keeps a
/// ring's first point and both ends of a line, keeps the points in order,
/// and leaves alone a ring it would collapse. A spiral, Douglas–Peucker's
/// quadratic case, is thinned in windows like any curve.
#[test]
fn thin_keeps_every_dropped_point_within_tolerance_of_its_chord() {
    let spiral: Vec<(f64, f64)> = (0..5_000)
        .map(|i| (i as f64 * 0.01, 0.002 + i as f64 * 1e-4))
        .map(|(a, r)| (r * a.cos(), r * a.sin()))
        .collect();
    let wiggle: Vec<(f64, f64)> = (0..1_000)
        .map(|i| std::f64::consts::TAU * i as f64 / 1_000.0)
        .map(|a| (10.0 * a.cos() + 0.003 * (37.0 * a).sin(), 7.0 * a.sin()))
        .collect();
    for (points, closed) in [(&spiral, false), (&wiggle, true), (&wiggle, false)] {
        for tol in [0.0005, 0.002, 0.05] {
            let kept = thin(points, closed, tol);
            assert!(kept.len() < points.len(), "tolerance {tol}: nothing dropped");
            assert_eq!(kept[0], points[0]);
            if !closed {
                assert_eq!(kept.last(), points.last());
            }
            // Each kept point's position in `points`, in order.
            let mut at = Vec::new();
            let mut i = 0;
            for k in &kept {
                while points[i] != *k {
                    i += 1;
                }
                at.push(i);
            }
            if closed {
                at.push(points.len());
            }
            for w in at.windows(2) {
                let (a, b) = (points[w[0]], points[w[1] % points.len()]);
                for &p in &points[w[0] + 1..w[1]] {
                    let d = distance_to_segment(p, a, b);
                    assert!(d <= tol + 1e-12, "tolerance {tol}: {p:?} is {d} from its chord");
                }
            }
        }
    }
    // A ring smaller than the tolerance is kept whole, a tolerance of 0 or
    // none changes nothing.
    let speck = [(0.0, 0.0), (1e-4, 0.0), (1e-4, 1e-4), (5e-5, 1.2e-4), (0.0, 1e-4)];
    assert_eq!(thin(&speck, true, 0.01), speck.to_vec());
    assert_eq!(thin(&wiggle, true, 0.0), wiggle);
    assert_eq!(thin(&wiggle, true, f64::NAN), wiggle);
}

/// Douglas–Peucker as it was written before [`Farthest`]: `hypot` for
/// every point, `max_by` over `total_cmp` for a ring's split.
fn simplify_measuring_every_point(points: &[(f64, f64)], closed: bool, tol: f64) -> Vec<(f64, f64)> {
    if points.len() <= 3 {
        return points.to_vec();
    }
    let mut keep = vec![false; points.len()];
    let last = points.len() - 1;
    keep[0] = true;
    keep[last] = true;
    let mut stack = vec![(0usize, last)];
    if closed {
        let far = (1..points.len())
            .max_by(|&a, &b| dist(points[0], points[a]).total_cmp(&dist(points[0], points[b])))
            .unwrap_or(last);
        keep[far] = true;
        stack = vec![(0, far), (far, last)];
    }
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        let (mut worst, mut at) = (0.0, a);
        for i in a + 1..b {
            let d = distance_to_segment(points[i], points[a], points[b]);
            if d > worst {
                (worst, at) = (d, i);
            }
        }
        if worst > tol {
            keep[at] = true;
            stack.push((a, at));
            stack.push((at, b));
        }
    }
    points.iter().zip(keep).filter(|(_, k)| *k).map(|(p, _)| *p).collect()
}

/// A xorshift generator of uniform numbers in [0, 1) from `seed`.
fn uniform(mut state: u64) -> impl FnMut() -> f64 {
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn simplify_keeps_the_points_that_measuring_every_point_keeps() {
    let mut next = uniform(0x9e37_79b9_7f4a_7c15u64);
    let mut cases: Vec<Vec<(f64, f64)>> = Vec::new();
    for k in 0..300 {
        let n = 4 + (next() * 400.0) as usize;
        let scale = [1e-3, 1.0, 300.0, 1e20, 1e150, 1e-150][k % 6];
        let pts: Vec<(f64, f64)> = match k % 4 {
            // Random walks.
            0 => {
                let mut p = (0.0, 0.0);
                (0..n)
                    .map(|_| {
                        p = (p.0 + (next() - 0.5) * scale, p.1 + (next() - 0.5) * scale);
                        p
                    })
                    .collect()
            }
            // Flattened arcs: the farthest point moves at almost every step.
            1 => (0..n)
                .map(|i| {
                    let t = i as f64 / n as f64 * 6.0;
                    (scale * t.cos() + next() * scale * 1e-6, scale * t.sin())
                })
                .collect(),
            // Lattice points: many equal distances, so ties decide.
            2 => (0..n).map(|_| ((next() * 8.0).floor() * scale, (next() * 8.0).floor() * scale)).collect(),
            // Nearly collinear points, within rounding of the chord.
            _ => (0..n).map(|i| (i as f64 * scale, (i as f64 * scale) * (1.0 + next() * 1e-15))).collect(),
        };
        cases.push(pts);
    }
    for (k, pts) in cases.iter().enumerate() {
        for closed in [false, true] {
            for tol in [0.0, 0.002, 0.05, 1e-3 * pts[1].0.abs().max(1e-300)] {
                assert_eq!(
                    simplify(pts, closed, tol),
                    simplify_measuring_every_point(pts, closed, tol),
                    "case {k}, closed {closed}, tolerance {tol}"
                );
            }
        }
    }
}

/// Offsets `(a, b)` whose squares order them one way and whose `hypot`
/// the other (`a`'s square above `b`'s, `a` nearer): a few ulps apart.
fn squares_and_hypot_disagree() -> Vec<((f64, f64), (f64, f64))> {
    let mut next = uniform(0x853c_49e6_748f_ea9bu64);
    let ulps = |v: f64, k: i64| f64::from_bits((v.to_bits() as i64 + k) as u64);
    let mut out = Vec::new();
    while out.len() < 40 {
        let base = (0.5 + 3.0 * next(), 0.5 + 3.0 * next());
        let near: Vec<(f64, f64)> = (0..144).map(|k| (ulps(base.0, k % 12 - 6), ulps(base.1, 6 - k / 12))).collect();
        for &a in &near {
            if let Some(&b) =
                near.iter().find(|b| a.0 * a.0 + a.1 * a.1 > b.0 * b.0 + b.1 * b.1 && a.0.hypot(a.1) < b.0.hypot(b.1))
            {
                out.push((a, b));
                break;
            }
        }
    }
    out
}

#[test]
fn simplify_measures_where_squares_and_hypot_disagree() {
    for (a, b) in squares_and_hypot_disagree() {
        // A ring split at the point farthest from its first: `b`, though
        // `a`'s square is larger (offsets from (0, 0) are exact).
        let ring = [(0.0, 0.0), (-a.0, -a.1), (1e-3, 0.0), (-b.0, -b.1), (2e-3, 0.0)];
        // An open path back to its start: each point's offset from the
        // chord is the point itself. `b` lies farther than `a`'s distance.
        let there_and_back = [(0.0, 0.0), b, (1e-9, 0.0), (0.0, 0.0)];
        for (pts, closed, tol) in
            [(&ring[..], true, 1e9), (&ring[..], true, 0.0), (&there_and_back[..], false, a.0.hypot(a.1))]
        {
            assert_eq!(
                simplify(pts, closed, tol),
                simplify_measuring_every_point(pts, closed, tol),
                "{a:?} {b:?}, closed {closed}, tolerance {tol}"
            );
        }
    }
}

#[test]
fn even_odd_and_nonzero_differ_for_a_doubled_square() {
    let sq = Polyline { points: vec![(0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0)], closed: true };
    let polys = vec![sq.clone(), sq];
    assert!(contains(&polys, (2.0, 2.0), FillRule::NonZero));
    assert!(!contains(&polys, (2.0, 2.0), FillRule::EvenOdd));
}

#[test]
fn crossing_segments_have_zero_distance() {
    assert_eq!(segment_distance((0.0, 0.0), (2.0, 2.0), (0.0, 2.0), (2.0, 0.0)), 0.0);
    assert!((segment_distance((0.0, 0.0), (1.0, 0.0), (0.0, 3.0), (1.0, 3.0)) - 3.0).abs() < 1e-12);
}

#[test]
fn points_at_walks_arc_length() {
    let pl = Polyline { points: vec![(0.0, 0.0), (10.0, 0.0), (10.0, 10.0)], closed: false };
    let p = points_at(&pl, &[0.0, 5.0, 15.0, 20.0]);
    assert_eq!(p, vec![(0.0, 0.0), (5.0, 0.0), (10.0, 5.0), (10.0, 10.0)]);
}

#[test]
fn distance_within_a_reach_is_the_full_distance_to_the_bit() {
    // Random closed and open walks and points around them (a linear congruential sequence).
    let mut s = 7u64;
    let mut next = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 33) as f64 / (1u64 << 31) as f64
    };
    let (mut within, mut stopped_early) = (0, 0);
    for k in 0..200 {
        let n = 2 + k % 40;
        let (mut x, mut y) = (next() * 20.0, next() * 20.0);
        let points: Vec<_> = (0..n)
            .map(|_| {
                x += (next() - 0.5) * 3.0;
                y += (next() - 0.5) * 3.0;
                (x, y)
            })
            .collect();
        let polys = vec![Polyline { points, closed: k % 2 == 0 }];
        let p = (next() * 24.0 - 2.0, next() * 24.0 - 2.0);
        let full = distance_to_outline(&polys, p);
        for reach in [0.0, 0.5, 2.0, 8.0, f64::INFINITY] {
            let d = distance_to_outline_within(&polys, p, reach, f64::NEG_INFINITY);
            if full <= reach {
                within += 1;
                assert_eq!(d.to_bits(), full.to_bits(), "walk {k}, reach {reach}");
            } else {
                assert!(d > reach, "walk {k}, reach {reach}: {d}, full {full}");
            }
            // Stopping at 1 mm: some value at or below it when the
            // outline comes that close within the reach, the same value
            // as without stopping when it does not come that close.
            let stopped = distance_to_outline_within(&polys, p, reach, 1.0);
            if full <= reach.min(1.0) {
                stopped_early += 1;
                assert!(stopped <= 1.0, "walk {k}, reach {reach}: {stopped}, full {full}");
            } else if full > 1.0 {
                assert_eq!(stopped.to_bits(), d.to_bits(), "walk {k}, reach {reach}");
            } else {
                assert!(stopped > reach, "walk {k}, reach {reach}: {stopped}, full {full}");
            }
        }
    }
    assert!(within > 300, "only {within} within reach");
    assert!(stopped_early > 30, "only {stopped_early} stopped early");
    assert_eq!(distance_to_outline_within(&[], (0.0, 0.0), 1.0, 0.0), f64::INFINITY);
}

/// `deep_inside` is `contains` and `distance_to_outline_within` together, on
/// random rings (self-crossing, open and closed, several subpaths), at
/// points near and away from the sides.
#[test]
fn deep_inside_agrees_with_contains_and_distance() {
    use proptest::prelude::*;
    use proptest::test_runner::{Config, TestRunner};
    let point = || (-5.0..15.0f64, -5.0..15.0f64);
    let ring =
        (prop::collection::vec(point(), 1..12), any::<bool>()).prop_map(|(points, closed)| Polyline { points, closed });
    let case = (prop::collection::vec(ring, 1..4), prop::collection::vec(point(), 1..40), 0.0..3.0f64);
    TestRunner::new(Config { cases: 400, ..Config::default() })
        .run(&case, |(polys, points, margin)| {
            // Points on the sides and at the vertices too, where the margin decides.
            let on: Vec<(f64, f64)> = polys
                .iter()
                .flat_map(|p| p.segments())
                .flat_map(|(a, b)| [a, ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0)])
                .collect();
            for &p in points.iter().chain(&on) {
                for rule in [FillRule::NonZero, FillRule::EvenOdd] {
                    let want =
                        contains(&polys, p, rule) && distance_to_outline_within(&polys, p, margin, margin) > margin;
                    prop_assert_eq!(deep_inside(&polys, p, rule, margin), want, "{:?} {:?} {}", p, rule, margin);
                }
            }
            Ok(())
        })
        .unwrap();
}

/// `SideRows::deep_inside` answers as `deep_inside` reading every side, on
/// outlines of many sides (many strips), self-crossing and open ones too,
/// at points near the sides, at the strips' edges and off the outline.
#[test]
fn filed_sides_answer_as_every_side() {
    use proptest::prelude::*;
    use proptest::test_runner::{Config, TestRunner};
    let point = || (-5.0..15.0f64, -5.0..15.0f64);
    let ring = (prop::collection::vec(point(), 1..300), any::<bool>())
        .prop_map(|(points, closed)| Polyline { points, closed });
    let case = (prop::collection::vec(ring, 1..4), prop::collection::vec(point(), 1..40), 0.0..2.0f64);
    TestRunner::new(Config { cases: 200, ..Config::default() })
        .run(&case, |(polys, points, margin)| {
            let rows = SideRows::new(&polys).expect("finite");
            let on: Vec<(f64, f64)> = polys
                .iter()
                .flat_map(|p| p.segments())
                .flat_map(|(a, b)| [a, ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0), (a.0 - 0.3, b.1)])
                .collect();
            for &p in points.iter().chain(&on) {
                for rule in [FillRule::NonZero, FillRule::EvenOdd] {
                    let want = deep_inside(&polys, p, rule, margin);
                    prop_assert_eq!(rows.deep_inside(p, rule, margin), want, "{:?} {:?} {}", p, rule, margin);
                }
            }
            Ok(())
        })
        .unwrap();
    // A level outline (one height) and an empty one.
    let flat = [Polyline { points: vec![(0.0, 1.0), (5.0, 1.0), (9.0, 1.0)], closed: true }];
    let rows = SideRows::new(&flat).expect("finite");
    assert!(!rows.deep_inside((4.0, 1.0), FillRule::NonZero, 0.0));
    assert!(!SideRows::new(&[] as &[Polyline]).expect("finite").deep_inside((0.0, 0.0), FillRule::EvenOdd, 0.1));
}
