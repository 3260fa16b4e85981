//! The exact layers of a compiled drawing, from the compiler's own stages.
//!
//! The drawing is resolved as the compiler resolves it
//! (`taxel_compiler::pipeline::resolve`, with the bundle's profile and the
//! same style sheet, `--width-mm` and fonts), and the plan of its layers
//! (`taxel_compiler::latero::plan`) says what each distance layer is made
//! of: the exact geometry the compiler builds it from (fills, bands, the
//! vibrating bands cut out of a grating, clips, the opaque fills and braille
//! clearings that hide it). Each distance chunk of the bundle is paired with
//! the planned layer of the same kind and sources, and its region is that
//! geometry's exact region, the compiler's ([`Region`]). The layers' other
//! parameters (frequency, wavelength, angle, amplitude) come from the bundle
//! itself, as the player reads them; dots are exact in the bundle already.

use std::sync::Arc;

use taxel_compiler::CompileOptions;
use taxel_format::{Bundle, Chunk, MaskKind};

use super::exact::{ExactLayer, Region};

/// The exact layers of `bundle`, compiled from `svg` with `opts`: one per
/// distance layer, one for each dot table, in the bundle's order, and a
/// note for each layer left out of the reference (with no planned layer
/// of its sources, or a raster mask, which has no plan).
pub fn exact_layers(
    svg: &str,
    bundle: &Bundle,
    opts: &CompileOptions,
) -> Result<(Vec<ExactLayer>, Vec<String>), String> {
    let opts = CompileOptions {
        profile: bundle.manifest.profile,
        flattening: taxel_compiler::geometry::REFERENCE_FLATTENING,
        ..opts.clone()
    };
    let resolved = taxel_compiler::pipeline::resolve(svg, &opts);
    let Some(drawing) = resolved.drawing else {
        return Err(resolved.diagnostics.first().map_or("the SVG could not be read".into(), |d| d.message.clone()));
    };
    let plan = taxel_compiler::latero::plan(&drawing, &opts);
    let prov = bundle.provenance();
    let named = |sources: &[u32]| -> String {
        let names: Vec<String> = sources
            .iter()
            .filter_map(|&s| prov.and_then(|p| p.entries.get(s as usize)))
            .map(|e| format!("{} line {}", e.id, e.line))
            .collect();
        if names.is_empty() { "(no provenance)".into() } else { names.join(", ") }
    };
    let mut taken = vec![false; plan.layers.len()];
    let (mut layers, mut missing) = (Vec::new(), Vec::new());
    for chunk in &bundle.chunks {
        match chunk {
            Chunk::Distance(d) => {
                let found = (0..plan.layers.len())
                    .find(|&k| !taken[k] && plan.layers[k].kind == d.kind && plan.layers[k].sources == d.sources);
                let Some(g) = found.and_then(|k| plan.geometry(&drawing, k).map(|g| (k, g))) else {
                    missing.push(named(&d.sources));
                    continue;
                };
                taken[g.0] = true;
                let (amplitude, sources) = (d.amplitude as f64, d.sources.clone());
                let region = Arc::new(Region::of(&g.1));
                layers.push(match d.kind {
                    MaskKind::Vibration { freq } => ExactLayer::Vibration {
                        region,
                        freq_hz: freq.0 as f64 / 1000.0,
                        amplitude,
                        ramp_mm: 0.0,
                        sources,
                    },
                    MaskKind::Grating { wavelength, angle_deg } => ExactLayer::Grating {
                        region,
                        wavelength_mm: wavelength.0 as f64,
                        angle_deg: angle_deg as f64,
                        amplitude,
                        ramp_mm: 0.0,
                        sources,
                    },
                });
            }
            Chunk::Mask(m) => missing.push(named(&m.source.into_iter().collect::<Vec<_>>())),
            Chunk::Dots(d) => layers.push(ExactLayer::Dots(super::exact::Dots::new(
                d.dots.iter().map(|d| (d.x.0 as f64, d.y.0 as f64, d.radius.0 as f64, d.amplitude as f64)),
            ))),
            _ => {}
        }
    }
    Ok((layers, missing))
}
