//! Dot tables, height fields, provenance and footprints as CSV; stroke tables as TOML
//! (strokes hold points that hold drives, which a flat table would lose for
//! a stroke without points).

use std::fmt::Write as _;

use taxel_format::{
    ActuatorIndex, Dot, Drive, FIELD_CONTACT, FIELD_EDGE, Footprint, FootprintKind, HeightField, MilliHertz, Mm,
    Provenance, ProvenanceEntry, Stroke, StrokePoint, StrokeTable, Tick,
};

use super::error::TextError;
use super::toml_in::{Doc, f32_text, toml_string};

pub const DOTS_HEADER: &[&str] = &["x_mm", "y_mm", "radius_mm", "amplitude", "source"];
pub const HEIGHT_HEADER: &[&str] = &["col", "row", "height_mm", "grad_x", "grad_y", "contact", "edge"];
pub const PROVENANCE_HEADER: &[&str] = &["index", "id", "label", "line"];
pub const FOOTPRINTS_HEADER: &[&str] = &["shape", "source", "kind", "half_width_q", "points_q"];

const FOOTPRINT_KINDS: [(FootprintKind, &str); 4] = [
    (FootprintKind::AreaNonZero, "area-nonzero"),
    (FootprintKind::AreaEvenOdd, "area-evenodd"),
    (FootprintKind::Line, "line"),
    (FootprintKind::ClosedLine, "closed-line"),
];

fn opt(v: Option<u32>) -> String {
    v.map_or_else(String::new, |s| s.to_string())
}

fn csv_bytes(header: &[&str], rows: impl Iterator<Item = Vec<String>>) -> Vec<u8> {
    let mut w = csv::WriterBuilder::new().terminator(csv::Terminator::Any(b'\n')).from_writer(Vec::new());
    // Writing to a Vec cannot fail.
    let _ = w.write_record(header);
    for r in rows {
        let _ = w.write_record(&r);
    }
    w.into_inner().unwrap_or_default()
}

/// The CSV of a dot table.
pub fn dots_csv(dots: &[Dot]) -> Vec<u8> {
    csv_bytes(
        DOTS_HEADER,
        dots.iter().map(|d| {
            vec![f32_text(d.x.0), f32_text(d.y.0), f32_text(d.radius.0), f32_text(d.amplitude), opt(d.source)]
        }),
    )
}

/// The CSV of a height field: one row per node, row-major.
pub fn height_csv(h: &HeightField) -> Vec<u8> {
    let n = h.cols as usize * h.rows as usize;
    csv_bytes(
        HEIGHT_HEADER,
        (0..n).map(|k| {
            let f = h.flags.get(k).copied().unwrap_or(0);
            vec![
                (k % h.cols as usize).to_string(),
                (k / h.cols as usize).to_string(),
                f32_text(h.heights.get(k).copied().unwrap_or(0.0)),
                f32_text(h.grad_x.get(k).copied().unwrap_or(0.0)),
                f32_text(h.grad_y.get(k).copied().unwrap_or(0.0)),
                u8::from(f & FIELD_CONTACT != 0).to_string(),
                u8::from(f & FIELD_EDGE != 0).to_string(),
            ]
        }),
    )
}

/// The CSV of a provenance table.
pub fn provenance_csv(p: &Provenance) -> Vec<u8> {
    csv_bytes(
        PROVENANCE_HEADER,
        p.entries
            .iter()
            .enumerate()
            .map(|(i, e)| vec![i.to_string(), e.id.clone(), e.label.clone(), e.line.to_string()]),
    )
}

/// The CSV of footprint shapes: one row per ring, its points as `x y`
/// pairs in quanta separated by `;` (SPEC.md section 10.1).
pub fn footprints_csv(shapes: &[Footprint]) -> Vec<u8> {
    csv_bytes(
        FOOTPRINTS_HEADER,
        shapes.iter().enumerate().flat_map(|(i, s)| {
            let kind = FOOTPRINT_KINDS.iter().find(|k| k.0 == s.kind).map_or("line", |k| k.1);
            s.rings.iter().map(move |r| {
                let pts: Vec<String> = r.iter().map(|(x, y)| format!("{x} {y}")).collect();
                vec![i.to_string(), s.source.to_string(), kind.to_string(), s.half_width.to_string(), pts.join(";")]
            })
        }),
    )
}

/// Parses a footprints CSV: rows of one shape are consecutive, shapes
/// numbered from 0 in order.
pub fn parse_footprints(file: &str, bytes: &[u8]) -> Result<Vec<Footprint>, TextError> {
    let mut shapes: Vec<Footprint> = Vec::new();
    for (line, rec) in csv_records(file, bytes, FOOTPRINTS_HEADER)? {
        let f = Field { file, line, rec: &rec, header: FOOTPRINTS_HEADER };
        let i = f.uint(0, u32::MAX as u64)? as usize;
        let source = f.uint(1, taxel_format::MAX_PROVENANCE_ENTRIES as u64 - 1)? as u32;
        let kind = FOOTPRINT_KINDS
            .iter()
            .find(|k| k.1 == f.text(2))
            .map(|k| k.0)
            .ok_or_else(|| f.err(2, "area-nonzero, area-evenodd, line or closed-line"))?;
        let half_width = f.uint(3, u16::MAX as u64)? as u16;
        let mut ring = Vec::new();
        for pair in f.text(4).split(';') {
            let mut it = pair.split_whitespace().map(|v| v.parse::<u16>());
            match (it.next(), it.next(), it.next()) {
                (Some(Ok(x)), Some(Ok(y)), None) => ring.push((x, y)),
                _ => return Err(f.err(4, "points `x y` (integers 0 to 65535) separated by `;`")),
            }
        }
        let n = shapes.len();
        match shapes.last_mut() {
            Some(last) if i + 1 == n => {
                if (last.source, last.kind, last.half_width) != (source, kind, half_width) {
                    return Err(f.err(0, "the same source, kind and half width on every row of one shape"));
                }
                last.rings.push(ring);
            }
            _ if i == n => shapes.push(Footprint { source, kind, half_width, rings: vec![ring] }),
            _ => {
                let expected = if n == 0 { "0".to_string() } else { format!("{} or {n}", n - 1) };
                return Err(f.err(0, &format!("{expected} (shapes are numbered from 0, in order)")));
            }
        }
    }
    Ok(shapes)
}

/// The TOML of a stroke table.
pub fn strokes_toml(t: &StrokeTable) -> Vec<u8> {
    let mut s = String::from(
        "# Strokes in ticks of the profile's rate_hz; carriers in millihertz; positions in mm.\n\
         # Point times are ticks after the stroke's start. Each point drives the listed\n\
         # actuators (row-major index) at the listed intensities (0 to 1).\n",
    );
    for st in &t.strokes {
        let _ = write!(
            s,
            "\n[[stroke]]\nstart_tick = {}\nduration_ticks = {}\ncarrier_mhz = {}\nintensity = {}\n",
            st.start.0,
            st.duration,
            st.carrier.0,
            f32_text(st.intensity)
        );
        if let Some(src) = st.source {
            let _ = writeln!(s, "source = {src}");
        }
        for p in &st.points {
            let acts: Vec<String> = p.drives.iter().map(|d| d.actuator.0.to_string()).collect();
            let ints: Vec<String> = p.drives.iter().map(|d| f32_text(d.intensity)).collect();
            let _ = write!(
                s,
                "\n[[stroke.point]]\nonset_tick = {}\nduration_ticks = {}\npeak_tick = {}\nx_mm = {}\ny_mm = {}\nactuators = [{}]\nintensities = [{}]\n",
                p.onset,
                p.duration,
                p.peak,
                f32_text(p.x.0),
                f32_text(p.y.0),
                acts.join(", "),
                ints.join(", ")
            );
        }
    }
    s.into_bytes()
}

/// CSV of `rows` with no header line (a distance layer's tile index and plane records).
pub fn csv_rows(rows: impl Iterator<Item = Vec<String>>) -> Vec<u8> {
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .flexible(true)
        .terminator(csv::Terminator::Any(b'\n'))
        .from_writer(Vec::new());
    // Writing to a Vec cannot fail.
    for r in rows {
        let _ = w.write_record(&r);
    }
    w.into_inner().unwrap_or_default()
}

/// Reads CSV with no header line whose every row has `width` fields, each
/// parsed by `parse` (`what` names them in the error); yields the values in
/// row order. Fields may be padded with spaces.
pub fn parse_rows<T>(
    file: &str,
    bytes: &[u8],
    width: usize,
    what: &str,
    parse: impl Fn(&str) -> Option<T>,
) -> Result<Vec<T>, TextError> {
    let mut r = csv::ReaderBuilder::new().has_headers(false).flexible(true).trim(csv::Trim::All).from_reader(bytes);
    let mut out = Vec::new();
    for rec in r.records() {
        let rec = rec.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line() as usize);
            TextError::at(file, line, format!("not valid CSV: {e}"))
        })?;
        let line = rec.position().map_or(0, |p| p.line() as usize);
        if rec.len() != width {
            return Err(TextError::at(file, line, format!("expected {width} {what}, found {}", rec.len())));
        }
        for field in &rec {
            out.push(
                parse(field).ok_or_else(|| TextError::at(file, line, format!("expected {what}, found `{field}`")))?,
            );
        }
    }
    Ok(out)
}

/// Reads CSV records after checking the header; yields `(line, record)`.
fn csv_records(file: &str, bytes: &[u8], header: &[&str]) -> Result<Vec<(usize, csv::StringRecord)>, TextError> {
    let mut r = csv::ReaderBuilder::new().has_headers(true).from_reader(bytes);
    let found = r.headers().map_err(|e| TextError::at(file, 1, format!("cannot read the header: {e}")))?.clone();
    if found.iter().collect::<Vec<_>>() != header {
        return Err(TextError::at(file, 1, format!("expected the header `{}`", header.join(","))));
    }
    let mut out = Vec::new();
    for rec in r.records() {
        let rec = rec.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line() as usize);
            TextError::at(file, line, format!("not valid CSV: {e}"))
        })?;
        let line = rec.position().map_or(0, |p| p.line() as usize);
        if rec.len() != header.len() {
            return Err(TextError::at(file, line, format!("expected {} fields, found {}", header.len(), rec.len())));
        }
        out.push((line, rec));
    }
    Ok(out)
}

/// A field of a CSV record, parsed.
struct Field<'a> {
    file: &'a str,
    line: usize,
    rec: &'a csv::StringRecord,
    header: &'a [&'a str],
}

impl Field<'_> {
    fn text(&self, col: usize) -> &str {
        self.rec.get(col).unwrap_or("").trim()
    }

    fn err(&self, col: usize, expected: &str) -> TextError {
        let name = self.header.get(col).copied().unwrap_or("?");
        TextError::at(self.file, self.line, format!("column `{name}`: expected {expected}, found `{}`", self.text(col)))
    }

    fn f32(&self, col: usize) -> Result<f32, TextError> {
        self.text(col).parse::<f32>().map_err(|_| self.err(col, "a number"))
    }

    fn uint(&self, col: usize, max: u64) -> Result<u64, TextError> {
        self.text(col)
            .parse::<u64>()
            .ok()
            .filter(|&v| v <= max)
            .ok_or_else(|| self.err(col, &format!("an integer from 0 to {max}")))
    }

    fn source(&self, col: usize) -> Result<Option<u32>, TextError> {
        if self.text(col).is_empty() {
            return Ok(None);
        }
        // u32::MAX is the format's "none", so it cannot be an index.
        self.uint(col, u32::MAX as u64 - 1).map(|v| Some(v as u32))
    }

    fn flag(&self, col: usize) -> Result<bool, TextError> {
        match self.text(col) {
            "0" => Ok(false),
            "1" => Ok(true),
            _ => Err(self.err(col, "0 or 1")),
        }
    }
}

/// Parses a dot table CSV.
pub fn parse_dots(file: &str, bytes: &[u8]) -> Result<Vec<Dot>, TextError> {
    csv_records(file, bytes, DOTS_HEADER)?
        .iter()
        .map(|(line, rec)| {
            let f = Field { file, line: *line, rec, header: DOTS_HEADER };
            Ok(Dot {
                x: Mm(f.f32(0)?),
                y: Mm(f.f32(1)?),
                radius: Mm(f.f32(2)?),
                amplitude: f.f32(3)?,
                source: f.source(4)?,
            })
        })
        .collect()
}

/// Fills the node arrays of `h` (whose `cols` and `rows` are set) from its CSV.
pub fn parse_height(file: &str, bytes: &[u8], h: &mut HeightField) -> Result<(), TextError> {
    let n = h.cols as usize * h.rows as usize;
    let mut seen = vec![false; n];
    h.heights = vec![0.0; n];
    h.grad_x = vec![0.0; n];
    h.grad_y = vec![0.0; n];
    h.flags = vec![0; n];
    for (line, rec) in csv_records(file, bytes, HEIGHT_HEADER)? {
        let f = Field { file, line, rec: &rec, header: HEIGHT_HEADER };
        let col = f.uint(0, h.cols.saturating_sub(1) as u64)? as usize;
        let row = f.uint(1, h.rows.saturating_sub(1) as u64)? as usize;
        let k = row * h.cols as usize + col;
        if std::mem::replace(&mut seen[k], true) {
            return Err(TextError::at(file, line, format!("node ({col}, {row}) is listed twice")));
        }
        h.heights[k] = f.f32(2)?;
        h.grad_x[k] = f.f32(3)?;
        h.grad_y[k] = f.f32(4)?;
        h.flags[k] = if f.flag(5)? { FIELD_CONTACT } else { 0 } | if f.flag(6)? { FIELD_EDGE } else { 0 };
    }
    if let Some(k) = seen.iter().position(|s| !s) {
        let (col, row) = (k % h.cols as usize, k / h.cols as usize);
        return Err(TextError::new(
            file,
            format!("node ({col}, {row}) is missing: expected one row per node of the {} x {} grid", h.cols, h.rows),
        ));
    }
    Ok(())
}

/// Parses a provenance CSV; entries must be listed in index order from 0.
pub fn parse_provenance(file: &str, bytes: &[u8]) -> Result<Provenance, TextError> {
    let mut entries = Vec::new();
    for (line, rec) in csv_records(file, bytes, PROVENANCE_HEADER)? {
        let f = Field { file, line, rec: &rec, header: PROVENANCE_HEADER };
        let i = entries.len();
        if f.uint(0, u32::MAX as u64)? != i as u64 {
            return Err(f.err(0, &format!("{i} (entries are numbered from 0, in order, because layers refer to them)")));
        }
        let text = |col: usize| rec.get(col).unwrap_or("").to_string();
        let (id, label) = (text(1), text(2));
        for (col, s) in [(1, &id), (2, &label)] {
            if s.len() > u16::MAX as usize {
                return Err(f.err(col, "at most 65535 bytes"));
            }
        }
        entries.push(ProvenanceEntry { id, label, line: f.uint(3, u32::MAX as u64)? as u32 });
    }
    Ok(Provenance { entries })
}

const STROKE_KEYS: &[&str] = &["start_tick", "duration_ticks", "carrier_mhz", "intensity", "source", "point"];
const POINT_KEYS: &[&str] = &["onset_tick", "duration_ticks", "peak_tick", "x_mm", "y_mm", "actuators", "intensities"];

/// Parses a stroke table TOML.
pub fn parse_strokes(file: &str, bytes: &[u8]) -> Result<StrokeTable, TextError> {
    let text = std::str::from_utf8(bytes).map_err(|_| TextError::new(file, "expected UTF-8 text"))?;
    let doc = Doc::parse(file, text)?;
    let root = doc.root(&["stroke"])?;
    let u32max = u32::MAX as u64;
    let mut strokes = Vec::new();
    for s in root.tables("stroke", STROKE_KEYS)? {
        let mut points = Vec::new();
        for p in s.tables("point", POINT_KEYS)? {
            let acts = p.uint_array("actuators", u16::MAX as u64)?;
            let ints = p.f32_array("intensities")?;
            if acts.len() != ints.len() {
                return Err(p.err("intensities", format!("expected one intensity per actuator ({})", acts.len())));
            }
            points.push(StrokePoint {
                onset: p.uint("onset_tick", u32max)? as u32,
                duration: p.uint("duration_ticks", u32max)? as u32,
                peak: p.uint("peak_tick", u32max)? as u32,
                x: Mm(p.f32("x_mm")?),
                y: Mm(p.f32("y_mm")?),
                drives: acts
                    .iter()
                    .zip(&ints)
                    .map(|(&a, &i)| Drive { actuator: ActuatorIndex(a as u16), intensity: i })
                    .collect(),
            });
        }
        strokes.push(Stroke {
            start: Tick(s.uint("start_tick", u64::MAX)?),
            duration: s.uint("duration_ticks", u32max)? as u32,
            carrier: MilliHertz(s.uint("carrier_mhz", u32max)? as u32),
            intensity: s.f32("intensity")?,
            source: s.opt_uint("source", u32max - 1)?.map(|v| v as u32),
            points,
        });
    }
    Ok(StrokeTable { strokes })
}

/// The quoted TOML text of `s` (re-exported for the manifest writer).
pub fn quoted(s: &str) -> String {
    toml_string(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_errors_name_file_line_and_column() {
        let e = parse_dots("03-dots.csv", b"x_mm,y_mm,radius_mm,amplitude,source\n1,2,3,4,\n1,2,x,4,\n").unwrap_err();
        assert_eq!(e.to_string(), "03-dots.csv:3: column `radius_mm`: expected a number, found `x`");
        let e = parse_dots("03-dots.csv", b"x,y\n").unwrap_err();
        assert_eq!(e.to_string(), "03-dots.csv:1: expected the header `x_mm,y_mm,radius_mm,amplitude,source`");
        let e = parse_dots("d.csv", b"x_mm,y_mm,radius_mm,amplitude,source\n1,2,3\n").unwrap_err();
        assert_eq!(e.line, Some(2));
        let e = parse_provenance("p.csv", b"index,id,label,line\n1,a,b,0\n").unwrap_err();
        assert!(e.to_string().starts_with("p.csv:2: column `index`: expected 0"), "{e}");
    }

    #[test]
    fn height_nodes_must_each_appear_once() {
        let mut h = HeightField {
            source: None,
            cols: 2,
            rows: 2,
            origin_x: Mm(0.0),
            origin_y: Mm(0.0),
            cell: Mm(1.0),
            gradient_cap: 1.0,
            heights: vec![],
            grad_x: vec![],
            grad_y: vec![],
            flags: vec![],
            encoding: taxel_format::HeightEncoding::Float,
        };
        let head = "col,row,height_mm,grad_x,grad_y,contact,edge\n";
        let e = parse_height("h.csv", format!("{head}0,0,1,0,0,1,0\n0,0,1,0,0,1,0\n").as_bytes(), &mut h).unwrap_err();
        assert_eq!(e.to_string(), "h.csv:3: node (0, 0) is listed twice");
        let e = parse_height("h.csv", format!("{head}0,0,1,0,0,1,0\n").as_bytes(), &mut h).unwrap_err();
        assert!(e.to_string().starts_with("h.csv: node (1, 0) is missing"), "{e}");
        let e = parse_height("h.csv", format!("{head}2,0,1,0,0,1,0\n").as_bytes(), &mut h).unwrap_err();
        assert_eq!(e.to_string(), "h.csv:2: column `col`: expected an integer from 0 to 1, found `2`");
    }

    #[test]
    fn stroke_errors_name_the_key() {
        let e = parse_strokes("s.toml", b"[[stroke]]\nstart_tick = 0\nduration_ticks = 5\ncarrier_mhz = 1\nintensity = 1.0\n\n[[stroke.point]]\nonset_tick = 0\n").unwrap_err();
        assert_eq!(e.to_string(), "s.toml:7: key `stroke[1].point[1].actuators`: missing key");
    }
}
