//! What a batch shows while it runs and at the end: a progress bar on a
//! terminal, one plain line per input when the output is piped, every
//! diagnostic with its file name, and a summary.

use std::fmt;
use std::io::Write;
use std::sync::Mutex;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// How one input ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Outcome {
    /// The bundle was written; `warnings` diagnostics were warnings.
    Built {
        /// Number of warnings.
        warnings: usize,
    },
    /// The existing bundle is up to date.
    Skipped,
    /// Nothing was written.
    Failed,
}

/// Counts of outcomes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counts {
    /// Bundles written (with or without warnings).
    pub built: usize,
    /// Of those, bundles written with warnings.
    pub warned: usize,
    /// Inputs skipped as up to date.
    pub skipped: usize,
    /// Inputs that failed.
    pub failed: usize,
}

impl Counts {
    /// Inputs accounted for.
    pub fn total(&self) -> usize {
        self.built + self.skipped + self.failed
    }
}

/// The end-of-batch summary.
#[derive(Debug, Clone, Copy)]
pub struct Summary {
    /// The counts.
    pub counts: Counts,
    /// Wall-clock time of the whole batch.
    pub elapsed: Duration,
    /// The most memory the process held meanwhile, bytes (as its allocator
    /// counts it; 0: not known, not said).
    pub peak: usize,
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let c = &self.counts;
        write!(
            f,
            "built {}, with warnings {}, failed {}, skipped {} (up to date); {} inputs in {:.2} s",
            c.built,
            c.warned,
            c.failed,
            c.skipped,
            c.total(),
            self.elapsed.as_secs_f64()
        )?;
        if self.peak > 0 {
            write!(f, ", peak memory {}", taxel_compiler::budget::human_bytes(self.peak))?;
        }
        Ok(())
    }
}

/// Reports outcomes as they come, from any thread.
pub struct Reporter {
    bar: Option<ProgressBar>,
    counts: Mutex<Counts>,
}

impl Reporter {
    /// A reporter for `total` inputs: a progress bar when `terminal`, plain lines otherwise.
    pub fn new(total: usize, terminal: bool) -> Reporter {
        let bar = terminal.then(|| {
            let bar = ProgressBar::with_draw_target(Some(total as u64), ProgressDrawTarget::stderr());
            let style = ProgressStyle::with_template("{bar:40} {pos}/{len} {elapsed_precise} eta {eta} {wide_msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar());
            bar.set_style(style);
            bar
        });
        Reporter { bar, counts: Mutex::new(Counts::default()) }
    }

    /// Records one input's outcome; `line` is the plain line for it and
    /// `messages` its diagnostics, printed together so that parallel
    /// inputs never interleave.
    pub fn report(&self, outcome: &Outcome, line: &str, messages: &[String]) {
        let mut counts = self.counts.lock().unwrap_or_else(|p| p.into_inner());
        match outcome {
            Outcome::Built { warnings } => {
                counts.built += 1;
                counts.warned += usize::from(*warnings > 0);
            }
            Outcome::Skipped => counts.skipped += 1,
            Outcome::Failed => counts.failed += 1,
        }
        // Printing under the lock keeps each input's block whole.
        match &self.bar {
            Some(bar) => {
                for m in messages {
                    bar.println(m);
                }
                if *outcome == Outcome::Failed {
                    bar.println(line);
                }
                bar.set_message(line.to_string());
                bar.inc(1);
            }
            None => {
                let mut err = std::io::stderr().lock();
                for m in messages {
                    let _ = writeln!(err, "{m}");
                }
                let _ = writeln!(std::io::stdout().lock(), "{line}");
            }
        }
    }

    /// Ends the progress bar and returns the counts.
    pub fn finish(self) -> Counts {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
        self.counts.into_inner().unwrap_or_else(|p| p.into_inner())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_each_outcome() {
        let r = Reporter::new(4, false);
        r.report(&Outcome::Built { warnings: 0 }, "built a", &[]);
        r.report(&Outcome::Built { warnings: 2 }, "built b", &[]);
        r.report(&Outcome::Skipped, "skipped c", &[]);
        r.report(&Outcome::Failed, "failed d", &[]);
        assert_eq!(r.finish(), Counts { built: 2, warned: 1, skipped: 1, failed: 1 });
    }

    #[test]
    fn the_summary_names_every_count() {
        let s = Summary {
            counts: Counts { built: 3, warned: 1, skipped: 2, failed: 4 },
            elapsed: Duration::from_millis(1500),
            peak: 0,
        };
        assert_eq!(s.to_string(), "built 3, with warnings 1, failed 4, skipped 2 (up to date); 9 inputs in 1.50 s");
        let s = Summary { peak: 300 << 20, ..s };
        assert!(s.to_string().ends_with("9 inputs in 1.50 s, peak memory 300 MB"), "{s}");
    }
}
