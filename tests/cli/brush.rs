//! Brushed strokes end to end: stroke tables compiled for `brush-4x3`, played
//! by `taxel play` to a multichannel WAV (read back and checked against the
//! table per channel) and to frames CSV.

use std::path::Path;
use std::process::{Command, Output};

use taxel_compiler::brush::{BrushRequest, compile_strokes};
use taxel_format::{Bundle, Chunk, Manifest, StrokeTable, profiles};

fn taxel(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taxel")).args(args).output().unwrap()
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

/// The paper's diagonal stroke (corner to corner of the chair) over 1 s, as a bundle file.
fn diagonal_bundle(path: &Path) -> StrokeTable {
    let profile = profiles::builtin("brush-4x3").unwrap();
    let req = BrushRequest {
        polyline: vec![(0.0, 0.0), (189.0, 126.0)],
        duration_ms: 1000.0,
        intensity: 0.8,
        freq_hz: 200.0,
        start_ms: None,
        source: None,
        element: "diagonal".into(),
        line: None,
    };
    let mut diags = Vec::new();
    let table = compile_strokes(&[req], &profile, &mut diags).expect("stroke table");
    let mut b = Bundle::new(Manifest::new(profile));
    b.chunks.push(Chunk::Strokes(table.clone()));
    std::fs::write(path, b.to_bytes().unwrap()).unwrap();
    table
}

/// For each actuator, the tick intervals in which some point of the table drives it.
fn active_intervals(table: &StrokeTable, actuators: usize) -> Vec<Vec<(u64, u64)>> {
    let mut v = vec![Vec::new(); actuators];
    for s in &table.strokes {
        for p in &s.points {
            let on = s.start.0 + p.onset as u64;
            for d in &p.drives {
                v[d.actuator.0 as usize].push((on, on + p.duration as u64));
            }
        }
    }
    v
}

#[test]
fn play_writes_a_wav_that_follows_the_table() {
    let dir = tempfile::tempdir().unwrap();
    let bundle = dir.path().join("diagonal.taxel");
    let table = diagonal_bundle(&bundle);
    let wav = dir.path().join("drive.wav");
    let o = taxel(&["play", bundle.to_str().unwrap(), "--out", wav.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("12 channels"), "{}", text(&o));

    let mut r = hound::WavReader::open(&wav).unwrap();
    let spec = r.spec();
    assert_eq!((spec.channels, spec.sample_rate, spec.bits_per_sample), (12, 48_000, 16));
    let samples: Vec<i32> = r.samples::<i32>().map(|s| s.unwrap()).collect();
    let frames = samples.len() / 12;
    assert_eq!(frames, 48_000, "1 s at 48 kHz");
    let intervals = active_intervals(&table, 12);
    // 1 ms ticks: tick t covers samples 48 t .. 48 (t + 1).
    for (a, spans) in intervals.iter().enumerate() {
        let at = |n: usize| samples[n * 12 + a];
        let active = |n: usize| spans.iter().any(|&(on, end)| (on * 48..end * 48).contains(&(n as u64)));
        let mut loud_inside = 0usize;
        let mut inside = 0usize;
        for n in 0..frames {
            if active(n) {
                inside += 1;
                loud_inside += (at(n).abs() > 1000) as usize;
            } else {
                assert_eq!(at(n), 0, "actuator {a} sounds at sample {n}, outside its points");
            }
        }
        if inside > 0 {
            // Most of the activity is well above silence (ramps and zero crossings aside).
            assert!(loud_inside * 2 > inside, "actuator {a}: {loud_inside} of {inside}");
        }
    }
    // The diagonal starts on actuator 0 and ends on actuator 11; actuator 3 never sounds.
    assert!(!intervals[0].is_empty() && !intervals[11].is_empty() && intervals[3].is_empty());
}

#[test]
fn play_writes_frames_csv_to_a_file_or_standard_output() {
    let dir = tempfile::tempdir().unwrap();
    let bundle = dir.path().join("diagonal.taxel");
    let table = diagonal_bundle(&bundle);
    let csv = dir.path().join("frames.csv");
    let o = taxel(&["play", bundle.to_str().unwrap(), "--out", csv.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    let body = std::fs::read_to_string(&csv).unwrap();
    let mut lines = body.lines();
    let header: Vec<String> = std::iter::once("tick".to_string()).chain((0..12).map(|a| format!("a{a}"))).collect();
    assert_eq!(lines.next().unwrap(), header.join(","));
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    assert_eq!(rows.len(), 1001, "ticks 0..=1000");
    // Half way through the first point's activity, actuator 0 is at its table intensity.
    let p0 = &table.strokes[0].points[0];
    let mid = (p0.onset + p0.duration / 2) as usize;
    assert_eq!(rows[mid][0], mid as f64);
    assert!((rows[mid][1] - p0.drives[0].intensity as f64).abs() < 1e-5, "{:?}", rows[mid]);
    assert!(rows[1000][1..].iter().all(|&v| v == 0.0));

    let o = taxel(&["play", bundle.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(String::from_utf8_lossy(&o.stdout), body);
}

#[test]
fn play_refuses_a_broken_bundle_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let bundle = dir.path().join("broken.taxel");
    std::fs::write(&bundle, b"TAXL not really").unwrap();
    let wav = dir.path().join("drive.wav");
    let o = taxel(&["play", bundle.to_str().unwrap(), "--out", wav.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("broken.taxel"), "{}", text(&o));
    assert!(!wav.exists());
    let o = taxel(&["play", dir.path().join("missing.taxel").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
}

/// Compiles an SVG for `brush-4x3` with the library's SVG front end and writes the bundle.
fn build_svg(svg: &str, path: &Path) -> Vec<taxel_compiler::Diagnostic> {
    let opts = taxel_compiler::CompileOptions::new(profiles::builtin("brush-4x3").unwrap());
    let compiled = taxel_compiler::compile_svg(svg, &opts);
    let bundle = compiled.bundle.unwrap_or_else(|| panic!("no bundle: {:?}", compiled.diagnostics));
    std::fs::write(path, bundle.to_bytes().unwrap()).unwrap();
    compiled.diagnostics
}

/// Per channel, the largest absolute sample.
fn channel_peaks(wav: &Path) -> (hound::WavSpec, usize, Vec<i32>) {
    let mut r = hound::WavReader::open(wav).unwrap();
    let spec = r.spec();
    let mut peaks = vec![0i32; spec.channels as usize];
    let mut n = 0;
    for (i, s) in r.samples::<i32>().enumerate() {
        let c = i % spec.channels as usize;
        peaks[c] = peaks[c].max(s.unwrap().abs());
        n += 1;
    }
    (spec, n / spec.channels as usize, peaks)
}

#[test]
fn svg_brush_path_builds_and_plays_to_wav() {
    let dir = tempfile::tempdir().unwrap();
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="189mm" height="126mm" viewBox="0 0 189 126">
  <path id="sweep" d="M 0,63 L 189,63" fill="none" stroke="black" data-tactile="brush(duration: 1s)"/>
</svg>"#;
    let input = dir.path().join("sweep.svg");
    std::fs::write(&input, svg).unwrap();
    let bundle = dir.path().join("sweep.taxel");
    let o = taxel(&["build", input.to_str().unwrap(), "--profile", "brush-4x3", "-o", bundle.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    let wav = dir.path().join("drive.wav");
    let o = taxel(&["play", bundle.to_str().unwrap(), "--out", wav.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    let (spec, frames, peaks) = channel_peaks(&wav);
    assert_eq!((spec.channels, spec.sample_rate), (12, 48_000));
    assert_eq!(frames, 48_000, "a 1 s stroke");
    // Along row 1: the four actuators of that row sound, no other.
    for (a, &p) in peaks.iter().enumerate() {
        assert_eq!(p > 0, (4..8).contains(&a), "actuator {a}: peak {p}");
    }
}

#[test]
fn example_brush_scenes_build_and_play() {
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/brush");
    let mut seen = 0;
    for entry in std::fs::read_dir(&root).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("svg") {
            continue;
        }
        seen += 1;
        let svg = std::fs::read_to_string(&path).unwrap();
        let bundle = dir.path().join("scene.taxel");
        let diags = build_svg(&svg, &bundle);
        let loud: Vec<_> = diags.iter().filter(|d| d.severity >= taxel_compiler::Severity::Warning).collect();
        assert!(loud.is_empty(), "{}: {loud:?}", path.display());
        let wav = dir.path().join("scene.wav");
        let o = taxel(&["play", bundle.to_str().unwrap(), "--out", wav.to_str().unwrap()]);
        assert!(o.status.success(), "{}: {}", path.display(), text(&o));
        let (_, frames, peaks) = channel_peaks(&wav);
        assert!(frames >= 48_000 * 8 / 10, "{}: {frames} frames", path.display());
        assert!(peaks.iter().filter(|&&p| p > 0).count() >= 2, "{}: {peaks:?}", path.display());
    }
    assert!(seen >= 3, "brush examples found: {seen}");
}
