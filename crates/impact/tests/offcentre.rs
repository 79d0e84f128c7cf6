//! Off-centre strikes: the torsion modes of the modal method against the 3D Simo beam's, the
//! static stiffness of the struck face, and the checks of `impact.offset`
//! (validation/REFERENCES.md 1.9).
#![allow(clippy::unwrap_used)] // a test stops on a bad fixture

use impact::{simulate, Plan, Scene};
use nalgebra::Vector3;
use simo_beam::{natural_modes, BeamModel, Material, Mesh, Section, Support};

const E: f64 = 2.1e11;
const NU: f64 = 0.3;
const RHO: f64 = 7850.0;
const WIDTH: f64 = 0.025;
const THICKNESS: f64 = 0.005;
const LENGTH: f64 = 1.15;

/// The paper's strip in torsion, clamped-free, as the modal method takes it.
fn strip() -> modal::Torsion {
    let (j, _) = modal::rectangle_torsion(WIDTH, THICKNESS);
    let polar = (WIDTH * THICKNESS.powi(3) + THICKNESS * WIDTH.powi(3)) / 12.0;
    modal::Torsion::new(
        E / (2.0 * (1.0 + NU)) * j,
        RHO * polar,
        LENGTH,
        modal::Support::ClampedFree,
    )
    .unwrap()
}

/// The first three torsion frequencies (rad/s) of the 3D Simo beam (the modes whose shape
/// lies mostly in the rotation about the axis), clamped at x = 0, on `elements` elements.
fn fe_torsion(elements: usize) -> Vec<f64> {
    let steel = Material::new(E, NU, RHO).unwrap();
    let section = Section::rectangle(&steel, WIDTH, THICKNESS).unwrap();
    let mesh = Mesh::straight(
        Vector3::zeros(),
        Vector3::new(LENGTH, 0.0, 0.0),
        elements,
        section,
        Vector3::z(),
    )
    .unwrap();
    let model = BeamModel::new(mesh).unwrap().support(0, Support::Clamped).unwrap();
    let mut out = Vec::new();
    for mode in natural_modes(&model, 6 * elements).unwrap() {
        let (mut twist, mut total) = (0.0, 0.0);
        for node in 0..=elements {
            for k in 0..6 {
                if let Some(i) = model.dof(node, k) {
                    let s = mode.shape[i] * mode.shape[i];
                    total += s;
                    if k == 3 {
                        twist += s;
                    }
                }
            }
        }
        if twist > 0.9 * total {
            out.push(mode.omega);
        }
        if out.len() == 3 {
            break;
        }
    }
    out
}

#[test]
fn torsion_frequencies_meet_the_3d_beam() {
    // omega_n = (n - 1/2) pi c_t / L for the clamped-free strip (1570, 4710, 7850 rad/s). The
    // 3D beam's two-node elements (lumped rotary inertia) are low by about (k h)^2 / 24,
    // second order: the error must shrink about fourfold from 32 to 64 elements and be within
    // 1e-3 at 64 (its torsion constant, Roark's formula, is within 1e-4 of the exact series).
    let analytic: Vec<f64> = strip().modes(3).iter().map(|m| m.omega).collect();
    let (coarse, fine) = (fe_torsion(32), fe_torsion(64));
    for n in 0..3 {
        let (ec, ef) = ((coarse[n] / analytic[n] - 1.0).abs(), (fine[n] / analytic[n] - 1.0).abs());
        assert!(ef < 1e-3, "mode {n}: {} vs {}", fine[n], analytic[n]);
        if n > 0 {
            // (Mode 1's error is at the torsion constant's scale, where no order shows.)
            assert!((2.5..5.5).contains(&(ec / ef)), "mode {n}: {ec:e} -> {ef:e}");
        }
    }
}

/// The paper's beam struck at x = 1.1 m, `offset` m off the centreline (gravity off, 0.2 ms).
fn tip(offset: &str, solver: &str) -> Result<Scene, impact::ImpactError> {
    struck(1.1, offset, &format!("end_time = 0.0002\n{solver}"))
}

/// The paper's beam and ball (0.2 m, gravity off) struck at `position` (m), `offset` (m) off
/// the centreline, with the `[solver]` lines `solver`.
fn struck(position: f64, offset: &str, solver: &str) -> Result<Scene, impact::ImpactError> {
    Scene::from_toml(&text(position, offset, solver))
}

/// The scene file of [`struck`].
fn text(position: f64, offset: &str, solver: &str) -> String {
    format!(
        r#"
name = "tip-offset"
[beam]
length = {LENGTH}
width = {WIDTH}
thickness = {THICKNESS}
support = "clamped-free"
youngs_modulus = {E}
poisson_ratio = {NU}
density = {RHO}
[ball]
radius = 0.005
mass = 0.009
youngs_modulus = {E}
poisson_ratio = {NU}
density = {RHO}
[impact]
position = {position}
offset = {offset}
drop_height = 0.2
gravity = false
[solver]
{solver}
"#
    )
}

#[test]
fn the_struck_face_is_as_stiff_as_bending_and_twist_in_series() {
    // A static force F at (c, e) on a cantilever: the face moves F (c^3 / (3 EI) + e^2 c / GJ).
    let scene =
        tip("0.01", "method = \"modal\"\nmodes = 64\nbeam_theory = \"euler-bernoulli\"").unwrap();
    let report = simulate(&scene).unwrap().report;
    let ei = E * WIDTH * THICKNESS.powi(3) / 12.0;
    let c: f64 = 1.1;
    let flexibility = c.powi(3) / (3.0 * ei) + 0.01f64.powi(2) * c / strip().rigidity();
    let k = report.static_stiffness.unwrap();
    assert!((k * flexibility - 1.0).abs() < 1e-12, "{k} vs {}", 1.0 / flexibility);
    let twist = report.max_twist.unwrap();
    assert!(twist > 0.0 && report.max_twist_time.unwrap() <= 0.0002, "{twist}");
    assert!(report.plan.reasons.iter().any(|r| r.contains("Saint-Venant torsion modes")));
    // A centred strike reports no twist.
    let centred = simulate(&tip("0.0", "method = \"modal\"\nmodes = 64").unwrap()).unwrap();
    assert_eq!(centred.report.max_twist, None);
}

#[test]
fn an_offset_off_the_face_or_on_a_planar_beam_is_refused() {
    for bad in ["0.0126", "-0.013", "nan"] {
        let err = Plan::new(&tip(bad, "").unwrap()).unwrap_err().to_string();
        assert!(
            err.contains("impact.offset") && err.contains("-0.0125 <= offset <= 0.0125"),
            "{bad}: {err}"
        );
    }
    let planar = "method = \"fe\"\nfe_model = \"planar\"";
    let err = Plan::new(&tip("0.01", planar).unwrap()).unwrap_err().to_string();
    assert!(err.contains("impact.offset") && err.contains("fe_model = \"3d\""), "{err}");
    let err = Plan::new(&tip("0.01", "method = \"modal\"\nfe_model = \"3d\"").unwrap())
        .unwrap_err()
        .to_string();
    assert!(err.contains("fe_model belong"), "{err}");

    let half_space = std::fs::read_to_string(format!(
        "{}/../../validation/scenes/half-space-r10.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
    .replace("[impact]", "[impact]\noffset = 0.001");
    let err = Plan::new(&Scene::from_toml(&half_space).unwrap()).unwrap_err().to_string();
    assert!(err.contains("impact.offset") && err.contains("[half_space]"), "{err}");
    // The patch (radius ~0.37 mm) past the edge: allowed, with a warning giving the ratio.
    let plan = Plan::new(&tip("0.0123", "").unwrap()).unwrap();
    assert!(
        plan.warnings().iter().any(|w| w.contains("past the face's edge")),
        "{:?}",
        plan.warnings()
    );
    // Within its own radius of the edge (the rim at 0.99 of the half-size): warned too (it had
    // been passed without a word, a review's); two radii inside (10 mm off): nothing said.
    let near = |offset: &str| {
        Plan::new(&tip(offset, "").unwrap())
            .unwrap()
            .warnings()
            .iter()
            .any(|w| w.contains("within its own radius of the face's edge"))
    };
    assert!(near("0.012") && !near("0.01"));
}

/// The converged row (most modes, residual flexibility) of `case` in
/// validation/reference/offcentre_tip.csv: (peak force (N), duration (s), impulse (N s)).
fn reference(case: &str) -> (f64, f64, f64) {
    // Compiled in: no file to read at run time (a missing one fails the build, naming it).
    let text = include_str!("../../../validation/reference/offcentre_tip.csv");
    let rows: Vec<Vec<&str>> = text
        .lines()
        .filter(|l| !l.starts_with('#') && l.starts_with(case))
        .map(|l| l.split(',').collect())
        .filter(|r: &Vec<&str>| r[0] == case && r[5] == "1")
        .collect();
    let best = rows.iter().max_by_key(|r| r[3].parse::<usize>().unwrap()).unwrap();
    let f = |k: usize| best[k].parse::<f64>().unwrap();
    (f(6), f(7), f(8))
}

#[test]
fn an_off_centre_strike_meets_the_independent_bending_and_torsion_reference() {
    // validation/peers/offcentre_reference.py (scipy, DOP853 at rtol 1e-10, 800 bending and
    // 11083 torsion modes with the residual flexibility; converged to 6-8 digits,
    // validation/REFERENCES.md 1.9). The modal method at 256 bending modes (and the torsion
    // modes below the highest, 1132) with the residual flexibility, Euler-Bernoulli like the
    // reference: measured within 3e-6 in force and 1e-6 in duration and impulse in all four
    // cases; held to 1e-4, a fifth of the issue's 0.5 %. The tip's off-centre contact is long
    // (the ball rides the twisting tip for 0.83 ms at a few newtons), so its window is 1 ms.
    let mut force = std::collections::HashMap::new();
    for (case, position, offset, end) in [
        ("tip-offset10", 1.15, "0.01", 1e-3),
        ("tip-centred", 1.15, "0.0", 2e-4),
        ("x1.10-offset10", 1.10, "0.01", 2e-4),
        ("x1.10-centred", 1.10, "0.0", 2e-4),
    ] {
        let solver = format!(
            "end_time = {end}\nmethod = \"modal\"\nmodes = 256\nresidual_flexibility = true\nbeam_theory = \"euler-bernoulli\""
        );
        let report = simulate(&struck(position, offset, &solver).unwrap()).unwrap().report;
        let c = &report.contacts[0];
        let (peak, duration, impulse) = reference(case);
        let rel = |a: f64, b: f64| (a / b - 1.0).abs();
        assert!(c.complete, "{case}");
        assert!(rel(c.peak_force, peak) < 1e-4, "{case}: {} vs {peak}", c.peak_force);
        assert!(rel(c.duration, duration) < 1e-4, "{case}: {} vs {duration}", c.duration);
        assert!(rel(c.impulse, impulse) < 1e-4, "{case}: {} vs {impulse}", c.impulse);
        force.insert(case, c.peak_force);
    }
    // What the offset changes, as the reference says: 37 % less force at the tip, 32 % at 1.1 m.
    let ratio = |a: &str, b: &str| force[a] / force[b];
    let expected = |a: &str, b: &str| reference(a).0 / reference(b).0;
    for (a, b) in [("tip-offset10", "tip-centred"), ("x1.10-offset10", "x1.10-centred")] {
        assert!((ratio(a, b) / expected(a, b) - 1.0).abs() < 1e-4, "{a}/{b}: {}", ratio(a, b));
    }
}

#[test]
fn the_default_modal_run_off_the_centre_takes_the_residual_flexibility() {
    // Struck 10 mm off the centre line at 1.10 m, the modes the plan chooses (93 below
    // omega t_c = 20) and nothing else asked: the torsion modes' static share, which falls as
    // 1/N, is then the residual flexibility's by default. Against the independent reference
    // (validation/peers/offcentre_reference.py): before, 874.75 N and 45.620 us, 2.6 % and
    // 2.1 % off; now 852.34 N and 46.610 us, measured 7e-4 and 2e-4 off, held to 2e-3.
    let report = simulate(
        &struck(
            1.10,
            "0.01",
            "end_time = 0.0002\nmethod = \"modal\"\nbeam_theory = \"euler-bernoulli\"",
        )
        .unwrap(),
    )
    .unwrap()
    .report;
    assert!(report
        .plan
        .reasons
        .iter()
        .any(|r| r.starts_with("residual flexibility (the default off the centreline)")));
    let c = &report.contacts[0];
    let (peak, duration, impulse) = reference("x1.10-offset10");
    let rel = |a: f64, b: f64| (a / b - 1.0).abs();
    assert!(rel(c.peak_force, peak) < 2e-3, "{} vs {peak}", c.peak_force);
    assert!(rel(c.duration, duration) < 2e-3, "{} vs {duration}", c.duration);
    assert!(rel(c.impulse, impulse) < 2e-3, "{} vs {impulse}", c.impulse);
}

#[test]
fn a_pinned_end_holds_the_twist_on_the_3d_beam_as_in_the_torsion_modes() {
    // A pinned [beam] end is a fork in 3D (its twist held, as the torsion modes take it): a
    // bare pin had left the strip free to spin about its axis, and struck off the centre line
    // the fe method's twist grew without bound (4.9e-3 rad at the support after 2 ms, the
    // modes' 4.6e-4). A 0.5 m pinned-pinned strip struck 10 mm off at 0.3 m: the struck
    // section's twist over 0.1 ms, fe 4.643e-4 against the modes' 4.620e-4 rad (0.5 %, the
    // fe mesh's; held to 1 %), and over 2 ms no twist anywhere past 1e-3 rad.
    let text = |method: &str, end: &str| {
        format!(
            "name = \"pp\"\n[beam]\nlength = 0.5\nwidth = 0.025\nthickness = 0.005\nsupport = \"pinned-pinned\"\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n[ball]\nradius = 0.005\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n[impact]\nposition = 0.3\noffset = 0.01\nspeed = 1.0\ngravity = false\n[solver]\nmethod = \"{method}\"\nend_time = {end}\n"
        )
    };
    let run = |method: &str, end: &str| {
        simulate(&Scene::from_toml(&text(method, end)).unwrap()).unwrap().report
    };
    let (fe, modal) = (run("fe", "1e-4"), run("modal", "1e-4"));
    let (tf, tm) = (fe.max_twist.unwrap(), modal.max_twist.unwrap());
    assert!((tf / tm - 1.0).abs() < 1e-2, "{tf} vs {tm}");
    let long = run("fe", "2e-3").largest_twist.unwrap();
    assert!(long.max < 1e-3, "{long:?}");
}

#[test]
fn every_support_takes_an_off_centre_strike_with_its_ledger_closed() {
    // Each support's torsion ends (a free-free strip has a rigid twist mode, which comes first
    // with the rigid bending modes): the energy ledger closes as on a centred strike (the
    // adaptive step's 1e-6 of the impact energy per contact), and the twist is finite.
    for support in
        ["clamped-free", "pinned-pinned", "clamped-clamped", "clamped-pinned", "free-free"]
    {
        let scene = text(1.1, "0.01", "end_time = 0.0002\nmethod = \"modal\"\nmodes = 64")
            .replace("support = \"clamped-free\"", &format!("support = \"{support}\""));
        let report = simulate(&Scene::from_toml(&scene).unwrap()).unwrap().report;
        let e = &report.energy;
        assert!((e.balance_error / e.initial).abs() < 1e-6, "{support}: {e:?}");
        let twist = report.max_twist.unwrap();
        assert!(twist.is_finite() && twist > 0.0, "{support}: {twist}");
        assert!(report.contacts[0].peak_force.is_finite(), "{support}");
    }
}

#[test]
fn a_centred_strike_on_the_3d_beam_is_the_planar_one() {
    // The paper's tip (gravity off) on the same graded mesh (1 mm at the tip), forced into 3D:
    // nothing leaves the plane, so the 3D rod (6 unknowns a node, automatic derivatives,
    // quaternions) must give the planar rod's contacts. Measured at 256 uniform elements over
    // 1 ms: all 9 contacts within 1.1e-5 (peak, start, duration); here over 0.4 ms, within 1e-4.
    let solver = |model: &str| {
        format!("end_time = 0.0004\nmethod = \"fe\"\nelement_size = 1e-3\nfe_model = \"{model}\"")
    };
    let planar = simulate(&struck(1.15, "0.0", &solver("planar")).unwrap()).unwrap().report;
    let solid = simulate(&struck(1.15, "0.0", &solver("3d")).unwrap()).unwrap().report;
    assert!(solid.plan.reasons.iter().any(|r| r.contains("3D geometrically exact beam")));
    let d = solid.differences_from(&planar);
    assert!(d.same_contacts && d.worst() < 1e-4, "{d:?}");
    assert!(solid.max_twist.unwrap() < 1e-12, "{:?}", solid.max_twist);
    let e = &solid.energy;
    assert!((e.balance_error / e.initial).abs() < 1e-4, "{e:?}");
}

#[test]
fn an_off_centre_strike_on_the_3d_beam_meets_the_reference() {
    // The tip struck 10 mm off the centreline by the fe method (3D by default off the
    // centreline), graded mesh of 1 mm at the tip, over the pulse's peak (12.4 us): the peak
    // force against the independent bending + torsion reference (491.921 N; Euler-Bernoulli,
    // Saint-Venant): measured 493.22 N (+0.26 %, as the centred strike's 783.02 against
    // 781.67: shear and the mesh); the issue's bound is 2 %. At 256 uniform elements (4.5 mm)
    // it is 481.27 N (-2.2 %), at 512 490.68 N (-0.25 %): the torsion needs the finer mesh.
    let solver = "end_time = 0.00003\nmethod = \"fe\"\nelement_size = 1e-3";
    let report = simulate(&struck(1.15, "0.01", solver).unwrap()).unwrap().report;
    assert!(report.plan.reasons.iter().any(|r| r.contains("the contact force twists the beam")));
    let (peak, _, _) = reference("tip-offset10");
    let got = report.contacts[0].peak_force;
    assert!((got / peak - 1.0).abs() < 0.005, "{got} vs {peak}");
    // The twist, at the accepted steps, against the modal method's (searched between
    // instants) over the same window: the same torsion, to the mesh's error.
    let modal = simulate(
        &struck(
            1.15,
            "0.01",
            "end_time = 0.00003\nmethod = \"modal\"\nresidual_flexibility = true",
        )
        .unwrap(),
    )
    .unwrap()
    .report;
    let (fe_twist, modal_twist) = (report.max_twist.unwrap(), modal.max_twist.unwrap());
    assert!((fe_twist / modal_twist - 1.0).abs() < 0.02, "{fe_twist} vs {modal_twist}");
    let e = &report.energy;
    assert!((e.balance_error / e.initial).abs() < 1e-4, "{e:?}");
}

#[test]
fn a_twist_held_by_a_rotary_inertia_gives_the_centred_force() {
    // A rotary inertia of 1e3 kg m^2 about the axis at the tip (no mass): the struck section
    // cannot turn during the pulse, so 10 mm off the centreline the ball meets what it meets
    // on the centreline: the 3D beam's centred peak (783.02 N on this mesh) within 0.2 %,
    // where the free tip gives 493.2 N. A spring at the impact point on the 3D beam adds its
    // stiffness to the face's static stiffness, as on the planar beam.
    let solver = "end_time = 0.00003\nmethod = \"fe\"\nelement_size = 1e-3\nfe_model = \"3d\"";
    let mut held = struck(1.15, "0.01", solver).unwrap();
    held.beam.as_mut().unwrap().masses.push(impact::MassSpec {
        at: 1.15,
        mass: 0.0,
        rotary_inertia: Some(impact::RotaryInertia::Axis(1e3)),
    });
    let held = simulate(&held).unwrap().report;
    let centred = simulate(&struck(1.15, "0.0", solver).unwrap()).unwrap().report;
    let (a, b) = (held.contacts[0].peak_force, centred.contacts[0].peak_force);
    assert!((a / b - 1.0).abs() < 2e-3, "{a} vs {b}");
    assert!(held.max_twist.unwrap() < 1e-6, "{:?}", held.max_twist);
    let e = &held.energy;
    assert!((e.balance_error / e.initial).abs() < 1e-4, "{e:?}");
    // On 512 equal elements, where the fe beam's static flexibility is within 1e-5 of the
    // analytic one (the one-point element's 1/(4 n^2)). The spring holds the tip's z, not its
    // twist: it stiffens the bending part only, f = 1/(k_b + k) + e^2 L/GJ.
    let solver = "end_time = 0.000002\nmethod = \"fe\"\nelements = 512\nfe_model = \"3d\"";
    let k = 2000.0;
    let mut sprung = struck(1.15, "0.01", solver).unwrap();
    sprung.beam.as_mut().unwrap().springs.push(impact::SpringSpec {
        at: 1.15,
        stiffness: k,
        rotational_stiffness: None,
    });
    let sprung = simulate(&sprung).unwrap().report;
    let free = simulate(&struck(1.15, "0.01", solver).unwrap()).unwrap().report;
    let (ks, kf) = (sprung.static_stiffness.unwrap(), free.static_stiffness.unwrap());
    // The free one is analytic (bending + e^2 twist, Timoshenko); the sprung one the fe beam's
    // static solve of the face.
    let twist = 0.01f64.powi(2) * LENGTH / strip().rigidity();
    let bending = 1.0 / kf - twist;
    let expected = 1.0 / (1.0 / (1.0 / bending + k) + twist);
    assert!((ks / expected - 1.0).abs() < 1e-4, "{ks} vs {expected}");
}

/// The paper's strip pinned at both ends (forked: the twist held), struck at 0.4 m 10 mm off
/// its centre line by the paper's ball (0.2 m, gravity off) over 2 ms, with `solver`.
fn pinned_strip(solver: &str) -> impact::Report {
    let text = format!(
        "name = \"pinned strip\"\n[beam]\nlength = 1.15\nwidth = 0.025\nthickness = 0.005\nsupport = \"pinned-pinned\"\n\
         youngs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
         [ball]\nradius = 0.005\nmass = 0.009\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
         [impact]\nposition = 0.4\noffset = 0.01\ndrop_height = 0.2\ngravity = false\n\
         [solver]\n{solver}\nend_time = 0.002\n"
    );
    simulate(&Scene::from_toml(&text).unwrap()).unwrap().report
}

#[test]
fn a_torsion_front_keeps_its_plateau_by_the_modes_and_overshoots_on_a_coarse_mesh_which_warns() {
    // Saint-Venant torsion does not disperse: the contact's torque impulse e J puts a twist
    // e J / (2 sqrt(G J rho Ip)) into the struck section, a plateau until the supports'
    // reflections (inverted: the forks hold the twist) come back, 0.68 and 1.28 ms later at
    // 1176 m/s; the struck section's twist never exceeds it in magnitude over 2 ms (the exact
    // wave solution by images, validation/REFERENCES.md 1.9). The modal method's analytic
    // torsion modes hold it: measured 1.6069e-3 against 1.6018e-3 rad (3e-3; 195 torsion
    // modes). The fe method's elements disperse the fronts, which overshoot: at 256 elements
    // the far support's reflection arrives 15 % over it (1.8367e-3 rad at 1.33 ms), and the
    // plan warns "about 21 %" (its estimate for a front that travelled the whole window, 2.35
    // m; the fit of TORSION_OVERSHOOT); at 1024 elements 2 % (measured 1.6335e-3 at the
    // window's end, a double step's 1 %), the plan's estimate 1.1 % (warned from 1 %).
    let plateau = |r: &impact::Report| {
        let (g, j) = (2.1e11 / 2.6, modal::rectangle_torsion(WIDTH, THICKNESS).0);
        let polar = (WIDTH * THICKNESS.powi(3) + THICKNESS * WIDTH.powi(3)) / 12.0;
        0.01 * r.contacts[0].impulse / (2.0 * (g * j * RHO * polar).sqrt())
    };
    let modal = pinned_strip("method = \"modal\"");
    let over = |r: &impact::Report| r.max_twist.unwrap() / plateau(r) - 1.0;
    assert!(
        over(&modal).abs() < 5e-3,
        "modal {} against {}",
        modal.max_twist.unwrap(),
        plateau(&modal)
    );
    let warned = |r: &impact::Report| r.warnings.iter().any(|w| w.contains("of a front's step"));
    let coarse = pinned_strip("method = \"fe\"\nelements = 256");
    assert!((0.10..0.20).contains(&over(&coarse)), "{}", over(&coarse));
    assert!(warned(&coarse), "{:?}", coarse.warnings);
    let fine = pinned_strip("method = \"fe\"\nelements = 1024");
    assert!(over(&fine).abs() < 0.025, "{}", over(&fine));
    let stated = fine.plan.reasons.iter().find(|r| r.contains("torsion fronts")).unwrap();
    assert!(stated.contains("by about 1.1 %"), "{stated}");
}

#[test]
fn the_torsion_shear_at_the_clamp_meets_the_exact_wave_solution_and_the_mesh_states_its_overshoot()
{
    // validation/scenes/paper-tip-offset.toml (the paper's tip 10 mm off, 1 ms): the tip's
    // torque e F(t) sends one twist wave (a free end reflects it upright, so it does not split)
    // that doubles on reaching the clamp at 1.15 m / 1176 m/s = 0.978 ms. Saint-Venant's
    // exact solution by images (validation/peers/twist_images.py --ends held-free --rate-at 0,
    // with the modal run's own force history) puts the clamp's largest shear at 53.9954 MPa at
    // 0.9900 ms (validation/REFERENCES.md 1.9). The modal method's analytic torsion modes:
    // measured 53.9994 MPa at 0.9901 ms (7e-5; tolerance 1e-3, the modes' truncation at a
    // front). The fe method on its default mesh (1.54 mm) measured 57.38 MPa, +6.3 % against the
    // exact solution with its own force (53.82 MPa at its element's midpoint): the elements
    // disperse the torque's sharp front. The plan's estimate (an upper one) must cover it; it
    // had stated 1.0 % for "the twist and the torsion shear" alike (the twist: 2.607e-3 rad
    // against the exact 2.610e-3, right).
    let path =
        format!("{}/../../validation/scenes/paper-tip-offset.toml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).unwrap();
    let modal = simulate(&Scene::from_toml(&text).unwrap()).unwrap().report;
    let shear = modal.torsion_shear.unwrap();
    assert!((shear.max / 53.9954e6 - 1.0).abs() < 1e-3, "{} Pa", shear.max);
    assert!(shear.position == 0.0 && (shear.time - 0.9900e-3).abs() < 2e-6, "{shear:?}");
    let fe = text
        .replace("method = \"modal\"", "method = \"fe\"")
        .replace("modes = 256\n", "")
        .replace("residual_flexibility = true\n", "")
        .replace("beam_theory = \"euler-bernoulli\"", "");
    let plan = Plan::new(&Scene::from_toml(&fe).unwrap()).unwrap();
    let stated = plan.summary().reasons.iter().find(|r| r.contains("torsion fronts")).unwrap();
    // The estimate there is at its cap (41 % before it): said as "30 % or more".
    assert!(stated.contains("moves the torsion shear by 30 % or more"), "{stated}");
    assert!(plan.warnings().iter().any(|w| w.contains("the torsion shear may be off")));
}

#[test]
fn a_free_free_strip_struck_off_centre_takes_its_own_modes() {
    // The paper's strip free at both ends, struck 10 mm off its centreline at 0.5 m (0.1 ms:
    // the first contact, 47 us, is over before its bending waves come back from the ends):
    // the uniform beam's analytic modes had no residual flexibility on the free body and read
    // the torque's jump at the struck section as its mean: 868.3 N and a torsion shear of
    // 6.0e4 Pa (a review's). By default it now takes its own modes (inertia relief), which
    // meet the same strike on the clamped-free strip (analytic modes with their residual
    // flexibility: 844.48 N, 1.6022e-3 rad) and the fe method's 3D beam (844.86 N, a torsion
    // shear of 2.349e7 Pa) within the beam theories' difference: measured 844.00 N (5.7e-4
    // and 1.0e-3 below), 1.6019e-3 rad (2e-4) and 2.335e7 Pa (6e-3).
    let text = |support: &str, solver: &str| {
        format!(
            "name = \"free\"\n[beam]\nlength = 1.15\nwidth = 0.025\nthickness = 0.005\nsupport = \"{support}\"\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n[ball]\nradius = 0.005\nmass = 0.009\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n[impact]\nposition = 0.5\noffset = 0.01\ndrop_height = 0.2\ngravity = false\n[solver]\nend_time = 0.0001\n{solver}"
        )
    };
    let run = |support: &str, solver: &str| {
        simulate(&Scene::from_toml(&text(support, solver)).unwrap()).unwrap().report
    };
    let free = run("free-free", "");
    assert!(free
        .plan
        .reasons
        .iter()
        .any(|r| r.contains("the default for a free-free beam struck off its centreline")));
    let clamped = run("clamped-free", "");
    let fe = run("free-free", "method = \"fe\"");
    let rel = |a: f64, b: f64| (a / b - 1.0).abs();
    let (f, c, e) = (&free.contacts[0], &clamped.contacts[0], &fe.contacts[0]);
    assert!(rel(f.peak_force, c.peak_force) < 2e-3, "{} vs {}", f.peak_force, c.peak_force);
    assert!(rel(f.peak_force, e.peak_force) < 2e-3, "{} vs {}", f.peak_force, e.peak_force);
    let (tf, tc) = (free.max_twist.unwrap(), clamped.max_twist.unwrap());
    assert!(rel(tf, tc) < 1e-3, "{tf} vs {tc}");
    let (sf, se) = (free.torsion_shear.unwrap().max, fe.torsion_shear.unwrap().max);
    assert!(rel(sf, se) < 3e-2, "{sf} vs {se}");
    // The analytic modes asked for: warned, with what they miss.
    let asked =
        Plan::new(&Scene::from_toml(&text("free-free", "modal_basis = \"analytic\"")).unwrap())
            .unwrap();
    assert!(asked
        .warnings()
        .iter()
        .any(|w| w.contains("carry no residual flexibility on a free body")));
}
