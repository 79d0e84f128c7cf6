//! Element force + tangent, assembly + factorisation of a 64-element cantilever, one HHT step
//! of it, the Mattiasson k = 10 static solve with 32 elements, and 50 ms of the paper's
//! cantilever with 64 elements at 10 us steps (the comparison run of issue 3); the planar
//! beam's tangent, banded factorisation, back-substitution and HHT step at 64, 256 and 1024
//! elements; the 3D beam's forces, update and back-substitution at 256.
#![allow(clippy::expect_used, missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion};
use faer::Col;
use hht::{Integrator, Model, NewtonOptions, NewtonWeights, Scheme, SparseLu, Triplets};
use nalgebra::Vector3;
use simo_beam::benchmarks::{mattiasson, paper_cantilever};
use simo_beam::{BeamModel, Load, Profile};

fn loaded_cantilever(elements: usize) -> BeamModel {
    paper_cantilever(elements)
        .expect("mesh")
        .load(Load {
            node: elements,
            force: Vector3::new(0.0, 0.0, -10.0),
            moment: Vector3::zeros(),
            follower: false,
            profile: Profile::Table(vec![(0.0, 0.0), (1e-3, 1.0), (2e-3, 0.0)]),
        })
        .expect("load")
}

/// The modes of a right-angle frame of the paper's strip (two 1.15 m legs of 256 elements,
/// 3078 unknowns, clamped at one end) up to omega t_c = 20 for the paper's 40 us contact
/// (5e5 rad/s): what a modal impact run on the frame needs (issue "Goldsmith's method on any
/// beam structure": under a second).
fn frame_modes(c: &mut Criterion) {
    use simo_beam::{modes_below, Material, Mesh, Section, Support};
    let steel = Material::new(2.1e11, 0.3, 7850.0).expect("steel");
    let section = Section::rectangle(&steel, 0.025, 0.005).expect("section");
    let leg = |a: Vector3<f64>, b: Vector3<f64>| {
        Mesh::straight(a, b, 256, section, Vector3::z()).expect("leg")
    };
    let mesh = leg(Vector3::zeros(), Vector3::new(1.15, 0.0, 0.0))
        .join(leg(Vector3::new(1.15, 0.0, 0.0), Vector3::new(1.15, 1.15, 0.0)))
        .expect("frame");
    let model = BeamModel::new(mesh).expect("model").support(0, Support::Clamped).expect("clamp");
    let mut group = c.benchmark_group("simo_beam");
    group.sample_size(10);
    group.bench_function("modes_below_frame_512", |b| {
        b.iter(|| modes_below(&model, 5e5).expect("modes"))
    });
    group.finish();
}

fn element(c: &mut Criterion) {
    let model = paper_cantilever(8).expect("mesh");
    let e = model.mesh().elements[3];
    let x = [Vector3::new(0.1, 0.0, 0.01), Vector3::new(0.24, 0.01, 0.03)];
    let r = [
        nalgebra::UnitQuaternion::from_scaled_axis(Vector3::new(0.1, -0.2, 0.05)),
        nalgebra::UnitQuaternion::from_scaled_axis(Vector3::new(0.12, -0.3, 0.02)),
    ];
    c.bench_function("simo_beam/element_force", |b| {
        b.iter(|| e.force([&x[0], &x[1]], [&r[0], &r[1]]))
    });
    // A fine mesh's element: the relative rotation ~1e-3 rad takes the series branch of the
    // rotation coefficients (the impact runs' case).
    let small =
        [r[0], r[0] * nalgebra::UnitQuaternion::from_scaled_axis(Vector3::new(1e-3, -2e-3, 5e-4))];
    c.bench_function("simo_beam/element_force_small_rotation", |b| {
        b.iter(|| e.force([&x[0], &x[1]], [&small[0], &small[1]]))
    });
    c.bench_function("simo_beam/element_force_and_tangent", |b| {
        b.iter(|| e.force_and_tangent([&x[0], &x[1]], [&r[0], &r[1]]))
    });
}

fn assembly(c: &mut Criterion) {
    let model = loaded_cantilever(64);
    let q = model.reference_state();
    let n = model.ndof();
    let zero = Col::<f64>::zeros(n);
    let w = NewtonWeights { inertia: 1.0, force: 1.1, da: 1e10, dv: 1e5, dq: 1.0 };
    let mut lu = SparseLu::new();
    let mut t = Triplets::new();
    c.bench_function("simo_beam/assemble_and_factor_64", |b| {
        b.iter(|| {
            t.clear();
            model.tangent(0.0, &q, zero.as_ref(), zero.as_ref(), w, &mut t);
            lu.factor(n, &t, 0.0).expect("factor");
        })
    });
    let mut integrator =
        Integrator::new(Scheme::hht(-0.1).expect("alpha"), NewtonOptions::default());
    let mut state = integrator.initial_state(&model, 0.0, q.clone(), zero.clone()).expect("state");
    c.bench_function("simo_beam/hht_step_64", |b| {
        b.iter(|| integrator.step(&model, &mut state, 1e-5).expect("step"))
    });
}

fn statics(c: &mut Criterion) {
    let mut group = c.benchmark_group("simo_beam/static");
    group.sample_size(10);
    group.bench_function("mattiasson_k10_32", |b| {
        b.iter(|| mattiasson(10.0, 32, 5).expect("solve"))
    });
    group.finish();
}

fn comparison_run(c: &mut Criterion) {
    // 50 ms of the paper's cantilever, 64 3D elements, 10 us steps, a 10 N tip pulse.
    let model = loaded_cantilever(64);
    let mut group = c.benchmark_group("simo_beam/paper_cantilever");
    group.sample_size(10);
    group.bench_function("50ms_64_elements_10us", |b| {
        b.iter(|| {
            let mut integrator =
                Integrator::new(Scheme::hht(-0.1).expect("alpha"), NewtonOptions::default());
            let n = model.ndof();
            let mut state = integrator
                .initial_state(&model, 0.0, model.reference_state(), Col::zeros(n))
                .expect("state");
            for _ in 0..5000 {
                integrator.step(&model, &mut state, 1e-5).expect("step");
            }
            state.q.positions[64].z
        })
    });
    group.finish();
}

/// The planar beam the impact's fe method runs on, at 64, 256 and 1024 elements: one tangent
/// assembly, one net (internal) and inertial force, one configuration update, one banded
/// factorisation, one back-substitution and one HHT step (with the factorisation reused, as the
/// impact solver runs it).
fn planar(c: &mut Criterion) {
    use hht::BandedLu;
    use simo_beam::{Material, PlanarBeam, Section, Support};
    let steel = Material::new(2.1e11, 0.3, 7850.0).expect("material");
    let section = Section::rectangle(&steel, 0.025, 0.005).expect("section");
    let mut group = c.benchmark_group("simo_beam/planar");
    for elements in [64usize, 256, 1024] {
        let nodes: Vec<f64> = (0..=elements).map(|i| 1.15 * i as f64 / elements as f64).collect();
        let beam = PlanarBeam::new(&nodes, &section)
            .and_then(|b| b.support(0, Support::Clamped))
            .expect("beam");
        let mut q = beam.reference_state();
        for (i, z) in q.z.iter_mut().enumerate() {
            *z = 1e-4 * (i as f64 / elements as f64).powi(2);
        }
        let n = beam.ndof();
        let zero = Col::<f64>::zeros(n);
        let w = NewtonWeights { inertia: 1.0, force: 1.05, da: 1e13, dv: 1e6, dq: 1.0 };
        let mut t = Triplets::new();
        group.bench_function(format!("tangent_{elements}"), |b| {
            b.iter(|| {
                t.clear();
                beam.tangent(0.0, &q, zero.as_ref(), zero.as_ref(), w, &mut t);
            })
        });
        let mut force = Col::<f64>::zeros(n);
        group.bench_function(format!("net_force_{elements}"), |b| {
            b.iter(|| beam.net_force(0.0, &q, zero.as_ref(), force.as_mut()))
        });
        let mut strains = [vec![0.0; elements], vec![0.0; elements], vec![0.0; elements]];
        group.bench_function(format!("net_force_and_strains_{elements}"), |b| {
            b.iter(|| {
                let out = force.as_mut().try_as_col_major_mut().expect("contiguous");
                let [e, s, c] = &mut strains;
                beam.internal_force_and_strains(&q, out.as_slice_mut(), [e, s, c])
            })
        });
        group.bench_function(format!("inertial_force_{elements}"), |b| {
            b.iter(|| beam.inertial_force(&q, zero.as_ref(), zero.as_ref(), force.as_mut()))
        });
        let dq = Col::<f64>::from_fn(n, |i| 1e-7 * ((i % 7) as f64 - 3.0));
        let mut moved = q.clone();
        group.bench_function(format!("displaced_{elements}"), |b| {
            b.iter(|| beam.displaced(&q, dq.as_ref(), &mut moved))
        });
        // The matrix and its factors made here too: a bench filtered by name runs alone.
        t.clear();
        beam.tangent(0.0, &q, zero.as_ref(), zero.as_ref(), w, &mut t);
        let band = beam.band().expect("banded");
        let mut lu = BandedLu::new();
        group.bench_function(format!("factor_{elements}"), |b| {
            b.iter(|| lu.factor(n, band, &t, 0.0).expect("factor"))
        });
        lu.factor(n, band, &t, 0.0).expect("factor");
        let mut rhs = Col::<f64>::from_fn(n, |i| (i % 7) as f64 - 3.0);
        group.bench_function(format!("solve_{elements}"), |b| {
            b.iter(|| lu.solve_in_place(rhs.as_mut(), 0.0).expect("solve"))
        });
        // A right-hand side at one end only, as a short step's correction near the ball: its
        // solution decays by orders of magnitude a node along the mass-dominated matrix.
        let mut local = Col::<f64>::zeros(n);
        group.bench_function(format!("solve_local_{elements}"), |b| {
            b.iter(|| {
                local.fill(0.0);
                local[n - 2] = 1.0;
                lu.solve_in_place(local.as_mut(), 0.0).expect("solve")
            })
        });
        let options = NewtonOptions { reuse_factorisation: true, ..NewtonOptions::default() };
        let mut integrator = Integrator::new(Scheme::hht(-0.05).expect("alpha"), options);
        let start = integrator.initial_state(&beam, 0.0, q.clone(), zero.clone()).expect("state");
        group.bench_function(format!("hht_step_{elements}"), |b| {
            b.iter(|| {
                let mut state = start.clone();
                integrator.step(&beam, &mut state, 2e-7).expect("step");
                state.t
            })
        });
    }
    group.finish();
}

/// The 3D beam the impact's fe method runs on with `solver.fe_model = "3d"` (the paper's strip
/// at 256 elements, bent and twisted): one net (internal) force, the same with the elements'
/// strains (as the impact asks it), one inertial force (with spin: the gyroscopic term), one
/// configuration update and one banded back-substitution with the impact's band
/// (half-bandwidth 11): the kernels of its every Newton iteration; and the tangent's assembly
/// and its banded factorisation, which every change of step (an event located) asks.
fn spatial(c: &mut Criterion) {
    use hht::{Band, BandedLu};
    use nalgebra::UnitQuaternion;
    let elements = 256;
    let beam = paper_cantilever(elements).expect("beam");
    let mut q = beam.reference_state();
    for (i, (x, r)) in q.positions.iter_mut().zip(&mut q.rotations).enumerate() {
        let s = i as f64 / elements as f64;
        x.z += 1e-3 * s * s;
        *r = UnitQuaternion::from_scaled_axis(Vector3::new(2e-3 * s, -2e-3 * s, 0.0));
    }
    let n = beam.ndof();
    let v = Col::<f64>::from_fn(n, |i| 1e-2 * ((i % 5) as f64 - 2.0));
    let a = Col::<f64>::from_fn(n, |i| 1e2 * ((i % 3) as f64 - 1.0));
    let dq = Col::<f64>::from_fn(n, |i| 1e-7 * ((i % 7) as f64 - 3.0));
    let mut group = c.benchmark_group("simo_beam/spatial");
    let mut force = Col::<f64>::zeros(n);
    group.bench_function(format!("net_force_{elements}"), |b| {
        b.iter(|| beam.net_force(0.0, &q, v.as_ref(), force.as_mut()))
    });
    let mut strains: [Vec<f64>; 6] = Default::default();
    group.bench_function(format!("net_force_and_strains_{elements}"), |b| {
        b.iter(|| beam.net_force_and_strains(0.0, &q, force.as_mut(), &mut strains))
    });
    group.bench_function(format!("inertial_force_{elements}"), |b| {
        b.iter(|| beam.inertial_force(&q, v.as_ref(), a.as_ref(), force.as_mut()))
    });
    let mut moved = q.clone();
    group.bench_function(format!("displaced_{elements}"), |b| {
        b.iter(|| beam.displaced(&q, dq.as_ref(), &mut moved))
    });
    let w = NewtonWeights { inertia: 1.0, force: 1.05, da: 1e13, dv: 1e6, dq: 1.0 };
    let mut t = Triplets::new();
    group.bench_function(format!("tangent_{elements}"), |b| {
        b.iter(|| {
            t.clear();
            beam.tangent(0.0, &q, v.as_ref(), a.as_ref(), w, &mut t);
        })
    });
    t.clear();
    beam.tangent(0.0, &q, v.as_ref(), a.as_ref(), w, &mut t);
    let mut lu = BandedLu::new();
    let band = Band { half_bandwidth: 11, border: 0 };
    group.bench_function(format!("factor_{elements}"), |b| {
        b.iter(|| lu.factor(n, band, &t, 0.0).expect("factor"))
    });
    lu.factor(n, band, &t, 0.0).expect("factor");
    let mut rhs = Col::<f64>::from_fn(n, |i| (i % 7) as f64 - 3.0);
    group.bench_function(format!("solve_{elements}"), |b| {
        b.iter(|| lu.solve_in_place(rhs.as_mut(), 0.0).expect("solve"))
    });
    group.finish();
}

criterion_group!(benches, element, assembly, statics, comparison_run, planar, spatial, frame_modes);
criterion_main!(benches);
