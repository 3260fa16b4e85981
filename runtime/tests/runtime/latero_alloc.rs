//! The per-tick path allocates nothing (counted by the test binary's global allocator).

use taxel_format::{BundleView, Mm, Tick};
use taxel_runtime::latero::LateroPlayer;

use crate::support::*;

#[test]
fn frames_allocate_nothing() {
    let mut list = Vec::new();
    for i in 0..100 {
        for j in 0..50 {
            list.push((1.0 + 1.1 * i as f32, 1.0 + 1.2 * j as f32, 0.5, 1.0));
        }
    }
    let bytes = bundle_bytes(
        stress2(),
        vec![full_surface(vibration(50_000), 0.3), full_surface(grating(2.0, 45.0), 0.3), dots(&list)],
    );
    let view = BundleView::parse(&bytes).unwrap();
    let mut out = [0u16; 64];
    let mut moved = 0u64;
    let info = allocation_counter::measure(|| {
        // Building the player with in-place storage allocates nothing either.
        let player = LateroPlayer::new(&view).unwrap();
        for k in 0..5_000u64 {
            let x = (k % 1200) as f32 * 0.1 - 5.0;
            let y = (k % 700) as f32 * 0.1 - 5.0;
            let stats = player.frame(Tick(k * 1_000_003), Mm(x), Mm(y), &mut out);
            moved += out.iter().filter(|&&c| c > 0).count() as u64 + stats.clamped as u64;
        }
    });
    assert_eq!(info.count_total, 0, "allocations while playing: {info:?}");
    assert!(moved > 0, "the frames were not all at rest");
}

/// The same for the distance layers every build writes (`VDST`, `GDST`):
/// a vibration and a grating layer over the whole surface, holding every
/// kind of tile (outside, inside, stored, plane, ridge, corner, notch, bend),
/// played anywhere on and off the surface, allocate nothing either.
#[test]
fn distance_layer_frames_allocate_nothing() {
    let entries: Vec<u8> = (0..8).collect();
    let codes: Vec<u8> = (0..=255).collect();
    // 4 mm tiles (0.5 mm pitch) over 112 x 60 mm, from just off the surface's corner.
    let layer = |kind| crate::latero_field::field(kind, -1.0, -0.5, 0.5, 28, 16, &entries, &codes, 0.0);
    let bytes = bundle_bytes(
        stress2(),
        vec![
            taxel_format::Chunk::Distance(layer(vibration(50_000))),
            taxel_format::Chunk::Distance(layer(grating(2.0, 45.0))),
        ],
    );
    let view = BundleView::parse(&bytes).unwrap();
    let mut out = [0u16; 64];
    let mut moved = 0u64;
    let info = allocation_counter::measure(|| {
        let player = LateroPlayer::new(&view).unwrap();
        for k in 0..5_000u64 {
            let x = (k % 1200) as f32 * 0.1 - 5.0;
            let y = (k % 700) as f32 * 0.1 - 5.0;
            let stats = player.frame(Tick(k * 1_000_003), Mm(x), Mm(y), &mut out);
            moved += out.iter().filter(|&&c| c > 0).count() as u64 + stats.clamped as u64;
        }
    });
    assert_eq!(info.count_total, 0, "allocations while playing distance layers: {info:?}");
    assert!(moved > 0, "the frames were not all at rest");
}

/// A device without an allocator loads a bundle file in its stored form
/// (SPEC.md 15) by inflating it into a buffer of the plain length: that
/// allocates nothing either, and gives the plain bundle byte for byte.
#[test]
fn a_stored_bundle_inflates_into_a_buffer_without_allocating() {
    let bytes =
        bundle_bytes(stress2(), vec![full_surface(vibration(50_000), 0.3), full_surface(grating(2.0, 45.0), 0.3)]);
    let file = taxel_format::stored::store(&bytes).unwrap();
    let mut buf = vec![0u8; taxel_format::stored::plain_len(&file).unwrap()];
    let mut ok = false;
    let info = allocation_counter::measure(|| {
        ok = taxel_format::stored::inflate_into(&file, &mut buf).is_ok();
    });
    assert_eq!(info.count_total, 0, "allocations while inflating: {info:?}");
    assert!(ok && buf == bytes, "the plain bundle comes back");
    assert!(LateroPlayer::new(&BundleView::parse(&buf).unwrap()).is_ok());
}
