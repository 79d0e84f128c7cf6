//! Eigenvalues, mode shapes and static identities against validation/REFERENCES.md 1 and high-precision values.
#![allow(clippy::unwrap_used, clippy::float_cmp)] // helpers stop on bad fixtures; exact zeros are part of the contract

use modal::*;
use std::f64::consts::PI;

/// validation/REFERENCES.md 1.1, b_n L of the cantilever, 15 significant digits (mpmath, 40 digits).
const CANTILEVER: [f64; 10] = [
    1.87510406871196,
    4.69409113297417,
    7.85475743823761,
    10.9955407348755,
    14.1371683910465,
    17.2787595320882,
    20.4203522510413,
    23.5619449018064,
    26.7035375555183,
    29.8451302091028,
];

#[test]
fn cantilever_eigenvalues_match_table() {
    // 15 printed digits: 1e-14 relative is one unit in the last digit.
    for (n, r) in CANTILEVER.iter().enumerate() {
        let x = Support::ClampedFree.eigenvalue(n + 1).unwrap();
        assert!((x - r).abs() / r < 1e-14, "mode {}: {x} vs {r}", n + 1);
    }
}

#[test]
fn other_supports_first_roots() {
    // mpmath at 60 digits (findroot on the same bounded equations), printed to 16 digits.
    let cases = [
        (Support::ClampedClamped, [4.730040744862704, 7.853204624095838, 10.99560783800167]),
        (Support::FreeFree, [4.730040744862704, 7.853204624095838, 10.99560783800167]),
        (Support::ClampedPinned, [3.926602312047919, 7.068582745628732, 10.21017612281303]),
        (Support::PinnedPinned, [PI, 2.0 * PI, 3.0 * PI]),
    ];
    for (s, roots) in cases {
        for (n, r) in roots.iter().enumerate() {
            let x = s.eigenvalue(n + 1).unwrap();
            assert!((x - r).abs() / r < 1e-14, "{s} mode {}: {x} vs {r}", n + 1);
        }
    }
}

#[test]
fn thousand_modes_to_round_off() {
    // Past mode ~10 the roots equal their asymptotes up to 2 exp(-x) (validation/REFERENCES.md 1.1), which
    // is below 1e-16 relative from mode 15 on; so the asymptote is an independent reference
    // to round-off there. Tolerance 1e-13 relative: ~100 ulps, far inside the 1e-10 asked.
    for s in Support::ALL {
        for n in (15..=1000).step_by(7) {
            let x = s.eigenvalue(n).unwrap();
            let asym = match s {
                Support::ClampedFree => (2 * n - 1) as f64 * PI / 2.0,
                Support::PinnedPinned => n as f64 * PI,
                Support::ClampedClamped | Support::FreeFree => (2 * n + 1) as f64 * PI / 2.0,
                Support::ClampedPinned => (4 * n + 1) as f64 * PI / 4.0,
            };
            assert!((x - asym).abs() / asym < 1e-13, "{s} mode {n}: {x} vs {asym}");
        }
    }
}

#[test]
fn cantilever_tip_value_is_two_for_every_mode() {
    // validation/REFERENCES.md 1.2: phi_n(L) = 2 (-1)^(n+1) exactly in the textbook scaling.
    let beam = Beam::new(1.0, 1.0, 1.0, Support::ClampedFree).unwrap();
    for (i, m) in beam.modes(1000).unwrap().iter().enumerate() {
        let expected = if i % 2 == 0 { 2.0 } else { -2.0 };
        assert!(
            (m.shape.value(1.0) - expected).abs() < 1e-12,
            "mode {}: {}",
            i + 1,
            m.shape.value(1.0)
        );
        // Clamp: phi(0) = phi'(0) = 0; free end: phi''(L) = phi'''(L) = 0 (relative to beta^k).
        let b = m.shape.beta();
        assert!(m.shape.value(0.0).abs() < 1e-12);
        assert!((m.shape.slope(0.0) / b).abs() < 1e-12);
        assert!((m.shape.curvature(1.0) / (b * b)).abs() < 1e-12);
        assert!((m.shape.derivative(3, 1.0) / b.powi(3)).abs() < 1e-12);
    }
}

#[test]
fn mode_500_matches_high_precision_reference() {
    // validation/reference/cantilever_mode500.csv: mpmath at 800 digits. Values are O(1), so
    // 1e-12 absolute allows ~1e-13 for the argument beta x ~ 1569 (its ulp is 2e-13).
    // Compiled in: no file to read at run time (a full run once failed to read it, transiently).
    let text = include_str!("../../../validation/reference/cantilever_mode500.csv");
    let beam = Beam::new(1.0, 1.0, 1.0, Support::ClampedFree).unwrap();
    let beta_l = Support::ClampedFree.eigenvalue(500).unwrap();
    assert!((beta_l - 1_569.225_530_468_101_7).abs() < 1e-12);
    let mode = beam.modes(500).unwrap()[499];
    let mut rows = 0;
    for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let b = mode.shape.beta();
        assert!((mode.shape.value(v[0]) - v[1]).abs() < 2e-12, "phi at {}", v[0]);
        assert!((mode.shape.slope(v[0]) / b - v[2]).abs() < 2e-12, "slope at {}", v[0]);
        assert!(
            (mode.shape.curvature(v[0]) / (b * b) - v[3]).abs() < 2e-12,
            "curvature at {}",
            v[0]
        );
        rows += 1;
    }
    assert_eq!(rows, 9);
}

/// Composite 5-point Gauss-Legendre on [0, L] with `panels` panels.
fn integrate(f: impl Fn(f64) -> f64, length: f64, panels: usize) -> f64 {
    let nodes = [0.0, 0.538469310105683, -0.538469310105683, 0.906179845938664, -0.906179845938664];
    let weights = [
        0.568888888888889,
        0.478628670499366,
        0.478628670499366,
        0.236926885056189,
        0.236926885056189,
    ];
    let h = length / panels as f64;
    (0..panels)
        .map(|p| {
            let mid = (p as f64 + 0.5) * h;
            nodes.iter().zip(&weights).map(|(x, w)| w * f(mid + 0.5 * h * x)).sum::<f64>() * 0.5 * h
        })
        .sum()
}

#[test]
fn modes_are_orthonormal() {
    // 5-point Gauss-Legendre on 600 panels: mode 40 has beta L ~ 127, i.e. ~40 half-waves, so
    // each panel spans under a tenth of a half-wave and the rule's error (h^10 f^(10)) is ~1e-14;
    // the nodes and weights are given to 15 digits, so 1e-10 is the justified bound.
    for s in Support::ALL {
        let beam = Beam::new(1.0, 1.0, 2.0, s).unwrap();
        let modes = beam.modes(40).unwrap();
        for i in (0..40).step_by(3) {
            for j in (i..40).step_by(5) {
                let v = integrate(|x| modes[i].shape.value(x) * modes[j].shape.value(x), 2.0, 600);
                let expected = if i == j { 2.0 } else { 0.0 };
                assert!((v - expected).abs() < 1e-10, "{s}: <{i}, {j}> = {v}");
            }
        }
    }
}

#[test]
fn static_compliance_identity() {
    // sum phi_n(c)^2 / omega_n^2 / (rho A L) = static flexibility at c (validation/REFERENCES.md 6.3 and
    // beam tables). With 3000 modes the neglected tail is below sum_{n>3000} 4/((n-1/2) pi)^4 ~
    // 2e-13 of L^3/EI, i.e. < 1e-10 relative to any flexibility tested; tolerance 1e-9.
    for s in [
        Support::ClampedFree,
        Support::PinnedPinned,
        Support::ClampedClamped,
        Support::ClampedPinned,
    ] {
        let beam = Beam::new(3.0, 2.0, 1.5, s).unwrap();
        let modes = beam.modes(3000).unwrap();
        let points: &[f64] = if s == Support::ClampedFree { &[1.5, 0.45] } else { &[0.45, 0.75] };
        for &c in points {
            let pm = PointModes::new(&beam, &modes, c, 0.0).unwrap();
            let exact = beam.static_flexibility(c).unwrap();
            let sum = pm.static_flexibility();
            assert!((sum - exact).abs() / exact < 1e-9, "{s} at {c}: {sum} vs {exact}");
        }
    }
    // validation/REFERENCES.md 1.2: sum 4/(b_n L)^4 = 1/3 for the cantilever tip.
    let s: f64 =
        (1..=3000).map(|n| 4.0 / Support::ClampedFree.eigenvalue(n).unwrap().powi(4)).sum();
    assert!((s - 1.0 / 3.0).abs() < 1e-10);
}

#[test]
fn bad_beams_are_rejected() {
    let e = Beam::new(1.0, 1.0, -1.0, Support::ClampedFree).unwrap_err();
    assert!(e.to_string().contains("length = -1"), "{e}");
    assert!(Beam::new(f64::NAN, 1.0, 1.0, Support::ClampedFree).is_err());
    assert!(Beam::rectangular(2e11, 7850.0, 0.0, 0.005, 1.0, Support::ClampedFree).is_err());
    let beam = Beam::new(1.0, 1.0, 1.0, Support::ClampedFree).unwrap();
    assert!(beam.modes(0).is_err());
    let modes = beam.modes(4).unwrap();
    assert!(PointModes::new(&beam, &modes, 1.5, 0.0).is_err());
    assert!(PointModes::new(&beam, &modes, 0.5, 1.0).is_err());
    assert!(Support::from_name("clamped-floppy")
        .unwrap_err()
        .to_string()
        .contains("clamped-floppy"));
    assert_eq!(Support::from_name("free-free").unwrap(), Support::FreeFree);
}

#[test]
fn the_modal_series_of_the_static_moment_converges_to_the_beam_tables() {
    // The static curvature under a unit force at c is sum_n phi_n''(x) phi_n(c) / (M omega_n^2)
    // over all modes (mass-normalised, M = rho A L); its tail falls as 1/n^2 (curvature
    // ~ n^2 against omega^2 ~ n^4) away from c, so 2000 modes leave about 1e-4 of the largest
    // moment there. The closed forms (Beam::static_curvature, Roark Table 8.1) must agree.
    // Steel, 25 x 5 mm, L = 1.15 m (the paper's beam); force at c = 0.4 L.
    // Free-free by inertia relief: the elastic modes alone (the rigid ones carry no moment).
    for support in [
        Support::ClampedFree,
        Support::PinnedPinned,
        Support::ClampedClamped,
        Support::ClampedPinned,
        Support::FreeFree,
    ] {
        let beam = Beam::rectangular(2.1e11, 7850.0, 0.025, 0.005, 1.15, support).unwrap();
        let modes: Vec<_> =
            beam.modes(2000).unwrap().into_iter().filter(|m| m.omega > 0.0).collect();
        let c = 0.46;
        let scale = 1.0 / beam.mass();
        let largest = (0..=100)
            .map(|k| beam.static_curvature(c, 1.15 * k as f64 / 100.0).unwrap().abs())
            .fold(0.0, f64::max);
        for x in [0.0, 0.1, 0.3, 0.6, 0.9, 1.1, 1.15] {
            let series: f64 = modes
                .iter()
                .map(|m| m.shape.curvature(x) * m.shape.value(c) * scale / (m.omega * m.omega))
                .sum();
            let exact = beam.static_curvature(c, x).unwrap();
            assert!(
                (series - exact).abs() < 1e-3 * largest,
                "{support:?} at x = {x}: series {series:e} against {exact:e} (largest {largest:e})"
            );
        }
    }
    // Free-free, Timoshenko: the rotary inertia takes its share of the relief (the series of
    // its own modes agrees to the same 1e-3), and both free ends hold no moment.
    let free = Beam::rectangular(2.1e11, 7850.0, 0.025, 0.005, 1.15, Support::FreeFree)
        .unwrap()
        .with_shear(0.8333 * 8.1e10 * 1.25e-4, 7850.0 * 2.6e-10)
        .unwrap();
    let modes: Vec<_> = free.modes(2000).unwrap().into_iter().filter(|m| m.omega > 0.0).collect();
    let c = 0.46;
    let largest = (0..=100)
        .map(|k| free.static_curvature(c, 1.15 * k as f64 / 100.0).unwrap().abs())
        .fold(0.0, f64::max);
    for x in [0.1, 0.3, 0.6, 0.9, 1.1] {
        let series: f64 = modes
            .iter()
            .map(|m| m.shape.curvature(x) * m.shape.value(c) / free.mass() / (m.omega * m.omega))
            .sum();
        let exact = free.static_curvature(c, x).unwrap();
        assert!((series - exact).abs() < 1e-3 * largest, "x = {x}: {series:e} vs {exact:e}");
    }
    for end in [0.0, 1.15] {
        assert!(free.static_curvature(c, end).unwrap().abs() < 1e-12 * largest);
    }
}

/// The paper's beam (steel, 25 x 5 mm, L = 1.15 m) on `support`, Euler-Bernoulli and
/// Timoshenko (k G A with k = 0.8333, rho I).
fn both_theories(support: Support) -> [Beam; 2] {
    let base = Beam::rectangular(2.1e11, 7850.0, 0.025, 0.005, 1.15, support).unwrap();
    let timoshenko = base.with_shear(0.8333 * 8.1e10 * 1.25e-4, 7850.0 * 2.6e-10).unwrap();
    [base, timoshenko]
}

#[test]
fn curvatures_on_a_grid_match_the_pointwise_ones() {
    // The carried terms against direct evaluation, for every support and modes 1 to 600 (the
    // boundary layers of the high modes decay over a small fraction of the grid step).
    for support in Support::ALL {
        let beam = Beam::rectangular(2.1e11, 7850.0, 0.025, 0.005, 1.15, support).unwrap();
        for m in beam.modes(600).unwrap().iter().step_by(7) {
            let (x0, dx, count) = (0.0, 1.15 / 32.0, 33);
            let grid = m.shape.curvatures_on_grid(x0, dx, count);
            let largest = (m.shape.beta() * m.shape.beta()).max(1e-300) * 4.0;
            for (k, g) in grid.iter().enumerate() {
                let direct = m.shape.curvature(x0 + dx * k as f64);
                assert!(
                    (g - direct).abs() <= 1e-12 * largest,
                    "{support:?} beta {}: {g} vs {direct} at {k}",
                    m.shape.beta()
                );
            }
        }
    }
}

#[test]
fn curvature_bounds_hold_everywhere_and_are_not_vacuous() {
    // ModeShape::curvature_bound(k) bounds |d^k Psi'/dx^k| on the whole beam. Checked against
    // the curvature sampled at 20001 points and its second derivative by central differences
    // (step 1e-4 L: truncation ~ (beta dx)^2/12 < 1e-3 of it up to mode 60), for both
    // theories and every support, up to mode 60. The bound sums the waves' magnitudes, so it
    // exceeds the sampled maximum by at most their count (3): asserted below 4x.
    for support in Support::ALL {
        for beam in both_theories(support) {
            let length = beam.length();
            for mode in beam.modes(60).unwrap().iter().filter(|m| m.omega > 0.0) {
                let s = &mode.shape;
                let (b0, b2) = (s.curvature_bound(0), s.curvature_bound(2));
                let dx = 1e-4 * length;
                let (mut m0, mut m2) = (0.0_f64, 0.0_f64);
                for k in 0..=20000 {
                    let x = length * k as f64 / 20000.0;
                    m0 = m0.max(s.curvature(x).abs());
                    if x > dx && x < length - dx {
                        let d2 = (s.curvature(x + dx) - 2.0 * s.curvature(x) + s.curvature(x - dx))
                            / (dx * dx);
                        m2 = m2.max(d2.abs());
                    }
                }
                assert!(m0 <= b0 * (1.0 + 1e-12) && b0 < 4.0 * m0, "{support}: {m0} vs {b0}");
                assert!(m2 <= b2 * (1.0 + 1e-3) && b2 < 4.0 * m2, "{support}: {m2} vs {b2}");
            }
        }
    }
}

#[test]
fn curvature_derivatives_match_finite_differences() {
    // d^k Psi'/dx^k against central differences of the order below (step 1e-5 L: truncation
    // (beta h)^2/6 < 1e-6 at mode 20, round-off ~1e-16 L^2 beta^2 / h^2 far below), both
    // theories, at 37 points; relative to the derivative's scale beta^(k+2).
    for beam in both_theories(Support::ClampedPinned) {
        for mode in beam.modes(20).unwrap() {
            let s = &mode.shape;
            let (h, scale) = (1e-5 * 1.15, mode.shape.beta());
            for i in 1..37 {
                let x = 1.15 * i as f64 / 37.0;
                for k in 1..=2 {
                    let below = |x: f64| s.curvature_derivative(k - 1, x);
                    let fd = (below(x + h) - below(x - h)) / (2.0 * h);
                    let got = s.curvature_derivative(k, x);
                    let size = scale.powi(k as i32 + 2);
                    assert!((got - fd).abs() < 1e-5 * size, "k {k} at {x}: {got} vs {fd}");
                }
                assert_eq!(s.curvature_derivative(0, x), s.curvature(x));
            }
        }
    }
}

#[test]
fn curvatures_of_many_modes_at_once_match_each_modes_own() {
    // modal::Curvatures (the waves' factors from vectorised sine, cosine and exponential)
    // against ModeShape::curvature_derivative, k = 0, 1, 2, for both theories, every support,
    // 600 modes (wave arguments to about 1900 rad), at 41 points: within 1e-14 of the term
    // sum curvature_bound(k) (each wave's factor within 2 ulp: a few ulps of the sum).
    for support in Support::ALL {
        for beam in both_theories(support) {
            let modes = beam.modes(600).unwrap();
            let batch = modal::Curvatures::new(modes.iter().map(|m| &m.shape));
            assert_eq!(batch.len(), modes.len());
            let mut rows = [vec![0.0; modes.len()], vec![0.0; modes.len()], vec![0.0; modes.len()]];
            for i in 0..=40 {
                let x = 1.15 * i as f64 / 40.0;
                let [a, b, c] = &mut rows;
                batch.at(x, &mut [a.as_mut_slice(), b.as_mut_slice(), c.as_mut_slice()]);
                for (k, row) in rows.iter().enumerate() {
                    for (m, got) in modes.iter().zip(row) {
                        let own = m.shape.curvature_derivative(k as u32, x);
                        let scale = m.shape.curvature_bound(k as i32);
                        assert!(
                            (got - own).abs() <= 1e-14 * scale,
                            "{support:?} beta {} k {k} at {x}: {got} vs {own}",
                            m.shape.beta()
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn a_static_flexibility_off_the_beam_is_none() {
    // A review's cantilever answered -6.1e-3 m/N at c = -1 m and NaN for NaN; on the beam,
    // to round-off at its ends, the closed form.
    let beam = Beam::new(1.0, 1.0, 1.15, Support::ClampedFree).unwrap();
    for c in [-1.0, 2.3, f64::NAN] {
        assert_eq!(beam.static_flexibility(c), None, "{c}");
        assert_eq!(beam.static_curvature(c, 0.5), None, "{c}");
    }
    assert!(beam.static_flexibility(1.15 * (1.0 + 1e-15)).is_some());
    assert!(beam.static_curvature(0.5, 1.15).is_some());
}

#[test]
#[should_panic(expected = "ModalState::at_rest(5)")]
fn a_state_for_other_modes_is_refused_by_its_lengths() {
    // A short state had panicked inside a vector kernel, or been read as if its missing modes
    // were at rest (a review's): the panic now names both lengths and the remedy.
    let beam = Beam::new(1.0, 1.0, 1.15, Support::ClampedFree).unwrap();
    let modes = beam.modes(5).unwrap();
    let point = PointModes::new(&beam, &modes, 1.15, 0.0).unwrap();
    let _ = point.displacement(&modal::ModalState::at_rest(2));
}
