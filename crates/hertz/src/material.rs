//! Elastic (and optionally plastic) constants of a contacting surface.

use crate::error::{positive, HertzError};

/// Elastic constants of one contacting body, and its yield stress if it can yield.
///
/// Density is not part of it: contact mechanics needs only the surface's stiffness and
/// strength; the inertia belongs to the body (ball mass, beam density).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio nu (-).
    pub poisson_ratio: f64,
    /// Uniaxial yield stress Y (Pa), if the body can yield.
    pub yield_stress: Option<f64>,
}

impl Material {
    /// An elastic material.
    ///
    /// # Errors
    /// `InvalidParameter` if E is not finite and positive or nu is outside (-1, 0.5).
    pub fn new(youngs_modulus: f64, poisson_ratio: f64) -> Result<Self, HertzError> {
        positive("youngs_modulus", youngs_modulus, "Pa")?;
        crate::error::poisson_ratio(poisson_ratio)?;
        Ok(Self { youngs_modulus, poisson_ratio, yield_stress: None })
    }

    /// The same material with a yield stress Y (Pa).
    ///
    /// # Errors
    /// `InvalidParameter` if Y is not finite and positive.
    pub fn with_yield_stress(self, yield_stress: f64) -> Result<Self, HertzError> {
        positive("yield_stress", yield_stress, "Pa")?;
        Ok(Self { yield_stress: Some(yield_stress), ..self })
    }

    /// Plane-strain compliance (1 - nu^2) / E (1/Pa), the body's share of 1/E*.
    pub fn plane_strain_compliance(&self) -> f64 {
        (1.0 - self.poisson_ratio * self.poisson_ratio) / self.youngs_modulus
    }
}

/// Effective contact modulus E* (Pa): 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2
/// (Johnson, *Contact Mechanics*, eq. 4.22; validation/REFERENCES.md 2).
pub fn effective_modulus(a: &Material, b: &Material) -> f64 {
    1.0 / (a.plane_strain_compliance() + b.plane_strain_compliance())
}

/// Yield stress of the softer of two bodies (Pa), the one that limits the contact pressure
/// (Johnson 1985, §11.4: "Y the yield stress of the softer body"). `None` if neither can yield.
pub fn softer_yield_stress(a: &Material, b: &Material) -> Option<f64> {
    match (a.yield_stress, b.yield_stress) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, y) => x.or(y),
    }
}
