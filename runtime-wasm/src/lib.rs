//! taxel's runtime for the browser: the `no_std` players of `taxel-runtime`
//! and the point lookup of `taxel-format`, behind a plain C ABI, compiled to
//! `wasm32-unknown-unknown` and embedded in `taxel studio`. The page plays a
//! bundle through this module; there is no second implementation of the
//! runtime in JavaScript.
//!
//! [`Session`] is the safe Rust API (tested natively); [`abi`] exports it to
//! JavaScript. The ABI has no wasm-bindgen: numbers in, addresses of buffers
//! in linear memory out.
//!
//! - `taxel_input(len) -> ptr`: room for a bundle of `len` bytes; the page
//!   copies the bundle there, then calls `taxel_load() -> 0 | 1` (on 1 the
//!   message is the text buffer).
//! - `taxel_info() -> len`: the profile and the bundle's shape as JSON in the
//!   text buffer (`taxel_text_ptr()`).
//! - `taxel_latero_frame(tick, x, y) -> ptr`: one `u16` code per actuator.
//! - `taxel_pins_frame(tick, x, y) -> ptr`: one byte (pin height) per pin of
//!   the display whose page or viewport holds `(x, y)` mm; `taxel_pins_view()`
//!   gives that viewport's top-left pin as `col + row · 65536`.
//! - `taxel_finger_sample(tick, x, y, contact) -> ptr`: six `f32`: the left,
//!   down and right intensities, the period in ms, the height in mm, and 1
//!   when on a step.
//! - `taxel_grid_frame(tick) -> ptr`: one `f32` amplitude per actuator;
//!   `taxel_grid_end()` the last tick of the strokes.
//! - `taxel_name_at(x, y) -> len`: the name of the element under `(x, y)` mm
//!   (the point lookup) in the text buffer, 0 when none; `taxel_id_at(x, y)`
//!   its id.
//!
//! A module instance plays one bundle: the page instantiates the compiled
//! module afresh for each bundle, so the bundle's bytes live as long as the
//! instance.

use taxel_format::lookup::PointLookup;
use taxel_format::{BundleView, Family, FamilyParams, Mm, Tick};
use taxel_runtime::finger::{FingerPlayer, Touch};
use taxel_runtime::grid::{ActuatorDrive, GridPlayer};
use taxel_runtime::latero::{LateroPlayer, Layer};
use taxel_runtime::pins::{PinsPlayer, Viewport};

pub mod abi;

/// The player of a bundle's device family.
#[derive(Debug)]
enum Player<'a> {
    Latero(LateroPlayer<'a, Vec<Layer<'a>>>),
    Pins(PinsPlayer<'a>),
    Finger(Box<FingerPlayer<'a>>),
    Grid(GridPlayer<'a>),
}

/// One bundle being played: its player, its point lookup and the buffers
/// the frames are written into (allocated once, so a frame allocates nothing).
#[derive(Debug)]
pub struct Session<'a> {
    view: BundleView<'a>,
    player: Player<'a>,
    lookup: Option<PointLookup>,
    codes: Vec<u16>,
    pins: Vec<u8>,
    packed: Vec<u8>,
    levels: Vec<f32>,
    drive: Vec<ActuatorDrive>,
    viewport: Viewport,
}

impl<'a> Session<'a> {
    /// Validates `bytes` as a bundle and builds the player of its family.
    /// The error says why it cannot be played.
    pub fn load(bytes: &'a [u8]) -> Result<Self, String> {
        let view = BundleView::parse(bytes).map_err(|e| format!("not a valid taxel bundle: {e}"))?;
        let profile = view.manifest().profile;
        let n = profile.actuator_count();
        let player = match profile.family() {
            Family::Laterotactile => {
                // Storage for every chunk is always enough for the player's layers.
                let storage = vec![Layer::EMPTY; view.chunk_count() as usize];
                Player::Latero(LateroPlayer::with_storage(&view, storage).map_err(|e| e.to_string())?)
            }
            Family::Pins => Player::Pins(PinsPlayer::new(&view).map_err(|e| e.to_string())?),
            Family::Finger => Player::Finger(Box::new(FingerPlayer::new(&view).map_err(|e| e.to_string())?)),
            Family::Grid => Player::Grid(GridPlayer::new(&view).map_err(|e| e.to_string())?),
            // No bundle holds a print profile (the manifest has no code for it).
            Family::Print => return Err("a print profile makes no bundle".to_string()),
        };
        let packed = match &player {
            Player::Pins(p) => vec![0; p.frame_len()],
            _ => Vec::new(),
        };
        Ok(Session {
            lookup: PointLookup::new(&view, PointLookup::DEFAULT_TOLERANCE_MM),
            view,
            player,
            codes: vec![0; n],
            pins: vec![0; n],
            packed,
            levels: vec![0.0; n.max(6)],
            drive: vec![ActuatorDrive::default(); n],
            viewport: Viewport::ORIGIN,
        })
    }

    /// The profile and the bundle's shape, as a JSON object.
    pub fn info(&self) -> String {
        let p = self.view.manifest().profile;
        let (pages, image) = match &self.player {
            Player::Pins(pl) => (pl.pages(), pl.image_size()),
            _ => ((1, 1), (p.cols as u32, p.rows as u32)),
        };
        let end = match &self.player {
            Player::Grid(g) => g.end().0,
            _ => 0,
        };
        let levels = match p.params {
            FamilyParams::Pins(pp) => pp.height_levels as u32,
            _ => 0,
        };
        format!(
            concat!(
                "{{\"profile\":\"{}\",\"family\":\"{}\",\"rows\":{},\"cols\":{},\"pitch_x_mm\":{},",
                "\"pitch_y_mm\":{},\"rate_hz\":{},\"output_bits\":{},\"surface_w_mm\":{},",
                "\"surface_h_mm\":{},\"pages\":[{},{}],\"image\":[{},{}],\"pin_levels\":{},",
                "\"strokes_end\":{},\"lookup\":{}}}"
            ),
            json_escape(p.name.as_str()),
            p.family().name(),
            p.rows,
            p.cols,
            p.pitch_x_mm,
            p.pitch_y_mm,
            p.rate_hz,
            p.output_bits,
            p.surface_w_mm,
            p.surface_h_mm,
            pages.0,
            pages.1,
            image.0,
            image.1,
            levels,
            end,
            self.lookup.is_some()
        )
    }

    /// The latero frame at `tick` with the array at `(x, y)` mm: one code per
    /// actuator (`cols · row + col`), as [`LateroPlayer::frame`] writes it;
    /// empty for another family.
    pub fn latero_frame(&mut self, tick: Tick, x: f32, y: f32) -> &[u16] {
        match &self.player {
            Player::Latero(p) => {
                p.frame(tick, Mm(x), Mm(y), &mut self.codes);
                &self.codes
            }
            _ => &[],
        }
    }

    /// The pin display's frame at `tick` on the page (or, on a pannable
    /// image, the viewport centred) where `(x, y)` mm lies: each pin's
    /// height, one byte per pin, row-major, unpacked from the player's
    /// bit-packed frame; empty for another family.
    pub fn pins_frame(&mut self, tick: Tick, x: f32, y: f32) -> &[u8] {
        let Player::Pins(p) = &self.player else { return &[] };
        let profile = self.view.manifest().profile;
        let (cols, rows) = p.display();
        let pin = |mm: f32, pitch: f32| if mm.is_finite() && pitch > 0.0 { (mm / pitch).max(0.0) as u32 } else { 0 };
        let (c, r) = (pin(x, profile.pitch_x_mm), pin(y, profile.pitch_y_mm));
        let want = match p.navigation() {
            taxel_format::Navigation::Pages => Viewport { col: c, row: r },
            taxel_format::Navigation::Pan => {
                Viewport { col: c.saturating_sub(cols / 2), row: r.saturating_sub(rows / 2) }
            }
        };
        self.viewport = p.settle(want);
        p.frame(tick, self.viewport, &mut self.packed);
        let bits = profile.output_bits as usize;
        let mask = (1u16 << bits) - 1;
        for (i, h) in self.pins.iter_mut().enumerate() {
            let at = i * bits;
            let byte = self.packed.get(at / 8).copied().unwrap_or(0) as u16;
            *h = ((byte >> (at % 8)) & mask) as u8;
        }
        &self.pins
    }

    /// The viewport of the last [`Session::pins_frame`]: its top-left pin on the image.
    pub fn pins_viewport(&self) -> (u32, u32) {
        (self.viewport.col, self.viewport.row)
    }

    /// The finger device's drive for one touch sample: the left, down and
    /// right intensities, the period in ms, the height in mm, and 1 on a
    /// step; empty for another family.
    pub fn finger_sample(&mut self, tick: Tick, x: f32, y: f32, contact: bool) -> &[f32] {
        let Player::Finger(p) = &mut self.player else { return &[] };
        let f = p.sample(Touch { tick, x: Mm(x), y: Mm(y), contact });
        let [l, d, r] = f.levels();
        self.levels[..6].copy_from_slice(&[l, d, r, f.period_ms, f.height, if f.on_edge { 1.0 } else { 0.0 }]);
        &self.levels[..6]
    }

    /// The grid's actuator amplitudes at `tick` (the brushed strokes play on
    /// their own clock, wherever the finger is); empty for another family.
    pub fn grid_frame(&mut self, tick: Tick) -> &[f32] {
        let Player::Grid(g) = &self.player else { return &[] };
        g.frame(tick, &mut self.drive);
        let n = self.drive.len();
        for (l, d) in self.levels.iter_mut().zip(&self.drive) {
            *l = d.amplitude;
        }
        &self.levels[..n]
    }

    /// The name of the element under `(x, y)` mm (the bundle's point
    /// lookup): its label, else its id; `None` on nothing or without footprints.
    pub fn name_at(&self, x: f64, y: f64) -> Option<String> {
        self.lookup.as_ref()?.under(x, y).map(|h| h.name())
    }

    /// The id of the element under `(x, y)` mm (empty when it has none).
    pub fn id_at(&self, x: f64, y: f64) -> Option<String> {
        self.lookup.as_ref()?.under(x, y).map(|h| h.entry.map_or(String::new(), |e| e.id.clone()))
    }
}

/// `s` as the inside of a JSON string.
fn json_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out
}

/// A tick given by JavaScript as a number: whole, non-negative and finite,
/// else 0 (a `u64` crosses the ABI as a BigInt; an `f64` holds every tick
/// below 2^53, 285 years at 1 kHz).
pub fn tick_of(t: f64) -> Tick {
    if t.is_finite() && t >= 0.0 { Tick(t as u64) } else { Tick(0) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bundle_that_is_not_one_is_refused_with_the_format_s_reason() {
        let e = Session::load(b"not a bundle").unwrap_err();
        assert!(e.starts_with("not a valid taxel bundle: "), "{e}");
    }

    #[test]
    fn an_empty_stress2_bundle_plays_at_rest_and_names_nothing() {
        use taxel_format::{Bundle, Manifest, profiles};
        let profile = profiles::builtin("stress2").unwrap();
        let bytes = Bundle::new(Manifest::new(profile)).to_bytes().unwrap();
        let mut s = Session::load(&bytes).unwrap();
        let frame = s.latero_frame(Tick(5), 10.0, 10.0);
        assert_eq!(frame.len(), profile.actuator_count());
        assert!(frame.iter().all(|&c| c == frame[0]));
        assert_eq!(s.name_at(10.0, 10.0), None);
        assert!(s.pins_frame(Tick(0), 0.0, 0.0).is_empty());
        assert!(s.info().contains("\"family\":\"laterotactile\""), "{}", s.info());
    }

    #[test]
    fn ticks_from_javascript_numbers() {
        assert_eq!(tick_of(12.0), Tick(12));
        assert_eq!(tick_of(-1.0), Tick(0));
        assert_eq!(tick_of(f64::NAN), Tick(0));
    }
}
