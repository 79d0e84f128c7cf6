//! # hht: HHT-alpha and generalized-alpha time integration
//!
//! Integrates `I(q, v, a) + g(t, q, v) = 0`, where `I` is the inertial force (`M a` plus, for
//! rotating bodies, the gyroscopic term) and `g` the rest of the force balance (internal plus
//! damping minus external), over a configuration `q` that may hold rotations: the [`Model`]
//! owns the update `q <- q (+) dq`, velocities and accelerations live in its tangent space.
//!
//! ## The scheme
//! The generalized-alpha family (Chung & Hulbert 1993), REFERENCES.md 4.4:
//!
//! `(1 - alpha_m) I_{n+1} + alpha_m I_n + (1 - alpha_f) g_{n+1} + alpha_f g_n = 0`,
//! with Newmark's updates for displacement and velocity. HHT-alpha, the paper's eq. (9), is
//! `alpha_m = 0`, `alpha_f = -alpha`, `alpha` in `[-1/3, 0]`, `beta = (1 - alpha)^2 / 4`,
//! `gamma = 1/2 - alpha` ([`Scheme::hht`]). That pins the sign convention of Hilber, Hughes &
//! Taylor (1977): new-time weight `1 + alpha`, old-time weight `-alpha` (REFERENCES.md 4.1; the
//! paper's `+ alpha F_n` is a transcription slip). Positive alpha is refused: with these beta and
//! gamma it is unstable (4.3).
//!
//! ## Newton
//! The unknown is the configuration increment over the step. The Newton matrix is
//! `(1 - alpha_m)(M/(beta h^2) + C_I gamma/(beta h) + K_I) + (1 - alpha_f)(C gamma/(beta h) + K)`,
//! assembled by the model from [`NewtonWeights`] into a fixed sparsity pattern and factorised with
//! faer's sparse LU, whose symbolic analysis is done once ([`SparseLu`]). The residual test is
//! relative to the size of the force terms, with a round-off floor set by the model's
//! [`Model::force_scale`], so a beam
//! with EA/EI ~ 1e6 converges without tuning. A failed step is halved (recursively), and
//! [`HhtError::NewtonDiverged`] says when and how badly it failed if that does not help.
//! Stepping is caller-driven with any step size; [`StepReport::error_estimate`] lets a caller
//! adapt it.
//!
//! ## Example
//! ```
//! use hht::{Integrator, NewtonOptions, Oscillator, Scheme};
//! use faer::Col;
//!
//! // Unit-mass oscillator, omega = 2 pi (period 1 s), released from d = 1.
//! let model = Oscillator::undamped(2.0 * std::f64::consts::PI)?;
//! let mut integrator = Integrator::new(Scheme::hht(-0.1)?, NewtonOptions::default());
//! let mut state = integrator.initial_state(&model, 0.0, 1.0, Col::zeros(1))?;
//! for _ in 0..1000 {
//!     integrator.step(&model, &mut state, 1e-3)?;
//! }
//! // One period later the oscillator is back near d = 1 (period error ~ 1e-5 at omega h = 0.006).
//! assert!((state.q - 1.0).abs() < 1e-3);
//! # Ok::<(), hht::HhtError>(())
//! ```

mod error;
mod integrator;
mod linear;
mod model;
mod oscillator;
mod scheme;
mod spectral;

pub use error::HhtError;
pub use integrator::{Integrator, NewtonOptions, State, StepReport, ROUND_OFF_FACTOR};
pub use linear::SparseLu;
pub use model::{Model, NewtonWeights, Triplets};
pub use oscillator::Oscillator;
pub use scheme::Scheme;
pub use spectral::{amplification, spectrum, Spectrum};
