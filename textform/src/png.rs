//! Masks as grayscale PNG files: 8-bit masks as 8-bit gray, 16-bit masks as
//! 16-bit gray, one pixel per sample, top row first, so any image editor can
//! open and change them.

use image::{DynamicImage, ImageBuffer, ImageFormat, Luma};
use taxel_format::MaskSamples;

use super::error::TextError;

/// Encodes samples as a PNG. `width * height` must be the sample count.
pub fn encode(file: &str, width: u32, height: u32, samples: &MaskSamples) -> Result<Vec<u8>, TextError> {
    let image = match samples {
        MaskSamples::U8(v) => ImageBuffer::<Luma<u8>, _>::from_raw(width, height, v.clone()).map(DynamicImage::from),
        MaskSamples::U16(v) => ImageBuffer::<Luma<u16>, _>::from_raw(width, height, v.clone()).map(DynamicImage::from),
    }
    .ok_or_else(|| TextError::new(file, "mask samples do not fill its width and height"))?;
    let mut out = std::io::Cursor::new(Vec::new());
    image.write_to(&mut out, ImageFormat::Png).map_err(|e| TextError::new(file, format!("cannot encode PNG: {e}")))?;
    Ok(out.into_inner())
}

/// Decodes a grayscale PNG into `(width, height, samples)`.
pub fn decode(file: &str, bytes: &[u8]) -> Result<(u32, u32, MaskSamples), TextError> {
    let image = image::load_from_memory_with_format(bytes, ImageFormat::Png)
        .map_err(|e| TextError::new(file, format!("not a readable PNG: {e}")))?;
    let (w, h) = (image.width(), image.height());
    let samples = match image {
        DynamicImage::ImageLuma8(b) => MaskSamples::U8(b.into_raw()),
        DynamicImage::ImageLuma16(b) => MaskSamples::U16(b.into_raw()),
        other => {
            return Err(TextError::new(
                file,
                format!(
                    "expected an 8- or 16-bit grayscale PNG without alpha, found {:?}; save it as grayscale",
                    other.color()
                ),
            ));
        }
    };
    Ok((w, h, samples))
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
    }

    #[test]
    fn colour_images_are_refused_with_the_reason() {
        let rgb = DynamicImage::ImageRgb8(ImageBuffer::new(2, 2));
        let mut png = std::io::Cursor::new(Vec::new());
        rgb.write_to(&mut png, ImageFormat::Png).unwrap();
        let e = decode("02-grating.png", png.get_ref()).unwrap_err();
        assert!(e.to_string().starts_with("02-grating.png: expected an 8- or 16-bit grayscale PNG"), "{e}");
        assert!(decode("x.png", b"GIF89a").unwrap_err().to_string().contains("not a readable PNG"));
    }
}
