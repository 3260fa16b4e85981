//! The SVG front end: annotated SVG in, bundle and diagnostics out.
//!
//! Stages: [`crate::drawing::resolve`] turns the SVG into the resolved
//! drawing (styles, paint, exact geometry in page mm); `prepare` is where
//! the drawing is adapted before layers are made (automatic style sheet,
//! `--fit`, `--region`); `layers` turns the drawing into masks, dot tables
//! and strokes; `rules` checks the design rules; the bundle is assembled last.
//!
//! ```
//! use taxel_compiler::{CompileOptions, svg::compile_svg};
//! use taxel_format::profiles;
//!
//! let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="60mm" height="40mm" viewBox="0 0 60 40">
//!   <rect x="10" y="10" width="30" height="22" data-tactile="vibrate()"/>
//! </svg>"#;
//! let out = compile_svg(svg, &CompileOptions::new(profiles::builtin("stress2").unwrap()));
//! assert!(out.bundle.is_some(), "{:?}", out.diagnostics);
//! ```

mod braille;
mod dots;
mod footprints;
mod layers;
pub(crate) mod rules;

/// The paper's braille geometry, for the automatic sheet's measures too.
pub(crate) use braille::{CELL_PITCH_MM, DOT_PITCH_MM};
pub(crate) use layers::OpaqueFills;
pub(crate) use layers::missing_help as braille_missing_help;
pub use layers::{braille_clearing, clearing_within, occluders};

use taxel_format::{Bundle, Manifest};

use crate::Compiled;
use crate::diagnostic::{Diagnostic, Severity, has_errors};
use crate::drawing;
use crate::options::{CompileOptions, DEFAULT_PX_PER_MM};

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
/// use taxel_compiler::{CompileOptions, svg::compile_svg_with_fonts};
/// use taxel_format::profiles;
///
/// let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="60mm" height="40mm" viewBox="0 0 60 40">
///   <rect x="10" y="10" width="30" height="22" data-tactile="vibrate()"/>
/// </svg>"#;
/// let out = compile_svg_with_fonts(svg, &CompileOptions::new(profiles::builtin("stress2").unwrap()), &|| None);
/// assert!(out.bundle.is_some(), "{:?}", out.diagnostics);
/// ```
pub fn compile_svg_with_fonts(svg_text: &str, opts: &CompileOptions, fonts: drawing::Fonts<'_>) -> Compiled {
    let (mut diagnostics, mut fonts_used, mut print) = (Vec::new(), Vec::new(), None);
    let bundle = compile(svg_text, opts, fonts, &mut diagnostics, &mut fonts_used, &mut print);
    let bundle = if has_errors(&diagnostics) { None } else { bundle };
    let print = if has_errors(&diagnostics) { None } else { print };
    Compiled { bundle, diagnostics, fonts_used, print }
}

/// The pipeline: resolve → prepare → layers → design rules → bundle (or,
/// for a print profile, the print sheet in `print`).
fn compile(
    text: &str,
    opts: &CompileOptions,
    fonts: drawing::Fonts<'_>,
    diags: &mut Vec<Diagnostic>,
    fonts_used: &mut Vec<drawing::FontFace>,
    print: &mut Option<crate::print::Sheet>,
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
    let mut drawing = drawing::resolve_into(text, opts, fonts, diags, fonts_used)?;
    // Styles asked of shapes that are not drawn count as asked (for the T0300 message below).
    let not_drawn = diags.iter().filter(|d| d.code == drawing::NOT_DRAWN).count();
    crate::prepare::prepare(&mut drawing, opts, diags);
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
        *print = crate::print::legalise_with(&drawing, opts, diags);
        return None;
    }
    // The design rules but the overlaps need only the features: they run
    // beside the distance fields, and add their diagnostics after them.
    let (built, checked) = layers::build(&drawing, opts, px, diags, |f| rules::check_features(f, &opts.profile));
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
            let why = auto.then(|| crate::auto::nothing_made(&drawing, &opts.profile)).flatten();
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

/// T0300 when elements asked for styles and nothing was made of them: what
/// was asked, and why nothing was kept (the warnings given with it, or layers that
/// came out empty because opaque fills painted later hide them, or because
/// they lie off the surface), so the message never points at warnings that
/// are not there.
fn nothing_rendered(
    drawing: &drawing::Drawing,
    built: &layers::Built,
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
    let elsewhere = diags.iter().filter(|d| d.code == layers::NOT_ON_DEVICE).count();
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

/// Renders the drawing itself (no tactile layers) with resvg at `px_per_mm`,
/// page origin at the top-left, for previews. `None` when it cannot be read.
pub(crate) fn render_page(
    text: &str,
    opts: &CompileOptions,
    px_per_mm: f64,
    placement: Option<crate::fit::Placement>,
) -> Option<resvg::tiny_skia::Pixmap> {
    let mut scratch = Vec::new();
    let doc = drawing::source::parse_xml(text, &mut scratch)?;
    let tree = usvg::Tree::from_xmltree(&doc, &drawing::usvg_options(opts.fonts.as_ref(), &opts.languages)).ok()?;
    let (w, h) = (tree.size().width(), tree.size().height());
    let page = drawing::page_size(doc.root_element(), w as f64, h as f64, opts.width_mm, &opts.profile, &mut scratch);
    // With --fit or --region the page is placed on the surface as the compiler placed the drawing.
    let (s, t, (page_w, page_h)) = match placement {
        Some(p) => (p.scale, p.shift, p.surface),
        None => (1.0, (0.0, 0.0), (page.width_mm, page.height_mm)),
    };
    let k = (page.scale * s * px_per_mm) as f32;
    let (pw, ph) = ((page_w * px_per_mm).ceil(), (page_h * px_per_mm).ceil());
    if !(pw >= 1.0 && ph >= 1.0 && pw * ph <= 64e6) {
        return None;
    }
    let mut pixmap = resvg::tiny_skia::Pixmap::new(pw as u32, ph as u32)?;
    let ts = resvg::tiny_skia::Transform::from_row(k, 0.0, 0.0, k, (t.0 * px_per_mm) as f32, (t.1 * px_per_mm) as f32);
    resvg::render(&tree, ts, &mut pixmap.as_mut());
    Some(pixmap)
}
