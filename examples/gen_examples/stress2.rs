//! The STRESS² stimuli (seed 000, section 4), laid out for the 110 x 60 mm
//! surface of profile `stress2`. Each scene is one sheet a subject could be
//! given; where the paper showed one stimulus per trial, several are put on a
//! sheet only when they fit with room between them.

use crate::scene::{Scene, Visit};
use crate::shapes::{Kind, Shape, n};

const W: f64 = 110.0;
const H: f64 = 60.0;

/// The three rendering methods of experiment 1, with the parameters the paper
/// used (section 4.1.1): 1 mm dots, a 1.5 mm vibrating outline, a 2 mm vertical grating.
#[derive(Clone, Copy)]
enum Method {
    Dots,
    Vibrate,
    Grating,
}

impl Method {
    fn name(self) -> &'static str {
        match self {
            Method::Dots => "dots",
            Method::Vibrate => "vibrate",
            Method::Grating => "grating",
        }
    }

    fn annotation(self) -> &'static str {
        match self {
            Method::Dots => "dots(radius: 1mm)",
            Method::Vibrate => "vibrate(width: 1.5mm)",
            Method::Grating => "grating(wavelength: 2mm, angle: 90deg)",
        }
    }

    /// How the shape looks on screen; the annotation decides how it feels.
    fn paint(self) -> &'static str {
        match self {
            Method::Dots => {
                r##"fill="none" stroke="#000000" stroke-width="2" stroke-dasharray="0.01 3" stroke-linecap="round""##
            }
            Method::Vibrate => r##"fill="none" stroke="#000000" stroke-width="1.5" stroke-linejoin="round""##,
            Method::Grating => r##"fill="#9a9a9a" stroke="none""##,
        }
    }

    fn visit(self, sh: &Shape) -> Visit {
        match self {
            Method::Grating => Visit::Area { centre: sh.centre(), reach: sh.s * 0.4 },
            _ => Visit::Outline(sh.outline()),
        }
    }
}

/// Every STRESS² scene, in the order of the paper.
pub fn scenes() -> Vec<Scene> {
    let mut v = Vec::new();
    for m in [Method::Vibrate, Method::Dots, Method::Grating] {
        v.push(exp1(m, "2cm", &Kind::EXP1));
        v.push(exp1(m, "3cm-a", &Kind::EXP1[..3]));
        v.push(exp1(m, "3cm-b", &Kind::EXP1[3..]));
    }
    // Pairs at the 0.5 mm step that was told apart 74 % of the time, at both
    // ends of the range and in the middle; the pair of Fig. 6; and the extremes.
    // Expected: T0402 where the wavelengths differ by less than 3 mm (the
    // point of the experiment: 0.5 mm is told apart only 74 % of the time),
    // T0405 where a wavelength is below twice the 1.2 mm column pitch.
    let pairs: [(f64, f64, &[&'static str]); 5] = [
        (1.0, 1.5, &["T0402", "T0405"]),
        (3.0, 3.5, &["T0402"]),
        (5.5, 6.0, &["T0402"]),
        (3.0, 6.0, &[]),
        (1.0, 6.0, &["T0405"]),
    ];
    for (a, b, warnings) in pairs {
        v.push(exp2(a, b, warnings));
    }
    for wl in [4.0, 6.0, 8.0] {
        v.push(orientations(3, wl, &[0.0, 30.0, 60.0, 90.0, -60.0, -30.0]));
    }
    v.push(orientations(4, 6.0, &[0.0, 45.0, 90.0, -45.0]));
    for kind in Kind::EXP5 {
        for (dir, angle) in [("vertical", 90.0), ("horizontal", 0.0)] {
            for wl in [2.0, 6.0] {
                v.push(icon(kind, dir, angle, wl));
            }
        }
    }
    v
}

fn human(kind: Kind) -> &'static str {
    match kind {
        Kind::TriangleUp => "upward triangle",
        Kind::TriangleDown => "downward triangle",
        Kind::Circle => "circle",
        Kind::Square => "square",
        Kind::Diamond => "diamond",
        Kind::Plus => "plus",
        Kind::RightTriangle => "right triangle",
    }
}

/// Experiment 1 (Fig. 4): shapes filling a 2 or 3 cm square. Six 2 cm shapes
/// fit in three columns and two rows; 3 cm shapes fit three to a sheet.
fn exp1(m: Method, size: &str, kinds: &[Kind]) -> Scene {
    let (s, xs, ys): (f64, [f64; 3], &[f64]) = if kinds.len() == 6 {
        // 12.5 mm between columns, 7 mm between rows.
        (20.0, [12.5, 45.0, 77.5], &[6.5, 33.5])
    } else {
        // 7 mm between shapes (room for 1 mm dots and the 3.2 mm rule), 3 mm
        // at the sides, centred vertically.
        (30.0, [3.0, 40.0, 77.0], &[15.0])
    };
    let mut body = format!("  <g id=\"{}\" data-tactile=\"{}\">\n", m.name(), m.annotation());
    let mut visits = Vec::new();
    for (i, kind) in kinds.iter().enumerate() {
        let sh = Shape { kind: *kind, x: xs[i % 3], y: ys[i / 3], s };
        let id = format!("{}-{}mm", kind.name(), n(s));
        body += &format!("    {}\n", sh.svg(&id, m.paint(), human(*kind)));
        visits.push(m.visit(&sh));
    }
    body += "  </g>\n";
    Scene {
        name: format!("exp1-{}-{}", m.name(), size),
        dir: "stress2",
        profile: "stress2",
        external: None,
        size: (W, H),
        body: Some(body),
        visits: Some(visits),
        style: None,
        warnings: exp1_warnings(m, s),
        source: "STRESS² (seed 000) experiment 1, section 4.1, Fig. 4.".into(),
        description: format!(
            "{} {} shapes ({}) drawn with {}, `{}`.",
            if kinds.len() == 6 { "Six" } else { "Three" },
            if s == 20.0 { "2 cm" } else { "3 cm" },
            kinds.iter().map(|k| human(*k)).collect::<Vec<_>>().join(", "),
            match m {
                Method::Dots => "dotted outlines",
                Method::Vibrate => "vibrating outlines",
                Method::Grating => "a filling grating",
            },
            m.annotation()
        ),
    }
}

/// The warnings the paper's own experiment-1 stimuli get, and why.
fn exp1_warnings(m: Method, s: f64) -> Vec<&'static str> {
    let small = s < 25.0;
    match m {
        Method::Vibrate => vec![],
        // T0302: dots spread evenly round the whole outline straddle the
        // acute corners of the 2 cm downward triangle, and two are dropped
        // (reported: dots anchored at corners would not overlap).
        Method::Dots if small => vec!["T0302"],
        Method::Dots => vec![],
        // T0405: the paper's 2 mm vertical grating is below twice the 1.2 mm
        // column pitch; it reads while the array moves (seed 000, 4.1).
        Method::Grating => vec!["T0405"],
    }
}

/// Experiment 2 (Fig. 6): two vertical gratings side by side with a 1 cm
/// blank between them, so the display never touches both at once.
fn exp2(a: f64, b: f64, warnings: &[&'static str]) -> Scene {
    let mut body = String::new();
    let mut visits = Vec::new();
    for (i, wl) in [a, b].into_iter().enumerate() {
        let x = 2.0 + 58.0 * i as f64;
        body += &format!(
            "  <rect id=\"grating-{}mm\" x=\"{}\" y=\"2\" width=\"48\" height=\"56\" fill=\"#9a9a9a\" \
             data-tactile=\"grating(wavelength: {}mm, angle: 90deg)\"><title>vertical grating, {} mm</title></rect>\n",
            n(wl),
            n(x),
            n(wl),
            n(wl)
        );
        visits.push(Visit::Area { centre: (x + 24.0, 30.0), reach: 20.0 });
    }
    Scene {
        name: format!("exp2-gratings-{:.1}-{:.1}mm", a, b),
        dir: "stress2",
        profile: "stress2",
        external: None,
        size: (W, H),
        body: Some(body),
        visits: Some(visits),
        style: None,
        warnings: warnings.to_vec(),
        source: "STRESS² (seed 000) experiment 2, section 4.2, Fig. 6.".into(),
        description: format!(
            "Two vertical gratings of {:.1} mm and {:.1} mm wavelength, 1 cm apart: which is finer?",
            a, b
        ),
    }
}

/// Experiments 3 and 4 (Fig. 8): round grated patches, one per orientation,
/// at one wavelength. Round, so that no edge hints at the orientation.
fn orientations(exp: u32, wl: f64, angles: &[f64]) -> Scene {
    let r = 12.5;
    let centres: Vec<(f64, f64)> = if angles.len() == 6 {
        [15.0, 45.0].iter().flat_map(|&y| [1.0, 3.0, 5.0].map(|k| (k * W / 6.0, y))).collect()
    } else {
        vec![(30.0, 15.0), (80.0, 15.0), (30.0, 45.0), (80.0, 45.0)]
    };
    let mut body = String::new();
    let mut visits = Vec::new();
    for (&angle, &(cx, cy)) in angles.iter().zip(&centres) {
        let a = n(angle);
        let id = format!("grating-{}deg", a.replace('-', "minus-"));
        body += &format!(
            "  <circle id=\"{id}\" cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"#9a9a9a\" \
             data-tactile=\"grating(wavelength: {}mm, angle: {a}deg)\"><title>grating at {a}°, {} mm</title></circle>\n",
            n(cx),
            n(cy),
            n(r),
            n(wl),
            n(wl)
        );
        visits.push(Visit::Area { centre: (cx, cy), reach: r * 0.8 });
    }
    let (section, fig, what) = if exp == 3 {
        ("4.3", "Fig. 8", "fine orientations (0°, ±30°, ±60°, 90°; −30° is 150°)")
    } else {
        ("4.4", "section 4.4", "coarse orientations (0°, 45°, 90°, −45°; −45° is 135°)")
    };
    Scene {
        name: format!("exp{exp}-orientations-{}mm", n(wl)),
        dir: "stress2",
        profile: "stress2",
        external: None,
        size: (W, H),
        body: Some(body),
        visits: Some(visits),
        style: None,
        // Experiment 3's sheets show what the paper found: 30° steps are not
        // identified (T0403), and six textures on one sheet are more than a
        // graphic should use (T0409). Experiment 4's set is clean. On both,
        // the key's two-line meanings ("grating at 45°, 6 mm") go on more
        // pages than one: nothing is left out of the key.
        warnings: if exp == 3 { vec!["T0403", "T0409"] } else { vec![] },
        source: format!("STRESS² (seed 000) experiment {exp}, section {section}, {fig}."),
        description: format!("Gratings of {} mm at the {what}.", n(wl)),
    }
}

/// Experiment 5 (Fig. 12): a 3 cm vibrating outline filled with a grating,
/// one icon per sheet as in the experiment.
fn icon(kind: Kind, dir: &str, angle: f64, wl: f64) -> Scene {
    let sh = Shape { kind, x: 40.0, y: 15.0, s: 30.0 };
    let style = format!("vibrate(width: 1.5mm); grating(wavelength: {}mm, angle: {}deg)", n(wl), n(angle));
    let el = sh.svg(
        &format!("icon-{}", kind.name()),
        &format!(
            r##"fill="#c8c8c8" stroke="#000000" stroke-width="1.5" stroke-linejoin="round" data-tactile="{style}""##
        ),
        &format!("{}, {dir} grating of {} mm", human(kind), n(wl)),
    );
    let body = format!("  {}\n", el);
    Scene {
        name: format!("exp5-icon-{}-{dir}-{}mm", kind.name(), n(wl)),
        dir: "stress2",
        profile: "stress2",
        external: None,
        size: (W, H),
        body: Some(body),
        visits: Some(vec![Visit::Outline(sh.outline()), Visit::Area { centre: sh.centre(), reach: 9.0 }]),
        style: None,
        // T0405: 2 mm is below twice the pitch across the ridges (1.2 mm
        // columns for vertical, 1.4 mm rows for horizontal gratings).
        warnings: if wl < 2.8 { vec!["T0405"] } else { vec![] },
        source: "STRESS² (seed 000) experiment 5, section 4.5, Fig. 12.".into(),
        description: format!(
            "Tactile icon: a 3 cm {} with a vibrating outline, filled with a {dir} grating of {} mm, `{style}`.",
            human(kind),
            n(wl)
        ),
    }
}
