//! Closed-form results for a sphere striking a massive half-space (quasi-static Hertz).

use crate::error::{positive, HertzError};
use crate::hertz::Hertz;
use std::f64::consts::PI;

/// I = integral_0^1 (1 - x^(5/2))^(-1/2) dx = (2/5) B(2/5, 1/2), the constant of the Hertz
/// contact duration t_c = 2 I delta_max / V (validation/REFERENCES.md 2.1, evaluated to 15 digits;
/// checked by quadrature in the tests).
pub const HERTZ_DURATION_INTEGRAL: f64 = 1.471_637_592_162_35;

/// Elastic impact of a sphere of mass m on a massive half-space at normal speed V
/// (Timoshenko & Goodier §140; Johnson §11.4; validation/REFERENCES.md 2.1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfSpaceImpact {
    /// delta_max = (5 m V^2 / (4 K))^(2/5) (m).
    pub max_approach: f64,
    /// F_max = K delta_max^(3/2) (N).
    pub peak_force: f64,
    /// t_c = 2 I delta_max / V = 2.9433 delta_max / V (s).
    pub duration: f64,
    /// a_max = sqrt(R delta_max) (m).
    pub max_contact_radius: f64,
    /// p0 = (2 E*/pi) sqrt(delta_max / R) (Pa).
    pub max_pressure: f64,
}

impl HalfSpaceImpact {
    /// The elastic closed form for a contact `hertz`, a sphere of mass `mass` (kg) and impact
    /// speed `speed` (m/s).
    ///
    /// # Errors
    /// `InvalidParameter` if the mass or the speed is not finite and positive.
    pub fn elastic(hertz: &Hertz, mass: f64, speed: f64) -> Result<Self, HertzError> {
        positive("mass", mass, "kg")?;
        positive("speed", speed, "m/s")?;
        let max_approach = (1.25 * mass * speed * speed / hertz.stiffness_constant()).powf(0.4);
        Ok(Self {
            max_approach,
            peak_force: hertz.elastic_force(max_approach),
            duration: 2.0 * HERTZ_DURATION_INTEGRAL * max_approach / speed,
            max_contact_radius: hertz.contact_radius(max_approach),
            max_pressure: hertz.max_pressure(max_approach),
        })
    }
}

/// Impact speed (m/s) at which the central pressure of an elastic Hertz impact reaches
/// `limiting_pressure` p_y (Pa): (1/2) m V_y^2 = (2/5) K delta_y^(5/2), that is
/// V_y^2 = 16 E* sqrt(R) delta_y^(5/2) / (15 m), with
/// delta_y = R (pi p_y / (2 E*))^2. Equal to Thornton's V_y = (pi/(2E*))^2
/// sqrt(8 pi R^3 p_y^5 / (15 m)) (validation/REFERENCES.md 2.4).
///
/// # Errors
/// `InvalidParameter` if the mass or the pressure is not finite and positive.
pub fn elastic_limit_velocity(
    hertz: &Hertz,
    mass: f64,
    limiting_pressure: f64,
) -> Result<f64, HertzError> {
    positive("mass", mass, "kg")?;
    positive("limiting_pressure", limiting_pressure, "Pa")?;
    let delta_y = hertz.approach_at_pressure(limiting_pressure)?;
    Ok((2.0 * hertz.elastic_energy(delta_y) / mass).sqrt())
}

/// Johnson's yield-onset speed (m/s) of a sphere of density rho on a flat:
/// rho V_Y^2 / Y = (4/(5 pi)) (0.8 pi)^5 (Y/E*)^4 = 25.54 (Y/E*)^4 (validation/REFERENCES.md 2.3; Johnson
/// eq. 11.27 quotes the rounded 26), with Y the yield stress of the softer body.
///
/// # Errors
/// `InvalidParameter` if any argument is not finite and positive.
pub fn johnson_yield_velocity(
    sphere_density: f64,
    yield_stress: f64,
    effective_modulus: f64,
) -> Result<f64, HertzError> {
    positive("sphere_density", sphere_density, "kg/m^3")?;
    positive("yield_stress", yield_stress, "Pa")?;
    positive("effective_modulus", effective_modulus, "Pa")?;
    let coefficient = 4.0 / (5.0 * PI) * (0.8 * PI).powi(5);
    Ok((coefficient * (yield_stress / effective_modulus).powi(4) * yield_stress / sphere_density)
        .sqrt())
}

/// Thornton's (1997) coefficient of restitution of an elastic-perfectly-plastic impact at speed
/// V above the yield velocity V_y, with r = V_y / V (validation/REFERENCES.md 2.4):
/// e = sqrt(6 sqrt(3)/5) sqrt(1 - r^2/6) (r / (r + 2 sqrt(6/5 - r^2/5)))^(1/4); e = 1 for V <= V_y.
///
/// # Errors
/// `InvalidParameter` if either speed is not finite and positive.
pub fn thornton_restitution(yield_velocity: f64, speed: f64) -> Result<f64, HertzError> {
    positive("yield_velocity", yield_velocity, "m/s")?;
    positive("speed", speed, "m/s")?;
    if speed <= yield_velocity {
        return Ok(1.0);
    }
    let r = yield_velocity / speed;
    let r2 = r * r;
    Ok((6.0 * 3f64.sqrt() / 5.0).sqrt()
        * (1.0 - r2 / 6.0).sqrt()
        * (r / (r + 2.0 * (1.2 - r2 / 5.0).sqrt())).powf(0.25))
}
