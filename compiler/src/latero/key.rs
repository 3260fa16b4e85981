//! The key as bundles of its own, for the laterotactile arrays and the
//! vibrotactile grids (SPEC.md section 10.2): a bundle has one surface, so
//! the key ([`crate::style::legend()`]) is laid out as a drawing of its own
//! on the same surface and compiled for the same profile by the same
//! builder as the graphic (`latero::build`), so that each swatch is felt as the
//! graphic has it.
//!
//! On an array, each entry is a line of the key: its swatch (a patch of its
//! texture, a sample of its line or dotted line, its symbol) at the left,
//! its meaning in braille to its right, then the key codes, a line each. A
//! key longer than the surface goes on as many pages as it needs, each a
//! bundle (`NAME.key.taxel`, `NAME.key2.taxel`, ...), as a key page of
//! embossed graphics goes on to a second sheet; an entry is never split
//! between two pages. On a grid, which plays neither braille nor textures,
//! each brushed stroke of the key is played once across the surface, one
//! after the other, each named by its meaning for a host to say. What does
//! not fit even so (an entry longer than a page, or past
//! [`MAX_PAGES`]) is said (T0332); every entry stays in the graphic's
//! provenance.

use taxel_format::{Bundle, Family, Manifest, ProvenanceEntry};

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
/// Most pages a key goes on: past them a reader is better served by fewer
/// textures and symbols, or shorter labels, than by leafing through
/// bundles (T0332 says what is left out).
pub const MAX_PAGES: usize = 9;
/// The provenance entry that says which page of the key a key's bundle is:
/// its label is `page K of N`.
pub const PAGE_ID: &str = "page";

/// Whether a bundle of `family` plays an entry of kind `s`: an array plays
/// textures, lines, dotted lines and symbols; a grid plays brushed strokes.
pub(crate) fn plays(family: Family, s: &Swatch) -> bool {
    match family {
        Family::Laterotactile => !matches!(s, Swatch::Stroke(_)),
        Family::Grid => matches!(s, Swatch::Stroke(_)),
        _ => false,
    }
}

/// The key's bundles for `drawing` (the graphic's, prepared) on `opts`'s
/// profile, a page each, first page first; none when the drawing needs no
/// key or the family plays none of its entries. With note T0331 saying what
/// they hold, and T0332 when some of it fits on no page. `legend` is the
/// drawing's key when the caller has it already ([`super::Built::legend`]).
pub(crate) fn bundles(
    drawing: &Drawing,
    legend: Option<crate::style::legend::Legend>,
    opts: &CompileOptions,
    px: f32,
    diags: &mut Vec<Diagnostic>,
) -> Vec<Bundle> {
    let family = opts.profile.family();
    if !matches!(family, Family::Laterotactile | Family::Grid) {
        return Vec::new();
    }
    let legend = legend.unwrap_or_else(|| crate::style::legend(drawing));
    let entries: Vec<&Entry> = legend.shown().iter().filter(|e| plays(family, &e.swatch)).collect();
    // Key codes, and the texts the graphic has no room for, are braille,
    // which only an array plays.
    let codes = if family == Family::Laterotactile { legend.text_lines() } else { Vec::new() };
    if !legend.needed() || (entries.is_empty() && codes.is_empty()) {
        return Vec::new();
    }
    let surface = (opts.profile.surface_w_mm as f64, opts.profile.surface_h_mm as f64);
    let (pages, left_out) = match family {
        Family::Grid => (vec![strokes(drawing, &entries, surface)], Vec::new()),
        _ => lines(drawing, &entries, &codes, surface, opts),
    };
    let count = pages.len();
    let mut out = Vec::with_capacity(count);
    // Each element its own provenance entry (entries are told apart by name
    // and line, and the key's elements have no line), numbered across the
    // pages: a host names each swatch and each braille line by its own meaning.
    let mut named = 0;
    for (k, mut elements) in pages.into_iter().enumerate() {
        for e in &mut elements {
            named += 1;
            e.name = format!("key.{named}");
        }
        let page = Page { width_mm: surface.0, height_mm: surface.1, scale: 1.0, ..Default::default() };
        let key = Drawing { page, title: "key".into(), elements };
        // The key's own layout needs no design rules, and says once what the
        // graphic already said (T0307); what a reader would miss is still said.
        let mut own = Vec::new();
        let (built, ()) = super::build(&key, opts, px, &mut own, |_| ());
        diags.extend(own.into_iter().filter(|d| d.code == "T0304"));
        if built.is_empty() {
            continue;
        }
        let mut built = without_key_entries(built);
        if count > 1 {
            let label = format!("page {} of {count}", k + 1);
            built.provenance.push(ProvenanceEntry { id: PAGE_ID.into(), label, line: 0 });
        }
        let mut b = Bundle::new(Manifest { content_hash: opts.content_hash, ..Manifest::new(opts.profile) });
        b.chunks = built.into_chunks();
        if let Err(e) = b.to_bytes() {
            diags.push(Diagnostic::error("T0900", format!("internal error: the key's bundle does not validate: {e}")));
            return Vec::new();
        }
        out.push(b);
    }
    if out.len() != count {
        // A page with nothing to play: the pages no longer say how many there are.
        diags.push(Diagnostic::error("T0900", "internal error: a page of the key has nothing on it"));
        return Vec::new();
    }
    let total = entries.len() + codes.len();
    let what = match family {
        Family::Grid => "each brushed stroke played once, named by its meaning",
        _ => "each texture, line style and symbol felt as itself beside its meaning in braille",
    };
    let mut held = plural(entries.len(), "entry", "entries");
    if family == Family::Laterotactile {
        if !legend.codes.is_empty() {
            held += &format!(", {}", plural(legend.codes.len(), "key code", "key codes"));
        }
        if !legend.unplaced.is_empty() {
            held += &format!(", {} the graphic has no room for", plural(legend.unplaced.len(), "text", "texts"));
        }
    }
    let profile = opts.profile.name.as_str();
    let message = if count == 1 {
        format!("the key ({held}) is a second bundle for {profile}: {what}")
    } else {
        format!("the key ({held}) is {count} more bundles for {profile}, a page each, as its surface holds: {what}")
    };
    diags.push(Diagnostic::note("T0331", message));
    if !left_out.is_empty() {
        let mut named = left_out.iter().take(3).map(|t| crate::diagnostic::quoted(t)).collect::<Vec<_>>().join(", ");
        if left_out.len() > 3 {
            named += &format!(" and {} more", left_out.len() - 3);
        }
        let (verb, them) = if left_out.len() == 1 { ("is", "it") } else { ("are", "them") };
        diags.push(
            Diagnostic::warning(
                "T0332",
                format!(
                    "the key's {} hold {} of its {total} entries and lines of text: {named} {verb} in the \
                     graphic's provenance only (a host says {them})",
                    plural(count, "page", "pages"),
                    total - left_out.len(),
                ),
            )
            .with_help(
                "fewer textures, line styles and symbols, or shorter legend texts and labels, make the key shorter",
            ),
        );
    }
    out
}

/// The page of the key a key's bundle is, and how many pages there are,
/// from its [`PAGE_ID`] entry; `(1, 1)` for a key of one page.
pub fn page_of(entries: &[ProvenanceEntry]) -> (usize, usize) {
    entries
        .iter()
        .find(|e| e.id == PAGE_ID)
        .and_then(|e| {
            let (k, n) = e.label.strip_prefix("page ")?.split_once(" of ")?;
            Some((k.parse().ok()?, n.parse().ok()?))
        })
        .unwrap_or((1, 1))
}

fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The key's bundle is a bundle like any other: the `key` and `key.*`
/// provenance entries its own swatches would give (they stand beside their
/// texts as a legend does) are not written, which come after the elements'.
fn without_key_entries(mut built: super::Built) -> super::Built {
    let keyish = |id: &str| {
        id == "key" || id == crate::style::legend::UNPLACED_ID || crate::style::legend::kind_of_id(id).is_some()
    };
    while built.provenance.last().is_some_and(|p| keyish(&p.id)) {
        built.provenance.pop();
    }
    built
}

/// The key on an array: a line per entry (its swatch, then its meaning in
/// braille, wrapped), then a line per key code, page after page as the
/// surface holds them, an entry's lines on one page. Returns the pages'
/// elements and the meanings (and codes) that fit on no page.
fn lines(
    drawing: &Drawing,
    entries: &[&Entry],
    codes: &[String],
    surface: (f64, f64),
    opts: &CompileOptions,
) -> (Vec<Vec<Element>>, Vec<String>) {
    // A braille line's dots stand this high above its baseline (three rows and a radius).
    let cell_h = 2.0 * DOT_PITCH_MM + 2.0 * DOT_R_MM;
    let baseline = |l: usize| MARGIN_MM + cell_h + l as f64 * LINE_PITCH_MM;
    // Lines a page holds (at least one, so that a page is never empty).
    let per_page = (0..).take_while(|&l| baseline(l) <= surface.1 - MARGIN_MM).count().max(1);
    let swatch_w = SWATCH_CELLS * CELL_PITCH_MM;
    let text_x = MARGIN_MM + swatch_w + CELL_PITCH_MM;
    let cells = |x: f64| {
        (((surface.0 - MARGIN_MM - x - DOT_PITCH_MM - 2.0 * DOT_R_MM) / CELL_PITCH_MM).floor() + 1.0).max(1.0) as usize
    };
    let width = |s: &str| crate::braille::translate(s, None, opts, None, false).cells.len();
    let mut pages = Pages { done: Vec::new(), page: Vec::new(), line: 0, per_page };
    let mut left_out = Vec::new();
    for e in entries {
        let texts = key_page::wrap(&e.meaning, cells(text_x), &width);
        let Some(line) = pages.room(texts.len().max(1)) else {
            left_out.push(e.meaning.clone());
            continue;
        };
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
        pages.page.push(key_page::swatch(e, drawing, at));
        for (k, t) in texts.iter().enumerate() {
            pages.page.push(key_page::braille_text(t, text_x, baseline(line + k), e.lang.clone()));
        }
    }
    for code in codes {
        // Past the last page nothing more fits: no braille to lay out (a
        // map's thousands of texts with no room on the graphic).
        if pages.full() {
            left_out.push(code.clone());
            continue;
        }
        let texts = key_page::wrap(code, cells(MARGIN_MM), &width);
        let Some(line) = pages.room(texts.len().max(1)) else {
            left_out.push(code.clone());
            continue;
        };
        for (k, t) in texts.iter().enumerate() {
            pages.page.push(key_page::braille_text(t, MARGIN_MM, baseline(line + k), None));
        }
    }
    (pages.finish(), left_out)
}

/// The key's pages as they fill.
struct Pages {
    /// The full pages.
    done: Vec<Vec<Element>>,
    /// The page being filled.
    page: Vec<Element>,
    /// Its next free line.
    line: usize,
    /// Lines a page holds.
    per_page: usize,
}

impl Pages {
    /// The first of `n` lines kept together, on this page or a new one;
    /// `None` when they fit on no page ([`MAX_PAGES`]).
    fn room(&mut self, n: usize) -> Option<usize> {
        if n > self.per_page {
            return None;
        }
        if self.line + n > self.per_page {
            if self.done.len() + 1 >= MAX_PAGES {
                return None;
            }
            self.done.push(std::mem::take(&mut self.page));
            self.line = 0;
        }
        let first = self.line;
        self.line += n;
        Some(first)
    }

    /// Whether the last page there may be is full.
    fn full(&self) -> bool {
        self.done.len() + 1 >= MAX_PAGES && self.line >= self.per_page
    }

    /// Every page with something on it.
    fn finish(mut self) -> Vec<Vec<Element>> {
        if !self.page.is_empty() {
            self.done.push(self.page);
        }
        self.done
    }
}

/// The key on a grid: each brushed stroke once, left to right across the
/// surface, a row of its own each, played one after the other.
fn strokes(drawing: &Drawing, entries: &[&Entry], surface: (f64, f64)) -> Vec<Element> {
    let n = entries.len() as f64;
    entries
        .iter()
        .enumerate()
        .map(|(k, e)| {
            let y = surface.1 * (k as f64 + 1.0) / (n + 1.0);
            let at = SwatchBox { rect: (0.0, y, surface.0, y), mid_y: y, inset: 0.1 * surface.0, half: 0.0 };
            key_page::swatch(e, drawing, at)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use taxel_format::profiles;

    #[test]
    fn a_drawing_that_needs_no_key_has_no_key_bundle() {
        let opts = CompileOptions::new(profiles::builtin("stress2").unwrap());
        let mut diags = Vec::new();
        assert!(bundles(&Drawing::default(), None, &opts, 4.0, &mut diags).is_empty());
        assert!(diags.is_empty());
    }

    #[test]
    fn lines_kept_together_go_to_the_next_page_and_what_fits_on_none_is_refused() {
        let mut p = Pages { done: Vec::new(), page: Vec::new(), line: 0, per_page: 6 };
        let put = |p: &mut Pages, n: usize| {
            let first = p.room(n);
            if first.is_some() {
                p.page.push(Element::default());
            }
            first
        };
        assert_eq!(put(&mut p, 3), Some(0));
        assert_eq!(put(&mut p, 2), Some(3));
        // Two more lines do not fit on the first page's one left: a second page.
        assert_eq!(put(&mut p, 2), Some(0));
        assert_eq!(p.done.len(), 1);
        // Longer than a page: on no page, and the page is not turned for it.
        assert_eq!(put(&mut p, 7), None);
        assert_eq!((p.done.len(), p.line), (1, 2));
        for _ in 2..MAX_PAGES {
            assert_eq!(put(&mut p, 6), Some(0));
        }
        // Every page used, the last one full: what comes next is refused.
        assert_eq!(put(&mut p, 1), None);
        assert_eq!(p.finish().len(), MAX_PAGES);
    }

    #[test]
    fn a_page_says_which_page_it_is() {
        let entry = |label: &str| ProvenanceEntry { id: PAGE_ID.into(), label: label.into(), line: 0 };
        assert_eq!(page_of(&[entry("page 2 of 3")]), (2, 3));
        assert_eq!(page_of(&[]), (1, 1));
        assert_eq!(page_of(&[entry("second")]), (1, 1));
    }
}
