//! A readable account of one compilation, for `taxel build` and `taxel
//! check`: diagnostics of one rule are grouped into one line with their count
//! and the first three elements, then the rule's help, so that a real map's
//! build fits on one screen. `-v` lists every instance; `--format json`
//! always keeps them all.

use taxel_compiler::{Diagnostic, Severity};

/// The code of the note that says how many elements became which style; it
/// goes on the input's summary line rather than among the diagnostics.
pub const STYLE_SUMMARY: &str = "T0330";

/// How many elements a group names before "and N more".
const NAMED: usize = 3;

/// Longest list of a group's different messages written out; a longer one
/// gives the first message, said to be the first.
const LISTED_CHARS: usize = 160;

/// Where an instance is, `#id (line N)`, written into `out` (cleared
/// first); `false` when it has no place.
fn write_place(d: &Diagnostic, out: &mut String) -> bool {
    use std::fmt::Write;
    out.clear();
    let _ = match (&d.element, d.line) {
        (Some(e), Some(l)) => write!(out, "#{e} (line {l})"),
        (Some(e), None) => write!(out, "#{e}"),
        (None, Some(l)) => write!(out, "line {l}"),
        (None, None) => return false,
    };
    true
}

/// The lines to print for `diags` of the input shown as `file`: those at or
/// above `min`, the style summary left out. Without `verbose`, a code that
/// occurs more than once is one line (its count, the first instance's
/// message, the first three places) and its help; with `verbose`, every
/// instance as [`Diagnostic::render`] prints it. Errors come first, then
/// warnings, then notes, each in order of first appearance.
pub fn lines(diags: &[Diagnostic], file: &str, min: Severity, verbose: bool) -> Vec<String> {
    if !verbose {
        return groups(diags, file, min).into_iter().flat_map(|g| g.lines).collect();
    }
    let shown = diags.iter().filter(|d| d.severity >= min && d.code != STYLE_SUMMARY);
    let mut out = Vec::new();
    for severity in [Severity::Error, Severity::Warning, Severity::Note] {
        let of = shown.clone().filter(|d| d.severity == severity);
        out.extend(of.flat_map(|d| d.render(file).lines().map(str::to_string).collect::<Vec<_>>()));
    }
    out
}

/// The diagnostics of one code and severity, as the account groups them.
#[derive(Debug)]
pub struct Group<'a> {
    /// How bad they are.
    pub severity: Severity,
    /// Their code.
    pub code: &'static str,
    /// Every instance, in order.
    pub members: Vec<&'a Diagnostic>,
    /// The lines [`lines`] prints for the group (without `verbose`).
    pub lines: Vec<String>,
}

/// The account's groups of `diags` of the input shown as `file`, in the
/// order [`lines`] prints them: those at or above `min`, the style summary
/// left out; errors first, then warnings, then notes, each in order of first
/// appearance. The studio shows the same groups as the command line.
pub fn groups<'a>(diags: &'a [Diagnostic], file: &str, min: Severity) -> Vec<Group<'a>> {
    let shown: Vec<&Diagnostic> = diags.iter().filter(|d| d.severity >= min && d.code != STYLE_SUMMARY).collect();
    let mut out = Vec::new();
    for severity in [Severity::Error, Severity::Warning, Severity::Note] {
        let of: Vec<&Diagnostic> = shown.iter().copied().filter(|d| d.severity == severity).collect();
        let mut codes: Vec<&'static str> = Vec::new();
        for d in &of {
            if !codes.contains(&d.code) {
                codes.push(d.code);
            }
        }
        for code in codes {
            let members: Vec<&Diagnostic> = of.iter().copied().filter(|d| d.code == code).collect();
            let lines = group_lines(&members, file, severity, code);
            out.push(Group { severity, code, members, lines });
        }
    }
    out
}

/// The lines of one group: a single instance as [`Diagnostic::render`]
/// prints it; several as one line (count, message, first places) and the help.
fn group_lines(group: &[&Diagnostic], file: &str, severity: Severity, code: &str) -> Vec<String> {
    let first = group[0];
    if group.len() == 1 {
        return first.render(file).lines().map(str::to_string).collect();
    }
    // Only the named places are written out: a dense map has hundreds of
    // thousands. An element met twice (its band and its fill) is named once.
    // Each place is written into one buffer, not a string of its own.
    let mut places: Vec<String> = Vec::new();
    let mut more = 0;
    let mut p = String::new();
    for d in group {
        if !write_place(d, &mut p) || places.contains(&p) {
            continue;
        }
        if places.len() < NAMED {
            places.push(p.clone());
        } else {
            more += 1;
        }
    }
    let mut at = places.join(", ");
    if more > 0 {
        at += &format!(" and {more} more");
    }
    let (text, first_of) = group_message(group);
    let at = match (first_of, at.is_empty()) {
        (Some(f), false) => format!(" ({f}; at {at})"),
        (Some(f), true) => format!(" ({f})"),
        (None, false) => format!(" (at {at})"),
        (None, true) => String::new(),
    };
    let mut out = vec![format!("{file}: {severity}[{code}] x{}: {text}{at}; -v lists each", group.len())];
    if let Some(h) = &first.help {
        out.push(format!("  help: {h}"));
    }
    out
}

/// What one line says for a group of one code: its message when every
/// instance says the same; each message with its count when they say up to
/// [`NAMED`] different things (`grating` and `vibrate` not rendered); else
/// the first, said to be the first, so a line never names one style, size or
/// distance for a group that holds several.
fn group_message(group: &[&Diagnostic]) -> (String, Option<String>) {
    let mut kinds: Vec<(&str, usize)> = Vec::new();
    for d in group {
        match kinds.iter().position(|(m, _)| *m == d.message) {
            Some(k) => kinds[k].1 += 1,
            None => kinds.push((&d.message, 1)),
        }
        if kinds.len() > NAMED {
            break;
        }
    }
    let listed = kinds.iter().map(|(m, c)| format!("{m} (x{c})")).collect::<Vec<_>>().join(" | ");
    match kinds.len() {
        1 => (kinds[0].0.to_string(), None),
        // Listed when the list stays a readable line (messages naming long element paths do not).
        n if n <= NAMED && listed.len() <= LISTED_CHARS => (listed, None),
        _ => {
            // A fast hasher: SipHash over the half a million messages of the
            // map at the input limit was a tenth of a second on one thread.
            let distinct: std::collections::HashSet<&str, foldhash::fast::RandomState> =
                group.iter().map(|d| d.message.as_str()).collect();
            (group[0].message.clone(), Some(format!("the first of {} different messages", distinct.len())))
        }
    }
}

/// The style summary note's message (how many elements became which style), if any.
pub fn style_summary(diags: &[Diagnostic]) -> Option<&str> {
    diags.iter().find(|d| d.code == STYLE_SUMMARY).map(|d| d.message.as_str())
}

/// The notes of a folder's inputs, counted once for the whole build: the
/// notes a thousand drawings all get (T0201 "no physical size", T0320 "the
/// automatic style sheet decided") were three lines per input, most of a
/// folder's account. Warnings and errors stay with their input; a note given
/// to one input only is printed as that input's account would have.
#[derive(Debug, Default)]
pub struct NoteTally {
    codes: Vec<Tallied>,
}

/// One note code across the inputs.
#[derive(Debug)]
struct Tallied {
    code: &'static str,
    /// Inputs that had it.
    files: usize,
    /// The position in the batch of the first input that had it (inputs
    /// finish in any order on several threads; the account must not).
    first_at: usize,
    /// The first input's name and its lines for this code.
    first_file: String,
    first_lines: Vec<String>,
    /// The first instance's message and help.
    message: String,
    help: Option<String>,
    /// Whether every instance so far says `message`.
    same: bool,
}

impl NoteTally {
    /// Counts the notes among `diags` of the input shown as `file`, the
    /// input at position `at` of the batch (the style summary left out: it
    /// goes on the input's own line). The account names, for each code, the
    /// input of lowest position that had it, whichever finished first.
    pub fn add(&mut self, diags: &[Diagnostic], file: &str, at: usize) {
        let notes: Vec<&Diagnostic> =
            diags.iter().filter(|d| d.severity == Severity::Note && d.code != STYLE_SUMMARY).collect();
        let mut seen: Vec<&str> = Vec::new();
        for d in &notes {
            if seen.contains(&d.code) {
                let t = self.codes.iter_mut().find(|t| t.code == d.code);
                if let Some(t) = t {
                    t.same &= t.message == d.message;
                }
                continue;
            }
            seen.push(d.code);
            let first = || {
                let of: Vec<Diagnostic> = notes.iter().filter(|n| n.code == d.code).map(|&n| n.clone()).collect();
                Tallied {
                    code: d.code,
                    files: 1,
                    first_at: at,
                    first_file: file.to_string(),
                    first_lines: lines(&of, file, Severity::Note, false),
                    message: d.message.clone(),
                    help: d.help.clone(),
                    same: true,
                }
            };
            match self.codes.iter_mut().find(|t| t.code == d.code) {
                None => self.codes.push(first()),
                Some(t) => {
                    // Whether every instance says one message does not
                    // depend on which is compared with which.
                    let same = t.same && t.message == d.message;
                    let files = t.files + 1;
                    if at < t.first_at {
                        *t = first();
                    }
                    t.same = same;
                    t.files = files;
                }
            }
        }
        self.codes.sort_by_key(|t| t.first_at);
    }

    /// The account's lines: each code given to more than one input as one
    /// line with the number of inputs and its help, in the order of the
    /// inputs that first had them; a code of one input as that input's lines.
    pub fn lines(&self) -> Vec<String> {
        let mut out = Vec::new();
        for t in &self.codes {
            if t.files == 1 {
                out.extend(t.first_lines.iter().cloned());
                continue;
            }
            let what = if t.same { String::new() } else { format!(", the first ({})", t.first_file) };
            out.push(format!("note[{}] in {} files{what}: {}", t.code, t.files, t.message));
            if let Some(h) = &t.help {
                out.push(format!("  help: {h}"));
            }
        }
        if self.codes.iter().any(|t| t.files > 1) {
            out.push("notes given to several inputs are counted above, once each; -v gives every input's".to_string());
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gap(e: &str, line: u32) -> Diagnostic {
        Diagnostic::warning("T0408", format!("this element is 1.0 mm from #{e}x, closer than 3.2 mm"))
            .with_help("leave at least 3.2 mm")
            .with_element(e)
            .at(line, 3)
    }

    #[test]
    fn one_rule_many_times_is_one_line_with_count_three_places_and_help() {
        let mut diags: Vec<Diagnostic> = (1..=42).map(|k| gap(&format!("r{k}"), 10 + k)).collect();
        diags.push(Diagnostic::error("T0401", "adjacent gratings").with_element("g").at(5, 1));
        diags.push(Diagnostic::note(STYLE_SUMMARY, "44 element(s): 44 grating"));
        diags.push(Diagnostic::note("T0320", "no annotation: the automatic style sheet was used"));
        let out = lines(&diags, "map.svg", Severity::Note, false);
        assert_eq!(
            out,
            [
                "map.svg:5:1: error[T0401]: adjacent gratings (element #g)",
                "map.svg: warning[T0408] x42: this element is 1.0 mm from #r1x, closer than 3.2 mm (the first of 42 different messages; at #r1 (line 11), #r2 (line 12), #r3 (line 13) and 39 more); -v lists each",
                "  help: leave at least 3.2 mm",
                "map.svg: note[T0320]: no annotation: the automatic style sheet was used",
            ]
        );
        assert_eq!(lines(&diags, "map.svg", Severity::Warning, false).len(), 3);
        // -v: every instance, each with its help line.
        assert_eq!(lines(&diags, "map.svg", Severity::Warning, true).len(), 1 + 42 * 2);
        assert_eq!(style_summary(&diags), Some("44 element(s): 44 grating"));
    }

    /// Regression (real corpora): a group's line gave the first instance's
    /// message, so three T0120 about `grating`, `grating` and `vibrate` read
    /// "x3: `grating` is not rendered", and a group of gaps named one distance.
    #[test]
    fn a_group_of_different_messages_never_reads_as_one() {
        let not = |s: &str, e: &str| {
            Diagnostic::warning("T0120", format!("`{s}` is not rendered on brush-4x3; it is left out")).with_element(e)
        };
        let diags = [not("grating", "a"), not("grating", "b"), not("vibrate", "c")];
        let out = lines(&diags, "f.svg", Severity::Note, false);
        assert_eq!(out.len(), 1, "{out:?}");
        for (style, n) in [("grating", 2), ("vibrate", 1)] {
            assert!(
                out[0].contains(&format!("`{style}` is not rendered on brush-4x3; it is left out (x{n})")),
                "{out:?}"
            );
        }
        // Two long messages that would make an unreadable line: the first, said to be the first.
        let long = |k: usize| Diagnostic::warning("T0410", format!("this layer overlaps #{}{k}", "g[1]/".repeat(20)));
        let out = lines(&[long(1), long(2)], "f.svg", Severity::Note, false);
        assert!(out[0].contains("(the first of 2 different messages)") && out[0].len() < 200, "{out:?}");
        // Many different messages: the first, said to be the first of so many.
        let diags: Vec<Diagnostic> = (1..=42).map(|k| gap(&format!("r{k}"), 10 + k)).collect();
        let mut diags: Vec<Diagnostic> = diags
            .into_iter()
            .enumerate()
            .map(|(k, d)| Diagnostic { message: format!("this element is {k}.0 mm from #x, closer than 3.2 mm"), ..d })
            .collect();
        // The same element and line twice is named once.
        diags.insert(1, diags[0].clone());
        let out = lines(&diags, "f.svg", Severity::Note, false);
        assert!(out[0].contains("x43: this element is 0.0 mm from #x, closer than 3.2 mm (the first of 42 different messages; at #r1 (line 11), #r2 (line 12), #r3 (line 13) and 39 more)"), "{out:?}");
    }

    /// Issue 14: a folder of 1,802 drawings printed three lines of notes per
    /// drawing (T0201, T0320 and its help), most of the account.
    #[test]
    fn a_folders_repeated_notes_are_one_line_each_and_a_single_ones_stay_whole() {
        let sized = |mm: u32| {
            Diagnostic::note("T0201", format!("the drawing has no physical size; fitted at {mm} x 60.0 mm"))
                .with_help("give the root <svg> a width and height in mm")
        };
        let auto = || Diagnostic::note("T0320", "the automatic style sheet decided").with_help("`taxel style auto`");
        let odd = Diagnostic::note("T0324", "borders left out").with_element("r1").at(4, 2).with_help("use --region");
        let files = 40;
        let input = |k: u32| {
            let mut diags = vec![sized(50 + k), auto(), auto(), Diagnostic::note(STYLE_SUMMARY, "3 element(s)")];
            if k == 7 {
                diags.push(odd.clone());
            }
            diags
        };
        let mut tally = NoteTally::default();
        for k in 0..files {
            tally.add(&input(k), &format!("d{k}.svg"), k as usize);
        }
        let out = tally.lines();
        // Inputs finish in any order on several threads; the account is the same.
        let mut backwards = NoteTally::default();
        for k in (0..files).rev() {
            backwards.add(&input(k), &format!("d{k}.svg"), k as usize);
        }
        assert_eq!(backwards.lines(), out);
        let per_file: usize =
            (0..files).map(|k| lines(&[sized(50 + k), auto()], "x", Severity::Note, false).len()).sum();
        assert!(out.len() * 10 < per_file, "{out:#?}");
        // Different messages say which input the one shown is from; the same
        // message twice in one input counts that input once.
        assert_eq!(
            out[0],
            format!(
                "note[T0201] in {files} files, the first (d0.svg): the drawing has no physical size; fitted at 50 x 60.0 mm"
            )
        );
        assert_eq!(out[1], "  help: give the root <svg> a width and height in mm");
        assert_eq!(out[2], format!("note[T0320] in {files} files: the automatic style sheet decided"));
        // A note of one input is that input's line, as its own account gives it.
        assert_eq!(out[4..6], lines(&[odd], "d7.svg", Severity::Note, false)[..]);
        assert!(!out.iter().any(|l| l.contains(STYLE_SUMMARY)), "{out:#?}");
    }
}
