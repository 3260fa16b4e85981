//! The plan of a drawing's laterotactile layers: a public stage, as usvg's
//! `Tree` is between SVG text and pixels.
//!
//! For each distance layer the bundle will hold (one per vibration or
//! grating style and set of clip regions), the plan says what it is (its
//! kind and parameters), which elements and provenance entries it holds, and
//! the exact source geometry it is built from: the fills of a grating, the
//! centre lines of a vibrating band, the vibrating bands cut out of a
//! grating, the clip regions, and the opaque fills and braille clearings
//! that hide it. The compiler builds every distance layer from its plan
//! ([`LayerPlan::geometry`] is what the field builder is given), and tools
//! such as `taxel report` measure the built layers against the same plan.

use taxel_format::{DotTable, MaskKind, MilliHertz, Mm};

use super::distance::LayerGeometry;
use super::{LayerStyle, Pending, clearing_within, clips_of, field_pitch, fill_rule, outline};
use crate::brush::BrushRequest;
use crate::drawing::{Drawing, OpaqueFills};
use crate::geometry::{FillRule, Polyline};
use crate::options::CompileOptions;

/// The layers of one drawing, as the laterotactile back end will build them.
#[derive(Debug, Clone)]
pub struct LayerPlan<'d> {
    /// The lattice pitch every layer of the drawing shares, mm (five pixels
    /// at the resolution, at most half the narrowest vibrating band).
    pub pitch_mm: f64,
    /// The part of the page on the device's surface `(x0, y0, x1, y1)`, mm:
    /// nothing beyond it is felt or stored.
    pub page: (f64, f64, f64, f64),
    /// The distance layers, in the order of their styles' first elements
    /// (the bundle's order, less the layers that come out empty).
    pub layers: Vec<PlannedLayer<'d>>,
    /// Where gratings are not felt around the braille written (closed
    /// rectangles: the box of each braille line's dots, grown by the design
    /// rules' gap).
    pub braille_clearing: Vec<Polyline>,
    /// The dot tables (outline, symbol and braille dots, the non-empty
    /// ones in that order): exact already, a centre, radius and amplitude each.
    pub dots: Vec<DotTable>,
    /// The brushed paths to schedule on a grid device (one per subpath of
    /// each brushed element, in document order), as the stroke table is
    /// planned from them ([`brush::plan_strokes`](crate::brush::plan_strokes)).
    pub brush: Vec<BrushRequest>,
}

/// One distance layer of a [`LayerPlan`]: what it is and the exact geometry it is made of.
#[derive(Debug, Clone)]
pub struct PlannedLayer<'d> {
    /// The primitive and its parameters, as the bundle stores them.
    pub kind: MaskKind,
    /// Amplitude, 0..=1.
    pub amplitude: f64,
    /// Width of the edge profile's ramp, mm (0: hard).
    pub soft_mm: f64,
    /// The drawing's elements it holds (indices into `Drawing::elements`), in document order.
    pub elements: Vec<usize>,
    /// Their provenance entries, ascending (the distance chunk's `sources`).
    pub sources: Vec<u32>,
    /// A grating's filled shapes, each with its fill rule (subpaths closed implicitly).
    pub fills: Vec<(&'d [Polyline], FillRule)>,
    /// A vibration's centre lines and the band's width, mm.
    pub band: Option<(Vec<&'d [Polyline]>, f64)>,
    /// The vibrating bands (centre lines, width mm) cut out of a grating:
    /// every band of the drawing that comes near it.
    pub cuts: Vec<(&'d [Polyline], f64)>,
    /// The clip regions its elements share: it is felt only inside every one.
    pub clips: Vec<(&'d [Polyline], FillRule)>,
    /// The opaque fills painted over a grating's elements (drawing indices), which hide it there.
    pub covered_by: Vec<usize>,
    /// The braille clearings that meet a grating (indices into [`LayerPlan::braille_clearing`]).
    pub clearing: Vec<usize>,
    /// Its place among the styles the back end gathered (the features' layer number).
    pub(super) pending: usize,
}

impl PlannedLayer<'_> {
    /// The style's name in messages: `vibrate` or `grating`.
    pub fn style_name(&self) -> &'static str {
        match self.kind {
            MaskKind::Vibration { .. } => "vibrate",
            MaskKind::Grating { .. } => "grating",
        }
    }
}

impl<'d> LayerPlan<'d> {
    /// The geometry layer `k` is built from: its own parts, and as
    /// occluders the opaque fills over it, then the braille clearings that
    /// meet it.
    pub fn geometry<'p>(&'p self, drawing: &'p Drawing, k: usize) -> Option<LayerGeometry<'p>> {
        let l = self.layers.get(k)?;
        let mut occluders: Vec<(&[Polyline], FillRule)> =
            l.covered_by.iter().filter_map(|&j| drawing.elements.get(j)).map(|e| (outline(e), fill_rule(e))).collect();
        occluders.extend(
            l.clearing
                .iter()
                .filter_map(|&c| self.braille_clearing.get(c))
                .map(|c| (std::slice::from_ref(c), FillRule::NonZero)),
        );
        Some(LayerGeometry {
            fills: l.fills.clone(),
            band: l.band.clone(),
            cuts: l.cuts.clone(),
            clips: l.clips.clone(),
            occluders,
        })
    }

    /// Checks the plan's invariants, in the spirit of spade's
    /// `sanity_check` (the tests call it): a shared lattice pitch within
    /// half of every band's width; each layer holds elements of `drawing`,
    /// ascending, with strictly ascending sources; a vibration is a band of
    /// one centre line set per element and nothing else; a grating is one
    /// fill per element; what hides a grating is painted after one of its
    /// elements; every clearing it names exists.
    pub fn sanity_check(&self, drawing: &Drawing) -> Result<(), String> {
        if !(self.pitch_mm.is_finite() && self.pitch_mm > 0.0) {
            return Err(format!("pitch {} mm", self.pitch_mm));
        }
        let (x0, y0, x1, y1) = self.page;
        if !(x0 <= x1 && y0 <= y1) {
            return Err(format!("page {:?}", self.page));
        }
        for (k, l) in self.layers.iter().enumerate() {
            let bad = |what: &str| Err(format!("layer {k} ({}): {what}", l.style_name()));
            if l.elements.is_empty() || !l.elements.windows(2).all(|w| w[0] < w[1]) {
                return bad("elements not ascending, or none");
            }
            if l.elements.iter().any(|&i| i >= drawing.elements.len()) {
                return bad("an element beyond the drawing");
            }
            if !l.sources.windows(2).all(|w| w[0] < w[1]) {
                return bad("sources not strictly ascending");
            }
            match (l.kind, &l.band) {
                (MaskKind::Vibration { .. }, Some((lines, w))) => {
                    if lines.len() != l.elements.len() || !(*w > 0.0 && self.pitch_mm <= w / 2.0) {
                        return bad("a band not of one centre line set per element, or narrower than two pitches");
                    }
                    if !(l.fills.is_empty() && l.cuts.is_empty() && l.covered_by.is_empty() && l.clearing.is_empty()) {
                        return bad("a band with a grating's parts");
                    }
                }
                (MaskKind::Grating { .. }, None) if l.fills.len() == l.elements.len() => {}
                _ => return bad("parts that do not match its kind"),
            }
            let first = l.elements[0];
            if l.covered_by.iter().any(|&j| j <= first || j >= drawing.elements.len()) {
                return bad("an occluder not painted after its elements");
            }
            if l.clearing.iter().any(|&c| c >= self.braille_clearing.len()) {
                return bad("a braille clearing that does not exist");
            }
        }
        Ok(())
    }

    /// The plan of the styles gathered from `drawing` (`pending`, with the
    /// provenance entry of each element), at `px` samples per mm, for the
    /// part of the page on the surface `felt`.
    pub(super) fn new(
        drawing: &'d Drawing,
        pending: &[Pending],
        source_of: impl Fn(usize) -> Option<u32>,
        braille_clearing: Vec<Polyline>,
        px: f32,
        felt: (f64, f64),
        opaque: &OpaqueFills,
    ) -> LayerPlan<'d> {
        let page = drawing.page;
        let polys = |i: usize| outline(&drawing.elements[i]);
        let bands: Vec<(usize, f64)> = pending
            .iter()
            .filter_map(|p| match p.style {
                LayerStyle::Vibrate(v) => Some(p.elements.iter().map(move |&i| (i, v.width_mm))),
                LayerStyle::Grating(_) => None,
            })
            .flatten()
            .collect();
        // One lattice for every layer of the drawing: a grating's cut-out band
        // is then sampled at the same points as the band itself, so the two
        // interpolate to complementary values and never overlap.
        let narrowest = bands.iter().map(|&(_, w)| w).reduce(f64::min);
        let pitch = field_pitch(px, narrowest);
        let mut layers = Vec::with_capacity(pending.len());
        for (k, p) in pending.iter().enumerate() {
            // The clips every element of the layer shares (its first element's).
            let shared = p.elements.first().map_or(&[][..], |&i| clips_of(&drawing.elements[i]));
            let clips: Vec<_> = shared.iter().map(|c| (&c.outline[..], c.fill_rule)).collect();
            let mut sources: Vec<u32> = p.elements.iter().filter_map(|&i| source_of(i)).collect();
            sources.sort_unstable();
            sources.dedup();
            let mut layer = PlannedLayer {
                kind: MaskKind::Grating { wavelength: Mm(0.0), angle_deg: 0.0 },
                amplitude: 0.0,
                soft_mm: 0.0,
                elements: p.elements.clone(),
                sources,
                fills: Vec::new(),
                band: None,
                cuts: Vec::new(),
                clips,
                covered_by: Vec::new(),
                clearing: Vec::new(),
                pending: k,
            };
            match p.style {
                LayerStyle::Vibrate(v) => {
                    // (Styles of a frequency the format cannot hold gather no elements.)
                    let Some(freq) = MilliHertz::from_hz(v.freq_hz) else { continue };
                    layer.kind = MaskKind::Vibration { freq };
                    (layer.amplitude, layer.soft_mm) = (v.amplitude, v.soft_mm);
                    layer.band = Some((p.elements.iter().map(|&i| polys(i)).collect(), v.width_mm));
                }
                LayerStyle::Grating(gr) => {
                    layer.kind =
                        MaskKind::Grating { wavelength: Mm(gr.wavelength_mm as f32), angle_deg: gr.angle_deg as f32 };
                    (layer.amplitude, layer.soft_mm) = (gr.amplitude, gr.soft_mm);
                    layer.fills = p.elements.iter().map(|&i| (polys(i), fill_rule(&drawing.elements[i]))).collect();
                    let reach = gr.soft_mm / 2.0 + 2.0 * pitch;
                    let mine = p
                        .elements
                        .iter()
                        .filter_map(|&i| crate::geometry::bounds(polys(i)))
                        .reduce(|a, r| (a.0.min(r.0), a.1.min(r.1), a.2.max(r.2), a.3.max(r.3)));
                    layer.cuts = bands
                        .iter()
                        .filter(|(i, w)| {
                            let m = w / 2.0 + reach;
                            match (mine, crate::geometry::bounds(polys(*i))) {
                                (Some(a), Some(r)) => {
                                    r.0 - m <= a.2 && a.0 <= r.2 + m && r.1 - m <= a.3 && a.1 <= r.3 + m
                                }
                                _ => false,
                            }
                        })
                        .map(|&(i, w)| (polys(i), w))
                        .collect();
                    layer.covered_by = opaque.above(drawing, &p.elements);
                    // Nor under braille and a gap around it: braille amid a
                    // texture reads as more texture.
                    layer.clearing = clearing_within(&braille_clearing, mine).collect();
                }
            }
            layers.push(layer);
        }
        // Nothing beyond the page, or the device's surface, is felt or stored.
        let page_rect = (0.0, 0.0, page.width_mm.min(felt.0), page.height_mm.min(felt.1));
        LayerPlan { pitch_mm: pitch, page: page_rect, layers, braille_clearing, dots: Vec::new(), brush: Vec::new() }
    }
}

/// The plan of `drawing`'s laterotactile layers (a drawing after
/// [`pipeline::resolve`](crate::pipeline::resolve), placed and styled) for
/// the profile and resolution of `opts`: the layers
/// [`compile_svg`](crate::compile_svg) builds, from the same code. The
/// diagnostics of the walk are left out (`compile_svg` gives them).
///
/// ```
/// use taxel_compiler::{CompileOptions, latero, pipeline};
/// use taxel_format::{MaskKind, profiles};
///
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="60mm" height="40mm" viewBox="0 0 60 40">
///   <rect x="10" y="10" width="20" height="20" data-tactile="grating(wavelength: 2mm)"/>
///   <circle cx="45" cy="20" r="8" fill="none" stroke="black" data-tactile="vibrate()"/>
/// </svg>"#;
/// let opts = CompileOptions::new(profiles::builtin("stress2").expect("a built-in profile"));
/// let drawing = pipeline::resolve(svg, &opts).drawing.expect("a drawing");
/// let plan = latero::plan(&drawing, &opts);
/// assert_eq!(plan.layers.len(), 2);
/// assert!(matches!(plan.layers[0].kind, MaskKind::Grating { .. }));
/// // The grating is one filled square; the vibrating ring is a band 1.5 mm wide.
/// assert_eq!(plan.layers[0].fills.len(), 1);
/// assert_eq!(plan.layers[1].band.as_ref().map(|b| b.1), Some(1.5));
/// ```
pub fn plan<'d>(drawing: &'d Drawing, opts: &CompileOptions) -> LayerPlan<'d> {
    let px = match opts.resolution_px_per_mm {
        Some(r) if r.is_finite() && (0.1..=200.0).contains(&r) => r,
        _ => crate::DEFAULT_PX_PER_MM,
    };
    super::walk(drawing, opts, px, &mut Vec::new()).1
}
