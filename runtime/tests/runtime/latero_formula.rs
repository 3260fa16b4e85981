//! The player's frames against a direct f64 evaluation of the seed-000
//! equations (support.rs), within one 10-bit step, at random positions and
//! ticks; plus mask sampling, surface and box edges, composite and clamping.

use proptest::prelude::*;
use taxel_format::{Chunk, MaskLayer, MaskSamples, Mm};

use crate::support::*;

/// Carrier positions that keep the whole array well inside the surface.
fn inside() -> impl Strategy<Value = (f32, f32)> {
    (6.0f32..104.0, 6.0f32..54.0)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn dots_follow_equation_one(
        (x, y) in inside(),
        list in prop::collection::vec((-6.0f32..6.0, -6.0f32..6.0, 0.3f32..4.0, 0.0f32..=1.0), 1..6),
    ) {
        // Dots scattered around the carrier (they may overlap: the sum is then clamped, as the reference does).
        let d: Vec<_> = list.iter().map(|&(dx, dy, r, a)| (x + dx, y + dy, r, a)).collect();
        assert_matches_reference(&stress2(), vec![dots(&d)], 0, x, y);
    }

    #[test]
    fn vibration_follows_equation_two(
        (x, y) in inside(),
        tick in 0u64..100_000_000,
        mhz in 1_000u32..400_000,
        amplitude in 0.0f32..=1.0,
    ) {
        assert_matches_reference(&stress2(), vec![full_surface(vibration(mhz), amplitude)], tick, x, y);
    }

    #[test]
    fn grating_follows_equation_three(
        (x, y) in inside(),
        lambda in 0.5f32..12.0,
        angle in -360.0f32..=360.0,
        amplitude in 0.0f32..=1.0,
        tick in 0u64..1_000_000,
    ) {
        assert_matches_reference(&stress2(), vec![full_surface(grating(lambda, angle), amplitude)], tick, x, y);
    }

    #[test]
    fn composite_of_all_three_is_their_clamped_sum(
        (x, y) in inside(),
        tick in 0u64..10_000_000,
        lambda in 1.0f32..8.0,
        angle in -90.0f32..90.0,
        (dx, dy, r) in (-4.0f32..4.0, -4.0f32..4.0, 0.5f32..3.0),
    ) {
        let chunks = vec![
            Chunk::Mask(uniform_mask(vibration(50_000), 0.4, x - 20.0, y - 20.0, 20, 40)),
            Chunk::Mask(uniform_mask(grating(lambda, angle), 0.5, x, y - 20.0, 20, 40)),
            dots(&[(x + dx, y + dy, r, 0.8)]),
        ];
        assert_matches_reference(&stress2(), chunks, tick, x, y);
    }

    #[test]
    fn masks_are_sampled_bilinearly_at_actuators(
        (x, y) in (0.0f32..110.0, 0.0f32..60.0),
        (ox, oy) in (-5.0f32..100.0, -5.0f32..50.0),
        (w, h) in (1u32..40, 1u32..40),
        ppm in 0.3f32..6.0,
        seed in any::<u64>(),
        wide in any::<bool>(),
    ) {
        // Random samples (from a small LCG), 8 or 16 bits, a random box that
        // may cross the surface's edge, and a carrier that may hang off it.
        let mut s = seed | 1;
        let mut next = || { s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407); (s >> 33) as u32 };
        let n = (w * h) as usize;
        let samples = if wide {
            MaskSamples::U16((0..n).map(|_| next() as u16).collect())
        } else {
            MaskSamples::U8((0..n).map(|_| next() as u8).collect())
        };
        let m = MaskLayer { samples, px_per_mm: ppm, width: w, height: h, origin_x: Mm(ox), origin_y: Mm(oy),
            ..uniform_mask(grating(3.0, 0.0), 1.0, 0.0, 0.0, 1, 1) };
        assert_matches_reference(&stress2(), vec![Chunk::Mask(m)], 0, x, y);
    }
}

#[test]
fn a_linear_ramp_mask_is_reproduced_exactly_between_pixel_centres() {
    // Samples a·i + b·j: bilinear interpolation reproduces the plane, so the
    // value at an actuator is known without interpolating anything.
    let (w, h, ppm) = (40u32, 30u32, 2.0f32);
    let (a, b) = (1000.0, 700.0);
    let samples: Vec<u16> = (0..h).flat_map(|j| (0..w).map(move |i| (a * i as f64 + b * j as f64) as u16)).collect();
    let m = MaskLayer {
        samples: MaskSamples::U16(samples),
        px_per_mm: ppm,
        width: w,
        height: h,
        origin_x: Mm(30.0),
        origin_y: Mm(20.0),
        ..uniform_mask(vibration(50_000), 1.0, 0.0, 0.0, 1, 1)
    };
    let p = stress2();
    let bytes = bundle_bytes(p, vec![Chunk::Mask(m)]);
    let (x, y) = (40.13, 27.71);
    // Tick 5 at 50 Hz is a quarter period: cos = 0, so eq. 2 gives ½ everywhere.
    let frame = play(&bytes, 5, x, y);
    for row in 0..8 {
        for col in 0..8 {
            let (ax, ay) = actuator_pos(&p, x as f64, y as f64, row, col);
            let u = (ax - 30.0) * ppm as f64 - 0.5;
            let v = (ay - 20.0) * ppm as f64 - 0.5;
            let want = 0.5 * (a * u + b * v) / 65535.0 * 1023.0;
            let got = frame[8 * row + col] as f64;
            assert!((got - want).abs() <= 1.0, "({row}, {col}): {got} vs {want}");
        }
    }
}

#[test]
fn actuators_off_the_surface_or_outside_a_box_rest() {
    let p = stress2();
    // A grating mask reaching 10 mm beyond every edge of the surface.
    let chunks = vec![Chunk::Mask(uniform_mask(grating(2.4, 90.0), 1.0, -10.0, -10.0, 130, 80))];
    let bytes = bundle_bytes(p, chunks);
    // Carrier at the top-left corner: rows 0-3 and columns 0-3 are off the page.
    let frame = play(&bytes, 0, 0.0, 0.0);
    for row in 0..8 {
        for col in 0..8 {
            if row < 4 || col < 4 {
                assert_eq!(frame[8 * row + col], 0, "({row}, {col}) is off the surface");
            }
        }
    }
    // Somewhere on the page columns alternate 1 and 0 (λ = 2 pitches).
    let frame = play(&bytes, 0, 24.0 + 4.2, 30.0);
    assert_eq!(&frame[..8], &[1023, 0, 1023, 0, 1023, 0, 1023, 0]);
    // Far off the page in every direction, and at non-finite positions: rest.
    for (x, y) in [(-50.0, 30.0), (200.0, 30.0), (50.0, -50.0), (50.0, 500.0), (f32::NAN, 1.0), (1.0, f32::INFINITY)] {
        assert!(play(&bytes, 0, x, y).iter().all(|&c| c == 0), "carrier at ({x}, {y})");
    }
    // A mask box of 10 x 10 mm: only actuators inside it move.
    let bytes = bundle_bytes(p, vec![Chunk::Mask(uniform_mask(grating(2.4, 90.0), 1.0, 50.0, 30.0, 10, 10))]);
    let frame = play(&bytes, 0, 50.0, 30.0);
    for row in 0..8 {
        for col in 0..8 {
            let (ax, ay) = actuator_pos(&p, 50.0, 30.0, row, col);
            if ax < 50.0 || ay < 30.0 {
                assert_eq!(frame[8 * row + col], 0, "({row}, {col}) is outside the box");
            }
        }
    }
    assert!(frame.iter().any(|&c| c > 900), "inside the box the grating moves");
    assert_matches_reference(
        &p,
        vec![Chunk::Mask(uniform_mask(grating(2.4, 90.0), 1.0, 50.0, 30.0, 10, 10))],
        0,
        50.0,
        30.0,
    );
}

#[test]
fn overlapping_layers_are_clamped_and_counted() {
    use taxel_format::{BundleView, Tick};
    use taxel_runtime::latero::LateroPlayer;
    let p = stress2();
    // Two full-surface gratings in phase plus a vibration: the sum exceeds 1 on most actuators.
    let chunks = vec![
        full_surface(grating(4.0, 30.0), 1.0),
        full_surface(grating(4.0, 30.0), 1.0),
        full_surface(vibration(50_000), 0.5),
    ];
    let bytes = bundle_bytes(p, chunks.clone());
    let view = BundleView::parse(&bytes).unwrap();
    let player = LateroPlayer::new(&view).unwrap();
    let mut out = [0u16; 64];
    let (x, y, tick) = (40.0f32, 30.0f32, 3u64);
    let stats = player.frame(Tick(tick), Mm(x), Mm(y), &mut out);
    let sums: Vec<f64> = (0..64).map(|k| reference(&p, &chunks, tick, x as f64, y as f64, k / 8, k % 8)).collect();
    let surely = sums.iter().filter(|&&s| s > 1.0 + 1e-3).count() as u32;
    let maybe = sums.iter().filter(|&&s| s > 1.0).count() as u32;
    assert!(surely > 10, "the scene must overlap ({surely})");
    assert!((surely..=maybe).contains(&stats.clamped), "clamped {} not in {surely}..={maybe}", stats.clamped);
    assert_eq!(stats.written, 64);
    for (k, &s) in sums.iter().enumerate() {
        if s >= 1.0 {
            assert_eq!(out[k], 1023, "actuator {k} is clamped to full deflection");
        }
    }
}

#[test]
fn hour_24_equals_hour_0_for_a_50_hz_vibration() {
    let p = stress2();
    let bytes = bundle_bytes(p, vec![full_surface(vibration(50_000), 0.8)]);
    for (x, y) in [(20.0, 20.0), (55.5, 31.25)] {
        for k in 0..40 {
            assert_eq!(play(&bytes, 86_400_000 + k, x, y), play(&bytes, k, x, y), "tick {k}");
        }
    }
    // And far beyond where tick · mhz overflows 64 bits (u64::MAX is divisible by 5).
    let frame0 = play(&bytes, 0, 20.0, 20.0);
    let far = u64::MAX - u64::MAX % 1_000_000;
    assert_eq!(play(&bytes, far, 20.0, 20.0), frame0);
    // The frames do move: a quarter period later they differ.
    assert_ne!(play(&bytes, 86_400_005, 20.0, 20.0), frame0);
}

#[test]
fn dots_match_the_reference_among_ten_thousand() {
    // A 100 x 100 lattice of dots 1.1 x 0.55 mm apart with radius 0.25 (no overlaps):
    // the reference sums over all of them, the player looks only nearby.
    let mut list = Vec::new();
    for i in 0..100 {
        for j in 0..100 {
            let a = ((i * 7 + j * 13) % 10) as f32 / 9.0;
            list.push((1.0 + 1.1 * i as f32, 1.0 + 0.55 * j as f32, 0.25, a));
        }
    }
    let p = stress2();
    for (x, y) in [(10.0, 10.0), (57.3, 28.9), (108.0, 58.0), (0.5, 0.5)] {
        assert_matches_reference(&p, vec![dots(&list)], 0, x, y);
    }
}

#[test]
fn masks_ending_inside_the_array_are_sampled_to_their_last_samples() {
    // The carrier at (50, 30): columns sit at 45.8 + 1.2 c, rows at 25.1 + 1.4 r.
    // Each box below starts between two columns (so a group of four columns
    // starts at column 5, 6 or 7 and runs past the last row's end) and ends
    // after the array's last row, or just inside it, so that the lowest
    // actuators read the mask's last row and last column (where a four-byte
    // read would run past the samples). Random samples, 8 and 16 bits, at
    // several resolutions, checked against the f64 reference.
    let mut s = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 33) as u32
    };
    for first_col in 4..8 {
        let ox = 45.8 + 1.2 * first_col as f32 + 0.3;
        for (ppm, oy) in [(1.0f32, 33.0f32), (2.0, 34.3), (10.0, 30.0), (0.5, 26.0)] {
            for wide in [false, true] {
                let (w, h) =
                    (((50.0 + 4.2 + 0.5 - ox) * ppm).ceil() as u32, ((35.0 - oy) * ppm).ceil().max(1.0) as u32);
                let n = (w * h) as usize;
                let samples = if wide {
                    MaskSamples::U16((0..n).map(|_| next() as u16).collect())
                } else {
                    MaskSamples::U8((0..n).map(|_| next() as u8).collect())
                };
                for kind in [vibration(50_000), grating(3.0, 30.0)] {
                    let m = MaskLayer {
                        samples: samples.clone(),
                        px_per_mm: ppm,
                        width: w,
                        height: h,
                        origin_x: Mm(ox),
                        origin_y: Mm(oy),
                        ..uniform_mask(kind, 1.0, 0.0, 0.0, 1, 1)
                    };
                    assert_matches_reference(&stress2(), vec![Chunk::Mask(m)], 3, 50.0, 30.0);
                }
            }
        }
    }
}
