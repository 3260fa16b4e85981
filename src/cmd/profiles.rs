//! `taxel profiles`: the built-in device profiles and their key figures.

use taxel_format::{FamilyParams, profiles};

use crate::error::CmdResult;
use crate::io::stdout::outln;

pub fn run() -> CmdResult {
    outln!(
        "{:<20} {:<14} {:>9} {:>15} {:>8} {:>6} {:>15}  notes",
        "name",
        "family",
        "actuators",
        "pitch mm",
        "rate Hz",
        "bits",
        "surface mm"
    )?;
    for name in profiles::builtin_names() {
        let Some(p) = profiles::builtin(name) else { continue };
        let notes = match p.params {
            FamilyParams::Laterotactile => String::new(),
            FamilyParams::Grid(g) => format!(
                "carriers {}-{} Hz, audio {} Hz, ramps {} ms",
                g.carrier_min_hz, g.carrier_max_hz, g.audio_rate_hz, g.ramp_ms
            ),
            FamilyParams::Finger(f) => format!(
                "rhythm up to {}, intensity up to {}, direction over {} samples",
                f.rhythm_max, f.intensity_max, f.direction_window
            ),
            FamilyParams::Pins(q) => format!(
                "heights 0-{}, {}, {}-dot cells, {}",
                q.height_levels,
                if q.can_blink() { format!("blinks in {} ms steps", q.blink_step_ms) } else { "no blink".into() },
                q.cell_rows * 2,
                if q.text_cells > 0 { format!("{}-cell text line", q.text_cells) } else { "no text line".into() }
            ),
            FamilyParams::Print(q) => format!(
                "{} on {} x {} mm paper, {} mm margins, {}{}",
                q.medium.name(),
                q.paper_w_mm,
                q.paper_h_mm,
                q.margin_mm,
                match q.medium {
                    taxel_format::Medium::Emboss => format!("dots every {} mm", q.grid_mm),
                    taxel_format::Medium::Relief => format!("{} mm plate, features {} mm", q.base_mm, q.raise_mm),
                    taxel_format::Medium::Swell => "vector art".into(),
                },
                match q.medium {
                    taxel_format::Medium::Relief => ", writes STL",
                    taxel_format::Medium::Emboss => ", writes PDF or PNG",
                    taxel_format::Medium::Swell => ", writes PDF",
                }
            ),
        };
        outln!(
            "{:<20} {:<14} {:>9} {:>15} {:>8} {:>6} {:>15}  {}",
            name,
            p.family().name(),
            format!("{}x{}", p.cols, p.rows),
            format!("{} x {}", p.pitch_x_mm, p.pitch_y_mm),
            p.rate_hz,
            p.output_bits,
            format!("{} x {}", p.surface_w_mm, p.surface_h_mm),
            notes
        )?;
    }
    outln!(
        "\nA profile file (TOML, same layout as format-spec/profiles/*.toml) can be given to --profile instead of a name."
    )
}
