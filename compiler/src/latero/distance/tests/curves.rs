//! Curved and meeting edges against exact geometry: circles and holes as
//! arc tiles, band junctions as segments tiles, sides meeting holes as cut
//! arcs, and the wedges fine tiles keep.

use super::*;

/// A circle of radius `r` round `c` as a closed polygon of `n` vertices on it.
fn ring(c: (f64, f64), r: f64, n: usize) -> Polyline {
    let at = |k: usize| {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        (c.0 + r * a.cos(), c.1 + r * a.sin())
    };
    Polyline { points: (0..n).map(at).collect(), closed: true }
}

/// Points along a circle of radius `r` round `c`, `off` mm out from it.
fn along_circle(c: (f64, f64), r: f64, offsets: &[f64]) -> Vec<(f64, f64)> {
    (0..997)
        .flat_map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 997.0;
            offsets.iter().map(move |o| (c.0 + (r + o) * a.cos(), c.1 + (r + o) * a.sin()))
        })
        .collect()
}

#[test]
fn a_filled_circle_plays_its_exact_distance_at_the_edge() {
    // 720 vertices: the chords stay within 0.08 µm of the circle, a
    // hundredth of a code.
    let (c, r) = ((20.0, 15.0), 8.0);
    let disc = [ring(c, r, 720)];
    let g = LayerGeometry { fills: vec![(&disc, FillRule::NonZero)], ..Default::default() };
    let p = params(0.5, 0.0);
    let f = build_field(&g, p).expect("a field");
    // Every tile the circle crosses is a cone (a bend tile round its centre).
    assert_eq!(f.stored(), 0);
    let ramp = taxel_format::edge_ramp(0.0, f.step_mm as f32) as f64;
    let amp = |d: f64| (0.5 + d / ramp).clamp(0.0, 1.0);
    // Within the hard edge's ramp, where a sampled tile was off by up to
    // the whole amplitude, the amplitude is the exact distance's within 2%.
    for q in along_circle(c, r, &[-0.006, -0.003, -0.001, 0.0, 0.0015, 0.004, 0.05, -0.3]) {
        let (d, e) = (field_distance(&f, 0.5, q).expect("in the lattice"), exact_signed_distance(&g, p.page, q));
        assert!((amp(d) - amp(e)).abs() <= 0.02, "{q:?}: field {d}, exact {e}");
    }
}

#[test]
fn a_band_round_a_circle_and_a_hole_play_their_exact_distance_at_the_edges() {
    let (c, r, w) = ((20.0, 15.0), 8.0, 1.5);
    let lines = [ring(c, r, 720)];
    // A band round the circle: both its sides in one tile are an arc tile's ring.
    let band = LayerGeometry { band: Some((vec![&lines[..]], w)), ..Default::default() };
    // A square with a circular hole (even-odd): the hole's side is an arc tile.
    let holed = [square(8.0, 3.0, 24.0), ring(c, r, 720)];
    let hole = LayerGeometry { fills: vec![(&holed, FillRule::EvenOdd)], ..Default::default() };
    let p = params(0.5, 0.0);
    for (g, sides) in [(&band, [r - w / 2.0, r + w / 2.0]), (&hole, [r, r])] {
        let f = build_field(g, p).expect("a field");
        assert_eq!(f.stored(), 0, "every tile a circle crosses is a cone or an arc");
        let arcs =
            f.tiles.iter().filter(|&&e| matches!(taxel_format::TileEntry::of(e), taxel_format::TileEntry::Arc(_)));
        assert!(arcs.count() > 0);
        let ramp = taxel_format::edge_ramp(0.0, f.step_mm as f32) as f64;
        let amp = |d: f64| (0.5 + d / ramp).clamp(0.0, 1.0);
        for side in sides {
            for q in along_circle(c, side, &[-0.004, -0.001, 0.0, 0.002, 0.006, 0.2]) {
                let d = field_distance(&f, 0.5, q).expect("in the lattice");
                let e = exact_signed_distance(g, p.page, q);
                assert!((amp(d) - amp(e)).abs() <= 0.02, "{q:?}: field {d}, exact {e}");
            }
        }
    }
}

/// A band round a circle as a drawing's `<circle>` reaches the compiler:
/// four cubic Béziers, flattened on the circle into chords within 0.5 µm of
/// it. Where a tile holds the band's outer side over a chord's vertex, the
/// band's bend at that vertex plays the chords too, up to the sagitta
/// inside the circle; the circle through the vertices plays the drawing
/// itself. At the 0.25 mm lattice (`taxel report`'s finest rung, whose
/// hard ramp is 4 µm) the chords put the experiment-5 circle icon's edge
/// 45 nm in at an actuator, 12 steps of its vibration. Every point within
/// the ramp of either side plays the circle's amplitude within a 10-bit
/// step, at both lattices.
#[test]
fn a_band_round_a_drawn_circle_plays_the_circle_not_its_chords() {
    // The experiment-5 circle icon's outline on its 110 by 60 mm page.
    let (c, r, w) = ((55.0, 30.0), 15.0, 1.5);
    let quarter = std::f64::consts::FRAC_PI_2;
    let mut pb = resvg::tiny_skia::PathBuilder::new();
    pb.move_to((c.0 + r) as f32, c.1 as f32);
    for k in 0..4 {
        crate::geometry::tests::arc_cubic(&mut pb, c, r, k as f64 * quarter, quarter);
    }
    pb.close();
    let path = pb.finish().expect("a path");
    let lines = crate::geometry::flatten_with(&path, usvg::Transform::identity(), crate::geometry::Flattening::DEFAULT);
    let g = LayerGeometry { band: Some((vec![&lines[..]], w)), ..Default::default() };
    for pitch in [0.5, 0.25] {
        let f = build_field(&g, FieldParams { pitch_mm: pitch, soft_mm: 0.0, page: (0.0, 0.0, 110.0, 60.0) })
            .expect("a field");
        let ramp = taxel_format::edge_ramp(0.0, f.step_mm as f32) as f64;
        let amp = |d: f64| (0.5 + d / ramp).clamp(0.0, 1.0);
        for side in [r - w / 2.0, r + w / 2.0] {
            for q in along_circle(c, side, &[-0.0015, -0.001, -0.0002, 0.0, 0.0002, 0.001, 0.0015]) {
                let d = field_distance(&f, pitch, q).expect("in the lattice");
                // Positive within the band.
                let e = w / 2.0 - ((q.0 - c.0).hypot(q.1 - c.1) - r).abs();
                assert!((amp(d) - amp(e)).abs() <= 1e-3, "pitch {pitch}, {q:?}: field {d}, circle {e}");
            }
        }
    }
}

/// A small circle painted over a grated region (a map's town, 1.2 mm in
/// radius): the hole it makes plays the circle exactly. Its tiles were
/// stored, whose interpolation put the hole's edge up to 0.029 mm inside
/// the circle, between the lattice points and cell centres the writer
/// checks: every actuator the trace took over that ring played the full
/// amplitude against 0 (`tala-plain`, RMS 6 steps).
#[test]
fn a_small_circle_painted_over_a_region_cuts_its_exact_hole() {
    for (c, r) in [((17.0, 18.0), 1.2), ((22.3, 12.1), 1.2), ((30.0, 15.0), 2.5)] {
        let region = [square(c.0 - 6.0, c.1 - 6.0, 12.0)];
        let town = [ring(c, r, 720)];
        let g = LayerGeometry {
            fills: vec![(&region, FillRule::NonZero)],
            occluders: vec![(&town, FillRule::NonZero)],
            ..Default::default()
        };
        let p = params(0.5, 0.0);
        let f = build_field(&g, p).expect("a field");
        assert_eq!(f.stored(), 0, "{c:?}: every tile the town crosses is a cone or an arc");
        let ramp = taxel_format::edge_ramp(0.0, f.step_mm as f32) as f64;
        let amp = |d: f64| (0.5 + d / ramp).clamp(0.0, 1.0);
        for q in along_circle(c, r, &[-0.029, -0.02, -0.01, -0.004, -0.001, 0.0, 0.002, 0.006, 0.02, 0.2]) {
            let (d, e) = (field_distance(&f, 0.5, q).expect("in the lattice"), exact_signed_distance(&g, p.page, q));
            assert!((amp(d) - amp(e)).abs() <= 0.02, "{c:?} {q:?}: field {d}, exact {e}");
        }
    }
}

/// Whether the tile of a built field at `p` is a segments tile (format 4.2).
fn segments_at(f: &Field, h: f64, p: (f64, f64)) -> bool {
    let (tx, ty) = (((p.0 - f.origin.0) / h) as usize / TILE_CELLS, ((p.1 - f.origin.1) / h) as usize / TILE_CELLS);
    f.tiles
        .get(ty * f.tile_cols as usize + tx)
        .is_some_and(|&e| matches!(taxel_format::TileEntry::of(e), taxel_format::TileEntry::Segments(_)))
}

#[test]
fn three_bands_meeting_at_a_point_play_their_exact_distance_round_the_junction() {
    // Three centre lines from (20.3, 14.7) at 0, 110 and 230 degrees (a
    // map's coast and two borders), bands 1.5 mm wide: the union has three
    // sharp concave corners between the bands. Cut out of a square
    // grating, the same lines leave three sharp convex corners.
    let v = (20.3, 14.7);
    let arm = |deg: f64| {
        let a = deg.to_radians();
        Polyline { points: vec![v, (v.0 + 9.0 * a.cos(), v.1 + 9.0 * a.sin())], closed: false }
    };
    let lines = [arm(0.0), arm(110.0), arm(230.0)];
    let band = LayerGeometry { band: Some((vec![&lines[..]], 1.5)), ..Default::default() };
    let sq = [square(8.0, 3.0, 24.0)];
    let cut = LayerGeometry { fills: vec![(&sq, FillRule::NonZero)], cuts: vec![(&lines, 1.5)], ..Default::default() };
    let p = params(0.5, 0.0);
    for g in [&band, &cut] {
        let f = build_field(g, p).expect("a field");
        let ramp = taxel_format::edge_ramp(0.0, f.step_mm as f32) as f64;
        let amp = |d: f64| (0.5 + d / ramp).clamp(0.0, 1.0);
        // Within 1.5 mm of the junction no tile is stored (where a bend
        // plays the junction's tile, the third arm only grazes it), and in
        // the segments tiles there, on a grid finer than the lattice and
        // off its points, the amplitude is the exact distance's within 2%
        // (a sampled tile rounded the corners by up to the whole amplitude).
        let mut checked = 0;
        for i in 0..=60 {
            for j in 0..=60 {
                let q = (v.0 - 1.5 + i as f64 * 0.0501, v.1 - 1.5 + j as f64 * 0.0497);
                let (tx, ty) = (
                    ((q.0 - f.origin.0) / 0.5) as usize / TILE_CELLS,
                    ((q.1 - f.origin.1) / 0.5) as usize / TILE_CELLS,
                );
                let e = f.tiles.get(ty * f.tile_cols as usize + tx).copied().unwrap_or(TILE_OUTSIDE);
                assert!(!matches!(taxel_format::TileEntry::of(e), taxel_format::TileEntry::Stored(_)), "{q:?} stored");
                if !segments_at(&f, 0.5, q) {
                    continue;
                }
                checked += 1;
                let (d, e) = (field_distance(&f, 0.5, q).expect("in the lattice"), exact_signed_distance(g, p.page, q));
                assert!((amp(d) - amp(e)).abs() <= 0.02, "{q:?}: field {d}, exact {e}");
            }
        }
        assert!(checked > 500, "{checked} points in segments tiles");
    }
}

/// Whether the tile of a built field at `p` is a cut arc (format 4.3).
fn cut_arc_at(f: &Field, h: f64, p: (f64, f64)) -> bool {
    let (tx, ty) = (((p.0 - f.origin.0) / h) as usize / TILE_CELLS, ((p.1 - f.origin.1) / h) as usize / TILE_CELLS);
    f.tiles.get(ty * f.tile_cols as usize + tx).is_some_and(|&e| match taxel_format::TileEntry::of(e) {
        taxel_format::TileEntry::Arc(r) => f.planes.get(r as usize + 1).is_some_and(taxel_format::is_cut_arc),
        _ => false,
    })
}

#[test]
fn a_side_and_a_hole_within_a_millimetre_play_their_exact_distance_as_cut_arcs() {
    // A square with a circular hole (a province and its lake) whose edge
    // comes within 0.8 mm of the square's top side: where both lie within
    // the clamp of one tile, no plane or arc plays it alone.
    let (c, r) = ((20.0, 8.8), 5.0);
    let holed = [square(8.0, 3.0, 24.0), ring(c, r, 720)];
    let g = LayerGeometry { fills: vec![(&holed, FillRule::EvenOdd)], ..Default::default() };
    let p = params(0.5, 0.0);
    let f = build_field(&g, p).expect("a field");
    assert_eq!(f.stored(), 0, "every tile is analytic");
    let ramp = taxel_format::edge_ramp(0.0, f.step_mm as f32) as f64;
    let amp = |d: f64| (0.5 + d / ramp).clamp(0.0, 1.0);
    // Along the circle and along the side, inside the hard edge's ramp and
    // off the lattice, in the cut arcs the amplitude is the exact
    // distance's within 2% (a sampled tile was off by up to the whole).
    let side = (0..997)
        .flat_map(|k| [-0.004, -0.001, 0.0, 0.002, 0.006, 0.3].map(|o| (8.0 + 24.0 * k as f64 / 997.0, 3.0 + o)));
    let mut checked = 0;
    for q in along_circle(c, r, &[-0.004, -0.001, 0.0, 0.002, 0.006, 0.3]).into_iter().chain(side) {
        if !cut_arc_at(&f, 0.5, q) {
            continue;
        }
        checked += 1;
        let (d, e) = (field_distance(&f, 0.5, q).expect("in the lattice"), exact_signed_distance(&g, p.page, q));
        assert!((amp(d) - amp(e)).abs() <= 0.02, "{q:?}: field {d}, exact {e}");
    }
    assert!(checked > 100, "{checked} points in cut arcs");
}

#[test]
fn a_curved_side_meeting_a_straight_one_plays_its_corner_as_a_cut_arc() {
    // A disc cut by a chord (a country's Bézier coast meeting a straight
    // border): at the two corners the lesser of the chord's plane and the
    // circle's cone is the miter outside, not the exact distance, which a
    // check of codes alone refused, so those tiles were stored and their
    // corners rounded (0.17 mm on a teacher's map).
    let (c, r, chord) = ((20.0, 14.0), 6.0, 11.0);
    let (t0, t1) = (-std::f64::consts::FRAC_PI_6, 7.0 * std::f64::consts::FRAC_PI_6);
    let arc = Polyline {
        points: (0..=720)
            .map(|k| t0 + (t1 - t0) * k as f64 / 720.0)
            .map(|t| (c.0 + r * t.cos(), c.1 + r * t.sin()))
            .collect(),
        closed: true,
    };
    let shapes = [arc];
    let g = LayerGeometry { fills: vec![(&shapes, FillRule::NonZero)], ..Default::default() };
    let p = params(0.5, 0.0);
    let f = build_field(&g, p).expect("a field");
    let half = (r * r - (c.1 - chord) * (c.1 - chord)).sqrt();
    let corners = [(c.0 - half, chord), (c.0 + half, chord)];
    for x in corners {
        let at = |p: (f64, f64)| {
            let (tx, ty) =
                (((p.0 - f.origin.0) / 0.5) as usize / TILE_CELLS, ((p.1 - f.origin.1) / 0.5) as usize / TILE_CELLS);
            taxel_format::TileEntry::of(f.tiles[ty * f.tile_cols as usize + tx])
        };
        assert!(
            cut_arc_at(&f, 0.5, x),
            "the tile of the corner at {x:?} is a cut arc: {:?}, stored {}",
            at(x),
            f.stored()
        );
    }
    assert_eq!(f.stored(), 0, "every tile is analytic");
    // Round each corner, off the lattice, inside and outside the hard edge's
    // ramp: the amplitude is the exact distance's within 2%, but within
    // the spot (SPOT_MM) round the corner point.
    let ramp = taxel_format::edge_ramp(0.0, f.step_mm as f32) as f64;
    let amp = |d: f64| (0.5 + d / ramp).clamp(0.0, 1.0);
    let mut checked = 0;
    for x in corners {
        for i in -60..=60 {
            for j in -60..=60 {
                let q = (x.0 + i as f64 * 0.0101, x.1 + j as f64 * 0.0097);
                if (q.0 - x.0).hypot(q.1 - x.1) <= bends::SPOT_MM {
                    continue;
                }
                let (d, e) =
                    (field_distance(&f, 0.5, q).expect("in the lattice"), exact_signed_distance(&g, p.page, q));
                assert!((amp(d) - amp(e)).abs() <= 0.02, "{q:?}: field {d}, exact {e}");
                checked += 1;
            }
        }
    }
    assert!(checked > 20_000, "{checked}");
}

/// A thin wedge of land between a lake and a river band crossing its shore
/// at about 8 degrees (the river over the lake of a teacher's map): no
/// analytic kind plays two curved edges, and stored samples round the
/// crease between them away, so before fine tiles (format 4.4) the wedge
/// was lost for up to 0.76 mm from where they cross. Fine tiles keep it:
/// wherever the exact distance is farther than 0.1 mm from the edge, the
/// field is on its side, even round the crossings (`taxel report` counts
/// those within 1 mm of them as corners; the writer checks its tolerance,
/// 0.03 mm, at points `h / 4` apart).
#[test]
fn a_thin_wedge_between_a_lake_and_a_river_is_kept_by_fine_tiles() {
    let land = [square(2.0, 2.0, 26.0)];
    let (c, a, b) = ((20.0, 18.0), 9.0, 4.5);
    let lake = [Polyline {
        points: (0..600)
            .map(|k| k as f64 * std::f64::consts::TAU / 600.0)
            .map(|t| (c.0 + a * t.cos(), c.1 + b * t.sin()))
            .collect(),
        closed: true,
    }];
    // A river gently curving across the lake's top: y = 13.6 + 0.1 d + 0.004 d², d = x − 20.
    let river = [Polyline {
        points: (0..=400)
            .map(|k| 8.0 + 20.0 * k as f64 / 400.0)
            .map(|x| (x, 13.6 + 0.1 * (x - 20.0) + 0.004 * (x - 20.0) * (x - 20.0)))
            .collect(),
        closed: false,
    }];
    let g = LayerGeometry {
        fills: vec![(&land, FillRule::NonZero)],
        cuts: vec![(&river, 0.35)],
        occluders: vec![(&lake, FillRule::NonZero)],
        ..Default::default()
    };
    let p = params(0.5, 0.0);
    let f = build_field(&g, p).expect("a field");
    let fine =
        f.tiles.iter().filter(|&&e| matches!(taxel_format::TileEntry::of(e), taxel_format::TileEntry::Fine { .. }));
    assert!(fine.count() > 0, "fine tiles where the river crosses the shore");
    // Round both crossings (x near 19.2 and 25.0), 0.02 mm apart.
    let tol = 0.1;
    let (mut wedge, mut checked) = (0, 0);
    for x0 in [17.5, 23.0] {
        for i in 0..200 {
            for j in 0..100 {
                let q = (x0 + i as f64 * 0.0201, 12.8 + j as f64 * 0.0199);
                let e = exact_signed_distance(&g, p.page, q);
                if e.abs() <= tol {
                    continue;
                }
                let d = field_distance(&f, 0.5, q).expect("in the lattice");
                assert!(d.signum() == e.signum(), "{q:?}: field {d}, exact {e}");
                checked += 1;
                wedge += usize::from(e > 0.0 && e < 0.2);
            }
        }
    }
    assert!(checked > 30_000 && wedge > 200, "{checked} points, {wedge} in the wedges");
}

/// An icon as experiment 5 draws it: a grated right triangle less its
/// vibrating outline cut out of it. The grating's edge is the outline's
/// inner offset; near an acute corner both offsets cross one tile, a wedge
/// that a corner tile of two cut lines plays (each segment's line less the
/// cut's half width), exactly, and the field matches the exact geometry
/// everywhere.
#[test]
fn a_grating_s_wedge_inside_a_cut_outline_is_a_corner_tile() {
    let tri = [Polyline { points: vec![(5.0, 3.0), (27.0, 25.0), (5.0, 25.0)], closed: true }];
    let g = LayerGeometry { fills: vec![(&tri, FillRule::NonZero)], cuts: vec![(&tri, 1.5)], ..Default::default() };
    let p = params(0.5, 0.0);
    check(&g, p, &grid_points(0.173)).expect("field within bounds");
    let f = build_field(&g, p).expect("a field");
    // Below the top acute corner, the wedge between the offsets of the leg
    // x = 5 and the hypotenuse y = x - 2 (both 0.75 mm in) crosses the tile
    // from (4, 6) to (8, 10).
    let q = (5.75, 8.0);
    let (tx, ty) = (((q.0 - f.origin.0) / 0.5) as usize / TILE_CELLS, ((q.1 - f.origin.1) / 0.5) as usize / TILE_CELLS);
    let e = f.tiles.get(ty * f.tile_cols as usize + tx).copied().unwrap_or(TILE_OUTSIDE);
    assert!(
        matches!(taxel_format::TileEntry::of(e), taxel_format::TileEntry::Corner(_)),
        "{:?}",
        taxel_format::TileEntry::of(e)
    );
    assert_amplitude_exact_round(&g, p, &f, q);
}

/// `tala-map`'s ash province and its key swatch, one grated layer, at the
/// 0.25 mm rung: the province's east corner (a 74° tip at (31.02, 26.69))
/// pokes into a tile between its samples, which all lie beyond the hard
/// edge's ramp, outside, and the tile was written as outside: the tip was
/// not felt (a corner edge error of 0.047 mm, one actuator off by 896
/// steps). A tile holding a fill's vertex is written as any other: the
/// amplitude round the tip is the exact distance's, and where the exact
/// edge is farther than the writer's tolerance (0.03 mm), the tip is felt.
#[test]
fn a_province_s_corner_tip_between_a_tile_s_samples_is_felt() {
    let ash = [
        Polyline { points: vec![(7.55, 25.27), (9.58, 10.34), (26.89, 6.73), (31.02, 26.69)], closed: true },
        ring((17.0, 18.0), 5.0, 720),
    ];
    let key = [square(73.0, 14.0, 8.0)];
    let g = LayerGeometry { fills: vec![(&ash, FillRule::EvenOdd), (&key, FillRule::NonZero)], ..Default::default() };
    let p = params(0.25, 0.0);
    let f = build_field(&g, p).expect("a field");
    let v: (f64, f64) = (31.02, 26.69);
    // Into the province along the corner's bisector, and round it.
    let (a, b): ((f64, f64), (f64, f64)) = ((26.89 - v.0, 6.73 - v.1), (7.55 - v.0, 25.27 - v.1));
    let (la, lb) = (a.0.hypot(a.1), b.0.hypot(b.1));
    let bis = (a.0 / la + b.0 / lb, a.1 / la + b.1 / lb);
    let bis = (bis.0 / bis.0.hypot(bis.1), bis.1 / bis.0.hypot(bis.1));
    let mut felt = 0;
    for t in [0.02, 0.03, 0.04, 0.05, 0.06, 0.08, 0.1, 0.15, 0.2] {
        let q = (v.0 + t * bis.0, v.1 + t * bis.1);
        let (d, e) = (field_distance(&f, 0.25, q).expect("in the lattice"), exact_signed_distance(&g, p.page, q));
        assert!((d - e).abs() <= 0.03, "{t} mm in, {q:?}: field {d}, exact {e}");
        felt += usize::from(d > 0.0);
    }
    assert!(felt >= 7, "{felt}");
}
