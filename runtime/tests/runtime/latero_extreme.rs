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

proptest! {
    #![proptest_config(ProptestConfig { cases: 100, ..ProptestConfig::default() })]

    /// The distance layers every build writes (random fields holding every
    /// kind of tile, anywhere within ±1e6 mm) at hostile carrier positions
    /// (far away, on the surface's edges, NaN, infinite): no panic, every
    /// code in range.
    #[test]
    fn distance_layer_frames_stay_in_range_whatever_the_position(
        origins in prop::collection::vec((coordinate(), coordinate()), 1..4),
        pitch in prop::sample::select(vec![0.25f32, 0.5, 1.0]),
        (cols, rows) in (1u32..6, 1u32..6),
        entries in prop::collection::vec(any::<u8>(), 1..20),
        codes in prop::collection::vec(any::<u8>(), 81..400),
        soft in prop::sample::select(vec![0.0f32, 0.3, 2.0]),
        positions in prop::collection::vec((coordinate(), coordinate(), any::<u64>()), 1..8),
    ) {
        let chunks: Vec<Chunk> = origins
            .iter()
            .enumerate()
            .map(|(k, &(x, y))| {
                let kind = if k % 2 == 0 { vibration(50_000) } else { grating(2.0, 30.0) };
                let (x, y) = (x.clamp(-1e6, 1e6), y.clamp(-1e6, 1e6));
                Chunk::Distance(crate::latero_field::field(kind, x, y, pitch, cols, rows, &entries, &codes, soft))
            })
            .collect();
        let bytes = bundle_bytes(stress2(), chunks);
        let view = BundleView::parse(&bytes).unwrap();
        let player = LateroPlayer::new(&view).unwrap();
        let mut out = [0u16; 64];
        let edges = [(0.0, 0.0, 0), (110.0, 60.0, 1), (f32::NAN, 0.0, 2), (0.0, f32::NEG_INFINITY, 3), (f32::INFINITY, f32::NAN, 4)];
        for (x, y, tick) in positions.into_iter().chain(edges) {
            player.frame(Tick(tick), Mm(x), Mm(y), &mut out);
            prop_assert!(out.iter().all(|&c| c <= 1023));
        }
        // Carriers on each layer's own tiles, so the kernels run, not only the bounds checks.
        for &(x, y) in &origins {
            let (x, y) = (x.clamp(-1e6, 1e6), y.clamp(-1e6, 1e6));
            player.frame(Tick(7), Mm(x + 1.0), Mm(y + 1.0), &mut out);
            prop_assert!(out.iter().all(|&c| c <= 1023));
        }
    }
}
