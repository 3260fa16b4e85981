//! The report's plot: RMS error against run time (compile + play of the
//! trace) on log–log axes, one line per kernel, each point labelled with its
//! setting, the default setting ringed, and a legend beside the chart.
//! When the rows measure an edge position error (distance layers), a second
//! panel below draws it (the larger of the error at and away from corners,
//! mm) against the same run time.
//! Point labels keep clear of every point and of each other (a label with
//! no free spot is left out), and the legend's text is wrapped to its panel.
//! Drawn with `plotters` into an RGB buffer and encoded as PNG; the text
//! is DejaVu Sans, bundled in `assets/fonts/` (its licence is there), so the
//! plot looks the same on every machine and needs no system font.

use std::sync::OnceLock;

use anyhow::{Result, anyhow};
use plotters::coord::Shift;
use plotters::coord::combinators::WithKeyPoints;
use plotters::prelude::*;
use plotters::style::FontStyle;

use super::Row;

/// Plot size in pixels.
pub const W: u32 = 1000;
/// Plot height in pixels.
pub const H: u32 = 640;
/// Width of the legend panel on the right.
const LEGEND_W: u32 = 230;
/// The font family name the bundled font is registered under.
const FAMILY: &str = "taxel-sans";
static FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// Colour per kernel, fixed so that plots of different scenes compare.
pub fn colour(kernel: &str) -> RGBColor {
    match kernel {
        "vibration" => RGBColor(200, 60, 40),
        "grating" => RGBColor(40, 110, 200),
        "dots" => RGBColor(30, 150, 70),
        "all" => RGBColor(60, 60, 60),
        "strokes" => RGBColor(170, 90, 20),
        _ => RGBColor(150, 90, 180),
    }
}

fn register_font() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| plotters::style::register_font(FAMILY, FontStyle::Normal, FONT).is_ok());
    if ok { Ok(()) } else { Err(anyhow!("the bundled plot font cannot be read")) }
}

/// Draws the plot as PNG bytes; `title` goes on top.
pub fn draw(rows: &[Row], title: &str) -> Result<Vec<u8>> {
    Ok(layout(rows, title)?.0)
}

/// What [`draw`] drew where, in the picture's pixels: each panel's plotting
/// area, the point labels' boxes, and the legend's text boxes.
#[derive(Debug, Default)]
struct Drawn {
    areas: Vec<Boxed>,
    labels: Vec<Boxed>,
    legend: Vec<Boxed>,
}

/// The plot as PNG bytes, and where its labels went.
fn layout(rows: &[Row], title: &str) -> Result<(Vec<u8>, Drawn)> {
    register_font()?;
    let mut drawn = Drawn::default();
    let edges = rows.iter().any(|r| edge_mm(r).is_some());
    let height = if edges { 2 * H } else { H };
    let mut rgb = vec![0u8; (W * height * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (W, height)).into_drawing_area();
        let fail = |e: DrawingAreaErrorKind<_>| anyhow!("cannot draw the plot: {e}");
        let (top, bottom) = root.split_vertically(H);
        let error_unit = rows.first().map_or("", |r| r.error_unit.as_str());
        chart(&top, rows, title, &|r| Some(r.rms_error), &format!("RMS error ({error_unit}, log scale)"), &mut drawn)
            .map_err(fail)?;
        if edges {
            let title = format!("{title}: edge position error");
            let y_desc = "edge position error (mm, at or away from corners, log scale)";
            chart(&bottom, rows, &title, &edge_mm, y_desc, &mut drawn).map_err(fail)?;
        }
        root.present().map_err(fail)?;
    }
    Ok((crate::io::png::encode(W, height, taxel_textform::png::ColorType::Rgb, &rgb)?, drawn))
}

/// The larger of a row's edge position errors at and away from corners, mm.
fn edge_mm(r: &Row) -> Option<f64> {
    super::edge::max_opt(r.edge_error_mm, r.corner_edge_error_mm)
}

type DrawResult<T> = Result<T, DrawingAreaErrorKind<<BitMapBackend<'static> as DrawingBackend>::ErrorType>>;

/// A rectangle in pixels, for keeping labels apart.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Boxed {
    x0: i32,
    y0: i32,
    x1: i32,
    y1: i32,
}

/// Pixels kept clear round a label, so that two labels never touch.
const LABEL_GAP: i32 = 3;

impl Boxed {
    fn overlaps(&self, o: &Boxed) -> bool {
        self.x0 < o.x1 && o.x0 < self.x1 && self.y0 < o.y1 && o.y0 < self.y1
    }

    /// The box grown by `by` pixels on every side.
    fn grown(&self, by: i32) -> Boxed {
        Boxed { x0: self.x0 - by, y0: self.y0 - by, x1: self.x1 + by, y1: self.y1 + by }
    }

    fn within(&self, o: &Boxed) -> bool {
        self.x0 >= o.x0 && self.y0 >= o.y0 && self.x1 <= o.x1 && self.y1 <= o.y1
    }
}

fn chart(
    root: &DrawingArea<BitMapBackend<'_>, Shift>,
    rows: &[Row],
    title: &str,
    value: &dyn Fn(&Row) -> Option<f64>,
    y_desc: &str,
    drawn: &mut Drawn,
) -> DrawResult<()> {
    root.fill(&WHITE)?;
    // The rows that measured this value, with it as their error.
    let rows: Vec<Row> = rows.iter().filter_map(|r| value(r).map(|v| Row { rms_error: v, ..r.clone() })).collect();
    let rows = &rows[..];
    let (left, right) = root.split_horizontally(W - LEGEND_W);
    let pos = |v: f64| v.is_finite() && v > 0.0;
    let (x_lo, x_hi) = decades(rows.iter().map(|r| r.run_ms).filter(|&v| pos(v)));
    let (y_lo, y_hi) = decades(rows.iter().map(|r| r.rms_error).filter(|&v| pos(v)));
    // An error of exactly zero (or a time too small to show) sits on the lower axis.
    let clamp = |v: f64, lo: f64| if pos(v) { v.max(lo) } else { lo };
    let setting_unit = rows.first().map_or("", |r| r.unit.as_str());
    let mut chart = ChartBuilder::on(&left)
        .caption(title, (FAMILY, 22).into_font())
        .margin(16)
        .x_label_area_size(52)
        .y_label_area_size(78)
        .build_cartesian_2d(log_axis(x_lo, x_hi), log_axis(y_lo, y_hi))?;
    chart
        .configure_mesh()
        .x_desc("run time: compile + play the trace (ms, log scale)")
        .y_desc(y_desc)
        .label_style((FAMILY, 15))
        .axis_desc_style((FAMILY, 16))
        .x_label_formatter(&|v| number(*v))
        .y_label_formatter(&|v| number(*v))
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(205, 205, 205))
        .draw()?;

    let mut kernels: Vec<&str> = Vec::new();
    for r in rows {
        if !kernels.contains(&r.kernel.as_str()) {
            kernels.push(&r.kernel);
        }
    }
    // Every point first, so that the labels placed next can keep off them all.
    let mut taken: Vec<Boxed> = Vec::new();
    let mut placed: Vec<(String, (i32, i32), RGBColor)> = Vec::new();
    for k in &kernels {
        let c = colour(k);
        let pts: Vec<(f64, f64, &Row)> = rows
            .iter()
            .filter(|r| r.kernel == *k)
            .map(|r| (clamp(r.run_ms, x_lo), clamp(r.rms_error, y_lo), r))
            .collect();
        chart.draw_series(LineSeries::new(pts.iter().map(|p| (p.0, p.1)), c.stroke_width(2)))?;
        chart.draw_series(pts.iter().map(|p| Circle::new((p.0, p.1), 4, c.filled())))?;
        for p in &pts {
            let (px, py) = chart.backend_coord(&(p.0, p.1));
            // The default's ring is part of its point.
            let r = if p.2.default { 12 } else { 5 };
            taken.push(Boxed { x0: px - r, y0: py - r, x1: px + r, y1: py + r });
            if p.2.default {
                chart.draw_series(std::iter::once(Circle::new((p.0, p.1), 10, BLACK.stroke_width(2))))?;
            }
        }
    }
    let label_font: TextStyle = (FAMILY, 14).into_font().into();
    // `backend_coord` and the plotting area are in the whole picture's
    // pixels; `left` draws from its own top left corner.
    let area = chart.plotting_area().get_pixel_range();
    let area = Boxed { x0: area.0.start, y0: area.1.start, x1: area.0.end, y1: area.1.end };
    drawn.areas.push(area);
    let base = left.get_base_pixel();
    for k in &kernels {
        let c = colour(k);
        for r in rows.iter().filter(|r| r.kernel == *k) {
            let text = number(r.setting);
            let (w, h) = left.estimate_text_size(&text, &label_font)?;
            let at = chart.backend_coord(&(clamp(r.run_ms, x_lo), clamp(r.rms_error, y_lo)));
            if let Some(spot) = place(at, (w as i32, h as i32), &taken, area) {
                taken.push(spot.grown(LABEL_GAP));
                drawn.labels.push(spot);
                placed.push((text, (spot.x0 - base.0, spot.y0 - base.1), c));
            }
        }
    }
    for (text, at, c) in placed {
        // A white ground keeps a label readable where a line passes under it.
        let (w, h) = left.estimate_text_size(&text, &label_font)?;
        let ground = [(at.0 - 1, at.1), (at.0 + w as i32 + 1, at.1 + h as i32)];
        left.draw(&Rectangle::new(ground, WHITE.mix(0.85).filled()))?;
        left.draw(&Text::new(text, at, label_font.color(&c)))?;
    }
    legend(&right, &kernels, setting_unit, drawn)
}

/// Where a label of size `(w, h)` for the point at `at` goes: the first of
/// eight spots around the point (right, left, above, below, then the
/// corners, each at two distances) that stays inside `area` and clear of
/// every box in `taken`; `None` when all are taken (the label is left out
/// rather than drawn over another).
fn place(at: (i32, i32), (w, h): (i32, i32), taken: &[Boxed], area: Boxed) -> Option<Boxed> {
    let (x, y) = at;
    let mut spots = Vec::new();
    for gap in [8, 20] {
        spots.extend([
            (x + gap, y - h / 2),
            (x - gap - w, y - h / 2),
            (x - w / 2, y - gap - h),
            (x - w / 2, y + gap),
            (x + gap, y - gap - h),
            (x + gap, y + gap),
            (x - gap - w, y - gap - h),
            (x - gap - w, y + gap),
        ]);
    }
    spots
        .into_iter()
        .map(|(x0, y0)| Boxed { x0, y0, x1: x0 + w, y1: y0 + h })
        .find(|b| b.within(&area) && taken.iter().all(|t| !t.overlaps(b)))
}

/// The legend panel: one line per kernel, the default's ring, what the
/// point labels are, its text wrapped to the panel.
fn legend(
    area: &DrawingArea<BitMapBackend<'_>, Shift>,
    kernels: &[&str],
    setting_unit: &str,
    drawn: &mut Drawn,
) -> DrawResult<()> {
    let font: TextStyle = (FAMILY, 16).into_font().into();
    let small: TextStyle = (FAMILY, 14).into_font().into();
    let base = area.get_base_pixel();
    let (x, mut y) = (12, 70);
    let mut text = |s: &str, at: (i32, i32), f: &TextStyle<'_>| -> DrawResult<()> {
        let (w, h) = area.estimate_text_size(s, f)?;
        let (x0, y0) = (base.0 + at.0, base.1 + at.1);
        drawn.legend.push(Boxed { x0, y0, x1: x0 + w as i32, y1: y0 + h as i32 });
        area.draw(&Text::new(s.to_string(), at, f.clone()))
    };
    text("Kernels", (x, y - 30), &font)?;
    for k in kernels {
        let c = colour(k);
        area.draw(&PathElement::new(vec![(x, y), (x + 34, y)], c.stroke_width(3)))?;
        area.draw(&Circle::new((x + 17, y), 4, c.filled()))?;
        text(k, (x + 46, y - 9), &font)?;
        y += 28;
    }
    y += 12;
    area.draw(&Circle::new((x + 17, y), 4, BLACK.filled()))?;
    area.draw(&Circle::new((x + 17, y), 10, BLACK.stroke_width(2)))?;
    text("default setting", (x + 46, y - 9), &font)?;
    y += 40;
    let width = LEGEND_W as i32 - 2 * x;
    let paragraphs =
        [format!("Point labels: the setting ({setting_unit})"), "Lower left is better: fast and accurate.".into()];
    for p in &paragraphs {
        let measure = |s: &str| area.estimate_text_size(s, &small).map_or(0, |(w, _)| w as usize);
        for line in taxel_compiler::style::wrap(p, width as usize, &measure) {
            text(&line, (x, y), &small)?;
            y += 18;
        }
        y += 12;
    }
    Ok(())
}

/// Whole decades around the values (at least one decade wide), as the axis range.
fn decades(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
    if !(lo.is_finite() && hi.is_finite()) {
        return (1.0, 10.0);
    }
    let (a, b) = (lo.log10().floor(), hi.log10().ceil());
    let b = b.max(a + 1.0);
    (10f64.powf(a), 10f64.powf(b))
}

/// A log-scale axis over `lo..hi` (decades, from [`decades`]) with its
/// own ticks: a label at every decade, and at 2, 3 and 5 times the lower
/// one where the axis spans a single decade; light grid lines at the other
/// whole multiples. plotters' own ticks for one decade gave its top twice,
/// as the last light tick and the next bold one ("100" drawn over itself).
fn log_axis(lo: f64, hi: f64) -> WithKeyPoints<LogCoord<f64>> {
    let (bold, light) = log_ticks(lo, hi);
    (lo..hi).log_scale().with_key_points(bold).with_light_points(light)
}

/// The labelled and the light ticks of [`log_axis`], each in increasing
/// order, none twice, none in both, all within `lo..=hi`.
fn log_ticks(lo: f64, hi: f64) -> (Vec<f64>, Vec<f64>) {
    let (a, b) = (lo.log10().round(), hi.log10().round());
    // (Bounded: a plot's decades come from finite, positive values.)
    let (a, b) = (a.clamp(-300.0, 300.0) as i32, b.clamp(-300.0, 300.0) as i32);
    let single = b - a <= 1;
    let (mut bold, mut light) = (Vec::new(), Vec::new());
    for k in a..=b {
        let decade = 10f64.powi(k);
        for m in 1..=9 {
            let v = f64::from(m) * decade;
            if v < lo * (1.0 - 1e-9) || v > hi * (1.0 + 1e-9) {
                continue;
            }
            if m == 1 || (single && matches!(m, 2 | 3 | 5)) {
                bold.push(v);
            } else {
                light.push(v);
            }
        }
    }
    (bold, light)
}

/// A number as a person writes it on an axis: no trailing zeros, no exponent
/// between 0.001 and 10⁶.
fn number(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if !(1e-3..1e6).contains(&a) {
        return format!("{v:.0e}");
    }
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(kernel: &str, setting: f64, ms: f64, err: f64, default: bool) -> Row {
        Row {
            kernel: kernel.into(),
            setting,
            unit: "px/mm".into(),
            default,
            compile_ms: ms,
            bundle_bytes: 0,
            frame_us: 0.0,
            max_error: err,
            rms_error: err,
            step_rms_error: None,
            error_unit: "10-bit steps".into(),
            far_error: None,
            far_rms_error: None,
            corner_error: None,
            edge_error_mm: None,
            corner_edge_error_mm: None,
            lattice_mm: None,
            fine_detail: None,
            unfelt: None,
            frames: 1,
            run_ms: ms,
            on_front: true,
        }
    }

    #[test]
    fn plot_is_a_png_with_coloured_lines() {
        let rows = vec![row("grating", 2.0, 1.0, 30.0, false), row("grating", 8.0, 10.0, 3.0, true)];
        let png = draw(&rows, "test.svg on stress2").expect("plot");
        let img = taxel_textform::png::read(&png).expect("decodes");
        assert_eq!((img.width, img.height), (W, H));
        let rgb = img.to_rgb8();
        let px = |x: u32, y: u32| rgb[(y * W + x) as usize];
        // Some pixel carries the grating's blue, and the legend (right of the chart) has text.
        assert!(rgb.contains(&[40, 110, 200]));
        let legend_dark = (W - LEGEND_W..W).flat_map(|x| (0..H).map(move |y| (x, y)));
        assert!(legend_dark.filter(|&(x, y)| px(x, y)[0] < 100).count() > 100);
    }

    #[test]
    fn edge_errors_get_a_second_panel() {
        let mut rows = vec![row("grating", 2.0, 1.0, 30.0, false), row("grating", 8.0, 10.0, 3.0, true)];
        rows[0].edge_error_mm = Some(0.5);
        rows[1].corner_edge_error_mm = Some(0.05);
        let png = draw(&rows, "test.svg on stress2").expect("plot");
        let img = taxel_textform::png::read(&png).expect("decodes");
        assert_eq!((img.width, img.height), (W, 2 * H));
        let rgb = img.to_rgb8();
        // The lower panel has the grating's line too.
        let lower = (0..W - LEGEND_W).flat_map(|x| (H..2 * H).map(move |y| (x, y)));
        assert!(lower.filter(|&(x, y)| rgb[(y * W + x) as usize] == [40, 110, 200]).count() > 20);
    }

    /// Issue 46: on a ladder as crowded as `tala-map`'s (four kernels of
    /// four rungs, the coarse rungs within a few ms of each other), every
    /// point's label is drawn, whole, inside its panel, clear of every other
    /// label; and the legend's text stays inside the picture.
    #[test]
    fn every_label_is_drawn_whole_and_none_overlaps() {
        let unit = "mm lattice pitch of the distance layers (at most half a vibrating band's width)";
        let mut rows = Vec::new();
        for (k, ms, err, edge) in [
            ("vibration", 25.0, 0.09, 0.0033),
            ("grating", 36.0, 0.16, 0.006),
            ("dots", 10.5, 0.035, f64::NAN),
            ("all", 58.0, 0.18, 0.006),
        ] {
            for (setting, dms, derr, dedge) in
                [(2.0, -1.5, 10.0, 11.0), (1.0, 1.0, 10.0, 11.0), (0.5, 0.0, 1.0, 1.0), (0.25, 12.0, 5.0, 7.0)]
            {
                let mut r = row(k, setting, ms + dms, err * derr, setting == 0.5);
                r.unit = unit.into();
                r.edge_error_mm = (!edge.is_nan()).then_some(edge * dedge);
                rows.push(r);
            }
        }
        let (png, drawn) = layout(&rows, "tala-map.svg on stress2").expect("plot");
        let img = taxel_textform::png::read(&png).expect("decodes");
        assert_eq!((img.width, img.height), (W, 2 * H));
        // 16 points above, 12 below (the dots have no edge).
        assert_eq!(drawn.labels.len(), 16 + 12, "{drawn:?}");
        assert_eq!(drawn.areas.len(), 2);
        for (i, a) in drawn.labels.iter().enumerate() {
            assert!(drawn.areas.iter().any(|area| a.within(area)), "label {a:?} outside the panels {:?}", drawn.areas);
            for b in &drawn.labels[i + 1..] {
                assert!(!a.grown(LABEL_GAP).overlaps(b), "labels {a:?} and {b:?} touch");
            }
        }
        let picture = Boxed { x0: (W - LEGEND_W) as i32, y0: 0, x1: W as i32, y1: (2 * H) as i32 };
        assert!(drawn.legend.len() > 10, "{:?}", drawn.legend);
        for t in &drawn.legend {
            assert!(t.within(&picture), "legend text {t:?} outside its panel");
        }
    }

    /// Each panel's label is drawn where it was placed: the lower panel's
    /// too, whose area starts `H` pixels down the picture.
    #[test]
    fn labels_are_drawn_in_their_boxes_in_both_panels() {
        let mut r = row("grating", 0.5, 20.0, 0.3, false);
        r.edge_error_mm = Some(0.02);
        let (png, drawn) = layout(&[r], "one point").expect("plot");
        let rgb = taxel_textform::png::read(&png).expect("decodes").to_rgb8();
        assert_eq!(drawn.labels.len(), 2, "{drawn:?}");
        assert!(drawn.labels[1].y0 >= H as i32, "the lower panel's label: {drawn:?}");
        for a in &drawn.labels {
            // A lone point has no line: the only dark pixels in the box are its text's.
            let dark = (a.y0..a.y1)
                .flat_map(|y| (a.x0..a.x1).map(move |x| (x, y)))
                .filter(|&(x, y)| rgb[(y as u32 * W + x as u32) as usize].iter().min().is_some_and(|&v| v < 150))
                .count();
            assert!(dark > 5, "no text in the label at {a:?}");
        }
    }

    #[test]
    fn decades_cover_the_values() {
        assert_eq!(decades([0.5, 30.0].into_iter()), (0.1, 100.0));
        assert_eq!(decades([3.0].into_iter()), (1.0, 10.0));
        assert_eq!(decades(std::iter::empty()), (1.0, 10.0));
    }

    /// Every labelled tick once, in order, at every decade; on a single
    /// decade also at 2, 3 and 5 times its foot; the light ticks apart from
    /// them; all within the axis. (plotters' own ticks on 10..100 had 100
    /// twice.)
    #[test]
    fn log_axes_label_each_tick_once() {
        use plotters::coord::ranged1d::{BoldPoints, LightPoints};
        for (lo, hi) in [(10.0, 100.0), (1.0, 100.0), (0.001, 10.0), (0.1, 1.0), (1.0, 1e6)] {
            let (bold, light) = log_ticks(lo, hi);
            let axis = log_axis(lo, hi);
            // What plotters labels, and draws its bold lines at; the light lines.
            assert_eq!(axis.key_points(BoldPoints(100)), bold, "{lo}..{hi}");
            assert_eq!(axis.key_points(LightPoints::new(100, 100)), light, "{lo}..{hi}");
            assert!(
                bold.windows(2).all(|w| w[0] < w[1]) && light.windows(2).all(|w| w[0] < w[1]),
                "{bold:?} {light:?}"
            );
            assert!(light.iter().all(|l| !bold.contains(l)), "{bold:?} {light:?}");
            assert!(bold.iter().chain(&light).all(|&v| v >= lo * 0.999_999 && v <= hi * 1.000_001), "{lo}..{hi}");
            let decades = (hi / lo).log10().round() as usize;
            let labels: Vec<String> = bold.iter().map(|&v| number(v)).collect();
            let mut once = labels.clone();
            once.dedup();
            assert_eq!(once, labels, "{lo}..{hi}");
            if decades == 1 {
                assert_eq!(labels, [lo, 2.0 * lo, 3.0 * lo, 5.0 * lo, hi].map(number), "{lo}..{hi}");
                assert_eq!(light.len(), 5, "{light:?}");
            } else {
                assert_eq!(bold.len(), decades + 1, "{labels:?}");
                assert_eq!(light.len(), 8 * decades, "{light:?}");
            }
        }
    }

    #[test]
    fn axis_numbers_read_like_a_person_wrote_them() {
        assert_eq!(number(16.0), "16");
        assert_eq!(number(0.5), "0.5");
        assert_eq!(number(1000.0), "1000");
        assert_eq!(number(0.0001), "1e-4");
    }

    #[test]
    fn labels_keep_clear_of_each_other_and_of_points() {
        let area = Boxed { x0: 0, y0: 0, x1: 500, y1: 500 };
        let point = Boxed { x0: 95, y0: 95, x1: 105, y1: 105 };
        let first = place((100, 100), (20, 12), &[point], area).expect("room");
        assert_eq!(first, Boxed { x0: 108, y0: 94, x1: 128, y1: 106 }, "right of the point first");
        let second = place((100, 100), (20, 12), &[point, first], area).expect("room");
        assert_eq!(second, Boxed { x0: 72, y0: 94, x1: 92, y1: 106 }, "then left");
        // A point in a corner of the area cannot put its label outside.
        let corner = place((2, 2), (20, 12), &[], area).expect("room");
        assert!(corner.x0 >= 0 && corner.y0 >= 0);
        // Surrounded on every side: no label rather than an overlap.
        assert_eq!(place((100, 100), (20, 12), &[Boxed { x0: 0, y0: 0, x1: 500, y1: 500 }], area), None);
    }
}
