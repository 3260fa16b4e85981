//! Dot tables (seed 000 eq. 1), found through the table's grid index.

use taxel_format::DotTableView;

use wide::bytemuck::cast;
use wide::{f32x4, i32x4};

use super::osc::{floor4, sin_turns4_quarter};
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
    // whatever the square root and the cosine made of them. (`s` is a sum
    // of squares times a positive factor, so it is not negative; a NaN
    // lane leaves the clamp as 1.)
    let inside = s.simd_lt(f32x4::ONE);
    let r = s.fast_min(f32x4::ONE).sqrt();
    // (r − P) / (2 (1 − P)) is within [−⅙, ½] turn, where the cosine needs
    // no reduction. The amplitude is folded into ½ + ½ cos, off the chain
    // of dependent steps that a dot's cost follows.
    // cos 2πu = sin 2π(¼ − u), the sine's polynomial taken directly: for
    // u ≥ 0 this is `cos_turns4_half`, lane for lane. On the plateau
    // (u < 0, so ¼ − u is up to 0.42) it is not the cosine, but it stays
    // at most 1 (measured over every f32 in [¼, 0.45]), which is all the
    // selection below needs.
    let half = f32x4::splat(0.5 * amplitude);
    let rim = half + half * sin_turns4_quarter(f32x4::splat(0.25) - (r - PLATEAU) * (0.5 / (1.0 - PLATEAU)));
    // On the plateau the amplitude, elsewhere the rim: the rim never
    // exceeds the amplitude (the polynomial is at most 1) and off the
    // plateau is not negative (at least −1), so the larger of the two is
    // the plateau's selection.
    let plateau = r.simd_le(f32x4::splat(PLATEAU)) & f32x4::splat(amplitude);
    rim.fast_max(plateau) & inside
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
    /// The largest radius, in the lanes of `[x0, x1, y0, y1]`: `[−r, r, −r, r]`.
    reach: f32x4,
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
            reach: f32x4::new([-g.max_radius, g.max_radius, -g.max_radius, g.max_radius]),
        }
    }

    /// Adds every dot that touches an actuator of rows `f.r0..f.r1` to `acc`.
    ///
    /// The table stores its dots sorted by grid cell, so the dots of cells
    /// `c0..=c1` in one grid row are one contiguous run: the query reads
    /// two cell starts per grid row under the array and then only dots that
    /// lie near it. The cost depends on the array's size and the local dot
    /// density, never on the size of the table.
    #[inline(always)]
    pub(crate) fn accumulate(&self, f: &Frame, acc: &mut Acc) {
        accumulate_dots(self, f, acc)
    }
}

/// What a frame's block needs to find the actuators a dot reaches.
struct Span {
    /// [`Frame`]'s `run_first` and `run_inv`: `[x_first, x_first,
    /// y_first, y_first]` and the reciprocal pitches in the same lanes.
    first: f32x4,
    inv: f32x4,
    /// The clamps of `[c0, c1, q0, q1]`: the columns on the surface and
    /// the block's rows on it, `lo..=hi` for the first column and row,
    /// `lo − 1..=hi − 1` for the last.
    lo: f32x4,
    hi: f32x4,
}

/// The sign bits of lanes 0 and 2.
const NEG02: i32x4 = i32x4::new([i32::MIN, 0, i32::MIN, 0]);

impl Span {
    #[inline(always)]
    fn new(f: &Frame) -> Self {
        let step = i32x4::new([0, 1, 0, 1]);
        Span {
            first: f.run_first,
            inv: f.run_inv,
            lo: f32x4::from_i32x4(f.run_lo - step),
            hi: f32x4::from_i32x4(f.run_hi - step),
        }
    }

    /// The dot's actuator columns `c0..=c1` and rows `q0..=q1`, as
    /// `[c0, c1, q0, q1]`: the first column at or past x − ρ and the last
    /// at or before x + ρ, the same for rows, clipped to the surface and
    /// the block (an empty range when the dot lies beside them: c0 > c1
    /// or q0 > q1). Each is a ceiling or a floor of `(bound − first) /
    /// pitch` (by the reciprocal) clamped to its lane's range, exactly
    /// `ceil_in` and `floor_in`; the ceilings are taken as floors of the
    /// negated lanes, so that the four round at once. The positions are
    /// finite, so no lane is NaN.
    #[inline(always)]
    fn of(&self, x: f32, y: f32, rho: f32) -> [i32; 4] {
        let neg = cast::<i32x4, f32x4>(NEG02);
        let ends = f32x4::new([x, x, y, y]) + (f32x4::splat(rho) ^ neg);
        let v = ((ends - self.first) * self.inv).fast_max(self.lo).fast_min(self.hi) ^ neg;
        let [c0, c1, q0, q1] = floor4(v).to_array();
        [c0.wrapping_neg(), c1, q0.wrapping_neg(), q1]
    }
}

kernel! {
/// [`DotLayer::accumulate`] (a `kernel!`).
fn accumulate_dots<'a>(layer: &DotLayer<'a>, f: &Frame, acc: &mut Acc) {
    accumulate_table(layer, f, acc)
}
}

/// The body of [`accumulate_dots`].
#[inline(always)]
fn accumulate_table(layer: &DotLayer<'_>, f: &Frame, acc: &mut Acc) {
    let t = &layer.table;
    // No column on the surface, or none of the block's rows: the runs'
    // bounds are `[c_lo, c_lo, r_lo, r_lo]` and `[c_hi, c_hi, r_hi, r_hi]`.
    if f.run_lo.simd_lt(f.run_hi).to_bitmask() != 0b1111 {
        return;
    }
    let g = t.grid;
    // The cells under the block's actuators widened by the largest radius
    // (the floor-and-clamp of `DotGrid::col_of`). Every index below is
    // far inside the ±2²² that the rounding trick accepts: grids have at
    // most 2²⁰ cells and arrays at most 64 columns.
    // (A product by the reciprocal may land a hair below a cell boundary
    // that the division would reach; a dot so placed is a full radius away
    // from every actuator the query serves, where eq. 1 gives 0.)
    // The four bounds at once, in the lanes. Clamped first, the index is
    // not negative, where truncation is the floor: one conversion. (The
    // positions are finite, so no lane is NaN; an overflow to ±∞ clamps.)
    let bounds = f.run_positions() + layer.reach;
    let cells = ((bounds - layer.origin) * layer.inv_cell).fast_max(f32x4::ZERO).fast_min(layer.last);
    let [gc0, gc1, gr0, gr1] = cast::<i32x4, [u32; 4]>(cells.fast_trunc_int());
    let span = Span::new(f);
    // The cells are clamped to the grid: each grid row's run is cells
    // `cell..cell + width` of the index, the next row's `grid.cols` on.
    let (width, stride) = (gc1.saturating_sub(gc0) as usize + 1, g.cols as usize);
    let mut cell = gr0 as usize * stride + gc0 as usize;
    // (A half-open range, cheaper to step than an inclusive one; `gr1` is
    // a truncation of at most the grid's last row, far below `u32::MAX`.)
    for _ in gr0..gr1 + 1 {
        let run = t.cell_run(cell, cell + width);
        cell += stride;
        for d in run {
            let (x, y, rho) = (d.x.0, d.y.0, d.radius.0);
            let [c0, c1, q0, q1] = span.of(x, y, rho);
            // No column: the next dot. (No row: the row loop is empty.)
            if c0 > c1 {
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

    /// [`dot_profile4`]'s larger-of-two selection of the plateau and its
    /// lone clamp give the lanes of the blend it replaced, bit for bit:
    /// every `s` near the plateau's edge and the rim, a sweep elsewhere,
    /// several amplitudes, and NaN and ∞.
    #[test]
    fn profile_equals_the_blended_one() {
        use super::super::osc::cos_turns4_half;
        let blended = |s: f32x4, amplitude: f32| {
            let inside = s.simd_lt(f32x4::ONE);
            let r = s.fast_max(f32x4::ZERO).fast_min(f32x4::ONE).sqrt();
            let half = f32x4::splat(0.5 * amplitude);
            let rim = half + half * cos_turns4_half((r - PLATEAU) * (0.5 / (1.0 - PLATEAU)));
            r.simd_le(f32x4::splat(PLATEAU)).select(f32x4::splat(amplitude), rim) & inside
        };
        let edges = [PLATEAU * PLATEAU, 1.0f32];
        let near = edges
            .iter()
            .flat_map(|e| (-20_000i32..20_000).map(move |k| f32::from_bits((e.to_bits() as i32 + k) as u32)));
        let sweep = (0..2_000_000).map(|k| k as f32 * 6e-7);
        let special = [0.0, f32::NAN, f32::INFINITY, f32::MAX, f32::MIN_POSITIVE];
        for s in near.chain(sweep).chain(special) {
            for amplitude in [1.0f32, 0.8, 0.3, 1e-3, 0.0] {
                let (got, want) = (dot_profile4(f32x4::splat(s), amplitude), blended(f32x4::splat(s), amplitude));
                assert_eq!(
                    got.to_array().map(f32::to_bits),
                    want.to_array().map(f32::to_bits),
                    "s = {s}, amplitude {amplitude}"
                );
            }
        }
    }

    /// [`Span::of`] against the scalar ceilings and floors it replaces,
    /// over frames near and far from the origin, surface and block limits,
    /// and dots beside, across and inside the array.
    #[test]
    fn span_equals_the_scalar_bounds() {
        use super::super::osc::{ceil_in, floor_in};
        let mut next = super::super::tests::lcg(0x853c_49e6_748f_ea9bu64);
        for _ in 0..200_000 {
            let unit = |n: u32| n as f32 / (1 << 24) as f32;
            let (cols, rows) = (1 + next() as usize % 16, 1 + next() as usize % 16);
            let (pitch_x, pitch_y) = (0.05 + 5.0 * unit(next()), 0.05 + 5.0 * unit(next()));
            let scale = [1.0, 100.0, 1e4][next() as usize % 3];
            let (x_first, y_first) = (scale * unit(next()), scale * unit(next()));
            let (col_lo, row_lo) = (next() as usize % cols, next() as usize % rows);
            let col_hi = col_lo + 1 + next() as usize % (cols - col_lo);
            let (r_lo, r_hi) = (row_lo, row_lo + 1 + next() as usize % (rows - row_lo));
            let (inv_x, inv_y) = (1.0 / pitch_x, 1.0 / pitch_y);
            let span = Span {
                first: f32x4::new([x_first, x_first, y_first, y_first]),
                inv: f32x4::new([inv_x, inv_x, inv_y, inv_y]),
                lo: f32x4::new([col_lo as f32, col_lo as f32 - 1.0, r_lo as f32, r_lo as f32 - 1.0]),
                hi: f32x4::new([col_hi as f32, col_hi as f32 - 1.0, r_hi as f32, r_hi as f32 - 1.0]),
            };
            let rho = 0.01 + 4.0 * unit(next());
            let x = x_first + (unit(next()) * 1.4 - 0.2) * cols as f32 * pitch_x;
            // On a row exactly, or anywhere.
            let y = if next().is_multiple_of(4) {
                y_first + (next() as usize % rows) as f32 * pitch_y + rho
            } else {
                y_first + (unit(next()) * 1.4 - 0.2) * rows as f32 * pitch_y
            };
            let (cl, ch, rl, rh) = (col_lo as i32, col_hi as i32, r_lo as i32, r_hi as i32);
            let want = [
                ceil_in((x - rho - x_first) * inv_x, cl, ch),
                floor_in((x + rho - x_first) * inv_x, cl - 1, ch - 1),
                ceil_in((y - rho - y_first) * inv_y, rl, rh),
                floor_in((y + rho - y_first) * inv_y, rl - 1, rh - 1),
            ];
            assert_eq!(span.of(x, y, rho), want, "dot ({x}, {y}) radius {rho}");
        }
    }
}
