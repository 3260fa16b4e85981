//! The hook between the resolved drawing and its layers: where the drawing
//! is adapted to the device before anything is rasterised. The automatic
//! style sheet (`auto`), `--region` and `--fit` belong here, so that the
//! layers and the design rules see the drawing as it will be felt.

use crate::diagnostic::Diagnostic;
use crate::drawing::Drawing;
use crate::options::CompileOptions;

/// Prepares `drawing` for `opts` before its layers are built: `--region` and
/// `--fit` and the crop to the surface, then the automatic style sheet where
/// it applies, then the style summary ([`crate::auto::prepare`]). When an
/// error stops it (a region that cannot be taken) the drawing is emptied, so
/// no layer is built; the error says why. Called by both `svg::compile_svg`
/// and the public `drawing::resolve`, so that `taxel report`'s reference sees
/// the drawing the layers were built from.
pub(crate) fn prepare(drawing: &mut Drawing, opts: &CompileOptions, diags: &mut Vec<Diagnostic>) {
    if !crate::auto::prepare(drawing, opts, diags) {
        drawing.elements.clear();
    }
}
