//! The key as a second bundle, for the laterotactile arrays and the
//! vibrotactile grids (SPEC.md section 10.2): a bundle has one surface, so
//! the key ([`crate::style::legend()`]) is laid out as a drawing of its own
//! on the same surface and compiled for the same profile by the same
//! [`super::build`] as the graphic, so that each swatch is felt as the
//! graphic has it.
//!
//! On an array, each entry is a line of the key: its swatch (a patch of its
//! texture, a sample of its line or dotted line, its symbol) at the left,
//! its meaning in braille to its right, then the key codes, a line each. On
//! a grid, which plays neither braille nor textures, each brushed stroke of
//! the key is played once across the surface, one after the other, each
//! named by its meaning for a host to say. What does not fit on the surface
//! is said (T0332); every entry stays in the graphic's provenance.

use taxel_format::{Bundle, Family, Manifest};

use crate::braille::paper::{CELL_PITCH_MM, DOT_PITCH_MM, LINE_PITCH_MM};
use crate::diagnostic::Diagnostic;
use crate::drawing::{Drawing, Element, Page};
use crate::options::CompileOptions;
use crate::style::key_page::{self, SwatchBox};
use crate::style::legend::{Entry, Swatch};

use super::MIN_GAP_MM;

/// Margin kept free around the key on the surface, mm: one, so that six
/// braille lines fit on `stress2`'s 60 mm (two entries whose meanings take
/// three lines each, as "vertical grating, 1.5 mm" does beside a swatch).
const MARGIN_MM: f64 = 1.0;
/// Cells a swatch is wide on an array.
const SWATCH_CELLS: f64 = 3.0;
/// The braille dots' radius in the key (the default braille's).
const DOT_R_MM: f64 = 0.72;

/// Whether a bundle of `family` plays an entry of kind `s`: an array plays
/// textures, lines, dotted lines and symbols; a grid plays brushed strokes.
pub(crate) fn plays(family: Family, s: &Swatch) -> bool {
    match family {
        Family::Laterotactile => !matches!(s, Swatch::Stroke(_)),
        Family::Grid => matches!(s, Swatch::Stroke(_)),
        _ => false,
    }
}

/// The key's bundle for `drawing` (the graphic's, prepared) on `opts`'s
/// profile, or `None` when the drawing needs no key or the family plays
/// none of its entries; with note T0331 saying what it holds, and T0332
/// when some of it does not fit on the surface. `legend` is the drawing's
/// key when the caller has it already ([`super::Built::legend`]).
pub(crate) fn bundle(
    drawing: &Drawing,
    legend: Option<crate::style::legend::Legend>,
    opts: &CompileOptions,
    px: f32,
    diags: &mut Vec<Diagnostic>,
) -> Option<Bundle> {
    let family = opts.profile.family();
    if !matches!(family, Family::Laterotactile | Family::Grid) {
        return None;
    }
    let legend = legend.unwrap_or_else(|| crate::style::legend(drawing));
    let entries: Vec<&Entry> = legend.shown().iter().filter(|e| plays(family, &e.swatch)).collect();
    // Key codes are braille, which only an array plays.
    let codes = if family == Family::Laterotactile { legend.code_lines() } else { Vec::new() };
    if !legend.needed() || (entries.is_empty() && codes.is_empty()) {
        return None;
    }
    let surface = (opts.profile.surface_w_mm as f64, opts.profile.surface_h_mm as f64);
    let (mut elements, left_out) = match family {
        Family::Grid => strokes(drawing, &entries, surface),
        _ => lines(drawing, &entries, &codes, surface, opts),
    };
    // Each its own provenance entry (entries are told apart by name and
    // line, and the key's elements have no line): a host names each swatch
    // and each braille line by its own meaning.
    for (n, e) in elements.iter_mut().enumerate() {
        e.name = format!("key.{}", n + 1);
    }
    let page = Page { width_mm: surface.0, height_mm: surface.1, scale: 1.0, ..Default::default() };
    let key = Drawing { page, title: "key".into(), elements };
    // The key's own layout needs no design rules, and says once what the
    // graphic already said (T0307); what a reader would miss is still said.
    let mut own = Vec::new();
    let (built, ()) = super::build(&key, opts, px, &mut own, |_| ());
    diags.extend(own.into_iter().filter(|d| d.code == "T0304"));
    if built.is_empty() {
        return None;
    }
    let mut b = Bundle::new(Manifest { content_hash: opts.content_hash, ..Manifest::new(opts.profile) });
    b.chunks = without_key_entries(built).into_chunks();
    if let Err(e) = b.to_bytes() {
        diags.push(Diagnostic::error("T0900", format!("internal error: the key's bundle does not validate: {e}")));
        return None;
    }
    let total = entries.len() + codes.len();
    let what = match family {
        Family::Grid => "each brushed stroke played once, named by its meaning",
        _ => "each texture, line style and symbol felt as itself beside its meaning in braille",
    };
    diags.push(Diagnostic::note(
        "T0331",
        format!(
            "the key ({}{}) is a second bundle for {}: {what}",
            count(entries.len(), "entry", "entries"),
            if codes.is_empty() { String::new() } else { format!(", {}", count(codes.len(), "key code", "key codes")) },
            opts.profile.name.as_str(),
        ),
    ));
    if !left_out.is_empty() {
        let mut named = left_out.iter().take(3).cloned().collect::<Vec<_>>().join(", ");
        if left_out.len() > 3 {
            named += &format!(" and {} more", left_out.len() - 3);
        }
        let (verb, them) = if left_out.len() == 1 { ("is", "it") } else { ("are", "them") };
        diags.push(
            Diagnostic::warning(
                "T0332",
                format!(
                    "the key's surface holds {} of its {total} entries and key codes: {named} {verb} in the \
                     graphic's provenance only (a host says {them})",
                    total - left_out.len(),
                ),
            )
            .with_help(
                "fewer textures, line styles and symbols, or shorter legend texts and labels, make the key shorter",
            ),
        );
    }
    Some(b)
}

fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The key's bundle is a bundle like any other: the `key` and `key.*`
/// provenance entries its own swatches would give (they stand beside their
/// texts as a legend does) are not written, which come after the elements'.
fn without_key_entries(mut built: super::Built) -> super::Built {
    while built.provenance.last().is_some_and(|p| p.id == "key" || crate::style::legend::kind_of_id(&p.id).is_some()) {
        built.provenance.pop();
    }
    built
}

/// The key on an array: a line per entry (its swatch, then its meaning in
/// braille, wrapped), then a line per key code, as many as the surface
/// holds. Returns the elements and the meanings (and codes) left out.
fn lines(
    drawing: &Drawing,
    entries: &[&Entry],
    codes: &[String],
    surface: (f64, f64),
    opts: &CompileOptions,
) -> (Vec<Element>, Vec<String>) {
    // A braille line's dots stand this high above its baseline (three rows and a radius).
    let cell_h = 2.0 * DOT_PITCH_MM + 2.0 * DOT_R_MM;
    let baseline = |l: usize| MARGIN_MM + cell_h + l as f64 * LINE_PITCH_MM;
    let fits = |l: usize| baseline(l) <= surface.1 - MARGIN_MM;
    let swatch_w = SWATCH_CELLS * CELL_PITCH_MM;
    let text_x = MARGIN_MM + swatch_w + CELL_PITCH_MM;
    let cells = |x: f64| {
        (((surface.0 - MARGIN_MM - x - DOT_PITCH_MM - 2.0 * DOT_R_MM) / CELL_PITCH_MM).floor() + 1.0).max(1.0) as usize
    };
    let width = |s: &str| crate::braille::translate(s, None, opts, None, false).cells.len();
    let (mut out, mut left_out, mut line) = (Vec::new(), Vec::new(), 0usize);
    for e in entries {
        let texts = key_page::wrap(&e.meaning, cells(text_x), &width);
        let n = texts.len().max(1);
        if !fits(line + n - 1) {
            left_out.push(e.meaning.clone());
            continue;
        }
        // The swatch's box: the first line's cells, less the gap that keeps
        // it apart from the next line's swatch.
        let mid = baseline(line) - cell_h / 2.0;
        let half_h = (LINE_PITCH_MM - MIN_GAP_MM) / 2.0;
        let at = SwatchBox {
            rect: (MARGIN_MM, mid - half_h, MARGIN_MM + swatch_w, mid + half_h),
            mid_y: mid,
            inset: 1.0,
            half: 0.5,
        };
        out.push(key_page::swatch(e, drawing, at));
        for (k, t) in texts.iter().enumerate() {
            out.push(key_page::braille_text(t, text_x, baseline(line + k), e.lang.clone()));
        }
        line += n;
    }
    for code in codes {
        let texts = key_page::wrap(code, cells(MARGIN_MM), &width);
        if !fits(line + texts.len().max(1) - 1) {
            left_out.push(code.clone());
            continue;
        }
        for t in texts {
            out.push(key_page::braille_text(&t, MARGIN_MM, baseline(line), None));
            line += 1;
        }
    }
    (out, left_out)
}

/// The key on a grid: each brushed stroke once, left to right across the
/// surface, a row of its own each, played one after the other.
fn strokes(drawing: &Drawing, entries: &[&Entry], surface: (f64, f64)) -> (Vec<Element>, Vec<String>) {
    let n = entries.len() as f64;
    let out = entries
        .iter()
        .enumerate()
        .map(|(k, e)| {
            let y = surface.1 * (k as f64 + 1.0) / (n + 1.0);
            let at = SwatchBox { rect: (0.0, y, surface.0, y), mid_y: y, inset: 0.1 * surface.0, half: 0.0 };
            key_page::swatch(e, drawing, at)
        })
        .collect();
    (out, Vec::new())
}

#[cfg(test)]
mod tests {
    use super::*;
    use taxel_format::profiles;

    #[test]
    fn a_drawing_that_needs_no_key_has_no_key_bundle() {
        let opts = CompileOptions::new(profiles::builtin("stress2").unwrap());
        let mut diags = Vec::new();
        assert!(bundle(&Drawing::default(), None, &opts, 4.0, &mut diags).is_none());
        assert!(diags.is_empty());
    }
}
