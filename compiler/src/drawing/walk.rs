//! Walks usvg's resolved tree and turns every shape and image it draws into
//! a drawing [`Element`] with its styles, paint and exact geometry in page
//! millimetres.
//!
//! Style resolution (later wins): inherited < style sheet < the element's own
//! annotation (`data-tactile`, else a `tactile:` label). Inheritance follows
//! usvg's tree from the root `<svg>` down, so an element reached through
//! `<use>` inherits from the `<use>`; containers that usvg may flatten away
//! (`a`, `switch`, `symbol`) pass their annotations on from the XML side.

use std::collections::{HashMap, HashSet};

use rayon::prelude::*;
use resvg::tiny_skia::{Path, Transform};
use usvg::{Group, Node};

use super::source::{Kind, Source};
use super::{Clip, Element, Paint, PathShape, Rgba, Shape, StyledBy};
use crate::annotation::Declaration;
use crate::annotation::sheet::{ElementFacts, StyleSheet};
use crate::geometry::{self, FillRule, Polyline};

/// A declaration and where it came from.
pub(crate) type Decl = (Declaration, StyledBy);

/// What the walk found.
pub(crate) struct Walked {
    /// Drawn shapes and images, each with the index of its source element, in tree order.
    pub elements: Vec<(usize, Element)>,
    /// Glyph outlines (page mm) of the `<text>` elements usvg laid out, by source element.
    pub text_outlines: HashMap<usize, Vec<Polyline>>,
    /// The first span's fill of each laid-out text, and its font size in page mm.
    pub text_paint: HashMap<usize, (Paint, f64)>,
    /// Absolute transforms (usvg pixels) of the groups usvg kept, by key.
    pub group_ts: HashMap<String, Transform>,
    /// Source elements that usvg rendered.
    pub seen: HashSet<usize>,
}

/// A drawn element found by the walk, made into a drawing [`Element`] once
/// the walk is over, in parallel: flattening its path and copying its
/// source element's strings were a tenth of the time before the layers that
/// used one core (the 1,000-region map).
struct Found<'t> {
    elem: usize,
    decl: Option<Decl>,
    visible: bool,
    paint: Paint,
    shape: FoundShape<'t>,
}

/// A found element's geometry: a path still to flatten, or a shape.
enum FoundShape<'t> {
    Path { data: &'t Path, ts: Transform, fill_rule: FillRule, markers: Vec<(f64, f64)>, clips: Vec<Clip> },
    Done(Shape),
}

struct Walker<'s, 't> {
    src: &'s Source,
    sheet: Option<&'s StyleSheet>,
    page_ts: Transform,
    out: Walked,
    found: Vec<Found<'t>>,
    /// The glyph paths of each laid-out text, in tree order: its source element and its paths.
    glyphs: Vec<(usize, Vec<(&'t Path, Transform)>)>,
    /// How finely outlines are flattened.
    flattening: geometry::Flattening,
}

/// Walks `tree`; `mm_per_px` maps usvg pixels to page millimetres, and
/// outlines are flattened within `flattening`.
pub(crate) fn walk(
    tree: &usvg::Tree,
    src: &Source,
    sheet: Option<&StyleSheet>,
    mm_per_px: f64,
    flattening: geometry::Flattening,
) -> Walked {
    let s = mm_per_px as f32;
    let mut w = Walker {
        src,
        sheet,
        flattening,
        page_ts: Transform::from_scale(s, s),
        out: Walked {
            elements: Vec::new(),
            text_outlines: HashMap::new(),
            text_paint: HashMap::new(),
            group_ts: HashMap::new(),
            seen: HashSet::new(),
        },
        found: Vec::new(),
        glyphs: Vec::new(),
    };
    // usvg's root group stands for the root `<svg>`, whose annotation applies to the whole drawing.
    let root = src.elements.first().and_then(|_| w.resolve(0, None, None, None));
    let here = (!src.elements.is_empty()).then_some(0);
    let seen = Seen { ts: tree.root().abs_transform(), opacity: tree.root().opacity().get() };
    w.group(tree.root(), root.as_ref(), None, here, &mut Vec::new(), seen);
    let Walker { mut out, found, glyphs, .. } = w;
    // Each element alone, in parallel; collected in the walk's order.
    let (elements, outlines) = rayon::join(
        || {
            found
                .into_par_iter()
                .map(|f| {
                    let shape = match f.shape {
                        FoundShape::Path { data, ts, fill_rule, markers, clips } => Shape::Path(PathShape {
                            outline: geometry::flatten_with(data, ts, flattening),
                            fill_rule,
                            markers,
                            clips,
                        }),
                        FoundShape::Done(shape) => shape,
                    };
                    (f.elem, element_of(&src.elements[f.elem], f.decl, f.visible, f.paint, shape))
                })
                .collect()
        },
        || {
            glyphs
                .par_iter()
                .map(|(elem, paths)| {
                    let outline =
                        paths.iter().flat_map(|&(data, ts)| geometry::flatten_with(data, ts, flattening)).collect();
                    (*elem, outline)
                })
                .collect::<Vec<_>>()
        },
    );
    out.elements = elements;
    // In tree order, so a text usvg met twice keeps its last outline, as it would be inserted last.
    out.text_outlines.extend(outlines);
    out
}

fn rgba(p: &usvg::Paint, opacity: f32) -> Option<Rgba> {
    match p {
        usvg::Paint::Color(c) => Some([c.red, c.green, c.blue, (opacity.clamp(0.0, 1.0) * 255.0).round() as u8]),
        _ => None,
    }
}

fn rgb(p: Option<&usvg::Paint>) -> Option<[u8; 3]> {
    match p {
        Some(usvg::Paint::Color(c)) => Some([c.red, c.green, c.blue]),
        _ => None,
    }
}

/// How much a transform scales lengths (the square root of its area scale).
pub(crate) fn length_scale(ts: Transform) -> f64 {
    let det = ts.sx as f64 * ts.sy as f64 - ts.kx as f64 * ts.ky as f64;
    det.abs().sqrt()
}

/// The paint of a path under `ts` (usvg pixels to page mm).
pub(crate) fn paint_of(fill: Option<&usvg::Fill>, stroke: Option<&usvg::Stroke>, ts: Transform) -> Paint {
    Paint {
        fill: fill.and_then(|f| rgba(f.paint(), f.opacity().get())),
        filled: fill.is_some(),
        stroke: stroke.and_then(|s| rgba(s.paint(), s.opacity().get())),
        stroked: stroke.is_some(),
        stroke_width_mm: stroke.map_or(0.0, |s| s.width().get() as f64 * length_scale(ts)),
    }
}

/// `paint` seen through groups of `opacity` in all: its colours' alpha
/// scaled. A gradient or a pattern (no one colour) seen at no opacity at all
/// is a colour of no alpha: not seen, as a colour would not be.
fn faded(mut paint: Paint, opacity: f32) -> Paint {
    let opacity = if opacity.is_nan() { 0.0 } else { opacity.clamp(0.0, 1.0) };
    let fade = |c: &mut Rgba| c[3] = (f32::from(c[3]) * opacity).round() as u8;
    for c in [paint.fill.as_mut(), paint.stroke.as_mut()].into_iter().flatten() {
        fade(c);
    }
    if (opacity * 255.0).round() == 0.0 {
        for (painted, c) in [(paint.filled, &mut paint.fill), (paint.stroked, &mut paint.stroke)] {
            if painted && c.is_none() {
                *c = Some([0, 0, 0, 0]);
            }
        }
    }
    paint
}

/// The most a mask lets through, from 0 (it hides all it masks: no
/// content, or content that is black in a luminance mask or clear in an
/// alpha one) to 1, as a factor on the masked group's opacity: an upper
/// bound, as resvg renders it (the mask's value at a point is its
/// content's luminance, or alpha, there; the mask of the mask multiplies).
fn mask_strength(mask: &usvg::Mask) -> f32 {
    if mask.root().children().is_empty() {
        return 0.0;
    }
    let alpha = matches!(mask.kind(), usvg::MaskType::Alpha);
    let own = nodes_strength(mask.root(), alpha);
    own * mask.mask().map_or(1.0, mask_strength)
}

/// The most that the children of `g` show in a mask (see [`mask_strength`]).
fn nodes_strength(g: &Group, alpha: bool) -> f32 {
    let mut most = 0.0f32;
    for c in g.children() {
        let s = match c {
            Node::Group(cg) => cg.opacity().get() * nodes_strength(cg, alpha) * cg.mask().map_or(1.0, mask_strength),
            Node::Path(p) if !p.is_visible() => 0.0,
            Node::Path(p) => {
                let fill = p.fill().map_or(0.0, |f| paint_strength(f.paint(), alpha) * f.opacity().get());
                let stroke = p.stroke().map_or(0.0, |s| paint_strength(s.paint(), alpha) * s.opacity().get());
                fill.max(stroke)
            }
            Node::Text(t) => nodes_strength(t.flattened(), alpha),
            Node::Image(im) if !im.is_visible() => 0.0,
            Node::Image(_) => 1.0,
        };
        most = most.max(if s.is_nan() { 1.0 } else { s.clamp(0.0, 1.0) });
    }
    most
}

/// The most a paint shows in a mask: a colour's luminance (the weights
/// tiny-skia's luminance masks use), or 1 in an alpha mask; a gradient's
/// most between any two of its stops; a pattern may show anything.
fn paint_strength(p: &usvg::Paint, alpha: bool) -> f32 {
    let luma = |c: usvg::Color| {
        if alpha {
            1.0
        } else {
            (0.2125 * f32::from(c.red) + 0.7154 * f32::from(c.green) + 0.0721 * f32::from(c.blue)) / 255.0
        }
    };
    let stops = |s: &[usvg::Stop]| {
        let at = |s: &usvg::Stop| (luma(s.color()), s.opacity().get());
        // One stop alone has no pair to lie between.
        let one = s.iter().map(at).map(|(l, a)| l * a).fold(0.0, f32::max);
        s.windows(2).map(|w| between(at(&w[0]), at(&w[1]))).fold(one, f32::max)
    };
    match p {
        usvg::Paint::Color(c) => luma(*c),
        usvg::Paint::LinearGradient(g) => stops(g.stops()),
        usvg::Paint::RadialGradient(g) => stops(g.stops()),
        usvg::Paint::Pattern(_) => 1.0,
    }
}

/// The most of `l(t) a(t)` for `t` in 0..1, where luminance `l` and alpha
/// `a` go in a straight line from `(l0, a0)` to `(l1, a1)`: between two
/// stops, a colour going lighter as it fades shows most in the middle
/// (white at alpha 0 to black shows a quarter at half way).
fn between((l0, a0): (f32, f32), (l1, a1): (f32, f32)) -> f32 {
    let (dl, da) = (l1 - l0, a1 - a0);
    let f = |t: f32| (l0 + dl * t) * (a0 + da * t);
    // The product's turning point, where its slope l0 da + a0 dl + 2 dl da t is 0.
    let turn = -(l0 * da + a0 * dl) / (2.0 * dl * da);
    let inner = if turn.is_finite() && (0.0..=1.0).contains(&turn) { f(turn) } else { 0.0 };
    f(0.0).max(f(1.0)).max(inner)
}

/// The regions a mask may show, in page mm (`base` maps the masked group's
/// user units there): its rectangle, and, where its content is only filled
/// shapes, those of them that show anything (their union, kept as one
/// [`Clip`] as [`clip_regions`] keeps a clip path's). Where the content
/// strokes, draws images or text, or masks again, its rectangle alone
/// bounds it: what is felt may then reach past what is seen, never less.
fn mask_regions(mask: &usvg::Mask, base: Transform, flattening: geometry::Flattening, out: &mut Vec<Clip>) {
    let rect = resvg::tiny_skia::PathBuilder::from_rect(mask.rect().to_rect());
    out.push(Clip { outline: geometry::flatten_with(&rect, base, flattening), fill_rule: FillRule::NonZero });
    let alpha = matches!(mask.kind(), usvg::MaskType::Alpha);
    let mut shown = Clip::default();
    let mut rule = None;
    if mask_shapes(mask.root(), base, flattening, alpha, &mut shown, &mut rule) {
        shown.fill_rule = rule.unwrap_or_default();
        out.push(shown);
    }
    if let Some(inner) = mask.mask() {
        mask_regions(inner, base, flattening, out);
    }
}

/// Gathers into `region` the outlines of the shapes under `g` that show in
/// a mask; `false` where some content is not a plain filled shape (its
/// extent is not its outline).
fn mask_shapes(
    g: &Group,
    ts: Transform,
    flattening: geometry::Flattening,
    alpha: bool,
    region: &mut Clip,
    rule: &mut Option<FillRule>,
) -> bool {
    for c in g.children() {
        match c {
            Node::Group(cg) => {
                let plain = cg.filters().is_empty() && cg.mask().is_none() && cg.clip_path().is_none();
                if !plain || !mask_shapes(cg, ts.pre_concat(cg.transform()), flattening, alpha, region, rule) {
                    return false;
                }
            }
            Node::Path(p) => {
                if p.stroke().is_some_and(|s| paint_strength(s.paint(), alpha) * s.opacity().get() > 0.0) {
                    return false;
                }
                let shows = p.fill().is_some_and(|f| paint_strength(f.paint(), alpha) * f.opacity().get() > 0.0);
                if p.is_visible() && shows {
                    rule.get_or_insert(fill_rule(p));
                    region.outline.extend(geometry::flatten_with(p.data(), ts, flattening));
                }
            }
            Node::Text(_) | Node::Image(_) => return false,
        }
    }
    true
}

/// How a group is seen: its transform to the root, and the product of its
/// opacity and those of the groups round it, which its paths' paint is
/// seen at (an element drawn at opacity 0 is not seen, and does not hide
/// what lies under it).
#[derive(Clone, Copy)]
struct Seen {
    ts: Transform,
    opacity: f32,
}

/// The regions of a clip path (and of the clip path on it), in page mm.
///
/// A clip path made of several shapes is their union; it is kept as one
/// [`Clip`] whose outline holds them all under the first shape's rule, which
/// is exact for shapes that do not overlap (the common case: one shape).
fn clip_regions(clip: &usvg::ClipPath, base: Transform, flattening: geometry::Flattening, out: &mut Vec<Clip>) {
    let ts = base.pre_concat(clip.transform());
    let mut region = Clip::default();
    let mut first_rule = None;
    clip_group(clip.root(), ts, flattening, &mut region, &mut first_rule);
    region.fill_rule = first_rule.unwrap_or_default();
    out.push(region);
    if let Some(inner) = clip.clip_path() {
        clip_regions(inner, base, flattening, out);
    }
}

fn clip_group(
    g: &Group,
    ts: Transform,
    flattening: geometry::Flattening,
    region: &mut Clip,
    rule: &mut Option<FillRule>,
) {
    for c in g.children() {
        match c {
            Node::Group(cg) => clip_group(cg, ts.pre_concat(cg.transform()), flattening, region, rule),
            // A hidden shape clips nothing in (SVG 1.1, 14.3.5).
            Node::Path(p) if p.is_visible() => {
                rule.get_or_insert(fill_rule(p));
                region.outline.extend(geometry::flatten_with(p.data(), ts, flattening));
            }
            Node::Path(_) => {}
            Node::Text(t) => {
                let fg = t.flattened();
                clip_group(fg, ts.pre_concat(fg.transform()), flattening, region, rule);
            }
            Node::Image(_) => {}
        }
    }
}

fn fill_rule(p: &usvg::Path) -> FillRule {
    match p.fill().map(|f| f.rule()) {
        Some(usvg::FillRule::EvenOdd) => FillRule::EvenOdd,
        _ => FillRule::NonZero,
    }
}

/// The drawing element of source element `e` with `decl` in force.
pub(crate) fn element_of(
    e: &super::source::Element,
    decl: Option<Decl>,
    visible: bool,
    paint: Paint,
    shape: Shape,
) -> Element {
    let (styles, styled_by) = match decl {
        Some((d, by)) => (d.styles().to_vec(), by),
        None => (Vec::new(), StyledBy::Nothing),
    };
    Element {
        id: e.id.clone(),
        name: e.name.clone(),
        line: e.line,
        label: e.label.clone(),
        tag: e.tag.clone(),
        classes: e.classes.clone(),
        layers: e.layers.clone(),
        styles,
        styled_by,
        visible,
        paint,
        shape,
    }
}

impl<'t> Walker<'_, 't> {
    /// The declaration in force at a node whose element is `elem`, given what
    /// its usvg parent has.
    fn resolve(
        &self,
        elem: usize,
        fill: Option<[u8; 3]>,
        stroke: Option<[u8; 3]>,
        inherited: Option<&Decl>,
    ) -> Option<Decl> {
        let e = &self.src.elements[elem];
        if let Some(own) = &e.own {
            return Some((own.clone(), StyledBy::Annotation));
        }
        if let Some(sheet) = self.sheet {
            let facts = ElementFacts { id: &e.id, classes: &e.classes, layers: &e.layers, fill, stroke };
            if let Some(r) = sheet.lookup(&facts) {
                return Some((r.declaration.clone(), StyledBy::StyleSheet));
            }
        }
        // Containers usvg may have flattened away between this element and its usvg parent.
        let mut p = e.parent;
        while let Some(i) = p {
            let a = &self.src.elements[i];
            if a.kind != Kind::Container {
                break;
            }
            if let Some(d) = &a.own {
                return Some((d.clone(), StyledBy::Annotation));
            }
            if let Some(d) = &a.sheet {
                return Some((d.clone(), StyledBy::StyleSheet));
            }
            p = a.parent;
        }
        inherited.cloned()
    }

    /// Records the drawing element of source element `elem` with `decl` in force.
    fn element(&mut self, elem: usize, decl: Option<Decl>, visible: bool, paint: Paint, shape: FoundShape<'t>) {
        self.found.push(Found { elem, decl, visible, paint, shape });
    }

    fn bounds_mm(&self, r: usvg::Rect) -> Option<(f64, f64, f64, f64)> {
        let s = self.page_ts.sx as f64;
        let b = (r.left() as f64 * s, r.top() as f64 * s, r.right() as f64 * s, r.bottom() as f64 * s);
        [b.0, b.1, b.2, b.3].iter().all(|v| v.is_finite()).then_some(b)
    }

    /// Walks a group. `owner` is the `<use>` whose copy this is, if any: usvg
    /// clears the ids of the elements it copies, so those belong to the `<use>`.
    /// `here` is the source element of the nearest group with one.
    /// `seen` is how `g` is seen: its transform to the root, and its opacity.
    fn group(
        &mut self,
        g: &'t Group,
        inherited: Option<&Decl>,
        owner: Option<usize>,
        here: Option<usize>,
        clips: &mut Vec<Clip>,
        seen: Seen,
    ) {
        let opacity = seen.opacity;
        let children = g.children();
        let mut skip_next = false;
        for (i, child) in children.iter().enumerate() {
            if std::mem::take(&mut skip_next) {
                continue;
            }
            match child {
                Node::Group(cg) => {
                    let own = self.src.get(cg.id(), here).map(|(ei, _)| ei);
                    // The group's transform to the root, from its parent's
                    // (usvg's own leaves out the transform of the group it
                    // adds to clip a `<use>` of a symbol to its viewport).
                    let abs = seen.ts.pre_concat(cg.transform());
                    let decl = match own {
                        Some(ei) => {
                            self.out.seen.insert(ei);
                            self.out.group_ts.insert(cg.id().to_string(), abs);
                            self.resolve(ei, None, None, inherited)
                        }
                        None => inherited.cloned(),
                    };
                    // usvg wraps an <image> in a group that carries its id.
                    if let Some(ei) = own.filter(|&ei| self.src.elements[ei].tag == "image") {
                        if let Some(bounds) = self.bounds_mm(cg.abs_bounding_box()) {
                            self.element(ei, decl, true, Paint::default(), FoundShape::Done(Shape::Image { bounds }));
                        }
                        continue;
                    }
                    let before = clips.len();
                    let base = self.page_ts.pre_concat(abs);
                    if let Some(c) = cg.clip_path() {
                        clip_regions(c, base, self.flattening, clips);
                    }
                    // A mask is seen as what it may show: a clip to where
                    // it shows anything, and a fade to the most it shows
                    // (none: the group is not seen, as at opacity 0).
                    let mut shown = opacity * cg.opacity().get();
                    if let Some(m) = cg.mask() {
                        mask_regions(m, base, self.flattening, clips);
                        shown *= mask_strength(m);
                    }
                    let owner = own.filter(|&ei| self.src.elements[ei].tag == "use").or(owner);
                    self.group(cg, decl.as_ref(), owner, own.or(here), clips, Seen { ts: abs, opacity: shown });
                    clips.truncate(before);
                }
                Node::Path(p) => {
                    let found = if p.id().is_empty() { owner } else { self.src.get(p.id(), here).map(|(ei, _)| ei) };
                    let Some(ei) = found else { continue };
                    self.out.seen.insert(ei);
                    let markers = if self.src.elements[ei].has_markers {
                        match children.get(i + 1) {
                            Some(Node::Group(mg)) if mg.id().is_empty() => {
                                skip_next = true;
                                mg.children().iter().filter_map(|m| self.centre(m.abs_bounding_box())).collect()
                            }
                            _ => Vec::new(),
                        }
                    } else {
                        Vec::new()
                    };
                    let decl = self.resolve(
                        ei,
                        rgb(p.fill().map(|f| f.paint())),
                        rgb(p.stroke().map(|s| s.paint())),
                        inherited,
                    );
                    // (Its group's transform to the root, as composed above.)
                    let ts = self.page_ts.pre_concat(seen.ts);
                    let shape =
                        FoundShape::Path { data: p.data(), ts, fill_rule: fill_rule(p), markers, clips: clips.clone() };
                    let paint = faded(paint_of(p.fill(), p.stroke(), ts), opacity);
                    self.element(ei, decl, p.is_visible(), paint, shape);
                }
                Node::Text(t) => {
                    let Some((ei, _)) = self.src.get(t.id(), here) else { continue };
                    self.out.seen.insert(ei);
                    let mut paths = Vec::new();
                    glyph_paths(t.flattened(), self.page_ts, &mut paths);
                    self.glyphs.push((ei, paths));
                    let span = t.chunks().first().and_then(|c| c.spans().first());
                    if let Some(span) = span {
                        let ts = self.page_ts.pre_concat(t.abs_transform());
                        let mut paint = faded(paint_of(span.fill(), span.stroke(), ts), opacity);
                        // Laid out with neither fill nor stroke (a scanned
                        // PDF's hidden text layer): seen as a fill of no
                        // alpha, unlike a text no fonts laid out, whose
                        // paint is not known.
                        if !(paint.filled || paint.stroked) {
                            (paint.filled, paint.fill) = (true, Some([0, 0, 0, 0]));
                        }
                        self.out.text_paint.insert(ei, (paint, span.font_size().get() as f64 * length_scale(ts)));
                    }
                }
                Node::Image(im) => {
                    if let Some((ei, _)) = self.src.get(im.id(), here) {
                        self.out.seen.insert(ei);
                        if let Some(bounds) = self.bounds_mm(im.abs_bounding_box()) {
                            let decl = self.resolve(ei, None, None, inherited);
                            let shape = FoundShape::Done(Shape::Image { bounds });
                            self.element(ei, decl, im.is_visible(), Paint::default(), shape);
                        }
                    }
                }
            }
        }
    }

    fn centre(&self, r: usvg::Rect) -> Option<(f64, f64)> {
        let s = self.page_ts.sx as f64;
        let c = ((r.left() as f64 + r.right() as f64) / 2.0 * s, (r.top() as f64 + r.bottom() as f64) / 2.0 * s);
        (c.0.is_finite() && c.1.is_finite()).then_some(c)
    }
}

/// The glyph paths of a laid-out text, each with its transform to page mm.
fn glyph_paths<'t>(g: &'t Group, page_ts: Transform, out: &mut Vec<(&'t Path, Transform)>) {
    for c in g.children() {
        match c {
            Node::Path(p) => out.push((p.data(), page_ts.pre_concat(p.abs_transform()))),
            Node::Group(g) => glyph_paths(g, page_ts, out),
            _ => {}
        }
    }
}
