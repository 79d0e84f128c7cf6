//! The natural modes of a long beam or frame below a frequency: shift-invert Lanczos on a
//! banded factorisation, with the count checked by Sylvester's law of inertia.
//!
//! `K phi = lambda M phi` (lambda = omega^2) with K and M the tangent's stiffness and mass
//! parts at rest, symmetric and banded (a chain of elements numbered node by node: half-band
//! 11 for the 3D beam). Steps (Ericsson & Ruhe 1980, "The spectral transformation Lanczos
//! method"; Parlett, The Symmetric Eigenvalue Problem, ch. 13):
//!
//! 1. **How many**: `K - lambda M = L D L^T` (banded, no interchanges); its negative pivots
//!    are the number of eigenvalues below `lambda` (Sylvester: D has the inertia of
//!    `K - lambda M`, and `M` is positive definite). Counted at the cutoff, and at the points
//!    that cut `(-1e-6 lambda_max, lambda_max]` into slices of at most [`SLICE`] modes
//!    (bisection in omega).
//! 2. **Which**, slice by slice: Lanczos on `(K - sigma M)^-1 M` in the M inner product,
//!    `sigma` in the slice's middle (its modes are then the operator's largest |theta|; the
//!    lowest slice starts below zero, so a free structure's rigid-body modes are inside it),
//!    each new vector M-orthogonalised against all the previous ones (classical Gram-Schmidt
//!    twice: full reorthogonalisation). The tridiagonal `T`'s eigenpairs `(theta, s)` give
//!    `lambda = sigma + 1/theta`, `phi = Q s` (M-orthonormal), converged when
//!    `beta |s_last| <= 1e-9 |theta|`, until as many converged Ritz values lie in the slice as
//!    the counts say (a mode a single start vector cannot see, such as an exact double
//!    eigenvalue, shows as a shortfall and is refused with both counts, not silently dropped).
//! 3. **Refined**: a shape whose residual `|K phi - lambda M phi| / |lambda M phi|` is above
//!    1e-9 takes inverse iteration steps at its own eigenvalue (the Lanczos bound is on the
//!    inverted operator, and a stiff strip's spread turns it into up to 3e-6 in `K`).
//!
//! A mode below `RIGID` times the largest diagonal ratio `K_ii / M_ii` (45 eps of it: the
//! stiffness' round-off, which no computed eigenvalue is more accurate than) is rigid (omega
//! 0): counted by a tolerance, not by an exact zero. On a very slender fine mesh that is a
//! real floor: the paper's strip on 40 elements has it at 6e-4 rad^2/s^2 (its rigid modes come
//! out below 1e-5), a 1 x 25 mm strip on 512 elements at 0.14 (its first mode at 5.4).

use crate::error::BeamError;
use crate::modes::Mode;
use faer::{Col, Mat, Side};
use hht::{Model, NewtonWeights, Triplets};

/// An eigenvalue below this fraction of the largest `K_ii / M_ii` is a rigid-body mode's.
const RIGID: f64 = 1e-14;
/// A Ritz pair is converged when its residual bound is below this fraction of theta: its
/// Ritz value is then good to about the square of it, and its shape is refined afterwards
/// ([`refine`]). Tighter bounds are out of reach for the modes near the cutoff: their theta is
/// 1e-5 of the rigid modes' and the solves' round-off is relative to the largest.
const CONVERGED: f64 = 1e-9;

/// A symmetric banded matrix: row `i` holds columns `i - kd ..= i` (the lower band).
#[derive(Debug, Clone)]
struct Band {
    n: usize,
    kd: usize,
    /// `A[i][j]` at `i * (kd + 1) + (j + kd - i)` for `i - kd <= j <= i`.
    a: Vec<f64>,
}

impl Band {
    fn zeros(n: usize, kd: usize) -> Self {
        Self { n, kd, a: vec![0.0; n * (kd + 1)] }
    }

    fn at(&self, i: usize, j: usize) -> f64 {
        self.a[i * (self.kd + 1) + (j + self.kd - i)]
    }

    /// The symmetric part of `t`'s entries, `(T + T^T) / 2`, into the lower band.
    fn add_symmetric(&mut self, t: &Triplets, scale: f64) {
        let w = self.kd + 1;
        for (r, c, v) in t.iter() {
            let (i, j) = if r >= c { (r, c) } else { (c, r) };
            // An off-diagonal entry and its mirror each bring half of their mean.
            let share = if r == c { 1.0 } else { 0.5 };
            self.a[i * w + (j + self.kd - i)] += share * scale * v;
        }
    }

    /// `K - sigma M` for `self` = K and `mass` = M (the same bandwidth).
    fn shifted(&self, mass: &Band, sigma: f64) -> Band {
        let a = self.a.iter().zip(&mass.a).map(|(k, m)| k - sigma * m).collect();
        Band { n: self.n, kd: self.kd, a }
    }

    /// `y = A x`: row `i`'s band times `x` and, mirrored, `x_i` times it into `y` (both on
    /// contiguous slices).
    fn mul(&self, x: &[f64], y: &mut [f64]) {
        let (kd, w) = (self.kd, self.kd + 1);
        y.fill(0.0);
        for i in 0..self.n {
            let start = i.saturating_sub(kd);
            let row = &self.a[i * w + (start + kd - i)..i * w + kd];
            let xi = x[i];
            let mut sum = 0.0;
            for ((yj, xj), a) in y[start..i].iter_mut().zip(&x[start..i]).zip(row) {
                sum += a * xj;
                *yj += a * xi;
            }
            y[i] += sum + self.a[i * w + kd] * xi;
        }
    }
}

/// `A = L D L^T` of a symmetric banded matrix, without interchanges.
#[derive(Debug)]
struct Ldlt {
    n: usize,
    kd: usize,
    /// Unit lower band, as [`Band::a`] (the diagonal slot unused).
    l: Vec<f64>,
    d: Vec<f64>,
}

impl Ldlt {
    /// # Errors
    /// [`BeamError::Eigen`] for a zero (or not finite) pivot: the shift is an eigenvalue.
    fn factor(a: &Band) -> Result<Self, BeamError> {
        let (n, kd) = (a.n, a.kd);
        let w = kd + 1;
        let mut l = vec![0.0; n * w];
        let mut d = vec![0.0; n];
        for j in 0..n {
            let start = j.saturating_sub(kd);
            let mut dj = a.at(j, j);
            for k in start..j {
                let ljk = l[j * w + (k + kd - j)];
                dj -= ljk * ljk * d[k];
            }
            if !(dj.is_finite() && dj != 0.0) {
                return Err(BeamError::Eigen(format!(
                    "the shifted stiffness has a zero pivot at unknown {j}: the shift is an eigenvalue"
                )));
            }
            d[j] = dj;
            for i in j + 1..n.min(j + kd + 1) {
                let mut v = a.at(i, j);
                for k in i.saturating_sub(kd)..j {
                    v -= l[i * w + (k + kd - i)] * l[j * w + (k + kd - j)] * d[k];
                }
                l[i * w + (j + kd - i)] = v / dj;
            }
        }
        Ok(Self { n, kd, l, d })
    }

    /// Eigenvalues of the factored matrix below zero (Sylvester's inertia).
    fn negatives(&self) -> usize {
        self.d.iter().filter(|d| **d < 0.0).count()
    }

    /// `b <- A^-1 b`: forward by rows of L, then by D, then backward by L's rows as columns
    /// of L^T (each solved unknown taken out of the ones before it), every loop on
    /// contiguous slices.
    fn solve(&self, b: &mut [f64]) {
        let (kd, w) = (self.kd, self.kd + 1);
        for i in 0..self.n {
            let start = i.saturating_sub(kd);
            let row = &self.l[i * w + (start + kd - i)..i * w + kd];
            let v: f64 = row.iter().zip(&b[start..i]).map(|(l, x)| l * x).sum();
            b[i] -= v;
        }
        for (bi, di) in b.iter_mut().zip(&self.d) {
            *bi /= di;
        }
        for i in (0..self.n).rev() {
            let start = i.saturating_sub(kd);
            let row = &self.l[i * w + (start + kd - i)..i * w + kd];
            let xi = b[i];
            for (bj, l) in b[start..i].iter_mut().zip(row) {
                *bj -= l * xi;
            }
        }
    }
}

/// The half-bandwidth of `t`'s entries.
fn half_bandwidth(t: &Triplets) -> usize {
    t.iter().map(|(r, c, _)| r.abs_diff(c)).max().unwrap_or(0)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The stiffness and mass parts of `model`'s tangent at `q` (no velocity): the model
/// linearised there, as the eigen-solver takes it.
pub(crate) fn linearised<M: Model>(model: &M, q: &M::Config) -> (Triplets, Triplets) {
    let n = model.ndof();
    let zero = Col::<f64>::zeros(n);
    let mut t = Triplets::new();
    model.tangent(0.0, q, zero.as_ref(), zero.as_ref(), NewtonWeights::stiffness(), &mut t);
    let mut tm = Triplets::new();
    model.tangent(0.0, q, zero.as_ref(), zero.as_ref(), NewtonWeights::mass(), &mut tm);
    (t, tm)
}

/// The stiffness `t` and mass `tm` (entries over `n` unknowns) as bands, and the largest
/// diagonal ratio `K_ii / M_ii` (the scale of the stiffness' round-off: a rigid-body mode's
/// computed eigenvalue is about eps times it; measured 1e-5 on the paper's free strip, where
/// it is 7e10).
///
/// # Errors
/// [`BeamError::Eigen`] for a mass matrix that is not positive definite.
fn banded(n: usize, t: &Triplets, tm: &Triplets) -> Result<(Band, Band, f64), BeamError> {
    let kd = half_bandwidth(t).max(half_bandwidth(tm));
    let mut stiffness = Band::zeros(n, kd);
    stiffness.add_symmetric(t, 1.0);
    let mut mass = Band::zeros(n, kd);
    mass.add_symmetric(tm, 1.0);
    if Ldlt::factor(&mass).map_or(true, |f| f.negatives() > 0) {
        return Err(BeamError::Eigen("the mass matrix is not positive definite".into()));
    }
    let ratio = (0..n).map(|i| stiffness.at(i, i) / mass.at(i, i)).fold(0.0, f64::max);
    Ok((stiffness, mass, ratio))
}

/// How many directions `model`'s equilibrium `q` is unstable in: the eigenvalues of its
/// tangent stiffness below minus the round-off threshold [`RIGID`] x max `K_ii / M_ii` (in the
/// mass's metric), counted by Sylvester's inertia of `K + threshold M` (banded L D L^T). For
/// conservative loads the tangent is symmetric at equilibrium and a negative eigenvalue is a
/// direction of falling energy: the beam past a buckling load on the branch it started on.
/// `None` where the count cannot be made (a mass that is not positive definite, a pivot that
/// is exactly zero: the threshold itself an eigenvalue).
pub(crate) fn unstable_directions<M: Model>(model: &M, q: &M::Config) -> Option<usize> {
    let (t, tm) = linearised(model, q);
    let (stiffness, mass, ratio) = banded(model.ndof(), &t, &tm).ok()?;
    Some(Ldlt::factor(&stiffness.shifted(&mass, -RIGID * ratio)).ok()?.negatives())
}

/// How many rigid-body modes the model of stiffness `t` and mass `tm` (over `n` unknowns)
/// has: its eigenvalues below the round-off threshold [`RIGID`] x max `K_ii / M_ii` (those
/// [`modes_below`] sets to omega = 0), counted by Sylvester's inertia. 0 for a held
/// structure, 6 for a free body, between for a mechanism.
///
/// # Errors
/// As [`banded`], and a shift that hits an eigenvalue exactly.
pub(crate) fn rigid_body_modes(n: usize, t: &Triplets, tm: &Triplets) -> Result<usize, BeamError> {
    let (stiffness, mass, ratio) = banded(n, t, tm)?;
    Ok(Ldlt::factor(&stiffness.shifted(&mass, RIGID * ratio))?.negatives())
}

/// Every natural mode of the model of stiffness `t` and mass `tm` (over `n` unknowns) with
/// `omega <= omega_max` (rad/s), ascending, mass-normalised; see the module text.
///
/// # Errors
/// [`BeamError::Eigen`] for a cutoff that is not finite and positive, a mass matrix that is not
/// positive definite, a shift that hits an eigenvalue, or a Lanczos run that finds fewer modes
/// below the cutoff than the inertia count says.
pub(crate) fn modes_below(
    n: usize,
    (t, tm): (&Triplets, &Triplets),
    omega_max: f64,
) -> Result<Vec<Mode>, BeamError> {
    if !(omega_max.is_finite() && omega_max > 0.0) {
        return Err(BeamError::Eigen(format!(
            "the cutoff frequency must be finite and greater than 0 rad/s, not {omega_max}"
        )));
    }
    let (stiffness, mass, ratio) = banded(n, t, tm)?;
    let shifted = |sigma: f64| stiffness.shifted(&mass, sigma);
    let lambda_max = omega_max * omega_max;
    let wanted = Ldlt::factor(&shifted(lambda_max))?.negatives();
    if wanted == 0 {
        return Ok(Vec::new());
    }
    // The lowest slice starts below zero: a free structure's rigid-body modes are then inside
    // it, not on its edge. As little below as the round-off allows (a thousand times the
    // rigid modes' threshold, at most a millionth of the cutoff): the lowest mode's
    // eigenvalue is sigma + 1/theta, and a shift far below it cancels its digits (at a
    // millionth of a cutoff of 1e9 rad/s, the first mode of a 6-element frame came out 1.5e-7
    // off, and its share of the static flexibility 3e-7, a residual flexibility's whole size).
    let floor = -(1e3 * RIGID * ratio).min(1e-6 * lambda_max);
    if Ldlt::factor(&shifted(floor))?.negatives() > 0 {
        return Err(BeamError::Eigen(
            "the stiffness has a negative eigenvalue: the configuration is unstable".into(),
        ));
    }
    let count = |lambda: f64| -> Result<usize, BeamError> {
        Ok(Ldlt::factor(&shifted(lambda))?.negatives())
    };
    let mut slices = Vec::new();
    split((floor, 0), (lambda_max, wanted), &count, &mut slices)?;
    let mut modes = Vec::with_capacity(wanted);
    for ((lower, below_lower), (upper, below_upper)) in slices {
        // The shift in the slice's middle: its modes are the operator's largest |theta|. The
        // lowest slice's at its floor, below every eigenvalue: K - sigma M is then positive
        // definite and its factors as accurate as the lowest modes need (a shift among them
        // left the first mode of a 1 mm strip's 128 planar elements 6e-7 off).
        let sigma = if below_lower == 0 { lower } else { 0.5 * (lower + upper) };
        let op = Ldlt::factor(&shifted(sigma))?;
        modes.extend(lanczos(&op, &mass, (sigma, lower, upper), below_upper - below_lower)?);
    }
    for mode in &mut modes {
        // A rigid-body mode is left as Lanczos made it: inverse iteration at its round-off
        // eigenvalue would mix it with the other rigid modes (their eigenvalues are all
        // round-off), and the set would lose its M-orthogonality (a free frame's six modes then
        // left 0.55 of the load they should take out whole).
        if mode.omega * mode.omega <= RIGID * ratio {
            mode.omega = 0.0;
        } else {
            refine(mode, &stiffness, &mass)?;
        }
    }
    Ok(modes)
}

/// Modes a spectrum slice holds at most: Lanczos' cost grows with the square of the modes it
/// finds at once (the reorthogonalisation), so a wide spectrum is cut into slices of this many,
/// each solved from a shift in its middle. The 855 modes below 5e5 rad/s of a 512-element
/// frame (the criterion bench `simo_beam/modes_below_frame_512`): 34 s in one slice; 1.09,
/// 1.01, 0.93, 0.89 s in slices of 32, 24, 16, 12.
const SLICE: usize = 16;

/// A slice's edge: an eigenvalue (rad^2/s^2) and how many lie below it.
type Edge = (f64, usize);

/// Cuts `(lower, upper]` (with the eigenvalue counts below each) into slices of at most
/// [`SLICE`] modes by bisection in omega, the counts by Sylvester's inertia (`count`).
fn split(
    (lower, below_lower): Edge,
    (upper, below_upper): Edge,
    count: &dyn Fn(f64) -> Result<usize, BeamError>,
    out: &mut Vec<(Edge, Edge)>,
) -> Result<(), BeamError> {
    let inside = below_upper.saturating_sub(below_lower);
    if inside == 0 {
        return Ok(());
    }
    // Down to a slice as narrow as 1e-9 of its top: a cluster that fine is solved at once.
    if inside <= SLICE || upper - lower <= 1e-9 * upper.abs() {
        out.push(((lower, below_lower), (upper, below_upper)));
        return Ok(());
    }
    let middle = (0.5 * (lower.max(0.0).sqrt() + upper.sqrt())).powi(2);
    let middle = if middle > lower && middle < upper { middle } else { 0.5 * (lower + upper) };
    let below_middle = count(middle)?;
    split((lower, below_lower), (middle, below_middle), count, out)?;
    split((middle, below_middle), (upper, below_upper), count, out)
}

/// The relative residual `|K phi - lambda M phi| / |lambda M phi|` below which a mode is
/// kept as Lanczos gives it.
const RESIDUAL: f64 = 1e-9;

/// Inverse iteration, shifted just below the mode's own eigenvalue, where its residual is above
/// [`RESIDUAL`] (at most [`REFINEMENTS`] steps). Lanczos' convergence test bounds the residual of the
/// shift-inverted operator; back in `K phi = lambda M phi` that bound is multiplied by the
/// stiffness' spread (`|K - sigma M| / lambda`), so the modes near the cutoff of a stiff
/// strip come out with residuals up to 3e-6 (measured: the paper's strip, 40 elements, at
/// 5.8e4 rad/s). A step at `lambda (1 - 1e-6)` divides the error by `1e-6 lambda` over the
/// gap to the next mode (1e-4 for neighbours 1 % apart); the frequency, a Ritz value accurate
/// to the square of the shape's error, is kept.
fn refine(mode: &mut Mode, stiffness: &Band, mass: &Band) -> Result<(), BeamError> {
    let n = stiffness.n;
    let lambda = mode.omega * mode.omega;
    let phi: Vec<f64> = mode.shape.iter().copied().collect();
    let (mut k_phi, mut m_phi) = (vec![0.0; n], vec![0.0; n]);
    stiffness.mul(&phi, &mut k_phi);
    mass.mul(&phi, &mut m_phi);
    // |K phi - lambda M phi|^2 against RESIDUAL^2 |lambda M phi|^2 (of the first M phi: the
    // shape's size stays one in M).
    let scale = m_phi.iter().map(|m| (lambda * m).powi(2)).sum::<f64>();
    let small = |k_phi: &[f64], m_phi: &[f64]| {
        let residual: f64 = k_phi.iter().zip(m_phi).map(|(k, m)| (k - lambda * m).powi(2)).sum();
        residual <= RESIDUAL * RESIDUAL * scale
    };
    if lambda <= 0.0 || small(&k_phi, &m_phi) {
        return Ok(());
    }
    let factors = Ldlt::factor(&stiffness.shifted(mass, lambda * (1.0 - 1e-6)))?;
    let mut phi = phi;
    for _ in 0..REFINEMENTS {
        let mut z = m_phi.clone();
        factors.solve(&mut z);
        let mut mz = vec![0.0; n];
        mass.mul(&z, &mut mz);
        let norm = dot(&z, &mz).sqrt();
        // The same sign as before (inverse iteration keeps the direction).
        let sign = if dot(&z, &m_phi) < 0.0 { -norm } else { norm };
        phi = z.iter().map(|v| v / sign).collect();
        m_phi = mz.iter().map(|v| v / sign).collect();
        stiffness.mul(&phi, &mut k_phi);
        if small(&k_phi, &m_phi) {
            break;
        }
    }
    for (v, p) in mode.shape.iter_mut().zip(&phi) {
        *v = *p;
    }
    Ok(())
}

/// Inverse iteration steps at most a mode.
const REFINEMENTS: usize = 3;

/// Shift-invert Lanczos with full reorthogonalisation (module text, steps 2 and 3).
fn lanczos(
    op: &Ldlt,
    mass: &Band,
    (sigma, lower, upper): (f64, f64, f64),
    wanted: usize,
) -> Result<Vec<Mode>, BeamError> {
    let n = op.n;
    // Q and M Q, a column a Lanczos vector.
    let mut basis: Vec<Vec<f64>> = Vec::new();
    let mut mbasis: Vec<Vec<f64>> = Vec::new();
    let (mut alpha, mut beta): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
    // A start vector with every unknown in it (a fixed pseudo-random sequence).
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut r: Vec<f64> = (0..n)
        .map(|_| {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        })
        .collect();
    let mut mr = vec![0.0; n];
    mass.mul(&r, &mut mr);
    let mut norm = dot(&r, &mr).sqrt();
    // The Ritz values are first checked after `wanted + 10` vectors, then after a third as
    // many again (at least [`CHECK_EVERY`]): a slice's modes converge after 3 to 4 vectors
    // each, and a check (the tridiagonal's eigen-solution with its vectors, cubic in its size)
    // is worth the vectors a coarser schedule runs past convergence only while it is small.
    // Measured (same machine): the paper's beam on 374 elements (102 modes) 530 vectors with
    // checks after 2 wanted + 10 and then 1.5 times as many + 10, 382 with checks every 6;
    // the 855 modes of the 512-element frame (criterion `modes_below_frame_512`) 1.13 s, 1.34 s
    // every 6, 0.84 s so.
    let mut check = (wanted + 10).min(n);
    loop {
        let qj: Vec<f64> = r.iter().map(|v| v / norm).collect();
        let mqj: Vec<f64> = mr.iter().map(|v| v / norm).collect();
        // w = (K - sigma M)^-1 M q_j.
        let mut w = mqj.clone();
        op.solve(&mut w);
        // alpha = q_j^T M w = (M q_j)^T w (M symmetric): no product by M for it.
        let a = dot(&mqj, &w);
        let mut mw = vec![0.0; n];
        basis.push(qj);
        mbasis.push(mqj);
        alpha.push(a);
        // Full reorthogonalisation (classical Gram-Schmidt twice), M w
        // then computed afresh (updated along, it drifts from M times the w left, by more
        // than that w once the Krylov space nears an invariant one).
        hht::fast::run(Reorthogonalise { basis: &basis, mbasis: &mbasis, w: &mut w });
        mass.mul(&w, &mut mw);
        let b = dot(&w, &mw).max(0.0).sqrt();
        let done = basis.len() >= n || b <= f64::EPSILON * a.abs();
        if basis.len() >= check || done {
            let found = match ritz(&basis, &alpha, &beta, b, (sigma, lower, upper), wanted)? {
                Ok(modes) => return Ok(modes),
                Err(found) => found,
            };
            if done {
                return Err(BeamError::Eigen(format!(
                    "Lanczos found {found} modes between {:e} and {:e} rad/s where the inertia count says {wanted}: a multiple eigenvalue one start vector does not see",
                    lower.max(0.0).sqrt(),
                    upper.sqrt()
                )));
            }
            check = (check + CHECK_EVERY.max(check / 3)).min(n);
        }
        beta.push(b);
        (r, mr, norm) = (w, mw, b);
    }
}

/// Lanczos vectors at least between two checks of the Ritz values (after the first).
const CHECK_EVERY: usize = 6;

/// `w <- w - Q (M Q)^T w`, twice (classical Gram-Schmidt twice, "twice is enough": Giraud,
/// Langou & Rozloznik 2005), in the fast kernels' wide copy: the Lanczos run's cost (on a
/// 512-element frame 90 % of it is here and in the products by M).
struct Reorthogonalise<'a> {
    basis: &'a [Vec<f64>],
    mbasis: &'a [Vec<f64>],
    w: &'a mut [f64],
}

impl hht::fast::Kernel for Reorthogonalise<'_> {
    type Output = ();

    #[inline(always)]
    fn run<A: hht::fast::MulAdd>(self, arith: A) {
        let Reorthogonalise { basis, mbasis, w } = self;
        let mut c = vec![0.0; basis.len()];
        for _ in 0..2 {
            for (ck, mq) in c.iter_mut().zip(mbasis) {
                *ck = hht::fast::dot(mq, w);
            }
            for (ck, q) in c.iter().zip(basis) {
                for (wi, qi) in w.iter_mut().zip(q) {
                    *wi = arith.mul_add(-ck, *qi, *wi);
                }
            }
        }
    }
}

/// The tridiagonal's eigen decomposition: ascending theta and the eigenvectors.
fn tridiagonal(alpha: &[f64], beta: &[f64]) -> Result<(Vec<f64>, Mat<f64>), BeamError> {
    let m = alpha.len();
    let mut t = Mat::<f64>::zeros(m, m);
    for i in 0..m {
        t[(i, i)] = alpha[i];
        if i + 1 < m {
            t[(i, i + 1)] = beta[i];
            t[(i + 1, i)] = beta[i];
        }
    }
    let e = t.self_adjoint_eigen(Side::Lower).map_err(|e| BeamError::Eigen(format!("{e:?}")))?;
    let theta = (0..m).map(|i| e.S().column_vector()[i]).collect();
    Ok((theta, e.U().to_owned()))
}

/// Whether the Ritz value `theta` of shift `sigma` is an eigenvalue in `(lower, upper]`.
fn in_slice(theta: f64, (sigma, lower, upper): (f64, f64, f64)) -> bool {
    let lambda = sigma + 1.0 / theta;
    theta != 0.0 && lambda > lower && lambda <= upper
}

/// The slice's modes, ascending, if `wanted` of them have converged, else how many have.
fn ritz(
    basis: &[Vec<f64>],
    alpha: &[f64],
    beta: &[f64],
    last: f64,
    slice: (f64, f64, f64),
    wanted: usize,
) -> Result<Result<Vec<Mode>, usize>, BeamError> {
    let (theta, s) = tridiagonal(alpha, beta)?;
    let m = alpha.len();
    let sigma = slice.0;
    let mut below: Vec<usize> = (0..m).filter(|&i| in_slice(theta[i], slice)).collect();
    below.sort_by(|&i, &j| (sigma + 1.0 / theta[i]).total_cmp(&(sigma + 1.0 / theta[j])));
    let converged =
        below.iter().filter(|&&i| last * s[(m - 1, i)].abs() <= CONVERGED * theta[i].abs()).count();
    if converged < wanted || below.len() > converged {
        return Ok(Err(converged));
    }
    let n = basis[0].len();
    // More than the count only by a Ritz value at the cutoff within rounding: the lowest.
    Ok(Ok(below
        .into_iter()
        .take(wanted)
        .map(|i| {
            let lambda = sigma + 1.0 / theta[i];
            let mut shape = Col::<f64>::zeros(n);
            for (k, qk) in basis.iter().enumerate() {
                let c = s[(k, i)];
                for (v, q) in shape.iter_mut().zip(qk) {
                    *v += c * q;
                }
            }
            Mode { omega: lambda.max(0.0).sqrt(), shape }
        })
        .collect()))
}
