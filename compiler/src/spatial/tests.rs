//! Tests of the spatial indexes and the outline distances against
//! all-pairs scans.

use super::outline_set::{RUNS_FROM, TREE_ABOVE, segment_distance};
use super::*;

/// The pairs an all-pairs scan finds, the reference the index must match.
fn brute(boxes: &[Bbox], m: f64) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for i in 0..boxes.len() {
        for j in i + 1..boxes.len() {
            if usable(boxes[i]) && usable(boxes[j]) && meet(grow(boxes[i], m), boxes[j]) {
                out.push((i, j));
            }
        }
    }
    out
}

#[test]
fn near_pairs_match_an_all_pairs_scan() {
    // A deterministic scatter of boxes of mixed sizes (a linear congruential sequence).
    let mut s = 12345u64;
    let mut next = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 33) as f64 / (1u64 << 31) as f64
    };
    let boxes: Vec<Bbox> = (0..400)
        .map(|_| {
            let (x, y, w, h) = (next() * 200.0, next() * 100.0, next() * 8.0, next() * 8.0);
            (x, y, x + w, y + h)
        })
        .chain([(f64::NAN, 0.0, 1.0, 1.0), (5.0, 5.0, 4.0, 4.0)])
        .collect();
    for m in [0.0, 1.0, 3.2, 10.0] {
        assert_eq!(near_pairs(&boxes, m), brute(&boxes, m), "margin {m}");
    }
}

#[test]
fn meeting_groups_are_the_boxes_joined_through_every_meeting_pair() {
    let mut s = 777u64;
    let mut next = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 33) as f64 / (1u64 << 31) as f64
    };
    let boxes: Vec<Bbox> = (0..300)
        .map(|_| {
            let (x, y, w, h) = (next() * 200.0, next() * 100.0, next() * 6.0, next() * 6.0);
            (x, y, x + w, y + h)
        })
        .chain([(f64::NAN, 0.0, 1.0, 1.0), (5.0, 5.0, 4.0, 4.0), (300.0, 0.0, 301.0, 1.0), (301.0, 0.0, 302.0, 1.0)])
        .collect();
    // The reference: a label per box, spread along every meeting pair until
    // nothing changes (the lowest position of its group).
    let mut label: Vec<usize> = (0..boxes.len()).collect();
    let pairs = brute(&boxes, 0.0);
    loop {
        let mut changed = false;
        for &(i, j) in &pairs {
            let l = label[i].min(label[j]);
            for k in [i, j] {
                changed |= label[k] != l;
                label[k] = l;
            }
        }
        if !changed {
            break;
        }
    }
    let groups = meeting_groups(&boxes);
    let mut seen = vec![false; boxes.len()];
    let mut firsts = Vec::new();
    for g in &groups {
        assert!(g.windows(2).all(|w| w[0] < w[1]), "positions in order: {g:?}");
        assert!(g.iter().all(|&k| label[k] == g[0]), "one group per label: {g:?}");
        assert_eq!(label.iter().filter(|&&l| l == g[0]).count(), g.len(), "the whole label in the group");
        for &k in g {
            assert!(!std::mem::replace(&mut seen[k], true), "box {k} in two groups");
        }
        firsts.push(g[0]);
    }
    assert!(seen.iter().all(|&s| s), "every box in a group");
    assert!(firsts.windows(2).all(|w| w[0] < w[1]), "groups in the order of their first boxes");
    // Touching edges join; the inverted and the non-finite box stand alone.
    let at = |k: usize| groups.iter().position(|g| g.contains(&k)).expect("grouped");
    let n = boxes.len();
    assert_eq!(at(n - 1), at(n - 2), "boxes that touch are one group");
    assert_eq!(groups[at(n - 3)], vec![n - 3]);
    assert_eq!(groups[at(n - 4)], vec![n - 4]);
    assert!(groups.len() > 10 && groups.iter().any(|g| g.len() > 3), "a scatter with groups of every size");
}

fn square(x: f64, y: f64, s: f64, n: usize) -> Vec<Polyline> {
    // A square with `n` vertices per side, so that the tree path is taken for large n.
    let mut pts = Vec::new();
    for k in 0..n {
        pts.push((x + s * k as f64 / n as f64, y));
    }
    for k in 0..n {
        pts.push((x + s, y + s * k as f64 / n as f64));
    }
    for k in 0..n {
        pts.push((x + s - s * k as f64 / n as f64, y + s));
    }
    for k in 0..n {
        pts.push((x, y + s - s * k as f64 / n as f64));
    }
    vec![Polyline { points: pts, closed: true }]
}

#[test]
fn the_fast_segment_distance_agrees_with_the_geometry_module() {
    let mut s = 99u64;
    let mut next = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 33) as f64 / (1u64 << 31) as f64 * 20.0
    };
    for _ in 0..2000 {
        let (a0, a1, b0, b1) = ((next(), next()), (next(), next()), (next(), next()), (next(), next()));
        let (fast, slow) = (segment_distance(a0, a1, b0, b1), crate::geometry::segment_distance(a0, a1, b0, b1));
        assert!((fast - slow).abs() < 1e-9, "{a0:?} {a1:?} {b0:?} {b1:?}: {fast} vs {slow}");
    }
}

/// A random-walk outline of `n` segments from `(x, y)`, closed or open.
fn walk(next: &mut impl FnMut() -> f64, x: f64, y: f64, n: usize, step: f64) -> Vec<Polyline> {
    let (mut x, mut y) = (x, y);
    let mut points = vec![(x, y)];
    for _ in 0..n {
        x += (next() - 0.5) * step;
        y += (next() - 0.5) * step;
        points.push((x, y));
    }
    vec![Polyline { points, closed: n.is_multiple_of(3) }]
}

#[test]
fn prepared_outline_distances_are_those_of_every_segment_pair() {
    let mut s = 4242u64;
    let mut next = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 33) as f64 / (1u64 << 31) as f64
    };
    // Short ways and long borders (above the tree threshold), packed so that many cross.
    let outlines: Vec<Vec<Polyline>> = (0..60)
        .map(|k| {
            let n = if k % 5 == 0 { 150 + k } else { 1 + k % 17 };
            let (x, y) = (next() * 30.0, next() * 30.0);
            walk(&mut next, x, y, n, if n > 100 { 1.5 } else { 4.0 })
        })
        .chain([vec![], vec![Polyline { points: vec![(3.0, 3.0)], closed: false }]])
        .collect();
    let set = OutlineSet::new(outlines.iter().map(Vec::as_slice));
    assert_eq!(set.len(), outlines.len());
    let mut within = 0;
    for i in 0..outlines.len() {
        for j in 0..outlines.len() {
            let exact = all_pairs_distance(&outlines[i], &outlines[j]);
            for reach in [0.5, 3.2, 10.0] {
                let d = set.distance(i, j, reach, 0.0);
                if exact <= reach {
                    within += 1;
                    assert_eq!(d, exact, "{i} {j} reach {reach}");
                } else {
                    assert!(d > reach, "{i} {j} reach {reach}: {d}, exact {exact}");
                }
                let old = min_outline_distance(&outlines[i], &outlines[j], reach, 0.0);
                assert_eq!(old <= reach, d <= reach, "{i} {j} reach {reach}");
                if exact <= reach {
                    assert_eq!(old, d);
                }
                // Stopping early at 1 mm: some value at or below it when
                // the outlines come that close, the exact distance otherwise.
                let stop = set.distance(i, j, reach, 1.0);
                if exact <= reach.min(1.0) {
                    assert!(stop <= 1.0, "{i} {j} reach {reach}: {stop}, exact {exact}");
                } else if exact > 1.0 {
                    assert!(stop > 1.0 && (exact > reach || stop == exact), "{i} {j} reach {reach}: {stop}");
                }
            }
        }
    }
    assert!(within > 1000, "only {within} pairs within reach");
    assert_eq!(set.distance(0, 999, 10.0, 0.0), f64::INFINITY);
}

/// The exact distance between two outlines: every pair of segments.
fn all_pairs_distance(a: &[Polyline], b: &[Polyline]) -> f64 {
    a.iter()
        .flat_map(|p| p.segments())
        .flat_map(|s| b.iter().flat_map(|p| p.segments()).map(move |t| (s, t)))
        .map(|(s, t)| segment_distance(s.0, s.1, t.0, t.1))
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn outlines_of_up_to_64_sides_measured_by_runs_are_exact() {
    // Random walks of 20 to 64 segments (no tree; most pairs past
    // `RUNS_FROM`), some short and packed, some spread out.
    let mut s = 777u64;
    let mut next = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 33) as f64 / (1u64 << 31) as f64
    };
    let outlines: Vec<Vec<Polyline>> = (0..40)
        .map(|k| {
            let n = 20 + (k * 7) % 45;
            let (x, y) = (next() * 12.0, next() * 12.0);
            walk(&mut next, x, y, n, if k % 2 == 0 { 0.6 } else { 2.0 })
        })
        .collect();
    let set = OutlineSet::new(outlines.iter().map(Vec::as_slice));
    let (mut runs, mut within) = (0, 0);
    for i in 0..outlines.len() {
        for j in 0..outlines.len() {
            let (ni, nj) = (set.segments(i).len(), set.segments(j).len());
            assert!(ni <= TREE_ABOVE && nj <= TREE_ABOVE);
            runs += usize::from(ni * nj >= RUNS_FROM);
            let exact = all_pairs_distance(&outlines[i], &outlines[j]);
            for reach in [0.05, 0.5, 3.2] {
                let d = set.distance(i, j, reach, 0.0);
                if exact <= reach {
                    within += 1;
                    assert_eq!(d, exact, "{i} {j} reach {reach}");
                } else {
                    assert!(d > reach, "{i} {j} reach {reach}: {d}, exact {exact}");
                }
                let stop = set.distance(i, j, reach, 0.3);
                if exact <= reach.min(0.3) {
                    assert!(stop <= 0.3, "{i} {j} reach {reach}: {stop}, exact {exact}");
                } else if exact > 0.3 {
                    assert!(stop > 0.3 && (exact > reach || stop == exact), "{i} {j} reach {reach}: {stop}");
                }
            }
        }
    }
    assert!(runs > 1000 && within > 1000, "{runs} pairs by runs, {within} within reach");
}

/// Trees are built only for the outlines a distance searches through one
/// (issue 46: building every long outline's tree up front cost more than
/// the searches), and the distances are the all-pairs scan's either way.
#[test]
fn outline_trees_are_built_when_first_searched() {
    // Two long wiggly borders side by side 0.2 mm apart (each far above
    // `TREE_ABOVE` segments, so their near parts exceed 4,096 pairs), and a
    // long outline far from both.
    let border = |y: f64, n: usize| {
        vec![Polyline {
            points: (0..n).map(|k| (k as f64 * 0.1, y + 0.03 * ((k * 7 % 5) as f64))).collect(),
            closed: false,
        }]
    };
    let outlines = [border(0.0, 300), border(0.32, 300), border(50.0, 300)];
    let set = OutlineSet::new(outlines.iter().map(Vec::as_slice));
    let built = |set: &OutlineSet| set.trees_built().iter().filter(|&&b| b).count();
    assert_eq!(built(&set), 0, "no tree before a search");
    for (i, j) in [(0, 1), (1, 0), (0, 2)] {
        let exact = all_pairs_distance(&outlines[i], &outlines[j]);
        let d = set.distance(i, j, 3.2, 0.0);
        if exact <= 3.2 {
            assert_eq!(d, exact, "{i} {j}");
        } else {
            assert!(d > 3.2, "{i} {j}: {d}");
        }
    }
    assert!((1..=2).contains(&built(&set)), "{} trees built", built(&set));
    assert!(!set.trees_built()[2], "the far outline's tree was built");

    // A short outline (an island) beside a long one (a coast): the short
    // one is walked through the long one's tree, whichever is asked first,
    // and the distance is exact.
    let island = vec![Polyline { points: vec![(10.0, 0.5), (10.4, 0.6), (10.2, 0.9)], closed: true }];
    let outlines = [border(0.0, 300), island];
    for (i, j) in [(0, 1), (1, 0)] {
        let set = OutlineSet::new(outlines.iter().map(Vec::as_slice));
        let exact = all_pairs_distance(&outlines[i], &outlines[j]);
        assert_eq!(set.distance(i, j, 3.2, 0.0), exact, "{i} {j}");
        assert_eq!(set.trees_built(), vec![true, false], "{i} {j}");
    }
}

#[test]
fn shared_vertices_are_those_an_all_pairs_scan_finds_and_touch() {
    // Squares on a grid of spacing 1 with sides of 1 (sharing corners
    // and sides with their neighbours) or 0.5 (sharing nothing), plus
    // an open line and a one-point outline through a grid corner.
    let mut outlines: Vec<Vec<Polyline>> = Vec::new();
    for k in 0..36 {
        let (x, y) = ((k % 6) as f64, (k / 6) as f64);
        let side = if k % 5 == 0 { 0.5 } else { 1.0 };
        let points = vec![(x, y), (x + side, y), (x + side, y + side), (x, y + side)];
        outlines.push(vec![Polyline { points, closed: true }]);
    }
    outlines.push(vec![Polyline { points: vec![(-0.0, 0.0), (-3.0, 0.5)], closed: false }]);
    outlines.push(vec![Polyline { points: vec![(2.0, 2.0)], closed: false }]);
    let refs: Vec<&[Polyline]> = outlines.iter().map(Vec::as_slice).collect();
    let shared = SharedVertices::new(&refs);
    assert!(shared.sanity_check());
    let on_segments = |o: &[Polyline]| -> Vec<(f64, f64)> {
        o.iter().filter(|p| p.points.len() >= 2).flat_map(|p| p.points.clone()).collect()
    };
    let mut pairs = 0;
    for i in 0..outlines.len() {
        for j in 0..outlines.len() {
            let brute =
                i != j && on_segments(&outlines[i]).iter().any(|a| on_segments(&outlines[j]).iter().any(|b| a == b));
            assert_eq!(shared.share(i, j), brute, "{i} {j}");
            if brute {
                pairs += 1;
                assert_eq!(min_outline_distance(&outlines[i], &outlines[j], 1.0, -1.0), 0.0, "{i} {j}");
            }
        }
    }
    assert!(pairs > 100, "only {pairs} pairs share a vertex");
    // Through one point of more outlines than are listed: none listed.
    let star: Vec<Vec<Polyline>> = (0..=SharedVertices::MAX_AT_ONE_POINT)
        .map(|k| vec![Polyline { points: vec![(0.0, 0.0), (1.0, k as f64)], closed: false }])
        .collect();
    let refs: Vec<&[Polyline]> = star.iter().map(Vec::as_slice).collect();
    assert!(!SharedVertices::new(&refs).share(0, 1));
    assert!(SharedVertices::new(&refs[..2]).share(0, 1));
    // An outline through the point twice (two subpaths) counts once.
    let mut star = star;
    star.truncate(SharedVertices::MAX_AT_ONE_POINT);
    star[3].push(Polyline { points: vec![(0.0, 0.0), (-1.0, 2.0)], closed: false });
    let refs: Vec<&[Polyline]> = star.iter().map(Vec::as_slice).collect();
    let shared = SharedVertices::new(&refs);
    assert!(shared.share(0, 1) && shared.share(3, 15) && shared.sanity_check());
}

#[test]
fn outline_distance_is_exact_with_and_without_the_tree() {
    for n in [1, 4, 200] {
        // Two 10 mm squares 2.5 mm apart side by side.
        let d = min_outline_distance(&square(0.0, 0.0, 10.0, n), &square(12.5, 3.0, 10.0, n), 10.0, 0.0);
        assert!((d - 2.5).abs() < 1e-9, "n {n}: {d}");
        // Diagonal: corner (10, 10) to corner (13, 14) is 5 mm.
        let d = min_outline_distance(&square(0.0, 0.0, 10.0, n), &square(13.0, 14.0, 10.0, n), 10.0, 0.0);
        assert!((d - 5.0).abs() < 1e-9, "n {n}: {d}");
        // Sharing a border.
        let d = min_outline_distance(&square(0.0, 0.0, 10.0, n), &square(10.0, 0.0, 10.0, n), 10.0, 0.0);
        assert_eq!(d, 0.0);
        // Beyond reach: above it.
        let d = min_outline_distance(&square(0.0, 0.0, 10.0, n), &square(40.0, 0.0, 10.0, n), 10.0, 0.0);
        assert!(d > 10.0);
    }
}
