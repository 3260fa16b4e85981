//! Shared service: pictures of what will be felt, for every family but print (which draws its own sheet).
//!
//! Previews: a picture of what a reader will feel, drawn the way the STRESS²
//! paper drew its primitives (seed 000, Fig. 2): a noise texture where the
//! surface vibrates, stripes at the true wavelength and angle where it is
//! grated, raised-cosine discs for dots and braille, and for grid devices the
//! stroke paths with their virtual points. Everything sits over a faint copy
//! of the drawing (when there is one), with a 10 mm scale bar.
//!
//! The picture is drawn from the bundle alone, so `taxel preview BUNDLE`
//! shows exactly what was compiled.

mod backdrop;
mod overlay;
pub mod pins;

pub use backdrop::{drawing_picture, preview_compiled};

use rayon::prelude::*;
use resvg::tiny_skia::Pixmap;

use overlay::Overlay;
use taxel_format::{Bundle, Chunk, DistanceLayer, DotKind, DotTable, HeightField, MaskKind, MaskLayer, MaskSamples};

/// Pixels per millimetre of a preview.
pub const PREVIEW_PX_PER_MM: f64 = 8.0;
/// Margin around the surface, in millimetres (room for the scale bar).
const MARGIN_MM: f64 = 8.0;
/// Largest preview side in pixels (hostile bundles may claim huge extents).
const MAX_SIDE_PX: f64 = 8000.0;

/// An RGBA picture, 8 bits per channel, row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct Picture {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height * 4` bytes.
    pub rgba: Vec<u8>,
}

/// A faint copy of the drawing to draw under the layers.
pub struct Backdrop {
    /// The drawing rendered at `px_per_mm`, page origin at its top-left.
    pub pixmap: Pixmap,
}

struct Canvas {
    w: usize,
    h: usize,
    /// Page mm at pixel (0, 0).
    x0: f64,
    y0: f64,
    k: f64,
    rgb: Vec<[f32; 3]>,
}

impl Canvas {
    /// Blends `colour` over pixel `(i, j)` with opacity `a`.
    fn paint(&mut self, i: usize, j: usize, colour: [f32; 3], a: f64) {
        if i >= self.w || j >= self.h || a.is_nan() || a <= 0.0 {
            return;
        }
        blend(&mut self.rgb[j * self.w + i], colour, a);
    }

    /// The page position of pixel centre `(i, j)`.
    fn at(&self, i: usize, j: usize) -> (f64, f64) {
        (self.x0 + (i as f64 + 0.5) / self.k, self.y0 + (j as f64 + 0.5) / self.k)
    }

    /// Pixel range covering page x from `a` to `b`.
    fn cols(&self, a: f64, b: f64) -> core::ops::Range<usize> {
        let lo = ((a - self.x0) * self.k).floor().clamp(0.0, self.w as f64) as usize;
        let hi = ((b - self.x0) * self.k).ceil().clamp(0.0, self.w as f64) as usize;
        lo..hi
    }

    fn rows(&self, a: f64, b: f64) -> core::ops::Range<usize> {
        let lo = ((a - self.y0) * self.k).floor().clamp(0.0, self.h as f64) as usize;
        let hi = ((b - self.y0) * self.k).ceil().clamp(0.0, self.h as f64) as usize;
        lo..hi
    }
}

const VIBRATION: [f32; 3] = [0.75, 0.1, 0.1];
const GRATING: [f32; 3] = [0.1, 0.25, 0.7];
const DOTS: [f32; 3] = [0.05, 0.05, 0.05];
const BRAILLE: [f32; 3] = [0.2, 0.45, 0.1];
const HEIGHT: [f32; 3] = [0.35, 0.25, 0.1];

/// Bilinear mask value in 0..=1 at page `(x, y)`, as a player reads it.
fn mask_value(m: &MaskLayer, x: f64, y: f64) -> f64 {
    let px = m.px_per_mm as f64;
    let fx = (x - m.origin_x.0 as f64) * px - 0.5;
    let fy = (y - m.origin_y.0 as f64) * px - 0.5;
    let (i0, j0) = (fx.floor(), fy.floor());
    let (tx, ty) = (fx - i0, fy - j0);
    let get = |i: f64, j: f64| -> f64 {
        if i < 0.0 || j < 0.0 || i >= m.width as f64 || j >= m.height as f64 {
            return 0.0;
        }
        let k = j as usize * m.width as usize + i as usize;
        match &m.samples {
            MaskSamples::U8(v) => v.get(k).map_or(0.0, |&s| s as f64 / 255.0),
            MaskSamples::U16(v) => v.get(k).map_or(0.0, |&s| s as f64 / 65535.0),
        }
    };
    let a = get(i0, j0) * (1.0 - tx) + get(i0 + 1.0, j0) * tx;
    let b = get(i0, j0 + 1.0) * (1.0 - tx) + get(i0 + 1.0, j0 + 1.0) * tx;
    a * (1.0 - ty) + b * ty
}

/// Deterministic noise in 0..1 for a pixel (a small integer hash).
fn noise(i: usize, j: usize) -> f64 {
    let mut h = (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ (j as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
    h ^= h >> 29;
    h = h.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h ^= h >> 32;
    (h & 0xFFFF) as f64 / 65535.0
}

fn draw_mask(c: &mut Canvas, m: &MaskLayer) {
    let px = m.px_per_mm as f64;
    let (x0, y0) = (m.origin_x.0 as f64, m.origin_y.0 as f64);
    let (x1, y1) = (x0 + m.width as f64 / px, y0 + m.height as f64 / px);
    draw_layer(c, m.kind, m.amplitude as f64, (x0, y0, x1, y1), |x, y| mask_value(m, x, y));
}

/// A distance layer: its edge profile at each preview pixel.
fn draw_distance(c: &mut Canvas, d: &DistanceLayer) {
    let (x0, y0) = (d.origin_x.0 as f64, d.origin_y.0 as f64);
    let span = 8.0 * d.pitch_mm as f64;
    let (x1, y1) = (x0 + d.tile_cols as f64 * span, y0 + d.tile_rows as f64 * span);
    draw_layer(c, d.kind, d.amplitude as f64, (x0, y0, x1, y1), |x, y| d.coverage_at(x as f32, y as f32) as f64);
}

fn draw_layer(
    c: &mut Canvas,
    kind: MaskKind,
    amp: f64,
    b: (f64, f64, f64, f64),
    value: impl Fn(f64, f64) -> f64 + Sync,
) {
    let (rows, cols) = (c.rows(b.1, b.3), c.cols(b.0, b.2));
    let (w, x0, y0, k) = (c.w, c.x0, c.y0, c.k);
    let Some(band) = c.rgb.get_mut(rows.start * w..rows.end * w) else { return };
    // Row by row on every core: a large map's layers are most of a
    // rebuild's preview (each pixel samples the layer as a player does).
    band.par_chunks_mut(w.max(1)).enumerate().for_each(|(n, row)| {
        let j = rows.start + n;
        let y = y0 + (j as f64 + 0.5) / k;
        for i in cols.clone() {
            let x = x0 + (i as f64 + 0.5) / k;
            let v = value(x, y) * amp;
            if v <= 0.0 {
                continue;
            }
            let a = match kind {
                // Seed 000 drew vibration as a noise texture.
                MaskKind::Vibration { .. } => v * (0.25 + 0.75 * noise(i, j)),
                // Eq. 3 with the page's y axis flipped, so angles are counter-clockwise as seen.
                MaskKind::Grating { wavelength, angle_deg } => {
                    let t = (angle_deg as f64).to_radians();
                    let d = -y * t.cos() - x * t.sin();
                    let delta = 0.5 + 0.5 * (2.0 * core::f64::consts::PI * d / wavelength.0 as f64).cos();
                    v * (0.1 + 0.9 * delta)
                }
            };
            let colour = if matches!(kind, MaskKind::Vibration { .. }) { VIBRATION } else { GRATING };
            if let Some(p) = row.get_mut(i)
                && !a.is_nan()
                && a > 0.0
            {
                blend(p, colour, a);
            }
        }
    });
}

/// Blends `colour` over pixel `p` with opacity `a` (in `(0, 1]`; more is 1).
fn blend(p: &mut [f32; 3], colour: [f32; 3], a: f64) {
    let a = a.min(1.0) as f32;
    for c in 0..3 {
        p[c] = p[c] * (1.0 - a) + colour[c] * a;
    }
}

/// Seed 000 eq. 1: the dot's deflection profile, plateau P = 0.25.
pub(crate) fn dot_profile(r: f64) -> f64 {
    const P: f64 = 0.25;
    if r <= P {
        1.0
    } else if r <= 1.0 {
        0.5 + 0.5 * (core::f64::consts::PI * (r - P) / (1.0 - P)).cos()
    } else {
        0.0
    }
}

fn draw_dots(c: &mut Canvas, t: &DotTable) {
    let colour = if t.kind == DotKind::Braille { BRAILLE } else { DOTS };
    for d in &t.dots {
        let (x, y, r) = (d.x.0 as f64, d.y.0 as f64, d.radius.0 as f64);
        if r.is_nan() || r <= 0.0 {
            continue;
        }
        for j in c.rows(y - r, y + r) {
            for i in c.cols(x - r, x + r) {
                let (px, py) = c.at(i, j);
                let rel = ((px - x).powi(2) + (py - y).powi(2)).sqrt() / r;
                c.paint(i, j, colour, dot_profile(rel) * d.amplitude as f64);
            }
        }
    }
}

/// A height field: each preview pixel takes its nearest node's height, so
/// that nodes finer than a pixel blend into no pattern (painting node by
/// node blended some pixels twice: a moiré over the whole field).
fn draw_height(c: &mut Canvas, f: &HeightField) {
    let cell = f.cell.0 as f64;
    let max = f.heights.iter().fold(0.0f32, |m, h| m.max(h.abs())) as f64;
    if cell.is_nan() || cell <= 0.0 || max.is_nan() || max <= 0.0 || f.cols == 0 || f.rows == 0 {
        return;
    }
    let (x0, y0) = (f.origin_x.0 as f64, f.origin_y.0 as f64);
    let (last_q, last_r) = (f.cols as usize - 1, f.rows as usize - 1);
    let node = |v: f64, last: usize| (v.round().max(0.0) as usize).min(last);
    for j in c.rows(y0 - cell / 2.0, y0 + (last_r as f64 + 0.5) * cell) {
        for i in c.cols(x0 - cell / 2.0, x0 + (last_q as f64 + 0.5) * cell) {
            let (x, y) = c.at(i, j);
            let (q, r) = (node((x - x0) / cell, last_q), node((y - y0) / cell, last_r));
            let h = f.heights.get(r * f.cols as usize + q).copied().unwrap_or(0.0) as f64;
            c.paint(i, j, HEIGHT, 0.8 * h.abs() / max);
        }
    }
}

/// 3 x 5 pixel glyphs for the scale bar's label ("0"-"9", "m", " ").
/// Millimetres from one line of the key to the next under the picture.
const KEY_LINE_MM: f64 = 4.0;

/// The key as the bundle's provenance holds it, a line each: "Key", then
/// each texture, line style and symbol with its meaning (entries `key.*`,
/// `texture: Forest (grating 3 mm at 0°)`), then each key code and the label
/// it stands for (entry `key`, `key: bs Bundle Store, kf 1 kHz frames`),
/// then the texts the graphic has no room for (entry `key.text`).
fn key_lines(b: &Bundle) -> Vec<String> {
    let Some(p) = b.chunks.iter().find_map(|c| match c {
        Chunk::Provenance(p) => Some(p),
        _ => None,
    }) else {
        return Vec::new();
    };
    let mut lines: Vec<String> = p
        .entries
        .iter()
        .filter_map(|e| crate::style::legend::kind_of_id(&e.id).map(|kind| format!("{kind}: {}", e.label)))
        .collect();
    let codes = p.entries.iter().find(|e| e.id == "key").map(|e| e.label.as_str());
    if let Some(codes) = codes.map(|k| k.strip_prefix("key: ").unwrap_or(k)).filter(|k| !k.is_empty()) {
        lines.extend(codes.split(", ").map(String::from));
    }
    // The texts the graphic has no room for (entry `key.text`, all of them
    // joined by ", "), a few to a line as the key prints them: one line of
    // thousands of labels ran off the picture.
    if let Some(e) = p.entries.iter().find(|e| e.id == crate::style::legend::UNPLACED_ID) {
        let texts: Vec<&str> = e.label.split(", ").collect();
        lines.extend(crate::style::legend::unplaced_lines(&texts));
    }
    if lines.is_empty() {
        return lines;
    }
    std::iter::once("Key".to_string()).chain(lines).collect()
}

/// The page extent a bundle covers: the device surface and every layer.
fn extent(b: &Bundle) -> (f64, f64, f64, f64) {
    let p = &b.manifest.profile;
    let mut e = (0.0f64, 0.0f64, p.surface_w_mm as f64, p.surface_h_mm as f64);
    // Room for the key under the scale bar (added to the bottom after the layers, below).
    let key = key_lines(b).len() as f64 * KEY_LINE_MM;
    let mut grow = |x0: f64, y0: f64, x1: f64, y1: f64| {
        if [x0, y0, x1, y1].iter().all(|v| v.is_finite()) {
            e = (e.0.min(x0), e.1.min(y0), e.2.max(x1), e.3.max(y1));
        }
    };
    for c in &b.chunks {
        match c {
            Chunk::Mask(m) => {
                let px = m.px_per_mm as f64;
                let (x, y) = (m.origin_x.0 as f64, m.origin_y.0 as f64);
                grow(x, y, x + m.width as f64 / px, y + m.height as f64 / px);
            }
            Chunk::Distance(d) => {
                let (x, y) = (d.origin_x.0 as f64, d.origin_y.0 as f64);
                let span = 8.0 * d.pitch_mm as f64;
                grow(x, y, x + d.tile_cols as f64 * span, y + d.tile_rows as f64 * span);
            }
            Chunk::Dots(t) => {
                for d in &t.dots {
                    let r = d.radius.0 as f64;
                    grow(d.x.0 as f64 - r, d.y.0 as f64 - r, d.x.0 as f64 + r, d.y.0 as f64 + r);
                }
            }
            _ => {}
        }
    }
    (e.0, e.1, e.2, e.3 + key)
}

/// Draws a bundle, optionally over a faint backdrop rendered at [`PREVIEW_PX_PER_MM`].
pub fn render_bundle(bundle: &Bundle, backdrop: Option<&Backdrop>) -> Picture {
    // A pin display is drawn pin by pin, as the reader meets it.
    if let Some(image) = bundle.pin_image() {
        return pins::render(image, &bundle.manifest.profile);
    }
    let (ex0, ey0, ex1, ey1) = extent(bundle);
    let (x0, y0, k, wmm, hmm) = layout((ex0, ey0, ex1, ey1));
    let (w, h) = ((wmm * k).ceil().max(1.0) as usize, (hmm * k).ceil().max(1.0) as usize);
    let mut c = Canvas { w, h, x0, y0, k, rgb: vec![[1.0; 3]; w * h] };
    // The device's surface, lightly shaded, so the reachable area is visible.
    let p = bundle.manifest.profile;
    for j in c.rows(0.0, p.surface_h_mm as f64) {
        for i in c.cols(0.0, p.surface_w_mm as f64) {
            c.paint(i, j, [0.9, 0.9, 0.88], 1.0);
        }
    }
    if let Some(b) = backdrop.filter(|_| (k - PREVIEW_PX_PER_MM).abs() < 1e-9) {
        let off_i = ((0.0 - c.x0) * k).round() as usize;
        let off_j = ((0.0 - c.y0) * k).round() as usize;
        for (n, px) in b.pixmap.pixels().iter().enumerate() {
            let (bi, bj) = (n % b.pixmap.width() as usize, n / b.pixmap.width() as usize);
            let a = px.alpha() as f64 / 255.0;
            if a > 0.0 {
                let col = px.demultiply();
                let rgb = [col.red() as f32 / 255.0, col.green() as f32 / 255.0, col.blue() as f32 / 255.0];
                c.paint(bi + off_i, bj + off_j, rgb, 0.3 * a);
            }
        }
    }
    for ch in &bundle.chunks {
        match ch {
            Chunk::Height(f) => draw_height(&mut c, f),
            Chunk::Mask(m) => draw_mask(&mut c, m),
            Chunk::Distance(d) => draw_distance(&mut c, d),
            _ => {}
        }
    }
    for ch in &bundle.chunks {
        if let Chunk::Dots(t) = ch {
            draw_dots(&mut c, t);
        }
    }
    // Lines, discs and text are drawn by tiny-skia over the fields above.
    if let Some(mut over) = Overlay::new(&c) {
        for ch in &bundle.chunks {
            if let Chunk::Strokes(t) = ch {
                over.strokes(t);
            }
        }
        // (The extent holds the key's lines under the drawing: the bar goes above them.)
        let key = key_lines(bundle);
        let bar_y = ey1 - key.len() as f64 * KEY_LINE_MM + MARGIN_MM - 3.0;
        over.scale_bar(ex0 - MARGIN_MM + 2.0, bar_y);
        for (n, line) in key.iter().enumerate() {
            over.text(line, (ex0 - MARGIN_MM + 2.0, bar_y + (n + 1) as f64 * KEY_LINE_MM), 2.8);
        }
        over.onto(&mut c);
    }
    let rgba = c
        .rgb
        .iter()
        .flat_map(|p| [p[0], p[1], p[2]].map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8).into_iter().chain([255]))
        .collect();
    Picture { width: w as u32, height: h as u32, rgba }
}

/// Where [`render_bundle`]'s picture of `bundle` lies on the page: the page
/// position in mm of its pixel (0, 0) and its pixels per mm, so that a
/// caller can draw over it; `None` for a pin display (drawn pin by pin).
pub fn bundle_frame(bundle: &Bundle) -> Option<(f64, f64, f64)> {
    if bundle.pin_image().is_some() {
        return None;
    }
    let (x0, y0, k, _, _) = layout(extent(bundle));
    Some((x0, y0, k))
}

/// A preview's page mm at pixel (0, 0), its pixels per mm, and its size in
/// mm, for the page extent `(x0, y0, x1, y1)`: the extent and a margin, at
/// [`PREVIEW_PX_PER_MM`] unless that makes a side longer than [`MAX_SIDE_PX`].
fn layout((ex0, ey0, ex1, ey1): (f64, f64, f64, f64)) -> (f64, f64, f64, f64, f64) {
    let (wmm, hmm) = (ex1 - ex0 + 2.0 * MARGIN_MM, ey1 - ey0 + 2.0 * MARGIN_MM);
    let k = if wmm.max(hmm) * PREVIEW_PX_PER_MM > MAX_SIDE_PX { MAX_SIDE_PX / wmm.max(hmm) } else { PREVIEW_PX_PER_MM };
    (ex0 - MARGIN_MM, ey0 - MARGIN_MM, k, wmm, hmm)
}

#[cfg(test)]
mod tests {
    use super::*;
    use taxel_format::Mm;

    #[test]
    fn the_key_names_each_texture_line_and_symbol_before_its_codes() {
        let mut b = Bundle::new(taxel_format::Manifest::new(taxel_format::profiles::builtin("stress2").unwrap()));
        let plain = render_bundle(&b, None);
        let entry =
            |id: &str, label: &str| taxel_format::ProvenanceEntry { id: id.into(), label: label.into(), line: 0 };
        let entries = vec![
            entry("a", "a"),
            entry("key", "key: cr Check rules"),
            entry("key.texture", "Forest (grating 3 mm at 0°)"),
            entry("key.line", "Road (vibrating line 1.5 mm, 50 Hz)"),
            entry("key.symbol", "Town (dot of 2 mm)"),
            // An id that merely starts alike is not the key's.
            entry("key.other", "not a key entry"),
        ];
        b.chunks.push(Chunk::Provenance(taxel_format::Provenance { entries }));
        assert_eq!(
            key_lines(&b),
            [
                "Key",
                "texture: Forest (grating 3 mm at 0°)",
                "line: Road (vibrating line 1.5 mm, 50 Hz)",
                "symbol: Town (dot of 2 mm)",
                "cr Check rules"
            ]
        );
        let keyed = render_bundle(&b, None);
        let k = PREVIEW_PX_PER_MM;
        assert_eq!(keyed.height, plain.height + (5.0 * KEY_LINE_MM * k).ceil() as u32);
    }

    /// A map's hundred labels with no room on the graphic are listed as the
    /// key prints them, eight to a line and then how many more, not on one
    /// line that runs off the picture.
    #[test]
    fn the_texts_with_no_room_are_listed_a_few_to_a_line() {
        let mut b = Bundle::new(taxel_format::Manifest::new(taxel_format::profiles::builtin("stress2").unwrap()));
        let label = (0..100).map(|k| format!("R{k}")).collect::<Vec<_>>().join(", ");
        let entry = taxel_format::ProvenanceEntry { id: crate::style::legend::UNPLACED_ID.into(), label, line: 0 };
        b.chunks.push(Chunk::Provenance(taxel_format::Provenance { entries: vec![entry] }));
        let lines = key_lines(&b);
        assert_eq!(lines.len(), 1 + 8 + 1, "{lines:?}");
        assert_eq!(lines[1], "not on the graphic: R0, R1, R2, R3, R4, R5, R6, R7");
        assert_eq!(lines[2], "R8, R9, R10, R11, R12, R13, R14, R15");
        assert_eq!(lines[9], "and 36 more not on the graphic");
    }

    #[test]
    fn the_key_of_a_bundle_is_listed_under_its_picture() {
        let mut b = Bundle::new(taxel_format::Manifest::new(taxel_format::profiles::builtin("stress2").unwrap()));
        let plain = render_bundle(&b, None);
        let entry =
            |id: &str, label: &str| taxel_format::ProvenanceEntry { id: id.into(), label: label.into(), line: 0 };
        let entries = vec![entry("a", "a"), entry("key", "key: cr Check rules, eb Emit bundle")];
        b.chunks.push(Chunk::Provenance(taxel_format::Provenance { entries }));
        let keyed = render_bundle(&b, None);
        // A title and two codes: three lines more, the picture otherwise the same.
        let k = PREVIEW_PX_PER_MM;
        assert_eq!(keyed.width, plain.width);
        assert_eq!(keyed.height, plain.height + (3.0 * KEY_LINE_MM * k).ceil() as u32, "{}", plain.height);
        let row = |p: &Picture, j: u32| p.rgba[(j * p.width * 4) as usize..((j + 1) * p.width * 4) as usize].to_vec();
        // The scale bar's line is 3 mm above the plain picture's bottom; the key's lines are 4 mm apart under it.
        let bar = plain.height as f64 - 3.0 * k;
        assert!((0..(bar + k) as u32).all(|j| row(&plain, j) == row(&keyed, j)));
        for line in 1..=3 {
            let baseline = bar + line as f64 * KEY_LINE_MM * k;
            let ink = |j: u32| row(&keyed, j).chunks(4).any(|px| px[0] < 128);
            assert!(((baseline - 2.0 * k) as u32..baseline as u32).any(ink), "line {line}");
            assert!(!((baseline + 0.9 * k) as u32..(baseline + 1.9 * k) as u32).any(ink), "between lines {line}");
        }
    }

    #[test]
    fn a_height_field_of_one_height_paints_one_colour_at_any_node_spacing() {
        // Nodes finer than a pixel, about a pixel, and coarser: every pixel
        // whose centre is on the field is painted once, with the same colour
        // (painting node squares blended pixels under two nodes twice).
        for cell in [0.0713f32, 0.13, 1.37] {
            let n = (20.0 / cell) as u32;
            let nodes = (n * n) as usize;
            let f = HeightField {
                source: None,
                cols: n,
                rows: n,
                origin_x: Mm(3.1),
                origin_y: Mm(2.7),
                cell: Mm(cell),
                gradient_cap: 1.0,
                heights: vec![5.0; nodes],
                grad_x: vec![0.0; nodes],
                grad_y: vec![0.0; nodes],
                flags: vec![0; nodes],
                encoding: taxel_format::HeightEncoding::Float,
            };
            let (w, h) = (240, 240);
            let k = PREVIEW_PX_PER_MM;
            let mut c = Canvas { w, h, x0: 0.0, y0: 0.0, k, rgb: vec![[1.0; 3]; w * h] };
            draw_height(&mut c, &f);
            let end = |o: f32| (o + (n - 1) as f32 * cell) as f64;
            let mut seen = std::collections::BTreeSet::new();
            for j in 0..h {
                for i in 0..w {
                    let (x, y) = c.at(i, j);
                    let p = c.rgb[j * w + i];
                    if x > 3.1 + 0.01 && x < end(3.1) - 0.01 && y > 2.7 + 0.01 && y < end(2.7) - 0.01 {
                        seen.insert(p.map(f32::to_bits));
                    } else if x < 3.1 - cell as f64 || y < 2.7 - cell as f64 {
                        assert_eq!(p, [1.0; 3], "pixel ({i}, {j}) off the field, cell {cell}");
                    }
                }
            }
            assert_eq!(seen.len(), 1, "cell {cell} mm: {} colours on a field of one height", seen.len());
        }
    }

    #[test]
    fn dot_profile_matches_eq_1() {
        assert_eq!(dot_profile(0.0), 1.0);
        assert_eq!(dot_profile(0.25), 1.0);
        assert!((dot_profile(0.625) - 0.5).abs() < 1e-12);
        assert!(dot_profile(1.0).abs() < 1e-12);
        assert_eq!(dot_profile(1.5), 0.0);
    }
}
