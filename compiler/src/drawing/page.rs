//! Physical size: how many millimetres one usvg unit is.
//!
//! usvg resolves the root's `width`/`height` to CSS pixels (96 per inch) and
//! maps the `viewBox` onto them, so every transform it gives lands in that
//! pixel space. A root `width` or `height` in an absolute unit (mm, cm, in,
//! pt, pc, px or a bare number, which SVG reads as px) fixes the millimetres;
//! a percentage or no size at all does not, and then the drawing is fitted to
//! the device's surface (with a note) unless `--width-mm` decides.

use roxmltree::Node;
use svgtypes::{Length, LengthUnit};
use taxel_format::DeviceProfile;

use crate::diagnostic::{Diagnostic, number};

/// The page as usvg sees it: millimetres per usvg pixel and the page size in millimetres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Sizing {
    /// Millimetres per usvg pixel.
    pub scale: f64,
    pub width_mm: f64,
    pub height_mm: f64,
}

/// Millimetres for an absolute SVG length, `None` for relative ones.
fn absolute_mm(s: &str) -> Option<f64> {
    let l: Length = s.trim().parse().ok()?;
    let per = match l.unit {
        LengthUnit::None | LengthUnit::Px => 25.4 / 96.0,
        LengthUnit::Mm => 1.0,
        LengthUnit::Cm => 10.0,
        LengthUnit::In => 25.4,
        LengthUnit::Pt => 25.4 / 72.0,
        LengthUnit::Pc => 25.4 / 6.0,
        _ => return None,
    };
    let mm = l.number * per;
    (mm.is_finite() && mm > 0.0).then_some(mm)
}

/// Decides the page size for a drawing whose usvg size is `w` x `h` pixels.
pub(crate) fn page(
    root: Node<'_, '_>,
    w: f64,
    h: f64,
    width_mm: Option<f32>,
    profile: &DeviceProfile,
    diags: &mut Vec<Diagnostic>,
) -> Sizing {
    let abs_w = root.attribute("width").and_then(absolute_mm);
    let abs_h = root.attribute("height").and_then(absolute_mm);
    let (sw, sh) = (profile.surface_w_mm as f64, profile.surface_h_mm as f64);
    let own = abs_w.map(|mm| mm / w).or(abs_h.map(|mm| mm / h));
    let scale = match (width_mm.map(f64::from).filter(|v| v.is_finite() && *v > 0.0), own) {
        (Some(mm), own) => {
            if let Some(s) = own {
                diags.push(Diagnostic::note(
                    "T0203",
                    format!("--width-mm {mm} mm replaces the drawing's own width of {} mm", number(s * w, 1)),
                ));
            }
            mm / w
        }
        (None, Some(s)) => s,
        (None, None) => {
            let s = (sw / w).min(sh / h);
            diags.push(
                Diagnostic::note(
                    "T0201",
                    format!(
                        "the drawing has no physical size; it is fitted to the {} surface ({sw} x {sh} mm) at {} x {} mm",
                        profile.name,
                        number(w * s, 1),
                        number(h * s, 1)
                    ),
                )
                .with_help("give the root <svg> a width and height in mm (width=\"100mm\"), or pass --width-mm"),
            );
            s
        }
    };
    // A page larger than the surface is reported once, after `--fit` and
    // `--region` had their say, by `crate::place::apply` (T0202).
    Sizing { scale, width_mm: w * scale, height_mm: h * scale }
}

/// The transform usvg applies at the root (the root's `transform`, then the
/// `viewBox` mapped onto the size `w` x `h`), read with svgtypes the way usvg
/// reads it. Used to place text that usvg could not lay out (no fonts).
pub(crate) fn root_transform(root: Node<'_, '_>, w: f32, h: f32) -> resvg::tiny_skia::Transform {
    own_transform(root).pre_concat(view_box_transform(root, w, h))
}

/// An element's own `transform` attribute (identity when absent or unreadable).
pub(crate) fn own_transform(n: Node<'_, '_>) -> resvg::tiny_skia::Transform {
    use resvg::tiny_skia::Transform;
    n.attribute("transform").and_then(|t| t.parse::<svgtypes::Transform>().ok()).map_or(Transform::identity(), |t| {
        Transform::from_row(t.a as f32, t.b as f32, t.c as f32, t.d as f32, t.e as f32, t.f as f32)
    })
}

/// The `viewBox` of `n` (an `<svg>`) mapped onto the size `w` x `h` under
/// its `preserveAspectRatio`; identity without a usable `viewBox`.
pub(crate) fn view_box_transform(n: Node<'_, '_>, w: f32, h: f32) -> resvg::tiny_skia::Transform {
    use resvg::tiny_skia::Transform;
    use svgtypes::Align;
    let Some(vb) = n.attribute("viewBox").and_then(|v| v.parse::<svgtypes::ViewBox>().ok()) else {
        return Transform::identity();
    };
    if !(vb.w > 0.0 && vb.h > 0.0) {
        return Transform::identity();
    }
    let aspect: svgtypes::AspectRatio =
        n.attribute("preserveAspectRatio").and_then(|v| v.parse().ok()).unwrap_or_default();
    let (mut sx, mut sy) = (w / vb.w as f32, h / vb.h as f32);
    if aspect.align != Align::None {
        let s = if aspect.slice { sx.max(sy) } else { sx.min(sy) };
        (sx, sy) = (s, s);
    }
    let (x, y) = (-vb.x as f32 * sx, -vb.y as f32 * sy);
    let (rw, rh) = (w - vb.w as f32 * sx, h - vb.h as f32 * sy);
    let (fx, fy) = match aspect.align {
        Align::None | Align::XMinYMin => (0.0, 0.0),
        Align::XMidYMin => (0.5, 0.0),
        Align::XMaxYMin => (1.0, 0.0),
        Align::XMinYMid => (0.0, 0.5),
        Align::XMidYMid => (0.5, 0.5),
        Align::XMaxYMid => (1.0, 0.5),
        Align::XMinYMax => (0.0, 1.0),
        Align::XMidYMax => (0.5, 1.0),
        Align::XMaxYMax => (1.0, 1.0),
    };
    Transform::from_row(sx, 0.0, 0.0, sy, x + fx * rw, y + fy * rh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn absolute_units_convert_to_millimetres() {
        let close = |s: &str, mm: f64| (absolute_mm(s).unwrap() - mm).abs() < 1e-9;
        assert!(close("100mm", 100.0));
        assert!(close("2.5cm", 25.0));
        assert!(close("1in", 25.4));
        assert!(close("72pt", 25.4));
        assert!(close("96px", 25.4));
        assert!(close("96", 25.4));
        assert!(close("6pc", 25.4));
        assert_eq!(absolute_mm("100%"), None);
        assert_eq!(absolute_mm("10em"), None);
        assert_eq!(absolute_mm("-3mm"), None);
        assert_eq!(absolute_mm("wide"), None);
    }
}
