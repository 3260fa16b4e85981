//! The actuator grid and the phantom (energy) model of seed 001.
//!
//! Actuator `(r, c)` sits at page `(c · pitch_x, r · pitch_y)` and has index
//! `cols · r + c`. A virtual point anywhere inside the grid is produced by the
//! up-to-four actuators at the corners of its cell, with bilinear weights used
//! as *energy* shares: `A_i = √w_i · Av`, so `Σ A_i² = Av²`. On a grid line this
//! is exactly the paper's Eq. 4 (`A1 = √(1−β)·Av`, `A2 = √β·Av`); on an
//! actuator it is that actuator alone.

use taxel_format::{ActuatorIndex, DeviceProfile};

/// Weights at or below this share of the energy are dropped: they come from
/// rounding when a point sits on a grid line or an actuator, and an actuator
/// driven at `√1e-9 ≈ 3e-5` of the intensity is noise, not a phantom.
const NEGLIGIBLE_WEIGHT: f64 = 1e-9;

/// Distance (mm) within which a computed point is snapped onto a grid line,
/// so that points on lines and actuators map to two or one actuators exactly
/// (grown with the grid's size by [`GridGeometry::tolerance`]).
pub(crate) const SNAP_MM: f64 = 1e-7;

/// The geometry of a vibrotactile grid, in page millimetres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridGeometry {
    /// Actuator rows.
    pub rows: u16,
    /// Actuator columns.
    pub cols: u16,
    /// Distance between columns (mm).
    pub pitch_x: f64,
    /// Distance between rows (mm).
    pub pitch_y: f64,
}

/// One physical actuator driven by a virtual point.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PhysicalDrive {
    /// Row-major actuator index.
    pub actuator: ActuatorIndex,
    /// Intensity, 0..=1 of full drive.
    pub intensity: f64,
}

/// The (at most four) actuators that produce one virtual point. Fixed size so
/// that planning a stroke allocates nothing per point.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Drives {
    items: [PhysicalDrive; 4],
    len: u8,
}

impl Drives {
    /// The drives, in row-major order of their actuators.
    pub fn as_slice(&self) -> &[PhysicalDrive] {
        &self.items[..self.len as usize]
    }

    fn push(&mut self, d: PhysicalDrive) {
        if let Some(slot) = self.items.get_mut(self.len as usize) {
            *slot = d;
            self.len += 1;
        }
    }

    /// Sum of the squared intensities (the energy the point delivers).
    pub fn energy(&self) -> f64 {
        self.as_slice().iter().map(|d| d.intensity * d.intensity).sum()
    }
}

impl GridGeometry {
    /// The grid of a profile (any family; only grid profiles make sense here).
    pub fn from_profile(p: &DeviceProfile) -> Self {
        GridGeometry { rows: p.rows, cols: p.cols, pitch_x: p.pitch_x_mm as f64, pitch_y: p.pitch_y_mm as f64 }
    }

    /// Page x of the last column (the grid's width in millimetres).
    pub fn width(&self) -> f64 {
        (self.cols.max(1) - 1) as f64 * self.pitch_x
    }

    /// Page y of the last row (the grid's height in millimetres).
    pub fn height(&self) -> f64 {
        (self.rows.max(1) - 1) as f64 * self.pitch_y
    }

    /// Whether a page point lies on the grid (edges included).
    pub fn contains(&self, x: f64, y: f64) -> bool {
        (0.0..=self.width()).contains(&x) && (0.0..=self.height()).contains(&y)
    }

    /// The nearest point of the grid's rectangle.
    pub fn clamp(&self, x: f64, y: f64) -> (f64, f64) {
        (x.clamp(0.0, self.width()), y.clamp(0.0, self.height()))
    }

    /// The distance (mm) below which two computed positions are the same: 1e-7 mm,
    /// or more on grids so large that f64 rounding of their coordinates is coarser.
    pub(crate) fn tolerance(&self) -> f64 {
        SNAP_MM.max(1e-12 * (self.width() + self.height()))
    }

    /// Moves a coordinate that is within [`GridGeometry::tolerance`] of a grid line onto it.
    pub(crate) fn snap(&self, x: f64, y: f64) -> (f64, f64) {
        let tol = self.tolerance();
        let snap1 = |v: f64, pitch: f64, n: u16| {
            let k = (v / pitch).round().clamp(0.0, (n.max(1) - 1) as f64);
            let line = k * pitch;
            if (v - line).abs() <= tol { line } else { v }
        };
        (snap1(x, self.pitch_x, self.cols), snap1(y, self.pitch_y, self.rows))
    }

    /// The actuators, and their intensities, that produce a phantom of
    /// intensity `av` at page `(x, y)` (clamped to the grid): bilinear energy
    /// shares over the point's cell.
    pub fn phantom(&self, x: f64, y: f64, av: f64) -> Drives {
        fn cell(v: f64, pitch: f64, n: u16) -> (u16, f64) {
            if n <= 1 {
                return (0, 0.0);
            }
            let u = (v / pitch).clamp(0.0, (n - 1) as f64);
            let i = (u.floor() as u16).min(n - 2);
            (i, (u - i as f64).clamp(0.0, 1.0))
        }
        let (x, y) = self.clamp(x, y);
        let (c0, fx) = cell(x, self.pitch_x, self.cols);
        let (r0, fy) = cell(y, self.pitch_y, self.rows);
        let corners = [
            (r0, c0, (1.0 - fx) * (1.0 - fy)),
            (r0, c0 + 1, fx * (1.0 - fy)),
            (r0 + 1, c0, (1.0 - fx) * fy),
            (r0 + 1, c0 + 1, fx * fy),
        ];
        let mut out = Drives::default();
        for (r, c, w) in corners {
            if w > NEGLIGIBLE_WEIGHT && r < self.rows && c < self.cols {
                let index = r as u32 * self.cols as u32 + c as u32;
                out.push(PhysicalDrive {
                    actuator: ActuatorIndex(index as u16),
                    intensity: (w.sqrt() * av).clamp(0.0, 1.0),
                });
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> GridGeometry {
        GridGeometry { rows: 3, cols: 4, pitch_x: 63.0, pitch_y: 63.0 }
    }

    #[test]
    fn point_on_an_actuator_drives_it_alone() {
        let d = grid().phantom(126.0, 63.0, 0.8);
        assert_eq!(d.as_slice(), &[PhysicalDrive { actuator: ActuatorIndex(6), intensity: 0.8 }]);
    }

    #[test]
    fn point_on_a_row_line_is_eq_4() {
        // β = 0.25 of the way from (0,1) to (0,2): A1 = √0.75·Av, A2 = √0.25·Av.
        let d = grid().phantom(63.0 + 0.25 * 63.0, 0.0, 1.0);
        let s = d.as_slice();
        assert_eq!(s.len(), 2);
        assert_eq!((s[0].actuator, s[1].actuator), (ActuatorIndex(1), ActuatorIndex(2)));
        assert!((s[0].intensity - 0.75f64.sqrt()).abs() < 1e-12);
        assert!((s[1].intensity - 0.5).abs() < 1e-12);
    }

    #[test]
    fn far_corner_and_single_row_grids() {
        let d = grid().phantom(189.0, 126.0, 1.0);
        assert_eq!(d.as_slice(), &[PhysicalDrive { actuator: ActuatorIndex(11), intensity: 1.0 }]);
        let line = GridGeometry { rows: 1, cols: 3, pitch_x: 10.0, pitch_y: 10.0 };
        let d = line.phantom(15.0, 0.0, 1.0);
        assert_eq!(d.as_slice().len(), 2);
        assert!((d.energy() - 1.0).abs() < 1e-12);
        let dot = GridGeometry { rows: 1, cols: 1, pitch_x: 10.0, pitch_y: 10.0 };
        assert_eq!(dot.phantom(5.0, 5.0, 0.5).as_slice().len(), 1);
    }
}
