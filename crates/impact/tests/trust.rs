//! The numbers a report prints do not depend on what it records: maxima between the observed
//! instants (validation/REFERENCES.md 1.8), and coarse models refused or named.
#![allow(clippy::unwrap_used)] // helpers stop on bad fixtures

use impact::*;

/// The steel ball of radius 5 mm both beams here are struck by.
const BALL: &str = r#"[ball]
radius = 0.005
youngs_modulus = 2.1e11
poisson_ratio = 0.3
density = 7850.0"#;

/// An aluminium strip (1 m, 30 x 6 mm) pinned at both ends, struck at a third of its span by
/// a 10 mm steel ball at 1.5 m/s, gravity off, over 20 ms (its first mode's period is 36 ms,
/// so the largest displacement comes in free flight, far from any contact step).
fn aluminium(solver: &str) -> Scene {
    Scene::from_toml(&format!(
        r#"
name = "aluminium-third"
[beam]
length = 1.0
width = 0.03
thickness = 0.006
support = "pinned-pinned"
youngs_modulus = 7.0e10
poisson_ratio = 0.33
density = 2700.0
{BALL}
[impact]
position = 0.3333333333333333
speed = 1.5
gravity = false
[contact]
law = "hertz"
[solver]
end_time = 0.02
{solver}
"#
    ))
    .unwrap()
}

/// (largest displacement, its time, largest stress, each support's largest stress).
fn maxima(scene: &Scene) -> (f64, f64, f64, Vec<f64>) {
    let r = simulate(scene).unwrap().report;
    let b = r.bending_stress.unwrap();
    (r.max_displacement, r.max_displacement_time, b.max, b.supports.iter().map(|s| s.max).collect())
}

fn assert_same(a: &(f64, f64, f64, Vec<f64>), b: &(f64, f64, f64, Vec<f64>), what: &str) {
    let rel = |x: f64, y: f64| (x - y).abs() / y.abs().max(f64::MIN_POSITIVE);
    assert!(rel(a.0, b.0) < 1e-9, "{what}: displacement {} vs {}", a.0, b.0);
    assert!(rel(a.2, b.2) < 1e-9, "{what}: stress {} vs {}", a.2, b.2);
    // A support's stress below 1e-4 of the largest (a pinned end's, round-off) is certified
    // only to that floor (the largest itself to 1e-9): any two values below it agree.
    let floor = 1e-4 * b.2.abs();
    for (x, y) in a.3.iter().zip(&b.3) {
        let below = x.abs() <= floor && y.abs() <= floor;
        assert!(below || rel(*x, *y) < 1e-9, "{what}: support {x} vs {y}");
    }
}

#[test]
fn the_modal_maxima_do_not_depend_on_the_output_interval() {
    // Before the search between instants, an output interval of 1 ms or longer gave a
    // largest displacement 3.5 % low here (3.8146e-4 against 3.9511e-4 m: the free flight's
    // steps ran up to it, and the maximum was sampled at their ends). Now the largest displacement is
    // searched in time to 1e-10 and the stress over the beam to 1e-9 and polished by Newton's
    // method to round-off: three intervals agree to 1e-9.
    let fine = maxima(&aluminium("method = \"modal\"\nmodes = 64"));
    for interval in ["1e-3", "0.05"] {
        let coarse = maxima(&aluminium(&format!(
            "method = \"modal\"\nmodes = 64\noutput_interval = {interval}"
        )));
        assert_same(&coarse, &fine, interval);
    }
    // The largest displacement comes in free flight, between the contacts' steps.
    assert!(fine.1 > 5e-3, "at {} s", fine.1);
}

#[test]
fn the_fe_maxima_do_not_depend_on_the_output_interval() {
    // The fe method observes its stress at every accepted step and the displacement between
    // steps by the cubic through their ends and rates; its steps do not depend on what it
    // records. 64 elements, over 5 ms.
    let fe = |interval: &str| {
        let mut s = aluminium(&format!("method = \"fe\"\nelements = 64\n{interval}"));
        s.solver.end_time = Some(5e-3);
        maxima(&s)
    };
    let fine = fe("");
    assert_same(&fe("output_interval = 1e-3"), &fine, "1e-3");
    assert_same(&fe("output_interval = 0.05"), &fine, "0.05");
}

/// The paper's tip (1 ms, gravity off), its mid-span (2 ms, gravity off), and a stubby
/// pinned-pinned steel beam (L = 0.1 m, h = 12.5 mm, struck at mid-span at 1 m/s), with the
/// solver lines `solver`.
fn theory_scenes(solver: &str) -> Vec<Scene> {
    let read = |name: &str| {
        edited_text(name, &[("gravity = true", "gravity = false"), ("modes = 128", solver)])
    };
    let tip = read("paper-tip.toml").replace("end_time = 0.005", "end_time = 0.001");
    let stubby = format!(
        r#"
name = "stubby"
[beam]
length = 0.1
width = 0.025
thickness = 0.0125
support = "pinned-pinned"
youngs_modulus = 2.1e11
poisson_ratio = 0.3
density = 7850.0
{BALL}
[impact]
position = 0.05
speed = 1.0
gravity = false
[contact]
law = "hertz"
[solver]
method = "modal"
end_time = 0.0005
{solver}
"#
    );
    [tip, read("paper-midspan.toml"), stubby].iter().map(|t| Scene::from_toml(t).unwrap()).collect()
}

#[test]
fn the_euler_bernoulli_model_error_is_measured_not_bounded() {
    // Euler-Bernoulli asked for, tolerance 1e-3: the estimated error holds the difference a
    // Timoshenko run at the same modes makes (the report's model_error). Against Timoshenko
    // modes converged to 1e-3 on their own (the worst of the one comparison,
    // Report::differences_from: 1 where the significant contacts differ in number), it is
    // at least that difference and at most 10 times it. Measured: the tip's chatter has one
    // significant contact more or less (1; its first contact differs by 4.6e-4, its largest
    // stress by 9.9e-3: Euler-Bernoulli's near field is 1 % low), mid-span 1.5e-2 against an
    // estimate of 1.52e-2, the stubby beam 5.9e-3 against 6.4e-3. Before, the estimate was at
    // least the first-order frequency shift at pi/t_c: 4.4e-2 wherever the paper's beam was
    // struck.
    let eb = theory_scenes("tolerance = 1e-3\nbeam_theory = \"euler-bernoulli\"");
    let timoshenko = theory_scenes("tolerance = 1e-3\nbeam_theory = \"timoshenko\"");
    for (e, t) in eb.iter().zip(&timoshenko) {
        let (e, t) = (simulate(e).unwrap().report, simulate(t).unwrap().report);
        let d = e.differences_from(&t);
        let measured = if d.same_contacts { d.worst() } else { 1.0 };
        let estimate = e.estimated_error.unwrap();
        assert!(e.model_error.is_some(), "{}: no model error", e.name);
        let within_tolerance = measured < 1e-4 && estimate <= 1e-3;
        assert!(
            within_tolerance || (measured <= estimate && estimate <= 10.0 * measured),
            "{}: measured {measured:e} ({d}), estimated {estimate:e}",
            e.name
        );
    }
}

#[test]
fn a_mesh_too_coarse_to_mean_anything_is_refused_or_named() {
    // One element on a pinned-pinned beam pins both its nodes: the ball would meet a rigid
    // support, and the report said restitution 1, no displacement and no stress. Refused,
    // naming solver.elements.
    let one = aluminium("method = \"fe\"\nelements = 1");
    let e = Plan::new(&one).unwrap_err().to_string();
    assert!(e.contains("solver.elements") && e.contains("holds the impact point"), "{e}");
    // On a support itself no mesh moves the point: refused for where it is (it said "use more
    // elements").
    let text = edited_text(
        "paper-tip.toml",
        &[
            ("position = 1.15", "position = 0.0"),
            ("method = \"modal\"\nmodes = 128", "method = \"fe\"\nelements = 16"),
        ],
    );
    let e = Plan::new(&impact::Scene::from_toml(&text).unwrap()).unwrap_err().to_string();
    assert!(e.contains("impact.position = 0 m is on a support") && e.contains("x = 0 m"), "{e}");
    // The modal method alike (it had answered a ball bouncing off a rigid face, with the
    // beam's stresses of a few pascals, a review's), and with a mass on the beam, where it
    // takes the beam's finite-element modes (it said "rows = 0 (-) is not allowed"): by the
    // [beam]'s own key.
    let modal = text.replace("method = \"fe\"\nelements = 16", "method = \"modal\"");
    let massive = modal.replace("[ball]", "[[beam.mass]]\nat = 0.575\nmass = 0.1\n\n[ball]");
    for scene in [modal, massive] {
        let e = Plan::new(&impact::Scene::from_toml(&scene).unwrap()).unwrap_err().to_string();
        assert!(e.contains("impact.position = 0 m is on a support"), "{e}");
    }
    // Two elements: the stress was ten times too low with nothing said. Warned, with the
    // elements' size against the pulse's wavelength and the first mode.
    let two = Plan::new(&aluminium("method = \"fe\"\nelements = 2")).unwrap();
    let w = two.warnings().join("\n");
    assert!(w.contains("solver.elements: elements of") && w.contains("several times off"), "{w}");
    assert!(w.contains("per half-wave of the first mode"), "{w}");
    // Struck on a support node: refused too.
    let mut on_support = aluminium("method = \"fe\"\nelements = 3");
    on_support.impact.position = Some(0.0);
    assert!(Plan::new(&on_support).is_err());
    // A fine mesh says nothing of the kind, and the reasons carry the criterion.
    let fine = Plan::new(&aluminium("method = \"fe\"\nelements = 512")).unwrap();
    assert!(
        fine.warnings().iter().all(|w| !w.contains("solver.elements")),
        "{:?}",
        fine.warnings()
    );
    assert!(fine.summary().reasons.iter().any(|r| r.starts_with("mesh check:")));
    // An element size below what a position can tell apart names its key.
    let tiny = aluminium("method = \"fe\"\nelement_size = 1e-300");
    let e = Plan::new(&tiny).unwrap_err().to_string();
    assert!(e.contains("solver.element_size") && e.contains("1e-300"), "{e}");
}

#[test]
fn the_accuracy_study_and_the_report_measure_the_same_model_error() {
    // The accuracy study's Euler-Bernoulli curve (its finest setting against the Timoshenko
    // modal reference) and an Euler-Bernoulli report's model_error (a Timoshenko run at the
    // same modes) measure the same thing: on the paper's mid-span, where shear and rotary
    // inertia move the results by 1.5 %, they agree within the study's finest setting's own
    // error (1.3e-2 and 1.5e-2 measured; the quick study's finest Euler-Bernoulli setting is
    // 128 modes, the report's 186).
    let scene = Scene::from_toml(&edited_text("paper-midspan.toml", &[])).unwrap();
    let ladders = study::accuracy::Ladders::quick();
    let study = study::accuracy::run(&scene, &ladders, &|_, _| {}).unwrap();
    let curve = study.theory_difference.unwrap().worst();
    let mut eb = scene.clone();
    eb.solver.modes = None;
    eb.solver.tolerance = Some(1e-3);
    eb.solver.beam_theory = Some(TheoryName::EulerBernoulli);
    let model = simulate(&eb).unwrap().report.model_error.unwrap();
    assert!((model - curve).abs() <= 0.25 * curve, "report {model:e}, study {curve:e}");
}

/// The text of validation/scenes/`file` with each (from, to) of `edits` replaced.
fn edited_text(file: &str, edits: &[(&str, &str)]) -> String {
    let path = format!("{}/../../validation/scenes/{file}", env!("CARGO_MANIFEST_DIR"));
    edits
        .iter()
        .fold(std::fs::read_to_string(path).unwrap(), |text, (from, to)| text.replace(from, to))
}

/// The report of validation/scenes/`file` with each (from, to) of `edits` replaced.
fn edited_scene(file: &str, edits: &[(&str, &str)]) -> Report {
    simulate(&Scene::from_toml(&edited_text(file, edits)).unwrap()).unwrap().report
}

/// The searches' worst gap the report's note gives, with the note.
fn searches_gap(r: &Report) -> (f64, &str) {
    let note = r.plan.reasons.iter().find(|s| s.contains("each within")).unwrap();
    let gap = note.split("each within ").nth(1).unwrap().split(' ').next().unwrap();
    (gap.parse().unwrap(), note)
}

#[test]
fn a_search_past_its_budget_stops_and_says_how_certain_its_maxima_are() {
    // 20000 modes (a scene's most) over the first contact: the bounds of the highest modes
    // are loose. Before the budget, the search kept a mode state for every instant it made
    // and ran out of 24 GiB (`xtask validate`, case hard-20000-modes); now each search stops
    // at 2e7 mode-values and the report says the gap it reached. The clamp's stress (the
    // series' noise: no wave reaches the clamp in 50 us) stops at its budget 7e-4 of the
    // largest stress short of its floor (1e-4 of the largest), which the note reports; the
    // largest stress itself, which stopped at its budget 8.9e-2 short of itself while its
    // cells were bounded by how far the force rose above the lower end rather than by how
    // far it leaves its chord, is now certified.
    let edits = [("modes = 128", "modes = 20000"), ("end_time = 0.005", "end_time = 5e-5")];
    let r = edited_scene("paper-tip.toml", &edits);
    let w = r.warnings.join("\n");
    assert!(!w.contains("the largest stress is certain only"), "{w}");
    let (gap, note) = searches_gap(&r);
    assert!(gap > 1e-4 && gap < 1e-3, "{note}");
    assert!(r.bending_stress.unwrap().max.is_finite());
}

#[test]
fn a_support_stress_far_below_the_largest_is_certified_to_what_the_largest_is() {
    // The paper's tip with 256 modes over its first contact (60 us): no bending or shear wave
    // reaches the clamp in that time (the shear wave, sqrt(kappa G / rho) = 3.0 km/s, needs
    // 0.38 ms for 1.15 m), so the clamp's stress is the truncated series' noise, about 130 Pa
    // against the largest 55 MPa. Certifying it to 1e-10 of itself took 9400 splits of its
    // search, 4/5 of the run's time; it is now certified to 1e-4 of the largest stress (a
    // floor: the largest itself is searched to 1e-9), and the report's note counts its gap as
    // a share of that.
    let edits = [("modes = 128", "modes = 256"), ("end_time = 0.005", "end_time = 6e-5")];
    let r = edited_scene("paper-tip.toml", &edits);
    let b = r.bending_stress.as_ref().unwrap();
    let clamp = b.supports[0].max;
    assert!(clamp > 0.0 && clamp < 1e-4 * b.max, "clamp {clamp} Pa, largest {} Pa", b.max);
    let (gap, note) = searches_gap(&r);
    assert!(gap <= 1e-4, "{note}");
    assert!(!r.warnings.iter().any(|w| w.contains("certain only")), "{:?}", r.warnings);
}

#[test]
fn every_search_of_a_window_ending_inside_a_long_contact_is_certified() {
    // validation/scenes/paper-tip-offset.toml (10 mm off the centreline: its first contact
    // lasts 0.83 ms) cut at 0.1 ms, inside that contact. No twist reaches the clamp by then
    // (the strip's torsion wave needs about 0.9 ms), so the clamp's torsion shear is the
    // series' noise (about 120 Pa against 27 MPa at the struck section). Its search ran to
    // its budget, and the budget counted the instants earlier searches had made, so the
    // largest displacement's search, the last, started spent: the report warned that it and
    // the torsion shear were certain only to 7e-3 and 3.9 of themselves. Each search now has
    // its own budget and the sections' torsion shear is certified to 1e-4 of the largest.
    let r = edited_scene("paper-tip-offset.toml", &[("end_time = 0.001", "end_time = 1e-4")]);
    assert!(!r.warnings.iter().any(|w| w.contains("certain only")), "{:?}", r.warnings);
    let (gap, note) = searches_gap(&r);
    assert!(gap <= 1e-4, "{note}");
}

#[test]
fn a_free_free_beam_s_stress_takes_its_static_share_by_inertia_relief() {
    // A 0.5 m strip struck at 0.4 m at 1 m/s, 0.1 ms: no wave reaches an end before the
    // largest stress, so every support gives the same one. The free-free beam's had come from
    // the plain series (no static moment to take the truncated modes' share from): 1.1907e7
    // Pa at the 52 modes the plan chooses, 15 % low. With the static moment by inertia relief
    // (modal::Beam::static_curvature), measured 1.409579e7 against the cantilever's 1.409582e7.
    let run = |support: &str| {
        let text = format!(
            "name = \"strip\"\n[beam]\nlength = 0.5\nwidth = 0.025\nthickness = 0.005\nsupport = \"{support}\"\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n[ball]\nradius = 0.005\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n[impact]\nposition = 0.4\nspeed = 1.0\ngravity = false\n[solver]\nmethod = \"modal\"\nend_time = 1e-4\n"
        );
        simulate(&Scene::from_toml(&text).unwrap()).unwrap().report.bending_stress.unwrap().max
    };
    let (free, clamped) = (run("free-free"), run("clamped-free"));
    assert!((free / clamped - 1.0).abs() < 1e-4, "{free} vs {clamped}");
}

#[test]
fn a_first_contact_without_the_truncated_modes_compliance_says_how_far_off_it_is() {
    // The paper's tip at the default modes (106 Timoshenko modes, 0.1 ms): the plain series
    // leaves out the truncated modes' static compliance at the tip, in series with the
    // contact, and the first peak force came out 1.31 % above the run that takes it (791.46
    // against 781.23 N; converged 781.29 N), unsaid (a review's). The warning's estimate,
    // 3/4 c F / d (Hertz with a series spring, first order), says 1.64 %: within 1 to 1.5 times
    // the measured error; the run that takes it says nothing.
    let edits = [("modes = 128\n", ""), ("end_time = 0.005", "end_time = 0.0001")];
    let plain = edited_scene("paper-tip.toml", &edits);
    let with = edited_scene(
        "paper-tip.toml",
        &[edits[0], edits[1], ("[solver]", "[solver]\nresidual_flexibility = true")],
    );
    let measured = plain.contacts[0].peak_force / with.contacts[0].peak_force - 1.0;
    let said = plain
        .warnings
        .iter()
        .find_map(|w| {
            let (_, rest) = w.split_once("its peak force comes out about ")?;
            rest.split_once(" % high")?.0.parse::<f64>().ok()
        })
        .expect("the first contact's warning");
    assert!((1.0..1.5).contains(&(said / 100.0 / measured)), "{said} % said, {measured} measured");
    assert!(with.warnings.iter().all(|w| !w.contains("the first contact leaves out")));
    // Past its first order the estimate gives no size: twenty modes at the tip, where it said
    // 189 % for 110 % measured (a second review's), now say the contact is far off.
    let few = edited_scene(
        "paper-tip.toml",
        &[("modes = 128", "modes = 20"), ("end_time = 0.005", "end_time = 0.0001")],
    );
    let w = few.warnings.iter().find(|w| w.contains("the first contact leaves out")).unwrap();
    assert!(w.contains("far too few modes") && !w.contains("comes out about"), "{w}");
}

#[test]
fn a_free_free_beam_s_analytic_modes_say_they_leave_out_the_truncated_modes_compliance() {
    // The paper's strip free at both ends, struck at mid-span (0.1 ms): its analytic modes
    // (107 at the default) have no residual flexibility on the free body, and the first peak
    // force came out 1243.12 N against its own modes' 1234.14 N (0.73 %, inertia relief
    // carrying the truncated modes' share), unsaid (a second review's). Warned now, and the
    // size it quotes holds: the analytic run between 0.3 and 1.5 % above.
    let edits = [
        ("support = \"clamped-free\"", "support = \"free-free\""),
        ("end_time = 0.002", "end_time = 0.0001"),
        ("modes = 128\n", ""),
    ];
    let analytic = edited_scene("paper-midspan.toml", &edits);
    assert!(analytic
        .warnings
        .iter()
        .any(|w| w.contains("a free-free beam's analytic modes carry no residual flexibility")));
    let own = edited_scene(
        "paper-midspan.toml",
        &[edits[0], edits[1], ("modes = 128", "modal_basis = \"fe\"")],
    );
    let above = analytic.contacts[0].peak_force / own.contacts[0].peak_force - 1.0;
    assert!((3e-3..1.5e-2).contains(&above), "{above}");
    assert!(own.warnings.iter().all(|w| !w.contains("carry no residual flexibility")));
}
