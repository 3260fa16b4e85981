//! Braille on paper: the cells the compiler makes for a label
//! (`crate::braille`, the same as on every device), drawn as
//! round dots at the medium's dimensions (base diameter, dot spacing, cell
//! spacing, line spacing), never through a font. A label's cells start where
//! its text starts (after its anchor) and stand on its baseline. The key
//! pages are `key.rs`'s.

use taxel_format::{Medium, PrintParams};

use super::{Level, Mark, MarkShape};
use crate::CompileOptions;
use crate::braille::Notes;
use crate::diagnostic::Diagnostic;
use crate::drawing::{Drawing, Element, Shape, TextShape};

/// The labels' braille: its dots, and the box of each label (paper mm,
/// grown by the medium's minimum gap) that textures are cleared from.
#[derive(Debug, Default)]
pub(super) struct Labels {
    pub marks: Vec<Mark>,
    pub boxes: Vec<(f64, f64, f64, f64)>,
    /// The element of each box.
    pub owners: Vec<usize>,
}

/// Translates `text` as the other devices do (`crate::braille`: liblouis
/// where it is, contracted where the language has it, else the built-in UEB
/// grade 1), warning (T0304) about characters left out; six-dot cells.
pub(super) fn cells(
    text: &str,
    ask: (Option<&TextShape>, Option<u8>),
    e: Option<&Element>,
    cx: &mut Cx<'_>,
) -> Vec<u8> {
    let t = crate::braille::translate(text, ask.0, cx.opts, ask.1, false);
    // (A key code's grade 1 is taxel's choice, not the reader's: no note for it.)
    if ask.0.is_none_or(|s| s.keyed.is_none()) {
        cx.notes.add(&t);
    }
    let mut cells = crate::braille::cells_warning_missing(text, t, e, cx.diags);
    // Paper has six-dot cells: an eight-dot table's dots 7 and 8 are not drawn.
    for c in &mut cells {
        *c &= 0x3f;
    }
    cells
}

/// What braille is written with, and where its notes and diagnostics go.
pub(super) struct Cx<'a> {
    pub opts: &'a CompileOptions,
    pub notes: &'a mut Notes,
    pub diags: &'a mut Vec<Diagnostic>,
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

pub(super) fn dot_marks(p: &PrintParams, dots: &[(f64, f64)], elem: Option<usize>) -> impl Iterator<Item = Mark> {
    let d = p.braille_dot_mm as f64;
    dots.iter().map(move |&c| Mark {
        shape: MarkShape::Dot { centre: c, diameter_mm: d },
        level: Level::Braille,
        element: elem,
    })
}

/// The braille of every visible label with a `braille` style.
pub(super) fn labels(drawing: &Drawing, p: &PrintParams, origin: (f64, f64), cx: &mut Cx<'_>) -> Labels {
    let mut out = Labels::default();
    let (dp, cp) = (p.braille_dot_pitch_mm as f64, p.braille_cell_mm as f64);
    let r = p.braille_dot_mm as f64 / 2.0;
    let gap = p.min_gap_mm as f64;
    let emboss = p.medium == Medium::Emboss;
    for (i, e) in drawing.elements.iter().enumerate().filter(|(_, e)| e.visible) {
        let Shape::Text(t) = &e.shape else { continue };
        let Some(grade) = e.styles.iter().find_map(|s| match s {
            crate::annotation::Style::Braille(b) => Some(b.grade),
            _ => None,
        }) else {
            continue;
        };
        // A key code is letters, not a word: uncontracted.
        let grade = if t.keyed.is_some() { Some(1) } else { grade };
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
            let cells = cells(text.trim(), (Some(t), grade), Some(e), cx);
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
