//! A banded LU with a dense border: the Newton matrix of a chain of elements (a beam) plus a
//! few unknowns coupled to anything (a ball).
//!
//! The matrix is `A = [B C; D E]`: `B` (n x n) banded with half-bandwidth `kd` (entries only
//! where `|i - j| <= kd`), `E` (k x k) dense, `C` and `D` the couplings. `B = L U` by Gaussian
//! elimination without row interchanges while the pivots stay positive (a symmetric positive
//! definite Newton matrix, mass plus stiffness, needs none; a beam's rotation rows have small
//! diagonals against their shear coupling, and partial pivoting would swap them needlessly),
//! otherwise `B = P L U` with partial pivoting inside the band (LAPACK's `gbtrf` scheme: the
//! interchanges widen `U` to `2 kd` super-diagonals), then the Schur complement `S = E - D B^-1 C` (k x k) is
//! factorised densely. A solve is `y = B^-1 r1`, `z = S^-1 (r2 - D y)`, `x1 = y - (B^-1 C) z`.
//! The work is O(n kd^2 + n kd k) per factorisation and O(n (kd + k)) per solve, against the
//! general sparse LU's analysis, fill and indirection: for a beam of 256 elements (kd = 5 with
//! three unknowns a node) it is a few tens of microseconds.

use crate::error::HhtError;
use crate::fast::{dot, whole, Lanes, MulAdd};
use crate::model::Triplets;
use faer::ColMut;
use pulp::{Scalar, Simd};

/// The shape of a Newton matrix that [`BandedLu`] can factorise.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Band {
    /// Half-bandwidth of the leading block: entries `(i, j)` with `|i - j| <= half_bandwidth`.
    pub half_bandwidth: usize,
    /// Unknowns at the end of the numbering that may couple to any other (the border).
    pub border: usize,
}

/// LU factors of a banded matrix with a dense border; see the module text.
#[derive(Debug, Default)]
pub struct BandedLu {
    /// Size of the banded block.
    n: usize,
    /// Half-bandwidth.
    kd: usize,
    /// Row length of the band storage, `3 kd + 1` (kd below, kd above, kd more of fill).
    width: usize,
    /// Row `i` holds columns `i - kd ..= i + 2 kd` at `i * width + (j + kd - i)`.
    ab: Vec<f64>,
    /// Row interchanged with row `i` at elimination step `i`.
    pivots: Vec<usize>,
    /// Reciprocals of U's diagonal (the back-substitution multiplies instead of dividing).
    inverse_diagonal: Vec<f64>,
    /// L's multipliers of column `i` (rows i + 1 ..= i + kd) at `i * kd ..`, contiguous for
    /// the forward substitution.
    lower: Vec<f64>,
    /// Without row interchanges: L's row `i` left of the diagonal, nearest first
    /// (`L[i][i - 1 - j]` at `i * kd + j`), for a forward substitution by rows.
    lower_rows: Vec<f64>,
    /// Without row interchanges: U's row `i` right of the diagonal divided by the diagonal,
    /// at `i * kd ..`, so that the back-substitution's chain from one unknown to the next is
    /// one multiply and one subtraction.
    scaled_upper: Vec<f64>,
    /// Without row interchanges at half-bandwidth 5 (the only one whose substitution reads
    /// them; empty otherwise), the substitutions' rows two ahead (see
    /// [`BandedLu::solve_band_ahead`]): row `i` at `i * (kd + 1) ..` holds the weight of the
    /// right-hand side one row back (forward) or on (backward), then the weights of the
    /// solved values two to `kd + 1` rows away.
    lower_ahead: Vec<f64>,
    upper_ahead: Vec<f64>,
    /// With [`BandedLu::node_blocks`] at half-bandwidth 5 (the planar beam's nodes of three),
    /// the rows two ahead of each node without their weights that are exact zeros (see
    /// [`AHEAD_OF_THREE`]), a node's 15 at a time; empty otherwise.
    lower_ahead_nodes: Vec<f64>,
    upper_ahead_nodes: Vec<f64>,
    /// Whether the factors (no interchange) are those of a chain of nodes of `m = (kd + 1) / 2`
    /// unknowns each (the 3D beam's six at kd = 11, where the substitution uses it) coupled to
    /// its neighbours only: row `m k + r` of L then has weights only at the `m + r` nearest
    /// columns, of U at the `kd - r` nearest, the rest exact zeros (elimination keeps a row's
    /// envelope): each node's rows are then a few small matrices ([`node_matrices`]).
    node_blocks: bool,
    /// With [`BandedLu::node_blocks`] at half-bandwidth 11 (the 3D beam's nodes of six), each
    /// node's substitution as matrices ([`node_matrices`]), 4 x 36 numbers a node, made at the
    /// factorisation's [`NODE_MATRICES_AFTER`]th solve (`node_matrices_due` until then); empty
    /// otherwise.
    node_matrices: Vec<f64>,
    node_matrices_due: bool,
    /// Solves with the current factors.
    solves: usize,
    /// Super-diagonals of U that may hold non-zeros: kd without a row interchange (a
    /// diagonally dominant Newton matrix, the usual case), 2 kd with.
    upper: usize,
    /// Border size.
    k: usize,
    /// `C`, then `B^-1 C` after factorising: column `c` at `c * n ..`.
    border_columns: Vec<f64>,
    /// `D`, row `r` at `r * n ..`.
    border_rows: Vec<f64>,
    /// The columns of each row of `D` from its first non-zero to its last (a ball touches a
    /// few unknowns of one element): the solve's products of `D` run over these alone.
    border_spans: Vec<std::ops::Range<usize>>,
    /// `E`, then its Schur complement's LU factors, row-major k x k.
    corner: Vec<f64>,
    /// Row interchanges of the corner's LU.
    corner_pivots: Vec<usize>,
    /// Work space of a solve (the border's right-hand side).
    scratch: Vec<f64>,
    /// Whether `C` or `D` holds a non-zero: a ball out of contact couples to nothing, and its
    /// border is then solved on its own (no `B^-1 C`, no products of length n).
    coupled: bool,
}

impl BandedLu {
    /// An empty solver.
    pub fn new() -> Self {
        Self::default()
    }

    /// Factorises the `total x total` matrix in `a`, shaped as `band` says.
    ///
    /// # Errors
    /// [`HhtError::Model`] for an entry outside the band or the matrix; [`HhtError::Singular`]
    /// (with time `t`, for the message) for a zero pivot.
    pub fn factor(
        &mut self,
        total: usize,
        band: Band,
        a: &Triplets,
        t: f64,
    ) -> Result<(), HhtError> {
        let k = band.border.min(total);
        let n = total - k;
        let kd = band.half_bandwidth;
        self.n = n;
        self.kd = kd;
        self.k = k;
        self.width = 3 * kd + 1;
        self.assemble(a)?;
        // No row interchanges first: the Newton matrix of a beam is symmetric positive
        // definite (mass plus stiffness), for which elimination without pivoting is stable
        // (it is LDL^T) and keeps U at kd super-diagonals. A pivot that is not positive and
        // clear of round-off says otherwise: then again with partial pivoting.
        if !self.factor_band(false, t)? {
            self.assemble(a)?;
            self.factor_band(true, t)?;
        }
        if self.upper == kd {
            self.lower_rows.clear();
            self.lower_rows.resize(n * kd, 0.0);
            for col in 0..n {
                for j in 0..kd.min(n - 1 - col) {
                    self.lower_rows[(col + 1 + j) * kd + j] = self.lower[col * kd + j];
                }
            }
            self.scaled_upper.clear();
            self.scaled_upper.resize(n * kd, 0.0);
            for row in 0..n {
                let base = row * self.width + kd;
                let span = kd.min(n - 1 - row);
                for j in 0..span {
                    self.scaled_upper[row * kd + j] =
                        self.ab[base + 1 + j] * self.inverse_diagonal[row];
                }
            }
            // The rows two ahead: only the planar beam's half-bandwidth takes them.
            (self.lower_ahead, self.upper_ahead) = if kd == 5 {
                let lower = two_ahead(&self.lower_rows, n, kd, |i| i.checked_sub(1));
                (lower, two_ahead(&self.scaled_upper, n, kd, |i| Some(i + 1)))
            } else {
                (Vec::new(), Vec::new())
            };
        }
        let m = kd.div_ceil(2);
        self.node_blocks = self.upper == kd && kd % 2 == 1 && n % m == 0 && {
            let beyond = |rows: &[f64], reach: &dyn Fn(usize) -> usize| {
                rows.chunks_exact(kd)
                    .enumerate()
                    .all(|(i, row)| row[reach(i % m)..].iter().all(|&w| w == 0.0))
            };
            beyond(&self.lower_rows, &|r| m + r) && beyond(&self.scaled_upper, &|r| kd - r)
        };
        self.node_matrices.clear();
        self.node_matrices_due = self.node_blocks && kd == 11;
        self.solves = 0;
        self.lower_ahead_nodes.clear();
        self.upper_ahead_nodes.clear();
        if self.node_blocks && kd == 5 {
            let lower = compact_nodes(&self.lower_ahead, AHEAD_OF_THREE.0);
            let upper = compact_nodes(&self.upper_ahead, AHEAD_OF_THREE.1);
            if let (Some(lower), Some(upper)) = (lower, upper) {
                (self.lower_ahead_nodes, self.upper_ahead_nodes) = (lower, upper);
            }
        }
        self.coupled = self.border_columns.iter().chain(&self.border_rows).any(|&v| v != 0.0);
        self.border_spans = (0..k)
            .map(|r| {
                let row = &self.border_rows[r * n..(r + 1) * n];
                let first = row.iter().position(|&v| v != 0.0).unwrap_or(0);
                let end = row.iter().rposition(|&v| v != 0.0).map_or(first, |last| last + 1);
                first..end
            })
            .collect();
        if !self.coupled {
            return self.factor_corner(t);
        }
        // B^-1 C, column by column, then S = E - D (B^-1 C).
        let mut columns = std::mem::take(&mut self.border_columns);
        for col in columns.chunks_mut(n.max(1)).take(k) {
            self.solve_band(col);
        }
        self.border_columns = columns;
        for r in 0..k {
            let d = &self.border_rows[r * n..(r + 1) * n];
            for c in 0..k {
                let x = &self.border_columns[c * n..(c + 1) * n];
                self.corner[r * k + c] -= dot(d, x);
            }
        }
        self.factor_corner(t)
    }

    /// Scatters the triplets into the band, the border and the corner.
    fn assemble(&mut self, a: &Triplets) -> Result<(), HhtError> {
        let (n, k, kd) = (self.n, self.k, self.kd);
        let total = n + k;
        self.ab.clear();
        self.ab.resize(n * self.width, 0.0);
        self.pivots.resize(n, 0);
        self.inverse_diagonal.resize(n, 0.0);
        self.lower.clear();
        self.lower.resize(n * kd, 0.0);
        self.border_columns.clear();
        self.border_columns.resize(n * k, 0.0);
        self.border_rows.clear();
        self.border_rows.resize(n * k, 0.0);
        self.corner.clear();
        self.corner.resize(k * k, 0.0);
        self.corner_pivots.resize(k, 0);
        let w = self.width;
        for ((&r, &c), &v) in a.rows.iter().zip(&a.cols).zip(&a.vals) {
            match (r < n, c < n) {
                (true, true) if r.abs_diff(c) <= kd => self.ab[r * w + c + kd - r] += v,
                (true, true) => {
                    return Err(HhtError::Model(format!(
                        "matrix entry ({r}, {c}) outside the declared half-bandwidth {kd}"
                    )))
                }
                _ if r >= total || c >= total => {
                    return Err(HhtError::Model(format!(
                        "matrix entry ({r}, {c}) outside a {total} x {total} matrix"
                    )))
                }
                (true, false) => self.border_columns[(c - n) * n + r] += v,
                (false, true) => self.border_rows[(r - n) * n + c] += v,
                (false, false) => self.corner[(r - n) * k + (c - n)] += v,
            }
        }
        Ok(())
    }

    /// Gaussian elimination inside the band, with partial pivoting (`gbtrf`) or without. Entry
    /// (i, j) lives at `i * width + j + kd - i`, so row i's columns are contiguous and the
    /// update of a row by the pivot row is one slice operation. Without pivoting it returns
    /// `false` (and leaves the band spoilt) at the first pivot that is not positive or is
    /// below `1e-8` of its column's largest entry.
    fn factor_band(&mut self, pivoting: bool, t: f64) -> Result<bool, HhtError> {
        let (n, kd, w) = (self.n, self.kd, self.width);
        let ab = &mut self.ab;
        self.upper = kd;
        for col in 0..n {
            let last_row = (col + kd).min(n - 1);
            let mut pivot = col;
            let mut largest = ab[col * w + kd].abs();
            for row in col + 1..=last_row {
                let v = ab[row * w + kd + col - row].abs();
                if v > largest {
                    largest = v;
                    pivot = row;
                }
            }
            if !pivoting {
                let diagonal = ab[col * w + kd];
                if !(diagonal > 1e-8 * largest && diagonal.is_finite()) {
                    return Ok(false);
                }
                pivot = col;
            }
            if !(largest > 0.0 && largest.is_finite()) {
                return Err(HhtError::Singular {
                    t,
                    reason: format!("zero or non-finite pivot in column {col} of the band"),
                });
            }
            self.pivots[col] = pivot;
            // Columns col ..= col + span take part in this step: kd on without row interchanges
            // (U keeps the band's kd super-diagonals; the fill columns stay zero), 2 kd with.
            let reach = if pivoting { 2 * kd } else { kd };
            let span = (col + reach).min(n - 1) - col;
            if pivot != col {
                self.upper = 2 * kd;
                let (p, q) = (col * w + kd, pivot * w + kd + col - pivot);
                for j in 0..=span {
                    ab.swap(p + j, q + j);
                }
            }
            let (head, tail) = ab.split_at_mut((col + 1) * w);
            let top = &head[col * w + kd..=col * w + kd + span];
            let inverse = 1.0 / top[0];
            self.inverse_diagonal[col] = inverse;
            for row in col + 1..=last_row {
                let start = (row - col - 1) * w + kd + col - row;
                let r = &mut tail[start..=start + span];
                let l = r[0] * inverse;
                r[0] = l;
                self.lower[col * kd + row - col - 1] = l;
                if l != 0.0 {
                    for (x, u) in r[1..].iter_mut().zip(&top[1..]) {
                        *x -= l * u;
                    }
                }
            }
        }
        Ok(true)
    }

    /// Overwrites `b` (length n) with `B^-1 b`.
    fn solve_band(&self, b: &mut [f64]) {
        // Without row interchanges (the usual, diagonally dominant Newton matrix) a planar beam
        // of three unknowns a node (kd = 5) takes the fixed-width path two rows ahead, which
        // keeps the last values solved in registers (and runs in its AVX2/FMA copy where there
        // is one): its time was the chain from row to row (2.07 -> 1.77 us a solve on the
        // paper's tip at 256 elements), and without the weights a chain of nodes of three
        // leaves zero where its factors are a chain's (`lower_ahead_nodes`: 1.75 -> 1.64 us).
        // The 3D beam (six unknowns a node, kd = 11) takes each node's matrices where its
        // factors are a chain's, from the factorisation's `NODE_MATRICES_AFTER`th solve
        // (`node_matrices`; row by row, skipping the zeros of a chain's factors, 6.1 -> 5.0
        // us a solve at 256 elements; by the matrices 3.4 us), else the fixed-width path one
        // row ahead: its instructions set its time, and the weight more a row made it slower
        // two rows ahead. (The planar beam a node of three at a time took
        // 1.94 us against 1.77 two rows ahead: its chain, not its instructions, sets its time.)
        match (self.kd, self.upper) {
            (5, 5) if !self.lower_ahead_nodes.is_empty() => {
                return crate::fast::run(AheadOfThree { lu: self, b })
            }
            (5, 5) => return crate::fast::run(FixedSolve::<5, true> { lu: self, b }),
            (11, 11) if !self.node_matrices.is_empty() => {
                return crate::fast::run(NodeMatrices { lu: self, b })
            }
            (11, 11) => return crate::fast::run(FixedSolve::<11, false> { lu: self, b }),
            _ => {}
        }
        self.solve_band_general(b);
    }

    /// `solve_band` for half-bandwidth `KD` and no row interchanges, by rows both ways:
    /// forward `y_i = b_i - sum_j L[i][i-1-j] y_{i-1-j}`, backward with U's rows divided by
    /// their diagonal. The terms of the older values are summed first, so the chain from one
    /// unknown to the next is one multiply-add, and the last KD values ride in registers.
    /// (Forward by columns, a window of the next KD right-hand sides updated a column, the
    /// compiler packed the window into one vector register: the shuffles doubled the chain.)
    #[inline(always)]
    fn solve_band_fixed<const KD: usize, A: MulAdd>(&self, b: &mut [f64], arith: A) {
        let n = self.n;
        // The rows' factors as fixed-length chunks zipped with the unknowns: no bounds check
        // and no reload of the slices a row (the loop is a chain of one multiply-add a row,
        // and the instructions around it count as much).
        let b = &mut b[..n];
        let lower = self.lower_rows[..n * KD].chunks_exact(KD);
        // Forward: known[j] = y[row - 1 - j].
        let mut known = [0.0; KD];
        for (value, l) in b.iter_mut().zip(lower) {
            let mut far = *value;
            for j in (1..KD).rev() {
                far = arith.mul_add(-l[j], known[j], far);
            }
            let y = arith.mul_add(-l[0], known[0], far);
            *value = y;
            for j in (1..KD).rev() {
                known[j] = known[j - 1];
            }
            known[0] = y;
        }
        // Backward: solved[j] = b[row + 1 + j], with U's rows divided by their diagonal.
        let upper = self.scaled_upper[..n * KD].chunks_exact(KD);
        let rows = b.iter_mut().zip(upper).zip(&self.inverse_diagonal[..n]);
        let mut solved = [0.0; KD];
        for ((value, u), inverse) in rows.rev() {
            let mut far = *value * inverse;
            for j in (1..KD).rev() {
                far = arith.mul_add(-u[j], solved[j], far);
            }
            let x = arith.mul_add(-u[0], solved[0], far);
            *value = x;
            for j in (1..KD).rev() {
                solved[j] = solved[j - 1];
            }
            solved[0] = x;
        }
    }

    /// `solve_band` for half-bandwidth `KD` and no row interchanges, each row solved from the
    /// values two rows back: forward `y_i = b_i - L[i][i-1] y_{i-1} - ...` with row `i - 1`'s
    /// own equation put in for `y_{i-1}`,
    /// `y_i = (b_i - l_i b_{i-1}) - sum_{j=1..=KD} (L[i][i-1-j] - l_i L[i-1][i-1-j]) y_{i-1-j}`
    /// (`l_i = L[i][i-1]`), and backward likewise with U's rows divided by their diagonal.
    /// Two neighbouring rows then depend on none of each other's results, so the chain from a
    /// row to the next is half a multiply-add: where it, not the multiply-adds, sets the time
    /// (kd = 5, the planar beam) the substitution runs in about three quarters of the time of
    /// [`BandedLu::solve_band_fixed`], for one weight more a row.
    #[inline(always)]
    fn solve_band_ahead<const KD: usize, A: MulAdd>(&self, b: &mut [f64], arith: A) {
        let n = self.n;
        let b = &mut b[..n];
        // Forward, on the rows in order.
        let mut chain = Ahead::<KD>::default();
        for (value, l) in b.iter_mut().zip(self.lower_ahead[..n * (KD + 1)].chunks_exact(KD + 1)) {
            *value = chain.next(*value, l, arith);
        }
        // Backward on y_i / u_ii, on the rows in reverse.
        let upper = self.upper_ahead[..n * (KD + 1)].chunks_exact(KD + 1);
        let rows = b.iter_mut().zip(upper).zip(&self.inverse_diagonal[..n]);
        let mut chain = Ahead::<KD>::default();
        for ((value, u), inverse) in rows.rev() {
            *value = chain.next(*value * inverse, u, arith);
        }
    }

    /// [`BandedLu::solve_band_ahead`] at half-bandwidth 5 for factors of nodes of three
    /// ([`BandedLu::lower_ahead_nodes`]): each row with only its weights that may be non-zero,
    /// in the same order, so the same result to the bit, for 30 multiply-adds a node instead of
    /// 36 and a sixth less of the factors streamed.
    #[inline(always)]
    fn solve_ahead_of_three<A: MulAdd>(&self, b: &mut [f64], arith: A) {
        let n = self.n;
        let b = &mut b[..n];
        let (forward, backward) = AHEAD_OF_THREE;
        let mut chain = Ahead::<5>::default();
        for (node, w) in b.chunks_exact_mut(3).zip(self.lower_ahead_nodes.chunks_exact(15)) {
            let (w0, rest) = w.split_at(forward[0]);
            let (w1, w2) = rest.split_at(forward[1]);
            node[0] = chain.next_within(node[0], w0, arith);
            node[1] = chain.next_within(node[1], w1, arith);
            node[2] = chain.next_within(node[2], w2, arith);
        }
        let upper = self.upper_ahead_nodes.chunks_exact(15);
        let inverse = self.inverse_diagonal[..n].chunks_exact(3);
        let mut chain = Ahead::<5>::default();
        for ((node, w), inverse) in b.chunks_exact_mut(3).zip(upper).zip(inverse).rev() {
            let (w0, rest) = w.split_at(backward[0]);
            let (w1, w2) = rest.split_at(backward[1]);
            node[2] = chain.next_within(node[2] * inverse[2], w2, arith);
            node[1] = chain.next_within(node[1] * inverse[1], w1, arith);
            node[0] = chain.next_within(node[0] * inverse[0], w0, arith);
        }
    }

    /// Makes the factors' [`node_matrices`] where they are due.
    fn make_node_matrices(&mut self) {
        if std::mem::take(&mut self.node_matrices_due) {
            let (l, u, d) = (&self.lower_rows, &self.scaled_upper, &self.inverse_diagonal);
            node_matrices(l, u, d, &mut self.node_matrices);
        }
    }

    /// The substitutions by [`node_matrices`]: forward `y_i = P_i b_i - E_i y_(i-1)`, backward
    /// `x_i = R_i y_i - F_i x_(i+1)`, each node's six rows at once. From one node to the next
    /// the chain is the product with the last node's values, summed in two halves (three
    /// multiply-adds deep), where row by row it was up to eleven (4.9 -> 3.4 us a solve on the
    /// paper's strip at 256 elements in 3D; the columns padded to eight rows for whole vectors,
    /// 4.2 us: the matrices streamed set the time).
    #[inline(always)]
    fn solve_node_matrices<A: MulAdd>(&self, b: &mut [f64], arith: A) {
        const M: usize = 6;
        let n = self.n;
        let b = &mut b[..n];
        let matrices = self.node_matrices.chunks_exact(4 * M * M);
        let mut last = [0.0; M];
        for (node, m) in b.chunks_exact_mut(M).zip(matrices.clone()) {
            last = node_step::<true, A>(arith, (&m[..M * M], node), (&m[M * M..2 * M * M], &last));
            node.copy_from_slice(&last);
        }
        let mut last = [0.0; M];
        for (node, m) in b.chunks_exact_mut(M).zip(matrices).rev() {
            last = node_step::<false, A>(
                arith,
                (&m[2 * M * M..3 * M * M], node),
                (&m[3 * M * M..], &last),
            );
            node.copy_from_slice(&last);
        }
    }

    fn solve_band_general(&self, b: &mut [f64]) {
        let (n, kd, w) = (self.n, self.kd, self.width);
        for col in 0..n {
            let p = self.pivots[col];
            if p != col {
                b.swap(col, p);
            }
            let (head, tail) = b.split_at_mut(col + 1);
            let bc = head[col];
            let rows = kd.min(tail.len());
            let l = &self.lower[col * kd..col * kd + rows];
            for (bi, li) in tail[..rows].iter_mut().zip(l) {
                *bi -= li * bc;
            }
        }
        for row in (0..n).rev() {
            let span = (row + self.upper).min(n - 1) - row;
            let base = row * w + kd;
            let u = &self.ab[base + 1..=base + span];
            let x = &b[row + 1..=row + span];
            // The terms of b[row + 2 ..] are known well before b[row + 1], the one just
            // computed: summing them first in two independent partial sums keeps the
            // dependency chain from row to row at one multiply-add.
            let (mut s0, mut s1) = (0.0, 0.0);
            let mut j = 1;
            while j + 1 < span {
                s0 += u[j] * x[j];
                s1 += u[j + 1] * x[j + 1];
                j += 2;
            }
            if j < span {
                s0 += u[j] * x[j];
            }
            let near = if span > 0 { u[0] * x[0] } else { 0.0 };
            b[row] = (b[row] - (s0 + s1) - near) * self.inverse_diagonal[row];
        }
    }

    /// Dense LU with partial pivoting of the k x k Schur complement.
    fn factor_corner(&mut self, t: f64) -> Result<(), HhtError> {
        dense_lu(&mut self.corner, self.k, &mut self.corner_pivots, t, "of the border")
    }

    /// Overwrites `rhs` with the solution of `A x = rhs` for the last factorised `A`.
    ///
    /// # Errors
    /// [`HhtError::Model`] for a right-hand side of the wrong length, [`HhtError::Singular`]
    /// if the solution is not finite.
    pub fn solve_in_place(&mut self, mut rhs: ColMut<'_, f64>, t: f64) -> Result<(), HhtError> {
        let (n, k) = (self.n, self.k);
        if rhs.nrows() != n + k {
            return Err(HhtError::Model(format!(
                "right-hand side of length {} for a {} x {} matrix",
                rhs.nrows(),
                n + k,
                n + k
            )));
        }
        self.solves += 1;
        if self.node_matrices_due && self.solves >= NODE_MATRICES_AFTER {
            self.make_node_matrices();
        }
        // A contiguous right-hand side is solved where it lies; another is copied.
        if let Some(slice) = rhs.as_mut().try_as_col_major_mut() {
            let b = slice.as_slice_mut();
            self.solve_all(b);
            return finite(b, t);
        }
        let mut b: Vec<f64> = std::mem::take(&mut self.scratch);
        b.clear();
        b.extend((0..n + k).map(|i| rhs[i]));
        self.solve_all(&mut b);
        for (i, v) in b.iter().enumerate() {
            rhs[i] = *v;
        }
        let result = finite(&b, t);
        self.scratch = b;
        result
    }

    /// Overwrites `b` (length n + k) with `A^-1 b`.
    fn solve_all(&self, b: &mut [f64]) {
        let (n, k) = (self.n, self.k);
        let (top, border) = b.split_at_mut(n);
        self.solve_band(top);
        if !self.coupled {
            return dense_solve(&self.corner, k, &self.corner_pivots, border);
        }
        // The border's products of length n (a ball in contact), on the wider lanes.
        crate::fast::run(CoupledBorder { lu: self, top, border });
    }

    /// The border's unknowns `z = S^-1 (r2 - D y)` and the band's `x1 = y - (B^-1 C) z`, with
    /// `y` (the band's solution) in `top` and `r2` in `border`.
    #[inline(always)]
    fn solve_coupled_border(&self, top: &mut [f64], border: &mut [f64]) {
        let n = self.n;
        for ((r, z), span) in border.iter_mut().enumerate().zip(&self.border_spans) {
            let row = &self.border_rows[r * n..(r + 1) * n];
            *z -= dot(&row[span.clone()], &top[span.clone()]);
        }
        dense_solve(&self.corner, self.k, &self.corner_pivots, border);
        for (c, z) in border.iter().enumerate() {
            let x = &self.border_columns[c * n..(c + 1) * n];
            for (yi, xi) in top.iter_mut().zip(x) {
                *yi -= xi * z;
            }
        }
    }
}

/// Dense LU with partial pivoting of the row-major `k x k` matrix `a`, in place.
fn dense_lu(
    a: &mut [f64],
    k: usize,
    pivots: &mut [usize],
    t: f64,
    what: &str,
) -> Result<(), HhtError> {
    for col in 0..k {
        let pivot = (col..k)
            .max_by(|&x, &y| a[x * k + col].abs().total_cmp(&a[y * k + col].abs()))
            .unwrap_or(col);
        let largest = a[pivot * k + col].abs();
        if !(largest > 0.0 && largest.is_finite()) {
            return Err(HhtError::Singular {
                t,
                reason: format!("zero or non-finite pivot in column {col} {what}"),
            });
        }
        pivots[col] = pivot;
        if pivot != col {
            for j in 0..k {
                a.swap(col * k + j, pivot * k + j);
            }
        }
        for row in col + 1..k {
            let l = a[row * k + col] / a[col * k + col];
            a[row * k + col] = l;
            for j in col + 1..k {
                a[row * k + j] -= l * a[col * k + j];
            }
        }
    }
    Ok(())
}

/// Overwrites `b` with `A^-1 b` for the factors of [`dense_lu`]: `P A = L U`, so the row
/// interchanges are all made first (`dense_lu` swaps whole rows, L's multipliers with them:
/// applying each interchange between the eliminations instead, as the border's solve once did,
/// pairs a multiplier with the wrong row as soon as a later column interchanges rows, which
/// a border of two unknowns never does, but three do).
fn dense_solve(a: &[f64], k: usize, pivots: &[usize], b: &mut [f64]) {
    for (col, &p) in pivots.iter().enumerate().take(k) {
        b.swap(col, p);
    }
    for col in 0..k {
        for row in col + 1..k {
            b[row] -= a[row * k + col] * b[col];
        }
    }
    for row in (0..k).rev() {
        let u = &a[row * k + row + 1..(row + 1) * k];
        let known: f64 = u.iter().zip(&b[row + 1..]).map(|(a, b)| a * b).sum();
        b[row] = (b[row] - known) / a[row * k + row];
    }
}

/// The substitution for half-bandwidth `KD` as a [`crate::fast::Kernel`]: two rows ahead
/// ([`BandedLu::solve_band_ahead`]) or one ([`BandedLu::solve_band_fixed`]).
struct FixedSolve<'a, const KD: usize, const AHEAD: bool> {
    lu: &'a BandedLu,
    b: &'a mut [f64],
}

impl<const KD: usize, const AHEAD: bool> crate::fast::Kernel for FixedSolve<'_, KD, AHEAD> {
    type Output = ();

    #[inline(always)]
    fn run<A: MulAdd>(self, arith: A) {
        if AHEAD {
            self.lu.solve_band_ahead::<KD, A>(self.b, arith);
        } else {
            self.lu.solve_band_fixed::<KD, A>(self.b, arith);
        }
    }
}

/// How many of the `kd + 1 = 6` weights of a row two ahead ([`BandedLu::solve_band_ahead`])
/// may be non-zero for each of a node's three rows, forward and backward, where the factors are
/// a chain of nodes of three ([`BandedLu::node_blocks`]). Forward, row `r` of L reaches
/// `3 + r` values back, and its row two ahead reaches as far as the row before it reaches from
/// there: rows 1 and 2 the `3 + r` (their weight of the right-hand side one back, then values
/// 2 to `3 + r` back: `3 + r` weights), row 0 as far as the last node's row 2 (`5 + 1` back:
/// all six). Backward (U reaches `5 - r` values on) the same from the other end: row 2 all six,
/// rows 1 and 0 `5 - r`.
const AHEAD_OF_THREE: ([usize; 3], [usize; 3]) = ([6, 4, 5], [5, 4, 6]);

/// The rows two ahead (`kd + 1 = 6` weights each) of a chain of nodes of three, a node's 15
/// weights at a time: row `r`'s first `lengths[r]`; `None` if a weight beyond is not an exact
/// zero (then they are not the chain's).
fn compact_nodes(rows: &[f64], lengths: [usize; 3]) -> Option<Vec<f64>> {
    let mut out = Vec::with_capacity(rows.len() / 18 * 15);
    for node in rows.chunks_exact(18) {
        for (r, row) in node.chunks_exact(6).enumerate() {
            let (kept, beyond) = row.split_at(lengths[r]);
            if beyond.iter().any(|&w| w != 0.0) {
                return None;
            }
            out.extend_from_slice(kept);
        }
    }
    Some(out)
}

/// [`BandedLu::solve_ahead_of_three`] as a [`crate::fast::Kernel`].
struct AheadOfThree<'a> {
    lu: &'a BandedLu,
    b: &'a mut [f64],
}

impl crate::fast::Kernel for AheadOfThree<'_> {
    type Output = ();

    #[inline(always)]
    fn run<A: MulAdd>(self, arith: A) {
        self.lu.solve_ahead_of_three(self.b, arith);
    }
}

/// [`BandedLu::solve_node_matrices`] as a [`crate::fast::Kernel`].
struct NodeMatrices<'a> {
    lu: &'a BandedLu,
    b: &'a mut [f64],
}

impl crate::fast::Kernel for NodeMatrices<'_> {
    type Output = ();

    #[inline(always)]
    fn run<A: MulAdd>(self, arith: A) {
        self.lu.solve_node_matrices(self.b, arith);
    }
}

/// `own x - other last` for 6 x 6 matrices column by column, the product with `last` in two
/// partial sums (a function, not a closure: a closure's body was not compiled into the
/// kernel's copy with the fused multiply-add, and called the library's). `own` is triangular,
/// lower with `OWN_LOWER` (`P_i`), else upper (`R_i`): its rows 0..4 and 4..6 (a vector and a
/// half) are taken apart, each from the columns not zero in it (the lower's rows 0..4 from
/// columns 0..4, the upper's rows 4..6 from columns 4..6: 10 and 8 of the 12 products, the
/// same sums, since the terms left out are zeros).
#[inline(always)]
fn node_step<const OWN_LOWER: bool, A: MulAdd>(
    arith: A,
    (own, x): (&[f64], &[f64]),
    (other, last): (&[f64], &[f64; 6]),
) -> [f64; 6] {
    const M: usize = 6;
    let (own, other) = (&own[..M * M], &other[..M * M]);
    let mut t = [0.0; M];
    let (top, bottom) = if OWN_LOWER { (0..4, 0..M) } else { (0..M, 4..M) };
    for c in top {
        for r in 0..4 {
            t[r] = arith.mul_add(own[c * M + r], x[c], t[r]);
        }
    }
    for c in bottom {
        for r in 4..M {
            t[r] = arith.mul_add(own[c * M + r], x[c], t[r]);
        }
    }
    let (mut s0, mut s1) = ([0.0; M], [0.0; M]);
    for c in 0..M / 2 {
        for r in 0..M {
            s0[r] = arith.mul_add(other[c * M + r], last[c], s0[r]);
            s1[r] = arith.mul_add(other[(c + M / 2) * M + r], last[c + M / 2], s1[r]);
        }
    }
    std::array::from_fn(|r| (t[r] - s0[r]) - s1[r])
}

/// The solve with a factorisation at which its [`node_matrices`] are made: until then the
/// fixed-width path solves. They take some 70 us to make at 256 nodes and save some 3 us a
/// solve: the one-off factorisation of an event's re-step is solved two to five times, a kept
/// one hundreds (the paper's tip in 3D made 16 of the first kind and 2 of the second in 1 ms).
const NODE_MATRICES_AFTER: usize = 8;

/// The substitutions of factors with [`BandedLu::node_blocks`] at half-bandwidth 11 (nodes of
/// six coupled to their neighbours only) as each node's matrices, 6 x 6 column by column:
/// L's rows of node i are `L_ii y_i + C_i y_(i-1)` (`L_ii` unit lower triangular, `C_i` the
/// weights of the node before), so `y_i = P_i b_i - E_i y_(i-1)` with `P_i = L_ii^-1` and
/// `E_i = P_i C_i`; U's rows scaled by their diagonal `D_i` are `V_ii x_i + G_i x_(i+1)`
/// (`V_ii` unit upper triangular), so `x_i = R_i y_i - F_i x_(i+1)` with
/// `R_i = V_ii^-1 D_i^-1` and `F_i = V_ii^-1 G_i`. A node's `[P, E, R, F]` at `144 i ..`.
fn node_matrices(
    lower_rows: &[f64],
    scaled_upper: &[f64],
    inverse_diagonal: &[f64],
    out: &mut Vec<f64>,
) {
    const M: usize = 6;
    const KD: usize = 11;
    let nodes = inverse_diagonal.len() / M;
    // (Into the last factorisation's buffer: no new allocation of its some 300 kB.)
    out.resize(nodes * 4 * M * M, 0.0);
    for (i, matrices) in out.chunks_exact_mut(4 * M * M).enumerate() {
        let (l, u) = (&lower_rows[i * M * KD..], &scaled_upper[i * M * KD..]);
        // Row r's weight of this node's column c < r, and of the node before's column c
        // (row 6 i + r of L reaches j + 1 columns back at `r * KD + j`).
        let own_lower = |r: usize, c: usize| l[r * KD + (r - 1 - c)];
        let before = |r: usize, c: usize| l[r * KD + (r + M - 1 - c)];
        // U's row r (scaled) at this node's column c > r, and the next node's column c.
        let own_upper = |r: usize, c: usize| u[r * KD + (c - r - 1)];
        let after = |r: usize, c: usize| u[r * KD + (M + c - r - 1)];
        // P = L_ii^-1 by forward substitution on the identity's columns; V^-1 likewise.
        let mut p = [[0.0; M]; M];
        let mut v = [[0.0; M]; M];
        for c in 0..M {
            for r in 0..M {
                let unit = if r == c { 1.0 } else { 0.0 };
                p[r][c] = unit - (0..r).map(|k| own_lower(r, k) * p[k][c]).sum::<f64>();
            }
            for r in (0..M).rev() {
                let unit = if r == c { 1.0 } else { 0.0 };
                v[r][c] = unit - (r + 1..M).map(|k| own_upper(r, k) * v[k][c]).sum::<f64>();
            }
        }
        let d = &inverse_diagonal[i * M..(i + 1) * M];
        let (pm, rest) = matrices.split_at_mut(M * M);
        let (em, rest) = rest.split_at_mut(M * M);
        let (rm, fm) = rest.split_at_mut(M * M);
        for c in 0..M {
            for r in 0..M {
                pm[c * M + r] = p[r][c];
                em[c * M + r] =
                    if i == 0 { 0.0 } else { (0..M).map(|k| p[r][k] * before(k, c)).sum() };
                rm[c * M + r] = v[r][c] * d[c];
                fm[c * M + r] =
                    if i + 1 == nodes { 0.0 } else { (0..M).map(|k| v[r][k] * after(k, c)).sum() };
            }
        }
    }
}

/// A triangular factor's rows `rows` (row `i`'s `kd` weights of the values 1 to `kd` rows
/// away at `i * kd ..`, the row `neighbour(i)` one nearer the start of the substitution)
/// rewritten to reach two rows away: row `i` becomes `[w, r_1 - w s_0, ..., r_kd - w s_(kd-1)]`
/// with `w = r_0` and `s` the neighbour's row (`r_kd = 0`; no neighbour, no change).
fn two_ahead(
    rows: &[f64],
    n: usize,
    kd: usize,
    neighbour: impl Fn(usize) -> Option<usize>,
) -> Vec<f64> {
    let mut ahead = vec![0.0; n * (kd + 1)];
    for i in 0..n {
        let row = &rows[i * kd..(i + 1) * kd];
        let out = &mut ahead[i * (kd + 1)..(i + 1) * (kd + 1)];
        let w = row.first().copied().unwrap_or(0.0);
        out[0] = w;
        for j in 1..=kd {
            out[j] = if j < kd { row[j] } else { 0.0 };
        }
        if let Some(m) = neighbour(i).filter(|&m| m < n) {
            let near = &rows[m * kd..(m + 1) * kd];
            for j in 1..=kd {
                out[j] -= w * near[j - 1];
            }
        }
    }
    ahead
}

/// [`BandedLu::solve_coupled_border`] as a [`crate::fast::Kernel`] (a struct, not a closure:
/// a closure's body is not inlined into the wider copy, and runs in the baseline one).
struct CoupledBorder<'a> {
    lu: &'a BandedLu,
    top: &'a mut [f64],
    border: &'a mut [f64],
}

impl crate::fast::Kernel for CoupledBorder<'_> {
    type Output = ();

    #[inline(always)]
    fn run<A: MulAdd>(self, _: A) {
        self.lu.solve_coupled_border(self.top, self.border);
    }
}

/// `Singular` unless every entry of the solution is finite.
fn finite(b: &[f64], t: f64) -> Result<(), HhtError> {
    if crate::fast::run_lanes(ZeroSum(b)).is_finite() {
        Ok(())
    } else {
        Err(HhtError::Singular { t, reason: "the solution is not finite".into() })
    }
}

/// `sum x * 0`: 0 if every `x` is finite, NaN otherwise (a sum on vectors instead of a test
/// a value).
struct ZeroSum<'a>(&'a [f64]);

impl Lanes for ZeroSum<'_> {
    type Output = f64;

    #[inline(always)]
    fn run<S: Simd>(self, simd: S) -> f64 {
        #[inline(always)]
        fn sum<S: Simd>(simd: S, x: &[f64]) -> f64 {
            // Four sums side by side: one would be a chain of multiply-adds as long as x.
            let zero = simd.splat_f64s(0.0);
            let lanes = S::as_simd_f64s(x).0;
            let (mut s0, mut s1, mut s2, mut s3) = (zero, zero, zero, zero);
            let mut quads = lanes.chunks_exact(4);
            for q in &mut quads {
                s0 = simd.mul_add_e_f64s(q[0], zero, s0);
                s1 = simd.mul_add_e_f64s(q[1], zero, s1);
                s2 = simd.mul_add_e_f64s(q[2], zero, s2);
                s3 = simd.mul_add_e_f64s(q[3], zero, s3);
            }
            for x in quads.remainder() {
                s0 = simd.mul_add_e_f64s(*x, zero, s0);
            }
            let total = simd.add_f64s(simd.add_f64s(s0, s1), simd.add_f64s(s2, s3));
            simd.reduce_sum_f64s(total)
        }
        let (head, tail) = self.0.split_at(whole::<S>(self.0.len()));
        sum(simd, head) + sum(Scalar::new(), tail)
    }
}

/// The substitution two rows ahead ([`BandedLu::solve_band_ahead`]) in one direction: the
/// values solved two and more rows back (`known[j]` = the row `2 + j` back), the last one and
/// the last right-hand side.
struct Ahead<const KD: usize> {
    known: [f64; KD],
    newest: f64,
    last_b: f64,
}

impl<const KD: usize> Default for Ahead<KD> {
    fn default() -> Self {
        Self { known: [0.0; KD], newest: 0.0, last_b: 0.0 }
    }
}

impl<const KD: usize> Ahead<KD> {
    /// The next row's value from its right-hand side `b_now` and its `KD + 1` weights
    /// (`w[0]` on the last right-hand side, `w[1 + j]` on the value `2 + j` rows back).
    #[inline(always)]
    fn next<A: MulAdd>(&mut self, b_now: f64, w: &[f64], arith: A) -> f64 {
        self.next_within(b_now, &w[..KD + 1], arith)
    }

    /// [`Ahead::next`] with the row's first `w.len()` weights (those beyond are zeros): the
    /// same operations but for the terms of zero weight, which add nothing (`x - 0 y` is `x`
    /// for a finite `y`).
    #[inline(always)]
    fn next_within<A: MulAdd>(&mut self, b_now: f64, w: &[f64], arith: A) -> f64 {
        let mut far = arith.mul_add(-w[0], self.last_b, b_now);
        for j in (1..w.len() - 1).rev() {
            far = arith.mul_add(-w[j + 1], self.known[j], far);
        }
        let y = arith.mul_add(-w[1], self.known[0], far);
        for j in (1..KD).rev() {
            self.known[j] = self.known[j - 1];
        }
        self.known[0] = self.newest;
        (self.newest, self.last_b) = (y, b_now);
        y
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use faer::Col;

    #[test]
    fn a_solution_with_any_non_finite_entry_is_refused() {
        // Every position, in the vectors' part and in the one-lane rest, and huge finite
        // values (whose product with 0 is still 0) accepted.
        for n in [1, 4, 7, 13] {
            let fine: Vec<f64> = (0..n).map(|i| 1e300 * (i as f64 - 3.0)).collect();
            assert!(finite(&fine, 0.0).is_ok(), "n {n}");
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                for at in 0..n {
                    let mut x = fine.clone();
                    x[at] = bad;
                    assert!(finite(&x, 0.0).is_err(), "n {n}, {bad} at {at}");
                }
            }
        }
    }

    /// A cheap, deterministic pseudo-random sequence in [-1, 1].
    fn noise(seed: &mut u64) -> f64 {
        *seed =
            seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// A random banded matrix with a border; `weak_diagonal` makes pivoting necessary.
    fn matrix(n: usize, kd: usize, k: usize, weak_diagonal: bool, seed: &mut u64) -> Triplets {
        let mut t = Triplets::new();
        let total = n + k;
        for i in 0..total {
            for j in 0..total {
                let in_band = i < n && j < n && i.abs_diff(j) <= kd;
                let in_border = i >= n || j >= n;
                if !(in_band || in_border) {
                    continue;
                }
                let mut v = noise(seed);
                if i == j && !weak_diagonal {
                    v += 4.0 * kd as f64 + k as f64;
                }
                if i == j && weak_diagonal {
                    v *= 1e-3;
                }
                t.push(i, j, v);
            }
        }
        t
    }

    #[test]
    fn solves_banded_bordered_systems_to_round_off() {
        // Against the product A x for a known x: relative residual at the level of round-off
        // times the condition (diagonally dominant: ~1e-15; weak diagonal with pivoting: the
        // condition grows, 1e-10 still catches a wrong interchange, which gives O(1)).
        let mut seed = 3;
        for (n, kd, k, weak) in [
            (1, 0, 0, false),
            // The planar beam's path two rows ahead on fewer rows than its half-bandwidth.
            (1, 5, 0, false),
            (3, 5, 1, false),
            (6, 5, 2, false),
            (12, 2, 0, false),
            (40, 5, 2, false),
            (41, 5, 2, false),
            (40, 5, 2, true),
            (7, 6, 3, true),
            // The 3D beam's fixed-width path (kd = 11, no interchange) and its pivoting one.
            (66, 11, 3, false),
            (67, 11, 0, false),
            (66, 11, 3, true),
        ] {
            let a = matrix(n, kd, k, weak, &mut seed);
            let total = n + k;
            let x: Vec<f64> = (0..total).map(|_| noise(&mut seed)).collect();
            let mut b = vec![0.0; total];
            a.mul_vec(&x, &mut b);
            let mut lu = BandedLu::new();
            lu.factor(total, Band { half_bandwidth: kd, border: k }, &a, 0.0).unwrap();
            let mut rhs = Col::<f64>::from_fn(total, |i| b[i]);
            lu.solve_in_place(rhs.as_mut(), 0.0).unwrap();
            let err = (0..total).map(|i| (rhs[i] - x[i]).abs()).fold(0.0, f64::max);
            let tol = if weak { 1e-10 } else { 1e-13 };
            assert!(err < tol, "n {n} kd {kd} k {k} weak {weak}: error {err:e}");
        }
    }

    /// A chain of `nodes` nodes of `m` unknowns each, coupled to its neighbours, with a dense
    /// border of `k` (random entries, `diagonal` added on the diagonal; symmetric if asked) and
    /// the `extra` entries, factorised at half-bandwidth `2 m - 1`; a random system with it is
    /// solved to round-off. Returns the factors, the band's size and the right-hand side.
    /// A chain of `nodes` nodes of `m` unknowns with a border of `k`, factorised by `lu` (a
    /// solver used before, or a new one) and its solution checked.
    fn node_chain(
        (m, nodes, k): (usize, usize, usize),
        (symmetric, diagonal): (bool, f64),
        extra: &[(usize, usize, f64)],
        (mut lu, seed): (BandedLu, &mut u64),
    ) -> (BandedLu, usize, Vec<f64>) {
        let n = m * nodes;
        let mut a = Triplets::new();
        for i in 0..n + k {
            for j in if symmetric { i } else { 0 }..n + k {
                let neighbours = i < n && j < n && (i / m).abs_diff(j / m) <= 1;
                if neighbours || i >= n || j >= n {
                    let v = noise(seed) + if i == j { diagonal } else { 0.0 };
                    a.push(i, j, v);
                    if symmetric && i != j {
                        a.push(j, i, v);
                    }
                }
            }
        }
        for &(i, j, v) in extra {
            a.push(i, j, v);
        }
        let x: Vec<f64> = (0..n + k).map(|_| noise(seed)).collect();
        let mut b = vec![0.0; n + k];
        a.mul_vec(&x, &mut b);
        lu.factor(n + k, Band { half_bandwidth: 2 * m - 1, border: k }, &a, 0.0).unwrap();
        // Solved again and again: a chain of nodes of six by the fixed-width path, then from
        // the factorisation's eighth solve by its nodes' matrices; both to round-off.
        assert!(lu.node_matrices.is_empty());
        let due = lu.node_matrices_due;
        for solve in 1..=NODE_MATRICES_AFTER + 2 {
            let mut rhs = Col::<f64>::from_fn(n + k, |i| b[i]);
            lu.solve_in_place(rhs.as_mut(), 0.0).unwrap();
            let err = (0..n + k).map(|i| (rhs[i] - x[i]).abs()).fold(0.0, f64::max);
            assert!(err < 1e-13, "extra entries {extra:?}, solve {solve}: error {err:e}");
            assert_eq!(lu.node_matrices.is_empty(), !(due && solve >= NODE_MATRICES_AFTER));
        }
        (lu, n, b)
    }

    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }

    #[test]
    fn a_chain_of_six_unknown_nodes_is_solved_by_each_node_s_matrices() {
        // A chain of nodes of six unknowns each coupled to its neighbours (the 3D beam's
        // pattern, half-bandwidth 11) with a border of three: the nodes' matrices give the
        // fixed-width substitution's result to round-off (other sums of the same factors: a
        // few ulps of the solution, entries of order one, on a diagonally dominant matrix), and
        // `node_chain` checks the solution itself by both, before and after the matrices are
        // made (and that a factorisation makes them anew); one node alone too (no node before
        // or after). One entry two nodes away (inside the band) turns them off, and the fixed
        // path still solves, with the solver of a chain used again.
        let mut seed = 11;
        let mut lu = BandedLu::new();
        for (nodes, far_entry) in [(12, false), (1, false), (12, true)] {
            let extra = if far_entry { vec![(30, 30 - 11, 0.5)] } else { vec![] };
            let chain = node_chain((6, nodes, 3), (false, 60.0), &extra, (lu, &mut seed));
            let (n, b);
            (lu, n, b) = chain;
            assert_eq!(lu.node_blocks, !far_entry);
            assert_eq!(lu.node_matrices.is_empty(), far_entry);
            // The band's substitution alone, both ways.
            let mut fixed = b[..n].to_vec();
            crate::fast::run(FixedSolve::<11, false> { lu: &lu, b: &mut fixed });
            let mut by_nodes = b[..n].to_vec();
            lu.solve_band(&mut by_nodes);
            let scale = fixed.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            for (a, b) in by_nodes.iter().zip(&fixed) {
                assert!((a - b).abs() <= 1e-14 * scale, "far entry {far_entry}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn a_chain_of_three_unknown_nodes_skips_the_zeros_two_ahead_to_the_bit() {
        // Nodes of three coupled to their neighbours (the planar beam's pattern, half-bandwidth
        // 5), symmetric positive definite, with a border of two: the compact rows two ahead
        // give the full rows' result to the bit, and the solution to round-off. An entry two
        // nodes away (inside the band) turns them off, and the full rows still solve.
        let mut seed = 5;
        for far_entry in [false, true] {
            let extra = if far_entry { vec![(30, 25, 0.5), (25, 30, 0.5)] } else { vec![] };
            let (lu, n, b) =
                node_chain((3, 20, 2), (true, 40.0), &extra, (BandedLu::new(), &mut seed));
            assert_eq!(lu.lower_ahead_nodes.is_empty(), far_entry);
            let mut full = b[..n].to_vec();
            crate::fast::run(FixedSolve::<5, true> { lu: &lu, b: &mut full });
            let mut compact = b[..n].to_vec();
            lu.solve_band(&mut compact);
            assert_eq!(bits(&compact), bits(&full), "far entry {far_entry}");
        }
    }

    #[test]
    fn a_border_touching_a_few_unknowns_is_solved_to_round_off() {
        // A ball on one element: D's rows are zero but for a few unknowns (the solve's products
        // of D run over those alone), C's columns likewise, at the start, inside and at the end
        // of the band.
        let mut seed = 9;
        for (n, first, last) in [(40, 0, 3), (41, 17, 22), (40, 34, 39)] {
            let full = matrix(n, 5, 2, false, &mut seed);
            let mut t = Triplets::new();
            for (r, c, v) in full.iter() {
                let band = |i: usize| i >= n || (first..=last).contains(&i);
                if (r < n && c < n) || (band(r) && band(c)) {
                    t.push(r, c, v);
                }
            }
            let x: Vec<f64> = (0..n + 2).map(|_| noise(&mut seed)).collect();
            let mut b = vec![0.0; n + 2];
            t.mul_vec(&x, &mut b);
            let mut lu = BandedLu::new();
            lu.factor(n + 2, Band { half_bandwidth: 5, border: 2 }, &t, 0.0).unwrap();
            assert!(lu.coupled);
            assert_eq!(lu.border_spans, vec![first..last + 1; 2]);
            let mut rhs = Col::<f64>::from_fn(n + 2, |i| b[i]);
            lu.solve_in_place(rhs.as_mut(), 0.0).unwrap();
            let err = (0..n + 2).map(|i| (rhs[i] - x[i]).abs()).fold(0.0, f64::max);
            assert!(err < 1e-13, "n {n}, border on {first}..={last}: error {err:e}");
        }
    }

    #[test]
    fn an_uncoupled_border_is_solved_on_its_own() {
        // A ball out of contact: the border couples to nothing (C = D = 0), so the factors skip
        // B^-1 C; the band's unknowns and the border's are each solved to round-off, with an
        // odd and an even number of rows (the substitution's row pairs and the row left over).
        let mut seed = 5;
        for n in [40, 41] {
            let full = matrix(n, 5, 2, false, &mut seed);
            let mut t = Triplets::new();
            for (r, c, v) in full.iter() {
                if (r < n) == (c < n) {
                    t.push(r, c, v);
                }
            }
            let x: Vec<f64> = (0..n + 2).map(|_| noise(&mut seed)).collect();
            let mut b = vec![0.0; n + 2];
            t.mul_vec(&x, &mut b);
            let mut lu = BandedLu::new();
            lu.factor(n + 2, Band { half_bandwidth: 5, border: 2 }, &t, 0.0).unwrap();
            assert!(!lu.coupled);
            let mut rhs = Col::<f64>::from_fn(n + 2, |i| b[i]);
            lu.solve_in_place(rhs.as_mut(), 0.0).unwrap();
            let err = (0..n + 2).map(|i| (rhs[i] - x[i]).abs()).fold(0.0, f64::max);
            assert!(err < 1e-13, "n {n}: error {err:e}");
        }
    }

    #[test]
    fn symmetric_positive_definite_bands_need_no_interchange() {
        // A = G^T G + 1e-6 I with G random and upper-banded (two super-diagonals, so A's band is
        // within kd = 5): symmetric positive definite with diagonals no larger than many of
        // their off-diagonals, as a beam's rotation rows. Elimination without interchanges
        // keeps U at kd super-diagonals and solves to round-off of the condition (1e-9).
        let (n, kd): (usize, usize) = (60, 5);
        let mut seed = 11;
        let g: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n).map(|j| if j >= i && j - i <= 2 { noise(&mut seed) } else { 0.0 }).collect()
            })
            .collect();
        let mut t = Triplets::new();
        for i in 0..n {
            for j in 0..n {
                if i.abs_diff(j) <= kd {
                    let v: f64 = (0..n).map(|m| g[m][i] * g[m][j]).sum::<f64>()
                        + if i == j { 1e-6 } else { 0.0 };
                    t.push(i, j, v);
                }
            }
        }
        let x: Vec<f64> = (0..n).map(|_| noise(&mut seed)).collect();
        let mut b = vec![0.0; n];
        t.mul_vec(&x, &mut b);
        let mut lu = BandedLu::new();
        lu.factor(n, Band { half_bandwidth: kd, border: 0 }, &t, 0.0).unwrap();
        assert_eq!(lu.upper, kd, "a row interchange was made");
        let mut rhs = Col::<f64>::from_fn(n, |i| b[i]);
        lu.solve_in_place(rhs.as_mut(), 0.0).unwrap();
        let err = (0..n).map(|i| (rhs[i] - x[i]).abs()).fold(0.0, f64::max);
        assert!(err < 1e-9, "error {err:e}");
    }

    #[test]
    fn dense_factors_with_a_later_interchange_solve_exactly() {
        // Column 0 keeps its row, column 1 interchanges rows 1 and 2 (after the first
        // elimination row 1 is (0, 0, 2)): every right-hand side against A x. Applying the
        // interchanges between the eliminations gave an O(1) error here.
        let a0 = [4.0, 1.0, 2.0, 2.0, 0.5, 3.0, 1.0, 3.0, 1.0];
        let mut a = a0;
        let mut pivots = [0; 3];
        dense_lu(&mut a, 3, &mut pivots, 0.0, "").unwrap();
        assert_eq!(pivots, [0, 2, 2]);
        for x in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.3, -2.0, 5.0]] {
            let mut b: Vec<f64> =
                (0..3).map(|i| (0..3).map(|j| a0[i * 3 + j] * x[j]).sum()).collect();
            dense_solve(&a, 3, &pivots, &mut b);
            for (got, want) in b.iter().zip(x) {
                assert!((got - want).abs() < 1e-15, "{b:?} vs {x:?}");
            }
        }
    }

    #[test]
    fn refuses_entries_outside_the_band_and_zero_pivots() {
        let mut t = Triplets::new();
        t.push(0, 3, 1.0);
        let band = Band { half_bandwidth: 1, border: 0 };
        assert!(matches!(BandedLu::new().factor(4, band, &t, 0.0), Err(HhtError::Model(_))));
        let mut zero = Triplets::new();
        zero.push(1, 1, 1.0);
        assert!(matches!(
            BandedLu::new().factor(2, band, &zero, 0.5),
            Err(HhtError::Singular { .. })
        ));
    }
}
