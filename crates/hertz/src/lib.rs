//! # hertz: contact mechanics of a sphere striking a body
//!
//! Normal contact of a sphere on a flat (or on another sphere) under the Hertz theory, with the
//! laws a ball-impact simulation needs and the closed forms to check it against.
//!
//! **Equations.** The approach delta (m) is positive in compression; the force F (N) is
//! compressive and zero for delta <= 0. With 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 and the
//! effective radius R (Johnson, *Contact Mechanics*, 1985, eqs. 4.22-4.23):
//!
//! * [`Hertz`]: F = K delta^(3/2), K = (4/3) E* sqrt(R) (the paper's eq. 4; its eq. 3 is
//!   [`Hertz::approach_for_force`]);
//! * [`HuntCrossley`]: F = K delta^(3/2) (1 + chi delta-dot) (Hunt & Crossley 1975);
//! * [`Thornton`]: elastic-perfectly-plastic with a limiting pressure p_y, a permanent print and
//!   plastic work (Thornton 1997, J. Appl. Mech. 64, 383);
//! * closed forms for a sphere on a massive half-space ([`HalfSpaceImpact`]), the yield-onset
//!   speed ([`johnson_yield_velocity`], [`elastic_limit_velocity`]) and Thornton's restitution
//!   ([`thornton_restitution`]), validation/REFERENCES.md sections 2.1-2.4.
//!
//! **History.** Laws implement [`ContactLaw`]: `force` is pure, so a Newton iteration can call
//! it freely; the caller owns the law's `State` and calls `commit` once per accepted step.
//!
//! **Units.** SI throughout: m, N, Pa, J, s.
//!
//! ```
//! use hertz::{geometry, ContactLaw, HalfSpaceImpact, Hertz, Material};
//!
//! let steel = Material::new(2.1e11, 0.3)?;
//! let contact = Hertz::between(&steel, &steel, geometry::sphere_on_flat(0.01)?)?;
//! let mass = 7850.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.01f64.powi(3);
//! let impact = HalfSpaceImpact::elastic(&contact, mass, 1.0)?;
//! // validation/REFERENCES.md 2.2: t_c = 69.11 us, F_max = 1750.5 N.
//! assert!((impact.duration - 6.91104e-5).abs() < 1e-9);
//! assert!((contact.force(&(), impact.max_approach, 0.0).force - impact.peak_force).abs() < 1e-9);
//! # Ok::<(), hertz::HertzError>(())
//! ```

mod closed_form;
mod error;
pub mod geometry;
mod hertz;
mod hunt_crossley;
mod law;
mod material;
mod stress;
mod thornton;

pub use closed_form::{
    elastic_limit_velocity, johnson_yield_velocity, thornton_restitution, HalfSpaceImpact,
    HERTZ_DURATION_INTEGRAL,
};
pub use error::HertzError;
pub use hertz::Hertz;
pub use hunt_crossley::{
    damping_for_restitution, restitution_relation, HuntCrossley, HuntCrossleyState,
};
pub use law::{ContactForce, ContactLaw};
pub use material::{effective_modulus, softer_yield_stress, Material};
pub use stress::{max_subsurface_shear, ContactStress};
pub use thornton::{Thornton, ThorntonState, FIRST_YIELD_PRESSURE_RATIO};
