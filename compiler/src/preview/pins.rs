//! A picture of a pin image as a reader meets it: every pin a small disc,
//! flush pins faint, raised pins dark (darker when higher, on a display with
//! heights), blinking pins ringed in red; the display's pages (or, on a
//! pannable surface, its first viewport) outlined in blue; the text line's
//! cells below the image.

use resvg::tiny_skia::{Color, FillRule, Paint, PathBuilder, Pixmap, Rect, Stroke, Transform};
use taxel_format::{DeviceProfile, FamilyParams, Navigation, PinImage};

use crate::preview::Picture;

/// Pixels from one pin to the next in a preview.
pub const PX_PER_PIN: u32 = 10;
/// Largest preview side in pixels (an image may be large).
const MAX_SIDE_PX: u64 = 8000;

/// The picture being drawn: tiny-skia paths, anti-aliased, in pixels.
struct Px {
    pixmap: Pixmap,
}

impl Px {
    /// A filled disc (or a ring between `inner` and `r`) centred at `(cx, cy)`.
    fn disc(&mut self, cx: f64, cy: f64, r: f64, inner: f64, c: [u8; 3]) {
        let mut pb = PathBuilder::new();
        pb.push_circle(cx as f32, cy as f32, r as f32);
        if inner > 0.0 {
            pb.push_circle(cx as f32, cy as f32, inner as f32);
        }
        if let Some(path) = pb.finish() {
            self.pixmap.fill_path(&path, &paint(c), FillRule::EvenOdd, Transform::identity(), None);
        }
    }

    /// A one-pixel outline through the pixels `(x0, y0)` to `(x1, y1)`.
    fn rect(&mut self, x0: f64, y0: f64, x1: f64, y1: f64, c: [u8; 3]) {
        let Some(r) = Rect::from_ltrb(x0 as f32 + 0.5, y0 as f32 + 0.5, x1 as f32 + 0.5, y1 as f32 + 0.5) else {
            return;
        };
        let path = PathBuilder::from_rect(r);
        let mut p = paint(c);
        p.anti_alias = false;
        self.pixmap.stroke_path(&path, &p, &Stroke { width: 1.0, ..Stroke::default() }, Transform::identity(), None);
    }
}

fn paint(c: [u8; 3]) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color_rgba8(c[0], c[1], c[2], 255);
    p.anti_alias = true;
    p
}

/// The shade of a raised pin of `height` out of `levels`: from mid grey (lowest) to black (highest).
pub fn shade(height: u8, levels: u8) -> [u8; 3] {
    let t = height.min(levels) as f64 / levels.max(1) as f64;
    let v = (150.0 * (1.0 - t)).round() as u8;
    [v, v, v]
}

/// Draws `image` for `profile`.
pub fn render(image: &PinImage, profile: &DeviceProfile) -> Picture {
    let (levels, per_line) = match profile.params {
        FamilyParams::Pins(p) => (p.height_levels, (p.text_cells as usize).max(1)),
        _ => (1, 1),
    };
    // The text line as the device shows it, `text_cells` cells at a time,
    // each stretch under the previous one.
    let text_lines = image.text.len().div_ceil(per_line) as u32;
    let text_rows = if image.text.is_empty() { 0 } else { 1 + 5 * text_lines };
    let mut s = PX_PER_PIN as u64;
    let text_cols = if image.text.is_empty() { 0 } else { 3 * per_line.min(image.text.len()) as u32 };
    let cols = image.cols.max(text_cols);
    let side = (cols.max(image.rows + text_rows) as u64 + 2) * s;
    if side > MAX_SIDE_PX {
        s = (MAX_SIDE_PX / (cols.max(image.rows + text_rows) as u64 + 2)).max(2);
    }
    let (w, h) = ((cols as u64 + 2) * s, (image.rows as u64 + 2 + text_rows as u64) * s);
    // (The sides are at most MAX_SIDE_PX, or a few pins' width over it, and at least two pins.)
    let Some(mut pixmap) = Pixmap::new(w as u32, h as u32) else {
        return Picture { width: 0, height: 0, rgba: Vec::new() };
    };
    pixmap.fill(Color::from_rgba8(250, 250, 246, 255));
    let mut px = Px { pixmap };
    let s = s as f64;
    let centre = |c: u32, r: u32| ((c as f64 + 1.5) * s, (r as f64 + 1.5) * s);
    for r in 0..image.rows {
        for c in 0..image.cols {
            let pin = image.get(c, r);
            let (x, y) = centre(c, r);
            if pin.raised() {
                px.disc(x, y, 0.42 * s, 0.0, shade(pin.height(), levels));
                if pin.blinks() {
                    px.disc(x, y, 0.5 * s, 0.36 * s, [220, 30, 30]);
                }
            } else {
                px.disc(x, y, 0.12 * s, 0.0, [205, 205, 200]);
            }
        }
    }
    // The display's extent on the image: every page, or the first viewport.
    let (dw, dh) = (profile.cols as u32, profile.rows as u32);
    let blue = [40, 90, 200];
    let frame = |px: &mut Px, c0: u32, r0: u32| {
        let (x0, y0) = ((c0 as f64 + 1.0) * s, (r0 as f64 + 1.0) * s);
        let (x1, y1) = (((c0 + dw).min(image.cols) as f64 + 1.0) * s, ((r0 + dh).min(image.rows) as f64 + 1.0) * s);
        px.rect(x0, y0, x1 - 1.0, y1 - 1.0, blue);
    };
    match image.navigation {
        Navigation::Pages => {
            for (c0, r0) in pages(image, profile) {
                frame(&mut px, c0, r0);
            }
        }
        Navigation::Pan => frame(&mut px, 0, 0),
    }
    // The text line: its cells as pins, below the image.
    for (k, &m) in image.text.iter().enumerate() {
        let (line, cell) = ((k / per_line) as u32, (k % per_line) as u32);
        for (bit, &(dc, dr)) in crate::braille::DOT_POSITIONS.iter().enumerate() {
            let (x, y) = centre(cell * 3 + dc, image.rows + 1 + 5 * line + dr);
            if m & (1 << bit) != 0 {
                px.disc(x, y, 0.42 * s, 0.0, [0, 0, 0]);
            } else if dr < 3 {
                px.disc(x, y, 0.12 * s, 0.0, [205, 205, 200]);
            }
        }
    }
    // Every pixel is opaque, so the premultiplied bytes are the plain ones.
    let (width, height) = (px.pixmap.width(), px.pixmap.height());
    Picture { width, height, rgba: px.pixmap.take() }
}

/// The display pages of `image` for `profile`, row-major: each `(col, row)` of its top-left pin.
pub fn pages(image: &PinImage, profile: &DeviceProfile) -> Vec<(u32, u32)> {
    let (w, h) = (profile.cols as u32, profile.rows as u32);
    let (across, down) = (image.cols.div_ceil(w).max(1), image.rows.div_ceil(h).max(1));
    (0..down).flat_map(|j| (0..across).map(move |i| (i * w, j * h))).collect()
}
