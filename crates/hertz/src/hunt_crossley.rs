//! Hunt-Crossley: Hertz with damping proportional to delta^(3/2) delta-dot.

use crate::error::{positive, HertzError};
use crate::hertz::Hertz;
use crate::law::{ContactForce, ContactLaw};

/// Hunt & Crossley (1975) dissipative Hertz law
/// F = K delta^(3/2) (1 + chi delta-dot), clipped at zero so the contact never pulls.
///
/// The damping factor chi (s/m) relates to a coefficient of restitution e at impact speed V by
/// chi = 3 (1 - e) / (2 V) (Hunt & Crossley 1975, small-damping limit), see
/// [`HuntCrossley::from_restitution`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HuntCrossley {
    hertz: Hertz,
    damping_factor: f64,
}

/// History of a Hunt-Crossley contact: the damping work done so far, integrated over the
/// approach with the trapezoidal rule between committed steps.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct HuntCrossleyState {
    last_approach: f64,
    last_damping_force: f64,
    damping_work: f64,
}

impl HuntCrossley {
    /// From an elastic Hertz contact and the damping factor chi (s/m).
    ///
    /// # Errors
    /// `InvalidParameter` if chi is negative or not finite.
    pub fn new(hertz: Hertz, damping_factor: f64) -> Result<Self, HertzError> {
        if !(damping_factor.is_finite() && damping_factor >= 0.0) {
            return Err(HertzError::InvalidParameter {
                name: "damping",
                value: damping_factor,
                unit: "s/m",
                allowed: "a finite number >= 0",
            });
        }
        Ok(Self { hertz, damping_factor })
    }

    /// chi = 3 (1 - e) / (2 V) for a target restitution e at impact speed V (m/s).
    ///
    /// # Errors
    /// `InvalidParameter` if e is outside (0, 1] or V is not finite and positive.
    pub fn from_restitution(
        hertz: Hertz,
        restitution: f64,
        speed: f64,
    ) -> Result<Self, HertzError> {
        if !(restitution.is_finite() && restitution > 0.0 && restitution <= 1.0) {
            return Err(HertzError::InvalidParameter {
                name: "restitution",
                value: restitution,
                unit: "-",
                allowed: "a number in (0, 1]",
            });
        }
        positive("speed", speed, "m/s")?;
        Self::new(hertz, 1.5 * (1.0 - restitution) / speed)
    }

    /// The elastic part.
    pub fn hertz(&self) -> &Hertz {
        &self.hertz
    }

    /// Damping factor chi (s/m).
    pub fn damping_factor(&self) -> f64 {
        self.damping_factor
    }
}

impl ContactLaw for HuntCrossley {
    type State = HuntCrossleyState;

    fn force(&self, _: &HuntCrossleyState, delta: f64, delta_dot: f64) -> ContactForce {
        let elastic = self.hertz.elastic_force(delta);
        let factor = 1.0 + self.damping_factor * delta_dot;
        if delta <= 0.0 || factor <= 0.0 {
            return ContactForce::default();
        }
        ContactForce {
            force: elastic * factor,
            stiffness: self.hertz.elastic_stiffness(delta) * factor,
            damping: elastic * self.damping_factor,
        }
    }

    fn commit(&self, s: &mut HuntCrossleyState, delta: f64, delta_dot: f64) {
        // The damping work is the integral of the damping force over the approach. When the
        // total force is clipped to zero the damping force is whatever cancels the elastic part.
        let delta = delta.max(0.0);
        let total = self.force(s, delta, delta_dot).force;
        let damping = total - self.hertz.elastic_force(delta);
        s.damping_work += 0.5 * (damping + s.last_damping_force) * (delta - s.last_approach);
        s.last_approach = delta;
        s.last_damping_force = if delta > 0.0 { damping } else { 0.0 };
    }

    fn stored_energy(&self, _: &HuntCrossleyState, delta: f64) -> f64 {
        self.hertz.elastic_energy(delta)
    }

    fn dissipated_energy(&self, s: &HuntCrossleyState) -> f64 {
        s.damping_work
    }
}
