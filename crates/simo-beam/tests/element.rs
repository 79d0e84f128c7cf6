//! Finite-difference and objectivity checks of the element (ARCHITECTURE.md at the repository root, Tests; validation/REFERENCES.md 5.1).
#![allow(clippy::unwrap_used, clippy::float_cmp)]

use nalgebra::{UnitQuaternion, Vector3};
use simo_beam::{Element, Material, Section};

fn section() -> Section {
    // The paper's strip: EA/EI ~ 1e6 makes the checks exercise very different magnitudes.
    let steel = Material::new(2.1e11, 0.3, 7850.0).unwrap();
    Section::rectangle(&steel, 0.025, 0.005).unwrap()
}

/// A curved reference element and a strongly deformed current state (rotations ~ 1 rad).
fn setup() -> (Element, [Vector3<f64>; 2], [UnitQuaternion<f64>; 2]) {
    let x0 = [Vector3::new(0.0, 0.0, 0.0), Vector3::new(0.1, 0.01, 0.0)];
    let r0 = [
        UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, 0.05)),
        UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, 0.15)),
    ];
    let e = Element::new([0, 1], section(), [&x0[0], &x0[1]], [&r0[0], &r0[1]]);
    let x = [Vector3::new(0.01, -0.02, 0.005), Vector3::new(0.08, 0.05, 0.03)];
    let r = [
        UnitQuaternion::from_scaled_axis(Vector3::new(0.3, -0.2, 0.4)),
        UnitQuaternion::from_scaled_axis(Vector3::new(-0.5, 0.9, 1.1)),
    ];
    (e, x, r)
}

/// Perturbs component j of [dx1, th1, dx2, th2] by h (rotations multiplicatively, material).
fn perturbed(
    x: &[Vector3<f64>; 2],
    r: &[UnitQuaternion<f64>; 2],
    j: usize,
    h: f64,
) -> ([Vector3<f64>; 2], [UnitQuaternion<f64>; 2]) {
    let (mut x, mut r) = (*x, *r);
    let node = j / 6;
    let k = j % 6;
    if k < 3 {
        x[node][k] += h;
    } else {
        let mut th = Vector3::zeros();
        th[k - 3] = h;
        r[node] *= UnitQuaternion::from_scaled_axis(th);
    }
    (x, r)
}

#[test]
fn force_is_the_gradient_of_the_energy() {
    // Central differences of the energy along each variation. Step 1e-7 (m, rad): truncation
    // O(h^2) ~ 1e-14 relative, round-off eps E / h ~ 1e-9 of the force scale; 1e-6 relative.
    let (e, x, r) = setup();
    let f = e.force([&x[0], &x[1]], [&r[0], &r[1]]);
    let scale = f.amax();
    for j in 0..12 {
        let h = 1e-7;
        let (xp, rp) = perturbed(&x, &r, j, h);
        let (xm, rm) = perturbed(&x, &r, j, -h);
        let fd = (e.energy([&xp[0], &xp[1]], [&rp[0], &rp[1]])
            - e.energy([&xm[0], &xm[1]], [&rm[0], &rm[1]]))
            / (2.0 * h);
        assert!((fd - f[j]).abs() < 1e-6 * scale, "component {j}: force {} vs FD {fd}", f[j]);
    }
}

#[test]
fn tangent_matches_finite_differences_of_the_force() {
    let (e, x, r) = setup();
    let (f, k) = e.force_and_tangent([&x[0], &x[1]], [&r[0], &r[1]]);
    let f_plain = e.force([&x[0], &x[1]], [&r[0], &r[1]]);
    assert!((f - f_plain).amax() <= 1e-12 * f.amax());
    let scale = k.amax();
    for j in 0..12 {
        let h = 1e-7;
        let (xp, rp) = perturbed(&x, &r, j, h);
        let (xm, rm) = perturbed(&x, &r, j, -h);
        let column = (e.force([&xp[0], &xp[1]], [&rp[0], &rp[1]])
            - e.force([&xm[0], &xm[1]], [&rm[0], &rm[1]]))
            / (2.0 * h);
        for i in 0..12 {
            assert!(
                (column[i] - k[(i, j)]).abs() < 1e-6 * scale,
                "K[{i},{j}] = {} vs FD {}",
                k[(i, j)],
                column[i]
            );
        }
    }
    // Away from equilibrium the exact tangent of a multiplicative update is not symmetric.
    let skew = (k - k.transpose()).amax();
    assert!(skew > 1e-8 * scale, "skew part {skew}");
}

#[test]
fn strains_are_objective_and_reference_is_stress_free() {
    let (e, x, r) = setup();
    let s = e.strains([&x[0], &x[1]], [&r[0], &r[1]]);
    let f = e.force([&x[0], &x[1]], [&r[0], &r[1]]);
    let q = UnitQuaternion::from_scaled_axis(Vector3::new(2.0, -1.0, 2.5));
    let xr = [q * x[0] + Vector3::new(1.0, 2.0, 3.0), q * x[1] + Vector3::new(1.0, 2.0, 3.0)];
    let rr = [q * r[0], q * r[1]];
    let sr = e.strains([&xr[0], &xr[1]], [&rr[0], &rr[1]]);
    // Round-off only: 1e-13 of the strain magnitude.
    assert!((s.gamma - sr.gamma).amax() < 1e-13 * s.gamma.amax().max(1.0));
    assert!((s.kappa - sr.kappa).amax() < 1e-13 * s.kappa.amax().max(1.0));
    // Forces rotate with the body (positions) and material moments are unchanged.
    let fr = e.force([&xr[0], &xr[1]], [&rr[0], &rr[1]]);
    for node in 0..2 {
        let fx = f.fixed_rows::<3>(6 * node).into_owned();
        let fxr = fr.fixed_rows::<3>(6 * node).into_owned();
        assert!((q * fx - fxr).amax() < 1e-10 * f.amax());
        let m = f.fixed_rows::<3>(6 * node + 3).into_owned();
        let mr = fr.fixed_rows::<3>(6 * node + 3).into_owned();
        assert!((m - mr).amax() < 1e-10 * f.amax());
    }
    // The reference configuration carries no strain and no force.
    let x0 = [Vector3::new(0.0, 0.0, 0.0), Vector3::new(0.1, 0.01, 0.0)];
    let r0 = [
        UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, 0.05)),
        UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, 0.15)),
    ];
    let f0 = e.force([&x0[0], &x0[1]], [&r0[0], &r0[1]]);
    assert!(f0.amax() < 1e-6, "{f0}");
}

#[test]
fn the_f64_force_is_the_generic_force_the_tangent_differentiates() {
    // `force` (quaternions on vectors, Jacobians by cross products) against the value of
    // `force_and_tangent` (the generic, matrix form on dual numbers): the same formulas, so
    // equal to round-off (1e-12 of the largest entry), in the series branch of the
    // trigonometric coefficients (a small relative rotation), in the closed form (about 1 rad,
    // `setup`), near pi, and with corner offsets at both ends (a frame's joint).
    let (mut e, x, r) = setup();
    let small = [r[0], r[0] * UnitQuaternion::from_scaled_axis(Vector3::new(1e-3, -2e-3, 5e-4))];
    let near_pi = [r[0], r[0] * UnitQuaternion::from_scaled_axis(Vector3::new(0.3, 2.9, -0.7))];
    for offsets in [false, true] {
        if offsets {
            e.offsets = [
                UnitQuaternion::from_scaled_axis(Vector3::new(
                    0.0,
                    0.0,
                    std::f64::consts::FRAC_PI_2,
                )),
                UnitQuaternion::from_scaled_axis(Vector3::new(0.4, -0.1, 0.2)),
            ];
        }
        for rotations in [r, small, near_pi] {
            let fast = e.force([&x[0], &x[1]], [&rotations[0], &rotations[1]]);
            let (generic, _) = e.force_and_tangent([&x[0], &x[1]], [&rotations[0], &rotations[1]]);
            let scale = generic.amax();
            let error = (fast - generic).amax();
            assert!(scale > 1.0, "a force of {scale:e} tests nothing");
            assert!(error <= 1e-12 * scale, "offsets {offsets}: error {error:e} of {scale:e}");
        }
    }
}

#[test]
fn the_update_exponential_is_the_rotation_of_its_vector() {
    // The series branch (a Newton correction's small angle) and the closed form against
    // nalgebra's axis-angle quaternion, to round-off; on both sides of the series bound.
    for phi in [
        Vector3::new(1e-9, 0.0, -2e-9),
        Vector3::new(3e-4, -2e-3, 1e-3),
        Vector3::new(5e-3, 5e-3, -5e-3),
        Vector3::new(6e-3, 6e-3, -6e-3),
        Vector3::new(0.4, -1.2, 2.0),
    ] {
        let ours = simo_beam::rotation::exp(&phi);
        let reference = UnitQuaternion::from_scaled_axis(phi);
        let error = (ours.coords - reference.coords).amax();
        assert!(error < 2e-16, "phi {phi:?}: error {error:e}");
    }
}

#[test]
fn the_strain_jacobian_is_the_derivative_of_the_strains() {
    // Central differences of the six strains along each variation, on the curved, deformed
    // element, once with a corner offset on its end frames: step 1e-6 (m, rad), truncation
    // O(h^2) ~ 1e-12, round-off eps |K| / h ~ 1e-10 (curvatures of order 1/m): 1e-7 absolute
    // against entries of order 1 (Gamma) and 1/l0 = 10 (K).
    let (mut e, x, r) = setup();
    for offset in [None, Some(Vector3::new(0.2, -0.4, 0.7))] {
        if let Some(o) = offset {
            e.offsets = [UnitQuaternion::identity(), UnitQuaternion::from_scaled_axis(o)];
        }
        let jacobian = e.strain_jacobian([&x[0], &x[1]], [&r[0], &r[1]]);
        let strains = |x: &[Vector3<f64>; 2], r: &[UnitQuaternion<f64>; 2]| {
            let s = e.strains([&x[0], &x[1]], [&r[0], &r[1]]);
            [s.gamma[0], s.gamma[1], s.gamma[2], s.kappa[0], s.kappa[1], s.kappa[2]]
        };
        for j in 0..12 {
            let h = 1e-6;
            let (xp, rp) = perturbed(&x, &r, j, h);
            let (xm, rm) = perturbed(&x, &r, j, -h);
            let (sp, sm) = (strains(&xp, &rp), strains(&xm, &rm));
            for i in 0..6 {
                let fd = (sp[i] - sm[i]) / (2.0 * h);
                assert!(
                    (jacobian[(i, j)] - fd).abs() < 1e-7,
                    "strain {i}, variation {j}: {} vs {fd} (offset {offset:?})",
                    jacobian[(i, j)]
                );
            }
        }
    }
}
