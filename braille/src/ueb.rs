//! The built-in braille table: uncontracted Unified English Braille (grade
//! 1), used when liblouis is not installed (or not wanted).
//!
//! A Latin letter with diacritics (a place name's é, ü, ñ, ç, whether written
//! as one character or as a letter and combining marks) is its letter after
//! the UEB modifiers of its marks (The Rules of UEB, section 4.2), the capital
//! indicator first. Signs are those of the UEB reference list ("Guide to
//! Reading UEB", ICEB; The Rules of UEB, section 3); a character with no
//! sign here is left out and named in a warning.

use unicode_normalization::UnicodeNormalization;

pub use crate::Cell;

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
    static DOLLAR: [Cell; 2] = [cell(&[4]), cell(&[2, 3, 4])];
    static POUND: [Cell; 2] = [cell(&[4]), cell(&[1, 2, 3])];
    static EURO: [Cell; 2] = [cell(&[4]), cell(&[1, 5])];
    static CENT: [Cell; 2] = [cell(&[4]), cell(&[1, 4])];
    static YEN: [Cell; 2] = [cell(&[4]), cell(&[1, 3, 4, 5, 6])];
    static DEGREE: [Cell; 2] = [cell(&[4, 5]), cell(&[2, 4, 5])];
    static LESS: [Cell; 2] = [cell(&[4]), cell(&[1, 2, 6])];
    static GREATER: [Cell; 2] = [cell(&[4]), cell(&[3, 4, 5])];
    static LSQUARE: [Cell; 2] = [cell(&[4, 6]), cell(&[1, 2, 6])];
    static RSQUARE: [Cell; 2] = [cell(&[4, 6]), cell(&[3, 4, 5])];
    static LCURLY: [Cell; 2] = [cell(&[4, 5, 6]), cell(&[1, 2, 6])];
    static RCURLY: [Cell; 2] = [cell(&[4, 5, 6]), cell(&[3, 4, 5])];
    static NUMBER_SIGN: [Cell; 2] = [cell(&[4, 5, 6]), cell(&[1, 4, 5, 6])];
    static UNDERSCORE: [Cell; 2] = [cell(&[4, 6]), cell(&[3, 6])];
    static TILDE: [Cell; 2] = [cell(&[4]), cell(&[3, 5])];
    static CARET: [Cell; 2] = [cell(&[4]), cell(&[2, 6])];
    static BAR: [Cell; 2] = [cell(&[4, 5, 6]), cell(&[1, 2, 5, 6])];
    static BACKSLASH: [Cell; 2] = [cell(&[4, 5, 6]), cell(&[1, 6])];
    static GRAVE: [Cell; 2] = [cell(&[4, 5]), cell(&[1, 6])];
    static EN_DASH: [Cell; 2] = [cell(&[6]), cell(&[3, 6])];
    static EM_DASH: [Cell; 3] = [cell(&[5]), cell(&[6]), cell(&[3, 6])];
    static ELLIPSIS: [Cell; 3] = [cell(&[2, 5, 6]), cell(&[2, 5, 6]), cell(&[2, 5, 6])];
    static TIMES: [Cell; 2] = [cell(&[5]), cell(&[2, 3, 6])];
    static DIVIDE: [Cell; 2] = [cell(&[5]), cell(&[3, 4])];
    static MINUS: [Cell; 2] = [cell(&[5]), cell(&[3, 6])];
    static OPEN_QUOTE: [Cell; 1] = one(&[2, 3, 6]);
    static CLOSE_QUOTE: [Cell; 1] = one(&[3, 5, 6]);
    static OPEN_SINGLE: [Cell; 2] = [cell(&[6]), cell(&[2, 3, 6])];
    Some(match c {
        ',' => &COMMA,
        ';' => &SEMI,
        ':' => &COLON,
        '.' => &PERIOD,
        '!' => &EXCL,
        '?' => &QUESTION,
        '\'' | '’' => &APOS,
        '-' => &HYPHEN,
        '"' => &QUOTE,
        '“' => &OPEN_QUOTE,
        '”' => &CLOSE_QUOTE,
        '‘' => &OPEN_SINGLE,
        '$' => &DOLLAR,
        '£' => &POUND,
        '€' => &EURO,
        '¢' => &CENT,
        '¥' => &YEN,
        '°' => &DEGREE,
        '<' => &LESS,
        '>' => &GREATER,
        '[' => &LSQUARE,
        ']' => &RSQUARE,
        '{' => &LCURLY,
        '}' => &RCURLY,
        '#' => &NUMBER_SIGN,
        '_' => &UNDERSCORE,
        '~' => &TILDE,
        '^' => &CARET,
        '|' => &BAR,
        '\\' => &BACKSLASH,
        '`' => &GRAVE,
        '–' => &EN_DASH,
        '—' => &EM_DASH,
        '…' => &ELLIPSIS,
        '×' => &TIMES,
        '÷' => &DIVIDE,
        '−' => &MINUS,
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

/// The UEB modifier of a combining diacritical mark, written before the
/// letter it marks (The Rules of UEB, section 4.2).
fn modifier(mark: char) -> Option<[Cell; 2]> {
    Some(match mark {
        '\u{301}' => [cell(&[4, 5]), cell(&[3, 4])],          // acute
        '\u{300}' => [cell(&[4, 5]), cell(&[1, 6])],          // grave
        '\u{302}' => [cell(&[4, 5]), cell(&[1, 4, 6])],       // circumflex
        '\u{308}' => [cell(&[4, 5]), cell(&[2, 5])],          // diaeresis
        '\u{303}' => [cell(&[4, 5]), cell(&[1, 2, 4, 5, 6])], // tilde
        '\u{327}' => [cell(&[4, 5]), cell(&[1, 2, 3, 4, 6])], // cedilla
        '\u{304}' => [cell(&[4]), cell(&[3, 6])],             // macron
        _ => return None,
    })
}

/// Whether `c` is a combining diacritical mark (it belongs to the letter before it).
fn is_mark(c: char) -> bool {
    ('\u{300}'..='\u{36f}').contains(&c)
}

/// Whether `c` is part of a word for the capital indicators: a Latin letter or a mark on one.
fn in_word(c: char) -> bool {
    c.is_ascii_alphabetic() || is_mark(c)
}

/// The characters `missing` (as [`translate`] returns them) for a message:
/// each once, in the order they first appear in the text (sorted, an Arabic
/// or Hebrew word would read backwards, and a CJK one scrambled), in double
/// quotes. Only control characters, quotes and backslashes are escaped, so
/// that a letter and its combining mark (ř) show as the letter, not as
/// `r\u{30c}` as Rust's `{:?}` writes them.
pub fn left_out(missing: &[char]) -> String {
    let mut seen = Vec::new();
    for &c in missing {
        if !seen.contains(&c) {
            seen.push(c);
        }
    }
    let mut out = String::from("\"");
    for c in seen {
        match c {
            '"' | '\\' => out.extend(['\\', c]),
            c if c.is_control() => out.extend(c.escape_default()),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Whether the braille of `text` would say nothing: it has letters or
/// digits and [`translate`] left every one of them out (`missing`), so
/// that only its punctuation and spaces would be written, as for a label in
/// another script, `Осадки (мм)`. Such a text is left out whole.
pub fn says_nothing(text: &str, missing: &[char]) -> bool {
    let letters = text.chars().filter(|c| c.is_alphanumeric()).count();
    letters > 0 && missing.iter().filter(|c| c.is_alphanumeric()).count() >= letters
}

/// What T0304 says helps: what the built-in table covers.
pub const TABLE_HELP: &str = "taxel's built-in table covers Latin letters (with common accents), digits, space, \
                              punctuation and the signs of maps and charts";

/// Translates text to uncontracted UEB cells (a space is an empty cell).
/// Returns the cells and the characters that have no translation (left out;
/// a letter whose marks are not all known is left out with its marks).
pub fn translate(text: &str) -> (Vec<Cell>, Vec<char>) {
    // Latin letters decomposed, so that é written as one character or as e
    // and a combining acute is the same letter and mark (other scripts are
    // left whole, so that their characters are named whole when left out).
    let mut chars: Vec<char> = Vec::with_capacity(text.len());
    for c in text.chars() {
        let start = chars.len();
        chars.extend(c.nfd());
        if !chars.get(start).is_some_and(char::is_ascii_alphabetic) {
            chars.truncate(start);
            chars.push(c);
        }
    }
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
            // The letter's marks, and their modifiers if every one has one.
            let marks = chars[i + 1..].iter().take_while(|&&m| is_mark(m)).count();
            let modifiers: Option<Vec<[Cell; 2]>> = chars[i + 1..i + 1 + marks].iter().map(|&m| modifier(m)).collect();
            let Some(modifiers) = modifiers else {
                numeric = false;
                missing.extend_from_slice(&chars[i..i + 1 + marks]);
                i += 1 + marks;
                continue;
            };
            let lower = c.to_ascii_lowercase();
            if numeric && !c.is_ascii_uppercase() && lower <= 'j' && modifiers.is_empty() {
                out.push(GRADE1);
            }
            numeric = false;
            if c.is_ascii_uppercase() {
                let word_start = i == 0 || !in_word(chars[i - 1]);
                let word: Vec<char> =
                    chars[i..].iter().take_while(|&&c| in_word(c)).filter(|c| !is_mark(**c)).copied().collect();
                let caps_word = word.len() >= 2 && word.iter().all(|c| c.is_ascii_uppercase());
                let in_caps_word = {
                    let start = chars[..i].iter().rposition(|&c| !in_word(c)).map_or(0, |p| p + 1);
                    let w: Vec<char> =
                        chars[start..].iter().take_while(|&&c| in_word(c)).filter(|c| !is_mark(**c)).copied().collect();
                    w.len() >= 2 && w.iter().all(|c| c.is_ascii_uppercase())
                };
                if word_start && caps_word {
                    out.extend([CAPITAL, CAPITAL]);
                } else if !in_caps_word {
                    out.push(CAPITAL);
                }
            }
            out.extend(modifiers.into_iter().flatten());
            out.push(LETTERS[(lower as u8 - b'a') as usize]);
            i += 1 + marks;
            continue;
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
        assert_eq!(translate("ø").1, vec!['ø']);
    }

    #[test]
    fn letters_with_diacritics_take_ueb_modifiers_before_the_letter() {
        // The Rules of UEB 4.2 and the ICEB reference sheet (Braille ASCII
        // `^/` acute, `^*` grave, `^%` circumflex, `^3` diaeresis): the
        // modifier, then the letter; a capital's indicator comes first.
        assert_eq!(translate("Café"), (cells(&["6", "14", "1", "124", "45", "34", "15"]), vec![]));
        // Written as a letter and a combining mark, the same cells.
        assert_eq!(translate("Cafe\u{301}"), translate("Café"));
        assert_eq!(translate("ü").0, cells(&["45", "25", "136"]));
        assert_eq!(translate("à").0, cells(&["45", "16", "1"]));
        assert_eq!(translate("ô").0, cells(&["45", "146", "135"]));
        assert_eq!(translate("ñ").0, cells(&["45", "12456", "1345"]));
        assert_eq!(translate("ç").0, cells(&["45", "12346", "14"]));
        // An all-capital word with an accented letter is still one capitalised word.
        assert_eq!(translate("ÉTÉ").0, cells(&["6", "6", "45", "34", "15", "2345", "45", "34", "15"]));
        // After a number the modifier ends numeric mode: no grade 1 indicator.
        assert_eq!(translate("1é").0, cells(&["3456", "1", "45", "34", "15"]));
        // A mark without a modifier here (the caron of ř) leaves its letter out, named whole.
        let (c, missing) = translate("Dvořák");
        assert_eq!(left_out(&missing), "\"r\u{30c}\"");
        assert_eq!(left_out(&['"', '\n', '京']), r#""\"\n京""#);
        assert_eq!(c, cells(&["6", "145", "1236", "135", "45", "34", "1", "13"]));
        // Letters of other scripts are not decomposed: named as written.
        assert_eq!(translate("й").1, vec!['й']);
    }

    #[test]
    fn signs_of_maps_and_charts_follow_the_ueb_reference_list() {
        // Braille ASCII of the ICEB sheet: `^j` degree, `@s` dollar, `@l`
        // pound, `.<` `.>` square brackets, `,-` dash, `444` ellipsis.
        assert_eq!(translate("45°").0, cells(&["3456", "145", "15", "45", "245"]));
        assert_eq!(translate("$5").0, cells(&["4", "234", "3456", "15"]));
        assert_eq!(translate("£").0, cells(&["4", "123"]));
        assert_eq!(translate("[a]").0, cells(&["46", "126", "1", "46", "345"]));
        assert_eq!(translate("–").0, cells(&["6", "36"]));
        assert_eq!(translate("…").0, cells(&["256", "256", "256"]));
        assert_eq!(translate("“a”").0, cells(&["236", "1", "356"]));
        for c in "#<>{}_~^|\\`—×÷−€¢¥‘".chars() {
            assert!(translate(&c.to_string()).1.is_empty(), "{c}");
        }
    }
}
