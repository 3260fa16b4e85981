//! `taxel play BUNDLE [--trace CSV] [--out FRAMES.csv|DRIVE.wav]`: reads and
//! validates the bundle, then hands it to the player of its device family.
//! Output files are written through [`crate::io`] (atomic, one permission
//! policy); without `--out` the frames go to standard output.

use std::path::Path;

use taxel_format::{BundleView, Family};
use taxel_runtime::trace::Trace;

use crate::error::{CliError, CmdResult};

mod finger;
mod grid;
mod latero;

pub fn run(bundle: &Path, trace: Option<&Path>, out: Option<&Path>, elements: Option<&Path>) -> CmdResult {
    let bytes = crate::io::read_bundle(bundle)?;
    let view = BundleView::parse(&bytes)
        .map_err(|e| CliError::input(anyhow::anyhow!("{}: not a valid taxel bundle: {e}", bundle.display())))?;
    let family = view.manifest().profile.family();
    if elements.is_some() && family != Family::Laterotactile {
        return Err(CliError::trouble(anyhow::anyhow!(
            "--elements follows the carrier of a laterotactile bundle; {} is for a {} device",
            bundle.display(),
            family.name()
        )));
    }
    match family {
        Family::Grid => grid::run(bundle, &view, trace, out),
        Family::Laterotactile => latero::run(bundle, &view, trace, out, elements),
        Family::Finger => finger::run(bundle, &view, trace, out),
        // A bundle never holds a print profile (the manifest has no code for it).
        Family::Print => Err(CliError::input(anyhow::anyhow!("{}: a print profile makes no bundle", bundle.display()))),
        Family::Pins => {
            // A pin display shows a still image (pages or a pannable surface);
            // there is nothing to play along a trace.
            Err(CliError::trouble(anyhow::anyhow!(
                "{} is a pin-display bundle: it is not played along a trace; \
                 write the device's own file with `taxel export` or look at it with `taxel preview`",
                bundle.display()
            )))
        }
    }
}

/// Reads the exploration trace at `path`: a file that cannot be read is exit
/// 2, a malformed trace exit 1 with its line.
fn read_trace(path: &Path) -> Result<Trace, CliError> {
    let bytes = crate::io::read_input(path)?;
    Trace::parse(&bytes[..]).map_err(|e| CliError::input(anyhow::anyhow!("{}: {e}", path.display())))
}
