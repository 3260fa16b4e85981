//! The example scenes in `examples/`, through their index `examples.toml`:
//! every file the index names exists, every drawing is indexed and described
//! in the README, every drawing has a physical size that fits its profile's
//! surface, and every exploration trace is a plausible finger path.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use taxel_format::profiles;

/// `examples/examples.toml`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Index {
    scene: Vec<Scene>,
}

/// One `[[scene]]` of the index.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(dead_code)] // `source` and `description` are for people and the demo.
struct Scene {
    name: String,
    input: String,
    profile: String,
    trace: Option<String>,
    style: Option<String>,
    warnings: Vec<String>,
    source: String,
    description: String,
}

fn examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")
}

fn index() -> Index {
    let path = examples_dir().join("examples.toml");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    toml::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every `.svg` under `examples/`, relative to it, except the finger meshes'
/// folder (indexed by their own generator's scenes, if any).
fn drawings(dir: &Path, out: &mut BTreeSet<String>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            drawings(&p, out);
        } else if p.extension().is_some_and(|x| x == "svg") {
            let rel = p.strip_prefix(examples_dir()).unwrap_or(&p);
            out.insert(rel.to_string_lossy().replace('\\', "/"));
        }
    }
}

#[test]
fn the_index_names_every_drawing_and_every_file_it_names_exists() {
    let idx = index();
    assert!(idx.scene.len() >= 40, "the papers' stimuli, the map and the brush strokes are all indexed");
    let mut names = BTreeSet::new();
    for s in &idx.scene {
        assert!(names.insert(s.name.clone()), "scene name {} is used twice", s.name);
        assert!(profiles::builtin(&s.profile).is_some(), "{}: unknown profile {}", s.name, s.profile);
        for f in [Some(&s.input), s.trace.as_ref(), s.style.as_ref()].into_iter().flatten() {
            assert!(examples_dir().join(f).is_file(), "{}: {f} does not exist", s.name);
        }
        let mut sorted = s.warnings.clone();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted, s.warnings, "{}: expected warnings are listed once each, sorted", s.name);
    }
    let indexed: BTreeSet<String> = idx.scene.iter().map(|s| s.input.clone()).collect();
    let mut found = BTreeSet::new();
    drawings(&examples_dir(), &mut found);
    let missing: Vec<_> = found.difference(&indexed).collect();
    assert!(missing.is_empty(), "drawings not in examples.toml: {missing:?}");
}

#[test]
fn the_readme_describes_every_scene() {
    let path = examples_dir().join("README.md");
    let readme = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    for s in index().scene {
        assert!(readme.contains(&s.name), "examples/README.md does not mention {}", s.name);
    }
}

/// The value of attribute `name` on the root `<svg>` element, found by a plain
/// scan: these are our own files, and the compiler tests cover real parsing.
fn root_attr(svg: &str, name: &str) -> Option<String> {
    let start = svg.find("<svg")?;
    let tag = &svg[start..start + svg[start..].find('>')?];
    let key = format!("{name}=\"");
    let at = tag.match_indices(&key).map(|(i, _)| i).find(|&i| {
        // A whole attribute name, not the tail of `inkscape:width` or `stroke-width`.
        tag[..i].ends_with(char::is_whitespace)
    })? + key.len();
    Some(tag[at..at + tag[at..].find('"')?].to_string())
}

fn mm(value: &str) -> Option<f32> {
    value.strip_suffix("mm")?.trim().parse().ok()
}

#[test]
fn every_drawing_has_a_physical_size_that_fits_its_profile() {
    for s in index().scene.iter().filter(|s| s.input.ends_with(".svg")) {
        let text = std::fs::read_to_string(examples_dir().join(&s.input)).unwrap_or_default();
        let w = root_attr(&text, "width").and_then(|v| mm(&v));
        let h = root_attr(&text, "height").and_then(|v| mm(&v));
        let (Some(w), Some(h)) = (w, h) else { panic!("{}: root width/height are not in mm", s.name) };
        let p = profiles::builtin(&s.profile).unwrap_or_else(|| panic!("{}: unknown profile", s.name));
        assert!(
            w <= p.surface_w_mm + 1e-3 && h <= p.surface_h_mm + 1e-3,
            "{}: {w} x {h} mm does not fit the {} x {} mm surface of {}",
            s.name,
            p.surface_w_mm,
            p.surface_h_mm,
            s.profile
        );
    }
}

/// A trace as `(t_ms, x_mm, y_mm)` rows, checking the header.
fn read_trace(path: &Path) -> Vec<(f64, f64, f64)> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t_ms,x_mm,y_mm"), "{}: header", path.display());
    lines
        .enumerate()
        .map(|(i, l)| {
            let v: Vec<f64> = l.split(',').map(|f| f.parse().unwrap_or(f64::NAN)).collect();
            assert!(v.len() == 3 && v.iter().all(|x| x.is_finite()), "{}:{}: bad row {l:?}", path.display(), i + 2);
            (v[0], v[1], v[2])
        })
        .collect()
}

#[test]
fn every_trace_is_a_plausible_exploration_at_20_to_80_mm_per_s() {
    for s in index().scene {
        let p = profiles::builtin(&s.profile).unwrap_or_else(|| panic!("{}: unknown profile", s.name));
        let grid = matches!(p.params, taxel_format::FamilyParams::Grid(_));
        let Some(trace) = &s.trace else {
            assert!(grid, "{}: a scene explored by hand needs a trace", s.name);
            continue;
        };
        assert!(!grid, "{}: brush scenes are time-driven and take no trace", s.name);
        let rows = read_trace(&examples_dir().join(trace));
        assert!(rows.len() > 100, "{}: a trace of {} samples explores nothing", s.name, rows.len());
        assert_eq!(rows[0].0, 0.0, "{}: t_ms starts at 0 (tick 0)", s.name);
        let (mut path, mut in_band) = (0.0, 0);
        for w in rows.windows(2) {
            let ((t0, x0, y0), (t1, x1, y1)) = (w[0], w[1]);
            assert!(t1 > t0, "{}: time goes backwards at t = {t1} ms", s.name);
            let d = (x1 - x0).hypot(y1 - y0);
            let v = d / (t1 - t0) * 1000.0;
            // A chord is never longer than the path it cuts, so no sample can
            // exceed the fastest leg (positions are rounded to 0.01 mm, worth
            // 1.42 mm/s over 10 ms); corners make a few chords slower.
            assert!(v <= 80.0 + 1.5, "{}: {v:.1} mm/s at t = {t1} ms", s.name);
            in_band += usize::from(v >= 20.0);
            path += d;
        }
        for &(t, x, y) in &rows {
            assert!(
                (0.0..=p.surface_w_mm as f64).contains(&x) && (0.0..=p.surface_h_mm as f64).contains(&y),
                "{}: ({x}, {y}) at t = {t} ms is off the surface",
                s.name
            );
        }
        let mean = path / rows[rows.len() - 1].0 * 1000.0;
        assert!((20.0..=80.0).contains(&mean), "{}: mean speed {mean:.1} mm/s", s.name);
        let share = in_band as f64 / (rows.len() - 1) as f64;
        assert!(share >= 0.95, "{}: only {:.0} % of samples move at 20-80 mm/s", s.name, share * 100.0);
    }
}

/// Every annotation written in a drawing: `data-tactile` values and the
/// `tactile:` part of Inkscape layer labels, found by a plain scan.
fn annotations(svg: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (key, prefix) in [("data-tactile=\"", ""), ("inkscape:label=\"", "tactile:")] {
        for (i, _) in svg.match_indices(key) {
            let rest = &svg[i + key.len()..];
            let value = &rest[..rest.find('"').unwrap_or(0)];
            if let Some(a) = value.trim_start().strip_prefix(prefix) {
                out.push(a.trim().to_string());
            }
        }
    }
    out
}

#[test]
fn every_annotation_and_style_sheet_parses() {
    let mut seen = 0;
    for s in index().scene {
        let text = std::fs::read_to_string(examples_dir().join(&s.input)).unwrap_or_default();
        for a in annotations(&text) {
            if let Err(e) = taxel_compiler::annotation::parse(&a) {
                panic!("{}: annotation {a:?}: {e}", s.input);
            }
            seen += 1;
        }
        if let Some(style) = &s.style {
            let text = std::fs::read_to_string(examples_dir().join(style)).unwrap_or_default();
            if let Err(e) = taxel_compiler::StyleSheet::parse(&text, style) {
                panic!("{e}");
            }
        }
    }
    assert!(seen >= 40, "only {seen} annotations found: the scan is broken");
}
