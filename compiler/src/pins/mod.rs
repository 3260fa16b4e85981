//! Back end for pin-array displays (stage 4, family 4).
//!
//! Pin-matrix displays (device family 4): a resolved [`Drawing`] legalised
//! to a pin image, from the same annotations as every other device.
//!
//! Each style becomes what a pin array can say (`docs/pins.md`):
//! - `vibrate` → an outline one pin wide, 8-connected, without L-corners
//!   (pixel-art rules, `line.rs`), blinking where the device can blink and
//!   solid elsewhere;
//! - `grating` → a ridge texture that keeps the orientation, its period in
//!   whole pins, distinct from the drawing's other gratings (`texture.rs`),
//!   one blank pin inside its own outline;
//! - `dots` → clusters of pins along the path, `dot` → a cluster at each
//!   point symbol;
//! - `braille` → cells on the device's own braille grid (`text.rs`); the
//!   drawing's `<title>` goes to the device's text line when it has one.
//!
//! On a device with heights, outlines, dots and braille stand at the top
//! level and textures at half of it, so outlines stand above textures. The
//! design rules are checked on the pin grid (`rules.rs`). The image covers the
//! whole drawing; when that is larger than the display, the bundle says
//! whether it is read as pages or panned ([`navigation`]).
//!
//! ```
//! use taxel_compiler::drawing::{Drawing, Element, Page, PathShape, Shape};
//! use taxel_compiler::annotation::{Style, Vibrate};
//! use taxel_compiler::geometry::Polyline;
//! use taxel_format::profiles;
//!
//! let square = Polyline { points: vec![(10.0, 10.0), (40.0, 10.0), (40.0, 40.0), (10.0, 40.0)], closed: true };
//! let drawing = Drawing {
//!     page: Page { width_mm: 150.0, height_mm: 100.0, scale: 1.0, offset_mm: (0.0, 0.0), sheet_mm: None },
//!     elements: vec![Element {
//!         name: "square".into(),
//!         visible: true,
//!         styles: vec![Style::Vibrate(Vibrate { width_mm: 1.5, freq_hz: 50.0, amplitude: 1.0, soft_mm: 0.0 })],
//!         shape: Shape::Path(PathShape { outline: vec![square], ..Default::default() }),
//!         ..Default::default()
//!     }],
//!     ..Default::default()
//! };
//! let mut diags = Vec::new();
//! let image = taxel_compiler::pins::legalise(&drawing, &profiles::builtin("dotpad").unwrap(), &mut diags).unwrap();
//! assert_eq!((image.cols, image.rows), (60, 40));
//! // A 30 mm square at 2.5 mm pitch: 13 pins a side, 48 pins around.
//! assert_eq!(image.pins.iter().filter(|p| p.raised()).count(), 48);
//! ```

pub mod export;
pub(crate) mod key;
pub(crate) mod line;
pub(crate) mod rules;
pub(crate) mod text;
pub(crate) mod texture;

use taxel_format::{
    Bundle, Chunk, DeviceProfile, FamilyParams, MAX_PIN_IMAGE, MAX_PIN_SIDE, Manifest, Navigation, Pin, PinImage,
    PinParams, Provenance, ProvenanceEntry,
};

use crate::annotation::Style;
use crate::diagnostic::Diagnostic;
use crate::drawing::{Clip, Drawing, Element, Shape};
use crate::geometry::{FillRule, Polyline};
use crate::style::legend::Swatch;
use line::PinPos;
use texture::Pattern;

/// Blink half-period for `vibrate` outlines, in milliseconds (rounded up to
/// the device's blink step). Half a second up, half a second down: slow
/// enough that a resting finger feels each change, fast enough to notice
/// within a second. Chosen, not measured: no study of blink rates on pin
/// arrays was found (`reference/pins.md`).
pub const BLINK_HALF_PERIOD_MS: u32 = 500;

/// A refresh time (ms) below which a device pans; at or above it, and when
/// it is not published, a drawing larger than the display is read as pages.
pub const PAN_REFRESH_MS: u32 = 500;

/// How a drawing larger than `profile`'s display is read, and why.
///
/// A pannable surface lets the reader move the picture a pin at a time, but
/// every move costs a refresh; on a display that refreshes in about 2 s (the
/// Monarch) or whose refresh time is not published (Dot Pad, Graphiti),
/// moving a pin at a time would leave the reader waiting with the picture
/// shifting under the finger, so those get pages, each a whole display,
/// which is also how Dot Pad's own DTMS files are organised. A display that
/// refreshes quickly (HyperBraille, about 10 Hz) pans.
pub fn navigation(p: &PinParams) -> Navigation {
    if p.refresh_ms > 0 && p.refresh_ms < PAN_REFRESH_MS { Navigation::Pan } else { Navigation::Pages }
}

/// The heights a profile gives each kind of feature.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Heights {
    pub outline: u8,
    pub texture: u8,
}

impl Heights {
    fn new(levels: u8) -> Self {
        Heights { outline: levels.max(1), texture: if levels >= 2 { levels / 2 } else { 1 } }
    }
}

/// The pin image being built, with the element that raised each pin (for
/// the design rules).
pub(crate) struct Canvas {
    pub image: PinImage,
    /// Element index + 1 of the feature that raised each pin, 0 for none.
    pub owner: Vec<u32>,
    /// Pairs of distinct elements closer than one blank pin, with a pin where they meet.
    pub touching: std::collections::BTreeMap<(u32, u32), PinPos>,
    pub pitch: (f64, f64),
    /// The pins the element being drawn may raise, by index, when it is
    /// clipped ([`clip_mask`]); `None` for every pin.
    clip: Option<std::rc::Rc<Vec<bool>>>,
    /// The pins (by index) the texture being drawn may not raise: those
    /// under opaque fills painted over it, which hide it ([`hidden_under`]).
    hidden: std::collections::HashSet<usize>,
    /// The pins (by index) raised by a texture and by nothing else, which
    /// a braille label clears around itself ([`Canvas::clear_texture`]).
    texture: Vec<bool>,
    /// Whether the feature being drawn is a texture.
    filling: bool,
}

impl Canvas {
    fn new(cols: u32, rows: u32, pitch: (f64, f64)) -> Self {
        Canvas {
            image: PinImage::new(cols, rows),
            owner: vec![0; cols as usize * rows as usize],
            touching: Default::default(),
            pitch,
            clip: None,
            hidden: Default::default(),
            texture: vec![false; cols as usize * rows as usize],
            filling: false,
        }
    }

    /// Page millimetres to pin units (pin centres at integers).
    pub fn to_pins(&self, p: (f64, f64)) -> (f64, f64) {
        (p.0 / self.pitch.0 - 0.5, p.1 / self.pitch.1 - 0.5)
    }

    fn index(&self, p: PinPos) -> Option<usize> {
        let (c, r) = p;
        (c >= 0 && r >= 0 && (c as u64) < self.image.cols as u64 && (r as u64) < self.image.rows as u64)
            .then(|| r as usize * self.image.cols as usize + c as usize)
    }

    pub fn owner_at(&self, p: PinPos) -> u32 {
        self.index(p).map_or(0, |i| self.owner[i])
    }

    /// Raises pin `p` for element `elem` (its index) at `height`. Where
    /// features overlap the higher wins, and a pin blinks only if everything
    /// on it blinks. Records distinct elements that meet or touch.
    pub fn raise(&mut self, p: PinPos, elem: usize, height: u8, blink: bool) {
        let Some(i) = self.index(p) else { return };
        if self.clip.as_ref().is_some_and(|c| !c.get(i).copied().unwrap_or(false)) || self.hidden.contains(&i) {
            return;
        }
        let me = elem as u32 + 1;
        for dr in -1..=1 {
            for dc in -1..=1 {
                let o = self.owner_at((p.0 + dc, p.1 + dr));
                if o != 0 && o != me {
                    self.touching.entry((o.min(me), o.max(me))).or_insert(p);
                }
            }
        }
        let old = self.image.pins[i];
        let blink = if old.raised() { old.blinks() && blink } else { blink };
        self.image.pins[i] = Pin::new(old.height().max(height), blink);
        self.owner[i] = me;
        // (A pin an outline raised stays the outline's under a texture.)
        self.texture[i] = self.filling && (!old.raised() || self.texture[i]);
    }

    /// Lowers pin `p` if a texture alone raised it: the blank a braille
    /// label keeps around itself inside a textured region.
    pub fn clear_texture(&mut self, p: PinPos) {
        let Some(i) = self.index(p) else { return };
        if self.texture[i] {
            self.image.pins[i] = Pin::FLUSH;
            self.owner[i] = 0;
            self.texture[i] = false;
        }
    }

    /// Lowers pin `p` (an empty dot of a braille cell placed by `elem`),
    /// recording the element whose graphics it cut into.
    pub fn lower(&mut self, p: PinPos, elem: usize) {
        let Some(i) = self.index(p) else { return };
        let me = elem as u32 + 1;
        let o = self.owner[i];
        if o != 0 && o != me {
            self.touching.entry((o.min(me), o.max(me))).or_insert(p);
        }
        self.image.pins[i] = Pin::FLUSH;
        self.owner[i] = me;
        self.texture[i] = false;
    }
}

/// Legalises `drawing` for the pin-matrix `profile`: the pin image, or
/// `None` (with an error diagnostic) when the profile is not a pin matrix or
/// the drawing is too large for any pin image.
pub fn legalise(drawing: &Drawing, profile: &DeviceProfile, diags: &mut Vec<Diagnostic>) -> Option<PinImage> {
    legalise_with(drawing, &crate::CompileOptions::new(*profile), diags)
}

/// [`legalise`] for `opts.profile`, its braille written as `opts` chooses
/// (the braille service, the reader's language, a style sheet's table).
pub fn legalise_with(drawing: &Drawing, opts: &crate::CompileOptions, diags: &mut Vec<Diagnostic>) -> Option<PinImage> {
    let profile = &opts.profile;
    let FamilyParams::Pins(params) = profile.params else {
        diags.push(Diagnostic::error("T0900", format!("internal error: {} is not a pin-matrix profile", profile.name)));
        return None;
    };
    let pitch = (profile.pitch_x_mm as f64, profile.pitch_y_mm as f64);
    let (dev_cols, dev_rows) = (profile.cols as u32, profile.rows as u32);
    let want = |mm: f64, p: f64| if mm.is_finite() && mm > 0.0 { (mm / p - 1e-9).ceil().min(1e12) } else { 0.0 };
    let (w, h) = (want(drawing.page.width_mm, pitch.0), want(drawing.page.height_mm, pitch.1));
    if w > MAX_PIN_SIDE as f64 || h > MAX_PIN_SIDE as f64 || w * h > MAX_PIN_IMAGE as f64 {
        diags.push(
            Diagnostic::error(
                "T0701",
                format!(
                    "the drawing is {} x {} mm, {w} x {h} pins at the {} x {} mm pitch: more than a pin image holds \
                     ({MAX_PIN_SIDE} pins a side, {MAX_PIN_IMAGE} pins)",
                    drawing.page.width_mm, drawing.page.height_mm, pitch.0, pitch.1
                ),
            )
            .with_help("use --fit to scale it to the display, or --region to take part of it"),
        );
        return None;
    }
    let cols = (w as u32).max(dev_cols);
    let rows = (h as u32).max(dev_rows);
    let mut canvas = Canvas::new(cols, rows, pitch);
    canvas.image.navigation = navigation(&params);
    let heights = Heights::new(params.height_levels);
    let blink = params.can_blink();

    // Gratings first get their patterns, in document order, so that the
    // textures of different gratings stay distinguishable.
    let patterns = assign_patterns(drawing, pitch.0.max(pitch.1), diags);
    let how = Draw { opts, params: &params, patterns: &patterns, heights, blink };
    let mut notes = crate::braille::Notes::default();
    draw(&mut canvas, drawing, &how, &mut notes, diags);
    // The device's text line says the drawing's title, then the key of the
    // labels written as key codes (T0326), as a transcriber gives the key
    // beside the graphic.
    let key = crate::style::key_line(drawing);
    let line = [drawing.title.as_str(), key.as_str()].into_iter().filter(|s| !s.is_empty()).collect::<Vec<_>>();
    if params.text_cells > 0 && !line.is_empty() {
        canvas.image.text = text::text_line(&line.join("; "), opts, &mut notes, diags);
    }
    // The key's pages (`key.rs`), drawn as the graphic is.
    let legend = crate::style::legend(drawing);
    let key = key::pages(drawing, &legend, &how, (dev_cols, dev_rows), pitch, &mut notes, diags);
    notes.emit(diags);
    rules::check(&canvas, drawing, diags);
    let mut image = canvas.image;
    let appended = match &key {
        key::Key::None => None,
        key::Key::Pages(k) => Some(key::append(&mut image, k, (dev_cols, dev_rows))),
        key::Key::TooLarge => Some(None),
    };
    if let Some(appended) = appended {
        match appended {
            Some((first, n)) => diags.push(Diagnostic::note(
                "T0710",
                format!(
                    "the key ({} entries{}{}) is on page{} {} of the pin image, after the graphic",
                    legend.shown().len(),
                    if legend.codes.is_empty() { String::new() } else { format!(", {} key codes", legend.codes.len()) },
                    if legend.unplaced.is_empty() {
                        String::new()
                    } else {
                        format!(", {} texts the graphic has no room for", legend.unplaced.len())
                    },
                    if n == 1 { "" } else { "s" },
                    if n == 1 { first.to_string() } else { format!("{first} to {}", first + n - 1) }
                ),
            )),
            None => diags.push(
                Diagnostic::warning(
                    "T0711",
                    "the key's pages would make the pin image larger than a bundle holds: the key is in the \
                     bundle's provenance only (a host says it), not on the display",
                )
                .with_help("use --fit to scale the drawing to one display"),
            ),
        }
    }
    if image.pins.iter().any(|p| p.blinks()) {
        let step = params.blink_step_ms as u32;
        image.blink_ms = BLINK_HALF_PERIOD_MS.div_ceil(step.max(1)) * step.max(1);
    }
    if cols > dev_cols || rows > dev_rows {
        let (across, down) = (cols.div_ceil(dev_cols), rows.div_ceil(dev_rows));
        let how = match image.navigation {
            Navigation::Pages => format!("read as {} pages ({across} across, {down} down)", across * down),
            Navigation::Pan => "read as a pannable surface".to_string(),
        };
        diags.push(
            Diagnostic::note(
                "T0702",
                format!("the drawing is {cols} x {rows} pins, larger than the {dev_cols} x {dev_rows} display: {how}"),
            )
            .with_help("use --fit to scale it to one display"),
        );
    }
    Some(image)
}

/// What a drawing's elements are drawn with on a canvas.
pub(crate) struct Draw<'a> {
    pub opts: &'a crate::CompileOptions,
    pub params: &'a PinParams,
    /// Each grating's pattern ([`assign_patterns`]).
    pub patterns: &'a [((u64, u64), Pattern)],
    pub heights: Heights,
    pub blink: bool,
}

/// Draws every visible element of `drawing` on `canvas`, labels last.
pub(crate) fn draw(
    canvas: &mut Canvas,
    drawing: &Drawing,
    how: &Draw<'_>,
    notes: &mut crate::braille::Notes,
    diags: &mut Vec<Diagnostic>,
) {
    let (heights, blink, pitch) = (how.heights, how.blink, canvas.pitch);
    let regions = region_map(canvas, drawing);
    let opaque = crate::drawing::OpaqueFills::of(drawing);
    let mut labels = Vec::new();
    // Elements clipped alike (a chart's data in its axes) share one mask.
    let mut clipped_by: Option<(&[Clip], std::rc::Rc<Vec<bool>>)> = None;
    for (i, e) in drawing.elements.iter().enumerate() {
        if !e.visible {
            continue;
        }
        canvas.clip = match &e.shape {
            Shape::Path(p) if !p.clips.is_empty() => match &clipped_by {
                Some((c, mask)) if *c == &p.clips[..] => Some(mask.clone()),
                _ => {
                    let mask = std::rc::Rc::new(clip_mask(canvas, &p.clips));
                    clipped_by = Some((&p.clips[..], mask.clone()));
                    Some(mask)
                }
            },
            _ => None,
        };
        for style in &e.styles {
            match (style, &e.shape) {
                (Style::Vibrate(_), Shape::Path(p)) => {
                    outline(canvas, &p.outline, i, heights.outline, blink);
                }
                (Style::Grating(g), Shape::Path(p)) => {
                    let pattern = how
                        .patterns
                        .iter()
                        .find(|(k, _)| *k == grating_key(g.wavelength_mm, g.angle_deg))
                        .map_or(Pattern::wanted(g.wavelength_mm, g.angle_deg, pitch.0), |(_, p)| *p);
                    let outlined = e.styles.iter().any(|s| matches!(s, Style::Vibrate(_) | Style::Dots(_)));
                    let fill = Fill { pattern, height: heights.texture, outlined, regions: &regions };
                    // Not where opaque fills painted later hide it (a flag's
                    // canton over its stripes, a map's legend box), as the
                    // array's grated layers are not.
                    canvas.hidden = hidden_under(canvas, drawing, &opaque, i);
                    canvas.filling = true;
                    texture_fill(canvas, &p.outline, fill, i, e, diags);
                    canvas.filling = false;
                    canvas.hidden.clear();
                }
                (Style::Dots(d), Shape::Path(p)) => {
                    dotted(canvas, &p.outline, d.radius_mm, d.spacing_mm, i, heights.outline);
                }
                (Style::Dot(d), Shape::Path(p)) => {
                    let centres = if p.markers.is_empty() {
                        e.bounds().map(|b| vec![((b.0 + b.2) / 2.0, (b.1 + b.3) / 2.0)]).unwrap_or_default()
                    } else {
                        p.markers.clone()
                    };
                    for c in centres {
                        cluster(canvas, c, d.radius_mm, i, heights.outline);
                    }
                }
                (Style::Braille(br), Shape::Text(t)) => labels.push((i, t, br.grade)),
                (Style::Braille(_), _) => diags.push(
                    Diagnostic::warning("T0121", "braille() applies to <text> elements; this one is not text")
                        .with_element(e.name.clone())
                        .on_line(e.line),
                ),
                (Style::Brush(_), _) => diags.push(
                    Diagnostic::warning(
                        "T0120",
                        format!(
                            "brush() strokes do not play on the pin-matrix display {}; left out",
                            how.opts.profile.name
                        ),
                    )
                    .with_element(e.name.clone())
                    .with_help("brush() strokes play on vibrotactile grids such as brush-4x3")
                    .on_line(e.line),
                ),
                (_, _) => {}
            }
        }
    }
    canvas.clip = None;
    // Labels last, on top of the graphics they name.
    for (i, t, grade) in labels {
        let label = text::Label { text: t, grade, elem: i, height: heights.outline, e: &drawing.elements[i] };
        text::place(canvas, how.params, &label, how.opts, notes, diags);
    }
}

/// A bundle for the pin-matrix `profile` from `drawing`: its manifest and
/// pin image. `None` when nothing tactile was made (with an error) or the
/// drawing cannot be legalised.
pub fn build_bundle(drawing: &Drawing, opts: &crate::CompileOptions, diags: &mut Vec<Diagnostic>) -> Option<Bundle> {
    let (profile, content_hash) = (&opts.profile, opts.content_hash);
    let image = legalise_with(drawing, opts, diags)?;
    if !image.pins.iter().any(|p| p.raised()) && image.text.is_empty() {
        if !crate::diagnostic::has_errors(diags) {
            let error = if drawing.only_pictures() {
                Diagnostic::error(
                    "T0300",
                    format!(
                        "nothing in this drawing can be rendered on {}: it holds only {} picture(s)",
                        profile.name,
                        drawing.elements.len()
                    ),
                )
                .with_help(crate::drawing::PICTURES_HELP)
            } else {
                Diagnostic::error("T0300", format!("nothing in this drawing can be rendered on {}", profile.name))
                    .with_help(
                        "mark shapes with data-tactile=\"vibrate()\" (or grating(), dots(), dot(), braille()), \
                         or map colours with --style FILE (see docs/annotations.md)",
                    )
            };
            diags.push(error);
        }
        return None;
    }
    let mut bundle = Bundle::new(Manifest { content_hash, ..Manifest::new(*profile) });
    bundle.chunks.push(Chunk::Pins(image));
    // Provenance entry 0 of a pin bundle is the drawing itself, so that
    // exports and hosts can name it (the DTMS title); an entry `key` holds
    // the key of its key codes in print (the DTMS text line's print text).
    let key = crate::style::key_line(drawing);
    let mut entries = Vec::new();
    if !drawing.title.is_empty() {
        entries.push(ProvenanceEntry { id: "svg".into(), label: drawing.title.clone(), line: 0 });
    }
    if !key.is_empty() {
        entries.push(ProvenanceEntry { id: "key".into(), label: key, line: 0 });
    }
    // The key's entries, and the texts the graphic has no room for, for a
    // host to say (the display shows them on its key pages).
    let legend = crate::style::legend(drawing);
    entries.extend(crate::style::legend::provenance(&legend, |s| !matches!(s, Swatch::Stroke(_))));
    entries.extend(legend.unplaced_entry());
    if !entries.is_empty() {
        bundle.chunks.push(Chunk::Provenance(Provenance { entries }));
    }
    if let Err(e) = bundle.to_bytes() {
        diags.push(Diagnostic::error("T0900", format!("internal error: the pin bundle does not validate: {e}")));
        return None;
    }
    Some(bundle)
}

fn grating_key(wavelength: f64, angle: f64) -> (u64, u64) {
    (wavelength.to_bits(), angle.to_bits())
}

/// Each distinct grating's pattern, in order of first use.
fn assign_patterns(drawing: &Drawing, pitch: f64, diags: &mut Vec<Diagnostic>) -> Vec<((u64, u64), Pattern)> {
    let mut out: Vec<((u64, u64), Pattern)> = Vec::new();
    for e in drawing.elements.iter().filter(|e| e.visible) {
        for s in &e.styles {
            let Style::Grating(g) = s else { continue };
            let key = grating_key(g.wavelength_mm, g.angle_deg);
            if out.iter().any(|(k, _)| *k == key) {
                continue;
            }
            let want = Pattern::wanted(g.wavelength_mm, g.angle_deg, pitch);
            if g.wavelength_mm / pitch < want.period as f64 - 0.5 {
                diags.push(
                    Diagnostic::warning(
                        "T0705",
                        format!(
                            "a grating of {} mm is finer than the {pitch} mm pin pitch can carry; \
                             it becomes ridges every {} pins ({} mm)",
                            g.wavelength_mm,
                            want.period,
                            want.period as f64 * pitch
                        ),
                    )
                    .with_element(e.name.clone())
                    .on_line(e.line),
                );
            }
            let taken: Vec<Pattern> = out.iter().map(|(_, p)| *p).collect();
            let got = want.nearest_free(&taken).unwrap_or(want);
            if got != want {
                diags.push(
                    Diagnostic::note(
                        "T0706",
                        format!(
                            "the grating ({} mm, {}°) would feel like another grating of this drawing on pins; \
                             it becomes ridges at {}° every {} pins instead",
                            g.wavelength_mm,
                            g.angle_deg,
                            got.angle_deg(),
                            got.period
                        ),
                    )
                    .with_element(e.name.clone())
                    .on_line(e.line),
                );
            }
            out.push((key, got));
        }
    }
    out
}

/// The pins of a shape's outline (every subpath, walked).
pub(crate) fn outline_pins(canvas: &Canvas, polys: &[Polyline]) -> Vec<PinPos> {
    let mut out = Vec::new();
    for pl in polys {
        let pts: Vec<(f64, f64)> = pl.walked().into_iter().map(|p| canvas.to_pins(p)).collect();
        out.extend(line::walk(&pts, pl.closed));
    }
    out
}

fn outline(canvas: &mut Canvas, polys: &[Polyline], elem: usize, height: u8, blink: bool) {
    for p in outline_pins(canvas, polys) {
        canvas.raise(p, elem, height, blink);
    }
}

/// The pins (by index) whose centres lie under the opaque fills painted
/// over element `i` ([`crate::drawing::OpaqueFills::above`]), which hide its texture.
fn hidden_under(
    canvas: &Canvas,
    drawing: &Drawing,
    opaque: &crate::drawing::OpaqueFills,
    i: usize,
) -> std::collections::HashSet<usize> {
    let mut out = std::collections::HashSet::new();
    for j in opaque.above(drawing, &[i]) {
        let Some(Shape::Path(p)) = drawing.elements.get(j).map(|e| &e.shape) else { continue };
        out.extend(inside_pins(canvas, &p.outline, p.fill_rule).into_iter().filter_map(|q| canvas.index(q)));
    }
    out
}

/// The pins an element clipped by `clips` may raise, by index: those inside
/// every clip region or on its edge (so that a line drawn along the edge, a
/// bar's base on a chart's axis, keeps its pins).
fn clip_mask(canvas: &Canvas, clips: &[Clip]) -> Vec<bool> {
    let n = canvas.owner.len();
    let mut mask = vec![true; n];
    for c in clips {
        let mut this = vec![false; n];
        let pins = inside_pins(canvas, &c.outline, c.fill_rule).into_iter().chain(outline_pins(canvas, &c.outline));
        for i in pins.filter_map(|p| canvas.index(p)) {
            if let Some(t) = this.get_mut(i) {
                *t = true;
            }
        }
        for (m, t) in mask.iter_mut().zip(this) {
            *m &= t;
        }
    }
    mask
}

/// Pins whose centres are inside the shape, by scanlines through pin centres.
pub(crate) fn inside_pins(canvas: &Canvas, polys: &[Polyline], rule: FillRule) -> Vec<PinPos> {
    let Some((x0, y0, x1, y1)) = crate::geometry::bounds(polys) else { return Vec::new() };
    let (_, r0) = canvas.to_pins((x0, y0));
    let (_, r1) = canvas.to_pins((x1, y1));
    let rows = canvas.image.rows as i64;
    let cols = canvas.image.cols as i64;
    let (r0, r1) = ((r0.ceil() as i64).max(0), (r1.floor() as i64).min(rows - 1));
    let mut out = Vec::new();
    let mut xs: Vec<(f64, i32)> = Vec::new();
    for r in r0..=r1 {
        let y = (r as f64 + 0.5) * canvas.pitch.1;
        xs.clear();
        for pl in polys {
            let n = pl.points.len();
            for i in 0..n {
                let (a, b) = (pl.points[i], pl.points[(i + 1) % n]);
                if (a.1 <= y) != (b.1 <= y) {
                    xs.push((a.0 + (y - a.1) / (b.1 - a.1) * (b.0 - a.0), if b.1 > a.1 { 1 } else { -1 }));
                }
            }
        }
        xs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut winding = 0;
        for k in 0..xs.len().saturating_sub(1) {
            winding += xs[k].1;
            let inside = match rule {
                FillRule::NonZero => winding != 0,
                FillRule::EvenOdd => k % 2 == 0,
            };
            if !inside {
                continue;
            }
            let (ca, cb) = (xs[k].0 / canvas.pitch.0 - 0.5, xs[k + 1].0 / canvas.pitch.0 - 0.5);
            let (ca, cb) = ((ca.ceil() as i64).max(0), (cb.floor() as i64).min(cols - 1));
            out.extend((ca..=cb).map(|c| (c, r)));
        }
    }
    out
}

/// The pins inside every grated region, found once for its texture and
/// for its neighbours' ([`region_map`]).
struct Regions {
    /// Which region each pin's centre lies in: element index + 1 (the first
    /// in drawing order where regions overlap), 0 for none.
    map: Vec<u32>,
    /// Each grated element's pins inside it ([`inside_pins`]), by index.
    inside: std::collections::HashMap<usize, Vec<PinPos>>,
}

/// [`Regions`] of the visible grated paths of `drawing`.
fn region_map(canvas: &Canvas, drawing: &Drawing) -> Regions {
    let mut map = vec![0u32; canvas.owner.len()];
    let mut inside = std::collections::HashMap::new();
    for (i, e) in drawing.elements.iter().enumerate().filter(|(_, e)| e.visible) {
        let Shape::Path(p) = &e.shape else { continue };
        if !e.styles.iter().any(|s| matches!(s, Style::Grating(_))) {
            continue;
        }
        let pins = inside_pins(canvas, &p.outline, p.fill_rule);
        for &q in &pins {
            if let Some(slot) = canvas.index(q).and_then(|k| map.get_mut(k))
                && *slot == 0
            {
                *slot = i as u32 + 1;
            }
        }
        inside.insert(i, pins);
    }
    Regions { map, inside }
}

/// How a region is textured.
struct Fill<'r> {
    pattern: Pattern,
    height: u8,
    /// Whether the element also draws its outline (`vibrate` or `dots`).
    outlined: bool,
    /// Every grated region's pins ([`region_map`]), this one's among them.
    regions: &'r Regions,
}

fn texture_fill(
    canvas: &mut Canvas,
    polys: &[Polyline],
    fill: Fill,
    elem: usize,
    e: &Element,
    diags: &mut Vec<Diagnostic>,
) {
    let Fill { pattern, height, outlined, regions } = fill;
    // One blank pin between the texture and the region's own outline, so that
    // the outline is felt as a line and not as the texture's first ridge.
    // Without an outline the texture fills the region (its gap to other
    // elements is the design rule T0703).
    let border: std::collections::HashSet<PinPos> =
        if outlined { outline_pins(canvas, polys).into_iter().collect() } else { Default::default() };
    let near_border = |p: PinPos| (-1..=1).any(|dr| (-1..=1).any(|dc| border.contains(&(p.0 + dc, p.1 + dr))));
    let inside = regions.inside.get(&elem).map_or(&[][..], Vec::as_slice);
    let room: Vec<PinPos> = inside.iter().copied().filter(|&p| !near_border(p)).collect();
    let ridges: Vec<PinPos> = room.iter().copied().filter(|p| pattern.raised(p.0, p.1)).collect();
    // A texture is felt as one only with two ridges or more: a region that
    // holds one (a bar of a chart two pins wide) would read as a line, like
    // an outline, or as nothing. It is filled solid instead, when no other
    // grated region comes within a pin of it: regions that touch (the
    // provinces of a map shrunk onto the display) would merge into one
    // solid mass, where their ridges at least differ. (Two ridges stay a
    // texture: a key's swatch a few pins square shows its orientation with
    // two.)
    // Ridges held: 0, 1, or 2 for two or more.
    let lines =
        ridges.first().map_or(0, |&f| 1 + ridges.iter().any(|&p| pattern.ridge(p) != pattern.ridge(f)) as usize);
    let me = elem as u32 + 1;
    let other = |q: PinPos| canvas.index(q).and_then(|k| regions.map.get(k)).is_some_and(|&a| a != 0 && a != me);
    let alone = || room.iter().all(|&(c, r)| !(-1..=1).any(|dr| (-1..=1).any(|dc| other((c + dc, r + dr)))));
    let solid = !room.is_empty() && lines < 2 && alone();
    for &p in if solid { &room } else { &ridges } {
        canvas.raise(p, elem, height, false);
    }
    let (room, raised, period) = (room.len(), ridges.len(), pattern.period);
    let warning = if solid {
        format!(
            "the region is too narrow for its texture on pins ({room} pins inside it would carry {} every \
             {period} pins, felt as a line, not as a texture): it is filled solid",
            if lines == 0 { "no ridge" } else { "one ridge" }
        )
    } else if raised == 0 || room < 2 * period as usize * period as usize {
        format!(
            "the region is too small for its texture on pins: {room} pins inside it, {raised} of them ridges every {period} pins"
        )
    } else {
        return;
    };
    diags.push(
        Diagnostic::warning("T0707", warning)
            .with_element(e.name.clone())
            .with_help("make the region larger, or give it an outline or dots instead")
            .on_line(e.line),
    );
}

/// Side of a pin cluster for a dot of `radius_mm`: its diameter in pins, 2 to 4.
fn cluster_side(radius_mm: f64, pitch: f64) -> i64 {
    let s = (2.0 * radius_mm / pitch).round();
    if s.is_finite() { (s as i64).clamp(2, 4) } else { 2 }
}

fn cluster(canvas: &mut Canvas, centre_mm: (f64, f64), radius_mm: f64, elem: usize, height: u8) {
    let side = cluster_side(radius_mm, canvas.pitch.0.max(canvas.pitch.1));
    let (cx, cy) = canvas.to_pins(centre_mm);
    if !(cx.is_finite() && cy.is_finite()) {
        return;
    }
    // The block's top-left pin, so that the block is centred on the point.
    let half = (side - 1) as f64 / 2.0;
    let (c0, r0) = ((cx - half).round().clamp(-1e12, 1e12) as i64, (cy - half).round().clamp(-1e12, 1e12) as i64);
    for r in r0..r0 + side {
        for c in c0..c0 + side {
            canvas.raise((c, r), elem, height, false);
        }
    }
}

fn dotted(canvas: &mut Canvas, polys: &[Polyline], radius_mm: f64, spacing: Option<f64>, elem: usize, height: u8) {
    let pitch = canvas.pitch.0.max(canvas.pitch.1);
    let side = cluster_side(radius_mm, pitch);
    // At least two blank pins between clusters, so they are felt as dots.
    let step = spacing.unwrap_or(3.0 * radius_mm).max((side + 2) as f64 * pitch);
    for pl in polys {
        let len = pl.length();
        if !(len.is_finite() && len > 0.0) {
            continue;
        }
        let n = ((len / step).floor() as usize).min(100_000);
        // A closed path's last position would land on its first.
        let end = if pl.closed { len - step / 2.0 } else { len };
        let positions: Vec<f64> = (0..=n).map(|k| k as f64 * step).filter(|s| *s <= end).collect();
        for c in crate::geometry::points_at(pl, &positions) {
            cluster(canvas, c, radius_mm, elem, height);
        }
    }
}

#[cfg(test)]
mod tests;
