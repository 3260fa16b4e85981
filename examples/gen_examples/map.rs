//! The Tala map (`examples/map/`), drawn by hand: the annotated Inkscape
//! drawing and the plain-colour drawing with its style sheet. The generator
//! only indexes them and writes their traces, so the places visited here
//! repeat the drawings' coordinates (the examples test checks that the trace
//! passes over every layer, which catches a drawing that moved).

use crate::scene::{Scene, Visit};

/// The two map scenes.
pub fn scenes() -> Vec<Scene> {
    let map = Scene {
        name: "tala-map".into(),
        dir: "map",
        profile: "stress2",
        external: None,
        size: (110.0, 60.0),
        body: None,
        visits: Some(visits()),
        style: None,
        // T0407: the key's swatches (9 x 8 mm) and line are smaller than 2 cm,
        // which is right for a key: they are textures to match, not shapes.
        // T0120: the brushed road is for the Tactile Brush chair.
        warnings: vec!["T0120", "T0407"],
        source: "STRESS² (seed 000) section 5: \"vibrating political boundaries and regions colored with easily discriminable textures\".".into(),
        description: "A teacher's tactile map drawn in Inkscape with one layer per kind (`tactile: …` labels): vibrating coast and province borders, three provinces with gratings 3 mm apart in wavelength at 0°, 90° and 45°, town dots in cleared circles, and a braille key.".into(),
    };
    let plain = Scene {
        name: "tala-plain".into(),
        style: Some("map/tala-plain.toml"),
        // T0407 as for tala-map. Its towns are painted over its regions and
        // hide the textures under them, so they do not sum (no T0410).
        warnings: vec!["T0407"],
        description: "The same map drawn in plain colours by someone who never heard of taxel (regions touch their borders, towns sit on the regions and hide the textures under them, as on paper), built through the style sheet tala-plain.toml that maps its colours, ids and classes to tactile styles.".into(),
        ..map.clone()
    };
    // One source, more families: the same Inkscape file on the Tactile Brush
    // chair (its brushed road) and on two pin displays.
    let same_file = |name: &str, profile: &'static str, warnings: Vec<&'static str>, description: &str| Scene {
        name: name.into(),
        profile,
        external: Some(("map/tala-map.svg".into(), None)),
        visits: None,
        warnings,
        description: description.into(),
        ..map.clone()
    };
    let brush = same_file(
        "tala-map-brush",
        "brush-4x3",
        vec!["T0120"],
        "The same tala-map.svg on the Tactile Brush chair: only its brushed road plays there (the other layers are for \
         surfaces and are left out with T0120).",
    );
    let dotpad = same_file(
        "tala-map-dotpad",
        "dotpad",
        PINS_WARNINGS.to_vec(),
        "The same tala-map.svg legalised for the Dot Pad's 60 x 40 binary pins: pixel-art borders, ridge textures, \
         town clusters, braille on the pad's cell grid and the title on its text line.",
    );
    let graphiti = same_file(
        "tala-map-graphiti",
        "graphiti",
        PINS_WARNINGS.to_vec(),
        "The same tala-map.svg on the Graphiti: blinking borders standing at height 4 above textures at height 2.",
    );
    vec![map, plain, brush, dotpad, graphiti]
}

/// The same Inkscape file on paper and as a print (`docs/print.md`): one
/// scene per print profile. They come last in the index, after the finger
/// meshes, where they were first added.
pub fn print_scenes() -> Vec<Scene> {
    let map = scenes().swap_remove(0);
    // T0724: the key's swatches (9 x 8 mm) are smaller than a texture needs
    // on paper; on the 2.5 mm grid a key label also snaps onto the legend's
    // line (T0722). The brushed road is drawn as a line with an arrowhead, so no T0120.
    let print = |name: &str, profile: &'static str, warnings: Vec<&'static str>, description: &str| Scene {
        name: name.into(),
        profile,
        external: Some(("map/tala-map.svg".into(), None)),
        visits: None,
        warnings,
        description: description.into(),
        ..map.clone()
    };
    vec![
        print(
            "tala-map-swell",
            "swell-a4",
            vec!["T0724"],
            "The same tala-map.svg on A4 swell paper: a black vector PDF at true size, line textures that keep the \
             gratings' orientations, point symbols, NLS-size braille dots (docs/print.md).",
        ),
        print(
            "tala-map-tiger",
            "tiger-20dpi",
            vec!["T0724"],
            "The same tala-map.svg for a ViewPlus Tiger embosser: every mark on the 20-dpi grid, textures lower than \
             borders.",
        ),
        print(
            "tala-map-braille-grid",
            "emboss-braille-grid",
            vec!["T0722", "T0724"],
            "The same tala-map.svg for a braille embosser's graphics mode: dots on the 2.5 mm grid.",
        ),
        print(
            "tala-map-print3d",
            "print3d",
            vec!["T0724"],
            "The same tala-map.svg as a 3D-printed relief: a watertight binary STL on a 2 mm plate, borders and \
             braille 1 mm high, textures 0.5 mm.",
        ),
    ]
}

/// What the map's pin scenes are expected to warn (see examples/README.md):
/// the 110 x 60 mm map is only 44 x 24 pins at 2.5 mm, so the 3 mm grating is
/// finer than the pitch (T0705), a key swatch is too small for its texture
/// (T0707) and textures reach within a pin of towns and borders (T0703); the
/// road is a brush (T0120). (Two key labels sit next to their swatches, whose
/// texture they clear around them.)
const PINS_WARNINGS: &[&str] = &["T0120", "T0703", "T0705", "T0707"];

fn visits() -> Vec<Visit> {
    let coast = vec![
        (6.0, 7.0),
        (30.0, 2.0),
        (52.0, 4.5),
        (68.0, 14.0),
        (69.0, 41.0),
        (56.0, 57.0),
        (28.0, 58.0),
        (8.0, 50.5),
        (3.0, 29.0),
    ];
    let mut v = vec![
        Visit::Outline(coast),
        Visit::Path(vec![(30.0, 2.0), (36.0, 31.0)]),
        Visit::Path(vec![(3.0, 29.0), (36.0, 31.0), (69.0, 41.0)]),
        Visit::Area { centre: (19.0, 18.0), reach: 8.0 },
        Visit::Area { centre: (52.0, 22.0), reach: 10.0 },
        Visit::Area { centre: (35.0, 45.0), reach: 12.0 },
        Visit::Point((17.0, 18.0)),
        Visit::Point((52.0, 22.0)),
        Visit::Point((30.0, 45.0)),
        Visit::Path(vec![(73.0, 6.0), (82.0, 6.0)]),
    ];
    for y in [18.0, 30.0, 42.0] {
        v.push(Visit::Area { centre: (77.5, y), reach: 4.0 });
    }
    v.push(Visit::Point((77.5, 54.0)));
    // Reading each braille label left to right along its cells.
    for y in [6.0, 18.0, 30.0, 42.0, 54.0] {
        v.push(Visit::Path(vec![(86.0, y), (108.0, y)]));
    }
    v
}
