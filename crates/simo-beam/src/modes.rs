//! Linearised modal analysis about the reference configuration.

use crate::error::BeamError;
use crate::model::BeamModel;
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
/// configuration: `K phi = omega^2 M phi`, solved densely with faer (Cholesky `M = L L^T`,
/// symmetric eigenproblem of `L^-1 K L^-T`, shapes `phi = L^-T u`).
///
/// # Errors
/// [`BeamError::Eigen`] if M is not positive definite or the eigen solver fails.
pub fn natural_modes(model: &BeamModel, count: usize) -> Result<Vec<Mode>, BeamError> {
    let mut model = model.clone();
    model.clear_loads();
    let n = model.ndof();
    let q = model.reference_state();
    let zero = faer::Col::<f64>::zeros(n);
    let mut t = Triplets::new();
    model.tangent(0.0, &q, zero.as_ref(), zero.as_ref(), NewtonWeights::stiffness(), &mut t);
    let k = dense(n, &t);
    let k = (&k + k.transpose()) * 0.5;
    t.clear();
    model.tangent(0.0, &q, zero.as_ref(), zero.as_ref(), NewtonWeights::mass(), &mut t);
    let m = dense(n, &t);
    let llt = m.llt(Side::Lower).map_err(|e| BeamError::Eigen(format!("mass matrix: {e:?}")))?;
    let l = llt.L();
    // A = L^-1 K L^-T: solve L X = K, then L A = X^T (K symmetric).
    let mut x = k.clone();
    l.solve_lower_triangular_in_place(x.as_mut());
    let mut a = x.transpose().to_owned();
    l.solve_lower_triangular_in_place(a.as_mut());
    let a = (&a + a.transpose()) * 0.5;
    let eigen =
        a.self_adjoint_eigen(Side::Lower).map_err(|e| BeamError::Eigen(format!("{e:?}")))?;
    let mut u = eigen.U().to_owned();
    l.transpose().solve_upper_triangular_in_place(u.as_mut());
    let values = eigen.S().column_vector().to_owned();
    Ok((0..count.min(n))
        .map(|i| Mode { omega: values[i].max(0.0).sqrt(), shape: u.col(i).to_owned() })
        .collect())
}

/// The lowest `count` natural angular frequencies (rad/s); see [`natural_modes`].
///
/// # Errors
/// As [`natural_modes`].
pub fn natural_frequencies(model: &BeamModel, count: usize) -> Result<Vec<f64>, BeamError> {
    Ok(natural_modes(model, count)?.into_iter().map(|m| m.omega).collect())
}
