//! Dot tables (seed 000 eq. 1), found through the table's grid index.

use taxel_format::DotTableView;

use wide::bytemuck::cast;
use wide::{f32x4, i32x4};

use super::osc::{ceil_in, cos_turns4_half, floor_in};
use super::{Acc, Frame, LANES, add_lanes};

/// Lane offsets 0, 1, 2, 3.
const LANE: i32x4 = i32x4::new([0, 1, 2, 3]);

/// Radius of the plateau of full deflection, as a fraction of the dot radius (seed 000, section 3.1).
pub const PLATEAU: f32 = 0.25;

/// Eq. 1 as a function of `s = r²` (`r` the distance from the centre over the radius):
/// 1 on the plateau, a half cosine down to 0 at the rim, 0 outside. The
/// scalar form, kept as the reference the four-lane [`dot_profile4`] is
/// tested against.
#[cfg(test)]
fn dot_profile(s: f32) -> f32 {
    use super::osc::cos_turns;
    if s.is_nan() || s >= 1.0 {
        return 0.0;
    }
    let r = libm::sqrtf(s);
    if r <= PLATEAU {
        1.0
    } else {
        // cos(π (r − P) / (1 − P)) = cos(2π u) with u = (r − P) / (2 (1 − P)).
        0.5 + 0.5 * cos_turns((r - PLATEAU) * (0.5 / (1.0 - PLATEAU)))
    }
}

/// `dot_profile` (the tests' scalar reference) on four lanes, times `amplitude`: equal to it lane by
/// lane up to the last bit of the square root and of the scaling (both use
/// the same cosine), so within 1e-6 of full deflection.
#[inline(always)]
pub(crate) fn dot_profile4(s: f32x4, amplitude: f32) -> f32x4 {
    // NaN and s ≥ 1 fail `s < 1` and rest: the last mask gives them 0
    // whatever the square root and the cosine made of them.
    let inside = s.simd_lt(f32x4::ONE);
    let r = s.fast_max(f32x4::ZERO).fast_min(f32x4::ONE).sqrt();
    // (r − P) / (2 (1 − P)) is within [−⅙, ½] turn, where the cosine needs
    // no reduction. The amplitude is folded into ½ + ½ cos, off the chain
    // of dependent steps that a dot's cost follows.
    let half = f32x4::splat(0.5 * amplitude);
    let rim = half + half * cos_turns4_half((r - PLATEAU) * (0.5 / (1.0 - PLATEAU)));
    let v = r.simd_le(f32x4::splat(PLATEAU)).select(f32x4::splat(amplitude), rim);
    v & inside
}

/// A dot table prepared for playback.
#[derive(Debug, Clone, Copy)]
pub(crate) struct DotLayer<'a> {
    table: DotTableView<'a>,
    /// The reciprocal of the grid's cell size, so the per-tick path
    /// multiplies where it would divide.
    inv_cell: f32,
    /// The grid's origin and its last cell column and row, in the lanes of
    /// a query's `[x0, x1, y0, y1]`, so that the query finds its four cell
    /// bounds at once.
    origin: f32x4,
    last: f32x4,
}

impl<'a> DotLayer<'a> {
    pub(crate) fn new(table: DotTableView<'a>) -> Self {
        let g = table.grid;
        // Grids have at least one cell each way (`saturating_sub` only
        // keeps a malformed view from panicking), at most 2²⁰: exact in f32.
        let (cols, rows) = (g.cols.saturating_sub(1) as f32, g.rows.saturating_sub(1) as f32);
        DotLayer {
            table,
            // The format keeps cells positive and finite.
            inv_cell: 1.0 / g.cell_mm,
            origin: f32x4::new([g.origin_x, g.origin_x, g.origin_y, g.origin_y]),
            last: f32x4::new([cols, cols, rows, rows]),
        }
    }

    /// Adds every dot that touches an actuator of rows `f.r0..f.r1` to `acc`.
    ///
    /// The table stores its dots sorted by grid cell, so the dots of cells
    /// `c0..=c1` in one grid row are one contiguous run: the query reads
    /// two cell starts per grid row under the array and then only dots that
    /// lie near it. The cost depends on the array's size and the local dot
    /// density, never on the size of the table.
    ///
    /// Not inlined: inlined, its set-up is hoisted into the frame's
    /// prologue and paid by every frame, even one without this kind of layer.
    #[inline(never)]
    pub(crate) fn accumulate(&self, f: &Frame, acc: &mut Acc) {
        accumulate_table(self, f, acc)
    }
}

/// [`DotLayer::accumulate`].
#[inline(always)]
fn accumulate_table(layer: &DotLayer<'_>, f: &Frame, acc: &mut Acc) {
    let t = &layer.table;
    let (r_lo, r_hi) = (f.r0.max(f.row_lo), f.r1.min(f.row_hi));
    if t.is_empty() || f.col_lo >= f.col_hi || r_lo >= r_hi {
        return;
    }
    let g = t.grid;
    let reach = g.max_radius;
    // The cells under the block's actuators widened by the largest radius
    // (the floor-and-clamp of `DotGrid::col_of`). Every index below is
    // far inside the ±2²² that `floor_in` and `ceil_in` accept: grids have
    // at most 2²⁰ cells and arrays at most 64 columns.
    // (A product by the reciprocal may land a hair below a cell boundary
    // that the division would reach; a dot so placed is a full radius away
    // from every actuator the query serves, where eq. 1 gives 0.)
    // The four bounds at once, in the lanes. Clamped first, the index is
    // not negative, where truncation is the floor: one conversion. (The
    // positions are finite, so no lane is NaN; an overflow to ±∞ clamps.)
    let bounds = f.run_positions() + f32x4::new([-reach, reach, -reach, reach]);
    let cells = ((bounds - layer.origin) * layer.inv_cell).fast_max(f32x4::ZERO).fast_min(layer.last);
    let [gc0, gc1, gr0, gr1] = cast::<i32x4, [u32; 4]>(cells.fast_trunc_int());
    let (inv_px, inv_py) = (f.inv_pitch_x, f.inv_pitch_y);
    let (col_lo, col_hi) = (f.col_lo as i32, f.col_hi as i32);
    let (row_lo, row_hi) = (r_lo as i32, r_hi as i32);
    for gr in gr0..=gr1 {
        for d in t.row_run(gc0, gc1, gr) {
            let (x, y, rho) = (d.x.0, d.y.0, d.radius.0);
            // Actuator columns and rows within the dot's radius, clipped to
            // the surface and to this block (an empty range when the dot
            // lies beside them: then c0 > c1 or q0 > q1).
            let c0 = ceil_in((x - rho - f.x_first) * inv_px, col_lo, col_hi);
            let c1 = floor_in((x + rho - f.x_first) * inv_px, col_lo - 1, col_hi - 1);
            let q0 = ceil_in((y - rho - f.y_first) * inv_py, row_lo, row_hi);
            let q1 = floor_in((y + rho - f.y_first) * inv_py, row_lo - 1, row_hi - 1);
            if c0 > c1 || q0 > q1 {
                continue;
            }
            let inv2 = 1.0 / (rho * rho);
            // Four columns at a time; lanes past c1 rest (they may fall on
            // the next row's first columns or past the block: they add 0).
            for r in q0..=q1 {
                let ey = f.row_y(r as usize) - y;
                let k0 = (r as usize - f.r0) * f.cols;
                let mut c = c0;
                while c <= c1 {
                    let cols = i32x4::splat(c) + LANE;
                    let ex = f32x4::splat(f.x_first) + f32x4::from_i32x4(cols) * f.pitch_x - x;
                    let v = dot_profile4((ex * ex + ey * ey) * inv2, d.amplitude);
                    let v = cols.simd_le(i32x4::splat(c1)).select(v, f32x4::ZERO);
                    add_lanes(acc, k0 + c as usize, v);
                    c += LANES as i32;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profile_follows_equation_one() {
        let eq1 = |r: f64| {
            if r <= 0.25 {
                1.0
            } else if r <= 1.0 {
                0.5 + 0.5 * (core::f64::consts::PI * (r - 0.25) / 0.75).cos()
            } else {
                0.0
            }
        };
        for k in 0..=1200 {
            let r = k as f64 / 1000.0;
            let got = dot_profile((r * r) as f32) as f64;
            let lanes = dot_profile4(f32x4::splat((r * r) as f32), 1.0).to_array();
            assert!(lanes.iter().all(|&l| (l as f64 - got).abs() < 1e-6), "r = {r}: {lanes:?} vs {got}");
            assert!((got - eq1(r)).abs() < 1e-5, "r = {r}: {got} vs {}", eq1(r));
        }
        assert_eq!(dot_profile(f32::NAN), 0.0);
        assert_eq!(dot_profile4(f32x4::splat(f32::NAN), 0.7).to_array(), [0.0; 4]);
        assert_eq!(dot_profile4(f32x4::splat(f32::INFINITY), 0.7).to_array(), [0.0; 4]);
        assert_eq!(dot_profile(f32::INFINITY), 0.0);
    }
}
