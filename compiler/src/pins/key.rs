//! The key on a pin display: display-sized pages after the graphic's, each
//! texture, line style and point symbol of the key
//! ([`crate::style::legend()`]) felt as itself (a patch of its texture, a
//! sample of its line, its symbol's cluster) with its meaning in braille on
//! the cell grid to its right, then the key codes.
//!
//! The key is laid out as a small drawing of its own (swatches and braille
//! texts in page millimetres, on the display's cell grid) and drawn through
//! the same code as the graphic, with the graphic's texture patterns, so that
//! a swatch is pin for pin the texture, line or symbol of the graphic.

use taxel_format::{PinImage, PinParams};

use super::{Canvas, Draw};
use crate::diagnostic::Diagnostic;
use crate::drawing::{Drawing, Element, Page, Shape};
use crate::style::key_page::{self, SwatchBox};
use crate::style::legend::{Entry, Legend, Swatch};

/// Cells a swatch is wide (its columns: this many cell pitches less one).
const SWATCH_CELLS: u32 = 3;
/// Braille lines a swatch is high (less the gap under its last line).
const SWATCH_LINES: u32 = 2;

/// The key on pins: none, its pages, or too large for a pin image.
pub(crate) enum Key {
    /// The drawing needs no key.
    None,
    /// The key's pages as one image one display wide and a whole number of
    /// displays high (page *k* at rows `k * dev_rows ..`).
    Pages(PinImage),
    /// The key's pages would pass the pin image's limits.
    TooLarge,
}

/// The key's pages ([`Key`]). Brushed strokes are not in it: pins do not play them.
pub(crate) fn pages(
    drawing: &Drawing,
    legend: &Legend,
    how: &Draw<'_>,
    dev: (u32, u32),
    pitch: (f64, f64),
    notes: &mut crate::braille::Notes,
    diags: &mut Vec<Diagnostic>,
) -> Key {
    if !legend.needed() {
        return Key::None;
    }
    let p = how.params;
    let dev = (dev.0.max(2), dev.1.max(1));
    let lay = Layout::new(p, dev);
    let entries: Vec<&Entry> = legend.shown().iter().filter(|e| !matches!(e.swatch, Swatch::Stroke(_))).collect();
    let mut elements: Vec<Element> = Vec::new();
    let mut line = 0u32;
    let computer = p.cell_rows == 4;
    let width = |s: &str| crate::braille::translate(s, None, how.opts, None, computer).cells.len();
    // The heading, then each entry, then the key codes.
    for text in key_page::wrap("key", lay.full_cells(), &width) {
        elements.push(lay.text(&text, 0, line, pitch));
        line += 1;
    }
    for e in entries {
        let texts = key_page::wrap(&e.meaning, lay.beside_cells(), &width);
        let tall = (texts.len() as u32).max(SWATCH_LINES);
        line = lay.fit(line, tall);
        elements.push(swatch(e, drawing, &lay, line, pitch));
        for (n, t) in texts.iter().enumerate() {
            let mut el = lay.text(t, SWATCH_CELLS + 1, line + n as u32, pitch);
            if let Shape::Text(ts) = &mut el.shape {
                ts.lang = e.lang.clone();
            }
            elements.push(el);
        }
        // A blank line between entries, so that swatches are felt apart.
        line += tall + 1;
    }
    for code in legend.text_lines() {
        let texts = key_page::wrap(&code, lay.full_cells(), &width);
        line = lay.fit(line, texts.len() as u32);
        for t in texts {
            elements.push(lay.text(&t, 0, line, pitch));
            line += 1;
        }
    }
    let pages = (lay.top(line.saturating_sub(1)) / dev.1 + 1).max(1);
    let rows = pages as u64 * dev.1 as u64;
    if rows > taxel_format::MAX_PIN_SIDE as u64 || rows * dev.0 as u64 > taxel_format::MAX_PIN_IMAGE as u64 {
        return Key::TooLarge;
    }
    let rows = rows as u32;
    let page =
        Page { width_mm: dev.0 as f64 * pitch.0, height_mm: rows as f64 * pitch.1, scale: 1.0, ..Default::default() };
    let key = Drawing { page, title: String::new(), elements };
    let mut canvas = Canvas::new(dev.0, rows, pitch);
    // The key's own layout needs no design rules; what a reader would miss
    // (braille a table lacks, cells off the page) is still said.
    let mut own = Vec::new();
    super::draw(&mut canvas, &key, how, notes, &mut own);
    diags.extend(own.into_iter().filter(|d| d.code != "T0707"));
    Key::Pages(canvas.image)
}

/// Where the key's lines and swatches go on the display's cell grid.
struct Layout {
    /// Columns from one cell to the next, rows from one braille line to the next.
    cp: u32,
    lp: u32,
    cell_rows: u32,
    dev: (u32, u32),
}

impl Layout {
    fn new(p: &PinParams, dev: (u32, u32)) -> Self {
        Layout { cp: p.cell_pitch_cols().max(1), lp: p.line_pitch_rows().max(1), cell_rows: p.cell_rows as u32, dev }
    }

    /// Cells a line holds from cell `k0` on (the last cell's right dots inside the display).
    fn cells_from(&self, k0: u32) -> usize {
        let last = self.dev.0.saturating_sub(2) / self.cp;
        (last + 1).saturating_sub(k0).max(1) as usize
    }

    fn full_cells(&self) -> usize {
        self.cells_from(0)
    }

    fn beside_cells(&self) -> usize {
        self.cells_from(SWATCH_CELLS + 1)
    }

    /// The top row of braille line `l`.
    fn top(&self, l: u32) -> u32 {
        l * self.lp
    }

    /// The first line from `l` on where `n` lines fit on one display page
    /// (the next page's first line when they do not fit on this one).
    fn fit(&self, l: u32, n: u32) -> u32 {
        let page = self.top(l) / self.dev.1;
        let end = self.top(l + n.max(1) - 1) + self.cell_rows;
        if end <= (page + 1) * self.dev.1 || self.top(n) > self.dev.1 {
            return l;
        }
        ((page + 1) * self.dev.1).div_ceil(self.lp)
    }

    /// A braille text at cell `k` of line `l` (its run's baseline on the
    /// cells' bottom row, so that `text::place` puts it there).
    fn text(&self, s: &str, k: u32, l: u32, pitch: (f64, f64)) -> Element {
        let (c, r) = ((k * self.cp) as f64, (self.top(l) + self.cell_rows - 1) as f64);
        key_page::braille_text(s, (c + 0.5) * pitch.0, (r + 0.5) * pitch.1, None)
    }
}

/// The swatch of entry `e` at line `l` ([`key_page::swatch`]): a box
/// [`SWATCH_CELLS`] cells wide and [`SWATCH_LINES`] lines high; a line runs
/// along its middle row of pins, half a pin inside its ends, and a symbol is
/// a quarter pin either side of that row's middle pin.
fn swatch(e: &Entry, drawing: &Drawing, lay: &Layout, l: u32, pitch: (f64, f64)) -> Element {
    let (cols, rows) = (SWATCH_CELLS * lay.cp - 1, SWATCH_LINES * lay.lp - (lay.lp - lay.cell_rows).max(1));
    let y0 = lay.top(l) as f64 * pitch.1;
    let at = SwatchBox {
        rect: (0.0, y0, cols as f64 * pitch.0, y0 + rows as f64 * pitch.1),
        mid_y: ((lay.top(l) + rows / 2) as f64 + 0.5) * pitch.1,
        inset: 0.5 * pitch.0,
        half: pitch.0.min(pitch.1) / 4.0,
    };
    key_page::swatch(e, drawing, at)
}

/// Appends the key's pages (`key`, one display wide) below the graphic in
/// `image`: the graphic's rows rounded up to whole displays, then the key's
/// pages left to right across as many displays as the graphic is wide, a
/// band of display rows at a time, so that the reader's next pages are the
/// key. Returns the number of the key's first page (1-based, in the
/// row-major order `export::pages` gives) and how many it has; `None`,
/// leaving `image` as it was, when the image would pass the format's limits.
pub(crate) fn append(image: &mut PinImage, key: &PinImage, dev: (u32, u32)) -> Option<(u32, u32)> {
    let (w, h) = (dev.0.max(1), dev.1.max(1));
    let across = image.cols.div_ceil(w).max(1);
    let down = image.rows.div_ceil(h).max(1);
    let n = key.rows.div_ceil(h).max(1);
    let cols = across.checked_mul(w)?;
    let rows = down.checked_add(n.div_ceil(across))?.checked_mul(h)?;
    if cols > taxel_format::MAX_PIN_SIDE
        || rows > taxel_format::MAX_PIN_SIDE
        || cols as u64 * rows as u64 > taxel_format::MAX_PIN_IMAGE as u64
    {
        return None;
    }
    let mut out = PinImage::new(cols, rows);
    for r in 0..image.rows {
        for c in 0..image.cols {
            out.set(c, r, image.get(c, r));
        }
    }
    for k in 0..n {
        let (c0, r0) = ((k % across) * w, (down + k / across) * h);
        for r in 0..h.min(key.rows.saturating_sub(k * h)) {
            for c in 0..w.min(key.cols) {
                out.set(c0 + c, r0 + r, key.get(c, k * h + r));
            }
        }
    }
    out.blink_ms = image.blink_ms;
    out.navigation = image.navigation;
    out.text = std::mem::take(&mut image.text);
    *image = out;
    Some((across * down + 1, n))
}
