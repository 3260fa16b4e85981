//! A sheet as a PDF at true size, one page per page of the sheet, drawn
//! with krilla (the Typst project's PDF writer): black vector art on swell
//! paper; on an embosser its grid dots, grey where a dot is lower (an
//! embosser's driver turns grey levels into dot heights).

use krilla::color::luma;
use krilla::geom::{Path, PathBuilder, Transform};
use krilla::num::NormalizedF32;
use krilla::page::PageSettings;
use krilla::paint::{Fill, FillRule, LineCap, LineJoin, Stroke};
use krilla::{Document, SerializeSettings};
use taxel_format::Medium;

use super::{Level, MarkShape, PrintError, Sheet};

/// PDF points per millimetre.
pub const PT_PER_MM: f64 = 72.0 / 25.4;

/// Bézier handle length of a quarter circle, as a fraction of the radius.
const KAPPA: f32 = 0.552_284_8;

fn circle(c: (f64, f64), r: f64) -> Option<Path> {
    let (x, y, r) = (c.0 as f32, c.1 as f32, r as f32);
    let k = KAPPA * r;
    let mut pb = PathBuilder::new();
    pb.move_to(x + r, y);
    pb.cubic_to(x + r, y + k, x + k, y + r, x, y + r);
    pb.cubic_to(x - k, y + r, x - r, y + k, x - r, y);
    pb.cubic_to(x - r, y - k, x - k, y - r, x, y - r);
    pb.cubic_to(x + k, y - r, x + r, y - k, x + r, y);
    pb.close();
    pb.finish()
}

fn polyline(points: &[(f64, f64)], closed: bool) -> Option<Path> {
    let mut pb = PathBuilder::new();
    let first = points.first()?;
    pb.move_to(first.0 as f32, first.1 as f32);
    if points.len() == 1 {
        pb.line_to(first.0 as f32, first.1 as f32);
    }
    for p in &points[1..] {
        pb.line_to(p.0 as f32, p.1 as f32);
    }
    if closed {
        pb.close();
    }
    pb.finish()
}

/// The grey of a level: black on swell paper and for an embosser's highest dots.
fn grey(sheet: &Sheet, level: Level) -> u8 {
    if sheet.medium() != Medium::Emboss {
        return 0;
    }
    let levels = sheet.params.dot_levels.max(1) as u32;
    let l = super::raster::grid_level(level, levels);
    (255 - 255 * l / levels).min(200) as u8
}

/// Writes `sheet` as a PDF whose pages are the paper's size, in millimetres
/// scaled to points (content streams compressed).
pub fn pdf(sheet: &Sheet) -> Result<Vec<u8>, PrintError> {
    if sheet.medium() == Medium::Relief {
        return Err(PrintError(format!("{} is a relief: it is written as STL, not PDF", sheet.profile.name)));
    }
    let mut doc = Document::new_with(SerializeSettings::default());
    let (w, h) = ((sheet.paper_mm.0 * PT_PER_MM) as f32, (sheet.paper_mm.1 * PT_PER_MM) as f32);
    let settings = || PageSettings::from_wh(w, h).ok_or_else(|| PrintError(format!("a page of {w} x {h} pt")));
    for marks in &sheet.pages {
        let mut page = doc.start_page_with(settings()?);
        let mut s = page.surface();
        s.push_transform(&Transform::from_scale(PT_PER_MM as f32, PT_PER_MM as f32));
        for m in marks {
            let paint = luma::Color::new(grey(sheet, m.level)).into();
            match &m.shape {
                MarkShape::Line { points, closed, width_mm } => {
                    let Some(path) = polyline(points, *closed) else { continue };
                    s.set_fill(None);
                    s.set_stroke(Some(Stroke {
                        paint,
                        width: *width_mm as f32,
                        miter_limit: 4.0,
                        line_cap: LineCap::Round,
                        line_join: LineJoin::Round,
                        opacity: NormalizedF32::ONE,
                        dash: None,
                    }));
                    s.draw_path(&path);
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
                    let Some(path) = pb.finish() else { continue };
                    s.set_stroke(None);
                    s.set_fill(Some(Fill { paint, opacity: NormalizedF32::ONE, rule: FillRule::NonZero }));
                    s.draw_path(&path);
                }
                MarkShape::Dot { centre, diameter_mm } => {
                    let Some(path) = circle(*centre, diameter_mm / 2.0) else { continue };
                    s.set_stroke(None);
                    s.set_fill(Some(Fill { paint, opacity: NormalizedF32::ONE, rule: FillRule::NonZero }));
                    s.draw_path(&path);
                }
            }
        }
        s.pop();
        s.finish();
        page.finish();
    }
    doc.finish().map_err(|e| PrintError(format!("the PDF writer failed: {e:?}")))
}
