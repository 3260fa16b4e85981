#!/usr/bin/env python3
# SPDX-License-Identifier: MIT OR Apache-2.0
"""Extensions > Tactile > Check: runs `taxel check --format json` on the
document as it is now and shows its diagnostics grouped as the command line
groups them (one numbered group per code, errors first), then marks the
elements of the group the teacher picks (the first by default).

Inkscape does not let an extension change the selection on the canvas
(it restores the selection it had by id after every effect), so the
elements are marked on a locked layer of their own, "taxel check", with a
frame around each, and named in the message (Edit > Find selects by id).
The extension's selection is set too, for hosts that honour it. Running
Check again replaces the layer; a check with nothing to mark removes it.
"""

import json
import re
import sys

sys.dont_write_bytecode = True  # leave no __pycache__ beside the installed extension

import inkex  # noqa: E402

import taxel_ink as tk  # noqa: E402

# The style summary note: on the summary line, not among the diagnostics (src/account.rs).
STYLE_SUMMARY = "T0330"
# How many places a group names before "and N more", as the command line.
NAMED = 3
# Longest list of a group's different messages written out, as the command line.
LISTED_CHARS = 160
SEVERITIES = ("error", "warning", "note")


def group(diagnostics):
    """The diagnostics grouped as `taxel check` prints them without -v: one
    group per code, errors first, then warnings, then notes, each in order
    of first appearance. Returns a list of lists of diagnostics."""
    shown = [d for d in diagnostics if d.get("code") != STYLE_SUMMARY]
    groups = []
    for severity in SEVERITIES:
        codes = []
        for d in shown:
            if d.get("severity") == severity and d.get("code") not in codes:
                codes.append(d.get("code"))
        for code in codes:
            groups.append([d for d in shown if d.get("severity") == severity and d.get("code") == code])
    return groups


def place(d):
    """Which element one diagnostic is about: `#id`. Line numbers are left
    out: they count lines of the copy taxel read, not of anything the
    teacher sees."""
    element = d.get("element")
    return f"#{element}" if element else ""


def describe_group(number, diags):
    """One group as lines: `3. warning[T0302] x4: message (at #a, #b, #c and 1 more)` and its help."""
    first = diags[0]
    head = f"{number}. {first['severity']}[{first['code']}]"
    places = []
    for d in diags:
        p = place(d)
        if p and p not in places:
            places.append(p)
    at = ", ".join(places[:NAMED]) + (f" and {len(places) - NAMED} more" if len(places) > NAMED else "")
    counts = {}
    for d in diags:
        counts[d["message"]] = counts.get(d["message"], 0) + 1
    listed = " | ".join(f"{m} (x{c})" for m, c in counts.items())
    if len(diags) > 1:
        head += f" x{len(diags)}"
    if len(counts) == 1:
        text = first["message"]
    elif len(counts) <= NAMED and len(listed) <= LISTED_CHARS:
        text = listed
    else:
        text = f"{first['message']} (the first of {len(counts)} different messages)"
    lines = [f"{head}: {text}" + (f" (at {at})" if at else "")]
    if first.get("help"):
        lines.append(f"   help: {first['help']}")
    return lines


_STEP = re.compile(r"^([A-Za-z_][\w.-]*)\[(\d+)\]$")


def resolve(svg, name):
    """The element a diagnostic names: its id, or a path such as
    `svg/g[2]/path[1]` or `layer1/path[3]` (the parent's name, then the
    element's tag and its rank, from 1, among its siblings of that tag),
    as the compiler names elements without an id. None when nothing
    matches."""
    if not name:
        return None
    found = svg.getElementById(name)
    if found is not None:
        return found
    parts = name.split("/")
    # The head is an id (which may itself hold `/`) or the root's tag.
    for cut in range(len(parts) - 1, 0, -1):
        head, steps = "/".join(parts[:cut]), parts[cut:]
        if not all(_STEP.match(s) for s in steps):
            continue
        node = svg if head == "svg" else svg.getElementById(head)
        for step in steps if node is not None else []:
            tag, nth = _STEP.match(step).groups()
            same = [c for c in node if isinstance(c.tag, str) and c.TAG == tag]
            node = same[int(nth) - 1] if 1 <= int(nth) <= len(same) else None
            if node is None:
                break
        if node is not None:
            return node
    return None


class Check(inkex.EffectExtension):
    """Extensions > Tactile > Check."""

    def add_arguments(self, pars):
        tk.add_compile_args(pars)
        pars.add_argument("--group", type=int, default=1)

    def effect(self):
        exe = tk.find_taxel(self.options.taxel)
        with tk.temp_folder() as folder:
            path = tk.write_document(self.document, folder, drop_own=False)
            code, out, err = tk.run_taxel(exe, ["check", path, "--format", "json"] + tk.compile_args(self.options))
        try:
            reports = json.loads(out)
        except ValueError:
            raise inkex.AbortExtension(f"taxel check failed (exit {code}):\n{err.strip() or out.strip()}")
        diagnostics = [d for r in reports for d in r.get("diagnostics", [])]
        errors = sum(r.get("errors", 0) for r in reports)
        warnings = sum(r.get("warnings", 0) for r in reports)
        groups = group(diagnostics)
        lines = [f"taxel check: {'failed' if errors else 'ok'}, {errors} error(s), {warnings} warning(s)"]
        summary = next((d["message"] for d in diagnostics if d.get("code") == STYLE_SUMMARY), None)
        if summary:
            lines.append(summary)
        lines.append("")
        for n, g in enumerate(groups, 1):
            lines += describe_group(n, g)
        picked = self.options.group
        marked = []
        if groups:
            if not 1 <= picked <= len(groups):
                lines.append(f"\nThere is no diagnostic {picked}: showing 1 (there are {len(groups)}).")
                picked = 1
            marked = self.mark(groups[picked - 1])
            if marked:
                names = ", ".join(tk.element_name(e) for e in marked[:10])
                more = f" and {len(marked) - 10} more" if len(marked) > 10 else ""
                lines.append(
                    f"\nDiagnostic {picked} is about {names}{more}: framed in red on the layer "
                    "\"taxel check\" (Edit > Find selects an element by its id). Pick another "
                    "with \"Frame the elements of diagnostic number\"."
                )
            else:
                lines.append(f"\nDiagnostic {picked} names no element of the drawing.")
        if not marked:
            for old in tk.own_layers(self.svg, "check"):
                old.getparent().remove(old)
        self.msg("\n".join(lines).rstrip())

    def mark(self, diags):
        """Frames the elements of one group on the "taxel check" layer and
        selects them (in the extension); returns them."""
        elements = []
        for d in diags:
            elem = resolve(self.svg, d.get("element"))
            if elem is not None and elem not in elements and elem is not self.svg:
                elements.append(elem)
        if not elements:
            return []
        layer = tk.replace_own_layer(self.svg, "check", "taxel check")
        x, y, w, h = tk.document_box(self.svg)
        stroke = max(w, h) / 300.0
        for elem in elements:
            box = self.box(elem)
            if box is None:
                continue
            pad = 2 * stroke
            edges = (box.left - pad, box.top - pad, box.width + 2 * pad, box.height + 2 * pad)
            rect = inkex.Rectangle.new(*(round(v, 3) for v in edges))
            rect.style = inkex.Style(
                {"fill": "none", "stroke": "#e00000", "stroke-width": number(stroke), "stroke-dasharray": number(3 * stroke)}
            )
            layer.append(rect)
        self.svg.selection.set(*elements)
        return elements

    @staticmethod
    def box(elem):
        """The element's box in the document's user units, or None."""
        try:
            parent = elem.getparent()
            transform = parent.composed_transform() if isinstance(parent, inkex.BaseElement) else None
            box = elem.bounding_box(transform) if transform is not None else elem.bounding_box()
        except (AttributeError, TypeError, ValueError, ZeroDivisionError):
            return None
        if box is None or box.width is None:
            return None
        return box


def number(value):
    return f"{value:.4g}"


if __name__ == "__main__":
    Check().run()
