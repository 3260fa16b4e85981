//! The pipeline: the order of the stages, the family dispatch and the
//! bundle's assembly. Annotated SVG in, a bundle (or a print sheet) and
//! diagnostics out.
//!
//! Stages: 1. [`crate::drawing::resolve`] turns the SVG into the drawing as
//! written (styles, paint, exact geometry in page mm); 2. [`crate::place`]
//! takes `--region`, `--fit` and the crop to the surface; 3. [`crate::style`]
//! styles what no annotation styles (the automatic sheet); 4. the family's
//! back end ([`crate::latero`], [`crate::pins`], [`crate::print`]) makes its
//! layers; 5. [`crate::rules`] checks the design rules; the bundle is
//! assembled last. [`resolve`] is the drawing after stages 1 to 3, the one
//! the layers are built from.
//!
//! ```
//! use taxel_compiler::{CompileOptions, compile_svg};
//! use taxel_format::profiles;
//!
//! let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="60mm" height="40mm" viewBox="0 0 60 40">
//!   <rect x="10" y="10" width="30" height="22" data-tactile="vibrate()"/>
//! </svg>"#;
//! let out = compile_svg(svg, &CompileOptions::new(profiles::builtin("stress2").unwrap()));
//! assert!(out.bundle.is_some(), "{:?}", out.diagnostics);
//! ```

use taxel_format::{Bundle, Manifest};

use crate::Compiled;
use crate::diagnostic::{Diagnostic, Severity, has_errors};
use crate::drawing;
use crate::drawing::Drawing;
use crate::options::{CompileOptions, DEFAULT_PX_PER_MM};
use crate::{latero, place, rules, style};

/// Compiles an annotated SVG for `opts.profile`. A drawing that cannot be
/// compiled gives error diagnostics and no bundle. No panic is reachable
/// from the input; one would be a bug, and it is not caught here (the batch
/// builder catches it at its boundary, so one file cannot stop a batch).
pub fn compile_svg(svg_text: &str, opts: &CompileOptions) -> Compiled {
    compile_svg_with_fonts(svg_text, opts, &|| opts.fonts.clone())
}

/// [`compile_svg`] with the fonts given late: `fonts` is called (once) when
/// the text is about to be laid out, after the XML has been parsed, so that
/// the caller can load them meanwhile on another thread; `opts.fonts` is
/// not used. The `taxel` binary loads the system's fonts this way.
///
/// ```
/// use taxel_compiler::{CompileOptions, compile_svg_with_fonts};
/// use taxel_format::profiles;
///
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="60mm" height="40mm" viewBox="0 0 60 40">
///   <rect x="10" y="10" width="30" height="22" data-tactile="vibrate()"/>
/// </svg>"#;
/// let out = compile_svg_with_fonts(svg, &CompileOptions::new(profiles::builtin("stress2").unwrap()), &|| None);
/// assert!(out.bundle.is_some(), "{:?}", out.diagnostics);
/// ```
pub fn compile_svg_with_fonts(svg_text: &str, opts: &CompileOptions, fonts: drawing::Fonts<'_>) -> Compiled {
    let (mut diagnostics, mut fonts_used, mut extra) = (Vec::new(), Vec::new(), Extra::default());
    let bundle = compile(svg_text, opts, fonts, &mut diagnostics, &mut fonts_used, &mut extra);
    let ok = !has_errors(&diagnostics);
    let (bundle, print) = (bundle.filter(|_| ok), extra.print.filter(|_| ok));
    let key = if ok { extra.key } else { Vec::new() };
    Compiled { bundle, diagnostics, fonts_used, print, key }
}

/// What a compilation makes beside the bundle: a print profile's sheet, or
/// the key's own bundles.
#[derive(Default)]
struct Extra {
    print: Option<crate::print::Sheet>,
    key: Vec<Bundle>,
}

/// The pipeline: resolve → prepare → layers → design rules → bundle (or,
/// for a print profile, the print sheet in `extra`; the key's bundle there
/// too, for the families whose key is a bundle of its own).
fn compile(
    text: &str,
    opts: &CompileOptions,
    fonts: drawing::Fonts<'_>,
    diags: &mut Vec<Diagnostic>,
    fonts_used: &mut Vec<drawing::FontFace>,
    extra: &mut Extra,
) -> Option<Bundle> {
    let px = match opts.resolution_px_per_mm {
        None => DEFAULT_PX_PER_MM,
        Some(r) if r.is_finite() && (0.1..=200.0).contains(&r) => r,
        Some(r) => {
            diags.push(Diagnostic::error(
                "T0204",
                format!("the resolution {r} px/mm is out of range, expected 0.1 to 200"),
            ));
            return None;
        }
    };
    // On the other core, while the drawing is read, liblouis finds and
    // compiles the labels' table, which the style sheet asks for first:
    // reading every table's metadata took 9 ms of one core, after the
    // parse, on a map of 2,000 islands. (A drawing that may hold text only:
    // the rest would have no use for it.)
    let labelled = ["<text", "<flowRoot", "<foreignObject", ":text"].iter().any(|t| text.contains(t));
    let (drawing, ()) = rayon::join(
        || drawing::resolve_into(text, opts, fonts, diags, fonts_used),
        || {
            if labelled {
                crate::braille::warm(opts);
            }
        },
    );
    let mut drawing = drawing?;
    // Styles asked of shapes that are not drawn count as asked (for the T0300 message below).
    let not_drawn = diags.iter().filter(|d| d.code == drawing::NOT_DRAWN).count();
    prepare(&mut drawing, opts, diags);
    if let Some(d) = crate::budget::check(opts.memory.as_ref(), "reading the drawing") {
        diags.push(d);
        return None;
    }
    // Pin displays are legalised from the same drawing into one pin image.
    if opts.profile.family() == taxel_format::Family::Pins {
        return crate::pins::build_bundle(&drawing, opts, diags);
    }
    // Print media are legalised from the same drawing into a sheet of raised marks (no bundle).
    if opts.profile.family() == taxel_format::Family::Print {
        extra.print = crate::print::legalise_with(&drawing, opts, diags);
        return None;
    }
    // The design rules but the overlaps need only the features: they run
    // beside the distance fields, and add their diagnostics after them.
    let (mut built, checked) = latero::build(&drawing, opts, px, diags, |f| rules::check_features(f, &opts.profile));
    if built.is_empty() {
        // A malformed annotation already explains why nothing is tactile.
        if has_errors(diags) {
            return None;
        }
        let any_style = built.styled_elements + not_drawn > 0;
        let d = if any_style {
            nothing_rendered(&drawing, &built, &opts.profile, diags)
        } else {
            // Converted automatically, the drawing had nothing the sheet could make tactile: say what it had.
            let auto = opts.auto || diags.iter().any(|d| d.code == "T0320");
            let why = auto.then(|| style::nothing_made(&drawing, &opts.profile)).flatten();
            let cropped = diags.iter().any(|d| d.code == "T0205");
            let message = match why {
                Some(w) => format!("nothing tactile was found in the drawing: {w}"),
                None if cropped => {
                    "nothing tactile was found on the surface: the annotated shapes are all beyond it".into()
                }
                None => "nothing tactile was found in the drawing".into(),
            };
            // Annotated shapes all cropped away (T0205 says so): the way out
            // is the surface, not annotating.
            let help = if cropped {
                "build with --fit to scale the drawing to the surface, or --region to take the part you annotated"
            } else if drawing.only_pictures() {
                drawing::PICTURES_HELP
            } else {
                "mark shapes with data-tactile=\"vibrate()\" (or grating(), dots(), dot(), braille()), \
                 put them in an Inkscape layer labelled \"tactile: vibrate()\", or map colours with --style FILE \
                 (see docs/annotations.md)"
            };
            Diagnostic::error("T0300", message).with_help(help)
        };
        diags.push(d);
        return None;
    }
    // The key, on the families that have one surface, is a second bundle (SPEC.md 10.2).
    let legend = built.legend.take();
    extra.key = latero::key::bundles(&drawing, legend, opts, px, diags);
    // The drawing is no longer needed: it is freed on another thread while
    // the bundle is put together (on the map at the input limit, freeing its
    // hundred thousand elements took a tenth of a second on the one thread
    // left working).
    // (The bundle is made on this thread, the one that goes on with it.)
    let (bundle, ()) = rayon::join(
        || {
            checked.finish(&built, diags);
            let mut bundle = Bundle::new(Manifest { content_hash: opts.content_hash, ..Manifest::new(opts.profile) });
            bundle.chunks = built.into_chunks();
            bundle
        },
        move || drop(drawing),
    );
    if let Err(e) = bundle.to_bytes() {
        diags.push(Diagnostic::error("T0900", format!("internal error: the bundle does not validate: {e}")));
        return None;
    }
    Some(bundle)
}

/// Prepares `drawing` for `opts` before its layers are built: `--region` and
/// `--fit` and the crop to the surface, then the automatic style sheet where
/// it applies, then the style summary. When an error stops it (a region that
/// cannot be taken) the drawing is emptied, so no layer is built; the error
/// says why. Called by both [`compile_svg`] and [`resolve`], so that
/// `taxel report`'s reference sees the drawing the layers were built from.
pub(crate) fn prepare(drawing: &mut Drawing, opts: &CompileOptions, diags: &mut Vec<Diagnostic>) {
    if !adapt(drawing, opts, diags) {
        drawing.elements.clear();
    }
}

/// The passes between the resolved drawing and its layers that make a
/// drawing as teachers have it usable: `--region` and `--fit` (and cropping to
/// the surface, [`place::apply`]); then the automatic sheet, where
/// `--style auto` asks for it or where nothing else styles the drawing (no
/// annotation, no style sheet; with note T0320); then the note saying how many
/// elements became which style. Returns `false` when an error stops the
/// compilation (a region that cannot be taken).
fn adapt(d: &mut Drawing, opts: &CompileOptions, diags: &mut Vec<Diagnostic>) -> bool {
    // Whether the author annotated the drawing is decided on the whole
    // drawing: annotated shapes that cropping leaves out (beyond the surface,
    // outside `--region`) still make it an annotated drawing, not one for the
    // automatic sheet.
    let annotated = !style::unannotated(d);
    if !place::apply(d, &opts.profile, opts.fit, opts.region.as_ref(), opts.flattening, diags) {
        return false;
    }
    if annotated && style::unannotated(d) {
        diags.push(
            Diagnostic::warning(
                "T0205",
                format!(
                    "every annotated shape lies {} the {} surface: nothing annotated is left to build",
                    if opts.region.is_some() { "outside the region or beyond" } else { "beyond" },
                    opts.profile.name
                ),
            )
            .with_help(
                "build with --fit to scale the drawing to the surface, or --region to take the part you annotated",
            ),
        );
    }
    let implicit = !opts.auto && opts.style.is_none() && !annotated;
    if implicit {
        diags.push(
            Diagnostic::note(
                "T0320",
                "nothing in the drawing is annotated: the automatic style sheet decided its tactile styles",
            )
            .with_help("`taxel style auto INPUT` prints what it decided as a style sheet to start your own from"),
        );
    }
    if opts.auto || implicit {
        style::apply_measured(d, &opts.profile, style::Measure::of(opts), diags);
    }
    diags.push(style::summary(d));
    true
}

/// The drawing of an SVG as the pipeline builds its layers from it:
/// [`drawing::resolve`] (the drawing as written), then prepared for `opts`
/// as [`compile_svg`] prepares it (automatic styles, `--region`, `--fit`).
/// No panic is reachable from the input.
///
/// ```
/// use taxel_compiler::{CompileOptions, pipeline};
/// use taxel_format::profiles;
///
/// // Unannotated: the automatic style sheet styles the rectangle.
/// let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="60mm" height="40mm" viewBox="0 0 60 40">
///   <rect id="box" x="10" y="10" width="30" height="20" fill="#3060c0"/>
/// </svg>"##;
/// let d = pipeline::resolve(svg, &CompileOptions::new(profiles::builtin("stress2").unwrap())).drawing.unwrap();
/// assert!(!d.elements[0].styles.is_empty());
/// ```
pub fn resolve(svg_text: &str, opts: &CompileOptions) -> drawing::Resolved {
    let mut r = drawing::resolve(svg_text, opts);
    if let Some(d) = &mut r.drawing {
        prepare(d, opts, &mut r.diagnostics);
    }
    r
}

/// T0300 when elements asked for styles and nothing was made of them: what
/// was asked, and why nothing was kept (the warnings given with it, or layers that
/// came out empty because opaque fills painted later hide them, or because
/// they lie off the surface), so the message never points at warnings that
/// are not there.
fn nothing_rendered(
    drawing: &drawing::Drawing,
    built: &latero::Built,
    device: &taxel_format::DeviceProfile,
    diags: &[Diagnostic],
) -> Diagnostic {
    let profile = device.name.as_str();
    let names = |ix: &[usize]| {
        let mut s = ix.iter().take(3).map(|&i| format!("#{}", drawing.elements[i].name)).collect::<Vec<_>>().join(", ");
        if ix.len() > 3 {
            s += &format!(" and {} more", ix.len() - 3);
        }
        s
    };
    let mut why = Vec::new();
    let mut help = Vec::new();
    for u in &built.unfelt {
        let n = u.elements.len();
        if u.covered_by.is_empty() {
            why.push(format!("{n} element(s) with {} ({}) cover nothing on the surface", u.style, names(&u.elements)));
        } else {
            why.push(format!(
                "{n} element(s) with {} ({}) lie wholly under opaque fills painted over them ({}), which hide them as on paper",
                u.style,
                names(&u.elements),
                names(&u.covered_by)
            ));
            help.push(format!(
                "{} is drawn after them with an opaque fill (from its attributes, `style` or CSS): \
                 move it before the shapes it covers, or make its fill none or translucent",
                names(&u.covered_by[..1])
            ));
        }
    }
    let warnings = diags.iter().filter(|d| d.severity == Severity::Warning).count();
    let elsewhere = diags.iter().filter(|d| d.code == latero::NOT_ON_DEVICE).count();
    if warnings > 0 {
        why.push(format!("the {warnings} warning(s) given with this error say why"));
    }
    // Every warning a style this family does not play: say what it plays
    // (then what the automatic sheet made of each colour does not matter).
    let other_family = elsewhere == warnings && warnings > 0;
    match device.family() {
        taxel_format::Family::Grid if other_family => help.push(format!(
            "{profile} plays moving strokes: mark the paths to feel with data-tactile=\"brush()\" \
             (docs/annotations.md); outlines, textures, dots and braille, which the automatic style sheet makes, \
             play on laterotactile arrays (stress2) and pin displays (dotpad, monarch, graphiti, hyperbraille)"
        )),
        taxel_format::Family::Finger if other_family => help.push(format!(
            "{profile} plays height meshes: build a relief as .gltf or .glb (docs/finger.md); drawings play on \
             laterotactile arrays (stress2) and pin displays (dotpad, monarch, graphiti, hyperbraille)"
        )),
        _ if warnings > 0 => {
            help.push("the styles used may not be rendered on this device, or the shapes may be empty or hidden".into())
        }
        _ => {}
    }
    let unstyled: Vec<usize> = (0..drawing.elements.len()).filter(|&i| drawing.elements[i].styles.is_empty()).collect();
    if !unstyled.is_empty() {
        why.push(format!("{} other element(s) have no tactile style ({})", unstyled.len(), names(&unstyled)));
    }
    if why.is_empty() {
        why.push("the shapes given styles make nothing on the surface".into());
    }
    let family_help = other_family && device.family() != taxel_format::Family::Laterotactile;
    if !family_help && drawing.elements.iter().any(|e| e.styled_by == drawing::StyledBy::Auto) {
        help.push("`taxel style auto INPUT` shows what the automatic style sheet made of each colour".into());
    }
    let d =
        Diagnostic::error("T0300", format!("nothing in this drawing can be rendered on {profile}: {}", why.join("; ")));
    if help.is_empty() { d } else { d.with_help(help.join("; ")) }
}

/// Compiles an SVG and draws the result over a faint copy of the drawing.
/// The picture is `None` when the drawing did not compile (see the diagnostics).
pub fn preview_svg(svg_text: &str, opts: &CompileOptions) -> (Option<crate::preview::Picture>, Compiled) {
    let compiled = compile_svg(svg_text, opts);
    // A print profile's sheet is drawn as it is felt on paper or as a relief.
    if let Some(sheet) = compiled.print.as_ref() {
        return (Some(crate::print::preview::render(sheet)), compiled);
    }
    let Some(bundle) = compiled.bundle.as_ref() else { return (None, compiled) };
    (Some(crate::preview::preview_compiled(svg_text, opts, bundle)), compiled)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::StyledBy;
    use crate::style::tests::{RED, page, rect, shape};
    use taxel_format::profiles;

    #[test]
    fn prepare_uses_the_automatic_sheet_only_when_nothing_else_styles_the_drawing() {
        let profile = profiles::builtin("stress2").unwrap();
        let drawing = || Drawing {
            page: page(100.0, 50.0),
            elements: vec![shape("a", rect(10.0, 10.0, 40.0, 40.0), RED, None)],
            ..Default::default()
        };
        let codes = |diags: &[Diagnostic]| diags.iter().map(|d| d.code).collect::<Vec<_>>();
        // Unannotated, no sheet: automatic, with the note.
        let (mut d, mut diags) = (drawing(), Vec::new());
        assert!(adapt(&mut d, &crate::CompileOptions::new(profile), &mut diags));
        assert_eq!(codes(&diags), ["T0320", "T0330"]);
        assert_eq!(d.elements[0].styled_by, StyledBy::Auto);
        // --style auto: automatic, no note needed.
        let (mut d, mut diags) = (drawing(), Vec::new());
        let opts = crate::CompileOptions { auto: true, ..crate::CompileOptions::new(profile) };
        assert!(adapt(&mut d, &opts, &mut diags));
        assert_eq!(codes(&diags), ["T0330"]);
        assert_eq!(d.elements[0].styled_by, StyledBy::Auto);
        // A style sheet was given: it decides, even if it styled nothing.
        let (mut d, mut diags) = (drawing(), Vec::new());
        let sheet = crate::StyleSheet::parse("[[rule]]\nid = \"b\"\ntactile = \"vibrate()\"\n", "s.toml").unwrap();
        let opts = crate::CompileOptions { style: Some(sheet), ..crate::CompileOptions::new(profile) };
        assert!(adapt(&mut d, &opts, &mut diags));
        assert_eq!(codes(&diags), ["T0330"]);
        assert_eq!(d.elements[0].styled_by, StyledBy::Nothing);
        // --fit runs first: what the drawing shows (10..40 mm, with a margin of
        // 0.9 mm: 31.8 mm square) fills the 60 mm height of the surface, centred.
        let (mut d, mut diags) = (drawing(), Vec::new());
        let opts = crate::CompileOptions { fit: true, ..crate::CompileOptions::new(profile) };
        assert!(adapt(&mut d, &opts, &mut diags));
        assert_eq!(codes(&diags), ["T0211", "T0320", "T0330"]);
        let b = d.elements[0].bounds().unwrap();
        let s = 60.0 / 31.8;
        assert!((b.0 - (55.0 - 15.0 * s)).abs() < 1e-9 && (b.2 - (55.0 + 15.0 * s)).abs() < 1e-9, "{b:?}");
    }
}
