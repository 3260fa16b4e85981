//! The content hash recorded in each bundle's manifest: everything the build
//! depended on, so that an incremental build can tell an up-to-date bundle.
//!
//! BLAKE3 over, each length-prefixed: a domain string; the tool and format
//! versions; the input's extension and bytes; for a `.gltf`, the bytes of
//! every relative buffer and image file it names; for a drawing, the font
//! faces its text is laid out with (see [`font_faces`]); the style sheet's
//! bytes; the profile (its name, or its file's bytes); the resolution, width,
//! fit, region, up axis and exaggeration.

use std::path::Path;

use anyhow::{Context, Result};

use taxel_compiler::drawing::FontFace;

use crate::cli::CompileOpts;

struct Hasher(blake3::Hasher);

impl Hasher {
    fn field(&mut self, bytes: &[u8]) -> &mut Self {
        self.0.update(&(bytes.len() as u64).to_le_bytes());
        self.0.update(bytes);
        self
    }
    fn opt(&mut self, bytes: Option<&[u8]>) -> &mut Self {
        match bytes {
            None => self.field(b"-"),
            Some(b) => self.field(b"+").field(b),
        }
    }
}

/// The content hash of building `input` (whose bytes are `bytes`) with
/// `opts`, finding the font faces by laying the drawing's text out (see
/// [`Partial::fonts_by_parsing`]). The batch builder uses [`Partial`]'s
/// steps itself; this is the whole hash at once, for the tests.
#[cfg(test)]
pub fn content_hash(input: &Path, bytes: &[u8], opts: &CompileOpts) -> Result<[u8; 32]> {
    let part = Partial::begin(input, bytes);
    let fonts = part.fonts_by_parsing(bytes, opts)?;
    part.finish(&fonts, opts)
}

/// A drawing's text as the build reads it: borrowed when it is plain, unpacked
/// when it is compressed (`.svgz`); `None` when it is neither.
fn text_of<'a>(input: &Path, bytes: &'a [u8]) -> Option<std::borrow::Cow<'a, str>> {
    if crate::io::is_gzip(bytes) {
        crate::io::drawing_text(input, bytes.to_vec()).ok().map(std::borrow::Cow::Owned)
    } else {
        std::str::from_utf8(bytes).ok().map(std::borrow::Cow::Borrowed)
    }
}

/// A content hash up to the input's own bytes (and a glTF's files), with
/// the rest to come: the font faces, then the options. It lets a build that
/// rebuilds anyway (`--force`, no bundle yet) drop the input's bytes, compile,
/// and finish the hash with the faces the compiler itself laid the text out
/// with ([`taxel_compiler::Compiled::fonts_used`]), instead of parsing the
/// drawing a second time only to find them. Either way the hash is the same.
pub struct Partial {
    h: Hasher,
    /// Whether the font faces are part of the hash: a drawing (UTF-8 `.svg`,
    /// or `.svgz` that unpacks to it) whose text mentions `<text`, as
    /// [`taxel_compiler::drawing::fonts_used`] decides.
    fonts_matter: bool,
    /// Whether the reader's languages are part of the hash: a drawing whose
    /// text mentions `systemLanguage` (a `<switch>` may choose by it).
    switches: bool,
    /// The input, for unpacking a compressed drawing the same way the build does.
    input: std::path::PathBuf,
}

impl Partial {
    /// Hashes the domain, the versions, the input's extension and bytes, and a glTF's files.
    pub fn begin(input: &Path, bytes: &[u8]) -> Partial {
        let mut h = Hasher(blake3::Hasher::new());
        h.field(b"taxel build content hash v1")
            .field(env!("CARGO_PKG_VERSION").as_bytes())
            .field(&[taxel_format::FORMAT_MAJOR.to_le_bytes(), taxel_format::FORMAT_MINOR.to_le_bytes()].concat());
        let ext = input.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
        h.field(ext.as_bytes()).field(bytes);
        if ext == "gltf" {
            for (uri, data) in gltf_resources(input, bytes) {
                h.field(uri.as_bytes()).opt(data.as_deref());
            }
        }
        let text = matches!(ext.as_str(), "svg" | "svgz").then(|| text_of(input, bytes)).flatten();
        let fonts_matter = text.as_ref().is_some_and(|t| t.contains("<text"));
        let switches = text.as_ref().is_some_and(|t| t.contains("systemLanguage"));
        Partial { h, fonts_matter, switches, input: input.to_path_buf() }
    }

    /// The font faces the text of `bytes` (the input's, as given to
    /// [`Partial::begin`]) is laid out with, under `--fonts DIR` or the
    /// system's fonts: one parse of the drawing. Empty when fonts do not matter.
    pub fn fonts_by_parsing(&self, bytes: &[u8], opts: &CompileOpts) -> Result<Vec<FontFace>> {
        let text = match text_of(&self.input, bytes) {
            Some(t) if self.fonts_matter => t,
            _ => return Ok(Vec::new()),
        };
        let db = crate::compile::font_database(opts.fonts.as_deref())?;
        Ok(taxel_compiler::drawing::fonts_used(&text, &db, &crate::compile::languages(opts)))
    }

    /// The hash, given the faces the text was laid out with (those of
    /// [`Partial::fonts_by_parsing`] or of the build; ignored when fonts do
    /// not matter) and the options.
    pub fn finish(&self, fonts: &[FontFace], opts: &CompileOpts) -> Result<[u8; 32]> {
        let mut h = Hasher(self.h.0.clone());
        if self.fonts_matter {
            font_faces(&mut h, fonts);
        }
        let style = match &opts.style {
            // The built-in sheet is part of taxel, which the version above covers.
            Some(_) if opts.style_is_auto() => Some(b"auto".to_vec()),
            Some(p) => {
                Some(crate::io::read_input(p).with_context(|| format!("cannot read style sheet {}", p.display()))?)
            }
            None => None,
        };
        h.opt(style.as_deref());
        match &opts.profile {
            // A file is hashed by content, so editing it rebuilds; a name by name.
            Some(p) if Path::new(p).is_file() => {
                let text = crate::io::read_input(Path::new(p)).with_context(|| format!("cannot read profile {p}"))?;
                h.field(b"file").field(&text)
            }
            Some(p) => h.field(b"name").field(p.as_bytes()),
            None => h.field(b"default"),
        };
        h.opt(opts.resolution.map(|r| r.to_le_bytes()).as_ref().map(|b| &b[..]));
        h.opt(opts.width_mm.map(|w| w.to_le_bytes()).as_ref().map(|b| &b[..]));
        // Fitting, the region, the up axis and the exaggeration change the bundle too.
        h.field(&[opts.fit as u8, opts.up.map_or(2, |u| u as u8)]);
        h.opt(opts.region.as_ref().map(|r| format!("{r:?}")).as_ref().map(|s| s.as_bytes()));
        h.opt(opts.exaggerate.map(|e| e.to_le_bytes()).as_ref().map(|b| &b[..]));
        // Text's braille: the braille service (liblouis's version, or the
        // built-in table) and the reader's language, which chooses the table
        // of text that does not say its own.
        if self.fonts_matter {
            let braille = crate::compile::braille();
            h.field(braille.liblouis_version().unwrap_or("built-in").as_bytes());
            h.field(crate::compile::languages(opts).first().map_or("en", String::as_str).as_bytes());
        }
        // The reader's languages choose among a `<switch>`'s children.
        if self.switches {
            h.field(crate::compile::languages(opts).join(",").as_bytes());
        }
        Ok(*h.0.finalize().as_bytes())
    }
}

/// Hashes the font faces a drawing's text is laid out with (under `--fonts
/// DIR` or the system's fonts), so that a bundle is rebuilt when one of them
/// changes, is removed, or another face takes its place.
///
/// A face loaded from a file is hashed by its path, its index in the file,
/// and the file's size and modification time, not its bytes: reading every
/// used font (CJK faces weigh 10 to 20 MB) for every input of every
/// incremental run would cost more than the check saves, and installing or
/// updating a font changes its size or time. A face held in memory is hashed
/// by its names.
fn font_faces(h: &mut Hasher, faces: &[FontFace]) {
    for face in faces {
        h.field(b"font").field(&face.index.to_le_bytes());
        match &face.path {
            Some(p) => {
                let meta = std::fs::metadata(p).ok();
                let since = |t: std::time::SystemTime| t.duration_since(std::time::UNIX_EPOCH).ok();
                let mtime = meta.as_ref().and_then(|m| m.modified().ok()).and_then(since).map_or(0, |d| d.as_nanos());
                h.field(p.as_os_str().as_encoded_bytes())
                    .field(&meta.map_or(u64::MAX, |m| m.len()).to_le_bytes())
                    .field(&mtime.to_le_bytes());
            }
            None => {
                h.field(face.family.as_bytes()).field(face.post_script_name.as_bytes());
            }
        }
    }
}

/// The relative files (buffers, images) a glTF file names, with their bytes
/// (`None` when missing: the compiler will say so). Embedded `data:` URIs are
/// already in the file's own bytes.
fn gltf_resources(input: &Path, bytes: &[u8]) -> Vec<(String, Option<Vec<u8>>)> {
    let Ok(json) = serde_json::from_slice::<serde_json::Value>(bytes) else { return Vec::new() };
    let base = input.parent().unwrap_or(Path::new(""));
    let mut out = Vec::new();
    for list in ["buffers", "images"] {
        let Some(items) = json.get(list).and_then(|v| v.as_array()) else { continue };
        for item in items {
            let Some(uri) = item.get("uri").and_then(|u| u.as_str()) else { continue };
            if uri.starts_with("data:") || uri.contains("://") {
                continue;
            }
            // URIs in glTF are percent-encoded (`my%20mesh.bin`).
            let rel = percent_encoding::percent_decode_str(uri).decode_utf8_lossy();
            let data = crate::io::read_input(&base.join(&*rel)).ok();
            out.push((uri.to_string(), data));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opts() -> CompileOpts {
        CompileOpts::default()
    }

    /// The reader's languages choose among a `<switch>`'s children: they
    /// count for a drawing that mentions `systemLanguage`, and only there.
    #[test]
    fn languages_change_the_hash_of_a_drawing_with_a_switch() {
        let svg = Path::new("x.svg");
        let fr = CompileOpts { lang: Some("fr".into()), ..opts() };
        let de = CompileOpts { lang: Some("de".into()), ..opts() };
        let switch = br#"<svg><switch><rect systemLanguage="fr"/></switch></svg>"#;
        assert_ne!(content_hash(svg, switch, &fr).unwrap(), content_hash(svg, switch, &de).unwrap());
        let plain = b"<svg><rect/></svg>";
        assert_eq!(content_hash(svg, plain, &fr).unwrap(), content_hash(svg, plain, &de).unwrap());
    }

    #[test]
    fn every_dependency_changes_the_hash() {
        let dir = tempfile::tempdir().unwrap();
        let style = dir.path().join("s.toml");
        std::fs::write(&style, "a").unwrap();
        let svg = Path::new("x.svg");
        let base = content_hash(svg, b"<svg/>", &opts()).unwrap();
        assert_eq!(base, content_hash(svg, b"<svg/>", &opts()).unwrap(), "deterministic");
        let mut variants = vec![
            content_hash(svg, b"<svg />", &opts()).unwrap(),
            content_hash(Path::new("x.glb"), b"<svg/>", &opts()).unwrap(),
            content_hash(svg, b"<svg/>", &CompileOpts { profile: Some("finger3".into()), ..opts() }).unwrap(),
            content_hash(svg, b"<svg/>", &CompileOpts { resolution: Some(8.0), ..opts() }).unwrap(),
            content_hash(svg, b"<svg/>", &CompileOpts { width_mm: Some(8.0), ..opts() }).unwrap(),
            content_hash(svg, b"<svg/>", &CompileOpts { fit: true, ..opts() }).unwrap(),
            content_hash(svg, b"<svg/>", &CompileOpts { up: Some(crate::cli::Up::Z), ..opts() }).unwrap(),
            content_hash(svg, b"<svg/>", &CompileOpts { exaggerate: Some(2.0), ..opts() }).unwrap(),
            content_hash(svg, b"<svg/>", &CompileOpts { region: "1,2,3,4".parse().ok(), ..opts() }).unwrap(),
            content_hash(svg, b"<svg/>", &CompileOpts { style: Some(style.clone()), ..opts() }).unwrap(),
        ];
        std::fs::write(&style, "b").unwrap();
        variants.push(content_hash(svg, b"<svg/>", &CompileOpts { style: Some(style), ..opts() }).unwrap());
        variants.push(base);
        let distinct: std::collections::HashSet<_> = variants.iter().collect();
        assert_eq!(distinct.len(), variants.len());
    }

    #[test]
    fn a_gltf_buffer_is_part_of_the_hash() {
        let dir = tempfile::tempdir().unwrap();
        let gltf = dir.path().join("m.gltf");
        let json = br#"{"buffers":[{"uri":"m%20data.bin","byteLength":1}]}"#;
        std::fs::write(dir.path().join("m data.bin"), [1]).unwrap();
        let a = content_hash(&gltf, json, &opts()).unwrap();
        std::fs::write(dir.path().join("m data.bin"), [2]).unwrap();
        assert_ne!(a, content_hash(&gltf, json, &opts()).unwrap());
    }

    #[test]
    fn the_fonts_a_drawing_uses_are_part_of_the_hash() {
        let dir = tempfile::tempdir().unwrap();
        let fonts = dir.path().join("fonts");
        std::fs::create_dir(&fonts).unwrap();
        let tuffy = std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fonts/Tuffy.ttf")).unwrap();
        // Each state of the folder gets a fresh path, so the process-wide font cache sees it as new.
        let with = |name: &str, bytes: Option<&[u8]>| {
            let d = fonts.join(name);
            std::fs::create_dir(&d).unwrap();
            if let Some(b) = bytes {
                std::fs::write(d.join("Tuffy.ttf"), b).unwrap();
            }
            CompileOpts { fonts: Some(d), ..opts() }
        };
        let svg = Path::new("x.svg");
        let text: &[u8] = br#"<svg xmlns="http://www.w3.org/2000/svg" width="50mm" height="20mm"><text x="1" y="15" font-family="Tuffy">Hi</text></svg>"#;
        let shapes: &[u8] =
            br#"<svg xmlns="http://www.w3.org/2000/svg" width="50mm" height="20mm"><rect width="5" height="5"/></svg>"#;
        let (a, b) = (with("a", Some(&tuffy)), with("b", Some(&tuffy)));
        let mut longer = tuffy.clone();
        longer.extend_from_slice(&[0; 4]);
        let (changed, none) = (with("c", Some(&longer)), with("d", None));
        let h = |bytes: &[u8], o: &CompileOpts| content_hash(svg, bytes, o).unwrap();
        assert_eq!(h(text, &a), h(text, &a), "deterministic");
        // The same face at another path, a changed face, and no face at all each rebuild.
        let variants = [h(text, &a), h(text, &b), h(text, &changed), h(text, &none)];
        let distinct: std::collections::HashSet<_> = variants.iter().collect();
        assert_eq!(distinct.len(), variants.len());
        // A drawing without text does not depend on the fonts.
        assert_eq!(h(shapes, &a), h(shapes, &none));
    }

    #[test]
    fn the_builds_own_fonts_give_the_hash_a_parse_gives() {
        let dir = tempfile::tempdir().unwrap();
        let fonts = dir.path().join("fonts");
        std::fs::create_dir(&fonts).unwrap();
        std::fs::copy(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fonts/Tuffy.ttf"), fonts.join("Tuffy.ttf"))
            .unwrap();
        let o = CompileOpts { fonts: Some(fonts), fit: true, ..opts() };
        let text = r#"<svg xmlns="http://www.w3.org/2000/svg" width="50mm" height="20mm"><text x="1" y="15" font-family="Tuffy">Hi</text><rect width="5" height="5"/></svg>"#;
        let shapes =
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="50mm" height="20mm"><rect width="5" height="5"/></svg>"#;
        for (name, svg) in [("text.svg", text), ("shapes.svg", shapes)] {
            let input = dir.path().join(name);
            std::fs::write(&input, svg).unwrap();
            let compiled = crate::compile::compile_file(&input, &o).unwrap();
            assert_eq!(compiled.fonts_used.is_empty(), name == "shapes.svg", "{name}: {:?}", compiled.fonts_used);
            let built = Partial::begin(&input, svg.as_bytes()).finish(&compiled.fonts_used, &o).unwrap();
            assert_eq!(built, content_hash(&input, svg.as_bytes(), &o).unwrap(), "{name}");
        }
        // A face the build did not use changes the hash, so the check above can fail.
        let input = dir.path().join("text.svg");
        let compiled = crate::compile::compile_file(&input, &o).unwrap();
        let part = Partial::begin(&input, text.as_bytes());
        assert_ne!(part.finish(&compiled.fonts_used, &o).unwrap(), part.finish(&[], &o).unwrap());
    }
}
