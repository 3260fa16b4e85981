#!/usr/bin/env python3
# SPDX-License-Identifier: MIT OR Apache-2.0
"""Extensions > Tactile > Preview: runs `taxel preview` on the document as
it is now and adds the picture of what the reader will feel as a locked
layer "taxel preview": one embedded image beside the page, on its right,
as tall as the page. Running it again replaces that layer; the drawing's
own layers are never touched, and the layer is left out of what taxel
compiles (`data-tactile="none"`).

Beside the page rather than over it: the picture already draws the drawing
faintly under what is felt, and with --fit or a pin device its scale is the
device's, not the page's.
"""

import base64
import os
import struct
import sys

sys.dont_write_bytecode = True  # leave no __pycache__ beside the installed extension

import inkex  # noqa: E402

import taxel_ink as tk  # noqa: E402


def png_size(data):
    """(width, height) of a PNG from its header, or None."""
    if len(data) < 24 or data[:8] != b"\x89PNG\r\n\x1a\n" or data[12:16] != b"IHDR":
        return None
    width, height = struct.unpack(">II", data[16:24])
    return (width, height) if width and height else None


class Preview(inkex.EffectExtension):
    """Extensions > Tactile > Preview."""

    def add_arguments(self, pars):
        tk.add_compile_args(pars)

    def effect(self):
        exe = tk.find_taxel(self.options.taxel)
        with tk.temp_folder() as folder:
            path = tk.write_document(self.document, folder, drop_own=True)
            png = os.path.join(folder, "preview.png")
            code, out, err = tk.run_taxel(exe, ["preview", path, "-o", png] + tk.compile_args(self.options))
            data = b""
            if os.path.isfile(png):
                with open(png, "rb") as f:
                    data = f.read()
        said = tk.for_teacher(err + out, path)
        size = png_size(data)
        if code != 0 or size is None:
            raise inkex.AbortExtension(f"taxel preview made no picture (exit {code}):\n" + "\n".join(said))
        x, y, w, h = tk.document_box(self.svg)
        layer = tk.replace_own_layer(self.svg, "preview", "taxel preview")
        image = inkex.Image()
        image.set("id", self.svg.get_unique_id("taxel-preview-image-"))
        height = h
        width = h * size[0] / size[1]
        for name, value in (("x", x + w * 1.05), ("y", y), ("width", width), ("height", height)):
            image.set(name, f"{value:.4f}".rstrip("0").rstrip("."))
        image.set("preserveAspectRatio", "xMidYMid meet")
        image.set("xlink:href", "data:image/png;base64," + base64.b64encode(data).decode("ascii"))
        layer.append(image)
        if said:
            self.msg("taxel preview:\n" + "\n".join(said))


if __name__ == "__main__":
    Preview().run()
