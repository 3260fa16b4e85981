//! The example scenes in `examples/`, through their index `examples.toml`
//! (so nothing here names a scene except the map and brush checks):
//! every file the index names exists and every drawing is indexed and
//! described in the README; every drawing has a physical size that fits its
//! profile; every annotation and style sheet parses; every scene builds with
//! no errors and exactly the warnings the index expects; every exploration
//! trace is a plausible finger path that passes over every layer of its
//! bundle and plays on the runtime, clamping only where the compiler warned of
//! overlap; the plain map through its style sheet feels like the Inkscape map;
//! and the Tactile Brush strokes have the virtual points the paper describes.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use taxel_compiler::compile_svg;
use taxel_compiler::{CompileOptions, Compiled, Severity, StyleSheet};
use taxel_format::{Chunk, DeviceProfile, DotKind, MaskKind, MaskLayer, MaskSamples, profiles};

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
pub(crate) struct Scene {
    pub(crate) name: String,
    pub(crate) input: String,
    pub(crate) profile: String,
    pub(crate) trace: Option<String>,
    pub(crate) style: Option<String>,
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

/// Every drawing (`.svg`) and mesh (`.gltf`, `.glb`) under `examples/`, relative to it.
fn drawings(dir: &Path, out: &mut BTreeSet<String>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            drawings(&p, out);
        } else if p.extension().is_some_and(|x| x == "svg" || x == "gltf" || x == "glb") {
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
    // A `.glb` is the binary twin of the indexed `.gltf` beside it.
    let twin = |f: &String| f.strip_suffix(".glb").is_some_and(|stem| indexed.contains(&format!("{stem}.gltf")));
    let missing: Vec<_> = found.difference(&indexed).filter(|f| !twin(f)).collect();
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

/// A trace as `(t_ms, x_mm, y_mm)` rows of the samples in contact, checking
/// the header (`t_ms,x_mm,y_mm`, or with `contact` for the finger device).
fn read_trace(path: &Path) -> Vec<(f64, f64, f64)> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header = lines.next();
    let cols = match header {
        Some("t_ms,x_mm,y_mm") => 3,
        Some("t_ms,x_mm,y_mm,contact") => 4,
        _ => panic!("{}: header {header:?}", path.display()),
    };
    lines
        .enumerate()
        .filter_map(|(i, l)| {
            let v: Vec<f64> = l.split(',').map(|f| f.parse().unwrap_or(f64::NAN)).collect();
            assert!(v.len() == cols && v.iter().all(|x| x.is_finite()), "{}:{}: bad row {l:?}", path.display(), i + 2);
            (cols == 3 || v[3] != 0.0).then_some((v[0], v[1], v[2]))
        })
        .collect()
}

/// Whether a trace comes from a touch screen (it has a `contact` column):
/// coarse, jittery samples whose sweep, not each step, has the reader's speed.
fn is_touch(path: &Path) -> bool {
    std::fs::read_to_string(path).unwrap_or_default().lines().next().is_some_and(|h| h.ends_with(",contact"))
}

#[test]
fn every_trace_is_a_plausible_exploration_at_20_to_80_mm_per_s() {
    for s in index().scene {
        let p = profiles::builtin(&s.profile).unwrap_or_else(|| panic!("{}: unknown profile", s.name));
        let grid = matches!(p.params, taxel_format::FamilyParams::Grid(_));
        let pins = matches!(p.params, taxel_format::FamilyParams::Pins(_));
        let print = matches!(p.params, taxel_format::FamilyParams::Print(_));
        let Some(trace) = &s.trace else {
            // Brush scenes are time-driven; pin displays show still pages; print is paper.
            assert!(grid || pins || print, "{}: a scene explored by hand needs a trace", s.name);
            continue;
        };
        assert!(!grid, "{}: brush scenes are time-driven and take no trace", s.name);
        let rows = read_trace(&examples_dir().join(trace));
        assert!(rows.len() > 100, "{}: a trace of {} samples explores nothing", s.name, rows.len());
        assert_eq!(rows[0].0, 0.0, "{}: t_ms starts at 0 (tick 0)", s.name);
        if is_touch(&examples_dir().join(trace)) {
            // A touch screen's positions jitter by a fraction of a millimetre
            // from sample to sample, so the reader's speed is the sweep's.
            let (a, b) = (rows[0], rows[rows.len() - 1]);
            let sweep = (b.1 - a.1).hypot(b.2 - a.2) / (b.0 - a.0) * 1000.0;
            assert!((20.0..=80.0).contains(&sweep), "{}: sweeps at {sweep:.1} mm/s", s.name);
            assert!(rows.windows(2).all(|w| w[1].0 > w[0].0), "{}: time goes backwards", s.name);
            continue;
        }
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

/// Compiles a scene the way `taxel build` does: its profile, its style sheet.
fn build(s: &Scene) -> Compiled {
    let profile = profiles::builtin(&s.profile).unwrap_or_else(|| panic!("{}: unknown profile", s.name));
    let mut opts = CompileOptions::new(profile);
    if let Some(style) = &s.style {
        let text = std::fs::read_to_string(examples_dir().join(style)).unwrap_or_default();
        opts.style = Some(StyleSheet::parse(&text, style).unwrap_or_else(|e| panic!("{e}")));
    }
    let path = examples_dir().join(&s.input);
    if s.input.ends_with(".gltf") || s.input.ends_with(".glb") {
        let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let mut beside = |uri: &str| std::fs::read(dir.join(uri)).map_err(|e| format!("{uri}: {e}"));
        let mesh = taxel_compiler::mesh::MeshOptions::default();
        return taxel_compiler::mesh::compile_gltf(&bytes, &mut beside, &opts.profile, &mesh);
    }
    let text = std::fs::read_to_string(&path).unwrap_or_default();
    compile_svg(&text, &opts)
}

/// Every indexed scene (drawings and meshes alike).
pub(crate) fn scenes() -> Vec<Scene> {
    index().scene
}

#[test]
fn every_example_builds_with_exactly_the_warnings_it_is_meant_to_show() {
    let mut failures = Vec::new();
    let mut sizes = Vec::new();
    for s in scenes() {
        let out = build(&s);
        if let Some(b) = &out.bundle {
            sizes.push((s.name.clone(), b.to_bytes().map_or(usize::MAX, |bytes| bytes.len())));
            // The layer plan keeps its invariants on every example drawing.
            if b.manifest.profile.family() == taxel_format::Family::Laterotactile
                && let Err(e) = taxel_compiler::sanity::latero_plan(b)
            {
                failures.push(format!("{}: the layer plan breaks an invariant: {e}", s.name));
            }
        }
        let errors = out.diagnostics.iter().any(|d| d.severity == Severity::Error);
        let warnings: Vec<String> = out
            .diagnostics
            .iter()
            .filter(|d| d.severity == Severity::Warning)
            .map(|d| d.code.to_string())
            .collect::<BTreeSet<_>>()
            .into_iter()
            .collect();
        // A print scene makes a sheet (its file), not a bundle.
        let made = out.bundle.is_some() || out.print.is_some();
        if errors || !made || warnings != s.warnings {
            let all: Vec<String> = out.diagnostics.iter().map(|d| d.render(&s.input)).collect();
            failures.push(format!(
                "{}: expected warnings {:?}, got {warnings:?}{}\n{}",
                s.name,
                s.warnings,
                if made { "" } else { " and no bundle" },
                all.join("\n")
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    // Built once here, so their sizes are checked here too.
    no_example_bundle_is_larger_than_before_layers_by_style(&sizes);
}

/// Actuator offsets from the carrier: the array centred on it, row 0 on top
/// (primitives.md, "Device family 1").
fn actuator_offsets(p: &DeviceProfile) -> Vec<(f32, f32)> {
    let (rows, cols) = (p.rows as f32, p.cols as f32);
    (0..p.rows)
        .flat_map(|r| {
            (0..p.cols).map(move |c| {
                ((c as f32 - (cols - 1.0) / 2.0) * p.pitch_x_mm, (r as f32 - (rows - 1.0) / 2.0) * p.pitch_y_mm)
            })
        })
        .collect()
}

/// Whether the mask is non-zero at page point `(x, y)` (nearest sample).
fn mask_on(m: &MaskLayer, x: f32, y: f32) -> bool {
    let i = ((x - m.origin_x.0) * m.px_per_mm).floor();
    let j = ((y - m.origin_y.0) * m.px_per_mm).floor();
    if i < 0.0 || j < 0.0 || i >= m.width as f32 || j >= m.height as f32 {
        return false;
    }
    let k = j as usize * m.width as usize + i as usize;
    match &m.samples {
        MaskSamples::U8(v) => v.get(k).is_some_and(|&s| s > 0),
        MaskSamples::U16(v) => v.get(k).is_some_and(|&s| s > 0),
    }
}

#[test]
fn every_trace_passes_over_every_layer_of_its_bundle() {
    for s in scenes() {
        let Some(trace) = &s.trace else { continue };
        let Some(bundle) = build(&s).bundle else { panic!("{}: does not build", s.name) };
        let offsets = actuator_offsets(&bundle.manifest.profile);
        let carrier: Vec<(f32, f32)> =
            read_trace(&examples_dir().join(trace)).iter().map(|&(_, x, y)| (x as f32, y as f32)).collect();
        let touched = |on: &dyn Fn(f32, f32) -> bool| {
            carrier.iter().any(|&(cx, cy)| offsets.iter().any(|&(dx, dy)| on(cx + dx, cy + dy)))
        };
        let mut layers = 0;
        for chunk in &bundle.chunks {
            let ok = match chunk {
                Chunk::Mask(m) => touched(&|x, y| mask_on(m, x, y)),
                Chunk::Distance(d) => touched(&|x, y| d.coverage_at(x, y) > 0.0),
                Chunk::Dots(t) => t.dots.iter().all(|d| touched(&|x, y| (x - d.x.0).hypot(y - d.y.0) <= d.radius.0)),
                // The finger device feels the mesh under the fingertip itself.
                Chunk::Height(h) => carrier.iter().any(|&(x, y)| {
                    let (w, ht) =
                        (h.cols.saturating_sub(1) as f32 * h.cell.0, h.rows.saturating_sub(1) as f32 * h.cell.0);
                    (h.origin_x.0..=h.origin_x.0 + w).contains(&x) && (h.origin_y.0..=h.origin_y.0 + ht).contains(&y)
                }),
                _ => continue,
            };
            layers += 1;
            assert!(ok, "{}: the trace never puts an actuator on layer {:?}", s.name, chunk.tag());
        }
        assert!(layers > 0, "{}: no layers", s.name);
    }
}

/// What a bundle's layers are, without their rasters: kind and parameters of
/// each mask, kind and dot count of each dot table, sorted.
fn layer_summary(b: &taxel_format::Bundle) -> Vec<String> {
    let mut v: Vec<String> = b
        .chunks
        .iter()
        .filter_map(|c| match c {
            Chunk::Mask(m) => Some(match m.kind {
                MaskKind::Vibration { freq } => format!("vibration {} mHz", freq.0),
                MaskKind::Grating { wavelength, angle_deg } => format!("grating {} mm at {angle_deg}°", wavelength.0),
            }),
            Chunk::Distance(d) => Some(match d.kind {
                MaskKind::Vibration { freq } => format!("vibration {} mHz", freq.0),
                MaskKind::Grating { wavelength, angle_deg } => format!("grating {} mm at {angle_deg}°", wavelength.0),
            }),
            Chunk::Dots(t) => Some(format!("{} dots x{}", t.kind.name(), t.dots.len())),
            _ => None,
        })
        .collect();
    v.sort();
    v
}

fn bundle_of(name: &str) -> taxel_format::Bundle {
    let s = scenes().into_iter().find(|s| s.name == name).unwrap_or_else(|| panic!("no scene {name}"));
    build(&s).bundle.unwrap_or_else(|| panic!("{name} does not build"))
}

fn dots_of(b: &taxel_format::Bundle, kind: DotKind) -> Vec<(f32, f32, f32)> {
    let mut v: Vec<(f32, f32, f32)> = b
        .chunks
        .iter()
        .filter_map(|c| match c {
            Chunk::Dots(t) if t.kind == kind => Some(t.dots.iter().map(|d| (d.x.0, d.y.0, d.radius.0))),
            _ => None,
        })
        .flatten()
        .collect();
    v.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
    v
}

#[test]
fn the_plain_map_through_its_style_sheet_feels_like_the_inkscape_map() {
    let (map, plain) = (bundle_of("tala-map"), bundle_of("tala-plain"));
    let expected = [
        // Uncontracted braille of the key's labels: edge (e d g e: 2+3+4+2 dots), ash (1+3+3),
        // elm (2+3+3), oak (3+1+2), town (4+3+4+4).
        "braille dots x47",
        // One layer per style: each province with its key swatch.
        "grating 3 mm at 0°",
        "grating 6 mm at 90°",
        "grating 9 mm at 45°",
        // Three towns and the key's town.
        "symbol dots x4",
    ];
    // The vibrating lines: one style, so one layer whether the teacher
    // combined the coast and the province borders into one path (tala-map)
    // or kept them apart (tala-plain): borders that touch are one border
    // and their junctions do not add up. 50 Hz is the default (seed 000, 3.2).
    let mut with: Vec<&str> = expected.iter().copied().chain(["vibration 50000 mHz"]).collect();
    with.sort();
    assert_eq!(layer_summary(&map), with);
    assert_eq!(layer_summary(&plain), with);
    let towns: Vec<(f32, f32, f32)> = vec![(17.0, 18.0, 1.5), (30.0, 45.0, 1.5), (52.0, 22.0, 1.5), (77.5, 54.0, 1.5)];
    assert_close(&dots_of(&map, DotKind::Symbol), &towns, "towns of tala-map");
    // The style sheet's 1.5 mm radius, not the 1.2 mm drawn.
    assert_close(&dots_of(&plain, DotKind::Symbol), &towns, "towns of tala-plain");
    assert_close(&dots_of(&map, DotKind::Braille), &dots_of(&plain, DotKind::Braille), "braille");
}

/// Same dots to a micrometre (an SVG transform's f32 rounding is allowed).
fn assert_close(a: &[(f32, f32, f32)], b: &[(f32, f32, f32)], what: &str) {
    let same = a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(p, q)| (p.0 - q.0).abs() < 1e-3 && (p.1 - q.1).abs() < 1e-3 && (p.2 - q.2).abs() < 1e-3);
    assert!(same, "{what}: {a:?} != {b:?}");
}

/// Where a straight stroke from `a` to `b` crosses the grid lines x = l·c and
/// y = l·r, with its ends, in order along it (seed 001, step 1).
fn grid_crossings(a: (f64, f64), b: (f64, f64), l: f64) -> Vec<(f64, f64)> {
    let mut ts = vec![0.0, 1.0];
    for (p, q) in [(a.0, b.0), (a.1, b.1)] {
        if (q - p).abs() > 1e-12 {
            for k in -10..=10 {
                let t = (l * k as f64 - p) / (q - p);
                if t > 1e-9 && t < 1.0 - 1e-9 {
                    ts.push(t);
                }
            }
        }
    }
    ts.sort_by(|x, y| x.partial_cmp(y).unwrap_or(std::cmp::Ordering::Equal));
    ts.dedup_by(|x, y| (*x - *y).abs() < 1e-9);
    ts.iter().map(|t| (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t)).collect()
}

#[test]
fn the_evaluation_strokes_have_the_virtual_points_the_paper_describes() {
    // (scene, start, end, duration ms, intensity, carrier Hz), as annotated.
    let cases = [
        ("brush-1-diagonal", (0.0, 0.0), (189.0, 126.0), 1000.0, 1.0, 200.0),
        ("brush-2-horizontal", (31.5, 63.0), (157.5, 63.0), 800.0, 0.8, 150.0),
        ("brush-3-virtual", (31.5, 0.0), (157.5, 126.0), 1200.0, 0.9, 270.0),
    ];
    for (name, a, b, ms, intensity, hz) in cases {
        let bundle = bundle_of(name);
        let p = bundle.manifest.profile;
        let strokes: Vec<&taxel_format::Stroke> = bundle
            .chunks
            .iter()
            .filter_map(|c| if let Chunk::Strokes(t) = c { Some(&t.strokes) } else { None })
            .flatten()
            .collect();
        assert_eq!(strokes.len(), 1, "{name}: one stroke");
        let s = strokes[0];
        assert_eq!(s.duration as f64, ms * p.rate_hz as f64 / 1000.0, "{name}: T in ticks");
        assert_eq!(s.carrier.0 as f64, hz * 1000.0, "{name}: carrier");
        assert!((s.intensity as f64 - intensity).abs() < 1e-6, "{name}: intensity");
        let expected = grid_crossings(a, b, p.pitch_x_mm as f64);
        let got: Vec<(f64, f64)> = s.points.iter().map(|q| (q.x.0 as f64, q.y.0 as f64)).collect();
        assert_eq!(got.len(), expected.len(), "{name}: points {got:?}, expected {expected:?}");
        for (g, e) in got.iter().zip(&expected) {
            assert!((g.0 - e.0).abs() < 0.01 && (g.1 - e.1).abs() < 0.01, "{name}: point {g:?}, expected {e:?}");
        }
        // On an actuator a point drives it alone; between actuators it is a phantom.
        let on_actuator = |q: &(f64, f64)| {
            let l = p.pitch_x_mm as f64;
            ((q.0 / l).round() * l - q.0).abs() < 1e-6 && ((q.1 / l).round() * l - q.1).abs() < 1e-6
        };
        let physical: Vec<bool> = expected.iter().map(on_actuator).collect();
        match name {
            "brush-1-diagonal" => assert_eq!(physical, [true, false, false, false, true], "{name}"),
            "brush-2-horizontal" => assert_eq!(physical, [false, true, true, false], "{name}"),
            _ => assert!(physical.iter().all(|x| !x), "{name}: virtual points only"),
        }
        for (q, phys) in s.points.iter().zip(&physical) {
            let driven = q.drives.iter().filter(|d| d.intensity > 1e-6).count();
            assert_eq!(driven == 1, *phys, "{name}: point ({}, {}) drives {driven} actuators", q.x.0, q.y.0);
        }
    }
}

#[test]
fn every_stress2_example_plays_on_its_trace_and_clamps_only_where_it_warns_of_overlap() {
    use taxel_runtime::latero::LateroPlayer;
    use taxel_runtime::trace::Trace;
    for s in scenes().into_iter().filter(|s| s.profile == "stress2") {
        let Some(trace) = &s.trace else { panic!("{}: no trace", s.name) };
        let path = examples_dir().join(trace);
        let file = std::fs::File::open(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let trace = Trace::parse(file).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let Some(bundle) = build(&s).bundle else { panic!("{}: does not build", s.name) };
        let bytes = bundle.to_bytes().unwrap_or_else(|e| panic!("{}: {e}", s.name));
        let view = taxel_format::BundleView::parse(&bytes).unwrap_or_else(|e| panic!("{}: {e}", s.name));
        let player = LateroPlayer::new(&view).unwrap_or_else(|e| panic!("{}: {e}", s.name));
        let max = (1u32 << bundle.manifest.profile.output_bits) - 1;
        let mut out = vec![0u16; player.actuator_count()];
        let (mut active, mut clamped) = (0u64, 0u64);
        // Every 13th tick: a stride prime to the 20-tick period of the 50 Hz
        // vibration samples all its phases.
        for (tick, p) in trace.ticks(bundle.manifest.profile.rate_hz).step_by(13) {
            let stats = player.frame(tick, taxel_format::Mm(p.x_mm as f32), taxel_format::Mm(p.y_mm as f32), &mut out);
            assert!(out.iter().all(|&c| u32::from(c) <= max), "{}: code above {max}", s.name);
            active += u64::from(out.iter().any(|&c| c > 0));
            clamped += u64::from(stats.clamped);
        }
        assert!(active > 0, "{}: the array never moves along the trace", s.name);
        let share = clamped as f64 / (active.max(1) * out.len() as u64) as f64;
        if s.warnings.iter().any(|w| w == "T0410") {
            assert!(clamped > 0, "{}: T0410 is expected, yet no layers add past full deflection", s.name);
        } else {
            // Layers that meet edge to edge (an icon's grating inside its
            // vibrating outline) clamp in a strip half a mask pixel wide, where
            // the runtime holds one mask's edge sample while the other
            // interpolates (reported); a real overlap clamps far more often
            // (tala-plain: about 3 % of actuator samples).
            assert!(share < 0.005, "{}: {:.2} % of actuator samples clamp, with no T0410", s.name, share * 100.0);
        }
    }
}

/// Each example's bundle size in bytes as the build before issue 16 wrote
/// it (`0688be9`, format 1.0, raster masks): the demo (`taxel` with no
/// arguments) run by that build on its own `examples/`. Scenes added since
/// have no entry.
#[rustfmt::skip]
const SIZES_BEFORE_LAYERS_BY_STYLE: [(&str, usize); 45] = [
    ("exp1-vibrate-2cm", 280896), ("exp1-vibrate-3cm-a", 300192), ("exp1-vibrate-3cm-b", 300160),
    ("exp1-dots-2cm", 7280), ("exp1-dots-3cm-a", 5472), ("exp1-dots-3cm-b", 5704), ("exp1-grating-2cm", 240960),
    ("exp1-grating-3cm-a", 270624), ("exp1-grating-3cm-b", 270592), ("exp2-gratings-1.0-1.5mm", 538112),
    ("exp2-gratings-3.0-3.5mm", 538112), ("exp2-gratings-5.5-6.0mm", 538112), ("exp2-gratings-3.0-6.0mm", 538112),
    ("exp2-gratings-1.0-6.0mm", 538112), ("exp3-orientations-4mm", 377056), ("exp3-orientations-6mm", 377056),
    ("exp3-orientations-8mm", 377056), ("exp4-orientations-6mm", 250792), ("exp5-icon-circle-vertical-2mm", 182128),
    ("exp5-icon-circle-vertical-6mm", 182128), ("exp5-icon-circle-horizontal-2mm", 182128),
    ("exp5-icon-circle-horizontal-6mm", 182128), ("exp5-icon-square-vertical-2mm", 182128),
    ("exp5-icon-square-vertical-6mm", 182128), ("exp5-icon-square-horizontal-2mm", 182128),
    ("exp5-icon-square-horizontal-6mm", 182128), ("exp5-icon-triangle-down-vertical-2mm", 176800),
    ("exp5-icon-triangle-down-vertical-6mm", 176800), ("exp5-icon-triangle-down-horizontal-2mm", 176800),
    ("exp5-icon-triangle-down-horizontal-6mm", 176800), ("exp5-icon-right-triangle-vertical-2mm", 175976),
    ("exp5-icon-right-triangle-vertical-6mm", 175976), ("exp5-icon-right-triangle-horizontal-2mm", 175976),
    ("exp5-icon-right-triangle-horizontal-6mm", 175976), ("tala-map", 664056), ("tala-plain", 1093488),
    ("brush-1-diagonal", 576), ("brush-2-horizontal", 528), ("brush-3-virtual", 592), ("brush-4-curve", 664),
    ("finger-edge", 379448), ("finger-flat", 379448), ("finger-inclined", 379456), ("finger-convex", 379456),
    ("finger-concave", 379456),
];

/// Issue 16 point 6: no example bundle is larger than it was before layers
/// by style (the sizes `taxel build` writes: the bundle's bytes), given each
/// scene's bundle size as [`every_example_builds_with_exactly_the_warnings_it_is_meant_to_show`]
/// builds it.
fn no_example_bundle_is_larger_than_before_layers_by_style(sizes: &[(String, usize)]) {
    let mut larger = Vec::new();
    for (name, before) in SIZES_BEFORE_LAYERS_BY_STYLE {
        let now = sizes.iter().find(|(n, _)| n == name).map(|&(_, b)| b);
        let now = now.unwrap_or_else(|| panic!("{name}: no longer in the index, or no bundle"));
        if now > before {
            larger.push(format!("{name}: {before} -> {now} bytes"));
        }
    }
    assert!(larger.is_empty(), "larger than before layers by style:\n{}", larger.join("\n"));
}
