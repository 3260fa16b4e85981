//! Generated drawings of the shapes issue 46 found slow on public files: a
//! world map of thousands of tiny islands beside a few landmasses, a world
//! map of a few hundred states with long shared wiggly coasts (Natural Earth
//! exports), and a subway plan of long ways crossing each other
//! (OpenStreetMap exports). Inkscape-like layers and groups, labels, stroke
//! widths and the colours maps use. Deterministic: the same arguments give
//! the same text.

use std::f64::consts::TAU;
use std::fmt::Write as _;

use super::{MAP_FILLS, Rng, map_geometry};

/// The Inkscape header of a `w` x `h` mm page whose user units are tenths of
/// a millimetre, with a sea background on a layer of its own.
fn inkscape_head(s: &mut String, title: &str, (w, h): (f64, f64), sea: &str) {
    let (uw, uh) = (w * 10.0, h * 10.0);
    let _ = write!(
        s,
        r##"<?xml version="1.0" encoding="UTF-8" standalone="no"?>
<!-- Created with Inkscape (http://www.inkscape.org/) -->
<svg width="{w}mm" height="{h}mm" viewBox="0 0 {uw} {uh}" version="1.1" id="svg1"
   xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
   xmlns:sodipodi="http://sodipodi.sourceforge.net/DTD/sodipodi-0.dtd"
   xmlns="http://www.w3.org/2000/svg" xmlns:svg="http://www.w3.org/2000/svg">
  <title id="title1">{title}</title>
  <sodipodi:namedview id="namedview1" pagecolor="#ffffff" inkscape:document-units="mm"/>
  <g inkscape:groupmode="layer" id="layer-ocean" inkscape:label="Ocean">
    <rect id="ocean" x="0" y="0" width="{uw}" height="{uh}" style="fill:{sea};stroke:none"/>
  </g>
"##
    );
}

/// A closed blob of `n` points around `(cx, cy)`: radius `r` modulated by a
/// few random harmonics (`rough` of the radius) and a little noise, as a
/// coastline is.
fn blob(rng: &mut Rng, (cx, cy): (f64, f64), r: f64, n: usize, rough: f64) -> Vec<(f64, f64)> {
    let harmonics: Vec<(f64, f64, f64)> =
        (2..7).map(|k| (k as f64, rng.range(0.0, rough) / k as f64 * 2.0, rng.range(0.0, TAU))).collect();
    (0..n)
        .map(|k| {
            let a = k as f64 / n as f64 * TAU;
            let mut rr = 1.0 + rng.range(-0.15, 0.15) * rough;
            for &(f, amp, ph) in &harmonics {
                rr += amp * (f * a + ph).sin();
            }
            let rr = r * rr.max(0.25);
            (cx + rr * a.cos(), cy + rr * a.sin())
        })
        .collect()
}

fn ring_d(s: &mut String, poly: &[(f64, f64)]) {
    for (k, p) in poly.iter().enumerate() {
        let _ = write!(s, "{}{:.2},{:.2} ", if k == 0 { "M " } else { "L " }, p.0, p.1);
    }
    s.push('Z');
}

fn graticule(s: &mut String, (uw, uh): (f64, f64), step: f64) {
    s.push_str(
        "  <g inkscape:groupmode=\"layer\" id=\"layer-graticule\" inkscape:label=\"Graticule\" style=\"fill:none;stroke:#7f7f7f;stroke-width:1;stroke-opacity:0.6\">\n",
    );
    let mut x = step;
    while x < uw {
        let _ = writeln!(s, r##"    <path id="meridian{:.0}" d="M {x:.1},0 V {uh:.1}"/>"##, x);
        x += step;
    }
    let mut y = step;
    while y < uh {
        let _ = writeln!(s, r##"    <path id="parallel{:.0}" d="M 0,{y:.1} H {uw:.1}"/>"##, y);
        y += step;
    }
    s.push_str("  </g>\n");
}

/// A world map as Natural Earth's 1:110m countries come out of Inkscape:
/// `big` landmasses (wiggly outlines of 400 points, a country each, labelled),
/// and `islands` tiny islands (5 to 12 points, 0.3 to 2.5 mm across) strung
/// in archipelagos along arcs, each its own path in a country's group, with a
/// thin dark coast; a graticule; labels for the landmasses and one island in
/// twenty. A 300 x 160 mm page.
pub fn archipelago(big: usize, islands: usize, seed: u64) -> String {
    let mut rng = Rng::new(seed);
    let (w, h) = (300.0, 160.0);
    let (uw, uh) = (w * 10.0, h * 10.0);
    let mut s = String::with_capacity(islands * 260 + big * 8_000 + 8_192);
    inkscape_head(&mut s, &format!("World: {big} landmasses, {islands} islands"), (w, h), "#aad3df");
    graticule(&mut s, (uw, uh), 200.0);
    s.push_str("  <g inkscape:groupmode=\"layer\" id=\"layer-land\" inkscape:label=\"Countries\">\n");
    let mut labels = Vec::new();
    for b in 0..big {
        let c = (rng.range(0.12, 0.88) * uw, rng.range(0.15, 0.85) * uh);
        let r = rng.range(0.05, 0.11) * uh;
        let poly = blob(&mut rng, c, r, 400, 0.5);
        let fill = MAP_FILLS[b % MAP_FILLS.len()];
        let _ = write!(
            s,
            r##"    <path id="country{b}" inkscape:label="Land {b}" style="fill:{fill};fill-opacity:1;stroke:#646464;stroke-width:1.2;stroke-linejoin:round" d=""##
        );
        ring_d(&mut s, &poly);
        s.push_str("\"/>\n");
        labels.push((c, format!("Land {b}"), 60.0));
    }
    // Archipelagos: chains of islands along arcs, each chain a country's group.
    let chains = (islands / 60).max(1);
    let mut made = 0;
    for ch in 0..chains {
        let per = (islands - made) / (chains - ch);
        let (mut x, mut y) = (rng.range(0.03, 0.97) * uw, rng.range(0.05, 0.95) * uh);
        let mut a = rng.range(0.0, TAU);
        let fill = MAP_FILLS[(ch * 3 + 1) % MAP_FILLS.len()];
        let _ = writeln!(
            s,
            r##"    <g id="archipelago{ch}" inkscape:label="Islands {ch}" style="fill:{fill};stroke:#646464;stroke-width:0.6">"##
        );
        for k in 0..per {
            a += rng.range(-0.35, 0.35);
            let step = rng.range(6.0, 30.0);
            x = (x + step * a.cos()).clamp(5.0, uw - 5.0);
            y = (y + step * a.sin()).clamp(5.0, uh - 5.0);
            let r = rng.range(1.5, 12.5);
            let pts = 5 + (rng.next() * 8.0) as usize;
            let poly = blob(&mut rng, (x, y), r, pts, 0.3);
            let id = made + k;
            let _ = write!(s, r##"      <path id="island{id}" d=""##);
            ring_d(&mut s, &poly);
            s.push_str("\"/>\n");
            if id % 20 == 0 {
                labels.push(((x + r + 4.0, y), format!("Isl. {id}"), 22.0));
            }
        }
        made += per;
        s.push_str("    </g>\n");
    }
    s.push_str("  </g>\n");
    labels_layer(&mut s, &labels);
    s.push_str("</svg>\n");
    s
}

fn labels_layer(s: &mut String, labels: &[((f64, f64), String, f64)]) {
    s.push_str(
        "  <g inkscape:groupmode=\"layer\" id=\"layer-labels\" inkscape:label=\"Labels\" style=\"font-family:sans-serif;fill:#1a1a1a\">\n",
    );
    for (k, ((x, y), text, size)) in labels.iter().enumerate() {
        let _ = writeln!(
            s,
            r##"    <text id="label{k}" x="{x:.1}" y="{y:.1}" style="font-size:{size}px;text-anchor:middle">{text}</text>"##
        );
    }
    s.push_str("  </g>\n");
}

/// A world map of states as Natural Earth's admin-1 layer comes out of
/// Inkscape: about `n` states on a few continents, each outline with `detail`
/// points per border (borders shared exactly between neighbours, wiggly as
/// a coast or a river is), states filled in map colours with a thin white
/// border, grouped by continent on layers of their own; a graticule and a
/// label per state. A 300 x 160 mm page.
pub fn world_states(n: usize, detail: usize, seed: u64) -> String {
    // A grid of about twice as many cells, of which the continents keep half.
    let g = map_geometry(n * 2, detail, seed);
    let (gw, gh) = g.size;
    let (w, h) = (300.0, 160.0);
    let (uw, uh) = (w * 10.0, h * 10.0);
    let (kx, ky) = (uw / gw, uh / gh);
    let mut rng = Rng::new(seed ^ 0x5eed);
    let continents: Vec<((f64, f64), f64)> = (0..4)
        .map(|_| ((rng.range(0.2, 0.8) * g.cols as f64, rng.range(0.25, 0.75) * g.rows as f64), rng.range(0.2, 0.32)))
        .collect();
    let mut s = String::with_capacity(n * detail * 4 * 16 + 8_192);
    inkscape_head(&mut s, &format!("States of the world: {n} states"), (w, h), "#aad3df");
    graticule(&mut s, (uw, uh), 200.0);
    let mut labels = Vec::new();
    let mut kept = 0;
    for (c, &(centre, radius)) in continents.iter().enumerate() {
        let _ = writeln!(s, r##"  <g inkscape:groupmode="layer" id="continent{c}" inkscape:label="Continent {c}">"##);
        for (r, poly) in g.cells.iter().enumerate() {
            let (i, j) = g.at[r];
            let (dx, dy) = ((i as f64 - centre.0) / g.cols as f64, (j as f64 - centre.1) / g.rows as f64);
            // Each cell belongs to the first continent that covers it.
            let covers = |&((cx, cy), rad): &((f64, f64), f64)| {
                let (ex, ey) = ((i as f64 - cx) / g.cols as f64, (j as f64 - cy) / g.rows as f64);
                ex.hypot(ey) < rad
            };
            if dx.hypot(dy) >= radius || continents.iter().position(covers) != Some(c) || kept >= n {
                continue;
            }
            kept += 1;
            let fill = MAP_FILLS[(i + 3 * j) % MAP_FILLS.len()];
            let _ = write!(
                s,
                r##"    <path id="state{r}" inkscape:label="State {r}" style="fill:{fill};stroke:#ffffff;stroke-width:0.8;stroke-linejoin:round" d=""##
            );
            let scaled: Vec<(f64, f64)> = poly.iter().map(|p| (p.0 * kx, p.1 * ky)).collect();
            ring_d(&mut s, &scaled);
            s.push_str("\"/>\n");
            let n = scaled.len() as f64;
            let centroid = (scaled.iter().map(|p| p.0).sum::<f64>() / n, scaled.iter().map(|p| p.1).sum::<f64>() / n);
            labels.push((centroid, format!("S{r}"), 16.0));
        }
        s.push_str("  </g>\n");
    }
    labels_layer(&mut s, &labels);
    s.push_str("</svg>\n");
    s
}

/// A subway plan as an OpenStreetMap export comes out: `lines` routes in
/// their operators' colours, each a long wiggly line across the page cut
/// into ways of 3 to 12 segments (as OSM cuts a route between junctions),
/// drawn with wide round-capped strokes over a grid of long streets (thin
/// grey ways crossing the whole page), a station (white circle with a dark
/// ring) and its name every few ways. `ways` ways in all, streets and route
/// pieces. A 250 x 250 mm page.
pub fn subway_plan(lines: usize, ways: usize, seed: u64) -> String {
    const COLOURS: [&str; 12] = [
        "#e3001b", "#0065ae", "#00963f", "#f6a800", "#9b3e96", "#00a7e1", "#a05a2c", "#ee7ea6", "#8d9d1f", "#f3cd00",
        "#65c3b6", "#6e6e6e",
    ];
    let mut rng = Rng::new(seed);
    let side = 2500.0;
    let mut s = String::with_capacity(ways * 400 + 8_192);
    let _ = write!(
        s,
        r##"<?xml version="1.0" encoding="UTF-8" standalone="no"?>
<svg width="250mm" height="250mm" viewBox="0 0 {side} {side}" version="1.1" id="svg1"
   xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
   xmlns="http://www.w3.org/2000/svg">
  <title id="title1">Subway plan: {lines} lines, {ways} ways</title>
  <rect id="background" width="{side}" height="{side}" style="fill:#f2efe9"/>
  <g inkscape:groupmode="layer" id="layer-streets" inkscape:label="Streets" style="fill:none;stroke:#c8c8c8;stroke-width:4;stroke-linecap:round;stroke-linejoin:round">
"##
    );
    // Each route's pieces: about half the ways, the streets the rest.
    let route_ways = (ways / 2).max(lines);
    let streets = ways.saturating_sub(route_ways);
    for k in 0..streets {
        // A long street from one edge to the opposite, gently bending.
        let horizontal = k % 2 == 0;
        let (mut x, mut y) = if horizontal { (0.0, rng.range(0.0, side)) } else { (rng.range(0.0, side), 0.0) };
        let mut a: f64 = if horizontal { 0.0 } else { TAU / 4.0 } + rng.range(-0.4, 0.4);
        let _ = write!(s, r##"    <path id="street{k}" class="highway-secondary" d="M {x:.1},{y:.1}"##);
        let segs = 10 + (rng.next() * 30.0) as usize;
        for _ in 0..segs {
            a += rng.range(-0.15, 0.15);
            let l = side / segs as f64 * rng.range(0.8, 1.3);
            x = (x + l * a.cos()).clamp(0.0, side);
            y = (y + l * a.sin()).clamp(0.0, side);
            let _ = write!(s, " L {x:.1},{y:.1}");
        }
        s.push_str("\"/>\n");
    }
    s.push_str("  </g>\n  <g inkscape:groupmode=\"layer\" id=\"layer-routes\" inkscape:label=\"Subway\">\n");
    let mut stations = Vec::new();
    let per_line = route_ways / lines;
    let mut way = 0;
    for l in 0..lines {
        let colour = COLOURS[l % COLOURS.len()];
        let _ = writeln!(
            s,
            r##"    <g id="route{l}" inkscape:label="Line {}" style="fill:none;stroke:{colour};stroke-width:9;stroke-linecap:round;stroke-linejoin:round">"##,
            l + 1
        );
        // From a point near one edge across the centre to the other side.
        let a0 = rng.range(0.0, TAU);
        let (mut x, mut y) = (side / 2.0 - 0.48 * side * a0.cos(), side / 2.0 - 0.48 * side * a0.sin());
        let mut a = a0 + rng.range(-0.3, 0.3);
        for p in 0..per_line {
            let _ = write!(s, r##"      <path id="way{way}" d="M {x:.1},{y:.1}"##);
            let segs = 3 + (rng.next() * 10.0) as usize;
            for _ in 0..segs {
                a += rng.range(-0.25, 0.25);
                let toward = (side / 2.0 - y).atan2(side / 2.0 - x);
                // Keep heading roughly across the page.
                if p < per_line / 2 {
                    a += 0.1 * (toward - a).sin();
                }
                let step = side * 0.9 / (per_line as f64 * 7.5);
                x = (x + step * a.cos()).clamp(10.0, side - 10.0);
                y = (y + step * a.sin()).clamp(10.0, side - 10.0);
                let _ = write!(s, " L {x:.1},{y:.1}");
            }
            s.push_str("\"/>\n");
            if p % 2 == 0 {
                stations.push((x, y, format!("Station {}-{p}", l + 1)));
            }
            way += 1;
        }
        s.push_str("    </g>\n");
    }
    s.push_str("  </g>\n  <g inkscape:groupmode=\"layer\" id=\"layer-stations\" inkscape:label=\"Stations\">\n");
    for (k, (x, y, name)) in stations.iter().enumerate() {
        let _ = writeln!(
            s,
            r##"    <circle id="station{k}" cx="{x:.1}" cy="{y:.1}" r="9" style="fill:#ffffff;stroke:#1a1a1a;stroke-width:3"/>
    <text id="name{k}" x="{:.1}" y="{:.1}" style="font-size:20px;font-family:sans-serif;fill:#1a1a1a">{name}</text>"##,
            x + 14.0,
            y + 6.0
        );
    }
    s.push_str("  </g>\n</svg>\n");
    s
}
