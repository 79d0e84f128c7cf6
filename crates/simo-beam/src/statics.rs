//! Static equilibrium by Newton's method with load stepping and automatic step cutting.

use crate::error::BeamError;
use crate::model::{load_norm, BeamModel, BeamState};
use faer::Col;
use hht::{Model, NewtonWeights, SparseLu, Triplets};

/// Settings of the static solver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticOptions {
    /// Equal load increments to the full load (each may be cut automatically).
    pub load_steps: usize,
    /// Newton iterations per increment before it is cut in half.
    pub max_iterations: usize,
    /// Relative residual tolerance against the applied load, plus the round-off floor
    /// `hht::ROUND_OFF_FACTOR` x eps x the model's force scale (of order EA).
    pub rtol: f64,
    /// Smallest load increment, as a fraction of the full load, before giving up.
    pub min_step: f64,
}

impl Default for StaticOptions {
    fn default() -> Self {
        Self { load_steps: 1, max_iterations: 30, rtol: 1e-10, min_step: 1e-4 }
    }
}

/// The result of [`solve_static`].
#[derive(Debug, Clone)]
pub struct StaticSolution {
    /// The equilibrium configuration at the full load.
    pub state: BeamState,
    /// Newton iterations of each accepted increment.
    pub iterations: Vec<usize>,
    /// Residual norms of the iterations of the first increment (to show Newton's rate).
    pub first_residuals: Vec<f64>,
    /// Increments that were cut and retried.
    pub cuts: usize,
    /// The load path: (load factor, equilibrium configuration) after each accepted increment,
    /// ending with the full load.
    pub path: Vec<(f64, BeamState)>,
    /// The first accepted load factor whose equilibrium is unstable, and in how many
    /// directions (negative eigenvalues of the tangent stiffness, Sylvester's inertia): past
    /// a buckling load the path from the straight beam stays on the unstable branch it started
    /// on (a cantilever under 12 times Euler's axial load stays straight). `None`: stable
    /// throughout (or not countable).
    pub unstable_from: Option<(f64, usize)>,
}

/// Solves `f_int(q) = lambda f_ext(q)` for lambda from 0 to 1, starting from the reference
/// configuration. Follower loads and dead moments contribute their load stiffness.
///
/// # Errors
/// [`BeamError::InvalidParameter`] for zero load steps; [`BeamError::NotConverged`] when an
/// increment below `min_step` still fails; [`BeamError::Integrator`] if the tangent is singular
/// (a mechanism: check the supports).
pub fn solve_static(
    model: &BeamModel,
    options: StaticOptions,
) -> Result<StaticSolution, BeamError> {
    if options.load_steps == 0 {
        return Err(BeamError::InvalidParameter {
            name: "load_steps",
            value: 0.0,
            allowed: "at least one load step",
        });
    }
    let mut model = model.clone();
    model.set_time_dependent(false);
    let mut solver = SparseLu::new();
    let mut triplets = Triplets::new();
    let n = model.ndof();
    let zero = Col::<f64>::zeros(n);
    let mut state = model.reference_state();
    let nominal = 1.0 / options.load_steps as f64;
    let mut step = nominal;
    let mut lambda = 0.0;
    let mut iterations = Vec::new();
    let mut first_residuals = Vec::new();
    let mut cuts = 0;
    let mut path = Vec::new();
    let mut unstable_from = None;
    while lambda < 1.0 - 1e-14 {
        // Land exactly on the full load, not on a sum of rounded increments.
        let target = if lambda + step >= 1.0 - 1e-12 { 1.0 } else { lambda + step };
        model.set_load_factor(target);
        let mut trial = state.clone();
        let mut residuals = Vec::new();
        let mut converged = None;
        let mut reason = String::new();
        for iteration in 0..=options.max_iterations {
            let mut r = Col::<f64>::zeros(n);
            model.net_force(0.0, &trial, zero.as_ref(), r.as_mut());
            let norm = r.norm_l2();
            residuals.push(norm);
            let floor = hht::ROUND_OFF_FACTOR
                * f64::EPSILON
                * model.force_scale(&trial)
                * (n as f64).sqrt();
            let scale = load_norm(&model, 0.0, &trial);
            if !norm.is_finite() {
                reason = "the residual is not finite".into();
                break;
            }
            if norm <= options.rtol * scale + floor || n == 0 {
                converged = Some(iteration);
                break;
            }
            if iteration == options.max_iterations {
                reason = format!("residual {norm:e} after {iteration} iterations");
                break;
            }
            triplets.clear();
            model.tangent(
                0.0,
                &trial,
                zero.as_ref(),
                zero.as_ref(),
                NewtonWeights::stiffness(),
                &mut triplets,
            );
            // A singular tangent at the load factor `target` (passed where the linear solver
            // says "t", a time): said as what it is, with what to check (a free beam's had
            // read "singular ... at t = 1 s", a review's).
            solver.factor(n, &triplets, target).map_err(|e| match e {
                hht::HhtError::Singular { reason, .. } => BeamError::Mesh(format!(
                    "the static stiffness is singular at load factor {target}: the beam is a mechanism or free (check its supports: {reason})"
                )),
                other => BeamError::Integrator(other),
            })?;
            r *= -1.0;
            solver.solve_in_place(r.as_mut(), target)?;
            model.update(&mut trial, r.as_ref());
        }
        match converged {
            Some(k) => {
                if first_residuals.is_empty() {
                    first_residuals = residuals;
                }
                iterations.push(k);
                lambda = target;
                if unstable_from.is_none() {
                    unstable_from = crate::eigen::unstable_directions(&model, &trial)
                        .filter(|k| *k > 0)
                        .map(|k| (lambda, k));
                }
                path.push((lambda, trial.clone()));
                state = trial;
                step = (2.0 * step).min(nominal);
            }
            None => {
                cuts += 1;
                step *= 0.5;
                if step < options.min_step {
                    return Err(BeamError::NotConverged { load_factor: lambda, step, reason });
                }
            }
        }
    }
    Ok(StaticSolution { state, iterations, first_residuals, cuts, path, unstable_from })
}
