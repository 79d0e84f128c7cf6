//! The dissipation a step reports is the energy HHT removes: on a linear oscillator it accounts
//! for the whole loss, step by step; the trapezoidal rule (alpha = 0) removes none. (A single
//! HHT step may report a negative value: the energy HHT decreases monotonically is a modified
//! one, weighted between the step's ends; the kinetic plus strain energy oscillates around it.)
#![allow(clippy::unwrap_used)] // helpers stop on bad fixtures

use faer::Col;
use hht::{Integrator, NewtonOptions, Oscillator, Scheme, State};

fn energy(omega: f64, s: &State<f64>) -> f64 {
    0.5 * s.v[0] * s.v[0] + 0.5 * omega * omega * s.q * s.q
}

#[test]
fn reported_dissipation_closes_the_energy_balance_of_a_linear_oscillator() {
    // omega h = 0.6: HHT (alpha = -0.3) damps this mode strongly (spectral radius ~0.99 a
    // step), so the loss is large and the balance is a real check. For a linear system the
    // Newmark energy identity is exact: what is left is Newton's tolerance (rtol 1e-10 of the
    // forces) and round-off, measured 1e-13 of the initial energy; 1e-9 leaves margin.
    let omega = 2.0 * std::f64::consts::PI;
    let h = 0.6 / omega;
    let model = Oscillator::undamped(omega).unwrap();
    for (alpha, lossy) in [(-0.3, true), (0.0, false)] {
        let mut integrator = Integrator::new(Scheme::hht(alpha).unwrap(), NewtonOptions::default());
        let mut state = integrator.initial_state(&model, 0.0, 1.0, Col::zeros(1)).unwrap();
        let e0 = energy(omega, &state);
        let mut dissipated = 0.0;
        for _ in 0..200 {
            let report = integrator.step(&model, &mut state, h).unwrap();
            dissipated += report.dissipation;
            let balance = e0 - energy(omega, &state) - dissipated;
            assert!(balance.abs() < 1e-9 * e0, "alpha {alpha}: balance {balance:e}");
        }
        if lossy {
            assert!(dissipated > 0.5 * e0, "HHT should have damped it: {dissipated}");
        } else {
            assert!(dissipated.abs() < 1e-9 * e0, "trapezoidal rule: {dissipated}");
        }
    }
}

/// The oscillator declaring its (constant) mass: the predictor's inertial force is then the old
/// state's, read where it is.
struct ConstantMass(Oscillator);

impl hht::Model for ConstantMass {
    type Config = f64;
    fn ndof(&self) -> usize {
        1
    }
    fn update(&self, q: &mut f64, dq: faer::ColRef<'_, f64>) {
        self.0.update(q, dq);
    }
    fn inertial_force(
        &self,
        q: &f64,
        v: faer::ColRef<'_, f64>,
        a: faer::ColRef<'_, f64>,
        out: faer::ColMut<'_, f64>,
    ) {
        self.0.inertial_force(q, v, a, out);
    }
    fn constant_mass(&self) -> bool {
        true
    }
    fn net_force(&self, t: f64, q: &f64, v: faer::ColRef<'_, f64>, out: faer::ColMut<'_, f64>) {
        self.0.net_force(t, q, v, out);
    }
    fn tangent(
        &self,
        t: f64,
        q: &f64,
        v: faer::ColRef<'_, f64>,
        a: faer::ColRef<'_, f64>,
        w: hht::NewtonWeights,
        out: &mut hht::Triplets,
    ) {
        self.0.tangent(t, q, v, a, w, out);
    }
}

#[test]
fn a_constant_mass_and_the_predictor_read_in_place_change_no_bit() {
    // The same oscillator stepped with and without declaring its mass constant (the step then
    // reads the predictor's acceleration, increment and inertial force where they are, and
    // fills the new state's columns only if the predictor is accepted): the same states and
    // reports, bit for bit, over 50 steps with a kept Newton matrix and without.
    let omega = 2.0 * std::f64::consts::PI;
    let h = 0.6 / omega;
    let plain = Oscillator::undamped(omega).unwrap();
    let constant = ConstantMass(Oscillator::undamped(omega).unwrap());
    for reuse_factorisation in [false, true] {
        let options = NewtonOptions { reuse_factorisation, ..NewtonOptions::default() };
        let scheme = Scheme::hht(-0.3).unwrap();
        let (mut a, mut b) = (Integrator::new(scheme, options), Integrator::new(scheme, options));
        let mut x = a.initial_state(&plain, 0.0, 1.0, Col::zeros(1)).unwrap();
        let mut y = b.initial_state(&constant, 0.0, 1.0, Col::zeros(1)).unwrap();
        for _ in 0..50 {
            let (rx, ry) =
                (a.step(&plain, &mut x, h).unwrap(), b.step(&constant, &mut y, h).unwrap());
            assert_eq!(rx.iterations, ry.iterations);
            assert_eq!(rx.dissipation.to_bits(), ry.dissipation.to_bits());
            assert_eq!(rx.error_estimate.to_bits(), ry.error_estimate.to_bits());
            let bits = |s: &State<f64>| [s.q, s.v[0], s.a[0]].map(f64::to_bits);
            assert_eq!(bits(&x), bits(&y));
        }
        // At rest under no force the predictor is the answer (no iteration): the new state's
        // acceleration and inertial force are the old ones, written into its own columns (the
        // integrator's spare ones hold the moving oscillator's: left there, the next step
        // would move).
        let mut rest = b.initial_state(&constant, 0.0, 0.0, Col::zeros(1)).unwrap();
        for _ in 0..3 {
            let report = b.step(&constant, &mut rest, h).unwrap();
            assert_eq!(report.iterations, 0);
            assert_eq!((rest.q, rest.v[0], rest.a[0], report.dissipation), (0.0, 0.0, 0.0, 0.0));
        }
    }
}
