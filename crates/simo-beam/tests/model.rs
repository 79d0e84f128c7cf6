//! The assembled model against finite differences, and its energies.
#![allow(clippy::unwrap_used, clippy::float_cmp)]

use faer::Col;
use hht::{Model, NewtonWeights, Triplets};
use nalgebra::Vector3;
use simo_beam::{BeamModel, BeamState, Load, Material, Mesh, Profile, Section, Support};

/// The right-angle frame of validation/REFERENCES.md 3.4 (two legs, a rigid corner), with a dead force,
/// a follower force and a dead moment, in a deformed, moving state.
fn frame() -> (BeamModel, BeamState, Col<f64>, Col<f64>) {
    let a2: f64 = 12e-3;
    let mat = Material { youngs_modulus: 1e6 / a2, shear_modulus: 0.5e6 / a2, density: 1.0 / a2 };
    let sec = Section::rectangle(&mat, a2.sqrt(), a2.sqrt()).unwrap();
    let leg1 = Mesh::straight(
        Vector3::new(0.0, 10.0, 0.0),
        Vector3::new(10.0, 10.0, 0.0),
        3,
        sec,
        Vector3::z(),
    )
    .unwrap();
    let leg2 = Mesh::straight(
        Vector3::new(10.0, 10.0, 0.0),
        Vector3::new(10.0, 0.0, 0.0),
        3,
        sec,
        Vector3::z(),
    )
    .unwrap();
    let model = BeamModel::new(leg1.join(leg2).unwrap())
        .unwrap()
        .support(0, Support::Clamped)
        .unwrap()
        .load(Load {
            node: 3,
            force: Vector3::new(0.0, 0.0, 30.0),
            moment: Vector3::new(5.0, -2.0, 1.0),
            follower: false,
            profile: Profile::Constant,
        })
        .unwrap()
        .load(Load {
            node: 6,
            force: Vector3::new(1.0, 4.0, -3.0),
            moment: Vector3::new(0.0, 2.0, 0.0),
            follower: true,
            profile: Profile::Constant,
        })
        .unwrap();
    let n = model.ndof();
    let mut q = model.reference_state();
    let dq = Col::from_fn(n, |i| 0.3 * ((i as f64) * 0.7).sin());
    model.update(&mut q, dq.as_ref());
    let v = Col::from_fn(n, |i| 2.0 * ((i as f64) * 1.3).cos());
    let a = Col::from_fn(n, |i| 5.0 * ((i as f64) * 0.4).sin());
    (model, q, v, a)
}

fn dense(n: usize, t: &Triplets) -> Vec<Vec<f64>> {
    let mut m = vec![vec![0.0; n]; n];
    for (r, c, v) in t.iter() {
        m[r][c] += v;
    }
    m
}

#[test]
fn newton_matrix_matches_finite_differences() {
    // The HHT residual w_I I(q, v, a) + w_g g(q, v) along the step's own linearisation
    // (q (+) e, v + dv e, a + da e) against the model's Newton matrix. Central differences with
    // eps = 1e-6: truncation ~1e-12 relative, round-off ~1e-10 of the force scale.
    let (model, q, v, a) = frame();
    let n = model.ndof();
    let w = NewtonWeights { inertia: 1.0, force: 0.9, da: 40.0, dv: 6.0, dq: 1.0 };
    let residual = |e: &Col<f64>| {
        let mut qe = q.clone();
        model.update(&mut qe, e.as_ref());
        let ve = &v + w.dv * e;
        let ae = &a + w.da * e;
        let mut i = Col::zeros(n);
        let mut g = Col::zeros(n);
        model.inertial_force(&qe, ve.as_ref(), ae.as_ref(), i.as_mut());
        model.net_force(0.0, &qe, ve.as_ref(), g.as_mut());
        w.inertia * i + w.force * g
    };
    let mut t = Triplets::new();
    model.tangent(0.0, &q, v.as_ref(), a.as_ref(), w, &mut t);
    let j = dense(n, &t);
    let scale = j.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let eps = 1e-6;
    for col in 0..n {
        let mut e = Col::zeros(n);
        e[col] = eps;
        let fd = (residual(&e) - residual(&(-&e))) / (2.0 * eps);
        for row in 0..n {
            assert!(
                (fd[row] - j[row][col]).abs() < 1e-6 * scale,
                "J[{row},{col}] = {} vs FD {}",
                j[row][col],
                fd[row]
            );
        }
    }
}

#[test]
fn a_newton_matrix_re_weighted_is_its_part_without_stiffness_added() {
    // The integrator re-weights a kept Newton matrix for a new step size by adding the
    // tangent of the weights' difference with dq = 0 (mass, gyroscopic: no stiffness), which
    // pushes only its own entries: on the frame (a held node, a point mass, a corner),
    // T(w1) - T(w2) is that tangent to round-off; and the mass matrix's product with any a
    // is the inertial force at rest, I(q, 0, a).
    let (model, q, v, a) = frame();
    let n = model.ndof();
    let tangent = |w: NewtonWeights| {
        let mut t = Triplets::new();
        model.tangent(0.0, &q, v.as_ref(), a.as_ref(), w, &mut t);
        dense(n, &t)
    };
    let w1 = NewtonWeights { inertia: 0.95, force: 0.9, da: 4e6, dv: 3e3, dq: 1.0 };
    let w2 = NewtonWeights { da: 1e6, dv: 1.5e3, ..w1 };
    let delta = NewtonWeights { da: w1.da - w2.da, dv: w1.dv - w2.dv, dq: 0.0, ..w1 };
    let (t1, t2, td) = (tangent(w1), tangent(w2), tangent(delta));
    let scale = t1.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    for row in 0..n {
        for col in 0..n {
            let (difference, part) = (t1[row][col] - t2[row][col], td[row][col]);
            assert!(
                (difference - part).abs() <= 1e-14 * scale,
                "[{row},{col}] {difference} {part}"
            );
        }
    }
    let mass = tangent(NewtonWeights::mass());
    let mut inertial = Col::zeros(n);
    model.inertial_force(&q, Col::<f64>::zeros(n).as_ref(), a.as_ref(), inertial.as_mut());
    let largest = (0..n).map(|k| inertial[k].abs()).fold(0.0, f64::max);
    for (row, m) in mass.iter().enumerate() {
        let product: f64 = m.iter().zip(0..n).map(|(m, k)| m * a[k]).sum();
        assert!((product - inertial[row]).abs() <= 1e-13 * largest, "{row}: {product}");
    }
}

#[test]
fn kinetic_energy_is_half_v_dot_inertial_force() {
    // With the gyroscopic term orthogonal to W, v . I(q, v, v) = 2 T for any v.
    let (model, q, v, _) = frame();
    let mut i = Col::zeros(model.ndof());
    model.inertial_force(&q, v.as_ref(), v.as_ref(), i.as_mut());
    let two_t = (0..model.ndof()).map(|k| v[k] * i[k]).sum::<f64>();
    assert!((two_t - 2.0 * model.kinetic_energy(v.as_ref())).abs() < 1e-12 * two_t.abs());
}

/// Free vibration of the paper's cantilever from an initial velocity (first-mode-like shape,
/// tip speed `speed`), 400 steps of 0.5 ms; returns the total energy after each step.
fn free_vibration(alpha: f64, speed: f64) -> Vec<f64> {
    use hht::{Integrator, NewtonOptions, Scheme};
    let model = simo_beam::benchmarks::paper_cantilever(16).unwrap();
    let n = model.ndof();
    let mut v = Col::zeros(n);
    for node in 1..=16 {
        let s = node as f64 / 16.0;
        if let Some(i) = model.dof(node, 2) {
            v[i] = speed * s * s;
        }
    }
    let mut integrator = Integrator::new(Scheme::hht(alpha).unwrap(), NewtonOptions::default());
    let mut state = integrator.initial_state(&model, 0.0, model.reference_state(), v).unwrap();
    (0..400)
        .map(|_| {
            integrator.step(&model, &mut state, 5e-4).unwrap();
            model.strain_energy(&state.q) + model.kinetic_energy(state.v.as_ref())
        })
        .collect()
}

#[test]
fn free_vibration_energy_is_kept_by_trapezoid_and_never_gained_with_alpha() {
    // alpha = 0 on a small-amplitude (nearly linear) vibration: the trapezoidal rule conserves
    // the quadratic energy exactly, so what moves it is where Newton stops: the round-off floor
    // 64 eps EA sqrt(n) ~ 4e-6 N against elastic forces of ~0.1 N here, i.e. ~1e-7 per step in
    // the energy (measured: 1.3e-7 over 400 steps). 1e-6 bounds it.
    let e = free_vibration(0.0, 0.01);
    let (lo, hi) = e.iter().fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    assert!(hi - lo < 1e-6 * hi, "alpha = 0: energy between {lo} and {hi}");
    // alpha < 0 at large amplitude (tip speed 2 m/s, rotations ~ 0.2 rad): dissipative. HHT's
    // dissipation is proven for linear problems; on the nonlinear beam the mechanical energy
    // may rise within a step by O(period error x nonlinearity) (measured: up to 1.4e-7 relative),
    // bounded here by 1e-6, and its envelope falls.
    let e = free_vibration(-0.1, 2.0);
    for w in e.windows(2) {
        assert!(w[1] <= w[0] * (1.0 + 1e-6), "energy rose from {} to {}", w[0], w[1]);
    }
    let first = e[..100].iter().copied().fold(f64::MIN, f64::max);
    let last = e[300..].iter().copied().fold(f64::MIN, f64::max);
    assert!(last < first, "envelope {first} -> {last}");
}

#[test]
fn degenerate_meshes_and_sections_are_refused_by_name() {
    // A review's: a NaN hint and an arc without a plane gave NaN frames and positions, fewer
    // frames than nodes panicked, coincident nodes failed only in a solve, and a section of
    // EA = -1 was solved (the 3D path never checked it; the planar one did).
    use nalgebra::UnitQuaternion;
    let steel = Material::new(2.1e11, 0.3, 7850.0).unwrap();
    let s = Section::rectangle(&steel, 0.025, 0.005).unwrap();
    let (o, x) = (Vector3::zeros(), Vector3::x());
    let err = |r: Result<Mesh, simo_beam::BeamError>| r.map(|_| ()).unwrap_err().to_string();
    assert!(err(Mesh::straight(o, x, 4, s, Vector3::new(f64::NAN, 0.0, 1.0))).contains("hint"));
    assert!(err(Mesh::arc(o, 1.0, x, Vector3::zeros(), 1.0, 4, s)).contains("normal"));
    assert!(err(Mesh::arc(o, 1.0, Vector3::z(), Vector3::z(), 1.0, 4, s)).contains("start"));
    let three = vec![o, x, 2.0 * x];
    let one_frame = vec![UnitQuaternion::identity()];
    assert!(err(Mesh::from_nodes(three.clone(), one_frame, s)).contains("frame"));
    let frames = vec![UnitQuaternion::identity(); 3];
    assert!(err(Mesh::from_nodes(vec![o, x, x], frames.clone(), s)).contains("one place"));
    let negative = Section { ea: -1.0, ..s };
    assert!(err(Mesh::from_nodes(three, frames, negative)).contains("EA"));
    assert!(err(Mesh::straight(o, x, 4, negative, Vector3::z())).contains("EA"));
}

#[test]
fn a_configuration_update_turns_each_node_by_the_exponential_of_its_increment() {
    // q (+) dq = (x + u, Lambda exp(th^)) (Simo & Vu-Quoc's update), here against nalgebra's
    // own exponential (sine and cosine): the update's series below |th|^2 = 1e-4 (truncated
    // past a^8 / 1e7) and its multiply-adds agree to a few ulps of the unit quaternion; a
    // turn past the series (0.2 rad at node 2) and the clamped node (nothing moves) too; and
    // with a node held along y mid-leg (the nodes updated in two runs, that node by index).
    let (model, q, _, _) = frame();
    let held = model.clone().hold(&[(3, 1)]).unwrap();
    for model in [model, held] {
        turns_each_node_by_the_exponential(&model, &q);
    }
}

fn turns_each_node_by_the_exponential(model: &BeamModel, q: &BeamState) {
    let n = model.ndof();
    let dq = Col::<f64>::from_fn(n, |i| {
        let k = i % 6;
        let size = if k < 3 { 1e-4 } else { 3e-3 };
        size * (((i * 7919) % 13) as f64 / 6.0 - 1.0)
    });
    let mut big = dq.clone();
    if let Some(i) = model.dof(2, 3) {
        big[i] = 0.2;
    }
    for dq in [dq, big] {
        let mut moved = q.clone();
        model.displaced(q, dq.as_ref(), &mut moved);
        for node in 0..q.positions.len() {
            let at = |k: usize| model.dof(node, k).map_or(0.0, |i| dq[i]);
            let u = Vector3::new(at(0), at(1), at(2));
            let th = Vector3::new(at(3), at(4), at(5));
            let expected = q.rotations[node] * nalgebra::UnitQuaternion::from_scaled_axis(th);
            assert!((moved.positions[node] - (q.positions[node] + u)).amax() <= 1e-15);
            let (a, b) = (moved.rotations[node].quaternion(), expected.quaternion());
            assert!((a.coords - b.coords).amax() <= 4.0 * f64::EPSILON, "node {node}: {a} {b}");
        }
    }
}

#[test]
fn the_banded_solve_of_a_3d_newton_matrix_is_backward_stable() {
    // The banded LU solves a chain of nodes of six by each node's 6 x 6 matrices (explicit
    // inverses of the factors' diagonal blocks, hht's `node_matrices`), not by substitution:
    // on the 3D strip's own Newton matrices, from a fine step's (the mass's weight 1e13 of the
    // stiffness's, the impact runs') to a long one's (weight 1, the stiffness's scales: EA / l
    // against GJ / l, some 1e6 apart), its backward error ||A x - b|| / (||A||_F ||x||) is a
    // dense LU's with partial pivoting to a factor of ten (measured 0.7-1.5, both 1e-21 to
    // 2e-18: round-off's; an unstable inverse would show as orders of magnitude).
    use hht::{Band, BandedLu};
    use nalgebra::UnitQuaternion;
    let steel = Material::new(2.1e11, 0.3, 7850.0).unwrap();
    let section = Section::rectangle(&steel, 0.025, 0.005).unwrap();
    let mesh =
        Mesh::straight(Vector3::zeros(), Vector3::x() * 1.15, 64, section, Vector3::z()).unwrap();
    let model = BeamModel::new(mesh).unwrap().support(0, Support::Clamped).unwrap();
    let n = model.ndof();
    let mut q = model.reference_state();
    for (k, r) in q.rotations.iter_mut().enumerate() {
        *r *= UnitQuaternion::from_scaled_axis(Vector3::new(1e-3, -2e-3, 5e-4) * k as f64 / 64.0);
    }
    let (v, a) = (Col::<f64>::zeros(n), Col::<f64>::zeros(n));
    for da in [1e13, 1e6, 1.0] {
        let w = NewtonWeights { inertia: 1.0, force: 1.05, da, dv: da.sqrt(), dq: 1.0 };
        let mut t = Triplets::new();
        model.tangent(0.0, &q, v.as_ref(), a.as_ref(), w, &mut t);
        let b: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 / 6.0 - 1.0).collect();
        let mut lu = BandedLu::new();
        lu.factor(n, Band { half_bandwidth: 11, border: 0 }, &t, 0.0).unwrap();
        // (The node matrices are made at a factorisation's eighth solve: the first seven take
        // the fixed-width path; the tenth's solution is the node matrices'.)
        let mut x = Col::<f64>::from_fn(n, |i| b[i]);
        for _ in 0..10 {
            x = Col::<f64>::from_fn(n, |i| b[i]);
            lu.solve_in_place(x.as_mut(), 0.0).unwrap();
        }
        let dense = nalgebra::DMatrix::from_fn(n, n, |_, _| 0.0);
        let dense = t.iter().fold(dense, |mut m, (r, c, v)| {
            m[(r, c)] += v;
            m
        });
        let exact = dense.clone().lu().solve(&nalgebra::DVector::from_vec(b.clone())).unwrap();
        let backward = |x: &[f64]| {
            let mut ax = vec![0.0; n];
            t.mul_vec(x, &mut ax);
            let r = ax.iter().zip(&b).map(|(p, q)| (p - q).powi(2)).sum::<f64>().sqrt();
            let x_norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
            r / (dense.norm() * x_norm)
        };
        let x: Vec<f64> = (0..n).map(|i| x[i]).collect();
        let (ours, theirs) = (backward(&x), backward(exact.as_slice()));
        assert!(ours < 10.0 * theirs, "da {da}: {ours:e} against {theirs:e}");
    }
}
