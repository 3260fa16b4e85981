//! Lines, dotted lines, point symbols and arrows: the marks of every style
//! but textures and braille.
//!
//! Several vibrating styles in one drawing are told apart on paper by line
//! style, in order of first use: solid, dashed, double, dotted ([`LineStyle`]).
//! Dot styles get point symbols of distinct shapes in the same way
//! ([`SYMBOLS`]). Sizes never fall below the medium's minimum line width and
//! symbol size; where a style asked for less, a note says what was widened.

use std::collections::HashMap;

use taxel_format::PrintParams;

use super::{Level, Mark, MarkShape};
use crate::annotation::Vibrate;
use crate::diagnostic::Diagnostic;
use crate::drawing::Drawing;
use crate::geometry::Polyline;

/// The line styles, in the order vibrating styles take them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineStyle {
    /// One solid line.
    Solid,
    /// Dashes [`DASH_MM`] long with gaps of the medium's minimum gap.
    Dashed,
    /// Two parallel lines.
    Double,
    /// Round dots.
    Dotted,
}

/// The styles a drawing's vibrating styles take, in order of first use.
pub const LINE_STYLES: [LineStyle; 4] = [LineStyle::Solid, LineStyle::Dashed, LineStyle::Double, LineStyle::Dotted];

/// Length of a dash (chosen: twice the gap that follows it on swell paper,
/// long enough to be felt as a line and not as a dot).
pub const DASH_MM: f64 = 6.0;

/// Point symbol shapes, in the order dot styles take them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Symbol {
    /// A filled disc.
    Disc,
    /// A filled square.
    Square,
    /// A filled triangle, point up.
    Triangle,
    /// A filled diamond.
    Diamond,
    /// A ring (a circle's outline).
    Ring,
    /// A cross of two lines.
    Cross,
}

/// The symbols dot styles take, in order of first use.
pub const SYMBOLS: [Symbol; 6] =
    [Symbol::Disc, Symbol::Square, Symbol::Triangle, Symbol::Diamond, Symbol::Ring, Symbol::Cross];

/// Arrowhead length and width at a brushed stroke's end (chosen: as large as
/// a point symbol, so that it is not felt as a thickening of the line).
const ARROW_LEN_FACTOR: f64 = 1.0;

pub(super) struct Builder<'d> {
    pub marks: Vec<Mark>,
    params: PrintParams,
    origin: (f64, f64),
    drawing: &'d Drawing,
    /// Vibrating styles in order of first use, by `(width, freq)` bits.
    line_styles: Vec<(u64, u64)>,
    /// Dot styles in order of first use, by radius bits.
    symbol_styles: Vec<u64>,
    /// Elements whose line was widened to the medium's minimum.
    widened: Vec<usize>,
    /// The point symbols placed, by cell of [`SYMBOL_CELL_MM`]: centre and size.
    placed: HashMap<(i64, i64), Vec<Placed>>,
    /// The largest symbol placed, mm.
    largest: f64,
    /// Point symbols left out because they would touch one placed before
    /// (how many, and the elements of the first three).
    crowded: (usize, Vec<usize>),
}

/// A placed point symbol: its centre and size, mm.
type Placed = ((f64, f64), f64);

/// The side of the cells placed symbols are found by, mm.
const SYMBOL_CELL_MM: f64 = 8.0;

impl<'d> Builder<'d> {
    pub fn new(drawing: &'d Drawing, params: &PrintParams, origin: (f64, f64)) -> Self {
        Builder {
            marks: Vec::new(),
            params: *params,
            origin,
            drawing,
            line_styles: Vec::new(),
            symbol_styles: Vec::new(),
            widened: Vec::new(),
            placed: HashMap::new(),
            largest: 0.0,
            crowded: (0, Vec::new()),
        }
    }

    fn at(&self, p: (f64, f64)) -> (f64, f64) {
        (p.0 + self.origin.0, p.1 + self.origin.1)
    }

    fn push(&mut self, shape: MarkShape, level: Level, elem: usize) {
        self.marks.push(Mark { shape, level, element: Some(elem) });
    }

    fn line(&mut self, points: Vec<(f64, f64)>, closed: bool, width_mm: f64, elem: usize) {
        if points.len() >= 2 || (points.len() == 1 && !closed) {
            self.push(MarkShape::Line { points, closed, width_mm }, Level::Line, elem);
        }
    }

    fn dot(&mut self, centre: (f64, f64), diameter_mm: f64, elem: usize) {
        self.push(MarkShape::Dot { centre, diameter_mm }, Level::Line, elem);
    }

    /// A vibrating outline: a line of the style's width (at least the
    /// medium's), in the line style of its vibrating style.
    pub fn outline(&mut self, elem: usize, polys: &[Polyline], v: &Vibrate) {
        let key = (v.width_mm.to_bits(), v.freq_hz.to_bits());
        let k = match self.line_styles.iter().position(|s| *s == key) {
            Some(k) => k,
            None => {
                self.line_styles.push(key);
                self.line_styles.len() - 1
            }
        };
        let min = self.params.min_line_mm as f64;
        let want = if v.width_mm.is_finite() { v.width_mm } else { min };
        if want < min && !self.widened.contains(&elem) {
            self.widened.push(elem);
        }
        let width = want.clamp(min, 10.0 * min.max(1.0));
        let gap = self.params.min_gap_mm as f64;
        let style = LINE_STYLES[k % LINE_STYLES.len()];
        for pl in polys {
            let pts: Vec<(f64, f64)> = pl.points.iter().map(|&p| self.at(p)).collect();
            match style {
                LineStyle::Solid => self.line(pts, pl.closed, width, elem),
                LineStyle::Dashed => {
                    for dash in dashes(&pts, pl.closed, DASH_MM.max(2.0 * gap), gap) {
                        self.line(dash, false, width, elem);
                    }
                }
                LineStyle::Double => {
                    // Two lines of the minimum width with half the minimum gap between them.
                    let w = min;
                    let off = (w + gap / 2.0) / 2.0;
                    for side in [-1.0, 1.0] {
                        let shifted = offset(&pts, pl.closed, side * off);
                        self.line(shifted, pl.closed, w, elem);
                    }
                }
                LineStyle::Dotted => {
                    let d = (2.0 * width).max(self.params.braille_dot_mm as f64);
                    for c in along(&pts, pl.closed, d + gap / 2.0) {
                        self.dot(c, d, elem);
                    }
                }
            }
        }
    }

    /// A dotted outline: dots of the style's diameter (at least the
    /// minimum line width), a gap of at least half the minimum gap apart.
    pub fn dotted(&mut self, elem: usize, polys: &[Polyline], radius_mm: f64, spacing: Option<f64>) {
        let min = self.params.min_line_mm as f64;
        let d = if radius_mm.is_finite() { (2.0 * radius_mm).clamp(min, 20.0) } else { min };
        let least = d + self.params.min_gap_mm as f64 / 2.0;
        let step = spacing.filter(|s| s.is_finite()).unwrap_or(3.0 * d / 2.0).clamp(least, 1000.0);
        for pl in polys {
            let pts: Vec<(f64, f64)> = pl.points.iter().map(|&p| self.at(p)).collect();
            for c in along(&pts, pl.closed, step) {
                self.dot(c, d, elem);
            }
        }
    }

    /// Point symbols at `centres`, the shape of the dot style, at least the medium's symbol size.
    pub fn symbols(&mut self, elem: usize, centres: &[(f64, f64)], radius_mm: f64) {
        let key = radius_mm.to_bits();
        let k = match self.symbol_styles.iter().position(|s| *s == key) {
            Some(k) => k,
            None => {
                self.symbol_styles.push(key);
                self.symbol_styles.len() - 1
            }
        };
        let size =
            if radius_mm.is_finite() { (2.0 * radius_mm).clamp(self.params.symbol_mm as f64, 50.0) } else { 0.0 };
        let size = size.max(self.params.symbol_mm as f64);
        for &c in centres {
            let c = self.at(c);
            if !(c.0.is_finite() && c.1.is_finite()) {
                continue;
            }
            if self.touches_a_symbol(c, size) {
                self.crowded.0 += 1;
                if self.crowded.1.len() < 3 && !self.crowded.1.contains(&elem) {
                    self.crowded.1.push(elem);
                }
                continue;
            }
            let cell = ((c.0 / SYMBOL_CELL_MM).floor() as i64, (c.1 / SYMBOL_CELL_MM).floor() as i64);
            self.placed.entry(cell).or_default().push((c, size));
            self.largest = self.largest.max(size);
            self.symbol(SYMBOLS[k % SYMBOLS.len()], c, size, elem);
        }
    }

    /// Whether a symbol of `size` at `c` would come closer to one placed
    /// before than the medium's least gap (the outer circles of the two
    /// symbols, so that they are felt apart).
    fn touches_a_symbol(&self, c: (f64, f64), size: f64) -> bool {
        let gap = self.params.min_gap_mm as f64;
        let reach = (size + self.largest) / 2.0 + gap;
        let k = (reach / SYMBOL_CELL_MM).ceil() as i64;
        let (cx, cy) = ((c.0 / SYMBOL_CELL_MM).floor() as i64, (c.1 / SYMBOL_CELL_MM).floor() as i64);
        (cy - k..=cy + k).any(|y| {
            (cx - k..=cx + k).any(|x| {
                self.placed
                    .get(&(x, y))
                    .is_some_and(|v| v.iter().any(|&(o, s)| (o.0 - c.0).hypot(o.1 - c.1) < (size + s) / 2.0 + gap))
            })
        })
    }

    fn symbol(&mut self, s: Symbol, c: (f64, f64), size: f64, elem: usize) {
        let h = size / 2.0;
        let line = self.params.min_line_mm as f64;
        let poly = |pts: &[(f64, f64)]| MarkShape::Polygon {
            rings: vec![pts.iter().map(|p| (c.0 + p.0, c.1 + p.1)).collect()],
        };
        match s {
            Symbol::Disc => self.dot(c, size, elem),
            Symbol::Square => self.push(poly(&[(-h, -h), (h, -h), (h, h), (-h, h)]), Level::Line, elem),
            Symbol::Triangle => {
                let r = h * 1.15;
                self.push(poly(&[(0.0, -r), (r * 0.866, r * 0.5), (-r * 0.866, r * 0.5)]), Level::Line, elem)
            }
            Symbol::Diamond => {
                let r = h * 1.2;
                self.push(poly(&[(0.0, -r), (r, 0.0), (0.0, r), (-r, 0.0)]), Level::Line, elem)
            }
            Symbol::Ring => {
                let w = line.max(size / 6.0);
                let r = h - w / 2.0;
                let pts = (0..32)
                    .map(|k| {
                        let a = k as f64 * std::f64::consts::TAU / 32.0;
                        (c.0 + r * a.cos(), c.1 + r * a.sin())
                    })
                    .collect();
                self.line(pts, true, w, elem)
            }
            Symbol::Cross => {
                let w = line.max(size / 6.0);
                let r = h - w / 2.0;
                self.line(vec![(c.0 - r, c.1 - r), (c.0 + r, c.1 + r)], false, w, elem);
                self.line(vec![(c.0 - r, c.1 + r), (c.0 + r, c.1 - r)], false, w, elem);
            }
        }
    }

    /// A brushed stroke: its path as a line, an arrowhead at its end.
    pub fn arrow(&mut self, elem: usize, polys: &[Polyline]) {
        let width = (self.params.min_line_mm as f64).max(1.0);
        let len = self.params.symbol_mm as f64 * ARROW_LEN_FACTOR;
        for pl in polys {
            let pts: Vec<(f64, f64)> = pl.points.iter().map(|&p| self.at(p)).collect();
            self.line(pts.clone(), pl.closed, width, elem);
            // The direction of travel at the end: from the last point at least a head's length back.
            let Some(&tip) = pts.last() else { continue };
            let Some(&back) = pts.iter().rev().find(|p| (p.0 - tip.0).hypot(p.1 - tip.1) > 1e-6) else { continue };
            let (dx, dy) = (tip.0 - back.0, tip.1 - back.1);
            let n = dx.hypot(dy);
            let (ux, uy) = (dx / n, dy / n);
            let base = (tip.0 - ux * len, tip.1 - uy * len);
            let half = len * 0.45;
            let ring = vec![tip, (base.0 - uy * half, base.1 + ux * half), (base.0 + uy * half, base.1 - ux * half)];
            self.push(MarkShape::Polygon { rings: vec![ring] }, Level::Line, elem);
        }
    }

    /// The notes of what was widened (T0721) and of styles beyond what the
    /// medium tells apart (T0726).
    pub fn finish_notes(&self, diags: &mut Vec<Diagnostic>) {
        if let Some(&first) = self.widened.first() {
            let e = &self.drawing.elements[first];
            diags.push(
                Diagnostic::note(
                    "T0721",
                    format!(
                        "{} vibrating line(s) narrower than the medium's {} mm are printed {} mm wide",
                        self.widened.len(),
                        self.params.min_line_mm,
                        self.params.min_line_mm
                    ),
                )
                .with_element(e.name.clone())
                .on_line(e.line),
            );
        }
        if let Some(&first) = self.crowded.1.first() {
            let e = &self.drawing.elements[first];
            let named: Vec<String> =
                self.crowded.1.iter().map(|&i| format!("#{}", self.drawing.elements[i].name)).collect();
            diags.push(
                Diagnostic::note(
                    "T0728",
                    format!(
                        "{} point symbol(s) left out where they would touch one already placed \
                         (closer than the medium's {} mm gap): {}",
                        self.crowded.0,
                        self.params.min_gap_mm,
                        named.join(", ")
                    ),
                )
                .with_help("take part of the drawing with --region so that the marks spread out")
                .with_element(e.name.clone())
                .on_line(e.line),
            );
        }
        if self.line_styles.len() > LINE_STYLES.len() {
            diags.push(Diagnostic::warning(
                "T0726",
                format!(
                    "{} vibrating styles, but paper tells {} line styles apart (solid, dashed, double, dotted): \
                     some styles share one",
                    self.line_styles.len(),
                    LINE_STYLES.len()
                ),
            ));
        }
        if self.symbol_styles.len() > SYMBOLS.len() {
            diags.push(Diagnostic::warning(
                "T0726",
                format!(
                    "{} dot styles, but there are {} point symbols: some styles share one",
                    self.symbol_styles.len(),
                    SYMBOLS.len()
                ),
            ));
        }
    }
}

/// Segment lengths of a polyline (closed: with the closing segment).
fn segments(pts: &[(f64, f64)], closed: bool) -> Vec<((f64, f64), (f64, f64))> {
    let mut out: Vec<_> = pts.windows(2).map(|w| (w[0], w[1])).collect();
    if closed && pts.len() > 2 {
        out.push((pts[pts.len() - 1], pts[0]));
    }
    out.retain(|(a, b)| (b.0 - a.0).hypot(b.1 - a.1).is_finite());
    out
}

/// Points every `step` mm along a polyline, from its start (a closed one's
/// last point kept half a step from its first).
pub(super) fn along(pts: &[(f64, f64)], closed: bool, step: f64) -> Vec<(f64, f64)> {
    let segs = segments(pts, closed);
    let total: f64 = segs.iter().map(|(a, b)| (b.0 - a.0).hypot(b.1 - a.1)).sum();
    if !(total.is_finite() && step > 0.0) {
        return Vec::new();
    }
    if total == 0.0 {
        return pts.first().copied().into_iter().collect();
    }
    let n = ((total / step).floor() as usize).min(1_000_000);
    let end = if closed { total - step / 2.0 } else { total + 1e-9 };
    let mut out = Vec::with_capacity(n + 1);
    let (mut k, mut walked) = (0usize, 0.0);
    for (a, b) in segs {
        let len = (b.0 - a.0).hypot(b.1 - a.1);
        while k <= n && (k as f64 * step) <= walked + len && (k as f64 * step) <= end {
            let t = if len > 0.0 { (k as f64 * step - walked) / len } else { 0.0 };
            out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
            k += 1;
        }
        walked += len;
    }
    out
}

/// Dashes `dash` mm long with `gap` mm between them along a polyline.
fn dashes(pts: &[(f64, f64)], closed: bool, dash: f64, gap: f64) -> Vec<Vec<(f64, f64)>> {
    let period = dash + gap;
    let mut out = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    let mut walked = 0.0;
    for (a, b) in segments(pts, closed) {
        let len = (b.0 - a.0).hypot(b.1 - a.1);
        let mut s = 0.0;
        while s < len {
            let phase = (walked + s) % period;
            let on = phase < dash;
            let next = if on { dash - phase } else { period - phase };
            let e = (s + next).min(len);
            let p = |t: f64| (a.0 + t / len * (b.0 - a.0), a.1 + t / len * (b.1 - a.1));
            if on {
                if cur.is_empty() {
                    cur.push(p(s));
                }
                cur.push(p(e));
            } else if !cur.is_empty() {
                out.push(std::mem::take(&mut cur));
            }
            s = e;
        }
        walked += len;
        if out.len() > 1_000_000 {
            break;
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out.retain(|d| d.len() >= 2);
    out
}

/// A polyline moved sideways by `d` mm (left of its direction for positive
/// `d`), with mitred joins limited to twice the offset.
fn offset(pts: &[(f64, f64)], closed: bool, d: f64) -> Vec<(f64, f64)> {
    let n = pts.len();
    let normal = |a: (f64, f64), b: (f64, f64)| {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let l = dx.hypot(dy);
        if l > 1e-12 { Some((-dy / l, dx / l)) } else { None }
    };
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let prev = if i > 0 {
            Some(pts[i - 1])
        } else if closed {
            pts.get(n - 1).copied()
        } else {
            None
        };
        let next = if i + 1 < n {
            Some(pts[i + 1])
        } else if closed {
            pts.first().copied()
        } else {
            None
        };
        let n1 = prev.and_then(|p| normal(p, pts[i]));
        let n2 = next.and_then(|q| normal(pts[i], q));
        let m = match (n1, n2) {
            (Some(a), Some(b)) => {
                let s = (a.0 + b.0, a.1 + b.1);
                let l = s.0.hypot(s.1);
                if l < 1e-9 {
                    a
                } else {
                    let u = (s.0 / l, s.1 / l);
                    let cos = (u.0 * a.0 + u.1 * a.1).max(0.5);
                    (u.0 / cos, u.1 / cos)
                }
            }
            (Some(a), None) | (None, Some(a)) => a,
            (None, None) => (0.0, 0.0),
        };
        out.push((pts[i].0 + m.0 * d, pts[i].1 + m.1 * d));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_along_a_line_are_a_step_apart() {
        let p = along(&[(0.0, 0.0), (10.0, 0.0)], false, 2.5);
        assert_eq!(p, vec![(0.0, 0.0), (2.5, 0.0), (5.0, 0.0), (7.5, 0.0), (10.0, 0.0)]);
        // A closed square of side 10: 40 mm around, the last point half a step before the first.
        let sq = [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)];
        assert_eq!(along(&sq, true, 5.0).len(), 8);
    }

    #[test]
    fn dashes_alternate_dash_and_gap() {
        let d = dashes(&[(0.0, 0.0), (30.0, 0.0)], false, 6.0, 3.0);
        let spans: Vec<(f64, f64)> = d.iter().map(|d| (d[0].0, d[d.len() - 1].0)).collect();
        assert_eq!(spans, vec![(0.0, 6.0), (9.0, 15.0), (18.0, 24.0), (27.0, 30.0)]);
    }

    #[test]
    fn an_offset_square_stays_square() {
        let sq = [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)];
        let o = offset(&sq, true, 1.0);
        // Left of a clockwise-on-screen (y down) square's direction is outside it... or inside: either way 1 mm away.
        for (p, q) in o.iter().zip(sq) {
            assert!(((p.0 - q.0).abs() - 1.0).abs() < 1e-9 && ((p.1 - q.1).abs() - 1.0).abs() < 1e-9, "{p:?}");
        }
    }
}
