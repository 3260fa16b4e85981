#!/usr/bin/env python3
# SPDX-License-Identifier: MIT OR Apache-2.0
"""Extensions > Tactile > Style selection: writes a tactile style on the
selected elements (`data-tactile`), or on a layer (its label `tactile: ...`,
or a `data-tactile` attribute that keeps its name). With nothing selected it
styles the current layer. The "What is there" tab changes nothing and says
what each selected element has, its own or inherited, with every parameter.
"""

import sys

sys.dont_write_bytecode = True  # leave no __pycache__ beside the installed extension

import inkex  # noqa: E402

import taxel_ink as tk  # noqa: E402


class Style(inkex.EffectExtension):
    """Extensions > Tactile > Style selection."""

    def add_arguments(self, pars):
        pars.add_argument("--tab", default="vibrate")
        pars.add_argument("--combine", default="replace")
        pars.add_argument("--layer_as", default="label")
        for style, params in tk.STYLES.items():
            for p in params:
                default = p.default if p.default is not None else 0.0
                pars.add_argument(f"--{style}_{p.name}", type=float, default=default)
        pars.add_argument("--brush_start_fixed", type=inkex.Boolean, default=False)

    def targets(self):
        """The selected elements, else the current layer; never the
        extension's own layers (the preview, the check's frames)."""
        own = tk.own_layers(self.svg)
        mine = lambda e: any(e is layer or layer in e.iterancestors() for layer in own)
        chosen = [e for e in self.svg.selection.values() if not mine(e)]
        if chosen:
            return chosen
        layer = self.svg.get_current_layer()
        if layer is not None and tk.is_layer(layer) and not mine(layer):
            return [layer]
        raise inkex.AbortExtension(
            "Nothing to style: select the shapes, lines or texts to style (or a layer), then run this again."
        )

    def chosen_style(self):
        """The style the dialog's tab and fields say, as written."""
        tab = self.options.tab.strip('"')
        if tab == "none":
            return "none"
        values = {p.name: getattr(self.options, f"{tab}_{p.name}") for p in tk.STYLES[tab]}
        if tab == "brush" and not self.options.brush_start_fixed:
            values["start"] = None
        return tk.format_style(tab, values)

    def effect(self):
        tab = self.options.tab.strip('"')
        targets = self.targets()
        if tab == "current":
            self.report(targets)
            return False
        if tab == "clear":
            for elem in targets:
                self.clear(elem)
            return None
        if tab not in tk.STYLES and tab != "none":
            raise inkex.AbortExtension(f"unknown tab {tab!r}")
        style = self.chosen_style()
        for elem in targets:
            self.write(elem, style)
        return None

    def write(self, elem, style):
        """Writes `style` on `elem`, replacing its annotation or (`combine`
        = add) the style of the same kind in it."""
        own = tk.own_annotation(elem)
        on_label = tk.is_layer(elem) and self.options.layer_as == "label" and (own is None or own[0] == "label")
        text = style
        if self.options.combine == "add" and own is not None and style != "none":
            kind = tk.style_name(style)
            kept = [s for s in tk.split_styles(own[1]) if tk.style_name(s) not in (kind, "none")]
            text = "; ".join(kept + [style])
        if on_label:
            elem.set(tk.INKSCAPE_LABEL, f"{tk.LABEL_PREFIX} {text}")
        else:
            elem.set("data-tactile", text)

    def clear(self, elem):
        """Takes the annotation off `elem`; a layer named `tactile: ...` gets its id as its name."""
        if elem.get("data-tactile") is not None:
            del elem.attrib["data-tactile"]
        label = elem.get(tk.INKSCAPE_LABEL) or ""
        if label.strip().lower().startswith(tk.LABEL_PREFIX):
            elem.set(tk.INKSCAPE_LABEL, elem.get("id") or "Layer")

    def report(self, targets):
        """Says what each target has, its own or inherited."""
        lines = []
        for elem in targets:
            own = tk.own_annotation(elem)
            if own is not None:
                where = "its data-tactile" if own[0] == "data-tactile" else "its layer name"
                styles = tk.split_styles(own[1]) or ["(empty)"]
                lines.append(f"{tk.element_name(elem)}: {where}:")
                lines += [f"    {tk.describe(s)}" for s in styles]
                continue
            source = next((a for a in elem.iterancestors() if tk.own_annotation(a) is not None), None)
            if source is not None:
                styles = tk.split_styles(tk.own_annotation(source)[1])
                lines.append(f"{tk.element_name(elem)}: inherits from {tk.element_name(source)}:")
                lines += [f"    {tk.describe(s)}" for s in styles]
            else:
                lines.append(
                    f"{tk.element_name(elem)}: no tactile style of its own nor inherited: the automatic "
                    "style decides when the drawing has no annotation at all (or with \"automatic\" "
                    "in Check, Preview and Export); otherwise it is left out"
                )
        self.msg("\n".join(lines))


if __name__ == "__main__":
    Style().run()
