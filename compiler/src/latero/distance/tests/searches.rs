//! The pieces tiles are built from, each against a plain version: the
//! buckets, the nearest-segment searches, the writers' orderings, the inline
//! floor and ceil.

use super::*;

proptest! {
    /// `nearest_first` keeps what a stable sort then a truncation keep, ties
    /// (few distinct keys, so many) and NaN included.
    #[test]
    fn nearest_first_is_a_stable_sort_cut_short(
        keys in proptest::collection::vec(prop_oneof![0u8..6, Just(255u8)], 0..40),
        max in 0usize..12,
    ) {
        let v: Vec<(f64, usize)> =
            keys.iter().enumerate().map(|(i, &k)| (if k == 255 { f64::NAN } else { k as f64 }, i)).collect();
        let mut want = v.clone();
        want.sort_by(|a, b| a.0.total_cmp(&b.0));
        want.truncate(max);
        let got = nearest_first(v.into_iter(), max);
        let ids = |x: &[(f64, usize)]| x.iter().map(|e| e.1).collect::<Vec<_>>();
        prop_assert_eq!(ids(&got), ids(&want));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Each tile's bucket holds, in segment order, every segment within
    /// its reach of the tile (measured: the least distance between the
    /// segment and the tile's square), and only segments whose bounds grown
    /// by their reach meet the tile (with the same rounding of bounds to
    /// tiles); each segment's span is the range of tiles its bounds meet,
    /// and the tiles holding it lie within its span. A negative reach (a
    /// span that comes out empty) acts on no tile and never panics; an
    /// infinite one acts on every tile.
    #[test]
    fn buckets_hold_the_segments_that_reach_each_tile(
        segs in prop::collection::vec(
            ((-3.0f64..12.0, -3.0f64..12.0), (-8.0f64..8.0, -8.0f64..8.0), prop_oneof![
                8 => 0.0f64..2.0,
                1 => -3.0f64..0.0,
                1 => Just(f64::INFINITY),
            ]),
            0..60,
        ),
        (cols, rows) in (1usize..6, 1usize..6),
        tile in 0.5f64..3.0,
        origin in (-1.0f64..1.0, -1.0f64..1.0),
    ) {
        let segs: Vec<(Seg, Part, f64)> =
            segs.iter().map(|&((x, y), (dx, dy), m)| (((x, y), (x + dx, y + dy)), Part::Fill, m)).collect();
        let tiles = Tiles { origin, side: tile, cols, rows };
        let (buckets, spans) = buckets_of(&segs, &tiles);
        prop_assert_eq!(buckets.len(), cols * rows);
        prop_assert_eq!(spans.len(), segs.len());
        // The tile index of a coordinate (unbounded: the lattice's first and
        // last tiles take what lies beyond them).
        let index = |v: f64, o: f64| ((v - o) / tile).floor();
        let by_bounds = |(s, _, m): &(Seg, Part, f64), c: usize, r: usize| {
            let b = seg_bounds(s);
            let (lo_c, hi_c) = (index(b.0 - m, origin.0), index(b.2 + m, origin.0));
            let (lo_r, hi_r) = (index(b.1 - m, origin.1), index(b.3 + m, origin.1));
            let covers = |lo: f64, hi: f64, k: usize| lo <= k as f64 && k as f64 <= hi;
            b.2 + m >= origin.0
                && b.3 + m >= origin.1
                && lo_c < cols as f64
                && lo_r < rows as f64
                && covers(lo_c, hi_c, c)
                && covers(lo_r, hi_r, r)
        };
        for r in 0..rows {
            for c in 0..cols {
                let bucket = &buckets[r * cols + c];
                prop_assert!(bucket.windows(2).all(|w| w[0] < w[1]), "tile ({}, {}) in segment order", c, r);
                let square = (
                    (origin.0 + c as f64 * tile, origin.1 + r as f64 * tile),
                    (origin.0 + (c + 1) as f64 * tile, origin.1 + (r + 1) as f64 * tile),
                );
                for (n, seg) in segs.iter().enumerate() {
                    let held = bucket.contains(&(n as u32));
                    prop_assert!(!held || by_bounds(seg, c, r), "tile ({}, {}) holds segment {} beyond its bounds", c, r, n);
                    let d = distance_to_square(seg.0, square);
                    prop_assert!(held || d >= seg.2 * (1.0 - 1e-9), "tile ({}, {}) lacks segment {} at {}", c, r, n, d);
                }
            }
        }
        for (n, sp) in spans.iter().enumerate() {
            let [c0, c1, r0, r1] = sp.map(usize::from);
            let in_span = |c: usize, r: usize| c0 <= c && c <= c1 && r0 <= r && r <= r1;
            for (c, r) in (0..rows).flat_map(|r| (0..cols).map(move |c| (c, r))) {
                prop_assert_eq!(in_span(c, r), by_bounds(&segs[n], c, r), "segment {} tile ({}, {})", n, c, r);
                prop_assert!(!buckets[r * cols + c].contains(&(n as u32)) || in_span(c, r));
            }
        }
    }
}

/// The least distance between segment `s` and the closed square
/// `(low, high)` corners: 0 where they meet.
fn distance_to_square(s: Seg, (lo, hi): ((f64, f64), (f64, f64))) -> f64 {
    let inside = |p: (f64, f64)| lo.0 <= p.0 && p.0 <= hi.0 && lo.1 <= p.1 && p.1 <= hi.1;
    if inside(s.0) || inside(s.1) {
        return 0.0;
    }
    let sides = [(lo, (hi.0, lo.1)), ((hi.0, lo.1), hi), (hi, (lo.0, hi.1)), ((lo.0, hi.1), lo)];
    sides.iter().map(|&(a, b)| crate::geometry::segment_distance(s.0, s.1, a, b)).fold(f64::INFINITY, f64::min)
}

/// A long slanted segment is held by the tiles along it, not by every tile
/// of its bounds: a diagonal across 20 by 20 tiles is held by a band of
/// them a few tiles wide.
#[test]
fn a_diagonal_is_held_by_the_tiles_along_it() {
    let tiles = Tiles { origin: (0.0, 0.0), side: 2.0, cols: 20, rows: 20 };
    let segs = [(((0.5, 0.5), (39.5, 39.0)), Part::Band, 0.6)];
    let (buckets, spans) = buckets_of(&segs, &tiles);
    assert_eq!(spans[0], [0, 19, 0, 19]);
    let held: Vec<(usize, usize)> = (0..400).filter(|&k| !buckets[k].is_empty()).map(|k| (k % 20, k / 20)).collect();
    assert!(held.iter().all(|&(c, r)| c.abs_diff(r) <= 1), "{held:?}");
    assert!((0..20).all(|k| held.contains(&(k, k))), "{held:?}");
    assert!(held.len() < 60, "{} tiles", held.len());
}

/// Points to search from near [`clustered_segments`]' tile: anywhere, or on
/// its lattice of 0.5 mm (where distances tie).
fn probe_points() -> impl Strategy<Value = (f64, f64)> {
    prop_oneof![
        (8.0f64..14.0, 8.0f64..14.0),
        (0u8..9, 0u8..9).prop_map(|(i, j)| (9.0 + i as f64 * 0.5, 9.0 + j as f64 * 0.5))
    ]
}

/// Segments for the nearest-segment searches: short ones clustered round a
/// tile, many sharing ends or lying on one another (equal keys), some far.
fn clustered_segments() -> impl Strategy<Value = Vec<(Seg, Part, f64)>> {
    let coord = prop_oneof![4 => 8.0f64..14.0, 1 => -20.0f64..40.0, 1 => (0u8..8).prop_map(|k| 9.0 + k as f64 * 0.5)];
    let part = prop_oneof![Just(Part::Fill), Just(Part::Band), Just(Part::Cut(0)), Just(Part::Cut(1))];
    proptest::collection::vec((coord.clone(), coord.clone(), coord.clone(), coord, part), 0..160)
        .prop_map(|v| v.into_iter().map(|(ax, ay, bx, by, p)| (((ax, ay), (bx, by)), p, 1.0)).collect())
}

proptest! {
    /// The writers' shared nearest segments: the first `max` of the
    /// [`planes::NEAREST_KEPT`] nearest (what [`TileCtx::nearest`](planes::TileCtx::nearest)
    /// hands a writer asking for `max`) are what `nearest_first` with `max`
    /// keeps, bit for bit, ties (shared ends, overlapping segments) included.
    #[test]
    fn the_shared_nearest_segments_are_nearest_firsts(
        segs in clustered_segments(),
        middle in (9.0f64..13.0, 9.0f64..13.0),
        max in 0usize..=planes::NEAREST_KEPT,
        part in prop_oneof![Just(Part::Fill), Just(Part::Band), Just(Part::Cut(0))],
    ) {
        let all = |max: usize| {
            nearest_first(
                segs.iter().filter(|s| s.1 == part).map(|&((a, b), _, _)| (distance2_to_segment(middle, a, b), (a, b))),
                max,
            )
        };
        let bits = |v: &[(f64, Seg)]| {
            v.iter().map(|(k, (a, b))| [k.to_bits(), a.0.to_bits(), a.1.to_bits(), b.0.to_bits(), b.1.to_bits()]).collect::<Vec<_>>()
        };
        let shared = all(planes::NEAREST_KEPT);
        prop_assert_eq!(bits(&shared[..max.min(shared.len())]), bits(&all(max)));
    }

    /// `nearest_of` (which stops at the first segment too far from the
    /// tile's middle to be nearer the point) finds the same segment and
    /// distance as a scan of them all keeping the first least; fails if it
    /// stopped one segment too early.
    #[test]
    fn nearest_of_is_the_first_least_of_a_full_scan(
        segs in clustered_segments(),
        middle in (9.0f64..13.0, 9.0f64..13.0),
        p in probe_points(),
        max in 1usize..48,
    ) {
        let near = nearest_first(segs.iter().map(|&((a, b), _, _)| (distance2_to_segment(middle, a, b), (a, b))), max);
        let want = near
            .iter()
            .enumerate()
            .map(|(k, (_, (a, b)))| (distance2_to_segment(p, *a, *b), k))
            .min_by(|x, y| x.0.total_cmp(&y.0))
            .map(|(d, k)| (k, d.to_bits()));
        prop_assert_eq!(nearest_of(&near, middle, p, None).map(|(k, d)| (k, d.to_bits())), want);
    }

    /// `nearest_of` told the least distance over a set of segments that
    /// holds its list (all the segments, of which the list keeps the
    /// nearest to the middle) finds what it finds untold; fails if it
    /// stopped at a segment merely close to that least distance.
    #[test]
    fn nearest_of_told_the_least_finds_what_it_finds_untold(
        segs in clustered_segments(),
        middle in (9.0f64..13.0, 9.0f64..13.0),
        p in probe_points(),
        max in 1usize..48,
    ) {
        let near = nearest_first(segs.iter().map(|&((a, b), _, _)| (distance2_to_segment(middle, a, b), (a, b))), max);
        let least = segs.iter().map(|&((a, b), _, _)| distance2_to_segment(p, a, b)).min_by(f64::total_cmp);
        let bits = |v: Option<(usize, f64)>| v.map(|(k, d)| (k, d.to_bits()));
        prop_assert_eq!(bits(nearest_of(&near, middle, p, least)), bits(nearest_of(&near, middle, p, None)));
    }

    /// The gradient length the corner writer reckons once per segment is
    /// that of the record it makes, for either sign, bit for bit; fails if
    /// it were taken from the unrounded gradient.
    #[test]
    fn a_segments_gradient_length_is_its_records(
        gx in prop_oneof![-300.0f64..300.0, -1e-3f64..1e-3, (-1000i32..1000).prop_map(|k| k as f64 / 7.0)],
        gy in prop_oneof![-300.0f64..300.0, -1e-3f64..1e-3, (-1000i32..1000).prop_map(|k| k as f64 / 3.0)],
        c in -200.0f64..200.0,
    ) {
        for s in [1.0, -1.0] {
            if let Some(r) = planes::record(128.0 + s * c, s * gx, s * gy, 0.0) {
                prop_assert_eq!(bends::gradient_norm(gx, gy).to_bits(), (r.gx as f64).hypot(r.gy as f64).to_bits());
            }
        }
    }

    /// `floor_f64` and `ceil_f64` equal `f64::floor` and `f64::ceil`
    /// (whole values, halves, tiny and huge magnitudes, both signs).
    #[test]
    fn the_inline_floor_and_ceil_are_libms(
        v in prop_oneof![
            -1e7f64..1e7,
            (-1000i64..1000).prop_map(|k| k as f64 * 0.5),
            any::<f64>(),
            prop_oneof![Just(-0.0), Just(0.0), Just(f64::INFINITY), Just(f64::NEG_INFINITY), Just(4_503_599_627_370_495.5), Just(-4_503_599_627_370_495.5)],
        ],
    ) {
        let same = |a: f64, b: f64| a == b || (a.is_nan() && b.is_nan());
        prop_assert!(same(floor_f64(v), v.floor()), "floor {v}: {} vs {}", floor_f64(v), v.floor());
        prop_assert!(same(ceil_f64(v), v.ceil()), "ceil {v}: {} vs {}", ceil_f64(v), v.ceil());
    }
}

proptest! {
    /// The order in which the writers check candidates at a tile's samples
    /// holds every sample once (so a check over it is a check over all 81),
    /// those nearest the edge first; fails if a sample were left out or
    /// taken twice.
    #[test]
    fn the_writers_check_every_sample_edge_first(
        exact in proptest::collection::vec(prop_oneof![-127.0f64..127.0, -3.0f64..3.0, Just(f64::NAN), Just(0.0)], TILE_SAMPLES),
        near in prop_oneof![0.0f64..40.0, Just(f64::NAN)],
    ) {
        let exact: [f64; TILE_SAMPLES] = exact.try_into().expect("81 samples");
        let order = planes::edge_first(&exact, near);
        let mut seen = [false; TILE_SAMPLES];
        for &i in &order {
            prop_assert!(!seen[i as usize], "sample {} twice", i);
            seen[i as usize] = true;
        }
        let close = |i: u8| exact[i as usize].abs() <= 2.0;
        let first_far = order.iter().position(|&i| !close(i)).unwrap_or(TILE_SAMPLES);
        prop_assert!(order[first_far..].iter().all(|&i| !close(i)));
    }
}
