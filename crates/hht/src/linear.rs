//! A sparse LU that keeps its symbolic factorisation while the pattern stays the same.

use crate::error::HhtError;
use crate::model::Triplets;
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};
use faer::{linalg::solvers::Solve, Col, ColMut};

/// Factorises matrices given as [`Triplets`]; the symbolic analysis (ordering, elimination
/// structure) is done once per sparsity pattern and reused for every later matrix.
#[derive(Debug, Default)]
pub struct SparseLu {
    pattern: Option<Pattern>,
    lu: Option<Lu<usize, f64>>,
    /// Number of symbolic analyses done so far (for tests and reports).
    pub symbolic_count: usize,
}

#[derive(Debug)]
struct Pattern {
    n: usize,
    rows: Vec<usize>,
    cols: Vec<usize>,
    symbolic: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    lu: SymbolicLu<usize>,
}

impl SparseLu {
    /// An empty solver.
    pub fn new() -> Self {
        Self::default()
    }

    /// Factorises the `n x n` matrix in `a`.
    ///
    /// # Errors
    /// [`HhtError::Model`] for an index out of range; [`HhtError::Singular`] (with time `t`, for
    /// the message) when the numeric factorisation fails.
    pub fn factor(&mut self, n: usize, a: &Triplets, t: f64) -> Result<(), HhtError> {
        let same =
            self.pattern.as_ref().is_some_and(|p| p.n == n && p.rows == a.rows && p.cols == a.cols);
        if !same {
            if let Some((r, c)) = a.rows.iter().zip(&a.cols).find(|(&r, &c)| r >= n || c >= n) {
                return Err(HhtError::Model(format!(
                    "matrix entry ({r}, {c}) outside a {n} x {n} matrix"
                )));
            }
            let pairs: Vec<Pair<usize, usize>> =
                a.rows.iter().zip(&a.cols).map(|(&row, &col)| Pair { row, col }).collect();
            let (symbolic, argsort) = SymbolicSparseColMat::try_new_from_indices(n, n, &pairs)
                .map_err(|e| HhtError::Model(format!("bad sparsity pattern: {e:?}")))?;
            let lu = SymbolicLu::try_new(symbolic.as_ref())
                .map_err(|e| HhtError::Singular { t, reason: format!("{e:?}") })?;
            self.pattern = Some(Pattern {
                n,
                rows: a.rows.clone(),
                cols: a.cols.clone(),
                symbolic,
                argsort,
                lu,
            });
            self.symbolic_count += 1;
        }
        let p = self.pattern.as_ref().ok_or_else(|| HhtError::Model("no pattern".into()))?;
        let mat = SparseColMat::new_from_argsort(p.symbolic.clone(), &p.argsort, &a.vals)
            .map_err(|e| HhtError::Singular { t, reason: format!("{e:?}") })?;
        let lu = Lu::try_new_with_symbolic(p.lu.clone(), mat.as_ref())
            .map_err(|e| HhtError::Singular { t, reason: format!("{e:?}") })?;
        self.lu = Some(lu);
        Ok(())
    }

    /// Overwrites `rhs` with the solution of `A x = rhs` for the last factorised `A`.
    ///
    /// # Errors
    /// [`HhtError::Model`] if nothing has been factorised, [`HhtError::Singular`] if the
    /// solution is not finite.
    pub fn solve_in_place(&self, mut rhs: ColMut<'_, f64>, t: f64) -> Result<(), HhtError> {
        let lu = self.lu.as_ref().ok_or_else(|| HhtError::Model("solve before factor".into()))?;
        lu.solve_in_place(rhs.as_mut().as_mat_mut());
        if rhs.iter().any(|x| !x.is_finite()) {
            return Err(HhtError::Singular { t, reason: "the solution is not finite".into() });
        }
        Ok(())
    }

    /// Solves `A x = b` for the last factorised `A`.
    ///
    /// # Errors
    /// As [`SparseLu::solve_in_place`].
    pub fn solve(&self, b: &Col<f64>, t: f64) -> Result<Col<f64>, HhtError> {
        let mut x = b.clone();
        self.solve_in_place(x.as_mut(), t)?;
        Ok(x)
    }
}
