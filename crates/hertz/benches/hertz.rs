//! Cost of one contact-law evaluation (the inner loop of every implicit contact step).
#![allow(clippy::expect_used, missing_docs)] // benches stop on bad set-up data, as tests do

use criterion::{criterion_group, criterion_main, Criterion};
use hertz::{ContactLaw, Hertz, Material, Thornton, ThorntonState};
use std::hint::black_box;

fn laws(c: &mut Criterion) {
    let steel = Material::new(2.1e11, 0.3).expect("valid material");
    let hertz = Hertz::between(&steel, &steel, 0.005).expect("valid contact");
    let thornton = Thornton::from_yield_stress(hertz, 3.4e8).expect("valid law");
    let state = ThorntonState { max_approach: 2e-5 };
    c.bench_function("hertz force", |b| b.iter(|| hertz.force(&(), black_box(1.3e-5), 0.0)));
    c.bench_function("thornton force (unloading)", |b| {
        b.iter(|| thornton.force(&state, black_box(1.9e-5), 0.0))
    });
}

criterion_group!(benches, laws);
criterion_main!(benches);
