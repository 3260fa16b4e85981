//! Stage 5, design rules (laterotactile arrays): the back end's features checked against the perception research.
//!
//! Design rules from the research: what will not read well by touch.
//! Every rule, its threshold and its source are listed in docs/diagnostics.md.

use std::collections::HashSet;
use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

use taxel_format::DeviceProfile;

use crate::diagnostic::Diagnostic;
use crate::geometry::{FillRule, Polyline, bounds, contains, dist, distance_to_outline_within, simplify};
use crate::latero::{Built, Feature, FeatureKind};
use crate::spatial;

mod overlap;

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
    let mut parent: Vec<usize> = (0..f.len()).collect();
    fn root(parent: &mut [usize], mut k: usize) -> usize {
        while parent[k] != k {
            parent[k] = parent[parent[k]];
            k = parent[k];
        }
        k
    }
    let index = spatial::BoxIndex::new(&gratings.iter().map(|&k| f[k].bbox).collect::<Vec<_>>());
    for &a in &gratings {
        for b in index.meeting(f[a].bbox).map(|n| gratings[n]) {
            if b <= a || f[a].mask != f[b].mask {
                continue;
            }
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            if ra != rb
                && spatial::min_outline_distance(&f[a].outline, &f[b].outline, GAP_TOLERANCE_MM, GAP_TOLERANCE_MM)
                    <= GAP_TOLERANCE_MM
            {
                // The lower index stays the root: the texture's first feature.
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    // Per texture (its root): how many gratings, and their box.
    let mut whole: Textures = Default::default();
    for &k in &gratings {
        let r = root(&mut parent, k);
        let b = bounds(&f[k].outline).unwrap_or(f[k].bbox);
        let e = whole.entry(r).or_insert((0, b));
        e.0 += 1;
        e.1 = (e.1.0.min(b.0), e.1.1.min(b.1), e.1.2.max(b.2), e.1.3.max(b.3));
    }
    let mut out = std::collections::HashMap::new();
    for &k in &gratings {
        let r = root(&mut parent, k);
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

/// Whether gratings of these (wavelength, angle) could be confused: the same
/// angle (within 1°) and wavelengths that differ, by less than [`WAVELENGTH_WARN_MM`].
fn confusable(la: f64, ta: f64, lb: f64, tb: f64) -> bool {
    let turn = (ta - tb).rem_euclid(180.0);
    let d = (la - lb).abs();
    !(1.0..=179.0).contains(&turn) && d > 1e-9 && d < WAVELENGTH_WARN_MM
}

/// T0401 and T0402: distinct gratings within [`ADJACENT_MM`] of each other
/// whose textures can be confused, one diagnostic per pair (at the later
/// feature). Features are grouped by texture, and only groups that can be
/// confused are searched, so a drawing whose textures all differ well (the
/// automatic style sheet's) costs one pass over its gratings.
fn confusable_gratings(f: &[Feature], diags: &mut Vec<Diagnostic>) {
    let mut textures: Vec<((f64, f64), Vec<usize>)> = Vec::new();
    for (i, x) in f.iter().enumerate() {
        if let FeatureKind::Grating { wavelength_mm, angle_deg } = x.kind {
            match textures
                .iter_mut()
                .find(|(t, _)| t.0.to_bits() == wavelength_mm.to_bits() && t.1.to_bits() == angle_deg.to_bits())
            {
                Some((_, members)) => members.push(i),
                None => textures.push(((wavelength_mm, angle_deg), vec![i])),
            }
        }
    }
    let mut found: Vec<(usize, usize, f64)> = Vec::new();
    for (p, ((la, ta), ps)) in textures.iter().enumerate() {
        for ((lb, tb), qs) in &textures[p + 1..] {
            if !confusable(*la, *ta, *lb, *tb) {
                continue;
            }
            let qboxes: Vec<_> = qs.iter().map(|&q| f[q].bbox).collect();
            let qindex = spatial::BoxIndex::new(&qboxes);
            for &i in ps {
                for k in qindex.meeting(spatial::grow(f[i].bbox, ADJACENT_MM)) {
                    let (a, b) = (i.min(qs[k]), i.max(qs[k]));
                    if f[a].elem != f[b].elem {
                        let g = gap(&f[a], &f[b], ADJACENT_MM, |r, stop| {
                            spatial::min_outline_distance(&f[a].outline, &f[b].outline, r, stop)
                        });
                        if g <= ADJACENT_MM {
                            found.push((a, b, g));
                        }
                    }
                }
            }
        }
    }
    found.sort_unstable_by_key(|&(a, b, _)| (a, b));
    for (a, b) in found.into_iter().map(|(a, b, _)| (&f[a], &f[b])) {
        let (FeatureKind::Grating { wavelength_mm: la, .. }, FeatureKind::Grating { wavelength_mm: lb, .. }) =
            (a.kind, b.kind)
        else {
            continue;
        };
        let d = (la - lb).abs();
        let msg =
            format!("adjacent gratings #{} ({la} mm) and this one ({lb} mm) differ by {d:.2} mm in wavelength", a.name);
        let diag = if d < WAVELENGTH_ERROR_MM {
            Diagnostic::error("T0401", format!("{msg}; readers cannot tell them apart"))
        } else {
            Diagnostic::warning("T0402", format!("{msg}; readers may confuse them"))
        };
        diags.push(at(
            diag.with_help(
                "make neighbouring wavelengths differ by 3 mm or more (2 mm and 6 mm work well), or change the angle",
            ),
            b,
        ));
    }
}

/// For each feature, its nearest feature of another element whose footprint
/// comes closer than [`MIN_GAP_MM`] without touching it (a gap above 0), and
/// that gap; `None` when there is none. Among equal gaps the first feature
/// is named.
///
/// Two passes, because a dense drawing's neighbours come in two kinds. The
/// pairs whose boxes meet (a plan's crossing ways, a map's bordering
/// regions) are mostly touching; each is measured once, for both of its
/// features, up to the larger of their nearest gaps so far. The pairs whose
/// boxes do not meet are then searched from each feature in turn, nearest
/// box first, measured only up to that feature's nearest gap, and the search
/// stops at the first box farther than it (the distance between boxes bounds
/// the gap from below). Measuring those once for both as well (up to the
/// larger nearest gap, the whole [`MIN_GAP_MM`] for a feature not yet
/// reached) made the 45,000-region map measure every pair within 3.2 mm in
/// full; searching the meeting pairs from each side measured a dense plan's
/// touching pairs twice. Every pair is measured with its lower position
/// first, so both sides see the same gap to the bit.
///
/// Both passes run in parallel and visit the features along a Hilbert curve
/// ([`spatial::locality_order`]), whose outlines are laid out in memory in
/// the same order: a feature's neighbours were mostly read for the feature
/// before, and in document order each one was a cache miss (most of the
/// time the gap rule took on a 10,000-way plan). In the first pass, pairs
/// are shared out by feature (each pair goes with the one that comes first
/// on the curve), and the nearest gaps found so far are shared between the
/// threads as bounds that only ever go down: a bound only decides how far a
/// pair is measured, and a pair is kept only when it is measured exactly
/// (up to the larger of its features' bounds, which are never below their
/// final nearest gaps). The kept gaps are then taken in for each feature
/// as the smallest (the first feature among equal ones), which does not
/// depend on the order they come in, so neither does the outcome depend on
/// how the threads share the work.
///
/// The first pass calls `on_meet(i, j, out)` for every pair `i < j` whose
/// boxes meet and that are not one layer (whose overlaps need a look); what
/// it adds to `out` is returned in order of `i` then `j`.
fn nearest_gaps<D: Send>(
    f: &[Feature],
    index: &spatial::BoxIndex,
    textures: &Textures,
    on_meet: impl Fn(usize, usize, &mut Vec<D>) + Sync,
) -> (Vec<Option<(usize, f64)>>, Vec<D>) {
    let boxes: Vec<_> = f.iter().map(|x| x.bbox).collect();
    let order = spatial::locality_order(&boxes);
    let mut rank = vec![0; f.len()];
    for (r, &k) in order.iter().enumerate() {
        rank[k] = r;
    }
    // Gaps are measured between outlines simplified to `GAP_TOLERANCE_MM`:
    // a small circle flattened for the fields has ~100 sides, and a pair of
    // nearby ones costs the product of their counts.
    let simple: Vec<Vec<Polyline>> = f
        .par_iter()
        .map(|x| {
            x.outline
                .iter()
                .map(|p| Polyline { points: simplify(&p.points, p.closed, GAP_TOLERANCE_MM), closed: p.closed })
                .collect()
        })
        .collect();
    let outlines: Vec<&[Polyline]> = simple.iter().map(Vec::as_slice).collect();
    let search = GapSearch {
        f,
        index,
        outlines: spatial::OutlineSet::in_order(&outlines, order.iter().copied()),
        shared: spatial::SharedVertices::new(&outlines),
        probes: f.iter().enumerate().map(|(k, x)| Probe::of(x, textures.get(&k).map(|t| t.0))).collect(),
    };
    let masks: Vec<Option<usize>> = f.iter().map(|x| x.mask).collect();
    // Gaps are above 0, and the bits of positive floats order as the floats do.
    let bounds: Vec<AtomicU64> = f.iter().map(|_| AtomicU64::new(MIN_GAP_MM.to_bits())).collect();
    let bound = |k: usize| f64::from_bits(bounds[k].load(Ordering::Relaxed));
    let found: Vec<Found<D>> = order
        .par_chunks(MEET_CHUNK)
        .map_init(
            || (Vec::new(), Vec::new()),
            |(met, out), chunk| {
                let mut found = Found { gaps: Vec::new(), meets: Vec::new(), near: Vec::new(), covered: Vec::new() };
                for &i in chunk {
                    let a = f[i].bbox;
                    // The boxes apart from this one but nearer than what the
                    // second pass's first ring would look at come from the
                    // same query: by now a dense drawing's features mostly
                    // have a small bound from the neighbours before them.
                    let covered = GAP_RINGS[0].min(bound(i));
                    let before = found.near.len();
                    met.clear();
                    for (j, bj) in index.meeting_boxes(spatial::grow(a, covered)) {
                        if spatial::meet(a, bj) {
                            if rank[j] > rank[i] {
                                met.push(j);
                            }
                        } else if search.probes[j].distinct(&search.probes[i]) {
                            let d = spatial::box_distance(bj, a);
                            if d < covered {
                                found.near.push((d, j));
                            }
                        }
                    }
                    found.covered.push((covered, found.near.len() - before));
                    for &j in met.iter() {
                        let (p, q) = (i.min(j), i.max(j));
                        if !(masks[p].is_some() && masks[p] == masks[q]) {
                            on_meet(p, q, out);
                            found.meets.extend(out.drain(..).map(|d| (p, q, d)));
                        }
                        if search.probes[p].distinct(&search.probes[q]) {
                            let reach = bound(p).max(bound(q));
                            let g = search.measure(p, q, reach);
                            if g > 0.0 && g <= reach {
                                found.gaps.push((p, q, g));
                                bounds[p].fetch_min(g.to_bits(), Ordering::Relaxed);
                                bounds[q].fetch_min(g.to_bits(), Ordering::Relaxed);
                            }
                        }
                    }
                }
                found
            },
        )
        .collect();
    let mut best: Vec<Option<(usize, f64)>> = vec![None; f.len()];
    let (mut meets, mut near, mut covered) = (Vec::new(), Vec::new(), Vec::with_capacity(f.len()));
    for x in found {
        for (p, q, g) in x.gaps {
            offer(&mut best[p], q, g);
            offer(&mut best[q], p, g);
        }
        meets.extend(x.meets);
        near.extend(x.near);
        covered.extend(x.covered);
    }
    meets.sort_by_key(|&(p, q, _)| (p, q));
    // Where each feature's candidates apart start in `near` (`covered` is in
    // the order of the curve, as `near` is).
    let mut start = Vec::with_capacity(f.len() + 1);
    start.push(0);
    for &(_, k) in &covered {
        start.push(start[start.len() - 1] + k);
    }
    // Each feature's search of the boxes apart from its own writes only its
    // own result.
    let apart: Vec<Option<(usize, f64)>> = order
        .par_iter()
        .enumerate()
        .map_init(Vec::new, |cands, (k, &i)| {
            let mut b = best[i];
            search.apart(i, &mut b, cands, &near[start[k]..start[k + 1]], covered[k].0);
            b
        })
        .collect();
    for (&i, b) in order.iter().zip(apart) {
        best[i] = b;
    }
    (best, meets.into_iter().map(|(_, _, d)| d).collect())
}

/// What [`nearest_gaps`]'s first pass finds in a piece of the curve.
struct Found<D> {
    /// Pairs `(i, j, gap)` measured exactly, `i < j`, with a gap above 0.
    gaps: Vec<(usize, usize, f64)>,
    /// What `on_meet` added for the pair `(i, j)`.
    meets: Vec<(usize, usize, D)>,
    /// Each feature's candidates for the second pass that the first pass's
    /// query found: `(box distance, position)`, below what it covered.
    near: Vec<(f64, usize)>,
    /// For each feature of the piece, the box distance below which `near`
    /// holds all its candidates, and how many they are.
    covered: Vec<(f64, usize)>,
}

/// Features per piece of work in [`nearest_gaps`]'s first pass: enough that
/// handing pieces out costs nothing next to measuring them, few enough
/// that the threads stay busy to the end.
const MEET_CHUNK: usize = 32;

/// How far a feature's nearest gap so far leaves its search open.
fn limit(best: Option<(usize, f64)>) -> f64 {
    best.map_or(MIN_GAP_MM, |(_, g)| g)
}

/// Takes gap `g` to feature `k` as `best` when it is a gap (above 0) and
/// nearer (or as near, and `k` first).
fn offer(best: &mut Option<(usize, f64)>, k: usize, g: f64) {
    let nearer = match *best {
        None => g < MIN_GAP_MM,
        Some((m, b)) => g < b || (g == b && k < m),
    };
    if g > 0.0 && nearer {
        *best = Some((k, g));
    }
}

/// The box distances up to which [`GapSearch::apart`] looks for candidates,
/// one ring after another: a dense map gives each feature hundreds of boxes
/// within [`MIN_GAP_MM`], but its nearest gap is most often within the first
/// ring, and taking all of them from the index and sorting them cost as
/// much as measuring the few that matter.
const GAP_RINGS: [f64; 4] = [0.4, 0.8, 1.6, MIN_GAP_MM];

/// What [`nearest_gaps`] searches: the features, an index of their boxes,
/// their outlines prepared for distances, and what a gap needs of each
/// feature side by side in memory (in a dense drawing each feature has
/// hundreds of neighbours, and reading them from the features themselves
/// was a cache miss each).
struct GapSearch<'a> {
    f: &'a [Feature],
    index: &'a spatial::BoxIndex,
    outlines: spatial::OutlineSet,
    /// Which of `outlines` share a vertex (and so touch).
    shared: spatial::SharedVertices,
    probes: Vec<Probe>,
}

/// What [`GapSearch::measure`] reads of a feature for most pairs.
#[derive(Debug, Clone, Copy)]
struct Probe {
    elem: usize,
    /// The first feature of the texture this grating is part of
    /// ([`one_texture`]), or `usize::MAX`.
    texture: usize,
    half_band: f64,
    /// No dots: the gap is between outlines (after a grating's inside).
    dotless: bool,
    /// Outlines only: no dots, and not a grating (whose inside counts).
    plain: bool,
}

impl Probe {
    fn of(f: &Feature, texture: Option<usize>) -> Self {
        let dotless = f.dots.is_empty();
        let plain = dotless && !matches!(f.kind, FeatureKind::Grating { .. });
        Probe { elem: f.elem, texture: texture.unwrap_or(usize::MAX), half_band: f.half_band, dotless, plain }
    }

    /// Whether a gap between these two is one to feel: they are distinct
    /// elements, and not two parts of one texture (what lies between those
    /// is the same texture, so a nearer one must not hide a farther real gap).
    fn distinct(&self, other: &Probe) -> bool {
        self.elem != other.elem && (self.texture == usize::MAX || self.texture != other.texture)
    }
}

impl GapSearch<'_> {
    /// [`gap`] between features `i` and `j`, measured with the lower
    /// position first whichever side asks.
    fn measure(&self, i: usize, j: usize, reach: f64) -> f64 {
        let (p, q) = (i.min(j), i.max(j));
        let (a, b) = (self.probes[p], self.probes[q]);
        // Outlines that share a vertex are 0 apart, within any band: the
        // gap is at most 0 (a grating's inside would only make it 0), and
        // every rule treats such gaps alike. On a map most neighbours share
        // a border, and finding the first close segments of each pair
        // (measuring up to the nearest gaps, often the whole 3.2 mm, so
        // scanning most segment pairs before reaching the border) was most
        // of the gap rule's time.
        if a.dotless && b.dotless && a.half_band + b.half_band >= 0.0 && self.shared.share(p, q) {
            return 0.0;
        }
        if a.plain && b.plain {
            // `gap` for two outlines, without reading the features.
            let bands = a.half_band + b.half_band;
            return self.outlines.distance(p, q, reach + bands, bands) - bands;
        }
        gap(&self.f[p], &self.f[q], reach, |r, stop| self.outlines.distance(p, q, r, stop))
    }

    /// Lowers feature `i`'s nearest gap `best` to the nearest among the
    /// features of other elements whose boxes do not meet its own but lie
    /// within [`MIN_GAP_MM`], ring by ring. The candidates whose box
    /// distance is below `covered` are `near` (the first pass found them);
    /// the rings beyond come from the index. `cands` is scratch space, kept
    /// by the caller across features.
    fn apart(
        &self,
        i: usize,
        best: &mut Option<(usize, f64)>,
        cands: &mut Vec<(f64, usize)>,
        near: &[(f64, usize)],
        covered: f64,
    ) {
        let a = self.f[i].bbox;
        cands.clear();
        cands.extend_from_slice(near);
        if !self.nearest_of(i, best, cands) || best.is_some_and(|(_, g)| g < covered) {
            return;
        }
        let mut inner = covered;
        for ring in GAP_RINGS.into_iter().filter(|&r| r > covered) {
            // The candidates whose box distance lies in [inner, ring), and
            // none beyond the nearest gap so far.
            cands.clear();
            cands.extend(
                self.index
                    .meeting_boxes(spatial::grow(a, ring.min(limit(*best))))
                    .filter(|&(j, bj)| self.probes[j].distinct(&self.probes[i]) && !spatial::meet(a, bj))
                    .map(|(j, bj)| (spatial::box_distance(bj, a), j))
                    .filter(|&(d, _)| d >= inner && d < ring),
            );
            // Every candidate of the rings beyond lies at least `ring` away.
            if !self.nearest_of(i, best, cands) || best.is_some_and(|(_, g)| g < ring) {
                return;
            }
            inner = ring;
        }
    }

    /// Measures `cands` (`(box distance, position)`) against feature `i`
    /// nearest box first, lowering `best`, until the next box lies farther
    /// than the nearest gap; whether the search should go on (every
    /// candidate was measured).
    fn nearest_of(&self, i: usize, best: &mut Option<(usize, f64)>, cands: &mut [(f64, usize)]) -> bool {
        cands.sort_unstable_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)));
        for &(lower, j) in cands.iter() {
            if let Some((m, g)) = *best
                && (lower > g || (lower == g && j > m))
            {
                // Every later candidate lies farther (or as far and later).
                return false;
            }
            let g = self.measure(i, j, limit(*best));
            offer(best, j, g);
        }
        true
    }
}

/// The gap between two features' footprints (≤ 0 when they touch or overlap),
/// exact when it is at most `reach`; otherwise some value above `reach`.
/// `outline_distance(reach, stop_at)` is [`spatial::min_outline_distance`]
/// between the two outlines (prepared once for all pairs in [`nearest_gaps`]).
fn gap(a: &Feature, b: &Feature, reach: f64, outline_distance: impl FnOnce(f64, f64) -> f64) -> f64 {
    // A feature inside a filled region overlaps it, whatever the distance to its outline.
    for (r, o) in [(a, b), (b, a)] {
        if let FeatureKind::Grating { .. } = r.kind {
            let p = o.dots.first().map(|d| (d.0, d.1)).or(o.outline.first().and_then(|p| p.points.first().copied()));
            if p.is_some_and(|p| contains(&r.outline, p, FillRule::NonZero)) {
                return 0.0;
            }
        }
    }
    match (a.dots.is_empty(), b.dots.is_empty()) {
        (true, true) => {
            // Outlines that touch or cross need no exact distance: every rule treats them alike.
            let bands = a.half_band + b.half_band;
            outline_distance(reach + bands, bands) - bands
        }
        (false, true) | (true, false) => {
            let (d, m) = if a.dots.is_empty() { (b, a) } else { (a, b) };
            // A dot's gap is at most `reach` when its centre is within
            // `reach` plus its radius and the band of the outline.
            // A dot that reaches into the outline's band settles the gap at
            // or below 0, and every rule treats such gaps alike.
            let mut best = f64::INFINITY;
            for &(x, y, r) in &d.dots {
                let within = |stop| distance_to_outline_within(&m.outline, (x, y), reach + r + m.half_band, stop);
                let touch = r + m.half_band;
                let mut dist = within(touch);
                if dist <= touch && dist - r - m.half_band > 0.0 {
                    // Stopped at a distance that rounds to a gap above 0:
                    // the exact one decides.
                    dist = within(f64::NEG_INFINITY);
                }
                best = best.min(dist - r - m.half_band);
                if best <= 0.0 {
                    break;
                }
            }
            best
        }
        (false, false) => {
            let mut best = f64::INFINITY;
            near_dot_pairs(a, b, MIN_GAP_MM, |p, q| best = best.min(dist((p.0, p.1), (q.0, q.1)) - p.2 - q.2));
            best
        }
    }
}

/// Calls `f` for every pair of dots (one of `a`, one of `b`) whose discs come
/// within `reach` of each other, using a grid so the work stays near linear.
fn near_dot_pairs(a: &Feature, b: &Feature, reach: f64, mut f: impl FnMut((f64, f64, f64), (f64, f64, f64))) {
    let rmax = a.dots.iter().chain(&b.dots).map(|d| d.2).fold(0.0, f64::max);
    let cell = (2.0 * rmax + reach).max(1e-3);
    let key = |x: f64, y: f64| ((x / cell).floor() as i64, (y / cell).floor() as i64);
    let mut grid: std::collections::HashMap<(i64, i64), Vec<usize>> = std::collections::HashMap::new();
    for (i, d) in b.dots.iter().enumerate() {
        grid.entry(key(d.0, d.1)).or_default().push(i);
    }
    for &p in &a.dots {
        let (kx, ky) = key(p.0, p.1);
        for x in kx - 1..=kx + 1 {
            for y in ky - 1..=ky + 1 {
                for &j in grid.get(&(x, y)).into_iter().flatten() {
                    f(p, b.dots[j]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gap_below_the_limit_never_reads_as_the_limit() {
        assert_eq!(below(1.74, MIN_GAP_MM), "1.7");
        assert_eq!(below(3.17, MIN_GAP_MM), "3.17");
        assert_eq!(below(3.1999, MIN_GAP_MM), "3.199");
        assert_eq!(below(3.198, MIN_GAP_MM), "3.198");
    }

    /// A deterministic sequence in [0, 1) (a linear congruential generator).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (self.0 >> 33) as f64 / (1u64 << 31) as f64
        }
    }

    /// A random drawing: vibrating outlines (closed and open), gratings and
    /// dotted features, some of them parts of one element, packed closely
    /// enough that many touch, cross or lie inside each other.
    fn random_features(seed: u64, n: usize) -> Vec<Feature> {
        let mut r = Lcg(seed);
        (0..n)
            .map(|k| {
                let (cx, cy) = (r.next() * 60.0, r.next() * 40.0);
                let size = 0.5 + r.next() * 6.0;
                let sides = 3 + (r.next() * 5.0) as usize;
                let turn = r.next() * 6.3;
                let points: Vec<(f64, f64)> = (0..sides)
                    .map(|s| {
                        let a = turn + s as f64 * std::f64::consts::TAU / sides as f64;
                        let rad = size * (0.5 + r.next());
                        (cx + rad * a.cos(), cy + rad * a.sin())
                    })
                    .collect();
                let (kind, half_band, closed) = match k % 4 {
                    0 => (FeatureKind::Vibrate { width_mm: 1.5, freq_hz: 40.0 }, 0.75, true),
                    1 => (FeatureKind::Vibrate { width_mm: 1.0, freq_hz: 40.0 }, 0.5, false),
                    2 => (FeatureKind::Grating { wavelength_mm: 4.0, angle_deg: 0.0 }, 0.0, true),
                    _ => (FeatureKind::Dot { radius_mm: 0.6 }, 0.0, false),
                };
                let (outline, dots) = if k % 4 == 3 {
                    (Vec::new(), points.iter().map(|p| (p.0, p.1, 0.6)).collect::<Vec<_>>())
                } else {
                    (vec![Polyline { points, closed }], Vec::new())
                };
                let bbox = if dots.is_empty() {
                    let b = crate::geometry::bounds(&outline).unwrap();
                    spatial::grow(b, half_band)
                } else {
                    dots.iter().fold((f64::MAX, f64::MAX, f64::MIN, f64::MIN), |b, d| {
                        (b.0.min(d.0 - d.2), b.1.min(d.1 - d.2), b.2.max(d.0 + d.2), b.3.max(d.1 + d.2))
                    })
                };
                Feature {
                    // Every seventh feature is a second style of the element before it.
                    elem: if k % 7 == 6 { k - 1 } else { k },
                    name: format!("f{k}"),
                    line: 1,
                    kind,
                    outline,
                    half_band,
                    dots,
                    bbox,
                    mask: None,
                    amplitude: 1.0,
                }
            })
            .collect()
    }

    /// The exact gap between two features, every segment pair measured.
    fn reference_gap(a: &Feature, b: &Feature) -> f64 {
        gap(a, b, 1e9, |r, stop| spatial::min_outline_distance(&a.outline, &b.outline, r, stop))
    }

    #[test]
    fn nearest_gaps_are_those_of_an_all_pairs_scan() {
        // Without textures, then with every grating one style, so that those
        // that touch are one texture and a nearer part of one's own texture
        // must not hide a farther gap to something else.
        for (seed, one_style) in [(1, false), (2, false), (3, false), (1, true), (2, true), (3, true)] {
            let mut f = random_features(seed, 300);
            if one_style {
                for x in f.iter_mut().filter(|x| matches!(x.kind, FeatureKind::Grating { .. })) {
                    x.mask = Some(0);
                }
            }
            let textures = one_texture(&f);
            let texture = |k: usize| textures.get(&k).map(|t| t.0);
            let one = |i: usize, j: usize| texture(i).is_some() && texture(i) == texture(j);
            let boxes: Vec<_> = f.iter().map(|x| x.bbox).collect();
            let got = nearest_gaps(&f, &spatial::BoxIndex::new(&boxes), &textures, |_, _, _: &mut Vec<()>| {}).0;
            let (mut reported, mut hidden) = (0, 0);
            for (j, b) in f.iter().enumerate() {
                // Every other feature, its exact gap with no reach to cut it short.
                let nearest = |keep: &dyn Fn(usize) -> bool| {
                    (0..f.len())
                        .filter(|&i| f[i].elem != b.elem && keep(i))
                        .map(|i| (reference_gap(&f[i], b), i))
                        .filter(|&(g, _)| g > 0.0 && g < MIN_GAP_MM)
                        .min_by(|p, q| p.0.total_cmp(&q.0))
                };
                let want = nearest(&|i| !one(i, j)).map(|(g, _)| g);
                if nearest(&|_| true).is_some_and(|(_, i)| one(i, j)) {
                    hidden += 1;
                }
                match (got[j], want) {
                    (None, None) => {}
                    (Some((i, g)), Some(w)) => {
                        reported += 1;
                        assert!((g - w).abs() < 1e-12, "seed {seed}, f{j}: nearest gap {g}, all pairs {w}");
                        assert!(f[i].elem != b.elem && !one(i, j));
                        assert!(
                            (reference_gap(&f[i], b) - g).abs() < 1e-12,
                            "seed {seed}, f{j}: #f{i} is not {g} away"
                        );
                    }
                    (g, w) => panic!("seed {seed}, f{j}: nearest {g:?}, all pairs {w:?}"),
                }
            }
            // The drawing is dense enough that the rule has something to find,
            // and, with one style, that textures hide nearer gaps.
            assert!(reported > 30, "seed {seed}: only {reported} features have a near neighbour");
            assert_eq!(hidden > 0, one_style, "seed {seed}: {hidden} nearest gaps within a texture");
        }
    }

    #[test]
    fn nearest_gaps_do_not_depend_on_how_many_threads_share_the_work() {
        let f = random_features(4, 600);
        let boxes: Vec<_> = f.iter().map(|x| x.bbox).collect();
        let index = spatial::BoxIndex::new(&boxes);
        // Every pair whose boxes meet, as the overlap checks see them.
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                nearest_gaps(&f, &index, &Textures::default(), |i, j, out: &mut Vec<(usize, usize)>| out.push((i, j)))
            })
        };
        let (gaps, meets) = run(1);
        assert!(gaps.iter().filter(|g| g.is_some()).count() > 50);
        let mut sorted = meets.clone();
        sorted.sort_unstable();
        assert_eq!(meets, sorted, "pairs are reported in order");
        assert_eq!(meets, spatial::near_pairs(&boxes, 0.0), "every pair whose boxes meet, once");
        for threads in [2, 3, 8] {
            let (g, m) = run(threads);
            assert_eq!(m, meets, "{threads} threads");
            for (k, (a, b)) in g.iter().zip(&gaps).enumerate() {
                assert_eq!(
                    a.map(|(i, g)| (i, g.to_bits())),
                    b.map(|(i, g)| (i, g.to_bits())),
                    "f{k}, {threads} threads"
                );
            }
        }
    }

    /// A filled square of its own element, `(x, y)` its lower corner.
    fn square(k: usize, x: f64, y: f64, side: f64) -> Feature {
        let points = vec![(x, y), (x + side, y), (x + side, y + side), (x, y + side)];
        Feature {
            elem: k,
            name: format!("f{k}"),
            line: 1,
            kind: FeatureKind::Grating { wavelength_mm: 4.0, angle_deg: 0.0 },
            outline: vec![Polyline { points, closed: true }],
            half_band: 0.0,
            dots: Vec::new(),
            bbox: (x, y, x + side, y + side),
            mask: None,
            amplitude: 1.0,
        }
    }

    #[test]
    fn among_equal_gaps_the_first_feature_is_named_whichever_pass_finds_it() {
        // Feature 1 has a neighbour 1 mm away on each side: the later one
        // (2) at the left, the earlier one (0) at the right, both with boxes
        // apart from its own; and 3, a square 1.5 mm above 1 whose box is
        // stretched down to meet 1's, 0's and 2's (a box only bounds the
        // gap from below, and boxes that meet are measured in the other pass).
        let f = vec![square(0, 13.0, 0.0, 2.0), square(1, 10.0, 0.0, 2.0), square(2, 7.0, 0.0, 2.0), {
            let mut x = square(3, 9.0, 3.5, 4.0);
            x.bbox = (9.0, 1.9, 13.0, 7.5);
            x
        }];
        let boxes: Vec<_> = f.iter().map(|x| x.bbox).collect();
        let got = nearest_gaps(&f, &spatial::BoxIndex::new(&boxes), &Textures::default(), |_, _, _: &mut Vec<()>| {}).0;
        assert_eq!(got[1], Some((0, 1.0)));
        assert_eq!(got[0], Some((1, 1.0)));
        assert_eq!(got[2], Some((1, 1.0)));
        // 3's nearest is 1, found through boxes that meet; 0's corner is as far (1.5 mm), and first.
        assert_eq!(got[3], Some((0, 1.5)));
        // With 0 and 2 gone, 1's nearest is 3, through boxes that meet.
        let f = vec![f[1].clone(), f[3].clone()];
        let boxes: Vec<_> = f.iter().map(|x| x.bbox).collect();
        assert_eq!(
            nearest_gaps(&f, &spatial::BoxIndex::new(&boxes), &Textures::default(), |_, _, _: &mut Vec<()>| {}).0[0],
            Some((1, 1.5))
        );
    }

    /// Over [`MAX_MEETING_PAIRS`] (here a cap of 1,000), the rules between
    /// features are left out with one T0412 that says why; under it, the
    /// same features are checked pair by pair.
    #[test]
    fn a_drawing_too_dense_for_the_rules_between_elements_says_so() {
        // 60 squares, each 0.5 mm right of the last: every box meets every
        // other (1,770 pairs), and each square's nearest gap is to nobody
        // (they overlap) but the overlaps are pairs to check.
        let f: Vec<Feature> = (0..60).map(|k| square(k, k as f64 * 0.5, 0.0, 40.0)).collect();
        let textures = Textures::default();
        let mut capped = Vec::new();
        let meets = pairs_within(&f, &textures, &mut capped, 1_000);
        assert!(meets.is_empty());
        let dense: Vec<_> = capped.iter().filter(|d| d.code == "T0412").collect();
        assert_eq!(dense.len(), 1, "{capped:?}");
        assert!(dense[0].message.contains("1770 pairs of its 60 elements"), "{}", dense[0].message);
        let mut checked = Vec::new();
        let meets = pairs_within(&f, &textures, &mut checked, usize::MAX);
        assert_eq!(meets.len(), 60 * 59 / 2);
        assert!(checked.iter().all(|d| d.code != "T0412"));
    }

    /// The estimate of meeting pairs is the count of an all-pairs scan when
    /// every box is sampled, and close to it when a sample stands for them.
    #[test]
    fn meeting_pairs_are_counted_from_a_sample_of_the_boxes() {
        for (seed, n) in [(3, 300), (5, 3_000)] {
            let f = random_features(seed, n);
            let boxes: Vec<_> = f.iter().map(|x| x.bbox).collect();
            let index = spatial::BoxIndex::new(&boxes);
            let all = (0..n)
                .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
                .filter(|&(i, j)| spatial::meet(boxes[i], boxes[j]))
                .count();
            let est = meeting_pairs(&index, &boxes);
            if n <= DENSITY_SAMPLE {
                assert_eq!(est, all);
            } else {
                assert!((est as f64 - all as f64).abs() <= 0.1 * all as f64, "estimated {est}, counted {all}");
            }
        }
    }
}
