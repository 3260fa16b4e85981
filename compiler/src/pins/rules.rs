//! Design rules on the pin grid: what a reader cannot tell apart once the
//! drawing is pins.
//!
//! - T0703: distinct elements with less than one blank pin between them
//!   (they are felt as one). On paper about 1/4 inch separates elements
//!   (`reference/primitives.md`); on a 2.5 mm pitch one blank pin is the
//!   least that keeps two raised pins apart at all, so that is the rule.
//! - T0704: a braille label that touches or cuts into graphics.
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
    for (k, code) in [(0, "T0703"), (1, "T0704")] {
        if counts[k] > MAX_REPORTED {
            diags.push(Diagnostic::note(
                code,
                format!("{} more pairs like the above are not listed", counts[k] - MAX_REPORTED),
            ));
        }
    }
}
