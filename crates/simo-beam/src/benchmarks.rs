//! The standard problems of validation/REFERENCES.md section 3, set up once so that the tests, the
//! `cargo xtask validate` cases and the benches run exactly the same models.

use crate::error::BeamError;
use crate::mesh::Mesh;
use crate::model::{BeamModel, Load, Profile, Support};
use crate::modes::bending_frequencies;
use crate::section::{Material, Section};
use crate::statics::{solve_static, StaticOptions};
use faer::Col;
use hht::{Integrator, Model, NewtonOptions, Scheme};
use nalgebra::Vector3;

/// A section given by its stiffnesses, with unit mass per length (statics ignores inertia).
pub fn stiffness_section(ea: f64, ga: f64, gj: f64, ei: f64) -> Section {
    Section { ea, ga2: ga, ga3: ga, gj, ei2: ei, ei3: ei, rho_a: 1.0, rho_i: [1e-3; 3] }
}

/// A cantilever along x, clamped at x = 0, section axis E3 = z.
///
/// # Errors
/// From the mesh.
pub fn cantilever(length: f64, elements: usize, section: Section) -> Result<BeamModel, BeamError> {
    let mesh = Mesh::straight(
        Vector3::zeros(),
        Vector3::new(length, 0.0, 0.0),
        elements,
        section,
        Vector3::z(),
    )?;
    BeamModel::new(mesh)?.support(0, Support::Clamped)
}

fn dead(node: usize, force: Vector3<f64>, moment: Vector3<f64>) -> Load {
    Load { node, force, moment, follower: false, profile: Profile::Constant }
}

/// Roll-up (validation/REFERENCES.md 3.1): a cantilever (EI = 2, L = 1) under the end moment
/// `M = turns 2 pi EI / L` about -y, which bends it into `turns` full circles, in one load
/// step. Returns (tip position (m), total tip rotation (rad), Newton iterations).
///
/// # Errors
/// From the static solver.
pub fn roll_up(turns: f64, elements: usize) -> Result<(Vector3<f64>, f64, usize), BeamError> {
    let ei = 2.0;
    let model = cantilever(1.0, elements, stiffness_section(1e6 * ei, 1e6 * ei, ei, ei))?;
    let moment = turns * 2.0 * std::f64::consts::PI * ei;
    let model = model.load(dead(elements, Vector3::zeros(), Vector3::new(0.0, -moment, 0.0)))?;
    let s = solve_static(&model, StaticOptions::default())?;
    // The total rotation is the sum of the element rotations (each below pi), which a single
    // quaternion cannot hold beyond one turn.
    let rotation: f64 = model
        .mesh()
        .elements
        .iter()
        .map(|e| {
            let [a, b] = e.nodes;
            let strains = e.strains(
                [&s.state.positions[a], &s.state.positions[b]],
                [&s.state.rotations[a], &s.state.rotations[b]],
            );
            -strains.kappa.y * e.length
        })
        .sum();
    Ok((s.state.positions[elements], rotation, s.iterations.iter().sum()))
}

/// Mattiasson's cantilever (validation/REFERENCES.md 3.3): dead tip load with k = P L^2 / EI, slender
/// (EA = GA = 1e7 EI / L^2, so extension and shear stay below 1e-6), in `load_steps`
/// increments. Returns [u/L, w/L, tip rotation (rad)].
///
/// # Errors
/// From the static solver.
pub fn mattiasson(k: f64, elements: usize, load_steps: usize) -> Result<[f64; 3], BeamError> {
    let model = cantilever(1.0, elements, stiffness_section(1e7, 1e7, 1.0, 1.0))?.load(dead(
        elements,
        Vector3::new(0.0, 0.0, -k),
        Vector3::zeros(),
    ))?;
    let s = solve_static(&model, StaticOptions { load_steps, ..StaticOptions::default() })?;
    let tip = s.state.positions[elements];
    let rotation = s.state.rotations[elements].scaled_axis().y;
    Ok([1.0 - tip.x, -tip.z, rotation])
}

/// The 45-degree bend (validation/REFERENCES.md 3.2): arc of radius 100 from the clamp at the origin to
/// the undeformed tip (29.29, 70.71, 0), unit square section with the stiffness data of
/// Bathe & Bolourchi as tabulated by kynema (EA = 1e7, kGA = 4.16667e6, GJ = EI = 8.333e5),
/// dead tip load P along z in `load_steps` equal increments. Returns the tip position.
///
/// # Errors
/// From the static solver.
pub fn bend45(p: f64, elements: usize, load_steps: usize) -> Result<Vector3<f64>, BeamError> {
    let section = stiffness_section(1e7, 4.16667e6, 8.333e5, 8.333e5);
    let mesh = Mesh::arc(
        Vector3::new(100.0, 0.0, 0.0),
        100.0,
        -Vector3::x(),
        -Vector3::z(),
        std::f64::consts::FRAC_PI_4,
        elements,
        section,
    )?;
    let model = BeamModel::new(mesh)?.support(0, Support::Clamped)?.load(dead(
        elements,
        Vector3::new(0.0, 0.0, p),
        Vector3::zeros(),
    ))?;
    let s = solve_static(&model, StaticOptions { load_steps, ..StaticOptions::default() })?;
    Ok(s.state.positions[elements])
}

/// Linear tip deflection of a slender cantilever (L/h = 1000, square steel section, so
/// kGA L^2 / EI ~ 8e5) under a small tip load, over `PL^3/3EI + PL/kGA`: shear locking shows as
/// a ratio far below 1.
///
/// # Errors
/// From the static solver.
pub fn shear_locking_ratio(elements: usize) -> Result<f64, BeamError> {
    let h = 1e-3;
    let length = 1000.0 * h;
    let steel = Material::new(2.1e11, 0.3, 7850.0)?;
    let section = Section::rectangle(&steel, h, h)?;
    let p = 1e-6;
    let model = cantilever(length, elements, section)?.load(dead(
        elements,
        Vector3::new(0.0, 0.0, p),
        Vector3::zeros(),
    ))?;
    let s = solve_static(&model, StaticOptions::default())?;
    let exact = p * length.powi(3) / (3.0 * section.ei2) + p * length / section.ga3;
    Ok(s.state.positions[elements].z / exact)
}

/// The paper's cantilever: steel (E = 2.1e11 Pa, nu = 0.3, 7850 kg/m^3), 25 x 5 mm, 1.15 m.
///
/// # Errors
/// From the mesh.
pub fn paper_cantilever(elements: usize) -> Result<BeamModel, BeamError> {
    let steel = Material::new(2.1e11, 0.3, 7850.0)?;
    cantilever(1.15, elements, Section::rectangle(&steel, 0.025, 0.005)?)
}

/// Natural frequencies (Hz) of the first `count` bending modes of the paper's cantilever in
/// its flexible plane (deflection along z, the 5 mm direction), picked out of the 3D spectrum
/// as the modes whose shape lives mostly in z translation and rotation about y.
///
/// # Errors
/// From the eigen solver.
pub fn paper_cantilever_flexural_frequencies(
    elements: usize,
    count: usize,
) -> Result<Vec<f64>, BeamError> {
    let model = paper_cantilever(elements)?;
    let omegas = bending_frequencies(&model, count)?;
    Ok(omegas.into_iter().map(|w| w / (2.0 * std::f64::consts::PI)).collect())
}

/// Samples (t (s), tip z (m)) and the total energy (J) after the load is removed.
pub type TipHistory = (Vec<(f64, f64)>, Vec<f64>);

/// The right-angle cantilever of Simo & Vu-Quoc (1988), validation/REFERENCES.md 3.4: legs of 10 (clamp
/// at (0, 10, 0), elbow at (10, 10, 0), tip at (10, 0, 0)), EA = GA = 1e6, EI = GJ = 1e3,
/// rho A = 1, rho I = diag(20, 10, 10) (SVQ's data), out-of-plane elbow force 50 t on [0, 1],
/// 50 (2 - t) on [1, 2], trapezoidal rule (alpha = 0) with step `dt`. Returns samples
/// (t (s), tip z (m)) every step and the total energy after the load is removed.
///
/// # Errors
/// From the integrator.
pub fn right_angle_cantilever(
    elements_per_leg: usize,
    dt: f64,
    end_time: f64,
) -> Result<TipHistory, BeamError> {
    let section = Section { rho_i: [20.0, 10.0, 10.0], ..stiffness_section(1e6, 1e6, 1e3, 1e3) };
    let n = elements_per_leg;
    let leg1 = Mesh::straight(
        Vector3::new(0.0, 10.0, 0.0),
        Vector3::new(10.0, 10.0, 0.0),
        n,
        section,
        Vector3::z(),
    )?;
    let leg2 = Mesh::straight(
        Vector3::new(10.0, 10.0, 0.0),
        Vector3::new(10.0, 0.0, 0.0),
        n,
        section,
        Vector3::z(),
    )?;
    let profile = Profile::Table(vec![(0.0, 0.0), (1.0, 50.0), (2.0, 0.0)]);
    let model = BeamModel::new(leg1.join(leg2)?)?.support(0, Support::Clamped)?.load(Load {
        node: n,
        force: Vector3::new(0.0, 0.0, 1.0),
        moment: Vector3::zeros(),
        follower: false,
        profile,
    })?;
    let mut integrator = Integrator::new(Scheme::trapezoidal(), NewtonOptions::default());
    let mut state =
        integrator.initial_state(&model, 0.0, model.reference_state(), Col::zeros(model.ndof()))?;
    let steps = (end_time / dt).round() as usize;
    let mut tip = vec![(0.0, 0.0)];
    let mut energy = Vec::new();
    for _ in 0..steps {
        integrator.step(&model, &mut state, dt)?;
        tip.push((state.t, state.q.positions[2 * n].z));
        if state.t > 2.0 + 1e-9 {
            energy.push(model.strain_energy(&state.q) + model.kinetic_energy(state.v.as_ref()));
        }
    }
    Ok((tip, energy))
}
