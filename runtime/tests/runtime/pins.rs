//! The pin player's frame path allocates nothing and never panics, whatever
//! the viewport and tick (counted by the test binary's global allocator).

use taxel_format::{Bundle, BundleView, Chunk, Manifest, Navigation, Pin, PinImage, Tick, profiles};
use taxel_runtime::pins::{PinsPlayer, Viewport};

#[test]
fn frames_allocate_nothing_at_any_viewport() {
    let mut im = PinImage::new(200, 130);
    im.navigation = Navigation::Pan;
    for r in 0..130 {
        for c in 0..200 {
            if (c * 7 + r * 3) % 5 == 0 {
                im.set(c, r, Pin::new(1 + (c % 4) as u8, r % 3 == 0));
            }
        }
    }
    im.blink_ms = 300;
    let mut b = Bundle::new(Manifest::new(profiles::builtin("graphiti").unwrap()));
    b.chunks.push(Chunk::Pins(im));
    let bytes = b.to_bytes().unwrap();
    let view = BundleView::parse(&bytes).unwrap();
    let mut out = [0u8; 1200];
    let mut raised = 0u64;
    let info = allocation_counter::measure(|| {
        let player = PinsPlayer::new(&view).unwrap();
        for k in 0..2_000u64 {
            let vp = Viewport { col: (k * 37 % 260) as u32, row: (k * 11 % 190) as u32 };
            player.frame(Tick(k.wrapping_mul(0x9E37_79B9_7F4A_7C15)), vp, &mut out);
            raised += out.iter().map(|b| b.count_ones() as u64).sum::<u64>();
        }
        player.frame(Tick(u64::MAX), Viewport { col: u32::MAX, row: u32::MAX }, &mut out);
    });
    assert_eq!(info.count_total, 0, "allocations while playing: {info:?}");
    assert!(raised > 0, "some frames had raised pins");
}
