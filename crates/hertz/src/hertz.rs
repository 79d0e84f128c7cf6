//! The elastic Hertz law F = K delta^(3/2).

use crate::error::{positive, HertzError};
use crate::law::{ContactForce, ContactLaw};
use crate::material::{effective_modulus, Material};

/// Elastic Hertz contact of two bodies with effective modulus E* and effective radius R:
/// F = K delta^(3/2), K = (4/3) E* sqrt(R) (Johnson eq. 4.23; the paper's eq. 4 with k2 = K).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hertz {
    effective_modulus: f64,
    effective_radius: f64,
    /// K, computed once: the modal contact step evaluates the law a few times per step.
    stiffness_constant: f64,
}

impl Hertz {
    /// From the effective modulus E* (Pa) and effective radius R (m).
    ///
    /// # Errors
    /// `InvalidParameter` if either is not finite and positive.
    pub fn new(effective_modulus: f64, effective_radius: f64) -> Result<Self, HertzError> {
        positive("effective_modulus", effective_modulus, "Pa")?;
        positive("effective_radius", effective_radius, "m")?;
        let stiffness_constant = 4.0 / 3.0 * effective_modulus * effective_radius.sqrt();
        Ok(Self { effective_modulus, effective_radius, stiffness_constant })
    }

    /// Two materials and an effective radius (see [`crate::geometry`]).
    ///
    /// # Errors
    /// `InvalidParameter` if the radius is not finite and positive.
    pub fn between(a: &Material, b: &Material, effective_radius: f64) -> Result<Self, HertzError> {
        Self::new(effective_modulus(a, b), effective_radius)
    }

    /// Effective modulus E* (Pa).
    pub fn effective_modulus(&self) -> f64 {
        self.effective_modulus
    }

    /// Effective radius R (m).
    pub fn effective_radius(&self) -> f64 {
        self.effective_radius
    }

    /// Hertz constant K = (4/3) E* sqrt(R) (N/m^1.5).
    pub fn stiffness_constant(&self) -> f64 {
        self.stiffness_constant
    }

    /// Force K delta^(3/2) (N), zero for delta <= 0.
    pub fn elastic_force(&self, delta: f64) -> f64 {
        if delta > 0.0 {
            self.stiffness_constant() * delta * delta.sqrt()
        } else {
            0.0
        }
    }

    /// Stiffness dF/d(delta) = (3/2) K delta^(1/2) (N/m).
    pub fn elastic_stiffness(&self, delta: f64) -> f64 {
        if delta > 0.0 {
            1.5 * self.stiffness_constant() * delta.sqrt()
        } else {
            0.0
        }
    }

    /// Stored energy (2/5) K delta^(5/2) (J).
    pub fn elastic_energy(&self, delta: f64) -> f64 {
        0.4 * delta.max(0.0) * self.elastic_force(delta)
    }

    /// Approach delta = (F/K)^(2/3) (m) that carries a force F (N); the paper's eq. (3).
    pub fn approach_for_force(&self, force: f64) -> f64 {
        if force > 0.0 {
            (force / self.stiffness_constant()).powf(2.0 / 3.0)
        } else {
            0.0
        }
    }

    /// Contact radius a = sqrt(R delta) (m).
    pub fn contact_radius(&self, delta: f64) -> f64 {
        (self.effective_radius * delta.max(0.0)).sqrt()
    }

    /// Maximum (central) contact pressure p0 = (2 E*/pi) sqrt(delta/R) = 3F/(2 pi a^2) (Pa).
    pub fn max_pressure(&self, delta: f64) -> f64 {
        2.0 * self.effective_modulus / std::f64::consts::PI
            * (delta.max(0.0) / self.effective_radius).sqrt()
    }

    /// Approach (m) at which the central pressure reaches `pressure` (Pa):
    /// delta = R (pi p / (2 E*))^2, the inverse of [`Hertz::max_pressure`].
    ///
    /// # Errors
    /// `InvalidParameter` if the pressure is not finite and positive (a negative one had
    /// given a positive approach, a review's).
    pub fn approach_at_pressure(&self, pressure: f64) -> Result<f64, HertzError> {
        positive("pressure", pressure, "Pa")?;
        let x = std::f64::consts::PI * pressure / (2.0 * self.effective_modulus);
        Ok(self.effective_radius * x * x)
    }
}

impl ContactLaw for Hertz {
    type State = ();

    fn force(&self, _: &(), delta: f64, _delta_dot: f64) -> ContactForce {
        // elastic_force and elastic_stiffness with one square root between them.
        let (force, stiffness) = if delta > 0.0 {
            let (k, root) = (self.stiffness_constant, delta.sqrt());
            (k * delta * root, 1.5 * k * root)
        } else {
            (0.0, 0.0)
        };
        ContactForce { force, stiffness, damping: 0.0 }
    }

    fn commit(&self, _: &mut (), _delta: f64, _delta_dot: f64) {}

    fn stored_energy(&self, _: &(), delta: f64) -> f64 {
        self.elastic_energy(delta)
    }

    fn dissipated_energy(&self, _: &()) -> f64 {
        0.0
    }
}
