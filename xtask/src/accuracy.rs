//! `cargo xtask accuracy SCENE.toml`: speed against error, for every method that applies.
//!
//! The settings, the references and the errors are [`impact::study::accuracy`]'s; this module
//! runs the settings one at a time (a wall time shared with another run on the same cores is
//! not the setting's cost), keeps a journal of the finished runs, and writes the table and the
//! chart. Each run's report is appended to `runs.partial.jsonl` as it finishes (the references
//! and their checks first), so a stopped study keeps its runs and `--resume` runs only the
//! missing ones; when the last is done, `work_precision.csv` and `.svg` are written and the
//! journal is renamed `runs.jsonl`.

use crate::files::{read_input, say, write_atomic, OutDir};
use crate::plot::{Chart, Series};
use anyhow::Context;
use impact::study::accuracy::{
    settings, Ladders, Setting, Study, EULER_BERNOULLI, RESIDUAL, ROW_COLUMNS,
};
use impact::{Differences, Report, Scene};
use std::collections::HashMap;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

/// One of a run's errors.
type Metric = fn(&Differences) -> f64;

const JOURNAL: &str = "runs.partial.jsonl";

/// The ladders of a full or a `quick` study.
fn ladders(quick: bool) -> Ladders {
    if quick {
        Ladders::quick()
    } else {
        Ladders::full()
    }
}

/// One line of the journal: the study's fingerprint (the journal's first line), the
/// setting's label and its report. The fingerprint proves where the line comes from: a run
/// copied from another study's journal is refused.
#[derive(serde::Serialize, serde::Deserialize)]
struct Entry {
    #[serde(default)]
    study: String,
    setting: String,
    report: Report,
}

/// Runs `todo` (indices into `all`) one at a time with a progress bar, handing each report to
/// `done` as it finishes.
fn run_settings(
    all: &[Setting],
    todo: &[usize],
    done: &(dyn Fn(usize, &Report) -> anyhow::Result<()> + Sync),
) -> anyhow::Result<Vec<(usize, Report)>> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    pool.install(|| {
        crate::sweep::par_run("accuracy", todo, |&i| {
            let s = &all[i];
            let report =
                impact::simulate(&s.scene).with_context(|| format!("setting {}", s.label))?.report;
            done(i, &report)?;
            Ok((i, report))
        })
        .into_iter()
        .collect()
    })
}

/// The study of `scene`, run in memory (for `reproduce`), with a progress bar.
pub(crate) fn study(scene: &Scene, quick: bool) -> anyhow::Result<Study> {
    let bar = crate::sweep::progress_bar("accuracy", 0);
    let study = impact::study::accuracy::run(scene, &ladders(quick), &|done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    });
    bar.finish_and_clear();
    Ok(study?)
}

/// work_precision.csv.
pub(crate) fn csv(study: &Study) -> String {
    let mut csv = format!("method,setting,{}\n", ROW_COLUMNS.join(","));
    for r in &study.rows {
        let errors: Vec<String> = r.values()[1..].iter().map(|x| format!("{x:.3e}")).collect();
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
pub(crate) fn table(study: &Study) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{}: relative errors from each method's converged run (significant contacts: peak >= {} of the first's)\n",
        study.name, impact::SIGNIFICANT_PEAK
    );
    let _ = writeln!(
        t,
        "{:<6} {:<44} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}",
        "method",
        "setting",
        "wall (s)",
        "first t_c",
        "first F",
        "sequence",
        "max disp",
        "max stress",
        "energy"
    );
    for r in &study.rows {
        let errors: Vec<String> = r.values()[1..].iter().map(|x| format!("{x:>10.2e}")).collect();
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
    for r in &study.references {
        let _ = writeln!(
            t,
            "{} reference: {}, itself within {:.1e} (a third of its difference from {})",
            r.method, r.setting, r.estimated_error, r.check
        );
    }
    let _ = writeln!(
        t,
        "the two references differ by {}: the models' own difference ({}) where both references are converged, more where one is not",
        study.model_difference,
        models(study)
    );
    if let Some(d) = study.theory_difference {
        let _ = writeln!(
            t,
            "Euler-Bernoulli modes at the finest setting differ from the modal reference by {d}: what shear and rotary inertia change on this scene"
        );
    }
    let _ = writeln!(t);
    for target in [1e-2, 1e-3] {
        for method in ["modal", "fe"] {
            let _ = match study.cheapest(method, target) {
                Some(r) => writeln!(
                    t,
                    "cheapest {method} setting for {target:.0e} on every error: {} ({:.4} s, worst {:.2e})",
                    r.setting,
                    r.wall_time,
                    r.worst()
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

/// What the two references model: the modal method's linear beam of its theory, loaded on the
/// centre line, and the geometrically exact beam struck on its face (on a structure, its 3D
/// beam linearised at rest and geometrically exact).
pub(crate) fn models(study: &Study) -> String {
    if study.structure {
        return "the structure's 3D beam linearised at rest (its own modes) against the same beam geometrically exact, both struck on the face".into();
    }
    let theory = match study.modal_theory {
        Some(impact::TheoryName::EulerBernoulli) => "Euler-Bernoulli",
        Some(impact::TheoryName::Timoshenko) => "Timoshenko",
        None => "linear",
    };
    format!("{theory} modes loaded on the centre line against the geometrically exact beam struck on its face")
}

/// work_precision.svg and work_precision.csv (the rows, with the errors as columns) in
/// `dir`.
pub(crate) fn write(study: &Study, dir: &Path) -> anyhow::Result<()> {
    // The chart writes its points as work_precision.csv; the table of rows replaces them.
    chart(study, dir, "work_precision")?;
    write_atomic(&dir.join("work_precision.csv"), csv(study).as_bytes())
}

/// The chart: wall time against each error, one curve per
/// method and metric over the method's main ladder, and its other settings' worst errors
/// as points. The stress error is in the CSV and the table, not drawn: a fifth curve per
/// method would crowd a legend that already covers data (the figures' issue).
fn chart(study: &Study, dir: &Path, stem: &str) -> anyhow::Result<()> {
    let metrics: [(&str, Metric); 4] = [
        ("first duration", |e| e.first_duration),
        ("first peak force", |e| e.first_peak_force),
        ("contact sequence", |e| e.contact_sequence),
        ("max displacement", |e| e.max_displacement),
    ];
    let mut series = Vec::new();
    let curves =
        [("modal", "modal"), ("modal", RESIDUAL), ("modal", EULER_BERNOULLI), ("fe", "fe")];
    for (method, curve) in curves {
        // The Euler-Bernoulli ladder by two of its errors: where they level off is what it
        // says (its later contacts can differ in number, an error of 1), and four more curves
        // would crowd the chart.
        let picks: Vec<(&str, Metric)> =
            if curve == EULER_BERNOULLI { vec![metrics[1], metrics[3]] } else { metrics.to_vec() };
        for (name, pick) in picks {
            let points: Vec<(f64, f64)> = study
                .rows
                .iter()
                .filter(|r| r.series == curve && r.ladder)
                .map(|r| (r.wall_time, pick(&r.errors)))
                // An error of exactly 0 has no place on a logarithmic axis.
                .filter(|p| p.0 > 0.0 && p.1 > 0.0)
                .collect();
            // In the ladder's order (each point the next refinement), not the wall time's: the
            // times of runs of a few milliseconds are noisy, and sorted by them a converging
            // ladder had zig-zagged in its errors (a review's, 1 -> 0.12 -> 1).
            series.push(Series { label: format!("{curve}: {name}"), points });
        }
        if curve != method {
            continue;
        }
        let others: Vec<(f64, f64)> = study
            .rows
            .iter()
            .filter(|r| r.method == method && !r.ladder && !r.check)
            .map(|r| (r.wall_time, r.worst()))
            .filter(|p| p.0 > 0.0 && p.1 > 0.0)
            .collect();
        series.push(Series { label: format!("{method}: other settings, worst"), points: others });
    }
    series.retain(|s| !s.points.is_empty());
    Chart {
        title: "Work-precision: wall time against relative error",
        x_label: "wall time (s)",
        y_label: "relative error (-)",
        series,
        markers: true,
        reference_first: false,
    }
    .write_log_log(dir, stem)
}

/// `cargo xtask accuracy`: the study of the scene at `path`, its runs journalled in the
/// output folder as they finish; with `resume`, the journal's runs are kept and only the
/// missing settings run; with `limit`, at most that many settings run now.
pub(crate) fn run(
    path: &Path,
    out: Option<&Path>,
    quick: bool,
    resume: bool,
    limit: Option<usize>,
) -> anyhow::Result<bool> {
    let text = read_input(path, "scene file")?;
    let scene = Scene::from_toml(&text).with_context(|| format!("in {}", path.display()))?;
    let all =
        settings(&scene, &ladders(quick)).with_context(|| format!("in {}", path.display()))?;
    let dir = OutDir::create(&crate::files::out_dir("accuracy", &scene.name, out)?)?;
    let journal = dir.join(JOURNAL);
    // The journal's first line names the study, so that a resume refuses another's runs.
    let id = impact::study::fingerprint(&format!("{}\nquick = {quick}", toml::to_string(&scene)?));
    let mut reports: HashMap<String, Report> = HashMap::new();
    if resume {
        anyhow::ensure!(
            journal.exists(),
            "{} holds no unfinished study ({JOURNAL} is missing): nothing to resume",
            dir.path().display()
        );
        let text = std::fs::read_to_string(&journal)
            .with_context(|| format!("cannot read {}", journal.display()))?;
        let mut lines = text.split_inclusive('\n');
        anyhow::ensure!(
            lines.next().map(str::trim_end) == Some(&serde_json::to_string(&id)?),
            "{} holds the runs of another study (scene or ladders differ): nothing to resume",
            journal.display()
        );
        // A line cut by a kill has no line end: that setting runs again. Every other line
        // must be a run of this study, of one of its settings; an error names its line.
        for (k, line) in lines.enumerate().filter(|(_, l)| l.ends_with('\n')) {
            let at = format!("{}, line {}", journal.display(), k + 2);
            let entry: Entry =
                serde_json::from_str(line).with_context(|| format!("{at}: not a run"))?;
            anyhow::ensure!(
                entry.study == id,
                "{at}: a run of another study (its fingerprint {:?} is not this study's {id:?}): remove the line, or give the study it comes from",
                impact::study::printable(&entry.study)
            );
            anyhow::ensure!(
                all.iter().any(|s| s.label == entry.setting),
                "{at}: {:?} is not a setting of this study",
                impact::study::printable(&entry.setting)
            );
            reports.insert(entry.setting, entry.report);
        }
        let mut kept = serde_json::to_string(&id)? + "\n";
        for (label, report) in &reports {
            let entry = Entry { study: id.clone(), setting: label.clone(), report: report.clone() };
            kept += &serde_json::to_string(&entry)?;
            kept += "\n";
        }
        write_atomic(&journal, kept.as_bytes())?;
    } else {
        anyhow::ensure!(
            !journal.exists(),
            "{} holds an unfinished study ({JOURNAL}): add --resume to finish it, or remove it",
            dir.path().display()
        );
        write_atomic(&journal, (serde_json::to_string(&id)? + "\n").as_bytes())?;
    }
    let file = std::sync::Mutex::new(
        std::fs::OpenOptions::new()
            .append(true)
            .open(&journal)
            .with_context(|| format!("cannot append to {}", journal.display()))?,
    );
    let todo: Vec<usize> = (0..all.len())
        .filter(|&i| !reports.contains_key(&all[i].label))
        .take(limit.unwrap_or(usize::MAX))
        .collect();
    let ran = run_settings(&all, &todo, &|i, report| {
        let line = serde_json::to_string(&Entry {
            study: id.clone(),
            setting: all[i].label.clone(),
            report: report.clone(),
        })? + "\n";
        let mut f = file.lock().map_err(|_| anyhow::anyhow!("a run panicked"))?;
        // Synced as a sweep's rows are: a machine that stops keeps the finished runs.
        f.write_all(line.as_bytes())
            .and_then(|()| f.sync_data())
            .with_context(|| format!("cannot write {}", journal.display()))
    })
    .with_context(|| format!("in {}", path.display()))?;
    reports.extend(ran.into_iter().map(|(i, r)| (all[i].label.clone(), r)));
    let missing = all.iter().filter(|s| !reports.contains_key(&s.label)).count();
    if missing > 0 {
        say!(
            "{} of {} settings done; their runs are in {}: run again with --resume to finish",
            all.len() - missing,
            all.len(),
            journal.display()
        )?;
        return Ok(true);
    }
    let ordered: Vec<Report> = all.iter().filter_map(|s| reports.remove(&s.label)).collect();
    let study = Study::new(&scene.name, &all, &ordered)?;
    write(&study, dir.path())?;
    crate::files::rename_output(&journal, &dir.join("runs.jsonl"))?;
    say!("{}", table(&study).trim_end())?;
    say!(
        "\nwrote work_precision.csv, work_precision.svg and runs.jsonl (every run's report) to {}",
        dir.path().display()
    )?;
    Ok(true)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use impact::study::accuracy::Row;

    fn row(method: &'static str, setting: &str, wall_time: f64, worst: f64) -> Row {
        Row {
            method,
            series: method,
            setting: setting.into(),
            ladder: true,
            check: false,
            wall_time,
            errors: Differences {
                first_duration: worst / 10.0,
                first_peak_force: worst,
                contact_sequence: worst / 2.0,
                max_displacement: 0.0,
                max_stress: worst / 4.0,
                same_contacts: true,
            },
            energy_balance: 1e-7,
        }
    }

    /// The CSV without its wall-time column (the one that differs between runs).
    fn timeless(dir: &Path) -> Vec<String> {
        std::fs::read_to_string(dir.join("work_precision.csv"))
            .unwrap()
            .lines()
            .map(|l| {
                let mut cells: Vec<&str> = l.split(',').collect();
                cells.remove(2);
                cells.join(",")
            })
            .collect()
    }

    #[test]
    fn a_stopped_study_resumes_to_the_table_of_a_whole_run() {
        let scene = Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../validation/scenes/paper-midspan.toml"
        ));
        let root = std::env::temp_dir().join(format!("accuracy-resume-{}", std::process::id()));
        std::fs::remove_dir_all(&root).ok();
        let (whole, parts) = (root.join("whole"), root.join("parts"));
        run(scene, Some(&whole), true, false, None).unwrap();
        // Stopped after the references and their checks: they are kept, no table yet.
        run(scene, Some(&parts), true, false, Some(4)).unwrap();
        assert_eq!(std::fs::read_to_string(parts.join(JOURNAL)).unwrap().lines().count(), 5);
        assert!(!parts.join("work_precision.csv").exists());
        // Not thrown away by a run without --resume.
        assert!(run(scene, Some(&parts), true, false, None).is_err());
        // A run copied from another study's journal, and a damaged third line: refused by
        // their line (before: taken as this study's reference; "line 1 column 13").
        let journal = std::fs::read_to_string(parts.join(JOURNAL)).unwrap();
        let lines: Vec<&str> = journal.lines().collect();
        let id = lines[0].trim_matches('"');
        let foreign = lines[1].replacen(id, "0123456789abcdef", 1);
        for (text, says) in [
            (format!("{journal}{foreign}\n"), "line 6: a run of another study"),
            (format!("{}\n{}\n{{\"study\": 1,\n", lines[0], lines[1]), "line 3: not a run"),
        ] {
            std::fs::write(parts.join(JOURNAL), text).unwrap();
            let e = format!("{:#}", run(scene, Some(&parts), true, true, None).unwrap_err());
            assert!(e.contains(says), "{says}: {e}");
        }
        std::fs::write(parts.join(JOURNAL), journal).unwrap();
        run(scene, Some(&parts), true, true, None).unwrap();
        assert_eq!(timeless(&parts), timeless(&whole));
        assert!(parts.join("runs.jsonl").exists() && !parts.join(JOURNAL).exists());
        std::fs::remove_dir_all(&root).ok();
    }

    #[test]
    fn the_csv_has_the_columns_and_the_table_the_cheapest_settings() {
        let study = Study {
            name: "test".into(),
            rows: vec![
                row("modal", "16 modes", 0.001, 3e-2),
                row("modal", "256 modes", 0.004, 4e-4),
                row("fe", "64 elements", 0.05, 2e-2),
            ],
            references: vec![],
            model_difference: row("modal", "reference", 0.0, 1e-3).errors,
            modal_theory: Some(impact::TheoryName::Timoshenko),
            theory_difference: Some(row("modal", "1024 modes", 0.0, 5e-4).errors),
            structure: false,
        };
        let csv = csv(&study);
        let mut lines = csv.lines();
        assert_eq!(
            lines.next(),
            Some("method,setting,wall_time_s,error_first_duration,error_first_peak_force,error_contact_sequence,error_max_displacement,error_max_stress,energy_balance")
        );
        let first: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
        assert_eq!(first.len(), 9, "{first:?}");
        assert_eq!(first[1], "\"16 modes\"");
        assert!((first[4].parse::<f64>().unwrap_or(0.0) - 3e-2).abs() < 1e-12);
        let t = table(&study);
        assert!(t.contains("cheapest modal setting for 1e-3 on every error: 256 modes"), "{t}");
        assert!(t.contains("cheapest fe setting for 1e-2 on every error: none of these"), "{t}");
        assert!(t.contains("Timoshenko modes loaded on the centre line"), "{t}");
        assert!(t.contains("Euler-Bernoulli modes at the finest setting differ from the modal reference by first contact 5.0e-5 in duration and 5.0e-4 in peak force"), "{t}");
    }
}
