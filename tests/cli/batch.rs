//! `taxel build` over many inputs with the real compiler: good, warning-only
//! and broken drawings in one batch, incremental re-runs, shards, output
//! placement, determinism and an interrupted batch.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Duration;

use taxel_format::BundleView;

fn taxel(args: &[&str]) -> Output {
    // Piped output: plain lines, no progress bar.
    Command::new(env!("CARGO_BIN_EXE_taxel")).args(args).output().unwrap()
}

fn all_text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A drawing that compiles cleanly: 3 cm shapes (above the 2 cm size rule),
/// a vibrating outline and a 3 mm grating (above twice the 1.2 mm pitch),
/// different for each `i`.
fn good_svg(i: usize) -> String {
    let x = 5 + (i * 3) % 40;
    format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="110mm" height="60mm" viewBox="0 0 110 60">
  <rect id="box{i}" x="{x}" y="10" width="30" height="30" fill="none" stroke="black" data-tactile="vibrate()"/>
  <rect id="field{i}" x="70" y="15" width="32" height="32" fill="gray" data-tactile="grating(wavelength: 3mm, angle: 90deg)"/>
</svg>
"#
    )
}

/// Compiles, but with a warning: the shape is smaller than 2 cm.
const WARNING_SVG: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" width="110mm" height="60mm" viewBox="0 0 110 60">
  <rect id="tiny" x="10" y="10" width="6" height="6" fill="none" stroke="black" data-tactile="vibrate()"/>
</svg>
"#;

/// Not XML at all (the element is never closed).
const BROKEN_XML: &str =
    "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"110mm\" height=\"60mm\">\n  <rect x=\"1\"\n";

/// Well-formed, but the annotation cannot be parsed.
const BAD_ANNOTATION: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" width="110mm" height="60mm" viewBox="0 0 110 60">
  <rect id="r" x="10" y="10" width="30" height="30" data-tactile="vibrate(width: banana)"/>
</svg>
"#;

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

/// The `.taxel` files under `dir`, relative and `/`-separated, each checked to validate.
fn bundles(dir: &Path) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    if !dir.exists() {
        return out;
    }
    for e in walk(dir) {
        if e.extension().is_some_and(|x| x == "taxel") {
            let bytes = crate::read_plain(&e);
            assert!(BundleView::parse(&bytes).is_ok(), "{} does not validate", e.display());
            out.insert(e.strip_prefix(dir).unwrap().to_string_lossy().replace('\\', "/"));
        }
    }
    out
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() { out.extend(walk(&p)) } else { out.push(p) }
    }
    out
}

fn set(items: &[&str]) -> BTreeSet<String> {
    items.iter().map(|s| s.to_string()).collect()
}

#[test]
fn good_warning_and_broken_files_in_one_batch() {
    let tmp = tempfile::tempdir().unwrap();
    let src = tmp.path().join("src");
    write(&src.join("good.svg"), &good_svg(1));
    write(&src.join("sub/deeper/good2.svg"), &good_svg(2));
    write(&src.join("warn.svg"), WARNING_SVG);
    write(&src.join("broken.svg"), BROKEN_XML);
    write(&src.join("sub/bad-annotation.svg"), BAD_ANNOTATION);
    write(&src.join("notes.txt"), "not an input");
    let out = tmp.path().join("out");
    let o = taxel(&["build", s(&src), "-o", s(&out), "--profile", "stress2", "--jobs", "2"]);
    let text = all_text(&o);
    assert_eq!(o.status.code(), Some(1), "{text}");
    // Every good one is built, mirroring the tree; no output for a bad one.
    assert_eq!(bundles(&out), set(&["good.taxel", "sub/deeper/good2.taxel", "warn.taxel"]), "{text}");
    // Each bad one is reported with its file name, and its line where known.
    assert!(text.contains("broken.svg:"), "{text}");
    assert!(text.contains("bad-annotation.svg:2:"), "{text}");
    assert!(text.contains("warn.svg") && text.contains("warning["), "{text}");
    assert!(text.contains("built 3, with warnings 1, failed 2, skipped 0"), "{text}");
}

#[test]
fn the_same_batch_twice_skips_everything_until_something_changes() {
    let tmp = tempfile::tempdir().unwrap();
    let src = tmp.path().join("src");
    for i in 0..5 {
        write(&src.join(format!("d{i}.svg")), &good_svg(i));
    }
    let out = tmp.path().join("out");
    let build = |extra: &[&str]| {
        let mut args = vec!["build", s(&src), "-o", s(&out), "--profile", "stress2"];
        args.extend_from_slice(extra);
        let o = taxel(&args);
        assert_eq!(o.status.code(), Some(0), "{}", all_text(&o));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    assert!(build(&[]).contains("built 5, with warnings 0, failed 0, skipped 0"));
    let first: Vec<Vec<u8>> = (0..5).map(|i| std::fs::read(out.join(format!("d{i}.taxel"))).unwrap()).collect();
    assert!(build(&[]).contains("built 0, with warnings 0, failed 0, skipped 5"));
    // Forced: rebuilt, and byte-identical (deterministic).
    assert!(build(&["--force"]).contains("built 5,"));
    for (i, bytes) in first.iter().enumerate() {
        assert_eq!(&std::fs::read(out.join(format!("d{i}.taxel"))).unwrap(), bytes, "d{i} differs");
    }
    // One input changed: only it is rebuilt.
    write(&src.join("d3.svg"), &good_svg(33));
    assert!(build(&[]).contains("built 1, with warnings 0, failed 0, skipped 4"));
    // Another option: everything is rebuilt.
    assert!(build(&["--resolution", "8"]).contains("built 5,"));
}

#[test]
fn shards_cover_every_input_exactly_once_whatever_the_argument_order() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    let mut all = BTreeSet::new();
    for i in 0..9 {
        let (dir, name) = if i % 2 == 0 { (&a, format!("x{i}.svg")) } else { (&b, format!("sub/y{i}.svg")) };
        write(&dir.join(&name), &good_svg(i));
        all.insert(name.replace(".svg", ".taxel"));
    }
    let shard_out = |n: usize, i: usize, order: [&Path; 2]| {
        let out = tmp.path().join(format!("out-{n}-{i}-{}", order[0].file_name().unwrap().to_string_lossy()));
        let shard = format!("{i}/{n}");
        let o = taxel(&["build", s(order[0]), s(order[1]), "-o", s(&out), "--profile", "stress2", "--shard", &shard]);
        assert_eq!(o.status.code(), Some(0), "{}", all_text(&o));
        bundles(&out)
    };
    for n in [1, 2, 3, 4] {
        let mut union = BTreeSet::new();
        let mut total = 0;
        for i in 1..=n {
            let got = shard_out(n, i, [&a, &b]);
            assert_eq!(got, shard_out(n, i, [&b, &a]), "shard {i}/{n} depends on the argument order");
            total += got.len();
            union.extend(got);
        }
        assert_eq!(union, all, "{n} shards");
        assert_eq!(total, all.len(), "an input is in two of {n} shards");
    }
    let o = taxel(&["build", s(&a), "--shard", "0/3"]);
    assert_eq!(o.status.code(), Some(2), "{}", all_text(&o));
}

#[test]
fn where_the_bundles_go() {
    let tmp = tempfile::tempdir().unwrap();
    let one = tmp.path().join("one.svg");
    let two = tmp.path().join("two.svg");
    write(&one, &good_svg(1));
    write(&two, &good_svg(2));
    // Without -o: beside the input.
    assert!(taxel(&["build", s(&one), "--profile", "stress2"]).status.success());
    assert!(tmp.path().join("one.taxel").is_file());
    // One input and -o FILE.taxel: that file.
    let named = tmp.path().join("named/here.taxel");
    assert!(taxel(&["build", s(&one), "-o", s(&named), "--profile", "stress2"]).status.success());
    assert!(BundleView::parse(&crate::read_plain(&named)).is_ok());
    // Several inputs and -o FILE.taxel: a usage error, nothing written.
    let o = taxel(&["build", s(&one), s(&two), "-o", s(&tmp.path().join("x.taxel"))]);
    assert_eq!(o.status.code(), Some(2), "{}", all_text(&o));
    assert!(!tmp.path().join("x.taxel").exists());
    // A missing input: a usage error naming it.
    let o = taxel(&["build", s(&tmp.path().join("absent.svg"))]);
    assert_eq!(o.status.code(), Some(2));
    assert!(all_text(&o).contains("absent.svg"));
}

#[test]
fn an_interrupted_batch_leaves_only_whole_bundles() {
    let tmp = tempfile::tempdir().unwrap();
    let src = tmp.path().join("src");
    for i in 0..40 {
        write(&src.join(format!("d{i:02}.svg")), &good_svg(i));
    }
    let out = tmp.path().join("out");
    for delay_ms in [50, 200, 600] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_taxel"))
            .args(["build", s(&src), "-o", s(&out), "--profile", "stress2", "--force", "--jobs", "2"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(delay_ms));
        let _ = child.kill();
        let _ = child.wait();
        // Whatever was written validates (`bundles` checks each one).
        bundles(&out);
    }
    // A run to the end afterwards builds or skips every input.
    let o = taxel(&["build", s(&src), "-o", s(&out), "--profile", "stress2"]);
    assert!(o.status.success(), "{}", all_text(&o));
    assert_eq!(bundles(&out).len(), 40);
}

#[test]
fn drawings_and_meshes_in_one_folder_each_with_its_default_profile() {
    let tmp = tempfile::tempdir().unwrap();
    let src = tmp.path().join("src");
    let finger = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/finger");
    std::fs::create_dir_all(src.join("meshes")).unwrap();
    std::fs::copy(finger.join("convex.glb"), src.join("meshes/convex.glb")).unwrap();
    std::fs::copy(finger.join("concave.gltf"), src.join("meshes/concave.gltf")).unwrap();
    write(&src.join("drawing.svg"), &good_svg(4));
    let out = tmp.path().join("out");
    let o = taxel(&["build", s(&src), "-o", s(&out)]);
    assert!(o.status.success(), "{}", all_text(&o));
    assert_eq!(bundles(&out), set(&["drawing.taxel", "meshes/concave.taxel", "meshes/convex.taxel"]));
    let profile = |name: &str| {
        let bytes = crate::read_plain(out.join(name));
        BundleView::parse(&bytes).unwrap().manifest().profile.name.as_str().to_string()
    };
    assert_eq!((profile("drawing.taxel"), profile("meshes/convex.taxel")), ("stress2".into(), "finger3".into()));
    let again = taxel(&["build", s(&src), "-o", s(&out)]);
    assert!(String::from_utf8_lossy(&again.stdout).contains("skipped 3"), "{}", all_text(&again));
}

/// Hostile nesting in a batch: 1,000 nested `<tspan>`s (usvg's text parser
/// recurses once per level, and 700 overflowed a worker's default stack,
/// aborting the whole batch) build; 2,000 are refused with T0200 naming the
/// line; the other inputs are built either way.
#[test]
fn deeply_nested_text_neither_aborts_the_batch_nor_is_lost_silently() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    let nested = |n: usize| {
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"110mm\" height=\"60mm\" viewBox=\"0 0 110 60\">\n<text x=\"10\" y=\"30\" data-tactile=\"braille()\">{}deep{}</text></svg>",
            "<tspan>".repeat(n),
            "</tspan>".repeat(n)
        )
    };
    write(&src.join("a.svg"), &nested(1000));
    write(&src.join("b.svg"), &nested(2000));
    write(&src.join("c.svg"), &good_svg(1));
    let out = dir.path().join("out");
    let o = taxel(&["build", s(&src), "-o", s(&out), "--profile", "stress2", "--jobs", "2"]);
    let text = all_text(&o);
    assert_eq!(o.status.code(), Some(1), "{text}");
    assert_eq!(bundles(&out), set(&["a.taxel", "c.taxel"]), "{text}");
    assert!(text.contains("b.svg:2: error[T0200]") && text.contains("more than 1,024 deep"), "{text}");
}
