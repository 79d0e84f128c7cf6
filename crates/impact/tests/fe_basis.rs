//! Goldsmith's method on a finite-element basis (a `[structure]` by `solver.method = "modal"`):
//! against the analytic basis on the paper's uniform cantilever, centred and off the centre
//! line, and against the fe method on the frame (validation/REFERENCES.md 1.13).
#![allow(clippy::unwrap_used)] // a test stops on a bad fixture

use impact::{simulate, Report, Scene};

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

/// validation/scenes/frame-impact.toml by `method`.
fn frame(method: &str) -> Report {
    let text = std::fs::read_to_string(format!(
        "{}/../../validation/scenes/frame-impact.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
    .replace("method = \"fe\"", &format!("method = \"{method}\""));
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
    let (sm, sf) = (modal.bending_stress.unwrap(), fe.bending_stress.unwrap());
    assert!(
        off(sm.max, sf.max) < 2e-3 && (sm.position - sf.position).abs() < 1e-12,
        "{sm:?} vs {sf:?}"
    );
    let (hm, hf) = (modal.torsion_shear.unwrap(), fe.torsion_shear.unwrap());
    assert!(off(hm.max, hf.max) < 2e-3, "{hm:?} vs {hf:?}");
    assert!(modal.energy.balance_error.abs() < 1e-6 * modal.energy.initial);
    assert_eq!(modal.plan.elements, 80);
    assert!(modal.plan.modes > 200, "{}", modal.plan.modes);
}
