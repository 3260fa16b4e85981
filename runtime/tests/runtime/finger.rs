//! The finger player (seed 002) against independently computed expectations:
//! eq. 3 (local gradient), eq. 4 (D = k2 |h|, R = k1 |∇f|), eq. 5 (R = −0.5 T + 105),
//! Tab. 1 (which actuator), the direction window, contact, and no allocation.

use proptest::prelude::*;
use taxel_format::{
    Bundle, BundleView, Chunk, FIELD_CONTACT, FIELD_EDGE, FamilyParams, FingerParams, HeightField, HeightFieldView,
    Manifest, Mm, Tick, profiles,
};
use taxel_runtime::finger::{Actuator, FingerError, FingerFrame, FingerPlayer, Touch, field};

/// A field sampled from `h(x, y)` with its exact gradient, on a grid from
/// (0, 0) mm every `cell` mm; nodes where `h` is `None` have no contact.
fn field_of(cols: u32, rows: u32, cell: f32, h: impl Fn(f64, f64) -> Option<(f64, f64, f64)>) -> HeightField {
    let n = (cols * rows) as usize;
    let mut f = HeightField {
        source: None,
        cols,
        rows,
        origin_x: Mm(0.0),
        origin_y: Mm(0.0),
        cell: Mm(cell),
        gradient_cap: 10.0,
        heights: vec![0.0; n],
        grad_x: vec![0.0; n],
        grad_y: vec![0.0; n],
        flags: vec![0; n],
        encoding: taxel_format::HeightEncoding::Float,
    };
    for j in 0..rows {
        for i in 0..cols {
            let k = (j * cols + i) as usize;
            if let Some((z, gx, gy)) = h(i as f64 * cell as f64, j as f64 * cell as f64) {
                f.heights[k] = z as f32;
                f.grad_x[k] = gx as f32;
                f.grad_y[k] = gy as f32;
                f.flags[k] = FIELD_CONTACT;
            }
        }
    }
    f
}

fn finger3() -> (taxel_format::DeviceProfile, FingerParams) {
    let p = profiles::builtin("finger3").unwrap();
    let FamilyParams::Finger(fp) = p.params else { panic!("finger3 is a finger profile") };
    (p, fp)
}

fn bytes_of(f: HeightField) -> Vec<u8> {
    let mut b = Bundle::new(Manifest::new(finger3().0));
    b.chunks.push(Chunk::Height(f));
    b.to_bytes().unwrap()
}

/// A plane h = 20 + a x + b y over 0..100 x 0..100 mm.
fn plane(a: f64, b: f64) -> Vec<u8> {
    bytes_of(field_of(101, 101, 1.0, |x, y| Some((20.0 + a * x + b * y, a, b))))
}

fn touch(k: u64, x: f64, y: f64) -> Touch {
    Touch { tick: Tick(k), x: Mm(x as f32), y: Mm(y as f32), contact: true }
}

/// Sweeps from (x0, y0) in steps of (dx, dy) and returns the frames.
fn sweep(bytes: &[u8], x0: f64, y0: f64, dx: f64, dy: f64, n: u64) -> Vec<taxel_runtime::finger::FingerFrame> {
    let view = BundleView::parse(bytes).unwrap();
    let mut p = FingerPlayer::new(&view).unwrap();
    (0..n).map(|k| p.sample(touch(k, x0 + dx * k as f64, y0 + dy * k as f64))).collect()
}

#[test]
fn table_1_declining_left_to_right_is_left_flat_is_down_rising_is_right() {
    for (slope, want) in [(-0.2, Actuator::Left), (0.0, Actuator::Down), (0.2, Actuator::Right)] {
        // Left to right and right to left: the actuator follows the surface, not the stroke.
        for dir in [1.0, -1.0] {
            let frames = sweep(&plane(slope, 0.0), 50.0 - 20.0 * dir, 50.0, 0.5 * dir, 0.0, 80);
            for f in &frames[6..] {
                assert!(f.moving);
                assert_eq!(f.active, Some(want), "slope {slope}, direction {dir}");
            }
        }
    }
}

#[test]
fn a_vertical_stroke_is_down_whatever_the_slope() {
    let frames = sweep(&plane(0.3, 0.3), 50.0, 20.0, 0.0, 0.5, 80);
    for f in &frames[6..] {
        assert_eq!(f.active, Some(Actuator::Down));
        // The local gradient is the slope along the motion: ∂h/∂y = 0.3.
        assert!((f.local_gradient - 0.3).abs() < 1e-4, "{}", f.local_gradient);
    }
}

#[test]
fn equations_4_and_5_scale_height_and_slope_by_the_field_extremes() {
    // h = 20 + 0.1 x - 0.05 y: highest node 30 at (100, 0), steepest |∇h| = sqrt(0.0125).
    let (a, b) = (0.1, -0.05);
    let bytes = plane(a, b);
    let (_, fp) = finger3();
    let hmax = 20.0 + a * 100.0;
    let gmax = (a * a + b * b).sqrt();
    let frames = sweep(&bytes, 10.0, 60.0, 0.4, 0.3, 150);
    for (k, f) in frames.iter().enumerate().skip(6) {
        let (x, y) = (10.0 + 0.4 * k as f64, 60.0 + 0.3 * k as f64);
        if x > 100.0 || y > 100.0 {
            break;
        }
        let h = 20.0 + a * x + b * y;
        let d = fp.intensity_max as f64 * h / hmax;
        // Motion direction (0.8, 0.6): ∇f = 0.8 a + 0.6 b.
        let local = 0.8 * a + 0.6 * b;
        let r = fp.rhythm_max as f64 * local.abs() / gmax;
        assert!((f.intensity as f64 - d).abs() < 1e-4, "D {} vs {d}", f.intensity);
        assert!((f.rhythm as f64 - r).abs() < 1e-3, "R {} vs {r}", f.rhythm);
        assert!((f.period_ms as f64 - (105.0 - r) / 0.5).abs() < 2e-3, "T {}", f.period_ms);
        assert_eq!(f.levels()[f.active.unwrap() as usize], f.intensity);
        assert_eq!(f.levels().iter().filter(|&&v| v > 0.0).count(), 1);
    }
}

#[test]
fn a_still_finger_has_no_direction_and_feels_the_height_below() {
    let view_bytes = plane(0.2, 0.0);
    let view = BundleView::parse(&view_bytes).unwrap();
    let mut p = FingerPlayer::new(&view).unwrap();
    for k in 0..20 {
        // Wobbling by 0.1 mm, under the profile's 0.5 mm over the window.
        let f = p.sample(touch(k, 50.0 + 0.1 * (k % 2) as f64, 50.0));
        assert!(!f.moving);
        assert_eq!(f.active, Some(Actuator::Down));
        assert_eq!(f.rhythm, 0.0);
        assert_eq!(f.period_ms, 210.0);
    }
}

#[test]
fn coarse_jittery_positions_do_not_flicker() {
    // A touch screen reporting whole millimetres with ±1 mm of jitter across
    // the stroke, at 0.5 mm per sample, over a surface declining to the right.
    let bytes = plane(-0.15, 0.0);
    let view = BundleView::parse(&bytes).unwrap();
    let mut p = FingerPlayer::new(&view).unwrap();
    let mut acts = Vec::new();
    for k in 0..150u64 {
        let x = (10.0 + 0.5 * k as f64).round();
        let y = 50.0 + [0.0, 1.0, -1.0, 1.0, 0.0, -1.0][(k % 6) as usize];
        let f = p.sample(touch(k, x, y));
        if f.moving {
            acts.push(f.active);
        }
    }
    assert!(acts.len() > 130);
    assert!(acts.iter().all(|a| *a == Some(Actuator::Left)), "{acts:?}");
}

#[test]
fn lifting_the_finger_or_leaving_the_field_switches_everything_off() {
    let bytes = plane(0.2, 0.0);
    let view = BundleView::parse(&bytes).unwrap();
    let mut p = FingerPlayer::new(&view).unwrap();
    for k in 0..10 {
        p.sample(touch(k, 40.0 + k as f64, 50.0));
    }
    assert!(p.direction().is_some());
    let off = p.sample(Touch { contact: false, ..touch(10, 50.0, 50.0) });
    assert_eq!(off.active, None);
    assert_eq!(off.levels(), [0.0; 3]);
    assert!(p.direction().is_none(), "lifting forgets the motion");
    // Touching down again: no direction until the finger has moved.
    assert!(!p.sample(touch(11, 50.0, 50.0)).moving);
    for (x, y) in [(-1.0, 50.0), (101.0, 50.0), (50.0, 100.5), (f64::NAN, 50.0), (50.0, f64::INFINITY)] {
        assert_eq!(p.sample(touch(12, x, y)).active, None, "({x}, {y})");
    }
}

#[test]
fn holes_have_no_contact_to_half_a_cell() {
    // No surface where x < 30 mm.
    let bytes = bytes_of(field_of(101, 11, 1.0, |x, _| (x >= 30.0).then_some((10.0, 0.0, 0.0))));
    let view = BundleView::parse(&bytes).unwrap();
    let hf = *FingerPlayer::new(&view).unwrap().field();
    assert!(field::sample(&hf, 28.0, 5.0).is_none());
    assert!(field::sample(&hf, 29.4, 5.0).is_none());
    let s = field::sample(&hf, 29.6, 5.0).unwrap();
    assert_eq!(s.height, 10.0, "contact nodes are renormalised, not pulled to 0");
    assert!(field::sample(&hf, 31.0, 5.0).is_some());
}

#[test]
fn edge_nodes_are_reported() {
    let mut f = field_of(11, 11, 1.0, |_, _| Some((5.0, 0.0, 0.0)));
    f.flags[5 * 11 + 5] |= FIELD_EDGE;
    let bytes = bytes_of(f);
    let view = BundleView::parse(&bytes).unwrap();
    let p = FingerPlayer::new(&view).unwrap();
    assert!(field::sample(p.field(), 5.5, 5.5).unwrap().edge);
    assert!(!field::sample(p.field(), 7.5, 7.5).unwrap().edge);
}

#[test]
fn other_families_and_bundles_without_a_field_are_refused() {
    let b = Bundle::new(Manifest::new(profiles::builtin("stress2").unwrap())).to_bytes().unwrap();
    let view = BundleView::parse(&b).unwrap();
    assert!(matches!(FingerPlayer::new(&view), Err(FingerError::WrongFamily(_))));
    let b = Bundle::new(Manifest::new(finger3().0)).to_bytes().unwrap();
    let view = BundleView::parse(&b).unwrap();
    assert_eq!(FingerPlayer::new(&view).err(), Some(FingerError::NoHeightField));
}

#[test]
fn the_same_input_gives_the_same_frame_after_24_hours_of_ticks() {
    let bytes = plane(0.1, 0.0);
    let view = BundleView::parse(&bytes).unwrap();
    let day = 100 * 86_400; // ticks at 100 Hz
    let mut a = FingerPlayer::new(&view).unwrap();
    let mut b = FingerPlayer::new(&view).unwrap();
    for k in 0..20u64 {
        let (x, y) = (30.0 + k as f64, 40.0);
        let fa = a.sample(touch(k, x, y));
        let fb = b.sample(touch(k + day, x, y));
        assert_eq!(FingerFrameNoTick::from(fa), FingerFrameNoTick::from(fb));
    }
}

#[derive(Debug, PartialEq)]
struct FingerFrameNoTick(Option<Actuator>, u32, u32, u32);

impl From<taxel_runtime::finger::FingerFrame> for FingerFrameNoTick {
    fn from(f: taxel_runtime::finger::FingerFrame) -> Self {
        FingerFrameNoTick(f.active, f.intensity.to_bits(), f.rhythm.to_bits(), f.period_ms.to_bits())
    }
}

#[test]
fn samples_allocate_nothing() {
    let bytes = plane(0.1, -0.1);
    let view = BundleView::parse(&bytes).unwrap();
    let mut on = 0;
    let info = allocation_counter::measure(|| {
        let mut p = FingerPlayer::new(&view).unwrap();
        for k in 0..10_000u64 {
            let f = p.sample(touch(k, (k % 1000) as f64 * 0.1, 50.0 + (k % 7) as f64));
            on += f.active.is_some() as u32;
        }
    });
    assert_eq!(info.count_total, 0, "allocations while playing: {info:?}");
    assert!(on > 0);
}

proptest! {
    /// Bilinear sampling reproduces a bilinear function exactly (up to f32 rounding).
    #[test]
    fn bilinear_sampling_is_exact_on_bilinear_surfaces(
        a in -2.0f64..2.0, b in -2.0f64..2.0, c in -0.05f64..0.05,
        x in 0.0f64..20.0, y in 0.0f64..20.0,
    ) {
        let h = |x: f64, y: f64| 50.0 + a * x + b * y + c * x * y;
        let bytes = bytes_of(field_of(21, 21, 1.0, |x, y| Some((h(x, y), a + c * y, b + c * x))));
        let view = BundleView::parse(&bytes).unwrap();
        let p = FingerPlayer::new(&view).unwrap();
        let s = field::sample(p.field(), x as f32, y as f32).unwrap();
        // The query point itself is rounded to f32.
        let (xf, yf) = (x as f32 as f64, y as f32 as f64);
        prop_assert!((s.height as f64 - h(xf, yf)).abs() < 1e-3, "{} vs {}", s.height, h(xf, yf));
        prop_assert!((s.grad_x as f64 - (a + c * yf)).abs() < 1e-4);
        prop_assert!((s.grad_y as f64 - (b + c * xf)).abs() < 1e-4);
    }

    /// Whatever the input, the outputs stay finite and in range, and only one actuator drives.
    #[test]
    fn outputs_stay_in_range(moves in proptest::collection::vec((-50.0f32..150.0, -50.0f32..150.0, any::<bool>()), 1..60)) {
        let bytes = plane(0.3, -0.2);
        let view = BundleView::parse(&bytes).unwrap();
        let (_, fp) = finger3();
        let mut p = FingerPlayer::new(&view).unwrap();
        for (k, (x, y, c)) in moves.into_iter().enumerate() {
            let f = p.sample(Touch { tick: Tick(k as u64), x: Mm(x), y: Mm(y), contact: c });
            prop_assert!(f.intensity >= 0.0 && f.intensity <= fp.intensity_max);
            prop_assert!(f.rhythm >= 0.0 && f.rhythm <= fp.rhythm_max);
            if f.active.is_some() {
                prop_assert!(f.period_ms >= 10.0 && f.period_ms <= 210.0);
            }
            prop_assert!(f.levels().iter().filter(|&&v| v > 0.0).count() <= 1);
        }
    }
}

/// The field sampler as it was before the four-node read (commit 83accde):
/// sixteen single-node reads, a loop that skips the nodes without contact,
/// and a floor. The fast sampler must match it bit for bit.
fn reference_sample(field: &HeightFieldView<'_>, x: f32, y: f32) -> Option<field::SurfacePoint> {
    let cell = field.cell.0;
    let u = (x - field.origin_x.0) / cell;
    let v = (y - field.origin_y.0) / cell;
    let (cols, rows) = (field.cols, field.rows);
    if !(u >= 0.0 && v >= 0.0 && u <= (cols - 1) as f32 && v <= (rows - 1) as f32) {
        return None;
    }
    let i = (u.floor() as u32).min(cols - 2);
    let j = (v.floor() as u32).min(rows - 2);
    let (fx, fy) = (u - i as f32, v - j as f32);
    let k00 = j * cols + i;
    let nodes = [
        (k00, (1.0 - fx) * (1.0 - fy)),
        (k00 + 1, fx * (1.0 - fy)),
        (k00 + cols, (1.0 - fx) * fy),
        (k00 + cols + 1, fx * fy),
    ];
    let (mut w, mut h, mut gx, mut gy) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
    let mut edge = false;
    for (k, wk) in nodes {
        let fl = field.flags_at(k);
        if fl & FIELD_CONTACT == 0 {
            continue;
        }
        edge |= fl & FIELD_EDGE != 0 && wk > 0.0;
        let (a, b) = field.gradient_at(k);
        w += wk;
        h += wk * field.height_at(k);
        gx += wk * a;
        gy += wk * b;
    }
    if w < 0.5 {
        return None;
    }
    Some(field::SurfacePoint { height: h / w, grad_x: gx / w, grad_y: gy / w, edge })
}

/// The player as it was before (commit 83accde): a ring of 65 positions
/// indexed modulo 65, and the reference sampler.
struct ReferencePlayer<'a> {
    field: HeightFieldView<'a>,
    params: FingerParams,
    k1: f32,
    k2: f32,
    ring: [(f32, f32); 65],
    len: usize,
    head: usize,
}

impl<'a> ReferencePlayer<'a> {
    const RING: usize = 65;

    fn new(field: HeightFieldView<'a>, params: FingerParams) -> Self {
        let hmax = field.height_min.abs().max(field.height_max.abs());
        let gmax = field.max_gradient;
        let k1 = if gmax > 0.0 { params.rhythm_max / gmax } else { 0.0 };
        let k2 = if hmax > 0.0 { params.intensity_max / hmax } else { 0.0 };
        ReferencePlayer { field, params, k1, k2, ring: [(0.0, 0.0); 65], len: 0, head: 0 }
    }

    fn direction(&self) -> Option<(f32, f32)> {
        if self.len < 2 {
            return None;
        }
        let newest = self.ring[(self.head + Self::RING - 1) % Self::RING];
        let oldest = self.ring[(self.head + Self::RING - self.len) % Self::RING];
        let (dx, dy) = (newest.0 - oldest.0, newest.1 - oldest.1);
        let d = (dx * dx + dy * dy).sqrt();
        if !(d > 0.0 && d >= self.params.min_move_mm) {
            return None;
        }
        Some((dx / d, dy / d))
    }

    fn sample(&mut self, t: Touch) -> FingerFrame {
        let (x, y) = (t.x.0, t.y.0);
        if !t.contact || !x.is_finite() || !y.is_finite() {
            (self.len, self.head) = (0, 0);
            return FingerFrame::off(t.tick);
        }
        let cap = (self.params.direction_window as usize).clamp(1, Self::RING - 1) + 1;
        self.ring[self.head] = (x, y);
        self.head = (self.head + 1) % Self::RING;
        self.len = (self.len + 1).min(cap);
        let Some(p) = reference_sample(&self.field, x, y) else {
            return FingerFrame::off(t.tick);
        };
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
        let rhythm = (self.k1 * local.abs()).clamp(0.0, self.params.rhythm_max);
        let intensity = (self.k2 * p.height.abs()).clamp(0.0, self.params.intensity_max);
        FingerFrame {
            tick: t.tick,
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

/// Bit patterns of a surface point, so that `-0.0` and `0.0` differ.
fn point_bits(p: Option<field::SurfacePoint>) -> Option<(u32, u32, u32, bool)> {
    p.map(|p| (p.height.to_bits(), p.grad_x.to_bits(), p.grad_y.to_bits(), p.edge))
}

/// Bit patterns of a frame.
fn frame_bits(f: FingerFrame) -> (Tick, Option<Actuator>, [u32; 5], bool, bool) {
    let floats = [f.intensity, f.rhythm, f.period_ms, f.height, f.local_gradient].map(f32::to_bits);
    (f.tick, f.active, floats, f.moving, f.on_edge)
}

/// One node of a random field: contact, edge, height and gradient.
type Node = (bool, bool, f32, f32, f32);

/// A random field of 2..=9 by 2..=9 nodes at a cell size that is rarely a
/// power of two, with holes (no-contact nodes, some holding -0.0, which the
/// format allows), edges, and heights that are sometimes exactly ±0.
fn random_field() -> impl Strategy<Value = HeightField> {
    let node = (
        prop::bool::weighted(0.8),
        prop::bool::weighted(0.2),
        prop_oneof![8 => -5.0f32..5.0, 1 => Just(0.0f32), 1 => Just(-0.0f32)],
        -3.0f32..3.0,
        -3.0f32..3.0,
    );
    (2u32..10, 2u32..10, 0.05f32..3.0, -20.0f32..20.0, -20.0f32..20.0, any::<bool>()).prop_flat_map(
        move |(cols, rows, cell, ox, oy, neg_zero_holes)| {
            prop::collection::vec(node.clone(), (cols * rows) as usize).prop_map(move |nodes: Vec<Node>| {
                let n = nodes.len();
                let zero = if neg_zero_holes { -0.0 } else { 0.0 };
                let mut f = HeightField {
                    source: None,
                    cols,
                    rows,
                    origin_x: Mm(ox),
                    origin_y: Mm(oy),
                    cell: Mm(cell),
                    gradient_cap: 10.0,
                    heights: vec![0.0; n],
                    grad_x: vec![0.0; n],
                    grad_y: vec![0.0; n],
                    flags: vec![0; n],
                    encoding: taxel_format::HeightEncoding::Float,
                };
                for (k, (contact, edge, h, gx, gy)) in nodes.into_iter().enumerate() {
                    (f.heights[k], f.grad_x[k], f.grad_y[k], f.flags[k]) = if contact {
                        (h, gx, gy, FIELD_CONTACT | if edge { FIELD_EDGE } else { 0 })
                    } else {
                        (zero, zero, zero, 0)
                    };
                }
                f
            })
        },
    )
}

/// Where to look on a field: a fraction of its extent (beyond it on every
/// side too), exactly a node, or not a number.
#[derive(Debug, Clone, Copy)]
enum Spot {
    Frac(f32, f32),
    Node(u32, u32),
    Nan,
}

fn spot() -> impl Strategy<Value = Spot> {
    prop_oneof![
        8 => (-0.2f32..1.2, -0.2f32..1.2).prop_map(|(a, b)| Spot::Frac(a, b)),
        3 => (0u32..11, 0u32..11).prop_map(|(i, j)| Spot::Node(i, j)),
        1 => Just(Spot::Nan),
    ]
}

fn place(f: &HeightFieldView<'_>, s: Spot) -> (f32, f32) {
    let (ox, oy, c) = (f.origin_x.0, f.origin_y.0, f.cell.0);
    match s {
        Spot::Frac(a, b) => (ox + a * c * (f.cols - 1) as f32, oy + b * c * (f.rows - 1) as f32),
        Spot::Node(i, j) => (ox + i as f32 * c, oy + j as f32 * c),
        Spot::Nan => (f32::NAN, oy),
    }
}

fn field_view(bytes: &[u8]) -> HeightFieldView<'_> {
    let view = BundleView::parse(bytes).unwrap();
    *FingerPlayer::new(&view).unwrap().field()
}

proptest! {
    /// The four-node sampler gives, bit for bit, what the sixteen-read
    /// sampler gave: inside, outside, on nodes and cell sides, next to
    /// holes and edges.
    #[test]
    fn field_sampling_matches_the_reference_bit_for_bit(
        f in random_field(),
        spots in prop::collection::vec(spot(), 1..64),
    ) {
        let bytes = bytes_of(f);
        let hf = field_view(&bytes);
        for s in spots {
            let (x, y) = place(&hf, s);
            prop_assert_eq!(
                point_bits(field::sample(&hf, x, y)),
                point_bits(reference_sample(&hf, x, y)),
                "{:?} at ({}, {})", s, x, y
            );
        }
    }

    /// The player gives, bit for bit, the frames and directions that the
    /// 65-slot player gave, over walks long enough to wrap both rings, with
    /// jumps, lifts, non-finite positions, every window size (and sizes
    /// past the profile's range, which are clamped) and any minimum move.
    #[test]
    fn player_matches_the_reference_bit_for_bit(
        f in random_field(),
        window in prop_oneof![1u32..=64, Just(0u32), Just(65u32), Just(1000u32)],
        min_move in prop_oneof![0.0f32..2.0, Just(0.0f32)],
        start in spot(),
        steps in prop::collection::vec(
            (-1.0f32..1.0, -1.0f32..1.0, prop::bool::weighted(0.97), prop::option::weighted(0.03, spot())),
            1..300,
        ),
    ) {
        let bytes = bytes_of(f);
        let hf = field_view(&bytes);
        let params = FingerParams { direction_window: window, min_move_mm: min_move, ..finger3().1 };
        let mut fast = FingerPlayer::with_field(hf, params);
        let mut slow = ReferencePlayer::new(hf, params);
        let (mut x, mut y) = place(&hf, start);
        let step = hf.cell.0 * 0.7;
        for (k, (dx, dy, contact, jump)) in steps.into_iter().enumerate() {
            (x, y) = match jump {
                Some(s) => place(&hf, s),
                None if !x.is_finite() => place(&hf, Spot::Frac(0.5, 0.5)),
                None => (x + dx * step, y + dy * step),
            };
            let t = Touch { tick: Tick(k as u64), x: Mm(x), y: Mm(y), contact };
            let (a, b) = (fast.sample(t), slow.sample(t));
            prop_assert_eq!(frame_bits(a), frame_bits(b), "sample {} at ({}, {})", k, x, y);
            prop_assert_eq!(
                fast.direction().map(|(a, b)| (a.to_bits(), b.to_bits())),
                slow.direction().map(|(a, b)| (a.to_bits(), b.to_bits()))
            );
        }
    }
}
