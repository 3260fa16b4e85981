//! The player for refreshable pin-matrix displays (device family 4: Dot Pad,
//! Monarch, Graphiti, HyperBraille): the bundle's pin image in, the display's
//! bit-packed pin frame out.
//!
//! A [`PinsPlayer`] is built once from a validated [`BundleView`] and keeps a
//! zero-copy view of the bundle's pin image. [`PinsPlayer::frame`] gives, for
//! a tick and a viewport, every pin of the display packed at the profile's
//! `output_bits` per pin (pin `i = row * cols + col` in bits
//! `i * bits .. (i + 1) * bits`, least significant bit first within each
//! byte): 1 bit on a binary display, the height on a display with heights.
//! A blinking pin shows its height in the blink's up phase and 0 in its down
//! phase, and the phase comes from the integer tick alone (SPEC.md section
//! 14), so nothing drifts however long it plays. The frame path does not
//! allocate and cannot panic.
//!
//! ```
//! use taxel_format::{Bundle, BundleView, Chunk, Manifest, Pin, PinImage, Tick, profiles};
//! use taxel_runtime::pins::{PinsPlayer, Viewport};
//!
//! let mut image = PinImage::new(60, 40);
//! image.set(0, 0, Pin::new(1, false));
//! image.set(9, 1, Pin::new(1, false));
//! let mut bundle = Bundle::new(Manifest::new(profiles::builtin("dotpad").unwrap()));
//! bundle.chunks.push(Chunk::Pins(image));
//! let bytes = bundle.to_bytes().unwrap();
//! let view = BundleView::parse(&bytes).unwrap();
//! let player = PinsPlayer::new(&view).unwrap();
//! let mut frame = [0u8; 300]; // 60 x 40 pins at 1 bit
//! assert_eq!(player.frame(Tick(0), Viewport::ORIGIN, &mut frame), 300);
//! assert_eq!(frame[0], 0b1); // pin 0
//! assert_eq!(frame[8], 0b10_0000); // pin 69 = row 1, col 9: byte 8, bit 5
//! ```

use taxel_format::{BundleView, ChunkView, Family, FamilyParams, Navigation, PinImageView, Tag, Tick};

use crate::error::RuntimeError;

/// Where the display's top-left pin is on the image, in image pins.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Viewport {
    /// Image column shown at the display's column 0.
    pub col: u32,
    /// Image row shown at the display's row 0.
    pub row: u32,
}

impl Viewport {
    /// The image's top-left corner.
    pub const ORIGIN: Viewport = Viewport { col: 0, row: 0 };
}

/// Plays the pin image of a pin-matrix bundle.
#[derive(Debug, Clone, Copy)]
pub struct PinsPlayer<'a> {
    image: Option<PinImageView<'a>>,
    cols: u32,
    rows: u32,
    bits: u32,
    levels: u8,
    rate_hz: u32,
}

impl<'a> PinsPlayer<'a> {
    /// A player for a validated pin-matrix bundle. Refuses bundles of another
    /// family. A bundle without a pin image plays as a flush display.
    /// Allocates nothing.
    pub fn new(view: &BundleView<'a>) -> Result<Self, RuntimeError> {
        let profile = view.manifest().profile;
        let FamilyParams::Pins(p) = profile.params else {
            return Err(RuntimeError::WrongFamily {
                expected: Family::Pins,
                found: profile.family(),
                profile: profile.name,
            });
        };
        let mut image = None;
        for chunk in view.chunks() {
            match chunk {
                ChunkView::Pins(v) => image = Some(v),
                ChunkView::Provenance(_) | ChunkView::Footprints(_) | ChunkView::Unknown { .. } => {}
                // The reader refuses other layers in a pin bundle; this is the player's own guard.
                ChunkView::Mask(m) => return Err(unexpected(m.kind.tag())),
                ChunkView::Distance(d) => return Err(unexpected(d.tag())),
                ChunkView::Dots(_) => return Err(unexpected(Tag::DOTS)),
                ChunkView::Strokes(_) => return Err(unexpected(Tag::STROKES)),
                ChunkView::Height(_) => return Err(unexpected(Tag::HEIGHT)),
            }
        }
        Ok(PinsPlayer {
            image,
            cols: profile.cols as u32,
            rows: profile.rows as u32,
            bits: profile.output_bits as u32,
            levels: p.height_levels,
            rate_hz: profile.rate_hz,
        })
    }

    /// Bytes of one frame: `ceil(rows * cols * output_bits / 8)`.
    pub fn frame_len(&self) -> usize {
        (self.rows as usize * self.cols as usize * self.bits as usize).div_ceil(8)
    }

    /// The display's size `(cols, rows)`.
    pub fn display(&self) -> (u32, u32) {
        (self.cols, self.rows)
    }

    /// The image's size `(cols, rows)` (the display's when there is no image).
    pub fn image_size(&self) -> (u32, u32) {
        self.image.map_or((self.cols, self.rows), |v| (v.cols(), v.rows()))
    }

    /// How the viewport moves over an image larger than the display.
    pub fn navigation(&self) -> Navigation {
        self.image.map_or(Navigation::Pages, |v| v.navigation())
    }

    /// Pages across and down: how many displays it takes to cover the image.
    pub fn pages(&self) -> (u32, u32) {
        let (c, r) = self.image_size();
        (c.div_ceil(self.cols).max(1), r.div_ceil(self.rows).max(1))
    }

    /// The viewport of page `index` (row-major over [`PinsPlayer::pages`]), if there is such a page.
    pub fn page(&self, index: u32) -> Option<Viewport> {
        let (across, down) = self.pages();
        (index < across.saturating_mul(down))
            .then(|| Viewport { col: (index % across) * self.cols, row: (index / across) * self.rows })
    }

    /// The viewport a request lands on: on a paged image, the page that
    /// holds the requested top-left pin; on a pannable surface the request
    /// itself, kept so that the display stays on the image.
    pub fn settle(&self, want: Viewport) -> Viewport {
        let (c, r) = self.image_size();
        match self.navigation() {
            Navigation::Pages => Viewport {
                col: want.col.min(c.saturating_sub(1)) / self.cols * self.cols,
                row: want.row.min(r.saturating_sub(1)) / self.rows * self.rows,
            },
            Navigation::Pan => Viewport {
                col: want.col.min(c.saturating_sub(self.cols)),
                row: want.row.min(r.saturating_sub(self.rows)),
            },
        }
    }

    /// Whether blinking pins are up at `tick`: up when
    /// `floor(tick * 1000 / (rate_hz * blink_ms))` is even (SPEC.md section 14).
    /// Always true when no pin blinks.
    pub fn blink_up(&self, tick: Tick) -> bool {
        let blink_ms = self.image.map_or(0, |v| v.blink_ms()) as u64;
        if blink_ms == 0 {
            return true;
        }
        let span = self.rate_hz as u64 * blink_ms;
        // Reducing modulo two half-periods first keeps the product in range for any tick.
        let k = tick.0 % (2 * span);
        (k * 1000 / span).is_multiple_of(2)
    }

    /// Writes the frame for `tick` with the display's top-left pin at image
    /// pin `viewport` (taken as given; see [`PinsPlayer::settle`]) into
    /// `out`, and returns the bytes written: [`PinsPlayer::frame_len`], or
    /// fewer when `out` is shorter (pins that do not fit are left out).
    pub fn frame(&self, tick: Tick, viewport: Viewport, out: &mut [u8]) -> usize {
        let len = self.frame_len().min(out.len());
        let out = &mut out[..len];
        out.fill(0);
        let Some(image) = self.image else { return len };
        let up = self.blink_up(tick);
        let bits = self.bits as usize;
        let mask = ((1u32 << self.bits) - 1) as u8;
        for r in 0..self.rows {
            let Some(src_row) = viewport.row.checked_add(r) else { break };
            let row = image.row(src_row);
            let start = (viewport.col as usize).min(row.len());
            let end = (viewport.col as usize).saturating_add(self.cols as usize).min(row.len());
            let Some(src) = row.get(start..end) else { continue };
            let base = r as usize * self.cols as usize * bits;
            for (c, &b) in src.iter().enumerate() {
                let pin = taxel_format::Pin::from_byte(b);
                let h = if pin.blinks() && !up { 0 } else { pin.height().min(self.levels) };
                if h == 0 {
                    continue;
                }
                let at = base + c * bits;
                if let Some(byte) = out.get_mut(at / 8) {
                    *byte |= (h & mask) << (at % 8);
                }
            }
        }
        len
    }
}

fn unexpected(tag: Tag) -> RuntimeError {
    RuntimeError::UnexpectedChunk { family: Family::Pins, tag }
}

#[cfg(test)]
mod tests;
