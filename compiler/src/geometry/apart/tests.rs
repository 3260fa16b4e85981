use i_overlay::core::fill_rule::FillRule as OvFill;
use i_overlay::core::overlay::{IntOverlayOptions, Overlay, ShapeType};
use i_overlay::core::overlay_rule::OverlayRule;
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

use super::{Filled, apart};
use crate::geometry::overlay::{Frame, contours, ov_rule, shapes_of};
use crate::geometry::{FillRule, Polyline};

fn ring(points: &[(f64, f64)]) -> Vec<Polyline> {
    vec![Polyline { points: points.to_vec(), closed: true }]
}

fn square(x: f64, y: f64, side: f64) -> Vec<(f64, f64)> {
    vec![(x, y), (x + side, y), (x + side, y + side), (x, y + side)]
}

fn reversed(mut points: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    points.reverse();
    points
}

fn is_apart(a: &[Polyline], ra: FillRule, b: &[Polyline], rb: FillRule) -> bool {
    let (fa, fb) = (Filled::new(a, ra), Filled::new(b, rb));
    let one = apart(&fa, &fb);
    assert_eq!(one, apart(&fb, &fa), "the answer does not depend on the order");
    one
}

/// Whether the insides of two shapes have area in common: i_overlay's
/// intersection (each shape made simple under its rule, on a fine integer
/// frame), confirmed by a point inside a piece of it that both shapes hold
/// (a piece made by rounding a crossing to the frame, in no shape, is not).
fn overlap(a: &[Polyline], ra: FillRule, b: &[Polyline], rb: FillRule) -> bool {
    let f = Frame { ox: 0.0, oy: 0.0, q: 1.0 / 1024.0 };
    let sa: Vec<_> = shapes_of(&contours(a, f), ov_rule(ra)).into_iter().flatten().collect();
    let sb: Vec<_> = shapes_of(&contours(b, f), ov_rule(rb)).into_iter().flatten().collect();
    if sa.is_empty() || sb.is_empty() {
        return false;
    }
    let mut o = Overlay::new_custom(sa.len() + sb.len(), IntOverlayOptions::<u64>::default(), Default::default());
    o.add_source(&sa, ShapeType::Subject);
    o.add_source(&sb, ShapeType::Clip);
    let common = o.overlay(OverlayRule::Intersect, OvFill::NonZero);
    common.iter().any(|shape| {
        let piece: Vec<Polyline> = shape
            .iter()
            .map(|c| Polyline {
                points: c.iter().map(|p| (p.x as f64 * f.q, p.y as f64 * f.q)).collect(),
                closed: true,
            })
            .collect();
        let Some((x0, y0, x1, y1)) = crate::geometry::bounds(&piece) else { return false };
        (0..64 * 64).any(|k| {
            let p =
                (x0 + (x1 - x0) * ((k % 64) as f64 + 0.37) / 64.0, y0 + (y1 - y0) * ((k / 64) as f64 + 0.61) / 64.0);
            crate::geometry::contains(&piece, p, NZ)
                && crate::geometry::contains(a, p, ra)
                && crate::geometry::contains(b, p, rb)
        })
    })
}

const NZ: FillRule = FillRule::NonZero;
const EO: FillRule = FillRule::EvenOdd;

#[test]
fn neighbours_sharing_a_side_are_apart_whichever_way_they_run() {
    let (a, b) = (square(0.0, 0.0, 1.0), square(1.0, 0.0, 1.0));
    assert!(is_apart(&ring(&a), NZ, &ring(&b), NZ));
    assert!(is_apart(&ring(&a), NZ, &ring(&reversed(b.clone())), EO));
    assert!(is_apart(&ring(&reversed(a)), EO, &ring(&b), NZ));
}

#[test]
fn neighbours_sharing_a_wiggly_border_vertex_for_vertex_are_apart() {
    // Two regions either side of a border of 40 points (a map's states).
    let border: Vec<(f64, f64)> = (0..=40).map(|i| (i as f64 * 0.5, (i as f64 * 1.7).sin() * 0.8)).collect();
    let mut north = border.clone();
    north.extend([(20.0, 10.0), (0.0, 10.0)]);
    let mut south = reversed(border);
    south.extend([(0.0, -10.0), (20.0, -10.0)]);
    assert!(is_apart(&ring(&north), NZ, &ring(&south), NZ));
}

#[test]
fn shapes_that_overlap_or_lie_one_in_the_other_may_meet() {
    let a = ring(&square(0.0, 0.0, 2.0));
    // Overlapping; the same square (every side shared, inside the same way);
    // the same square drawn the other way; one inside the other.
    assert!(!is_apart(&a, NZ, &ring(&square(1.0, 1.0, 2.0)), NZ));
    assert!(!is_apart(&a, NZ, &a, NZ));
    assert!(!is_apart(&a, NZ, &ring(&reversed(square(0.0, 0.0, 2.0))), NZ));
    assert!(!is_apart(&a, NZ, &ring(&square(0.5, 0.5, 1.0)), NZ));
    // A square sharing a side and folding over it into the other.
    let over = ring(&[(2.0, 0.0), (2.0, 2.0), (1.0, 1.0)]);
    assert!(!is_apart(&a, NZ, &over, NZ));
}

#[test]
fn a_shape_in_a_hole_is_apart_under_even_odd_and_not_when_the_hole_is_filled() {
    let holed = vec![
        Polyline { points: square(0.0, 0.0, 10.0), closed: true },
        Polyline { points: square(2.0, 2.0, 6.0), closed: true },
    ];
    let inner = ring(&square(4.0, 4.0, 2.0));
    assert!(is_apart(&holed, EO, &inner, NZ));
    // Both rings run the same way: under non-zero the hole is filled.
    assert!(!is_apart(&holed, NZ, &inner, NZ));
    // The island fills the hole exactly, sharing its four sides: the hole
    // ring is not one simple ring's side, so the answer is "may meet".
    assert!(!is_apart(&holed, EO, &ring(&square(2.0, 2.0, 6.0)), NZ));
}

#[test]
fn shapes_that_touch_at_a_corner_or_stand_apart_are_apart() {
    let a = ring(&square(0.0, 0.0, 1.0));
    assert!(is_apart(&a, NZ, &ring(&square(1.0, 1.0, 1.0)), NZ));
    assert!(is_apart(&a, NZ, &ring(&square(3.0, 0.0, 1.0)), NZ));
    assert!(is_apart(&a, NZ, &ring(&square(1.5, -3.0, 1.0)), EO));
}

#[test]
fn outlines_that_touch_away_from_shared_points_may_meet() {
    let a = ring(&square(0.0, 0.0, 2.0));
    // A corner on the other's side (a T-junction); a side along part of the
    // other's; a gap thinner than the tolerance; a crossing.
    assert!(!is_apart(&a, NZ, &ring(&[(2.0, 1.0), (3.0, 0.0), (3.0, 2.0)]), NZ));
    assert!(!is_apart(&a, NZ, &ring(&square(2.0, 0.5, 1.0)), NZ));
    assert!(!is_apart(&a, NZ, &ring(&square(2.0 + 1e-8, 0.0, 1.0)), NZ));
    assert!(!is_apart(&a, NZ, &ring(&[(1.0, 1.0), (3.0, -1.0), (3.0, 3.0)]), NZ));
    // Sides from a shared corner a hair's breadth apart in angle.
    assert!(!is_apart(&a, NZ, &ring(&[(2.0, 0.0), (2.0 + 1e-12, 1.0), (3.0, 0.0)]), NZ));
    assert!(is_apart(&a, NZ, &ring(&[(2.0, 0.0), (2.001, 1.0), (3.0, 0.0)]), NZ));
}

#[test]
fn bad_coordinates_may_meet() {
    let a = ring(&square(0.0, 0.0, 1.0));
    assert!(!is_apart(&a, NZ, &ring(&[(5.0, 5.0), (f64::NAN, 6.0), (6.0, 6.0)]), NZ));
}

/// Whenever two shapes are said to be apart, no area is common to them: random rings on a small grid of whole numbers (so that they
/// share points and sides, cross, fold back and nest as often as not), under
/// either rule, and the cells of a map, which share their sides.
#[test]
fn shapes_said_to_be_apart_have_no_area_in_common() {
    let point = || (0..7i32, 0..7i32).prop_map(|(x, y)| (x as f64, y as f64));
    let shape = prop::collection::vec(prop::collection::vec(point(), 3..9), 1..3)
        .prop_map(|rings| rings.into_iter().map(|points| Polyline { points, closed: true }).collect::<Vec<_>>());
    let rule = prop::sample::select(vec![NZ, EO]);
    // The second shape is another one, or the first moved by whole steps
    // (and perhaps drawn the other way): then they share sides often.
    let moved = (-3..4i32, -3..4i32, any::<bool>(), any::<bool>());
    let said_apart = std::cell::Cell::new(0);
    TestRunner::new(Config { cases: 3000, ..Config::default() })
        .run(&(shape.clone(), rule.clone(), shape, rule, moved), |(a, ra, b, rb, (dx, dy, copy, flip))| {
            let b = if copy {
                a.iter()
                    .map(|pl| {
                        let mut points: Vec<(f64, f64)> =
                            pl.points.iter().map(|p| (p.0 + dx as f64, p.1 + dy as f64)).collect();
                        if flip {
                            points.reverse();
                        }
                        Polyline { points, closed: true }
                    })
                    .collect()
            } else {
                b
            };
            if is_apart(&a, ra, &b, rb) {
                said_apart.set(said_apart.get() + 1);
                prop_assert!(!overlap(&a, ra, &b, rb), "{:?} {:?} / {:?} {:?}", a, ra, b, rb);
            }
            Ok(())
        })
        .unwrap();
    // Not a test that passes by saying "may meet" every time.
    let said_apart = said_apart.get();
    assert!(said_apart > 100, "only {said_apart} pairs said to be apart");
}

/// The cells of a grid whose inner points are moved at random share their
/// sides point for point, as a map's regions do: every two are apart.
#[test]
fn the_cells_of_a_map_are_apart() {
    let n = 6;
    let mut rng = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng % 1000) as f64 / 1000.0 - 0.5
    };
    let mut at = vec![vec![(0.0, 0.0); n + 1]; n + 1];
    for (i, row) in at.iter_mut().enumerate() {
        for (j, p) in row.iter_mut().enumerate() {
            let inner = |k: usize| k > 0 && k < n;
            *p = (
                i as f64 * 10.0 + if inner(i) { next() * 6.0 } else { 0.0 },
                j as f64 * 10.0 + if inner(j) { next() * 6.0 } else { 0.0 },
            );
        }
    }
    let cells: Vec<Vec<Polyline>> = (0..n * n)
        .map(|k| {
            let (i, j) = (k / n, k % n);
            let corners = [at[i][j], at[i + 1][j], at[i + 1][j + 1], at[i][j + 1]];
            // Alternate cells drawn the other way round.
            ring(&if k % 3 == 0 { reversed(corners.to_vec()) } else { corners.to_vec() })
        })
        .collect();
    for (p, a) in cells.iter().enumerate() {
        for b in &cells[p + 1..] {
            assert!(is_apart(a, NZ, b, EO));
        }
    }
}

/// Long sides across each other (a scribble's) stop the sweep within its
/// bounds, and the answer is "may meet".
#[test]
fn a_scribble_is_looked_at_within_bounds() {
    let n = 2_000;
    let across: Vec<(f64, f64)> =
        (0..n).map(|k| if k % 2 == 0 { (0.0, k as f64 * 0.01) } else { (100.0, k as f64 * 0.01) }).collect();
    let down: Vec<(f64, f64)> =
        (0..n).map(|k| if k % 2 == 0 { (k as f64 * 0.05, -5.0) } else { (k as f64 * 0.05, 40.0) }).collect();
    let (a, b) = (ring(&across), ring(&down));
    let (fa, fb) = (Filled::new(&a, NZ), Filled::new(&b, NZ));
    let sides = |f: &Filled<'_>| super::sides_of(&f.rings[0], 0);
    let mut pairs = 0usize;
    assert!(!super::sweep(&sides(&fa), &sides(&fb), |_, _| {
        pairs += 1;
        true
    }));
    assert!(pairs <= super::SWEEP_WORK * 2 * n, "{pairs} pairs looked at");
    assert!(!apart(&fa, &fb));
}
