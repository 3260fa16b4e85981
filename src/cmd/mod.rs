//! One module per command; `run` dispatches.

use crate::cli::{Cli, Command, DeviceCommand, InkscapeCommand};
use crate::error::{CliError, CmdResult};

mod build;
mod check;
mod device;
pub mod export;
mod inkscape;
mod inspect;
mod load;
mod pack;
mod play;
mod preview;
mod profiles;
mod report;
mod style;
mod unpack;

/// Runs a parsed command line.
pub fn run(cli: Cli) -> CmdResult {
    match cli.command {
        None => crate::demo::main(),
        Some(Command::Build { inputs, out, opts, jobs, shard, force, verbose }) => {
            build::run(build::BuildArgs { inputs, out, opts, jobs, shard, force, verbose })
        }
        Some(Command::Check { inputs, opts, format, verbose }) => check::run(&inputs, &opts, format, verbose),
        Some(Command::Style { sheet, input, opts }) => style::run(sheet, input.as_deref(), &opts),
        Some(Command::Inspect { bundle, format, at }) => inspect::run(&bundle, format, at),
        Some(Command::Pack { dir, out }) => pack::run(&dir, &out),
        Some(Command::Unpack { bundle, out }) => unpack::run(&bundle, &out),
        Some(Command::Export { bundle, format, out }) => export::run(&bundle, format, &out),
        Some(Command::Preview { input, out, opts }) => preview::run(&input, &out, &opts),
        Some(Command::Play { bundle, trace, out, elements }) => {
            play::run(&bundle, trace.as_deref(), out.as_deref(), elements.as_deref())
        }
        Some(Command::Report { input, opts, plot, default_only, format }) => {
            report::run(&input, &opts, plot.as_deref(), default_only, format)
        }
        Some(Command::Load { bundles, device }) => load::run(&bundles, &device),
        Some(Command::Device(DeviceCommand::Serve { store, listen, capacity, profile })) => {
            device::serve(&store, &listen, capacity, profile.as_deref())
        }
        Some(Command::Device(DeviceCommand::Ls { device })) => device::ls(&device),
        Some(Command::Device(DeviceCommand::Rm { name, device })) => device::rm(&name, &device),
        Some(Command::Profiles) => profiles::run(),
        Some(Command::Inkscape(InkscapeCommand::Install { dir })) => inkscape::install(dir.as_deref()),
        Some(Command::Inkscape(InkscapeCommand::Uninstall { dir })) => inkscape::uninstall(dir.as_deref()),
        Some(Command::Studio { path, port, no_open, listen, opts }) => {
            crate::studio::run(crate::studio::StudioArgs { path, port, no_open, listen, opts })
        }
    }
}

/// A problem with a text-form folder or bundle: exit 1 when the input is
/// wrong, 2 when the file system failed or the command would overwrite data.
fn text_error(e: crate::textform::TextError) -> CliError {
    if e.io { CliError::trouble(e) } else { CliError::input(e) }
}
