# SPDX-License-Identifier: MIT OR Apache-2.0
"""The extension as Inkscape runs it: installed by `taxel inkscape install`
into the folder Inkscape reads, then Style selection and Preview run by
Inkscape's own command line (`--actions`, with the dialogs' defaults), and
the document Inkscape saves read back by `taxel check`.

Inkscape runs effects only with its window open, so the test needs a
display: Xvfb through `xvfb-run` (Debian's `xvfb`), or $DISPLAY. Without
Inkscape it is skipped, unless TAXEL_INKSCAPE_REQUIRED is set, as .ci/run
sets it after installing Debian's `inkscape` and `xvfb`.
"""

import os
import shutil
import subprocess
import sysconfig
import unittest

from inkex.tester import TestCase

from helpers import check_json, taxel

REQUIRED = bool(os.environ.get("TAXEL_INKSCAPE_REQUIRED"))
INKSCAPE = shutil.which("inkscape")
XVFB = shutil.which("xvfb-run")


def missing():
    if not INKSCAPE:
        return "Inkscape is not installed (Debian: apt-get install inkscape)"
    if not XVFB and not os.environ.get("DISPLAY"):
        return "no display for Inkscape's window (Debian: apt-get install xvfb)"
    return None


class InkscapeRunsTheExtension(TestCase):
    def setUp(self):
        super().setUp()
        reason = missing()
        if reason and REQUIRED:
            self.fail(reason)
        elif reason:
            raise unittest.SkipTest(reason)

    def test_style_and_preview_through_inkscape_s_command_line(self):
        config = os.path.join(self.tempdir, "config")
        env = dict(os.environ, XDG_CONFIG_HOME=config)
        env.pop("TAXEL")  # found through what `taxel inkscape install` recorded, as on a teacher's machine
        # Inkscape runs `python3` from PATH, and may resolve a virtual environment's
        # link to the interpreter behind it: give it this environment's packages.
        env["PYTHONPATH"] = sysconfig.get_paths()["purelib"]
        done = subprocess.run([os.environ["TAXEL"], "inkscape", "install"], env=env, capture_output=True, text=True)
        self.assertEqual(done.returncode, 0, done.stderr)
        folder = os.path.join(config, "inkscape", "extensions", "taxel")
        self.assertTrue(os.path.isfile(os.path.join(folder, "tactile_style.inx")), done.stderr)

        drawing = os.path.join(self.tempdir, "map.svg")
        shutil.copy(self.data_file("map.svg"), drawing)
        out = os.path.join(self.tempdir, "out.svg")
        actions = ";".join([
            "select-by-id:lake",
            "org.taxel.tactile.style.noprefs",
            "select-clear",
            "org.taxel.tactile.preview.noprefs",
            f"export-filename:{out}",
            "export-do",
        ])
        command = [INKSCAPE, "-g", "--batch-process", f"--actions={actions}", drawing]
        if XVFB and not os.environ.get("DISPLAY"):
            command = [XVFB, "-a"] + command
        try:
            done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=180)
        except subprocess.TimeoutExpired as late:
            # Inkscape waits for a click on a dialog it opened: a script's error message.
            self.fail(f"Inkscape did not finish within {late.timeout} s (a message dialog left open?)")
        self.assertTrue(os.path.isfile(out), done.stderr[-2000:])

        code, diags = check_json(out)
        self.assertEqual([d for d in diags if d["severity"] == "error"], [])
        self.assertIn("1 vibrate", next(d["message"] for d in diags if d["code"] == "T0330"))
        with open(out, encoding="utf-8") as f:
            text = f.read()
        self.assertIn('data-tactile="vibrate(width: 1.5mm)"', text)
        self.assertEqual(text.count('data-taxel-layer="preview"'), 1)
        self.assertIn("data:image/png;base64,", text)

        done = subprocess.run([os.environ["TAXEL"], "inkscape", "uninstall"], env=env, capture_output=True, text=True)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertFalse(os.path.exists(folder), done.stderr)
