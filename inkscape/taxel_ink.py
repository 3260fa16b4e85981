# SPDX-License-Identifier: MIT OR Apache-2.0
"""What the taxel effects for Inkscape share: the styles and their
parameters, writing and reading annotations, finding and running the
`taxel` program, the document as it is now written to a file, and the
layers the extension owns ("taxel preview", "taxel check").

The annotation grammar and every default mirror the compiler's
(`compiler/src/annotation/parse.rs`, docs/annotations.md); the tests
re-read what this module writes with `taxel check`.
"""

import os
import re
import shutil
import subprocess
import sys
import tempfile
from collections import namedtuple
from copy import deepcopy

import inkex

# A style parameter: its name in the annotation, its unit in the dialog
# (the one written after the number), its default, and whether it is always
# written (the parameters a teacher thinks of first) or only when it differs
# from the default.
Param = namedtuple("Param", "name unit default always")

STYLES = {
    "vibrate": [
        Param("width", "mm", 1.5, True),
        Param("freq", "Hz", 50.0, False),
        Param("amplitude", "%", 100.0, False),
        Param("soft", "mm", 0.0, False),
    ],
    "grating": [
        Param("wavelength", "mm", 2.0, True),
        Param("angle", "deg", 90.0, True),
        Param("amplitude", "%", 100.0, False),
        Param("soft", "mm", 0.0, False),
    ],
    # spacing 0 in the dialog stands for "not given": three radii.
    "dots": [
        Param("radius", "mm", 1.0, True),
        Param("spacing", "mm", 0.0, False),
        Param("amplitude", "%", 100.0, False),
    ],
    "dot": [Param("radius", "mm", 1.0, True), Param("amplitude", "%", 100.0, False)],
    "braille": [
        Param("radius", "mm", 0.72, False),
        Param("amplitude", "%", 100.0, False),
        # None (0 in the dialog): the language's own, contracted where it has it.
        Param("grade", "", None, False),
    ],
    # start: None (not given) follows the previous stroke.
    "brush": [
        Param("duration", "ms", 1000.0, True),
        Param("intensity", "%", 100.0, False),
        Param("freq", "Hz", 200.0, False),
        Param("start", "ms", None, False),
    ],
}

# What the dialog calls each style, for messages.
STYLE_TITLES = {
    "vibrate": "vibrate",
    "grating": "grating",
    "dots": "dots",
    "dot": "dot",
    "braille": "braille",
    "brush": "brush",
    "none": "left out",
}

LABEL_PREFIX = "tactile:"
INKSCAPE_LABEL = inkex.addNS("label", "inkscape")
GROUPMODE = inkex.addNS("groupmode", "inkscape")
INSENSITIVE = inkex.addNS("insensitive", "sodipodi")
# Marks the layers this extension owns, whatever the teacher renames them to.
OWN_ATTR = "data-taxel-layer"


def number(value):
    """A number as a person writes it: 1.5, 90, 0.72 (no trailing zeros)."""
    text = f"{value:.4f}".rstrip("0").rstrip(".")
    return "0" if text in ("", "-0") else text


def format_style(name, values):
    """One style as written: `grating(wavelength: 6mm, angle: 0deg)`.

    `values` maps parameter names to numbers in the dialog's units; a
    parameter left out, or None, is not written.
    """
    args = []
    for p in STYLES.get(name, []):
        v = values.get(p.name)
        if v is None or (p.name in ("spacing", "grade") and v <= 0):
            continue
        if not p.always and p.default is not None and abs(v - p.default) < 1e-9:
            continue
        args.append(f"{p.name}: {number(v)}{p.unit}")
    return f"{name}({', '.join(args)})"


def split_styles(text):
    """The styles of an annotation as written, one string each (`none` is one)."""
    return [s.strip() for s in (text or "").split(";") if s.strip()]


def style_name(written):
    """The name of one written style: `grating` for `grating(6mm)`."""
    m = re.match(r"\s*([A-Za-z_][A-Za-z0-9_-]*)", written)
    return m.group(1).lower() if m else ""


# Unit conversions into the dialog's units, as the compiler converts them.
_TO_DIALOG = {
    "mm": 1.0, "cm": 10.0, "in": 25.4, "pt": 25.4 / 72, "px": 25.4 / 96,
    "deg": 1.0, "rad": 180.0 / 3.141592653589793, "turn": 360.0,
    "hz": 1.0, "khz": 1000.0, "ms": 1.0, "s": 1000.0, "%": 1.0,
}
_VALUE = re.compile(r"^\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*([A-Za-z%]*)\s*$")


def parse_style(written):
    """One written style read back: (name, {parameter: value in the dialog's
    units}) with the defaults filled in, or None when it does not read (the
    Check effect says why)."""
    m = re.match(r"^\s*([A-Za-z_][A-Za-z0-9_-]*)\s*(?:\((.*)\))?\s*$", written, re.S)
    if not m or m.group(1).lower() not in STYLES:
        return None
    name = m.group(1).lower()
    params = STYLES[name]
    values = {p.name: p.default for p in params}
    inside = (m.group(2) or "").strip()
    position = 0
    for arg in [a for a in inside.split(",") if a.strip()] if inside else []:
        key, _, raw = arg.rpartition(":")
        key = key.strip()
        if key:
            if key not in values:
                return None
        else:
            if position >= len(params):
                return None
            key = params[position].name
            position += 1
        vm = _VALUE.match(raw)
        if not vm:
            return None
        value, unit = float(vm.group(1)), vm.group(2).lower()
        if unit == "" and key in ("amplitude", "intensity"):
            value, unit = value * 100.0, "%"
        if unit and unit not in _TO_DIALOG:
            return None
        values[key] = value * _TO_DIALOG.get(unit, 1.0)
    return name, values


def describe(written):
    """One written style with every parameter, defaults included, in the
    dialog's units: `grating: wavelength 6 mm, angle 0 deg, amplitude 100 %`."""
    parsed = parse_style(written)
    if written.strip().lower() == "none":
        return "left out (none)"
    if parsed is None:
        return f"`{written}` (does not read: run Extensions > Tactile > Check)"
    name, values = parsed
    parts = []
    for p in STYLES[name]:
        v = values[p.name]
        if v is None or (p.name in ("spacing", "grade") and v <= 0):
            auto = {"spacing": "three radii", "grade": "as its language is read"}.get(p.name, "after the previous stroke")
            parts.append(f"{p.name} {auto}")
        else:
            parts.append(f"{p.name} {number(v)}{(' ' + p.unit) if p.unit else ''}")
    return f"{name}: {', '.join(parts)}"


def is_layer(elem):
    """Whether `elem` is an Inkscape layer (a group in layer mode)."""
    return isinstance(elem, inkex.Group) and elem.get(GROUPMODE) == "layer"


def own_annotation(elem):
    """The annotation written on `elem` itself, and where: ('data-tactile',
    text), ('label', text after `tactile:`) or None. On one element
    `data-tactile` wins over a `tactile:` label, as in the compiler."""
    attr = elem.get("data-tactile")
    if attr is not None:
        return "data-tactile", attr
    label = elem.get(INKSCAPE_LABEL) or ""
    if label.strip().lower().startswith(LABEL_PREFIX):
        return "label", label.strip()[len(LABEL_PREFIX):].strip()
    return None


def element_name(elem):
    """How messages name an element: `#id`, with its label when it has one."""
    label = elem.get(INKSCAPE_LABEL)
    ident = elem.get("id")
    shown = f"#{ident}" if ident else f"<{elem.TAG}>"
    return f"{shown} ({label})" if label and label != ident else shown


# --- the taxel program -------------------------------------------------------

MISSING = (
    "The taxel program was not found{where}.\n\n"
    "What to do: install taxel (see its README), then either\n"
    "  - run `taxel inkscape install` again, which records where taxel is, or\n"
    "  - give its full path in this dialog's \"taxel program\" field, or\n"
    "  - set the environment variable TAXEL to its full path, or\n"
    "  - put the folder that holds it on the PATH Inkscape starts with.\n"
    "Then run this effect again."
)


def here():
    """The folder this module (and the installed extension) is in."""
    return os.path.dirname(os.path.abspath(__file__))


def candidates(configured):
    """Where to look for taxel, in order: the dialog's field, $TAXEL, the
    program that installed the extension, PATH, then cargo's install folder
    (a desktop-started Inkscape often lacks ~/.cargo/bin on its PATH)."""
    found = []
    if configured:
        found.append(("the dialog's \"taxel program\" field", configured))
        return found
    if os.environ.get("TAXEL"):
        found.append(("the TAXEL environment variable", os.environ["TAXEL"]))
        return found
    recorded = os.path.join(here(), "taxel-program.txt")
    if os.path.isfile(recorded):
        with open(recorded, encoding="utf-8") as f:
            line = f.readline().strip()
        if line:
            found.append(("taxel-program.txt", line))
    on_path = shutil.which("taxel")
    if on_path:
        found.append(("PATH", on_path))
    exe = "taxel.exe" if sys.platform == "win32" else "taxel"
    found.append(("cargo's install folder", os.path.join(os.path.expanduser("~"), ".cargo", "bin", exe)))
    return found


def find_taxel(configured=""):
    """The path of the taxel program, or AbortExtension saying what to do."""
    tried = candidates((configured or "").strip())
    for _, path in tried:
        if os.path.isfile(path) and os.access(path, os.X_OK):
            return path
    if (configured or "").strip() or os.environ.get("TAXEL"):
        source, path = tried[0]
        where = f" at {path} (from {source})"
    else:
        where = " (looked in: " + ", ".join(p for _, p in tried) + ")"
    raise inkex.AbortExtension(MISSING.format(where=where))


def run_taxel(exe, args):
    """Runs taxel with `args` and returns (exit code, stdout, stderr)."""
    flags = getattr(subprocess, "CREATE_NO_WINDOW", 0)
    try:
        done = subprocess.run(
            [exe] + list(args), capture_output=True, text=True, encoding="utf-8",
            errors="replace", creationflags=flags, check=False,
        )
    except OSError as err:
        raise inkex.AbortExtension(f"cannot run {exe}: {err}") from err
    return done.returncode, done.stdout, done.stderr


def for_teacher(text, temp_path):
    """taxel's account of the temporary copy, as the teacher reads it: the
    copy named "the drawing", without its line numbers (they count lines
    of the copy, not of anything the teacher sees)."""
    lines = []
    for line in text.splitlines():
        if not line.strip() or line.startswith("wrote "):
            continue
        line = re.sub(re.escape(temp_path) + r"(:\d+)*", "the drawing", line)
        lines.append(re.sub(r" \(line \d+\)", "", line))
    return lines


# --- compile options shared by Check, Preview and Export ---------------------

def add_compile_args(pars):
    """The dialog fields of the effects that compile."""
    pars.add_argument("--profile", default="stress2")
    pars.add_argument("--profile_file", default="")
    pars.add_argument("--style_mode", default="drawing")
    pars.add_argument("--style_file", default="")
    pars.add_argument("--fit", type=inkex.Boolean, default=False)
    pars.add_argument("--taxel", default="")


def compile_args(options):
    """taxel's options for the dialog's fields."""
    args = []
    profile = (options.profile_file or "").strip() if options.profile == "file" else options.profile
    if options.profile == "file" and not profile:
        raise inkex.AbortExtension("Profile \"a profile file\" is chosen but no file is given.")
    args += ["--profile", profile]
    if options.style_mode == "auto":
        args += ["--style", "auto"]
    elif options.style_mode == "file":
        sheet = (options.style_file or "").strip()
        if not sheet:
            raise inkex.AbortExtension("\"A style sheet\" is chosen but no style sheet file is given.")
        args += ["--style", sheet]
    if options.fit:
        args.append("--fit")
    return args


# --- the document as it is now ----------------------------------------------

def own_layers(svg, kind=None):
    """The layers this extension made (of one kind, or all)."""
    return [
        g for g in svg.xpath(f"//svg:g[@{OWN_ATTR}]")
        if kind is None or g.get(OWN_ATTR) == kind
    ]


def write_document(document, folder, drop_own):
    """Writes the document as it is now to `folder/drawing.svg` for taxel.

    The extension's own layers are taken out (`drop_own`, for a preview
    that must not draw the last preview) or hidden, which keeps every other
    element's path (`svg/g[2]/path[1]`) as in the document, so Check's
    diagnostics name the teacher's elements.
    """
    copy = deepcopy(document)
    root = copy.getroot()
    for layer in own_layers(root):
        if drop_own:
            layer.getparent().remove(layer)
        else:
            layer.set("style", "display:none")
            layer.set("data-tactile", "none")
    path = os.path.join(folder, "drawing.svg")
    copy.write(path, encoding="utf-8", xml_declaration=True)
    return path


def temp_folder():
    """A temporary folder, removed when the `with` block ends."""
    return tempfile.TemporaryDirectory(prefix="taxel-inkscape-")


def replace_own_layer(svg, kind, label):
    """A new, empty layer of this extension's `kind` at the top of the
    drawing, in place of the previous one: locked (sodipodi:insensitive),
    and left out of what taxel compiles (data-tactile="none")."""
    for old in own_layers(svg, kind):
        old.getparent().remove(old)
    layer = inkex.Layer.new(label)
    layer.set(OWN_ATTR, kind)
    layer.set("id", svg.get_unique_id(f"taxel-{kind}-"))
    layer.set(INSENSITIVE, "true")
    layer.set("data-tactile", "none")
    svg.append(layer)
    return layer


def document_box(svg):
    """The page in user units: (x, y, width, height) of the viewBox, else
    of the width and height (inkex before 1.2 has no viewport_width)."""
    vb = svg.get_viewbox()
    if vb and vb[2] > 0 and vb[3] > 0:
        return list(vb)
    width = getattr(svg, "viewport_width", None) or svg.unittouu(svg.get("width") or "100")
    height = getattr(svg, "viewport_height", None) or svg.unittouu(svg.get("height") or "100")
    return [0.0, 0.0, width or 100.0, height or 100.0]
