//! `taxel load`, `taxel device serve|ls|rm`: the simulator as a separate
//! process on 127.0.0.1 port 0 (killed when the test ends) and mounted device
//! folders with and without a marker file.

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};

use taxel_format::{Bundle, BundleView, Manifest, profiles};

fn taxel(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taxel")).args(args).output().unwrap()
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

/// Writes a valid bundle for `profile`, made distinct by `mark`.
fn write_bundle(path: &Path, profile: &str, mark: u8) -> Vec<u8> {
    let mut m = Manifest::new(profiles::builtin(profile).unwrap());
    m.content_hash = [mark; 32];
    let bytes = Bundle::new(m).to_bytes().unwrap();
    std::fs::write(path, &bytes).unwrap();
    bytes
}

/// A simulator process, killed when dropped.
struct Simulator {
    child: Child,
    url: String,
}

impl Simulator {
    fn start(store: &Path, extra: &[&str]) -> Simulator {
        let mut child = Command::new(env!("CARGO_BIN_EXE_taxel"))
            .args(["device", "serve", "--store", store.to_str().unwrap(), "--listen", "127.0.0.1:0"])
            .args(extra)
            .stdout(Stdio::piped())
            .spawn()
            .unwrap();
        let mut line = String::new();
        // The first line names the bound address; EOF (a failed start) ends the read.
        BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).unwrap();
        let url = line.split_whitespace().find(|w| w.starts_with("tcp://")).map(String::from);
        let Some(url) = url else {
            let _ = child.kill();
            panic!("the simulator did not start: {line:?}");
        };
        Simulator { child, url }
    }
}

impl Drop for Simulator {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn stored_bundles_validate(dir: &Path) {
    for e in std::fs::read_dir(dir).unwrap() {
        let e = e.unwrap();
        let name = e.file_name().into_string().unwrap();
        if !name.starts_with('.') {
            assert!(BundleView::parse(&std::fs::read(e.path()).unwrap()).is_ok(), "{name}");
        }
    }
}

#[test]
fn load_ls_and_rm_through_the_simulator() {
    let tmp = tempfile::tempdir().unwrap();
    let store = tmp.path().join("store");
    let sim = Simulator::start(&store, &["--profile", "stress2"]);
    let a = write_bundle(&tmp.path().join("a.taxel"), "stress2", 1);
    write_bundle(&tmp.path().join("b.taxel"), "stress2", 2);
    let other = tmp.path().join("other.taxel");
    write_bundle(&other, "finger3", 3);
    let pa = tmp.path().join("a.taxel");
    let pb = tmp.path().join("b.taxel");
    let o = taxel(&["load", pa.to_str().unwrap(), other.to_str().unwrap(), pb.to_str().unwrap(), "--device", &sim.url]);
    // The wrong-profile bundle is refused, the others still load, the exit code says so.
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("wrong profile"), "{}", text(&o));
    assert_eq!(std::fs::read(store.join("a.taxel")).unwrap(), a);
    assert!(store.join("b.taxel").exists());
    assert!(!store.join("other.taxel").exists());

    let o = taxel(&["device", "ls", "--device", &sim.url]);
    assert!(o.status.success(), "{}", text(&o));
    let listing = String::from_utf8_lossy(&o.stdout);
    assert!(listing.contains("a.taxel") && listing.contains("b.taxel") && listing.contains("2 bundles"), "{listing}");

    let o = taxel(&["device", "rm", "b.taxel", "--device", &sim.url]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(!store.join("b.taxel").exists());
    let o = taxel(&["device", "rm", "b.taxel", "--device", &sim.url]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    stored_bundles_validate(&store);
}

#[test]
fn a_full_simulator_refuses_and_keeps_its_bundles() {
    let tmp = tempfile::tempdir().unwrap();
    let store = tmp.path().join("store");
    let pa = tmp.path().join("a.taxel");
    let pb = tmp.path().join("b.taxel");
    let a = write_bundle(&pa, "stress2", 1);
    write_bundle(&pb, "stress2", 2);
    let capacity = (a.len() + 10).to_string();
    let sim = Simulator::start(&store, &["--capacity", &capacity]);
    assert!(taxel(&["load", pa.to_str().unwrap(), "--device", &sim.url]).status.success());
    let o = taxel(&["load", pb.to_str().unwrap(), "--device", &sim.url]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("no space"), "{}", text(&o));
    assert_eq!(std::fs::read(store.join("a.taxel")).unwrap(), a);
    stored_bundles_validate(&store);
}

#[test]
fn the_simulator_refuses_to_listen_beyond_loopback() {
    let tmp = tempfile::tempdir().unwrap();
    let o = taxel(&["device", "serve", "--store", tmp.path().to_str().unwrap(), "--listen", "0.0.0.0:0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("loopback"), "{}", text(&o));
}

#[test]
fn a_mounted_folder_with_a_marker_checks_the_profile_and_the_space() {
    let tmp = tempfile::tempdir().unwrap();
    let dev = tmp.path().join("sdcard");
    std::fs::create_dir(&dev).unwrap();
    let pa = tmp.path().join("a.taxel");
    let a = write_bundle(&pa, "stress2", 1);
    std::fs::write(dev.join(".taxel-device.toml"), format!("profile = \"stress2\"\ncapacity = {}\n", a.len() + 10))
        .unwrap();
    let dev_s = dev.to_str().unwrap();
    assert!(taxel(&["load", pa.to_str().unwrap(), "--device", dev_s]).status.success());
    assert_eq!(std::fs::read(dev.join("a.taxel")).unwrap(), a);

    let other = tmp.path().join("a2.taxel");
    write_bundle(&other, "finger3", 2);
    let o = taxel(&["load", other.to_str().unwrap(), "--device", dev_s]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("wrong profile"), "{}", text(&o));

    let big = tmp.path().join("b.taxel");
    write_bundle(&big, "stress2", 3);
    let o = taxel(&["load", big.to_str().unwrap(), "--device", dev_s]);
    assert!(text(&o).contains("no space"), "{}", text(&o));

    // A broken file is refused before it reaches the device.
    let broken = tmp.path().join("broken.taxel");
    std::fs::write(&broken, &a[..a.len() - 3]).unwrap();
    let o = taxel(&["load", broken.to_str().unwrap(), "--device", dev_s]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("invalid bundle"), "{}", text(&o));

    let o = taxel(&["device", "ls", "--device", dev_s]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("1 bundles"), "{}", text(&o));
    stored_bundles_validate(&dev);
    assert_eq!(std::fs::read_dir(&dev).unwrap().count(), 2, "only the marker and a.taxel");
}

#[test]
fn a_folder_without_a_marker_accepts_any_profile_and_a_bad_marker_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let dev = tmp.path().join("usb");
    std::fs::create_dir(&dev).unwrap();
    let p = tmp.path().join("f.taxel");
    write_bundle(&p, "finger3", 1);
    assert!(taxel(&["load", p.to_str().unwrap(), "--device", dev.to_str().unwrap()]).status.success());
    std::fs::write(dev.join(".taxel-device.toml"), "profil = \"x\"\n").unwrap();
    let o = taxel(&["load", p.to_str().unwrap(), "--device", dev.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains(".taxel-device.toml"), "{}", text(&o));
    let o = taxel(&["load", p.to_str().unwrap(), "--device", tmp.path().join("absent").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("mounted"), "{}", text(&o));
}

/// A bundle as `taxel build` writes it (distance layers, one per style)
/// goes onto the device whole: stored byte for byte, listed, and what the
/// device holds validates and plays its layers.
#[test]
fn a_built_map_with_distance_layers_loads_and_plays_from_the_device() {
    let tmp = tempfile::tempdir().unwrap();
    let store = tmp.path().join("store");
    let sim = Simulator::start(&store, &["--profile", "stress2"]);
    let map = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/map/tala-map.svg");
    let built = tmp.path().join("tala-map.taxel");
    let o = taxel(&["build", map, "-o", built.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    let bytes = crate::read_plain(&built);
    let layers = BundleView::parse(&bytes)
        .unwrap()
        .chunks()
        .filter(|c| matches!(c, taxel_format::ChunkView::Distance(_)))
        .count();
    assert!(layers >= 2, "the map has distance layers: {layers}");
    let o = taxel(&["load", built.to_str().unwrap(), "--device", &sim.url]);
    assert!(o.status.success(), "{}", text(&o));
    let o = taxel(&["device", "ls", "--device", &sim.url]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("tala-map.taxel"), "{}", text(&o));
    // The device holds the file as `taxel build` wrote it (its stored form), byte for byte.
    let stored = std::fs::read(store.join("tala-map.taxel")).unwrap();
    assert_eq!(stored, std::fs::read(&built).unwrap(), "the device holds the bundle byte for byte");
    assert_eq!(crate::plain(stored), bytes);
    let view = BundleView::parse(&bytes).unwrap();
    let player = taxel_runtime::latero::LateroPlayer::new(&view).unwrap();
    let mut frame = [0u16; 64];
    // A sweep across the map meets its layers.
    let played = (0..40).any(|k| {
        player.frame(
            taxel_format::Tick(k),
            taxel_format::Mm(10.0 + 2.2 * k as f32),
            taxel_format::Mm(30.0),
            &mut frame,
        );
        frame.iter().any(|&c| c > 0)
    });
    assert!(played, "the stored map plays");
}
