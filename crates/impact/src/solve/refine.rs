//! The fe method to a tolerance: uniform meshes of [`FE_LADDER_START`] elements, doubled until
//! the last two agree.
//!
//! The element is second order in its size (the paper's tip: the second contact's start moves
//! 8.85, 2.03 and 0.49 us from 256 to 512, 1024 and 2048 elements, ratios 4.4 and 4.1), so the
//! finer of two meshes carries about a third of their difference (Richardson). Compared are
//! every significant contact (a peak force of at least [`SIGNIFICANT_PEAK`] of the first's, in
//! the finer run): its start (after the first), its duration (when it ended within the
//! window in both runs) and its peak force, and the largest displacement, each relative to the
//! finer run's value. Two runs that do not find the same significant contacts have not
//! converged. The time steps stay the plan's (the contact step t_c / 200 resolves the pulses far
//! below 1e-3; what the mesh decides is how the waves between contacts travel).

use super::fe::FeRun;
use super::Progress;
use crate::error::ImpactError;
use crate::outcome::{Outcome, Report};
use crate::plan::{uniform, FePlan, Plan, FE_LADDER_END};

/// Contacts whose peak force is below this fraction of the first contact's are not compared:
/// the paper's tip has a third contact at 8.6e-3 of the first's peak that a user reads, and
/// grazes of 1e-4 whose count changes with the mesh.
pub(crate) const SIGNIFICANT_PEAK: f64 = 1e-3;

/// Runs `target` on doubling uniform meshes until the estimated relative error of the finer
/// is within `tolerance` (or the mesh reaches [`FE_LADDER_END`] elements, with a warning).
pub(super) fn run(
    plan: &Plan,
    target: &FePlan,
    tolerance: f64,
    progress: Progress<'_>,
) -> Result<Outcome, ImpactError> {
    let clock = std::time::Instant::now();
    let length = target.analytic.length();
    let mut elements = target.elements();
    let mut ladder: Vec<String> = Vec::new();
    let mut coarse: Option<Outcome> = None;
    loop {
        let mut mesh = target.clone();
        mesh.nodes = uniform(length, elements);
        let fine = plan.law.with(FeRun { plan, target: &mesh, progress })?;
        let error =
            coarse.as_ref().map_or(f64::INFINITY, |c| estimated_error(&c.report, &fine.report));
        ladder.push(format!("{elements} ({:.3} s)", fine.report.wall_time));
        let met = error <= tolerance;
        if met || elements >= FE_LADDER_END {
            let mut out = fine;
            let report = &mut out.report;
            report.plan.elements = elements;
            report.plan.reasons.push(format!(
                "meshes of {} elements: the last two agree within {error:.2e} (estimated error of the finer, Richardson, second order){}",
                ladder.join(", "),
                if met { format!(" <= tolerance {tolerance}") } else { String::new() }
            ));
            if !met {
                report.warnings.push(format!(
                    "solver.tolerance = {tolerance} not met: {elements} elements (the most this refinement takes) leave an estimated error of {error:.2e}"
                ));
            }
            report.estimated_error = error.is_finite().then_some(error);
            report.wall_time = clock.elapsed().as_secs_f64();
            return Ok(out);
        }
        coarse = Some(fine);
        elements *= 2;
    }
}

/// The estimated relative error of `fine`: a third of the largest relative difference from
/// `coarse` over the compared quantities (see the module text), infinite when they do not
/// find the same significant contacts.
pub(crate) fn estimated_error(coarse: &Report, fine: &Report) -> f64 {
    let first_peak = fine.contacts.first().map_or(0.0, |c| c.peak_force);
    let significant = |r: &Report| {
        r.contacts.iter().filter(|c| c.peak_force >= SIGNIFICANT_PEAK * first_peak).count()
    };
    let count = significant(fine);
    if count == 0 || significant(coarse) != count {
        return f64::INFINITY;
    }
    let relative = |a: f64, b: f64| if b == 0.0 { 0.0 } else { ((a - b) / b).abs() };
    let pairs = fine
        .contacts
        .iter()
        .filter(|c| c.peak_force >= SIGNIFICANT_PEAK * first_peak)
        .zip(coarse.contacts.iter().filter(|c| c.peak_force >= SIGNIFICANT_PEAK * first_peak));
    let mut worst = relative(coarse.max_displacement, fine.max_displacement);
    for (i, (f, c)) in pairs.enumerate() {
        worst = worst.max(relative(c.peak_force, f.peak_force));
        if i > 0 {
            worst = worst.max(relative(c.start, f.start));
        }
        if f.complete && c.complete {
            worst = worst.max(relative(c.duration, f.duration));
        }
    }
    worst / 3.0
}
