//! How a sampled height field is stored for the device: heights quantised
//! to the device's resolution in the tiled encoding (format 4.6,
//! `format-spec/SPEC.md` section 9.1), gradients left to the player.

use taxel_format::{DeviceProfile, FIELD_CONTACT, HeightEncoding, HeightField};

/// The height step of `f` for a device whose outputs have `output_bits`
/// bits: half a code of either output the heights drive.
///
/// - Intensity is `k2 · |h|` with the highest `|h|` at full scale, so a
///   height error of `max |h| / (2 · levels)` is half an intensity code.
/// - Rhythm is `k1 · |∇f|` with the largest gradient at full scale, and the
///   player derives the gradient from two node heights, each within half a
///   step, so it errs by at most `step / cell`: a step of
///   `cell · max |∇h| / (2 · levels)` keeps that within half a rhythm code.
///
/// The step never goes below `range / (2²⁴ − 1)`, so every code stays exact
/// in `f32`; a field without height or slope gets a step of 1 mm.
pub fn height_step(f: &HeightField, output_bits: u8) -> f32 {
    let levels = ((1u64 << output_bits.clamp(1, 24)) - 1) as f64;
    let contact = || (0..f.heights.len()).filter(|&k| f.flags.get(k).is_some_and(|fl| fl & FIELD_CONTACT != 0));
    let (mut lo, mut hi, mut habs, mut g) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64, 0.0f64);
    for k in contact() {
        let h = f.heights[k] as f64;
        lo = lo.min(h);
        hi = hi.max(h);
        habs = habs.max(h.abs());
        let (gx, gy) = (f.grad_x.get(k).copied().unwrap_or(0.0), f.grad_y.get(k).copied().unwrap_or(0.0));
        g = g.max((gx as f64).hypot(gy as f64));
    }
    let by_height = habs / (2.0 * levels);
    let by_slope = f.cell.0 as f64 * g / (2.0 * levels);
    let step = [by_height, by_slope].into_iter().filter(|&s| s > 0.0).fold(f64::INFINITY, f64::min);
    let step = if step.is_finite() { step } else { 1.0 };
    let floor = if hi > lo { (hi - lo) / ((1u64 << 24) - 2) as f64 } else { 0.0 };
    step.max(floor) as f32
}

/// `f` in the tiled encoding for `profile` (its gradients stay as the
/// writer's hint and give the largest gradient the player scales by).
pub fn tiled(mut f: HeightField, profile: &DeviceProfile) -> HeightField {
    let step = height_step(&f, profile.output_bits);
    let mut base = f32::INFINITY;
    let mut g = 0.0f32;
    for k in 0..f.heights.len() {
        if f.flags.get(k).is_some_and(|fl| fl & FIELD_CONTACT != 0) {
            base = base.min(f.heights[k]);
            let (gx, gy) = (f.grad_x.get(k).copied().unwrap_or(0.0), f.grad_y.get(k).copied().unwrap_or(0.0));
            g = g.max(libm_hypot(gx, gy));
        }
    }
    let base = if base.is_finite() { base } else { 0.0 };
    f.encoding = HeightEncoding::Tiled { step, base, max_gradient: g.min(f.gradient_cap) };
    f
}

/// `sqrt(x² + y²)` in `f32`, as the 4.0 format derives its largest gradient.
fn libm_hypot(x: f32, y: f32) -> f32 {
    (x * x + y * y).sqrt()
}
