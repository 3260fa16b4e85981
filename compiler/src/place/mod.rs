//! Stage 2, place: `--region`, `--fit` and the crop to the surface.
//!
//! Fitting a resolved drawing to the device: `--region` takes part of it,
//! `--fit` scales it to fill the profile's surface keeping its aspect ratio,
//! and in every case what lies beyond the surface is left out, so it is never
//! stored in a bundle. Runs on the [`Drawing`] before any layer is built, so
//! the design rules judge the drawing at the size it will be felt.

use rayon::prelude::*;
use taxel_format::{DeviceProfile, FamilyParams};

use crate::diagnostic::{Diagnostic, number};
use crate::drawing::{Clip, Drawing, Element, Shape};
use crate::geometry::{self, FillRule, Flattening, Polyline};
use crate::options::Region;
use crate::spatial::{Bbox, meet};

/// A page larger than the surface by more than this (mm) is reported.
const SLACK_MM: f64 = 0.5;

fn rect(b: Bbox) -> Vec<Polyline> {
    vec![Polyline { points: vec![(b.0, b.1), (b.2, b.1), (b.2, b.3), (b.0, b.3)], closed: true }]
}

fn inside(b: Bbox, outer: Bbox) -> bool {
    b.0 >= outer.0 && b.1 >= outer.1 && b.2 <= outer.2 && b.3 <= outer.3
}

/// The region in page mm, or the error that says why it cannot be taken.
fn region_box(d: &Drawing, region: &Region) -> Result<Bbox, Diagnostic> {
    match region {
        Region::Rect { x, y, w, h } => {
            let (s, (ox, oy)) = (d.page.scale, d.page.offset_mm);
            Ok((ox + x * s, oy + y * s, ox + (x + w) * s, oy + (y + h) * s))
        }
        Region::Element(id) => {
            // The element with that id, else every element in the layer (or group) of that label.
            let of = |pick: &dyn Fn(&Element) -> bool| {
                d.elements
                    .iter()
                    .filter(|e| pick(e))
                    .filter_map(Element::bounds)
                    .reduce(|a, b| (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3)))
            };
            of(&|e| e.id == *id).or_else(|| of(&|e| e.layers.iter().any(|l| l.trim() == id.trim()))).ok_or_else(|| {
                Diagnostic::error(
                    "T0210",
                    format!("--region #{id}: no element has the id `{id}` and no layer is labelled so"),
                )
                .with_help(
                    "give the id of a drawn element or the label of an Inkscape layer, or X,Y,W,H in drawing units",
                )
            })
        }
    }
}

/// Drops the points of `e`'s outlines (its shape's, its clips' and its
/// glyphs') that lie within `tol` of the rest ([`geometry::thin`]).
fn thin(e: &mut Element, tol: f64) {
    let polys = |v: &mut Vec<Polyline>| {
        for p in v.iter_mut() {
            p.points = geometry::thin(&p.points, p.closed, tol);
        }
    };
    match &mut e.shape {
        Shape::Path(p) => {
            polys(&mut p.outline);
            p.clips.iter_mut().for_each(|c| polys(&mut c.outline));
        }
        Shape::Text(t) => polys(&mut t.outline),
        Shape::Image { .. } => {}
    }
}

/// Moves every coordinate of `e` by `p -> p * s + t`.
fn transform(e: &mut Element, s: f64, t: (f64, f64)) {
    let map = |p: &mut (f64, f64)| *p = (p.0 * s + t.0, p.1 * s + t.1);
    let polys = |v: &mut Vec<Polyline>| v.iter_mut().flat_map(|p| p.points.iter_mut()).for_each(map);
    e.paint.stroke_width_mm *= s;
    match &mut e.shape {
        Shape::Path(p) => {
            polys(&mut p.outline);
            p.markers.iter_mut().for_each(map);
            p.clips.iter_mut().for_each(|c| polys(&mut c.outline));
        }
        Shape::Text(t) => {
            polys(&mut t.outline);
            t.font_size_mm *= s;
            for r in &mut t.runs {
                let mut q = (r.x_mm, r.y_mm);
                map(&mut q);
                (r.x_mm, r.y_mm) = q;
            }
        }
        Shape::Image { bounds } => {
            let (mut a, mut b) = ((bounds.0, bounds.1), (bounds.2, bounds.3));
            map(&mut a);
            map(&mut b);
            *bounds = (a.0, a.1, b.0, b.1);
        }
    }
}

/// Keeps only what lies in `keep`: elements wholly outside are removed, and
/// paths that cross its edge are clipped to it. Text is kept when its first
/// run starts inside (braille beyond the edge is cut by the layer builder),
/// an image when it lies wholly inside. Returns how many were removed.
fn crop(d: &mut Drawing, keep: Bbox) -> usize {
    let before = d.elements.len();
    // Each element is decided alone, so in parallel (its bounds are a pass
    // over all its points); the ones left out are removed in order after.
    let kept: Vec<bool> = d
        .elements
        .par_iter_mut()
        .map(|e| {
            let Some(b) = e.bounds() else { return true };
            if !meet(b, keep) {
                return false;
            }
            match &mut e.shape {
                Shape::Path(p) => {
                    if !inside(b, keep) {
                        p.clips.push(Clip { outline: rect(keep), fill_rule: FillRule::NonZero });
                    }
                    true
                }
                Shape::Text(t) => t.runs.first().is_none_or(|r| inside((r.x_mm, r.y_mm, r.x_mm, r.y_mm), keep)),
                Shape::Image { .. } => inside(b, keep),
            }
        })
        .collect();
    let mut kept = kept.into_iter();
    d.elements.retain(|_| kept.next().unwrap_or(true));
    before - d.elements.len()
}

/// A drawing occupies less than this share of its page's width or height
/// for `--fit` to fit what it occupies rather than the page.
const OCCUPIED_SHARE: f64 = 0.9;
/// The margin kept around what a drawing occupies, as a share of its larger side.
const MARGIN_SHARE: f64 = 0.03;

/// What the drawing shows on its page, in page mm: the union of its
/// visible elements' boxes within the page (as far as their clips let them
/// be seen), grown by a margin of 3 % of its larger side (kept on the page).
/// `None` when it takes up nearly the whole page (at least 90 % of its width
/// and of its height), or nothing. An artboard a drawing fills a corner of
/// (an Illustrator letter page, an Inkscape A4 with a small diagram) is then
/// fitted by what it shows; a drawing with a background across its page (a
/// flag's field, a map's sea) shows its whole page.
fn occupied(d: &Drawing) -> Option<Bbox> {
    let page: Bbox = (0.0, 0.0, d.page.width_mm, d.page.height_mm);
    let on_page = |b: Bbox| (b.0.max(page.0), b.1.max(page.1), b.2.min(page.2), b.3.min(page.3));
    let shown = d
        .elements
        .par_iter()
        .filter(|e| e.visible)
        .filter_map(Element::seen_bounds)
        .filter(|&b| b.0.is_finite() && b.1.is_finite() && b.2.is_finite() && b.3.is_finite() && meet(b, page))
        .map(on_page)
        .reduce_with(|a, b| (a.0.min(b.0), a.1.min(b.1), a.2.max(b.2), a.3.max(b.3)))?;
    let (w, h) = (shown.2 - shown.0, shown.3 - shown.1);
    let most = w >= OCCUPIED_SHARE * (page.2 - page.0) && h >= OCCUPIED_SHARE * (page.3 - page.1);
    if most || !(w > 0.0 && h > 0.0) {
        return None;
    }
    let m = MARGIN_SHARE * w.max(h);
    Some(on_page((shown.0 - m, shown.1 - m, shown.2 + m, shown.3 + m)))
}

/// Where `--region` and `--fit` put a drawing: page mm `p` goes to
/// `p * scale + shift` on a page the size of the surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// The part taken (`--region`), in page mm before scaling.
    pub part: Option<Bbox>,
    /// The box fitted, in page mm before scaling: the part, else what the
    /// drawing shows (when it shows only part of its page), else the page.
    pub from: Bbox,
    /// The scale factor.
    pub scale: f64,
    /// The shift after scaling, mm.
    pub shift: (f64, f64),
    /// The surface, mm: the page after placing.
    pub surface: (f64, f64),
}

/// The placement `fit` and `region` ask of `d` on `profile`'s surface:
/// `Ok(None)` when neither is asked (or the surface is degenerate), an error
/// when the region cannot be taken.
pub fn placement(
    d: &Drawing,
    profile: &DeviceProfile,
    fit: bool,
    region: Option<&Region>,
) -> Result<Option<Placement>, Diagnostic> {
    let (sw, sh) = (profile.surface_w_mm as f64, profile.surface_h_mm as f64);
    if !(sw.is_finite() && sh.is_finite() && sw > 0.0 && sh > 0.0) || !(fit || region.is_some()) {
        return Ok(None);
    }
    let part = match region {
        None => None,
        Some(r) => match region_box(d, r)? {
            b if b.2 - b.0 > 0.0 && b.3 - b.1 > 0.0 && b.0.is_finite() && b.3.is_finite() => Some(b),
            _ => return Err(Diagnostic::error("T0210", "--region: the part to take has no area")),
        },
    };
    let from = part.or_else(|| occupied(d)).unwrap_or((0.0, 0.0, d.page.width_mm, d.page.height_mm));
    let (w, h) = (from.2 - from.0, from.3 - from.1);
    if !(w > 0.0 && h > 0.0 && w.is_finite() && h.is_finite()) {
        return Ok(None);
    }
    let scale = (sw / w).min(sh / h);
    // Centred on the surface.
    let shift = ((sw - w * scale) / 2.0 - from.0 * scale, (sh - h * scale) / 2.0 - from.1 * scale);
    Ok(Some(Placement { part, from, scale, shift, surface: (sw, sh) }))
}

/// Applies `--region` and `--fit` (`region` and `fit`) to `d` for a device of
/// `profile`'s surface, then leaves out what lies beyond the surface. A region
/// implies fitting. Without fitting, a page larger than the surface gives one
/// warning that suggests `--fit`, except on paper, where it is printed on
/// several pages ([`print_pages`]). A drawing shrunk keeps its outlines
/// within `flattening` of its curves, and no finer (the tolerance it was
/// flattened at). Returns `false` (with an error) when the region cannot be
/// taken or the drawing would take too many pages.
pub fn apply(
    d: &mut Drawing,
    profile: &DeviceProfile,
    fit: bool,
    region: Option<&Region>,
    flattening: Flattening,
    diags: &mut Vec<Diagnostic>,
) -> bool {
    let (sw, sh) = (profile.surface_w_mm as f64, profile.surface_h_mm as f64);
    if !(sw.is_finite() && sh.is_finite() && sw > 0.0 && sh > 0.0) {
        return true;
    }
    let place = match placement(d, profile, fit, region) {
        Ok(p) => p,
        Err(e) => {
            diags.push(e);
            return false;
        }
    };
    if let Some(p) = place {
        if let Some(b) = p.part {
            crop(d, b);
        }
        let page: Bbox = (0.0, 0.0, d.page.width_mm, d.page.height_mm);
        let from = p.from;
        let (w, h) = (from.2 - from.0, from.3 - from.1);
        let part = p.part;
        let shown = part.is_none() && from != page;
        {
            let (s, t) = (p.scale, p.shift);
            // The drawing was flattened at its own size, within `flattening`:
            // shrunk by `s`, its curves have `1 / s` times the points that
            // tolerance asks (a world map fitted to a 110 mm surface, 638,000
            // for 214,000). What the shrinking brought within the rest of the
            // tolerance of its neighbours goes, so every point of a curve
            // stays within `flattening` of its polyline.
            let tol = flattening.curves.min(flattening.arcs) * (1.0 - s);
            d.elements.par_iter_mut().for_each(|e| {
                transform(e, s, t);
                if s < 1.0 {
                    thin(e, tol);
                }
            });
            let sheet = d.page.sheet();
            d.page.sheet_mm = Some((sheet.0 * s + t.0, sheet.1 * s + t.1, sheet.2 * s + t.0, sheet.3 * s + t.1));
            d.page.scale *= s;
            d.page.offset_mm = (d.page.offset_mm.0 * s + t.0, d.page.offset_mm.1 * s + t.1);
            d.page.width_mm = sw;
            d.page.height_mm = sh;
            // A drawing without a size was already fitted to the surface (T0201 says so):
            // "scaled by 1.000" would only repeat it.
            let unchanged = part.is_none() && !shown && (s - 1.0).abs() < 5e-4;
            if !unchanged {
                let what = match (part, shown) {
                    (Some(_), _) => "the region was".to_string(),
                    (None, true) => format!(
                        "what the drawing shows (its {} x {} mm page less the empty margins) was",
                        number(page.2, 1),
                        number(page.3, 1)
                    ),
                    (None, false) => "the drawing was".to_string(),
                };
                diags.push(Diagnostic::note(
                    "T0211",
                    format!(
                        "{} scaled by {}: {} x {} mm became {} x {} mm on the {} surface ({sw} x {sh} mm)",
                        what,
                        number(s, 3),
                        number(w, 1),
                        number(h, 1),
                        number(w * s, 1),
                        number(h * s, 1),
                        profile.name
                    ),
                ));
            }
        }
    }
    let surface: Bbox = (0.0, 0.0, sw, sh);
    let (pw, ph) = (d.page.width_mm, d.page.height_mm);
    if matches!(profile.params, FamilyParams::Print(_)) && place.is_none() {
        return page_for_print(d, profile, diags);
    }
    let dropped = crop(d, surface);
    if pw > sw + SLACK_MM || ph > sh + SLACK_MM {
        let left = if dropped > 0 { format!("; {dropped} element(s) beyond it are left out") } else { String::new() };
        diags.push(Diagnostic::warning(
            "T0202",
            format!(
                "the drawing ({} x {} mm) is larger than the {} surface ({sw} x {sh} mm){left}; build with --fit to scale it to the surface, or --region to take part of it",
                number(pw, 1),
                number(ph, 1),
                profile.name
            ),
        ));
    }
    true
}

/// What can be felt of a placed drawing `d` on `profile`, in page mm: its
/// page as far as it lies on the device's surface; on paper, its whole page
/// (a page larger than the printable area is printed on several).
pub fn felt(d: &Drawing, profile: &DeviceProfile) -> Bbox {
    let (pw, ph) = (d.page.width_mm, d.page.height_mm);
    if matches!(profile.params, FamilyParams::Print(_)) {
        return (0.0, 0.0, pw, ph);
    }
    (0.0, 0.0, pw.min(profile.surface_w_mm as f64), ph.min(profile.surface_h_mm as f64))
}

/// Most pages a drawing is printed on (a 10 x 10 grid of sheets, a wall
/// map of nearly 2 x 3 m on A4): beyond it the drawing is refused (T0213).
pub const MAX_PRINT_PAGES: usize = 100;

/// The pages `(across, down)` a drawing of `page` size takes on a print
/// `profile` whose printable area is its surface: one when it fits (within
/// half a millimetre), else as many whole printable areas as cover it,
/// read row by row from the top left. `None` for a degenerate size.
pub fn print_pages(page: (f64, f64), profile: &DeviceProfile) -> Option<(usize, usize)> {
    let (sw, sh) = (profile.surface_w_mm as f64, profile.surface_h_mm as f64);
    let count = |len: f64, side: f64| {
        let n = ((len - SLACK_MM) / side).ceil().max(1.0);
        (n.is_finite() && side > 0.0).then_some(n.min(1e9) as usize)
    };
    Some((count(page.0, sw)?, count(page.1, sh)?))
}

/// Without `--fit` or `--region`, a print drawing keeps its size: what lies
/// on its page is kept (and only that), and a page larger than the paper's
/// printable area is printed on several sheets (note T0212), as a
/// transcriber tiles a wall map; more than [`MAX_PRINT_PAGES`] is refused
/// (T0213).
fn page_for_print(d: &mut Drawing, profile: &DeviceProfile, diags: &mut Vec<Diagnostic>) -> bool {
    let (pw, ph) = (d.page.width_mm, d.page.height_mm);
    let Some((across, down)) = print_pages((pw, ph), profile) else { return true };
    let pages = across.saturating_mul(down);
    if pages > MAX_PRINT_PAGES {
        diags.push(
            Diagnostic::error(
                "T0213",
                format!(
                    "the drawing ({} x {} mm) would take {pages} pages of {}'s printable area ({} x {} mm), \
                     more than {MAX_PRINT_PAGES}",
                    number(pw, 1),
                    number(ph, 1),
                    profile.name,
                    profile.surface_w_mm,
                    profile.surface_h_mm
                ),
            )
            .with_help("build with --fit to scale it to one page, or --region to take part of it"),
        );
        return false;
    }
    crop(d, (0.0, 0.0, pw, ph));
    if pages > 1 {
        diags.push(
            Diagnostic::note(
                "T0212",
                format!(
                    "the drawing ({} x {} mm) is larger than {}'s printable area ({} x {} mm): it is printed at \
                     its size on {pages} pages, {across} across and {down} down, read row by row",
                    number(pw, 1),
                    number(ph, 1),
                    profile.name,
                    profile.surface_w_mm,
                    profile.surface_h_mm
                ),
            )
            .with_help("build with --fit to scale it to one page"),
        );
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::{Page, PathShape, TextRun, TextShape};
    use taxel_format::profiles;

    fn square(id: &str, x: f64, y: f64, s: f64) -> Element {
        Element {
            id: id.into(),
            name: id.into(),
            visible: true,
            shape: Shape::Path(PathShape { outline: rect((x, y, x + s, y + s)), ..Default::default() }),
            ..Default::default()
        }
    }

    /// A 500 x 500 mm page whose user unit is 2 mm.
    fn big() -> Drawing {
        Drawing {
            page: Page { width_mm: 500.0, height_mm: 500.0, scale: 2.0, offset_mm: (0.0, 0.0), sheet_mm: None },
            elements: vec![
                square("a", 0.0, 0.0, 100.0),
                square("b", 400.0, 400.0, 100.0),
                square("c", 200.0, 0.0, 20.0),
            ],
            ..Default::default()
        }
    }

    fn points(e: &Element) -> Vec<(f64, f64)> {
        match &e.shape {
            Shape::Path(p) => p.outline[0].points.clone(),
            _ => vec![],
        }
    }

    #[test]
    fn fit_scales_a_large_drawing_into_the_surface_centred() {
        let p = profiles::builtin("stress2").unwrap(); // 110 x 60 mm
        let mut d = big();
        let mut diags = Vec::new();
        assert!(apply(&mut d, &p, true, None, Flattening::DEFAULT, &mut diags));
        // 500 mm square into 110 x 60: scale 60 / 500 = 0.12, 60 mm wide, centred: x offset 25 mm.
        assert_eq!(points(&d.elements[0])[2], (25.0 + 12.0, 12.0));
        assert_eq!(points(&d.elements[1])[0], (25.0 + 48.0, 48.0));
        assert!((d.page.scale - 0.24).abs() < 1e-12);
        assert_eq!((d.page.width_mm, d.page.height_mm), (110.0, 60.0));
        assert!(!diags.iter().any(|d| d.code == "T0202"));
        assert!(diags.iter().any(|d| d.code == "T0211"));
    }

    /// A drawing that shows a corner of its page (a diagram on an
    /// Illustrator letter artboard) is fitted by what it shows, with a margin
    /// of 3 % of its larger side, not by its empty page. One that shows most
    /// of its page (shapes across it, a background over it, a flag's
    /// triangle) is fitted by the page.
    #[test]
    fn fit_scales_what_the_drawing_shows_not_its_empty_page() {
        let p = profiles::builtin("stress2").unwrap(); // 110 x 60 mm
        let page = Page { width_mm: 200.0, height_mm: 100.0, scale: 1.0, offset_mm: (0.0, 0.0), sheet_mm: None };
        let filled = |mut e: Element| {
            e.paint.filled = true;
            e
        };
        let shown = |extra: Vec<Element>| {
            let mut elements = vec![square("a", 10.0, 10.0, 30.0)];
            elements.push(square("b", 20.0, 10.0, 30.0));
            elements.extend(extra);
            Drawing { page, elements, ..Default::default() }
        };
        let mut d = shown(vec![]);
        let mut diags = Vec::new();
        assert!(apply(&mut d, &p, true, None, Flattening::DEFAULT, &mut diags));
        // Shown: 10..50 x 10..40 mm, grown by 1.2 mm: 42.4 x 32.4 mm, so 60 mm high.
        let s = 60.0 / 32.4;
        let b = d.elements[0].bounds().unwrap();
        let want = (55.0 - 21.2 * s + 1.2 * s, 1.2 * s, 55.0 - 21.2 * s + 31.2 * s, 31.2 * s);
        for (got, want) in [b.0, b.1, b.2, b.3].into_iter().zip([want.0, want.1, want.2, want.3]) {
            assert!((got - want).abs() < 1e-9, "{b:?} against {want:?}");
        }
        let note = diags.iter().find(|d| d.code == "T0211").expect("T0211");
        assert!(
            note.message.contains("what the drawing shows") && note.message.contains("42.4 x 32.4 mm"),
            "{}",
            note.message
        );
        // Shapes across most of the page, a fill across half of it (a flag's
        // triangle) or all of it (a background): the page is fitted, 110 mm
        // wide.
        let triangle = Element {
            shape: Shape::Path(PathShape {
                outline: vec![Polyline { points: vec![(0.0, 0.0), (200.0, 0.0), (0.0, 100.0)], closed: true }],
                ..Default::default()
            }),
            ..filled(square("t", 0.0, 0.0, 1.0))
        };
        let background = filled(square("bg", -5.0, -5.0, 210.0));
        for extra in
            [vec![square("c", 185.0, 85.0, 10.0), square("d", 5.0, 5.0, 1.0)], vec![triangle], vec![background]]
        {
            let mut d = shown(extra);
            assert!(apply(&mut d, &p, true, None, Flattening::DEFAULT, &mut Vec::new()));
            let b = d.elements[0].bounds().unwrap();
            assert!((b.0 - 5.5).abs() < 1e-9 && (b.2 - 22.0).abs() < 1e-9, "{b:?}");
        }
    }

    #[test]
    fn without_fit_one_warning_suggests_it_and_nothing_beyond_the_surface_is_kept() {
        let p = profiles::builtin("stress2").unwrap();
        let mut d = big();
        let mut diags = Vec::new();
        assert!(apply(&mut d, &p, false, None, Flattening::DEFAULT, &mut diags));
        let w: Vec<_> = diags.iter().filter(|d| d.code == "T0202").collect();
        assert_eq!(w.len(), 1);
        assert!(w[0].message.contains("--fit") && w[0].message.contains("2 element(s) beyond it"), "{}", w[0].message);
        // Only `a` (0..100 mm) remains, clipped to the surface.
        assert_eq!(d.elements.len(), 1);
        let Shape::Path(pa) = &d.elements[0].shape else { panic!() };
        assert_eq!(pa.clips.len(), 1);
        assert_eq!(crate::geometry::bounds(&pa.clips[0].outline), Some((0.0, 0.0, 110.0, 60.0)));
    }

    #[test]
    fn a_region_by_rectangle_or_id_is_taken_then_fitted() {
        let p = profiles::builtin("stress2").unwrap();
        // Drawing units are 2 mm: 200,200,50,50 is page mm 400..500, the square `b`.
        for region in [Region::Rect { x: 200.0, y: 200.0, w: 50.0, h: 50.0 }, Region::Element("b".into())] {
            let mut d = big();
            assert!(apply(&mut d, &p, false, Some(&region), Flattening::DEFAULT, &mut Vec::new()), "{region:?}");
            assert_eq!(d.elements.len(), 1, "{region:?}");
            assert_eq!(d.elements[0].id, "b");
            // 100 mm into 60 mm high: scale 0.6, centred x offset (110 - 60) / 2.
            let b = d.elements[0].bounds().unwrap();
            for (got, want) in [b.0, b.1, b.2, b.3].into_iter().zip([25.0, 0.0, 85.0, 60.0]) {
                assert!((got - want).abs() < 1e-9, "{region:?}: {b:?}");
            }
        }
        let mut diags = Vec::new();
        assert!(!apply(
            &mut big(),
            &p,
            false,
            Some(&Region::Element("nowhere".into())),
            Flattening::DEFAULT,
            &mut diags
        ));
        assert_eq!(diags[0].code, "T0210");
    }

    #[test]
    fn text_moves_with_the_drawing() {
        let p = profiles::builtin("stress2").unwrap();
        let mut d = big();
        d.elements.push(Element {
            id: "t".into(),
            visible: true,
            shape: Shape::Text(TextShape {
                content: "A".into(),
                runs: vec![TextRun { text: "A".into(), x_mm: 250.0, y_mm: 250.0, anchor: 0.0, continues: false }],
                font_size_mm: 10.0,
                ..Default::default()
            }),
            ..Default::default()
        });
        assert!(apply(&mut d, &p, true, None, Flattening::DEFAULT, &mut Vec::new()));
        let Shape::Text(t) = &d.elements[3].shape else { panic!() };
        assert_eq!((t.runs[0].x_mm, t.runs[0].y_mm, t.font_size_mm), (25.0 + 30.0, 30.0, 1.2));
    }

    /// A drawing of curves shrunk by `--fit` keeps the points its curves
    /// need at the size they are felt, not the size they were drawn: a
    /// tenth of the size, about a third of the points (flattening's chords
    /// go as the square root of the tolerance). Every point of the curve
    /// stays within the flattening tolerance of its polyline.
    #[test]
    fn a_shrunk_drawing_keeps_the_points_its_felt_size_needs() {
        // 40 wiggles of cubics round a ring, none a circular arc, drawn on a
        // page of 1,100 x 600 mm (fitted to stress2's 110 x 60 mm at 0.1)
        // and on one of 110 x 60 mm (not scaled), over a background that
        // makes `--fit` take the whole page.
        let mut d = String::from("M 550 40");
        for k in 0..40 {
            let a = |t: f64| std::f64::consts::TAU * (k as f64 + t) / 40.0;
            let at = |t: f64, r: f64| (550.0 + 500.0 * r * a(t).sin(), 300.0 - 260.0 * r * a(t).cos());
            let (c1, c2, e) = (at(0.3, 1.08), at(0.6, 0.9), at(1.0, 1.0));
            d += &format!(" C {} {} {} {} {} {}", c1.0, c1.1, c2.0, c2.1, e.0, e.1);
        }
        let svg = |w: u32, h: u32| {
            format!(
                r##"<svg xmlns="http://www.w3.org/2000/svg" width="{w}mm" height="{h}mm" viewBox="0 0 1100 600"><rect width="1100" height="600" fill="#fff"/><path d="{d} Z" fill="#000"/></svg>"##
            )
        };
        let outline = |svg: &str, fit: bool, flattening: Flattening| {
            let opts = crate::CompileOptions {
                fit,
                flattening,
                ..crate::CompileOptions::new(profiles::builtin("stress2").unwrap())
            };
            let d = crate::pipeline::resolve(svg, &opts).drawing.expect("the drawing resolves");
            let Shape::Path(p) = &d.elements[1].shape else { panic!("a path") };
            p.outline.clone()
        };
        let shrunk = outline(&svg(1100, 600), true, Flattening::DEFAULT);
        let felt = outline(&svg(110, 60), false, Flattening::DEFAULT);
        let count = |o: &[Polyline]| o.iter().map(|p| p.points.len()).sum::<usize>();
        let (n_shrunk, n_felt) = (count(&shrunk), count(&felt));
        assert!(n_felt > 200, "the curve has {n_felt} points at its felt size");
        assert!(n_shrunk * 4 <= n_felt * 5, "{n_shrunk} points shrunk from 1,100 mm against {n_felt} drawn at 110 mm");
        let fine = outline(&svg(110, 60), false, Flattening { curves: 1e-5, arcs: 1e-5 });
        for p in fine.iter().flat_map(|pl| pl.points.iter()) {
            let off = geometry::distance_to_outline(&shrunk, *p);
            assert!(off <= FLATTEN_MM + 1e-5 + 1e-9, "{p:?} of the curve is {off} mm from the shrunk outline");
        }
    }

    const FLATTEN_MM: f64 = geometry::FLATTEN_TOLERANCE_MM;
}
