//! One HHT step of a single oscillator: the integrator's own overhead.
#![allow(clippy::expect_used, missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion};
use faer::Col;
use hht::{Integrator, NewtonOptions, Oscillator, Scheme};

fn step(c: &mut Criterion) {
    let model = Oscillator::undamped(1.0).expect("omega");
    let mut integrator =
        Integrator::new(Scheme::hht(-0.1).expect("alpha"), NewtonOptions::default());
    let mut state = integrator.initial_state(&model, 0.0, 1.0, Col::zeros(1)).expect("state");
    c.bench_function("hht/oscillator_step", |b| {
        b.iter(|| integrator.step(&model, &mut state, 1e-2).expect("step"))
    });
}

criterion_group!(benches, step);
criterion_main!(benches);
