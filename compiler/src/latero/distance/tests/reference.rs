//! What the tests measure fields against: the exact signed distance of a
//! layer in f64, and a built field played at a point as a player plays it.

use taxel_format::{DISTANCE_ZERO, TILE_CELLS, TILE_FIRST_STORED, TILE_INSIDE, TILE_OUTSIDE, TILE_SAMPLES, TILE_SIDE};

use crate::geometry::distance_to_segment;
use crate::latero::distance::{Field, LayerGeometry, closed_segments, inside_rect};

/// The exact signed distance of a layer at `p`, in f64, before clamping:
/// the reference the tests measure fields against.
pub(crate) fn exact_signed_distance(g: &LayerGeometry<'_>, page: (f64, f64, f64, f64), p: (f64, f64)) -> f64 {
    let mut s = f64::NEG_INFINITY;
    if !g.fills.is_empty() {
        let d = g
            .fills
            .iter()
            .flat_map(|(pls, _)| pls.iter().flat_map(closed_segments))
            .map(|(a, b)| distance_to_segment(p, a, b))
            .fold(f64::INFINITY, f64::min);
        let inside = g.fills.iter().any(|(pls, rule)| crate::geometry::contains(pls, p, *rule));
        s = if inside { d } else { -d };
    }
    if let Some((lines, w)) = &g.band {
        let d = lines
            .iter()
            .flat_map(|pls| pls.iter().flat_map(|pl| pl.segments()))
            .map(|(a, b)| distance_to_segment(p, a, b))
            .fold(f64::INFINITY, f64::min);
        s = s.max(w / 2.0 - d);
    }
    for (lines, w) in &g.cuts {
        let d = lines
            .iter()
            .flat_map(|pl| pl.segments())
            .map(|(a, b)| distance_to_segment(p, a, b))
            .fold(f64::INFINITY, f64::min);
        s = s.min(d - w / 2.0);
    }
    for (pls, rule) in &g.clips {
        let d = pls
            .iter()
            .flat_map(closed_segments)
            .map(|(a, b)| distance_to_segment(p, a, b))
            .fold(f64::INFINITY, f64::min);
        s = s.min(if crate::geometry::contains(pls, p, *rule) { d } else { -d });
    }
    if !g.occluders.is_empty() {
        let d = g
            .occluders
            .iter()
            .flat_map(|(pls, _)| pls.iter().flat_map(closed_segments))
            .map(|(a, b)| distance_to_segment(p, a, b))
            .fold(f64::INFINITY, f64::min);
        let inside = g.occluders.iter().any(|(pls, rule)| crate::geometry::contains(pls, p, *rule));
        s = s.min(if inside { -d } else { d });
    }
    s.min(inside_rect(page, p))
}

/// The interpolated signed distance of a built field at `p` in mm (SPEC.md
/// section 6.2), `None` outside its lattice: what a player computes, in f64.
pub(super) fn field_distance(f: &Field, h: f64, p: (f64, f64)) -> Option<f64> {
    let fx = (p.0 - f.origin.0) / h;
    let fy = (p.1 - f.origin.1) / h;
    let (w, ht) = ((f.tile_cols as usize * TILE_CELLS) as f64, (f.tile_rows as usize * TILE_CELLS) as f64);
    if !(fx >= 0.0 && fy >= 0.0 && fx < w && fy < ht) {
        return None;
    }
    let (ci, cj) = (fx as usize, fy as usize);
    let (tx, ty) = (ci / TILE_CELLS, cj / TILE_CELLS);
    let e = *f.tiles.get(ty * f.tile_cols as usize + tx)?;
    let step = f.step_mm;
    match e {
        TILE_OUTSIDE => Some(-128.0 * step),
        TILE_INSIDE => Some(127.0 * step),
        e if e >> 28 == taxel_format::TILE_FINE >> 28 => {
            let taxel_format::TileEntry::Fine { first, fine, pair } = taxel_format::TileEntry::of(e) else {
                return None;
            };
            let fine = fine as usize;
            let cell = |v: f64| {
                let last = TILE_CELLS * fine - 1;
                let c = ((v * fine as f64).max(0.0) as usize).min(last);
                (c / TILE_CELLS, c % TILE_CELLS, v * fine as f64 - c as f64)
            };
            let ((a, i, wx), (b, j, wy)) = (cell(fx - (tx * TILE_CELLS) as f64), cell(fy - (ty * TILE_CELLS) as f64));
            let channel = |c: usize| {
                let base = (first as usize + (c * fine + b) * fine + a) * TILE_SAMPLES;
                let s = |i: usize, j: usize| {
                    f.samples.get(base + j * TILE_SIDE + i).map_or(0.0, |&v| v as f64 - DISTANCE_ZERO as f64)
                };
                let top = s(i, j) + (s(i + 1, j) - s(i, j)) * wx;
                let bot = s(i, j + 1) + (s(i + 1, j + 1) - s(i, j + 1)) * wx;
                top + (bot - top) * wy
            };
            Some(if pair { channel(0).min(channel(1)) } else { channel(0) } * step)
        }
        e if e >= taxel_format::TILE_PLANE => {
            // A plane, ridge, corner or notch tile: its function at the point itself.
            let (u, w) = (fx - (tx * TILE_CELLS) as f64, fy - (ty * TILE_CELLS) as f64);
            let code = taxel_format::TileEntry::of(e).code(&f.planes, u, w)?;
            Some((code - DISTANCE_ZERO as f64) * step)
        }
        e => {
            let base = (e - TILE_FIRST_STORED) as usize * TILE_SAMPLES;
            let (i, j) = (ci - tx * TILE_CELLS, cj - ty * TILE_CELLS);
            let s = |i: usize, j: usize| {
                f.samples.get(base + j * TILE_SIDE + i).map_or(0.0, |&v| v as f64 - DISTANCE_ZERO as f64)
            };
            let (wx, wy) = (fx - ci as f64, fy - cj as f64);
            let top = s(i, j) + (s(i + 1, j) - s(i, j)) * wx;
            let bot = s(i, j + 1) + (s(i + 1, j + 1) - s(i, j + 1)) * wx;
            Some((top + (bot - top) * wy) * step)
        }
    }
}

/// Whether `p` lies in a constant tile of a built field: `Some(true)` inside,
/// `Some(false)` outside, `None` in a stored tile or off the lattice.
pub(super) fn constant_tile_at(f: &Field, h: f64, p: (f64, f64)) -> Option<bool> {
    let fx = (p.0 - f.origin.0) / h;
    let fy = (p.1 - f.origin.1) / h;
    if !(fx >= 0.0 && fy >= 0.0) {
        return None;
    }
    let (tx, ty) = (fx as usize / TILE_CELLS, fy as usize / TILE_CELLS);
    if tx >= f.tile_cols as usize {
        return None;
    }
    match *f.tiles.get(ty * f.tile_cols as usize + tx)? {
        TILE_OUTSIDE => Some(false),
        TILE_INSIDE => Some(true),
        _ => None,
    }
}
