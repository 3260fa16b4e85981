//! What a compilation needs besides the drawing itself.

use taxel_format::DeviceProfile;

use crate::stylesheet::StyleSheet;

/// Default mask resolution in samples per millimetre (see `docs/annotations.md`,
/// "Mask resolution"): the bilinear 50 % contour of an edge then lies within
/// 11.4 µm of the true edge, under the STRESS² carrier's 13 µm position
/// resolution, and more than 0.15 mm from edges the mask is exact.
pub const DEFAULT_PX_PER_MM: f32 = 10.0;

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
}

impl CompileOptions {
    /// Options for `profile` with every other setting at its default.
    pub fn new(profile: DeviceProfile) -> Self {
        CompileOptions { profile, style: None, resolution_px_per_mm: None, width_mm: None, content_hash: [0; 32] }
    }
}
