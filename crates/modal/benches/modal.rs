//! Cost of building modes (Euler-Bernoulli and Timoshenko) and transitions and of one exact
//! step (also as the solver takes it in contact and in free flight, with the next step's free
//! end displacement), for 64 and 256 modes; Timoshenko modes also at 4096 (the paper tip's
//! reference); the curvature of 256 modes at a point, shape by shape and all at once.
#![allow(clippy::expect_used, missing_docs)] // benches stop on bad set-up data, as tests do

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use modal::{Beam, Curvatures, Hold, ModalState, PointModes, Support, Transition};
use std::hint::black_box;

fn propagation(c: &mut Criterion) {
    let beam = Beam::rectangular(2.1e11, 7850.0, 0.025, 0.005, 1.15, Support::ClampedFree)
        .expect("valid beam");
    let mut group = c.benchmark_group("modal");
    for n in [64usize, 256] {
        group.bench_with_input(BenchmarkId::new("modes", n), &n, |b, &n| {
            b.iter(|| beam.modes(black_box(n)))
        });
        let modes = beam.modes(n).expect("modes");
        let tip = PointModes::new(&beam, &modes, 1.15, 0.0).expect("tip");
        group.bench_with_input(BenchmarkId::new("transition", n), &n, |b, _| {
            b.iter(|| Transition::new(&tip, black_box(1e-7), Hold::FirstOrder))
        });
        let t = Transition::new(&tip, 1e-7, Hold::FirstOrder).expect("transition");
        let mut s = ModalState::at_rest(n);
        group.bench_with_input(BenchmarkId::new("step", n), &n, |b, _| {
            b.iter(|| t.advance(&mut s, black_box(10.0), 11.0))
        });
        // The solver's contact step and free-flight step (the next step's free end
        // displacement summed in the same pass).
        group.bench_with_input(BenchmarkId::new("contact step", n), &n, |b, _| {
            b.iter(|| t.advance_predicting(&mut s, black_box(10.0), 11.0))
        });
        group.bench_with_input(BenchmarkId::new("free step", n), &n, |b, _| {
            b.iter(|| t.advance_predicting(&mut s, black_box(0.0), 0.0))
        });
    }
    // The paper's tip as a Timoshenko beam (steel, nu = 0.3, k = 5/6).
    let g = 2.1e11 / 2.6;
    let thick = beam
        .with_shear(5.0 / 6.0 * g * 0.025 * 0.005, 7850.0 * 0.025 * 0.005f64.powi(3) / 12.0)
        .expect("valid shear");
    for n in [64usize, 256, 4096] {
        group.bench_with_input(BenchmarkId::new("timoshenko modes", n), &n, |b, &n| {
            b.iter(|| thick.modes(black_box(n)))
        });
    }
    // The curvature of 256 Timoshenko modes at a point: each shape on its own (a library
    // sine, cosine and exponential a wave) and all at once (modal::Curvatures).
    let modes = thick.modes(256).expect("modes");
    group.bench_function("curvatures each/256", |b| {
        b.iter(|| {
            modes.iter().map(|m| m.shape.curvature_derivative(0, black_box(0.731))).sum::<f64>()
        })
    });
    let batch = Curvatures::new(modes.iter().map(|m| &m.shape));
    let mut row = vec![0.0; modes.len()];
    group.bench_function("curvatures at once/256", |b| {
        b.iter(|| batch.at(black_box(0.731), &mut [row.as_mut_slice()]))
    });
    group.finish();
}

criterion_group!(benches, propagation);
criterion_main!(benches);
