//! From tactile shapes to layers: one mask per shape and mask style, dot
//! tables per kind, brush requests for grid devices, provenance, and the
//! features the design rules look at.

use std::collections::{HashMap, HashSet};

use resvg::tiny_skia::Transform;
use roxmltree::Document;
use taxel_format::{
    Chunk, Dot, DotKind, DotTable, Family, MaskKind, MaskLayer, MilliHertz, Mm, Provenance, ProvenanceEntry,
    StrokeTable,
};

use super::braille;
use super::dots;
use super::masks::{self, Coverage};
use super::scene::{Item, Scene};
use super::size::Page;
use super::source::{Kind, Source};
use crate::annotation::{Declaration, Style};
use crate::brush::{self, BrushRequest};
use crate::diagnostic::Diagnostic;
use crate::geometry::Polyline;
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
    prov_index: HashMap<usize, u32>,
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

    fn source(&mut self, src: &Source, elem: usize) -> u32 {
        if let Some(&i) = self.prov_index.get(&elem) {
            return i;
        }
        let e = &src.elements[elem];
        let i = self.provenance.len() as u32;
        self.provenance.push(ProvenanceEntry { id: e.id.clone(), label: e.label.clone(), line: e.line });
        self.prov_index.insert(elem, i);
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
    let d = Diagnostic::warning("T0120", format!("`{}` is not rendered on {profile}; it is left out", style.name()))
        .with_element(e)
        .with_help(help);
    with_line(d, line)
}

/// Places a diagnostic at a source line (no column: it is about the whole element).
fn with_line(d: Diagnostic, line: u32) -> Diagnostic {
    Diagnostic { line: Some(line), column: None, ..d }
}

/// A vibrating band: its outline, width (mm) and bounds (x0, y0, x1, y1).
type Band<'a> = (&'a resvg::tiny_skia::Path, f64, (f32, f32, f32, f32));

/// Builds every layer.
#[allow(clippy::too_many_arguments)]
pub(crate) fn build(
    scene: &Scene<'_>,
    src: &Source,
    doc: &Document<'_>,
    opts: &CompileOptions,
    page: Page,
    px: f32,
    root_ts: Transform,
    diags: &mut Vec<Diagnostic>,
) -> Built {
    let family = opts.profile.family();
    let profile = opts.profile.name.as_str();
    let mut b = Built::default();
    let mut styled: HashSet<usize> = HashSet::new();
    let mut requests: Vec<BrushRequest> = Vec::new();
    // Every vibrating band on the page, to cut out of the gratings it crosses.
    let bands: Vec<Band<'_>> = if family == Family::Laterotactile {
        scene
            .items
            .iter()
            .filter(|it| it.visible)
            .flat_map(|it| {
                it.styles.iter().filter_map(move |s| match s {
                    Style::Vibrate(v) => it.path.as_ref().map(|p| (p, v.width_mm)),
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
    for item in &scene.items {
        let e = &src.elements[item.elem];
        styled.insert(item.elem);
        if !item.visible {
            diags.push(with_line(
                Diagnostic::warning("T0301", "this shape is hidden (visibility: hidden); nothing is rendered for it")
                    .with_element(&e.name),
                e.line,
            ));
            continue;
        }
        if item.polylines.is_empty() || item.path.is_none() {
            diags.push(with_line(
                Diagnostic::warning("T0301", "this shape is empty; nothing is rendered for it").with_element(&e.name),
                e.line,
            ));
            continue;
        }
        for style in &item.styles {
            if !renders_on(style, family) {
                diags.push(not_here(style, &e.name, e.line, profile));
                continue;
            }
            match *style {
                Style::Vibrate(v) => {
                    let Some(freq) = MilliHertz::from_hz(v.freq_hz) else { continue };
                    let kind = MaskKind::Vibration { freq };
                    let fk = FeatureKind::Vibrate { width_mm: v.width_mm, freq_hz: v.freq_hz };
                    mask(&mut b, src, item, Coverage::Band(v.width_mm), kind, v.amplitude, fk, page, px, diags);
                }
                Style::Grating(g) => {
                    let kind =
                        MaskKind::Grating { wavelength: Mm(g.wavelength_mm as f32), angle_deg: g.angle_deg as f32 };
                    let fk = FeatureKind::Grating { wavelength_mm: g.wavelength_mm, angle_deg: g.angle_deg };
                    let mine = item.path.as_ref().and_then(|p| p.compute_tight_bounds());
                    let minus_bands = bands
                        .iter()
                        .filter(|(_, _, b)| {
                            mine.is_some_and(|m| {
                                b.0 <= m.right() && m.left() <= b.2 && b.1 <= m.bottom() && m.top() <= b.3
                            })
                        })
                        .map(|&(p, w, _)| (p, w))
                        .collect();
                    let cov = Coverage::Fill { minus_bands };
                    mask(&mut b, src, item, cov, kind, g.amplitude, fk, page, px, diags);
                }
                Style::Dots(d) => {
                    let pts = dots::along(&item.polylines, d.radius_mm, d.spacing_mm, &e.name, diags);
                    let spacing = d.spacing_mm.unwrap_or(3.0 * d.radius_mm).max(2.0 * d.radius_mm);
                    let fk = FeatureKind::Dots { radius_mm: d.radius_mm, spacing_mm: spacing };
                    dot_feature(
                        &mut b,
                        src,
                        item.elem,
                        DotKind::Outline,
                        &pts,
                        d.radius_mm,
                        d.amplitude,
                        fk,
                        page,
                        diags,
                    );
                }
                Style::Dot(d) => {
                    let pts = dots::symbol(&item.polylines, &item.markers);
                    let fk = FeatureKind::Dot { radius_mm: d.radius_mm };
                    dot_feature(
                        &mut b,
                        src,
                        item.elem,
                        DotKind::Symbol,
                        &pts,
                        d.radius_mm,
                        d.amplitude,
                        fk,
                        page,
                        diags,
                    );
                }
                Style::Braille(_) => diags.push(with_line(
                    Diagnostic::warning(
                        "T0121",
                        "braille() applies to <text> elements; this shape is left out of the braille",
                    )
                    .with_element(&e.name),
                    e.line,
                )),
                Style::Brush(br) => {
                    let source = b.source(src, item.elem);
                    for pl in &item.polylines {
                        let polyline = pl.walked();
                        requests.push(BrushRequest {
                            polyline,
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
    braille_texts(&mut b, scene, src, doc, opts, page, root_ts, &mut styled, diags);
    for &i in &scene.images {
        let e = &src.elements[i];
        styled.insert(i);
        diags.push(with_line(
            Diagnostic::warning("T0305", "images are not rendered tactilely; this one is left out")
                .with_element(&e.name)
                .with_help("trace the picture as paths (Inkscape: Path > Trace Bitmap) and annotate the paths"),
            e.line,
        ));
    }
    const SHAPES: &[&str] = &["path", "rect", "circle", "ellipse", "line", "polyline", "polygon"];
    for (i, e) in src.elements.iter().enumerate() {
        let annotated = matches!(&e.own, Some(Declaration::Styles(s)) if !s.is_empty());
        if annotated && !e.in_defs && SHAPES.contains(&e.tag.as_str()) && !scene.seen.contains(&i) {
            styled.insert(i);
            diags.push(with_line(
                Diagnostic::warning(
                    "T0301",
                    "this shape is not drawn (display: none, zero size or no geometry); nothing is rendered for it",
                )
                .with_element(&e.name),
                e.line,
            ));
        }
    }
    if !requests.is_empty() {
        b.strokes = brush::compile_strokes(&requests, &opts.profile, diags);
    }
    b.styled_elements = styled.len();
    b
}

#[allow(clippy::too_many_arguments)]
fn mask(
    b: &mut Built,
    src: &Source,
    item: &Item<'_>,
    coverage: Coverage,
    kind: MaskKind,
    amplitude: f64,
    fk: FeatureKind,
    page: Page,
    px: f32,
    diags: &mut Vec<Diagnostic>,
) {
    let e = &src.elements[item.elem];
    let source = b.source(src, item.elem);
    match masks::render(item, &coverage, kind, amplitude as f32, Some(source), page, px, &e.name, diags) {
        Some(m) => {
            let half_band = match &coverage {
                Coverage::Band(w) => w / 2.0,
                Coverage::Fill { .. } => 0.0,
            };
            let bbox = (
                m.origin_x.0 as f64,
                m.origin_y.0 as f64,
                m.origin_x.0 as f64 + m.width as f64 / m.px_per_mm as f64,
                m.origin_y.0 as f64 + m.height as f64 / m.px_per_mm as f64,
            );
            b.features.push(Feature {
                elem: item.elem,
                name: e.name.clone(),
                line: e.line,
                kind: fk,
                outline: item.polylines.clone(),
                half_band,
                dots: Vec::new(),
                bbox,
                mask: Some(b.masks.len()),
                amplitude,
            });
            b.masks.push(m);
        }
        None => diags.push(with_line(
            Diagnostic::warning(
                "T0301",
                "nothing of this shape is left on the page (empty, invisible or outside the page)",
            )
            .with_element(&e.name),
            e.line,
        )),
    }
}

#[allow(clippy::too_many_arguments)]
fn dot_feature(
    b: &mut Built,
    src: &Source,
    elem: usize,
    kind: DotKind,
    pts: &[(f64, f64)],
    radius: f64,
    amplitude: f64,
    fk: FeatureKind,
    page: Page,
    diags: &mut Vec<Diagnostic>,
) {
    let e = &src.elements[elem];
    let pts: Vec<(f64, f64)> = pts
        .iter()
        .copied()
        .filter(|&(x, y)| x >= -radius && y >= -radius && x <= page.width_mm + radius && y <= page.height_mm + radius)
        .collect();
    if pts.is_empty() {
        diags.push(with_line(
            Diagnostic::warning("T0301", "no dots are left on the page for this element").with_element(&e.name),
            e.line,
        ));
        return;
    }
    let source = b.source(src, elem);
    b.push_dots(kind, &pts, radius, amplitude, source);
    let (x0, y0, x1, y1) = pts.iter().fold((f64::MAX, f64::MAX, f64::MIN, f64::MIN), |a, p| {
        (a.0.min(p.0), a.1.min(p.1), a.2.max(p.0), a.3.max(p.1))
    });
    b.features.push(Feature {
        elem,
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

/// The declaration in force at an element from the XML alone (own, style
/// sheet by id/class/layer, then its ancestors'), for `<text>` elements.
fn xml_decl(src: &Source, elem: usize) -> Option<&Declaration> {
    let mut i = Some(elem);
    while let Some(k) = i {
        let e = &src.elements[k];
        if let Some(d) = e.own.as_ref().or(e.sheet.as_ref()) {
            return Some(d);
        }
        i = e.parent;
    }
    None
}

#[allow(clippy::too_many_arguments)]
fn braille_texts(
    b: &mut Built,
    scene: &Scene<'_>,
    src: &Source,
    doc: &Document<'_>,
    opts: &CompileOptions,
    page: Page,
    root_ts: Transform,
    styled: &mut HashSet<usize>,
    diags: &mut Vec<Diagnostic>,
) {
    let family = opts.profile.family();
    for (i, e) in src.elements.iter().enumerate() {
        if e.kind != Kind::Text || e.in_defs {
            continue;
        }
        let Some(style) = xml_decl(src, i).and_then(|d| {
            d.styles().iter().find_map(|s| match s {
                Style::Braille(br) => Some(*br),
                _ => None,
            })
        }) else {
            continue;
        };
        styled.insert(i);
        if family != Family::Laterotactile {
            diags.push(not_here(&Style::Braille(style), &e.name, e.line, opts.profile.name.as_str()));
            continue;
        }
        // The nearest group usvg kept gives the transform; if usvg dropped it, the text is not drawn.
        let mut parent_ts = root_ts;
        let mut p = e.parent;
        while let Some(k) = p {
            let a = &src.elements[k];
            if a.kind == Kind::Group && a.parent.is_some() {
                match scene.group_ts.get(&a.key) {
                    Some(ts) => parent_ts = *ts,
                    None => {
                        parent_ts = Transform::from_scale(f32::NAN, f32::NAN);
                    }
                }
                break;
            }
            p = a.parent;
        }
        let Some(node) = doc.get_node(e.node) else { continue };
        let own_ts = node
            .attribute("transform")
            .and_then(|t| t.parse::<svgtypes::Transform>().ok())
            .map_or(Transform::identity(), |t| {
                Transform::from_row(t.a as f32, t.b as f32, t.c as f32, t.d as f32, t.e as f32, t.f as f32)
            });
        let s = page.scale as f32;
        let ts = Transform::from_scale(s, s).pre_concat(parent_ts).pre_concat(own_ts);
        if !(ts.sx.is_finite() && ts.ty.is_finite()) || node.attribute("display") == Some("none") {
            diags.push(with_line(
                Diagnostic::warning("T0301", "this text is not drawn; no braille is made for it").with_element(&e.name),
                e.line,
            ));
            continue;
        }
        let r = style.radius_mm;
        let anchor = braille::anchor(node);
        let (mut ux, mut uy) = (0.0f64, 0.0f64);
        let mut prev_baseline: Option<f64> = None;
        let mut cursor: Option<f64> = None;
        let mut pts = Vec::new();
        let mut missing: Vec<char> = Vec::new();
        for run in braille::runs(node) {
            let (cells, miss) = braille::translate(&run.text);
            missing.extend(miss);
            let continues = run.x.is_none() && run.y.is_none() && cursor.is_some();
            ux = run.x.unwrap_or(ux);
            uy = run.y.unwrap_or(uy);
            let (fx, fy) = (ux as f32, uy as f32);
            let px_mm = (ts.sx * fx + ts.kx * fy + ts.tx) as f64;
            let mut py_mm = (ts.ky * fx + ts.sy * fy + ts.ty) as f64;
            if let Some(prev) = prev_baseline {
                if py_mm > prev + 1e-6 && py_mm < prev + braille::LINE_PITCH_MM {
                    // A new line closer than braille's line pitch: keep lines apart.
                    py_mm = prev + braille::LINE_PITCH_MM;
                } else if py_mm <= prev + 1e-6 && run.y.is_none() {
                    py_mm = prev;
                }
            }
            let width = braille::run_width(cells.len(), r);
            let x0 = match (continues, cursor) {
                (true, Some(c)) => c,
                _ => px_mm - anchor * width,
            };
            pts.extend(braille::layout(&cells, x0, py_mm, r));
            cursor = Some(x0 + cells.len() as f64 * braille::CELL_PITCH_MM);
            prev_baseline = Some(py_mm);
        }
        if !missing.is_empty() {
            missing.sort_unstable();
            missing.dedup();
            let list: String = missing.iter().collect();
            diags.push(with_line(
                Diagnostic::warning(
                    "T0304",
                    format!("no uncontracted UEB braille for {list:?}; these characters are left out"),
                )
                .with_element(&e.name)
                .with_help("taxel's built-in table covers a-z, A-Z, 0-9, space and common punctuation"),
                e.line,
            ));
        }
        if pts.is_empty() {
            diags.push(with_line(
                Diagnostic::warning("T0301", "this text has no characters to write in braille").with_element(&e.name),
                e.line,
            ));
            continue;
        }
        dot_feature(b, src, i, DotKind::Braille, &pts, r, style.amplitude, FeatureKind::Braille, page, diags);
    }
}
