//! What the studio does with a file: the CLI's pipeline, whole. A drawing
//! or mesh is compiled through [`crate::compile::compile_bytes`], its
//! diagnostics grouped as `taxel build` prints them ([`crate::account`]),
//! its bundle stamped with the content hash `taxel build` gives it (so the
//! download is byte for byte the CLI's bundle), and drawn as `taxel preview`
//! draws it; a bundle is read as `taxel inspect` reads it.

use std::path::{Path, PathBuf};

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
    /// The felt preview (PNG).
    pub preview_png: Option<Vec<u8>>,
    /// The drawing rasterised (PNG): drawings are never shown as SVG.
    pub drawing_png: Option<Vec<u8>>,
    /// What the page is told (ids and URLs are added by the caller).
    pub summary: Value,
}

/// Builds `bytes`, a file named `name` at `path` (a path inside the opened
/// folder, or in an empty folder for an upload: a glTF's buffers are read
/// beside it), with `opts`. An input problem is in the summary's
/// diagnostics; `Err` is a failure of the machine (a font folder, say).
pub fn build(name: &str, path: &Path, bytes: Vec<u8>, opts: &CompileOpts) -> anyhow::Result<Built> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).unwrap_or_default();
    let mut built = Built {
        name: name.to_string(),
        svg_text: None,
        opened: None,
        opts: opts.clone(),
        bundle: None,
        bundle_bytes: None,
        preview_png: None,
        drawing_png: None,
        summary: Value::Null,
    };
    if !matches!(ext.as_str(), "svg" | "svgz" | "gltf" | "glb") {
        return Ok(open_bundle(built, &bytes));
    }
    let part = Partial::begin(path, &bytes);
    let text = matches!(ext.as_str(), "svg" | "svgz").then(|| crate::io::drawing_text(path, bytes.clone()).ok());
    let compiled = compile_bytes(path, bytes, opts)?;
    let diags = &compiled.diagnostics;
    let errors = diags.iter().filter(|d| d.severity == Severity::Error).count();
    // As `taxel build`: a bundle only when there is no error, stamped with its content hash.
    if let Some(mut bundle) = compiled.bundle.clone().filter(|_| errors == 0) {
        bundle.manifest.content_hash = part.finish(&compiled.fonts_used, opts)?;
        built.bundle_bytes = Some(
            bundle
                .to_bytes()
                .map_err(|e| anyhow::anyhow!("internal error: the compiler made an invalid bundle: {e}"))?,
        );
        built.bundle = Some(bundle);
    }
    let options = compile_options(opts)?.ok();
    match (text.flatten(), options) {
        (Some(text), Some(options)) => {
            built.drawing_png = preview::drawing_picture(&text, &options).map(|p| png(&p)).transpose()?;
            if let Some(b) = &built.bundle {
                built.preview_png = Some(png(&preview::preview_compiled(&text, &options, b))?);
            }
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
