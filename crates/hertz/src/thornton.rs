//! Thornton's elastic-perfectly-plastic contact law with a permanent print.

use crate::error::{positive, HertzError};
use crate::hertz::Hertz;
use crate::law::{ContactForce, ContactLaw};
use std::f64::consts::PI;

/// Ratio of the central contact pressure at first yield to the uniaxial yield stress,
/// p0 = 1.60 Y (Johnson, *Contact Mechanics* §4.2, Tresca/von Mises with nu ~ 0.3;
/// validation/REFERENCES.md 2.3). With it, Thornton's yield velocity equals Johnson's V_Y.
pub const FIRST_YIELD_PRESSURE_RATIO: f64 = 1.6;

/// Thornton (1997) elastic-perfectly-plastic law (J. Appl. Mech. 64, 383-386):
///
/// * loading below the limiting pressure p_y: Hertz, F = K delta^(3/2);
/// * loading beyond the yield approach delta_y = R (pi p_y / (2 E*))^2: linear,
///   F = F_y + pi p_y R (delta - delta_y) (the contact area grows at constant pressure p_y);
/// * unloading from the largest approach delta_max: Hertz with an enlarged radius R_p and a
///   residual (permanent) approach delta_p, F = (4/3) E* sqrt(R_p) (delta - delta_p)^(3/2),
///   R_p = 4 E* a_p^3 / (3 F_max), a_p^2 = R delta_max, delta_p = delta_max - 3 F_max / (4 E* a_p);
/// * reloading follows the unloading curve elastically until delta_max, then loads plastically.
///
/// The permanent print has rim radius a_p (the contact radius at the largest load) and depth
/// delta_p. The plastic work is the loading work minus the elastic energy recovered on
/// unloading. Limits: no strain hardening, no rate effects, the contact radius stays well below
/// the ball radius (the law does not cap a_p at R).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Thornton {
    hertz: Hertz,
    limiting_pressure: f64,
    yield_approach: f64,
    yield_force: f64,
    plastic_stiffness: f64,
}

/// History of a Thornton contact: the largest approach reached so far (m).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ThorntonState {
    /// Largest approach delta_max reached in a committed step (m).
    pub max_approach: f64,
}

/// The elastic unloading curve from a plastic maximum.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Unloading {
    /// Force at the largest approach (N).
    max_force: f64,
    /// Rim radius of the print a_p (m).
    print_radius: f64,
    /// Residual approach delta_p (m).
    residual_approach: f64,
    /// (4/3) E* sqrt(R_p) (N/m^1.5).
    stiffness_constant: f64,
}

impl Thornton {
    /// From an elastic Hertz contact and the limiting contact pressure p_y (Pa).
    ///
    /// # Errors
    /// `InvalidParameter` if p_y is not finite and positive.
    pub fn new(hertz: Hertz, limiting_pressure: f64) -> Result<Self, HertzError> {
        positive("limiting_pressure", limiting_pressure, "Pa")?;
        let yield_approach = hertz.approach_at_pressure(limiting_pressure)?;
        Ok(Self {
            hertz,
            limiting_pressure,
            yield_approach,
            yield_force: hertz.elastic_force(yield_approach),
            plastic_stiffness: PI * limiting_pressure * hertz.effective_radius(),
        })
    }

    /// With p_y = 1.6 Y, the pressure at which a Hertz contact first yields
    /// ([`FIRST_YIELD_PRESSURE_RATIO`]), for the yield stress Y (Pa) of the softer body.
    ///
    /// # Errors
    /// `InvalidParameter` if Y is not finite and positive.
    pub fn from_yield_stress(hertz: Hertz, yield_stress: f64) -> Result<Self, HertzError> {
        positive("yield_stress", yield_stress, "Pa")?;
        Self::new(hertz, FIRST_YIELD_PRESSURE_RATIO * yield_stress)
    }

    /// The elastic part.
    pub fn hertz(&self) -> &Hertz {
        &self.hertz
    }

    /// Limiting contact pressure p_y (Pa).
    pub fn limiting_pressure(&self) -> f64 {
        self.limiting_pressure
    }

    /// Approach at first yield delta_y (m).
    pub fn yield_approach(&self) -> f64 {
        self.yield_approach
    }

    /// Force at first yield F_y (N).
    pub fn yield_force(&self) -> f64 {
        self.yield_force
    }

    /// Force on the loading curve at approach `delta` (N).
    fn loading_force(&self, delta: f64) -> f64 {
        if delta <= self.yield_approach {
            self.hertz.elastic_force(delta)
        } else {
            self.yield_force + self.plastic_stiffness * (delta - self.yield_approach)
        }
    }

    /// Work done along the loading curve from 0 to `delta` (J).
    fn loading_work(&self, delta: f64) -> f64 {
        if delta <= self.yield_approach {
            return self.hertz.elastic_energy(delta);
        }
        let d = delta - self.yield_approach;
        self.hertz.elastic_energy(self.yield_approach)
            + self.yield_force * d
            + 0.5 * self.plastic_stiffness * d * d
    }

    /// The unloading curve from a largest approach `max_approach` beyond yield.
    fn unloading(&self, max_approach: f64) -> Unloading {
        let e_star = self.hertz.effective_modulus();
        let max_force = self.loading_force(max_approach);
        let print_radius = (self.hertz.effective_radius() * max_approach).sqrt();
        let plastic_radius = 4.0 * e_star * print_radius.powi(3) / (3.0 * max_force);
        Unloading {
            max_force,
            print_radius,
            residual_approach: max_approach - 3.0 * max_force / (4.0 * e_star * print_radius),
            stiffness_constant: 4.0 / 3.0 * e_star * plastic_radius.sqrt(),
        }
    }

    /// The central pressure p0 (Pa) and contact radius a (m) at a contact's peak force `force`
    /// (N) and largest approach `approach` (m), after a history whose largest approach is
    /// `history_max` (m, this contact's included). A contact that reached the history's
    /// largest approach past yield loaded plastically: p0 = p_y over the print's rim a_p. One
    /// that stayed below it reloaded the print elastically (Thornton 1997): Hertz on the
    /// print's enlarged radius R_p, a = (3 F R_p / 4 E*)^(1/3), p0 = 3 F / (2 pi a^2), but no
    /// more than p_y, which it passes near F* (the loading relations there gave p_y over a_p for
    /// a tap of a few newtons: 88 times the force). Below yield, Hertz's.
    pub fn pressure_and_radius(&self, history_max: f64, approach: f64, force: f64) -> (f64, f64) {
        let force = force.max(0.0);
        if history_max <= self.yield_approach {
            let delta = self.hertz.approach_for_force(force);
            return (self.hertz.max_pressure(delta), self.hertz.contact_radius(delta));
        }
        let u = self.unloading(history_max);
        if approach >= history_max * (1.0 - 1e-9) {
            return (self.limiting_pressure, u.print_radius);
        }
        if force == 0.0 {
            return (0.0, 0.0);
        }
        let e_star = self.hertz.effective_modulus();
        // (4/3) E* sqrt(R_p) = the unloading curve's constant.
        let plastic_radius = (0.75 * u.stiffness_constant / e_star).powi(2);
        let radius = (0.75 * force * plastic_radius / e_star).cbrt();
        // Hertz's central pressure on R_p passes p_y near F* (3 F* / (2 pi a_p^2) is 1.5 times
        // the plastic contact's mean pressure; a review's reload at 0.97 F* read 1175 MPa
        // against p_y = 800): the material carries no more than p_y, as in the loading.
        let pressure = 1.5 * force / (std::f64::consts::PI * radius * radius);
        (pressure.min(self.limiting_pressure), radius)
    }

    /// Depth of the permanent print delta_p (m) after the history `state` (0 if elastic).
    pub fn residual_approach(&self, state: &ThorntonState) -> f64 {
        if state.max_approach > self.yield_approach {
            self.unloading(state.max_approach).residual_approach
        } else {
            0.0
        }
    }
}

impl ContactLaw for Thornton {
    type State = ThorntonState;

    fn force(&self, s: &ThorntonState, delta: f64, _delta_dot: f64) -> ContactForce {
        let max = s.max_approach.max(delta);
        if max <= self.yield_approach {
            return self.hertz.force(&(), delta, 0.0);
        }
        if delta >= s.max_approach {
            return ContactForce {
                force: self.loading_force(delta),
                stiffness: self.plastic_stiffness,
                damping: 0.0,
            };
        }
        let u = self.unloading(s.max_approach);
        let e = delta - u.residual_approach;
        if e <= 0.0 {
            return ContactForce::default();
        }
        ContactForce {
            force: u.stiffness_constant * e * e.sqrt(),
            stiffness: 1.5 * u.stiffness_constant * e.sqrt(),
            damping: 0.0,
        }
    }

    fn commit(&self, s: &mut ThorntonState, delta: f64, _delta_dot: f64) {
        s.max_approach = s.max_approach.max(delta);
    }

    fn stored_energy(&self, s: &ThorntonState, delta: f64) -> f64 {
        let max = s.max_approach.max(delta);
        if max <= self.yield_approach {
            return self.hertz.elastic_energy(delta);
        }
        // Elastic unloading from `delta` along the curve of the history that includes `delta`.
        let u = self.unloading(max);
        let e = delta - u.residual_approach;
        if e <= 0.0 {
            0.0
        } else {
            0.4 * u.stiffness_constant * e * e * e.sqrt()
        }
    }

    fn dissipated_energy(&self, s: &ThorntonState) -> f64 {
        if s.max_approach <= self.yield_approach {
            return 0.0;
        }
        let u = self.unloading(s.max_approach);
        self.loading_work(s.max_approach)
            - 0.4 * u.max_force * (s.max_approach - u.residual_approach)
    }

    fn release_approach(&self, s: &ThorntonState) -> f64 {
        self.residual_approach(s)
    }

    fn print_radius(&self, s: &ThorntonState) -> f64 {
        if s.max_approach > self.yield_approach {
            self.unloading(s.max_approach).print_radius
        } else {
            0.0
        }
    }
}
