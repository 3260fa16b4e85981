//! The per-tile accessors (`DistanceLayer::each_tile`, `DistanceView::each_tile`,
//! `Tile`): every tile of a layer once, row by row; its own records and
//! samples, read the same from the owned layer and from the bytes; its
//! samples and codes what the SPEC's reference (`distance_at`) plays.

use taxel_format::{
    BundleView, ChunkView, DISTANCE_ZERO, TILE_CELLS, TILE_SAMPLES, TILE_SIDE, TileEntry, TileGroup, TileKind,
    fine_entry, sample,
};

/// The sample bundle's distance layer read in place, for `f`.
fn with_view(f: impl FnOnce(taxel_format::DistanceView<'_>)) {
    let bytes = sample::every_kind().to_bytes().expect("a valid bundle");
    let view = BundleView::parse(&bytes).expect("it reads back");
    let dv = view.chunks().find_map(|c| if let ChunkView::Distance(d) = c { Some(d) } else { None });
    f(dv.expect("the distance chunk"));
}

#[test]
fn every_tile_comes_once_with_its_own_records_and_samples() {
    let layer = sample::distance_layer();
    let tiles: Vec<_> = layer.each_tile().collect();
    assert_eq!(tiles.len(), (layer.tile_cols * layer.tile_rows) as usize);
    for (i, t) in tiles.iter().enumerate() {
        assert_eq!((t.col as usize, t.row as usize), (i % layer.tile_cols as usize, i / layer.tile_cols as usize));
        assert_eq!(t.entry, TileEntry::of(layer.tiles[i]));
        let h = layer.pitch_mm as f64;
        let want = (layer.origin_x.0 as f64 + (8 * t.col) as f64 * h, layer.origin_y.0 as f64 + (8 * t.row) as f64 * h);
        assert_eq!(t.corner_mm, want);
        match t.entry {
            TileEntry::Stored(k) => {
                assert_eq!((t.refinement(), t.channels(), t.side()), (1, 1, TILE_SIDE));
                for (x, y) in [(0, 0), (8, 0), (3, 5), (8, 8)] {
                    let at = layer.samples[k as usize * TILE_SAMPLES + y * TILE_SIDE + x];
                    assert_eq!(t.sample(0, x, y), Some(at));
                }
                assert_eq!(t.sample(0, 9, 0), None);
                assert_eq!(t.sample(1, 0, 0), None);
            }
            e => {
                assert_eq!(t.side(), 0);
                assert_eq!(t.sample(0, 0, 0), None);
                for (u, w) in [(0.0, 0.0), (2.5, 7.25), (8.0, 8.0)] {
                    assert_eq!(t.code(u, w), e.code(&layer.planes, u, w), "{e:?} at ({u}, {w})");
                }
            }
        }
    }
    // Read in place, the same tiles.
    with_view(|dv| {
        let viewed: Vec<_> = dv.each_tile().collect();
        assert_eq!(viewed.len(), tiles.len());
        for (a, b) in tiles.iter().zip(&viewed) {
            assert_eq!((a.col, a.row, a.entry, a.corner_mm), (b.col, b.row, b.entry, b.corner_mm));
            assert_eq!(a.records(), b.records());
            for (x, y) in [(0, 0), (4, 7), (8, 8)] {
                assert_eq!(a.sample(0, x, y), b.sample(0, x, y));
            }
        }
        assert!(dv.tile(dv.tile_cols, 0).is_none() && dv.tile(0, dv.tile_rows).is_none());
    });
}

/// A fine tile's samples, as [`taxel_format::Tile::sample`] indexes them,
/// are the codes the SPEC's reference plays at the fine lattice's points.
#[test]
fn a_fine_tiles_samples_are_its_fine_lattices_codes() {
    for (fine, pair) in [(2u32, false), (4, false), (2, true)] {
        let f = fine as usize;
        let channels = 1 + pair as usize;
        let mut layer = sample::distance_layer();
        (layer.tile_cols, layer.tile_rows, layer.planes) = (1, 1, Vec::new());
        layer.tiles = vec![fine_entry(0, fine, pair).expect("an entry")];
        // Channel c's code at fine point (x, y): a slope, the second channel steeper.
        let code = |c: usize, x: usize, y: usize| (100 + x + 2 * y + 40 * c).min(255) as u8;
        layer.samples = Vec::new();
        for c in 0..channels {
            for b in 0..f {
                for a in 0..f {
                    for j in 0..TILE_SIDE {
                        for i in 0..TILE_SIDE {
                            layer.samples.push(code(c, TILE_CELLS * a + i, TILE_CELLS * b + j));
                        }
                    }
                }
            }
        }
        let t = layer.tile(0, 0).expect("the tile");
        assert_eq!((t.kind(), t.kind().group()), (TileKind::Fine, TileGroup::Fine));
        assert_eq!((t.refinement(), t.channels(), t.side()), (f, channels, TILE_CELLS * f + 1));
        for y in 0..t.side() {
            for x in 0..t.side() {
                for c in 0..channels {
                    assert_eq!(t.sample(c, x, y), Some(code(c, x, y)), "channel {c} at ({x}, {y})");
                }
                // The played code is the lesser channel's (the first, here);
                // the lattice's far sides belong to no tile of this layer.
                if x + 1 == t.side() || y + 1 == t.side() {
                    continue;
                }
                let h = layer.pitch_mm / fine as f32;
                let (px, py) = (layer.origin_x.0 + x as f32 * h, layer.origin_y.0 + y as f32 * h);
                let want = (code(0, x, y) as f32 - DISTANCE_ZERO as f32) * layer.step_mm;
                let got = layer.distance_at(px, py).expect("inside the lattice");
                assert!((got - want).abs() < 1e-3 * layer.step_mm.max(1e-3), "({x}, {y}): {got} vs {want}");
            }
        }
        assert_eq!(t.sample(channels, 0, 0), None);
    }
}

#[test]
fn kinds_and_groups_cover_every_entry() {
    // One entry of each kind, decoded to that kind; counted in its group.
    for kind in TileKind::ALL {
        assert_eq!(TileEntry::of(kind.first_entry()).kind(), kind);
    }
    let groups: Vec<TileGroup> = TileKind::ALL.iter().map(|k| k.group()).collect();
    for g in
        [TileGroup::Constant, TileGroup::Stored, TileGroup::Fine, TileGroup::Plane, TileGroup::Corner, TileGroup::Bend]
    {
        assert!(groups.contains(&g), "{g:?}");
    }
}
