extern crate std;

use std::string::String;
use std::vec;
use std::vec::Vec;

use taxel_format::{Bundle, BundleView, Chunk, Manifest, Navigation, Pin, PinImage, Tick, profiles};

use super::*;

fn bytes(profile: &str, image: PinImage) -> Vec<u8> {
    let mut b = Bundle::new(Manifest::new(profiles::builtin(profile).unwrap()));
    b.chunks.push(Chunk::Pins(image));
    b.to_bytes().unwrap()
}

/// The frame's pins as text rows, `#` for raised (binary) or the height digit,
/// decoded from the packed bits as a device driver would.
fn art(frame: &[u8], cols: usize, rows: usize, bits: usize) -> String {
    let mut s = String::new();
    for r in 0..rows {
        for c in 0..cols {
            let i = (r * cols + c) * bits;
            let v = (frame[i / 8] >> (i % 8)) & ((1u16 << bits) - 1) as u8;
            s.push(match (bits, v) {
                (_, 0) => '.',
                (1, _) => '#',
                (_, v) => char::from(b'0' + v),
            });
        }
        s.push('\n');
    }
    s
}

#[test]
fn a_binary_frame_shows_the_viewport_bit_packed() {
    // A 70 x 45 image on the 60 x 40 Dot Pad: a diagonal from (58, 38) to (62, 42).
    let mut im = PinImage::new(70, 45);
    for k in 0..5 {
        im.set(58 + k, 38 + k, Pin::new(1, false));
    }
    let b = bytes("dotpad", im);
    let view = BundleView::parse(&b).unwrap();
    let p = PinsPlayer::new(&view).unwrap();
    assert_eq!(p.frame_len(), 300);
    let mut f = vec![0u8; 300];
    p.frame(Tick(0), Viewport { col: 55, row: 36 }, &mut f);
    let text = art(&f, 60, 40, 1);
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(&rows[0][..9], ".........");
    assert_eq!(&rows[2][..9], "...#.....");
    assert_eq!(&rows[3][..9], "....#....");
    assert_eq!(&rows[6][..9], ".......#.");
    assert_eq!(&rows[7][..9], ".........", "beyond the image the pins are flush");
    assert_eq!(text.matches('#').count(), 5);
}

#[test]
fn heights_pack_four_bits_per_pin_and_blink_from_the_tick() {
    let mut im = PinImage::new(60, 40);
    im.set(0, 0, Pin::new(4, false));
    im.set(1, 0, Pin::new(2, true));
    im.set(3, 0, Pin::new(3, false));
    im.blink_ms = 500;
    let b = bytes("graphiti", im);
    let view = BundleView::parse(&b).unwrap();
    let p = PinsPlayer::new(&view).unwrap();
    assert_eq!(p.frame_len(), 1200);
    let mut f = vec![0u8; 1200];
    p.frame(Tick(499), Viewport::ORIGIN, &mut f);
    assert_eq!(&art(&f, 60, 40, 4)[..5], "42.3.");
    assert_eq!(f[0], 0x24, "pin 0 in the low nibble, pin 1 in the high one");
    p.frame(Tick(500), Viewport::ORIGIN, &mut f);
    assert_eq!(&art(&f, 60, 40, 4)[..5], "4..3.", "the blinking pin is down for the second half-period");
    p.frame(Tick(1000), Viewport::ORIGIN, &mut f);
    assert_eq!(&art(&f, 60, 40, 4)[..5], "42.3.");
}

#[test]
fn the_blink_phase_holds_over_24_hours_of_ticks() {
    let mut im = PinImage::new(60, 40);
    im.set(0, 0, Pin::new(1, true));
    im.blink_ms = 300;
    let b = bytes("graphiti", im);
    let view = BundleView::parse(&b).unwrap();
    let p = PinsPlayer::new(&view).unwrap();
    // 1 kHz ticks for 24 hours: the pin toggles every 300 ticks, exactly.
    let day = 24 * 3600 * 1000u64;
    let mut toggles = 0u64;
    let mut last = p.blink_up(Tick(0));
    assert!(last, "blinking starts up");
    let mut k = 0;
    while k <= day {
        let up = p.blink_up(Tick(k));
        assert_eq!(up, (k / 300) % 2 == 0, "tick {k}");
        toggles += (up != last) as u64;
        last = up;
        // Visit both sides of every toggle without walking all 86 million ticks.
        k += if k % 300 == 299 { 1 } else { 299 - k % 300 };
    }
    assert_eq!(toggles, day / 300);
    // And far beyond: the phase comes from the tick alone.
    for k in [u64::MAX, u64::MAX - 299, 1 << 60] {
        assert_eq!(p.blink_up(Tick(k)), (k / 300) % 2 == 0, "tick {k}");
    }
}

#[test]
fn pages_and_panning_settle_the_viewport() {
    let mut im = PinImage::new(130, 50);
    im.navigation = Navigation::Pages;
    let b = bytes("dotpad", im.clone());
    let view = BundleView::parse(&b).unwrap();
    let p = PinsPlayer::new(&view).unwrap();
    assert_eq!(p.pages(), (3, 2));
    assert_eq!(p.page(4), Some(Viewport { col: 60, row: 40 }));
    assert_eq!(p.page(6), None);
    assert_eq!(p.settle(Viewport { col: 75, row: 41 }), Viewport { col: 60, row: 40 });
    assert_eq!(p.settle(Viewport { col: 999, row: 999 }), Viewport { col: 120, row: 40 });
    im.navigation = Navigation::Pan;
    let b = bytes("dotpad", im);
    let view = BundleView::parse(&b).unwrap();
    let p = PinsPlayer::new(&view).unwrap();
    assert_eq!(p.settle(Viewport { col: 13, row: 7 }), Viewport { col: 13, row: 7 });
    assert_eq!(p.settle(Viewport { col: 999, row: 999 }), Viewport { col: 70, row: 10 });
}

#[test]
fn refuses_other_families_and_short_buffers_are_safe() {
    let b = Bundle::new(Manifest::new(profiles::builtin("stress2").unwrap())).to_bytes().unwrap();
    let view = BundleView::parse(&b).unwrap();
    assert!(matches!(PinsPlayer::new(&view), Err(RuntimeError::WrongFamily { .. })));
    let mut im = PinImage::new(60, 40);
    im.set(59, 39, Pin::new(1, false));
    let b = bytes("dotpad", im);
    let view = BundleView::parse(&b).unwrap();
    let p = PinsPlayer::new(&view).unwrap();
    let mut short = [0u8; 7];
    assert_eq!(p.frame(Tick(0), Viewport { col: u32::MAX, row: u32::MAX }, &mut short), 7);
    let mut f = [0u8; 300];
    p.frame(Tick(0), Viewport::ORIGIN, &mut f);
    assert_eq!(f[299], 0x80, "the last pin is the last bit");
}
