//! A single linear oscillator: the smallest [`Model`], used by the examples, tests and benches.

use crate::error::HhtError;
use crate::model::{Model, NewtonWeights, Triplets};
use faer::{ColMut, ColRef};

/// `m a + c v + k d = f` for one degree of freedom.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Oscillator {
    /// Mass m (kg).
    pub mass: f64,
    /// Viscous damping c (N s/m).
    pub damping: f64,
    /// Stiffness k (N/m).
    pub stiffness: f64,
    /// Constant applied force f (N).
    pub force: f64,
}

impl Oscillator {
    /// An undamped, unloaded oscillator with natural frequency `omega` (rad/s) and unit mass.
    ///
    /// # Errors
    /// [`HhtError::InvalidParameter`] when `omega` is not finite and positive.
    pub fn undamped(omega: f64) -> Result<Self, HhtError> {
        if !(omega.is_finite() && omega > 0.0) {
            return Err(HhtError::InvalidParameter {
                name: "omega",
                value: omega,
                allowed: "a finite angular frequency greater than zero (rad/s)",
            });
        }
        Ok(Self { mass: 1.0, damping: 0.0, stiffness: omega * omega, force: 0.0 })
    }
}

impl Model for Oscillator {
    type Config = f64;

    fn ndof(&self) -> usize {
        1
    }

    fn update(&self, q: &mut f64, dq: ColRef<'_, f64>) {
        *q += dq[0];
    }

    fn inertial_force(
        &self,
        _q: &f64,
        _v: ColRef<'_, f64>,
        a: ColRef<'_, f64>,
        mut out: ColMut<'_, f64>,
    ) {
        out[0] = self.mass * a[0];
    }

    fn net_force(&self, _t: f64, q: &f64, v: ColRef<'_, f64>, mut out: ColMut<'_, f64>) {
        out[0] = self.damping * v[0] + self.stiffness * q - self.force;
    }

    fn tangent(
        &self,
        _t: f64,
        _q: &f64,
        _v: ColRef<'_, f64>,
        _a: ColRef<'_, f64>,
        w: NewtonWeights,
        out: &mut Triplets,
    ) {
        let value =
            w.inertia * w.da * self.mass + w.force * (w.dv * self.damping + w.dq * self.stiffness);
        out.push(0, 0, value);
    }
}
