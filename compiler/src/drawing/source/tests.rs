//! Tests of the XML side: the ids both passes agree on, and the drawings
//! refused before usvg reads them.

use super::*;

/// Drawings whose ids the first pass must get right: elements without
/// ids, ids that already use the inserted prefix, entity expansions
/// (used twice, quoted either way, nested in a group), Inkscape layers
/// with labels in other scripts, self-closing and empty elements.
const DRAWINGS: [&str; 4] = [
    r#"<svg xmlns="http://www.w3.org/2000/svg" width="10mm" height="10mm"><rect width="2" height="2"/><g id="a"><circle r="1"/><path d="M0 0L1 1"/></g><g/></svg>"#,
    r#"<svg xmlns="http://www.w3.org/2000/svg" id="taxel-auto-3">
  <rect width="2" height="2"/><rect id="taxel-auto-x1" width="1" height="1"/>
  <rect width="3" height="3"></rect>
</svg>"#,
    r#"<?xml version="1.0"?>
<!DOCTYPE svg [
  <!ENTITY square "<rect x='10' y='10' width='20' height='20'/>">
  <!ENTITY dot '<g><circle cx="5" cy="5" r="2"/></g>'>
]>
<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm" viewBox="0 0 100 60">
  <g id="v">&square;</g>
  <g>&square;&dot;</g>
  <text x="1" y="2">é &amp; ü</text>
</svg>"#,
    r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" width="10mm" height="10mm">
  <g inkscape:groupmode="layer" inkscape:label="Calque élévation"><path d="M0 0H5V5Z"/>
    <g inkscape:groupmode="layer" inkscape:label="レイヤー 1"><rect width="1" height="1"/></g>
  </g>
  <g inkscape:groupmode="layer" inkscape:label="tactile: vibrate()" id="l"><rect width="4" height="4"/></g>
</svg>"#,
];

fn parse(text: &str) -> Document<'_> {
    Document::parse_with_options(text, xml_options()).unwrap()
}

#[test]
fn the_first_pass_inserts_exactly_the_keys_usvg_then_reads() {
    for text in DRAWINGS {
        let doc = parse(text);
        let Keys { keys, rewritten } = keys(text, &doc, &mut Vec::new()).unwrap();
        let elements: Vec<Node<'_, '_>> = doc.root_element().descendants().filter(|n| n.is_element()).collect();
        assert_eq!(keys.len(), elements.len(), "{text}");
        // What usvg parses: the same elements, in the same order, each carrying its key as its id.
        let doc2 = parse(&rewritten);
        let seen: Vec<&str> = doc2
            .root_element()
            .descendants()
            .filter(|n| n.is_element())
            .map(|n| n.attribute("id").unwrap_or("(none)"))
            .collect();
        assert_eq!(seen, keys, "{rewritten}");
        // Outside entities, the key is the id as written, or the prefix and
        // the element's position in document order; the prefix is one no
        // id of the drawing starts with.
        let ids: Vec<&str> = elements.iter().filter_map(|n| n.attribute("id")).collect();
        let prefix = (0..)
            .map(|x| format!("taxel-auto-{}", "x".repeat(x)))
            .find(|p| !ids.iter().any(|i| i.starts_with(p.as_str())))
            .unwrap();
        let body = doc.root_element().range().start;
        for (n, (e, k)) in elements.iter().zip(&keys).enumerate() {
            match e.attribute("id") {
                Some(id) => assert_eq!(k, id),
                None if e.range().start >= body => assert_eq!(*k, format!("{prefix}{n}")),
                None => assert!(k.starts_with(&prefix), "{k}"),
            }
        }
        // Taking the inserted ids out again gives the text back, line for line.
        let mut back = rewritten.clone();
        // (Each once: the copies of an entity's element share the one inserted in the entity.)
        let inserted: HashSet<&String> = keys.iter().filter(|k| !ids.contains(&k.as_str())).collect();
        for k in inserted {
            let at = back.find(&format!(" id=\"{k}\"")).or_else(|| back.find(&format!(" id='{k}'"))).unwrap();
            back.replace_range(at..at + k.len() + 6, "");
        }
        assert_eq!(back, text);
    }
}

#[test]
fn the_second_pass_reads_each_element_under_its_key() {
    for text in DRAWINGS {
        let doc = parse(text);
        let first = keys(text, &doc, &mut Vec::new()).unwrap();
        let src = read(text, &doc, first.keys.clone(), None, &["en".to_string()], &mut Vec::new());
        let elements: Vec<Node<'_, '_>> = doc.root_element().descendants().filter(|n| n.is_element()).collect();
        assert_eq!(src.elements.len(), elements.len());
        for (i, (e, node)) in src.elements.iter().zip(&elements).enumerate() {
            assert_eq!(e.key, first.keys[i]);
            assert_eq!(e.node, node.id());
            assert_eq!(e.tag, node.tag_name().name());
            assert!(src.by_key[&e.key].contains(&i));
            assert_eq!(src.get(&e.key, e.parent).map(|(_, f)| f.key.as_str()), Some(e.key.as_str()));
        }
    }
    // Layers, labels and annotations still come from the original text.
    let text = DRAWINGS[3];
    let doc = parse(text);
    let src =
        read(text, &doc, keys(text, &doc, &mut Vec::new()).unwrap().keys, None, &["en".to_string()], &mut Vec::new());
    let rect = src.elements.iter().find(|e| e.layers.len() == 2).unwrap();
    assert_eq!(rect.layers, ["Calque élévation", "レイヤー 1"]);
    assert_eq!(rect.line, 3);
    assert!(src.elements.iter().any(|e| e.id == "l" && e.own.is_some()));
}

#[test]
fn a_root_that_is_not_svg_is_refused_by_the_first_pass() {
    let text = "<html><svg/></html>";
    let mut diags = Vec::new();
    assert!(keys(text, &parse(text), &mut diags).is_none());
    assert_eq!(diags.len(), 1);
    assert_eq!(diags[0].code, "T0200");
}

/// Patterns filled with patterns, `levels` deep, each of ten rectangles
/// (the last stroked only), in `style` or as attributes.
fn nested_patterns(levels: usize, in_style: bool) -> String {
    let mut defs = String::new();
    for k in 0..levels {
        let paint = if k + 1 < levels { format!("url(#p{})", k + 1) } else { "none".into() };
        let fill = if in_style { format!(r#"style="fill: {paint}""#) } else { format!(r#"fill="{paint}""#) };
        defs += &format!(r#"<pattern id="p{k}" width="20" height="20" patternUnits="userSpaceOnUse">"#);
        for j in 0..10 {
            defs += &format!(r#"<rect x="{j}" width="20" height="20" {fill} stroke="green"/>"#);
        }
        defs += "</pattern>";
    }
    format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg"><defs>{defs}</defs><rect width="9" height="9" fill="url(#p0)"/></svg>"#
    )
}

/// Patterns nested so deeply that expanding them would not end (usvg
/// took 24 s on ten levels of ten, librsvg's "billion laughs" test) are
/// refused before usvg reads them, naming the outermost; hatchings
/// nested a few levels, and patterns that name each other in a cycle,
/// are not.
#[test]
fn patterns_nested_past_reason_are_refused() {
    for in_style in [false, true] {
        // 11^6 shapes: refused, at the first pattern's line.
        let text = nested_patterns(6, in_style);
        let d = patterns_too_nested(&parse(&text)).expect("refused");
        assert_eq!(d.code, "T0200");
        assert!(d.message.contains("pattern #p0 "), "{}", d.message);
        // 11^5: read.
        assert!(patterns_too_nested(&parse(&nested_patterns(5, in_style))).is_none());
    }
    let cycle = r#"<svg xmlns="http://www.w3.org/2000/svg"><pattern id="a"><rect fill="url(#b)"/></pattern><pattern id="b"><rect fill="url('#a')"/></pattern></svg>"#;
    assert!(patterns_too_nested(&parse(cycle)).is_none());
    // A pattern that takes another's content by `href` counts it.
    let text = nested_patterns(6, false)
        .replace("<defs>", r##"<defs><pattern id="q" xmlns:xlink="http://www.w3.org/1999/xlink" xlink:href="#p0"/>"##);
    let d = patterns_too_nested(&parse(&text)).expect("refused");
    assert!(d.message.contains("pattern #q "), "{}", d.message);
}

/// Elements nested past 1,024 deep (usvg's limit for groups; 700 nested
/// `<tspan>`s overflowed a worker's stack inside usvg) are refused
/// before usvg reads them, at the line of the first too deep; 1,024 are
/// read. A chain of patterns each painting with the next (100,000 of
/// them overflowed the stack) is refused past 64 levels.
#[test]
fn nesting_past_the_limits_is_refused_before_usvg() {
    let tspans = |n: usize| {
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\">\n<text>{}deep{}</text></svg>",
            "<tspan>".repeat(n),
            "</tspan>".repeat(n)
        )
    };
    // The root is 1 deep, the text 2: 1,022 tspans reach 1,024.
    assert!(nested_too_deep(&parse(&tspans(1022))).is_none());
    let d = nested_too_deep(&parse(&tspans(1023))).expect("refused");
    assert_eq!((d.code, d.line), ("T0200", Some(2)));
    assert!(d.message.contains("(<tspan>)"), "{}", d.message);
    let chain = |n: usize| {
        let defs: String = (0..n)
            .map(|i| format!(r#"<pattern id="p{i}"><rect width="2" height="2" fill="url(#p{})"/></pattern>"#, i + 1))
            .collect();
        format!(r#"<svg xmlns="http://www.w3.org/2000/svg"><defs>{defs}</defs><rect fill="url(#p0)"/></svg>"#)
    };
    assert!(patterns_too_nested(&parse(&chain(64))).is_none());
    let d = patterns_too_nested(&parse(&chain(65))).expect("refused");
    assert!(d.message.contains("pattern #p0 ") && d.message.contains("64 deep"), "{}", d.message);
}

/// An XML comment in a `<style>` (Wikimedia's world maps open theirs with
/// `/* <!-- Done up to row 1708 --> */`) is cut out of usvg's text, so
/// that usvg, which reads a style sheet's first text only, applies the
/// rules after it: the whole map was drawn black. Ids still go in.
#[test]
fn comments_in_a_style_sheet_do_not_hide_its_rules_from_usvg() {
    let text = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10\" height=\"10\"><style type=\"text/css\">\n/* <!-- Done up to row 1708 --> */\n.land { fill: #c0c0c0 }\n<!-- and another -->.sea { fill: #0000ff }</style><rect class=\"land\" width=\"4\" height=\"4\"/><rect id=\"s\" class=\"sea\" x=\"5\" width=\"4\" height=\"4\"/></svg>";
    let doc = parse(text);
    let Keys { keys, rewritten } = keys(text, &doc, &mut Vec::new()).unwrap();
    assert!(!rewritten.contains("<!--") && rewritten.contains("/*  */"), "{rewritten}");
    let tree = usvg::Tree::from_str(&rewritten, &usvg::Options::default()).unwrap();
    let fill = |id: &str| match tree.node_by_id(id) {
        Some(usvg::Node::Path(p)) => match p.fill().map(|f| f.paint()) {
            Some(usvg::Paint::Color(c)) => Some((c.red, c.green, c.blue)),
            _ => None,
        },
        _ => None,
    };
    assert_eq!(fill(&keys[2]), Some((0xc0, 0xc0, 0xc0)), "{rewritten}");
    assert_eq!(fill("s"), Some((0, 0, 0xff)), "{rewritten}");
}
