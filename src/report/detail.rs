//! Where a rung's error comes from: how much of it is where the drawing has
//! detail finer than the lattice (docs/report.md, "Where the error comes
//! from").
//!
//! A distance layer plays, between its lattice points, a function of the
//! distance sampled at them. Where one piece of edge passes near a cell,
//! that distance is smooth and the cell carries the edge (a plane, an arc,
//! a corner, or samples a code or two off). Where two separate pieces of
//! edge pass within one pitch of the cell, a region or a gap narrower than
//! about two pitches, the distance has a crease between them (its ridge,
//! the medial axis) inside the cell's reach: samples one pitch apart cannot
//! say where the two edges are, and a region narrower than a pitch can fall
//! between the samples altogether. No writer can play that at this pitch,
//! whatever the tile kind; a finer lattice, a larger surface (the drawing
//! drawn larger) or a part of the drawing can. So the report classifies
//! each lattice cell by the exact geometry, not by the tile the writer
//! chose: a stored tile may be stored for a curve the lattice carries well,
//! and an analytic tile may play two features exactly.
//!
//! The test is cheap: coverage is read at [`CIRCLE_SAMPLES`] points on the
//! circle of radius one pitch round the cell's centre. Each piece of edge
//! that crosses the disc changes the coverage twice round the circle, so
//! four changes or more are two pieces or more; a piece wholly inside the
//! disc (an island, a hole) changes nothing on the circle and is found by
//! the exact distance from the centre. Pieces narrower than the circle's
//! sampling (2π/64 of the radius, 0.05 mm at a 0.5 mm pitch) may be missed,
//! and an island inside a disc that an edge also crosses is not counted:
//! the share is a lower bound. Each cell is classified once.

use std::collections::HashMap;

use serde::Serialize;
use taxel_compiler::latero::ExactRegion;
use taxel_format::{Bundle, Chunk};

use super::{Measured, Prepared, Row};

/// Points on the circle round a cell at which its coverage is read.
pub const CIRCLE_SAMPLES: usize = 64;
/// Actuators off by at most this many output steps (the final rounding
/// and little more) are not classified: they hold at most one step² each
/// of the squared error, which the share then counts as elsewhere.
pub const CLASSIFIED_ABOVE_STEPS: f64 = 1.0;
/// The edge target of issue 16 (edge error away from corners), mm.
pub const EDGE_TARGET_MM: f64 = 0.05;
/// The RMS target of issue 16, output steps.
pub const RMS_TARGET_STEPS: f64 = 1.0;
/// The share of the squared error above which the report says where the
/// error comes from: most of it.
pub const NOTE_ABOVE_SHARE: f64 = 0.5;

/// Where a row's error comes from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Share {
    /// Of the squared error of every compared actuator, the part at
    /// actuators in a lattice cell with detail finer than the lattice
    /// ([`FineDetail::at`]), 0 to 1.
    pub share: f64,
    /// The lattice cells with detail finer than the lattice in which some
    /// compared actuator was off by more than [`CLASSIFIED_ABOVE_STEPS`].
    pub cells: usize,
    /// The coarsest lattice pitch of the kernel's layers, mm.
    pub lattice_mm: f64,
}

/// Splits the squared error that `m` measured on `bundle` (one kernel's
/// chunks) by where it is: in the lattice cells of the kernel's distance
/// layers with detail finer than the lattice, or elsewhere. Only the
/// actuators off by more than [`CLASSIFIED_ABOVE_STEPS`] are classified
/// (`Measured::off`). `None` for a kernel with no distance layer (dots).
pub fn share(prep: &Prepared, bundle: &Bundle, m: &Measured, kernel: &str) -> Option<Share> {
    let lattices: Vec<Lattice<'_>> = prep
        .reference
        .iter()
        .filter(|l| kernel == "all" || super::exact_kind(l) == kernel)
        .filter_map(|l| {
            let (region, sources) = (super::region_of(l)?, super::sources_of(l)?);
            bundle.chunks.iter().find_map(|c| match c {
                Chunk::Distance(d)
                    if super::chunk_kind(c) == Some(super::exact_kind(l)) && d.sources[..] == *sources =>
                {
                    Some(Lattice {
                        region: &region.exact,
                        pitch: d.pitch_mm as f64,
                        origin: (d.origin_x.0 as f64, d.origin_y.0 as f64),
                    })
                }
                _ => None,
            })
        })
        .collect();
    let mut detail = FineDetail::new(lattices);
    let lattice_mm = detail.lattice_mm()?;
    let fine: f64 = m.off.iter().filter(|(p, _)| detail.at(*p)).map(|(_, e2)| e2).sum();
    let share = if m.square_error_sum > 0.0 { (fine / m.square_error_sum).min(1.0) } else { 0.0 };
    Some(Share { share, cells: detail.places(), lattice_mm })
}

/// The note saying where the default rung's error comes from, when it is
/// above the targets ([`EDGE_TARGET_MM`], [`RMS_TARGET_STEPS`]) and most
/// of it ([`NOTE_ABOVE_SHARE`]) is where the drawing has detail finer than
/// the lattice: of the composite's default row (`all`), or of the one
/// kernel's.
pub fn note(rows: &[Row]) -> Option<String> {
    let defaults = || rows.iter().filter(|r| r.default && r.fine_detail.is_some());
    let row = defaults().find(|r| r.kernel == "all").or_else(|| defaults().next())?;
    let s = row.fine_detail?;
    let above = row.rms_error > RMS_TARGET_STEPS || row.edge_error_mm.is_some_and(|e| e > EDGE_TARGET_MM);
    if !above || s.share <= NOTE_ABOVE_SHARE {
        return None;
    }
    Some(format!(
        "{:.0} % of the RMS error is where the drawing has detail finer than the {} mm lattice ({} lattice cells): \
         the surface cannot carry it; take part of the drawing with --region X,Y,W,H or #id, or use a profile with a larger surface",
        (s.share * 100.0).floor(),
        s.lattice_mm,
        grouped(s.cells)
    ))
}

/// A note where the default rung's edge error is a feature smaller than
/// the lattice that is not felt at all ([`super::Row::unfelt`]): what, where,
/// and what to do.
pub fn unfelt_note(rows: &[Row]) -> Option<String> {
    let defaults = || rows.iter().filter(|r| r.default && r.unfelt.is_some());
    let row = defaults().find(|r| r.kernel == "all").or_else(|| defaults().next())?;
    let (u, lattice) = (row.unfelt?, row.lattice_mm?);
    Some(format!(
        "the edge error of {:.2} mm is a feature {:.2} mm across at ({:.1}, {:.1}) mm, smaller than the {} mm lattice, \
         that is not felt at all: the distance from it to the nearest felt edge; enlarge it in the drawing, \
         take part of the drawing with --region X,Y,W,H or #id, or use a profile with a larger surface",
        u.edge_error_mm, u.across_mm, u.x_mm, u.y_mm, lattice
    ))
}

/// `n` with its thousands grouped by commas (1,204).
fn grouped(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// How many separate pieces of `region`'s edge the disc of radius `r` round
/// `c` meets, as far as the coverage at [`CIRCLE_SAMPLES`] points on its
/// circle tells: half the number of changes of coverage round the circle,
/// or 1 when nothing changes on the circle but an edge passes within `r`
/// (a piece wholly inside the disc). Page mm.
pub fn separate_edges(region: &ExactRegion, c: (f64, f64), r: f64) -> usize {
    if !r.is_finite() || r <= 0.0 || !region.edge_may_pass_within(c, r) {
        return 0;
    }
    let at = |k: usize| {
        let a = k as f64 * std::f64::consts::TAU / CIRCLE_SAMPLES as f64;
        region.covers((c.0 + r * a.cos(), c.1 + r * a.sin()))
    };
    let first = at(0);
    let (mut prev, mut changes) = (first, 0);
    for k in 1..CIRCLE_SAMPLES {
        let here = at(k);
        changes += usize::from(here != prev);
        prev = here;
    }
    changes += usize::from(prev != first);
    if changes == 0 { usize::from(region.distance_to_edge_within(c, r).is_some()) } else { changes / 2 }
}

/// One distance layer as the classification sees it: its exact region and
/// its lattice (pitch and first lattice point, page mm).
pub struct Lattice<'a> {
    /// The exact region of the layer's style.
    pub region: &'a ExactRegion,
    /// Lattice pitch, mm.
    pub pitch: f64,
    /// The layer's first lattice point, page mm.
    pub origin: (f64, f64),
}

/// The lattice cells of a kernel's layers with detail finer than their
/// lattice, classified lazily, each once.
pub struct FineDetail<'a> {
    layers: Vec<Lattice<'a>>,
    /// Whether a cell `(layer, column, row)` is finer than its lattice.
    cells: HashMap<(usize, i64, i64), bool>,
}

impl<'a> FineDetail<'a> {
    /// The classification of `layers`' cells (layers with a pitch that is
    /// not above 0 are left out).
    pub fn new(layers: Vec<Lattice<'a>>) -> FineDetail<'a> {
        let layers = layers.into_iter().filter(|l| l.pitch.is_finite() && l.pitch > 0.0).collect();
        FineDetail { layers, cells: HashMap::new() }
    }

    /// Whether page point `p` is in a lattice cell of any of the layers
    /// whose disc of radius one pitch round its centre meets two separate
    /// pieces of the layer's exact edge or more.
    pub fn at(&mut self, p: (f64, f64)) -> bool {
        let FineDetail { layers, cells } = self;
        layers.iter().enumerate().any(|(k, l)| {
            let (i, j) = (((p.0 - l.origin.0) / l.pitch).floor(), ((p.1 - l.origin.1) / l.pitch).floor());
            if !(i.is_finite() && j.is_finite()) {
                return false;
            }
            *cells.entry((k, i as i64, j as i64)).or_insert_with(|| {
                let c = (l.origin.0 + (i + 0.5) * l.pitch, l.origin.1 + (j + 0.5) * l.pitch);
                separate_edges(l.region, c, l.pitch) >= 2
            })
        })
    }

    /// How many cells were found finer than their lattice.
    pub fn places(&self) -> usize {
        self.cells.values().filter(|&&f| f).count()
    }

    /// The coarsest pitch of the layers, mm.
    pub fn lattice_mm(&self) -> Option<f64> {
        self.layers.iter().map(|l| l.pitch).reduce(f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use taxel_compiler::geometry::{FillRule, Polyline};
    use taxel_compiler::latero::LayerGeometry;

    fn rect(x: f64, y: f64, w: f64, h: f64) -> Polyline {
        Polyline { points: vec![(x, y), (x + w, y), (x + w, y + h), (x, y + h)], closed: true }
    }

    fn region(fills: &[Polyline]) -> ExactRegion {
        LayerGeometry { fills: vec![(fills, FillRule::NonZero)], ..Default::default() }.exact()
    }

    /// A strip 0.3 mm wide (narrower than a 0.5 mm pitch): both its sides
    /// pass within 0.5 mm of a point on it, and of a point 0.1 mm beside it;
    /// 0.4 and 0.45 mm beside it only the near side does, 2 mm away neither.
    /// A strip 3 mm wide has one side within reach anywhere.
    #[test]
    fn a_strip_narrower_than_the_pitch_is_two_edges_and_a_wide_one_is_one() {
        let thin = region(&[rect(10.0, 0.0, 0.3, 20.0)]);
        assert_eq!(separate_edges(&thin, (10.15, 10.0), 0.5), 2);
        assert_eq!(separate_edges(&thin, (9.9, 10.0), 0.5), 2);
        assert_eq!(separate_edges(&thin, (9.6, 10.0), 0.5), 1);
        assert_eq!(separate_edges(&thin, (9.55, 10.0), 0.5), 1);
        assert_eq!(separate_edges(&thin, (8.0, 10.0), 0.5), 0);
        let wide = region(&[rect(10.0, 0.0, 3.0, 20.0)]);
        for x in [9.6, 10.2, 11.5, 12.8, 13.4] {
            assert!(separate_edges(&wide, (x, 10.0), 0.5) <= 1, "{x}");
        }
        // The wide strip's corner is one piece of edge, not two.
        assert_eq!(separate_edges(&wide, (10.2, 0.2), 0.5), 1);
    }

    /// A gap of 0.3 mm between two regions is two edges; a square island
    /// 0.2 mm wide wholly inside the circle is one piece of edge, found by
    /// the distance from the centre.
    #[test]
    fn a_narrow_gap_is_two_edges_and_an_island_inside_the_disc_is_one() {
        let gap = region(&[rect(0.0, 0.0, 10.0, 10.0), rect(10.3, 0.0, 10.0, 10.0)]);
        assert_eq!(separate_edges(&gap, (10.15, 5.0), 0.5), 2);
        let island = region(&[rect(5.0, 5.0, 0.2, 0.2)]);
        assert_eq!(separate_edges(&island, (5.1, 5.1), 0.5), 1);
        assert_eq!(separate_edges(&island, (7.0, 7.0), 0.5), 0);
    }

    /// The cells of a 0.5 mm lattice over 40 strips 0.3 mm wide, 0.3 mm
    /// apart: every cell whose disc meets the strips' sides twice is fine,
    /// cells 2 mm away are not, and each cell is classified once.
    #[test]
    fn cells_over_a_grating_of_thin_strips_are_finer_than_the_lattice() {
        let strips: Vec<Polyline> = (0..40).map(|k| rect(10.0 + 0.6 * k as f64, 0.0, 0.3, 20.0)).collect();
        let r = region(&strips);
        let mut d = FineDetail::new(vec![Lattice { region: &r, pitch: 0.5, origin: (0.0, 0.0) }]);
        assert!(d.at((15.0, 10.0)) && d.at((15.2, 10.1)));
        assert_eq!(d.places(), 1, "one cell, asked twice");
        assert!(!d.at((5.0, 10.0)) && !d.at((40.0, 10.0)));
        assert_eq!(d.places(), 1);
        // Every cell over the strips (x from 10.5 to 33.5 mm, well inside) is fine.
        let n = (21..67).filter(|&i| d.at((i as f64 * 0.5 + 0.25, 10.25))).count();
        assert_eq!(n, 46);
        assert_eq!(d.lattice_mm(), Some(0.5));
    }

    fn row(kernel: &str, rms: f64, edge_mm: f64, share: f64) -> Row {
        Row {
            kernel: kernel.into(),
            setting: 0.5,
            unit: "mm".into(),
            default: true,
            compile_ms: 1.0,
            bundle_bytes: 0,
            frame_us: 0.0,
            max_error: rms,
            rms_error: rms,
            step_rms_error: None,
            far_error: None,
            far_rms_error: None,
            corner_error: None,
            edge_error_mm: Some(edge_mm),
            corner_edge_error_mm: None,
            lattice_mm: Some(0.5),
            fine_detail: Some(Share { share, cells: 1204, lattice_mm: 0.5 }),
            unfelt: None,
            error_unit: "10-bit steps".into(),
            frames: 1,
            run_ms: 1.0,
            on_front: true,
        }
    }

    /// The report's "every 3rd of N frames" (it said "3th").
    #[test]
    fn ordinals_read_as_english() {
        let got: Vec<String> = [1, 2, 3, 4, 11, 12, 13, 21, 22, 23, 101, 111, 112].map(crate::report::ordinal).into();
        assert_eq!(
            got,
            ["1st", "2nd", "3rd", "4th", "11th", "12th", "13th", "21st", "22nd", "23rd", "101st", "111th", "112th"]
        );
    }

    /// A feature is unfelt where the outline's farthest place from the
    /// contour is beyond the edge target and smaller than the lattice; the
    /// note names it, of the composite row when there is one.
    #[test]
    fn an_unfelt_feature_is_one_smaller_than_the_lattice_beyond_the_edge_target() {
        use crate::report::{Unfelt, edge::Farthest};
        let at = |distance_mm: f64, across_mm: f64| Some(Farthest { at: (85.64, 32.29), distance_mm, across_mm });
        let u = Unfelt::of(at(1.03, 0.4), Some(0.5)).expect("unfelt");
        assert_eq!((u.x_mm, u.y_mm, u.across_mm, u.edge_error_mm), (85.64, 32.29, 0.4, 1.03));
        // Within the edge target, as large as the lattice, or with no lattice: not.
        assert_eq!(Unfelt::of(at(EDGE_TARGET_MM, 0.4), Some(0.5)), None);
        assert_eq!(Unfelt::of(at(1.03, 0.5), Some(0.5)), None);
        assert_eq!(Unfelt::of(at(1.03, 0.4), None), None);
        assert_eq!(Unfelt::of(None, Some(0.5)), None);
        // Nothing played at all: no one feature's error.
        assert_eq!(Unfelt::of(at(f64::INFINITY, 0.4), Some(0.5)), None);
        let with = |kernel: &str, u: Option<Unfelt>| Row { unfelt: u, ..row(kernel, 34.0, 1.0, 0.1) };
        let other = Unfelt { x_mm: 1.0, y_mm: 2.0, ..u };
        let said = unfelt_note(&[with("grating", Some(other)), with("all", Some(u))]).expect("a note");
        assert!(said.starts_with("the edge error of 1.03 mm is a feature 0.40 mm across at (85.6, 32.3) mm"), "{said}");
        assert!(said.contains("smaller than the 0.5 mm lattice") && said.contains("--region X,Y,W,H or #id"), "{said}");
        assert_eq!(unfelt_note(&[with("grating", None)]), None);
        // Only a default row says it.
        assert_eq!(unfelt_note(&[Row { default: false, ..with("grating", Some(u)) }]), None);
    }

    /// The note is said when the error is above a target and most of it is
    /// finer than the lattice, of the composite row when there is one;
    /// never within the targets, nor when the share is a minority.
    #[test]
    fn the_note_is_said_above_the_targets_when_most_error_is_finer_than_the_lattice() {
        let said = note(&[row("grating", 34.0, 0.02, 0.82)]).expect("a note");
        assert!(
            said.starts_with("82 % of the RMS error") && said.contains("0.5 mm lattice (1,204 lattice cells)"),
            "{said}"
        );
        assert!(said.contains("--region X,Y,W,H or #id"), "{said}");
        // The edge alone above its target.
        assert!(note(&[row("grating", 0.7, 0.4, 0.9)]).is_some());
        // Within both targets, or mostly elsewhere: nothing.
        assert_eq!(note(&[row("grating", 0.7, 0.04, 0.99)]), None);
        assert_eq!(note(&[row("grating", 34.0, 1.5, 0.4)]), None);
        // The composite's figure wins over a kernel's.
        let rows = [row("grating", 34.0, 1.5, 0.9), row("all", 34.0, 1.5, 0.3)];
        assert_eq!(note(&rows), None);
        assert_eq!(grouped(0), "0");
        assert_eq!(grouped(999), "999");
        assert_eq!(grouped(1_234_567), "1,234,567");
    }
}
