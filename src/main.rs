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
mod studio;
mod textform;

/// mimalloc rather than the system allocator: a build allocates and frees
/// millions of small vectors on two threads. On the map at the input limit
/// it took the build from 8.6 to 7.0 s (medians of seven alternated runs)
/// for a fifth more peak memory; a 1 MB map is unchanged (docs/performance.md).
/// Without transparent huge pages (`no_thp`), whose 2 MB pages cost system
/// time and memory on every build.
///
/// Counted (`cap`, with no limit of its own: an allocation that failed
/// would abort), so that `--max-memory` can stop a build before the
/// memory is gone ([`held`]).
#[global_allocator]
static ALLOCATOR: cap::Cap<mimalloc::MiMalloc> = cap::Cap::new(mimalloc::MiMalloc, usize::MAX);

/// The bytes the process holds now (allocated through Rust and not freed).
pub fn held() -> usize {
    ALLOCATOR.allocated()
}

/// The most bytes the process has held at once.
pub fn peak_held() -> usize {
    ALLOCATOR.max_allocated()
}

/// The one place that turns an outcome into an exit code and prints the error.
/// Stack of the threads that compile (the batch's workers and rayon's
/// global pool): usvg's parser recurses once per nested element (in text,
/// deeper frames than in groups), and a drawing may nest 1,024 deep
/// (`taxel_compiler`'s limit) but 700 nested `<tspan>`s overflowed the
/// default 2 MiB. Reserved, not used: pages are touched only as needed.
pub const WORKER_STACK: usize = 32 << 20;

fn main() -> ExitCode {
    // (A pool already built, as in tests that call in twice, keeps its stacks.)
    let _ = rayon::ThreadPoolBuilder::new().stack_size(WORKER_STACK).build_global();
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
