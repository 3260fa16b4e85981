//! What the automatic sheet tells the reader of a build: the notes on
//! textures shared or given up, lines and marks left out and labels keyed,
//! why nothing was made, and the summary of styles (T0330).

use std::collections::BTreeMap;

use taxel_format::DeviceProfile;

use super::keys::{KEY_SHOWN, KeyCode};
use super::{FAINT_SHARE, LIGHT_GUIDE, LeftOut, MARK_SPACING_MM, MAX_TEXTURES, Plan, min_region_mm, plan};
use crate::annotation::Style;
use crate::diagnostic::Diagnostic;
use crate::drawing::{Drawing, StyledBy};

impl LeftOut {
    /// What it says in a message.
    pub fn describe(self) -> &'static str {
        match self {
            LeftOut::Hidden => "hidden",
            LeftOut::Empty => "empty",
            LeftOut::OffPage => "off the page",
            LeftOut::ClippedAway => "clipped or masked away",
            LeftOut::Background => "page background(s)",
            LeftOut::Unpainted => "with no visible fill or stroke (white, transparent or none)",
            LeftOut::SmallShape => "small shape(s) (glyph outlines, slivers)",
            LeftOut::TextDoesNotFit => "text whose braille does not fit",
            LeftOut::Image => "image(s)",
            LeftOut::Faint => "faint grey line(s)",
            LeftOut::Crowded => "mark(s) too crowded to feel apart",
            LeftOut::Thinned { .. } => "tick label(s) thinned to an even step",
        }
    }
}

/// Why the automatic sheet made nothing of `d`, when it made nothing: how
/// many elements it left out for which reason, most first (`3 hidden, 2
/// images`), for the error that says nothing tactile was found. `None` when
/// it styled something (then the layers say why nothing was made).
pub fn nothing_made(d: &Drawing, profile: &DeviceProfile) -> Option<String> {
    let plan = plan(d, profile);
    if (0..d.elements.len()).any(|i| !plan.styles(i).is_empty()) {
        return None;
    }
    // An element the sheet did not decide was styled by an annotation or a sheet: as nothing.
    let mut why: BTreeMap<&str, usize> = BTreeMap::new();
    for dec in &plan.decisions {
        *why.entry(dec.left_out.map_or("annotated `none`", LeftOut::describe)).or_default() += 1;
    }
    let mut why: Vec<(&str, usize)> = why.into_iter().collect();
    why.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
    Some(match d.elements.len() {
        0 => "the drawing has no elements that are drawn".into(),
        n => format!(
            "the automatic style sheet left out all {n} element(s): {}",
            why.iter().map(|(w, k)| format!("{k} {w}")).collect::<Vec<_>>().join(", ")
        ),
    })
}

/// A fill for messages: `#rrggbb`, or `a gradient`.
pub fn fill_name(f: Option<[u8; 3]>) -> String {
    f.map_or("a gradient or pattern".into(), |c| format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2]))
}

/// Up to three names, then how many more.
fn first_three(names: &[String]) -> String {
    let mut s = names.iter().take(3).cloned().collect::<Vec<_>>().join(", ");
    if names.len() > 3 {
        s += &format!(" and {} more", names.len() - 3);
    }
    s
}

/// The automatic sheet's notes on `plan` for drawing `d`, in the order a
/// reader meets them: fills left as outlines, textures shared, borders,
/// faint strokes, keyed labels, crowded marks, thinned ticks and text left
/// out.
pub(super) fn notes(plan: &Plan, d: &Drawing, diags: &mut Vec<Diagnostic>) {
    let notes = [
        outlines_only(plan),
        shared_textures(plan),
        borders_left_out(plan, d),
        faint_strokes(plan),
        keyed_labels(plan, d),
        crowded_marks(plan, d),
        thinned_ticks(plan, d),
        text_left_out(plan, d),
    ];
    diags.extend(notes.into_iter().flatten());
}

/// The fills that became outlines because too many textures would touch (T0321).
fn outlines_only(plan: &Plan) -> Option<Diagnostic> {
    let dropped: Vec<String> = plan.fills.iter().filter(|f| f.texture.is_none()).map(|f| fill_name(f.fill)).collect();
    if dropped.is_empty() {
        return None;
    }
    Some(
        Diagnostic::note(
            "T0321",
            format!(
                "{} fill colour(s) became outlines only, because more than {MAX_TEXTURES} textures would be needed where they touch: {}",
                dropped.len(),
                first_three(&dropped)
            ),
        )
        .with_help("give them textures in a style sheet (start from `taxel style auto INPUT`), or split the drawing"),
    )
}

/// The textures shared by fills whose regions do not touch (T0322).
fn shared_textures(plan: &Plan) -> Option<Diagnostic> {
    // One note for every texture that is shared: a note per texture would be
    // grouped into one line naming a single texture for all of them.
    let shared: Vec<String> = plan
        .textures
        .iter()
        .enumerate()
        .filter_map(|(t, g)| {
            let sharing: Vec<String> =
                plan.fills.iter().filter(|f| f.texture == Some(t)).map(|f| fill_name(f.fill)).collect();
            (sharing.len() > 1)
                .then(|| format!("{} share grating({} mm, {}°)", first_three(&sharing), g.wavelength_mm, g.angle_deg))
        })
        .collect();
    if shared.is_empty() {
        return None;
    }
    Some(Diagnostic::note("T0322", format!("fills whose regions do not touch share textures: {}", shared.join("; "))))
}

/// The borders left out between regions of one fill too small for them (T0324).
fn borders_left_out(plan: &Plan, d: &Drawing) -> Option<Diagnostic> {
    if plan.too_small.is_empty() {
        return None;
    }
    let names: Vec<String> = plan.too_small.iter().map(|&i| format!("#{}", d.elements[i].name)).collect();
    Some(
        Diagnostic::note(
            "T0324",
            format!(
                "the borders between {} region(s) of one fill are left out, so they are felt as one texture: most are under {:.1} mm across, where a {} mm border would cover most of each ({})",
                names.len(),
                min_region_mm(plan.outline.width_mm),
                plan.outline.width_mm,
                first_three(&names)
            ),
        )
        .with_help("to feel them apart, take part of the drawing with --region so they are larger, or give them colours of their own"),
    )
}

/// The faint grey strokes left out, as a chart's grid lines (T0325).
fn faint_strokes(plan: &Plan) -> Option<Diagnostic> {
    let faint = plan.decisions.iter().filter(|dec| dec.faint).count();
    if faint == 0 {
        return None;
    }
    let colours: Vec<String> = plan.faint.iter().map(|&c| fill_name(Some(c))).collect();
    let first = plan.faint.first().map_or_else(|| "#dddddd".to_string(), |&c| fill_name(Some(c)));
    Some(
        Diagnostic::note(
            "T0325",
            format!(
                "{faint} faint grey stroke(s) left out ({}): less than {:.0} % as dark as the darkest lines ({}), or as light as {}, as a chart's grid lines are, so the axes and the data are felt rather than the grid",
                first_three(&colours),
                FAINT_SHARE * 100.0,
                fill_name(plan.darkest),
                fill_name(Some([LIGHT_GUIDE; 3])),
            ),
        )
        .with_help(format!(
            "to feel them, weaker than the other lines, use a style sheet with a rule `stroke = \"{first}\"`, `tactile = \"vibrate(amplitude: 0.5)\"` (start from `taxel style auto INPUT`)"
        )),
    )
}

/// The labels too long for their place, written as key codes (T0326).
fn keyed_labels(plan: &Plan, d: &Drawing) -> Option<Diagnostic> {
    let mut key: BTreeMap<KeyCode, &str> = BTreeMap::new();
    for (dec, e) in plan.decisions.iter().zip(&d.elements) {
        if let Some(code) = dec.key {
            key.insert(code, &e.label);
        }
    }
    if key.is_empty() {
        return None;
    }
    let shown: Vec<String> = key
        .iter()
        .take(KEY_SHOWN)
        .map(|(c, label)| format!("{} {}", String::from_utf8_lossy(c), crate::diagnostic::quoted(label)))
        .collect();
    let more = if key.len() > KEY_SHOWN { format!(" and {} more", key.len() - KEY_SHOWN) } else { String::new() };
    Some(
        Diagnostic::note(
            "T0326",
            format!(
                "{} label(s) too long for their place are written as two-letter key codes: {}{more}",
                key.len(),
                shown.join("; ")
            ),
        )
        .with_help("a keyed label's words are its name in the bundle, said when the finger is on it; the whole key is the bundle's provenance entry `key` (`taxel unpack` lists it) and a Dot Pad's text line"),
    )
}

/// The marks left out, too crowded to feel apart (T0327).
fn crowded_marks(plan: &Plan, d: &Drawing) -> Option<Diagnostic> {
    let crowded = left_out_names(plan, d, LeftOut::Crowded);
    if crowded.is_empty() {
        return None;
    }
    let kept = plan.decisions.iter().filter(|dec| dec.mark).count();
    Some(
        Diagnostic::note(
            "T0327",
            format!(
                "{} mark(s) left out, too crowded to feel apart: {kept} dot(s) are kept, an even sample with centres at least {MARK_SPACING_MM:.1} mm apart ({})",
                crowded.len(),
                first_three(&crowded)
            ),
        )
        .with_help("to feel more of them, take part of the drawing with --region so they spread out, or draw a density texture (a grating) in a style sheet"),
    )
}

/// The tick labels left out where an axis was thinned (T0328).
fn thinned_ticks(plan: &Plan, d: &Drawing) -> Option<Diagnostic> {
    // One note for every axis thinned (the steps named), so that grouped
    // output, which shows one message a code, loses none of them.
    let (mut thinned, mut steps) = (Vec::new(), Vec::new());
    for (dec, e) in plan.decisions.iter().zip(&d.elements) {
        if let Some(LeftOut::Thinned { every }) = dec.left_out {
            thinned.push(format!("#{}", e.name));
            if !steps.contains(&every) {
                steps.push(every);
            }
        }
    }
    if thinned.is_empty() {
        return None;
    }
    steps.sort_unstable();
    let nth = |n: &u8| if *n == 2 { "every other one".to_string() } else { format!("every {n}th") };
    let steps: Vec<String> = steps.iter().map(nth).collect();
    Some(
        Diagnostic::note(
            "T0328",
            format!(
                "{} tick label(s) left out: axes whose labels' braille would run together were thinned to {}, so that the labels kept stand clear of each other ({})",
                thinned.len(),
                steps.join(" or "),
                first_three(&thinned)
            ),
        )
        .with_help("to feel every label, take part of the chart with --region, or use a larger surface"),
    )
}

/// The text elements left out because their braille does not fit (T0323).
fn text_left_out(plan: &Plan, d: &Drawing) -> Option<Diagnostic> {
    let text = left_out_names(plan, d, LeftOut::TextDoesNotFit);
    if text.is_empty() {
        return None;
    }
    Some(
        Diagnostic::note(
            "T0323",
            format!(
                "{} text element(s) have no room on the graphic, so the key lists them instead: their braille would leave the page, or run into other braille or a vibrating line ({})",
                text.len(),
                first_three(&text)
            ),
        )
        .with_help("braille cells are 6.2 mm wide: shorten the labels, or take part of the drawing with --region"),
    )
}

/// The names (`#id`) of the elements of `d` that `plan` left out for `why`.
fn left_out_names(plan: &Plan, d: &Drawing, why: LeftOut) -> Vec<String> {
    plan.decisions
        .iter()
        .zip(&d.elements)
        .filter(|(dec, _)| dec.left_out == Some(why))
        .map(|(_, e)| format!("#{}", e.name))
        .collect()
}

/// One note saying how many elements became which tactile style, for any
/// drawing (annotated, styled by a sheet, or automatic).
pub fn summary(d: &Drawing) -> Diagnostic {
    let mut counts: BTreeMap<&'static str, usize> = BTreeMap::new();
    let mut none = 0;
    for e in &d.elements {
        if e.styles.is_empty() {
            none += 1;
        }
        let mut seen: Vec<&'static str> = e.styles.iter().map(Style::name).collect();
        seen.sort_unstable();
        seen.dedup();
        for n in seen {
            *counts.entry(n).or_default() += 1;
        }
    }
    let order = ["vibrate", "grating", "dots", "dot", "brush", "braille"];
    let mut parts: Vec<String> =
        order.iter().filter_map(|n| counts.get(n).map(|c| format!("{c} {n}"))).collect::<Vec<_>>();
    if none > 0 {
        parts.push(format!("{none} left out"));
    }
    let by = if d.elements.iter().any(|e| e.styled_by == StyledBy::Auto) { " (automatic style sheet)" } else { "" };
    Diagnostic::note(
        "T0330",
        format!(
            "{} element(s){by}: {}",
            d.elements.len(),
            if parts.is_empty() { "none".into() } else { parts.join(", ") }
        ),
    )
}
