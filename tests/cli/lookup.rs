//! The point lookup from the command line: `taxel inspect --at X,Y` and
//! `taxel play --elements` on the tala map, and the footprints chunk through
//! `unpack` and `pack`. Expected points are read off tala-map.svg.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn taxel(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taxel")).args(args).output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

fn tala(dir: &Path) -> PathBuf {
    let svg = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/map/tala-map.svg");
    let out = dir.join("tala.taxel");
    let o = taxel(&["build", svg, "-p", "stress2", "-o", p(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    out
}

fn at(bundle: &Path, point: &str) -> String {
    let o = taxel(&["inspect", p(bundle), "--at", point]);
    assert!(o.status.success(), "{}", stderr(&o));
    String::from_utf8(o.stdout).unwrap()
}

#[test]
fn inspect_at_names_the_province_the_border_and_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let bundle = tala(tmp.path());
    let ash = at(&bundle, "25,15");
    assert!(ash.starts_with("(25, 15) mm: ash province\n"), "{ash}");
    assert!(ash.contains("  id      path1\n") && ash.contains("GDST (grating-field)"), "{ash}");
    let line = ash.lines().find_map(|l| l.strip_prefix("  line    ")).unwrap();
    let svg = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/map/tala-map.svg")).unwrap();
    let line: usize = line.parse().unwrap();
    assert!(svg.lines().nth(line - 1).unwrap().contains("<path"), "line {line} opens the element");
    let border = at(&bundle, "33,16.5");
    assert!(border.starts_with("(33, 16.5) mm: coast and province borders\n"), "{border}");
    assert!(border.contains("VDST (vibration-field)"), "{border}");
    assert_eq!(at(&bundle, "100,58"), "(100, 58) mm: nothing\n");
    let o = taxel(&["inspect", p(&bundle), "--at", "25,15", "--format", "json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["element"]["name"], "ash province");
    assert_eq!(v["element"]["id"], "path1");
}

#[test]
fn inspect_at_refuses_a_bad_point_and_a_bundle_without_footprints() {
    let tmp = tempfile::tempdir().unwrap();
    let bundle = tala(tmp.path());
    let o = taxel(&["inspect", p(&bundle), "--at", "25;15"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("not a point X,Y"), "{}", stderr(&o));
    let old = tmp.path().join("old.taxel");
    std::fs::write(&old, taxel_format::sample::every_kind().to_bytes().unwrap()).unwrap();
    let o = taxel(&["inspect", p(&old), "--at", "1,1"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("no footprints") && stderr(&o).contains("taxel build"), "{}", stderr(&o));
}

#[test]
fn unpack_shows_the_footprints_and_pack_gives_the_same_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    let bundle = tala(tmp.path());
    let dir = tmp.path().join("tala");
    let o = taxel(&["unpack", p(&bundle), "-o", p(&dir)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let manifest = std::fs::read_to_string(dir.join("manifest.toml")).unwrap();
    assert!(
        // The bundle's own minor version (4.1 where a lake is an arc tile).
        manifest.contains(&format!("format = \"{}.", taxel_format::FORMAT_MAJOR))
            && manifest.contains("kind = \"footprints\""),
        "{manifest}"
    );
    let csv = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|f| f.to_string_lossy().ends_with("-footprints.csv"))
        .unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with("shape,source,kind,half_width_q,points_q\n0,0,area-evenodd,0,"), "{text}");
    let again = tmp.path().join("again.taxel");
    let o = taxel(&["pack", p(&dir), "-o", p(&again)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(&again).unwrap(), std::fs::read(&bundle).unwrap());
    // A shape numbered out of order is refused with its file and line.
    std::fs::write(&csv, text.replacen("\n0,0,", "\n3,0,", 1)).unwrap();
    let o = taxel(&["pack", p(&dir), "-o", p(&again)]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("-footprints.csv:2: column `shape`: expected 0"), "{}", stderr(&o));
}

#[test]
fn play_elements_lists_what_the_carrier_touched() {
    let tmp = tempfile::tempdir().unwrap();
    let bundle = tala(tmp.path());
    let trace = tmp.path().join("trace.csv");
    // Along y = 12, 1.1 mm a tick: the sea, the coast from (6, 7) to (3, 29) at x 5.32, ash
    // province (x 9.35 to 27.98), the sea, the border from (30, 2) to (36, 31) at x 32.07,
    // the sea, elm province (from x 36.16).
    std::fs::write(&trace, "t_ms,x_mm,y_mm\n0,1,12\n40,45,12\n").unwrap();
    let (frames, names) = (tmp.path().join("frames.csv"), tmp.path().join("elements.csv"));
    let o = taxel(&["play", p(&bundle), "--trace", p(&trace), "-o", p(&frames), "--elements", p(&names)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&names).unwrap();
    let touched: Vec<&str> = text.lines().skip(1).map(|l| l.split(',').nth(3).unwrap()).collect();
    assert_eq!(text.lines().next(), Some("tick,x_mm,y_mm,element,id,line"));
    let border = "coast and province borders";
    assert_eq!(touched, ["", border, "", "ash province", "", border, "", "elm province"]);
}

/// Issue 16 point 3: the text form shows each distance layer as a picture of
/// the amplitude it produces. On tala-map's vibration layer (coast and
/// province borders), the border from (30, 2) to (36, 31) mm is felt at full
/// amplitude halfway along it, and the inside of ash province, 8 mm from any
/// border, not at all. Points are read off tala-map.svg, pixels placed from
/// the layer's origin in the manifest at 10 px/mm.
#[test]
fn unpack_draws_each_distance_layer_as_the_amplitude_it_plays() {
    let tmp = tempfile::tempdir().unwrap();
    let bundle = tala(tmp.path());
    let dir = tmp.path().join("tala");
    let o = taxel(&["unpack", p(&bundle), "-o", p(&dir)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let manifest: toml::Value = toml::from_str(&std::fs::read_to_string(dir.join("manifest.toml")).unwrap()).unwrap();
    let chunks = manifest["chunk"].as_array().unwrap();
    let vibration: Vec<&toml::Value> =
        chunks.iter().filter(|c| c["kind"].as_str() == Some("vibration-field")).collect();
    assert_eq!(vibration.len(), 1, "one vibrating style: {chunks:?}");
    let v = vibration[0];
    let img = crate::read_png(dir.join(v["file"].as_str().unwrap()));
    let origin = (v["origin_x_mm"].as_float().unwrap(), v["origin_y_mm"].as_float().unwrap());
    let px = |x: f64, y: f64| {
        let (i, j) = (((x - origin.0) * 10.0).floor() as u32, ((y - origin.1) * 10.0).floor() as u32);
        img.pixel(i, j).expect("in the mask")[0]
    };
    assert!(px(33.0, 16.5) >= 250, "on the border: {}", px(33.0, 16.5));
    assert_eq!(px(25.0, 15.0), 0, "inside ash province");
    // The picture is for people: pack ignores it and still gives the same bytes.
    let again = tmp.path().join("again.taxel");
    std::fs::write(dir.join(v["file"].as_str().unwrap()), b"not a png").unwrap();
    let o = taxel(&["pack", p(&dir), "-o", p(&again)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(&again).unwrap(), std::fs::read(&bundle).unwrap());
}
