//! `simulate --plots DIR`: the figures a person wants after one run.
//!
//! contact_force (and contact_force_first, the first pulse in µs), displacement (at the
//! impact point), energy (the ledger's terms, on a logarithmic time axis),
//! stress_history (the bending stress at the worst point and at each support) and
//! stress_map (position along the beam against time, colour = stress on the struck face,
//! the maximum marked), each as SVG with its data as CSV, and index.html: the report's
//! numbers and warnings above the figures.

use crate::plot::{Chart, Series};
use impact::Outcome;
use plotters::prelude::*;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

/// Writes the figures of `outcome` into `dir`.
pub(crate) fn one_run(dir: &Path, outcome: &Outcome) -> anyhow::Result<()> {
    // An earlier run's page and figures go first, the page is written last: the page shows
    // only this run's figures, and a run stopped on its way leaves no page (a half-space's page
    // had shown a beam run's stress figures left in the folder, a review's).
    crate::files::remove_output(&dir.join("index.html"))?;
    for (stem, _) in FIGURES {
        crate::plot::remove_figure(dir, stem)?;
    }
    let h = &outcome.history;
    let ms = |v: &[f64], scale: f64| -> Vec<(f64, f64)> {
        h.time.iter().zip(v).map(|(t, y)| (t * 1e3, y * scale)).collect()
    };
    let name = impact::study::printable(&outcome.report.name);
    let title = |what: &str| format!("{name}: {what}");
    Chart {
        title: &title("contact force"),
        x_label: "time (ms)",
        y_label: "contact force (N)",
        series: vec![Series { label: "contact force".into(), points: ms(&h.force, 1.0) }],
        markers: false,
        reference_first: false,
    }
    .write(dir, "contact_force")?;
    // The first pulse on its own time scale: in a window of milliseconds it is a spike.
    if let Some(first) = outcome.report.contacts.first() {
        let end = first.start + 1.2 * first.duration.max(f64::MIN_POSITIVE);
        let points: Vec<(f64, f64)> = h
            .time
            .iter()
            .zip(&h.force)
            .filter(|(t, _)| **t >= first.start - 0.1 * first.duration && **t <= end)
            .map(|(t, f)| (t * 1e6, *f))
            .collect();
        if points.len() > 1 {
            Chart {
                title: &title("the first contact"),
                x_label: "time (µs)",
                y_label: "contact force (N)",
                series: vec![Series { label: "contact force".into(), points }],
                markers: false,
                reference_first: false,
            }
            .write(dir, "contact_force_first")?;
        }
    }
    Chart {
        title: &title("displacement at the impact point"),
        x_label: "time (ms)",
        y_label: "displacement (mm)",
        series: vec![Series {
            label: "beam at the impact point".into(),
            points: ms(&h.beam_displacement, 1e3),
        }],
        markers: false,
        reference_first: false,
    }
    .write(dir, "displacement")?;
    let energy = [
        ("ball (kinetic + gravity)", &h.ball_energy),
        ("beam (kinetic + strain)", &h.beam_energy),
        ("contact (stored)", &h.contact_energy),
        ("dissipated", &h.dissipated_energy),
    ];
    Chart {
        title: &title("energy ledger"),
        x_label: "time (ms)",
        y_label: "energy (mJ)",
        // On a logarithmic time axis: the exchange happens in the first contact's tens of
        // microseconds of a window of milliseconds (t = 0 has no place on it).
        series: energy
            .iter()
            .map(|(label, v)| {
                let points = ms(v, 1e3).into_iter().filter(|p| p.0 > 0.0).collect();
                Series { label: (*label).into(), points }
            })
            .collect(),
        markers: false,
        reference_first: false,
    }
    .write_log_x(dir, "energy")?;
    stress_figures(dir, outcome, "")?;
    index(dir, outcome)
}

/// The figures that `one_run` wrote, with what each shows; [`captions`] adds the run's numbers
/// and settings.
const FIGURES: [(&str, &str); 6] = [
    ("contact_force", "Contact force between ball and beam over the whole window."),
    ("contact_force_first", "The first contact on its own time scale (from a tenth of its duration before it to a fifth after)."),
    ("displacement", "Displacement of the beam at the impact point, towards the beam positive."),
    ("energy", "The energy ledger on a logarithmic time axis (the exchange happens within the first contact): the ball's kinetic and gravitational energy, the beam's kinetic and strain energy, the energy stored in the contact and the work dissipated (plastic work, damping)."),
    ("stress_history", "Bending stress on the struck face (outer fibre, tension positive) at the worst point and at each support."),
    ("stress_map", "Bending stress on the struck face along the beam (vertical) against time, blue compression to red tension; the largest marked with a cross."),
];

/// Each figure's caption: what it shows, its numbers, and the settings and error behind them
/// (a caption stands alone: the page may be read without the report).
fn captions(outcome: &Outcome) -> Vec<(&'static str, String)> {
    let r = &outcome.report;
    let p = &r.plan;
    let resolution = resolution(p);
    let error = r.estimated_error.map_or(
        "error not estimated (set solver.tolerance to have the resolution refined until it is)"
            .into(),
        |e| format!("estimated relative error {e:.1e}"),
    );
    let settings = format!(
        "Settings: {} method, {resolution}, {} contact, time step in contact {:.3} µs, window {:.3} ms; {error}.",
        p.method,
        p.contact_law,
        p.time_step * 1e6,
        outcome.history.time.last().copied().unwrap_or(0.0) * 1e3,
    );
    let first = r.contacts.first();
    FIGURES
        .iter()
        .map(|(stem, what)| {
            let numbers = match *stem {
                "contact_force" => format!(" {} contact(s).", r.contact_count),
                "contact_force_first" => first.map_or(String::new(), |c| {
                    format!(" Peak {:.4} N, duration {:.4} µs.", c.peak_force, c.duration * 1e6)
                }),
                "displacement" => format!(
                    " Largest {:.4} mm at {:.4} ms.",
                    r.max_displacement * 1e3,
                    r.max_displacement_time * 1e3
                ),
                "stress_history" | "stress_map" => {
                    r.bending_stress.as_ref().map_or(String::new(), |b| {
                        format!(
                            " Largest |stress| {:.2} MPa at {} = {:.4} m, t = {:.4} ms.",
                            b.max * 1e-6,
                            along(&r.plan).0,
                            b.position,
                            b.time * 1e3
                        )
                    })
                }
                _ => String::new(),
            };
            (*stem, format!("{what}{numbers} {settings}"))
        })
        .collect()
}

/// index.html: the report's numbers and warnings, then the figures, on one page.
fn index(dir: &Path, outcome: &Outcome) -> anyhow::Result<()> {
    let r = &outcome.report;
    let mut html = crate::plot::page_head(&r.name);
    let _ = write!(html, "<h1>{}</h1>", crate::plot::escape_html(&r.name));
    let _ = write!(
        html,
        "<p>Method {:?}; impact speed {:.4} m/s; {} contact(s); largest displacement at the impact point {:.4} mm at {:.4} ms; equivalent static force {}; estimated error {}.</p>",
        r.plan.method,
        r.impact_speed,
        r.contact_count,
        r.max_displacement * 1e3,
        r.max_displacement_time * 1e3,
        r.equivalent_static_force.map_or("none".into(), |f| format!("{f:.2} N")),
        r.estimated_error.map_or("not estimated (no solver.tolerance)".into(), |e| format!("{e:.1e}")),
    );
    html.push_str("<table><tr><th>#</th><th>start (µs)</th><th>duration (µs)</th><th>peak force (N)</th><th>peak pressure (MPa)</th><th>print radius (mm)</th></tr>");
    for (i, c) in r.contacts.iter().enumerate() {
        let _ = write!(
            html,
            "<tr><td>{}</td><td>{:.2}</td><td>{:.2}{}</td><td>{:.2}</td><td>{:.0}</td><td>{:.4}</td></tr>",
            i + 1,
            c.start * 1e6,
            c.duration * 1e6,
            if c.complete { "" } else { " (cut by the window)" },
            c.peak_force,
            c.max_pressure * 1e-6,
            c.print_radius * 1e3
        );
    }
    html.push_str("</table>");
    if !r.warnings.is_empty() {
        html.push_str("<h2>Warnings</h2><ul>");
        for w in &r.warnings {
            let _ = write!(html, "<li>{}</li>", crate::plot::escape_html(w));
        }
        html.push_str("</ul>");
    }
    for (stem, caption) in captions(outcome) {
        if dir.join(format!("{stem}.svg")).exists() {
            let _ = write!(
                html,
                "<figure><img src=\"{stem}.svg\" alt=\"{stem}\"><figcaption>{caption} Data: {stem}.csv.</figcaption></figure>"
            );
        }
    }
    html.push_str("<p>Every number and the reasons for each choice are in the report (simulate --json).</p></body></html>\n");
    crate::files::write_atomic(&dir.join("index.html"), html.as_bytes())
}

/// `{prefix}stress_history` (the stress at the worst point and at each support against time)
/// and `{prefix}stress_map` (the space-time map), when the run recorded its field.
pub(crate) fn stress_figures(dir: &Path, outcome: &Outcome, prefix: &str) -> anyhow::Result<()> {
    let name = impact::study::printable(&outcome.report.name);
    let title = |what: &str| format!("{name}: {what}");
    if let (Some(field), Some(stress)) = (&outcome.field, &outcome.report.bending_stress) {
        let x = along(&outcome.report.plan).0;
        let mut at: Vec<(String, f64)> =
            vec![(format!("largest, {x} = {:.4} m", stress.position), stress.position)];
        at.extend(
            stress
                .supports
                .iter()
                .map(|s| (format!("support, {x} = {} m", s.position), s.position)),
        );
        let p = field.points.len();
        let series = at
            .iter()
            .map(|(label, x)| {
                let k = nearest(&field.points, *x);
                Series {
                    label: format!("{label} (field point {:.4} m)", field.points[k]),
                    points: field
                        .time
                        .iter()
                        .enumerate()
                        .map(|(i, t)| (t * 1e3, field.stress[i * p + k] * 1e-6))
                        .collect(),
                }
            })
            .collect();
        Chart {
            title: &title("bending stress on the struck face"),
            x_label: "time (ms)",
            y_label: "stress, tension positive (MPa)",
            series,
            markers: false,
            reference_first: false,
        }
        .write(dir, &format!("{prefix}stress_history"))?;
        let caption = title(&format!(
            "stress on the struck face; cross: largest |stress| {:.2} MPa at {x} = {:.4} m, {:.4} ms",
            stress.max * 1e-6,
            stress.position,
            stress.time * 1e3
        ));
        let y_title = along(&outcome.report.plan).1;
        stress_map(dir, &format!("{prefix}stress_map"), (&caption, y_title), field, stress)?;
    }
    Ok(())
}

/// How a report's positions read: x along a beam, or s (arc length) along a structure's
/// chain of segments; and the axis title of a position.
pub(crate) fn along(plan: &impact::PlanSummary) -> (&'static str, &'static str) {
    if plan.structure {
        ("s", "arc length along the structure (m)")
    } else {
        ("x", "position along the beam (m)")
    }
}

fn nearest(points: &[f64], x: f64) -> usize {
    (0..points.len())
        .min_by(|a, b| (points[*a] - x).abs().total_cmp(&(points[*b] - x).abs()))
        .unwrap_or(0)
}

/// Blue (compression) through white to red (tension), for `v` in [-1, 1].
fn diverging(v: f64) -> RGBColor {
    let v = v.clamp(-1.0, 1.0);
    let fade = |c: f64| (255.0 - (255.0 - c) * v.abs()) as u8;
    if v >= 0.0 {
        RGBColor(fade(178.0), fade(24.0), fade(43.0))
    } else {
        RGBColor(fade(33.0), fade(102.0), fade(172.0))
    }
}

/// The space-time map: a cell per field point and instant (time on x, position on y), the
/// colour scaled to the largest magnitude, the maximum marked; its data as a CSV of the cells.
fn stress_map(
    dir: &Path,
    stem: &str,
    (title, y_title): (&str, &str),
    field: &impact::Field,
    stress: &impact::BendingStress,
) -> anyhow::Result<()> {
    let p = field.points.len();
    let scale = field.stress.iter().fold(0.0_f64, |a, s| a.max(s.abs())).max(f64::MIN_POSITIVE);
    let (t_end, length) = (
        field.time.last().copied().unwrap_or(0.0) * 1e3,
        field.points.last().copied().unwrap_or(1.0),
    );
    let svg = dir.join(format!("{stem}.svg"));
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, (900, 560)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow::anyhow!("{e}"))?;
        let (plot, bar) = root.split_horizontally(800);
        let mut chart = ChartBuilder::on(&plot)
            .caption(title, ("sans-serif", 17))
            .margin(18)
            .x_label_area_size(48)
            .y_label_area_size(70)
            .build_cartesian_2d(0.0..t_end.max(1e-9), 0.0..length)
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        chart
            .configure_mesh()
            .x_desc("time (ms)")
            .y_desc(y_title)
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 17))
            .disable_mesh()
            .draw()
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        // Cells: each instant to the next, each point's half-way to its neighbours.
        let edges: Vec<f64> = std::iter::once(0.0)
            .chain(field.points.windows(2).map(|w| 0.5 * (w[0] + w[1])))
            .chain(std::iter::once(length))
            .collect();
        // At most 600 columns of instants: a map of every one of thousands is no clearer.
        let stride = field.time.len().div_ceil(600).max(1);
        let columns: Vec<usize> = (0..field.time.len()).step_by(stride).collect();
        let cells = columns.iter().enumerate().flat_map(|(c, &i)| {
            let t0 = field.time[i] * 1e3;
            let t1 = columns.get(c + 1).map_or(t_end, |&j| field.time[j] * 1e3);
            let edges = &edges;
            (0..p).map(move |k| {
                let v = field.stress[i * p + k] / scale;
                Rectangle::new([(t0, edges[k]), (t1, edges[k + 1])], diverging(v).filled())
            })
        });
        chart.draw_series(cells).map_err(|e| anyhow::anyhow!("{e}"))?;
        let mark = (stress.time * 1e3, stress.position);
        chart
            .draw_series([Cross::new(mark, 9, BLACK.stroke_width(3))])
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        // The colour bar: -scale to +scale (MPa).
        let mut key = ChartBuilder::on(&bar)
            .margin_top(60)
            .margin_bottom(66)
            .margin_right(50)
            .y_label_area_size(0)
            .right_y_label_area_size(45)
            .build_cartesian_2d(0.0..1.0, -scale * 1e-6..scale * 1e-6)
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        key.configure_mesh()
            .disable_x_axis()
            .disable_mesh()
            .y_desc("stress (MPa)")
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(|e| anyhow::anyhow!("{e}"))?;
        let steps = 100;
        key.draw_series((0..steps).map(|s| {
            let lo = -1.0 + 2.0 * s as f64 / steps as f64;
            let hi = lo + 2.0 / steps as f64;
            Rectangle::new(
                [(0.0, lo * scale * 1e-6), (1.0, hi * scale * 1e-6)],
                diverging(0.5 * (lo + hi)).filled(),
            )
        }))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
        root.present().map_err(|e| anyhow::anyhow!("{e}"))?;
    }
    crate::files::write_atomic(&svg, text.as_bytes())?;
    let mut csv = crate::files::create(&dir.join(format!("{stem}.csv")))?;
    writeln!(csv, "time_ms,x_m,stress_mpa")?;
    for (i, t) in field.time.iter().enumerate() {
        for (k, x) in field.points.iter().enumerate() {
            writeln!(csv, "{:.9e},{x:.6e},{:.9e}", t * 1e3, field.stress[i * p + k] * 1e-6)?;
        }
    }
    csv.finish()
}

/// A run's resolution in words: "512 elements", "128 Timoshenko modes", "rigid block".
pub(crate) fn resolution(plan: &impact::PlanSummary) -> String {
    match plan.method {
        impact::MethodKind::Fe => format!("{} elements", plan.elements),
        impact::MethodKind::Modal => match plan.beam_theory {
            Some(impact::TheoryName::Timoshenko) => format!("{} Timoshenko modes", plan.modes),
            Some(impact::TheoryName::EulerBernoulli) => {
                format!("{} Euler-Bernoulli modes", plan.modes)
            }
            _ => format!("{} modes", plan.modes),
        },
        impact::MethodKind::HalfSpace => "rigid block".to_string(),
    }
}
