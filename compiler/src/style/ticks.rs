//! A chart's tick labels thinned to an even step (T0328): where the
//! braille of an axis's labels, each at its own place, would run into the
//! next one's, every other label is kept, or every fifth, tenth or
//! twentieth, the first step at which the kept ones stand clear of each
//! other. A reader follows an axis by labels at an even step, as a
//! transcriber labels a tactile chart's axis; placed one by one in document
//! order, the labels that happened to find room first were kept instead
//! (the first, third, fourth and seventh), and the rest left out or piled
//! under the axis.

use super::labels::braille_boxes;
use super::{BRAILLE_CLEARANCE_MM, Measure};
use crate::drawing::TextShape;
use crate::spatial::{self, Bbox};

/// The steps tried, smallest first: every other label, every fifth, tenth
/// and twentieth (an axis's values are counted in twos, fives and tens).
const STEPS: [usize; 4] = [2, 5, 10, 20];

/// Fewest labels that make an axis, and fewest kept on one.
const MIN_TICKS: usize = 4;
const MIN_KEPT: usize = 2;

/// Most ratio of an axis's widest gap between neighbouring labels to its
/// narrowest: an axis's ticks are evenly spaced (a category axis's too).
const MAX_GAP_RATIO: f64 = 1.5;

/// Whether `text` reads as a tick label: a number, with its sign, decimal
/// and thousands marks, a unit or currency sign, a percentage, a time or a
/// degree (`-2.5`, `1,000`, `€40`, `75 %`, `10:30`, `45°`).
fn tick_like(text: &str) -> bool {
    let t = text.trim();
    !t.is_empty()
        && t.chars().count() <= 10
        && t.chars().any(|c| c.is_ascii_digit())
        && t.chars()
            .all(|c| c.is_ascii_digit() || " +-\u{2212}\u{2013}.,:%$\u{20ac}\u{a3}\u{a5}\u{b0}'\u{2032}".contains(c))
}

/// Whether two boxes meet.
fn meet(a: Bbox, b: Bbox) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

/// The labels of `texts` (element, text) to leave out, each with the step
/// its axis was thinned to. An axis is a row (same baseline) or a column
/// (same anchor point across) of at least [`MIN_TICKS`] tick-like labels
/// of one size, evenly spaced, each one line; it is thinned only when the
/// braille of two neighbours at their own places would meet.
pub(super) fn thin(texts: &[(usize, &TextShape)], m: Measure<'_>) -> Vec<(usize, usize)> {
    // (element, along the axis, braille box at its own place), by axis.
    type Tick = (usize, f64, Bbox);
    let mut rows: Vec<((i64, i64), Vec<Tick>)> = Vec::new();
    let mut cols: Vec<((i64, i64, i64), Vec<Tick>)> = Vec::new();
    for &(i, t) in texts {
        let runs: Vec<_> = t.runs.iter().filter(|r| !r.text.trim().is_empty()).collect();
        let [run] = runs[..] else { continue };
        if !tick_like(&run.text) {
            continue;
        }
        let Some(&b) = braille_boxes(std::slice::from_ref(run), Some(t), m).first() else { continue };
        // Keys in hundredths of a millimetre (quarter millimetres for the line).
        let size = (t.font_size_mm * 100.0).round() as i64;
        let row = (size, (run.y_mm * 4.0).round() as i64);
        match rows.iter_mut().find(|(k, _)| *k == row) {
            Some((_, v)) => v.push((i, run.x_mm, b)),
            None => rows.push((row, vec![(i, run.x_mm, b)])),
        }
        let col = (size, (run.x_mm * 4.0).round() as i64, (run.anchor * 100.0).round() as i64);
        match cols.iter_mut().find(|(k, _)| *k == col) {
            Some((_, v)) => v.push((i, run.y_mm, b)),
            None => cols.push((col, vec![(i, run.y_mm, b)])),
        }
    }
    let mut out: Vec<(usize, usize)> = Vec::new();
    for mut axis in rows.into_iter().map(|r| r.1).chain(cols.into_iter().map(|c| c.1)) {
        // A label already thinned on one axis is not counted on another.
        axis.retain(|t| !out.iter().any(|&(i, _)| i == t.0));
        if axis.len() < MIN_TICKS {
            continue;
        }
        axis.sort_by(|a, b| a.1.total_cmp(&b.1));
        let gaps: Vec<f64> = axis.windows(2).map(|w| w[1].1 - w[0].1).collect();
        let (lo, hi) = gaps.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &g| (lo.min(g), hi.max(g)));
        if !(lo > 0.0 && hi <= MAX_GAP_RATIO * lo) {
            continue;
        }
        let clear = |step: usize| {
            let kept: Vec<Bbox> = axis.iter().step_by(step).map(|t| spatial::grow(t.2, BRAILLE_CLEARANCE_MM)).collect();
            kept.windows(2).all(|w| !meet(w[0], w[1]))
        };
        if clear(1) {
            continue;
        }
        let Some(step) = STEPS.into_iter().find(|&s| axis.len().div_ceil(s) >= MIN_KEPT && clear(s)) else { continue };
        out.extend(axis.iter().enumerate().filter(|(k, _)| k % step != 0).map(|(_, t)| (t.0, step)));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::tick_like;

    #[test]
    fn numbers_units_and_times_are_tick_labels_and_words_are_not() {
        for t in ["0", "-2.5", "1,000", "\u{2212}40", "75 %", "\u{20ac}40", "10:30", "45\u{b0}", " 2020 "] {
            assert!(tick_like(t), "{t:?}");
        }
        for t in ["", "Paris", "Q1", "2020 sales", "x", "12345678901", "3 km"] {
            assert!(!tick_like(t), "{t:?}");
        }
    }
}
