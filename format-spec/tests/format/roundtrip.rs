//! Round trips of every chunk kind through the writer and the reader.

use taxel_format::{
    Bundle, BundleView, Chunk, ChunkView, Dot, DotKind, DotTable, FormatError, MaskSamples, Mm, RawChunk, Tag, sample,
};

#[test]
fn every_chunk_kind_round_trips() {
    let b = sample::every_kind();
    let bytes = b.to_bytes().unwrap();
    let view = BundleView::parse(&bytes).unwrap();
    assert_eq!(view.version(), (taxel_format::FORMAT_MAJOR, 0));
    assert_eq!(view.manifest(), &b.manifest);
    assert_eq!(Bundle::from_view(&view), b);
    let tags: Vec<String> = view.chunks().map(|c| kind(&c)).collect();
    assert_eq!(
        tags,
        [
            "mask 8",
            "mask 16",
            "distance GDST",
            "dots outline",
            "dots symbol",
            "dots braille",
            "dots outline",
            "strokes",
            "height",
            "provenance",
            "unknown XTRA"
        ]
    );
    // The table lists the same chunks with the manifest first.
    assert_eq!(view.chunk_count() as usize, b.chunks.len() + 1);
    assert_eq!(view.chunk_entry(0).unwrap().0, Tag::MANIFEST);
    for (i, c) in b.chunks.iter().enumerate() {
        let (tag, required, ..) = view.chunk_entry(i as u32 + 1).unwrap();
        assert_eq!(tag, c.tag());
        assert_eq!(required, !matches!(c, Chunk::Provenance(_) | Chunk::Raw(_)));
    }
    assert!(view.chunk_entry(view.chunk_count()).is_none());
}

fn kind(c: &ChunkView<'_>) -> String {
    match c {
        ChunkView::Mask(m) => format!("mask {}", m.bits),
        ChunkView::Distance(d) => format!("distance {}", d.tag()),
        ChunkView::Dots(d) => format!("dots {}", d.kind.name()),
        ChunkView::Strokes(_) => "strokes".into(),
        ChunkView::Height(_) => "height".into(),
        ChunkView::Pins(_) => "pins".into(),
        ChunkView::Provenance(_) => "provenance".into(),
        ChunkView::Footprints(_) => "footprints".into(),
        ChunkView::Unknown { tag, .. } => format!("unknown {tag}"),
    }
}

#[test]
fn sixteen_bit_masks_keep_every_sample_little_endian() {
    let b = sample::every_kind();
    let bytes = b.to_bytes().unwrap();
    let view = BundleView::parse(&bytes).unwrap();
    let m = view
        .chunks()
        .find_map(|c| if let ChunkView::Mask(m) = c { (m.bits == 16).then_some(m) } else { None })
        .unwrap();
    assert_eq!(m.full_scale(), 65_535);
    let expected = [0u16, 1, 255, 256, 65_534, 65_535];
    for (k, &e) in expected.iter().enumerate() {
        assert_eq!(m.raw(k as u32 % 2, k as u32 / 2), e as u32);
        assert_eq!(m.sample_bytes()[2 * k..2 * k + 2], e.to_le_bytes());
    }
    assert_eq!(m.raw(2, 0), 0, "outside the mask is 0");
}

#[test]
fn dots_of_every_kind_read_back_and_are_found_near_a_point() {
    let b = sample::every_kind();
    let bytes = b.to_bytes().unwrap();
    let view = BundleView::parse(&bytes).unwrap();
    let tables: Vec<_> =
        view.chunks().filter_map(|c| if let ChunkView::Dots(d) = c { Some(d) } else { None }).collect();
    let kinds: Vec<DotKind> = tables.iter().map(|t| t.kind).collect();
    assert_eq!(kinds, [DotKind::Outline, DotKind::Symbol, DotKind::Braille, DotKind::Outline]);
    assert!(tables[3].is_empty());
    // Brute force against the index: every dot whose disc holds the point is visited.
    for t in &tables {
        for (px, py) in [(5.0f32, 5.0f32), (7.0, 5.5), (40.5, 30.0), (22.0, 41.0), (60.0, 47.0), (-100.0, 1e6)] {
            let mut near = Vec::new();
            t.for_each_near(px, py, |d| near.push(d));
            for i in 0..t.len() {
                let d = t.dot(i).unwrap();
                let dist = ((d.x.0 - px) as f64).hypot((d.y.0 - py) as f64);
                if dist <= d.radius.0 as f64 {
                    assert!(near.contains(&d), "{d:?} missed at ({px}, {py})");
                }
            }
        }
    }
}

#[test]
fn a_run_of_cells_by_index_holds_the_dots_of_the_row_run() {
    let b = sample::every_kind();
    let bytes = b.to_bytes().unwrap();
    let view = BundleView::parse(&bytes).unwrap();
    for c in view.chunks() {
        let ChunkView::Dots(t) = c else { continue };
        let g = t.grid;
        for row in 0..g.rows {
            for c0 in 0..g.cols {
                for c1 in c0..g.cols {
                    let cell = (row * g.cols + c0) as usize;
                    let by_index: Vec<_> = t.cell_run(cell, cell + (c1 - c0) as usize + 1).collect();
                    assert_eq!(by_index, t.row_run(c0, c1, row).collect::<Vec<_>>(), "cells {c0}..={c1} of row {row}");
                }
            }
        }
        // Past the index: no dots.
        let past = (g.cols * g.rows) as usize + 1;
        assert_eq!(t.cell_run(past, past + 3).count(), 0);
    }
}

#[test]
fn dots_are_stored_by_grid_cell() {
    let dot = |x: f32, y: f32| Dot { x: Mm(x), y: Mm(y), radius: Mm(0.5), amplitude: 1.0, source: None };
    let mut b = Bundle::new(sample::every_kind().manifest);
    // Given right to left; stored left to right (cells of 1 mm from x = 0).
    b.chunks
        .push(Chunk::Dots(DotTable { kind: DotKind::Symbol, dots: vec![dot(3.0, 0.0), dot(0.0, 0.0), dot(1.5, 0.0)] }));
    let back = Bundle::from_bytes(&b.to_bytes().unwrap()).unwrap();
    let Chunk::Dots(t) = &back.chunks[0] else { panic!() };
    let xs: Vec<f32> = t.dots.iter().map(|d| d.x.0).collect();
    assert_eq!(xs, [0.0, 1.5, 3.0]);
    // And writing what was read gives the same bytes.
    assert_eq!(back.to_bytes().unwrap(), b.to_bytes().unwrap());
}

#[test]
fn dots_far_apart_still_get_a_bounded_grid() {
    let dot = |x: f32, y: f32| Dot { x: Mm(x), y: Mm(y), radius: Mm(0.001), amplitude: 1.0, source: None };
    let mut b = Bundle::new(sample::every_kind().manifest);
    let dots = vec![dot(-3.0e38, -3.0e38), dot(3.0e38, 3.0e38), dot(0.0, 0.0), dot(1e-3, 0.0)];
    b.chunks.push(Chunk::Dots(DotTable { kind: DotKind::Outline, dots }));
    let bytes = b.to_bytes().unwrap();
    let view = BundleView::parse(&bytes).unwrap();
    let Some(ChunkView::Dots(t)) = view.chunks().next() else { panic!() };
    assert!(t.grid.cols as u64 * t.grid.rows as u64 <= taxel_format::MAX_DOT_GRID_CELLS as u64);
    assert!(t.grid.cell_mm.is_finite());
    let mut n = 0;
    t.for_each_near(0.0, 0.0, |_| n += 1);
    assert!(n >= 2);
}

#[test]
fn masks_with_the_wrong_sample_count_are_refused_by_the_writer() {
    let mut b = sample::every_kind();
    let Chunk::Mask(m) = &mut b.chunks[0] else { panic!() };
    m.samples = MaskSamples::U8(vec![1, 2, 3]);
    assert!(matches!(b.to_bytes().unwrap_err(), FormatError::InvalidValue { index: 1, field: "samples", .. }));
    let mut b = sample::every_kind();
    let Some(Chunk::Height(h)) = b.chunks.iter_mut().find(|c| matches!(c, Chunk::Height(_))) else { panic!() };
    h.flags.pop();
    assert!(matches!(b.to_bytes().unwrap_err(), FormatError::InvalidValue { tag: Tag::HEIGHT, .. }));
}

#[test]
fn raw_chunks_keep_their_bytes_and_flag() {
    let mut b = Bundle::new(sample::tiny().manifest);
    b.chunks.push(Chunk::Raw(RawChunk { tag: Tag(*b"ZZZZ"), required: false, data: vec![] }));
    b.chunks.push(Chunk::Raw(RawChunk { tag: Tag(*b"ZZZY"), required: false, data: (0..=255).collect() }));
    assert_eq!(Bundle::from_bytes(&b.to_bytes().unwrap()).unwrap(), b);
    // A writer may not produce what no reader accepts.
    b.chunks.push(Chunk::Raw(RawChunk { tag: Tag(*b"ZZZX"), required: true, data: vec![] }));
    assert!(matches!(b.to_bytes().unwrap_err(), FormatError::UnknownRequiredChunk { index: 3, .. }));
}

#[test]
fn provenance_keeps_unicode_and_lines() {
    let b = sample::every_kind();
    let bytes = b.to_bytes().unwrap();
    let view = BundleView::parse(&bytes).unwrap();
    let p = view.provenance().unwrap();
    assert_eq!(p.len(), 2);
    assert_eq!(p.get(0), Some(("lake", "Lac Léman", 12)));
    assert_eq!(p.get(1), Some(("route-1", "", 0)));
    assert_eq!(p.get(2), None);
    assert_eq!(b.provenance().unwrap().entries[0].label, "Lac Léman");
}

#[test]
fn the_smallest_bundle_is_a_manifest() {
    let b = Bundle::new(sample::tiny().manifest);
    let bytes = b.to_bytes().unwrap();
    // Header, one table entry, the 144-byte manifest.
    assert_eq!(bytes.len(), 32 + 32 + 144);
    assert_eq!(Bundle::from_bytes(&bytes).unwrap(), b);
}
