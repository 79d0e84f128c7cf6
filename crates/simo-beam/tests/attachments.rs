//! Point masses and elastic supports on the planar beam (validation/REFERENCES.md 1.10):
//! frequencies against the characteristic equations of a cantilever with a tip mass and with a
//! tip spring, and the force's derivative against finite differences.
#![allow(clippy::unwrap_used)] // a test stops on a bad fixture

use faer::Col;
use hht::{Model, NewtonWeights, Triplets};
use simo_beam::{planar_modes, Material, PlanarBeam, Section, Support};

/// A thin steel strip, 25 x 1 mm, 1 m long (shear shifts its lowest modes by < 1e-5).
const E: f64 = 2.1e11;
const RHO: f64 = 7850.0;
const WIDTH: f64 = 0.025;
const THICKNESS: f64 = 0.001;

fn section() -> Section {
    Section::rectangle(&Material::new(E, 0.3, RHO).unwrap(), WIDTH, THICKNESS).unwrap()
}

fn ei() -> f64 {
    E * WIDTH * THICKNESS.powi(3) / 12.0
}

/// The cantilever (clamped at x = 0) on `n` equal elements.
fn cantilever(n: usize) -> PlanarBeam {
    let nodes: Vec<f64> = (0..=n).map(|k| k as f64 / n as f64).collect();
    PlanarBeam::new(&nodes, &section()).unwrap().support(0, Support::Clamped).unwrap()
}

/// The lowest three lambda^2 = omega L^2 sqrt(rho A / EI) of `beam`.
fn lambda2(beam: &PlanarBeam) -> Vec<f64> {
    let scale = (RHO * WIDTH * THICKNESS / ei()).sqrt();
    planar_modes(beam, 3).unwrap().iter().map(|m| m.omega * scale).collect()
}

#[test]
fn a_tip_mass_and_a_tip_spring_give_their_characteristic_roots() {
    // Tip mass M = rho A L (mu = 1): 1 + cos l cosh l + mu l (cos l sinh l - sin l cosh l) = 0,
    // lambda^2 = 1.557298, 16.25009, 50.89584 (Blevins, Formulas for Natural Frequency and
    // Mode Shape, table 8-8; roots recomputed by brentq). Tip spring k = 100 EI/L^3: the
    // spring takes the mass's -M omega^2 in the shear condition, so
    // 1 + cos l cosh l - (K / l^3)(cos l sinh l - sin l cosh l) = 0, lambda^2 = 13.253544,
    // 31.539412, 65.352462 (derived here, roots by brentq; K -> infinity gives the
    // clamped-pinned 15.418). The element converges at second order: the error must fall
    // about fourfold from 128 to 256 elements and be within 1e-4 at 256.
    let mass: [f64; 3] = [1.5572979, 16.2500852, 50.8958428];
    let spring: [f64; 3] = [13.2535440, 31.5394120, 65.3524617];
    let tip_mass = |n: usize| cantilever(n).attach_mass(n, RHO * WIDTH * THICKNESS, 0.0).unwrap();
    let tip_spring = |n: usize| cantilever(n).attach_spring(n, 100.0 * ei(), 0.0).unwrap();
    for (name, exact, coarse, fine) in [
        ("mass", mass, lambda2(&tip_mass(128)), lambda2(&tip_mass(256))),
        ("spring", spring, lambda2(&tip_spring(128)), lambda2(&tip_spring(256))),
    ] {
        for k in 0..3 {
            let (ec, ef) = ((coarse[k] / exact[k] - 1.0).abs(), (fine[k] / exact[k] - 1.0).abs());
            assert!(ef < 1e-4, "{name} mode {k}: {} vs {}", fine[k], exact[k]);
            if k > 0 {
                assert!((3.0..5.0).contains(&(ec / ef)), "{name} mode {k}: {ec:e} -> {ef:e}");
            }
        }
    }
}

#[test]
fn the_springs_force_is_the_derivative_of_their_energy_and_the_tangent_its_own() {
    // A bent state of the strip with a spring (k, k_theta) at its middle and a mass at its
    // tip: the net force's z and theta entries at the spring are the energy's derivatives
    // (central differences of strain_energy), and the tangent's stiffness part is the force's
    // derivative there.
    let beam = cantilever(8).attach_spring(4, 3e3, 40.0).unwrap().attach_mass(8, 0.1, 0.0).unwrap();
    let mut q = beam.reference_state();
    for k in 0..=8 {
        q.z[k] = 1e-3 * (k as f64).powi(2);
        q.theta[k] = 2e-3 * k as f64;
    }
    let n = beam.ndof();
    let zero = Col::<f64>::zeros(n);
    let mut force = Col::<f64>::zeros(n);
    beam.net_force(0.0, &q, zero.as_ref(), force.as_mut());
    let mut tangent = Triplets::new();
    beam.tangent(0.0, &q, zero.as_ref(), zero.as_ref(), NewtonWeights::stiffness(), &mut tangent);
    for unknown in [1, 2] {
        let i = beam.dof(4, unknown).unwrap();
        let h = 1e-7;
        let at = |d: f64| {
            let mut p = q.clone();
            let mut dq = Col::<f64>::zeros(n);
            dq[i] = d;
            beam.update(&mut p, dq.as_ref());
            p
        };
        let (up, down) = (at(h), at(-h));
        let energy = (beam.strain_energy(&up) - beam.strain_energy(&down)) / (2.0 * h);
        assert!(
            (energy - force[i]).abs() < 1e-6 * force[i].abs().max(1.0),
            "{energy} vs {}",
            force[i]
        );
        let (mut fu, mut fd) = (Col::<f64>::zeros(n), Col::<f64>::zeros(n));
        beam.net_force(0.0, &up, zero.as_ref(), fu.as_mut());
        beam.net_force(0.0, &down, zero.as_ref(), fd.as_mut());
        let column: f64 = tangent.iter().filter(|(r, c, _)| *r == i && *c == i).map(|e| e.2).sum();
        let fd_ii = (fu[i] - fd[i]) / (2.0 * h);
        assert!((column - fd_ii).abs() < 1e-5 * column.abs(), "{column} vs {fd_ii}");
    }
    // The tip mass adds to the kinetic energy of a tip moving at 1 m/s along z: 0.1 / 2 J more.
    let mut v = Col::<f64>::zeros(n);
    v[beam.dof(8, 1).unwrap()] = 1.0;
    let bare = cantilever(8).attach_spring(4, 3e3, 40.0).unwrap();
    assert!(
        (beam.kinetic_energy(v.as_ref()) - bare.kinetic_energy(v.as_ref()) - 0.05).abs() < 1e-15
    );
    // Bad values are refused by name.
    let err = cantilever(4).attach_mass(2, -1.0, 0.0).unwrap_err().to_string();
    assert!(err.contains("mass = -1"), "{err}");
    let err = cantilever(4).attach_spring(9, 1.0, 0.0).unwrap_err().to_string();
    assert!(err.contains("node 9"), "{err}");
}

#[test]
fn the_3d_beam_takes_a_tip_mass_in_bending_and_its_rotary_inertia_in_twist() {
    // The paper's strip (25 x 5 mm, 1.15 m) clamped-free on 64 elements with a tip mass equal
    // to its own (mu = 1) and a rotary inertia about the axis equal to the strip's own, rho Ip L:
    // bending lambda^2 = 1.557298, 16.25009 (as the planar beam); torsion of a shaft with a tip
    // disk, G J beta cos(beta L) = J_tip omega^2 sin(beta L), so beta L tan(beta L) =
    // rho Ip L / J_tip = 1: beta L = 0.8603336 (Blevins, table 8-17, mu = 1),
    // omega = beta c_t, c_t = sqrt(G J / rho Ip). Within 1e-3 at 64 elements (second order).
    use nalgebra::Vector3;
    use simo_beam::{bending_frequencies, natural_modes, BeamModel, Mesh};
    let (b, t, l) = (0.025, 0.005, 1.15);
    let steel = Material::new(E, 0.3, RHO).unwrap();
    let section = Section::rectangle(&steel, b, t).unwrap();
    let mesh =
        Mesh::straight(Vector3::zeros(), Vector3::new(l, 0.0, 0.0), 64, section, Vector3::z())
            .unwrap();
    let rho_a = RHO * b * t;
    let rho_ip = RHO * (b * t.powi(3) + t * b.powi(3)) / 12.0;
    let model = BeamModel::new(mesh)
        .unwrap()
        .support(0, Support::Clamped)
        .unwrap()
        .attach_mass(64, rho_a * l, [rho_ip * l, 0.0, 0.0])
        .unwrap();
    let ei = E * b * t.powi(3) / 12.0;
    let scale = l * l * (rho_a / ei).sqrt();
    let bending = bending_frequencies(&model, 2).unwrap();
    for (k, exact) in [1.5572979, 16.2500852].into_iter().enumerate() {
        let got = bending[k] * scale;
        assert!((got / exact - 1.0).abs() < 1e-3, "bending {k}: {got} vs {exact}");
    }
    // The torsion constant the section uses (Roark's formula).
    let gj = section.gj;
    let omega = 0.8603336 / l * (gj / rho_ip).sqrt();
    let twist = natural_modes(&model, 40)
        .unwrap()
        .into_iter()
        .find(|m| {
            let rot: f64 =
                (0..=64).filter_map(|n| model.dof(n, 3)).map(|i| m.shape[i].powi(2)).sum();
            let all: f64 = m.shape.iter().map(|v| v * v).sum();
            rot > 0.9 * all
        })
        .unwrap();
    assert!((twist.omega / omega - 1.0).abs() < 1e-3, "torsion: {} vs {omega}", twist.omega);
}

#[test]
fn a_rotational_spring_s_moment_is_the_derivative_of_its_energy() {
    // A 3D strip with a rotational spring K = (3, 40, 7) N m/rad at its free end, the end
    // turned by psi = (0.3, -0.2, 0.1) rad (far from small): the net force's rotation entries
    // there are the derivative of the strain energy along the material increments (central
    // differences through the exponential update), to 1e-6.
    use faer::Col;
    use nalgebra::{UnitQuaternion, Vector3};
    use simo_beam::{BeamModel, Mesh};
    let steel = Material::new(E, 0.3, RHO).unwrap();
    let section = Section::rectangle(&steel, 0.025, 0.005).unwrap();
    let mesh =
        Mesh::straight(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0), 4, section, Vector3::z())
            .unwrap();
    let model = BeamModel::new(mesh)
        .unwrap()
        .support(0, Support::Clamped)
        .unwrap()
        .attach_rotational_spring(4, Vector3::new(3.0, 40.0, 7.0))
        .unwrap();
    let mut q = model.reference_state();
    q.rotations[4] *= UnitQuaternion::from_scaled_axis(Vector3::new(0.3, -0.2, 0.1));
    let n = model.ndof();
    let zero = Col::<f64>::zeros(n);
    let mut force = Col::<f64>::zeros(n);
    model.net_force(0.0, &q, zero.as_ref(), force.as_mut());
    for k in 3..6 {
        let i = model.dof(4, k).unwrap();
        let h = 1e-6;
        let energy = |d: f64| {
            let mut p = q.clone();
            let mut dq = Col::<f64>::zeros(n);
            dq[i] = d;
            model.update(&mut p, dq.as_ref());
            model.strain_energy(&p)
        };
        let fd = (energy(h) - energy(-h)) / (2.0 * h);
        assert!(
            (fd - force[i]).abs() < 1e-6 * force[i].abs().max(1.0),
            "{k}: {fd} vs {}",
            force[i]
        );
    }
}

#[test]
fn the_planar_beam_s_banded_modes_are_its_dense_ones() {
    // The planar strip with the tip mass on 32 elements (96 unknowns): every mode below 2e4
    // rad/s by simo_beam::planar_modes_below (banded Lanczos, counted by Sylvester's inertia)
    // as the dense solution gives them, to 1e-7. (This 1 mm strip is as stiff a case as they
    // come: its axial stiffness is 1e11 of its first mode's at 32 elements, growing as n^2, and
    // both solutions' first frequency carries that round-off: 3e-8 apart here, 7e-7 at 128
    // elements, where the mesh's own second-order differences say the banded one is within
    // 1e-7 and the dense one 4e-7 off.)
    let beam = cantilever(32).attach_mass(32, RHO * WIDTH * THICKNESS, 0.0).unwrap();
    let banded = simo_beam::planar_modes_below(&beam, 2e4).unwrap();
    let dense: Vec<f64> = planar_modes(&beam, beam.ndof())
        .unwrap()
        .into_iter()
        .map(|m| m.omega)
        .filter(|w| *w <= 2e4)
        .collect();
    assert_eq!(banded.len(), dense.len());
    assert!(dense.len() > 10, "{} modes test little", dense.len());
    for (k, (a, b)) in banded.iter().zip(&dense).enumerate() {
        assert!((a.omega / b - 1.0).abs() < 1e-7, "mode {k}: {} vs {b}", a.omega);
    }
}

#[test]
fn a_tip_mass_s_rotary_inertia_in_bending_gives_its_characteristic_roots() {
    // A cantilever with a tip mass M = alpha rho A L and a rotary inertia J = beta rho A L^3
    // about the bending axis (a compact block, not a point): the tip's shear and moment take
    // -M omega^2 w and +J omega^2 w', so
    // 1 + c C + alpha l (c S - s C) - beta l^3 (C s + S c) + alpha beta l^4 (1 - c C) = 0
    // (c, s = cos, sin l; C, S = cosh, sinh l); at alpha = 1, beta = 0.1 its roots are
    // lambda^2 = 1.4296263, 6.2753257, 24.7516045 (derived here, roots by brentq, and an
    // independent Hermite beam of 60 elements with the tip's M and J: within 2e-7;
    // validation/REFERENCES.md 1.10). Without J (beta = 0) they are Blevins' 1.557298,
    // 16.25009, 50.89584: the block's J lowers the second by 61 %. The planar beam (its
    // rotary inertia about the width axis) and the 3D beam (about E2) on 128 elements.
    use nalgebra::Vector3;
    use simo_beam::{bending_frequencies, BeamModel, Mesh};
    let exact: [f64; 3] = [1.4296263, 6.2753257, 24.7516045];
    let rho_a = RHO * WIDTH * THICKNESS;
    let (mass, rotary) = (rho_a, 0.1 * rho_a);
    let planar = lambda2(&cantilever(128).attach_mass(128, mass, rotary).unwrap());
    let mesh =
        Mesh::straight(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0), 128, section(), Vector3::z())
            .unwrap();
    let model = BeamModel::new(mesh)
        .unwrap()
        .support(0, Support::Clamped)
        .unwrap()
        .attach_mass(128, mass, [0.0, rotary, 0.0])
        .unwrap();
    let scale = (rho_a / ei()).sqrt();
    let solid: Vec<f64> =
        bending_frequencies(&model, 3).unwrap().iter().map(|w| w * scale).collect();
    for k in 0..3 {
        for (name, got) in [("planar", planar[k]), ("3d", solid[k])] {
            assert!((got / exact[k] - 1.0).abs() < 2e-4, "{name} mode {k}: {got} vs {}", exact[k]);
        }
    }
}
