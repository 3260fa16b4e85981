//! Key codes: two letters that stand for a label whose braille finds no
//! place, and the key that explains them (T0326).

use std::collections::BTreeMap;

use super::{Decision, Measure};
use crate::drawing::{Drawing, Shape, TextRun, TextShape};

/// A key code: two lowercase Latin letters that stand for a label whose
/// braille finds no place (BANA's Guidelines and Standards for Tactile
/// Graphics, 2010: a label that does not fit is replaced by a short
/// abbreviation explained in a key).
pub type KeyCode = [u8; 2];

/// The key codes of a drawing: each label text that needs one has one
/// (the same text, the same code), no two texts share one, and no code is
/// the text of a label written whole.
pub(super) struct Keys {
    /// Codes taken, and by which label (empty for a label written whole).
    taken: BTreeMap<KeyCode, String>,
    /// Each keyed label's code.
    of_label: BTreeMap<String, KeyCode>,
}

impl Keys {
    pub(super) fn new(d: &Drawing, decisions: &[Decision]) -> Keys {
        let mut taken = BTreeMap::new();
        for (e, dec) in d.elements.iter().zip(decisions) {
            let Shape::Text(t) = &e.shape else { continue };
            if let (true, [a, b]) = (dec.braille, t.content.trim().to_lowercase().as_bytes()) {
                taken.insert([*a, *b], String::new());
            }
        }
        Keys { taken, of_label: BTreeMap::new() }
    }

    /// The code for a label, and the run that writes it where the label's
    /// first line starts; `None` for a label shorter than [`MIN_KEYED_CELLS`], or one
    /// with fewer than two Latin letters (a code must say something of what
    /// it stands for: "R108" gets none).
    pub(super) fn code_for(&self, t: &TextShape, m: Measure<'_>) -> Option<(KeyCode, TextRun)> {
        let text = label_text(t);
        let first = t.runs.iter().find(|r| !r.text.trim().is_empty())?;
        let words: Vec<Vec<u8>> = text
            .split(|c: char| !c.is_alphanumeric())
            .map(|w| w.chars().filter_map(latin_letter).collect::<Vec<u8>>())
            .filter(|w| !w.is_empty())
            .collect();
        let letters: Vec<u8> = words.concat();
        let &initial = letters.first()?;
        // Letters first: translating a label to count its cells is the
        // dear part (liblouis, on a map's 45,000 region numbers), and a
        // label of fewer than two letters gets no code whatever its length.
        if letters.len() < 2 || text.chars().filter(|c| !c.is_whitespace()).count() < MIN_KEYED_CELLS {
            return None;
        }
        if m.cells(Some(t), &text) < MIN_KEYED_CELLS {
            return None;
        }
        let code = match self.of_label.get(&text) {
            Some(code) => *code,
            None => {
                // The first letters of its first two words, then its first
                // letter with each later one, then with any letter, then
                // any free pair.
                let initials = words.get(1).and_then(|w| w.first()).map(|&b| [initial, b]);
                let with_first = letters.iter().skip(1).map(|&b| [initial, b]);
                let first_any = (b'a'..=b'z').map(|b| [initial, b]);
                let any = (b'a'..=b'z').flat_map(|a| (b'a'..=b'z').map(move |b| [a, b]));
                initials
                    .into_iter()
                    .chain(with_first)
                    .chain(first_any)
                    .chain(any)
                    .find(|c| !self.taken.contains_key(c))?
            }
        };
        let run = TextRun { text: String::from_utf8_lossy(&code).into_owned(), continues: false, ..first.clone() };
        Some((code, run))
    }

    pub(super) fn take(&mut self, t: &TextShape, code: KeyCode) {
        let text = label_text(t);
        self.of_label.insert(text.clone(), code);
        self.taken.insert(code, text);
    }
}

/// The key of a drawing's key codes (T0326) as one line of print, codes in
/// order: `"key: bs Bundle Store, kf 1 kHz frames"`; empty when it has none.
pub fn key_line(d: &Drawing) -> String {
    let mut key: BTreeMap<&str, &str> = BTreeMap::new();
    for e in &d.elements {
        if let Shape::Text(TextShape { content, keyed: Some(label), .. }) = &e.shape {
            key.insert(content, label);
        }
    }
    if key.is_empty() {
        return String::new();
    }
    let entries: Vec<String> = key.iter().map(|(code, label)| format!("{code} {label}")).collect();
    format!("key: {}", entries.join(", "))
}

/// A label's words, its runs joined by spaces (the lines of a label).
pub fn label_text(t: &TextShape) -> String {
    let words: Vec<&str> = t.runs.iter().flat_map(|r| r.text.split_whitespace()).collect();
    words.join(" ")
}

/// A letter as a key code's letter: Latin, lowercase, without its accents.
fn latin_letter(c: char) -> Option<u8> {
    use unicode_normalization::UnicodeNormalization;
    let base = c.nfd().next()?.to_ascii_lowercase();
    base.is_ascii_lowercase().then_some(base as u8)
}

/// The fewest characters and braille cells a label takes to be worth a key
/// code (two cells): one of two characters ("No", "Nr") is written whole or not at all.
const MIN_KEYED_CELLS: usize = 3;

/// How many of a drawing's key codes note T0326 shows.
pub(super) const KEY_SHOWN: usize = 8;
