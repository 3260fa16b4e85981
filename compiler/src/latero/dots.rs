//! Dot placement: dots along a path at a spacing that never lets them
//! overlap, and one dot per point symbol.

use std::collections::HashMap;

use crate::diagnostic::Diagnostic;
use crate::geometry::{Polyline, bounds, dist, points_at};

/// Most dots one element may have along its paths.
pub(crate) const MAX_DOTS_PER_ELEMENT: usize = 200_000;

/// Dot centres spaced along every subpath of `polys`.
///
/// The spacing is at least two radii (dots must not overlap, seed 000 §3.1);
/// a smaller requested spacing is raised, with a warning. On each subpath the
/// dots are spread evenly, at the requested spacing or slightly more: a closed
/// subpath of length L gets ⌊L / s⌋ dots, an open one ⌊L / s⌋ + 1 including
/// both ends. Where the path turns sharply or runs close to itself a dot that
/// would touch an earlier one is left out, with a warning.
pub(crate) fn along(
    polys: &[Polyline],
    radius: f64,
    spacing: Option<f64>,
    element: &str,
    diags: &mut Vec<Diagnostic>,
) -> Vec<(f64, f64)> {
    let mut s = spacing.unwrap_or(3.0 * radius);
    if s < 2.0 * radius {
        diags.push(
            Diagnostic::warning(
                "T0302",
                format!(
                    "dots of radius {radius} mm at a spacing of {s} mm would overlap; the spacing is raised to {} mm",
                    2.0 * radius
                ),
            )
            .with_element(element)
            .with_help("give a spacing of at least twice the radius"),
        );
        s = 2.0 * radius;
    }
    let total: f64 = polys.iter().map(Polyline::length).sum();
    let count = total / s;
    if count.is_nan() || count > MAX_DOTS_PER_ELEMENT as f64 {
        diags.push(
            Diagnostic::warning(
                "T0302",
                format!("the path is too long ({total:.0} mm) for dots every {s} mm; no dots are made for it"),
            )
            .with_element(element)
            .with_help("check the drawing's size, or use a larger spacing"),
        );
        return Vec::new();
    }
    let mut out: Vec<(f64, f64)> = Vec::new();
    // A grid of cells two radii wide: an overlapping dot can only be in the 3 x 3 cells around.
    let cell = 2.0 * radius;
    let key = |p: (f64, f64)| ((p.0 / cell).floor() as i64, (p.1 / cell).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    let mut dropped = 0usize;
    for pl in polys {
        let len = pl.length();
        let positions: Vec<f64> = if len < s {
            vec![if pl.closed { 0.0 } else { len / 2.0 }]
        } else {
            // A hair of tolerance so that a length of exactly k spacings (up to rounding) gets k of them.
            let n = (len / s * (1.0 + 1e-5)).floor() as usize;
            if pl.closed {
                (0..n).map(|k| k as f64 * len / n as f64).collect()
            } else {
                (0..=n).map(|k| k as f64 * len / n as f64).collect()
            }
        };
        for p in points_at(pl, &positions) {
            let (kx, ky) = key(p);
            let near = (kx - 1..=kx + 1).flat_map(|x| (ky - 1..=ky + 1).map(move |y| (x, y)));
            // Touching is allowed, overlapping is not (a hair of tolerance for rounding).
            let clash =
                near.filter_map(|k| grid.get(&k)).flatten().any(|&i| dist(p, out[i]) < 2.0 * radius * (1.0 - 1e-4));
            if clash {
                dropped += 1;
            } else {
                grid.entry((kx, ky)).or_default().push(out.len());
                out.push(p);
            }
        }
    }
    if dropped > 0 {
        diags.push(
            Diagnostic::warning(
                "T0302",
                format!("{dropped} dot(s) were left out where the path turns sharply or runs close to itself, so that no dots overlap"),
            )
            .with_element(element),
        );
    }
    out
}

/// The dots of a point symbol: the centres of its markers when it has any,
/// else the centre of its bounding box.
pub(crate) fn symbol(polys: &[Polyline], markers: &[(f64, f64)]) -> Vec<(f64, f64)> {
    if !markers.is_empty() {
        return markers.to_vec();
    }
    bounds(polys).map(|(x0, y0, x1, y1)| vec![((x0 + x1) / 2.0, (y0 + y1) / 2.0)]).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_square_gets_evenly_spread_dots_that_never_overlap() {
        let sq = Polyline { points: vec![(0.0, 0.0), (20.0, 0.0), (20.0, 20.0), (0.0, 20.0)], closed: true };
        let mut d = Vec::new();
        let dots = along(&[sq], 1.0, Some(3.0), "sq", &mut d);
        // Perimeter 80 mm at 3 mm: 26 dots, 80/26 ≈ 3.08 mm apart along the outline.
        assert_eq!(dots.len(), 26);
        assert!(d.is_empty());
        for (i, a) in dots.iter().enumerate() {
            for b in &dots[i + 1..] {
                assert!(dist(*a, *b) >= 2.0 - 1e-9);
            }
        }
    }

    #[test]
    fn too_small_spacing_is_raised_and_reported() {
        let line = Polyline { points: vec![(0.0, 0.0), (10.0, 0.0)], closed: false };
        let mut d = Vec::new();
        let dots = along(&[line], 1.0, Some(1.0), "l", &mut d);
        assert_eq!(dots.len(), 6); // 0, 2, 4, 6, 8, 10
        assert_eq!(d[0].code, "T0302");
    }

    #[test]
    fn hairpin_path_drops_touching_dots() {
        let hairpin = Polyline { points: vec![(0.0, 0.0), (10.0, 0.0), (0.0, 0.5)], closed: false };
        let mut d = Vec::new();
        let dots = along(&[hairpin], 1.0, Some(2.0), "h", &mut d);
        for (i, a) in dots.iter().enumerate() {
            for b in &dots[i + 1..] {
                assert!(dist(*a, *b) >= 2.0 - 1e-9);
            }
        }
        assert!(d.iter().any(|x| x.message.contains("left out")));
    }
}
