//! Whole simulations: the paper's tip scene (h = 0.2 m, 5 ms) with 4, 64 and 256 modes (and
//! with 256 modes on uniform steps, and gravity off: the scipy peer's case), its
//! first contact with 256 modes, the same scene with the finite-element method (default graded
//! mesh; first contact only, and 5 ms; 256 equal elements over 1 ms, gravity off, the peer
//! comparison, planar and forced into 3D), the frame of validation/scenes/frame-impact.toml
//! over 2 ms by the modal method on its own modes (eigen-solution included) and by the fe
//! method, and the half-space closed-form case.
#![allow(clippy::expect_used, missing_docs)] // benches stop on bad set-up data, as tests do

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use impact::{simulate, Scene};

const PAPER: &str = include_str!("../../../validation/scenes/paper-tip.toml");
const FRAME: &str = include_str!("../../../validation/scenes/frame-impact.toml");
const HALF_SPACE: &str = include_str!("../../../validation/scenes/half-space-r10.toml");

fn scenes(c: &mut Criterion) {
    let mut group = c.benchmark_group("impact");
    group.sample_size(10);
    for modes in [4usize, 64, 256] {
        let mut scene = Scene::from_toml(PAPER).expect("valid scene");
        scene.solver.modes = Some(modes);
        group.bench_with_input(BenchmarkId::new("paper tip 5 ms", modes), &scene, |b, s| {
            b.iter(|| simulate(s))
        });
    }
    // The scipy peer's case (validation/peers/scipy_modal_tip.py): 256 modes, gravity off.
    let mut peer = Scene::from_toml(PAPER).expect("valid scene");
    peer.solver.modes = Some(256);
    peer.impact.gravity = false;
    group.bench_function("paper tip 5 ms gravity off/256", |b| b.iter(|| simulate(&peer)));
    // The scheme before the adaptive step: uniform steps, 1000 per pulse (energy balance
    // 7e-7 on the 64-mode run, against 4e-7 for the adaptive default).
    let mut uniform = Scene::from_toml(PAPER).expect("valid scene");
    uniform.solver.modes = Some(256);
    uniform.solver.samples_per_pulse = Some(1000);
    uniform.solver.adaptive_step = Some(false);
    group.bench_function("paper tip 5 ms uniform 1000 per pulse/256", |b| {
        b.iter(|| simulate(&uniform))
    });
    // The modal method at the FE default's accuracy on the first contact (256 modes: duration
    // 0.05 % from converged; the FE default mesh 0.17 %).
    let mut first = Scene::from_toml(PAPER).expect("valid scene");
    first.solver.modes = Some(256);
    first.solver.end_time = Some(6e-5);
    group.bench_function("modal paper tip first contact 256", |b| b.iter(|| simulate(&first)));
    for (label, end) in [("fe paper tip first contact", 6e-5), ("fe paper tip 5 ms", 5e-3)] {
        let mut scene = Scene::from_toml(PAPER).expect("valid scene");
        scene.solver.method = impact::MethodName::Fe;
        scene.solver.modes = None;
        scene.solver.end_time = Some(end);
        group.bench_function(label, |b| b.iter(|| simulate(&scene)));
    }
    // The peer comparison: 256 equal elements, 1 ms, gravity off (validation/peers/).
    let mut peer = Scene::from_toml(PAPER).expect("valid scene");
    peer.solver.method = impact::MethodName::Fe;
    peer.solver.modes = None;
    peer.solver.elements = Some(256);
    peer.solver.end_time = Some(1e-3);
    peer.impact.gravity = false;
    group.bench_function("fe paper tip 1 ms 256 equal elements", |b| b.iter(|| simulate(&peer)));
    // The same run forced into the 3D beam (issue "impact anywhere": at most 3x the planar).
    let mut three_d = peer.clone();
    three_d.solver.fe_model = Some(impact::FeModelName::ThreeD);
    group.bench_function("fe paper tip 1 ms 256 equal elements 3d", |b| {
        b.iter(|| simulate(&three_d))
    });
    // The chatter of the time-convergence test: 512 equal elements, the first 8 contacts.
    let mut chatter = peer.clone();
    chatter.solver.elements = Some(512);
    chatter.solver.end_time = Some(1.05e-3);
    group.bench_function("fe paper tip 1.05 ms 512 equal elements", |b| {
        b.iter(|| simulate(&chatter))
    });
    // A structure by Goldsmith's method on its 3D beam's modes (80 elements, 240 modes below
    // omega t_c = 20; the eigen-solution two thirds of it) and by the fe method, same mesh.
    let fe_frame = Scene::from_toml(FRAME).expect("valid scene");
    let mut modal_frame = fe_frame.clone();
    modal_frame.solver.method = impact::MethodName::Modal;
    group.bench_function("frame 2 ms modal fe basis", |b| b.iter(|| simulate(&modal_frame)));
    group.bench_function("frame 2 ms fe", |b| b.iter(|| simulate(&fe_frame)));
    let hs = Scene::from_toml(HALF_SPACE).expect("valid scene");
    group.bench_function("half-space", |b| b.iter(|| simulate(&hs)));
    group.finish();
}

criterion_group!(benches, scenes);
criterion_main!(benches);
