//! Off-centre strikes: the torsion modes of the modal method against the 3D Simo beam's, the
//! static stiffness of the struck face, and the checks of `impact.offset`
//! (validation/REFERENCES.md 1.9).
#![allow(clippy::unwrap_used)] // a test stops on a bad fixture

use impact::{simulate, Plan, Scene};
use nalgebra::Vector3;
use simo_beam::{natural_modes, BeamModel, Material, Mesh, Section, Support};

const E: f64 = 2.1e11;
const NU: f64 = 0.3;
const RHO: f64 = 7850.0;
const WIDTH: f64 = 0.025;
const THICKNESS: f64 = 0.005;
const LENGTH: f64 = 1.15;

/// The paper's strip in torsion, clamped-free, as the modal method takes it.
fn strip() -> modal::Torsion {
    let (j, _) = modal::rectangle_torsion(WIDTH, THICKNESS);
    let polar = (WIDTH * THICKNESS.powi(3) + THICKNESS * WIDTH.powi(3)) / 12.0;
    modal::Torsion::new(
        E / (2.0 * (1.0 + NU)) * j,
        RHO * polar,
        LENGTH,
        modal::Support::ClampedFree,
    )
    .unwrap()
}

/// The first three torsion frequencies (rad/s) of the 3D Simo beam (the modes whose shape
/// lies mostly in the rotation about the axis), clamped at x = 0, on `elements` elements.
fn fe_torsion(elements: usize) -> Vec<f64> {
    let steel = Material::new(E, NU, RHO).unwrap();
    let section = Section::rectangle(&steel, WIDTH, THICKNESS).unwrap();
    let mesh = Mesh::straight(
        Vector3::zeros(),
        Vector3::new(LENGTH, 0.0, 0.0),
        elements,
        section,
        Vector3::z(),
    )
    .unwrap();
    let model = BeamModel::new(mesh).unwrap().support(0, Support::Clamped).unwrap();
    let mut out = Vec::new();
    for mode in natural_modes(&model, 6 * elements).unwrap() {
        let (mut twist, mut total) = (0.0, 0.0);
        for node in 0..=elements {
            for k in 0..6 {
                if let Some(i) = model.dof(node, k) {
                    let s = mode.shape[i] * mode.shape[i];
                    total += s;
                    if k == 3 {
                        twist += s;
                    }
                }
            }
        }
        if twist > 0.9 * total {
            out.push(mode.omega);
        }
        if out.len() == 3 {
            break;
        }
    }
    out
}

#[test]
fn torsion_frequencies_meet_the_3d_beam() {
    // omega_n = (n - 1/2) pi c_t / L for the clamped-free strip (1570, 4710, 7850 rad/s). The
    // 3D beam's two-node elements (lumped rotary inertia) are low by about (k h)^2 / 24,
    // second order: the error must shrink about fourfold from 32 to 64 elements and be within
    // 1e-3 at 64 (its torsion constant, Roark's formula, is within 1e-4 of the exact series).
    let analytic: Vec<f64> = strip().modes(3).iter().map(|m| m.omega).collect();
    let (coarse, fine) = (fe_torsion(32), fe_torsion(64));
    for n in 0..3 {
        let (ec, ef) = ((coarse[n] / analytic[n] - 1.0).abs(), (fine[n] / analytic[n] - 1.0).abs());
        assert!(ef < 1e-3, "mode {n}: {} vs {}", fine[n], analytic[n]);
        if n > 0 {
            // (Mode 1's error is at the torsion constant's scale, where no order shows.)
            assert!((2.5..5.5).contains(&(ec / ef)), "mode {n}: {ec:e} -> {ef:e}");
        }
    }
}

/// The paper's tip (gravity off, 0.2 ms) struck `offset` m off the centreline.
fn tip(offset: &str, solver: &str) -> Result<Scene, impact::ImpactError> {
    Scene::from_toml(&format!(
        r#"
name = "tip-offset"
[beam]
length = {LENGTH}
width = {WIDTH}
thickness = {THICKNESS}
support = "clamped-free"
youngs_modulus = {E}
poisson_ratio = {NU}
density = {RHO}
[ball]
radius = 0.005
mass = 0.009
youngs_modulus = {E}
poisson_ratio = {NU}
density = {RHO}
[impact]
position = 1.1
offset = {offset}
drop_height = 0.2
gravity = false
[solver]
end_time = 0.0002
{solver}
"#
    ))
}

#[test]
fn the_struck_face_is_as_stiff_as_bending_and_twist_in_series() {
    // A static force F at (c, e) on a cantilever: the face moves F (c^3 / (3 EI) + e^2 c / GJ).
    let scene =
        tip("0.01", "method = \"modal\"\nmodes = 64\nbeam_theory = \"euler-bernoulli\"").unwrap();
    let report = simulate(&scene).unwrap().report;
    let ei = E * WIDTH * THICKNESS.powi(3) / 12.0;
    let c: f64 = 1.1;
    let flexibility = c.powi(3) / (3.0 * ei) + 0.01f64.powi(2) * c / strip().rigidity();
    let k = report.static_stiffness.unwrap();
    assert!((k * flexibility - 1.0).abs() < 1e-12, "{k} vs {}", 1.0 / flexibility);
    let twist = report.max_twist.unwrap();
    assert!(twist > 0.0 && report.max_twist_time.unwrap() <= 0.0002, "{twist}");
    assert!(report.plan.reasons.iter().any(|r| r.contains("Saint-Venant torsion modes")));
    // A centred strike reports no twist.
    let centred = simulate(&tip("0.0", "method = \"modal\"\nmodes = 64").unwrap()).unwrap();
    assert_eq!(centred.report.max_twist, None);
}

#[test]
fn an_offset_off_the_face_or_on_the_planar_beam_is_refused() {
    for bad in ["0.0126", "-0.013", "nan"] {
        let err = Plan::new(&tip(bad, "").unwrap()).unwrap_err().to_string();
        assert!(err.contains("impact.offset") && err.contains("beam.width/2"), "{bad}: {err}");
    }
    let err = Plan::new(&tip("0.01", "method = \"fe\"").unwrap()).unwrap_err().to_string();
    assert!(err.contains("impact.offset") && err.contains("solver.method = \"modal\""), "{err}");
    // The patch (radius ~0.37 mm) past the edge: allowed, with a warning giving the ratio.
    let plan = Plan::new(&tip("0.0123", "").unwrap()).unwrap();
    assert!(
        plan.warnings().iter().any(|w| w.contains("past the face's edge")),
        "{:?}",
        plan.warnings()
    );
}
