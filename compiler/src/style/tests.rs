use super::labels::braille_boxes;
use super::*;
use crate::braille::paper::{CELL_PITCH_MM, DOT_PITCH_MM};
use crate::drawing::{Clip, Element, Page, Paint, PathShape, TextRun, TextShape};
use crate::geometry::{FillRule, Polyline};
use taxel_format::profiles;

/// stress2 with a surface large enough for the test pages (fitting is not what these test).
fn stress2() -> DeviceProfile {
    let mut p = profiles::builtin("stress2").unwrap();
    (p.surface_w_mm, p.surface_h_mm) = (400.0, 300.0);
    p
}

pub(crate) fn page(w: f64, h: f64) -> Page {
    Page { width_mm: w, height_mm: h, scale: 1.0, offset_mm: (0.0, 0.0), sheet_mm: None }
}

pub(crate) fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Polyline> {
    vec![Polyline { points: vec![(x0, y0), (x1, y0), (x1, y1), (x0, y1)], closed: true }]
}

fn circle(cx: f64, cy: f64, r: f64) -> Vec<Polyline> {
    let points = (0..64)
        .map(|k| {
            let t = k as f64 / 64.0 * std::f64::consts::TAU;
            (cx + r * t.cos(), cy + r * t.sin())
        })
        .collect();
    vec![Polyline { points, closed: true }]
}

pub(crate) fn shape(name: &str, outline: Vec<Polyline>, fill: Option<Rgba>, stroke: Option<Rgba>) -> Element {
    Element {
        id: name.into(),
        name: name.into(),
        tag: "path".into(),
        visible: true,
        paint: Paint {
            fill,
            filled: fill.is_some(),
            stroke,
            stroked: stroke.is_some(),
            stroke_width_mm: if stroke.is_some() { 0.3 } else { 0.0 },
        },
        shape: Shape::Path(PathShape { outline, ..Default::default() }),
        ..Default::default()
    }
}

fn text(name: &str, s: &str, x: f64, y: f64) -> Element {
    Element {
        id: name.into(),
        name: name.into(),
        tag: "text".into(),
        visible: true,
        shape: Shape::Text(TextShape {
            content: s.into(),
            runs: vec![TextRun { text: s.into(), x_mm: x, y_mm: y, anchor: 0.0, continues: false }],
            font_size_mm: 4.0,
            ..Default::default()
        }),
        ..Default::default()
    }
}

const BLACK: Option<Rgba> = Some([0, 0, 0, 255]);
pub(crate) const RED: Option<Rgba> = Some([228, 26, 28, 255]);
const BLUE: Option<Rgba> = Some([55, 126, 184, 255]);
const WHITE_FILL: Option<Rgba> = Some([255, 255, 255, 255]);

#[test]
fn each_kind_of_element_gets_what_the_sheet_promises() {
    let mut d = Drawing {
        page: page(200.0, 120.0),
        elements: vec![
            shape("background", rect(0.0, 0.0, 200.0, 120.0), Some([235, 225, 200, 255]), None),
            shape("sea", rect(0.0, 0.0, 199.0, 119.0), BLUE, None), // covers the page: a background too
            shape("land", rect(10.0, 10.0, 90.0, 90.0), RED, BLACK),
            shape("road", vec![Polyline { points: vec![(0.0, 100.0), (150.0, 100.0)], closed: false }], None, BLACK),
            shape("town", circle(50.0, 50.0, 1.5), BLACK, None),
            shape(
                "glyph",
                vec![Polyline {
                    points: vec![(120.0, 10.0), (120.4, 10.0), (120.4, 14.0), (120.0, 14.0)],
                    closed: true,
                }],
                BLACK,
                None,
            ),
            shape("paper", rect(100.0, 10.0, 140.0, 40.0), WHITE_FILL, None),
            shape("ghost", rect(100.0, 50.0, 140.0, 60.0), Some([255, 0, 0, 10]), None),
            text("label", "Tala", 20.0, 30.0),
            // Too long for the page, and no key code: it has no letter.
            text("too-long", "3,141,592,653,589,793,238,462,643,383,279", 150.0, 60.0),
            shape("off", rect(300.0, 10.0, 320.0, 40.0), RED, None),
            Element { visible: false, ..shape("hidden", rect(10.0, 10.0, 30.0, 30.0), RED, None) },
            {
                let mut e = shape("clipped", rect(10.0, 10.0, 30.0, 30.0), RED, None);
                if let Shape::Path(p) = &mut e.shape {
                    p.clips.push(Clip { outline: rect(100.0, 100.0, 110.0, 110.0), ..Default::default() });
                }
                e
            },
        ],
        ..Default::default()
    };
    let mut diags = Vec::new();
    let plan = apply(&mut d, &stress2(), &mut diags);
    let names: Vec<Vec<&str>> = d.elements.iter().map(|e| e.styles.iter().map(Style::name).collect()).collect();
    let left: Vec<Option<LeftOut>> = plan.decisions.iter().map(|d| d.left_out).collect();
    assert_eq!(left[0], Some(LeftOut::Background));
    assert_eq!(left[1], Some(LeftOut::Background));
    assert_eq!(names[2], ["vibrate", "grating"]);
    assert_eq!(names[3], ["vibrate"]);
    assert_eq!(names[4], ["dot"]);
    assert_eq!(left[5], Some(LeftOut::SmallShape), "a 0.4 x 4 mm sliver is not a mark");
    assert_eq!(left[6], Some(LeftOut::Unpainted));
    assert_eq!(left[7], Some(LeftOut::Unpainted));
    assert_eq!(names[8], ["braille"]);
    assert_eq!(left[9], Some(LeftOut::TextDoesNotFit));
    assert_eq!(left[10], Some(LeftOut::OffPage));
    assert_eq!(left[11], Some(LeftOut::Hidden));
    assert_eq!(left[12], Some(LeftOut::ClippedAway));
    assert!(d.elements.iter().all(|e| (e.styled_by == StyledBy::Auto) != e.styles.is_empty()));
    // One note for the text left out, naming it.
    let t: Vec<_> = diags.iter().filter(|d| d.code == "T0323").collect();
    assert_eq!(t.len(), 1);
    assert!(t[0].message.contains("#too-long"), "{}", t[0].message);
    let s = summary(&d);
    assert_eq!(s.message, "13 element(s) (automatic style sheet): 2 vibrate, 1 grating, 1 dot, 1 braille, 9 left out");
}

#[test]
fn annotated_elements_are_left_as_they_are() {
    let mut annotated = shape("a", rect(10.0, 10.0, 50.0, 50.0), RED, None);
    annotated.styles = vec![Style::Vibrate(outline_style(&stress2()))];
    annotated.styled_by = StyledBy::Annotation;
    let mut d = Drawing {
        page: page(100.0, 60.0),
        elements: vec![annotated.clone(), shape("b", rect(60.0, 10.0, 90.0, 50.0), BLUE, None)],
        ..Default::default()
    };
    assert!(!unannotated(&d));
    apply(&mut d, &stress2(), &mut Vec::new());
    assert_eq!(d.elements[0].styles, annotated.styles);
    assert_eq!(d.elements[0].styled_by, StyledBy::Annotation);
    assert_eq!(d.elements[1].styled_by, StyledBy::Auto);
}

#[test]
fn braille_labels_that_would_collide_keep_the_first() {
    let mut d = Drawing {
        page: page(200.0, 100.0),
        elements: vec![
            text("one", "Oslo", 10.0, 50.0),
            text("two", "Bergen", 12.0, 52.0),
            text("three", "Moss", 10.0, 80.0),
        ],
        ..Default::default()
    };
    let plan = apply(&mut d, &stress2(), &mut Vec::new());
    let b: Vec<bool> = plan.decisions.iter().map(|d| d.braille).collect();
    assert_eq!(b, [true, false, true]);
}

#[test]
fn more_fills_than_textures_reuse_textures_only_between_regions_that_do_not_touch() {
    // Six colours in a row of touching squares: the five largest take a
    // texture each, the sixth shares the least used one its neighbour lacks.
    let fills: Vec<Rgba> = (0..6).map(|k| [40 * k as u8, 100, 200 - 30 * k as u8, 255]).collect();
    let elements: Vec<Element> = (0..6)
        .map(|k| {
            // Decreasing sizes so the order by area is the order in the row.
            let x = 30.0 * k as f64;
            shape(&format!("r{k}"), rect(x, 0.0, x + 30.0, 40.0 - 3.0 * k as f64), Some(fills[k]), None)
        })
        .collect();
    let mut d = Drawing { page: page(200.0, 100.0), elements, ..Default::default() };
    let mut diags = Vec::new();
    let plan = apply(&mut d, &stress2(), &mut diags);
    let tex: Vec<Option<usize>> = plan.fills.iter().map(|f| f.texture).collect();
    assert_eq!(tex, [Some(0), Some(1), Some(2), Some(3), Some(4), Some(0)]);
    assert!(diags.iter().any(|d| d.code == "T0322"), "{diags:?}");
    assert!(!diags.iter().any(|d| d.code == "T0321"));
}

/// Regression (logos with many colours, such as Apache Flink's): one T0322
/// per shared texture was grouped by the account into one line naming the
/// first texture for all of them. One note names every shared texture.
#[test]
fn textures_shared_by_several_groups_of_fills_are_one_note_naming_each() {
    // Eleven colours in a row, none touching: five textures, the first
    // shared by three fills, the others by two.
    let fills: Vec<Rgba> = (0..11u8).map(|k| [20 * k, 200 - 15 * k, 60 + 10 * k, 255]).collect();
    let elements = (0..11)
        .map(|k| {
            let x = 20.0 * k as f64;
            shape(&format!("r{k}"), rect(x, 0.0, x + 10.0, 40.0 - k as f64), Some(fills[k]), None)
        })
        .collect();
    let mut d = Drawing { page: page(230.0, 100.0), elements, ..Default::default() };
    let mut diags = Vec::new();
    let plan = apply(&mut d, &stress2(), &mut diags);
    let notes: Vec<&Diagnostic> = diags.iter().filter(|d| d.code == "T0322").collect();
    assert_eq!(notes.len(), 1, "{diags:?}");
    for (t, g) in plan.textures.iter().enumerate() {
        let n = plan.fills.iter().filter(|f| f.texture == Some(t)).count();
        let named = format!("grating({} mm, {}°)", g.wavelength_mm, g.angle_deg);
        assert_eq!(n > 1, notes[0].message.contains(&named), "{named} x{n}: {}", notes[0].message);
    }
    assert!(
        plan.textures
            .iter()
            .enumerate()
            .filter(|&(t, _)| plan.fills.iter().filter(|f| f.texture == Some(t)).count() > 1)
            .count()
            > 1
    );
}

#[test]
fn the_sheet_for_a_drawing_parses_and_maps_each_fill_to_its_texture() {
    let d = Drawing {
        page: page(200.0, 100.0),
        elements: vec![
            shape("a", rect(10.0, 10.0, 60.0, 60.0), RED, BLACK),
            shape("b", rect(60.0, 10.0, 100.0, 60.0), BLUE, None),
            shape("c", rect(120.0, 10.0, 160.0, 60.0), Some([77, 175, 74, 255]), BLACK),
            shape(
                "line",
                vec![Polyline { points: vec![(0.0, 80.0), (100.0, 80.0)], closed: false }],
                None,
                Some([0, 0, 255, 255]),
            ),
        ],
        ..Default::default()
    };
    let plan = plan(&d, &stress2());
    let toml = sheet_toml(&stress2(), Some((&d, &plan)));
    let sheet = crate::StyleSheet::parse(&toml, "auto.toml").unwrap_or_else(|e| panic!("{e}\n{toml}"));
    let facts = |fill: Option<[u8; 3]>, stroke: Option<[u8; 3]>| crate::annotation::sheet::ElementFacts {
        fill,
        stroke,
        ..Default::default()
    };
    let styles = |f| sheet.lookup(&f).map(|r| r.declaration.styles().to_vec()).unwrap_or_default();
    let t = textures(&stress2());
    assert_eq!(styles(facts(Some([228, 26, 28]), None)), [Style::Grating(t[0])]);
    // `a` abuts `b`: the border is the change of texture, its stroke does not vibrate.
    assert_eq!(styles(facts(Some([228, 26, 28]), Some([0, 0, 0]))), [Style::Grating(t[0])]);
    // `c` stands alone: its stroke vibrates around its texture.
    let c = plan.fills.iter().find(|f| f.fill == Some([77, 175, 74])).and_then(|f| f.texture).unwrap();
    assert_eq!(
        styles(facts(Some([77, 175, 74]), Some([0, 0, 0]))),
        [Style::Vibrate(outline_style(&stress2())), Style::Grating(t[c])]
    );
    assert_eq!(styles(facts(Some([55, 126, 184]), None)), [Style::Grating(t[1])]);
    assert_eq!(styles(facts(None, Some([0, 0, 255]))), [Style::Vibrate(outline_style(&stress2()))]);
}

#[test]
fn a_ring_glyph_is_not_a_mark_but_a_filled_disc_is() {
    // A "0" as fonts draw it: outer contour one way, the hole the other; 3 x 4 mm.
    let ellipse = |rx: f64, ry: f64, reverse: bool, cx: f64| {
        let mut points: Vec<(f64, f64)> = (0..48)
            .map(|k| {
                let t = k as f64 / 48.0 * std::f64::consts::TAU;
                (cx + rx * t.cos(), 50.0 + ry * t.sin())
            })
            .collect();
        if reverse {
            points.reverse();
        }
        Polyline { points, closed: true }
    };
    let ring = vec![ellipse(1.5, 2.0, false, 30.0), ellipse(1.0, 1.5, true, 30.0)];
    let mut d = Drawing {
        page: page(100.0, 100.0),
        elements: vec![
            shape("zero", ring, BLACK, None),
            shape("disc", vec![ellipse(1.5, 2.0, false, 60.0)], BLACK, None),
        ],
        ..Default::default()
    };
    let plan = apply(&mut d, &stress2(), &mut Vec::new());
    assert_eq!(plan.decisions[0].left_out, Some(LeftOut::SmallShape));
    assert!(plan.decisions[1].mark);
}

/// Issue 14 point 2: beyond five textures where regions touch, the fill of
/// least area keeps only its outline, and one note (T0321) names it.
#[test]
fn a_sixth_fill_touching_five_others_falls_back_to_its_outline_with_a_note() {
    // Six thin strips 0.2 mm apart: every pair is closer than NEAR_MM (the
    // outer two 2.6 mm), so all six fills touch and need six textures.
    // Shorter strips have less area, so the last is the one given up.
    let fills: Vec<Rgba> = (0..6).map(|k| [30 + 40 * k as u8, 90, 220 - 35 * k as u8, 255]).collect();
    let elements: Vec<Element> = (0..6)
        .map(|k| {
            let y = 20.0 + 0.6 * k as f64;
            shape(&format!("s{k}"), rect(10.0, y, 90.0 - 5.0 * k as f64, y + 0.4), Some(fills[k]), None)
        })
        .collect();
    let mut d = Drawing { page: page(200.0, 100.0), elements, ..Default::default() };
    let mut diags = Vec::new();
    let plan = apply(&mut d, &stress2(), &mut diags);
    let tex: Vec<Option<usize>> = plan.fills.iter().map(|f| f.texture).collect();
    assert_eq!(tex[..5].iter().flatten().collect::<std::collections::BTreeSet<_>>().len(), 5, "{tex:?}");
    assert_eq!(tex[5], None, "{tex:?}");
    let last = fills[5];
    assert_eq!(plan.fills[5].fill, Some([last[0], last[1], last[2]]));
    // The given-up strip vibrates along its outline and has no grating.
    assert!(plan.decisions[5].outline);
    assert_eq!(d.elements[5].styles.iter().map(Style::name).collect::<Vec<_>>(), ["vibrate"]);
    let notes: Vec<_> = diags.iter().filter(|d| d.code == "T0321").collect();
    assert_eq!(notes.len(), 1, "{diags:?}");
    assert!(notes[0].message.contains(&fill_name(plan.fills[5].fill)), "{}", notes[0].message);
    assert!(!notes[0].message.contains(&fill_name(plan.fills[4].fill)), "{}", notes[0].message);
}

/// Issue 14 point 2: the textures are ones readers tell apart (seed 000
/// section 4): for every built-in profile, five distinct gratings, each at
/// 0°, 45°, 90° or 135°, two of one orientation at least 3 mm apart in
/// wavelength, and none shorter than twice the actuator pitch (no aliasing).
#[test]
fn textures_are_distinguishable_on_every_built_in_profile() {
    for name in profiles::builtin_names() {
        let p = profiles::builtin(name).unwrap();
        let t = textures(&p);
        let pitch = f64::from(p.pitch_x_mm.max(p.pitch_y_mm));
        for (i, a) in t.iter().enumerate() {
            assert!([0.0, 45.0, 90.0, 135.0].contains(&a.angle_deg), "{name}: {a:?}");
            assert!(a.wavelength_mm >= 2.0 * pitch - 1e-9, "{name}: {a:?} aliases at pitch {pitch} mm");
            for b in &t[i + 1..] {
                assert!(a != b, "{name}: {a:?} twice");
                if a.angle_deg == b.angle_deg {
                    assert!((a.wavelength_mm - b.wavelength_mm).abs() >= 3.0, "{name}: {a:?} and {b:?}");
                }
            }
        }
    }
}

/// What a fill covers is measured under its rule: a figure eight (whose
/// lobes wind opposite ways) and two squares drawn in opposite directions
/// in one path cover the area of their lobes, and are regions; their signed
/// areas cancelled out, and they were left out as enclosing nothing.
#[test]
fn a_figure_eight_and_blobs_drawn_opposite_ways_are_regions() {
    let eight = vec![Polyline {
        points: vec![(20.0, 20.0), (60.0, 20.0), (60.0, 100.0), (100.0, 100.0), (100.0, 60.0), (20.0, 60.0)],
        closed: true,
    }];
    let mut pair = rect(120.0, 20.0, 160.0, 60.0);
    let mut back = rect(170.0, 20.0, 210.0, 60.0);
    back[0].points.reverse();
    pair.extend(back);
    for rule in [FillRule::NonZero, FillRule::EvenOdd] {
        let mut elements = vec![shape("eight", eight.clone(), RED, None), shape("pair", pair.clone(), BLUE, None)];
        for e in &mut elements {
            if let Shape::Path(p) = &mut e.shape {
                p.fill_rule = rule;
            }
        }
        let d = Drawing { page: page(230.0, 120.0), elements, ..Default::default() };
        let plan = plan(&d, &stress2());
        for (k, name) in ["eight", "pair"].iter().enumerate() {
            assert_eq!(plan.decisions[k].left_out, None, "{name} ({rule:?})");
            assert!(plan.styles(k).iter().any(|s| matches!(s, Style::Grating(_))), "{name} ({rule:?})");
        }
        // Each covers 2 x 40 x 40 mm².
        for e in &d.elements {
            let Shape::Path(p) = &e.shape else { unreachable!() };
            assert!((crate::geometry::filled_area(&p.outline, rule) - 3200.0).abs() < 0.01, "{} ({rule:?})", e.name);
        }
    }
}

/// A page-sized shape clipped to a small square is that square, not the
/// page's background: it was left out as one (a chart's clipped plot area).
#[test]
fn a_page_sized_shape_clipped_small_is_not_a_background() {
    let mut clipped = shape("clipped", rect(0.0, 0.0, 200.0, 100.0), RED, None);
    if let Shape::Path(p) = &mut clipped.shape {
        p.clips = vec![Clip { outline: rect(50.0, 25.0, 100.0, 75.0), fill_rule: FillRule::NonZero }];
    }
    let ground = shape("ground", rect(0.0, 0.0, 200.0, 100.0), Some([40, 40, 40, 255]), None);
    let d = Drawing { page: page(200.0, 100.0), elements: vec![ground, clipped], ..Default::default() };
    let plan = plan(&d, &stress2());
    assert_eq!(plan.decisions[0].left_out, Some(LeftOut::Background));
    assert_eq!(plan.decisions[1].left_out, None);
    assert!(plan.styles(1).iter().any(|s| matches!(s, Style::Grating(_))));
}

/// A page-sized shape drawn alone is the figure: a logo drawn as one
/// rounded square with its letters cut out (Simple Icons' MobX) was left
/// out as the page's background, and nothing was felt. With anything else
/// drawn on the page, it is the background, as before.
#[test]
fn a_page_sized_shape_drawn_alone_is_the_figure() {
    let mut outline = rect(0.0, 0.0, 200.0, 100.0);
    outline.extend(rect(90.0, 40.0, 110.0, 60.0));
    let alone = || {
        let mut logo = shape("logo", outline.clone(), RED, None);
        if let Shape::Path(p) = &mut logo.shape {
            p.fill_rule = FillRule::EvenOdd;
        }
        logo
    };
    let d = Drawing { page: page(200.0, 100.0), elements: vec![alone()], ..Default::default() };
    let plan = plan_of(&d);
    assert_eq!(plan.decisions[0].left_out, None);
    assert!(plan.styles(0).iter().any(|s| matches!(s, Style::Grating(_))));
    let on_it = shape("mark", rect(20.0, 20.0, 60.0, 50.0), BLUE, None);
    let d = Drawing { page: page(200.0, 100.0), elements: vec![alone(), on_it], ..Default::default() };
    assert_eq!(plan_of(&d).decisions[0].left_out, Some(LeftOut::Background));
}

/// A label that runs off the page's side (a town on a fitted map's east
/// coast) is pulled back onto it, whole, still covering where it began; it
/// was left out. One wider than the page, or that would have to move past
/// its own width, is still left out.
#[test]
fn a_label_running_off_the_page_is_pulled_back_onto_it() {
    let braille_width = |cells: usize| (cells - 1) as f64 * CELL_PITCH_MM + DOT_PITCH_MM + 2.0 * BRAILLE_RADIUS_MM;
    // "abcd" (4 cells, no capital) starting 10 mm from the right edge of a 200 mm page.
    let d =
        Drawing { page: page(200.0, 100.0), elements: vec![text("east", "abcd", 190.0, 50.0)], ..Default::default() };
    let plan = plan(&d, &stress2());
    let dec = &plan.decisions[0];
    assert!(dec.braille && dec.left_out.is_none(), "{dec:?}");
    // Its right edge on the page's, or a clearance shift short of it.
    let right = 190.0 + dec.braille_shift.0 + braille_width(4);
    assert!((200.0 - 3.0 - 1e-9..=200.0 + 1e-9).contains(&right), "{dec:?}");
    // Off the left edge (centred on x = 5 mm) and the top (the cells stand on
    // the baseline, 3 mm down) alike.
    let mut west = text("west", "abcd", 5.0, 3.0);
    if let Shape::Text(t) = &mut west.shape {
        t.runs[0].anchor = 0.5;
    }
    let d = Drawing { page: page(200.0, 100.0), elements: vec![west], ..Default::default() };
    let dec = &plan_of(&d).decisions[0];
    assert!(
        dec.braille && dec.braille_shift.0 >= braille_width(4) / 2.0 - 5.0 && dec.braille_shift.1 >= 1.0,
        "{dec:?}"
    );
    // Starting just inside the edge; and beyond it, off the page.
    let d = Drawing { page: page(200.0, 100.0), elements: vec![text("far", "ab", 199.5, 50.0)], ..Default::default() };
    let dec = &plan_of(&d).decisions[0];
    assert!(dec.braille, "{dec:?}");
    let d = Drawing { page: page(200.0, 100.0), elements: vec![text("far", "ab", 215.0, 50.0)], ..Default::default() };
    assert!(!plan_of(&d).decisions[0].braille);
    // Wider than the page (digits: no key code).
    let long = "12".repeat(20);
    let d = Drawing { page: page(200.0, 100.0), elements: vec![text("long", &long, 10.0, 50.0)], ..Default::default() };
    assert_eq!(plan_of(&d).decisions[0].left_out, Some(LeftOut::TextDoesNotFit));
}

fn plan_of(d: &Drawing) -> Plan {
    plan(d, &stress2())
}

/// A chart's plot panel (Plotly's `#e5ecf6`, ggplot2's `#ebebeb`: a very
/// light rectangle with the bars painted on it) is a background, not a
/// region: it was given a texture under the bars' own, and on pins the two
/// were raised into one mass. A very light region with nothing coloured on
/// it, or with only marks, stays a region; so does a light one carrying
/// shapes painted before it (under it).
#[test]
fn a_chart_s_light_plot_panel_is_a_background() {
    let panel = |fill: Rgba| shape("panel", rect(20.0, 10.0, 150.0, 90.0), Some(fill), None);
    let bar = |x: f64| shape("bar", rect(x, 40.0, x + 20.0, 90.0), BLUE, None);
    let page_rect = shape("page", rect(0.0, 0.0, 200.0, 120.0), WHITE_FILL, None);
    let d = Drawing {
        page: page(200.0, 120.0),
        elements: vec![page_rect.clone(), panel([229, 236, 246, 255]), bar(40.0), bar(90.0)],
        ..Default::default()
    };
    let plan = plan(&d, &stress2());
    assert_eq!(plan.decisions[1].left_out, Some(LeftOut::Background));
    for k in [2, 3] {
        assert!(plan.styles(k).iter().any(|s| matches!(s, Style::Grating(_))), "bar {k}");
    }
    // ggplot2's grey92 alike.
    let d = Drawing { elements: vec![page_rect.clone(), panel([235, 235, 235, 255]), bar(40.0)], ..d.clone() };
    assert_eq!(plan_of(&d).decisions[1].left_out, Some(LeftOut::Background));
    // Alone, or with a mark only, or painted over the bar: a region.
    let mark = shape("mark", rect(60.0, 50.0, 62.0, 52.0), BLUE, None);
    let light = panel([229, 236, 246, 255]);
    for rest in [vec![light.clone()], vec![light.clone(), mark], vec![bar(40.0), light.clone()]] {
        let elements: Vec<Element> = std::iter::once(page_rect.clone()).chain(rest).collect();
        let k = elements.iter().position(|e| e.name == "panel").unwrap_or(0);
        let d = Drawing { page: page(200.0, 120.0), elements, ..Default::default() };
        let plan = plan_of(&d);
        assert_eq!(plan.decisions[k].left_out, None, "{:?}", plan.decisions);
    }
    // A panel of a stronger colour is a region the bars lie in.
    let elements = vec![page_rect, panel([200, 215, 240, 255]), bar(40.0)];
    let d = Drawing { page: page(200.0, 120.0), elements, ..Default::default() };
    assert_eq!(plan_of(&d).decisions[1].left_out, None);
}

/// A tick label set in a font smaller than braille, just under its axis:
/// braille stands on the baseline and grows upwards into the axis, at its
/// place and at every small shift; a cell's height lower it fits, and is
/// kept there (it was left out). Nothing moves a whole cell upwards, where
/// an axis's labels would land on the bars they name (and a label that
/// meets other braille is not stacked under it:
/// `braille_labels_that_would_collide_keep_the_first`).
#[test]
fn a_tick_label_under_its_axis_moves_a_cell_down_rather_than_out() {
    let axis = shape("axis", vec![Polyline { points: vec![(10.0, 50.0), (190.0, 50.0)], closed: false }], None, BLACK);
    let d = Drawing {
        page: page(200.0, 100.0),
        elements: vec![axis.clone(), text("tick", "12", 90.0, 52.0)],
        ..Default::default()
    };
    let dec = &plan_of(&d).decisions[1];
    assert!(dec.braille && dec.braille_shift == (0.0, 6.0), "{dec:?}");
    // Above an axis, the same label moves up only as far as the small shifts.
    let d = Drawing {
        page: page(200.0, 100.0),
        elements: vec![axis, text("tick", "12", 90.0, 49.0)],
        ..Default::default()
    };
    let dec = &plan_of(&d).decisions[1];
    assert!(!dec.braille || dec.braille_shift.1 >= -3.0, "{dec:?}");
}

/// A diagram's arrowhead (Graphviz, draw.io, LibreOffice: a small filled
/// triangle of the line's colour, its tip on the box the line points at) is
/// a mark at the line's end. It was taken for a piece of a tessellation
/// with the box (they touch), became a tiny grating, and the box lost its
/// outline beside it. A triangle of the same size and colour that no line
/// of its colour ends on, touching a box, stays a region; so does one where
/// only a line of another colour ends, one where a line shorter than twice
/// its size ends (an emblem's detail stroke), and a small curved shape (a
/// leaf of an emblem: many corners).
#[test]
fn an_arrowhead_touching_a_box_is_a_mark_and_the_box_keeps_its_outline() {
    let boxed = shape("box", rect(50.0, 40.0, 90.0, 60.0), BLUE, BLACK);
    let line = |stroke| {
        shape("edge", vec![Polyline { points: vec![(10.0, 50.0), (46.1, 50.0)], closed: false }], None, stroke)
    };
    // Its base 0.1 mm past the line's end (Graphviz's gap), its tip on the box.
    let head = shape(
        "head",
        vec![Polyline { points: vec![(46.2, 48.5), (50.0, 50.0), (46.2, 51.5)], closed: true }],
        BLACK,
        BLACK,
    );
    for (stroke, arrow) in [(BLACK, true), (RED, false), (None, false)] {
        let mut elements = vec![boxed.clone(), head.clone()];
        if stroke.is_some() {
            elements.push(line(stroke));
        }
        let d = Drawing { page: page(200.0, 100.0), elements, ..Default::default() };
        let plan = plan_of(&d);
        let (b, h) = (&plan.decisions[0], &plan.decisions[1]);
        if arrow {
            assert!(h.mark && h.region.is_none(), "the arrowhead: {h:?}");
            assert!(b.outline && b.region.is_some(), "the box: {b:?}");
        } else {
            assert!(!h.mark && h.region.is_some(), "no line of its colour ends on it: {h:?}");
        }
    }
    let short =
        shape("stroke", vec![Polyline { points: vec![(40.0, 50.0), (46.1, 50.0)], closed: false }], None, BLACK);
    // A leaf touching the box, the line ending on it.
    let leaf = shape("leaf", circle(48.5, 50.0, 1.5), BLACK, BLACK);
    let stem = shape("stem", vec![Polyline { points: vec![(10.0, 50.0), (47.0, 50.0)], closed: false }], None, BLACK);
    for (head, line) in [(head.clone(), short), (leaf, stem)] {
        let d = Drawing { page: page(200.0, 100.0), elements: vec![boxed.clone(), head, line], ..Default::default() };
        let h = &plan_of(&d).decisions[1];
        assert!(!h.mark && h.region.is_some(), "not an arrowhead: {h:?}");
    }
}

/// Key codes: a label's initials (accents dropped), else its first letter
/// with a later one; none for a label of fewer than three characters or
/// two letters; none
/// that a label written whole already reads as.
#[test]
fn key_codes_are_initials_unless_short_or_taken() {
    let keyed = |labels: &[(&str, f64, f64)], w: f64| {
        let elements = labels.iter().map(|&(s, x, y)| text(s, s, x, y)).collect();
        let plan = plan_of(&Drawing { page: page(w, 20.0), elements, ..Default::default() });
        plan.decisions
            .iter()
            .map(|d| (d.braille, d.key.map(|k| String::from_utf8_lossy(&k).into_owned())))
            .collect::<Vec<_>>()
    };
    // 20 mm wide: room for two cells, not for a whole label of four or more.
    assert_eq!(keyed(&[("Read input", 2.0, 12.0)], 20.0), [(true, Some("ri".into()))]);
    assert_eq!(keyed(&[("Élysée Palace", 2.0, 12.0)], 20.0), [(true, Some("ep".into()))]);
    assert_eq!(keyed(&[("Bremen", 2.0, 12.0)], 20.0), [(true, Some("br".into()))]);
    // One letter says too little of the label.
    assert_eq!(keyed(&[("R108", 2.0, 12.0)], 20.0), [(false, None)]);
    assert_eq!(keyed(&[("Tea", 2.0, 12.0)], 16.0), [(true, Some("te".into()))]);
    // Two characters take three cells ("No": a capital sign, n, o): whole or not at all.
    assert_eq!(keyed(&[("No", 2.0, 12.0)], 14.0), [(false, None)]);
    // "ri" written whole (it fits) takes its code from "Read input".
    assert_eq!(keyed(&[("ri", 2.0, 8.0), ("Read input", 2.0, 18.0)], 20.0), [(true, None), (true, Some("re".into()))]);
}

/// Braille keeps off a region that stands alone (a chart's bar, a
/// diagram's box) unless it was drawn on it: braille clears a grating
/// around itself, and a tick label moved onto a bar cut the bar short. A
/// label drawn on a box stays on it; a label across the border of two
/// regions of a tessellation (a map's) stays where it is.
#[test]
fn braille_keeps_off_figures_it_was_not_drawn_on() {
    let boxes_of = |dec: &Decision, s: &str, x: f64, y: f64| {
        let text = dec.key.map_or(s.to_string(), |k| String::from_utf8_lossy(&k).into_owned());
        let run = TextRun { text, x_mm: x + dec.braille_shift.0, y_mm: y + dec.braille_shift.1, ..Default::default() };
        braille_boxes(&[run], None, Measure::BUILTIN)
    };
    let bar = shape("bar", rect(50.0, 20.0, 60.0, 80.0), BLUE, None);
    let d = Drawing {
        page: page(200.0, 100.0),
        elements: vec![
            bar,
            text("tick", "abcd", 40.0, 50.0),
            shape("box", rect(100.0, 20.0, 160.0, 60.0), RED, None),
            text("inside", "abcd", 110.0, 45.0),
        ],
        ..Default::default()
    };
    let plan = plan_of(&d);
    let tick = &plan.decisions[1];
    for q in boxes_of(tick, "abcd", 40.0, 50.0).into_iter().filter(|_| tick.braille) {
        assert!(q.2 + BRAILLE_CLEARANCE_MM <= 50.0 || q.0 - BRAILLE_CLEARANCE_MM >= 60.0, "{tick:?}: {q:?} on the bar");
    }
    let inside = &plan.decisions[3];
    assert!(inside.braille && inside.braille_shift == (0.0, 0.0) && inside.key.is_none(), "{inside:?}");
    // Across the border of two regions that abut.
    let d = Drawing {
        page: page(200.0, 100.0),
        elements: vec![
            shape("west", rect(0.0, 0.0, 50.0, 50.0), RED, None),
            shape("east", rect(50.0, 0.0, 100.0, 50.0), BLUE, None),
            text("across", "abcd", 45.0, 30.0),
        ],
        ..Default::default()
    };
    let across = &plan_of(&d).decisions[2];
    assert!(across.braille && across.braille_shift == (0.0, 0.0) && across.key.is_none(), "{across:?}");
}

/// An axis of tick labels: `values` at `step` mm along a row at y = 90 mm
/// (or down a column at x = 40 mm, each label ending there).
fn axis(values: &[&str], step: f64, column: bool) -> Vec<Element> {
    values
        .iter()
        .enumerate()
        .map(|(k, v)| {
            let mut e = if column {
                text(&format!("t{k}"), v, 40.0, 10.0 + step * k as f64)
            } else {
                text(&format!("t{k}"), v, 10.0 + step * k as f64, 90.0)
            };
            if let (true, Shape::Text(t)) = (column, &mut e.shape) {
                t.runs[0].anchor = 1.0;
            }
            e
        })
        .collect()
}

/// The element numbers a plan left out as thinned, with their steps.
fn thinned(plan: &Plan) -> Vec<(usize, u8)> {
    plan.decisions
        .iter()
        .enumerate()
        .filter_map(|(i, d)| match d.left_out {
            Some(LeftOut::Thinned { every }) => Some((i, every)),
            _ => None,
        })
        .collect()
}

#[test]
fn an_axis_whose_labels_would_run_together_keeps_them_at_an_even_step() {
    // 0 to 100 every 8 mm: "100" is four cells (over 20 mm), so every other
    // label still meets the next kept one, and every fifth stands clear.
    let values = ["0", "10", "20", "30", "40", "50", "60", "70", "80", "90", "100"];
    let mut d = Drawing { page: page(200.0, 100.0), elements: axis(&values, 8.0, false), ..Default::default() };
    let mut diags = Vec::new();
    let plan = apply(&mut d, &stress2(), &mut diags);
    let left = thinned(&plan);
    let kept: Vec<usize> = (0..values.len()).filter(|i| !left.iter().any(|l| l.0 == *i)).collect();
    assert_eq!(kept, [0, 5, 10], "{left:?}");
    assert!(left.iter().all(|l| l.1 == 5), "{left:?}");
    // The kept labels are written, and nothing else piles up under the axis.
    assert!(kept.iter().all(|&i| plan.decisions[i].braille), "{:?}", plan.decisions);
    let notes: Vec<_> = diags.iter().filter(|d| d.code == "T0328").collect();
    assert_eq!(notes.len(), 1, "{diags:#?}");
    assert!(notes[0].message.starts_with("8 tick label(s) left out") && notes[0].message.contains("to every 5th,"));
    assert!(notes[0].message.contains("#t1, #t2, #t3 and 5 more"), "{}", notes[0].message);

    // A column of values 4 mm apart (braille is a cell over 6 mm high): every fifth.
    let values = ["0", "1", "2", "3", "4", "5", "6", "7", "8", "9", "10"];
    let d = Drawing { page: page(200.0, 100.0), elements: axis(&values, 4.0, true), ..Default::default() };
    let left = thinned(&plan_of(&d));
    assert_eq!(left.len(), 8, "{left:?}");
    assert!(left.iter().all(|&(i, every)| i % 5 != 0 && every == 5), "{left:?}");
}

#[test]
fn labels_that_stand_clear_or_are_not_ticks_are_not_thinned() {
    // Far enough apart for their braille.
    let values = ["0", "10", "20", "30", "40", "50"];
    let d = Drawing { page: page(200.0, 100.0), elements: axis(&values, 30.0, false), ..Default::default() };
    let plan = plan_of(&d);
    assert!(thinned(&plan).is_empty());
    assert!(plan.decisions.iter().all(|d| d.braille), "{:?}", plan.decisions);
    // Words as close: names, not an axis's values.
    let words = ["Lyon", "Nice", "Metz", "Caen", "Brest", "Dijon"];
    assert!(
        thinned(&plan_of(&Drawing {
            page: page(200.0, 100.0),
            elements: axis(&words, 8.0, false),
            ..Default::default()
        }))
        .is_empty()
    );
    // Three values are not an axis; nor are values unevenly spaced.
    assert!(
        thinned(&plan_of(&Drawing {
            page: page(200.0, 100.0),
            elements: axis(&values[..3], 8.0, false),
            ..Default::default()
        }))
        .is_empty()
    );
    let mut uneven = axis(&values, 8.0, false);
    if let Shape::Text(t) = &mut uneven[5].shape {
        t.runs[0].x_mm += 30.0;
    }
    assert!(
        thinned(&plan_of(&Drawing { page: page(200.0, 100.0), elements: uneven, ..Default::default() })).is_empty()
    );
}
