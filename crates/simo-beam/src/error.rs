//! Errors of the beam crate.

/// What can go wrong when building or solving a beam model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BeamError {
    /// A parameter is outside its physical range.
    #[error("{name} = {value} is not allowed: {allowed}")]
    InvalidParameter {
        /// Name of the parameter, as a user knows it.
        name: &'static str,
        /// The value that was given.
        value: f64,
        /// What would be accepted.
        allowed: &'static str,
    },
    /// The mesh or a load does not fit together (no elements, a node out of range, ...).
    #[error("invalid mesh: {0}")]
    Mesh(String),
    /// The static solver could not reach the full load even with the smallest load step.
    #[error(
        "the static solution stopped at load factor {load_factor} (smallest step {step}): {reason}"
    )]
    NotConverged {
        /// Fraction of the load that was reached.
        load_factor: f64,
        /// The load step that failed last.
        step: f64,
        /// Why the last attempt failed.
        reason: String,
    },
    /// The time integrator failed.
    #[error(transparent)]
    Integrator(#[from] hht::HhtError),
    /// The eigenvalue problem could not be solved (the mass matrix is not positive definite).
    #[error("linear modal analysis failed: {0}")]
    Eigen(String),
}

/// Checks that `value` is finite and strictly positive.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64, BeamError> {
    if !(value.is_finite() && value > 0.0) {
        return Err(BeamError::InvalidParameter {
            name,
            value,
            allowed: "a finite number greater than zero (SI units)",
        });
    }
    Ok(value)
}

/// Checks that `value` is finite and not negative; `allowed` says so with the unit.
pub(crate) fn not_negative(
    name: &'static str,
    value: f64,
    allowed: &'static str,
) -> Result<f64, BeamError> {
    if !(value.is_finite() && value >= 0.0) {
        return Err(BeamError::InvalidParameter { name, value, allowed });
    }
    Ok(value)
}
