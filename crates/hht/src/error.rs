//! Errors of the time integrator.

/// What can go wrong when building a scheme or taking a step.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum HhtError {
    /// A parameter is outside its allowed range.
    #[error("{name} = {value} is not allowed: {allowed}")]
    InvalidParameter {
        /// Name of the parameter.
        name: &'static str,
        /// The value that was given.
        value: f64,
        /// What would be accepted.
        allowed: &'static str,
    },
    /// Newton's iteration did not reach the tolerance, even after halving the step.
    #[error(
        "Newton's iteration diverged at t = {t} s after {iterations} iterations \
         (residual norm {residual_norm:e})"
    )]
    NewtonDiverged {
        /// Time at the end of the failed step (s).
        t: f64,
        /// Iterations spent on the last attempt.
        iterations: usize,
        /// Norm of the last residual (model units, N and N m for a beam).
        residual_norm: f64,
    },
    /// The Newton matrix could not be factorised.
    #[error("the Newton matrix is singular or could not be factorised at t = {t} s: {reason}")]
    Singular {
        /// Time of the failed factorisation (s).
        t: f64,
        /// What the linear algebra reported.
        reason: String,
    },
    /// The model wrote something the integrator cannot use (wrong size, index out of range).
    #[error("the model is inconsistent: {0}")]
    Model(String),
}

/// Checks that `value` is finite and inside `[lo, hi]`.
pub(crate) fn in_range(
    name: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    allowed: &'static str,
) -> Result<f64, HhtError> {
    if !(value.is_finite() && value >= lo && value <= hi) {
        return Err(HhtError::InvalidParameter { name, value, allowed });
    }
    Ok(value)
}
