//! Building many inputs at once: discovery of inputs in folders, where each
//! bundle goes, sharding, the incremental check, parallel compilation, safe
//! writes, progress and the summary. `taxel build` is a thin layer over this.
//!
//! A failing input is reported with its diagnostics and the batch goes on;
//! nothing is ever written for it. Every bundle is written to a temporary
//! file and renamed into place ([`crate::io::write_file`]), so an interrupted
//! batch leaves each output either as it was or complete.

pub mod discover;
pub mod hash;
pub mod output;
pub mod progress;
pub mod shard;

use std::collections::HashMap;
use std::io::Write;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

use anyhow::{Result, bail};
use rayon::prelude::*;
use taxel_compiler::print::FileKind;
use taxel_compiler::{Compiled, Diagnostic, Severity};

use crate::account::NoteTally;
use crate::cli::CompileOpts;
pub use discover::{Input, discover, discover_all};
pub use progress::{Outcome, Reporter, Summary};
pub use shard::Shard;

/// Compiles one file from its bytes, read once by the builder (the real one
/// is [`crate::compile::compile_bytes`]).
pub type CompileFn = dyn Fn(&Path, Vec<u8>, &CompileOpts) -> Result<Compiled> + Sync;

/// What a build writes for each input: a bundle, or a print medium's file
/// (`--profile swell-a4` and the like; the kind follows `-o`'s extension).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Output {
    /// A `.taxel` bundle.
    #[default]
    Bundle,
    /// A print medium's file.
    Print(FileKind),
}

impl Output {
    /// The extension of what is written.
    pub fn extension(self) -> &'static str {
        match self {
            Output::Bundle => "taxel",
            Output::Print(k) => k.extension(),
        }
    }

    /// What a build for `profile` writes when `-o` is `out`: for a print
    /// profile, the kind `out`'s extension names, else the medium's usual
    /// one; an extension the medium is not written as is refused.
    pub fn for_profile(profile: &taxel_format::DeviceProfile, out: Option<&Path>) -> Result<Output> {
        let ext = out.and_then(|o| o.extension()).and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        let taxel_format::FamilyParams::Print(p) = profile.params else {
            if let Some(k) =
                ext.as_deref().and_then(FileKind::from_extension).filter(|_| out.is_some_and(|o| !o.is_dir()))
            {
                bail!(
                    "-o {}: .{} files come from print profiles (swell-a4, swell-letter, tiger-20dpi, \
                     emboss-braille-grid, print3d), and {} makes bundles (.taxel)",
                    out.map(|o| o.display().to_string()).unwrap_or_default(),
                    k.extension(),
                    profile.name
                );
            }
            return Ok(Output::Bundle);
        };
        let kinds = FileKind::for_medium(p.medium);
        let named = ext.as_deref().filter(|_| out.is_some_and(|o| !o.is_dir()));
        match named.map(|e| (e, FileKind::from_extension(e))) {
            Some((_, Some(k))) if kinds.contains(&k) => Ok(Output::Print(k)),
            Some((e, _)) if e == "taxel" || FileKind::from_extension(e).is_some() => bail!(
                "-o {}: {} ({} medium) writes .{}, not .{e}",
                out.map(|o| o.display().to_string()).unwrap_or_default(),
                profile.name,
                p.medium.name(),
                kinds.iter().map(|k| k.extension()).collect::<Vec<_>>().join(" or .")
            ),
            _ => Ok(Output::Print(kinds[0])),
        }
    }
}

/// Where the bundles go.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Destination {
    /// Beside each input, with the `.taxel` extension.
    NextToInputs,
    /// Under a folder, mirroring the inputs' relative paths.
    Folder(PathBuf),
    /// One named bundle for the one input.
    File(PathBuf),
}

impl Destination {
    /// `-o OUT` for these inputs: a path ending in `.taxel` that is not an
    /// existing folder names one bundle (and needs exactly one input);
    /// anything else is a folder.
    /// For a print profile (`output`), `-o` names one file when it ends in
    /// that output's extension.
    pub fn choose(out: Option<&Path>, inputs_found: usize, output: Output) -> Result<Destination> {
        let Some(out) = out else { return Ok(Destination::NextToInputs) };
        let named_bundle = out.extension().is_some_and(|e| e.eq_ignore_ascii_case(output.extension())) && !out.is_dir();
        if !named_bundle {
            return Ok(Destination::Folder(out.to_path_buf()));
        }
        if inputs_found != 1 {
            bail!(
                "-o {}: names one bundle, but {inputs_found} inputs were found; give a folder to mirror the inputs under",
                out.display()
            );
        }
        Ok(Destination::File(out.to_path_buf()))
    }

    /// Where the output of `input` goes, with extension `ext` unless `-o` named the file.
    pub fn output_with(&self, input: &Input, ext: &str) -> PathBuf {
        match self {
            Destination::NextToInputs => input.path.with_extension(ext),
            Destination::Folder(dir) => dir.join(&input.rel).with_extension(ext),
            Destination::File(f) => f.clone(),
        }
    }
}

/// One input and its bundle.
#[derive(Debug, Clone)]
pub struct Job {
    /// The input.
    pub input: Input,
    /// Its bundle.
    pub output: PathBuf,
    /// Why it must not be built (another input would write the same bundle).
    pub conflict: Option<String>,
}

/// The jobs for `inputs`. Inputs that would write the same bundle (`a.svg`
/// and `a.gltf` in one folder) are all refused rather than one silently
/// overwriting another.
pub fn plan(inputs: Vec<Input>, dest: &Destination, output: Output) -> Vec<Job> {
    let ext = output.extension();
    let mut jobs: Vec<Job> =
        inputs.into_iter().map(|input| Job { output: dest.output_with(&input, ext), input, conflict: None }).collect();
    // A bundle's key may be written beside it (`a.key.taxel`, then
    // `a.key2.taxel` ...): an input whose bundle would be another's key
    // (`a.key.svg` or `a.key2.svg` beside `a.svg`) is refused too.
    let mut by_output: HashMap<PathBuf, Vec<usize>> = HashMap::new();
    for (i, j) in jobs.iter().enumerate() {
        by_output.entry(j.output.clone()).or_default().push(i);
        if output == Output::Bundle {
            for page in 1..=taxel_compiler::latero::key::MAX_PAGES {
                by_output.entry(output::key_page_path(&j.output, page)).or_default().push(i);
            }
        }
    }
    let mut shared: Vec<(&PathBuf, &Vec<usize>)> = by_output.iter().filter(|(_, v)| v.len() > 1).collect();
    shared.sort();
    for (path, same) in shared {
        let names: Vec<String> = same.iter().map(|&i| jobs[i].input.path.display().to_string()).collect();
        for &i in same {
            if jobs[i].conflict.is_none() {
                jobs[i].conflict =
                    Some(format!("{} would all write {}; rename one of them", names.join(", "), path.display()));
            }
        }
    }
    jobs
}

/// How to build.
#[derive(Debug, Clone)]
pub struct Settings {
    /// Compiler options from the command line.
    pub opts: CompileOpts,
    /// Rebuild even when the bundle is up to date.
    pub force: bool,
    /// Parallel jobs; `None` for all cores.
    pub jobs: Option<usize>,
    /// Show a progress bar (on a terminal) rather than plain lines.
    pub terminal: bool,
    /// List every diagnostic instead of one line per rule (`-v`).
    pub verbose: bool,
    /// What is written for each input.
    pub output: Output,
}

/// Builds every job in parallel; `problems` (unreadable folder entries) are
/// reported as failures. Returns the summary; IO failures of single inputs
/// are failures in it, not errors.
pub fn run(jobs: &[Job], problems: &[String], settings: &Settings, compile: &CompileFn) -> Result<Summary> {
    let started = Instant::now();
    let reporter = Reporter::new(jobs.len() + problems.len(), settings.terminal);
    for p in problems {
        reporter.report(&Outcome::Failed, &format!("failed {p}"), &[format!("error: {p}")]);
    }
    // Several inputs: the notes of those built are counted for the whole
    // batch and given once at the end (`-v` keeps every one with its input).
    let notes = (jobs.len() + problems.len() > 1 && !settings.verbose).then(|| Mutex::new(NoteTally::default()));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(settings.jobs.unwrap_or(0))
        .stack_size(crate::WORKER_STACK)
        .build()?;
    pool.install(|| {
        jobs.par_iter().enumerate().for_each(|(at, job)| {
            let (outcome, line, messages) = build_one(job, settings, compile, notes.as_ref().map(|n| (n, at)));
            reporter.report(&outcome, &line, &messages);
        })
    });
    let counts = reporter.finish();
    if let Some(notes) = notes {
        let mut err = std::io::stderr().lock();
        for l in notes.into_inner().unwrap_or_else(|p| p.into_inner()).lines() {
            let _ = writeln!(err, "{l}");
        }
    }
    Ok(Summary { counts, elapsed: started.elapsed(), peak: crate::peak_held() })
}

/// Builds one job: `(outcome, plain line, diagnostics)`. With `notes`, the
/// notes of a built input are counted there instead of listed with it.
fn build_one(
    job: &Job,
    settings: &Settings,
    compile: &CompileFn,
    notes: Option<(&Mutex<NoteTally>, usize)>,
) -> (Outcome, String, Vec<String>) {
    let shown = job.input.path.display().to_string();
    let out = job.output.display();
    let failed = |message: String| (Outcome::Failed, format!("failed {shown}"), vec![format!("error: {message}")]);
    if let Some(c) = &job.conflict {
        return failed(format!("{shown}: {c}"));
    }
    // Refuse an oversized input before reading it whole; it is read once, for the content hash and the compiler.
    // A drawing's fonts are loaded on the other core while it is read and
    // parsed (the system's took about 5 ms, with one core in use).
    crate::compile::warm_up_fonts(&job.input.path, &settings.opts);
    let bytes = match crate::io::read_input(&job.input.path) {
        Ok(b) => b,
        Err(e) => return failed(format!("{e:#}")),
    };
    // When the bundle is rebuilt anyway (forced, or none yet), the hash is
    // finished after the build with the font faces the build laid the text
    // out with, rather than parsing the drawing a second time for them.
    let part = hash::Partial::begin(&job.input.path, &bytes);
    // A print file records no content hash: it is always made anew.
    let checked = if settings.force || !job.output.is_file() || settings.output != Output::Bundle {
        None
    } else {
        let hash = match part.fonts_by_parsing(&bytes, &settings.opts) {
            Ok(fonts) => part.finish(&fonts, &settings.opts),
            Err(e) => Err(e),
        };
        match hash {
            Ok(h) if output::complete(&job.output, &h) => {
                return (Outcome::Skipped, format!("skipped {shown} ({out} is up to date)"), Vec::new());
            }
            Ok(h) => Some(h),
            Err(e) => return failed(format!("{shown}: {e:#}")),
        }
    };
    // A panic in the compiler is a bug, but it must cost one input, not the batch.
    let compiled = match catch_unwind(AssertUnwindSafe(|| compile(&job.input.path, bytes, &settings.opts))) {
        Ok(Ok(c)) => c,
        Ok(Err(e)) => return failed(format!("{e:#}")),
        Err(_) => {
            let d = Diagnostic::error("T0900", "internal error: the compiler panicked on this input")
                .with_help("please report it with the input attached; the other inputs are built");
            return (Outcome::Failed, format!("failed {shown}"), vec![d.render(&shown)]);
        }
    };
    let Compiled { bundle, mut diagnostics, fonts_used, print, key } = compiled;
    let styles = crate::account::style_summary(&diagnostics).map(|s| format!(": {s}")).unwrap_or_default();
    let warnings = diagnostics.iter().filter(|d| d.severity == Severity::Warning).count();
    let errors = diagnostics.iter().filter(|d| d.severity == Severity::Error).count();
    // The account is written while the bundle is encoded and written: on
    // the map at the input limit each took a few tenths of a second, one
    // after the other on one thread, at the end of the build.
    // The key's bundles go beside the graphic's, and the note that says
    // they are bundles of their own says where.
    let key_paths: Vec<PathBuf> = (1..=key.len()).map(|k| output::key_page_path(&job.output, k)).collect();
    if let (Some(first), Some(last)) = (key_paths.first(), key_paths.last())
        && let Some(d) = diagnostics.iter_mut().find(|d| d.code == "T0331")
    {
        d.message += &match key_paths.len() {
            1 => format!(", written to {}", first.display()),
            _ => format!(", written to {} ... {}", first.display(), last.display()),
        };
    }
    // The key is written first, so that a graphic's bundle that says it has
    // a key is never beside a missing or older one (all record the hash);
    // pages an earlier build left past the last are removed.
    let write = |bundle: taxel_format::Bundle| -> Result<(), String> {
        let hash = match checked {
            Some(h) => h,
            None => part.finish(&fonts_used, &settings.opts).map_err(|e| format!("{shown}: {e:#}"))?,
        };
        let encode = |mut b: taxel_format::Bundle| {
            b.manifest.content_hash = hash;
            b.to_stored_bytes()
                .map_err(|e| format!("{shown}: internal error: the compiler made an invalid bundle: {e}"))
        };
        let pages = key.len();
        for (page, path) in key.into_iter().zip(&key_paths) {
            crate::io::write_file(path, &encode(page)?).map_err(|e| e.to_string())?;
        }
        output::remove_stale_key(&job.output, pages + 1).map_err(|e| e.to_string())?;
        crate::io::write_file(&job.output, &encode(bundle)?).map_err(|e| e.to_string())
    };
    // A print sheet is written as the file its output names.
    let write_print = |sheet: taxel_compiler::print::Sheet| -> Result<(), String> {
        let Output::Print(kind) = settings.output else {
            return Err(format!("{shown}: internal error: a print sheet for a bundle"));
        };
        let bytes = taxel_compiler::print::write(&sheet, kind).map_err(|e| format!("{shown}: {e}"))?;
        crate::io::write_file(&job.output, &bytes).map_err(|e| e.to_string())
    };
    let (written, messages) = rayon::join(
        || match print {
            Some(sheet) if errors == 0 => Some(write_print(sheet)),
            _ => bundle.filter(|_| errors == 0).map(write),
        },
        || crate::account::lines(&diagnostics, &shown, Severity::Note, settings.verbose),
    );
    match written {
        None => {
            let why = if errors == 0 { "no bundle".to_string() } else { plural(errors, "error") };
            return (Outcome::Failed, format!("failed {shown} ({why})"), messages);
        }
        Some(Err(e)) => return failed(e),
        Some(Ok(())) => {}
    }
    let messages = match notes {
        Some((tally, at)) => {
            tally.lock().unwrap_or_else(|p| p.into_inner()).add(&diagnostics, &shown, at);
            crate::account::lines(&diagnostics, &shown, Severity::Warning, settings.verbose)
        }
        None => messages,
    };
    let line = match warnings {
        0 => format!("built {shown} -> {out}{styles}"),
        n => format!("built {shown} -> {out} ({}){styles}", plural(n, "warning")),
    };
    (Outcome::Built { warnings }, line, messages)
}

fn plural(n: usize, what: &str) -> String {
    if n == 1 { format!("1 {what}") } else { format!("{n} {what}s") }
}

#[cfg(test)]
mod tests {
    use super::progress::Counts;
    use super::*;
    use taxel_format::{Bundle, Manifest, profiles};

    /// Stands in for the compiler in these unit tests (the command-line
    /// tests use the real one): "good" builds, "warn" builds with a warning,
    /// "bad" fails, "panic" panics.
    fn fake(_: &Path, bytes: Vec<u8>, _: &CompileOpts) -> Result<Compiled> {
        let text = String::from_utf8(bytes)?;
        let bundle = Some(Bundle::new(Manifest::new(profiles::builtin("stress2").unwrap())));
        Ok(match text.trim() {
            "good" => Compiled { bundle, diagnostics: vec![], fonts_used: vec![], print: None, key: Vec::new() },
            "warn" => Compiled {
                bundle,
                diagnostics: vec![Diagnostic::warning("T9", "thin").at(1, 1)],
                fonts_used: vec![],
                print: None,
                key: Vec::new(),
            },
            "panic" => panic!("fake compiler panic"),
            _ => Compiled {
                bundle: None,
                diagnostics: vec![Diagnostic::error("T8", "broken").at(2, 3)],
                fonts_used: vec![],
                print: None,
                key: Vec::new(),
            },
        })
    }

    fn settings(force: bool) -> Settings {
        Settings {
            opts: CompileOpts::default(),
            force,
            jobs: Some(2),
            terminal: false,
            verbose: false,
            output: Output::Bundle,
        }
    }

    #[test]
    fn good_warning_bad_and_panicking_inputs_then_an_incremental_run() {
        let dir = tempfile::tempdir().unwrap();
        let src = dir.path().join("src");
        for (f, t) in [("a.svg", "good"), ("sub/b.svg", "warn"), ("c.svg", "bad"), ("d.svg", "panic")] {
            let p = src.join(f);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, t).unwrap();
        }
        let out = dir.path().join("out");
        let (inputs, problems) = discover(std::slice::from_ref(&src)).unwrap();
        let jobs = plan(inputs, &Destination::Folder(out.clone()), Output::Bundle);
        let s = run(&jobs, &problems, &settings(false), &fake).unwrap();
        assert_eq!(s.counts, Counts { built: 2, warned: 1, skipped: 0, failed: 2 });
        assert!(out.join("a.taxel").is_file() && out.join("sub/b.taxel").is_file());
        assert!(!out.join("c.taxel").exists() && !out.join("d.taxel").exists());
        let again = run(&jobs, &problems, &settings(false), &fake).unwrap();
        assert_eq!(again.counts, Counts { built: 0, warned: 0, skipped: 2, failed: 2 });
        let forced = run(&jobs, &problems, &settings(true), &fake).unwrap();
        assert_eq!(forced.counts.built, 2);
    }

    #[test]
    fn a_panicking_compiler_costs_one_input_and_reports_t0900() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("d.svg");
        std::fs::write(&p, "panic").unwrap();
        let (inputs, _) = discover(&[dir.path().to_path_buf()]).unwrap();
        let jobs = plan(inputs, &Destination::Folder(dir.path().join("out")), Output::Bundle);
        let (outcome, _, messages) = build_one(&jobs[0], &settings(true), &fake, None);
        assert_eq!(outcome, Outcome::Failed);
        assert_eq!(messages.len(), 1);
        assert!(messages[0].starts_with(&format!("{}: error[T0900]: internal error", p.display())), "{messages:?}");
    }

    #[test]
    fn inputs_writing_the_same_bundle_are_all_refused() {
        let dir = tempfile::tempdir().unwrap();
        for f in ["a.svg", "a.gltf", "b.svg"] {
            std::fs::write(dir.path().join(f), "good").unwrap();
        }
        let (inputs, _) = discover(&[dir.path().to_path_buf()]).unwrap();
        let jobs = plan(inputs, &Destination::NextToInputs, Output::Bundle);
        let refused: Vec<_> = jobs.iter().filter(|j| j.conflict.is_some()).map(|j| j.input.key()).collect();
        assert_eq!(refused, ["a.gltf", "a.svg"]);
    }

    #[test]
    fn a_named_bundle_needs_exactly_one_input() {
        let f = Path::new("x.taxel");
        assert_eq!(Destination::choose(Some(f), 1, Output::Bundle).unwrap(), Destination::File(f.into()));
        assert!(Destination::choose(Some(f), 2, Output::Bundle).is_err());
        assert_eq!(
            Destination::choose(Some(Path::new("out")), 2, Output::Bundle).unwrap(),
            Destination::Folder("out".into())
        );
        assert_eq!(Destination::choose(None, 3, Output::Bundle).unwrap(), Destination::NextToInputs);
    }
}
