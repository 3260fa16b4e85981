//! Standard output. `println!` panics when the reader has gone away
//! (`taxel inspect B | head -1`); these return [`CliError::stdout_closed`]
//! instead, which ends the command quietly with success.

use std::io::{self, BufWriter, StdoutLock, Write};

use crate::error::CliError;

/// What a write to standard output failing with `e` means for the command.
pub fn error(e: io::Error) -> CliError {
    if e.kind() == io::ErrorKind::BrokenPipe {
        CliError::stdout_closed()
    } else {
        CliError::trouble(anyhow::Error::new(e).context("cannot write to standard output"))
    }
}

/// Writes `text` to standard output.
pub fn print(text: &str) -> Result<(), CliError> {
    let mut out = io::stdout().lock();
    out.write_all(text.as_bytes()).and_then(|()| out.flush()).map_err(error)
}

/// Streams into standard output through a buffer (frames, CSV).
pub fn stream<T>(fill: impl FnOnce(&mut BufWriter<StdoutLock<'static>>) -> io::Result<T>) -> Result<T, CliError> {
    let mut w = BufWriter::new(io::stdout().lock());
    let value = fill(&mut w).map_err(error)?;
    w.flush().map_err(error)?;
    Ok(value)
}

/// `println!` for commands: `outln!("...")?` ends the command quietly when
/// standard output is closed.
macro_rules! outln {
    () => { $crate::io::stdout::print("\n") };
    ($($arg:tt)*) => { $crate::io::stdout::print(&format!("{}\n", format_args!($($arg)*))) };
}
pub(crate) use outln;
