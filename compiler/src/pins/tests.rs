//! The legaliser on hand-built drawings, asserted through the Unicode braille
//! art that `taxel export --format unicode` writes (decoded back to pins
//! where a property is checked).

use std::collections::HashSet;

use taxel_format::{Navigation, PinImage, profiles};

use super::export::unicode;
use super::*;
use crate::annotation::{Braille, Dot, Dots, Grating, Style, Vibrate};
use crate::drawing::{Clip, Element, Page, PathShape, TextRun, TextShape};

const VIBRATE: Style = Style::Vibrate(Vibrate { width_mm: 1.5, freq_hz: 50.0, amplitude: 1.0, soft_mm: 0.0 });

fn grating(wavelength_mm: f64, angle_deg: f64) -> Style {
    Style::Grating(Grating { wavelength_mm, angle_deg, amplitude: 1.0, soft_mm: 0.0 })
}

fn path(name: &str, points: &[(f64, f64)], closed: bool, styles: Vec<Style>) -> Element {
    Element {
        name: name.into(),
        line: 3,
        visible: true,
        styles,
        shape: Shape::Path(PathShape {
            outline: vec![Polyline { points: points.to_vec(), closed }],
            ..Default::default()
        }),
        ..Default::default()
    }
}

fn label(name: &str, text: &str, x: f64, y: f64) -> Element {
    Element {
        name: name.into(),
        visible: true,
        styles: vec![Style::Braille(Braille { radius_mm: 0.72, amplitude: 1.0, grade: None })],
        shape: Shape::Text(TextShape {
            content: text.into(),
            runs: vec![TextRun { text: text.into(), x_mm: x, y_mm: y, anchor: 0.0, continues: false }],
            font_size_mm: 4.0,
            ..Default::default()
        }),
        ..Default::default()
    }
}

fn drawing(w: f64, h: f64, elements: Vec<Element>) -> Drawing {
    Drawing {
        page: Page { width_mm: w, height_mm: h, scale: 1.0, offset_mm: (0.0, 0.0), sheet_mm: None },
        title: String::new(),
        elements,
    }
}

fn run(profile: &str, d: &Drawing) -> (PinImage, Vec<Diagnostic>) {
    let mut diags = Vec::new();
    let image = legalise(d, &profiles::builtin(profile).unwrap(), &mut diags).expect("legalised");
    (image, diags)
}

/// Decodes Unicode braille art back to the set of raised pins, from the
/// dot positions of `reference/pins.md` alone.
fn decode_art(art: &str) -> HashSet<(i64, i64)> {
    let pos = [(0, 0), (0, 1), (0, 2), (1, 0), (1, 1), (1, 2), (0, 3), (1, 3)];
    let mut out = HashSet::new();
    for (line, text) in art.lines().enumerate() {
        for (k, ch) in text.chars().enumerate() {
            let m = (ch as u32).wrapping_sub(0x2800);
            assert!(m < 256, "not a braille character: {ch:?}");
            for (bit, (dc, dr)) in pos.iter().enumerate() {
                if m & (1 << bit) != 0 {
                    out.insert((k as i64 * 2 + dc, line as i64 * 4 + dr));
                }
            }
        }
    }
    out
}

/// The art's lines from `first` to `last` (inclusive), columns `from..to` (in characters).
fn crop(art: &str, lines: std::ops::RangeInclusive<usize>, cols: std::ops::Range<usize>) -> String {
    art.lines()
        .skip(*lines.start())
        .take(lines.end() - lines.start() + 1)
        .map(|l| l.chars().skip(cols.start).take(cols.end - cols.start).collect::<String>() + "\n")
        .collect()
}

#[test]
fn lines_at_every_5_degrees_are_unbroken_one_pin_wide_and_never_doubled() {
    for step in 0..=36 {
        let a = (step as f64 * 5.0).to_radians();
        // A 40 mm line through the middle of the Dot Pad (16 pins long), y down the page.
        let (cx, cy, half) = (75.0, 50.0, 20.0);
        let ends = [(cx - half * a.cos(), cy + half * a.sin()), (cx + half * a.cos(), cy - half * a.sin())];
        let (image, _) = run("dotpad", &drawing(150.0, 100.0, vec![path("l", &ends, false, vec![VIBRATE])]));
        let pins = decode_art(&unicode(&image));
        let deg = step * 5;
        // Unbroken: one 8-connected component.
        let start = *pins.iter().min().unwrap();
        let mut seen = HashSet::from([start]);
        let mut todo = vec![start];
        while let Some((c, r)) = todo.pop() {
            for dr in -1..=1 {
                for dc in -1..=1 {
                    let q = (c + dc, r + dr);
                    if pins.contains(&q) && seen.insert(q) {
                        todo.push(q);
                    }
                }
            }
        }
        assert_eq!(seen.len(), pins.len(), "{deg}°: the line breaks");
        // Never thickened: no 2 x 2 block holds more than two raised pins (no L-corner, no double).
        for &(c, r) in &pins {
            let n = [(0, 0), (1, 0), (0, 1), (1, 1)].iter().filter(|(dc, dr)| pins.contains(&(c + dc, r + dr))).count();
            assert!(n <= 2, "{deg}°: a thick spot at pin ({c}, {r})");
        }
        // One pin per step along the line's major axis: exactly max(|dx|, |dy|) + 1 pins.
        let (cs, rs): (Vec<i64>, Vec<i64>) = pins.iter().copied().unzip();
        let span = |v: &[i64]| v.iter().max().unwrap() - v.iter().min().unwrap();
        assert_eq!(pins.len() as i64, span(&cs).max(span(&rs)) + 1, "{deg}°: pins = major-axis span + 1");
    }
}

#[test]
fn lines_read_as_expected_in_braille_art() {
    let art = |ends: &[(f64, f64)]| {
        let (image, _) = run("dotpad", &drawing(150.0, 100.0, vec![path("l", ends, false, vec![VIBRATE])]));
        unicode(&image)
    };
    // Horizontal: pins 26..=34 of row 19, the bottom dots (7, 8) of line 4.
    assert_eq!(crop(&art(&[(65.0, 48.75), (85.0, 48.75)]), 4..=4, 12..18), "⠀⣀⣀⣀⣀⡀\n");
    // The 45° diagonal from pin (24, 23) to pin (32, 15): one pin per row and column.
    let diag = art(&[(61.25, 58.75), (81.25, 38.75)]);
    assert_eq!(crop(&diag, 3..=5, 12..17), "⠀⠀⠀⠀⡀\n⠀⠀⡠⠊⠀\n⡠⠊⠀⠀⠀\n");
}

#[test]
fn a_rectangle_keeps_square_corners() {
    let rect = [(10.0, 10.0), (25.0, 10.0), (25.0, 20.0), (10.0, 20.0)];
    let (image, _) = run("dotpad", &drawing(150.0, 100.0, vec![path("r", &rect, true, vec![VIBRATE])]));
    // Pins 4..=10 by 4..=8 (10 / 2.5 - 0.5 = 3.5 rounds to 4).
    assert_eq!(crop(&unicode(&image), 1..=2, 2..6), "⡏⠉⠉⡇\n⠉⠉⠉⠁\n");
}

#[test]
fn gratings_become_ridges_that_keep_their_orientation() {
    let square = [(10.0, 10.0), (50.0, 10.0), (50.0, 50.0), (10.0, 50.0)];
    let art = |angle: f64| {
        let d = drawing(150.0, 100.0, vec![path("g", &square, true, vec![grating(7.5, angle)])]);
        let (image, diags) = run("dotpad", &d);
        assert!(diags.iter().all(|d| d.severity < crate::Severity::Warning), "{diags:?}");
        crop(&unicode(&image), 2..=3, 3..7)
    };
    // Period 3 pins (7.5 mm at 2.5 mm), phase from the image origin.
    assert_eq!(art(0.0), "⠒⠒⠒⠒\n⣉⣉⣉⣉\n", "horizontal ridges every third row");
    assert_eq!(art(90.0), "⡇⢸⠀⡇\n⡇⢸⠀⡇\n", "vertical ridges every third column");
    assert_eq!(art(45.0), "⢊⠔⡡⢊\n⡡⢊⠔⡡\n", "ridges rising to the right");
    assert_eq!(art(135.0), "⠢⡑⢌⠢\n⡑⢌⠢⡑\n", "ridges falling to the right");
}

#[test]
fn a_texture_keeps_one_blank_pin_from_its_outline_which_stands_above_it() {
    let square = [(10.0, 10.0), (40.0, 10.0), (40.0, 40.0), (10.0, 40.0)];
    let d = drawing(150.0, 100.0, vec![path("g", &square, true, vec![VIBRATE, grating(5.0, 90.0)])]);
    let (image, _) = run("graphiti", &d);
    let outline: HashSet<(u32, u32)> = (0..image.rows)
        .flat_map(|r| (0..image.cols).map(move |c| (c, r)))
        .filter(|&(c, r)| image.get(c, r).height() == 4)
        .collect();
    let texture: Vec<(u32, u32)> = (0..image.rows)
        .flat_map(|r| (0..image.cols).map(move |c| (c, r)))
        .filter(|&(c, r)| image.get(c, r).height() == 2)
        .collect();
    assert_eq!(outline.len(), 48, "the outline at the top height, 13 pins a side");
    assert!(!texture.is_empty(), "textures at half height");
    for &(c, r) in &texture {
        for dr in -1..=1i64 {
            for dc in -1..=1i64 {
                let q = ((c as i64 + dc) as u32, (r as i64 + dr) as u32);
                assert!(!outline.contains(&q), "texture pin ({c}, {r}) touches the outline");
            }
        }
        assert_eq!(c % 2, 0, "ridges every 2 pins, on even columns");
    }
    // Blinking outline on the Graphiti (it blinks), half-period 500 ms.
    assert!(outline.iter().all(|&(c, r)| image.get(c, r).blinks()));
    assert_eq!(image.blink_ms, 500);
    assert!(texture.iter().all(|&(c, r)| !image.get(c, r).blinks()));
    // On the Dot Pad (no blink) the same outline is solid.
    let (image, _) = run("dotpad", &d);
    assert!(image.pins.iter().all(|p| !p.blinks()) && image.blink_ms == 0);
}

#[test]
fn gratings_that_would_feel_the_same_get_distinct_textures() {
    let a = [(10.0, 10.0), (40.0, 10.0), (40.0, 40.0), (10.0, 40.0)];
    let b = [(60.0, 10.0), (90.0, 10.0), (90.0, 40.0), (60.0, 40.0)];
    // 6 mm and 7 mm both round to 2 pins at 2.5 mm.
    let d = drawing(
        150.0,
        100.0,
        vec![path("a", &a, true, vec![grating(6.0, 90.0)]), path("b", &b, true, vec![grating(7.0, 90.0)])],
    );
    let (image, diags) = run("dotpad", &d);
    assert!(diags.iter().any(|d| d.code == "T0706" && d.element.as_deref() == Some("b")), "{diags:?}");
    // (On the graphic's page: two gratings get a key page after it, whose
    // braille is no texture.)
    assert_eq!(image.rows, 80);
    let cols_of =
        |c0: u32, c1: u32| -> Vec<u32> { (c0..c1).filter(|&c| (0..40).any(|r| image.get(c, r).raised())).collect() };
    let (ca, cb) = (cols_of(0, 20), cols_of(20, 40));
    assert!(ca.windows(2).all(|w| w[1] - w[0] == 2), "a: every 2 pins: {ca:?}");
    assert!(cb.windows(2).all(|w| w[1] - w[0] == 4), "b: every 4 pins: {cb:?}");
}

#[test]
fn braille_sits_on_the_devices_cell_grid() {
    // "ab" with its baseline at 21 mm, starting at 16 mm: dotpad cells are
    // 3 pins apart (2 + 1 blank) on lines 4 pins apart (3 + 1 blank).
    let d = drawing(150.0, 100.0, vec![label("t", "ab", 16.0, 21.0)]);
    let (image, _) = run("dotpad", &d);
    // Start pin 5.9 -> cell 2 (column 6); top row 7.9 - 2 = 5.9 -> line 1 (row 4).
    let raised: Vec<(u32, u32)> = (0..image.rows)
        .flat_map(|r| (0..image.cols).map(move |c| (c, r)))
        .filter(|&(c, r)| image.get(c, r).raised())
        .collect();
    // a = dot 1; b = dots 1, 2.
    assert_eq!(raised, vec![(6, 4), (9, 4), (9, 5)]);
    // Monarch: eight-dot cells, 3 columns and 5 rows apart.
    let (image, _) = run("monarch", &d);
    let raised: Vec<(u32, u32)> = (0..image.rows)
        .flat_map(|r| (0..image.cols).map(move |c| (c, r)))
        .filter(|&(c, r)| image.get(c, r).raised())
        .collect();
    // Top row 7.9 - 3 = 4.9 -> line 1 (row 5).
    assert_eq!(raised, vec![(6, 5), (9, 5), (9, 6)]);
}

/// A label whose letters all lack braille is left out whole: its
/// punctuation alone would put cells on the display that say nothing. A
/// label that keeps some letters keeps its punctuation too.
#[test]
fn a_label_in_another_script_raises_no_pins_for_its_punctuation() {
    let raised = |image: &PinImage| {
        (0..image.rows)
            .flat_map(|r| (0..image.cols).map(move |c| (c, r)))
            .filter(|&(c, r)| image.get(c, r).raised())
            .count()
    };
    for profile in ["dotpad", "monarch"] {
        let (image, diags) = run(profile, &drawing(150.0, 100.0, vec![label("t", "Осадки (мм), 2024", 16.0, 21.0)]));
        // The digits stay: "2024" keeps the label.
        assert!(raised(&image) > 0, "{profile}");
        let w: Vec<_> = diags.iter().filter(|d| d.code == "T0304").collect();
        assert!(w.len() == 1 && w[0].message.contains("these characters are left out"), "{profile}: {w:?}");
        let (image, diags) = run(profile, &drawing(150.0, 100.0, vec![label("t", "Осадки (мм)", 16.0, 21.0)]));
        assert_eq!(raised(&image), 0, "{profile}: the parentheses alone are left out");
        let w: Vec<_> = diags.iter().filter(|d| d.code == "T0304").collect();
        assert!(w.len() == 1 && w[0].message.contains("the text is left out"), "{profile}: {w:?}");
        assert!(w[0].help.as_deref().is_some_and(|h| h.contains("Latin letters")), "{profile}: {w:?}");
    }
    // The title on the Dot Pad's text line, the same way.
    let mut d = drawing(150.0, 100.0, vec![path("l", &[(10.0, 10.0), (50.0, 10.0)], false, vec![VIBRATE])]);
    d.title = "«Карта»".into();
    assert!(run("dotpad", &d).0.text.is_empty());
}

#[test]
fn the_title_goes_to_the_text_line_where_there_is_one() {
    let mut d = drawing(150.0, 100.0, vec![path("l", &[(10.0, 10.0), (50.0, 10.0)], false, vec![VIBRATE])]);
    d.title = "Map".into();
    let (image, _) = run("dotpad", &d);
    // UEB grade 1: capital sign (dot 6), m (1 3 4), a (1), p (1 2 3 4).
    assert_eq!(image.text, vec![0x20, 0x0D, 0x01, 0x0F]);
    assert!(run("graphiti", &d).0.text.is_empty(), "the Graphiti has no text line");
}

#[test]
fn labels_over_graphics_and_elements_too_close_are_reported() {
    let d = drawing(
        150.0,
        100.0,
        vec![
            path("a", &[(10.0, 10.0), (60.0, 10.0)], false, vec![VIBRATE]),
            path("b", &[(10.0, 12.5), (60.0, 12.5)], false, vec![VIBRATE]),
            path("c", &[(10.0, 30.0), (60.0, 30.0)], false, vec![VIBRATE]),
            label("name", "x", 20.0, 33.0),
        ],
    );
    let (_, diags) = run("dotpad", &d);
    let codes: Vec<(&str, Option<&str>)> = diags.iter().map(|d| (d.code, d.element.as_deref())).collect();
    assert!(codes.contains(&("T0703", Some("a"))), "{codes:?}");
    assert!(codes.contains(&("T0704", Some("name"))), "{codes:?}");
    assert!(!codes.iter().any(|(c, e)| *c == "T0703" && *e == Some("c")), "c is two pins from b: {codes:?}");
}

#[test]
fn two_shapes_of_one_element_too_close_are_named_as_its_parts() {
    // A `<use>` of a group gives its shapes the one name.
    let d = drawing(
        150.0,
        100.0,
        vec![
            path("use1", &[(10.0, 10.0), (60.0, 10.0)], false, vec![VIBRATE]),
            path("use1", &[(10.0, 12.5), (60.0, 12.5)], false, vec![VIBRATE]),
        ],
    );
    let (_, diags) = run("dotpad", &d);
    let m: Vec<&str> = diags.iter().filter(|d| d.code == "T0703").map(|d| d.message.as_str()).collect();
    assert!(!m.is_empty() && m.iter().all(|m| m.starts_with("two parts of use1 are")), "{m:?}");
}

#[test]
fn a_texture_the_pitch_cannot_carry_is_reported() {
    let square = [(10.0, 10.0), (40.0, 10.0), (40.0, 40.0), (10.0, 40.0)];
    let (_, diags) = run("dotpad", &drawing(150.0, 100.0, vec![path("g", &square, true, vec![grating(2.0, 0.0)])]));
    assert!(diags.iter().any(|d| d.code == "T0705"), "{diags:?}");
    let tiny = [(10.0, 10.0), (16.0, 10.0), (16.0, 16.0), (10.0, 16.0)];
    let (_, diags) = run("dotpad", &drawing(150.0, 100.0, vec![path("g", &tiny, true, vec![grating(5.0, 0.0)])]));
    assert!(diags.iter().any(|d| d.code == "T0707"), "{diags:?}");
}

/// A region that holds one ridge of its texture (a chart's bar two pins
/// wide) would be felt as a line, like an outline: it is filled solid, with
/// T0707 saying so, unless another grated region comes within a pin of it.
/// A region with two ridges or more keeps its texture.
#[test]
fn a_region_too_narrow_for_two_ridges_is_filled_solid() {
    let raised_in = |image: &PinImage| {
        (0..image.rows)
            .flat_map(|r| (0..image.cols).map(move |c| (c, r)))
            .filter(|&(c, r)| image.get(c, r).raised())
            .count()
    };
    let bar = |w: f64| [(20.0, 20.0), (20.0 + w, 20.0), (20.0 + w, 50.0), (20.0, 50.0)];
    // Vertical ridges every 2 pins (5 mm at 2.5 mm). Bars 30 mm tall (pins
    // 8 to 19, centres 21.25 to 48.75 mm) and 2.5 or 5 mm wide: pins 8, or
    // 8 and 9, one ridge (column 8): every pin raised.
    for (w, cols) in [(2.5, 1), (5.0, 2)] {
        let (image, diags) =
            run("dotpad", &drawing(150.0, 100.0, vec![path("bar", &bar(w), true, vec![grating(5.0, 90.0)])]));
        assert_eq!(raised_in(&image), cols * 12, "{w} mm: {}", unicode(&image));
        let w707: Vec<_> = diags.iter().filter(|d| d.code == "T0707").collect();
        assert!(w707.len() == 1 && w707[0].message.contains("filled solid"), "{w} mm: {diags:?}");
    }
    // Two such bars side by side (pins 8-9 and 10-11) would merge into one
    // solid block: they keep their ridges (columns 8 and 10), as the
    // touching provinces of a map shrunk onto the display do.
    let other = [(25.0, 20.0), (30.0, 20.0), (30.0, 50.0), (25.0, 50.0)];
    let pair =
        vec![path("a", &bar(5.0), true, vec![grating(5.0, 90.0)]), path("b", &other, true, vec![grating(5.0, 90.0)])];
    let (image, diags) = run("dotpad", &drawing(150.0, 100.0, pair));
    assert_eq!(raised_in(&image), 2 * 12, "{}", unicode(&image));
    assert!(!diags.iter().any(|d| d.message.contains("filled solid")), "{diags:?}");
    // 7.5 mm: pins 8 to 10, two ridges (8 and 10), a texture.
    let (image, diags) =
        run("dotpad", &drawing(150.0, 100.0, vec![path("bar", &bar(7.5), true, vec![grating(5.0, 90.0)])]));
    assert_eq!(raised_in(&image), 2 * 12, "{}", unicode(&image));
    assert!(!diags.iter().any(|d| d.message.contains("filled solid")), "{diags:?}");
}

/// Lines closer than a pin fill the display solid: one warning says the
/// picture is too dense, where T0703 lists pairs. Solid bars and a texture
/// are not.
#[test]
fn a_picture_packed_solid_is_reported_once() {
    let streets: Vec<Element> = (0..40)
        .map(|k| {
            path(
                &format!("street{k}"),
                &[(10.0, 10.0 + 2.0 * k as f64), (90.0, 10.0 + 2.0 * k as f64)],
                false,
                vec![VIBRATE],
            )
        })
        .collect();
    let (_, diags) = run("dotpad", &drawing(150.0, 100.0, streets));
    let w: Vec<_> = diags.iter().filter(|d| d.code == "T0709").collect();
    assert!(w.len() == 1 && w[0].message.contains("too dense"), "{w:?}");
    // Two solid bars three pins wide and a textured square: no T0709.
    let bar = |x: f64| vec![(x, 20.0), (x + 5.0, 20.0), (x + 5.0, 80.0), (x, 80.0)];
    let square = [(60.0, 20.0), (100.0, 20.0), (100.0, 60.0), (60.0, 60.0)];
    let d = drawing(
        150.0,
        100.0,
        vec![
            path("a", &bar(20.0), true, vec![grating(5.0, 90.0)]),
            path("b", &bar(40.0), true, vec![grating(5.0, 90.0)]),
            path("c", &square, true, vec![grating(5.0, 0.0)]),
        ],
    );
    let (image, diags) = run("dotpad", &d);
    assert!(raised_count(&image) > 150, "{}", unicode(&image));
    assert!(!diags.iter().any(|d| d.code == "T0709"), "{diags:?}");
}

fn raised_count(image: &PinImage) -> usize {
    image.pins.iter().filter(|p| p.raised()).count()
}

#[test]
fn dots_become_pin_clusters() {
    let mut sym = path("city", &[(49.0, 49.0), (51.0, 49.0), (51.0, 51.0), (49.0, 51.0)], true, vec![]);
    sym.styles = vec![Style::Dot(Dot { radius_mm: 2.5, amplitude: 1.0 })];
    let trail = path(
        "trail",
        &[(10.0, 80.0), (110.0, 80.0)],
        false,
        vec![Style::Dots(Dots { radius_mm: 1.0, spacing_mm: None, amplitude: 1.0 })],
    );
    let (image, _) = run("dotpad", &drawing(150.0, 100.0, vec![sym, trail]));
    // The city: a 2 x 2 cluster on the pins around (50, 50) mm = pin (19.5, 19.5).
    let city: Vec<(u32, u32)> =
        (15..25).flat_map(|r| (15..25).map(move |c| (c, r))).filter(|&(c, r)| image.get(c, r).raised()).collect();
    assert_eq!(city, vec![(19, 19), (20, 19), (19, 20), (20, 20)]);
    // The trail: 2 x 2 clusters 4 pins apart (two blank pins between).
    let row: String = (0..image.cols).map(|c| if image.get(c, 31).raised() { '#' } else { '.' }).collect();
    assert_eq!(&row[..20], "...##..##..##..##..#");
}

#[test]
fn a_drawing_larger_than_the_display_is_paged_or_panned() {
    let d = drawing(300.0, 120.0, vec![path("l", &[(10.0, 10.0), (290.0, 110.0)], false, vec![VIBRATE])]);
    let (image, diags) = run("dotpad", &d);
    assert_eq!((image.cols, image.rows, image.navigation), (120, 48, Navigation::Pages));
    assert!(diags.iter().any(|d| d.code == "T0702" && d.message.contains("4 pages")), "{diags:?}");
    let (image, _) = run("hyperbraille", &d);
    assert_eq!((image.cols, image.rows, image.navigation), (120, 60, Navigation::Pan));
}

#[test]
fn hostile_drawings_give_errors_not_panics() {
    let mut diags = Vec::new();
    let huge = drawing(1e9, 1e9, vec![path("l", &[(0.0, 0.0), (1e9, 1e9)], false, vec![VIBRATE])]);
    assert!(legalise(&huge, &profiles::builtin("dotpad").unwrap(), &mut diags).is_none());
    assert!(diags.iter().any(|d| d.code == "T0701" && d.severity == crate::Severity::Error));
    let wild = drawing(
        150.0,
        100.0,
        vec![path(
            "w",
            &[(f64::NAN, 1.0), (1e300, -1e300), (f64::INFINITY, 0.0), (5.0, 5.0)],
            true,
            vec![VIBRATE, grating(f64::NAN, f64::INFINITY)],
        )],
    );
    let (image, _) = run("dotpad", &wild);
    assert_eq!((image.cols, image.rows), (60, 40));
    assert!(legalise(&wild, &profiles::builtin("stress2").unwrap(), &mut Vec::new()).is_none());
}

/// A clipped shape raises pins only inside its clip regions (or on their
/// edges): a page-sized rectangle clipped to a square in the middle, its
/// texture and its outline; the pins were raised over the whole shape.
#[test]
fn a_clipped_shape_raises_pins_only_inside_its_clip() {
    let page = [(0.0, 0.0), (150.0, 0.0), (150.0, 100.0), (0.0, 100.0)];
    let square =
        vec![Polyline { points: vec![(50.0, 25.0), (100.0, 25.0), (100.0, 75.0), (50.0, 75.0)], closed: true }];
    let mut e = path("clipped", &page, true, vec![VIBRATE, grating(7.5, 90.0)]);
    if let Shape::Path(p) = &mut e.shape {
        p.clips = vec![Clip { outline: square.clone(), fill_rule: FillRule::NonZero }];
    }
    let (image, _) = run("dotpad", &drawing(150.0, 100.0, vec![e.clone()]));
    let raised = decode_art(&unicode(&image));
    // The square's pins: centres (c + 0.5) 2.5 mm inside or on its edge.
    let within = |(c, r): (i64, i64)| (19..=40).contains(&c) && (9..=30).contains(&r);
    assert!(!raised.is_empty() && raised.iter().all(|&p| within(p)), "{}", unicode(&image));
    // Its texture is there: vertical ridges every third column across the square.
    let columns: HashSet<i64> = raised.iter().map(|p| p.0).collect();
    assert!(columns.len() >= 6, "{columns:?}");
    // The page's outline lies wholly outside the clip: none of it is raised.
    assert!(!raised.iter().any(|&(c, r)| c == 0 || r == 0), "{}", unicode(&image));
    // Unclipped, the same shape covers the page.
    if let Shape::Path(p) = &mut e.shape {
        p.clips.clear();
    }
    let (image, _) = run("dotpad", &drawing(150.0, 100.0, vec![e]));
    assert!(decode_art(&unicode(&image)).iter().any(|&p| !within(p)));
}

/// A texture is not raised under an opaque fill painted over it (a map's
/// legend box, an inset), as the array's grated layers are not felt there;
/// the pins of both textures were raised on top of each other.
#[test]
fn a_texture_is_hidden_under_an_opaque_fill_painted_over_it() {
    let big = [(10.0, 10.0), (110.0, 10.0), (110.0, 90.0), (10.0, 90.0)];
    let small = [(40.0, 30.0), (80.0, 30.0), (80.0, 70.0), (40.0, 70.0)];
    let opaque = |mut e: Element, rgb: [u8; 3]| {
        e.paint.fill = Some([rgb[0], rgb[1], rgb[2], 255]);
        e.paint.filled = true;
        e
    };
    let under = opaque(path("under", &big, true, vec![grating(7.5, 90.0)]), [200, 0, 0]);
    // The box over it: plain (a white legend box the sheet leaves out), or with its own texture.
    for styles in [vec![], vec![grating(7.5, 0.0)]] {
        let over = opaque(path("over", &small, true, styles.clone()), [0, 0, 200]);
        let (image, _) = run("dotpad", &drawing(150.0, 100.0, vec![under.clone(), over]));
        let raised = decode_art(&unicode(&image));
        // Pins whose centres lie inside the box: columns 16..=31, rows 12..=27.
        let inside = |&(c, r): &(i64, i64)| (16..=31).contains(&c) && (12..=27).contains(&r);
        let in_box: HashSet<(i64, i64)> = raised.iter().copied().filter(inside).collect();
        if styles.is_empty() {
            assert!(in_box.is_empty(), "{}", unicode(&image));
        } else {
            // Only the box's horizontal ridges: whole rows, never a lone vertical ridge.
            let rows: HashSet<i64> = in_box.iter().map(|p| p.1).collect();
            assert!(!rows.is_empty() && rows.len() <= 6, "{rows:?}\n{}", unicode(&image));
        }
        // Around the box the texture under it stays.
        assert!(raised.iter().any(|p| !inside(p) && p.0 > 4 && p.0 < 43), "{}", unicode(&image));
    }
}

/// A label that would run off the image's right side (the device's cells
/// are wider than the page's braille) is pulled back inside, whole, ending
/// on the last cell; one that starts left of the image starts on the first.
/// Its cells past the side were left out (T0708).
#[test]
fn a_label_running_off_the_side_is_pulled_back_whole() {
    // dotpad: 60 columns, cells 3 pins apart, so cell 19 (columns 57, 58) is the last.
    for (x, want_first) in [(140.0, 57 - 3 * 3), (-4.0, 0)] {
        let d = drawing(150.0, 100.0, vec![label("t", "abcd", x, 21.0)]);
        let (image, diags) = run("dotpad", &d);
        assert!(diags.iter().all(|d| d.code != "T0708"), "{diags:?}");
        let cols: Vec<u32> = (0..image.rows)
            .flat_map(|r| (0..image.cols).map(move |c| (c, r)))
            .filter(|&(c, r)| image.get(c, r).raised())
            .map(|(c, _)| c)
            .collect();
        // a, b, c, d all start with dot 1: four cells, their left columns 3 apart.
        let first = cols.iter().copied().min();
        assert_eq!(first, Some(want_first), "x = {x}: {cols:?}");
        assert_eq!(cols.iter().copied().max(), Some(want_first + 3 * 3 + 1), "x = {x}: {cols:?}");
    }
    // Longer than the display: cut, and said so.
    let d = drawing(150.0, 100.0, vec![label("t", &"ab".repeat(15), 16.0, 21.0)]);
    let (_, diags) = run("dotpad", &d);
    assert!(diags.iter().any(|d| d.code == "T0708"), "{diags:?}");
}

/// A label inside a textured region clears the texture under its cells and
/// one pin around them, as transcribers clear an area's texture around its
/// label (braille amid ridges reads as more ridges); the texture stays
/// elsewhere, and the label is not reported as colliding with it.
#[test]
fn a_label_clears_the_texture_around_itself() {
    let region = path("lake", &[(5.0, 5.0), (145.0, 5.0), (145.0, 95.0), (5.0, 95.0)], true, vec![grating(7.5, 90.0)]);
    let name = label("name", "abc", 60.0, 50.0);
    let (alone, _) = run("dotpad", &drawing(150.0, 100.0, vec![name.clone()]));
    let braille = decode_art(&unicode(&alone));
    assert!(!braille.is_empty());
    let (image, diags) = run("dotpad", &drawing(150.0, 100.0, vec![region, name]));
    let raised = decode_art(&unicode(&image));
    // The braille's box, one pin wider each way, holds the braille alone.
    let (c0, c1) = (braille.iter().map(|p| p.0).min().unwrap_or(0), braille.iter().map(|p| p.0).max().unwrap_or(0));
    let (r0, r1) = (braille.iter().map(|p| p.1).min().unwrap_or(0), braille.iter().map(|p| p.1).max().unwrap_or(0));
    let near = |&(c, r): &(i64, i64)| (c0 - 1..=c1 + 1).contains(&c) && (r0 - 1..=r1 + 1).contains(&r);
    let around: HashSet<(i64, i64)> = raised.iter().copied().filter(near).collect();
    assert_eq!(around, braille, "{}", unicode(&image));
    // Three pins further out the texture goes on, and no collision is reported.
    let far = |&(c, r): &(i64, i64)| (c0 - 4..=c1 + 4).contains(&c) && (r0 - 4..=r1 + 4).contains(&r) && !near(&(c, r));
    assert!(raised.iter().filter(|p| far(p)).count() > 6, "{}", unicode(&image));
    assert!(diags.iter().all(|d| d.code != "T0704"), "{diags:?}");
}

/// Whether the pins of `page` (rows `r0..r0 + rows` of `image`) hold the
/// braille `cells` somewhere on one line, cell after cell at the device's
/// cell pitch (found by search, so where the key puts them does not matter).
fn holds_braille(image: &PinImage, r0: u32, rows: u32, cells: &[u8], p: &taxel_format::PinParams) -> bool {
    let cp = p.cell_pitch_cols();
    let fits = |c0: u32, r: u32| {
        cells.iter().enumerate().all(|(k, &cell)| {
            text::DOT_POSITIONS.iter().enumerate().take(p.cell_rows as usize * 2).all(|(bit, &(dc, dr))| {
                let pin = image.get(c0 + k as u32 * cp + dc, r + dr);
                pin.raised() == (cell & (1 << bit) != 0)
            })
        })
    };
    (r0..r0 + rows).any(|r| (0..image.cols).any(|c| fits(c, r)))
}

#[test]
fn the_key_is_a_display_page_after_the_graphic_with_each_texture_felt_and_its_meaning() {
    let profile = profiles::builtin("dotpad").unwrap();
    let FamilyParams::Pins(params) = profile.params else { unreachable!() };
    let region = |name: &str, x: f64, g: Style, label: &str| {
        let mut e = path(name, &[(x, 10.0), (x + 60.0, 10.0), (x + 60.0, 90.0), (x, 90.0)], true, vec![g]);
        e.label = label.into();
        e
    };
    let one = drawing(150.0, 100.0, vec![region("a", 5.0, grating(5.0, 0.0), "Forest")]);
    let two = drawing(
        150.0,
        100.0,
        vec![region("a", 5.0, grating(5.0, 0.0), "Forest"), region("b", 80.0, grating(10.0, 90.0), "Lake")],
    );
    let (plain, _) = run("dotpad", &one);
    let (keyed, diags) = run("dotpad", &two);
    // One texture needs no key; two get a page of their own.
    assert_eq!(export::pages(&plain, &profile).len(), 1);
    assert_eq!(export::pages(&keyed, &profile).len(), 2, "{diags:?}");
    assert_eq!((keyed.cols, keyed.rows), (60, 80));
    assert!(diags.iter().any(|d| d.code == "T0710" && d.message.contains("page 2")), "{diags:?}");
    let opts = crate::CompileOptions::new(profile);
    for name in ["Forest", "Lake"] {
        let cells = crate::braille::translate(name, None, &opts, None, false).cells;
        assert!(holds_braille(&keyed, 40, 40, &cells, &params), "{name}'s braille on the key page");
        assert!(!holds_braille(&keyed, 0, 40, &cells, &params), "{name} is not on the graphic");
    }
    // The swatches, left of the braille: blocks of rows apart from each
    // other, the first of horizontal ridges (rows raised across it), the
    // second of vertical ones (columns raised down it), as the textures are.
    let raised_in = |r: u32| (0..8).filter(|&c| keyed.get(c, r).raised()).count();
    let mut blocks: Vec<Vec<u32>> = Vec::new();
    for r in (40..80).filter(|&r| raised_in(r) > 0) {
        match blocks.last_mut() {
            Some(b) if r - b[b.len() - 1] < 3 => b.push(r),
            _ => blocks.push(vec![r]),
        }
    }
    assert_eq!(blocks.len(), 2, "{blocks:?}");
    let full_rows = blocks[0].iter().filter(|&&r| raised_in(r) == 8).count();
    assert!(full_rows >= 2, "horizontal ridges across the first swatch: {blocks:?}");
    let (top, bottom) = (blocks[1][0], blocks[1][blocks[1].len() - 1]);
    let full_cols = (0..8).filter(|&c| (top..=bottom).all(|r| keyed.get(c, r).raised())).count();
    assert!((2..8).contains(&full_cols), "vertical ridges down the second swatch: {full_cols}");
    // The exports carry it: DTMS one item more, Graphiti one frame more.
    let dtms = |image: &PinImage| export::dtms(image, &profile, "t", "t", "").unwrap();
    let items = |s: &str| s.matches("\"page\"").count();
    assert_eq!(items(&dtms(&keyed)), items(&dtms(&plain)) + 1);
    // Graphiti's display is 60 x 40 too: a 4,800-byte frame a page.
    let frames =
        |image: &PinImage| export::graphiti(image, &profiles::builtin("graphiti").unwrap()).unwrap().len() / 4800;
    assert_eq!(frames(&keyed), frames(&plain) + 1);
    assert_eq!(unicode(&keyed).lines().count(), unicode(&plain).lines().count() + 10);
}

#[test]
fn a_drawing_whose_key_is_not_needed_keeps_its_pages_and_a_long_key_takes_more() {
    // Twelve distinct symbols, each named: a key longer than one Dot Pad page.
    let elements: Vec<Element> = (0..12)
        .map(|k| {
            let (x, y) = (10.0 + 11.0 * (k % 12) as f64, 50.0);
            let mut e = path(
                &format!("s{k}"),
                &[(x, y), (x + 1.0, y), (x + 1.0, y + 1.0), (x, y + 1.0)],
                true,
                vec![Style::Dot(Dot { radius_mm: 1.0 + 0.01 * k as f64, amplitude: 1.0 })],
            );
            e.label = format!("symbol named {k}");
            e
        })
        .collect();
    let (image, diags) = run("dotpad", &drawing(150.0, 100.0, elements));
    let profile = profiles::builtin("dotpad").unwrap();
    let pages = export::pages(&image, &profile).len();
    assert!(pages >= 3, "{pages} pages");
    assert!(diags.iter().any(|d| d.code == "T0710" && d.message.contains(&format!("pages 2 to {pages}"))), "{diags:?}");
    let FamilyParams::Pins(params) = profile.params else { unreachable!() };
    let opts = crate::CompileOptions::new(profile);
    for k in 0..12 {
        let cells = crate::braille::translate(&format!("symbol named {k}"), None, &opts, None, false).cells;
        // (A meaning may wrap: its last word alone is found wherever it is.)
        let last = crate::braille::translate(&k.to_string(), None, &opts, None, false).cells;
        assert!(
            holds_braille(&image, 40, image.rows - 40, &cells, &params)
                || holds_braille(&image, 40, image.rows - 40, &last, &params),
            "symbol {k}"
        );
    }
}
