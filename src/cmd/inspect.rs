//! `taxel inspect BUNDLE [--format human|json]`: what a bundle holds —
//! profile, surface, version, content hash, and each chunk with its kind,
//! parameters, provenance and size. With `--at X,Y`, the element under that
//! surface point instead (the footprints' point lookup, SPEC.md section 10.1).

use std::collections::BTreeSet;
use std::path::Path;

use serde_json::{Value, json};
use taxel_compiler::style::legend;
use taxel_format::lookup::PointLookup;
use taxel_format::{BundleView, ChunkView, FamilyParams, MaskKind, ProvenanceView, TileGroup};

use crate::cli::Format;
use crate::error::{CliError, CmdResult};
use crate::io::read_bundle;
use crate::io::stdout::{self, outln};

pub fn run(path: &Path, format: Format, at: Option<(f64, f64)>) -> CmdResult {
    let bytes = read_bundle(path)?;
    let view = BundleView::parse(&bytes).map_err(|e| CliError::input(anyhow::anyhow!("{}: {e}", path.display())))?;
    let mut report = describe(&view);
    // The file's own length: a stored bundle (SPEC.md 15) is smaller than its plain bundle.
    report["file_bytes"] = json!(std::fs::metadata(path).map_or(bytes.len() as u64, |m| m.len()));
    if let Some(point) = at {
        let found = under(path, &view, &report, point)?;
        return match format {
            Format::Json => outln!("{}", serde_json::to_string_pretty(&found).map_err(anyhow::Error::new)?),
            Format::Human => stdout::print(&human_under(&found)),
        };
    }
    match format {
        Format::Json => outln!("{}", serde_json::to_string_pretty(&report).map_err(anyhow::Error::new)?),
        Format::Human => stdout::print(&human(path, &report)),
    }
}

/// What lies under `(x, y)`: the topmost element, with the chunks (layers) that hold it.
fn under(path: &Path, view: &BundleView<'_>, report: &Value, (x, y): (f64, f64)) -> Result<Value, CliError> {
    let lookup = PointLookup::new(view, PointLookup::DEFAULT_TOLERANCE_MM).ok_or_else(|| {
        CliError::input(anyhow::anyhow!(
            "{}: this bundle has no footprints (chunk FOOT, format 2.1), so it cannot say what lies under a point; \
             rebuild it from its drawing with `taxel build`",
            path.display()
        ))
    })?;
    let Some(hit) = lookup.under(x, y) else {
        return Ok(json!({ "at_mm": [x, y], "element": null }));
    };
    let layers: Vec<Value> = report["chunks"]
        .as_array()
        .into_iter()
        .flatten()
        .filter(|c| {
            c["sources"].as_array().is_some_and(|s| s.iter().any(|e| e["index"].as_u64() == Some(hit.source as u64)))
        })
        .map(|c| json!({ "index": c["index"], "tag": c["tag"], "kind": c["kind"] }))
        .collect();
    let (id, label, line) = hit.entry.map_or(("", "", 0), |e| (e.id.as_str(), e.label.as_str(), e.line));
    Ok(json!({
        "at_mm": [x, y],
        "element": { "name": hit.name(), "index": hit.source, "id": id, "label": label, "line": line, "layers": layers },
    }))
}

fn human_under(r: &Value) -> String {
    let at = pair(&r["at_mm"], ", ");
    let e = &r["element"];
    if e.is_null() {
        return format!("({at}) mm: nothing\n");
    }
    let mut out = format!("({at}) mm: {}\n", e["name"].as_str().unwrap_or(""));
    if let Some(id) = e["id"].as_str().filter(|id| !id.is_empty()) {
        out += &format!("  id      {id}\n");
    }
    if let Some(line) = e["line"].as_u64().filter(|&l| l > 0) {
        out += &format!("  line    {line}\n");
    }
    for l in e["layers"].as_array().into_iter().flatten() {
        out += &format!(
            "  layer   #{} {} ({})\n",
            l["index"],
            l["tag"].as_str().unwrap_or("?"),
            l["kind"].as_str().unwrap_or("?")
        );
    }
    out
}

/// The names of provenance entries `sources`, as `id "label"`.
fn names(prov: Option<&ProvenanceView<'_>>, sources: &BTreeSet<u32>) -> Vec<Value> {
    sources
        .iter()
        .map(|&s| match prov.and_then(|p| p.get(s)) {
            Some((id, label, line)) => json!({ "index": s, "id": id, "label": label, "line": line }),
            None => json!({ "index": s }),
        })
        .collect()
}

/// The whole report as JSON; the human form is printed from it.
fn describe(view: &BundleView<'_>) -> Value {
    let m = view.manifest();
    let p = &m.profile;
    let (major, minor) = view.version();
    let family = match p.params {
        FamilyParams::Laterotactile => json!({}),
        FamilyParams::Grid(g) => json!({
            "carrier_min_hz": g.carrier_min_hz, "carrier_max_hz": g.carrier_max_hz,
            "audio_rate_hz": g.audio_rate_hz, "ramp_ms": g.ramp_ms,
        }),
        FamilyParams::Finger(f) => json!({
            "rhythm_max": f.rhythm_max, "intensity_max": f.intensity_max, "flat_slope": f.flat_slope,
            "direction_window": f.direction_window, "min_move_mm": f.min_move_mm,
        }),
        FamilyParams::Pins(q) => json!({
            "height_levels": q.height_levels, "blink_step_ms": q.blink_step_ms, "cell_rows": q.cell_rows,
            "cell_gap_cols": q.cell_gap_cols, "line_gap_rows": q.line_gap_rows, "text_cells": q.text_cells,
            "refresh_ms": q.refresh_ms,
        }),
        // No bundle holds a print profile; kept for completeness.
        FamilyParams::Print(q) => json!({ "medium": q.medium.name() }),
    };
    let prov = view.provenance();
    let mut chunks = Vec::new();
    if let Some((tag, required, _, length)) = view.chunk_entry(0) {
        chunks.push(
            json!({ "index": 0, "tag": tag.to_string(), "required": required, "bytes": length, "kind": "manifest" }),
        );
    }
    for (i, c) in view.chunks().enumerate() {
        let index = i as u32 + 1;
        let Some((tag, required, _, length)) = view.chunk_entry(index) else { continue };
        let mut sources = BTreeSet::new();
        let mut entry = match c {
            ChunkView::Mask(mk) => {
                sources.extend(mk.source);
                let mut e = json!({
                    "kind": match mk.kind { MaskKind::Vibration { .. } => "vibration", MaskKind::Grating { .. } => "grating" },
                    "width": mk.width, "height": mk.height, "bits": mk.bits, "px_per_mm": mk.px_per_mm,
                    "origin_mm": [mk.origin_x.0, mk.origin_y.0],
                    "size_mm": [mk.width as f32 / mk.px_per_mm, mk.height as f32 / mk.px_per_mm],
                    "amplitude": mk.amplitude,
                });
                match mk.kind {
                    MaskKind::Vibration { freq } => e["freq_hz"] = json!(freq.hz()),
                    MaskKind::Grating { wavelength, angle_deg } => {
                        e["wavelength_mm"] = json!(wavelength.0);
                        e["angle_deg"] = json!(angle_deg);
                    }
                }
                e
            }
            ChunkView::Distance(dv) => {
                sources.extend((0..dv.source_count()).filter_map(|i| dv.source(i)));
                let span = 8.0 * dv.pitch_mm;
                // Counted by what plays them (`TileKind::group`): stored and
                // fine tiles, plane and ridge tiles (one record), corner and
                // notch tiles (two planes), and bend, arc and segments tiles as bends.
                let (mut planar, mut bent, mut bends, mut stored, mut fine) = (0u32, 0u32, 0u32, 0u32, 0u32);
                for tile in dv.each_tile() {
                    match tile.kind().group() {
                        TileGroup::Stored => stored += 1,
                        TileGroup::Fine => fine += 1,
                        TileGroup::Plane => planar += 1,
                        TileGroup::Corner => bent += 1,
                        TileGroup::Bend => bends += 1,
                        TileGroup::Constant => {}
                    }
                }
                let mut e = json!({
                    "kind": match dv.kind { MaskKind::Vibration { .. } => "vibration-field", MaskKind::Grating { .. } => "grating-field" },
                    "tiles": [dv.tile_cols, dv.tile_rows], "stored_tiles": stored, "fine_tiles": fine, "plane_tiles": planar,
                    "corner_tiles": bent, "bend_tiles": bends, "pitch_mm": dv.pitch_mm,
                    "step_mm": dv.step_mm, "soft_mm": dv.soft_mm,
                    "origin_mm": [dv.origin_x.0, dv.origin_y.0],
                    "size_mm": [dv.tile_cols as f32 * span, dv.tile_rows as f32 * span],
                    "amplitude": dv.amplitude, "elements": dv.source_count(),
                });
                match dv.kind {
                    MaskKind::Vibration { freq } => e["freq_hz"] = json!(freq.hz()),
                    MaskKind::Grating { wavelength, angle_deg } => {
                        e["wavelength_mm"] = json!(wavelength.0);
                        e["angle_deg"] = json!(angle_deg);
                    }
                }
                e
            }
            ChunkView::Dots(d) => {
                let (mut rmin, mut rmax) = (f32::INFINITY, 0.0f32);
                for k in 0..d.len() {
                    if let Some(dot) = d.dot(k) {
                        rmin = rmin.min(dot.radius.0);
                        rmax = rmax.max(dot.radius.0);
                        sources.extend(dot.source);
                    }
                }
                json!({ "kind": "dots", "dot_kind": d.kind.name(), "dots": d.len(),
                        "radius_mm": if d.is_empty() { json!(null) } else { json!([rmin, rmax]) } })
            }
            ChunkView::Strokes(s) => {
                let (mut first, mut last, mut drives) = (u64::MAX, 0u64, 0u64);
                for k in 0..s.stroke_count() {
                    if let Some((stroke, points)) = s.stroke(k) {
                        first = first.min(stroke.start.0);
                        last = last.max(stroke.start.0 + stroke.duration as u64);
                        sources.extend(stroke.source);
                        for pk in points {
                            drives += s.point_timing(pk).map_or(0, |(_, _, d)| d.len() as u64);
                        }
                    }
                }
                json!({ "kind": "strokes", "strokes": s.stroke_count(), "points": s.point_count(), "drives": drives,
                        "ticks": if s.stroke_count() == 0 { json!(null) } else { json!([first, last]) } })
            }
            ChunkView::Height(h) => {
                sources.extend(h.source);
                json!({ "kind": "height", "cols": h.cols, "rows": h.rows, "cell_mm": h.cell.0,
                        "origin_mm": [h.origin_x.0, h.origin_y.0],
                        "height_mm": [h.height_min, h.height_max], "max_gradient": h.max_gradient,
                        "gradient_cap": h.gradient_cap })
            }
            ChunkView::Pins(v) => {
                let (mut raised, mut blinking) = (0u64, 0u64);
                for r in 0..v.rows() {
                    for &b in v.row(r) {
                        let pin = taxel_format::Pin::from_byte(b);
                        raised += pin.raised() as u64;
                        blinking += pin.blinks() as u64;
                    }
                }
                json!({ "kind": "pins", "cols": v.cols(), "rows": v.rows(), "raised": raised, "blinking": blinking,
                        "blink_ms": v.blink_ms(), "navigation": v.navigation().name(), "text_cells": v.text().len() })
            }
            ChunkView::Provenance(p) => json!({ "kind": "provenance", "entries": p.len() }),
            ChunkView::Footprints(f) => {
                let (mut rings, mut points) = (0u64, 0u64);
                for s in f.shapes() {
                    for r in s.rings() {
                        rings += 1;
                        points += r.len() as u64;
                    }
                }
                json!({ "kind": "footprints", "shapes": f.len(), "rings": rings, "points": points,
                        "quantum_mm": f.quantum_mm() })
            }
            ChunkView::Unknown { .. } => json!({ "kind": "unknown" }),
        };
        entry["index"] = json!(index);
        entry["tag"] = json!(tag.to_string());
        entry["required"] = json!(required);
        entry["bytes"] = json!(length);
        if !sources.is_empty() {
            entry["sources"] = json!(names(prov.as_ref(), &sources));
        }
        chunks.push(entry);
    }
    json!({
        "format_version": format!("{major}.{minor}"),
        "bytes": view.bytes().len(),
        "profile": {
            "name": p.name.as_str(), "family": p.family().name(), "rows": p.rows, "cols": p.cols,
            "pitch_mm": [p.pitch_x_mm, p.pitch_y_mm], "rate_hz": p.rate_hz, "output_bits": p.output_bits,
            "params": family,
        },
        "surface_mm": [p.surface_w_mm, p.surface_h_mm],
        "generator": m.generator.as_str(),
        "content_hash": m.content_hash.iter().map(|b| format!("{b:02x}")).collect::<String>(),
        "chunks": chunks,
        // The key of the labels written as key codes (provenance entry `key`: `key: co Count, fs Fruit sold`).
        "key": prov.as_ref().and_then(|p| (0..p.len()).filter_map(|i| p.get(i)).find(|e| e.0 == "key")).map(|e| e.1),
        // The key's textures, line styles and symbols with their meanings
        // (provenance entries `key.texture`, `key.line`, ...: SPEC.md 10.2).
        "key_entries": prov.as_ref().map_or(Vec::new(), |p| (0..p.len())
            .filter_map(|i| p.get(i))
            .filter_map(|e| legend::kind_of_id(e.0).map(|kind| json!({ "kind": kind, "meaning": e.1 })))
            .collect::<Vec<_>>()),
        // The texts the graphic has no room for, which the key lists (`key.text`).
        "key_text": prov.as_ref().and_then(|p| (0..p.len())
            .filter_map(|i| p.get(i))
            .find(|e| e.0 == legend::UNPLACED_ID)
            .map(|e| e.1)),
        // A page of a key longer than the surface (`[page, pages]`; SPEC.md 10.2).
        "key_page": prov.as_ref().and_then(|p| (0..p.len())
            .filter_map(|i| p.get(i))
            .filter(|e| e.0 == taxel_compiler::latero::key::PAGE_ID)
            .map(|(id, label, line)| taxel_format::ProvenanceEntry { id: id.into(), label: label.into(), line })
            .map(|e| taxel_compiler::latero::key::page_of(std::slice::from_ref(&e)))
            .find(|&(_, n)| n > 1)),
    })
}

fn num(v: &Value) -> String {
    match v.as_f64() {
        Some(f) if f.fract() == 0.0 && f.abs() < 1e15 => format!("{}", f as i64),
        Some(f) => format!("{}", (f * 1e4).round() / 1e4),
        None => v.to_string(),
    }
}

fn pair(v: &Value, sep: &str) -> String {
    format!("{}{sep}{}", num(&v[0]), num(&v[1]))
}

fn human(path: &Path, r: &Value) -> String {
    let p = &r["profile"];
    let mut out = format!(
        "{}: taxel bundle {}, {} bytes{}, {} chunks\nprofile    {} ({}), {} x {} actuators, pitch {} mm, {} Hz, {}-bit output\nsurface    {} mm\ngenerator  {}\ncontent    {}\n\n",
        path.display(),
        r["format_version"].as_str().unwrap_or("?"),
        r["bytes"],
        match r["file_bytes"].as_u64() {
            Some(file) if r["bytes"].as_u64() != Some(file) => format!(" ({file} in the compressed file)"),
            _ => String::new(),
        },
        r["chunks"].as_array().map_or(0, Vec::len),
        p["name"].as_str().unwrap_or("?"),
        p["family"].as_str().unwrap_or("?"),
        p["cols"],
        p["rows"],
        pair(&p["pitch_mm"], " x "),
        p["rate_hz"],
        p["output_bits"],
        pair(&r["surface_mm"], " x "),
        r["generator"].as_str().unwrap_or(""),
        r["content_hash"].as_str().unwrap_or(""),
    );
    // Before the chunks: the key, one entry a line, as a transcriber's key
    // page lists it: its textures, line styles and symbols, then its codes.
    let mut key: Vec<String> = r["key_entries"]
        .as_array()
        .into_iter()
        .flatten()
        .map(|e| format!("{}: {}", e["kind"].as_str().unwrap_or("?"), e["meaning"].as_str().unwrap_or("")))
        .collect();
    if let Some(codes) = r["key"].as_str() {
        key.extend(codes.strip_prefix("key: ").unwrap_or(codes).split(", ").map(String::from));
    }
    // A few to a line, then how many more, as the key prints them (all of
    // them are in the JSON): a map's thousands of labels on one line was no
    // screen's width.
    if let Some(texts) = r["key_text"].as_str() {
        key.extend(legend::unplaced_lines(&texts.split(", ").collect::<Vec<_>>()));
    }
    if !key.is_empty() {
        out.insert_str(out.len() - 1, &format!("key        {}\n", key.join("\n           ")));
    }
    if let Some([k, n]) = r["key_page"].as_array().and_then(|a| <&[Value; 2]>::try_from(a.as_slice()).ok()) {
        out.insert_str(
            out.len() - 1,
            &format!("key page   {k} of {n}: a page of the key of the bundle it is beside\n"),
        );
    }
    out += "     #  tag   flag         bytes  layer\n";
    for c in r["chunks"].as_array().into_iter().flatten() {
        let what = match c["kind"].as_str().unwrap_or("") {
            "manifest" => "manifest".to_string(),
            k @ ("vibration" | "grating") => {
                let prim = if k == "vibration" {
                    format!("vibration {} Hz", num(&c["freq_hz"]))
                } else {
                    format!("grating {} mm at {}°", num(&c["wavelength_mm"]), num(&c["angle_deg"]))
                };
                format!(
                    "{prim}, amplitude {}; mask {} x {} {}-bit at {} px/mm, {} mm from ({}) mm",
                    num(&c["amplitude"]),
                    c["width"],
                    c["height"],
                    c["bits"],
                    num(&c["px_per_mm"]),
                    pair(&c["size_mm"], " x "),
                    pair(&c["origin_mm"], ", ")
                )
            }
            k @ ("vibration-field" | "grating-field") => {
                let prim = if k == "vibration-field" {
                    format!("vibration {} Hz", num(&c["freq_hz"]))
                } else {
                    format!("grating {} mm at {}°", num(&c["wavelength_mm"]), num(&c["angle_deg"]))
                };
                let edge = if c["soft_mm"].as_f64() == Some(0.0) {
                    "hard edge".to_string()
                } else {
                    format!("soft edge {} mm", num(&c["soft_mm"]))
                };
                format!(
                    "{prim}, amplitude {}, {edge}; {} element(s); distance field {} tiles ({} stored, {} fine, {} plane, {} corner, {} bend) every {} mm, {} mm from ({}) mm",
                    num(&c["amplitude"]),
                    c["elements"],
                    pair(&c["tiles"], " x "),
                    c["stored_tiles"],
                    c["fine_tiles"],
                    c["plane_tiles"],
                    c["corner_tiles"],
                    c["bend_tiles"],
                    num(&c["pitch_mm"]),
                    pair(&c["size_mm"], " x "),
                    pair(&c["origin_mm"], ", ")
                )
            }
            "dots" => match c["radius_mm"].as_array() {
                Some(r) => format!(
                    "{} {} {}, radius {} mm",
                    c["dots"],
                    c["dot_kind"].as_str().unwrap_or(""),
                    if c["dots"] == 1 { "dot" } else { "dots" },
                    if r[0] == r[1] { num(&r[0]) } else { pair(&c["radius_mm"], " to ") }
                ),
                None => format!("no {} dots", c["dot_kind"].as_str().unwrap_or("")),
            },
            "strokes" => format!(
                "{} strokes, {} points, {} drives{}",
                c["strokes"],
                c["points"],
                c["drives"],
                c["ticks"].as_array().map_or(String::new(), |_| format!(", ticks {}", pair(&c["ticks"], " to ")))
            ),
            "height" => format!(
                "height field {} x {} nodes every {} mm from ({}) mm, heights {} mm, max gradient {}",
                c["cols"],
                c["rows"],
                num(&c["cell_mm"]),
                pair(&c["origin_mm"], ", "),
                pair(&c["height_mm"], " to "),
                num(&c["max_gradient"])
            ),
            "provenance" => format!("provenance, {} entries", c["entries"]),
            "footprints" => format!(
                "footprints for the point lookup, {} shapes, {} rings, {} points every {} mm",
                c["shapes"],
                c["rings"],
                c["points"],
                num(&c["quantum_mm"])
            ),
            _ => "unknown to this taxel (optional, kept as is)".to_string(),
        };
        let flag = if c["required"].as_bool() == Some(true) { "required" } else { "optional" };
        // serde_json values ignore width, so pad their text.
        out += &format!(
            "{:>6}  {:<4}  {:<8}  {:>8}  {what}\n",
            c["index"].to_string(),
            c["tag"].as_str().unwrap_or("?"),
            flag,
            c["bytes"].to_string()
        );
        for s in c["sources"].as_array().into_iter().flatten().take(5) {
            let mut name = format!("#{}", s["index"]);
            if let Some(id) = s["id"].as_str().filter(|id| !id.is_empty()) {
                name += &format!(" {id}");
            }
            if let Some(label) = s["label"].as_str().filter(|l| !l.is_empty()) {
                name += &format!(" \"{label}\"");
            }
            if let Some(line) = s["line"].as_u64().filter(|&l| l > 0) {
                name += &format!(" (line {line})");
            }
            out += &format!("{:34}from {name}\n", "");
        }
        let more = c["sources"].as_array().map_or(0, Vec::len).saturating_sub(5);
        if more > 0 {
            out += &format!("{:34}and {more} more sources\n", "");
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The texts a graphic has no room for are printed as the key prints
    /// them, a few to a line and then how many more, so that a map's
    /// thousands of labels fit on a screen.
    #[test]
    fn texts_with_no_room_are_printed_a_few_to_a_line() {
        let texts = (0..1000).map(|k| format!("R{k}")).collect::<Vec<_>>().join(", ");
        let r = json!({ "profile": {}, "chunks": [], "key_text": texts });
        let out = human(Path::new("a.taxel"), &r);
        // Eight lines of eight: the first 64.
        let listed: Vec<&str> = out.lines().filter(|l| l.contains(", R")).collect();
        assert_eq!(listed.len(), 8, "{out}");
        assert!(listed[0].ends_with("not on the graphic: R0, R1, R2, R3, R4, R5, R6, R7"), "{out}");
        assert!(out.contains("and 936 more not on the graphic"), "{out}");
        assert!(out.lines().all(|l| l.chars().count() < 100), "{out}");
    }
}
