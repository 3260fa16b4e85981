//! Braille on the array: each text's cells as a braille dot table, the
//! dots' features and footprints, and the clearing around braille where
//! gratings are not felt.

use taxel_format::{Dot, DotKind, Family, ProvenanceEntry};

use super::{Built, DotJob, FeatureKind, MIN_GAP_MM, dot_feature, not_here};
use crate::annotation::{Braille as BrailleStyle, Style};
use crate::braille::paper;
use crate::diagnostic::Diagnostic;
use crate::drawing::{Drawing, Shape, TextShape};
use crate::geometry::Polyline;
use crate::options::CompileOptions;
use crate::style::legend::Swatch;

/// Braille for every text with a braille style, in document order, after the other layers.
pub(super) fn braille_texts(
    b: &mut Built,
    drawing: &Drawing,
    opts: &CompileOptions,
    opaque: &crate::drawing::OpaqueFills,
    diags: &mut Vec<Diagnostic>,
) {
    let family = opts.profile.family();
    let mut notes = crate::braille::Notes::default();
    for (order, e) in drawing.elements.iter().enumerate() {
        let Shape::Text(text) = &e.shape else { continue };
        let Some(style) = e.styles.iter().find_map(|s| match s {
            Style::Braille(br) => Some(*br),
            _ => None,
        }) else {
            continue;
        };
        if family != Family::Laterotactile {
            diags.push(not_here(&Style::Braille(style), &e.name, e.line, opts.profile.name.as_str()));
            continue;
        }
        let (mut pts, missing, table) = braille_dots(text, &style, opts, &mut notes);
        // Punctuation alone says nothing: then the text is left out whole.
        if taxel_braille::says_nothing(&text.runs.iter().map(|r| r.text.as_str()).collect::<String>(), &missing) {
            pts.clear();
        }
        if !missing.is_empty() {
            // When no character has braille, this one warning says the text is left out.
            let left = if pts.is_empty() { "the text is left out" } else { "these characters are left out" };
            diags.push(
                Diagnostic::warning(
                    "T0304",
                    format!("no braille in {table} for {}; {left}", taxel_braille::left_out(&missing)),
                )
                .with_element(&e.name)
                .with_help(crate::braille::missing_help(&table))
                .at_line(e.line),
            );
            if pts.is_empty() {
                continue;
            }
        }
        if pts.is_empty() {
            diags.push(
                Diagnostic::warning("T0301", "this text has no characters to write in braille")
                    .with_element(&e.name)
                    .at_line(e.line),
            );
            continue;
        }
        let job = DotJob {
            e,
            order,
            kind: DotKind::Braille,
            radius: style.radius_mm,
            amplitude: style.amplitude,
            fk: FeatureKind::Braille,
        };
        dot_feature(b, job, &pts, drawing.page, diags);
    }
    notes.emit(diags);
    b.braille_clear = braille_clearing(&b.braille_dots);
    // The key of the labels written as key codes (T0326) in print, for a
    // host to give the reader: provenance entry `key`, with no footprint.
    let key = crate::style::key_line(drawing);
    if family == Family::Laterotactile && !key.is_empty() {
        b.provenance.push(ProvenanceEntry { id: "key".into(), label: key, line: 0 });
    }
    // The key's textures, line styles and symbols (and, on a grid, its
    // brushed strokes), each with its meaning, for a host to say (the key's
    // own bundle, `key.rs`, is felt; SPEC.md section 10.2).
    let plays = |s: &Swatch| super::key::plays(family, s);
    let legend = crate::style::legend::legend_with(drawing, opaque);
    b.provenance.extend(crate::style::legend::provenance(&legend, plays));
    // And the texts the graphic has no room for, which the key's bundle lists.
    if family == Family::Laterotactile {
        b.provenance.extend(legend.unplaced_entry());
    }
    b.legend = Some(legend);
}

/// The braille dot centres of a text, the characters braille has no cell
/// for (in text order), and the table that wrote it (for messages). Lines
/// closer than braille's line pitch are moved apart; a run without its
/// own `y` stays on the line before.
fn braille_dots(
    text: &TextShape,
    style: &BrailleStyle,
    opts: &CompileOptions,
    notes: &mut crate::braille::Notes,
) -> (Vec<(f64, f64)>, Vec<char>, String) {
    let r = style.radius_mm;
    let mut prev_baseline: Option<f64> = None;
    let mut cursor: Option<f64> = None;
    let mut pts = Vec::new();
    let mut missing: Vec<char> = Vec::new();
    let mut table = String::from("uncontracted UEB");
    for run in &text.runs {
        // A key code is letters, not a word: uncontracted, so that no
        // contracted table reads it as a word sign (`be`, `st`).
        let grade = if text.keyed.is_some() { Some(1) } else { style.grade };
        let t = crate::braille::translate(&run.text, Some(text), opts, grade, false);
        if text.keyed.is_none() {
            notes.add(&t);
        }
        table = crate::braille::table_name(&t);
        let (cells, miss) = (t.cells, t.missing);
        missing.extend(miss);
        let mut y = run.y_mm;
        if let Some(prev) = prev_baseline {
            if y > prev + 1e-6 && y < prev + paper::LINE_PITCH_MM {
                // A new line closer than braille's line pitch: keep lines apart.
                y = prev + paper::LINE_PITCH_MM;
            } else if y <= prev + 1e-6 && run.continues {
                y = prev;
            }
        }
        let width = paper::run_width(cells.len(), r);
        let x0 = match (run.continues, cursor) {
            (true, Some(c)) => c,
            _ => run.x_mm - run.anchor * width,
        };
        pts.extend(paper::layout(&cells, x0, y, r));
        cursor = Some(x0 + cells.len() as f64 * paper::CELL_PITCH_MM);
        prev_baseline = Some(y);
    }
    (pts, missing, table)
}

/// The boxes of `clearing` ([`braille_clearing`]) that meet `bounds` (a
/// grated layer's shapes' box), by their place in `clearing`: the ones the
/// layer is built with, as occluders ([`LayerPlan`](super::LayerPlan)).
pub(crate) fn clearing_within(
    clearing: &[Polyline],
    bounds: Option<(f64, f64, f64, f64)>,
) -> impl Iterator<Item = usize> + '_ {
    clearing
        .iter()
        .enumerate()
        .filter(move |(_, c)| match (bounds, crate::geometry::bounds(std::slice::from_ref(*c))) {
            (Some(a), Some(r)) => r.0 <= a.2 && a.0 <= r.2 && r.1 <= a.3 && a.1 <= r.3,
            _ => false,
        })
        .map(|(n, _)| n)
}

/// Dot centres of one braille line lie within this of each other vertically
/// (three rows, 2.34 mm apart); the nearest rows of two lines of a label,
/// 10.2 mm apart, are 5.5 mm apart.
const LINE_SPLIT_MM: f64 = 5.0;

/// Where gratings are not felt around braille (on the laterotactile array):
/// for each braille line of each text, the box of its dots (each dot's
/// disc), grown by the design rules' gap (3.2 mm), as closed rectangles.
/// Braille amid a texture reads as more texture, and the two would add up
/// and clamp. Found from the braille dot table alone (its dots grouped by
/// source, then into lines where their centres are more than 5 mm apart
/// vertically), so that a tool finds the same boxes from a bundle's dots
/// ([`LayerPlan::braille_clearing`](super::LayerPlan::braille_clearing) holds them too).
pub(crate) fn braille_clearing(dots: &[Dot]) -> Vec<Polyline> {
    let gap = MIN_GAP_MM;
    let mut by_source: Vec<&Dot> = dots.iter().collect();
    by_source.sort_by(|a, b| a.source.cmp(&b.source).then(a.y.0.total_cmp(&b.y.0)));
    let mut out = Vec::new();
    let mut line: Option<(Option<u32>, f64, [f64; 4])> = None;
    let close = |b: [f64; 4], out: &mut Vec<Polyline>| {
        let [x0, y0, x1, y1] = [b[0] - gap, b[1] - gap, b[2] + gap, b[3] + gap];
        out.push(Polyline { points: vec![(x0, y0), (x1, y0), (x1, y1), (x0, y1)], closed: true });
    };
    for d in by_source {
        let (x, y, r) = (d.x.0 as f64, d.y.0 as f64, d.radius.0 as f64);
        if !(x.is_finite() && y.is_finite() && r.is_finite()) {
            continue;
        }
        line = match line {
            Some((src, last_y, b)) if src == d.source && y - last_y <= LINE_SPLIT_MM => {
                Some((src, y, [b[0].min(x - r), b[1].min(y - r), b[2].max(x + r), b[3].max(y + r)]))
            }
            other => {
                if let Some((_, _, b)) = other {
                    close(b, &mut out);
                }
                Some((d.source, y, [x - r, y - r, x + r, y + r]))
            }
        };
    }
    if let Some((_, _, b)) = line {
        close(b, &mut out);
    }
    out
}
