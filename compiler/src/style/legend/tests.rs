//! The legend stage's tests.

use super::*;
use crate::CompileOptions;
use taxel_format::profiles;

fn drawing(body: &str) -> Drawing {
    let svg = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
            width="200mm" height="150mm" viewBox="0 0 200 150">{body}</svg>"#
    );
    crate::drawing::resolve(&svg, &CompileOptions::new(profiles::builtin("swell-a4").unwrap())).drawing.unwrap()
}

const FINE: &str = "grating(wavelength: 3mm, angle: 0deg)";
const COARSE: &str = "grating(wavelength: 6mm, angle: 90deg)";

fn meanings(l: &Legend) -> Vec<(&str, Source)> {
    l.entries.iter().map(|e| (e.meaning.as_str(), e.source)).collect()
}

#[test]
fn a_legends_text_beside_its_swatch_names_the_texture() {
    // Two regions with titles that the legend overrides, and a legend of
    // two swatches in a column, each with its text to the right.
    let d = drawing(&format!(
        r#"<rect x="0" y="0" width="80" height="60" fill="green" data-tactile="{FINE}"><title>region a</title></rect>
           <rect x="90" y="0" width="80" height="60" fill="blue" data-tactile="{COARSE}"><title>region b</title></rect>
           <rect x="10" y="100" width="10" height="6" fill="green" data-tactile="{FINE}"/>
           <text x="24" y="105" font-size="5">Forest</text>
           <rect x="10" y="112" width="10" height="6" fill="blue" data-tactile="{COARSE}"/>
           <text x="24" y="117" font-size="5">Lake</text>"#
    ));
    let l = legend(&d);
    assert_eq!(meanings(&l), [("Forest", Source::Legend), ("Lake", Source::Legend)]);
    // Each entry stands for its region and its swatch.
    assert_eq!(l.entries[0].elements.len(), 2);
}

#[test]
fn a_legend_text_written_as_a_key_code_means_its_label() {
    let mut d = drawing(&format!(
        r#"<rect x="0" y="0" width="80" height="60" data-tactile="{FINE}"/>
           <rect x="90" y="0" width="80" height="60" data-tactile="{COARSE}"/>
           <rect x="10" y="100" width="10" height="6" data-tactile="{FINE}"/>
           <text x="24" y="105" font-size="5">Farmland</text>
           <rect x="10" y="112" width="10" height="6" data-tactile="{COARSE}"/>
           <text x="24" y="117" font-size="5">Lake</text>"#
    ));
    // As the automatic sheet leaves a label that finds no place: its
    // code in its place, the label it stands for kept.
    for e in &mut d.elements {
        if let Shape::Text(t) = &mut e.shape
            && t.content == "Farmland"
        {
            t.keyed = Some("Farmland".into());
            t.content = "fa".into();
            for r in &mut t.runs {
                r.text = "fa".into();
            }
        }
    }
    let l = legend(&d);
    assert_eq!(meanings(&l), [("Farmland", Source::Legend), ("Lake", Source::Legend)]);
}

#[test]
fn a_lone_text_beside_a_small_region_is_not_a_legend() {
    // A small region with its name beside it (a lake on a map): no
    // second pair lines up, so the name is not taken for the texture's.
    let d = drawing(&format!(
        r#"<rect x="0" y="0" width="80" height="60" fill="green" data-tactile="{FINE}"/>
           <rect x="100" y="10" width="10" height="6" fill="green" data-tactile="{FINE}"/>
           <text x="114" y="15" font-size="5">Small wood</text>
           <rect x="0" y="80" width="80" height="60" fill="blue" data-tactile="{COARSE}"/>"#
    ));
    let l = legend(&d);
    assert_eq!(meanings(&l), [("green areas", Source::Colour), ("blue areas", Source::Colour)]);
}

#[test]
fn a_shared_label_then_the_innermost_layer_name_the_entries() {
    let d = drawing(&format!(
        r#"<g inkscape:groupmode="layer" inkscape:label="Land use">
             <g inkscape:groupmode="layer" inkscape:label="Farmland">
               <rect x="0" y="0" width="40" height="40" fill="yellow" data-tactile="{FINE}"/>
               <rect x="50" y="0" width="40" height="40" fill="orange" data-tactile="{FINE}"/>
             </g>
             <rect x="0" y="50" width="40" height="40" fill="blue" data-tactile="{COARSE}" aria-label="Water"/>
             <rect x="50" y="50" width="40" height="40" fill="navy" data-tactile="{COARSE}" aria-label="Water"/>
           </g>"#
    ));
    let l = legend(&d);
    assert_eq!(meanings(&l), [("Farmland", Source::Layer), ("Water", Source::Label)]);
}

#[test]
fn a_layer_two_entries_share_tells_neither_apart() {
    // Both textures lie in "Land use" alone: the layer would name both
    // alike, so their colours name them.
    let d = drawing(&format!(
        r#"<g inkscape:groupmode="layer" inkscape:label="Land use">
             <rect x="0" y="0" width="40" height="40" fill="rgb(200,30,30)" data-tactile="{FINE}"/>
             <rect x="50" y="0" width="40" height="40" fill="rgb(30,80,230)" data-tactile="{COARSE}"/>
           </g>"#
    ));
    let l = legend(&d);
    assert_eq!(meanings(&l), [("red areas", Source::Colour), ("blue areas", Source::Colour)]);
}

#[test]
fn without_names_or_colours_entries_are_numbered() {
    // Two different fills per texture: no colour names either.
    let d = drawing(&format!(
        r#"<rect x="0" y="0" width="40" height="40" fill="red" data-tactile="{FINE}"/>
           <rect x="50" y="0" width="40" height="40" fill="blue" data-tactile="{FINE}"/>
           <rect x="0" y="50" width="40" height="40" fill="red" data-tactile="{COARSE}"/>
           <rect x="50" y="50" width="40" height="40" fill="blue" data-tactile="{COARSE}"/>"#
    ));
    let l = legend(&d);
    assert_eq!(meanings(&l), [("texture 1", Source::Ordinal), ("texture 2", Source::Ordinal)]);
}

#[test]
fn lines_are_named_by_their_stroke_and_symbols_by_their_fill() {
    let d = drawing(
        r#"<path d="M0 0 L100 0" stroke="rgb(0,150,40)" fill="none" data-tactile="vibrate()"/>
           <path d="M0 20 L100 20" stroke="rgb(240,130,0)" fill="none" data-tactile="vibrate(width: 3mm)"/>
           <circle cx="10" cy="50" r="2" fill="rgb(120,40,180)" data-tactile="dot(radius: 1mm)"/>"#,
    );
    let l = legend(&d);
    let kinds: Vec<&str> = l.entries.iter().map(|e| e.swatch.kind()).collect();
    assert_eq!(kinds, ["line", "line", "symbol"]);
    assert_eq!(meanings(&l)[..2], [("green lines", Source::Colour), ("orange lines", Source::Colour)]);
    assert_eq!(l.entries[2].meaning, "purple points");
}

#[test]
fn a_key_is_needed_for_two_of_a_kind_or_key_codes_only() {
    let one_each = drawing(&format!(
        r#"<rect x="0" y="0" width="40" height="40" fill="red" data-tactile="{FINE}"/>
           <path d="M0 60 L100 60" stroke="black" data-tactile="vibrate()"/>
           <circle cx="10" cy="90" r="2" data-tactile="dot()"/>"#
    ));
    let l = legend(&one_each);
    assert_eq!(l.entries.len(), 3);
    assert!(!l.needed(), "one texture, one line and one symbol need no key");
    assert!(l.shown().is_empty());
    let two_textures = drawing(&format!(
        r#"<rect x="0" y="0" width="40" height="40" fill="red" data-tactile="{FINE}"/>
           <rect x="50" y="0" width="40" height="40" fill="blue" data-tactile="{COARSE}"/>
           <path d="M0 60 L100 60" stroke="black" data-tactile="vibrate()"/>"#
    ));
    let l = legend(&two_textures);
    assert!(l.needed());
    // The key then lists the line too.
    assert_eq!(l.shown().len(), 3);
    let mut keyed = one_each.clone();
    keyed.elements.push(Element {
        visible: true,
        shape: Shape::Text(TextShape {
            content: "fo".into(),
            keyed: Some("Forest office".into()),
            ..Default::default()
        }),
        ..Default::default()
    });
    let l = legend(&keyed);
    assert_eq!(l.codes, [("fo".to_string(), "Forest office".to_string())]);
    assert!(l.needed(), "key codes always need a key");
}

#[test]
fn colour_words_are_the_nearest_basic_names() {
    assert_eq!(colour_word([255, 0, 0, 255]).as_deref(), Some("red"));
    assert_eq!(colour_word([0, 0, 139, 255]).as_deref(), Some("blue"));
    assert_eq!(colour_word([34, 139, 34, 255]).as_deref(), Some("green"));
    assert_eq!(colour_word([250, 250, 250, 255]).as_deref(), Some("white"));
    assert_eq!(colour_word([30, 30, 30, 255]).as_deref(), Some("black"));
    assert_eq!(colour_word([128, 128, 128, 255]).as_deref(), Some("grey"));
    // CSS's named colours whose names say their basic colour.
    for (rgb, word) in [
        ([255, 165, 0], "orange"),
        ([255, 255, 0], "yellow"),
        ([128, 0, 128], "purple"),
        ([255, 192, 203], "pink"),
        ([139, 69, 19], "brown"),
        ([0, 128, 0], "green"),
        ([0, 0, 255], "blue"),
        ([100, 149, 237], "blue"),
        ([0, 128, 128], "blue"),
        ([220, 20, 60], "red"),
    ] {
        assert_eq!(colour_word([rgb[0], rgb[1], rgb[2], 255]).as_deref(), Some(word), "{rgb:?}");
    }
    assert_eq!(colour_word([255, 0, 0, 0]), None);
}

/// `lined_up` as it was written first: every pair against every other.
fn lined_up_pairwise(pairs: &[(usize, Bounds)]) -> Vec<bool> {
    pairs
        .iter()
        .map(|p| {
            pairs.iter().any(|q| {
                q.0 != p.0
                    && ((q.1.0 - p.1.0).abs() <= ALIGN_MM
                        || ((q.1.1 + q.1.3) / 2.0 - (p.1.1 + p.1.3) / 2.0).abs() <= ALIGN_MM)
            })
        })
        .collect()
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

    /// The sorted search finds the same aligned swatches as comparing
    /// every pair, ties and repeated ids included.
    #[test]
    fn lined_up_matches_every_pair_compared(
        raw in proptest::collection::vec((0usize..6, 0.0f64..40.0, 0.0f64..40.0, 0.5f64..8.0), 0..40),
    ) {
        let pairs: Vec<(usize, Bounds)> = raw
            .iter()
            .map(|&(id, x, y, s)| (id, ((x * 2.0).round() / 2.0, (y * 2.0).round() / 2.0, x + s, y + s)))
            .collect();
        proptest::prop_assert_eq!(lined_up(&pairs), lined_up_pairwise(&pairs));
    }
}

/// The banded search beside a swatch finds what a look at every text finds,
/// on a page of labels at every height and size, the nearest and the first
/// among equals.
#[test]
fn the_text_beside_a_swatch_is_found_as_by_a_look_at_every_text() {
    let mut body = String::new();
    for k in 0..300 {
        let (x, y, size) = ((k * 37 % 190) as f64, (k * 53 % 140) as f64 + 5.0, 2.0 + (k % 7) as f64);
        body.push_str(&format!(r#"<text x="{x}" y="{y}" font-size="{size}">L{k}</text>"#));
    }
    let d = drawing(&body);
    let texts = Texts::of(&d);
    assert_eq!(texts.texts.len(), 300);
    let every = |b: Bounds| {
        let (h, mid) = (b.3 - b.1, (b.1 + b.3) / 2.0);
        let mut best: Option<(f64, usize, &TextShape)> = None;
        for &(t, (tx, ty, size), rank) in &texts.texts {
            let gap = tx - b.2;
            let reach = (h / 2.0).max(size * 0.75).max(1.0);
            if (-0.5..=LEGEND_GAP_MM).contains(&gap)
                && (ty - mid).abs() <= reach
                && best.is_none_or(|bb| (gap, rank) < (bb.0, bb.1))
            {
                best = Some((gap, rank, t));
            }
        }
        best.map(|(g, _, t)| (g, t.content.clone()))
    };
    let mut found = 0;
    for i in 0..60 {
        for j in 0..45 {
            let (x, y) = (i as f64 * 3.3, j as f64 * 3.1);
            let b = (x, y, x + 1.0 + (i % 5) as f64, y + 0.5 + (j % 9) as f64);
            let banded = texts.beside(b).map(|(g, t)| (g, t.content.clone()));
            assert_eq!(banded, every(b), "swatch {b:?}");
            found += usize::from(banded.is_some());
        }
    }
    // The page is dense enough that most swatches have a text beside them.
    assert!(found > 1000, "{found}");
}

/// A map's region labels are not a legend, however they line up: a label
/// over a region of a texture, just right of a small region, names no
/// texture. The same texts on the page, beside the same swatches, do.
#[test]
fn a_regions_label_beside_a_small_region_is_not_a_legend_text() {
    const THIRD: &str = "grating(wavelength: 9mm, angle: 45deg)";
    // Two small regions of two textures in a column, each followed by a
    // large region of a third whose label starts just right of the small
    // one, level with it; `dy` moves the large regions out from under the labels.
    let map = |dy: f64| {
        let mut body = String::new();
        for (row, (y, fill, style)) in [(10.0, "green", FINE), (40.0, "red", COARSE)].into_iter().enumerate() {
            body.push_str(&format!(
                r#"<rect x="10" y="{y}" width="6" height="6" fill="{fill}" data-tactile="{style}"/>
                   <rect x="16" y="{y0}" width="60" height="20" fill="blue" data-tactile="{THIRD}"/>
                   <text x="18" y="{ty}" font-size="4">R{row}</text>"#,
                y0 = y - 7.0 + dy,
                ty = y + 4.5,
            ));
        }
        legend(&drawing(&body))
    };
    let from_legend = |l: &Legend| l.entries.iter().filter(|e| e.source == Source::Legend).count();
    let labels = map(0.0);
    assert_eq!(from_legend(&labels), 0, "{:?}", meanings(&labels));
    let on_the_page = map(60.0);
    assert_eq!(from_legend(&on_the_page), 2, "{:?}", meanings(&on_the_page));
    assert!(meanings(&on_the_page).contains(&("R0", Source::Legend)), "{:?}", meanings(&on_the_page));
}

#[test]
fn the_key_lists_texts_with_no_room_a_few_to_a_line_and_says_how_many_more() {
    let text = |n: usize| format!("t{n}");
    let l = Legend { unplaced: (0..70).map(text).collect(), ..Legend::default() };
    assert!(l.needed(), "texts with no room on the graphic need a key");
    let lines = l.text_lines();
    assert_eq!(lines[0], "not on the graphic: t0, t1, t2, t3, t4, t5, t6, t7");
    assert_eq!(lines[1], "t8, t9, t10, t11, t12, t13, t14, t15");
    assert_eq!(lines.len(), 9);
    assert_eq!(lines[7], "t56, t57, t58, t59, t60, t61, t62, t63");
    assert_eq!(lines[8], "and 6 more not on the graphic");
    // The provenance has them all, for a host.
    let e = l.unplaced_entry().expect("an entry");
    assert_eq!((e.id.as_str(), e.label.split(", ").count()), (UNPLACED_ID, 70));
    // Key codes come first.
    let l = Legend { codes: vec![("fo".into(), "Forest office".into())], unplaced: vec!["A".into()], ..l };
    assert_eq!(l.text_lines(), ["fo Forest office", "not on the graphic: A"]);
    assert!(Legend::default().unplaced_entry().is_none());
}
