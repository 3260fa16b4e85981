//! A relief as a binary STL (written by `stl_io`): a closed height-field
//! mesh over the whole plate.
//!
//! The marks are drawn with tiny-skia into a raster whose pixel centres are
//! the vertices of a grid `grid_mm` apart, without anti-aliasing: a vertex
//! stands at the base plate's thickness, plus the height of the highest
//! level whose marks cover it (`raise_mm` for lines, symbols and braille,
//! `texture_mm` for textures). The mesh is that grid's top surface (two
//! triangles a cell), the plate's four side walls down to z = 0, and its
//! bottom (a fan from its centre). Being a height field over a rectangle,
//! it is watertight and 2-manifold by construction: every edge is shared by
//! exactly two triangles, which run along it in opposite directions; every
//! triangle winds counter-clockwise seen from outside, so the volume is
//! positive. Features rise over one grid step at their edges, as a nozzle
//! would draw them. x runs right and y up (the map reads as on paper, seen
//! from above), in millimetres.

use taxel_format::Medium;

use super::raster::{Frame, coverage};
use super::{Level, PrintError, Sheet};

/// Largest number of vertices of a relief's grid (a profile file may ask
/// for a fine grid over a large plate).
pub const MAX_RELIEF_VERTICES: u64 = 16_000_000;

/// Gap between the plates of a relief printed on several pages (the
/// graphic's pages and the key), in mm: a slicer splits them into objects.
pub const PLATE_GAP_MM: f32 = 10.0;

/// The grid's size in cells `(cols, rows)` of one plate of `sheet`.
fn grid(sheet: &Sheet) -> Result<(u32, u32), PrintError> {
    let g = sheet.params.grid_mm as f64;
    let cols = (sheet.paper_mm.0 / g * (1.0 + 1e-6)).floor().max(1.0);
    let rows = (sheet.paper_mm.1 / g * (1.0 + 1e-6)).floor().max(1.0);
    let plates = sheet.pages.len().max(1) as f64;
    if (cols + 1.0) * (rows + 1.0) * plates > MAX_RELIEF_VERTICES as f64 {
        return Err(PrintError(format!(
            "a relief of {plates} plate(s) of {cols} x {rows} cells of {g} mm is more than {MAX_RELIEF_VERTICES} vertices: \
             make grid_mm larger"
        )));
    }
    Ok((cols as u32, rows as u32))
}

/// The relief's height at every grid vertex of the plate of `marks` (a
/// page of `sheet`), `(cols + 1) x (rows + 1)` of them row by row from the
/// paper's top edge, in mm above z = 0; and the grid's size in cells
/// `(cols, rows)`.
pub fn heights(sheet: &Sheet, marks: &[super::Mark]) -> Result<(Vec<f32>, (u32, u32)), PrintError> {
    let p = &sheet.params;
    let g = p.grid_mm as f64;
    let (cols, rows) = grid(sheet)?;
    let frame = Frame { x0: -g / 2.0, y0: -g / 2.0, px: 1.0 / g, w: cols + 1, h: rows + 1 };
    let cov = coverage(marks, frame, false).ok_or_else(|| PrintError("cannot draw the relief's raster".into()))?;
    let lift = |l: Level| match l {
        Level::Texture => p.texture_mm,
        Level::Braille | Level::Line => p.raise_mm,
    };
    let mut z = vec![p.base_mm; (cols as usize + 1) * (rows as usize + 1)];
    for (li, l) in [Level::Texture, Level::Braille, Level::Line].into_iter().enumerate() {
        for (k, &a) in cov.levels[li].iter().enumerate() {
            if a >= 128 {
                z[k] = z[k].max(p.base_mm + lift(l));
            }
        }
    }
    Ok((z, (cols, rows)))
}

/// The relief's triangles, each three vertices `[x, y, z]` counter-clockwise
/// seen from outside: a plate a page, laid out as [`Sheet::layout`] places
/// the pages, [`PLATE_GAP_MM`] apart (x right, y up).
pub fn triangles(sheet: &Sheet) -> Result<Vec<[[f32; 3]; 3]>, PrintError> {
    if sheet.medium() != Medium::Relief {
        return Err(PrintError(format!("{} is not a relief: it is written as PDF, not STL", sheet.profile.name)));
    }
    let (cols, rows) = grid(sheet)?;
    let g = sheet.params.grid_mm;
    let (w, h) = (cols as f32 * g + PLATE_GAP_MM, rows as f32 * g + PLATE_GAP_MM);
    let mut out = Vec::new();
    for (marks, (c, r)) in sheet.pages.iter().zip(sheet.layout()) {
        let (z, _) = heights(sheet, marks)?;
        plate(&z, (cols, rows), g, (c as f32 * w, -(r as f32) * h), &mut out);
    }
    Ok(out)
}

/// The closed mesh of one plate of heights `z` over a grid of `cols x rows`
/// cells `g` apart, its top-left corner moved by `at` (mm, y up).
fn plate(z: &[f32], (cols, rows): (u32, u32), g: f32, at: (f32, f32), out: &mut Vec<[[f32; 3]; 3]>) {
    let (nx, ny) = (cols as usize + 1, rows as usize + 1);
    let height = rows as f32 * g;
    // Vertex (i, j) of the grid, j from the paper's top edge; y runs up.
    let top = |i: usize, j: usize| [at.0 + i as f32 * g, at.1 + height - j as f32 * g, z[j * nx + i]];
    let bottom = |i: usize, j: usize| [at.0 + i as f32 * g, at.1 + height - j as f32 * g, 0.0];
    out.reserve(2 * cols as usize * rows as usize + 6 * (nx + ny));
    for j in 0..rows as usize {
        for i in 0..cols as usize {
            // Seen from above (y up), (i, j+1) -> (i+1, j+1) -> (i+1, j) is counter-clockwise.
            out.push([top(i, j + 1), top(i + 1, j + 1), top(i + 1, j)]);
            out.push([top(i, j + 1), top(i + 1, j), top(i, j)]);
        }
    }
    // The boundary, counter-clockwise seen from above: along the bottom
    // edge of the paper (j = rows) left to right, up the right side, along
    // the top edge right to left, down the left side.
    let mut ring: Vec<(usize, usize)> = Vec::with_capacity(2 * (nx + ny));
    ring.extend((0..cols as usize).map(|i| (i, rows as usize)));
    ring.extend((1..=rows as usize).rev().map(|j| (cols as usize, j)));
    ring.extend((1..=cols as usize).rev().map(|i| (i, 0)));
    ring.extend((0..rows as usize).map(|j| (0, j)));
    let centre = [at.0 + cols as f32 * g / 2.0, at.1 + height / 2.0, 0.0];
    for k in 0..ring.len() {
        let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
        // A wall quad, outward: the boundary runs counter-clockwise, so
        // outside is to its right; a -> b along the bottom, then up.
        out.push([bottom(a.0, a.1), bottom(b.0, b.1), top(b.0, b.1)]);
        out.push([bottom(a.0, a.1), top(b.0, b.1), top(a.0, a.1)]);
        // The bottom face, seen from below: clockwise seen from above.
        out.push([centre, bottom(b.0, b.1), bottom(a.0, a.1)]);
    }
}

fn normal(t: &[[f32; 3]; 3]) -> [f32; 3] {
    let u = [t[1][0] - t[0][0], t[1][1] - t[0][1], t[1][2] - t[0][2]];
    let v = [t[2][0] - t[0][0], t[2][1] - t[0][1], t[2][2] - t[0][2]];
    let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if l > 0.0 { [n[0] / l, n[1] / l, n[2] / l] } else { [0.0, 0.0, 0.0] }
}

/// Writes `sheet` (a relief) as a binary STL.
pub fn stl(sheet: &Sheet) -> Result<Vec<u8>, PrintError> {
    let tris = triangles(sheet)?;
    let mut out = Vec::with_capacity(84 + 50 * tris.len());
    let mesh = tris.iter().map(|t| stl_io::Triangle {
        normal: stl_io::Normal::new(normal(t)),
        vertices: [stl_io::Vertex::new(t[0]), stl_io::Vertex::new(t[1]), stl_io::Vertex::new(t[2])],
    });
    stl_io::write_stl(&mut out, mesh).map_err(|e| PrintError(format!("cannot write the STL: {e}")))?;
    Ok(out)
}

/// A mesh with shared corners: the distinct points, and each triangle as
/// three indices into them.
pub type Indexed = (Vec<[f32; 3]>, Vec<[usize; 3]>);

/// The relief's triangles with their corners shared: each distinct corner
/// (by its exact coordinates) once, and each triangle as three indices into
/// them, in the order of [`triangles`].
pub fn indexed(sheet: &Sheet) -> Result<Indexed, PrintError> {
    let tris = triangles(sheet)?;
    let mut index: std::collections::HashMap<[u32; 3], usize> = std::collections::HashMap::new();
    let mut points: Vec<[f32; 3]> = Vec::new();
    let faces = tris
        .iter()
        .map(|t| {
            t.map(|p| {
                *index.entry(p.map(f32::to_bits)).or_insert_with(|| {
                    points.push(p);
                    points.len() - 1
                })
            })
        })
        .collect();
    Ok((points, faces))
}

/// Writes `sheet` (a relief) as a 3MF package: one object, its mesh in
/// millimetres with shared vertices (the same triangles as the STL).
pub fn three_mf(sheet: &Sheet) -> Result<Vec<u8>, PrintError> {
    let (points, faces) = indexed(sheet)?;
    let mesh = threemf::Mesh {
        vertices: threemf::model::Vertices {
            vertex: points
                .iter()
                .map(|p| threemf::model::Vertex { x: f64::from(p[0]), y: f64::from(p[1]), z: f64::from(p[2]) })
                .collect(),
        },
        triangles: threemf::model::Triangles {
            triangle: faces.iter().map(|f| threemf::model::Triangle { v1: f[0], v2: f[1], v3: f[2] }).collect(),
        },
    };
    let mut out = std::io::Cursor::new(Vec::new());
    threemf::write(&mut out, mesh).map_err(|e| PrintError(format!("cannot write the 3MF: {e}")))?;
    Ok(out.into_inner())
}
