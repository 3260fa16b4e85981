//! Confusable gratings (T0401, T0402): distinct gratings near each other
//! whose wavelengths readers cannot tell apart, or may confuse.

use super::gaps::gap;
use super::{ADJACENT_MM, WAVELENGTH_ERROR_MM, WAVELENGTH_WARN_MM, at};
use crate::diagnostic::Diagnostic;
use crate::latero::{Feature, FeatureKind};
use crate::spatial;

/// Whether gratings of these (wavelength, angle) could be confused: the same
/// angle (within 1°) and wavelengths that differ, by less than [`WAVELENGTH_WARN_MM`].
fn confusable(la: f64, ta: f64, lb: f64, tb: f64) -> bool {
    let turn = (ta - tb).rem_euclid(180.0);
    let d = (la - lb).abs();
    !(1.0..=179.0).contains(&turn) && d > 1e-9 && d < WAVELENGTH_WARN_MM
}

/// T0401 and T0402: distinct gratings within [`ADJACENT_MM`] of each other
/// whose textures can be confused, one diagnostic per pair (at the later
/// feature). Features are grouped by texture, and only groups that can be
/// confused are searched, so a drawing whose textures all differ well (the
/// automatic style sheet's) costs one pass over its gratings.
pub(super) fn confusable_gratings(f: &[Feature], diags: &mut Vec<Diagnostic>) {
    let mut textures: Vec<((f64, f64), Vec<usize>)> = Vec::new();
    for (i, x) in f.iter().enumerate() {
        if let FeatureKind::Grating { wavelength_mm, angle_deg } = x.kind {
            match textures
                .iter_mut()
                .find(|(t, _)| t.0.to_bits() == wavelength_mm.to_bits() && t.1.to_bits() == angle_deg.to_bits())
            {
                Some((_, members)) => members.push(i),
                None => textures.push(((wavelength_mm, angle_deg), vec![i])),
            }
        }
    }
    let mut found: Vec<(usize, usize, f64)> = Vec::new();
    for (p, ((la, ta), ps)) in textures.iter().enumerate() {
        for ((lb, tb), qs) in &textures[p + 1..] {
            if !confusable(*la, *ta, *lb, *tb) {
                continue;
            }
            let qboxes: Vec<_> = qs.iter().map(|&q| f[q].bbox).collect();
            let qindex = spatial::BoxIndex::new(&qboxes);
            for &i in ps {
                for k in qindex.meeting(spatial::grow(f[i].bbox, ADJACENT_MM)) {
                    let (a, b) = (i.min(qs[k]), i.max(qs[k]));
                    if f[a].elem != f[b].elem {
                        let g = gap(&f[a], &f[b], ADJACENT_MM, |r, stop| {
                            spatial::min_outline_distance(&f[a].outline, &f[b].outline, r, stop)
                        });
                        if g <= ADJACENT_MM {
                            found.push((a, b, g));
                        }
                    }
                }
            }
        }
    }
    found.sort_unstable_by_key(|&(a, b, _)| (a, b));
    for (a, b) in found.into_iter().map(|(a, b, _)| (&f[a], &f[b])) {
        let (FeatureKind::Grating { wavelength_mm: la, .. }, FeatureKind::Grating { wavelength_mm: lb, .. }) =
            (a.kind, b.kind)
        else {
            continue;
        };
        let d = (la - lb).abs();
        let msg =
            format!("adjacent gratings #{} ({la} mm) and this one ({lb} mm) differ by {d:.2} mm in wavelength", a.name);
        let diag = if d < WAVELENGTH_ERROR_MM {
            Diagnostic::error("T0401", format!("{msg}; readers cannot tell them apart"))
        } else {
            Diagnostic::warning("T0402", format!("{msg}; readers may confuse them"))
        };
        diags.push(at(
            diag.with_help(
                "make neighbouring wavelengths differ by 3 mm or more (2 mm and 6 mm work well), or change the angle",
            ),
            b,
        ));
    }
}
