//! The overlap checks (T0406, T0410): the pairs of features whose boxes
//! meet, once their layers are built. Gaps and the rules of single features
//! are checked before the layers ([`super::check_features`]).

use taxel_format::{DistanceLayer, TILE_CELLS, TILE_OUTSIDE, edge_profile as profile, edge_ramp as ramp};

use super::gaps::near_dot_pairs;
use super::{Built, Feature, FeatureKind, at};
use crate::diagnostic::Diagnostic;
use crate::geometry::dist;
use crate::spatial::{self, Bbox};

/// A distance layer's edge profile (0..=1) at `(x, y)`, 0 outside it.
fn mask_at(m: &DistanceLayer, x: f64, y: f64) -> f64 {
    m.coverage_at(x as f32, y as f32) as f64
}

/// Where a dot is probed for overlaps, in units of its radius: the centre,
/// then eight directions on rings at a quarter (the plateau's edge), half
/// and three quarters of the radius.
const DOT_PROBES: [(f64, f64); 25] = {
    let mut p = [(0.0, 0.0); 25];
    let dirs = [
        (1.0, 0.0),
        (core::f64::consts::FRAC_1_SQRT_2, core::f64::consts::FRAC_1_SQRT_2),
        (0.0, 1.0),
        (-core::f64::consts::FRAC_1_SQRT_2, core::f64::consts::FRAC_1_SQRT_2),
        (-1.0, 0.0),
        (-core::f64::consts::FRAC_1_SQRT_2, -core::f64::consts::FRAC_1_SQRT_2),
        (0.0, -1.0),
        (core::f64::consts::FRAC_1_SQRT_2, -core::f64::consts::FRAC_1_SQRT_2),
    ];
    let rings = [0.25, 0.5, 0.75];
    let mut k = 1;
    let mut ri = 0;
    while ri < 3 {
        let mut di = 0;
        while di < 8 {
            p[k] = (dirs[di].0 * rings[ri], dirs[di].1 * rings[ri]);
            k += 1;
            di += 1;
        }
        ri += 1;
    }
    p
};

/// Slack above full deflection before an overlap is reported: anti-aliased
/// edges of shapes that merely meet (two regions sharing a border) can sum a
/// little above 1 at the seam; a real overlap sums to about 2.
const SUM_SLACK: f64 = 0.1;

/// How far inside both layers' exact edges a point must lie to count as an
/// overlap of two distance layers, mm: the edge accuracy the layers promise.
const OVERLAP_DEPTH_MM: f64 = 0.05;

/// Where two distance layers (each with the amplitude of its feature)
/// overlap within the box `(x0, y0, x1, y1)`: a point of the box's 0.1 mm
/// lattice (as the raster masks were sampled) felt more than
/// [`OVERLAP_DEPTH_MM`] inside both layers' edges, where their amplitudes
/// sum above full deflection (where two layers merely meet, each one's ramp
/// may sum a little above 1 in a seam a few micrometres wide).
///
/// Every condition is a pure function of the point, so the answer is that
/// of reading both layers' coverage and depth at every point (as this did
/// until it was most of a map's overlap checks), but each point costs less:
///
/// - a point in a tile wholly outside one layer (or off its lattice) is not
///   deep in it, which [`Row`] tells without reading the layer;
/// - otherwise one layer's distance is read first and the other's only
///   where the first is deep, and the profile comes from that same
///   distance ([`DistanceLayer::coverage_at`] is the profile of
///   [`DistanceLayer::distance_at`]); the layer that turned the last point
///   away is read first.
///
/// Two bordering regions' boxes overlap mostly outside one of them, and a
/// map's sea is a grating cut out under every region painted over it: 83 %
/// of the points sampled against it on a map of 1,000 regions lie in its
/// outside tiles.
// Not inlined: inlined into `overlap` (with one of its reads of
// `distance_at`), it took 14 M more instructions on the map of 1,000 regions.
#[inline(never)]
fn layers_overlap((ma, amp_a): (&DistanceLayer, f64), (mb, amp_b): (&DistanceLayer, f64), common: Bbox) -> bool {
    let (x0, y0, x1, y1) = common;
    let deep = |m: &DistanceLayer, x: f32, y: f32| m.distance_at(x, y).filter(|&d| d as f64 > OVERLAP_DEPTH_MM);
    let coverage = |m: &DistanceLayer, d: f32| profile(d, ramp(m.soft_mm, m.step_mm)) as f64;
    // Sampled every 0.1 mm, as the raster masks were.
    let px = 10.0;
    let mut b_first = false;
    let mut y = ((y0 * px).floor() + 0.5) / px;
    while y < y1 {
        let yf = y as f32;
        let mut rows = [Row::new(ma, yf), Row::new(mb, yf)];
        y += 1.0 / px;
        if rows.iter().any(Row::never_deep) {
            continue;
        }
        let mut x = ((x0 * px).floor() + 0.5) / px;
        while x < x1 {
            let xf = x as f32;
            x += 1.0 / px;
            let (first, second) = if b_first { (1, 0) } else { (0, 1) };
            if rows[first].outside_at(xf) {
                continue;
            }
            let Some(d1) = deep(rows[first].m, xf, yf) else { continue };
            if rows[second].outside_at(xf) {
                b_first = !b_first;
                continue;
            }
            let Some(d2) = deep(rows[second].m, xf, yf) else {
                b_first = !b_first;
                continue;
            };
            let (da, db) = if first == 0 { (d1, d2) } else { (d2, d1) };
            if amp_a * coverage(ma, da) + amp_b * coverage(mb, db) > 1.0 + SUM_SLACK {
                return true;
            }
        }
    }
    false
}

/// One row of points (one `y`) across a distance layer, and the run of it
/// last looked at: the points whose lattice `x` (as
/// [`DistanceLayer::distance_at`] works it out, `(x - origin_x) / pitch`)
/// lies in `lo..hi` fall in one tile, or all off the lattice, and `outside`
/// says whether that is a tile wholly outside or off the lattice. There the
/// layer's distance is at or below 0 (an outside tile's is `-128` steps,
/// for a step at or above 0), or it has none: never deep. Along a row a
/// 0.1 mm step stays 40 points in one tile of 4 mm, so finding its tile
/// costs one division and two comparisons a point.
struct Row<'a> {
    m: &'a DistanceLayer,
    /// The row of tiles, or `None` when the row lies off the lattice.
    tiles: Option<usize>,
    lo: f32,
    hi: f32,
    outside: bool,
}

impl<'a> Row<'a> {
    fn new(m: &'a DistanceLayer, y: f32) -> Self {
        let fy = (y - m.origin_y.0) / m.pitch_mm;
        let rows = (m.tile_rows as usize * TILE_CELLS) as f32;
        let tiles = (fy >= 0.0 && fy < rows).then_some(fy as usize / TILE_CELLS);
        // Empty until the first point is looked up.
        Row { m, tiles, lo: f32::INFINITY, hi: f32::NEG_INFINITY, outside: false }
    }

    /// Whether no point of the row can be deep in the layer (it lies off
    /// the lattice).
    fn never_deep(&self) -> bool {
        self.tiles.is_none()
    }

    /// Whether the point at `x` of the row lies in a tile wholly outside
    /// the layer or off its lattice.
    fn outside_at(&mut self, x: f32) -> bool {
        let m = self.m;
        let fx = (x - m.origin_x.0) / m.pitch_mm;
        if !(self.lo <= fx && fx < self.hi) {
            self.locate(fx);
        }
        self.outside
    }

    fn locate(&mut self, fx: f32) {
        let m = self.m;
        let cols = (m.tile_cols as usize * TILE_CELLS) as f32;
        // Where `distance_at` finds no tile, there is no distance.
        (self.lo, self.hi, self.outside) = match self.tiles {
            None => (f32::NEG_INFINITY, f32::INFINITY, true),
            Some(row) if fx >= 0.0 && fx < cols => {
                let t = fx as usize / TILE_CELLS;
                let entry = m.tiles.get(row * m.tile_cols as usize + t);
                let outside = entry.is_none_or(|&e| e == TILE_OUTSIDE && m.step_mm >= 0.0);
                // The tile's run, `8 t ..8 (t + 1)`, while f32 holds those
                // exactly; beyond, this point alone.
                let (lo, hi) = (t * TILE_CELLS, (t + 1) * TILE_CELLS);
                if hi <= 1 << f32::MANTISSA_DIGITS { (lo as f32, hi as f32, outside) } else { (fx, fx, outside) }
            }
            Some(_) if fx >= cols => (cols, f32::INFINITY, true),
            // Below 0, or not a number (which no run holds).
            Some(_) => (f32::NEG_INFINITY, 0.0, true),
        };
    }
}

pub(super) fn overlap(built: &Built, a: &Feature, b: &Feature, diags: &mut Vec<Diagnostic>) {
    if !spatial::meet(a.bbox, b.bbox) {
        return;
    }
    let over = match (a.mask, b.mask) {
        // Shapes of one style are one layer: where they touch or overlap
        // they merge into one border or region instead of adding up.
        (Some(ia), Some(ib)) if ia == ib => false,
        // A vibrating band is cut out of every grating whose shapes its box
        // meets (`layers::distance_layers`): where the band is felt deep
        // inside, the grating's distance is negative, so the two never
        // overlap and there is nothing to sample.
        (Some(_), Some(_))
            if matches!(
                (&a.kind, &b.kind),
                (FeatureKind::Vibrate { .. }, FeatureKind::Grating { .. })
                    | (FeatureKind::Grating { .. }, FeatureKind::Vibrate { .. })
            ) =>
        {
            false
        }
        (Some(ia), Some(ib)) => {
            let common =
                (a.bbox.0.max(b.bbox.0), a.bbox.1.max(b.bbox.1), a.bbox.2.min(b.bbox.2), a.bbox.3.min(b.bbox.3));
            layers_overlap((&built.layers[ia], a.amplitude), (&built.layers[ib], b.amplitude), common)
        }
        (Some(im), None) | (None, Some(im)) => {
            let (m, d) = if a.mask.is_some() { (a, b) } else { (b, a) };
            let layer = &built.layers[im];
            // Eq. 1 at the centre and on rings across the dot's slope: a
            // layer cut out under the dot (hidden by the painted circle)
            // may still reach under its edge.
            d.dots.iter().any(|&(x, y, r)| {
                DOT_PROBES.iter().any(|&(u, v)| {
                    let (px, py) = (x + u * r, y + v * r);
                    let dot = crate::preview::dot_profile(u.hypot(v));
                    d.amplitude * dot + m.amplitude * mask_at(layer, px, py) > 1.0 + SUM_SLACK
                })
            })
        }
        (None, None) => {
            let mut n = 0usize;
            near_dot_pairs(a, b, 0.0, |p, q| {
                if dist((p.0, p.1), (q.0, q.1)) < (p.2 + q.2) * (1.0 - 1e-4) {
                    n += 1;
                }
            });
            if n > 0 {
                diags.push(at(
                    Diagnostic::warning("T0406", format!("{n} dot(s) of this element overlap dots of #{}", a.name))
                        .with_help("dots must not overlap (seed 000 eq. 1); move the elements apart"),
                    b,
                ));
            }
            false
        }
    };
    if over {
        diags.push(at(
            Diagnostic::warning(
                "T0410",
                format!("this layer overlaps #{} and together they exceed full deflection", a.name),
            )
            .with_help("layers add up (seed 000 §3.4); keep active regions apart or lower their amplitudes"),
            b,
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use taxel_format::{MaskKind, Mm, TILE_FIRST_STORED, TILE_INSIDE, TILE_SAMPLES};

    /// The overlap of two layers as it was first written: both layers'
    /// coverage and depth read at every point of the box.
    fn overlap_read_at_every_point(
        (ma, amp_a): (&DistanceLayer, f64),
        (mb, amp_b): (&DistanceLayer, f64),
        (x0, y0, x1, y1): Bbox,
    ) -> bool {
        let px = 10.0;
        let mut y = ((y0 * px).floor() + 0.5) / px;
        while y < y1 {
            let mut x = ((x0 * px).floor() + 0.5) / px;
            while x < x1 {
                let deep =
                    |m: &DistanceLayer| m.distance_at(x as f32, y as f32).is_some_and(|d| d as f64 > OVERLAP_DEPTH_MM);
                if amp_a * mask_at(ma, x, y) + amp_b * mask_at(mb, x, y) > 1.0 + SUM_SLACK && deep(ma) && deep(mb) {
                    return true;
                }
                x += 1.0 / px;
            }
            y += 1.0 / px;
        }
        false
    }

    /// A deterministic sequence in [0, 1) (xorshift).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// A layer of random tiles, wholly outside, wholly inside or stored
    /// (samples from 40 steps outside to 60 inside), on a lattice near the
    /// page's corner; now and then with a negative step, where a tile
    /// wholly outside is felt deep inside and must be read.
    fn random_layer(r: &mut Rng) -> DistanceLayer {
        let (cols, rows) = (1 + (r.next() * 5.0) as u32, 1 + (r.next() * 4.0) as u32);
        let pitch = [0.5f32, 0.25, 0.3][(r.next() * 3.0) as usize];
        let mut step = 0.01 + 0.03 * r.next() as f32;
        if r.next() < 0.1 {
            step = -step;
        }
        let (mut tiles, mut samples) = (Vec::new(), Vec::new());
        for _ in 0..cols * rows {
            let u = r.next();
            if u < 0.45 {
                tiles.push(TILE_OUTSIDE);
            } else if u < 0.6 {
                tiles.push(TILE_INSIDE);
            } else {
                tiles.push(TILE_FIRST_STORED + (samples.len() / TILE_SAMPLES) as u32);
                let level = r.next() * 100.0 - 40.0;
                samples.extend((0..TILE_SAMPLES).map(|_| (128.0 + level + r.next() * 30.0 - 15.0) as u8));
            }
        }
        DistanceLayer {
            kind: MaskKind::Grating { wavelength: Mm(2.0), angle_deg: 0.0 },
            amplitude: 1.0,
            soft_mm: if r.next() < 0.5 { 0.0 } else { 0.3 },
            step_mm: step,
            origin_x: Mm((r.next() * 4.0 - 2.0) as f32),
            origin_y: Mm((r.next() * 4.0 - 2.0) as f32),
            pitch_mm: pitch,
            tile_cols: cols,
            tile_rows: rows,
            sources: Vec::new(),
            tiles,
            planes: Vec::new(),
            samples,
        }
    }

    #[test]
    fn layers_overlap_where_reading_every_point_finds_it() {
        let mut r = Rng(0x2545_f491_4f6c_dd1d);
        let (mut found, mut beside_outside, mut cases) = (0, 0, 0);
        for _ in 0..300 {
            let (ma, mb) = (random_layer(&mut r), random_layer(&mut r));
            let tile = |m: &DistanceLayer| m.pitch_mm as f64 * TILE_CELLS as f64;
            for _ in 0..12 {
                // Corners anywhere around the lattices, or on a tile's edge.
                let corner = |r: &mut Rng, m: &DistanceLayer| {
                    if r.next() < 0.3 {
                        let k = (r.next() * 4.0).floor();
                        (m.origin_x.0 as f64 + k * tile(m), m.origin_y.0 as f64 + k * tile(m))
                    } else {
                        (r.next() * 16.0 - 4.0, r.next() * 14.0 - 4.0)
                    }
                };
                let on_a = r.next() < 0.5;
                let (x0, y0) = corner(&mut r, if on_a { &ma } else { &mb });
                let (w, h) = (r.next() * 8.0, r.next() * 6.0);
                let common = (x0, y0, x0 + w, y0 + h);
                let (amp_a, amp_b) = (0.4 + 0.6 * r.next(), 0.4 + 0.6 * r.next());
                let want = overlap_read_at_every_point((&ma, amp_a), (&mb, amp_b), common);
                assert_eq!(layers_overlap((&ma, amp_a), (&mb, amp_b), common), want, "{common:?}");
                cases += 1;
                found += usize::from(want);
                // An overlap in a box that also holds a tile wholly outside one layer.
                let outside = |m: &DistanceLayer| {
                    let mut rows = (0..=(h * 10.0) as usize).map(|k| Row::new(m, (y0 + k as f64 * 0.1) as f32));
                    rows.any(|mut row| (0..=(w * 10.0) as usize).any(|k| row.outside_at((x0 + k as f64 * 0.1) as f32)))
                };
                if want && (outside(&ma) || outside(&mb)) {
                    beside_outside += 1;
                }
            }
        }
        // Both answers are common, and overlaps beside outside tiles too.
        assert!(found > cases / 20 && found < cases * 19 / 20, "{found} overlaps of {cases}");
        assert!(beside_outside > 100, "only {beside_outside} overlaps beside tiles wholly outside");
    }
}
