//! Goldsmith's method on a finite-element basis (a `[structure]` by `solver.method = "modal"`):
//! against the analytic basis on the paper's uniform cantilever, centred and off the centre
//! line, and against the fe method on the frame (validation/REFERENCES.md 1.13).
#![allow(clippy::unwrap_used)] // a test stops on a bad fixture

use impact::{simulate, Plan, Report, Scene};

/// The paper's cantilever (L = 1.15 m, 25 x 5 mm, clamped at x = 0) struck at 1.10 m by the
/// paper's ball (0.2 m drop, gravity off) over the first contact, `offset` (m) off the centre
/// line: as a uniform `[beam]` on its analytic Timoshenko modes, with the residual flexibility,
/// and as a one-segment `[structure]` of `elements` on its own modes.
fn cantilever(structure: Option<usize>, offset: f64) -> Report {
    let struck = match structure {
        Some(elements) => format!(
            "[structure.section]\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\nwidth = 0.025\nthickness = 0.005\n\
             [[structure.segment]]\nstart = [0.0, 0.0, 0.0]\nend = [1.15, 0.0, 0.0]\nelements = {elements}\n\
             [[structure.support]]\nat = 0.0\nkind = \"clamped\"\n\
             [impact]\nat = 1.10\ndirection = [0.0, 0.0, -1.0]\n"
        ),
        None => "[beam]\nlength = 1.15\nwidth = 0.025\nthickness = 0.005\nsupport = \"clamped-free\"\n\
                 youngs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
                 [impact]\nposition = 1.10\n"
            .to_string(),
    };
    let solver = match structure {
        Some(_) => "",
        None => "beam_theory = \"timoshenko\"\nresidual_flexibility = true\nmodes = 256\n",
    };
    let text = format!(
        "name = \"cantilever\"\n{struck}drop_height = 0.2\ngravity = false\noffset = {offset}\n\
         [ball]\nradius = 0.005\nmass = 0.009\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
         [solver]\nmethod = \"modal\"\nend_time = 1e-4\n{solver}"
    );
    simulate(&Scene::from_toml(&text).unwrap()).unwrap().report
}

/// The relative difference of `a` from `b`.
fn off(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

#[test]
fn the_fe_basis_gives_the_analytic_basis_first_contact_on_the_uniform_cantilever() {
    // The analytic basis at 256 Timoshenko modes with its residual flexibility is converged
    // to 1e-5 (512 and 1024 modes: the same digits). Measured, centred, at 368 elements (384
    // modes below omega t_c = 20): the duration 39.835 against 39.856 us (5.3e-4), the peak
    // force 1234.56 against 1233.77 N (6.4e-4); the difference is the mesh's, second order (at
    // 184 elements 3.2e-3 and 2.7e-3). Struck 10 mm off the centre line the torsion modes join
    // both bases and the mesh converges more slowly: the peak 842.23, 843.70, 844.21 N at 368,
    // 736, 1472 elements against 845.30 (3.7e-3, 1.9e-3, 1.3e-3), the duration 46.98 against
    // 46.97 us, toward a limit about 1e-3 below the analytic one (the fe section's torsion
    // constant is Roark's, 7e-4 below the exact series the analytic torsion takes). The
    // issue's bound, 2e-3, at 736 elements off the centre line.
    for (offset, elements) in [(0.0, 368), (0.01, 736)] {
        let analytic = cantilever(None, offset);
        let fe = cantilever(Some(elements), offset);
        let (a, f) = (&analytic.contacts[0], &fe.contacts[0]);
        assert!(off(f.duration, a.duration) < 2e-3, "{offset}: {} vs {}", f.duration, a.duration);
        assert!(
            off(f.peak_force, a.peak_force) < 2e-3,
            "{offset}: {} vs {}",
            f.peak_force,
            a.peak_force
        );
        // The ball leaves at a small share of its speed off the centre line (0.24 of 1.98 m/s):
        // its difference against the impact speed (measured 5.5e-4 of it).
        let rebound = (f.ball_velocity_after - a.ball_velocity_after).abs();
        assert!(rebound < 2e-3 * fe.impact_speed, "{offset}: rebound {rebound} m/s apart");
        // The structure's static solve is the beam's static flexibility (the one-point element
        // 1/(4 n^2) off, 2e-6; Timoshenko's shear in both; Roark's J off the centre line).
        let (ka, kf) = (analytic.static_stiffness.unwrap(), fe.static_stiffness.unwrap());
        assert!(off(kf, ka) < 1e-4, "{offset}: static stiffness {kf} vs {ka}");
        assert!(fe.energy.balance_error.abs() < 1e-6 * fe.energy.initial, "{:?}", fe.energy);
    }
}

/// validation/scenes/frame-impact.toml's text.
fn frame_text() -> String {
    std::fs::read_to_string(format!(
        "{}/../../validation/scenes/frame-impact.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
}

/// validation/scenes/frame-impact.toml by `method`.
fn frame(method: &str) -> Report {
    frame_of(method, 40)
}

/// validation/scenes/frame-impact.toml by `method` on `elements` a member.
fn frame_of(method: &str, elements: usize) -> Report {
    let text = frame_text()
        .replace("method = \"fe\"", &format!("method = \"{method}\""))
        .replace("elements = 40", &format!("elements = {elements}"));
    simulate(&Scene::from_toml(&text).unwrap()).unwrap().report
}

#[test]
fn the_frame_by_its_modes_is_the_frame_by_the_fe_method() {
    // The frame (two 0.5 m members at a right angle, 40 elements each, clamped at one end)
    // struck out of its plane on the free member, over 2 ms, both methods on the same mesh:
    // measured 39.634 against 39.640 us, 1245.96 against 1245.92 N, the largest displacement at
    // the impact point 2.2550e-4 against 2.2551e-4 m, the largest twist of the clamped member
    // 2.6161e-3 against 2.6164e-3 rad. What differs is the fe method's time integration
    // (HHT-alpha, steps of the contact's hundredth) against exact propagation: bounds 1e-3 on
    // the contact and the displacement (the 1.5 % and 3 % are for each method at its
    // own tolerance), 2e-3 on the twist and the stresses (read at instants, not searched).
    let modal = frame("modal");
    let fe = frame("fe");
    assert_eq!(modal.contacts.len(), fe.contacts.len());
    let (m, f) = (&modal.contacts[0], &fe.contacts[0]);
    assert!(off(m.duration, f.duration) < 1e-3, "{} vs {}", m.duration, f.duration);
    assert!(off(m.peak_force, f.peak_force) < 1e-3, "{} vs {}", m.peak_force, f.peak_force);
    let (dm, df) = (modal.max_displacement, fe.max_displacement);
    assert!(off(dm, df) < 1e-3, "{dm} vs {df}");
    let (tm, tf) = (modal.largest_twist.unwrap(), fe.largest_twist.unwrap());
    assert!(
        off(tm.max, tf.max) < 2e-3 && (tm.position - tf.position).abs() < 1e-12,
        "{tm:?} vs {tf:?}"
    );
    // The stress is the section's worst corner, so the fe method's geometrically exact axial
    // stress (membrane strain the linear modes do not have) adds in full: 45.810 against
    // 45.715 MPa at the impact point (45.787 on the struck face alone): 2.5e-3 on it.
    let (sm, sf) = (modal.bending_stress.unwrap(), fe.bending_stress.unwrap());
    assert!(
        off(sm.max, sf.max) < 2.5e-3 && (sm.position - sf.position).abs() < 1e-12,
        "{sm:?} vs {sf:?}"
    );
    // The clamp's stress, each method's (it had listed no support: 1.63835e7 and 1.63797e7 Pa
    // now).
    let (cm, cf) = (&sm.supports, &sf.supports);
    assert!(cm.len() == 1 && cf.len() == 1 && cm[0].position == 0.0, "{cm:?} vs {cf:?}");
    assert!(off(cm[0].max, cf[0].max) < 2e-3, "{cm:?} vs {cf:?}");
    let (hm, hf) = (modal.torsion_shear.unwrap(), fe.torsion_shear.unwrap());
    assert!(off(hm.max, hf.max) < 2e-3, "{hm:?} vs {hf:?}");
    assert!(modal.energy.balance_error.abs() < 1e-6 * modal.energy.initial);
    assert_eq!(modal.plan.elements, 80);
    // 240 modes below the cutoff, of which the 145 out of the frame's plane move the struck
    // face: its in-plane unknowns are held (240 of 480 kept), exactly (the unit tests in
    // solve/fe_basis.rs compare the held and the whole model).
    assert_eq!(modal.plan.modes, 145);
    assert!(
        modal
            .plan
            .reasons
            .iter()
            .any(|r| r.contains("a planar structure struck normal to its plane")
                && r.contains("240 of 480")),
        "{:?}",
        modal.plan.reasons
    );
}

#[test]
fn the_twist_at_a_corner_is_read_about_each_member_s_own_axis() {
    // The frame's second member in two elements and clamped at its far end too, struck on
    // the first member at s = 0.25 m: the first member's bending slope at the corner is the
    // second member's twist there (about its own axis, y), which falls to 0 at its clamp; it
    // is the largest twist anywhere. The corner node's own frame is the first member's, whose
    // reading there is the first member's twist, smaller: before the corner ends were read
    // on their own, both methods reported 1.717e-3 rad at s = 0.75 m. Measured: fe 2.88868e-3,
    // modal 2.88875e-3 rad at s = 0.5 m (2.3e-5 apart; 2e-3 as the frame's test above, the
    // twist read at instants).
    let text = frame_text()
        .replace("at = 0.9 ", "at = 0.25 ")
        .replace("end = [0.5, 0.5, 0.0]\nelements = 40", "end = [0.5, 0.5, 0.0]\nelements = 2")
        .replace(
            "kind = \"clamped\"",
            "kind = \"clamped\"\n[[structure.support]]\nat = 1.0\nkind = \"clamped\"",
        );
    let run = |method: &str| {
        let text = text.replace("method = \"fe\"", &format!("method = \"{method}\""));
        simulate(&Scene::from_toml(&text).unwrap()).unwrap().report
    };
    let (modal, fe) = (run("modal"), run("fe"));
    let (tm, tf) = (modal.largest_twist.unwrap(), fe.largest_twist.unwrap());
    for t in [tm, tf] {
        assert!((t.position - 0.5).abs() < 1e-12, "{t:?}");
    }
    assert!(off(tm.max, tf.max) < 2e-3, "{tm:?} vs {tf:?}");
    assert!(tf.max > 2.8e-3, "{tf:?}");
}

#[test]
fn a_beam_left_a_mechanism_by_its_springs_is_refused_in_its_own_words() {
    // A free-free strip on two springs along z: its 3D beam keeps 4 rigid-body motions (along
    // x and y, about x and z), which the modal method would take linearised at rest. The
    // refusal had spoken of "structure.support: no support"; it names the [beam]'s keys.
    let text = "name = \"strip\"\n[beam]\nlength = 0.5\nwidth = 0.025\nthickness = 0.005\nsupport = \"free-free\"\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n[[beam.spring]]\nat = 0.0\nstiffness = 1e6\n[[beam.spring]]\nat = 0.5\nstiffness = 1e6\n[ball]\nradius = 0.005\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n[impact]\nposition = 0.4\nspeed = 1.0\ngravity = false\n[solver]\nmethod = \"modal\"\nend_time = 1e-4\n";
    let err = Plan::new(&Scene::from_toml(text).unwrap()).unwrap_err().to_string();
    assert!(
        err.starts_with("beam.support = \"free-free\" with its springs")
            && err.contains("4 rigid-body motion(s)")
            && !err.contains("structure"),
        "{err}"
    );
    let fe = text.replace("method = \"modal\"", "method = \"fe\"");
    assert!(Plan::new(&Scene::from_toml(&fe).unwrap()).is_ok());
}

#[test]
fn an_interior_support_of_a_structure_lists_its_stress() {
    // The frame pinned at its corner as well as clamped at its root, struck out of its plane
    // on the free member: the corner's stress is an interior support's, the larger of the
    // extrapolations from the midpoints on its two sides (a structure's interior supports had
    // listed none). Both methods list both supports; the corner's, measured 2.657e7 (fe) and
    // 2.672e7 Pa (modal), 5.7e-3 apart (the extrapolation doubles the midpoints' differences),
    // held to 1e-2. The root holds no bending: the pin takes the member's shear, the corner's
    // moment is the first member's torsion (its stress below 1e-3 of the corner's).
    let pinned = |method: &str| {
        let text = frame_text()
            .replace(
                "kind = \"clamped\"",
                "kind = \"clamped\"\n[[structure.support]]\nat = 0.5\nkind = \"pinned\"",
            )
            .replace("method = \"fe\"", &format!("method = \"{method}\""));
        simulate(&Scene::from_toml(&text).unwrap()).unwrap().report.bending_stress.unwrap()
    };
    let (modal, fe) = (pinned("modal"), pinned("fe"));
    for s in [&modal, &fe] {
        assert_eq!(s.supports.len(), 2, "{s:?}");
        assert!((s.supports[1].position - 0.5).abs() < 1e-12, "{s:?}");
        assert!(s.supports[0].max < 1e-3 * s.supports[1].max, "{s:?}");
    }
    let (m, f) = (modal.supports[1].max, fe.supports[1].max);
    assert!(off(m, f) < 1e-2, "{m} vs {f}");
}

#[test]
fn a_frame_forked_at_both_ends_is_held_where_pinned_ends_leave_a_mechanism() {
    // The frame held at both ends of its chain (s = 0 and 1 m), struck at its corner's second
    // member 0.25 m along: pinned (a ball joint) at both ends it turns freely about the line
    // through the two pins, a mechanism the modal method refuses; forked (position and twist
    // about the member's axis held) each end's fork holds that line's component along its
    // member, so the frame is held and both methods run it. Measured over 0.5 ms: the first
    // contact 1246.17 (modal) against 1245.92 N (fe), 39.620 against 39.626 us, the largest
    // displacement at the impact point 8.8287e-5 against 8.8291e-5 m; the two meshes are the
    // same 40-element members and the bases the same elements, bounds 1e-3.
    let frame = |kind: &str, method: &str| {
        let text = frame_text()
            .replace(
                "kind = \"clamped\"",
                &format!("kind = \"{kind}\"\n[[structure.support]]\nat = 1.0\nkind = \"{kind}\""),
            )
            .replace("at = 0.9 ", "at = 0.75 ")
            .replace("end_time = 0.002", "end_time = 0.0005")
            .replace("method = \"fe\"", &format!("method = \"{method}\""));
        Scene::from_toml(&text).unwrap()
    };
    let err = Plan::new(&frame("pinned", "modal")).unwrap_err().to_string();
    assert!(
        err.contains("mechanism")
            && err.contains("1 rigid-body motion(s)")
            && err.contains("a forked support"),
        "{err}"
    );
    let (modal, fe) = (frame("forked", "modal"), frame("forked", "fe"));
    let (modal, fe) = (simulate(&modal).unwrap().report, simulate(&fe).unwrap().report);
    assert!(!fe.warnings.iter().any(|w| w.contains("mechanism")), "{:?}", fe.warnings);
    let (m, f) = (&modal.contacts[0], &fe.contacts[0]);
    assert!(off(m.peak_force, f.peak_force) < 1e-3, "{} vs {}", m.peak_force, f.peak_force);
    assert!(off(m.duration, f.duration) < 1e-3, "{} vs {}", m.duration, f.duration);
    let (dm, df) = (modal.max_displacement, fe.max_displacement);
    assert!(off(dm, df) < 1e-3, "{dm} vs {df}");
}

#[test]
fn a_beam_carrying_a_mass_and_a_spring_runs_by_its_own_modes() {
    // The paper's cantilever with a 20 g sensor at 0.9 m and a 2000 N/m spring at 0.5 m,
    // struck at 1.10 m, 5 mm off the centre line: by the modal method the [beam] is lowered to
    // the [structure] it is (748 elements of at most a sixteenth of the bending wave at the
    // cutoff, a node at each attachment and at the ball; 259 modes below omega t_c = 20) and
    // against the fe method's 3D beam at 736 equal elements. Measured over 2 ms: 41.188
    // against 41.206 us, 1107.29 against 1107.21 N (8e-5), the largest displacement at the
    // impact point 3.6453e-4 against 3.6458e-4 m (1.4e-4), the twist of the struck section
    // 1.9409e-3 against 1.9403e-3 rad. Over the first contact here, bounds 2e-3 (the two
    // meshes differ; each is second order).
    let text = |method: &str| {
        format!(
            "name = \"sensor\"\n[beam]\nlength = 1.15\nwidth = 0.025\nthickness = 0.005\nsupport = \"clamped-free\"\n\
             youngs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
             [[beam.mass]]\nat = 0.9\nmass = 0.02\n[[beam.spring]]\nat = 0.5\nstiffness = 2000.0\n\
             [ball]\nradius = 0.005\nmass = 0.009\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
             [impact]\nposition = 1.10\ndrop_height = 0.2\ngravity = false\noffset = 0.005\n\
             [solver]\nend_time = 1e-4\n{method}"
        )
    };
    let run = |method: &str| simulate(&Scene::from_toml(&text(method)).unwrap()).unwrap().report;
    let modal = run("method = \"modal\"");
    let fe = run("method = \"fe\"\nfe_model = \"3d\"\nelements = 736");
    assert!(modal.plan.reasons.iter().any(|r| r.contains(
        "modes from the beam's finite elements (solver.modal_basis = \"fe\", the default here)"
    )));
    let (m, f) = (&modal.contacts[0], &fe.contacts[0]);
    assert!(off(m.duration, f.duration) < 2e-3, "{} vs {}", m.duration, f.duration);
    assert!(off(m.peak_force, f.peak_force) < 2e-3, "{} vs {}", m.peak_force, f.peak_force);
    // The struck section's twist is still growing at the window's end (its peak is at 126 us):
    // a value at one instant, 8.5e-4 apart (over 2 ms, at its peak, 3.2e-4).
    let (tm, tf) = (modal.max_twist.unwrap(), fe.max_twist.unwrap());
    assert!(off(tm, tf) < 5e-3, "{tm} vs {tf}");
    // Its static stiffness is the carried beam's own static solve (the spring included).
    let (km, kf) = (modal.static_stiffness.unwrap(), fe.static_stiffness.unwrap());
    assert!(off(km, kf) < 1e-4, "{km} vs {kf}");
    // With a rotational spring too (about the width axis, against the bending rotation): the
    // fe basis carries it as the fe method's 3D beam does, the same bounds.
    let sprung = |method: &str| {
        let text = text(method)
            .replace("stiffness = 2000.0", "stiffness = 2000.0\nrotational_stiffness = 20.0");
        simulate(&Scene::from_toml(&text).unwrap()).unwrap().report
    };
    let (modal_r, fe_r) = (
        sprung("method = \"modal\""),
        sprung("method = \"fe\"\nfe_model = \"3d\"\nelements = 736"),
    );
    let (m, f) = (&modal_r.contacts[0], &fe_r.contacts[0]);
    assert!(off(m.duration, f.duration) < 2e-3, "{} vs {}", m.duration, f.duration);
    assert!(off(m.peak_force, f.peak_force) < 2e-3, "{} vs {}", m.peak_force, f.peak_force);
    let (km_r, kf_r) = (modal_r.static_stiffness.unwrap(), fe_r.static_stiffness.unwrap());
    assert!(off(km_r, kf_r) < 1e-4, "{km_r} vs {kf_r}");
    // The spring stiffens the struck point (it holds the section at 0.5 m of the 1.10 m arm).
    assert!(km_r > km * (1.0 + 1e-3), "{km_r} vs {km}");
}

#[test]
fn a_rotational_spring_too_stiff_for_the_modes_is_refused_by_the_modal_method() {
    // The frame with a spring about all three axes at its free tip: at 1e16 N m/rad (9.1e10
    // times its elements' 1.09e5 at 40 a member) the modes lost their lowest to round-off (on
    // the review's frame of 16 a member, the largest displacement 48 % off the fe method's,
    // the struck section's twist 1.2e-4 rad against 3e-17), silently; refused now, naming the
    // key and the clamp that holds the node. The fe method runs it; 1e12 (9.1e6 times) runs
    // by the modes (the review: within 1e-5 of the fe method).
    let spring = |k: &str| {
        let tip = format!(
            "kind = \"clamped\"\n[[structure.spring]]\nat = 1.0\nstiffness = [0.0, 0.0, 0.0]\nrotational_stiffness = [{k}, {k}, {k}]"
        );
        frame_text()
            .replace("kind = \"clamped\"", &tip)
            .replace("method = \"fe\"", "method = \"modal\"")
            .replace("end_time = 0.002", "end_time = 0.0001")
    };
    let err = Plan::new(&Scene::from_toml(&spring("1e16")).unwrap()).unwrap_err().to_string();
    assert!(
        err.contains("structure.spring[0].rotational_stiffness = [1e16, 1e16, 1e16]")
            && err.contains("9.1e10 times")
            && err.contains("kind = \"clamped\""),
        "{err}"
    );
    let fe = spring("1e16").replace("method = \"modal\"", "method = \"fe\"");
    assert!(Plan::new(&Scene::from_toml(&fe).unwrap()).is_ok());
    assert!(Plan::new(&Scene::from_toml(&spring("1e12")).unwrap()).is_ok());
}

#[test]
fn solver_modal_basis_chooses_where_the_modes_come_from() {
    // The paper's uniform cantilever struck at 1.10 m: by default on its analytic modes; with
    // solver.modal_basis = "fe" lowered to the one-member structure it is (374 elements, a node
    // at the impact point; 383 modes below omega t_c = 20). Measured over the first contact,
    // centred: 39.8374 against 39.8660 us (7.2e-4) and 1234.49 against 1233.60 N (7.2e-4) for
    // the analytic basis at 256 Timoshenko modes with its residual flexibility; bound 2e-3 as
    // for the one-segment structure (the mesh's error, second order).
    let text = |solver: &str| {
        format!(
            "name = \"basis\"\n[beam]\nlength = 1.15\nwidth = 0.025\nthickness = 0.005\nsupport = \"clamped-free\"\n\
             youngs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
             [ball]\nradius = 0.005\nmass = 0.009\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
             [impact]\nposition = 1.10\ndrop_height = 0.2\ngravity = false\n\
             [solver]\nend_time = 6e-5\n{solver}"
        )
    };
    let plan = |solver: &str| impact::Plan::new(&Scene::from_toml(&text(solver)).unwrap());
    let says = |solver: &str, what: &str| {
        let p = plan(solver).unwrap();
        assert!(
            p.summary().reasons.iter().any(|r| r.contains(what)),
            "{solver}: {:?}",
            p.summary()
        );
    };
    says("method = \"modal\"", "modal_basis = \"analytic\", the default");
    says("method = \"modal\"\nmodal_basis = \"fe\"", "modal_basis = \"fe\", as asked");
    // A modal-only key under auto picks the modal method, saying so.
    says("modal_basis = \"fe\"", "method modal (auto): solver.modal_basis given");
    // Refused: with the fe method, and the analytic modes for a beam carrying a mass.
    let refused = |solver: &str, extra: &str, what: &str| {
        let text = text(solver).replace("[ball]", &format!("{extra}[ball]"));
        let err = impact::Plan::new(&Scene::from_toml(&text).unwrap()).unwrap_err().to_string();
        assert!(err.contains(what), "{solver}: {err}");
    };
    refused(
        "method = \"fe\"\nmodal_basis = \"fe\"",
        "",
        "solver.modal_basis belongs to method = \"modal\"",
    );
    refused("modal_basis = \"fe\"\nelements = 64", "", "belong to method = \"fe\"");
    refused(
        "method = \"modal\"\nmodal_basis = \"analytic\"",
        "[[beam.mass]]\nat = 0.9\nmass = 0.02\n",
        "solver.modal_basis = \"analytic\" with [[beam.mass]]",
    );
    let run = |solver: &str| simulate(&Scene::from_toml(&text(solver)).unwrap()).unwrap().report;
    let fe = run("method = \"modal\"\nmodal_basis = \"fe\"");
    let analytic = run("method = \"modal\"\nmodes = 256\nresidual_flexibility = true");
    let (f, a) = (&fe.contacts[0], &analytic.contacts[0]);
    assert!(off(f.duration, a.duration) < 2e-3, "{} vs {}", f.duration, a.duration);
    assert!(off(f.peak_force, a.peak_force) < 2e-3, "{} vs {}", f.peak_force, a.peak_force);
}

#[test]
fn a_free_frame_by_its_modes_with_inertia_relief_is_the_free_frame_by_the_fe_method() {
    // The frame with its clamp taken away: a free body (six rigid-body modes, counted when
    // planned). The modal method keeps the rigid modes among its own and the residual
    // flexibility by inertia relief (the load balanced by the rigid modes' inertia, solved
    // with one node clamped); measured over 2 ms against the fe method on the same mesh:
    // 39.6314 against 39.6404 us (2.3e-4), 1246.06 against 1245.92 N (1.1e-4), the largest
    // displacement at the impact point 2.13137e-4 against 2.13143e-4 m. A free body has no
    // static stiffness: none reported by either (before the count, a static solve of the
    // singular K reported 7e-8 N/m). Here over the first contact: bounds 1e-3 as for the held
    // frame.
    let text = |method: &str, support: &str| {
        frame_text()
            .replace("method = \"fe\"", &format!("method = \"{method}\""))
            .replace("end_time = 0.002", "end_time = 1e-4")
            .replace("[[structure.support]]\nat = 0.0\nkind = \"clamped\"\n", support)
    };
    let run =
        |method: &str| simulate(&Scene::from_toml(&text(method, "")).unwrap()).unwrap().report;
    let (modal, fe) = (run("modal"), run("fe"));
    let (m, f) = (&modal.contacts[0], &fe.contacts[0]);
    assert!(off(m.duration, f.duration) < 1e-3, "{} vs {}", m.duration, f.duration);
    assert!(off(m.peak_force, f.peak_force) < 1e-3, "{} vs {}", m.peak_force, f.peak_force);
    assert!(modal.plan.reasons.iter().any(|r| r.contains("by inertia relief")));
    assert_eq!((modal.static_stiffness, fe.static_stiffness), (None, None));
    assert!(modal.energy.balance_error.abs() < 1e-6 * modal.energy.initial);
    // One pin leaves three rotations free: a mechanism, refused by the modal method naming
    // the supports (the fe method runs it, and warns).
    let pinned = "[[structure.support]]\nat = 0.0\nkind = \"pinned\"\n";
    let err = impact::Plan::new(&Scene::from_toml(&text("modal", pinned)).unwrap())
        .unwrap_err()
        .to_string();
    assert!(err.contains("mechanism") && err.contains("pinned at s = 0 m"), "{err}");
    let fe_plan = impact::Plan::new(&Scene::from_toml(&text("fe", pinned)).unwrap()).unwrap();
    assert!(fe_plan.warnings().iter().any(|w| w.contains("leave 3 rigid-body")));
}

#[test]
fn a_mesh_too_coarse_for_the_cutoff_says_which_key_refines_it() {
    // The frame at 2 elements a member: its 12 modes out of the plane (9 move the face) end
    // at 1.95e5 rad/s, below the plan's cutoff (omega t_c = 20, 4.85e5 rad/s): every one is
    // kept and they reach omega_N t_c = 8.1 only. The warning counts the modes kept and names
    // the key that adds modes to an fe basis (its mesh), not solver.modes.
    let report = frame_of("modal", 2);
    let warning = report.warnings.iter().find(|w| w.contains("reach only")).unwrap();
    assert!(warning.starts_with("9 modes reach only omega_N t_c = 8.1"), "{warning}");
    assert!(warning.contains("structure.segment[k].elements"), "{warning}");
    assert!(!warning.contains("solver.modes"), "{warning}");
}

/// A portal (two 0.5 m columns clamped at their feet, a 0.6 m beam; the paper's strip) struck
/// at mid-beam, down, over 1 ms by its modes; `flip` turns the last column's thickness
/// direction around (the same structure).
fn portal(flip: bool) -> Report {
    let turn = if flip { "thickness_direction = [-1.0, 0.0, 0.0]\n" } else { "" };
    let text = format!(
        "name = \"portal\"\n[structure.section]\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\nwidth = 0.025\nthickness = 0.005\n\
         [[structure.segment]]\nstart = [0.0, 0.0, 0.0]\nend = [0.0, 0.0, 0.5]\nelements = 25\n\
         [[structure.segment]]\nend = [0.6, 0.0, 0.5]\nelements = 30\n\
         [[structure.segment]]\nend = [0.6, 0.0, 0.0]\nelements = 25\n{turn}\
         [[structure.support]]\nat = 0.0\nkind = \"clamped\"\n[[structure.support]]\nat = 1.6\nkind = \"clamped\"\n\
         [ball]\nradius = 0.005\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
         [impact]\nat = 0.8\ndirection = [0.0, 0.0, -1.0]\nspeed = 1.0\ngravity = false\n\
         [solver]\nmethod = \"modal\"\nend_time = 0.001\n"
    );
    simulate(&Scene::from_toml(&text).unwrap()).unwrap().report
}

#[test]
fn a_symmetric_portal_reads_the_same_stress_at_both_feet_whichever_way_its_faces_point() {
    // By symmetry the feet carry equal moments and axial forces, so their sections' worst
    // corners are equal. Each member's stress had been its struck face's (the face its
    // thickness direction names), and the supports' extrapolated from signed corner values
    // whose sign flips where the axial share outweighs the bending: 4.857 and 4.422 MPa at
    // this mesh (a review's finer mesh: 4.98 and 5.62, the same foot 5.62 or 4.98 with that
    // direction reversed). Now each part of the stress is extrapolated, then the worst corner
    // taken: 4.857 MPa at both feet, either way.
    let feet = |r: &Report| {
        let s = &r.bending_stress.as_ref().unwrap().supports;
        (s[0].max, s[1].max)
    };
    let (upright, flipped) = (portal(false), portal(true));
    let (a, b) = feet(&upright);
    let (c, d) = feet(&flipped);
    assert!(off(a, b) < 1e-9 && off(c, d) < 1e-9 && off(a, c) < 1e-9, "{a} {b} {c} {d}");
    assert!((a / 4.857e6 - 1.0).abs() < 1e-3, "{a}");
    // Struck in its own plane, the plane frame moves in it only: nothing twists (1.6e-14 rad
    // measured), so nothing is said of torsion fronts (it had warned of a torsion shear 30 %
    // off, advising 13933 elements).
    for r in [&upright, &flipped] {
        assert!(r.largest_twist.is_none_or(|t| t.max < 1e-9), "{:?}", r.largest_twist);
        assert!(
            !r.plan.reasons.iter().any(|x| x.contains("torsion fronts")),
            "{:?}",
            r.plan.reasons
        );
        assert!(!r.warnings.iter().any(|x| x.contains("torsion")), "{:?}", r.warnings);
    }
}

#[test]
fn a_coarse_output_thins_the_history_not_the_maxima_of_the_modes() {
    // A 1 m strip clamped-free struck at 0.6 m at 0.1 m/s by its finite-element modes: the
    // maxima are read at instants, and in free flight those had been the output's, so over
    // 1 ms output_interval = 2e-4 s read the clamp at 4.86e5 Pa against 7.91e5 (a review's;
    // the fe method 7.906e5). Now they are at least every end_time / 2000.
    let run = |end: &str, output: &str| {
        let text = format!(
            "name = \"strip\"\n[beam]\nlength = 1.0\nwidth = 0.025\nthickness = 0.005\nsupport = \"clamped-free\"\n\
             youngs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
             [ball]\nradius = 0.005\nyoungs_modulus = 2.1e11\npoisson_ratio = 0.3\ndensity = 7850.0\n\
             [impact]\nposition = 0.6\nspeed = 0.1\ngravity = false\n\
             [solver]\nmethod = \"modal\"\nmodal_basis = \"fe\"\nend_time = {end}\n{output}"
        );
        let r = simulate(&Scene::from_toml(&text).unwrap()).unwrap().report;
        r.bending_stress.unwrap().supports[0].max
    };
    let (coarse, fine) = (run("0.001", "output_interval = 2e-4\n"), run("0.001", ""));
    assert!(off(coarse, fine) < 1e-3 && (fine / 7.906e5 - 1.0).abs() < 5e-3, "{coarse} vs {fine}");
    // Nor with a long window's default output: over 50 ms its 2000 instants are 25 us apart,
    // where the clamp read 1.2158 MPa; the instants are now at most half a radian of the
    // fastest mode kept apart: 1.43882 MPa, against 1.43901 read every 0.2 us (1.3e-4).
    let long = run("0.05", "");
    assert!((long / 1.43901e6 - 1.0).abs() < 1e-3, "{long}");
}
