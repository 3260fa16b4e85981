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

/// Where an instance is: `#id (line N)`.
fn place(d: &Diagnostic) -> Option<String> {
    match (&d.element, d.line) {
        (Some(e), Some(l)) => Some(format!("#{e} (line {l})")),
        (Some(e), None) => Some(format!("#{e}")),
        (None, Some(l)) => Some(format!("line {l}")),
        (None, None) => None,
    }
}

/// The lines to print for `diags` of the input shown as `file`: those at or
/// above `min`, the style summary left out. Without `verbose`, a code that
/// occurs more than once is one line (its count, the first instance's
/// message, the first three places) and its help; with `verbose`, every
/// instance as [`Diagnostic::render`] prints it. Errors come first, then
/// warnings, then notes, each in order of first appearance.
pub fn lines(diags: &[Diagnostic], file: &str, min: Severity, verbose: bool) -> Vec<String> {
    let shown: Vec<&Diagnostic> = diags.iter().filter(|d| d.severity >= min && d.code != STYLE_SUMMARY).collect();
    let mut out = Vec::new();
    for severity in [Severity::Error, Severity::Warning, Severity::Note] {
        let of: Vec<&Diagnostic> = shown.iter().copied().filter(|d| d.severity == severity).collect();
        if verbose {
            out.extend(of.iter().flat_map(|d| d.render(file).lines().map(str::to_string).collect::<Vec<_>>()));
            continue;
        }
        let mut codes: Vec<&str> = Vec::new();
        for d in &of {
            if !codes.contains(&d.code) {
                codes.push(d.code);
            }
        }
        for code in codes {
            let group: Vec<&Diagnostic> = of.iter().copied().filter(|d| d.code == code).collect();
            let first = group[0];
            if group.len() == 1 {
                out.extend(first.render(file).lines().map(str::to_string));
                continue;
            }
            // Only the named places are written out: a dense map has hundreds of thousands.
            let placed = group.iter().filter(|d| d.element.is_some() || d.line.is_some()).count();
            let mut at = group.iter().filter_map(|d| place(d)).take(NAMED).collect::<Vec<_>>().join(", ");
            if placed > NAMED {
                at += &format!(" and {} more", placed - NAMED);
            }
            let at = if at.is_empty() { String::new() } else { format!(" (at {at})") };
            out.push(format!("{file}: {severity}[{code}] x{}: {}{at}; -v lists each", group.len(), first.message));
            if let Some(h) = &first.help {
                out.push(format!("  help: {h}"));
            }
        }
    }
    out
}

/// The style summary note's message (how many elements became which style), if any.
pub fn style_summary(diags: &[Diagnostic]) -> Option<&str> {
    diags.iter().find(|d| d.code == STYLE_SUMMARY).map(|d| d.message.as_str())
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
                "map.svg: warning[T0408] x42: this element is 1.0 mm from #r1x, closer than 3.2 mm (at #r1 (line 11), #r2 (line 12), #r3 (line 13) and 39 more); -v lists each",
                "  help: leave at least 3.2 mm",
                "map.svg: note[T0320]: no annotation: the automatic style sheet was used",
            ]
        );
        assert_eq!(lines(&diags, "map.svg", Severity::Warning, false).len(), 3);
        // -v: every instance, each with its help line.
        assert_eq!(lines(&diags, "map.svg", Severity::Warning, true).len(), 1 + 42 * 2);
        assert_eq!(style_summary(&diags), Some("44 element(s): 44 grating"));
    }
}
