#!/usr/bin/env python3
# SPDX-License-Identifier: MIT OR Apache-2.0
"""Extensions > Tactile > Export: compiles the document as it is now with
`taxel build` for the chosen device and writes the bundle, or the device's
own file through `taxel export` (a Dot Pad DTMS page file, Graphiti frames,
Unicode braille text). The drawing is not changed.
"""

import os
import sys

sys.dont_write_bytecode = True  # leave no __pycache__ beside the installed extension

import inkex  # noqa: E402

import taxel_ink as tk  # noqa: E402

# Each format: its file extension and whether it is a device file made from a bundle.
FORMATS = {"bundle": ".taxel", "dtms": ".dtms", "graphiti": ".bin", "unicode": ".txt"}
# The print profiles, each with the file it writes by default (taxel build
# writes the medium's file, not a bundle; `.png` and `.3mf` when chosen).
PRINT_FILES = {
    "swell-a4": ".pdf", "swell-letter": ".pdf", "tiger-20dpi": ".pdf",
    "emboss-braille-grid": ".pdf", "print3d": ".stl",
}


class Export(inkex.EffectExtension):
    """Extensions > Tactile > Export."""

    def add_arguments(self, pars):
        tk.add_compile_args(pars)
        pars.add_argument("--format", default="bundle")
        pars.add_argument("--out_file", default="")

    def output_path(self):
        """The file to write: the dialog's, else beside the drawing with the format's extension."""
        fmt = self.options.format
        if fmt not in FORMATS:
            raise inkex.AbortExtension(f"unknown format {fmt!r}: expected one of {', '.join(FORMATS)}")
        printed = PRINT_FILES.get(self.options.profile)
        if printed and fmt != "bundle":
            raise inkex.AbortExtension(
                f"{self.options.profile} is paper or a 3D print: it writes its own file ({printed}), "
                "not a pin device's; choose \"A taxel bundle ... or a print profile's file\" in \"Write\"."
            )
        chosen = (self.options.out_file or "").strip()
        if chosen:
            return os.path.abspath(os.path.expanduser(chosen))
        doc = self.document_path()
        if not doc:
            raise inkex.AbortExtension(
                "The drawing has not been saved yet, so there is no folder to write beside it: "
                "save it, or choose a file in \"File\"."
            )
        return os.path.splitext(doc)[0] + (printed or FORMATS[fmt])

    def effect(self):
        exe = tk.find_taxel(self.options.taxel)
        out = self.output_path()
        said = []
        with tk.temp_folder() as folder:
            path = tk.write_document(self.document, folder, drop_own=True)
            bundle = out if self.options.format == "bundle" else os.path.join(folder, "drawing.taxel")
            code, stdout, stderr = tk.run_taxel(
                exe, ["build", path, "-o", bundle, "--force"] + tk.compile_args(self.options)
            )
            said += tk.for_teacher(stdout + stderr, path)
            if code != 0 or not os.path.isfile(bundle):
                raise inkex.AbortExtension(f"taxel build wrote nothing (exit {code}):\n" + "\n".join(said))
            if self.options.format != "bundle":
                code, stdout, stderr = tk.run_taxel(
                    exe, ["export", bundle, "--format", self.options.format, "-o", out]
                )
                said += tk.for_teacher(stdout + stderr, bundle)
                if code != 0:
                    raise inkex.AbortExtension(f"taxel export wrote nothing (exit {code}):\n" + "\n".join(said))
        self.msg("\n".join(said + [f"Written: {out} ({os.path.getsize(out)} bytes)"]))
        return False


if __name__ == "__main__":
    Export().run()
