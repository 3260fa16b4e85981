//! Fuzzes the exploration-trace reader: any bytes either parse into a trace
//! whose samples keep the documented invariants (finite numbers, times not
//! negative and never decreasing) and whose ticks interpolate inside the
//! samples' box, or give an error; never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use taxel_runtime::trace::Trace;

fuzz_target!(|data: &[u8]| {
    let Ok(t) = Trace::parse(data) else { return };
    let s = t.samples();
    assert!(!s.is_empty());
    assert!(s.iter().all(|s| s.t_ms.is_finite() && s.t_ms >= 0.0 && s.x_mm.is_finite() && s.y_mm.is_finite()));
    assert!(s.windows(2).all(|w| w[0].t_ms <= w[1].t_ms));
    let (x0, x1) = s.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, s| (a.0.min(s.x_mm), a.1.max(s.x_mm)));
    for (_, p) in t.ticks(1000).take(10_000) {
        assert!(p.x_mm >= x0 - 1e-9 * x0.abs().max(1.0) && p.x_mm <= x1 + 1e-9 * x1.abs().max(1.0));
    }
});
