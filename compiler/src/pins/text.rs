//! Braille on the pin grid: labels placed on the device's own cell grid, and
//! the drawing's title on the device's text line.
//!
//! The cell grid starts at the image's top-left pin: cell *k* of line *l*
//! has its top-left dot at pin `(k * (2 + cell_gap_cols), l * (cell_rows +
//! line_gap_rows))`, so on a paged image whose display is a whole number of
//! cells wide every page starts on the grid too. A label goes to the grid
//! cell nearest to where its text starts, on the line whose cells stand on
//! its baseline, and reads left to right from there; one that would run off
//! the image's side is pulled back inside, whole, while it still covers
//! where it began. The braille is the shared service's
//! ([`crate::braille`]): the label's language's literary braille on a
//! six-dot cell, and on an eight-dot cell the language's eight-dot computer
//! braille where liblouis has it (as the displays' own screen readers
//! write text on eight-dot cells), its literary braille otherwise. The
//! device's text line is six-dot literary braille (the Dot Pad's).

use crate::braille::Notes;
use crate::diagnostic::Diagnostic;
use crate::drawing::{Element, TextShape};
use crate::options::CompileOptions;
use taxel_format::PinParams;

use super::Canvas;

/// A label to place: its text, the grade its style asks for, and its element.
pub(crate) struct Label<'a> {
    /// The text.
    pub text: &'a TextShape,
    /// `braille(grade: ..)`.
    pub grade: Option<u8>,
    /// The element's index (provenance).
    pub elem: usize,
    /// The pins' height.
    pub height: u8,
    /// The element.
    pub e: &'a Element,
}

/// Dot `k` (0-based bit of a Unicode braille mask) at `(column, row)` within its cell.
pub const DOT_POSITIONS: [(u32, u32); 8] = [(0, 0), (0, 1), (0, 2), (1, 0), (1, 1), (1, 2), (0, 3), (1, 3)];

/// How a text is to be written: its shape (language), grade, and whether in eight-dot computer braille.
struct Ask<'a> {
    shape: Option<&'a TextShape>,
    grade: Option<u8>,
    computer: bool,
}

/// Translates `text` to cells, warning about characters left out.
fn cells(
    text: &str,
    ask: Ask<'_>,
    e: Option<&Element>,
    opts: &CompileOptions,
    notes: &mut Notes,
    diags: &mut Vec<Diagnostic>,
) -> Vec<u8> {
    let t = crate::braille::translate(text, ask.shape, opts, ask.grade, ask.computer);
    // (A key code's grade 1 is taxel's choice, not the reader's: no note for it.)
    if ask.shape.is_none_or(|s| s.keyed.is_none()) {
        notes.add(&t);
    }
    crate::braille::cells_warning_missing(text, t, e, diags)
}

/// Places a label's braille on the cell grid, over whatever graphics are
/// there once the texture under it and one pin around it is cleared (the
/// design rules report a collision with other graphics).
pub(crate) fn place(
    canvas: &mut Canvas,
    params: &PinParams,
    label: &Label<'_>,
    opts: &CompileOptions,
    notes: &mut Notes,
    diags: &mut Vec<Diagnostic>,
) {
    let (t, elem, height, e) = (label.text, label.elem, label.height, label.e);
    let (cp, lp) = (params.cell_pitch_cols() as f64, params.line_pitch_rows() as f64);
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
    let mut off_image = false;
    for (x, y, anchor, text) in lines {
        // A key code is letters, not a word: uncontracted.
        let grade = if t.keyed.is_some() { Some(1) } else { label.grade };
        let ask = Ask { shape: Some(t), grade, computer: params.cell_rows == 4 };
        let cells = cells(text.trim(), ask, Some(e), opts, notes, diags);
        if cells.is_empty() {
            continue;
        }
        let width_pins = cells.len() as f64 * cp;
        let (px, py) = canvas.to_pins((x, y));
        // The text's start (after its anchor), and the top of cells standing on the baseline.
        let start = px - anchor * width_pins;
        let top = py - (params.cell_rows as f64 - 1.0);
        let (k0, l) = ((start / cp).round(), (top / lp).round());
        if !(k0.is_finite() && l.is_finite()) {
            continue;
        }
        let (k0, l) = (k0.clamp(-1e9, 1e9) as i64, l.clamp(-1e9, 1e9) as i64);
        // A label that runs off the image's side (a town on a fitted map's
        // east coast: the device's cells are wider than the page's braille)
        // is pulled back inside, whole, while it still covers where it began.
        let n = cells.len() as i64;
        let last = (canvas.image.cols as i64 - 2).div_euclid(cp as i64);
        let k0 = if n - 1 <= last && k0 + n - 1 > last && k0 + n - 1 - last < n {
            last - (n - 1)
        } else if n - 1 <= last && k0 < 0 && -k0 < n {
            0
        } else {
            k0
        };
        // The texture under the label and one pin around it is cleared, as
        // transcribers clear an area's texture around its label: braille
        // amid ridges reads as more ridges. (Outlines and dots stay; T0704
        // reports a label on them.)
        let (r0, c_first, c_last) = (l * lp as i64, k0 * cp as i64, (k0 + n - 1) * cp as i64 + 1);
        for r in r0 - 1..=r0 + params.cell_rows as i64 {
            for c in c_first - 1..=c_last + 1 {
                canvas.clear_texture((c, r));
            }
        }
        for (k, &cell) in cells.iter().enumerate() {
            let c0 = (k0 + k as i64) * cp as i64;
            let r0 = l * lp as i64;
            if c0 < 0
                || r0 < 0
                || c0 + 1 >= canvas.image.cols as i64
                || r0 + params.cell_rows as i64 > canvas.image.rows as i64
            {
                off_image = true;
                continue;
            }
            for (bit, &(dc, dr)) in DOT_POSITIONS.iter().enumerate().take(params.cell_rows as usize * 2) {
                let p = (c0 + dc as i64, r0 + dr as i64);
                if cell & (1 << bit) != 0 {
                    canvas.raise(p, elem, height, false);
                } else {
                    // A dot that is down in the cell must read as down, whatever graphics lie under it.
                    canvas.lower(p, elem);
                }
            }
        }
    }
    if off_image {
        diags.push(
            Diagnostic::warning("T0708", "braille cells of this label fall off the pin image and are left out")
                .with_element(e.name.clone())
                .with_help("move the label inside the drawing, or shorten it")
                .on_line(e.line),
        );
    }
}

/// The title as text-line cells (six-dot masks).
pub(crate) fn text_line(title: &str, opts: &CompileOptions, notes: &mut Notes, diags: &mut Vec<Diagnostic>) -> Vec<u8> {
    let ask = Ask { shape: None, grade: None, computer: false };
    let mut c = cells(title.trim(), ask, None, opts, notes, diags);
    // A six-dot line: an eight-dot table's dots 7 and 8 cannot be written.
    for cell in &mut c {
        *cell &= 0x3f;
    }
    c.truncate(taxel_format::MAX_TEXT_CELLS as usize);
    c
}
