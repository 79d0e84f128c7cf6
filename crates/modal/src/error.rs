//! Errors of the modal crate.

/// What can go wrong when building or propagating a modal beam model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ModalError {
    /// A parameter is outside its allowed range.
    #[error("{name} = {value} ({unit}) is not allowed: {allowed}")]
    InvalidParameter {
        /// Name of the parameter.
        name: &'static str,
        /// The value that was given.
        value: f64,
        /// Its SI unit.
        unit: &'static str,
        /// What would be accepted.
        allowed: &'static str,
    },
    /// The characteristic equation's root could not be bracketed (a bug, not a user error).
    #[error("eigenvalue {mode} of the {support} beam could not be bracketed near {guess}")]
    RootNotBracketed {
        /// Mode number (1-based, elastic modes).
        mode: usize,
        /// Support name.
        support: &'static str,
        /// Starting guess of beta L.
        guess: f64,
    },
    /// An unknown support name.
    #[error("support = \"{0}\" is not known: use clamped-free, pinned-pinned, clamped-clamped, clamped-pinned or free-free")]
    UnknownSupport(String),
}

/// Checks that `value` is finite and strictly positive.
pub(crate) fn positive(
    name: &'static str,
    value: f64,
    unit: &'static str,
) -> Result<f64, ModalError> {
    if !(value.is_finite() && value > 0.0) {
        return Err(ModalError::InvalidParameter {
            name,
            value,
            unit,
            allowed: "a finite number greater than zero",
        });
    }
    Ok(value)
}
