//! PNG files, through the `png` crate (the codec the `image` crate itself
//! uses; see ARCHITECTURE.md for why taxel calls it directly).
//!
//! Masks are grayscale PNG files: 8-bit masks as 8-bit gray, 16-bit masks as
//! 16-bit gray, one pixel per sample, top row first, so any image editor can
//! open and change them. [`encode`] and [`decode`] are the program's other
//! PNG files' way in and out too (previews, plots, the report's sizes).

use std::io::Cursor;

pub use ::png::{BitDepth, ColorType, Compression, Filter};
use taxel_format::MaskSamples;

use super::error::TextError;

/// The most a decoded PNG may take, as the `image` crate allowed by default.
const MAX_DECODED_BYTES: usize = 512 << 20;

/// A decoded PNG: samples of fewer than 8 bits and palettes expanded to 8
/// bits (as most readers do), 16-bit samples kept, big-endian as in the file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    /// Pixels a row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// The samples' colour type (after expansion).
    pub color: ColorType,
    /// Bits a sample: 8 or 16.
    pub depth: BitDepth,
    /// The rows, top first, with no padding.
    pub data: Vec<u8>,
}

impl Image {
    /// Samples a pixel.
    pub fn channels(&self) -> usize {
        self.color.samples()
    }

    /// The 8-bit samples of pixel `(x, y)` (16-bit samples by their high
    /// byte), or `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<Vec<u8>> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let (c, wide) = (self.channels(), usize::from(self.depth == BitDepth::Sixteen) + 1);
        let at = ((y as usize * self.width as usize) + x as usize) * c * wide;
        (0..c).map(|k| self.data.get(at + k * wide).copied()).collect()
    }

    /// Each pixel as one gray byte: gray as it is, colour by its luma
    /// (Rec. 709 weights, as `image`'s `to_luma8`), alpha dropped.
    pub fn to_gray8(&self) -> Vec<u8> {
        let (c, wide) = (self.channels(), usize::from(self.depth == BitDepth::Sixteen) + 1);
        self.data
            .chunks_exact(c * wide)
            .map(|px| match c {
                1 | 2 => px[0],
                _ => {
                    let (r, g, b) = (px[0] as u32, px[wide] as u32, px[2 * wide] as u32);
                    ((2126 * r + 7152 * g + 722 * b + 5000) / 10_000) as u8
                }
            })
            .collect()
    }

    /// Each pixel as RGB bytes: gray repeated, alpha dropped.
    pub fn to_rgb8(&self) -> Vec<[u8; 3]> {
        let (c, wide) = (self.channels(), usize::from(self.depth == BitDepth::Sixteen) + 1);
        self.data
            .chunks_exact(c * wide)
            .map(|px| match c {
                1 | 2 => [px[0]; 3],
                _ => [px[0], px[wide], px[2 * wide]],
            })
            .collect()
    }
}

/// Reads a PNG file's bytes.
pub fn read(bytes: &[u8]) -> Result<Image, ::png::DecodingError> {
    let mut decoder = ::png::Decoder::new_with_limits(Cursor::new(bytes), ::png::Limits { bytes: MAX_DECODED_BYTES });
    decoder.set_transformations(::png::Transformations::EXPAND);
    let mut reader = decoder.read_info()?;
    let size = reader.output_buffer_size().ok_or(::png::DecodingError::LimitsExceeded)?;
    if size > MAX_DECODED_BYTES {
        return Err(::png::DecodingError::LimitsExceeded);
    }
    let mut data = vec![0; size];
    let frame = reader.next_frame(&mut data)?;
    data.truncate(frame.buffer_size());
    Ok(Image { width: frame.width, height: frame.height, color: frame.color_type, depth: frame.bit_depth, data })
}

/// Writes rows of `color` samples of `depth` bits (16-bit ones big-endian)
/// as a PNG with adaptive filters and `compression`.
pub fn write(
    width: u32,
    height: u32,
    color: ColorType,
    depth: BitDepth,
    data: &[u8],
    compression: Compression,
) -> Result<Vec<u8>, ::png::EncodingError> {
    let mut out = Vec::new();
    let mut encoder = ::png::Encoder::new(&mut out, width, height);
    encoder.set_color(color);
    encoder.set_depth(depth);
    encoder.set_compression(compression);
    encoder.set_filter(Filter::Adaptive);
    encoder.write_header()?.write_image_data(data)?;
    Ok(out)
}

/// 16-bit samples as a PNG's big-endian bytes.
pub fn be_bytes(samples: &[u16]) -> Vec<u8> {
    samples.iter().flat_map(|s| s.to_be_bytes()).collect()
}

/// Encodes samples as a PNG. `width * height` must be the sample count.
pub fn encode(file: &str, width: u32, height: u32, samples: &MaskSamples) -> Result<Vec<u8>, TextError> {
    let n = match samples {
        MaskSamples::U8(v) => v.len(),
        MaskSamples::U16(v) => v.len(),
    };
    if n as u64 != u64::from(width) * u64::from(height) {
        return Err(TextError::new(file, "mask samples do not fill its width and height"));
    }
    match samples {
        MaskSamples::U8(v) => write(width, height, ColorType::Grayscale, BitDepth::Eight, v, Compression::Fast),
        MaskSamples::U16(v) => {
            write(width, height, ColorType::Grayscale, BitDepth::Sixteen, &be_bytes(v), Compression::Fast)
        }
    }
    .map_err(|e| TextError::new(file, format!("cannot encode PNG: {e}")))
}

/// Decodes a grayscale PNG into `(width, height, samples)`.
pub fn decode(file: &str, bytes: &[u8]) -> Result<(u32, u32, MaskSamples), TextError> {
    let image = read(bytes).map_err(|e| TextError::new(file, format!("not a readable PNG: {e}")))?;
    let samples = match (image.color, image.depth) {
        (ColorType::Grayscale, BitDepth::Eight) => MaskSamples::U8(image.data),
        (ColorType::Grayscale, BitDepth::Sixteen) => {
            MaskSamples::U16(image.data.chunks_exact(2).map(|b| u16::from_be_bytes([b[0], b[1]])).collect())
        }
        (color, depth) => {
            return Err(TextError::new(
                file,
                format!(
                    "expected an 8- or 16-bit grayscale PNG without alpha, found {color:?} of {} bits; save it as grayscale",
                    depth as u8
                ),
            ));
        }
    };
    Ok((image.width, image.height, samples))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_depths_round_trip() {
        for s in [MaskSamples::U8(vec![0, 1, 254, 255, 7, 9]), MaskSamples::U16(vec![0, 1, 256, 65_535, 300, 4])] {
            let png = encode("m.png", 3, 2, &s).unwrap();
            assert_eq!(decode("m.png", &png).unwrap(), (3, 2, s));
        }
        assert!(encode("m.png", 4, 2, &MaskSamples::U8(vec![0; 6])).is_err());
    }

    #[test]
    fn colour_images_are_refused_with_the_reason() {
        let rgb = write(2, 2, ColorType::Rgb, BitDepth::Eight, &[0; 12], Compression::Fast).unwrap();
        let e = decode("02-grating.png", &rgb).unwrap_err();
        assert!(e.to_string().starts_with("02-grating.png: expected an 8- or 16-bit grayscale PNG"), "{e}");
        assert!(e.to_string().contains("Rgb of 8 bits"), "{e}");
        assert!(decode("x.png", b"GIF89a").unwrap_err().to_string().contains("not a readable PNG"));
    }

    #[test]
    fn pixels_convert_to_gray_and_rgb() {
        let rgba =
            write(2, 1, ColorType::Rgba, BitDepth::Eight, &[255, 0, 0, 9, 10, 20, 30, 255], Compression::Fast).unwrap();
        let image = read(&rgba).unwrap();
        assert_eq!((image.width, image.height, image.channels()), (2, 1, 4));
        assert_eq!(image.pixel(1, 0), Some(vec![10, 20, 30, 255]));
        assert_eq!((image.pixel(2, 0), image.pixel(0, 1)), (None, None));
        assert_eq!(image.to_rgb8(), [[255, 0, 0], [10, 20, 30]]);
        // Rec. 709: 0.2126 of red; 0.2126 * 10 + 0.7152 * 20 + 0.0722 * 30 = 18.6.
        assert_eq!(image.to_gray8(), [54, 19]);
        let gray16 =
            read(&write(1, 1, ColorType::Grayscale, BitDepth::Sixteen, &[0x12, 0x34], Compression::Fast).unwrap())
                .unwrap();
        assert_eq!(
            (gray16.pixel(0, 0).unwrap(), gray16.to_gray8(), gray16.to_rgb8()),
            (vec![0x12], vec![0x12], vec![[0x12; 3]])
        );
    }

    #[test]
    fn a_palette_image_is_expanded() {
        let mut out = Vec::new();
        let mut e = ::png::Encoder::new(&mut out, 2, 1);
        e.set_color(ColorType::Indexed);
        e.set_depth(BitDepth::One);
        e.set_palette(vec![0, 0, 0, 200, 100, 50]);
        e.write_header().unwrap().write_image_data(&[0b0100_0000]).unwrap();
        let image = read(&out).unwrap();
        assert_eq!((image.color, image.depth), (ColorType::Rgb, BitDepth::Eight));
        assert_eq!(image.to_rgb8(), [[0, 0, 0], [200, 100, 50]]);
    }
}
