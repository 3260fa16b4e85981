//! The top surface of a triangle soup, seen from above (+Y), built on a
//! spade constrained Delaunay triangulation.
//!
//! Every projected mesh edge is a constraint; where projected edges cross
//! (overhangs, walls, overlapping parts) spade splits them at the crossing.
//! The triangulation then refines the arrangement of all projected
//! triangles: each of its faces lies wholly inside or wholly outside each
//! mesh triangle, so a face has a fixed set of covering triangles, and the
//! surface over it is the highest of their planes (the finger touches the
//! top). Heights are interpolated linearly on the original triangles, which
//! for a single-valued mesh is exactly spade's barycentric interpolation on
//! the triangulation (a test checks this). Height jumps across a constraint
//! edge are recorded as steps.
//!
//! A mesh whose projected triangles already tile the page (`sheet`) skips
//! the triangulation: its triangles are the faces, and its steps lie on the
//! edges two triangles share.

use std::collections::HashMap;
use std::collections::hash_map::Entry;

use spade::handles::{FixedFaceHandle, FixedVertexHandle, InnerTag};
use spade::{ConstrainedDelaunayTriangulation, Point2, PositionInTriangulation, Triangulation};

use super::error::MeshError;
use super::load::Soup;
use super::planar::{self, Points, Snap};
use super::sheet;

/// Slope (|∇h|) above which a triangle counts as a wall: it still covers its
/// thin footprint, but it does not raise the gradient cap.
pub const WALL_SLOPE: f64 = 10.0;
/// Largest number of (face, covering triangle) pairs, which bounds the work
/// that heavily overlapping meshes can cause.
const MAX_COVER_PAIRS: usize = 50_000_000;

/// The plane of one mesh triangle over the page.
#[derive(Debug, Clone, Copy)]
pub struct Plane {
    x0: f64,
    y0: f64,
    h0: f64,
    /// ∂h/∂x.
    pub gx: f64,
    /// ∂h/∂y (y down the page).
    pub gy: f64,
    lo: f64,
    hi: f64,
}

impl Plane {
    /// The plane through three `[x, y, h]` points, or `None` when their
    /// projection has no area (a vertical or degenerate triangle).
    pub fn through(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Option<Plane> {
        let (dx1, dy1, dh1) = (b[0] - a[0], b[1] - a[1], b[2] - a[2]);
        let (dx2, dy2, dh2) = (c[0] - a[0], c[1] - a[1], c[2] - a[2]);
        let det = dx1 * dy2 - dx2 * dy1;
        let scale = (dx1 * dx1 + dy1 * dy1).max(dx2 * dx2 + dy2 * dy2);
        // Relative test: the sine of the triangle's smallest angle seen from
        // above must be above 1e-12, so the gradient is not rounding noise.
        if det.abs() <= 1e-12 * scale || det.is_nan() {
            return None;
        }
        let gx = (dh1 * dy2 - dh2 * dy1) / det;
        let gy = (dx1 * dh2 - dx2 * dh1) / det;
        if !gx.is_finite() || !gy.is_finite() {
            return None;
        }
        Some(Plane { x0: a[0], y0: a[1], h0: a[2], gx, gy, lo: a[2].min(b[2]).min(c[2]), hi: a[2].max(b[2]).max(c[2]) })
    }

    /// Height at page point `(x, y)`, kept within the triangle's own range
    /// so that evaluating a sliver just outside itself cannot run away.
    pub fn at(&self, x: f64, y: f64) -> f64 {
        (self.h0 + self.gx * (x - self.x0) + self.gy * (y - self.y0)).clamp(self.lo, self.hi)
    }

    /// Slope magnitude |∇h|.
    pub fn slope(&self) -> f64 {
        self.gx.hypot(self.gy)
    }
}

/// One face of the triangulation with the mesh triangles that cover it.
#[derive(Debug, Clone)]
pub struct Face {
    /// Corners `[x, y]` in page mm, counter-clockwise.
    pub corners: [[f64; 2]; 3],
    /// Range into [`Surface::cover`].
    pub cover: core::ops::Range<u32>,
}

/// A height jump along a segment of the page.
#[derive(Debug, Clone, Copy)]
pub struct Step {
    /// One end, page mm.
    pub a: [f64; 2],
    /// The other end, page mm.
    pub b: [f64; 2],
}

/// The top surface: covered faces, planes, steps and statistics.
#[derive(Debug, Clone)]
pub struct Surface {
    /// Faces covered by at least one triangle.
    pub faces: Vec<Face>,
    /// Covering triangle indices (into `planes`), grouped per face.
    pub cover: Vec<u32>,
    /// The plane of each covering (non-degenerate) triangle.
    pub planes: Vec<Plane>,
    /// Height jumps.
    pub steps: Vec<Step>,
    /// Footprint bounding box `[xmin, ymin, xmax, ymax]` in mm.
    pub bbox: [f64; 4],
    /// Median length of the projected edges of covering triangles, mm.
    pub median_edge: f64,
    /// Height jumps smaller than this are rounding, not steps (mm).
    pub step_tol: f64,
    /// Steepest slope among triangles that are not walls.
    pub max_surface_slope: f64,
    /// Triangles with no projected area (vertical walls, degenerate or duplicate corners).
    pub degenerate: usize,
    /// Projected edges still crossing another after the arrangement's rounds
    /// (left out of the triangulation's constraints; 0 in every case seen).
    pub unresolved: usize,
    /// Whether the faces are the mesh triangles themselves, whose projections
    /// cross too often to arrange: the field takes the highest of them at
    /// each node and finds steps between nodes (`field::sample`).
    pub raster: bool,
}

impl Surface {
    /// Highest plane over face `f` at `(x, y)`: `(height, ∂h/∂x, ∂h/∂y)`.
    pub fn top(&self, f: &Face, x: f64, y: f64) -> Option<(f64, f64, f64)> {
        let mut best: Option<(f64, f64, f64)> = None;
        for &t in self.cover.get(f.cover.start as usize..f.cover.end as usize).unwrap_or(&[]) {
            if let Some(p) = self.planes.get(t as usize) {
                let h = p.at(x, y);
                if best.is_none_or(|b| h > b.0) {
                    best = Some((h, p.gx, p.gy));
                }
            }
        }
        best
    }
}

impl Surface {
    /// Whether the tops of faces `f1` and `f2` differ by more than the
    /// rounding tolerance at either end or the middle of their edge `a`–`b`.
    fn is_step(&self, f1: &Face, f2: &Face, a: [f64; 2], b: [f64; 2]) -> bool {
        let m = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
        [a, m, b].iter().any(|q| match (self.top(f1, q[0], q[1]), self.top(f2, q[0], q[1])) {
            (Some(h1), Some(h2)) => (h1.0 - h2.0).abs() > self.step_tol,
            _ => false,
        })
    }
}

type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// Builds the top surface of `soup`.
pub fn build(soup: &Soup) -> Result<Surface, MeshError> {
    let snapped = Snapped::new(soup)?;
    let Covering { planes, mut corners, degenerate, heights } = Covering::new(soup, &snapped.verts);
    let max_surface_slope = planes.iter().map(Plane::slope).filter(|&m| m <= WALL_SLOPE).fold(0.0, f64::max);
    if planes.is_empty() {
        return Err(MeshError::NoArea);
    }
    let (grid_points, map) = distinct_points(&corners, &snapped.grid_of, soup.vertices.len());
    let edges = projected_edges(&corners, &map);
    let points = positions(&grid_points, &snapped.snap);
    let mut surface = Surface::unarranged(planes, &points, &edges, heights, max_surface_slope, degenerate);

    // A mesh whose projection already tiles the page (a terrain) is its own
    // triangulation: each triangle is a face covered by itself (sheet.rs).
    let tris: Vec<[u32; 3]> = corners.iter().map(|t| t.map(|i| map[i as usize])).collect();
    if let Some(shared) = sheet::tiling(&grid_points.at, &tris) {
        surface.tile(&tris, &points, &shared);
        return Ok(surface);
    }

    let Some((grid_points, edges)) = arrangement(&grid_points, &edges) else {
        surface.rasterise(&corners, &snapped.verts);
        return Ok(surface);
    };
    snapped.drop_hidden(&mut surface.planes, &mut corners);
    let (cdt, unresolved) = triangulate(grid_points, edges, &snapped.snap, true)?;
    surface.unresolved = unresolved;
    check_bulk_order(&cdt, &points)?;
    let pairs = cover_pairs(&cdt, &corners, &snapped.verts, &map)?;
    let face_slot = surface.arrange(&cdt, &pairs);
    surface.steps = constraint_steps(&cdt, &surface, &face_slot);
    Ok(surface)
}

/// The soup's vertices snapped to the arrangement's grid (planar.rs), so
/// the planes, the inside tests and the triangulation see the same points.
struct Snapped {
    /// The grid of the footprint of the referenced vertices.
    snap: Snap,
    /// Each vertex's grid point.
    grid_of: Vec<[i64; 2]>,
    /// Each vertex as `[x, y, h]`, its page position on the grid.
    verts: Vec<[f64; 3]>,
}

impl Snapped {
    /// Snaps every vertex of `soup` to the grid over the footprint of the
    /// vertices its triangles reference, or fails when they have none.
    fn new(soup: &Soup) -> Result<Snapped, MeshError> {
        let mut foot = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
        for t in &soup.triangles {
            for &i in t {
                if let Some(v) = soup.vertices.get(i as usize) {
                    foot = [foot[0].min(v[0]), foot[1].min(v[1]), foot[2].max(v[0]), foot[3].max(v[1])];
                }
            }
        }
        if !foot.iter().all(|v| v.is_finite()) {
            return Err(MeshError::EmptyScene);
        }
        let snap = Snap::new(foot);
        let grid_of: Vec<[i64; 2]> = soup.vertices.iter().map(|v| snap.to_grid(v[0], v[1])).collect();
        let verts: Vec<[f64; 3]> = soup
            .vertices
            .iter()
            .zip(&grid_of)
            .map(|(v, &g)| {
                let m = snap.to_mm(g);
                [m[0], m[1], v[2]]
            })
            .collect();
        Ok(Snapped { snap, grid_of, verts })
    }

    /// Leaves out of `planes` and `corners` (in step) each triangle with
    /// the same projection as another and nowhere above it (a block's
    /// bottom under its top, a repeated triangle): it never makes the top
    /// surface. (The tiling test refuses such pairs, so only an arranged
    /// surface needs this.)
    fn drop_hidden(&self, planes: &mut Vec<Plane>, corners: &mut Vec<[u32; 3]>) {
        let corner_heights = |t: &[u32; 3]| {
            let mut c = t.map(|i| (self.grid_of[i as usize], self.verts[i as usize][2]));
            c.sort_unstable_by_key(|x| x.0);
            c
        };
        let mut keep = vec![true; corners.len()];
        let mut first: HashMap<[[i64; 2]; 3], usize> = HashMap::with_capacity(corners.len());
        for (k, t) in corners.iter().enumerate() {
            let c = corner_heights(t);
            match first.entry(c.map(|x| x.0)) {
                Entry::Vacant(e) => {
                    e.insert(k);
                }
                Entry::Occupied(mut e) => {
                    let o = corner_heights(&corners[*e.get()]);
                    if c.iter().zip(&o).all(|(a, b)| a.1 <= b.1) {
                        keep[k] = false;
                    } else if c.iter().zip(&o).all(|(a, b)| a.1 >= b.1) {
                        keep[*e.get()] = false;
                        e.insert(k);
                    }
                }
            }
        }
        if keep.contains(&false) {
            let mut kept = keep.iter();
            planes.retain(|_| kept.next().copied().unwrap_or(true));
            let mut kept = keep.iter();
            corners.retain(|_| kept.next().copied().unwrap_or(true));
        }
    }
}

/// The triangles of a soup that cover area, with their planes.
struct Covering {
    /// The plane of each covering triangle.
    planes: Vec<Plane>,
    /// The vertex indices of each covering triangle, in step with `planes`.
    corners: Vec<[u32; 3]>,
    /// How many triangles have no projected area (walls, degenerate).
    degenerate: usize,
    /// The lowest and highest height of any triangle's corner.
    heights: [f64; 2],
}

impl Covering {
    /// Sorts the triangles of `soup`, on the snapped `verts`, into those
    /// that cover area and the rest, which are walls or degenerate.
    fn new(soup: &Soup, verts: &[[f64; 3]]) -> Covering {
        let mut planes = Vec::new();
        let mut corners = Vec::new();
        let mut degenerate = 0usize;
        let (mut lo_h, mut hi_h) = (f64::INFINITY, f64::NEG_INFINITY);
        for t in &soup.triangles {
            let v = t.map(|i| verts.get(i as usize).copied().unwrap_or([f64::NAN; 3]));
            for p in &v {
                lo_h = lo_h.min(p[2]);
                hi_h = hi_h.max(p[2]);
            }
            match Plane::through(v[0], v[1], v[2]) {
                Some(p) => {
                    planes.push(p);
                    corners.push(*t);
                }
                None => degenerate += 1,
            }
        }
        Covering { planes, corners, degenerate, heights: [lo_h, hi_h] }
    }
}

/// The distinct grid points of the covering triangles' corners in
/// first-seen order (spade keeps the order of a duplicate-free bulk load,
/// so index i is vertex handle i), and each soup vertex's index among them
/// (`u32::MAX` for a vertex no covering triangle uses).
fn distinct_points(corners: &[[u32; 3]], grid_of: &[[i64; 2]], vertices: usize) -> (Points, Vec<u32>) {
    let mut grid_points = Points::default();
    let mut map = vec![u32::MAX; vertices];
    for t in corners {
        for &i in t {
            if let (Some(slot), Some(&g)) = (map.get_mut(i as usize), grid_of.get(i as usize))
                && *slot == u32::MAX
            {
                *slot = grid_points.add(g);
            }
        }
    }
    (grid_points, map)
}

/// The projected edges of the covering triangles between distinct points,
/// each once with its lower end first, sorted.
fn projected_edges(corners: &[[u32; 3]], map: &[u32]) -> Vec<[u32; 2]> {
    let mut edges: Vec<[u32; 2]> = Vec::with_capacity(3 * corners.len());
    for t in corners {
        let m = t.map(|i| map[i as usize]);
        for (a, b) in [(m[0], m[1]), (m[1], m[2]), (m[2], m[0])] {
            if a != b {
                edges.push([a.min(b), a.max(b)]);
            }
        }
    }
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// The arrangement of all projected `edges` over `grid_points`: the points
/// with the crossings added and the edges split at them, or `None` when it
/// costs too much.
///
/// Triangles that cross one another many times (a terrain seen edge on:
/// every column of its grid projects onto one thin strip where its
/// slivers cross) make an arrangement, a triangulation and covers that
/// grow with the crossings: 16 s to 35 s for a 64,000-triangle terrain
/// read with the wrong axis, against 0.3 s from above. The arrangement
/// of all edges is tried within a budget proportional to the edges; past
/// it, or when it splits the edges into more than twice the points, the
/// triangles are the faces as they are, each covered by itself, and the
/// field takes the highest at each node: the exact top surface at the
/// nodes, for the cost of the nodes the triangles cover
/// ([`Surface::rasterise`]).
fn arrangement(grid_points: &Points, edges: &[[u32; 2]]) -> Option<(Points, Vec<[u32; 2]>)> {
    let mut split_points = grid_points.clone();
    let budget = 20 * edges.len() + 100_000;
    let arranged = planar::split(&mut split_points, edges, edges, budget)
        .ok()
        .filter(|_| split_points.at.len() <= 2 * grid_points.at.len() + 1000)?;
    Some((split_points, arranged))
}

/// Checks that each of `points` is the vertex of `cdt` with its index: a
/// handle in a bulk load is its input index; check rather than trust.
fn check_bulk_order(cdt: &Cdt, points: &[Point2<f64>]) -> Result<(), MeshError> {
    for (i, p) in points.iter().enumerate() {
        if i >= cdt.num_vertices() || cdt.vertex(FixedVertexHandle::from_index(i)).position() != *p {
            return Err(MeshError::Triangulation("vertex order changed in the bulk load".into()));
        }
    }
    Ok(())
}

/// Which faces of `cdt` each covering triangle covers, as sorted (face,
/// triangle) pairs: a walk from the face under the triangle's centroid to
/// neighbours whose centroid is inside it. Fails past [`MAX_COVER_PAIRS`].
fn cover_pairs(cdt: &Cdt, corners: &[[u32; 3]], verts: &[[f64; 3]], map: &[u32]) -> Result<Vec<(u32, u32)>, MeshError> {
    let mut stamp = vec![u32::MAX; cdt.num_all_faces()];
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    let mut queue: Vec<FixedFaceHandle<InnerTag>> = Vec::new();
    for (ti, t) in corners.iter().enumerate() {
        let v = t.map(|i| verts[i as usize]);
        let tri = Tri::new(v);
        let c = Point2::new((v[0][0] + v[1][0] + v[2][0]) / 3.0, (v[0][1] + v[1][1] + v[2][1]) / 3.0);
        let hint = FixedVertexHandle::from_index(map[t[0] as usize] as usize);
        queue.clear();
        for f in seed_faces(cdt, c, hint) {
            let fi = f.index();
            if stamp[fi] != ti as u32 && tri.contains(face_centroid(cdt, f)) {
                stamp[fi] = ti as u32;
                queue.push(f);
            }
        }
        while let Some(f) = queue.pop() {
            pairs.push((f.index() as u32, ti as u32));
            if pairs.len() > MAX_COVER_PAIRS {
                return Err(MeshError::TooBig { what: "overlapping triangle layers", limit: MAX_COVER_PAIRS });
            }
            for e in cdt.face(f).adjacent_edges() {
                let Some(n) = e.rev().face().as_inner() else { continue };
                let n = n.fix();
                if stamp[n.index()] != ti as u32 && tri.contains(face_centroid(cdt, n)) {
                    stamp[n.index()] = ti as u32;
                    queue.push(n);
                }
            }
        }
    }
    pairs.sort_unstable();
    Ok(pairs)
}

/// The inner faces of `cdt` at point `c` (located from vertex `hint`): the
/// face it is in, the faces on either side of the edge it is on, or the
/// faces around the vertex it is on.
fn seed_faces(cdt: &Cdt, c: Point2<f64>, hint: FixedVertexHandle) -> Vec<FixedFaceHandle<InnerTag>> {
    match cdt.locate_with_hint(c, hint) {
        PositionInTriangulation::OnFace(f) => vec![f],
        PositionInTriangulation::OnEdge(e) => {
            let d = cdt.directed_edge(e);
            [d.face(), d.rev().face()].iter().filter_map(|f| f.as_inner()).map(|f| f.fix()).collect()
        }
        PositionInTriangulation::OnVertex(vh) => {
            cdt.vertex(vh).out_edges().filter_map(|e| e.face().as_inner()).map(|f| f.fix()).collect()
        }
        _ => Vec::new(),
    }
}

/// The steps of an arranged surface: constraint edges of `cdt` with a
/// covered face on each side (`face_slot` of [`Surface::arrange`]) whose
/// tops differ.
fn constraint_steps(cdt: &Cdt, surface: &Surface, face_slot: &[u32]) -> Vec<Step> {
    let mut steps = Vec::new();
    for e in cdt.undirected_edges() {
        if !cdt.is_constraint_edge(e.fix()) {
            continue;
        }
        let d = e.as_directed();
        let side = |f: spade::handles::FaceHandle<'_, spade::handles::PossiblyOuterTag, _, _, _, _>| {
            f.as_inner().and_then(|f| surface.faces.get(face_slot[f.fix().index()] as usize))
        };
        let (Some(f1), Some(f2)) = (side(d.face()), side(d.rev().face())) else { continue };
        let [a, b] = d.positions().map(|p| [p.x, p.y]);
        if surface.is_step(f1, f2, a, b) {
            steps.push(Step { a, b });
        }
    }
    steps
}

impl Surface {
    /// The surface of `planes` with no faces yet: the footprint of
    /// `points`, the rounding tolerance of steps from the extent of the
    /// points and the corners' `heights` (lowest, highest), and the median
    /// length of the projected `edges`.
    fn unarranged(
        planes: Vec<Plane>,
        points: &[Point2<f64>],
        edges: &[[u32; 2]],
        heights: [f64; 2],
        max_surface_slope: f64,
        degenerate: usize,
    ) -> Surface {
        let [lo_h, hi_h] = heights;
        let mut bbox = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
        for p in points {
            bbox = [bbox[0].min(p.x), bbox[1].min(p.y), bbox[2].max(p.x), bbox[3].max(p.y)];
        }
        let extent = (bbox[2] - bbox[0]).max(bbox[3] - bbox[1]).max(hi_h - lo_h);
        let step_tol = (extent * 1e-7).max(f64::MIN_POSITIVE);

        let mut lengths: Vec<f64> = edges
            .iter()
            .map(|&[a, b]| {
                let (a, b) = (points[a as usize], points[b as usize]);
                (a.x - b.x).hypot(a.y - b.y)
            })
            .collect();
        let mid = lengths.len() / 2;
        let median_edge = if lengths.is_empty() { 0.0 } else { *lengths.select_nth_unstable_by(mid, f64::total_cmp).1 };

        Surface {
            faces: Vec::new(),
            cover: Vec::new(),
            planes,
            steps: Vec::new(),
            bbox,
            median_edge,
            step_tol,
            max_surface_slope,
            degenerate,
            unresolved: 0,
            raster: false,
        }
    }

    /// Makes each of `tris` (indices into `points`), which tile the page, a
    /// face covered by itself, with its steps on the `shared` edges whose
    /// two triangles' tops differ.
    fn tile(&mut self, tris: &[[u32; 3]], points: &[Point2<f64>], shared: &[sheet::Shared]) {
        self.faces = tris
            .iter()
            .zip(0u32..)
            .map(|(t, k)| Face { corners: t.map(|i| [points[i as usize].x, points[i as usize].y]), cover: k..k + 1 })
            .collect();
        self.cover = (0..tris.len() as u32).collect();
        let steps = shared
            .iter()
            .filter_map(|e| {
                let [a, b] = e.ends.map(|i| [points[i as usize].x, points[i as usize].y]);
                let [f1, f2] = e.tris.map(|t| &self.faces[t as usize]);
                self.is_step(f1, f2, a, b).then_some(Step { a, b })
            })
            .collect();
        self.steps = steps;
    }

    /// Makes each covering triangle (`corners` into `verts`) a face covered
    /// by itself, for a surface with no arrangement ([`arrangement`]): the
    /// field finds its top and steps node by node.
    fn rasterise(&mut self, corners: &[[u32; 3]], verts: &[[f64; 3]]) {
        self.faces = corners
            .iter()
            .zip(0u32..)
            .map(|(t, k)| Face { corners: t.map(|i| [verts[i as usize][0], verts[i as usize][1]]), cover: k..k + 1 })
            .collect();
        self.cover = (0..corners.len() as u32).collect();
        self.raster = true;
    }

    /// Sets the faces to the covered faces of `cdt` in triangulation order,
    /// with their covering triangles from the sorted (face, triangle)
    /// `pairs`. Returns each face's slot in [`Surface::faces`] by its index
    /// in `cdt` (`u32::MAX` for a face nothing covers).
    fn arrange(&mut self, cdt: &Cdt, pairs: &[(u32, u32)]) -> Vec<u32> {
        let mut handles: Vec<Option<FixedFaceHandle<InnerTag>>> = vec![None; cdt.num_all_faces()];
        for f in cdt.inner_faces() {
            if let Some(h) = handles.get_mut(f.fix().index()) {
                *h = Some(f.fix());
            }
        }
        let mut face_slot = vec![u32::MAX; cdt.num_all_faces()];
        let mut faces = Vec::new();
        let mut cover = Vec::with_capacity(pairs.len());
        let mut k = 0;
        while k < pairs.len() {
            let f = pairs[k].0;
            let start = cover.len() as u32;
            while k < pairs.len() && pairs[k].0 == f {
                cover.push(pairs[k].1);
                k += 1;
            }
            let Some(Some(fh)) = handles.get(f as usize) else { continue };
            let pos = cdt.face(*fh).positions();
            face_slot[f as usize] = faces.len() as u32;
            faces.push(Face { corners: pos.map(|p| [p.x, p.y]), cover: start..cover.len() as u32 });
        }
        self.faces = faces;
        self.cover = cover;
        face_slot
    }
}

/// Rounds of arrangement before giving up on a crossing (each round only
/// splits what the rounding of the previous one created, a grid step long).
const MAX_ROUNDS: usize = 6;

/// Builds the triangulation of `points` with every edge a constraint. Edges
/// are split where they cross or touch, in exact arithmetic (planar.rs);
/// edges that the bulk loader still reports as crossing (the rounding of a
/// crossing can make new ones) are split again and the triangulation is
/// loaded again. Returns
/// the number of edges still crossing after [`MAX_ROUNDS`] (not constraints).
fn triangulate(
    mut points: Points,
    mut edges: Vec<[u32; 2]>,
    snap: &Snap,
    arranged: bool,
) -> Result<(Cdt, usize), MeshError> {
    // Each crossing adds a vertex; bound them so a hostile mesh of long
    // crossing slivers cannot exhaust memory.
    let budget = 4 * points.at.len() + 1_000_000;
    let work = 40 * edges.len() + 50_000_000;
    // The arrangement of all edges first: a bulk load that meets crossing
    // constraints costs as much as one that does not, and would be repeated.
    if !arranged {
        edges = planar::split(&mut points, &edges, &edges, work)?;
    }
    if points.at.len() > budget {
        return Err(MeshError::TooBig { what: "crossings between projected edges", limit: budget });
    }
    let mut round = 0;
    loop {
        let pos = positions(&points, snap);
        for p in &pos {
            spade::validate_vertex(p)
                .map_err(|e| MeshError::Triangulation(format!("vertex ({}, {}): {e:?}", p.x, p.y)))?;
        }
        let mut conflicts: Vec<[u32; 2]> = Vec::new();
        let cdt = Cdt::try_bulk_load_cdt(pos, edges.iter().map(|e| e.map(|i| i as usize)).collect(), |e| {
            // The loader may name an edge's ends in either order; the edge list has the lower first.
            let (a, b) = (e[0].min(e[1]) as u32, e[0].max(e[1]) as u32);
            conflicts.push([a, b])
        })
        .map_err(|e| MeshError::Triangulation(format!("{e:?}")))?;
        round += 1;
        if conflicts.is_empty() || round > MAX_ROUNDS {
            return Ok((cdt, conflicts.len()));
        }
        edges = planar::split(&mut points, &edges, &conflicts, work)?;
        if points.at.len() > budget {
            return Err(MeshError::TooBig { what: "crossings between projected edges", limit: budget });
        }
    }
}

/// The page positions of the grid points, in order.
fn positions(points: &Points, snap: &Snap) -> Vec<Point2<f64>> {
    points
        .at
        .iter()
        .map(|&g| {
            let m = snap.to_mm(g);
            Point2::new(m[0], m[1])
        })
        .collect()
}

fn face_centroid(cdt: &Cdt, f: FixedFaceHandle<InnerTag>) -> [f64; 2] {
    let p = cdt.face(f).positions();
    [(p[0].x + p[1].x + p[2].x) / 3.0, (p[0].y + p[1].y + p[2].y) / 3.0]
}

/// A projected triangle for inside tests.
struct Tri {
    p: [[f64; 2]; 3],
    area2: f64,
}

impl Tri {
    fn new(v: [[f64; 3]; 3]) -> Tri {
        let p = v.map(|q| [q[0], q[1]]);
        let area2 = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        Tri { p, area2 }
    }

    /// Whether `q` is inside or on the triangle (either winding).
    fn contains(&self, q: [f64; 2]) -> bool {
        let w = |a: [f64; 2], b: [f64; 2]| ((b[0] - a[0]) * (q[1] - a[1]) - (q[0] - a[0]) * (b[1] - a[1])) / self.area2;
        w(self.p[0], self.p[1]) >= 0.0 && w(self.p[1], self.p[2]) >= 0.0 && w(self.p[2], self.p[0]) >= 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn soup(vertices: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> Soup {
        Soup { vertices, triangles, ..Soup::default() }
    }

    #[test]
    fn crossing_triangles_are_split_and_the_top_one_wins() {
        // Two triangles whose projections cross like a star of David; the
        // second lies 5 mm higher, so wherever both cover, it is on top.
        let s = soup(
            vec![
                [0.0, 0.0, 0.0],
                [10.0, 0.0, 0.0],
                [5.0, 9.0, 0.0],
                [0.0, 6.0, 5.0],
                [10.0, 6.0, 5.0],
                [5.0, -3.0, 5.0],
            ],
            vec![[0, 1, 2], [3, 4, 5]],
        );
        let surf = build(&s).unwrap();
        let mut both = 0;
        for f in &surf.faces {
            let c = [
                (f.corners[0][0] + f.corners[1][0] + f.corners[2][0]) / 3.0,
                (f.corners[0][1] + f.corners[1][1] + f.corners[2][1]) / 3.0,
            ];
            let h = surf.top(f, c[0], c[1]).unwrap().0;
            if f.cover.len() == 2 {
                both += 1;
                assert_eq!(h, 5.0);
            }
        }
        assert!(both > 0, "the overlap must be a set of faces covered twice");
    }

    #[test]
    fn vertical_wall_is_a_step_and_not_a_face() {
        // Two flat squares at heights 0 and 10 joined by a vertical wall at x = 10.
        let s = soup(
            vec![
                [0.0, 0.0, 0.0],
                [10.0, 0.0, 0.0],
                [10.0, 10.0, 0.0],
                [0.0, 10.0, 0.0],
                [10.0, 0.0, 10.0],
                [20.0, 0.0, 10.0],
                [20.0, 10.0, 10.0],
                [10.0, 10.0, 10.0],
            ],
            vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7], [1, 4, 7], [1, 7, 2]],
        );
        let surf = build(&s).unwrap();
        assert_eq!(surf.degenerate, 2);
        assert_eq!(surf.faces.len(), 4);
        assert!(!surf.steps.is_empty());
        for st in &surf.steps {
            assert_eq!(st.a[0], 10.0);
            assert_eq!(st.b[0], 10.0);
        }
    }
}
