//! The key as a second bundle (`NAME.key.taxel`, SPEC.md section 10.2) on
//! the laterotactile arrays and vibrotactile grids, and more pages
//! (`NAME.key2.taxel` ...) when it is longer than the surface: written
//! beside the graphic's bundle by `taxel build`, one input or a batch, kept
//! up to date and removed when no longer needed.

use std::path::Path;
use std::process::{Command, Output};

use taxel_format::{BundleView, Mm, Tick};

fn taxel(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taxel")).args(args).output().unwrap()
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Two textures and a line, each named by its title: a key is needed.
const KEYED: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm" viewBox="0 0 100 60">
<rect x="5" y="5" width="40" height="30" data-tactile="grating(wavelength: 3mm, angle: 0deg)"><title>Forest</title></rect>
<rect x="55" y="5" width="40" height="30" data-tactile="grating(wavelength: 6mm, angle: 90deg)"><title>Lake</title></rect>
<path d="M5 50 L95 50" stroke="black" fill="none" data-tactile="vibrate(width: 2mm)"><title>Road</title></path>
</svg>"#;

/// One texture: no key.
const PLAIN: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm" viewBox="0 0 100 60">
<rect x="5" y="5" width="40" height="30" data-tactile="grating(wavelength: 3mm, angle: 0deg)"><title>Forest</title></rect>
</svg>"#;

#[test]
fn build_writes_the_key_beside_the_bundle_as_a_bundle_that_plays() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("map.svg");
    std::fs::write(&input, KEYED).unwrap();
    let o = taxel(&["build", s(&input), "--profile", "stress2"]);
    assert!(o.status.success(), "{}", text(&o));
    let key = dir.path().join("map.key.taxel");
    assert!(text(&o).contains(&format!("written to {}", key.display())), "{}", text(&o));
    assert!(text(&o).contains("note[T0331]"), "{}", text(&o));
    let bytes = crate::read_plain(&key);
    let view = BundleView::parse(&bytes).unwrap();
    let main = crate::read_plain(dir.path().join("map.taxel"));
    assert_eq!(
        view.manifest().content_hash,
        BundleView::parse(&main).unwrap().manifest().content_hash,
        "both record the build's content hash"
    );
    // The runtime plays it: the first swatch, a grating, is felt at the key's left.
    let player = taxel_runtime::latero::LateroPlayer::new(&view).unwrap();
    let mut frame = [0u16; 64];
    let felt = (0..20).any(|k| {
        player.frame(Tick(k), Mm(5.0 + k as f32 * 0.5), Mm(4.0), &mut frame);
        frame.iter().any(|&c| c > 0)
    });
    assert!(felt, "the key's first swatch plays");
    // `inspect` reads it as a bundle like any other, and the graphic's
    // bundle still lists the key's entries.
    let o = taxel(&["inspect", s(&key)]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(!text(&o).contains("texture: Forest"), "{}", text(&o));
    let o = taxel(&["inspect", s(&dir.path().join("map.taxel"))]);
    assert!(text(&o).contains("texture: Forest"), "{}", text(&o));
    // The element under the finger on the key's first swatch is named by its meaning.
    let o = taxel(&["inspect", s(&key), "--at", "10,4"]);
    assert!(text(&o).contains("Forest"), "{}", text(&o));
    // `-o OUT.taxel` puts the key at `OUT.key.taxel`.
    let out = dir.path().join("out/named.taxel");
    let o = taxel(&["build", s(&input), "--profile", "stress2", "-o", s(&out)]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(dir.path().join("out/named.key.taxel").is_file());
}

#[test]
fn a_batch_writes_each_key_keeps_it_up_to_date_and_removes_it_when_not_needed() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    std::fs::create_dir_all(&src).unwrap();
    std::fs::write(src.join("a.svg"), KEYED).unwrap();
    std::fs::write(src.join("b.svg"), PLAIN).unwrap();
    let out = dir.path().join("out");
    let build = || taxel(&["build", s(&src), "-o", s(&out), "--profile", "stress2", "--jobs", "2"]);
    let o = build();
    assert!(o.status.success(), "{}", text(&o));
    assert!(out.join("a.key.taxel").is_file() && !out.join("b.key.taxel").exists());
    // Up to date: nothing is built again.
    let o = build();
    assert!(String::from_utf8_lossy(&o.stdout).contains("skipped 2"), "{}", text(&o));
    // A missing key makes its graphic out of date.
    std::fs::remove_file(out.join("a.key.taxel")).unwrap();
    let o = build();
    assert!(text(&o).contains("built 1"), "{}", text(&o));
    assert!(out.join("a.key.taxel").is_file());
    // A drawing that no longer needs a key loses its old one.
    std::fs::write(src.join("a.svg"), PLAIN).unwrap();
    let o = build();
    assert!(o.status.success(), "{}", text(&o));
    assert!(!out.join("a.key.taxel").exists());
}

/// Eight textures with long names: more than the six braille lines of
/// `stress2`'s surface, so the key goes on more pages.
pub fn long_key() -> String {
    let mut svg =
        String::from(r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm" viewBox="0 0 100 60">"#);
    for k in 0..8 {
        svg += &format!(
            r#"<rect x="{}" y="5" width="10" height="30" data-tactile="grating(wavelength: {}mm, angle: 0deg)"><title>region number {k} of the map</title></rect>"#,
            2 + 12 * k,
            2 + k
        );
    }
    svg + "</svg>"
}

#[test]
fn a_key_longer_than_the_surface_is_written_page_after_page_and_kept_whole() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    std::fs::create_dir_all(&src).unwrap();
    std::fs::write(src.join("a.svg"), long_key()).unwrap();
    let out = dir.path().join("out");
    let build = || taxel(&["build", s(&src), "-o", s(&out), "--profile", "stress2"]);
    let o = build();
    assert!(o.status.success(), "{}", text(&o));
    assert!(!text(&o).contains("T0332"), "nothing is left out of the key: {}", text(&o));
    // Pages 1, 2 ... without a gap, each saying which it is, all with the graphic's hash.
    let pages: Vec<_> = (1..=9)
        .map(|k| if k == 1 { out.join("a.key.taxel") } else { out.join(format!("a.key{k}.taxel")) })
        .take_while(|p| p.is_file())
        .collect();
    assert!(pages.len() >= 2, "{}", text(&o));
    let last = pages.last().unwrap();
    assert!(text(&o).contains(&format!("{} more bundles", pages.len())), "{}", text(&o));
    assert!(text(&o).contains(&format!("... {}", last.display())), "the note says where: {}", text(&o));
    let hash = |p: &Path| BundleView::parse(&crate::read_plain(p)).unwrap().manifest().content_hash;
    for (k, page) in pages.iter().enumerate() {
        assert_eq!(hash(page), hash(&out.join("a.taxel")));
        let o = taxel(&["inspect", s(page)]);
        let want = format!("key page   {} of {}", k + 1, pages.len());
        assert!(text(&o).contains(&want), "{want}: {}", text(&o));
    }
    // Up to date only with every page: a missing last page is built again.
    let o = build();
    assert!(String::from_utf8_lossy(&o.stdout).contains("skipped 1"), "{}", text(&o));
    std::fs::remove_file(last).unwrap();
    let o = build();
    assert!(text(&o).contains("built 1") && last.is_file(), "{}", text(&o));
    // A page of another build of the same name is not a page of this one.
    std::fs::copy(&pages[0], last).unwrap();
    let o = build();
    assert!(text(&o).contains("built 1"), "{}", text(&o));
    // A shorter key removes the pages past its last; a file of a page's name
    // that is not a bundle is never removed.
    std::fs::write(src.join("a.svg"), KEYED).unwrap();
    let o = build();
    assert!(o.status.success(), "{}", text(&o));
    assert!(out.join("a.key.taxel").is_file() && !out.join("a.key2.taxel").exists(), "{}", text(&o));
    std::fs::write(out.join("a.key2.taxel"), "a teacher's notes").unwrap();
    std::fs::write(src.join("a.svg"), PLAIN).unwrap();
    let o = build();
    assert!(o.status.success(), "{}", text(&o));
    assert!(!out.join("a.key.taxel").exists(), "{}", text(&o));
    assert_eq!(std::fs::read_to_string(out.join("a.key2.taxel")).unwrap(), "a teacher's notes");
}

#[test]
fn an_input_whose_bundle_would_be_anothers_key_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("a.svg"), KEYED).unwrap();
    std::fs::write(dir.path().join("a.key.svg"), PLAIN).unwrap();
    let o = taxel(&["build", s(dir.path()), "--profile", "stress2"]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("would all write"), "{}", text(&o));
    assert!(!dir.path().join("a.taxel").exists() && !dir.path().join("a.key.taxel").exists());
    // Nor a later page's.
    std::fs::remove_file(dir.path().join("a.key.svg")).unwrap();
    std::fs::write(dir.path().join("a.key3.svg"), PLAIN).unwrap();
    let o = taxel(&["build", s(dir.path()), "--profile", "stress2"]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("a.key3.taxel"), "{}", text(&o));
}

#[test]
fn a_grid_and_a_pin_display() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("wind.svg");
    std::fs::write(
        &input,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm" viewBox="0 0 100 60">
<path d="M5 10 L95 10" stroke="black" data-tactile="brush(duration: 800ms)"><title>Wind</title></path>
<path d="M5 40 L95 40" stroke="black" data-tactile="brush(duration: 1500ms)"><title>Rain</title></path>
</svg>"#,
    )
    .unwrap();
    let o = taxel(&["build", s(&input), "--profile", "brush-4x3"]);
    assert!(o.status.success(), "{}", text(&o));
    let bytes = crate::read_plain(dir.path().join("wind.key.taxel"));
    let view = BundleView::parse(&bytes).unwrap();
    assert!(taxel_runtime::grid::GridPlayer::new(&view).is_ok());
    // A pin display's key is pages of its own image: no second bundle.
    let map = dir.path().join("map.svg");
    std::fs::write(&map, KEYED).unwrap();
    let o = taxel(&["build", s(&map), "--profile", "dotpad"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("T0710") && !dir.path().join("map.key.taxel").exists(), "{}", text(&o));
}
