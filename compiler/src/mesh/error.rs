//! What can stop a mesh from compiling.

use crate::diagnostic::number;

/// A problem that prevents a height field from being built. Messages name
/// the node, mesh and primitive where they can; the caller names the file.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshError {
    /// The bytes are not glTF 2.0 (JSON or binary), or fail its validation.
    Parse(String),
    /// A buffer could not be loaded.
    Buffer {
        /// The buffer's index.
        index: usize,
        /// Why.
        message: String,
    },
    /// The node graph is not a tree.
    Graph {
        /// The node.
        node: String,
        /// What is wrong.
        problem: &'static str,
    },
    /// A primitive is points or lines.
    Mode {
        /// Where.
        at: Where,
        /// The mode found.
        mode: String,
    },
    /// A primitive has no `POSITION` attribute.
    NoPositions {
        /// Where.
        at: Where,
    },
    /// An accessor cannot be read.
    Accessor {
        /// Where.
        at: Where,
        /// Which accessor (`POSITION`, `indices`).
        what: &'static str,
        /// What is wrong.
        problem: String,
    },
    /// A node's `EXT_mesh_gpu_instancing` cannot be read.
    Instancing {
        /// The node.
        node: String,
        /// What is wrong.
        problem: String,
    },
    /// An index points past the end of the vertices.
    Index {
        /// Where.
        at: Where,
        /// The bad index.
        index: u32,
        /// Number of vertices.
        count: usize,
    },
    /// A transform or position is not finite.
    NonFinite {
        /// The node.
        node: String,
        /// The mesh (empty for a node's transform).
        mesh: String,
        /// What.
        what: &'static str,
    },
    /// A vertex lies more than 10 million km from the origin.
    Range {
        /// Where.
        at: Where,
    },
    /// A vertex of the placed model lies more than 100 km from the origin
    /// (raw UTM coordinates without `--fit`).
    Far {
        /// The part it is in, or "the model".
        part: String,
        /// The footprint `[xmin, ymin, xmax, ymax]`, in model units (metres).
        footprint: [f64; 4],
        /// The model's extent along its X, Y and Z axes, metres.
        extent: [f64; 3],
    },
    /// The scene has no triangles.
    EmptyScene,
    /// Every triangle is vertical or degenerate: nothing covers the page.
    NoArea,
    /// Too much of something.
    TooBig {
        /// What.
        what: &'static str,
        /// The limit.
        limit: usize,
    },
    /// The requested field is larger than a bundle may hold.
    FieldTooLarge {
        /// Nodes per row that were asked for.
        cols: u64,
        /// Rows that were asked for.
        rows: u64,
        /// The resolution asked for, in nodes per mm.
        per_mm: f64,
        /// The finest resolution that would fit, in nodes per mm.
        max_per_mm: f64,
    },
    /// A resolution that is not a positive finite number.
    BadResolution(f64),
    /// The triangulation failed (a bug, or a mesh spade cannot handle).
    Triangulation(String),
    /// The file's meshes are compressed (Draco, meshopt).
    Compressed {
        /// The extension, as the file names it.
        extension: String,
        /// How to export the model without it.
        help: String,
    },
    /// The file requires an extension that changes geometry and that this reader does not know.
    Extension(String),
    /// `--region` names nothing, or keeps nothing of the model.
    Region(String),
    /// A height factor that is not a positive finite number.
    BadExaggeration(f64),
}

impl core::fmt::Display for MeshError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            MeshError::Parse(m) => write!(f, "not a valid glTF 2.0 file: {m}"),
            MeshError::Buffer { index, message } => write!(f, "buffer {index}: {message}"),
            MeshError::Graph { node, problem } => write!(f, "{node} {problem}"),
            MeshError::Mode { at, mode } => {
                write!(
                    f,
                    "{at}: mode {mode} is not supported (expected triangles, a triangle strip or a fan), and the \
                     scene has no triangles"
                )
            }
            MeshError::NoPositions { at } => write!(f, "{at}: no POSITION attribute"),
            MeshError::Accessor { at, what, problem } => write!(f, "{at}: {what} accessor: {problem}"),
            MeshError::Index { at, index, count } => {
                write!(f, "{at}: index {index} is out of range (the primitive has {count} vertices)")
            }
            MeshError::Instancing { node, problem } => write!(f, "{node}: EXT_mesh_gpu_instancing: {problem}"),
            MeshError::NonFinite { node, mesh, what } if mesh.is_empty() => {
                write!(f, "{node}: the {what} is not finite")
            }
            MeshError::NonFinite { node, mesh, what } => write!(f, "{node}, {mesh}: a {what} is not finite"),
            MeshError::Range { at } => write!(f, "{at}: a vertex lies more than 10 million km from the origin"),
            MeshError::Far { part, footprint: b, .. } => write!(
                f,
                "{part}: a vertex lies more than 100 km from the origin (the footprint is x {}..{}, y {}..{} in model units)",
                number(b[0], 3),
                number(b[2], 3),
                number(b[1], 3),
                number(b[3], 3)
            ),
            MeshError::EmptyScene => write!(f, "the scene has no triangles (no node with a triangle mesh)"),
            MeshError::NoArea => {
                write!(f, "no triangle covers any area of the page (all are vertical or degenerate seen from +Y)")
            }
            MeshError::TooBig { what, limit } => write!(f, "too many {what} (the limit is {limit})"),
            MeshError::FieldTooLarge { cols, rows, per_mm, max_per_mm } => write!(
                f,
                "a height field of {cols} x {rows} nodes at {per_mm} nodes per mm exceeds the limit of \
                 {} nodes per side and {} nodes; use a resolution of at most {max_per_mm:.6} nodes per mm",
                taxel_format::MAX_FIELD_SIDE,
                taxel_format::MAX_FIELD_NODES
            ),
            MeshError::BadResolution(r) => write!(f, "resolution {r} is not a positive finite number of nodes per mm"),
            MeshError::Triangulation(m) => write!(f, "triangulating the mesh failed: {m}"),
            MeshError::Compressed { extension, help } => {
                write!(f, "the meshes are compressed with {extension}, which taxel cannot decode; {help}")
            }
            MeshError::Extension(e) => {
                write!(f, "the file requires the extension {e}, which taxel cannot read; export the model without it")
            }
            MeshError::Region(m) => write!(f, "--region: {m}"),
            MeshError::BadExaggeration(v) => write!(f, "--exaggerate {v} is not a positive finite factor"),
        }
    }
}

impl std::error::Error for MeshError {}

impl MeshError {
    /// The diagnostic code (documented in docs/finger.md).
    pub fn code(&self) -> &'static str {
        match self {
            MeshError::Parse(_) | MeshError::Buffer { .. } | MeshError::Extension(_) => "T0601",
            MeshError::Graph { .. } | MeshError::EmptyScene => "T0602",
            MeshError::Mode { .. } => "T0603",
            MeshError::NoPositions { .. }
            | MeshError::Accessor { .. }
            | MeshError::Index { .. }
            | MeshError::Instancing { .. } => "T0604",
            MeshError::NonFinite { .. } | MeshError::Range { .. } | MeshError::Far { .. } => "T0605",
            MeshError::NoArea => "T0606",
            MeshError::TooBig { .. }
            | MeshError::FieldTooLarge { .. }
            | MeshError::BadResolution(_)
            | MeshError::BadExaggeration(_) => "T0607",
            MeshError::Triangulation(_) => "T0608",
            MeshError::Compressed { .. } => "T0614",
            MeshError::Region(_) => "T0615",
        }
    }

    /// The node, mesh and primitive the error is about, if any.
    pub fn element(&self) -> Option<String> {
        match self {
            MeshError::Mode { at, .. }
            | MeshError::NoPositions { at }
            | MeshError::Accessor { at, .. }
            | MeshError::Index { at, .. }
            | MeshError::Range { at } => Some(at.to_string()),
            MeshError::Graph { node, .. } => Some(node.clone()),
            MeshError::NonFinite { node, mesh, .. } if mesh.is_empty() => Some(node.clone()),
            MeshError::NonFinite { node, mesh, .. } => Some(format!("{node}, {mesh}")),
            MeshError::Far { part, .. } => Some(part.clone()),
            _ => None,
        }
    }
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
