//! Braille: uncontracted Unified English Braille (grade 1) translation and
//! cell layout with NLS Specification 800 geometry.
//!
//! Braille is made from the text's characters, never from glyph outlines, so
//! it does not depend on fonts. Contracted (grade 2) braille is not supported.

/// Dot pitch within a cell (NLS Spec 800: 0.092 in).
pub const DOT_PITCH_MM: f64 = 2.34;
/// Distance between corresponding dots of neighbouring cells (0.245 in).
pub const CELL_PITCH_MM: f64 = 6.2;
/// Distance between corresponding dots of neighbouring lines (0.400 in).
pub const LINE_PITCH_MM: f64 = 10.2;

/// A braille cell: bit `k` is dot `k + 1` (dots 1-3 down the left column, 4-6 down the right).
pub type Cell = u8;

const fn cell(dots: &[u8]) -> Cell {
    let mut c = 0u8;
    let mut i = 0;
    while i < dots.len() {
        c |= 1 << (dots[i] - 1);
        i += 1;
    }
    c
}

const LETTERS: [Cell; 26] = [
    cell(&[1]),
    cell(&[1, 2]),
    cell(&[1, 4]),
    cell(&[1, 4, 5]),
    cell(&[1, 5]),
    cell(&[1, 2, 4]),
    cell(&[1, 2, 4, 5]),
    cell(&[1, 2, 5]),
    cell(&[2, 4]),
    cell(&[2, 4, 5]),
    cell(&[1, 3]),
    cell(&[1, 2, 3]),
    cell(&[1, 3, 4]),
    cell(&[1, 3, 4, 5]),
    cell(&[1, 3, 5]),
    cell(&[1, 2, 3, 4]),
    cell(&[1, 2, 3, 4, 5]),
    cell(&[1, 2, 3, 5]),
    cell(&[2, 3, 4]),
    cell(&[2, 3, 4, 5]),
    cell(&[1, 3, 6]),
    cell(&[1, 2, 3, 6]),
    cell(&[2, 4, 5, 6]),
    cell(&[1, 3, 4, 6]),
    cell(&[1, 3, 4, 5, 6]),
    cell(&[1, 3, 5, 6]),
];
/// Numeric indicator (dots 3456).
pub const NUMERIC: Cell = cell(&[3, 4, 5, 6]);
/// Capital letter indicator (dot 6); twice for a capitalised word.
pub const CAPITAL: Cell = cell(&[6]);
/// Grade 1 symbol indicator (dots 56), before a-j right after a number.
pub const GRADE1: Cell = cell(&[5, 6]);

/// UEB punctuation and signs taxel writes.
fn punctuation(c: char) -> Option<&'static [Cell]> {
    const fn one(d: &[u8]) -> [Cell; 1] {
        [cell(d)]
    }
    static COMMA: [Cell; 1] = one(&[2]);
    static SEMI: [Cell; 1] = one(&[2, 3]);
    static COLON: [Cell; 1] = one(&[2, 5]);
    static PERIOD: [Cell; 1] = one(&[2, 5, 6]);
    static EXCL: [Cell; 1] = one(&[2, 3, 5]);
    static QUESTION: [Cell; 1] = one(&[2, 3, 6]);
    static APOS: [Cell; 1] = one(&[3]);
    static HYPHEN: [Cell; 1] = one(&[3, 6]);
    static QUOTE: [Cell; 2] = [cell(&[6]), cell(&[2, 3, 5, 6])];
    static LPAREN: [Cell; 2] = [cell(&[5]), cell(&[1, 2, 6])];
    static RPAREN: [Cell; 2] = [cell(&[5]), cell(&[3, 4, 5])];
    static SLASH: [Cell; 2] = [cell(&[4, 5, 6]), cell(&[3, 4])];
    static AMP: [Cell; 2] = [cell(&[4]), cell(&[1, 2, 3, 4, 6])];
    static AT: [Cell; 2] = [cell(&[4]), cell(&[1])];
    static PERCENT: [Cell; 2] = [cell(&[4, 6]), cell(&[3, 5, 6])];
    static PLUS: [Cell; 2] = [cell(&[5]), cell(&[2, 3, 5])];
    static EQUALS: [Cell; 2] = [cell(&[5]), cell(&[2, 3, 5, 6])];
    static STAR: [Cell; 2] = [cell(&[5]), cell(&[3, 5])];
    Some(match c {
        ',' => &COMMA,
        ';' => &SEMI,
        ':' => &COLON,
        '.' => &PERIOD,
        '!' => &EXCL,
        '?' => &QUESTION,
        '\'' | '’' => &APOS,
        '-' => &HYPHEN,
        '"' | '“' | '”' => &QUOTE,
        '(' => &LPAREN,
        ')' => &RPAREN,
        '/' => &SLASH,
        '&' => &AMP,
        '@' => &AT,
        '%' => &PERCENT,
        '+' => &PLUS,
        '=' => &EQUALS,
        '*' => &STAR,
        _ => return None,
    })
}

/// The characters `missing` (as [`translate`] returns them) for a message:
/// each once, in the order they first appear in the text (sorted, an Arabic
/// or Hebrew word would read backwards, and a CJK one scrambled).
pub fn left_out(missing: &[char]) -> String {
    let mut seen = Vec::new();
    for &c in missing {
        if !seen.contains(&c) {
            seen.push(c);
        }
    }
    seen.into_iter().collect()
}

/// Translates text to uncontracted UEB cells (a space is an empty cell).
/// Returns the cells and the characters that have no translation (left out).
pub fn translate(text: &str) -> (Vec<Cell>, Vec<char>) {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::with_capacity(chars.len() + 4);
    let mut missing = Vec::new();
    let mut numeric = false;
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let next_is_digit = chars.get(i + 1).is_some_and(|n| n.is_ascii_digit());
        if c.is_ascii_digit() {
            if !numeric {
                out.push(NUMERIC);
                numeric = true;
            }
            let d = c as u8 - b'0';
            out.push(LETTERS[if d == 0 { 9 } else { d as usize - 1 }]);
        } else if numeric && (c == '.' || c == ',') && next_is_digit {
            // Numeric mode continues through a decimal point or digit separator.
            out.push(if c == '.' { cell(&[2, 5, 6]) } else { cell(&[2]) });
        } else if c.is_ascii_alphabetic() {
            let lower = c.to_ascii_lowercase();
            if numeric && !c.is_ascii_uppercase() && lower <= 'j' {
                out.push(GRADE1);
            }
            numeric = false;
            if c.is_ascii_uppercase() {
                let word_start = i == 0 || !chars[i - 1].is_ascii_alphabetic();
                let word: Vec<char> = chars[i..].iter().take_while(|c| c.is_ascii_alphabetic()).copied().collect();
                let caps_word = word.len() >= 2 && word.iter().all(|c| c.is_ascii_uppercase());
                let in_caps_word = {
                    let start = chars[..i].iter().rposition(|c| !c.is_ascii_alphabetic()).map_or(0, |p| p + 1);
                    let w: Vec<char> = chars[start..].iter().take_while(|c| c.is_ascii_alphabetic()).copied().collect();
                    w.len() >= 2 && w.iter().all(|c| c.is_ascii_uppercase())
                };
                if word_start && caps_word {
                    out.extend([CAPITAL, CAPITAL]);
                } else if !in_caps_word {
                    out.push(CAPITAL);
                }
            }
            out.push(LETTERS[(lower as u8 - b'a') as usize]);
        } else if c.is_whitespace() {
            numeric = false;
            out.push(0);
        } else if let Some(cells) = punctuation(c) {
            numeric = false;
            out.extend_from_slice(cells);
        } else {
            numeric = false;
            missing.push(c);
        }
        i += 1;
    }
    (out, missing)
}

/// Dot centres of a run of cells whose first cell's left edge is at `x0` and
/// whose lowest dots rest on the baseline `baseline` (page mm), dots of radius `r`.
pub fn layout(cells: &[Cell], x0: f64, baseline: f64, r: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for (k, &c) in cells.iter().enumerate() {
        let left = x0 + k as f64 * CELL_PITCH_MM + r;
        for dot in 0..6 {
            if c & (1 << dot) != 0 {
                let col = (dot / 3) as f64;
                let row = (dot % 3) as f64;
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

    /// Cells written as dot-number strings, for readable expectations.
    fn cells(spec: &[&str]) -> Vec<Cell> {
        spec.iter().map(|s| s.bytes().fold(0u8, |c, d| if d == b' ' { c } else { c | 1 << (d - b'1') })).collect()
    }

    #[test]
    fn letters_capitals_and_numbers_follow_ueb() {
        // "Hi 42": capital h i, space, numeric indicator, d b.
        let (c, missing) = translate("Hi 42");
        assert!(missing.is_empty());
        assert_eq!(c, [cells(&["6", "125", "24"]), vec![0], cells(&["3456", "145", "12"])].concat());
        // An all-capital word takes the capital word indicator once.
        assert_eq!(translate("OK").0, cells(&["6", "6", "135", "13"]));
        // a-j right after a number needs the grade 1 indicator.
        assert_eq!(translate("1a").0, cells(&["3456", "1", "56", "1"]));
        // A decimal point stays in numeric mode.
        assert_eq!(translate("2.5").0, cells(&["3456", "12", "256", "15"]));
        assert_eq!(translate("é").1, vec!['é']);
    }

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
    }
}
