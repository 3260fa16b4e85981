//! PNG encoding: previews and plots (through `taxel_textform::png`, which
//! also writes the text form's masks).

use anyhow::{Context, Result, ensure};
use taxel_compiler::preview::Picture;
use taxel_textform::png::{self, BitDepth, ColorType, Compression};

/// Encodes 8-bit pixels of `color` (RGB or RGBA), rows top first.
pub fn encode(width: u32, height: u32, color: ColorType, data: &[u8]) -> Result<Vec<u8>> {
    let want = width as usize * height as usize * color.samples();
    ensure!(data.len() == want, "the picture's {} bytes do not fill {width} x {height} pixels", data.len());
    png::write(width, height, color, BitDepth::Eight, data, Compression::Fast).context("cannot encode PNG")
}

/// Encodes an RGBA preview picture.
pub fn encode_picture(p: &Picture) -> Result<Vec<u8>> {
    encode(p.width, p.height, ColorType::Rgba, &p.rgba)
}
