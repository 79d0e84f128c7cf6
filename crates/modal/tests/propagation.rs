//! Exact modal propagation against the paper's eq. (1), closed-form responses and convergence.
#![allow(clippy::unwrap_used, clippy::float_cmp)] // helpers stop on bad fixtures; exact zeros are part of the contract

use modal::*;

/// The paper's cantilever (validation/REFERENCES.md / paper: 25 x 5 mm steel, L = 1.15 m).
fn paper_tip(n: usize, damping: f64) -> PointModes {
    let beam = Beam::rectangular(2.1e11, 7850.0, 0.025, 0.005, 1.15, Support::ClampedFree).unwrap();
    let modes = beam.modes(n).unwrap();
    PointModes::new(&beam, &modes, 1.15, damping).unwrap()
}

#[test]
fn zero_order_hold_equals_the_papers_duhamel_series() {
    // Both are exact for a piecewise-constant force, so they agree to round-off: 1e-12 of the
    // largest displacement (~2000 steps of O(modes) sums).
    let tip = paper_tip(64, 0.0);
    let dt = 2e-6;
    let forces: Vec<f64> =
        (0..2000).map(|k| 100.0 * ((k as f64 * 0.013).sin() + (k % 7) as f64 * 0.1)).collect();
    let series = duhamel_series(&tip, &forces, dt).unwrap();
    let step = Transition::new(&tip, dt, Hold::Zero).unwrap();
    let mut s = ModalState::at_rest(tip.len());
    let scale = series.iter().fold(0.0f64, |m, w| m.max(w.abs()));
    assert!(scale > 0.0);
    for (k, f) in forces.iter().enumerate() {
        step.advance(&mut s, *f, f64::NAN);
        let w = tip.displacement(&s);
        assert!((w - series[k + 1]).abs() < 1e-12 * scale, "step {k}: {w} vs {}", series[k + 1]);
    }
}

#[test]
fn free_free_rigid_modes_in_the_series() {
    // A free-free beam has omega = 0 modes; the series uses their limit. Same round-off agreement.
    let beam = Beam::new(10.0, 2.0, 1.0, Support::FreeFree).unwrap();
    let modes = beam.modes(12).unwrap();
    let pm = PointModes::new(&beam, &modes, 0.3, 0.0).unwrap();
    let forces = vec![1.0; 300];
    let series = duhamel_series(&pm, &forces, 1e-4).unwrap();
    let t = Transition::new(&pm, 1e-4, Hold::Zero).unwrap();
    let mut s = ModalState::at_rest(pm.len());
    for (k, f) in forces.iter().enumerate() {
        t.advance(&mut s, *f, 0.0);
        assert!(
            (pm.displacement(&s) - series[k + 1]).abs() < 1e-12 * series[k + 1].abs().max(1e-9)
        );
    }
}

/// Smooth force pulse F(t) = sin^2(pi t / T) on [0, T].
fn pulse(t: f64) -> f64 {
    let period = 1e-4;
    if t < period {
        (std::f64::consts::PI * t / period).sin().powi(2) * 100.0
    } else {
        0.0
    }
}

fn run_foh(tip: &PointModes, h: f64, end: f64) -> f64 {
    let t = Transition::new(tip, h, Hold::FirstOrder).unwrap();
    let mut s = ModalState::at_rest(tip.len());
    let n = (end / h).round() as usize;
    for k in 0..n {
        t.advance(&mut s, pulse(k as f64 * h), pulse((k + 1) as f64 * h));
    }
    tip.displacement(&s)
}

#[test]
fn first_order_hold_converges_at_second_order() {
    // The only error of the exact propagator is the linear interpolation of F, O(h^2). Halving
    // h must divide the error by 4: accept 3.6-4.4 (the asymptotic regime is reached at 20+
    // steps per pulse). Reference: h/64.
    let tip = paper_tip(32, 0.0);
    let end = 2e-4;
    let reference = run_foh(&tip, 1e-4 / 1280.0, end);
    let errors: Vec<f64> = [20.0, 40.0, 80.0]
        .iter()
        .map(|n| (run_foh(&tip, 1e-4 / n, end) - reference).abs())
        .collect();
    for w in errors.windows(2) {
        let ratio = w[0] / w[1];
        assert!((3.6..4.4).contains(&ratio), "ratio {ratio}, errors {errors:?}");
    }
}

#[test]
fn damped_step_response_is_exact() {
    // Unit step force on one damped oscillator from rest (any textbook, e.g. Rao 4.6):
    // q(t) = (g/omega^2)(1 - e^(-zeta omega t)(cos wd t + zeta omega/wd sin wd t)),
    // q'(t) = (g/wd) e^(-zeta omega t) sin wd t. One transition of length t must give it to
    // round-off (1e-13 relative), for omega t from 0.3 to 50. At omega t = 1e-4 (the series
    // branch) the closed form cancels, so the reference there is the Taylor expansion of the
    // ODE, q = g (t^2/2 - zeta omega t^3/3 + (4 zeta^2 - 1) omega^2 t^4/24), exact to (omega t)^5.
    for (omega, zeta) in [(1e3, 0.05), (20.0, 0.3), (5e4, 0.9)] {
        let pm = PointModes::from_parts(vec![omega], vec![zeta], vec![0.7]).unwrap();
        for t in [1e-4 / omega, 0.3 / omega, 2.0 / omega, 50.0 / omega] {
            let wd = omega * (1.0 - zeta * zeta).sqrt();
            let decay = (-zeta * omega * t).exp();
            let (q, v) = if omega * t < 1e-3 {
                let (a, w2) = (zeta * omega, omega * omega);
                (
                    0.7 * (t * t / 2.0 - a * t.powi(3) / 3.0
                        + (4.0 * zeta * zeta - 1.0) * w2 * t.powi(4) / 24.0),
                    0.7 * (t - a * t * t + (4.0 * zeta * zeta - 1.0) * w2 * t.powi(3) / 6.0),
                )
            } else {
                (
                    0.7 / (omega * omega)
                        * (1.0 - decay * ((wd * t).cos() + zeta * omega / wd * (wd * t).sin())),
                    0.7 / wd * decay * (wd * t).sin(),
                )
            };
            for hold in [Hold::Zero, Hold::FirstOrder] {
                let tr = Transition::new(&pm, t, hold).unwrap();
                let mut s = ModalState::at_rest(1);
                tr.advance(&mut s, 1.0, 1.0);
                // Round-off is relative to the response's natural scale (g/omega^2 and g/omega_d
                // at omega t >= 1; the response itself where it is still growing), not to a value
                // that has decayed by e^-15.
                let (q_scale, v_scale) = if omega * t >= 1.0 {
                    (0.7 / (omega * omega), 0.7 / wd)
                } else {
                    (q.abs(), v.abs())
                };
                assert!(
                    (s.q[0] - q).abs() <= 1e-13 * q_scale,
                    "{omega} {zeta} {t}: {} vs {q}",
                    s.q[0]
                );
                assert!(
                    (s.v[0] - v).abs() <= 1e-12 * v_scale,
                    "{omega} {zeta} {t}: {} vs {v}",
                    s.v[0]
                );
            }
        }
    }
}

#[test]
fn damped_free_decay_and_vanishing_damping() {
    // Free decay: the energy after time t is E0 e^(-2 zeta omega t) averaged... exactly,
    // q(t) = e^(-zeta omega t)(q0 cos wd t + (v0 + zeta omega q0)/wd sin wd t).
    let (omega, zeta) = (300.0, 0.02);
    let pm = PointModes::from_parts(vec![omega], vec![zeta], vec![1.0]).unwrap();
    let t = 0.37;
    let tr = Transition::new(&pm, t, Hold::FirstOrder).unwrap();
    let mut s = ModalState { q: vec![1e-3], v: vec![0.2] };
    tr.advance(&mut s, 0.0, 0.0);
    let wd = omega * (1.0 - zeta * zeta).sqrt();
    let q = (-zeta * omega * t).exp()
        * (1e-3 * (wd * t).cos() + (0.2 + zeta * omega * 1e-3) / wd * (wd * t).sin());
    assert!((s.q[0] - q).abs() < 1e-13 * 1e-3);
    // A tiny damping ratio must give the undamped transition (continuity of the two branches).
    let a = Transition::new(
        &PointModes::from_parts(vec![omega], vec![1e-12], vec![1.0]).unwrap(),
        1e-3,
        Hold::FirstOrder,
    )
    .unwrap();
    let b = Transition::new(
        &PointModes::from_parts(vec![omega], vec![0.0], vec![1.0]).unwrap(),
        1e-3,
        Hold::FirstOrder,
    )
    .unwrap();
    let (mut sa, mut sb) =
        (ModalState { q: vec![1e-3], v: vec![0.1] }, ModalState { q: vec![1e-3], v: vec![0.1] });
    a.advance(&mut sa, 2.0, 3.0);
    b.advance(&mut sb, 2.0, 3.0);
    assert!((sa.q[0] - sb.q[0]).abs() < 1e-11 * sb.q[0].abs());
    assert!((sa.v[0] - sb.v[0]).abs() < 1e-11 * sb.v[0].abs());
}

#[test]
fn undamped_free_vibration_conserves_energy_over_long_runs() {
    // Exact transitions are rotations in (omega q, v): 1e5 steps of 256 modes keep the energy
    // to ~1e5 x eps relative (random-walk round-off, bounded here by 1e-10).
    let tip = paper_tip(256, 0.0);
    let t = Transition::new(&tip, 3.3e-6, Hold::FirstOrder).unwrap();
    let mut s = ModalState::at_rest(tip.len());
    t.advance(&mut s, 500.0, 0.0); // an impulse-like kick
    let e0 = tip.energy(&s);
    for _ in 0..100_000 {
        t.advance(&mut s, 0.0, 0.0);
    }
    assert!((tip.energy(&s) - e0).abs() < 1e-10 * e0);
}

#[test]
fn end_displacement_is_affine_in_end_force() {
    // free_displacement + compliance F1 must equal the displacement after advance (the basis of
    // the scalar implicit contact step), to round-off.
    let tip = paper_tip(128, 0.01);
    let t = Transition::new(&tip, 1e-6, Hold::FirstOrder).unwrap();
    let mut s = ModalState {
        q: (0..128).map(|i| 1e-6 / (1.0 + i as f64)).collect(),
        v: (0..128).map(|i| 1e-3 * (i as f64).cos()).collect(),
    };
    let predicted = t.free_displacement(&s, 40.0) + t.compliance() * 55.0;
    t.advance(&mut s, 40.0, 55.0);
    let w = tip.displacement(&s);
    assert!((predicted - w).abs() < 1e-13 * w.abs().max(1e-9), "{predicted} vs {w}");
    assert!(t.compliance() > 0.0);
}

#[test]
fn event_search_displacement_and_step_energy_match_the_transition() {
    // free_displacement_after (no transition built) must give the transition's free end
    // displacement, damped and undamped, for steps where omega h spans the Taylor branch
    // (< 0.5) and the trigonometric one; advance_with_energy's energy must be the modes' own.
    for damping in [0.0, 0.02] {
        let tip = paper_tip(128, damping);
        let s = ModalState {
            q: (0..128).map(|i| 1e-6 / (1.0 + i as f64)).collect(),
            v: (0..128).map(|i| 1e-3 * (i as f64).cos()).collect(),
        };
        for h in [1e-9, 3e-7, 1e-4] {
            let t = Transition::new(&tip, h, Hold::FirstOrder).unwrap();
            let a = t.free_displacement(&s, 40.0);
            let b = tip.free_displacement_after(&s, h, 40.0).unwrap();
            assert!((a - b).abs() < 1e-13 * a.abs(), "h {h}: {a} vs {b}");
            let mut moved = s.clone();
            let (w, energy) = t.advance_with_energy(&mut moved, 40.0, 55.0);
            assert!((w - tip.displacement(&moved)).abs() < 1e-14 * w.abs());
            let exact = tip.energy(&moved);
            assert!((energy - exact).abs() < 1e-14 * exact, "h {h}: {energy} vs {exact}");
            // A step taken once (OneStep, as the event search keeps it) is the transition's.
            let mut once = s.clone();
            let (w1, e1) = tip.advance_once(&mut once, h, 40.0, 55.0).unwrap();
            assert!((w1 - w).abs() < 1e-13 * w.abs() && (e1 - energy).abs() < 1e-13 * energy);
            for (x, y) in once.q.iter().zip(&moved.q).chain(once.v.iter().zip(&moved.v)) {
                assert!((x - y).abs() <= 1e-12 * y.abs().max(1e-18), "h {h}: {x} vs {y}");
            }
            // And the next step's free end displacement, summed while advancing, is the one a
            // second pass over the new state gives, to the last bit.
            let mut next = s.clone();
            let (_, _, predicted) = t.advance_predicting(&mut next, 40.0, 55.0);
            assert_eq!(predicted.to_bits(), t.free_displacement(&next, 55.0).to_bits());
        }
        assert!(tip.free_displacement_after(&s, -1.0, 0.0).is_err());
    }
}
