//! Line charts (SVG, plotters) and CSV files of series.

use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use std::io::Write;
use std::path::Path;

/// One named curve.
pub(crate) struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
}

/// A chart: title, axis labels with units, curves, and whether to draw markers.
pub(crate) struct Chart<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub series: Vec<Series>,
    pub markers: bool,
    /// Whether the first series is the reference the others are measured against: drawn
    /// last, black, dashed and wider, so that no curve hides it.
    pub reference_first: bool,
}

/// Okabe & Ito's palette (2008), told apart with the common colour-vision deficiencies; the
/// ninth series on is dashed, so sixteen stay distinct.
const COLOURS: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(230, 159, 0),
    RGBColor(0, 158, 115),
    RGBColor(213, 94, 0),
    RGBColor(86, 180, 233),
    RGBColor(204, 121, 167),
    RGBColor(0, 0, 0),
    RGBColor(240, 228, 66),
];

/// The colour and whether the line of series `i` is dashed.
fn style(i: usize) -> (RGBColor, bool) {
    (COLOURS[i % COLOURS.len()], (i / COLOURS.len()) % 2 == 1)
}

/// Tick labels of a linear axis over `lo..hi` with the fewest digits that tell its ticks
/// apart (plotters puts about ten, at 1, 2 or 5 times a power of ten): "1400", "0.05",
/// "2.5e-6"; never "-0".
fn tick_label(lo: f64, hi: f64) -> impl Fn(&f64) -> String {
    let step = ((hi - lo).abs() / 10.0).max(f64::MIN_POSITIVE);
    let magnitude = lo.abs().max(hi.abs()).max(f64::MIN_POSITIVE);
    let step_exponent = step.log10().floor();
    move |v: &f64| {
        if v.abs() < 1e-6 * step {
            return "0".into();
        }
        if (1e-3..1e5).contains(&magnitude) {
            let decimals = (-step_exponent).clamp(0.0, 6.0) as usize;
            format!("{v:.decimals$}")
        } else {
            let digits = (magnitude.log10().floor() - step_exponent).clamp(0.0, 5.0) as usize;
            format!("{v:.digits$e}")
        }
    }
}

/// A tick label of a logarithmic axis, whose ticks are powers of ten (and their multiples)
/// computed in floating point: printed as they come they read "9.999999999e-5". One significant
/// digit, plain from 0.001 to 1000 ("0.01", "1", "200"), else with an exponent ("1e-7"); only
/// the multiples 1, 2 and 5 of a decade are labelled (the others keep their grid line): where
/// a decade fills its last tenth of the axis, 0.006 to 0.01 had run into one another.
fn decade_label(v: &f64) -> String {
    let rounded: f64 = format!("{v:.0e}").parse().unwrap_or(*v);
    let mantissa = rounded.abs() / 10f64.powf(rounded.abs().log10().floor());
    if ![1.0, 2.0, 5.0].iter().any(|m| (mantissa - m).abs() < 1e-6) {
        return String::new();
    }
    if (1e-3..=1e3).contains(&rounded.abs()) {
        format!("{rounded}")
    } else {
        format!("{rounded:.0e}")
    }
}

fn bounds(values: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let lo = values.clone().fold(f64::INFINITY, f64::min);
    let hi = values.fold(f64::NEG_INFINITY, f64::max);
    let pad = if hi > lo { 0.04 * (hi - lo) } else { 1e-12f64.max(lo.abs() * 0.1) };
    (lo - pad, hi + pad)
}

/// Removes the figure `stem` ([`Chart::write`]'s `stem.svg` and `stem.csv`) from `dir`, if
/// there: a command clears the figures it owns in a reused folder before it writes, so that
/// none of an earlier run's stays beside its own.
pub(crate) fn remove_figure(dir: &Path, stem: &str) -> anyhow::Result<()> {
    for ext in ["svg", "csv"] {
        crate::files::remove_output(&dir.join(format!("{stem}.{ext}")))?;
    }
    Ok(())
}

impl Chart<'_> {
    /// Writes `stem.svg` and `stem.csv` (long format: series, x, y) into `dir`.
    pub(crate) fn write(&self, dir: &Path, stem: &str) -> anyhow::Result<()> {
        self.write_scaled(dir, stem, false, false)
    }

    /// [`Chart::write`] on logarithmic axes (every value must be positive): a work-precision
    /// diagram.
    pub(crate) fn write_log_log(&self, dir: &Path, stem: &str) -> anyhow::Result<()> {
        self.write_scaled(dir, stem, true, true)
    }

    /// [`Chart::write`] with a logarithmic x axis (every x must be positive): a history whose
    /// events crowd its start, as an energy ledger's.
    pub(crate) fn write_log_x(&self, dir: &Path, stem: &str) -> anyhow::Result<()> {
        self.write_scaled(dir, stem, true, false)
    }

    fn write_scaled(&self, dir: &Path, stem: &str, log_x: bool, log_y: bool) -> anyhow::Result<()> {
        let svg = dir.join(format!("{stem}.svg"));
        let mut text = String::new();
        let all = self.series.iter().flat_map(|s| s.points.iter());
        anyhow::ensure!(
            all.clone().all(|(x, y)| x.is_finite() && y.is_finite()),
            "figure {stem}: a value is not finite"
        );
        anyhow::ensure!(
            !log_x || all.clone().all(|(x, y)| *x > 0.0 && (!log_y || *y > 0.0)),
            "figure {stem}: a value is not positive on a logarithmic axis"
        );
        let (x0, x1) = bounds(all.clone().map(|p| p.0));
        let (y0, y1) = bounds(all.clone().map(|p| p.1));
        // On a logarithmic axis the margin is a factor.
        let (lx0, lx1) = log_bounds(all.clone().map(|p| p.0));
        let (ly0, ly1) = log_bounds(all.map(|p| p.1));
        {
            // The legend has a column of its own right of the axes, as wide as its longest
            // label: no curve passes under it.
            let longest = self.series.iter().map(|s| s.label.chars().count()).max().unwrap_or(0);
            let legend_width = (LEGEND_SAMPLE + 7 * longest as u32 + 24).clamp(140, 420);
            let root = SVGBackend::with_string(&mut text, (PLOT_WIDTH + legend_width, HEIGHT))
                .into_drawing_area();
            root.fill(&WHITE).map_err(|e| anyhow::anyhow!("{e}"))?;
            let (plot, legend) = root.split_horizontally(PLOT_WIDTH);
            let mut builder = ChartBuilder::on(&plot);
            builder
                .caption(self.title, ("sans-serif", 22))
                .margin(18)
                .x_label_area_size(48)
                .y_label_area_size(80);
            if log_x && log_y {
                let mut chart = builder
                    .build_cartesian_2d((lx0..lx1).log_scale(), (ly0..ly1).log_scale())
                    .map_err(|e| anyhow::anyhow!("{e}"))?;
                self.draw(&mut chart, &decade_label, &decade_label)?;
            } else if log_x {
                let mut chart = builder
                    .build_cartesian_2d((lx0..lx1).log_scale(), y0..y1)
                    .map_err(|e| anyhow::anyhow!("{e}"))?;
                self.draw(&mut chart, &decade_label, &tick_label(y0, y1))?;
            } else {
                let mut chart = builder
                    .build_cartesian_2d(x0..x1, y0..y1)
                    .map_err(|e| anyhow::anyhow!("{e}"))?;
                self.draw(&mut chart, &tick_label(x0, x1), &tick_label(y0, y1))?;
            }
            self.draw_legend(&legend)?;
            root.present().map_err(|e| anyhow::anyhow!("{e}"))?;
        }
        // Drawn into memory, then written whole (a link at the name is replaced, not
        // followed).
        crate::files::write_atomic(&svg, text.as_bytes())?;
        let csv = dir.join(format!("{stem}.csv"));
        let mut f = crate::files::create(&csv)?;
        writeln!(f, "series,{},{}", column_name(self.x_label), column_name(self.y_label))?;
        for s in &self.series {
            for (x, y) in &s.points {
                writeln!(f, "\"{}\",{x:.9e},{y:.9e}", s.label)?;
            }
        }
        f.finish()
    }
}

impl Chart<'_> {
    /// The axes with tick labels by `x_tick` and `y_tick`, and the curves (and markers).
    fn draw<'a, X, Y>(
        &self,
        chart: &mut ChartContext<'a, SVGBackend<'a>, Cartesian2d<X, Y>>,
        x_tick: &dyn Fn(&f64) -> String,
        y_tick: &dyn Fn(&f64) -> String,
    ) -> anyhow::Result<()>
    where
        X: Ranged<ValueType = f64> + ValueFormatter<f64>,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        chart
            .configure_mesh()
            .x_label_formatter(x_tick)
            .y_label_formatter(y_tick)
            .x_desc(self.x_label)
            .y_desc(self.y_label)
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 17))
            .draw()
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        // The reference, if any, last: on top of the curves that would hide it.
        let order: Vec<usize> = if self.reference_first {
            (1..self.series.len()).chain(0..1.min(self.series.len())).collect()
        } else {
            (0..self.series.len()).collect()
        };
        for i in order {
            let s = &self.series[i];
            let (colour, dashed, width) = self.style_of(i);
            let line = colour.stroke_width(width);
            let points = s.points.iter().copied();
            if dashed {
                chart.draw_series(DashedLineSeries::new(points, 8, 5, line))
            } else {
                chart.draw_series(LineSeries::new(points, line))
            }
            .map_err(|e| anyhow::anyhow!("{e}"))?;
            if self.markers {
                chart
                    .draw_series(s.points.iter().map(|p| Circle::new(*p, 4, colour.filled())))
                    .map_err(|e| anyhow::anyhow!("{e}"))?;
            }
        }
        Ok(())
    }

    /// Series `i`'s colour, whether dashed, and line width (px).
    fn style_of(&self, i: usize) -> (RGBColor, bool, u32) {
        match (self.reference_first, i) {
            (true, 0) => (RGBColor(0, 0, 0), true, 3),
            (true, _) => {
                let (c, d) = style(i - 1);
                (c, d, 2)
            }
            (false, _) => {
                let (c, d) = style(i);
                (c, d, 2)
            }
        }
    }

    /// The legend in its own column: each series' line (and marker) and its label.
    fn draw_legend(&self, area: &DrawingArea<SVGBackend<'_>, Shift>) -> anyhow::Result<()> {
        let font = ("sans-serif", 15).into_font().color(&BLACK);
        for (i, s) in self.series.iter().enumerate() {
            let (colour, dashed, width) = self.style_of(i);
            let y = LEGEND_TOP + LEGEND_ROW * i as i32;
            let line = colour.stroke_width(width);
            let sample = LEGEND_SAMPLE as i32;
            let ends = [(4, y), (4 + sample, y)];
            if dashed {
                area.draw(&DashedPathElement::new(ends, 8, 5, line))
            } else {
                area.draw(&PathElement::new(ends.to_vec(), line))
            }
            .map_err(|e| anyhow::anyhow!("{e}"))?;
            if self.markers {
                area.draw(&Circle::new((4 + sample / 2, y), 4, colour.filled()))
                    .map_err(|e| anyhow::anyhow!("{e}"))?;
            }
            area.draw(&Text::new(s.label.clone(), (sample + 12, y - 8), font.clone()))
                .map_err(|e| anyhow::anyhow!("{e}"))?;
        }
        Ok(())
    }
}

/// `text` safe inside an HTML element: `&`, `<`, `>` as entities.
pub(crate) fn escape_html(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// The head of every HTML page the commands write, up to `<body>`: one column at most 1100 px
/// wide (a laptop screen shows it without scrolling sideways; a figure fills it, its text at
/// about the page's size), long words broken rather than widening it, a wide table scrolling in
/// its own box. `title` is escaped.
pub(crate) fn page_head(title: &str) -> String {
    let title = escape_html(title);
    format!(
        "<!doctype html><html><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><title>{title}</title>\
         <style>body{{font-family:sans-serif;max-width:1100px;margin:1.5em auto;padding:0 1em;line-height:1.45;overflow-wrap:anywhere}}\
         figure{{margin:2em 0}}img{{width:100%;height:auto;border:1px solid #ccc}}figcaption{{margin-top:.5em}}\
         table{{border-collapse:collapse;display:block;overflow-x:auto}}td,th{{padding:2px 8px;text-align:right;border-bottom:1px solid #ddd}}li{{margin:.3em 0}}</style></head><body>"
    )
}

/// The axes' part of a figure (px); the legend's column comes on its right.
const PLOT_WIDTH: u32 = 820;
/// A figure's height (px).
const HEIGHT: u32 = 560;
/// The legend: the first row's centre below the top, the rows' pitch, a line sample's length
/// (px).
const LEGEND_TOP: i32 = 70;
const LEGEND_ROW: i32 = 22;
pub(crate) const LEGEND_SAMPLE: u32 = 34;

/// Bounds of positive values with a margin of a factor 1.3 either side (1 to 10 when there are
/// none).
fn log_bounds(values: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let lo = values.clone().filter(|v| *v > 0.0).fold(f64::INFINITY, f64::min);
    let hi = values.filter(|v| *v > 0.0).fold(f64::NEG_INFINITY, f64::max);
    if lo.is_finite() && hi.is_finite() {
        (lo / 1.3, hi * 1.3)
    } else {
        (1.0, 10.0)
    }
}

/// An axis label as a CSV column name: ASCII, one field, units kept: "time (µs)" is
/// "time_us", "stress, tension positive (MPa)" is "stress_tension_positive_mpa" (a comma in a
/// name gave the header a field more than its rows), "5 %" is "5_pct".
fn column_name(label: &str) -> String {
    let mut name = label
        .replace('µ', "u")
        .replace('%', "pct")
        .replace([' ', '(', ')', '/', ',', ';', '"'], "_");
    while name.contains("__") {
        name = name.replace("__", "_");
    }
    name.trim_matches('_').to_lowercase()
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_column_name_is_one_csv_field_with_its_unit() {
        use super::column_name;
        assert_eq!(column_name("time (µs)"), "time_us");
        assert_eq!(column_name("stress, tension positive (MPa)"), "stress_tension_positive_mpa");
        assert_eq!(
            column_name("pulse duration, force above 5 % of its peak (µs)"),
            "pulse_duration_force_above_5_pct_of_its_peak_us"
        );
    }

    use super::{decade_label, style, tick_label};

    #[test]
    fn decades_read_plainly_near_one() {
        let labels: Vec<String> = [9.999999999e-5, 0.0009999999999, 0.01, 1.0000000001, 200.0, 1e7]
            .iter()
            .map(decade_label)
            .collect();
        assert_eq!(labels, ["1e-4", "0.001", "0.01", "1", "200", "1e7"]);
        // Between 1, 2 and 5 of a decade the ticks keep their grid line and no label (0.006 to
        // 0.01 had run into one another on the work-precision chart).
        let between: Vec<String> =
            [0.003, 0.0060000000001, 0.008, 0.05].iter().map(decade_label).collect();
        assert_eq!(between, ["", "", "", "0.05"]);
    }

    #[test]
    fn tick_labels_have_the_digits_that_tell_ticks_apart() {
        let f = tick_label(0.0, 1500.0);
        assert_eq!((f(&1400.0), f(&0.0), f(&-1e-13)), ("1400".into(), "0".into(), "0".into()));
        let f = tick_label(-0.02, 0.1);
        assert_eq!(
            (f(&0.05), f(&0.09999999999999998), f(&-0.0)),
            ("0.05".into(), "0.10".into(), "0".into())
        );
        let f = tick_label(0.0, 5e-6);
        assert_eq!(f(&2.5e-6), "2.5e-6");
        let f = tick_label(3.0e5, 3.6e5);
        assert_eq!(f(&3.45e5), "3.45e5");
    }

    #[test]
    fn sixteen_series_have_sixteen_styles() {
        let styles: Vec<_> = (0..16).map(style).collect();
        for (i, a) in styles.iter().enumerate() {
            assert_eq!(styles.iter().filter(|b| *b == a).count(), 1, "series {i}");
        }
    }
}
