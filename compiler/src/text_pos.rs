//! Byte offsets to 1-based line and column numbers, and the mapping from an
//! offset inside a decoded XML attribute value back to the source text.

/// The 1-based line and column (counted in characters) of byte `offset` in `text`.
pub(crate) fn line_col(text: &str, offset: usize) -> (u32, u32) {
    LineIndex::new(text).line_col(text, offset)
}

/// The byte offsets where the lines of one text start, built once so that
/// each position costs a binary search, not a scan from the start of the file
/// (a drawing with thousands of elements asks for thousands of positions).
#[derive(Debug, Clone)]
pub(crate) struct LineIndex {
    starts: Vec<usize>,
}

impl LineIndex {
    /// Indexes the line starts of `text`.
    pub(crate) fn new(text: &str) -> Self {
        let starts =
            std::iter::once(0).chain(text.bytes().enumerate().filter(|&(_, b)| b == b'\n').map(|(i, _)| i + 1));
        LineIndex { starts: starts.collect() }
    }

    /// The 1-based line of byte `offset`: a binary search. The column costs a
    /// count of the characters before it on its line, which, asked for every
    /// element of a drawing written on one line (Vega's, 2 MB), was most of
    /// the time to read it; [`Self::line_col`] only when a column is wanted.
    pub(crate) fn line(&self, offset: usize) -> u32 {
        self.starts.partition_point(|&s| s <= offset).max(1) as u32
    }

    /// The 1-based line and column (counted in characters) of byte `offset` in
    /// `text`, the text this index was built from.
    pub(crate) fn line_col(&self, text: &str, offset: usize) -> (u32, u32) {
        let mut offset = offset.min(text.len());
        while !text.is_char_boundary(offset) {
            offset -= 1;
        }
        // The last line start at or before `offset` (there is always line 1 at 0).
        let line = self.line(offset) as usize;
        let start = self.starts[line - 1].min(offset);
        let col = text.get(start..offset).map_or(0, |s| s.chars().count()) + 1;
        (line as u32, col as u32)
    }
}

/// Maps a byte offset in the decoded value of an XML attribute to a byte
/// offset in its raw source text `raw` (the text between the quotes): entity
/// and character references decode to one character, and `\r\n` to one space.
#[allow(dead_code)] // Used by the SVG front end.
pub(crate) fn raw_offset(raw: &str, decoded_offset: usize) -> usize {
    let mut decoded = 0usize;
    let mut i = 0usize;
    let b = raw.as_bytes();
    while i < raw.len() && decoded < decoded_offset {
        if b[i] == b'&'
            && let Some(end) = raw[i..].find(';')
        {
            let ent = &raw[i + 1..i + end];
            decoded += decoded_len(ent);
            i += end + 1;
            continue;
        }
        if b[i] == b'\r' && b.get(i + 1) == Some(&b'\n') {
            decoded += 1;
            i += 2;
            continue;
        }
        let c = raw[i..].chars().next().map_or(1, char::len_utf8);
        decoded += c;
        i += c;
    }
    i
}

/// Length in bytes of what an entity or character reference decodes to.
#[allow(dead_code)]
fn decoded_len(entity: &str) -> usize {
    let num = if let Some(h) = entity.strip_prefix("#x").or_else(|| entity.strip_prefix("#X")) {
        u32::from_str_radix(h, 16).ok()
    } else if let Some(d) = entity.strip_prefix('#') {
        d.parse().ok()
    } else {
        None
    };
    num.and_then(char::from_u32).map_or(1, char::len_utf8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_and_columns_are_one_based_and_count_characters() {
        let t = "ab\ncé d";
        assert_eq!(line_col(t, 0), (1, 1));
        assert_eq!(line_col(t, 3), (2, 1));
        assert_eq!(line_col(t, t.find('d').unwrap()), (2, 4));
    }

    #[test]
    fn the_line_index_agrees_with_a_scan_from_the_start() {
        // The scan the index replaces, as the reference.
        let scan = |text: &str, offset: usize| {
            let mut offset = offset.min(text.len());
            while !text.is_char_boundary(offset) {
                offset -= 1;
            }
            let before = &text[..offset];
            let line = before.bytes().filter(|&b| b == b'\n').count() + 1;
            let start = before.rfind('\n').map_or(0, |i| i + 1);
            (line as u32, before[start..].chars().count() as u32 + 1)
        };
        for t in ["", "\n", "a\n\nb", "ab\ncé d\r\nレイヤー 1\n", "x\n\n\nyé"] {
            let index = LineIndex::new(t);
            for o in 0..=t.len() + 2 {
                assert_eq!(index.line_col(t, o), scan(t, o), "{t:?} at {o}");
                if t.is_char_boundary(o.min(t.len())) {
                    assert_eq!(index.line(o), scan(t, o).0, "{t:?} at {o}");
                }
            }
        }
    }

    #[test]
    fn raw_offsets_skip_entities() {
        let raw = "a&amp;b&#x2014;c";
        // decoded: "a&b—c": 'c' is at decoded byte 1 + 1 + 1 + 3 = 6.
        assert_eq!(&raw[raw_offset(raw, 6)..], "c");
        assert_eq!(raw_offset(raw, 0), 0);
    }
}
