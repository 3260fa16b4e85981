//! The backdrop: the drawing itself, rendered by resvg under the felt
//! preview, placed as the compiler placed the drawing.

use resvg::tiny_skia::Pixmap;
use taxel_format::Bundle;

use super::{Backdrop, PREVIEW_PX_PER_MM, Picture, render_bundle};
use crate::drawing;
use crate::options::CompileOptions;

/// The backdrop is drawn without the drawing's filter effects (shadows,
/// blurs, glows), which are not felt: a style sheet before the drawing's
/// own, which no later declaration overrides. Some filters cost resvg time
/// with no bound: resvg's own test of an `feMorphology` of radius 9,999 on
/// a 160 px square took 26 s to preview, and builds in 0.07 s.
const NO_FILTERS: &str = "* { filter: none !important; }";

/// Renders the drawing itself (no tactile layers and no filter effects) with
/// resvg at `px_per_mm`, page origin at the top-left, for previews. `None`
/// when it cannot be read.
fn render_page(
    text: &str,
    opts: &CompileOptions,
    px_per_mm: f64,
    placement: Option<crate::place::Placement>,
) -> Option<resvg::tiny_skia::Pixmap> {
    let mut scratch = Vec::new();
    let doc = drawing::source::parse_xml(text, &mut scratch)?;
    let mut uopt = drawing::usvg_options(opts.fonts.as_ref(), &opts.languages);
    uopt.style_sheet = Some(NO_FILTERS.into());
    let tree = usvg::Tree::from_xmltree(&doc, &uopt).ok()?;
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

/// The drawing alone, no tactile layer and no filter effect, rendered at [`PREVIEW_PX_PER_MM`]
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The pixel at `(x, y)` mm of a picture at [`PREVIEW_PX_PER_MM`].
    fn at(p: &Picture, x: f64, y: f64) -> [u8; 4] {
        let (i, j) = ((x * PREVIEW_PX_PER_MM) as usize, (y * PREVIEW_PX_PER_MM) as usize);
        let k = 4 * (j * p.width as usize + i);
        p.rgba[k..k + 4].try_into().expect("four bytes")
    }

    /// A filter, by attribute, by `style` or by the drawing's own CSS
    /// (even `!important`), is not applied: the square stays where it is
    /// drawn rather than moved 30 mm by `feOffset`, and an `feMorphology`
    /// of radius 9,999, which resvg takes seconds over, is not run.
    #[test]
    fn the_backdrop_leaves_filters_out() {
        let opts = CompileOptions::new(taxel_format::profiles::builtin("stress2").expect("a built-in profile"));
        for applied in
            [r#"filter="url(#move)""#, r#"style="filter:url(#move)""#, r#"class="moved""#, r#"filter="url(#grow)""#]
        {
            let svg = format!(
                r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm" viewBox="0 0 100 60">
                <style>.moved {{ filter: url(#move) !important; }}</style>
                <filter id="move" x="-1" y="-1" width="4" height="4"><feOffset dx="30" dy="0"/></filter>
                <filter id="grow"><feMorphology operator="dilate" radius="9999"/></filter>
                <rect x="10" y="10" width="20" height="20" fill="black" {applied}/></svg>"#
            );
            let p = drawing_picture(&svg, &opts).expect("a picture");
            assert_eq!(at(&p, 20.0, 20.0), [0, 0, 0, 255], "{applied}: the square where it is drawn");
            assert_eq!(at(&p, 50.0, 20.0)[3], 0, "{applied}: nothing where the filter would move it");
        }
    }
}
