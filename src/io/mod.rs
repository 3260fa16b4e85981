//! The binary's one way to touch files: every command and every output goes
//! through here.
//!
//! - [`write`](mod@write): atomic writes of files and folders with one permission policy
//!   (files 0644 and folders 0755, like any file a person saves), through a
//!   temporary file or folder beside the target, flushed to disk, then
//!   renamed into place. A reader (or an interrupted run) sees the old
//!   output or the whole new one, never a partial file.
//! - [`read`]: inputs read with a size limit, so a huge file is refused
//!   before it is read.
//! - [`load`]: device profiles and style sheets, one function each.
//! - [`png`]: PNG encoding of pictures and masks.
//! - [`stdout`]: standard output that ends the command quietly when its
//!   reader goes away.

pub mod load;
pub mod png;
pub mod read;
pub mod stdout;
pub mod write;

pub use read::{drawing_text, is_gzip, read_bundle, read_bundle_file, read_drawing, read_input, read_input_text};
pub use write::{IoError, write_file, write_folder, write_with};
