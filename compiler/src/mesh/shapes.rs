//! The five test shapes of seed 002 (Fig. 5): edge, flat, inclined, convex
//! and concave quadric surfaces, as exact analytic surfaces and as closed
//! glTF solids. The example generator writes them to `examples/finger/`;
//! tests compare the compiled height fields with the exact values here.
//!
//! Every shape covers page x 20..140 mm, y 20..80 mm, sits on a base at
//! height 0 (sides and bottom included, as a modelling tool would export a
//! solid), and has its top between 5 and 35 mm.

use super::write::HeightMesh;

/// Footprint `[xmin, ymin, xmax, ymax]` of every shape, page mm.
pub const FOOTPRINT: [f64; 4] = [20.0, 20.0, 140.0, 80.0];
/// The page row the example sweeps follow.
pub const SWEEP_Y: f64 = 50.0;
/// Page x of the edge shape's step.
pub const STEP_X: f64 = 80.0;

/// One of the paper's shapes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Shape {
    /// A step up from 5 mm to 15 mm at x = 80 mm (a vertical wall).
    Edge,
    /// A level surface at 10 mm.
    Flat,
    /// A plane declining from left (20 mm) to right (5 mm).
    Inclined,
    /// An elliptic paraboloid cap, highest (35 mm) in the middle.
    Convex,
    /// An elliptic paraboloid bowl, lowest (5 mm) in the middle.
    Concave,
}

impl Shape {
    /// All five, in the paper's order.
    pub const ALL: [Shape; 5] = [Shape::Edge, Shape::Flat, Shape::Inclined, Shape::Convex, Shape::Concave];

    /// File stem.
    pub fn name(self) -> &'static str {
        match self {
            Shape::Edge => "edge",
            Shape::Flat => "flat",
            Shape::Inclined => "inclined",
            Shape::Convex => "convex",
            Shape::Concave => "concave",
        }
    }

    /// Normalised coordinates: u in -1..1 across x, v in -1..1 across y.
    fn uv(x: f64, y: f64) -> (f64, f64) {
        ((x - 80.0) / 60.0, (y - 50.0) / 30.0)
    }

    /// Exact height (mm) of the top surface at page `(x, y)`; `None` outside
    /// the footprint. On the step itself the top (15 mm) counts.
    pub fn height(self, x: f64, y: f64) -> Option<f64> {
        let [x0, y0, x1, y1] = FOOTPRINT;
        if !(x0..=x1).contains(&x) || !(y0..=y1).contains(&y) {
            return None;
        }
        let (u, v) = Self::uv(x, y);
        Some(match self {
            Shape::Edge => {
                if x >= STEP_X {
                    15.0
                } else {
                    5.0
                }
            }
            Shape::Flat => 10.0,
            Shape::Inclined => 5.0 + 15.0 * (x1 - x) / (x1 - x0),
            Shape::Convex => 35.0 - 20.0 * u * u - 10.0 * v * v,
            Shape::Concave => 5.0 + 20.0 * u * u + 10.0 * v * v,
        })
    }

    /// Exact gradient `(∂h/∂x, ∂h/∂y)`; `None` outside and on the step.
    pub fn gradient(self, x: f64, y: f64) -> Option<(f64, f64)> {
        self.height(x, y)?;
        let (u, v) = Self::uv(x, y);
        // du/dx = 1/60, dv/dy = 1/30.
        Some(match self {
            Shape::Edge if x == STEP_X => return None,
            Shape::Edge | Shape::Flat => (0.0, 0.0),
            Shape::Inclined => (-15.0 / 120.0, 0.0),
            Shape::Convex => (-40.0 * u / 60.0, -20.0 * v / 30.0),
            Shape::Concave => (40.0 * u / 60.0, 20.0 * v / 30.0),
        })
    }

    /// Largest second derivative of the height in any direction, 1/mm
    /// (the curvature bound M the error bounds of docs/finger.md use).
    pub fn curvature_bound(self) -> f64 {
        match self {
            Shape::Edge | Shape::Flat | Shape::Inclined => 0.0,
            // h_xx = 40/3600, h_yy = 20/900, h_xy = 0.
            Shape::Convex | Shape::Concave => 20.0 / 900.0,
        }
    }

    /// Quads per side of the top surface grid (x, y); 2 mm squares for the curved shapes.
    pub fn grid(self) -> (u32, u32) {
        match self {
            Shape::Convex | Shape::Concave => (60, 30),
            _ => (12, 6),
        }
    }

    /// The shape as a closed solid in glTF coordinates (metres, +Y up).
    pub fn mesh(self) -> HeightMesh {
        let [x0, y0, x1, y1] = FOOTPRINT;
        let (nu, nv) = self.grid();
        let mut m = HeightMesh { name: self.name().into(), ..HeightMesh::default() };
        let top = |xa: f64, xb: f64, nu: u32, h: &dyn Fn(f64, f64) -> f64| {
            HeightMesh::grid(nu, nv, |s, t| {
                let (x, y) = (xa + s * (xb - xa), y0 + t * (y1 - y0));
                mm_to_gltf(x, y, h(x, y))
            })
        };
        let exact = |x: f64, y: f64| self.height(x, y).unwrap_or(0.0);
        match self {
            Shape::Edge => {
                // Two terraces and the wall between them.
                m.append(&top(x0, STEP_X, nu / 2, &|_, _| 5.0));
                m.append(&top(STEP_X, x1, nu / 2, &|_, _| 15.0));
                m.append(&wall([STEP_X, y0], [STEP_X, y1], nv, &|_, _| 5.0, &|_, _| 15.0));
            }
            _ => m.append(&top(x0, x1, nu, &exact)),
        }
        // Sides down to the base, and the bottom.
        let corners = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]];
        for k in 0..4 {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            let n = if a[0] == b[0] { nv } else { nu };
            m.append(&wall(a, b, n, &|_, _| 0.0, &exact));
        }
        m.append(&HeightMesh::grid(1, 1, |s, t| mm_to_gltf(x0 + s * (x1 - x0), y0 + t * (y1 - y0), 0.0)));
        m
    }
}

/// Page millimetres and height to glTF metres: X = x, Y = h, Z = y.
pub fn mm_to_gltf(x: f64, y: f64, h: f64) -> [f64; 3] {
    [x / 1000.0, h / 1000.0, y / 1000.0]
}

/// A vertical wall over the page segment `a..b` in `n` panels, from height `lo` to `hi`.
fn wall(a: [f64; 2], b: [f64; 2], n: u32, lo: &dyn Fn(f64, f64) -> f64, hi: &dyn Fn(f64, f64) -> f64) -> HeightMesh {
    HeightMesh::grid(n, 1, |s, t| {
        let (x, y) = (a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]));
        let h = lo(x, y) + t * (hi(x, y) - lo(x, y));
        mm_to_gltf(x, y, h)
    })
}
