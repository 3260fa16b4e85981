//! Walks usvg's resolved tree and finds every shape that has a tactile style,
//! with its geometry in page millimetres.
//!
//! Style resolution (later wins): inherited < style sheet < the element's own
//! annotation (`data-tactile`, else a `tactile:` label). Inheritance follows
//! usvg's tree, so an element reached through `<use>` inherits from the
//! `<use>`; containers that usvg may flatten away (`a`, `switch`, `symbol`)
//! pass their annotations on from the XML side.

use std::collections::{HashMap, HashSet};

use resvg::tiny_skia::{Path, Transform};
use usvg::{Group, Node, Paint};

use super::size::Page;
use super::source::{Kind, Source};
use crate::annotation::{Declaration, Style};
use crate::geometry::{self, FillRule, Polyline};
use crate::stylesheet::{ElementFacts, StyleSheet};

/// A shape with tactile styles.
pub(crate) struct Item<'t> {
    /// Index of its element in [`Source::elements`].
    pub elem: usize,
    pub styles: Vec<Style>,
    /// The outline in page millimetres (for rasterising); `None` when nothing is left of it.
    pub path: Option<Path>,
    pub fill_rule: FillRule,
    pub visible: bool,
    /// The outline flattened in f64 page millimetres.
    pub polylines: Vec<Polyline>,
    /// Centres of the marker instances drawn on the path, in page millimetres.
    pub markers: Vec<(f64, f64)>,
    /// Clip paths of the enclosing groups, with the groups' absolute transforms (usvg pixels).
    pub clips: Vec<(&'t usvg::ClipPath, Transform)>,
}

/// What the walk found.
pub(crate) struct Scene<'t> {
    pub items: Vec<Item<'t>>,
    /// Absolute transforms (usvg pixels) of the groups usvg kept, by key.
    pub group_ts: HashMap<String, Transform>,
    /// Elements that usvg rendered.
    pub seen: HashSet<usize>,
    /// Elements with a tactile style that are images (not rendered tactilely).
    pub images: Vec<usize>,
}

struct Walker<'s, 't> {
    src: &'s Source,
    sheet: Option<&'s StyleSheet>,
    page_ts: Transform,
    scene: Scene<'t>,
}

/// Collects the tactile items of `tree`.
pub(crate) fn collect<'t>(tree: &'t usvg::Tree, src: &Source, sheet: Option<&StyleSheet>, page: Page) -> Scene<'t> {
    let s = page.scale as f32;
    let mut w = Walker {
        src,
        sheet,
        page_ts: Transform::from_scale(s, s),
        scene: Scene { items: Vec::new(), group_ts: HashMap::new(), seen: HashSet::new(), images: Vec::new() },
    };
    w.group(tree.root(), None, None, &mut Vec::new());
    w.scene
}

fn rgb(p: Option<&Paint>) -> Option<[u8; 3]> {
    match p {
        Some(Paint::Color(c)) => Some([c.red, c.green, c.blue]),
        _ => None,
    }
}

impl<'s, 't> Walker<'s, 't> {
    /// The declaration in force at a node whose element is `elem`, given what
    /// its usvg parent has.
    fn resolve(
        &self,
        elem: usize,
        fill: Option<[u8; 3]>,
        stroke: Option<[u8; 3]>,
        inherited: Option<&Declaration>,
    ) -> Option<Declaration> {
        let e = &self.src.elements[elem];
        if let Some(own) = &e.own {
            return Some(own.clone());
        }
        if let Some(sheet) = self.sheet {
            let facts = ElementFacts { id: &e.id, classes: &e.classes, layers: &e.layers, fill, stroke };
            if let Some(r) = sheet.lookup(&facts) {
                return Some(r.declaration.clone());
            }
        }
        // Containers usvg may have flattened away between this element and its usvg parent.
        let mut p = e.parent;
        while let Some(i) = p {
            let a = &self.src.elements[i];
            if a.kind != Kind::Container {
                break;
            }
            if let Some(d) = a.own.as_ref().or(a.sheet.as_ref()) {
                return Some(d.clone());
            }
            p = a.parent;
        }
        inherited.cloned()
    }

    /// Walks a group. `owner` is the `<use>` whose copy this is, if any: usvg
    /// clears the ids of the elements it copies, so those belong to the `<use>`.
    fn group(
        &mut self,
        g: &'t Group,
        inherited: Option<&Declaration>,
        owner: Option<usize>,
        clips: &mut Vec<(&'t usvg::ClipPath, Transform)>,
    ) {
        let children = g.children();
        let mut skip_next = false;
        for (i, child) in children.iter().enumerate() {
            if std::mem::take(&mut skip_next) {
                continue;
            }
            match child {
                Node::Group(cg) => {
                    let own = self.src.get(cg.id()).map(|(ei, _)| ei);
                    let decl = match own {
                        Some(ei) => {
                            self.scene.seen.insert(ei);
                            self.scene.group_ts.insert(cg.id().to_string(), cg.abs_transform());
                            self.resolve(ei, None, None, inherited)
                        }
                        None => inherited.cloned(),
                    };
                    // usvg wraps an <image> in a group that carries its id.
                    if let Some(ei) = own.filter(|&ei| self.src.elements[ei].tag == "image") {
                        if decl.as_ref().is_some_and(|d| !d.styles().is_empty()) {
                            self.scene.images.push(ei);
                        }
                        continue;
                    }
                    let pushed = cg.clip_path().map(|c| clips.push((c, cg.abs_transform()))).is_some();
                    let owner = own.filter(|&ei| self.src.elements[ei].tag == "use").or(owner);
                    self.group(cg, decl.as_ref(), owner, clips);
                    if pushed {
                        clips.pop();
                    }
                }
                Node::Path(p) => {
                    let found = if p.id().is_empty() {
                        owner.map(|ei| (ei, &self.src.elements[ei]))
                    } else {
                        self.src.get(p.id())
                    };
                    let Some((ei, e)) = found else { continue };
                    self.scene.seen.insert(ei);
                    let markers = if e.has_markers {
                        match children.get(i + 1) {
                            Some(Node::Group(mg)) if mg.id().is_empty() => {
                                skip_next = true;
                                mg.children().iter().filter_map(|m| self.centre(m.abs_bounding_box())).collect()
                            }
                            _ => Vec::new(),
                        }
                    } else {
                        Vec::new()
                    };
                    let decl = self.resolve(
                        ei,
                        rgb(p.fill().map(|f| f.paint())),
                        rgb(p.stroke().map(|s| s.paint())),
                        inherited,
                    );
                    let Some(Declaration::Styles(styles)) = decl else { continue };
                    let ts = self.page_ts.pre_concat(p.abs_transform());
                    let rule = match p.fill().map(|f| f.rule()) {
                        Some(usvg::FillRule::EvenOdd) => FillRule::EvenOdd,
                        _ => FillRule::NonZero,
                    };
                    self.push(ei, styles, vec![(p.data(), ts)], rule, p.is_visible(), markers, clips);
                }
                Node::Text(t) => {
                    let Some((ei, _)) = self.src.get(t.id()) else { continue };
                    self.scene.seen.insert(ei);
                    let Some(Declaration::Styles(styles)) = self.resolve(ei, None, None, inherited) else { continue };
                    // Braille is read from the text itself (see `braille`), never from glyph outlines.
                    let styles: Vec<Style> = styles.into_iter().filter(|s| !matches!(s, Style::Braille(_))).collect();
                    if styles.is_empty() {
                        continue;
                    }
                    let mut parts = Vec::new();
                    text_paths(t.flattened(), &mut parts);
                    let parts =
                        parts.into_iter().map(|p| (p.data(), self.page_ts.pre_concat(p.abs_transform()))).collect();
                    self.push(ei, styles, parts, FillRule::NonZero, true, Vec::new(), clips);
                }
                Node::Image(im) => {
                    if let Some((ei, _)) = self.src.get(im.id()) {
                        self.scene.seen.insert(ei);
                        if let Some(Declaration::Styles(s)) = self.resolve(ei, None, None, inherited)
                            && !s.is_empty()
                        {
                            self.scene.images.push(ei);
                        }
                    }
                }
            }
        }
    }

    fn centre(&self, r: usvg::Rect) -> Option<(f64, f64)> {
        let s = self.page_ts.sx as f64;
        let c = ((r.left() as f64 + r.right() as f64) / 2.0 * s, (r.top() as f64 + r.bottom() as f64) / 2.0 * s);
        (c.0.is_finite() && c.1.is_finite()).then_some(c)
    }

    #[allow(clippy::too_many_arguments)]
    fn push(
        &mut self,
        elem: usize,
        styles: Vec<Style>,
        parts: Vec<(&usvg::tiny_skia_path::Path, Transform)>,
        fill_rule: FillRule,
        visible: bool,
        markers: Vec<(f64, f64)>,
        clips: &[(&'t usvg::ClipPath, Transform)],
    ) {
        if styles.is_empty() {
            return;
        }
        let mut pb = resvg::tiny_skia::PathBuilder::new();
        let mut polylines = Vec::new();
        for (data, ts) in parts {
            polylines.extend(geometry::flatten(data, ts, geometry::FLATTEN_TOLERANCE_MM));
            if let Some(p) = data.clone().transform(ts) {
                pb.push_path(&p);
            }
        }
        let path = pb.finish();
        self.scene.items.push(Item {
            elem,
            styles,
            path,
            fill_rule,
            visible,
            polylines,
            markers,
            clips: clips.to_vec(),
        });
    }
}

fn text_paths<'a>(g: &'a Group, out: &mut Vec<&'a usvg::Path>) {
    for c in g.children() {
        match c {
            Node::Path(p) => out.push(p),
            Node::Group(g) => text_paths(g, out),
            _ => {}
        }
    }
}
