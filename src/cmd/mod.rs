//! One module per command; `run` dispatches.

use std::process::ExitCode;

use anyhow::Result;

use crate::cli::{Cli, Command, DeviceCommand};

mod build;
mod device;
mod load;
mod play;
mod profiles;

/// Runs a parsed command line.
pub fn run(cli: Cli) -> Result<ExitCode> {
    match cli.command {
        None => not_yet("the demo", 8),
        Some(Command::Build { inputs, out, opts, jobs, shard, force }) => {
            build::run(build::BuildArgs { inputs, out, opts, jobs, shard, force })
        }
        Some(Command::Check { .. }) => not_yet("taxel check", 3),
        Some(Command::Inspect { .. }) => not_yet("taxel inspect", 2),
        Some(Command::Pack { .. }) => not_yet("taxel pack", 2),
        Some(Command::Unpack { .. }) => not_yet("taxel unpack", 2),
        Some(Command::Preview { .. }) => not_yet("taxel preview", 3),
        Some(Command::Play { bundle, trace, out }) => play::run(&bundle, trace.as_deref(), out.as_deref()),
        Some(Command::Report { .. }) => not_yet("taxel report", 8),
        Some(Command::Load { bundles, device }) => load::run(&bundles, &device),
        Some(Command::Device(DeviceCommand::Serve { store, listen, capacity, profile })) => {
            device::serve(&store, &listen, capacity, profile.as_deref())
        }
        Some(Command::Device(DeviceCommand::Ls { device })) => device::ls(&device),
        Some(Command::Device(DeviceCommand::Rm { name, device })) => device::rm(&name, &device),
        Some(Command::Profiles) => profiles::run(),
    }
}

/// A command whose issue has not landed: it says so and exits 2, never pretending to work.
fn not_yet(what: &str, issue: u32) -> Result<ExitCode> {
    eprintln!("error: {what} is not available yet (issue {issue})");
    Ok(ExitCode::from(2))
}
