//! How the automatic sheet decides what each element becomes, in steps: the
//! ground it lies on, lines and marks, regions and their textures, the
//! regions' borders, then labels.

use std::collections::{BTreeMap, BTreeSet};

use taxel_format::DeviceProfile;

use super::arrows::LineEnds;
use super::ground::{Ground, clipped_away, paper};
use super::labels::{Figures, Lines, Room, place_labels};
use super::legend;
use super::{
    BRAILLE_CLEARANCE_MM, CIRCLE_MM, Decision, FAINT_SHARE, FillClass, Filled, LIGHT_GUIDE_GREY, LeftOut,
    MARK_KIND_MIN, MARK_MM, MARK_SPACING_MM, MAX_TEXTURES, MIN_FILL_MM2, Measure, NEAR_MM, Neighbours, Plan, Region,
    colour, compact, darkness, grey, min_region_mm, outline_style, rgb, round, textures, visible,
};
use crate::drawing::{Drawing, Paint, PathShape, Rgba, Shape, StyledBy, TextShape};
use crate::geometry::filled_area;
use crate::spatial::{self, Bbox, Occupancy};

/// Shapes closer than this share a border (a tessellation's neighbours).
const ABUT_MM: f64 = 0.05;

/// Decides, without changing the drawing, what the automatic sheet makes of
/// each element that no annotation or style sheet styled.
pub fn plan(d: &Drawing, profile: &DeviceProfile) -> Plan {
    plan_measured(d, profile, Measure::BUILTIN)
}

/// [`plan`] with labels measured by `m`.
pub fn plan_measured(d: &Drawing, profile: &DeviceProfile, m: Measure<'_>) -> Plan {
    let ground = Ground::of(d, profile);
    let darkest = darkest_line(d);
    let mut draft = Draft {
        d,
        decisions: vec![Decision::default(); d.elements.len()],
        strokes: Vec::new(),
        faint: Vec::new(),
        shapes: Vec::new(),
        texts: Vec::new(),
        braille: Occupancy::default(),
    };
    draft.elements(&ground, darkest);
    // Shapes that share a border with another filled shape are regions of a
    // tessellation (a map's small districts), however small they have become.
    let regions: Vec<Region<'_>> = draft.shapes.iter().map(|f| f.region).collect();
    let neighbours = Neighbours::of(&regions);
    let abuts = neighbours.abutting(ABUT_MM);
    let small = draft.small(&neighbours, &abuts);
    let small = draft.legend_swatches(small);
    let (class_of, fills) = draft.marks_and_classes(&small);
    // Colour the fill classes: touching regions of different fills get different textures.
    // Touching (or lying in) each other, through the R*-tree.
    let edges = neighbours.class_edges(&class_of, NEAR_MM);
    let (fills, rank) = textured(fills, &edges);
    let outline = outline_style(profile);
    let too_small = draft.borders(&neighbours, &abuts, &class_of, &fills, &rank, min_region_mm(outline.width_mm));
    draft.labels(ground.page, &abuts, BRAILLE_CLEARANCE_MM + outline.width_mm / 2.0, m);
    Plan {
        textures: textures(profile),
        outline,
        fills,
        strokes: draft.strokes,
        faint: draft.faint,
        darkest: darkest.map(rgb),
        decisions: draft.decisions,
        too_small,
    }
}

/// The darkest line the sheet would make vibrate: grey lines much lighter
/// than it are guides (grid lines, light frames) and are left out, so the
/// axes and the data are felt rather than a lattice of grid lines.
fn darkest_line(d: &Drawing) -> Option<Rgba> {
    d.elements
        .iter()
        .filter(|e| e.styled_by == StyledBy::Nothing && e.visible && matches!(e.shape, Shape::Path(_)))
        .filter(|e| e.paint.stroked && e.paint.stroke_width_mm > 0.0)
        .filter_map(|e| e.paint.stroke.filter(|&c| visible(c)))
        .max_by(|a, b| darkness(*a).total_cmp(&darkness(*b)))
}

/// Whether a stroke of colour `c` is faint beside the drawing's `darkest`
/// line: a grey much lighter than it, or a grey as light as a guide.
fn faint(c: Option<Rgba>, darkest: Option<Rgba>) -> bool {
    c.zip(darkest).is_some_and(|(c, top)| {
        let (d, top) = (darkness(c), darkness(top));
        grey(c) && (d < FAINT_SHARE * top || (d <= darkness(LIGHT_GUIDE_GREY) && d < top))
    })
}

/// Whether a fill of `paint` is seen on the page: painted, and not paper
/// on a ground where paper is not a figure.
fn fill_seen(paint: Paint, ground: &Ground) -> bool {
    paint.filled && paint.fill.is_none_or(|c| visible(c) && (ground.white_is_figure || !paper(c)))
}

/// Whether text of `paint` is seen: unless a colour of it is known and
/// neither its fill nor its stroke is painted in a colour with alpha. (A
/// text that no fonts laid out has no known colour; a gradient or a
/// pattern is taken to be seen.)
fn text_seen(paint: Paint) -> bool {
    let unseen = |painted: bool, c: Option<Rgba>| !painted || c.is_some_and(|c| !visible(c));
    let known = paint.fill.is_some() || paint.stroke.is_some();
    !(known && unseen(paint.filled, paint.fill) && unseen(paint.stroked, paint.stroke))
}

/// Small enough to be a mark (before its neighbours are looked at).
fn small_size(f: &Filled<'_>) -> bool {
    let b = f.region.bbox;
    let (w, h) = (b.2 - b.0, b.3 - b.1);
    w.max(h) <= MARK_MM || (w.max(h) <= CIRCLE_MM && round(b, f.area))
}

/// Textures for the fill classes, so that touching regions (`edges`) of
/// different fills get different ones: the classes largest first, and the
/// rank of each class (as `fills` gave them) in that order.
fn textured(mut fills: Vec<FillClass>, edges: &[(usize, usize)]) -> (Vec<FillClass>, Vec<usize>) {
    let mut order: Vec<usize> = (0..fills.len()).collect();
    order.sort_by(|&a, &b| fills[b].area_mm2.total_cmp(&fills[a].area_mm2).then(fills[a].fill.cmp(&fills[b].fill)));
    let colours = colour(fills.len(), edges, &order, MAX_TEXTURES);
    for (k, c) in colours.into_iter().enumerate() {
        fills[k].texture = c;
    }
    // Report classes largest first; keep decisions pointing at the right class.
    let mut rank = vec![0; fills.len()];
    for (r, &k) in order.iter().enumerate() {
        rank[k] = r;
    }
    let fills: Vec<FillClass> = order.iter().map(|&k| fills[k].clone()).collect();
    (fills, rank)
}

/// What the sheet has decided so far, filled in step by step.
struct Draft<'d> {
    d: &'d Drawing,
    /// One decision per element.
    decisions: Vec<Decision>,
    /// Distinct stroke colours that vibrate, in first-seen order.
    strokes: Vec<Option<[u8; 3]>>,
    /// Distinct faint stroke colours, in first-seen order.
    faint: Vec<[u8; 3]>,
    /// The filled shapes, to be told apart into regions and marks.
    shapes: Vec<Filled<'d>>,
    /// The texts, placed last.
    texts: Vec<(usize, &'d TextShape)>,
    /// Where braille may not go: the marks, then the braille placed.
    braille: Occupancy,
}

impl<'d> Draft<'d> {
    /// Each element no annotation styled: left out, a text set aside, or a
    /// path decided by [`Draft::path`].
    fn elements(&mut self, ground: &Ground, darkest: Option<Rgba>) {
        let d = self.d;
        let line_ends = LineEnds::of(d);
        // Each seen fill's area, measured once and on every core: a
        // scribble's area is a sweep of many rows, and a map at the input
        // limit has tens of thousands of regions.
        let areas: Vec<f64> = {
            use rayon::prelude::*;
            d.elements
                .par_iter()
                .map(|e| match &e.shape {
                    Shape::Path(p) if e.styled_by == StyledBy::Nothing && fill_seen(e.paint, ground) => {
                        filled_area(&p.outline, p.fill_rule)
                    }
                    _ => 0.0,
                })
                .collect()
        };
        for (i, e) in d.elements.iter().enumerate() {
            if e.styled_by != StyledBy::Nothing {
                continue;
            }
            let dec = &mut self.decisions[i];
            let Some(b) = e.bounds() else {
                dec.left_out = Some(LeftOut::Empty);
                continue;
            };
            dec.left_out = if !e.visible {
                Some(LeftOut::Hidden)
            } else if !spatial::meet(b, ground.page) {
                Some(LeftOut::OffPage)
            } else if clipped_away(e, b) {
                Some(LeftOut::ClippedAway)
            } else {
                None
            };
            if dec.left_out.is_some() {
                continue;
            }
            match &e.shape {
                Shape::Image { .. } => dec.left_out = Some(LeftOut::Image),
                // Text drawn in no colour that is seen (at opacity 0, as a
                // chart's tooltip waiting for the pointer) is not a label.
                Shape::Text(_) if !text_seen(e.paint) => dec.left_out = Some(LeftOut::Unpainted),
                // Text is placed once every mark is known, so braille avoids the dots.
                Shape::Text(t) => self.texts.push((i, t)),
                Shape::Path(p) => self.path(i, p, (b, areas[i]), ground, darkest, &line_ends),
            }
        }
    }

    /// Path `i`, of box `b` and filled area `area` (mm²): a line that vibrates or is faint, its markers'
    /// dots, an arrowhead, or a filled shape for [`Draft::small`] and
    /// [`Draft::marks_and_classes`] to tell apart.
    fn path(
        &mut self,
        i: usize,
        p: &'d PathShape,
        (b, area): (Bbox, f64),
        ground: &Ground,
        darkest: Option<Rgba>,
        line_ends: &LineEnds,
    ) {
        let dec = &mut self.decisions[i];
        let paint = self.d.elements[i].paint;
        // A fill that encloses nothing (a `<line>`, which SVG fills by default, or
        // collinear points) is not seen, so not a region: taken for one, it would
        // abut the lines it crosses and lose its vibrating stroke (a chart's axes).
        let filled = fill_seen(paint, ground) && area > MIN_FILL_MM2;
        let stroked = paint.stroked && paint.stroke_width_mm > 0.0 && paint.stroke.is_none_or(visible);
        if filled && ground.backgrounds.contains(&i) {
            dec.left_out = Some(LeftOut::Background);
            return;
        }
        if stroked && faint(paint.stroke, darkest) {
            dec.faint = true;
            let c = paint.stroke.map(rgb).unwrap_or_default();
            if !self.faint.contains(&c) {
                self.faint.push(c);
            }
        } else if stroked {
            dec.outline = true;
            let key = paint.stroke.map(rgb);
            if !self.strokes.contains(&key) {
                self.strokes.push(key);
            }
        }
        for &(x, y) in &p.markers {
            dec.mark = true;
            let r = 1.0 + BRAILLE_CLEARANCE_MM;
            self.braille.place((x - r, y - r, x + r, y + r));
        }
        if filled && line_ends.arrowhead(&p.outline, b, paint.fill) {
            // An arrowhead (a diagram's, a chart's annotation): a
            // mark at its line's end, not a piece of a tessellation
            // with the box its tip touches, which would lose its
            // outline there.
            if compact(b, area) {
                dec.mark = true;
                self.braille.place(spatial::grow(b, BRAILLE_CLEARANCE_MM));
            } else if !dec.outline && !dec.mark {
                dec.left_out = Some(LeftOut::SmallShape);
            }
        } else if filled {
            self.shapes.push(Filled { i, region: Region { outline: &p.outline, bbox: b }, area });
        } else if !dec.outline && !dec.mark {
            dec.left_out = Some(if dec.faint { LeftOut::Faint } else { LeftOut::Unpainted });
        }
    }

    /// Which filled shapes are marks rather than regions, given which of
    /// them `abuts` a neighbour.
    fn small(&self, neighbours: &Neighbours<'_, '_>, abuts: &[bool]) -> Vec<bool> {
        let (d, shapes) = (self.d, &self.shapes);
        // Small shapes that touch are a tessellation's pieces (a map's small
        // districts), but marks that lie across each other (a dense scatter
        // plot's) stay marks, and so do all the marks of their kind (one fill,
        // one size), the ones that only graze a neighbour too.
        let across = neighbours.lying_across(ABUT_MM, |k| abuts[k] && small_size(&shapes[k]));
        let kind_of = |f: &Filled<'_>| {
            let b = f.region.bbox;
            let size = |v: f64| (v * 100.0).round() as i64;
            (d.elements[f.i].paint.fill.map(rgb), size(b.2 - b.0), size(b.3 - b.1))
        };
        let mut kinds: BTreeMap<_, (usize, bool)> = BTreeMap::new();
        for (k, f) in shapes.iter().enumerate().filter(|(_, f)| small_size(f)) {
            let e = kinds.entry(kind_of(f)).or_default();
            *e = (e.0 + 1, e.1 || across[k]);
        }
        let scattered = |f: &Filled<'_>| kinds.get(&kind_of(f)).is_some_and(|&(n, any)| any && n >= MARK_KIND_MIN);
        shapes.iter().enumerate().map(|(k, f)| small_size(f) && (!abuts[k] || across[k] || scattered(f))).collect()
    }

    /// `small` without a legend's swatches (a small shape with a text just
    /// right of it, lined up with another such, as matplotlib, Vega-Lite and
    /// map legends draw them: [`legend::Texts::beside`]) of a fill that has
    /// regions elsewhere: those are regions of that fill, patches of its
    /// texture. Made a dot, or left out as a small shape, a swatch would no
    /// longer stand beside its text as the texture it explains, and the key
    /// would list the legend's swatches as a symbol of their own ("symbol:
    /// Legend") instead of giving the texture its legend text.
    fn legend_swatches(&self, mut small: Vec<bool>) -> Vec<bool> {
        let fill = |k: usize| self.d.elements[self.shapes[k].i].paint.fill.map(rgb);
        let region_fills: BTreeSet<_> = (0..self.shapes.len()).filter(|&k| !small[k]).map(fill).collect();
        let candidates: Vec<usize> =
            (0..self.shapes.len()).filter(|&k| small[k] && region_fills.contains(&fill(k))).collect();
        if candidates.is_empty() {
            return small;
        }
        let texts = legend::Texts::of(self.d);
        let pairs: Vec<(usize, Bbox)> = candidates
            .into_iter()
            .map(|k| (k, self.shapes[k].region.bbox))
            .filter(|&(_, b)| texts.beside(b).is_some())
            .collect();
        for (&(k, _), lined) in pairs.iter().zip(legend::lined_up(&pairs)) {
            if lined {
                small[k] = false;
            }
        }
        small
    }

    /// The `small` shapes become marks (thinned where crowded) and the
    /// others regions: each shape's fill class (`None` for a mark), and the
    /// classes in the order first seen.
    fn marks_and_classes(&mut self, small: &[bool]) -> (Vec<Option<usize>>, Vec<FillClass>) {
        let mut classes: BTreeMap<Option<[u8; 3]>, usize> = BTreeMap::new();
        let mut fills: Vec<FillClass> = Vec::new();
        let mut class_of = vec![None; self.shapes.len()];
        let mut kept_marks = Occupancy::default();
        for (k, f) in self.shapes.iter().enumerate() {
            let e = &self.d.elements[f.i];
            let b = f.region.bbox;
            let dec = &mut self.decisions[f.i];
            if small[k] {
                if compact(b, f.area) {
                    // A dot closer to one already kept than it can be felt apart
                    // from is left out: a dense scatter keeps an even sample of its marks.
                    let (cx, cy) = ((b.0 + b.2) / 2.0, (b.1 + b.3) / 2.0);
                    let half = MARK_SPACING_MM / 2.0;
                    if !kept_marks.place((cx - half, cy - half, cx + half, cy + half)) {
                        dec.left_out = Some(LeftOut::Crowded);
                        continue;
                    }
                    dec.mark = true;
                    self.braille.place(spatial::grow(b, BRAILLE_CLEARANCE_MM));
                } else if !dec.outline && !dec.mark {
                    dec.left_out = Some(LeftOut::SmallShape);
                }
                continue;
            }
            let key = e.paint.fill.map(rgb);
            let c = *classes.entry(key).or_insert_with(|| {
                fills.push(FillClass { fill: key, area_mm2: 0.0, regions: 0, first: e.name.clone(), texture: None });
                fills.len() - 1
            });
            fills[c].area_mm2 += f.area;
            fills[c].regions += 1;
            dec.region = Some(c);
            class_of[k] = Some(c);
        }
        (class_of, fills)
    }

    /// The regions' outlines: which vibrate, given each shape's class
    /// `class_of` and each class's `rank` among the textured `fills`; the
    /// decisions' regions renumbered by rank. Returns the regions whose
    /// borders are left out, their fill's regions being mostly smaller than
    /// `min_region` across.
    fn borders(
        &mut self,
        neighbours: &Neighbours<'_, '_>,
        abuts: &[bool],
        class_of: &[Option<usize>],
        fills: &[FillClass],
        rank: &[usize],
        min_region: f64,
    ) -> Vec<usize> {
        // Regions of one fill that share a border (a map's districts drawn in one
        // colour) have one texture on both sides: only an outline tells them apart.
        let alike = neighbours.abutting_alike(class_of, ABUT_MM);
        // A region its own border band would mostly cover is felt as border, not
        // as a region. The borders of one fill are kept or left out together, so
        // the reader meets one rule across the map rather than a few outlined
        // regions adrift in a texture: left out when most of the fill's regions
        // that share borders with each other are that small (France's 96
        // departments on a 60 mm map), kept when most are large enough (a map of
        // states keeps its few small ones' borders).
        let mut felt = vec![(0usize, 0usize); fills.len()];
        for (k, f) in self.shapes.iter().enumerate() {
            if let (true, Some(c)) = (alike[k], class_of[k]) {
                felt[rank[c]].0 += usize::from(f.area.sqrt() >= min_region);
                felt[rank[c]].1 += 1;
            }
        }
        let bordered = |c: usize| 2 * felt[c].0 >= felt[c].1;
        let mut too_small = Vec::new();
        for (k, f) in self.shapes.iter().enumerate() {
            let dec = &mut self.decisions[f.i];
            if let Some(c) = dec.region {
                let c = rank[c];
                dec.region = Some(c);
                if alike[k] && !bordered(c) {
                    too_small.push(f.i);
                }
                if fills[c].texture.is_none() || (alike[k] && bordered(c)) {
                    // Given up, or beside its own texture: its outline says where it is.
                    dec.outline = true;
                } else if abuts[k] {
                    // Between textured regions the border is felt as the change of
                    // texture; a stroke on both sides of it would vibrate twice.
                    dec.outline = false;
                }
            }
        }
        too_small
    }

    /// The texts' braille, last, once every mark and vibrating line is
    /// known: braille on a vibrating line is felt as neither (the two add
    /// up, T0410; a chart's tick labels sat on its axis), so a label is
    /// moved off the lines (by `off_lines` mm), a little, or left out.
    fn labels(&mut self, page: Bbox, abuts: &[bool], off_lines: f64, m: Measure<'_>) {
        let d = self.d;
        let room = Room {
            page,
            lines: if self.texts.is_empty() { Lines::default() } else { Lines::of(d, &self.decisions) },
            off_lines,
            figures: if self.texts.is_empty() {
                Figures::default()
            } else {
                Figures::of(d, &self.shapes, abuts, &self.decisions)
            },
        };
        let mut texts = std::mem::take(&mut self.texts);
        // An axis's tick labels that would run together, thinned to an even step first (T0328).
        let thinned = super::ticks::thin(&texts, m);
        for &(i, every) in &thinned {
            self.decisions[i].left_out = Some(LeftOut::Thinned { every: every as u8 });
        }
        texts.retain(|(i, _)| !thinned.iter().any(|&(k, _)| k == *i));
        place_labels(d, texts, &room, &mut self.decisions, &mut self.braille, m);
    }
}
