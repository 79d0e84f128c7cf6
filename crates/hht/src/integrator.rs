//! Caller-driven stepping with Newton's method.

use crate::banded::{Band, BandedLu};
use crate::error::HhtError;
use crate::fast::{whole, Kernel, Lanes, MulAdd};
use crate::linear::SparseLu;
use crate::model::{Model, NewtonWeights, Triplets};
use crate::scheme::Scheme;
use faer::{Col, ColMut, ColRef};
use pulp::{Scalar, Simd};

/// Newton's iteration settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonOptions {
    /// Iterations before a step attempt is declared diverged.
    pub max_iterations: usize,
    /// Relative residual tolerance: the residual norm must fall below `rtol` times the size of
    /// the force terms in the balance (inertial, net, old-time), plus the round-off floor
    /// [`ROUND_OFF_FACTOR`] x eps x [`Model::force_scale`].
    pub rtol: f64,
    /// Absolute residual tolerance (model units), added to the relative one.
    pub atol: f64,
    /// How many times a failed step may be halved (each half stepped separately) before
    /// [`HhtError::NewtonDiverged`] is returned.
    pub max_halvings: usize,
    /// Keep the last factorised Newton matrix while it still converges (modified Newton):
    /// a step whose weights (its h) equal those of the last factorisation starts with it, and
    /// the matrix is rebuilt at the current iterate only when an iteration fails to reduce the
    /// residual by [`STALE_CONTRACTION`]. Each step still converges to `rtol`; what changes is
    /// the cost: a residual and a back-substitution instead of an assembly and a
    /// factorisation, for a model whose tangent changes little from step to step (a beam in
    /// small rotations). Default false: a fresh matrix every iteration.
    pub reuse_factorisation: bool,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self {
            max_iterations: 20,
            rtol: 1e-10,
            atol: 0.0,
            max_halvings: 8,
            reuse_factorisation: false,
        }
    }
}

/// A reused (stale) Newton matrix is rebuilt when an iteration with it leaves more than this
/// fraction of the residual: modified Newton converges linearly at the rate of the matrix's
/// error, and a rebuild (one assembly and factorisation) costs several residuals and
/// back-substitutions.
pub const STALE_CONTRACTION: f64 = 0.25;

/// The state at one time: configuration, velocity, acceleration, and the force terms of the
/// balance at that time (the next step weights them with `alpha_m` and `alpha_f`).
#[derive(Debug, Clone)]
pub struct State<C> {
    /// Time (s).
    pub t: f64,
    /// Configuration.
    pub q: C,
    /// Velocity (tangent space of `q`).
    pub v: Col<f64>,
    /// Acceleration (tangent space of `q`).
    pub a: Col<f64>,
    inertial: Col<f64>,
    net: Col<f64>,
    /// The larger of `|inertial|` and `|net|`: the round-off scale of the next step's balance.
    force_norm: f64,
}

impl<C> State<C> {
    /// A state with a given acceleration `a` (not solved from the balance): for studies of the
    /// scheme itself (amplification matrices) and for restarting from saved states.
    ///
    /// # Errors
    /// [`HhtError::Model`] if `v` or `a` has the wrong length.
    pub fn new<M: Model<Config = C>>(
        model: &M,
        t: f64,
        q: C,
        v: Col<f64>,
        a: Col<f64>,
    ) -> Result<Self, HhtError> {
        let n = model.ndof();
        if v.nrows() != n || a.nrows() != n {
            return Err(HhtError::Model(format!(
                "velocity and acceleration need {n} entries, got {} and {}",
                v.nrows(),
                a.nrows()
            )));
        }
        let mut inertial = Col::<f64>::zeros(n);
        let mut net = Col::<f64>::zeros(n);
        model.inertial_force(&q, v.as_ref(), a.as_ref(), inertial.as_mut());
        model.net_force(t, &q, v.as_ref(), net.as_mut());
        let force_norm = force_norm(&inertial, &net);
        Ok(Self { t, q, v, a, inertial, net, force_norm })
    }
}

/// What one call of [`Integrator::step`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepReport {
    /// Newton iterations, summed over substeps.
    pub iterations: usize,
    /// Residual norm at convergence (largest over substeps).
    pub residual_norm: f64,
    /// Local error estimate of the displacement, `h^2 |beta - 1/6| ||a_{n+1} - a_n||`
    /// (Zienkiewicz & Xie 1991), same units as the configuration increment. Largest over
    /// substeps. A caller can grow or shrink `h` to keep it near a target.
    pub error_estimate: f64,
    /// Substeps taken: 1 unless Newton failed and the step was halved.
    pub substeps: usize,
    /// Energy the scheme removed over the step (J in SI models), summed over substeps:
    ///
    /// `D = -dq . (M a_gamma + (g_n + g_{n+1}) / 2) + (beta - gamma / 2) h^2 (a_{n+1} - a_n) . M a_gamma`
    ///
    /// with `M a_gamma = (1 - gamma) I_n + gamma I_{n+1}`. Newmark's kinematics give the change
    /// of kinetic energy exactly as `(dq - (beta - gamma/2) h^2 da) . M a_gamma`, so `D` is
    /// minus that change minus the trapezoidal work of the net force: the energy a step loses
    /// beyond the forces' work (Krenk 2006, the Newmark energy balance). It is zero for the
    /// trapezoidal rule (alpha = 0) and positive over many steps for HHT's damping of high
    /// frequencies (a single step may be negative: HHT decreases a weighted energy). Exact
    /// for a constant mass matrix (`I = M a`) and a linear net force; for a nonlinear force the
    /// trapezoidal rule's error over the step is what remains in a caller's energy balance.
    pub dissipation: f64,
}

/// A reusable factorisation set aside for a step of another size: its weights (`None` once it
/// no longer serves) and the step attempt it was set aside at.
#[derive(Debug)]
struct Aside {
    weights: Option<NewtonWeights>,
    lu: LinearSolver,
    since: usize,
}

/// A factorisation set aside serves again only within this many step attempts (an event's
/// location re-steps a few times, 1-5 trials, and comes back to the step it left), and only
/// if the last step made with it converged in one iteration: a matrix that needed more was
/// already losing touch with the model's state. (A heavy ball riding the beam, its contact
/// steps changing size every few steps at 3 iterations a step: recalling those matrices saved
/// 23 factorisations in its first 20 ms and cost 854 more iterations, each some twentieth of
/// a factorisation.)
const ASIDE_ATTEMPTS: usize = 8;

/// The factorisation a model's Newton matrix gets: general sparse, or banded with a border
/// when the model declares it ([`Model::band`]).
#[derive(Debug)]
enum LinearSolver {
    Sparse(Box<SparseLu>),
    Banded(Box<BandedLu>),
}

impl LinearSolver {
    fn factor(
        &mut self,
        n: usize,
        band: Option<Band>,
        a: &Triplets,
        t: f64,
    ) -> Result<(), HhtError> {
        match (band, &mut *self) {
            (Some(band), LinearSolver::Banded(lu)) => lu.factor(n, band, a, t),
            (None, LinearSolver::Sparse(lu)) => lu.factor(n, a, t),
            (Some(band), LinearSolver::Sparse(_)) => {
                let mut lu = Box::<BandedLu>::default();
                let factored = lu.factor(n, band, a, t);
                *self = LinearSolver::Banded(lu);
                factored
            }
            (None, LinearSolver::Banded(_)) => {
                let mut lu = Box::<SparseLu>::default();
                let factored = lu.factor(n, a, t);
                *self = LinearSolver::Sparse(lu);
                factored
            }
        }
    }

    fn solve_in_place(&mut self, rhs: faer::ColMut<'_, f64>, t: f64) -> Result<(), HhtError> {
        match self {
            LinearSolver::Sparse(lu) => lu.solve_in_place(rhs, t),
            LinearSolver::Banded(lu) => lu.solve_in_place(rhs, t),
        }
    }
}

/// HHT-alpha / generalized-alpha integrator. It owns the Newton work space and the
/// factorisation (a sparse LU whose symbolic analysis is reused across steps, or a banded LU);
/// the caller owns the [`State`].
#[derive(Debug)]
pub struct Integrator {
    scheme: Scheme,
    /// Whether a step checks the scheme against the family's stable region (only
    /// [`crate::amplification`] steps one outside it: that is how such a scheme is studied).
    pub(crate) check_scheme: bool,
    options: NewtonOptions,
    lu: LinearSolver,
    triplets: Triplets,
    /// The fast part of the Newton matrix being built (see [`Model::tangent_parts`]).
    fast: Triplets,
    /// The weights of the last Newton matrix built in full (with reuse), whose slow part is
    /// `triplets[..base_len]`: a matrix for another step size is that part re-weighted plus
    /// a fresh fast part (see [`Integrator::newton_matrix`]).
    base: Option<NewtonWeights>,
    base_len: usize,
    /// The weights of the Newton matrix now factorised, if it may be reused.
    factored: Option<NewtonWeights>,
    /// The reusable factorisation before the current one, for other weights: a step of
    /// another size (an event's re-steps) and back then costs no factorisation on the way
    /// back (one is some ten steps' work).
    aside: Option<Aside>,
    /// Step attempts so far (the age of a factorisation set aside).
    attempts: usize,
    /// Newton iterations of the last step that converged.
    last_iterations: usize,
    /// Set while a step that failed with a kept matrix is retried with full Newton.
    full_newton: bool,
    /// Newton matrices factorised so far.
    pub factorisations: usize,
    work: Work,
}

/// The residual norm cannot fall below about this many ulps of the model's force scale (the
/// sum of a few large internal force terms that cancel) times the square root of the number of
/// unknowns (independent round-off per equation); see [`Model::force_scale`].
pub const ROUND_OFF_FACTOR: f64 = 64.0;

/// The entries of a column the integrator owns (an owned column is contiguous).
fn entries(x: &Col<f64>) -> &[f64] {
    match x.as_ref().try_as_col_major() {
        Some(x) => x.as_slice(),
        None => unreachable!("an owned column is contiguous"),
    }
}

fn entries_mut(x: &mut Col<f64>) -> &mut [f64] {
    match x.as_mut().try_as_col_major_mut() {
        Some(x) => x.as_slice_mut(),
        None => unreachable!("an owned column is contiguous"),
    }
}

/// Euclidean norm (four partial sums, see [`crate::fast::dot`]).
#[inline(always)]
fn norm_of(x: &[f64]) -> f64 {
    crate::fast::dot(x, x).sqrt()
}

/// The larger of `|inertial|` and `|net|`: a state's round-off scale.
fn force_norm(inertial: &Col<f64>, net: &Col<f64>) -> f64 {
    norm_of(entries(inertial)).max(norm_of(entries(net)))
}

/// The vectors a step works in, kept between steps.
#[derive(Debug, Default)]
struct Work {
    base: Vec<f64>,
    old_terms: Vec<f64>,
    delta: Vec<f64>,
    residual: Vec<f64>,
    /// Columns of states handed back ([`Integrator::recycle`]), for the next states.
    spare: Vec<Col<f64>>,
    /// The configuration of the last state handed back, for the next step's: an
    /// `Option<Config>` of any model's configuration type (checked when taken), boxed once and
    /// refilled, so that a step allocates nothing.
    spare_config: Option<Box<dyn std::any::Any>>,
}

/// At most this many columns are kept for reuse: the four of a state, twice (a caller may
/// hold a trial and the state it came from).
const SPARE_COLUMNS: usize = 8;

/// Whether a Newton correction of the acceleration of norm `correction` is below the round-off
/// of what it corrects: the accelerations `(a1, a0)`, or, times `beta_h2` = beta h^2, the
/// step's increments `(delta, base)` and the `configuration`'s own round-off scale.
fn round_off(
    correction: f64,
    (a1, a0): (&[f64], &[f64]),
    (delta, base): (&[f64], &[f64]),
    beta_h2: f64,
    configuration: f64,
) -> bool {
    let increments = norm_of(delta).max(norm_of(base));
    correction <= 1e-14 * norm_of(a1).max(norm_of(a0))
        || beta_h2 * correction <= 1e-14 * increments.max(configuration)
}

impl Work {
    /// A column of `n` entries whose values are not specified (every one is written before
    /// it is read): a spare one if there is, otherwise a new one.
    fn column(&mut self, n: usize) -> Col<f64> {
        while let Some(c) = self.spare.pop() {
            if c.nrows() == n {
                return c;
            }
        }
        Col::zeros(n)
    }
}

/// The step's predicted increment `h v_n + h^2 a_n / 2` (also the predictor's increment: its
/// acceleration is `a_n`), the predictor's velocity (Newmark's for `a_{n+1} = a_n`, as
/// [`Correct`] would write it) and the old-time force terms. The predictor's acceleration,
/// increment and (for a constant mass) inertial force are read where they are, `a_n`, this
/// increment and the old state's, not copied: each sweep of a step streams its vectors from
/// the second-level cache (a beam of 256 elements: 771 entries, 6 KB a vector), and its time
/// is the bytes it moves.
struct Predict<'a> {
    s: Scheme,
    h: f64,
    v0: &'a [f64],
    a0: &'a [f64],
    inertial0: &'a [f64],
    net0: &'a [f64],
    v1: &'a mut [f64],
    work: &'a mut Work,
}

impl Lanes for Predict<'_> {
    type Output = ();

    #[inline(always)]
    fn run<S: Simd>(self, simd: S) {
        let (h, s, work) = (self.h, self.s, self.work);
        let m = whole::<S>(work.base.len());
        let (base, old) = (work.base.split_at_mut(m), work.old_terms.split_at_mut(m));
        let v1 = self.v1.split_at_mut(m);
        let (v, a) = (self.v0.split_at(m), self.a0.split_at(m));
        let (i, g) = (self.inertial0.split_at(m), self.net0.split_at(m));
        predict(simd, h, s, [base.0, v1.0, old.0], (v.0, a.0, i.0, g.0));
        predict(Scalar::new(), h, s, [base.1, v1.1, old.1], (v.1, a.1, i.1, g.1));
    }
}

#[inline(always)]
fn predict<S: Simd>(
    simd: S,
    h: f64,
    s: Scheme,
    [base, v1, old]: [&mut [f64]; 3],
    (v, a, i, g): (&[f64], &[f64], &[f64], &[f64]),
) {
    let (hv, ha) = (simd.splat_f64s(h), simd.splat_f64s(0.5 * h * h));
    let (v_old, v_new) = (simd.splat_f64s(h * (1.0 - s.gamma)), simd.splat_f64s(h * s.gamma));
    let (am, af) = (simd.splat_f64s(s.alpha_m), simd.splat_f64s(s.alpha_f));
    let (base, v1, old) =
        (S::as_mut_simd_f64s(base).0, S::as_mut_simd_f64s(v1).0, S::as_mut_simd_f64s(old).0);
    let (v, a) = (S::as_simd_f64s(v).0, S::as_simd_f64s(a).0);
    let (i, g) = (S::as_simd_f64s(i).0, S::as_simd_f64s(g).0);
    for ((base, v1), (v, a)) in base.iter_mut().zip(v1.iter_mut()).zip(v.iter().zip(a)) {
        *base = simd.mul_add_e_f64s(ha, *a, simd.mul_f64s(hv, *v));
        *v1 = simd.mul_add_e_f64s(v_new, *a, simd.mul_add_e_f64s(v_old, *a, *v));
    }
    for (old, (i, g)) in old.iter_mut().zip(i.iter().zip(g)) {
        *old = simd.mul_add_e_f64s(af, *g, simd.mul_f64s(am, *i));
    }
}

/// A Newton correction and Newmark's kinematics in one sweep: the new iterate
/// `a1 = a + scaling r` (`a` the last iterate: `a0` at the predictor, else `a1` itself), its
/// increment `delta = base + beta h^2 (a1 - a0)` and velocity
/// `v1 = v0 + h (1 - gamma) a0 + h gamma a1`.
struct Correct<'a> {
    s: Scheme,
    h: f64,
    scaling: f64,
    /// Whether the last iterate is the predictor's (`a0`), not `a1`.
    from_predictor: bool,
    v0: &'a [f64],
    a0: &'a [f64],
    a1: &'a mut [f64],
    v1: &'a mut [f64],
    work: &'a mut Work,
}

impl Lanes for Correct<'_> {
    type Output = ();

    #[inline(always)]
    fn run<S: Simd>(self, simd: S) {
        let (s, h, scaling, work) = (self.s, self.h, self.scaling, self.work);
        let m = whole::<S>(work.delta.len());
        let (delta, base) = (work.delta.split_at_mut(m), work.base.split_at(m));
        let r = work.residual.split_at(m);
        let (v0, a0) = (self.v0.split_at(m), self.a0.split_at(m));
        let (a1, v1) = (self.a1.split_at_mut(m), self.v1.split_at_mut(m));
        let from = self.from_predictor;
        let weights = (s, h, scaling);
        correct(simd, weights, from, (a1.0, delta.0, v1.0), (r.0, base.0, v0.0, a0.0));
        correct(Scalar::new(), weights, from, (a1.1, delta.1, v1.1), (r.1, base.1, v0.1, a0.1));
    }
}

#[inline(always)]
fn correct<S: Simd>(
    simd: S,
    (s, h, scaling): (Scheme, f64, f64),
    from_predictor: bool,
    (a1, delta, v1): (&mut [f64], &mut [f64], &mut [f64]),
    (r, base, v0, a0): (&[f64], &[f64], &[f64], &[f64]),
) {
    let da = simd.splat_f64s(s.beta * h * h);
    let (v_old, v_new) = (simd.splat_f64s(h * (1.0 - s.gamma)), simd.splat_f64s(h * s.gamma));
    let scaling = simd.splat_f64s(scaling);
    let (a1, delta, v1) =
        (S::as_mut_simd_f64s(a1).0, S::as_mut_simd_f64s(delta).0, S::as_mut_simd_f64s(v1).0);
    let (r, base) = (S::as_simd_f64s(r).0, S::as_simd_f64s(base).0);
    let (v0, a0) = (S::as_simd_f64s(v0).0, S::as_simd_f64s(a0).0);
    let rows = a1.iter_mut().zip(delta.iter_mut().zip(v1));
    for ((a1, (delta, v1)), ((r, base), (v0, a0))) in
        rows.zip(r.iter().zip(base).zip(v0.iter().zip(a0)))
    {
        let last = if from_predictor { *a0 } else { *a1 };
        let a = simd.add_f64s(last, simd.mul_f64s(scaling, *r));
        *a1 = a;
        *delta = simd.mul_add_e_f64s(da, simd.sub_f64s(a, *a0), *base);
        *v1 = simd.mul_add_e_f64s(v_new, a, simd.mul_add_e_f64s(v_old, *a0, *v0));
    }
}

/// The residual `(1 - alpha_m) I + (1 - alpha_f) g + old terms` into the work space; returns
/// its norm and the larger of the force terms' norms, and, given the rest of a step's vectors
/// (`closing`, a corrected iterate, which is usually the step's last), its [`Closing`] sums
/// from the same sweep (the same operations on each entry: the same bits).
struct Balance<'a> {
    s: Scheme,
    inertial: &'a [f64],
    net: &'a [f64],
    work: &'a mut Work,
    closing: Option<ClosingOf<'a>>,
}

/// What [`Closing`] reads besides the iterate's forces: `h`, `[a0, a1, inertial0, net0]`.
struct ClosingOf<'a> {
    h: f64,
    old: [&'a [f64]; 4],
}

impl Lanes for Balance<'_> {
    type Output = (f64, f64, Option<(f64, f64)>);

    #[inline(always)]
    fn run<S: Simd>(self, simd: S) -> Self::Output {
        let s = self.s;
        let w = (1.0 - s.alpha_m, 1.0 - s.alpha_f);
        let work = self.work;
        let m = whole::<S>(work.residual.len());
        let (r, old) = (work.residual.split_at_mut(m), work.old_terms.split_at(m));
        let (i, g) = (self.inertial.split_at(m), self.net.split_at(m));
        let norm = |sums: [f64; 3], k: usize| sums[k].sqrt();
        let Some(ClosingOf { h, old: [a0, a1, i0, g0] }) = self.closing else {
            let none = (s, 0.0, [&[][..]; 5]);
            let head = balance::<S, false>(simd, w, r.0, (old.0, i.0, g.0), none);
            let tail = balance::<Scalar, false>(Scalar::new(), w, r.1, (old.1, i.1, g.1), none);
            let sums = [0, 1, 2].map(|k| head.0[k] + tail.0[k]);
            return (norm(sums, 0), norm(sums, 1).max(norm(sums, 2)), None);
        };
        let rest = [a0, a1, i0, g0, &work.delta[..]];
        let head =
            balance::<S, true>(simd, w, r.0, (old.0, i.0, g.0), (s, h, rest.map(|x| &x[..m])));
        let tail = balance::<Scalar, true>(
            Scalar::new(),
            w,
            r.1,
            (old.1, i.1, g.1),
            (s, h, rest.map(|x| &x[m..])),
        );
        let sums = [0, 1, 2].map(|k| head.0[k] + tail.0[k]);
        let closing = (head.1[0] + tail.1[0], (head.1[1] + tail.1[1]).sqrt());
        (norm(sums, 0), norm(sums, 1).max(norm(sums, 2)), Some(closing))
    }
}

/// The residual into `r`, and the sums of squares of it, `inertial` and `net`; with `CLOSE`,
/// the [`closing`] sums over `[a0, a1, inertial0, net0, delta]` too.
#[inline(always)]
fn balance<S: Simd, const CLOSE: bool>(
    simd: S,
    (wi, wn): (f64, f64),
    r: &mut [f64],
    (old, inertial, net): (&[f64], &[f64], &[f64]),
    (s, h, rest): (Scheme, f64, [&[f64]; 5]),
) -> ([f64; 3], [f64; 2]) {
    let (wi, wn) = (simd.splat_f64s(wi), simd.splat_f64s(wn));
    let r = S::as_mut_simd_f64s(r).0;
    let (old, i, g) = (S::as_simd_f64s(old).0, S::as_simd_f64s(inertial).0, S::as_simd_f64s(net).0);
    let [a0, a1, i0, g0, d] = rest.map(|x| S::as_simd_f64s(x).0);
    let zero = simd.splat_f64s(0.0);
    let (mut rr, mut ii, mut gg) = (zero, zero, zero);
    let mut sums = ClosingSums::new(simd, s, h);
    for (k, ((r, old), (i, g))) in r.iter_mut().zip(old).zip(i.iter().zip(g)).enumerate() {
        let x = simd.mul_add_e_f64s(wn, *g, simd.mul_add_e_f64s(wi, *i, *old));
        *r = x;
        rr = simd.mul_add_e_f64s(x, x, rr);
        ii = simd.mul_add_e_f64s(*i, *i, ii);
        gg = simd.mul_add_e_f64s(*g, *g, gg);
        if CLOSE {
            sums.add(simd, [a0[k], a1[k], i0[k], *i, g0[k], *g, d[k]]);
        }
    }
    let squares = [simd.reduce_sum_f64s(rr), simd.reduce_sum_f64s(ii), simd.reduce_sum_f64s(gg)];
    (squares, sums.total(simd))
}

/// `|x|`.
struct Norm<'a>(&'a [f64]);

impl Kernel for Norm<'_> {
    type Output = f64;

    #[inline(always)]
    fn run<A: MulAdd>(self, _: A) -> f64 {
        norm_of(self.0)
    }
}

/// The accepted step's numerical dissipation (see [`StepReport::dissipation`]) and
/// `|a_{n+1} - a_n|`.
struct Closing<'a> {
    s: Scheme,
    h: f64,
    a0: &'a [f64],
    a1: &'a [f64],
    inertial0: &'a [f64],
    inertial: &'a [f64],
    net0: &'a [f64],
    net: &'a [f64],
    delta: &'a [f64],
}

impl Lanes for Closing<'_> {
    type Output = (f64, f64);

    #[inline(always)]
    fn run<S: Simd>(self, simd: S) -> (f64, f64) {
        let m = whole::<S>(self.delta.len());
        let x = [self.a0, self.a1, self.inertial0, self.inertial, self.net0, self.net, self.delta];
        let (s, h) = (self.s, self.h);
        let head = closing(simd, s, h, x.map(|x| &x[..m]));
        let tail = closing(Scalar::new(), s, h, x.map(|x| &x[m..]));
        (head[0] + tail[0], (head[1] + tail[1]).sqrt())
    }
}

/// The dissipation and `|a_1 - a_0|^2` over `[a0, a1, inertial0, inertial, net0, net, delta]`:
/// with `m a = (1 - gamma) I_0 + gamma I_1` (the inertial force at the step's gamma point),
/// `(beta - gamma / 2) h^2 (a_1 - a_0) . m a - delta . (m a + (g_0 + g_1) / 2)` summed.
#[inline(always)]
fn closing<S: Simd>(simd: S, s: Scheme, h: f64, x: [&[f64]; 7]) -> [f64; 2] {
    let [a0, a1, i0, i1, g0, g1, d] = x.map(|x| S::as_simd_f64s(x).0);
    let mut sums = ClosingSums::new(simd, s, h);
    for k in 0..d.len() {
        sums.add(simd, [a0[k], a1[k], i0[k], i1[k], g0[k], g1[k], d[k]]);
    }
    sums.total(simd)
}

/// [`closing`]'s sums, a vector of entries at a time.
struct ClosingSums<S: Simd> {
    kinematic: S::f64s,
    old: S::f64s,
    new: S::f64s,
    half: S::f64s,
    dissipation: S::f64s,
    jump_sq: S::f64s,
}

impl<S: Simd> ClosingSums<S> {
    #[inline(always)]
    fn new(simd: S, s: Scheme, h: f64) -> Self {
        let zero = simd.splat_f64s(0.0);
        Self {
            kinematic: simd.splat_f64s((s.beta - 0.5 * s.gamma) * h * h),
            old: simd.splat_f64s(1.0 - s.gamma),
            new: simd.splat_f64s(s.gamma),
            half: simd.splat_f64s(0.5),
            dissipation: zero,
            jump_sq: zero,
        }
    }

    /// Adds the entries `[a0, a1, inertial0, inertial, net0, net, delta]`.
    #[inline(always)]
    fn add(&mut self, simd: S, [a0, a1, i0, i1, g0, g1, d]: [S::f64s; 7]) {
        let m_a = simd.mul_add_e_f64s(self.new, i1, simd.mul_f64s(self.old, i0));
        let jump = simd.sub_f64s(a1, a0);
        self.jump_sq = simd.mul_add_e_f64s(jump, jump, self.jump_sq);
        let work = simd.mul_add_e_f64s(self.half, simd.add_f64s(g0, g1), m_a);
        let kinetic = simd.mul_f64s(self.kinematic, simd.mul_f64s(jump, m_a));
        self.dissipation =
            simd.add_f64s(self.dissipation, simd.sub_f64s(kinetic, simd.mul_f64s(d, work)));
    }

    /// The dissipation and `|a_1 - a_0|^2`.
    #[inline(always)]
    fn total(&self, simd: S) -> [f64; 2] {
        [simd.reduce_sum_f64s(self.dissipation), simd.reduce_sum_f64s(self.jump_sq)]
    }
}

impl Integrator {
    /// An integrator for `scheme` (see [`Scheme::hht`], [`Scheme::generalized_alpha`]).
    pub fn new(scheme: Scheme, options: NewtonOptions) -> Self {
        Self {
            scheme,
            check_scheme: true,
            options,
            lu: LinearSolver::Sparse(Box::default()),
            triplets: Triplets::new(),
            fast: Triplets::new(),
            base: None,
            base_len: 0,
            factored: None,
            aside: None,
            attempts: 0,
            last_iterations: 0,
            full_newton: false,
            factorisations: 0,
            work: Work::default(),
        }
    }

    /// The scheme in use.
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }

    /// Symbolic factorisations done so far (one each time the pattern of the matrices changes:
    /// 1 for a model that pushes one pattern, more where a mass matrix or a re-weighted Newton
    /// matrix pushes another; 0 for a banded model, which needs none).
    pub fn symbolic_factorisations(&self) -> usize {
        match &self.lu {
            LinearSolver::Sparse(lu) => lu.symbolic_count,
            LinearSolver::Banded(_) => 0,
        }
    }

    /// The state at time `t` with configuration `q` and velocity `v`; the acceleration solves
    /// `M a = -(I(q, v, 0) + g(t, q, v))` so the balance holds at the start.
    ///
    /// # Errors
    /// [`HhtError::Model`] if `v` has the wrong length, [`HhtError::Singular`] if the mass
    /// matrix cannot be factorised.
    pub fn initial_state<M: Model>(
        &mut self,
        model: &M,
        t: f64,
        q: M::Config,
        v: Col<f64>,
    ) -> Result<State<M::Config>, HhtError> {
        self.check_settings()?;
        let n = model.ndof();
        if v.nrows() != n {
            return Err(HhtError::Model(format!(
                "velocity has {} entries, the model {n}",
                v.nrows()
            )));
        }
        let zero = Col::<f64>::zeros(n);
        let mut inertial = Col::<f64>::zeros(n);
        let mut net = Col::<f64>::zeros(n);
        model.inertial_force(&q, v.as_ref(), zero.as_ref(), inertial.as_mut());
        model.net_force(t, &q, v.as_ref(), net.as_mut());
        let rhs = -(&inertial + &net);
        let a = if n == 0 {
            zero
        } else {
            self.triplets.clear();
            self.base = None;
            model.tangent(
                t,
                &q,
                v.as_ref(),
                zero.as_ref(),
                NewtonWeights::mass(),
                &mut self.triplets,
            );
            self.lu.factor(n, model.band(), &self.triplets, t)?;
            self.factored = None;
            let mut a = rhs;
            self.lu.solve_in_place(a.as_mut(), t)?;
            a
        };
        model.inertial_force(&q, v.as_ref(), a.as_ref(), inertial.as_mut());
        let force_norm = force_norm(&inertial, &net);
        Ok(State { t, q, v, a, inertial, net, force_norm })
    }

    /// Advances `state` by `h` (s). On a Newton failure the step is split in two halves,
    /// recursively up to [`NewtonOptions::max_halvings`] times; `state` is changed only on success.
    ///
    /// # Errors
    /// [`HhtError::InvalidParameter`] for a step that is not finite and positive;
    /// [`HhtError::NewtonDiverged`] when even the smallest substep fails;
    /// [`HhtError::Singular`] from the linear solver.
    pub fn step<M: Model>(
        &mut self,
        model: &M,
        state: &mut State<M::Config>,
        h: f64,
    ) -> Result<StepReport, HhtError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(HhtError::InvalidParameter {
                name: "time step",
                value: h,
                allowed: "a finite time step greater than zero (s)",
            });
        }
        self.check_settings()?;
        self.step_split(model, state, h, 0)
    }

    /// The scheme and the Newton options as the constructors allow them: their fields are
    /// public, and a struct literal could hold an unstable scheme or a tolerance that is not a
    /// number (a review's ran to 1.2e18 without a word).
    fn check_settings(&self) -> Result<(), HhtError> {
        if self.check_scheme {
            self.scheme.checked()?;
        }
        let o = &self.options;
        let bad =
            |name, value: f64, allowed| Err(HhtError::InvalidParameter { name, value, allowed });
        if o.max_iterations == 0 {
            return bad("max_iterations", 0.0, "at least one Newton iteration");
        }
        if !(o.rtol.is_finite() && o.rtol >= 0.0) {
            return bad("rtol", o.rtol, "a finite relative tolerance >= 0");
        }
        if !(o.atol.is_finite() && o.atol >= 0.0) {
            return bad("atol", o.atol, "a finite absolute tolerance >= 0");
        }
        Ok(())
    }

    /// Hands back a state no longer needed, so that the next steps reuse its columns and its
    /// configuration instead of allocating (a state of a beam of 256 elements is four columns
    /// of 771 entries, and a step costs some 15 us).
    pub fn recycle<C: 'static>(&mut self, state: State<C>) {
        match self.work.spare_config.as_mut().and_then(|c| c.downcast_mut::<Option<C>>()) {
            Some(slot) => *slot = Some(state.q),
            None => self.work.spare_config = Some(Box::new(Some(state.q))),
        }
        let spare = &mut self.work.spare;
        for c in [state.v, state.a, state.inertial, state.net] {
            if spare.len() < SPARE_COLUMNS {
                spare.push(c);
            }
        }
    }

    /// The state `h` (s) after `from`, leaving `from` as it is: [`Integrator::step`] for a
    /// caller that keeps the old state (to try a step and perhaps take another), without
    /// copying it first. On a Newton failure the step is split as `step` does.
    ///
    /// # Errors
    /// As [`Integrator::step`].
    pub fn advance<M: Model>(
        &mut self,
        model: &M,
        from: &State<M::Config>,
        h: f64,
    ) -> Result<(State<M::Config>, StepReport), HhtError> {
        self.check_settings()?;
        if !(h.is_finite() && h > 0.0) {
            return Err(HhtError::InvalidParameter {
                name: "time step",
                value: h,
                allowed: "a finite time step greater than zero (s)",
            });
        }
        // The usual case, one Newton solve, needs no copy of `from`; a failure takes the
        // general path (fresh matrix, halving) on a copy.
        match self.attempt(model, from, h) {
            Ok(done) => Ok(done),
            Err(failure) => {
                let mut state = from.clone();
                let report = self.recover(model, &mut state, h, 0, failure)?;
                Ok((state, report))
            }
        }
    }

    fn step_split<M: Model>(
        &mut self,
        model: &M,
        state: &mut State<M::Config>,
        h: f64,
        depth: usize,
    ) -> Result<StepReport, HhtError> {
        match self.attempt(model, state, h) {
            Ok((next, report)) => {
                let old = std::mem::replace(state, next);
                self.recycle(old);
                Ok(report)
            }
            Err(failure) => self.recover(model, state, h, depth, failure),
        }
    }

    /// After the attempt of a step from `state` failed with `failure`: again with a fresh
    /// matrix, then in halves.
    fn recover<M: Model>(
        &mut self,
        model: &M,
        state: &mut State<M::Config>,
        h: f64,
        depth: usize,
        failure: HhtError,
    ) -> Result<StepReport, HhtError> {
        match failure {
            // A kept matrix can lead Newton astray where the tangent changed fast (a contact
            // closing): the step is tried again with a fresh matrix every iteration, and so
            // are its halves if it still fails.
            HhtError::NewtonDiverged { .. } | HhtError::Singular { .. }
                if self.options.reuse_factorisation && !self.full_newton =>
            {
                self.full_newton = true;
                let result = self.step_split(model, state, h, depth);
                self.full_newton = false;
                result
            }
            e @ (HhtError::NewtonDiverged { .. } | HhtError::Singular { .. })
                if depth < self.options.max_halvings =>
            {
                let mut trial = state.clone();
                let first = self.step_split(model, &mut trial, 0.5 * h, depth + 1);
                let second = first.and_then(|r1| {
                    self.step_split(model, &mut trial, 0.5 * h, depth + 1).map(|r2| (r1, r2))
                });
                match second {
                    Ok((r1, r2)) => {
                        *state = trial;
                        Ok(StepReport {
                            iterations: r1.iterations + r2.iterations,
                            residual_norm: r1.residual_norm.max(r2.residual_norm),
                            error_estimate: r1.error_estimate.max(r2.error_estimate),
                            substeps: r1.substeps + r2.substeps,
                            dissipation: r1.dissipation + r2.dissipation,
                        })
                    }
                    Err(_) => Err(e),
                }
            }
            e => Err(e),
        }
    }

    /// Brings back the factorisation set aside for weights `w`, if there is one and it is
    /// recent (see [`ASIDE_ATTEMPTS`]), setting the current one aside in its place.
    fn recall(&mut self, w: NewtonWeights) {
        let now = self.attempts;
        let Some(aside) = self.aside.as_mut().filter(|a| a.weights == Some(w)) else { return };
        if now - aside.since > ASIDE_ATTEMPTS {
            return;
        }
        std::mem::swap(&mut self.lu, &mut aside.lu);
        let current = self.factored.replace(w);
        aside.weights = current.filter(|_| self.last_iterations <= 1);
        aside.since = now;
    }

    /// Sets the current (reusable) factorisation aside before a new one is made; the new one
    /// reuses the storage of the one set aside before.
    fn keep_aside(&mut self) {
        let Some(current) = self.factored.take() else { return };
        let storage = match self.aside.take() {
            Some(aside) => aside.lu,
            None => LinearSolver::Sparse(Box::default()),
        };
        let lu = std::mem::replace(&mut self.lu, storage);
        let weights = (self.last_iterations <= 1).then_some(current);
        self.aside = Some(Aside { weights, lu, since: self.attempts });
    }

    /// The Newton matrix for the weights `w` at the iterate `(t1, q1, v1, a1)`, factored: full
    /// Newton (no reuse) rebuilds it every iteration; with reuse, only for new weights (after
    /// bringing back one set aside for them) or when the kept one is `stale` (it stopped
    /// contracting the residual).
    fn newton_matrix<M: Model>(
        &mut self,
        model: &M,
        (t1, q1, v1, a1): (f64, &M::Config, ColRef<'_, f64>, ColRef<'_, f64>),
        w: NewtonWeights,
        (reuse, stale): (bool, bool),
    ) -> Result<(), HhtError> {
        if reuse && self.factored != Some(w) {
            self.recall(w);
        }
        if reuse && self.factored == Some(w) && !stale {
            return Ok(());
        }
        // A kept matrix's weights differ from w in the step size alone (da and dv; inertia,
        // force and dq are the scheme's), and the Newton matrix is linear in da, dv and dq
        // (see `Model::tangent`): the slow part of the last matrix built in full, plus the
        // slow part's terms in the differences of da and dv (its mass, gyroscopic and damping
        // terms, without the stiffness: dq = 0), is that part for w, its stiffness taken at the
        // state where it was built, as a kept matrix's is; the fast part (a contact) is the
        // iterate's. An event's one-off step then needs no element stiffness (on the paper's
        // tip in 3D at 256 elements, 1.4 ms a matrix, 17 times in 1 ms). A stale matrix is
        // built in full, at the iterate, and so is every matrix while the last step needed
        // more than one iteration: the kept stiffness is then too far from the state's (the
        // heavy ball's large swing took 23 % more iterations with it re-weighted).
        let base = self.base.filter(|b| {
            reuse
                && !stale
                && self.last_iterations <= 1
                && (b.inertia, b.force, b.dq) == (w.inertia, w.force, w.dq)
        });
        self.fast.clear();
        if let Some(b) = base {
            self.triplets.truncate(self.base_len);
            if b != w {
                let delta = NewtonWeights { da: w.da - b.da, dv: w.dv - b.dv, dq: 0.0, ..w };
                model.tangent_parts(
                    t1,
                    q1,
                    v1,
                    a1,
                    delta,
                    Some(&mut self.triplets),
                    &mut self.fast,
                );
                self.fast.clear();
            }
            model.tangent_parts(t1, q1, v1, a1, w, None, &mut self.fast);
        } else {
            self.triplets.clear();
            model.tangent_parts(t1, q1, v1, a1, w, Some(&mut self.triplets), &mut self.fast);
            self.base = reuse.then_some(w);
            self.base_len = self.triplets.len();
        }
        self.triplets.append(&self.fast);
        if reuse && self.factored.is_some_and(|kept| kept != w) {
            self.keep_aside();
        }
        self.factored = None;
        self.lu.factor(model.ndof(), model.band(), &self.triplets, t1)?;
        self.factorisations += 1;
        self.factored = reuse.then_some(w);
        Ok(())
    }

    /// Whether the residual's `rows` are within `rtol` of their own force terms `forces`
    /// (inertial and net, new and old), plus those terms' round-off floor.
    fn own_rows_balanced(&self, rows: std::ops::Range<usize>, forces: [&[f64]; 4]) -> bool {
        let norm = |x: &[f64]| x.iter().map(|v| v * v).sum::<f64>().sqrt();
        let residual = norm(&self.work.residual[rows.clone()]);
        let scale = forces.iter().map(|f| norm(&f[rows.clone()])).fold(0.0, f64::max);
        let floor = ROUND_OFF_FACTOR * f64::EPSILON * scale * (rows.len() as f64).sqrt();
        residual <= self.options.atol + self.options.rtol * scale + floor
    }

    /// One Newton solve of the step equation; returns the new state without touching the old.
    fn attempt<M: Model>(
        &mut self,
        model: &M,
        old: &State<M::Config>,
        h: f64,
    ) -> Result<(State<M::Config>, StepReport), HhtError> {
        self.attempts += 1;
        let s = self.scheme;
        let n = model.ndof();
        let t1 = old.t + h;
        let w = NewtonWeights {
            inertia: 1.0 - s.alpha_m,
            force: 1.0 - s.alpha_f,
            da: 1.0 / (s.beta * h * h),
            dv: s.gamma / (s.beta * h),
            dq: 1.0,
        };
        let (v0, a0) = (entries(&old.v), entries(&old.a));
        let (inertial0, net0) = (entries(&old.inertial), entries(&old.net));
        // The step's work vectors, kept between steps (every entry is written before it is
        // read): the predicted increment h v + h^2 a / 2, the old-time force terms
        // alpha_m I_n + alpha_f g_n, the increment and the residual.
        // The iteration unknown is the new acceleration a_{n+1} (predictor: a_n). Iterating on
        // the configuration increment instead would compute a_{n+1} as a difference of
        // increments divided by beta h^2, a round-off floor of eps |dq| / (beta h^2) on the
        // inertial force that stalls Newton at small steps.
        let (mut v1, mut a1) = (self.work.column(n), self.work.column(n));
        let (mut inertial, mut net) = (self.work.column(n), self.work.column(n));
        let work = &mut self.work;
        for v in [&mut work.base, &mut work.old_terms, &mut work.delta, &mut work.residual] {
            v.resize(n, 0.0);
        }
        crate::fast::run_lanes(Predict {
            s,
            h,
            v0,
            a0,
            inertial0,
            net0,
            v1: entries_mut(&mut v1),
            work,
        });
        // Round-off floor of the balance: forces of the size of the old ones are recomputed at
        // q_n (+) delta, so their round-off is carried even when the balance itself is tiny.
        let old_scale = old.force_norm;
        let mut residual_norm = f64::INFINITY;
        let reuse = self.options.reuse_factorisation && !self.full_newton;
        let mut previous_residual = f64::INFINITY;
        let spare =
            self.work.spare_config.as_mut().and_then(|c| c.downcast_mut::<Option<M::Config>>());
        let mut q1 = spare.and_then(Option::take).unwrap_or_else(|| old.q.clone());
        let constant_mass = model.constant_mass();
        // Until the first correction the iterate is the predictor: its acceleration `a0`, its
        // increment `base` and, with a constant mass, its inertial force the old state's (M a_n,
        // to the last bit), read where they are; the correction writes `a1` and `delta`.
        let mut predicted = true;
        for iteration in 0..=self.options.max_iterations {
            let delta = if predicted { &self.work.base } else { &self.work.delta };
            model.displaced(&old.q, ColRef::from_slice(delta), &mut q1);
            let a_now = ColRef::from_slice(if predicted { a0 } else { entries(&a1) });
            let kept_inertial = predicted && constant_mass;
            if !kept_inertial {
                let out = inertial.as_mut();
                if predicted {
                    let old_inertial = ColRef::from_slice(inertial0);
                    model.predicted_inertial_force(&q1, v1.as_ref(), a_now, old_inertial, out);
                } else {
                    model.inertial_force(&q1, v1.as_ref(), a_now, out);
                }
            }
            model.net_force(t1, &q1, v1.as_ref(), net.as_mut());
            let inertial_now = if kept_inertial { inertial0 } else { entries(&inertial) };
            // A corrected iterate's closing sums from the balance's sweep (it is usually the
            // step's last): one sweep less over the forces when it is.
            let closing =
                (!predicted).then(|| ClosingOf { h, old: [a0, entries(&a1), inertial0, net0] });
            let (force_norm, closed);
            (residual_norm, force_norm, closed) = crate::fast::run_lanes(Balance {
                s,
                inertial: inertial_now,
                net: entries(&net),
                work: &mut self.work,
                closing,
            });
            let scale = force_norm.max(old_scale);
            if !residual_norm.is_finite() {
                break;
            }
            let floor =
                ROUND_OFF_FACTOR * f64::EPSILON * model.force_scale(&q1) * (n as f64).sqrt();
            let mut converged =
                residual_norm <= self.options.atol + self.options.rtol * scale + floor;
            // A predictor is accepted as it is only where the model's own rows balance too;
            // once corrected, the whole balance decides (see `Model::own_balance_rows`).
            let own = model.own_balance_rows();
            if converged && predicted && !own.is_empty() {
                let forces = [inertial_now, entries(&net), inertial0, net0];
                converged = self.own_rows_balanced(own, forces);
            }
            if !converged && iteration < self.options.max_iterations {
                let stale = residual_norm > STALE_CONTRACTION * previous_residual;
                self.newton_matrix(model, (t1, &q1, v1.as_ref(), a_now), w, (reuse, stale))?;
                previous_residual = residual_norm;
                // The Newton matrix solves for the configuration's correction times
                // -beta h^2; the acceleration's is that solution scaled back.
                let r = &mut self.work.residual;
                self.lu.solve_in_place(ColMut::from_slice_mut(r), t1)?;
                let scaling = -1.0 / (s.beta * h * h);
                // A correction below the round-off of the quantities it corrects cannot improve
                // the iterate: the balance is then at its floating-point floor (for example a
                // tiny displacement computed as the difference of two O(1) increments), so accept.
                // The configuration's own round-off is ~eps |q| per coordinate (sqrt(n) in norm).
                // (Not at the predictor: its correction is the step's own.)
                converged = iteration > 0 && {
                    let correction = scaling.abs() * crate::fast::run(Norm(r));
                    let configuration = model.configuration_scale(&q1) * (n as f64).sqrt();
                    let increments = (&self.work.delta[..], &self.work.base[..]);
                    round_off(
                        correction,
                        (entries(&a1), a0),
                        increments,
                        s.beta * h * h,
                        configuration,
                    )
                };
                if !converged {
                    crate::fast::run_lanes(Correct {
                        s,
                        h,
                        scaling,
                        from_predictor: predicted,
                        v0,
                        a0,
                        a1: entries_mut(&mut a1),
                        v1: entries_mut(&mut v1),
                        work: &mut self.work,
                    });
                    predicted = false;
                    continue;
                }
            }
            if !converged {
                break;
            }
            // The predictor accepted as it is: its acceleration (and kept inertial force) into
            // the new state's columns.
            if predicted {
                entries_mut(&mut a1).copy_from_slice(a0);
                self.work.delta.copy_from_slice(&self.work.base);
            }
            if kept_inertial {
                entries_mut(&mut inertial).copy_from_slice(inertial0);
            }
            let (dissipation, jump) = closed.unwrap_or_else(|| {
                crate::fast::run_lanes(Closing {
                    s,
                    h,
                    a0,
                    a1: entries(&a1),
                    inertial0,
                    inertial: entries(&inertial),
                    net0,
                    net: entries(&net),
                    delta: &self.work.delta,
                })
            });
            let error_estimate = h * h * (s.beta - 1.0 / 6.0).abs() * jump;
            let next = State { t: t1, q: q1, v: v1, a: a1, inertial, net, force_norm };
            self.last_iterations = iteration;
            let report = StepReport {
                iterations: iteration,
                residual_norm,
                error_estimate,
                substeps: 1,
                dissipation,
            };
            return Ok((next, report));
        }
        Err(HhtError::NewtonDiverged {
            t: t1,
            iterations: self.options.max_iterations,
            residual_norm,
        })
    }
}
