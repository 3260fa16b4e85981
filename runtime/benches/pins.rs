//! Pin player cost: one whole frame (every pin of the display, bit-packed)
//! per call, for a binary display (Dot Pad, 60 x 40 at 1 bit) and a display
//! with heights and blinking (Graphiti, 60 x 40 at 4 bits), on an image of
//! four pages so that the viewport is away from the origin.
//!
//! `cargo bench -p taxel-runtime --features bench --bench pins -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use taxel_format::{Bundle, BundleView, Chunk, Manifest, Navigation, Pin, PinImage, Tick, profiles};
use taxel_runtime::pins::{PinsPlayer, Viewport};

/// A 120 x 80 image, about a third of its pins raised (diagonal hatching),
/// every seventh raised pin blinking where the device can blink.
fn bundle(profile: &str, blink: bool) -> Vec<u8> {
    let p = profiles::builtin(profile).unwrap();
    let taxel_format::FamilyParams::Pins(q) = p.params else { unreachable!() };
    let mut im = PinImage::new(120, 80);
    im.navigation = Navigation::Pan;
    for r in 0..80 {
        for c in 0..120 {
            if (c + r) % 3 == 0 {
                im.set(c, r, Pin::new(1 + ((c / 3) % q.height_levels as u32) as u8, blink && (c + r) % 7 == 0));
            }
        }
    }
    if blink {
        im.blink_ms = 500;
    }
    let mut b = Bundle::new(Manifest::new(p));
    b.chunks.push(Chunk::Pins(im));
    b.to_bytes().unwrap()
}

fn frames(c: &mut Criterion) {
    let mut g = c.benchmark_group("pins_frame");
    for (profile, blink) in [("dotpad", false), ("graphiti", true)] {
        let bytes = bundle(profile, blink);
        let view = BundleView::parse(&bytes).unwrap();
        let player = PinsPlayer::new(&view).unwrap();
        let mut out = vec![0u8; player.frame_len()];
        g.throughput(Throughput::Elements(1));
        let mut tick = 0u64;
        g.bench_function(profile, |b| {
            b.iter(|| {
                tick = tick.wrapping_add(37);
                player.frame(black_box(Tick(tick)), black_box(Viewport { col: 31, row: 17 }), &mut out)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, frames);
criterion_main!(benches);
