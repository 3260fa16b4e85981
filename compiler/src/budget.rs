//! The memory a compilation may take (`taxel build --max-memory`).
//!
//! The library allocates through whatever allocator its program chose, so
//! it cannot count its own bytes: the program that counts them (the `taxel`
//! binary wraps its allocator in a counter) hands in a [`MemoryBudget`]
//! with a function that reads the count. The stages whose work grows with
//! the geometry look at it between pieces of work (the distance fields,
//! tile by tile) and stop with [`OverBudget`], which the pipeline turns
//! into an error that names the elements (T0308), before the memory is
//! gone rather than after.

/// How much memory the process may hold while compiling.
#[derive(Debug, Clone, Copy)]
pub struct MemoryBudget {
    /// The bytes the process holds now (allocated and not yet freed).
    pub in_use: fn() -> usize,
    /// The most it may hold, bytes.
    pub limit: usize,
}

impl MemoryBudget {
    /// Whether the process holds more than the budget allows.
    pub fn exceeded(&self) -> bool {
        (self.in_use)() > self.limit
    }
}

/// A stage stopped because the budget was exceeded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OverBudget;

/// The code of the error a stage stopped by the budget gives.
pub const OVER_BUDGET: &str = "T0308";

/// What to do when the budget stops a build.
pub const OVER_BUDGET_HELP: &str = "simplify the drawing's largest shapes (Inkscape: Path > Simplify), \
     take part of it with --region, or raise the limit with --max-memory";

/// The error for a build that `budget` stopped after `stage` (such as
/// "reading the drawing"), or `None` while within it.
pub fn check(budget: Option<&MemoryBudget>, stage: &str) -> Option<crate::Diagnostic> {
    let b = budget.filter(|b| b.exceeded())?;
    Some(
        crate::Diagnostic::error(
            OVER_BUDGET,
            format!("{stage} took more memory than the limit of {}: stopped", human_bytes(b.limit)),
        )
        .with_help(OVER_BUDGET_HELP),
    )
}

/// `bytes` for a person: `1.5 GB`, `512 MB`.
pub fn human_bytes(bytes: usize) -> String {
    const MB: f64 = (1u64 << 20) as f64;
    let mb = bytes as f64 / MB;
    match mb {
        m if m >= 1024.0 => format!("{:.1} GB", m / 1024.0),
        m if m >= 1.0 => format!("{m:.0} MB"),
        m => format!("{:.0} KB", m * 1024.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_budget_is_exceeded_only_past_its_limit() {
        fn held() -> usize {
            1000
        }
        assert!(!MemoryBudget { in_use: held, limit: 1000 }.exceeded());
        assert!(MemoryBudget { in_use: held, limit: 999 }.exceeded());
        assert_eq!(human_bytes(512 << 20), "512 MB");
        assert_eq!(human_bytes(3 << 29), "1.5 GB");
        assert_eq!(human_bytes(1024), "1 KB");
        assert!(check(Some(&MemoryBudget { in_use: held, limit: 1000 }), "reading").is_none());
        let d = check(Some(&MemoryBudget { in_use: held, limit: 10 }), "reading the drawing").expect("stopped");
        assert_eq!(d.code, OVER_BUDGET);
        assert!(d.message.starts_with("reading the drawing took more memory"), "{}", d.message);
        assert!(check(None, "reading").is_none());
    }
}
