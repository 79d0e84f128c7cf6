//! Spectral analysis of a scheme on the undamped linear oscillator (validation/REFERENCES.md 4.2).

use crate::error::HhtError;
use crate::integrator::{Integrator, NewtonOptions, State};
use crate::oscillator::Oscillator;
use crate::scheme::Scheme;
use faer::Col;
use nalgebra::Matrix3;

/// Spectral properties of one step at `Omega = omega h`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spectrum {
    /// Largest modulus of the amplification matrix's eigenvalues.
    pub radius: f64,
    /// Algorithmic damping ratio `xi` of the principal root pair
    /// `lambda = exp(Omega_bar (-xi +- i))`.
    pub damping_ratio: f64,
    /// Relative period error `(T_bar - T) / T = Omega / Omega_bar - 1`.
    pub period_error: f64,
}

/// Amplification matrix of one step of size `omega_h` on `d'' + d = 0`, for the scaled state
/// (d, h v, h^2 a), measured by stepping the integrator itself from the three unit states.
/// Any scheme, in the family's stable region or not (the integrator refuses one outside it;
/// here it is studied: validation/REFERENCES.md 4.3).
///
/// # Errors
/// [`HhtError::InvalidParameter`] for a step that is not finite and positive.
pub fn amplification(scheme: Scheme, omega_h: f64) -> Result<Matrix3<f64>, HhtError> {
    let model = Oscillator::undamped(1.0)?;
    let h = omega_h;
    let mut integrator = Integrator::new(scheme, NewtonOptions::default());
    integrator.check_scheme = false;
    let mut m = Matrix3::zeros();
    for j in 0..3 {
        let mut x = [0.0; 3];
        x[j] = 1.0;
        let v = Col::from_fn(1, |_| x[1] / h);
        let a = Col::from_fn(1, |_| x[2] / (h * h));
        let mut state = State::new(&model, 0.0, x[0], v, a)?;
        integrator.step(&model, &mut state, h)?;
        m[(0, j)] = state.q;
        m[(1, j)] = h * state.v[0];
        m[(2, j)] = h * h * state.a[0];
    }
    Ok(m)
}

/// Spectral radius, damping ratio and period error of `scheme` at `Omega = omega_h`.
///
/// # Errors
/// As [`amplification`]; [`HhtError::Model`] when no complex principal pair exists (Omega
/// beyond the bifurcation, where damping ratio and period are undefined).
pub fn spectrum(scheme: Scheme, omega_h: f64) -> Result<Spectrum, HhtError> {
    let roots = amplification(scheme, omega_h)?.complex_eigenvalues();
    let radius = roots.iter().map(|z| z.norm()).fold(0.0, f64::max);
    let principal =
        roots.iter().find(|z| z.im > 0.0).copied().ok_or_else(|| {
            HhtError::Model(format!("no oscillating root pair at Omega = {omega_h}"))
        })?;
    let omega_bar = principal.arg();
    Ok(Spectrum {
        radius,
        damping_ratio: -principal.norm().ln() / omega_bar,
        period_error: omega_h / omega_bar - 1.0,
    })
}
