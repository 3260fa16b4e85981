//! `taxel load BUNDLE... --device DIR|tcp://HOST:PORT`: each bundle is checked
//! here, then by the device, which stores it only once verified. A refused
//! bundle is reported and the others still load; the exit code is 1 if any
//! was refused.

use std::path::PathBuf;

use taxel_runtime::device::{ClientError, valid_name};

use super::device::Device;
use crate::error::{CliError, CmdResult};
use crate::io::stdout::outln;

pub fn run(bundles: &[PathBuf], spec: &str) -> CmdResult {
    let mut device = Device::open(spec)?;
    let target = device.describe();
    let mut refused = 0usize;
    for path in bundles {
        let shown = path.display();
        let Some(name) = path.file_name().and_then(|n| n.to_str()).filter(|n| valid_name(n)) else {
            eprintln!(
                "error: {shown}: the file name cannot name a bundle on a device \
                 (1-64 letters, digits, '-', '_', '.', not starting with '.')"
            );
            refused += 1;
            continue;
        };
        let bytes = match crate::io::read_bundle_file(path) {
            Ok(b) => b,
            Err(e) => {
                eprintln!("error: {e:#}");
                refused += 1;
                continue;
            }
        };
        match device.load(name, &bytes) {
            Ok(entry) => outln!("loaded {shown} onto {target} as {} ({} bytes, verified)", entry.name, entry.size)?,
            Err(ClientError::Refused(r)) => {
                eprintln!("error: {shown}: refused by {target}: {r}");
                refused += 1;
            }
            Err(e) => {
                // The connection is gone: the remaining bundles cannot load either.
                return Err(CliError::trouble(anyhow::anyhow!("{shown}: {target}: {e}")));
            }
        }
    }
    device.close();
    match refused {
        0 => Ok(()),
        n => Err(CliError::input(anyhow::anyhow!("{n} of {} bundles were not loaded", bundles.len()))),
    }
}
