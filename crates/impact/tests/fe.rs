//! The finite-element impact: the contact's Newton matrix against finite differences, and the
//! paper's tip impact against the converged modal method.
#![allow(clippy::unwrap_used, clippy::float_cmp)] // helpers stop on bad fixtures; exact zeros are part of the contract

use faer::Col;
use hht::{Model, NewtonWeights, Triplets};
use impact::*;
use nalgebra::Vector2;

fn dense(n: usize, t: &Triplets) -> Vec<Vec<f64>> {
    let mut m = vec![vec![0.0; n]; n];
    for (r, c, v) in t.iter() {
        m[r][c] += v;
    }
    m
}

/// A bent 4-element strip with the ball pressed 20 um into its face over element 2, moving:
/// every term of the contact (sliding point, turning normal, damping) is active.
fn pressed<'a, L: hertz::ContactLaw>(
    law: &'a L,
) -> (BallOnBeam<'a, L>, BallOnBeamConfig, Col<f64>) {
    let steel = simo_beam::Material::new(2.1e11, 0.3, 7850.0).unwrap();
    let section = simo_beam::Section::rectangle(&steel, 0.025, 0.005).unwrap();
    let nodes: Vec<f64> = (0..=4).map(|i| 1.15 * i as f64 / 4.0).collect();
    let beam = simo_beam::PlanarBeam::new(&nodes, &section)
        .unwrap()
        .support(0, simo_beam::Support::Clamped)
        .unwrap();
    let radius = 0.005;
    let model = BallOnBeam::new(beam, 0.009, 9.81, radius, 0.0025, law);
    let nb = model.beam().ndof();
    let mut q = BallOnBeamConfig { beam: model.beam().reference_state(), ball: Vector2::zeros() };
    let mut dq = Col::<f64>::zeros(nb + 2);
    for i in 0..nb {
        // Displacements up to 2 cm and rotations up to 0.05 rad, varied along the beam.
        let k = i % 3;
        let node = (i / 3 + 1) as f64;
        dq[i] = if k < 2 { 0.004 * node * [0.3, 1.0][k] } else { 0.0125 * node };
    }
    model.update(&mut q, dq.as_ref());
    // The ball over 40 % of element 2, on the local face normal, 20 um into the face.
    let b = &q.beam;
    let (xa, xb) = (Vector2::new(b.x[1], b.z[1]), Vector2::new(b.x[2], b.z[2]));
    let x = xa + (xb - xa) * 0.4;
    let normal = |t: f64| Vector2::new(-t.sin(), t.cos());
    let n = (normal(b.theta[1]) * 0.6 + normal(b.theta[2]) * 0.4).normalize();
    q.ball = x + n * (0.0025 + radius - 20e-6);
    let v = Col::<f64>::from_fn(nb + 2, |i| 0.01 * ((i % 7) as f64 - 3.0));
    (model, q, v)
}

fn check_newton_matrix<L: hertz::ContactLaw>(law: &L, damped: bool) {
    let (model, q, v) = pressed(law);
    let n = model.ndof();
    let zero = Col::<f64>::zeros(n);
    let force = |q: &BallOnBeamConfig, v: &Col<f64>| {
        let mut f = Col::<f64>::zeros(n);
        model.net_force(0.0, q, v.as_ref(), f.as_mut());
        f
    };
    for (w, label) in [
        (NewtonWeights { inertia: 0.0, force: 1.0, da: 0.0, dv: 0.0, dq: 1.0 }, "dq"),
        (NewtonWeights { inertia: 0.0, force: 1.0, da: 0.0, dv: 1.0, dq: 0.0 }, "dv"),
    ] {
        let mut t = Triplets::new();
        model.tangent(0.0, &q, v.as_ref(), zero.as_ref(), w, &mut t);
        let k = dense(n, &t);
        let scale = k.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        // Central differences along the update (rotation increments for rotations). Truncation
        // is ~(eps / delta)^2 / 24 of the contact stiffness (delta = 20 um: 1e-8 at eps =
        // 1e-8 m; 1e-7 m gave 6e-7), round-off ~ eps_mach |f| / eps with |f| up to 1e5 N;
        // the approach is linear in the velocity, so dv is exact up to round-off.
        // (The 3D model's residual 1.4e-7 of the largest entry, in the ball's own x-z coupling,
        // came from composing rotation increments; the planar rotations add, and the Hessian
        // is exact.) Leaving out the Hessian term F Hess(delta) gave 2.7e-5 in 3D, so 1e-6 of
        // the largest entry still catches a missing geometric term.
        let mut worst: f64 = 0.0;
        for j in 0..n {
            let eps = if w.dq > 0.0 { 1e-8 } else { 1e-4 };
            let mut e = Col::<f64>::zeros(n);
            e[j] = eps;
            let (fp, fm) = if w.dq > 0.0 {
                let (mut qp, mut qm) = (q.clone(), q.clone());
                model.update(&mut qp, e.as_ref());
                model.update(&mut qm, (-&e).as_ref());
                (force(&qp, &v), force(&qm, &v))
            } else {
                (force(&q, &(&v + &e)), force(&q, &(&v - &e)))
            };
            for i in 0..n {
                let fd = (fp[i] - fm[i]) / (2.0 * eps);
                worst = worst.max((fd - k[i][j]).abs());
            }
        }
        assert!(worst <= 1e-6 * scale, "{label}: worst {worst:e} of scale {scale:e}");
        if label == "dv" && damped {
            assert!(scale > 0.0, "the damping term is missing");
        }
    }
}

#[test]
fn contact_newton_matrix_matches_finite_differences() {
    let steel = hertz::Material::new(2.1e11, 0.3).unwrap();
    let hertz = hertz::Hertz::between(&steel, &steel, 0.005).unwrap();
    check_newton_matrix(&hertz, false);
    // Hunt-Crossley adds the damping term through the approach rate.
    check_newton_matrix(&hertz::HuntCrossley::new(hertz, 0.5).unwrap(), true);
}

fn paper_tip(solver: &str) -> Outcome {
    // First contact only (it ends at 37 us).
    with_solver("paper-tip.toml", "method = \"modal\"\nmodes = 128\nend_time = 0.005", solver)
}

/// validation/scenes/`file` with its `[solver]` lines `own` replaced by `solver`.
fn scene_with_solver(file: &str, own: &str, solver: &str) -> Scene {
    let text = std::fs::read_to_string(format!(
        "{}/../../validation/scenes/{file}",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    assert!(text.contains(own), "{file} has no {own}");
    Scene::from_toml(&text.replace(own, solver)).unwrap()
}

/// [`scene_with_solver`], run.
fn with_solver(file: &str, own: &str, solver: &str) -> Outcome {
    simulate(&scene_with_solver(file, own, solver)).unwrap()
}

#[test]
fn struck_beside_its_clamp_the_clamp_s_stress_is_read_on_its_own_side() {
    // The paper's cantilever struck 1 mm from its clamp (0.2 ms, gravity off): the moment is
    // linear between the clamp and the ball, kinked under it. The default mesh had one element
    // there, so the clamp's stress was extrapolated across the kink: 9.89 MPa against the modal
    // method's 14.40 MPa (128 Timoshenko modes with the residual flexibility, which the plan
    // takes there: an independent model, analytic modes), 31 % low under a stated 3.3 %. With
    // two elements between the ball and the clamp the two agree within 0.07 % and the
    // displacements within 0.4 % (validation/REFERENCES.md 1.5); 1 % allows for the fe steps.
    let near = |method: &str| {
        let mut s = scene_with_solver(
            "paper-tip.toml",
            "method = \"modal\"\nmodes = 128\nend_time = 0.005",
            &format!("method = \"{method}\"\nend_time = 0.0002"),
        );
        s.impact.position = Some(0.001);
        s.impact.gravity = false;
        if method == "modal" {
            s.solver.modes = Some(128);
        }
        simulate(&s).unwrap().report
    };
    let (fe, modal) = (near("fe"), near("modal"));
    let clamp = |r: &Report| r.bending_stress.as_ref().unwrap().supports[0].max;
    let stress = clamp(&fe) / clamp(&modal) - 1.0;
    assert!(stress.abs() < 1e-2, "{stress}: {} against {}", clamp(&fe), clamp(&modal));
    let displacement = fe.max_displacement / modal.max_displacement - 1.0;
    assert!(displacement.abs() < 1e-2, "{displacement}");
    assert!(!fe.warnings.iter().any(|w| w.contains("kink")), "{:?}", fe.warnings);
    // Both say that 1 mm from the clamp, within the strip's 5 mm depth, is past beam theory.
    for r in [&fe, &modal] {
        assert!(r.warnings.iter().any(|w| w.contains("closer than the beam's thickness")));
    }
    // A tolerance's ladder: its uniform meshes had no node at the ball, which lay somewhere in
    // an element of each, and the ladder ran to 8192 elements without meeting 1e-2 (the last
    // two 5.3e-2 apart, 1.85 s); with a node there and two elements to the clamp it stops at
    // 128 and agrees with the modal method as the default mesh does.
    let mut tolerant = scene_with_solver(
        "paper-tip.toml",
        "method = \"modal\"\nmodes = 128\nend_time = 0.005",
        "method = \"fe\"\nend_time = 0.0002\ntolerance = 1e-2",
    );
    tolerant.impact.position = Some(0.001);
    tolerant.impact.gravity = false;
    let ladder = simulate(&tolerant).unwrap().report;
    assert!(ladder.estimated_error.is_some_and(|e| e <= 1e-2), "{:?}", ladder.warnings);
    let stress = clamp(&ladder) / clamp(&modal) - 1.0;
    let displacement = ladder.max_displacement / modal.max_displacement - 1.0;
    assert!(stress.abs() < 1e-2 && displacement.abs() < 1e-2, "{stress} {displacement}");
    // 4 mm out, the local elements between the clamp and the ball refined with the ladder
    // (with two on every rung it stopped 3.0 % low under an estimate of 4.6e-3): the estimate
    // holds against the review's reference 1.1693e-6 m (validation/REFERENCES.md 1.5).
    tolerant.impact.position = Some(0.004);
    let four = simulate(&tolerant).unwrap().report;
    let (error, estimate) =
        (four.max_displacement / 1.1693e-6 - 1.0, four.estimated_error.unwrap());
    assert!(error.abs() <= estimate && estimate <= 1e-2, "{error} against {estimate}");
    // 1 um out (past beam theory, warned) the ladder's elements there stop at 1e-7 of the
    // beam: split into 4 nm elements beside 140 um ones, Newton's iteration had diverged.
    tolerant.impact.position = Some(1e-6);
    assert!(simulate(&tolerant).is_ok());
    // A uniform mesh with the ball inside the clamp's first element is warned of.
    let mut coarse = scene_with_solver(
        "paper-tip.toml",
        "method = \"modal\"\nmodes = 128\nend_time = 0.005",
        "method = \"fe\"\nelements = 747\nend_time = 0.0002",
    );
    coarse.impact.position = Some(0.001);
    let plan = Plan::new(&coarse).unwrap();
    assert!(
        plan.warnings().iter().any(|w| w.contains("kink") && w.contains("solver.elements = 2300")),
        "{:?}",
        plan.warnings()
    );
    // Inside the second element (3 mm on 719 elements of 1.6 mm) the ball's load reaches the
    // mesh at the node between the clamp's two midpoints: the clamp 2.3 % low and the
    // displacement 6.4 % (a review's reference, validation/REFERENCES.md 1.5), warned; on a node
    // two elements out (767) right, and not warned.
    let kinked = |elements: usize| {
        let mut s = coarse.clone();
        s.impact.position = Some(0.003);
        s.solver.elements = Some(elements);
        Plan::new(&s).unwrap().warnings().iter().any(|w| w.contains("kink"))
    };
    assert!(kinked(719) && !kinked(767));
}

#[test]
fn paper_tip_first_contact_fe_matches_converged_modal() {
    // The FE beam (Simo: shear and rotary inertia, default mesh, 200 steps per pulse)
    // and Goldsmith's series of Timoshenko modes with residual flexibility (converged: the
    // duration moves 6e-9 of itself from 512 to 8192 modes, validation/REFERENCES.md 1.6)
    // agree on the first contact's duration and peak force within 1 %. Measured: 0.06 % and
    // 0.2 %; with 0.375 mm elements at the tip 0.06 % and 0.13 %, the two models' remaining
    // difference (the fe duration converges to 3.7235e-5 s, the modal one is 3.7253e-5 s).
    let modal =
        paper_tip("method = \"modal\"\nmodes = 512\nresidual_flexibility = true\nend_time = 6e-5");
    let fe = paper_tip("method = \"fe\"\nend_time = 6e-5");
    let (m, f) = (&modal.report.contacts[0], &fe.report.contacts[0]);
    assert!(m.complete && f.complete);
    assert_eq!(fe.report.plan.method, MethodKind::Fe);
    assert!(modal.report.plan.reasons.iter().any(|r| r.contains("Timoshenko modes (default)")));
    let rel = |a: f64, b: f64| (a - b).abs() / b;
    assert!(rel(f.duration, m.duration) < 0.01, "{} vs {}", f.duration, m.duration);
    assert!(rel(f.peak_force, m.peak_force) < 0.01, "{} vs {}", f.peak_force, m.peak_force);
    // Mesh convergence toward the modal value: the duration error falls 6.4x from 3 mm to
    // 0.75 mm elements at the tip (5.5e-3 to 8.6e-4), down to the models' difference.
    let coarse = paper_tip("method = \"fe\"\nelement_size = 3e-3\nend_time = 6e-5");
    let fine = paper_tip("method = \"fe\"\nelement_size = 0.75e-3\nend_time = 6e-5");
    let e_coarse = rel(coarse.report.contacts[0].duration, m.duration);
    let e_fine = rel(fine.report.contacts[0].duration, m.duration);
    assert!(e_fine < e_coarse / 5.0, "{e_coarse} -> {e_fine}");
    // The history is finite and the energy ledger closes: HHT (alpha = -0.05) removes 9.4e-6
    // of the initial energy over the pulse and the free flight after it (3.7e-4 when the
    // flights took up to 8 contact steps, 1.2e-3 with 32: its damping grows with omega h),
    // reported as numerical_dissipation from the Newmark energy identity step by step; what
    // is left is the trapezoidal rule's error on the nonlinear contact and beam forces,
    // measured 3.2e-5 of the initial energy.
    assert!(fe.history.force.iter().all(|x| x.is_finite()));
    let e = &fe.report.energy;
    assert!(e.numerical_dissipation > 1e-6 * e.initial, "{e:?}");
    assert!(e.balance_error.abs() < 1e-4 * e.initial, "{e:?}");
    // The trapezoidal rule (alpha = 0) removes nothing: the term is zero to the Newton
    // tolerance (measured 1e-8 of the energy over 1 ms), and what is left stays as small.
    let undamped = paper_tip("method = \"fe\"\nalpha = 0.0\nend_time = 6e-5");
    let e0 = &undamped.report.energy;
    assert!(e0.numerical_dissipation.abs() < 1e-6 * e0.initial, "{e0:?}");
    assert!(e0.balance_error.abs() < 1e-4 * e0.initial, "{e0:?}");
}

#[test]
fn paper_tip_thornton_fe_matches_converged_modal() {
    // Thornton's elastic-plastic law end to end in both methods, first 100 us (the print is
    // made within the first 20 us; the ball then rides the tip). Measured FE vs 512 modes:
    // peak force +0.12 %, print radius +0.06 %, plastic work +0.24 % (512 -> 2048 modes moves
    // them by < 2e-5). Allowed: the 1 % of the elastic check.
    let scene = |solver: &str| {
        let text = std::fs::read_to_string(format!(
            "{}/../../validation/scenes/paper-tip.toml",
            env!("CARGO_MANIFEST_DIR")
        ))
        .unwrap()
        .replace("law = \"hertz\"", "law = \"thornton\"")
        .replace("method = \"modal\"\nmodes = 128\nend_time = 0.005", solver);
        simulate(&Scene::from_toml(&text).unwrap()).unwrap()
    };
    let modal = scene("method = \"modal\"\nmodes = 512\nend_time = 1e-4");
    let fe = scene("method = \"fe\"\nend_time = 1e-4");
    let (m, f) = (&modal.report.contacts[0], &fe.report.contacts[0]);
    let rel = |a: f64, b: f64| (a - b).abs() / b;
    assert!(rel(f.peak_force, m.peak_force) < 0.01, "{} vs {}", f.peak_force, m.peak_force);
    assert!(rel(f.print_radius, m.print_radius) < 0.01, "{} vs {}", f.print_radius, m.print_radius);
    assert!(f.print_radius > 0.0 && f.print_radius < 0.005);
    let (em, ef) = (&modal.report.energy, &fe.report.energy);
    assert!(rel(ef.dissipated, em.dissipated) < 0.01, "{} vs {}", ef.dissipated, em.dissipated);
    // Plastic work is in the FE ledger: it closes to HHT's numerical damping (measured 1.2e-5).
    assert!(ef.dissipated > 0.3 * ef.initial);
    assert!(ef.balance_error.abs() < 1e-3 * ef.initial, "{ef:?}");
    let last = fe.history.dissipated_energy.last().unwrap();
    assert!((last - ef.dissipated).abs() <= 1e-12 * ef.initial);
}

fn heavy_ball(solver: &str) -> Outcome {
    let text = std::fs::read_to_string(format!(
        "{}/../../validation/scenes/heavy-ball.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
    .replace("method = \"auto\"\nend_time = 0.2", solver);
    simulate(&Scene::from_toml(&text).unwrap()).unwrap()
}

#[test]
fn heavy_ball_is_planned_fe_and_the_modal_report_warns() {
    // 1 kg at 5 m/s at 0.8 L: sqrt(m V^2 / k) = 0.34 m, 30 % of L (k = 3 EI / a^3 = 210.7 N/m).
    let text = std::fs::read_to_string(format!(
        "{}/../../validation/scenes/heavy-ball.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let plan = Plan::new(&Scene::from_toml(&text).unwrap()).unwrap();
    assert_eq!(plan.summary().method, MethodKind::Fe);
    assert!(plan
        .summary()
        .reasons
        .iter()
        .any(|r| r.contains("small-deflection theory does not hold")));
    // Forced modal over the first swing: the beam bends by a third of its length (measured
    // 0.334 m with 40 modes) and the report says small-deflection theory is exceeded.
    let modal = heavy_ball("method = \"modal\"\nend_time = 0.2");
    assert!(modal.report.max_displacement > 0.2 * 1.15);
    assert!(
        modal
            .report
            .warnings
            .iter()
            .any(|w| w.contains("small-deflection (modal) theory is exceeded")),
        "{:?}",
        modal.report.warnings
    );
}

#[test]
fn heavy_ball_first_contact_converges_in_the_step() {
    // The first contact of the heavy ball (8 kN, 427 us) with the adaptive contact step from
    // 100 and 400 steps per estimated pulse: measured 427.29 / 426.71 us and 8022.3 / 8019.6 N
    // on the default mesh (301 elements of 3.6 mm where the waves reach in the window). The
    // contact is 430.9 us on 1024 equal elements and by the modal method refined to 1e-3; the
    // mesh graded to L/16 that the default was before left the waves unresolved 10 cm from the
    // ball and ended it at 358 us. The contact element must not flip over the node under the
    // ball: that cost 523 step halvings in 2 ms before the element was kept; now none at 400.
    let coarse = heavy_ball("method = \"fe\"\nsamples_per_pulse = 100\nend_time = 5e-4");
    let fine = heavy_ball("method = \"fe\"\nsamples_per_pulse = 400\nend_time = 5e-4");
    let (c, f) = (&coarse.report.contacts[0], &fine.report.contacts[0]);
    assert!(c.complete && f.complete);
    let rel = |a: f64, b: f64| (a - b).abs() / b;
    assert!(rel(c.duration, f.duration) < 3e-3, "{} vs {}", c.duration, f.duration);
    assert!(rel(c.peak_force, f.peak_force) < 3e-3, "{} vs {}", c.peak_force, f.peak_force);
    assert!(
        fine.report.plan.reasons.iter().any(|r| r.contains(" 0 step halvings")),
        "{:?}",
        fine.report.plan.reasons
    );
    // By default every step is the contact step (plan::FE_FREE_STEP_RATIO); with a longer
    // `solver.time_step` the contact step grows above it over part of the contact, where the
    // ball's local error allows, and the contact stays within 3e-3 of the fine run.
    let fixed = f.duration / fine.report.plan.time_step;
    assert!((f.steps as f64 - fixed).abs() < 2.0, "{} steps, {fixed} at the fixed step", f.steps);
    let free =
        heavy_ball("method = \"fe\"\nsamples_per_pulse = 400\ntime_step = 1e-5\nend_time = 5e-4");
    let g = &free.report.contacts[0];
    assert!((g.steps as f64) < 0.8 * fixed, "{} steps, {fixed} at the fixed step", g.steps);
    assert!(rel(g.duration, f.duration) < 3e-3, "{} vs {}", g.duration, f.duration);
}

/// The paper's tip scene by the fe method, gravity off, over `end_time` (s).
fn paper_tip_fe_without_gravity(end_time: f64) -> Scene {
    let text = std::fs::read_to_string(format!(
        "{}/../../validation/scenes/paper-tip.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let mut scene = Scene::from_toml(&text).unwrap();
    scene.solver.method = MethodName::Fe;
    scene.solver.modes = None;
    scene.solver.end_time = Some(end_time);
    scene.impact.gravity = false;
    scene
}

#[test]
fn paper_tip_256_elements_matches_the_peer_contact_for_contact() {
    // validation/reference/exudyn_tip_256.csv: Exudyn's planar geometrically exact beam at the
    // same mesh (256 equal elements, 1 ms, gravity off). Both discretise the same rod; they
    // differ in the time integrator (generalized-alpha at 1 us against HHT with located events
    // and adaptive contact steps) and in the contact (a sphere on the tip node against the
    // face). Measured: first contact 36.875 us / 790.09 N (0.01 % / 0.09 % from Exudyn's
    // 36.88 us / 789.4 N), second start 382.78 us (0.07 % from 383.04 us). The first contact
    // is also within 1.5 % of the converged modal value 37.214 us / 782.14 N.
    let mut scene = paper_tip_fe_without_gravity(1e-3);
    scene.solver.elements = Some(256);
    let out = simulate(&scene).unwrap();
    let c = &out.report.contacts;
    assert!(c.len() >= 3, "{} contacts", c.len());
    let rel = |a: f64, b: f64| (a - b).abs() / b;
    assert!(rel(c[0].duration, 36.88e-6) < 2e-3, "{}", c[0].duration);
    assert!(rel(c[0].peak_force, 789.4) < 5e-3, "{}", c[0].peak_force);
    assert!(rel(c[0].duration, 37.214e-6) < 0.015 && rel(c[0].peak_force, 782.14) < 0.015);
    assert!(rel(c[1].start, 383.04e-6) < 0.01, "{}", c[1].start);
    assert!(rel(c[2].start, 651.37e-6) < 0.01, "{}", c[2].start);
}

#[test]
fn a_tolerance_chooses_the_mesh_for_every_contact() {
    // validation/reference/fe_tip_converged.csv: the FE method's own converged contacts 2 and
    // 3 (Richardson from 1024 and 2048 elements). With tolerance = 0.01 the mesh refinement
    // stops at 512 elements (estimated 8.2e-3), and the steps' at a quarter of the contact
    // step (uniform; the plan's adaptive steps and half the contact step differ by 5.1e-3 on
    // the third contact's duration, half and a quarter by 8.7e-4: the steps get the 1.8e-3
    // the mesh leaves). Measured: estimated 9.05e-3; contacts 2 and 3 start 0.68 % and 0.70 %
    // late, durations within 0.15 %; the estimate is not optimistic.
    let mut scene = paper_tip_fe_without_gravity(8e-4);
    scene.solver.tolerance = Some(0.01);
    let out = simulate(&scene).unwrap();
    let r = &out.report;
    let estimated = r.estimated_error.unwrap();
    assert!(estimated <= 0.01, "{estimated}");
    let rel = |a: f64, b: f64| (a - b).abs() / b;
    let converged = [(371.24e-6, 66.35e-6), (631.12e-6, 106.03e-6)];
    let mut actual: f64 = 0.0;
    for (c, (start, duration)) in r.contacts[1..3].iter().zip(converged) {
        assert!(rel(c.start, start) < 0.01, "start {} vs {start}", c.start);
        assert!(rel(c.duration, duration) < 0.02, "duration {} vs {duration}", c.duration);
        actual = actual.max(rel(c.start, start)).max(rel(c.duration, duration));
    }
    assert!(estimated >= 0.5 * actual, "estimate {estimated} against {actual}");
    assert!(
        r.plan.reasons.iter().any(|x| x.contains("elements tried: 64")),
        "{:?}",
        r.plan.reasons
    );
    let steps = r.plan.reasons.iter().find(|x| x.contains("step divisions tried: 1")).unwrap();
    assert!(steps.contains(", 4 ("), "{steps}");
    let planned = Plan::new(&scene).unwrap().summary().time_step;
    assert!((r.plan.time_step - planned / 4.0).abs() < 1e-9 * planned, "{}", r.plan.time_step);
    assert!(r.plan.reasons.iter().any(|x| x.contains("(the mesh limiting)")));
    // The tolerance chooses the mesh itself; with the modal method it chooses the modes.
    let mut both = scene.clone();
    both.solver.elements = Some(100);
    assert!(matches!(Plan::new(&both), Err(ImpactError::Inconsistent(_))));
    let mut modal = scene.clone();
    modal.solver.method = MethodName::Modal;
    assert!(matches!(Plan::new(&modal).unwrap().method(), Method::Modal(_)));
    let mut zero = scene;
    zero.solver.tolerance = Some(0.0);
    let message = Plan::new(&zero).unwrap_err().to_string();
    assert!(message.contains("solver.tolerance = 0"), "{message}");
}

#[test]
fn heavy_ball_slides_off_the_end_and_the_ledger_closes() {
    // validation/scenes/heavy-ball.toml over 0.4 s: the ball bounces along the turning
    // cantilever, slides off its free end near 0.19 s and falls away. The largest displacement
    // stays in the converged band 0.29-0.31 m (measured 0.3029 m at the default steps, 0.3021
    // with flights of up to 8 contact steps); HHT's numerical dissipation is reported
    // (measured 1.5-2 % of the ball's energy, moving with rounding in this chatter; 12 % with
    // those longer flights) and what is left of the ledger is below 1e-3 (measured 1.6e-4). Before the corner contact past the end, the face was extrapolated
    // beyond the tip: the run chattered on a beam that was not there (over 1000 "contacts") and,
    // with the ball below it, diverged.
    let text = std::fs::read_to_string(format!(
        "{}/../../validation/scenes/heavy-ball.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let mut scene = Scene::from_toml(&text).unwrap();
    scene.solver.end_time = Some(0.4);
    let out = simulate(&scene).unwrap();
    let r = &out.report;
    assert!((0.29..=0.31).contains(&r.max_displacement), "{}", r.max_displacement);
    let e = &r.energy;
    assert!(e.numerical_dissipation > 0.005 * e.initial, "{e:?}");
    assert!(e.balance_error.abs() < 1e-3 * e.initial, "{e:?}");
    let last = r.contacts.last().unwrap();
    assert!(last.start < 0.25, "a contact at {} s, after the ball left", last.start);
    assert!(*out.history.approach.last().unwrap() < -0.1);
}

/// The largest bending stress and the clamp's over the paper's tip over 1 ms.
fn tip_stress(solver: &str) -> (f64, f64) {
    let o = paper_tip(&format!("{solver}\nend_time = 0.001"));
    let b = o.report.bending_stress.unwrap();
    assert!(!b.at_window_end);
    (b.max, b.supports[0].max)
}

#[test]
fn paper_tip_stress_converges_with_elements_and_meets_the_modal_method() {
    // validation/REFERENCES.md 1.5: on the paper's tip over 1 ms the Euler-Bernoulli modes
    // converge to 54.3619 MPa beam-wide (54.3628 at 512 modes; at x = 1.1263 m, t = 32.6 us,
    // 2.4 cm from the struck tip, under the first contact) and 27.4404 MPa at the clamp. The
    // fe stress, from the elements' midpoint curvatures, converges at second order in the
    // mesh (measured 50.92, 53.75, 54.60, 54.82 MPa at 128 to 1024 elements: differences
    // 2.82, 0.85, 0.22, ratios 3.3 and 3.8) to about 54.89 MPa (Richardson), at the same
    // place and time: 1.0 % above the Euler-Bernoulli modes, within 0.1 % of the Timoshenko
    // modes (54.93 MPa at 512): the Simo beam's shear slows the short bending waves that
    // Euler-Bernoulli lets run without limit. The clamp's, carried by the long waves, agree
    // within 1 %.
    let [(s128, _), (s256, _), (s512, c512)] =
        [128, 256, 512].map(|n| tip_stress(&format!("method = \"fe\"\nelements = {n}")));
    let ratio = (s256 - s128) / (s512 - s256);
    assert!(ratio > 2.5, "convergence ratio {ratio} ({s128}, {s256}, {s512})");
    let extrapolated = s512 + (s512 - s256) / (ratio - 1.0);
    let (modal, modal_clamp) =
        tip_stress("method = \"modal\"\nmodes = 512\nbeam_theory = \"euler-bernoulli\"");
    assert!((modal - 54.3628e6).abs() < 1e-5 * modal, "{modal}");
    assert!(((s512 - modal) / modal).abs() < 0.01, "fe {s512} against modal {modal}");
    assert!(((c512 - modal_clamp) / modal_clamp).abs() < 0.01, "{c512} against {modal_clamp}");
    // Timoshenko modes (the default) sit on the fe beam's limit; Euler-Bernoulli 1 % below.
    let (timoshenko, _) = tip_stress("method = \"modal\"\nmodes = 512");
    assert!(
        (extrapolated - timoshenko).abs() < 0.3 * (extrapolated - modal).abs(),
        "fe {extrapolated} (extrapolated), Timoshenko {timoshenko}, Euler-Bernoulli {modal}"
    );
}

#[test]
fn the_default_steps_are_converged_in_time_through_a_chatter() {
    // validation/REFERENCES.md 1.7: the paper's tip, 512 equal elements, gravity off, its first
    // 8 contacts (to 1.05 ms; the fourth is the ball riding the tip for 142 us, then four short
    // ones). The reference is the run with every step at most 0.25 us
    // (`time_step = 2.5e-7`): the default must match it within 1e-3 in start and 2e-3 in
    // duration. Flights of up to 8 contact steps (the default until then) missed it by 1.5e-2
    // and 1.7e-1 (the fourth contact 159.6 us long against 141.7 us). And the default is
    // converged in time: against half its steps the contacts move by at most 6e-4 (start) and
    // 3.8e-3 (duration, the third contact, 106.4 against 106.0 us) over 5 ms; allowed 1e-3 and
    // 5e-3.
    let run = |time_step: Option<f64>, samples: Option<usize>| {
        let mut scene = paper_tip_fe_without_gravity(1.05e-3);
        scene.solver.elements = Some(512);
        scene.solver.time_step = time_step;
        scene.solver.samples_per_pulse = samples;
        simulate(&scene).unwrap().report
    };
    let default = run(None, None);
    let capped = run(Some(2.5e-7), None);
    let half = run(Some(1e-7), Some(400));
    let worst = |a: &impact::Report, b: &impact::Report| {
        assert!(
            a.contacts.len() >= 8 && b.contacts.len() >= 8,
            "{} and {} contacts",
            a.contacts.len(),
            b.contacts.len()
        );
        let rel = |x: f64, y: f64| (x - y).abs() / y.abs().max(1e-12);
        let pairs = || a.contacts.iter().zip(&b.contacts).take(8);
        let start = pairs().skip(1).map(|(x, y)| rel(x.start, y.start)).fold(0.0, f64::max);
        let duration = pairs().map(|(x, y)| rel(x.duration, y.duration)).fold(0.0, f64::max);
        (start, duration)
    };
    let (start, duration) = worst(&default, &capped);
    assert!(start < 1e-3 && duration < 2e-3, "against the 0.25 us cap: {start:e}, {duration:e}");
    let (start, duration) = worst(&default, &half);
    assert!(start < 1e-3 && duration < 5e-3, "against half the steps: {start:e}, {duration:e}");
}

/// The largest bending stress of validation/scenes/paper-midspan.toml (the paper's cantilever
/// struck at mid-span) over its first contact by `solver`.
fn midspan_stress(solver: &str) -> f64 {
    let own = "method = \"modal\"\nmodes = 128\nend_time = 0.002";
    let report = with_solver("paper-midspan.toml", own, solver).report;
    report.bending_stress.unwrap().max
}

#[test]
fn the_stress_under_the_ball_is_extrapolated_to_the_impact_point() {
    // Struck at mid-span the largest stress is under the ball (at 26 us), where the moment
    // has a kink: the elements' midpoints on either side sit h/2 of the shear below its peak,
    // a first-order error (uniform meshes of 64 to 512 elements read 31.3, 33.1, 40.2,
    // 44.3 MPa), which the impact point's value, extrapolated from the two midpoints on each
    // side, does not have (40.9, 47.7, 48.87, 48.86 MPa). The reference is the modal method's
    // certified maximum on 256 Timoshenko modes with the residual flexibility (validation/
    // REFERENCES.md 1.8; 48.8178 MPa, 4096 modes 48.8182: converged to 1e-5; the plain series
    // had 48.858 at 256 modes and 48.822 at 4096, and this test had taken 48.858 for the
    // truth): measured 1.1e-3 above it at 256 elements and 7.4e-4 on the default graded mesh;
    // bounds 1.5e-3 and 1e-3 (the midpoints alone: 1.8e-1 and 6.5e-2).
    let modal = midspan_stress(
        "method = \"modal\"\nmodes = 256\nresidual_flexibility = true\nend_time = 0.0001",
    );
    assert!((modal / 48.8182e6 - 1.0).abs() < 2e-5, "{modal}");
    let off = |a: f64| (a / modal - 1.0).abs();
    let fe256 = midspan_stress("method = \"fe\"\nelements = 256\nend_time = 0.0001");
    assert!(off(fe256) < 1.5e-3, "{fe256} against {modal}");
    let default = midspan_stress("method = \"fe\"\nend_time = 0.0001");
    assert!(off(default) < 1e-3, "{default} against {modal}");
}

#[test]
fn a_clamped_end_read_on_long_elements_warns_and_the_default_mesh_states_its_size() {
    // The paper's tip over 1 ms (its waves reach the clamp: the default mesh is uniform, 747
    // elements of at most 1.54 mm, a sixteenth of the 24.65 mm wave the pulse excites): it states
    // the clamp's extrapolation error, 20 (h/lambda)^2 = 7.8 %, without a warning; on 64
    // elements (18 mm, 0.73 of the wave) it warns and names 747 elements.
    let own = "method = \"modal\"\nmodes = 128\nend_time = 0.005";
    let plan = |solver: &str| Plan::new(&scene_with_solver("paper-tip.toml", own, solver)).unwrap();
    let default = plan("method = \"fe\"\nend_time = 0.001");
    assert_eq!(default.summary().elements, 747);
    let reasons = default.summary().reasons.join("\n");
    assert!(
        reasons.contains("the clamped end at x = 0 m") && reasons.contains("= 7.8 %"),
        "{reasons}"
    );
    assert!(!default.warnings().iter().any(|w| w.contains("clamped end")));
    let coarse = plan("method = \"fe\"\nelements = 64\nend_time = 0.001");
    let w = coarse.warnings().join("\n");
    assert!(
        w.contains("the clamped end at x = 0 m: its stress is not resolved")
            && w.contains("solver.elements = 747 or more"),
        "{w}"
    );
}

#[test]
fn a_heavy_balls_default_mesh_is_sized_for_the_beams_local_response() {
    // A 0.2 kg ball (R 10 mm) at 1 m/s on a 1 m cantilever of the paper's strip, struck at
    // 0.8 m, 5 ms: the ball is heavy against the beam, whose local response (12 times the
    // contact's local frequency, 5.78e5 rad/s) is 4.1 times omega t_c = 20: the modal plan
    // keeps its modes to it, and the fe mesh now takes elements a sixteenth of its wave too
    // (709 of 1.41 mm; 350 of 2.86 mm before). A review measured the clamp's largest stress
    // on 350 elements 105.35 MPa against 95.43 (modal, refined to 1e-3) and 96.34 (2000
    // elements), with its statement "up to 7.8 %"; on the mesh now 96.41 MPa; the modal
    // default 95.25 MPa. Within 2 % of it.
    let text = "name = \"heavy\"\n[beam]\nlength = 1.0\nwidth = 0.025\nthickness = 0.005\nsupport = \"clamped-free\"\n\
                youngs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
                [ball]\nradius = 0.01\nmass = 0.2\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
                [impact]\nposition = 0.8\nspeed = 1.0\ngravity = false\n[solver]\nmethod = \"fe\"\nend_time = 0.005\n";
    let fe = simulate(&Scene::from_toml(text).unwrap()).unwrap().report;
    assert_eq!(fe.plan.elements, 709);
    assert!(
        fe.plan.reasons.iter().any(|r| r.contains("at 5.7831e5 rad/s")),
        "{:?}",
        fe.plan.reasons
    );
    let modal = text.replace("method = \"fe\"", "method = \"modal\"");
    let modal = simulate(&Scene::from_toml(&modal).unwrap()).unwrap().report;
    let clamp = |r: &impact::Report| r.bending_stress.as_ref().unwrap().supports[0].max;
    let (f, m) = (clamp(&fe), clamp(&modal));
    assert!((f / m - 1.0).abs() < 0.02, "fe {f} against modal {m}");
}

#[test]
fn a_time_step_shorter_than_the_contact_step_sets_every_step() {
    // solver.time_step is the largest step. Below the contact step (the estimated contact
    // duration 41.2 us over 200: 2.06e-7 s on the paper's tip) it had been raised to the
    // contact step without a word, so a user halving it to check convergence in time saw the
    // same run; now it sets every step, as many per estimated contact duration as it takes.
    let own = "method = \"modal\"\nmodes = 128\nend_time = 0.005";
    let plan = |solver: &str| {
        impact::Plan::new(&scene_with_solver("paper-tip.toml", own, solver)).unwrap()
    };
    let default = plan("method = \"fe\"\nelements = 64\nend_time = 1e-4");
    let short = plan("method = \"fe\"\nelements = 64\nend_time = 1e-4\ntime_step = 5e-8");
    let long = plan("method = \"fe\"\nelements = 64\nend_time = 1e-4\ntime_step = 1e-6");
    let step = |p: &impact::Plan| p.summary().time_step;
    assert!((step(&default) / 2.0619e-7 - 1.0).abs() < 1e-3, "{}", step(&default));
    assert!(step(&short) <= 5e-8 && step(&short) > 4.9e-8, "{}", step(&short));
    // ... and the plan says every step is that long (it had described longer steps out of
    // contact, "not converged in time").
    let said = &short.summary().reasons;
    assert!(said.iter().any(|r| r.contains("; every step 4.")), "{said:?}");
    assert!(!said
        .iter()
        .any(|r| r.contains("up to") && r.contains("out of contact (solver.time_step)")));
    assert_eq!(step(&long), step(&default));
}

#[test]
fn the_integrator_s_damping_past_a_percent_of_the_energy_is_warned() {
    // A 1 m strip with a tip block (0.98 kg, J2 = 0.098 kg m^2) struck at 0.6 m at 0.1 m/s,
    // stepped at solver.time_step = 2e-5 s out of contact over 0.1 s: HHT-alpha's damping of
    // the waves those steps do not resolve took 19 % of the impact energy (28 % over 1.2 s, a
    // review's), with no word; the default steps take 1e-4 of it or less.
    let text = "name = \"tip block\"\n[beam]\nlength = 1.0\nwidth = 0.025\nthickness = 0.005\nsupport = \"clamped-free\"\n\
                youngs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
                [[beam.mass]]\nat = 1.0\nmass = 0.98125\nrotary_inertia = [0.0, 0.098125, 0.0]\n\
                [ball]\nradius = 0.005\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
                [impact]\nposition = 0.6\nspeed = 0.1\ngravity = false\n\
                [solver]\nmethod = \"fe\"\nfe_model = \"planar\"\ntime_step = 2e-5\nend_time = 0.1\noutput_interval = 2e-4\n";
    let r = simulate(&Scene::from_toml(text).unwrap()).unwrap().report;
    let share = r.energy.numerical_dissipation / r.energy.initial;
    assert!(share > 0.1, "{share}");
    assert!(r.warnings.iter().any(|w| w.contains("numerical damping took")), "{:?}", r.warnings);
}

#[test]
fn a_ball_heavy_against_the_beam_takes_steps_from_its_local_frequency() {
    // The paper's tip struck by a 10 kg ball (gravity off, 2 ms): the contact step sized by the
    // rigid-support pulse (200 a pulse) takes 22.8 steps over a period of the contact's local
    // frequency, and the first contact came out 5.4 % long (1.4267 ms) against steps 14 times
    // shorter (2816 a pulse: 1.3542 ms; 12000: 1.3541 ms), without a word (a review's, 5 %).
    // The default now takes 40 steps a period (352 a pulse): 0.6 % long, the plan says why;
    // 200 asked for is warned of. The paper's 9 g ball: 200, nothing said.
    let heavy = |solver: &str| {
        Scene::from_toml(
            &std::fs::read_to_string(format!(
                "{}/../../validation/scenes/paper-tip.toml",
                env!("CARGO_MANIFEST_DIR")
            ))
            .unwrap()
            .replace("mass = 0.009", "mass = 10.0")
            .replace("gravity = true", "gravity = false")
            .replace("method = \"modal\"\nmodes = 128\nend_time = 0.005", solver),
        )
        .unwrap()
    };
    let warned = |s: &Scene| {
        Plan::new(s).unwrap().warnings().iter().any(|w| w.contains("the contact's local frequency"))
    };
    let default = heavy("method = \"fe\"\nend_time = 0.002");
    assert!(!warned(&default));
    let run = simulate(&default).unwrap().report;
    assert!(
        run.plan
            .reasons
            .iter()
            .any(|r| r.contains("352 contact steps per estimated contact duration, not 200")),
        "{:?}",
        run.plan.reasons
    );
    let fine = simulate(&heavy("method = \"fe\"\nend_time = 0.002\nsamples_per_pulse = 2816"))
        .unwrap()
        .report;
    let long = run.contacts[0].duration / fine.contacts[0].duration - 1.0;
    assert!((0.0..1e-2).contains(&long), "{long}");
    assert!(warned(&heavy("method = \"fe\"\nend_time = 0.002\nsamples_per_pulse = 200")));
    // 100 kg at mid-span (the auto plan's fe: it could bend the beam by more than a tenth of
    // its length): at 200 steps a pulse (5.3 a local period) Newton's iteration diverged at
    // 4.4 us; the default steps carry it.
    let mut mid = heavy("method = \"auto\"\nend_time = 0.0002");
    mid.ball.mass = Some(100.0);
    mid.impact.position = Some(0.575);
    let run = simulate(&mid).unwrap().report;
    assert_eq!(run.plan.method, MethodKind::Fe);
    assert!(run.contacts[0].peak_force > 0.0);
    // A [structure] (the same cantilever as one straight member) takes its steps the same way
    // from its struck section: at 200 a pulse a 100 kg ball on its tip had its first contact
    // 29 % long (1.7559 against 1.3594 ms converged, a review's); the default's 1201: 1.3554.
    let member = |solver: &str| {
        Scene::from_toml(&format!(
            "name = \"member\"\n[structure.section]\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\n\
             density = 7850.0\nwidth = 0.025\nthickness = 0.005\n[[structure.segment]]\n\
             start = [0.0, 0.0, 0.0]\nend = [1.15, 0.0, 0.0]\nelements = 747\n\
             [[structure.support]]\nat = 0.0\nkind = \"clamped\"\n[ball]\nradius = 0.005\n\
             mass = 100.0\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
             [impact]\nat = 1.15\ndirection = [0.0, 0.0, -1.0]\ndrop_height = 0.2\n\
             gravity = false\n[solver]\nmethod = \"fe\"\nend_time = 0.003\n{solver}"
        ))
        .unwrap()
    };
    let plan = Plan::new(&member("")).unwrap();
    let said = &plan.summary().reasons;
    assert!(
        said.iter()
            .any(|r| r.contains("1201 contact steps per estimated contact duration, not 200")),
        "{said:?}"
    );
    assert!(warned(&member("samples_per_pulse = 200")));
    let light =
        scene_with_solver("paper-tip.toml", "method = \"modal\"\nmodes = 128", "method = \"fe\"");
    assert!(!warned(&light));
    assert!(!Plan::new(&light).unwrap().summary().reasons.iter().any(|r| r.contains("not 200")));
}
