//! glTF 2.0 to a triangle soup in page millimetres.
//!
//! The convention of `primitives.md`: glTF is +Y up and in metres, so a
//! vertex `(X, Y, Z)` (after its node's world transform) becomes page point
//! `(1000 X, 1000 Z)` mm with height `1000 Y` mm; +Z runs towards the bottom
//! of the page. Accessors are read here with bounds-checked code rather than
//! through `gltf`'s reader, whose slicing trusts offsets and counts that a
//! hostile file controls.

use gltf::Document;
use gltf::accessor::{DataType, Dimensions};
use gltf::buffer::Source;
use gltf::mesh::Mode;

use super::error::MeshError;

/// Largest number of triangles one file may contribute.
pub const MAX_TRIANGLES: usize = 20_000_000;
/// Largest coordinate magnitude after conversion to millimetres (100 km).
pub const MAX_COORD_MM: f64 = 1.0e8;
/// Deepest node nesting that is followed.
const MAX_DEPTH: usize = 256;

/// Every triangle of every mesh primitive of the scene, in page millimetres.
#[derive(Debug, Clone, Default)]
pub struct Soup {
    /// Vertices as `[x, y, h]`: page x, page y (down), height, all in mm.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
    /// Names of the meshes that contributed, for provenance.
    pub mesh_names: Vec<String>,
    /// The scene's name, when it has one.
    pub scene_name: Option<String>,
}

/// What `resolve` returns for an external buffer URI: its bytes, or a message.
pub type Resolver<'r> = dyn FnMut(&str) -> Result<Vec<u8>, String> + 'r;

/// Parses `bytes` (`.gltf` JSON or `.glb`) and collects the scene's triangles.
pub fn load(bytes: &[u8], resolve: &mut Resolver<'_>) -> Result<Soup, MeshError> {
    let gltf = gltf::Gltf::from_slice(bytes).map_err(|e| MeshError::Parse(e.to_string()))?;
    let buffers = load_buffers(&gltf.document, gltf.blob.clone(), resolve)?;
    let doc = &gltf.document;
    let scene = doc.default_scene().or_else(|| doc.scenes().next());
    let mut soup = Soup { scene_name: scene.as_ref().and_then(|s| s.name()).map(str::to_owned), ..Soup::default() };
    // Without a scene, every node that is nobody's child is a root.
    let roots: Vec<gltf::Node<'_>> = match &scene {
        Some(s) => s.nodes().collect(),
        None => {
            let mut child = vec![false; doc.nodes().len()];
            for n in doc.nodes() {
                for c in n.children() {
                    if let Some(f) = child.get_mut(c.index()) {
                        *f = true;
                    }
                }
            }
            doc.nodes().filter(|n| !child.get(n.index()).copied().unwrap_or(true)).collect()
        }
    };
    let mut visited = vec![false; doc.nodes().len()];
    let mut stack: Vec<(gltf::Node<'_>, [[f64; 4]; 4], usize)> =
        roots.into_iter().rev().map(|n| (n, IDENTITY, 0)).collect();
    while let Some((node, parent, depth)) = stack.pop() {
        let name = node_name(&node);
        let seen =
            visited.get_mut(node.index()).ok_or_else(|| MeshError::Parse(format!("bad node index in {name}")))?;
        if *seen {
            return Err(MeshError::Graph { node: name, problem: "is reached twice (a cycle or a shared child)" });
        }
        *seen = true;
        if depth > MAX_DEPTH {
            return Err(MeshError::Graph { node: name, problem: "is nested more than 256 levels deep" });
        }
        let world = mul(&parent, &to_f64(node.transform().matrix()));
        if world.iter().flatten().any(|v| !v.is_finite()) {
            return Err(MeshError::NonFinite { node: name, mesh: String::new(), what: "transform" });
        }
        if let Some(mesh) = node.mesh() {
            add_mesh(&mut soup, &node, &mesh, &world, &buffers)?;
        }
        for c in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((c, world, depth + 1));
        }
    }
    if soup.triangles.is_empty() {
        return Err(MeshError::EmptyScene);
    }
    Ok(soup)
}

fn load_buffers(
    doc: &Document,
    mut blob: Option<Vec<u8>>,
    resolve: &mut Resolver<'_>,
) -> Result<Vec<Vec<u8>>, MeshError> {
    let mut out = Vec::new();
    for b in doc.buffers() {
        let data = match b.source() {
            Source::Uri(uri) if !uri.starts_with("data:") => {
                resolve(uri).map_err(|message| MeshError::Buffer { index: b.index(), message })?
            }
            src => {
                gltf::buffer::Data::from_source_and_blob(src, None, &mut blob)
                    .map_err(|e| MeshError::Buffer { index: b.index(), message: e.to_string() })?
                    .0
            }
        };
        if data.len() < b.length() {
            return Err(MeshError::Buffer {
                index: b.index(),
                message: format!("holds {} bytes but declares {}", data.len(), b.length()),
            });
        }
        out.push(data);
    }
    Ok(out)
}

fn add_mesh(
    soup: &mut Soup,
    node: &gltf::Node<'_>,
    mesh: &gltf::Mesh<'_>,
    world: &[[f64; 4]; 4],
    buffers: &[Vec<u8>],
) -> Result<(), MeshError> {
    let mesh_name = mesh_name(mesh);
    soup.mesh_names.push(mesh.name().unwrap_or("").to_owned());
    for prim in mesh.primitives() {
        let at = || Where { node: node_name(node), mesh: mesh_name.clone(), primitive: prim.index() };
        let mode = prim.mode();
        if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
            return Err(MeshError::Mode { at: at(), mode: format!("{mode:?}") });
        }
        let acc = prim.get(&gltf::Semantic::Positions).ok_or_else(|| MeshError::NoPositions { at: at() })?;
        let raw =
            read_vec3(&acc, buffers).map_err(|problem| MeshError::Accessor { at: at(), what: "POSITION", problem })?;
        let base = soup.vertices.len();
        if base + raw.len() > u32::MAX as usize / 2 {
            return Err(MeshError::TooBig { what: "vertices", limit: u32::MAX as usize / 2 });
        }
        for p in &raw {
            let v = apply(world, [p[0] as f64, p[1] as f64, p[2] as f64]);
            if v.iter().any(|c| !c.is_finite()) {
                return Err(MeshError::NonFinite { node: at().node, mesh: at().mesh, what: "vertex position" });
            }
            let mm = [v[0] * 1000.0, v[2] * 1000.0, v[1] * 1000.0];
            if mm.iter().any(|c| c.abs() > MAX_COORD_MM) {
                return Err(MeshError::Range { at: at() });
            }
            soup.vertices.push(mm);
        }
        let indices: Vec<u32> = match prim.indices() {
            Some(ia) => read_indices(&ia, buffers).map_err(|problem| MeshError::Accessor {
                at: at(),
                what: "indices",
                problem,
            })?,
            None => (0..raw.len() as u32).collect(),
        };
        if let Some(&bad) = indices.iter().find(|&&i| i as usize >= raw.len()) {
            return Err(MeshError::Index { at: at(), index: bad, count: raw.len() });
        }
        let b = base as u32;
        let mut push = |t: [u32; 3]| soup.triangles.push([t[0] + b, t[1] + b, t[2] + b]);
        match mode {
            Mode::Triangles => indices.chunks_exact(3).for_each(|c| push([c[0], c[1], c[2]])),
            Mode::TriangleStrip => {
                for (k, w) in indices.windows(3).enumerate() {
                    // Odd triangles of a strip swap two corners to keep the winding.
                    push(if k % 2 == 0 { [w[0], w[1], w[2]] } else { [w[1], w[0], w[2]] });
                }
            }
            _ => {
                if let Some((&first, rest)) = indices.split_first() {
                    rest.windows(2).for_each(|w| push([first, w[0], w[1]]));
                }
            }
        }
        if soup.triangles.len() > MAX_TRIANGLES {
            return Err(MeshError::TooBig { what: "triangles", limit: MAX_TRIANGLES });
        }
    }
    Ok(())
}

/// Where in the file a problem is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Where {
    /// The node, as `node 'name' (#i)`.
    pub node: String,
    /// The mesh, as `mesh 'name' (#i)`.
    pub mesh: String,
    /// Index of the primitive within the mesh.
    pub primitive: usize,
}

impl core::fmt::Display for Where {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{}, {}, primitive {}", self.node, self.mesh, self.primitive)
    }
}

fn node_name(n: &gltf::Node<'_>) -> String {
    match n.name() {
        Some(s) => format!("node '{s}' (#{})", n.index()),
        None => format!("node #{}", n.index()),
    }
}

fn mesh_name(m: &gltf::Mesh<'_>) -> String {
    match m.name() {
        Some(s) => format!("mesh '{s}' (#{})", m.index()),
        None => format!("mesh #{}", m.index()),
    }
}

/// The bytes of element `k` of an accessor, bounds-checked: `(data, stride, element size)`.
fn accessor_bytes<'b>(
    acc: &gltf::Accessor<'_>,
    buffers: &'b [Vec<u8>],
    elem: usize,
) -> Result<(&'b [u8], usize), String> {
    if acc.sparse().is_some() {
        return Err("sparse accessors are not supported".into());
    }
    let view = acc.view().ok_or("the accessor has no buffer view")?;
    let buf = buffers.get(view.buffer().index()).ok_or("the buffer view names a missing buffer")?;
    let vstart = view.offset();
    let vend = vstart.checked_add(view.length()).ok_or("buffer view length overflows")?;
    let vdata = buf.get(vstart..vend).ok_or_else(|| {
        format!("buffer view {} (bytes {vstart}..{vend}) lies outside its buffer of {} bytes", view.index(), buf.len())
    })?;
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(format!("byte stride {stride} is smaller than the element size {elem}"));
    }
    let count = acc.count();
    if count == 0 {
        return Ok((&[], stride));
    }
    let end = (count - 1)
        .checked_mul(stride)
        .and_then(|v| v.checked_add(elem))
        .and_then(|v| v.checked_add(acc.offset()))
        .ok_or("accessor size overflows")?;
    let data = vdata.get(acc.offset()..end).ok_or_else(|| {
        format!("{count} elements at offset {} need {end} bytes but the buffer view has {}", acc.offset(), vdata.len())
    })?;
    Ok((data, stride))
}

fn read_vec3(acc: &gltf::Accessor<'_>, buffers: &[Vec<u8>]) -> Result<Vec<[f32; 3]>, String> {
    if acc.dimensions() != Dimensions::Vec3 || acc.data_type() != DataType::F32 {
        return Err(format!(
            "expected 32-bit float VEC3, found {:?} {:?} (quantised meshes are not supported)",
            acc.data_type(),
            acc.dimensions()
        ));
    }
    let (data, stride) = accessor_bytes(acc, buffers, 12)?;
    let count = acc.count();
    let mut out = Vec::with_capacity(count.min(data.len() / 12 + 1));
    for k in 0..count {
        let o = k * stride;
        let f = |i: usize| {
            data.get(o + 4 * i..o + 4 * i + 4)
                .and_then(|b| b.try_into().ok())
                .map(f32::from_le_bytes)
                .unwrap_or(f32::NAN)
        };
        out.push([f(0), f(1), f(2)]);
    }
    if out.iter().flatten().any(|v| !v.is_finite()) {
        return Err("holds a value that is not a finite number".into());
    }
    Ok(out)
}

fn read_indices(acc: &gltf::Accessor<'_>, buffers: &[Vec<u8>]) -> Result<Vec<u32>, String> {
    let size = match (acc.dimensions(), acc.data_type()) {
        (Dimensions::Scalar, DataType::U8) => 1,
        (Dimensions::Scalar, DataType::U16) => 2,
        (Dimensions::Scalar, DataType::U32) => 4,
        (d, t) => return Err(format!("expected unsigned 8, 16 or 32-bit SCALAR, found {t:?} {d:?}")),
    };
    let (data, stride) = accessor_bytes(acc, buffers, size)?;
    let count = acc.count();
    let mut out = Vec::with_capacity(count.min(data.len() / size + 1));
    for k in 0..count {
        let o = k * stride;
        let b = data.get(o..o + size).ok_or("index data ends early")?;
        out.push(match size {
            1 => b[0] as u32,
            2 => u16::from_le_bytes([b[0], b[1]]) as u32,
            _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        });
    }
    Ok(out)
}

const IDENTITY: [[f64; 4]; 4] =
    [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]];

fn to_f64(m: [[f32; 4]; 4]) -> [[f64; 4]; 4] {
    m.map(|c| c.map(f64::from))
}

/// Column-major product `a * b` (glTF stores matrices column by column).
fn mul(a: &[[f64; 4]; 4], b: &[[f64; 4]; 4]) -> [[f64; 4]; 4] {
    let mut out = [[0.0; 4]; 4];
    for (c, col) in out.iter_mut().enumerate() {
        for (r, v) in col.iter_mut().enumerate() {
            *v = (0..4).map(|k| a[k][r] * b[c][k]).sum();
        }
    }
    out
}

fn apply(m: &[[f64; 4]; 4], p: [f64; 3]) -> [f64; 3] {
    let mut out = [0.0; 3];
    for (r, v) in out.iter_mut().enumerate() {
        *v = m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + m[3][r];
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn column_major_product_composes_translation_after_scale() {
        // T(1,2,3) * S(2): a point is scaled first, then moved.
        let mut t = IDENTITY;
        t[3] = [1.0, 2.0, 3.0, 1.0];
        let mut s = IDENTITY;
        s[0][0] = 2.0;
        s[1][1] = 2.0;
        s[2][2] = 2.0;
        assert_eq!(apply(&mul(&t, &s), [1.0, 1.0, 1.0]), [3.0, 4.0, 5.0]);
        assert_eq!(apply(&mul(&s, &t), [1.0, 1.0, 1.0]), [4.0, 6.0, 8.0]);
    }
}
