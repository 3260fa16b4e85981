//! End-to-end tests of the `taxel` command line, one module per area.

mod batch;
mod braille;
mod brush;
mod compile;
mod device;
mod examples;
mod finger;
mod finger_size;
mod format;
mod inkscape;
mod key;
mod lookup;
mod outputs;
mod pins;
mod play;
mod played;
mod print;
mod real;
mod report;
mod runaway;
mod stability;
mod studio;
mod studio_wasm;

/// The plain bundle of a bundle file's bytes: a stored (compressed) file,
/// as `taxel build` writes it (SPEC.md 15), inflated; a plain one as it is.
fn plain(bytes: Vec<u8>) -> Vec<u8> {
    taxel_format::stored::plain(&bytes).expect("a bundle file inflates").into_owned()
}

/// The PNG file at `path`, decoded.
fn read_png(path: impl AsRef<std::path::Path>) -> taxel_textform::png::Image {
    let path = path.as_ref();
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    taxel_textform::png::read(&bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The plain bundle of the bundle file at `path`.
fn read_plain(path: impl AsRef<std::path::Path>) -> Vec<u8> {
    let path = path.as_ref();
    plain(std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())))
}
