//! Plane and ridge tiles (SPEC.md section 6.2, format 3.0): a tile that one
//! straight edge crosses holds an affine signed distance, and a tile that
//! one straight band centre line crosses a ridge `top − |affine|`; either is
//! one 16-byte record instead of 81 samples, and plays the function at the
//! point itself, with no bilinear interpolation.
//!
//! The writer fits the function to the tile's unquantised samples (least
//! squares, so that exact affine data gives the exact plane) and keeps it
//! only if, rounded to the record's `f32`s, it is within half a code of the
//! exact distance at all 81 samples and at the 64 cell centres, wherever that
//! distance is within the clamp (and saturated on the same side where it is
//! not). A sampled tile is within half a code at its samples only, so a
//! plane tile is never worse than the stored tile it replaces there.

use std::f64::consts::FRAC_1_SQRT_2;

use taxel_format::{
    DISTANCE_ZERO, MAX_PLANE_CODE, MAX_PLANE_GRADIENT, TILE_CELLS, TILE_PLANE, TILE_RIDGE, TILE_SAMPLES, TILE_SIDE,
    TilePlane,
};

use super::{LayerGeometry, Near, Part, Seg};

/// Largest error of a plane or ridge tile against the exact distance, codes.
const TOLERANCE: f64 = 0.5;
/// The clamp, in codes (the writer clamps distances to ±127 steps).
const CAP: f64 = 127.0;

/// The unbiased codes from which on the edge profile is saturated: at or
/// above `hi` a code plays full amplitude, at or below `lo` none (the
/// `full` and `none` of `saturated_codes`, less the bias).
#[derive(Debug, Clone, Copy)]
pub(super) struct Saturation {
    pub hi: f64,
    pub lo: f64,
}

impl Saturation {
    /// Whether the code `v` (unbiased) plays as the exact distance `e`
    /// (codes, clamped to ±[`CAP`]): within [`TOLERANCE`], or both saturated
    /// on the same side, where the amplitude is the same whatever the code.
    fn close(&self, v: f64, e: f64) -> bool {
        (v - e).abs() <= TOLERANCE || (e >= self.hi && v >= self.hi) || (e <= self.lo && v <= self.lo)
    }
}

/// The windows (largest |code| of the samples fitted) tried in turn: all
/// unclamped samples, then those within about one and a half cells of the
/// edge, so that a tile where a second feature bends the distance only in
/// the saturated part still fits its edge's plane.
const WINDOWS: [f64; 3] = [CAP, 96.0, 48.0];

/// The plane or ridge that plays a tile's samples (`exact`, unquantised
/// codes clamped to ±127, row-major 9 x 9) within half a code, or saturated
/// on the same side where they are, as its tile index kind and record;
/// `ridge_top` is a vibration layer's half band width in codes (the ridge's
/// top), `None` for a grating.
pub(super) fn fit(exact: &[f64; TILE_SAMPLES], ridge_top: Option<f64>, sat: Saturation) -> Option<(u32, TilePlane)> {
    let at = |t: usize| ((t % TILE_SIDE) as f64, (t / TILE_SIDE) as f64);
    let plays = |kind: u32, rec: &TilePlane| {
        exact.iter().enumerate().all(|(t, &e)| {
            let (u, w) = at(t);
            sat.close(rec.code(kind, u, w) - DISTANCE_ZERO as f64, e)
        })
    };
    for window in WINDOWS {
        let open = |e: f64| e.abs() < window;
        // A plane: least squares in (1, u, w) over the samples in the window.
        let mut ls = LeastSquares::<3>::default();
        for (t, &e) in exact.iter().enumerate().filter(|(_, e)| open(**e)) {
            let (u, w) = at(t);
            ls.add([1.0, u, w], e);
        }
        if let Some([c, gx, gy]) = ls.solve() {
            let rec = record(c + DISTANCE_ZERO as f64, gx, gy, 0.0);
            if let Some(rec) = rec.filter(|r| plays(TILE_PLANE, r)) {
                return Some((TILE_PLANE, rec));
            }
        }
        // A ridge: the squared distance to the centre line,
        // `(c + gx u + gy w)²` = `(top − e)²`, is a quadratic in (u, w) whose
        // coefficients give the line.
        let Some(top) = ridge_top else { continue };
        let mut ls = LeastSquares::<6>::default();
        for (t, &e) in exact.iter().enumerate().filter(|(_, e)| open(**e)) {
            let (u, w) = at(t);
            let m = top - e;
            ls.add([u * u, u * w, w * w, u, w, 1.0], m * m);
        }
        let Some([a, b, cc, d, e, _]) = ls.solve() else { continue };
        let gx = a.max(0.0).sqrt();
        let gy = cc.max(0.0).sqrt() * if b < 0.0 { -1.0 } else { 1.0 };
        let g2 = gx * gx + gy * gy;
        if g2 <= 0.0 {
            continue;
        }
        let c = (d * gx + e * gy) / (2.0 * g2);
        if let Some(rec) = record(c, gx, gy, top + DISTANCE_ZERO as f64).filter(|r| plays(TILE_RIDGE, r)) {
            return Some((TILE_RIDGE, rec));
        }
    }
    None
}

/// A record in `f32`, if its values are within the format's bounds.
fn record(c: f64, gx: f64, gy: f64, top: f64) -> Option<TilePlane> {
    let ok = |v: f64, m: f32| v.is_finite() && v.abs() <= m as f64;
    (ok(c, MAX_PLANE_CODE) && ok(top, MAX_PLANE_CODE) && ok(gx, MAX_PLANE_GRADIENT) && ok(gy, MAX_PLANE_GRADIENT))
        .then(|| TilePlane { c: c as f32, gx: gx as f32, gy: gy as f32, top: top as f32 })
}

/// Normal equations of a linear least-squares fit in `N` unknowns.
struct LeastSquares<const N: usize> {
    a: [[f64; N]; N],
    b: [f64; N],
    n: usize,
}

impl<const N: usize> Default for LeastSquares<N> {
    fn default() -> Self {
        LeastSquares { a: [[0.0; N]; N], b: [0.0; N], n: 0 }
    }
}

impl<const N: usize> LeastSquares<N> {
    fn add(&mut self, x: [f64; N], y: f64) {
        for i in 0..N {
            for j in 0..N {
                self.a[i][j] += x[i] * x[j];
            }
            self.b[i] += x[i] * y;
        }
        self.n += 1;
    }

    /// The solution, by Gaussian elimination with partial pivoting; `None`
    /// when the samples do not determine it.
    fn solve(&self) -> Option<[f64; N]> {
        if self.n < N {
            return None;
        }
        let (mut a, mut b) = (self.a, self.b);
        let scale = a.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        for col in 0..N {
            let piv = (col..N).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
            if !(a[piv][col].abs() > 1e-12 * scale) {
                return None;
            }
            a.swap(col, piv);
            b.swap(col, piv);
            for row in col + 1..N {
                let f = a[row][col] / a[col][col];
                for k in col..N {
                    a[row][k] -= f * a[col][k];
                }
                b[row] -= f * b[col];
            }
        }
        let mut x = [0.0; N];
        for row in (0..N).rev() {
            let s: f64 = (row + 1..N).map(|k| a[row][k] * x[k]).sum();
            x[row] = (b[row] - s) / a[row][row];
        }
        x.iter().all(|v| v.is_finite()).then_some(x)
    }
}

/// One tile of a layer being built: what measuring its cell centres needs.
pub(super) struct TileCtx<'a, 'g> {
    pub g: &'a LayerGeometry<'g>,
    pub segs: &'a [(Seg, Part, f64)],
    pub bucket: &'a [u32],
    /// Page position of the tile's first lattice point.
    pub corner: (f64, f64),
    pub h: f64,
    pub margin: f64,
    pub page: (f64, f64, f64, f64),
    /// The clamp in codes, and mm per code.
    pub cap: f64,
    pub step: f64,
    pub sat: Saturation,
    /// Lattice index of the tile's first point, and points per lattice row.
    pub first: usize,
    pub nx: usize,
    /// Inside-the-fills, inside-the-occluders and inside-each-clip bits at every lattice point.
    pub inside: &'a [bool],
    pub occluded: &'a [bool],
    pub clip_bits: &'a [Vec<bool>],
}

impl TileCtx<'_, '_> {
    /// Whether plane record `rec` (tile index kind `kind`) plays the exact
    /// distance within half a code at the tile's 64 cell centres; `near`
    /// holds the tile's samples' measures, `centres` is scratch.
    ///
    /// Which side of each part's outline a centre lies on follows from its
    /// corners: a part's signed distance is 1-Lipschitz, so the centre's
    /// lies within `h / √2` of each corner's, which leaves one sign unless
    /// the outline passes within a hair of the centre (where the sign does
    /// not matter) or the corners cannot tell (then the tile stays sampled).
    pub(super) fn centres_fit(&self, near: &Near, centres: &mut Near, kind: u32, rec: &TilePlane) -> bool {
        let h = self.h;
        centres.measure(
            self.g,
            self.segs,
            self.bucket,
            (self.corner.0 + h / 2.0, self.corner.1 + h / 2.0),
            h,
            self.margin,
        );
        let mut in_clip = vec![false; self.clip_bits.len()];
        for j in 0..TILE_CELLS {
            for i in 0..TILE_CELLS {
                let tc = j * TILE_SIDE + i;
                let quad = [tc, tc + 1, tc + TILE_SIDE, tc + TILE_SIDE + 1];
                let lattice = |q: usize| self.first + (q / TILE_SIDE) * self.nx + q % TILE_SIDE;
                let side = |dc2: f64, d2: &dyn Fn(usize) -> f64, bit: &dyn Fn(usize) -> bool| {
                    let corners = quad.map(|q| (d2(q).sqrt(), bit(lattice(q))));
                    centre_side(dc2.sqrt(), &corners, h)
                };
                let Some(inside) = side(centres.fill[tc], &|q| near.fill[q], &|k| self.inside[k]) else {
                    return false;
                };
                let Some(occluded) = side(centres.occ[tc], &|q| near.occ[q], &|k| self.occluded[k]) else {
                    return false;
                };
                for (kc, slot) in in_clip.iter_mut().enumerate() {
                    let at = |q: usize| near.clip.get(kc * TILE_SAMPLES + q).copied().unwrap_or(f64::INFINITY);
                    let dc = centres.clip.get(kc * TILE_SAMPLES + tc).copied().unwrap_or(f64::INFINITY);
                    let bits = &self.clip_bits[kc];
                    let Some(b) = side(dc, &at, &|k| bits[k]) else { return false };
                    *slot = b;
                }
                let p = (self.corner.0 + (i as f64 + 0.5) * h, self.corner.1 + (j as f64 + 0.5) * h);
                let s = centres.signed(self.g, tc, (inside, occluded), &in_clip, p, self.page);
                let e = (s / self.step).clamp(-self.cap, self.cap);
                let v = rec.code(kind, i as f64 + 0.5, j as f64 + 0.5) - DISTANCE_ZERO as f64;
                if !self.sat.close(v, e) {
                    return false;
                }
            }
        }
        true
    }
}

/// The side of a part's outline (`true`: the side its bit calls inside) of
/// a cell centre at unsigned distance `dc` from it, from the cell's corners'
/// unsigned distances and sides; `None` when the corners leave both.
/// Infinite distances are beyond the measured reach: all on one side.
fn centre_side(dc: f64, corners: &[(f64, bool); 4], h: f64) -> Option<bool> {
    if !dc.is_finite() {
        return Some(corners[0].1);
    }
    let reach = h * FRAC_1_SQRT_2 * (1.0 + 1e-9);
    let fits = |side: bool| {
        let sc = if side { dc } else { -dc };
        corners
            .iter()
            .all(|&(d, b)| if d.is_finite() { (sc - if b { d } else { -d }).abs() <= reach } else { b == side })
    };
    match (fits(true), fits(false)) {
        (true, false) => Some(true),
        (false, true) => Some(false),
        (true, true) if dc <= 1e-9 * h => Some(true),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAT: Saturation = Saturation { hi: 1.0, lo: -1.0 };

    fn samples(f: impl Fn(f64, f64) -> f64) -> [f64; TILE_SAMPLES] {
        std::array::from_fn(|t| f((t % TILE_SIDE) as f64, (t / TILE_SIDE) as f64).clamp(-CAP, CAP))
    }

    #[test]
    fn an_affine_tile_fits_a_plane_exactly() {
        let f = |u: f64, w: f64| 3.0 + 12.5 * u - 7.25 * w;
        let (kind, rec) = fit(&samples(f), None, SAT).expect("a plane");
        assert_eq!(kind, TILE_PLANE);
        for (u, w) in [(0.0, 0.0), (3.5, 2.25), (8.0, 8.0)] {
            assert!((rec.code(kind, u, w) - 128.0 - f(u, w)).abs() < 1e-3);
        }
    }

    #[test]
    fn a_band_across_a_tile_fits_a_ridge() {
        // Distance 30 codes per cell; the line through (4, 0) and (6, 8).
        let (nx, ny) = (8.0 / 68f64.sqrt(), -2.0 / 68f64.sqrt());
        let f = |u: f64, w: f64| 90.0 - 30.0 * (nx * (u - 4.0) + ny * w).abs();
        let (kind, rec) = fit(&samples(f), Some(90.0), SAT).expect("a ridge");
        assert_eq!(kind, TILE_RIDGE);
        for (u, w) in [(0.0, 0.0), (4.5, 1.5), (5.0, 4.0), (8.0, 8.0)] {
            assert!((rec.code(kind, u, w) - 128.0 - f(u, w).clamp(-CAP, CAP)).abs() < 1e-2 || f(u, w) < -CAP);
        }
        // Without a band the same samples are no plane.
        assert_eq!(fit(&samples(f), None, SAT), None);
    }

    #[test]
    fn a_corner_is_no_plane() {
        // Inside a square corner the distance is the min of two planes.
        let f = |u: f64, w: f64| 10.0 * (u - 4.0).min(w - 4.0);
        assert_eq!(fit(&samples(f), None, SAT), None);
    }

    #[test]
    fn a_centre_takes_the_side_its_corners_allow() {
        // An edge along x = 0.3 h: corners at -0.3 and 0.7 (h = 1).
        let c = [(0.3, false), (0.7, true), (0.3, false), (0.7, true)];
        assert_eq!(centre_side(0.2, &c, 1.0), Some(true));
        // The same edge with the other side inside.
        let c = [(0.3, true), (0.7, false), (0.3, true), (0.7, false)];
        assert_eq!(centre_side(0.2, &c, 1.0), Some(false));
        // Corners that cannot tell (all within a hair of the outline).
        assert_eq!(centre_side(0.2, &[(0.1, true), (0.1, false), (0.1, true), (0.1, false)], 1.0), None);
        assert_eq!(centre_side(f64::INFINITY, &[(f64::INFINITY, true); 4], 1.0), Some(true));
    }
}
