//! The exact geometry behind a compiled drawing's mask layers.
//!
//! Each mask names its source element (provenance: id and line). The same
//! drawing is read again with usvg (never by hand), the element's paths are
//! flattened in f64 page millimetres with `taxel_compiler::geometry`, and the
//! layer's parameters come from the bundle itself (kind, frequency,
//! wavelength, angle, amplitude) except the vibrating band's width, which the
//! bundle does not store: it is read from the element's annotation (own
//! `data-tactile` or `tactile:` label, then the style sheet, then its
//! ancestors), the order in which the compiler resolves styles.

use std::collections::HashMap;
use std::sync::{Arc, OnceLock};

use taxel_compiler::StyleSheet;
use taxel_compiler::annotation::{self, Style};
use taxel_compiler::geometry::{FillRule, Polyline, flatten};
use taxel_compiler::stylesheet::ElementFacts;
use taxel_format::{Bundle, Chunk, DeviceProfile, MaskKind};

use super::exact::{ExactLayer, Index, Region};

/// Flattening tolerance of the reference, in mm: far below any mask pixel on the ladder.
const TOLERANCE_MM: f64 = 0.0005;
/// Band width when no annotation gives one (the documented `vibrate()` default, seed 000 §4.1).
const DEFAULT_BAND_MM: f64 = 1.5;
const INKSCAPE_NS: &str = "http://www.inkscape.org/namespaces/inkscape";

/// What the reference could not cover, said to the reader of the report.
#[derive(Debug, Default)]
pub struct Gaps {
    /// Layers whose source element was not found (they are left out of the reference).
    pub missing: Vec<String>,
}

fn fonts() -> Arc<usvg::fontdb::Database> {
    static DB: OnceLock<Arc<usvg::fontdb::Database>> = OnceLock::new();
    DB.get_or_init(|| {
        let mut db = usvg::fontdb::Database::new();
        db.load_system_fonts();
        Arc::new(db)
    })
    .clone()
}

/// A drawing read again for the reference: the XML (for annotations and
/// lines), usvg's tree (for geometry) and the page scale.
pub struct Drawing<'a> {
    doc: roxmltree::Document<'a>,
    keys: HashMap<roxmltree::NodeId, String>,
    tree: usvg::Tree,
    scale: f64,
}

impl<'a> Drawing<'a> {
    /// Reads `svg` as the compiler does for `profile` (and `--width-mm`).
    pub fn read(svg: &'a str, profile: &DeviceProfile, width_mm: Option<f32>) -> Result<Drawing<'a>, String> {
        let opts = roxmltree::ParsingOptions { allow_dtd: true, nodes_limit: 2_000_000, ..Default::default() };
        let doc = roxmltree::Document::parse_with_options(svg, opts)
            .map_err(|e| format!("the SVG could not be read: {e}"))?;
        // Give every element a unique id usvg will keep, so that a usvg node leads back to its element.
        let mut keys: HashMap<roxmltree::NodeId, String> = HashMap::new();
        let mut inserts: Vec<(usize, String)> = Vec::new();
        for (n, node) in doc.descendants().filter(|n| n.is_element()).enumerate() {
            match node.attribute("id") {
                Some(id) if !id.is_empty() => {
                    keys.insert(node.id(), id.to_string());
                }
                _ => {
                    let key = format!("taxel-report-{n}");
                    let start = node.range().start;
                    let name_len =
                        svg[start + 1..].find(|c: char| c.is_whitespace() || c == '/' || c == '>').unwrap_or(0);
                    inserts.push((start + 1 + name_len, format!(" id=\"{key}\"")));
                    keys.insert(node.id(), key);
                }
            }
        }
        let mut rewritten = svg.to_string();
        for (at, text) in inserts.iter().rev() {
            rewritten.insert_str(*at, text);
        }
        let uopt = usvg::Options { fontdb: fonts(), ..usvg::Options::default() };
        let tree = usvg::Tree::from_str(&rewritten, &uopt).map_err(|e| format!("the SVG could not be read: {e}"))?;
        let scale = page_scale(doc.root_element(), &tree, width_mm, profile);
        Ok(Drawing { doc, keys, tree, scale })
    }

    /// The element a provenance entry names: by id, or by line when it has none.
    pub fn element(&self, id: &str, line: u32) -> Option<roxmltree::Node<'_, 'a>> {
        self.doc.descendants().filter(|n| n.is_element()).find(|n| {
            if id.is_empty() {
                self.doc.text_pos_at(n.range().start).row == line
            } else {
                n.attribute("id") == Some(id)
            }
        })
    }

    /// The element's paths in page mm, its fill rule and plain colours.
    pub fn geometry(&self, elem: roxmltree::Node<'_, '_>, tolerance: f64) -> Option<Geometry> {
        let node = self.keys.get(&elem.id()).and_then(|k| self.tree.node_by_id(k))?;
        Some(node_geometry(node, self.scale, tolerance))
    }
}

/// What [`Drawing::geometry`] finds.
pub struct Geometry {
    /// Flattened subpaths in page mm.
    pub polys: Vec<Polyline>,
    /// The first path's fill rule.
    pub rule: FillRule,
    /// Its plain fill colour.
    pub fill: Option<[u8; 3]>,
    /// Its plain stroke colour.
    pub stroke: Option<[u8; 3]>,
}

/// The exact layers of a compiled drawing: one per mask chunk, plus the dot tables.
pub fn exact_layers(
    svg: &str,
    bundle: &Bundle,
    sheet: Option<&StyleSheet>,
    width_mm: Option<f32>,
) -> Result<(Vec<ExactLayer>, Gaps), String> {
    let drawing = Drawing::read(svg, &bundle.manifest.profile, width_mm)?;
    let prov = bundle.provenance();
    let mut layers = Vec::new();
    let mut gaps = Gaps::default();
    // Every vibrating band, to cut out of the gratings (as the compiler does).
    let mut bands: Vec<(Arc<Index>, f64)> = Vec::new();
    let mut pending: Vec<(usize, Geometry, MaskKind, f64, f64)> = Vec::new();
    // Each element of a vibration or grating layer (a raster mask's one
    // source, every source of a distance layer), as (source, kind, amplitude).
    let mut elements: Vec<(Option<u32>, MaskKind, f32)> = Vec::new();
    for chunk in &bundle.chunks {
        match chunk {
            Chunk::Mask(m) => elements.push((m.source, m.kind, m.amplitude)),
            Chunk::Distance(d) => elements.extend(d.sources.iter().map(|&s| (Some(s), d.kind, d.amplitude))),
            Chunk::Dots(d) => layers.push(ExactLayer::Dots(
                d.dots.iter().map(|d| (d.x.0 as f64, d.y.0 as f64, d.radius.0 as f64, d.amplitude as f64)).collect(),
            )),
            _ => {}
        }
    }
    for (source, kind, amplitude) in elements {
        {
            {
                let m = Elem { kind, amplitude };
                let entry = source.and_then(|s| prov.and_then(|p| p.entries.get(s as usize)));
                let found = entry.and_then(|e| drawing.element(&e.id, e.line));
                let Some((elem, geo)) = found.and_then(|el| drawing.geometry(el, TOLERANCE_MM).map(|g| (el, g))) else {
                    gaps.missing.push(entry.map_or("(no provenance)".into(), |e| format!("{} line {}", e.id, e.line)));
                    continue;
                };
                let width = match m.kind {
                    MaskKind::Vibration { .. } => {
                        let styles = resolved_styles(elem, sheet, geo.fill, geo.stroke);
                        let w = styles
                            .iter()
                            .find_map(|s| match s {
                                Style::Vibrate(v) => Some(v.width_mm),
                                _ => None,
                            })
                            .unwrap_or(DEFAULT_BAND_MM);
                        bands.push((Arc::new(Index::new(&geo.polys, false)), w));
                        w
                    }
                    MaskKind::Grating { .. } => 0.0,
                };
                let band = if matches!(m.kind, MaskKind::Vibration { .. }) { bands.len() - 1 } else { usize::MAX };
                pending.push((band, geo, m.kind, m.amplitude as f64, width));
            }
        }
    }
    for (band, geo, kind, amplitude, width) in pending {
        layers.push(match kind {
            MaskKind::Vibration { freq } => ExactLayer::Vibration {
                region: Region::Band { polys: bands[band].0.clone(), width },
                freq_hz: freq.0 as f64 / 1000.0,
                amplitude,
            },
            MaskKind::Grating { wavelength, angle_deg } => ExactLayer::Grating {
                region: Region::Fill {
                    polys: Index::new(&geo.polys, true),
                    rule: geo.rule,
                    minus_bands: bands.clone(),
                },
                wavelength_mm: wavelength.0 as f64,
                angle_deg: angle_deg as f64,
                amplitude,
            },
        });
    }
    Ok((layers, gaps))
}

/// One element's layer parameters.
struct Elem {
    kind: MaskKind,
    amplitude: f32,
}

/// Millimetres per usvg pixel, decided as the compiler decides the page size:
/// `--width-mm`, else the root's absolute width or height, else fitted to the surface.
fn page_scale(root: roxmltree::Node<'_, '_>, tree: &usvg::Tree, width_mm: Option<f32>, p: &DeviceProfile) -> f64 {
    let (w, h) = (tree.size().width() as f64, tree.size().height() as f64);
    let abs = |s: &str| -> Option<f64> {
        let l: svgtypes::Length = s.parse().ok()?;
        use svgtypes::LengthUnit as U;
        let f = match l.unit {
            U::None | U::Px => 25.4 / 96.0,
            U::Mm => 1.0,
            U::Cm => 10.0,
            U::In => 25.4,
            U::Pt => 25.4 / 72.0,
            U::Pc => 25.4 / 6.0,
            _ => return None,
        };
        (l.number > 0.0).then_some(l.number * f)
    };
    let own = root
        .attribute("width")
        .and_then(abs)
        .map(|mm| mm / w)
        .or(root.attribute("height").and_then(abs).map(|mm| mm / h));
    match (width_mm.map(f64::from).filter(|v| v.is_finite() && *v > 0.0), own) {
        (Some(mm), _) => mm / w,
        (None, Some(s)) => s,
        (None, None) => (p.surface_w_mm as f64 / w).min(p.surface_h_mm as f64 / h),
    }
}

/// Every path under `node`, flattened in page mm, with the fill rule and the
/// plain fill and stroke colours of the first path (for style-sheet colour rules).
fn node_geometry(node: &usvg::Node, scale: f64, tolerance: f64) -> Geometry {
    let mut polys = Vec::new();
    let (mut rule, mut fill, mut stroke, mut first) = (FillRule::NonZero, None, None, true);
    let page = usvg::Transform::from_scale(scale as f32, scale as f32);
    let mut visit = |p: &usvg::Path| {
        let ts = page.pre_concat(p.abs_transform());
        polys.extend(flatten(p.data(), ts, tolerance));
        if first {
            first = false;
            let colour = |paint: &usvg::Paint| match paint {
                usvg::Paint::Color(c) => Some([c.red, c.green, c.blue]),
                _ => None,
            };
            fill = p.fill().and_then(|f| colour(f.paint()));
            stroke = p.stroke().and_then(|s| colour(s.paint()));
            if let Some(f) = p.fill() {
                rule = if f.rule() == usvg::FillRule::EvenOdd { FillRule::EvenOdd } else { FillRule::NonZero };
            }
        }
    };
    walk(node, &mut visit);
    Geometry { polys, rule, fill, stroke }
}

fn walk(node: &usvg::Node, f: &mut impl FnMut(&usvg::Path)) {
    match node {
        usvg::Node::Path(p) => f(p),
        usvg::Node::Group(g) => g.children().iter().for_each(|c| walk(c, f)),
        usvg::Node::Text(t) => t.flattened().children().iter().for_each(|c| walk(c, f)),
        usvg::Node::Image(_) => {}
    }
}

/// The styles of `elem`, resolved like the compiler resolves them: its own
/// annotation, else the style sheet's rule, else its parent's.
pub fn resolved_styles(
    elem: roxmltree::Node<'_, '_>,
    sheet: Option<&StyleSheet>,
    fill: Option<[u8; 3]>,
    stroke: Option<[u8; 3]>,
) -> Vec<Style> {
    let layers: Vec<String> = elem
        .ancestors()
        .filter(|n| n.attribute((INKSCAPE_NS, "groupmode")) == Some("layer"))
        .filter_map(|n| n.attribute((INKSCAPE_NS, "label")))
        .map(str::to_string)
        .collect();
    for (depth, n) in elem.ancestors().filter(|n| n.is_element()).enumerate() {
        let own = n
            .attribute("data-tactile")
            .or_else(|| n.attribute((INKSCAPE_NS, "label")).and_then(|l| l.trim().strip_prefix("tactile:")));
        if let Some(d) = own.and_then(|t| annotation::parse(t).ok()) {
            return d.styles().to_vec();
        }
        if let Some(sheet) = sheet {
            let facts = ElementFacts {
                id: n.attribute("id").unwrap_or(""),
                classes: n.attribute("class").unwrap_or(""),
                layers: &layers,
                fill: if depth == 0 { fill } else { None },
                stroke: if depth == 0 { stroke } else { None },
            };
            if let Some(rule) = sheet.lookup(&facts) {
                return rule.declaration.styles().to_vec();
            }
        }
    }
    Vec::new()
}
