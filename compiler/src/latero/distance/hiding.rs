//! The occluders that can change a layer's field. A map's region is an
//! occluder of every region of another style painted after it whose box
//! meets its own, though it only borders them: on a map of 1,200 states,
//! each layer had 350 occluders, whose union and distances were a quarter of
//! the build, and none of which hid anything.
//!
//! The field is `min(s, −d_W)` (with the clips and the page), `W` the
//! occluders' union and `d_W` its signed distance, clamped to `±cap`. Let
//! `K` be the occluders whose inside may meet the fills' (by
//! [`apart`]), and `A` an occluder apart from the fills whose box, grown by
//! `2 cap`, meets no box where a member of `K` meets a fill. Then leaving `A`
//! out changes no clamped sample:
//!
//! - `A`'s inside holds no point inside the fills, so at a point inside
//!   them the nearest point of `A` lies across the fills' outline and
//!   `dist(p, A) ≥ s`: outside `W`, `min(s, dist(p, W))` is the same with or
//!   without `A`.
//! - Inside `W`, `−d_W` changes only where the nearest point outside `W`
//!   without `A` lies inside `A`, and the value can only matter (be below `s`
//!   and above `−cap`) where both that point and the fills' outline within
//!   `K` lie within `cap` of the sample: within `2 cap` of each other,
//!   which the boxes rule out.
//!
//! With no member of `K` at all, the layer has no occluders.

use std::sync::OnceLock;

use rayon::prelude::*;

use crate::geometry::apart::{Filled, apart};
use crate::geometry::{FillRule, Polyline, bounds, common_bounds};
use crate::spatial::{self, Bbox, BoxIndex};

/// The most points (an occluder's and a fill's, summed over the pairs whose
/// boxes meet) one layer's look at its occluders may read: the 1,200-state
/// map's layers read 110,000 to 118,000, the Wikipedia world map's land
/// 2.7 million.
const MAX_WORK: usize = 20_000_000;

/// ... and at most this many points for each of the occluders' own, and
/// [`WORK_FLOOR`] more: what leaving an occluder out saves follows its own
/// points (its union, its distances), what looking costs follows the fills
/// it is looked at against.
const WORK_PER_POINT: usize = 16;
const WORK_FLOOR: usize = 100_000;

/// The occluders of `fills` (in their order) that can change the field whose
/// samples are clamped to `±cap`.
pub(super) fn occluders_that_hide<'a>(
    fills: &[(&'a [Polyline], FillRule)],
    occluders: &[(&'a [Polyline], FillRule)],
    cap: f64,
) -> Vec<(&'a [Polyline], FillRule)> {
    if occluders.is_empty() || fills.is_empty() || !(cap.is_finite() && cap >= 0.0) {
        return occluders.to_vec();
    }
    let no_box = (f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
    let fill_boxes: Vec<Bbox> = fills.iter().map(|(pls, _)| bounds(pls).unwrap_or(no_box)).collect();
    let index = BoxIndex::new(&fill_boxes);
    // The work is bounded: past it, every occluder is kept, as before they
    // were looked at (a thousand long strokes' fills across a thousand
    // regions would be a million pairs).
    let points = |pls: &[Polyline]| pls.iter().map(|p| p.points.len()).sum::<usize>();
    let fill_points: Vec<usize> = fills.iter().map(|(pls, _)| points(pls)).collect();
    let mut work = 0usize;
    let own_points: usize = occluders.iter().map(|(pls, _)| points(pls)).sum();
    let most = MAX_WORK.min(own_points.saturating_mul(WORK_PER_POINT).saturating_add(WORK_FLOOR));
    for (pls, _) in occluders {
        let own = points(pls);
        for k in bounds(pls).into_iter().flat_map(|b| index.meeting(b)) {
            work = work.saturating_add(own + fill_points[k]);
        }
        if work > most {
            return occluders.to_vec();
        }
    }
    let prepared: Vec<OnceLock<Filled<'a>>> = fills.iter().map(|_| OnceLock::new()).collect();
    let fill = |k: usize| prepared[k].get_or_init(|| Filled::new(fills[k].0, fills[k].1));
    // Each occluder's box, and where it may cover a fill: the common boxes
    // of the pairs that are not apart (`None`: anywhere).
    let looked: Vec<(Option<Bbox>, Option<Vec<Bbox>>)> = occluders
        .par_iter()
        .map(|&(pls, rule)| {
            let Some(b) = bounds(pls) else { return (None, Some(Vec::new())) };
            let o = Filled::new(pls, rule);
            if !(b.0.is_finite() && b.1.is_finite() && b.2.is_finite() && b.3.is_finite()) {
                return (Some(b), None);
            }
            let covers =
                index.meeting(b).filter(|&k| !apart(&o, fill(k))).map(|k| common_bounds(b, fill_boxes[k])).collect();
            (Some(b), Some(covers))
        })
        .collect();
    if looked.iter().any(|(_, covers)| covers.is_none()) {
        return occluders.to_vec();
    }
    let regions: Vec<Bbox> = looked.iter().flat_map(|(_, c)| c.iter().flatten().copied()).collect();
    if regions.is_empty() {
        return Vec::new();
    }
    let near = BoxIndex::new(&regions);
    let margin = 2.0 * cap;
    occluders
        .iter()
        .zip(&looked)
        .filter(|(_, (b, covers))| {
            covers.as_ref().is_some_and(|c| !c.is_empty())
                || b.is_some_and(|b| near.meeting(spatial::grow(b, margin)).next().is_some())
        })
        .map(|(o, _)| *o)
        .collect()
}

#[cfg(test)]
mod tests;
