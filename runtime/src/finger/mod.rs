//! Player for the finger-mounted device family (seed 002): a ring of three
//! actuators, Left, Down and Right, driven by the height field under the
//! finger and the direction the finger moves.
//!
//! For each touch sample the player finds the height `h` and gradient ∇h
//! under the finger ([`field::sample`]), the motion direction `V` averaged
//! over the profile's `direction_window` samples, and the local gradient
//! `∇f = ∇h · V` (the slope along the motion, eq. 3). Then (eq. 4, 5):
//!
//! - intensity `D = k2 · |h|`, with `k2 = intensity_max / max |h|`;
//! - rhythm `R = k1 · |∇f|`, with `k1 = rhythm_max / max |∇h|`, and the
//!   modulating period `T = (105 − R) / 0.5` ms;
//! - the active actuator (Tab. 1) from the slope the finger meets, seen
//!   left to right: `s = ∇f · V_x`. For a finger moving right `s = ∂h/∂x`;
//!   moving left it is the same `∂h/∂x`, so the choice follows the surface,
//!   not the stroke: a surface declining from left to right (`s < 0`) is
//!   Left, rising (`s > 0`, declining from right to left) is Right, and
//!   `|s| <= flat_slope` is flat, Down. A vertical stroke has `V_x = 0` and
//!   gives Down, as the paper reports for a vertical slide over the convex
//!   surface. Sliding left to right over a convex bump this gives Right,
//!   Down, Left, the paper's order (Fig. 5(d)).
//!
//! A finger that has moved less than `min_move_mm` over the window has no
//! direction: it gets Down at the height's intensity and the slowest
//! rhythm. Lifting the finger (no contact) switches everything off and
//! forgets the direction. Per sample: no allocation, no panic, and time is
//! only ever the caller's integer tick.

pub mod field;

use taxel_format::{BundleView, ChunkView, Family, FamilyParams, FieldReader, FingerParams, HeightFieldView, Mm, Tick};

pub use field::SurfacePoint;

/// Most steps the direction window spans (the profile allows 1..=64); the
/// window holds one sample more than it has steps.
const WINDOW_MAX: usize = 64;

/// Capacity of the ring of recent positions: the power of two above the
/// largest window's `WINDOW_MAX + 1` samples, so that slots are found with a
/// mask instead of a division by 65.
const RING: usize = 128;
const RING_MASK: usize = RING - 1;

/// One of the three actuators. The discriminant is its index in a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Actuator {
    /// Left side of the fingertip.
    Left = 0,
    /// Under the fingertip.
    Down = 1,
    /// Right side of the fingertip.
    Right = 2,
}

impl Actuator {
    /// All three, in frame order.
    pub const ALL: [Actuator; 3] = [Actuator::Left, Actuator::Down, Actuator::Right];

    /// Lower-case name, as in the motors CSV header.
    pub fn name(self) -> &'static str {
        match self {
            Actuator::Left => "left",
            Actuator::Down => "down",
            Actuator::Right => "right",
        }
    }
}

/// One touch sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Touch {
    /// When, in ticks of the profile's rate.
    pub tick: Tick,
    /// Page x in mm.
    pub x: Mm,
    /// Page y in mm (down).
    pub y: Mm,
    /// Whether the finger touches the screen.
    pub contact: bool,
}

/// What the player drives for one sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FingerFrame {
    /// The sample's tick.
    pub tick: Tick,
    /// The vibrating actuator, or `None` when off (no contact with the surface).
    pub active: Option<Actuator>,
    /// Intensity D of the active actuator (0..=intensity_max).
    pub intensity: f32,
    /// Rhythm R (0..=rhythm_max).
    pub rhythm: f32,
    /// Modulating period T in ms, `(105 − R) / 0.5`.
    pub period_ms: f32,
    /// Height under the finger, mm.
    pub height: f32,
    /// Local gradient ∇f (slope along the motion); 0 without a direction.
    pub local_gradient: f32,
    /// Whether the finger has a direction.
    pub moving: bool,
    /// Whether the finger is at a step.
    pub on_edge: bool,
}

impl FingerFrame {
    /// The off frame.
    pub const fn off(tick: Tick) -> Self {
        FingerFrame {
            tick,
            active: None,
            intensity: 0.0,
            rhythm: 0.0,
            period_ms: 0.0,
            height: 0.0,
            local_gradient: 0.0,
            moving: false,
            on_edge: false,
        }
    }

    /// Intensity per actuator (Left, Down, Right): the active one's D, zero for the others.
    pub fn levels(&self) -> [f32; 3] {
        let mut out = [0.0; 3];
        if let Some(a) = self.active {
            out[a as usize] = self.intensity;
        }
        out
    }
}

/// Why a bundle cannot be played on the finger device.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FingerError {
    /// The bundle was compiled for another device family.
    WrongFamily(Family),
    /// The bundle has no height field.
    NoHeightField,
}

impl core::fmt::Display for FingerError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            FingerError::WrongFamily(fam) => {
                write!(f, "the bundle was compiled for a {fam} device, not a finger device")
            }
            FingerError::NoHeightField => write!(f, "the bundle has no height field"),
        }
    }
}

/// Plays a height field on the three-actuator ring.
#[derive(Debug, Clone)]
pub struct FingerPlayer<'a> {
    // The field, and for a tiled one (format 4.6) the tiles decoded so
    // far: a finger that stays in a tile decodes it once.
    field: FieldReader<'a>,
    params: FingerParams,
    k1: f32,
    k2: f32,
    ring: [(f32, f32); RING],
    len: usize,
    head: usize,
}

impl<'a> FingerPlayer<'a> {
    /// A player for a validated bundle: its profile's parameters and its first height field.
    pub fn new(bundle: &BundleView<'a>) -> Result<Self, FingerError> {
        let profile = bundle.manifest().profile;
        let FamilyParams::Finger(params) = profile.params else {
            return Err(FingerError::WrongFamily(profile.family()));
        };
        let field = bundle
            .chunks()
            .find_map(|c| match c {
                ChunkView::Height(h) => Some(h),
                _ => None,
            })
            .ok_or(FingerError::NoHeightField)?;
        Ok(Self::with_field(field, params))
    }

    /// A player for one field and a profile's parameters.
    pub fn with_field(field: HeightFieldView<'a>, params: FingerParams) -> Self {
        let hmax = libm::fabsf(field.height_min).max(libm::fabsf(field.height_max));
        let gmax = field.max_gradient;
        // The paper's k1 and k2 map the largest gradient and height to the
        // largest rhythm and intensity; a flat or zero-height field gets 0.
        let k1 = if gmax > 0.0 { params.rhythm_max / gmax } else { 0.0 };
        let k2 = if hmax > 0.0 { params.intensity_max / hmax } else { 0.0 };
        FingerPlayer { field: FieldReader::new(field), params, k1, k2, ring: [(0.0, 0.0); RING], len: 0, head: 0 }
    }

    /// Forgets the motion history.
    pub fn reset(&mut self) {
        self.len = 0;
        self.head = 0;
    }

    /// The field being played.
    pub fn field(&self) -> &HeightFieldView<'a> {
        self.field.view()
    }

    /// The averaged unit motion direction, if the finger moved far enough over the window.
    pub fn direction(&self) -> Option<(f32, f32)> {
        if self.len < 2 {
            return None;
        }
        // `head` is the slot after the newest sample and the window holds
        // `len` samples, so both slots are `head` minus a count, modulo RING.
        // RING divides `usize::MAX + 1`, so a wrapping subtraction and the
        // mask give exactly that remainder.
        let newest = self.ring[self.head.wrapping_sub(1) & RING_MASK];
        let oldest = self.ring[self.head.wrapping_sub(self.len) & RING_MASK];
        let (dx, dy) = (newest.0 - oldest.0, newest.1 - oldest.1);
        let d = libm::sqrtf(dx * dx + dy * dy);
        if !(d > 0.0 && d >= self.params.min_move_mm) {
            return None;
        }
        Some((dx / d, dy / d))
    }

    /// Processes one touch sample.
    #[inline]
    pub fn sample(&mut self, t: Touch) -> FingerFrame {
        if self.field.view().is_tiled() { self.sample_as::<true>(t) } else { self.sample_as::<false>(t) }
    }

    /// [`FingerPlayer::sample`] for a field that is tiled exactly when
    /// `TILED` is: one function for each encoding, each with its own
    /// registers (one function for both saved and restored, for the 4.0
    /// field too, what the tiled path needs: a 4.0 sample took a tenth
    /// longer).
    #[inline(never)]
    fn sample_as<const TILED: bool>(&mut self, t: Touch) -> FingerFrame {
        let (x, y) = (t.x.0, t.y.0);
        if !t.contact || !x.is_finite() || !y.is_finite() {
            self.reset();
            return FingerFrame::off(t.tick);
        }
        // The window spans `direction_window` steps: that many samples plus one.
        let cap = (self.params.direction_window as usize).clamp(1, WINDOW_MAX) + 1;
        self.ring[self.head & RING_MASK] = (x, y);
        self.head = (self.head + 1) & RING_MASK;
        self.len = (self.len + 1).min(cap);
        let Some((i, j, fx, fy)) = field::locate(self.field.view(), x, y) else {
            return FingerFrame::off(t.tick);
        };
        let p = if TILED {
            // A tile not decoded yet is left to a function of its own, so
            // this path calls nothing and keeps its values in registers
            // (with the call here, they were saved to the stack and read
            // back on every sample: a fifth of a tiled sample's time).
            let Some(c) = self.field.kept_cell(i, j) else {
                return self.sample_decoding(t.tick, i, j, fx, fy);
            };
            field::tiled_point(self.field.view(), c, fx, fy)
        } else {
            field::float_point(self.field.view(), i, j, fx, fy)
        };
        match p {
            Some(p) => self.frame(t.tick, p),
            None => FingerFrame::off(t.tick),
        }
    }

    /// The rest of a tiled field's sample when the cell's tiles are not all
    /// decoded: decodes them, then as [`FingerPlayer::sample_as`].
    #[cold]
    #[inline(never)]
    fn sample_decoding(&mut self, tick: Tick, i: u32, j: u32, fx: f32, fy: f32) -> FingerFrame {
        self.field.keep_cell(i, j);
        match self.field.kept_cell(i, j).and_then(|c| field::tiled_point(self.field.view(), c, fx, fy)) {
            Some(p) => self.frame(tick, p),
            None => FingerFrame::off(tick),
        }
    }

    /// The drive for the surface point `p` under the finger (its direction
    /// already in the window).
    #[inline(always)]
    fn frame(&self, tick: Tick, p: SurfacePoint) -> FingerFrame {
        let (local, lateral, moving) = match self.direction() {
            Some((vx, vy)) => {
                let f = p.grad_x * vx + p.grad_y * vy;
                (f, f * vx, true)
            }
            None => (0.0, 0.0, false),
        };
        let active = if lateral < -self.params.flat_slope {
            Actuator::Left
        } else if lateral > self.params.flat_slope {
            Actuator::Right
        } else {
            Actuator::Down
        };
        let rhythm = (self.k1 * libm::fabsf(local)).clamp(0.0, self.params.rhythm_max);
        let intensity = (self.k2 * libm::fabsf(p.height)).clamp(0.0, self.params.intensity_max);
        FingerFrame {
            tick,
            active: Some(active),
            intensity,
            rhythm,
            period_ms: (105.0 - rhythm) / 0.5,
            height: p.height,
            local_gradient: local,
            moving,
            on_edge: p.edge,
        }
    }
}
