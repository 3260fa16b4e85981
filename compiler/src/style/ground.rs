//! The ground a drawing's elements lie on: the felt page, the page
//! backgrounds (and a chart's very light plot panel) the sheet leaves out,
//! whether white is paper or figure, and shapes whose clip regions hide them.

use taxel_format::DeviceProfile;

use super::{BACKGROUND_SHARE, LIGHT_GUIDE, MARK_MM, WHITE, visible};
use crate::drawing::{Drawing, Element, Rgba, Shape};
use crate::geometry::filled_area_within;
use crate::spatial::{self, Bbox};

/// What the elements lie on.
pub(super) struct Ground {
    /// What can be felt: the page, as far as it lies on the device's surface
    /// (on paper, all of it: [`crate::place::felt`]).
    pub(super) page: Bbox,
    /// The elements that are page backgrounds ([`backgrounds`]).
    pub(super) backgrounds: Vec<usize>,
    /// White shapes are figures, not paper.
    pub(super) white_is_figure: bool,
}

impl Ground {
    pub(super) fn of(d: &Drawing, profile: &DeviceProfile) -> Ground {
        let page = crate::place::felt(d, profile);
        // The drawing's own page on it: all of it, unless `--fit` or `--region`
        // placed a page of another shape there (a 3:2 map on a 2:1 surface).
        let s = d.page.sheet();
        let sheet: Bbox = (s.0.max(page.0), s.1.max(page.1), s.2.min(page.2), s.3.min(page.3));
        let backgrounds = backgrounds(d, page, sheet);
        // White is the paper, except where a coloured ground carries nothing but
        // white shapes (a flag's white cross on its red field, an app icon's white
        // glyph on its tile): there the white shapes are the figure. Where other
        // colours are drawn too (a map's white label boxes), white stays the paper.
        let coloured = |e: &Element| e.paint.filled && e.paint.fill.is_none_or(|c| visible(c) && !paper(c));
        let coloured_ground = backgrounds.iter().any(|&i| coloured(&d.elements[i]));
        let white_is_figure = coloured_ground
            && !d.elements.iter().enumerate().any(|(i, e)| {
                e.visible && matches!(e.shape, Shape::Path(_)) && coloured(e) && !backgrounds.contains(&i)
            });
        Ground { page, backgrounds, white_is_figure }
    }
}

/// A colour of the paper: white, or near it ([`WHITE`]).
pub(super) fn paper(c: Rgba) -> bool {
    c[..3].iter().all(|&v| v >= WHITE)
}

/// The page backgrounds among the filled paths: those covering nine tenths of
/// the drawing's own page (`sheet`, where it lies on the felt `page`), and
/// those covering nine tenths of what the drawing occupies when other
/// filled shapes lie on them (a sea under the countries; a lone country with
/// only labels on it stays a region). A shape drawn alone is never one.
fn backgrounds(d: &Drawing, page: Bbox, sheet: Bbox) -> Vec<usize> {
    let area = |b: Bbox| (b.2 - b.0).max(0.0) * (b.3 - b.1).max(0.0);
    let clip = |b: Bbox| (b.0.max(page.0), b.1.max(page.1), b.2.min(page.2), b.3.min(page.3));
    let filled = |e: &Element| matches!(e.shape, Shape::Path(_)) && e.visible && e.paint.filled;
    // Every element's box as far as its clip regions let it be seen (a
    // page-sized shape clipped to a small square is that square), worked out
    // once and in parallel (each is a pass over its outline).
    let bounds: Vec<Option<Bbox>> = {
        use rayon::prelude::*;
        d.elements.par_iter().map(Element::seen_bounds).collect()
    };
    let boxes: Vec<Option<Bbox>> =
        d.elements.iter().zip(&bounds).map(|(e, b)| b.filter(|_| filled(e)).map(clip)).collect();
    let extent = d
        .elements
        .iter()
        .zip(&bounds)
        .filter(|(e, _)| e.visible)
        .filter_map(|(_, b)| *b)
        .map(clip)
        .reduce(|a, b| (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3)));
    let Some(extent) = extent else { return Vec::new() };
    // A shape drawn alone is the figure, not a ground under nothing: a logo
    // drawn as one rounded square with its letters cut out (Simple Icons'
    // MobX, Y Combinator and 18 more of its 3,453 icons were left out whole).
    if d.elements.iter().zip(&bounds).filter(|(e, b)| e.visible && b.is_some()).nth(1).is_none() {
        return Vec::new();
    }
    let mut out = Vec::new();
    // Each candidate looks at every other shape once; a drawing has a few
    // backgrounds, so a flood of page-sized shapes is cut short (never all pairs).
    let mut candidates = 0;
    let mut panels = 0;
    // What a shape covers is its own area on the page, not its box's: a flag's
    // cross or a logo's disc spans the page without covering it.
    let covered = |i: usize| match (&d.elements[i].shape, boxes[i]) {
        (Shape::Path(p), Some(seen)) => filled_area_within(&p.outline, p.fill_rule, seen),
        _ => 0.0,
    };
    for (i, b) in boxes.iter().enumerate() {
        let Some(b) = *b else { continue };
        if area(sheet) > 0.0
            && area(b) >= BACKGROUND_SHARE * area(sheet)
            && covered(i) >= BACKGROUND_SHARE * area(sheet)
        {
            out.push(i);
        } else if area(b) >= BACKGROUND_SHARE * area(extent)
            && candidates < 8
            && covered(i) >= BACKGROUND_SHARE * area(extent)
        {
            candidates += 1;
            let under = |j: usize, o: Bbox| {
                j != i && o.0 >= b.0 && o.1 >= b.1 && o.2 <= b.2 && o.3 <= b.3 && (o.2 - o.0).max(o.3 - o.1) > MARK_MM
            };
            if boxes.iter().enumerate().any(|(j, o)| o.is_some_and(|o| under(j, o))) {
                out.push(i);
            }
        } else if panels < 8 && very_light(&d.elements[i]) && covered(i) >= BACKGROUND_SHARE * area(b) {
            // A chart's plot panel: a very light rectangle (Plotly's
            // #e5ecf6, ggplot2's #ebebeb, seaborn's #eaeaf2) with coloured
            // shapes painted on it (the bars), which the panel only sets off.
            panels += 1;
            let on_it = |j: usize, o: Bbox| {
                j > i
                    && o.0 >= b.0
                    && o.1 >= b.1
                    && o.2 <= b.2
                    && o.3 <= b.3
                    && (o.2 - o.0).max(o.3 - o.1) > MARK_MM
                    && !very_light(&d.elements[j])
            };
            if boxes.iter().enumerate().any(|(j, o)| o.is_some_and(|o| on_it(j, o))) {
                out.push(i);
            }
        }
    }
    out
}

/// Whether an element's fill is very light: every channel, over white
/// paper after its opacity, at least [`LIGHT_GUIDE`] (a gradient's or a
/// pattern's is not known, so not).
fn very_light(e: &Element) -> bool {
    e.paint.fill.is_some_and(|c| {
        let a = c[3] as f64 / 255.0;
        c[..3].iter().all(|&v| a * v as f64 + (1.0 - a) * 255.0 >= LIGHT_GUIDE as f64)
    })
}

/// Whether one of the element's clip regions lies wholly away from it.
pub(super) fn clipped_away(e: &Element, b: Bbox) -> bool {
    let Shape::Path(p) = &e.shape else { return false };
    p.clips.iter().any(|c| crate::geometry::bounds(&c.outline).is_none_or(|cb| !spatial::meet(cb, b)))
}
