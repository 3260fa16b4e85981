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
    svg_text(path, bytes)
}

/// SVG bytes as text: UTF-8, or UTF-16 with its byte-order mark, or the
/// encoding the XML declaration names (`encoding="ISO-8859-1"`, as older GIS
/// and Windows tools write), decoded exactly: a byte that is not valid in
/// that encoding is an error, never replaced.
fn svg_text(path: &Path, bytes: Vec<u8>) -> Result<String> {
    let undecodable =
        |name: &str| anyhow::anyhow!("{}: the file is not valid {name} text, expected an SVG document", path.display());
    if let Some((enc, bom)) = encoding_rs::Encoding::for_bom(&bytes)
        && enc != encoding_rs::UTF_8
    {
        return bytes
            .get(bom..)
            .and_then(|b| enc.decode_without_bom_handling_and_without_replacement(b))
            .map(|t| t.into_owned())
            .ok_or_else(|| undecodable(enc.name()));
    }
    let bytes = match String::from_utf8(bytes) {
        Ok(text) => return Ok(text),
        Err(e) => e.into_bytes(),
    };
    match declared_encoding(&bytes) {
        Some(enc) if enc != encoding_rs::UTF_8 => enc
            .decode_without_bom_handling_and_without_replacement(&bytes)
            .map(|t| t.into_owned())
            .ok_or_else(|| undecodable(enc.name())),
        _ => Err(anyhow::anyhow!(
            "{}: the file is not UTF-8 text, and its XML declaration names no other encoding; expected an SVG document",
            path.display()
        )),
    }
}

/// The encoding an XML declaration at the start of `bytes` names
/// (`<?xml version="1.0" encoding="ISO-8859-1"?>`), if it names one
/// encoding_rs knows. (The declaration is ASCII in every encoding it can name
/// without a byte-order mark.)
fn declared_encoding(bytes: &[u8]) -> Option<&'static encoding_rs::Encoding> {
    let head = bytes.get(..bytes.len().min(1024))?;
    let end = head.windows(2).position(|w| w == b"?>")?;
    let decl = head.get(..end)?.strip_prefix(b"<?xml")?;
    let at = decl.windows(8).position(|w| w == b"encoding")?;
    let rest = decl.get(at + 8..)?;
    let rest = rest.get(rest.iter().position(|&b| b == b'=')? + 1..)?;
    let rest = rest.get(rest.iter().position(|&b| b == b'"' || b == b'\'')?..)?;
    let (&quote, rest) = rest.split_first()?;
    let label = rest.get(..rest.iter().position(|&b| b == quote)?)?;
    encoding_rs::Encoding::for_label(label)
}

/// Reads a drawing (`.svg` or `.svgz`) as SVG text, through [`read_input`] and [`drawing_text`].
pub fn read_drawing(path: &Path) -> Result<String> {
    drawing_text(path, read_input(path)?)
}

/// Reads a bundle file as it is, stored (compressed) or plain, of at most
/// the format's own limit ([`taxel_format::MAX_FILE_LEN`]): what goes to a
/// device as it is.
pub fn read_bundle_file(path: &Path) -> Result<Vec<u8>> {
    check_size(path, taxel_format::MAX_FILE_LEN)?;
    std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))
}

/// Reads a bundle file and gives its plain bundle (SPEC.md 15: a stored
/// bundle is inflated), for [`taxel_format::BundleView::parse`], which
/// checks everything else.
pub fn read_bundle(path: &Path) -> Result<Vec<u8>> {
    let bytes = read_bundle_file(path)?;
    match taxel_format::stored::plain(&bytes) {
        Ok(std::borrow::Cow::Owned(plain)) => Ok(plain),
        Ok(std::borrow::Cow::Borrowed(_)) => Ok(bytes),
        Err(e) => anyhow::bail!("{}: not a valid taxel bundle: {e}", path.display()),
    }
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

    /// Drawings in UTF-16 (with its byte-order mark) or in the encoding
    /// their XML declaration names are read, decoded exactly; they were
    /// refused as "not UTF-8". Bytes no encoding explains are still refused,
    /// naming the file.
    #[test]
    fn drawings_in_utf16_or_a_declared_encoding_are_decoded() {
        let p = Path::new("map.svg");
        let svg = "<?xml version=\"1.0\" encoding=\"UTF-16\"?><svg><text>Café Zürich</text></svg>";
        let le: Vec<u8> = [0xff, 0xfe].into_iter().chain(svg.encode_utf16().flat_map(u16::to_le_bytes)).collect();
        let be: Vec<u8> = [0xfe, 0xff].into_iter().chain(svg.encode_utf16().flat_map(u16::to_be_bytes)).collect();
        assert_eq!(drawing_text(p, le).unwrap(), svg);
        assert_eq!(drawing_text(p, be.clone()).unwrap(), svg);
        // Compressed alike.
        assert_eq!(drawing_text(p, gzip(&be)).unwrap(), svg);
        // ISO-8859-1, named in the declaration (either quote): é is one byte, 0xe9.
        for q in ['"', '\''] {
            let head = format!("<?xml version={q}1.0{q} encoding={q}ISO-8859-1{q}?>\n<svg><text>Caf");
            let bytes: Vec<u8> = head.bytes().chain([0xe9]).chain(*b"</text></svg>").collect();
            assert_eq!(drawing_text(p, bytes).unwrap(), format!("{head}é</text></svg>"));
        }
        // UTF-8 with its byte-order mark, as before.
        let bom: Vec<u8> = [0xef, 0xbb, 0xbf].into_iter().chain(*b"<svg/>").collect();
        assert!(drawing_text(p, bom).unwrap().ends_with("<svg/>"));
        // Not UTF-8, and no other encoding named (or UTF-8 named): refused.
        for head in ["<svg><text>Caf", "<?xml version=\"1.0\" encoding=\"UTF-8\"?><svg><text>Caf"] {
            let bytes: Vec<u8> = head.bytes().chain([0xe9]).chain(*b"</text></svg>").collect();
            let e = format!("{:#}", drawing_text(p, bytes).unwrap_err());
            assert!(e.starts_with("map.svg: the file is not UTF-8 text"), "{e}");
        }
        // UTF-16 cut in the middle of a character: refused as such.
        let mut odd: Vec<u8> = [0xff, 0xfe].into_iter().chain(svg.encode_utf16().flat_map(u16::to_le_bytes)).collect();
        odd.extend([0x00, 0xd8]);
        let e = format!("{:#}", drawing_text(p, odd).unwrap_err());
        assert!(e.contains("not valid UTF-16LE text"), "{e}");
    }
}
