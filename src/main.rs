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
mod report;
mod textform;

fn main() -> ExitCode {
    let args = cli::Cli::parse();
    match cmd::run(args) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}
