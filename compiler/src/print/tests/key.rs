//! The key pages on paper: each texture, line and symbol felt as itself
//! beside its meaning in braille, over as many pages as it needs.

use super::*;

#[test]
fn the_key_is_a_page_of_its_own() {
    let mut t = label("k", "ab", 30.0, 40.0);
    if let Shape::Text(ts) = &mut t.shape {
        ts.keyed = Some("Abbey Road".into());
    }
    let d = drawing(vec![t, path("a", rect(20.0, 60.0, 60.0, 40.0), vec![vibrate(1.5, 50.0)])]);
    let (s, _) = sheet(&d, "swell-a4");
    assert_eq!(s.pages.len(), 2);
    // Braille, and the one line style's sample (a key that is written lists
    // every entry), drawn for the line's element.
    let (braille, rest): (Vec<&Mark>, Vec<&Mark>) = s.pages[1].iter().partition(|m| m.element.is_none());
    assert!(braille.iter().all(|m| matches!(m.shape, MarkShape::Dot { .. }) && m.level == Level::Braille));
    assert!(braille.len() > 20);
    assert!(rest.iter().all(|m| m.element == Some(1) && matches!(m.shape, MarkShape::Line { .. })), "{rest:?}");
    assert_eq!(rest.len(), 1, "a solid line's sample is one line");
}

/// How a set of marks is felt, as the key must repeat it: the texture's
/// direction or dots, the line style, the symbol's shape.
fn felt_as(marks: &[&Mark]) -> String {
    let lines: Vec<&Vec<(f64, f64)>> = marks
        .iter()
        .filter_map(|m| match &m.shape {
            MarkShape::Line { points, .. } => Some(points),
            _ => None,
        })
        .collect();
    let dots: Vec<f64> = marks
        .iter()
        .filter_map(|m| match m.shape {
            MarkShape::Dot { diameter_mm, .. } => Some(diameter_mm),
            _ => None,
        })
        .collect();
    let polygons: Vec<usize> = marks
        .iter()
        .filter_map(|m| match &m.shape {
            MarkShape::Polygon { rings } => Some(rings[0].len()),
            _ => None,
        })
        .collect();
    let level = marks.first().map(|m| m.level);
    if level == Some(Level::Texture) {
        // A hatch's directions, rounded to degrees, as a sorted set.
        let mut dirs: Vec<i64> = lines
            .iter()
            .map(|p| {
                let (a, b) = (p[0], p[p.len() - 1]);
                ((b.1 - a.1).atan2(b.0 - a.0).to_degrees().rem_euclid(180.0).round() as i64) % 180
            })
            .collect();
        dirs.sort();
        dirs.dedup();
        return format!("texture lines {dirs:?} dots {}", dots.first().map_or(0.0, |d| *d));
    }
    match (lines.len(), dots.len(), polygons.as_slice()) {
        (0, 0, [n]) => format!("polygon of {n}"),
        (0, 1, []) => format!("disc {}", dots[0]),
        (0, n, []) if n > 1 => "dotted".into(),
        (1, 0, []) => "solid".into(),
        (2, 0, []) => "double".into(),
        (n, 0, []) if n > 2 => "dashed".into(),
        other => format!("{other:?}"),
    }
}

/// The braille cells of `text` as the key writes them (the crate's braille
/// service, six dots).
fn braille_cells(text: &str, profile: &DeviceProfile) -> Vec<u8> {
    let opts = crate::CompileOptions::new(*profile);
    crate::braille::translate(text, None, &opts, None, false).cells.iter().map(|c| c & 0x3f).collect()
}

/// Whether the braille dots `dots` are the cells `cells`, moved as a whole
/// (so where the key puts them does not matter, only what they say).
fn says(dots: &[(f64, f64)], cells: &[u8], q: &PrintParams) -> bool {
    let mut want = super::braille::run_dots(q, cells, 0.0, 0.0);
    let mut got = dots.to_vec();
    let order = |a: &(f64, f64), b: &(f64, f64)| (a.1, a.0).partial_cmp(&(b.1, b.0)).unwrap();
    want.sort_by(order);
    got.sort_by(order);
    if want.len() != got.len() || want.is_empty() {
        return false;
    }
    let d = (got[0].0 - want[0].0, got[0].1 - want[0].1);
    want.iter().zip(&got).all(|(w, g)| (w.0 + d.0 - g.0).abs() < 1e-6 && (w.1 + d.1 - g.1).abs() < 1e-6)
}

#[test]
fn the_key_page_holds_each_texture_line_and_symbol_felt_as_itself_with_its_meaning() {
    let named = |mut e: Element, label: &str| {
        e.label = label.into();
        e
    };
    let line = |k: usize| {
        vec![Polyline {
            points: vec![(10.0, 120.0 + 10.0 * k as f64), (150.0, 120.0 + 10.0 * k as f64)],
            closed: false,
        }]
    };
    let dot = |r: f64| Style::Dot(Dot { radius_mm: r, amplitude: 1.0 });
    let d = drawing(vec![
        named(path("forest", rect(10.0, 10.0, 50.0, 40.0), vec![grating(2.0, 0.0)]), "Forest"),
        named(path("lake", rect(70.0, 10.0, 50.0, 40.0), vec![grating(6.0, 45.0)]), "Lake"),
        named(path("fields", rect(10.0, 60.0, 50.0, 40.0), vec![grating(4.0, 90.0)]), "Fields"),
        named(path("road", line(0), vec![vibrate(1.5, 50.0)]), "Road"),
        named(path("rail", line(1), vec![vibrate(1.5, 120.0)]), "Railway"),
        named(path("town", rect(130.0, 20.0, 2.0, 2.0), vec![dot(1.0)]), "Town"),
        named(path("well", rect(150.0, 20.0, 2.0, 2.0), vec![dot(2.0)]), "Well"),
    ]);
    let (s, diags) = sheet(&d, "swell-a4");
    let (p, q) = profile("swell-a4");
    assert_eq!(s.pages.len(), 2, "{diags:?}");
    assert!(!diags.iter().any(|d| d.code == "T0727"), "one page, no note");
    let key = &s.pages[1];
    let braille: Vec<(f64, f64)> = key
        .iter()
        .filter(|m| m.element.is_none())
        .filter_map(|m| match m.shape {
            MarkShape::Dot { centre, .. } => Some(centre),
            _ => None,
        })
        .collect();
    let mut felt = Vec::new();
    for (i, e) in d.elements.iter().enumerate() {
        fn on(page: &[Mark], i: usize) -> Vec<&Mark> {
            page.iter().filter(|m| m.element == Some(i)).collect()
        }
        let swatch = on(key, i);
        assert!(!swatch.is_empty(), "{}: no swatch", e.name);
        // Felt as on the graphic: the same texture, line style or symbol.
        assert_eq!(felt_as(&swatch), felt_as(&on(&s.pages[0], i)), "{}", e.name);
        felt.push(felt_as(&swatch));
        // Its meaning in braille, on the swatch's line, to its right.
        let (mut y0, mut y1, mut x1) = (f64::MAX, f64::MIN, f64::MIN);
        for m in &swatch {
            let pts: Vec<(f64, f64)> = match &m.shape {
                MarkShape::Line { points, .. } => points.clone(),
                MarkShape::Dot { centre, .. } => vec![*centre],
                MarkShape::Polygon { rings } => rings.concat(),
            };
            for (x, y) in pts {
                (y0, y1, x1) = (y0.min(y), y1.max(y), x1.max(x));
            }
        }
        let mid = (y0 + y1) / 2.0;
        let beside: Vec<(f64, f64)> = braille.iter().copied().filter(|b| (b.1 - mid).abs() < 4.0 && b.0 > x1).collect();
        assert!(says(&beside, &braille_cells(&e.label, &p), &q), "{}: {beside:?}", e.label);
    }
    // Every entry is told apart from the others of its kind.
    let mut distinct = felt.clone();
    distinct.sort();
    distinct.dedup();
    assert_eq!(distinct.len(), felt.len(), "{felt:?}");
}

#[test]
fn a_long_key_goes_on_over_more_pages_and_leaves_nothing_out() {
    // Thirty line styles (the medium has four: they are shared on the
    // graphic, but each is its own entry with its own meaning).
    let elements: Vec<Element> = (0..30)
        .map(|k| {
            let y = 5.0 + 5.0 * k as f64;
            let mut e = path(
                &format!("l{k}"),
                vec![Polyline { points: vec![(10.0, y), (150.0, y)], closed: false }],
                vec![vibrate(1.5, 40.0 + k as f64)],
            );
            e.label = format!("line {k}");
            e
        })
        .collect();
    let d = drawing(elements);
    let (s, diags) = sheet(&d, "swell-a4");
    assert!(s.pages.len() >= 3, "{}", s.pages.len());
    let note = diags.iter().find(|d| d.code == "T0727").expect("a note says the key takes pages");
    assert!(note.message.contains(&format!("{} pages", s.pages.len() - 1)), "{}", note.message);
    for k in 0..30 {
        let pages = s.pages[1..].iter().filter(|p| p.iter().any(|m| m.element == Some(k))).count();
        assert_eq!(pages, 1, "line {k}'s sample is on one key page");
    }
    // Every mark lies on the printable area.
    let (_, q) = profile("swell-a4");
    let m = q.margin_mm as f64;
    for page in &s.pages[1..] {
        for mk in page {
            if let MarkShape::Dot { centre, .. } = mk.shape {
                assert!(centre.1 > m && centre.1 < q.paper_h_mm as f64 - m, "{centre:?}");
            }
        }
    }
}

/// A key entry whose meaning is a paragraph (a label of thousands of
/// words) goes on over as many pages as its lines take: it was laid out on
/// one page and ran off its bottom, unseen, while the note said that none
/// of it was left out.
#[test]
fn a_key_entry_longer_than_a_page_goes_on_over_pages() {
    let mut e = path(
        "long",
        vec![Polyline { points: vec![(10.0, 20.0), (150.0, 20.0)], closed: false }],
        vec![vibrate(1.5, 50.0)],
    );
    e.label = "a long legend text ".repeat(200);
    let mut short = path(
        "short",
        vec![Polyline { points: vec![(10.0, 60.0), (150.0, 60.0)], closed: false }],
        vec![vibrate(1.5, 80.0)],
    );
    short.label = "a road".into();
    let d = drawing(vec![e, short]);
    let (s, diags) = sheet(&d, "swell-a4");
    assert!(s.pages.len() >= 4, "{} pages", s.pages.len());
    let note = diags.iter().find(|d| d.code == "T0727").expect("a note says the key takes pages");
    assert!(note.message.contains(&format!("{} pages", s.pages.len() - 1)), "{}", note.message);
    let (pr, q) = profile("swell-a4");
    let m = q.margin_mm as f64;
    let mut dots = 0;
    for page in &s.pages[1..] {
        for mk in page {
            if let MarkShape::Dot { centre, .. } = mk.shape {
                dots += 1;
                assert!(centre.1 > m && centre.1 < q.paper_h_mm as f64 - m, "{centre:?}");
            }
        }
    }
    // Every cell's dots are there: the text's braille, less nothing.
    let cells = braille_cells(&"a long legend text ".repeat(200), &pr);
    let raised: usize = cells.iter().map(|c| c.count_ones() as usize).sum();
    assert!(dots >= raised, "{dots} dots for {raised}");
}
