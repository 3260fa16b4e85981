//! Device profiles as TOML files, and the built-in ones (`std` only).
//!
//! ```
//! let p = taxel_format::profiles::builtin("stress2").unwrap();
//! assert_eq!((p.rows, p.cols, p.rate_hz, p.output_bits), (8, 8, 1000, 10));
//! let err = taxel_format::profiles::parse("name = \"x\"\n", "x.toml").unwrap_err();
//! assert!(err.to_string().contains("x.toml"));
//! ```

use std::string::{String, ToString};
use std::vec::Vec;
use std::{fmt, format};

use crate::profile::{
    DeviceProfile, FamilyParams, FingerParams, GridParams, Medium, PinParams, PrintParams, ProfileName,
};

/// The built-in profiles: `(name, TOML source)`.
pub const BUILTIN: &[(&str, &str)] = &[
    ("stress2", include_str!("../profiles/stress2.toml")),
    ("brush-4x3", include_str!("../profiles/brush-4x3.toml")),
    ("finger3", include_str!("../profiles/finger3.toml")),
    ("dotpad", include_str!("../profiles/dotpad.toml")),
    ("monarch", include_str!("../profiles/monarch.toml")),
    ("graphiti", include_str!("../profiles/graphiti.toml")),
    ("hyperbraille", include_str!("../profiles/hyperbraille.toml")),
    ("swell-a4", include_str!("../profiles/swell-a4.toml")),
    ("swell-letter", include_str!("../profiles/swell-letter.toml")),
    ("tiger-20dpi", include_str!("../profiles/tiger-20dpi.toml")),
    ("emboss-braille-grid", include_str!("../profiles/emboss-braille-grid.toml")),
    ("print3d", include_str!("../profiles/print3d.toml")),
];

/// Why a profile file was refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ProfileError {
    /// The file (or built-in name) the profile came from.
    pub source_name: String,
    /// The key that was wrong, when one is known (`array.rows`).
    pub key: Option<String>,
    /// What was wrong and what was expected.
    pub message: String,
}

impl fmt::Display for ProfileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.key {
            Some(k) => write!(f, "{}: key `{}`: {}", self.source_name, k, self.message),
            None => write!(f, "{}: {}", self.source_name, self.message),
        }
    }
}

impl std::error::Error for ProfileError {}

/// The keys a profile file may have, per table; everything else is refused
/// by name, so that a misspelt key cannot be silently ignored.
const TOP_KEYS: &[&str] =
    &["name", "family", "rate_hz", "output_bits", "array", "surface", "grid", "finger", "pins", "print"];
const ARRAY_KEYS: &[&str] = &["rows", "cols", "pitch_x_mm", "pitch_y_mm"];
const SURFACE_KEYS: &[&str] = &["width_mm", "height_mm"];
const GRID_KEYS: &[&str] = &["carrier_min_hz", "carrier_max_hz", "audio_rate_hz", "ramp_ms"];
const FINGER_KEYS: &[&str] = &["rhythm_max", "intensity_max", "flat_slope", "direction_window", "min_move_mm"];
const PINS_KEYS: &[&str] =
    &["height_levels", "blink_step_ms", "cell_rows", "cell_gap_cols", "line_gap_rows", "text_cells", "refresh_ms"];
const PRINT_KEYS: &[&str] = &[
    "medium",
    "paper_width_mm",
    "paper_height_mm",
    "margin_mm",
    "grid_mm",
    "dot_levels",
    "min_line_mm",
    "min_gap_mm",
    "min_texture_mm",
    "symbol_mm",
    "braille_dot_mm",
    "braille_dot_pitch_mm",
    "braille_cell_mm",
    "braille_line_mm",
    "base_mm",
    "raise_mm",
    "texture_mm",
];

type Table<'i> = toml::de::DeTable<'i>;
type Value<'i> = toml::de::DeValue<'i>;

/// Reads typed values out of one TOML table, naming keys by their full path
/// and values by their line. Numbers are read from their text, so that a
/// float written with Rust's shortest round-trip `Display` of an `f32` reads
/// back as exactly that `f32` (not through an `f64` and a second rounding).
struct Fields<'a, 'i> {
    table: &'a Table<'i>,
    path: &'static str,
    source_name: &'a str,
    text: &'a str,
}

impl<'a, 'i> Fields<'a, 'i> {
    fn new(
        table: &'a Table<'i>,
        path: &'static str,
        allowed: &[&str],
        source_name: &'a str,
        text: &'a str,
    ) -> Result<Self, ProfileError> {
        let f = Fields { table, path, source_name, text };
        // In file order, so that the first unknown key reported is the first in the file.
        let mut keys: Vec<_> = table.iter().map(|(k, _)| k).collect();
        keys.sort_by_key(|k| k.span().start);
        if let Some(k) = keys.into_iter().find(|k| !allowed.contains(&k.get_ref().as_ref())) {
            let line = f.line(k.span().start);
            return Err(f.err(
                k.get_ref(),
                Some(line),
                format!("unknown key, expected one of: {}", allowed.join(", ")),
            ));
        }
        Ok(f)
    }

    fn line(&self, at: usize) -> usize {
        self.text.get(..at).map_or(0, |t| t.matches('\n').count()) + 1
    }

    fn err(&self, k: &str, line: Option<usize>, message: String) -> ProfileError {
        let key = if self.path.is_empty() { k.into() } else { format!("{}.{k}", self.path) };
        let message = match line {
            Some(l) => format!("line {l}: {message}"),
            None => message,
        };
        ProfileError { source_name: self.source_name.into(), key: Some(key), message }
    }

    fn get(&self, k: &str) -> Result<(&'a Value<'i>, usize), ProfileError> {
        self.table
            .iter()
            .find(|(key, _)| key.get_ref().as_ref() == k)
            .map(|(_, v)| (v.get_ref(), self.line(v.span().start)))
            .ok_or_else(|| self.err(k, None, "missing key".into()))
    }

    fn string(&self, k: &str) -> Result<&'a str, ProfileError> {
        match self.get(k)? {
            (Value::String(s), _) => Ok(s.as_ref()),
            (_, line) => Err(self.err(k, Some(line), "expected a string".into())),
        }
    }

    fn int(&self, k: &str, max: u64) -> Result<u64, ProfileError> {
        let (v, line) = self.get(k)?;
        let parsed = match v {
            Value::Integer(i) => u64::from_str_radix(i.as_str(), i.radix()).ok(),
            _ => None,
        };
        parsed
            .filter(|&v| v <= max)
            .ok_or_else(|| self.err(k, Some(line), format!("expected an integer from 0 to {max}")))
    }

    fn float(&self, k: &str) -> Result<f32, ProfileError> {
        let (v, line) = self.get(k)?;
        let parsed = match v {
            Value::Float(f) => f.as_str().parse::<f32>().ok(),
            Value::Integer(i) if i.radix() == 10 => i.as_str().parse::<f32>().ok(),
            _ => None,
        };
        parsed.ok_or_else(|| self.err(k, Some(line), "expected a number".into()))
    }

    fn table(&self, k: &str) -> Result<Option<&'a Table<'i>>, ProfileError> {
        match self.get(k) {
            Err(_) => Ok(None),
            Ok((Value::Table(t), _)) => Ok(Some(t)),
            Ok((_, line)) => Err(self.err(k, Some(line), "expected a table".into())),
        }
    }
}

/// Parses a profile from TOML. `source_name` (a file path or a built-in name)
/// is carried into every error, with the key (`array.rows`) when one is at fault.
pub fn parse(text: &str, source_name: &str) -> Result<DeviceProfile, ProfileError> {
    let doc = Table::parse(text).map_err(|e| ProfileError {
        source_name: source_name.into(),
        key: None,
        message: e.to_string().trim_end().replace('\n', " "),
    })?;
    let top = Fields::new(doc.get_ref(), "", TOP_KEYS, source_name, text)?;
    // Only a print profile turns here; a missing or mistyped family goes on
    // to the other families' checks, which name the first thing missing in
    // their own order (`[array]` before `family`), as before print existed.
    if top.string("family").ok() == Some("print") {
        return parse_print(&top, source_name, text);
    }
    if top.table("print")?.is_some() {
        return Err(top.err("print", None, "only a print profile has a [print] table".into()));
    }
    let array = top.table("array")?.ok_or_else(|| top.err("array", None, "missing table [array]".into()))?;
    let array = Fields::new(array, "array", ARRAY_KEYS, source_name, text)?;
    let surface = top.table("surface")?.ok_or_else(|| top.err("surface", None, "missing table [surface]".into()))?;
    let surface = Fields::new(surface, "surface", SURFACE_KEYS, source_name, text)?;
    let name_text = top.string("name")?;
    let name = ProfileName::new(name_text)
        .filter(|_| !name_text.is_empty())
        .ok_or_else(|| top.err("name", None, "expected a name of 1 to 31 bytes without NUL".into()))?;
    let grid = top.table("grid")?;
    let finger = top.table("finger")?;
    let pins = top.table("pins")?;
    let family = top.string("family")?;
    // Each family has at most its own table.
    for (table, present, owner) in
        [("grid", grid.is_some(), "grid"), ("finger", finger.is_some(), "finger"), ("pins", pins.is_some(), "pins")]
    {
        if present && family != owner && matches!(family, "laterotactile" | "grid" | "finger" | "pins") {
            return Err(top.err(table, None, format!("a {family} profile has no [{table}] table")));
        }
    }
    let params = match family {
        "laterotactile" => FamilyParams::Laterotactile,
        "grid" => {
            let g = grid.ok_or_else(|| top.err("grid", None, "missing table [grid] for family \"grid\"".into()))?;
            let g = Fields::new(g, "grid", GRID_KEYS, source_name, text)?;
            FamilyParams::Grid(GridParams {
                carrier_min_hz: g.float("carrier_min_hz")?,
                carrier_max_hz: g.float("carrier_max_hz")?,
                audio_rate_hz: g.int("audio_rate_hz", u32::MAX as u64)? as u32,
                ramp_ms: g.float("ramp_ms")?,
            })
        }
        "finger" => {
            let f =
                finger.ok_or_else(|| top.err("finger", None, "missing table [finger] for family \"finger\"".into()))?;
            let f = Fields::new(f, "finger", FINGER_KEYS, source_name, text)?;
            FamilyParams::Finger(FingerParams {
                rhythm_max: f.float("rhythm_max")?,
                intensity_max: f.float("intensity_max")?,
                flat_slope: f.float("flat_slope")?,
                direction_window: f.int("direction_window", u32::MAX as u64)? as u32,
                min_move_mm: f.float("min_move_mm")?,
            })
        }
        "pins" => {
            let p = pins.ok_or_else(|| top.err("pins", None, "missing table [pins] for family \"pins\"".into()))?;
            let p = Fields::new(p, "pins", PINS_KEYS, source_name, text)?;
            FamilyParams::Pins(PinParams {
                height_levels: p.int("height_levels", u8::MAX as u64)? as u8,
                blink_step_ms: p.int("blink_step_ms", u16::MAX as u64)? as u16,
                cell_rows: p.int("cell_rows", u8::MAX as u64)? as u8,
                cell_gap_cols: p.int("cell_gap_cols", u8::MAX as u64)? as u8,
                line_gap_rows: p.int("line_gap_rows", u8::MAX as u64)? as u8,
                text_cells: p.int("text_cells", u16::MAX as u64)? as u16,
                refresh_ms: p.int("refresh_ms", u32::MAX as u64)? as u32,
            })
        }
        other => {
            return Err(top.err(
                "family",
                None,
                format!("unknown family \"{other}\", expected \"laterotactile\", \"grid\", \"finger\", \"pins\" or \"print\""),
            ));
        }
    };
    let profile = DeviceProfile {
        name,
        rows: array.int("rows", u16::MAX as u64)? as u16,
        cols: array.int("cols", u16::MAX as u64)? as u16,
        pitch_x_mm: array.float("pitch_x_mm")?,
        pitch_y_mm: array.float("pitch_y_mm")?,
        rate_hz: top.int("rate_hz", u32::MAX as u64)? as u32,
        output_bits: top.int("output_bits", u8::MAX as u64)? as u8,
        surface_w_mm: surface.float("width_mm")?,
        surface_h_mm: surface.float("height_mm")?,
        params,
    };
    profile.check().map_err(|(key, expected)| ProfileError {
        source_name: source_name.into(),
        key: Some(key.into()),
        message: format!("out of range, expected {expected}"),
    })?;
    Ok(profile)
}

/// A print profile: the `[print]` table decides everything; the common
/// fields (`[array]`, `[surface]`, `rate_hz`, `output_bits`) are derived from
/// it, and where a file gives them they must agree.
fn parse_print(top: &Fields<'_, '_>, source_name: &str, text: &str) -> Result<DeviceProfile, ProfileError> {
    for t in ["grid", "finger", "pins"] {
        if top.table(t)?.is_some() {
            return Err(top.err(t, None, format!("a print profile has no [{t}] table")));
        }
    }
    let name_text = top.string("name")?;
    let name = ProfileName::new(name_text)
        .filter(|_| !name_text.is_empty())
        .ok_or_else(|| top.err("name", None, "expected a name of 1 to 31 bytes without NUL".into()))?;
    let t = top
        .table("print")?
        .ok_or_else(|| top.err("print", None, "missing table [print] for family \"print\"".into()))?;
    let f = Fields::new(t, "print", PRINT_KEYS, source_name, text)?;
    let medium_name = f.string("medium")?;
    let medium = Medium::from_name(medium_name).ok_or_else(|| {
        f.err("medium", None, format!("unknown medium \"{medium_name}\", expected \"swell\", \"emboss\" or \"relief\""))
    })?;
    let p = PrintParams {
        medium,
        paper_w_mm: f.float("paper_width_mm")?,
        paper_h_mm: f.float("paper_height_mm")?,
        margin_mm: f.float("margin_mm")?,
        grid_mm: f.float("grid_mm")?,
        dot_levels: f.int("dot_levels", u8::MAX as u64)? as u8,
        min_line_mm: f.float("min_line_mm")?,
        min_gap_mm: f.float("min_gap_mm")?,
        min_texture_mm: f.float("min_texture_mm")?,
        symbol_mm: f.float("symbol_mm")?,
        braille_dot_mm: f.float("braille_dot_mm")?,
        braille_dot_pitch_mm: f.float("braille_dot_pitch_mm")?,
        braille_cell_mm: f.float("braille_cell_mm")?,
        braille_line_mm: f.float("braille_line_mm")?,
        base_mm: f.float("base_mm")?,
        raise_mm: f.float("raise_mm")?,
        texture_mm: f.float("texture_mm")?,
    };
    let err = |(key, expected): (&str, &str)| ProfileError {
        source_name: source_name.into(),
        key: Some(key.into()),
        message: format!("out of range, expected {expected}"),
    };
    p.check().map_err(err)?;
    let (w, h) = p.surface_mm();
    let (cols, rows) = p.grid_size();
    let mut profile = DeviceProfile {
        name,
        rows: rows.min(u16::MAX as u64) as u16,
        cols: cols.min(u16::MAX as u64) as u16,
        pitch_x_mm: p.grid_mm,
        pitch_y_mm: p.grid_mm,
        rate_hz: 1,
        output_bits: 8,
        surface_w_mm: w,
        surface_h_mm: h,
        params: FamilyParams::Print(p),
    };
    // What a file gives of the common fields must be what the print table makes.
    if top.get("rate_hz").is_ok() {
        profile.rate_hz = top.int("rate_hz", u32::MAX as u64)? as u32;
    }
    if top.get("output_bits").is_ok() {
        profile.output_bits = top.int("output_bits", u8::MAX as u64)? as u8;
    }
    if let Some(a) = top.table("array")? {
        let a = Fields::new(a, "array", ARRAY_KEYS, source_name, text)?;
        for k in ARRAY_KEYS {
            if a.get(k).is_ok() {
                match *k {
                    "rows" => profile.rows = a.int(k, u16::MAX as u64)? as u16,
                    "cols" => profile.cols = a.int(k, u16::MAX as u64)? as u16,
                    "pitch_x_mm" => profile.pitch_x_mm = a.float(k)?,
                    _ => profile.pitch_y_mm = a.float(k)?,
                }
            }
        }
    }
    if let Some(sf) = top.table("surface")? {
        let sf = Fields::new(sf, "surface", SURFACE_KEYS, source_name, text)?;
        if sf.get("width_mm").is_ok() {
            profile.surface_w_mm = sf.float("width_mm")?;
        }
        if sf.get("height_mm").is_ok() {
            profile.surface_h_mm = sf.float("height_mm")?;
        }
    }
    profile.check().map_err(err)?;
    Ok(profile)
}

/// A built-in profile by name.
pub fn builtin(name: &str) -> Option<DeviceProfile> {
    BUILTIN.iter().find(|(n, _)| *n == name).and_then(|(n, text)| parse(text, n).ok())
}

/// The names of the built-in profiles.
pub fn builtin_names() -> Vec<&'static str> {
    BUILTIN.iter().map(|(n, _)| *n).collect()
}

/// Writes a profile back as TOML in the same layout as the built-in files.
pub fn to_toml(p: &DeviceProfile) -> String {
    let mut s = format!(
        "name = {:?}\nfamily = {:?}\nrate_hz = {}\noutput_bits = {}\n\n[array]\nrows = {}\ncols = {}\npitch_x_mm = {}\npitch_y_mm = {}\n\n[surface]\nwidth_mm = {}\nheight_mm = {}\n",
        p.name.as_str(),
        p.family().name(),
        p.rate_hz,
        p.output_bits,
        p.rows,
        p.cols,
        p.pitch_x_mm,
        p.pitch_y_mm,
        p.surface_w_mm,
        p.surface_h_mm
    );
    match p.params {
        FamilyParams::Laterotactile => {}
        FamilyParams::Grid(g) => {
            s += &format!(
                "\n[grid]\ncarrier_min_hz = {}\ncarrier_max_hz = {}\naudio_rate_hz = {}\nramp_ms = {}\n",
                g.carrier_min_hz, g.carrier_max_hz, g.audio_rate_hz, g.ramp_ms
            )
        }
        FamilyParams::Finger(f) => {
            s += &format!(
                "\n[finger]\nrhythm_max = {}\nintensity_max = {}\nflat_slope = {}\ndirection_window = {}\nmin_move_mm = {}\n",
                f.rhythm_max, f.intensity_max, f.flat_slope, f.direction_window, f.min_move_mm
            )
        }
        FamilyParams::Print(q) => {
            s += &format!(
                "\n[print]\nmedium = {:?}\npaper_width_mm = {}\npaper_height_mm = {}\nmargin_mm = {}\ngrid_mm = {}\ndot_levels = {}\nmin_line_mm = {}\nmin_gap_mm = {}\nmin_texture_mm = {}\nsymbol_mm = {}\nbraille_dot_mm = {}\nbraille_dot_pitch_mm = {}\nbraille_cell_mm = {}\nbraille_line_mm = {}\nbase_mm = {}\nraise_mm = {}\ntexture_mm = {}\n",
                q.medium.name(),
                q.paper_w_mm,
                q.paper_h_mm,
                q.margin_mm,
                q.grid_mm,
                q.dot_levels,
                q.min_line_mm,
                q.min_gap_mm,
                q.min_texture_mm,
                q.symbol_mm,
                q.braille_dot_mm,
                q.braille_dot_pitch_mm,
                q.braille_cell_mm,
                q.braille_line_mm,
                q.base_mm,
                q.raise_mm,
                q.texture_mm
            )
        }
        FamilyParams::Pins(p) => {
            s += &format!(
                "\n[pins]\nheight_levels = {}\nblink_step_ms = {}\ncell_rows = {}\ncell_gap_cols = {}\nline_gap_rows = {}\ntext_cells = {}\nrefresh_ms = {}\n",
                p.height_levels,
                p.blink_step_ms,
                p.cell_rows,
                p.cell_gap_cols,
                p.line_gap_rows,
                p.text_cells,
                p.refresh_ms
            )
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::Medium;

    #[test]
    fn builtins_parse_with_the_papers_values() {
        let s = builtin("stress2").unwrap();
        assert_eq!((s.rows, s.cols, s.pitch_x_mm, s.pitch_y_mm), (8, 8, 1.2, 1.4));
        assert_eq!((s.rate_hz, s.output_bits, s.surface_w_mm, s.surface_h_mm), (1000, 10, 110.0, 60.0));
        let b = builtin("brush-4x3").unwrap();
        assert_eq!((b.rows, b.cols, b.pitch_x_mm), (3, 4, 63.0));
        let FamilyParams::Grid(g) = b.params else { panic!("brush-4x3 is a grid") };
        assert_eq!((g.carrier_min_hz, g.carrier_max_hz), (150.0, 270.0));
        assert_eq!(builtin("finger3").unwrap().actuator_count(), 3);
        assert!(builtin("nope").is_none());
    }

    fn pins(name: &str) -> (DeviceProfile, PinParams) {
        let p = builtin(name).unwrap();
        let FamilyParams::Pins(q) = p.params else { panic!("{name} is a pin matrix") };
        (p, q)
    }

    #[test]
    fn pin_builtins_have_the_published_sizes() {
        // reference/pins.md: Dot Pad 60 x 40 + 20-cell line, Monarch 96 x 40,
        // Graphiti 60 x 40 heights 0-4 blinking in 100 ms steps, HyperBraille 120 x 60.
        let (d, dq) = pins("dotpad");
        assert_eq!((d.cols, d.rows, dq.height_levels, dq.text_cells, dq.blink_step_ms), (60, 40, 1, 20, 0));
        let (m, mq) = pins("monarch");
        assert_eq!((m.cols, m.rows, mq.height_levels, mq.text_cells, mq.cell_rows), (96, 40, 1, 0, 4));
        // 8 lines x 32 cells of 8-dot text with a blank pin both ways.
        assert_eq!((m.cols as u32 / mq.cell_pitch_cols(), m.rows as u32 / mq.line_pitch_rows()), (32, 8));
        let (g, gq) = pins("graphiti");
        assert_eq!((g.cols, g.rows, gq.height_levels, gq.blink_step_ms), (60, 40, 4, 100));
        let (h, hq) = pins("hyperbraille");
        assert_eq!((h.cols, h.rows, hq.height_levels, hq.blink_step_ms), (120, 60, 1, 0));
        for p in [d, m, g, h] {
            assert_eq!((p.pitch_x_mm, p.pitch_y_mm), (2.5, 2.5), "{}: the documented pitch assumption", p.name);
        }
    }

    #[test]
    fn hostile_pin_profiles_are_refused_by_key() {
        let dotpad = BUILTIN.iter().find(|(n, _)| *n == "dotpad").unwrap().1;
        let cases = [
            ("cols = 60", "cols = 0", "array.cols"),
            ("rows = 40", "rows = 0", "array.rows"),
            ("rows = 40", "rows = 65535", "array.rows"),
            ("cols = 60", "cols = 70000", "array.cols"),
            ("pitch_x_mm = 2.5", "pitch_x_mm = 0", "array.pitch_x_mm"),
            ("pitch_x_mm = 2.5", "pitch_x_mm = 1e30", "array.pitch_x_mm"),
            ("height_levels = 1", "height_levels = 0", "pins.height_levels"),
            ("height_levels = 1", "height_levels = 200", "pins.height_levels"),
            // One bit per pin cannot carry two raised levels.
            ("height_levels = 1", "height_levels = 2", "pins.height_levels"),
            ("cell_rows = 3", "cell_rows = 5", "pins.cell_rows"),
            ("cell_gap_cols = 1", "cell_gap_cols = 99", "pins.cell_gap_cols"),
            ("text_cells = 20", "text_cells = 60000", "pins.text_cells"),
            ("text_cells = 20", "text_cells = 99999999", "pins.text_cells"),
            ("\nrefresh_ms = 0", "\nrefresh_ms = 99999999", "pins.refresh_ms"),
            ("output_bits = 1", "output_bits = 3", "output_bits"),
            ("width_mm = 150", "width_mm = 151", "surface.width_mm"),
            ("\nrefresh_ms = 0", "\nrefresh_ms = 0\nspeed = 3", "pins.speed"),
        ];
        for (from, to, key) in cases {
            assert!(dotpad.contains(from), "{from}");
            let e = parse(&dotpad.replace(from, to), "hostile.toml").unwrap_err();
            assert_eq!(e.key.as_deref(), Some(key), "{to}: {e}");
            assert!(e.to_string().starts_with("hostile.toml"), "{e}");
        }
        // A 300 x 300 display is more pins than any profile may have.
        let big = dotpad.replace("rows = 40", "rows = 300").replace("cols = 60", "cols = 300");
        assert_eq!(parse(&big, "p").unwrap_err().key.as_deref(), Some("array.rows"));
        let no_table = dotpad.split("[pins]").next().unwrap();
        assert_eq!(parse(no_table, "p").unwrap_err().key.as_deref(), Some("pins"));
        let wrong_table = BUILTIN[0].1.to_string() + "\n[pins]\nheight_levels = 1\n";
        assert_eq!(parse(&wrong_table, "p").unwrap_err().key.as_deref(), Some("pins"));
    }

    fn print(name: &str) -> (DeviceProfile, PrintParams) {
        let p = builtin(name).unwrap();
        let FamilyParams::Print(q) = p.params else { panic!("{name} is a print profile") };
        (p, q)
    }

    #[test]
    fn print_builtins_have_their_paper_and_grid() {
        // Tiger: 11 x 11.5 in at 20 dpi, half-inch margins: 10 x 10.5 in of 20 dots an inch.
        let (t, tq) = print("tiger-20dpi");
        assert_eq!((tq.medium, tq.paper_w_mm, tq.paper_h_mm, tq.grid_mm), (Medium::Emboss, 279.4, 292.1, 1.27));
        assert_eq!((t.cols, t.rows), (200, 210));
        let (b, bq) = print("emboss-braille-grid");
        assert_eq!((bq.grid_mm, b.cols, b.rows), (2.5, 76, 110));
        let (a4, q) = print("swell-a4");
        assert_eq!((q.medium, q.paper_w_mm, q.paper_h_mm), (Medium::Swell, 210.0, 297.0));
        assert_eq!((a4.surface_w_mm, a4.surface_h_mm), (190.0, 277.0));
        let (_, l) = print("swell-letter");
        assert_eq!((l.paper_w_mm, l.paper_h_mm), (215.9, 279.4));
        let (_, r) = print("print3d");
        assert_eq!(r.medium, Medium::Relief);
        assert!(r.base_mm > 0.0 && r.raise_mm > r.texture_mm && r.texture_mm > 0.0);
        // NLS Specification 800's ranges hold on every paper profile (Tiger's
        // dot spacing is its grid's 2.54 mm, named in its file).
        for n in ["swell-a4", "swell-letter", "emboss-braille-grid", "print3d", "tiger-20dpi"] {
            let (_, q) = print(n);
            assert!((1.5..=1.6).contains(&q.braille_dot_mm), "{n}");
            assert!((6.1..=7.6).contains(&q.braille_cell_mm), "{n}");
            assert!((10.0..=10.2).contains(&q.braille_line_mm), "{n}");
            assert!((2.3..=2.5).contains(&q.braille_dot_pitch_mm) || n == "tiger-20dpi", "{n}");
        }
    }

    #[test]
    fn a_print_profile_file_may_change_paper_margins_and_dimensions() {
        let a4 = BUILTIN.iter().find(|(n, _)| *n == "swell-a4").unwrap().1;
        let text = a4
            .replace("paper_width_mm = 210", "paper_width_mm = 297")
            .replace("paper_height_mm = 297", "paper_height_mm = 420")
            .replace("margin_mm = 10", "margin_mm = 15")
            .replace("braille_cell_mm = 6.2", "braille_cell_mm = 6.5");
        let p = parse(&text, "a3.toml").unwrap();
        let FamilyParams::Print(q) = p.params else { panic!() };
        assert_eq!((p.surface_w_mm, p.surface_h_mm, q.braille_cell_mm), (267.0, 390.0, 6.5));
        assert_eq!((p.cols, p.rows), (1068, 1560));
    }

    #[test]
    fn hostile_print_profiles_are_refused_by_key() {
        let a4 = BUILTIN.iter().find(|(n, _)| *n == "swell-a4").unwrap().1;
        let relief = BUILTIN.iter().find(|(n, _)| *n == "print3d").unwrap().1;
        let cases = [
            (a4, "paper_width_mm = 210", "paper_width_mm = 0", "print.paper_width_mm"),
            (a4, "paper_width_mm = 210", "paper_width_mm = nan", "print.paper_width_mm"),
            (a4, "paper_height_mm = 297", "paper_height_mm = 1e30", "print.paper_height_mm"),
            (a4, "paper_height_mm = 297", "paper_height_mm = \"A4\"", "print.paper_height_mm"),
            (a4, "margin_mm = 10", "margin_mm = 105", "print.margin_mm"),
            (a4, "margin_mm = 10", "margin_mm = -1", "print.margin_mm"),
            (a4, "grid_mm = 0.25", "grid_mm = 0", "print.grid_mm"),
            // Too many grid points: 190 x 277 mm at 0.05 mm is 21 million.
            (a4, "grid_mm = 0.25", "grid_mm = 0.05", "print.grid_mm"),
            (a4, "dot_levels = 1", "dot_levels = 9", "print.dot_levels"),
            (a4, "dot_levels = 1", "dot_levels = 300", "print.dot_levels"),
            (a4, "min_line_mm = 0.8", "min_line_mm = inf", "print.min_line_mm"),
            (a4, "braille_dot_mm = 1.5", "braille_dot_mm = 2.5", "print.braille_dot_mm"),
            (a4, "braille_cell_mm = 6.2", "braille_cell_mm = 4", "print.braille_cell_mm"),
            (a4, "braille_line_mm = 10.2", "braille_line_mm = 6", "print.braille_line_mm"),
            (a4, "medium = \"swell\"", "medium = \"vellum\"", "print.medium"),
            (a4, "texture_mm = 0", "texture_mm = 0\ncolour = 1", "print.colour"),
            (a4, "texture_mm = 0", "", "print.texture_mm"),
            (relief, "base_mm = 2", "base_mm = 0", "print.base_mm"),
            (relief, "raise_mm = 1", "raise_mm = 0", "print.raise_mm"),
        ];
        for (base, from, to, key) in cases {
            assert!(base.contains(from), "{from}");
            let e = parse(&base.replace(from, to), "hostile.toml").unwrap_err();
            assert_eq!(e.key.as_deref(), Some(key), "{to}: {e}");
            assert!(e.to_string().starts_with("hostile.toml"), "{e}");
        }
        // The common fields, where given, must be what the print table makes.
        let e = parse(&format!("{a4}\n[surface]\nwidth_mm = 200\n"), "p").unwrap_err();
        assert_eq!(e.key.as_deref(), Some("surface.width_mm"), "{e}");
        let e = parse(&format!("{a4}\n[array]\ncols = 3\n"), "p").unwrap_err();
        assert_eq!(e.key.as_deref(), Some("array.cols"), "{e}");
        let e = parse(&format!("{a4}\n[pins]\nheight_levels = 1\n"), "p").unwrap_err();
        assert_eq!(e.key.as_deref(), Some("pins"), "{e}");
        let e = parse(&format!("{}\n[print]\nmedium = \"swell\"\n", BUILTIN[0].1), "p").unwrap_err();
        assert_eq!(e.key.as_deref(), Some("print"), "{e}");
        let no_table = a4.split("[print]").next().unwrap();
        assert_eq!(parse(no_table, "p").unwrap_err().key.as_deref(), Some("print"));
    }

    #[test]
    fn a_print_profile_makes_no_bundle() {
        let b = crate::Bundle::new(crate::Manifest::new(builtin("swell-a4").unwrap()));
        assert!(b.to_bytes().is_err());
    }

    #[test]
    fn a_profile_file_may_change_the_pitch() {
        let dotpad = BUILTIN.iter().find(|(n, _)| *n == "dotpad").unwrap().1;
        let text = dotpad
            .replace("pitch_x_mm = 2.5", "pitch_x_mm = 2.4")
            .replace("pitch_y_mm = 2.5", "pitch_y_mm = 2.4")
            .replace("width_mm = 150", "width_mm = 144")
            .replace("height_mm = 100", "height_mm = 96");
        let p = parse(&text, "mine.toml").unwrap();
        assert_eq!((p.pitch_x_mm, p.surface_w_mm), (2.4, 144.0));
    }

    #[test]
    fn to_toml_round_trips() {
        for name in builtin_names() {
            let p = builtin(name).unwrap();
            assert_eq!(parse(&to_toml(&p), "x").unwrap(), p);
        }
    }

    #[test]
    fn unknown_field_is_named_with_the_file() {
        let text = BUILTIN[0].1.replace("rate_hz = 1000", "rate_hz = 1000\nspeed = 3");
        let e = parse(&text, "my.toml").unwrap_err();
        assert!(e.to_string().starts_with("my.toml"), "{e}");
        assert_eq!(e.key.as_deref(), Some("speed"), "{e}");
    }

    #[test]
    fn missing_field_is_named() {
        let text = BUILTIN[0].1.replace("rate_hz = 1000", "");
        let e = parse(&text, "my.toml").unwrap_err();
        assert_eq!(e.key.as_deref(), Some("rate_hz"), "{e}");
    }

    #[test]
    fn a_profile_with_a_name_alone_misses_its_array_first() {
        // Regression: the print family's check read `family` before
        // anything else, so this profile named `family` instead of `[array]`.
        let e = parse("name = \"x\"\n", "p").unwrap_err();
        assert_eq!(e.key.as_deref(), Some("array"), "{e}");
        assert!(e.to_string().contains("missing table [array]"), "{e}");
        let e = parse("name = \"x\"\nfamily = 5\n", "p").unwrap_err();
        assert_eq!(e.key.as_deref(), Some("array"), "{e}");
    }

    #[test]
    fn out_of_range_value_names_the_key() {
        let text = BUILTIN[0].1.replace("pitch_x_mm = 1.2", "pitch_x_mm = -1.2");
        let e = parse(&text, "my.toml").unwrap_err();
        assert_eq!(e.key.as_deref(), Some("array.pitch_x_mm"), "{e}");
        let text = BUILTIN[0].1.replace("output_bits = 10", "output_bits = 40");
        assert_eq!(parse(&text, "p").unwrap_err().key.as_deref(), Some("output_bits"));
        let text = BUILTIN[0].1.replace("family = \"laterotactile\"", "family = \"piano\"");
        assert_eq!(parse(&text, "p").unwrap_err().key.as_deref(), Some("family"));
    }

    #[test]
    fn grid_profile_needs_its_table() {
        let text = BUILTIN[1].1.split("[grid]").next().unwrap();
        assert_eq!(parse(text, "p").unwrap_err().key.as_deref(), Some("grid"));
        let e = parse(&BUILTIN[0].1.replace("[surface]", "[surface]\nwidth = 3"), "p").unwrap_err();
        assert_eq!(e.key.as_deref(), Some("surface.width"));
    }
}
