//! The key pages on paper: the drawing's title, then each texture, line
//! style and point symbol of the key ([`crate::style::legend()`]) felt as
//! itself (a swatch of the texture the sheet gave it, a sample of its line
//! style, its symbol) with its meaning in braille to the right, then the key
//! codes with the labels they stand for. A key longer than a page goes on
//! over as many pages as it needs (note T0727), never cut.

use taxel_format::{Medium, PrintParams};

use super::braille::{Cx, cells, dot_marks, run_dots, snap};
use super::marks::Builder;
use super::{Mark, TextureId, texture};
use crate::diagnostic::Diagnostic;
use crate::drawing::{Drawing, PathShape};
use crate::geometry::Polyline;
use crate::style::legend::{Entry, Legend, Swatch};

/// A swatch's size on swell paper, `(width, height)` mm (spaced out with
/// the medium's textures, [`texture::scale`]): room for two or more lines
/// of any texture of the catalogue across its height, and long enough that
/// a dashed line's sample holds three dashes ([`super::marks::DASH_MM`]
/// and their gaps), so that it is not felt as a double line.
pub const SWATCH_MM: (f64, f64) = (25.0, 10.0);

/// One row of the key being laid out: a swatch (or none) and braille lines.
struct Row<'a> {
    entry: Option<&'a Entry>,
    cells: Vec<u8>,
}

/// The key's pages (none when the drawing needs no key, [`Legend::needed`]).
pub(super) fn pages(
    drawing: &Drawing,
    legend: &Legend,
    textures: &[(usize, TextureId)],
    p: &PrintParams,
    origin: (f64, f64),
    cx: &mut Cx<'_>,
) -> Vec<Vec<Mark>> {
    if !legend.needed() {
        return Vec::new();
    }
    let mut rows: Vec<Row<'_>> = Vec::new();
    if !drawing.title.is_empty() {
        rows.push(Row { entry: None, cells: cells(&drawing.title, (None, None), None, cx) });
    }
    rows.push(Row { entry: None, cells: cells("key", (None, None), None, cx) });
    for e in legend.shown() {
        rows.push(Row { entry: Some(e), cells: cells(&e.meaning, (None, None), None, cx) });
    }
    for line in legend.text_lines() {
        rows.push(Row { entry: None, cells: cells(&line, (None, None), None, cx) });
    }
    let k = texture::scale(p);
    let (sw, sh) = (SWATCH_MM.0 * k, SWATCH_MM.1 * k);
    let (dp, cp, lp) = (p.braille_dot_pitch_mm as f64, p.braille_cell_mm as f64, p.braille_line_mm as f64);
    let r = p.braille_dot_mm as f64 / 2.0;
    let gap = (p.min_gap_mm as f64).max(cp);
    let (w, h) = (p.surface_mm().0 as f64, p.surface_mm().1 as f64);
    let mut b = Builder::new(drawing, p, (0.0, 0.0));
    let mut pages: Vec<Vec<Mark>> = vec![Vec::new()];
    let mut y = origin.1;
    let bottom = origin.1 + h + 1e-9;
    for row in rows {
        // Braille beside a swatch starts right of it; other lines at the margin.
        let x0 = origin.0 + r + if row.entry.is_some() { sw + gap } else { 0.0 };
        let per_line = ((origin.0 + w - x0 - r) / cp).floor().max(1.0) as usize;
        let lines = wrap(&row.cells, per_line);
        let text_h = lines.len() as f64 * lp;
        let swatch_h = if row.entry.is_some() { sh + p.min_gap_mm as f64 } else { 0.0 };
        let tall = text_h.max(swatch_h);
        // A row that fits on a page starts on the next page when it would
        // run past this one's bottom; a longer one (a paragraph of a label)
        // starts here, with its swatch and first line, and goes on over.
        let needs = if tall <= h + 1e-9 { tall } else { lp.max(swatch_h) };
        if y + needs > bottom && y > origin.1 {
            pages.push(Vec::new());
            y = origin.1;
        }
        if let Some(e) = row.entry {
            let before = b.marks.len();
            swatch(&mut b, e, textures, p, (origin.0, y), (sw, sh));
            let marks: Vec<Mark> = b.marks.drain(before..).collect();
            if let Some(page) = pages.last_mut() {
                page.extend(marks);
            }
        }
        let swatch_end = y + swatch_h;
        let page_of_swatch = pages.len();
        // The first line's dots centred on the swatch's height.
        let mut dots_below = if row.entry.is_some() { ((sh - 2.0 * dp) / 2.0).max(r) } else { r };
        let mut line_y = y;
        for (n, chunk) in lines.iter().enumerate() {
            if n > 0 && line_y + lp > bottom {
                pages.push(Vec::new());
                (line_y, dots_below) = (origin.1, r);
            }
            let (mut cx0, mut cy0) = (x0, line_y + dots_below);
            if p.medium == Medium::Emboss {
                cx0 = snap(cx0, origin.0, p.grid_mm as f64);
                cy0 = snap(cy0, origin.1, p.grid_mm as f64);
            }
            let dots = run_dots(p, chunk, cx0, cy0);
            if let Some(page) = pages.last_mut() {
                page.extend(dot_marks(p, &dots, None));
            }
            line_y += lp;
        }
        y = if pages.len() == page_of_swatch { line_y.max(swatch_end) } else { line_y };
    }
    if pages.len() > 1 {
        cx.diags.push(
            Diagnostic::note(
                "T0727",
                format!("the key takes {} pages; it goes on over them, none of it left out", pages.len()),
            )
            .with_help("a shorter title or shorter legend texts make the key shorter"),
        );
    }
    pages
}

/// `cells` cut into lines of at most `per_line`, at a blank cell (a space)
/// where there is one in the line, else where the line is full.
pub(super) fn wrap(cells: &[u8], per_line: usize) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    let mut rest = cells;
    while rest.len() > per_line {
        let cut = rest[..=per_line].iter().rposition(|&c| c == 0).filter(|&k| k > 0).unwrap_or(per_line);
        out.push(rest[..cut].to_vec());
        rest = &rest[cut..];
        while rest.first() == Some(&0) {
            rest = &rest[1..];
        }
    }
    if !rest.is_empty() || out.is_empty() {
        out.push(rest.to_vec());
    }
    out
}

/// The swatch of entry `e` in the box at `at`, `(w, h)`: its texture, a
/// sample of its line, dots or stroke across it, or its symbol at its middle.
fn swatch(
    b: &mut Builder<'_>,
    e: &Entry,
    textures: &[(usize, TextureId)],
    p: &PrintParams,
    at: (f64, f64),
    (w, h): (f64, f64),
) {
    let Some(&elem) = e.elements.first() else { return };
    let across = || vec![Polyline { points: vec![(at.0, at.1 + h / 2.0), (at.0 + w, at.1 + h / 2.0)], closed: false }];
    match e.swatch {
        Swatch::Texture(_) => {
            // The texture the sheet gave the entry's regions (they all share
            // it: a grating style has one texture, `texture.rs`).
            let Some(&(_, t)) = textures.iter().find(|(i, _)| e.elements.contains(i)) else { return };
            let rect =
                Polyline { points: vec![at, (at.0 + w, at.1), (at.0 + w, at.1 + h), (at.0, at.1 + h)], closed: true };
            let path = PathShape { outline: vec![rect], ..Default::default() };
            let fill = texture::Fill { texture: t, outlined: false, clear: &[] };
            b.marks.extend(texture::fill(p, (0.0, 0.0), elem, &path, fill));
        }
        Swatch::Line(v) => b.outline(elem, &across(), &v),
        Swatch::Dotted(d) => b.dotted(elem, &across(), d.radius_mm, d.spacing_mm),
        Swatch::Symbol(d) => b.symbols(elem, &[(at.0 + w / 2.0, at.1 + h / 2.0)], d.radius_mm),
        Swatch::Stroke(_) => b.arrow(elem, &across()),
    }
}
