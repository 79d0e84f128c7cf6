//! Solving a plan: [`run`] hands it, with its contact law, to the solver of its method.
//!
//! - `modal`: the ball, the beam's modes at the impact point (none on a half-space) and the
//!   law, one scalar implicit equation per contact step, exact propagation between.
//! - `fe`: the ball on the geometrically exact beam ([`BallOnBeam`]), monolithic HHT-alpha;
//! - `refine`: either on doubling meshes or modes until two agree within `solver.tolerance`.
//!
//! A new method is one module here and one arm in [`run`].

mod ball_on_beam;
mod ball_on_beam3d;
mod fe;
mod fe_basis;
mod fe_stress;
mod modal;
mod modal_peak;
mod modal_stress;
mod observe;
mod refine;
mod struck;

pub use ball_on_beam::{BallOnBeam, BallOnBeamConfig};
pub(crate) use ball_on_beam3d::face_rows;
pub use ball_on_beam3d::{BallOnBeam3d, BallOnBeam3dConfig, Face};
pub(crate) use struck::{static_response, static_response_at_rest};

use crate::error::ImpactError;
use crate::outcome::Outcome;
use crate::plan::{Method, Plan};
use std::sync::atomic::{AtomicU64, Ordering};

/// Runs a plan to its end time.
///
/// # Errors
/// `SolverFailed` if a modal step produces a non-finite value (not expected for valid plans);
/// `Integrator` when the fe method's Newton iteration fails even after step halving, with the
/// time reached and the integrator's error as the source.
pub fn run(plan: &Plan) -> Result<Outcome, ImpactError> {
    run_with_progress(plan, &|_| {})
}

/// Something told the fraction of the simulated window done (0 to 1) as a run goes, each time
/// it has moved by a thousandth: a progress bar.
pub type Progress<'a> = &'a (dyn Fn(f64) + Sync);

/// [`run`], telling `progress` how far it has got.
///
/// # Errors
/// As [`run`].
pub fn run_with_progress(plan: &Plan, progress: Progress<'_>) -> Result<Outcome, ImpactError> {
    // The solvers report at every recorded instant (6000 times on the paper's 5 ms modal run),
    // and a progress bar's update takes a lock and reads the clock: passed on at each of them
    // it took 2.3 % of that `simulate` process (perf), passed on only when it moves by a
    // thousandth it is lost in the noise.
    let reported = AtomicU64::new(0);
    let throttled = |fraction: f64| {
        let thousandths = (fraction * 1000.0) as u64;
        if thousandths != reported.load(Ordering::Relaxed) {
            reported.store(thousandths, Ordering::Relaxed);
            progress(fraction);
        }
    };
    let progress: Progress<'_> = &throttled;
    let unchecked = match &plan.method {
        Method::HalfSpace => return plan.law.with(modal::ModalRun { plan, progress }),
        Method::Modal(target) => {
            let out = match target.tolerance {
                Some(tolerance) => refine::run_modal(plan, target, tolerance, progress)?,
                None => plan.law.with(modal::ModalRun { plan, progress })?,
            };
            let out = match target.twin {
                Some(twin) => measure_theory(plan, target, twin, out)?,
                None => out,
            };
            if target.tolerance.is_some() {
                return Ok(out);
            }
            out
        }
        Method::Fe(target) => match target.tolerance {
            Some(tolerance) => return refine::run_fe(plan, target, tolerance, progress),
            None => plan.law.with(fe::FeRun { plan, target, progress })?,
        },
    };
    Ok(warn_unchecked(unchecked))
}

/// What an Euler-Bernoulli run leaves out, measured: the same run with the Timoshenko beam
/// `twin.0` at the modes `out` ended on, its difference from `out` (the worst of
/// [`crate::Differences`]) added to the estimated error (the model's share beside the
/// numerical one) and named in the reasons and a warning; the first-order frequency shift
/// `twin.1` is only the warning's why. The twin's time counts in the wall time.
fn measure_theory(
    plan: &Plan,
    target: &crate::plan::ModalPlan,
    twin: (::modal::Beam, f64),
    mut out: Outcome,
) -> Result<Outcome, ImpactError> {
    let (timoshenko, shift) = twin;
    let modes = out.report.plan.modes;
    let mut other = plan.clone();
    other.method = Method::Modal(crate::plan::ModalPlan {
        basis: crate::plan::ModalBasis::Analytic(timoshenko),
        modes,
        tolerance: None,
        twin: None,
        ..target.clone()
    });
    let measured = plan.law.with(modal::ModalRun { plan: &other, progress: &|_| {} })?.report;
    let d = out.report.differences_from(&measured);
    let worst = if d.same_contacts { d.worst() } else { 1.0 };
    let report = &mut out.report;
    report.wall_time += measured.wall_time;
    report.model_error = Some(worst);
    if let Some(error) = report.estimated_error.as_mut() {
        *error += worst;
    }
    report.plan.reasons.push(format!(
        "model error (beam theory), measured: Timoshenko modes at the same {modes} modes differ by {d}{}",
        if report.estimated_error.is_some() { ", added to the estimated error" } else { "" }
    ));
    // Runs whose significant contacts differ have no relative difference to give: 1 stands
    // for it (model_error), and the warning says what happened.
    let differs = if d.same_contacts {
        format!("differs by {worst:.2e} on the worst of the contacts, the largest displacement and the largest stress")
    } else {
        format!("does not find the same significant contacts (model_error 1 stands for that; where they can be compared: {d})")
    };
    report.warnings.push(format!(
        "solver.beam_theory = \"euler-bernoulli\" leaves out shear and rotary inertia, which lower the frequency the pulse excites most by {:.2} % here (first-order): a Timoshenko run at the same modes {differs} (beam_theory = \"timoshenko\" includes them)",
        100.0 * shift
    ));
    Ok(out)
}

/// A beam run at a fixed resolution: the plan sized it for the first contact, and nothing
/// has checked the later ones (on the paper's tip 128 modes get the first contact to 1e-4 but
/// start the second and third 3 % and 4 % early against 2048). Says so when there are later
/// significant contacts.
fn warn_unchecked(mut out: Outcome) -> Outcome {
    let report = &mut out.report;
    let first_peak = report.contacts.first().map_or(0.0, |c| c.peak_force);
    let later = report
        .contacts
        .iter()
        .skip(1)
        .filter(|c| c.peak_force >= crate::outcome::SIGNIFICANT_PEAK * first_peak)
        .count();
    // How far off they were measured, by method: the fe method's ringing between contacts is
    // integrated (dispersion in space and time), the modal method's is exact per mode.
    let (resolution, size) = match report.plan.method {
        crate::MethodKind::Fe => (
            format!("{} elements at the plan's steps", report.plan.elements),
            "by tens of per cent, and contacts may be added or missed (a review's, the paper's tip over 1 ms at the default 747 elements against 16384 at 8 times the steps: the fourth contact 25 % short, the fifth's peak 50 % off among three contacts the converged run does not have; the first three within 0.4 %)",
        ),
        _ => (
            format!("{} modes", report.plan.modes),
            "by several per cent (on the paper's tip 128 modes start the second and third contacts 3 % and 4 % early against 2048)",
        ),
    };
    if later > 0 && report.estimated_error.is_none() {
        report.warnings.push(format!(
            "{resolution}: nothing checks the {later} later significant contact(s) against a finer run (the default resolution is sized for the first contact), and they may be off {size}: set solver.tolerance (and no modes or elements) to have the resolution refined until they agree"
        ));
    }
    out
}
