//! Goldsmith's Duhamel series, the paper's eq. (1), kept literally as a reference.

use crate::error::{positive, ModalError};
use crate::propagate::PointModes;

/// Displacement at the load point at t_n = n dt, n = 0..=N, of an undamped beam at rest under a
/// piecewise-constant force that is `forces[j-1]` on [(j-1) dt, j dt] (the paper's eq. 1):
///
/// w(n dt) = sum_{j=1..n} F_j sum_i g_i^2 (cos omega_i (n-j) dt - cos omega_i (n-j+1) dt) / omega_i^2,
///
/// with g_i = chi_i(c) / sqrt(rho A integral chi_i^2) (mass-normalised). The paper's upper limit
/// n - 1 leaves out the interval that ends at t_n, whose force an explicit scheme does not know
/// yet; here every interval up to t_n is included, so the series is the exact response and can
/// be compared with [`crate::Transition`] with a zero-order hold. Rigid-body modes (omega = 0)
/// use the limit ((n-j+1)^2 - (n-j)^2) dt^2 / 2. Cost O(N^2 + N modes).
///
/// # Errors
/// `InvalidParameter` if dt is not finite and positive or a mode is damped (the series is the
/// undamped one).
pub fn duhamel_series(modes: &PointModes, forces: &[f64], dt: f64) -> Result<Vec<f64>, ModalError> {
    positive("time_step", dt, "s")?;
    if let Some(&z) = modes.damping_ratio().iter().find(|z| **z != 0.0) {
        return Err(ModalError::InvalidParameter {
            name: "modal_damping",
            value: z,
            unit: "-",
            allowed: "0: the paper's series is undamped",
        });
    }
    let n = forces.len();
    // kernel[k] = sum_i g_i^2 (cos(omega_i k dt) - cos(omega_i (k+1) dt)) / omega_i^2.
    let kernel: Vec<f64> = (0..n)
        .map(|k| {
            let (a, b) = (k as f64 * dt, (k + 1) as f64 * dt);
            modes
                .omega()
                .iter()
                .zip(modes.gain())
                .map(|(&w, &g)| {
                    let response = if w == 0.0 {
                        0.5 * (b * b - a * a)
                    } else {
                        // cos(wa) - cos(wb) = 2 sin(w(a+b)/2) sin(w(b-a)/2), free of cancellation.
                        2.0 * (0.5 * w * (a + b)).sin() * (0.5 * w * (b - a)).sin() / (w * w)
                    };
                    g * g * response
                })
                .sum()
        })
        .collect();
    Ok((0..=n).map(|step| (1..=step).map(|j| forces[j - 1] * kernel[step - j]).sum()).collect())
}
