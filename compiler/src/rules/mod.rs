//! Stage 5, design rules (laterotactile arrays): the back end's features checked against the perception research.
//!
//! Design rules from the research: what will not read well by touch.
//! Every rule, its threshold and its source are listed in docs/diagnostics.md.
//!
//! This module checks the features' own rules and finds the pairs the rules
//! between features look at; `gaps.rs` searches the gaps (T0408),
//! `gratings.rs` the confusable gratings (T0401, T0402), and `overlap.rs`
//! the overlaps of two built layers (T0406, T0410).

use std::collections::HashSet;

use rayon::prelude::*;

use taxel_format::DeviceProfile;

use crate::diagnostic::Diagnostic;
use crate::geometry::bounds;
use crate::latero::{Built, Feature, FeatureKind};
use crate::spatial;

mod gaps;
mod gratings;
mod overlap;

use gaps::nearest_gaps;
use gratings::confusable_gratings;

pub use crate::latero::MIN_GAP_MM;

/// How far the outlines the gap rule measures may lie from the drawn ones
/// (Douglas–Peucker), in mm: a reported gap is within twice this of the
/// exact one, far below the 0.1 mm the rule prints.
pub const GAP_TOLERANCE_MM: f64 = 0.002;
/// Smallest shape readers identified reliably (seed 000 §4.1: 2-3 cm shapes).
pub const MIN_SHAPE_MM: f64 = 20.0;
/// Grating wavelengths closer than this cannot be told apart (seed 000 §4.2: 0.5 mm at 74 %).
pub const WAVELENGTH_ERROR_MM: f64 = 0.5;
/// Grating wavelengths closer than this are not told apart reliably (seed 000 §4.2: 3 mm almost always).
pub const WAVELENGTH_WARN_MM: f64 = 3.0;
/// Gratings this close count as adjacent: both fit under the array (about 9 x 11 mm) in one hand position.
pub const ADJACENT_MM: f64 = 10.0;
/// Most distinct textures, line styles or point symbols in one graphic (BANA 2010).
pub const MAX_DISTINCT: usize = 5;

/// A length for messages: profile values are f32, so show them as written (2.4, not 2.4000000953674316).
fn short(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

fn at(d: Diagnostic, f: &Feature) -> Diagnostic {
    Diagnostic { line: Some(f.line), ..d.with_element(&f.name) }
}

/// What the design rules find from the features alone, before the layers
/// are built: everything but the overlaps of layers, which sample them.
/// `layers::build` runs this beside the distance fields (the gap rule and
/// the fields are the two large parts of a map's build).
pub(crate) struct Checked {
    /// The features' own rules and the counts, which come before the overlaps.
    head: Vec<Diagnostic>,
    /// Pairs `(i, j)`, `i < j`, in order, whose boxes meet and that are not
    /// of one layer: the overlap checks' candidates.
    meets: Vec<(usize, usize)>,
    /// Confusable gratings and gaps, which come after the overlaps.
    tail: Vec<Diagnostic>,
}

/// The design rules that need only the features (their layers need not be
/// built: a feature's `mask` may still be its style's place among the
/// styles, which names one layer for features of one style, as the built
/// layer's index does). Every design rule is checked by this and
/// [`Checked::finish`] in turn.
pub(crate) fn check_features(features: &[Feature], profile: &DeviceProfile) -> Checked {
    let mut head = Vec::new();
    let diags = &mut head;
    let (px, py) = (profile.pitch_x_mm as f64, profile.pitch_y_mm as f64);
    let pitch = px.max(py);
    let textures = one_texture(features);
    // A size or gap is said once per element, not once per style it has (its fill and its border).
    let mut sized = HashSet::new();
    for (k, f) in features.iter().enumerate() {
        match f.kind {
            FeatureKind::Vibrate { width_mm, .. } if width_mm < pitch => diags.push(at(
                Diagnostic::warning(
                    "T0404",
                    format!("the vibrating outline is {width_mm} mm wide, thinner than the actuator pitch ({} mm), so it aliases", short(pitch)),
                )
                .with_help(format!("use a width of at least {} mm (the STRESS² study used 1.5 mm)", short(pitch))),
                f,
            )),
            FeatureKind::Grating { wavelength_mm, angle_deg } => {
                let a = angle_deg.rem_euclid(180.0);
                let near = [0.0, 45.0, 90.0, 135.0, 180.0].iter().any(|c| (a - c).abs() < 0.5);
                if !near {
                    diags.push(at(
                        Diagnostic::warning("T0403", format!("the grating angle {angle_deg}° is not one of 0°, 45°, 90°, 135°"))
                            .with_help("readers identify only these orientations reliably (30° steps were at chance)"),
                        f,
                    ));
                }
                // Spatial frequency across the ridges, per axis; Nyquist needs each under 1 / (2 pitch).
                let t = angle_deg.to_radians();
                let (kx, ky) = (t.sin().abs() / wavelength_mm, t.cos().abs() / wavelength_mm);
                if kx > 1.0 / (2.0 * px) + 1e-9 || ky > 1.0 / (2.0 * py) + 1e-9 {
                    let across = if kx * px >= ky * py { px } else { py };
                    diags.push(at(
                        Diagnostic::warning(
                            "T0405",
                            format!(
                                "the grating wavelength {wavelength_mm} mm is below twice the actuator pitch across its ridges ({} mm), so the array aliases it when still",
                                short(2.0 * across)
                            ),
                        )
                        .with_help("it still reads while the array moves; use a longer wavelength for a texture felt at rest"),
                        f,
                    ));
                }
            }
            _ => {}
        }
        // Only closed shapes: the research measured shapes, not line segments (a key's sample line, say).
        let closed = f.outline.iter().any(|p| p.closed);
        if closed
            && matches!(f.kind, FeatureKind::Vibrate { .. } | FeatureKind::Grating { .. } | FeatureKind::Dots { .. })
        {
            // A grating merged with others of its style into one texture is
            // felt as part of that texture: the shape is theirs, said once.
            let (x0, y0, x1, y1) = match textures.get(&k) {
                Some(&(first, _)) if first != k => continue,
                Some(&(_, whole)) => whole,
                None => bounds(&f.outline).unwrap_or(f.bbox),
            };
            let (w, h) = (x1 - x0, y1 - y0);
            // A hair of tolerance: a shape drawn at exactly 2 cm must not be reported.
            if w.max(h) < MIN_SHAPE_MM - 0.05 && sized.insert(f.elem) {
                diags.push(at(
                    Diagnostic::warning("T0407", format!("the shape is {w:.1} x {h:.1} mm, smaller than 2 cm"))
                        .with_help("shapes of 2-3 cm were identified reliably; enlarge it or use a point symbol"),
                    f,
                ));
            }
        }
    }
    counts(features, diags);
    let mut tail = Vec::new();
    let meets = pairs(features, &textures, &mut tail);
    Checked { head, meets, tail }
}

/// Gratings felt as one texture: feature -> (the texture's first feature, its box).
type Textures = std::collections::HashMap<usize, (usize, (f64, f64, f64, f64))>;

/// The gratings felt as one texture: those of one style (one layer) whose
/// outlines touch, joined through every such pair (a map's regions of one
/// fill whose borders were left out, T0324). Each such feature maps to its
/// texture's first feature and the box of the whole texture; a grating that
/// touches none of its style is not in the map. Two of one texture are not
/// two shapes to identify (T0407) nor two elements to feel apart (T0408):
/// what lies between them is the same texture.
fn one_texture(f: &[Feature]) -> Textures {
    let gratings: Vec<usize> =
        (0..f.len()).filter(|&k| f[k].mask.is_some() && matches!(f[k].kind, FeatureKind::Grating { .. })).collect();
    let mut groups = spatial::Groups::new(f.len());
    let index = spatial::BoxIndex::new(&gratings.iter().map(|&k| f[k].bbox).collect::<Vec<_>>());
    for &a in &gratings {
        for b in index.meeting(f[a].bbox).map(|n| gratings[n]) {
            if b <= a || f[a].mask != f[b].mask {
                continue;
            }
            if groups.root(a) != groups.root(b)
                && spatial::min_outline_distance(&f[a].outline, &f[b].outline, GAP_TOLERANCE_MM, GAP_TOLERANCE_MM)
                    <= GAP_TOLERANCE_MM
            {
                // The lower index stays the root: the texture's first feature.
                groups.join(a, b);
            }
        }
    }
    // Per texture (its root): how many gratings, and their box.
    let mut whole: Textures = Default::default();
    for &k in &gratings {
        let r = groups.root(k);
        let b = bounds(&f[k].outline).unwrap_or(f[k].bbox);
        let e = whole.entry(r).or_insert((0, b));
        e.0 += 1;
        e.1 = (e.1.0.min(b.0), e.1.1.min(b.1), e.1.2.max(b.2), e.1.3.max(b.3));
    }
    let mut out = std::collections::HashMap::new();
    for &k in &gratings {
        let r = groups.root(k);
        if let Some(&(_, b)) = whole.get(&r).filter(|(n, _)| *n > 1) {
            out.insert(k, (r, b));
        }
    }
    out
}

impl Checked {
    /// Adds the rules' diagnostics in their order, the overlaps of the
    /// built layers among them.
    pub(crate) fn finish(self, built: &Built, diags: &mut Vec<Diagnostic>) {
        let f = &built.features;
        // Room for the rules' own diagnostics at once: on the map at the
        // input limit there are half a million, and growing the list as
        // they came copied it again at each doubling, on one thread.
        diags.reserve(self.head.len() + self.tail.len());
        diags.extend(self.head);
        // Flattened as they are found, straight into the list (rayon keeps
        // the pairs' order): a list with one entry (24 bytes) per meeting
        // pair, nearly all empty, was freshly paged in on one thread on the
        // map at the input limit.
        diags.par_extend(self.meets.par_iter().flat_map_iter(|&(i, j)| {
            let mut out = Vec::new();
            overlap::overlap(built, &f[i], &f[j], &mut out);
            out
        }));
        drop(self.meets);
        diags.extend(self.tail);
    }
}

fn counts(features: &[Feature], diags: &mut Vec<Diagnostic>) {
    let key = |v: f64| (v * 100.0).round() as i64;
    let mut textures = HashSet::new();
    let mut lines = HashSet::new();
    let mut symbols = HashSet::new();
    for f in features {
        match f.kind {
            FeatureKind::Grating { wavelength_mm, angle_deg } => {
                textures.insert((key(wavelength_mm), key(angle_deg.rem_euclid(180.0)), key(f.amplitude)));
            }
            FeatureKind::Vibrate { width_mm, freq_hz } => {
                lines.insert((0, key(width_mm), key(freq_hz), key(f.amplitude)));
            }
            FeatureKind::Dots { radius_mm, spacing_mm } => {
                lines.insert((1, key(radius_mm), key(spacing_mm), key(f.amplitude)));
            }
            FeatureKind::Dot { radius_mm } => {
                symbols.insert((key(radius_mm), key(f.amplitude)));
            }
            FeatureKind::Braille => {}
        }
    }
    for (n, what) in [(textures.len(), "textures"), (lines.len(), "line styles"), (symbols.len(), "point symbols")] {
        if n > MAX_DISTINCT {
            diags.push(
                Diagnostic::warning(
                    "T0409",
                    format!("the drawing uses {n} distinct {what}; more than {MAX_DISTINCT} are hard to keep apart"),
                )
                .with_help("merge similar ones, or split the graphic and give a key"),
            );
        }
    }
}

/// `value` (below `limit`) with one decimal, or as many more as it takes (up
/// to three, then cut rather than rounded) for it not to read as `limit` or
/// more: "3.19 mm, closer than 3.2 mm", not "3.2 mm, closer than 3.2 mm".
fn below(value: f64, limit: f64) -> String {
    (1..=3)
        .map(|d| format!("{value:.d$}"))
        .find(|s| s.parse::<f64>().is_ok_and(|v| v < limit))
        .unwrap_or_else(|| format!("{:.3}", (value * 1000.0).floor() / 1000.0))
}

/// The rules between features, each through an R*-tree over the footprints'
/// boxes, so that the cost grows with the features, not with all pairs nor
/// with how many neighbours fall within a rule's radius (a map shrunk by
/// `--fit` packs ever more of them into 10 mm):
///
/// - overlaps (T0406, T0410): the pairs whose boxes meet, found in the same
///   pass as the gaps' candidates and returned (checked once the layers are
///   built, by [`Checked::finish`]);
/// - confusable gratings (T0401, T0402): only between textures that can be
///   confused, each pair of such textures through its own index;
/// - gaps (T0408): each feature's nearest distinct neighbour that does not
///   touch it, each pair measured once and only while its boxes could still
///   hold a nearer gap for one of the two.
///
/// A drawing so dense that more than [`MAX_MEETING_PAIRS`] pairs of features have
/// boxes that meet (estimated from a sample of the features) is not
/// checked pair by pair: the gaps and overlaps are left out with one
/// warning (T0412) that says why.
fn pairs(f: &[Feature], textures: &Textures, diags: &mut Vec<Diagnostic>) -> Vec<(usize, usize)> {
    pairs_within(f, textures, diags, MAX_MEETING_PAIRS)
}

/// Pairs of features whose boxes meet beyond which the rules between
/// features are not checked (T0412). Each pair costs about half a
/// microsecond of one core (its outlines' distance, and an overlap check
/// between layers). Estimated, fitted to stress2: the map at the input
/// limit has 3.6 million (each of its 54,000 features' boxes meets 130
/// others) and builds in 8 s; a 40,000-way city plan 19 million, 5 s; the
/// 64 MB plan at the input limit (238,000 ways, each street's box meeting
/// some 7,500 others) 670 million, which took four minutes.
const MAX_MEETING_PAIRS: usize = 20_000_000;
/// Features whose box queries estimate the number of meeting pairs.
const DENSITY_SAMPLE: usize = 1024;

/// The number of pairs of `boxes` that meet, estimated from the boxes at
/// [`DENSITY_SAMPLE`] evenly spaced positions (all of them when there are
/// fewer): deterministic, and a few milliseconds however dense.
fn meeting_pairs(index: &spatial::BoxIndex, boxes: &[spatial::Bbox]) -> usize {
    let n = boxes.len();
    let picks = n.min(DENSITY_SAMPLE);
    if picks == 0 {
        return 0;
    }
    // Each sampled box meets itself (when usable): not a pair.
    let met: usize =
        (0..picks).filter_map(|k| boxes.get(k * n / picks)).map(|&b| index.meeting(b).count().saturating_sub(1)).sum();
    // Every pair is counted from both of its boxes.
    (met as f64 * n as f64 / picks as f64 / 2.0) as usize
}

/// [`pairs`] with the cap on meeting pairs `max_pairs`.
fn pairs_within(
    f: &[Feature],
    textures: &Textures,
    diags: &mut Vec<Diagnostic>,
    max_pairs: usize,
) -> Vec<(usize, usize)> {
    let boxes: Vec<_> = f.iter().map(|x| x.bbox).collect();
    let index = spatial::BoxIndex::new(&boxes);
    let meeting = meeting_pairs(&index, &boxes);
    if meeting > max_pairs {
        confusable_gratings(f, diags);
        diags.push(
            Diagnostic::warning(
                "T0412",
                format!(
                    "the drawing is too dense to check its elements against each other: about {meeting} pairs of its {} elements lie within each other's bounds (more than {max_pairs}), so gaps (T0408) and overlaps (T0406, T0410) were not checked",
                    f.len()
                ),
            )
            .with_help("at this density its elements cannot be felt apart: take part of the drawing with --region, or simplify it"),
        );
        return Vec::new();
    }
    let (gaps, meets) = nearest_gaps(f, &index, textures, |i, j, out| out.push((i, j)));
    confusable_gratings(f, diags);
    // Each element's nearest gap over its styles, at its first feature.
    let mut nearest: std::collections::HashMap<usize, (usize, usize, f64)> = Default::default();
    for (j, near) in gaps.into_iter().enumerate() {
        let Some((i, g)) = near else { continue };
        let e = nearest.entry(f[j].elem).or_insert((j, i, g));
        if g < e.2 {
            *e = (e.0, i, g);
        }
    }
    let mut nearest: Vec<(usize, usize, f64)> = nearest.into_values().collect();
    nearest.sort_unstable_by_key(|&(j, _, _)| j);
    for (j, i, g) in nearest {
        diags.push(at(
            Diagnostic::warning(
                "T0408",
                format!("this element is {} mm from #{}, closer than {MIN_GAP_MM} mm", below(g, MIN_GAP_MM), f[i].name),
            )
            .with_help("leave at least 3.2 mm (1/8 in) between distinct elements so they are felt apart"),
            &f[j],
        ));
    }
    meets
}

#[cfg(test)]
mod tests;
