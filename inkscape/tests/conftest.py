# SPDX-License-Identifier: MIT OR Apache-2.0
"""Test setup: the extension's modules import as Inkscape imports them (from
their own folder), and the effects run the taxel program built from this
repository: $TAXEL, else target/debug/taxel (`cargo build` or `cargo test`
makes it)."""

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
EXTENSION = os.path.dirname(HERE)
REPO = os.path.dirname(EXTENSION)
sys.path.insert(0, EXTENSION)

if not os.environ.get("TAXEL"):
    exe = os.path.join(REPO, "target", "debug", "taxel.exe" if sys.platform == "win32" else "taxel")
    if not os.path.isfile(exe):
        raise SystemExit(f"the tests run the taxel program: build it first (cargo build), or set TAXEL; not found: {exe}")
    os.environ["TAXEL"] = exe
