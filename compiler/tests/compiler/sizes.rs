//! Bundle sizes that issues 16 (point 6) and 46 (point 4) promise: the `tala-map` bundle is at
//! most the 8-bit grayscale PNG of the same scene at 10 px/mm, and its file (the stored form) a quarter of it (rendered here
//! by resvg, independently of the compiler, and as the issue measured it), and a scene of 2,000 regions and
//! a fitted map of 1,000 regions are each one layer per style and at most 1 MB.

use taxel_compiler::{CompileOptions, compile_svg};
use taxel_format::Chunk;

use super::common::*;

use super::realistic::drawings;

/// What issue 16 point 6 allows a 2,000-region scene or a fitted map.
const ONE_MB: usize = 1 << 20;

/// The 8-bit grayscale PNG of `tala-map` at 10 px/mm as issue 16 measured
/// it. The PNG this test renders with the `image` crate's default
/// compression is about twice as large, so the bundle must be within the
/// smaller of the two.
const ISSUE_TALA_PNG_BYTES: usize = 15_827;

/// The bundle's bytes, failing on errors.
fn bytes_of(svg: &str, opts: &CompileOptions) -> (Vec<u8>, taxel_format::Bundle) {
    let c = no_internal_error(compile_svg(svg, opts));
    let b = bundle(&c).clone();
    (b.to_bytes().expect("the bundle encodes"), b)
}

/// The 8-bit grayscale PNG of `svg` at 10 px/mm on white, as the issue
/// measured it (resvg's render, luma of each pixel, the `image` crate's PNG).
fn png_len(svg: &str) -> usize {
    let tree = usvg::Tree::from_str(svg, &usvg::Options::default()).expect("the SVG parses");
    // usvg's size is in CSS px (96 per inch); 10 px/mm.
    let k = 10.0 * 25.4 / 96.0;
    let (w, h) = ((tree.size().width() * k).ceil() as u32, (tree.size().height() * k).ceil() as u32);
    let mut pixmap = resvg::tiny_skia::Pixmap::new(w, h).expect("pixmap");
    pixmap.fill(resvg::tiny_skia::Color::WHITE);
    resvg::render(&tree, resvg::tiny_skia::Transform::from_scale(k, k), &mut pixmap.as_mut());
    let gray: Vec<u8> = pixmap
        .data()
        .chunks_exact(4)
        .map(|p| ((p[0] as u32 * 299 + p[1] as u32 * 587 + p[2] as u32 * 114) / 1000) as u8)
        .collect();
    // As the `image` crate writes an 8-bit gray PNG by default: fast compression, adaptive filters.
    use taxel_textform::png::{BitDepth, ColorType, Compression, write};
    let png = write(w, h, ColorType::Grayscale, BitDepth::Eight, &gray, Compression::Fast).expect("png");
    png.len()
}

#[test]
fn the_tala_map_bundle_is_at_most_the_png_of_the_scene_and_its_file_a_quarter() {
    let svg = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/map/tala-map.svg")).unwrap();
    let (bytes, bundle) = bytes_of(&svg, &CompileOptions::new(stress2()));
    // The file `taxel build` writes: the stored form (SPEC.md 15).
    let file = bundle.to_stored_bytes().expect("the bundle stores");
    let png = png_len(&svg).min(ISSUE_TALA_PNG_BYTES);
    eprintln!(
        "tala-map: plain bundle {} bytes, file {} bytes, 8-bit PNG at 10 px/mm {} bytes here, {ISSUE_TALA_PNG_BYTES} in the issue",
        bytes.len(),
        file.len(),
        png_len(&svg)
    );
    // Issue 16 point 6: the plain bundle within the PNG.
    assert!(bytes.len() <= png, "tala-map: plain bundle {} bytes, PNG {png} bytes", bytes.len());
    // Issue 46 point 4: the file at most a quarter of it.
    assert!(4 * file.len() <= png, "tala-map: file {} bytes, more than a quarter of the PNG's {png}", file.len());
    assert_eq!(&*taxel_format::stored::plain(&file).expect("the file reads back"), &bytes[..]);
}

#[test]
fn two_thousand_grated_squares_are_one_layer_and_at_most_1_mb() {
    // 2,000 grated 1 mm squares, 50 x 40, spread over the 100 x 60 mm page.
    let mut squares = String::new();
    for k in 0..2_000 {
        let (i, j) = (k % 50, k / 50);
        squares += &format!(
            "<rect id=\"s{k}\" x=\"{:.2}\" y=\"{:.2}\" width=\"1\" height=\"1\"/>\n",
            1.0 + i as f64 * 1.95,
            1.0 + j as f64 * 1.45
        );
    }
    let svg = page(&format!("<g data-tactile=\"grating(wavelength: 3mm)\">{squares}</g>"));
    let (bytes, b) = bytes_of(&svg, &CompileOptions::new(stress2()));
    let layers = masks(&b);
    assert_eq!(layers.len(), 1, "one style, one layer");
    assert_eq!(layers[0].sources.len(), 2_000, "the layer holds every square");
    assert!(bytes.len() <= ONE_MB, "2,000 squares: {} bytes", bytes.len());
}

#[test]
fn a_fitted_map_of_a_thousand_regions_is_at_most_1_mb() {
    let svg = drawings::inkscape_map(1_000, 8, 7);
    let opts = CompileOptions { fit: true, ..CompileOptions::new(stress2()) };
    let (bytes, b) = bytes_of(&svg, &opts);
    // Far fewer layers than regions: one per style.
    let layers = masks(&b);
    assert!(!layers.is_empty() && layers.len() <= 6, "{} layers", layers.len());
    let held: usize = b
        .chunks
        .iter()
        .filter_map(|c| match c {
            Chunk::Distance(d) => Some(d.sources.len()),
            _ => None,
        })
        .sum();
    assert!(held >= 1_000, "the layers hold the regions: {held}");
    assert!(bytes.len() <= ONE_MB, "fitted 1,000-region map: {} bytes", bytes.len());
}
