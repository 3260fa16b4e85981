//! Device profiles: the geometry, rate and ranges of one tactile device.
//!
//! A profile is data, not code. It is stored in every bundle's manifest, so a
//! player needs nothing but the bundle; the `std` feature adds TOML parsing and
//! the built-in profiles (`stress2`, `brush-4x3`, `finger3`, and the pin
//! arrays `dotpad`, `monarch`, `graphiti`, `hyperbraille`, and the print
//! media `swell-a4`, `swell-letter`, `tiger-20dpi`, `emboss-braille-grid`,
//! `print3d`).

use crate::units::FixedStr;

/// A profile name: at most 31 bytes of UTF-8.
pub type ProfileName = FixedStr<32>;

/// The device families taxel can drive. Each has its own player in the runtime.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Family {
    /// A laterotactile pin array such as STRESS² (dots, vibration, gratings).
    Laterotactile,
    /// A sparse grid of vibrotactile tactors (Tactile Brush strokes).
    Grid,
    /// A finger-mounted ring of three actuators (Left, Down, Right) fed by a height field.
    Finger,
    /// A refreshable pin-matrix display (Dot Pad, Monarch, Graphiti, HyperBraille).
    Pins,
    /// Print media: swell paper, graphics embossers and 3D-printed reliefs.
    /// A print profile makes device files (PDF, PNG, STL), never bundles: no
    /// manifest holds this family ([`Family::from_code`] never returns it).
    Print,
}

impl Family {
    /// The family's code in a bundle manifest.
    pub fn code(self) -> u8 {
        match self {
            Family::Laterotactile => 1,
            Family::Grid => 2,
            Family::Finger => 3,
            Family::Pins => 4,
            // Never written: a bundle cannot be made for a print profile.
            Family::Print => 5,
        }
    }

    /// The family for a manifest code (1 to 4; print profiles have no bundles).
    pub fn from_code(code: u8) -> Option<Self> {
        match code {
            1 => Some(Family::Laterotactile),
            2 => Some(Family::Grid),
            3 => Some(Family::Finger),
            4 => Some(Family::Pins),
            _ => None,
        }
    }

    /// The name used in profile files and messages.
    pub fn name(self) -> &'static str {
        match self {
            Family::Laterotactile => "laterotactile",
            Family::Grid => "grid",
            Family::Finger => "finger",
            Family::Pins => "pins",
            Family::Print => "print",
        }
    }
}

impl core::fmt::Display for Family {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// Parameters that only a vibrotactile grid has.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridParams {
    /// Lowest carrier frequency the tactors accept, in hertz.
    pub carrier_min_hz: f32,
    /// Highest carrier frequency the tactors accept, in hertz.
    pub carrier_max_hz: f32,
    /// Sample rate of the audio interface that drives the tactors.
    pub audio_rate_hz: u32,
    /// Length of the onset and offset ramps that keep a tactor from clicking, in milliseconds.
    pub ramp_ms: f32,
}

/// Parameters that only the finger-mounted device has.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FingerParams {
    /// Largest vibration rhythm R (the paper's unit); the modulating period is `T = (105 - R) / 0.5` ms.
    pub rhythm_max: f32,
    /// Largest vibration intensity D (0..=1 of full drive).
    pub intensity_max: f32,
    /// Slope (|dh/ds|, dimensionless) below which the surface counts as flat.
    pub flat_slope: f32,
    /// Number of touch samples over which the motion direction is averaged.
    pub direction_window: u32,
    /// Smallest movement, in millimetres over the window, that gives the finger a direction.
    pub min_move_mm: f32,
}

/// Parameters that only a pin-matrix display has. Columns, rows and pitch are
/// the profile's common fields; the surface is the pin area
/// (`cols * pitch_x` by `rows * pitch_y`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PinParams {
    /// Raised height levels above flush: 1 for a binary display, 4 for the
    /// Graphiti's heights 0 to 4. At most [`MAX_PIN_HEIGHT`].
    pub height_levels: u8,
    /// Step of the device's own blink rate in milliseconds; 0 when pins cannot blink.
    pub blink_step_ms: u16,
    /// Rows of the device's braille cell: 3 (six dots, 2 x 3 pins) or 4 (eight dots, 2 x 4 pins).
    pub cell_rows: u8,
    /// Blank pin columns between braille cells (0 to 8).
    pub cell_gap_cols: u8,
    /// Blank pin rows between braille lines (0 to 8).
    pub line_gap_rows: u8,
    /// Cells of the separate braille text line; 0 when the device has none.
    pub text_cells: u16,
    /// Time to refresh the whole display in milliseconds; 0 when not published.
    pub refresh_ms: u32,
}

/// Largest raised height level of a pin.
pub const MAX_PIN_HEIGHT: u8 = 15;
/// Largest number of pins of a pin-matrix profile (`rows * cols`).
pub const MAX_PINS: u32 = 65_536;
/// Largest number of cells of a profile's braille text line.
pub const MAX_TEXT_LINE_CELLS: u16 = 256;

impl PinParams {
    /// Columns from one braille cell to the next (`2 + cell_gap_cols`).
    pub fn cell_pitch_cols(&self) -> u32 {
        2 + self.cell_gap_cols as u32
    }

    /// Rows from one braille line to the next (`cell_rows + line_gap_rows`).
    pub fn line_pitch_rows(&self) -> u32 {
        self.cell_rows as u32 + self.line_gap_rows as u32
    }

    /// Whether the device can blink pins.
    pub fn can_blink(&self) -> bool {
        self.blink_step_ms > 0
    }
}

/// The kind of print medium, which decides how a drawing is legalised and
/// which files it gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Medium {
    /// Swell (microcapsule) paper: black vector art at true size, raised by heat.
    Swell,
    /// A graphics embosser: dots on the embosser's grid (`grid_mm`).
    Emboss,
    /// A 3D-printed relief: a base plate with raised features.
    Relief,
}

impl Medium {
    /// The name used in profile files.
    pub fn name(self) -> &'static str {
        match self {
            Medium::Swell => "swell",
            Medium::Emboss => "emboss",
            Medium::Relief => "relief",
        }
    }

    /// The medium of a profile file's name.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "swell" => Some(Medium::Swell),
            "emboss" => Some(Medium::Emboss),
            "relief" => Some(Medium::Relief),
            _ => None,
        }
    }
}

/// Parameters that only print media have (`docs/print.md` gives each
/// built-in value its source). The surface is the paper less its margins;
/// the array is the grid: the embosser's dots, or for swell paper and reliefs
/// the raster step of the preview, the design rules and the relief's mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrintParams {
    /// Swell paper, embosser or relief.
    pub medium: Medium,
    /// Paper (or plate) width, in millimetres.
    pub paper_w_mm: f32,
    /// Paper (or plate) height, in millimetres.
    pub paper_h_mm: f32,
    /// Blank margin on every side, in millimetres.
    pub margin_mm: f32,
    /// The grid: an embosser's dot spacing, else the raster step (mm).
    pub grid_mm: f32,
    /// Dot heights an embosser has (1 when one); ignored elsewhere.
    pub dot_levels: u8,
    /// Narrowest raised line the medium keeps (mm).
    pub min_line_mm: f32,
    /// Narrowest gap between raised features a finger tells apart (mm).
    pub min_gap_mm: f32,
    /// Smallest side of a textured area that is felt as a texture (mm).
    pub min_texture_mm: f32,
    /// Size of a point symbol (mm).
    pub symbol_mm: f32,
    /// Braille dot base diameter (mm).
    pub braille_dot_mm: f32,
    /// Braille dot spacing within a cell (mm).
    pub braille_dot_pitch_mm: f32,
    /// Braille cell spacing, from a cell to the next (mm).
    pub braille_cell_mm: f32,
    /// Braille line spacing (mm).
    pub braille_line_mm: f32,
    /// A relief's base plate thickness (mm); 0 on paper.
    pub base_mm: f32,
    /// Height of a relief's lines, symbols and braille above the plate (mm).
    pub raise_mm: f32,
    /// Height of a relief's textures above the plate (mm).
    pub texture_mm: f32,
}

/// Largest number of grid points of a print profile (`rows * cols`).
pub const MAX_PRINT_GRID: u32 = 1 << 24;

impl PrintParams {
    /// The printable area (paper less margins), `(width, height)` in mm.
    pub fn surface_mm(&self) -> (f32, f32) {
        (self.paper_w_mm - 2.0 * self.margin_mm, self.paper_h_mm - 2.0 * self.margin_mm)
    }

    /// The grid points across and down the printable area, `(cols, rows)`.
    pub fn grid_size(&self) -> (u64, u64) {
        let (w, h) = self.surface_mm();
        // In f64, a millionth up: 266.7 mm at 1.27 mm is 210 points, not
        // 209.99998 rounded down.
        let g = self.grid_mm as f64;
        let n = |v: f32| {
            let q = v as f64 / g * (1.0 + 1e-6);
            // A cast truncates, which for a positive value is its floor (and
            // needs no `std`: this crate is `no_std`).
            if q.is_finite() && q > 0.0 { q.min(1e9) as u64 } else { 0 }
        };
        (n(w), n(h))
    }

    /// Checks the print fields; `(key, expected)` on the first problem.
    pub fn check(&self) -> Result<(), (&'static str, &'static str)> {
        let within = |v: f32, lo: f32, hi: f32| v.is_finite() && v >= lo && v <= hi;
        if !within(self.paper_w_mm, 20.0, 2000.0) {
            return Err(("print.paper_width_mm", "from 20 to 2000 mm"));
        }
        if !within(self.paper_h_mm, 20.0, 2000.0) {
            return Err(("print.paper_height_mm", "from 20 to 2000 mm"));
        }
        let (w, h) = self.surface_mm();
        if !within(self.margin_mm, 0.0, 200.0) || w < 10.0 || h < 10.0 {
            return Err(("print.margin_mm", "from 0 to 200 mm, leaving at least 10 x 10 mm to print on"));
        }
        if !within(self.grid_mm, 0.05, 10.0) {
            return Err(("print.grid_mm", "from 0.05 to 10 mm"));
        }
        let (c, r) = self.grid_size();
        if c.saturating_mul(r) > MAX_PRINT_GRID as u64 || c == 0 || r == 0 {
            return Err(("print.grid_mm", "a grid of at most 16777216 points on the printable area"));
        }
        if self.dot_levels == 0 || self.dot_levels > 8 {
            return Err(("print.dot_levels", "from 1 to 8 dot heights"));
        }
        for (v, key, lo, hi, what) in [
            (self.min_line_mm, "print.min_line_mm", 0.05, 10.0, "from 0.05 to 10 mm"),
            (self.min_gap_mm, "print.min_gap_mm", 0.05, 20.0, "from 0.05 to 20 mm"),
            (self.min_texture_mm, "print.min_texture_mm", 1.0, 100.0, "from 1 to 100 mm"),
            (self.symbol_mm, "print.symbol_mm", 1.0, 50.0, "from 1 to 50 mm"),
            (self.braille_dot_mm, "print.braille_dot_mm", 0.5, 3.0, "from 0.5 to 3 mm"),
            (self.braille_dot_pitch_mm, "print.braille_dot_pitch_mm", 1.0, 5.0, "from 1 to 5 mm"),
            (self.braille_cell_mm, "print.braille_cell_mm", 3.0, 15.0, "from 3 to 15 mm"),
            (self.braille_line_mm, "print.braille_line_mm", 5.0, 25.0, "from 5 to 25 mm"),
            (self.base_mm, "print.base_mm", 0.0, 20.0, "from 0 to 20 mm"),
            (self.raise_mm, "print.raise_mm", 0.0, 20.0, "from 0 to 20 mm"),
            (self.texture_mm, "print.texture_mm", 0.0, 20.0, "from 0 to 20 mm"),
        ] {
            if !within(v, lo, hi) {
                return Err((key, what));
            }
        }
        if self.braille_dot_mm >= self.braille_dot_pitch_mm {
            return Err(("print.braille_dot_mm", "smaller than the dot spacing, so that dots stay apart"));
        }
        if self.braille_cell_mm < 2.0 * self.braille_dot_pitch_mm {
            return Err(("print.braille_cell_mm", "at least twice the dot spacing, so that cells stay apart"));
        }
        if self.braille_line_mm < 3.0 * self.braille_dot_pitch_mm {
            return Err(("print.braille_line_mm", "at least three dot spacings, so that lines stay apart"));
        }
        if self.medium == Medium::Relief {
            if self.base_mm < 0.2 {
                return Err(("print.base_mm", "at least 0.2 mm for a relief (the plate holds it together)"));
            }
            if self.raise_mm < 0.1 || self.texture_mm < 0.1 {
                return Err(("print.raise_mm", "raised features at least 0.1 mm high on a relief"));
            }
        }
        Ok(())
    }
}

/// What a family needs beyond the common fields.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FamilyParams {
    /// Laterotactile arrays need nothing more.
    Laterotactile,
    /// Vibrotactile grid parameters.
    Grid(GridParams),
    /// Finger device parameters.
    Finger(FingerParams),
    /// Pin-matrix parameters.
    Pins(PinParams),
    /// Print-medium parameters.
    Print(PrintParams),
}

impl FamilyParams {
    /// The family these parameters belong to.
    pub fn family(&self) -> Family {
        match self {
            FamilyParams::Laterotactile => Family::Laterotactile,
            FamilyParams::Grid(_) => Family::Grid,
            FamilyParams::Finger(_) => Family::Finger,
            FamilyParams::Pins(_) => Family::Pins,
            FamilyParams::Print(_) => Family::Print,
        }
    }
}

/// One device: its actuator layout, rate, output resolution and surface.
///
/// Actuator `(row, col)` has index `cols * row + col` in a frame. For a
/// laterotactile array the actuators are centred on the carrier position:
/// actuator `(row, col)` sits at `carrier + ((col - (cols-1)/2) * pitch_x,
/// (row - (rows-1)/2) * pitch_y)`. For a grid, actuator `(row, col)` sits at
/// page position `(col * pitch_x, row * pitch_y)`. For a pin matrix, pin
/// `(row, col)` of the image sits at page position `((col + 0.5) * pitch_x,
/// (row + 0.5) * pitch_y)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeviceProfile {
    /// The profile's name (`stress2`, `brush-4x3`, ...).
    pub name: ProfileName,
    /// Actuator rows.
    pub rows: u16,
    /// Actuator columns.
    pub cols: u16,
    /// Distance between columns, in millimetres.
    pub pitch_x_mm: f32,
    /// Distance between rows, in millimetres.
    pub pitch_y_mm: f32,
    /// Ticks per second of the device's output.
    pub rate_hz: u32,
    /// Bits per actuator value (10 for STRESS²).
    pub output_bits: u8,
    /// Width of the surface the device explores, in millimetres.
    pub surface_w_mm: f32,
    /// Height of the surface the device explores, in millimetres.
    pub surface_h_mm: f32,
    /// Family-specific parameters; they also say which family this is.
    pub params: FamilyParams,
}

/// Largest number of actuators in a profile.
pub const MAX_ACTUATORS: u32 = 4096;
/// Largest tick rate a profile may declare.
pub const MAX_RATE_HZ: u32 = 1_000_000;

impl DeviceProfile {
    /// The profile's family.
    pub fn family(&self) -> Family {
        self.params.family()
    }

    /// Number of actuators (`rows * cols`).
    pub fn actuator_count(&self) -> usize {
        self.rows as usize * self.cols as usize
    }

    /// Largest actuator value (`2^bits - 1`).
    pub fn max_code(&self) -> u32 {
        (1u32 << self.output_bits.min(31)) - 1
    }

    /// Checks every field's range; the first problem is returned as
    /// `(key, expected)`, the key named as in a profile TOML file (`array.rows`).
    pub fn check(&self) -> Result<(), (&'static str, &'static str)> {
        fn pos(v: f32) -> bool {
            v.is_finite() && v > 0.0
        }
        if self.name.as_str().is_empty() {
            return Err(("name", "a non-empty name"));
        }
        if self.rows == 0 || self.cols == 0 {
            return Err((if self.rows == 0 { "array.rows" } else { "array.cols" }, "at least 1"));
        }
        let pins = self.family() == Family::Pins;
        let print = self.family() == Family::Print;
        if pins && self.rows as u32 * self.cols as u32 > MAX_PINS {
            return Err(("array.rows", "rows * cols at most 65536 pins"));
        }
        if !pins && !print && self.rows as u32 * self.cols as u32 > MAX_ACTUATORS {
            return Err(("array.rows", "rows * cols at most 4096 actuators"));
        }
        if !pos(self.pitch_x_mm) || self.pitch_x_mm > 1000.0 {
            return Err(("array.pitch_x_mm", "a finite pitch above 0 and at most 1000 mm"));
        }
        if !pos(self.pitch_y_mm) || self.pitch_y_mm > 1000.0 {
            return Err(("array.pitch_y_mm", "a finite pitch above 0 and at most 1000 mm"));
        }
        if self.rate_hz == 0 || self.rate_hz > MAX_RATE_HZ {
            return Err(("rate_hz", "a rate from 1 to 1000000 Hz"));
        }
        if self.output_bits == 0 || self.output_bits > 24 {
            return Err(("output_bits", "from 1 to 24 bits"));
        }
        if !pos(self.surface_w_mm) || self.surface_w_mm > 1.0e6 {
            return Err(("surface.width_mm", "a finite width above 0 and at most 1e6 mm"));
        }
        if !pos(self.surface_h_mm) || self.surface_h_mm > 1.0e6 {
            return Err(("surface.height_mm", "a finite height above 0 and at most 1e6 mm"));
        }
        match self.params {
            FamilyParams::Laterotactile => {}
            FamilyParams::Grid(g) => {
                if !pos(g.carrier_min_hz) || !g.carrier_max_hz.is_finite() || g.carrier_max_hz < g.carrier_min_hz {
                    return Err(("grid.carrier_min_hz", "finite, above 0 and at most carrier_max_hz"));
                }
                if g.audio_rate_hz < 8000 || g.audio_rate_hz > 384_000 {
                    return Err(("grid.audio_rate_hz", "from 8000 to 384000 Hz"));
                }
                if (g.carrier_max_hz as f64) * 2.0 >= g.audio_rate_hz as f64 {
                    return Err(("grid.carrier_max_hz", "below half the audio rate"));
                }
                if !g.ramp_ms.is_finite() || g.ramp_ms < 0.0 || g.ramp_ms > 1000.0 {
                    return Err(("grid.ramp_ms", "from 0 to 1000 ms"));
                }
            }
            FamilyParams::Finger(p) => {
                if self.rows as u32 * self.cols as u32 != 3 {
                    return Err((
                        "array.cols",
                        "rows * cols exactly 3 actuators (Left, Down, Right) for a finger device",
                    ));
                }
                if !pos(p.rhythm_max) || p.rhythm_max >= 105.0 {
                    return Err((
                        "finger.rhythm_max",
                        "above 0 and below 105 (the period T = (105 - R) / 0.5 ms must stay positive)",
                    ));
                }
                if !pos(p.intensity_max) || p.intensity_max > 1.0 {
                    return Err(("finger.intensity_max", "above 0 and at most 1"));
                }
                if !p.flat_slope.is_finite() || p.flat_slope < 0.0 || p.flat_slope > 10.0 {
                    return Err(("finger.flat_slope", "from 0 to 10"));
                }
                if p.direction_window == 0 || p.direction_window > 64 {
                    return Err(("finger.direction_window", "from 1 to 64 samples"));
                }
                if !p.min_move_mm.is_finite() || p.min_move_mm < 0.0 || p.min_move_mm > 100.0 {
                    return Err(("finger.min_move_mm", "from 0 to 100 mm"));
                }
            }
            FamilyParams::Pins(p) => {
                if !matches!(self.output_bits, 1 | 2 | 4 | 8) {
                    return Err(("output_bits", "1, 2, 4 or 8 bits per pin for a pin matrix"));
                }
                if p.height_levels == 0 || p.height_levels > MAX_PIN_HEIGHT {
                    return Err(("pins.height_levels", "from 1 to 15 raised levels"));
                }
                if p.height_levels as u32 > self.max_code() {
                    return Err(("pins.height_levels", "at most 2^output_bits - 1"));
                }
                if !matches!(p.cell_rows, 3 | 4) {
                    return Err(("pins.cell_rows", "3 (six-dot cells) or 4 (eight-dot cells)"));
                }
                if p.cell_gap_cols > 8 {
                    return Err(("pins.cell_gap_cols", "from 0 to 8 blank pins"));
                }
                if p.line_gap_rows > 8 {
                    return Err(("pins.line_gap_rows", "from 0 to 8 blank pins"));
                }
                if p.cell_pitch_cols() > self.cols as u32 || p.line_pitch_rows() > self.rows as u32 {
                    return Err(("pins.cell_rows", "a braille cell and its gaps that fit on the pin area"));
                }
                if p.text_cells > MAX_TEXT_LINE_CELLS {
                    return Err(("pins.text_cells", "from 0 to 256 cells"));
                }
                if p.refresh_ms > 600_000 {
                    return Err(("pins.refresh_ms", "from 0 (not published) to 600000 ms"));
                }
                // The surface is the pin area, so that a drawing fitted to the
                // surface lands exactly on the pins.
                let near = |a: f32, b: f32| (a - b).abs() <= 1e-4 * b.max(1.0);
                if !near(self.surface_w_mm, self.cols as f32 * self.pitch_x_mm) {
                    return Err(("surface.width_mm", "cols * pitch_x_mm for a pin matrix (the pin area)"));
                }
                if !near(self.surface_h_mm, self.rows as f32 * self.pitch_y_mm) {
                    return Err(("surface.height_mm", "rows * pitch_y_mm for a pin matrix (the pin area)"));
                }
            }
            FamilyParams::Print(p) => {
                p.check()?;
                // The common fields are derived from the print fields
                // (`profiles::parse` fills them in), so they must agree.
                let (w, h) = p.surface_mm();
                let (c, r) = p.grid_size();
                let near = |a: f32, b: f32| (a - b).abs() <= 1e-3 * b.max(1.0);
                if !near(self.surface_w_mm, w) || !near(self.surface_h_mm, h) {
                    return Err(("surface.width_mm", "the paper less its margins for a print profile"));
                }
                if self.pitch_x_mm != p.grid_mm || self.pitch_y_mm != p.grid_mm {
                    return Err(("array.pitch_x_mm", "print.grid_mm for a print profile"));
                }
                if (self.cols as u64, self.rows as u64) != (c.min(u16::MAX as u64), r.min(u16::MAX as u64)) {
                    return Err(("array.cols", "the grid points on the printable area for a print profile"));
                }
            }
        }
        Ok(())
    }
}
