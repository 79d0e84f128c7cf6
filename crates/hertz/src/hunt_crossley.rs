//! Hunt-Crossley: Hertz with damping proportional to delta^(3/2) delta-dot.

use crate::error::{positive, HertzError};
use crate::hertz::Hertz;
use crate::law::{ContactForce, ContactLaw};

/// Hunt & Crossley (1975) dissipative Hertz law
/// F = K delta^(3/2) (1 + chi delta-dot), clipped at zero so the contact never pulls.
///
/// The damping factor chi (s/m) gives a ball striking a massive half-space at speed V the
/// restitution e that solves [`restitution_relation`] (exact for this law; chi = 3 (1 - e) /
/// (2 V), Hunt & Crossley's small-damping limit, is its first term), see
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

    /// The chi that gives restitution e on a massive half-space at impact speed V (m/s):
    /// chi = a / V with a the root of [`restitution_relation`] (exact for this law, where the
    /// small-damping chi = 3 (1 - e) / (2 V) gives 0.77, 0.66, 0.52 for e = 0.7, 0.5, 0.1).
    ///
    /// # Errors
    /// `InvalidParameter` if e is outside (0, 1] or V is not finite and positive.
    pub fn from_restitution(
        hertz: Hertz,
        restitution: f64,
        speed: f64,
    ) -> Result<Self, HertzError> {
        let a = damping_for_restitution(restitution)?;
        positive("speed", speed, "m/s")?;
        Self::new(hertz, a / speed)
    }

    /// The elastic part.
    pub fn hertz(&self) -> &Hertz {
        &self.hertz
    }

    /// Damping factor chi (s/m).
    pub fn damping_factor(&self) -> f64 {
        self.damping_factor
    }

    /// The time (s) from first touch to the peak force of a sphere of `mass` (kg) striking a
    /// rigid half-space at `speed` (m/s): m x'' = -K x^(3/2) (1 + chi x'), integrated by RK4
    /// in steps of a 4000th of the elastic contact's duration until the force stops rising.
    /// The damping raises the force while the approach is still small, so the pulse peaks
    /// sooner than Hertz's half duration (the paper's ball at 1.98 m/s: 20.6 us elastic, 11.6
    /// us at e = 0.5, 5.6 us at e = 0.1), and its fastest content is that much faster.
    ///
    /// # Errors
    /// `InvalidParameter` if the mass or the speed is not finite and positive.
    pub fn half_space_peak_time(&self, mass: f64, speed: f64) -> Result<f64, HertzError> {
        Ok(self.half_space_times(mass, speed)?.0)
    }

    /// The time (s) from first touch to the approach's return to zero on a rigid half-space
    /// (as [`HuntCrossley::half_space_peak_time`]): at a low restitution the force reaches
    /// zero while the surfaces still overlap and the ball creeps out at about 1/chi, so the
    /// contact lasts far longer than Hertz's (the paper's ball at 1.98 m/s: 41.2 us elastic,
    /// 82.8 us at e = 0.1).
    ///
    /// # Errors
    /// `InvalidParameter` if the mass or the speed is not finite and positive.
    pub fn half_space_duration(&self, mass: f64, speed: f64) -> Result<f64, HertzError> {
        Ok(self.half_space_times(mass, speed)?.1)
    }

    /// (peak time, duration) of the rigid half-space impact: RK4 in steps of a 4000th of the
    /// elastic duration, for at most a thousand elastic durations.
    fn half_space_times(&self, mass: f64, speed: f64) -> Result<(f64, f64), HertzError> {
        let elastic = crate::closed_form::HalfSpaceImpact::elastic(&self.hertz, mass, speed)?;
        let h = elastic.duration / 4000.0;
        let k = self.hertz.stiffness_constant();
        let accel = |x: f64, v: f64| {
            -k * x.max(0.0).powf(1.5) * (1.0 + self.damping_factor * v).max(0.0) / mass
        };
        let force = |x: f64, v: f64| -mass * accel(x, v);
        let (mut x, mut v, mut t) = (0.0, speed, 0.0);
        let (mut last, mut peak) = (0.0, None);
        for _ in 0..4_000_000 {
            let (k1x, k1v) = (v, accel(x, v));
            let (k2x, k2v) = (v + 0.5 * h * k1v, accel(x + 0.5 * h * k1x, v + 0.5 * h * k1v));
            let (k3x, k3v) = (v + 0.5 * h * k2v, accel(x + 0.5 * h * k2x, v + 0.5 * h * k2v));
            let (k4x, k4v) = (v + h * k3v, accel(x + h * k3x, v + h * k3v));
            let x1 = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
            v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            let f = force(x1, v);
            if peak.is_none() && f < last {
                peak = Some(t);
            }
            if x1 <= 0.0 && t > 0.0 {
                // The return within the step, linearly.
                return Ok((peak.unwrap_or(t), t + h * x / (x - x1)));
            }
            (x, last, t) = (x1, f, t + h);
        }
        Ok((peak.unwrap_or(0.5 * elastic.duration), t))
    }
}

/// The half-space relation between a = chi V and the restitution e of the Hunt-Crossley law:
///
/// `a - ln(1 + a) = -a e - ln(1 - a e)`.
///
/// With v = delta-dot, the law's equation of motion m v dv = -K delta^(3/2) (1 + chi v) d delta
/// separates: m v dv / (1 + chi v) = -K delta^(3/2) d delta. Integrated from V to 0 over the
/// compression and from 0 to -e V over the restitution, both sides of the second equal minus
/// those of the first (the elastic side goes back over the same approaches), which leaves this
/// relation between a and e alone: the mass, the stiffness and the exponent drop out. Returns
/// its residual `[a - ln(1 + a)] - [-a e - ln(1 - a e)]`, zero at the pair that belongs together.
pub fn restitution_relation(a: f64, e: f64) -> f64 {
    (a - a.ln_1p()) - (-a * e - (-a * e).ln_1p())
}

/// The a = chi V (-) that gives restitution e (in (0, 1]) on a half-space: the root of
/// [`restitution_relation`] in (0, 1 / e), by bisection to round-off (the residual is positive
/// near 0 and falls to minus infinity at 1 / e, one root between).
///
/// # Errors
/// `InvalidParameter` for e not in (0, 1] (it had answered inf, -1 or NaN there, a review's).
pub fn damping_for_restitution(e: f64) -> Result<f64, HertzError> {
    if !(e.is_finite() && e > 0.0 && e <= 1.0) {
        return Err(HertzError::InvalidParameter {
            name: "restitution",
            value: e,
            unit: "-",
            allowed: "a number in (0, 1]",
        });
    }
    if e >= 1.0 {
        return Ok(0.0);
    }
    let (mut lo, mut hi) = (0.0, 1.0 / e);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if restitution_relation(mid, e) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(0.5 * (lo + hi))
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
