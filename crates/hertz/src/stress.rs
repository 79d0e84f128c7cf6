//! Stresses under a Hertz contact.

use crate::error::HertzError;
use crate::hertz::Hertz;

/// Stresses of a Hertz contact of a sphere on a body of Poisson's ratio nu.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactStress {
    /// Contact radius a (m).
    pub contact_radius: f64,
    /// Central pressure p0 (Pa).
    pub max_pressure: f64,
    /// Largest shear stress below the surface, on the axis (Pa).
    pub max_shear: f64,
    /// Its depth below the surface (m).
    pub max_shear_depth: f64,
}

/// Largest principal shear stress on the axis of a Hertz point contact, as a fraction of p0,
/// and its depth as a fraction of a. Along the axis (Johnson eq. 3.45, zeta = z/a):
/// sigma_z/p0 = -1/(1 + zeta^2),
/// sigma_r/p0 = -(1 + nu)(1 - zeta atan(1/zeta)) + 1/(2 (1 + zeta^2)),
/// tau = (sigma_r - sigma_z)/2, maximised over zeta by golden-section search.
/// For nu = 0.3: 0.3100 p0 at 0.4809 a (Johnson quotes 0.31 p0 at 0.48 a).
///
/// # Errors
/// `InvalidParameter` for a Poisson's ratio not in (-1, 0.5) (it had answered NaN, or the
/// search bracket's edge, there, a review's).
pub fn max_subsurface_shear(poisson_ratio: f64) -> Result<(f64, f64), HertzError> {
    crate::error::poisson_ratio(poisson_ratio)?;
    let tau = |z: f64| {
        let sz = -1.0 / (1.0 + z * z);
        let sr = -(1.0 + poisson_ratio) * (1.0 - z * (1.0 / z).atan()) + 0.5 / (1.0 + z * z);
        0.5 * (sr - sz)
    };
    let golden = 0.5 * (5f64.sqrt() - 1.0);
    let (mut lo, mut hi) = (0.05, 3.0);
    // 80 golden-section steps shrink the bracket by 0.618^80 ~ 2e-17: round-off limited.
    for _ in 0..80 {
        let a = hi - golden * (hi - lo);
        let b = lo + golden * (hi - lo);
        if tau(a) > tau(b) {
            hi = b;
        } else {
            lo = a;
        }
    }
    let z = 0.5 * (lo + hi);
    Ok((tau(z), z))
}

impl Hertz {
    /// Contact radius, central pressure and the largest subsurface shear stress at approach
    /// `delta` (m), in a body of Poisson's ratio `poisson_ratio`.
    ///
    /// # Errors
    /// As [`max_subsurface_shear`].
    pub fn stresses(&self, delta: f64, poisson_ratio: f64) -> Result<ContactStress, HertzError> {
        let a = self.contact_radius(delta);
        let p0 = self.max_pressure(delta);
        let (tau, depth) = max_subsurface_shear(poisson_ratio)?;
        Ok(ContactStress {
            contact_radius: a,
            max_pressure: p0,
            max_shear: tau * p0,
            max_shear_depth: depth * a,
        })
    }
}
