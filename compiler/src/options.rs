//! What a compilation needs besides the drawing itself.

use std::sync::Arc;

use taxel_format::DeviceProfile;

use crate::annotation::sheet::StyleSheet;

/// Default mask resolution in samples per millimetre (see `docs/annotations.md`,
/// "Mask resolution"): the bilinear 50 % contour of an edge then lies within
/// 11.4 µm of the true edge, under the STRESS² carrier's 13 µm position
/// resolution, and more than 0.15 mm from edges the mask is exact.
pub const DEFAULT_PX_PER_MM: f32 = 10.0;

/// Part of a drawing or mesh to keep (`--region`), before fitting.
#[derive(Debug, Clone, PartialEq)]
pub enum Region {
    /// A rectangle in drawing units (SVG user units of the root, or model
    /// units of a mesh's footprint): left, top, width, height.
    Rect {
        /// Left edge.
        x: f64,
        /// Top edge.
        y: f64,
        /// Width, above 0.
        w: f64,
        /// Height, above 0.
        h: f64,
    },
    /// The bounding box of the element (or mesh node) with this id or name.
    Element(String),
}

impl std::str::FromStr for Region {
    type Err = String;

    /// `X,Y,W,H` (four finite numbers, W and H above 0) or `#id`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let s = s.trim();
        if let Some(id) = s.strip_prefix('#') {
            if id.is_empty() {
                return Err("`#` must be followed by an element id, as in `#france`".into());
            }
            return Ok(Region::Element(id.to_string()));
        }
        let parts: Vec<&str> = s.split(',').map(str::trim).collect();
        let nums: Vec<f64> = parts.iter().filter_map(|p| p.parse::<f64>().ok()).filter(|v| v.is_finite()).collect();
        match (parts.len(), nums.as_slice()) {
            (4, &[x, y, w, h]) if w > 0.0 && h > 0.0 => Ok(Region::Rect { x, y, w, h }),
            (4, &[_, _, _, _]) => Err(format!("the region `{s}` has a width or height that is not above 0")),
            _ => Err(format!("the region `{s}` is not `X,Y,W,H` (four numbers in drawing units) nor `#id`")),
        }
    }
}

/// Which model axis is "up" (height) for a mesh (`--up`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UpAxis {
    /// +Y, as glTF 2.0 says.
    #[default]
    Y,
    /// +Z, as GIS tools and some exporters write terrains.
    Z,
}

/// Options for one compilation.
#[derive(Debug, Clone)]
pub struct CompileOptions {
    /// The device to compile for.
    pub profile: DeviceProfile,
    /// A style sheet (`--style`), applied between inherited styles and element attributes.
    pub style: Option<StyleSheet>,
    /// Mask resolution in samples per millimetre; `None` means [`DEFAULT_PX_PER_MM`].
    pub resolution_px_per_mm: Option<f32>,
    /// Physical width of the drawing in millimetres; overrides the SVG's own size.
    pub width_mm: Option<f32>,
    /// Hash of everything the build depended on, stored in the manifest.
    pub content_hash: [u8; 32],
    /// Scale (and centre) the drawing or mesh to fill the profile's surface,
    /// keeping its aspect ratio (`--fit`).
    pub fit: bool,
    /// Keep only this part of the drawing or mesh, then fit it (`--region`).
    pub region: Option<Region>,
    /// Height axis of a mesh (`--up`); `None` takes +Y, as glTF says, unless
    /// the model is clearly flat across Z (see `mesh::chosen_up`).
    pub up: Option<UpAxis>,
    /// Factor on a mesh's heights (`--exaggerate`), above 0; 1 keeps them.
    pub exaggerate: f64,
    /// The fonts text is laid out with (glyph outlines for styles on text,
    /// the preview's backdrop). The library loads no fonts itself: `None`
    /// means no fonts, so text gives no outlines (braille, made from the
    /// characters, does not need them). The `taxel` binary passes the
    /// system's fonts, or those of `--fonts DIR`.
    pub fonts: Option<Arc<usvg::fontdb::Database>>,
    /// Use the built-in automatic style sheet (`--style auto`, see
    /// [`crate::style`]) for every element no annotation styles. Without it the
    /// automatic sheet is still used, with a note, when the drawing has no
    /// annotation and no [`CompileOptions::style`].
    pub auto: bool,
    /// The reader's languages (BCP 47 tags such as `fr` or `fr-CA`; `--lang`):
    /// a `<switch>` draws its first child whose `systemLanguage` names one of
    /// them (or a longer tag of one: `fr` takes `fr-CA`), or that has none, as
    /// browsers do. Multilingual maps (Wikimedia's) hold each label once per
    /// language this way. Default `["en"]`.
    pub languages: Vec<String>,
    /// The braille service: liblouis when the caller found it
    /// ([`taxel_braille::Braille::load`]), else the built-in uncontracted
    /// UEB. Default: the built-in table alone, so that a library build
    /// writes the same cells on every system; the `taxel` binary loads
    /// liblouis.
    pub braille: Arc<taxel_braille::Braille>,
    /// The memory the compilation may take (`--max-memory`): the stages
    /// whose work grows with the geometry stop with an error (T0308) past
    /// it. `None` (the default): no limit.
    pub memory: Option<crate::budget::MemoryBudget>,
    /// How finely the drawing's curves are flattened; default
    /// [`Flattening::DEFAULT`](crate::geometry::Flattening::DEFAULT).
    /// `taxel report`'s reference flattens circular arcs finer
    /// ([`REFERENCE_FLATTENING`](crate::geometry::REFERENCE_FLATTENING)),
    /// so that it stands for the circle itself.
    pub flattening: crate::geometry::Flattening,
}

impl CompileOptions {
    /// Options for `profile` with every other setting at its default.
    pub fn new(profile: DeviceProfile) -> Self {
        CompileOptions {
            profile,
            style: None,
            resolution_px_per_mm: None,
            width_mm: None,
            content_hash: [0; 32],
            fit: false,
            region: None,
            up: None,
            exaggerate: 1.0,
            fonts: None,
            auto: false,
            languages: vec!["en".to_string()],
            braille: Arc::new(taxel_braille::Braille::builtin()),
            memory: None,
            flattening: crate::geometry::Flattening::DEFAULT,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regions_parse_from_rectangles_and_ids() {
        assert_eq!("10,20,30,40".parse(), Ok(Region::Rect { x: 10.0, y: 20.0, w: 30.0, h: 40.0 }));
        assert_eq!(" -1.5, 2e1 ,3,4 ".parse(), Ok(Region::Rect { x: -1.5, y: 20.0, w: 3.0, h: 4.0 }));
        assert_eq!("#France".parse(), Ok(Region::Element("France".into())));
        for bad in ["", "#", "1,2,3", "1,2,3,4,5", "1,2,0,4", "1,2,3,-4", "a,b,c,d", "1,2,inf,4", "1,2,NaN,4"] {
            assert!(bad.parse::<Region>().is_err(), "{bad:?} was accepted");
        }
    }
}
