//! Mask layers: a shape's outline band (vibration) or fill (grating)
//! rasterised with tiny-skia, anti-aliased, on the page-wide pixel lattice
//! (so masks of different shapes sample the same points), cropped to the
//! samples that are not zero.

use resvg::tiny_skia::{
    BlendMode, FillRule as SkFillRule, LineCap, LineJoin, Paint, Path, PathBuilder, Pixmap, Stroke, Transform,
};
use taxel_format::{MAX_MASK_SIDE, MaskKind, MaskLayer, MaskSamples, Mm};

use crate::diagnostic::Diagnostic;
use crate::drawing::Page;
use crate::geometry::{FillRule, Polyline};

/// A tiny-skia path through the polylines (page mm): what the masks rasterise.
/// `None` when no subpath is left.
pub(crate) fn to_path(polys: &[Polyline]) -> Option<Path> {
    let mut pb = PathBuilder::new();
    for pl in polys {
        let mut pts = pl.points.iter().map(|&(x, y)| (x as f32, y as f32));
        let Some((x, y)) = pts.next() else { continue };
        pb.move_to(x, y);
        for (x, y) in pts {
            pb.line_to(x, y);
        }
        if pl.closed {
            pb.close();
        }
    }
    pb.finish()
}

/// A shape to rasterise: its path in page mm and fill rule.
pub(crate) type Area<'a> = (&'a Path, FillRule);

fn sk_rule(rule: FillRule) -> SkFillRule {
    match rule {
        FillRule::NonZero => SkFillRule::Winding,
        FillRule::EvenOdd => SkFillRule::EvenOdd,
    }
}

/// Largest mask the compiler makes, in samples.
pub(crate) const MAX_SAMPLES: u64 = 16 << 20;
/// Largest raster rendered for one mask before averaging (128 MB of RGBA).
const SUPERSAMPLED_MAX: u64 = 32 << 20;

/// What to draw.
pub(crate) enum Coverage<'a> {
    /// The band of this width (mm) centred on the outline, round joins and caps.
    Band(f64),
    /// The fill, minus the vibrating bands `(outline in page mm, width)` that
    /// cross it (its own, for a tactile icon, and any other shape's border),
    /// so a vibrating outline is never summed with the grating under it.
    Fill { minus_bands: Vec<(&'a Path, f64)> },
}

/// Renders one mask; `None` when nothing of it is left on the page.
#[allow(clippy::too_many_arguments)]
pub(crate) fn render(
    shape: Area<'_>,
    clips: &[Area<'_>],
    coverage: &Coverage<'_>,
    kind: MaskKind,
    amplitude: f32,
    source: Option<u32>,
    page: Page,
    px_per_mm: f32,
    element: &str,
    diags: &mut Vec<Diagnostic>,
) -> Option<MaskLayer> {
    let (path, fill_rule) = shape;
    let b = path.compute_tight_bounds()?;
    let grow = match coverage {
        Coverage::Band(w) => *w / 2.0,
        Coverage::Fill { .. } => 0.0,
    };
    let x0 = (b.left() as f64 - grow).max(0.0);
    let y0 = (b.top() as f64 - grow).max(0.0);
    let x1 = (b.right() as f64 + grow).min(page.width_mm);
    let y1 = (b.bottom() as f64 + grow).min(page.height_mm);
    if !(x1 > x0 && y1 > y0) {
        return None;
    }
    let mut px = px_per_mm as f64;
    let extent = |px: f64| {
        let (i0, j0) = ((x0 * px).floor(), (y0 * px).floor());
        (i0, j0, ((x1 * px).ceil() - i0).max(1.0), ((y1 * px).ceil() - j0).max(1.0))
    };
    let (_, _, w, h) = extent(px);
    if w * h > MAX_SAMPLES as f64 || w > MAX_MASK_SIDE as f64 || h > MAX_MASK_SIDE as f64 {
        let f = (MAX_SAMPLES as f64 / (w * h)).sqrt().min(MAX_MASK_SIDE as f64 / w.max(h)) * 0.99;
        let lower = px * f;
        diags.push(
            Diagnostic::warning(
                "T0303",
                format!("the mask of this shape would need {:.0} x {:.0} samples; its resolution is lowered from {px} to {lower:.3} px/mm", w, h),
            )
            .with_element(element)
            .with_help("split the shape, or lower --resolution for the whole drawing"),
        );
        px = lower;
    }
    let (i0, j0, w, h) = extent(px);
    // Render 3 x 3 times finer and average: tiny-skia's anti-aliasing
    // quantises coverage to a quarter pixel, which alone would move edges by
    // up to 0.2 sample; averaging sub-pixels makes each sample the shape's
    // area coverage (docs/annotations.md, "Mask resolution": at 10 px/mm the
    // worst edge displacement is 21 µm without this, 11.4 µm with it).
    let s = [3.0, 2.0, 1.0].into_iter().find(|s| w * h * s * s <= SUPERSAMPLED_MAX as f64).unwrap_or(1.0);
    let (fw, fh) = ((w * s) as u32, (h * s) as u32);
    let mut pixmap = Pixmap::new(fw, fh)?;
    let fine = px * s;
    let ts = Transform::from_row(fine as f32, 0.0, 0.0, fine as f32, (-i0 * s) as f32, (-j0 * s) as f32);
    let mut paint = Paint::default();
    paint.set_color_rgba8(0, 0, 0, 255);
    paint.anti_alias = true;
    let band = |width: f64| Stroke {
        width: width as f32,
        line_cap: LineCap::Round,
        line_join: LineJoin::Round,
        ..Stroke::default()
    };
    match coverage {
        Coverage::Band(width) => pixmap.stroke_path(path, &paint, &band(*width), ts, None),
        Coverage::Fill { minus_bands } => {
            pixmap.fill_path(path, &paint, sk_rule(fill_rule), ts, None);
            let mut cut = paint.clone();
            cut.blend_mode = BlendMode::DestinationOut;
            for (p, wb) in minus_bands {
                pixmap.stroke_path(p, &cut, &band(*wb), ts, None);
            }
        }
    }
    let mut alpha: Vec<u8> = pixmap.pixels().iter().map(|p| p.alpha()).collect();
    for &(clip, rule) in clips {
        let mut cp = Pixmap::new(fw, fh)?;
        cp.fill_path(clip, &paint, sk_rule(rule), ts, None);
        for (a, c) in alpha.iter_mut().zip(cp.pixels()) {
            *a = ((*a as u32 * c.alpha() as u32 + 127) / 255) as u8;
        }
    }
    let alpha = downsample(&alpha, fw as usize, w as usize, h as usize, s as usize);
    crop(alpha, w as u32, h as u32).map(|(ci, cj, cw, ch, samples)| MaskLayer {
        source,
        kind,
        amplitude,
        origin_x: Mm(((i0 + ci as f64) / px) as f32),
        origin_y: Mm(((j0 + cj as f64) / px) as f32),
        px_per_mm: px as f32,
        width: cw,
        height: ch,
        samples: MaskSamples::U8(samples),
    })
}

/// Averages `s` x `s` blocks of a fine raster `fw` samples wide into a `w` x `h` one.
fn downsample(fine: &[u8], fw: usize, w: usize, h: usize, s: usize) -> Vec<u8> {
    if s == 1 {
        return fine.to_vec();
    }
    let n = (s * s) as u32;
    let mut out = Vec::with_capacity(w * h);
    for j in 0..h {
        for i in 0..w {
            let mut sum = 0u32;
            for dj in 0..s {
                let row = (j * s + dj) * fw + i * s;
                sum += fine[row..row + s].iter().map(|&v| v as u32).sum::<u32>();
            }
            out.push(((sum + n / 2) / n) as u8);
        }
    }
    out
}

/// Crops a raster to its non-zero samples: `(first column, first row, width, height, samples)`.
fn crop(a: Vec<u8>, w: u32, h: u32) -> Option<(u32, u32, u32, u32, Vec<u8>)> {
    let (w, h) = (w as usize, h as usize);
    let rows: Vec<usize> = (0..h).filter(|&j| a[j * w..(j + 1) * w].iter().any(|&v| v > 0)).collect();
    let (&j0, &j1) = (rows.first()?, rows.last()?);
    let mut i0 = w;
    let mut i1 = 0;
    for j in j0..=j1 {
        let row = &a[j * w..(j + 1) * w];
        if let Some(f) = row.iter().position(|&v| v > 0) {
            i0 = i0.min(f);
            i1 = i1.max(row.iter().rposition(|&v| v > 0).unwrap_or(f));
        }
    }
    if i0 == 0 && i1 + 1 == w && j0 == 0 && j1 + 1 == h {
        return Some((0, 0, w as u32, h as u32, a));
    }
    let mut out = Vec::with_capacity((i1 + 1 - i0) * (j1 + 1 - j0));
    for j in j0..=j1 {
        out.extend_from_slice(&a[j * w + i0..j * w + i1 + 1]);
    }
    Some((i0 as u32, j0 as u32, (i1 + 1 - i0) as u32, (j1 + 1 - j0) as u32, out))
}

#[cfg(test)]
mod tests {
    use super::crop;

    #[test]
    fn crop_keeps_only_nonzero_extent() {
        #[rustfmt::skip]
        let a = vec![
            0, 0, 0, 0,
            0, 5, 0, 0,
            0, 0, 7, 0,
        ];
        assert_eq!(crop(a, 4, 3), Some((1, 1, 2, 2, vec![5, 0, 0, 7])));
        assert_eq!(crop(vec![0; 6], 3, 2), None);
    }
}
