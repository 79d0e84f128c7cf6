//! `cargo xtask simulate SCENE.toml`: one scene, a readable summary or JSON.

use crate::files::{claim, create, read_input, say, OutDir};
use anyhow::Context;
use impact::MethodKind;
use std::path::Path;

/// Reads and runs a scene file.
pub(crate) fn load_and_run(path: &Path) -> anyhow::Result<impact::Outcome> {
    load_and_run_with(path, false, false)
}

/// Reads and runs a scene file, recording the beam's field when `field`, or for `plots` where
/// the plan can record one (a `[structure]`'s plots then leave out the stress along it).
fn load_and_run_with(path: &Path, field: bool, plots: bool) -> anyhow::Result<impact::Outcome> {
    let text = read_input(path, "scene file")?;
    let scene =
        impact::Scene::from_toml(&text).with_context(|| format!("in {}", path.display()))?;
    let mut plan = impact::Plan::new(&scene).with_context(|| format!("in {}", path.display()))?;
    if field || (plots && plan.can_record_field()) {
        plan = plan.with_field().with_context(|| format!("in {}", path.display()))?;
    }
    // Said before the run as well as in the report after it (standard error).
    if let Some(warning) = plan.long_run() {
        let line = format!("warning: {warning}\n");
        std::io::Write::write_all(&mut std::io::stderr(), line.as_bytes())?;
    }
    // On standard error, and only on a terminal: --json output stays clean.
    let bar = indicatif::ProgressBar::new(1000);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {percent:>3}% of the simulated window, {elapsed} (eta {eta})",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let outcome = impact::run_with_progress(&plan, &|fraction| {
        bar.set_position((fraction.clamp(0.0, 1.0) * 1000.0) as u64)
    })
    .with_context(|| format!("in {}", path.display()));
    bar.finish_and_clear();
    // A run that fails prints no report: its plan (the mesh, the steps, their warnings) is
    // what a user needs to see why, so it goes to standard error before the error.
    if outcome.is_err() {
        let summary = plan.summary();
        let mut text = format!("the plan the run failed on ({}):\n", path.display());
        for reason in &summary.reasons {
            text += &format!("  - {reason}\n");
        }
        for warning in plan.warnings() {
            text += &format!("  warning: {warning}\n");
        }
        std::io::Write::write_all(&mut std::io::stderr(), text.as_bytes())?;
    }
    outcome
}

/// What `simulate` writes besides its report.
pub(crate) struct Outputs<'a> {
    pub json: bool,
    pub history: Option<&'a Path>,
    pub field: Option<&'a Path>,
    pub plots: Option<&'a Path>,
}

pub(crate) fn run(path: &Path, outputs: &Outputs<'_>) -> anyhow::Result<bool> {
    // The scene is read (and so registered as an input) before any output is opened: an
    // output that names it is refused before it could be emptied.
    read_input(path, "scene file")?;
    // Every output is claimed against the others (the same file twice, a file inside the
    // plots folder) and opened as a new temporary file (or its folder proven writable) before
    // the run: a path that cannot be written fails now, not after the simulation, and an
    // existing file is replaced only when the run has succeeded.
    for (path, folder, what) in [
        (outputs.history, false, "--history"),
        (outputs.field, false, "--field"),
        (outputs.plots, true, "--plots"),
    ] {
        if let Some(path) = path {
            claim(path, folder, what)?;
        }
    }
    let history = outputs.history.map(create).transpose()?;
    let field_file = outputs.field.map(create).transpose()?;
    let plots = outputs.plots.map(OutDir::create).transpose()?;
    let outcome = load_and_run_with(path, outputs.field.is_some(), plots.is_some())?;
    if let (Some(mut file), Some(h)) = (history, outputs.history) {
        outcome
            .history
            .write_csv(&mut file)
            .with_context(|| format!("cannot write {}", h.display()))?;
        file.finish()?;
    }
    if let (Some(mut file), Some(f), Some(field)) = (field_file, outputs.field, &outcome.field) {
        field.write_csv(&mut file).with_context(|| format!("cannot write {}", f.display()))?;
        file.finish()?;
    }
    if let Some(dir) = &plots {
        crate::plots::one_run(dir.path(), &outcome)?;
    }
    let json = outputs.json;
    let r = &outcome.report;
    if json {
        say!("{}", serde_json::to_string_pretty(r)?)?;
        return Ok(true);
    }
    let resolution = crate::plots::resolution(&r.plan);
    // The fe method's contact step grows from the plan's; the others' (adaptive) stays below.
    let bound = if r.plan.method == MethodKind::Fe { "from" } else { "up to" };
    say!(
        "{}: {} model, {resolution}, contact law {}, contact step {bound} {:.3e} s",
        r.name,
        r.plan.method,
        r.plan.contact_law,
        r.plan.time_step
    )?;
    for reason in &r.plan.reasons {
        say!("  - {reason}")?;
    }
    for w in &r.warnings {
        say!("  warning: {w}")?;
    }
    say!("impact speed {:.4} m/s; {} contact(s)", r.impact_speed, r.contact_count)?;
    say!(
        "  {:>3} {:>12} {:>12} {:>12} {:>12} {:>10} {:>10} {:>10} {:>10} {:>9}",
        "#",
        "start (us)",
        "length (us)",
        "peak F (N)",
        "approach (um)",
        "v in",
        "v out",
        "print (mm)",
        "p0 (MPa)",
        "a (mm)"
    )?;
    for (i, c) in r.contacts.iter().enumerate().take(40) {
        say!(
            "  {:>3} {:>12.3} {:>12.3}{} {:>12.3} {:>12.4} {:>10.4} {:>10.4} {:>10.4} {:>10.1} {:>9.4}",
            i + 1,
            c.start * 1e6,
            c.duration * 1e6,
            if c.complete { " " } else { "+" },
            c.peak_force,
            c.max_approach * 1e6,
            c.ball_velocity_before,
            c.ball_velocity_after,
            c.print_radius * 1e3,
            c.max_pressure * 1e-6,
            c.contact_radius * 1e3
        )?;
    }
    if r.contact_count > 40 {
        say!("  ... {} more", r.contact_count - 40)?;
    }
    match r.restitution {
        Some(e) => say!("restitution (first contact) {e:.5}")?,
        None => say!(
            "restitution: the first contact had not ended (a longer solver.end_time holds it)"
        )?,
    }
    say!(
        "max displacement at the impact point {:.4e} m at t = {:.4e} s",
        r.max_displacement,
        r.max_displacement_time
    )?;
    if let Some(b) = &r.bending_stress {
        let x = crate::plots::along(&r.plan).0;
        let ratio =
            b.yield_ratio.map_or_else(String::new, |y| format!(", {y:.3} of the yield stress"));
        say!(
            "largest bending stress {:.4e} Pa ({}) at {x} = {:.4} m, t = {:.4e} s{ratio}{}",
            b.max,
            if b.value >= 0.0 {
                "tension on the struck face"
            } else {
                "compression on the struck face"
            },
            b.position,
            b.time,
            if b.at_window_end { " (at the window's end: not yet the maximum)" } else { "" }
        )?;
        for s in &b.supports {
            say!(
                "  at the support {x} = {} m: {:.4e} Pa, t = {:.4e} s",
                s.position,
                s.max,
                s.time
            )?;
        }
    }
    // Twist lines only where something twisted: a centred strike on a structure's modes
    // reports exact zeros, a plane frame struck in its plane the modes' round-off (1e-14 rad,
    // 1e-5 Pa against 1e7 of bending: a review's); positions named as the stress's are.
    let x = crate::plots::along(&r.plan).0;
    let arc = if r.plan.structure { " (arc length)" } else { "" };
    const ROUND_OFF_TWIST: f64 = 1e-9;
    let bending = r.bending_stress.as_ref().map_or(0.0, |b| b.max);
    if let (Some(twist), Some(t)) = (r.max_twist.filter(|w| *w > ROUND_OFF_TWIST), r.max_twist_time)
    {
        say!("largest twist of the struck section {twist:.4e} rad at t = {t:.4e} s")?;
    }
    if let Some(w) = r.largest_twist.as_ref().filter(|w| w.max > ROUND_OFF_TWIST) {
        say!(
            "largest twist anywhere {:.4e} rad at {x} = {:.4} m{arc}, t = {:.4e} s",
            w.max,
            w.position,
            w.time
        )?;
    }
    if let Some(w) = r.torsion_shear.as_ref().filter(|w| w.max > ROUND_OFF_TWIST * bending) {
        say!(
            "largest torsion shear stress {:.4e} Pa at {x} = {:.4} m{arc}, t = {:.4e} s",
            w.max,
            w.position,
            w.time
        )?;
    }
    if let Some(f) = r.equivalent_static_force {
        say!(
            "equivalent static force {f:.4} N (static stiffness {:.4e} N/m)",
            r.static_stiffness.unwrap_or(f64::NAN)
        )?;
    }
    let e = &r.energy;
    say!(
        "energy (J): initial {:.6e}; ball kinetic {:.6e}, potential {:.6e}; beam {:.6e}; contact {:.6e}; dissipated {:.6e}; numerical dissipation {:.6e}; balance error {:.2e} ({:.1e} of initial)",
        e.initial, e.ball_kinetic, e.ball_potential, e.beam, e.contact_stored, e.dissipated, e.numerical_dissipation, e.balance_error, e.balance_error / e.initial
    )?;
    say!("wall time {:.4} s", r.wall_time)?;
    Ok(true)
}
