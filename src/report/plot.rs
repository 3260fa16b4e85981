//! The report's plot: RMS error against run time (compile + play of the
//! trace) on log–log axes, one line per kernel, each point labelled with its
//! setting and the default ringed. Drawn with tiny-skia and the built-in font.

use tiny_skia::{Color, FillRule, Paint, PathBuilder, Pixmap, Rect, Stroke, StrokeDash, Transform};

use super::Row;
use super::font;

const W: u32 = 900;
const H: u32 = 600;
const LEFT: f32 = 90.0;
const RIGHT: f32 = 200.0;
const TOP: f32 = 60.0;
const BOTTOM: f32 = 70.0;

/// Colour per kernel, fixed so that plots of different scenes compare.
fn colour(kernel: &str) -> Color {
    let (r, g, b) = match kernel {
        "vibration" => (200, 60, 40),
        "grating" => (40, 110, 200),
        "dots" => (30, 150, 70),
        "all" => (60, 60, 60),
        _ => (150, 90, 180),
    };
    Color::from_rgba8(r, g, b, 255)
}

/// Draws the plot as PNG bytes; `title` goes on top.
pub fn draw(rows: &[Row], title: &str) -> Result<Vec<u8>, String> {
    let mut pm = Pixmap::new(W, H).ok_or("cannot allocate the plot")?;
    pm.fill(Color::WHITE);
    let pts: Vec<(f64, f64)> = rows.iter().map(|r| (r.run_ms, r.rms_error)).collect();
    let pos = |v: f64| v.is_finite() && v > 0.0;
    let xs: Vec<f64> = pts.iter().map(|p| p.0).filter(|&v| pos(v)).collect();
    let ys: Vec<f64> = pts.iter().map(|p| p.1).filter(|&v| pos(v)).collect();
    let (x_lo, x_hi) = decades(&xs);
    let (y_lo, y_hi) = decades(&ys);
    let (pw, ph) = (W as f32 - LEFT - RIGHT, H as f32 - TOP - BOTTOM);
    // Errors of exactly zero sit on the bottom axis.
    let sx = move |v: f64| LEFT + ((v.max(10f64.powi(x_lo)).log10() - x_lo as f64) / (x_hi - x_lo) as f64) as f32 * pw;
    let sy =
        move |v: f64| TOP + ph - ((v.max(10f64.powi(y_lo)).log10() - y_lo as f64) / (y_hi - y_lo) as f64) as f32 * ph;
    let black = Color::from_rgba8(0, 0, 0, 255);
    let grey = Color::from_rgba8(220, 220, 220, 255);
    for e in x_lo..=x_hi {
        let x = sx(10f64.powi(e));
        line(&mut pm, (x, TOP), (x, TOP + ph), grey, 1.0, false);
        let label = decade_label(e);
        text(&mut pm, &label, x - font::text_width(&label) as f32, TOP + ph + 10.0, 2.0, black);
    }
    let light = Color::from_rgba8(240, 240, 240, 255);
    for e in x_lo..x_hi {
        for m in [2.0, 5.0] {
            let x = sx(m * 10f64.powi(e));
            line(&mut pm, (x, TOP), (x, TOP + ph), light, 1.0, false);
        }
    }
    for e in y_lo..y_hi {
        for m in [2.0, 5.0] {
            let y = sy(m * 10f64.powi(e));
            line(&mut pm, (LEFT, y), (LEFT + pw, y), light, 1.0, false);
        }
    }
    for e in y_lo..=y_hi {
        let y = sy(10f64.powi(e));
        line(&mut pm, (LEFT, y), (LEFT + pw, y), grey, 1.0, false);
        let label = decade_label(e);
        text(&mut pm, &label, LEFT - 10.0 - 2.0 * font::text_width(&label) as f32, y - 7.0, 2.0, black);
    }
    line(&mut pm, (LEFT, TOP + ph), (LEFT + pw, TOP + ph), black, 2.0, false);
    line(&mut pm, (LEFT, TOP), (LEFT, TOP + ph), black, 2.0, false);
    let xl = "RUN TIME: COMPILE + PLAY TRACE (MS, LOG)";
    text(&mut pm, xl, LEFT + pw / 2.0 - font::text_width(xl) as f32, H as f32 - 30.0, 2.0, black);
    text(&mut pm, title, 10.0, 8.0, 2.0, black);
    let unit = rows.first().map_or(String::new(), |r| format!("RMS ERROR ({}, LOG)", r.error_unit));
    text(&mut pm, &unit, 10.0, 28.0, 2.0, black);
    let mut kernels: Vec<&str> = Vec::new();
    for r in rows {
        if !kernels.contains(&r.kernel.as_str()) {
            kernels.push(&r.kernel);
        }
    }
    for (ki, k) in kernels.iter().enumerate() {
        let c = colour(k);
        let mine: Vec<(usize, &Row)> = rows.iter().enumerate().filter(|(_, r)| r.kernel == *k).collect();
        for w in mine.windows(2) {
            let (a, b) = (pts[w[0].0], pts[w[1].0]);
            line(&mut pm, (sx(a.0), sy(a.1)), (sx(b.0), sy(b.1)), c, 2.5, false);
        }
        for (i, r) in &mine {
            let (x, y) = (sx(pts[*i].0), sy(pts[*i].1));
            dot(&mut pm, x, y, 4.5, c);
            let label = format!("{}", r.setting);
            text(&mut pm, &label, x + 7.0, y + 4.0, 1.0, c);
            if r.default {
                ring(&mut pm, x, y, 11.0, black);
                text(&mut pm, "DEFAULT", x + 7.0, y - 16.0, 1.0, black);
            }
        }
        let ly = TOP + 10.0 + ki as f32 * 24.0;
        line(&mut pm, (W as f32 - RIGHT + 15.0, ly + 6.0), (W as f32 - RIGHT + 45.0, ly + 6.0), c, 3.0, false);
        text(&mut pm, k, W as f32 - RIGHT + 52.0, ly, 2.0, c);
    }
    let unit = rows.first().map_or("", |r| r.unit.as_str());
    text(&mut pm, "POINT LABELS:", W as f32 - RIGHT + 15.0, TOP + ph - 60.0, 1.0, black);
    text(&mut pm, &format!("SETTING ({unit})"), W as f32 - RIGHT + 15.0, TOP + ph - 44.0, 1.0, black);
    text(&mut pm, "RING: DEFAULT", W as f32 - RIGHT + 15.0, TOP + ph - 28.0, 1.0, black);
    pm.encode_png().map_err(|e| format!("cannot encode the plot: {e}"))
}

/// Whole decades around the positive values (at least one decade wide).
fn decades(v: &[f64]) -> (i32, i32) {
    let lo = v.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = v.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    if !(lo.is_finite() && hi.is_finite()) {
        return (0, 1);
    }
    let (a, b) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    (a, b.max(a + 1))
}

fn decade_label(e: i32) -> String {
    if e >= 0 { format!("{}", 10u64.saturating_pow(e as u32)) } else { format!("{}", 10f64.powi(e)) }
}

fn line(pm: &mut Pixmap, a: (f32, f32), b: (f32, f32), c: Color, width: f32, dashed: bool) {
    let mut pb = PathBuilder::new();
    pb.move_to(a.0, a.1);
    pb.line_to(b.0, b.1);
    let Some(path) = pb.finish() else { return };
    let mut paint = Paint::default();
    paint.set_color(c);
    paint.anti_alias = true;
    let stroke =
        Stroke { width, dash: if dashed { StrokeDash::new(vec![6.0, 4.0], 0.0) } else { None }, ..Stroke::default() };
    pm.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
}

fn dot(pm: &mut Pixmap, x: f32, y: f32, r: f32, c: Color) {
    let Some(path) = PathBuilder::from_circle(x, y, r) else { return };
    let mut paint = Paint::default();
    paint.set_color(c);
    paint.anti_alias = true;
    pm.fill_path(&path, &paint, FillRule::Winding, Transform::identity(), None);
}

fn ring(pm: &mut Pixmap, x: f32, y: f32, r: f32, c: Color) {
    let Some(path) = PathBuilder::from_circle(x, y, r) else { return };
    let mut paint = Paint::default();
    paint.set_color(c);
    paint.anti_alias = true;
    pm.stroke_path(&path, &paint, &Stroke { width: 2.0, ..Stroke::default() }, Transform::identity(), None);
}

/// Draws `s` with its top-left at `(x, y)`, each font pixel `scale` plot pixels wide.
fn text(pm: &mut Pixmap, s: &str, x: f32, y: f32, scale: f32, c: Color) {
    let mut paint = Paint::default();
    paint.set_color(c);
    let scale = scale.max(1.0) + if scale < 2.0 { 1.0 } else { 0.0 };
    for (i, ch) in s.chars().enumerate() {
        let g = font::glyph(ch);
        let gx = x + i as f32 * (font::GLYPH_W + 1) as f32 * scale;
        for (row, bits) in g.iter().enumerate().take(font::GLYPH_H as usize) {
            for col in 0..font::GLYPH_W {
                if bits & (1 << (font::GLYPH_W - 1 - col)) != 0 {
                    let px = gx + col as f32 * scale;
                    let py = y + row as f32 * scale;
                    if let Some(rect) = Rect::from_xywh(px, py, scale, scale) {
                        pm.fill_rect(rect, &paint, Transform::identity(), None);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(kernel: &str, setting: f64, ms: f64, err: f64, default: bool) -> Row {
        Row {
            kernel: kernel.into(),
            setting,
            unit: "px/mm".into(),
            default,
            compile_ms: ms,
            bundle_bytes: 0,
            frame_us: 0.0,
            max_error: err,
            rms_error: err,
            far_error: None,
            error_unit: "steps".into(),
            frames: 1,
            run_ms: ms,
            on_front: true,
        }
    }

    #[test]
    fn plot_is_a_png_with_coloured_lines() {
        let rows = vec![row("grating", 2.0, 1.0, 30.0, false), row("grating", 8.0, 10.0, 3.0, true)];
        let png = draw(&rows, "TEST").expect("plot");
        let img = image::load_from_memory(&png).expect("decodes").to_rgba8();
        assert_eq!(img.dimensions(), (W, H));
        // Some pixel carries the grating's blue.
        assert!(img.pixels().any(|p| p.0 == [40, 110, 200, 255]));
    }

    #[test]
    fn decades_cover_the_values() {
        assert_eq!(decades(&[0.5, 30.0]), (-1, 2));
        assert_eq!(decades(&[3.0]), (0, 1));
        assert_eq!(decades(&[]), (0, 1));
    }
}
