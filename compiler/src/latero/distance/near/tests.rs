//! The ways to a tile's nearest segments against each other: the grid
//! search against the sweep, the least distance given against the exact
//! minimum, and the layer's grid against each tile's.

use proptest::prelude::*;

use super::*;

/// The tiles of the layer grid tests' layers, (columns, rows).
const GRID_TILES: (usize, usize) = (3, 3);

/// The layer grid tests' set-up: `segs` binned into the tiles of a
/// [`GRID_TILES`] layer at `origin` with lattice pitch `h`, and the
/// layer's grid of them (one slot per part kind, as one style's layer).
fn layer_grid_of(segs: &[(Seg, Part, f64)], origin: (f64, f64), h: f64, margin: f64) -> (Vec<Vec<u32>>, LayerGrid) {
    let (cols, rows) = GRID_TILES;
    let tile = TILE_CELLS as f64 * h;
    let tiles = super::super::Tiles { origin, side: tile, cols, rows };
    let (buckets, spans) = super::super::buckets_of(segs, &tiles);
    let lattice = super::super::layer_grid::Lattice { tiles, h, margin, slots: slots(1, 1) };
    let grid = LayerGrid::new(segs, (&buckets, spans.clone()), &lattice, |p| slot_of(p, 1, 1), 0, MAX_RINGS)
        .expect("a layer grid");
    // Each tile's counts, taken from the buckets, are those of every
    // segment's rows of tiles worked out again (as they were counted before).
    let mut stats = vec![(0u32, 0u32, 0u64); cols * rows];
    for (&(seg, part, m), sp) in segs.iter().zip(&spans) {
        let Some(s) = slot_of(part, 1, 1).filter(|_| sp[0] <= sp[1] && sp[2] <= sp[3]) else { continue };
        let whole = sp.map(usize::from);
        for row in whole[2]..=whole[3] {
            let (c0, c1) = tiles.row_cols(&seg, m, row, whole);
            for col in c0..=c1 {
                let t = &mut stats[row * cols + col];
                if super::super::layer_grid::is_own(s) {
                    t.0 += 1;
                } else {
                    t.1 += 1;
                }
                t.2 |= 1 << s;
            }
        }
    }
    for r in 0..rows {
        for c in 0..cols {
            let t = grid.tile((c, r));
            assert_eq!((t.own, t.rest, t.slots), stats[r * cols + c], "tile {c} {r}");
        }
    }
    (buckets, grid)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// The grid search and the segment sweep store the same minimum of
    /// every part at every sample wherever it is within the part's reach
    /// plus the margin (the exact minimum over all the segments there),
    /// and both something beyond it elsewhere.
    #[test]
    fn the_grid_search_finds_what_the_sweep_finds(
        segs in prop::collection::vec(((-2.0f64..6.0, -2.0f64..6.0), (-0.6f64..0.6, -0.6f64..0.6), 0u8..5, any::<bool>()), 1..300),
        h in prop::sample::select(vec![0.25, 0.5]),
        (reach, margin) in (0.2f64..1.5, 0.0f64..0.1),
    ) {
        // Slots: fill, band, occluder, one cut group, one clip.
        let segs: Vec<(Seg, Part, f64)> = segs
            .iter()
            .map(|&((x, y), (dx, dy), kind, long)| {
                let k = if long { 5.0 } else { 1.0 };
                let part = [Part::Fill, Part::Band, Part::Occluder, Part::Cut(0), Part::Clip(0)][kind as usize];
                let r = if matches!(part, Part::Band | Part::Cut(_)) { reach + 0.3 } else { reach };
                (((x, y), (x + k * dx, y + k * dy)), part, r)
            })
            .collect();
        let bucket: Vec<u32> = (0..segs.len() as u32).collect();
        let (mut grid, mut sweep) = (Near::new(1, vec![0.6]), Near::new(1, vec![0.6]));
        let corner = (0.0, 0.0);
        grid.run(&segs, &bucket, (corner, h, margin), None, None, (0, false));
        sweep.run(&segs, &bucket, (corner, h, margin), None, None, (usize::MAX, false));
        for slot in 0..grid.slots() {
            let reach = segs.iter().filter(|s| sweep.slot(s.1) == Some(slot)).map(|s| s.2 + margin).fold(0.0, f64::max);
            for t in 0..TILE_SAMPLES {
                let p = (corner.0 + (t % TILE_SIDE) as f64 * h, corner.1 + (t / TILE_SIDE) as f64 * h);
                let exact = segs
                    .iter()
                    .filter(|s| sweep.slot(s.1) == Some(slot))
                    .map(|&((a, b), _, _)| distance2_to_segment(p, a, b))
                    .fold(f64::INFINITY, f64::min);
                let (g, s) = (grid.at(slot, t), sweep.at(slot, t));
                if exact <= reach * reach {
                    prop_assert_eq!(g, exact, "grid, slot {} sample {}", slot, t);
                    prop_assert_eq!(s, exact, "sweep, slot {} sample {}", slot, t);
                } else {
                    prop_assert!(g > reach * reach && s > reach * reach, "slot {slot} sample {t}: {g} {s} beyond {reach}");
                }
            }
        }
    }

    /// Where [`Near::least`] gives a part's least distance at a sample
    /// (after the grid search or the sweep), it is the exact minimum
    /// over the part's segments; fails if it were trusted farther than
    /// the part's reach plus the margin.
    #[test]
    fn the_least_distance_given_is_the_exact_minimum(
        segs in prop::collection::vec(((-2.0f64..6.0, -2.0f64..6.0), (-0.6f64..0.6, -0.6f64..0.6), 0u8..5), 1..300),
        h in prop::sample::select(vec![0.25, 0.5]),
        (reach, margin) in (0.2f64..1.5, 0.0f64..0.1),
        grid_from in prop::sample::select(vec![0, usize::MAX]),
    ) {
        let parts = [Part::Fill, Part::Band, Part::Occluder, Part::Cut(0), Part::Clip(0)];
        let segs: Vec<(Seg, Part, f64)> = segs
            .iter()
            .map(|&((x, y), (dx, dy), kind)| (((x, y), (x + dx, y + dy)), parts[kind as usize], reach))
            .collect();
        let bucket: Vec<u32> = (0..segs.len() as u32).collect();
        let mut near = Near::new(1, vec![0.6]);
        near.run(&segs, &bucket, ((0.0, 0.0), h, margin), None, None, (grid_from, false));
        for part in parts {
            for t in 0..TILE_SAMPLES {
                let p = ((t % TILE_SIDE) as f64 * h, (t / TILE_SIDE) as f64 * h);
                let exact = segs
                    .iter()
                    .filter(|s| s.1 == part)
                    .map(|&((a, b), _, _)| distance2_to_segment(p, a, b))
                    .fold(f64::INFINITY, f64::min);
                match near.least(part, t) {
                    Some(v) => prop_assert_eq!(v.to_bits(), exact.to_bits(), "{:?} sample {}", part, t),
                    // Well within the reach it is given.
                    None => prop_assert!(exact > (reach + margin).powi(2) / 2.0, "{:?} sample {}: none", part, t),
                }
            }
        }
    }

    /// The nearest segments to a lattice point that the rings of the
    /// layer's grid find are what `nearest_first` keeps of the tile's
    /// bucket (one part's, or every part's), bit for bit and in the
    /// same order (ties by segment number, shared ends included); fails
    /// if the search stopped a ring early.
    #[test]
    fn the_nearest_in_the_layer_grid_are_nearest_firsts(
        segs in prop::collection::vec(((-1.5f64..7.5, -1.5f64..7.5), (-0.6f64..0.6, -0.6f64..0.6), 0u8..5, any::<bool>()), 1..400),
        h in prop::sample::select(vec![0.25, 0.3]),
        (reach, margin) in (0.2f64..1.0, 0.0f64..0.1),
        max in prop::sample::select(vec![0usize, 1, 2, 5, 24, 48]),
        (pi, pj) in (0usize..TILE_SIDE, 0usize..TILE_SIDE),
        part in prop::sample::select(vec![None, Some(Part::Fill), Some(Part::Band), Some(Part::Cut(0)), Some(Part::Clip(0))]),
    ) {
        // Chained segments: every other one starts where the last ended (shared ends, equal distances).
        let mut last = (0.0, 0.0);
        let segs: Vec<(Seg, Part, f64)> = segs
            .iter()
            .enumerate()
            .map(|(n, &((x, y), (dx, dy), kind, long))| {
                let k = if long { 5.0 } else { 1.0 };
                let part = [Part::Fill, Part::Band, Part::Occluder, Part::Cut(0), Part::Clip(0)][kind as usize];
                let r = if matches!(part, Part::Band | Part::Cut(_)) { reach + 0.3 } else { reach };
                let a = if n % 2 == 1 { last } else { (x, y) };
                last = (a.0 + k * dx, a.1 + k * dy);
                ((a, last), part, r)
            })
            .collect();
        let cols = GRID_TILES.0;
        let (buckets, grid) = layer_grid_of(&segs, (0.0, 0.0), h, margin);
        let want_slot = part.map(|p| slot_of(p, 1, 1).expect("a slot"));
        for (k, bucket) in buckets.iter().enumerate() {
            let (c, r) = (k % cols, k / cols);
            let p = ((c * TILE_CELLS + pi) as f64 * h, (r * TILE_CELLS + pj) as f64 * h);
            let sub = SUB;
            let xy = grid.corner((c, r), (pi as isize * sub, pj as isize * sub));
            let taken = |s: usize| want_slot.is_none_or(|w| w == s);
            let groups = match want_slot {
                Some(s) => [super::super::layer_grid::is_own(s), !super::super::layer_grid::is_own(s)],
                None => [true, true],
            };
            let found = grid.nearest_to(&segs, ((c, r), xy, p), groups, taken, max).expect("both groups binned");
            let want = super::super::nearest_first(
                bucket
                    .iter()
                    .filter(|&&n| part.is_none_or(|q| segs[n as usize].1 == q))
                    .map(|&n| (distance2_to_segment(p, segs[n as usize].0.0, segs[n as usize].0.1), n)),
                max,
            );
            let bits = |v: &[(f64, u32)]| v.iter().map(|&(d, n)| (d.to_bits(), n)).collect::<Vec<_>>();
            prop_assert_eq!(bits(&found), bits(&want), "tile {:?} point {:?}", (c, r), (pi, pj));
        }
    }

    /// The search in the layer's grid stores at every sample of every
    /// tile (and at the cell centres, one grid cell on) what the tile's
    /// own grid stores: the exact minimum over the tile's bucket
    /// wherever it is within the part's reach plus the margin, and
    /// something beyond it elsewhere; segments of other tiles' buckets
    /// in the same cells are not taken.
    #[test]
    fn the_layer_grid_finds_what_each_tiles_grid_finds(
        segs in prop::collection::vec(((-1.5f64..7.5, -1.5f64..7.5), (-0.6f64..0.6, -0.6f64..0.6), 0u8..5, any::<bool>()), 1..400),
        h in prop::sample::select(vec![0.25, 0.3]),
        (reach, margin) in (0.2f64..1.0, 0.0f64..0.1),
        origin in (-0.7f64..0.0, -0.7f64..0.0),
    ) {
        let segs: Vec<(Seg, Part, f64)> = segs
            .iter()
            .map(|&((x, y), (dx, dy), kind, long)| {
                let k = if long { 5.0 } else { 1.0 };
                let part = [Part::Fill, Part::Band, Part::Occluder, Part::Cut(0), Part::Clip(0)][kind as usize];
                let r = if matches!(part, Part::Band | Part::Cut(_)) { reach + 0.3 } else { reach };
                (((x, y), (x + k * dx, y + k * dy)), part, r)
            })
            .collect();
        let cols = GRID_TILES.0;
        let (buckets, grid) = layer_grid_of(&segs, origin, h, margin);
        let (mut by_layer, mut by_tile) = (Near::new(1, vec![0.6]), Near::new(1, vec![0.6]));
        for (k, bucket) in buckets.iter().enumerate() {
            let (c, r) = (k % cols, k / cols);
            for shift in [0, 1] {
                let corner = (
                    origin.0 + (c * TILE_CELLS) as f64 * h + shift as f64 * h / 2.0,
                    origin.1 + (r * TILE_CELLS) as f64 * h + shift as f64 * h / 2.0,
                );
                let at = InLayer { grid: &grid, tile: (c, r), shift };
                by_layer.run(&segs, bucket, (corner, h, margin), None, Some(at), (0, false));
                by_tile.run(&segs, bucket, (corner, h, margin), None, None, (0, false));
                for slot in 0..by_tile.slots() {
                    let mine: Vec<&(Seg, Part, f64)> =
                        bucket.iter().map(|&n| &segs[n as usize]).filter(|s| by_tile.slot(s.1) == Some(slot)).collect();
                    let reach = mine.iter().map(|s| s.2 + margin).fold(0.0, f64::max);
                    for t in 0..TILE_SAMPLES {
                        let p = (corner.0 + (t % TILE_SIDE) as f64 * h, corner.1 + (t / TILE_SIDE) as f64 * h);
                        let exact =
                            mine.iter().map(|&&((a, b), _, _)| distance2_to_segment(p, a, b)).fold(f64::INFINITY, f64::min);
                        let (l, g) = (by_layer.at(slot, t), by_tile.at(slot, t));
                        if exact <= reach * reach {
                            prop_assert_eq!(l, exact, "layer, tile {:?} shift {} slot {} sample {}", (c, r), shift, slot, t);
                            prop_assert_eq!(g, exact, "tile, tile {:?} shift {} slot {} sample {}", (c, r), shift, slot, t);
                        } else {
                            prop_assert!(l > reach * reach && g > reach * reach, "slot {slot} sample {t}: {l} {g} beyond {reach}");
                        }
                    }
                }
            }
        }
    }
}
