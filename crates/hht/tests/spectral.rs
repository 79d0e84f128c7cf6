//! The scheme on a single undamped oscillator against validation/REFERENCES.md 4.2-4.4.
#![allow(clippy::unwrap_used, clippy::float_cmp)]

use faer::Col;
use hht::{HhtError, Integrator, Model, NewtonOptions, Oscillator, Scheme, State};

fn spectral_radius(scheme: Scheme, h: f64) -> f64 {
    hht::amplification(scheme, h)
        .unwrap()
        .complex_eigenvalues()
        .iter()
        .map(|z| z.norm())
        .fold(0.0, f64::max)
}

fn damping_and_period(scheme: Scheme, omega_h: f64) -> (f64, f64) {
    let s = hht::spectrum(scheme, omega_h).unwrap();
    (s.damping_ratio, s.period_error)
}

/// Spectral radius at Omega = 1e6 and the tolerance on its distance to rho_inf. HHT with
/// alpha > -1/3 has a simple limiting root, approached like Omega^-2: 1e-6. HHT at -1/3 and the
/// Chung-Hulbert optima have a double root there (that is their optimality), approached only
/// like Omega^(-1/2..-2/3) (measured: 3.6e-4 at 1e5, 8e-5 at 1e6), and a larger Omega would
/// trade that for sqrt(eps) round-off in the double root: 2e-4.
fn rho_infinity(scheme: Scheme) -> (f64, f64) {
    let double_root = scheme.alpha_m != 0.0 || (scheme.alpha_f - 1.0 / 3.0).abs() < 1e-12;
    (spectral_radius(scheme, 1e6), if double_root { 2e-4 } else { 1e-6 })
}

const ALPHAS: [f64; 6] = [0.0, -0.05, -0.1, -0.2, -0.3, -1.0 / 3.0];

#[test]
fn hht_spectral_radius_at_infinity() {
    // validation/REFERENCES.md 4.2: rho_inf = (1 + alpha)/(1 - alpha).
    for alpha in ALPHAS {
        let (rho, tolerance) = rho_infinity(Scheme::hht(alpha).unwrap());
        let expected = (1.0 + alpha) / (1.0 - alpha);
        assert!((rho - expected).abs() < tolerance, "alpha {alpha}: {rho} vs {expected}");
    }
}

#[test]
fn generalized_alpha_parameters_and_radius() {
    // validation/REFERENCES.md 4.4 table (6 printed digits) and rho(Omega = 1e7) = rho_inf.
    let table = [
        (1.0, 0.5, 0.5, 0.5, 0.25),
        (0.9, 0.421053, 0.473684, 0.552632, 0.277008),
        (0.8, 0.333333, 0.444444, 0.611111, 0.308642),
        (0.6, 0.125, 0.375, 0.75, 0.390625),
        (0.5, 0.0, 0.333333, 0.833333, 0.444444),
        (0.0, -1.0, 0.0, 1.5, 1.0),
    ];
    for (rho_inf, am, af, g, b) in table {
        let s = Scheme::generalized_alpha(rho_inf).unwrap();
        for (got, want) in [(s.alpha_m, am), (s.alpha_f, af), (s.gamma, g), (s.beta, b)] {
            assert!((got - want).abs() < 1e-6, "rho_inf {rho_inf}: {got} vs {want}");
        }
        let (rho, tolerance) = rho_infinity(s);
        assert!((rho - rho_inf).abs() < tolerance, "rho_inf {rho_inf}: measured {rho}");
    }
    // At rho_inf = 0.5 the optimum coincides with HHT alpha = -1/3 (validation/REFERENCES.md 4.4).
    let (hht, tolerance) = rho_infinity(Scheme::hht(-1.0 / 3.0).unwrap());
    assert!((hht - 0.5).abs() < tolerance);
}

#[test]
fn hht_damping_ratio_is_third_order() {
    // validation/REFERENCES.md 4.2: xi = -(alpha/8)(1 + alpha)^2 Omega^3 + O(Omega^5). At Omega = 0.02 the
    // O(Omega^2) relative correction is below 1e-3; 2e-3 allows for it.
    for alpha in ALPHAS[1..].iter().copied() {
        let coefficient = -(alpha / 8.0) * (1.0 + alpha).powi(2);
        for omega_h in [0.02, 0.04] {
            let (xi, _) = damping_and_period(Scheme::hht(alpha).unwrap(), omega_h);
            let measured = xi / omega_h.powi(3);
            assert!(
                (measured / coefficient - 1.0).abs() < 2e-3 * (omega_h / 0.02).powi(2),
                "alpha {alpha}, Omega {omega_h}: xi/Omega^3 = {measured}, series {coefficient}"
            );
        }
    }
    // The computed example values of validation/REFERENCES.md 4.2, printed to 5 digits.
    let (xi, period) = damping_and_period(Scheme::hht(-0.1).unwrap(), 0.1);
    assert!((xi / 1.0077e-5 - 1.0).abs() < 1e-4, "{xi}");
    assert!((period / 1.04458e-3 - 1.0).abs() < 1e-4, "{period}");
    let (xi, period) = damping_and_period(Scheme::hht(-0.3).unwrap(), 0.2);
    assert!((xi / 1.4389e-4 - 1.0).abs() < 1e-4, "{xi}");
    assert!((period / 4.9533e-3 - 1.0).abs() < 1e-4, "{period}");
}

#[test]
fn hht_period_error_is_second_order() {
    // validation/REFERENCES.md 4.2: (T' - T)/T = (1/12 - alpha/4 - 3 alpha^2/8) Omega^2 + O(Omega^4).
    for alpha in ALPHAS {
        let coefficient = 1.0 / 12.0 - alpha / 4.0 - 3.0 * alpha * alpha / 8.0;
        let (_, period) = damping_and_period(Scheme::hht(alpha).unwrap(), 0.02);
        let measured = period / 0.02f64.powi(2);
        assert!(
            (measured / coefficient - 1.0).abs() < 1e-3,
            "alpha {alpha}: {measured} vs {coefficient}"
        );
    }
}

#[test]
fn mixed_sign_convention_is_detected() {
    // validation/REFERENCES.md 4.3: HHT's beta and gamma with alpha > 0 are unstable (rho -> 1.2222 at
    // alpha = 0.1); the constructor refuses them.
    for alpha in [0.1, 1.0 / 3.0, -0.34, f64::NAN] {
        assert!(matches!(
            Scheme::hht(alpha),
            Err(HhtError::InvalidParameter { name: "alpha", .. })
        ));
    }
    // Mixing the weights the other way, (1 + alpha) with beta = (1 + alpha)^2 / 4 and
    // gamma = 1/2 + alpha, is stable but first order: its damping ratio tends to a constant
    // times Omega, which the third-order test above would catch. Build it by hand to show
    // that the measurement tells the two apart.
    let mixed = Scheme { alpha_m: 0.0, alpha_f: -0.1, beta: 0.3025, gamma: 0.6 };
    let (xi_mixed, _) = damping_and_period(mixed, 0.02);
    let (xi_right, _) = damping_and_period(Scheme::hht(-0.1).unwrap(), 0.02);
    assert!(xi_mixed / 0.02 > 0.04, "mixed convention: xi/Omega = {}", xi_mixed / 0.02);
    assert!(xi_right / 0.02 < 1e-4);
}

#[test]
fn no_growth_up_to_omega_h_1e4() {
    // Unconditional stability: spectral radius <= 1 over Omega in [1e-3, 1e4] for every alpha,
    // and a free vibration at Omega = 1e4 never exceeds its initial amplitude.
    for alpha in ALPHAS {
        let scheme = Scheme::hht(alpha).unwrap();
        let mut omega_h = 1e-3;
        while omega_h <= 1e4 {
            let rho = spectral_radius(scheme, omega_h);
            // alpha = 0 tends to a triple root at -1 (the principal pair and Newmark's spurious
            // root -(1 - gamma)/gamma), whose computed eigenvalues are only eps^(1/3) ~ 6e-6
            // accurate; alpha < 0 keeps the roots apart and the bound is round-off tight.
            let tolerance = if alpha == 0.0 { 5e-5 } else { 1e-12 };
            assert!(rho <= 1.0 + tolerance, "alpha {alpha}, Omega {omega_h}: rho = {rho}");
            omega_h *= 1.5;
        }
        let model = Oscillator::undamped(1.0).unwrap();
        let mut integrator = Integrator::new(scheme, NewtonOptions::default());
        let mut state = integrator.initial_state(&model, 0.0, 1.0, Col::zeros(1)).unwrap();
        for _ in 0..2000 {
            integrator.step(&model, &mut state, 1e4).unwrap();
            assert!(state.q.abs() <= 1.0 + 1e-9, "alpha {alpha}: d = {}", state.q);
        }
    }
}

/// Error at t = 0.3 of d'' + 4 pi^2 d = 0, d(0) = 1, for step h (not a whole period, where the
/// second-order phase error would cancel to first order).
fn oscillator_error(scheme: Scheme, h: f64) -> f64 {
    let omega = 2.0 * std::f64::consts::PI;
    let model = Oscillator::undamped(omega).unwrap();
    let mut integrator = Integrator::new(scheme, NewtonOptions::default());
    let mut state = integrator.initial_state(&model, 0.0, 1.0, Col::zeros(1)).unwrap();
    let steps = (0.3 / h).round() as usize;
    for _ in 0..steps {
        integrator.step(&model, &mut state, h).unwrap();
    }
    (state.q - (omega * state.t).cos()).abs()
}

#[test]
fn second_order_convergence() {
    for scheme in [
        Scheme::hht(-0.1).unwrap(),
        Scheme::hht(-0.3).unwrap(),
        Scheme::generalized_alpha(0.8).unwrap(),
    ] {
        let e: Vec<f64> =
            [0.02, 0.01, 0.005].iter().map(|&h| oscillator_error(scheme, h)).collect();
        for pair in e.windows(2) {
            let ratio = pair[0] / pair[1];
            assert!((ratio - 4.0).abs() < 0.3, "{scheme:?}: errors {e:?}");
        }
    }
}

/// Hardening spring m a + k d + k3 d^3 = 0, to exercise Newton.
struct Duffing;
impl Model for Duffing {
    type Config = f64;
    fn ndof(&self) -> usize {
        1
    }
    fn update(&self, q: &mut f64, dq: faer::ColRef<'_, f64>) {
        *q += dq[0];
    }
    fn inertial_force(
        &self,
        _: &f64,
        _: faer::ColRef<'_, f64>,
        a: faer::ColRef<'_, f64>,
        mut out: faer::ColMut<'_, f64>,
    ) {
        out[0] = a[0];
    }
    fn net_force(&self, _: f64, q: &f64, _: faer::ColRef<'_, f64>, mut out: faer::ColMut<'_, f64>) {
        out[0] = q + 100.0 * q.powi(3);
    }
    fn tangent(
        &self,
        _: f64,
        q: &f64,
        _: faer::ColRef<'_, f64>,
        _: faer::ColRef<'_, f64>,
        w: hht::NewtonWeights,
        out: &mut hht::Triplets,
    ) {
        out.push(0, 0, w.inertia * w.da + w.force * w.dq * (1.0 + 300.0 * q * q));
    }
}

#[test]
fn newton_on_a_hard_spring_keeps_energy_bounded() {
    // The trapezoidal rule conserves the energy of a nonlinear spring only approximately, but
    // with alpha < 0 the energy must not grow, and Newton converges in a few iterations.
    let energy = |s: &State<f64>| 0.5 * s.v[0] * s.v[0] + 0.5 * s.q * s.q + 25.0 * s.q.powi(4);
    let mut integrator = Integrator::new(Scheme::hht(-0.2).unwrap(), NewtonOptions::default());
    let mut state = integrator.initial_state(&Duffing, 0.0, 1.0, Col::zeros(1)).unwrap();
    let e0 = energy(&state);
    let mut largest: f64 = 0.0;
    for _ in 0..2000 {
        let report = integrator.step(&Duffing, &mut state, 2e-3).unwrap();
        assert!(report.iterations <= 6, "{report:?}");
        largest = largest.max(energy(&state));
    }
    // HHT is dissipative on linear problems; on a nonlinear spring the energy oscillates within
    // the period error (omega h ~ 0.035, so ~1e-4 here) and the high-frequency content decays.
    assert!(largest <= e0 * (1.0 + 1e-3), "energy rose to {largest} from {e0}");
    assert!(energy(&state) < e0 && energy(&state) > 0.99 * e0);
}

#[test]
fn newton_failure_is_reported_with_context() {
    // One iteration is never enough on a nonlinear spring, even after halving: the error says
    // when and with which residual, and the caller's state is unchanged.
    let options = NewtonOptions { max_iterations: 1, max_halvings: 3, ..NewtonOptions::default() };
    let mut integrator = Integrator::new(Scheme::hht(-0.1).unwrap(), options);
    let mut state = integrator.initial_state(&Duffing, 0.0, 1.0, Col::zeros(1)).unwrap();
    let err = integrator.step(&Duffing, &mut state, 0.1).unwrap_err();
    match err {
        HhtError::NewtonDiverged { t, iterations, residual_norm } => {
            assert!(t > 0.0 && t <= 0.1);
            assert_eq!(iterations, 1);
            assert!(residual_norm.is_finite() && residual_norm > 0.0);
        }
        other => panic!("unexpected {other:?}"),
    }
    assert_eq!(state.t, 0.0);
    assert_eq!(state.q, 1.0);
    assert!(integrator.step(&Duffing, &mut state, -1.0).is_err());
    assert!(integrator.step(&Duffing, &mut state, f64::NAN).is_err());
}

#[test]
fn step_halving_rescues_a_large_step() {
    // With a step of 0.5 s on the hard spring (period ~0.2 s) Newton from the predictor diverges
    // within 4 iterations; halving lets the step complete.
    let options = NewtonOptions { max_iterations: 4, ..NewtonOptions::default() };
    let mut integrator = Integrator::new(Scheme::hht(-0.1).unwrap(), options);
    let mut state = integrator.initial_state(&Duffing, 0.0, 1.0, Col::zeros(1)).unwrap();
    let report = integrator.step(&Duffing, &mut state, 0.5).unwrap();
    assert!(report.substeps > 1, "{report:?}");
    assert!((state.t - 0.5).abs() < 1e-15);
}

#[test]
fn error_estimate_is_third_order_and_symbolic_analysis_is_reused() {
    let model = Oscillator::undamped(1.0).unwrap();
    let estimate = |h: f64| {
        let mut integrator = Integrator::new(Scheme::hht(-0.1).unwrap(), NewtonOptions::default());
        // From d = 0 with v = 1 the acceleration changes by O(h) over a step, so the estimate
        // h^2 |beta - 1/6| |a_{n+1} - a_n| is O(h^3).
        let mut state =
            integrator.initial_state(&model, 0.0, 0.0, Col::from_fn(1, |_| 1.0)).unwrap();
        let r = integrator.step(&model, &mut state, h).unwrap();
        let r = integrator.step(&model, &mut state, h).map(|r2| (r, r2)).unwrap().1;
        assert_eq!(integrator.symbolic_factorisations(), 1);
        r.error_estimate
    };
    let ratio = estimate(0.02) / estimate(0.01);
    assert!((ratio - 8.0).abs() < 0.2, "ratio {ratio}");
}

#[test]
fn a_kept_matrix_serves_again_after_a_step_of_another_size() {
    // With reuse, a run of steps of one size, one of another (an event's re-step) and back
    // factorises twice, not three times: the first matrix is set aside, not dropped. The
    // states agree with full Newton's to the convergence tolerance.
    let options = NewtonOptions { reuse_factorisation: true, rtol: 1e-10, ..Default::default() };
    let mut kept = Integrator::new(Scheme::hht(-0.05).unwrap(), options);
    let mut full = Integrator::new(Scheme::hht(-0.05).unwrap(), NewtonOptions::default());
    let mut a = kept.initial_state(&Duffing, 0.0, 0.01, Col::zeros(1)).unwrap();
    let mut b = full.initial_state(&Duffing, 0.0, 0.01, Col::zeros(1)).unwrap();
    let start = kept.factorisations;
    for h in [1e-3, 1e-3, 3e-4, 1e-3, 1e-3, 3e-4, 1e-3] {
        kept.step(&Duffing, &mut a, h).unwrap();
        full.step(&Duffing, &mut b, h).unwrap();
    }
    assert_eq!(kept.factorisations - start, 2);
    assert!((a.q - b.q).abs() < 1e-12 && (a.v[0] - b.v[0]).abs() < 1e-10, "{a:?} {b:?}");
}

/// Two masses on springs, the second also on a contact-like spring `k_c` (the fast part), the
/// first's springs and both masses the slow part; it counts the stiffnesses it builds.
struct SplitChain {
    builds: std::cell::Cell<usize>,
    /// Whether `tangent_parts` splits; if not, it is the trait's default (everything in
    /// `fast`, every matrix built in full).
    split: bool,
}

impl SplitChain {
    const K: [f64; 2] = [400.0, 900.0];
    const K_C: f64 = 2500.0;
    const C: f64 = 0.3;

    fn slow(&self, w: hht::NewtonWeights, out: &mut hht::Triplets) {
        if w.dq != 0.0 {
            self.builds.set(self.builds.get() + 1);
        }
        let [k0, k1] = Self::K;
        let k = w.force * w.dq;
        out.push(0, 0, w.inertia * w.da + w.force * w.dv * Self::C + k * (k0 + k1));
        out.push(0, 1, -k * k1);
        out.push(1, 0, -k * k1);
        out.push(1, 1, w.inertia * w.da * 2.0 + k * k1);
    }

    fn fast(w: hht::NewtonWeights, out: &mut hht::Triplets) {
        out.push(1, 1, w.force * w.dq * Self::K_C);
    }
}

impl Model for SplitChain {
    type Config = [f64; 2];

    fn ndof(&self) -> usize {
        2
    }

    fn update(&self, q: &mut [f64; 2], dq: faer::ColRef<'_, f64>) {
        q[0] += dq[0];
        q[1] += dq[1];
    }

    fn inertial_force(
        &self,
        _: &[f64; 2],
        _: faer::ColRef<'_, f64>,
        a: faer::ColRef<'_, f64>,
        mut out: faer::ColMut<'_, f64>,
    ) {
        out[0] = a[0];
        out[1] = 2.0 * a[1];
    }

    fn net_force(
        &self,
        _: f64,
        q: &[f64; 2],
        v: faer::ColRef<'_, f64>,
        mut out: faer::ColMut<'_, f64>,
    ) {
        let [k0, k1] = Self::K;
        out[0] = Self::C * v[0] + k0 * q[0] - k1 * (q[1] - q[0]);
        out[1] = k1 * (q[1] - q[0]) + Self::K_C * q[1];
    }

    fn tangent(
        &self,
        _: f64,
        _: &[f64; 2],
        _: faer::ColRef<'_, f64>,
        _: faer::ColRef<'_, f64>,
        w: hht::NewtonWeights,
        out: &mut hht::Triplets,
    ) {
        self.slow(w, out);
        Self::fast(w, out);
    }

    fn tangent_parts(
        &self,
        _: f64,
        _: &[f64; 2],
        _: faer::ColRef<'_, f64>,
        _: faer::ColRef<'_, f64>,
        w: hht::NewtonWeights,
        slow: Option<&mut hht::Triplets>,
        fast: &mut hht::Triplets,
    ) {
        if !self.split {
            self.slow(w, fast);
        } else if let Some(slow) = slow {
            self.slow(w, slow);
        }
        Self::fast(w, fast);
    }
}

#[test]
fn a_new_step_size_re_weights_the_kept_stiffness() {
    // A linear model split into a slow part (its springs and masses, with damping) and a fast
    // one: with reuse, steps of three sizes build the slow stiffness once (each new size
    // re-weights the kept one by its mass and damping terms alone), and the states agree with
    // full Newton's on the unsplit tangent to the convergence tolerance: for a linear model the
    // re-weighted matrix is the exact one.
    let options = NewtonOptions { reuse_factorisation: true, rtol: 1e-12, ..Default::default() };
    let model = SplitChain { builds: std::cell::Cell::new(0), split: true };
    let mut kept = Integrator::new(Scheme::hht(-0.05).unwrap(), options);
    let mut full = Integrator::new(Scheme::hht(-0.05).unwrap(), NewtonOptions::default());
    let v0 = Col::from_fn(2, |i| [0.3, -0.2][i]);
    let mut a = kept.initial_state(&model, 0.0, [0.01, 0.0], v0.clone()).unwrap();
    let unsplit = SplitChain { builds: std::cell::Cell::new(0), split: false };
    let mut b = full.initial_state(&unsplit, 0.0, [0.01, 0.0], v0).unwrap();
    let (start, builds) = (kept.factorisations, model.builds.get());
    for h in [1e-3, 1e-3, 3e-4, 1e-3, 7e-4, 7e-4, 2e-4, 1e-3] {
        let r = kept.step(&model, &mut a, h).unwrap();
        assert_eq!(r.iterations, 1, "a linear model converges in one iteration");
        full.step(&unsplit, &mut b, h).unwrap();
    }
    assert_eq!(model.builds.get() - builds, 1, "the slow stiffness was built again");
    // Five sizes' matrices factorised (the first 1e-3 comes back from aside once, not after
    // 7e-4 and 2e-4 have taken its place), one stiffness built.
    assert_eq!(kept.factorisations - start, 5);
    for k in 0..2 {
        assert!((a.q[k] - b.q[k]).abs() < 1e-14, "{a:?} {b:?}");
        assert!((a.v[k] - b.v[k]).abs() < 1e-11, "{a:?} {b:?}");
    }
}

#[test]
fn a_scheme_written_by_hand_is_checked_before_a_step() {
    // The unstable convention of validation/REFERENCES.md 4.3 as a struct literal: the
    // constructors refuse it, and the integrator had run it to 1.2e18 in 200 steps without a
    // word (a review's). Now the first step refuses it by name; so is a tolerance that is not
    // a number.
    let unstable = Scheme { alpha_m: 0.0, alpha_f: -0.1, beta: 0.2025, gamma: 0.4 };
    let model = Oscillator::undamped(100.0).unwrap();
    let mut integrator = Integrator::new(unstable, NewtonOptions::default());
    let err = integrator.initial_state(&model, 0.0, 1.0, Col::zeros(1)).unwrap_err().to_string();
    assert!(err.contains("alpha_f"), "{err}");
    let nan = NewtonOptions { rtol: f64::NAN, ..NewtonOptions::default() };
    let mut integrator = Integrator::new(Scheme::trapezoidal(), nan);
    let err = integrator.initial_state(&model, 0.0, 1.0, Col::zeros(1)).unwrap_err().to_string();
    assert!(err.contains("rtol"), "{err}");
    // beta past the family's upper bound: the message says the bound.
    let err = Scheme::custom(0.0, 0.0, 100.0, 0.5).unwrap_err().to_string();
    assert!(err.contains("<= 10"), "{err}");
}
