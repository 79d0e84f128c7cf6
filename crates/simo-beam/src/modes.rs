//! Linearised modal analysis about the reference configuration.

use crate::error::BeamError;
use crate::model::BeamModel;
use crate::planar::PlanarBeam;
use faer::{Mat, Side};
use hht::{Model, NewtonWeights, Triplets};

fn dense(n: usize, t: &Triplets) -> Mat<f64> {
    let mut m = Mat::<f64>::zeros(n, n);
    for (r, c, v) in t.iter() {
        m[(r, c)] += v;
    }
    m
}

/// A natural mode of the linearised beam.
#[derive(Debug, Clone)]
pub struct Mode {
    /// Angular frequency omega (rad/s).
    pub omega: f64,
    /// Mass-normalised shape over the free unknowns (`phi^T M phi = 1`).
    pub shape: faer::Col<f64>,
}

/// The lowest `count` natural modes of the beam linearised about its undeformed, unloaded
/// configuration: `K phi = omega^2 M phi`, solved densely with faer in inverted form. A direct
/// reduction `L_M^-1 K L_M^-T` gets every eigenvalue to `eps ||A||`, and `||A||` is the
/// highest (shear and rotary-inertia) mode, ~1e12 times the first bending mode of a slender
/// strip: the first frequency of the paper's cantilever then drifted by 1 % at 100 elements
/// and 70 % at 120. Inverting puts the lowest modes at the top of the spectrum: with
/// `K + s M = L L^T` (Cholesky; the shift `s > 0` makes it definite for free beams too),
/// `A = L^-1 M L^-T` has eigenvalues `mu = 1 / (omega^2 + s)`, each accurate to `eps mu_max`,
/// so `omega^2` has relative error ~ `eps n (omega^2 + s)^2 / (s omega^2)`: round-off for the
/// low modes when `s` is near them. `s` is 1e-8 of the largest diagonal ratio `K_ii / M_ii`.
/// Shapes are `phi = L^-T u / sqrt(mu)`.
///
/// # Errors
/// [`BeamError::Eigen`] if `K + s M` is not positive definite or the eigen solver fails.
pub fn natural_modes(model: &BeamModel, count: usize) -> Result<Vec<Mode>, BeamError> {
    let mut model = model.clone();
    model.clear_loads();
    let q = model.reference_state();
    linear_modes(&model, &q, count)
}

/// The lowest `count` natural modes of the planar beam (with its point masses and springs)
/// about its straight, unstressed configuration, as [`natural_modes`] solves them.
///
/// # Errors
/// As [`natural_modes`].
pub fn planar_modes(beam: &PlanarBeam, count: usize) -> Result<Vec<Mode>, BeamError> {
    linear_modes(beam, &beam.reference_state(), count)
}

/// [`natural_modes`] of any model about the configuration `q`, from its tangent's stiffness
/// and mass parts.
fn linear_modes<M: Model>(model: &M, q: &M::Config, count: usize) -> Result<Vec<Mode>, BeamError> {
    let n = model.ndof();
    let q = q.clone();
    let zero = faer::Col::<f64>::zeros(n);
    let mut t = Triplets::new();
    model.tangent(0.0, &q, zero.as_ref(), zero.as_ref(), NewtonWeights::stiffness(), &mut t);
    let k = dense(n, &t);
    let k = (&k + k.transpose()) * 0.5;
    t.clear();
    model.tangent(0.0, &q, zero.as_ref(), zero.as_ref(), NewtonWeights::mass(), &mut t);
    let m = dense(n, &t);
    let m = (&m + m.transpose()) * 0.5;
    let ratio = (0..n).map(|i| k[(i, i)] / m[(i, i)]).fold(0.0, f64::max);
    let shift = 1e-8 * ratio;
    let shifted = &k + &m * shift;
    let llt = shifted
        .llt(Side::Lower)
        .map_err(|e| BeamError::Eigen(format!("stiffness + shift x mass: {e:?}")))?;
    let l = llt.L();
    // A = L^-1 M L^-T: solve L X = M, then L A = X^T (M symmetric).
    let mut x = m.clone();
    l.solve_lower_triangular_in_place(x.as_mut());
    let mut a = x.transpose().to_owned();
    l.solve_lower_triangular_in_place(a.as_mut());
    let a = (&a + a.transpose()) * 0.5;
    let eigen =
        a.self_adjoint_eigen(Side::Lower).map_err(|e| BeamError::Eigen(format!("{e:?}")))?;
    let mut u = eigen.U().to_owned();
    l.transpose().solve_upper_triangular_in_place(u.as_mut());
    let mu = eigen.S().column_vector().to_owned();
    // Eigenvalues come ascending in mu, so descending in omega: walk them from the top.
    Ok((0..count.min(n))
        .map(|i| {
            let j = n - 1 - i;
            let omega2 = 1.0 / mu[j] - shift;
            let shape = u.col(j).to_owned() * (1.0 / mu[j].sqrt());
            Mode { omega: omega2.max(0.0).sqrt(), shape }
        })
        .collect())
}

/// Every natural mode of the beam (with its point masses and springs) linearised about its
/// undeformed, unloaded configuration with `omega <= omega_max` (rad/s), ascending and
/// mass-normalised: shift-invert Lanczos on a banded factorisation, the count checked by
/// Sylvester's law of inertia (`crate::eigen`). For long beams and frames, where
/// [`natural_modes`]' dense solution (cubic in the unknowns) is out of reach: 512 elements of
/// the 3D beam (3078 unknowns) in a fraction of a second.
///
/// # Errors
/// [`BeamError::Eigen`] as the solver says (see `crate::eigen::modes_below`).
pub fn modes_below(model: &BeamModel, omega_max: f64) -> Result<Vec<Mode>, BeamError> {
    AtRest::of(model).modes_below(omega_max)
}

/// How many rigid-body modes `model` has at rest (its loads cleared): 0 where its supports
/// hold it, 6 for a free body, between for a mechanism (one pin leaves 3). Counted by
/// Sylvester's inertia below the round-off threshold [`modes_below`] calls rigid (omega 0).
///
/// # Errors
/// [`BeamError::Eigen`] for a mass matrix that is not positive definite.
pub fn rigid_body_modes(model: &BeamModel) -> Result<usize, BeamError> {
    AtRest::of(model).rigid_body_modes()
}

/// A beam linearised at rest (its loads cleared): the stiffness and mass parts of its tangent
/// at the reference configuration, which every linear question about it asks of (its modes,
/// their count, a static solve). Built once and asked many times: the elements' tangents are
/// the cost (on the paper's beam lowered to 374 elements a tenth of a modal run on its modes
/// each time they were assembled).
#[derive(Debug, Clone)]
pub struct AtRest {
    ndof: usize,
    stiffness: Triplets,
    mass: Triplets,
}

impl AtRest {
    /// `model` linearised at rest.
    pub fn of(model: &BeamModel) -> Self {
        let mut model = model.clone();
        model.clear_loads();
        let (stiffness, mass) = crate::eigen::linearised(&model, &model.reference_state());
        Self { ndof: model.ndof(), stiffness, mass }
    }

    /// How many unknowns.
    pub fn ndof(&self) -> usize {
        self.ndof
    }

    /// The stiffness K (entries, duplicates summed).
    pub fn stiffness(&self) -> &Triplets {
        &self.stiffness
    }

    /// The mass M (entries, duplicates summed; consistent, with the point masses).
    pub fn mass(&self) -> &Triplets {
        &self.mass
    }

    /// [`modes_below`].
    ///
    /// # Errors
    /// As [`modes_below`].
    pub fn modes_below(&self, omega_max: f64) -> Result<Vec<Mode>, BeamError> {
        crate::eigen::modes_below(self.ndof, (&self.stiffness, &self.mass), omega_max)
    }

    /// [`rigid_body_modes`].
    ///
    /// # Errors
    /// As [`rigid_body_modes`].
    pub fn rigid_body_modes(&self) -> Result<usize, BeamError> {
        crate::eigen::rigid_body_modes(self.ndof, &self.stiffness, &self.mass)
    }
}

/// [`modes_below`] for the planar beam.
///
/// # Errors
/// As [`modes_below`].
pub fn planar_modes_below(beam: &PlanarBeam, omega_max: f64) -> Result<Vec<Mode>, BeamError> {
    let (stiffness, mass) = crate::eigen::linearised(beam, &beam.reference_state());
    crate::eigen::modes_below(beam.ndof(), (&stiffness, &mass), omega_max)
}

/// The lowest `count` natural angular frequencies (rad/s); see [`natural_modes`].
///
/// # Errors
/// As [`natural_modes`].
pub fn natural_frequencies(model: &BeamModel, count: usize) -> Result<Vec<f64>, BeamError> {
    Ok(natural_modes(model, count)?.into_iter().map(|m| m.omega).collect())
}

/// The lowest `count` natural angular frequencies (rad/s) of bending across the section's E3
/// axis (deflection along z for a beam along x with E3 = z): the modes whose shape lives mostly
/// in z translation and rotation about y, rigid-body modes (omega below 1 rad/s) left out.
///
/// # Errors
/// As [`natural_modes`].
pub fn bending_frequencies(model: &BeamModel, count: usize) -> Result<Vec<f64>, BeamError> {
    let nodes = model.mesh().positions.len();
    let mut out = Vec::new();
    for mode in natural_modes(model, 6 * nodes)? {
        let (mut bending, mut total) = (0.0, 0.0);
        for node in 0..nodes {
            for k in 0..6 {
                if let Some(i) = model.dof(node, k) {
                    let s = mode.shape[i] * mode.shape[i];
                    total += s;
                    if k == 2 || k == 4 {
                        bending += s;
                    }
                }
            }
        }
        if mode.omega > 1.0 && bending > 0.5 * total {
            out.push(mode.omega);
            if out.len() == count {
                break;
            }
        }
    }
    Ok(out)
}
