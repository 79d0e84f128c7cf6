//! `cargo xtask beam SCENE.toml`: a beam under prescribed loads (no ball), static or dynamic;
//! the tracked node's history and the final shape as CSV, and a chart of the tracked node; with
//! `--modes-below OMEGA`, the beam's natural modes below OMEGA (rad/s) as well.

use crate::files::{create, read_input, say, OutDir};
use crate::plot::{Chart, Series};
use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use simo_beam::scene::{AnalysisName, BeamScene};
use std::io::Write;
use std::path::Path;

pub(crate) fn run(
    path: &Path,
    out: Option<&Path>,
    modes_below: Option<f64>,
) -> anyhow::Result<bool> {
    let text = read_input(path, "scene file")?;
    let scene = BeamScene::from_toml(&text).with_context(|| format!("in {}", path.display()))?;
    if let Some(omega) = modes_below.filter(|w| !(w.is_finite() && *w > 0.0)) {
        anyhow::bail!("--modes-below {omega}: must be a finite frequency greater than 0 (rad/s)");
    }
    // The folder is named and proven writable before the run.
    let dir = OutDir::create(&crate::files::out_dir("beam", &scene.name, out)?)?;
    let bar = ProgressBar::new(1000);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {percent:>3}% {elapsed} (eta {eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let run = scene
        .run(|fraction| bar.set_position((fraction * 1000.0) as u64))
        .with_context(|| format!("in {}", path.display()))?;
    bar.finish_and_clear();

    let mut history = create(&dir.join("history.csv"))?;
    run.write_history_csv(&mut history)?;
    history.finish()?;
    let mut shape = create(&dir.join("shape.csv"))?;
    run.write_shape_csv(&mut shape)?;
    shape.finish()?;
    let dir = dir.path();

    let (x_label, what) = match scene.analysis {
        AnalysisName::Static => ("load factor (-)", "load path"),
        AnalysisName::Dynamic => ("time (s)", "history"),
    };
    let first = run.history.first().map_or([0.0; 3], |s| s.position);
    let series = ["x", "y", "z"]
        .iter()
        .enumerate()
        .map(|(k, axis)| Series {
            label: format!("{axis} displacement"),
            points: run
                .history
                .iter()
                .map(|s| (s.time_or_load, s.position[k] - first[k]))
                .collect(),
        })
        .collect();
    // A title is SVG text: no control characters from the file.
    let name = impact::study::printable(&run.name);
    let title = format!("{name}: {what} of the node at s = {} m", run.tracked_arc_length);
    Chart {
        title: &title,
        x_label,
        y_label: "displacement (m)",
        series,
        markers: false,
        reference_first: false,
    }
    .write(dir, "tracked-displacement")?;
    let shape = ["x", "y", "z"]
        .iter()
        .enumerate()
        .map(|(k, axis)| Series {
            label: axis.to_string(),
            points: run.shape.iter().map(|n| (n.arc_length, n.position[k])).collect(),
        })
        .collect();
    let title = format!("{name}: final shape");
    Chart {
        title: &title,
        x_label: "arc length (m)",
        y_label: "position (m)",
        series: shape,
        markers: false,
        reference_first: false,
    }
    .write(dir, "final-shape")?;

    let last = run.history.last().map_or([0.0; 3], |s| s.position);
    let rotation = run.history.last().map_or([0.0; 3], |s| s.rotation);
    say!(
        "{}: {} unknowns, {} Newton iterations, {} cut step(s), {:.3} s",
        run.name,
        run.unknowns,
        run.newton_iterations,
        run.cuts,
        run.wall_time
    )?;
    say!(
        "node at s = {} m: final position ({:.6e}, {:.6e}, {:.6e}) m, rotation vector ({:.6e}, {:.6e}, {:.6e}) rad",
        run.tracked_arc_length, last[0], last[1], last[2], rotation[0], rotation[1], rotation[2]
    )?;
    for w in &run.warnings {
        say!("  warning: {w}")?;
    }
    say!(
        "wrote {}/{{history,shape,tracked-displacement,final-shape}}.csv and the two .svg",
        dir.display()
    )?;
    if let Some(omega) = modes_below {
        modes(&scene, omega, dir).with_context(|| format!("in {}", path.display()))?;
    }
    Ok(true)
}

/// The beam's natural modes below `omega` (rad/s), linearised about its undeformed
/// configuration without loads: `modes.csv` (`mode, omega_rad_s, frequency_hz`; a rigid-body
/// mode at 0) and the first few printed.
fn modes(scene: &BeamScene, omega: f64, dir: &Path) -> anyhow::Result<()> {
    let modes = scene.modes_below(omega)?;
    let mut csv = create(&dir.join("modes.csv"))?;
    writeln!(csv, "mode,omega_rad_s,frequency_hz")?;
    for (k, m) in modes.iter().enumerate() {
        writeln!(csv, "{},{:.9e},{:.9e}", k + 1, m.omega, m.omega / std::f64::consts::TAU)?;
    }
    csv.finish()?;
    let first: Vec<String> =
        modes.iter().take(6).map(|m| format!("{:.4}", m.omega / std::f64::consts::TAU)).collect();
    say!(
        "{} natural mode(s) below {omega:e} rad/s (the unloaded beam, linearised): {}{} Hz; wrote {}",
        modes.len(),
        first.join(", "),
        if modes.len() > 6 { ", ..." } else { "" },
        dir.join("modes.csv").display()
    )?;
    Ok(())
}
