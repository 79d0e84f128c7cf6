//! The 3D beam's internal force and strains a block of elements at a time: the fe method's
//! innermost loop in 3D (every Newton iteration evaluates the force of every element, every
//! accepted step the strains).
//!
//! The formulas are [`Element::force`]'s (Crisfield & Jelenic's one-point element, see
//! `element.rs`), written lane by lane over arrays of a block's elements: the nodes' positions
//! and quaternions gathered into arrays, then one loop of plain arithmetic without branches,
//! which the compiler runs on several elements at once in `hht::fast`'s AVX2 copy. That loop
//! takes the rotation functions' series branch (`rotation::log_and_half`, the right Jacobian's
//! and its inverse's coefficients), valid where the element's relative rotation `|phi|^2` is
//! below `rotation::SERIES_BELOW` (1e-4: 0.01 rad between neighbouring sections, a curvature of
//! 2.2 1/m on the paper's 4.5 mm elements, some 20 times what its largest stress bends it by); an
//! element past it, or at a corner (its end frames offset from its nodes'), is computed again by
//! [`Element::force`]. Both give the same force to round-off (a test holds them equal).

use crate::element::{Element, Strains};
use crate::rotation::{inverse_series, log_ratio_series, SERIES_BELOW};
use hht::fast::MulAdd;
use nalgebra::{UnitQuaternion, Vector3};

/// Elements a block (the block's arrays, [`Scratch`], some 17 kB kept per thread). Fewer cost
/// their setup a block: 8, 16, 32, 64 and 128 took 18, 10, 8.1, 7.5 and 7.5 us a pass over 256
/// elements (the paper's tip in 3D, timers in the run).
const BLOCK: usize = 64;

/// Each element's constants as arrays (one entry an element), for the block loops.
#[derive(Debug, Clone, Default)]
pub(crate) struct ElementTable {
    inverse_length: Vec<f64>,
    gamma0: [Vec<f64>; 3],
    phi0: [Vec<f64>; 3],
    /// EA, GA2, GA3 (N).
    force_stiffness: [Vec<f64>; 3],
    /// GJ, EI2, EI3 over the length (N m): the moment from the relative rotation.
    moment_per_length: [Vec<f64>; 3],
    /// Whether both end frames are the nodes' own (no corner offset).
    straight: Vec<bool>,
    /// Whether each block's elements are all straight.
    straight_blocks: Vec<bool>,
    /// The element's nodes (the elements themselves are some 300 bytes each: their loops
    /// read these instead).
    nodes: Vec<[usize; 2]>,
    /// The consistent mass matrix's off-diagonal term `rho A l0 / 6` (kg).
    translational_mass: Vec<f64>,
    /// Each block's first node where its elements run node to node (element k of the block
    /// joins nodes `first + k` and `first + k + 1`, a straight or curved member's mesh): its
    /// nodes are then read once each, not once for each of their two elements, and each
    /// node's two elements' forces are added to it at once.
    chains: Vec<Option<usize>>,
}

impl ElementTable {
    pub(crate) fn new(elements: &[Element]) -> Self {
        let mut table = Self::default();
        for e in elements {
            table.inverse_length.push(1.0 / e.length);
            let (cn, cm) = (e.section.force_stiffness(), e.section.moment_stiffness());
            for k in 0..3 {
                table.gamma0[k].push(e.gamma0[k]);
                table.phi0[k].push(e.phi0[k]);
                table.force_stiffness[k].push(cn[k]);
                table.moment_per_length[k].push(cm[k] / e.length);
            }
            table.straight.push(e.straight());
            table.nodes.push(e.nodes);
            table.translational_mass.push(e.section.rho_a * e.length / 6.0);
        }
        // The lanes' arrays padded to whole blocks (a unit length, no stiffness): the block
        // loop runs every lane.
        let whole = table.inverse_length.len().next_multiple_of(BLOCK);
        for (v, pad) in [(&mut table.inverse_length, 1.0)].into_iter().chain(
            [
                &mut table.gamma0,
                &mut table.phi0,
                &mut table.force_stiffness,
                &mut table.moment_per_length,
            ]
            .into_iter()
            .flatten()
            .map(|v| (v, 0.0)),
        ) {
            v.resize(whole, pad);
        }
        table.straight_blocks =
            table.straight.chunks(BLOCK).map(|b| b.iter().all(|&s| s)).collect();
        table.chains = table
            .nodes
            .chunks(BLOCK)
            .map(|block| {
                let first = block[0][0];
                block
                    .iter()
                    .enumerate()
                    .all(|(k, &[a, b])| a == first + k && b == first + k + 1)
                    .then_some(first)
            })
            .collect();
        table
    }

    /// The lanes' arrays' length: the elements padded to a whole number of blocks.
    pub(crate) fn padded(&self) -> usize {
        self.inverse_length.len()
    }

    /// Whether the elements are one chain from node 0 in order (element k joins nodes k and
    /// k + 1) over `nodes` nodes: then every node has an element.
    pub(crate) fn one_chain(&self, nodes: usize) -> bool {
        let elements = self.nodes.len();
        nodes == elements + 1 && self.chains.iter().enumerate().all(|(b, c)| *c == Some(b * BLOCK))
    }

    /// Each element's nodes.
    pub(crate) fn nodes(&self) -> &[[usize; 2]] {
        &self.nodes
    }

    /// Each element's `rho A l0 / 6` (kg): its consistent mass matrix is that times
    /// `[2 1; 1 2]` on each direction.
    pub(crate) fn translational_masses(&self) -> &[f64] {
        &self.translational_mass
    }
}

/// Adds the elements' forces `[f_x1, f_th1, f_x2, f_th2]` (N, N m; moments in the nodal
/// material frames) to `out` at their nodes' unknowns.
pub(crate) struct BlockForces<'a> {
    pub elements: &'a [Element],
    pub table: &'a ElementTable,
    pub positions: &'a [Vector3<f64>],
    pub rotations: &'a [UnitQuaternion<f64>],
    /// Each node's unknowns (`None` where held).
    pub dofs: &'a [[Option<usize>; 6]],
    /// Each node's first unknown where all six are free and in a row.
    pub rows: &'a [Option<usize>],
    pub out: &'a mut [f64],
    /// Whether `out` is written, not added to: the elements are one chain from node 0 in
    /// order ([`ElementTable::one_chain`]), so every node's first terms are written over
    /// whatever `out` held (no zeroing first: 1 % of the paper's tip in 3D).
    pub write: bool,
    /// Each element's strains (Gamma1..3, K1..3, one array each, an entry an element, padded
    /// past the last to a whole number of blocks), written too if given.
    pub strains: Option<&'a mut [Vec<f64>; 6]>,
    /// The block's arrays ([`with_scratch`]).
    pub scratch: &'a mut Scratch,
}

impl hht::fast::Kernel for BlockForces<'_> {
    type Output = ();

    #[inline(always)]
    fn run<A: hht::fast::MulAdd>(mut self, m: A) {
        let count = self.elements.len();
        let mut start = 0;
        while start < count {
            let end = (start + BLOCK).min(count);
            if self.strains.is_some() {
                self.block::<true, A>(m, start, end);
            } else {
                self.block::<false, A>(m, start, end);
            }
            start = end;
        }
    }
}

/// `a x b` on the lanes' components, each component one multiply and one multiply-add.
#[inline(always)]
pub(crate) fn cross<A: MulAdd>(m: A, a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        m.mul_add(a[1], b[2], -(a[2] * b[1])),
        m.mul_add(a[2], b[0], -(a[0] * b[2])),
        m.mul_add(a[0], b[1], -(a[1] * b[0])),
    ]
}

/// `a . b` by multiply-adds.
#[inline(always)]
pub(crate) fn dot<A: MulAdd>(m: A, a: [f64; 3], b: [f64; 3]) -> f64 {
    m.mul_add(a[0], b[0], m.mul_add(a[1], b[1], a[2] * b[2]))
}

/// A unit quaternion `(w, u)` with `2 u` (its turns take it: the multiply by two once, not
/// once a turn; the element's loop is bound by its multiplies).
#[derive(Clone, Copy)]
struct Turn {
    w: f64,
    u: [f64; 3],
    twice_u: [f64; 3],
}

impl Turn {
    #[inline(always)]
    fn new(w: f64, u: [f64; 3]) -> Self {
        Self { w, u, twice_u: u.map(|u| u + u) }
    }

    /// `v` turned: `v + 2 w u x v + 2 u x (u x v)`, or by the inverse `(w, -u)` with
    /// `INVERSE`: `v - 2 w u x v + 2 u x (u x v)`.
    #[inline(always)]
    fn apply<const INVERSE: bool, A: MulAdd>(self, m: A, v: [f64; 3]) -> [f64; 3] {
        let t = cross(m, self.twice_u, v);
        let ut = cross(m, self.u, t);
        let w = if INVERSE { -self.w } else { self.w };
        std::array::from_fn(|c| m.mul_add(w, t[c], v[c] + ut[c]))
    }
}

/// The sign bit of an `f64`.
const SIGN_BIT: u64 = 1 << 63;

/// `x` with its sign flipped where `sign` is [`SIGN_BIT`] (a bit operation, not a multiply).
#[inline(always)]
fn flipped(x: f64, sign: u64) -> f64 {
    f64::from_bits(x.to_bits() ^ sign)
}

/// `(1 - cos(a/2)) / a^2` and `(a/2 - sin(a/2)) / a^3`, the right Jacobian's coefficients at
/// `phi / 2` over 4 and 8 (`rotation::jacobian_series` at `a^2 / 4`), by their series in
/// `a2 = a^2`: `1/8 - a^2/384 + a^4/46080` and `1/48 - a^2/3840 + a^4/645120` (the terms left
/// out, `a^6/1.03e7` and `a^6/1.86e8`, below 1e-19 where the lanes' series hold: a test holds
/// them to their closed forms).
#[inline(always)]
fn half_jacobian_series<A: MulAdd>(m: A, a2: f64) -> (f64, f64) {
    (
        m.mul_add(a2, m.mul_add(a2, 1.0 / 46080.0, -1.0 / 384.0), 1.0 / 8.0),
        m.mul_add(a2, m.mul_add(a2, 1.0 / 645_120.0, -1.0 / 3840.0), 1.0 / 48.0),
    )
}

/// `1 / w` and `1 / sqrt(2 (1 + w))` by their series in `d = 1 - w`, not by a division and a
/// square root: `1 / (1 - d) = 1 + d + d^2 + d^3`, and `1 / sqrt(4 - 2 d) = (1 - x)^(-1/2) / 2`
/// with `x = d / 2`, `(1 + x / 2 + 3 x^2 / 8 + 5 x^3 / 16) / 2` (the terms left out are
/// `d^4 < 3e-20` where the lanes' series hold, `d < 1.3e-5`: a test holds them to their
/// closed forms).
#[inline(always)]
fn inverse_series_in_w<A: MulAdd>(m: A, d: f64) -> (f64, f64) {
    let x = 0.5 * d;
    (
        m.mul_add(d, m.mul_add(d, m.mul_add(d, 1.0, 1.0), 1.0), 1.0),
        0.5 * m.mul_add(x, m.mul_add(x, m.mul_add(x, 5.0 / 16.0, 3.0 / 8.0), 0.5), 1.0),
    )
}

/// A block's nodes: positions `x[end][component][element]` and quaternions
/// `q[end][w, i, j, k][element]` (one entry more than the block's elements: a chain's nodes
/// are gathered into the first ends' arrays, see [`gather`]).
struct Gathered {
    x: [[[f64; BLOCK + 1]; 3]; 2],
    q: [[[f64; BLOCK + 1]; 4]; 2],
}

/// A block's arrays: its nodes, the results by lanes (12 force components, and 6 more: the
/// strains of [`BlockStrains`], or where [`BlockForces`] writes none), each element's
/// `4 sin^2(a/2)` (its range). The lane loops run every lane of a block, past its elements
/// too (on an earlier block's values, or zeros): what a block uses of them, its own elements'
/// lanes, it has written first.
pub(crate) struct Scratch {
    nodes: Gathered,
    lanes: [[f64; BLOCK]; 18],
    chord2: [f64; BLOCK],
}

impl Scratch {
    fn boxed() -> Box<Self> {
        Box::new(Self {
            nodes: Gathered { x: [[[0.0; BLOCK + 1]; 3]; 2], q: [[[0.0; BLOCK + 1]; 4]; 2] },
            lanes: [[0.0; BLOCK]; 18],
            chord2: [0.0; BLOCK],
        })
    }
}

thread_local! {
    /// Each thread's block arrays, made once: made (zeroed) every pass, they took 3 % of the
    /// paper's tip in 3D.
    static SCRATCH: std::cell::Cell<Option<Box<Scratch>>> = const { std::cell::Cell::new(None) };
}

/// Runs `f` with this thread's block arrays, taken while it runs: a pass inside another (a
/// strain's callback of [`BlockStrains`] that evaluates forces) makes and zeroes arrays of its
/// own, as every pass once did.
pub(crate) fn with_scratch<R>(f: impl FnOnce(&mut Scratch) -> R) -> R {
    let kept = SCRATCH.try_with(std::cell::Cell::take).ok().flatten();
    let mut scratch = kept.unwrap_or_else(Scratch::boxed);
    let result = f(&mut scratch);
    // (Not kept where the thread's storage is already gone, in its last moments.)
    let _ = SCRATCH.try_with(|cell| cell.set(Some(scratch)));
    result
}

/// Writes node `node`'s position and quaternion into entry `k` of the arrays of `end`.
#[inline(always)]
fn put(g: &mut Gathered, (end, k): (usize, usize), (p, r): (&Vector3<f64>, &UnitQuaternion<f64>)) {
    let r = r.quaternion();
    for c in 0..3 {
        g.x[end][c][k] = p[c];
    }
    g.q[end][0][k] = r.w;
    g.q[end][1][k] = r.i;
    g.q[end][2][k] = r.j;
    g.q[end][3][k] = r.k;
}

/// Where a block's lanes read their elements' second nodes: `g.x[end][c][k + shift]` and
/// likewise `g.q`.
#[derive(Clone, Copy)]
struct SecondEnds {
    end: usize,
    shift: usize,
}

/// Gathers the nodes of the block's elements `nodes` into `g`, and says where their second
/// ends are: a chain's nodes (from node `first`) each once into the first ends' arrays (one
/// entry more than the elements: the second ends are those arrays from the next entry on),
/// else element by element.
#[inline(always)]
fn gather(
    g: &mut Gathered,
    (nodes, chain): (&[[usize; 2]], Option<usize>),
    positions: &[Vector3<f64>],
    rotations: &[UnitQuaternion<f64>],
) -> SecondEnds {
    let m = nodes.len();
    match chain {
        Some(first) => {
            let (x, r) = (&positions[first..=first + m], &rotations[first..=first + m]);
            for (k, node) in x.iter().zip(r).enumerate() {
                put(g, (0, k), node);
            }
            SecondEnds { end: 0, shift: 1 }
        }
        None => {
            for (k, e) in nodes.iter().enumerate() {
                for (end, &node) in e.iter().enumerate() {
                    put(g, (end, k), (&positions[node], &rotations[node]));
                }
            }
            SecondEnds { end: 1, shift: 0 }
        }
    }
}

/// One element's kinematics by the series (`Element::kinematics_f64`'s quantities).
struct Lane {
    /// The relative rotation vector `log(Lambda_1^T Lambda_2)` (rad).
    phi: [f64; 3],
    /// Its square norm.
    angle2: f64,
    /// `4 sin^2(a/2)` (<= a^2 = |phi|^2): the series hold where it is below `SERIES_BELOW`,
    /// and the lane's values are the element's only then. It tells the range from the
    /// relative rotation itself: `|phi|^2` from the series would not (past a = 1.9 rad the
    /// series of atan crosses zero, and a large turn would look small).
    chord2: f64,
    /// The half rotation `exp(phi^ / 2)`.
    half: Turn,
    /// The midpoint rotation `Lambda_1 exp(phi^ / 2)`.
    midpoint: Turn,
    /// `Lambda_m^T d` (m), `d` the chord between the nodes.
    chord: [f64; 3],
    /// `Lambda_m^T d / l0`.
    gamma_full: [f64; 3],
}

#[inline(always)]
fn lane<A: MulAdd>(
    m: A,
    (g, second): (&Gathered, SecondEnds),
    k: usize,
    inverse_length: f64,
) -> Lane {
    // (`min` tells the compiler the indices are in bounds.)
    let (e2, k2) = (second.end.min(1), k + second.shift.min(1));
    let (w1, u1) = (g.q[0][0][k], [g.q[0][1][k], g.q[0][2][k], g.q[0][3][k]]);
    let (w2, u2) = (g.q[e2][0][k2], [g.q[e2][1][k2], g.q[e2][2][k2], g.q[e2][3][k2]]);
    // The relative rotation conj(q1) q2 = (w1 w2 + u1.u2, w1 u2 - w2 u1 - u1 x u2), turned to
    // w >= 0 (q and -q are one rotation): its w's sign bit, where set, flips the two
    // coefficients its vector part is taken with below (a bit operation each, not a multiply
    // of the four parts).
    let c12 = cross(m, u1, u2);
    let rw = m.mul_add(w1, w2, dot(m, u1, u2));
    let sign = rw.to_bits() & SIGN_BIT;
    let rw = rw.abs();
    let rv: [f64; 3] = std::array::from_fn(|c| m.mul_add(w1, u2[c], -m.mul_add(w2, u1[c], c12[c])));
    // log: phi = v 2 atan(|v| / w) / |v|, by its series in |v|^2 / w^2.
    let s2 = dot(m, rv, rv);
    let (inverse_w, inverse_norm) = inverse_series_in_w(m, 1.0 - rw);
    let ratio = flipped(log_ratio_series(s2, inverse_w), sign);
    let phi = [rv[0] * ratio, rv[1] * ratio, rv[2] * ratio];
    // The half rotation: the normalised mean of the identity and the relative one.
    let one_plus_w = 1.0 + rw;
    let signed_norm = flipped(inverse_norm, sign);
    let (hw, hv) = (one_plus_w * inverse_norm, rv.map(|v| v * signed_norm));
    // The midpoint rotation q1 half.
    let c1h = cross(m, u1, hv);
    let mw = m.mul_add(w1, hw, -dot(m, u1, hv));
    let mv: [f64; 3] = std::array::from_fn(|c| m.mul_add(w1, hv[c], m.mul_add(hw, u1[c], c1h[c])));
    let span: [f64; 3] = std::array::from_fn(|c| g.x[e2][c][k2] - g.x[0][c][k]);
    let midpoint = Turn::new(mw, mv);
    let chord = midpoint.apply::<true, A>(m, span);
    Lane {
        phi,
        // |phi|^2 = |v|^2 ratio^2 (two multiplies, not three).
        angle2: s2 * (ratio * ratio),
        chord2: 4.0 * s2,
        half: Turn::new(hw, hv),
        midpoint,
        chord,
        gamma_full: chord.map(|c| c * inverse_length),
    }
}

/// Adds a node's force and moment, the sum of `forces` in their order, to its unknowns in
/// `out` (none where held); with `write`, the first is written over what `out` holds there
/// (the node's first terms: `out` need not be zeroed first).
#[inline(always)]
fn add_to_node<const N: usize>(
    (rows, dofs): (&[Option<usize>], &[[Option<usize>; 6]]),
    out: &mut [f64],
    (node, write): (usize, bool),
    forces: [[f64; 6]; N],
) {
    match rows[node] {
        Some(i) => {
            let o: &mut [f64] = &mut out[i..i + 6];
            for (k, f) in forces.into_iter().enumerate() {
                for (o, f) in o.iter_mut().zip(f) {
                    *o = if write && k == 0 { f } else { *o + f };
                }
            }
        }
        None => {
            for (k, f) in forces.into_iter().enumerate() {
                for (d, f) in dofs[node].iter().zip(f) {
                    if let Some(i) = d {
                        out[*i] = if write && k == 0 { f } else { out[*i] + f };
                    }
                }
            }
        }
    }
}

/// The first unknown of node `first + 1` where the nodes `first + 1 .. first + m` all have
/// their six free and in a row, each node's right after the last's.
#[inline(always)]
fn interior_rows(rows: &[Option<usize>], first: usize, m: usize) -> Option<usize> {
    let base = (*rows.get(first + 1)?)?;
    let inner = rows.get(first + 1..first + m)?;
    inner.iter().enumerate().all(|(k, r)| *r == Some(base + 6 * k)).then_some(base)
}

/// The block of `v` from `start` (a lane array of the table, padded to whole blocks).
#[inline(always)]
fn whole_block(v: &[f64], start: usize) -> &[f64; BLOCK] {
    #[allow(clippy::expect_used)] // the table is padded to whole blocks
    v[start..start + BLOCK].try_into().expect("a whole block")
}

/// [`whole_block`] to write (the strains' arrays, padded to whole blocks by the model).
#[inline(always)]
fn whole_block_mut(v: &mut [f64], start: usize) -> &mut [f64; BLOCK] {
    #[allow(clippy::expect_used)] // padded to whole blocks
    (&mut v[start..start + BLOCK]).try_into().expect("a whole block")
}

/// The forces (and with `STRAINS` the strains, into `strains`) of table `t`'s block from
/// element `start` by the series, into the lanes `f` and their ranges into `chord2`, from their
/// nodes `g`. A function of its own: its `&mut` arguments tell the compiler that the lanes
/// alias nothing it reads (inline, it checked that at run time, and ran part of the loop on one
/// lane).
#[inline(always)]
fn forces_by_lanes<'t, const STRAINS: bool, A: MulAdd>(
    fma: A,
    (t, start): (&'t ElementTable, usize),
    g: (&Gathered, SecondEnds),
    f: &mut [[f64; BLOCK]; 12],
    [s0, s1, s2, s3, s4, s5]: [&mut [f64; BLOCK]; 6],
    chord2: &mut [f64; BLOCK],
) {
    // Every lane of the block, past its elements too (the table is padded to whole blocks,
    // the nodes' arrays hold an earlier block's): a loop of a fixed count that the compiler
    // runs on whole vectors (up to the block's element count it left the last one to four
    // lanes to one-lane code: a fifth of the loop's time).
    let block = |v: &'t [f64]| -> &'t [f64; BLOCK] { whole_block(v, start) };
    let inverse = block(&t.inverse_length);
    let [g0, g1, g2] = t.gamma0.each_ref().map(|v| block(v));
    let [p0, p1, p2] = t.phi0.each_ref().map(|v| block(v));
    let [n0, n1, n2] = t.force_stiffness.each_ref().map(|v| block(v));
    let [m0, m1, m2] = t.moment_per_length.each_ref().map(|v| block(v));
    for k in 0..BLOCK {
        let Lane { phi, angle2: a2, chord2: range, half, midpoint, chord, gamma_full } =
            lane(fma, g, k, inverse[k]);
        chord2[k] = range;
        let strain = [gamma_full[0] - g0[k], gamma_full[1] - g1[k], gamma_full[2] - g2[k]];
        let relative = [phi[0] - p0[k], phi[1] - p1[k], phi[2] - p2[k]];
        // (A branch on whether to write them here, not a constant, kept the loop from the
        // vector lanes: the 3D run took 37 % longer.)
        if STRAINS {
            (s0[k], s1[k], s2[k]) = (strain[0], strain[1], strain[2]);
            let curvature = relative.map(|r| r * inverse[k]);
            (s3[k], s4[k], s5[k]) = (curvature[0], curvature[1], curvature[2]);
        }
        // N = C_N Gamma, M = C_M K = (C_M / l0) (phi - phi0).
        let n = [strain[0] * n0[k], strain[1] * n1[k], strain[2] * n2[k]];
        let moment = [relative[0] * m0[k], relative[1] * m1[k], relative[2] * m2[k]];
        let n_spatial = midpoint.apply::<false, A>(fma, n);
        // c = l0 N x Gamma_full = N x Lambda_m^T d.
        let c = cross(fma, n, chord);
        // m~ = M + J_r(phi / 2)^T c / 2, J_r(p)^T v = v + j1 p x v + j2 p x (p x v): with p and
        // v the halves of phi and c, M + c / 2 + (j1 / 4) phi x c + (j2 / 8) phi x (phi x c).
        let (k1, k2) = half_jacobian_series(fma, a2);
        let pc = cross(fma, phi, c);
        let ppc = cross(fma, phi, pc);
        let mt: [f64; 3] = std::array::from_fn(|i| {
            fma.mul_add(k1, pc[i], fma.mul_add(k2, ppc[i], fma.mul_add(0.5, c[i], moment[i])))
        });
        // f_th2 = J_r(phi)^-T m~ = m~ - phi x m~ / 2 + coefficient phi x (phi x m~).
        let coefficient = inverse_series(a2);
        let pm = cross(fma, phi, mt);
        let ppm = cross(fma, phi, pm);
        let f_th2: [f64; 3] = std::array::from_fn(|i| {
            fma.mul_add(coefficient, ppm[i], fma.mul_add(-0.5, pm[i], mt[i]))
        });
        // f_th1 = half (c - half f_th2).
        let turned = half.apply::<false, A>(fma, f_th2);
        let f_th1 =
            half.apply::<false, A>(fma, [c[0] - turned[0], c[1] - turned[1], c[2] - turned[2]]);
        for i in 0..3 {
            f[i][k] = -n_spatial[i];
            f[3 + i][k] = f_th1[i];
            f[6 + i][k] = n_spatial[i];
            f[9 + i][k] = f_th2[i];
        }
    }
}

impl BlockForces<'_> {
    /// One block's forces into `out`, and with `STRAINS` its strains into `strains`.
    #[inline(always)]
    fn block<const STRAINS: bool, A: MulAdd>(&mut self, fma: A, start: usize, end: usize) {
        let m = end - start;
        let t = self.table;
        let chain = t.chains[start / BLOCK];
        let Scratch { nodes: g, lanes, chord2 } = &mut *self.scratch;
        let (f, own) = lanes.split_at_mut(12);
        #[allow(clippy::expect_used)] // 18 lanes: 12 and 6
        let (f, own): (&mut [[f64; BLOCK]; 12], &mut [[f64; BLOCK]; 6]) =
            (f.try_into().expect("12 lanes"), own.try_into().expect("6 lanes"));
        // The strains straight into the caller's arrays (padded to whole blocks), not into
        // the block's lanes and copied (2 % of the paper's tip in 3D); without them, into the
        // block's own, unwritten.
        let strains = match self.strains.as_deref_mut() {
            Some(s) => s.each_mut().map(|s| whole_block_mut(s, start)),
            None => own.each_mut(),
        };
        let second = gather(g, (&t.nodes[start..end], chain), self.positions, self.rotations);
        forces_by_lanes::<STRAINS, A>(fma, (t, start), (g, second), f, strains, chord2);
        // The elements the series do not hold (or at a corner) again exactly, into the lanes
        // (looked for element by element only where the block has any).
        let beyond = chord2[..m].iter().fold(false, |b, &c| b | (c >= SERIES_BELOW) | c.is_nan());
        let looked = if beyond || !t.straight_blocks[start / BLOCK] { 0..m } else { 0..0 };
        for k in looked {
            let e = start + k;
            if t.straight[e] && chord2[k] < SERIES_BELOW {
                continue;
            }
            let [a, b] = t.nodes[e];
            let (x, r) = (
                [&self.positions[a], &self.positions[b]],
                [&self.rotations[a], &self.rotations[b]],
            );
            if let (true, Some(out)) = (STRAINS, self.strains.as_deref_mut()) {
                let strains = self.elements[e].strains(x, r);
                for c in 0..3 {
                    out[c][e] = strains.gamma[c];
                    out[3 + c][e] = strains.kappa[c];
                }
            }
            let force = self.elements[e].force(x, r);
            for (i, lane) in f.iter_mut().enumerate() {
                lane[k] = force[i];
            }
        }
        let (to, out) = ((self.rows, self.dofs), &mut *self.out);
        let end_force =
            |end: usize, k: usize| -> [f64; 6] { std::array::from_fn(|c| f[6 * end + c][k]) };
        match chain {
            // Node first + k: its element k - 1's second end, then its element k's first
            // (each node's sum in the elements' order, as element by element).
            // Written (one chain): the block's nodes but its first, which the block before
            // wrote (where there is one).
            Some(first) => {
                let write = self.write;
                add_to_node(to, out, (first, write && start == 0), [end_force(0, 0)]);
                match if write { interior_rows(self.rows, first, m) } else { None } {
                    // The block's inner nodes written over `out` where their unknowns follow
                    // each other: each node's two terms summed on the lanes, component by
                    // component (the same sum as `add_to_node`'s, the same bits), into the
                    // six lanes the pass leaves free (`own`: the strains go to the caller's
                    // arrays or nowhere), then copied node by node (node by node through
                    // `add_to_node`, 12 loads and 6 additions a node, the scatter took 5 % of
                    // the paper's tip in 3D).
                    Some(base) => {
                        let sums = own;
                        for (c, sum) in sums.iter_mut().enumerate() {
                            let (second, first_end) = (&f[6 + c], &f[c]);
                            for k in 1..m {
                                sum[k] = second[k - 1] + first_end[k];
                            }
                        }
                        let nodes = out[base..base + 6 * (m - 1)].chunks_exact_mut(6);
                        for (k, node) in nodes.enumerate() {
                            for (c, o) in node.iter_mut().enumerate() {
                                *o = sums[c][k + 1];
                            }
                        }
                    }
                    None => {
                        for k in 1..m {
                            let forces = [end_force(1, k - 1), end_force(0, k)];
                            add_to_node(to, out, (first + k, write), forces);
                        }
                    }
                }
                add_to_node(to, out, (first + m, write), [end_force(1, m - 1)]);
            }
            None => {
                for (k, &[a, b]) in t.nodes[start..end].iter().enumerate() {
                    add_to_node(to, out, (a, false), [end_force(0, k)]);
                    add_to_node(to, out, (b, false), [end_force(1, k)]);
                }
            }
        }
    }
}

/// Hands every element's strains to `each` (its index and strains, in the mesh's order), a
/// block at a time as [`BlockForces`] (the accepted steps' stresses and energy ask them of
/// every element).
pub(crate) struct BlockStrains<'a, F: FnMut(usize, Strains<f64>)> {
    pub elements: &'a [Element],
    pub table: &'a ElementTable,
    pub positions: &'a [Vector3<f64>],
    pub rotations: &'a [UnitQuaternion<f64>],
    pub each: F,
    /// The block's arrays ([`with_scratch`]).
    pub scratch: &'a mut Scratch,
}

impl<F: FnMut(usize, Strains<f64>)> hht::fast::Kernel for BlockStrains<'_, F> {
    type Output = ();

    #[inline(always)]
    fn run<A: hht::fast::MulAdd>(mut self, m: A) {
        let t = self.table;
        let Scratch { nodes: g, lanes: strains, chord2 } = &mut *self.scratch;
        for (b, block) in self.elements.chunks(BLOCK).enumerate() {
            let start = b * BLOCK;
            let nodes = (&t.nodes[start..start + block.len()], t.chains[b]);
            let second = gather(g, nodes, self.positions, self.rotations);
            // [Gamma; K] by lanes (every lane, as `forces_by_lanes`), then the elements the
            // series do not hold again exactly.
            let inverse = whole_block(&t.inverse_length, start);
            let gamma0 = t.gamma0.each_ref().map(|v| whole_block(v, start));
            let phi0 = t.phi0.each_ref().map(|v| whole_block(v, start));
            for k in 0..BLOCK {
                let l = lane(m, (g, second), k, inverse[k]);
                chord2[k] = l.chord2;
                for c in 0..3 {
                    strains[c][k] = l.gamma_full[c] - gamma0[c][k];
                    strains[3 + c][k] = (l.phi[c] - phi0[c][k]) * inverse[k];
                }
            }
            for (k, element) in block.iter().enumerate() {
                let e = start + k;
                let s = if t.straight[e] && chord2[k] < SERIES_BELOW {
                    Strains {
                        gamma: Vector3::from_fn(|c, _| strains[c][k]),
                        kappa: Vector3::from_fn(|c, _| strains[3 + c][k]),
                    }
                } else {
                    let [a, b] = element.nodes;
                    element.strains(
                        [&self.positions[a], &self.positions[b]],
                        [&self.rotations[a], &self.rotations[b]],
                    )
                };
                (self.each)(e, s);
            }
        }
    }
}

/// Each node's first unknown where its six are free and numbered in a row (the internal
/// force then adds a node's six at once), `None` where any is held.
pub(crate) fn rows(dofs: &[[Option<usize>; 6]]) -> Vec<Option<usize>> {
    dofs.iter()
        .map(|d| {
            let first = d[0]?;
            (0..6).all(|k| d[k] == Some(first + k)).then_some(first)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::{BeamModel, Material, Mesh, Section, Support};

    /// A frame: a straight leg of 50 elements joined at a right-angle corner to an arc of 0.1
    /// rad in 29 (more than one block, a corner, curved elements within the series), clamped at
    /// its start, moved off its reference by small turns and displacements everywhere and a
    /// large turn at three nodes.
    fn bent_frame() -> (BeamModel, crate::BeamState) {
        let steel = Material::new(2.1e11, 0.3, 7850.0).unwrap();
        let section = Section::rectangle(&steel, 0.025, 0.005).unwrap();
        let leg =
            Mesh::straight(Vector3::zeros(), Vector3::x(), 50, section, Vector3::z()).unwrap();
        let arc = Mesh::arc(
            Vector3::new(1.0, 0.5, 0.0),
            0.5,
            -Vector3::y(),
            Vector3::x(),
            0.1,
            29,
            section,
        )
        .unwrap();
        let model =
            BeamModel::new(leg.join(arc).unwrap()).unwrap().support(0, Support::Clamped).unwrap();
        let mut q = model.reference_state();
        let mut seed = 7_u64;
        let mut noise = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (seed >> 11) as f64 / (1_u64 << 53) as f64 - 0.5
        };
        for node in 1..q.positions.len() {
            q.positions[node] += Vector3::new(noise(), noise(), noise()) * 1e-4;
            // Turns of up to 1e-3 rad a node: within the series between neighbours.
            let turn = Vector3::new(noise(), noise(), noise()) * 2e-3;
            q.rotations[node] *= UnitQuaternion::from_scaled_axis(turn);
        }
        // Node 40 by the other of its two quaternions (q and -q are one rotation): its two
        // elements' relative quaternions have w < 0, turned by the sign bit.
        q.rotations[40] = UnitQuaternion::new_unchecked(-q.rotations[40].into_inner());
        // (Node 70 in the second block, all straight, no corner: only its own lanes past the
        // series send it to the exact elements.)
        for node in [5, 60, 70] {
            q.rotations[node] *= UnitQuaternion::from_scaled_axis(Vector3::new(0.3, -0.2, 0.1));
        }
        // And node 30 turned from node 29 by 1.90882 rad, where the series of atan(x) / x in
        // x = tan^2(a/2) cross zero (x = 1.99234): a large turn the series alone would take
        // for none.
        let turn = Vector3::new(0.0, 0.96, 0.28) * 1.908_822_652_815;
        q.rotations[30] = q.rotations[29] * UnitQuaternion::from_scaled_axis(turn);
        (model, q)
    }

    #[test]
    fn the_blocks_give_each_element_s_own_force_and_strains() {
        // The block loop and `Element::force` evaluate the same formulas (the series below
        // the bound; `Element::force` itself past it and at the corner) in another order: the
        // same to round-off, a few ulps of the terms that cancel in a force (EA times a strain of
        // 1e-4 here, against forces down to EA 1e-8): 1e-9 of the largest entry, an absolute 1e-13
        // on the strains (of order 1e-4 to 1); 5e-13 on the curvatures, phi / l0 with phi the
        // difference of O(1) quaternion components (a few ulps, 2.2e-16 each) over l0 = 0.02 m:
        // 1e-14 an ulp, and the multiply-adds round elsewhere than `Element::force` (1.4e-13
        // measured beside the large turns).
        let (model, q) = bent_frame();
        each_block_s_forces_are_its_elements(&model, &q);
        // The same elements listed last to first: no block runs node to node (the blocks
        // gather and scatter element by element, not as a chain).
        let mut reversed = model.mesh().clone();
        reversed.elements.reverse();
        let reversed = BeamModel::new(reversed).unwrap().support(0, Support::Clamped).unwrap();
        let chains = |m: &BeamModel| ElementTable::new(&m.mesh().elements).chains;
        assert!(chains(&reversed).iter().all(Option::is_none));
        assert!(chains(&model).iter().all(Option::is_some));
        each_block_s_forces_are_its_elements(&reversed, &q);
    }

    #[test]
    fn a_chain_s_inner_nodes_written_on_the_lanes_are_their_added_terms() {
        // Written over `out` (one chain from node 0, the inner nodes' sums on the lanes) and
        // added to a zeroed `out` (node by node through `add_to_node`): the same numbers
        // (0 + a + b is a + b), on the bent frame (two blocks, the second's nodes past the
        // corner), the same with a node held in one direction inside the first block (its
        // block node by node), a chain of 65 elements (a last block of one) and one of one.
        let steel = Material::new(2.1e11, 0.3, 7850.0).unwrap();
        let section = Section::rectangle(&steel, 0.025, 0.005).unwrap();
        let chain = |n: usize| {
            let mesh = Mesh::straight(Vector3::zeros(), Vector3::x(), n, section, Vector3::z());
            let model = BeamModel::new(mesh.unwrap()).unwrap().support(0, Support::Clamped);
            let model = model.unwrap();
            let mut q = model.reference_state();
            for (k, (x, r)) in q.positions.iter_mut().zip(&mut q.rotations).enumerate().skip(1) {
                let s = k as f64 / n as f64;
                *x += Vector3::new(1e-5 * s, 2e-4 * s * s, -3e-4 * s * s);
                *r *= UnitQuaternion::from_scaled_axis(Vector3::new(1e-3, -4e-4 * s, 6e-4 * s));
            }
            (model, q)
        };
        let (frame, bent) = bent_frame();
        let held = (frame.clone().hold(&[(30, 1)]).unwrap(), bent.clone());
        for (model, q) in [(frame, bent), held, chain(65), chain(1)] {
            let n = hht::Model::ndof(&model);
            let mut written = vec![f64::NAN; n];
            model.add_internal_on(&q, (&mut written, true), None, true);
            let mut added = vec![0.0; n];
            model.add_internal_on(&q, (&mut added, false), None, true);
            // (Bits, with a zero's sign set aside: 0 + -0 is +0.)
            let bits = |v: &[f64]| v.iter().map(|x| (x + 0.0).to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&written), bits(&added), "{} elements", model.mesh().elements.len());
            assert!(written.iter().any(|&f| f != 0.0));
        }
    }

    #[test]
    fn the_eight_lanes_copy_gives_the_four_lanes_bits() {
        // Each lane's element by the same operations in either copy (hht::fast::run_wide's
        // where the processor has AVX-512, else the same copy twice): forces and strains
        // to the bit, on both branches (the series, and the exact elements past them).
        if !hht::fast::wide_lanes() {
            eprintln!("no AVX-512 here: the two copies are one, nothing to compare");
            return;
        }
        let (model, q) = bent_frame();
        let n = hht::Model::ndof(&model);
        let each = |wide: bool| {
            let mut out = vec![0.0; n];
            let padded = ElementTable::new(&model.mesh().elements).padded();
            let mut strains: [Vec<f64>; 6] = std::array::from_fn(|_| vec![0.0; padded]);
            model.add_internal_on(&q, (&mut out, false), Some(&mut strains), wide);
            (out, strains)
        };
        let (wide, four) = (each(true), each(false));
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&wide.0), bits(&four.0));
        for (a, b) in wide.1.iter().zip(&four.1) {
            assert_eq!(bits(a), bits(b));
        }
        assert!(wide.0.iter().any(|&f| f != 0.0));
    }

    #[test]
    fn the_lanes_series_are_their_closed_forms() {
        // Where the lanes' series hold (|phi|^2 = a^2 up to about 1e-4, d = 1 - w up to
        // 1.25e-5): to a few ulps, so that a wrong coefficient of any term kept would show at
        // the bound (the last kept terms are there some 1e-12 and 1e-15 of the first).
        let m = hht::fast::Separate;
        for a2 in [0.0, 1e-8, 1e-6, 1e-5, 1e-4] {
            let (k1, k2) = half_jacobian_series(m, a2);
            // Their Taylor series in x = a/2 taken far (eight terms, each below the last by
            // x^2 / 56 at least: exact to an ulp): (1 - cos x) / (4 x^2) and
            // (x - sin x) / (8 x^3), sums of (-1)^k x^(2k) / (2k+2)! and / (2k+3)!.
            let x2 = a2 / 4.0;
            let factorial = |n: u32| (1..=n).map(f64::from).product::<f64>();
            let taylor = |first: u32| {
                (0..8).map(|k| (-x2).powi(k) / factorial(2 * k as u32 + first)).sum::<f64>()
            };
            let exact = (taylor(2) / 4.0, taylor(3) / 8.0);
            for (series, exact) in [(k1, exact.0), (k2, exact.1)] {
                assert!((series - exact).abs() <= 4.0 * f64::EPSILON * exact, "{a2}: {series}");
            }
            let w = (1.0 - a2 / 4.0).sqrt();
            let (inverse_w, inverse_norm) = inverse_series_in_w(m, 1.0 - w);
            assert!((inverse_w * w - 1.0).abs() <= 4.0 * f64::EPSILON, "{a2}: {inverse_w}");
            let norm = (2.0 * (1.0 + w)).sqrt();
            assert!((inverse_norm * norm - 1.0).abs() <= 4.0 * f64::EPSILON, "{a2}");
        }
    }

    fn each_block_s_forces_are_its_elements(model: &BeamModel, q: &crate::BeamState) {
        let elements = &model.mesh().elements;
        let mut expected = vec![0.0; hht::Model::ndof(model)];
        for e in elements {
            let [a, b] = e.nodes;
            let f = e.force([&q.positions[a], &q.positions[b]], [&q.rotations[a], &q.rotations[b]]);
            for (end, node) in [a, b].into_iter().enumerate() {
                for k in 0..6 {
                    if let Some(i) = model.dof(node, k) {
                        expected[i] += f[6 * end + k];
                    }
                }
            }
        }
        let force = model.internal_force(q);
        let scale = expected.iter().fold(0.0_f64, |m, f| m.max(f.abs()));
        for (i, f) in expected.iter().enumerate() {
            assert!((force[i] - f).abs() <= 1e-9 * scale, "unknown {i}: {} vs {f}", force[i]);
        }
        let zero = Strains { gamma: Vector3::zeros(), kappa: Vector3::zeros() };
        let mut strains = vec![zero; elements.len()];
        model.each_strain(q, |e, s| strains[e] = s);
        let mut series = 0;
        for (e, s) in elements.iter().zip(&strains) {
            let [a, b] = e.nodes;
            let exact =
                e.strains([&q.positions[a], &q.positions[b]], [&q.rotations[a], &q.rotations[b]]);
            assert!(
                (s.gamma - exact.gamma).amax() < 1e-13 && (s.kappa - exact.kappa).amax() < 5e-13
            );
            let phi = e.length * s.kappa + e.phi0;
            series += usize::from(e.straight() && phi.norm_squared() < SERIES_BELOW);
        }
        // Both branches ran: the corner's element and the eight beside the large turns not by
        // the series, the rest by it.
        assert_eq!(series, elements.len() - 9);
        // The force pass that writes the strains too: the same force and the same strains, to
        // the bit (the same formulas in the same order, on both branches).
        let mut lanes: [Vec<f64>; 6] = Default::default();
        let mut with = faer::Col::<f64>::zeros(hht::Model::ndof(model));
        model.net_force_and_strains(0.0, q, with.as_mut(), &mut lanes);
        // (Written over garbage where the elements are one chain from node 0, not added to a
        // zeroed vector: the same numbers.)
        let mut alone = faer::Col::<f64>::from_fn(hht::Model::ndof(model), |_| f64::NAN);
        hht::Model::net_force(model, 0.0, q, faer::Col::zeros(0).as_ref(), alone.as_mut());
        assert_eq!(with, alone);
        for (i, f) in expected.iter().enumerate() {
            assert!((alone[i] - f).abs() <= 1e-9 * scale, "unknown {i}: {} vs {f}", alone[i]);
        }
        let table = ElementTable::new(elements);
        let one_chain = table.one_chain(model.mesh().positions.len());
        assert_eq!(one_chain, table.chains.iter().all(Option::is_some));
        for (e, s) in strains.iter().enumerate() {
            let [g0, g1, g2, k0, k1, k2] = lanes.each_ref().map(|l| l[e]);
            assert_eq!((s.gamma, s.kappa), (Vector3::new(g0, g1, g2), Vector3::new(k0, k1, k2)));
        }
    }
}
