//! Line charts (SVG, plotters) and CSV files of series.

use plotters::coord::ranged1d::ValueFormatter;
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
}

const COLOURS: [RGBColor; 9] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(23, 190, 207),
];

fn bounds(values: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let lo = values.clone().fold(f64::INFINITY, f64::min);
    let hi = values.fold(f64::NEG_INFINITY, f64::max);
    let pad = if hi > lo { 0.04 * (hi - lo) } else { 1e-12f64.max(lo.abs() * 0.1) };
    (lo - pad, hi + pad)
}

impl Chart<'_> {
    /// Writes `stem.svg` and `stem.csv` (long format: series, x, y) into `dir`.
    pub(crate) fn write(&self, dir: &Path, stem: &str) -> anyhow::Result<()> {
        self.write_scaled(dir, stem, false, SeriesLabelPosition::MiddleRight)
    }

    /// [`Chart::write`] with the legend at `legend`, where the curves leave room.
    pub(crate) fn write_legend_at(
        &self,
        dir: &Path,
        stem: &str,
        legend: SeriesLabelPosition,
    ) -> anyhow::Result<()> {
        self.write_scaled(dir, stem, false, legend)
    }

    /// [`Chart::write`] on logarithmic axes (every value must be positive): a work-precision
    /// diagram.
    pub(crate) fn write_log_log(&self, dir: &Path, stem: &str) -> anyhow::Result<()> {
        self.write_scaled(dir, stem, true, SeriesLabelPosition::MiddleRight)
    }

    fn write_scaled(
        &self,
        dir: &Path,
        stem: &str,
        log: bool,
        legend: SeriesLabelPosition,
    ) -> anyhow::Result<()> {
        let svg = dir.join(format!("{stem}.svg"));
        // The backend writes the file itself: the check that it is no input comes first.
        crate::files::refuse_input(&svg)?;
        let all = self.series.iter().flat_map(|s| s.points.iter());
        anyhow::ensure!(
            all.clone().all(|(x, y)| x.is_finite() && y.is_finite()),
            "figure {stem}: a value is not finite"
        );
        anyhow::ensure!(
            !log || all.clone().all(|(x, y)| *x > 0.0 && *y > 0.0),
            "figure {stem}: a value is not positive on a logarithmic axis"
        );
        let (x0, x1) = bounds(all.clone().map(|p| p.0));
        let (y0, y1) = bounds(all.clone().map(|p| p.1));
        // On a logarithmic axis the margin is a factor.
        let (lx0, lx1) = log_bounds(all.clone().map(|p| p.0));
        let (ly0, ly1) = log_bounds(all.map(|p| p.1));
        {
            let root = SVGBackend::new(&svg, (900, 560)).into_drawing_area();
            root.fill(&WHITE).map_err(|e| anyhow::anyhow!("{e}"))?;
            let mut builder = ChartBuilder::on(&root);
            builder
                .caption(self.title, ("sans-serif", 22))
                .margin(18)
                .x_label_area_size(48)
                .y_label_area_size(80);
            if log {
                let mut chart = builder
                    .build_cartesian_2d((lx0..lx1).log_scale(), (ly0..ly1).log_scale())
                    .map_err(|e| anyhow::anyhow!("{e}"))?;
                self.draw(&mut chart, legend.clone(), true)?;
            } else {
                let mut chart = builder
                    .build_cartesian_2d(x0..x1, y0..y1)
                    .map_err(|e| anyhow::anyhow!("{e}"))?;
                self.draw(&mut chart, legend.clone(), false)?;
            }
            root.present().map_err(|e| anyhow::anyhow!("{e}"))?;
        }
        let csv = dir.join(format!("{stem}.csv"));
        let mut f = crate::files::create(&csv)?;
        let col = |label: &str| {
            label
                .replace([' ', '(', ')', '/'], "_")
                .replace("__", "_")
                .trim_matches('_')
                .to_lowercase()
        };
        writeln!(f, "series,{},{}", col(self.x_label), col(self.y_label))?;
        for s in &self.series {
            for (x, y) in &s.points {
                writeln!(f, "\"{}\",{x:.9e},{y:.9e}", s.label)?;
            }
        }
        Ok(())
    }
}

impl Chart<'_> {
    /// The axes, the curves (and markers) and the legend.
    fn draw<'a, X, Y>(
        &self,
        chart: &mut ChartContext<'a, SVGBackend<'a>, Cartesian2d<X, Y>>,
        legend: SeriesLabelPosition,
        log: bool,
    ) -> anyhow::Result<()>
    where
        X: Ranged<ValueType = f64> + ValueFormatter<f64>,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        // A logarithmic axis's ticks are powers of ten (and their multiples) computed in
        // floating point: printed as they come they read "9.999999999e-5".
        let decade = |v: &f64| format!("{v:.0e}");
        let mut mesh = chart.configure_mesh();
        if log {
            mesh.x_label_formatter(&decade).y_label_formatter(&decade);
        }
        mesh.x_desc(self.x_label)
            .y_desc(self.y_label)
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 17))
            .draw()
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        for (i, s) in self.series.iter().enumerate() {
            let colour = COLOURS[i % COLOURS.len()];
            chart
                .draw_series(LineSeries::new(s.points.iter().copied(), colour.stroke_width(2)))
                .map_err(|e| anyhow::anyhow!("{e}"))?
                .label(s.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
            if self.markers {
                chart
                    .draw_series(s.points.iter().map(|p| Circle::new(*p, 4, colour.filled())))
                    .map_err(|e| anyhow::anyhow!("{e}"))?;
            }
        }
        chart
            .configure_series_labels()
            .position(legend)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 15))
            .draw()
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        Ok(())
    }
}

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
