//! Textures on paper: a grating becomes lines or dots at spacings a finger
//! tells apart, and grated regions that touch never share a texture.
//!
//! Each distinct grating style (wavelength and angle) gets one texture of
//! [`TEXTURES`], as the same style means the same thing wherever it is
//! used. The styles are coloured over the graph of styles whose regions
//! touch (the automatic sheet's region adjacency,
//! [`crate::auto::adjacency::class_edges`], at the medium's minimum gap), in
//! order of first use: each takes the texture of its own orientation when no
//! touching style has it, else the first free one. A texture is drawn as
//! scanlines through the region at the pattern's angle, cut by the fill rule
//! (exact intersections with the outline, no raster), kept a gap inside an
//! outline the region draws, and cleared around braille.

use taxel_format::PrintParams;

use super::{Level, Mark, MarkShape, TextureId};
use crate::annotation::Style;
use crate::auto::adjacency::{self, Region};
use crate::diagnostic::Diagnostic;
use crate::drawing::{Drawing, PathShape, Shape};
use crate::geometry::{FillRule, Polyline};

/// One texture of the catalogue.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Pattern {
    /// Parallel lines at an angle (degrees, 0 along x, clockwise on paper as
    /// SVG's angles are), `spacing` mm apart.
    Lines { angle_deg: f64, spacing: f64 },
    /// Two sets of lines, at `angle_deg` and 90° more.
    Grid { angle_deg: f64, spacing: f64 },
    /// Dots of `diameter` on a square lattice `spacing` apart; `staggered`
    /// shifts every other row by half a spacing.
    Dots { spacing: f64, diameter: f64, staggered: bool },
}

/// The textures, in the order free ones are taken (spacings chosen: at least
/// the medium's minimum gap between raised lines of a texture, scaled by
/// [`scale`] for a medium whose minimum gap is larger than swell paper's
/// 3 mm; `docs/print.md`).
pub const TEXTURES: [Pattern; 8] = [
    Pattern::Lines { angle_deg: 0.0, spacing: 4.0 },
    Pattern::Lines { angle_deg: 90.0, spacing: 4.0 },
    Pattern::Lines { angle_deg: 45.0, spacing: 4.0 },
    Pattern::Lines { angle_deg: 135.0, spacing: 4.0 },
    Pattern::Dots { spacing: 4.0, diameter: 1.5, staggered: false },
    Pattern::Grid { angle_deg: 0.0, spacing: 6.0 },
    Pattern::Dots { spacing: 6.0, diameter: 2.5, staggered: true },
    Pattern::Grid { angle_deg: 45.0, spacing: 6.0 },
];

/// How much a medium's textures are spaced out beside swell paper's: the
/// ratio of its minimum gap to 3 mm, at least 1.
pub fn scale(p: &PrintParams) -> f64 {
    (p.min_gap_mm as f64 / 3.0).max(1.0)
}

/// The texture of `id` for the medium `p`.
pub fn pattern(p: &PrintParams, id: TextureId) -> Pattern {
    let k = scale(p);
    match TEXTURES[id.0 as usize % TEXTURES.len()] {
        Pattern::Lines { angle_deg, spacing } => Pattern::Lines { angle_deg, spacing: spacing * k },
        Pattern::Grid { angle_deg, spacing } => Pattern::Grid { angle_deg, spacing: spacing * k },
        Pattern::Dots { spacing, diameter, staggered } => {
            Pattern::Dots { spacing: spacing * k, diameter: diameter.max(p.min_line_mm as f64), staggered }
        }
    }
}

/// The line texture nearest a grating's angle (0, 45, 90 or 135°).
fn wanted(angle_deg: f64) -> TextureId {
    let a = if angle_deg.is_finite() { angle_deg.rem_euclid(180.0) } else { 0.0 };
    TextureId([0u8, 2, 1, 3][((a / 45.0).round() as usize) % 4])
}

fn key(wavelength: f64, angle: f64) -> (u64, u64) {
    (wavelength.to_bits(), angle.to_bits())
}

/// The texture of every visible grated path, by element index.
pub fn assign(drawing: &Drawing, p: &PrintParams, diags: &mut Vec<Diagnostic>) -> Vec<(usize, TextureId)> {
    // The grated paths and their styles' classes, in order of first use.
    let mut styles: Vec<((u64, u64), f64)> = Vec::new();
    let mut grated: Vec<(usize, usize, &PathShape)> = Vec::new();
    for (i, e) in drawing.elements.iter().enumerate().filter(|(_, e)| e.visible) {
        let Shape::Path(path) = &e.shape else { continue };
        let Some(g) = e.styles.iter().find_map(|s| if let Style::Grating(g) = s { Some(g) } else { None }) else {
            continue;
        };
        let k = key(g.wavelength_mm, g.angle_deg);
        let class = match styles.iter().position(|(s, _)| *s == k) {
            Some(c) => c,
            None => {
                styles.push((k, g.angle_deg));
                styles.len() - 1
            }
        };
        grated.push((i, class, path));
    }
    if grated.is_empty() {
        return Vec::new();
    }
    let regions: Vec<Region<'_>> = grated
        .iter()
        .filter_map(|(_, _, path)| {
            crate::geometry::bounds(&path.outline).map(|b| Region { outline: &path.outline, bbox: b })
        })
        .collect();
    let classes: Vec<Option<usize>> = grated
        .iter()
        .filter(|(_, _, path)| crate::geometry::bounds(&path.outline).is_some())
        .map(|(_, c, _)| Some(*c))
        .collect();
    let edges = adjacency::class_edges(&regions, &classes, p.min_gap_mm as f64);
    let mut next: Vec<Vec<usize>> = vec![Vec::new(); styles.len()];
    for &(a, b) in &edges {
        if a != b {
            next[a].push(b);
            next[b].push(a);
        }
    }
    let mut chosen: Vec<Option<TextureId>> = vec![None; styles.len()];
    let mut short = 0;
    for c in 0..styles.len() {
        let taken: Vec<TextureId> = next[c].iter().filter_map(|&m| chosen[m]).collect();
        let want = wanted(styles[c].1);
        let all = || std::iter::once(want).chain((0..TEXTURES.len() as u8).map(TextureId));
        let unused = |t: &TextureId| !chosen.contains(&Some(*t));
        let apart = |t: &TextureId| !taken.contains(t);
        // A texture no style has yet, its own orientation first; else one no
        // touching style has; else (every texture touches) its own, said below.
        let got = all().find(unused).or_else(|| all().find(apart));
        if got.is_none() {
            short += 1;
        }
        chosen[c] = Some(got.unwrap_or(want));
    }
    if short > 0 {
        diags.push(
            Diagnostic::warning(
                "T0726",
                format!(
                    "{short} grating style(s) touch regions of every one of the {} paper textures: \
                     they share a texture with a neighbour",
                    TEXTURES.len()
                ),
            )
            .with_help("use fewer grating styles, or leave a gap between the regions"),
        );
    }
    grated.iter().map(|&(i, c, _)| (i, chosen[c].unwrap_or(TextureId(0)))).collect()
}

/// How a region is textured.
pub struct Fill<'a> {
    /// Its texture.
    pub texture: TextureId,
    /// Whether the element also draws its outline (then the texture keeps a gap inside it).
    pub outlined: bool,
    /// Boxes (paper mm) the texture is cleared from: braille labels and the gap around them.
    pub clear: &'a [(f64, f64, f64, f64)],
}

/// The marks of element `elem`'s texture.
pub fn fill(p: &PrintParams, origin: (f64, f64), elem: usize, path: &PathShape, f: Fill<'_>) -> Vec<Mark> {
    let polys: Vec<Polyline> = path
        .outline
        .iter()
        .map(|pl| Polyline {
            points: pl.points.iter().map(|q| (q.0 + origin.0, q.1 + origin.1)).collect(),
            closed: true,
        })
        .collect();
    let line = p.min_line_mm as f64;
    let inset = if f.outlined { p.min_gap_mm as f64 / 2.0 + line } else { line / 2.0 };
    let mut out = Vec::new();
    let mut push = |shape| out.push(Mark { shape, level: Level::Texture, element: Some(elem) });
    match pattern(p, f.texture) {
        Pattern::Lines { angle_deg, spacing } => {
            for s in hatch(&polys, path.fill_rule, angle_deg, spacing, inset, f.clear) {
                push(MarkShape::Line { points: vec![s.0, s.1], closed: false, width_mm: line });
            }
        }
        Pattern::Grid { angle_deg, spacing } => {
            for a in [angle_deg, angle_deg + 90.0] {
                for s in hatch(&polys, path.fill_rule, a, spacing, inset, f.clear) {
                    push(MarkShape::Line { points: vec![s.0, s.1], closed: false, width_mm: line });
                }
            }
        }
        Pattern::Dots { spacing, diameter, staggered } => {
            for c in lattice(&polys, path.fill_rule, spacing, staggered, inset + diameter / 2.0, f.clear) {
                push(MarkShape::Dot { centre: c, diameter_mm: diameter });
            }
        }
    }
    out
}

/// Largest number of texture pieces of one region (a hostile drawing may
/// ask for a texture over a huge area).
const MAX_PIECES: usize = 2_000_000;

/// The spans inside the region along the line `v = y` of the frame rotated
/// by `angle` (`u` along the line), as `(u0, u1)` pairs, trimmed by `inset`.
fn spans(rotated: &[Vec<(f64, f64)>], rule: FillRule, y: f64, inset: f64) -> Vec<(f64, f64)> {
    let mut xs: Vec<(f64, i32)> = Vec::new();
    for ring in rotated {
        let n = ring.len();
        for i in 0..n {
            let (a, b) = (ring[i], ring[(i + 1) % n]);
            if (a.1 <= y) != (b.1 <= y) {
                xs.push((a.0 + (y - a.1) / (b.1 - a.1) * (b.0 - a.0), if b.1 > a.1 { 1 } else { -1 }));
            }
        }
    }
    xs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out = Vec::new();
    let mut winding = 0;
    for k in 0..xs.len().saturating_sub(1) {
        winding += xs[k].1;
        let inside = match rule {
            FillRule::NonZero => winding != 0,
            FillRule::EvenOdd => k % 2 == 0,
        };
        let (u0, u1) = (xs[k].0 + inset, xs[k + 1].0 - inset);
        if inside && u1 > u0 {
            out.push((u0, u1));
        }
    }
    out
}

type Seg = ((f64, f64), (f64, f64));

/// Hatch lines through the region at `angle_deg`, `spacing` apart (phase
/// fixed on the paper, so that a texture continues across regions), less the
/// boxes in `clear`.
fn hatch(
    polys: &[Polyline],
    rule: FillRule,
    angle_deg: f64,
    spacing: f64,
    inset: f64,
    clear: &[(f64, f64, f64, f64)],
) -> Vec<Seg> {
    let (s, c) = angle_deg.to_radians().sin_cos();
    // Rotate by -angle: the hatch lines become horizontal.
    let rot = |p: (f64, f64)| (p.0 * c + p.1 * s, -p.0 * s + p.1 * c);
    let back = |q: (f64, f64)| (q.0 * c - q.1 * s, q.0 * s + q.1 * c);
    let rotated: Vec<Vec<(f64, f64)>> = polys.iter().map(|pl| pl.points.iter().map(|&p| rot(p)).collect()).collect();
    let (lo, hi) = rotated.iter().flatten().fold((f64::MAX, f64::MIN), |a, q| (a.0.min(q.1), a.1.max(q.1)));
    if !(lo.is_finite() && hi.is_finite() && spacing > 0.0) || (hi - lo) / spacing > MAX_PIECES as f64 {
        return Vec::new();
    }
    let mut out = Vec::new();
    let mut k = (lo / spacing).ceil();
    while k * spacing <= hi && out.len() < MAX_PIECES {
        let y = k * spacing;
        // Kept `inset` from the outline across the line too: where the spans
        // `inset` above and below hold it (a line along a side is none).
        let held = intersect(
            &intersect(&spans(&rotated, rule, y, inset), &spans(&rotated, rule, y - inset, inset)),
            &spans(&rotated, rule, y + inset, inset),
        );
        for (u0, u1) in held {
            for (a, b) in less_boxes(back((u0, y)), back((u1, y)), clear) {
                if (b.0 - a.0).hypot(b.1 - a.1) > spacing / 4.0 {
                    out.push((a, b));
                }
            }
        }
        k += 1.0;
    }
    out
}

/// The intersection of two sorted lists of disjoint spans.
fn intersect(a: &[(f64, f64)], b: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let (mut i, mut j, mut out) = (0, 0, Vec::new());
    while i < a.len() && j < b.len() {
        let (lo, hi) = (a[i].0.max(b[j].0), a[i].1.min(b[j].1));
        if hi > lo {
            out.push((lo, hi));
        }
        if a[i].1 < b[j].1 { i += 1 } else { j += 1 }
    }
    out
}

/// Dot centres on the lattice inside the region, `inset` from its outline.
fn lattice(
    polys: &[Polyline],
    rule: FillRule,
    spacing: f64,
    staggered: bool,
    inset: f64,
    clear: &[(f64, f64, f64, f64)],
) -> Vec<(f64, f64)> {
    let rings: Vec<Vec<(f64, f64)>> = polys.iter().map(|pl| pl.points.clone()).collect();
    let (lo, hi) = rings.iter().flatten().fold((f64::MAX, f64::MIN), |a, q| (a.0.min(q.1), a.1.max(q.1)));
    if !(lo.is_finite() && hi.is_finite() && spacing > 0.0) || (hi - lo) / spacing > MAX_PIECES as f64 {
        return Vec::new();
    }
    let mut out = Vec::new();
    let mut k = (lo / spacing).ceil();
    while k * spacing <= hi && out.len() < MAX_PIECES {
        let y = k * spacing;
        let shift = if staggered && (k as i64).rem_euclid(2) == 1 { spacing / 2.0 } else { 0.0 };
        // Away from the outline across the rows too: the spans a dot's radius above and below.
        let rows = [
            spans(&rings, rule, y - inset, inset),
            spans(&rings, rule, y, inset),
            spans(&rings, rule, y + inset, inset),
        ];
        for &(u0, u1) in &rows[1] {
            let mut m = ((u0 - shift) / spacing).ceil();
            while m * spacing + shift <= u1 && out.len() < MAX_PIECES {
                let x = m * spacing + shift;
                let held = rows[0].iter().any(|s| s.0 <= x && x <= s.1) && rows[2].iter().any(|s| s.0 <= x && x <= s.1);
                let cleared = clear.iter().any(|b| x >= b.0 && x <= b.2 && y >= b.1 && y <= b.3);
                if held && !cleared {
                    out.push((x, y));
                }
                m += 1.0;
            }
        }
        k += 1.0;
    }
    out
}

/// The parts of segment `a`-`b` outside every box (Liang-Barsky clipping).
fn less_boxes(a: (f64, f64), b: (f64, f64), boxes: &[(f64, f64, f64, f64)]) -> Vec<Seg> {
    let mut parts = vec![(0.0f64, 1.0f64)];
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    for bx in boxes {
        // The parameter interval of the segment inside the box.
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        let mut hit = true;
        for (p, q) in [(-dx, a.0 - bx.0), (dx, bx.2 - a.0), (-dy, a.1 - bx.1), (dy, bx.3 - a.1)] {
            if p == 0.0 {
                if q < 0.0 {
                    hit = false;
                    break;
                }
            } else {
                let r = q / p;
                if p < 0.0 {
                    t0 = t0.max(r);
                } else {
                    t1 = t1.min(r);
                }
            }
        }
        if !hit || t0 >= t1 {
            continue;
        }
        parts = parts
            .into_iter()
            .flat_map(|(s, e)| {
                let mut v = Vec::new();
                if t0 > s {
                    v.push((s, t0.min(e)));
                }
                if t1 < e {
                    v.push((t1.max(s), e));
                }
                v.into_iter().filter(|(s, e)| e > s)
            })
            .collect();
    }
    parts.into_iter().map(|(s, e)| ((a.0 + s * dx, a.1 + s * dy), (a.0 + e * dx, a.1 + e * dy))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x: f64, y: f64, s: f64) -> Vec<Polyline> {
        vec![Polyline { points: vec![(x, y), (x + s, y), (x + s, y + s), (x, y + s)], closed: true }]
    }

    #[test]
    fn horizontal_hatch_of_a_square_is_lines_a_spacing_apart() {
        let segs = hatch(&square(0.0, 0.0, 20.0), FillRule::NonZero, 0.0, 4.0, 1.0, &[]);
        // y = 4, 8, 12, 16 (0 and 20 lie on the edges: a crossing counted once, then none).
        let ys: Vec<f64> = segs.iter().map(|s| s.0.1).collect();
        assert_eq!(ys.len(), 4, "{segs:?}");
        for s in &segs {
            assert!((s.0.0 - 1.0).abs() < 1e-9 && (s.1.0 - 19.0).abs() < 1e-9, "{s:?}");
        }
    }

    #[test]
    fn a_hatch_is_cleared_from_a_box() {
        let segs = hatch(&square(0.0, 0.0, 20.0), FillRule::NonZero, 0.0, 4.0, 0.5, &[(5.0, 6.0, 15.0, 10.0)]);
        // y = 8 is cut in two around the box; the others are whole.
        assert_eq!(segs.len(), 5, "{segs:?}");
        assert!(segs.iter().all(|s| s.0.1 != 8.0 || s.1.0 <= 5.0 + 1e-9 || s.0.0 >= 15.0 - 1e-9));
    }

    #[test]
    fn a_diagonal_hatch_stays_inside() {
        let segs = hatch(&square(0.0, 0.0, 20.0), FillRule::NonZero, 45.0, 4.0, 0.5, &[]);
        assert!(!segs.is_empty());
        for (a, b) in segs {
            for p in [a, b] {
                assert!((-1e-9..=20.0 + 1e-9).contains(&p.0) && (-1e-9..=20.0 + 1e-9).contains(&p.1), "{p:?}");
            }
        }
    }

    #[test]
    fn lattice_dots_keep_their_inset() {
        let dots = lattice(&square(0.0, 0.0, 20.0), FillRule::NonZero, 4.0, false, 2.0, &[]);
        assert_eq!(dots.len(), 16, "{dots:?}");
        assert!(dots.iter().all(|d| d.0 >= 2.0 && d.0 <= 18.0 && d.1 >= 2.0 && d.1 <= 18.0));
    }

    #[test]
    fn a_grating_keeps_its_orientation_where_free() {
        assert_eq!(wanted(0.0), TextureId(0));
        assert_eq!(wanted(90.0), TextureId(1));
        assert_eq!(wanted(45.0), TextureId(2));
        assert_eq!(wanted(135.0), TextureId(3));
        assert_eq!(wanted(-45.0), TextureId(3));
        assert_eq!(wanted(f64::NAN), TextureId(0));
    }
}
