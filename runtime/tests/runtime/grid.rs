//! The grid player (Tactile Brush strokes) and its WAV sink: envelopes against
//! the table's timing, energy combination of shared actuators, refusal of
//! other bundles, no allocation per tick, exact long-run playback, and the
//! WAV read back and analysed per channel (frequency and envelope).

use std::io::Cursor;

use taxel_format::{
    ActuatorIndex, Bundle, BundleView, Chunk, DeviceProfile, Drive, Manifest, MilliHertz, Mm, Stroke, StrokePoint,
    StrokeTable, Tick, profiles,
};
use taxel_runtime::RuntimeError;
use taxel_runtime::grid::{ActuatorDrive, GridPlayer, envelope};
use taxel_runtime::sinks::wav::{SampleBits, carrier_phase, write_wav, write_wav_file};

fn brush() -> DeviceProfile {
    profiles::builtin("brush-4x3").expect("built-in profile")
}

fn point(onset: u32, duration: u32, drives: &[(u16, f32)]) -> StrokePoint {
    StrokePoint {
        onset,
        duration,
        peak: onset + duration / 2,
        x: Mm(0.0),
        y: Mm(0.0),
        drives: drives.iter().map(|&(a, i)| Drive { actuator: ActuatorIndex(a), intensity: i }).collect(),
    }
}

fn stroke(start: u64, duration: u32, hz: u32, points: Vec<StrokePoint>) -> Stroke {
    Stroke { start: Tick(start), duration, carrier: MilliHertz(hz * 1000), intensity: 1.0, source: None, points }
}

fn bytes_of(profile: DeviceProfile, strokes: Vec<Stroke>) -> Vec<u8> {
    let mut b = Bundle::new(Manifest::new(profile));
    b.chunks.push(Chunk::Strokes(StrokeTable { strokes }));
    b.to_bytes().expect("valid bundle")
}

/// A two-point stroke: actuator 0 from 0 to 300 ms, actuator 1 from 200 to 500 ms.
fn two_point_bytes() -> Vec<u8> {
    bytes_of(brush(), vec![stroke(100, 500, 200, vec![point(0, 300, &[(0, 0.9)]), point(200, 300, &[(1, 0.6)])])])
}

#[test]
fn amplitudes_follow_the_table_with_ramps() {
    let bytes = two_point_bytes();
    let view = BundleView::parse(&bytes).unwrap();
    let player = GridPlayer::new(&view).unwrap();
    assert_eq!(player.end(), Tick(600));
    let mut out = [ActuatorDrive::default(); 12];
    let amp = |t: u64, out: &mut [ActuatorDrive; 12]| {
        player.frame(Tick(t), out);
        (out[0].amplitude, out[1].amplitude)
    };
    // Before the stroke, at its onset (ramp starts from 0), 2.5 ms in (half way up a
    // 5 ms smoothstep ramp), on the plateau, half way down, and after.
    assert_eq!(amp(99, &mut out), (0.0, 0.0));
    assert_eq!(amp(100, &mut out), (0.0, 0.0));
    player.frame_at(Tick(102), 0.5, &mut out);
    assert!((out[0].amplitude - 0.45).abs() < 1e-6, "{}", out[0].amplitude);
    assert_eq!(amp(250, &mut out), (0.9, 0.0));
    assert_eq!(out[0].carrier, MilliHertz(200_000));
    assert_eq!(out[1].carrier, MilliHertz(0));
    assert_eq!(amp(350, &mut out), (0.9, 0.6));
    player.frame_at(Tick(397), 0.5, &mut out);
    assert!((out[0].amplitude - 0.45).abs() < 1e-6);
    assert_eq!(amp(400, &mut out), (0.0, 0.6));
    assert_eq!(amp(600, &mut out), (0.0, 0.0));
    assert!(out.iter().skip(2).all(|a| a.amplitude == 0.0));
}

#[test]
fn shared_actuators_combine_by_energy_and_clamp() {
    // Two strokes on actuator 5 at once: 0.6 and 0.8 give √(0.36 + 0.64) = 1,
    // 0.8 and 0.8 would give 1.13 and are clamped. The louder carrier wins.
    let bytes = bytes_of(
        brush(),
        vec![
            stroke(0, 100, 150, vec![point(0, 100, &[(5, 0.6), (6, 0.8)])]),
            stroke(0, 100, 250, vec![point(0, 100, &[(5, 0.8), (6, 0.8)])]),
        ],
    );
    let view = BundleView::parse(&bytes).unwrap();
    let player = GridPlayer::new(&view).unwrap();
    let mut out = [ActuatorDrive::default(); 12];
    let stats = player.frame(Tick(50), &mut out);
    assert!((out[5].amplitude - 1.0).abs() < 1e-6);
    assert_eq!(out[5].carrier, MilliHertz(250_000));
    assert_eq!(out[6].amplitude, 1.0);
    assert_eq!((stats.clamped, stats.active_points, stats.written), (1, 2, 12));
}

#[test]
fn other_bundles_are_refused() {
    let stress = Bundle::new(Manifest::new(profiles::builtin("stress2").unwrap())).to_bytes().unwrap();
    let view = BundleView::parse(&stress).unwrap();
    assert!(matches!(GridPlayer::new(&view), Err(RuntimeError::WrongFamily { .. })));
    let mut b = Bundle::new(Manifest::new(brush()));
    for _ in 0..9 {
        b.chunks.push(Chunk::Strokes(StrokeTable::default()));
    }
    let bytes = b.to_bytes().unwrap();
    let view = BundleView::parse(&bytes).unwrap();
    assert!(matches!(GridPlayer::new(&view), Err(RuntimeError::TooManyLayers { needed: 9, .. })));
}

#[test]
fn short_output_slices_are_filled_as_far_as_they_go() {
    let bytes = two_point_bytes();
    let view = BundleView::parse(&bytes).unwrap();
    let player = GridPlayer::new(&view).unwrap();
    let mut out = [ActuatorDrive::default(); 1];
    let stats = player.frame(Tick(350), &mut out);
    assert_eq!((stats.written, out[0].amplitude), (1, 0.9));
}

#[test]
fn frames_allocate_nothing() {
    let bytes = two_point_bytes();
    let view = BundleView::parse(&bytes).unwrap();
    let mut out = [ActuatorDrive::default(); 12];
    let mut sum = 0.0f32;
    let info = allocation_counter::measure(|| {
        let player = GridPlayer::new(&view).unwrap();
        for t in 0..1000u64 {
            player.frame_at(Tick(t), (t % 7) as f32 / 7.0, &mut out);
            sum += out.iter().map(|a| a.amplitude).sum::<f32>();
        }
    });
    assert_eq!(info.count_total, 0, "allocations while playing: {info:?}");
    assert!(sum > 0.0);
}

#[test]
fn a_stroke_a_day_later_plays_the_same() {
    let day = 86_400_000u64; // ticks of 1 ms in 24 hours
    let p = || vec![point(0, 300, &[(0, 0.9)]), point(200, 300, &[(1, 0.6)])];
    let early = bytes_of(brush(), vec![stroke(0, 500, 200, p())]);
    let late = bytes_of(brush(), vec![stroke(day, 500, 200, p())]);
    let (ve, vl) = (BundleView::parse(&early).unwrap(), BundleView::parse(&late).unwrap());
    let (pe, pl) = (GridPlayer::new(&ve).unwrap(), GridPlayer::new(&vl).unwrap());
    let (mut a, mut b) = ([ActuatorDrive::default(); 12], [ActuatorDrive::default(); 12]);
    for t in 0..520u64 {
        pe.frame_at(Tick(t), 0.25, &mut a);
        pl.frame_at(Tick(day + t), 0.25, &mut b);
        assert_eq!(a, b, "tick {t}");
    }
    // The carrier phase is exact too: sample n and n + 24 h of samples agree.
    let n = 12_345u64;
    assert_eq!(carrier_phase(n, 200_000, 48_000), carrier_phase(n + 48_000 * 86_400, 200_000, 48_000));
    assert_eq!(carrier_phase(48_000, 200_000, 48_000), 0.0);
    assert!((carrier_phase(60, 200_000, 48_000) - 0.25).abs() < 1e-12);
}

/// Goertzel power of `f` Hz in `x` sampled at `rate`.
fn goertzel(x: &[f64], f: f64, rate: f64) -> f64 {
    let w = std::f64::consts::TAU * f / rate;
    let c = 2.0 * w.cos();
    let (mut s1, mut s2) = (0.0, 0.0);
    for &v in x {
        let s = v + c * s1 - s2;
        s2 = s1;
        s1 = s;
    }
    s1 * s1 + s2 * s2 - c * s1 * s2
}

/// Read a WAV back into one `Vec<f64>` per channel, scaled to ±1.
fn read_channels(bytes: Vec<u8>) -> (hound::WavSpec, Vec<Vec<f64>>) {
    let mut r = hound::WavReader::new(Cursor::new(bytes)).unwrap();
    let spec = r.spec();
    let full = ((1i64 << (spec.bits_per_sample - 1)) - 1) as f64;
    let mut ch = vec![Vec::new(); spec.channels as usize];
    for (i, s) in r.samples::<i32>().enumerate() {
        ch[i % spec.channels as usize].push(s.unwrap() as f64 / full);
    }
    (spec, ch)
}

#[test]
fn wav_channels_carry_the_carrier_with_the_table_envelope() {
    // Actuator 0 at 150 Hz for 0-300 ms, actuator 1 at 270 Hz for 200-500 ms
    // (two strokes so that each has its own carrier).
    let bytes = bytes_of(
        brush(),
        vec![
            stroke(0, 300, 150, vec![point(0, 300, &[(0, 0.9)])]),
            stroke(200, 300, 270, vec![point(0, 300, &[(1, 0.6)])]),
        ],
    );
    let view = BundleView::parse(&bytes).unwrap();
    let player = GridPlayer::new(&view).unwrap();
    for bits in [SampleBits::Sixteen, SampleBits::TwentyFour] {
        let mut cur = Cursor::new(Vec::new());
        let summary = write_wav(&mut cur, &player, bits).unwrap();
        assert_eq!((summary.channels, summary.frames, summary.sample_rate), (12, 24_000, 48_000));
        let (spec, ch) = read_channels(cur.into_inner());
        assert_eq!((spec.channels, spec.sample_rate, spec.bits_per_sample), (12, 48_000, bits.bits()));
        assert_eq!(ch[0].len(), 24_000);
        let ms = |t: f64| (t * 48.0) as usize;
        for (c, f, on, off, amp) in [(0usize, 150.0, 0.0, 300.0, 0.9), (1, 270.0, 200.0, 500.0, 0.6)] {
            let x = &ch[c];
            // Silent outside its activity.
            assert!(x[..ms(on)].iter().chain(&x[ms(off)..]).all(|&v| v == 0.0), "channel {c} outside");
            // On the plateau (past the 5 ms ramps), the peak is the table intensity.
            let plateau = &x[ms(on + 10.0)..ms(off - 10.0)];
            let peak = plateau.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            assert!((peak - amp).abs() < 2e-3, "channel {c} peak {peak}");
            // The dominant frequency: Goertzel power at the carrier beats its neighbours,
            // and zero crossings count 2f per second.
            let p = goertzel(plateau, f, 48_000.0);
            for g in [f - 30.0, f + 30.0, 200.0, 100.0] {
                if (g - f).abs() > 1.0 {
                    assert!(p > 50.0 * goertzel(plateau, g, 48_000.0), "channel {c}: {f} vs {g}");
                }
            }
            let crossings = plateau.windows(2).filter(|w| (w[0] < 0.0) != (w[1] < 0.0)).count() as f64;
            let seconds = plateau.len() as f64 / 48_000.0;
            assert!((crossings / seconds / 2.0 - f).abs() < 5.0, "channel {c}: {}", crossings / seconds / 2.0);
            // The onset and offset ramps: inside amp · smoothstep(t / 5 ms), so
            // no click, from exactly 0 at the onset sample.
            assert_eq!(x[ms(on)], 0.0);
            for i in 0..240 {
                let u = i as f64 / 240.0;
                let bound = amp * u * u * (3.0 - 2.0 * u) + 1e-4;
                assert!(x[ms(on) + i].abs() <= bound, "channel {c} onset sample {i}: {}", x[ms(on) + i]);
                if i > 0 {
                    assert!(x[ms(off) - i].abs() <= bound, "channel {c} offset sample {i}");
                }
            }
            let rest: f64 = ch[2..].iter().flatten().map(|v| v.abs()).sum();
            assert_eq!(rest, 0.0);
        }
    }
}

#[test]
fn wav_files_are_written_atomically() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = two_point_bytes();
    let view = BundleView::parse(&bytes).unwrap();
    let player = GridPlayer::new(&view).unwrap();
    let path = dir.path().join("drive.wav");
    let s = write_wav_file(&path, &player, SampleBits::Sixteen).unwrap();
    assert_eq!(s.frames, 600 * 48);
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names, vec![std::ffi::OsString::from("drive.wav")]);
    assert_eq!(hound::WavReader::open(&path).unwrap().duration(), 28_800);
    let missing = dir.path().join("no/such/dir/drive.wav");
    let e = write_wav_file(&missing, &player, SampleBits::Sixteen).unwrap_err();
    assert!(e.to_string().contains("drive.wav"), "{e}");
    assert!(!missing.exists());
}

#[test]
fn envelope_is_never_above_one_and_symmetric() {
    for len in [1.0f32, 2.0, 7.0, 10.0, 300.0] {
        for i in 0..100 {
            let u = len * i as f32 / 100.0;
            let e = envelope(u, len - u, 5.0);
            assert!((0.0..=1.0).contains(&e));
            assert!((e - envelope(len - u, u, 5.0)).abs() < 1e-5 || u == 0.0);
        }
    }
}
