//! The finger device's five test shapes (seed 002): glTF height meshes and
//! touch-screen traces written into `examples/finger/` by their own generator
//! (`cargo run --example gen_finger_meshes`). This generator only indexes them
//! (the `.gltf` of each; the `.glb` beside it is the same mesh in binary).

use crate::scene::Scene;

/// The five finger scenes.
pub fn scenes() -> Vec<Scene> {
    [
        ("edge", "an edge (a step)"),
        ("flat", "a flat surface"),
        ("inclined", "an inclined surface"),
        ("convex", "a convex quadric surface"),
        ("concave", "a concave quadric surface"),
    ]
    .into_iter()
    .map(|(shape, what)| Scene {
        name: format!("finger-{shape}"),
        dir: "finger",
        profile: "finger3",
        external: Some((format!("finger/{shape}.gltf"), Some(format!("finger/{shape}.trace.csv")))),
        size: (160.0, 100.0),
        body: None,
        visits: None,
        style: None,
        warnings: vec![],
        source: "Finger-mounted vibrotactile device (seed 002), the five test shapes.".into(),
        description: format!(
            "A height mesh of {what}, swept left to right on a touch screen: height and the local gradient along the motion drive the Left, Down and Right actuators."
        ),
    })
    .collect()
}
