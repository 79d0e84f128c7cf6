//! Effective radius of curvature of two contacting bodies.

use crate::error::{positive, HertzError};

/// Effective radius R (m) of a sphere of radius `sphere_radius` on a flat face (the beam's).
///
/// # Errors
/// `InvalidParameter` if the radius is not finite and positive.
pub fn sphere_on_flat(sphere_radius: f64) -> Result<f64, HertzError> {
    positive("sphere_radius", sphere_radius, "m")
}

/// Effective radius R (m) of two spheres: 1/R = 1/R1 + 1/R2 (Johnson, eq. 4.23).
///
/// # Errors
/// `InvalidParameter` if either radius is not finite and positive.
pub fn sphere_on_sphere(radius_1: f64, radius_2: f64) -> Result<f64, HertzError> {
    let r1 = positive("radius_1", radius_1, "m")?;
    let r2 = positive("radius_2", radius_2, "m")?;
    Ok(r1 * r2 / (r1 + r2))
}
