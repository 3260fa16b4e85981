//! The text form's one error: which file, which line when known, and what
//! was expected, so that a hand-edited folder's mistakes are easy to find.

use std::fmt;

/// A problem in an unpacked folder (or in writing one).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TextError {
    /// The file, relative to the folder (or the folder itself).
    pub file: String,
    /// 1-based line in the file, when known.
    pub line: Option<usize>,
    /// What was wrong and what was expected.
    pub message: String,
    /// Whether this is a file-system failure (cannot read, cannot write,
    /// would overwrite) rather than a problem in the contents.
    pub io: bool,
}

impl TextError {
    /// An error about `file` as a whole.
    pub fn new(file: impl Into<String>, message: impl Into<String>) -> Self {
        TextError { file: file.into(), line: None, message: message.into(), io: false }
    }

    /// A file-system failure about `file`.
    pub fn io(file: impl Into<String>, message: impl Into<String>) -> Self {
        TextError { io: true, ..TextError::new(file, message) }
    }

    /// An error at `line` of `file`.
    pub fn at(file: impl Into<String>, line: usize, message: impl Into<String>) -> Self {
        TextError { file: file.into(), line: Some(line), message: message.into(), io: false }
    }
}

impl fmt::Display for TextError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(l) => write!(f, "{}:{}: {}", self.file, l, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl std::error::Error for TextError {}
