//! Circular arcs as bend tiles (SPEC.md section 6.2): a tile that one arc
//! of a circle crosses, a fill's curved side or a vibrating band's outer
//! side round a circle, plays `top − k |q − C|`, the exact distance to the
//! circle of centre `C`, instead of 81 samples.
//!
//! A sampled tile is exact only at its lattice points: between them the
//! bilinear interpolation of a curved distance is off by up to `h² / (8 r)`
//! (0.003 mm, 0.4 of a code, on a 10 mm circle at the default pitch), and
//! its codes are rounded to whole steps, while a hard edge's ramp is one
//! step wide. So an actuator within a step of a circle was off by up to
//! the full amplitude, which made 99% of the squared error of the
//! experiment-1 scenes (`taxel report`, docs/report.md).
//!
//! A bend tile plays `top − k · min(dist(q, ray 1), dist(q, ray 2))`, and
//! `dist(q, ray)` is `|q − V|` wherever `q` lies behind the ray's vertex
//! `V`. With `V` the circle's centre and both rays pointing away from the
//! tile, every point of the tile lies behind them (the centre is farther
//! from the tile's middle than the tile's half diagonal), so the tile plays
//! the cone `top − k |q − C|`: with `top` the radius in codes (plus the
//! bias), the signed distance to the circle, positive inside. For a band
//! round a circle of radius `r` and width `w`, `top` is `r + w / 2`: its
//! outer side, where the inner side does not cross the tile (the cone is
//! then saturated inside the band). The drawing's circles reach the
//! writer flattened (within 0.5 µm); their vertices lie on the circle, so
//! a circle through them is the drawn circle, and the writer keeps the cone
//! only where, as for every analytic tile, it plays the exact distance to
//! the flattened outline within half a code at the 81 lattice points and
//! the 64 cell centres (or saturated on the same side).
//!
//! Where no bend plays it (a band's two sides both cross the tile, a hole
//! in a fill, a circle whose centre is too close to the tile), an **arc**
//! tile (format 4.1) does: `top − k · ||q − C| − R|`, a ring round the
//! circle of radius `R` for a band, a cone (`R` = 0) for a disc, and for a
//! hole `R` beyond the tile's farthest point, where the code is
//! `top − k R + k |q − C|`.

use taxel_format::{
    DISTANCE_ZERO, MAX_ARC_RADIUS, MAX_PLANE_CODE, MAX_PLANE_GRADIENT, TILE_ARC, TILE_BEND, TILE_CELLS, TILE_SAMPLES,
    TILE_SIDE, TileEntry, TilePlane,
};

use super::Part;
use super::planes::{LeastSquares, TileCtx};

/// How far a vertex may lie from the circle fitted through its
/// neighbours and still count as on it, mm: the flattening's own tolerance
/// (a sixteenth of a code at the default pitch). An SVG circle reaches the
/// compiler as four cubic Béziers, which stray from the circle by up to
/// 0.027% of its radius (4 µm on a 15 mm circle); over one tile they stay
/// this close to a circle, the one the fit finds.
pub(super) const ON_CIRCLE_MM: f64 = crate::geometry::FLATTEN_TOLERANCE_MM;
/// How far the vertices of the segments nearest a tile may lie from a
/// circle, mm, for them to count as a circular arc that the flattening
/// laid on the circle ([`flattened_arc_circles`]): `geometry::flatten_with`
/// computes an arc's vertices on it in `f64`, and only its ends are the
/// drawing's `f32` points (a few nm off at page scale, as are the centres
/// of a circle's four Béziers from one another).
const ARC_VERTEX_MM: f64 = 2e-5;
/// The fewest distinct vertices near a tile that make an arc
/// ([`flattened_arc_circles`]): any three lie on a circle.
const ARC_VERTICES: usize = 6;
/// How many of the segments nearest a tile must be a flattened arc
/// ([`flattened_arc_circles`]).
const ARC_SEGMENTS: usize = 8;
/// The numbers of nearest segments whose vertices are fitted (besides the
/// vertices over the tile); the first is also the most segments looked at.
const FIT_SEGMENTS: [usize; 4] = [48, 24, 8, 3];

/// The circles that may play a tile whose exact codes are `exact`, as
/// their tile index kind ([`TILE_BEND`] or [`TILE_ARC`]) and two records:
/// circles through the vertices of the fill or band segments nearest the
/// tile, the one that follows the outline's vertices over the tile most
/// closely first, kept where they play the 81 samples (the caller checks
/// the cell centres). A cone that a bend tile plays comes first (format 4.0), then
/// an arc tile (format 4.1): a disc's cone, a hole, or a band's ring.
pub(super) fn circles(t: &TileCtx<'_, '_>, exact: &[f64; TILE_SAMPLES]) -> Vec<(u32, [TilePlane; 2])> {
    circles_where(t, exact, false)
}

/// [`circles`] where the segments nearest the tile are a circular arc
/// flattened within the build's tolerance: at least [`ARC_VERTICES`]
/// distinct vertices, each within [`ARC_VERTEX_MM`] of the circle, and no
/// chord's sagitta above `FLATTEN_TOLERANCE_MM`. Where such a tile is
/// also played by a corner of two chords or a band's bend at a vertex,
/// those play the chords, up to 0.5 µm inside the drawn circle, while the
/// circle plays the drawing itself (45 nm there was 12 steps of a hard
/// edge's one-code ramp at the 0.25 mm lattice, `taxel report`'s finer
/// rung, on the experiment-5 circle icon).
pub(super) fn flattened_arc_circles(t: &TileCtx<'_, '_>, exact: &[f64; TILE_SAMPLES]) -> Vec<(u32, [TilePlane; 2])> {
    circles_where(t, exact, true)
}

/// [`circles`], or [`flattened_arc_circles`] with `arcs_only`.
fn circles_where(t: &TileCtx<'_, '_>, exact: &[f64; TILE_SAMPLES], arcs_only: bool) -> Vec<(u32, [TilePlane; 2])> {
    let mut out: Vec<(u32, [TilePlane; 2])> = Vec::new();
    let circles_of =
        |part, offsets: &[f64], ring, out: &mut Vec<_>| circles_of(t, exact, part, offsets, ring, arcs_only, out);
    match t.g.band.as_ref() {
        // A band round a circle: its outer side as a cone, or the ring.
        Some((_, w)) => circles_of(Part::Band, &[w / 2.0], Some(w / 2.0), &mut out),
        // A fill's curved side: the disc, or the hole.
        None => circles_of(Part::Fill, &[0.0], None, &mut out),
    }
    // A vibrating band round a circle cut out of a grating: the grating's
    // edge is the band's inner side (the disc inside it, `R − w / 2`) or its
    // outer side (the hole round it, `R + w / 2`), the band's centre line's
    // circle offset by half its width. (The experiment-5 circle icon: the
    // grated disc less its vibrating outline; before these, its tiles on the
    // cut's inner side were stored.)
    for (k, w) in t.cut_widths().into_iter().enumerate() {
        circles_of(Part::Cut(k), &[-w / 2.0, w / 2.0], None, &mut out);
    }
    // A circle painted over the layer (a map's town on a grated region):
    // the hole it makes.
    circles_of(Part::Occluder, &[0.0], None, &mut out);
    out
}

/// [`circles`] for the circles through the vertices of `part`'s segments
/// nearest the tile, each grown by every one of `offsets` (mm), a band's
/// ring `ring` wide on each side of it where `ring` is given; with
/// `arcs_only`, only where those segments are a flattened circular arc
/// ([`flattened_arc_circles`]).
fn circles_of(
    t: &TileCtx<'_, '_>,
    exact: &[f64; TILE_SAMPLES],
    part: Part,
    offsets: &[f64],
    ring: Option<f64>,
    arcs_only: bool,
    out: &mut Vec<(u32, [TilePlane; 2])>,
) {
    let span = TILE_CELLS as f64 * t.h;
    let middle = t.middle();
    let near = t.nearest(part, FIT_SEGMENTS[0]);
    // The outline's vertices over the tile (grown by a cell): where the
    // circle must follow the outline, since the tile's edge is there.
    let m = t.h;
    let over = |p: &(f64, f64)| {
        p.0 >= t.corner.0 - m && p.0 <= t.corner.0 + span + m && p.1 >= t.corner.1 - m && p.1 <= t.corner.1 + span + m
    };
    let mut here: Vec<(f64, f64)> = near.iter().flat_map(|(_, (a, b))| [*a, *b]).filter(over).collect();
    here.dedup();
    // Candidate circles: through the vertices over the tile, and through
    // those of the nearest segments; the one that follows the vertices over
    // the tile most closely first. For a flattened arc, the circle through
    // the nearest segments' vertices only: every fit finds it within a few
    // nm, and the other segments are not on it.
    let mut fits: Vec<(f64, (f64, f64), f64)> = Vec::new();
    let through = |n: usize| near.iter().take(n).flat_map(|(_, (a, b))| [*a, *b]).collect::<Vec<_>>();
    let sets: Vec<Vec<(f64, f64)>> = if arcs_only {
        vec![through(ARC_SEGMENTS)]
    } else {
        std::iter::once(here.clone())
            .chain(FIT_SEGMENTS.iter().filter(|&&n| near.len() >= n).map(|&n| through(n)))
            .collect()
    };
    for points in sets {
        let Some((c, r)) = circle_through(points.iter().copied(), middle) else { continue };
        let off = here.iter().map(|v| ((v.0 - c.0).hypot(v.1 - c.1) - r).abs()).fold(0.0, f64::max);
        fits.push((off, c, r));
    }
    fits.sort_by(|a, b| a.0.total_cmp(&b.0));
    if arcs_only {
        let chords: Vec<super::Seg> = near.iter().take(ARC_SEGMENTS).map(|(_, ab)| *ab).collect();
        fits.retain(|&(_, c, r)| is_flattened_arc(&chords, &here, c, r));
    }
    let order = t.order(exact);
    for (_, c, r) in fits {
        for &offset in offsets {
            let radius = r + offset;
            if radius.is_nan() || radius <= 0.0 {
                continue;
            }
            let bend = cone(t, c, radius).map(|rec| (TILE_BEND, rec));
            let ring = match ring {
                Some(half) => arcs(t, c, r, Some(half)),
                None => arcs(t, c, radius, None),
            };
            for rec in bend.into_iter().chain(ring.into_iter().map(|rec| (TILE_ARC, rec))) {
                if plays(t, &rec, exact, order) && !out.contains(&rec) {
                    out.push(rec);
                }
            }
        }
    }
}

/// Whether `chords` (and the vertices `here`) are a circular arc of centre
/// `c` and radius `r` flattened within the build's tolerance: at least
/// [`ARC_VERTICES`] distinct vertices, every one within [`ARC_VERTEX_MM`]
/// of the circle, and every chord's sagitta (the circle's distance beyond
/// its middle) at most `FLATTEN_TOLERANCE_MM`.
fn is_flattened_arc(chords: &[super::Seg], here: &[(f64, f64)], c: (f64, f64), r: f64) -> bool {
    let on = |p: &(f64, f64)| ((p.0 - c.0).hypot(p.1 - c.1) - r).abs() <= ARC_VERTEX_MM;
    let mut vertices: Vec<(f64, f64)> = chords.iter().flat_map(|(a, b)| [*a, *b]).chain(here.iter().copied()).collect();
    vertices.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    vertices.dedup();
    let sagitta = |(a, b): &super::Seg| r - ((a.0 + b.0) / 2.0 - c.0).hypot((a.1 + b.1) / 2.0 - c.1);
    vertices.len() >= ARC_VERTICES
        && vertices.iter().all(on)
        && chords.iter().all(|ch| sagitta(ch) <= crate::geometry::FLATTEN_TOLERANCE_MM + ARC_VERTEX_MM)
}

/// The circle through `points` (least squares), if every point lies on it
/// within [`ON_CIRCLE_MM`]; `near` is a point near them, the origin of the
/// fit's coordinates (for its conditioning).
pub(super) fn circle_through(
    points: impl Iterator<Item = (f64, f64)> + Clone,
    near: (f64, f64),
) -> Option<((f64, f64), f64)> {
    // x² + y² + D x + E y + F = 0, linear in (D, E, F).
    let mut ls = LeastSquares::<3>::default();
    let mut distinct = 0usize;
    let mut last = None;
    for p in points.clone() {
        let (x, y) = (p.0 - near.0, p.1 - near.1);
        ls.add([x, y, 1.0], -(x * x + y * y));
        if last != Some(p) {
            distinct += 1;
            last = Some(p);
        }
    }
    if distinct < 3 {
        return None;
    }
    let [d, e, f] = ls.solve()?;
    let (cx, cy) = (-d / 2.0, -e / 2.0);
    let r2 = cx * cx + cy * cy - f;
    if !(r2.is_finite() && r2 > 0.0) {
        return None;
    }
    let r = r2.sqrt();
    let on = points.into_iter().all(|p| ((p.0 - near.0 - cx).hypot(p.1 - near.1 - cy) - r).abs() <= ON_CIRCLE_MM);
    on.then_some(((cx + near.0, cy + near.1), r))
}

/// The bend records of the cone `top − k |q − c|` over the tile, `radius`
/// mm round page point `c`: both rays point from `c` away from the tile's
/// middle, so that every point of the tile lies behind them. `None` when
/// `c` is too close to the tile for that, or too far for the record's
/// bounds.
fn cone(t: &TileCtx<'_, '_>, c: (f64, f64), radius: f64) -> Option<[TilePlane; 2]> {
    let half = TILE_CELLS as f64 / 2.0;
    let (vu, vw) = ((c.0 - t.corner.0) / t.h, (c.1 - t.corner.1) / t.h);
    let (du, dw) = (vu - half, vw - half);
    let len = du.hypot(dw);
    // Behind both rays: `(q − V) · d < 0` for every `q` within the tile's
    // half diagonal of its middle, with a cell to spare for f32 rounding.
    if !(len.is_finite() && len > half * std::f64::consts::SQRT_2 + 1.0) {
        return None;
    }
    let (ex, ey) = (du / len, dw / len);
    let k = t.h / t.step;
    let top = DISTANCE_ZERO as f64 + radius / t.step;
    let ok = |x: f64, m: f32| x.is_finite() && x.abs() <= m as f64;
    (ok(vu, MAX_PLANE_GRADIENT) && ok(vw, MAX_PLANE_GRADIENT) && ok(k, MAX_PLANE_GRADIENT) && ok(top, MAX_PLANE_CODE))
        .then_some([
            TilePlane { c: vu as f32, gx: vw as f32, gy: ex as f32, top: ey as f32 },
            TilePlane { c: ex as f32, gx: ey as f32, gy: k as f32, top: top as f32 },
        ])
}

/// The arc tiles' records (SPEC.md section 6.2, format 4.1) of the circle
/// of `radius` mm round page point `c` over the tile: for a band `half`
/// its width wide, the ring `top − k |ρ − R|` (`R` the radius in cells,
/// `top` the half width in codes); for a fill, the disc's cone (`R` = 0,
/// `top` the radius in codes) and the hole round it, whose distance grows
/// with `ρ`: `top − k (R − ρ)` with `R` beyond every point of the tile.
pub(super) fn arcs(t: &TileCtx<'_, '_>, c: (f64, f64), radius: f64, half: Option<f64>) -> Vec<[TilePlane; 2]> {
    let (vu, vw) = ((c.0 - t.corner.0) / t.h, (c.1 - t.corner.1) / t.h);
    let k = t.h / t.step;
    let zero = DISTANCE_ZERO as f64;
    let (r_cells, r_codes) = (radius / t.h, radius / t.step);
    let record = |rr: f64, top: f64| {
        let ok = |x: f64, m: f32| x.is_finite() && x.abs() <= m as f64;
        (ok(vu, MAX_PLANE_GRADIENT)
            && ok(vw, MAX_PLANE_GRADIENT)
            && ok(k, MAX_PLANE_GRADIENT)
            && ok(top, MAX_PLANE_CODE)
            && ok(rr, MAX_ARC_RADIUS)
            && rr >= 0.0)
            .then_some([
                TilePlane { c: vu as f32, gx: vw as f32, gy: rr as f32, top: k as f32 },
                TilePlane { c: top as f32, gx: 0.0, gy: 0.0, top: 0.0 },
            ])
    };
    match half {
        Some(half) => record(r_cells, zero + half / t.step).into_iter().collect(),
        None => {
            // Beyond the tile's farthest point from the centre, with a cell to spare.
            let half_tile = TILE_CELLS as f64 / 2.0;
            let far = (vu - half_tile).hypot(vw - half_tile) + half_tile * std::f64::consts::SQRT_2 + 1.0;
            let hole = record(far, zero - r_codes + k * far);
            record(0.0, zero + r_codes).into_iter().chain(hole).collect()
        }
    }
}

/// Whether a circle's records play the tile's 81 exact codes as a plane must.
/// `order` is [`edge_first`](super::planes::edge_first)'s.
fn plays(
    t: &TileCtx<'_, '_>,
    (kind, r): &(u32, [TilePlane; 2]),
    exact: &[f64; TILE_SAMPLES],
    order: &[u8; TILE_SAMPLES],
) -> bool {
    order.iter().map(|&i| i as usize).all(|i| {
        let code = TileEntry::of(*kind).code(r, (i % TILE_SIDE) as f64, (i / TILE_SIDE) as f64);
        code.is_some_and(|code| t.sat.close(code - DISTANCE_ZERO as f64, exact[i]))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The chords between consecutive `points`.
    fn chords(points: &[(f64, f64)]) -> Vec<super::super::Seg> {
        points.windows(2).map(|w| (w[0], w[1])).collect()
    }

    /// `n + 1` points on the circle of radius `r` round `c`, `step` radians apart from angle `a0`.
    fn on_circle(c: (f64, f64), r: f64, a0: f64, step: f64, n: usize) -> Vec<(f64, f64)> {
        (0..=n).map(|k| (c.0 + r * (a0 + step * k as f64).cos(), c.1 + r * (a0 + step * k as f64).sin())).collect()
    }

    #[test]
    fn only_a_circle_flattened_within_the_tolerance_is_a_flattened_arc() {
        let (c, r) = ((55.0, 30.0), 15.0);
        let tol = crate::geometry::FLATTEN_TOLERANCE_MM;
        // Chords whose sagitta is the tolerance, as the flattening lays them.
        let step = 2.0 * (1.0 - tol / r).acos();
        let arc = on_circle(c, r, 2.1, step, 8);
        assert!(is_flattened_arc(&chords(&arc), &[], c, r));
        // The same vertices a few nm off (the drawing's f32 points): still the arc.
        let nudged: Vec<_> = arc.iter().map(|p| (p.0 + 4e-6, p.1 - 3e-6)).collect();
        assert!(is_flattened_arc(&chords(&nudged), &[], c, r));
        // 0.1 µm off: not on the circle.
        let off: Vec<_> = arc.iter().enumerate().map(|(k, p)| (p.0 + 1e-4 * (k % 2) as f64, p.1)).collect();
        assert!(!is_flattened_arc(&chords(&off), &[], c, r));
        // Chords twice as long (sagitta four times the tolerance): a polygon on the circle.
        assert!(!is_flattened_arc(&chords(&on_circle(c, r, 2.1, 2.0 * step, 8)), &[], c, r));
        // A hexagon's vertices lie on a circle too.
        let hexagon = on_circle(c, r, 0.0, std::f64::consts::TAU / 6.0, 6);
        assert!(!is_flattened_arc(&chords(&hexagon), &[], c, r));
        // Five distinct vertices are too few to tell (any three are on a circle).
        assert!(!is_flattened_arc(&chords(&arc[..5]), &[], c, r));
        // A vertex over the tile off the circle.
        assert!(!is_flattened_arc(&chords(&arc), &[(c.0 + r + 1e-3, c.1)], c, r));
    }
}
