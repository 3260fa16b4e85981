# SPDX-License-Identifier: MIT OR Apache-2.0
"""Preview (the felt picture on its own locked layer) and Export (the
bundle and the pin devices' files), each compared with what the command
line makes of the same drawing."""

import base64
import json
import os
import shutil

from lxml import etree

import taxel_ink as tk
from helpers import EffectCase, taxel
from tactile_export import Export
from tactile_preview import Preview

MAP = "map.svg"


def drawing_only(doc):
    """The document less the extension's own layers, as text."""
    root = etree.fromstring(doc.tostring())
    for g in root.xpath("//*[@data-taxel-layer]"):
        g.getparent().remove(g)
    return etree.tostring(root, method="c14n")


class PreviewEffect(EffectCase):
    def embedded(self, doc):
        (layer,) = tk.own_layers(doc, "preview")
        (image,) = list(layer)
        href = image.get("{http://www.w3.org/1999/xlink}href")
        self.assertTrue(href.startswith("data:image/png;base64,"))
        return layer, image, base64.b64decode(href.split(",", 1)[1])

    def test_the_picture_is_taxel_preview_s_on_a_locked_layer_beside_the_page(self):
        path = self.data_file(MAP)
        doc, said, _ = self.run_effect(Preview, path, "--profile=stress2")
        layer, image, png = self.embedded(doc)
        self.assertEqual(layer.get(tk.INKSCAPE_LABEL), "taxel preview")
        self.assertEqual(layer.get(tk.INSENSITIVE), "true")
        self.assertEqual(layer.get("data-tactile"), "none")
        # The same picture the command line draws of the same drawing.
        out = os.path.join(self.tempdir, "cli.png")
        code, _, err = taxel("preview", path, "-o", out, "--profile", "stress2")
        self.assertEqual(code, 0, err)
        with open(out, "rb") as f:
            self.assertEqual(png, f.read())
        # Beside the page (its viewBox is 0 0 100 60), as tall as it.
        self.assertGreater(float(image.get("x")), 100)
        self.assertAlmostEqual(float(image.get("height")), 60)

    def test_running_again_replaces_the_layer_and_leaves_the_drawing_as_it_was(self):
        path = self.data_file(MAP)
        with open(path, "rb") as f:
            original = drawing_only(tk.inkex.load_svg(f).getroot())
        doc, _, _ = self.run_effect(Preview, path)
        _, _, first = self.embedded(doc)
        doc, _, _ = self.run_effect(Preview, self.write(doc), "--fit=true")
        self.assertEqual(len(tk.own_layers(doc, "preview")), 1)
        _, _, second = self.embedded(doc)
        self.assertNotEqual(first, second, "--fit draws another picture")
        self.assertEqual(drawing_only(doc), original)

    def test_a_pin_device_s_preview(self):
        doc, _, _ = self.run_effect(Preview, self.data_file(MAP), "--profile=dotpad", "--fit=true")
        _, _, png = self.embedded(doc)
        self.assertTrue(png.startswith(b"\x89PNG"))

    def test_a_drawing_with_errors_gets_no_picture_and_the_reason(self):
        doc, said, _ = self.run_effect(Preview, self.data_file("faulty.svg"))
        self.assertIsNone(doc)
        self.assertIn("taxel preview made no picture", said)
        self.assertIn("T0101", said)


class ExportEffect(EffectCase):
    def exported(self, fmt, profile, name):
        out = os.path.join(self.tempdir, name)
        doc, said, _ = self.run_effect(
            Export, self.data_file(MAP), f"--format={fmt}", f"--profile={profile}", "--fit=true",
            f"--out_file={out}",
        )
        self.assertIsNone(doc, "the drawing is not changed")
        self.assertIn(f"Written: {out}", said)
        return out, said

    def cli(self, fmt, profile, name):
        """The same file made with the command line."""
        folder = os.path.join(self.tempdir, "cli")
        os.makedirs(folder, exist_ok=True)
        bundle = os.path.join(folder, name + ".taxel")
        code, _, err = taxel("build", self.data_file(MAP), "-o", bundle, "--profile", profile, "--fit")
        self.assertEqual(code, 0, err)
        if fmt == "bundle":
            return bundle
        out = os.path.join(folder, name)
        code, _, err = taxel("export", bundle, "--format", fmt, "-o", out)
        self.assertEqual(code, 0, err)
        return out

    def test_a_bundle(self):
        out, said = self.exported("bundle", "stress2", "map.taxel")
        code, text, err = taxel("inspect", out, "--format", "json")
        self.assertEqual(code, 0, err)
        self.assertEqual(json.loads(text)["profile"]["name"], "stress2")
        self.assertIn("built the drawing", said)

    def test_the_pin_devices_files_are_the_command_line_s(self):
        for fmt, profile, name in [
            ("dtms", "dotpad", "map.dtms"),
            ("graphiti", "graphiti", "map.bin"),
            ("unicode", "monarch", "map.txt"),
        ]:
            with self.subTest(fmt=fmt):
                out, _ = self.exported(fmt, profile, name)
                with open(out, "rb") as mine, open(self.cli(fmt, profile, name), "rb") as theirs:
                    self.assertEqual(mine.read(), theirs.read())

    def test_a_print_profile_writes_its_medium_s_file_as_the_command_line_does(self):
        for profile, name, magic in [("swell-a4", "map.pdf", b"%PDF-"), ("print3d", "map.stl", None)]:
            with self.subTest(profile=profile):
                out, _ = self.exported("bundle", profile, name)
                folder = os.path.join(self.tempdir, "cli")
                os.makedirs(folder, exist_ok=True)
                theirs = os.path.join(folder, name)
                code, _, err = taxel("build", self.data_file(MAP), "-o", theirs, "--profile", profile, "--fit")
                self.assertEqual(code, 0, err)
                with open(out, "rb") as a, open(theirs, "rb") as b:
                    mine = a.read()
                    self.assertEqual(mine, b.read())
                if magic:
                    self.assertTrue(mine.startswith(magic))
        # Beside the drawing, with the medium's extension.
        copy = os.path.join(self.tempdir, "lesson.svg")
        shutil.copy(self.data_file(MAP), copy)
        self.run_effect(Export, copy, "--format=bundle", "--profile=swell-letter", "--fit=true")
        self.assertTrue(os.path.isfile(os.path.join(self.tempdir, "lesson.pdf")))
        # A pin device's file from a print profile is refused before anything is built.
        doc, said, _ = self.run_effect(Export, copy, "--format=dtms", "--profile=swell-a4")
        self.assertIn("writes its own file (.pdf)", said)

    def test_a_device_file_for_another_device_says_why(self):
        out = os.path.join(self.tempdir, "map.dtms")
        doc, said, _ = self.run_effect(Export, self.data_file(MAP), "--format=dtms", "--profile=stress2",
                                       f"--out_file={out}")
        self.assertIn("taxel export wrote nothing", said)
        self.assertIn("--profile dotpad", said)
        self.assertFalse(os.path.exists(out))

    def test_without_a_file_it_writes_beside_the_drawing(self):
        copy = os.path.join(self.tempdir, "lesson.svg")
        shutil.copy(self.data_file(MAP), copy)
        doc, said, _ = self.run_effect(Export, copy, "--format=unicode", "--profile=dotpad", "--fit=true")
        self.assertTrue(os.path.isfile(os.path.join(self.tempdir, "lesson.txt")), said)
        with open(os.path.join(self.tempdir, "lesson.txt"), encoding="utf-8") as f:
            self.assertTrue(any(0x2800 <= ord(c) <= 0x28FF for c in f.read()))
