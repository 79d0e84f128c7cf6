//! The banded Lanczos modal solver (`simo_beam::modes_below`, crates/simo-beam/src/eigen.rs)
//! against the dense one and against closed forms (validation/REFERENCES.md 1.10).
#![allow(clippy::unwrap_used)] // a test stops on a bad fixture

use hht::{Model, NewtonWeights, Triplets};
use nalgebra::Vector3;
use simo_beam::{modes_below, natural_modes, BeamModel, Material, Mesh, Section, Support};

const E: f64 = 2.1e11;
const RHO: f64 = 7850.0;

/// A straight steel strip along x, `b` wide (along y) and `t` thick (along z), on `n` elements.
fn strip(n: usize, (b, t, l): (f64, f64, f64)) -> BeamModel {
    let section = Section::rectangle(&Material::new(E, 0.3, RHO).unwrap(), b, t).unwrap();
    let mesh =
        Mesh::straight(Vector3::zeros(), Vector3::new(l, 0.0, 0.0), n, section, Vector3::z())
            .unwrap();
    BeamModel::new(mesh).unwrap()
}

/// Whether a mode bends across the thickness (most of its shape in z and the rotation about y).
fn bends_across(model: &BeamModel, shape: &faer::Col<f64>) -> bool {
    let nodes = model.mesh().positions.len();
    let (mut bending, mut total) = (0.0, 0.0);
    for node in 0..nodes {
        for k in 0..6 {
            if let Some(i) = model.dof(node, k) {
                total += shape[i] * shape[i];
                if k == 2 || k == 4 {
                    bending += shape[i] * shape[i];
                }
            }
        }
    }
    bending > 0.5 * total
}

/// `K` and `M` of `model` at rest, as triplets.
fn matrices(model: &BeamModel) -> (Triplets, Triplets) {
    let n = model.ndof();
    let q = model.reference_state();
    let zero = faer::Col::<f64>::zeros(n);
    let mut k = Triplets::new();
    model.tangent(0.0, &q, zero.as_ref(), zero.as_ref(), NewtonWeights::stiffness(), &mut k);
    let mut m = Triplets::new();
    model.tangent(0.0, &q, zero.as_ref(), zero.as_ref(), NewtonWeights::mass(), &mut m);
    (k, m)
}

/// `A x` for the symmetric part of `a`.
fn times(a: &Triplets, x: &faer::Col<f64>) -> Vec<f64> {
    let mut y = vec![0.0; x.nrows()];
    for (r, c, v) in a.iter() {
        y[r] += 0.5 * v * x[c];
        y[c] += 0.5 * v * x[r];
    }
    y
}

#[test]
fn the_banded_lanczos_modes_are_the_dense_solver_s() {
    // The paper's strip (25 x 5 mm, 1.15 m) clamped at x = 0 on 40 elements (240 unknowns):
    // every mode below 2e5 rad/s (bending both ways, torsion, extension) as the dense inverted
    // solution counts them, the frequencies within 1e-8 (each solution's round-off is about
    // 1e-9 on the first mode, whose stiffness is 1e-12 of the strip's stiffest), each shape an
    // eigenvector to 1e-8 (|K phi - lambda M phi| / |lambda M phi|; the dense solution's own
    // shapes near 8e4 rad/s are off by up to 2e-4 by that measure), M-orthonormal to 1e-8 (modes of different spectrum slices are orthogonal as far as they are exact), and
    // the first 20 the dense solution's to 1e-6 (up to sign).
    let model = strip(40, (0.025, 0.005, 1.15)).support(0, Support::Clamped).unwrap();
    let omega_max = 2e5;
    let lanczos = modes_below(&model, omega_max).unwrap();
    let all = natural_modes(&model, model.ndof()).unwrap();
    let dense: Vec<_> = all.iter().filter(|m| m.omega <= omega_max).collect();
    assert_eq!(lanczos.len(), dense.len());
    assert!(lanczos.len() > 60, "{} modes test little", lanczos.len());
    let (k, m) = matrices(&model);
    let m_shapes: Vec<Vec<f64>> = lanczos.iter().map(|a| times(&m, &a.shape)).collect();
    for (i, (a, b)) in lanczos.iter().zip(dense).enumerate() {
        assert!((a.omega / b.omega - 1.0).abs() < 1e-8, "mode {i}: {} vs {}", a.omega, b.omega);
        let lambda = a.omega * a.omega;
        let k_phi = times(&k, &a.shape);
        let residual: f64 = k_phi
            .iter()
            .zip(&m_shapes[i])
            .map(|(x, y)| (x - lambda * y).powi(2))
            .sum::<f64>()
            .sqrt();
        let scale: f64 = m_shapes[i].iter().map(|y| (lambda * y).powi(2)).sum::<f64>().sqrt();
        assert!(residual <= 1e-8 * scale, "mode {i}: residual {:e}", residual / scale);
        for (j, mj) in m_shapes.iter().enumerate() {
            let product: f64 = a.shape.iter().zip(mj).map(|(x, y)| x * y).sum();
            let expected = if i == j { 1.0 } else { 0.0 };
            assert!(
                (product - expected).abs() < 1e-10,
                "modes {i}, {j}: phi^T M phi = {product:e}"
            );
        }
        if i < 20 {
            let dot: f64 = a.shape.iter().zip(b.shape.iter()).map(|(x, y)| x * y).sum();
            let sign = if dot < 0.0 { -1.0 } else { 1.0 };
            let size = b.shape.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            let gap = a
                .shape
                .iter()
                .zip(b.shape.iter())
                .fold(0.0f64, |g, (x, y)| g.max((sign * x - y).abs()));
            assert!(gap < 1e-6 * size, "mode {i}: shape differs by {gap:e} of {size:e}");
        }
    }
}

#[test]
fn a_free_beam_s_six_rigid_body_modes_are_counted_by_a_tolerance() {
    // Free-free: three translations and three rotations at omega = 0 (reported exactly 0: below
    // the stiffness' round-off, 1e-13 of its largest K_ii / M_ii), then the elastic modes; the first bending across the thickness at
    // (4.7300408)^2 sqrt(EI / rho A) / L^2 within 1e-3 on 40 elements.
    let (b, t, l) = (0.025, 0.005, 1.15);
    let model = strip(40, (b, t, l));
    let modes = modes_below(&model, 200.0).unwrap();
    let rigid = modes.iter().filter(|m| m.omega == 0.0).count();
    assert_eq!(rigid, 6, "{:?}", modes.iter().map(|m| m.omega).collect::<Vec<_>>());
    let first = modes.iter().find(|m| m.omega > 0.0 && bends_across(&model, &m.shape)).unwrap();
    let exact =
        4.730_040_7_f64.powi(2) * (E * b * t.powi(3) / 12.0 / (RHO * b * t)).sqrt() / (l * l);
    assert!((first.omega / exact - 1.0).abs() < 1e-3, "{} vs {exact}", first.omega);
}

#[test]
fn a_tip_mass_gives_its_characteristic_roots_at_the_element_s_order() {
    // A thin strip (25 x 1 mm, 1 m: shear and rotary inertia move its lowest modes by < 1e-5)
    // clamped at x = 0 with a tip mass equal to its own (mu = 1): lambda^2 = omega L^2
    // sqrt(rho A / EI) = 1.557298, 16.25009, 50.89584 (Blevins, table 8-8; validation/
    // REFERENCES.md 1.10). The 3D beam on 128, 256 and 512 elements (3078 unknowns, beyond the
    // dense solver): within 1e-4 at 512, and the mesh's share of the error (the differences of
    // successive meshes; the rest is the rod's shear and rotary inertia) falling about
    // fourfold a halving (second order).
    let (b, t, l) = (0.025, 0.001, 1.0);
    let exact = [1.557_297_9, 16.250_085_2, 50.895_842_8];
    let scale = l * l * (RHO * b * t / (E * b * t.powi(3) / 12.0)).sqrt();
    let lambda2 = |n: usize| -> Vec<f64> {
        let model = strip(n, (b, t, l))
            .support(0, Support::Clamped)
            .unwrap()
            .attach_mass(n, RHO * b * t * l, [0.0; 3])
            .unwrap();
        let modes = modes_below(&model, 55.0 / scale).unwrap();
        modes.iter().filter(|m| bends_across(&model, &m.shape)).map(|m| m.omega * scale).collect()
    };
    let (coarse, middle, fine) = (lambda2(128), lambda2(256), lambda2(512));
    assert_eq!(fine.len(), 3, "{fine:?}");
    for k in 0..3 {
        assert!((fine[k] / exact[k] - 1.0).abs() < 1e-4, "mode {k}: {} vs {}", fine[k], exact[k]);
        // The first mode's mesh error is below 1e-7 already at 128 elements: its differences are
        // round-off's, not the mesh's.
        let order = (coarse[k] - middle[k]) / (middle[k] - fine[k]);
        if k > 0 {
            assert!((3.5..4.5).contains(&order), "mode {k}: successive differences fall {order}x");
        }
    }
}

#[test]
fn a_cutoff_that_is_not_a_frequency_is_refused() {
    let model = strip(4, (0.025, 0.005, 1.15)).support(0, Support::Clamped).unwrap();
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = modes_below(&model, bad).unwrap_err().to_string();
        assert!(e.contains("cutoff"), "{bad}: {e}");
    }
    assert!(modes_below(&model, 1e-3).unwrap().is_empty());
}

#[test]
fn a_stepped_cantilever_gives_its_transfer_matrix_frequencies() {
    // A 25 mm wide steel strip clamped at x = 0: 0.5 m of 2 mm thickness, then 0.5 m of 1 mm
    // (a stepped member: one mesh per piece, each with its own section, joined on one centre
    // line). Its first five bending frequencies across the thickness by Euler-Bernoulli
    // transfer matrices (validation/peers/stepped_beam_reference.py, brentq to 1e-14;
    // validation/REFERENCES.md 1.12): 12.4856002911, 44.3981788511, 131.6766130036,
    // 244.1812564566, 405.4485447109 rad/s. The 3D beam at 64, 128 and 256 elements a piece:
    // within 1e-4 at 256 (shear and rotary inertia move the fifth by about 1e-5), the mesh's
    // share of the error falling about fourfold a halving.
    let exact = [12.4856002911, 44.3981788511, 131.6766130036, 244.1812564566, 405.4485447109];
    let steel = Material::new(E, 0.3, RHO).unwrap();
    let frequencies = |n: usize| -> Vec<f64> {
        let piece = |x0: f64, t: f64| {
            let section = Section::rectangle(&steel, 0.025, t).unwrap();
            Mesh::straight(
                Vector3::new(x0, 0.0, 0.0),
                Vector3::new(x0 + 0.5, 0.0, 0.0),
                n,
                section,
                Vector3::z(),
            )
            .unwrap()
        };
        let mesh = piece(0.0, 0.002).join(piece(0.5, 0.001)).unwrap();
        let model = BeamModel::new(mesh).unwrap().support(0, Support::Clamped).unwrap();
        let modes = modes_below(&model, 420.0).unwrap();
        modes.iter().filter(|m| bends_across(&model, &m.shape)).map(|m| m.omega).collect()
    };
    let (coarse, middle, fine) = (frequencies(64), frequencies(128), frequencies(256));
    assert_eq!(fine.len(), 5, "{fine:?}");
    for k in 0..5 {
        assert!((fine[k] / exact[k] - 1.0).abs() < 1e-4, "mode {k}: {} vs {}", fine[k], exact[k]);
        let order = (coarse[k] - middle[k]) / (middle[k] - fine[k]);
        if k > 0 {
            assert!((3.5..4.5).contains(&order), "mode {k}: successive differences fall {order}x");
        }
    }
}

#[test]
fn a_square_section_s_double_frequencies_are_both_found() {
    // A 10 x 10 mm steel bar, 1 m, clamped: bending the same both ways, so each bending
    // frequency is double (the hard case of a single-vector Lanczos: one start vector sees one
    // direction of a double eigenspace in exact arithmetic; round-off brings the other in,
    // and the inertia count makes sure both are there). The first pair at 1.8751041^2
    // sqrt(EI / rho A) / L^2 = 52.498 rad/s (Euler-Bernoulli) within 2e-4 (shear and rotary
    // inertia), the two members within 1e-10 of each other, and as many modes as the count.
    let model = strip(64, (0.01, 0.01, 1.0)).support(0, Support::Clamped).unwrap();
    let modes = modes_below(&model, 2e4).unwrap();
    let all = natural_modes(&model, model.ndof()).unwrap();
    assert_eq!(modes.len(), all.iter().filter(|m| m.omega <= 2e4).count());
    let exact = 1.875_104_1_f64.powi(2) * (E * 0.01 * 0.01 / 12.0 / RHO).sqrt();
    for pair in [&modes[0..2], &modes[2..4], &modes[4..6]] {
        assert!(
            (pair[1].omega / pair[0].omega - 1.0).abs() < 1e-10,
            "{} vs {}",
            pair[0].omega,
            pair[1].omega
        );
    }
    assert!((modes[0].omega / exact - 1.0).abs() < 2e-4, "{} vs {exact}", modes[0].omega);
}

#[test]
fn a_frame_s_modes_are_the_dense_solver_s() {
    // A right angle of the paper's strip (two 0.5 m legs of 12 elements, a rigid corner,
    // clamped at the start): the corner's constant frame offsets make the bandwidth and the
    // coupling of bending and twist across it. Every mode below 1e5 rad/s as the dense solution
    // counts and places them, to 1e-8.
    let steel = Material::new(E, 0.3, RHO).unwrap();
    let section = Section::rectangle(&steel, 0.025, 0.005).unwrap();
    let leg =
        |a: Vector3<f64>, b: Vector3<f64>| Mesh::straight(a, b, 12, section, Vector3::z()).unwrap();
    let corner = Vector3::new(0.5, 0.0, 0.0);
    let mesh =
        leg(Vector3::zeros(), corner).join(leg(corner, Vector3::new(0.5, 0.5, 0.0))).unwrap();
    let model = BeamModel::new(mesh).unwrap().support(0, Support::Clamped).unwrap();
    let lanczos = modes_below(&model, 1e5).unwrap();
    let dense: Vec<f64> = natural_modes(&model, model.ndof())
        .unwrap()
        .into_iter()
        .map(|m| m.omega)
        .filter(|w| *w <= 1e5)
        .collect();
    assert_eq!(lanczos.len(), dense.len());
    assert!(dense.len() > 20, "{} modes test little", dense.len());
    for (k, (a, b)) in lanczos.iter().zip(&dense).enumerate() {
        assert!((a.omega / b - 1.0).abs() < 1e-8, "mode {k}: {} vs {b}", a.omega);
    }
}

#[test]
fn the_rigid_body_modes_are_what_the_supports_leave_free() {
    // The paper's strip (25 x 5 mm, 1.15 m) on 40 elements: free, six (three translations,
    // three rotations); pinned at one end, the three rotations about the pin; pinned at both
    // ends, the twist about the line through the pins; clamped, none. The modes below a cutoff
    // carry as many at omega = 0, mutually M-orthogonal (the refinement leaves them alone:
    // run on their round-off eigenvalue it mixed them).
    let free = strip(40, (0.025, 0.005, 1.15));
    let last = free.mesh().positions.len() - 1;
    let pinned = free.clone().support(0, Support::Pinned).unwrap();
    let both = pinned.clone().support(last, Support::Pinned).unwrap();
    let clamped = free.clone().support(0, Support::Clamped).unwrap();
    for (model, rigid) in [(&free, 6), (&pinned, 3), (&both, 1), (&clamped, 0)] {
        assert_eq!(simo_beam::rigid_body_modes(model).unwrap(), rigid);
    }
    let modes = modes_below(&free, 100.0).unwrap();
    let rigid: Vec<_> = modes.iter().filter(|m| m.omega == 0.0).collect();
    assert_eq!(rigid.len(), 6);
    let (_, mass) = matrices(&free);
    for (i, a) in rigid.iter().enumerate() {
        for (j, b) in rigid.iter().enumerate() {
            let mut m_b = vec![0.0; b.shape.nrows()];
            for (r, c, x) in mass.iter() {
                m_b[r] += x * b.shape[c];
            }
            let product: f64 = a.shape.iter().zip(&m_b).map(|(x, y)| x * y).sum();
            let expected = if i == j { 1.0 } else { 0.0 };
            assert!((product - expected).abs() < 1e-8, "{i} {j}: {product}");
        }
    }
}

#[test]
fn holding_the_motions_in_a_plane_keeps_the_modes_out_of_it() {
    // The paper's clamped strip (along x, thickness along z) with every node's x and y
    // translations and its rotation about E3 (z) held: what is left, the deflection along z,
    // the twist and the bending about E2, uncouples from the rest when linearised at rest, so
    // its modes are the whole model's modes out of the x-y plane, to the eigen-solver's
    // accuracy; the modes in the plane (bending across the width, extension) are gone.
    let whole = strip(40, (0.025, 0.005, 1.15)).support(0, Support::Clamped).unwrap();
    let nodes = whole.mesh().positions.len();
    let holds: Vec<(usize, usize)> = (0..nodes).flat_map(|n| [(n, 0), (n, 1), (n, 5)]).collect();
    let held = whole.clone().hold(&holds).unwrap();
    assert_eq!(held.ndof(), 3 * (nodes - 1));
    let cutoff = 2e4;
    let (all, out) = (modes_below(&whole, cutoff).unwrap(), modes_below(&held, cutoff).unwrap());
    assert!(!out.is_empty() && out.len() < all.len(), "{} of {}", out.len(), all.len());
    for mode in &out {
        let nearest = all.iter().map(|m| (m.omega / mode.omega - 1.0).abs()).fold(1.0, f64::min);
        assert!(nearest < 1e-9, "{}: {nearest:e}", mode.omega);
    }
    let err = whole.clone().hold(&[(0, 6)]).unwrap_err().to_string();
    assert!(err.contains("unknown 6 of node 0"), "{err}");
}
