//! The binary's one error path: every command returns `Result<(), CliError>`
//! and `main` prints the error once and exits with its code (README.md):
//! 0 success, 1 the input has errors, 2 usage or IO failure.
//!
//! A command that reports many things (the diagnostics of `check`, the
//! refused bundles of `load`) prints them as its output and then returns one
//! error that sums them up. A closed standard output (`taxel inspect B | head
//! -1`) is not an error: the reader has what it wanted, so the command ends
//! quietly with success.

use std::fmt;

/// Why a command stopped, with the exit code it stands for.
#[derive(Debug)]
pub struct CliError {
    kind: Kind,
    error: anyhow::Error,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// The input has errors: exit 1.
    Input,
    /// Usage, IO or device failure: exit 2.
    Trouble,
    /// The reader of standard output went away: exit 0, print nothing.
    StdoutClosed,
}

/// What every command returns.
pub type CmdResult = Result<(), CliError>;

impl CliError {
    /// The input (a drawing, a bundle, a trace, a folder) has errors: exit 1.
    pub fn input(error: impl Into<anyhow::Error>) -> Self {
        CliError { kind: Kind::Input, error: error.into() }
    }

    /// A usage, file-system or device failure: exit 2.
    pub fn trouble(error: impl Into<anyhow::Error>) -> Self {
        CliError { kind: Kind::Trouble, error: error.into() }
    }

    /// Standard output was closed by its reader.
    pub fn stdout_closed() -> Self {
        CliError { kind: Kind::StdoutClosed, error: anyhow::anyhow!("standard output was closed") }
    }

    /// Whether this is a closed standard output (success, nothing to print).
    pub fn is_stdout_closed(&self) -> bool {
        self.kind == Kind::StdoutClosed
    }

    /// The process exit code.
    pub fn exit_code(&self) -> u8 {
        match self.kind {
            Kind::Input => 1,
            Kind::Trouble => 2,
            Kind::StdoutClosed => 0,
        }
    }
}

/// Anything that went wrong without saying otherwise is a usage or IO
/// failure (exit 2); input problems are marked with [`CliError::input`].
impl From<anyhow::Error> for CliError {
    fn from(error: anyhow::Error) -> Self {
        CliError::trouble(error)
    }
}

impl From<std::io::Error> for CliError {
    fn from(error: std::io::Error) -> Self {
        CliError::trouble(error)
    }
}

impl From<crate::io::IoError> for CliError {
    fn from(error: crate::io::IoError) -> Self {
        CliError::trouble(error)
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // `{:#}` prints anyhow's context chain on one line, outermost first.
        write!(f, "{:#}", self.error)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exit_codes_follow_the_readme() {
        assert_eq!(CliError::input(anyhow::anyhow!("bad")).exit_code(), 1);
        assert_eq!(CliError::trouble(anyhow::anyhow!("gone")).exit_code(), 2);
        assert_eq!(CliError::from(anyhow::anyhow!("unmarked")).exit_code(), 2);
        assert_eq!(CliError::stdout_closed().exit_code(), 0);
    }

    #[test]
    fn the_message_carries_the_whole_context_chain() {
        let inner = anyhow::anyhow!("line 3: `x_mm` must be a number").context("a.csv");
        let e = CliError::input(inner);
        assert_eq!(e.exit_code(), 1);
        assert_eq!(e.to_string(), "a.csv: line 3: `x_mm` must be a number");
    }
}
