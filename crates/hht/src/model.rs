//! What a mechanical model supplies to the integrator.

use faer::{ColMut, ColRef};

/// Scalar weights of the Newton matrix. A model assembles
///
/// `J = inertia (da dI/da + dv dI/dv + dq dI/dq) + force (dv dg/dv + dq dg/dq)`
///
/// where `I(q, v, a)` is its inertial force, `g(t, q, v)` its net force, and `dq` differentiates
/// along the configuration update `q (+) dq` (so for rotations it is the derivative with respect
/// to the incremental rotation vector the model's [`Model::update`] uses).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonWeights {
    /// Weight of the inertial force's derivatives (`1 - alpha_m` in a step; 1 for a mass matrix).
    pub inertia: f64,
    /// Weight of the net force's derivatives (`1 - alpha_f` in a step; 1 in statics).
    pub force: f64,
    /// `d a / d q` along the iteration: `1 / (beta h^2)` (1/s^2).
    pub da: f64,
    /// `d v / d q` along the iteration: `gamma / (beta h)` (1/s).
    pub dv: f64,
    /// `d q / d q`: 1 in a step or in statics, 0 for a pure mass matrix.
    pub dq: f64,
}

impl NewtonWeights {
    /// The weights that make `J` the mass matrix `dI/da`.
    pub fn mass() -> Self {
        Self { inertia: 1.0, force: 0.0, da: 1.0, dv: 0.0, dq: 0.0 }
    }

    /// The weights that make `J` the static tangent stiffness `dg/dq`.
    pub fn stiffness() -> Self {
        Self { inertia: 0.0, force: 1.0, da: 0.0, dv: 0.0, dq: 1.0 }
    }
}

/// Entries of a sparse matrix in coordinate form. Duplicates are summed. A model should push
/// the same (row, column) sequence at every call with weights of the same kind (only the values
/// change): the sparse LU keeps the symbolic factorisation of the last pattern and rebuilds it
/// only if the pattern changes. A call without stiffness (`dq = 0`: a mass matrix, or a Newton
/// matrix's change with the step size) may push only its own entries.
#[derive(Debug, Clone, Default)]
pub struct Triplets {
    pub(crate) rows: Vec<usize>,
    pub(crate) cols: Vec<usize>,
    pub(crate) vals: Vec<f64>,
}

impl Triplets {
    /// An empty list.
    pub fn new() -> Self {
        Self::default()
    }

    /// Removes every entry, keeping the allocation.
    pub fn clear(&mut self) {
        self.rows.clear();
        self.cols.clear();
        self.vals.clear();
    }

    /// Adds `value` at (`row`, `col`).
    #[inline]
    pub fn push(&mut self, row: usize, col: usize, value: f64) {
        self.rows.push(row);
        self.cols.push(col);
        self.vals.push(value);
    }

    /// Keeps the first `len` entries pushed.
    pub(crate) fn truncate(&mut self, len: usize) {
        self.rows.truncate(len);
        self.cols.truncate(len);
        self.vals.truncate(len);
    }

    /// Pushes every entry of `other`, in its order.
    pub(crate) fn append(&mut self, other: &Triplets) {
        self.rows.extend_from_slice(&other.rows);
        self.cols.extend_from_slice(&other.cols);
        self.vals.extend_from_slice(&other.vals);
    }

    /// Number of entries pushed (duplicates counted).
    pub fn len(&self) -> usize {
        self.vals.len()
    }

    /// True when nothing has been pushed.
    pub fn is_empty(&self) -> bool {
        self.vals.is_empty()
    }

    /// The values in push order.
    pub fn values(&self) -> &[f64] {
        &self.vals
    }

    /// The entries as (row, column, value), in push order.
    pub fn iter(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        self.rows.iter().zip(&self.cols).zip(&self.vals).map(|((&r, &c), &v)| (r, c, v))
    }

    /// The matrix-vector product `y = A x` (duplicates summed).
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|yi| *yi = 0.0);
        for (r, c, v) in self.iter() {
            y[r] += v * x[c];
        }
    }
}

/// A mechanical model `I(q, v, a) + g(t, q, v) = 0` for the integrator (ARCHITECTURE.md at the repository root, HHT).
///
/// The configuration `q` may live on a manifold (positions and rotations): the model owns the
/// update `q <- q (+) dq`, and velocities and accelerations are plain vectors in the tangent
/// space that update uses (for rotations: angular velocities in the same frame as `dq`).
pub trait Model {
    /// The configuration (positions, rotations, ...). `'static` so that the integrator can
    /// keep a spare one between steps (see [`crate::Integrator::recycle`]).
    type Config: Clone + 'static;

    /// Number of unknowns (the length of `v`, `a` and of every force vector).
    fn ndof(&self) -> usize;

    /// `q <- q (+) dq`.
    fn update(&self, q: &mut Self::Config, dq: ColRef<'_, f64>);

    /// `out <- q (+) dq`, `out`'s allocations reused: by default a copy of `q` then
    /// [`Model::update`]; a model overrides it to do both in one pass.
    fn displaced(&self, q: &Self::Config, dq: ColRef<'_, f64>, out: &mut Self::Config) {
        out.clone_from(q);
        self.update(out, dq);
    }

    /// The inertial force `I(q, v, a)` (for a rigid rotation: `J a + w x J w`), written to `out`.
    fn inertial_force(
        &self,
        q: &Self::Config,
        v: ColRef<'_, f64>,
        a: ColRef<'_, f64>,
        out: ColMut<'_, f64>,
    );

    /// The inertial force of a step's predictor, written to `out`: at the old state's
    /// acceleration `a` (a predictor keeps it, to the bit) and the predictor's velocity `v`,
    /// given `old`, the old state's inertial force `I(q_n, v_n, a)` at that same `a`. A model
    /// whose inertial force is `M a` but for the rows of a term in the velocity (a rigid
    /// rotation's `w x J w`) may take the other rows from `old` (the same arithmetic on the
    /// same `a`: the same bits) and compute only those. The integrator asks it for a
    /// predictor only, and only of a model without [`Model::constant_mass`]. The default
    /// computes the whole force, [`Model::inertial_force`].
    fn predicted_inertial_force(
        &self,
        q: &Self::Config,
        v: ColRef<'_, f64>,
        a: ColRef<'_, f64>,
        old: ColRef<'_, f64>,
        out: ColMut<'_, f64>,
    ) {
        let _ = old;
        self.inertial_force(q, v, a, out);
    }

    /// Whether the inertial force is `M a` with one constant matrix `M` (independent of `q`
    /// and `v`: point masses, a planar beam). A step's predictor keeps the old acceleration,
    /// so its inertial force is then the old state's, and the integrator reuses it instead
    /// of recomputing it (a mass product a step). The default, `false`, recomputes it.
    fn constant_mass(&self) -> bool {
        false
    }

    /// The net force `g(t, q, v)`: internal plus damping minus external, written to `out`.
    fn net_force(&self, t: f64, q: &Self::Config, v: ColRef<'_, f64>, out: ColMut<'_, f64>);

    /// The Newton matrix for the weights `w` (see [`NewtonWeights`]), pushed into `out` (which
    /// the caller has cleared), with the same sparsity sequence at every call with stiffness
    /// (`dq != 0`; one without may push only its own entries, see [`Triplets`]).
    fn tangent(
        &self,
        t: f64,
        q: &Self::Config,
        v: ColRef<'_, f64>,
        a: ColRef<'_, f64>,
        w: NewtonWeights,
        out: &mut Triplets,
    );

    /// [`Model::tangent`] in two parts: into `slow` (if given) the terms a Newton matrix kept
    /// over many steps may take from an earlier state (a structure's stiffness under small
    /// strains: building it is most of a matrix's cost), into `fast` those it must take at the
    /// iterate (a contact's, which switches on and off and stiffens with the approach, and the
    /// mass of a body that carries nothing else). Their sum must be the tangent, for any
    /// weights. The integrator keeps the slow part of the last matrix it built in full and,
    /// for a new step size, adds to it the slow part's change in `da` and `dv` alone (the
    /// weights' difference with `dq = 0`: no stiffness) and a fresh fast part. The default
    /// puts everything in `fast` (every matrix built in full).
    #[allow(clippy::too_many_arguments)] // the tangent's arguments and the two lists
    fn tangent_parts(
        &self,
        t: f64,
        q: &Self::Config,
        v: ColRef<'_, f64>,
        a: ColRef<'_, f64>,
        w: NewtonWeights,
        _slow: Option<&mut Triplets>,
        fast: &mut Triplets,
    ) {
        self.tangent(t, q, v, a, w, fast);
    }

    /// Magnitude of the largest terms that cancel inside the internal force (model units): for
    /// a beam, EA times an axial stretch of order one. It sets the round-off floor of the
    /// residual test, a few ulps of this number: a stiff beam carries forces that are small
    /// differences of terms of order EA, whose round-off a purely relative test would chase
    /// forever. The default, 0, means the model has no such terms.
    fn force_scale(&self, _q: &Self::Config) -> f64 {
        0.0
    }

    /// Magnitude of the coordinates that an update changes (model units; for a beam, the
    /// largest node distance from the origin). A Newton correction smaller than their
    /// round-off cannot improve the iterate, so the integrator accepts the step as at its
    /// floating-point floor. Positions of order 1 m moved by 1e-15 m change a fine element's
    /// strain by 1e-13 and its force by EA x 1e-13: the residual can then sit just above any
    /// fixed floor while the corrections are pure round-off. The default, 0, relies on the
    /// step's own increment as the scale.
    fn configuration_scale(&self, _q: &Self::Config) -> f64 {
        0.0
    }

    /// Rows whose balance must hold on its own as well as in the whole residual's norm: a light
    /// body coupled to a heavy one (a ball on a beam), whose forces the heavy body's would
    /// otherwise hide. A step's predictor is accepted uncorrected only where these rows'
    /// residual is also within `rtol` of their own force terms (a 1 um ball on the paper's
    /// beam, 3e-14 kg against 1 kg, took most of its contact steps with no Newton correction,
    /// its rows unbalanced, and left the contact 5 % faster than it came; one correction a
    /// step balances it). Not asked of a corrected iterate: a kept Newton matrix, factorised in
    /// contact, corrects a free ball's rows slowly (a 9 g ball's leftover 0.03 m/s^2 after
    /// its contact, which changes its speed by 3e-9 m/s a step), and asking it there cost the
    /// paper's tip 20-40 % more time in second back-substitutions. The default, none.
    fn own_balance_rows(&self) -> std::ops::Range<usize> {
        0..0
    }

    /// The shape of the Newton matrix when it is banded with a small dense border (a chain of
    /// elements plus a few unknowns coupled to anything): the integrator then factorises it
    /// with [`crate::BandedLu`] instead of the general sparse LU. The default, `None`, means
    /// a general sparse matrix.
    fn band(&self) -> Option<crate::Band> {
        None
    }
}
