//! Design rules on the pin grid: what a reader cannot tell apart once the
//! drawing is pins.
//!
//! - T0703: distinct elements with less than one blank pin between them
//!   (they are felt as one). On paper about 1/4 inch separates elements
//!   (`reference/primitives.md`); on a 2.5 mm pitch one blank pin is the
//!   least that keeps two raised pins apart at all, so that is the rule.
//! - T0704: a braille label that touches or cuts into graphics.
//! - T0709: a picture so dense that much of it is solid: most raised pins
//!   have every neighbour raised (a city plan of thousands of streets
//!   shrunk onto the display), where lines and textures are felt as one
//!   block. One warning for the drawing, since the pairs of T0703 run to
//!   thousands there and do not say that the whole is unreadable.
//!
//! (Textures the pitch cannot carry, T0705, and regions too small for their
//! texture, T0707, are reported where the textures are made.) Each pair is
//! found while pins are raised (a look at the 3 x 3 neighbourhood of every
//! raised pin), so the cost follows the pins, not the pairs of elements.

use crate::diagnostic::Diagnostic;
use crate::drawing::{Drawing, Shape};

use super::Canvas;

/// At most this many pairs are reported one by one per rule; a note counts the rest.
pub const MAX_REPORTED: usize = 20;

/// T0709: the share of raised pins buried in solid areas (every neighbour
/// raised) above which a picture is reported as too dense, and the fewest
/// such pins that count (a few solid bars of a chart stay below both: a
/// bar three pins wide buries a third of its pins).
pub const DENSE_SHARE: f64 = 0.5;
pub const DENSE_PINS: usize = 100;

/// T0709: how many raised pins have all eight neighbours raised, of how many raised.
fn buried(canvas: &Canvas) -> (usize, usize) {
    let (cols, rows) = (canvas.image.cols as i64, canvas.image.rows as i64);
    let up = |c: i64, r: i64| c >= 0 && r >= 0 && c < cols && r < rows && canvas.image.get(c as u32, r as u32).raised();
    let (mut buried, mut raised) = (0, 0);
    for r in 0..rows {
        for c in 0..cols {
            if up(c, r) {
                raised += 1;
                buried += (-1..=1).all(|dr| (-1..=1).all(|dc| up(c + dc, r + dr))) as usize;
            }
        }
    }
    (buried, raised)
}

pub(crate) fn check(canvas: &Canvas, drawing: &Drawing, diags: &mut Vec<Diagnostic>) {
    let name = |o: u32| drawing.elements.get(o as usize - 1).map_or("?", |e| e.name.as_str());
    let is_label = |o: u32| drawing.elements.get(o as usize - 1).is_some_and(|e| matches!(e.shape, Shape::Text(_)));
    let mut counts = [0usize; 2];
    for (&(a, b), &(c, r)) in &canvas.touching {
        let label = is_label(a) || is_label(b);
        let k = label as usize;
        counts[k] += 1;
        if counts[k] > MAX_REPORTED {
            continue;
        }
        let (first, second) = if is_label(b) && !is_label(a) { (b, a) } else { (a, b) };
        let line = drawing.elements.get(first as usize - 1).map_or(0, |e| e.line);
        let d = if label {
            Diagnostic::warning(
                "T0704",
                format!(
                    "the braille label {} collides with the graphics of {} at pin ({c}, {r}): \
                     less than one blank pin between them",
                    name(first),
                    name(second)
                ),
            )
            .with_help("move the label, or leave out the graphics under it")
        } else {
            // Two shapes of one element (a `<use>` of a group, a path and its
            // markers) share its name: "use1 and use1" read as a mistake.
            let which = if name(first) == name(second) {
                format!("two parts of {}", name(first))
            } else {
                format!("{} and {}", name(first), name(second))
            };
            Diagnostic::warning(
                "T0703",
                format!(
                    "{which} are less than one blank pin apart at pin ({c}, {r}): on the pin grid they are felt as one"
                ),
            )
            .with_help("move them apart, or leave one of them out on pin displays")
        };
        diags.push(d.with_element(name(first).to_string()).on_line(line));
    }
    let (solid, raised) = buried(canvas);
    if solid >= DENSE_PINS && solid as f64 > DENSE_SHARE * raised as f64 {
        diags.push(
            Diagnostic::warning(
                "T0709",
                format!(
                    "the picture is too dense for the pin grid: {solid} of its {raised} raised pins ({:.0} %) lie \
                     in solid areas, where its lines and textures are felt as one block",
                    100.0 * solid as f64 / raised as f64
                ),
            )
            .with_help(
                "take part of the drawing with --region, use a display with more pins, or leave out a kind of \
                 element with a style sheet (start from `taxel style auto INPUT`)",
            ),
        );
    }
    for (k, code) in [(0, "T0703"), (1, "T0704")] {
        if counts[k] > MAX_REPORTED {
            diags.push(Diagnostic::note(
                code,
                format!("{} more pairs like the above are not listed", counts[k] - MAX_REPORTED),
            ));
        }
    }
}
