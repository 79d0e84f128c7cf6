//! # impact: a ball striking a beam, end to end
//!
//! Reads a scene (TOML, SI units), plans the model it needs, couples the ball, the beam and the
//! contact law, and reports every contact, the energy ledger, the largest displacement and the
//! equivalent static force.
//!
//! **Model (modal path).** Goldsmith's method (Goldsmith, *Impact*, 1960, Ch. 4; the paper's
//! eqs. 1-4): the ball is a point mass m with a Hertzian surface, u'' = g - F/m; the beam is
//! its first N Euler-Bernoulli modes at the impact point, w = sum g_n q_n; the approach is
//! delta = u - w (positive in compression) and the force F = law(delta, delta-dot). Each step
//! holds F linear in time and propagates ball and modes exactly, so the end approach is affine
//! in the end force and the step is one scalar monotone equation. Contact onset and separation
//! are located by root finding; free flight jumps ahead by conservative advancement. See
//! [`modal_solver`] for the scheme and its error (second order in the contact step).
//!
//! **Conventions.** SI units. The impact direction is positive: ball velocities toward the
//! beam and beam displacements away from the ball are positive; a rebounding ball has a
//! negative velocity. Time starts at first touch.
//!
//! ```
//! let scene = impact::Scene::from_toml(r#"
//!     name = "steel ball on a steel block"
//!     [half_space]
//!     youngs_modulus = 2.1e11
//!     poisson_ratio = 0.3
//!     [ball]
//!     radius = 0.01
//!     youngs_modulus = 2.1e11
//!     poisson_ratio = 0.3
//!     density = 7850.0
//!     [impact]
//!     speed = 1.0
//!     gravity = false
//! "#)?;
//! let outcome = impact::simulate(&scene)?;
//! // REFERENCES.md 2.2: t_c = 69.1104 us.
//! assert!((outcome.report.contacts[0].duration - 6.91104e-5).abs() < 1e-9);
//! # Ok::<(), impact::ImpactError>(())
//! ```

pub mod beam_scene;
mod error;
pub mod fe_solver;
mod history;
mod illinois;
pub mod modal_solver;
mod plan;
mod report;
mod scene;

pub use beam_scene::{BeamRun, BeamScene};
pub use error::ImpactError;
pub use history::{History, Sample};
pub use modal_solver::{run, Outcome};
pub use plan::{
    FeTarget, Law, Plan, PlanSummary, Target, DEFAULT_SAMPLES_PER_PULSE, FE_ALPHA,
    FE_SAMPLES_PER_PULSE, GRAVITY, LARGE_DEFLECTION, MODE_CUTOFF,
};
pub use report::{Contact, Energy, Report};
pub use scene::{
    BallSpec, BeamSpec, ContactSpec, HalfSpaceSpec, ImpactSpec, LawName, MethodName, Scene,
    SolverSpec, SupportName,
};

/// Plans and runs a scene.
///
/// # Errors
/// Any validation error of [`Plan::new`] or solver error of [`run`].
pub fn simulate(scene: &Scene) -> Result<Outcome, ImpactError> {
    run(&Plan::new(scene)?)
}
