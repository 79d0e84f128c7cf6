//! Caller-driven stepping with Newton's method.

use crate::error::HhtError;
use crate::linear::SparseLu;
use crate::model::{Model, NewtonWeights, Triplets};
use crate::scheme::Scheme;
use faer::Col;

/// Newton's iteration settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonOptions {
    /// Iterations before a step attempt is declared diverged.
    pub max_iterations: usize,
    /// Relative residual tolerance: the residual norm must fall below `rtol` times the size of
    /// the force terms in the balance (inertial, net, old-time), plus the round-off floor
    /// [`ROUND_OFF_FACTOR`] x eps x [`Model::force_scale`].
    pub rtol: f64,
    /// Absolute residual tolerance (model units), added to the relative one.
    pub atol: f64,
    /// How many times a failed step may be halved (each half stepped separately) before
    /// [`HhtError::NewtonDiverged`] is returned.
    pub max_halvings: usize,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self { max_iterations: 20, rtol: 1e-10, atol: 0.0, max_halvings: 8 }
    }
}

/// The state at one time: configuration, velocity, acceleration, and the force terms of the
/// balance at that time (the next step weights them with `alpha_m` and `alpha_f`).
#[derive(Debug, Clone)]
pub struct State<C> {
    /// Time (s).
    pub t: f64,
    /// Configuration.
    pub q: C,
    /// Velocity (tangent space of `q`).
    pub v: Col<f64>,
    /// Acceleration (tangent space of `q`).
    pub a: Col<f64>,
    inertial: Col<f64>,
    net: Col<f64>,
}

impl<C> State<C> {
    /// A state with a given acceleration `a` (not solved from the balance): for studies of the
    /// scheme itself (amplification matrices) and for restarting from saved states.
    ///
    /// # Errors
    /// [`HhtError::Model`] if `v` or `a` has the wrong length.
    pub fn new<M: Model<Config = C>>(
        model: &M,
        t: f64,
        q: C,
        v: Col<f64>,
        a: Col<f64>,
    ) -> Result<Self, HhtError> {
        let n = model.ndof();
        if v.nrows() != n || a.nrows() != n {
            return Err(HhtError::Model(format!(
                "velocity and acceleration need {n} entries, got {} and {}",
                v.nrows(),
                a.nrows()
            )));
        }
        let mut inertial = Col::<f64>::zeros(n);
        let mut net = Col::<f64>::zeros(n);
        model.inertial_force(&q, v.as_ref(), a.as_ref(), inertial.as_mut());
        model.net_force(t, &q, v.as_ref(), net.as_mut());
        Ok(Self { t, q, v, a, inertial, net })
    }
}

/// What one call of [`Integrator::step`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepReport {
    /// Newton iterations, summed over substeps.
    pub iterations: usize,
    /// Residual norm at convergence (largest over substeps).
    pub residual_norm: f64,
    /// Local error estimate of the displacement, `h^2 |beta - 1/6| ||a_{n+1} - a_n||`
    /// (Zienkiewicz & Xie 1991), same units as the configuration increment. Largest over
    /// substeps. A caller can grow or shrink `h` to keep it near a target.
    pub error_estimate: f64,
    /// Substeps taken: 1 unless Newton failed and the step was halved.
    pub substeps: usize,
}

/// HHT-alpha / generalized-alpha integrator. It owns the Newton work space and the sparse LU
/// (symbolic analysis reused across steps); the caller owns the [`State`].
#[derive(Debug)]
pub struct Integrator {
    scheme: Scheme,
    options: NewtonOptions,
    lu: SparseLu,
    triplets: Triplets,
    /// Newton matrices factorised so far.
    pub factorisations: usize,
}

/// The residual norm cannot fall below about this many ulps of the model's force scale (the
/// sum of a few large internal force terms that cancel) times the square root of the number of
/// unknowns (independent round-off per equation); see [`Model::force_scale`].
pub const ROUND_OFF_FACTOR: f64 = 64.0;

fn norm(x: &Col<f64>) -> f64 {
    x.norm_l2()
}

impl Integrator {
    /// An integrator for `scheme` (see [`Scheme::hht`], [`Scheme::generalized_alpha`]).
    pub fn new(scheme: Scheme, options: NewtonOptions) -> Self {
        Self { scheme, options, lu: SparseLu::new(), triplets: Triplets::new(), factorisations: 0 }
    }

    /// The scheme in use.
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }

    /// Symbolic factorisations done so far (1 for a model with a fixed pattern).
    pub fn symbolic_factorisations(&self) -> usize {
        self.lu.symbolic_count
    }

    /// The state at time `t` with configuration `q` and velocity `v`; the acceleration solves
    /// `M a = -(I(q, v, 0) + g(t, q, v))` so the balance holds at the start.
    ///
    /// # Errors
    /// [`HhtError::Model`] if `v` has the wrong length, [`HhtError::Singular`] if the mass
    /// matrix cannot be factorised.
    pub fn initial_state<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        q: M::Config,
        v: Col<f64>,
    ) -> Result<State<M::Config>, HhtError> {
        let n = model.ndof();
        if v.nrows() != n {
            return Err(HhtError::Model(format!(
                "velocity has {} entries, the model {n}",
                v.nrows()
            )));
        }
        let zero = Col::<f64>::zeros(n);
        let mut inertial = Col::<f64>::zeros(n);
        let mut net = Col::<f64>::zeros(n);
        model.inertial_force(&q, v.as_ref(), zero.as_ref(), inertial.as_mut());
        model.net_force(t, &q, v.as_ref(), net.as_mut());
        let rhs = -(&inertial + &net);
        let a = if n == 0 {
            zero
        } else {
            self.triplets.clear();
            model.tangent(
                t,
                &q,
                v.as_ref(),
                zero.as_ref(),
                NewtonWeights::mass(),
                &mut self.triplets,
            );
            self.lu.factor(n, &self.triplets, t)?;
            self.lu.solve(&rhs, t)?
        };
        model.inertial_force(&q, v.as_ref(), a.as_ref(), inertial.as_mut());
        Ok(State { t, q, v, a, inertial, net })
    }

    /// Advances `state` by `h` (s). On a Newton failure the step is split in two halves,
    /// recursively up to [`NewtonOptions::max_halvings`] times; `state` is changed only on success.
    ///
    /// # Errors
    /// [`HhtError::InvalidParameter`] for a step that is not finite and positive;
    /// [`HhtError::NewtonDiverged`] when even the smallest substep fails;
    /// [`HhtError::Singular`] from the linear solver.
    pub fn step<M: Model>(
        &mut self,
        model: &M,
        state: &mut State<M::Config>,
        h: f64,
    ) -> Result<StepReport, HhtError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(HhtError::InvalidParameter {
                name: "time step",
                value: h,
                allowed: "a finite time step greater than zero (s)",
            });
        }
        self.step_split(model, state, h, 0)
    }

    fn step_split<M: Model>(
        &mut self,
        model: &M,
        state: &mut State<M::Config>,
        h: f64,
        depth: usize,
    ) -> Result<StepReport, HhtError> {
        match self.attempt(model, state, h) {
            Ok((next, report)) => {
                *state = next;
                Ok(report)
            }
            Err(e @ (HhtError::NewtonDiverged { .. } | HhtError::Singular { .. }))
                if depth < self.options.max_halvings =>
            {
                let mut trial = state.clone();
                let first = self.step_split(model, &mut trial, 0.5 * h, depth + 1);
                let second = first.and_then(|r1| {
                    self.step_split(model, &mut trial, 0.5 * h, depth + 1).map(|r2| (r1, r2))
                });
                match second {
                    Ok((r1, r2)) => {
                        *state = trial;
                        Ok(StepReport {
                            iterations: r1.iterations + r2.iterations,
                            residual_norm: r1.residual_norm.max(r2.residual_norm),
                            error_estimate: r1.error_estimate.max(r2.error_estimate),
                            substeps: r1.substeps + r2.substeps,
                        })
                    }
                    Err(_) => Err(e),
                }
            }
            Err(e) => Err(e),
        }
    }

    /// One Newton solve of the step equation; returns the new state without touching the old.
    fn attempt<M: Model>(
        &mut self,
        model: &M,
        old: &State<M::Config>,
        h: f64,
    ) -> Result<(State<M::Config>, StepReport), HhtError> {
        let s = self.scheme;
        let n = model.ndof();
        let t1 = old.t + h;
        // The iteration unknown is the new acceleration a_{n+1} (predictor: a_n). Iterating on
        // the configuration increment instead would compute a_{n+1} as a difference of
        // increments divided by beta h^2, a round-off floor of eps |dq| / (beta h^2) on the
        // inertial force that stalls Newton at small steps.
        let base = h * &old.v + (0.5 * h * h) * &old.a;
        let mut a1 = old.a.clone();
        let w = NewtonWeights {
            inertia: 1.0 - s.alpha_m,
            force: 1.0 - s.alpha_f,
            da: 1.0 / (s.beta * h * h),
            dv: s.gamma / (s.beta * h),
            dq: 1.0,
        };
        let old_terms = s.alpha_m * &old.inertial + s.alpha_f * &old.net;
        // Round-off floor of the balance: forces of the size of the old ones are recomputed at
        // q_n (+) delta, so their round-off is carried even when the balance itself is tiny.
        let old_scale = norm(&old.inertial).max(norm(&old.net));
        let mut inertial = Col::<f64>::zeros(n);
        let mut net = Col::<f64>::zeros(n);
        let mut residual_norm = f64::INFINITY;
        for iteration in 0..=self.options.max_iterations {
            let delta = &base + (s.beta * h * h) * (&a1 - &old.a);
            let v1 = &old.v + (h * (1.0 - s.gamma)) * &old.a + (h * s.gamma) * &a1;
            let mut q1 = old.q.clone();
            model.update(&mut q1, delta.as_ref());
            model.inertial_force(&q1, v1.as_ref(), a1.as_ref(), inertial.as_mut());
            model.net_force(t1, &q1, v1.as_ref(), net.as_mut());
            let mut r = (1.0 - s.alpha_m) * &inertial + (1.0 - s.alpha_f) * &net + &old_terms;
            residual_norm = norm(&r);
            let scale = norm(&inertial).max(norm(&net)).max(old_scale);
            if !residual_norm.is_finite() {
                break;
            }
            let floor =
                ROUND_OFF_FACTOR * f64::EPSILON * model.force_scale(&q1) * (n as f64).sqrt();
            let mut converged =
                residual_norm <= self.options.atol + self.options.rtol * scale + floor;
            if !converged && iteration < self.options.max_iterations {
                self.triplets.clear();
                model.tangent(t1, &q1, v1.as_ref(), a1.as_ref(), w, &mut self.triplets);
                self.lu.factor(n, &self.triplets, t1)?;
                self.factorisations += 1;
                r *= -1.0 / (s.beta * h * h);
                self.lu.solve_in_place(r.as_mut(), t1)?;
                // A correction below the round-off of the quantities it corrects cannot improve
                // the iterate: the balance is then at its floating-point floor (for example a
                // tiny displacement computed as the difference of two O(1) increments), so accept.
                // The configuration's own round-off is ~eps |q| per coordinate (sqrt(n) in norm).
                let correction = norm(&r);
                let configuration = model.configuration_scale(&q1) * (n as f64).sqrt();
                converged = iteration > 0
                    && (correction <= 1e-14 * norm(&a1).max(norm(&old.a))
                        || s.beta * h * h * correction
                            <= 1e-14 * norm(&delta).max(norm(&base)).max(configuration));
                if !converged {
                    a1 += &r;
                    continue;
                }
            }
            if !converged {
                break;
            }
            let error_estimate = h * h * (s.beta - 1.0 / 6.0).abs() * norm(&(&a1 - &old.a));
            let next = State { t: t1, q: q1, v: v1, a: a1, inertial, net };
            let report =
                StepReport { iterations: iteration, residual_norm, error_estimate, substeps: 1 };
            return Ok((next, report));
        }
        Err(HhtError::NewtonDiverged {
            t: t1,
            iterations: self.options.max_iterations,
            residual_norm,
        })
    }
}
