//! PNG encoding: previews, plots and the text form's masks.

use anyhow::{Context, Result};
use image::{DynamicImage, ImageFormat};
use taxel_compiler::preview::Picture;

/// Encodes any image as PNG bytes.
pub fn encode(image: &DynamicImage) -> Result<Vec<u8>> {
    let mut out = std::io::Cursor::new(Vec::new());
    image.write_to(&mut out, ImageFormat::Png).context("cannot encode PNG")?;
    Ok(out.into_inner())
}

/// Encodes an RGBA preview picture.
pub fn encode_picture(p: &Picture) -> Result<Vec<u8>> {
    let img = image::RgbaImage::from_raw(p.width, p.height, p.rgba.clone()).with_context(|| {
        format!("the picture's {} bytes do not fill {} x {} pixels", p.rgba.len(), p.width, p.height)
    })?;
    encode(&DynamicImage::ImageRgba8(img))
}
