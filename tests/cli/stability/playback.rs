//! Playback at the edges: 24 hours of ticks, overlapping layers past full
//! deflection, hostile carrier positions, and NaN or infinity in traces.

use std::process::Command;

use taxel_format::{
    Bundle, BundleView, Chunk, Manifest, MaskKind, MaskLayer, MaskSamples, MilliHertz, Mm, Tick, profiles,
};
use taxel_runtime::latero::LateroPlayer;
use taxel_runtime::trace::Trace;

fn full_mask(kind: MaskKind) -> Chunk {
    Chunk::Mask(MaskLayer {
        source: None,
        kind,
        amplitude: 1.0,
        origin_x: Mm(0.0),
        origin_y: Mm(0.0),
        px_per_mm: 1.0,
        width: 110,
        height: 60,
        samples: MaskSamples::U8(vec![255; 110 * 60]),
    })
}

fn bytes(chunks: Vec<Chunk>) -> Vec<u8> {
    let mut b = Bundle::new(Manifest::new(profiles::builtin("stress2").expect("profile")));
    b.chunks = chunks;
    b.to_bytes().expect("writes")
}

/// 24 hours at 1 kHz is tick 86,400,000. Phase comes from the integer tick,
/// so a 50 Hz frame then equals the frame at tick 0, and a 37.3 Hz frame
/// matches the f64 formula with the phase reduced exactly in integers.
#[test]
fn twenty_four_hour_playback() {
    let day = 86_400_000u64;
    for mhz in [50_000u32, 37_300] {
        let b = bytes(vec![full_mask(MaskKind::Vibration { freq: MilliHertz(mhz) })]);
        let view = BundleView::parse(&b).expect("reads");
        let player = LateroPlayer::new(&view).expect("player");
        let (mut a, mut z) = ([0u16; 64], [0u16; 64]);
        for k in 0..20u64 {
            player.frame(Tick(k), Mm(50.0), Mm(30.0), &mut z);
            player.frame(Tick(day + k), Mm(50.0), Mm(30.0), &mut a);
            // Exact phase in turns: (tick · mHz mod 10^6) / 10^6, then eq. 2.
            let turns = (((day + k) * mhz as u64) % 1_000_000) as f64 / 1e6;
            let c = (std::f64::consts::TAU * turns).cos();
            for (i, &v) in a.iter().enumerate() {
                let (row, col) = (i / 8, i % 8);
                let want = if row % 2 != col % 2 { 0.5 + 0.5 * c } else { 0.5 - 0.5 * c } * 1023.0;
                assert!((v as f64 - want).abs() <= 1.0, "{mhz} mHz, tick day+{k}, actuator {i}: {v} vs {want:.2}");
            }
            if mhz == 50_000 {
                assert_eq!(a, z, "hour 24 differs from hour 0 at tick {k}");
            }
        }
        // The largest tick a u64 holds still plays finite, in-range codes.
        player.frame(Tick(u64::MAX), Mm(50.0), Mm(30.0), &mut a);
        assert!(a.iter().all(|&v| v <= 1023));
    }
}

/// Two full-deflection layers over the same place add to 2: the runtime
/// clamps to full deflection and counts the clamped samples.
#[test]
fn overlapping_layers_clamp_and_count() {
    let b = bytes(vec![
        full_mask(MaskKind::Grating { wavelength: Mm(1e6), angle_deg: 90.0 }),
        full_mask(MaskKind::Grating { wavelength: Mm(1e6), angle_deg: 0.0 }),
    ]);
    let view = BundleView::parse(&b).expect("reads");
    let player = LateroPlayer::new(&view).expect("player");
    let mut out = [0u16; 64];
    let stats = player.frame(Tick(0), Mm(0.0), Mm(0.0), &mut out);
    // Near the origin both cosines are ≈ 1: each layer gives ≈ 1, the sum ≈ 2.
    let on: Vec<_> = out.iter().filter(|&&v| v > 0).collect();
    assert!(!on.is_empty() && on.iter().all(|&&v| v == 1023), "{out:?}");
    assert!(stats.clamped > 0);
}

/// NaN, infinite and absurd carrier positions put every actuator at rest.
#[test]
fn hostile_positions_rest() {
    let b = bytes(vec![full_mask(MaskKind::Vibration { freq: MilliHertz(50_000) })]);
    let view = BundleView::parse(&b).expect("reads");
    let player = LateroPlayer::new(&view).expect("player");
    let mut out = [7u16; 64];
    for (x, y) in [(f32::NAN, 1.0), (1.0, f32::INFINITY), (f32::NEG_INFINITY, 0.0), (1e30, 1e30), (-1e-30, 1e38)] {
        player.frame(Tick(3), Mm(x), Mm(y), &mut out);
        assert!(out.iter().all(|&v| v == 0), "({x}, {y}): {out:?}");
    }
}

/// NaN and infinity in a trace: refused with the line and the column, and
/// `taxel play` writes no output.
#[test]
fn nan_and_infinity_in_traces() {
    for (bad, line) in [("NaN", 3), ("inf", 3), ("-inf", 3), ("1e999", 3)] {
        let text = format!("t_ms,x_mm,y_mm\n0,10,10\n5,{bad},10\n");
        let e = Trace::parse(text.as_bytes()).expect_err(bad).to_string();
        assert!(e.contains(&format!("line {line}")) && e.contains("x_mm"), "{bad}: {e}");
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let bundle = dir.path().join("b.taxel");
    std::fs::write(&bundle, bytes(vec![full_mask(MaskKind::Vibration { freq: MilliHertz(50_000) })])).expect("write");
    let trace = dir.path().join("t.csv");
    std::fs::write(&trace, "t_ms,x_mm,y_mm\n0,10,10\nNaN,10,10\n").expect("write");
    let frames = dir.path().join("f.csv");
    let out = Command::new(env!("CARGO_BIN_EXE_taxel"))
        .args(["play", bundle.to_str().expect("utf-8"), "--trace", trace.to_str().expect("utf-8"), "--out"])
        .arg(&frames)
        .output()
        .expect("runs");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("t.csv") && err.contains("line 3"), "{err}");
    assert!(!frames.exists());
}
