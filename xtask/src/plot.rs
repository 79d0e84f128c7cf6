//! Line charts (SVG, plotters) and CSV files of series.

use anyhow::Context;
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
        let svg = dir.join(format!("{stem}.svg"));
        let all = self.series.iter().flat_map(|s| s.points.iter());
        anyhow::ensure!(
            all.clone().all(|(x, y)| x.is_finite() && y.is_finite()),
            "figure {stem}: a value is not finite"
        );
        let (x0, x1) = bounds(all.clone().map(|p| p.0));
        let (y0, y1) = bounds(all.map(|p| p.1));
        {
            let root = SVGBackend::new(&svg, (900, 560)).into_drawing_area();
            root.fill(&WHITE).map_err(|e| anyhow::anyhow!("{e}"))?;
            let mut chart = ChartBuilder::on(&root)
                .caption(self.title, ("sans-serif", 22))
                .margin(18)
                .x_label_area_size(48)
                .y_label_area_size(80)
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(|e| anyhow::anyhow!("{e}"))?;
            chart
                .configure_mesh()
                .x_desc(self.x_label)
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
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 15))
                .draw()
                .map_err(|e| anyhow::anyhow!("{e}"))?;
            root.present().map_err(|e| anyhow::anyhow!("{e}"))?;
        }
        let csv = dir.join(format!("{stem}.csv"));
        let mut f = std::io::BufWriter::new(
            std::fs::File::create(&csv)
                .with_context(|| format!("cannot write {}", csv.display()))?,
        );
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
