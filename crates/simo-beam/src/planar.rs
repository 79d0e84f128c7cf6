//! The geometrically exact beam in a plane (Reissner 1972; Simo's rod restricted to the x-z
//! plane): three unknowns a node, an analytic tangent and a banded Newton matrix.
//!
//! A straight beam lies along x; each node has its position (x, z) and the rotation theta of
//! its section (rad, positive turning the axis x toward z). With the section's tangent
//! `t = (cos theta, sin theta)` and normal `n = (-sin theta, cos theta)` (the thickness
//! direction, z at rest), the strains of Simo's rod in the plane are
//!
//! `Gamma1 = t . r' - 1` (extension), `Gamma2 = n . r'` (shear), `kappa = theta'` (bending),
//!
//! and the strain energy is `integral (EA Gamma1^2 + GA Gamma2^2 + EI kappa^2) / 2 ds`. A
//! two-node element interpolates r and theta linearly and integrates at its midpoint (one
//! point, against shear locking), which is what the 3D element of this crate does for a motion
//! in the plane: rotations about one axis commute, so the Crisfield-Jelenic interpolation is
//! linear in theta. The force and tangent are the exact first and second derivatives of the
//! element energy, written out (no automatic differentiation; the tests check them against
//! finite differences and against the 3D beam). The mass is the 3D beam's: consistent for the
//! translations, lumped rotary inertia `rho I` per node; it is constant, so the inertial force
//! is `M a`.
//!
//! Node-major numbering keeps every element's six unknowns within five of each other: the
//! Newton matrix is banded with half-bandwidth 5 and is factorised by [`hht::BandedLu`].

use crate::error::{not_negative, positive, BeamError};
use crate::model::Support;
use crate::section::Section;
use faer::{ColMut, ColRef};
use hht::fast::{whole, Lanes, Scalar, Simd};
use hht::{Band, Model, NewtonWeights, Triplets};

/// Unknowns of an element: (x, z, theta) of its two nodes.
const LOCAL: usize = 6;

/// Below this |angle| (rad) [`sin_cos`] sums its Taylor series: the first term left out,
/// `(pi/4)^17 / 17!` for the sine and `(pi/4)^18 / 18!` for the cosine, is below 5e-17, a
/// fraction of an ulp of either.
const SERIES_REACH: f64 = std::f64::consts::FRAC_PI_4;

/// `(sin x, cos x)`: by the Taylor series to x^15 and x^16 (Horner in x^2) where |x| <=
/// pi/4, otherwise by the library. A beam's section rotations are small in an impact: the
/// series is a few multiply-adds where the library's `sin_cos` reduces its argument first,
/// and the rotation of every element is evaluated at every Newton iteration (it was an eighth
/// of the fe method's time). Within 1 ulp of the library on the reach (tested).
#[inline]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    if x.abs() > SERIES_REACH {
        return x.sin_cos();
    }
    sin_cos_series(x)
}

/// Elements a block of the force loops: their work arrays stay on the stack and in cache.
const BLOCK: usize = 64;

/// The sines and cosines of the midpoint rotations of the elements between the nodes of
/// `theta` (one entry more than the outputs): by the series over the whole block when every
/// rotation in it is within its reach (a loop the compiler runs on several elements at once),
/// by the library otherwise.
#[inline(always)]
fn block_sin_cos(theta: &[f64], sines: &mut [f64], cosines: &mut [f64]) {
    let mids = || theta.iter().zip(&theta[1..]).map(|(a, b)| 0.5 * (a + b));
    let largest = mids().fold(0.0, |m: f64, x| m.max(x.abs()));
    // Separate loops, not a test inside one: a branch in the body keeps it scalar.
    if largest <= SHORT_REACH {
        for ((s, c), x) in sines.iter_mut().zip(cosines.iter_mut()).zip(mids()) {
            (*s, *c) = sin_cos_terms::<5, 6>(x);
        }
    } else if largest <= SERIES_REACH {
        for ((s, c), x) in sines.iter_mut().zip(cosines.iter_mut()).zip(mids()) {
            (*s, *c) = sin_cos_series(x);
        }
    } else {
        for ((s, c), x) in sines.iter_mut().zip(cosines.iter_mut()).zip(mids()) {
            (*s, *c) = x.sin_cos();
        }
    }
}

/// The series of [`sin_cos`] without its test of the reach: branch-free, so that a loop over
/// elements runs it on several at once (SIMD).
#[inline(always)]
fn sin_cos_series(x: f64) -> (f64, f64) {
    sin_cos_terms::<8, 9>(x)
}

/// Below this |angle| (rad) the series' first 5 terms of the sine and 6 of the cosine do: the
/// next, `0.1^11 / 11!` and `0.1^12 / 12!`, are below 3e-18 of either (an impact's section
/// rotations are mostly of order 1e-3).
const SHORT_REACH: f64 = 0.1;

/// The series' last `S` terms of the sine and `C` of the cosine (the lowest powers).
#[inline(always)]
fn sin_cos_terms<const S: usize, const C: usize>(x: f64) -> (f64, f64) {
    let y = x * x;
    // sin x = x sum_k (-1)^k y^k / (2k + 1)!, k = 7 ..= 0, and
    // cos x = sum_k (-1)^k y^k / (2k)!, k = 8 ..= 0: the coefficients highest first.
    const SIN: [f64; 8] = [
        -1.0 / 1_307_674_368_000.0,
        1.0 / 6_227_020_800.0,
        -1.0 / 39_916_800.0,
        1.0 / 362_880.0,
        -1.0 / 5_040.0,
        1.0 / 120.0,
        -1.0 / 6.0,
        1.0,
    ];
    const COS: [f64; 9] = [
        1.0 / 20_922_789_888_000.0,
        -1.0 / 87_178_291_200.0,
        1.0 / 479_001_600.0,
        -1.0 / 3_628_800.0,
        1.0 / 40_320.0,
        -1.0 / 720.0,
        1.0 / 24.0,
        -0.5,
        1.0,
    ];
    let s = SIN[SIN.len() - S..].iter().fold(0.0, |p, &k| p * y + k);
    let c = COS[COS.len() - C..].iter().fold(0.0, |p, &k| p * y + k);
    (x * s, c)
}

/// A straight beam along x moving in the x-z plane.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanarBeam {
    /// Reference x of each node (m), increasing.
    nodes: Vec<f64>,
    /// Each element's length (m) and its reciprocal (1/m).
    lengths: Vec<f64>,
    inverse_lengths: Vec<f64>,
    /// EA (N).
    ea: f64,
    /// k G A for shear along the thickness (N).
    ga: f64,
    /// E I about the width axis (N m^2).
    ei: f64,
    /// rho A (kg/m).
    rho_a: f64,
    /// rho I about the width axis (kg m).
    rho_i: f64,
    /// Equation number of each node's x, z and theta, `None` where a support holds it.
    dofs: Vec<[Option<usize>; 3]>,
    ndof: usize,
    /// The constant mass matrix: its diagonal by equation, and the couplings (i, j, m) between
    /// the same translation of neighbouring nodes (each pair once).
    mass_diagonal: Vec<f64>,
    mass_couplings: Vec<(usize, usize, f64)>,
    /// The couplings again when each is between unknowns `i` and `i + 3` (the same
    /// translation of neighbouring nodes, every node in between free): `next[i]` couples `i`
    /// to `i + 3`, so that `M x` is three sweeps the compiler vectorises.
    mass_next: Option<Vec<f64>>,
    /// The nodes `k0..k1` when they are exactly the free ones and each has its three unknowns
    /// `3 (k - k0) ..`: the update is then a sweep without look-ups.
    dense_nodes: Option<(usize, usize)>,
    /// max(EA, GA, EI / shortest element) (N): the size of the terms that cancel in the
    /// internal force, hence its round-off floor.
    force_scale: f64,
    /// Point masses (node, kg on x and z, kg m^2 on the rotation about the width axis):
    /// sensors, tip masses.
    point_masses: Vec<(usize, f64, f64)>,
    /// Elastic supports (node, N/m along z, N m/rad about the width axis).
    springs: Vec<(usize, f64, f64)>,
}

/// Configuration of a [`PlanarBeam`]: node positions (m) and section rotations (rad).
#[derive(Debug, PartialEq)]
pub struct PlanarState {
    /// Node x (m).
    pub x: Vec<f64>,
    /// Node z (m), along the thickness at rest.
    pub z: Vec<f64>,
    /// Section rotations (rad), positive turning x toward z.
    pub theta: Vec<f64>,
}

impl Clone for PlanarState {
    fn clone(&self) -> Self {
        Self { x: self.x.clone(), z: self.z.clone(), theta: self.theta.clone() }
    }

    /// Reuses the allocations: the integrator copies the configuration at every iteration.
    fn clone_from(&mut self, source: &Self) {
        self.x.clone_from(&source.x);
        self.z.clone_from(&source.z);
        self.theta.clone_from(&source.theta);
    }
}

/// The strains of one element at its midpoint and what their derivatives need.
struct Strains {
    length: f64,
    /// cos and sin of the midpoint rotation.
    c: f64,
    s: f64,
    extension: f64,
    shear: f64,
    curvature: f64,
}

impl PlanarBeam {
    /// A free, unloaded beam with nodes at `nodes` (m, increasing along x) and the in-plane
    /// properties of `section`: EA, the shear stiffness and bending stiffness along E3
    /// (`ga3`, `ei2`: a rectangle's thickness direction) and the matching inertias.
    ///
    /// # Errors
    /// [`BeamError::Mesh`] for fewer than two nodes or nodes not increasing;
    /// [`BeamError::InvalidParameter`] for a section that is not positive.
    pub fn new(nodes: &[f64], section: &Section) -> Result<Self, BeamError> {
        if nodes.len() < 2 {
            return Err(BeamError::Mesh("a beam needs at least one element".into()));
        }
        if nodes.iter().any(|x| !x.is_finite()) || nodes.windows(2).any(|w| w[1] <= w[0]) {
            return Err(BeamError::Mesh("node positions must be finite and increasing".into()));
        }
        let section = section.validated()?;
        let lengths: Vec<f64> = nodes.windows(2).map(|w| w[1] - w[0]).collect();
        let mut beam = Self {
            nodes: nodes.to_vec(),
            inverse_lengths: lengths.iter().map(|l| 1.0 / l).collect(),
            lengths,
            ea: section.ea,
            ga: section.ga3,
            ei: section.ei2,
            rho_a: section.rho_a,
            rho_i: positive("rho_i", section.rho_i[1])?,
            dofs: vec![[None; 3]; nodes.len()],
            ndof: 0,
            mass_diagonal: Vec::new(),
            mass_couplings: Vec::new(),
            mass_next: None,
            dense_nodes: None,
            force_scale: 0.0,
            point_masses: Vec::new(),
            springs: Vec::new(),
        };
        let shortest = nodes.windows(2).map(|w| w[1] - w[0]).fold(f64::INFINITY, f64::min);
        beam.force_scale = beam.ea.max(beam.ga).max(beam.ei / shortest);
        beam.number(&vec![Support::Free; nodes.len()]);
        Ok(beam)
    }

    fn number(&mut self, supports: &[Support]) {
        (self.dofs, self.ndof) = crate::model::number_unknowns(supports, 2);
        self.mass_diagonal = vec![0.0; self.ndof];
        self.mass_couplings.clear();
        for e in 0..self.elements() {
            let (m, j) = self.element_mass(e);
            let dofs = self.local_dofs(e);
            // Translational rho A l / 6 [2 1; 1 2] for x and for z, rotary rho I l / 2 a node.
            for (dof, value) in dofs.iter().zip([2.0 * m, 2.0 * m, j, 2.0 * m, 2.0 * m, j]) {
                if let Some(i) = dof {
                    self.mass_diagonal[*i] += value;
                }
            }
            for axis in 0..2 {
                if let (Some(i), Some(jj)) = (dofs[axis], dofs[axis + 3]) {
                    self.mass_couplings.push((i, jj, m));
                }
            }
        }
        for &(node, m, j) in &self.point_masses {
            for (i, value) in self.dofs[node].iter().zip([m, m, j]) {
                if let Some(i) = i {
                    self.mass_diagonal[*i] += value;
                }
            }
        }
        self.mass_next = self.mass_couplings.iter().all(|&(i, j, _)| j == i + 3).then(|| {
            let mut next = vec![0.0; self.ndof];
            for &(i, _, m) in &self.mass_couplings {
                next[i] += m;
            }
            next
        });
        let free: Vec<usize> =
            (0..self.dofs.len()).filter(|&k| self.dofs[k].iter().any(Option::is_some)).collect();
        self.dense_nodes = match (free.first(), free.last()) {
            (Some(&k0), Some(&k1))
                if free.len() == k1 - k0 + 1
                    && (k0..=k1).all(|k| {
                        let b = 3 * (k - k0);
                        self.dofs[k] == [Some(b), Some(b + 1), Some(b + 2)]
                    }) =>
            {
                Some((k0, k1 + 1))
            }
            _ => None,
        };
    }

    /// Sets the support of `node` (pinned holds x and z, clamped also theta).
    ///
    /// # Errors
    /// [`BeamError::Mesh`] for a node index out of range.
    pub fn support(mut self, node: usize, support: Support) -> Result<Self, BeamError> {
        self.check_node(node)?;
        let mut supports = self.supports();
        supports[node] = support;
        self.number(&supports);
        Ok(self)
    }

    /// Adds a point mass of `mass` (kg) at `node`, with `rotary_inertia` (kg m^2) about the
    /// width axis: it moves with the node in x and z and turns with its section in the plane (a
    /// tip mass's resistance to the bending rotation; its inertia about the beam's axis does not
    /// act in the plane).
    ///
    /// # Errors
    /// [`BeamError::Mesh`] for a node out of range; [`BeamError::InvalidParameter`] for a
    /// value that is negative or not finite.
    pub fn attach_mass(
        mut self,
        node: usize,
        mass: f64,
        rotary_inertia: f64,
    ) -> Result<Self, BeamError> {
        self.check_node(node)?;
        not_negative("mass", mass, "a finite number >= 0 (kg)")?;
        not_negative("rotary_inertia", rotary_inertia, "a finite number >= 0 (kg m^2)")?;
        self.point_masses.push((node, mass, rotary_inertia));
        let supports = self.supports();
        self.number(&supports);
        Ok(self)
    }

    /// Adds an elastic support at `node`: `stiffness` (N/m) against its z displacement and
    /// `rotational_stiffness` (N m/rad) against its section's rotation.
    ///
    /// # Errors
    /// As [`PlanarBeam::attach_mass`], for stiffnesses that are negative or not finite.
    pub fn attach_spring(
        mut self,
        node: usize,
        stiffness: f64,
        rotational_stiffness: f64,
    ) -> Result<Self, BeamError> {
        self.check_node(node)?;
        for (name, value) in
            [("stiffness", stiffness), ("rotational_stiffness", rotational_stiffness)]
        {
            not_negative(name, value, "a finite number >= 0 (N/m, N m/rad)")?;
        }
        self.springs.push((node, stiffness, rotational_stiffness));
        Ok(self)
    }

    fn check_node(&self, node: usize) -> Result<(), BeamError> {
        if node >= self.nodes.len() {
            return Err(BeamError::Mesh(format!(
                "node {node} is not in a mesh of {} nodes",
                self.nodes.len()
            )));
        }
        Ok(())
    }

    /// Each node's support, read back from its unknowns.
    fn supports(&self) -> Vec<Support> {
        self.dofs
            .iter()
            .map(|d| match d {
                [None, None, None] => Support::Clamped,
                [None, None, Some(_)] => Support::Pinned,
                _ => Support::Free,
            })
            .collect()
    }

    /// The springs' stored energy (J): `k w^2 / 2 + k_theta theta^2 / 2` each.
    pub fn spring_energy(&self, q: &PlanarState) -> f64 {
        self.springs
            .iter()
            .map(|&(node, k, kt)| {
                0.5 * (k * q.z[node] * q.z[node] + kt * q.theta[node] * q.theta[node])
            })
            .sum()
    }

    /// Reference x of the nodes (m).
    pub fn nodes(&self) -> &[f64] {
        &self.nodes
    }

    /// Number of elements.
    pub fn elements(&self) -> usize {
        self.nodes.len() - 1
    }

    /// Equation number of unknown `k` (0 x, 1 z, 2 theta) of `node`, if it is free.
    pub fn dof(&self, node: usize, k: usize) -> Option<usize> {
        self.dofs.get(node).and_then(|d| d.get(k).copied().flatten())
    }

    /// The straight, unstressed configuration.
    pub fn reference_state(&self) -> PlanarState {
        let n = self.nodes.len();
        PlanarState { x: self.nodes.clone(), z: vec![0.0; n], theta: vec![0.0; n] }
    }

    /// The section strains of element `e` (0-based) in configuration `q`: (extension,
    /// shear, curvature (1/m)), constant over the element (its rotation is interpolated
    /// linearly, so the curvature is the element's mean, most accurate at its midpoint).
    pub fn section_strains(&self, e: usize, q: &PlanarState) -> (f64, f64, f64) {
        let st = self.strains(e, q);
        (st.extension, st.shear, st.curvature)
    }

    /// The section strains of every element, in order (as [`PlanarBeam::section_strains`]),
    /// written to `out` (one entry an element).
    ///
    /// # Panics
    /// If `out` has fewer entries than the beam has elements.
    pub fn all_section_strains(&self, q: &PlanarState, out: &mut [(f64, f64, f64)]) {
        hht::fast::run(SectionStrains { beam: self, q, out });
    }

    fn strains(&self, e: usize, q: &PlanarState) -> Strains {
        let (s, c) = sin_cos(0.5 * (q.theta[e] + q.theta[e + 1]));
        self.strains_with(e, q, s, c)
    }

    /// The strains of element `e` given the sine and cosine of its midpoint rotation.
    #[inline(always)]
    fn strains_with(&self, e: usize, q: &PlanarState, s: f64, c: f64) -> Strains {
        let (length, inverse) = (self.lengths[e], self.inverse_lengths[e]);
        let a = (q.x[e + 1] - q.x[e]) * inverse;
        let b = (q.z[e + 1] - q.z[e]) * inverse;
        Strains {
            length,
            c,
            s,
            extension: a * c + b * s - 1.0,
            shear: -a * s + b * c,
            curvature: (q.theta[e + 1] - q.theta[e]) * inverse,
        }
    }

    /// Calls `each(e, (extension, shear, curvature))` for every element in order (as
    /// [`PlanarBeam::section_strains`]). A block of elements at a time, as the internal force:
    /// the midpoint rotations' sines and cosines by [`block_sin_cos`], then a loop over the
    /// block without calls or bounds checks, which runs on several elements at once.
    #[inline(always)]
    fn for_each_strain(&self, q: &PlanarState, mut each: impl FnMut(usize, (f64, f64, f64))) {
        let (mut sines, mut cosines) = ([0.0; BLOCK], [0.0; BLOCK]);
        let elements = self.elements();
        let mut start = 0;
        while start < elements {
            let end = (start + BLOCK).min(elements);
            let m = end - start;
            let (s, c) = (&mut sines[..m], &mut cosines[..m]);
            block_sin_cos(&q.theta[start..=end], s, c);
            let (x0, x1) = (&q.x[start..end], &q.x[start + 1..=end]);
            let (z0, z1) = (&q.z[start..end], &q.z[start + 1..=end]);
            let (t0, t1) = (&q.theta[start..end], &q.theta[start + 1..=end]);
            let inverse = &self.inverse_lengths[start..end];
            for k in 0..m {
                // As `strains_with`.
                let (s, c, inv) = (s[k], c[k], inverse[k]);
                let (a, b) = ((x1[k] - x0[k]) * inv, (z1[k] - z0[k]) * inv);
                each(start + k, (a * c + b * s - 1.0, -a * s + b * c, (t1[k] - t0[k]) * inv));
            }
            start = end;
        }
    }

    /// Gradients of (extension, shear, curvature) over the element's local unknowns
    /// (x1, z1, theta1, x2, z2, theta2).
    fn gradients(st: &Strains) -> [[f64; LOCAL]; 3] {
        let (c, s, l) = (st.c / st.length, st.s / st.length, st.length);
        let (g1, g2) = (0.5 * st.shear, -0.5 * (st.extension + 1.0));
        [[-c, -s, g1, c, s, g1], [s, -c, g2, -s, c, g2], [0.0, 0.0, -1.0 / l, 0.0, 0.0, 1.0 / l]]
    }

    /// Element tangent stiffness: the Hessian of the element energy.
    fn element_stiffness(&self, st: &Strains) -> [[f64; LOCAL]; LOCAL] {
        let g = Self::gradients(st);
        let (n, v) = (self.ea * st.extension, self.ga * st.shear);
        let (c, s) = (0.5 * st.c / st.length, 0.5 * st.s / st.length);
        // Second derivatives: only translation-rotation and rotation-rotation pairs. With
        // r' = (a, b) and theta_m = (theta1 + theta2)/2: d(extension)/d(theta_m) = shear and
        // d(shear)/d(theta_m) = -(extension + 1); each theta_i moves theta_m by a half.
        let mixed_ext = [s, -c, 0.0, -s, c, 0.0]; // d^2 extension / (du d theta_i)
        let mixed_shear = [c, s, 0.0, -c, -s, 0.0]; // d^2 shear / (du d theta_i)
        let rr_ext = -0.25 * (st.extension + 1.0);
        let rr_shear = -0.25 * st.shear;
        let mut k = [[0.0; LOCAL]; LOCAL];
        for i in 0..LOCAL {
            for j in 0..LOCAL {
                k[i][j] = self.ea * g[0][i] * g[0][j]
                    + self.ga * g[1][i] * g[1][j]
                    + self.ei * g[2][i] * g[2][j];
            }
        }
        for theta in [2, 5] {
            for i in 0..LOCAL {
                let h = n * mixed_ext[i] + v * mixed_shear[i];
                k[i][theta] += h;
                k[theta][i] += h;
            }
            for other in [2, 5] {
                k[theta][other] += n * rr_ext + v * rr_shear;
            }
        }
        for row in &mut k {
            for x in row.iter_mut() {
                *x *= st.length;
            }
        }
        k
    }

    fn local_dofs(&self, e: usize) -> [Option<usize>; LOCAL] {
        let (a, b) = (self.dofs[e], self.dofs[e + 1]);
        [a[0], a[1], a[2], b[0], b[1], b[2]]
    }

    /// Strain energy (J), the springs' included.
    pub fn strain_energy(&self, q: &PlanarState) -> f64 {
        let mut energy = self.spring_energy(q);
        self.for_each_strain(q, |e, st| energy += self.element_energy(e, st));
        energy
    }

    /// Strain energy (J) of the elements of a configuration whose section strains
    /// ([`PlanarBeam::all_section_strains`]) are `strains` (the springs' is
    /// [`PlanarBeam::spring_energy`]).
    pub fn strain_energy_of(&self, strains: &[(f64, f64, f64)]) -> f64 {
        // Four partial sums: one chain of additions would wait on each.
        let mut sums = [0.0; 4];
        for (e, st) in strains.iter().enumerate() {
            sums[e % 4] += self.element_energy(e, *st);
        }
        (sums[0] + sums[1]) + (sums[2] + sums[3])
    }

    /// `l (EA Gamma1^2 + GA Gamma2^2 + EI kappa^2) / 2` of element `e`.
    #[inline(always)]
    fn element_energy(&self, e: usize, (extension, shear, curvature): (f64, f64, f64)) -> f64 {
        0.5 * self.lengths[e]
            * (self.ea * extension * extension
                + self.ga * shear * shear
                + self.ei * curvature * curvature)
    }

    /// The internal force (N, N m) by equation, written to `out` (length [`Model::ndof`]).
    ///
    /// The element forces are the gradients of the element energy with the element length
    /// cancelled: with `N = EA Gamma1`, `V = GA Gamma2`, `M = EI kappa`, the second node takes
    /// `(N c - V s, N s + V c)` and the first its opposite; each rotation takes
    /// `l (N Gamma2 - V (Gamma1 + 1)) / 2` and `-+M`. Nodes are visited in order and each free
    /// unknown is written once, from its two elements (no zeroing, no gradient arrays: this is
    /// the fe method's innermost loop).
    pub fn internal_force(&self, q: &PlanarState, out: &mut [f64]) {
        let strains = [&mut [][..], &mut [][..], &mut [][..]];
        hht::fast::run_wide(InternalForce::<false> { beam: self, q, out, strains });
        self.add_spring_forces(q, out);
    }

    /// [`PlanarBeam::internal_force`] that also writes every element's section strains at `q`
    /// into `strains`, (extensions, shears, curvatures) an array each (as
    /// [`PlanarBeam::all_section_strains`], by the same operations: the same bits), from the
    /// same pass: a step's last force evaluation then gives its state's strains without a
    /// second pass over the sections' sines and cosines.
    ///
    /// # Panics
    /// If an array of `strains` has fewer entries than the beam has elements.
    pub fn internal_force_and_strains(
        &self,
        q: &PlanarState,
        out: &mut [f64],
        strains: [&mut [f64]; 3],
    ) {
        let e = self.elements();
        let strains = strains.map(|s| &mut s[..e]);
        hht::fast::run_wide(InternalForce::<true> { beam: self, q, out, strains });
        self.add_spring_forces(q, out);
    }

    /// The springs' forces added to the internal force `out`.
    fn add_spring_forces(&self, q: &PlanarState, out: &mut [f64]) {
        for &(node, k, kt) in &self.springs {
            if let Some(i) = self.dofs[node][1] {
                out[i] += k * q.z[node];
            }
            if let Some(i) = self.dofs[node][2] {
                out[i] += kt * q.theta[node];
            }
        }
    }

    /// The elements' part of the internal force; with `KEEP`, each element's extension, shear
    /// and curvature written to `strains` too (an array each, an entry an element).
    #[inline(always)]
    fn internal_force_inline<const KEEP: bool>(
        &self,
        q: &PlanarState,
        out: &mut [f64],
        strains: [&mut [f64]; 3],
    ) {
        let [kept_extensions, kept_shears, kept_curvatures] = strains;
        // A block of elements at a time: first each element's end forces in arrays (a loop
        // over elements without branches, run on several at once), then the nodes' sums.
        let [mut sines, mut cosines, mut fx, mut fz, mut first, mut second] = [[0.0; BLOCK]; 6];
        let mut carry = [0.0; 3];
        let elements = self.elements();
        let mut start = 0;
        while start < elements {
            let end = (start + BLOCK).min(elements);
            let m = end - start;
            let (s, c) = (&mut sines[..m], &mut cosines[..m]);
            block_sin_cos(&q.theta[start..=end], s, c);
            // Every slice is m long, so the loop runs without bounds checks.
            let (x0, x1) = (&q.x[start..end], &q.x[start + 1..=end]);
            let (z0, z1) = (&q.z[start..end], &q.z[start + 1..=end]);
            let (t0, t1) = (&q.theta[start..end], &q.theta[start + 1..=end]);
            let (lengths, inverse) = (&self.lengths[start..end], &self.inverse_lengths[start..end]);
            let (fx, fz) = (&mut fx[..m], &mut fz[..m]);
            let (first, second) = (&mut first[..m], &mut second[..m]);
            // The kept strains' part for this block (m long: no bounds checks below).
            let (ext, shr, cur) = if KEEP {
                let r = start..end;
                let e = &mut kept_extensions[r.clone()];
                (e, &mut kept_shears[r.clone()], &mut kept_curvatures[r])
            } else {
                (&mut [][..], &mut [][..], &mut [][..])
            };
            for k in 0..m {
                let (s, c, inv) = (s[k], c[k], inverse[k]);
                let (a, b) = ((x1[k] - x0[k]) * inv, (z1[k] - z0[k]) * inv);
                let extension = a * c + b * s - 1.0;
                let shear = -a * s + b * c;
                let curvature = (t1[k] - t0[k]) * inv;
                if KEEP {
                    (ext[k], shr[k], cur[k]) = (extension, shear, curvature);
                }
                let (n, v, m) = (self.ea * extension, self.ga * shear, self.ei * curvature);
                fx[k] = n * c - v * s;
                fz[k] = n * s + v * c;
                let turn = 0.5 * lengths[k] * (n * shear - v * (extension + 1.0));
                first[k] = turn - m;
                second[k] = turn + m;
            }
            // Each node takes its two elements' end forces: the free nodes of the dense run
            // (their three unknowns in a row) without looking each unknown up, the others
            // by their unknowns (a branch an unknown cost 5 % of a step).
            let (lo, hi) = match self.dense_nodes {
                Some((k0, k1)) => (k0.clamp(start, end), k1.clamp(start, end)),
                None => (end, end),
            };
            let node_sums = |k: usize, carry: &mut [f64; 3]| {
                let node = [carry[0] - fx[k], carry[1] - fz[k], carry[2] + first[k]];
                *carry = [fx[k], fz[k], second[k]];
                node
            };
            for k in start..lo {
                let node = node_sums(k - start, &mut carry);
                self.write_node(k, node, out);
            }
            if lo < hi {
                let k0 = self.dense_nodes.map_or(0, |d| d.0);
                let dense = out[3 * (lo - k0)..3 * (hi - k0)].chunks_exact_mut(3);
                for (o, k) in dense.zip(lo - start..hi - start) {
                    o.copy_from_slice(&node_sums(k, &mut carry));
                }
            }
            for k in hi..end {
                let node = node_sums(k - start, &mut carry);
                self.write_node(k, node, out);
            }
            start = end;
        }
        self.write_node(elements, carry, out);
    }

    /// The forces (x, z, theta) on `node` into its unknowns' rows of `out`.
    #[inline(always)]
    fn write_node(&self, node: usize, forces: [f64; 3], out: &mut [f64]) {
        for (d, f) in self.dofs[node].iter().zip(forces) {
            if let Some(i) = d {
                out[*i] = f;
            }
        }
    }

    /// Element mass blocks: translational `rho A l / 6 [2 1; 1 2]`, rotary `rho I l / 2` a node.
    fn element_mass(&self, e: usize) -> (f64, f64) {
        let l = self.nodes[e + 1] - self.nodes[e];
        (self.rho_a * l / 6.0, 0.5 * self.rho_i * l)
    }

    /// `out = M x` with the constant mass matrix.
    fn mass_times(&self, x: ColRef<'_, f64>, mut out: ColMut<'_, f64>) {
        match (x.try_as_col_major(), out.as_mut().try_as_col_major_mut()) {
            (Some(x), Some(o)) => {
                hht::fast::run(MassProduct { beam: self, x: x.as_slice(), out: o.as_slice_mut() })
            }
            _ => {
                let x: Vec<f64> = x.iter().copied().collect();
                let mut product = vec![0.0; x.len()];
                self.mass_product(&x, &mut product);
                for (i, v) in product.into_iter().enumerate() {
                    out[i] = v;
                }
            }
        }
    }

    /// `out = M x` on slices: with the couplings all three unknowns apart (a chain of nodes of
    /// three), one sweep, each row its diagonal's term, then its coupling to the unknown three
    /// on, then three back; otherwise the diagonal, then the couplings.
    #[inline(always)]
    fn mass_product(&self, x: &[f64], out: &mut [f64]) {
        let (n, diagonal) = (x.len(), &self.mass_diagonal[..x.len()]);
        if let Some(next) = self.mass_next.as_ref().filter(|_| n >= 6) {
            // One pass instead of three over the vectors (a step streams them from the second-
            // level cache), the same sum in the same order: the same bits.
            for i in 0..3 {
                out[i] = diagonal[i] * x[i] + next[i] * x[i + 3];
            }
            let rows = out[3..n - 3].iter_mut().zip(&diagonal[3..n - 3]).zip(&x[3..n - 3]);
            let on = next[3..n - 3].iter().zip(&x[6..]);
            let back = next[..n - 6].iter().zip(&x[..n - 6]);
            for (((o, m), x), ((u, xu), (d, xd))) in rows.zip(on.zip(back)) {
                *o = m * x + u * xu + d * xd;
            }
            for i in n - 3..n {
                out[i] = diagonal[i] * x[i] + next[i - 3] * x[i - 3];
            }
            return;
        }
        for ((o, m), x) in out.iter_mut().zip(diagonal).zip(x) {
            *o = m * x;
        }
        match &self.mass_next {
            Some(next) if x.len() >= 3 => {
                let n = x.len() - 3;
                for ((o, m), x) in out[..n].iter_mut().zip(&next[..n]).zip(&x[3..]) {
                    *o += m * x;
                }
                for ((o, m), x) in out[3..].iter_mut().zip(&next[..n]).zip(&x[..n]) {
                    *o += m * x;
                }
            }
            _ => {
                for &(i, j, m) in &self.mass_couplings {
                    out[i] += m * x[j];
                    out[j] += m * x[i];
                }
            }
        }
    }

    /// Kinetic energy (J) for velocity `v`.
    pub fn kinetic_energy(&self, v: ColRef<'_, f64>) -> f64 {
        let Some(v) = v.try_as_col_major().map(|v| v.as_slice()) else {
            let v: Vec<f64> = v.iter().copied().collect();
            return self.kinetic_energy(ColRef::from_slice(&v));
        };
        match &self.mass_next {
            // The diagonal and the couplings by sweeps on vectors (as the mass product): a
            // sum term by term would wait on each addition.
            Some(next) if v.len() >= 3 => hht::fast::run_lanes(KineticEnergy {
                diagonal: &self.mass_diagonal,
                next: &next[..v.len() - 3],
                v,
            }),
            _ => {
                let diagonal: f64 = self.mass_diagonal.iter().zip(v).map(|(m, v)| m * v * v).sum();
                let couplings: f64 =
                    self.mass_couplings.iter().map(|&(i, j, m)| m * v[i] * v[j]).sum();
                0.5 * diagonal + couplings
            }
        }
    }
}

/// `v . M v / 2` with the couplings between unknowns `i` and `i + 3` (`next`), on vectors.
struct KineticEnergy<'a> {
    diagonal: &'a [f64],
    next: &'a [f64],
    v: &'a [f64],
}

impl Lanes for KineticEnergy<'_> {
    type Output = f64;

    #[inline(always)]
    fn run<S: Simd>(self, simd: S) -> f64 {
        /// `sum m a b` over equal-length slices.
        #[inline(always)]
        fn weighted<S: Simd>(simd: S, m: &[f64], a: &[f64], b: &[f64]) -> f64 {
            let (m, a, b) = (S::as_simd_f64s(m).0, S::as_simd_f64s(a).0, S::as_simd_f64s(b).0);
            let mut sum = simd.splat_f64s(0.0);
            for ((m, a), b) in m.iter().zip(a).zip(b) {
                sum = simd.mul_add_e_f64s(simd.mul_f64s(*m, *a), *b, sum);
            }
            simd.reduce_sum_f64s(sum)
        }
        let one = Scalar::new();
        let (n, c) = (self.v.len(), self.next.len());
        let (d, k) = (whole::<S>(n), whole::<S>(c));
        let (v, near, far) = (self.v, &self.v[..c], &self.v[3..3 + c]);
        let diagonal = weighted(simd, &self.diagonal[..d], &v[..d], &v[..d])
            + weighted(one, &self.diagonal[d..n], &v[d..], &v[d..]);
        let couplings = weighted(simd, &self.next[..k], &near[..k], &far[..k])
            + weighted(one, &self.next[k..], &near[k..], &far[k..]);
        0.5 * diagonal + couplings
    }
}

impl Model for PlanarBeam {
    type Config = PlanarState;

    fn ndof(&self) -> usize {
        self.ndof
    }

    fn update(&self, q: &mut PlanarState, dq: ColRef<'_, f64>) {
        if let (Some(dq), Some((k0, k1))) = (dq.try_as_col_major(), self.dense_nodes) {
            let nodes = q.x[k0..k1].iter_mut().zip(&mut q.z[k0..k1]).zip(&mut q.theta[k0..k1]);
            for (((x, z), theta), d) in nodes.zip(dq.as_slice().chunks_exact(3)) {
                *x += d[0];
                *z += d[1];
                *theta += d[2];
            }
            return;
        }
        for (node, d) in self.dofs.iter().enumerate() {
            if let Some(i) = d[0] {
                q.x[node] += dq[i];
            }
            if let Some(i) = d[1] {
                q.z[node] += dq[i];
            }
            if let Some(i) = d[2] {
                q.theta[node] += dq[i];
            }
        }
    }

    /// One pass over the nodes, writing `out` from `q` (no copy first).
    fn displaced(&self, q: &PlanarState, dq: ColRef<'_, f64>, out: &mut PlanarState) {
        let Some((dq, (k0, k1))) = dq.try_as_col_major().zip(self.dense_nodes) else {
            out.clone_from(q);
            return self.update(out, dq);
        };
        let n = q.x.len();
        for v in [&mut out.x, &mut out.z, &mut out.theta] {
            v.resize(n, 0.0);
        }
        // Nodes outside k0..k1 have no unknowns (held): copied.
        for range in [0..k0, k1..n] {
            out.x[range.clone()].copy_from_slice(&q.x[range.clone()]);
            out.z[range.clone()].copy_from_slice(&q.z[range.clone()]);
            out.theta[range.clone()].copy_from_slice(&q.theta[range]);
        }
        // dq interleaves x, z, theta a node: the loop goes node by node, in the vector copy
        // (257 -> 155 ns a pass at 256 elements against the zipped iterators in the baseline one).
        hht::fast::run(Displace { q, dq: dq.as_slice(), out, nodes: k0..k1 });
    }

    fn inertial_force(
        &self,
        _q: &PlanarState,
        _v: ColRef<'_, f64>,
        a: ColRef<'_, f64>,
        out: ColMut<'_, f64>,
    ) {
        self.mass_times(a, out);
    }

    /// In the plane a section's rotation is one angle: its inertia `rho I theta''` has no
    /// gyroscopic term, and the mass matrix is constant.
    fn constant_mass(&self) -> bool {
        true
    }

    fn net_force(&self, _t: f64, q: &PlanarState, _v: ColRef<'_, f64>, mut out: ColMut<'_, f64>) {
        if let Some(contiguous) = out.as_mut().try_as_col_major_mut() {
            return self.internal_force(q, contiguous.as_slice_mut());
        }
        let mut force = vec![0.0; self.ndof];
        self.internal_force(q, &mut force);
        for (i, f) in force.into_iter().enumerate() {
            out[i] = f;
        }
    }

    fn tangent(
        &self,
        _t: f64,
        q: &PlanarState,
        _v: ColRef<'_, f64>,
        _a: ColRef<'_, f64>,
        w: NewtonWeights,
        out: &mut Triplets,
    ) {
        let inertia = w.inertia * w.da;
        let stiffness = w.force * w.dq;
        for e in 0..self.elements() {
            // The mass alone (the eigen-solver's M, a Newton matrix re-weighted for a new step
            // size) needs no element stiffness: the same entries are pushed, its zero.
            let mut block = if stiffness == 0.0 {
                [[0.0; 6]; 6]
            } else {
                self.element_stiffness(&self.strains(e, q))
            };
            for row in &mut block {
                for x in row.iter_mut() {
                    *x *= stiffness;
                }
            }
            // The mass: translational rho A l / 6 [2 1; 1 2] for x and for z, rotary rho I l / 2.
            let (m, j) = self.element_mass(e);
            let (m, j) = (inertia * m, inertia * j);
            for axis in 0..2 {
                let (a, b) = (axis, 3 + axis);
                block[a][a] += 2.0 * m;
                block[a][b] += m;
                block[b][a] += m;
                block[b][b] += 2.0 * m;
            }
            block[2][2] += j;
            block[5][5] += j;
            let dofs = self.local_dofs(e);
            for (row, dr) in block.iter().zip(dofs) {
                let Some(i) = dr else { continue };
                for (value, dc) in row.iter().zip(dofs) {
                    if let Some(jj) = dc {
                        out.push(i, jj, *value);
                    }
                }
            }
        }
        for &(node, m, j) in &self.point_masses {
            for (i, value) in self.dofs[node].iter().zip([m, m, j]) {
                if let Some(i) = i {
                    out.push(*i, *i, inertia * value);
                }
            }
        }
        for &(node, k, kt) in &self.springs {
            for (d, value) in self.dofs[node][1..].iter().zip([k, kt]) {
                if let Some(i) = d {
                    out.push(*i, *i, stiffness * value);
                }
            }
        }
    }

    fn force_scale(&self, _q: &PlanarState) -> f64 {
        self.force_scale
    }

    fn configuration_scale(&self, q: &PlanarState) -> f64 {
        q.x.iter().chain(&q.z).fold(0.0, |m: f64, v| m.max(v.abs()))
    }

    fn band(&self) -> Option<Band> {
        Some(Band { half_bandwidth: 2 * 3 - 1, border: 0 })
    }
}

/// [`PlanarBeam::internal_force`] as a [`hht::fast::Kernel`] (wider lanes for the rotations'
/// sines and cosines).
struct InternalForce<'a, const KEEP: bool> {
    beam: &'a PlanarBeam,
    q: &'a PlanarState,
    out: &'a mut [f64],
    /// The elements' extensions, shears and curvatures (with `KEEP`; empty without).
    strains: [&'a mut [f64]; 3],
}

impl<const KEEP: bool> hht::fast::Kernel for InternalForce<'_, KEEP> {
    type Output = ();

    #[inline(always)]
    fn run<A: hht::fast::MulAdd>(self, _: A) {
        self.beam.internal_force_inline::<KEEP>(self.q, self.out, self.strains);
    }
}

/// The free nodes' part of [`hht::Model::displaced`] (`out = q + dq` on `nodes`, whose
/// unknowns `dq` interleaves x, z, theta) as a [`hht::fast::Kernel`].
struct Displace<'a> {
    q: &'a PlanarState,
    dq: &'a [f64],
    out: &'a mut PlanarState,
    nodes: std::ops::Range<usize>,
}

impl hht::fast::Kernel for Displace<'_> {
    type Output = ();

    #[inline(always)]
    fn run<A: hht::fast::MulAdd>(self, _: A) {
        let (q, out) = (self.q, self.out);
        // Every slice `len` (or 3 len) long, so the loop runs without bounds checks.
        let len = self.nodes.len().min(self.dq.len() / 3);
        let nodes = self.nodes.start..self.nodes.start + len;
        let (x0, z0, t0) = (&q.x[nodes.clone()], &q.z[nodes.clone()], &q.theta[nodes.clone()]);
        let (x, z, t) =
            (&mut out.x[nodes.clone()], &mut out.z[nodes.clone()], &mut out.theta[nodes]);
        for (k, d) in self.dq[..3 * len].chunks_exact(3).enumerate().take(len) {
            x[k] = x0[k] + d[0];
            z[k] = z0[k] + d[1];
            t[k] = t0[k] + d[2];
        }
    }
}

/// [`PlanarBeam::mass_product`] as a [`hht::fast::Kernel`].
struct MassProduct<'a> {
    beam: &'a PlanarBeam,
    x: &'a [f64],
    out: &'a mut [f64],
}

impl hht::fast::Kernel for MassProduct<'_> {
    type Output = ();

    #[inline(always)]
    fn run<A: hht::fast::MulAdd>(self, _: A) {
        self.beam.mass_product(self.x, self.out);
    }
}

/// [`PlanarBeam::all_section_strains`] as a [`hht::fast::Kernel`].
struct SectionStrains<'a> {
    beam: &'a PlanarBeam,
    q: &'a PlanarState,
    out: &'a mut [(f64, f64, f64)],
}

impl hht::fast::Kernel for SectionStrains<'_> {
    type Output = ();

    #[inline(always)]
    fn run<A: hht::fast::MulAdd>(self, _: A) {
        let out = &mut self.out[..self.beam.elements()];
        self.beam.for_each_strain(self.q, |e, st| out[e] = st);
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::section::Material;

    #[test]
    fn displaced_is_a_copy_then_the_update() {
        // A clamped end (the dense run of free nodes, one pass) and a pinned end (unknowns
        // looked up): the same bits as copying q and adding dq, into a configuration that held
        // something else.
        for support in [Support::Clamped, Support::Pinned] {
            let beam = strip().support(0, support).unwrap();
            let mut q = beam.reference_state();
            q.z[3] = 1e-3;
            q.theta[2] = 0.01;
            let dq = faer::Col::<f64>::from_fn(beam.ndof(), |i| 1e-4 * (i as f64 - 2.5));
            let mut expected = q.clone();
            beam.update(&mut expected, dq.as_ref());
            let mut out = PlanarState { x: vec![9.0; 2], z: vec![], theta: vec![7.0; 9] };
            beam.displaced(&q, dq.as_ref(), &mut out);
            assert_eq!(out, expected, "{support:?}");
        }
    }

    #[test]
    fn the_eight_lanes_copy_gives_the_four_lanes_bits() {
        // The force pass in hht::fast::run_wide's copy (AVX-512 where the processor has it)
        // and in the four lanes' one: each element by the same operations, the same bits (a
        // mesh of 300 elements, several blocks and a tail; bent, clamped at one end), with
        // the sections' angles small, mid-way and large (each of the sine and cosine's
        // ranges).
        if !hht::fast::wide_lanes() {
            eprintln!("no AVX-512 here: the two copies are one, nothing to compare");
            return;
        }
        let steel = Material::new(2.1e11, 0.3, 7850.0).unwrap();
        let section = Section::rectangle(&steel, 0.025, 0.005).unwrap();
        let nodes: Vec<f64> = (0..=300).map(|i| 1.15 * f64::from(i) / 300.0).collect();
        let beam = PlanarBeam::new(&nodes, &section).unwrap().support(0, Support::Clamped).unwrap();
        for turn in [0.04, 0.5, 1.5] {
            let mut q = beam.reference_state();
            for (i, (z, theta)) in q.z.iter_mut().zip(q.theta.iter_mut()).enumerate() {
                let s = i as f64 / 300.0;
                (*z, *theta) = (0.02 * s * s + 1e-4 * (37.0 * s).sin(), turn * s + 0.01 * s.cos());
            }
            let each = |wide: bool| {
                let mut out = vec![0.0; beam.ndof()];
                let mut strains = [vec![0.0; 300], vec![0.0; 300], vec![0.0; 300]];
                let [a, b, c] = &mut strains;
                let kernel = InternalForce::<true> {
                    beam: &beam,
                    q: &q,
                    out: &mut out,
                    strains: [&mut a[..], &mut b[..], &mut c[..]],
                };
                if wide {
                    hht::fast::run_wide(kernel);
                } else {
                    hht::fast::run(kernel);
                }
                (out, strains)
            };
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            let (wide, four) = (each(true), each(false));
            assert_eq!(bits(&wide.0), bits(&four.0));
            for (a, b) in wide.1.iter().zip(&four.1) {
                assert_eq!(bits(a), bits(b));
            }
            assert!(wide.0.iter().any(|&f| f != 0.0));
        }
    }

    fn strip() -> PlanarBeam {
        let steel = Material::new(2.1e11, 0.3, 7850.0).unwrap();
        let section = Section::rectangle(&steel, 0.025, 0.005).unwrap();
        PlanarBeam::new(&[0.0, 0.3, 0.5, 1.15], &section).unwrap()
    }

    fn bent(beam: &PlanarBeam) -> PlanarState {
        let mut q = beam.reference_state();
        for i in 0..q.x.len() {
            q.x[i] -= 0.01 * i as f64;
            q.z[i] = 0.05 * (i as f64).powi(2) - 0.02;
            q.theta[i] = 0.3 * i as f64 - 0.1;
        }
        q
    }

    #[test]
    fn force_and_tangent_are_the_derivatives_of_the_energy() {
        // Central differences on a bent, stretched, sheared configuration. Truncation is
        // eps^2 |f'''| (eps = 1e-7 m or rad: ~1e-14 of the scale) and round-off
        // ~eps_mach |energy| / eps; 1e-6 of the largest entry leaves room for both and still
        // catches a missing term (the geometric terms are ~1e-2 of it here). Free, clamped at
        // one end (the free nodes one dense run) and pinned inside (the run broken, the pinned
        // node's rotation looked up), and clamped at the last two nodes (the run ends before
        // the last element; the nodes after it have no unknowns, as a run is all free nodes).
        for beam in [
            strip(),
            strip().support(0, Support::Clamped).unwrap(),
            strip().support(1, Support::Pinned).unwrap(),
            strip()
                .support(2, Support::Clamped)
                .and_then(|b| b.support(3, Support::Clamped))
                .unwrap(),
        ] {
            derivatives_of_the_energy(&beam);
        }
    }

    fn derivatives_of_the_energy(beam: &PlanarBeam) {
        let q = bent(beam);
        let n = beam.ndof();
        let zero = faer::Col::<f64>::zeros(n);
        let force = |q: &PlanarState| {
            let mut f = faer::Col::<f64>::zeros(n);
            beam.net_force(0.0, q, zero.as_ref(), f.as_mut());
            f
        };
        let f = force(&q);
        let mut t = Triplets::new();
        beam.tangent(0.0, &q, zero.as_ref(), zero.as_ref(), NewtonWeights::stiffness(), &mut t);
        let mut k = vec![vec![0.0; n]; n];
        for (r, c, v) in t.iter() {
            k[r][c] += v;
        }
        let eps = 1e-7;
        let (mut worst_f, mut worst_k) = (0.0f64, 0.0f64);
        let scale_f = f.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let scale_k = k.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        for j in 0..n {
            let mut e = faer::Col::<f64>::zeros(n);
            e[j] = eps;
            let (mut qp, mut qm) = (q.clone(), q.clone());
            beam.update(&mut qp, e.as_ref());
            beam.update(&mut qm, (-&e).as_ref());
            let de = (beam.strain_energy(&qp) - beam.strain_energy(&qm)) / (2.0 * eps);
            worst_f = worst_f.max((de - f[j]).abs());
            let (fp, fm) = (force(&qp), force(&qm));
            for i in 0..n {
                worst_k = worst_k.max(((fp[i] - fm[i]) / (2.0 * eps) - k[i][j]).abs());
            }
        }
        assert!(worst_f < 1e-6 * scale_f, "force: {worst_f:e} of {scale_f:e}");
        assert!(worst_k < 1e-6 * scale_k, "tangent: {worst_k:e} of {scale_k:e}");
        // Symmetric (a hyperelastic rod).
        for (i, row) in k.iter().enumerate() {
            for (j, kij) in row.iter().enumerate() {
                assert!((kij - k[j][i]).abs() <= 1e-12 * scale_k);
            }
        }
    }

    #[test]
    fn all_section_strains_are_each_element_s() {
        // The block loop against the element-by-element strains, on a bent strip (rotations
        // past pi/4, the library's sines there) and on one of 150 elements in small rotations
        // (blocks of 64, the short series): to 4 ulp of the largest strain.
        let long = {
            let steel = Material::new(2.1e11, 0.3, 7850.0).unwrap();
            let section = Section::rectangle(&steel, 0.025, 0.005).unwrap();
            let nodes: Vec<f64> = (0..=150).map(|i| 1.15 * f64::from(i) / 150.0).collect();
            PlanarBeam::new(&nodes, &section).unwrap()
        };
        let mut small = long.reference_state();
        for i in 0..small.x.len() {
            let s = i as f64 / 150.0;
            (small.z[i], small.theta[i]) = (1e-3 * s * s, 2e-3 * s + 1e-6 * (i % 3) as f64);
            small.x[i] -= 1e-7 * s;
        }
        for (beam, q) in [(strip(), bent(&strip())), (long, small)] {
            let mut all = vec![(0.0, 0.0, 0.0); beam.elements()];
            beam.all_section_strains(&q, &mut all);
            let largest = all.iter().fold(0.0f64, |m, s| m.max(s.0.abs()).max(s.1.abs()));
            for (e, got) in all.iter().enumerate() {
                let want = beam.section_strains(e, &q);
                for (g, w) in [(got.0, want.0), (got.1, want.1)] {
                    assert!((g - w).abs() <= 4.0 * f64::EPSILON * largest, "{e}: {g} vs {w}");
                }
                assert_eq!(got.2.to_bits(), want.2.to_bits());
            }
        }
    }

    #[test]
    fn the_force_pass_s_strains_are_the_strains_pass_s_to_the_bit() {
        // A clamped strip of 150 elements with a spring, bent in small rotations (the short
        // series, blocks of 64) and a bent one past pi/4: the force and the strains of one pass
        // are those of the two passes alone, bit for bit.
        let steel = Material::new(2.1e11, 0.3, 7850.0).unwrap();
        let section = Section::rectangle(&steel, 0.025, 0.005).unwrap();
        let nodes: Vec<f64> = (0..=150).map(|i| 1.15 * f64::from(i) / 150.0).collect();
        let long = PlanarBeam::new(&nodes, &section)
            .unwrap()
            .support(0, Support::Clamped)
            .unwrap()
            .attach_spring(75, 3e3, 20.0)
            .unwrap();
        let mut small = long.reference_state();
        for i in 0..small.x.len() {
            let s = i as f64 / 150.0;
            (small.z[i], small.theta[i]) = (1e-3 * s * s, 2e-3 * s + 1e-6 * (i % 3) as f64);
        }
        for (beam, q) in [(strip(), bent(&strip())), (long, small)] {
            let n = hht::Model::ndof(&beam);
            let (mut force, mut alone) = (vec![7.0; n], vec![8.0; n]);
            let e = beam.elements();
            let [mut extensions, mut shears, mut curvatures] =
                [vec![9.0; e], vec![9.0; e], vec![9.0; e]];
            let mut expected = vec![(0.0, 0.0, 0.0); e];
            let strains = [&mut extensions[..], &mut shears[..], &mut curvatures[..]];
            beam.internal_force_and_strains(&q, &mut force, strains);
            beam.internal_force(&q, &mut alone);
            beam.all_section_strains(&q, &mut expected);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&force), bits(&alone));
            let columns = |k: usize| {
                expected.iter().map(|s| [s.0, s.1, s.2][k].to_bits()).collect::<Vec<_>>()
            };
            assert_eq!(bits(&extensions), columns(0));
            assert_eq!(bits(&shears), columns(1));
            assert_eq!(bits(&curvatures), columns(2));
        }
    }

    #[test]
    fn the_series_sine_and_cosine_are_the_library_s_to_an_ulp() {
        // 20001 angles over each reach, and both sides of its edge: within 2 ulp of the
        // library's value (the library itself is within 1 ulp of the true one), measured 1.
        let ulps = |a: f64, b: f64| (a - b).abs() / (f64::EPSILON * b.abs().max(f64::MIN_POSITIVE));
        let mut worst = 0.0f64;
        for (reach, short) in [(SERIES_REACH, false), (SHORT_REACH, true)] {
            for i in -10_000..=10_000 {
                let x = reach * f64::from(i) / 10_000.0;
                let (s, c) = if short { sin_cos_terms::<5, 6>(x) } else { sin_cos_series(x) };
                let (ls, lc) = x.sin_cos();
                if x != 0.0 {
                    worst = worst.max(ulps(s, ls));
                }
                worst = worst.max(ulps(c, lc));
            }
        }
        assert!(worst <= 2.0, "{worst} ulp");
        for x in [SERIES_REACH * (1.0 - 1e-12), SERIES_REACH * (1.0 + 1e-12), 2.0, -3.0] {
            let ((s, c), (ls, lc)) = (sin_cos(x), x.sin_cos());
            assert!(ulps(s, ls) <= 2.0 && ulps(c, lc) <= 2.0, "{x}");
        }
    }

    #[test]
    fn the_swept_mass_product_and_update_equal_the_general_ones() {
        // A clamped-free strip takes the sweeps (every coupling i to i + 3, the free nodes
        // dense); a pinned end in the middle of the numbering does not. Both against the mass
        // matrix the tangent assembles (the kinetic energy too) and against the update written
        // out node by node.
        for beam in [
            strip().support(0, Support::Clamped).unwrap(),
            strip().support(0, Support::Clamped).unwrap().support(3, Support::Pinned).unwrap(),
            strip().support(1, Support::Pinned).unwrap(),
        ] {
            let n = beam.ndof();
            let x = faer::Col::<f64>::from_fn(n, |i| (i as f64 * 0.7).sin() + 0.1 * i as f64);
            let mut product = faer::Col::<f64>::zeros(n);
            let zero = faer::Col::<f64>::zeros(n);
            let q = beam.reference_state();
            beam.inertial_force(&q, zero.as_ref(), x.as_ref(), product.as_mut());
            let mut t = Triplets::new();
            beam.tangent(0.0, &q, zero.as_ref(), zero.as_ref(), NewtonWeights::mass(), &mut t);
            let mut expected = vec![0.0; n];
            for (r, c, v) in t.iter() {
                expected[r] += v * x[c];
            }
            for i in 0..n {
                assert!((product[i] - expected[i]).abs() <= 1e-15 * expected[i].abs().max(1.0));
            }
            // The kinetic energy (swept where the product is) is x . M x / 2.
            let twice: f64 = (0..n).map(|i| x[i] * expected[i]).sum();
            let kinetic = beam.kinetic_energy(x.as_ref());
            assert!((2.0 * kinetic - twice).abs() <= 1e-14 * twice, "{kinetic} vs {twice}");
            let mut moved = beam.reference_state();
            beam.update(&mut moved, x.as_ref());
            for (node, d) in beam.dofs.iter().enumerate() {
                let value = |k: usize| d[k].map_or(0.0, |i| x[i]);
                assert_eq!(moved.x[node].to_bits(), (q.x[node] + value(0)).to_bits());
                assert_eq!(moved.z[node].to_bits(), (q.z[node] + value(1)).to_bits());
                assert_eq!(moved.theta[node].to_bits(), (q.theta[node] + value(2)).to_bits());
            }
        }
        assert!(strip().support(0, Support::Clamped).unwrap().dense_nodes.is_some());
        assert!(strip().support(1, Support::Pinned).unwrap().dense_nodes.is_none());
    }

    #[test]
    fn supports_remove_unknowns_and_keep_the_band() {
        let beam =
            strip().support(0, Support::Clamped).unwrap().support(3, Support::Pinned).unwrap();
        assert_eq!(beam.ndof(), 12 - 3 - 2);
        assert_eq!(beam.dof(0, 2), None);
        assert_eq!(beam.dof(3, 1), None);
        assert_eq!(beam.dof(3, 2), Some(6));
        let q = bent(&beam);
        let zero = faer::Col::<f64>::zeros(beam.ndof());
        let mut t = Triplets::new();
        beam.tangent(0.0, &q, zero.as_ref(), zero.as_ref(), NewtonWeights::stiffness(), &mut t);
        assert!(t.iter().all(|(r, c, _)| r.abs_diff(c) <= 5));
        assert!(strip().support(4, Support::Free).is_err());
        assert!(PlanarBeam::new(
            &[0.0, 0.0],
            &Section::rectangle(&Material::new(1.0, 0.3, 1.0).unwrap(), 1.0, 1.0).unwrap()
        )
        .is_err());
    }
}
