//! Bundle -> text form (in memory: a list of file names and contents).

use std::fmt::Write as _;

use taxel_format::{Bundle, BundleView, Chunk, DistanceLayer, MaskKind, MaskSamples, Tag, profiles};

use super::error::TextError;
use super::tables::{csv_rows, dots_csv, footprints_csv, height_csv, provenance_csv, quoted, strokes_toml};
use super::toml_in::f32_text;
use super::{MANIFEST, MANIFEST_HEADER, PROFILE, png};

/// The files of the text form of `bytes` (a bundle), in the order they should
/// be written, the manifest last. `name` is used in error messages.
pub fn unpack(name: &str, bytes: &[u8]) -> Result<Vec<(String, Vec<u8>)>, TextError> {
    // A stored bundle (SPEC.md 15) is inflated first.
    let plain = taxel_format::stored::plain(bytes).map_err(|e| TextError::new(name, e.to_string()))?;
    let view = BundleView::parse(&plain).map_err(|e| TextError::new(name, e.to_string()))?;
    let bundle = Bundle::from_view(&view);
    let (major, minor) = view.version();
    let m = &bundle.manifest;
    let mut files = Vec::new();
    let mut toml = format!(
        "{MANIFEST_HEADER}\n\
         # Edit the files it lists, then run `taxel pack DIR -o BUNDLE`. Chunks are\n\
         # written in the order listed here. Lengths are mm on the page (origin at the\n\
         # top-left, y down), frequencies mHz, times ticks of the profile's rate_hz.\n\
         # See docs/text-form.md.\n\n\
         format = \"{major}.{minor}\"\nprofile = \"{PROFILE}\"\ngenerator = {}\ncontent_hash = \"{}\"\n",
        quoted(m.generator.as_str()),
        m.content_hash.iter().map(|b| format!("{b:02x}")).collect::<String>()
    );
    files.push((PROFILE.to_string(), profiles::to_toml(&m.profile).into_bytes()));
    let width = bundle.chunks.len().to_string().len().max(2);
    for (i, c) in bundle.chunks.iter().enumerate() {
        let index = i + 1;
        let stem = format!("{index:0width$}");
        let _ = write!(toml, "\n[[chunk]]\n");
        let (file, data) = match c {
            Chunk::Mask(mk) => {
                let (kind, ext) = match mk.kind {
                    MaskKind::Vibration { .. } => ("vibration", "png"),
                    MaskKind::Grating { .. } => ("grating", "png"),
                };
                let file = format!("{stem}-{kind}.{ext}");
                let _ = writeln!(toml, "kind = \"{kind}\"\nfile = \"{file}\"");
                if let Some(s) = mk.source {
                    let _ = writeln!(toml, "source = {s}");
                }
                let _ = writeln!(
                    toml,
                    "amplitude = {}\norigin_x_mm = {}\norigin_y_mm = {}\npx_per_mm = {}",
                    f32_text(mk.amplitude),
                    f32_text(mk.origin_x.0),
                    f32_text(mk.origin_y.0),
                    f32_text(mk.px_per_mm)
                );
                kind_params(&mut toml, mk.kind);
                let data = png::encode(&file, mk.width, mk.height, &mk.samples)?;
                (file, data)
            }
            Chunk::Distance(d) => {
                let kind = match d.kind {
                    MaskKind::Vibration { .. } => "vibration-field",
                    MaskKind::Grating { .. } => "grating-field",
                };
                let file = format!("{stem}-{kind}.png");
                let tiles = format!("{stem}-{kind}-tiles.csv");
                // Every kind of tile entry, as the format spells it.
                let entries: Vec<&str> = taxel_format::TileKind::ALL.iter().map(|k| k.entry_text()).collect();
                let note = format!(
                    "{file}: the amplitude this layer produces at 10 px/mm, for people (pack ignores it); \
                     the exact data are the tile index ({tiles}: {}) and the stored tiles' codes and plane records.",
                    entries.join(", ")
                );
                let _ = writeln!(toml, "kind = \"{kind}\"\n{}\nfile = \"{file}\"\ntiles = \"{tiles}\"", comment(&note));
                if d.stored_tiles() > 0 {
                    let samples = format!("{stem}-{kind}-samples.png");
                    let _ = writeln!(toml, "samples = \"{samples}\"");
                    let png = png::encode(
                        &samples,
                        taxel_format::TILE_SIDE as u32,
                        (taxel_format::TILE_SIDE * d.stored_tiles()) as u32,
                        &MaskSamples::U8(d.samples.clone()),
                    )?;
                    files.push((samples, png));
                }
                if !d.planes.is_empty() {
                    // One record a line, `c, gx, gy, top` in codes (SPEC.md section 6.2).
                    let planes = format!("{stem}-{kind}-planes.csv");
                    let _ = writeln!(toml, "planes = \"{planes}\"");
                    let rows = d.planes.iter().map(|p| [p.c, p.gx, p.gy, p.top].map(f32_text).to_vec());
                    files.push((planes, csv_rows(rows)));
                }
                let sources: Vec<String> = d.sources.iter().map(|s| s.to_string()).collect();
                let _ = writeln!(
                    toml,
                    "sources = [{}]\namplitude = {}\nsoft_mm = {}\nstep_mm = {}\norigin_x_mm = {}\norigin_y_mm = {}\npitch_mm = {}\ntile_cols = {}\ntile_rows = {}",
                    sources.join(", "),
                    f32_text(d.amplitude),
                    f32_text(d.soft_mm),
                    f32_text(d.step_mm),
                    f32_text(d.origin_x.0),
                    f32_text(d.origin_y.0),
                    f32_text(d.pitch_mm),
                    d.tile_cols,
                    d.tile_rows
                );
                kind_params(&mut toml, d.kind);
                let rows = d.tiles.chunks(d.tile_cols.max(1) as usize).map(|r| r.iter().map(u32::to_string).collect());
                files.push((tiles, csv_rows(rows)));
                (file.clone(), amplitude_png(&file, d)?)
            }
            Chunk::Dots(d) => {
                let file = format!("{stem}-dots.csv");
                let _ = writeln!(toml, "kind = \"dots\"\nfile = \"{file}\"\ndot_kind = \"{}\"", d.kind.name());
                (file, dots_csv(&d.dots))
            }
            Chunk::Strokes(s) => {
                let file = format!("{stem}-strokes.toml");
                let _ = writeln!(toml, "kind = \"strokes\"\nfile = \"{file}\"");
                (file, strokes_toml(s))
            }
            Chunk::Height(h) => {
                let file = format!("{stem}-height.csv");
                let _ = writeln!(toml, "kind = \"height\"\nfile = \"{file}\"");
                if let Some(s) = h.source {
                    let _ = writeln!(toml, "source = {s}");
                }
                let _ = writeln!(
                    toml,
                    "cols = {}\nrows = {}\norigin_x_mm = {}\norigin_y_mm = {}\ncell_mm = {}\ngradient_cap = {}",
                    h.cols,
                    h.rows,
                    f32_text(h.origin_x.0),
                    f32_text(h.origin_y.0),
                    f32_text(h.cell.0),
                    f32_text(h.gradient_cap)
                );
                if let taxel_format::HeightEncoding::Tiled { step, base, max_gradient } = h.encoding {
                    let _ = writeln!(
                        toml,
                        "height_step_mm = {}\nheight_base_mm = {}\nmax_gradient = {}",
                        f32_text(step),
                        f32_text(base),
                        f32_text(max_gradient)
                    );
                }
                (file, height_csv(h))
            }
            Chunk::Provenance(p) => {
                let file = format!("{stem}-provenance.csv");
                let _ = writeln!(toml, "kind = \"provenance\"\nfile = \"{file}\"");
                (file, provenance_csv(p))
            }
            Chunk::Footprints(fp) => {
                let file = format!("{stem}-footprints.csv");
                let _ = writeln!(
                    toml,
                    "kind = \"footprints\"\n# {file}: one row per ring; point (x, y) lies at origin + quantum * (x, y) mm.\n\
                     file = \"{file}\"\norigin_x_mm = {}\norigin_y_mm = {}\nquantum_mm = {}",
                    f32_text(fp.origin_x),
                    f32_text(fp.origin_y),
                    f32_text(fp.quantum_mm)
                );
                (file, footprints_csv(&fp.shapes))
            }
            Chunk::Pins(image) => {
                let file = format!("{stem}-pins.txt");
                let (entry, data) = super::pins::write(image, &file);
                toml.push_str(&entry);
                (file, data)
            }
            Chunk::Raw(r) => {
                let file = format!("{stem}-raw.bin");
                let _ = writeln!(toml, "kind = \"raw\"\nfile = \"{file}\"");
                let _ = writeln!(toml, "{}", tag_text(r.tag));
                let _ = writeln!(toml, "required = {}", r.required);
                (file, r.data.clone())
            }
        };
        files.push((file, data));
    }
    files.push((MANIFEST.to_string(), toml.into_bytes()));
    Ok(files)
}

/// `tag = "XTRA"` for a printable tag, `tag_hex = "..."` otherwise.
/// A vibration's or grating's parameters, as TOML lines.
fn kind_params(toml: &mut String, kind: MaskKind) {
    match kind {
        MaskKind::Vibration { freq } => {
            let _ = writeln!(toml, "freq_mhz = {}", freq.0);
        }
        MaskKind::Grating { wavelength, angle_deg } => {
            let _ = writeln!(toml, "wavelength_mm = {}\nangle_deg = {}", f32_text(wavelength.0), f32_text(angle_deg));
        }
    }
}

fn tag_text(tag: Tag) -> String {
    if tag.0.iter().all(|b| b.is_ascii_graphic() && *b != b'"' && *b != b'\\') {
        format!("tag = \"{tag}\"")
    } else {
        format!("tag_hex = \"{}\"", tag.0.iter().map(|b| format!("{b:02x}")).collect::<String>())
    }
}

/// Pixels per millimetre of a distance layer's amplitude picture.
const PICTURE_PX_PER_MM: f32 = 10.0;

/// The amplitude a distance layer produces (edge profile times the layer's
/// amplitude, before the primitive), as an 8-bit grayscale PNG over its
/// lattice at [`PICTURE_PX_PER_MM`], sampled at pixel centres.
fn amplitude_png(file: &str, d: &DistanceLayer) -> Result<Vec<u8>, TextError> {
    let span = taxel_format::TILE_CELLS as f32 * d.pitch_mm;
    let w = ((d.tile_cols as f32 * span * PICTURE_PX_PER_MM).ceil() as u32).clamp(1, 16_384);
    let h = ((d.tile_rows as f32 * span * PICTURE_PX_PER_MM).ceil() as u32).clamp(1, 16_384);
    let mut v = Vec::with_capacity((w * h) as usize);
    for j in 0..h {
        for i in 0..w {
            let x = d.origin_x.0 + (i as f32 + 0.5) / PICTURE_PX_PER_MM;
            let y = d.origin_y.0 + (j as f32 + 0.5) / PICTURE_PX_PER_MM;
            v.push((d.coverage_at(x, y) * d.amplitude * 255.0).round() as u8);
        }
    }
    png::encode(file, w, h, &MaskSamples::U8(v))
}

/// `text` as TOML comment lines of at most about 100 characters, broken at spaces.
fn comment(text: &str) -> String {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ') {
        match lines.last_mut() {
            Some(l) if l.len() + 1 + word.len() <= 100 => {
                l.push(' ');
                l.push_str(word);
            }
            _ => lines.push(format!("# {word}")),
        }
    }
    lines.join("\n")
}
