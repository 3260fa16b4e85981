//! `taxel unpack`, `taxel pack` and `taxel inspect` on bundles the format's
//! sample builder makes: byte-identical round trips through the folder,
//! errors that name the file, and what inspect prints.

use std::path::Path;
use std::process::{Command, Output};

use taxel_format::sample;

fn taxel(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_taxel")).args(args).output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

fn every_kind(dir: &Path) -> (std::path::PathBuf, Vec<u8>) {
    let bytes = sample::every_kind().to_bytes().unwrap();
    let path = dir.join("every.taxel");
    std::fs::write(&path, &bytes).unwrap();
    (path, bytes)
}

#[test]
fn unpack_then_pack_gives_the_same_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    let (bundle, bytes) = every_kind(tmp.path());
    let dir = tmp.path().join("every");
    let o = taxel(&["unpack", p(&bundle), "-o", p(&dir)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("manifest.toml").is_file() && dir.join("01-vibration.png").is_file());
    let out = tmp.path().join("again.taxel");
    let o = taxel(&["pack", p(&dir), "-o", p(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    // `pack` writes the stored form, as `taxel build` does (SPEC.md 15): the same bundle.
    let packed = std::fs::read(&out).unwrap();
    assert!(taxel_format::stored::is_stored(&packed));
    assert_eq!(crate::plain(packed.clone()), bytes);
    // A stored file unpacked and packed again is the same file, byte for byte.
    let stored = tmp.path().join("stored.taxel");
    std::fs::write(&stored, &packed).unwrap();
    let again = tmp.path().join("stored-again");
    assert!(taxel(&["unpack", p(&stored), "-o", p(&again)]).status.success());
    let out2 = tmp.path().join("again2.taxel");
    assert!(taxel(&["pack", p(&again), "-o", p(&out2)]).status.success());
    assert_eq!(std::fs::read(&out2).unwrap(), packed);
    // No temporary files are left behind.
    let names: Vec<_> = std::fs::read_dir(tmp.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), 6, "{names:?}");
}

#[test]
fn masks_are_grayscale_pngs_of_their_depth() {
    let tmp = tempfile::tempdir().unwrap();
    let (bundle, _) = every_kind(tmp.path());
    let dir = tmp.path().join("d");
    assert!(taxel(&["unpack", p(&bundle), "-o", p(&dir)]).status.success());
    use taxel_textform::png::{BitDepth, ColorType};
    let v = crate::read_png(dir.join("01-vibration.png"));
    assert_eq!((v.color, v.depth, v.width, v.height), (ColorType::Grayscale, BitDepth::Eight, 3, 2));
    assert_eq!(v.data, [0, 1, 127, 128, 254, 255]);
    let g = crate::read_png(dir.join("02-grating.png"));
    assert_eq!((g.color, g.depth), (ColorType::Grayscale, BitDepth::Sixteen));
    let g16: Vec<u16> = g.data.chunks_exact(2).map(|b| u16::from_be_bytes([b[0], b[1]])).collect();
    assert_eq!(g16, [0, 1, 255, 256, 65_534, 65_535]);
}

#[test]
fn an_edited_folder_packs_the_edit() {
    let tmp = tempfile::tempdir().unwrap();
    let (bundle, _) = every_kind(tmp.path());
    let dir = tmp.path().join("d");
    assert!(taxel(&["unpack", p(&bundle), "-o", p(&dir)]).status.success());
    // Halve the grating's amplitude and move a dot, as a person would.
    let m = std::fs::read_to_string(dir.join("manifest.toml")).unwrap();
    std::fs::write(dir.join("manifest.toml"), m.replace("amplitude = 0.1\n", "amplitude = 0.05\n")).unwrap();
    let d = std::fs::read_to_string(dir.join("05-dots.csv")).unwrap();
    std::fs::write(dir.join("05-dots.csv"), d.replace("60.0,45.0,", "61.5,45.0,")).unwrap();
    let out = tmp.path().join("edited.taxel");
    let o = taxel(&["pack", p(&dir), "-o", p(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let b = taxel_format::Bundle::from_bytes(&std::fs::read(&out).unwrap()).unwrap();
    let mut expected = sample::every_kind();
    let taxel_format::Chunk::Mask(g) = &mut expected.chunks[1] else { panic!() };
    g.amplitude = 0.05;
    let taxel_format::Chunk::Dots(t) = &mut expected.chunks[4] else { panic!() };
    t.dots[0].x = taxel_format::Mm(61.5);
    assert_eq!(b, expected);
}

#[test]
fn mistakes_in_a_hand_edited_folder_name_the_file_and_what_was_expected() {
    let tmp = tempfile::tempdir().unwrap();
    let (bundle, _) = every_kind(tmp.path());
    let dir = tmp.path().join("d");
    assert!(taxel(&["unpack", p(&bundle), "-o", p(&dir)]).status.success());
    let manifest = std::fs::read_to_string(dir.join("manifest.toml")).unwrap();
    let out = tmp.path().join("o.taxel");
    let cases: Vec<(&str, String, String, &str)> = vec![
        (
            "manifest.toml",
            manifest.replace("amplitude = 0.75", "amplitude = \"loud\""),
            "manifest.toml:".into(),
            "key `chunk[1].amplitude`: expected a number",
        ),
        (
            "manifest.toml",
            manifest.replace("freq_mhz = 50000", "freq_hz = 50"),
            "manifest.toml:".into(),
            "key `chunk[1].freq_hz`: unknown key",
        ),
        (
            "manifest.toml",
            manifest.replace("dot_kind = \"symbol\"", "dot_kind = \"stars\""),
            "manifest.toml:".into(),
            "unknown dot kind \"stars\"",
        ),
        (
            "manifest.toml",
            manifest.replace("format = \"4.0\"", "format = \"5.0\""),
            "manifest.toml:".into(),
            "key `format`",
        ),
        (
            "04-dots.csv",
            "x_mm,y_mm,radius_mm,amplitude,source\n1,2,fat,1,\n".into(),
            "04-dots.csv:2:".into(),
            "column `radius_mm`: expected a number, found `fat`",
        ),
        // Values that parse but that the format refuses name the chunk's file.
        (
            "04-dots.csv",
            "x_mm,y_mm,radius_mm,amplitude,source\n1,2,1,7,\n".into(),
            "04-dots.csv:".into(),
            "dot amplitude must be from 0 to 1",
        ),
        ("profile.toml", "name = \"x\"\n".into(), "profile.toml".into(), "key `array`: missing table [array]"),
        // ... or, for a distance layer, the manifest key or the file that
        // holds the value refused.
        (
            "manifest.toml",
            manifest.replace("pitch_mm = 0.5", "pitch_mm = 500.0"),
            "manifest.toml:".into(),
            "key `chunk[3].pitch_mm`: not a valid chunk: chunk 3 (GDST): pitch_mm must be from 0.001 to 100 mm",
        ),
        (
            "03-grating-field-tiles.csv",
            "99999999,0,0,0\n0,0,0,0\n".into(),
            "03-grating-field-tiles.csv:".into(),
            "tile index must be",
        ),
    ];
    for (file, contents, at, expected) in cases {
        let original = std::fs::read(dir.join(file)).unwrap();
        std::fs::write(dir.join(file), contents).unwrap();
        let o = taxel(&["pack", p(&dir), "-o", p(&out)]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{file}: {err}");
        assert!(err.contains(&format!("{}", dir.join(&at).display())), "{file}: {err}");
        assert!(err.contains(expected), "{file}: expected `{expected}` in {err}");
        assert!(!out.exists(), "no bundle is written when the folder has errors");
        std::fs::write(dir.join(file), original).unwrap();
    }
    std::fs::remove_file(dir.join("09-height.csv")).unwrap();
    let o = taxel(&["pack", p(&dir), "-o", p(&out)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("09-height.csv: cannot read"), "{}", stderr(&o));
}

#[test]
fn unpack_refuses_to_overwrite_other_files_but_replaces_a_previous_unpack() {
    let tmp = tempfile::tempdir().unwrap();
    let (bundle, _) = every_kind(tmp.path());
    let dir = tmp.path().join("d");
    std::fs::create_dir(&dir).unwrap();
    std::fs::write(dir.join("thesis.txt"), "mine").unwrap();
    let o = taxel(&["unpack", p(&bundle), "-o", p(&dir)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("refusing to overwrite"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(dir.join("thesis.txt")).unwrap(), "mine");
    // A previous unpack (here of a bundle with more chunks) is replaced whole.
    std::fs::remove_file(dir.join("thesis.txt")).unwrap();
    assert!(taxel(&["unpack", p(&bundle), "-o", p(&dir)]).status.success());
    let tiny = tmp.path().join("tiny.taxel");
    std::fs::write(&tiny, sample::tiny().to_bytes().unwrap()).unwrap();
    let o = taxel(&["unpack", p(&tiny), "-o", p(&dir)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut names: Vec<_> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    names.sort();
    assert_eq!(names, ["01-vibration.png", "manifest.toml", "profile.toml"]);
    // But not once someone has added a file to it.
    std::fs::write(dir.join("notes.md"), "x").unwrap();
    assert_eq!(taxel(&["unpack", p(&tiny), "-o", p(&dir)]).status.code(), Some(2));
}

#[test]
fn inspect_prints_profile_layers_and_sizes() {
    let tmp = tempfile::tempdir().unwrap();
    let (bundle, bytes) = every_kind(tmp.path());
    let o = taxel(&["inspect", p(&bundle)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8(o.stdout).unwrap();
    assert!(
        out.contains(&format!("taxel bundle {}.0, {} bytes, 12 chunks", taxel_format::FORMAT_MAJOR, bytes.len())),
        "{out}"
    );
    assert!(
        out.contains("profile    brush-4x3 (grid), 4 x 3 actuators, pitch 63 x 63 mm, 1000 Hz, 16-bit output"),
        "{out}"
    );
    assert!(out.contains("surface    189 x 126 mm"), "{out}");
    assert!(out.contains("vibration 50 Hz, amplitude 0.75; mask 3 x 2 8-bit at 4 px/mm"), "{out}");
    assert!(out.contains("grating 6 mm at 45°"), "{out}");
    assert!(
        out.contains("grating 3 mm at 30°, amplitude 0.9, soft edge 0.3 mm; 2 element(s); distance field 4 x 2 tiles (2 stored, 0 fine, 2 plane, 2 corner, 0 bend) every 0.5 mm"),
        "{out}"
    );
    assert!(out.contains("6 braille dots"), "{out}");
    assert!(out.contains("2 strokes, 4 points, 5 drives"), "{out}");
    assert!(out.contains("from #0 lake \"Lac Léman\" (line 12)"), "{out}");
    assert!(out.contains("XTRA  optional"), "{out}");
}

#[test]
fn inspect_json_has_every_chunk_with_its_size() {
    let tmp = tempfile::tempdir().unwrap();
    let (bundle, bytes) = every_kind(tmp.path());
    let o = taxel(&["inspect", p(&bundle), "--format", "json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["bytes"], bytes.len());
    assert_eq!(v["profile"]["name"], "brush-4x3");
    assert_eq!(v["surface_mm"], serde_json::json!([189.0, 126.0]));
    let chunks = v["chunks"].as_array().unwrap();
    let view = taxel_format::BundleView::parse(&bytes).unwrap();
    assert_eq!(chunks.len() as u32, view.chunk_count());
    for (i, c) in chunks.iter().enumerate() {
        let (tag, required, _, len) = view.chunk_entry(i as u32).unwrap();
        assert_eq!(
            (c["tag"].as_str().unwrap(), c["required"].as_bool().unwrap()),
            (tag.to_string().as_str(), required)
        );
        assert_eq!(c["bytes"], len);
    }
    assert_eq!(chunks[2]["kind"], "grating");
    assert_eq!(chunks[2]["bits"], 16);
    assert_eq!(chunks[1]["sources"][0]["label"], "Lac Léman");
}

#[test]
fn a_corrupt_bundle_is_bad_input_named_with_its_file() {
    let tmp = tempfile::tempdir().unwrap();
    let (bundle, mut bytes) = every_kind(tmp.path());
    let last = bytes.len() - 20;
    bytes[last] ^= 1;
    std::fs::write(&bundle, &bytes).unwrap();
    for args in [vec!["inspect", p(&bundle)], vec!["unpack", p(&bundle), "-o", p(&tmp.path().join("x"))]] {
        let o = taxel(&args);
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        let err = stderr(&o);
        assert!(err.contains(p(&bundle)) && err.contains("is corrupt: checksum"), "{err}");
    }
    assert!(!tmp.path().join("x").exists());
    let o = taxel(&["inspect", p(&tmp.path().join("missing.taxel"))]);
    assert_eq!(o.status.code(), Some(2));
}

/// A hand-painted mask still has its place beside the distance layers a
/// build writes: a grayscale PNG added to a built map's folder as a
/// vibration chunk packs into a raster mask of exactly its pixels, and the
/// bundle validates and plays it (SPEC.md section 6.1).
#[test]
fn a_hand_painted_png_packs_into_a_raster_mask_beside_the_distance_layers() {
    let tmp = tempfile::tempdir().unwrap();
    let built = tmp.path().join("map.taxel");
    let map = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/map/tala-map.svg");
    let o = taxel(&["build", map, "-o", p(&built)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let dir = tmp.path().join("d");
    assert!(taxel(&["unpack", p(&built), "-o", p(&dir)]).status.success());
    // A 10 x 5 mm patch painted at 4 px/mm: full inside a disc, a soft rim.
    let (w, h) = (40u32, 20u32);
    let painted: Vec<u8> = (0..w * h)
        .map(|k| {
            let (x, y) = (k % w, k / w);
            let r = ((x as f32 - 19.5).powi(2) + (y as f32 - 9.5).powi(2)).sqrt();
            (255.0 * (9.0 - r).clamp(0.0, 1.0)) as u8
        })
        .collect();
    use taxel_textform::png::{BitDepth, ColorType, Compression, write};
    let png = write(w, h, ColorType::Grayscale, BitDepth::Eight, &painted, Compression::Fast).unwrap();
    std::fs::write(dir.join("99-painted.png"), png).unwrap();
    let manifest = std::fs::read_to_string(dir.join("manifest.toml")).unwrap();
    let chunk = "\n[[chunk]]\nkind = \"vibration\"\nfile = \"99-painted.png\"\namplitude = 1.0\n\
                 origin_x_mm = 80.0\norigin_y_mm = 40.0\npx_per_mm = 4.0\nfreq_mhz = 50000\n";
    std::fs::write(dir.join("manifest.toml"), manifest + chunk).unwrap();
    let out = tmp.path().join("painted.taxel");
    let o = taxel(&["pack", p(&dir), "-o", p(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bytes = crate::read_plain(&out);
    let b = taxel_format::Bundle::from_bytes(&bytes).unwrap();
    let distance = b.chunks.iter().filter(|c| matches!(c, taxel_format::Chunk::Distance(_))).count();
    let masks: Vec<_> = b
        .chunks
        .iter()
        .filter_map(|c| match c {
            taxel_format::Chunk::Mask(m) => Some(m),
            _ => None,
        })
        .collect();
    assert!(distance >= 2, "the map's distance layers stay: {distance}");
    assert_eq!(masks.len(), 1);
    assert_eq!((masks[0].width, masks[0].height, masks[0].px_per_mm), (w, h, 4.0));
    assert_eq!(masks[0].samples, taxel_format::MaskSamples::U8(painted));
    // Played: over the disc's middle, at tick 0, actuators whose row and
    // column parities differ are deflected by the patch on top of the map.
    let play = |bytes: &[u8]| {
        let view = taxel_format::BundleView::parse(bytes).unwrap();
        let player = taxel_runtime::latero::LateroPlayer::new(&view).unwrap();
        let mut frame = [0u16; 64];
        player.frame(taxel_format::Tick(0), taxel_format::Mm(85.0), taxel_format::Mm(42.5), &mut frame);
        frame
    };
    let (with, without) = (play(&bytes), play(&crate::read_plain(&built)));
    let raised = with.iter().zip(&without).filter(|(a, b)| a > b).count();
    assert!(raised >= 4 && with.contains(&1023), "the patch plays: {with:?} against {without:?}");
}
