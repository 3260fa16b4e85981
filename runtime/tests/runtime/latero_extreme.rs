//! Hostile but valid bundles and carrier positions: the player never panics
//! (integer overflow included: tests build with debug assertions) and every
//! code stays in range.

use proptest::prelude::*;
use taxel_format::{BundleView, Chunk, MaskLayer, MaskSamples, Mm, Tick};
use taxel_runtime::latero::LateroPlayer;

use crate::support::*;

fn coordinate() -> impl Strategy<Value = f32> {
    prop_oneof![-1e6f32..1e6, -200.0f32..200.0, Just(0.0), Just(110.0), Just(60.0), Just(-1e30), Just(1e30)]
}

fn mask() -> impl Strategy<Value = Chunk> {
    (
        (coordinate(), coordinate()),
        prop_oneof![1e-3f32..1e-2, 0.5f32..20.0, 1e3f32..1e4],
        (1u32..6, 1u32..6),
        prop_oneof![1e-3f32..0.1, 0.5f32..10.0, 1e5f32..1e6],
        -360.0f32..=360.0,
        any::<bool>(),
        any::<u32>(),
    )
        .prop_map(|((ox, oy), ppm, (w, h), lambda, angle, vib, mhz)| {
            let kind = if vib { vibration(mhz.max(1)) } else { grating(lambda, angle) };
            Chunk::Mask(MaskLayer {
                origin_x: Mm(ox.clamp(-1e6, 1e6)),
                origin_y: Mm(oy.clamp(-1e6, 1e6)),
                px_per_mm: ppm,
                width: w,
                height: h,
                samples: MaskSamples::U16(vec![u16::MAX; (w * h) as usize]),
                ..uniform_mask(kind, 1.0, 0.0, 0.0, 1, 1)
            })
        })
}

fn dot_table() -> impl Strategy<Value = Chunk> {
    prop::collection::vec(
        (coordinate(), coordinate(), prop_oneof![1e-6f32..1e-3, 0.1f32..5.0, 1e3f32..1e6], 0.0f32..=1.0),
        1..20,
    )
    .prop_map(|v| {
        dots(&v.into_iter().map(|(x, y, r, a)| (x.clamp(-1e6, 1e6), y.clamp(-1e6, 1e6), r, a)).collect::<Vec<_>>())
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 100, ..ProptestConfig::default() })]

    #[test]
    fn frames_stay_in_range_whatever_the_scene_and_position(
        masks in prop::collection::vec(mask(), 0..4),
        tables in prop::collection::vec(dot_table(), 0..3),
        positions in prop::collection::vec((coordinate(), coordinate(), any::<u64>()), 1..8),
    ) {
        let mut chunks = masks;
        chunks.extend(tables);
        let bytes = bundle_bytes(stress2(), chunks);
        let view = BundleView::parse(&bytes).unwrap();
        let player = LateroPlayer::new(&view).unwrap();
        let mut out = [0u16; 64];
        for (x, y, tick) in positions.into_iter().chain([(f32::NAN, 0.0, 0), (0.0, f32::NEG_INFINITY, 1)]) {
            player.frame(Tick(tick), Mm(x), Mm(y), &mut out);
            prop_assert!(out.iter().all(|&c| c <= 1023));
        }
    }
}
