//! Generated drawings shaped like the ones teachers have (issue 14): an
//! Inkscape country map with many layers, non-ASCII layer names, touching
//! regions, towns and labels; an OpenStreetMap-like city plan of many ways;
//! a chart as matplotlib exports it (glyph `<use>` text, markers, clip paths);
//! the shapes of issue 46 (`world.rs`): thousands of tiny islands, states
//! with long shared coasts, long ways crossing each other.
//! Shared by the compiler's benchmarks and tests (`#[path]`-included), so
//! what is measured is what is tested. Deterministic: the same arguments give
//! the same text.
#![allow(dead_code)]

use std::fmt::Write as _;

mod world;
#[allow(unused_imports)]
pub use world::{archipelago, subway_plan, world_states};

/// A small deterministic generator (SplitMix64), so drawings need no dependency.
pub struct Rng(u64);

impl Rng {
    /// Seeded.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }
    /// Uniform in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

/// Layer labels as Inkscape users write them, in several scripts.
pub const LAYER_NAMES: [&str; 6] =
    ["Calque élévation", "レイヤー 1", "Région Île-de-France", "Höhenlinien", "Территория", "Ελλάδα"];

/// Fill colours of a political map: seven, so every cell's eight neighbours differ.
pub const MAP_FILLS: [&str; 7] = ["#e5d8bd", "#fbb4ae", "#b3cde3", "#ccebc5", "#decbe4", "#fed9a6", "#ffffcc"];

/// The grid a map of `n` regions is laid on: (columns, rows).
pub fn map_grid(n: usize) -> (usize, usize) {
    let cols = ((n as f64 * 1.2).sqrt().ceil() as usize).max(1);
    (cols, n.div_ceil(cols).max(1))
}

/// Map geometry in user units: the jittered grid vertices and, per region,
/// its outline (every edge subdivided into `detail` points, shared exactly
/// with the neighbour across it).
pub struct MapGeometry {
    /// Columns and rows of cells.
    pub cols: usize,
    /// Rows.
    pub rows: usize,
    /// The outline of each region (closed polygon), in user units.
    pub cells: Vec<Vec<(f64, f64)>>,
    /// The grid cell `(i, j)` of each region.
    pub at: Vec<(usize, usize)>,
    /// User units across and down.
    pub size: (f64, f64),
}

/// The geometry of a map of `n` touching regions.
pub fn map_geometry(n: usize, detail: usize, seed: u64) -> MapGeometry {
    let (cols, rows) = map_grid(n);
    let cell = 100.0;
    let size = (cols as f64 * cell + 200.0, rows as f64 * cell + 200.0);
    let mut rng = Rng::new(seed);
    let mut vx = vec![(0.0, 0.0); (cols + 1) * (rows + 1)];
    for j in 0..=rows {
        for i in 0..=cols {
            let edge = i == 0 || j == 0 || i == cols || j == rows;
            let (dx, dy) = if edge { (0.0, 0.0) } else { (rng.range(-25.0, 25.0), rng.range(-25.0, 25.0)) };
            vx[j * (cols + 1) + i] = (100.0 + i as f64 * cell + dx, 100.0 + j as f64 * cell + dy);
        }
    }
    let v = |i: usize, j: usize| j * (cols + 1) + i;
    // The points strictly between vertices a and b, from a to b; the same for (b, a) reversed.
    let edge = |a: usize, b: usize| -> Vec<(f64, f64)> {
        let (lo, hi) = (a.min(b), a.max(b));
        let mut r = Rng::new(seed ^ ((lo as u64) << 32 | hi as u64).wrapping_mul(0x2545_F491_4F6C_DD1D));
        let (p, q) = (vx[lo], vx[hi]);
        let (nx, ny) = (-(q.1 - p.1), q.0 - p.0);
        let len = nx.hypot(ny).max(1e-9);
        let mut pts: Vec<(f64, f64)> = (1..detail)
            .map(|k| {
                let t = k as f64 / detail as f64;
                let wob = r.range(-4.0, 4.0) * (std::f64::consts::PI * t).sin();
                (p.0 + t * (q.0 - p.0) + wob * nx / len, p.1 + t * (q.1 - p.1) + wob * ny / len)
            })
            .collect();
        if a > b {
            pts.reverse();
        }
        pts
    };
    let mut cells = Vec::with_capacity(n);
    let mut at = Vec::with_capacity(n);
    'grid: for j in 0..rows {
        for i in 0..cols {
            if cells.len() == n {
                break 'grid;
            }
            let corners = [v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)];
            let mut poly = Vec::with_capacity(4 * detail);
            for k in 0..4 {
                let (a, b) = (corners[k], corners[(k + 1) % 4]);
                poly.push(vx[a]);
                poly.extend(edge(a, b));
            }
            cells.push(poly);
            at.push((i, j));
        }
    }
    MapGeometry { cols, rows, cells, at, size }
}

fn path_d(s: &mut String, poly: &[(f64, f64)]) {
    for (k, p) in poly.iter().enumerate() {
        let _ = write!(s, "{}{:.2},{:.2} ", if k == 0 { "M " } else { "L " }, p.0, p.1);
    }
    s.push('Z');
}

/// An Inkscape map of `n` touching regions (fills from [`MAP_FILLS`], white
/// borders), spread over Inkscape layers with non-ASCII labels, a sea
/// background, a label per region, a town (small circle) in every fifth, on a
/// 529 x 508 mm page scaled to fit. `detail` points per region edge.
pub fn inkscape_map(n: usize, detail: usize, seed: u64) -> String {
    let g = map_geometry(n, detail, seed);
    let (w, h) = g.size;
    let mut s = String::with_capacity(n * detail * 4 * 16 + 4096);
    let _ = write!(
        s,
        r##"<?xml version="1.0" encoding="UTF-8" standalone="no"?>
<!-- Created with Inkscape (http://www.inkscape.org/) -->
<svg width="529mm" height="{:.3}mm" viewBox="0 0 {w} {h}" version="1.1" id="svg1"
   xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
   xmlns:sodipodi="http://sodipodi.sourceforge.net/DTD/sodipodi-0.dtd"
   xmlns="http://www.w3.org/2000/svg" xmlns:svg="http://www.w3.org/2000/svg">
  <title id="title1">Régions: a generated map of {n} regions</title>
  <sodipodi:namedview id="namedview1" pagecolor="#ffffff" inkscape:document-units="mm"/>
  <g inkscape:groupmode="layer" id="layer-sea" inkscape:label="Mer">
    <rect id="sea" x="0" y="0" width="{w}" height="{h}" style="fill:#cfe8f5;stroke:none"/>
  </g>
"##,
        529.0 * h / w
    );
    let layers = LAYER_NAMES.len();
    let per = n.div_ceil(layers).max(1);
    for (l, chunk) in g.cells.chunks(per).enumerate() {
        let _ = writeln!(
            s,
            r##"  <g inkscape:groupmode="layer" id="layer{l}" inkscape:label="{} {}">"##,
            LAYER_NAMES[l % layers],
            l + 1
        );
        for (k, poly) in chunk.iter().enumerate() {
            let r = l * per + k;
            let (i, j) = g.at[r];
            let fill = MAP_FILLS[(i + 3 * j) % MAP_FILLS.len()];
            let _ = write!(
                s,
                r##"    <path id="region{r}" inkscape:label="Région {r}" style="fill:{fill};stroke:#ffffff;stroke-width:1.5" d=""##
            );
            path_d(&mut s, poly);
            s += "\"/>\n";
        }
        s += "  </g>\n";
    }
    s += "  <g inkscape:groupmode=\"layer\" id=\"layer-towns\" inkscape:label=\"Villes et étiquettes\">\n";
    for (r, poly) in g.cells.iter().enumerate() {
        let (cx, cy) = (
            poly.iter().map(|p| p.0).sum::<f64>() / poly.len() as f64,
            poly.iter().map(|p| p.1).sum::<f64>() / poly.len() as f64,
        );
        if r % 5 == 0 {
            let _ = writeln!(
                s,
                r##"    <circle id="town{r}" cx="{:.2}" cy="{:.2}" r="6" style="fill:#000000"/>"##,
                cx + 20.0,
                cy + 20.0
            );
        }
        let _ = writeln!(
            s,
            r##"    <text id="label{r}" x="{cx:.2}" y="{cy:.2}" style="font-size:14px;font-family:sans-serif;text-anchor:middle">R{r}</text>"##
        );
    }
    s += "  </g>\n</svg>\n";
    s
}

/// An OpenStreetMap-like city plan: `n` ways (streets as random-walk
/// polylines of 4 to 19 segments, classed like OSM highways), on a 400 mm
/// square page with a land background.
pub fn city_plan(n: usize, seed: u64) -> String {
    let mut rng = Rng::new(seed);
    let side = 4000.0;
    let mut s = String::with_capacity(n * 200 + 1024);
    let _ = write!(
        s,
        r##"<?xml version="1.0" encoding="UTF-8"?>
<svg xmlns="http://www.w3.org/2000/svg" width="400mm" height="400mm" viewBox="0 0 {side} {side}">
  <title>City plan: {n} ways</title>
  <rect id="land" width="{side}" height="{side}" fill="#f2efe9"/>
  <g id="ways" fill="none" stroke-linecap="round" stroke-linejoin="round">
"##
    );
    let classes = [
        ("residential", "#ffffff", 6.0),
        ("primary", "#fcd6a4", 10.0),
        ("footway", "#fa8072", 2.0),
        ("rail", "#707070", 3.0),
    ];
    for k in 0..n {
        let (class, colour, width) = classes[k % classes.len()];
        let (mut x, mut y) = (rng.range(0.0, side), rng.range(0.0, side));
        let mut a: f64 = rng.range(0.0, std::f64::consts::TAU);
        let segs = 4 + (rng.next() * 16.0) as usize;
        let _ = write!(
            s,
            r##"    <path id="way{k}" class="highway-{class}" stroke="{colour}" stroke-width="{width}" d="M {x:.1} {y:.1}"##
        );
        for _ in 0..segs {
            a += rng.range(-0.6, 0.6);
            let l = rng.range(20.0, 80.0);
            x = (x + l * a.cos()).clamp(0.0, side);
            y = (y + l * a.sin()).clamp(0.0, side);
            let _ = write!(s, " L {x:.1} {y:.1}");
        }
        s += "\"/>\n";
    }
    s += "  </g>\n</svg>\n";
    s
}

/// A glyph-like outline for a digit: a ring (outer and inner contour), as
/// fonts draw "0", in font units (1000 per em, y up as matplotlib writes them).
fn glyph(d: usize) -> String {
    let w = 300.0 + 20.0 * d as f64;
    format!(
        "M {w} 360 Q {w} 730 {h} 730 Q 40 730 40 360 Q 40 -10 {h} -10 Q {w} -10 {w} 360 Z M 120 360 Q 120 650 {h} 650 Q {i} 650 {i} 360 Q {i} 70 {h} 70 Q 120 70 120 360 Z",
        h = w / 2.0 + 20.0,
        i = w - 80.0
    )
}

/// A chart as matplotlib's SVG backend writes it: a white figure patch, axes
/// spines and ticks (`<use>` of tick marks), tick labels as glyph `<use>`s
/// (`<!-- 0.5 -->` comments, `scale(0.1 -0.1)`), `bars` filled bars in two
/// colours, a line with circle markers (`<use>` of a marker path), all
/// clipped to the axes.
pub fn matplotlib_chart(bars: usize) -> String {
    let (fw, fh) = (460.8, 345.6);
    let (ax, ay, aw, ah) = (57.6, 41.472, 357.12, 266.112);
    let mut s = String::new();
    let _ = write!(
        s,
        r##"<?xml version="1.0" encoding="utf-8" standalone="no"?>
<!DOCTYPE svg PUBLIC "-//W3C//DTD SVG 1.1//EN" "http://www.w3.org/Graphics/SVG/1.1/DTD/svg11.dtd">
<svg xmlns:xlink="http://www.w3.org/1999/xlink" width="{fw}pt" height="{fh}pt" viewBox="0 0 {fw} {fh}" xmlns="http://www.w3.org/2000/svg" version="1.1">
 <metadata>matplotlib</metadata>
 <defs>
  <style type="text/css">*{{stroke-linejoin: round; stroke-linecap: butt}}</style>
 </defs>
 <g id="figure_1">
  <g id="patch_1">
   <path d="M 0 {fh} L {fw} {fh} L {fw} 0 L 0 0 z" style="fill: #ffffff"/>
  </g>
  <g id="axes_1">
   <g id="patch_2">
    <path d="M {ax} {y1} L {x1} {y1} L {x1} {ay} L {ax} {ay} z" style="fill: #ffffff"/>
   </g>
"##,
        y1 = ay + ah,
        x1 = ax + aw
    );
    let bw = aw / (bars as f64 * 1.5 + 0.5);
    for b in 0..bars {
        let x = ax + bw * (0.5 + 1.5 * b as f64);
        let v = 0.2 + 0.7 * ((b * 37 % 11) as f64 / 10.0);
        let colour = if b % 2 == 0 { "#1f77b4" } else { "#ff7f0e" };
        let _ = writeln!(
            s,
            r##"   <g id="patch_{}"><path d="M {x:.3} {y1:.3} L {x2:.3} {y1:.3} L {x2:.3} {yt:.3} L {x:.3} {yt:.3} z" clip-path="url(#p0)" style="fill: {colour}"/></g>"##,
            b + 3,
            y1 = ay + ah,
            x2 = x + bw,
            yt = ay + ah - v * ah
        );
    }
    s += "   <g id=\"matplotlib.axis_1\">\n";
    s += "    <defs><path id=\"m_tick\" d=\"M 0 0 L 0 3.5\" style=\"stroke: #000000; stroke-width: 0.8\"/></defs>\n";
    let ticks = 6;
    for t in 0..ticks {
        let x = ax + aw * t as f64 / (ticks - 1) as f64;
        let _ = writeln!(
            s,
            r##"    <g id="xtick_{t}"><g id="line2d_{t}"><use xlink:href="#m_tick" x="{x:.3}" y="{:.3}" style="stroke: #000000; stroke-width: 0.8"/></g>
     <g id="text_{t}"><!-- {t} --><g transform="translate({:.3} {:.3}) scale(0.1 -0.1)"><use xlink:href="#DejaVuSans-3{t}"/></g></g></g>"##,
            ay + ah,
            x - 3.0,
            ay + ah + 14.0
        );
    }
    s += "   </g>\n";
    // The line with circle markers.
    let mut d = String::new();
    let pts: Vec<(f64, f64)> = (0..bars)
        .map(|b| (ax + bw * (1.0 + 1.5 * b as f64), ay + ah * (0.3 + 0.4 * ((b as f64) * 0.7).sin().abs())))
        .collect();
    for (k, p) in pts.iter().enumerate() {
        let _ = write!(d, "{} {:.3} {:.3} ", if k == 0 { "M" } else { "L" }, p.0, p.1);
    }
    let _ = writeln!(
        s,
        r##"   <g id="line2d_line"><path d="{d}" clip-path="url(#p0)" style="fill: none; stroke: #2ca02c; stroke-width: 1.5; stroke-linecap: square"/>
    <defs><path id="m_circle" d="M 0 3 C 0.796 3 1.559 2.684 2.121 2.121 C 2.684 1.559 3 0.796 3 0 C 3 -0.796 2.684 -1.559 2.121 -2.121 C 1.559 -2.684 0.796 -3 0 -3 C -0.796 -3 -1.559 -2.684 -2.121 -2.121 C -2.684 -1.559 -3 -0.796 -3 0 C -3 0.796 -2.684 1.559 -2.121 2.121 C -1.559 2.684 -0.796 3 0 3 z" style="stroke: #2ca02c"/></defs>
    <g clip-path="url(#p0)">"##
    );
    for p in &pts {
        let _ = writeln!(
            s,
            r##"     <use xlink:href="#m_circle" x="{:.3}" y="{:.3}" style="fill: #2ca02c; stroke: #2ca02c"/>"##,
            p.0, p.1
        );
    }
    s += "    </g>\n   </g>\n";
    let _ = write!(
        s,
        r##"   <g id="patch_spines"><path d="M {ax} {y1} L {ax} {ay}" style="fill: none; stroke: #000000; stroke-width: 0.8; stroke-linejoin: miter; stroke-linecap: square"/>
    <path d="M {ax} {y1} L {x1} {y1}" style="fill: none; stroke: #000000; stroke-width: 0.8; stroke-linejoin: miter; stroke-linecap: square"/></g>
   <g id="text_title"><!-- Rainfall --><g transform="translate(190 35) scale(0.14 -0.14)"><use xlink:href="#DejaVuSans-30"/><use xlink:href="#DejaVuSans-31" x="63"/></g></g>
  </g>
 </g>
 <defs>
  <clipPath id="p0"><rect x="{ax}" y="{ay}" width="{aw}" height="{ah}"/></clipPath>
"##,
        y1 = ay + ah,
        x1 = ax + aw
    );
    for dgt in 0..10 {
        let _ = writeln!(s, r##"  <path id="DejaVuSans-3{dgt}" d="{}" transform="scale(0.1)"/>"##, glyph(dgt));
    }
    s += " </defs>\n</svg>\n";
    s
}

// Drawings that ran away (issue 47): hand-drawn scribbles, noisy filled
// areas and dense scatter plots.

/// One filled path of `n` random segments across a `w` x `h` mm page, crossing
/// itself some n²/10 times; `attrs` are its other attributes.
pub fn scribble(n: usize, (w, h): (f64, f64), attrs: &str, seed: u64) -> String {
    let mut rng = Rng::new(seed);
    let mut d = format!("M{:.3},{:.3}", w / 2.0, h / 2.0);
    for _ in 0..n {
        d += &format!(" L{:.3},{:.3}", rng.next() * w, rng.next() * h);
    }
    d += " Z";
    plain_svg((w, h), &format!(r##"<path fill="#c33" {attrs} d="{d}"/>"##))
}

/// `n` filled circles of radius `r` mm scattered over the page (a scatter plot).
pub fn scatter(n: usize, r: f64, (w, h): (f64, f64), seed: u64) -> String {
    let mut rng = Rng::new(seed);
    let mut body = String::new();
    for _ in 0..n {
        body += &format!(r##"<circle cx="{:.2}" cy="{:.2}" r="{r}" fill="#36c"/>"##, rng.next() * w, rng.next() * h);
        body.push('\n');
    }
    plain_svg((w, h), &body)
}

/// One closed filled ring of `n` points, each jittered `jitter` mm in or out
/// from a circle of radius `radius` mm (a traced scan's noisy outline).
pub fn jittered_ring(n: usize, radius: f64, jitter: f64, (w, h): (f64, f64), seed: u64) -> String {
    let mut rng = Rng::new(seed);
    let mut d = String::new();
    for k in 0..n {
        let a = k as f64 / n as f64 * std::f64::consts::TAU;
        let r = radius + (rng.next() * 2.0 - 1.0) * jitter;
        d += &format!("{}{:.3},{:.3}", if k == 0 { "M" } else { " L" }, w / 2.0 + r * a.cos(), h / 2.0 + r * a.sin());
    }
    d += " Z";
    plain_svg((w, h), &format!(r##"<path fill="#3a3" d="{d}"/>"##))
}

fn plain_svg((w, h): (f64, f64), body: &str) -> String {
    format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}mm" height="{h}mm" viewBox="0 0 {w} {h}">
{body}
</svg>"#
    )
}

/// Seeds for the `svg` fuzz target (`fuzz/`), as (file name, drawing): each
/// class of drawing above at a size a fuzzer mutates in milliseconds, so
/// that it starts from real shapes (a self-crossing scribble, plain and
/// annotated, a scatter plot, a jittered ring, an Inkscape map, a city plan,
/// a matplotlib chart). `cargo run --example fuzz_seeds` writes them; the
/// compiler's tests compile each (`fuzzed.rs`).
pub fn fuzz_seeds() -> Vec<(&'static str, String)> {
    let page = (200.0, 150.0);
    let annotated = r##"stroke="#000" stroke-width="0.5" data-tactile="grating(); vibrate()""##;
    vec![
        ("scribble.svg", scribble(300, page, "", 1)),
        ("scribble-annotated.svg", scribble(200, page, annotated, 2)),
        ("scatter.svg", scatter(400, 0.6, page, 3)),
        ("ring.svg", jittered_ring(3_000, 50.0, 3.0, page, 4)),
        ("map.svg", inkscape_map(30, 4, 5)),
        ("city-plan.svg", city_plan(60, 6)),
        ("chart.svg", matplotlib_chart(6)),
    ]
}
