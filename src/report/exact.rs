//! The exact reference for laterotactile scenes: the seed-000 equations
//! evaluated in f64 with exact geometry, at every actuator of a frame.
//!
//! A raster mask is an approximation of a region; here the region is the
//! shape itself (a polygon fill, or the band within `width / 2` of the
//! outline), tested point by point on the flattened f64 outline by the
//! compiler's exact region of the layer's planned geometry
//! (`taxel_compiler::latero::ExactRegion`); this module turns it into
//! actuator values (eq. 1 to 3 and the edge profile) and lists the corners
//! the report measures apart. Dots are
//! already exact (centre and radius), so they enter through eq. 1 in f64.
//! The reference is what the runtime *should* output before its last rounding
//! to 10 bits; errors are reported in steps of that output.

use std::sync::Arc;

use taxel_compiler::geometry::Polyline;
use taxel_compiler::latero::{ExactRegion, LayerGeometry};
use taxel_format::DeviceProfile;

/// Plateau of eq. 1 (seed 000, section 3.1), written here again so that the
/// reference does not borrow the runtime's constant.
const PLATEAU: f64 = 0.25;

/// Where a layer is on: the compiler's exact region of the layer's geometry
/// ([`ExactRegion`]: the union of its sources, a grating less the vibrating
/// bands cut out of it, the opaque fills and braille clearings over it,
/// within its clips), and the corners of its outlines, which the report
/// measures apart.
#[derive(Debug)]
pub struct Region {
    /// The exact region: coverage and the distance to its edge.
    pub exact: ExactRegion,
    /// The corners of the outlines and of the bands' centre lines (see [`corners`]).
    pub corners: Vec<(f64, f64)>,
}

impl Region {
    /// The region of a layer made of `g`, with its corners: a band's centre
    /// lines' (with the band's inner corners and ends), and the outlines'
    /// of the fills, clips and occluders, and the cut bands' centre lines'.
    pub fn of(g: &LayerGeometry<'_>) -> Region {
        let band = g.band.iter().flat_map(|(lines, w)| lines.iter().flat_map(|pl| corners(pl, false, Some(*w))));
        let outlines = g.fills.iter().chain(&g.clips).chain(&g.occluders).flat_map(|(f, _)| corners(f, true, None));
        let cuts = g.cuts.iter().flat_map(|&(b, w)| corners(b, false, Some(w)));
        Region { exact: g.exact(), corners: band.chain(outlines).chain(cuts).collect() }
    }

    /// The exact edge profile at page point `p` for a layer whose edge ramp
    /// is `ramp` mm wide: SPEC.md section 6.2's `clamp(½ + d / ramp, 0, 1)` of
    /// the exact signed distance `d` (positive where the region is felt).
    /// A ramp of 0 is the ideal step: 1 where the region covers `p`, else 0.
    pub fn edge_profile(&self, p: (f64, f64), ramp: f64) -> f64 {
        self.edge_sample(p, ramp / 2.0).profile(ramp)
    }

    /// What [`Region::edge_profile`] needs at `p` for any ramp up to
    /// `2 reach` mm wide: the coverage, and the distance to the edge where it
    /// is less than `reach`. The distances are most of a report's time, and
    /// the same at every rung: only the ramp changes.
    pub fn edge_sample(&self, p: (f64, f64), reach: f64) -> EdgeSample {
        let covers = self.exact.covers(p);
        let distance = self.exact.distance_to_edge_within(p, reach).unwrap_or(f64::INFINITY);
        EdgeSample { covers, distance }
    }
}

/// Where a place stands against a region's edge ([`Region::edge_sample`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeSample {
    /// Whether the region covers the place.
    pub covers: bool,
    /// Its distance to the region's edge, mm, where less than the reach it
    /// was sampled with; else infinite.
    pub distance: f64,
}

impl EdgeSample {
    /// The edge profile for a ramp `ramp` mm wide, at most twice the reach
    /// the sample was taken with: SPEC.md section 6.2's `clamp(½ + d / ramp,
    /// 0, 1)` of the signed distance `d`; the ideal step for a ramp of 0
    /// (or NaN), and beyond half the ramp. The same as the distance within
    /// half the ramp: the nearest edge point found within a larger reach is
    /// the one found within a smaller reach, when it lies within that.
    pub fn profile(&self, ramp: f64) -> f64 {
        if ramp > 0.0 && self.distance < ramp / 2.0 {
            let d = if self.covers { self.distance } else { -self.distance };
            return (0.5 + d / ramp).clamp(0.0, 1.0);
        }
        if self.covers { 1.0 } else { 0.0 }
    }
}

/// A segment in page mm.
pub type Seg = ((f64, f64), (f64, f64));

/// Turns sharper than this (degrees) make a vertex a corner.
pub const CORNER_TURN_DEG: f64 = 30.0;

/// The corners of outlines: vertices where the direction turns by more than
/// [`CORNER_TURN_DEG`]. Fills close every outline. For the centre line of a
/// band `band` mm wide also the ends of open outlines (a round cap is as
/// sharp a feature as a corner) and, at each corner, the inner corner of the
/// band, where its two offset lines meet (`band / 2 / cos(turn / 2)` from the
/// vertex along the bisector, at most `5 band`): its round outer join is
/// within `band / 2` of the vertex.
pub fn corners(polys: &[Polyline], closed_fill: bool, band: Option<f64>) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for pl in polys {
        // Consecutive repeated points make no direction.
        let mut pts: Vec<(f64, f64)> = Vec::with_capacity(pl.points.len());
        for &p in &pl.points {
            if pts.last() != Some(&p) && p.0.is_finite() && p.1.is_finite() {
                pts.push(p);
            }
        }
        let closed = if closed_fill { pts.len() > 2 } else { pl.closed && pts.len() > 2 };
        if closed && pts.len() > 1 && pts.first() == pts.last() {
            pts.pop();
        }
        let n = pts.len();
        if n == 1 {
            out.push(pts[0]);
            continue;
        }
        for i in 0..n {
            let (prev, next) = if closed {
                (pts[(i + n - 1) % n], pts[(i + 1) % n])
            } else if i == 0 || i == n - 1 {
                if band.is_some() {
                    out.push(pts[i]);
                }
                continue;
            } else {
                (pts[i - 1], pts[i + 1])
            };
            let p = pts[i];
            let (a, b) = (unit(p.0 - prev.0, p.1 - prev.1), unit(next.0 - p.0, next.1 - p.1));
            let turn = (a.0 * b.1 - a.1 * b.0).atan2(a.0 * b.0 + a.1 * b.1).abs();
            if turn > CORNER_TURN_DEG.to_radians() {
                out.push(p);
                if let Some(w) = band {
                    let reach = (w / 2.0 / (turn / 2.0).cos()).min(5.0 * w);
                    let bis = unit(b.0 - a.0, b.1 - a.1);
                    out.push((p.0 + bis.0 * reach, p.1 + bis.1 * reach));
                }
            }
        }
    }
    out
}

/// `(x, y)` scaled to length 1 (0 stays 0).
fn unit(x: f64, y: f64) -> (f64, f64) {
    let l = x.hypot(y);
    if l > 0.0 { (x / l, y / l) } else { (0.0, 0.0) }
}

/// One layer of the reference scene.
#[derive(Debug, Clone)]
pub enum ExactLayer {
    /// Eq. 2 over a region.
    Vibration {
        /// Where it is on.
        region: Arc<Region>,
        /// Frequency in hertz.
        freq_hz: f64,
        /// Amplitude 0..=1.
        amplitude: f64,
        /// Width of the edge ramp in mm (the layer's `soft` width, or its
        /// distance code's `step` for a hard edge; SPEC.md section 6.2); 0 is
        /// the ideal step.
        ramp_mm: f64,
        /// Provenance entries of the elements it holds (of its distance layer).
        sources: Vec<u32>,
    },
    /// Eq. 3 over a region.
    Grating {
        /// Where it is on.
        region: Arc<Region>,
        /// Wavelength in mm.
        wavelength_mm: f64,
        /// Ridge direction on the page, degrees counter-clockwise from +x.
        angle_deg: f64,
        /// Amplitude 0..=1.
        amplitude: f64,
        /// Width of the edge ramp in mm, as for [`ExactLayer::Vibration`].
        ramp_mm: f64,
        /// Provenance entries of the elements it holds (of its distance layer).
        sources: Vec<u32>,
    },
    /// Eq. 1 for each dot.
    Dots(Dots),
}

/// A dots layer's dots `(x, y, radius, amplitude)` in mm, sorted by `x`,
/// so that a point asks only the dots that may reach it (a map's dotted
/// symbols hold hundreds, and every actuator of every frame asked each).
#[derive(Debug, Clone, Default)]
pub struct Dots {
    dots: Vec<(f64, f64, f64, f64)>,
    /// The largest radius.
    reach: f64,
}

impl Dots {
    /// The dots of radius above 0 among `dots` (`(x, y, radius, amplitude)`, mm).
    pub fn new(dots: impl IntoIterator<Item = (f64, f64, f64, f64)>) -> Self {
        let mut dots: Vec<_> =
            dots.into_iter().filter(|&(x, y, r, _)| r > 0.0 && x.is_finite() && y.is_finite()).collect();
        dots.sort_by(|a, b| a.0.total_cmp(&b.0));
        let reach = dots.iter().map(|d| d.2).fold(0.0, f64::max);
        Dots { dots, reach }
    }

    /// Eq. 1 summed over the dots at `(x, y)`: those within their radius of it.
    pub fn at(&self, x: f64, y: f64) -> f64 {
        let from = self.dots.partition_point(|d| d.0 < x - self.reach);
        self.dots[from..]
            .iter()
            .take_while(|d| d.0 <= x + self.reach)
            .filter(|&&(cx, cy, r, _)| (x - cx).abs() < r && (y - cy).abs() < r)
            .map(|&(cx, cy, r, a)| a * dot_profile((x - cx).hypot(y - cy) / r))
            .sum()
    }
}

/// Eq. 1 with plateau P = 0.25: deflection at normalised distance `r`.
pub fn dot_profile(r: f64) -> f64 {
    if r <= PLATEAU {
        1.0
    } else if r <= 1.0 {
        0.5 + 0.5 * (std::f64::consts::PI * (r - PLATEAU) / (1.0 - PLATEAU)).cos()
    } else {
        0.0
    }
}

/// The exact frame at `tick` with the carrier at `(x, y)`: deflection δ of
/// each actuator, composited by addition and clamped to `[0, 1]` (seed 000
/// section 3.4), in the runtime's index order `cols · row + col`.
#[cfg(test)]
pub fn frame(layers: &[ExactLayer], profile: &DeviceProfile, tick: u64, x: f64, y: f64, out: &mut [f64]) {
    frame_sum(layers, &[], profile, tick, x, y, out);
    for o in out.iter_mut() {
        *o = clamp_sum(*o);
    }
}

/// A frame's value from the sum of its layers' values: 0 for NaN, else clamped to 0..=1.
pub fn clamp_sum(d: f64) -> f64 {
    if d.is_nan() { 0.0 } else { d.clamp(0.0, 1.0) }
}

/// The sum of `layers`' values at each actuator, in layer order, before
/// [`clamp_sum`] makes it the exact frame (the tests' `frame`), so that
/// the sums of several groups of layers can be added first. Where
/// `samples[i]` is given, it holds layer `i`'s [`EdgeSample`] of each
/// actuator (in the runtime's index order), taken with a reach of at least
/// half the layer's ramp, and the layer's edge is read from it rather than
/// measured again.
pub fn frame_sum(
    layers: &[ExactLayer],
    samples: &[Option<&[EdgeSample]>],
    profile: &DeviceProfile,
    tick: u64,
    x: f64,
    y: f64,
    out: &mut [f64],
) {
    let (rows, cols) = (profile.rows as usize, profile.cols as usize);
    let (px, py) = (profile.pitch_x_mm as f64, profile.pitch_y_mm as f64);
    let (sw, sh) = (profile.surface_w_mm as f64, profile.surface_h_mm as f64);
    // Phase of the time-varying part, in turns, from the integer tick (exact
    // in f64 for any tick below 2^53).
    let t_s = tick as f64 / profile.rate_hz.max(1) as f64;
    for row in 0..rows {
        for col in 0..cols {
            let Some(o) = out.get_mut(row * cols + col) else { return };
            let ax = x + (col as f64 - (cols as f64 - 1.0) / 2.0) * px;
            let ay = y + (row as f64 - (rows as f64 - 1.0) / 2.0) * py;
            if !(0.0..=sw).contains(&ax) || !(0.0..=sh).contains(&ay) {
                *o = 0.0;
                continue;
            }
            let mut d = 0.0;
            for (i, layer) in layers.iter().enumerate() {
                let sampled = samples.get(i).copied().flatten().and_then(|s| s.get(row * cols + col));
                let edge_of = |region: &Region, ramp: f64| match sampled {
                    Some(s) => s.profile(ramp),
                    None => region.edge_profile((ax, ay), ramp),
                };
                d += match layer {
                    ExactLayer::Vibration { region, freq_hz, amplitude, ramp_mm, .. } => {
                        let edge = edge_of(region, *ramp_mm);
                        if edge == 0.0 {
                            continue;
                        }
                        let c = (std::f64::consts::TAU * freq_hz * t_s).cos();
                        let v = if row % 2 != col % 2 { 0.5 + 0.5 * c } else { 0.5 - 0.5 * c };
                        amplitude * edge * v
                    }
                    ExactLayer::Grating { region, wavelength_mm, angle_deg, amplitude, ramp_mm, .. } => {
                        let edge = edge_of(region, *ramp_mm);
                        if edge == 0.0 {
                            continue;
                        }
                        // Eq. 3 with the page's y axis flipped (primitives.md): the
                        // author's angle is counter-clockwise as seen on the page.
                        let th = angle_deg.to_radians();
                        let dist = (-ay) * th.cos() - ax * th.sin();
                        amplitude * edge * (0.5 + 0.5 * (std::f64::consts::TAU * dist / wavelength_mm).cos())
                    }
                    ExactLayer::Dots(dots) => dots.at(ax, ay),
                };
            }
            *o = d;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use taxel_compiler::geometry::FillRule;

    /// The region of fills `(outline, rule)`, less cut bands `(centre lines, width)`.
    fn fill(fills: &[(&[Polyline], FillRule)], cuts: &[(&[Polyline], f64)]) -> Arc<Region> {
        Arc::new(Region::of(&LayerGeometry { fills: fills.to_vec(), cuts: cuts.to_vec(), ..Default::default() }))
    }

    /// The region of a band `width` mm wide along `lines`.
    fn band(lines: Vec<&[Polyline]>, width: f64) -> Arc<Region> {
        Arc::new(Region::of(&LayerGeometry { band: Some((lines, width)), ..Default::default() }))
    }

    fn stress2() -> DeviceProfile {
        taxel_format::profiles::builtin("stress2").expect("built-in profile")
    }

    #[test]
    fn dot_profile_follows_eq1() {
        assert_eq!(dot_profile(0.0), 1.0);
        assert_eq!(dot_profile(0.25), 1.0);
        // Half way down the cosine flank: r = P + (1 − P)/2.
        assert!((dot_profile(0.625) - 0.5).abs() < 1e-12);
        assert!(dot_profile(1.0).abs() < 1e-12);
        assert_eq!(dot_profile(1.5), 0.0);
    }

    #[test]
    fn vibration_is_checkerboard_antiphase_at_tick_zero() {
        let sq = Polyline { points: vec![(0.0, 0.0), (110.0, 0.0), (110.0, 60.0), (0.0, 60.0)], closed: true };
        let sq = [sq];
        let layers = [ExactLayer::Vibration {
            region: fill(&[(&sq, FillRule::NonZero)], &[]),
            freq_hz: 50.0,
            amplitude: 1.0,
            ramp_mm: 0.0,
            sources: Vec::new(),
        }];
        let mut out = [0.0; 64];
        frame(&layers, &stress2(), 0, 50.0, 30.0, &mut out);
        // cos 0 = 1: parities that differ are fully left, the others at rest.
        assert_eq!(&out[..4], &[0.0, 1.0, 0.0, 1.0]);
        // 10 ms later (half a period at 50 Hz) the pattern has swapped.
        frame(&layers, &stress2(), 10, 50.0, 30.0, &mut out);
        assert!((out[0] - 1.0).abs() < 1e-12 && out[1].abs() < 1e-12);
    }

    /// One style's two touching outlines are one region: on the shared side
    /// the layer is felt once (amplitude · v), not twice and clamped.
    #[test]
    fn touching_outlines_of_one_style_are_one_band() {
        let sq = |x0: f64| Polyline {
            points: vec![(x0, 20.0), (x0 + 20.0, 20.0), (x0 + 20.0, 40.0), (x0, 40.0)],
            closed: true,
        };
        let (a, b) = ([sq(30.0)], [sq(50.0)]);
        let layers = [ExactLayer::Vibration {
            region: band(vec![&a, &b], 1.5),
            freq_hz: 50.0,
            amplitude: 0.6,
            ramp_mm: 0.0,
            sources: vec![0, 1],
        }];
        let p = stress2();
        let mut out = [0.0; 64];
        // Carrier centred on the shared side x = 50: actuator columns 3 and 4
        // are at x = 50 ∓ 0.6 (within the 0.75 mm half-width of both bands).
        frame(&layers, &p, 0, 50.0, 30.0, &mut out);
        for row in 0..8 {
            for col in [3usize, 4] {
                let v = if row % 2 != col % 2 { 1.0 } else { 0.0 };
                assert!((out[row * 8 + col] - 0.6 * v).abs() < 1e-12, "{row} {col}: {}", out[row * 8 + col]);
            }
        }
        // And the union's outline runs round both squares, not along the shared side.
        let region = match &layers[0] {
            ExactLayer::Vibration { region, .. } => region,
            _ => unreachable!(),
        };
        let covers = |p| region.exact.covers(p);
        assert!(covers((50.0, 30.0)) && covers((50.7, 30.0)) && !covers((50.8, 30.0)));
    }

    /// SPEC.md 6.2's edge profile of the exact distance: `½ + d / ramp`
    /// within half a ramp of an edge, saturated beyond, a step for ramp 0;
    /// a side two fills of one style share is no edge.
    /// A sample taken for the widest ramp gives, at every narrower ramp
    /// (the finer rungs of the ladder), the very profile measured afresh:
    /// on points swept across a fill's side, past its corner, and across
    /// a band's edges, at reaches from far wider than the ramp to exactly
    /// half of it.
    #[test]
    fn a_sample_for_a_wide_ramp_gives_every_narrower_ramp_s_profile() {
        let sq = [Polyline { points: vec![(30.0, 20.0), (50.0, 20.0), (50.0, 40.0), (30.0, 40.0)], closed: true }];
        let regions = [fill(&[(&sq, FillRule::NonZero)], &[]), band(vec![&sq], 1.5)];
        let ramps = [2.0, 1.0, 0.5, 0.25, 0.008, 0.0];
        let mut compared = 0;
        for region in &regions {
            for k in 0..=400 {
                // Across the left side (and the band's two edges), and diagonally past the corner.
                let t = -2.0 + 4.0 * k as f64 / 400.0;
                for p in [(30.0 + t, 30.0 + t / 7.0), (30.0 + t, 20.0 + t)] {
                    for (w, &wide) in ramps.iter().enumerate() {
                        let sample = region.edge_sample(p, wide / 2.0);
                        for &ramp in &ramps[w..] {
                            let (kept, fresh) = (sample.profile(ramp), region.edge_profile(p, ramp));
                            assert_eq!(kept.to_bits(), fresh.to_bits(), "{p:?}: ramp {ramp} from {wide}");
                            compared += usize::from(fresh > 0.0 && fresh < 1.0);
                        }
                    }
                }
            }
        }
        // Many of the points are on a ramp, where the distance counts.
        assert!(compared > 500, "{compared}");
    }

    #[test]
    fn edge_profile_ramps_across_the_exact_edge_only() {
        let sq = |x0: f64| Polyline {
            points: vec![(x0, 20.0), (x0 + 20.0, 20.0), (x0 + 20.0, 40.0), (x0, 40.0)],
            closed: true,
        };
        let (a, b) = ([sq(30.0)], [sq(50.0)]);
        let fill = fill(&[(&a, FillRule::NonZero), (&b, FillRule::NonZero)], &[]);
        let ramp = 0.008;
        let near = |got: f64, want: f64| (got - want).abs() < 1e-6;
        // The left side x = 30: 0.002 mm inside and outside, on it, far.
        assert!(near(fill.edge_profile((30.002, 30.0), ramp), 0.75), "{}", fill.edge_profile((30.002, 30.0), ramp));
        assert!(near(fill.edge_profile((29.998, 30.0), ramp), 0.25));
        assert!(near(fill.edge_profile((30.0, 30.0), ramp), 0.5));
        assert!(near(fill.edge_profile((30.01, 30.0), ramp), 1.0) && near(fill.edge_profile((29.99, 30.0), ramp), 0.0));
        // The shared side x = 50 is inside the union.
        assert!(
            near(fill.edge_profile((50.001, 30.0), ramp), 1.0) && near(fill.edge_profile((49.999, 30.0), ramp), 1.0)
        );
        // Outside a corner the distance is to the corner itself.
        let q = (30.0 - 0.002 / 2f64.sqrt(), 20.0 - 0.002 / 2f64.sqrt());
        assert!(near(fill.edge_profile(q, ramp), 0.25), "{}", fill.edge_profile(q, ramp));
        // Ramp 0 is the step of `covers`.
        assert_eq!(fill.edge_profile((30.002, 30.0), 0.0), 1.0);
        assert_eq!(fill.edge_profile((29.998, 30.0), 0.0), 0.0);
        // A 1.5 mm band round the left square: its outer edge at x = 29.25.
        let band = band(vec![&a], 1.5);
        assert!(near(band.edge_profile((29.251, 30.0), ramp), 0.625));
        assert!(near(band.edge_profile((30.749, 30.0), ramp), 0.625));
        assert!(near(band.edge_profile((30.0, 30.0), ramp), 1.0) && near(band.edge_profile((29.2, 30.0), ramp), 0.0));
        // A grating cut by that band: its edge is the band's inner offset.
        let cut = self::fill(&[(&a, FillRule::NonZero)], &[(&a, 1.5)]);
        assert!(near(cut.edge_profile((30.751, 30.0), ramp), 0.625));
        assert!(near(cut.edge_profile((30.0, 30.0), ramp), 0.0));
    }

    #[test]
    fn grating_at_90_degrees_varies_along_x_only() {
        let sq = Polyline { points: vec![(0.0, 0.0), (110.0, 0.0), (110.0, 60.0), (0.0, 60.0)], closed: true };
        let sq = [sq];
        let layers = [ExactLayer::Grating {
            region: fill(&[(&sq, FillRule::NonZero)], &[]),
            wavelength_mm: 2.4,
            angle_deg: 90.0,
            amplitude: 1.0,
            ramp_mm: 0.0,
            sources: Vec::new(),
        }];
        let mut out = [0.0; 64];
        frame(&layers, &stress2(), 0, 50.0, 30.0, &mut out);
        for row in 1..8 {
            for col in 0..8 {
                assert!((out[row * 8 + col] - out[col]).abs() < 1e-9);
            }
        }
        // Column x = 50 + (c − 3.5)·1.2; with λ = 2.4, columns two apart are in
        // phase (up to the profile's f32 pitch, 1.2 + 5e-8 mm).
        assert!((out[0] - out[2]).abs() < 1e-6, "{out:?}");
        let pitch = stress2().pitch_x_mm as f64;
        let want = 0.5 + 0.5 * (std::f64::consts::TAU * (50.0 - 3.5 * pitch) / 2.4).cos();
        assert!((out[0] - want).abs() < 1e-9);
    }

    /// [`Dots::at`], which asks only the dots within the largest radius, is
    /// the sum over every dot: overlapping dots of several radii, points on
    /// and off them, and a dot of radius 0 that counts for nothing.
    #[test]
    fn dots_in_reach_sum_as_every_dot_does() {
        let mut s = 7u64;
        let mut next = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 33) as f64 / (1u64 << 31) as f64
        };
        let dots: Vec<(f64, f64, f64, f64)> = (0..300)
            .map(|k| (next() * 40.0, next() * 20.0, if k == 7 { 0.0 } else { 0.2 + next() * 3.0 }, next()))
            .collect();
        let set = Dots::new(dots.iter().copied());
        let mut felt = 0;
        for _ in 0..2000 {
            let (x, y) = (next() * 44.0 - 2.0, next() * 24.0 - 2.0);
            let every: f64 = dots
                .iter()
                .filter(|d| d.2 > 0.0)
                .map(|&(cx, cy, r, a)| a * dot_profile((x - cx).hypot(y - cy) / r))
                .sum();
            assert!(
                (set.at(x, y) - every).abs() <= 1e-12 * every.max(1.0),
                "({x}, {y}): {} against {every}",
                set.at(x, y)
            );
            felt += usize::from(every > 0.0);
        }
        assert!(felt > 1000, "{felt} points on a dot");
    }

    #[test]
    fn off_surface_actuators_rest() {
        let layers = [ExactLayer::Dots(Dots::new([(0.0, 0.0, 5.0, 1.0)]))];
        let mut out = [9.0; 64];
        frame(&layers, &stress2(), 0, 0.0, 0.0, &mut out);
        // Actuator (0, 0) is at (−4.2, −4.9), off the page.
        assert_eq!(out[0], 0.0);
        // Actuator (4, 4) is at (0.6, 0.7), inside the dot's plateau radius 1.25.
        assert_eq!(out[4 * 8 + 4], 1.0);
    }
}
