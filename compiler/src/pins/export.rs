//! The devices' own files for a pin image (`taxel export`): Dot Inc.'s DTMS
//! page file, Graphiti full frames, and Unicode braille art.
//!
//! All three are written from the bundle alone (its profile, pin image and,
//! for the DTMS title, its provenance), byte for byte as `reference/pins.md`
//! describes the devices' formats.

use serde::Serialize;
use taxel_format::{DeviceProfile, FamilyParams, PinImage};

/// Why a bundle cannot be exported in a format.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExportError(pub String);

impl std::fmt::Display for ExportError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ExportError {}

/// Unicode braille mask bit of dot `(col, row)` within a 2 x 4 block (`reference/pins.md`).
pub fn unicode_bit(col: u32, row: u32) -> u8 {
    match (col, row) {
        (0, 0) => 0x01,
        (0, 1) => 0x02,
        (0, 2) => 0x04,
        (1, 0) => 0x08,
        (1, 1) => 0x10,
        (1, 2) => 0x20,
        (0, 3) => 0x40,
        (1, 3) => 0x80,
        _ => 0,
    }
}

/// Dot Pad graphic byte for a Unicode braille mask: `bit = (y % 4) + (x % 2) * 4`
/// (`reference/pins.md`, from NVDA's driver and BRLTTY).
pub fn dotpad_byte(u: u8) -> u8 {
    (u & 0x07) | ((u & 0x38) << 1) | ((u & 0x40) >> 3) | (u & 0x80)
}

/// The Unicode braille mask of the 2 x 4 block whose top-left pin is `(c0, r0)`
/// (raised pins, blinking or not; pins outside the image are down).
fn block(image: &PinImage, c0: u32, r0: u32) -> u8 {
    let mut m = 0;
    for r in 0..4 {
        for c in 0..2 {
            if image.get(c0.saturating_add(c), r0.saturating_add(r)).raised() {
                m |= unicode_bit(c, r);
            }
        }
    }
    m
}

/// The pin image as lines of Unicode braille (U+2800 + mask), each character
/// 2 pins wide and 4 high, with a newline after each line; then, when the
/// image has a text line, a blank line and the text line's cells.
pub fn unicode(image: &PinImage) -> String {
    let mut s = String::new();
    for r0 in (0..image.rows).step_by(4) {
        for c0 in (0..image.cols).step_by(2) {
            s.push(char::from_u32(0x2800 + block(image, c0, r0) as u32).unwrap_or(' '));
        }
        s.push('\n');
    }
    if !image.text.is_empty() {
        s.push('\n');
        s.extend(image.text.iter().map(|&m| char::from_u32(0x2800 + m as u32).unwrap_or(' ')));
        s.push('\n');
    }
    s
}

pub use crate::preview::pins::pages;

fn need_60x40(profile: &DeviceProfile, format: &str) -> Result<(), ExportError> {
    if !matches!(profile.params, FamilyParams::Pins(_)) || (profile.cols, profile.rows) != (60, 40) {
        return Err(ExportError(format!(
            "{format} files are for a 60 x 40 pin display; this bundle was compiled for {} ({} x {}, {} family): \
             build it with --profile {}",
            profile.name,
            profile.cols,
            profile.rows,
            profile.family(),
            if format == "graphiti" { "graphiti" } else { "dotpad" }
        )));
    }
    Ok(())
}

#[derive(Serialize)]
struct Dtms<'a> {
    title: &'a str,
    lang: &'a str,
    lang_option: &'a str,
    device: &'a str,
    items: Vec<DtmsItem<'a>>,
}

#[derive(Serialize)]
struct DtmsItem<'a> {
    page: usize,
    title: &'a str,
    graphic: DtmsGraphic,
    text: DtmsText<'a>,
}

#[derive(Serialize)]
struct DtmsGraphic {
    name: String,
    data: String,
}

#[derive(Serialize)]
struct DtmsText<'a> {
    name: String,
    data: String,
    plain: &'a str,
}

/// Cells per line of the Dot Pad's text line (`text.data` is padded to whole lines).
pub const DTMS_TEXT_LINE: usize = 20;

/// A Dot Pad DTMS page file: one item per display page of the image (60 x
/// 40 pins each, row-major), as the sample in `dotincorp/dotpad-sdk-guide`
/// is laid out (`title`, `lang`, `lang_option`, `device`, `items`; each item
/// `page`, `title`, `graphic {name, data}`, `text {name, data, plain}`).
/// `graphic.data` is 300 bytes, one per 2 x 4 cell, 30 cells a line, as
/// lower-case hex; `text.data` the text line's six-dot cells as upper-case
/// hex padded with `00` to whole 20-cell lines, as in the sample; `plain`
/// the text line in print (`line`: the title, and the key of the labels
/// written as key codes). `file_title` names the file (the sample uses its
/// file name), `title` is the drawing's title. `lang` is `english` (the
/// braille is UEB) and `lang_option` `1`, the value of the sample.
pub fn dtms(
    image: &PinImage,
    profile: &DeviceProfile,
    file_title: &str,
    title: &str,
    line: &str,
) -> Result<String, ExportError> {
    need_60x40(profile, "dtms")?;
    let mut text = String::new();
    let cells = image.text.len().div_ceil(DTMS_TEXT_LINE) * DTMS_TEXT_LINE;
    for k in 0..cells {
        text += &format!("{:02X}", image.text.get(k).map_or(0, |m| m & 0x3F));
    }
    let items = pages(image, profile)
        .into_iter()
        .enumerate()
        .map(|(n, (c0, r0))| {
            let mut data = String::with_capacity(600);
            for line in 0..10 {
                for cell in 0..30 {
                    let u = block(image, c0 + cell * 2, r0 + line * 4);
                    data += &format!("{:02x}", dotpad_byte(u));
                }
            }
            DtmsItem {
                page: n + 1,
                title: if title.is_empty() { file_title } else { title },
                graphic: DtmsGraphic { name: format!("{}.dtm", n + 1), data },
                text: DtmsText { name: format!("{}.txt", n + 1), data: text.clone(), plain: line },
            }
        })
        .collect();
    let doc = Dtms { title: file_title, lang: "english", lang_option: "1", device: "dotpad320", items };
    serde_json::to_string(&doc).map_err(|e| ExportError(format!("cannot write the DTMS JSON: {e}")))
}

/// Graphiti full frames (the data of command 0x15, `reference/pins.md`): per
/// display page of the image (row-major), 4,800 bytes, a (height, blink)
/// byte pair per pin, row-major, pair `(row * 60 + col) * 2`. The height is
/// the pin's (0 to 4), the blink byte the blink half-period in the device's
/// blink steps for a blinking pin and 0 otherwise. Pages follow each other;
/// the serial framing (0x1B, command, checksum) is the sender's.
pub fn graphiti(image: &PinImage, profile: &DeviceProfile) -> Result<Vec<u8>, ExportError> {
    need_60x40(profile, "graphiti")?;
    let FamilyParams::Pins(p) = profile.params else { return Err(ExportError("not a pin-matrix bundle".into())) };
    let step = (p.blink_step_ms as u32).max(1);
    let blink = (image.blink_ms / step).min(255) as u8;
    let mut out = Vec::new();
    for (c0, r0) in pages(image, profile) {
        for r in 0..40 {
            for c in 0..60 {
                let pin = image.get(c0 + c, r0 + r);
                out.push(pin.height());
                out.push(if pin.blinks() { blink } else { 0 });
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use taxel_format::{Navigation, Pin, profiles};

    use super::*;

    /// A two-page image (120 x 40) with pins chosen to hit every bit of a cell,
    /// and a title on the text line.
    fn image() -> PinImage {
        let mut im = PinImage::new(120, 40);
        im.navigation = Navigation::Pages;
        for (c, r) in [(0, 0), (1, 3), (3, 1), (58, 36), (59, 39), (61, 2), (119, 39), (64, 20), (65, 21)] {
            im.set(c, r, Pin::new(1, false));
        }
        im.text = vec![0x20, 0x0D, 0x01, 0x0F];
        im
    }

    /// Decodes one DTMS `graphic.data` string into the set of raised pins of
    /// its page, from the description in `reference/pins.md` alone: 300 bytes
    /// as 600 hex digits (high nibble first), one byte per 2 x 4 cell, 30 cells
    /// a line, 10 lines, bit `(y % 4) + (x % 2) * 4`.
    fn decode_graphic(data: &str) -> Vec<(u32, u32)> {
        assert_eq!(data.len(), 600);
        let mut out = Vec::new();
        for i in 0..300u32 {
            let byte = u8::from_str_radix(&data[2 * i as usize..2 * i as usize + 2], 16).unwrap();
            let (cell_x, cell_y) = (i % 30, i / 30);
            for bit in 0..8u32 {
                if byte & (1 << bit) != 0 {
                    out.push((cell_x * 2 + bit / 4, cell_y * 4 + bit % 4));
                }
            }
        }
        out.sort_by_key(|&(x, y)| (y, x));
        out
    }

    #[test]
    fn dtms_graphic_bytes_decode_to_the_pins_of_each_page() {
        let dotpad = profiles::builtin("dotpad").unwrap();
        let im = image();
        let json = dtms(&im, &dotpad, "map.dtms", "Map", "Map").unwrap();
        let v: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(v["title"], "map.dtms");
        assert_eq!(v["device"], "dotpad320");
        let items = v["items"].as_array().unwrap();
        assert_eq!(items.len(), 2, "one page per 60 x 40 pin area");
        for (n, item) in items.iter().enumerate() {
            assert_eq!(item["page"], n + 1);
            assert_eq!(item["title"], "Map");
            let c0 = n as u32 * 60;
            let want: Vec<(u32, u32)> = (0..40)
                .flat_map(|y| (0..60).map(move |x| (x, y)))
                .filter(|&(x, y)| im.get(c0 + x, y).raised())
                .collect();
            assert_eq!(decode_graphic(item["graphic"]["data"].as_str().unwrap()), want, "page {}", n + 1);
            // The text line: six-dot cells, bit 0 = dot 1, padded with 00 to 20 cells.
            let text = item["text"]["data"].as_str().unwrap();
            assert_eq!(text, format!("200D010F{}", "00".repeat(16)));
            assert_eq!(item["text"]["plain"], "Map");
        }
        // The object keys in the sample's order.
        assert!(json.starts_with("{\"title\":\"map.dtms\",\"lang\":\"english\",\"lang_option\":\"1\",\"device\":\"dotpad320\",\"items\":[{\"page\":1,"));
    }

    #[test]
    fn the_dotpad_byte_follows_the_documented_bit_order() {
        // Unicode dots 1 2 3 (left column, top three) keep bits 0 1 2; dot 7 (left, bottom) is bit 3;
        // dots 4 5 6 (right column) move to bits 4 5 6; dot 8 stays bit 7.
        for (u, g) in [(0x01, 0x01), (0x04, 0x04), (0x40, 0x08), (0x08, 0x10), (0x20, 0x40), (0x80, 0x80), (0xFF, 0xFF)]
        {
            assert_eq!(dotpad_byte(u), g, "{u:#04x}");
        }
    }

    #[test]
    fn graphiti_frames_are_height_and_blink_pairs_row_major() {
        let profile = profiles::builtin("graphiti").unwrap();
        let mut im = PinImage::new(60, 40);
        im.set(0, 0, Pin::new(4, false));
        im.set(59, 0, Pin::new(2, true));
        im.set(5, 39, Pin::new(1, false));
        im.blink_ms = 500;
        let f = graphiti(&im, &profile).unwrap();
        assert_eq!(f.len(), 4800);
        let at = |row: usize, col: usize| (f[(row * 60 + col) * 2], f[(row * 60 + col) * 2 + 1]);
        assert_eq!(at(0, 0), (4, 0));
        assert_eq!(at(0, 59), (2, 5), "blinks every 5 x 100 ms");
        assert_eq!(at(39, 5), (1, 0));
        assert_eq!(f.iter().filter(|&&b| b != 0).count(), 4);
        // Other displays' bundles are refused with a reason.
        let e = graphiti(&im, &profiles::builtin("monarch").unwrap()).unwrap_err();
        assert!(e.to_string().contains("monarch (96 x 40"), "{e}");
    }

    #[test]
    fn unicode_art_packs_2_by_4_pins_per_character() {
        let mut im = PinImage::new(4, 4);
        for (c, r) in [(0, 0), (1, 1), (0, 3), (3, 3)] {
            im.set(c, r, Pin::new(1, false));
        }
        // Dots 1, 5, 7 = 0x51; dot 8 = 0x80.
        assert_eq!(unicode(&im), "\u{2851}\u{2880}\n");
    }
}
