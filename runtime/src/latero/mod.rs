//! The player for laterotactile arrays such as STRESS² (device family 1):
//! dots, vibration and gratings of seed 000, composited per tick.
//!
//! A [`LateroPlayer`] is built once from a validated [`BundleView`]: it reads
//! the manifest's profile, refuses any other family, and prepares one
//! [`Layer`] per chunk with its constants (mask box, sample scale, sin θ / λ,
//! cos θ / λ, ...). After that, [`LateroPlayer::frame`] turns a tick and the
//! carrier position into one output code per actuator. The per-tick path
//! does not allocate, does not re-read chunk headers, and cannot panic.
//!
//! # Geometry
//! Actuator (row, col) sits at carrier + ((col − (cols − 1)/2) · pitch_x,
//! (row − (rows − 1)/2) · pitch_y) on the page (x right, y down), and its
//! index in a frame is `cols · row + col` (primitives.md, device family 1).
//! An actuator outside the profile's surface, or outside every layer, rests at 0.
//!
//! # Storage
//! The player keeps its layers in storage the caller chooses, so it needs no
//! allocator: [`LateroPlayer::new`] uses an array of [`DEFAULT_LAYERS`]
//! layers inside the player; [`LateroPlayer::with_storage`] takes any
//! `[Layer; N]`, a borrowed `&mut [Layer]` or (with an allocator) a
//! `Vec<Layer>`, so a host can size it to the bundle
//! (`BundleView::chunk_count()` is always enough). A bundle with more layers
//! than the storage holds is refused with [`RuntimeError::TooManyLayers`].
//!
//! Profiles may have at most [`MAX_COLS`] columns (any number of rows up to
//! the format's actuator limit) and at most 16 output bits.
//!
//! # Cost
//! Work per frame is per layer whose box meets the array: for a mask, two
//! sample-pair reads per covered actuator and the interpolation and
//! primitive four actuators at a time in 128-bit lanes (`mask.rs`, through
//! the `wide` crate: SSE2 on x86-64, NEON on AArch64, plain arrays
//! elsewhere; on x86-64 `safe_arch` adds the 16-bit unpacks `wide` lacks);
//! for a dot table, two cell starts per grid row under the array and the
//! dots found there, each evaluated four columns at a time. Phases
//! (vibration from the tick, grating at the array's corner) are computed
//! once per layer per frame; oscillators use a polynomial cosine with an
//! error below 1e-6. The per-tick path has no integer division (the tick is
//! reduced by a reciprocal taken at load, see `osc::PhaseClock`), and its
//! only float division is one reciprocal per dot it evaluates. An array of
//! exactly one block (64 actuators: every 64-actuator profile of up
//! to 14 bits) wholly on the surface, the usual case, is tested in four
//! lanes and plays from a frame geometry built at load, of which each tick
//! sets only the tick and the position; the rest goes through
//! `frame_in_blocks`.
//! `benches/latero.rs` measures a 64-actuator frame; `docs/performance.md`
//! has the figures.
//!
//! # Kernels for the CPU
//! Each layer kind's kernel (`accumulate_field`, `accumulate_dots`,
//! `accumulate_mask`) and `quantise_block` are compiled twice on x86-64 by
//! the `multiversion` crate: for the baseline (SSE2) and with AVX, whose
//! three-operand (VEX) forms save the register copies and many of the
//! spills and reloads of the two-operand SSE forms (about 8 % of a frame's
//! instructions). With the `std` feature the AVX copy is chosen at run time
//! when the CPU has AVX (one cached test per call); without `std` (the crate
//! needs it) there is no copy and the baseline plays. The two copies are the
//! same source and the same IEEE operations (AVX adds no fused multiply-add,
//! and Rust never contracts), so their frames are bit-identical; CI runs the runtime's tests in both builds
//! (`cargo test -p taxel-runtime --no-default-features` plays the
//! baseline). The AVX copy stays at 128-bit lanes: AVX2's wider integer
//! forms measured slower here.
//!
//! ```
//! use taxel_format::{Bundle, BundleView, Manifest, MaskKind, MaskLayer, MaskSamples, MilliHertz, Mm, Tick, profiles};
//! use taxel_runtime::latero::LateroPlayer;
//!
//! let mut bundle = Bundle::new(Manifest::new(profiles::builtin("stress2").unwrap()));
//! bundle.chunks.push(taxel_format::Chunk::Mask(MaskLayer {
//!     source: None,
//!     kind: MaskKind::Vibration { freq: MilliHertz(50_000) },
//!     amplitude: 1.0,
//!     origin_x: Mm(0.0),
//!     origin_y: Mm(0.0),
//!     px_per_mm: 1.0,
//!     width: 110,
//!     height: 60,
//!     samples: MaskSamples::U8(vec![255; 110 * 60]),
//! }));
//! let bytes = bundle.to_bytes().unwrap();
//! let view = BundleView::parse(&bytes).unwrap();
//! let player = LateroPlayer::new(&view).unwrap();
//! let mut frame = [0u16; 64];
//! let stats = player.frame(Tick(0), Mm(50.0), Mm(30.0), &mut frame);
//! // At tick 0, cos 2πft = 1: actuators whose row and column parities differ
//! // are fully left, the others at rest.
//! assert_eq!(&frame[..4], &[0, 1023, 0, 1023]);
//! assert_eq!(stats.clamped, 0);
//! ```

/// A kernel of the frame, not inlined (inlined, its set-up would be hoisted
/// into the frame's prologue and paid by every frame, even one without its
/// kind of layer), and compiled for the CPU's vector extensions too (see
/// "Kernels for the CPU" above): the one place that names them.
macro_rules! kernel {
    ($(#[$meta:meta])* fn $($fn:tt)*) => {
        $(#[$meta])*
        #[cfg_attr(
            all(feature = "std", target_arch = "x86_64"),
            multiversion::multiversion(targets("x86_64+avx"))
        )]
        #[inline(never)]
        fn $($fn)*
    };
}

mod dots;
mod field;
mod mask;
mod osc;

pub use dots::PLATEAU;

use taxel_format::{BundleView, ChunkView, Family, Mm, Tag, Tick};
use wide::bytemuck::cast;
use wide::{f32x4, i16x8, i32x4};

use crate::error::RuntimeError;
use mask::MaskLayer;

/// Number of layers [`LateroPlayer::new`] can hold.
pub const DEFAULT_LAYERS: usize = 64;
/// Largest number of columns a laterotactile profile may have for this player.
pub const MAX_COLS: usize = 64;
/// Actuators evaluated together: frames are computed in blocks of whole
/// rows of at most this many actuators, accumulated on the stack.
pub(crate) const BLOCK: usize = 64;
/// Actuators a mask layer interpolates at once: the width of a 128-bit
/// vector of `f32`, which every x86-64 and AArch64 core has.
pub(crate) const LANES: usize = 4;
/// A block's sums. Layers add [`LANES`] actuators at a time through
/// [`add_lanes`]; a group's lanes past its row's last column add 0.
pub(crate) type Acc = [f32; BLOCK];

/// Adds `v` to the sums of actuators `k..k + LANES` of the block. Lanes
/// past the block's end carry 0 and are dropped. The block is exactly
/// [`BLOCK`] sums, so that clearing it takes 16 vector stores. (Measured:
/// padded by three sums, so that a masked `k` needs no bounds check, it
/// took a `memset` call of some 70 instructions, more than the checks
/// saved; with this fallback out of line, the kernels spilled more.)
#[inline(always)]
pub(crate) fn add_lanes(acc: &mut Acc, k: usize, v: f32x4) {
    match acc.get_mut(k..k + LANES).and_then(|s| <&mut [f32; LANES]>::try_from(s).ok()) {
        Some(out) => *out = (f32x4::new(*out) + v).to_array(),
        None => {
            for (a, x) in acc.iter_mut().skip(k).zip(v.to_array()) {
                *a += x;
            }
        }
    }
}
/// 2²³: an `f32` in [2²³, 2²⁴) has integer spacing, so `v + 2²³` rounds `v`.
const ROUND_BITS: f32 = 8_388_608.0;
/// Largest output resolution, in bits (codes are `u16`).
pub const MAX_OUTPUT_BITS: u8 = 16;

/// One prepared layer: a vibration or grating mask, or a dot table.
/// Opaque; it exists so that callers can provide storage for a player.
#[derive(Debug, Clone, Copy)]
pub struct Layer<'a>(Slot<'a>);

/// An explicit one-byte tag (`repr(u8)`): the frame's dispatch reads it
/// and jumps, where the tag hidden in a niche of a layer's fields took a
/// subtraction and a conditional move more per layer.
#[derive(Debug, Clone, Copy)]
#[repr(u8)]
enum Slot<'a> {
    Empty,
    Mask(MaskLayer<'a>),
    Field(field::FieldLayer<'a>),
    Dots(dots::DotLayer<'a>),
}

impl Layer<'_> {
    /// An unused slot, to fill storage with.
    pub const EMPTY: Self = Layer(Slot::Empty);

    /// Adds this layer's deflection for the block of `f` to `acc`.
    #[inline(always)]
    fn accumulate(&self, f: &Frame, acc: &mut Acc) {
        match &self.0 {
            Slot::Mask(m) => m.accumulate(f, acc),
            Slot::Field(m) => m.accumulate(f, acc),
            Slot::Dots(d) => d.accumulate(f, acc),
            Slot::Empty => {}
        }
    }
}

/// What happened while computing one frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FrameStats {
    /// Actuators whose summed deflection exceeded full deflection by more
    /// than half an output step and were clamped to it (overlapping layers).
    pub clamped: u32,
    /// Actuator codes written (the profile's actuator count, or less when
    /// the output slice is shorter).
    pub written: u32,
}

/// Plays a laterotactile bundle: tick and carrier position in, one code per actuator out.
#[derive(Debug, Clone)]
pub struct LateroPlayer<'a, S = [Layer<'a>; DEFAULT_LAYERS]> {
    layers: S,
    len: usize,
    rows: usize,
    cols: usize,
    pitch_x: f32,
    pitch_y: f32,
    surface_w: f32,
    surface_h: f32,
    clock: osc::PhaseClock,
    max_code: f32,
    /// The same for [`quantise_block`].
    block_scale: BlockScale,
    /// Distance from the array's centre to column 0 and to row 0.
    half_span_x: f32,
    half_span_y: f32,
    /// Rows per block of at most [`BLOCK`] actuators (at least 1).
    rows_per_block: usize,
    /// A sum counts as clamped above this: clamping changed its code.
    clamp_at: f32,
    /// The one-block test of [`LateroPlayer::frame`], in the lanes of
    /// `[x_first, y_first, x_last, y_last]` (the positions of the first and
    /// last columns and rows): `half_span` is what the first lies before
    /// the carrier (`[half_span_x, half_span_y]` twice), `span` what the
    /// last lies past the first (`[0, 0, (cols − 1) · pitch_x,
    /// (rows − 1) · pitch_y]`, as [`inside`] computes them), and the array
    /// plays as one block when every lane is within `fits_lo..=fits_hi`:
    /// the first column and row at or past 0, the last ones at or before
    /// the surface's edges. For an array that is not one block, `fits_hi`
    /// is −∞: no lane fits.
    half_span: f32x4,
    span: f32x4,
    fits_lo: f32x4,
    fits_hi: f32x4,
    /// The frame of an array wholly on the surface, as one block, but for
    /// the tick and the position: built at load, copied by every frame
    /// that plays as one block.
    whole: Frame,
    _bundle: core::marker::PhantomData<&'a [u8]>,
}

impl<'a> LateroPlayer<'a> {
    /// A player for `view` with room for [`DEFAULT_LAYERS`] layers.
    pub fn new(view: &BundleView<'a>) -> Result<Self, RuntimeError> {
        Self::with_storage(view, [Layer::EMPTY; DEFAULT_LAYERS])
    }
}

impl<'a, S: AsRef<[Layer<'a>]> + AsMut<[Layer<'a>]>> LateroPlayer<'a, S> {
    /// A player for `view` that keeps its layers in `storage` (see the module docs).
    pub fn with_storage(view: &BundleView<'a>, mut storage: S) -> Result<Self, RuntimeError> {
        let p = &view.manifest().profile;
        if p.family() != Family::Laterotactile {
            return Err(RuntimeError::WrongFamily {
                expected: Family::Laterotactile,
                found: p.family(),
                profile: p.name,
            });
        }
        if p.cols as usize > MAX_COLS {
            return Err(RuntimeError::Unsupported { field: "cols", value: p.cols as u32, limit: MAX_COLS as u32 });
        }
        if p.output_bits > MAX_OUTPUT_BITS {
            return Err(RuntimeError::Unsupported {
                field: "output_bits",
                value: p.output_bits as u32,
                limit: MAX_OUTPUT_BITS as u32,
            });
        }
        let mut needed = 0usize;
        for chunk in view.chunks() {
            match chunk {
                ChunkView::Mask(_) | ChunkView::Distance(_) | ChunkView::Dots(_) => needed += 1,
                ChunkView::Strokes(_) => {
                    return Err(RuntimeError::UnexpectedChunk { family: Family::Laterotactile, tag: Tag::STROKES });
                }
                ChunkView::Height(_) => {
                    return Err(RuntimeError::UnexpectedChunk { family: Family::Laterotactile, tag: Tag::HEIGHT });
                }
                ChunkView::Pins(_) => {
                    return Err(RuntimeError::UnexpectedChunk { family: Family::Laterotactile, tag: Tag::PINS });
                }
                // Provenance and unknown optional chunks do not play.
                ChunkView::Provenance(_) | ChunkView::Footprints(_) | ChunkView::Unknown { .. } => {}
            }
        }
        let slots = storage.as_mut();
        if needed > slots.len() {
            return Err(RuntimeError::TooManyLayers { needed, capacity: slots.len() });
        }
        let mut len = 0;
        for chunk in view.chunks() {
            let slot = match chunk {
                ChunkView::Mask(m) => Slot::Mask(MaskLayer::new(&m, p.pitch_x_mm, p.pitch_y_mm)),
                ChunkView::Distance(m) => Slot::Field(field::FieldLayer::new(&m, p.pitch_x_mm, p.pitch_y_mm)),
                ChunkView::Dots(d) if d.is_empty() => continue,
                ChunkView::Dots(d) => Slot::Dots(dots::DotLayer::new(d)),
                _ => continue,
            };
            if let Some(s) = slots.get_mut(len) {
                *s = Layer(slot);
                len += 1;
            }
        }
        let (rows, cols) = (p.rows as usize, p.cols as usize);
        let clock = osc::PhaseClock::new(p.rate_hz);
        // Profiles have positive pitches (taxel-format checks them).
        let whole = Frame::new(clock, cols, rows, p.pitch_x_mm, p.pitch_y_mm);
        // Whether the array is exactly one block ([`BLOCK`] actuators) and
        // its codes fit [`quantise_block`]: then a frame on the surface is
        // one block.
        let whole_block = rows * cols == BLOCK && p.max_code() as f32 <= VECTOR_MAX_CODE;
        let half_span_x = cols.saturating_sub(1) as f32 * 0.5 * p.pitch_x_mm;
        let half_span_y = rows.saturating_sub(1) as f32 * 0.5 * p.pitch_y_mm;
        Ok(LateroPlayer {
            layers: storage,
            len,
            rows: p.rows as usize,
            cols: p.cols as usize,
            pitch_x: p.pitch_x_mm,
            pitch_y: p.pitch_y_mm,
            surface_w: p.surface_w_mm,
            surface_h: p.surface_h_mm,
            clock,
            max_code: p.max_code() as f32,
            block_scale: BlockScale::new(p.max_code() as f32),
            half_span_x,
            half_span_y,
            rows_per_block: (BLOCK / (p.cols as usize).max(1)).max(1),
            clamp_at: 1.0 + 0.5 / p.max_code() as f32,
            half_span: f32x4::new([half_span_x, half_span_y, half_span_x, half_span_y]),
            span: f32x4::new([
                0.0,
                0.0,
                cols.saturating_sub(1) as u32 as f32 * p.pitch_x_mm,
                rows.saturating_sub(1) as u32 as f32 * p.pitch_y_mm,
            ]),
            fits_lo: f32x4::new([0.0, 0.0, f32::NEG_INFINITY, f32::NEG_INFINITY]),
            fits_hi: if whole_block {
                f32x4::new([f32::INFINITY, f32::INFINITY, p.surface_w_mm, p.surface_h_mm])
            } else {
                f32x4::splat(f32::NEG_INFINITY)
            },
            whole,
            _bundle: core::marker::PhantomData,
        })
    }

    /// Number of actuators in a frame (`rows · cols`).
    pub fn actuator_count(&self) -> usize {
        self.rows * self.cols
    }

    /// Number of layers the player holds (empty dot tables are dropped at load).
    pub fn layer_count(&self) -> usize {
        self.len
    }

    /// Writes the code of every actuator at `tick` with the carrier at
    /// `(x, y)` into `out` (index `cols · row + col`; codes in
    /// `0..=2^output_bits − 1`). Each code is the sum of the layers' δ,
    /// clamped to [0, 1], times `2^output_bits − 1`, rounded to nearest
    /// (ties to even). If `out` is shorter than the actuator count only its
    /// length is written; entries past the actuator count are left alone. A
    /// non-finite position puts every actuator at rest.
    ///
    /// Allocates nothing, cannot panic, and costs the same for a table of
    /// ten dots or ten thousand (it depends on the dots near the array).
    pub fn frame(&self, tick: Tick, x: Mm, y: Mm, out: &mut [u16]) -> FrameStats {
        // The common case: the whole array is one block of [`BLOCK`]
        // actuators, quantised in vector lanes (every 64-actuator profile
        // of up to 14 bits), and wholly on the surface. Its frame is the one
        // built at load but for the tick and the position. (A NaN or
        // infinite position fails these comparisons, and rests below.)
        let first = f32x4::new([x.0, y.0, x.0, y.0]) - self.half_span;
        let ends = first + self.span;
        if (ends.simd_ge(self.fits_lo) & ends.simd_le(self.fits_hi)).to_bitmask() == 0b1111
            && let Ok(block) = <&mut [u16; BLOCK]>::try_from(&mut *out)
        {
            let [x_first, y_first, ..] = first.to_array();
            let w = &self.whole;
            let f = Frame {
                tick_in_second: self.clock.tick_in_second(tick),
                clock: w.clock,
                cols: w.cols,
                pitch_x: w.pitch_x,
                pitch_y: w.pitch_y,
                x_first,
                y_first,
                col_lo: w.col_lo,
                col_hi: w.col_hi,
                row_lo: w.row_lo,
                row_hi: w.row_hi,
                r0: w.r0,
                r1: w.r1,
                run_first: first.unpack_lo(first),
                run_pitch: w.run_pitch,
                run_inv: w.run_inv,
                run_lo: w.run_lo,
                run_hi: w.run_hi,
            };
            let mut acc: Acc = [0.0; BLOCK];
            let layers = self.layers.as_ref();
            // `len` never exceeds the storage (checked at load); the
            // `min` only spares the slicing a bounds check.
            for layer in layers.get(..self.len.min(layers.len())).unwrap_or(&[]) {
                layer.accumulate(&f, &mut acc);
            }
            let clamped = quantise_block(block, &acc, &self.block_scale);
            return FrameStats { clamped, written: BLOCK as u32 };
        }
        self.frame_in_blocks(tick, x, y, out)
    }

    /// [`LateroPlayer::frame`] for every other case: an array of several
    /// blocks, or partly off the surface, or a short output.
    #[inline(never)]
    fn frame_in_blocks(&self, tick: Tick, x: Mm, y: Mm, out: &mut [u16]) -> FrameStats {
        let n = self.actuator_count().min(out.len());
        let out = &mut out[..n];
        let mut stats = FrameStats { clamped: 0, written: n as u32 };
        if !(x.0.is_finite() && y.0.is_finite()) {
            out.fill(0);
            return stats;
        }
        let mut f = Frame { tick_in_second: self.clock.tick_in_second(tick), ..self.whole };
        f.set_position(x.0 - self.half_span_x, y.0 - self.half_span_y);
        // Actuators on the surface form one rectangle of columns and rows.
        (f.col_lo, f.col_hi) = inside(self.cols, f.x_first, self.pitch_x, self.surface_w);
        (f.row_lo, f.row_hi) = inside(self.rows, f.y_first, self.pitch_y, self.surface_h);
        let layers = self.layers.as_ref().get(..self.len).unwrap_or(&[]);
        let rows_per_block = self.rows_per_block;
        for (b, block) in out.chunks_mut(rows_per_block * self.cols).enumerate() {
            f.set_block(b * rows_per_block, (b * rows_per_block + rows_per_block).min(self.rows));
            let mut acc: Acc = [0.0; BLOCK];
            for layer in layers {
                layer.accumulate(&f, &mut acc);
            }
            stats.clamped += match <&mut [u16; BLOCK]>::try_from(&mut *block) {
                // A whole block (every 64-actuator array) at up to 14 bits:
                // eight codes at a time in 16-bit lanes.
                Ok(block) if self.max_code <= VECTOR_MAX_CODE => quantise_block(block, &acc, &self.block_scale),
                _ => quantise(block, &acc, self.clamp_at, self.max_code),
            };
        }
        stats
    }
}

/// Clamps each sum to [0, 1], scales it to `max_code` and rounds it to
/// the nearest code (ties to even) into `out`; returns how many sums
/// clamping changed (those above `clamp_at`).
#[inline(never)]
fn quantise(out: &mut [u16], acc: &Acc, clamp_at: f32, max_code: f32) -> u32 {
    let mut clamped = 0u32;
    for (o, &a) in out.iter_mut().zip(acc.iter()) {
        clamped += (a > clamp_at) as u32;
        // Comparisons rather than `min`/`max` compile to one instruction
        // each; a NaN (impossible from validated layers) fails `v > 0.0`
        // and rests.
        let v = if a < 1.0 { a } else { 1.0 };
        let v = if v > 0.0 { v } else { 0.0 };
        // Adding 2²³ leaves round(v · max) in the low mantissa bits
        // (v · max ≤ 65535), a conversion that vectorises, unlike `as`.
        *o = ((v * max_code + ROUND_BITS).to_bits() & 0xffff) as u16;
    }
    clamped
}

/// [`quantise_block`]'s `max_code` in lanes, splat at load rather than
/// in every frame.
#[derive(Debug, Clone, Copy)]
struct BlockScale {
    /// `max_code` as `f32`, the sums' scale.
    scale: f32x4,
    /// `max_code` as `i16`, the largest code (saturated for a `max_code`
    /// above [`VECTOR_MAX_CODE`], which [`quantise_block`] does not serve).
    top: i16x8,
}

impl BlockScale {
    fn new(max_code: f32) -> Self {
        BlockScale { scale: f32x4::splat(max_code), top: i16x8::splat(max_code as i16) }
    }
}

/// The largest `max_code` that [`quantise_block`] serves: twice it (a sum
/// clamped to 2) must still fit an `i16` lane, or saturation would hide the
/// codes above `max_code` that count as clamped. 14 bits.
const VECTOR_MAX_CODE: f32 = (i16::MAX / 2) as f32;

kernel! {
/// [`quantise`] for a whole block and `max_code` ≤ [`VECTOR_MAX_CODE`], in
/// vector lanes: the sums are scaled and rounded to nearest, ties to even,
/// by the same 2²³ addition; the codes then narrow to 16-bit lanes, where
/// those above `max_code` are counted and every code is clamped to
/// `0..=max_code` (so that even a NaN, impossible from validated layers,
/// gives a code in range on every target). A sum above 1 by more than half
/// a step rounds above `max_code`, exactly the sums [`quantise`] counts. The sums need no clamp above: past `2²³ + 2¹⁵`
/// the float's bits less those of 2²³ still grow with it (up to +∞), so the
/// narrowing saturates them to `i16::MAX`.
///
/// Not inlined: inlined, its constants are hoisted out of the frame's loop
/// over blocks and live in vector registers across the layers' calls, which
/// may overwrite them (caller-saved on x86-64), so the frame reloaded all of
/// them after every layer.
fn quantise_block(out: &mut [u16; BLOCK], acc: &Acc, q: &BlockScale) -> u32 {
    let (scale, round, top) = (q.scale, f32x4::splat(ROUND_BITS), q.top);
    let bias = i32x4::splat(ROUND_BITS.to_bits() as i32);
    let mut over = i16x8::ZERO;
    for (o, a) in out.chunks_exact_mut(8).zip(acc.chunks_exact(8)) {
        let code = |a: &[f32]| -> i32x4 {
            let a: [f32; 4] = a.try_into().unwrap_or([0.0; 4]);
            // No lower clamp: a negative sum (down to about −2²³ / max_code,
            // far below any sum of validated layers, whose deflections are
            // not negative) gives a negative code, which the clamp to 0
            // below settles.
            cast::<f32x4, i32x4>(f32x4::new(a) * scale + round) - bias
        };
        let c = i16x8::from_i32x8_saturate(cast([code(&a[..4]), code(&a[4..])]));
        // A true lane compares as −1.
        over += c.simd_gt(top);
        if let Ok(o) = <&mut [u16; 8]>::try_from(o) {
            *o = cast(c.max(i16x8::ZERO).min(top));
        }
    }
    // Each lane holds minus its count (at most 8): the products by −1 add
    // them in pairs (`pmaddwd` on x86-64), then the four pair sums.
    let pairs = over.dot(i16x8::splat(-1)).to_array();
    (pairs[0] + pairs[1] + pairs[2] + pairs[3]) as u32
}
}

/// The half-open range of indices `0..n` whose position `first + i · pitch`
/// lies in `[0, limit]`.
#[inline(always)]
fn inside(n: usize, first: f32, pitch: f32, limit: f32) -> (usize, usize) {
    // The usual case: the whole array is on the surface.
    if n > 0 && first >= 0.0 && first + (n - 1) as u32 as f32 * pitch <= limit {
        return (0, n);
    }
    inside_edge(n, first, pitch, limit)
}

/// [`inside`] for an array that reaches past an edge of the surface.
#[cold]
#[inline(never)]
fn inside_edge(n: usize, first: f32, pitch: f32, limit: f32) -> (usize, usize) {
    let pos = |i: usize| first + i as u32 as f32 * pitch;
    // Estimate from the division, then settle the edges with the same
    // position formula the layers use, so both agree exactly.
    let mut lo = osc::ceil_i32(-first / pitch).clamp(0, n as i32) as usize;
    while lo > 0 && pos(lo - 1) >= 0.0 {
        lo -= 1;
    }
    while lo < n && pos(lo) < 0.0 {
        lo += 1;
    }
    let mut hi = (osc::floor_i32((limit - first) / pitch).saturating_add(1)).clamp(0, n as i32) as usize;
    while hi < n && pos(hi) <= limit {
        hi += 1;
    }
    while hi > 0 && pos(hi - 1) > limit {
        hi -= 1;
    }
    if lo >= hi { (0, 0) } else { (lo, hi) }
}

/// The geometry of one frame and the block of rows being computed.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frame {
    /// The tick modulo one second of millihertz cycles, and the clock
    /// that turns it into phases.
    pub(crate) tick_in_second: u64,
    pub(crate) clock: osc::PhaseClock,
    pub(crate) cols: usize,
    pub(crate) pitch_x: f32,
    pub(crate) pitch_y: f32,
    /// Page position of column 0 and row 0.
    pub(crate) x_first: f32,
    pub(crate) y_first: f32,
    /// Columns and rows whose actuators lie on the surface.
    pub(crate) col_lo: usize,
    pub(crate) col_hi: usize,
    pub(crate) row_lo: usize,
    pub(crate) row_hi: usize,
    /// The block's rows.
    pub(crate) r0: usize,
    pub(crate) r1: usize,
    /// What [`Frame::runs`] needs of the frame, in the lanes of a box's
    /// `[x0, x1, y0, y1]`, built once per frame ([`Frame::new`], [`Frame::set_position`])
    /// and block ([`Frame::set_block`]) rather than by every layer: the
    /// position of column 0 and row 0, the pitches and their reciprocals,
    /// and the first and last indices a run may hold (the columns on the
    /// surface, the block's rows on the surface).
    run_first: f32x4,
    run_pitch: f32x4,
    run_inv: f32x4,
    run_lo: i32x4,
    run_hi: i32x4,
}

impl Frame {
    /// The frame of an array of `cols` columns and `rows` rows these
    /// pitches apart (positive), all of it on the surface and one block,
    /// at tick 0 with row 0 and column 0 at the page's origin.
    fn new(clock: osc::PhaseClock, cols: usize, rows: usize, pitch_x: f32, pitch_y: f32) -> Self {
        // Their reciprocals, so that the per-tick path divides nothing.
        let (inv_x, inv_y) = (1.0 / pitch_x, 1.0 / pitch_y);
        let mut f = Frame {
            tick_in_second: 0,
            clock,
            cols,
            pitch_x,
            pitch_y,
            x_first: 0.0,
            y_first: 0.0,
            col_lo: 0,
            col_hi: cols,
            row_lo: 0,
            row_hi: rows,
            r0: 0,
            r1: 0,
            run_first: f32x4::ZERO,
            run_pitch: f32x4::new([pitch_x, pitch_x, pitch_y, pitch_y]),
            run_inv: f32x4::new([inv_x, inv_x, inv_y, inv_y]),
            run_lo: i32x4::ZERO,
            run_hi: i32x4::ZERO,
        };
        f.set_block(0, rows);
        f
    }

    /// Puts column 0 and row 0 at `(x_first, y_first)` on the page.
    #[inline(always)]
    fn set_position(&mut self, x_first: f32, y_first: f32) {
        (self.x_first, self.y_first) = (x_first, y_first);
        self.run_first = f32x4::new([x_first, x_first, y_first, y_first]);
    }

    /// Makes rows `r0..r1` the block, and sets the index bounds of
    /// [`Frame::runs`] (after [`Frame::new`], [`Frame::set_position`]'s surface).
    #[inline(always)]
    fn set_block(&mut self, r0: usize, r1: usize) {
        (self.r0, self.r1) = (r0, r1);
        let (rlo, rhi) = (r0.max(self.row_lo), r1.min(self.row_hi).max(r0.max(self.row_lo)));
        self.run_lo = i32x4::new([self.col_lo as i32, self.col_lo as i32, rlo as i32, rlo as i32]);
        self.run_hi = i32x4::new([self.col_hi as i32, self.col_hi as i32, rhi as i32, rhi as i32]);
    }

    /// `[col_x(col_lo), col_x(col_hi − 1), row_y(r_lo), row_y(r_hi − 1)]`:
    /// the positions of the first and last columns on the surface and of the
    /// block's first and last rows on it (`r_lo` and `r_hi` as in
    /// [`Frame::runs`]; meaningful when neither run is empty).
    #[inline(always)]
    pub(crate) fn run_positions(&self) -> f32x4 {
        let first_last = i32x4::new([0, -1, 0, -1]).simd_eq(i32x4::ZERO);
        let index = first_last.select(self.run_lo, self.run_hi - i32x4::ONE);
        // `col_x`'s and `row_y`'s arithmetic, lane by lane.
        self.run_first + f32x4::from_i32x4(index) * self.run_pitch
    }

    /// Page x of column `c`.
    #[inline(always)]
    pub(crate) fn col_x(&self, c: usize) -> f32 {
        // Through i32: an unsigned 64-bit to float conversion is a branchy
        // sequence on x86-64, a signed 32-bit one a single instruction (an
        // unsigned one needs a zero-extension first, and four of them in
        // vector lanes seven instructions: SSE2 converts signed integers
        // only). Indices are far below 2²⁴, where every conversion is exact.
        self.x_first + c as i32 as f32 * self.pitch_x
    }

    /// Page y of row `r`.
    #[inline(always)]
    pub(crate) fn row_y(&self, r: usize) -> f32 {
        // As in `col_x`.
        self.y_first + r as i32 as f32 * self.pitch_y
    }

    /// The runs of actuators inside the box `[x0, x1) x [y0, y1)` given as
    /// `[x0, x1, y0, y1]`: returns `[c_lo, c_hi, r_lo, r_hi]`, the columns
    /// `c_lo..c_hi` of `col_lo..col_hi` whose [`col_x`](Self::col_x) is in
    /// `[x0, x1)` and the rows `r_lo..r_hi` of the block's rows on the
    /// surface whose [`row_y`](Self::row_y) is in `[y0, y1)` (positions grow
    /// with the index, so each is one run). The four ends are found at once,
    /// in vector lanes: an estimate from the pitch, clamped, then settled
    /// with the positions themselves, so that each end is exactly the first
    /// index whose position reaches the bound. (The estimate is off by less
    /// than one index: a bound near the array is a few pitches away, where
    /// the rounding of the estimate is far below one pitch.)
    #[inline(always)]
    pub(crate) fn runs(&self, bounds: f32x4) -> [usize; 4] {
        let (first, pitch, inv, lo, hi) = (self.run_first, self.run_pitch, self.run_inv, self.run_lo, self.run_hi);
        let pos = |i: i32x4| first + f32x4::from_i32x4(i) * pitch;
        let e = osc::ceil_in4((bounds - first) * inv, lo, hi);
        // One step down if the index before already reaches the bound, one
        // up if this one does not yet: a true lane compares as −1, so the
        // masks are the steps. (A NaN bound gives `hi`.)
        let e = e + (e.simd_gt(lo) & cast::<f32x4, i32x4>(pos(e - 1).simd_ge(bounds)));
        let e = e - (e.simd_lt(hi) & cast::<f32x4, i32x4>(!pos(e).simd_ge(bounds)));
        e.to_array().map(|v| v as usize)
    }
}

#[cfg(test)]
mod tests;
