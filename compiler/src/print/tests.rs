//! The print back end on small drawings built in code: textures of touching
//! regions, braille dimensions, the embosser's grid, the relief's mesh.

use std::collections::HashMap;

use taxel_format::{DeviceProfile, FamilyParams, PrintParams, profiles};

use super::*;
use crate::annotation::{Braille, Dot, Grating, Style, Vibrate};
use crate::diagnostic::Diagnostic;
use crate::drawing::{Element, Page, PathShape, TextRun, TextShape};
use crate::geometry::Polyline;

fn profile(name: &str) -> (DeviceProfile, PrintParams) {
    let p = profiles::builtin(name).unwrap();
    let FamilyParams::Print(q) = p.params else { panic!("{name} is a print profile") };
    (p, q)
}

fn rect(x: f64, y: f64, w: f64, h: f64) -> Vec<Polyline> {
    vec![Polyline { points: vec![(x, y), (x + w, y), (x + w, y + h), (x, y + h)], closed: true }]
}

fn path(name: &str, outline: Vec<Polyline>, styles: Vec<Style>) -> Element {
    Element {
        name: name.into(),
        visible: true,
        styles,
        shape: Shape::Path(PathShape { outline, ..Default::default() }),
        ..Default::default()
    }
}

fn grating(wavelength_mm: f64, angle_deg: f64) -> Style {
    Style::Grating(Grating { wavelength_mm, angle_deg, amplitude: 1.0, soft_mm: 0.0 })
}

fn vibrate(width_mm: f64, freq_hz: f64) -> Style {
    Style::Vibrate(Vibrate { width_mm, freq_hz, amplitude: 1.0, soft_mm: 0.0 })
}

fn label(name: &str, text: &str, x: f64, y: f64) -> Element {
    Element {
        name: name.into(),
        visible: true,
        styles: vec![Style::Braille(Braille { radius_mm: 0.72, amplitude: 1.0, grade: None })],
        shape: Shape::Text(TextShape {
            content: text.into(),
            runs: vec![TextRun { text: text.into(), x_mm: x, y_mm: y, anchor: 0.0, continues: false }],
            font_size_mm: 4.0,
            ..Default::default()
        }),
        ..Default::default()
    }
}

fn drawing(elements: Vec<Element>) -> Drawing {
    Drawing {
        page: Page { width_mm: 180.0, height_mm: 180.0, scale: 1.0, offset_mm: (0.0, 0.0), sheet_mm: None },
        elements,
        ..Default::default()
    }
}

fn sheet(d: &Drawing, name: &str) -> (Sheet, Vec<Diagnostic>) {
    let mut diags = Vec::new();
    let s = legalise(d, &profile(name).0, &mut diags).unwrap_or_else(|| panic!("no sheet: {diags:?}"));
    (s, diags)
}

#[test]
fn touching_regions_never_share_a_texture() {
    // A 6 x 6 checkerboard-like map of 20 mm squares with 5 grating styles
    // laid out so that every style touches every other somewhere: the
    // textures must still differ across every shared side.
    let n = 6;
    let mut elements = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let style = (i + 2 * j) % 5;
            let g = grating(2.0 + style as f64, 0.0);
            elements.push(path(
                &format!("r{i}_{j}"),
                rect(10.0 + 20.0 * i as f64, 10.0 + 20.0 * j as f64, 20.0, 20.0),
                vec![g],
            ));
        }
    }
    let d = drawing(elements);
    let (s, _) = sheet(&d, "swell-a4");
    let tex: HashMap<usize, TextureId> = s.textures.iter().copied().collect();
    assert_eq!(tex.len(), n * n);
    // Neighbours by geometry: squares sharing a side (or a corner, which touches too).
    let mut pairs = 0;
    for j in 0..n {
        for i in 0..n {
            for (di, dj) in [(1, 0), (0, 1), (1, 1), (1, -1i64)] {
                let (a, b) = (i as i64 + di, j as i64 + dj);
                if a < 0 || b < 0 || a >= n as i64 || b >= n as i64 {
                    continue;
                }
                let (k, m) = (j * n + i, b as usize * n + a as usize);
                assert_ne!(tex[&k], tex[&m], "squares {k} and {m} touch and share a texture");
                pairs += 1;
            }
        }
    }
    assert!(pairs > 50);
    // Same style, same texture (it means the same thing).
    for k in 0..n * n {
        for m in 0..n * n {
            if (k % n + 2 * (k / n)) % 5 == (m % n + 2 * (m / n)) % 5 {
                assert_eq!(tex[&k], tex[&m]);
            }
        }
    }
}

#[test]
fn a_grating_keeps_its_orientation_when_free() {
    let d = drawing(vec![
        path("h", rect(10.0, 10.0, 40.0, 40.0), vec![grating(2.0, 0.0)]),
        path("v", rect(60.0, 10.0, 40.0, 40.0), vec![grating(2.0, 90.0)]),
    ]);
    let (s, _) = sheet(&d, "swell-a4");
    assert_eq!(s.textures, vec![(0, TextureId(0)), (1, TextureId(1))]);
    // The horizontal one is horizontal lines inside its region, a gap from its sides.
    let lines: Vec<_> = s.pages[0]
        .iter()
        .filter(|m| m.element == Some(0))
        .map(|m| match &m.shape {
            MarkShape::Line { points, .. } => (points[0], points[1]),
            other => panic!("{other:?}"),
        })
        .collect();
    assert!(lines.len() >= 9, "{}", lines.len());
    for (a, b) in lines {
        assert!((a.1 - b.1).abs() < 1e-9, "horizontal");
        // The region is at 10..50 on the drawing, 20..60 on the paper (10 mm margin).
        assert!(a.0 > 20.0 && b.0 < 60.0 && a.1 > 20.0 && a.1 < 60.0);
    }
}

fn dots_of(marks: &[Mark], elem: usize) -> Vec<((f64, f64), f64)> {
    marks
        .iter()
        .filter(|m| m.element == Some(elem))
        .filter_map(|m| match m.shape {
            MarkShape::Dot { centre, diameter_mm } => Some((centre, diameter_mm)),
            _ => None,
        })
        .collect()
}

#[test]
fn braille_is_dots_at_the_profile_s_dimensions() {
    // "ll": two cells of dots 1-2-3, so columns one dot pitch apart within a
    // cell and one cell pitch apart between cells.
    let d = drawing(vec![label("t", "ll", 20.0, 40.0)]);
    for name in ["swell-a4", "print3d"] {
        let (s, _) = sheet(&d, name);
        let (_, q) = profile(name);
        let dots = dots_of(&s.pages[0], 0);
        assert_eq!(dots.len(), 6, "{name}");
        assert!(dots.iter().all(|d| d.1 == q.braille_dot_mm as f64));
        let mut xs: Vec<f64> = dots.iter().map(|d| d.0.0).collect();
        let mut ys: Vec<f64> = dots.iter().map(|d| d.0.1).collect();
        xs.sort_by(f64::total_cmp);
        ys.sort_by(f64::total_cmp);
        xs.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        ys.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        assert_eq!(xs.len(), 2, "{name}: {xs:?}");
        assert!((xs[1] - xs[0] - q.braille_cell_mm as f64).abs() < 1e-6, "{name}");
        assert_eq!(ys.len(), 3);
        assert!((ys[1] - ys[0] - q.braille_dot_pitch_mm as f64).abs() < 1e-6, "{name}");
        // The lowest dots rest on the baseline (40 mm, plus the margin).
        let m = q.margin_mm as f64;
        assert!((ys[2] + q.braille_dot_mm as f64 / 2.0 - (40.0 + m)).abs() < 1e-6, "{name}");
    }
}

#[test]
fn an_embosser_s_dots_all_lie_on_its_grid() {
    let d = drawing(vec![
        path("a", rect(10.3, 10.7, 50.0, 33.3), vec![vibrate(1.5, 50.0), grating(2.0, 45.0)]),
        path(
            "b",
            vec![Polyline { points: vec![(70.0, 20.0), (150.0, 90.0)], closed: false }],
            vec![vibrate(0.5, 80.0)],
        ),
        label("t", "map", 20.0, 120.0),
    ]);
    for name in ["tiger-20dpi", "emboss-braille-grid"] {
        let (s, _) = sheet(&d, name);
        let (_, q) = profile(name);
        let (g, m) = (q.grid_mm as f64, q.margin_mm as f64);
        let marks = &s.pages[0];
        assert!(marks.len() > 50, "{name}: {}", marks.len());
        for mk in marks {
            let MarkShape::Dot { centre, .. } = mk.shape else { panic!("{name}: {mk:?}") };
            for v in [centre.0, centre.1] {
                let k = (v - m) / g - 0.5;
                assert!((k - k.round()).abs() < 1e-6, "{name}: {v} is off the grid");
            }
        }
        // The embosser's braille keeps the cell's shape: a dot spacing that is whole grid steps.
        let steps = q.braille_dot_pitch_mm as f64 / g;
        assert!((steps - steps.round()).abs() < 1e-6, "{name}");
    }
    // Tiger's grid is 20 dots an inch.
    assert!((profile("tiger-20dpi").1.grid_mm as f64 - 25.4 / 20.0).abs() < 1e-6);
}

#[test]
fn several_vibrating_styles_get_distinct_line_styles_and_dot_styles_distinct_symbols() {
    let mut elements = Vec::new();
    for (k, f) in [50.0, 80.0, 120.0].into_iter().enumerate() {
        let y = 20.0 + 30.0 * k as f64;
        elements.push(path(
            &format!("l{k}"),
            vec![Polyline { points: vec![(10.0, y), (100.0, y)], closed: false }],
            vec![vibrate(1.5, f)],
        ));
    }
    for (k, r) in [1.0, 2.0].into_iter().enumerate() {
        let mut e = path(
            &format!("p{k}"),
            rect(120.0 + 20.0 * k as f64, 20.0, 2.0, 2.0),
            vec![Style::Dot(Dot { radius_mm: r, amplitude: 1.0 })],
        );
        e.styles = vec![Style::Dot(Dot { radius_mm: r, amplitude: 1.0 })];
        elements.push(e);
    }
    let (s, _) = sheet(&drawing(elements), "swell-a4");
    let marks = &s.pages[0];
    let of = |e: usize| marks.iter().filter(|m| m.element == Some(e)).collect::<Vec<_>>();
    // Solid: one line; dashed: many short lines; double: two lines.
    assert_eq!(of(0).len(), 1);
    assert!(of(1).len() > 5, "{}", of(1).len());
    assert_eq!(of(2).len(), 2);
    // A disc, then a square.
    assert!(matches!(of(3)[0].shape, MarkShape::Dot { diameter_mm, .. } if diameter_mm >= 6.4));
    assert!(matches!(&of(4)[0].shape, MarkShape::Polygon { rings } if rings[0].len() == 4));
}

#[test]
fn a_thin_line_is_widened_with_a_note() {
    let d = drawing(vec![path("thin", rect(10.0, 10.0, 30.0, 30.0), vec![vibrate(0.2, 50.0)])]);
    let (s, diags) = sheet(&d, "swell-a4");
    assert!(diags.iter().any(|d| d.code == "T0721"), "{diags:?}");
    assert!(
        matches!(s.pages[0][0].shape, MarkShape::Line { width_mm, .. } if width_mm == profile("swell-a4").1.min_line_mm as f64)
    );
}

#[test]
fn braille_over_a_line_and_lines_too_close_are_reported() {
    let d = drawing(vec![
        path(
            "road",
            vec![Polyline { points: vec![(10.0, 38.0), (120.0, 38.0)], closed: false }],
            vec![vibrate(1.5, 50.0)],
        ),
        path(
            "rail",
            vec![Polyline { points: vec![(10.0, 41.0), (120.0, 41.0)], closed: false }],
            vec![vibrate(1.5, 50.0)],
        ),
        label("name", "road", 20.0, 40.0),
    ]);
    let (_, diags) = sheet(&d, "swell-a4");
    let codes: Vec<&str> = diags.iter().map(|d| d.code).collect();
    assert!(codes.contains(&"T0722"), "{codes:?}");
    assert!(codes.contains(&"T0723"), "{codes:?}");
    // Apart and labelled clear of them: neither.
    let d = drawing(vec![
        path(
            "road",
            vec![Polyline { points: vec![(10.0, 38.0), (120.0, 38.0)], closed: false }],
            vec![vibrate(1.5, 50.0)],
        ),
        path(
            "rail",
            vec![Polyline { points: vec![(10.0, 48.0), (120.0, 48.0)], closed: false }],
            vec![vibrate(1.5, 50.0)],
        ),
        label("name", "road", 20.0, 80.0),
    ]);
    let (_, diags) = sheet(&d, "swell-a4");
    assert!(diags.iter().all(|d| d.code != "T0722" && d.code != "T0723"), "{diags:?}");
}

#[test]
fn a_small_textured_region_is_reported() {
    let d = drawing(vec![path("speck", rect(10.0, 10.0, 5.0, 30.0), vec![grating(2.0, 0.0)])]);
    let (_, diags) = sheet(&d, "swell-a4");
    assert!(diags.iter().any(|d| d.code == "T0724"), "{diags:?}");
}

/// Checks a closed triangle mesh: every edge shared by exactly two
/// triangles running along it in opposite directions; returns its volume
/// (divergence theorem, positive for outward winding).
fn closed_volume(tris: &[[[f32; 3]; 3]]) -> f64 {
    let key = |v: [f32; 3]| v.map(f32::to_bits);
    let mut edges: HashMap<([u32; 3], [u32; 3]), i32> = HashMap::new();
    let mut volume = 0.0f64;
    for t in tris {
        for k in 0..3 {
            let (a, b) = (key(t[k]), key(t[(k + 1) % 3]));
            assert_ne!(a, b, "a degenerate edge");
            *edges.entry((a, b)).or_default() += 1;
        }
        let [p, q, r] = t.map(|v| v.map(f64::from));
        volume += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0])
            + p[2] * (q[0] * r[1] - q[1] * r[0]))
            / 6.0;
    }
    for (&(a, b), &n) in &edges {
        assert_eq!(n, 1, "edge {a:?}-{b:?} run {n} times the same way");
        assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a:?}-{b:?} has no opposite half");
    }
    volume
}

#[test]
fn the_relief_is_watertight_manifold_with_positive_volume_and_its_heights() {
    let d = drawing(vec![
        path("a", rect(20.0, 20.0, 60.0, 40.0), vec![vibrate(1.5, 50.0), grating(2.0, 0.0)]),
        label("t", "ab", 30.0, 100.0),
    ]);
    let (s, _) = sheet(&d, "print3d");
    let (_, q) = profile("print3d");
    let tris = stl::triangles(&s).unwrap();
    let v = closed_volume(&tris);
    let (w, h) = (q.paper_w_mm as f64, q.paper_h_mm as f64);
    // At least the plate's volume, at most the plate with everything raised.
    assert!(v >= w * h * q.base_mm as f64 * 0.999, "{v}");
    assert!(v <= w * h * (q.base_mm + q.raise_mm) as f64, "{v}");
    let zs: std::collections::BTreeSet<u32> = tris.iter().flatten().map(|p| p[2].to_bits()).collect();
    let want: std::collections::BTreeSet<u32> =
        [0.0, q.base_mm, q.base_mm + q.texture_mm, q.base_mm + q.raise_mm].iter().map(|z| z.to_bits()).collect();
    assert_eq!(zs, want, "the heights are the plate, the textures and the raised features");
    // The binary STL: 84 bytes of header and count, 50 a triangle.
    let bytes = stl(&s).unwrap();
    assert_eq!(bytes.len(), 84 + 50 * tris.len());
    assert_eq!(u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize, tris.len());
}

#[test]
fn each_medium_writes_only_its_own_files() {
    let d = drawing(vec![path("a", rect(20.0, 20.0, 60.0, 40.0), vec![vibrate(1.5, 50.0)])]);
    let (swell, _) = sheet(&d, "swell-a4");
    assert!(write(&swell, FileKind::Pdf).unwrap().starts_with(b"%PDF-"));
    assert!(write(&swell, FileKind::Stl).is_err());
    assert!(write(&swell, FileKind::Png).is_err());
    let (relief, _) = sheet(&d, "print3d");
    assert!(write(&relief, FileKind::Pdf).is_err());
    let (tiger, _) = sheet(&d, "tiger-20dpi");
    let png = write(&tiger, FileKind::Png).unwrap();
    let img = taxel_textform::png::read(&png).unwrap();
    // 11 x 11.5 in at 20 px an inch.
    assert_eq!((img.width, img.height), (220, 230));
    assert!(img.to_gray8().contains(&0));
}

#[test]
fn the_pdf_page_is_the_paper() {
    let d = drawing(vec![path("a", rect(20.0, 20.0, 60.0, 40.0), vec![vibrate(1.5, 50.0)])]);
    for (name, w_in, h_in) in
        [("swell-a4", 210.0 / 25.4, 297.0 / 25.4), ("swell-letter", 8.5, 11.0), ("tiger-20dpi", 11.0, 11.5)]
    {
        let (s, _) = sheet(&d, name);
        let pdf = pdf(&s).unwrap();
        let text = String::from_utf8_lossy(&pdf);
        let at = text.find("/MediaBox [").unwrap_or_else(|| panic!("{name}: no MediaBox"));
        let nums: Vec<f64> =
            text[at + 11..].split(']').next().unwrap().split_whitespace().map(|v| v.parse().unwrap()).collect();
        assert_eq!(nums.len(), 4);
        assert!((nums[2] - nums[0] - w_in * 72.0).abs() < 0.01, "{name}: {nums:?}");
        assert!((nums[3] - nums[1] - h_in * 72.0).abs() < 0.01, "{name}: {nums:?}");
    }
}

#[test]
fn nothing_tactile_is_an_error_not_an_empty_page() {
    let d = drawing(vec![path("plain", rect(20.0, 20.0, 60.0, 40.0), vec![])]);
    let mut diags = Vec::new();
    assert!(legalise(&d, &profile("swell-a4").0, &mut diags).is_none());
    assert!(diags.iter().any(|d| d.code == "T0300"), "{diags:?}");
}

#[test]
fn the_relief_as_3mf_reads_back_as_the_stl_s_triangles_in_millimetres() {
    let d = drawing(vec![
        path("a", rect(20.0, 20.0, 60.0, 40.0), vec![vibrate(1.5, 50.0), grating(2.0, 0.0)]),
        label("t", "ab", 30.0, 100.0),
    ]);
    let (s, _) = sheet(&d, "print3d");
    let bytes = write(&s, FileKind::ThreeMf).unwrap();
    // threemf's own reader, as a slicer would open the package.
    let models = threemf::read(std::io::Cursor::new(&bytes)).unwrap();
    assert_eq!(models.len(), 1);
    let model = &models[0];
    assert!(matches!(model.unit, threemf::model::Unit::Millimeter), "in millimetres");
    assert_eq!(model.resources.object.len(), 1);
    let mesh = model.resources.object[0].mesh.as_ref().expect("a mesh");
    let v = &mesh.vertices.vertex;
    let read: Vec<[[f32; 3]; 3]> = mesh
        .triangles
        .triangle
        .iter()
        .map(|t| [t.v1, t.v2, t.v3].map(|k| [v[k].x as f32, v[k].y as f32, v[k].z as f32]))
        .collect();
    // The STL's triangles, corner for corner, with each corner stored once.
    let tris = stl::triangles(&s).unwrap();
    assert_eq!(read, tris);
    let distinct: std::collections::HashSet<[u32; 3]> = tris.iter().flatten().map(|p| p.map(f32::to_bits)).collect();
    assert_eq!(v.len(), distinct.len());
    assert!(closed_volume(&read) > 0.0);
    // Not for other media.
    let (swell, _) = sheet(&d, "swell-a4");
    assert!(write(&swell, FileKind::ThreeMf).is_err());
}

#[test]
fn point_symbols_that_would_touch_are_left_out_with_a_note() {
    // A scatter plot's marks 3 mm apart in a row: paper draws each at least
    // the medium's symbol size, so neighbours would touch.
    let elements: Vec<Element> = (0..40)
        .map(|k| {
            let mut e = path(&format!("m{k}"), rect(20.0 + 3.0 * k as f64, 50.0, 1.0, 1.0), vec![]);
            e.styles = vec![Style::Dot(Dot { radius_mm: 1.0, amplitude: 1.0 })];
            e
        })
        .collect();
    let (s, diags) = sheet(&drawing(elements), "swell-a4");
    let (_, q) = profile("swell-a4");
    let placed: Vec<((f64, f64), f64)> = (0..40).flat_map(|e| dots_of(&s.pages[0], e)).collect();
    assert!(placed.len() > 5 && placed.len() < 40, "{} kept", placed.len());
    for (i, a) in placed.iter().enumerate() {
        for b in &placed[i + 1..] {
            let d = (a.0.0 - b.0.0).hypot(a.0.1 - b.0.1);
            assert!(d >= (a.1 + b.1) / 2.0 + q.min_gap_mm as f64 - 1e-9, "{a:?} and {b:?} {d} mm apart");
        }
    }
    let note = diags.iter().find(|d| d.code == "T0728").expect("a note says so");
    assert!(note.message.starts_with(&format!("{} point symbol(s) left out", 40 - placed.len())), "{}", note.message);
    // Marks far apart are all kept, with no note.
    let far: Vec<Element> = (0..5)
        .map(|k| {
            let mut e = path(&format!("f{k}"), rect(20.0 + 30.0 * k as f64, 50.0, 1.0, 1.0), vec![]);
            e.styles = vec![Style::Dot(Dot { radius_mm: 1.0, amplitude: 1.0 })];
            e
        })
        .collect();
    let (s, diags) = sheet(&drawing(far), "swell-a4");
    assert_eq!((0..5).map(|e| dots_of(&s.pages[0], e).len()).sum::<usize>(), 5);
    assert!(diags.iter().all(|d| d.code != "T0728"));
}

/// Every point a mark draws: a line's centre line, a polygon's corners, a dot's centre.
fn mark_points(m: &Mark) -> Vec<(f64, f64)> {
    match &m.shape {
        MarkShape::Line { points, .. } => points.clone(),
        MarkShape::Polygon { rings } => rings.iter().flatten().copied().collect(),
        MarkShape::Dot { centre, .. } => vec![*centre],
    }
}

/// The length of the lines of `marks` (their centre lines).
fn line_length(marks: &[Mark]) -> f64 {
    marks
        .iter()
        .map(|m| match &m.shape {
            MarkShape::Line { points, closed, .. } => {
                let open: f64 = points.windows(2).map(|w| (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1)).sum();
                let back = match (closed, points.first(), points.last()) {
                    (true, Some(a), Some(b)) => (a.0 - b.0).hypot(a.1 - b.1),
                    _ => 0.0,
                };
                open + back
            }
            _ => 0.0,
        })
        .sum()
}

/// A shape clipped to a square in its middle (a chart's data in its axes,
/// an inset) prints only inside the square: its texture, its outline cut
/// where it crosses the square, a point symbol inside kept and one outside
/// left out. Every mark was printed over the whole shape before.
#[test]
fn a_clipped_shape_prints_only_inside_its_clip() {
    let (_, q) = profile("swell-a4");
    let o = q.margin_mm as f64;
    let square = rect(50.0, 50.0, 60.0, 60.0);
    let clip = crate::drawing::Clip { outline: square.clone(), fill_rule: crate::geometry::FillRule::NonZero };
    let mut big = path("big", rect(20.0, 20.0, 140.0, 140.0), vec![vibrate(1.5, 50.0), grating(3.0, 45.0)]);
    // A diagonal line through the square: 60 * sqrt 2 mm of it inside.
    let mut diagonal = path(
        "diagonal",
        vec![Polyline { points: vec![(20.0, 20.0), (160.0, 160.0)], closed: false }],
        // The same style as `big`'s outline: solid (a second style would be dashed).
        vec![vibrate(1.5, 50.0)],
    );
    let mut dots: Vec<Element> = [(80.0, 80.0), (140.0, 140.0)]
        .iter()
        .enumerate()
        .map(|(k, &(x, y))| {
            let mut e = path(&format!("m{k}"), rect(x, y, 1.0, 1.0), vec![]);
            e.styles = vec![Style::Dot(Dot { radius_mm: 1.0, amplitude: 1.0 })];
            e
        })
        .collect();
    for e in std::iter::once(&mut big).chain([&mut diagonal]).chain(dots.iter_mut()) {
        if let Shape::Path(p) = &mut e.shape {
            p.clips = vec![clip.clone()];
        }
    }
    let mut elements = vec![big.clone(), diagonal.clone()];
    elements.extend(dots.clone());
    let (s, _) = sheet(&drawing(elements.clone()), "swell-a4");
    let marks = &s.pages[0];
    let inside = |p: (f64, f64)| (50.0 + o..=110.0 + o).contains(&p.0) && (50.0 + o..=110.0 + o).contains(&p.1);
    let within = |p: (f64, f64)| {
        (50.0 + o - 1e-6..=110.0 + o + 1e-6).contains(&p.0) && (50.0 + o - 1e-6..=110.0 + o + 1e-6).contains(&p.1)
    };
    assert!(marks.iter().flat_map(mark_points).all(within), "every mark lies in the clip");
    // The big square's outline lies wholly outside the clip; its texture fills the clip.
    let of = |e: usize| marks.iter().filter(move |m| m.element == Some(e));
    assert!(of(0).all(|m| m.level == Level::Texture), "no outline of `big` is printed");
    let texture: Vec<(f64, f64)> = of(0).flat_map(mark_points).collect();
    let (x0, x1) = texture.iter().fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.0), a.1.max(p.0)));
    assert!(x0 < 55.0 + o && x1 > 105.0 + o, "the texture spans the clip: {x0}..{x1}");
    // The diagonal: only its 60 * sqrt 2 mm inside the square.
    let diag: Vec<Mark> = of(1).cloned().collect();
    assert!((line_length(&diag) - 60.0 * 2f64.sqrt()).abs() < 1e-6, "{}", line_length(&diag));
    // The symbol inside is kept, the one outside is not.
    assert!(of(2).count() > 0 && of(3).count() == 0);
    assert!(of(2).flat_map(mark_points).all(inside));
    // Unclipped, the same drawing prints beyond the square.
    for e in &mut elements {
        if let Shape::Path(p) = &mut e.shape {
            p.clips.clear();
        }
    }
    let (s, _) = sheet(&drawing(elements), "swell-a4");
    assert!(s.pages[0].iter().flat_map(mark_points).any(|p| !within(p)));
}

/// A drawing larger than the printable area, at its size, is printed on
/// several pages, each a window of it: a line across it is cut at the
/// windows' edges and its pieces add up to its whole length; a braille
/// label across a page edge is kept whole on one page; every mark lies on
/// its page's printable area. The key follows the graphic's pages.
#[test]
fn a_large_drawing_is_printed_on_pages_that_join() {
    let (p, q) = profile("swell-a4");
    let (sw, sh) = (p.surface_w_mm as f64, p.surface_h_mm as f64);
    let o = q.margin_mm as f64;
    let (w, h) = (2.5 * sw, 1.5 * sh);
    let line = path(
        "across",
        vec![Polyline { points: vec![(10.0, 10.0), (w - 10.0, h - 10.0)], closed: false }],
        vec![vibrate(1.5, 50.0)],
    );
    let frame = path("frame", rect(5.0, 5.0, w - 10.0, h - 10.0), vec![vibrate(1.0, 50.0)]);
    // A label that starts just left of the first vertical page edge.
    let mut keyed = label("k", "ab", 30.0, 40.0);
    if let Shape::Text(ts) = &mut keyed.shape {
        ts.keyed = Some("Abbey Road".into());
    }
    let elements = vec![line.clone(), frame.clone(), label("t", "across the edge", sw - 10.0, 50.0), keyed];
    let mut d = drawing(elements);
    d.page.width_mm = w;
    d.page.height_mm = h;
    let mut diags = Vec::new();
    assert!(crate::place::apply(&mut d, &p, false, None, crate::geometry::Flattening::DEFAULT, &mut diags));
    let note = diags.iter().find(|d| d.code == "T0212").expect("a note says how many pages");
    assert!(note.message.contains("6 pages, 3 across and 2 down"), "{}", note.message);
    assert!(!diags.iter().any(|d| d.code == "T0202"), "nothing is left out: {diags:?}");
    let (s, _) = sheet(&d, "swell-a4");
    assert_eq!(s.tiles, (3, 2));
    assert_eq!(s.pages.len(), 7, "six pages of the graphic, then the key");
    let on_page =
        |p: (f64, f64)| (o - 1e-6..=o + sw + 1e-6).contains(&p.0) && (o - 1e-6..=o + sh + 1e-6).contains(&p.1);
    for (n, page) in s.pages[..6].iter().enumerate() {
        let lines = page.iter().filter(|m| m.level != Level::Braille);
        assert!(lines.flat_map(mark_points).all(on_page), "page {n}: a mark beyond its printable area");
    }
    // The line's pieces, on every page, add up to the whole line.
    let pieces: Vec<Mark> = s.pages[..6].iter().flatten().filter(|m| m.element == Some(0)).cloned().collect();
    let whole = (w - 20.0).hypot(h - 20.0);
    assert!((line_length(&pieces) - whole).abs() < 1e-6, "{} of {whole}", line_length(&pieces));
    // The label's braille is on one page only, and as many dots as on one page.
    let label_pages: Vec<usize> =
        (0..6).filter(|&n| s.pages[n].iter().any(|m| m.element == Some(2) && m.level == Level::Braille)).collect();
    assert_eq!(label_pages, vec![0]);
    let alone = {
        let (one, _) = sheet(&drawing(vec![label("t", "across the edge", 10.0, 50.0)]), "swell-a4");
        one.pages[0].iter().filter(|m| m.element == Some(0)).count()
    };
    assert_eq!(s.pages[0].iter().filter(|m| m.element == Some(2)).count(), alone);
    // The key's page comes last, beside the graphic in the preview's layout.
    assert_eq!(s.layout()[6], (3, 0));
    assert!(s.pages[6].iter().any(|m| m.element.is_none() && m.level == Level::Braille), "the key's braille");
}

/// A drawing that would take more than a hundred pages is refused, with
/// the way out; one that fits a page prints on one.
#[test]
fn a_drawing_of_too_many_pages_is_refused() {
    let (p, _) = profile("swell-a4");
    let mut d = drawing(vec![path("a", rect(20.0, 20.0, 60.0, 40.0), vec![vibrate(1.5, 50.0)])]);
    let mut diags = Vec::new();
    assert!(crate::place::apply(&mut d.clone(), &p, false, None, crate::geometry::Flattening::DEFAULT, &mut diags));
    assert!(diags.iter().all(|d| d.code != "T0212"));
    d.page.width_mm = 3000.0;
    d.page.height_mm = 3000.0;
    let mut diags = Vec::new();
    assert!(!crate::place::apply(&mut d, &p, false, None, crate::geometry::Flattening::DEFAULT, &mut diags));
    let e = diags.iter().find(|d| d.code == "T0213").expect("refused");
    assert!(e.message.contains("more than 100") && e.help.as_deref().is_some_and(|h| h.contains("--fit")), "{e:?}");
}

/// A relief on several pages is a plate a page, each closed: the mesh is
/// still watertight and 2-manifold, with the plates' volume.
#[test]
fn a_relief_of_several_pages_is_a_closed_plate_a_page() {
    let (p, q) = profile("print3d");
    let (sw, sh) = (p.surface_w_mm as f64, p.surface_h_mm as f64);
    let mut d = drawing(vec![path(
        "across",
        vec![Polyline { points: vec![(10.0, 10.0), (1.5 * sw, 10.0)], closed: false }],
        vec![vibrate(1.5, 50.0)],
    )]);
    d.page.width_mm = 1.6 * sw;
    d.page.height_mm = 0.5 * sh;
    assert!(crate::place::apply(&mut d, &p, false, None, crate::geometry::Flattening::DEFAULT, &mut Vec::new()));
    let (s, _) = sheet(&d, "print3d");
    assert_eq!((s.tiles, s.pages.len()), ((2, 1), 2));
    let tris = stl::triangles(&s).unwrap();
    let v = closed_volume(&tris);
    let (w, h) = (q.paper_w_mm as f64, q.paper_h_mm as f64);
    let plate = w * h * q.base_mm as f64;
    assert!(v >= 2.0 * plate * 0.999 && v <= 2.0 * w * h * (q.base_mm + q.raise_mm) as f64, "{v}");
    // Both plates carry part of the line.
    let raised = |range: std::ops::Range<f32>| {
        tris.iter().flatten().any(|c| range.contains(&c[0]) && c[2] > q.base_mm + 0.5 * q.raise_mm)
    };
    assert!(raised(0.0..w as f32) && raised(w as f32..2.0 * w as f32 + 20.0));
}

/// A texture is not printed under an opaque fill painted over it (a map's
/// legend box, an inset), as on the pin arrays: no texture line runs
/// through the box, and the texture around it stays.
#[test]
fn a_texture_is_hidden_under_an_opaque_fill_painted_over_it() {
    let (_, q) = profile("swell-a4");
    let o = q.margin_mm as f64;
    let under = path("under", rect(20.0, 20.0, 120.0, 100.0), vec![grating(3.0, 0.0)]);
    let mut over = path("box", rect(60.0, 50.0, 40.0, 30.0), vec![]);
    over.paint.fill = Some([255, 255, 255, 255]);
    over.paint.filled = true;
    let (hidden, _) = sheet(&drawing(vec![under.clone(), over.clone()]), "swell-a4");
    let (open, _) = sheet(&drawing(vec![under.clone()]), "swell-a4");
    let in_box = |p: &(f64, f64)| {
        p.0 > 60.0 + o + 1e-6 && p.0 < 100.0 + o - 1e-6 && p.1 > 50.0 + o + 1e-6 && p.1 < 80.0 + o - 1e-6
    };
    // Sample every texture line densely: no point of it inside the box.
    let samples = |marks: &[Mark]| -> Vec<(f64, f64)> {
        marks
            .iter()
            .filter(|m| m.element == Some(0))
            .flat_map(|m| match &m.shape {
                MarkShape::Line { points, .. } => points
                    .windows(2)
                    .flat_map(|w| {
                        (0..=50).map(move |k| {
                            let t = k as f64 / 50.0;
                            (w[0].0 + t * (w[1].0 - w[0].0), w[0].1 + t * (w[1].1 - w[0].1))
                        })
                    })
                    .collect::<Vec<_>>(),
                _ => mark_points(m),
            })
            .collect()
    };
    assert!(samples(&open.pages[0]).iter().any(in_box), "the texture runs under the box when nothing is over it");
    assert!(!samples(&hidden.pages[0]).iter().any(in_box), "no texture under the opaque box");
    // What the box hides is its width of each line that crossed it: 40 mm
    // for every line whose row runs through the box.
    let rows_through = open.pages[0]
        .iter()
        .filter_map(|m| match &m.shape {
            MarkShape::Line { points, .. } if m.element == Some(0) => Some(points[0].1),
            _ => None,
        })
        .filter(|y| *y > 50.0 + o && *y < 80.0 + o)
        .count() as f64;
    let lost = line_length(&open.pages[0]) - line_length(&hidden.pages[0]);
    assert!(rows_through > 3.0 && (lost - 40.0 * rows_through).abs() < 1e-6, "{lost} mm for {rows_through} rows");
    // Painted under the texture instead, the box hides nothing.
    let (below, _) = sheet(&drawing(vec![over, under]), "swell-a4");
    assert!((line_length(&below.pages[0]) - line_length(&open.pages[0])).abs() < 1e-6);
}

/// Unannotated and larger than the paper, a drawing is styled by the
/// automatic sheet on all of its page, not only on the first page's worth:
/// a region and a line far beyond the printable area are made tactile, and
/// printed on the page they lie on. They were left out before.
#[test]
fn the_automatic_sheet_styles_all_of_a_paged_drawing() {
    let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="500mm" height="300mm" viewBox="0 0 500 300">
        <rect x="20" y="20" width="60" height="40" fill="#3a7"/>
        <rect x="400" y="200" width="60" height="40" fill="#37a"/>
        <path d="M300 50 L480 80" stroke="#000" stroke-width="1.5" fill="none"/>
    </svg>"##;
    let (p, _) = profile("swell-a4");
    let opts = crate::CompileOptions { auto: true, ..crate::CompileOptions::new(p) };
    let r = crate::pipeline::resolve(svg, &opts);
    let d = r.drawing.expect("resolved");
    let styled =
        |x: f64| d.elements.iter().any(|e| e.bounds().is_some_and(|b| b.0 <= x && x <= b.2) && !e.styles.is_empty());
    assert!(
        styled(50.0) && styled(430.0) && styled(470.0),
        "{:?}",
        d.elements.iter().map(|e| &e.styles).collect::<Vec<_>>()
    );
    let (s, _) = sheet(&d, "swell-a4");
    assert_eq!(s.tiles, (3, 2));
    // The far region (400..460 x 200..240 mm) lies on the third page of the first row.
    assert!(s.pages[2].iter().any(|m| m.element.is_some()), "the third page has marks");
}

mod key;
