//! The pieces a key is drawn from when a back end lays the key
//! ([`super::legend()`]) out as a small drawing of its own: an entry's
//! swatch, felt as the graphic has it, a braille text, and the wrapping of a
//! meaning into lines. The pin displays draw that drawing on their key pages
//! (`pins/key.rs`); the laterotactile arrays and vibrotactile grids compile
//! it as a second bundle (`latero/key.rs`). Each back end keeps its own
//! layout (a pin display's cell grid, an array's surface), so that only
//! what a swatch and a text are is shared.

use crate::annotation::{Braille, Style};
use crate::drawing::{Drawing, Element, PathShape, Shape, TextRun, TextShape};
use crate::geometry::Polyline;

use super::legend::{Entry, Swatch};

/// Where an entry's swatch goes: its box `(x0, y0, x1, y1)` in page mm, the
/// height a line runs at and a symbol sits at (`mid_y`), how far a line or
/// dotted line stays inside the box's ends (`inset`), and the half side of a
/// symbol's square (`half`).
#[derive(Debug, Clone, Copy)]
pub struct SwatchBox {
    /// The box, page mm.
    pub rect: (f64, f64, f64, f64),
    /// The height of a line across the box and of a symbol's middle, page mm.
    pub mid_y: f64,
    /// How far a line stays inside the box's left and right sides, mm.
    pub inset: f64,
    /// Half the side of a symbol's square, mm.
    pub half: f64,
}

/// The swatch of entry `e` in `at`: its texture over the box, its line or
/// dots across the box at `mid_y`, its symbol there at the box's middle, or
/// its brushed stroke across it. Named as the entry's first element of `drawing`, so
/// that a message names that, and labelled with the entry's meaning, so
/// that a host says it when the finger is on it.
pub fn swatch(e: &Entry, drawing: &Drawing, at: SwatchBox) -> Element {
    let (x0, y0, x1, y1) = at.rect;
    let ym = at.mid_y;
    let across = Polyline { points: vec![(x0 + at.inset, ym), (x1 - at.inset, ym)], closed: false };
    let (xm, h) = ((x0 + x1) / 2.0, at.half);
    let (outline, style) = match e.swatch {
        Swatch::Texture(g) => {
            (Polyline { points: vec![(x0, y0), (x1, y0), (x1, y1), (x0, y1)], closed: true }, Style::Grating(g))
        }
        Swatch::Line(v) => (across, Style::Vibrate(v)),
        Swatch::Dotted(d) => (across, Style::Dots(d)),
        Swatch::Symbol(d) => (
            Polyline {
                points: vec![(xm - h, ym - h), (xm + h, ym - h), (xm + h, ym + h), (xm - h, ym + h)],
                closed: true,
            },
            Style::Dot(d),
        ),
        Swatch::Stroke(b) => (across, Style::Brush(b)),
    };
    let first = e.elements.first().and_then(|&i| drawing.elements.get(i));
    Element {
        name: first.map_or("key".to_string(), |x| x.name.clone()),
        id: first.map(|x| x.id.clone()).unwrap_or_default(),
        label: e.meaning.clone(),
        visible: true,
        styles: vec![style],
        shape: Shape::Path(PathShape { outline: vec![outline], ..Default::default() }),
        ..Default::default()
    }
}

/// A braille text `s` (of language `lang`) whose first cell starts at
/// `x_mm` and whose run's baseline is `y_mm`, named `key`.
pub fn braille_text(s: &str, x_mm: f64, y_mm: f64, lang: Option<String>) -> Element {
    let run = TextRun { text: s.to_string(), x_mm, y_mm, anchor: 0.0, continues: false };
    Element {
        name: "key".into(),
        label: s.to_string(),
        visible: true,
        styles: vec![Style::Braille(Braille { radius_mm: 0.72, amplitude: 1.0, grade: None })],
        shape: Shape::Text(TextShape {
            content: s.to_string(),
            runs: vec![run],
            font_size_mm: 4.0,
            lang,
            ..Default::default()
        }),
        ..Default::default()
    }
}

/// `text` cut into lines of at most `per_line` cells as `width` measures
/// them, at spaces (a word longer than a line stands alone).
pub fn wrap(text: &str, per_line: usize, width: &dyn Fn(&str) -> usize) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut cur = String::new();
    for w in text.split_whitespace() {
        let with = if cur.is_empty() { w.to_string() } else { format!("{cur} {w}") };
        if cur.is_empty() || width(&with) <= per_line {
            cur = with;
        } else {
            out.push(std::mem::take(&mut cur));
            cur = w.to_string();
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_meaning_wraps_at_spaces_and_a_long_word_stands_alone() {
        let cells = |s: &str| s.chars().count();
        assert_eq!(wrap("deciduous forest and heath", 10, &cells), ["deciduous", "forest and", "heath"]);
        assert_eq!(wrap("photosynthesis is", 5, &cells), ["photosynthesis", "is"]);
        assert!(wrap("  ", 5, &cells).is_empty());
    }
}
