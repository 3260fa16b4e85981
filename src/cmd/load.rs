//! `taxel load BUNDLE... --device DIR|tcp://HOST:PORT`: each bundle is checked
//! here, then by the device, which stores it only once verified. A refused
//! bundle is reported and the others still load; the exit code is 1 if any
//! was refused.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use taxel_runtime::device::{ClientError, valid_name};

use super::device::Device;

pub fn run(bundles: &[PathBuf], spec: &str) -> Result<ExitCode> {
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
        let bytes = match std::fs::read(path) {
            Ok(b) => b,
            Err(e) => {
                eprintln!("error: cannot read {shown}: {e}");
                refused += 1;
                continue;
            }
        };
        match device.load(name, &bytes) {
            Ok(entry) => println!("loaded {shown} onto {target} as {} ({} bytes, verified)", entry.name, entry.size),
            Err(ClientError::Refused(r)) => {
                eprintln!("error: {shown}: refused by {target}: {r}");
                refused += 1;
            }
            Err(e) => {
                // The connection is gone: the remaining bundles cannot load either.
                eprintln!("error: {shown}: {target}: {e}");
                return Ok(ExitCode::from(2));
            }
        }
    }
    device.close();
    Ok(if refused == 0 { ExitCode::SUCCESS } else { ExitCode::from(1) })
}
