//! The planar beam is the 3D beam restricted to a plane: same energies, same motion.
#![allow(clippy::unwrap_used)] // helpers stop on bad fixtures

use faer::Col;
use hht::{Integrator, Model, NewtonOptions, Scheme};
use nalgebra::{UnitQuaternion, Vector3};
use simo_beam::*;

fn section() -> Section {
    let steel = Material::new(2.1e11, 0.3, 7850.0).unwrap();
    Section::rectangle(&steel, 0.025, 0.005).unwrap()
}

/// The same clamped strip, 3D and planar, on nodes `xs`.
fn pair(xs: &[f64]) -> (BeamModel, PlanarBeam) {
    let s = section();
    let mesh = Mesh::from_nodes(
        xs.iter().map(|x| Vector3::new(*x, 0.0, 0.0)).collect(),
        vec![UnitQuaternion::identity(); xs.len()],
        s,
    )
    .unwrap();
    let spatial = BeamModel::new(mesh).unwrap().support(0, Support::Clamped).unwrap();
    let planar = PlanarBeam::new(xs, &s).unwrap().support(0, Support::Clamped).unwrap();
    (spatial, planar)
}

/// The 3D state of a planar one: theta turns x toward z, a rotation of -theta about y.
fn lift(q: &PlanarState) -> BeamState {
    BeamState {
        positions: (0..q.x.len()).map(|i| Vector3::new(q.x[i], 0.0, q.z[i])).collect(),
        rotations: q
            .theta
            .iter()
            .map(|t| UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -t))
            .collect(),
    }
}

#[test]
fn strain_energy_is_the_3d_beams_in_the_plane() {
    // One-point integration with the Crisfield-Jelenic interpolation is linear in the angle
    // when every rotation is about one axis: the energies agree to round-off (1e-12 of the
    // energy, which is a sum of terms ~EA Gamma^2 that cancel little here).
    let xs = [0.0, 0.2, 0.45, 0.8, 1.15];
    let (spatial, planar) = pair(&xs);
    let mut q = planar.reference_state();
    for i in 1..xs.len() {
        q.x[i] -= 1e-3 * i as f64;
        q.z[i] = 0.02 * (i as f64).powi(2);
        q.theta[i] = 0.15 * i as f64;
    }
    let (e2, e3) = (planar.strain_energy(&q), spatial.strain_energy(&lift(&q)));
    assert!((e2 - e3).abs() < 1e-12 * e3, "{e2} vs {e3}");
}

#[test]
fn free_vibration_matches_the_3d_beam() {
    // The clamped strip released from a static-like tip deflection, HHT alpha = -0.05, 40
    // steps of 50 us: the planar and the 3D tip agree to 1e-9 of the deflection (both solve
    // the same discrete equations; what is left is Newton's tolerance).
    let xs: Vec<f64> = (0..=8).map(|i| 1.15 * i as f64 / 8.0).collect();
    let (spatial, planar) = pair(&xs);
    let mut q2 = planar.reference_state();
    for (i, x) in xs.iter().enumerate() {
        let s = x / 1.15;
        q2.z[i] = 0.01 * s * s * (3.0 - s) / 2.0;
        q2.theta[i] = 0.01 * 3.0 * s * (2.0 - s) / 2.0 / 1.15;
    }
    let q3 = lift(&q2);
    let mut int2 = Integrator::new(Scheme::hht(-0.05).unwrap(), NewtonOptions::default());
    let mut int3 = Integrator::new(Scheme::hht(-0.05).unwrap(), NewtonOptions::default());
    let mut s2 = int2.initial_state(&planar, 0.0, q2, Col::zeros(planar.ndof())).unwrap();
    let mut s3 = int3.initial_state(&spatial, 0.0, q3, Col::zeros(spatial.ndof())).unwrap();
    for _ in 0..40 {
        int2.step(&planar, &mut s2, 5e-5).unwrap();
        int3.step(&spatial, &mut s3, 5e-5).unwrap();
    }
    let tip = xs.len() - 1;
    let (z2, z3) = (s2.q.z[tip], s3.q.positions[tip].z);
    assert!((z2 - z3).abs() < 1e-9 * 0.01, "{z2} vs {z3}");
    assert!(z2.abs() > 1e-4, "the tip should have moved: {z2}");
    let (k2, k3) = (planar.kinetic_energy(s2.v.as_ref()), spatial.kinetic_energy(s3.v.as_ref()));
    assert!((k2 - k3).abs() < 1e-7 * k3.max(1e-12), "{k2} vs {k3}");
}
