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
use taxel_compiler::drawing::{self, Clip, Shape};
use taxel_compiler::geometry::{FillRule, Polyline};
use taxel_format::{Bundle, Chunk, DeviceProfile, MaskKind};

use super::exact::{ExactLayer, Index, Region, corners};

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
    /// The drawing's elements that are its drawn copies (indices).
    pub elements: Vec<usize>,
    /// Flattened subpaths in page mm (of every copy, for a `<use>`).
    pub polys: Vec<Polyline>,
    /// The first shape's fill rule.
    pub rule: FillRule,
    /// The styles the compiler resolved for it.
    pub styles: Vec<Style>,
    /// Its clip regions (a nested `<svg>`'s viewport, `clip-path`), when
    /// every drawn copy has the same ones; else none.
    pub clips: Vec<Clip>,
}

impl Drawing {
    /// Resolves `svg` as the compiler does with `opts` (its profile, style
    /// sheet, `--width-mm` and fonts), for the profile `profile` the bundle was built for.
    pub fn read(svg: &str, profile: &DeviceProfile, opts: &CompileOptions) -> Result<Drawing, String> {
        let opts = CompileOptions { profile: *profile, ..opts.clone() };
        let r = taxel_compiler::pipeline::resolve(svg, &opts);
        match r.drawing {
            Some(drawing) => Ok(Drawing { drawing }),
            None => Err(r.diagnostics.first().map_or("the SVG could not be read".into(), |d| d.message.clone())),
        }
    }

    /// The element a provenance entry names (its id, or its line when it has
    /// none): every drawn copy of it together.
    pub fn source(&self, id: &str, line: u32) -> Option<Source> {
        let mut found =
            self.drawing.elements.iter().enumerate().filter(|(_, e)| e.id == id && e.line == line).peekable();
        let styles = found.peek()?.1.styles.clone();
        let mut polys = Vec::new();
        let mut rule = None;
        let mut elements = Vec::new();
        let mut clips: Option<Vec<Clip>> = None;
        for (i, e) in found {
            elements.push(i);
            let own: &[Clip] = match &e.shape {
                Shape::Path(p) => {
                    rule.get_or_insert(p.fill_rule);
                    polys.extend(p.outline.iter().cloned());
                    &p.clips
                }
                Shape::Text(t) => {
                    polys.extend(t.outline.iter().cloned());
                    &[]
                }
                Shape::Image { .. } => &[],
            };
            // Copies clipped differently (a `<use>` in two viewports): none kept.
            match &clips {
                None => clips = Some(own.to_vec()),
                Some(c) if c.as_slice() != own => clips = Some(Vec::new()),
                Some(_) => {}
            }
        }
        Some(Source { elements, polys, rule: rule.unwrap_or_default(), styles, clips: clips.unwrap_or_default() })
    }

    /// The opaque fills that hide a grated layer made of `sources`, as the
    /// compiler finds them ([`taxel_compiler::drawing::occluders`]): each one's
    /// outline and fill rule.
    pub fn occluders(&self, sources: &[Source]) -> Vec<(&[Polyline], FillRule)> {
        let mut elements: Vec<usize> = sources.iter().flat_map(|s| s.elements.iter().copied()).collect();
        elements.sort_unstable();
        elements.dedup();
        taxel_compiler::drawing::occluders(&self.drawing, &elements)
            .into_iter()
            .filter_map(|j| match &self.drawing.elements.get(j)?.shape {
                Shape::Path(p) => Some((p.outline.as_slice(), p.fill_rule)),
                _ => None,
            })
            .collect()
    }
}

/// The exact layers of a compiled drawing: one per distance layer (the
/// union of its sources, SPEC.md section 6.2: touching borders of one style
/// are one border), one per element of a raster mask layer, and the dot
/// tables. Every vibrating band on the page is cut out of every grating, as
/// the compiler does.
pub fn exact_layers(svg: &str, bundle: &Bundle, opts: &CompileOptions) -> Result<(Vec<ExactLayer>, Gaps), String> {
    let drawing = Drawing::read(svg, &bundle.manifest.profile, opts)?;
    let prov = bundle.provenance();
    let mut layers = Vec::new();
    let mut gaps = Gaps::default();
    // Gratings are not felt around braille, where the compiler cleared them
    // (found from the bundle's braille dots, as the compiler finds them).
    let clearing: Vec<Polyline> = bundle
        .chunks
        .iter()
        .filter_map(|c| match c {
            Chunk::Dots(d) if d.kind == taxel_format::DotKind::Braille => Some(&d.dots),
            _ => None,
        })
        .flat_map(|dots| taxel_compiler::latero::braille_clearing(dots))
        .collect();
    // Each vibration or grating layer as (its sources, kind, amplitude): a
    // distance layer's every source, a raster mask's one source.
    let mut groups: Vec<(Vec<u32>, MaskKind, f32)> = Vec::new();
    for chunk in &bundle.chunks {
        match chunk {
            Chunk::Mask(m) => groups.push((m.source.into_iter().collect(), m.kind, m.amplitude)),
            Chunk::Distance(d) => groups.push((d.sources.clone(), d.kind, d.amplitude)),
            Chunk::Dots(d) => layers.push(ExactLayer::Dots(
                d.dots.iter().map(|d| (d.x.0 as f64, d.y.0 as f64, d.radius.0 as f64, d.amplitude as f64)).collect(),
            )),
            _ => {}
        }
    }
    // The geometry of every group's sources, and every vibrating band on the page.
    let mut resolved: Vec<Vec<Source>> = Vec::new();
    let mut all_bands: Vec<(Arc<Index>, f64)> = Vec::new();
    let mut band_corners: Vec<(f64, f64)> = Vec::new();
    for (sources, kind, _) in &groups {
        let mut geos = Vec::new();
        if sources.is_empty() {
            gaps.missing.push("(no provenance)".into());
        }
        for &s in sources {
            let entry = prov.and_then(|p| p.entries.get(s as usize));
            match entry.and_then(|e| drawing.source(&e.id, e.line)) {
                Some(geo) => {
                    if matches!(kind, MaskKind::Vibration { .. }) {
                        all_bands.push((Arc::new(Index::new(&geo.polys, false)), band_width(&geo)));
                        band_corners.extend(corners(&geo.polys, false, Some(band_width(&geo))));
                    }
                    geos.push(geo);
                }
                None => {
                    gaps.missing.push(entry.map_or("(no provenance)".into(), |e| format!("{} line {}", e.id, e.line)))
                }
            }
        }
        resolved.push(geos);
    }
    for ((sources, kind, amplitude), geos) in groups.into_iter().zip(resolved) {
        if geos.is_empty() {
            continue;
        }
        let amplitude = amplitude as f64;
        layers.push(match kind {
            MaskKind::Vibration { freq } => ExactLayer::Vibration {
                region: Region::Band {
                    bands: geos.iter().map(|g| (Arc::new(Index::new(&g.polys, false)), band_width(g))).collect(),
                    clips: geos.iter().map(clip_regions).collect(),
                    corners: geos
                        .iter()
                        .flat_map(|g| {
                            corners(&g.polys, false, Some(band_width(g)))
                                .into_iter()
                                .chain(g.clips.iter().flat_map(|c| corners(&c.outline, true, None)))
                        })
                        .collect(),
                },
                freq_hz: freq.0 as f64 / 1000.0,
                amplitude,
                ramp_mm: 0.0,
                sources,
            },
            MaskKind::Grating { wavelength, angle_deg } => {
                let mut occluders = drawing.occluders(&geos);
                // The clearings that meet the layer's shapes, as the compiler takes them.
                let mine = geos
                    .iter()
                    .filter_map(|g| taxel_compiler::geometry::bounds(&g.polys))
                    .reduce(|a, r| (a.0.min(r.0), a.1.min(r.1), a.2.max(r.2), a.3.max(r.3)));
                occluders.extend(taxel_compiler::latero::clearing_within(&clearing, mine));
                ExactLayer::Grating {
                    region: Region::Fill {
                        fills: geos.iter().map(|g| (Index::new(&g.polys, true), g.rule)).collect(),
                        clips: geos.iter().map(clip_regions).collect(),
                        minus_bands: all_bands.clone(),
                        minus_fills: occluders.iter().map(|&(o, rule)| (Index::new(o, true), rule)).collect(),
                        corners: geos
                            .iter()
                            .flat_map(|g| {
                                corners(&g.polys, true, None)
                                    .into_iter()
                                    .chain(g.clips.iter().flat_map(|c| corners(&c.outline, true, None)))
                            })
                            .chain(occluders.iter().flat_map(|&(o, _)| corners(o, true, None)))
                            .chain(band_corners.iter().copied())
                            .collect(),
                    },
                    wavelength_mm: wavelength.0 as f64,
                    angle_deg: angle_deg as f64,
                    amplitude,
                    ramp_mm: 0.0,
                    sources,
                }
            }
        });
    }
    Ok((layers, gaps))
}

/// A source's clip regions, indexed for coverage.
fn clip_regions(geo: &Source) -> Vec<(Index, FillRule)> {
    geo.clips.iter().map(|c| (Index::new(&c.outline, true), c.fill_rule)).collect()
}

/// The vibrating band's width of an element: its `vibrate(width: ...)`, or the default.
fn band_width(geo: &Source) -> f64 {
    geo.styles
        .iter()
        .find_map(|s| match s {
            Style::Vibrate(v) => Some(v.width_mm),
            _ => None,
        })
        .unwrap_or(DEFAULT_BAND_MM)
}
