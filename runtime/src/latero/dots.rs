//! Dot tables (seed 000 eq. 1), found through the table's grid index.

use taxel_format::DotTableView;

use super::osc::{ceil_i32, cos_turns, floor_i32};
use super::{BLOCK, Frame};

/// Radius of the plateau of full deflection, as a fraction of the dot radius (seed 000, section 3.1).
pub const PLATEAU: f32 = 0.25;

/// Eq. 1 as a function of `s = r²` (`r` the distance from the centre over the radius):
/// 1 on the plateau, a half cosine down to 0 at the rim, 0 outside.
#[inline]
pub(crate) fn dot_profile(s: f32) -> f32 {
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

/// Adds every dot that touches an actuator of rows `f.r0..f.r1` to `acc`.
///
/// The table stores its dots sorted by grid cell, so the dots of cells
/// `c0..=c1` in one grid row are one contiguous index range: the query reads
/// two cell starts per grid row under the array and then only dots that lie
/// near it. The cost depends on the array's size and the local dot density,
/// never on the size of the table.
#[inline]
pub(crate) fn accumulate(t: &DotTableView<'_>, f: &Frame, acc: &mut [f32; BLOCK]) {
    if t.is_empty() || f.col_lo >= f.col_hi {
        return;
    }
    let (r_lo, r_hi) = (f.r0.max(f.row_lo), f.r1.min(f.row_hi));
    if r_lo >= r_hi {
        return;
    }
    let g = t.grid;
    let reach = g.max_radius;
    // The cells under the block's actuators widened by the largest radius
    // (the same floor-and-clamp as `DotGrid::col_of`, without a libm call).
    let cell = |v: f32, origin: f32, n: u32| floor_i32((v - origin) / g.cell_mm).clamp(0, n as i32 - 1) as u32;
    let (gc0, gc1) =
        (cell(f.col_x(f.col_lo) - reach, g.origin_x, g.cols), cell(f.col_x(f.col_hi - 1) + reach, g.origin_x, g.cols));
    let (gr0, gr1) =
        (cell(f.row_y(r_lo) - reach, g.origin_y, g.rows), cell(f.row_y(r_hi - 1) + reach, g.origin_y, g.rows));
    let (inv_px, inv_py) = (1.0 / f.pitch_x, 1.0 / f.pitch_y);
    for gr in gr0..=gr1 {
        let (first, last) = (t.cell(gc0, gr), t.cell(gc1, gr));
        for i in first.start..last.end.max(first.start) {
            let Some(d) = t.dot(i) else { continue };
            let rho = d.radius.0;
            // Actuator columns and rows within the dot's radius, clipped to
            // the surface and to this block.
            let c0 = ceil_i32((d.x.0 - rho - f.x_first) * inv_px).max(f.col_lo as i32);
            let c1 = floor_i32((d.x.0 + rho - f.x_first) * inv_px).min(f.col_hi as i32 - 1);
            let q0 = ceil_i32((d.y.0 - rho - f.y_first) * inv_py).max(r_lo as i32);
            let q1 = floor_i32((d.y.0 + rho - f.y_first) * inv_py).min(r_hi as i32 - 1);
            if c0 > c1 || q0 > q1 {
                continue;
            }
            let inv2 = 1.0 / (rho * rho);
            for r in q0 as usize..=q1 as usize {
                let ey = f.row_y(r) - d.y.0;
                let k0 = (r - f.r0) * f.cols;
                for c in c0 as usize..=c1 as usize {
                    let ex = f.col_x(c) - d.x.0;
                    let delta = dot_profile((ex * ex + ey * ey) * inv2);
                    if let Some(a) = acc.get_mut(k0 + c) {
                        *a += d.amplitude * delta;
                    }
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
            assert!((got - eq1(r)).abs() < 1e-5, "r = {r}: {got} vs {}", eq1(r));
        }
        assert_eq!(dot_profile(f32::NAN), 0.0);
        assert_eq!(dot_profile(f32::INFINITY), 0.0);
    }
}
