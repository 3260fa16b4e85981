//! What a preview draws as vectors over its fields: brushed strokes, the
//! scale bar and its label. Lines and discs are tiny-skia paths, anti-aliased;
//! the label is set in the bundled DejaVu Sans through ab_glyph (the glyph
//! rasteriser the report's plot uses), so no bitmap font is drawn by hand.

use ab_glyph::{Font, FontRef, ScaleFont};
use resvg::tiny_skia::{Color, FillRule, LineCap, Paint, PathBuilder, Pixmap, PremultipliedColorU8, Stroke, Transform};
use taxel_format::StrokeTable;

use super::Canvas;

/// DejaVu Sans (its licence: `assets/fonts/LICENSE-DejaVu.txt`), the font of
/// every picture taxel draws text on.
static FONT: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");

const STROKE: [f32; 3] = [0.55, 0.2, 0.6];
const BLACK: [f32; 3] = [0.0, 0.0, 0.0];

/// A transparent layer the size of the canvas, in page mm through the canvas' frame.
pub(super) struct Overlay {
    pixmap: Pixmap,
    /// Page mm to pixels.
    ts: Transform,
    /// Pixels per mm.
    k: f64,
    /// Page mm at pixel (0, 0).
    origin: (f64, f64),
}

fn paint(colour: [f32; 3], alpha: f64) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color(
        Color::from_rgba(colour[0], colour[1], colour[2], alpha.clamp(0.0, 1.0) as f32).unwrap_or(Color::BLACK),
    );
    p.anti_alias = true;
    p
}

impl Overlay {
    /// `None` when the canvas is too large for a pixmap (tiny-skia's limit).
    pub(super) fn new(c: &Canvas) -> Option<Overlay> {
        let pixmap = Pixmap::new(u32::try_from(c.w).ok()?, u32::try_from(c.h).ok()?)?;
        let k = c.k as f32;
        let ts = Transform::from_row(k, 0.0, 0.0, k, (-c.x0 * c.k) as f32, (-c.y0 * c.k) as f32);
        Some(Overlay { pixmap, ts, k: c.k, origin: (c.x0, c.y0) })
    }

    /// A line through `points` (page mm), `width` mm wide, round-capped.
    fn polyline(&mut self, points: &[(f64, f64)], width: f64, colour: [f32; 3], alpha: f64) {
        let mut pb = PathBuilder::new();
        let mut it = points.iter().filter(|p| p.0.is_finite() && p.1.is_finite());
        let Some(&(x, y)) = it.next() else { return };
        pb.move_to(x as f32, y as f32);
        for &(x, y) in it {
            pb.line_to(x as f32, y as f32);
        }
        let Some(path) = pb.finish() else { return };
        let stroke = Stroke { width: width as f32, line_cap: LineCap::Round, ..Stroke::default() };
        self.pixmap.stroke_path(&path, &paint(colour, alpha), &stroke, self.ts, None);
    }

    fn disc(&mut self, (x, y): (f64, f64), r: f64, colour: [f32; 3], alpha: f64) {
        if let Some(path) = PathBuilder::from_circle(x as f32, y as f32, r as f32) {
            self.pixmap.fill_path(&path, &paint(colour, alpha), FillRule::Winding, self.ts, None);
        }
    }

    /// A stroke table: each stroke's path through its virtual points, and the points.
    pub(super) fn strokes(&mut self, t: &StrokeTable) {
        for s in &t.strokes {
            let pts: Vec<(f64, f64)> = s.points.iter().map(|p| (p.x.0 as f64, p.y.0 as f64)).collect();
            self.polyline(&pts, 1.5, STROKE, 0.6);
            for &p in &pts {
                self.disc(p, 2.5, STROKE, 0.9);
            }
        }
    }

    /// A 10 mm scale bar with a tick every millimetre from page `(x, y)`, labelled "10 mm".
    pub(super) fn scale_bar(&mut self, x: f64, y: f64) {
        self.polyline(&[(x, y), (x + 10.0, y)], 0.5, BLACK, 1.0);
        for k in 0..=10 {
            let tick = if k % 5 == 0 { 1.5 } else { 0.8 };
            let xk = x + k as f64;
            self.polyline(&[(xk, y - tick), (xk, y)], 0.25, BLACK, 1.0);
        }
        self.text("10 mm", (x + 11.5, y), 2.8);
    }

    /// `text` in black with its baseline starting at page `at`, `size_mm` to the em.
    pub(super) fn text(&mut self, text: &str, at: (f64, f64), size_mm: f64) {
        let Ok(font) = FontRef::try_from_slice(FONT) else { return };
        let font = font.as_scaled((size_mm * self.k) as f32);
        let (w, h) = (self.pixmap.width() as i64, self.pixmap.height() as i64);
        let mut pen = ((at.0 - self.origin.0) * self.k) as f32;
        let baseline = ((at.1 - self.origin.1) * self.k) as f32;
        let mut last = None;
        for ch in text.chars() {
            let id = font.glyph_id(ch);
            if let Some(prev) = last {
                pen += font.kern(prev, id);
            }
            last = Some(id);
            let glyph = id.with_scale_and_position(font.scale(), ab_glyph::point(pen, baseline));
            pen += font.h_advance(id);
            let Some(outline) = font.outline_glyph(glyph) else { continue };
            let b = outline.px_bounds();
            let pixels = self.pixmap.pixels_mut();
            outline.draw(|gx, gy, coverage| {
                let (px, py) = (b.min.x as i64 + gx as i64, b.min.y as i64 + gy as i64);
                if (0..w).contains(&px) && (0..h).contains(&py) {
                    let p = &mut pixels[(py * w + px) as usize];
                    // Black: a premultiplied pixel is its alpha alone; glyphs overlap by the larger cover.
                    let a = ((coverage.clamp(0.0, 1.0) * 255.0).round() as u8).max(p.alpha());
                    *p = PremultipliedColorU8::from_rgba(0, 0, 0, a).unwrap_or(*p);
                }
            });
        }
    }

    /// Blends the layer over the canvas.
    pub(super) fn onto(self, c: &mut Canvas) {
        let w = self.pixmap.width() as usize;
        for (n, px) in self.pixmap.pixels().iter().enumerate() {
            if px.alpha() == 0 {
                continue;
            }
            let col = px.demultiply();
            let rgb = [col.red(), col.green(), col.blue()].map(|v| v as f32 / 255.0);
            c.paint(n % w, n / w, rgb, px.alpha() as f64 / 255.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scale_bar_is_labelled_in_a_real_font() {
        // A 40 x 10 mm canvas at 8 px/mm, page origin at pixel (0, 0).
        let (k, w, h) = (8.0, 320, 80);
        let mut c = Canvas { w, h, x0: 0.0, y0: 0.0, k, rgb: vec![[1.0; 3]; w * h] };
        let mut over = Overlay::new(&c).unwrap();
        over.scale_bar(2.0, 6.0);
        over.onto(&mut c);
        // The label's ink: right of the bar's end (12 mm), above its line (6 mm).
        let ink: Vec<(usize, usize, f32)> = (0..h)
            .flat_map(|j| (0..w).map(move |i| (i, j)))
            .filter(|&(i, _)| i as f64 / k > 12.5)
            .map(|(i, j)| (i, j, c.rgb[j * w + i][0]))
            .filter(|p| p.2 < 0.99)
            .collect();
        let top = ink.iter().map(|p| p.1).min().unwrap() as f64 / k;
        let bottom = ink.iter().map(|p| p.1).max().unwrap() as f64 / k;
        // "10 mm" at 2.8 mm to the em: digits about 0.73 em tall, standing on the baseline.
        assert!((bottom - 6.0).abs() < 0.3 && (bottom - top - 2.05).abs() < 0.35, "{top} {bottom}");
        // Anti-aliased outlines, not square bitmap glyphs: edges take grey levels.
        assert!(ink.iter().filter(|p| p.2 > 0.1 && p.2 < 0.9).count() > 20);
        // Five characters' advance: about 7 mm of ink.
        let (left, right) = (ink.iter().map(|p| p.0).min().unwrap(), ink.iter().map(|p| p.0).max().unwrap());
        let width = (right - left) as f64 / k;
        assert!((5.5..8.5).contains(&width), "{width}");
    }
}
