//! Timoshenko modes against closed forms, the Euler-Bernoulli limit and their own identities
#![allow(clippy::unwrap_used)] // helpers stop on bad fixtures
//! (validation/REFERENCES.md 1.6).

use modal::{Beam, PointModes, Support};

/// Steel, 5/6 shear coefficient, nu = 0.3: a rectangle `width` x `thickness`, length `length`.
fn steel(length: f64, thickness: f64, support: Support) -> Beam {
    let (e, nu, rho, width) = (2.1e11, 0.3, 7850.0, 0.025);
    let g = e / (2.0 * (1.0 + nu));
    let area = width * thickness;
    let inertia = width * thickness.powi(3) / 12.0;
    Beam::rectangular(e, rho, width, thickness, length, support)
        .unwrap()
        .with_shear(5.0 / 6.0 * g * area, rho * inertia)
        .unwrap()
}

/// Pinned-pinned: W = sin(n pi x/L), Psi = C cos(n pi x/L), so each n gives the two roots of
/// det(K - omega^2 M) = 0 with K = [[kGA k^2, -kGA k], [-kGA k, EI k^2 + kGA]], M = diag(rho A,
/// rho I), k = n pi / L; n = 0 adds W = 0, Psi = const at the cut-off sqrt(kGA / rho I).
fn pinned_pinned_closed_form(beam: &Beam, count: usize) -> Vec<f64> {
    let shear = beam.shear().unwrap();
    let (ei, rho_a, kga, rho_i) =
        (beam.flexural_rigidity(), beam.mass_per_length(), shear.rigidity, shear.rotary_inertia);
    let mut all = vec![(kga / rho_i).sqrt()];
    for n in 1..=count {
        let k = n as f64 * std::f64::consts::PI / beam.length();
        let a = rho_a * rho_i;
        let b = rho_a * (ei * k * k + kga) + rho_i * kga * k * k;
        let c = kga * ei * k.powi(4);
        let root = (b * b - 4.0 * a * c).sqrt();
        // Smaller root without cancellation: c / (a * larger).
        let larger = (b + root) / (2.0 * a);
        all.push((c / (a * larger)).sqrt());
        all.push(larger.sqrt());
    }
    all.sort_by(f64::total_cmp);
    all.truncate(count);
    all
}

#[test]
fn pinned_pinned_frequencies_are_the_closed_form_on_both_branches() {
    // A thick beam (L/h = 5): the shear branch starts at the 9th mode and interleaves.
    for (length, count) in [(0.05, 300), (1.15, 1200)] {
        let beam = steel(length, 0.01, Support::PinnedPinned);
        let modes = beam.modes(count).unwrap();
        let exact = pinned_pinned_closed_form(&beam, count);
        assert_eq!(modes.len(), count);
        for (i, (m, w)) in modes.iter().zip(&exact).enumerate() {
            assert!(
                (m.omega - w).abs() <= 1e-11 * w,
                "L {length} mode {}: {} vs {w}",
                i + 1,
                m.omega
            );
        }
        assert_eq!(beam.count_below(exact[count - 1] * (1.0 + 1e-9)).unwrap(), count);
    }
}

#[test]
fn slender_beams_tend_to_euler_bernoulli() {
    // Shear and rotary inertia lower every frequency by a first-order correction
    // c_n (beta_n r)^2 (r^2 = I/A, c_n = (1 + E/(kG))/2 at pinned-pinned and for high modes),
    // so halving the thickness of a slender beam divides the relative difference by 4.
    for support in Support::ALL {
        let difference = |h: f64| -> Vec<f64> {
            let beam = steel(1.15, h, support);
            let eb = beam.euler_bernoulli().modes(8).unwrap();
            let ti = beam.modes(8).unwrap();
            eb.iter()
                .zip(&ti)
                .filter(|(e, _)| e.omega > 0.0)
                .map(|(e, t)| (e.omega - t.omega) / e.omega)
                .collect()
        };
        let (thick, thin) = (difference(0.004), difference(0.002));
        for (k, (a, b)) in thick.iter().zip(&thin).enumerate() {
            assert!(*b > 0.0 && *b < 1e-3, "{support} mode {k}: {b}");
            assert!((a / b - 4.0).abs() < 0.02, "{support} mode {k}: ratio {}", a / b);
        }
        if support == Support::PinnedPinned {
            let r2 = 0.002f64.powi(2) / 12.0;
            for (n, b) in thin.iter().enumerate() {
                let beta = (n + 1) as f64 * std::f64::consts::PI / 1.15;
                let predicted = 0.5 * beta * beta * r2 * (1.0 + 2.0 * 1.3 * 6.0 / 5.0);
                assert!((b / predicted - 1.0).abs() < 1e-3, "mode {n}: {b} vs {predicted}");
            }
        }
    }
}

/// Nodes and weights of composite 8-point Gauss-Legendre on [0, L] with `panels` panels.
fn gauss_grid(length: f64, panels: usize) -> (Vec<f64>, Vec<f64>) {
    let nodes = [
        0.183_434_642_495_649_8,
        0.525_532_409_916_329,
        0.796_666_477_413_626_7,
        0.960_289_856_497_536_3,
    ];
    let weights = [
        0.362_683_783_378_362,
        0.313_706_645_877_887_3,
        0.222_381_034_453_374_5,
        0.101_228_536_290_376_3,
    ];
    let h = length / panels as f64;
    let (mut x, mut w) = (Vec::new(), Vec::new());
    for p in 0..panels {
        let mid = (p as f64 + 0.5) * h;
        for (node, weight) in nodes.iter().zip(&weights) {
            for sign in [-1.0, 1.0] {
                x.push(mid + sign * 0.5 * h * node);
                w.push(0.5 * h * weight);
            }
        }
    }
    (x, w)
}

#[test]
fn modes_are_mass_orthonormal_and_meet_their_end_conditions() {
    // integral (W_i W_j + (rho I/rho A) Psi_i Psi_j) dx = L delta_ij, by quadrature, for every
    // support on a thick beam (L/h = 5), modes 1-40 (both branches), and 1000-1006.
    for support in Support::ALL {
        let beam = steel(0.05, 0.01, support);
        let rotary = 0.01f64.powi(2) / 12.0;
        let modes = beam.modes(1006).unwrap();
        let picked: Vec<usize> = (0..40).chain(999..1006).collect();
        // Composite 8-point Gauss-Legendre, 3000 panels (8 points per half wave at mode 1000).
        let (points, weights) = gauss_grid(0.05, 3000);
        let sampled: Vec<(Vec<f64>, Vec<f64>)> = picked
            .iter()
            .map(|&i| {
                let s = &modes[i].shape;
                (
                    points.iter().map(|&x| s.value(x)).collect(),
                    points.iter().map(|&x| s.rotation_at(x)).collect(),
                )
            })
            .collect();
        for (a, (wa, pa)) in sampled.iter().enumerate() {
            for (b, (wb, pb)) in sampled.iter().enumerate().skip(a) {
                let v: f64 = (0..points.len())
                    .map(|k| weights[k] * (wa[k] * wb[k] + rotary * pa[k] * pb[k]))
                    .sum::<f64>()
                    / 0.05;
                let expected = if a == b { 1.0 } else { 0.0 };
                let (i, j) = (picked[a], picked[b]);
                assert!((v - expected).abs() < 1e-9, "{support}: <{i}, {j}> = {v}");
            }
        }
        // End conditions, relative to each quantity's scale (W ~ 1, Psi ~ beta, Psi' ~ beta^2).
        for m in modes.iter().filter(|m| m.omega > 0.0) {
            let s = &m.shape;
            let k = m.beta_l / 0.05;
            let quantities = |x: f64| {
                [
                    s.value(x),
                    s.rotation_at(x) / k,
                    s.curvature(x) / (k * k),
                    (s.slope(x) - s.rotation_at(x)) / k,
                ]
            };
            let (left, right) = (quantities(0.0), quantities(0.05));
            let zero: &[(usize, usize)] = match support {
                Support::ClampedFree => &[(0, 0), (0, 1), (1, 2), (1, 3)],
                Support::PinnedPinned => &[(0, 0), (0, 2), (1, 0), (1, 2)],
                Support::ClampedClamped => &[(0, 0), (0, 1), (1, 0), (1, 1)],
                Support::ClampedPinned => &[(0, 0), (0, 1), (1, 0), (1, 2)],
                Support::FreeFree => &[(0, 2), (0, 3), (1, 2), (1, 3)],
            };
            for &(end, q) in zero {
                let v = if end == 0 { left[q] } else { right[q] };
                assert!(
                    v.abs() < 1e-9,
                    "{support} omega {}: end {end} quantity {q} = {v}",
                    m.omega
                );
            }
        }
    }
}

#[test]
fn the_counts_and_the_list_agree() {
    for support in Support::ALL {
        let beam = steel(0.05, 0.01, support);
        let modes = beam.modes(200).unwrap();
        for (i, pair) in modes.windows(2).enumerate().filter(|(_, p)| p[0].omega > 0.0) {
            let between = 0.5 * (pair[0].omega + pair[1].omega);
            if pair[1].omega > pair[0].omega * (1.0 + 1e-9) {
                assert_eq!(
                    beam.count_below(between).unwrap(),
                    i + 1,
                    "{support} after mode {}",
                    i + 1
                );
            }
        }
    }
}

#[test]
fn static_flexibility_with_shear_is_the_modal_sum() {
    // sum g^2/omega^2 over the modes tends to the closed form with its shear term (the static
    // compliance identity); the shear part is 3 E I/(kGA c (L - c)) of the bending part at
    // pinned-pinned, 12 % here.
    for support in [
        Support::ClampedFree,
        Support::PinnedPinned,
        Support::ClampedClamped,
        Support::ClampedPinned,
    ] {
        let beam = steel(0.1, 0.01, support);
        let modes = beam.modes(1500).unwrap();
        for c in [0.03, 0.05, 0.1] {
            if c > 0.09 && support != Support::ClampedFree {
                continue;
            }
            let point = PointModes::new(&beam, &modes, c, 0.0).unwrap();
            let sum = point.static_flexibility();
            let exact = beam.static_flexibility(c).unwrap();
            let eb = beam.euler_bernoulli().static_flexibility(c).unwrap();
            // The shear term of the determinate supports: c g and c (L - c) g / L.
            let g = 1.0 / beam.shear().unwrap().rigidity;
            match support {
                Support::ClampedFree => assert!((exact - eb - c * g).abs() < 1e-12 * exact),
                Support::PinnedPinned => {
                    assert!((exact - eb - c * (0.1 - c) * g / 0.1).abs() < 1e-12 * exact)
                }
                _ => assert!(exact > eb, "{support} at {c}: shear adds compliance"),
            }
            assert!((sum - exact).abs() / exact < 2e-4, "{support} at {c}: {sum} vs {exact}");
        }
    }
}

#[test]
fn a_nanometre_beam_s_modes_do_not_panic() {
    // A review's degenerate input: the paper's 25 x 5 mm section over 1 nm. The Wittrick-Williams
    // count sized its segments from frequencies whose squares overflow, and indexed an empty
    // band (a panic). No beam theory holds there (the impact plan refuses a section larger than
    // its span); the modal crate answers or errs, but does not panic.
    for support in [Support::ClampedFree, Support::PinnedPinned, Support::FreeFree] {
        let beam = steel(1e-9, 0.005, support);
        if let Ok(modes) = beam.modes(3) {
            assert!(modes.iter().all(|m| m.omega.is_finite() && m.omega >= 0.0));
        }
    }
}

#[test]
fn the_roots_and_shapes_found_side_by_side_are_those_of_one_thread() {
    // The frequency range's halves and each root's shapes run under rayon::join and a parallel
    // iterator; each side computes what the serial search did, so the modes are the same to
    // the bit in a pool of one thread and of four (the paper's beam and a stocky free-free one,
    // whose two rigid-body modes come first).
    let pool =
        |threads: usize| rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    for beam in [steel(1.15, 0.005, Support::ClampedFree), steel(0.05, 0.01, Support::FreeFree)] {
        let one = pool(1).install(|| beam.modes(256).unwrap());
        let four = pool(4).install(|| beam.modes(256).unwrap());
        assert_eq!(one.len(), four.len());
        for (k, (a, b)) in one.iter().zip(&four).enumerate() {
            assert_eq!(a.omega.to_bits(), b.omega.to_bits(), "mode {}", k + 1);
            for x in [0.0, 0.3 * beam.length(), beam.length()] {
                let (va, vb) = (a.shape.value(x), b.shape.value(x));
                assert_eq!(va.to_bits(), vb.to_bits(), "mode {} at {x} m", k + 1);
            }
        }
    }
}
