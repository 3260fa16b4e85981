//! Shared actuators: two virtual points active at once that need the same
//! physical actuator (neighbouring points of one stroke, or strokes that
//! overlap in time).
//!
//! **Decision:** the table keeps each point's own energy shares, and the
//! runtime combines whatever is active on an actuator at each instant by
//! energy, `A = min(1, √(Σ A_i²))` (the energy summation that the phantom
//! model rests on). Combining at play time is exact under the ramps and for
//! strokes whose overlap only the player sees; the compiler predicts the
//! clamping here, from the tick intervals of the table (ignoring the ramps,
//! which can only lower the sum), and says where it will happen: a warning
//! (T0512) when separate strokes overlap on an actuator, a note (T0515) when
//! the neighbouring points of one stroke do (inherent to apparent motion at
//! high intensity; only the moments of overlap lose some amplitude).

use std::collections::BTreeMap;

use taxel_format::Stroke;

use super::BrushRequest;
use crate::diagnostic::Diagnostic;

/// Energy above full drive by more than this counts as clamping (f32 shares
/// that sum to exactly 1 may round a hair above it).
const CLAMP_TOLERANCE: f64 = 1e-5;

struct Contribution {
    on: u64,
    end: u64,
    energy: f64,
    stroke: usize,
}

/// Warns (T0512) wherever the energy on one actuator exceeds full drive.
/// `strokes` pairs each scheduled stroke with its request's index.
pub(crate) fn check_shared(
    strokes: &[(usize, &Stroke)],
    requests: &[BrushRequest],
    cols: u16,
    rate_hz: u32,
    diags: &mut Vec<Diagnostic>,
) {
    let mut per_actuator: BTreeMap<u16, Vec<Contribution>> = BTreeMap::new();
    for (i, &(_, s)) in strokes.iter().enumerate() {
        for p in &s.points {
            let on = s.start.0 + p.onset as u64;
            for d in &p.drives {
                let e = d.intensity as f64 * d.intensity as f64;
                if e > 0.0 {
                    per_actuator.entry(d.actuator.0).or_default().push(Contribution {
                        on,
                        end: on + p.duration as u64,
                        energy: e,
                        stroke: i,
                    });
                }
            }
        }
    }
    // Worst instant per actuator: the energy sum is a step function that only
    // rises at onsets, so its maximum is at some onset.
    let mut groups: BTreeMap<Vec<usize>, (Vec<u16>, f64, u64)> = BTreeMap::new();
    for (actuator, list) in &per_actuator {
        let mut events: Vec<(u64, bool, f64)> = Vec::with_capacity(list.len() * 2);
        for c in list {
            events.push((c.on, true, c.energy));
            events.push((c.end, false, c.energy));
        }
        // Ends before starts at the same tick: activities are half-open.
        events.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.cmp(&b.1)));
        let (mut sum, mut worst, mut when) = (0.0f64, 0.0f64, 0u64);
        for (t, start, e) in events {
            if start {
                sum += e;
                if sum > worst {
                    (worst, when) = (sum, t);
                }
            } else {
                sum -= e;
            }
        }
        if worst > 1.0 + CLAMP_TOLERANCE {
            let mut who: Vec<usize> = list.iter().filter(|c| c.on <= when && when < c.end).map(|c| c.stroke).collect();
            who.sort_unstable();
            who.dedup();
            let g = groups.entry(who).or_insert((Vec::new(), 0.0, when));
            g.0.push(*actuator);
            if worst > g.1 {
                (g.1, g.2) = (worst, when);
            }
        }
    }
    for (who, (actuators, worst, when)) in groups {
        let names: Vec<String> =
            actuators.iter().map(|&a| format!("{a} (row {}, column {})", a / cols.max(1), a % cols.max(1))).collect();
        let at_ms = when as f64 * 1000.0 / rate_hz as f64;
        let first = who.first().and_then(|&i| strokes.get(i)).and_then(|&(r, _)| requests.get(r));
        let others: Vec<String> = who
            .iter()
            .skip(1)
            .filter_map(|&i| strokes.get(i).and_then(|&(r, _)| requests.get(r)))
            .map(|r| format!("#{}", r.element))
            .collect();
        let mut message = format!(
            "virtual points active at the same time need {worst:.2} times full energy on actuator{} {} at {at_ms:.0} ms; \
             combined by energy and clamped to full drive",
            if names.len() > 1 { "s" } else { "" },
            names.join(", "),
        );
        if !others.is_empty() {
            message += &format!(" (overlapping {})", others.join(", "));
        }
        let scale = 1.0 / worst.sqrt();
        // Overlap between neighbouring points of one stroke is how apparent
        // motion works, and at full intensity it is expected: a note. Strokes
        // the author placed over each other are worth a warning.
        let d = if who.len() > 1 { Diagnostic::warning("T0512", message) } else { Diagnostic::note("T0515", message) };
        let mut d = d.with_help(format!(
            "scale the intensity by {scale:.2} or less, or separate the strokes in time, to avoid clamping"
        ));
        if let Some(r) = first {
            if !r.element.is_empty() {
                d = d.with_element(&r.element);
            }
            d.line = r.line;
        }
        diags.push(d);
    }
}
