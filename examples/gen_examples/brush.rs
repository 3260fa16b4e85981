//! Tactile Brush strokes (seed 001) for profile `brush-4x3`: the three strokes
//! of the usability evaluation (Fig. 7) and a curved stroke. A full-size
//! drawing is 189 x 126 mm with actuator (row r, column c) at (63 c, 63 r), so
//! grid lines run at x = 0, 63, 126, 189 and y = 0, 63, 126.

use crate::scene::Scene;

const L: f64 = 63.0;

/// The four brush scenes.
pub fn scenes() -> Vec<Scene> {
    vec![
        // From actuator (0,0) to actuator (2,3): it crosses the column lines at
        // (63, 42) and (126, 84) and the row line at (94.5, 63), three virtual
        // points between two physical ends.
        stroke(
            "brush-1-diagonal",
            "M 0,0 L 189,126",
            "duration: 1s, intensity: 1, freq: 200Hz",
            "Evaluation stroke 1: a diagonal from actuator (0,0) to actuator (2,3) with three virtual actuation points in the middle.",
        ),
        // Along row 1 from halfway between columns 0 and 1 to halfway between
        // columns 2 and 3: virtual (phantom) ends, physical actuators (1,1) and
        // (1,2) in between.
        stroke(
            "brush-2-horizontal",
            "M 31.5,63 L 157.5,63",
            "duration: 800ms, intensity: 0.8, freq: 150Hz",
            "Evaluation stroke 2: horizontal along row 1, starting and ending on virtual actuators halfway between tactors.",
        ),
        // From halfway along row 0's first gap to halfway along row 2's last
        // gap; every crossing, (63, 31.5), (94.5, 63) and (126, 94.5), lies
        // between actuators, so the stroke is made of virtual points only.
        stroke(
            "brush-3-virtual",
            "M 31.5,0 L 157.5,126",
            "duration: 1.2s, intensity: 0.9, freq: 270Hz",
            "Evaluation stroke 3: a diagonal made of virtual actuation points only.",
        ),
        // Beyond the published algorithm: a curve that starts and ends off the
        // grid lines.
        stroke(
            "brush-4-curve",
            "M 15,15 C 15,150 174,150 174,15",
            "duration: 2s, intensity: 1, freq: 200Hz",
            "A curved U stroke starting and ending off the grid lines (the published algorithm drew straight strokes only).",
        ),
    ]
}

fn stroke(name: &str, d: &str, params: &str, description: &str) -> Scene {
    // The tactors are drawn for the sighted author and marked `none` so they
    // are never rendered.
    let mut body = String::from("  <g id=\"tactors\" data-tactile=\"none\" fill=\"#dddddd\" stroke=\"#888888\">\n");
    for r in 0..3 {
        for c in 0..4 {
            body += &format!(
                "    <circle id=\"tactor-{r}-{c}\" cx=\"{}\" cy=\"{}\" r=\"5\"/>\n",
                c as f64 * L,
                r as f64 * L
            );
        }
    }
    body += "  </g>\n";
    body += &format!(
        "  <path id=\"stroke\" d=\"{d}\" fill=\"none\" stroke=\"#c0392b\" stroke-width=\"4\" stroke-linecap=\"round\" \
         data-tactile=\"brush({params})\"><title>{name}</title></path>\n"
    );
    Scene {
        name: name.into(),
        dir: "brush",
        profile: "brush-4x3",
        external: None,
        size: (3.0 * L, 2.0 * L),
        body: Some(body),
        visits: None,
        style: None,
        warnings: vec![],
        source: if name.ends_with("curve") {
            "Tactile Brush (seed 001), limitations: curves \"remain a topic for future research\".".into()
        } else {
            "Tactile Brush (seed 001), usability evaluation, Fig. 7.".into()
        },
        description: description.into(),
    }
}
