//! The pin image (`PINS`): a drawing legalised for a pin-matrix display, at
//! pin resolution, with a height and a blink flag per pin, plus the cells of
//! the device's separate braille text line.
//!
//! The image covers the whole (fitted) drawing, so it may be larger than the
//! display: a player shows the part under a viewport, which moves either a
//! page at a time or freely ([`Navigation`]).

use alloc::vec::Vec;

use crate::Tag;
use crate::bytes::{Out, u8_at, u16_at, u32_at};
use crate::error::FormatError;
use crate::profile::{DeviceProfile, FamilyParams};

const HEADER_LEN: usize = 32;
/// Largest width or height of a pin image, in pins.
pub const MAX_PIN_SIDE: u32 = 8192;
/// Largest number of pins in one pin image (16 Mi).
pub const MAX_PIN_IMAGE: u32 = 1 << 24;
/// Largest number of text-line cells in one pin image.
pub const MAX_TEXT_CELLS: u32 = 4096;
/// Longest blink half-period, in milliseconds.
pub const MAX_BLINK_MS: u32 = 600_000;

/// Bit of a pin byte that says the pin blinks.
const BLINK_BIT: u8 = 0x80;
/// Bits of a pin byte that hold its height.
const HEIGHT_BITS: u8 = 0x0F;

/// One pin: its raised height (0 = flush) and whether it blinks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Pin(u8);

impl Pin {
    /// A flush pin.
    pub const FLUSH: Pin = Pin(0);

    /// A pin at `height` (0 to 15; higher values are clamped to 15), blinking
    /// or not. A flush pin never blinks.
    pub fn new(height: u8, blink: bool) -> Self {
        let h = height.min(HEIGHT_BITS);
        Pin(h | if blink && h > 0 { BLINK_BIT } else { 0 })
    }

    /// Raised height, 0 for flush.
    pub fn height(self) -> u8 {
        self.0 & HEIGHT_BITS
    }

    /// Whether the pin blinks.
    pub fn blinks(self) -> bool {
        self.0 & BLINK_BIT != 0
    }

    /// Whether the pin is raised at all.
    pub fn raised(self) -> bool {
        self.height() > 0
    }

    /// The byte stored in a bundle.
    pub fn to_byte(self) -> u8 {
        self.0
    }

    /// The pin of a stored byte (not validated: see [`PinImageView`]).
    pub fn from_byte(b: u8) -> Self {
        Pin(b)
    }
}

/// How a reader moves over an image larger than the display.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Navigation {
    /// A pannable surface: the viewport may start at any pin.
    #[default]
    Pan,
    /// Pages: the viewport starts at whole multiples of the display's size.
    Pages,
}

impl Navigation {
    fn code(self) -> u8 {
        match self {
            Navigation::Pan => 0,
            Navigation::Pages => 1,
        }
    }

    fn from_code(c: u8) -> Option<Self> {
        match c {
            0 => Some(Navigation::Pan),
            1 => Some(Navigation::Pages),
            _ => None,
        }
    }

    /// The name used in reports (`pan`, `pages`).
    pub fn name(self) -> &'static str {
        match self {
            Navigation::Pan => "pan",
            Navigation::Pages => "pages",
        }
    }
}

/// The owned pin image.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct PinImage {
    /// Width in pins.
    pub cols: u32,
    /// Height in pins.
    pub rows: u32,
    /// Blink half-period in milliseconds: a blinking pin is up this long,
    /// then down this long. 0 when no pin blinks.
    pub blink_ms: u32,
    /// How the viewport moves.
    pub navigation: Navigation,
    /// `cols * rows` pins, row-major, top row first.
    pub pins: Vec<Pin>,
    /// The text line's cells (Unicode braille dot masks: bit 0 = dot 1 ... bit 7 = dot 8).
    pub text: Vec<u8>,
}

impl PinImage {
    /// A flush image of `cols` x `rows` pins.
    pub fn new(cols: u32, rows: u32) -> Self {
        PinImage { cols, rows, pins: alloc::vec![Pin::FLUSH; cols as usize * rows as usize], ..Default::default() }
    }

    /// Pin `(col, row)`, flush outside the image.
    pub fn get(&self, col: u32, row: u32) -> Pin {
        if col >= self.cols || row >= self.rows {
            return Pin::FLUSH;
        }
        self.pins.get(row as usize * self.cols as usize + col as usize).copied().unwrap_or(Pin::FLUSH)
    }

    /// Sets pin `(col, row)`; outside the image nothing happens.
    pub fn set(&mut self, col: u32, row: u32, pin: Pin) {
        if col < self.cols
            && row < self.rows
            && let Some(p) = self.pins.get_mut(row as usize * self.cols as usize + col as usize)
        {
            *p = pin;
        }
    }

    pub(crate) fn check_shape(&self, index: u32) -> Result<(), FormatError> {
        let tag = Tag::PINS;
        if self.pins.len() as u64 != self.cols as u64 * self.rows as u64 {
            return Err(FormatError::InvalidValue { tag, index, field: "pins", expected: "cols * rows pins" });
        }
        Ok(())
    }

    pub(crate) fn encode(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(HEADER_LEN + self.pins.len() + self.text.len());
        let mut w = Out(&mut out);
        w.u32(self.cols)
            .u32(self.rows)
            .u32(self.blink_ms)
            .u16(self.text.len().min(u16::MAX as usize) as u16)
            .u8(self.navigation.code())
            .u8(0)
            .zeros(16);
        out.extend(self.pins.iter().map(|p| p.0));
        out.extend_from_slice(&self.text);
        out
    }

    pub(crate) fn from_view(v: &PinImageView<'_>) -> Self {
        PinImage {
            cols: v.cols,
            rows: v.rows,
            blink_ms: v.blink_ms,
            navigation: v.navigation,
            pins: v.pins.iter().map(|&b| Pin(b)).collect(),
            text: v.text.to_vec(),
        }
    }
}

/// A validated pin image, read in place.
#[derive(Debug, Clone, Copy)]
pub struct PinImageView<'a> {
    cols: u32,
    rows: u32,
    blink_ms: u32,
    navigation: Navigation,
    pins: &'a [u8],
    text: &'a [u8],
}

impl<'a> PinImageView<'a> {
    /// Width in pins.
    pub fn cols(&self) -> u32 {
        self.cols
    }

    /// Height in pins.
    pub fn rows(&self) -> u32 {
        self.rows
    }

    /// Blink half-period in milliseconds (0 when no pin blinks).
    pub fn blink_ms(&self) -> u32 {
        self.blink_ms
    }

    /// How the viewport moves.
    pub fn navigation(&self) -> Navigation {
        self.navigation
    }

    /// Pin `(col, row)`, flush outside the image.
    #[inline]
    pub fn get(&self, col: u32, row: u32) -> Pin {
        if col >= self.cols || row >= self.rows {
            return Pin::FLUSH;
        }
        Pin(u8_at(self.pins, row as usize * self.cols as usize + col as usize).unwrap_or(0))
    }

    /// Row `row`'s pin bytes (empty outside the image).
    #[inline]
    pub fn row(&self, row: u32) -> &'a [u8] {
        if row >= self.rows {
            return &[];
        }
        let start = row as usize * self.cols as usize;
        self.pins.get(start..start + self.cols as usize).unwrap_or(&[])
    }

    /// The text line's cells (Unicode braille dot masks).
    pub fn text(&self) -> &'a [u8] {
        self.text
    }

    /// Reads and validates the chunk against the bundle's profile: sizes
    /// within the limits, heights within the profile's levels, blinking only
    /// where the profile can blink (at a multiple of its blink step), text
    /// cells only where it has a text line. With `full`, every pin is checked.
    pub(crate) fn parse(d: &'a [u8], index: u32, profile: &DeviceProfile, full: bool) -> Result<Self, FormatError> {
        let tag = Tag::PINS;
        let bad = |field, expected| FormatError::InvalidValue { tag, index, field, expected };
        FormatError::check_header(d, HEADER_LEN, tag, index)?;
        let FamilyParams::Pins(params) = profile.params else {
            return Err(bad("chunk", "a pin image only in a bundle for a pin-matrix profile (family 4)"));
        };
        let cols = u32_at(d, 0).unwrap_or(0);
        let rows = u32_at(d, 4).unwrap_or(0);
        let blink_ms = u32_at(d, 8).unwrap_or(0);
        let text_len = u16_at(d, 12).unwrap_or(0) as u32;
        let navigation =
            Navigation::from_code(u8_at(d, 14).unwrap_or(0)).ok_or(bad("navigation", "0 pan or 1 pages"))?;
        if u8_at(d, 15) != Some(0) || d[16..HEADER_LEN].iter().any(|&b| b != 0) {
            return Err(bad("reserved", "zero"));
        }
        for (field, v) in [("cols", cols), ("rows", rows)] {
            if v == 0 {
                return Err(bad(field, "at least 1 pin"));
            }
            if v > MAX_PIN_SIDE {
                return Err(FormatError::Limit { tag, field, value: v as u64, limit: MAX_PIN_SIDE as u64 });
            }
        }
        let n = cols as u64 * rows as u64;
        if n > MAX_PIN_IMAGE as u64 {
            return Err(FormatError::Limit { tag, field: "cols * rows", value: n, limit: MAX_PIN_IMAGE as u64 });
        }
        if text_len > MAX_TEXT_CELLS {
            return Err(FormatError::Limit {
                tag,
                field: "text cells",
                value: text_len as u64,
                limit: MAX_TEXT_CELLS as u64,
            });
        }
        if text_len > 0 && params.text_cells == 0 {
            return Err(bad("text cells", "none: the profile has no braille text line"));
        }
        if blink_ms > MAX_BLINK_MS {
            return Err(FormatError::Limit {
                tag,
                field: "blink_ms",
                value: blink_ms as u64,
                limit: MAX_BLINK_MS as u64,
            });
        }
        if blink_ms > 0 && (params.blink_step_ms == 0 || !blink_ms.is_multiple_of(params.blink_step_ms as u32)) {
            return Err(bad("blink_ms", "0, or a multiple of the profile's blink step where it can blink"));
        }
        let expected = HEADER_LEN as u64 + n + text_len as u64;
        if d.len() as u64 != expected {
            return Err(FormatError::ChunkLength { tag, index, expected, found: d.len() as u64 });
        }
        let split = HEADER_LEN + n as usize;
        let view = PinImageView { cols, rows, blink_ms, navigation, pins: &d[HEADER_LEN..split], text: &d[split..] };
        if !full {
            return Ok(view);
        }
        let mut any_blink = false;
        for &b in view.pins {
            let p = Pin(b);
            if b & !(BLINK_BIT | HEIGHT_BITS) != 0 {
                return Err(bad("pin", "reserved bits 4 to 6 zero"));
            }
            if p.height() > params.height_levels {
                return Err(bad("pin height", "at most the profile's height levels"));
            }
            if p.blinks() && !p.raised() {
                return Err(bad("pin", "a blinking pin raised (height at least 1)"));
            }
            any_blink |= p.blinks();
        }
        // One encoding: the period is given exactly when some pin blinks.
        if any_blink != (blink_ms > 0) {
            return Err(bad("blink_ms", "above 0 exactly when some pin blinks"));
        }
        Ok(view)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Bundle, BundleView, Chunk, DotKind, DotTable, Manifest, profiles};

    fn bundle(profile: &str, image: PinImage) -> Bundle {
        let mut b = Bundle::new(Manifest::new(profiles::builtin(profile).unwrap()));
        b.chunks.push(Chunk::Pins(image));
        b
    }

    fn sample() -> PinImage {
        let mut im = PinImage::new(3, 2);
        im.set(0, 0, Pin::new(4, true));
        im.set(2, 1, Pin::new(2, false));
        im.blink_ms = 500;
        im.navigation = Navigation::Pages;
        im
    }

    #[test]
    fn round_trips_through_the_canonical_bytes() {
        let b = bundle("graphiti", sample());
        let bytes = b.to_bytes().unwrap();
        let view = BundleView::parse(&bytes).unwrap();
        let v = view.pin_image().unwrap();
        assert_eq!((v.cols(), v.rows(), v.blink_ms(), v.navigation()), (3, 2, 500, Navigation::Pages));
        assert_eq!(v.get(0, 0), Pin::new(4, true));
        assert_eq!(v.get(2, 1).height(), 2);
        assert_eq!(v.get(3, 0), Pin::FLUSH, "outside the image is flush");
        assert_eq!(v.row(1), &[0, 0, 2]);
        assert_eq!(Bundle::from_view(&view), b);
        // The chunk is the 32-byte header, one byte per pin, no text.
        let (_, _, _, len) = view.chunk_entry(1).unwrap();
        assert_eq!(len, 32 + 6);
    }

    #[test]
    fn text_cells_follow_the_pins() {
        let mut im = PinImage::new(2, 2);
        im.text = alloc::vec![0x01, 0x3f];
        let bytes = bundle("dotpad", im).to_bytes().unwrap();
        let view = BundleView::parse(&bytes).unwrap();
        assert_eq!(view.pin_image().unwrap().text(), &[0x01, 0x3f]);
    }

    fn refused(profile: &str, im: PinImage) -> FormatError {
        bundle(profile, im).to_bytes().unwrap_err()
    }

    #[test]
    fn images_the_profile_cannot_show_are_refused() {
        // Heights above the profile's levels.
        let mut im = PinImage::new(2, 1);
        im.set(0, 0, Pin::new(2, false));
        assert!(matches!(refused("dotpad", im), FormatError::InvalidValue { field: "pin height", .. }));
        // Blinking on a device that cannot blink.
        let mut im = PinImage::new(2, 1);
        im.set(0, 0, Pin::new(1, true));
        im.blink_ms = 100;
        assert!(matches!(refused("dotpad", im), FormatError::InvalidValue { field: "blink_ms", .. }));
        // A blink period that is not a multiple of the device's 100 ms step.
        let mut im = sample();
        im.blink_ms = 150;
        assert!(matches!(refused("graphiti", im), FormatError::InvalidValue { field: "blink_ms", .. }));
        // A period without a blinking pin, and a blinking pin without a period.
        let mut im = PinImage::new(2, 1);
        im.blink_ms = 100;
        assert!(matches!(refused("graphiti", im), FormatError::InvalidValue { field: "blink_ms", .. }));
        let mut im = sample();
        im.blink_ms = 0;
        assert!(matches!(refused("graphiti", im), FormatError::InvalidValue { field: "blink_ms", .. }));
        // Text cells on a device without a text line.
        let mut im = PinImage::new(2, 1);
        im.text = alloc::vec![1];
        assert!(matches!(refused("monarch", im), FormatError::InvalidValue { field: "text cells", .. }));
        // Zero and huge sizes.
        assert!(matches!(refused("dotpad", PinImage::new(0, 4)), FormatError::InvalidValue { field: "cols", .. }));
        let huge = PinImage { cols: MAX_PIN_SIDE + 1, rows: 1, ..Default::default() };
        assert!(matches!(refused("dotpad", huge), FormatError::InvalidValue { field: "pins", .. }));
        // A pin image in another family's bundle, other layers in a pin bundle, two images.
        assert!(matches!(refused("stress2", sample()), FormatError::InvalidValue { field: "chunk", .. }));
        let mut b = bundle("dotpad", PinImage::new(1, 1));
        b.chunks.push(Chunk::Dots(DotTable { kind: DotKind::Symbol, dots: alloc::vec![] }));
        assert!(matches!(b.to_bytes().unwrap_err(), FormatError::ChunkOrder { .. }));
        let mut b = bundle("dotpad", PinImage::new(1, 1));
        b.chunks.push(Chunk::Pins(PinImage::new(1, 1)));
        assert!(matches!(b.to_bytes().unwrap_err(), FormatError::ChunkOrder { .. }));
    }

    #[test]
    fn hostile_chunk_bytes_are_refused_without_panic() {
        let good = bundle("graphiti", sample()).to_bytes().unwrap();
        let view = BundleView::parse(&good).unwrap();
        let (_, _, off, len) = view.chunk_entry(1).unwrap();
        let chunk = &good[off as usize..(off + len) as usize];
        let profile = profiles::builtin("graphiti").unwrap();
        // Every truncation and a header claiming a huge image.
        for cut in 0..chunk.len() {
            assert!(PinImageView::parse(&chunk[..cut], 1, &profile, true).is_err(), "cut at {cut}");
        }
        let mut big = chunk.to_vec();
        big[0..4].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(matches!(PinImageView::parse(&big, 1, &profile, true), Err(FormatError::Limit { .. })));
        big[0..4].copy_from_slice(&8192u32.to_le_bytes());
        big[4..8].copy_from_slice(&8192u32.to_le_bytes());
        assert!(matches!(PinImageView::parse(&big, 1, &profile, true), Err(FormatError::Limit { .. })));
        // Reserved pin bits, reserved header bytes, an unknown navigation.
        for (at, v) in [(32usize, 0x10u8), (15, 1), (20, 1), (14, 2)] {
            let mut bad = chunk.to_vec();
            bad[at] = v;
            assert!(PinImageView::parse(&bad, 1, &profile, true).is_err(), "byte {at} = {v}");
        }
    }
}
