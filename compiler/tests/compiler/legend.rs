//! The key (issue 43, point 3): the laterotactile and grid families' key as
//! a second bundle, meanings told apart, and a drawing's own legend read as
//! its legend when `--fit` shrinks it.

use taxel_compiler::style::legend::{Source, Swatch, legend};
use taxel_compiler::{CompileOptions, Compiled, compile_svg, pipeline};
use taxel_format::{Bundle, BundleView, Chunk, DotKind, MaskKind, ProvenanceEntry, profiles};

use crate::common::{bundle, dots, masks, no_internal_error, page, with_code};

fn compile_for(svg: &str, profile: &str) -> Compiled {
    no_internal_error(compile_svg(svg, &CompileOptions::new(profiles::builtin(profile).unwrap())))
}

fn provenance(b: &Bundle) -> Vec<&ProvenanceEntry> {
    b.chunks
        .iter()
        .filter_map(|c| match c {
            Chunk::Provenance(p) => Some(&p.entries),
            _ => None,
        })
        .flatten()
        .collect()
}

/// The key's bundle, failing the test with the diagnostics when there is none.
fn key(c: &Compiled) -> &Bundle {
    c.key.first().unwrap_or_else(|| panic!("no key bundle: {:#?}", c.diagnostics))
}

/// Two textures and a vibrating line, each named by its title.
const MAP: &str = r#"<rect x="5" y="5" width="40" height="30" data-tactile="grating(wavelength: 3mm, angle: 0deg)"><title>Forest</title></rect>
<rect x="55" y="5" width="40" height="30" data-tactile="grating(wavelength: 6mm, angle: 90deg)"><title>Lake</title></rect>
<path d="M5 50 L95 50" stroke="black" fill="none" data-tactile="vibrate(width: 2mm)"><title>Road</title></path>"#;

#[test]
fn an_arrays_key_is_a_second_bundle_with_each_entry_felt_as_itself_beside_its_meaning() {
    let c = compile_for(&page(MAP), "stress2");
    let k = key(&c);
    // A bundle like any other, for the same profile, that the reader takes.
    let bytes = k.to_bytes().unwrap();
    let v = BundleView::parse(&bytes).unwrap();
    assert_eq!(v.manifest().profile.name.as_str(), "stress2");
    // Each swatch is the graphic's own style: the two gratings with their
    // wavelengths and angles, and the line at its frequency.
    let kinds = |b: &Bundle| masks(b).iter().map(|m| m.kind).collect::<Vec<_>>();
    assert_eq!(kinds(k), kinds(bundle(&c)));
    assert!(matches!(kinds(k)[0], MaskKind::Grating { angle_deg, .. } if angle_deg == 0.0));
    // One felt element per entry, named by its meaning for a host to say,
    // and the meanings in braille beside them.
    let labels: Vec<&str> = provenance(k).iter().map(|p| p.label.as_str()).collect();
    for meaning in ["Forest", "Lake", "Road"] {
        assert_eq!(
            labels.iter().filter(|l| **l == meaning).count(),
            2,
            "{meaning}: the swatch and its braille: {labels:?}"
        );
    }
    let braille = dots(k, DotKind::Braille).expect("the meanings in braille");
    assert!(braille.dots.len() > 10);
    // Every swatch lies left of the braille, on the surface.
    for m in masks(k) {
        assert!(m.origin_x.0 < 25.0, "{:?}", m.origin_x);
    }
    // Not a key of its own: no `key.*` entries, which the graphic's bundle keeps.
    assert!(provenance(k).iter().all(|p| !p.id.starts_with("key")), "{:?}", provenance(k));
    assert_eq!(provenance(bundle(&c)).iter().filter(|p| p.id.starts_with("key.")).count(), 3);
    let notes = with_code(&c, "T0331");
    assert_eq!(notes.len(), 1, "{:#?}", c.diagnostics);
    assert!(notes[0].message.contains("3 entries"), "{}", notes[0].message);
}

#[test]
fn a_grids_key_plays_each_brushed_stroke_once_named_by_its_meaning() {
    let svg = page(
        r#"<path d="M5 10 L95 10" stroke="black" data-tactile="brush(duration: 800ms)"><title>Wind</title></path>
           <path d="M5 40 L95 40" stroke="black" data-tactile="brush(duration: 1500ms)"><title>Rain</title></path>"#,
    );
    let c = compile_for(&svg, "brush-4x3");
    let k = key(&c);
    let strokes = k
        .chunks
        .iter()
        .find_map(|c| match c {
            Chunk::Strokes(s) => Some(s),
            _ => None,
        })
        .expect("the key's strokes");
    assert_eq!(strokes.strokes.len(), 2);
    // One after the other, each as long as the graphic's.
    let (a, b) = (&strokes.strokes[0], &strokes.strokes[1]);
    assert!(b.start.0 >= a.start.0 + a.duration as u64, "{:?} then {:?}", a.start, b.start);
    assert_eq!((a.duration, b.duration), (800, 1500));
    let labels: Vec<&str> = provenance(k).iter().map(|p| p.label.as_str()).collect();
    assert_eq!(labels, ["Wind", "Rain"]);
}

#[test]
fn no_key_bundle_when_the_key_is_not_needed_nor_on_pins() {
    // One texture and one line: nothing to tell apart.
    let one = page(
        r#"<rect x="5" y="5" width="40" height="30" data-tactile="grating()"/>
           <path d="M5 50 L95 50" stroke="black" data-tactile="vibrate()"/>"#,
    );
    let c = compile_for(&one, "stress2");
    assert!(c.bundle.is_some() && c.key.is_empty());
    assert!(with_code(&c, "T0331").is_empty());
    // A pin display has its key as pages of its own image.
    let c = compile_for(&page(MAP), "dotpad");
    assert!(c.bundle.is_some() && c.key.is_empty());
}

#[test]
fn a_key_longer_than_the_surface_goes_on_more_pages_and_only_what_fits_on_none_is_said() {
    // Eight textures with long names: the 60 mm surface holds six braille
    // lines, and each meaning takes two or three.
    let mut body = String::new();
    let meanings: Vec<String> = (0..8).map(|k| format!("region number {k} of the map")).collect();
    for (k, m) in meanings.iter().enumerate() {
        body += &format!(
            r#"<rect x="{}" y="5" width="10" height="30" data-tactile="grating(wavelength: {}mm, angle: 0deg)"><title>{m}</title></rect>"#,
            2 + 12 * k,
            2 + k
        );
    }
    let c = compile_for(&page(&body), "stress2");
    let pages = &c.key;
    assert!(pages.len() >= 2, "{} pages: {:#?}", pages.len(), c.diagnostics);
    // Nothing is left out: every entry is on a page.
    assert!(with_code(&c, "T0332").is_empty(), "{:#?}", c.diagnostics);
    let notes = with_code(&c, "T0331");
    assert!(notes[0].message.contains(&format!("{} more bundles", pages.len())), "{}", notes[0].message);
    let mut swatches = 0;
    for (k, p) in pages.iter().enumerate() {
        // Each page says which it is, and is a bundle like any other for the profile.
        let entries = provenance(p);
        let said: Vec<_> = entries.iter().filter(|e| e.id == "page").map(|e| e.label.as_str()).collect();
        assert_eq!(said, [format!("page {} of {}", k + 1, pages.len())], "{entries:?}");
        BundleView::parse(&p.to_bytes().unwrap()).unwrap();
        swatches += masks(p).len();
    }
    assert_eq!(swatches, 8, "one swatch per entry over the pages");
    // An entry is never split between pages: its swatch (labelled with the
    // whole meaning) and its braille lines (pieces of it) are on one page.
    for (n, m) in meanings.iter().enumerate() {
        // Its pieces: the braille lines that are part of it and hold its number.
        let piece = |label: &str| m.contains(label) && label.contains(&n.to_string());
        let on: Vec<usize> =
            (0..pages.len()).filter(|&k| provenance(&pages[k]).iter().any(|e| piece(&e.label))).collect();
        let whole: Vec<usize> =
            (0..pages.len()).filter(|&k| provenance(&pages[k]).iter().any(|e| e.label == *m)).collect();
        assert_eq!(whole.len(), 1, "{m}: on pages {whole:?}");
        assert!(on.iter().all(|k| *k == whole[0]), "{m}: pieces on pages {on:?}, the swatch on {}", whole[0]);
    }

    // A meaning longer than a whole page fits on none: said once, by name,
    // and the others are still on their pages.
    let long = "a legend text so long that its braille takes more lines than the whole surface of the device holds, \
                however the key is laid out, which no page can show";
    let body = format!(
        r#"{body}<rect x="5" y="40" width="10" height="10" data-tactile="grating(wavelength: 11mm, angle: 45deg)"><title>{long}</title></rect>"#
    );
    let c = compile_for(&page(&body), "stress2");
    let w = with_code(&c, "T0332");
    assert_eq!(w.len(), 1, "{:#?}", c.diagnostics);
    assert!(
        w[0].message.contains("8 of its 9 entries") && w[0].message.contains("a legend text so long"),
        "{}",
        w[0].message
    );
    assert_eq!(c.key.iter().map(|p| masks(p).len()).sum::<usize>(), 8);
}

#[test]
fn a_texture_and_its_outline_titled_alike_are_told_apart() {
    // The lake's texture and its outline share their title, and the
    // forest's texture and the road share a layer: every meaning is its own.
    let d = pipeline::resolve(
        &page(
            r##"<rect x="5" y="5" width="40" height="30" fill="#2060e0" stroke="black" data-tactile="grating(wavelength: 6mm); vibrate()"><title>Lake</title></rect>
               <g inkscape:groupmode="layer" inkscape:label="Roads">
                 <rect x="55" y="5" width="40" height="30" fill="#30a030" data-tactile="grating(wavelength: 3mm, angle: 0deg)"/>
                 <path d="M5 50 L95 50" stroke="#e02020" fill="none" data-tactile="vibrate(width: 3mm)"/>
               </g>"##,
        ),
        &CompileOptions::new(profiles::builtin("stress2").unwrap()),
    )
    .drawing
    .unwrap();
    let l = legend(&d);
    let meanings: Vec<(&str, &str)> = l.entries.iter().map(|e| (e.swatch.kind(), e.meaning.as_str())).collect();
    let mut distinct: Vec<&str> = meanings.iter().map(|m| m.1).collect();
    distinct.sort();
    distinct.dedup();
    assert_eq!(distinct.len(), meanings.len(), "{meanings:?}");
    assert_eq!(
        meanings,
        [("texture", "blue areas"), ("texture", "green areas"), ("line", "black lines"), ("line", "red lines")]
    );
}

/// A bar chart as a plotting library writes it (200 x 150 mm, unannotated):
/// three series of bars, tick labels under them, and a legend in a box
/// titled "Legend" whose square swatches `--fit` shrinks to marks.
fn chart() -> String {
    let colours = ["#1f77b4", "#ff7f0e", "#2ca02c"];
    let mut s = String::from(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="200mm" height="150mm" viewBox="0 0 200 150">
<rect width="200" height="150" fill="white"/>
<path d="M20 130 L190 130 M20 130 L20 10" stroke="black" stroke-width="0.5" fill="none"/>"#,
    );
    let heights = [[60.0, 90.0, 40.0], [80.0, 50.0, 70.0], [100.0, 30.0, 55.0], [45.0, 75.0, 95.0]];
    for (q, h) in heights.iter().enumerate() {
        for (k, c) in colours.iter().enumerate() {
            let x = 25.0 + q as f64 * 30.0 + k as f64 * 8.0;
            s += &format!(r#"<rect x="{x}" y="{}" width="7" height="{}" fill="{c}"/>"#, 130.0 - h[k], h[k]);
        }
        s += &format!(
            r#"<text x="{}" y="138" font-size="5" text-anchor="middle">Q{}</text>"#,
            37.0 + q as f64 * 30.0,
            q + 1
        );
    }
    s += r##"<g><title>Legend</title><rect x="150" y="12" width="38" height="30" fill="white" stroke="#cccccc"/>"##;
    for (k, (c, name)) in colours.iter().zip(["North", "South", "East"]).enumerate() {
        let y = 16.0 + k as f64 * 8.0;
        s += &format!(r#"<rect x="153" y="{y}" width="5" height="5" fill="{c}"/>"#);
        s += &format!(r#"<text x="161" y="{}" font-size="5">{name}</text>"#, y + 4.5);
    }
    s + "</g></svg>"
}

#[test]
fn a_charts_own_legend_names_its_textures_when_fit_shrinks_its_swatches() {
    for profile in ["stress2", "dotpad"] {
        let opts = CompileOptions { fit: true, ..CompileOptions::new(profiles::builtin(profile).unwrap()) };
        let d = pipeline::resolve(&chart(), &opts).drawing.unwrap();
        let l = legend(&d);
        let entries: Vec<(&str, &str, Source)> =
            l.entries.iter().map(|e| (e.swatch.kind(), e.meaning.as_str(), e.source)).collect();
        // The swatches are patches of the textures they explain, not a
        // symbol of their own ("symbol: Legend"), and the tick labels under
        // the bars are not taken for legend texts.
        assert!(l.entries.iter().all(|e| !matches!(e.swatch, Swatch::Symbol(_))), "{profile}: {entries:?}");
        let textures: Vec<&str> =
            l.entries.iter().filter(|e| matches!(e.swatch, Swatch::Texture(_))).map(|e| e.meaning.as_str()).collect();
        let mut sorted = textures.clone();
        sorted.sort();
        assert_eq!(sorted, ["East", "North", "South"], "{profile}: {entries:?}");
        assert!(
            l.entries.iter().filter(|e| matches!(e.swatch, Swatch::Texture(_))).all(|e| e.source == Source::Legend)
        );
    }
}

#[test]
fn texts_the_graphic_has_no_room_for_are_listed_by_the_key() {
    // A bar chart fitted to the surface's height: the axis's labels under
    // it are single letters (no key code is shorter) and their braille has
    // no room under the axis, nor beside the bars.
    let mut body = String::new();
    for k in 0..9 {
        body += &format!(
            r##"<rect x="{}" y="{}" width="8" height="{}" fill="#4c78a8"/>"##,
            10 + 9 * k,
            10 + 4 * k,
            45 - 4 * k
        );
        body += &format!(
            r#"<text x="{}" y="59.5" font-size="3" font-family="Tuffy">{}</text>"#,
            13 + 9 * k,
            (b'A' + k as u8) as char
        );
    }
    body += r#"<path d="M5 55.5 H95" stroke="black" stroke-width="0.5" fill="none"/>"#;
    let c = compile_for(&page(&body), "stress2");
    let letters: Vec<String> = (0..9).map(|k| ((b'A' + k) as char).to_string()).collect();
    // The note says where they went.
    let n = with_code(&c, "T0323");
    assert_eq!(n.len(), 1, "{:#?}", c.diagnostics);
    assert!(
        n[0].message.contains("9 text element(s)") && n[0].message.contains("the key lists them"),
        "{}",
        n[0].message
    );
    // The key's bundle lists them in braille, a few to a line, after what
    // it says first; the graphic's provenance has them for a host.
    let labels: Vec<String> = c.key.iter().flat_map(|k| provenance(k).into_iter().map(|e| e.label.clone())).collect();
    // (Braille lines are wrapped at spaces: joined again, they read as written.)
    let read = labels.join(" ");
    let first = format!("not on the graphic: {}", letters[..8].join(", "));
    assert!(read.contains(&format!("{first} ")), "{labels:?}");
    assert!(labels.iter().any(|l| *l == letters[8]), "{labels:?}");
    assert!(dots(&c.key[0], DotKind::Braille).is_some());
    let texts: Vec<&str> =
        provenance(bundle(&c)).into_iter().filter(|e| e.id == "key.text").map(|e| e.label.as_str()).collect();
    assert_eq!(texts, [letters.join(", ")]);
    // On a pin display, the key's pages list them too.
    let pins = compile_for(&page(&body), "dotpad");
    let texts: Vec<&str> =
        provenance(bundle(&pins)).into_iter().filter(|e| e.id == "key.text").map(|e| e.label.as_str()).collect();
    assert_eq!(texts, [letters.join(", ")]);
}

#[test]
fn the_key_lists_only_what_is_felt_somewhere() {
    // Marsh lies wholly under two white fills painted after it (neither
    // covers it alone); Fen is masked away (T0301); Lake is half under a
    // white fill; Forest and the Road are in plain view.
    let drawing = page(
        r#"<defs><mask id="none"><rect x="0" y="0" width="100" height="60" fill="black"/></mask></defs>
<rect x="5" y="5" width="30" height="20" data-tactile="grating(wavelength: 3mm, angle: 0deg)"><title>Marsh</title></rect>
<rect x="40" y="5" width="20" height="20" data-tactile="grating(wavelength: 4mm, angle: 45deg)"><title>Forest</title></rect>
<rect x="65" y="5" width="30" height="20" data-tactile="grating(wavelength: 6mm, angle: 90deg)"><title>Lake</title></rect>
<rect x="5" y="30" width="20" height="20" mask="url(#none)" data-tactile="grating(wavelength: 5mm, angle: 0deg)"><title>Fen</title></rect>
<path d="M5 55 L95 55" stroke="black" fill="none" data-tactile="vibrate(width: 2mm)"><title>Road</title></path>
<rect x="4" y="4" width="16" height="22" fill="white"/>
<rect x="19" y="4" width="17" height="22" fill="white"/>
<rect x="64" y="4" width="16" height="22" fill="white"/>"#,
    );
    let opts = CompileOptions::new(profiles::builtin("stress2").unwrap());
    let d = pipeline::resolve(&drawing, &opts).drawing.expect("a drawing");
    let key = legend(&d);
    let meanings: Vec<&str> = key.entries.iter().map(|e| e.meaning.as_str()).collect();
    assert_eq!(meanings, ["Forest", "Lake", "Road"]);
    // The key the devices give, and what they tell a host, say the same.
    for profile in ["stress2", "dotpad"] {
        let c = compile_for(&drawing, profile);
        let said: Vec<&str> = provenance(bundle(&c))
            .iter()
            .filter(|p| p.id.starts_with("key."))
            .map(|p| p.label.split(" (").next().unwrap_or_default())
            .collect();
        assert_eq!(said, ["Forest", "Lake", "Road"], "{profile}");
    }
    // The textures' layers agree: Marsh's is not felt, Lake's is.
    let c = compile_for(&drawing, "stress2");
    let gratings = masks(bundle(&c)).iter().filter(|m| matches!(m.kind, MaskKind::Grating { .. })).count();
    assert_eq!(gratings, 2);
}
