//! Bundle -> text form (in memory: a list of file names and contents).

use std::fmt::Write as _;

use taxel_format::{Bundle, BundleView, Chunk, MaskKind, Tag, profiles};

use super::error::TextError;
use super::tables::{dots_csv, height_csv, provenance_csv, quoted, strokes_toml};
use super::toml_in::f32_text;
use super::{MANIFEST, MANIFEST_HEADER, PROFILE, png};

/// The files of the text form of `bytes` (a bundle), in the order they should
/// be written, the manifest last. `name` is used in error messages.
pub fn unpack(name: &str, bytes: &[u8]) -> Result<Vec<(String, Vec<u8>)>, TextError> {
    let view = BundleView::parse(bytes).map_err(|e| TextError::new(name, e.to_string()))?;
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
                match mk.kind {
                    MaskKind::Vibration { freq } => {
                        let _ = writeln!(toml, "freq_mhz = {}", freq.0);
                    }
                    MaskKind::Grating { wavelength, angle_deg } => {
                        let _ = writeln!(
                            toml,
                            "wavelength_mm = {}\nangle_deg = {}",
                            f32_text(wavelength.0),
                            f32_text(angle_deg)
                        );
                    }
                }
                let data = png::encode(&file, mk.width, mk.height, &mk.samples)?;
                (file, data)
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
                (file, height_csv(h))
            }
            Chunk::Provenance(p) => {
                let file = format!("{stem}-provenance.csv");
                let _ = writeln!(toml, "kind = \"provenance\"\nfile = \"{file}\"");
                (file, provenance_csv(p))
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
fn tag_text(tag: Tag) -> String {
    if tag.0.iter().all(|b| b.is_ascii_graphic() && *b != b'"' && *b != b'\\') {
        format!("tag = \"{tag}\"")
    } else {
        format!("tag_hex = \"{}\"", tag.0.iter().map(|b| format!("{b:02x}")).collect::<String>())
    }
}
