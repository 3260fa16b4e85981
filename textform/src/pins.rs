//! The text form of a pin image (`NN-pins.txt`): the heights as a grid of
//! characters, one line per pin row (`.` flush, `1` to `F` the raised height
//! in hexadecimal), a blank line, then the blinking pins as a second grid of
//! the same size (`*` blinks, `.` does not). The manifest's chunk entry holds
//! `navigation` (`pages` or `pan`), `blink_ms` and the text line as `text`
//! (hexadecimal, two digits per cell). Readable and editable in any editor.

use std::fmt::Write as _;

use taxel_format::{MAX_PIN_SIDE, Navigation, Pin, PinImage};

use super::error::TextError;
use super::toml_in::Table;

/// Keys of a `pins` chunk entry.
pub const PINS_KEYS: &[&str] = &["kind", "file", "navigation", "blink_ms", "text"];

/// The chunk entry's lines (after `[[chunk]]`) and the grid file's text.
pub fn write(image: &PinImage, file: &str) -> (String, Vec<u8>) {
    let text: String = image.text.iter().map(|b| format!("{b:02x}")).collect();
    let entry = format!(
        "kind = \"pins\"\nfile = \"{file}\"\nnavigation = \"{}\"\nblink_ms = {}\ntext = \"{text}\"\n",
        image.navigation.name(),
        image.blink_ms
    );
    let mut grid = String::with_capacity(2 * (image.cols as usize + 1) * image.rows as usize + 1);
    for r in 0..image.rows {
        for c in 0..image.cols {
            let h = image.get(c, r).height();
            grid.push(if h == 0 { '.' } else { char::from_digit(h as u32, 16).unwrap_or('F').to_ascii_uppercase() });
        }
        grid.push('\n');
    }
    grid.push('\n');
    for r in 0..image.rows {
        for c in 0..image.cols {
            grid.push(if image.get(c, r).blinks() { '*' } else { '.' });
        }
        let _ = writeln!(grid);
    }
    (entry, grid.into_bytes())
}

/// Reads a pin image back from its chunk entry and grid file.
pub fn read(c: &Table<'_, '_>, file: &str, data: &[u8]) -> Result<PinImage, TextError> {
    let navigation = match c.str("navigation")? {
        "pages" => Navigation::Pages,
        "pan" => Navigation::Pan,
        other => return Err(c.err("navigation", format!("unknown navigation \"{other}\", expected pages or pan"))),
    };
    let blink_ms = c.uint("blink_ms", u32::MAX as u64)? as u32;
    let hex = c.str("text")?;
    let text = (0..hex.len() / 2)
        .map(|i| hex.get(2 * i..2 * i + 2).and_then(|d| u8::from_str_radix(d, 16).ok()))
        .collect::<Option<Vec<u8>>>()
        .filter(|_| hex.len() % 2 == 0)
        .ok_or_else(|| c.err("text", "expected hexadecimal digits, two per cell"))?;
    let grid = std::str::from_utf8(data).map_err(|_| TextError::new(file, "expected UTF-8 text"))?;
    let lines: Vec<&str> = grid.lines().collect();
    let rows = lines
        .iter()
        .position(|l| l.is_empty())
        .ok_or_else(|| TextError::new(file, "expected the heights, a blank line, then the blinking pins"))?;
    let cols = lines.first().map_or(0, |l| l.chars().count());
    if rows == 0 || cols == 0 || rows > MAX_PIN_SIDE as usize || cols > MAX_PIN_SIDE as usize {
        return Err(TextError::new(file, format!("expected 1 to {MAX_PIN_SIDE} rows and columns of pins")));
    }
    if lines.len() != 2 * rows + 1 {
        return Err(TextError::new(file, format!("expected {rows} lines of blinking pins after the blank line")));
    }
    let mut image = PinImage::new(cols as u32, rows as u32);
    image.navigation = navigation;
    image.blink_ms = blink_ms;
    image.text = text;
    for (r, (heights, blinks)) in lines[..rows].iter().zip(&lines[rows + 1..]).enumerate() {
        let line = r + 1;
        if heights.chars().count() != cols || blinks.chars().count() != cols {
            return Err(TextError::at(file, line, format!("expected {cols} pins on every line")));
        }
        for (k, (h, b)) in heights.chars().zip(blinks.chars()).enumerate() {
            let height = match h {
                '.' => 0,
                d => d.to_digit(16).filter(|&v| v > 0).ok_or_else(|| {
                    TextError::at(file, line, format!("pin {}: expected `.` or a height 1 to F", k + 1))
                })?,
            };
            let blink = match b {
                '*' => true,
                '.' => false,
                _ => {
                    return Err(TextError::at(
                        file,
                        rows + 1 + line,
                        format!("pin {}: expected `*` (blinks) or `.`", k + 1),
                    ));
                }
            };
            if blink && height == 0 {
                return Err(TextError::at(file, rows + 1 + line, format!("pin {}: a flush pin cannot blink", k + 1)));
            }
            image.set(k as u32, r as u32, Pin::new(height as u8, blink));
        }
    }
    Ok(image)
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use taxel_format::{Bundle, Chunk, Manifest, Navigation, Pin, PinImage, profiles};

    use super::super::{pack, unpack};
    use super::*;

    fn graphiti_bundle() -> Vec<u8> {
        let mut im = PinImage::new(5, 3);
        im.set(0, 0, Pin::new(4, true));
        im.set(4, 2, Pin::new(2, false));
        im.blink_ms = 500;
        im.navigation = Navigation::Pan;
        let mut b = Bundle::new(Manifest::new(profiles::builtin("graphiti").unwrap()));
        b.chunks.push(Chunk::Pins(im));
        b.to_bytes().unwrap()
    }

    #[test]
    fn a_pin_image_unpacks_to_readable_grids_and_packs_back_byte_for_byte() {
        let bytes = graphiti_bundle();
        let files: BTreeMap<String, Vec<u8>> = unpack("b.taxel", &bytes).unwrap().into_iter().collect();
        let grid = String::from_utf8(files["01-pins.txt"].clone()).unwrap();
        assert_eq!(grid, "4....\n.....\n....2\n\n*....\n.....\n.....\n");
        let read = |name: &str| files.get(name).cloned().ok_or_else(|| TextError::io(name, "missing"));
        assert_eq!(pack(&read).unwrap(), bytes);
    }

    #[test]
    fn mistakes_in_the_grids_name_the_line() {
        let bytes = graphiti_bundle();
        let mut files: BTreeMap<String, Vec<u8>> = unpack("b.taxel", &bytes).unwrap().into_iter().collect();
        for (grid, want) in [
            ("4....\n..x..\n....2\n\n*....\n.....\n.....\n", "01-pins.txt:2: pin 3: expected `.` or a height 1 to F"),
            ("4....\n.....\n....2\n\n*....\n.*...\n.....\n", "01-pins.txt:6: pin 2: a flush pin cannot blink"),
            ("4....\n....\n....2\n\n*....\n.....\n.....\n", "01-pins.txt:2: expected 5 pins on every line"),
        ] {
            files.insert("01-pins.txt".into(), grid.as_bytes().to_vec());
            let read = |name: &str| files.get(name).cloned().ok_or_else(|| TextError::io(name, "missing"));
            let e = pack(&read).unwrap_err();
            assert_eq!(e.to_string(), want);
        }
    }
}
