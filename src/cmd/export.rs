//! `taxel export BUNDLE --format dtms|graphiti|unicode -o FILE`: a pin-display
//! bundle as the device's own file (`docs/pins.md`): a Dot Pad DTMS page
//! file, Graphiti full frames, or Unicode braille art. The bundle is
//! validated first; the file is written atomically.

use std::path::Path;

use taxel_compiler::pins::export;
use taxel_format::Bundle;

use crate::cli::ExportFormat;
use crate::error::{CliError, CmdResult};
use crate::io;

pub fn run(bundle: &Path, format: ExportFormat, out: &Path) -> CmdResult {
    let shown = bundle.display();
    let bytes = io::read_bundle(bundle)?;
    let b = Bundle::from_bytes(&bytes)
        .map_err(|e| CliError::input(anyhow::anyhow!("{shown}: not a valid taxel bundle: {e}")))?;
    let profile = b.manifest.profile;
    let Some(image) = b.pin_image() else {
        return Err(CliError::input(anyhow::anyhow!(
            "{shown}: no pin image: the bundle was compiled for {} ({} family); \
             export needs a pin-display bundle (build with --profile dotpad, monarch, graphiti or hyperbraille)",
            profile.name,
            profile.family()
        )));
    };
    let file_title = out.file_name().and_then(|n| n.to_str()).unwrap_or("drawing.dtms");
    let data = data(&b, format, file_title).map_err(|e| CliError::input(anyhow::anyhow!("{shown}: {e}")))?;
    io::write_file(out, &data)?;
    let pages = export::pages(image, &profile).len();
    eprintln!("wrote {} ({} bytes, {pages} page{})", out.display(), data.len(), if pages == 1 { "" } else { "s" });
    Ok(())
}

/// The device's own file of a pin-display bundle in `format`; `file_title`
/// names it inside a DTMS file. The studio's downloads are this too.
pub fn data(b: &Bundle, format: ExportFormat, file_title: &str) -> Result<Vec<u8>, String> {
    let profile = b.manifest.profile;
    let Some(image) = b.pin_image() else {
        return Err(format!(
            "no pin image: the bundle was compiled for {} ({} family); export needs a pin-display bundle",
            profile.name,
            profile.family()
        ));
    };
    // The drawing's title, when the compiler recorded it (provenance entry 0,
    // id `svg`), and the key of its key codes (entry `key`): together the
    // print text of the device's text line.
    let entry = |id: &str| {
        b.provenance().and_then(|p| p.entries.iter().find(|e| e.id == id)).map_or(String::new(), |e| e.label.clone())
    };
    let title = entry("svg");
    let line =
        [title.as_str(), entry("key").as_str()].into_iter().filter(|s| !s.is_empty()).collect::<Vec<_>>().join("; ");
    let data = match format {
        ExportFormat::Unicode => Ok(export::unicode(image).into_bytes()),
        ExportFormat::Dtms => export::dtms(image, &profile, file_title, &title, &line).map(String::into_bytes),
        ExportFormat::Graphiti => export::graphiti(image, &profile),
    };
    data.map_err(|e| e.to_string())
}
