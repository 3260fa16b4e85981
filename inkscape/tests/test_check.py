# SPDX-License-Identifier: MIT OR Apache-2.0
"""Check: taxel's diagnostics of the document as it is now, grouped as the
command line groups them, and the elements of the one picked framed and
selected."""

import os
import re

import taxel_ink as tk
from helpers import EffectCase, check_json, taxel
from tactile_check import Check, group, resolve
from tactile_preview import Preview


def frames(doc):
    """The frames on the "taxel check" layer."""
    return [r for layer in tk.own_layers(doc, "check") for r in layer if r.TAG == "rect"]


class CheckEffect(EffectCase):
    def test_groups_are_the_command_line_s_and_the_first_is_framed(self):
        path = self.data_file("faulty.svg")
        doc, said, effect = self.run_effect(Check, path)
        # The command line's own account, without -v: one line per group.
        code, out, _ = taxel("check", path)
        cli = [l for l in out.splitlines() if "[T" in l]
        shown = [l for l in said.splitlines() if re.match(r"\d+\. ", l)]
        self.assertEqual(len(shown), len(cli), said)
        for mine, theirs in zip(shown, cli):
            code_of = lambda line: line[line.index("[") + 1 : line.index("]")]
            self.assertEqual(code_of(mine), code_of(theirs))
        self.assertTrue(shown[0].startswith("1. error[T0101]"), said)
        # The error is about #badge: framed on the locked check layer, and selected.
        (layer,) = tk.own_layers(doc, "check")
        self.assertEqual(layer.get(tk.INSENSITIVE), "true")
        (frame,) = frames(doc)
        # Around the badge (x 10 to 30, y 10 to 25 in the drawing's units).
        x, y = float(frame.get("x")), float(frame.get("y"))
        w, h = float(frame.get("width")), float(frame.get("height"))
        self.assertTrue(x < 10 and y < 10 and x + w > 30 and y + h > 25 and w < 25 and h < 20, (x, y, w, h))
        self.assertEqual([e.get("id") for e in effect.svg.selection.values()], ["badge"])
        self.assertIn("Diagnostic 1 is about #badge", said)

    def test_the_teacher_picks_another_group(self):
        path = self.data_file("faulty.svg")
        _, diags = check_json(path)
        groups = group(diags)
        # The first group naming several elements.
        n, chosen = next((i, g) for i, g in enumerate(groups, 1) if len({d.get("element") for d in g}) > 1)
        doc, said, effect = self.run_effect(Check, path, f"--group={n}")
        named = {d["element"] for d in chosen if d.get("element")}
        selected = list(effect.svg.selection.values())
        # Elements without an id are selected too, through their path, and get no id.
        self.assertEqual(selected, [resolve(effect.svg, name) for name in sorted(named)])
        self.assertTrue(all(e.get("id") is None for e in selected))
        self.assertEqual(len(frames(doc)), len(named))
        self.assertIn(f"Diagnostic {n} is about", said)

    def test_an_element_without_id_is_found_by_the_compiler_s_path(self):
        doc, said, effect = self.run_effect(Check, self.data_file("faulty.svg"), "--group=1")
        svg = effect.svg
        # Every element the compiler names resolves, and to one whose own name is that one.
        _, diags = check_json(self.data_file("faulty.svg"))
        for d in diags:
            if d.get("element"):
                elem = resolve(svg, d["element"])
                self.assertIsNotNone(elem, d["element"])
        unnamed = resolve(svg, "parts/path[2]")
        self.assertIsNotNone(unnamed)
        self.assertIsNone(unnamed.get("id"))
        self.assertEqual(unnamed.get("d"), "M 10 50 L 20 50")
        self.assertIsNone(resolve(svg, "parts/path[7]"))

    def test_a_group_naming_no_element_takes_the_old_frames_away(self):
        doc, said, _ = self.run_effect(Check, self.data_file("faulty.svg"))
        self.assertEqual(len(tk.own_layers(doc, "check")), 1)
        # The badge's annotation fixed; then a group about no element (the page size) is picked.
        doc.getElementById("badge").set("data-tactile", "vibrate()")
        fixed = self.write(doc, "fixed.svg")
        _, diags = check_json(fixed)
        n = next(i for i, g in enumerate(group(diags), 1) if not any(d.get("element") for d in g))
        doc, said, _ = self.run_effect(Check, fixed, f"--group={n}")
        self.assertIn("taxel check: ok, 0 error(s)", said)
        self.assertIn(f"Diagnostic {n} names no element", said)
        self.assertEqual(tk.own_layers(doc, "check"), [])

    def test_the_preview_layer_adds_no_diagnostic(self):
        path = self.data_file("map.svg")
        _, before, _ = self.run_effect(Check, path)
        doc, _, _ = self.run_effect(Preview, path)
        _, after, _ = self.run_effect(Check, self.write(doc))
        self.assertEqual(before, after)

    def test_missing_taxel_says_what_to_do(self):
        saved = os.environ["TAXEL"]
        os.environ["TAXEL"] = os.path.join(self.tempdir, "no-such-taxel")
        try:
            doc, said, _ = self.run_effect(Check, self.data_file("map.svg"))
        finally:
            os.environ["TAXEL"] = saved
        self.assertIsNone(doc)
        self.assertIn("The taxel program was not found at", said)
        self.assertIn("What to do", said)
        self.assertIn("[exit", said)
        # The dialog's field wins over the environment.
        doc, said, _ = self.run_effect(Check, self.data_file("map.svg"), "--taxel=/nowhere/taxel")
        self.assertIn("/nowhere/taxel (from the dialog's \"taxel program\" field)", said)
