//! The block quantisation and the frame's runs against their plain scalar
//! forms.

use super::*;

/// A 64-bit linear congruential generator (Knuth's MMIX constants)
/// from `seed`: each call gives the top 24 bits of the next state.
pub(super) fn lcg(mut s: u64) -> impl FnMut() -> u32 {
    move || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 40) as u32
    }
}

/// [`quantise_block`] gives [`quantise`]'s codes and count for sums
/// anywhere from below 0 to far above 1, +∞ included (but for a sum
/// exactly half a step above 1, whose count may differ).
#[test]
fn block_quantisation_equals_the_scalar_one() {
    let mut s = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    };
    for max in [1.0f32, 255.0, 1023.0, 4095.0, VECTOR_MAX_CODE] {
        let clamp_at = 1.0 + 0.5 / max;
        for _ in 0..2_000 {
            let mut acc: Acc = [0.0; BLOCK];
            for a in acc.iter_mut() {
                let u = (next() >> 40) as f32 / (1u64 << 24) as f32;
                *a = match next() % 8 {
                    0 => u * 2.0 - 0.5,
                    1 => (u * 4.0 * max).round() / max + [-0.5, 0.5, 0.0][next() as usize % 3] / max,
                    2 => 1.0 + (u - 0.5) * 2.0 / max,
                    3 => u * 1e6,
                    4 => u * f32::MAX,
                    5 => f32::INFINITY,
                    _ => u,
                };
                // Exactly half a step above 1, the codes agree but the
                // counts need not: the vector rounds the tie to even,
                // which for an odd `max_code` is above it and counts.
                if *a == clamp_at {
                    *a += 1.0 / max;
                }
            }
            let (mut block, mut scalar) = ([0u16; BLOCK], [0u16; BLOCK]);
            let n = quantise_block(&mut block, &acc, &BlockScale::new(max));
            let m = quantise(&mut scalar, &acc, clamp_at, max);
            assert_eq!((block, n), (scalar, m), "max code {max}, sums {acc:?}");
        }
    }
}

/// [`Frame::runs`] against a scan of the positions, over arrays far from
/// and near the origin, pitches, surface and block limits, and bounds
/// anywhere: beside the array, between actuators and exactly on one.
#[test]
fn runs_equal_a_scan_of_the_positions() {
    let mut next = lcg(0x9e37_79b9_7f4a_7c15u64);
    for _ in 0..200_000 {
        let unit = |n: u32| n as f32 / (1 << 24) as f32;
        let (cols, rows) = (1 + next() as usize % 16, 1 + next() as usize % 16);
        let pitch_x = [1.2, 1.4, 0.05 + 5.0 * unit(next())][next() as usize % 3];
        let pitch_y = [1.4, 1.2, 0.05 + 5.0 * unit(next())][next() as usize % 3];
        let scale = [1.0, 100.0, 1e4, 1e5][next() as usize % 4];
        let (col_lo, row_lo) = (next() as usize % cols, next() as usize % rows);
        let (col_hi, row_hi) =
            (col_lo + next() as usize % (cols - col_lo + 1), row_lo + next() as usize % (rows - row_lo + 1));
        let r0 = next() as usize % rows;
        let r1 = (r0 + 1 + next() as usize % rows).min(rows);
        let clock = osc::PhaseClock::new(1000);
        let mut f = Frame::new(clock, cols, rows, pitch_x, pitch_y);
        let (x_first, y_first) = (scale * unit(next()), scale * unit(next()));
        f.set_position(x_first, y_first);
        (f.col_lo, f.col_hi, f.row_lo, f.row_hi) = (col_lo, col_hi, row_lo, row_hi);
        f.set_block(r0, r1);
        // A bound on an actuator, between two, or anywhere around the array.
        let mut bound = |first: f32, pitch: f32, n: usize| match next() % 3 {
            0 => first + (next() as usize % (n + 2)) as u32 as f32 * pitch - pitch,
            1 => first + (next() as f32 / (1 << 24) as f32) * (n + 4) as f32 * pitch - 2.0 * pitch,
            _ => first + (next() as usize % (n + 2)) as u32 as f32 * pitch - pitch + 1e-3 * pitch,
        };
        let (a, b) = (bound(f.x_first, pitch_x, cols), bound(f.x_first, pitch_x, cols));
        let (c, d) = (bound(f.y_first, pitch_y, rows), bound(f.y_first, pitch_y, rows));
        let (x0, x1, y0, y1) = (a.min(b), a.max(b), c.min(d), c.max(d));
        let got = f.runs(f32x4::new([x0, x1, y0, y1]));
        let scan = |lo: usize, hi: usize, bound: f32, pos: &dyn Fn(usize) -> f32| {
            (lo..hi).find(|&i| pos(i) >= bound).unwrap_or(hi.max(lo))
        };
        let (rlo, rhi) = (r0.max(row_lo), r1.min(row_hi));
        let want = [
            scan(col_lo, col_hi, x0, &|c| f.col_x(c)),
            scan(col_lo, col_hi, x1, &|c| f.col_x(c)),
            scan(rlo, rhi, y0, &|r| f.row_y(r)),
            scan(rlo, rhi, y1, &|r| f.row_y(r)),
        ];
        assert_eq!(got, want, "bounds {:?} in a frame from ({}, {})", [x0, x1, y0, y1], f.x_first, f.y_first);
    }
}
