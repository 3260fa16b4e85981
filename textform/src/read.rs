//! Text form -> bundle. Every problem names the file (and line and key or
//! column) and what was expected.

use taxel_format::{
    Bundle, Chunk, DistanceLayer, DotKind, DotTable, FORMAT_MAJOR, FixedStr, FormatError, HeightField, Manifest,
    MaskKind, MaskLayer, MaskSamples, MilliHertz, Mm, RawChunk, Tag, profiles,
};

use super::error::TextError;
use super::tables::{parse_dots, parse_footprints, parse_height, parse_provenance, parse_rows, parse_strokes};
use super::toml_in::{Doc, Table};
use super::{MANIFEST, png};

const TOP_KEYS: &[&str] = &["format", "profile", "generator", "content_hash", "chunk"];
const MASK_KEYS: &[&str] = &[
    "kind",
    "file",
    "source",
    "amplitude",
    "origin_x_mm",
    "origin_y_mm",
    "px_per_mm",
    "freq_mhz",
    "wavelength_mm",
    "angle_deg",
];
const FIELD_KEYS: &[&str] = &[
    "kind",
    "file",
    "tiles",
    "samples",
    "planes",
    "sources",
    "amplitude",
    "soft_mm",
    "step_mm",
    "origin_x_mm",
    "origin_y_mm",
    "pitch_mm",
    "tile_cols",
    "tile_rows",
    "freq_mhz",
    "wavelength_mm",
    "angle_deg",
];
const DOTS_KEYS: &[&str] = &["kind", "file", "dot_kind"];
const FILE_KEYS: &[&str] = &["kind", "file"];
const HEIGHT_KEYS: &[&str] = &[
    "kind",
    "file",
    "source",
    "cols",
    "rows",
    "origin_x_mm",
    "origin_y_mm",
    "cell_mm",
    "gradient_cap",
    "height_step_mm",
    "height_base_mm",
    "max_gradient",
];
const FOOTPRINT_KEYS: &[&str] = &["kind", "file", "origin_x_mm", "origin_y_mm", "quantum_mm"];
const RAW_KEYS: &[&str] = &["kind", "file", "tag", "tag_hex", "required"];

/// Builds the bundle of an unpacked folder. `read(name)` returns the bytes of
/// the file `name` in the folder (or an error naming it).
pub fn pack(read: &dyn Fn(&str) -> Result<Vec<u8>, TextError>) -> Result<Vec<u8>, TextError> {
    let manifest_bytes = read(MANIFEST)?;
    let text = std::str::from_utf8(&manifest_bytes).map_err(|_| TextError::new(MANIFEST, "expected UTF-8 text"))?;
    let doc = Doc::parse(MANIFEST, text)?;
    let root = doc.root(TOP_KEYS)?;

    let version = root.str("format")?;
    let minor = parse_version(version).ok_or_else(|| {
        root.err(
            "format",
            format!("expected \"{FORMAT_MAJOR}.MINOR\" (this taxel writes major version {FORMAT_MAJOR})"),
        )
    })?;
    let profile_file = safe_name(&root, "profile")?;
    let profile_bytes = read(profile_file)?;
    let profile_text =
        std::str::from_utf8(&profile_bytes).map_err(|_| TextError::new(profile_file, "expected UTF-8 text"))?;
    let profile = profiles::parse(profile_text, profile_file).map_err(|e| {
        TextError::new(
            profile_file,
            match e.key {
                Some(k) => format!("key `{k}`: {}", e.message),
                None => e.message,
            },
        )
    })?;
    let mut manifest = Manifest::new(profile);
    manifest.generator = FixedStr::new(root.str("generator")?)
        .ok_or_else(|| root.err("generator", "expected at most 15 bytes of text without NUL"))?;
    manifest.content_hash = parse_hex::<32>(root.str("content_hash")?)
        .ok_or_else(|| root.err("content_hash", "expected 64 hexadecimal digits"))?;

    let mut bundle = Bundle::new(manifest);
    // Every kind's keys are checked once its kind is known.
    let any_keys: Vec<&str> =
        [MASK_KEYS, FIELD_KEYS, DOTS_KEYS, HEIGHT_KEYS, RAW_KEYS, FOOTPRINT_KEYS, super::pins::PINS_KEYS].concat();
    let tables = root.tables("chunk", &any_keys)?;
    for c in &tables {
        bundle.chunks.push(chunk(c, read)?);
    }
    bundle.to_bytes_with_minor(minor).map_err(|e| {
        // Chunk i of the bundle is [[chunk]] i of the manifest: name the
        // file or the key that holds what is wrong.
        match chunk_index(&e).and_then(|i| tables.get((i as usize).checked_sub(1)?)) {
            Some(c) => where_in(c, &e),
            None if chunk_index(&e) == Some(0) => TextError::new(profile_file, format!("not a valid profile: {e}")),
            None => TextError::new(MANIFEST, format!("the folder does not make a valid bundle: {e}")),
        }
    })
}

/// The error `e` about the chunk of table `c`, at what holds the wrong
/// value: a distance layer's tile index, plane records or samples file, a
/// manifest key at its line (`pitch_mm`), or else the chunk's data file.
fn where_in(c: &Table<'_, '_>, e: &FormatError) -> TextError {
    let message = format!("not a valid chunk: {e}");
    let field = match e {
        FormatError::InvalidValue { field, .. } => *field,
        _ => "",
    };
    let key = match field {
        "tile index" => "tiles",
        "plane record" => "planes",
        k => k,
    };
    let file = |k: &str| c.str(k).map(|f| TextError::new(f, message.clone()));
    match key {
        "tiles" | "planes" | "samples" if c.has(key) => file(key).unwrap_or_else(|err| err),
        _ if c.has(key) => c.err(key, message.clone()),
        _ => file("file").unwrap_or_else(|err| err),
    }
}

/// The table index of the chunk an error is about, if it names one.
fn chunk_index(e: &FormatError) -> Option<u32> {
    match e {
        FormatError::InvalidValue { index, .. }
        | FormatError::ChunkLength { index, .. }
        | FormatError::ChunkChecksum { index, .. }
        | FormatError::ChunkPlacement { index, .. }
        | FormatError::UnknownRequiredChunk { index, .. }
        | FormatError::ChunkOrder { index, .. }
        | FormatError::RequiredFlag { index, .. } => Some(*index),
        _ => None,
    }
}

fn chunk(c: &Table<'_, '_>, read: &dyn Fn(&str) -> Result<Vec<u8>, TextError>) -> Result<Chunk, TextError> {
    let kind = c.str("kind")?;
    let allowed = match kind {
        "vibration" | "grating" => MASK_KEYS,
        "vibration-field" | "grating-field" => FIELD_KEYS,
        "dots" => DOTS_KEYS,
        "strokes" | "provenance" => FILE_KEYS,
        "height" => HEIGHT_KEYS,
        "raw" => RAW_KEYS,
        "footprints" => FOOTPRINT_KEYS,
        "pins" => super::pins::PINS_KEYS,
        _ => {
            return Err(c.err(
                "kind",
                format!(
                    "unknown kind \"{kind}\", expected vibration, grating, vibration-field, grating-field, dots, strokes, height, pins, provenance, footprints or raw"
                ),
            ));
        }
    };
    // Keys that belong to another kind are refused by name.
    for k in [MASK_KEYS, FIELD_KEYS, DOTS_KEYS, HEIGHT_KEYS, RAW_KEYS, FOOTPRINT_KEYS, super::pins::PINS_KEYS].concat()
    {
        if c.has(k) && !allowed.contains(&k) {
            return Err(c.err(k, format!("not a key of a {kind} chunk, expected one of: {}", allowed.join(", "))));
        }
    }
    if kind.ends_with("-field") {
        return field_chunk(c, kind, read);
    }
    if kind == "vibration" && (c.has("wavelength_mm") || c.has("angle_deg")) {
        return Err(c.err("wavelength_mm", "a vibration chunk has freq_mhz, not wavelength_mm or angle_deg"));
    }
    if kind == "grating" && c.has("freq_mhz") {
        return Err(c.err("freq_mhz", "a grating chunk has wavelength_mm and angle_deg, not freq_mhz"));
    }
    let file = safe_name(c, "file")?;
    let data = read(file)?;
    let source = c.opt_uint("source", u32::MAX as u64 - 1)?.map(|v| v as u32);
    Ok(match kind {
        "vibration" | "grating" => {
            let (width, height, samples) = png::decode(file, &data)?;
            let kind = if kind == "vibration" {
                MaskKind::Vibration { freq: MilliHertz(c.uint("freq_mhz", u32::MAX as u64)? as u32) }
            } else {
                MaskKind::Grating { wavelength: Mm(c.f32("wavelength_mm")?), angle_deg: c.f32("angle_deg")? }
            };
            Chunk::Mask(MaskLayer {
                source,
                kind,
                amplitude: c.f32("amplitude")?,
                origin_x: Mm(c.f32("origin_x_mm")?),
                origin_y: Mm(c.f32("origin_y_mm")?),
                px_per_mm: c.f32("px_per_mm")?,
                width,
                height,
                samples,
            })
        }
        "dots" => {
            let dot_kind = match c.str("dot_kind")? {
                "outline" => DotKind::Outline,
                "symbol" => DotKind::Symbol,
                "braille" => DotKind::Braille,
                other => {
                    return Err(c.err(
                        "dot_kind",
                        format!("unknown dot kind \"{other}\", expected outline, symbol or braille"),
                    ));
                }
            };
            Chunk::Dots(DotTable { kind: dot_kind, dots: parse_dots(file, &data)? })
        }
        "strokes" => Chunk::Strokes(parse_strokes(file, &data)?),
        "height" => {
            let side = taxel_format::MAX_FIELD_SIDE as u64;
            let mut h = HeightField {
                source,
                cols: c.uint("cols", side)? as u32,
                rows: c.uint("rows", side)? as u32,
                origin_x: Mm(c.f32("origin_x_mm")?),
                origin_y: Mm(c.f32("origin_y_mm")?),
                cell: Mm(c.f32("cell_mm")?),
                gradient_cap: c.f32("gradient_cap")?,
                heights: Vec::new(),
                grad_x: Vec::new(),
                grad_y: Vec::new(),
                flags: Vec::new(),
                // A tiled field (format 4.6) names its step, base and largest gradient.
                encoding: if c.has("height_step_mm") {
                    taxel_format::HeightEncoding::Tiled {
                        step: c.f32("height_step_mm")?,
                        base: c.f32("height_base_mm")?,
                        max_gradient: c.f32("max_gradient")?,
                    }
                } else {
                    taxel_format::HeightEncoding::Float
                },
            };
            if (h.cols as u64) * (h.rows as u64) > taxel_format::MAX_FIELD_NODES {
                return Err(c.err("rows", format!("expected cols * rows at most {}", taxel_format::MAX_FIELD_NODES)));
            }
            parse_height(file, &data, &mut h)?;
            Chunk::Height(h)
        }
        "provenance" => Chunk::Provenance(parse_provenance(file, &data)?),
        "footprints" => Chunk::Footprints(taxel_format::Footprints {
            origin_x: c.f32("origin_x_mm")?,
            origin_y: c.f32("origin_y_mm")?,
            quantum_mm: c.f32("quantum_mm")?,
            shapes: parse_footprints(file, &data)?,
        }),
        "pins" => Chunk::Pins(super::pins::read(c, file, &data)?),
        _ => {
            let tag = match (c.has("tag"), c.has("tag_hex")) {
                (true, false) => {
                    let t = c.str("tag")?;
                    <[u8; 4]>::try_from(t.as_bytes()).map_err(|_| c.err("tag", "expected four ASCII characters"))?
                }
                (false, true) => parse_hex::<4>(c.str("tag_hex")?)
                    .ok_or_else(|| c.err("tag_hex", "expected 8 hexadecimal digits"))?,
                _ => return Err(c.err("tag", "expected exactly one of tag and tag_hex")),
            };
            Chunk::Raw(RawChunk { tag: Tag(tag), required: c.bool("required")?, data })
        }
    })
}

/// A file name from key `k`, refused if it could leave the folder.
fn safe_name<'d>(t: &Table<'d, '_>, k: &str) -> Result<&'d str, TextError> {
    let name = t.str(k)?;
    let ok = !name.is_empty()
        && !name.starts_with('.')
        && !name.contains(['/', '\\', ':'])
        && name.chars().all(|ch| !ch.is_control());
    if ok { Ok(name) } else { Err(t.err(k, "expected a plain file name in the folder (no path)")) }
}

fn parse_version(v: &str) -> Option<u16> {
    let (major, minor) = v.split_once('.')?;
    (major.parse::<u16>().ok()? == FORMAT_MAJOR).then_some(())?;
    minor.parse().ok()
}

fn parse_hex<const N: usize>(s: &str) -> Option<[u8; N]> {
    if s.len() != 2 * N || !s.is_ascii() {
        return None;
    }
    let mut out = [0u8; N];
    for (i, o) in out.iter_mut().enumerate() {
        *o = u8::from_str_radix(&s[2 * i..2 * i + 2], 16).ok()?;
    }
    Some(out)
}

/// A distance layer from its tile index (CSV, one line per row of tiles)
/// and its stored tiles' codes (an 8-bit grayscale PNG 9 pixels wide, one
/// 9 x 9 block per stored tile, top to bottom).
fn field_chunk(
    c: &Table<'_, '_>,
    kind: &str,
    read: &dyn Fn(&str) -> Result<Vec<u8>, TextError>,
) -> Result<Chunk, TextError> {
    let mask_kind = if kind == "vibration-field" {
        if c.has("wavelength_mm") || c.has("angle_deg") {
            return Err(c.err("wavelength_mm", "a vibration-field chunk has freq_mhz, not wavelength_mm or angle_deg"));
        }
        MaskKind::Vibration { freq: MilliHertz(c.uint("freq_mhz", u32::MAX as u64)? as u32) }
    } else {
        if c.has("freq_mhz") {
            return Err(c.err("freq_mhz", "a grating-field chunk has wavelength_mm and angle_deg, not freq_mhz"));
        }
        MaskKind::Grating { wavelength: Mm(c.f32("wavelength_mm")?), angle_deg: c.f32("angle_deg")? }
    };
    // The amplitude picture is for people; it must be named but is not read.
    safe_name(c, "file")?;
    let tile_cols = c.uint("tile_cols", taxel_format::MAX_DISTANCE_TILES as u64)? as u32;
    let tile_rows = c.uint("tile_rows", taxel_format::MAX_DISTANCE_TILES as u64)? as u32;
    let tiles_file = safe_name(c, "tiles")?;
    let what = "tile index entries (whole numbers; tile_cols of them a line)";
    let tiles = parse_rows(tiles_file, &read(tiles_file)?, tile_cols as usize, what, |v| v.parse::<u32>().ok())?;
    if tiles.len() as u64 != tile_cols as u64 * tile_rows as u64 {
        return Err(TextError::new(tiles_file, format!("expected {tile_rows} lines (tile_rows)")));
    }
    let samples = if c.has("samples") {
        let file = safe_name(c, "samples")?;
        match png::decode(file, &read(file)?)? {
            (w, _, MaskSamples::U8(v)) if w as usize == taxel_format::TILE_SIDE => v,
            _ => return Err(TextError::new(file, "expected an 8-bit grayscale PNG 9 pixels wide")),
        }
    } else {
        Vec::new()
    };
    let mut planes = Vec::new();
    if c.has("planes") {
        let file = safe_name(c, "planes")?;
        let what = "numbers (four a line: `c, gx, gy, top`)";
        let values = parse_rows(file, &read(file)?, 4, what, |v| v.parse::<f32>().ok())?;
        planes.extend(values.chunks_exact(4).map(|v| taxel_format::TilePlane {
            c: v[0],
            gx: v[1],
            gy: v[2],
            top: v[3],
        }));
    }
    let sources = c.uint_array("sources", u32::MAX as u64 - 1)?.into_iter().map(|v| v as u32).collect();
    Ok(Chunk::Distance(DistanceLayer {
        kind: mask_kind,
        amplitude: c.f32("amplitude")?,
        soft_mm: c.f32("soft_mm")?,
        step_mm: c.f32("step_mm")?,
        origin_x: Mm(c.f32("origin_x_mm")?),
        origin_y: Mm(c.f32("origin_y_mm")?),
        pitch_mm: c.f32("pitch_mm")?,
        tile_cols,
        tile_rows,
        sources,
        tiles,
        planes,
        samples,
    }))
}
