//! A sheet's marks drawn into rasters with tiny-skia, one coverage raster per
//! [`Level`]: the relief's height field, the embosser's grid, the felt
//! preview and the design rules read them. And the embosser's PNG.

use resvg::tiny_skia::{self, FillRule, LineCap, LineJoin, Paint, PathBuilder, Pixmap, Stroke, Transform};
use taxel_format::Medium;

use super::{Level, Mark, MarkShape, PrintError, Sheet};

/// Where a raster lies on the paper: `px` pixels a millimetre, pixel (0, 0)'s
/// top-left corner at paper mm `(x0, y0)`, `w` by `h` pixels.
#[derive(Debug, Clone, Copy)]
pub(super) struct Frame {
    pub x0: f64,
    pub y0: f64,
    pub px: f64,
    pub w: u32,
    pub h: u32,
}

/// Coverage (0 to 255) of each level, `[texture, braille, line]`, row-major.
pub(super) struct Coverage {
    pub levels: [Vec<u8>; 3],
}

fn level_index(l: Level) -> usize {
    match l {
        Level::Texture => 0,
        Level::Braille => 1,
        Level::Line => 2,
    }
}

/// The tiny-skia path of a mark's shape (in paper mm) and how it is painted:
/// `Some(width)` stroked, `None` filled.
fn path_of(shape: &MarkShape) -> Option<(tiny_skia::Path, Option<f32>)> {
    match shape {
        MarkShape::Line { points, closed, width_mm } => {
            let mut pb = PathBuilder::new();
            let first = points.first()?;
            pb.move_to(first.0 as f32, first.1 as f32);
            if points.len() == 1 {
                // A point: a zero-length line, drawn as a round dot by its cap.
                pb.line_to(first.0 as f32, first.1 as f32);
            }
            for p in &points[1..] {
                pb.line_to(p.0 as f32, p.1 as f32);
            }
            if *closed {
                pb.close();
            }
            Some((pb.finish()?, Some(*width_mm as f32)))
        }
        MarkShape::Polygon { rings } => {
            let mut pb = PathBuilder::new();
            for r in rings {
                let Some(f) = r.first() else { continue };
                pb.move_to(f.0 as f32, f.1 as f32);
                for p in &r[1..] {
                    pb.line_to(p.0 as f32, p.1 as f32);
                }
                pb.close();
            }
            Some((pb.finish()?, None))
        }
        MarkShape::Dot { centre, diameter_mm } => {
            Some((PathBuilder::from_circle(centre.0 as f32, centre.1 as f32, (*diameter_mm / 2.0) as f32)?, None))
        }
    }
}

/// Draws `marks` into a coverage raster per level.
pub(super) fn coverage(marks: &[Mark], f: Frame, anti_alias: bool) -> Option<Coverage> {
    let mut maps: Vec<Pixmap> = (0..3).map(|_| Pixmap::new(f.w.max(1), f.h.max(1))).collect::<Option<_>>()?;
    let t = Transform::from_row(f.px as f32, 0.0, 0.0, f.px as f32, (-f.x0 * f.px) as f32, (-f.y0 * f.px) as f32);
    let mut paint = Paint::default();
    paint.set_color_rgba8(0, 0, 0, 255);
    paint.anti_alias = anti_alias;
    for m in marks {
        let Some((path, stroke)) = path_of(&m.shape) else { continue };
        let map = &mut maps[level_index(m.level)];
        match stroke {
            Some(w) => {
                let s = Stroke { width: w, line_cap: LineCap::Round, line_join: LineJoin::Round, ..Default::default() };
                map.stroke_path(&path, &paint, &s, t, None);
            }
            None => map.fill_path(&path, &paint, FillRule::Winding, t, None),
        }
    }
    let mut it = maps.into_iter().map(|m| m.data().chunks_exact(4).map(|p| p[3]).collect::<Vec<u8>>());
    Some(Coverage { levels: [it.next()?, it.next()?, it.next()?] })
}

/// The embosser's grid as a grey PNG, a pixel per grid step over the whole
/// paper, its pages one under the other (so exactly `25.4 / grid_mm` pixels an inch, recorded in its `pHYs`
/// chunk): white where no dot is, darker for higher dots, black the highest.
pub fn png(sheet: &Sheet) -> Result<Vec<u8>, PrintError> {
    if sheet.medium() != Medium::Emboss {
        return Err(PrintError(format!(
            "{} is not an embosser: it has no dot grid to write as PNG",
            sheet.profile.name
        )));
    }
    let g = sheet.params.grid_mm as f64;
    let w = (sheet.paper_mm.0 / g * (1.0 + 1e-6)).floor() as u32;
    let page_h = (sheet.paper_mm.1 / g * (1.0 + 1e-6)).floor() as u32;
    let h = page_h.saturating_mul(sheet.pages.len().max(1) as u32);
    let levels = sheet.params.dot_levels.max(1) as u32;
    let mut gray = vec![255u8; w as usize * h as usize];
    // Every page, one under the other, as on an embosser's fanfold paper.
    for (n, page) in sheet.pages.iter().enumerate() {
        for m in page {
            let MarkShape::Dot { centre, .. } = m.shape else { continue };
            let (i, j) = ((centre.0 / g).floor(), (centre.1 / g).floor());
            if i < 0.0 || j < 0.0 || i >= w as f64 || j >= page_h as f64 {
                continue;
            }
            let k = (j as usize + n * page_h as usize) * w as usize + i as usize;
            let v = 255 - (255 * grid_level(m.level, levels) / levels) as u8;
            gray[k] = gray[k].min(v);
        }
    }
    let mut out = Vec::new();
    {
        let mut enc = ::png::Encoder::new(&mut out, w, h);
        enc.set_color(::png::ColorType::Grayscale);
        enc.set_depth(::png::BitDepth::Eight);
        let per_m = (1000.0 / g).round() as u32;
        enc.set_pixel_dims(Some(::png::PixelDimensions { xppu: per_m, yppu: per_m, unit: ::png::Unit::Meter }));
        let mut wr = enc.write_header().map_err(|e| PrintError(format!("cannot write the PNG: {e}")))?;
        wr.write_image_data(&gray).map_err(|e| PrintError(format!("cannot write the PNG: {e}")))?;
    }
    Ok(out)
}

/// The dot height (1 to `levels`) of a level on an embosser with `levels` heights.
pub(super) fn grid_level(l: Level, levels: u32) -> u32 {
    match l {
        Level::Line => levels,
        Level::Braille => levels.saturating_sub(1).max(1),
        Level::Texture => 1,
    }
}
