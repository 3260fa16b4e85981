//! `taxel build INPUT... [-o OUT] [--jobs N] [--shard I/N] [--force]`: one
//! file or thousands, through [`crate::batch`].

use std::io::IsTerminal;
use std::path::PathBuf;

use crate::batch::{self, Destination, Output, Settings, Shard};
use crate::cli::CompileOpts;
use crate::compile::compile_bytes;
use crate::error::{CliError, CmdResult};
use crate::io::stdout::outln;

/// The command line's arguments for `build`.
pub struct BuildArgs {
    /// Files and folders.
    pub inputs: Vec<PathBuf>,
    /// `-o`.
    pub out: Option<PathBuf>,
    /// Compiler options.
    pub opts: CompileOpts,
    /// `--jobs`.
    pub jobs: Option<usize>,
    /// `--shard`.
    pub shard: Option<String>,
    /// `--force`.
    pub force: bool,
    /// `-v`: every diagnostic, not one line per rule.
    pub verbose: bool,
}

pub fn run(args: BuildArgs) -> CmdResult {
    let shard = args.shard.as_deref().map(str::parse::<Shard>).transpose().map_err(anyhow::Error::msg)?;
    if args.jobs == Some(0) {
        return Err(anyhow::anyhow!("--jobs 0: at least one job is needed").into());
    }
    let discovered = batch::discover_all(&args.inputs)?;
    let others = discovered.others_line();
    let (found, problems) = (discovered.inputs, discovered.problems);
    let found_count = found.len();
    // A print profile writes the medium's file (PDF, PNG, STL) instead of a bundle.
    let profile =
        crate::io::load::profile(args.opts.profile.as_deref().unwrap_or(crate::io::load::DEFAULT_DRAWING_PROFILE))?;
    let output = Output::for_profile(&profile, args.out.as_deref())?;
    let dest = Destination::choose(args.out.as_deref(), found_count, output)?;
    let selected: Vec<_> = match shard {
        Some(s) => found.into_iter().filter(|i| s.contains(&i.key())).collect(),
        None => found,
    };
    if found_count == 0 && problems.is_empty() {
        eprintln!(
            "warning: no inputs found in {} (folders are searched for .svg, .svgz, .gltf and .glb)",
            args.inputs.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
        );
    }
    let jobs = batch::plan(selected, &dest, output);
    let settings = Settings {
        opts: args.opts,
        force: args.force,
        jobs: args.jobs,
        terminal: std::io::stderr().is_terminal(),
        verbose: args.verbose,
        output,
    };
    let summary = batch::run(&jobs, &problems, &settings, &compile_bytes)?;
    if let Some(line) = others {
        eprintln!("{line}");
    }
    match shard {
        Some(s) => outln!("shard {s} ({} of {found_count} inputs): {summary}", jobs.len())?,
        None => outln!("{summary}")?,
    }
    match summary.counts.failed {
        0 => Ok(()),
        1 => Err(CliError::input(anyhow::anyhow!("1 input failed"))),
        n => Err(CliError::input(anyhow::anyhow!("{n} inputs failed"))),
    }
}
