use super::occluders_that_hide;
use crate::geometry::{FillRule, Polyline};

fn square(x: f64, y: f64, side: f64) -> Vec<Polyline> {
    vec![Polyline { points: vec![(x, y), (x + side, y), (x + side, y + side), (x, y + side)], closed: true }]
}

const NZ: FillRule = FillRule::NonZero;

/// Which of `occluders` (by position) are kept over `fills`, with a cap of 1 mm.
fn kept(fills: &[Vec<Polyline>], occluders: &[Vec<Polyline>]) -> Vec<usize> {
    let f: Vec<(&[Polyline], FillRule)> = fills.iter().map(|p| (&p[..], NZ)).collect();
    let o: Vec<(&[Polyline], FillRule)> = occluders.iter().map(|p| (&p[..], NZ)).collect();
    let out = occluders_that_hide(&f, &o, 1.0);
    out.iter().map(|(p, _)| o.iter().position(|(q, _)| std::ptr::eq(*p, *q)).expect("one of them")).collect()
}

#[test]
fn regions_that_only_border_the_layer_hide_nothing() {
    // A region of the layer and its four neighbours, painted over it.
    let fills = [square(10.0, 10.0, 10.0)];
    let around = [square(0.0, 10.0, 10.0), square(20.0, 10.0, 10.0), square(10.0, 0.0, 10.0), square(10.0, 20.0, 10.0)];
    assert!(kept(&fills, &around).is_empty());
}

#[test]
fn what_covers_the_layer_is_kept_with_what_borders_it_near_there() {
    let fills = [square(10.0, 10.0, 10.0)];
    let occluders = [
        // A label's clearing over the region's right side.
        square(17.0, 12.0, 4.0),
        // The neighbour on the right, which the clearing also covers: its
        // side shared with the clearing's union must not be an edge.
        square(20.0, 10.0, 10.0),
        // The neighbour on the left, 7 mm from the clearing (more than
        // twice the cap).
        square(0.0, 10.0, 10.0),
        // A region across the page.
        square(80.0, 80.0, 10.0),
    ];
    assert_eq!(kept(&fills, &occluders), vec![0, 1]);
}

/// A small occluder beside a coast of 300,000 points is not looked at (the
/// look would read the coast for an occluder whose union costs next to
/// nothing): it is kept, as it would be beside a fill that may lie under
/// it. Beside a small fill, the same occluder is looked at and left out.
#[test]
fn a_small_occluder_beside_a_long_coast_is_kept_without_a_look() {
    let n = 300_000;
    let coast: Vec<Polyline> = vec![Polyline {
        points: (0..n)
            .map(|k| {
                let t = k as f64 / n as f64 * std::f64::consts::TAU;
                (50.0 + 40.0 * t.cos(), 50.0 + 40.0 * t.sin())
            })
            .collect(),
        closed: true,
    }];
    // Just outside the coast, touching its box.
    let beside = square(90.0, 45.0, 2.0);
    assert_eq!(kept(&[coast], std::slice::from_ref(&beside)), vec![0]);
    assert!(kept(&[square(88.0, 45.0, 2.0)], &[beside]).is_empty());
}
