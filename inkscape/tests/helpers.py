# SPDX-License-Identifier: MIT OR Apache-2.0
"""Running the effects and taxel in the tests."""

import contextlib
import io
import json
import os
import subprocess

import inkex
from inkex.tester import TestCase


def taxel(*args):
    """Runs the taxel program under test: (exit code, stdout, stderr)."""
    done = subprocess.run([os.environ["TAXEL"], *map(str, args)], capture_output=True, text=True, check=False)
    return done.returncode, done.stdout, done.stderr


def check_json(path, *extra):
    """`taxel check --format json` on one file: (exit code, its diagnostics)."""
    code, out, err = taxel("check", path, "--format", "json", *extra)
    assert out.strip(), f"taxel check printed nothing (exit {code}): {err}"
    return code, json.loads(out)[0]["diagnostics"]


class EffectCase(TestCase):
    """inkex's TestCase, with a way to run an effect and keep both what it
    writes (the document) and what it says (Inkscape's message dialog)."""

    def run_effect(self, cls, svg_file, *args):
        """Runs `cls` on `svg_file`; returns (the output document or None
        when unchanged, the messages, the effect)."""
        effect = cls()
        out, said = io.BytesIO(), io.StringIO()
        os.environ["DOCUMENT_PATH"] = svg_file
        with contextlib.redirect_stderr(said):
            try:
                effect.run([svg_file, *args], output=out)
            except SystemExit as stop:  # inkex ends an AbortExtension with exit(1)
                said.write(f"\n[exit {stop.code}]")
        data = out.getvalue()
        doc = inkex.load_svg(io.BytesIO(data)).getroot() if data else None
        return doc, said.getvalue(), effect

    def write(self, doc, name="out.svg"):
        """Writes a document into the test's temporary folder; returns the path."""
        path = os.path.join(self.tempdir, name)
        with open(path, "wb") as f:
            f.write(doc.tostring())
        return path
