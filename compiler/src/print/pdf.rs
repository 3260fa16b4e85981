//! A sheet as a PDF at true size, one page per page of the sheet, written
//! with pdf-writer (the Typst project's PDF object writer): black vector art
//! on swell paper; on an embosser its grid dots, grey where a dot is lower
//! (an embosser's driver turns grey levels into dot heights). Every mark is
//! a path (no text, no fonts), each page one compressed content stream.

use std::io::Write as _;

use flate2::Compression;
use flate2::write::ZlibEncoder;
use pdf_writer::types::{LineCapStyle, LineJoinStyle};
use pdf_writer::{Content, Filter, Pdf, Rect, Ref};
use taxel_format::Medium;

use super::{Level, MarkShape, PrintError, Sheet};

/// PDF points per millimetre.
pub const PT_PER_MM: f64 = 72.0 / 25.4;

/// Bézier handle length of a quarter circle, as a fraction of the radius.
const KAPPA: f32 = 0.552_284_8;

/// A circle of four Bézier quarters, as a closed subpath.
fn circle(c: &mut Content, centre: (f64, f64), r: f64) {
    let (x, y, r) = (centre.0 as f32, centre.1 as f32, r as f32);
    let k = KAPPA * r;
    c.move_to(x + r, y);
    c.cubic_to(x + r, y + k, x + k, y + r, x, y + r);
    c.cubic_to(x - k, y + r, x - r, y + k, x - r, y);
    c.cubic_to(x - r, y - k, x - k, y - r, x, y - r);
    c.cubic_to(x + k, y - r, x + r, y - k, x + r, y);
    c.close_path();
}

/// `points` as a subpath (a single point as a zero-length segment, which a
/// round cap draws as a disc); nothing when there are none.
fn polyline(c: &mut Content, points: &[(f64, f64)], closed: bool) {
    let Some(first) = points.first() else { return };
    c.move_to(first.0 as f32, first.1 as f32);
    if points.len() == 1 {
        c.line_to(first.0 as f32, first.1 as f32);
    }
    for p in &points[1..] {
        c.line_to(p.0 as f32, p.1 as f32);
    }
    if closed {
        c.close_path();
    }
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
    let (w, h) = ((sheet.paper_mm.0 * PT_PER_MM) as f32, (sheet.paper_mm.1 * PT_PER_MM) as f32);
    if !(w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0) {
        return Err(PrintError(format!("a page of {w} x {h} pt")));
    }
    // Object numbers: the catalogue, the page tree, then a page and its
    // content stream for each page of the sheet.
    let (catalog, tree) = (Ref::new(1), Ref::new(2));
    let page_ref = |n: usize| Ref::new(3 + 2 * n as i32);
    let content_ref = |n: usize| Ref::new(4 + 2 * n as i32);
    let pages = sheet.pages.len().max(1);
    let count = i32::try_from(pages).map_err(|_| PrintError(format!("{pages} pages")))?;
    let mut pdf = Pdf::new();
    pdf.catalog(catalog).pages(tree);
    pdf.pages(tree).kids((0..pages).map(page_ref)).count(count);
    for n in 0..pages {
        let marks = sheet.pages.get(n).map_or(&[][..], Vec::as_slice);
        let stream = compress(&content(sheet, marks, h))?;
        pdf.page(page_ref(n)).parent(tree).media_box(Rect::new(0.0, 0.0, w, h)).contents(content_ref(n)).resources();
        pdf.stream(content_ref(n), &stream).filter(Filter::FlateDecode);
    }
    Ok(pdf.finish())
}

/// One page's drawing: page millimetres, y down, mapped to points, y up.
fn content(sheet: &Sheet, marks: &[super::Mark], page_h_pt: f32) -> Vec<u8> {
    let k = PT_PER_MM as f32;
    let mut c = Content::new();
    c.transform([k, 0.0, 0.0, -k, 0.0, page_h_pt]);
    c.set_line_cap(LineCapStyle::RoundCap);
    c.set_line_join(LineJoinStyle::RoundJoin);
    for m in marks {
        // The state first: nothing may come between a path and its painting.
        let g = f32::from(grey(sheet, m.level)) / 255.0;
        match &m.shape {
            MarkShape::Line { points, closed, width_mm } => {
                if points.is_empty() {
                    continue;
                }
                c.set_stroke_gray(g);
                c.set_line_width(*width_mm as f32);
                polyline(&mut c, points, *closed);
                c.stroke();
            }
            MarkShape::Polygon { rings } => {
                if rings.iter().all(Vec::is_empty) {
                    continue;
                }
                c.set_fill_gray(g);
                for r in rings {
                    polyline(&mut c, r, true);
                }
                c.fill_nonzero();
            }
            MarkShape::Dot { centre, diameter_mm } => {
                c.set_fill_gray(g);
                circle(&mut c, *centre, diameter_mm / 2.0);
                c.fill_nonzero();
            }
        }
    }
    c.finish().into_vec()
}

/// A content stream deflated (`/FlateDecode`).
fn compress(data: &[u8]) -> Result<Vec<u8>, PrintError> {
    let mut z = ZlibEncoder::new(Vec::with_capacity(data.len() / 4), Compression::new(6));
    z.write_all(data).and_then(|()| z.finish()).map_err(|e| PrintError(format!("compressing a PDF page: {e}")))
}
