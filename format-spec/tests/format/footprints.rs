//! Footprints (`FOOT`, SPEC.md section 10.1) and the point lookup: chunks
//! crafted from the SPEC's text, hostile bytes refused, and the R-tree
//! lookup against a brute-force scan of every shape.

use proptest::prelude::*;
use taxel_format::lookup::PointLookup;
use taxel_format::{Bundle, BundleView, FootprintKind, FormatError, Tag};

use crate::craft::{Raw, craft_version, decompose, every_kind_bytes, find, put_f32, put_u16, put_u32, raw};

/// One shape as the SPEC lays it out: source, kind code, half width (quanta), rings.
type Shape = (u32, u8, u16, Vec<Vec<(u16, u16)>>);

/// A `FOOT` chunk's data, written from SPEC.md section 10.1.
fn foot(quantum: f32, origin: (f32, f32), shapes: &[Shape]) -> Vec<u8> {
    let rings: Vec<&Vec<(u16, u16)>> = shapes.iter().flat_map(|s| &s.3).collect();
    let points: usize = rings.iter().map(|r| r.len()).sum();
    let mut d = Vec::new();
    for v in [shapes.len() as u32, rings.len() as u32, points as u32] {
        d.extend_from_slice(&v.to_le_bytes());
    }
    for v in [quantum, origin.0, origin.1] {
        d.extend_from_slice(&v.to_le_bytes());
    }
    for s in shapes {
        d.extend_from_slice(&s.0.to_le_bytes());
        d.extend_from_slice(&[s.1, 0]);
        d.extend_from_slice(&s.2.to_le_bytes());
        d.extend_from_slice(&(s.3.len() as u32).to_le_bytes());
    }
    for r in &rings {
        d.extend_from_slice(&(r.len() as u32).to_le_bytes());
    }
    for &(x, y) in rings.iter().copied().flatten() {
        d.extend_from_slice(&x.to_le_bytes());
        d.extend_from_slice(&y.to_le_bytes());
    }
    d
}

/// A bundle of the sample's manifest and provenance and `foot` data.
fn bundle_with(foot_data: Vec<u8>, required: bool) -> Vec<u8> {
    let chunks = decompose(&every_kind_bytes());
    let mani = chunks[find(&chunks, b"MANI")].clone();
    let prov = chunks[find(&chunks, b"PROV")].clone();
    let list: Vec<Raw> = vec![mani, prov, raw(b"FOOT", required, foot_data)];
    craft_version(&list, taxel_format::FORMAT_MAJOR, 0)
}

fn square(x: u16, y: u16, side: u16) -> Vec<(u16, u16)> {
    vec![(x, y), (x + side, y), (x + side, y + side), (x, y + side)]
}

/// Two overlapping squares (the second on top), a line over them, a disc.
fn scene() -> Vec<Shape> {
    vec![
        (0, 0, 0, vec![square(0, 0, 200)]),
        (1, 1, 0, vec![square(100, 100, 200)]),
        (0, 2, 2, vec![vec![(0, 150), (400, 150)]]),
        (1, 2, 50, vec![vec![(350, 350)]]),
    ]
}

#[test]
fn a_crafted_chunk_reads_back_and_writes_the_same_bytes() {
    let bytes = bundle_with(foot(0.1, (5.0, -2.0), &scene()), false);
    let view = BundleView::parse(&bytes).unwrap();
    assert_eq!(view.version(), (taxel_format::FORMAT_MAJOR, 0));
    let f = view.footprints().unwrap();
    assert_eq!(f.len(), 4);
    let shapes: Vec<_> = f.shapes().collect();
    assert_eq!(shapes[1].kind, FootprintKind::AreaEvenOdd);
    assert_eq!(shapes[3].half_width_mm(), 5.0);
    let first: Vec<(f32, f32)> = shapes[0].rings().next().unwrap().points_mm().collect();
    assert_eq!(first[2], (5.0 + 20.0, -2.0 + 20.0));
    // The writer records 3.0 (which has footprints) and the same bytes.
    assert_eq!(Bundle::from_bytes(&bytes).unwrap().to_bytes().unwrap(), bytes);
}

#[test]
fn the_topmost_shape_wins_and_thin_lines_have_a_tolerance() {
    let bytes = bundle_with(foot(0.1, (0.0, 0.0), &scene()), false);
    let view = BundleView::parse(&bytes).unwrap();
    let lookup = PointLookup::new(&view, 0.5).unwrap();
    let at = |x, y| lookup.under(x, y).map(|h| h.shape);
    assert_eq!(at(5.0, 5.0), Some(0), "only the first square");
    assert_eq!(at(25.0, 25.0), Some(1), "both squares: the later one is on top");
    assert_eq!(at(5.0, 15.15), Some(2), "within the line's 0.2 mm half width, over the square");
    assert_eq!(at(35.0, 15.45), Some(2), "beyond its half width, within the 0.5 mm tolerance");
    assert_eq!(at(35.0, 15.6), None);
    let exact = PointLookup::new(&view, 0.0).unwrap();
    assert_eq!(exact.under(35.0, 15.45).map(|h| h.shape), None, "no tolerance");
    assert_eq!(exact.under(35.0, 15.15).map(|h| h.shape), Some(2));
    assert_eq!(at(35.0, 39.9), Some(3), "within the disc's 5 mm radius");
    assert_eq!(at(60.0, 60.0), None);
    assert_eq!(at(f64::NAN, 1.0), None);
    let all: Vec<usize> = lookup.all_under(15.0, 15.0).iter().map(|h| h.shape).collect();
    assert_eq!(all, vec![2, 1, 0]);
    // Names come from the provenance table: label, else id.
    let hit = lookup.under(5.0, 5.0).unwrap();
    let (id, label, _) = view.provenance().unwrap().get(hit.source).unwrap();
    assert_eq!(hit.name(), if label.is_empty() { id } else { label });
}

#[test]
fn the_hole_of_an_even_odd_region_is_outside_it() {
    let ring = |x, y, s| square(x, y, s);
    let shapes = vec![(0, 1, 0, vec![ring(0, 0, 100), ring(40, 40, 20)])];
    let bytes = bundle_with(foot(0.1, (0.0, 0.0), &shapes), false);
    let lookup = PointLookup::new(&BundleView::parse(&bytes).unwrap(), 0.0).unwrap();
    assert!(lookup.under(2.0, 2.0).is_some());
    assert!(lookup.under(5.0, 5.0).is_none(), "the hole");
}

fn refused(data: Vec<u8>) -> FormatError {
    BundleView::parse(&bundle_with(data, false)).unwrap_err()
}

#[test]
fn hostile_chunks_are_refused() {
    let good = foot(0.1, (0.0, 0.0), &scene());
    let edit = |f: &dyn Fn(&mut Vec<u8>)| {
        let mut d = good.clone();
        f(&mut d);
        refused(d)
    };
    // Lengths and limits.
    assert!(matches!(refused(good[..20].to_vec()), FormatError::ChunkLength { .. }));
    assert!(matches!(edit(&|d| d.push(0)), FormatError::ChunkLength { .. }));
    assert!(matches!(edit(&|d| put_u32(d, 0, u32::MAX)), FormatError::Limit { field: "shapes", .. }));
    assert!(matches!(edit(&|d| put_u32(d, 4, u32::MAX)), FormatError::Limit { field: "rings", .. }));
    assert!(matches!(edit(&|d| put_u32(d, 8, u32::MAX)), FormatError::Limit { field: "points", .. }));
    // Header values.
    for q in [0.0, f32::NAN, 2.0, -0.1] {
        assert!(matches!(edit(&|d| put_f32(d, 12, q)), FormatError::InvalidValue { field: "quantum_mm", .. }));
    }
    assert!(matches!(edit(&|d| put_f32(d, 16, f32::INFINITY)), FormatError::InvalidValue { field: "origin_x_mm", .. }));
    // Shape 0 starts at 24: source, kind, reserved, half width, rings.
    assert!(matches!(edit(&|d| put_u32(d, 24, u32::MAX)), FormatError::InvalidValue { field: "source", .. }));
    assert!(matches!(edit(&|d| d[28] = 4), FormatError::InvalidValue { field: "kind", .. }));
    assert!(matches!(edit(&|d| d[29] = 1), FormatError::InvalidValue { field: "reserved", .. }));
    assert!(matches!(edit(&|d| put_u32(d, 32, 0)), FormatError::InvalidValue { field: "rings", .. }));
    assert!(matches!(edit(&|d| put_u32(d, 32, 9)), FormatError::InvalidValue { field: "rings", .. }));
    // Ring table at 24 + 12 * 4 = 72: an area ring of 2 points, a line ring of 0.
    assert!(matches!(edit(&|d| put_u32(d, 72, 2)), FormatError::InvalidValue { field: "ring points", .. }));
    assert!(matches!(edit(&|d| put_u32(d, 80, 0)), FormatError::InvalidValue { field: "ring points", .. }));
    assert!(matches!(edit(&|d| put_u32(d, 80, 3)), FormatError::InvalidValue { field: "points", .. }));
    // The last shape claims fewer rings than the table has.
    let mut fewer = scene();
    fewer[3].3.push(vec![(1, 1)]);
    let mut d = foot(0.1, (0.0, 0.0), &fewer);
    put_u32(&mut d, 24 + 36 + 8, 1);
    assert!(matches!(refused(d), FormatError::InvalidValue { field: "rings", .. }));
    // Coordinates are any u16: no check to fail.
    assert!(BundleView::parse(&bundle_with(edit_ok(&good, |d| put_u16(d, 88, u16::MAX)), false)).is_ok());
}

fn edit_ok(good: &[u8], f: impl Fn(&mut Vec<u8>)) -> Vec<u8> {
    let mut d = good.to_vec();
    f(&mut d);
    d
}

#[test]
fn footprints_are_optional_and_once() {
    let data = foot(0.1, (0.0, 0.0), &scene());
    let e = BundleView::parse(&bundle_with(data.clone(), true)).unwrap_err();
    assert!(matches!(e, FormatError::RequiredFlag { tag: Tag::FOOTPRINTS, expected: false, .. }));
    let mut chunks = decompose(&bundle_with(data, false));
    chunks.push(chunks[2].clone());
    let e = BundleView::parse(&craft_version(&chunks, taxel_format::FORMAT_MAJOR, 0)).unwrap_err();
    assert!(matches!(e, FormatError::ChunkOrder { tag: Tag::FOOTPRINTS, .. }));
}

/// A random shape: a polygon, a polyline or a disc, anywhere in 0..100 mm at 0.1 mm.
fn shape() -> impl Strategy<Value = Shape> {
    let pt = (0u16..1000, 0u16..1000);
    (0u32..4, 0u8..4, 0u16..40, prop::collection::vec(prop::collection::vec(pt, 3..8), 1..3))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// The index finds exactly what a scan of every shape, topmost first, finds.
    #[test]
    fn the_index_agrees_with_a_brute_force_scan(
        shapes in prop::collection::vec(shape(), 1..40),
        probes in prop::collection::vec((-5.0f64..105.0, -5.0f64..105.0), 64),
        tolerance in 0.0f64..2.0,
    ) {
        let bytes = bundle_with(foot(0.1, (0.0, 0.0), &shapes), false);
        let lookup = PointLookup::new(&BundleView::parse(&bytes).unwrap(), tolerance).unwrap();
        for (x, y) in probes {
            let scan = (0..lookup.len()).rev().find(|&i| lookup.covers(i, x, y));
            prop_assert_eq!(lookup.under(x, y).map(|h| h.shape), scan);
            let all: Vec<usize> = lookup.all_under(x, y).iter().map(|h| h.shape).collect();
            let every: Vec<usize> = (0..lookup.len()).rev().filter(|&i| lookup.covers(i, x, y)).collect();
            prop_assert_eq!(all, every);
        }
    }
}

#[test]
fn every_truncation_is_refused_and_every_bit_flip_reads_or_is_refused() {
    let good = foot(0.1, (0.0, 0.0), &scene());
    for len in 0..good.len() {
        assert!(BundleView::parse(&bundle_with(good[..len].to_vec(), false)).is_err(), "cut at {len}");
    }
    for bit in 0..good.len() * 8 {
        let mut d = good.clone();
        d[bit / 8] ^= 1 << (bit % 8);
        // Resealed, so the chunk's own checks are reached; a flip that still
        // reads must give a lookup that answers without panicking.
        if let Ok(view) = BundleView::parse(&bundle_with(d, false)) {
            let lookup = PointLookup::new(&view, 0.5).unwrap();
            let _ = lookup.under(15.0, 15.0);
            assert_eq!(Bundle::from_view(&view).to_bytes().unwrap(), view.bytes());
        }
    }
}
