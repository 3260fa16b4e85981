//! What the studio does with a file: the CLI's pipeline, whole. A drawing
//! or mesh is compiled through [`crate::compile::compile_bytes`], its
//! diagnostics grouped as `taxel build` prints them ([`crate::account`]),
//! its bundle stamped with the content hash `taxel build` gives it (so the
//! download is byte for byte the CLI's bundle), and drawn as `taxel preview`
//! draws it; a bundle is read as `taxel inspect` reads it.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde_json::{Value, json};
use taxel_compiler::{Severity, preview};
use taxel_format::{Bundle, Family};

use crate::batch::hash::Partial;
use crate::cli::{CompileOpts, ExportFormat};
use crate::compile::{compile_bytes, compile_options};

/// Most element ids a diagnostic group hands to the page for highlighting.
const MAX_GROUP_ELEMENTS: usize = 500;

/// One compiled (or opened) file, kept while the page may ask for its parts.
pub struct Built {
    /// The file's name, as shown and as downloads are named.
    pub name: String,
    /// The drawing's text, for a style change (drawings only).
    pub svg_text: Option<String>,
    /// Where it was opened from in the folder, for saving a styled copy beside it.
    pub opened: Option<PathBuf>,
    /// The options it was compiled with.
    pub opts: CompileOpts,
    /// The bundle, when there is one.
    pub bundle: Option<Bundle>,
    /// Its bytes, as `taxel build` writes them.
    pub bundle_bytes: Option<Vec<u8>>,
    /// The key's own bundles, a page each, as `taxel build` writes them
    /// beside the bundle (`NAME.key.taxel`, `NAME.key2.taxel` ...,
    /// laterotactile and grid profiles); empty when the drawing needs no key.
    pub key_bytes: Vec<Vec<u8>>,
    /// The felt preview (PNG).
    pub preview_png: Option<Vec<u8>>,
    /// The drawing rasterised (PNG): drawings are never shown as SVG.
    pub drawing_png: Option<Vec<u8>>,
    /// The same picture as the felt preview's backdrop.
    pub backdrop: Option<Arc<preview::Backdrop>>,
    /// What the page is told (ids and URLs are added by the caller).
    pub summary: Value,
    /// The teacher's style sheet this build used, when the page made one
    /// (a change of style by fill colour).
    pub sheet: Option<Sheet>,
    /// Whether the drawing is a changed copy (a style changed by element).
    pub changed: bool,
    /// Whether the automatic style sheet styled the drawing (unannotated, no
    /// `--style`, or `--style auto`): a teacher's sheet then starts from its decisions.
    pub auto_styled: bool,
    /// The drawing's fill colours, found when the page first asks.
    pub fills: std::sync::OnceLock<Value>,
}

/// A teacher's style sheet: the sheet a change starts from (the command
/// line's `--style` file, or the automatic sheet as decided for the
/// drawing, or nothing) and, after it, one rule per fill colour changed in
/// the page, in the order first changed (a colour changed again keeps its
/// place and takes the new style).
#[derive(Debug, Clone, Default)]
pub struct Sheet {
    /// The TOML the page's rules follow.
    pub base: String,
    /// `(#rrggbb, style)` per colour.
    pub rules: Vec<(String, String)>,
    /// Whether the base is the automatic sheet as decided for the drawing.
    pub from_auto: bool,
}

impl Sheet {
    /// The sheet as TOML: its base, then the page's rules. Among rules as
    /// specific as a fill rule the later wins, so these override the base's
    /// rule for the same colour; an id, class or layer rule of the base
    /// stays more specific than any of them.
    pub fn text(&self) -> String {
        let mut out = self.base.clone();
        if !out.is_empty() && !out.ends_with('\n') {
            out.push('\n');
        }
        for (fill, style) in &self.rules {
            let style = toml::Value::String(style.clone());
            out.push_str(&format!(
                "\n# Changed in taxel studio: every element filled with {fill}\n[[rule]]\nfill = \"{fill}\"\ntactile = {style}\n"
            ));
        }
        out
    }
}

/// Builds `bytes`, a file named `name` at `path` (a path inside the opened
/// folder, or in an empty folder for an upload: a glTF's buffers are read
/// beside it), with `opts`. An input problem is in the summary's
/// diagnostics; `Err` is a failure of the machine (a font folder, say).
///
/// `looks` is the drawing's picture (PNG) and backdrop when the caller
/// knows the drawing looks as before (a style change: a `data-tactile`
/// attribute or a style sheet changes what is felt, never what is seen),
/// so that a rebuild does not draw it again.
pub fn build(
    name: &str,
    path: &Path,
    bytes: Vec<u8>,
    opts: &CompileOpts,
    looks: Option<Looks>,
) -> anyhow::Result<Built> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).unwrap_or_default();
    let mut built = Built {
        name: name.to_string(),
        svg_text: None,
        opened: None,
        opts: opts.clone(),
        bundle: None,
        bundle_bytes: None,
        key_bytes: Vec::new(),
        preview_png: None,
        drawing_png: None,
        backdrop: None,
        summary: Value::Null,
        sheet: None,
        changed: false,
        auto_styled: opts.style_is_auto(),
        fills: std::sync::OnceLock::new(),
    };
    if !matches!(ext.as_str(), "svg" | "svgz" | "gltf" | "glb") {
        return Ok(open_bundle(built, &bytes));
    }
    let part = Partial::begin(path, &bytes);
    let text = matches!(ext.as_str(), "svg" | "svgz").then(|| crate::io::drawing_text(path, bytes.clone()).ok());
    let compiled = compile_bytes(path, bytes, opts)?;
    let diags = &compiled.diagnostics;
    // T0320: nothing was annotated, so the automatic sheet styled the drawing.
    built.auto_styled |= diags.iter().any(|d| d.code == "T0320");
    let errors = diags.iter().filter(|d| d.severity == Severity::Error).count();
    // As `taxel build`: a bundle only when there is no error, stamped with its content hash.
    if let Some(mut bundle) = compiled.bundle.clone().filter(|_| errors == 0) {
        bundle.manifest.content_hash = part.finish(&compiled.fonts_used, opts)?;
        for mut key in compiled.key.iter().cloned() {
            key.manifest.content_hash = bundle.manifest.content_hash;
            built.key_bytes.push(
                key.to_stored_bytes()
                    .map_err(|e| anyhow::anyhow!("internal error: the compiler made an invalid key bundle: {e}"))?,
            );
        }
        built.bundle_bytes = Some(
            bundle
                .to_stored_bytes()
                .map_err(|e| anyhow::anyhow!("internal error: the compiler made an invalid bundle: {e}"))?,
        );
        built.bundle = Some(bundle);
    }
    let options = compile_options(opts)?.ok();
    match (text.flatten(), options) {
        (Some(text), Some(options)) => {
            // The drawing is drawn once, for its picture and as the felt
            // preview's backdrop (`preview::preview_compiled` would draw it
            // again, and on a large map drawing is half a rebuild's time).
            let (picture, backdrop) = match looks {
                Some(l) => l,
                None => match preview::drawing_picture(&text, &options) {
                    Some(p) => (Some(png(&p)?), backdrop_of(&p).map(Arc::new)),
                    None => (None, None),
                },
            };
            if let Some(b) = &built.bundle {
                built.preview_png = Some(png(&preview::render_bundle(b, backdrop.as_deref()))?);
            }
            (built.drawing_png, built.backdrop) = (picture, backdrop);
            built.svg_text = Some(text);
        }
        _ => {
            if let Some(b) = &built.bundle {
                built.preview_png = Some(png(&preview::render_bundle(b, None))?);
            }
        }
    }
    let groups: Vec<Value> = crate::account::groups(diags, name, Severity::Note)
        .iter()
        .map(|g| {
            let mut elements: Vec<&str> = Vec::new();
            for d in &g.members {
                if let Some(e) = d.element.as_deref()
                    && !elements.contains(&e)
                    && elements.len() < MAX_GROUP_ELEMENTS
                {
                    elements.push(e);
                }
            }
            json!({
                "severity": g.severity.to_string(),
                "code": g.code,
                "count": g.members.len(),
                "lines": g.lines,
                "elements": elements,
            })
        })
        .collect();
    let count = |s: Severity| diags.iter().filter(|d| d.severity == s).count();
    built.summary = json!({
        "name": name,
        "kind": if built.svg_text.is_some() { "drawing" } else { "mesh" },
        "errors": errors,
        "warnings": count(Severity::Warning),
        "notes": count(Severity::Note),
        "styles": crate::account::style_summary(diags),
        "groups": groups,
    });
    describe(&mut built);
    Ok(built)
}

/// A bundle opened as it is: validated as `taxel inspect` validates it.
fn open_bundle(mut built: Built, bytes: &[u8]) -> Built {
    let (groups, errors) = match Bundle::from_bytes(bytes) {
        Ok(b) => {
            built.preview_png = png(&preview::render_bundle(&b, None)).ok();
            built.bundle_bytes = Some(bytes.to_vec());
            built.bundle = Some(b);
            (Vec::new(), 0)
        }
        Err(e) => {
            let line = format!("{}: not a valid taxel bundle: {e}", built.name);
            (vec![json!({"severity": "error", "code": "bundle", "count": 1, "lines": [line], "elements": []})], 1)
        }
    };
    built.summary = json!({
        "name": built.name, "kind": "bundle", "errors": errors, "warnings": 0, "notes": 0,
        "styles": null, "groups": groups,
    });
    describe(&mut built);
    built
}

/// Adds what the page needs to show and play the bundle: its profile, the
/// preview's placement on the page, and which exports it has.
fn describe(built: &mut Built) {
    let Value::Object(s) = &mut built.summary else { return };
    let Some(b) = &built.bundle else {
        s.insert("bundle".into(), Value::Null);
        return;
    };
    let p = &b.manifest.profile;
    s.insert(
        "bundle".into(),
        json!({
            "bytes": built.bundle_bytes.as_ref().map_or(0, Vec::len),
            "profile": p.name.as_str(),
            "family": p.family().name(),
            "surface_mm": [p.surface_w_mm, p.surface_h_mm],
            "exports": if p.family() == Family::Pins { vec!["dtms", "graphiti", "unicode"] } else { vec![] },
            // The key's pages, each a bundle: `key`, `key2` ... (0: no key).
            "key": built.key_bytes.len(),
        }),
    );
    s.insert(
        "preview_frame".into(),
        preview::bundle_frame(b).map_or(Value::Null, |(x0, y0, k)| json!({"x0_mm": x0, "y0_mm": y0, "px_per_mm": k})),
    );
    s.insert("drawing_px_per_mm".into(), json!(preview::PREVIEW_PX_PER_MM));
}

/// The bundle as a pin display's own file, as `taxel export` writes it.
pub fn export(built: &Built, format: ExportFormat) -> anyhow::Result<(String, Vec<u8>)> {
    let b = built.bundle.as_ref().ok_or_else(|| anyhow::anyhow!("{}: no bundle (the input has errors)", built.name))?;
    let stem = Path::new(&built.name).file_stem().and_then(|s| s.to_str()).unwrap_or("drawing").to_string();
    let file = match format {
        ExportFormat::Dtms => format!("{stem}.dtms"),
        ExportFormat::Graphiti => format!("{stem}.graphiti"),
        ExportFormat::Unicode => format!("{stem}.txt"),
    };
    let data = crate::cmd::export::data(b, format, &file).map_err(|e| anyhow::anyhow!("{}: {e}", built.name))?;
    Ok((file, data))
}

/// The footprint outlines of the elements whose ids are `ids`, in page mm:
/// one entry per element, each a list of rings of `[x, y]` points (lines
/// and dots also carry their half width), for the page to outline them.
pub fn outlines(built: &Built, ids: &[&str]) -> Value {
    let Some(b) = &built.bundle else { return json!([]) };
    let (Some(fp), Some(prov)) = (b.footprints(), b.provenance()) else { return json!([]) };
    let mut out = Vec::new();
    for shape in &fp.shapes {
        let Some(entry) = prov.entries.get(shape.source as usize) else { continue };
        if entry.id.is_empty() || !ids.contains(&entry.id.as_str()) {
            continue;
        }
        let rings: Vec<Vec<[f32; 2]>> = shape
            .rings
            .iter()
            .map(|r| {
                r.iter()
                    .map(|&q| {
                        let (x, y) = fp.position(q);
                        [x, y]
                    })
                    .collect()
            })
            .collect();
        out.push(json!({
            "id": entry.id,
            "area": shape.kind.is_area(),
            "half_width_mm": shape.half_width as f32 * fp.quantum_mm,
            "rings": rings,
        }));
    }
    Value::Array(out)
}

/// A drawing's picture and backdrop, kept by a style change.
pub type Looks = (Option<Vec<u8>>, Option<Arc<preview::Backdrop>>);

/// The drawing's picture as the preview's backdrop: its pixels premultiplied
/// again (the picture holds them demultiplied; premultiplying gives back the
/// pixmap `preview::preview_compiled` draws, whose every pixel is `c · a / 255`
/// rounded, so demultiplying and premultiplying again lands on it).
fn backdrop_of(p: &preview::Picture) -> Option<preview::Backdrop> {
    let mut pixmap = tiny_skia::Pixmap::new(p.width, p.height)?;
    for (px, c) in pixmap.pixels_mut().iter_mut().zip(p.rgba.chunks_exact(4)) {
        *px = tiny_skia::ColorU8::from_rgba(c[0], c[1], c[2], c[3]).premultiply();
    }
    Some(preview::Backdrop { pixmap })
}

fn png(p: &preview::Picture) -> anyhow::Result<Vec<u8>> {
    crate::io::png::encode_picture(p)
}

/// The drawing's text with `data-tactile="STYLE"` on the element whose id
/// is `element` (replacing the attribute it had): the copy a style change
/// makes. The original file is not touched; the compiler judges the style.
pub fn restyle(built: &Built, element: &str, style: &str) -> Result<String, String> {
    let text = built.svg_text.as_deref().ok_or("only a drawing's styles can be changed")?;
    let opts = roxmltree::ParsingOptions { allow_dtd: true, ..roxmltree::ParsingOptions::default() };
    let doc = roxmltree::Document::parse_with_options(text, opts).map_err(|e| format!("{}: {e}", built.name))?;
    let node = doc
        .descendants()
        .find(|n| n.is_element() && n.attribute("id") == Some(element))
        .ok_or_else(|| format!("{}: no element has the id '{element}'", built.name))?;
    let value: String = style
        .chars()
        .map(|c| match c {
            '&' => "&amp;".to_string(),
            '<' => "&lt;".to_string(),
            '"' => "&quot;".to_string(),
            c => c.to_string(),
        })
        .collect();
    let mut out = String::with_capacity(text.len() + value.len() + 16);
    match node.attributes().find(|a| a.name() == "data-tactile" && a.namespace().is_none()) {
        Some(a) => {
            let r = a.range_value();
            out.push_str(&text[..r.start]);
            out.push_str(&value);
            out.push_str(&text[r.end..]);
        }
        None => {
            // Right after the tag's name: `<path` + ` data-tactile="…"`.
            let start = node.range().start;
            let name_len = text[start + 1..].find(|c: char| c.is_whitespace() || c == '/' || c == '>').unwrap_or(0);
            let at = start + 1 + name_len;
            out.push_str(&text[..at]);
            out.push_str(&format!(" data-tactile=\"{value}\""));
            out.push_str(&text[at..]);
        }
    }
    Ok(out)
}

/// The drawing's fill colours (plain colours only, as a style sheet's
/// `fill` selects them), most used first: `[{"fill": "#rrggbb", "count": N}]`.
pub fn fills(built: &Built) -> Value {
    built
        .fills
        .get_or_init(|| {
            let (Some(text), Ok(Ok(options))) = (&built.svg_text, compile_options(&built.opts)) else {
                return json!([]);
            };
            let Some(d) = taxel_compiler::drawing::resolve(text, &options).drawing else { return json!([]) };
            let mut counts: Vec<(String, usize)> = Vec::new();
            for e in &d.elements {
                let Some([r, g, b, _]) = e.paint.fill else { continue };
                let hex = format!("#{r:02x}{g:02x}{b:02x}");
                match counts.iter_mut().find(|(h, _)| *h == hex) {
                    Some((_, n)) => *n += 1,
                    None => counts.push((hex, 1)),
                }
            }
            // Most used first; colours used alike in the order met.
            counts.sort_by_key(|c| std::cmp::Reverse(c.1));
            Value::Array(counts.into_iter().map(|(fill, count)| json!({"fill": fill, "count": count})).collect())
        })
        .clone()
}

/// The teacher's sheet after giving every element filled with `fill`
/// (`#rrggbb`) the style `style`: the build's sheet, or a new one started
/// from [`base_sheet`], with that colour's rule set. The sheet is parsed
/// as the compiler will parse it, so a bad style is refused here with the
/// style sheet reader's message.
pub fn sheet_with(built: &Built, fill: &str, style: &str) -> Result<Sheet, String> {
    let text = built.svg_text.as_deref().ok_or("only a drawing's styles can be changed")?;
    let hex = fill.strip_prefix('#').filter(|h| h.len() == 6 && h.bytes().all(|b| b.is_ascii_hexdigit()));
    let Some(hex) = hex else { return Err(format!("'{fill}' is not a fill colour: #rrggbb")) };
    let fill = format!("#{}", hex.to_ascii_lowercase());
    let mut sheet = match &built.sheet {
        Some(s) => s.clone(),
        None => {
            let (base, from_auto) = base_sheet(built, text)?;
            Sheet { base, rules: Vec::new(), from_auto }
        }
    };
    match sheet.rules.iter_mut().find(|(f, _)| *f == fill) {
        Some(rule) => rule.1 = style.to_string(),
        None => sheet.rules.push((fill, style.to_string())),
    }
    taxel_compiler::StyleSheet::parse(&sheet.text(), &sheet_name(built)).map_err(|e| e.to_string())?;
    Ok(sheet)
}

/// A teacher's sheet of no rule yet, on the sheet [`base_sheet`] gives.
pub fn auto_sheet(built: &Built) -> Result<Sheet, String> {
    let text = built.svg_text.as_deref().ok_or("only a drawing's styles can be changed")?;
    let (base, from_auto) = base_sheet(built, text)?;
    Ok(Sheet { base, rules: Vec::new(), from_auto })
}

/// The file name a teacher's sheet is downloaded and saved under.
pub fn sheet_name(built: &Built) -> String {
    let stem = Path::new(&built.name).file_stem().and_then(|s| s.to_str()).unwrap_or("drawing");
    format!("{}.tactile.toml", stem.strip_suffix(".tactile").unwrap_or(stem))
}

/// What a teacher's first sheet starts from: the command line's `--style`
/// file as it is; for a drawing the automatic sheet styled, that sheet as
/// decided for this drawing (`taxel style auto INPUT`: a sheet replaces
/// the automatic one, so without its rules every other colour would lose
/// its texture); else an empty sheet. Also whether it is the automatic one.
fn base_sheet(built: &Built, text: &str) -> Result<(String, bool), String> {
    let opts = &built.opts;
    match &opts.style {
        Some(path) if !opts.style_is_auto() => {
            return crate::io::read_input_text(path).map(|t| (t, false)).map_err(|e| format!("{e:#}"));
        }
        _ if !built.auto_styled => {
            return Ok(("# The styles changed in taxel studio.\nversion = 1\n".to_string(), false));
        }
        _ => {}
    }
    let options = match compile_options(opts) {
        Ok(Ok(o)) => o,
        Ok(Err(d)) => return Err(d.message),
        Err(e) => return Err(format!("{e:#}")),
    };
    crate::cmd::style::decided(text, &options).map(|t| (t, true)).map_err(|diags| {
        let first = diags.iter().find(|d| d.severity == Severity::Error).map_or(String::new(), |d| d.message.clone());
        format!("{}: no style sheet can be made for this drawing: {first}", built.name)
    })
}
