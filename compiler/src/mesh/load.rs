//! glTF 2.0 to a triangle soup in page millimetres.
//!
//! The convention of `primitives.md`: glTF is +Y up and in metres, so a
//! vertex `(X, Y, Z)` (after its node's world transform) becomes page point
//! `(1000 X, 1000 Z)` mm with height `1000 Y` mm; +Z runs towards the bottom
//! of the page. With [`UpAxis::Z`] (terrains from GIS tools) the height is
//! `1000 Z` and the page point `(1000 X, −1000 Y)`: north stays up the page.
//!
//! Accessors are read here with bounds-checked code rather than through
//! `gltf`'s reader, whose slicing trusts offsets and counts that a hostile
//! file controls (its sparse iterator unwraps, and it reads positions as
//! f32 only). This reader takes every component type, normalised integers
//! (`KHR_mesh_quantization`) and sparse accessors. Compressed meshes are
//! recognised from `extensionsUsed`/`extensionsRequired` before any accessor
//! is read, so their refusal names the compression. A node with
//! `EXT_mesh_gpu_instancing` (trees and buildings of city models) places its
//! mesh once per instance, each instance's transform applied before the
//! node's.

use gltf::Document;
use gltf::accessor::{DataType, Dimensions};
use gltf::buffer::Source;
use gltf::mesh::Mode;

use super::error::{MeshError, Where};
use crate::options::UpAxis;

/// Largest number of triangles one file may contribute.
pub const MAX_TRIANGLES: usize = 20_000_000;
/// Largest coordinate magnitude of the placed model in millimetres (100 km):
/// what the surface stage takes. Farther models are refused unless `--fit`
/// recentres them (see `super::placed`).
pub const MAX_COORD_MM: f64 = 1.0e8;
/// Largest coordinate magnitude read from a file, in millimetres (10 million
/// km): beyond any coordinate on Earth (UTM, geocentric), and still with
/// micrometre steps in f64, so `--fit` can recentre such a model.
pub const MAX_MODEL_MM: f64 = 1.0e13;
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
    /// Every node with a mesh, with the footprint of its triangles.
    pub parts: Vec<Part>,
    /// Extent of the model along its own X, Y and Z axes (metres, after the
    /// node transforms), for the up-axis note.
    pub extent: [f64; 3],
    /// Primitives of points or lines left out (a relief is built from
    /// triangles).
    pub skipped: usize,
    /// The first of them, with its mode.
    pub first_skipped: Option<(Where, String)>,
    /// The height axis the vertices were read with.
    pub up: UpAxis,
    /// Whether that axis was chosen from the model's shape (no `--up`; see
    /// [`super::chosen_up`]) rather than given.
    pub up_chosen: bool,
}

/// One node's mesh and where it lies, for `--region #name`.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// The node's name (may be empty).
    pub node: String,
    /// The mesh's name (may be empty).
    pub mesh: String,
    /// Footprint `[xmin, ymin, xmax, ymax]` in page mm.
    pub bbox: [f64; 4],
}

/// Extensions that change how positions are stored, with what to do instead.
const COMPRESSIONS: [(&str, &str); 2] = [
    (
        "KHR_draco_mesh_compression",
        "export the model again without Draco (Blender: in the glTF 2.0 exporter untick \"Compression\")",
    ),
    ("EXT_meshopt_compression", "export the model again without meshopt (gltfpack: leave out -c and -cc)"),
];

/// Required extensions that do not touch positions (materials, textures,
/// lights): a relief can be built without understanding them.
const HARMLESS_PREFIXES: [&str; 6] =
    ["KHR_materials_", "KHR_texture_", "EXT_texture_", "KHR_lights_", "MSFT_texture_", "KHR_mesh_quantization"];

/// The instancing extension, which this reader applies ([`instances`]).
const INSTANCING: &str = "EXT_mesh_gpu_instancing";
/// Instances one node may place (a forest of a million trees).
const MAX_INSTANCES: usize = 1_000_000;

/// What `resolve` returns for an external buffer URI: its bytes, or a message.
pub type Resolver<'r> = dyn FnMut(&str) -> Result<Vec<u8>, String> + 'r;

/// Parses the glTF without the gltf crate's validation, refuses compressed
/// meshes by name, then validates, ignoring only extensions that do not
/// touch positions.
fn parse(bytes: &[u8]) -> Result<gltf::Gltf, MeshError> {
    use gltf::json::validation::{Error as VError, Validate};
    let gltf = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| MeshError::Parse(e.to_string()))?;
    let root = gltf.document.as_json();
    for ext in root.extensions_required.iter().chain(&root.extensions_used) {
        if let Some((name, help)) = COMPRESSIONS.iter().find(|(n, _)| n == ext) {
            return Err(MeshError::Compressed { extension: (*name).to_owned(), help: (*help).to_owned() });
        }
    }
    for ext in &root.extensions_required {
        if !HARMLESS_PREFIXES.iter().any(|p| ext.starts_with(p)) && ext != INSTANCING {
            return Err(MeshError::Extension(ext.clone()));
        }
    }
    // gltf-json's own validation indexes the POSITION accessor without a
    // bounds check (mesh.rs, primitive_validate_hook): check the indices first.
    let n = root.accessors.len();
    for (mi, mesh) in root.meshes.iter().enumerate() {
        for (pi, prim) in mesh.primitives.iter().enumerate() {
            let named = prim.attributes.values().chain(prim.indices.as_ref());
            if let Some(bad) = named.map(|a| a.value()).find(|&a| a >= n) {
                return Err(MeshError::Parse(format!(
                    "meshes[{mi}].primitives[{pi}] names accessor {bad}, but the file has {n} accessors"
                )));
            }
        }
    }
    let mut problems = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, e| {
        let path = path().to_string();
        if !(e == VError::Unsupported && path.starts_with("extensionsRequired")) {
            problems.push(format!("{path}: {e}"));
        }
    });
    if !problems.is_empty() {
        return Err(MeshError::Parse(format!("invalid glTF: {}", problems.join("; "))));
    }
    Ok(gltf)
}

/// Parses `bytes` (`.gltf` JSON or `.glb`) and collects the scene's
/// triangles with `up` as the height axis.
pub fn load_with(bytes: &[u8], resolve: &mut Resolver<'_>, up: UpAxis) -> Result<Soup, MeshError> {
    let gltf = parse(bytes)?;
    let buffers = load_buffers(&gltf.document, gltf.blob.clone(), resolve)?;
    let doc = &gltf.document;
    let scene = doc.default_scene().or_else(|| doc.scenes().next());
    let mut soup = Soup { scene_name: scene.as_ref().and_then(|s| s.name()).map(str::to_owned), up, ..Soup::default() };
    let mut model = [[f64::INFINITY; 3], [f64::NEG_INFINITY; 3]];
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
            let worlds = match instances(doc, &node, &buffers)? {
                Some(each) => each.iter().map(|m| mul(&world, m)).collect(),
                None => vec![world],
            };
            add_mesh(&mut soup, &node, &mesh, &worlds, &buffers, up, &mut model)?;
        }
        for c in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((c, world, depth + 1));
        }
    }
    if soup.triangles.is_empty() {
        return Err(match soup.first_skipped.take() {
            Some((at, mode)) => MeshError::Mode { at, mode },
            None => MeshError::EmptyScene,
        });
    }
    soup.extent = [0, 1, 2].map(|k| (model[1][k] - model[0][k]).max(0.0));
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
            Source::Uri(uri) => data_uri(uri).map_err(|message| MeshError::Buffer { index: b.index(), message })?,
            Source::Bin => blob.take().ok_or_else(|| MeshError::Buffer {
                index: b.index(),
                message: "refers to the binary chunk of a GLB file, and this file has none".into(),
            })?,
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

/// The bytes of a `data:` URI in base64 (RFC 2397), the only kind glTF
/// defines for buffers; padding may be left out.
fn data_uri(uri: &str) -> Result<Vec<u8>, String> {
    use base64::Engine;
    use base64::engine::{DecodePaddingMode, GeneralPurpose, GeneralPurposeConfig};
    const LENIENT: GeneralPurpose = GeneralPurpose::new(
        &base64::alphabet::STANDARD,
        GeneralPurposeConfig::new().with_decode_padding_mode(DecodePaddingMode::Indifferent),
    );
    let Some((_, text)) = uri.split_once(";base64,") else {
        return Err("is a data: URI that is not base64 (expected data:application/octet-stream;base64,...)".into());
    };
    LENIENT.decode(text.trim_end()).map_err(|e| format!("has a data: URI that is not valid base64: {e}"))
}

/// Adds `mesh`'s triangles placed by each of `worlds` (the node's world
/// transform, or one per instance): one part for the node.
fn add_mesh(
    soup: &mut Soup,
    node: &gltf::Node<'_>,
    mesh: &gltf::Mesh<'_>,
    worlds: &[[[f64; 4]; 4]],
    buffers: &[Vec<u8>],
    up: UpAxis,
    model: &mut [[f64; 3]; 2],
) -> Result<(), MeshError> {
    let mesh_name = mesh_name(mesh);
    soup.mesh_names.push(mesh.name().unwrap_or("").to_owned());
    let mut part_box = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
    for prim in mesh.primitives() {
        let at = || Where { node: node_name(node), mesh: mesh_name.clone(), primitive: prim.index() };
        let mode = prim.mode();
        if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
            // Loose edges and points (Blender's "Loose Edges", a road's
            // centre line in a city model) have no area to feel: left out,
            // and an error only when nothing else is left.
            soup.skipped += 1;
            if soup.first_skipped.is_none() {
                soup.first_skipped = Some((at(), format!("{mode:?}")));
            }
            continue;
        }
        let acc = prim.get(&gltf::Semantic::Positions).ok_or_else(|| MeshError::NoPositions { at: at() })?;
        let raw =
            read_vec3(&acc, buffers).map_err(|problem| MeshError::Accessor { at: at(), what: "POSITION", problem })?;
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
        for world in worlds {
            let base = soup.vertices.len();
            if base + raw.len() > u32::MAX as usize / 2 {
                return Err(MeshError::TooBig { what: "vertices", limit: u32::MAX as usize / 2 });
            }
            for p in &raw {
                let v = apply(world, *p);
                if v.iter().any(|c| !c.is_finite()) {
                    return Err(MeshError::NonFinite { node: at().node, mesh: at().mesh, what: "vertex position" });
                }
                let mm = match up {
                    UpAxis::Y => [v[0] * 1000.0, v[2] * 1000.0, v[1] * 1000.0],
                    UpAxis::Z => [v[0] * 1000.0, -v[1] * 1000.0, v[2] * 1000.0],
                };
                if mm.iter().any(|c| c.abs() > MAX_MODEL_MM) {
                    return Err(MeshError::Range { at: at() });
                }
                for k in 0..3 {
                    model[0][k] = model[0][k].min(v[k]);
                    model[1][k] = model[1][k].max(v[k]);
                }
                part_box =
                    [part_box[0].min(mm[0]), part_box[1].min(mm[1]), part_box[2].max(mm[0]), part_box[3].max(mm[1])];
                soup.vertices.push(mm);
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
    }
    if part_box.iter().all(|v| v.is_finite()) {
        soup.parts.push(Part {
            node: node.name().unwrap_or("").to_owned(),
            mesh: mesh.name().unwrap_or("").to_owned(),
            bbox: part_box,
        });
    }
    Ok(())
}

/// The instance transforms of a node with `EXT_mesh_gpu_instancing`, each
/// `T * R * S` from its `TRANSLATION`, `ROTATION` and `SCALE` (any of them
/// may be absent); `None` for a node without the extension.
fn instances(
    doc: &Document,
    node: &gltf::Node<'_>,
    buffers: &[Vec<u8>],
) -> Result<Option<Vec<[[f64; 4]; 4]>>, MeshError> {
    let Some(ext) = node.extension_value(INSTANCING) else { return Ok(None) };
    let bad = |problem: String| MeshError::Instancing { node: node_name(node), problem };
    let attributes = ext
        .get("attributes")
        .and_then(|a| a.as_object())
        .ok_or_else(|| bad("expected an object with \"attributes\" (TRANSLATION, ROTATION, SCALE)".into()))?;
    let read = |name: &str, dims: Dimensions| -> Result<Option<Vec<f64>>, MeshError> {
        let Some(v) = attributes.get(name) else { return Ok(None) };
        let acc = v
            .as_u64()
            .and_then(|i| doc.accessors().nth(i as usize))
            .ok_or_else(|| bad(format!("{name} names accessor {v}, which the file does not have")))?;
        let n = match dims {
            Dimensions::Vec4 => 4,
            _ => 3,
        };
        // Floats; rotations may be normalised 8 or 16-bit integers (the
        // extension's spec), and with KHR_mesh_quantization any of them 8 or
        // 16-bit integers, normalised or not.
        if acc.dimensions() != dims || acc.data_type() == DataType::U32 {
            let found = format!("{:?} {:?}", acc.data_type(), acc.dimensions());
            return Err(bad(format!("{name}: expected {dims:?} of floats or 8 or 16-bit integers, found {found}")));
        }
        let flat = read_accessor(&acc, buffers, n).map_err(|p| bad(format!("{name}: {p}")))?;
        if flat.iter().any(|v| !v.is_finite()) {
            return Err(bad(format!("{name} holds a value that is not a finite number")));
        }
        Ok(Some(flat))
    };
    let t = read("TRANSLATION", Dimensions::Vec3)?;
    let r = read("ROTATION", Dimensions::Vec4)?;
    let s = read("SCALE", Dimensions::Vec3)?;
    let counts = [(&t, 3), (&r, 4), (&s, 3)].map(|(v, n)| v.as_ref().map(|v| v.len() / n));
    let Some(count) = counts.iter().flatten().copied().max() else {
        return Err(bad("it has none of the attributes TRANSLATION, ROTATION and SCALE".into()));
    };
    if counts.iter().flatten().any(|&c| c != count) {
        let [t, r, s] = counts.map(|c| c.map_or("none".to_string(), |c| c.to_string()));
        return Err(bad(format!(
            "its attributes hold different numbers of instances (TRANSLATION {t}, ROTATION {r}, SCALE {s})"
        )));
    }
    if count > MAX_INSTANCES {
        return Err(MeshError::TooBig { what: "instances of one node", limit: MAX_INSTANCES });
    }
    let get = |v: &Option<Vec<f64>>, k: usize, n: usize, default: [f64; 4]| -> [f64; 4] {
        let mut out = default;
        if let Some(slot) = v.as_ref().and_then(|v| v.get(k * n..(k + 1) * n)) {
            out[..n].copy_from_slice(slot);
        }
        out
    };
    let mut each = Vec::with_capacity(count);
    for k in 0..count {
        let [tx, ty, tz, _] = get(&t, k, 3, [0.0; 4]);
        let [x, y, z, w] = get(&r, k, 4, [0.0, 0.0, 0.0, 1.0]);
        let [sx, sy, sz, _] = get(&s, k, 3, [1.0; 4]);
        let norm = (x * x + y * y + z * z + w * w).sqrt();
        if norm.is_nan() || norm <= 1e-6 {
            return Err(bad(format!("ROTATION of instance {k} is a zero quaternion")));
        }
        let (x, y, z, w) = (x / norm, y / norm, z / norm, w / norm);
        // Rotation rows of the unit quaternion (x, y, z, w).
        let rot = [
            [1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - z * w), 2.0 * (x * z + y * w)],
            [2.0 * (x * y + z * w), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - x * w)],
            [2.0 * (x * z - y * w), 2.0 * (y * z + x * w), 1.0 - 2.0 * (x * x + y * y)],
        ];
        // Column-major, as glTF: column c is rotation column c times scale c.
        let col = |c: usize, sc: f64| [rot[0][c] * sc, rot[1][c] * sc, rot[2][c] * sc, 0.0];
        each.push([col(0, sx), col(1, sy), col(2, sz), [tx, ty, tz, 1.0]]);
    }
    Ok(Some(each))
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

/// The bytes of `count` elements of `elem` bytes from buffer view `view`
/// starting at `offset`, bounds-checked: `(data, stride)`.
fn view_bytes<'b>(
    view: &gltf::buffer::View<'_>,
    buffers: &'b [Vec<u8>],
    offset: usize,
    count: usize,
    elem: usize,
    stride: Option<usize>,
) -> Result<(&'b [u8], usize), String> {
    let buf = buffers.get(view.buffer().index()).ok_or("the buffer view names a missing buffer")?;
    let vstart = view.offset();
    let vend = vstart.checked_add(view.length()).ok_or("buffer view length overflows")?;
    let vdata = buf.get(vstart..vend).ok_or_else(|| {
        format!("buffer view {} (bytes {vstart}..{vend}) lies outside its buffer of {} bytes", view.index(), buf.len())
    })?;
    let stride = stride.unwrap_or(elem);
    if stride < elem {
        return Err(format!("byte stride {stride} is smaller than the element size {elem}"));
    }
    if count == 0 {
        return Ok((&[], stride));
    }
    let end = (count - 1)
        .checked_mul(stride)
        .and_then(|v| v.checked_add(elem))
        .and_then(|v| v.checked_add(offset))
        .ok_or("accessor size overflows")?;
    let data = vdata.get(offset..end).ok_or_else(|| {
        format!(
            "{count} elements at offset {offset} need {end} bytes but buffer view {} has {}",
            view.index(),
            vdata.len()
        )
    })?;
    Ok((data, stride))
}

/// Size in bytes of one component.
fn component_size(t: DataType) -> usize {
    match t {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

/// Component `b` (exactly `component_size(t)` bytes) as a number,
/// normalised to -1..1 or 0..1 when `normalized` (glTF 2.0, 3.11).
fn component(t: DataType, b: &[u8], normalized: bool) -> f64 {
    let raw = match (t, b) {
        (DataType::I8, [x]) => *x as i8 as f64,
        (DataType::U8, [x]) => *x as f64,
        (DataType::I16, [x, y]) => i16::from_le_bytes([*x, *y]) as f64,
        (DataType::U16, [x, y]) => u16::from_le_bytes([*x, *y]) as f64,
        (DataType::U32, [x, y, z, w]) => u32::from_le_bytes([*x, *y, *z, *w]) as f64,
        (DataType::F32, [x, y, z, w]) => f32::from_le_bytes([*x, *y, *z, *w]) as f64,
        _ => f64::NAN,
    };
    if !normalized {
        return raw;
    }
    match t {
        DataType::I8 => (raw / 127.0).max(-1.0),
        DataType::U8 => raw / 255.0,
        DataType::I16 => (raw / 32767.0).max(-1.0),
        DataType::U16 => raw / 65535.0,
        _ => raw,
    }
}

/// Every element of an accessor as `n` numbers each (flattened), sparse
/// substitutions applied; `n` is the accessor's number of components.
fn read_accessor(acc: &gltf::Accessor<'_>, buffers: &[Vec<u8>], n: usize) -> Result<Vec<f64>, String> {
    let t = acc.data_type();
    let cs = component_size(t);
    let elem = n * cs;
    let count = acc.count();
    let norm = acc.normalized();
    let read = |data: &[u8], stride: usize, k: usize, out: &mut Vec<f64>| -> Result<(), String> {
        for c in 0..n {
            let o = k * stride + c * cs;
            let b = data.get(o..o + cs).ok_or("accessor data ends early")?;
            out.push(component(t, b, norm));
        }
        Ok(())
    };
    let mut out = Vec::with_capacity(count.saturating_mul(n).min(1 << 26));
    match acc.view() {
        Some(view) => {
            let (data, stride) = view_bytes(&view, buffers, acc.offset(), count, elem, view.stride())?;
            for k in 0..count {
                read(data, stride, k, &mut out)?;
            }
        }
        // Without a buffer view the elements are zeros (a sparse accessor's base).
        None if acc.sparse().is_some() => {
            if count > MAX_TRIANGLES.saturating_mul(3) {
                return Err(format!("{count} elements is more than the {} this reader takes", 3 * MAX_TRIANGLES));
            }
            out.resize(count * n, 0.0);
        }
        None => return Err("the accessor has no buffer view (a compressed mesh, or an empty accessor)".into()),
    }
    if let Some(sparse) = acc.sparse() {
        let m = sparse.count();
        if m > count {
            return Err(format!("the sparse part has {m} elements but the accessor only {count}"));
        }
        let iv = sparse.indices();
        let it = match iv.index_type() {
            gltf::accessor::sparse::IndexType::U8 => DataType::U8,
            gltf::accessor::sparse::IndexType::U16 => DataType::U16,
            gltf::accessor::sparse::IndexType::U32 => DataType::U32,
        };
        let isz = component_size(it);
        let (idata, _) =
            view_bytes(&iv.view(), buffers, iv.offset(), m, isz, None).map_err(|e| format!("sparse indices: {e}"))?;
        let vv = sparse.values();
        let (vdata, _) =
            view_bytes(&vv.view(), buffers, vv.offset(), m, elem, None).map_err(|e| format!("sparse values: {e}"))?;
        let mut last: Option<usize> = None;
        for s in 0..m {
            let ib = idata.get(s * isz..(s + 1) * isz).ok_or("sparse indices end early")?;
            let i = component(it, ib, false) as usize;
            if i >= count || last.is_some_and(|l| i <= l) {
                return Err(format!(
                    "sparse index {i} (entry {s}) is out of range or not increasing (the accessor has {count} elements)"
                ));
            }
            last = Some(i);
            let mut vals = Vec::with_capacity(n);
            read(vdata, elem, s, &mut vals)?;
            if let Some(slot) = out.get_mut(i * n..(i + 1) * n) {
                slot.copy_from_slice(&vals);
            }
        }
    }
    Ok(out)
}

/// POSITION: VEC3 of floats, or with `KHR_mesh_quantization` of (normalised
/// or plain) 8 or 16-bit integers.
fn read_vec3(acc: &gltf::Accessor<'_>, buffers: &[Vec<u8>]) -> Result<Vec<[f64; 3]>, String> {
    if acc.dimensions() != Dimensions::Vec3 || acc.data_type() == DataType::U32 {
        return Err(format!(
            "expected VEC3 of 32-bit floats or (KHR_mesh_quantization) 8 or 16-bit integers, found {:?} {:?}",
            acc.data_type(),
            acc.dimensions()
        ));
    }
    let flat = read_accessor(acc, buffers, 3)?;
    if flat.iter().any(|v| !v.is_finite()) {
        return Err("holds a value that is not a finite number".into());
    }
    Ok(flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
}

fn read_indices(acc: &gltf::Accessor<'_>, buffers: &[Vec<u8>]) -> Result<Vec<u32>, String> {
    match (acc.dimensions(), acc.data_type()) {
        (Dimensions::Scalar, DataType::U8 | DataType::U16 | DataType::U32) if !acc.normalized() => {}
        (d, t) => return Err(format!("expected unsigned 8, 16 or 32-bit SCALAR, found {t:?} {d:?}")),
    }
    Ok(read_accessor(acc, buffers, 1)?.into_iter().map(|v| v as u32).collect())
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
    fn data_uris_decode_with_or_without_padding() {
        for uri in ["data:application/octet-stream;base64,Zm8=", "data:application/gltf-buffer;base64,Zm8"] {
            assert_eq!(data_uri(uri).unwrap(), b"fo", "{uri}");
        }
        assert_eq!(data_uri("data:;base64,").unwrap(), b"");
        assert!(data_uri("data:,fo").unwrap_err().contains("not base64"));
        assert!(data_uri("data:;base64,Zm8*").unwrap_err().contains("not valid base64"));
    }

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
