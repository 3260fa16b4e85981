//! From the resolved drawing to layers: one mask per shape and mask style,
//! dot tables per kind, brush requests for grid devices, provenance, and the
//! features the design rules look at.

use std::collections::HashMap;

use resvg::tiny_skia::Path;
use taxel_format::{
    Chunk, Dot, DotKind, DotTable, Family, MaskKind, MaskLayer, MilliHertz, Mm, Provenance, ProvenanceEntry,
    StrokeTable,
};

use super::braille;
use super::dots;
use super::masks::{self, Area, Coverage};
use crate::annotation::{Braille as BrailleStyle, Style};
use crate::brush::{self, BrushRequest};
use crate::diagnostic::Diagnostic;
use crate::drawing::{Drawing, Element, Page, Shape, TextShape};
use crate::geometry::{FillRule, Polyline};
use crate::options::CompileOptions;

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
    /// Index of its mask in [`Built::masks`].
    pub mask: Option<usize>,
    pub amplitude: f64,
}

/// Everything the layers stage made.
#[derive(Default)]
pub(crate) struct Built {
    pub masks: Vec<MaskLayer>,
    pub outline_dots: Vec<Dot>,
    pub symbol_dots: Vec<Dot>,
    pub braille_dots: Vec<Dot>,
    pub strokes: Option<StrokeTable>,
    pub provenance: Vec<ProvenanceEntry>,
    pub features: Vec<Feature>,
    /// Elements that asked for any tactile style.
    pub styled_elements: usize,
    prov_index: HashMap<(String, u32), u32>,
}

impl Built {
    /// Whether no layer was made.
    pub fn is_empty(&self) -> bool {
        self.masks.is_empty()
            && self.outline_dots.is_empty()
            && self.symbol_dots.is_empty()
            && self.braille_dots.is_empty()
            && self.strokes.as_ref().is_none_or(|s| s.strokes.is_empty())
    }

    /// The chunks, in a fixed order: masks in document order, dot tables
    /// (outline, symbol, braille), strokes, provenance.
    pub fn into_chunks(self) -> Vec<Chunk> {
        let mut out: Vec<Chunk> = self.masks.into_iter().map(Chunk::Mask).collect();
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

fn not_here(style: &Style, e: &str, line: u32, profile: &str) -> Diagnostic {
    let help = match style {
        Style::Brush(_) => "brush() strokes play on vibrotactile grids such as brush-4x3",
        _ => "vibrate, grating, dots, dot and braille play on laterotactile arrays such as stress2",
    };
    Diagnostic::warning("T0120", format!("`{}` is not rendered on {profile}; it is left out", style.name()))
        .with_element(e)
        .with_help(help)
        .at_line(line)
}

/// A vibrating band: its outline, width (mm) and bounds (x0, y0, x1, y1).
type Band<'a> = (&'a Path, f64, (f32, f32, f32, f32));

/// An element's outline as a tiny-skia path (rebuilt from its exact
/// polylines), and its clip regions as paths; `None` for the whole when a
/// clip region is empty (nothing of the element is left).
struct Raster {
    path: Option<Path>,
    fill_rule: FillRule,
    clips: Option<Vec<(Path, FillRule)>>,
}

impl Raster {
    fn of(e: &Element) -> Raster {
        let (outline, fill_rule, clips): (&[Polyline], _, &[_]) = match &e.shape {
            Shape::Path(p) => (&p.outline, p.fill_rule, &p.clips),
            Shape::Text(t) => (&t.outline, FillRule::NonZero, &[]),
            Shape::Image { .. } => (&[], FillRule::NonZero, &[]),
        };
        let clips = clips.iter().map(|c| masks::to_path(&c.outline).map(|p| (p, c.fill_rule))).collect();
        Raster { path: masks::to_path(outline), fill_rule, clips }
    }
}

/// The outline a style is rendered from (glyph outlines for text).
fn outline(e: &Element) -> &[Polyline] {
    match &e.shape {
        Shape::Path(p) => &p.outline,
        Shape::Text(t) => &t.outline,
        Shape::Image { .. } => &[],
    }
}

/// Builds every layer of `drawing` at `px` samples per mm.
pub(crate) fn build(drawing: &Drawing, opts: &CompileOptions, px: f32, diags: &mut Vec<Diagnostic>) -> Built {
    let family = opts.profile.family();
    let profile = opts.profile.name.as_str();
    let page = drawing.page;
    let mut b = Built::default();
    let mut requests: Vec<BrushRequest> = Vec::new();
    let rasters: Vec<Raster> = drawing.elements.iter().map(Raster::of).collect();
    // Every vibrating band on the page, to cut out of the gratings it crosses.
    let bands: Vec<Band<'_>> = if family == Family::Laterotactile {
        drawing
            .elements
            .iter()
            .zip(&rasters)
            .filter(|(e, _)| e.visible)
            .flat_map(|(e, r)| {
                e.styles.iter().filter_map(move |s| match s {
                    Style::Vibrate(v) => r.path.as_ref().map(|p| (p, v.width_mm)),
                    _ => None,
                })
            })
            .filter_map(|(p, w)| {
                let b = p.compute_tight_bounds()?;
                let g = (w / 2.0) as f32;
                Some((p, w, (b.left() - g, b.top() - g, b.right() + g, b.bottom() + g)))
            })
            .collect()
    } else {
        Vec::new()
    };
    for (e, r) in drawing.elements.iter().zip(&rasters) {
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
        let (Some(path), Some(clips)) = (&r.path, &r.clips) else {
            let what = if r.path.is_none() { "this shape is empty" } else { "this shape is clipped away" };
            diags.push(
                Diagnostic::warning("T0301", format!("{what}; nothing is rendered for it"))
                    .with_element(&e.name)
                    .at_line(e.line),
            );
            continue;
        };
        let clips: Vec<Area<'_>> = clips.iter().map(|(p, rule)| (p, *rule)).collect();
        let area = (path, r.fill_rule);
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
                    let Some(freq) = MilliHertz::from_hz(v.freq_hz) else { continue };
                    let kind = MaskKind::Vibration { freq };
                    let fk = FeatureKind::Vibrate { width_mm: v.width_mm, freq_hz: v.freq_hz };
                    let m = MaskJob { e, area, clips: &clips, kind, amplitude: v.amplitude, fk };
                    mask(&mut b, m, Coverage::Band(v.width_mm), page, px, diags);
                }
                Style::Grating(g) => {
                    let kind =
                        MaskKind::Grating { wavelength: Mm(g.wavelength_mm as f32), angle_deg: g.angle_deg as f32 };
                    let fk = FeatureKind::Grating { wavelength_mm: g.wavelength_mm, angle_deg: g.angle_deg };
                    let mine = path.compute_tight_bounds();
                    let minus_bands = bands
                        .iter()
                        .filter(|(_, _, b)| {
                            mine.is_some_and(|m| {
                                b.0 <= m.right() && m.left() <= b.2 && b.1 <= m.bottom() && m.top() <= b.3
                            })
                        })
                        .map(|&(p, w, _)| (p, w))
                        .collect();
                    let m = MaskJob { e, area, clips: &clips, kind, amplitude: g.amplitude, fk };
                    mask(&mut b, m, Coverage::Fill { minus_bands }, page, px, diags);
                }
                Style::Dots(d) => {
                    let pts = dots::along(polylines, d.radius_mm, d.spacing_mm, &e.name, diags);
                    let spacing = d.spacing_mm.unwrap_or(3.0 * d.radius_mm).max(2.0 * d.radius_mm);
                    let fk = FeatureKind::Dots { radius_mm: d.radius_mm, spacing_mm: spacing };
                    let job = DotJob { e, kind: DotKind::Outline, radius: d.radius_mm, amplitude: d.amplitude, fk };
                    dot_feature(&mut b, job, &pts, page, diags);
                }
                Style::Dot(d) => {
                    let pts = dots::symbol(polylines, markers);
                    let fk = FeatureKind::Dot { radius_mm: d.radius_mm };
                    let job = DotJob { e, kind: DotKind::Symbol, radius: d.radius_mm, amplitude: d.amplitude, fk };
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
    braille_texts(&mut b, drawing, opts, diags);
    if !requests.is_empty() {
        b.strokes = brush::compile_strokes(&requests, &opts.profile, diags);
    }
    b
}

/// One mask to render: the element, its area and clips, and what the mask is.
struct MaskJob<'a> {
    e: &'a Element,
    area: Area<'a>,
    clips: &'a [Area<'a>],
    kind: MaskKind,
    amplitude: f64,
    fk: FeatureKind,
}

fn mask(b: &mut Built, m: MaskJob<'_>, coverage: Coverage, page: Page, px: f32, diags: &mut Vec<Diagnostic>) {
    let e = m.e;
    let source = b.source(e);
    match masks::render(m.area, m.clips, &coverage, m.kind, m.amplitude as f32, Some(source), page, px, &e.name, diags)
    {
        Some(layer) => {
            let half_band = match &coverage {
                Coverage::Band(w) => w / 2.0,
                Coverage::Fill { .. } => 0.0,
            };
            let bbox = (
                layer.origin_x.0 as f64,
                layer.origin_y.0 as f64,
                layer.origin_x.0 as f64 + layer.width as f64 / layer.px_per_mm as f64,
                layer.origin_y.0 as f64 + layer.height as f64 / layer.px_per_mm as f64,
            );
            b.features.push(Feature {
                elem: source as usize,
                name: e.name.clone(),
                line: e.line,
                kind: m.fk,
                outline: outline(e).to_vec(),
                half_band,
                dots: Vec::new(),
                bbox,
                mask: Some(b.masks.len()),
                amplitude: m.amplitude,
            });
            b.masks.push(layer);
        }
        None => diags.push(
            Diagnostic::warning(
                "T0301",
                "nothing of this shape is left on the page (empty, invisible or outside the page)",
            )
            .with_element(&e.name)
            .at_line(e.line),
        ),
    }
}

/// Dots to place for one element: what they are and how big.
struct DotJob<'a> {
    e: &'a Element,
    kind: DotKind,
    radius: f64,
    amplitude: f64,
    fk: FeatureKind,
}

fn dot_feature(b: &mut Built, job: DotJob<'_>, pts: &[(f64, f64)], page: Page, diags: &mut Vec<Diagnostic>) {
    let DotJob { e, kind, radius, amplitude, fk } = job;
    let pts: Vec<(f64, f64)> = pts
        .iter()
        .copied()
        .filter(|&(x, y)| x >= -radius && y >= -radius && x <= page.width_mm + radius && y <= page.height_mm + radius)
        .collect();
    if pts.is_empty() {
        diags.push(
            Diagnostic::warning("T0301", "no dots are left on the page for this element")
                .with_element(&e.name)
                .at_line(e.line),
        );
        return;
    }
    let source = b.source(e);
    b.push_dots(kind, &pts, radius, amplitude, source);
    let (x0, y0, x1, y1) = pts.iter().fold((f64::MAX, f64::MAX, f64::MIN, f64::MIN), |a, p| {
        (a.0.min(p.0), a.1.min(p.1), a.2.max(p.0), a.3.max(p.1))
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

/// Braille for every text with a braille style, in document order, after the other layers.
fn braille_texts(b: &mut Built, drawing: &Drawing, opts: &CompileOptions, diags: &mut Vec<Diagnostic>) {
    let family = opts.profile.family();
    for e in &drawing.elements {
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
        let (pts, missing) = braille_dots(text, &style);
        if !missing.is_empty() {
            let list: String = missing.iter().collect();
            diags.push(
                Diagnostic::warning(
                    "T0304",
                    format!("no uncontracted UEB braille for {list:?}; these characters are left out"),
                )
                .with_element(&e.name)
                .with_help("taxel's built-in table covers a-z, A-Z, 0-9, space and common punctuation")
                .at_line(e.line),
            );
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
            kind: DotKind::Braille,
            radius: style.radius_mm,
            amplitude: style.amplitude,
            fk: FeatureKind::Braille,
        };
        dot_feature(b, job, &pts, drawing.page, diags);
    }
}

/// The braille dot centres of a text, and the characters braille has no
/// cell for (sorted, once each). Lines closer than braille's line pitch are
/// moved apart; a run without its own `y` stays on the line before.
fn braille_dots(text: &TextShape, style: &BrailleStyle) -> (Vec<(f64, f64)>, Vec<char>) {
    let r = style.radius_mm;
    let mut prev_baseline: Option<f64> = None;
    let mut cursor: Option<f64> = None;
    let mut pts = Vec::new();
    let mut missing: Vec<char> = Vec::new();
    for run in &text.runs {
        let (cells, miss) = braille::translate(&run.text);
        missing.extend(miss);
        let mut y = run.y_mm;
        if let Some(prev) = prev_baseline {
            if y > prev + 1e-6 && y < prev + braille::LINE_PITCH_MM {
                // A new line closer than braille's line pitch: keep lines apart.
                y = prev + braille::LINE_PITCH_MM;
            } else if y <= prev + 1e-6 && run.continues {
                y = prev;
            }
        }
        let width = braille::run_width(cells.len(), r);
        let x0 = match (run.continues, cursor) {
            (true, Some(c)) => c,
            _ => run.x_mm - run.anchor * width,
        };
        pts.extend(braille::layout(&cells, x0, y, r));
        cursor = Some(x0 + cells.len() as f64 * braille::CELL_PITCH_MM);
        prev_baseline = Some(y);
    }
    missing.sort_unstable();
    missing.dedup();
    (pts, missing)
}
