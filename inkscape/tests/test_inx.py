# SPDX-License-Identifier: MIT OR Apache-2.0
"""The .inx files: valid for Inkscape's schema, each parameter matching its
script's (inkex's own checks), and the devices listed the ones taxel has."""

import glob
import os
import re

from inkex.inx import InxFile
from inkex.tester import TestCase
from inkex.tester.inx import InxMixin

from helpers import taxel

EXTENSION = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
INX = sorted(glob.glob(os.path.join(EXTENSION, "*.inx")))


class InxFiles(InxMixin, TestCase):
    def test_every_inx_is_valid_and_matches_its_script(self):
        self.assertEqual([os.path.basename(f) for f in INX],
                         [f"tactile_{n}.inx" for n in ("check", "export", "preview", "style")])
        here = os.getcwd()
        os.chdir(EXTENSION)  # inkex loads the script named in the .inx from the current folder
        try:
            for inx in INX:
                with self.subTest(inx=os.path.basename(inx)):
                    self.assertInxSchemaValid(inx)
                    self.assertInxIsGood(inx)
                    self.assertEqual(InxFile(inx).xml.find_one("effect/effects-menu/submenu").get("name"), "Tactile")
        finally:
            os.chdir(here)

    def test_the_devices_are_taxel_s_built_in_profiles(self):
        code, out, _ = taxel("profiles")
        self.assertEqual(code, 0)
        names = [l.split()[0] for l in out.splitlines()[1:] if l.strip() and not l.startswith("A profile")]
        for inx in INX:
            listed = [o.get("value") for o in InxFile(inx).xml.xpath("//*[local-name()='param'][@name='profile']/*")]
            if listed:
                with self.subTest(inx=os.path.basename(inx)):
                    self.assertEqual(listed, names + ["file"])
