//! End-to-end runs against closed forms, energy conservation and convergence, and bad input.
#![allow(clippy::unwrap_used, clippy::float_cmp)] // helpers stop on bad fixtures; exact zeros are part of the contract

use impact::*;

fn scene(path: &str) -> Scene {
    let text = std::fs::read_to_string(format!(
        "{}/../../validation/scenes/{path}",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    Scene::from_toml(&text).unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn half_space_matches_the_hertz_closed_form() {
    // validation/REFERENCES.md 2.2 via the hertz crate's closed form; the issue asks for 1e-4 relative.
    // Onset and separation are located by root finding and the peak is refined by a parabola,
    // so the remaining error is the O(h^2) of the force interpolation (~4e-6 at 1000 steps).
    let s = scene("half-space-r10.toml");
    let out = simulate(&s).unwrap();
    let steel = hertz::Material::new(2.1e11, 0.3).unwrap();
    let contact = hertz::Hertz::between(&steel, &steel, 0.01).unwrap();
    let mass = 7850.0 * 4.0 / 3.0 * std::f64::consts::PI * 1e-6;
    let exact = hertz::HalfSpaceImpact::elastic(&contact, mass, 1.0).unwrap();
    let c = &out.report.contacts[0];
    assert_eq!(out.report.contact_count, 1);
    assert!(rel(c.duration, exact.duration) < 1e-4, "{} vs {}", c.duration, exact.duration);
    assert!(rel(c.peak_force, exact.peak_force) < 1e-4, "{} vs {}", c.peak_force, exact.peak_force);
    assert!(rel(c.max_approach, exact.max_approach) < 1e-4);
    // Elastic on a rigid block: the ball comes back at the speed it came (restitution 1) and
    // the impulse is 2 m V.
    assert!((out.report.restitution.unwrap() - 1.0).abs() < 1e-6);
    assert!(rel(c.impulse, 2.0 * mass) < 1e-6);
}

fn paper_scene(modes: usize, samples: usize, gravity: bool) -> Scene {
    let mut s = scene("paper-tip.toml");
    s.solver.modes = Some(modes);
    s.solver.samples_per_pulse = Some(samples);
    s.impact.gravity = gravity;
    s
}

fn uniform(mut s: Scene) -> Scene {
    s.solver.adaptive_step = Some(false);
    s
}

#[test]
fn energy_balance_with_many_recontacts() {
    // Issue criterion: elastic Hertz, undamped beam, gravity off, paper's tip scene, 64 modes,
    // 5 ms, default settings: balance error below 1e-6 of the initial energy (measured 4.3e-7,
    // adaptive step, 6000 steps).
    let mut s = paper_scene(64, plan::DEFAULT_SAMPLES_PER_PULSE, false);
    s.solver.samples_per_pulse = None;
    let out = simulate(&s).unwrap();
    let e = &out.report.energy;
    assert!(out.report.contact_count >= 10, "only {} contacts", out.report.contact_count);
    assert!(e.balance_error.abs() < 1e-6 * e.initial, "{e:?}");
    assert!(e.dissipated == 0.0 && e.ball_potential == 0.0);
    // The scheme under it, with uniform steps, is second order: the error falls by ~4 per
    // halving of the step (measured 3.86, 3.89).
    let err = |n| {
        let e = simulate(&uniform(paper_scene(64, n, false))).unwrap().report.energy;
        e.balance_error.abs()
    };
    let (a, b, c) = (err(200), err(400), err(800));
    for ratio in [a / b, b / c] {
        assert!((3.4..4.6).contains(&ratio), "ratios {} {}", a / b, b / c);
    }
}

#[test]
fn adaptive_step_error_follows_its_tolerance() {
    // The same run as above with energy tolerances 1e-5, 1e-6, 1e-7. The tolerance is per
    // estimated contact duration, so the balance error may reach it times the contact time
    // over that duration (here ~16); it stays below one tolerance (measured 1.5e-6, 4.3e-7,
    // 8.4e-8 of the initial energy with 4355, 5981, 11902 steps), falls with it, and the
    // first contact agrees with the uniform-step limit (Richardson from 1600 and 3200 steps
    // per pulse: 35.3185225 us, 844.73994 N; measured 2e-8 and 1.2e-7 at 1e-6).
    let run = |tol: f64| {
        let mut s = paper_scene(64, plan::DEFAULT_SAMPLES_PER_PULSE, false);
        s.solver.energy_tolerance = Some(tol);
        // The uniform-step limit below was measured with Euler-Bernoulli modes.
        s.solver.beam_theory = Some(TheoryName::EulerBernoulli);
        let out = simulate(&s).unwrap();
        let steps: usize = out.report.contacts.iter().map(|c| c.steps).sum();
        (out.report.energy.balance_error.abs() / out.report.energy.initial, steps, out)
    };
    let (e5, n5, _) = run(1e-5);
    let (e6, n6, out6) = run(1e-6);
    let (e7, n7, _) = run(1e-7);
    assert!(e5 < 1e-5 && e6 < 1e-6 && e7 < 1e-7, "errors {e5:e} {e6:e} {e7:e}");
    assert!(e5 > e6 && e6 > e7, "errors {e5:e} {e6:e} {e7:e}");
    assert!(n5 < n6 && n6 < n7, "steps {n5} {n6} {n7}");
    let first = &out6.report.contacts[0];
    assert!(rel(first.duration, 35.318_522_5e-6) < 1e-7, "{}", first.duration);
    assert!(rel(first.peak_force, 844.739_94) < 1e-6, "{}", first.peak_force);
    // Uniform steps to the same energy error take 4 times as many steps (800 per pulse:
    // 1.0e-6 with 14609 steps).
    let u = simulate(&uniform(paper_scene(64, 800, false))).unwrap();
    let nu: usize = u.report.contacts.iter().map(|c| c.steps).sum();
    assert!(u.report.energy.balance_error.abs() > e6 * u.report.energy.initial && nu > 2 * n6);
}

#[test]
fn first_contact_converges_with_the_step() {
    // The paper's tip scene with 4 and with 128 modes, uniform steps: first-contact duration
    // and peak force converge at second order as the step is halved (differences fall by ~4).
    for modes in [4, 128] {
        let first =
            |n| simulate(&uniform(paper_scene(modes, n, true))).unwrap().report.contacts[0].clone();
        let (c1, c2, c3) = (first(100), first(200), first(400));
        let d = |f: fn(&Contact) -> f64| ((f(&c1) - f(&c2)).abs(), (f(&c2) - f(&c3)).abs());
        let (p1, p2) = d(|c| c.peak_force);
        let (t1, t2) = d(|c| c.duration);
        assert!(p1 / p2 > 3.0, "{modes} modes: peak differences {p1} {p2}");
        assert!(t1 / t2 > 2.0 || t2 < 1e-12, "{modes} modes: duration differences {t1} {t2}");
        assert!(c3.peak_force > 100.0 && c3.duration > 1e-5 && c3.duration < 1e-4);
    }
}

#[test]
fn thornton_contact_on_a_block_matches_thornton_restitution() {
    // validation/REFERENCES.md 2.4: for this law Thornton's formula is exact, so the solver's restitution
    // must match it to the scheme's accuracy (O(h^2), ~1e-5 at 1000 steps; 1e-4 allowed).
    let mut s = scene("half-space-r10.toml");
    s.half_space.as_mut().unwrap().yield_stress = Some(3.4e8);
    s.contact.law = LawName::Thornton;
    let out = simulate(&s).unwrap();
    let steel = hertz::Material::new(2.1e11, 0.3).unwrap();
    let contact = hertz::Hertz::between(&steel, &steel, 0.01).unwrap();
    let mass = 7850.0 * 4.0 / 3.0 * std::f64::consts::PI * 1e-6;
    let vy = hertz::elastic_limit_velocity(&contact, mass, 1.6 * 3.4e8).unwrap();
    let expected = hertz::thornton_restitution(vy, 1.0).unwrap();
    let e = out.report.restitution.unwrap();
    assert!((e - expected).abs() < 1e-4, "{e} vs {expected}");
    let c = &out.report.contacts[0];
    assert!(c.print_radius > 0.0 && c.print_radius < 0.01);
    // The lost kinetic energy is the plastic work in the ledger.
    let r = &out.report.energy;
    assert!(r.balance_error.abs() < 1e-4 * r.initial, "{r:?}");
    assert!(rel(r.dissipated, r.initial - r.ball_kinetic) < 1e-3);
}

fn error_of(text: &str) -> String {
    match Scene::from_toml(text) {
        Err(e) => e.to_string(),
        Ok(s) => Plan::new(&s).map(|_| String::from("accepted")).unwrap_or_else(|e| e.to_string()),
    }
}

#[test]
fn bad_inputs_name_the_field() {
    let good = std::fs::read_to_string(format!(
        "{}/../../validation/scenes/paper-tip.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    assert_eq!(error_of(&good), "accepted");
    let cases = [
        ("length = 1.15", "length = -1.0", "beam.length = -1"),
        ("length = 1.15", "length = nan", "beam.length = NaN"),
        // Values far outside what the models are built for are refused by the field the user
        // wrote, in scientific notation, not as an infinite stiffness or a NaN energy later.
        ("width = 0.025", "width = 1e308", "beam.width = 1e308: must be from 1e-9 to 10000 (m)"),
        (
            "density = 7850.0
yield",
            "density = 1e-300
yield",
            "beam.density = 1e-300",
        ),
        (
            "youngs_modulus = 2.1e11
poisson_ratio = 0.3
density = 7850.0
yield",
            "youngs_modulus = 1e308
poisson_ratio = 0.3
density = 7850.0
yield",
            "beam.youngs_modulus = 1e308",
        ),
        ("mass = 0.009", "mass = 1e308", "ball.mass = 1e308"),
        ("drop_height = 0.2", "drop_height = 1e308", "impact.drop_height = 1e308"),
        ("end_time = 0.005", "end_time = 1e308", "solver.end_time = 1e308"),
        ("law = \"hertz\"", "law = \"hunt-crossley\"\ndamping = 1e308", "contact.damping = 1e308"),
        ("drop_height = 0.2", "drop_height = 0.2\nspeed = 2.0", "exactly one of drop_height"),
        ("gravity = true", "gravity = true\ngravty = false", "unknown field `gravty`"),
        ("law = \"hertz\"", "law = \"thornton\"", "accepted"),
        ("yield_stress = 3.4e8\n", "", "accepted"),
        ("position = 1.15", "position = 1.5", "impact.position = 1.5"),
        (
            "support = \"clamped-free\"",
            "support = \"clamped\"",
            "\"clamped\" is not one of \"clamped-free\"",
        ),
        ("support = \"clamped-free\"", "support = 3", "3 is not one of \"clamped-free\""),
        ("method = \"modal\"", "method = \"fe\"", "solver.modes belongs to method = \"modal\""),
        ("modes = 128", "modes = 128\nelements = 10", "belong to method = \"fe\""),
        ("method = \"modal\"\nmodes = 128", "method = \"fe\"\nelements = 0", "solver.elements = 0"),
        ("method = \"modal\"\nmodes = 128", "method = \"fe\"\nalpha = 0.1", "solver.alpha = 0.1"),
        ("method = \"modal\"\nmodes = 128", "method = \"fe\"\nalpha = -0.5", "solver.alpha = -0.5"),
        (
            "method = \"modal\"\nmodes = 128",
            "method = \"fe\"\nelement_size = -1e-3",
            "solver.element_size = -0.001",
        ),
        (
            "method = \"modal\"\nmodes = 128",
            "method = \"fe\"\ntime_step = nan",
            "solver.time_step = NaN",
        ),
        (
            "method = \"modal\"\nmodes = 128",
            "method = \"fe\"\nelements = 10\nelement_size = 1e-3",
            "not both",
        ),
        ("method = \"modal\"\nmodes = 128", "method = \"fe\"", "accepted"),
        ("modes = 128", "modes = 128\nenergy_tolerance = 0.0", "solver.energy_tolerance = 0"),
        ("modes = 128", "modes = 128\nenergy_tolerance = nan", "solver.energy_tolerance = NaN"),
        (
            "modes = 128",
            "modes = 128\nadaptive_step = false\nenergy_tolerance = 1e-6",
            "no use with adaptive_step = false",
        ),
        ("modes = 128", "modes = 128\nadaptive_step = false", "accepted"),
        (
            "method = \"modal\"\nmodes = 128",
            "method = \"fe\"\nenergy_tolerance = 1e-6",
            "belong to the modal method",
        ),
        ("yield_stress = 3.4e8\n", "yield_stress = 3.4e8\nmodal_damping = 0.01\n", "accepted"),
        ("radius = 0.005", "radius = 0.0", "ball.radius = 0"),
        (
            "youngs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\nyield_stress",
            "poisson_ratio = 0.3\ndensity = 7850.0\nyield_stress",
            "missing field `youngs_modulus`",
        ),
    ];
    for (from, to, expected) in cases {
        assert!(good.contains(from), "{from}");
        let text = good.replacen(from, to, 1);
        let err = error_of(&text);
        assert!(err.contains(expected), "{to:?}: {err}");
    }
    // Thornton without any yield stress.
    let text = good.replacen("law = \"hertz\"", "law = \"thornton\"", 1).replacen(
        "yield_stress = 3.4e8\n",
        "",
        1,
    );
    assert!(error_of(&text).contains("needs a yield stress"), "{}", error_of(&text));
}

#[test]
fn paper_scene_reports_are_complete_and_finite() {
    let out = simulate(&scene("paper-tip.toml")).unwrap();
    let r = &out.report;
    let json = serde_json::to_string(r).unwrap();
    assert!(!json.contains("NaN") && !json.contains("null,\"equivalent"));
    // The paper's 9 g, 5 mm ball implies ~17 000 kg/m^3: accepted with a warning.
    assert!(r.warnings.iter().any(|w| w.contains("implies a density")));
    assert!(r.contact_count > 5, "the ball chases the tip: {} contacts", r.contact_count);
    assert!(r.equivalent_static_force.unwrap() > 0.0);
    // Static stiffness of the tip with shear (Timoshenko modes by default): 1/(L^3/(3EI) +
    // L/(kGA)), k = 5/6, G = E/2.6; the shear term is 3.1e-5 of the bending one.
    let ei = 2.1e11 * 0.025 * 0.005f64.powi(3) / 12.0;
    let kga = 5.0 / 6.0 * 2.1e11 / 2.6 * 0.025 * 0.005;
    let flexibility = 1.15f64.powi(3) / (3.0 * ei) + 1.15 / kga;
    assert!(rel(r.static_stiffness.unwrap(), 1.0 / flexibility) < 1e-12);
    assert!(out.history.len() > 100);
}

#[test]
fn hunt_crossley_on_a_block_gives_the_restitution_asked_for() {
    // The scene's restitution is met on a half-space (the relation chi V - ln(1 + chi V) =
    // -e chi V - ln(1 - e chi V) is exact there); the small-damping chi = 3(1 - e)/(2V) gave
    // 0.77, 0.66, 0.52 for 0.7, 0.5, 0.1. The solver's contact step leaves ~1e-5 (measured).
    for target in [0.7, 0.5, 0.1] {
        let mut s = scene("half-space-r10.toml");
        s.contact.law = LawName::HuntCrossley;
        s.contact.restitution = Some(target);
        let out = simulate(&s).unwrap();
        let e = out.report.restitution.unwrap();
        assert!((e - target).abs() < 1e-3, "target {target}: {e}");
        assert!(out.report.plan.reasons.iter().any(|r| r.contains("exact half-space relation")));
    }
}

#[test]
fn the_output_interval_does_not_change_the_physics() {
    // An output interval of 1e10 s (or 1e300 s) once let free flight jump by it: 28 contacts
    // became 27, then 9, and the ledger created energy. The jumps now stop at 1024 contact
    // durations: the same contacts as the default run and the same ledger. Different jumps
    // locate onsets from different brackets (to 1e-9 of the pulse scale each), which moves
    // later starts by ~1e-8 (measured 1.9e-8); 1e-6 still catches a lost or extra contact.
    let reference = simulate(&paper_scene(64, 200, false)).unwrap().report;
    for interval in [1e-3, 1e10, 1e300] {
        let mut s = paper_scene(64, 200, false);
        s.solver.output_interval = Some(interval);
        let r = simulate(&s).unwrap().report;
        assert_eq!(r.contact_count, reference.contact_count, "output_interval {interval}");
        for (c, c0) in r.contacts.iter().zip(&reference.contacts).skip(1) {
            assert!(rel(c.start, c0.start) < 1e-6, "{interval}: {} vs {}", c.start, c0.start);
        }
        assert!(r.energy.balance_error.abs() < 1e-6 * r.energy.initial, "{:?}", r.energy);
    }
}

#[test]
fn a_history_or_a_step_count_the_machine_cannot_hold_is_refused_up_front() {
    // An output interval of 1e-10 s over 5 ms once grew the history until the allocator
    // aborted; 1e9 samples per pulse hung. Both are refused before anything runs, with the
    // field, the value and the limit.
    let mut s = scene("paper-tip.toml");
    s.solver.output_interval = Some(1e-10);
    let message = Plan::new(&s).unwrap_err().to_string();
    assert!(
        message.contains("solver.output_interval = 1e-10") && message.contains("rows"),
        "{message}"
    );
    let mut s = scene("paper-tip.toml");
    s.solver.samples_per_pulse = Some(1_000_000_000);
    let message = Plan::new(&s).unwrap_err().to_string();
    assert!(message.contains("solver.samples_per_pulse = 1000000000"), "{message}");
}

#[test]
fn progress_is_told_how_far_the_run_has_got() {
    // What a progress bar is fed: fractions of the window that never go back and end at 1.
    for s in [scene("paper-tip.toml"), scene("half-space-r10.toml")] {
        let seen = std::sync::Mutex::new(Vec::new());
        simulate_with_progress(&s, &|f| seen.lock().unwrap().push(f)).unwrap();
        let seen = seen.into_inner().unwrap();
        assert!(seen.len() > 10, "{} calls", seen.len());
        assert!(seen.windows(2).all(|w| w[1] >= w[0]), "{seen:?}");
        assert!((seen.last().unwrap() - 1.0).abs() < 1e-9 && seen[0] >= 0.0);
    }
}

#[test]
fn a_contact_beyond_small_strain_is_flagged() {
    // Thornton with a 1 kPa yield stress on the paper's tip: an approach of millimetres, more
    // than the ball radius allows for Hertz's theory and a large share of the 5 mm strip. The
    // report says so; the paper's own scene stays silent.
    let mut s = scene("paper-tip.toml");
    s.contact.law = LawName::Thornton;
    s.beam.as_mut().unwrap().yield_stress = Some(1e3);
    s.solver.end_time = Some(1e-3);
    let r = simulate(&s).unwrap().report;
    assert!(
        r.warnings.iter().any(|w| w.contains("beyond small-strain contact")),
        "{:?}",
        r.warnings
    );
    assert!(
        r.warnings.iter().any(|w| w.contains("tenth of the beam's thickness")),
        "{:?}",
        r.warnings
    );
    let quiet = simulate(&scene("paper-tip.toml")).unwrap().report;
    assert!(!quiet.warnings.iter().any(|w| w.contains("extrapolated")), "{:?}", quiet.warnings);
}

#[test]
fn contact_pressure_and_subsurface_shear_follow_hertz_from_the_peak_force() {
    // validation/REFERENCES.md 2.2's half-space impact: Hertz's contact from the reported
    // peak force, by hand (Johnson, Contact Mechanics, eqs. 4.22-4.24): steel on steel,
    // E* = E / (2 (1 - nu^2)), R = 10 mm, a = (3 F R / (4 E*))^(1/3), p0 = 3 F / (2 pi a^2).
    let out = simulate(&scene("half-space-r10.toml")).unwrap();
    let c = &out.report.contacts[0];
    let e_star = 2.1e11 / (2.0 * (1.0 - 0.09));
    let a = (3.0 * c.peak_force * 0.01 / (4.0 * e_star)).cbrt();
    let p0 = 3.0 * c.peak_force / (2.0 * std::f64::consts::PI * a * a);
    // Round-off only: the same formulas in another order.
    assert!(rel(c.contact_radius, a) < 1e-12, "{} vs {a}", c.contact_radius);
    assert!(rel(c.max_pressure, p0) < 1e-12, "{} vs {p0}", c.max_pressure);
    // And the closed form's own p0 at its peak force, within the peak force's 1e-4.
    let steel = hertz::Material::new(2.1e11, 0.3).unwrap();
    let contact = hertz::Hertz::between(&steel, &steel, 0.01).unwrap();
    let mass = 7850.0 * 4.0 / 3.0 * std::f64::consts::PI * 1e-6;
    let exact = hertz::HalfSpaceImpact::elastic(&contact, mass, 1.0).unwrap();
    assert!(rel(c.max_pressure, exact.max_pressure) < 1e-4);
    // Johnson section 3.4: 0.31 p0 at 0.48 a below the surface for nu = 0.3 (two digits
    // quoted), in both bodies alike here.
    assert!((c.ball_max_shear / c.max_pressure - 0.31).abs() < 5e-3);
    assert!((c.body_max_shear_depth / c.contact_radius - 0.48).abs() < 5e-3);
    assert_eq!(c.ball_max_shear, c.body_max_shear);
}

#[test]
fn a_thornton_contact_reports_the_pressure_its_law_caps() {
    // The paper's tip with its Thornton law: p_y = 1.6 x 340 MPa, and the plastic contact's
    // radius at the largest load is the print's rim.
    let mut s = scene("paper-tip.toml");
    s.contact.law = LawName::Thornton;
    s.solver.end_time = Some(3e-4);
    let c = simulate(&s).unwrap().report.contacts[0].clone();
    assert!(c.print_radius > 0.0);
    assert!(rel(c.max_pressure, 1.6 * 3.4e8) < 1e-12, "{}", c.max_pressure);
    // The report's largest approach is refined between steps (a parabola through the
    // samples), the print's from the largest committed step: they differ at the step's
    // O(h^2), halved by the square root.
    assert!(
        rel(c.contact_radius, c.print_radius) < 1e-4,
        "{} vs {}",
        c.contact_radius,
        c.print_radius
    );
}

#[test]
fn the_first_yield_warning_gives_the_central_pressure() {
    // The paper's tip at 1.98 m/s with elastic Hertz: far past first yield (6 mm/s).
    let r = simulate(&scene("paper-tip.toml")).unwrap().report;
    assert!(
        r.warnings
            .iter()
            .any(|w| w.contains("the central pressure p0 = ") && w.contains("1.6 Y = 5.4400e8 Pa")),
        "{:?}",
        r.warnings
    );
}

#[test]
fn the_field_agrees_with_the_history_and_the_stress_envelope() {
    // The paper's tip over 1 ms with its field: at the impact point the field's displacement is
    // the history's (the same modal series, no residual flexibility), and the largest stress
    // on the field's points is the report's, found on a coarser-to-finer search of the same
    // recovery (the field's 65 points hold the report's point within 1.8 cm).
    let mut s = scene("paper-tip.toml");
    s.solver.end_time = Some(1e-3);
    let o = run(&Plan::new(&s).unwrap().with_field().unwrap()).unwrap();
    let field = o.field.unwrap();
    let tip = field.displacement_at(1.15);
    assert_eq!(tip.len(), o.history.time.len());
    for ((t, w), (th, wh)) in
        tip.iter().zip(o.history.time.iter().zip(&o.history.beam_displacement))
    {
        assert_eq!(t, th);
        assert!((w - wh).abs() <= 1e-12 * o.report.max_displacement, "{t}: {w} vs {wh}");
    }
    let b = o.report.bending_stress.unwrap();
    let largest = field.stress.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    assert!(largest <= b.max * (1.0 + 1e-12) && largest > 0.97 * b.max, "{largest} vs {}", b.max);
    // M = EI w'' and sigma = E (h/2) w'': sigma / M = (h/2) / I = 6 / (b h^2).
    let k = field.stress.iter().position(|v| v.abs() == largest).unwrap();
    assert!(rel(field.stress[k] / field.moment[k], 6.0 / (0.025 * 0.005 * 0.005)) < 1e-12);
    // Without the request, no field.
    assert!(simulate(&s).unwrap().field.is_none());
}

#[test]
fn with_the_residual_flexibility_the_field_s_displacement_is_the_history_s() {
    // Struck 1 mm from the clamp the plan takes the residual flexibility (validation/
    // REFERENCES.md 1.4): the history's displacement at the ball has the truncated modes'
    // quasi-static share, and the field's had not (86 % apart there). The field now adds their
    // static deflection (the beam tables' influence line less the kept modes' share) times
    // the force at every point: at the ball the history's, to round-off; and the influence
    // line is the static flexibility at the ball and symmetric (Maxwell).
    let mut s = scene("paper-tip.toml");
    s.impact.position = Some(0.001);
    s.impact.gravity = false;
    s.solver.end_time = Some(2e-4);
    let o = run(&Plan::new(&s).unwrap().with_field().unwrap()).unwrap();
    assert!(o.report.plan.reasons.iter().any(|r| r.starts_with("residual flexibility (taken")));
    let field = o.field.unwrap();
    let at_ball = field.displacement_at(0.001);
    for ((t, w), wh) in at_ball.iter().zip(&o.history.beam_displacement) {
        assert!((w - wh).abs() <= 1e-9 * o.report.max_displacement, "{t}: {w} vs {wh}");
    }
    let beam =
        modal::Beam::rectangular(2.1e11, 7850.0, 0.025, 0.005, 1.15, modal::Support::ClampedPinned)
            .unwrap()
            .with_shear(
                5.0 / 6.0 * 2.1e11 / 2.6 * 0.025 * 0.005,
                7850.0 * 0.025 * 0.005f64.powi(3) / 12.0,
            )
            .unwrap();
    for (c, x) in [(0.3, 0.8), (0.9, 0.1), (0.5, 0.5)] {
        let (a, b) = (beam.static_deflection(c, x).unwrap(), beam.static_deflection(x, c).unwrap());
        assert!(rel(a, b) < 1e-12, "{c} {x}: {a} vs {b}");
    }
    assert!(
        rel(beam.static_deflection(0.4, 0.4).unwrap(), beam.static_flexibility(0.4).unwrap())
            < 1e-12
    );
}

#[test]
fn a_field_that_would_not_fit_is_refused_with_its_size() {
    let mut s = scene("paper-tip.toml");
    s.solver.output_interval = Some(1e-9);
    let e = Plan::new(&s).unwrap().with_field().unwrap_err().to_string();
    assert!(e.starts_with("solver.output_interval = 1e-9: too fine for a field"), "{e}");
    assert!(Plan::new(&scene("half-space-r10.toml")).unwrap().with_field().is_err());
    // The fe field has a point a node: 20000 elements at 1e-5 s over 5 ms (about 2900
    // instants) would hold 2.3e8 values, where the modal method's 66 points hold 7.7e5.
    s.solver.output_interval = Some(1e-5);
    assert!(Plan::new(&s).unwrap().with_field().is_ok());
    s.solver.method = MethodName::Fe;
    s.solver.modes = None;
    s.solver.elements = Some(20_000);
    let e = Plan::new(&s).unwrap().with_field().unwrap_err().to_string();
    assert!(e.contains("x 40002 points x 4 quantities"), "{e}");
}

#[test]
fn the_fe_field_agrees_with_its_history_and_envelope() {
    // The fe method's field at the nodes and the midpoints: at the struck tip (a node) the
    // displacement is the history's, and the largest stress stays within the envelope.
    let mut s = scene("paper-tip.toml");
    s.solver.method = MethodName::Fe;
    s.solver.modes = None;
    s.solver.elements = Some(32);
    s.solver.end_time = Some(2e-4);
    let o = run(&Plan::new(&s).unwrap().with_field().unwrap()).unwrap();
    assert!(!o.report.plan.structure);
    let field = o.field.unwrap();
    // 33 nodes and 32 midpoints (struck at the end: no impact point inside an element).
    assert_eq!(field.points.len(), 65);
    let tip = field.displacement_at(1.15);
    assert_eq!(tip.len(), o.history.time.len());
    for ((_, w), wh) in tip.iter().zip(&o.history.beam_displacement) {
        assert!((w - wh).abs() <= 1e-12 * o.report.max_displacement.max(1e-12), "{w} vs {wh}");
    }
    let b = o.report.bending_stress.unwrap();
    let largest = field.stress.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let p = field.points.len();
    let k = field.points.iter().position(|x| (x - b.position).abs() < 1e-12).unwrap();
    let there = field.time.iter().enumerate().map(|(i, _)| field.stress[i * p + k].abs());
    let there = there.fold(0.0_f64, f64::max);
    assert!(largest <= b.max * (1.0 + 1e-9), "{largest} vs {}", b.max);
    // The report's largest is a point of the field (an element's midpoint, 1.0961 m), and
    // every accepted step a recorded instant here (output interval 1e-7 s, steps 2.06e-7 s):
    // the field there reaches it (30.05 MPa; at the nodes alone, the figures had plotted the
    // nearest node's, the mean of two midpoints).
    assert!((there - b.max).abs() <= 1e-12 * b.max, "{there} vs {}", b.max);
}

#[test]
fn a_maximum_at_the_window_end_is_flagged_with_the_window_that_holds_it() {
    // An aluminium cantilever (E = 70 GPa, 2700 kg/m^3) struck at its tip: its first mode's
    // quarter period is some 50 ms, so over the default 5 ms the tip is still moving away and
    // its "largest" displacement is the last one; over 0.1 s the first swing is held.
    let mut s = scene("paper-tip.toml");
    let beam = s.beam.as_mut().unwrap();
    (beam.youngs_modulus, beam.density, beam.yield_stress) = (7e10, 2700.0, Some(2.7e8));
    let short = simulate(&s).unwrap().report;
    assert!(short.max_displacement_at_window_end);
    assert!(
        short.warnings.iter().any(|w| w
            .contains("largest displacement at the impact point sits at the window's end")
            && w.contains("quarter period")),
        "{:?}",
        short.warnings
    );
    s.solver.end_time = Some(0.1);
    let long = simulate(&s).unwrap().report;
    assert!(!long.max_displacement_at_window_end);
    assert!(long.max_displacement > 1.5 * short.max_displacement);
}

#[test]
fn the_modal_stress_converges_at_third_order_in_the_modes() {
    // validation/REFERENCES.md 1.5: the paper's tip over 1 ms, the beam-wide largest stress
    // against 2048 modes falls 1.5e-3, 3.4e-4, 3.9e-5 at 128, 256, 512 modes (a factor 4 to 9
    // a doubling); at least 3 a doubling is asserted, and 2e-3 at the default 128.
    let stress = |modes: usize| {
        let mut s = scene("paper-tip.toml");
        s.solver.modes = Some(modes);
        s.solver.end_time = Some(1e-3);
        s.solver.beam_theory = Some(TheoryName::EulerBernoulli);
        simulate(&s).unwrap().report.bending_stress.unwrap().max
    };
    let converged = stress(2048);
    let errors: Vec<f64> = [128, 256, 512].iter().map(|n| rel(stress(*n), converged)).collect();
    assert!(errors[0] < 2e-3, "{errors:?}");
    assert!(errors[0] > 3.0 * errors[1] && errors[1] > 3.0 * errors[2], "{errors:?}");
}

#[test]
fn too_few_modes_for_the_stress_near_the_ball_warn_and_the_default_plan_does_not() {
    let warns = |modes: Option<usize>| {
        let mut s = scene("paper-tip.toml");
        s.solver.modes = modes;
        s.solver.end_time = Some(2e-4);
        simulate(&s).unwrap().report.warnings.iter().any(|w| w.contains("omega_N t_c"))
    };
    assert!(warns(Some(64)));
    assert!(!warns(None));
    assert!(!warns(Some(128)));
}

#[test]
fn the_plain_series_is_kept_where_asked_and_is_further_off_under_the_ball() {
    // validation/REFERENCES.md 1.5: against 2048 modes (mode-acceleration), the paper's tip
    // over 1 ms at 256 and 512 modes: mode-acceleration 1.3e-4 and 1.7e-5, plain 1.0e-3 and
    // 9.4e-5 (the plain series' error changes sign from one count to the next: at 128 modes
    // it lands within 6e-6 by chance, where the mode-acceleration form is 9.6e-4 off);
    // asserted: the plain series at least 3 times further off at both.
    let stress = |modes: usize, plain: bool| {
        let mut s = scene("paper-tip.toml");
        s.solver.modes = Some(modes);
        s.solver.end_time = Some(1e-3);
        s.solver.beam_theory = Some(TheoryName::EulerBernoulli);
        s.solver.plain_stress_series = Some(plain);
        simulate(&s).unwrap().report.bending_stress.unwrap().max
    };
    let converged = stress(2048, false);
    for modes in [256, 512] {
        let (ma, plain) =
            (rel(stress(modes, false), converged), rel(stress(modes, true), converged));
        assert!(plain > 3.0 * ma, "{modes}: mode-acceleration {ma:e}, plain {plain:e}");
    }
    // A modal-only key: refused with the fe method.
    let mut fe = scene("paper-tip.toml");
    fe.solver = SolverSpec {
        method: MethodName::Fe,
        plain_stress_series: Some(true),
        ..Default::default()
    };
    assert!(Plan::new(&fe).unwrap_err().to_string().contains("plain_stress_series"));
}

#[test]
fn a_thornton_reload_into_the_print_reports_its_own_pressure() {
    // The paper's tip with the Thornton law over 2 ms: the first contact dents the beam
    // (360.0 N, print rim a_p = 0.4594 mm), the later taps of a few newtons reload the print
    // elastically. They had reported p0 = p_y = 544 MPa over a = 0.432 mm, a pressure that
    // carries (2/3) pi p0 a^2 = 212 N against 2.4 N. Thornton (1997): Hertz on the print's
    // radius R_p = 4 E* a_p^3 / (3 F*) = 41.45 mm; a review's independent script gave contact
    // 2 (2.404 N) a = 0.0865 mm, p0 = 153.3 MPa.
    let mut s = scene("paper-tip.toml");
    s.contact.law = LawName::Thornton;
    s.solver.end_time = Some(0.002);
    let out = simulate(&s).unwrap();
    let c = &out.report.contacts;
    assert!(c[0].max_pressure == 5.44e8 && c[0].contact_radius == c[0].print_radius);
    assert!((c[0].print_radius / 0.4594e-3 - 1.0).abs() < 1e-3, "{}", c[0].print_radius);
    assert!(c.len() > 5);
    for later in &c[1..] {
        let carried =
            2.0 / 3.0 * std::f64::consts::PI * later.max_pressure * later.contact_radius.powi(2);
        assert!(rel(carried, later.peak_force) < 1e-9, "{later:?}");
        assert!(later.max_pressure < 5.44e8 && later.contact_radius < 0.3 * later.print_radius);
    }
    assert!(rel(c[1].contact_radius, 0.0865e-3) < 2e-3 && rel(c[1].max_pressure, 153.3e6) < 2e-3);
}

#[test]
fn a_window_that_ends_before_the_driven_swing_says_so() {
    // The paper's tip under gravity, 64 modes (as `reproduce` Fig. 5), dropped from 0.1 m: over
    // 0.1 s the largest displacement is 3.327 mm at 75 ms and nothing said it might not be the
    // maximum; the ball falls back and strikes the swinging beam after 0.1 s, and over 0.16 s
    // (the first contact's end plus half the first mode's period, 0.317 s) it is 3.594 mm at
    // 113 ms, 8 % more (a review's; validation/REFERENCES.md 1.15). The short window now warns
    // and names that window; the long one does not.
    let run = |end: f64| {
        let mut s = scene("paper-tip.toml");
        s.impact.drop_height = Some(0.1);
        s.solver.modes = Some(64);
        s.solver.end_time = Some(end);
        simulate(&s).unwrap().report
    };
    let said = |r: &Report| r.warnings.iter().any(|w| w.contains("may not be the maximum"));
    let short = run(0.1);
    assert!(said(&short) && short.warnings.iter().any(|w| w.contains("solver.end_time = 1.583")));
    let long = run(0.16);
    assert!(!said(&long), "{:?}", long.warnings);
    assert!(long.max_displacement > 1.05 * short.max_displacement);
}

#[test]
fn a_hunt_crossley_contact_that_creeps_out_is_one_contact() {
    // Hunt-Crossley at e = 0.02 on the half-space at 1 m/s: chi = 50 s/m, so the factor
    // 1 + chi delta' reaches zero when the ball leaves at 1/chi = 0.02 m/s with 4 um of
    // approach left, and the ball creeps out at that rate with the force hovering at zero.
    // Each zero had ended the contact and the next round-off begun another: 166 contacts, 165
    // of no force, and "stored" contact energy left at the end (a review's). On a rigid
    // half-space without gravity there is one contact; it ends when the approach returns,
    // within the default window (four times the damped contact's own length on a rigid
    // support, 332 us: it had been Hertz's 69 us, and the window ended before the exit).
    let mut s = scene("half-space-r10.toml");
    s.contact.law = LawName::HuntCrossley;
    s.contact.restitution = Some(0.02);
    let r = simulate(&s).unwrap().report;
    assert_eq!(r.contact_count, 1, "{:?}", r.contacts);
    assert!(r.contacts[0].complete);
    assert!((r.restitution.unwrap() - 0.02).abs() < 1e-9, "{:?}", r.restitution);
    // The ledger within the adaptive step's tolerance, 1e-6 of the impact energy per
    // estimated contact duration (the damped pulse's 9.95 us, 33 of them in the 332 us
    // contact): measured 4.4e-8 (1.0e-8 when the steps were sized for Hertz's 69 us pulse,
    // 7 times longer, and the tolerance per unit time as much tighter).
    assert!(
        r.energy.contact_stored == 0.0 && r.energy.balance_error.abs() < 1e-7 * r.energy.initial,
        "{:?}",
        r.energy
    );
}

#[test]
fn a_ledger_under_gravity_is_judged_against_the_energy_in_play() {
    // A 10 mm ball set down on the half-space at 1e-6 m/s under gravity (Thornton): it sinks
    // into the contact with gravity's work, about 2e-8 J at the window's end, against an
    // initial kinetic energy of 1.6e-14 J. The ledger's round-off (2e-15 J) had been warned as
    // 0.13 of the initial, blaming the stepping (a review's); against the energy in play it
    // is 1e-7.
    let mut s = scene("half-space-r10.toml");
    s.half_space.as_mut().unwrap().yield_stress = Some(5e8);
    s.contact.law = LawName::Thornton;
    s.impact.speed = Some(1e-6);
    s.impact.gravity = true;
    let r = simulate(&s).unwrap().report;
    let e = &r.energy;
    assert!(-e.ball_potential > 1e5 * e.initial, "{e:?}");
    assert!(e.balance_error.abs() < 1e-6 * (e.initial - e.ball_potential), "{e:?}");
    assert!(!r.warnings.iter().any(|w| w.contains("does not close")), "{:?}", r.warnings);
}

#[test]
fn a_strongly_damped_hunt_crossley_pulse_gets_the_modes_its_rise_needs() {
    // The paper's tip with Hunt-Crossley at e = 0.1 (chi V = 10): the damping brings the
    // force's peak forward to 5.6 us on a rigid support (Hertz's: 20.6 us), and the modes
    // sized for Hertz's 41 us pulse (106) gave a first peak of 1011.7 N against the fe
    // method's 892.3 N (a review's; 747 to 3000 elements agree to 0.1 %), 13 % high, at
    // e = 0.02 1785 against 1381 N, 29 %. The plan now sizes them for the faster rise: 263
    // modes, 888.0 N (-0.5 %; at e = 0.02, 628 modes, 1361 N, -1.4 %).
    let mut s = scene("paper-tip.toml");
    s.contact.law = LawName::HuntCrossley;
    s.contact.restitution = Some(0.1);
    s.solver.modes = None;
    s.solver.end_time = Some(9e-4);
    let r = simulate(&s).unwrap().report;
    assert!(r.plan.reasons.iter().any(|x| x.contains("brings the peak force forward")));
    assert!(rel(r.contacts[0].peak_force, 892.3) < 1e-2, "{}", r.contacts[0].peak_force);
}

#[test]
fn a_damped_contact_runs_by_the_fe_method_and_agrees_with_the_modal_one() {
    // Hunt-Crossley at e = 0.8 at mid-span: the fe method's contact step had been sized from
    // Hertz's pulse and its free-flight step from the damped contact's shorter one, which
    // left the free step below the contact step and the run panicked in a clamp (a review's,
    // on every real damping). Both steps now come from the pulse the meshes are sized for
    // (the damped rise, doubled), and the first contact agrees with the modal method's: 256
    // elements 1131.6 N and 41.80 us against 1135.2 N and 41.68 us at the modal plan's modes
    // (measured; the 0.3 % is the mesh's, the mid-span plan's own error estimate allows it).
    let mut s = scene("paper-midspan.toml");
    s.contact.law = LawName::HuntCrossley;
    s.contact.restitution = Some(0.8);
    s.solver.modes = None;
    s.solver.end_time = Some(1e-4);
    let modal = simulate(&s).unwrap().report;
    s.solver.method = MethodName::Fe;
    s.solver.elements = Some(256);
    let fe = simulate(&s).unwrap().report;
    assert!(fe.plan.time_step <= modal.plan.time_step * (1.0 + 1e-12));
    let (a, b) = (&fe.contacts[0], &modal.contacts[0]);
    assert!(rel(a.peak_force, b.peak_force) < 1e-2, "{} vs {}", a.peak_force, b.peak_force);
    assert!(rel(a.duration, b.duration) < 1e-2, "{} vs {}", a.duration, b.duration);
}

#[test]
fn a_single_element_runs_and_warns_instead_of_panicking() {
    // solver.elements = 1 was accepted and then read a second element's stress at the clamp
    // (index out of bounds, a review's: simulate, compare, sweep and Python all stopped).
    let mut s = scene("paper-midspan.toml");
    s.solver.method = MethodName::Fe;
    s.solver.modes = None;
    s.solver.elements = Some(1);
    s.solver.end_time = Some(1e-4);
    let r = simulate(&s).unwrap().report;
    assert!(r.bending_stress.unwrap().max.is_finite());
    assert!(r.warnings.iter().any(|w| w.contains("not resolved")), "{:?}", r.warnings);
}
