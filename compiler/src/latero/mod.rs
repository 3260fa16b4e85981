//! Back end for laterotactile arrays (stage 4, family 1).
//!
//! From the resolved drawing to layers: one distance layer per vibration or
//! grating style (every shape of that style, SPEC.md section 6.2), dot
//! tables per kind, brush requests for grid devices, provenance, and the
//! features the design rules look at. Braille's dots and the clearing
//! around them are placed in `braille.rs`. What each distance layer is made
//! of is the public plan (`plan.rs`, [`LayerPlan`]), from which the layers
//! are built; `key.rs` compiles the key as a second bundle.

mod braille;
#[doc(hidden)]
pub mod distance;
mod dots;
mod footprints;
pub mod key;
mod plan;

use braille::clearing_within;
pub use distance::{ExactRegion, LayerGeometry, ON_EDGE_MM, Segment};
pub use plan::{LayerPlan, PlannedLayer, plan};

use std::collections::HashMap;

use rayon::prelude::*;

use taxel_format::{
    Chunk, DistanceLayer, Dot, DotKind, DotTable, Family, MilliHertz, Mm, Provenance, ProvenanceEntry, StrokeTable,
};

use self::distance::{FieldParams, build_field_within};
use self::footprints::Pending as FootPending;
use crate::annotation::{Grating, Style, Vibrate};
use crate::brush::{self, BrushRequest};
use crate::diagnostic::Diagnostic;
use crate::drawing::{Clip, Drawing, Element, Page, Shape};
use crate::geometry::Polyline;
use crate::options::CompileOptions;

/// Smallest distance between distinct elements (1/8 in, Hasty): the
/// design rules' gap, and the clearing kept around braille.
pub const MIN_GAP_MM: f64 = 3.2;

/// What a feature is, with the parameters the design rules need.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum FeatureKind {
    Vibrate { width_mm: f64, freq_hz: f64 },
    Grating { wavelength_mm: f64, angle_deg: f64 },
    Dots { radius_mm: f64, spacing_mm: f64 },
    Dot { radius_mm: f64 },
    Braille,
}

/// One rendered style of one element.
#[derive(Debug, Clone)]
pub(crate) struct Feature {
    /// The source element it comes from (its provenance entry): the copies a
    /// `<use>` makes share one.
    pub elem: usize,
    pub name: String,
    pub line: u32,
    pub kind: FeatureKind,
    /// The outline (masks) in page mm; empty for dots.
    pub outline: Vec<Polyline>,
    /// Half the width of the band around the outline that the feature covers (vibration), else 0.
    pub half_band: f64,
    /// Dots `(x, y, radius)` for dot features.
    pub dots: Vec<(f64, f64, f64)>,
    /// Footprint bounds `(x0, y0, x1, y1)`.
    pub bbox: (f64, f64, f64, f64),
    /// Index of its layer in [`Built::layers`] (shapes of one style share one).
    pub mask: Option<usize>,
    pub amplitude: f64,
}

/// Everything the layers stage made.
#[derive(Default)]
pub(crate) struct Built {
    /// One distance layer per vibration or grating style (and clip).
    pub layers: Vec<DistanceLayer>,
    pub outline_dots: Vec<Dot>,
    pub symbol_dots: Vec<Dot>,
    pub braille_dots: Vec<Dot>,
    pub strokes: Option<StrokeTable>,
    pub provenance: Vec<ProvenanceEntry>,
    /// Where each element's rendered styles lie, for the footprints chunk.
    pub footprints: Vec<FootPending>,
    pub features: Vec<Feature>,
    /// Elements that asked for any tactile style.
    pub styled_elements: usize,
    /// Styles whose layer came out empty, so nothing was made for them: what
    /// they cover is hidden under opaque fills painted later, clipped away or
    /// off the surface. Said when nothing at all is made (T0300).
    pub unfelt: Vec<Unfelt>,
    /// Styles whose layer the memory budget stopped (their style's name
    /// and elements, drawing indices): each an error (T0308).
    pub over_budget: Vec<(&'static str, Vec<usize>)>,
    /// Where gratings are not felt around the braille written
    /// ([`braille::braille_clearing`]).
    pub braille_clear: Vec<Polyline>,
    /// The drawing's key ([`crate::style::legend()`]), as the braille stage
    /// read it for the provenance: the key's own bundle is made from it
    /// too, rather than reading the drawing again (a tenth of a second on
    /// the map at the input limit).
    pub legend: Option<crate::style::legend::Legend>,
    prov_index: HashMap<(String, u32), u32>,
}

/// A style whose layer came out empty.
pub(crate) struct Unfelt {
    /// The style's name (`grating`, `vibrate`).
    pub style: &'static str,
    /// The elements (drawing indices) that asked for it.
    pub elements: Vec<usize>,
    /// The opaque fills painted over them (drawing indices), which hide them.
    pub covered_by: Vec<usize>,
}

impl Built {
    /// Whether no layer was made.
    pub fn is_empty(&self) -> bool {
        self.layers.is_empty()
            && self.outline_dots.is_empty()
            && self.symbol_dots.is_empty()
            && self.braille_dots.is_empty()
            && self.strokes.as_ref().is_none_or(|s| s.strokes.is_empty())
    }

    /// The chunks, in a fixed order: distance layers in the document order
    /// of their styles' first shapes, dot tables (outline, symbol, braille),
    /// strokes, provenance, footprints.
    pub fn into_chunks(self) -> Vec<Chunk> {
        let mut out: Vec<Chunk> = self.layers.into_iter().map(Chunk::Distance).collect();
        for (kind, dots) in [
            (DotKind::Outline, self.outline_dots),
            (DotKind::Symbol, self.symbol_dots),
            (DotKind::Braille, self.braille_dots),
        ] {
            if !dots.is_empty() {
                out.push(Chunk::Dots(DotTable { kind, dots }));
            }
        }
        if let Some(s) = self.strokes.filter(|s| !s.strokes.is_empty()) {
            out.push(Chunk::Strokes(s));
        }
        if !self.provenance.is_empty() {
            out.push(Chunk::Provenance(Provenance { entries: self.provenance }));
            if let Some(f) = footprints::chunk(self.footprints) {
                out.push(Chunk::Footprints(f));
            }
        }
        out
    }

    /// The provenance entry of the source element that `e` comes from (its name and line).
    fn source(&mut self, e: &Element) -> u32 {
        if let Some(&i) = self.prov_index.get(&(e.name.clone(), e.line)) {
            return i;
        }
        let i = self.provenance.len() as u32;
        self.provenance.push(ProvenanceEntry { id: e.id.clone(), label: e.label.clone(), line: e.line });
        self.prov_index.insert((e.name.clone(), e.line), i);
        i
    }

    fn push_dots(&mut self, kind: DotKind, pts: &[(f64, f64)], radius: f64, amplitude: f64, source: u32) {
        let table = match kind {
            DotKind::Outline => &mut self.outline_dots,
            DotKind::Symbol => &mut self.symbol_dots,
            DotKind::Braille => &mut self.braille_dots,
        };
        table.extend(pts.iter().filter(|p| p.0.is_finite() && p.1.is_finite()).map(|&(x, y)| Dot {
            x: Mm(x as f32),
            y: Mm(y as f32),
            radius: Mm(radius as f32),
            amplitude: amplitude as f32,
            source: Some(source),
        }));
    }
}

/// Whether a style is rendered on devices of `family`.
fn renders_on(style: &Style, family: Family) -> bool {
    match style {
        Style::Brush(_) => family == Family::Grid,
        _ => family == Family::Laterotactile,
    }
}

/// The warning for a style that the device's family does not play.
pub(super) const NOT_ON_DEVICE: &str = "T0120";

fn not_here(style: &Style, e: &str, line: u32, profile: &str) -> Diagnostic {
    let help = match style {
        Style::Brush(_) => "brush() strokes play on vibrotactile grids such as brush-4x3",
        _ => "vibrate, grating, dots, dot and braille play on laterotactile arrays such as stress2",
    };
    Diagnostic::warning(NOT_ON_DEVICE, format!("`{}` is not rendered on {profile}; it is left out", style.name()))
        .with_element(e)
        .with_help(help)
        .at_line(line)
}

/// The style of one distance layer: kind and every parameter, compared exactly.
#[derive(Debug, Clone, Copy, PartialEq)]
enum LayerStyle {
    Vibrate(Vibrate),
    Grating(Grating),
}

/// A distance layer being gathered: its style, the clip regions its shapes
/// share, and the drawing elements it holds.
struct Pending {
    style: LayerStyle,
    clips: Vec<Clip>,
    elements: Vec<usize>,
}

/// The lattice pitch of distance layers at a resolution of `px` px/mm: five
/// pixels (0.5 mm at the default 10 px/mm), and at most half the narrowest
/// vibrating band's width. A distance is affine across a cell wherever one
/// straight edge is nearest, so its interpolation is exact there at any
/// pitch; the pitch bounds how sharp a corner stays and how far a curve of
/// radius `r` moves (about h²/8r). Within half the band's width, the lattice
/// points beside a band's centre line are inside the band, so a narrow band
/// is never lost between them.
pub(crate) fn field_pitch(px: f32, band_mm: Option<f64>) -> f64 {
    let h = 5.0 / px as f64;
    match band_mm {
        Some(w) if w > 0.0 => h.min(w / 2.0),
        _ => h,
    }
}

/// The clip regions of an element.
fn clips_of(e: &Element) -> &[Clip] {
    match &e.shape {
        Shape::Path(p) => &p.clips,
        _ => &[],
    }
}

/// The outline a style is rendered from (glyph outlines for text).
fn outline(e: &Element) -> &[Polyline] {
    e.outline()
}

/// Builds every layer of `drawing` at `px` samples per mm.
///
/// `beside` is given the features (the design rules' input) and runs
/// beside the distance fields; its result comes back with what was built.
pub(crate) fn build<R: Send>(
    drawing: &Drawing,
    opts: &CompileOptions,
    px: f32,
    diags: &mut Vec<Diagnostic>,
    beside: impl FnOnce(&[Feature]) -> R + Send,
) -> (Built, R) {
    let (mut b, mut plan) = walk(drawing, opts, px, diags);
    let requests = std::mem::take(&mut plan.brush);
    let features = std::mem::take(&mut b.features);
    let (built_index, beside) =
        rayon::join(|| distance_layers(&mut b, drawing, &plan, opts.memory.as_ref()), || beside(&features));
    b.features = features;
    for (style, elements) in std::mem::take(&mut b.over_budget) {
        diags.push(over_budget(drawing, style, &elements, opts.memory.as_ref()));
    }
    // Features name their built layer (a style whose field came out empty has none).
    for f in &mut b.features {
        if let Some(k) = f.mask {
            f.mask = built_index.get(k).copied().flatten();
        }
    }
    if !requests.is_empty() {
        b.strokes = brush::compile_strokes(&requests, &opts.profile, diags);
    }
    (b, beside)
}

/// Walks `drawing`'s styled elements: the features, dots, braille and
/// provenance (in the [`Built`]) and the [`LayerPlan`] of its layers, with
/// the warnings of each element.
fn walk<'d>(
    drawing: &'d Drawing,
    opts: &CompileOptions,
    px: f32,
    diags: &mut Vec<Diagnostic>,
) -> (Built, LayerPlan<'d>) {
    let family = opts.profile.family();
    let profile = opts.profile.name.as_str();
    let page = drawing.page;
    let mut b = Built::default();
    let mut requests: Vec<BrushRequest> = Vec::new();
    let mut pending: Vec<Pending> = Vec::new();
    // Where layers can be felt: the page, on the device's surface.
    let felt =
        (page.width_mm.min(opts.profile.surface_w_mm as f64), page.height_mm.min(opts.profile.surface_h_mm as f64));
    for (index, e) in drawing.elements.iter().enumerate() {
        if e.styles.is_empty() {
            continue;
        }
        b.styled_elements += 1;
        if let Shape::Image { .. } = e.shape {
            diags.push(
                Diagnostic::warning("T0305", "images are not rendered tactilely; this one is left out")
                    .with_element(&e.name)
                    .with_help("trace the picture as paths (Inkscape: Path > Trace Bitmap) and annotate the paths")
                    .at_line(e.line),
            );
            continue;
        }
        // Braille is made from a text's characters (below), never from its glyph outlines.
        let is_text = matches!(e.shape, Shape::Text(_));
        let styles: Vec<&Style> = e.styles.iter().filter(|s| !(is_text && matches!(s, Style::Braille(_)))).collect();
        if styles.is_empty() {
            continue;
        }
        let polylines = outline(e);
        if is_text && polylines.is_empty() {
            // Glyph outlines need fonts, which are optional: without them only braille is made of text.
            continue;
        }
        if !e.visible {
            diags.push(
                Diagnostic::warning("T0301", "this shape is hidden (visibility: hidden); nothing is rendered for it")
                    .with_element(&e.name)
                    .at_line(e.line),
            );
            continue;
        }
        let clipped_away = clips_of(e).iter().any(|c| c.outline.is_empty());
        if polylines.is_empty() || clipped_away {
            let what = if clipped_away { "this shape is clipped or masked away" } else { "this shape is empty" };
            diags.push(
                Diagnostic::warning("T0301", format!("{what}; nothing is rendered for it"))
                    .with_element(&e.name)
                    .at_line(e.line),
            );
            continue;
        }
        let markers: &[(f64, f64)] = match &e.shape {
            Shape::Path(p) => &p.markers,
            _ => &[],
        };
        for &style in &styles {
            if !renders_on(style, family) {
                diags.push(not_here(style, &e.name, e.line, profile));
                continue;
            }
            match *style {
                Style::Vibrate(v) => {
                    let fk = FeatureKind::Vibrate { width_mm: v.width_mm, freq_hz: v.freq_hz };
                    layer_feature(&mut b, &mut pending, index, e, LayerStyle::Vibrate(v), fk, felt, diags);
                }
                Style::Grating(g) => {
                    let fk = FeatureKind::Grating { wavelength_mm: g.wavelength_mm, angle_deg: g.angle_deg };
                    layer_feature(&mut b, &mut pending, index, e, LayerStyle::Grating(g), fk, felt, diags);
                }
                Style::Dots(d) => {
                    let pts = dots::along(polylines, d.radius_mm, d.spacing_mm, &e.name, diags);
                    let spacing = d.spacing_mm.unwrap_or(3.0 * d.radius_mm).max(2.0 * d.radius_mm);
                    let fk = FeatureKind::Dots { radius_mm: d.radius_mm, spacing_mm: spacing };
                    let (kind, radius, amplitude) = (DotKind::Outline, d.radius_mm, d.amplitude);
                    let job = DotJob { e, order: index, kind, radius, amplitude, fk };
                    dot_feature(&mut b, job, &pts, page, diags);
                }
                Style::Dot(d) => {
                    let pts = dots::symbol(polylines, markers);
                    let fk = FeatureKind::Dot { radius_mm: d.radius_mm };
                    let (kind, radius, amplitude) = (DotKind::Symbol, d.radius_mm, d.amplitude);
                    let job = DotJob { e, order: index, kind, radius, amplitude, fk };
                    dot_feature(&mut b, job, &pts, page, diags);
                }
                Style::Braille(_) => diags.push(
                    Diagnostic::warning(
                        "T0121",
                        "braille() applies to <text> elements; this shape is left out of the braille",
                    )
                    .with_element(&e.name)
                    .at_line(e.line),
                ),
                Style::Brush(br) => {
                    // No footprint: a brushed stroke plays in time on a grid
                    // worn on the body, with no reader's position on the page
                    // for a host to look up (SPEC.md section 10.1).
                    let source = b.source(e);
                    for pl in polylines {
                        requests.push(BrushRequest {
                            polyline: pl.walked(),
                            duration_ms: br.duration_ms,
                            intensity: br.intensity,
                            freq_hz: br.freq_hz,
                            start_ms: br.start_ms,
                            source: Some(source),
                            element: e.name.clone(),
                            line: Some(e.line),
                        });
                    }
                }
            }
        }
    }
    // Braille adds features and no layer (nor reads any), so it comes before the fields.
    // The opaque fills, which hide what is painted under them: from the
    // key's textures (braille) and from the grated layers (the plan).
    let opaque = crate::drawing::OpaqueFills::of(drawing);
    braille::braille_texts(&mut b, drawing, opts, &opaque, diags);
    let clearing = std::mem::take(&mut b.braille_clear);
    let source_of = |i: usize| {
        let e = &drawing.elements[i];
        b.prov_index.get(&(e.name.clone(), e.line)).copied()
    };
    let mut plan = LayerPlan::new(drawing, &pending, source_of, clearing, px, felt, &opaque);
    plan.dots =
        [(DotKind::Outline, &b.outline_dots), (DotKind::Symbol, &b.symbol_dots), (DotKind::Braille, &b.braille_dots)]
            .into_iter()
            .filter(|(_, dots)| !dots.is_empty())
            .map(|(kind, dots)| DotTable { kind, dots: dots.clone() })
            .collect();
    plan.brush = requests;
    (b, plan)
}

/// Records one element's vibration or grating style: a feature for the
/// design rules, and the element's place in its style's layer.
#[allow(clippy::too_many_arguments)]
fn layer_feature(
    b: &mut Built,
    pending: &mut Vec<Pending>,
    index: usize,
    e: &Element,
    style: LayerStyle,
    fk: FeatureKind,
    felt: (f64, f64),
    diags: &mut Vec<Diagnostic>,
) {
    let (half_band, amplitude) = match style {
        LayerStyle::Vibrate(v) => (v.width_mm / 2.0, v.amplitude),
        LayerStyle::Grating(g) => (0.0, g.amplitude),
    };
    if let LayerStyle::Vibrate(v) = style
        && MilliHertz::from_hz(v.freq_hz).is_none()
    {
        return;
    }
    let on_page = crate::geometry::bounds(outline(e))
        .map(|r| (r.0 - half_band, r.1 - half_band, r.2 + half_band, r.3 + half_band))
        .map(|r| (r.0.max(0.0), r.1.max(0.0), r.2.min(felt.0), r.3.min(felt.1)))
        .filter(|r| r.2 > r.0 && r.3 > r.1);
    let Some(bbox) = on_page else {
        diags.push(
            Diagnostic::warning(
                "T0301",
                "nothing of this shape is left on the page (empty, invisible or outside the page)",
            )
            .with_element(&e.name)
            .at_line(e.line),
        );
        return;
    };
    let source = b.source(e);
    b.footprints.extend(match style {
        LayerStyle::Vibrate(_) => FootPending::band(index, source, outline(e), half_band),
        LayerStyle::Grating(_) => FootPending::area(index, source, outline(e), fill_rule(e)),
    });
    let clips = clips_of(e);
    let layer = match pending.iter().position(|p| p.style == style && p.clips == clips) {
        Some(k) => k,
        None => {
            pending.push(Pending { style, clips: clips.to_vec(), elements: Vec::new() });
            pending.len() - 1
        }
    };
    pending[layer].elements.push(index);
    b.features.push(Feature {
        elem: source as usize,
        name: e.name.clone(),
        line: e.line,
        kind: fk,
        outline: outline(e).to_vec(),
        half_band,
        dots: Vec::new(),
        bbox,
        mask: Some(layer),
        amplitude,
    });
}

/// The error for a style's layer that the memory budget stopped: at its
/// first element, naming how many it has.
fn over_budget(
    drawing: &Drawing,
    style: &str,
    elements: &[usize],
    budget: Option<&crate::budget::MemoryBudget>,
) -> Diagnostic {
    let limit = budget.map_or_else(|| "the memory budget".to_string(), |b| crate::budget::human_bytes(b.limit));
    let more = match elements.len() {
        0 | 1 => String::new(),
        n => format!(" (and {} more of its elements)", n - 1),
    };
    let d = Diagnostic::error(
        crate::budget::OVER_BUDGET,
        format!("building the {style} layer needs more memory than the limit of {limit}{more}: stopped"),
    )
    .with_help(crate::budget::OVER_BUDGET_HELP);
    match elements.first().and_then(|&i| drawing.elements.get(i)) {
        Some(e) => d.with_element(&e.name).at_line(e.line),
        None => d,
    }
}

/// Builds each planned layer's distance field (vibrating outlines as one
/// band of the style, so touching borders merge; grated regions as one fill
/// less the vibrating bands that cross them, each within its clip regions
/// and the part of the page on the device's surface); returns each
/// gathered style's layer index (`None` for a style whose field came out
/// empty).
fn distance_layers(
    b: &mut Built,
    drawing: &Drawing,
    plan: &LayerPlan<'_>,
    budget: Option<&crate::budget::MemoryBudget>,
) -> Vec<Option<usize>> {
    // Every style's field at once: a layer's own setup (its segments'
    // buckets, the inside bits) runs on one thread, and with the layers one
    // after another the other core would wait for it at every layer. They
    // are pushed in style order afterwards, as before.
    let built: Vec<_> = (0..plan.layers.len())
        .into_par_iter()
        .filter_map(|k| {
            let l = &plan.layers[k];
            let geometry = plan.geometry(drawing, k)?;
            let params = FieldParams { pitch_mm: plan.pitch_mm, soft_mm: l.soft_mm, page: plan.page };
            Some((k, build_field_within(&geometry, params, budget)))
        })
        .collect();
    let pending = plan.layers.iter().map(|l| l.pending + 1).max().unwrap_or(0);
    let mut built_index = vec![None; pending];
    for (k, field) in built {
        let l = &plan.layers[k];
        let style = l.style_name();
        let field = match field {
            Ok(Some(field)) => field,
            Ok(None) => {
                b.unfelt.push(Unfelt { style, elements: l.elements.clone(), covered_by: l.covered_by.clone() });
                continue;
            }
            Err(crate::budget::OverBudget) => {
                b.over_budget.push((style, l.elements.clone()));
                continue;
            }
        };
        built_index[l.pending] = Some(b.layers.len());
        b.layers.push(DistanceLayer {
            kind: l.kind,
            amplitude: l.amplitude as f32,
            soft_mm: l.soft_mm as f32,
            step_mm: field.step_mm as f32,
            origin_x: Mm(field.origin.0 as f32),
            origin_y: Mm(field.origin.1 as f32),
            pitch_mm: plan.pitch_mm as f32,
            tile_cols: field.tile_cols,
            tile_rows: field.tile_rows,
            sources: l.sources.clone(),
            tiles: field.tiles,
            planes: field.planes,
            samples: field.samples,
        });
    }
    built_index
}

fn fill_rule(e: &Element) -> crate::geometry::FillRule {
    match &e.shape {
        Shape::Path(p) => p.fill_rule,
        _ => crate::geometry::FillRule::NonZero,
    }
}

/// Dots to place for one element: what they are and how big.
struct DotJob<'a> {
    e: &'a Element,
    /// The element's document order.
    order: usize,
    kind: DotKind,
    radius: f64,
    amplitude: f64,
    fk: FeatureKind,
}

fn dot_feature(b: &mut Built, job: DotJob<'_>, pts: &[(f64, f64)], page: Page, diags: &mut Vec<Diagnostic>) {
    let DotJob { e, order, kind, radius, amplitude, fk } = job;
    let placed = pts.len();
    let pts: Vec<(f64, f64)> = pts
        .iter()
        .copied()
        .filter(|&(x, y)| x >= -radius && y >= -radius && x <= page.width_mm + radius && y <= page.height_mm + radius)
        .collect();
    if pts.is_empty() {
        let d = if placed == 0 {
            Diagnostic::warning("T0301", "no dots could be placed for this element")
                .with_help("it is too small or too short for one dot; enlarge it or draw it as a point symbol")
        } else {
            Diagnostic::warning("T0301", "no dots are left on the page for this element")
                .with_help("its dots lie beyond the page (the root <svg>'s viewBox, or --region): move it onto the page, or enlarge the viewBox")
        };
        diags.push(d.with_element(&e.name).at_line(e.line));
        return;
    }
    let source = b.source(e);
    b.push_dots(kind, &pts, radius, amplitude, source);
    let (x0, y0, x1, y1) = pts.iter().fold((f64::MAX, f64::MAX, f64::MIN, f64::MIN), |a, p| {
        (a.0.min(p.0), a.1.min(p.1), a.2.max(p.0), a.3.max(p.1))
    });
    b.footprints.extend(match kind {
        DotKind::Braille => FootPending::rect(order, source, (x0 - radius, y0 - radius, x1 + radius, y1 + radius)),
        _ => FootPending::discs(order, source, &pts, radius),
    });
    b.features.push(Feature {
        elem: source as usize,
        name: e.name.clone(),
        line: e.line,
        kind: fk,
        outline: Vec::new(),
        half_band: 0.0,
        dots: pts.iter().map(|&(x, y)| (x, y, radius)).collect(),
        bbox: (x0 - radius, y0 - radius, x1 + radius, y1 + radius),
        mask: None,
        amplitude,
    });
}
