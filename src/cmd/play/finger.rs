//! Playing a finger-device bundle: one motors row per trace sample
//! ([`crate::playback::finger_motors`] says what the columns mean).

use std::path::Path;

use taxel_format::BundleView;
use taxel_runtime::finger::FingerPlayer;

use crate::error::{CliError, CmdResult};
use crate::io::{self, stdout};
use crate::playback::finger_motors;

/// Plays `view` on the trace at `trace_path`.
pub fn run(bundle: &Path, view: &BundleView<'_>, trace_path: Option<&Path>, out: Option<&Path>) -> CmdResult {
    let Some(trace_path) = trace_path else {
        return Err(CliError::trouble(anyhow::anyhow!(
            "{}: a finger bundle plays on a trace: add --trace TRACE.csv",
            bundle.display()
        )));
    };
    let trace = super::read_trace(trace_path)?;
    let mut player =
        FingerPlayer::new(view).map_err(|e| CliError::input(anyhow::anyhow!("{}: {e}", bundle.display())))?;
    let rate = view.manifest().profile.rate_hz;
    match out {
        Some(path) => {
            io::write_with(path, |w| finger_motors(&mut player, &trace, rate, w))?;
            stdout::outln!("wrote {}: {} samples", path.display(), trace.samples().len())
        }
        None => stdout::stream(|w| finger_motors(&mut player, &trace, rate, w)),
    }
}
