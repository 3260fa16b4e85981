//! The backdrop: the drawing itself, rendered by resvg under the felt
//! preview, placed as the compiler placed the drawing.

use resvg::tiny_skia::Pixmap;
use taxel_format::Bundle;

use super::{Backdrop, PREVIEW_PX_PER_MM, Picture, render_bundle};
use crate::drawing;
use crate::options::CompileOptions;

/// Renders the drawing itself (no tactile layers) with resvg at `px_per_mm`,
/// page origin at the top-left, for previews. `None` when it cannot be read.
fn render_page(
    text: &str,
    opts: &CompileOptions,
    px_per_mm: f64,
    placement: Option<crate::place::Placement>,
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

/// Draws `bundle`, compiled from `svg_text` with `opts`, over a faint copy
/// of the drawing: [`crate::pipeline::preview_svg`] for a caller that compiled it already.
pub fn preview_compiled(svg_text: &str, opts: &CompileOptions, bundle: &Bundle) -> Picture {
    let backdrop = drawing_pixmap(svg_text, opts).map(|pixmap| Backdrop { pixmap });
    render_bundle(bundle, backdrop.as_ref())
}

/// The drawing alone, no tactile layer, rendered at [`PREVIEW_PX_PER_MM`]
/// with page origin at its top-left, placed as the compiler placed it (under
/// `fit` or a region): a picture of the drawing that never executes it
/// (resvg draws; scripts and external files are not read). `None` when it
/// cannot be read.
pub fn drawing_picture(svg_text: &str, opts: &CompileOptions) -> Option<Picture> {
    let pixmap = drawing_pixmap(svg_text, opts)?;
    let (width, height) = (pixmap.width(), pixmap.height());
    let rgba = pixmap
        .pixels()
        .iter()
        .flat_map(|p| {
            let c = p.demultiply();
            [c.red(), c.green(), c.blue(), c.alpha()]
        })
        .collect();
    Some(Picture { width, height, rgba })
}

fn drawing_pixmap(svg_text: &str, opts: &CompileOptions) -> Option<Pixmap> {
    // Under --fit or --region the backdrop is placed as the drawing was (that needs the resolved drawing).
    let placement = if opts.fit || opts.region.is_some() {
        crate::drawing::resolve(svg_text, opts)
            .drawing
            .and_then(|d| crate::place::placement(&d, &opts.profile, opts.fit, opts.region.as_ref()).ok().flatten())
    } else {
        None
    };
    render_page(svg_text, opts, PREVIEW_PX_PER_MM, placement)
}
