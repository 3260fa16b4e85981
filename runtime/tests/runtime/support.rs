//! Bundles built directly with taxel-format, and an independent f64
//! reference of the seed-000 equations to compare the player against.

use std::f64::consts::{PI, TAU};

use taxel_format::{
    Bundle, BundleView, Chunk, DeviceProfile, DistanceLayer, Dot, DotKind, DotTable, FamilyParams, Manifest, MaskKind,
    MaskLayer, MaskSamples, MilliHertz, Mm, ProfileName, Tick, profiles,
};
use taxel_runtime::latero::LateroPlayer;

/// The built-in STRESS² profile (8 x 8, 1.2 x 1.4 mm, 1 kHz, 10 bits, 110 x 60 mm).
pub fn stress2() -> DeviceProfile {
    profiles::builtin("stress2").expect("built-in profile")
}

/// An 8 x 8 laterotactile profile with a square 1 mm pitch, so that diagonals are diagonals.
pub fn square_profile() -> DeviceProfile {
    DeviceProfile {
        name: ProfileName::new("square").unwrap(),
        pitch_x_mm: 1.0,
        pitch_y_mm: 1.0,
        params: FamilyParams::Laterotactile,
        ..stress2()
    }
}

/// The canonical bytes of a bundle for `profile` with `chunks`.
pub fn bundle_bytes(profile: DeviceProfile, chunks: Vec<Chunk>) -> Vec<u8> {
    let mut b = Bundle::new(Manifest::new(profile));
    b.chunks = chunks;
    b.to_bytes().expect("valid test bundle")
}

/// A mask layer of constant value 255 covering `[x0, x0 + w) x [y0, y0 + h)` at 1 px/mm.
pub fn uniform_mask(kind: MaskKind, amplitude: f32, x0: f32, y0: f32, w: u32, h: u32) -> MaskLayer {
    MaskLayer {
        source: None,
        kind,
        amplitude,
        origin_x: Mm(x0),
        origin_y: Mm(y0),
        px_per_mm: 1.0,
        width: w,
        height: h,
        samples: MaskSamples::U8(vec![255; (w * h) as usize]),
    }
}

/// A full-amplitude mask over the whole 110 x 60 mm surface.
pub fn full_surface(kind: MaskKind, amplitude: f32) -> Chunk {
    Chunk::Mask(uniform_mask(kind, amplitude, 0.0, 0.0, 110, 60))
}

/// A vibration kind at `hz`.
pub fn vibration(mhz: u32) -> MaskKind {
    MaskKind::Vibration { freq: MilliHertz(mhz) }
}

/// A grating kind.
pub fn grating(wavelength: f32, angle_deg: f32) -> MaskKind {
    MaskKind::Grating { wavelength: Mm(wavelength), angle_deg }
}

/// An outline dot table.
pub fn dots(list: &[(f32, f32, f32, f32)]) -> Chunk {
    Chunk::Dots(DotTable {
        kind: DotKind::Outline,
        dots: list
            .iter()
            .map(|&(x, y, r, a)| Dot { x: Mm(x), y: Mm(y), radius: Mm(r), amplitude: a, source: None })
            .collect(),
    })
}

/// Plays one frame of `bytes`.
pub fn play(bytes: &[u8], tick: u64, x: f32, y: f32) -> Vec<u16> {
    let view = BundleView::parse(bytes).expect("valid bundle");
    let mut storage = vec![taxel_runtime::latero::Layer::EMPTY; view.chunk_count() as usize];
    let player = LateroPlayer::with_storage(&view, &mut storage[..]).expect("laterotactile bundle");
    let mut out = vec![0u16; player.actuator_count()];
    player.frame(Tick(tick), Mm(x), Mm(y), &mut out);
    out
}

// ---- The reference: the paper's equations in f64, written from the paper. ----

/// Page position of actuator (row, col) with the carrier at (x, y) (primitives.md, device family 1).
pub fn actuator_pos(p: &DeviceProfile, x: f64, y: f64, row: usize, col: usize) -> (f64, f64) {
    let cx = (col as f64 - (p.cols as f64 - 1.0) / 2.0) * p.pitch_x_mm as f64;
    let cy = (row as f64 - (p.rows as f64 - 1.0) / 2.0) * p.pitch_y_mm as f64;
    (x + cx, y + cy)
}

/// Eq. 1 with P = 0.25.
pub fn eq1(r: f64) -> f64 {
    const P: f64 = 0.25;
    if r <= P {
        1.0
    } else if r <= 1.0 {
        0.5 + 0.5 * (PI * (r - P) / (1.0 - P)).cos()
    } else {
        0.0
    }
}

/// Eq. 2 for row i, column j at time t seconds.
pub fn eq2(i: usize, j: usize, f_hz: f64, t: f64) -> f64 {
    let c = (TAU * f_hz * t).cos();
    if i % 2 != j % 2 { 0.5 + 0.5 * c } else { 0.5 - 0.5 * c }
}

/// Eq. 3 at page position (x, y) (y down): the author's angle is measured
/// on the page, so the paper's formula is applied to (x, −y).
pub fn eq3(x: f64, y: f64, lambda: f64, angle_deg: f64) -> f64 {
    let th = angle_deg.to_radians();
    let y_up = -y;
    let d = y_up * th.cos() - x * th.sin();
    0.5 + 0.5 * (TAU * d / lambda).cos()
}

/// A mask's value (0..1) at page position (x, y): bilinear between pixel
/// centres, the edge sample between the box edge and the first centre, 0
/// outside the box (the MaskView convention).
pub fn mask_value(m: &MaskLayer, x: f64, y: f64) -> f64 {
    let ppm = m.px_per_mm as f64;
    let (x0, y0) = (m.origin_x.0 as f64, m.origin_y.0 as f64);
    if x < x0 || y < y0 || x >= x0 + m.width as f64 / ppm || y >= y0 + m.height as f64 / ppm {
        return 0.0;
    }
    let s = |i: i64, j: i64| -> f64 {
        let i = i.clamp(0, m.width as i64 - 1) as usize;
        let j = j.clamp(0, m.height as i64 - 1) as usize;
        match &m.samples {
            MaskSamples::U8(v) => v[j * m.width as usize + i] as f64 / 255.0,
            MaskSamples::U16(v) => v[j * m.width as usize + i] as f64 / 65535.0,
        }
    };
    // Continuous pixel coordinates of the point, pixel centres at integers.
    let u = ((x - x0) * ppm - 0.5).clamp(0.0, m.width as f64 - 1.0);
    let v = ((y - y0) * ppm - 0.5).clamp(0.0, m.height as f64 - 1.0);
    let (i, j) = (u.floor() as i64, v.floor() as i64);
    let (a, b) = (u - i as f64, v - j as f64);
    (1.0 - a) * (1.0 - b) * s(i, j)
        + a * (1.0 - b) * s(i + 1, j)
        + (1.0 - a) * b * s(i, j + 1)
        + a * b * s(i + 1, j + 1)
}

/// The composite δ of every layer at actuator (row, col), before clamping.
pub fn reference(p: &DeviceProfile, chunks: &[Chunk], tick: u64, x: f64, y: f64, row: usize, col: usize) -> f64 {
    let (ax, ay) = actuator_pos(p, x, y, row, col);
    if ax < 0.0 || ay < 0.0 || ax > p.surface_w_mm as f64 || ay > p.surface_h_mm as f64 {
        return 0.0;
    }
    let t = tick as f64 / p.rate_hz as f64;
    let mut sum = 0.0;
    for c in chunks {
        match c {
            Chunk::Mask(m) => {
                let a = m.amplitude as f64 * mask_value(m, ax, ay);
                sum += a * match m.kind {
                    MaskKind::Vibration { freq } => eq2(row, col, freq.0 as f64 / 1000.0, t),
                    MaskKind::Grating { wavelength, angle_deg } => eq3(ax, ay, wavelength.0 as f64, angle_deg as f64),
                };
            }
            Chunk::Dots(d) => {
                for dot in &d.dots {
                    let r =
                        ((ax - dot.x.0 as f64).powi(2) + (ay - dot.y.0 as f64).powi(2)).sqrt() / dot.radius.0 as f64;
                    sum += dot.amplitude as f64 * eq1(r);
                }
            }
            Chunk::Distance(d) => {
                let a = d.amplitude as f64 * field_value(d, ax, ay);
                sum += a * match d.kind {
                    MaskKind::Vibration { freq } => eq2(row, col, freq.0 as f64 / 1000.0, t),
                    MaskKind::Grating { wavelength, angle_deg } => eq3(ax, ay, wavelength.0 as f64, angle_deg as f64),
                };
            }
            _ => {}
        }
    }
    sum
}

/// The interpolated code (biased, 0..=255) of a distance layer at page
/// (x, y) in f64, or `None` outside its lattice (SPEC.md section 6.2).
pub fn field_code(d: &DistanceLayer, x: f64, y: f64) -> Option<f64> {
    let h = d.pitch_mm as f64;
    let (u, v) = ((x - d.origin_x.0 as f64) / h, (y - d.origin_y.0 as f64) / h);
    let (w, ht) = (d.tile_cols as f64 * 8.0, d.tile_rows as f64 * 8.0);
    if !(u >= 0.0 && v >= 0.0 && u < w && v < ht) {
        return None;
    }
    let (ci, cj) = (u.floor() as usize, v.floor() as usize);
    let e = d.tiles[(cj / 8) * d.tile_cols as usize + ci / 8];
    if e >> 28 == 0x6 {
        // A fine tile (0x6000_0000 | s << 26 | c << 25 | k, format 4.4): f =
        // 2^s times finer, f² stored tiles a channel from k (two channels
        // where c = 1), row-major; the fine lattice point (x, y) of the tile
        // (x, y in 0..=8f) is sample (x mod 8, y mod 8) of sub-tile (x div 8,
        // y div 8), the last fine cell's far side in the same sub-tile;
        // bilinear within the fine cell, the lesser of the two channels'.
        let f = 1usize << ((e >> 26) & 3);
        let first = (e & 0x01FF_FFFF) as usize;
        let channels = if e & 0x0200_0000 != 0 { 2 } else { 1 };
        let (fu, fw) = ((u - (ci / 8 * 8) as f64) * f as f64, (v - (cj / 8 * 8) as f64) * f as f64);
        let (x, y) = ((fu.floor() as usize).min(8 * f - 1), (fw.floor() as usize).min(8 * f - 1));
        let (a, b) = (fu - x as f64, fw - y as f64);
        let channel = |c: usize| {
            let sub = first + c * f * f + (y / 8) * f + x / 8;
            let s = |i: usize, j: usize| d.samples[sub * 81 + (y % 8 + j) * 9 + x % 8 + i] as f64;
            (1.0 - a) * (1.0 - b) * s(0, 0) + a * (1.0 - b) * s(1, 0) + (1.0 - a) * b * s(0, 1) + a * b * s(1, 1)
        };
        return Some((0..channels).map(channel).fold(f64::INFINITY, f64::min));
    }
    if e >= 0x8000_0000 {
        // A plane (0x8000_0000 | p), ridge (0xC000_0000 | p), corner
        // (0xA000_0000 | p) or notch (0xB000_0000 | p) tile: the record's
        // function at the point, in lattice units from the tile's first
        // lattice point, no interpolation; a corner the lesser of records p
        // and p + 1, a notch the greater.
        let (tu, tw) = (u - (ci / 8 * 8) as f64, v - (cj / 8 * 8) as f64);
        let affine = |p: usize| {
            let r = d.planes[p];
            r.c as f64 + r.gx as f64 * tu + r.gy as f64 * tw
        };
        if e >> 28 == 0x9 {
            // A bend (0x9000_0000 | p): records p = (Vx, Vy, d1x, d1y) and
            // p + 1 = (d2x, d2y, k, top); top − k · the distance to the
            // nearer of the two rays from V (to V itself behind a ray).
            let p = (e & 0x0FFF_FFFF) as usize;
            let (a, b) = (d.planes[p], d.planes[p + 1]);
            let (qx, qy) = (tu - a.c as f64, tw - a.gx as f64);
            let ray = |dx: f32, dy: f32| {
                let (dx, dy) = (dx as f64, dy as f64);
                if qx * dx + qy * dy >= 0.0 { (qx * dy - qy * dx).abs() } else { (qx * qx + qy * qy).sqrt() }
            };
            return Some(b.top as f64 - b.gy as f64 * ray(a.gy, a.top).min(ray(b.c, b.gx)));
        }
        if e >> 28 == 0xD {
            // An arc (0xD000_0000 | p, format 4.1): records p = (Cx, Cy, R,
            // k) and p + 1 = (top, 0, 0, 0); top − k · ||q − C| − R|. A cut
            // arc (format 4.3): p + 1 = (top, c, gx, gy), not all of the
            // last three 0; the lesser of that and c + gx u' + gy w'.
            let p = (e & 0x0FFF_FFFF) as usize;
            let (a, b) = (d.planes[p], d.planes[p + 1]);
            let rho = (tu - a.c as f64).hypot(tw - a.gx as f64);
            let arc = b.c as f64 - a.top as f64 * (rho - a.gy as f64).abs();
            if (b.gx, b.gy, b.top) == (0.0, 0.0, 0.0) {
                return Some(arc);
            }
            return Some(arc.min(b.gx as f64 + b.gy as f64 * tu + b.top as f64 * tw));
        }
        if e >> 28 == 0xE {
            // Segments (0xE000_0000 | p, format 4.2): records p to p + 2 =
            // (ax, ay, bx, by), p + 3 = (k, top, 0, 0); top − k · the
            // distance to the nearest of the three segments.
            let p = (e & 0x0FFF_FFFF) as usize;
            let seg = |s: taxel_format::TilePlane| {
                let (ax, ay, bx, by) = (s.c as f64, s.gx as f64, s.gy as f64, s.top as f64);
                let (ex, ey) = (bx - ax, by - ay);
                let l2 = ex * ex + ey * ey;
                let t = if l2 > 0.0 { (((tu - ax) * ex + (tw - ay) * ey) / l2).clamp(0.0, 1.0) } else { 0.0 };
                (tu - ax - t * ex).hypot(tw - ay - t * ey)
            };
            let near = seg(d.planes[p]).min(seg(d.planes[p + 1])).min(seg(d.planes[p + 2]));
            let last = d.planes[p + 3];
            return Some(last.gx as f64 - last.c as f64 * near);
        }
        return Some(match e >> 28 {
            0xA => affine((e & 0x0FFF_FFFF) as usize).min(affine((e & 0x0FFF_FFFF) as usize + 1)),
            0xB => affine((e & 0x0FFF_FFFF) as usize).max(affine((e & 0x0FFF_FFFF) as usize + 1)),
            0xC => d.planes[(e & 0x3FFF_FFFF) as usize].top as f64 - affine((e & 0x3FFF_FFFF) as usize).abs(),
            _ => affine((e & 0x3FFF_FFFF) as usize),
        });
    }
    let s = |i: usize, j: usize| -> f64 {
        match e {
            0 => 0.0,
            1 => 255.0,
            e => {
                d.samples[(e as usize - 2) * 81 + (j % 8 + (j / 8 - cj / 8) * 8) * 9 + (i % 8 + (i / 8 - ci / 8) * 8)]
                    as f64
            }
        }
    };
    let (a, b) = (u - ci as f64, v - cj as f64);
    Some(
        (1.0 - a) * (1.0 - b) * s(ci, cj)
            + a * (1.0 - b) * s(ci + 1, cj)
            + (1.0 - a) * b * s(ci, cj + 1)
            + a * b * s(ci + 1, cj + 1),
    )
}

/// A distance layer's edge profile (0..1) at page (x, y): ½ + d / ramp, clamped.
pub fn field_value(d: &DistanceLayer, x: f64, y: f64) -> f64 {
    match field_code(d, x, y) {
        None => 0.0,
        Some(c) => profile_of_code(d, c),
    }
}

/// The profile of an interpolated code.
pub fn profile_of_code(d: &DistanceLayer, code: f64) -> f64 {
    let step = d.step_mm as f64;
    let ramp = if d.soft_mm > 0.0 { d.soft_mm as f64 } else { step };
    (0.5 + (code - 128.0) * step / ramp).clamp(0.0, 1.0)
}

/// The expected output code (real-valued, before rounding) of a composite δ.
pub fn expected_code(p: &DeviceProfile, delta: f64) -> f64 {
    delta.clamp(0.0, 1.0) * ((1u32 << p.output_bits) - 1) as f64
}

/// Asserts that every actuator of the player's frame is within one output
/// step of the reference.
pub fn assert_matches_reference(p: &DeviceProfile, chunks: Vec<Chunk>, tick: u64, x: f32, y: f32) {
    let bytes = bundle_bytes(*p, chunks.clone());
    let got = play(&bytes, tick, x, y);
    for row in 0..p.rows as usize {
        for col in 0..p.cols as usize {
            let want = expected_code(p, reference(p, &chunks, tick, x as f64, y as f64, row, col));
            let code = got[p.cols as usize * row + col];
            assert!(
                (code as f64 - want).abs() <= 1.0,
                "actuator ({row}, {col}) at tick {tick}, carrier ({x}, {y}): got {code}, want {want:.3}"
            );
        }
    }
}

/// Draws a frame as text: `.` at rest, `#` at full deflection, otherwise
/// the first decimal digit of δ (so `5` is δ in [0.5, 0.6)).
pub fn art(p: &DeviceProfile, frame: &[u16]) -> String {
    let full = (1u32 << p.output_bits) - 1;
    let mut s = String::new();
    for row in 0..p.rows as usize {
        for col in 0..p.cols as usize {
            let c = frame[p.cols as usize * row + col] as u32;
            s.push(if c == 0 {
                '.'
            } else if c == full {
                '#'
            } else {
                char::from(b'0' + (c * 10 / (full + 1)) as u8)
            });
        }
        s.push('\n');
    }
    s
}
