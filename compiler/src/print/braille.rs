//! Braille on paper: the cells the compiler makes for a label
//! ([`crate::svg::braille_cells`], the same as on every device), drawn as
//! round dots at the medium's dimensions (base diameter, dot spacing, cell
//! spacing, line spacing), never through a font. A label's cells start where
//! its text starts (after its anchor) and stand on its baseline. The key of
//! the labels written as key codes is printed on a page of its own.

use taxel_format::{Medium, PrintParams};

use super::{Level, Mark, MarkShape};
use crate::diagnostic::Diagnostic;
use crate::drawing::{Drawing, Element, Shape};

/// The labels' braille: its dots, and the box of each label (paper mm,
/// grown by the medium's minimum gap) that textures are cleared from.
#[derive(Debug, Default)]
pub(super) struct Labels {
    pub marks: Vec<Mark>,
    pub boxes: Vec<(f64, f64, f64, f64)>,
    /// The element of each box.
    pub owners: Vec<usize>,
}

/// Translates `text`, warning (T0304) about characters left out, as the pin arrays do.
fn cells(text: &str, e: Option<&Element>, diags: &mut Vec<Diagnostic>) -> Vec<u8> {
    let (mut cells, missing) = crate::svg::braille_cells(text);
    if !missing.is_empty() {
        let list = crate::svg::braille_left_out(&missing);
        if crate::svg::braille_says_nothing(text, &missing) {
            cells.clear();
        }
        let left = if cells.iter().all(|&c| c == 0) { "the text is left out" } else { "these characters are left out" };
        let mut d = Diagnostic::warning("T0304", format!("no uncontracted UEB braille for {list}; {left}"))
            .with_help(crate::svg::BRAILLE_TABLE_HELP);
        if let Some(e) = e {
            d = d.with_element(e.name.clone()).on_line(e.line);
        }
        diags.push(d);
    }
    cells
}

/// Snaps a coordinate to an embosser's grid (grid points at `origin + (k + 0.5) * grid`).
pub(super) fn snap(v: f64, origin: f64, grid: f64) -> f64 {
    origin + (((v - origin) / grid - 0.5).round() + 0.5) * grid
}

/// The dots of a run of `cells` whose first cell's top-left dot is at `(x0, y0)`.
pub(super) fn run_dots(p: &PrintParams, cells: &[u8], x0: f64, y0: f64) -> Vec<(f64, f64)> {
    let (dp, cp) = (p.braille_dot_pitch_mm as f64, p.braille_cell_mm as f64);
    let mut out = Vec::new();
    for (k, &c) in cells.iter().enumerate() {
        for dot in 0..6 {
            if c & (1 << dot) != 0 {
                let (col, row) = ((dot / 3) as f64, (dot % 3) as f64);
                out.push((x0 + k as f64 * cp + col * dp, y0 + row * dp));
            }
        }
    }
    out
}

fn dot_marks(p: &PrintParams, dots: &[(f64, f64)], elem: Option<usize>) -> impl Iterator<Item = Mark> {
    let d = p.braille_dot_mm as f64;
    dots.iter().map(move |&c| Mark {
        shape: MarkShape::Dot { centre: c, diameter_mm: d },
        level: Level::Braille,
        element: elem,
    })
}

/// The braille of every visible label with a `braille` style.
pub(super) fn labels(drawing: &Drawing, p: &PrintParams, origin: (f64, f64), diags: &mut Vec<Diagnostic>) -> Labels {
    let mut out = Labels::default();
    let (dp, cp) = (p.braille_dot_pitch_mm as f64, p.braille_cell_mm as f64);
    let r = p.braille_dot_mm as f64 / 2.0;
    let gap = p.min_gap_mm as f64;
    let emboss = p.medium == Medium::Emboss;
    for (i, e) in drawing.elements.iter().enumerate().filter(|(_, e)| e.visible) {
        let Shape::Text(t) = &e.shape else { continue };
        if !e.styles.iter().any(|s| matches!(s, crate::annotation::Style::Braille(_))) {
            continue;
        }
        // One braille line per run that starts a line; continuing runs join it.
        let mut lines: Vec<(f64, f64, f64, String)> = Vec::new();
        for run in &t.runs {
            match lines.last_mut() {
                Some(last) if run.continues => last.3.push_str(&run.text),
                _ => lines.push((run.x_mm, run.y_mm, run.anchor, run.text.clone())),
            }
        }
        if lines.is_empty()
            && !t.content.is_empty()
            && let Some(b) = e.bounds()
        {
            lines.push((b.0, b.3, 0.0, t.content.clone()));
        }
        for (x, y, anchor, text) in lines {
            let cells = cells(text.trim(), Some(e), diags);
            if cells.is_empty() || !(x.is_finite() && y.is_finite()) {
                continue;
            }
            let width = (cells.len() - 1) as f64 * cp + dp;
            // The first dot's centre: the run's start after its anchor, the
            // lowest dots resting on the baseline.
            let mut x0 = x + origin.0 - anchor * (width + 2.0 * r) + r;
            let mut y0 = y + origin.1 - r - 2.0 * dp;
            if emboss {
                let g = p.grid_mm as f64;
                x0 = snap(x0, origin.0, g);
                y0 = snap(y0, origin.1, g);
            }
            let dots = run_dots(p, &cells, x0, y0);
            out.marks.extend(dot_marks(p, &dots, Some(i)));
            out.boxes.push((x0 - r - gap, y0 - r - gap, x0 + width + r + gap, y0 + 2.0 * dp + r + gap));
            out.owners.push(i);
        }
    }
    out
}

/// The key page: the drawing's title, then each key code with the label it
/// stands for, a braille line each, wrapped at the printable width. Empty
/// when the drawing has no key codes.
pub(super) fn key_page(
    drawing: &Drawing,
    p: &PrintParams,
    origin: (f64, f64),
    diags: &mut Vec<Diagnostic>,
) -> Vec<Mark> {
    let key = crate::auto::key_line(drawing);
    let Some(entries) = key.strip_prefix("key: ") else { return Vec::new() };
    let mut lines: Vec<String> = Vec::new();
    if !drawing.title.is_empty() {
        lines.push(drawing.title.clone());
    }
    lines.push("key".to_string());
    lines.extend(entries.split(", ").map(str::to_string));
    let (cp, lp) = (p.braille_cell_mm as f64, p.braille_line_mm as f64);
    let r = p.braille_dot_mm as f64 / 2.0;
    let per_line = ((p.surface_mm().0 as f64 - 2.0 * r) / cp).floor().max(1.0) as usize;
    let max_lines = ((p.surface_mm().1 as f64) / lp).floor().max(1.0) as usize;
    let mut marks = Vec::new();
    let mut row = 0usize;
    let mut cut = false;
    for text in lines {
        let cells = cells(&text, None, diags);
        for chunk in cells.chunks(per_line) {
            if row >= max_lines {
                cut = true;
                break;
            }
            let (mut x0, mut y0) = (origin.0 + r, origin.1 + r + row as f64 * lp);
            if p.medium == Medium::Emboss {
                x0 = snap(x0, origin.0, p.grid_mm as f64);
                y0 = snap(y0, origin.1, p.grid_mm as f64);
            }
            let dots = run_dots(p, chunk, x0, y0);
            marks.extend(dot_marks(p, &dots, None));
            row += 1;
        }
    }
    if cut {
        diags.push(Diagnostic::warning("T0727", "the key is longer than one page; its last lines are left out"));
    }
    marks
}
