//! The contact-law interface shared by every law.

/// Contact force and its derivatives at one approach and approach rate.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactForce {
    /// Compressive contact force F (N), never negative.
    pub force: f64,
    /// Stiffness dF/d(delta) (N/m).
    pub stiffness: f64,
    /// Damping dF/d(delta-dot) (N s/m).
    pub damping: f64,
}

/// A normal contact law F(delta, delta-dot) with an explicit history state.
///
/// The approach `delta` (m) is positive in compression and the force is zero for
/// `delta <= release_approach(state)`. Laws with a history (plasticity, hysteretic damping)
/// keep it in `State`, which the caller owns: `force` never changes the state, so a Newton
/// iteration may evaluate it freely, and `commit` is called once per accepted step.
pub trait ContactLaw {
    /// History carried between accepted steps.
    type State: Clone + Default + std::fmt::Debug;

    /// Force, stiffness and damping at (delta, delta-dot), given the committed history.
    fn force(&self, state: &Self::State, delta: f64, delta_dot: f64) -> ContactForce;

    /// Records an accepted step ending at (delta, delta-dot).
    fn commit(&self, state: &mut Self::State, delta: f64, delta_dot: f64);

    /// Elastic energy (J) stored in the contact at approach `delta`: what elastic unloading
    /// from `delta` would give back.
    fn stored_energy(&self, state: &Self::State, delta: f64) -> f64;

    /// Energy (J) dissipated by the contact so far (plastic work, damping work).
    fn dissipated_energy(&self, state: &Self::State) -> f64;

    /// Approach (m) below which the force is zero: 0 for a pristine surface, the residual
    /// depth of the permanent print after plastic loading.
    fn release_approach(&self, _state: &Self::State) -> f64 {
        0.0
    }

    /// Radius (m) of the permanent print left so far (0 if the contact stayed elastic).
    fn print_radius(&self, _state: &Self::State) -> f64 {
        0.0
    }
}
