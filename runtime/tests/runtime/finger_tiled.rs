//! The finger player on tiled height fields (format 4.6): the same field
//! stored as it is (4.0) and tiled plays the same heights within half a
//! step and the same slopes within what the quantisation and the cell's
//! bending allow; planes play exactly; the tiles a player keeps decoded
//! give what a fresh decoding gives, bit for bit, wherever the finger goes;
//! no allocation per sample.

use proptest::prelude::*;
use taxel_format::{
    Bundle, BundleView, Chunk, FIELD_CONTACT, FIELD_EDGE, FieldReader, HeightEncoding, HeightField, Manifest, Mm, Tick,
    profiles,
};
use taxel_runtime::finger::{FingerPlayer, Touch, field};

/// A field sampled from `h(x, y)` (height and exact gradient) every `cell`
/// mm from (0, 0); `None` is no contact.
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
        encoding: HeightEncoding::Float,
    };
    for j in 0..rows {
        for i in 0..cols {
            let k = (j * cols + i) as usize;
            if let Some((z, gx, gy)) = h(i as f64 * cell as f64, j as f64 * cell as f64) {
                (f.heights[k], f.grad_x[k], f.grad_y[k], f.flags[k]) = (z as f32, gx as f32, gy as f32, FIELD_CONTACT);
            }
        }
    }
    f
}

/// `f` tiled with `step`, its base the lowest contact height.
fn tiled(f: &HeightField, step: f32) -> HeightField {
    let contact = || f.heights.iter().zip(&f.flags).filter(|(_, fl)| **fl & FIELD_CONTACT != 0);
    let base = contact().map(|(h, _)| *h).fold(f32::INFINITY, f32::min);
    let g = f
        .grad_x
        .iter()
        .zip(&f.grad_y)
        .zip(&f.flags)
        .filter(|(_, fl)| **fl & FIELD_CONTACT != 0)
        .map(|((x, y), _)| (x * x + y * y).sqrt())
        .fold(0.0f32, f32::max);
    HeightField { encoding: HeightEncoding::Tiled { step, base, max_gradient: g.min(f.gradient_cap) }, ..f.clone() }
}

fn bytes_of(f: HeightField) -> Vec<u8> {
    let mut b = Bundle::new(Manifest::new(profiles::builtin("finger3").unwrap()));
    b.chunks.push(Chunk::Height(f));
    b.to_bytes().unwrap()
}

fn height_view(bytes: &[u8]) -> taxel_format::HeightFieldView<'_> {
    let view = BundleView::parse(bytes).unwrap();
    view.chunks()
        .find_map(|c| if let taxel_format::ChunkView::Height(h) = c { Some(h) } else { None })
        .expect("a field")
}

/// A convex cap like the paper's (35 − 20 u² − 10 v² mm) over 120 x 60 mm
/// every 0.5 mm, with a 6 mm step at x = 90 mm and a hole.
fn cap(x: f64, y: f64) -> Option<(f64, f64, f64)> {
    let (u, v) = ((x - 60.0) / 60.0, (y - 30.0) / 30.0);
    if (x - 30.0).hypot(y - 40.0) < 6.0 {
        return None;
    }
    let step = if x >= 90.0 { 6.0 } else { 0.0 };
    Some((35.0 - 20.0 * u * u - 10.0 * v * v + step, -40.0 * u / 60.0, -20.0 * v / 30.0))
}

/// [`cap`] every 0.5 mm with its step flagged: the 4.0 field holds the
/// finite difference there.
fn cap_field() -> HeightField {
    let mut f = field_of(241, 121, 0.5, cap);
    for j in 0..f.rows {
        let (a, b) = ((j * f.cols + 179) as usize, (j * f.cols + 180) as usize);
        if f.flags[a] & f.flags[b] & FIELD_CONTACT != 0 {
            let d = ((f.heights[b] - f.heights[a]) / 0.5).clamp(-10.0, 10.0);
            for k in [a, b] {
                f.grad_x[k] = d;
                f.flags[k] |= FIELD_EDGE;
            }
        }
    }
    f
}

#[test]
fn a_tiled_field_plays_the_float_field_within_half_a_step_and_its_slope_within_the_bound() {
    let f = cap_field();
    let step = 0.0005f32;
    let (old, new) = (bytes_of(f.clone()), bytes_of(tiled(&f, step)));
    assert!(new.len() * 5 < old.len(), "tiled {} bytes, 4.0 {} bytes", new.len(), old.len());
    assert_eq!(BundleView::parse(&new).unwrap().version(), (4, 6));
    let (fo, fn_) = (height_view(&old), height_view(&new));
    assert!(fn_.is_tiled() && !fo.is_tiled());
    // The slope of a quadric differs from the secant slope across a cell by
    // at most M * cell (M = 40 / 3600 per mm here), and quantisation adds step / cell.
    let bound = 40.0 / 3600.0 * 0.5 + step as f64 / 0.5 + 1e-4;
    let mut compared = 0;
    for k in 0..20_000u32 {
        let (x, y) = (0.3 + (k as f64 * 0.6180339887).fract() * 119.4, 0.3 + (k as f64 * 0.7548776662).fract() * 59.4);
        let (a, b) = (field::sample(&fo, x as f32, y as f32), field::sample(&fn_, x as f32, y as f32));
        assert_eq!(a.is_some(), b.is_some(), "contact at ({x}, {y})");
        let (Some(a), Some(b)) = (a, b) else { continue };
        assert_eq!(a.edge, b.edge, "edge at ({x}, {y})");
        assert!((a.height - b.height).abs() as f64 <= step as f64 / 2.0 + 1e-4, "height at ({x}, {y}): {a:?} {b:?}");
        // Within a cell of the hole a pair of nodes may lack contact, and
        // the derived slope along it is 0 (SPEC.md section 9.1): compare
        // where the whole cell touches.
        let inside =
            [(-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5)].iter().all(|(dx, dy)| cap(x + dx, y + dy).is_some());
        if !a.edge && inside {
            let e = (a.grad_x - b.grad_x).abs().max((a.grad_y - b.grad_y).abs()) as f64;
            assert!(e <= bound, "slope at ({x}, {y}): {a:?} {b:?}, bound {bound}");
            compared += 1;
        }
    }
    assert!(compared > 14_000, "{compared}");
}

#[test]
fn tiled_samples_allocate_nothing() {
    let bytes = bytes_of(tiled(&field_of(241, 121, 0.5, cap), 0.0005));
    let view = BundleView::parse(&bytes).unwrap();
    let mut on = 0;
    let info = allocation_counter::measure(|| {
        let mut p = FingerPlayer::new(&view).unwrap();
        for k in 0..10_000u64 {
            let t = Touch {
                tick: Tick(k),
                x: Mm((k % 1200) as f32 * 0.1),
                y: Mm(30.0 + (k % 7) as f32),
                contact: k % 500 != 499,
            };
            on += p.sample(t).active.is_some() as u32;
        }
    });
    assert_eq!(info.count_total, 0, "allocations while playing: {info:?}");
    assert!(on > 0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// A plane is stored as plane tiles and played with its own slope and
    /// its height within half a step, anywhere on the field.
    #[test]
    fn a_tiled_plane_plays_its_slope_and_height(
        a in -2.0f64..2.0, b in -2.0f64..2.0, x in 0.0f64..40.0, y in 0.0f64..30.0,
    ) {
        let h = |x: f64, y: f64| 20.0 + a * x + b * y;
        let f = field_of(81, 61, 0.5, |x, y| Some((h(x, y), a, b)));
        let step = 0.001f32;
        let bytes = bytes_of(tiled(&f, step));
        // Planes stored once each and reused from tile to tile: about a kilobyte, against 64 kB at 13 bytes a node.
        prop_assert!(bytes.len() < 2000, "{} bytes", bytes.len());
        let p = field::sample(&height_view(&bytes), x as f32, y as f32).expect("contact");
        prop_assert!((p.height as f64 - h(x, y)).abs() <= step as f64 / 2.0 + 1e-4, "{p:?} vs {}", h(x, y));
        // A plane tile's slope is within the derived slope's bound, step / cell.
        let tol = step as f64 / 0.5;
        prop_assert!((p.grad_x as f64 - a).abs() <= tol && (p.grad_y as f64 - b).abs() <= tol, "{p:?}");
    }
}

/// Points of a walk over a `w` x `h` mm field: steps of up to `reach` mm,
/// now and then a jump anywhere (and past the edges), from `seed`.
fn walk(seed: u64, w: f64, h: f64, reach: f64, n: usize) -> Vec<(f32, f32)> {
    let mut s = seed | 1;
    let mut next = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut x, mut y) = (w / 2.0, h / 2.0);
    (0..n)
        .map(|_| {
            if next() < 0.05 {
                (x, y) = (next() * (w + 4.0) - 2.0, next() * (h + 4.0) - 2.0);
            } else {
                x += (next() - 0.5) * 2.0 * reach;
                y += (next() - 0.5) * 2.0 * reach;
            }
            (x as f32, y as f32)
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// The tiles a reader keeps give, bit for bit, what a fresh decoding
    /// gives, on any walk: within a tile, across tile sides and corners,
    /// jumping, off the field; a cell at a step or a hole.
    #[test]
    fn a_kept_tile_plays_what_a_fresh_one_does(seed in any::<u64>(), reach in 0.05f64..6.0) {
        let bytes = bytes_of(tiled(&cap_field(), 0.0005));
        let view = height_view(&bytes);
        let mut reader = FieldReader::new(view);
        for (x, y) in walk(seed, 120.0, 60.0, reach, 3000) {
            let kept = field::sample_with(&mut reader, x, y);
            let fresh = field::sample(&view, x, y);
            prop_assert_eq!(kept.map(point_bits), fresh.map(point_bits), "at ({}, {})", x, y);
        }
    }
}

fn point_bits(p: field::SurfacePoint) -> [u32; 4] {
    [p.height.to_bits(), p.grad_x.to_bits(), p.grad_y.to_bits(), p.edge as u32]
}
