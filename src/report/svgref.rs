//! The exact geometry behind a compiled drawing's mask layers.
//!
//! Each mask names its source element (provenance: id and line). The drawing
//! is resolved again by the compiler's own drawing stage
//! (`taxel_compiler::drawing::resolve`, with the same profile, style sheet and
//! `--width-mm`), so the reference's geometry and each layer's style are the
//! very ones the layers were built from: exact f64 polylines in page
//! millimetres, and the element's resolved styles (for the vibrating band's
//! width, which the bundle does not store). The layer's other parameters come
//! from the bundle itself (kind, frequency, wavelength, angle, amplitude).
//! Nothing here reads SVG or annotations.

use std::sync::Arc;

use taxel_compiler::CompileOptions;
use taxel_compiler::annotation::Style;
use taxel_compiler::drawing::{self, Shape};
use taxel_compiler::geometry::{FillRule, Polyline};
use taxel_format::{Bundle, Chunk, DeviceProfile, MaskKind};

use super::exact::{ExactLayer, Index, Region};

/// Band width when no style gives one (the documented `vibrate()` default, seed 000 §4.1).
const DEFAULT_BAND_MM: f64 = 1.5;

/// What the reference could not cover, said to the reader of the report.
#[derive(Debug, Default)]
pub struct Gaps {
    /// Layers whose source element was not found (they are left out of the reference).
    pub missing: Vec<String>,
}

/// A drawing resolved again for the reference.
pub struct Drawing {
    drawing: drawing::Drawing,
}

/// One source element of the drawing: its geometry and resolved styles.
pub struct Source {
    /// Flattened subpaths in page mm (of every copy, for a `<use>`).
    pub polys: Vec<Polyline>,
    /// The first shape's fill rule.
    pub rule: FillRule,
    /// The styles the compiler resolved for it.
    pub styles: Vec<Style>,
}

impl Drawing {
    /// Resolves `svg` as the compiler does with `opts` (its profile, style
    /// sheet, `--width-mm` and fonts), for the profile `profile` the bundle was built for.
    pub fn read(svg: &str, profile: &DeviceProfile, opts: &CompileOptions) -> Result<Drawing, String> {
        let opts = CompileOptions { profile: *profile, ..opts.clone() };
        let r = drawing::resolve(svg, &opts);
        match r.drawing {
            Some(drawing) => Ok(Drawing { drawing }),
            None => Err(r.diagnostics.first().map_or("the SVG could not be read".into(), |d| d.message.clone())),
        }
    }

    /// The element a provenance entry names (its id, or its line when it has
    /// none): every drawn copy of it together.
    pub fn source(&self, id: &str, line: u32) -> Option<Source> {
        let mut found = self.drawing.elements.iter().filter(|e| e.id == id && e.line == line).peekable();
        let first = found.peek()?;
        let styles = first.styles.clone();
        let mut polys = Vec::new();
        let mut rule = None;
        for e in found {
            match &e.shape {
                Shape::Path(p) => {
                    rule.get_or_insert(p.fill_rule);
                    polys.extend(p.outline.iter().cloned());
                }
                Shape::Text(t) => polys.extend(t.outline.iter().cloned()),
                Shape::Image { .. } => {}
            }
        }
        Some(Source { polys, rule: rule.unwrap_or_default(), styles })
    }
}

/// The exact layers of a compiled drawing: one per element of each mask or
/// distance layer, plus the dot tables.
pub fn exact_layers(svg: &str, bundle: &Bundle, opts: &CompileOptions) -> Result<(Vec<ExactLayer>, Gaps), String> {
    let drawing = Drawing::read(svg, &bundle.manifest.profile, opts)?;
    let prov = bundle.provenance();
    let mut layers = Vec::new();
    let mut gaps = Gaps::default();
    // Every vibrating band, to cut out of the gratings (as the compiler does).
    let mut bands: Vec<(Arc<Index>, f64)> = Vec::new();
    let mut pending: Vec<(usize, Source, MaskKind, f64, f64)> = Vec::new();
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
        let entry = source.and_then(|s| prov.and_then(|p| p.entries.get(s as usize)));
        let Some(geo) = entry.and_then(|e| drawing.source(&e.id, e.line)) else {
            gaps.missing.push(entry.map_or("(no provenance)".into(), |e| format!("{} line {}", e.id, e.line)));
            continue;
        };
        let width = match kind {
            MaskKind::Vibration { .. } => {
                let w = geo
                    .styles
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
        let band = if matches!(kind, MaskKind::Vibration { .. }) { bands.len() - 1 } else { usize::MAX };
        pending.push((band, geo, kind, amplitude as f64, width));
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
