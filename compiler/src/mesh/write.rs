//! A minimal glTF 2.0 writer for height meshes: one node, one mesh, one
//! triangle primitive. The example generator and the tests use it to make
//! `.glb` files, `.gltf` files with an embedded (data URI) buffer, and
//! `.gltf` files with an external `.bin`. Output is deterministic.
//!
//! [`Builder`] writes anything else the tests need (many nodes and meshes,
//! quantised or sparse accessors, strips, extensions) from pieces of JSON.

/// An indexed triangle mesh in glTF coordinates (metres, +Y up).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct HeightMesh {
    /// Vertex positions `[X, Y, Z]` in metres.
    pub positions: Vec<[f32; 3]>,
    /// Triangle corner indices, three per triangle.
    pub indices: Vec<u32>,
    /// The mesh (and node) name.
    pub name: String,
    /// An optional node translation in metres.
    pub translation: Option<[f32; 3]>,
}

impl HeightMesh {
    /// A regular grid of `nu x nv` quads: `f(u, v)` gives the position of
    /// grid point `(u, v)` for `u, v` in `0..=1`. Each quad is split along
    /// its main diagonal.
    pub fn grid(nu: u32, nv: u32, f: impl Fn(f64, f64) -> [f64; 3]) -> HeightMesh {
        let mut m = HeightMesh { name: "grid".into(), ..HeightMesh::default() };
        for j in 0..=nv {
            for i in 0..=nu {
                let p = f(i as f64 / nu.max(1) as f64, j as f64 / nv.max(1) as f64);
                m.positions.push([p[0] as f32, p[1] as f32, p[2] as f32]);
            }
        }
        let at = |i: u32, j: u32| j * (nu + 1) + i;
        for j in 0..nv {
            for i in 0..nu {
                m.indices.extend([at(i, j), at(i, j + 1), at(i + 1, j + 1)]);
                m.indices.extend([at(i, j), at(i + 1, j + 1), at(i + 1, j)]);
            }
        }
        m
    }

    /// Appends another mesh's triangles (its indices shifted).
    pub fn append(&mut self, other: &HeightMesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.indices.extend(other.indices.iter().map(|i| i + base));
    }

    /// The binary buffer: positions (f32 x 3) then indices (u32).
    pub fn buffer(&self) -> Vec<u8> {
        let mut b = Vec::with_capacity(12 * self.positions.len() + 4 * self.indices.len());
        for p in &self.positions {
            for c in p {
                b.extend_from_slice(&c.to_le_bytes());
            }
        }
        for i in &self.indices {
            b.extend_from_slice(&i.to_le_bytes());
        }
        b
    }

    /// The JSON document; `uri` is the buffer's URI (`None` for a GLB's own chunk).
    pub fn json(&self, uri: Option<&str>) -> String {
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for p in &self.positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if self.positions.is_empty() {
            (lo, hi) = ([0.0; 3], [0.0; 3]);
        }
        let pos_len = 12 * self.positions.len();
        let idx_len = 4 * self.indices.len();
        let uri = uri.map(|u| format!(",\"uri\":\"{u}\"")).unwrap_or_default();
        let translation =
            self.translation.map(|t| format!(",\"translation\":[{},{},{}]", t[0], t[1], t[2])).unwrap_or_default();
        let name = self.name.replace(['"', '\\'], "_");
        format!(
            concat!(
                "{{\"asset\":{{\"version\":\"2.0\",\"generator\":\"taxel mesh writer\"}},",
                "\"scene\":0,\"scenes\":[{{\"name\":\"{name}\",\"nodes\":[0]}}],",
                "\"nodes\":[{{\"name\":\"{name}\",\"mesh\":0{translation}}}],",
                "\"meshes\":[{{\"name\":\"{name}\",\"primitives\":[{{\"attributes\":{{\"POSITION\":0}},\"indices\":1,\"mode\":4}}]}}],",
                "\"accessors\":[",
                "{{\"bufferView\":0,\"componentType\":5126,\"count\":{pc},\"type\":\"VEC3\",",
                "\"min\":[{l0},{l1},{l2}],\"max\":[{h0},{h1},{h2}]}},",
                "{{\"bufferView\":1,\"componentType\":5125,\"count\":{ic},\"type\":\"SCALAR\"}}],",
                "\"bufferViews\":[{{\"buffer\":0,\"byteOffset\":0,\"byteLength\":{pos_len},\"target\":34962}},",
                "{{\"buffer\":0,\"byteOffset\":{pos_len},\"byteLength\":{idx_len},\"target\":34963}}],",
                "\"buffers\":[{{\"byteLength\":{total}{uri}}}]}}"
            ),
            name = name,
            translation = translation,
            pc = self.positions.len(),
            l0 = lo[0],
            l1 = lo[1],
            l2 = lo[2],
            h0 = hi[0],
            h1 = hi[1],
            h2 = hi[2],
            ic = self.indices.len(),
            pos_len = pos_len,
            idx_len = idx_len,
            total = pos_len + idx_len,
            uri = uri,
        )
    }

    /// A binary glTF (`.glb`).
    pub fn to_glb(&self) -> Vec<u8> {
        glb(&self.json(None), &self.buffer())
    }

    /// A `.gltf` with the buffer embedded as a base64 data URI.
    pub fn to_gltf_embedded(&self) -> String {
        let uri = format!("data:application/octet-stream;base64,{}", base64(&self.buffer()));
        self.json(Some(&uri))
    }

    /// A `.gltf` referring to an external buffer file `bin_name`, and that file's bytes.
    pub fn to_gltf_external(&self, bin_name: &str) -> (String, Vec<u8>) {
        (self.json(Some(bin_name)), self.buffer())
    }
}

/// A binary glTF container of `json` and the buffer `bin`.
fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut json = json.as_bytes().to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

/// A glTF document assembled from parts: one binary buffer, buffer views,
/// accessors, meshes and nodes given as JSON objects, one scene.
#[derive(Debug, Clone, Default)]
pub struct Builder {
    buffer: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
    meshes: Vec<String>,
    nodes: Vec<String>,
    /// Names for `extensionsUsed`.
    pub extensions_used: Vec<String>,
    /// Names for `extensionsRequired`.
    pub extensions_required: Vec<String>,
}

impl Builder {
    /// Appends `bytes` (4-byte aligned) as a buffer view; returns its index.
    pub fn view(&mut self, bytes: &[u8], stride: Option<usize>) -> usize {
        while !self.buffer.len().is_multiple_of(4) {
            self.buffer.push(0);
        }
        let stride = stride.map(|s| format!(",\"byteStride\":{s}")).unwrap_or_default();
        self.views.push(format!(
            "{{\"buffer\":0,\"byteOffset\":{},\"byteLength\":{}{stride}}}",
            self.buffer.len(),
            bytes.len()
        ));
        self.buffer.extend_from_slice(bytes);
        self.views.len() - 1
    }

    /// Adds an accessor given as a JSON object; returns its index.
    pub fn accessor(&mut self, json: String) -> usize {
        self.accessors.push(json);
        self.accessors.len() - 1
    }

    /// Float VEC3 positions with their bounds; returns the accessor index.
    pub fn positions(&mut self, p: &[[f32; 3]]) -> usize {
        let bytes: Vec<u8> = p.iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
        let v = self.view(&bytes, None);
        let (lo, hi) = bounds(p);
        self.accessor(format!(
            "{{\"bufferView\":{v},\"componentType\":5126,\"count\":{},\"type\":\"VEC3\",\"min\":{lo},\"max\":{hi}}}",
            p.len()
        ))
    }

    /// Unsigned 32-bit indices; returns the accessor index.
    pub fn indices(&mut self, i: &[u32]) -> usize {
        let bytes: Vec<u8> = i.iter().flat_map(|c| c.to_le_bytes()).collect();
        let v = self.view(&bytes, None);
        self.accessor(format!(
            "{{\"bufferView\":{v},\"componentType\":5125,\"count\":{},\"type\":\"SCALAR\"}}",
            i.len()
        ))
    }

    /// Adds a mesh of the given primitive JSON objects; returns its index.
    pub fn mesh(&mut self, name: &str, primitives: &[String]) -> usize {
        self.meshes.push(format!("{{\"name\":\"{name}\",\"primitives\":[{}]}}", primitives.join(",")));
        self.meshes.len() - 1
    }

    /// Adds a node given as a JSON object; returns its index.
    pub fn node(&mut self, json: String) -> usize {
        self.nodes.push(json);
        self.nodes.len() - 1
    }

    /// Adds `m` as its own mesh (float positions, u32 triangles) and a node
    /// named like it with `extra` node properties (`,"translation":[...]`);
    /// returns the node index.
    pub fn height_mesh(&mut self, m: &HeightMesh, extra: &str) -> usize {
        let p = self.positions(&m.positions);
        let i = self.indices(&m.indices);
        let name = m.name.replace(['"', '\\'], "_");
        let mesh = self.mesh(&name, &[format!("{{\"attributes\":{{\"POSITION\":{p}}},\"indices\":{i}}}")]);
        self.node(format!("{{\"name\":\"{name}\",\"mesh\":{mesh}{extra}}}"))
    }

    /// The document's JSON with `roots` as the scene's nodes and the buffer at `uri` (`None` in a GLB).
    pub fn json(&self, roots: &[usize], uri: Option<&str>) -> String {
        let list = |v: &[String]| v.join(",");
        let names = |v: &[String]| v.iter().map(|e| format!("\"{e}\"")).collect::<Vec<_>>().join(",");
        let mut ext = String::new();
        if !self.extensions_used.is_empty() {
            ext += &format!(",\"extensionsUsed\":[{}]", names(&self.extensions_used));
        }
        if !self.extensions_required.is_empty() {
            ext += &format!(",\"extensionsRequired\":[{}]", names(&self.extensions_required));
        }
        let roots: Vec<String> = roots.iter().map(usize::to_string).collect();
        let uri = uri.map(|u| format!(",\"uri\":\"{u}\"")).unwrap_or_default();
        format!(
            concat!(
                "{{\"asset\":{{\"version\":\"2.0\",\"generator\":\"taxel mesh writer\"}}{ext},",
                "\"scene\":0,\"scenes\":[{{\"nodes\":[{roots}]}}],\"nodes\":[{nodes}],\"meshes\":[{meshes}],",
                "\"accessors\":[{accessors}],\"bufferViews\":[{views}],",
                "\"buffers\":[{{\"byteLength\":{len}{uri}}}]}}"
            ),
            ext = ext,
            roots = roots.join(","),
            nodes = list(&self.nodes),
            meshes = list(&self.meshes),
            accessors = list(&self.accessors),
            views = list(&self.views),
            len = self.buffer.len(),
            uri = uri,
        )
    }

    /// A binary glTF with `roots` as the scene's nodes.
    pub fn to_glb(&self, roots: &[usize]) -> Vec<u8> {
        glb(&self.json(roots, None), &self.buffer)
    }

    /// A `.gltf` with the buffer embedded as a data URI.
    pub fn to_gltf_embedded(&self, roots: &[usize]) -> String {
        let uri = format!("data:application/octet-stream;base64,{}", base64(&self.buffer));
        self.json(roots, Some(&uri))
    }
}

/// JSON arrays of the per-axis minimum and maximum of `p`.
fn bounds(p: &[[f32; 3]]) -> (String, String) {
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for v in p {
        for k in 0..3 {
            lo[k] = lo[k].min(v[k]);
            hi[k] = hi[k].max(v[k]);
        }
    }
    if p.is_empty() {
        (lo, hi) = ([0.0; 3], [0.0; 3]);
    }
    (format!("[{},{},{}]", lo[0], lo[1], lo[2]), format!("[{},{},{}]", hi[0], hi[1], hi[2]))
}

/// Standard base64 with padding (RFC 4648), for data URIs.
fn base64(data: &[u8]) -> String {
    use base64::Engine;
    base64::engine::general_purpose::STANDARD.encode(data)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc4648_vectors() {
        for (i, o) in [("", ""), ("f", "Zg=="), ("fo", "Zm8="), ("foo", "Zm9v"), ("foobar", "Zm9vYmFy")] {
            assert_eq!(base64(i.as_bytes()), o);
        }
    }
}
