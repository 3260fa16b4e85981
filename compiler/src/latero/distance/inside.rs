//! Which lattice points lie inside a layer's fills, occluders and clips:
//! each row of points swept across the outlines' crossings, for the whole
//! lattice at once or, for a fine tile, the shapes of its row of tiles.

use super::{LayerGeometry, Seg, ceil_f64, closed_segments, floor_f64};
use crate::geometry::{FillRule, Polyline};

/// Whether each lattice point `(i, j)` (row-major, `nx` wide) is inside the
/// union of the fills, by sweeping each row's crossings with every fill
/// outline (the same half-open rule as [`contains`](crate::geometry::contains)).
pub(super) fn fill_bits(
    fills: &[(&[Polyline], FillRule)],
    ox: f64,
    oy: f64,
    h: f64,
    nx: usize,
    ny: usize,
) -> Vec<bool> {
    let all = fills.iter().enumerate().flat_map(|(shape, (pls, _))| pls.iter().map(move |pl| (shape, pl)));
    fill_bits_of(fills, all, (ox, oy, h), (nx, ny))
}

/// [`fill_bits`] from the polylines `some` of `fills` (shape number and
/// polyline): the same bits wherever the others cross none of the rows
/// (a fine tile's rows, [`RowShapes`]).
fn fill_bits_of<'p>(
    fills: &[(&[Polyline], FillRule)],
    some: impl Iterator<Item = (usize, &'p Polyline)>,
    (ox, oy, h): (f64, f64, f64),
    (nx, ny): (usize, usize),
) -> Vec<bool> {
    let mut bits = vec![false; nx * ny];
    if fills.is_empty() {
        return bits;
    }
    // Each edge with the first and last lattice rows it spans, by first
    // row; the rows are swept in order with the edges that span the row in
    // hand (an edge kept once, not once per row it spans: a scribble's
    // edges span a hundred rows each, and copied into every row they took
    // 40 bytes a row, most of a gigabyte for 300,000 of them).
    let mut edges: Vec<(usize, usize, Seg, usize)> = Vec::new();
    for (shape, pl) in some {
        for s in closed_segments(pl) {
            let (lo, hi) = (s.0.1.min(s.1.1), s.0.1.max(s.1.1));
            let j0 = ceil_f64((lo - oy) / h).max(0.0);
            let j1 = floor_f64((hi - oy) / h).min(ny as f64 - 1.0);
            // NaN bounds (never from finite geometry) give no rows.
            if j0.is_nan() || j1.is_nan() || j0 > j1 {
                continue;
            }
            edges.push((j0 as usize, j1 as usize, s, shape));
        }
    }
    edges.sort_by_key(|e| e.0);
    let mut next = 0;
    // The edges spanning the current row (indices into `edges`).
    let mut active: Vec<usize> = Vec::new();
    // Each shape's winding number and crossing count so far along the row
    // (indexed by shape, reset after each row for the shapes it crossed).
    let mut state: Vec<(i32, u32)> = vec![(0, 0); fills.len()];
    let mut xs: Vec<(f64, usize, i32)> = Vec::new();
    for j in 0..ny {
        active.retain(|&k| edges.get(k).is_some_and(|e| e.1 >= j));
        while let Some(e) = edges.get(next).filter(|e| e.0 <= j) {
            if e.1 >= j {
                active.push(next);
            }
            next += 1;
        }
        if active.is_empty() && next >= edges.len() {
            break;
        }
        let y = oy + j as f64 * h;
        // Crossings to the right of a point decide it; sweep from the right.
        xs.clear();
        let spanning = active.iter().filter_map(|&k| edges.get(k)).map(|&(_, _, s, shape)| (s, shape));
        xs.extend(spanning.filter(|((a, b), _)| (a.1 <= y) != (b.1 <= y)).map(|((a, b), shape)| {
            let x = a.0 + (y - a.1) / (b.1 - a.1) * (b.0 - a.0);
            (x, shape, if b.1 > a.1 { 1 } else { -1 })
        }));
        if xs.is_empty() {
            continue;
        }
        xs.sort_by(|a, b| b.0.total_cmp(&a.0));
        for &(_, shape, _) in &xs {
            state[shape] = (0, 0);
        }
        let mut inside_count = 0i32;
        let mut k = 0;
        for i in (0..nx).rev() {
            let x = ox + i as f64 * h;
            while k < xs.len() && xs[k].0 > x {
                let (_, shape, dir) = xs[k];
                let rule = fills[shape].1;
                let e = &mut state[shape];
                let was = is_in(*e, rule);
                e.0 += dir;
                e.1 += 1;
                let now = is_in(*e, rule);
                inside_count += now as i32 - was as i32;
                k += 1;
            }
            bits[j * nx + i] = inside_count > 0;
        }
    }
    bits
}

/// The polylines of a layer's shapes (fills, occluders or one clip) whose
/// vertical extent meets each row of tiles, as (shape, polyline) numbers:
/// a row sweep of points in that row crosses no other.
struct RowShapes(Vec<Vec<(u32, u32)>>);

impl RowShapes {
    /// Over `rows` rows of tiles `tile` mm high from page y `oy`.
    fn new(shapes: &[(&[Polyline], FillRule)], oy: f64, tile: f64, rows: usize) -> RowShapes {
        let mut out = vec![Vec::new(); rows];
        for (k, (pls, _)) in shapes.iter().enumerate() {
            for (i, pl) in pls.iter().enumerate() {
                let (lo, hi) =
                    pl.points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.1), b.max(p.1)));
                // Rows from the one holding `lo` to the one holding `hi`, one more each way for rounding.
                let first = floor_f64((lo - oy) / tile - 1.0).max(0.0);
                let last = floor_f64((hi - oy) / tile + 1.0).min(rows as f64 - 1.0);
                // (NaN bounds, from no points, give no rows.)
                if first.is_nan() || last.is_nan() || first > last {
                    continue;
                }
                for row in out.iter_mut().take(last as usize + 1).skip(first as usize) {
                    row.push((k as u32, i as u32));
                }
            }
        }
        RowShapes(out)
    }

    /// Inside bits of `shapes` (those this index was built from) at the
    /// `n` x `n` points `hf` apart from `corner`, which lie in tile row `row`.
    fn bits(&self, shapes: &[(&[Polyline], FillRule)], row: usize, corner: (f64, f64), hf: f64, n: usize) -> Vec<bool> {
        let some = self.0.get(row).into_iter().flatten().filter_map(|&(k, i)| {
            let (pls, _) = shapes.get(k as usize)?;
            Some((k as usize, pls.get(i as usize)?))
        });
        fill_bits_of(shapes, some, (corner.0, corner.1, hf), (n, n))
    }
}

/// The [`RowShapes`] of a layer's fills, occluders and clips, built when a
/// fine tile is first measured.
pub(super) struct FineRows {
    fills: RowShapes,
    occluders: RowShapes,
    clips: Vec<RowShapes>,
}

impl FineRows {
    pub(super) fn new(g: &LayerGeometry<'_>, oy: f64, tile: f64, rows: usize) -> FineRows {
        FineRows {
            fills: RowShapes::new(&g.fills, oy, tile, rows),
            occluders: RowShapes::new(&g.occluders, oy, tile, rows),
            clips: g.clips.iter().map(|c| RowShapes::new(std::slice::from_ref(c), oy, tile, rows)).collect(),
        }
    }

    /// Inside-the-fills, inside-the-occluders and inside-each-clip bits at
    /// the `n` x `n` points `hf` apart from `corner`, in tile row `row`.
    pub(super) fn bits(
        &self,
        g: &LayerGeometry<'_>,
        row: usize,
        corner: (f64, f64),
        hf: f64,
        n: usize,
    ) -> (Vec<bool>, Vec<bool>, Vec<Vec<bool>>) {
        (
            self.fills.bits(&g.fills, row, corner, hf, n),
            self.occluders.bits(&g.occluders, row, corner, hf, n),
            self.clips.iter().zip(&g.clips).map(|(r, c)| r.bits(std::slice::from_ref(c), row, corner, hf, n)).collect(),
        )
    }
}

fn is_in(s: (i32, u32), rule: FillRule) -> bool {
    match rule {
        FillRule::NonZero => s.0 != 0,
        FillRule::EvenOdd => s.1 % 2 == 1,
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::fill_bits;
    use crate::geometry::{FillRule, Polyline, contains};

    proptest! {
        /// Every lattice point is inside the fills exactly where
        /// [`contains`] says it is inside one of them, for self-crossing
        /// scribbles under either rule, several shapes at once, and a
        /// lattice that begins inside the drawing or before it; fails if
        /// the row sweep dropped or doubled an edge that spans several rows.
        #[test]
        fn fill_bits_agree_with_contains_point_by_point(
            shapes in prop::collection::vec(
                (prop::collection::vec((0.0f64..10.0, 0.0f64..8.0), 3..40), any::<bool>()),
                1..4,
            ),
            origin in (-2.0f64..3.0, -2.0f64..3.0),
            h in prop::sample::select(vec![0.13, 0.25, 0.5]),
        ) {
            let shapes: Vec<(Vec<Polyline>, FillRule)> = shapes
                .into_iter()
                .map(|(points, even_odd)| {
                    let rule = if even_odd { FillRule::EvenOdd } else { FillRule::NonZero };
                    (vec![Polyline { points, closed: true }], rule)
                })
                .collect();
            let fills: Vec<(&[Polyline], FillRule)> = shapes.iter().map(|(p, r)| (&p[..], *r)).collect();
            let (nx, ny) = (40, 36);
            let bits = fill_bits(&fills, origin.0, origin.1, h, nx, ny);
            for j in 0..ny {
                for i in 0..nx {
                    let p = (origin.0 + i as f64 * h, origin.1 + j as f64 * h);
                    let want = shapes.iter().any(|(pls, rule)| contains(pls, p, *rule));
                    prop_assert_eq!(bits[j * nx + i], want, "point {:?}", (i, j));
                }
            }
        }
    }
}
