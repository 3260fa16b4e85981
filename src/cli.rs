//! The command line, as clap types. Exit codes: 0 success; 1 the input has
//! errors (diagnostics printed); 2 usage or IO failure.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

/// Compile annotated drawings and height meshes into refreshable tactile
/// graphics, and play them on tactile devices.
///
/// With no command, runs the demo: builds every scene in examples/, plays each
/// on its example trace, prints a summary and writes previews under
/// target/taxel-demo/.
#[derive(Debug, Parser)]
#[command(name = "taxel", version, about, long_about)]
pub struct Cli {
    /// What to do (the demo when omitted).
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// Output format of reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub enum Format {
    /// Text for people.
    #[default]
    Human,
    /// JSON for programs.
    Json,
}

/// A pin display's own file format (`taxel export`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ExportFormat {
    /// Dot Inc.'s DTMS page file (JSON) for the Dot Pad: one page per display.
    Dtms,
    /// Graphiti full frames: a (height, blink) byte pair per pin, row-major, one frame per page.
    Graphiti,
    /// The pin image as Unicode braille text (U+2800 + dot mask), 2 x 4 pins a character.
    Unicode,
}

/// The built-in style sheets (`taxel style`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum BuiltinSheet {
    /// The automatic style sheet (`--style auto`).
    Auto,
}

/// Height axis of a mesh (`--up`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Up {
    /// +Y is up, as glTF 2.0 says.
    Y,
    /// +Z is up, as GIS tools and some exporters write terrains.
    Z,
}

/// Options shared by the commands that compile.
#[derive(Debug, Clone, Default, Args)]
pub struct CompileOpts {
    /// Device profile: a built-in name (see `taxel profiles`) or a TOML file.
    #[arg(long, short = 'p', value_name = "NAME|FILE")]
    pub profile: Option<String>,
    /// Style sheet (TOML) mapping ids, classes, layers and colours to tactile
    /// styles, or `auto` for the built-in automatic sheet (`taxel style auto` prints it).
    #[arg(long, value_name = "FILE|auto")]
    pub style: Option<PathBuf>,
    /// Mask resolution in pixels per millimetre (default: see docs/annotations.md).
    #[arg(long, value_name = "PX_PER_MM")]
    pub resolution: Option<f32>,
    /// Physical width of a drawing that has no absolute size, in millimetres.
    #[arg(long, value_name = "MM")]
    pub width_mm: Option<f32>,
    /// Scale the drawing or mesh to fill the device's surface, keeping its aspect ratio.
    #[arg(long)]
    pub fit: bool,
    /// Keep only part of the drawing, then fit it: `X,Y,W,H` in drawing units, or `#id`.
    #[arg(long, value_name = "X,Y,W,H|#id", value_parser = parse_region)]
    pub region: Option<taxel_compiler::Region>,
    /// Meshes: which model axis is up (height). Default: +Y as glTF says,
    /// or +Z when the model is clearly flat across Z (a note says so).
    #[arg(long, value_enum)]
    pub up: Option<Up>,
    /// Meshes: multiply heights by this factor (above 0).
    #[arg(long, value_name = "F", value_parser = parse_exaggerate)]
    pub exaggerate: Option<f64>,
    /// Lay text out with the fonts in this folder (and its subfolders) instead of the system's.
    #[arg(long, value_name = "DIR")]
    pub fonts: Option<PathBuf>,
    /// The reader's languages, for drawings that hold a label in several
    /// (`<switch>` with `systemLanguage`, as Wikimedia's maps do): `fr`, or
    /// `fr-CA,fr`. Default: the system's language (LC_ALL, LC_MESSAGES or
    /// LANG), else English.
    #[arg(long, value_name = "LANG[,LANG...]", value_parser = parse_lang)]
    pub lang: Option<String>,
    /// The most memory the build may take, for the whole process: `512M`,
    /// `2G`, `1.5GB`, or `none`. Past it the layer being built stops with
    /// an error (T0308) that names its elements, and nothing is written.
    /// Default 2G, safe on a 4 GB laptop.
    #[arg(long, value_name = "SIZE|none", value_parser = parse_memory)]
    pub max_memory: Option<usize>,
}

/// `--max-memory`'s default, bytes: 2 GiB, half a 4 GB laptop.
pub const DEFAULT_MAX_MEMORY: usize = 2 << 30;

/// `--max-memory`: a size in bytes with an optional unit (`K`, `M`, `G`,
/// with or without `B` and `i`; powers of 1,024), or `none` (no limit:
/// `usize::MAX`).
fn parse_memory(s: &str) -> Result<usize, String> {
    let t = s.trim();
    if t.eq_ignore_ascii_case("none") {
        return Ok(usize::MAX);
    }
    let bad =
        || format!("`{s}` is not a memory size: expected a number with K, M or G (such as 512M or 1.5G), or none");
    let split = t.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(t.len());
    let (number, unit) = t.split_at(split);
    let unit = unit.trim().to_ascii_uppercase();
    let shift = match unit.trim_end_matches('B').trim_end_matches('I') {
        "" if unit.is_empty() => 0,
        "K" => 10,
        "M" => 20,
        "G" => 30,
        "T" => 40,
        _ => return Err(bad()),
    };
    let value = number.parse::<f64>().map_err(|_| bad())? * (1u64 << shift) as f64;
    if !(value.is_finite() && value >= 1.0) {
        return Err(format!("`{s}` is not a memory size: expected at least 1 byte"));
    }
    Ok(value.min(usize::MAX as f64) as usize)
}

impl CompileOpts {
    /// Whether `--style auto` asks for the built-in automatic style sheet.
    pub fn style_is_auto(&self) -> bool {
        self.style.as_deref() == Some(std::path::Path::new("auto"))
    }
}

/// `--lang`: comma-separated language tags (letters, digits and `-`),
/// given back with the spaces around them taken out.
fn parse_lang(s: &str) -> Result<String, String> {
    let tags: Vec<&str> = s.split(',').map(str::trim).filter(|t| !t.is_empty()).collect();
    match tags.iter().find(|t| !t.chars().all(|c| c.is_ascii_alphanumeric() || c == '-')) {
        _ if tags.is_empty() => Err("expected a language tag such as `fr` or `fr-CA,fr`".to_string()),
        Some(bad) => Err(format!("`{bad}` is not a language tag: expected letters, digits and `-`, such as `fr-CA`")),
        None => Ok(tags.join(",")),
    }
}

fn parse_region(s: &str) -> Result<taxel_compiler::Region, String> {
    s.parse()
}

/// A surface point `X,Y` in mm.
pub fn parse_point(s: &str) -> Result<(f64, f64), String> {
    let bad = || format!("`{s}` is not a point X,Y in mm (such as 30,20.5)");
    let (x, y) = s.split_once(',').ok_or_else(bad)?;
    match (x.trim().parse::<f64>(), y.trim().parse::<f64>()) {
        (Ok(x), Ok(y)) if x.is_finite() && y.is_finite() => Ok((x, y)),
        _ => Err(bad()),
    }
}

fn parse_exaggerate(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(f) if f.is_finite() && f > 0.0 && f <= 1e6 => Ok(f),
        _ => Err(format!("`{s}` is not a factor above 0 (such as 2 or 0.5)")),
    }
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Compile drawings (.svg, .svgz) and meshes (.gltf, .glb) into bundles.
    Build {
        /// Input files or folders (folders are searched for .svg, .svgz, .gltf and .glb).
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        /// Output bundle (one input) or folder (several inputs).
        #[arg(long, short = 'o')]
        out: Option<PathBuf>,
        #[command(flatten)]
        opts: CompileOpts,
        /// Parallel jobs (default: all cores).
        #[arg(long, short = 'j')]
        jobs: Option<usize>,
        /// Build only shard I of N (1-based), e.g. 2/8.
        #[arg(long, value_name = "I/N")]
        shard: Option<String>,
        /// Rebuild even when the bundle is up to date.
        #[arg(long)]
        force: bool,
        /// List every diagnostic (by default one line per rule with its count).
        #[arg(long, short = 'v')]
        verbose: bool,
    },
    /// Print diagnostics without writing bundles; exit 1 on errors.
    Check {
        /// Input files or folders.
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        #[command(flatten)]
        opts: CompileOpts,
        /// Output format (JSON keeps every diagnostic).
        #[arg(long, value_enum, default_value_t)]
        format: Format,
        /// List every diagnostic (by default one line per rule with its count).
        #[arg(long, short = 'v')]
        verbose: bool,
    },
    /// Print a built-in style sheet as TOML, a starting point for your own.
    Style {
        /// Which sheet (the automatic one is the only built-in).
        #[arg(value_enum)]
        sheet: BuiltinSheet,
        /// A drawing: print the sheet as decided for it (each fill colour with
        /// the texture chosen for it, each line colour).
        input: Option<PathBuf>,
        #[command(flatten)]
        opts: CompileOpts,
    },
    /// Describe a bundle: profile, surface, layers and sizes.
    Inspect {
        /// The bundle.
        bundle: PathBuf,
        /// Output format.
        #[arg(long, value_enum, default_value_t)]
        format: Format,
        /// Name the element under this surface point (mm, x right, y down) instead.
        #[arg(long, value_name = "X,Y", value_parser = parse_point)]
        at: Option<(f64, f64)>,
    },
    /// Turn an unpacked folder back into a bundle.
    Pack {
        /// The folder written by `taxel unpack`.
        dir: PathBuf,
        /// The bundle to write.
        #[arg(long, short = 'o', required = true)]
        out: PathBuf,
    },
    /// Write a bundle as a folder of TOML, PNG masks and CSV tables.
    Unpack {
        /// The bundle.
        bundle: PathBuf,
        /// The folder to write.
        #[arg(long, short = 'o', required = true)]
        out: PathBuf,
    },
    /// Draw a drawing or a bundle the way a reader will feel it.
    Preview {
        /// A drawing (.svg, .svgz, .gltf, .glb) or a bundle (.taxel).
        input: PathBuf,
        /// The PNG to write.
        #[arg(long, short = 'o', required = true)]
        out: PathBuf,
        #[command(flatten)]
        opts: CompileOpts,
    },
    /// Write a pin-display bundle as the device's own file.
    Export {
        /// The bundle (compiled for dotpad, monarch, graphiti, hyperbraille or another pin profile).
        bundle: PathBuf,
        /// The file format.
        #[arg(long, value_enum)]
        format: ExportFormat,
        /// The file to write.
        #[arg(long, short = 'o', required = true)]
        out: PathBuf,
    },
    /// Play a bundle: frames (CSV) for an exploration trace, or a WAV drive signal.
    Play {
        /// The bundle.
        bundle: PathBuf,
        /// Exploration trace (CSV with header `t_ms,x_mm,y_mm`, plus `contact` for the finger device; columns in
        /// any order, `#` comment lines, semicolons or tabs with decimal commas read too).
        #[arg(long)]
        trace: Option<PathBuf>,
        /// Output: FRAMES.csv, MOTORS.csv or DRIVE.wav (standard output when omitted).
        #[arg(long, short = 'o')]
        out: Option<PathBuf>,
        /// Also write what the finger touched along the trace (laterotactile bundles with
        /// footprints): one row `tick,x_mm,y_mm,element,id,line` each time the element
        /// under the carrier changes.
        #[arg(long, value_name = "ELEMENTS.csv")]
        elements: Option<PathBuf>,
    },
    /// Report error against run time over a ladder of settings.
    Report {
        /// A drawing or mesh.
        input: PathBuf,
        #[command(flatten)]
        opts: CompileOpts,
        /// Also draw error against run time to this PNG.
        #[arg(long)]
        plot: Option<PathBuf>,
        /// Measure the compiler's default setting alone, not the whole ladder (quicker).
        #[arg(long)]
        default_only: bool,
        /// Output format.
        #[arg(long, value_enum, default_value_t)]
        format: Format,
    },
    /// Load bundles onto a device (a mounted folder or tcp://HOST:PORT).
    Load {
        /// The bundles.
        #[arg(required = true)]
        bundles: Vec<PathBuf>,
        /// The device: a folder (USB storage, SD card) or tcp://HOST:PORT.
        #[arg(long, required = true)]
        device: String,
    },
    /// Device simulator and device management.
    #[command(subcommand)]
    Device(DeviceCommand),
    /// List the built-in device profiles.
    Profiles,
    /// Install or remove the Inkscape extension (Extensions > Tactile: style, check, preview, export).
    #[command(subcommand)]
    Inkscape(InkscapeCommand),
    /// A local web app: open a drawing, see and hear what will be felt, fix
    /// a style, download the bundle, explore it (docs/studio.md).
    Studio {
        /// A drawing, mesh, bundle or folder (default: the current folder).
        path: Option<PathBuf>,
        /// Port to listen on (default 8470, or any free one when it is taken; 0: any free one).
        #[arg(long, value_name = "N")]
        port: Option<u16>,
        /// Do not open the default browser.
        #[arg(long)]
        no_open: bool,
        /// Address to listen on (default 127.0.0.1, this machine only).
        #[arg(long, value_name = "ADDR")]
        listen: Option<std::net::IpAddr>,
        #[command(flatten)]
        opts: CompileOpts,
    },
}

/// `taxel inkscape ...`
#[derive(Debug, Subcommand)]
pub enum InkscapeCommand {
    /// Copy the extension into Inkscape's user extensions folder (a `taxel` folder inside it).
    Install {
        /// The extensions folder (default: Inkscape's user extensions folder for this system).
        #[arg(long, value_name = "DIR")]
        dir: Option<PathBuf>,
    },
    /// Remove the extension's files from that folder (and nothing else).
    Uninstall {
        /// The extensions folder (default: Inkscape's user extensions folder for this system).
        #[arg(long, value_name = "DIR")]
        dir: Option<PathBuf>,
    },
}

/// `taxel device ...`
#[derive(Debug, Subcommand)]
pub enum DeviceCommand {
    /// Run a device simulator that stores bundles like a real device.
    Serve {
        /// Where the simulated device keeps its bundles.
        #[arg(long, required = true)]
        store: PathBuf,
        /// Address to listen on (loopback), e.g. 127.0.0.1:7878.
        #[arg(long, required = true)]
        listen: String,
        /// Storage capacity in bytes.
        #[arg(long)]
        capacity: Option<u64>,
        /// Device profile the simulated device accepts.
        #[arg(long)]
        profile: Option<String>,
    },
    /// List the bundles on a device.
    Ls {
        /// The device: a folder or tcp://HOST:PORT.
        #[arg(long, required = true)]
        device: String,
    },
    /// Delete a bundle from a device.
    Rm {
        /// The bundle's name on the device.
        name: String,
        /// The device: a folder or tcp://HOST:PORT.
        #[arg(long, required = true)]
        device: String,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lang_takes_comma_separated_tags_and_refuses_others() {
        assert_eq!(parse_lang("fr").unwrap(), "fr");
        assert_eq!(parse_lang("fr-CA, fr").unwrap(), "fr-CA,fr");
        assert!(parse_lang("").unwrap_err().contains("expected a language tag"));
        assert!(parse_lang("fr_FR.UTF-8").unwrap_err().contains("`fr_FR.UTF-8` is not a language tag"));
    }

    #[test]
    fn memory_sizes_read_in_powers_of_1024() {
        assert_eq!(parse_memory("512M"), Ok(512 << 20));
        assert_eq!(parse_memory("2G"), Ok(2 << 30));
        assert_eq!(parse_memory("2 GiB"), Ok(2 << 30));
        assert_eq!(parse_memory("1.5gb"), Ok(3 << 29));
        assert_eq!(parse_memory("100000000"), Ok(100_000_000));
        assert_eq!(parse_memory("none"), Ok(usize::MAX));
        assert_eq!(parse_memory("1K"), Ok(1024));
        assert!(parse_memory("0").unwrap_err().contains("at least 1 byte"));
        assert!(parse_memory("lots").unwrap_err().contains("not a memory size"));
        assert!(parse_memory("2X").unwrap_err().contains("not a memory size"));
    }
}
