//! `taxel`: the command-line program. Glue only: it parses arguments, reads
//! and writes files, and calls the compiler, the format and the runtime.

use std::process::ExitCode;

use clap::Parser;

mod account;
mod batch;
mod cli;
mod cmd;
mod compile;
mod demo;
mod error;
mod examples;
mod io;
mod playback;
mod report;
mod textform;

/// The one place that turns an outcome into an exit code and prints the error.
fn main() -> ExitCode {
    let args = cli::Cli::parse();
    match cmd::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if e.is_stdout_closed() => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
