//! Solving a plan: [`run`] hands it, with its contact law, to the solver of its method.
//!
//! - `modal`: the ball, the beam's modes at the impact point (none on a half-space) and the
//!   law, one scalar implicit equation per contact step, exact propagation between.
//! - `fe`: the ball on the geometrically exact beam ([`BallOnBeam`]), monolithic HHT-alpha;
//!   `refine`: the same on doubling meshes until two agree within `solver.tolerance`.
//!
//! A new method is one module here and one arm in [`run`].

mod ball_on_beam;
mod fe;
mod modal;
mod refine;

pub use ball_on_beam::{BallOnBeam, BallOnBeamConfig};

use crate::error::ImpactError;
use crate::outcome::Outcome;
use crate::plan::{Method, Plan};

/// Runs a plan to its end time.
///
/// # Errors
/// `SolverFailed` if a modal step produces a non-finite value (not expected for valid plans);
/// `Integrator` when the fe method's Newton iteration fails even after step halving, with the
/// time reached and the integrator's error as the source.
pub fn run(plan: &Plan) -> Result<Outcome, ImpactError> {
    run_with_progress(plan, &|_| {})
}

/// Something told the fraction of the simulated window done (0 to 1) as a run goes, at every
/// recorded instant: a progress bar.
pub type Progress<'a> = &'a (dyn Fn(f64) + Sync);

/// [`run`], telling `progress` how far it has got.
///
/// # Errors
/// As [`run`].
pub fn run_with_progress(plan: &Plan, progress: Progress<'_>) -> Result<Outcome, ImpactError> {
    match &plan.method {
        Method::HalfSpace | Method::Modal(_) => plan.law.with(modal::ModalRun { plan, progress }),
        Method::Fe(target) => match target.tolerance {
            Some(tolerance) => refine::run(plan, target, tolerance, progress),
            None => plan.law.with(fe::FeRun { plan, target, progress }),
        },
    }
}
