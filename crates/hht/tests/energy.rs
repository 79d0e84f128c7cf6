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
