//! `taxel play` for laterotactile bundles: frames from an exploration trace,
//! checked against the seed-000 grating formula; bad traces refused with the
//! file and line, leaving no output file behind.

use std::f64::consts::TAU;
use std::path::Path;
use std::process::{Command, Output};

use taxel_format::{
    Bundle, Chunk, DotKind, DotTable, Manifest, MaskKind, MaskLayer, MaskSamples, MilliHertz, Mm, profiles,
};

fn taxel(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taxel")).args(args).output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A stress2 bundle with one full-surface layer.
fn write_bundle(path: &Path, kind: MaskKind) {
    let mut b = Bundle::new(Manifest::new(profiles::builtin("stress2").unwrap()));
    b.chunks.push(Chunk::Mask(MaskLayer {
        source: None,
        kind,
        amplitude: 1.0,
        origin_x: Mm(0.0),
        origin_y: Mm(0.0),
        px_per_mm: 1.0,
        width: 110,
        height: 60,
        samples: MaskSamples::U8(vec![255; 110 * 60]),
    }));
    b.chunks.push(Chunk::Dots(DotTable { kind: DotKind::Symbol, dots: vec![] }));
    std::fs::write(path, b.to_bytes().unwrap()).unwrap();
}

/// Parses a frames CSV into (tick, codes) rows, checking the header.
fn read_frames(text: &str) -> Vec<(u64, Vec<u16>)> {
    let mut lines = text.lines();
    let header: Vec<String> = std::iter::once("tick".to_string()).chain((0..64).map(|a| format!("a{a}"))).collect();
    assert_eq!(lines.next().unwrap(), header.join(","));
    lines
        .map(|l| {
            let v: Vec<u64> = l.split(',').map(|f| f.parse().unwrap()).collect();
            assert_eq!(v.len(), 65, "{l}");
            (v[0], v[1..].iter().map(|&c| c as u16).collect())
        })
        .collect()
}

#[test]
fn frames_follow_the_trace_and_the_grating_formula() {
    let dir = tempfile::tempdir().unwrap();
    let bundle = dir.path().join("grating.taxel");
    write_bundle(&bundle, MaskKind::Grating { wavelength: Mm(4.0), angle_deg: 30.0 });
    let trace = dir.path().join("trace.csv");
    // Right along x for 10 ms, then down along y until 25 ms.
    std::fs::write(&trace, "t_ms,x_mm,y_mm\n0,20,30\n10,30,30\n25,30,36\n").unwrap();
    let out = dir.path().join("frames.csv");
    let o =
        taxel(&["play", bundle.to_str().unwrap(), "--trace", trace.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let frames = read_frames(&std::fs::read_to_string(&out).unwrap());
    assert_eq!(frames.iter().map(|f| f.0).collect::<Vec<_>>(), (0..=25).collect::<Vec<_>>());
    for (tick, codes) in &frames {
        let t = *tick as f64;
        let (x, y) = if t <= 10.0 { (20.0 + t, 30.0) } else { (30.0, 30.0 + (t - 10.0) * 0.4) };
        for row in 0..8 {
            for col in 0..8 {
                let ax = x + (col as f64 - 3.5) * 1.2;
                let ay = y + (row as f64 - 3.5) * 1.4;
                let th = 30f64.to_radians();
                let d = -ay * th.cos() - ax * th.sin();
                let want = (0.5 + 0.5 * (TAU * d / 4.0).cos()) * 1023.0;
                let got = codes[8 * row + col] as f64;
                assert!((got - want).abs() <= 1.0, "tick {tick} ({row}, {col}): {got} vs {want}");
            }
        }
    }
    // Without --out the same frames go to standard output.
    let o = taxel(&["play", bundle.to_str().unwrap(), "--trace", trace.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(read_frames(&String::from_utf8(o.stdout).unwrap()), frames);
}

#[test]
fn a_vibration_plays_from_the_first_trace_tick() {
    let dir = tempfile::tempdir().unwrap();
    let bundle = dir.path().join("vibration.taxel");
    write_bundle(&bundle, MaskKind::Vibration { freq: MilliHertz(50_000) });
    let trace = dir.path().join("still.csv");
    // A still carrier from 100 ms to 120 ms: ticks 100..=120, 50 Hz = one period per 20 ticks.
    std::fs::write(&trace, "t_ms,x_mm,y_mm\n100,50,30\n120,50,30\n").unwrap();
    let o = taxel(&["play", bundle.to_str().unwrap(), "--trace", trace.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let frames = read_frames(&String::from_utf8(o.stdout).unwrap());
    assert_eq!((frames[0].0, frames.last().unwrap().0), (100, 120));
    // Tick 100 is a whole number of periods: cos = 1, eq. 2 gives 0 where
    // row and column parities agree and 1 where they differ.
    assert_eq!(&frames[0].1[..4], &[0, 1023, 0, 1023]);
    assert_eq!(frames[0].1, frames[20].1);
    // Half a period later the pattern is inverted.
    assert_eq!(&frames[10].1[..4], &[1023, 0, 1023, 0]);
}

#[test]
fn bad_traces_are_refused_with_file_and_line_and_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let bundle = dir.path().join("b.taxel");
    write_bundle(&bundle, MaskKind::Grating { wavelength: Mm(3.0), angle_deg: 0.0 });
    let cases = [
        ("missing.csv", "t_ms,x_mm\n0,1\n", "line 1"),
        ("word.csv", "t_ms,x_mm,y_mm\n0,1,2\n1,one,2\n", "line 3"),
        ("backwards.csv", "t_ms,x_mm,y_mm\n0,1,2\n5,1,2\n3,1,2\n", "line 4"),
        ("nan.csv", "t_ms,x_mm,y_mm\n0,1,2\n1,NaN,2\n", "line 3"),
        ("inf.csv", "t_ms,x_mm,y_mm\n0,1,2\ninf,1,2\n", "line 3"),
        ("empty.csv", "", "no samples"),
        ("header-only.csv", "t_ms,x_mm,y_mm\n", "no samples"),
        ("eternal.csv", "t_ms,x_mm,y_mm\n0,1,2\n1e300,1,2\n", "above the limit"),
    ];
    for (name, text, want) in cases {
        let trace = dir.path().join(name);
        std::fs::write(&trace, text).unwrap();
        let out = dir.path().join(format!("{name}.frames.csv"));
        let o = taxel(&[
            "play",
            bundle.to_str().unwrap(),
            "--trace",
            trace.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{name}: {err}");
        assert!(err.contains(name) && err.contains(want), "{name}: {err}");
        assert!(!out.exists(), "{name}: no partial output");
    }
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().starts_with('.'))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
    // Without a trace a laterotactile bundle cannot play.
    let o = taxel(&["play", bundle.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--trace"), "{}", stderr(&o));
}

#[test]
fn an_earlier_output_survives_a_failed_run() {
    let dir = tempfile::tempdir().unwrap();
    let bundle = dir.path().join("b.taxel");
    write_bundle(&bundle, MaskKind::Grating { wavelength: Mm(3.0), angle_deg: 0.0 });
    let out = dir.path().join("frames.csv");
    std::fs::write(&out, "previous").unwrap();
    let trace = dir.path().join("bad.csv");
    std::fs::write(&trace, "t_ms,x_mm,y_mm\n0,1,2\n1,2\n").unwrap();
    let o =
        taxel(&["play", bundle.to_str().unwrap(), "--trace", trace.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "previous");
}

#[test]
fn finger_bundles_without_a_height_field_and_garbage_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let bundle = dir.path().join("finger.taxel");
    std::fs::write(&bundle, Bundle::new(Manifest::new(profiles::builtin("finger3").unwrap())).to_bytes().unwrap())
        .unwrap();
    let trace = dir.path().join("t.csv");
    std::fs::write(&trace, "t_ms,x_mm,y_mm,contact\n0,1,2,1\n").unwrap();
    let o = taxel(&["play", bundle.to_str().unwrap(), "--trace", trace.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("no height field"), "{}", stderr(&o));
    let junk = dir.path().join("junk.taxel");
    std::fs::write(&junk, b"not a bundle at all").unwrap();
    let o = taxel(&["play", junk.to_str().unwrap(), "--trace", trace.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("junk.taxel"), "{}", stderr(&o));
}

#[test]
fn compiled_examples_play_along_their_traces() {
    // Each stress2 example scene, compiled with the compiler library and
    // played on its own exploration trace: one frame per millisecond of the
    // trace, and the reader feels something along the way.
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let dir = tempfile::tempdir().unwrap();
    let mut played = 0;
    for name in ["exp1-vibrate-2cm", "exp1-dots-2cm", "exp1-grating-2cm"] {
        let svg = examples.join("stress2").join(format!("{name}.svg"));
        let trace = examples.join("traces").join(format!("{name}.csv"));
        let (Ok(text), true) = (std::fs::read_to_string(&svg), trace.exists()) else { continue };
        let opts = taxel_compiler::CompileOptions::new(profiles::builtin("stress2").unwrap());
        let Some(bundle) = taxel_compiler::compile_svg(&text, &opts).bundle else { panic!("{name} does not compile") };
        let path = dir.path().join(format!("{name}.taxel"));
        std::fs::write(&path, bundle.to_bytes().unwrap()).unwrap();
        let out = dir.path().join(format!("{name}.csv"));
        let o = taxel(&[
            "play",
            path.to_str().unwrap(),
            "--trace",
            trace.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let frames = read_frames(&std::fs::read_to_string(&out).unwrap());
        let last_ms: f64 = std::fs::read_to_string(&trace)
            .unwrap()
            .lines()
            .last()
            .and_then(|l| l.split(',').next().map(|t| t.parse().unwrap()))
            .unwrap();
        assert_eq!(frames.last().unwrap().0, last_ms.floor() as u64, "{name}");
        let active = frames.iter().filter(|f| f.1.iter().any(|&c| c > 0)).count();
        assert!(active > frames.len() / 20, "{name}: only {active} of {} frames move", frames.len());
        played += 1;
    }
    assert!(played > 0, "no example scene found under {}", examples.display());
}
