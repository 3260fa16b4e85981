//! A picture of a sheet as a reader feels it: the paper, its raised marks
//! shaded as relief lit from the top left (darker where higher: on a relief
//! and a multi-level embosser, textures lower than lines), its pages as
//! [`Sheet::layout`] places them (the graphic's as they join, then its key).

use super::raster::{Frame, coverage};
use super::{Level, Sheet};
use crate::preview::Picture;
use taxel_format::Medium;

/// Pixels a millimetre of a print preview.
pub const PX_PER_MM: f64 = 6.0;
/// Largest preview side in pixels.
const MAX_SIDE_PX: f64 = 8000.0;
/// Gap between pages, in mm.
const GAP_MM: f64 = 8.0;

/// Relative height of each level on `sheet`'s medium, `[texture, braille, line]`.
fn relative(sheet: &Sheet) -> [f32; 3] {
    let p = &sheet.params;
    match sheet.medium() {
        Medium::Swell => [1.0; 3],
        Medium::Relief => {
            let top = p.raise_mm.max(p.texture_mm).max(1e-3);
            [p.texture_mm / top, p.raise_mm / top, p.raise_mm / top]
        }
        Medium::Emboss => {
            let n = p.dot_levels.max(1) as u32;
            [Level::Texture, Level::Braille, Level::Line].map(|l| super::raster::grid_level(l, n) as f32 / n as f32)
        }
    }
}

/// Draws `sheet`.
pub fn render(sheet: &Sheet) -> Picture {
    let layout = sheet.layout();
    let across = layout.iter().map(|p| p.0 + 1).max().unwrap_or(1) as f64;
    let down = layout.iter().map(|p| p.1 + 1).max().unwrap_or(1) as f64;
    let (pw, ph) = sheet.paper_mm;
    let total_w = pw * across + GAP_MM * (across + 1.0);
    let total_h = ph * down + GAP_MM * (down + 1.0);
    let k = PX_PER_MM.min(MAX_SIDE_PX / total_w).min(MAX_SIDE_PX / total_h);
    let (w, h) = ((total_w * k).ceil() as usize, (total_h * k).ceil() as usize);
    let mut rgb = vec![[226u8, 226, 230]; w * h];
    let rel = relative(sheet);
    for (marks, (c, r)) in sheet.pages.iter().zip(layout) {
        let (ox, oy) = (GAP_MM + c as f64 * (pw + GAP_MM), GAP_MM + r as f64 * (ph + GAP_MM));
        let (pw_px, ph_px) = ((pw * k).round() as usize, (ph * k).round() as usize);
        let frame = Frame { x0: 0.0, y0: 0.0, px: k, w: pw_px as u32, h: ph_px as u32 };
        let Some(cov) = coverage(marks, frame, true) else { continue };
        let height = |i: usize, j: usize| -> f32 {
            let q = j.min(ph_px - 1) * pw_px + i.min(pw_px - 1);
            (0..3).map(|l| cov.levels[l][q] as f32 / 255.0 * rel[l]).fold(0.0, f32::max)
        };
        let (x0, y0) = ((ox * k).round() as usize, (oy * k).round() as usize);
        for j in 0..ph_px {
            for i in 0..pw_px {
                let z = height(i, j);
                // Lit from the top left: brighter where the surface rises towards the light.
                let slope = height(i.saturating_sub(1), j.saturating_sub(1)) - height(i + 1, j + 1);
                let paper = [252.0, 250.0, 244.0];
                let raised = [120.0, 104.0, 84.0];
                let mut c = [0u8; 3];
                for ch in 0..3 {
                    let v = paper[ch] * (1.0 - z) + raised[ch] * z + 90.0 * slope;
                    c[ch] = v.clamp(0.0, 255.0) as u8;
                }
                if let Some(px) = rgb.get_mut((y0 + j) * w + x0 + i) {
                    *px = c;
                }
            }
        }
    }
    let rgba = rgb.iter().flat_map(|p| [p[0], p[1], p[2], 255]).collect();
    Picture { width: w as u32, height: h as u32, rgba }
}
