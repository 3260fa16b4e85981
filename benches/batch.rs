//! Batch throughput of `taxel build`: diagrams per second over a folder of
//! generated annotated SVGs plus the example scenes, with `--jobs 1` and
//! `--jobs 2` (the scaling between them), every run with `--force` so that
//! each diagram is compiled and written.
//!
//! `cargo bench --features bench --bench batch -- --warm-up-time 1 --measurement-time 3`

use std::path::Path;
use std::process::Command;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};

/// How many generated diagrams are in the folder (plus the examples).
const GENERATED: usize = 48;

/// A small annotated diagram, different for each `i`: an outline, a grating
/// and dots, the mix a transcriber's folder holds.
fn diagram(i: usize) -> String {
    let x = 5 + (i * 7) % 20;
    let r = 4 + i % 9;
    let w = 3 + i % 5;
    format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="110mm" height="60mm" viewBox="0 0 110 60">
  <rect id="box" x="{x}" y="8" width="40" height="22" fill="none" stroke="black" data-tactile="vibrate()"/>
  <circle id="disc" cx="85" cy="28" r="{r}" fill="gray" data-tactile="grating(wavelength: {w}mm, angle: 45deg)"/>
  <path id="route" d="M 10 52 L 60 54 L 100 50" fill="none" stroke="black" data-tactile="dots(radius: 1mm)"/>
</svg>
"#
    )
}

fn copy_examples(from: &Path, to: &Path) -> usize {
    let mut n = 0;
    for sub in ["stress2", "map"] {
        let Ok(entries) = std::fs::read_dir(from.join(sub)) else { continue };
        for e in entries.flatten() {
            if e.path().extension().is_some_and(|x| x == "svg") {
                let target = to.join(format!("example-{sub}-{}", e.file_name().to_string_lossy()));
                std::fs::copy(e.path(), target).unwrap();
                n += 1;
            }
        }
    }
    n
}

fn batch(c: &mut Criterion) {
    let tmp = tempfile::tempdir().unwrap();
    let src = tmp.path().join("src");
    std::fs::create_dir(&src).unwrap();
    for i in 0..GENERATED {
        std::fs::write(src.join(format!("diagram-{i:04}.svg")), diagram(i)).unwrap();
    }
    let n = GENERATED + copy_examples(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples"), &src);
    let out = tmp.path().join("out");
    let mut group = c.benchmark_group("batch_build");
    group.sample_size(10);
    group.throughput(Throughput::Elements(n as u64));
    for jobs in [1usize, 2] {
        group.bench_with_input(BenchmarkId::new("jobs", jobs), &jobs, |b, &jobs| {
            b.iter(|| {
                let status = Command::new(env!("CARGO_BIN_EXE_taxel"))
                    .arg("build")
                    .arg(&src)
                    .arg("-o")
                    .arg(&out)
                    .args(["--profile", "stress2", "--force", "--jobs", &jobs.to_string()])
                    .stdout(std::process::Stdio::null())
                    .stderr(std::process::Stdio::null())
                    .status()
                    .unwrap();
                // Failures are allowed (an example may need its style sheet);
                // what is measured is the batch running to its end.
                assert!(status.code().is_some_and(|c| c <= 1));
            })
        });
    }
    group.finish();
}

criterion_group!(benches, batch);
criterion_main!(benches);
