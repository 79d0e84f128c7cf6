//! # impact: a ball striking a beam or a structure of beams, end to end
//!
//! Reads a scene (TOML, SI units), plans the model it needs, couples the ball, the beam and the
//! contact law, and reports every contact, the energy ledger, the largest displacement and the
//! equivalent static force, the stresses and, off the centreline, the twist.
//!
//! **Model (modal path).** Goldsmith's method (Goldsmith, *Impact*, 1960, Ch. 4; the paper's
//! eqs. 1-4): the ball is a point mass m with a Hertzian surface, u'' = g - F/m; the beam is
//! its first N Euler-Bernoulli modes at the impact point, w = sum g_n q_n; the approach is
//! delta = u - w (positive in compression) and the force F = law(delta, delta-dot). Each step
//! holds F linear in time and propagates ball and modes exactly, so the end approach is affine
//! in the end force and the step is one scalar monotone equation. Contact onset and separation
//! are located by root finding; free flight jumps ahead by conservative advancement; the
//! scheme is second order in the contact step. Off the centreline (`impact.offset`) the basis
//! adds the beam's Saint-Venant torsion modes, each seen at the struck face through the offset.
//!
//! **Model (fe path).** The ball on a geometrically exact Simo beam, one monolithic HHT-alpha
//! system: in the plane ([`BallOnBeam`]) for a centred strike, in 3D ([`BallOnBeam3d`]) off the
//! centreline and for a `[structure]` of segments; for large deflections, masses and springs,
//! and structures, where the modal beam does not hold.
//!
//! **Data path.** `scene` (what a user writes, serde only) -> [`Plan::new`] (validated, every
//! choice made with its reason: [`Method`], [`Law`], steps) -> [`run`] (the solver of the
//! method, generic over the contact law) -> [`Outcome`] ([`Report`] and [`History`]). The
//! events module (onset and separation, refined peaks, the contact recorder) is shared by
//! both solvers. ARCHITECTURE.md at the repository root draws the whole picture.
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
//! // validation/REFERENCES.md 2.2: t_c = 69.1104 us.
//! assert!((outcome.report.contacts[0].duration - 6.91104e-5).abs() < 1e-9);
//! # Ok::<(), impact::ImpactError>(())
//! ```

mod error;
mod events;
mod law;
mod outcome;
pub mod plan;
mod scene;
mod solve;
pub mod study;

pub use error::ImpactError;
pub use law::Law;
pub use outcome::{
    BendingStress, Contact, Differences, Energy, Field, History, Outcome, Report, Sample,
    SupportStress, Twist, PULSE_FRACTION, SIGNIFICANT_PEAK,
};
pub use plan::{FePlan, Method, MethodKind, ModalPlan, Plan, PlanSummary};
pub use scene::{
    BallSpec, BeamSpec, ContactSpec, FeModelName, HalfSpaceSpec, ImpactSpec, LawName, MassSpec,
    MethodName, ModalBasisName, RotaryInertia, Scene, SolverSpec, SpringSpec, StructureSpec,
    StructureSpringSpec, SupportName, TheoryName,
};
pub use solve::{
    run, run_with_progress, BallOnBeam, BallOnBeam3d, BallOnBeam3dConfig, BallOnBeamConfig, Face,
    Progress,
};

/// Plans and runs a scene.
///
/// # Errors
/// Any validation error of [`Plan::new`] or solver error of [`run`].
pub fn simulate(scene: &Scene) -> Result<Outcome, ImpactError> {
    run(&Plan::new(scene)?)
}

/// [`simulate`], telling `progress` the fraction of the window done as it goes.
///
/// # Errors
/// As [`simulate`].
pub fn simulate_with_progress(
    scene: &Scene,
    progress: Progress<'_>,
) -> Result<Outcome, ImpactError> {
    run_with_progress(&Plan::new(scene)?, progress)
}
