//! Tests of the design rules between features: the gap rule's search
//! against an all-pairs scan, its messages, and the cap on meeting pairs.

use super::gaps::{gap, nearest_gaps};
use super::*;
use crate::geometry::Polyline;

#[test]
fn a_gap_below_the_limit_never_reads_as_the_limit() {
    assert_eq!(below(1.74, MIN_GAP_MM), "1.7");
    assert_eq!(below(3.17, MIN_GAP_MM), "3.17");
    assert_eq!(below(3.1999, MIN_GAP_MM), "3.199");
    assert_eq!(below(3.198, MIN_GAP_MM), "3.198");
}

/// A deterministic sequence in [0, 1) (a linear congruential generator).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 33) as f64 / (1u64 << 31) as f64
    }
}

/// A random drawing: vibrating outlines (closed and open), gratings and
/// dotted features, some of them parts of one element, packed closely
/// enough that many touch, cross or lie inside each other.
fn random_features(seed: u64, n: usize) -> Vec<Feature> {
    let mut r = Lcg(seed);
    (0..n)
        .map(|k| {
            let (cx, cy) = (r.next() * 60.0, r.next() * 40.0);
            let size = 0.5 + r.next() * 6.0;
            let sides = 3 + (r.next() * 5.0) as usize;
            let turn = r.next() * 6.3;
            let points: Vec<(f64, f64)> = (0..sides)
                .map(|s| {
                    let a = turn + s as f64 * std::f64::consts::TAU / sides as f64;
                    let rad = size * (0.5 + r.next());
                    (cx + rad * a.cos(), cy + rad * a.sin())
                })
                .collect();
            let (kind, half_band, closed) = match k % 4 {
                0 => (FeatureKind::Vibrate { width_mm: 1.5, freq_hz: 40.0 }, 0.75, true),
                1 => (FeatureKind::Vibrate { width_mm: 1.0, freq_hz: 40.0 }, 0.5, false),
                2 => (FeatureKind::Grating { wavelength_mm: 4.0, angle_deg: 0.0 }, 0.0, true),
                _ => (FeatureKind::Dot { radius_mm: 0.6 }, 0.0, false),
            };
            let (outline, dots) = if k % 4 == 3 {
                (Vec::new(), points.iter().map(|p| (p.0, p.1, 0.6)).collect::<Vec<_>>())
            } else {
                (vec![Polyline { points, closed }], Vec::new())
            };
            let bbox = if dots.is_empty() {
                let b = crate::geometry::bounds(&outline).unwrap();
                spatial::grow(b, half_band)
            } else {
                dots.iter().fold((f64::MAX, f64::MAX, f64::MIN, f64::MIN), |b, d| {
                    (b.0.min(d.0 - d.2), b.1.min(d.1 - d.2), b.2.max(d.0 + d.2), b.3.max(d.1 + d.2))
                })
            };
            Feature {
                // Every seventh feature is a second style of the element before it.
                elem: if k % 7 == 6 { k - 1 } else { k },
                name: format!("f{k}"),
                line: 1,
                kind,
                outline,
                half_band,
                dots,
                bbox,
                mask: None,
                amplitude: 1.0,
            }
        })
        .collect()
}

/// The exact gap between two features, every segment pair measured.
fn reference_gap(a: &Feature, b: &Feature) -> f64 {
    gap(a, b, 1e9, |r, stop| spatial::min_outline_distance(&a.outline, &b.outline, r, stop))
}

#[test]
fn nearest_gaps_are_those_of_an_all_pairs_scan() {
    // Without textures, then with every grating one style, so that those
    // that touch are one texture and a nearer part of one's own texture
    // must not hide a farther gap to something else.
    for (seed, one_style) in [(1, false), (2, false), (3, false), (1, true), (2, true), (3, true)] {
        let mut f = random_features(seed, 300);
        if one_style {
            for x in f.iter_mut().filter(|x| matches!(x.kind, FeatureKind::Grating { .. })) {
                x.mask = Some(0);
            }
        }
        let textures = one_texture(&f);
        let texture = |k: usize| textures.get(&k).map(|t| t.0);
        let one = |i: usize, j: usize| texture(i).is_some() && texture(i) == texture(j);
        let boxes: Vec<_> = f.iter().map(|x| x.bbox).collect();
        let got = nearest_gaps(&f, &spatial::BoxIndex::new(&boxes), &textures, |_, _, _: &mut Vec<()>| {}).0;
        let (mut reported, mut hidden) = (0, 0);
        for (j, b) in f.iter().enumerate() {
            // Every other feature, its exact gap with no reach to cut it short.
            let nearest = |keep: &dyn Fn(usize) -> bool| {
                (0..f.len())
                    .filter(|&i| f[i].elem != b.elem && keep(i))
                    .map(|i| (reference_gap(&f[i], b), i))
                    .filter(|&(g, _)| g > 0.0 && g < MIN_GAP_MM)
                    .min_by(|p, q| p.0.total_cmp(&q.0))
            };
            let want = nearest(&|i| !one(i, j)).map(|(g, _)| g);
            if nearest(&|_| true).is_some_and(|(_, i)| one(i, j)) {
                hidden += 1;
            }
            match (got[j], want) {
                (None, None) => {}
                (Some((i, g)), Some(w)) => {
                    reported += 1;
                    assert!((g - w).abs() < 1e-12, "seed {seed}, f{j}: nearest gap {g}, all pairs {w}");
                    assert!(f[i].elem != b.elem && !one(i, j));
                    assert!((reference_gap(&f[i], b) - g).abs() < 1e-12, "seed {seed}, f{j}: #f{i} is not {g} away");
                }
                (g, w) => panic!("seed {seed}, f{j}: nearest {g:?}, all pairs {w:?}"),
            }
        }
        // The drawing is dense enough that the rule has something to find,
        // and, with one style, that textures hide nearer gaps.
        assert!(reported > 30, "seed {seed}: only {reported} features have a near neighbour");
        assert_eq!(hidden > 0, one_style, "seed {seed}: {hidden} nearest gaps within a texture");
    }
}

#[test]
fn nearest_gaps_do_not_depend_on_how_many_threads_share_the_work() {
    let f = random_features(4, 600);
    let boxes: Vec<_> = f.iter().map(|x| x.bbox).collect();
    let index = spatial::BoxIndex::new(&boxes);
    // Every pair whose boxes meet, as the overlap checks see them.
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            nearest_gaps(&f, &index, &Textures::default(), |i, j, out: &mut Vec<(usize, usize)>| out.push((i, j)))
        })
    };
    let (gaps, meets) = run(1);
    assert!(gaps.iter().filter(|g| g.is_some()).count() > 50);
    let mut sorted = meets.clone();
    sorted.sort_unstable();
    assert_eq!(meets, sorted, "pairs are reported in order");
    assert_eq!(meets, spatial::near_pairs(&boxes, 0.0), "every pair whose boxes meet, once");
    for threads in [2, 3, 8] {
        let (g, m) = run(threads);
        assert_eq!(m, meets, "{threads} threads");
        for (k, (a, b)) in g.iter().zip(&gaps).enumerate() {
            assert_eq!(a.map(|(i, g)| (i, g.to_bits())), b.map(|(i, g)| (i, g.to_bits())), "f{k}, {threads} threads");
        }
    }
}

/// A filled square of its own element, `(x, y)` its lower corner.
fn square(k: usize, x: f64, y: f64, side: f64) -> Feature {
    let points = vec![(x, y), (x + side, y), (x + side, y + side), (x, y + side)];
    Feature {
        elem: k,
        name: format!("f{k}"),
        line: 1,
        kind: FeatureKind::Grating { wavelength_mm: 4.0, angle_deg: 0.0 },
        outline: vec![Polyline { points, closed: true }],
        half_band: 0.0,
        dots: Vec::new(),
        bbox: (x, y, x + side, y + side),
        mask: None,
        amplitude: 1.0,
    }
}

#[test]
fn among_equal_gaps_the_first_feature_is_named_whichever_pass_finds_it() {
    // Feature 1 has a neighbour 1 mm away on each side: the later one
    // (2) at the left, the earlier one (0) at the right, both with boxes
    // apart from its own; and 3, a square 1.5 mm above 1 whose box is
    // stretched down to meet 1's, 0's and 2's (a box only bounds the
    // gap from below, and boxes that meet are measured in the other pass).
    let f = vec![square(0, 13.0, 0.0, 2.0), square(1, 10.0, 0.0, 2.0), square(2, 7.0, 0.0, 2.0), {
        let mut x = square(3, 9.0, 3.5, 4.0);
        x.bbox = (9.0, 1.9, 13.0, 7.5);
        x
    }];
    let boxes: Vec<_> = f.iter().map(|x| x.bbox).collect();
    let got = nearest_gaps(&f, &spatial::BoxIndex::new(&boxes), &Textures::default(), |_, _, _: &mut Vec<()>| {}).0;
    assert_eq!(got[1], Some((0, 1.0)));
    assert_eq!(got[0], Some((1, 1.0)));
    assert_eq!(got[2], Some((1, 1.0)));
    // 3's nearest is 1, found through boxes that meet; 0's corner is as far (1.5 mm), and first.
    assert_eq!(got[3], Some((0, 1.5)));
    // With 0 and 2 gone, 1's nearest is 3, through boxes that meet.
    let f = vec![f[1].clone(), f[3].clone()];
    let boxes: Vec<_> = f.iter().map(|x| x.bbox).collect();
    assert_eq!(
        nearest_gaps(&f, &spatial::BoxIndex::new(&boxes), &Textures::default(), |_, _, _: &mut Vec<()>| {}).0[0],
        Some((1, 1.5))
    );
}

/// Over [`MAX_MEETING_PAIRS`] (here a cap of 1,000), the rules between
/// features are left out with one T0412 that says why; under it, the
/// same features are checked pair by pair.
#[test]
fn a_drawing_too_dense_for_the_rules_between_elements_says_so() {
    // 60 squares, each 0.5 mm right of the last: every box meets every
    // other (1,770 pairs), and each square's nearest gap is to nobody
    // (they overlap) but the overlaps are pairs to check.
    let f: Vec<Feature> = (0..60).map(|k| square(k, k as f64 * 0.5, 0.0, 40.0)).collect();
    let textures = Textures::default();
    let mut capped = Vec::new();
    let meets = pairs_within(&f, &textures, &mut capped, 1_000);
    assert!(meets.is_empty());
    let dense: Vec<_> = capped.iter().filter(|d| d.code == "T0412").collect();
    assert_eq!(dense.len(), 1, "{capped:?}");
    assert!(dense[0].message.contains("1770 pairs of its 60 elements"), "{}", dense[0].message);
    let mut checked = Vec::new();
    let meets = pairs_within(&f, &textures, &mut checked, usize::MAX);
    assert_eq!(meets.len(), 60 * 59 / 2);
    assert!(checked.iter().all(|d| d.code != "T0412"));
}

/// The estimate of meeting pairs is the count of an all-pairs scan when
/// every box is sampled, and close to it when a sample stands for them.
#[test]
fn meeting_pairs_are_counted_from_a_sample_of_the_boxes() {
    for (seed, n) in [(3, 300), (5, 3_000)] {
        let f = random_features(seed, n);
        let boxes: Vec<_> = f.iter().map(|x| x.bbox).collect();
        let index = spatial::BoxIndex::new(&boxes);
        let all = (0..n)
            .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
            .filter(|&(i, j)| spatial::meet(boxes[i], boxes[j]))
            .count();
        let est = meeting_pairs(&index, &boxes);
        if n <= DENSITY_SAMPLE {
            assert_eq!(est, all);
        } else {
            assert!((est as f64 - all as f64).abs() <= 0.1 * all as f64, "estimated {est}, counted {all}");
        }
    }
}
