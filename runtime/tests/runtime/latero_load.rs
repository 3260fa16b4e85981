//! Building players: family checks, storage, layer kinds.

use taxel_format::{BundleView, Family, Mm, Tick, profiles};
use taxel_runtime::RuntimeError;
use taxel_runtime::latero::{LateroPlayer, Layer};

use crate::support::*;

#[test]
fn a_bundle_for_another_family_is_refused_by_name() {
    for name in ["brush-4x3", "finger3"] {
        let p = profiles::builtin(name).unwrap();
        let bytes = bundle_bytes(p, vec![]);
        let view = BundleView::parse(&bytes).unwrap();
        let err = LateroPlayer::new(&view).unwrap_err();
        let RuntimeError::WrongFamily { expected, found, profile } = err.clone() else { panic!("{err:?}") };
        assert_eq!(expected, Family::Laterotactile);
        assert_eq!(found, p.family());
        assert_eq!(profile.as_str(), name);
        let msg = err.to_string();
        assert!(msg.contains(name) && msg.contains("laterotactile") && msg.contains(p.family().name()), "{msg}");
    }
}

#[test]
fn storage_too_small_is_refused_and_exact_storage_suffices() {
    let p = stress2();
    let chunks = vec![
        full_surface(grating(3.0, 0.0), 0.3),
        full_surface(vibration(50_000), 0.3),
        dots(&[(10.0, 10.0, 1.0, 1.0)]),
    ];
    let bytes = bundle_bytes(p, chunks);
    let view = BundleView::parse(&bytes).unwrap();
    let err = LateroPlayer::with_storage(&view, [Layer::EMPTY; 2]).unwrap_err();
    assert_eq!(err, RuntimeError::TooManyLayers { needed: 3, capacity: 2 });
    let player = LateroPlayer::with_storage(&view, [Layer::EMPTY; 3]).unwrap();
    assert_eq!(player.layer_count(), 3);
    let mut slice = [Layer::EMPTY; 3];
    let borrowed = LateroPlayer::with_storage(&view, &mut slice[..]).unwrap();
    let (mut a, mut b) = ([0u16; 64], [0u16; 64]);
    player.frame(Tick(7), Mm(10.0), Mm(10.0), &mut a);
    borrowed.frame(Tick(7), Mm(10.0), Mm(10.0), &mut b);
    assert_eq!(a, b);
}

#[test]
fn an_empty_scene_rests_and_short_outputs_are_not_overrun() {
    let bytes = bundle_bytes(stress2(), vec![]);
    let view = BundleView::parse(&bytes).unwrap();
    let player = LateroPlayer::new(&view).unwrap();
    assert_eq!(player.layer_count(), 0);
    let mut out = [7u16; 70];
    let stats = player.frame(Tick(0), Mm(50.0), Mm(30.0), &mut out);
    assert_eq!(stats.written, 64);
    assert!(out[..64].iter().all(|&c| c == 0));
    assert!(out[64..].iter().all(|&c| c == 7), "entries past the actuator count are left alone");
    let bytes = bundle_bytes(stress2(), vec![full_surface(grating(3.0, 0.0), 1.0)]);
    let view = BundleView::parse(&bytes).unwrap();
    let player = LateroPlayer::new(&view).unwrap();
    let mut short = [0u16; 10];
    assert_eq!(player.frame(Tick(0), Mm(50.0), Mm(30.0), &mut short).written, 10);
    let mut full = [0u16; 64];
    player.frame(Tick(0), Mm(50.0), Mm(30.0), &mut full);
    assert_eq!(short, full[..10]);
}

#[test]
fn other_array_shapes_follow_their_profile() {
    // A 3 x 5 array with another pitch, rate and resolution.
    let p = taxel_format::DeviceProfile {
        rows: 3,
        cols: 5,
        pitch_x_mm: 2.0,
        pitch_y_mm: 0.7,
        rate_hz: 2000,
        output_bits: 12,
        ..stress2()
    };
    let chunks = vec![full_surface(vibration(30_000), 0.9), full_surface(grating(5.0, 20.0), 0.1)];
    for (tick, x, y) in [(0, 30.0, 20.0), (13, 41.3, 7.9), (123_457, 77.7, 33.3)] {
        assert_matches_reference(&p, chunks.clone(), tick, x, y);
    }
}

#[test]
fn every_output_resolution_rounds_and_counts_like_the_reference() {
    use taxel_format::{BundleView, Tick};
    use taxel_runtime::latero::LateroPlayer;
    // A whole 8 x 8 block at up to 14 bits is quantised in 16-bit vector
    // lanes, at 15 and 16 bits (and other shapes) one code at a time: both must
    // give the reference's codes and count the same clamped sums. Uniform
    // masks keep the interpolation exact, so one step is a fair tolerance
    // even at 16 bits; the vibration and the grating overlap on purpose.
    for bits in [1, 8, 10, 14, 15, 16] {
        let p = taxel_format::DeviceProfile { output_bits: bits, ..stress2() };
        let chunks = vec![
            full_surface(vibration(50_000), 0.7),
            full_surface(grating(3.0, 30.0), 0.6),
            dots(&[(40.5, 30.2, 1.5, 0.9)]),
        ];
        let bytes = bundle_bytes(p, chunks.clone());
        let view = BundleView::parse(&bytes).unwrap();
        let player = LateroPlayer::new(&view).unwrap();
        let step = 1.0 / ((1u32 << bits) - 1) as f64;
        for (tick, x, y) in [(0u64, 40.0f32, 30.0f32), (3, 41.1, 29.3), (7, 12.3, 45.6)] {
            assert_matches_reference(&p, chunks.clone(), tick, x, y);
            let mut out = [0u16; 64];
            let stats = player.frame(Tick(tick), Mm(x), Mm(y), &mut out);
            let sums: Vec<f64> =
                (0..64).map(|k| reference(&p, &chunks, tick, x as f64, y as f64, k / 8, k % 8)).collect();
            // Sums within a hair of the rounding boundary may go either way.
            let surely = sums.iter().filter(|&&s| s > 1.0 + 0.5 * step + 1e-4).count() as u32;
            let maybe = sums.iter().filter(|&&s| s > 1.0 + 0.5 * step - 1e-4).count() as u32;
            assert!(
                (surely..=maybe).contains(&stats.clamped),
                "{bits} bits at tick {tick}: clamped {} not in {surely}..={maybe}",
                stats.clamped
            );
            assert!(out.iter().all(|&c| u32::from(c) < 1 << bits), "{bits} bits: {out:?}");
        }
    }
}
