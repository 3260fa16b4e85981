//! Reading inputs with a size limit: a file too large is refused from its
//! metadata, before it is read.

use std::path::Path;

use anyhow::{Context, Result, bail};

/// Largest drawing, mesh, trace, style sheet or profile taxel reads, in
/// bytes (docs/stability.md): far above any drawing a person makes, far below
/// what would exhaust memory once usvg's tree and the masks are built from it.
pub const MAX_INPUT_BYTES: u64 = 64 << 20;

fn check_size(path: &Path, limit: u64) -> Result<()> {
    let len = std::fs::metadata(path).with_context(|| format!("cannot read {}", path.display()))?.len();
    if len > limit {
        bail!(
            "{}: the file is {:.1} MB, larger than the {} MB input limit; split the drawing or remove embedded images",
            path.display(),
            len as f64 / (1 << 20) as f64,
            limit >> 20
        );
    }
    Ok(())
}

/// Reads an input (drawing, mesh, buffer, trace, style sheet, profile) of at
/// most [`MAX_INPUT_BYTES`].
pub fn read_input(path: &Path) -> Result<Vec<u8>> {
    check_size(path, MAX_INPUT_BYTES)?;
    std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))
}

/// Reads a text input of at most [`MAX_INPUT_BYTES`] that must be UTF-8.
pub fn read_input_text(path: &Path) -> Result<String> {
    String::from_utf8(read_input(path)?).map_err(|_| anyhow::anyhow!("{}: the file is not UTF-8 text", path.display()))
}

/// The two bytes every gzip stream starts with (RFC 1952).
const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];

/// Whether `bytes` are gzip-compressed (a `.svgz` drawing).
pub fn is_gzip(bytes: &[u8]) -> bool {
    bytes.starts_with(&GZIP_MAGIC)
}

/// A drawing's bytes as SVG text: gzip-compressed ones (`.svgz`, or any
/// drawing that starts with gzip's magic) unpacked first, to at most
/// [`MAX_INPUT_BYTES`] (a small file may unpack to gigabytes), then UTF-8.
pub fn drawing_text(path: &Path, bytes: Vec<u8>) -> Result<String> {
    let bytes = if is_gzip(&bytes) {
        use std::io::Read as _;
        let mut out = Vec::new();
        flate2::read::MultiGzDecoder::new(&bytes[..])
            .take(MAX_INPUT_BYTES + 1)
            .read_to_end(&mut out)
            .with_context(|| format!("{}: the compressed drawing cannot be unpacked", path.display()))?;
        if out.len() as u64 > MAX_INPUT_BYTES {
            bail!(
                "{}: the compressed drawing unpacks to more than the {} MB input limit; split the drawing",
                path.display(),
                MAX_INPUT_BYTES >> 20
            );
        }
        out
    } else {
        bytes
    };
    String::from_utf8(bytes)
        .map_err(|_| anyhow::anyhow!("{}: the file is not UTF-8 text, expected an SVG document", path.display()))
}

/// Reads a drawing (`.svg` or `.svgz`) as SVG text, through [`read_input`] and [`drawing_text`].
pub fn read_drawing(path: &Path) -> Result<String> {
    drawing_text(path, read_input(path)?)
}

/// Reads a bundle of at most the format's own limit
/// ([`taxel_format::MAX_FILE_LEN`]); the reader checks everything else.
pub fn read_bundle(path: &Path) -> Result<Vec<u8>> {
    check_size(path, taxel_format::MAX_FILE_LEN)?;
    std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_within_the_limit_and_names_missing_files() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.svg");
        std::fs::write(&p, "<svg/>").unwrap();
        assert_eq!(read_input_text(&p).unwrap(), "<svg/>");
        let missing = dir.path().join("nope.svg");
        let e = read_input(&missing).unwrap_err();
        assert!(format!("{e:#}").starts_with(&format!("cannot read {}", missing.display())), "{e:#}");
        std::fs::write(&p, [0xff, 0xfe]).unwrap();
        assert!(format!("{:#}", read_input_text(&p).unwrap_err()).contains("not UTF-8"));
    }

    fn gzip(data: &[u8]) -> Vec<u8> {
        use std::io::Write as _;
        let mut z = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        z.write_all(data).unwrap();
        z.finish().unwrap()
    }

    #[test]
    fn compressed_drawings_are_unpacked_within_the_limit() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.svgz");
        std::fs::write(&p, gzip(b"<svg/>")).unwrap();
        assert_eq!(read_drawing(&p).unwrap(), "<svg/>");
        // A plain drawing is read as it is, whatever its name.
        std::fs::write(&p, "<svg/>").unwrap();
        assert_eq!(read_drawing(&p).unwrap(), "<svg/>");
        // A few hundred kilobytes that unpack past the limit are refused, not unpacked.
        let bomb = gzip(&vec![b' '; MAX_INPUT_BYTES as usize + 1]);
        assert!((bomb.len() as u64) < MAX_INPUT_BYTES / 100);
        let e = format!("{:#}", drawing_text(&p, bomb).unwrap_err());
        assert!(e.contains("unpacks to more than the 64 MB input limit"), "{e}");
        // A damaged stream says so.
        let mut cut = gzip(b"<svg>long enough to be cut</svg>");
        cut.truncate(cut.len() - 12);
        let e = format!("{:#}", drawing_text(&p, cut).unwrap_err());
        assert!(e.contains("cannot be unpacked"), "{e}");
    }

    #[test]
    fn a_file_over_the_limit_is_refused_unread() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("big.svg");
        // A sparse file: the limit is checked on its length, not its contents.
        std::fs::File::create(&p).unwrap().set_len(MAX_INPUT_BYTES + 1).unwrap();
        let e = format!("{:#}", read_input(&p).unwrap_err());
        assert!(e.contains("larger than the 64 MB input limit"), "{e}");
        assert!(read_bundle(&p).is_ok(), "bundles have the format's own limit");
    }
}
