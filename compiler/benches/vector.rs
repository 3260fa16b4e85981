//! Technique (b) of issue 16 (vector layers: exact geometry with a per-cell
//! segment index, `compiler/src/vector.rs`) against technique (a) (the
//! distance layers the compiler writes, SPEC.md section 6.2), measured
//! side by side on the same layers of the same scenes:
//!
//! 1. figures, printed before the timings: encoded size of (a) and (b)
//!    against an 8-bit PNG of the scene's amplitude at 10 px/mm; accuracy of
//!    both against exact f64 geometry (an independent indexed evaluation of
//!    the layer's signed distance): RMS and largest error on a 0.1 mm grid,
//!    the largest error farther than 0.05 mm from every edge, the edge
//!    position error (largest distance from the exact outline of a probe on
//!    the wrong side of the half-amplitude contour), and the same at the
//!    corners of the exp1 squares, triangles, plus and diamond; segments
//!    per cell;
//! 2. timings (criterion): the coverage of 64 actuators (the STRESS² array)
//!    in one vibration and one grating layer of `tala-map` at carrier
//!    positions along a trace across the map, for (a)'s reference evaluation
//!    (`DistanceLayer::coverage_at`, scalar f32) and (b)'s kernel (scalar
//!    f32, four lanes a call), and the runtime's full (a) frame of the same
//!    two layers (production kernel, four lanes in SIMD, primitives included)
//!    for scale.
//!
//! `cargo bench -p taxel-compiler --bench vector -- --warm-up-time 1 --measurement-time 3`
//! (`TAXEL_VECTOR_FIGURES=0` skips the figures; `TAXEL_VECTOR_TOL=0.001` sets
//! (b)'s simplification tolerance in mm.)

use std::hint::black_box;

use criterion::{Criterion, criterion_group};
use taxel_compiler::distance::LayerGeometry;
use taxel_compiler::geometry::{FillRule, Polyline, distance_to_segment};
use taxel_compiler::vector::capture::{Captured, layers_of};
use taxel_compiler::vector::{VectorLayer, VectorParams, build_vector};
use taxel_compiler::{CompileOptions, svg::compile_svg};
use taxel_format::{Bundle, BundleView, Chunk, DistanceLayer, MaskKind, Mm, Tick, profiles};
use taxel_runtime::latero::LateroPlayer;

#[path = "drawings/mod.rs"]
mod drawings;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

fn compile(svg: &str, fit: bool) -> Vec<Captured> {
    let profile = profiles::builtin("stress2").expect("built-in profile");
    let opts = CompileOptions { fit, ..CompileOptions::new(profile) };
    layers_of(|| {
        let out = compile_svg(svg, &opts);
        assert!(out.bundle.is_some(), "{:?}", out.diagnostics);
    })
}

fn vector_of(c: &Captured, cell_mm: f64) -> Option<VectorLayer> {
    let mut p = VectorParams { cell_mm, ..VectorParams::new(c.params.soft_mm, c.params.page) };
    // `TAXEL_VECTOR_TOL=0` measures (b) without simplification (quantisation only).
    if let Some(t) = std::env::var("TAXEL_VECTOR_TOL").ok().and_then(|v| v.parse().ok()) {
        p.tolerance_mm = t;
    }
    build_vector(&c.geometry.view(), p).expect("vector layer")
}

/// (a)'s chunk length, SPEC.md section 6.2: `48 + 4 S + 4 C R + 81 K`.
fn field_len(l: &DistanceLayer) -> usize {
    48 + 4 * l.sources.len() + 4 * l.tiles.len() + l.samples.len()
}

/// Exact f64 signed distance of a layer, independent of both builders:
/// segments bucketed on a 1 mm grid (each within `half width + 1 mm` of a
/// cell), fill sides by crossing counts per shape under its rule. Distances
/// beyond 1 mm from every edge are reported as at least 1 mm, on the right side.
struct Exact {
    x0: f64,
    y0: f64,
    cols: usize,
    rows: usize,
    /// Per part: segments and per-cell lists.
    parts: Vec<Part>,
    page: (f64, f64, f64, f64),
    band_w: Option<f64>,
}

struct Part {
    kind: Kind,
    segs: Vec<(Pt, Pt, usize)>,
    cells: Vec<Vec<u32>>,
    rows: Vec<Vec<u32>>,
    rules: Vec<FillRule>,
}

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Fill,
    Band,
    Cut(f64),
    Clip,
}

const CAP: f64 = 1.0;

type Pt = (f64, f64);

impl Exact {
    fn new(g: &LayerGeometry<'_>, page: (f64, f64, f64, f64)) -> Self {
        let (x0, y0) = (page.0 - 5.0, page.1 - 5.0);
        let cols = ((page.2 - x0 + 5.0) / CAP).ceil() as usize;
        let rows = ((page.3 - y0 + 5.0) / CAP).ceil() as usize;
        let closed = |pls: &[Polyline], k: usize| {
            pls.iter()
                .flat_map(move |pl| {
                    let n = pl.points.len();
                    (0..if n > 1 { n } else { 0 }).map(move |i| (pl.points[i], pl.points[(i + 1) % n], k))
                })
                .collect::<Vec<_>>()
        };
        let open = |pls: &[Polyline]| {
            pls.iter()
                .flat_map(|pl| {
                    let one = (pl.points.len() == 1).then(|| (pl.points[0], pl.points[0], 0));
                    pl.segments().map(|(a, b)| (a, b, 0)).chain(one)
                })
                .collect::<Vec<_>>()
        };
        let mut parts = Vec::new();
        if !g.fills.is_empty() {
            let segs = g.fills.iter().enumerate().flat_map(|(k, (p, _))| closed(p, k)).collect();
            parts.push((Kind::Fill, segs, g.fills.iter().map(|f| f.1).collect(), 0.0));
        }
        if let Some((lines, w)) = &g.band {
            parts.push((Kind::Band, lines.iter().flat_map(|p| open(p)).collect(), vec![], w / 2.0));
        }
        for (p, w) in &g.cuts {
            parts.push((Kind::Cut(*w), open(p), vec![], w / 2.0));
        }
        for (p, r) in &g.clips {
            parts.push((Kind::Clip, closed(p, 0), vec![*r], 0.0));
        }
        let parts = parts
            .into_iter()
            .map(|(kind, segs, rules, hw): (Kind, Vec<_>, Vec<FillRule>, f64)| {
                let mut cells = vec![Vec::new(); cols * rows];
                let mut by_row = vec![Vec::new(); rows];
                let m = hw + CAP;
                for (n, &(a, b, _)) in segs.iter().enumerate() {
                    let c = |v: f64, o: f64, n: usize| (((v - o) / CAP).floor().max(0.0) as usize).min(n - 1);
                    let (c0, c1) = (c(a.0.min(b.0) - m, x0, cols), c(a.0.max(b.0) + m, x0, cols));
                    let (r0, r1) = (c(a.1.min(b.1) - m, y0, rows), c(a.1.max(b.1) + m, y0, rows));
                    for r in r0..=r1 {
                        for cc in c0..=c1 {
                            cells[r * cols + cc].push(n as u32);
                        }
                    }
                    let (r0, r1) = (c(a.1.min(b.1), y0, rows), c(a.1.max(b.1), y0, rows));
                    for row in by_row.iter_mut().take(r1 + 1).skip(r0) {
                        row.push(n as u32);
                    }
                }
                Part { kind, segs, cells, rows: by_row, rules }
            })
            .collect();
        Exact { x0, y0, cols, rows, parts, page, band_w: g.band.as_ref().map(|b| b.1) }
    }

    fn at(&self, p: (f64, f64)) -> f64 {
        let (ci, ri) = (((p.0 - self.x0) / CAP).floor(), ((p.1 - self.y0) / CAP).floor());
        let inside_grid = ci >= 0.0 && ri >= 0.0 && (ci as usize) < self.cols && (ri as usize) < self.rows;
        let k = if inside_grid { Some(ri as usize * self.cols + ci as usize) } else { None };
        let dist = |part: &Part| {
            k.map_or(f64::INFINITY, |k| {
                part.cells[k]
                    .iter()
                    .map(|&n| part.segs[n as usize])
                    .map(|(a, b, _)| distance_to_segment(p, a, b))
                    .fold(f64::INFINITY, f64::min)
            })
        };
        let contains = |part: &Part| {
            let Some(row) = k.map(|k| &part.rows[k / self.cols]) else { return false };
            let mut state = vec![(0i32, 0u32); part.rules.len()];
            for &n in row {
                let (a, b, s) = part.segs[n as usize];
                if (a.1 <= p.1) != (b.1 <= p.1) && a.0 + (p.1 - a.1) / (b.1 - a.1) * (b.0 - a.0) > p.0 {
                    state[s].0 += if b.1 > a.1 { 1 } else { -1 };
                    state[s].1 += 1;
                }
            }
            state.iter().zip(&part.rules).any(|(s, r)| match r {
                FillRule::NonZero => s.0 != 0,
                FillRule::EvenOdd => s.1 % 2 == 1,
            })
        };
        let mut s = f64::NEG_INFINITY;
        for part in &self.parts {
            let d = dist(part).min(CAP + 1.0);
            match part.kind {
                Kind::Fill => s = if contains(part) { d } else { -d },
                Kind::Band => s = s.max(self.band_w.unwrap_or(0.0) / 2.0 - d),
                Kind::Cut(w) => s = s.min(d - w / 2.0),
                Kind::Clip => s = s.min(if contains(part) { d } else { -d }),
            }
        }
        let r = self.page;
        let dx = (p.0 - r.0).min(r.2 - p.0);
        let dy = (p.1 - r.1).min(r.3 - p.1);
        s.min(if dx >= 0.0 && dy >= 0.0 { dx.min(dy) } else { -(dx.min(0.0).hypot(dy.min(0.0))) })
    }
}

/// Accumulated errors of one technique, in 10-bit steps and mm.
#[derive(Default, Clone, Copy)]
struct Err {
    sum2: f64,
    n: usize,
    max: f64,
    far: f64,
    edge_mm: f64,
    corner: f64,
    corner_edge_mm: f64,
}

fn profile(e: f64, soft: f64) -> f64 {
    if soft > 0.0 {
        (0.5 + e / soft).clamp(0.0, 1.0)
    } else if e > 0.0 {
        1.0
    } else if e < 0.0 {
        0.0
    } else {
        0.5
    }
}

/// Probes `e` with coverage `got` into `acc`.
fn probe(acc: &mut Err, e: f64, soft: f64, got: f32, grid: bool, corner: bool) {
    let err = (got as f64 - profile(e, soft)).abs() * 1023.0;
    if grid {
        acc.sum2 += err * err;
        acc.n += 1;
    }
    acc.max = acc.max.max(err);
    if e.abs() > 0.05 + soft / 2.0 {
        acc.far = acc.far.max(err);
    }
    let wrong = (got >= 0.5) != (e > 0.0) && e != 0.0;
    if wrong {
        acc.edge_mm = acc.edge_mm.max(e.abs());
    }
    if corner {
        acc.corner = acc.corner.max(err);
        if wrong {
            acc.corner_edge_mm = acc.corner_edge_mm.max(e.abs());
        }
    }
}

/// Every edge carrier of a layer: (segment, offset of the edge from it), and the corner vertices of small polygons.
type Carriers = (Vec<((f64, f64), (f64, f64), f64)>, Vec<(f64, f64, f64)>);

fn carriers(g: &LayerGeometry<'_>) -> Carriers {
    let mut segs = Vec::new();
    let mut corners = Vec::new();
    let mut add = |pls: &[Polyline], off: f64, closed: bool| {
        for pl in pls {
            let n = pl.points.len();
            let m = if closed || pl.closed { n } else { n.saturating_sub(1) };
            segs.extend((0..m).map(|i| (pl.points[i], pl.points[(i + 1) % n], off)));
            // Squares, triangles, the plus and the diamond (not circles).
            if n <= 12 {
                corners.extend(pl.points.iter().map(|p| (p.0, p.1, off)));
            }
        }
    };
    for (p, _) in g.fills.iter().chain(&g.clips) {
        add(p, 0.0, true);
    }
    if let Some((lines, w)) = &g.band {
        for p in lines {
            add(p, w / 2.0, false);
        }
    }
    for (p, w) in &g.cuts {
        add(p, w / 2.0, false);
    }
    (segs, corners)
}

/// Errors of (a) and (b) on one layer.
fn accuracy(c: &Captured, v: Option<&VectorLayer>, grid_step: f64, acc: &mut [Err; 2]) {
    let g = c.geometry.view();
    let ex = Exact::new(&g, c.params.page);
    let soft = c.params.soft_mm;
    let a = &c.layer;
    let (x0, y0) = (a.origin_x.0 as f64, a.origin_y.0 as f64);
    let span = |n: u32| n as f64 * 8.0 * a.pitch_mm as f64;
    let (x1, y1) = (x0 + span(a.tile_cols), y0 + span(a.tile_rows));
    let cov = |p: (f64, f64)| {
        let (x, y) = (p.0 as f32, p.1 as f32);
        [a.coverage_at(x, y), v.map_or(0.0, |v| v.coverage_at(x, y))]
    };
    let mut run = |p: (f64, f64), grid: bool, corner: bool| {
        let e = ex.at(p);
        let got = cov(p);
        for k in 0..2 {
            probe(&mut acc[k], e, soft, got[k], grid, corner);
        }
    };
    let mut y = y0 + grid_step / 3.0;
    while y < y1 {
        let mut x = x0 + grid_step / 7.0;
        while x < x1 {
            run((x, y), true, false);
            x += grid_step;
        }
        y += grid_step;
    }
    let (segs, corners) = carriers(&g);
    let offsets = [0.001, 0.0025, 0.005, 0.0075, 0.01, 0.015, 0.02, 0.03, 0.04, 0.05, 0.075, 0.1, 0.15, 0.2, 0.3];
    for (a, b, off) in segs {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = dx.hypot(dy);
        if len < 1e-9 {
            continue;
        }
        let (nx, ny) = (-dy / len, dx / len);
        let n = (len / 0.05).ceil() as usize;
        for i in 0..=n {
            let t = i as f64 / n as f64;
            for o in offsets {
                for k in [off - o, off + o, -off - o, -off + o] {
                    run((a.0 + dx * t + nx * k, a.1 + dy * t + ny * k), false, false);
                }
            }
        }
    }
    for (cx, cy, off) in corners {
        let r_max = off + 0.3;
        for i in 0..64 {
            let ang = i as f64 / 64.0 * std::f64::consts::TAU;
            for j in 1..=30 {
                let r = r_max * j as f64 / 30.0;
                run((cx + r * ang.cos(), cy + r * ang.sin()), false, true);
            }
        }
    }
}

/// An 8-bit PNG of the scene's amplitude (largest over layers, (b)) at 10 px/mm.
fn png_len(vs: &[VectorLayer], page: (f64, f64, f64, f64)) -> usize {
    let (w, h) = (((page.2 - page.0) * 10.0).ceil() as u32, ((page.3 - page.1) * 10.0).ceil() as u32);
    let mut img = image::GrayImage::new(w.max(1), h.max(1));
    for (x, y, px) in img.enumerate_pixels_mut() {
        let (mx, my) = ((page.0 + (x as f64 + 0.5) / 10.0) as f32, (page.1 + (y as f64 + 0.5) / 10.0) as f32);
        let a = vs.iter().map(|v| v.coverage_at(mx, my)).fold(0.0f32, f32::max);
        px.0 = [(a * 255.0).round() as u8];
    }
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).expect("png");
    out.into_inner().len()
}

fn squares_2000() -> String {
    let mut s = String::from(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="110mm" height="60mm" viewBox="0 0 110 60">
"#,
    );
    for k in 0..2000 {
        let (i, j) = (k % 50, k / 50);
        s += &format!(
            "<rect id=\"s{k}\" x=\"{:.2}\" y=\"{:.2}\" width=\"1\" height=\"1\" data-tactile=\"grating(wavelength: 3mm, angle: 0deg)\"/>\n",
            2.0 + i as f64 * 2.1,
            1.0 + j as f64 * 1.45
        );
    }
    s + "</svg>\n"
}

fn read(path: &str) -> String {
    std::fs::read_to_string(format!("{ROOT}/{path}")).expect("example")
}

fn figures() {
    let scenes: Vec<(&str, String, bool, bool)> = vec![
        ("tala-map", read("examples/map/tala-map.svg"), false, true),
        ("exp1-vibrate-2cm", read("examples/stress2/exp1-vibrate-2cm.svg"), false, true),
        ("exp1-grating-2cm", read("examples/stress2/exp1-grating-2cm.svg"), false, true),
        ("exp1-vibrate-3cm-a", read("examples/stress2/exp1-vibrate-3cm-a.svg"), false, true),
        ("exp1-grating-3cm-a", read("examples/stress2/exp1-grating-3cm-a.svg"), false, true),
        ("2,000 grated 1 mm squares", squares_2000(), false, true),
        ("country map, 1,000 regions, fitted", drawings::inkscape_map(1000, 8, 7), true, false),
    ];
    println!("\n## Sizes (bytes; layers only, provenance and the rest of the bundle excluded)\n");
    println!(
        "| scene | layers | (a) distance tiles | (b) vector, 2 mm cells | (b), 1 mm cells | (b), 4 mm cells | PNG 8-bit 10 px/mm |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- |");
    let mut acc_rows = Vec::new();
    for (name, svg, fit, acc) in &scenes {
        let caps = compile(svg, *fit);
        let a: usize = caps.iter().map(|c| field_len(&c.layer)).sum();
        let size = |cell: f64| -> usize {
            caps.iter().filter_map(|c| vector_of(c, cell).map(|v| v.encoded_len(c.sources))).sum()
        };
        let vs: Vec<VectorLayer> = caps.iter().filter_map(|c| vector_of(c, 2.0)).collect();
        let page = caps.first().map_or((0.0, 0.0, 1.0, 1.0), |c| c.params.page);
        println!(
            "| {name} | {} | {a} | {} | {} | {} | {} |",
            caps.len(),
            size(2.0),
            size(1.0),
            size(4.0),
            png_len(&vs, page)
        );
        for (c, v) in caps.iter().zip(&vs) {
            let (n, mean, max) = v.cell_stats();
            let (pts, refs) = (v.points.len(), v.refs.len());
            let cells = v.cols * v.rows;
            eprintln!(
                "  {name}: {:?} layer: {pts} points, {refs} refs, {cells} cells of 2 mm, {n} with segments, {mean:.1} mean, {max} max; (a) {} tiles, {} stored",
                c.layer.kind_name(),
                c.layer.tiles.len(),
                c.layer.samples.len() / 81
            );
        }
        if *acc {
            let mut e = [Err::default(); 2];
            for c in &caps {
                let v = vector_of(c, 2.0);
                accuracy(c, v.as_ref(), 0.1, &mut e);
            }
            acc_rows.push((name.to_string(), e));
        }
    }
    println!("\n## Accuracy against exact f64 geometry (10-bit steps; mm)\n");
    println!(
        "| scene | technique | RMS (0.1 mm grid) | max | far (> 0.05 mm) | edge error mm | corners: max | corners: edge mm |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- |");
    for (name, e) in acc_rows {
        for (k, t) in ["(a) 0.5 mm field", "(b) vector"].iter().enumerate() {
            let x = e[k];
            println!(
                "| {name} | {t} | {:.2} | {:.0} | {:.2} | {:.4} | {:.0} | {:.4} |",
                (x.sum2 / x.n.max(1) as f64).sqrt(),
                x.max,
                x.far,
                x.edge_mm,
                x.corner,
                x.corner_edge_mm
            );
        }
    }
    println!();
}

trait KindName {
    fn kind_name(&self) -> &'static str;
}

impl KindName for DistanceLayer {
    fn kind_name(&self) -> &'static str {
        match self.kind {
            MaskKind::Vibration { .. } => "vibration",
            MaskKind::Grating { .. } => "grating",
        }
    }
}

/// The STRESS² array's 64 actuator positions around carrier `(x, y)`.
fn actuators(x: f32, y: f32) -> ([f32; 64], [f32; 64]) {
    let (mut xs, mut ys) = ([0.0; 64], [0.0; 64]);
    for r in 0..8 {
        for c in 0..8 {
            xs[r * 8 + c] = x + (c as f32 - 3.5) * 1.2;
            ys[r * 8 + c] = y + (r as f32 - 3.5) * 1.4;
        }
    }
    (xs, ys)
}

fn timings(c: &mut Criterion) {
    let map = compile(&drawings::inkscape_map(1000, 8, 7), true);
    scene_timings(c, "country map 1,000 regions fitted", &map, &[2.0]);
    let tala = compile(&read("examples/map/tala-map.svg"), false);
    scene_timings(c, "tala-map", &tala, &[1.0, 2.0, 4.0]);
}

fn scene_timings(c: &mut Criterion, scene: &str, caps: &[Captured], cells: &[f64]) {
    let vib = caps.iter().find(|c| matches!(c.layer.kind, MaskKind::Vibration { .. })).expect("a vibration layer");
    let gr = caps.iter().find(|c| matches!(c.layer.kind, MaskKind::Grating { .. })).expect("a grating layer");
    // A trace across the page: 256 carrier positions along a wavy line over its edges.
    let pg = vib.params.page;
    let (w, h) = ((pg.2 - pg.0) as f32, (pg.3 - pg.1) as f32);
    let trace: Vec<(f32, f32)> = (0..256)
        .map(|k| {
            (pg.0 as f32 + w * (0.1 + 0.8 * k as f32 / 256.0), pg.1 as f32 + h * (0.5 + 0.2 * (k as f32 * 0.05).sin()))
        })
        .collect();
    for &cell in cells {
        let (Some(bv), Some(bg)) = (vector_of(vib, cell), vector_of(gr, cell)) else { continue };
        // Segments per cell where the trace's actuators land.
        let (mut n, mut sum, mut max) = (0usize, 0usize, 0u32);
        for v in [&bv, &bg] {
            for &(x, y) in &trace {
                let (xs, ys) = actuators(x, y);
                for k in 0..64 {
                    let q = v.quantum;
                    let cx = ((xs[k] - v.origin.0) / q - v.grid.0) / v.cell;
                    let cy = ((ys[k] - v.origin.1) / q - v.grid.1) / v.cell;
                    if cx >= 0.0 && cy >= 0.0 && (cx as u32) < v.cols && (cy as u32) < v.rows {
                        let i = cy as usize * v.cols as usize + cx as usize;
                        let m = v.starts[i + 1] - v.starts[i];
                        n += 1;
                        sum += m as usize;
                        max = max.max(m);
                    }
                }
            }
        }
        eprintln!(
            "{scene}, {cell} mm cells: segments listed in the cell of each actuator on the trace: mean {:.2}, max {max}",
            sum as f64 / n.max(1) as f64
        );
        let mut k = 0usize;
        c.bench_function(
            &format!("coverage 64 x (vibration + grating), {scene} trace: (b) vector, {cell} mm cells"),
            |b| {
                b.iter(|| {
                    k = (k + 1) % trace.len();
                    let (xs, ys) = actuators(black_box(trace[k].0), trace[k].1);
                    let mut s = 0.0f32;
                    for i in (0..64).step_by(4) {
                        let x4 = [xs[i], xs[i + 1], xs[i + 2], xs[i + 3]];
                        let y4 = [ys[i], ys[i + 1], ys[i + 2], ys[i + 3]];
                        let (v, g) = (bv.coverage4(x4, y4), bg.coverage4(x4, y4));
                        s += v[0] + v[1] + v[2] + v[3] + g[0] + g[1] + g[2] + g[3];
                    }
                    black_box(s)
                })
            },
        );
    }
    let mut k = 0usize;
    c.bench_function(
        &format!("coverage 64 x (vibration + grating), {scene} trace: (a) field, SPEC reference coverage_at"),
        |b| {
            b.iter(|| {
                k = (k + 1) % trace.len();
                let (xs, ys) = actuators(black_box(trace[k].0), trace[k].1);
                let mut s = 0.0f32;
                for i in 0..64 {
                    s += vib.layer.coverage_at(xs[i], ys[i]) + gr.layer.coverage_at(xs[i], ys[i]);
                }
                black_box(s)
            })
        },
    );
    // The runtime's production (a) frame of the same two layers.
    let profile = profiles::builtin("stress2").expect("built-in profile");
    let mut bundle = Bundle::new(taxel_format::Manifest::new(profile));
    bundle.chunks = vec![Chunk::Distance(vib.layer.clone()), Chunk::Distance(gr.layer.clone())];
    let bytes = bundle.to_bytes().expect("bundle");
    let view = BundleView::parse(&bytes).expect("parse");
    let player = LateroPlayer::new(&view).expect("player");
    let mut out = [0u16; 64];
    let mut tick = 0u64;
    c.bench_function(
        &format!("runtime frame 64 x (vibration + grating), {scene} trace: (a) field, production kernel"),
        |b| {
            b.iter(|| {
                tick += 1;
                let (x, y) = trace[tick as usize % trace.len()];
                black_box(player.frame(Tick(tick), Mm(black_box(x)), Mm(y), &mut out))
            })
        },
    );
}

criterion_group!(benches, timings);

fn main() {
    if std::env::var("TAXEL_VECTOR_FIGURES").map_or(true, |v| v != "0") {
        figures();
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
