//! `cargo xtask accuracy SCENE.toml`: speed against error, for every method that applies.
//!
//! A beam scene is run by the modal method over a ladder of mode counts, with and without the
//! residual flexibility (and with two looser energy tolerances of its adaptive contact step),
//! and by the finite-element method over a ladder of uniform meshes (and other contact steps
//! and HHT alphas). Each method's errors are measured from its own converged run, at four times
//! the finest resolution of its ladder (the modal one with the residual flexibility, which
//! converges fastest: validation/REFERENCES.md 1.4); that reference is checked against a run at
//! half its resolution, and the check says how far the reference itself may be off (a third of
//! their difference: Richardson at second order, the fe element's order and below the modal
//! series'). Where both references are converged they differ by the models (Euler-Bernoulli
//! modes against the geometrically exact beam), which the table's footer states and no setting
//! of either method removes.
//!
//! Errors are relative (-): the first contact's duration and peak force, the contact sequence
//! (the worst relative error in start, duration and peak force over the significant contacts,
//! those with a peak of at least [`SEQUENCE_PEAK`] of the first's, a missing one counting 1,
//! and 1 at most: not resolved), the largest displacement at the impact point, and the energy
//! balance error over the impact energy. Runs go one at a time, so that their wall times are
//! not shared with another run.

use crate::plot::{Chart, Series};
use anyhow::Context;
use impact::{Differences, MethodName, Outcome, Scene};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A contact is significant in the sequence error when its peak is at least this fraction of
/// the first contact's.
pub(crate) const SEQUENCE_PEAK: f64 = 0.01;

/// The figure's curve of the modal runs with the residual flexibility.
const RESIDUAL: &str = "modal, residual flexibility";

/// One of a run's errors.
type Metric = fn(&Differences) -> f64;

/// One run of the study.
struct Setting {
    method: &'static str,
    /// The figure's curve it belongs to (the method, or the method with an option).
    series: &'static str,
    /// What was set, e.g. "256 modes" or "128 elements; alpha -0.2" (no commas: a CSV field).
    label: String,
    /// Whether it is on the method's main ladder (mode or element counts): the figure's curves.
    ladder: bool,
    scene: Scene,
}

/// The ladders: full, or (`quick`) a reduced one for CI.
struct Ladders {
    modes: Vec<usize>,
    modal_reference: usize,
    elements: Vec<usize>,
    fe_reference: usize,
    /// The mode count and the element count the variants are run at.
    modal_variant: usize,
    fe_variant: usize,
}

impl Ladders {
    fn new(quick: bool) -> Self {
        if quick {
            Self {
                modes: vec![16, 32, 64, 128],
                modal_reference: 512,
                elements: vec![16, 32, 64, 128],
                fe_reference: 512,
                modal_variant: 64,
                fe_variant: 64,
            }
        } else {
            Self {
                modes: vec![32, 64, 128, 256, 512, 1024],
                modal_reference: 4096,
                elements: vec![32, 64, 128, 256, 512],
                fe_reference: 2048,
                modal_variant: 512,
                fe_variant: 256,
            }
        }
    }
}

fn modal(scene: &Scene, modes: usize) -> Scene {
    let mut s = scene.clone();
    s.solver.method = MethodName::Modal;
    s.solver.modes = Some(modes);
    s.solver.elements = None;
    s.solver.element_size = None;
    s.solver.alpha = None;
    s.solver.time_step = None;
    s.solver.tolerance = None;
    s
}

fn fe(scene: &Scene, elements: usize) -> Scene {
    let mut s = scene.clone();
    s.solver.method = MethodName::Fe;
    s.solver.modes = None;
    s.solver.elements = Some(elements);
    s.solver.element_size = None;
    s.solver.tolerance = None;
    s.solver.adaptive_step = None;
    s.solver.energy_tolerance = None;
    s
}

/// The settings of each method, then each method's reference and its check (half the
/// reference's resolution), last.
fn settings(scene: &Scene, l: &Ladders) -> Vec<Setting> {
    let mut out = Vec::new();
    let mut add = |method, label: String, ladder, scene| {
        let series = if label.contains("residual flexibility") { RESIDUAL } else { method };
        out.push(Setting { method, series, label, ladder, scene });
    };
    for &n in &l.modes {
        add("modal", format!("{n} modes"), true, modal(scene, n));
    }
    for &n in &l.modes {
        let mut s = modal(scene, n);
        s.solver.residual_flexibility = Some(true);
        add("modal", format!("{n} modes; residual flexibility"), true, s);
    }
    for tol in [1e-4, 1e-5] {
        let mut s = modal(scene, l.modal_variant);
        s.solver.energy_tolerance = Some(tol);
        add("modal", format!("{} modes; energy tolerance {tol:e}", l.modal_variant), false, s);
    }
    for &n in &l.elements {
        add("fe", format!("{n} elements"), true, fe(scene, n));
    }
    for samples in [100, 400] {
        let mut s = fe(scene, l.fe_variant);
        s.solver.samples_per_pulse = Some(samples);
        add("fe", format!("{} elements; {samples} steps per pulse", l.fe_variant), false, s);
    }
    for alpha in [0.0, -0.2] {
        let mut s = fe(scene, l.fe_variant);
        s.solver.alpha = Some(alpha);
        add("fe", format!("{} elements; alpha {alpha}", l.fe_variant), false, s);
    }
    // The modal reference with the residual flexibility: the same Euler-Bernoulli model,
    // converged far faster (validation/REFERENCES.md 1.4).
    for (n, label) in [(l.modal_reference / 2, "check"), (l.modal_reference, "reference")] {
        let mut s = modal(scene, n);
        s.solver.residual_flexibility = Some(true);
        add("modal", format!("{n} modes; residual flexibility ({label})"), false, s);
    }
    for (n, label) in [(l.fe_reference / 2, "check"), (l.fe_reference, "reference")] {
        add("fe", format!("{n} elements ({label})"), false, fe(scene, n));
    }
    out
}

/// One row of work_precision.csv.
pub(crate) struct Row {
    pub method: &'static str,
    pub series: &'static str,
    pub setting: String,
    pub ladder: bool,
    pub wall_time: f64,
    pub errors: Differences,
    pub energy_balance: f64,
}

/// A method's reference and how far it may itself be off.
pub(crate) struct Reference {
    pub method: &'static str,
    pub setting: String,
    /// A third of its worst difference from the check run (half its resolution).
    pub estimated_error: f64,
    pub check: String,
}

/// The study of one scene.
pub(crate) struct Study {
    pub name: String,
    pub rows: Vec<Row>,
    pub references: Vec<Reference>,
    /// The worst difference between the two methods' references.
    pub model_difference: f64,
}

/// Runs the study of `scene` (a beam scene).
pub(crate) fn study(scene: &Scene, quick: bool) -> anyhow::Result<Study> {
    anyhow::ensure!(
        scene.beam.is_some(),
        "accuracy needs a [beam] scene (a [half_space] has one model, exact to round-off)"
    );
    let all = settings(scene, &Ladders::new(quick));
    let scenes: Vec<Scene> = all.iter().map(|s| s.scene.clone()).collect();
    // One run at a time: a wall time shared with another run on the same cores is not the
    // setting's cost.
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let outcomes: Vec<Outcome> = pool.install(|| {
        crate::sweep::par_run("accuracy", &scenes, |s| {
            impact::simulate(s).with_context(|| format!("scene {}", s.name))
        })
        .into_iter()
        .collect::<anyhow::Result<_>>()
    })?;
    let reference_of = |method: &str| -> anyhow::Result<(usize, usize)> {
        let find = |tag: &str| {
            all.iter()
                .position(|s| s.method == method && s.label.ends_with(tag))
                .context("a reference run")
        };
        Ok((find("(check)")?, find("(reference)")?))
    };
    let mut rows = Vec::new();
    let mut references = Vec::new();
    for method in ["modal", "fe"] {
        let (check, reference) = reference_of(method)?;
        let r = &outcomes[reference].report;
        let c = outcomes[check].report.differences_from(r, SEQUENCE_PEAK);
        references.push(Reference {
            method,
            setting: all[reference].label.clone(),
            estimated_error: c.worst() / 3.0,
            check: all[check].label.clone(),
        });
        for (s, o) in all.iter().zip(&outcomes) {
            if s.method != method || s.label.ends_with("(reference)") {
                continue;
            }
            let e = &o.report.energy;
            rows.push(Row {
                method,
                series: s.series,
                setting: s.label.clone(),
                ladder: s.ladder,
                wall_time: o.report.wall_time,
                errors: o.report.differences_from(r, SEQUENCE_PEAK),
                energy_balance: if e.initial > 0.0 {
                    e.balance_error.abs() / e.initial
                } else {
                    0.0
                },
            });
        }
    }
    let (_, m) = reference_of("modal")?;
    let (_, f) = reference_of("fe")?;
    let model_difference =
        outcomes[m].report.differences_from(&outcomes[f].report, SEQUENCE_PEAK).worst();
    Ok(Study { name: scene.name.clone(), rows, references, model_difference })
}

impl Row {
    /// The four relative errors and the energy balance, in the CSV's order.
    fn columns(&self) -> [f64; 5] {
        let e = &self.errors;
        [
            e.first_duration,
            e.first_peak_force,
            e.contact_sequence,
            e.max_displacement,
            self.energy_balance,
        ]
    }
}

/// The error a setting is judged by: the worst of its four.
fn worst(row: &Row) -> f64 {
    row.errors.worst()
}

impl Study {
    /// The cheapest setting of `method` whose worst error is within `target`.
    pub(crate) fn cheapest(&self, method: &str, target: f64) -> Option<&Row> {
        self.rows
            .iter()
            .filter(|r| r.method == method && worst(r) <= target)
            .min_by(|a, b| a.wall_time.total_cmp(&b.wall_time))
    }

    /// work_precision.csv.
    pub(crate) fn csv(&self) -> String {
        let mut csv = String::from("method,setting,wall_time_s,error_first_duration,error_first_peak_force,error_contact_sequence,error_max_displacement,energy_balance\n");
        for r in &self.rows {
            let errors: Vec<String> = r.columns().iter().map(|x| format!("{x:.3e}")).collect();
            // Infallible: writing to a String.
            let _ = writeln!(
                csv,
                "{},\"{}\",{:.4e},{}",
                r.method,
                r.setting,
                r.wall_time,
                errors.join(",")
            );
        }
        csv
    }

    /// The printed table, ending with the cheapest setting for 1e-2 and 1e-3.
    pub(crate) fn table(&self) -> String {
        let mut t = String::new();
        let _ = writeln!(
            t,
            "{}: relative errors from each method's converged run (significant contacts: peak >= {} of the first's)\n",
            self.name, SEQUENCE_PEAK
        );
        let _ = writeln!(
            t,
            "{:<6} {:<44} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}",
            "method",
            "setting",
            "wall (s)",
            "first t_c",
            "first F",
            "sequence",
            "max disp",
            "energy"
        );
        for r in &self.rows {
            let errors: Vec<String> = r.columns().iter().map(|x| format!("{x:>10.2e}")).collect();
            let _ = writeln!(
                t,
                "{:<6} {:<44} {:>10.4} {}",
                r.method,
                r.setting,
                r.wall_time,
                errors.join(" ")
            );
        }
        let _ = writeln!(t);
        for r in &self.references {
            let _ = writeln!(
                t,
                "{} reference: {}, itself within {:.1e} (a third of its difference from {})",
                r.method, r.setting, r.estimated_error, r.check
            );
        }
        let _ = writeln!(
            t,
            "the two references differ by {:.2e}: the models' own difference (Euler-Bernoulli modes against the geometrically exact beam) where both references are converged, more where one is not\n",
            self.model_difference
        );
        for target in [1e-2, 1e-3] {
            for method in ["modal", "fe"] {
                let _ = match self.cheapest(method, target) {
                    Some(r) => writeln!(
                        t,
                        "cheapest {method} setting for {target:.0e} on every error: {} ({:.4} s, worst {:.2e})",
                        r.setting,
                        r.wall_time,
                        worst(r)
                    ),
                    None => writeln!(
                        t,
                        "cheapest {method} setting for {target:.0e} on every error: none of these"
                    ),
                };
            }
        }
        t
    }

    /// work_precision.svg and work_precision.csv (the rows, with the errors as columns) in
    /// `dir`.
    pub(crate) fn write(&self, dir: &Path) -> anyhow::Result<()> {
        // The chart writes its points as work_precision.csv; the table of rows replaces them.
        self.chart(dir, "work_precision")?;
        let csv = dir.join("work_precision.csv");
        std::fs::write(&csv, self.csv()).with_context(|| format!("cannot write {}", csv.display()))
    }

    /// The chart: wall time against each error, one curve per
    /// method and metric over the method's main ladder, and its other settings' worst errors
    /// as points.
    fn chart(&self, dir: &Path, stem: &str) -> anyhow::Result<()> {
        let metrics: [(&str, Metric); 4] = [
            ("first duration", |e| e.first_duration),
            ("first peak force", |e| e.first_peak_force),
            ("contact sequence", |e| e.contact_sequence),
            ("max displacement", |e| e.max_displacement),
        ];
        let mut series = Vec::new();
        for (method, curve) in [("modal", "modal"), ("modal", RESIDUAL), ("fe", "fe")] {
            for (name, pick) in metrics {
                let mut points: Vec<(f64, f64)> = self
                    .rows
                    .iter()
                    .filter(|r| r.series == curve && r.ladder)
                    .map(|r| (r.wall_time, pick(&r.errors)))
                    // An error of exactly 0 has no place on a logarithmic axis.
                    .filter(|p| p.0 > 0.0 && p.1 > 0.0)
                    .collect();
                points.sort_by(|a, b| a.0.total_cmp(&b.0));
                series.push(Series { label: format!("{curve}: {name}"), points });
            }
            if curve == RESIDUAL {
                continue;
            }
            let others: Vec<(f64, f64)> = self
                .rows
                .iter()
                .filter(|r| r.method == method && !r.ladder && !r.setting.ends_with("(check)"))
                .map(|r| (r.wall_time, worst(r)))
                .filter(|p| p.0 > 0.0 && p.1 > 0.0)
                .collect();
            series
                .push(Series { label: format!("{method}: other settings, worst"), points: others });
        }
        series.retain(|s| !s.points.is_empty());
        Chart {
            title: "Work-precision: wall time against relative error",
            x_label: "wall time (s)",
            y_label: "relative error (-)",
            series,
            markers: true,
        }
        .write_log_log(dir, stem)
    }
}

#[allow(clippy::print_stdout)]
pub(crate) fn run(path: &Path, out: Option<&Path>, quick: bool) -> anyhow::Result<bool> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read the scene file {}", path.display()))?;
    let scene = Scene::from_toml(&text).with_context(|| format!("in {}", path.display()))?;
    let out: PathBuf =
        out.map_or_else(|| Path::new("target/accuracy").join(&scene.name), Path::to_path_buf);
    std::fs::create_dir_all(&out).with_context(|| format!("cannot create {}", out.display()))?;
    let study = study(&scene, quick).with_context(|| format!("in {}", path.display()))?;
    study.write(&out)?;
    print!("{}", study.table());
    println!("\nwrote work_precision.csv and work_precision.svg to {}", out.display());
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::{Row, Study};
    use impact::Differences;

    fn row(method: &'static str, setting: &str, wall_time: f64, worst: f64) -> Row {
        Row {
            method,
            series: method,
            setting: setting.into(),
            ladder: true,
            wall_time,
            errors: Differences {
                first_duration: worst / 10.0,
                first_peak_force: worst,
                contact_sequence: worst / 2.0,
                max_displacement: 0.0,
                same_contacts: true,
            },
            energy_balance: 1e-7,
        }
    }

    #[test]
    fn the_cheapest_setting_meets_every_error_and_the_csv_has_the_columns() {
        let study = Study {
            name: "test".into(),
            rows: vec![
                row("modal", "16 modes", 0.001, 3e-2),
                row("modal", "64 modes", 0.002, 5e-3),
                row("modal", "256 modes", 0.004, 4e-4),
                row("fe", "64 elements", 0.05, 2e-2),
            ],
            references: vec![],
            model_difference: 0.0,
        };
        // The cheapest within 1e-2 is 64 modes (16 fails on its peak force), within 1e-3 256.
        assert_eq!(study.cheapest("modal", 1e-2).map(|r| r.setting.as_str()), Some("64 modes"));
        assert_eq!(study.cheapest("modal", 1e-3).map(|r| r.setting.as_str()), Some("256 modes"));
        assert!(study.cheapest("fe", 1e-2).is_none());
        let csv = study.csv();
        let mut lines = csv.lines();
        assert_eq!(
            lines.next(),
            Some("method,setting,wall_time_s,error_first_duration,error_first_peak_force,error_contact_sequence,error_max_displacement,energy_balance")
        );
        let first: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
        assert_eq!(first.len(), 8, "{first:?}");
        assert_eq!(first[1], "\"16 modes\"");
        assert!((first[4].parse::<f64>().unwrap_or(0.0) - 3e-2).abs() < 1e-12);
        assert!(study
            .table()
            .contains("cheapest modal setting for 1e-3 on every error: 256 modes"));
    }
}
