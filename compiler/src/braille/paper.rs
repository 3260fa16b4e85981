//! Braille cells on the page: NLS Specification 800 geometry. The cells
//! themselves come from the shared braille service ([`crate::braille`]).

pub use crate::braille::Cell;

/// Dot pitch within a cell (NLS Spec 800: 0.092 in).
pub const DOT_PITCH_MM: f64 = 2.34;
/// Distance between corresponding dots of neighbouring cells (0.245 in).
pub const CELL_PITCH_MM: f64 = 6.2;
/// Distance between corresponding dots of neighbouring lines (0.400 in).
pub const LINE_PITCH_MM: f64 = 10.2;

/// Dot centres of a run of cells whose first cell's left edge is at `x0` and
/// whose six-dot cells' lowest dots rest on the baseline `baseline` (page
/// mm), dots of radius `r`. Dots 7 and 8 (eight-dot tables: Japanese
/// kantenji, computer braille) are a row below, under the baseline.
pub fn layout(cells: &[Cell], x0: f64, baseline: f64, r: f64) -> Vec<(f64, f64)> {
    const ROWS: [(f64, f64); 8] =
        [(0.0, 0.0), (0.0, 1.0), (0.0, 2.0), (1.0, 0.0), (1.0, 1.0), (1.0, 2.0), (0.0, 3.0), (1.0, 3.0)];
    let mut out = Vec::new();
    for (k, &c) in cells.iter().enumerate() {
        let left = x0 + k as f64 * CELL_PITCH_MM + r;
        for (dot, &(col, row)) in ROWS.iter().enumerate() {
            if c & (1 << dot) != 0 {
                out.push((left + col * DOT_PITCH_MM, baseline - r - (2.0 - row) * DOT_PITCH_MM));
            }
        }
    }
    out
}

/// Width of a run of `n` cells of dots of radius `r`, from the first dot's left edge to the last's right edge.
pub fn run_width(n: usize, r: f64) -> f64 {
    if n == 0 { 0.0 } else { (n - 1) as f64 * CELL_PITCH_MM + DOT_PITCH_MM + 2.0 * r }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_uses_nls_spec_800_geometry() {
        // The full cell (dots 1-6) twice: dot 1 of the second cell is 6.2 mm right of the first's.
        let d = layout(&[0x3f, 0x3f], 10.0, 50.0, 0.72);
        assert_eq!(d.len(), 12);
        assert!((d[6].0 - d[0].0 - 6.2).abs() < 1e-12);
        // dot 4 is 2.34 mm right of dot 1, dot 2 is 2.34 mm below dot 1.
        assert!((d[3].0 - d[0].0 - 2.34).abs() < 1e-12);
        assert!((d[1].1 - d[0].1 - 2.34).abs() < 1e-12);
        // The lowest dots rest on the baseline.
        assert!((d[2].1 + 0.72 - 50.0).abs() < 1e-12);
        // Dots 7 and 8 are a pitch below dots 3 and 6.
        let d = layout(&[0xc0 | 0x24], 0.0, 50.0, 0.72);
        assert_eq!(d.len(), 4);
        assert!((d[2].1 - d[0].1 - 2.34).abs() < 1e-12 && (d[2].0 - d[0].0).abs() < 1e-12);
        assert!((d[3].0 - d[1].0).abs() < 1e-12 && (d[3].0 - d[2].0 - 2.34).abs() < 1e-12);
    }
}
