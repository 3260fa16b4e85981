//! The exact reference for laterotactile scenes: the seed-000 equations
//! evaluated in f64 with exact geometry, at every actuator of a frame.
//!
//! A raster mask is an approximation of a region; here the region is the
//! shape itself (a polygon fill, or the band within `width / 2` of the
//! outline), tested point by point on the flattened f64 outline. Dots are
//! already exact (centre and radius), so they enter through eq. 1 in f64.
//! The reference is what the runtime *should* output before its last rounding
//! to 10 bits; errors are reported in steps of that output.

use std::sync::Arc;

use taxel_compiler::geometry::{FillRule, Polyline, distance_to_segment};
use taxel_format::DeviceProfile;

/// Plateau of eq. 1 (seed 000, section 3.1), written here again so that the
/// reference does not borrow the runtime's constant.
const PLATEAU: f64 = 0.25;

/// Where a layer is on: a region of the page in exact geometry. A distance
/// layer holds every shape of one style (SPEC.md section 6.2), so its region
/// is the union of its sources' regions: touching borders of one style are
/// one border, and do not add up.
#[derive(Debug, Clone)]
pub enum Region {
    /// The union of the insides of closed outlines, minus the vibrating
    /// bands that cross it (the compiler keeps gratings out from under
    /// vibrating borders, so that a tactile icon's or a map region's two
    /// layers do not overlap) and minus the opaque fills painted over the
    /// sources (a lake drawn on the land hides the land's grating there) and
    /// the clearings round braille: the layer's plan says which.
    Fill {
        /// Each source's outline and SVG fill rule.
        fills: Vec<(Index, FillRule)>,
        /// The layer's clip regions (outline and fill rule): it is felt only
        /// inside all of them, as the compiler clips it (a nested `<svg>`'s
        /// viewport, `clip-path`).
        clips: Vec<(Index, FillRule)>,
        /// Vibrating bands (outline, width in mm) that are left out.
        minus_bands: Vec<(Arc<Index>, f64)>,
        /// Occluders (outline and fill rule), left out: the opaque fills
        /// painted over the sources and the braille clearings that meet them.
        minus_fills: Vec<(Index, FillRule)>,
        /// The corners of the outlines and of the cut bands' centre lines (see [`corners`]).
        corners: Vec<(f64, f64)>,
    },
    /// The union of bands of a width (mm) centred on outlines, round joins and caps.
    Band {
        /// Each source's outline and band width.
        bands: Vec<(Arc<Index>, f64)>,
        /// The layer's clip regions (as a fill's).
        clips: Vec<(Index, FillRule)>,
        /// The corners of the centre lines (see [`corners`]).
        corners: Vec<(f64, f64)>,
    },
}

impl Region {
    /// Exact coverage (0 or 1) at page point `p` in mm.
    pub fn covers(&self, p: (f64, f64)) -> bool {
        match self {
            Region::Fill { fills, clips, minus_bands, minus_fills, .. } => {
                fills.iter().any(|(f, rule)| f.contains(p, *rule))
                    && clips.iter().all(|(c, r)| c.contains(p, *r))
                    && !minus_bands.iter().any(|(b, w)| b.within(p, w / 2.0))
                    && !minus_fills.iter().any(|(f, rule)| f.contains(p, *rule))
            }
            Region::Band { bands, clips, .. } => {
                bands.iter().any(|(b, w)| b.within(p, w / 2.0)) && clips.iter().all(|(c, r)| c.contains(p, *r))
            }
        }
    }

    /// Whether an edge of the region may pass within `r` of `p`: a fill's
    /// outline within `r`, or a band's centre line within `r` plus its half
    /// width. Where not, the coverage is the same over the whole disc of
    /// radius `r` round `p` (it changes only across those lines); a cheap
    /// index query, so that callers test the coverage round `p` only where
    /// it may change.
    pub fn edge_may_pass_within(&self, p: (f64, f64), r: f64) -> bool {
        let band_near = |(b, w): &(Arc<Index>, f64)| b.within(p, r + w / 2.0);
        match self {
            Region::Fill { fills, clips, minus_bands, minus_fills, .. } => {
                fills.iter().chain(minus_fills).chain(clips.iter()).any(|(f, _)| f.within(p, r))
                    || minus_bands.iter().any(band_near)
            }
            Region::Band { bands, clips, .. } => {
                bands.iter().any(band_near) || clips.iter().any(|(f, _)| f.within(p, r))
            }
        }
    }

    /// The exact edge profile at page point `p` for a layer whose edge ramp
    /// is `ramp` mm wide: SPEC.md section 6.2's `clamp(½ + d / ramp, 0, 1)` of
    /// the exact signed distance `d` (positive where the region is felt).
    /// A ramp of 0 is the ideal step: 1 where the region covers `p`, else 0.
    pub fn edge_profile(&self, p: (f64, f64), ramp: f64) -> f64 {
        let here = self.covers(p);
        if ramp > 0.0
            && let Some(d) = self.distance_to_edge_within(p, ramp / 2.0)
        {
            let d = if here { d } else { -d };
            return (0.5 + d / ramp).clamp(0.0, 1.0);
        }
        if here { 1.0 } else { 0.0 }
    }

    /// The exact distance from `p` to the region's edge when it is less than
    /// `reach` mm, else `None`. Candidates are the nearest points of every
    /// outline segment (a fill's side, or the offset of a band's centre line
    /// at `width / 2`) within reach; a candidate is on the edge when the
    /// region's coverage differs on its two sides (so a side two fills of one
    /// style share, or a band's end inside another band, is not an edge).
    pub fn distance_to_edge_within(&self, p: (f64, f64), reach: f64) -> Option<f64> {
        if reach.is_nan() || reach <= 0.0 {
            return None;
        }
        let mut best = f64::INFINITY;
        let mut consider = |q: (f64, f64), across: (f64, f64)| {
            let d = (p.0 - q.0).hypot(p.1 - q.1);
            if d >= reach || d >= best {
                return;
            }
            // Across the edge: away from `p` where `p` is off it, else the side's normal.
            let u = if d > ON_EDGE_MM { ((p.0 - q.0) / d, (p.1 - q.1) / d) } else { across };
            let s = ON_EDGE_MM;
            if self.covers((q.0 + s * u.0, q.1 + s * u.1)) != self.covers((q.0 - s * u.0, q.1 - s * u.1)) {
                best = d;
            }
        };
        // A band's edge nearest `p` along each centre-line segment: `width / 2`
        // from the segment's point nearest `p`, on the side of `p`.
        let band = |b: &Index, w: f64, consider: &mut dyn FnMut((f64, f64), (f64, f64))| {
            let r = w / 2.0;
            b.near(p, reach + r, |a, c| {
                let m = nearest_on_segment(p, a, c);
                let l = (p.0 - m.0).hypot(p.1 - m.1);
                if l > ON_EDGE_MM {
                    let u = ((p.0 - m.0) / l, (p.1 - m.1) / l);
                    consider((m.0 + u.0 * r, m.1 + u.1 * r), u);
                } else {
                    // `p` on the centre line: the edge is `r` away on either side.
                    let n = unit(a.1 - c.1, c.0 - a.0);
                    consider((m.0 + n.0 * r, m.1 + n.1 * r), n);
                    consider((m.0 - n.0 * r, m.1 - n.1 * r), (-n.0, -n.1));
                }
                false
            });
        };
        match self {
            Region::Fill { fills, clips, minus_bands, minus_fills, .. } => {
                for (f, _) in fills.iter().chain(minus_fills).chain(clips.iter()) {
                    f.near(p, reach, |a, c| {
                        consider(nearest_on_segment(p, a, c), unit(a.1 - c.1, c.0 - a.0));
                        false
                    });
                }
                for (b, w) in minus_bands {
                    band(b, *w, &mut consider);
                }
            }
            Region::Band { bands, clips, .. } => {
                for (b, w) in bands {
                    band(b, *w, &mut consider);
                }
                for (f, _) in clips.iter() {
                    f.near(p, reach, |a, c| {
                        consider(nearest_on_segment(p, a, c), unit(a.1 - c.1, c.0 - a.0));
                        false
                    });
                }
            }
        }
        best.is_finite().then_some(best)
    }

    /// The corners of the region's outlines, page mm.
    pub fn corners(&self) -> &[(f64, f64)] {
        match self {
            Region::Fill { corners, .. } | Region::Band { corners, .. } => corners,
        }
    }

    /// Segments on which every point of the region's boundary lies (a
    /// superset of it): the fills' outlines, and each band's two offset
    /// lines and the circles round its vertices (polygons of chords within
    /// `sagitta` mm of the circle).
    pub fn candidate_edges(&self, sagitta: f64) -> Vec<Seg> {
        let mut out = Vec::new();
        let band = |idx: &Index, w: f64, out: &mut Vec<Seg>| {
            let r = w / 2.0;
            for &(a, b) in &idx.segs {
                let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                let len = dx.hypot(dy);
                if len > 0.0 {
                    let (nx, ny) = (-dy / len * r, dx / len * r);
                    out.push(((a.0 + nx, a.1 + ny), (b.0 + nx, b.1 + ny)));
                    out.push(((a.0 - nx, a.1 - ny), (b.0 - nx, b.1 - ny)));
                }
                for c in [a, b] {
                    circle(c, r, sagitta, out);
                }
            }
        };
        match self {
            Region::Fill { fills, clips, minus_bands, minus_fills, .. } => {
                for (f, _) in fills.iter().chain(minus_fills).chain(clips.iter()) {
                    out.extend_from_slice(&f.segs);
                }
                for (b, w) in minus_bands {
                    band(b, *w, &mut out);
                }
            }
            Region::Band { bands, clips, .. } => {
                for (b, w) in bands {
                    band(b, *w, &mut out);
                }
                for (f, _) in clips.iter() {
                    out.extend_from_slice(&f.segs);
                }
            }
        }
        out
    }
}

/// A segment in page mm.
pub type Seg = ((f64, f64), (f64, f64));

/// The circle of radius `r` round `c` as a polygon of chords that stay within `sagitta` of it.
fn circle(c: (f64, f64), r: f64, sagitta: f64, out: &mut Vec<Seg>) {
    if !(r.is_finite() && r > 0.0) {
        return;
    }
    // Sagitta of a chord over the angle 2π/n: r (1 − cos(π/n)) ≈ r π² / (2 n²).
    let n = (std::f64::consts::PI * (r / (2.0 * sagitta.max(1e-9))).sqrt()).ceil().clamp(16.0, 4096.0) as usize;
    let at = |k: usize| {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        (c.0 + r * a.cos(), c.1 + r * a.sin())
    };
    for k in 0..n {
        out.push((at(k), at(k + 1)));
    }
}

/// How close to an exact edge a point counts as on it, in mm, and the step
/// across an edge that tells its two sides apart: far below any position a
/// player is given (an f32 at 100 mm resolves 7.6e-6 mm).
pub const ON_EDGE_MM: f64 = 1e-7;

/// The point of segment `a`–`b` nearest `p`.
fn nearest_on_segment(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    if len2.is_nan() || len2 <= 0.0 {
        return a;
    }
    let t = (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0);
    (a.0 + t * dx, a.1 + t * dy)
}

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
        region: Region,
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
        region: Region,
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
    /// Eq. 1 for each dot `(x, y, radius, amplitude)` in mm.
    Dots(Vec<(f64, f64, f64, f64)>),
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
pub fn frame(layers: &[ExactLayer], profile: &DeviceProfile, tick: u64, x: f64, y: f64, out: &mut [f64]) {
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
            for layer in layers {
                d += match layer {
                    ExactLayer::Vibration { region, freq_hz, amplitude, ramp_mm, .. } => {
                        let edge = region.edge_profile((ax, ay), *ramp_mm);
                        if edge == 0.0 {
                            continue;
                        }
                        let c = (std::f64::consts::TAU * freq_hz * t_s).cos();
                        let v = if row % 2 != col % 2 { 0.5 + 0.5 * c } else { 0.5 - 0.5 * c };
                        amplitude * edge * v
                    }
                    ExactLayer::Grating { region, wavelength_mm, angle_deg, amplitude, ramp_mm, .. } => {
                        let edge = region.edge_profile((ax, ay), *ramp_mm);
                        if edge == 0.0 {
                            continue;
                        }
                        // Eq. 3 with the page's y axis flipped (primitives.md): the
                        // author's angle is counter-clockwise as seen on the page.
                        let th = angle_deg.to_radians();
                        let dist = (-ay) * th.cos() - ax * th.sin();
                        amplitude * edge * (0.5 + 0.5 * (std::f64::consts::TAU * dist / wavelength_mm).cos())
                    }
                    ExactLayer::Dots(dots) => dots
                        .iter()
                        .filter(|&&(_, _, r, _)| r > 0.0)
                        .map(|&(cx, cy, r, a)| a * dot_profile((ax - cx).hypot(ay - cy) / r))
                        .sum(),
                };
            }
            *o = if d.is_nan() { 0.0 } else { d.clamp(0.0, 1.0) };
        }
    }
}

/// Flattened outlines with a coarse bucket index, so that a point query only
/// looks at the segments near it. Answers are those of
/// `taxel_compiler::geometry::{contains, distance_to_outline}` (tested).
#[derive(Debug, Clone)]
pub struct Index {
    segs: Vec<((f64, f64), (f64, f64))>,
    x0: f64,
    y0: f64,
    cell: f64,
    cols: usize,
    rows: usize,
    /// Segment indices per cell (a segment is listed in every cell its box touches).
    cells: Vec<Vec<u32>>,
    /// Segment indices per row of cells, for the crossing test of fills.
    bands: Vec<Vec<u32>>,
}

impl Index {
    /// Indexes `polys` (each closed implicitly for fills; open ones keep their ends for bands).
    pub fn new(polys: &[Polyline], closed_fill: bool) -> Self {
        let mut segs = Vec::new();
        for pl in polys {
            let n = pl.points.len();
            if n == 1 {
                segs.push((pl.points[0], pl.points[0]));
            }
            // Fills close every subpath (as `geometry::contains` does); bands close only `Z` subpaths.
            let closing = if closed_fill { n >= 2 } else { pl.closed && n > 2 };
            for i in 0..n.saturating_sub(1) + usize::from(closing) {
                segs.push((pl.points[i], pl.points[(i + 1) % n]));
            }
        }
        segs.retain(|(a, b)| a.0.is_finite() && a.1.is_finite() && b.0.is_finite() && b.1.is_finite());
        let (mut x0, mut y0, mut x1, mut y1) = (f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
        for &(a, b) in &segs {
            x0 = x0.min(a.0).min(b.0);
            y0 = y0.min(a.1).min(b.1);
            x1 = x1.max(a.0).max(b.0);
            y1 = y1.max(a.1).max(b.1);
        }
        if segs.is_empty() {
            return Index { segs, x0: 0.0, y0: 0.0, cell: 1.0, cols: 0, rows: 0, cells: Vec::new(), bands: Vec::new() };
        }
        // About 64 cells along the longer side, never more than 4096 cells.
        let span = (x1 - x0).max(y1 - y0).max(1e-9);
        let cell = span / 64.0;
        let cols = (((x1 - x0) / cell).floor() as usize + 1).min(64);
        let rows = (((y1 - y0) / cell).floor() as usize + 1).min(64);
        let mut idx = Index {
            segs,
            x0,
            y0,
            cell,
            cols,
            rows,
            cells: vec![Vec::new(); cols * rows],
            bands: vec![Vec::new(); rows],
        };
        for (k, &(a, b)) in idx.segs.iter().enumerate() {
            let (c0, c1) = (idx.col(a.0.min(b.0)), idx.col(a.0.max(b.0)));
            let (r0, r1) = (idx.row(a.1.min(b.1)), idx.row(a.1.max(b.1)));
            for r in r0..=r1 {
                idx.bands[r].push(k as u32);
                for c in c0..=c1 {
                    idx.cells[r * idx.cols + c].push(k as u32);
                }
            }
        }
        idx
    }

    fn col(&self, x: f64) -> usize {
        (((x - self.x0) / self.cell).floor().max(0.0) as usize).min(self.cols.saturating_sub(1))
    }

    fn row(&self, y: f64) -> usize {
        (((y - self.y0) / self.cell).floor().max(0.0) as usize).min(self.rows.saturating_sub(1))
    }

    /// Whether `p` is inside (the crossing rule of `geometry::contains`).
    pub fn contains(&self, p: (f64, f64), rule: FillRule) -> bool {
        if self.rows == 0 || p.1 < self.y0 || p.1 > self.y0 + self.cell * self.rows as f64 {
            return false;
        }
        let (mut winding, mut crossings) = (0i32, 0u32);
        for &k in &self.bands[self.row(p.1)] {
            let (a, b) = self.segs[k as usize];
            if (a.1 <= p.1) != (b.1 <= p.1) {
                let x = a.0 + (p.1 - a.1) / (b.1 - a.1) * (b.0 - a.0);
                if x > p.0 {
                    crossings += 1;
                    winding += if b.1 > a.1 { 1 } else { -1 };
                }
            }
        }
        match rule {
            FillRule::NonZero => winding != 0,
            FillRule::EvenOdd => crossings % 2 == 1,
        }
    }

    /// Calls `f` with the ends of every segment listed in a cell within `r`
    /// mm of `p` (a segment may come more than once, and some may be farther
    /// than `r`) until `f` returns true; returns whether it did.
    pub fn near(&self, p: (f64, f64), r: f64, mut f: impl FnMut((f64, f64), (f64, f64)) -> bool) -> bool {
        if self.rows == 0 || r.is_nan() || r < 0.0 {
            return false;
        }
        let (lo_x, hi_x) = (p.0 - r, p.0 + r);
        let (lo_y, hi_y) = (p.1 - r, p.1 + r);
        if hi_x < self.x0
            || hi_y < self.y0
            || lo_x > self.x0 + self.cell * self.cols as f64
            || lo_y > self.y0 + self.cell * self.rows as f64
        {
            return false;
        }
        for row in self.row(lo_y)..=self.row(hi_y) {
            for col in self.col(lo_x)..=self.col(hi_x) {
                for &k in &self.cells[row * self.cols + col] {
                    let (a, b) = self.segs[k as usize];
                    if f(a, b) {
                        return true;
                    }
                }
            }
        }
        false
    }

    /// Whether `p` is within `r` mm of a segment.
    pub fn within(&self, p: (f64, f64), r: f64) -> bool {
        self.near(p, r, |a, b| distance_to_segment(p, a, b) <= r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use taxel_compiler::geometry::{contains, distance_to_outline};

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
        let layers = [ExactLayer::Vibration {
            region: Region::Fill {
                fills: vec![(Index::new(&[sq], true), FillRule::NonZero)],
                clips: Vec::new(),
                minus_bands: Vec::new(),
                minus_fills: vec![],
                corners: Vec::new(),
            },
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
        let band = |x0: f64| (Arc::new(Index::new(&[sq(x0)], false)), 1.5);
        let layers = [ExactLayer::Vibration {
            region: Region::Band { bands: vec![band(30.0), band(50.0)], clips: Vec::new(), corners: Vec::new() },
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
        assert!(region.covers((50.0, 30.0)) && region.covers((50.7, 30.0)) && !region.covers((50.8, 30.0)));
    }

    /// SPEC.md 6.2's edge profile of the exact distance: `½ + d / ramp`
    /// within half a ramp of an edge, saturated beyond, a step for ramp 0;
    /// a side two fills of one style share is no edge.
    #[test]
    fn edge_profile_ramps_across_the_exact_edge_only() {
        let sq = |x0: f64| Polyline {
            points: vec![(x0, 20.0), (x0 + 20.0, 20.0), (x0 + 20.0, 40.0), (x0, 40.0)],
            closed: true,
        };
        let fill = Region::Fill {
            fills: vec![
                (Index::new(&[sq(30.0)], true), FillRule::NonZero),
                (Index::new(&[sq(50.0)], true), FillRule::NonZero),
            ],
            clips: Vec::new(),
            minus_bands: Vec::new(),
            minus_fills: vec![],
            corners: Vec::new(),
        };
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
        let band = Region::Band {
            bands: vec![(Arc::new(Index::new(&[sq(30.0)], false)), 1.5)],
            clips: Vec::new(),
            corners: Vec::new(),
        };
        assert!(near(band.edge_profile((29.251, 30.0), ramp), 0.625));
        assert!(near(band.edge_profile((30.749, 30.0), ramp), 0.625));
        assert!(near(band.edge_profile((30.0, 30.0), ramp), 1.0) && near(band.edge_profile((29.2, 30.0), ramp), 0.0));
        // A grating cut by that band: its edge is the band's inner offset.
        let cut = Region::Fill {
            fills: vec![(Index::new(&[sq(30.0)], true), FillRule::NonZero)],
            clips: Vec::new(),
            minus_bands: vec![(Arc::new(Index::new(&[sq(30.0)], false)), 1.5)],
            minus_fills: vec![],
            corners: Vec::new(),
        };
        assert!(near(cut.edge_profile((30.751, 30.0), ramp), 0.625));
        assert!(near(cut.edge_profile((30.0, 30.0), ramp), 0.0));
    }

    #[test]
    fn grating_at_90_degrees_varies_along_x_only() {
        let sq = Polyline { points: vec![(0.0, 0.0), (110.0, 0.0), (110.0, 60.0), (0.0, 60.0)], closed: true };
        let layers = [ExactLayer::Grating {
            region: Region::Fill {
                fills: vec![(Index::new(&[sq], true), FillRule::NonZero)],
                clips: Vec::new(),
                minus_bands: Vec::new(),
                minus_fills: vec![],
                corners: Vec::new(),
            },
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

    #[test]
    fn off_surface_actuators_rest() {
        let layers = [ExactLayer::Dots(vec![(0.0, 0.0, 5.0, 1.0)])];
        let mut out = [9.0; 64];
        frame(&layers, &stress2(), 0, 0.0, 0.0, &mut out);
        // Actuator (0, 0) is at (−4.2, −4.9), off the page.
        assert_eq!(out[0], 0.0);
        // Actuator (4, 4) is at (0.6, 0.7), inside the dot's plateau radius 1.25.
        assert_eq!(out[4 * 8 + 4], 1.0);
    }

    fn poly() -> impl Strategy<Value = Polyline> {
        (prop::collection::vec((-20.0f64..20.0, -20.0f64..20.0), 1..12), any::<bool>())
            .prop_map(|(points, closed)| Polyline { points, closed })
    }

    proptest! {
        #[test]
        fn index_agrees_with_the_compilers_geometry(
            polys in prop::collection::vec(poly(), 1..4),
            p in (-25.0f64..25.0, -25.0f64..25.0),
            r in 0.0f64..6.0,
        ) {
            let idx = Index::new(&polys, true);
            // The compiler's `contains` closes every subpath implicitly, as fills do.
            for rule in [FillRule::NonZero, FillRule::EvenOdd] {
                prop_assert_eq!(idx.contains(p, rule), contains(&polys, p, rule));
            }
            let band = Index::new(&polys, false);
            let d = distance_to_outline(&polys, p);
            // Single points are no segment to the compiler; skip those scenes for distance.
            if polys.iter().all(|pl| pl.points.len() >= 2) && (d - r).abs() > 1e-9 {
                prop_assert_eq!(band.within(p, r), d <= r);
            }
        }
    }
}
