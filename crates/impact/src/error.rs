//! Errors of the impact crate.

/// What can go wrong when reading, planning or running a scene.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ImpactError {
    /// The scene file is not valid TOML or does not match the scene's keys (unknown key,
    /// missing field, wrong type); the message names the key and the line.
    #[error("scene file: {0}")]
    Parse(String),
    /// A field has a value outside what is allowed.
    #[error("{field} = {value}: {allowed}")]
    InvalidField {
        /// Dotted path of the field, e.g. `beam.length`.
        field: String,
        /// The value as written.
        value: String,
        /// What would be accepted, with the unit.
        allowed: String,
    },
    /// A scene file that cannot be read: missing, not a regular file, too large, not UTF-8
    /// text; the message names the file.
    #[error("{0}")]
    Input(String),
    /// A combination of fields that does not make a scene.
    #[error("{0}")]
    Inconsistent(String),
    /// A study (a grid of scenes, its shards, its output folder's name) asked for something
    /// that cannot be run as written; the message names the option or key and what is allowed.
    #[error("{0}")]
    Study(String),
    /// A fault of this library caught where a front end runs many scenes (a panic, which no
    /// input should cause): the message says what, to be reported.
    #[error("internal error (please report it): {0}")]
    Internal(String),
    /// A numerical failure in a run; carries the simulated time.
    #[error("the solver failed at t = {t} s: {reason}")]
    SolverFailed {
        /// Simulated time (s).
        t: f64,
        /// What went wrong.
        reason: String,
    },
    /// A run of `solver.tolerance`'s refinement failed: which (its resolution), and why (the
    /// source). The plan a front end prints before the error is the refinement's first run's.
    #[error("in solver.tolerance's refinement, its run at {at} (a plan printed with this error is the refinement's first run's)")]
    Refinement {
        /// The run's resolution, e.g. `512 elements`.
        at: String,
        /// How it failed.
        #[source]
        source: Box<ImpactError>,
    },
    /// The time integrator (HHT-alpha) of the finite-element method failed; the source says
    /// how (Newton diverged, a singular matrix, ...).
    // The source names the time it failed at: the message does not repeat it.
    #[error(
        "the finite-element method's time integrator (HHT-alpha) failed; a smaller contact step \
         (solver.samples_per_pulse or solver.time_step), another mesh (solver.elements), \
         numerical damping (solver.alpha) or a shorter window (solver.end_time) may carry it through"
    )]
    Integrator {
        /// Simulated time at the start of the failed step (s).
        t: f64,
        /// What the integrator reported.
        #[source]
        source: hht::HhtError,
    },
    /// An error from the contact crate.
    #[error(transparent)]
    Contact(#[from] hertz::HertzError),
    /// An error from the modal crate.
    #[error(transparent)]
    Modal(#[from] modal::ModalError),
    /// An error from the beam crate.
    #[error(transparent)]
    Beam(#[from] simo_beam::BeamError),
}

/// A number as a user reads it: plain when moderate, in scientific notation when very large or
/// small (1e308 is not printed with 309 digits).
pub(crate) fn show(value: f64) -> String {
    let size = value.abs();
    if size != 0.0 && !(1e-4..1e6).contains(&size) && size.is_finite() {
        format!("{value:e}")
    } else {
        value.to_string()
    }
}

/// `field` must be finite and strictly positive.
pub(crate) fn positive(field: &str, value: f64, unit: &str) -> Result<f64, ImpactError> {
    if !(value.is_finite() && value > 0.0) {
        return Err(ImpactError::InvalidField {
            field: field.to_owned(),
            value: show(value),
            allowed: format!("must be a finite number greater than 0 ({unit})"),
        });
    }
    Ok(value)
}

/// `value` must be finite and not negative (`unit`).
pub(crate) fn not_negative(field: &str, value: f64, unit: &str) -> Result<f64, ImpactError> {
    if !(value.is_finite() && value >= 0.0) {
        return Err(ImpactError::InvalidField {
            field: field.to_owned(),
            value: show(value),
            allowed: format!("must be a finite number >= 0 ({unit})"),
        });
    }
    Ok(value)
}

/// `field` must lie in [lo, hi] (`unit`): the range the models are built and tested for, so a
/// value far outside is refused by name instead of surfacing as an infinite stiffness, a zero
/// time step or a NaN energy deep in a run.
pub(crate) fn bounded(
    field: &str,
    value: f64,
    (lo, hi): (f64, f64),
    unit: &str,
) -> Result<f64, ImpactError> {
    positive(field, value, unit)?;
    if !(lo..=hi).contains(&value) {
        return Err(ImpactError::InvalidField {
            field: field.to_owned(),
            value: show(value),
            allowed: format!("must be from {} to {} ({unit})", show(lo), show(hi)),
        });
    }
    Ok(value)
}

/// Ranges the models are built and tested for.
pub(crate) mod range {
    /// Lengths (m): a nanometre to 10 km.
    pub(crate) const LENGTH: (f64, f64) = (1e-9, 1e4);
    /// Elastic moduli and stresses (Pa): soft rubber to ten times diamond.
    pub(crate) const MODULUS: (f64, f64) = (1e3, 1e13);
    /// Densities (kg/m^3): aerogel to ten times osmium.
    pub(crate) const DENSITY: (f64, f64) = (1e-3, 1e6);
    /// Masses (kg).
    pub(crate) const MASS: (f64, f64) = (1e-12, 1e6);
    /// Impact speeds (m/s): creeping to ballistic.
    pub(crate) const SPEED: (f64, f64) = (1e-6, 1e4);
    /// Simulated times (s).
    pub(crate) const TIME: (f64, f64) = (1e-12, 1e4);
}

/// `field = value` is outside what is `allowed`.
impl ImpactError {
    /// [`ImpactError::Internal`] with what a caught panic's `payload` said (its message, if it
    /// is text), for a front end that runs many scenes and keeps going past one.
    pub fn from_panic(payload: &(dyn std::any::Any + Send)) -> Self {
        let what = payload
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| payload.downcast_ref::<&str>().map(|s| (*s).to_string()))
            .unwrap_or_default();
        ImpactError::Internal(what)
    }
}

pub(crate) fn invalid(field: &str, value: impl ToString, allowed: &str) -> ImpactError {
    ImpactError::InvalidField {
        field: field.to_owned(),
        value: readable(value.to_string()),
        allowed: allowed.to_owned(),
    }
}

/// A number's text as the user can read it: Rust writes an `f64` without an exponent, so
/// 1e-300 came out as 300 digits; a long number is written with one.
fn readable(value: String) -> String {
    match value.parse::<f64>() {
        Ok(x) if value.len() > 24 => format!("{x:e}"),
        _ => value,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_value_in_an_error_is_written_as_a_user_reads_it() {
        let shown = |v: f64| invalid("impact.offset", v, "").to_string();
        assert!(shown(1e-300).contains("impact.offset = 1e-300"), "{}", shown(1e-300));
        assert!(shown(1e300).contains("= 1e300"), "{}", shown(1e300));
        assert!(shown(0.0126).contains("= 0.0126:"), "{}", shown(0.0126));
        let text = invalid("impact.direction", "[0.0, 1.0]", "").to_string();
        assert!(text.contains("= [0.0, 1.0]"), "{text}");
    }
}
