//! # hht: HHT-alpha and generalized-alpha time integration
//!
//! Integrates `I(q, v, a) + g(t, q, v) = 0`, where `I` is the inertial force (`M a` plus, for
//! rotating bodies, the gyroscopic term) and `g` the rest of the force balance (internal plus
//! damping minus external), over a configuration `q` that may hold rotations: the [`Model`]
//! owns the update `q <- q (+) dq`, velocities and accelerations live in its tangent space.
//!
//! ## The scheme
//! The generalized-alpha family (Chung & Hulbert 1993), validation/REFERENCES.md 4.4:
//!
//! `(1 - alpha_m) I_{n+1} + alpha_m I_n + (1 - alpha_f) g_{n+1} + alpha_f g_n = 0`,
//! with Newmark's updates for displacement and velocity. HHT-alpha, the paper's eq. (9), is
//! `alpha_m = 0`, `alpha_f = -alpha`, `alpha` in `[-1/3, 0]`, `beta = (1 - alpha)^2 / 4`,
//! `gamma = 1/2 - alpha` ([`Scheme::hht`]). That pins the sign convention of Hilber, Hughes &
//! Taylor (1977): new-time weight `1 + alpha`, old-time weight `-alpha` (validation/REFERENCES.md 4.1; the
//! paper's `+ alpha F_n` is a transcription slip). Positive alpha is refused: with these beta and
//! gamma it is unstable (4.3).
//!
//! ## Newton
//! The unknown is the configuration increment over the step. The Newton matrix is
//! `(1 - alpha_m)(M/(beta h^2) + C_I gamma/(beta h) + K_I) + (1 - alpha_f)(C gamma/(beta h) + K)`,
//! assembled by the model from [`NewtonWeights`] into a fixed sparsity pattern and factorised with
//! faer's sparse LU, whose symbolic analysis is done once ([`SparseLu`]), or, for a model that
//! declares a banded matrix with a dense border ([`Model::band`]: a beam and a ball), with
//! [`BandedLu`]. The residual test is
//! relative to the size of the force terms, with a round-off floor set by the model's
//! [`Model::force_scale`], so a beam
//! with EA/EI ~ 1e6 converges without tuning. A failed step is halved (recursively), and
//! [`HhtError::NewtonDiverged`] says when and how badly it failed if that does not help.
//! Stepping is caller-driven with any step size; [`StepReport::error_estimate`] lets a caller
//! adapt it; [`Integrator::advance`] tries a step from a state it leaves as it is.
//!
//! ## Speed
//! The step's vector work and the banded substitution run in [`fast`] kernels: compiled for
//! the baseline and again for AVX2 with fused multiply-adds, the second chosen at run time
//! where the processor has it (same results to rounding; the beams' element passes a third
//! time for AVX-512, [`fast::run_wide`]); the sweeps the compiler leaves
//! scalar are written on pulp's vectors ([`fast::Lanes`]), as few as the step allows (each
//! streams its vectors from the second-level cache: the predictor is read where it is, a
//! correction and Newmark's kinematics are one sweep, and so are a balance and the step's
//! closing sums). With
//! [`NewtonOptions::reuse_factorisation`] a Newton matrix serves the steps of its size, and
//! the last one of another size is kept aside for when that size comes back. A model with a
//! constant mass matrix ([`Model::constant_mass`]) spares the predictor's mass product, one
//! whose inertial force is a mass product but for a term in the velocity recomputes only that
//! term's rows for the predictor ([`Model::predicted_inertial_force`]), and one that writes
//! `q (+) dq` into a kept configuration in one pass ([`Model::displaced`]) the copy of `q` an
//! iteration. A model that splits its Newton matrix into a slow part (a structure's stiffness)
//! and a fast one (a contact, [`Model::tangent_parts`]) has a matrix for a new step size built
//! from the kept slow part re-weighted, without its stiffness.
//!
//! ## Example: your own model
//! A hard (Duffing) spring, `a + q + 100 q^3 = 0`, released from `q = 1`. The model gives the
//! inertial force, the rest of the force balance and the Newton matrix from the weights the
//! integrator hands it: `w.inertia * w.da * M + w.force * (w.dq * K + w.dv * C)`.
//! ```
//! use faer::{Col, ColMut, ColRef};
//! use hht::{Integrator, Model, NewtonOptions, NewtonWeights, Scheme, State, Triplets};
//!
//! struct Duffing;
//!
//! impl Model for Duffing {
//!     type Config = f64;
//!     fn ndof(&self) -> usize {
//!         1
//!     }
//!     fn update(&self, q: &mut f64, dq: ColRef<'_, f64>) {
//!         *q += dq[0];
//!     }
//!     fn inertial_force(&self, _q: &f64, _v: ColRef<'_, f64>, a: ColRef<'_, f64>, mut out: ColMut<'_, f64>) {
//!         out[0] = a[0]; // unit mass
//!     }
//!     fn net_force(&self, _t: f64, q: &f64, _v: ColRef<'_, f64>, mut out: ColMut<'_, f64>) {
//!         out[0] = q + 100.0 * q.powi(3); // internal force, no external load
//!     }
//!     fn tangent(&self, _t: f64, q: &f64, _v: ColRef<'_, f64>, _a: ColRef<'_, f64>, w: NewtonWeights, out: &mut Triplets) {
//!         out.push(0, 0, w.inertia * w.da + w.force * w.dq * (1.0 + 300.0 * q * q));
//!     }
//! }
//!
//! let energy = |s: &State<f64>| 0.5 * s.v[0] * s.v[0] + 0.5 * s.q * s.q + 25.0 * s.q.powi(4);
//! let mut integrator = Integrator::new(Scheme::hht(-0.2)?, NewtonOptions::default());
//! let mut state = integrator.initial_state(&Duffing, 0.0, 1.0, Col::zeros(1))?;
//! let e0 = energy(&state);
//! let mut largest = e0;
//! for _ in 0..2000 {
//!     let report = integrator.step(&Duffing, &mut state, 2e-3)?;
//!     assert!(report.iterations <= 6); // Newton converges in a few iterations
//!     largest = largest.max(energy(&state));
//! }
//! // Four seconds later (about 20 periods): the energy oscillates within the period error
//! // (omega h ~ 0.035) and HHT's numerical damping (alpha = -0.2) takes a little of it.
//! assert!(largest <= e0 * (1.0 + 1e-3));
//! assert!(energy(&state) < e0 && energy(&state) > 0.99 * e0);
//! # Ok::<(), hht::HhtError>(())
//! ```
//!
//! [`Oscillator`] is the same for a linear oscillator, ready made.

mod banded;
mod error;
pub mod fast;
mod integrator;
mod linear;
mod model;
mod oscillator;
mod scheme;
mod spectral;

pub use banded::{Band, BandedLu};
pub use error::HhtError;
pub use integrator::{
    Integrator, NewtonOptions, State, StepReport, ROUND_OFF_FACTOR, STALE_CONTRACTION,
};
pub use linear::SparseLu;
pub use model::{Model, NewtonWeights, Triplets};
pub use oscillator::Oscillator;
pub use scheme::Scheme;
pub use spectral::{amplification, spectrum, Spectrum};
