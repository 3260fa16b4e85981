//! The automatic style sheet written out as TOML (`taxel style auto [INPUT]`):
//! a starting point for a teacher's own sheet.

use std::fmt::Write as _;

use taxel_format::DeviceProfile;

use super::{Plan, fill_name, outline_style, textures};
use crate::annotation::{Grating, Vibrate};
use crate::drawing::{Drawing, Shape};

fn grating(g: &Grating) -> String {
    format!("grating(wavelength: {}mm, angle: {}deg)", g.wavelength_mm, g.angle_deg)
}

fn vibrate(v: &Vibrate) -> String {
    format!("vibrate(width: {}mm)", v.width_mm)
}

/// The automatic sheet as a style sheet (TOML that [`crate::StyleSheet::parse`]
/// reads). Without a drawing it lists the textures and example rules in
/// comments; with `input` (a drawing and the [`Plan`] made for it) it has one
/// rule per fill colour with the texture chosen for it (and `vibrate();` in
/// front where the regions of that fill are stroked), and one per stroke
/// colour of the lines. What a sheet cannot say (text to braille, marks to
/// dots, backgrounds left out) is explained in comments.
///
/// ```
/// use taxel_compiler::{StyleSheet, style::sheet_toml};
/// use taxel_format::profiles;
///
/// let toml = sheet_toml(&profiles::builtin("stress2").unwrap(), None);
/// assert!(StyleSheet::parse(&toml, "auto.toml").is_ok());
/// ```
pub fn sheet_toml(profile: &DeviceProfile, input: Option<(&Drawing, &Plan)>) -> String {
    let tex = input.map_or_else(|| textures(profile), |(_, p)| p.textures);
    let mut s = String::new();
    let _ = writeln!(s, "# taxel's automatic style sheet (`auto`) for the {} profile.", profile.name);
    s += "#\n";
    s += "# `taxel build` uses it when a drawing has no tactile annotation and no --style,\n";
    s += "# and `--style auto` asks for it. This file is a starting point for your own\n";
    s += "# sheet: edit the rules, then build with `--style THIS_FILE` (docs/annotations.md).\n";
    s += "#\n";
    s += "# What the automatic sheet decides from the drawing itself:\n";
    let _ = writeln!(
        s,
        "#   - stroked lines and outlines vibrate (grey lines less than {:.0} % as dark as the",
        super::FAINT_SHARE * 100.0
    );
    let _ = writeln!(
        s,
        "#     darkest lines, or as light as #{0:02x}{0:02x}{0:02x}, as a chart's grid, are left out), and so do the borders between regions",
        super::LIGHT_GUIDE
    );
    s += "#     of one fill (a map's districts drawn in one colour), unless most of them are\n";
    let _ = writeln!(
        s,
        "#     under {:.1} mm across, which their borders would mostly cover (one texture then);",
        super::min_region_mm(outline_style(profile).width_mm)
    );
    s += "#   - each filled colour becomes one of the textures below, largest area first,\n";
    s += "#     so that colours whose regions touch (closer than 3.2 mm) never share one;\n";
    s += "#     at most five textures; a colour that would need a sixth keeps only its outline;\n";
    s += "#   - filled circles up to 8 mm and compact marks up to 5 mm, markers and arrowheads\n";
    s += "#     (a small shape of a line's colour where the line ends) become dots;\n";
    s += "#   - text becomes braille where it fits on the page without running into other braille\n";
    s += "#     (moved a little, or pulled back onto the page when it runs off its side), else a\n";
    s += "#     two-letter key code where that fits (note T0326 gives the key);\n";
    s += "#   - page backgrounds (and a chart's very light plot panel), white or transparent fills, hidden, clipped- or masked-away and\n";
    s += "#     off-page elements, and images are left out (white fills are regions\n";
    s += "#     when they are all that a coloured background carries).\n";
    s += "# A style sheet selects by id, class, layer, fill and stroke only; for braille and\n";
    s += "# dots annotate the elements (data-tactile=\"braille()\", data-tactile=\"dot()\").\n";
    s += "#\n";
    s += "# Textures (wavelengths 3 mm apart, angles among 0, 45, 90 and 135 degrees):\n";
    for (k, g) in tex.iter().enumerate() {
        let _ = writeln!(s, "#   {}: {}", k + 1, grating(g));
    }
    s += "\nversion = 1\n";
    let Some((d, plan)) = input else {
        s += "\n# Examples: give a fill colour a texture, make a stroke colour vibrate.\n";
        s += "#\n# [[rule]]\n# fill = \"#e41a1c\"\n";
        let _ = writeln!(s, "# tactile = \"{}\"", grating(&tex[0]));
        s += "#\n# [[rule]]\n# stroke = \"#000000\"\n";
        let _ = writeln!(s, "# tactile = \"{}\"", vibrate(&outline_style(profile)));
        s += "#\n# [[rule]]\n# fill = \"#ffffff\"\n# tactile = \"none\"\n";
        return s;
    };
    // Fills whose regions are stroked, by stroke colour, and whether the
    // stroke vibrates (not where the region abuts another): the first seen decides.
    let mut stroked_fills: Vec<(usize, [u8; 3], bool)> = Vec::new();
    for (dec, e) in plan.decisions.iter().zip(&d.elements) {
        if let (Some(k), Shape::Path(_), Some(c)) = (dec.region, &e.shape, e.paint.stroke)
            && e.paint.stroked
            && !stroked_fills.iter().any(|&(kk, cc, _)| kk == k && cc[..] == c[..3])
        {
            stroked_fills.push((k, [c[0], c[1], c[2]], dec.outline));
        }
    }
    // Fills whose unstroked regions were given an outline (they share borders
    // with regions of their own fill).
    let mut outlined = vec![false; plan.fills.len()];
    for (dec, e) in plan.decisions.iter().zip(&d.elements) {
        if let Some(k) = dec.region.filter(|&k| k < outlined.len() && dec.outline && !e.paint.stroked) {
            outlined[k] = true;
        }
    }
    let line = vibrate(&plan.outline);
    for (k, f) in plan.fills.iter().enumerate() {
        let what = match f.texture {
            Some(t) if outlined[k] => format!("{line}; {}", grating(&tex[t])),
            Some(t) => grating(&tex[t]),
            None => line.clone(),
        };
        let about = format!(
            "{} region(s), {:.0} mm², first #{}{}",
            f.regions,
            f.area_mm2,
            f.first,
            if f.texture.is_none() { "; outline only: a sixth texture would be needed" } else { "" }
        );
        let Some(c) = f.fill else {
            let _ = writeln!(s, "\n# A gradient or pattern fill ({about}) became {what}; a sheet cannot select it.");
            continue;
        };
        let _ = writeln!(s, "\n# {about}\n[[rule]]\nfill = \"{}\"\ntactile = \"{what}\"", fill_name(Some(c)));
        for &(_, sc, vibrates) in stroked_fills.iter().filter(|(kk, _, _)| *kk == k) {
            let both = if f.texture.is_some() && vibrates {
                format!("vibrate(width: {}mm); {what}", plan.outline.width_mm)
            } else {
                what.clone()
            };
            let _ = writeln!(
                s,
                "\n[[rule]]\nfill = \"{}\"\nstroke = \"{}\"\ntactile = \"{both}\"",
                fill_name(Some(c)),
                fill_name(Some(sc))
            );
        }
    }
    for st in &plan.strokes {
        match st {
            Some(c) => {
                let _ = writeln!(s, "\n[[rule]]\nstroke = \"{}\"\ntactile = \"{line}\"", fill_name(Some(*c)));
            }
            None => {
                let _ = writeln!(
                    s,
                    "\n# Lines stroked with a gradient or pattern vibrate too; a sheet cannot select them."
                );
            }
        }
    }
    for c in &plan.faint {
        let _ = writeln!(
            s,
            "\n# Faint grey lines ({}, a chart's grid) were left out; to feel them, weaker:\n# [[rule]]\n# stroke = \"{}\"\n# tactile = \"vibrate(amplitude: 0.5)\"",
            fill_name(Some(*c)),
            fill_name(Some(*c))
        );
    }
    s
}
