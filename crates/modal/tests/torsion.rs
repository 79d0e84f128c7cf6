//! Saint-Venant torsion of a uniform beam (validation/REFERENCES.md 1.9): the modes' series
//! against the closed-form static twist, orthonormality, and the counts.
#![allow(clippy::unwrap_used)] // a test stops on a bad fixture

use modal::{rectangle_torsion, Support, Torsion};

/// The paper's strip: steel, 25 x 5 mm, L = 1.15 m.
fn strip(support: Support) -> Torsion {
    let (e, nu, rho, b, t) = (2.1e11, 0.3, 7850.0, 0.025, 0.005);
    let (j, _) = rectangle_torsion(b, t);
    let polar = (b * t * t * t + t * b * b * b) / 12.0;
    Torsion::new(e / (2.0 * (1.0 + nu)) * j, rho * polar, 1.15, support).unwrap()
}

/// sum over the elastic modes of Theta_n(c)^2 / (rho Ip L omega_n^2): the twist at c under a
/// unit torque there, by the modes.
fn modal_twist(t: &Torsion, c: f64, count: usize) -> f64 {
    t.modes(count)
        .iter()
        .filter(|m| m.omega > 0.0)
        .map(|m| m.value(c).powi(2) / (t.mass() * m.omega * m.omega))
        .sum()
}

#[test]
fn the_modes_sum_to_the_static_twist() {
    // Cantilever: theta(c) = T c / GJ (a torque T at c twists the part from the clamp to c
    // uniformly); held at both ends: T c (L - c) / (L GJ). The series' tail is
    // sum_{n > N} 2 sin^2 / (rho Ip L omega_n^2) <= 2 L / (pi^2 GJ N): it converges as 1/N,
    // so the error must fall about tenfold from N = 100 to 1000 and stay under that bound.
    for (support, c, at_free_end) in [
        (Support::ClampedFree, 1.15, true),
        (Support::ClampedFree, 0.4, false),
        (Support::PinnedPinned, 0.4, false),
    ] {
        let t = strip(support);
        let exact = match support {
            Support::ClampedFree => c / t.rigidity(),
            _ => c * (1.15 - c) / (1.15 * t.rigidity()),
        };
        assert_eq!(t.static_flexibility(c), Some(exact));
        let bound =
            |n: usize| 2.0 * 1.15 / (std::f64::consts::PI.powi(2) * t.rigidity() * n as f64);
        let (e100, e1000) = (exact - modal_twist(&t, c, 100), exact - modal_twist(&t, c, 1000));
        assert!(e100 >= 0.0 && e100 <= bound(100), "{support:?} {c}: {e100:e} vs {:e}", bound(100));
        assert!(e1000 >= 0.0 && e1000 <= bound(1000), "{support:?} {c}: {e1000:e}");
        if at_free_end {
            // At the free end every term is 2 / (rho Ip L omega_n^2): the tail is exactly
            // 8 L / (pi^2 GJ) sum_{n > N} 1/(2n - 1)^2 ~ 2 L / (pi^2 GJ N).
            assert!((e100 / e1000 - 10.0).abs() < 0.1, "{}", e100 / e1000);
        }
    }
    assert_eq!(strip(Support::FreeFree).static_flexibility(0.3), None);
}

#[test]
fn the_twist_rate_is_the_static_torque_over_gj() {
    // Held at both ends, a unit torque at c: the part before c carries (L - c)/L, the part
    // after -c/L; its integral from 0 is the static twist.
    let t = strip(Support::ClampedClamped);
    let c = 0.3;
    let twist = t.static_rate(c, 0.1).unwrap() * c;
    assert!((twist / t.static_flexibility(c).unwrap() - 1.0).abs() < 1e-12, "{twist}");
    assert!(t.static_rate(c, 0.9).unwrap() < 0.0);
}

#[test]
fn shapes_are_orthonormal_and_rates_are_their_slopes() {
    // integral Theta_m Theta_n dx = L delta_mn by the midpoint rule on 20000 intervals
    // (exact to 1e-8 for these smooth shapes), and Theta' by central differences.
    for support in Support::ALL {
        let t = strip(support);
        let modes = t.modes(6);
        let n = 20_000;
        let h = 1.15 / n as f64;
        for a in &modes {
            for b in &modes {
                let inner: f64 =
                    (0..n).map(|k| (k as f64 + 0.5) * h).map(|x| a.value(x) * b.value(x) * h).sum();
                let expected = if a == b { 1.15 } else { 0.0 };
                assert!((inner - expected).abs() < 1e-6, "{support:?}: {inner}");
            }
            for x in [0.1, 0.5, 1.0] {
                let d = 1e-6;
                let fd = (a.value(x + d) - a.value(x - d)) / (2.0 * d);
                assert!((fd - a.rate(x)).abs() < 1e-6 * a.rate_bound(0).max(1.0), "{support:?}");
            }
        }
        assert_eq!(t.rigid_modes(), usize::from(support == Support::FreeFree));
    }
}
