# SPDX-License-Identifier: MIT OR Apache-2.0
"""Style selection: what it writes, on elements and layers, read back by
`taxel check` and `taxel inspect`, and read back by its own "What is there"."""

import json

from inkex.tester import ComparisonMixin, TestCase

import taxel_ink as tk
from helpers import EffectCase, check_json, taxel
from tactile_preview import Preview
from tactile_style import Style

MAP = "map.svg"


class StyleComparisons(ComparisonMixin, TestCase):
    """The documents written for a few dialogs, reviewed once and kept
    (data/refs; EXPORT_COMPARE=1 writes new ones to review)."""

    effect_class = Style
    compare_file = "map.svg"
    comparisons = [
        ("--id=lake", "--id=forest", "--tab=grating", "--grating_wavelength=6", "--grating_angle=45"),
        ("--tab=vibrate", "--vibrate_width=2"),  # nothing selected: the current layer's name
        ("--tab=vibrate", "--layer_as=attribute"),
        ("--id=ashby", "--tab=dot", "--dot_radius=1.5"),
        ("--id=ashby-name", "--tab=braille"),
        ("--id=towns", "--tab=none"),
    ]


class StyleEffect(EffectCase):
    """Each tab's annotation, as taxel reads it."""

    def styled(self, *args):
        doc, said, _ = self.run_effect(Style, self.data_file(MAP), *args)
        self.assertIsNotNone(doc, said)
        return doc, said

    def test_each_style_is_read_by_taxel_check_as_the_style_chosen(self):
        cases = [
            ("lake", "vibrate", ["--vibrate_width=2.5", "--vibrate_freq=80", "--vibrate_amplitude=60"]),
            ("lake", "grating", ["--grating_wavelength=6", "--grating_angle=135", "--grating_soft=0.5"]),
            ("road", "dots", ["--dots_radius=1.2", "--dots_spacing=4"]),
            ("ashby", "dot", ["--dot_radius=1.5", "--dot_amplitude=80"]),
            ("ashby-name", "braille", ["--braille_radius=0.8"]),
            ("road", "none", []),
        ]
        for ident, tab, extra in cases:
            with self.subTest(tab=tab):
                doc, _ = self.styled(f"--id={ident}", f"--tab={tab}", *extra)
                # A drawing whose only annotation is `none` has nothing tactile
                # unless the rest is decided automatically.
                code, diags = check_json(self.write(doc), *(["--style", "auto"] if tab == "none" else []))
                errors = [d for d in diags if d["severity"] == "error"]
                self.assertEqual(errors, [], doc.getElementById(ident).get("data-tactile"))
                summary = next(d["message"] for d in diags if d["code"] == "T0330")
                self.assertIn(tk.STYLE_TITLES[tab], summary)

    def test_brush_is_read_by_taxel_check_on_a_grid_profile(self):
        doc, _ = self.styled("--id=road", "--tab=brush", "--brush_duration=1500", "--brush_start_fixed=true",
                             "--brush_start=200")
        self.assertEqual(doc.getElementById("road").get("data-tactile"), "brush(duration: 1500ms, start: 200ms)")
        code, diags = check_json(self.write(doc), "--profile", "brush-4x3")
        self.assertEqual([d for d in diags if d["severity"] == "error"], [])
        self.assertIn("brush", next(d["message"] for d in diags if d["code"] == "T0330"))

    def test_the_dialog_s_numbers_reach_the_bundle(self):
        doc, _ = self.styled("--id=lake", "--tab=vibrate", "--vibrate_width=2.5", "--vibrate_freq=80",
                             "--vibrate_amplitude=60", "--vibrate_soft=0.3")
        doc, _, _ = self.run_effect(Style, self.write(doc, "v.svg"), "--id=lake", "--tab=grating",
                                    "--combine=add", "--grating_wavelength=6", "--grating_angle=135")
        bundle = f"{self.tempdir}/lake.taxel"
        code, out, err = taxel("build", self.write(doc), "-o", bundle)
        self.assertEqual(code, 0, err)
        code, out, err = taxel("inspect", bundle, "--format", "json")
        chunks = {c["kind"]: c for c in json.loads(out)["chunks"] if any(s["id"] == "lake" for s in c.get("sources", []))}
        vib, grat = chunks["vibration-field"], chunks["grating-field"]
        self.assertAlmostEqual(vib["freq_hz"], 80)
        self.assertAlmostEqual(vib["amplitude"], 0.6)
        self.assertAlmostEqual(vib["soft_mm"], 0.3, places=5)
        self.assertAlmostEqual(grat["wavelength_mm"], 6)
        self.assertAlmostEqual(grat["angle_deg"], 135)

    def test_the_dialog_s_defaults_are_the_compiler_s(self):
        # Every parameter written out at the dialog's default compiles to the
        # same layers as the bare style, whose defaults are the compiler's.
        for name, params in tk.STYLES.items():
            if name == "brush":
                continue  # on a grid profile, below
            with self.subTest(style=name):
                spelled = ", ".join(
                    f"{p.name}: {tk.number(p.default)}{p.unit}" for p in params if p.default and p.name != "spacing"
                )
                self.assertEqual(self.layers(name, f"{name}()"), self.layers(name, f"{name}({spelled})"))
        spelled = ", ".join(f"{p.name}: {tk.number(p.default)}{p.unit}" for p in tk.STYLES["brush"] if p.default)
        grid = ("--profile", "brush-4x3")
        self.assertEqual(self.layers("brush", "brush()", grid), self.layers("brush", f"brush({spelled})", grid))

    def layers(self, name, annotation, extra=()):
        """The layers of a small drawing styled `annotation`, from `taxel inspect`."""
        target = "text" if name == "braille" else ("circle" if name == "dot" else "path")
        shapes = {
            "path": '<path id="s" d="M 10 10 L 60 10 L 60 40 Z" fill="#888" stroke="black"',
            "circle": '<circle id="s" cx="30" cy="30" r="2" fill="black"',
            "text": '<text id="s" x="10" y="30" font-size="5"',
        }
        body = shapes[target] + f' data-tactile="{annotation}"' + (">Ashby</text>" if target == "text" else "/>")
        svg = f'<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="60mm" viewBox="0 0 100 60">{body}</svg>'
        path, bundle = f"{self.tempdir}/{name}.svg", f"{self.tempdir}/{name}.taxel"
        with open(path, "w") as f:
            f.write(svg)
        code, out, err = taxel("build", path, "-o", bundle, "--force", *extra)
        self.assertEqual(code, 0, err)
        code, out, err = taxel("inspect", bundle, "--format", "json")
        chunks = json.loads(out)["chunks"]
        return [c for c in chunks if c["kind"] not in ("manifest", "provenance")]

    def test_nothing_selected_names_the_current_layer_or_writes_its_attribute(self):
        doc, _ = self.styled("--tab=dots", "--dots_radius=1.5")
        roads = doc.getElementById("roads")
        self.assertEqual(roads.get(tk.INKSCAPE_LABEL), "tactile: dots(radius: 1.5mm)")
        self.assertIsNone(roads.get("data-tactile"))
        doc, _ = self.styled("--tab=dots", "--layer_as=attribute")
        roads = doc.getElementById("roads")
        self.assertEqual((roads.get(tk.INKSCAPE_LABEL), roads.get("data-tactile")), ("Roads", "dots(radius: 1mm)"))
        # The layer's label is an annotation taxel reads: both roads inherit it.
        code, diags = check_json(self.write(self.styled("--tab=dots")[0]))
        self.assertIn("2 dots", next(d["message"] for d in diags if d["code"] == "T0330"))

    def test_add_keeps_the_other_kinds_and_replaces_the_same_kind(self):
        doc, _ = self.styled("--id=lake", "--tab=vibrate")
        first = self.write(doc, "a.svg")
        doc, _, _ = self.run_effect(Style, first, "--id=lake", "--tab=grating", "--combine=add",
                                    "--grating_wavelength=6", "--grating_angle=0")
        self.assertEqual(doc.getElementById("lake").get("data-tactile"),
                         "vibrate(width: 1.5mm); grating(wavelength: 6mm, angle: 0deg)")
        doc, _, _ = self.run_effect(Style, self.write(doc, "b.svg"), "--id=lake", "--tab=grating",
                                    "--combine=add", "--grating_wavelength=9")
        self.assertEqual(doc.getElementById("lake").get("data-tactile"),
                         "vibrate(width: 1.5mm); grating(wavelength: 9mm, angle: 90deg)")
        doc, _, _ = self.run_effect(Style, self.write(doc, "c.svg"), "--id=lake", "--tab=dot")
        self.assertEqual(doc.getElementById("lake").get("data-tactile"), "dot(radius: 1mm)")

    def test_clear_takes_the_style_off(self):
        doc, _ = self.styled("--tab=vibrate")  # the current layer, "Roads"
        doc, _, _ = self.run_effect(Style, self.write(doc), "--tab=clear")
        self.assertEqual(doc.getElementById("roads").get(tk.INKSCAPE_LABEL), "roads")
        doc, _ = self.styled("--id=lake", "--tab=grating")
        doc, _, _ = self.run_effect(Style, self.write(doc), "--id=lake", "--tab=clear")
        self.assertIsNone(doc.getElementById("lake").get("data-tactile"))

    def test_what_is_there_reads_back_every_setting_and_changes_nothing(self):
        doc, _ = self.styled("--id=lake", "--tab=grating", "--grating_wavelength=6", "--grating_angle=135",
                             "--grating_amplitude=70")
        path = self.write(doc)
        doc, said, _ = self.run_effect(Style, path, "--id=lake", "--id=forest", "--id=road", "--tab=current")
        self.assertIsNone(doc, "the document is unchanged")
        self.assertIn("#lake: its data-tactile:\n    grating: wavelength 6 mm, angle 135 deg, amplitude 70 %, soft 0 mm",
                      said)
        self.assertIn("#forest: no tactile style", said)
        doc, _ = self.styled("--tab=dots", "--dots_spacing=4")
        doc, said, _ = self.run_effect(Style, self.write(doc, "l.svg"), "--id=road", "--tab=current")
        self.assertIn("#road: inherits from #roads (tactile: dots(radius: 1mm, spacing: 4mm)):\n"
                      "    dots: radius 1 mm, spacing 4 mm, amplitude 100 %", said)

    def test_nothing_to_style_says_what_to_do(self):
        doc, said, _ = self.run_effect(Style, self.data_file("plain.svg"), "--tab=vibrate")
        self.assertIsNone(doc)
        self.assertIn("select the shapes", said)

    def test_the_extension_s_own_layers_are_never_styled(self):
        doc, _, _ = self.run_effect(Preview, self.data_file(MAP))
        (layer,) = tk.own_layers(doc, "preview")
        image = layer[0]
        # The preview layer current (the teacher clicked it), its picture selected.
        doc.getElement("//sodipodi:namedview").set("inkscape:current-layer", layer.get("id"))
        path = self.write(doc)
        for args in ([], [f"--id={image.get('id')}"]):
            out, said, _ = self.run_effect(Style, path, "--tab=vibrate", *args)
            self.assertIsNone(out, said)
            self.assertIn("Nothing to style", said)


class ReadingBack(TestCase):
    """The dialog's reading of what taxel's grammar allows."""

    def test_written_styles_read_back_to_the_dialog_s_values(self):
        for name, params in tk.STYLES.items():
            for scale in (0.5, 1.0, 3.0):
                values = {p.name: round((p.default or 7.0) * scale, 2) for p in params}
                if name == "braille":
                    values["grade"] = 1.0
                written = tk.format_style(name, values)
                parsed = tk.parse_style(written)
                self.assertIsNotNone(parsed, written)
                for p in params:
                    self.assertAlmostEqual(parsed[1][p.name], values[p.name], places=6, msg=written)

    def test_other_units_and_positional_values_convert_as_the_compiler_does(self):
        name, values = tk.parse_style("grating(0.6cm, 0.25turn, 0.5)")
        self.assertEqual(name, "grating")
        self.assertAlmostEqual(values["wavelength"], 6.0)
        self.assertAlmostEqual(values["angle"], 90.0)
        self.assertAlmostEqual(values["amplitude"], 50.0)
        self.assertIsNone(tk.parse_style("grating(wavelength 6mm)"))
        self.assertIsNone(tk.parse_style("sparkle()"))


class BrailleGrade(TestCase):
    """The dialog's braille grade: its default writes none, as the compiler's."""

    def test_the_default_grade_is_not_written_and_reads_as_the_language_s(self):
        self.assertEqual(tk.format_style("braille", {"grade": 0.0}), "braille()")
        self.assertEqual(tk.format_style("braille", {"grade": 2.0}), "braille(grade: 2)")
        self.assertIn("grade as its language is read", tk.describe("braille()"))
        self.assertIn("grade 1", tk.describe("braille(grade: 1)"))
