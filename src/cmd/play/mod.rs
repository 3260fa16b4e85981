//! `taxel play BUNDLE [--trace CSV] [--out FRAMES.csv|DRIVE.wav]`: reads and
//! validates the bundle, then hands it to the player of its device family.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Result;
use taxel_format::{BundleView, Family};

pub(crate) mod finger;
mod grid;
mod latero;

pub fn run(bundle: &Path, trace: Option<&Path>, out: Option<&Path>) -> Result<ExitCode> {
    let bytes = match std::fs::read(bundle) {
        Ok(b) => b,
        Err(e) => {
            eprintln!("error: cannot read {}: {e}", bundle.display());
            return Ok(ExitCode::from(2));
        }
    };
    let view = match BundleView::parse(&bytes) {
        Ok(v) => v,
        Err(e) => {
            eprintln!("error: {}: not a valid taxel bundle: {e}", bundle.display());
            return Ok(ExitCode::from(1));
        }
    };
    match view.manifest().profile.family() {
        Family::Grid => grid::run(bundle, &view, trace, out),
        Family::Laterotactile => latero::run(bundle, &view, trace, out),
        Family::Finger => finger::run(bundle, &view, trace, out),
        Family::Pins => {
            // A pin display shows a still image (pages or a pannable surface);
            // there is nothing to play along a trace.
            eprintln!(
                "error: {} is a pin-display bundle: it is not played along a trace; \
                 write the device's own file with `taxel export` or look at it with `taxel preview`",
                bundle.display()
            );
            Ok(ExitCode::from(2))
        }
    }
}
