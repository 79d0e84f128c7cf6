//! Errors of the contact crate.

/// What can go wrong when building a contact model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum HertzError {
    /// A parameter is outside its physical range.
    #[error("{name} = {value} ({unit}) is not allowed: {allowed}")]
    InvalidParameter {
        /// Name of the parameter, as a user knows it.
        name: &'static str,
        /// The value that was given.
        value: f64,
        /// Its SI unit.
        unit: &'static str,
        /// What would be accepted.
        allowed: &'static str,
    },
}

/// Checks that `value` is finite and strictly positive.
pub(crate) fn positive(
    name: &'static str,
    value: f64,
    unit: &'static str,
) -> Result<f64, HertzError> {
    if !(value.is_finite() && value > 0.0) {
        return Err(HertzError::InvalidParameter {
            name,
            value,
            unit,
            allowed: "a finite number greater than zero",
        });
    }
    Ok(value)
}

/// Checks that `nu` is a Poisson's ratio of a stable isotropic solid, in (-1, 0.5).
pub(crate) fn poisson_ratio(nu: f64) -> Result<f64, HertzError> {
    if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
        return Err(HertzError::InvalidParameter {
            name: "poisson_ratio",
            value: nu,
            unit: "-",
            allowed: "a number in (-1, 0.5)",
        });
    }
    Ok(nu)
}
