//! The indexed exact region against brute force: the same definitions over
//! every segment, with no index (`brute`), and the field's signed distance
//! (`tests/reference.rs`'s `exact_signed_distance`, the parts composed by
//! `min` and `max`), which has the same sign, is never larger in size, and
//! equals it where every outline is edge (one simple polygon, or outside
//! one band).

use proptest::prelude::*;

use super::*;
use crate::geometry::{contains, distance_to_outline};
use crate::latero::distance::tests::outline;
use crate::latero::distance::tests::reference::exact_signed_distance;

/// A page far beyond every generated shape, so that the field's distance
/// is not bounded by it.
const FAR_PAGE: (f64, f64, f64, f64) = (-1e4, -1e4, 1e4, 1e4);

fn square(x: f64, y: f64, s: f64) -> Polyline {
    Polyline { points: vec![(x, y), (x + s, y), (x + s, y + s), (x, y + s)], closed: true }
}

/// The region's definitions over every segment, with no index.
mod brute {
    use super::*;
    use crate::geometry::distance_to_segment;

    fn sides(pls: &[Polyline]) -> Vec<Segment> {
        pls.iter()
            .flat_map(|pl| {
                let n = pl.points.len();
                (0..if n > 1 { n } else { 0 }).map(move |i| (pl.points[i], pl.points[(i + 1) % n]))
            })
            .collect()
    }

    fn lines(pls: &[Polyline]) -> Vec<Segment> {
        pls.iter().flat_map(|pl| pl.segments()).collect()
    }

    fn in_band(pls: &[Polyline], p: (f64, f64), w: f64) -> bool {
        lines(pls).iter().any(|&(a, b)| distance_to_segment(p, a, b) <= w / 2.0)
    }

    pub fn covers(g: &LayerGeometry<'_>, p: (f64, f64)) -> bool {
        let felt = g.fills.iter().any(|(f, r)| contains(f, p, *r))
            || g.band.as_ref().is_some_and(|(ls, w)| ls.iter().any(|l| in_band(l, p, *w)));
        felt && g.clips.iter().all(|(c, r)| contains(c, p, *r))
            && !g.cuts.iter().any(|(l, w)| in_band(l, p, *w))
            && !g.occluders.iter().any(|(f, r)| contains(f, p, *r))
    }

    /// The least distance to a candidate of any part that is on the edge.
    pub fn edge_distance(g: &LayerGeometry<'_>, p: (f64, f64), reach: f64) -> Option<f64> {
        let mut candidates: Vec<((f64, f64), (f64, f64))> = Vec::new();
        for (f, _) in g.fills.iter().chain(&g.occluders).chain(&g.clips) {
            for (a, c) in sides(f) {
                candidates.push((nearest_on_segment(p, a, c), unit(a.1 - c.1, c.0 - a.0)));
            }
        }
        let bands = g.band.iter().flat_map(|(ls, w)| ls.iter().map(move |l| (*l, *w))).chain(g.cuts.iter().copied());
        for (l, w) in bands {
            for (a, c) in lines(l) {
                let m = nearest_on_segment(p, a, c);
                let len = length(p.0 - m.0, p.1 - m.1);
                let r = w / 2.0;
                if len > ON_EDGE_MM {
                    let u = ((p.0 - m.0) / len, (p.1 - m.1) / len);
                    candidates.push(((m.0 + u.0 * r, m.1 + u.1 * r), u));
                } else {
                    let n = unit(a.1 - c.1, c.0 - a.0);
                    candidates.push(((m.0 + n.0 * r, m.1 + n.1 * r), n));
                    candidates.push(((m.0 - n.0 * r, m.1 - n.1 * r), (-n.0, -n.1)));
                }
            }
        }
        candidates
            .into_iter()
            .filter_map(|(q, across)| {
                let d = length(p.0 - q.0, p.1 - q.1);
                let u = if d > ON_EDGE_MM { ((p.0 - q.0) / d, (p.1 - q.1) / d) } else { across };
                let s = ON_EDGE_MM;
                let edge = covers(g, (q.0 + s * u.0, q.1 + s * u.1)) != covers(g, (q.0 - s * u.0, q.1 - s * u.1));
                (edge && d < reach).then_some(d)
            })
            .reduce(f64::min)
    }
}

/// Points near the geometry's vertices and the middles of its sides
/// (within a micrometre to a millimetre, in eight directions), and `far`.
fn probes(polys: &[&Polyline], far: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = far.to_vec();
    for pl in polys {
        let n = pl.points.len();
        for i in 0..n {
            let (a, b) = (pl.points[i], pl.points[(i + 1) % n]);
            for v in [a, ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0)] {
                for (k, r) in [1e-6, 1e-3, 0.05, 0.7, 1.3].into_iter().enumerate() {
                    let t = (i * 5 + k) as f64 * std::f64::consts::TAU / 8.0 + 0.1;
                    out.push((v.0 + r * t.cos(), v.1 + r * t.sin()));
                }
            }
        }
    }
    out
}

/// Checks `g`'s indexed region at `points` against brute force and the
/// field's signed distance; with `simple`, every outline is edge, and the
/// two distances are equal.
fn check(g: &LayerGeometry<'_>, points: &[(f64, f64)], simple: bool) -> Result<(), TestCaseError> {
    let exact = g.exact();
    for &p in points {
        let covers = exact.covers(p);
        prop_assert_eq!(covers, brute::covers(g, p), "coverage at {:?}", p);
        for reach in [0.01, 0.4, 3.0] {
            prop_assert_eq!(
                exact.distance_to_edge_within(p, reach),
                brute::edge_distance(g, p, reach),
                "distance within {} at {:?}",
                reach,
                p
            );
            // No edge within `reach` of `p`: none within `reach` less the nearest one's distance either.
            if !exact.edge_may_pass_within(p, reach) {
                prop_assert_eq!(exact.distance_to_edge_within(p, reach), None);
            }
        }
        let sd = exact.signed_distance(p);
        let field = exact_signed_distance(g, FAR_PAGE, p);
        prop_assert_eq!(sd.is_sign_positive(), covers, "sign at {:?}: {}", p, sd);
        if field.abs() > 1e-9 {
            prop_assert_eq!(field > 0.0, covers, "the field's sign at {:?}: {}", p, field);
        }
        // (A micrometre: the oracle takes band widths as the fields store them, in f32.)
        prop_assert!(field.abs() <= sd.abs() + 1e-6, "{:?}: field {} beyond exact {}", p, field, sd);
        if simple {
            prop_assert!(field == sd || (field - sd).abs() <= 1e-6, "{:?}: field {}, exact {}", p, field, sd);
        }
    }
    Ok(())
}

fn page_points() -> impl Strategy<Value = Vec<(f64, f64)>> {
    prop::collection::vec((-2.0f64..42.0, -2.0f64..32.0), 24)
}

/// A star-shaped polygon round a centre: every side is edge.
fn star() -> impl Strategy<Value = Polyline> {
    (5.0f64..35.0, 5.0f64..25.0, prop::collection::vec((0.0f64..std::f64::consts::TAU, 2.0f64..3.0), 5..12))
        .prop_map(|(cx, cy, mut polar)| {
            polar.sort_by(|a, b| a.0.total_cmp(&b.0));
            polar.dedup_by(|a, b| (a.0 - b.0).abs() < 1e-3);
            let points = polar.iter().map(|&(a, r)| (cx + r * a.cos(), cy + r * a.sin())).collect();
            Polyline { points, closed: true }
        })
        .prop_filter("three sides or more, no corner sharper than a right angle", |pl| {
            pl.points.len() >= 3 && no_sharp_corner(pl)
        })
}

/// Whether every vertex of closed `pl` turns by less than 90 degrees either
/// way (interior angles between 90 and 270): at a sharper corner the
/// distance from the points whose nearest point is its vertex is not
/// found (`ExactRegion`'s doc).
fn no_sharp_corner(pl: &Polyline) -> bool {
    let n = pl.points.len();
    (0..n).all(|i| {
        let (a, b, c) = (pl.points[(i + n - 1) % n], pl.points[i], pl.points[(i + 1) % n]);
        let (u, v) = ((b.0 - a.0, b.1 - a.1), (c.0 - b.0, c.1 - b.1));
        // A turn below 90 degrees: the sides' directions make an acute angle.
        u.0 * v.0 + u.1 * v.1 > 1e-3 * u.0.hypot(u.1) * v.0.hypot(v.1)
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// The index's crossing rule and nearness are `geometry`'s.
    #[test]
    fn outlines_agree_with_the_compilers_geometry(
        polys in prop::collection::vec(outline(), 1..4),
        p in (-2.0f64..42.0, -2.0f64..32.0),
        r in 0.0f64..6.0,
    ) {
        let fill = Outlines::new([&polys[..]], true);
        for rule in [FillRule::NonZero, FillRule::EvenOdd] {
            prop_assert_eq!(fill.contains(p, rule), contains(&polys, p, rule));
        }
        let d = distance_to_outline(&polys, p);
        if (d - r).abs() > 1e-9 {
            prop_assert_eq!(Outlines::new([&polys[..]], false).within(p, r), d <= r);
        }
    }

    /// One star-shaped fill with no corner sharper than a right angle, or one
/// band outside it: every outline is edge.
    #[test]
    fn one_part_is_the_fields_distance(a in star(), width in 0.2f64..3.0, far in page_points()) {
        let shape = [a];
        let g = LayerGeometry { fills: vec![(&shape, FillRule::NonZero)], ..Default::default() };
        check(&g, &probes(&[&shape[0]], &far), true)?;
        let g = LayerGeometry { band: Some((vec![&shape[..]], width)), ..Default::default() };
        let outside: Vec<_> = probes(&[&shape[0]], &far).into_iter().filter(|&p| !g.exact().covers(p)).collect();
        check(&g, &outside, true)?;
    }

    /// Fills with holes and self-crossings, cut by bands, under occluders.
    #[test]
    fn a_grating_cut_and_occluded_is_brute_forces(
        a in outline(), b in outline(), c in outline(), d in outline(),
        width in 0.2f64..3.0, evenodd in any::<bool>(), far in page_points(),
    ) {
        let (shape, cut, over) = ([a, b], [c], [d]);
        let rule = if evenodd { FillRule::EvenOdd } else { FillRule::NonZero };
        let g = LayerGeometry {
            fills: vec![(&shape, rule)],
            cuts: vec![(&cut, width)],
            occluders: vec![(&over, FillRule::NonZero)],
            ..Default::default()
        };
        check(&g, &probes(&[&shape[0], &shape[1], &cut[0], &over[0]], &far), false)?;
    }

    /// Bands of two shapes within a clip.
    #[test]
    fn a_clipped_band_is_brute_forces(a in outline(), b in outline(), c in outline(), width in 0.2f64..3.0, far in page_points()) {
        let (one, two, clip) = ([a], [b], [c]);
        let g = LayerGeometry {
            band: Some((vec![&one[..], &two[..]], width)),
            clips: vec![(&clip, FillRule::EvenOdd)],
            ..Default::default()
        };
        check(&g, &probes(&[&one[0], &two[0], &clip[0]], &far), false)?;
    }
}

/// One style's two squares that share a side are one region: the shared
/// side is no edge; a band's edge is half its width from the centre line;
/// a cut band's inner offset is a grating's edge; a clip's side is one.
#[test]
fn edges_are_where_coverage_changes() {
    let (left, right) = ([square(30.0, 20.0, 20.0)], [square(50.0, 20.0, 20.0)]);
    let near = |got: Option<f64>, want: f64| got.is_some_and(|d| (d - want).abs() < 1e-9);
    let fills =
        LayerGeometry { fills: vec![(&left, FillRule::NonZero), (&right, FillRule::NonZero)], ..Default::default() }
            .exact();
    assert!(near(fills.distance_to_edge_within((30.002, 30.0), 0.01), 0.002));
    assert!(near(fills.distance_to_edge_within((29.998, 30.0), 0.01), 0.002));
    assert_eq!(fills.distance_to_edge_within((50.001, 30.0), 0.01), None);
    assert!(fills.covers((50.0, 30.0)) && fills.covers((49.999, 30.0)));
    // Outside a corner the distance is to the corner itself.
    let q = (30.0 - 0.002 / 2f64.sqrt(), 20.0 - 0.002 / 2f64.sqrt());
    assert!(near(fills.distance_to_edge_within(q, 0.01), 0.002));
    assert!((fills.signed_distance((40.0, 30.0)) - 10.0).abs() < 1e-9);
    assert!((fills.signed_distance((25.0, 30.0)) + 5.0).abs() < 1e-9);

    let band = LayerGeometry { band: Some((vec![&left[..]], 1.5)), ..Default::default() }.exact();
    assert!(near(band.distance_to_edge_within((29.251, 30.0), 0.01), 0.001));
    assert!(band.covers((29.251, 30.0)) && !band.covers((29.249, 30.0)));
    assert!((band.signed_distance((30.0, 30.0)) - 0.75).abs() < 1e-9);

    let cut = LayerGeometry { fills: vec![(&left, FillRule::NonZero)], cuts: vec![(&left, 1.5)], ..Default::default() };
    let cut = cut.exact();
    assert!(near(cut.distance_to_edge_within((30.751, 30.0), 0.01), 0.001));
    assert!(!cut.covers((30.0, 30.0)) && cut.covers((30.751, 30.0)));
    // On the cut's centre line, the fill's own side is inside the cut: no edge.
    assert_eq!(cut.distance_to_edge_within((30.0, 30.0), 0.5), None);

    let clip = [square(0.0, 0.0, 40.0)];
    let clipped = LayerGeometry {
        fills: vec![(&left, FillRule::NonZero)],
        clips: vec![(&clip, FillRule::NonZero)],
        ..Default::default()
    }
    .exact();
    assert!(clipped.covers((39.0, 30.0)) && !clipped.covers((41.0, 30.0)));
    assert!((clipped.signed_distance((39.0, 30.0)) - 1.0).abs() < 1e-9);
    assert!((clipped.signed_distance((41.0, 30.0)) + 1.0).abs() < 1e-9);

    // The edge candidates hold every edge: the clip's side x = 40 and the band's offsets.
    assert!(clipped.edge_candidates(0.001).iter().any(|&(a, b)| a.0 == 40.0 && b.0 == 40.0));
    let offsets = band.edge_candidates(0.001);
    assert!(offsets.iter().any(|&(a, b)| a.0 == 29.25 && b.0 == 29.25));
    assert!(offsets.iter().any(|&(a, b)| a.0 == 30.75 && b.0 == 30.75));
}

/// Nothing felt, nothing to measure: no geometry has no edge.
#[test]
fn an_empty_layer_has_no_edge() {
    let empty = LayerGeometry::default().exact();
    assert!(!empty.covers((1.0, 1.0)));
    assert_eq!(empty.distance_to_edge_within((1.0, 1.0), 1e9), None);
    assert_eq!(empty.signed_distance((1.0, 1.0)), f64::NEG_INFINITY);
    assert!(empty.edge_candidates(0.001).is_empty());
}

/// A map's layer of many parts (more than [`UNINDEXED_PARTS`]): fills side
/// by side and overlapping, regions painted over them, a clip, a band and a
/// cut. The region asks only the parts whose boxes hold or come near a
/// point, and answers as brute force does over every part.
#[test]
fn a_layer_of_many_parts_is_brute_forces() {
    let fills: Vec<[Polyline; 1]> = (0..24)
        .map(|k| {
            let (col, row) = ((k % 6) as f64, (k / 6) as f64);
            // Every third one overlaps its neighbour; the others touch or stand apart.
            [square(col * 3.0 + 0.13 * (k % 3) as f64, row * 3.0 + 0.07, if k % 3 == 0 { 3.4 } else { 2.9 })]
        })
        .collect();
    let occluders: Vec<[Polyline; 1]> =
        (0..20).map(|k| [square(1.1 + (k % 5) as f64 * 3.7, 0.9 + (k / 5) as f64 * 2.9, 0.8)]).collect();
    let clip = [square(0.5, 0.2, 16.0)];
    let band_line = [Polyline { points: vec![(0.0, 5.0), (9.0, 7.5), (18.0, 4.0)], closed: false }];
    let cut_line = [Polyline { points: vec![(4.0, 0.0), (6.0, 12.0)], closed: false }];
    let g = LayerGeometry {
        fills: fills.iter().map(|f| (&f[..], FillRule::NonZero)).collect(),
        occluders: occluders.iter().map(|f| (&f[..], FillRule::NonZero)).collect(),
        clips: vec![(&clip[..], FillRule::EvenOdd)],
        band: Some((vec![&band_line[..]], 0.6)),
        cuts: vec![(&cut_line[..], 0.3)],
    };
    assert!(g.exact().index.is_some(), "indexed");
    let polys: Vec<&Polyline> =
        fills.iter().chain(&occluders).map(|f| &f[0]).chain([&clip[0], &band_line[0], &cut_line[0]]).collect();
    let far: Vec<(f64, f64)> = (0..400).map(|k| ((k % 20) as f64 * 0.97 - 0.5, (k / 20) as f64 * 0.71 - 0.5)).collect();
    if let Err(e) = check(&g, &probes(&polys, &far), false) {
        panic!("{e}");
    }
}
