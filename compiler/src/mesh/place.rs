//! Placing a model on the page: `--region` keeps part of its footprint,
//! `--fit` scales and centres it onto the device's surface, `--exaggerate`
//! multiplies its heights.
//!
//! A region cuts every triangle at the rectangle's sides (Sutherland–Hodgman;
//! the height along a cut is the triangle's own plane, so the surface inside
//! is unchanged). Fitting scales page x, y and the heights by the same factor,
//! so slopes are the model's own, and puts the lowest point at height 0: the
//! runtime's intensity is proportional to height, and a terrain between 1000
//! and 1500 m above the sea would otherwise play at 67 to 100 % everywhere.

use super::error::MeshError;
use super::load::Soup;
use super::{MeshOptions, Region};
use crate::diagnostic::number;

/// Applies `opts.region`, `opts.fit` and `opts.exaggerate` to `soup` in
/// place. Returns the page millimetres per model metre (1000 without `--fit`).
pub fn place(soup: &mut Soup, opts: &MeshOptions) -> Result<f64, MeshError> {
    if !(opts.exaggerate.is_finite() && opts.exaggerate > 0.0) {
        return Err(MeshError::BadExaggeration(opts.exaggerate));
    }
    let frame = match &opts.region {
        None => None,
        Some(region) => {
            let rect = region_rect(soup, region)?;
            clip(soup, rect);
            if soup.triangles.is_empty() {
                let f = footprint(soup_all(soup)).map(|b| b.map(|v| v / 1000.0));
                return Err(MeshError::Region(format!(
                    "{} keeps nothing of the model{}",
                    describe(region),
                    f.map(|b| format!(
                        ", whose footprint is x {}..{}, y {}..{} (model units)",
                        number(b[0], 3),
                        number(b[2], 3),
                        number(b[1], 3),
                        number(b[3], 3)
                    ))
                    .unwrap_or_default()
                )));
            }
            Some(rect)
        }
    };
    let Some([w, h]) = opts.fit else {
        if opts.exaggerate != 1.0 {
            for v in &mut soup.vertices {
                v[2] *= opts.exaggerate;
            }
        }
        return Ok(1000.0);
    };
    let used = used_vertices(soup);
    let Some(foot) = frame.or_else(|| footprint(used.iter().filter_map(|&i| soup.vertices.get(i)).copied())) else {
        return Ok(1000.0);
    };
    let (fw, fh) = (foot[2] - foot[0], foot[3] - foot[1]);
    // A footprint with no width or depth cannot be fitted; the surface stage
    // refuses it (nothing covers the page), so leave it as it is.
    let s = (w / fw).min(h / fh);
    if !(s.is_finite() && s > 0.0) {
        return Ok(1000.0);
    }
    let (cx, cy) = ((foot[0] + foot[2]) / 2.0, (foot[1] + foot[3]) / 2.0);
    let base = used.iter().filter_map(|&i| soup.vertices.get(i)).map(|v| v[2]).fold(f64::INFINITY, f64::min);
    for v in &mut soup.vertices {
        *v = [(v[0] - cx) * s + w / 2.0, (v[1] - cy) * s + h / 2.0, (v[2] - base) * s * opts.exaggerate];
    }
    for p in &mut soup.parts {
        p.bbox = [
            (p.bbox[0] - cx) * s + w / 2.0,
            (p.bbox[1] - cy) * s + h / 2.0,
            (p.bbox[2] - cx) * s + w / 2.0,
            (p.bbox[3] - cy) * s + h / 2.0,
        ];
    }
    Ok(1000.0 * s)
}

fn describe(region: &Region) -> String {
    match region {
        Region::Rect { x, y, w, h } => format!("the rectangle {x},{y},{w},{h}"),
        Region::Element(name) => format!("#{name}"),
    }
}

/// The region as `[xmin, ymin, xmax, ymax]` in page mm.
fn region_rect(soup: &Soup, region: &Region) -> Result<[f64; 4], MeshError> {
    match region {
        Region::Rect { x, y, w, h } => {
            let r = [x * 1000.0, y * 1000.0, (x + w) * 1000.0, (y + h) * 1000.0];
            if r.iter().all(|v| v.is_finite()) {
                Ok(r)
            } else {
                Err(MeshError::Region(format!("{} is too large to be a part of a model", describe(region))))
            }
        }
        Region::Element(name) => {
            let hits: Vec<[f64; 4]> =
                soup.parts.iter().filter(|p| p.node == *name || p.mesh == *name).map(|p| p.bbox).collect();
            if hits.is_empty() {
                let mut names: Vec<&str> = soup
                    .parts
                    .iter()
                    .flat_map(|p| [p.node.as_str(), p.mesh.as_str()])
                    .filter(|n| !n.is_empty())
                    .collect();
                names.sort_unstable();
                names.dedup();
                let shown = names.iter().take(12).map(|n| format!("#{n}")).collect::<Vec<_>>().join(", ");
                let more = if names.len() > 12 { format!(" and {} more", names.len() - 12) } else { String::new() };
                return Err(MeshError::Region(if names.is_empty() {
                    format!("no node or mesh is named '{name}' (the file names none)")
                } else {
                    format!("no node or mesh is named '{name}'; the file has {shown}{more}")
                }));
            }
            let b = hits.iter().fold([f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY], |a, b| {
                [a[0].min(b[0]), a[1].min(b[1]), a[2].max(b[2]), a[3].max(b[3])]
            });
            Ok(b)
        }
    }
}

fn soup_all(soup: &Soup) -> impl Iterator<Item = [f64; 3]> + '_ {
    soup.vertices.iter().copied()
}

/// Indices of the vertices the triangles use.
fn used_vertices(soup: &Soup) -> Vec<usize> {
    let mut used = vec![false; soup.vertices.len()];
    for t in &soup.triangles {
        for &i in t {
            if let Some(u) = used.get_mut(i as usize) {
                *u = true;
            }
        }
    }
    used.iter().enumerate().filter(|(_, u)| **u).map(|(i, _)| i).collect()
}

fn footprint(points: impl Iterator<Item = [f64; 3]>) -> Option<[f64; 4]> {
    let mut b = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
    for v in points {
        b = [b[0].min(v[0]), b[1].min(v[1]), b[2].max(v[0]), b[3].max(v[1])];
    }
    b.iter().all(|v| v.is_finite()).then_some(b)
}

/// Cuts every triangle to `rect` (page mm); new corners are appended to the vertices.
fn clip(soup: &mut Soup, rect: [f64; 4]) {
    let triangles = std::mem::take(&mut soup.triangles);
    for t in triangles {
        let Some(v) = t.iter().map(|&i| soup.vertices.get(i as usize).copied()).collect::<Option<Vec<_>>>() else {
            continue;
        };
        let inside = |p: &[f64; 3]| p[0] >= rect[0] && p[0] <= rect[2] && p[1] >= rect[1] && p[1] <= rect[3];
        if v.iter().all(inside) {
            soup.triangles.push(t);
            continue;
        }
        let poly = clip_polygon(v, rect);
        if poly.len() < 3 {
            continue;
        }
        let base = soup.vertices.len() as u32;
        soup.vertices.extend_from_slice(&poly);
        for k in 1..poly.len() as u32 - 1 {
            soup.triangles.push([base, base + k, base + k + 1]);
        }
    }
}

/// Sutherland–Hodgman: the part of the polygon inside `rect`, heights
/// interpolated linearly along the cut edges.
fn clip_polygon(mut poly: Vec<[f64; 3]>, rect: [f64; 4]) -> Vec<[f64; 3]> {
    // (axis, bound, keep values >= bound?)
    for (axis, bound, keep_above) in [(0, rect[0], true), (0, rect[2], false), (1, rect[1], true), (1, rect[3], false)]
    {
        let inside = |p: &[f64; 3]| if keep_above { p[axis] >= bound } else { p[axis] <= bound };
        let mut out = Vec::with_capacity(poly.len() + 2);
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            if inside(&a) {
                out.push(a);
            }
            if inside(&a) != inside(&b) {
                let t = (bound - a[axis]) / (b[axis] - a[axis]);
                let mut p = [0.0; 3];
                for c in 0..3 {
                    p[c] = a[c] + t * (b[c] - a[c]);
                }
                p[axis] = bound;
                out.push(p);
            }
        }
        poly = out;
        if poly.is_empty() {
            break;
        }
    }
    poly
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_triangle_cut_by_a_rectangle_keeps_its_plane() {
        // h = x + 2y over the triangle (0,0) (10,0) (0,10), cut to 2..6 x 1..5.
        let h = |x: f64, y: f64| x + 2.0 * y;
        let tri = vec![[0.0, 0.0, h(0.0, 0.0)], [10.0, 0.0, h(10.0, 0.0)], [0.0, 10.0, h(0.0, 10.0)]];
        let poly = clip_polygon(tri, [2.0, 1.0, 6.0, 5.0]);
        assert!(poly.len() >= 4);
        for p in &poly {
            assert!(p[0] >= 2.0 && p[0] <= 6.0 && p[1] >= 1.0 && p[1] <= 5.0, "{p:?}");
            assert!(p[0] + p[1] <= 10.0 + 1e-12, "{p:?} is outside the triangle");
            assert!((p[2] - h(p[0], p[1])).abs() < 1e-12, "{p:?}");
        }
        // The cut polygon is the square minus the corner beyond x + y = 10: (6,4) (6,5) (5,5) go.
        let area: f64 = (0..poly.len())
            .map(|k| {
                let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum::<f64>()
            / 2.0;
        assert!((area.abs() - (16.0 - 0.5)).abs() < 1e-12, "area {area}");
    }
}
